"""Big occupancy rasters read by chunks: BigTIFF / GeoTIFF (through tifffile's Zarr view) and ``.npy``
memory maps. Each reader returns a :class:`~gridfield.core.chunkcache.LazyGridMap`: nothing is decoded
whole; the chunked computation (``gridfield brushfire MAP --chunks N --out F.zarr``) reads it tile by tile.

Occupancy (:mod:`gridfield.io._occupancy`, applied to each slice read by
:class:`~gridfield.core.chunkcache.Raster`): a TIFF is an image, read as PNG, PGM and BMP are, grey levels
with dark = occupied (``occupancy="dark"``, the default: occupancy ``(W - v) / W > threshold``, ``W`` the
white of its bit depth, 255 for 8 bits, 65535 for 16; ``negate``; photometric min-is-white honoured; a
1-bit TIFF likewise, so a boolean array written by tifffile, min-is-white, reads True = obstacle). Float
and signed-integer TIFFs have no grey convention and are refused under ``"dark"``; label rasters take
``occupancy="nonzero"`` (any non-zero value = obstacle). A ``.npy`` array is not an image: booleans as they
are, numbers non-zero = obstacle (``"nonzero"``, its default); ``occupancy="dark"`` reads its unsigned
integers as grey levels. The rule applied is in the map's ``meta["occupancy_rule"]``.

A TIFF's first row is the top of the map (the rows are flipped, as every image reader of
:mod:`gridfield.io` does); a ``.npy`` array is in gridfield's order (row 0 = lowest y), as
:func:`gridfield.io.write_npz` writes.

A GeoTIFF's ``ModelPixelScaleTag`` (33550) and ``ModelTiepointTag`` (33922) give the cell size and the
origin (the lower-left corner: the tie point's x, and its y minus the map's height) when present;
``resolution``/``origin`` options override them. tifffile is an optional dependency (the ``[dask]``
extra), imported inside the reader.

Either may be a URL (``s3://bucket/big.tif``, ``gs://``, ``memory://``; fsspec and its file system's
package, the ``[s3]`` extra, imported only then; credentials from the environment). The map's raster then
holds the URL, not an open file (:class:`UrlTiff`, :class:`UrlNpy`): it pickles to the workers of a cluster,
each of which opens the object once and reads only the byte ranges of the tiles (rows, for a ``.npy``) it
is asked for.
"""

from __future__ import annotations

import math
import weakref
from pathlib import Path as FsPath
from typing import Any, Literal

import numpy as np

from ..core.chunkcache import LazyArray, LazyGridMap, Raster, lazy_grid
from ..core.errors import GridfieldError, MapFormatError, shorten
from ._common import PathLike, _check_file, is_url, local_path, redact, store_errors, url_fs
from ._occupancy import check_grey_options, raster_rule

__all__ = ["UrlNpy", "UrlTiff", "read_npy", "read_tiff"]

PIXEL_SCALE_TAG = 33550
TIEPOINT_TAG = 33922
#: TIFF PhotometricInterpretation: 0 = WhiteIsZero (min-is-white), 1 = BlackIsZero (min-is-black).
MINISWHITE, MINISBLACK = 0, 1
#: Chunk shape of a ``.npy`` map when none is asked for.
NPY_CHUNKS = 1024


#: Per process: the open objects of :class:`UrlTiff` rasters (a worker opens each URL once).
_OPEN: dict[str, Any] = {}


