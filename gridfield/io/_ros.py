"""ROS map_server maps (YAML + image): the OccupancyGrid values as ROS 1 or Nav2 computes them, and the grid.

Both reference loaders are followed exactly (``semantics``), because they disagree in corner cases
(channel mean against luma, strict against inclusive thresholds, alpha); the values are then read like
the ROS costmap static layer does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path as FsPath
from typing import Any, Literal

import numpy as np
import yaml
from numpy.typing import NDArray

from ..core.errors import GridfieldError, MapFormatError, ParameterError, shorten
from ..core.grid import BORDERS, Grid, GridMap
from ._bitmap import UNKNOWN_CHOICES, _load_pixels, _Pixels, write_bitmap
from ._common import PathLike, _check_file, _check_regular, _choice
from ._yaml import read_yaml

SEMANTICS = ("nav2", "ros1")
ROS_MODES = ("trinary", "scale", "raw")


# ----------------------------------------------------------------------------------------
# ROS map_server maps
# ----------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _RosParams:
    yaml: FsPath
    image: FsPath
    resolution: float
    origin: tuple[float, float, float]
    negate: bool
    occupied_thresh: float
    free_thresh: float
    mode: str


def _ros_number(p: FsPath, key: str, value: Any) -> float:
    try:
        if isinstance(value, bool):
            raise TypeError
        return float(value)
    except (TypeError, ValueError):
        raise MapFormatError(f"{p}: '{key}' must be a number, got {shorten(value)}") from None


def _ros_params(yaml_path: PathLike) -> _RosParams:
    p = _check_file(yaml_path)
    data = read_yaml(p)
    if not isinstance(data, dict):
        raise MapFormatError(f"{p}: a ROS map YAML must be a mapping with 'image', 'resolution' and 'origin'")
    missing = [k for k in ("image", "resolution", "origin") if k not in data]
    if missing:
        raise MapFormatError(
            f"{p}: missing key{'s' if len(missing) > 1 else ''} {', '.join(map(repr, missing))}; a ROS map YAML "
            "needs image, resolution and origin [x, y, yaw]"
        )
    image = data["image"]
    if not isinstance(image, str) or not image.strip():
        raise MapFormatError(f"{p}: 'image' must be the image file name, got {shorten(image)}")
    img = FsPath(image)
    if not img.is_absolute():
        img = p.parent / img
    if not img.exists():
        raise MapFormatError(f"{p}: the image file {shorten(image)} does not exist (looked for {img})")
    if img.is_dir():
        raise MapFormatError(f"{p}: 'image' names a directory ({img}), expected an image file")
    _check_regular(img, f"{p}: 'image': ")

    res = _ros_number(p, "resolution", data["resolution"])
    if not (math.isfinite(res) and res > 0):
        raise MapFormatError(f"{p}: 'resolution' must be a positive finite number, got {shorten(data['resolution'])}")

    origin = data["origin"]
    if not isinstance(origin, list | tuple) or len(origin) != 3:
        raise MapFormatError(f"{p}: 'origin' must be [x, y, yaw], got {shorten(origin)}")
    ox, oy, yaw = (_ros_number(p, "origin", v) for v in origin)
    if not all(math.isfinite(v) for v in (ox, oy, yaw)):
        raise MapFormatError(f"{p}: 'origin' must hold finite numbers, got {shorten(origin)}")

    negate = data.get("negate", 0)
    if isinstance(negate, bool) or negate in (0, 1):
        neg = bool(negate)
    else:
        raise MapFormatError(f"{p}: 'negate' must be 0 or 1, got {shorten(negate)}")

    occ_th = _ros_number(p, "occupied_thresh", data.get("occupied_thresh", 0.65))
    free_th = _ros_number(p, "free_thresh", data.get("free_thresh", 0.196))
    for key, v in (("occupied_thresh", occ_th), ("free_thresh", free_th)):
        if not 0.0 <= v <= 1.0:
            raise MapFormatError(f"{p}: '{key}' must be in [0, 1], got {shorten(data.get(key))}")
    if not free_th < occ_th:
        raise MapFormatError(
            f"{p}: 'free_thresh' ({free_th:g}) must be smaller than 'occupied_thresh' ({occ_th:g})"
        )

    mode = data.get("mode", "trinary")
    if not isinstance(mode, str) or mode.strip().lower() not in ROS_MODES:
        raise MapFormatError(f"{p}: 'mode' must be one of {', '.join(ROS_MODES)}, got {shorten(mode)}")
    return _RosParams(p, img, res, (ox, oy, yaw), neg, occ_th, free_th, mode.strip().lower())


def _ros1_values(px: _Pixels, prm: _RosParams) -> NDArray[np.int8]:
    """ROS 1 map_server (image_loader.cpp): channel mean, strict thresholds, top row first."""
    d = px.data
    c = d.shape[2]
    # Trinary mode (or no alpha channel): average every channel, alpha included.
    avg = d.mean(axis=2) if (prm.mode == "trinary" or not px.has_alpha) else d[..., : c - 1].mean(axis=2)
    # ROS 1 reads "alpha" from the last channel of any multi-channel image.
    alpha = d[..., c - 1] if c > 1 else np.full(avg.shape, 255.0)
    if prm.negate:
        avg = 255.0 - avg
    if prm.mode == "raw":
        raw: NDArray[np.int8] = np.trunc(avg).astype(np.int64).astype(np.uint8).view(np.int8)
        return raw
    occ = (255.0 - avg) / 255.0
    if prm.mode == "trinary":
        middle = np.full(avg.shape, -1, dtype=np.int64)
    else:
        ratio = (occ - prm.free_thresh) / (prm.occupied_thresh - prm.free_thresh)
        middle = np.where(alpha < 1.0, -1, np.trunc(1.0 + 98.0 * ratio)).astype(np.int64)
    values = np.where(occ > prm.occupied_thresh, 100, np.where(occ < prm.free_thresh, 0, middle))
    return values.astype(np.int8)


def _nav2_values(px: _Pixels, prm: _RosParams) -> NDArray[np.int8]:
    """Nav2 map_io: luma grey, float32 shade, inclusive thresholds, alpha < 255 unknown, top row first."""
    grey = px.luma()
    shade = grey.astype(np.float32) / np.float32(255.0)
    if prm.mode == "raw":
        level = np.rint(shade.astype(np.float64) * 255.0)
        return np.where(level <= 100, level, -1).astype(np.int8)
    occ = (shade if prm.negate else np.float32(1.0) - shade).astype(np.float64)
    if prm.mode == "trinary":
        middle = np.full(grey.shape, -1, dtype=np.int64)
    else:
        ratio = (occ - prm.free_thresh) / (prm.occupied_thresh - prm.free_thresh)
        middle = np.rint(ratio * 100.0).astype(np.int64)
    values = np.where(occ >= prm.occupied_thresh, 100, np.where(occ <= prm.free_thresh, 0, middle))
    alpha = px.alpha
    if alpha is not None:
        values = np.where(alpha < 255.0, -1, values)
    return values.astype(np.int8)


def _ros_values_top_first(prm: _RosParams, semantics: str) -> NDArray[np.int8]:
    px = _load_pixels(prm.image)
    return _ros1_values(px, prm) if semantics == "ros1" else _nav2_values(px, prm)


def ros_occupancy_values(yaml_path: PathLike, *, semantics: Literal["nav2", "ros1"] = "nav2") -> NDArray[np.int8]:
    """The ``nav_msgs/OccupancyGrid`` values ROS map_server would publish for a map YAML.

    Values are 0 (free), 100 (occupied), -1 (unknown) or, in ``scale`` mode, scaled
    occupancies in between; ``raw`` mode gives the grey levels as ROS does. The array has
    gridfield's row order (row 0 = lowest y = the image's bottom row), which is also the
    order of ``OccupancyGrid.data``. The origin's yaw does not change the values and is not
    checked here (see :func:`read_ros_map`).

    Parameters
    ----------
    yaml_path : str or path-like
    semantics : {"nav2", "ros1"}
        ``"ros1"``: ROS 1 map_server (mean of the channels, alpha averaged in trinary mode,
        strict thresholds ``occ > occupied_thresh`` / ``occ < free_thresh``, scale mode
        ``1 + 98 * ratio`` truncated, alpha == 0 unknown in scale mode). ``"nav2"``: Nav2
        map_io (Rec. 601 luma, float32, inclusive thresholds ``>=`` / ``<=``, scale mode
        ``round(100 * ratio)``, raw mode grey levels above 100 unknown, any pixel with alpha < 255
        unknown in trinary and scale mode).

    Returns
    -------
    ndarray of int8, shape (rows, cols)

    Examples
    --------
    >>> from gridfield.io import bundled_map
    >>> v = ros_occupancy_values(bundled_map("turtlebot3_world/map.yaml"))
    >>> v.shape, sorted(np.unique(v).tolist())
    ((384, 384), [-1, 0, 100])
    """
    _choice("semantics", semantics, SEMANTICS)
    prm = _ros_params(yaml_path)
    return np.ascontiguousarray(_ros_values_top_first(prm, semantics)[::-1])


def read_ros_map(
    yaml_path: PathLike,
    *,
    unknown: Literal["occupied", "free"] = "occupied",
    semantics: Literal["nav2", "ros1"] = "nav2",
    border: Literal["open", "wall"] | None = None,
) -> GridMap:
    """Read a ROS map_server map (YAML + image) as an occupancy grid.

    Keys: ``image`` (relative to the YAML file, or absolute), ``resolution``, ``origin``
    ``[x, y, yaw]`` (the world pose of the lower-left pixel) — all three required — and
    ``negate`` (default 0), ``occupied_thresh`` (default 0.65), ``free_thresh`` (default
    0.196), ``mode`` (``trinary``, ``scale`` or ``raw``; absent means trinary).

    The image is turned into OccupancyGrid values exactly as ROS does
    (:func:`ros_occupancy_values`), then, like the ROS costmap static layer: 100 and above is
    an obstacle, -1 is unknown, everything else is free. Unknown cells become obstacles
    (``unknown="occupied"``, the default) or free space.

    Rotated origins (``yaw != 0``) are not supported — gridfield grids are axis-aligned — and
    raise :class:`MapFormatError` naming the file and the yaw instead of being ignored.

    Parameters
    ----------
    yaml_path : str or path-like
    unknown : {"occupied", "free"}
    semantics : {"nav2", "ros1"}
        Which reference loader to follow; they differ only in corner cases (see
        :func:`ros_occupancy_values`).
    border : {"open", "wall"}, optional
        What lies outside the map. Default: the space outside a ROS map is unknown, so it
        follows ``unknown`` ("wall" when unknown cells are occupied, else "open").

    Returns
    -------
    GridMap
        ``meta`` holds ``format="ros"``, ``semantics``, ``mode``, ``unknown_fraction`` and ``occupancy_rule`` (the
        thresholds in words).

    Examples
    --------
    >>> from gridfield.io import bundled_map
    >>> m = read_ros_map(bundled_map("turtlebot3_world/map.yaml"))
    >>> m.shape, m.grid.resolution, m.grid.origin, m.grid.border
    ((384, 384), 0.05, (-10.0, -10.0), 'wall')
    >>> round(m.meta["unknown_fraction"], 3)
    0.941
    >>> for part in m.meta["occupancy_rule"].split(", "):
    ...     print(part)
    ROS map_server trinary (nav2): occupancy (255 - v) / 255 >= occupied_thresh 0.65 occupied
    <= free_thresh 0.196 free
    between unknown
    """
    _choice("unknown", unknown, UNKNOWN_CHOICES)
    _choice("semantics", semantics, SEMANTICS)
    if border is not None:
        _choice("border", border, BORDERS)
    prm = _ros_params(yaml_path)
    ox, oy, yaw = prm.origin
    if abs(yaw) > 1e-12:
        raise MapFormatError(
            f"{prm.yaml}: origin yaw {yaw:g} rad is not supported: gridfield grids are axis-aligned, so a "
            "rotated map origin cannot be represented; rotate the image and set the yaw to 0"
        )
    values = _ros_values_top_first(prm, semantics)[::-1]
    u = values.view(np.uint8)
    is_unknown = u == 255
    occupied = (u >= 100) & ~is_unknown
    if unknown == "occupied":
        occupied |= is_unknown
    if border is None:
        border = "wall" if unknown == "occupied" else "open"
    try:
        grid = Grid(values.shape, prm.resolution, (ox, oy), border)
    except ParameterError as e:
        raise MapFormatError(f"{prm.yaml}: {e}") from None
    meta = {"format": "ros", "semantics": semantics, "mode": prm.mode, "unknown_fraction": float(is_unknown.mean()),
            "occupancy_rule": _ros_rule(prm, semantics)}
    return GridMap(grid, np.ascontiguousarray(occupied), source=str(yaml_path), meta=meta)


def _ros_rule(prm: _RosParams, semantics: str) -> str:
    """The map's occupancy rule in words (its ``meta["occupancy_rule"]``)."""
    head = f"ROS map_server {prm.mode} ({semantics})"
    if prm.mode == "raw":
        tail = "100 occupied, above 100 unknown" if semantics == "nav2" else "100..254 occupied, 255 unknown"
        return f"{head}: the grey level is the OccupancyGrid value, {tail}"
    ge, le = (">=", "<=") if semantics == "nav2" else (">", "<")
    between = "unknown" if prm.mode == "trinary" else "scaled (read as free)"
    occupancy = "v / 255 (negate)" if prm.negate else "(255 - v) / 255"
    return (f"{head}: occupancy {occupancy} {ge} occupied_thresh {prm.occupied_thresh:g} occupied, "
            f"{le} free_thresh {prm.free_thresh:g} free, between {between}")


