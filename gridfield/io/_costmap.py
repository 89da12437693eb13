"""Nav2 costmaps as map_server files, and ``nav_msgs/OccupancyGrid`` fields in and out.

A costmap is written as a ROS map_server pair: an 8-bit grey PGM (``P5``) whose grey levels are the
costs (top row first) and a YAML with ``mode: raw`` plus a ``costmap:`` mapping (how the costs were
made; map_server ignores keys it does not know). Nav2's map_server loads the pair (``map_io.cpp``,
raw mode: the grey level itself is the OccupancyGrid value, levels above 100 become -1), so costs
0..100 arrive unchanged and higher costs as unknown; gridfield reads every cost back bit-exactly.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path as FsPath
from typing import Any

import numpy as np
import yaml
from numpy.typing import ArrayLike

from ..core.errors import GridfieldError, MapFormatError, ParameterError, shorten
from ..core.grid import Grid, GridMap
from ._bitmap import UNKNOWN_CHOICES, _load_pixels
from ._common import PathLike, _choice
from ._ros import _ros_params
from ._yaml import read_yaml

__all__ = ["from_occupancy_grid", "is_costmap_yaml", "is_occupancy_grid_yaml", "read_costmap", "read_occupancy_grid",
           "to_occupancy_grid", "write_costmap"]

#: The ``format`` of a costmap YAML's ``costmap:`` mapping.
COSTMAP_FORMAT = "gridfield-nav2-costmap"


def is_costmap_yaml(data: Any) -> bool:
    """Whether a parsed YAML document is a costmap's (a ROS map YAML with a ``costmap:`` key)."""
    return isinstance(data, dict) and "costmap" in data and "image" in data


def write_costmap(yaml_path: PathLike, costmap: Any, *, image_name: str | None = None) -> FsPath:
    """Write a :class:`~gridfield.fields.costmap.Costmap` as a map_server YAML (``mode: raw``) and a grey PGM.

    Parameters
    ----------
    yaml_path : str or path-like
    costmap : Costmap
    image_name : str, optional
        File name of the image, relative to the YAML's folder (default: the YAML's stem + ``.pgm``).

    Returns
    -------
    pathlib.Path
        ``yaml_path``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from gridfield.core.grid import Grid
    >>> from gridfield.fields.costmap import Costmap
    >>> cm = Costmap.from_costs(Grid((2, 3), 0.05, origin=(-1.0, 2.5)), np.array([[0, 7, 254], [253, 255, 1]], np.uint8))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     back = read_costmap(write_costmap(pathlib.Path(d) / "c.yaml", cm))
    >>> back.cost.tolist(), back.grid.origin
    ([[0, 7, 254], [253, 255, 1]], (-1.0, 2.5))
    """
    from ..fields.costmap import Costmap

    if not isinstance(costmap, Costmap):
        raise ParameterError(f"costmap must be a gridfield Costmap, got {type(costmap).__name__}")
    yp = FsPath(yaml_path)
    name = image_name if image_name is not None else yp.stem + ".pgm"
    if not isinstance(name, str) or not name or FsPath(name).is_absolute():
        raise ParameterError(f"image_name must be a file name relative to the YAML's folder, got {shorten(image_name)}")
    rows, cols = costmap.cost.shape
    header = f"P5\n{cols} {rows}\n255\n".encode("ascii")
    x0, y0 = costmap.grid.origin
    info = {"format": COSTMAP_FORMAT, "version": 1}
    info.update({k: (v if not isinstance(v, np.generic) else v.item()) for k, v in dict(costmap.inflation).items()})
    doc = {
        "image": name,
        "mode": "raw",
        "resolution": float(costmap.grid.resolution),
        "origin": [float(x0), float(y0), 0.0],
        "negate": 0,
        "occupied_thresh": 0.65,
        "free_thresh": 0.196,
        "costmap": info,
    }
    try:
        (yp.parent / name).write_bytes(header + np.ascontiguousarray(costmap.cost[::-1]).tobytes())
        yp.write_text("# a Nav2 costmap written by gridfield: the grey levels are the costs 0..255 (mode raw)\n"
                      + yaml.safe_dump(doc, sort_keys=False, default_flow_style=None), encoding="utf-8")
    except OSError as e:
        raise GridfieldError(f"{yp}: cannot write: {e.strerror or e}") from None
    return yp


