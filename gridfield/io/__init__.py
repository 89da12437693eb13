"""Reading and writing maps, worlds and arrays (I/O only; no computation).

Supported inputs (:func:`read` picks by file name):

- world YAML (``bounds``/``obstacles``): :func:`read_world`
- ROS map_server YAML (``image``/``resolution``/``origin``): :func:`read_ros_map`
  (and :func:`ros_occupancy_values` for the raw OccupancyGrid values)
- bitmaps PNG, PGM (``P2`` ASCII and ``P5`` binary), BMP: :func:`read_bitmap`
- Moving AI ``.map``: :func:`read_movingai_map`; scenarios ``.scen``: :func:`read_scen`
- ``.npz`` arrays written by gridfield: :func:`read_npz`, :func:`read_npz_arrays`

Writers: :func:`write_bitmap`, :func:`write_ros_map`, :func:`write_npz`.

Orientation (see ``ARCHITECTURE.md``, "Conventions"): images are stored top row first; every image reader flips
them so that the image's top row becomes the highest y (row ``rows - 1``), exactly as ROS
map_server does. A Moving AI map's first map line is likewise the top of the world.

Every problem with an input file is raised as :class:`~gridfield.errors.MapFormatError`
naming the file (and the line, key or value at fault); errors of the underlying libraries
(Pillow, numpy, PyYAML) never escape.
"""

from __future__ import annotations

import inspect
import io as _io
import math
import os
import re
import struct
import warnings
import zipfile
import zlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path as FsPath
from typing import Any, Literal

import numpy as np
import yaml
from numpy.typing import NDArray

from ..errors import GridfieldError, MapFormatError, ParameterError, shorten
from ..grid import BORDERS, Grid, GridMap
from ..limits import check_cells
from ..world import World, world_from_dict

__all__ = [
    "NPZ_ARRAY_NAMES",
    "Scenarios",
    "bundled_map",
    "read",
    "read_bitmap",
    "read_movingai_map",
    "read_npz",
    "read_npz_arrays",
    "read_ros_map",
    "read_scen",
    "read_world",
    "read_yaml",
    "ros_occupancy_values",
    "write_bitmap",
    "write_npz",
    "write_ros_map",
]

PathLike = str | os.PathLike[str]

#: Array names gridfield gives to the fields an ``.npz`` file may hold (others are allowed too).
NPZ_ARRAY_NAMES = ("occupied", "steps", "distance", "label", "gvd", "potential", "grad_x", "grad_y")
_NPZ_RESERVED = ("resolution", "origin", "border")

UNKNOWN_CHOICES = ("occupied", "free")
SEMANTICS = ("nav2", "ros1")
ROS_MODES = ("trinary", "scale", "raw")


def bundled_map(name: str) -> FsPath:
    """Path of a map shipped with gridfield (``maps/`` in the source tree, ``gridfield/maps`` in a wheel).

    Examples
    --------
    >>> bundled_map("seed000.yaml").name
    'seed000.yaml'
    """
    from importlib import resources

    candidates = [resources.files("gridfield") / "maps", FsPath(__file__).resolve().parents[2] / "maps"]
    for base in candidates:
        p = FsPath(str(base)) / name
        if p.exists():
            return p
    raise MapFormatError(f"no bundled map named {shorten(name)}")


# ----------------------------------------------------------------------------------------
# small helpers
# ----------------------------------------------------------------------------------------
def _check_file(path: PathLike) -> FsPath:
    try:
        p = FsPath(path)
    except TypeError:
        raise MapFormatError(f"expected a file name, got {shorten(path)}") from None
    if not p.exists():
        raise MapFormatError(f"{p}: no such file")
    if p.is_dir():
        raise MapFormatError(f"{p}: is a directory, expected a map file")
    return p


def _read_bytes(p: FsPath) -> bytes:
    try:
        return p.read_bytes()
    except OSError as e:
        raise MapFormatError(f"{p}: cannot read: {e.strerror or e}") from None


def _choice(name: str, value: Any, choices: tuple[str, ...]) -> str:
    if value not in choices:
        raise ParameterError(f"{name} must be one of {', '.join(map(repr, choices))}, got {shorten(value)}")
    return value


def _decode_text(p: FsPath, data: bytes, what: str) -> str:
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data[: e.start].count(b"\n") + 1
        raise MapFormatError(f"{p}: line {line}: not a text {what} file (byte 0x{data[e.start]:02x} is not UTF-8)") from None


#: A YAML document may expand (aliases followed) to at most this many values, and at most
#: this many times its own number of values: more is an alias bomb, refused before it is built.
YAML_EXPANDED_LIMIT = 10**6


def _check_yaml_size(p: FsPath, root: Any) -> None:
    """Refuse a YAML node graph whose aliases expand beyond :data:`YAML_EXPANDED_LIMIT` values."""
    sizes: dict[int, int] = {}
    order: list[Any] = []
    stack = [root]
    while stack:  # distinct nodes, depth first; children before parents in `order` reversed
        node = stack.pop()
        if id(node) in sizes:
            continue
        sizes[id(node)] = 0
        order.append(node)
        if isinstance(node, yaml.SequenceNode):
            stack.extend(node.value)
        elif isinstance(node, yaml.MappingNode):
            stack.extend(n for pair in node.value for n in pair)
    for node in reversed(order):
        if isinstance(node, yaml.SequenceNode):
            total = 1 + sum(sizes[id(n)] for n in node.value)
        elif isinstance(node, yaml.MappingNode):
            total = 1 + sum(sizes[id(n)] for pair in node.value for n in pair)
        else:
            total = 1
        sizes[id(node)] = total
    expanded = sizes[id(root)]
    if expanded > max(YAML_EXPANDED_LIMIT, 10 * len(order)) and expanded > len(order):
        raise MapFormatError(
            f"{p}: YAML aliases expand its {len(order)} values to {expanded:.3g}; refused (more than "
            f"{YAML_EXPANDED_LIMIT:g} values after expansion, an alias bomb?)"
        )