class UrlTiff:
    """A TIFF's first image at a URL as a 2-D array read by slices (tifffile's Zarr view of an fsspec file),
    opened on first use in each process: it pickles as its URL, shape and dtype.

    Examples
    --------
    >>> import fsspec, numpy as np, tifffile, pickle
    >>> with fsspec.open("memory://doc/u.tif", "wb") as f:
    ...     tifffile.imwrite(f, np.arange(12, dtype=np.uint8).reshape(3, 4), tile=(16, 16))
    >>> t = pickle.loads(pickle.dumps(UrlTiff("memory://doc/u.tif")))
    >>> t.shape, t[1:3, 2:4].tolist()
    ((3, 4), [[6, 7], [10, 11]])
    """

    def __init__(self, url: str) -> None:
        self.url = url
        z = self._array()
        self.shape = tuple(int(n) for n in z.shape)
        self.dtype = np.dtype(z.dtype)
        self.chunks = tuple(int(n) for n in z.chunks)
        self.ndim = len(self.shape)

    def _array(self) -> Any:
        z = _OPEN.get(self.url)
        if z is None:
            import tifffile
            import zarr
            from tifffile.zarr import ZarrTiffStore

            fs, path = url_fs(self.url)
            with store_errors(self.url):
                tf = tifffile.TiffFile(fs.open(path, "rb"))  # kept open by the store, for this process
                z = zarr.open(ZarrTiffStore(tf.series[0], read_only=True), mode="r")
            _OPEN[self.url] = z
        return z

    def __getitem__(self, key: Any) -> Any:
        with store_errors(self.url):
            return np.asarray(self._array()[key])

    def __getstate__(self) -> dict[str, Any]:
        return dict(self.__dict__)


class UrlNpy:
    """A C-order ``.npy`` array at a URL read by slices: each slice is one ranged read of its rows (a row
    range is contiguous), then cut to its columns; it pickles as its URL and header.

    Examples
    --------
    >>> import fsspec, numpy as np, pickle
    >>> with fsspec.open("memory://doc/u.npy", "wb") as f:
    ...     np.save(f, np.arange(12).reshape(3, 4))
    >>> a = pickle.loads(pickle.dumps(UrlNpy("memory://doc/u.npy")))
    >>> a.shape, a[1:3, 2:4].tolist()
    ((3, 4), [[6, 7], [10, 11]])
    """

    def __init__(self, url: str) -> None:
        self.url = url
        fs, path = url_fs(url)
        with store_errors(url), fs.open(path, "rb") as f:
            try:
                version = np.lib.format.read_magic(f)
                header = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
                shape, fortran, dtype = header(f)
            except (ValueError, EOFError) as e:
                raise MapFormatError(f"{redact(url)}: not a readable .npy array: {shorten(str(e))}") from None
            self.offset = int(f.tell())
        if fortran and len(shape) == 2 and min(shape) > 1:
            raise MapFormatError(f"{redact(url)}: a Fortran-order .npy; read by rows at a URL, it must be in C order "
                                 "(np.save(f, np.ascontiguousarray(a)))")
        self.shape = tuple(int(n) for n in shape)
        self.dtype = np.dtype(dtype)
        self.ndim = len(self.shape)

    def __getitem__(self, key: Any) -> Any:
        rs, cs = key
        r0, r1, _ = rs.indices(self.shape[0])
        row = self.shape[1] * self.dtype.itemsize
        if r1 <= r0:
            return np.empty((0, self.shape[1]), self.dtype)[:, cs]
        fs, path = url_fs(self.url)
        with store_errors(self.url):
            data = fs.cat_file(path, start=self.offset + r0 * row, end=self.offset + r1 * row)
        if len(data) != (r1 - r0) * row:
            raise MapFormatError(f"{redact(self.url)}: shorter than its header's shape {self.shape}")
        return np.frombuffer(data, self.dtype).reshape(r1 - r0, self.shape[1])[:, cs]


def _raster_map(p: Any, raster: Raster, resolution: float, origin: Any, border: str, fmt: str) -> LazyGridMap:
    try:
        grid = lazy_grid(raster.shape, resolution, tuple(origin), border)
    except GridfieldError as e:
        raise type(e)(f"{p}: {e}") from None
    meta = {"format": fmt, "occupancy_rule": raster.rule.text}
    return LazyGridMap(grid, LazyArray(raster, name="occupied"), source=str(p), meta=meta)


