"""Bitmaps: PGM (``P2``/``P5``, decoded here), PNG and BMP (Pillow) read as pixels and as occupancy grids.

The PGM decoder is gridfield's own because ROS maps are mostly PGM and Pillow's PGM support differs from
map_server's in corner cases (16-bit maxval, comments in the header); Pillow is imported only when a
non-PGM image is read or written. The image's size is checked against the size guard from its header,
before any pixel is decoded. :class:`_Pixels` is also what the ROS loaders (:mod:`gridfield.io._ros`)
turn into OccupancyGrid values.
"""

from __future__ import annotations

import io as _io
import re
import struct
import warnings
import zlib
from dataclasses import dataclass
from pathlib import Path as FsPath
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from ..core.errors import GridfieldError, MapFormatError, ParameterError, SizeLimitError, shorten
from ..core.grid import BORDERS, Grid, GridMap
from ..core.limits import check_cells
from ._common import PathLike, _check_file, _choice, _read_bytes
from ._occupancy import check_grey_options, grey_text

UNKNOWN_CHOICES = ("occupied", "free")


# ----------------------------------------------------------------------------------------
# images: pixels as float64 arrays (rows, cols, channels) in [0, 255], top row first
# ----------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class _Pixels:
    """Decoded image: ``data`` has shape (rows, cols, C) with C = 1 (grey), 3 (RGB) or 4 (RGBA); ``index``
    the colour indices of a palette image (``data`` holds its colours), else None."""

    data: NDArray[np.float64]
    format: str  # "PGM", "PNG", "BMP", ...
    index: NDArray[np.uint8] | None = None

    @property
    def has_alpha(self) -> bool:
        channels: int = self.data.shape[2]
        return channels == 4

    @property
    def alpha(self) -> NDArray[np.float64] | None:
        return self.data[..., 3] if self.has_alpha else None

    def luma(self) -> NDArray[np.float64]:
        """Grey level 0..255: the image itself if grey, else Rec. 601 luma (rounded, as 8-bit converters do)."""
        if self.data.shape[2] == 1:
            return self.data[..., 0]
        luma: NDArray[np.float64] = np.rint(self.data[..., :3] @ np.array([0.299, 0.587, 0.114]))
        return luma


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
    _check_bitmap_cells((height, width), f"{p} (PGM header)")
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


#: What a bitmap's size error adds: bitmaps are decoded whole, the big-map formats are read by chunks.
IN_MEMORY_NOTE = ("PNG, PGM and BMP are in-memory formats (decoded whole); for a map larger than memory use a "
                  "BigTIFF/GeoTIFF, a .npy file (memory-mapped) or a Zarr array, read by chunks "
                  "(gridfield brushfire MAP --chunks N --out F.zarr)")


def _check_bitmap_cells(shape: tuple[int, int], what: str) -> None:
    try:
        check_cells(shape, what)
    except SizeLimitError as e:
        raise SizeLimitError(f"{e}. {IN_MEMORY_NOTE}") from None


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
                _check_bitmap_cells((height, width), f"{p} (image header)")
                im.load()
                fmt = im.format or "image"
                mode = im.mode
                img: Image.Image = im
                index = np.asarray(im) if mode == "P" else None
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
    return _Pixels(np.clip(pixels, 0.0, 255.0), fmt, index if index is not None and index.ndim == 2 else None)


def _load_pixels(path: PathLike) -> _Pixels:
    p = _check_file(path)
    data = _read_bytes(p)
    if not data:
        raise MapFormatError(f"{p}: the file is empty")
    if data[:2] in (b"P2", b"P5"):
        return _read_pgm(p, data)
    return _read_pillow(p, data)