def read_yaml(path: PathLike) -> Any:
    """Parse a YAML file, raising :class:`MapFormatError` with the file and line on bad syntax."""
    p = _check_file(path)
    try:
        text = p.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise MapFormatError(f"{p}: not a text (UTF-8) YAML file") from None
    except OSError as e:
        raise MapFormatError(f"{p}: cannot read: {e.strerror}") from None
    try:
        loader = yaml.SafeLoader(text)
        try:
            node = loader.get_single_node()
            if node is not None:
                _check_yaml_size(p, node)
            data = loader.construct_document(node) if node is not None else None
        finally:
            loader.dispose()
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f" line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(e, "problem", None) or str(e).splitlines()[0]
        raise MapFormatError(f"{p}:{where}: invalid YAML: {shorten(problem)}") from None
    except RecursionError:
        raise MapFormatError(f"{p}: invalid YAML: nested too deeply") from None
    if data is None:
        raise MapFormatError(f"{p}: the file is empty")
    return data


def read_world(path: PathLike) -> World:
    """Read a world YAML file (see :func:`gridfield.world.world_from_dict` for the keys).

    Examples
    --------
    >>> w = read_world(bundled_map("seed000.yaml"))
    >>> [ob.id for ob in w.obstacles], w.start, w.goal
    ([1, 2, 3], (1.0, 10.0), (22.0, 12.0))
    """
    data = read_yaml(path)
    return world_from_dict(data, source=str(path))


# ----------------------------------------------------------------------------------------
# images: pixels as float64 arrays (rows, cols, channels) in [0, 255], top row first
# ----------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class _Pixels:
    """Decoded image: ``data`` has shape (rows, cols, C) with C = 1 (grey), 3 (RGB) or 4 (RGBA)."""

    data: NDArray[np.float64]
    format: str  # "PGM", "PNG", "BMP", ...

    @property
    def has_alpha(self) -> bool:
        return self.data.shape[2] == 4

    @property
    def alpha(self) -> NDArray[np.float64] | None:
        return self.data[..., 3] if self.has_alpha else None

    def luma(self) -> NDArray[np.float64]:
        """Grey level 0..255: the image itself if grey, else Rec. 601 luma (rounded, as 8-bit converters do)."""
        if self.data.shape[2] == 1:
            return self.data[..., 0]
        return np.rint(self.data[..., :3] @ np.array([0.299, 0.587, 0.114]))


_WS = b" \t\r\n\v\f"


def _pnm_header(p: FsPath, data: bytes) -> tuple[bytes, list[int], int]:
    """Magic, [width, height, maxval] and the offset of the first byte after the header.

    Tokens are separated by whitespace; ``#`` starts a comment that runs to the end of the line.
    """
    magic = data[:2]
    pos = 2
    tokens: list[int] = []
    names = ("width", "height", "maxval")
    while len(tokens) < 3:
        # skip whitespace and comments
        while pos < len(data) and (data[pos] in _WS or data[pos] == ord("#")):
            if data[pos] == ord("#"):
                end = data.find(b"\n", pos)
                pos = len(data) if end < 0 else end + 1
            else:
                pos += 1
        start = pos
        while pos < len(data) and data[pos] not in _WS and data[pos] != ord("#"):
            pos += 1
        tok = data[start:pos]
        if not tok:
            raise MapFormatError(f"{p}: truncated PGM header: the file ends before the {names[len(tokens)]}")
        if not tok.isdigit():
            shown = tok[:20].decode("latin-1")
            raise MapFormatError(f"{p}: bad PGM header: expected the {names[len(tokens)]} (a number), found {shorten(shown)}")
        tokens.append(int(tok))
    # exactly one whitespace character separates the header from binary data
    if pos < len(data) and data[pos] in _WS:
        pos += 1
    width, height, maxval = tokens
    if width <= 0 or height <= 0:
        raise MapFormatError(f"{p}: PGM image has zero size ({width} x {height})")
    if not 0 < maxval < 65536:
        raise MapFormatError(f"{p}: PGM maxval must be in 1..65535, got {maxval}")
    return magic, tokens, pos


def _read_pgm(p: FsPath, data: bytes) -> _Pixels:
    """Decode a ``P2`` (ASCII) or ``P5`` (binary) PGM, 8 or 16 bits, to grey levels 0..255."""
    magic, (width, height, maxval), pos = _pnm_header(p, data)
    check_cells((height, width), f"{p} (PGM header)")
    n = width * height
    if magic == b"P5":
        itemsize = 1 if maxval < 256 else 2
        need = n * itemsize
        if len(data) - pos < need:
            raise MapFormatError(
                f"{p}: truncated PGM: {width} x {height} pixels need {need} bytes of pixel data, "
                f"found {len(data) - pos}"
            )
        values = np.frombuffer(data, dtype=np.uint8 if itemsize == 1 else ">u2", count=n, offset=pos)
    else:  # P2: whitespace-separated decimal numbers, comments allowed
        body = re.sub(rb"#[^\n]*", b" ", data[pos:]).split()
        if len(body) < n:
            raise MapFormatError(f"{p}: truncated PGM: {width} x {height} pixels need {n} values, found {len(body)}")
        try:
            values = np.array(body[:n], dtype=np.int64)
            ok = bool((values >= 0).all())
        except (ValueError, OverflowError):
            ok = False
        if not ok:
            bad = next(t for t in body[:n] if not t.isdigit() or len(t) > 6)
            raise MapFormatError(f"{p}: bad PGM pixel value {shorten(bad[:20].decode('latin-1'))}; expected a number") from None
    if int(values.max()) > maxval:
        raise MapFormatError(f"{p}: PGM pixel value {int(values.max())} exceeds maxval {maxval}")
    grey = values.reshape(height, width).astype(np.float64)
    if maxval != 255:
        grey *= 255.0 / maxval
    return _Pixels(grey[..., None], "PGM")