def read_costmap(yaml_path: PathLike) -> Any:
    """Read a costmap written by :func:`write_costmap` (or any raw-mode map YAML with a ``costmap:`` key).

    Parameters
    ----------
    yaml_path : str or path-like

    Returns
    -------
    Costmap
        The costs bit-exactly as written, the grid (border ``open``) and ``inflation`` from the YAML.

    Raises
    ------
    MapFormatError
        A YAML that is not a costmap's, a ``mode`` other than ``raw``, an image that is not 8-bit grey.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from gridfield.core.grid import Grid
    >>> from gridfield.fields.costmap import Costmap
    >>> cm = Costmap.from_costs(Grid((1, 3), 0.05), np.array([[0, 128, 255]], np.uint8), {"robot_radius": 0.1})
    >>> with tempfile.TemporaryDirectory() as d:
    ...     back = read_costmap(write_costmap(pathlib.Path(d) / "c.yaml", cm))
    >>> back.cost.tolist(), back.inflation["robot_radius"], back.occupied.tolist()
    ([[0, 128, 255]], 0.1, [[False, False, True]])
    """
    from ..fields.costmap import Costmap

    prm = _ros_params(yaml_path)
    data = read_yaml(prm.yaml)
    if not is_costmap_yaml(data):
        raise MapFormatError(f"{prm.yaml}: not a costmap YAML (it has no 'costmap:' mapping)")
    if prm.mode != "raw":
        raise MapFormatError(f"{prm.yaml}: a costmap YAML must say 'mode: raw' (its grey levels are the costs), "
                             f"got mode {prm.mode!r}")
    info = data["costmap"]
    if not isinstance(info, dict):
        raise MapFormatError(f"{prm.yaml}: 'costmap' must be a mapping, got {shorten(info)}")
    ox, oy, yaw = prm.origin
    if abs(yaw) > 1e-12:
        raise MapFormatError(f"{prm.yaml}: origin yaw {yaw:g} rad is not supported (gridfield grids are axis-aligned)")
    px = _load_pixels(prm.image)
    if px.data.shape[2] != 1:
        raise MapFormatError(f"{prm.image}: a costmap image must be 8-bit grey (one channel), got "
                             f"{px.data.shape[2]} channels")
    grey = px.data[..., 0]
    if grey.size and (grey.min() < 0 or grey.max() > 255 or not bool(np.all(grey == np.rint(grey)))):
        raise MapFormatError(f"{prm.image}: a costmap image must hold the grey levels 0..255")
    cost = np.ascontiguousarray(grey[::-1].astype(np.uint8))
    try:
        grid = Grid(cost.shape, prm.resolution, (ox, oy), "open")
    except ParameterError as e:
        raise MapFormatError(f"{prm.yaml}: {e}") from None
    inflation = {k: v for k, v in info.items() if k not in ("format", "version")}
    return Costmap.from_costs(grid, cost, inflation, source=str(yaml_path),
                              meta={"format": "costmap", "mode": "raw",
                                    "occupancy_rule": "Nav2 costmap: cost 253 (inscribed) and above = obstacle"})


# ----------------------------------------------------------------------------------------
# nav_msgs/OccupancyGrid
# ----------------------------------------------------------------------------------------
def _origin(origin: Any) -> tuple[float, float]:
    try:
        vals = [float(v) for v in origin]
    except (TypeError, ValueError):
        vals = []
    if len(vals) not in (2, 3) or not all(math.isfinite(v) for v in vals) or isinstance(origin, str):
        raise ParameterError(f"origin must be (x, y) or (x, y, yaw) finite numbers, got {shorten(origin)}")
    if len(vals) == 3 and abs(vals[2]) > 1e-12:
        raise ParameterError(f"origin yaw {vals[2]:g} rad is not supported: gridfield grids are axis-aligned")
    return vals[0], vals[1]