def _tiff_rule(p: FsPath, page: Any, occupancy: str, threshold: float, negate: bool) -> Any:
    """The occupancy rule of a TIFF's first page: its photometric interpretation and bit depth."""
    if occupancy == "dark" and page.dtype is not None and np.dtype(page.dtype).kind in "bu":
        photometric = int(page.photometric) if page.photometric is not None else MINISBLACK
        if photometric not in (MINISWHITE, MINISBLACK):
            name = getattr(page.photometric, "name", str(photometric))
            raise MapFormatError(f"{p}: a {name.lower()} TIFF (photometric {photometric}) holds no grey levels; give "
                                 "occupancy='nonzero' (--occupancy nonzero) to read every non-zero value as an "
                                 "obstacle, or save the map as a grey image")
        return raster_rule(p, page.dtype, occupancy, threshold, negate, image=True,
                           min_is_white=photometric == MINISWHITE, bits=int(page.bitspersample))
    return raster_rule(p, page.dtype, occupancy, threshold, negate, image=True)


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
              chunks: int | None = None, occupancy: Literal["dark", "nonzero"] = "dark", threshold: float = 0.5,
              negate: bool = False) -> LazyGridMap:
    """Read a (Big)TIFF or GeoTIFF occupancy raster lazily, chunk by chunk (tifffile's Zarr view).

    The image is read as :func:`read_bitmap` reads PNG, PGM and BMP: grey levels, dark = occupied. A
    value ``v`` of an image whose white is ``W`` (its bit depth: 255 for 8 bits, 65535 for 16, 1 for a
    1-bit image) has occupancy ``(W - v) / W`` (or ``v / W`` with ``negate``), an obstacle above
    ``threshold``; a min-is-white image (photometric 0) stores 0 as white, so a boolean array written by
    tifffile (1-bit, min-is-white) reads True = obstacle. Float and signed-integer images have no grey
    convention: refused under ``"dark"``, read with ``occupancy="nonzero"``.

    Parameters
    ----------
    path : str or path-like
        A single-image TIFF (tiled or striped, BigTIFF or classic), one grey channel.
    resolution : float, optional
        Cell size; default the GeoTIFF pixel scale, else 1.
    origin : (x, y), optional
        Lower-left corner; default from the GeoTIFF tie point, else ``(0, 0)``.
    border : {"open", "wall"}
    chunks : int, optional
        Tile size of the reads; default the file's own tiles (or strips).
    occupancy : {"dark", "nonzero"}
        ``"dark"`` (default): grey levels, dark = occupied. ``"nonzero"``: a label raster, every
        non-zero value an obstacle (booleans True).
    threshold : float in [0, 1]
        Occupancy above which a pixel is an obstacle (``"dark"`` only; default 0.5).
    negate : bool
        White is occupied, black free (``"dark"`` only).

    Returns
    -------
    LazyGridMap
        ``meta`` holds ``format="tiff"`` and ``occupancy_rule``, the rule applied in words.

    Raises
    ------
    MapFormatError
        Not a readable TIFF, not one 2-D image, inconsistent GeoTIFF tags, or under ``"dark"`` an image
        without grey levels (floats, signed integers, a palette).

    Examples
    --------
    >>> import tempfile, numpy as np, tifffile
    >>> f = tempfile.mkdtemp() + "/m.tif"
    >>> img = np.full((4, 6), 255, np.uint8); img[0, 5] = 0   # white, one black pixel: top row, right end
    >>> tifffile.imwrite(f, img, bigtiff=True, extratags=[(33550, 12, 3, (0.5, 0.5, 0.0))])
    >>> m = read_tiff(f)
    >>> m.grid.resolution, bool(m.occupied[3, 5]), bool(m.occupied[0, 5])
    (0.5, True, False)
    >>> m.meta["occupancy_rule"]
    'dark = occupied (grey level below 50 % of white; values 0..255, 0 = black)'
    >>> labels = read_tiff(f, occupancy="nonzero")   # as a label raster: the 23 non-zero pixels
    >>> labels.occupied.count_nonzero(), labels.meta["occupancy_rule"]
    (23, 'non-zero = obstacle')
    """
    rule_name, thr, neg = check_grey_options(occupancy, threshold, negate, path)
    path = local_path(path)
    try:
        import tifffile
        import zarr
    except ImportError:  # pragma: no cover - the [dask] extra installs them
        raise GridfieldError("reading TIFF maps needs tifffile and zarr: pip install 'gridfield[dask]'") from None
    if is_url(path):
        return _read_tiff_url(str(path), tifffile, resolution, origin, border, chunks, rule_name, thr, neg)
    p = _check_file(path)
    try:
        with tifffile.TiffFile(str(p)) as tf:
            if not tf.pages:
                raise MapFormatError(f"{p}: a TIFF without images")
            page = tf.pages[0]
            shape = tuple(page.shape)
            rows = int(shape[0]) if shape else 0
            res_tag, org_tag = _geo(p, page, rows)
            rule = _tiff_rule(p, page, rule_name, thr, neg) if len(shape) == 2 else None
        store = tifffile.imread(str(p), aszarr=True)
    except GridfieldError:
        raise
    except Exception as e:
        raise MapFormatError(f"{p}: not a readable TIFF: {shorten(str(e))}") from None
    try:
        z = zarr.open(store, mode="r")
    except Exception as e:
        store.close()
        raise MapFormatError(f"{p}: not a readable TIFF: {shorten(str(e))}") from None
    if not isinstance(z, zarr.Array) or z.ndim != 2 or rule is None:
        store.close()
        raise MapFormatError(f"{p}: expected one 2-D (greyscale) image, got shape {shorten(getattr(z, 'shape', '?'))}")
    ch = (chunks, chunks) if chunks is not None else None
    raster = Raster(z, flip=True, chunks=ch, rule=rule)
    res = resolution if resolution is not None else (res_tag if res_tag is not None else 1.0)
    org = origin if origin is not None else (org_tag if org_tag is not None else (0.0, 0.0))
    gm = _raster_map(p, raster, res, org, border, "tiff")
    weakref.finalize(gm, store.close)  # the file stays open while the map is in use
    return gm