def _read_pillow(p: FsPath, data: bytes) -> _Pixels:
    from PIL import Image, UnidentifiedImageError

    with warnings.catch_warnings():
        # Maps can be large: Pillow's decompression-bomb limit gives way to gridfield's own size
        # guard, applied to the header's size before decoding. Pillow's other notes are not for our users.
        warnings.simplefilter("ignore")
        bomb_limit = Image.MAX_IMAGE_PIXELS
        try:
            Image.MAX_IMAGE_PIXELS = None
            with Image.open(_io.BytesIO(data)) as im:
                width, height = im.size
                check_cells((height, width), f"{p} (image header)")
                im.load()
                fmt = im.format or "image"
                mode = im.mode
                img: Image.Image = im
                if mode == "P":
                    img = img.convert("RGBA" if "transparency" in im.info else "RGB")
                elif mode == "PA":
                    img = img.convert("RGBA")
                elif mode == "1":
                    img = img.convert("L")
                elif mode == "LA":
                    img = img.convert("RGBA")
                elif mode in ("RGBX", "CMYK", "YCbCr", "LAB", "HSV"):
                    img = img.convert("RGB")
                arr = np.asarray(img)
        except UnidentifiedImageError:
            raise MapFormatError(f"{p}: not a readable image (expected a PNG, PGM or BMP file)") from None
        except GridfieldError:
            raise
        except (OSError, ValueError, SyntaxError, EOFError, TypeError, IndexError, KeyError, struct.error,
                zlib.error) as e:
            raise MapFormatError(f"{p}: cannot decode image: {shorten(str(e))}") from None
        except MemoryError:
            raise MapFormatError(f"{p}: cannot decode image: out of memory") from None
        finally:
            Image.MAX_IMAGE_PIXELS = bomb_limit
    if mode.startswith("I"):
        pixels = arr.astype(np.float64) * (255.0 / 65535.0)
    elif arr.dtype == np.uint8:
        pixels = arr.astype(np.float64)
    else:
        raise MapFormatError(f"{p}: unsupported image mode {shorten(mode)}; save the map as 8-bit grey or RGB")
    if pixels.ndim == 2:
        pixels = pixels[..., None]
    if pixels.ndim != 3 or pixels.shape[2] not in (1, 3, 4) or pixels.shape[0] == 0 or pixels.shape[1] == 0:
        raise MapFormatError(f"{p}: unsupported image layout {arr.shape} (mode {shorten(mode)})")
    return _Pixels(np.clip(pixels, 0.0, 255.0), fmt)


def _load_pixels(path: PathLike) -> _Pixels:
    p = _check_file(path)
    data = _read_bytes(p)
    if not data:
        raise MapFormatError(f"{p}: the file is empty")
    if data[:2] in (b"P2", b"P5"):
        return _read_pgm(p, data)
    return _read_pillow(p, data)


def _check_unit(name: str, value: Any, where: str = "") -> float:
    """A number in [0, 1] (bools and NaN rejected)."""
    prefix = f"{where}: " if where else ""
    try:
        if isinstance(value, bool):
            raise TypeError
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{prefix}{name} must be a number in [0, 1], got {shorten(value)}") from None
    if not 0.0 <= v <= 1.0:
        raise ParameterError(f"{prefix}{name} must be a number in [0, 1], got {shorten(value)}")
    return v


def _as_bool01(name: str, value: Any, where: str = "") -> bool:
    if isinstance(value, bool | np.bool_):
        return bool(value)
    if isinstance(value, int | np.integer) and value in (0, 1):
        return bool(value)
    prefix = f"{where}: " if where else ""
    raise ParameterError(f"{prefix}{name} must be 0 or 1 (or false/true), got {shorten(value)}")