def from_occupancy_grid(data: ArrayLike | Sequence[int], width: int, height: int, resolution: float,
                        origin: Sequence[float], *, unknown: str = "occupied", border: str | None = None) -> GridMap:
    """An occupancy map from the fields of a ``nav_msgs/OccupancyGrid`` message.

    Parameters
    ----------
    data : sequence of int
        ``info.width * info.height`` values, row-major from the origin (the first row is the lowest y):
        -1 unknown, 0..100 occupancy probability in percent.
    width, height : int
        ``info.width`` (columns), ``info.height`` (rows).
    resolution : float
        ``info.resolution`` (m per cell).
    origin : (x, y) or (x, y, yaw)
        ``info.origin``'s position (yaw must be 0).
    unknown : {"occupied", "free"}
        What -1 becomes.
    border : {"open", "wall"}, optional
        Default: "wall" when unknown cells are occupied, else "open" (as :func:`read_ros_map`).

    Returns
    -------
    GridMap
        Cells of value 100 (and unknown cells with ``unknown="occupied"``) occupied, as the costmap
        static layer reads them; ``meta`` holds the values (``occupancy``) and ``unknown_fraction``.

    Raises
    ------
    ParameterError
        A data length that is not ``width * height``, a value outside -1..100, a bad size or origin.

    Examples
    --------
    >>> m = from_occupancy_grid([0, 100, -1, 0, 0, 0], 3, 2, 0.05, (1.0, 2.0, 0.0))
    >>> m.occupied.astype(int).tolist(), m.grid.origin
    ([[0, 1, 1], [0, 0, 0]], (1.0, 2.0))
    >>> to_occupancy_grid(m)["data"].tolist()
    [0, 100, -1, 0, 0, 0]
    """
    _choice("unknown", unknown, UNKNOWN_CHOICES)
    for name, v in (("width", width), ("height", height)):
        if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < 1:
            raise ParameterError(f"{name} must be an integer >= 1, got {shorten(v)}")
    try:
        arr = np.asarray(data)
    except (TypeError, ValueError) as e:
        raise ParameterError(f"data must be a sequence of integers, got {type(data).__name__} ({e})") from None
    if arr.ndim != 1:
        arr = arr.reshape(-1) if arr.ndim > 1 else arr
    n = int(width) * int(height)
    if arr.size != n:
        raise ParameterError(f"OccupancyGrid data has {arr.size} values, but width * height = {width} * {height} = {n}")
    if arr.size and not np.issubdtype(arr.dtype, np.integer):
        raise ParameterError(f"OccupancyGrid data must hold integers (int8), got dtype {arr.dtype}")
    values = arr.astype(np.int64)
    bad = (values < -1) | (values > 100)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ParameterError(f"OccupancyGrid data[{i}] = {int(values[i])} is not -1 (unknown) or 0..100")
    res = float(resolution)
    x0, y0 = _origin(origin)
    grid_values = values.reshape(int(height), int(width)).astype(np.int8)
    is_unknown = grid_values == -1
    occupied = grid_values >= 100
    if unknown == "occupied":
        occupied |= is_unknown
    if border is None:
        border = "wall" if unknown == "occupied" else "open"
    if border not in ("open", "wall"):
        raise ParameterError(f"border must be 'open' or 'wall', got {shorten(border)}")
    grid = Grid((int(height), int(width)), res, (x0, y0), "open" if border == "open" else "wall")
    meta = {"format": "occupancy_grid", "occupancy": grid_values, "unknown_fraction": float(is_unknown.mean()),
            "occupancy_rule": "OccupancyGrid values: 100 occupied, -1 unknown, 0..99 free"}
    return GridMap(grid, np.ascontiguousarray(occupied), source="OccupancyGrid", meta=meta)


def to_occupancy_grid(gridmap: GridMap, *, unknown: ArrayLike | None = None) -> dict[str, Any]:
    """The fields of a ``nav_msgs/OccupancyGrid`` for an occupancy map (or a costmap).

    Parameters
    ----------
    gridmap : GridMap
        Occupied cells become 100, free cells 0. A map from :func:`from_occupancy_grid` gives back
        its own values. A :class:`~gridfield.fields.costmap.Costmap` gives Nav2's costmap publisher's
        translation (0 -> 0, 1..252 -> 1..98, 253 -> 99, 254 -> 100, 255 -> -1).
    unknown : array of bool, optional
        Cells written as -1.

    Returns
    -------
    dict
        ``data`` (int8, row-major from the origin), ``width``, ``height``, ``resolution``, ``origin``
        ``(x, y, 0.0)``: the keyword arguments of :func:`from_occupancy_grid`.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> msg = to_occupancy_grid(GridMap(Grid((2, 2), 0.05), np.array([[True, False], [False, False]])))
    >>> msg["data"].tolist(), msg["width"], msg["height"], msg["origin"]
    ([100, 0, 0, 0], 2, 2, (0.0, 0.0, 0.0))
    """
    from ..fields.costmap import Costmap

    if not isinstance(gridmap, GridMap):
        raise ParameterError(f"gridmap must be a GridMap, got {type(gridmap).__name__}")
    g = gridmap.grid
    if isinstance(gridmap, Costmap):
        c = gridmap.cost.astype(np.int64)
        # nav2_costmap_2d Costmap2DPublisher's cost_translation_table
        mid = 1 + (97 * (c - 1)) // 251
        values = np.where(c == 0, 0, np.where(c == 253, 99, np.where(c == 254, 100, np.where(c == 255, -1, mid))))
    else:
        occ = gridmap.meta.get("occupancy") if gridmap.meta.get("format") == "occupancy_grid" else None
        values = np.where(gridmap.occupied, 100, 0)
        if isinstance(occ, np.ndarray) and occ.shape == g.shape:
            # the message's own values, while the occupancy still is theirs (a copy with other cells is not)
            same = np.where(occ == -1, True, (occ >= 100) == gridmap.occupied)
            if bool(same.all()):
                values = occ.astype(np.int64)
    if unknown is not None:
        u = np.asarray(unknown, dtype=bool)
        if u.shape != g.shape:
            raise ParameterError(f"unknown must have the grid's shape {g.shape}, got {u.shape}")
        values = np.where(u, -1, values)
    x0, y0 = g.origin
    return {"data": np.ascontiguousarray(values.astype(np.int8).reshape(-1)), "width": g.cols, "height": g.rows,
            "resolution": float(g.resolution), "origin": (float(x0), float(y0), 0.0)}