def _read_tiff_url(url: str, tifffile: Any, resolution: float | None, origin: Any, border: str, chunks: int | None,
                   rule_name: str, thr: float, neg: bool) -> LazyGridMap:
    """read_tiff of a URL: the metadata from one open, the raster a :class:`UrlTiff`."""
    shown = redact(url)
    fs, path = url_fs(url)
    try:
        with store_errors(url), fs.open(path, "rb") as fh, tifffile.TiffFile(fh) as tf:
            if not tf.pages:
                raise MapFormatError(f"{shown}: a TIFF without images")
            page = tf.pages[0]
            shape = tuple(page.shape)
            rows = int(shape[0]) if shape else 0
            res_tag, org_tag = _geo(shown, page, rows)  # type: ignore[arg-type]
            rule = _tiff_rule(shown, page, rule_name, thr, neg) if len(shape) == 2 else None  # type: ignore[arg-type]
        source = UrlTiff(url)
    except GridfieldError:
        raise
    except Exception as e:
        raise MapFormatError(f"{shown}: not a readable TIFF: {shorten(redact(e))}") from None
    if source.ndim != 2 or rule is None:
        raise MapFormatError(f"{shown}: expected one 2-D (greyscale) image, got shape {shorten(source.shape)}")
    ch = (chunks, chunks) if chunks is not None else None
    raster = Raster(source, flip=True, chunks=ch, rule=rule)
    res = resolution if resolution is not None else (res_tag if res_tag is not None else 1.0)
    org = origin if origin is not None else (org_tag if org_tag is not None else (0.0, 0.0))
    return _raster_map(shown, raster, res, org, border, "tiff")