def read_bitmap(
    path: PathLike,
    *,
    resolution: float = 1.0,
    origin: tuple[float, float] = (0.0, 0.0),
    negate: bool = False,
    threshold: float = 0.5,
    border: Literal["open", "wall"] = "open",
    unknown: Literal["occupied", "free"] = "occupied",
) -> GridMap:
    """Read a PNG, PGM (``P2``/``P5``) or BMP image as an occupancy grid.

    Colour pixels become grey by Rec. 601 luma (``0.299 R + 0.587 G + 0.114 B``). A pixel of grey
    level ``v`` has occupancy ``(255 - v) / 255`` (dark = obstacle), or ``v / 255`` with
    ``negate``; it is occupied when that exceeds ``threshold``. Transparent pixels (alpha < 255)
    are *unknown*, as in ROS map_server, and are treated per ``unknown``. The image is flipped
    vertically: its top row becomes the highest y.

    Parameters
    ----------
    path : str or path-like
    resolution : float
        Edge length of one pixel in world units.
    origin : (float, float)
        World coordinates of the lower-left corner of the lower-left pixel.
    negate : bool
        If true, white is occupied and black free.
    threshold : float in [0, 1]
        Occupancy above which a pixel is an obstacle.
    border : {"open", "wall"}
        What lies outside the image.
    unknown : {"occupied", "free"}
        How transparent pixels are treated.

    Returns
    -------
    GridMap
        ``meta`` holds ``format="bitmap"``, the image format and the fraction of transparent pixels.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from PIL import Image
    >>> img = np.array([[0, 255, 255], [255, 255, 255]], dtype=np.uint8)  # top-left pixel black
    >>> with tempfile.TemporaryDirectory() as d:
    ...     Image.fromarray(img).save(pathlib.Path(d) / "m.png")
    ...     m = read_bitmap(pathlib.Path(d) / "m.png", resolution=0.5)
    >>> m.occupied.astype(int)  # row 0 is the image's bottom row
    array([[0, 0, 0],
           [1, 0, 0]])
    >>> m.is_free([[0.25, 0.75], [0.25, 0.25]]).tolist()
    [False, True]
    """
    _choice("border", border, BORDERS)
    _choice("unknown", unknown, UNKNOWN_CHOICES)
    neg = _as_bool01("negate", negate)
    thr = _check_unit("threshold", threshold)
    px = _load_pixels(path)
    rows, cols = px.data.shape[:2]
    grid = Grid((rows, cols), resolution, origin, border)
    grey = px.luma()
    occ = grey / 255.0 if neg else (255.0 - grey) / 255.0
    occupied = occ > thr
    meta: dict[str, Any] = {"format": "bitmap", "image_format": px.format}
    alpha = px.alpha
    if alpha is not None:
        transparent = alpha < 255.0
        occupied = np.where(transparent, unknown == "occupied", occupied)
        meta["unknown_fraction"] = float(transparent.mean())
    return GridMap(grid, np.ascontiguousarray(occupied[::-1]), source=str(path), meta=meta)


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
        return np.trunc(avg).astype(np.int64).astype(np.uint8).view(np.int8)
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
        ``meta`` holds ``format="ros"``, ``semantics``, ``mode`` and ``unknown_fraction``.

    Examples
    --------
    >>> m = read_ros_map(bundled_map("turtlebot3_world/map.yaml"))
    >>> m.shape, m.grid.resolution, m.grid.origin, m.grid.border
    ((384, 384), 0.05, (-10.0, -10.0), 'wall')
    >>> round(m.meta["unknown_fraction"], 3)
    0.941
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
    meta = {"format": "ros", "semantics": semantics, "mode": prm.mode, "unknown_fraction": float(is_unknown.mean())}
    return GridMap(grid, np.ascontiguousarray(occupied), source=str(yaml_path), meta=meta)


# ----------------------------------------------------------------------------------------
# Moving AI benchmarks
# ----------------------------------------------------------------------------------------
_MAI_PASSABLE = b".GS"
_MAI_BLOCKED = b"@OTW"
_MAI_LUT = np.full(256, 2, dtype=np.uint8)  # 0 passable, 1 blocked, 2 invalid
_MAI_LUT[np.frombuffer(_MAI_PASSABLE, np.uint8)] = 0
_MAI_LUT[np.frombuffer(_MAI_BLOCKED, np.uint8)] = 1


def _text_lines(p: FsPath, what: str) -> list[str]:
    text = _decode_text(p, _read_bytes(p), what)
    return [ln[:-1] if ln.endswith("\r") else ln for ln in text.split("\n")]


def read_movingai_map(path: PathLike, *, border: Literal["open", "wall"] = "wall") -> GridMap:
    """Read a Moving AI benchmark ``.map`` file.

    The header is ``type octile``, ``height H``, ``width W``, ``map``; then H lines of W
    characters: passable ``.`` ``G`` ``S``, blocked ``@`` ``O`` ``T`` ``W``. CRLF line endings
    are accepted. The grid has resolution 1 and origin (0, 0); the file's first map line is
    the top (highest y), so the character in line ``y`` (0-based), column ``x`` is the cell
    ``(row, col) = (H - 1 - y, x)`` with centre ``(x + 0.5, H - 1 - y + 0.5)``.

    Parameters
    ----------
    path : str or path-like
    border : {"open", "wall"}
        Default "wall": Moving AI maps are closed worlds (a path never leaves the map).

    Examples
    --------
    >>> m = read_movingai_map(bundled_map("arena/arena.map"))
    >>> m.shape, m.grid.resolution, m.grid.border
    ((49, 49), 1.0, 'wall')
    >>> m.is_free([[1.5, 47.5], [0.5, 47.5]]).tolist()  # line 2 of the map is "TTT....", so y = 47
    [False, False]
    >>> m.is_free([[3.5, 47.5]]).tolist()
    [True]
    """
    _choice("border", border, BORDERS)
    p = _check_file(path)
    lines = _text_lines(p, "Moving AI map")
    header: dict[str, str] = {}
    map_line = None
    for i, raw in enumerate(lines):
        ln = raw.strip()
        if not ln:
            continue
        if ln.lower() == "map":
            map_line = i
            break
        parts = ln.split()
        if len(parts) != 2 or parts[0].lower() not in ("type", "height", "width"):
            raise MapFormatError(
                f"{p}: line {i + 1}: expected a header line 'type octile', 'height H', 'width W' or 'map', "
                f"got {shorten(raw[:40])}"
            )
        header[parts[0].lower()] = parts[1]
    if map_line is None:
        raise MapFormatError(f"{p}: no 'map' line; a Moving AI map starts with type, height, width and 'map' lines")
    for key in ("type", "height", "width"):
        if key not in header:
            raise MapFormatError(f"{p}: header has no '{key}' line before 'map' (line {map_line + 1})")
    size: dict[str, int] = {}
    for key in ("height", "width"):
        v = header[key]
        if not v.isdigit() or int(v) <= 0:
            raise MapFormatError(f"{p}: '{key}' must be a positive integer, got {shorten(v)}")
        size[key] = int(v)
    h, w = size["height"], size["width"]
    check_cells((h, w), f"{p} (Moving AI header)")

    first = map_line + 1
    while len(lines) > first and not lines[-1].strip():  # trailing blank lines / final newline
        lines.pop()
    rows = lines[first : first + h]
    if len(rows) < h:
        raise MapFormatError(
            f"{p}: truncated map: the header says height {h}, but the file ends at line {len(lines)} "
            f"after {len(rows)} map rows"
        )
    extra = [i for i in range(first + h, len(lines)) if lines[i].strip()]
    if extra:
        raise MapFormatError(f"{p}: line {extra[0] + 1}: more map rows than the header's height {h}")
    lengths = np.fromiter((len(r) for r in rows), dtype=np.int64, count=h)
    bad = np.flatnonzero(lengths != w)
    if bad.size:
        i = int(bad[0])
        raise MapFormatError(
            f"{p}: line {first + i + 1}: map row has {lengths[i]} characters, but the header says width {w}"
        )
    try:
        chars = np.frombuffer("".join(rows).encode("ascii"), dtype=np.uint8).reshape(h, w)
    except UnicodeEncodeError as e:
        i, j = divmod(e.start, w)
        raise MapFormatError(
            f"{p}: line {first + i + 1}, column {j + 1}: invalid map character {shorten(rows[i][j])}; "
            "expected . G S (passable) or @ O T W (blocked)"
        ) from None
    codes = _MAI_LUT[chars]
    invalid = np.flatnonzero(codes.ravel() == 2)
    if invalid.size:
        i, j = divmod(int(invalid[0]), w)
        raise MapFormatError(
            f"{p}: line {first + i + 1}, column {j + 1}: invalid map character {shorten(chr(chars[i, j]))}; "
            "expected . G S (passable) or @ O T W (blocked)"
        )
    occupied = np.ascontiguousarray((codes == 1)[::-1])
    meta = {"format": "movingai", "type": header["type"]}
    return GridMap(Grid((h, w), 1.0, (0.0, 0.0), border), occupied, source=str(path), meta=meta)


