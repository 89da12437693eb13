"""Big occupancy rasters read by chunks: BigTIFF / GeoTIFF (through tifffile's Zarr view) and ``.npy``
memory maps. Each reader returns a :class:`~gridfield._chunkcache.LazyGridMap`: nothing is decoded
whole; the chunked computation (``gridfield brushfire MAP --chunks N --out F.zarr``) reads it tile by tile.

Occupancy: booleans as they are, numbers non-zero = obstacle. A TIFF is an image: its first row is the
top of the map (the rows are flipped, as every image reader of :mod:`gridfield.io` does); a ``.npy``
array is in gridfield's order (row 0 = lowest y), as :func:`gridfield.io.write_npz` writes.

A GeoTIFF's ``ModelPixelScaleTag`` (33550) and ``ModelTiepointTag`` (33922) give the cell size and the
origin (the lower-left corner: the tie point's x, and its y minus the map's height) when present;
``resolution``/``origin`` options override them. tifffile is an optional dependency (the ``[dask]``
extra), imported inside the reader.
"""

from __future__ import annotations

import math
import weakref
from pathlib import Path as FsPath
from typing import Any

import numpy as np

from .._chunkcache import LazyArray, LazyGridMap, Raster, lazy_grid
from ..errors import GridfieldError, MapFormatError, shorten
from ._common import PathLike, _check_file

__all__ = ["read_npy", "read_tiff"]

PIXEL_SCALE_TAG = 33550
TIEPOINT_TAG = 33922
#: Chunk shape of a ``.npy`` map when none is asked for.
NPY_CHUNKS = 1024


def _raster_map(p: FsPath, raster: Raster, resolution: float, origin: Any, border: str) -> LazyGridMap:
    try:
        grid = lazy_grid(raster.shape, resolution, tuple(origin), border)
    except GridfieldError as e:
        raise type(e)(f"{p}: {e}") from None
    return LazyGridMap(grid, LazyArray(raster, name="occupied"), source=str(p))


def _geo(p: FsPath, page: Any, rows: int) -> tuple[float | None, tuple[float, float] | None]:
    scale = page.tags.get(PIXEL_SCALE_TAG)
    tie = page.tags.get(TIEPOINT_TAG)
    if scale is None:
        return None, None
    sx, sy = float(scale.value[0]), float(scale.value[1])
    if not (math.isfinite(sx) and math.isfinite(sy) and sx > 0 and sy > 0):
        raise MapFormatError(f"{p}: GeoTIFF pixel scale ({sx:g}, {sy:g}) is not two positive numbers")
    if not math.isclose(sx, sy, rel_tol=1e-9):
        raise MapFormatError(f"{p}: GeoTIFF pixels are {sx:g} x {sy:g}; gridfield's cells are square")
    if tie is None or len(tie.value) < 6:
        return sx, None
    i, j, _, x, y = (float(v) for v in tie.value[:5])
    left, top = x - i * sx, y + j * sy
    return sx, (left, top - rows * sx)