def read_npy(path: PathLike, *, resolution: float = 1.0, origin: Any = (0.0, 0.0), border: str = "open",
             chunks: int | None = None, occupancy: Literal["dark", "nonzero"] = "nonzero", threshold: float = 0.5,
             negate: bool = False) -> LazyGridMap:
    """Read a ``.npy`` occupancy array as a memory map (``np.load(mmap_mode="r")``), chunk by chunk.

    An array, not an image: row 0 is the lowest y, and by default booleans are as they are and numbers
    non-zero = obstacle (``occupancy="nonzero"``). ``occupancy="dark"`` reads unsigned integers as grey
    levels, as the image readers do (0 = black = obstacle, white the type's maximum: 255 for uint8);
    booleans stay True = obstacle; floats and signed integers are refused.

    Parameters
    ----------
    path : str or path-like
        A 2-D ``.npy`` array (row 0 = lowest y) of booleans or numbers.
    resolution : float
    origin : (x, y)
    border : {"open", "wall"}
    chunks : int, optional
        Tile size of the reads (default :data:`NPY_CHUNKS`).
    occupancy : {"nonzero", "dark"}
        ``"nonzero"`` (default): non-zero = obstacle; ``"dark"``: grey levels, dark = occupied.
    threshold : float in [0, 1]
        Occupancy above which a value is an obstacle (``"dark"`` only).
    negate : bool
        White is occupied (``"dark"`` only).

    Returns
    -------
    LazyGridMap
        ``meta`` holds ``format="npy"`` and ``occupancy_rule``.

    Examples
    --------
    >>> import tempfile, numpy as np
    >>> f = tempfile.mkdtemp() + "/m.npy"
    >>> a = np.zeros((3, 5), bool); a[0, 4] = True
    >>> np.save(f, a)
    >>> m = read_npy(f, resolution=0.25)
    >>> m.shape, bool(m.occupied[0, 4]), m.grid.resolution, m.meta["occupancy_rule"]
    ((3, 5), True, 0.25, 'True = obstacle (boolean raster)')
    >>> np.save(f, np.where(a, 0, 255).astype(np.uint8))   # grey levels: 0 = black
    >>> bool(read_npy(f, occupancy="dark").occupied[0, 4]), read_npy(f).occupied.count_nonzero()
    (True, 14)
    """
    rule_name, thr, neg = check_grey_options(occupancy, threshold, negate, path)
    path = local_path(path)
    if is_url(path):
        u = UrlNpy(str(path))
        if u.ndim != 2:
            raise MapFormatError(f"{redact(path)}: expected a 2-D occupancy array, got shape {shorten(u.shape)}")
        if u.dtype.kind not in "biuf":
            raise MapFormatError(f"{redact(path)}: expected booleans or numbers, got dtype {u.dtype}")
        rule = raster_rule(redact(path), u.dtype, rule_name, thr, neg, image=False)  # type: ignore[arg-type]
        c = NPY_CHUNKS if chunks is None else int(chunks)
        return _raster_map(redact(path), Raster(u, chunks=(c, c), rule=rule), resolution, origin, border, "npy")
    p = _check_file(path)
    try:
        a = np.load(p, mmap_mode="r", allow_pickle=False)
    except (OSError, ValueError, EOFError) as e:
        raise MapFormatError(f"{p}: not a readable .npy array: {shorten(str(e))}") from None
    if not isinstance(a, np.ndarray) or a.ndim != 2:
        raise MapFormatError(f"{p}: expected a 2-D occupancy array, got shape {shorten(getattr(a, 'shape', '?'))}")
    if a.dtype.kind not in "biuf":
        raise MapFormatError(f"{p}: expected booleans or numbers, got dtype {a.dtype}")
    rule = raster_rule(p, a.dtype, rule_name, thr, neg, image=False)
    c = NPY_CHUNKS if chunks is None else int(chunks)
    return _raster_map(p, Raster(a, chunks=(c, c), rule=rule), resolution, origin, border, "npy")
