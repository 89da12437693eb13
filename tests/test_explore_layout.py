"""The explorer's layout, slider ranges and web disconnect (issue: colour bar over the sliders' labels
on tall maps; sliders starting at an end of their range; two WebSocket tracebacks per closed tab)."""

from __future__ import annotations

import os

os.environ.setdefault("MPLBACKEND", "Agg")

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest

from gridfield.core.grid import Grid, GridMap
from gridfield.explore import Explorer


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _explorer(rows: int, cols: int) -> Explorer:
    occ = np.zeros((rows, cols), bool)
    occ[rows // 2, : cols // 2] = True
    return Explorer(GridMap(Grid((rows, cols), 1.0), occ), start=(1.5, 1.5), goal=(cols - 1.5, rows - 1.5))


@pytest.mark.parametrize(("rows", "cols"), [(200, 40), (60, 60), (40, 200)])
def test_colour_bar_beside_the_map_clear_of_the_sliders(rows: int, cols: int) -> None:
    ex = _explorer(rows, cols)
    try:
        ex.figure.canvas.draw()
        r = ex.figure.canvas.get_renderer()
        bar = ex.cax.get_tightbbox(r)  # with its tick labels and label
        drawn = ex.ax.get_window_extent(r)
        assert bar.x0 >= drawn.x1 and bar.x0 - drawn.x1 < 0.03 * ex.figure.bbox.width  # beside the map as drawn
        for name, s in ex.sliders.items():
            label = s.label.get_window_extent(r)
            assert bar.x1 < label.x0 or not s.ax.get_visible(), (name, bar, label)
    finally:
        ex.close()


def test_sliders_start_in_the_middle_of_their_range() -> None:
    ex = _explorer(60, 60)
    try:
        for name, s in ex.sliders.items():
            if name == "d_star" and np.isinf(ex.params.get("d_star", 0.0)):
                continue
            mid = 0.5 * (s.valmin + s.valmax)
            assert s.val == pytest.approx(mid), (name, s.valmin, s.val, s.valmax)
        assert ex.sliders["eta"].val == pytest.approx(128.0)  # the default balanced eta at one unit per cell
    finally:
        ex.close()


class _FakeManager:
    def __init__(self) -> None:
        self.web_sockets: set = set()

    def remove_web_socket(self, ws) -> None:
        self.web_sockets.remove(ws)


def test_a_closed_tab_is_a_clean_disconnect() -> None:
    pytest.importorskip("tornado")
    from tornado.concurrent import Future
    from tornado.iostream import StreamClosedError
    from tornado.websocket import WebSocketClosedError

    from gridfield.cli.explore import _clean_disconnect

    _clean_disconnect()
    from matplotlib.backends.backend_webagg import WebAggApplication

    handler = WebAggApplication.WebSocket

    class Closed:  # a socket whose browser tab went away
        supports_binary = True
        send_json = handler.send_json
        send_binary = handler.send_binary

        def __init__(self, raise_now: bool) -> None:
            self.manager = _FakeManager()
            self.manager.web_sockets.add(self)
            self.raise_now = raise_now

        def write_message(self, message, binary=False):
            if self.raise_now:
                raise WebSocketClosedError()
            f: Future = Future()
            f.set_exception(StreamClosedError())
            return f

    import asyncio

    async def tab_closed(raise_now: bool) -> set:
        ws = Closed(raise_now)
        ws.send_json({"type": "draw"})  # no exception: WebSocketClosedError at once, or a failed write
        ws.send_binary(b"\x89PNG")
        for _ in range(3):
            await asyncio.sleep(0)  # the failed writes' callbacks run (their exceptions are retrieved)
        return ws.manager.web_sockets

    for raise_now in (True, False):
        assert asyncio.run(tab_closed(raise_now)) == set()  # dropped from its figure, as on_close does