def is_occupancy_grid_yaml(data: Any) -> bool:
    """Whether a parsed YAML document is a ``nav_msgs/OccupancyGrid`` message (``info`` and ``data``)."""
    return isinstance(data, dict) and "info" in data and "data" in data and "image" not in data


def read_occupancy_grid(path: PathLike, *, unknown: str = "occupied", border: str | None = None) -> GridMap:
    """Read a ``nav_msgs/OccupancyGrid`` message saved as YAML (``ros2 topic echo --once /map > map_msg.yaml``).

    Parameters
    ----------
    path : str or path-like
        YAML with ``info`` (``width``, ``height``, ``resolution``, ``origin.position.x/y``,
        ``origin.orientation``, which must be the identity rotation about z) and ``data``.
    unknown, border
        As :func:`from_occupancy_grid`.

    Returns
    -------
    GridMap
        :func:`from_occupancy_grid` of the message's fields.

    Raises
    ------
    MapFormatError
        A missing or malformed field, a rotated origin, a data length other than ``width * height``,
        a value outside -1..100 (naming the file).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> text = ("info: {width: 2, height: 1, resolution: 0.05, origin: {position: {x: 1.0, y: 2.0, z: 0.0}, "
    ...         "orientation: {x: 0.0, y: 0.0, z: 0.0, w: 1.0}}}\\ndata: [0, 100]\\n")
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "m.yaml"; _ = p.write_text(text)
    ...     m = read_occupancy_grid(p)
    >>> m.occupied.tolist(), m.grid.origin
    ([[False, True]], (1.0, 2.0))
    """
    from ._common import _check_file

    p = _check_file(path)
    doc = read_yaml(p)
    if not is_occupancy_grid_yaml(doc):
        raise MapFormatError(f"{p}: not an OccupancyGrid message (it needs 'info' and 'data')")
    info = doc["info"]
    try:
        width, height, res = info["width"], info["height"], info["resolution"]
        pos = info.get("origin", {}).get("position", {})
        quat = info.get("origin", {}).get("orientation", {})
        x0, y0 = float(pos.get("x", 0.0)), float(pos.get("y", 0.0))
        qx, qy, qz, qw = (float(quat.get(k, d)) for k, d in (("x", 0.0), ("y", 0.0), ("z", 0.0), ("w", 1.0)))
    except (TypeError, ValueError, KeyError, AttributeError) as e:
        raise MapFormatError(f"{p}: malformed OccupancyGrid 'info' ({shorten(e)}); it needs width, height, "
                             "resolution and origin.position") from None
    if abs(qx) > 1e-9 or abs(qy) > 1e-9 or abs(qz) > 1e-9:
        raise MapFormatError(f"{p}: the origin is rotated (orientation {qx:g}, {qy:g}, {qz:g}, {qw:g}); gridfield "
                             "grids are axis-aligned")
    if not isinstance(doc["data"], list):
        raise MapFormatError(f"{p}: 'data' must be a list of integers, got {shorten(doc['data'])}")
    try:
        return from_occupancy_grid(np.asarray(doc["data"], dtype=np.int64) if doc["data"] else np.zeros(0, np.int64),
                                   width, height, res, (x0, y0), unknown=unknown, border=border)
    except (ParameterError, GridfieldError, TypeError, ValueError, OverflowError) as e:
        raise MapFormatError(f"{p}: {e}") from None