def read_bitmap(
    path: PathLike,
    *,
    resolution: float = 1.0,
    origin: tuple[float, float] = (0.0, 0.0),
    negate: bool = False,
    threshold: float = 0.5,
    border: Literal["open", "wall"] = "open",
    unknown: Literal["occupied", "free"] = "occupied",
    occupancy: Literal["dark", "nonzero"] = "dark",
) -> GridMap:
    """Read a PNG, PGM (``P2``/``P5``) or BMP image as an occupancy grid.

    Colour pixels become grey by Rec. 601 luma (``0.299 R + 0.587 G + 0.114 B``). A pixel of grey
    level ``v`` has occupancy ``(255 - v) / 255`` (dark = obstacle), or ``v / 255`` with
    ``negate``; it is occupied when that exceeds ``threshold`` (16-bit images are scaled to
    0..255 first). This is the rule of every image reader (:func:`read_tiff` too). With
    ``occupancy="nonzero"`` (a label image) every pixel whose value is not 0 is an obstacle: its
    grey level, any colour channel, or a palette image's colour index. Transparent pixels
    (alpha < 255) are *unknown*, as in ROS map_server, and are treated per ``unknown``. The image is
    flipped vertically: its top row becomes the highest y.

    Parameters
    ----------
    path : str or path-like
    resolution : float
        Edge length of one pixel in world units.
    origin : (float, float)
        World coordinates of the lower-left corner of the lower-left pixel.
    negate : bool
        If true, white is occupied and black free (the ``"dark"`` rule only).
    threshold : float in [0, 1]
        Occupancy above which a pixel is an obstacle (the ``"dark"`` rule only).
    border : {"open", "wall"}
        What lies outside the image.
    unknown : {"occupied", "free"}
        How transparent pixels are treated.
    occupancy : {"dark", "nonzero"}
        ``"dark"``: grey levels, dark = occupied (default); ``"nonzero"``: non-zero = obstacle.

    Returns
    -------
    GridMap
        ``meta`` holds ``format="bitmap"``, the image format, ``occupancy_rule`` (the rule in words)
        and the fraction of transparent pixels.

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
    >>> m.meta["occupancy_rule"]
    'dark = occupied (grey level below 50 % of white)'
    """
    _choice("border", border, BORDERS)
    _choice("unknown", unknown, UNKNOWN_CHOICES)
    rule, thr, neg = check_grey_options(occupancy, threshold, negate, path)
    px = _load_pixels(path)
    rows, cols = px.data.shape[:2]
    grid = Grid((rows, cols), resolution, origin, border)
    colour = px.data.shape[2] > 1
    if rule == "nonzero":
        if px.index is not None:
            occupied, text = px.index != 0, "non-zero = obstacle (palette index)"
        else:
            occupied = (px.data[..., :3] != 0).any(axis=2)
            text = "non-zero = obstacle" + (" (any colour channel)" if colour else "")
    else:
        grey = px.luma()
        occ = grey / 255.0 if neg else (255.0 - grey) / 255.0
        occupied = occ > thr
        text = grey_text(thr, neg, "colour by luma" if colour else "")
    meta: dict[str, Any] = {"format": "bitmap", "image_format": px.format}
    alpha = px.alpha
    if alpha is not None:
        transparent = alpha < 255.0
        occupied = np.where(transparent, unknown == "occupied", occupied)
        meta["unknown_fraction"] = float(transparent.mean())
        text += f"; transparent = unknown ({unknown})"
    meta["occupancy_rule"] = text
    return GridMap(grid, np.ascontiguousarray(occupied[::-1]), source=str(path), meta=meta)


def _image_of(gridmap: GridMap) -> NDArray[np.uint8]:
    """Occupied black (0), free white (254, map_saver's free level), top row first."""
    return np.ascontiguousarray(np.where(gridmap.occupied, 0, 254).astype(np.uint8)[::-1])


def write_bitmap(path: PathLike, gridmap: GridMap) -> FsPath:
    """Write an occupancy grid as an 8-bit grey image: PNG, PGM (binary ``P5``) or BMP by suffix.

    Occupied cells are black (0) and free cells white (254); the top image row is the highest
    y, so :func:`read_bitmap` (with the grid's resolution and origin) reads back the same grid.

    Parameters
    ----------
    path : str or path-like
        Ends in ``.png``, ``.pgm`` or ``.bmp`` (any case): the format.
    gridmap : GridMap

    Returns
    -------
    pathlib.Path
        ``path``.

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