def read_tiff(path: PathLike, *, resolution: float | None = None, origin: Any = None, border: str = "open",
              chunks: int | None = None) -> LazyGridMap:
    """Read a (Big)TIFF or GeoTIFF occupancy raster lazily, chunk by chunk (tifffile's Zarr view).

    Parameters
    ----------
    path : str or path-like
        A single-image TIFF (tiled or striped, BigTIFF or classic); non-zero pixels are obstacles.
    resolution : float, optional
        Cell size; default the GeoTIFF pixel scale, else 1.
    origin : (x, y), optional
        Lower-left corner; default from the GeoTIFF tie point, else ``(0, 0)``.
    border : {"open", "wall"}
    chunks : int, optional
        Tile size of the reads; default the file's own tiles (or strips).

    Returns
    -------
    LazyGridMap

    Raises
    ------
    MapFormatError
        Not a readable TIFF, not one 2-D image, or inconsistent GeoTIFF tags.

    Examples
    --------
    >>> import tempfile, numpy as np, tifffile
    >>> f = tempfile.mkdtemp() + "/m.tif"
    >>> img = np.zeros((4, 6), np.uint8); img[0, 5] = 255   # top row, right end
    >>> tifffile.imwrite(f, img, bigtiff=True, extratags=[(33550, 12, 3, (0.5, 0.5, 0.0))])
    >>> m = read_tiff(f)
    >>> m.grid.resolution, bool(m.occupied[3, 5]), bool(m.occupied[0, 5])
    (0.5, True, False)
    """
    p = _check_file(path)
    try:
        import tifffile
        import zarr
    except ImportError:  # pragma: no cover - the [dask] extra installs them
        raise GridfieldError("reading TIFF maps needs tifffile and zarr: pip install 'gridfield[dask]'") from None
    try:
        with tifffile.TiffFile(str(p)) as tf:
            if not tf.pages:
                raise MapFormatError(f"{p}: a TIFF without images")
            page = tf.pages[0]
            shape = tuple(page.shape)
            rows = int(shape[0]) if shape else 0
            res_tag, org_tag = _geo(p, page, rows)
        store = tifffile.imread(str(p), aszarr=True)
    except MapFormatError:
        raise
    except Exception as e:
        raise MapFormatError(f"{p}: not a readable TIFF: {shorten(str(e))}") from None
    try:
        z = zarr.open(store, mode="r")
    except Exception as e:
        store.close()
        raise MapFormatError(f"{p}: not a readable TIFF: {shorten(str(e))}") from None
    if not isinstance(z, zarr.Array) or z.ndim != 2:
        store.close()
        raise MapFormatError(f"{p}: expected one 2-D (greyscale) image, got shape {shorten(getattr(z, 'shape', '?'))}")
    ch = (chunks, chunks) if chunks is not None else None
    raster = Raster(z, flip=True, chunks=ch)
    res = resolution if resolution is not None else (res_tag if res_tag is not None else 1.0)
    org = origin if origin is not None else (org_tag if org_tag is not None else (0.0, 0.0))
    gm = _raster_map(p, raster, res, org, border)
    weakref.finalize(gm, store.close)  # the file stays open while the map is in use
    return gm


def read_npy(path: PathLike, *, resolution: float = 1.0, origin: Any = (0.0, 0.0), border: str = "open",
             chunks: int | None = None) -> LazyGridMap:
    """Read a ``.npy`` occupancy array as a memory map (``np.load(mmap_mode="r")``), chunk by chunk.

    Parameters
    ----------
    path : str or path-like
        A 2-D ``.npy`` array (row 0 = lowest y); non-zero = obstacle.
    resolution : float
    origin : (x, y)
    border : {"open", "wall"}
    chunks : int, optional
        Tile size of the reads (default :data:`NPY_CHUNKS`).

    Returns
    -------
    LazyGridMap

    Examples
    --------
    >>> import tempfile, numpy as np
    >>> f = tempfile.mkdtemp() + "/m.npy"
    >>> a = np.zeros((3, 5), bool); a[0, 4] = True
    >>> np.save(f, a)
    >>> m = read_npy(f, resolution=0.25)
    >>> m.shape, bool(m.occupied[0, 4]), m.grid.resolution
    ((3, 5), True, 0.25)
    """
    p = _check_file(path)
    try:
        a = np.load(p, mmap_mode="r", allow_pickle=False)
    except (OSError, ValueError, EOFError) as e:
        raise MapFormatError(f"{p}: not a readable .npy array: {shorten(str(e))}") from None
    if not isinstance(a, np.ndarray) or a.ndim != 2:
        raise MapFormatError(f"{p}: expected a 2-D occupancy array, got shape {shorten(getattr(a, 'shape', '?'))}")
    if a.dtype.kind not in "biuf":
        raise MapFormatError(f"{p}: expected booleans or numbers, got dtype {a.dtype}")
    c = NPY_CHUNKS if chunks is None else int(chunks)
    return _raster_map(p, Raster(a, chunks=(c, c)), resolution, origin, border)
