"""Talking to ``gridfield explore MAP --web``: the served process, canvas pixels, the mpl.js messages.

Shared by ``tests/test_explore_web.py`` (which speaks matplotlib's WebAgg websocket protocol itself,
as a browser's ``mpl.js`` does) and ``tools/check_web_explorer.py`` (which clicks in a real headless
chromium). Both start the real command with :class:`ExplorerServer`, find where to click with
:func:`data_pixel` and :func:`button_pixel` on an explorer figure identical to the served one, and
read what happened from the server's status lines.

Not part of the package and not a test module: the test puts ``tools/`` on ``sys.path`` to import
it; the tool finds it beside itself. It imports neither gridfield nor matplotlib: the callers pass
their :class:`gridfield.explore.Explorer`.
"""

from __future__ import annotations

import json
import os
import queue
import re
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]


def free_port() -> int:
    """A TCP port on 127.0.0.1 that is free now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class ExplorerServer:
    """``python -m gridfield explore ARGS`` in a subprocess (run from the repository, which is also its
    ``PYTHONPATH``; ``MPLBACKEND=Agg``); its stdout and stderr lines arrive on a queue.

    ``timeout`` is :meth:`wait_for`'s default; ``echo`` prints every line read (``  server: ...``).
    """

    def __init__(self, args: list[str], *, timeout: float = 60.0, echo: bool = False) -> None:
        env = dict(os.environ, PYTHONPATH=str(REPO), MPLBACKEND="Agg")
        self.proc = subprocess.Popen([sys.executable, "-m", "gridfield", "explore", *args], stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, text=True, env=env, cwd=REPO)
        self.timeout = timeout
        self.echo = echo
        self.lines: queue.Queue[str] = queue.Queue()
        self.seen: list[str] = []
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.put(line.rstrip("\n"))

    def wait_for(self, pattern: str, timeout: float | None = None) -> re.Match[str]:
        """The match of the first line from now on that matches ``pattern``; AssertionError (with the
        output so far) when the server printed none within ``timeout`` seconds or exited."""
        deadline = time.monotonic() + (self.timeout if timeout is None else timeout)
        while time.monotonic() < deadline:
            try:
                line = self.lines.get(timeout=0.2)
            except queue.Empty:
                if self.proc.poll() is not None and self.lines.empty():
                    break
                continue
            self.seen.append(line)
            if self.echo:
                print(f"  server: {line}")
            if m := re.search(pattern, line):
                return m
        raise AssertionError(f"the server printed no line matching {pattern!r}; output so far: {self.seen}")

    def stop(self) -> None:
        """Terminate the server (kill it after 10 s) and close its output."""
        self.proc.terminate()
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.reader.join(10)
        assert self.proc.stdout is not None
        self.proc.stdout.close()


# --- canvas pixels: display coordinates (y up) -> canvas pixels (y down), as mpl.js sends them


def canvas_pixel(explorer: Any, display_xy: Any) -> tuple[float, float]:
    """The canvas pixel (y down) of a point in the figure's display coordinates (y up)."""
    height = explorer.figure.canvas.get_width_height()[1]
    return float(display_xy[0]), float(height - display_xy[1])


def data_pixel(explorer: Any, x: float, y: float) -> tuple[float, float]:
    """The canvas pixel of the map point ``(x, y)``."""
    return canvas_pixel(explorer, explorer.ax.transData.transform((x, y)))


def button_pixel(explorer: Any, name: str) -> tuple[float, float]:
    """The canvas pixel of the centre of the explorer's button ``name`` (a key of ``explorer.buttons``)."""
    return canvas_pixel(explorer, explorer.buttons[name].ax.transAxes.transform((0.5, 0.5)))


# --- the mpl.js side of matplotlib's WebAgg websocket (a tornado websocket client connection ``ws``)


def figure_id(page: str) -> str:
    """The figure number in the served page's HTML (the websocket is ``/<figure_id>/ws``)."""
    m = re.search(r"figure_ready\((\d+)\)", page)
    assert m is not None, "the page names no figure (no figure_ready(...))"
    return m.group(1)


#: What mpl.js sends when it connects (then the server answers with the image mode and an image).
HANDSHAKE: tuple[dict[str, Any], ...] = (
    {"type": "supports_binary", "value": True}, {"type": "send_image_mode"},
    {"type": "set_device_pixel_ratio", "device_pixel_ratio": 1}, {"type": "refresh"},
)


def mouse(kind: str, xy: tuple[float, float], fig_id: str) -> dict[str, Any]:
    """The message mpl.js sends for a left-button press or release at canvas pixel ``xy``."""
    return {"type": kind, "x": xy[0], "y": xy[1], "button": 0, "buttons": 1 if kind == "button_press" else 0,
            "modifiers": [], "guiEvent": {}, "figure_id": fig_id}


async def handshake(ws: Any, fig_id: str) -> None:
    """Send :data:`HANDSHAKE`, as mpl.js does on connecting."""
    for msg in HANDSHAKE:
        await ws.write_message(json.dumps({**msg, "figure_id": fig_id}))


async def click(ws: Any, xy: tuple[float, float], fig_id: str) -> None:
    """A left click (press, release) at canvas pixel ``xy``."""
    await ws.write_message(json.dumps(mouse("button_press", xy, fig_id)))
    await ws.write_message(json.dumps(mouse("button_release", xy, fig_id)))


async def answer_draws(ws: Any, fig_id: str) -> None:
    """Until the connection closes, answer each ``draw`` the server asks for with a draw request, as
    mpl.js does (the server asks for a redraw, the browser requests it)."""
    from tornado.websocket import WebSocketClosedError

    while (msg := await ws.read_message()) is not None:
        if isinstance(msg, str) and json.loads(msg).get("type") == "draw":
            try:
                await ws.write_message(json.dumps({"type": "draw", "figure_id": fig_id}))
            except WebSocketClosedError:
                return
