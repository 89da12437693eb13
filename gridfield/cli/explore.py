"""``gridfield explore``: the interactive explorer (obstacles, robot, configuration space, plan) in a window or a browser."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from ._common import add_map_arguments, add_param_arguments, add_robot_arguments, collect_params, load_target


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "explore", help="open the interactive explorer on a map (a window, or a browser with --web)",
        description="Open the interactive explorer: left clicks set the start and then the "
                    "goal; buttons (and keys) draw obstacles and the robot, compute the configuration space, "
                    "calculate the path, record a movie, show the 3-D potential, undo and clear; sliders set the "
                    "current planner's parameters; radio buttons switch the planner. Needs an interactive "
                    "matplotlib backend (e.g. MPLBACKEND=TkAgg or QtAgg), or --web (a browser, no desktop "
                    "toolkit: needs tornado, pip install gridfield[web]).")
    add_map_arguments(p)
    p.add_argument("--start", nargs=2, type=float, metavar=("X", "Y"), help="start point (default: the world's)")
    p.add_argument("--goal", nargs=2, type=float, metavar=("X", "Y"), help="goal point (default: the world's)")
    # checked in run(): importing gridfield.explore here would load shapely for every `gridfield --help`
    p.add_argument("--planner", default="potential",
                   help="planner shown first: potential (default), exact-potential, wavefront-octile or navfn")
    p.add_argument("--save", metavar="F",
                   help="do not open a window: save a snapshot of the explorer (PNG) and exit (works headless)")
    p.add_argument("--movie", metavar="F", default=None,
                   help="file the 'movie' button writes (.gif, plus .mp4 when ffmpeg exists; default "
                        "gridfield_movie.gif)")
    p.add_argument("--web", action="store_true",
                   help="serve the explorer to a browser (matplotlib's WebAgg on 127.0.0.1) instead of a window")
    p.add_argument("--port", type=int, default=8988, metavar="P", help="port of --web (default 8988, or the next free)")
    add_robot_arguments(p)
    add_param_arguments(p)
    return p


def _interactive_backend() -> bool:
    import matplotlib
    from matplotlib.backends.registry import BackendFilter, backend_registry

    backend = matplotlib.get_backend().lower()
    return backend not in backend_registry.list_builtin(BackendFilter.NON_INTERACTIVE) and not backend.startswith(
        "module://matplotlib_inline")


def _use_webagg(port: int) -> None:
    """Switch matplotlib to WebAgg, serving on 127.0.0.1 only, without opening a browser."""
    from ..core.errors import GridfieldError, ParameterError

    if not 0 < port < 65536:
        raise ParameterError(f"--port must be a port number 1..65535, got {port}")
    try:
        import tornado  # noqa: F401
    except ImportError:
        raise GridfieldError("--web needs tornado: pip install 'gridfield[web]' (or pip install tornado)") from None
    import matplotlib

    matplotlib.use("webagg", force=True)
    matplotlib.rcParams["webagg.address"] = "127.0.0.1"
    matplotlib.rcParams["webagg.port"] = port
    matplotlib.rcParams["webagg.open_in_browser"] = False
    _clean_disconnect()


def _clean_disconnect() -> None:
    """A browser tab that closes is a clean disconnect: matplotlib's WebAgg socket handler sends the
    next frames to a socket that is gone, and tornado raised (``WebSocketClosedError``) or left a
    failed write unretrieved (``StreamClosedError``), two tracebacks on the server per closed tab.
    The handler's two send methods are wrapped once: a closed socket is dropped from its figure
    (as its ``on_close`` does) and a write that fails because the stream closed is consumed.
    Incoming messages are not touched."""
    from matplotlib.backends.backend_webagg import WebAggApplication

    from ..core.errors import GridfieldError

    try:
        from tornado.iostream import StreamClosedError
        from tornado.websocket import WebSocketClosedError
    except ImportError:
        raise GridfieldError("--web needs tornado: pip install 'gridfield[web]' (or pip install tornado)") from None

    handler: Any = WebAggApplication.WebSocket
    if getattr(handler, "_gridfield_clean_disconnect", False):
        return

    def closed(ws: Any) -> None:
        manager = getattr(ws, "manager", None)
        if manager is not None and ws in getattr(manager, "web_sockets", ()):
            manager.remove_web_socket(ws)

    def consume(ws: Any, future: Any) -> None:
        if future is None:
            return

        def done(f: Any) -> None:
            if not f.cancelled() and isinstance(f.exception(), StreamClosedError | WebSocketClosedError):
                closed(ws)

        future.add_done_callback(done)

    def send_json(self: Any, content: Any) -> None:
        import json

        try:
            consume(self, self.write_message(json.dumps(content)))
        except WebSocketClosedError:
            closed(self)

    original_binary = handler.send_binary

    def send_binary(self: Any, blob: Any) -> None:
        write = self.write_message
        futures: list[Any] = []

        def keep(*a: Any, **k: Any) -> Any:
            futures.append(write(*a, **k))
            return futures[-1]

        self.write_message = keep
        try:
            original_binary(self, blob)
        except WebSocketClosedError:
            closed(self)
        finally:
            del self.write_message
        for f in futures:
            consume(self, f)

    handler.send_json = send_json
    handler.send_binary = send_binary
    handler._gridfield_clean_disconnect = True


#: What the served page may send (matplotlib's mpl.js): the device pixel ratio, the canvas size in CSS pixels,
#: and how far outside the canvas an event may be (a drag leaving it), in canvas widths.
WEB_PIXEL_RATIO = (0.25, 8.0)
WEB_SIZE = (1, 8192)
WEB_EVENT_MARGIN = 1.0
_WEB_MOUSE = ("button_press", "button_release", "dblclick", "motion_notify", "scroll", "figure_enter", "figure_leave")
_WEB_OTHER = ("ack", "draw", "refresh", "send_image_mode", "supports_binary", "key_press", "key_release",
              "toolbar_button", "resize", "set_device_pixel_ratio", "set_dpi_ratio")


def _number(event: dict[str, Any], key: str, lo: float, hi: float, default: float | None = None) -> str | None:
    """None if ``event[key]`` is a finite number in ``[lo, hi]`` (or absent with a default), else the reason."""
    import math

    v = event.get(key, default)
    if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v) or not lo <= v <= hi:
        return f"{key} must be a finite number in [{lo:g}, {hi:g}], got {v!r:.40}"
    return None


def web_message_problem(event: object, width: float, height: float) -> str | None:
    """Why a message from the web page must not reach the figure (None: it may).

    Parameters
    ----------
    event : object
        The decoded JSON message.
    width, height : float
        The canvas size in physical pixels (event coordinates are checked against it).

    Returns
    -------
    str or None
        One line naming the field at fault.

    Examples
    --------
    >>> web_message_problem({"type": "set_device_pixel_ratio", "device_pixel_ratio": float("nan")}, 800, 600)
    'device_pixel_ratio must be a finite number in [0.25, 8], got nan'
    >>> web_message_problem({"type": "button_press", "x": 10, "y": 20, "button": 0, "buttons": 1,
    ...                      "modifiers": []}, 800, 600) is None
    True
    """
    if not isinstance(event, dict) or not isinstance(event.get("type"), str):
        return "a message must be a JSON object with a 'type'"
    kind = event["type"]
    if kind in ("set_device_pixel_ratio", "set_dpi_ratio"):
        key = "device_pixel_ratio" if kind == "set_device_pixel_ratio" else "dpi_ratio"
        return _number(event, key, *WEB_PIXEL_RATIO, default=1)
    if kind == "resize":
        return _number(event, "width", *WEB_SIZE, default=800) or _number(event, "height", *WEB_SIZE, default=800)
    if kind in _WEB_MOUSE:
        m = WEB_EVENT_MARGIN
        bad = (_number(event, "x", -m * width, (1 + m) * width) or _number(event, "y", -m * height, (1 + m) * height)
               or _number(event, "button", 0, 4, default=0) or _number(event, "buttons", 0, 31, default=0))
        if bad is None and kind == "scroll":
            bad = _number(event, "step", -1000, 1000)
        mods = event.get("modifiers", [])
        if bad is None and not (isinstance(mods, list) and len(mods) <= 8 and all(isinstance(x, str) and len(x) <= 16
                                                                                   for x in mods)):
            bad = "modifiers must be a short list of key names"
        return bad
    if kind in ("key_press", "key_release"):
        name = event.get("key")
        return None if isinstance(name, str) and 0 < len(name) <= 64 else "key must be a key name"
    if kind == "toolbar_button":
        return None if isinstance(event.get("name"), str) and len(event["name"]) <= 64 else "name must be a tool name"
    if kind in _WEB_OTHER:
        return None
    return f"unknown message type {kind!r:.40}"


def _guard_web_canvas(canvas: object, log: object) -> None:
    """Check every message of the page before the WebAgg canvas handles it; a bad one is dropped (one line
    on stdout), so that one client cannot break the figure for every later one (a NaN pixel ratio did)."""
    handle = canvas.handle_event  # type: ignore[attr-defined]

    def checked(event: object) -> object:
        w, h = canvas.get_width_height(physical=True)  # type: ignore[attr-defined]
        problem = web_message_problem(event, w, h)
        if problem is not None:
            log(f"ignored a message from the page: {problem}")  # type: ignore[operator]
            return None
        return handle(event)

    canvas.handle_event = checked  # type: ignore[attr-defined]


def run(args: argparse.Namespace) -> int:
    from ..core.errors import GridfieldError, ParameterError
    from ..explore import EXPLORER_PLANNERS, Explorer
    from ._common import _robot_from_args

    if args.planner not in EXPLORER_PLANNERS:
        raise ParameterError(f"--planner must be one of {', '.join(EXPLORER_PLANNERS)}, got {args.planner!r}")
    from ._common import check_figure_file
    if args.web and args.save is not None:
        raise ParameterError("--web serves the explorer; --save writes a snapshot: give one of them")

    check_figure_file(args.save, "--save")
    target = load_target(args)
    if args.web:
        _use_webagg(args.port)
    elif args.save is None and not _interactive_backend():
        import matplotlib

        raise GridfieldError(
            f"matplotlib's backend {matplotlib.get_backend()!r} cannot open a window; set MPLBACKEND to an "
            "interactive one (TkAgg, QtAgg), pass --web to use a browser, or --save F to write a snapshot")

    def log(text: str) -> None:
        print(text, flush=True)

    explorer = Explorer(target, params=collect_params(args), planner=args.planner, resolution=args.resolution,
                        start=args.start, goal=args.goal, robot=_robot_from_args(args, target),
                        movie_file=args.movie, on_message=log if args.web else None)
    if args.save is not None:
        try:
            explorer.figure.savefig(args.save, dpi=100)
        except (OSError, ValueError) as e:
            explorer.close()
            raise GridfieldError(f"{args.save}: cannot write the snapshot: {e}") from None
        explorer.close()
        print(f"wrote {args.save}: {explorer.message}")
        return 0
    import matplotlib.pyplot as plt

    if args.web:
        from matplotlib.backends.backend_webagg import WebAggApplication

        _guard_web_canvas(explorer.figure.canvas, log)

        try:
            WebAggApplication.initialize()
        except SystemExit:
            raise GridfieldError(f"no free port near {args.port} on 127.0.0.1; pass another --port") from None
        port = WebAggApplication.port  # type: ignore[attr-defined]  # set by initialize()
        print(f"gridfield explorer: http://127.0.0.1:{port}/ (Ctrl+C stops the server)",
              flush=True)
    else:
        print(explorer.message, file=sys.stderr)
    plt.show()
    return 0