@dataclass(frozen=True, eq=False)
class Scenarios:
    """The scenarios of a Moving AI ``.scen`` file, one array entry per scenario.

    Coordinates are converted to gridfield's conventions (see ``ARCHITECTURE.md``, "Conventions"): a scenario
    cell ``(x, y)`` (their y grows downward) of a map of height H is the world point
    ``(x + 0.5, H - 1 - y + 0.5)`` and the cell ``(row, col) = (H - 1 - y, x)``.

    Attributes
    ----------
    bucket : ndarray of int64
    map_name : ndarray of str
        Base name of the map file (the file may give a relative path).
    width, height : ndarray of int64
        Map size as given in each line.
    start_xy, goal_xy : ndarray of float64, shape (N, 2)
        World coordinates of the start and goal cell centres.
    start_cell, goal_cell : ndarray of int64, shape (N, 2)
        ``(row, col)`` in gridfield's row order (row 0 = lowest y).
    optimal : ndarray of float64
        Reference octile path length (8-connected, no corner cutting).
    no_path : ndarray of bool
        Length 0 with start != goal: the GPPC marker for "unreachable".
    version : str
        The file's ``version`` line (``"1"``, ``"1.0"``; ``""`` if absent).
    precision : {"significant", "decimals"}
        How ``optimal`` was printed: ``digits`` significant digits (old ``version 1`` files: 6)
        or ``digits`` decimals (newer files: 8; ``version 1.0``: 2).
    digits : int
    source : str
    """

    bucket: NDArray[np.int64]
    map_name: NDArray[np.str_]
    width: NDArray[np.int64]
    height: NDArray[np.int64]
    start_xy: NDArray[np.float64]
    goal_xy: NDArray[np.float64]
    start_cell: NDArray[np.int64]
    goal_cell: NDArray[np.int64]
    optimal: NDArray[np.float64]
    no_path: NDArray[np.bool_]
    version: str
    precision: Literal["significant", "decimals"]
    digits: int
    source: str = ""

    def __repr__(self) -> str:
        name = str(self.map_name[0]) if len(self) else ""
        return f"Scenarios({len(self)} scenarios for {name!r}, version {self.version!r})"

    def __len__(self) -> int:
        return len(self.optimal)

    def tolerance(self) -> NDArray[np.float64]:
        """Per-scenario absolute tolerance for comparing a computed length with ``optimal``:
        half a unit in the last printed place plus ``1e-5 * optimal`` (the reference
        generators sometimes print the last digit one low).

        Examples
        --------
        >>> s = read_scen(bundled_map("arena/arena.map.scen"))
        >>> s.precision, s.digits, float(s.optimal[0]), float(s.tolerance()[0])
        ('significant', 6, 1.0, 1.5e-05)
        """
        length = self.optimal
        if self.precision == "decimals":
            half_ulp = np.full(length.shape, 0.5 * 10.0 ** -self.digits)
        else:
            safe = np.where(length > 0, length, 1.0)
            half_ulp = 0.5 * 10.0 ** (np.floor(np.log10(safe)) - (self.digits - 1))
        return half_ulp + 1e-5 * length


