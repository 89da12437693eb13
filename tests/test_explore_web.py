"""``gridfield explore MAP --web`` end to end without a browser: the real command serves the page on
127.0.0.1, a tornado websocket client sends the JSON messages a browser's ``mpl.js`` sends for clicks
(start, goal, the "calculate path" button), and the server's status lines show the path planned.

(tests/browser/check_web_explorer.py drives the same page from a real headless chromium.)
"""

from __future__ import annotations

import asyncio
import json
import os
import queue
import re
import socket
import subprocess
import sys
import threading
import time
import urllib.request
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import pytest
from tornado.websocket import WebSocketClosedError, websocket_connect

from gridfield.explore import Explorer
from gridfield.io import bundled_map, read_world

REPO = Path(__file__).resolve().parents[1]
MAP_ARGS = [str(bundled_map("seed000.yaml")), "--resolution", "0.25"]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class Server:
    """``gridfield explore ... --web`` in a subprocess; its stdout lines arrive on a queue."""

    def __init__(self, args: list[str]) -> None:
        env = dict(os.environ, PYTHONPATH=str(REPO), MPLBACKEND="Agg")
        self.proc = subprocess.Popen([sys.executable, "-m", "gridfield", "explore", *args], stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, text=True, env=env, cwd=REPO)
        self.lines: queue.Queue[str] = queue.Queue()
        self.seen: list[str] = []
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.put(line.rstrip("\n"))

    def wait_for(self, pattern: str, timeout: float = 60.0) -> re.Match[str]:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            try:
                line = self.lines.get(timeout=0.2)
            except queue.Empty:
                if self.proc.poll() is not None and self.lines.empty():
                    break
                continue
            self.seen.append(line)
            m = re.search(pattern, line)
            if m:
                return m
        raise AssertionError(f"no line matching {pattern!r}; output so far: {self.seen}")

    def stop(self) -> None:
        self.proc.terminate()
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.reader.join(10)
        assert self.proc.stdout is not None
        self.proc.stdout.close()


@pytest.fixture(scope="module")
def layout():
    """Pixel positions on the served canvas, from an identical explorer figure (same size and dpi)."""
    ex = Explorer(read_world(bundled_map("seed000.yaml")), resolution=0.25)
    try:
        height = ex.figure.canvas.get_width_height()[1]

        def to_canvas(xy):  # display coordinates (y up) -> canvas pixels (y down), as mpl.js sends them
            return float(xy[0]), float(height - xy[1])

        yield {
            "start": to_canvas(ex.ax.transData.transform((2.0, 2.0))),
            "goal": to_canvas(ex.ax.transData.transform((20.0, 3.0))),
            "calculate": to_canvas(ex.buttons["calculate_path"].ax.transAxes.transform((0.5, 0.5))),
        }
    finally:
        ex.close()
        plt.close("all")


def mouse(kind: str, xy: tuple[float, float], fig_id: str) -> dict:
    """The message mpl.js sends for a left-button press or release at canvas pixel ``xy``."""
    return {"type": kind, "x": xy[0], "y": xy[1], "button": 0, "buttons": 1 if kind == "button_press" else 0,
            "modifiers": [], "guiEvent": {}, "figure_id": fig_id}


async def click(ws, xy, fig_id):
    await ws.write_message(json.dumps(mouse("button_press", xy, fig_id)))
    await ws.write_message(json.dumps(mouse("button_release", xy, fig_id)))


def test_web_explorer_serves_the_page_and_plans_from_websocket_clicks(layout):
    port = free_port()
    server = Server([*MAP_ARGS, "--web", "--port", str(port)])
    try:
        url = server.wait_for(r"gridfield explorer: (http://127\.0\.0\.1:(\d+)/)").group(1)
        assert url == f"http://127.0.0.1:{port}/"
        with urllib.request.urlopen(url, timeout=10) as r:
            page = r.read().decode()
        fig_id = re.search(r"figure_ready\((\d+)\)", page).group(1)
        assert "mpl.js" in page
        with urllib.request.urlopen(url + "js/mpl.js", timeout=10) as r:
            assert b"mpl.figure" in r.read()

        async def drive():
            ws = await websocket_connect(f"ws://127.0.0.1:{port}/{fig_id}/ws")
            for msg in ({"type": "supports_binary", "value": True}, {"type": "send_image_mode"},
                        {"type": "set_device_pixel_ratio", "device_pixel_ratio": 1}, {"type": "refresh"}):
                await ws.write_message(json.dumps({**msg, "figure_id": fig_id}))
            first = await asyncio.wait_for(ws.read_message(), 30)  # the server answers (image mode, image)
            assert first is not None

            async def answer():  # as mpl.js does: the server asks for a redraw, the browser requests it
                while (msg := await ws.read_message()) is not None:
                    if isinstance(msg, str) and json.loads(msg).get("type") == "draw":
                        try:
                            await ws.write_message(json.dumps({"type": "draw", "figure_id": fig_id}))
                        except WebSocketClosedError:
                            return

            reader = asyncio.create_task(answer())
            await ws.write_message(json.dumps({"type": "draw", "figure_id": fig_id}))
            await click(ws, layout["start"], fig_id)
            await asyncio.get_running_loop().run_in_executor(None, server.wait_for, r"start set to \(2, 2\)")
            await click(ws, layout["goal"], fig_id)
            await asyncio.get_running_loop().run_in_executor(None, server.wait_for, r"goal set to \(20, 3\)")
            line = await asyncio.get_running_loop().run_in_executor(None, server.wait_for, r"potential: (\w+)")
            assert line.group(1) == "reached"
            await click(ws, layout["calculate"], fig_id)  # the "calculate path" button
            again = await asyncio.get_running_loop().run_in_executor(None, server.wait_for,
                                                                     r"potential: reached, (\d+) steps")
            assert int(again.group(1)) > 10
            ws.close()
            await reader

        asyncio.run(drive())
    finally:
        server.stop()


def test_web_explorer_bad_port_is_a_one_line_error():
    out = subprocess.run([sys.executable, "-m", "gridfield", "explore", *MAP_ARGS, "--web", "--port", "70000"],
                         capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=str(REPO)), cwd=REPO,
                         timeout=120)
    assert out.returncode == 2 and "--port must be a port number" in out.stderr
    assert out.stderr.count("\n") == 1