def write_ros_map(yaml_path: PathLike, gridmap: GridMap, *, image_name: str | None = None) -> FsPath:
    """Write an occupancy grid as a ROS map: an image (PGM by default) and its YAML.

    The YAML says ``mode: trinary``, ``negate: 0``, ``occupied_thresh: 0.65``,
    ``free_thresh: 0.196``, the grid's resolution and ``origin: [x, y, 0.0]``; the image is
    written by :func:`write_bitmap` next to the YAML. :func:`read_ros_map` reads back the same
    occupancy, resolution and origin (ROS maps have no border: it reads back per its
    ``border``/``unknown`` options).

    Parameters
    ----------
    yaml_path : str or path-like
    gridmap : GridMap
    image_name : str, optional
        File name of the image, relative to the YAML's folder (default: the YAML's stem + ``.pgm``).

    Returns
    -------
    pathlib.Path
        ``yaml_path`` (the image lies beside it).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> m = GridMap(Grid((2, 3), 0.05, origin=(-1.0, 2.5)), np.array([[1, 0, 0], [0, 0, 1]], dtype=bool))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     back = read_ros_map(write_ros_map(pathlib.Path(d) / "m.yaml", m))
    >>> back.occupied.astype(int).tolist(), back.grid.resolution, back.grid.origin
    ([[1, 0, 0], [0, 0, 1]], 0.05, (-1.0, 2.5))
    """
    if not isinstance(gridmap, GridMap):
        raise ParameterError(f"gridmap must be a GridMap, got {type(gridmap).__name__}")
    yp = FsPath(yaml_path)
    name = image_name if image_name is not None else yp.stem + ".pgm"
    if not isinstance(name, str) or not name or FsPath(name).is_absolute():
        raise ParameterError(f"image_name must be a file name relative to the YAML's folder, got {shorten(image_name)}")
    write_bitmap(yp.parent / name, gridmap)
    x0, y0 = gridmap.grid.origin
    doc = {
        "image": name,
        "mode": "trinary",
        "resolution": float(gridmap.grid.resolution),
        "origin": [float(x0), float(y0), 0.0],
        "negate": 0,
        "occupied_thresh": 0.65,
        "free_thresh": 0.196,
    }
    try:
        yp.write_text(yaml.safe_dump(doc, sort_keys=False, default_flow_style=None), encoding="utf-8")
    except OSError as e:
        raise GridfieldError(f"{yp}: cannot write: {e.strerror or e}") from None
    return yp