def read_scen(path: PathLike, *, map_height: int | None = None) -> Scenarios:
    """Read a Moving AI scenario file (``.scen``).

    All three variants are accepted: ``version 1`` tab-separated with 6 significant digits or
    with 8 decimals, and ``version 1.0`` space-separated with 2 decimals. Each data line holds
    ``bucket map width height start_x start_y goal_x goal_y optimal``.

    Parameters
    ----------
    path : str or path-like
    map_height : int, optional
        Height of the map the scenarios belong to; every line's height column must match it.
        By default each line's own height column is used for the coordinate conversion.

    Returns
    -------
    Scenarios

    Examples
    --------
    >>> s = read_scen(bundled_map("arena/arena.map.scen"))
    >>> len(s), str(s.map_name[0]), s.version
    (160, 'arena.map', '1')
    >>> s.start_xy[0].tolist(), s.start_cell[0].tolist()  # first line: start (1, 11) on a 49-high map
    ([1.5, 37.5], [37, 1])
    """
    p = _check_file(path)
    lines = _text_lines(p, "Moving AI scenario")
    version = ""
    numbers: list[int] = []
    fields: list[list[str]] = []
    for i, raw in enumerate(lines):
        ln = raw.strip()
        if not ln:
            continue
        if not fields and not version and ln.lower().startswith("version"):
            version = ln.split(None, 1)[1].strip() if len(ln.split()) > 1 else ""
            continue
        parts = raw.strip("\n").split("\t") if "\t" in raw else ln.split()
        parts = [s.strip() for s in parts]
        if len(parts) != 9:
            raise MapFormatError(
                f"{p}: line {i + 1}: expected 9 fields (bucket map width height start_x start_y goal_x goal_y "
                f"optimal), got {len(parts)}"
            )
        numbers.append(i + 1)
        fields.append(parts)
    if not fields:
        raise MapFormatError(f"{p}: no scenarios in the file")
    table = np.array(fields, dtype=str)
    line_no = np.array(numbers)

    def column(k: int, dtype: type, what: str) -> NDArray[Any]:
        col = table[:, k]
        try:
            return col.astype(dtype)
        except (ValueError, OverflowError):
            for n, s in zip(line_no.tolist(), col.tolist(), strict=True):
                try:
                    dtype(s)
                except (ValueError, OverflowError):
                    raise MapFormatError(f"{p}: line {n}: {what} must be a number (in range), "
                                         f"got {shorten(s)}") from None
            raise MapFormatError(f"{p}: a {what} is not a number within range") from None

    ints = {k: column(k, np.int64, name) for k, name in ((0, "bucket"), (2, "width"), (3, "height"), (4, "start_x"),
                                                         (5, "start_y"), (6, "goal_x"), (7, "goal_y"))}
    optimal = column(8, np.float64, "optimal length")
    bucket, width, height = ints[0], ints[2], ints[3]
    sx, sy, gx, gy = ints[4], ints[5], ints[6], ints[7]

    def first_bad(mask: NDArray[np.bool_]) -> int | None:
        idx = np.flatnonzero(mask)
        return int(idx[0]) if idx.size else None

    if (k := first_bad((width <= 0) | (height <= 0))) is not None:
        raise MapFormatError(f"{p}: line {line_no[k]}: map width and height must be positive")
    if map_height is not None:
        mh = int(map_height)
        if mh <= 0:
            raise ParameterError(f"map_height must be a positive integer, got {shorten(map_height)}")
        if (k := first_bad(height != mh)) is not None:
            raise MapFormatError(f"{p}: line {line_no[k]}: scenario map height {height[k]} differs from map_height={mh}")
    h = height if map_height is None else np.full(height.shape, int(map_height))
    outside = (sx < 0) | (sx >= width) | (gx < 0) | (gx >= width) | (sy < 0) | (sy >= h) | (gy < 0) | (gy >= h)
    if (k := first_bad(outside)) is not None:
        raise MapFormatError(
            f"{p}: line {line_no[k]}: start ({sx[k]}, {sy[k]}) or goal ({gx[k]}, {gy[k]}) lies outside the "
            f"{width[k]} x {h[k]} map"
        )
    if (k := first_bad(~np.isfinite(optimal) | (optimal < 0))) is not None:
        raise MapFormatError(f"{p}: line {line_no[k]}: optimal length must be a finite number >= 0")

    opt_text = table[:, 8]
    dot = np.char.find(opt_text, ".")
    decimals = np.where(dot >= 0, np.char.str_len(opt_text) - dot - 1, 0)
    max_dp = int(decimals.max())
    if version == "1.0" or max_dp >= 7:
        precision, digits = "decimals", max_dp
    else:
        precision, digits = "significant", 6

    start_row, goal_row = h - 1 - sy, h - 1 - gy
    start_cell = np.stack([start_row, sx], axis=1)
    goal_cell = np.stack([goal_row, gx], axis=1)
    start_xy = np.stack([sx + 0.5, start_row + 0.5], axis=1).astype(np.float64)
    goal_xy = np.stack([gx + 0.5, goal_row + 0.5], axis=1).astype(np.float64)
    no_path = (optimal == 0) & ((sx != gx) | (sy != gy))
    names = np.array([os.path.basename(s.replace("\\", "/")) for s in table[:, 1]], dtype=str)
    return Scenarios(bucket, names, width, height, start_xy, goal_xy, start_cell, goal_cell, optimal, no_path,
                     version, precision, digits, str(path))  # type: ignore[arg-type]


# ----------------------------------------------------------------------------------------
# .npz arrays
# ----------------------------------------------------------------------------------------
def write_npz(path: PathLike, arrays: Mapping[str, NDArray[Any]], grid: Grid) -> FsPath:
    """Write named arrays and their grid geometry to an ``.npz`` file (compressed).

    The file holds each array under its name (gridfield's names: ``occupied``, ``steps``,
    ``distance``, ``label``, ``gvd``, ``potential``, ``grad_x``, ``grad_y``; others are
    allowed), plus ``resolution`` (scalar), ``origin`` ``[x, y]`` and ``border`` (a string).
    Every array must have the grid's shape (extra trailing axes are allowed). The file is
    written to ``path`` exactly (numpy's habit of appending ``.npz`` is not followed).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> g = Grid((2, 3), 0.5, origin=(1.0, 2.0), border="wall")
    >>> with tempfile.TemporaryDirectory() as d:
    ...     f = write_npz(pathlib.Path(d) / "out.npz", {"occupied": np.eye(2, 3, dtype=bool)}, g)
    ...     arrays, grid = read_npz_arrays(f)
    >>> sorted(arrays), grid == g
    (['occupied'], True)
    """
    if not isinstance(grid, Grid):
        raise ParameterError(f"grid must be a gridfield Grid, got {type(grid).__name__}")
    out: dict[str, Any] = {}  # arrays; Any so that **out is not matched against savez's allow_pickle
    for name, value in arrays.items():
        if not isinstance(name, str) or not name.isidentifier() or name in _NPZ_RESERVED:
            raise ParameterError(
                f"array name {shorten(name)} is not allowed; use an identifier other than {', '.join(_NPZ_RESERVED)}"
            )
        a = np.asarray(value)
        if a.dtype == object:
            raise ParameterError(f"array {shorten(name)} has dtype object; only numeric and boolean arrays can be stored")
        if a.shape[:2] != grid.shape:
            raise ParameterError(f"array {shorten(name)} has shape {a.shape}, but the grid has shape {grid.shape}")
        out[name] = a
    if not out:
        raise ParameterError("write_npz needs at least one array")
    p = FsPath(path)
    try:
        with open(p, "wb") as f:
            np.savez_compressed(
                f, **out, resolution=np.float64(grid.resolution), origin=np.asarray(grid.origin, dtype=np.float64),
                border=np.asarray(grid.border),
            )
    except OSError as e:
        raise GridfieldError(f"{p}: cannot write: {e.strerror or e}") from None
    return p


