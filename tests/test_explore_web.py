"""``gridfield explore MAP --web`` end to end without a browser: the real command serves the page on
127.0.0.1, a tornado websocket client sends the JSON messages a browser's ``mpl.js`` sends for clicks
(start, goal, the "calculate path" button), and the server's status lines show the path planned.

The server, the canvas pixels and the mpl.js messages come from ``tools/webagg_explorer.py``, which
``tools/check_web_explorer.py`` (the same page driven from a real headless chromium) shares.
"""

from __future__ import annotations

import asyncio
import json
import os
import subprocess
import sys
import urllib.request
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import pytest
from tornado.websocket import websocket_connect

from gridfield.explore import Explorer
from gridfield.io import bundled_map, read_world

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tools"))
from webagg_explorer import (  # tools/webagg_explorer.py
    ExplorerServer,
    answer_draws,
    button_pixel,
    click,
    data_pixel,
    figure_id,
    free_port,
    handshake,
)

REPO = Path(__file__).resolve().parents[1]
MAP_ARGS = [str(bundled_map("seed000.yaml")), "--resolution", "0.25"]


@pytest.fixture(scope="module")
def layout():
    """Pixel positions on the served canvas, from an identical explorer figure (same size and dpi)."""
    ex = Explorer(read_world(bundled_map("seed000.yaml")), resolution=0.25)
    try:
        yield {
            "start": data_pixel(ex, 2.0, 2.0),
            "goal": data_pixel(ex, 20.0, 3.0),
            "calculate": button_pixel(ex, "calculate_path"),
        }
    finally:
        ex.close()
        plt.close("all")


def test_web_explorer_serves_the_page_and_plans_from_websocket_clicks(layout):
    port = free_port()
    server = ExplorerServer([*MAP_ARGS, "--web", "--port", str(port)])
    try:
        url = server.wait_for(r"gridfield explorer: (http://127\.0\.0\.1:(\d+)/)").group(1)
        assert url == f"http://127.0.0.1:{port}/"
        with urllib.request.urlopen(url, timeout=10) as r:
            page = r.read().decode()
        fig_id = figure_id(page)
        assert "mpl.js" in page
        with urllib.request.urlopen(url + "js/mpl.js", timeout=10) as r:
            assert b"mpl.figure" in r.read()

        async def drive():
            ws = await websocket_connect(f"ws://127.0.0.1:{port}/{fig_id}/ws")
            await handshake(ws, fig_id)
            first = await asyncio.wait_for(ws.read_message(), 30)  # the server answers (image mode, image)
            assert first is not None
            reader = asyncio.create_task(answer_draws(ws, fig_id))
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


def test_web_explorer_drops_bad_page_messages_so_later_clients_still_get_images(layout):
    """A NaN device pixel ratio (and other malformed values) from one page used to reach the figure and break
    every later draw until restart; now each is dropped with one line, and a second client gets its image."""
    port = free_port()
    server = ExplorerServer([*MAP_ARGS, "--web", "--port", str(port)])
    try:
        url = server.wait_for(r"gridfield explorer: (http://127\.0\.0\.1:\d+/)").group(1)
        with urllib.request.urlopen(url, timeout=10) as r:
            fig_id = figure_id(r.read().decode())
        bad = [{"type": "set_device_pixel_ratio", "device_pixel_ratio": float("nan")},
               {"type": "set_dpi_ratio", "dpi_ratio": float("inf")},
               {"type": "resize", "width": 10**9, "height": 600},
               {"type": "button_press", "x": float("nan"), "y": 10, "button": 0, "buttons": 1, "modifiers": []},
               {"type": "scroll", "x": 10, "y": 10, "step": float("inf"), "button": 0, "buttons": 0, "modifiers": []}]

        async def image_after_handshake(ws) -> bool:
            await handshake(ws, fig_id)
            await ws.write_message(json.dumps({"type": "draw", "figure_id": fig_id}))
            while True:
                msg = await asyncio.wait_for(ws.read_message(), 30)
                if msg is None:
                    return False
                if isinstance(msg, bytes):
                    return True

        async def drive():
            first = await websocket_connect(f"ws://127.0.0.1:{port}/{fig_id}/ws")
            for msg in bad:
                await first.write_message(json.dumps({**msg, "figure_id": fig_id}))
            for _ in bad:
                await asyncio.get_running_loop().run_in_executor(None, server.wait_for,
                                                                 r"ignored a message from the page: ")
            first.close()
            await first.read_message()  # None once closed
            second = await websocket_connect(f"ws://127.0.0.1:{port}/{fig_id}/ws")
            assert await image_after_handshake(second)
            reader = asyncio.create_task(answer_draws(second, fig_id))
            await click(second, layout["start"], fig_id)
            await asyncio.get_running_loop().run_in_executor(None, server.wait_for, r"start set to \(2, 2\)")
            second.close()
            await reader

        asyncio.run(drive())
        assert not any("Traceback" in line or "Error" in line for line in server.seen), server.seen
    finally:
        server.stop()