def _check_npz_headers(p: FsPath, z: Any) -> None:
    """Size every array of an open ``.npz`` from its ``.npy`` header, before any is loaded."""
    fmt = np.lib.format
    for name in z.files:
        member = name if name in z.zip.namelist() else f"{name}.npy"
        with z.zip.open(member) as f:
            version = fmt.read_magic(f)
            if version == (1, 0):
                shape, _, dtype = fmt.read_array_header_1_0(f)
            elif version in ((2, 0), (3, 0)):
                shape, _, dtype = fmt.read_array_header_2_0(f)
            else:
                raise MapFormatError(f"{p}: array {shorten(name)} has an unknown .npy format version {version}")
        check_cells(shape if len(shape) <= 2 else (shape[0], shape[1], math.prod(shape[2:])),
                    f"{p}: array {shorten(name)} (from its .npz header)", bytes_per_cell=max(int(dtype.itemsize), 1))


def _npz_content(path: PathLike) -> dict[str, NDArray[Any]]:
    """Every array of a gridfield ``.npz`` by name, each sized from its header before it is loaded.

    Raises :class:`MapFormatError` (or :class:`~gridfield.errors.SizeLimitError`) for anything
    but a readable zip archive of ``.npy`` arrays within the size limit.
    """
    p = _check_file(path)
    try:
        with open(p, "rb") as fh:
            magic = fh.read(6)
            if magic == b"\x93NUMPY":  # np.load would read the whole array before we could size it
                raise MapFormatError(f"{p}: holds a single .npy array, not a gridfield .npz archive of named arrays")
            if not magic.startswith(b"PK"):
                raise MapFormatError(f"{p}: not a gridfield .npz file (not a zip archive)")
            fh.seek(0)
            z = np.load(fh, allow_pickle=False)
            if not isinstance(z, np.lib.npyio.NpzFile):  # pragma: no cover - a zip is always an NpzFile
                raise MapFormatError(f"{p}: not a gridfield .npz archive of named arrays")
            with z:
                _check_npz_headers(p, z)
                content = {k: z[k] for k in z.files}
    except GridfieldError:
        raise
    except (zipfile.BadZipFile, ValueError, OSError, EOFError, KeyError) as e:
        raise MapFormatError(f"{p}: not a gridfield .npz file ({shorten(str(e))})") from None
    except MemoryError:
        raise MapFormatError(f"{p}: damaged .npz file (an array too large for memory)") from None
    except Exception as e:  # zlib.error and friends: a damaged archive
        raise MapFormatError(f"{p}: damaged .npz file ({type(e).__name__}: {shorten(str(e))})") from None
    return content


def read_npz_arrays(path: PathLike) -> tuple[dict[str, NDArray[Any]], Grid]:
    """Read an ``.npz`` written by :func:`write_npz`: the arrays by name and their :class:`Grid`.

    Entries of fewer than two dimensions (e.g. the goal and parameters that
    :func:`gridfield.potential.save_field` adds) are returned too but do not set the grid's shape.
    """
    content = _npz_content(path)
    p = FsPath(path)
    for key in ("resolution", "origin"):
        if key not in content:
            raise MapFormatError(f"{p}: no '{key}' array; a gridfield .npz holds resolution and origin beside the arrays")
    try:
        res = float(np.asarray(content.pop("resolution")).reshape(()))
        origin = np.asarray(content.pop("origin"), dtype=np.float64).reshape(2)
        border = str(np.asarray(content.pop("border", "open")).reshape(()))
    except (TypeError, ValueError) as e:
        raise MapFormatError(f"{p}: bad resolution, origin or border entry ({e})") from None
    # Grid-shaped arrays share one shape; 0-d/1-d entries (a goal, parameters as JSON) are metadata.
    shapes = {k: a.shape[:2] for k, a in content.items() if a.ndim >= 2}
    if not shapes:
        raise MapFormatError(f"{p}: holds no arrays besides the grid geometry")
    shape = shapes.get("occupied", next(iter(shapes.values())))
    bad = [k for k, s in shapes.items() if s != shape]
    if bad:
        raise MapFormatError(f"{p}: arrays have different shapes: {shapes}")
    try:
        grid = Grid(shape, res, (float(origin[0]), float(origin[1])), border)  # type: ignore[arg-type]
    except ParameterError as e:
        raise MapFormatError(f"{p}: {e}") from None
    return content, grid


def read_npz(path: PathLike) -> GridMap:
    """Read the occupancy grid (array ``occupied``) of a gridfield ``.npz`` file.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> occ = np.array([[True, False, False]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     f = write_npz(pathlib.Path(d) / "m.npz", {"occupied": occ}, Grid((1, 3), 2.0))
    ...     m = read_npz(f)
    >>> m.occupied.tolist(), m.grid.resolution
    ([[True, False, False]], 2.0)
    """
    arrays, grid = read_npz_arrays(path)
    if "occupied" not in arrays:
        raise MapFormatError(f"{path}: no 'occupied' array (it holds {', '.join(sorted(arrays))})")
    occ = arrays["occupied"]
    if occ.shape != grid.shape:
        raise MapFormatError(f"{path}: 'occupied' must be a 2-D array, got shape {occ.shape}")
    if occ.dtype != bool:
        if not (np.issubdtype(occ.dtype, np.number) and np.isin(occ, (0, 1)).all()):
            raise MapFormatError(f"{path}: 'occupied' must hold booleans (or 0/1), got dtype {occ.dtype}")
        occ = occ.astype(bool)
    meta = {"format": "npz", "arrays": sorted(arrays)}
    return GridMap(grid, occ, source=str(path), meta=meta)


# ----------------------------------------------------------------------------------------
# writers
# ----------------------------------------------------------------------------------------
def _image_of(gridmap: GridMap) -> NDArray[np.uint8]:
    """Occupied black (0), free white (254, map_saver's free level), top row first."""
    return np.ascontiguousarray(np.where(gridmap.occupied, 0, 254).astype(np.uint8)[::-1])


def write_bitmap(path: PathLike, gridmap: GridMap) -> FsPath:
    """Write an occupancy grid as an 8-bit grey image: PNG, PGM (binary ``P5``) or BMP by suffix.

    Occupied cells are black (0) and free cells white (254); the top image row is the highest
    y, so :func:`read_bitmap` (with the grid's resolution and origin) reads back the same grid.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> m = GridMap(Grid((2, 2), 1.0), np.array([[True, False], [False, False]]))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     f = write_bitmap(pathlib.Path(d) / "m.pgm", m)
    ...     f.read_bytes()[:2], read_bitmap(f).occupied.tolist()
    (b'P5', [[True, False], [False, False]])
    """
    if not isinstance(gridmap, GridMap):
        raise ParameterError(f"gridmap must be a GridMap, got {type(gridmap).__name__}")
    p = FsPath(path)
    suffix = p.suffix.lower()
    img = _image_of(gridmap)
    try:
        if suffix == ".pgm":
            rows, cols = img.shape
            with open(p, "wb") as f:
                f.write(b"P5\n# CREATOR: gridfield\n%d %d\n255\n" % (cols, rows))
                f.write(img.tobytes())
        elif suffix in (".png", ".bmp"):
            from PIL import Image

            Image.fromarray(img).save(p, format=suffix[1:].upper())
        else:
            raise ParameterError(f"{p}: cannot write a bitmap with suffix {shorten(suffix)}; use .png, .pgm or .bmp")
    except OSError as e:
        raise GridfieldError(f"{p}: cannot write: {e.strerror or e}") from None
    return p


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


# ----------------------------------------------------------------------------------------
# dispatch
# ----------------------------------------------------------------------------------------
def _check_options(reader: Callable[..., Any], options: Mapping[str, Any], p: FsPath, what: str) -> None:
    accepted = [n for n, prm in inspect.signature(reader).parameters.items() if prm.kind is prm.KEYWORD_ONLY]
    bad = sorted(set(options) - set(accepted))
    if bad:
        takes = f"it takes {', '.join(accepted)}" if accepted else "it takes no options"
        verb = "do not apply" if len(bad) > 1 else "does not apply"
        raise ParameterError(f"{p}: option{'s' if len(bad) > 1 else ''} {', '.join(bad)} {verb} to a {what}; {takes}")


def read(path: PathLike, **options: Any) -> World | GridMap:
    """Read any supported map or world file; a world YAML gives a :class:`World`, the rest a :class:`GridMap`.

    ``options`` go to the format's reader (e.g. ``unknown="free"`` for ROS maps, ``resolution``
    for bitmaps). Options whose value is ``None`` mean "the default" and are dropped; an
    option the format's reader does not take raises :class:`ParameterError`.

    Examples
    --------
    >>> type(read(bundled_map("seed000.yaml"))).__name__, read(bundled_map("arena/arena.map")).shape
    ('World', (49, 49))
    """
    p = _check_file(path)
    options = {k: v for k, v in options.items() if v is not None}
    suffix = p.suffix.lower()
    reader: Callable[..., GridMap]
    if suffix in (".yaml", ".yml"):
        data = read_yaml(p)
        # a ROS map YAML names its image; one that lacks it still has an origin (a world has bounds instead)
        if isinstance(data, dict) and ("image" in data or ("origin" in data and "bounds" not in data)):
            reader, what = read_ros_map, "ROS map YAML"
        else:
            if options:
                raise ParameterError(
                    f"{p}: option{'s' if len(options) > 1 else ''} {', '.join(sorted(options))} "
                    f"{'do' if len(options) > 1 else 'does'} not apply to a world file (a world is rasterized later, e.g. by gridfield.rasterize.as_gridmap)"
                )
            return world_from_dict(data, source=str(p))
    elif suffix in (".png", ".pgm", ".bmp"):
        reader, what = read_bitmap, "bitmap"
    elif suffix == ".map":
        reader, what = read_movingai_map, "Moving AI map"
    elif suffix == ".npz":
        reader, what = read_npz, "gridfield .npz file"
    else:
        raise MapFormatError(
            f"{p}: unknown map format {shorten(suffix)}; expected a world or ROS map .yaml, a .png/.pgm/.bmp bitmap, "
            "a Moving AI .map or a gridfield .npz"
        )
    _check_options(reader, options, p, what)
    return reader(p, **options)
