"""Chunked brushfire distances on a ``dask.array`` of occupancy (exact, bit-identical to the in-memory one).

Exact (no saturation, or the nearest obstacle asked for): the separable transform of
:func:`gridfield.distance.brushfire.brushfire`, split at its one seam. The column pass needs whole columns, the row
pass whole rows; each is independent across its lines. So the occupancy is rechunked into strips of whole
columns, the column pass (the compiled ``column_block``) gives every cell the global row of its nearest
obstacle in its column (``int32``), that array is rechunked into strips of whole rows, and the row pass
(:mod:`gridfield.chunked._chunked`: the same lower envelope, cimported) gives the distance and the nearest
obstacle; the result is rechunked to the input's chunks (a slicing: the row chunks already agree).
Memory per task: one strip (:func:`strip_chunks`), ``rows x chunk_cols`` of occupancy and ``int32`` for
the column pass; ``chunk_rows x cols`` of ``int32`` in and ``float64`` (plus two ``int32`` with the
nearest obstacle) out for the row pass.

Euclidean through a temporary store (``scratch=``): the column pass runs on strips of whole columns about
one chunk's cells wide (:func:`_strip_width`, at least 64 columns), each written as one raw ``int32`` file
(rows in order, written aside and renamed); after all of them (one barrier task), each output chunk is one
task that reads its rows over its columns plus a margin of one strip on each side and runs
``_kernels_chunked.edt_block``: per row, the lower envelope over only the columns whose obstacles can be
nearest (or tie) inside the chunk, which lie within about the distance at the chunk's first and last
columns; a row that needs more than the window makes the task read a wider one (four times the margin).
Memory per task: the strip (``rows x width`` of occupancy and ``int32``) for the column pass, the window
(``chunk_rows x (chunk_cols + 2 x margin)`` of ``int32``) and one chunk's outputs for the row pass; no
rechunk, and the outputs come out in the input's chunks. The temporary store may be a URL (``s3://...``,
``memory://``; fsspec, imported only then): each strip is then one object, written whole by one request
(an object appears whole or not at all), and a window is read back by one ranged read per strip it
overlaps (a strip's rows are contiguous), so workers on machines that share no disk meet through the
object store.

Saturated (``saturate=`` and no nearest obstacle): a cell nearer than the radius has its nearest obstacle
less than ``h = ceil(saturate / resolution) + 1`` cells away along each axis, and no obstacle inside a
window is nearer than the true nearest one; so each chunk is computed on itself plus a halo of ``h``
cells (the wall border is a halo of obstacles, which adds no nearer cell than the ring at rows/columns
-1 and ``rows``/``cols``), by the in-memory brushfire, and cropped. No rechunk.
"""

from __future__ import annotations

import contextlib
import math
import os
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from numpy.typing import NDArray

from ..core.errors import ArgumentTypeError, ParameterError, check_positive, shorten


def _kernel_edt() -> Any:
    """The compiled kernel module (gridfield/distance/_edt.pyx), imported on first use."""
    from ..distance import _edt  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _edt


def _kernel_chunked() -> Any:
    """The compiled kernel module (gridfield/chunked/_chunked.pyx), imported on first use."""
    from . import _chunked  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _chunked


if TYPE_CHECKING:
    import dask.array as da

__all__ = ["BORDERS", "METRICS", "distance", "scratch_dir"]

METRICS = ("euclidean", "chessboard", "taxicab")
BORDERS = ("wall", "open")


def _dask_array() -> Any:
    try:
        import dask.array as da
    except ImportError:
        raise ParameterError("gridfield.chunked needs Dask: pip install 'gridfield[dask]'") from None
    return da


def check_occupied(occupied: object) -> da.Array:
    """``occupied`` as a 2-D boolean ``dask.array``, or one clear error."""
    da = _dask_array()
    if not isinstance(occupied, da.Array):
        hint = " (wrap it: dask.array.from_array(occupied, chunks=...))" if isinstance(occupied, np.ndarray) else ""
        raise ArgumentTypeError(f"occupied must be a dask.array.Array, got {type(occupied).__name__}{hint}")
    if occupied.ndim != 2:
        raise ParameterError(f"occupied must be 2-D (rows, cols), got {occupied.ndim} dimension(s)")
    if occupied.dtype != np.bool_:
        raise ParameterError(f"occupied must be boolean (True = obstacle), got dtype {occupied.dtype}")
    if any(math.isnan(c) for cs in occupied.chunks for c in cs):
        raise ParameterError("occupied has unknown chunk sizes; call compute_chunk_sizes() first")
    if occupied.size == 0:
        raise ParameterError(f"occupied is empty, shape {occupied.shape}")
    if max(occupied.shape) >= 2**30:
        raise ParameterError(f"occupied has {occupied.shape} cells: each side must be below 2**30")
    return occupied


def _check_choice(name: str, value: object, choices: tuple[str, ...]) -> str:
    if not isinstance(value, str) or value not in choices:
        raise ParameterError(f"{name} must be one of {choices}, got {shorten(value)}")
    return value


def _column_pass(block: NDArray[np.bool_], wall: bool) -> NDArray[np.int32]:
    """Whole columns: the global row of the nearest obstacle in each cell's column."""
    ke = _kernel_edt()

    occ8 = np.ascontiguousarray(block, dtype=bool).view(np.uint8)
    vr = np.empty(block.shape, np.int32)
    ke.column_block(0, block.shape[1], occ8, wall, vr)
    return vr


def _row_pass(vr: NDArray[np.int32], metric: str, rows: int, wall: bool, resolution: float, nearest: bool,
              block_info: dict[Any, Any] | None = None) -> NDArray[np.float64]:
    """Whole rows (``vr`` of rows ``row0..``): the distance."""
    kc = _kernel_chunked()

    row0 = int(block_info[0]["array-location"][0][0]) if block_info else 0
    vr = np.ascontiguousarray(vr, dtype=np.int32)
    d = np.empty(vr.shape, np.float64)
    if metric == "euclidean":
        no = np.empty((1, 1), np.int32)
        kc.edt_rows_block(vr, row0, rows, wall, resolution, d, no, no, False)
    else:
        (kc.l1_rows_block if metric == "taxicab" else kc.linf_rows_block)(vr, row0, rows, wall, resolution, d)
    return d


def _window_pass(window: NDArray[np.bool_], metric: str, resolution: float, saturate: float, far: float,
                 halo: int) -> NDArray[np.float64]:
    """A chunk with its halo: the saturated distance by the in-memory brushfire, cropped to the chunk."""
    from ..core.grid import Grid, GridMap
    from ..distance.brushfire import brushfire

    gm = GridMap(Grid(window.shape, resolution, border="open"), np.ascontiguousarray(window, dtype=bool))
    dm = brushfire(gm, metric=metric, saturate=saturate, far=far, compute_steps=False, compute_nearest=False,
                   compute_labels=False, threads=1)
    return dm.distance[halo:-halo, halo:-halo]


def distance(
    occupied: da.Array,
    *,
    metric: str = "euclidean",
    resolution: float = 1.0,
    saturate: float | None = None,
    return_nearest: bool = False,
    border: str = "wall",
    far: float = math.inf,
    scratch: str | os.PathLike[str] | None = None,
) -> Any:
    """The brushfire distance (and nearest obstacle) of a chunked occupancy grid, exact for any distance.

    Equal bit for bit to :func:`gridfield.distance.brushfire.brushfire` on the whole array (``DistanceMap.distance``,
    ``nearest_row``, ``nearest_col``), computed lazily with bounded memory per task (see the module notes).

    Parameters
    ----------
    occupied : dask.array.Array
        2-D boolean occupancy, ``True`` = obstacle, any chunks (they set the tasks' sizes).
    metric : {"euclidean", "chessboard", "taxicab"}
        The distance measured between cell centres.
    resolution : float
        Cell size in world units (distances are in world units).
    saturate : float, optional
        Saturation radius in world units: distances at or beyond it become ``far``. Without
        ``return_nearest`` the chunks are computed with a halo of that radius only (no rechunk), so every
        chunk must be at least ``ceil(saturate / resolution) + 1`` cells along each axis.
    return_nearest : bool
        Also return the nearest obstacle cell (row, column; the wall ring is rows/columns ``-1`` and
        ``rows``/``cols``; ``-1`` when there is no obstacle at all). Euclidean only: the chessboard and
        taxicab nearest cells of :func:`~gridfield.distance.brushfire.brushfire` follow its raster passes' order
        among equally near obstacles, which a chunked computation does not reproduce.
    border : {"wall", "open"}
        What lies outside the grid, as ``Grid.border``.
    far : float
        Value of saturated distances (default ``inf``).
    scratch : str or path-like, optional
        A directory (made if missing), or a URL (``s3://bucket/prefix``: an object store every worker reaches,
        see the module notes), for the temporary store between the passes of the exact Euclidean
        path (``metric="euclidean"`` and ``return_nearest`` or no ``saturate``): the column pass writes its
        ``int32`` rows there, and each output chunk is computed by one task that reads the rows it needs back
        (see the module notes), so no task holds much more than one chunk's outputs and nothing moves
        all-to-all between workers. The workers must see the same path (one machine, a shared file
        system, or the object store of a URL). The store stays until the caller removes it: compute the results inside
        :func:`scratch_dir`, which removes it on exit, also on error. Without it, the passes meet by a
        task rechunk in worker memory (whole row strips per task). Ignored by the other paths.

    Returns
    -------
    dask.array.Array or tuple of dask.array.Array
        ``float64`` distance with ``occupied``'s chunks; with ``return_nearest`` the tuple
        ``(distance, nearest_row, nearest_col)``, the latter two ``int32``.

    Raises
    ------
    ArgumentTypeError
        If ``occupied`` is not a dask array.
    ParameterError
        For a ``scratch`` that is not a directory, an unknown metric or border, a non-positive resolution or
        saturation radius, a non-boolean or non-2-D occupancy, chunks smaller than the saturation halo,
        ``return_nearest`` with a metric other than Euclidean, or Dask not installed.

    Examples
    --------
    >>> import dask.array as da, numpy as np
    >>> occ = np.zeros((4, 6), bool); occ[1, 1] = True
    >>> d = distance(da.from_array(occ, chunks=2), border="open")
    >>> d.chunks
    ((2, 2), (2, 2, 2))
    >>> d.compute()[1]
    array([1., 0., 1., 2., 3., 4.])
    >>> _, nr, nc = distance(da.from_array(occ, chunks=2), return_nearest=True)
    >>> int(nr[1, 5].compute()), int(nc[1, 5].compute())  # the wall ring beyond column 5
    (1, 6)
    """
    da = _dask_array()
    occupied = check_occupied(occupied)
    metric = _check_choice("metric", metric, METRICS)
    border = _check_choice("border", border, BORDERS)
    res = check_positive("resolution", resolution)
    if not isinstance(return_nearest, bool | np.bool_):
        raise ParameterError(f"return_nearest must be True or False, got {shorten(return_nearest)}")
    if return_nearest and metric != "euclidean":
        raise ParameterError(f"return_nearest=True needs metric='euclidean' (got {metric!r}): the in-memory "
                             "chessboard/taxicab nearest cells depend on its raster order among equally near "
                             "obstacles, which the chunked passes do not reproduce")
    sat = None if saturate is None else check_positive("saturate", saturate)
    try:
        far_v = float(far) if not isinstance(far, bool | str) else math.nan
    except (TypeError, ValueError):
        far_v = math.nan
    if math.isnan(far_v):
        raise ParameterError(f"far must be a number (inf allowed), got {shorten(far)}")
    wall = border == "wall"
    rows, cols = occupied.shape

    halo = 0 if sat is None else math.ceil(sat / res) + 1
    if sat is not None and not return_nearest and min(rows, cols) >= halo:  # (else: small, done exactly)
        chunks = tuple(_halo_chunks(cs, halo, sat, res) for cs in occupied.chunks)
        x = occupied if chunks == occupied.chunks else occupied.rechunk(chunks, method="tasks")
        ext = da.overlap.overlap(x, depth={0: halo, 1: halo}, boundary={0: wall, 1: wall})
        d = ext.map_blocks(_window_pass, metric, res, sat, far_v, halo, dtype=np.float64, chunks=chunks,
                           meta=np.empty((0, 0), np.float64))
        return d if chunks == occupied.chunks else d.rechunk(occupied.chunks, method="tasks")

    if scratch is not None and metric == "euclidean":
        outs = _via_store(occupied, _scratch_path(scratch), wall, res, return_nearest)
        if not return_nearest:
            return outs[0] if sat is None else _saturated(outs[0], sat, far_v)
        dist, nr, nc = outs
        return (dist if sat is None else _saturated(dist, sat, far_v)), nr, nc

    col_chunks, row_chunks = strip_chunks(occupied)
    strips = occupied.rechunk(col_chunks, method="tasks")
    vr = strips.map_blocks(_column_pass, wall, dtype=np.int32, meta=np.empty((0, 0), np.int32))
    vr_rows = vr.rechunk(row_chunks, method="tasks")
    if not return_nearest:
        out = vr_rows.map_blocks(_row_pass, metric, rows, wall, res, False, dtype=np.float64,
                                 meta=np.empty((0, 0), np.float64))
        d = out.rechunk(occupied.chunks, method="tasks")
        return d if sat is None else _saturated(d, sat, far_v)
    dist, nr, nc = (a.rechunk(occupied.chunks, method="tasks") for a in _row_pass_nearest(vr_rows, rows, wall, res))
    if sat is not None:
        dist = _saturated(dist, sat, far_v)
    return dist, nr, nc


def strip_chunks(occupied: da.Array) -> tuple[dict[int, int], dict[int, int]]:
    """The chunks of the two passes' strips: whole columns of the input's column chunks for the column
    pass, whole rows of its row chunks for the row pass (so the result's final rechunk is a slicing).

    Thinner strips (about one chunk's cells each, so that a task's memory would not grow with the map's
    side) were measured worse: at 8192^2 with 1024^2 chunks on 2 workers, 15.4 s and 802 MiB peak worker
    RSS against 5.3 s and 617 MiB (benchmarks/chunked.py, one run each, same load), because dask's task
    rechunk between the two strip shapes merges the (rows / height)^2 pieces through large intermediates.

    Examples
    --------
    >>> import dask.array as da
    >>> cols, rows = strip_chunks(da.zeros((4096, 2048), bool, chunks=1024))
    >>> cols[0], cols[1], rows[0], rows[1]
    (-1, (1024, 1024), (1024, 1024, 1024, 1024), -1)
    """
    return {0: -1, 1: occupied.chunks[1]}, {0: occupied.chunks[0], 1: -1}


def _row_pass_triple(vr: NDArray[np.int32], row0: int, rows: int, wall: bool,
                     resolution: float) -> tuple[NDArray[np.float64], NDArray[np.int32], NDArray[np.int32]]:
    kc = _kernel_chunked()

    vr = np.ascontiguousarray(vr, dtype=np.int32)
    d = np.empty(vr.shape, np.float64)
    nr, nc = np.empty(vr.shape, np.int32), np.empty(vr.shape, np.int32)
    kc.edt_rows_block(vr, row0, rows, wall, resolution, d, nr, nc, True)
    return d, nr, nc


def _row_pass_nearest(vr_rows: Any, rows: int, wall: bool, res: float) -> tuple[Any, Any, Any]:
    """The Euclidean row pass with the nearest cell: one task per strip returning the three arrays, and
    three arrays taking their part of it (no record array to split)."""
    import operator

    from dask.array import Array
    from dask.base import tokenize
    from dask.highlevelgraph import HighLevelGraph

    name = "chunked-edt-rows-" + tokenize(vr_rows, rows, wall, res)
    offsets = np.concatenate([[0], np.cumsum(vr_rows.chunks[0])[:-1]]).tolist()
    layer = {(name, i): (_row_pass_triple, (vr_rows.name, i, 0), int(offsets[i]), rows, wall, res)
             for i in range(len(vr_rows.chunks[0]))}
    layers: dict[str, Any] = {**vr_rows.dask.layers, name: layer}
    deps: dict[str, set[str]] = {**vr_rows.dask.dependencies, name: {vr_rows.name}}
    outs = []
    for k, part in enumerate(("distance", "nearest-row", "nearest-col")):
        pname = f"{name}-{part}"
        layers[pname] = {(pname, i, 0): (operator.getitem, (name, i), k) for i in range(len(offsets))}
        deps[pname] = {name}
        outs.append(pname)
    graph = HighLevelGraph(layers, deps)
    return cast("tuple[Any, Any, Any]", tuple(
        Array(graph, pname, vr_rows.chunks, dtype=dtype, meta=np.empty((0, 0), dtype))
        for pname, dtype in zip(outs, (np.float64, np.int32, np.int32), strict=True)))


def _halo_chunks(chunks: tuple[int, ...], halo: int, sat: float, res: float) -> tuple[int, ...]:
    """The chunks along one axis with a chunk smaller than the halo merged into its neighbour; an error if
    the chunks themselves (all but the last) are smaller."""
    if len(chunks) > 1 and min(chunks[:-1]) < halo:
        raise ParameterError(f"chunks of {min(chunks[:-1])} cells are smaller than the saturation halo of {halo} "
                             f"cells (saturate={sat} at resolution {res}); rechunk to at least {halo} cells per axis")
    if len(chunks) > 1 and chunks[-1] < halo:
        return (*chunks[:-2], chunks[-2] + chunks[-1])
    return chunks


def _saturate_block(d: NDArray[np.float64], sat: float, far: float) -> NDArray[np.float64]:
    out = np.array(d, dtype=np.float64, copy=True)
    out[out >= sat] = far
    return out


def _saturated(d: Any, sat: float, far: float) -> Any:
    return d.map_blocks(_saturate_block, sat, far, dtype=np.float64, meta=np.empty((0, 0), np.float64))


# ---------------------------------------------------------------------------------------------
# the exact Euclidean transform through a temporary store between the passes
# ---------------------------------------------------------------------------------------------
#: The prefix of the temporary stores' directories inside a scratch directory (one per graph: its dask token).
_SCRATCH_PREFIX = "column-pass-"


@contextlib.contextmanager
def scratch_dir(path: str | os.PathLike[str]) -> Iterator[Any]:
    """A directory for :func:`distance`'s temporary store (``scratch=``), removed on exit, also on error.

    ``path`` is made; one that a killed run left (holding nothing but temporary stores) is removed first.
    Compute (or write) the results inside the ``with`` block: the graphs read the store.

    Parameters
    ----------
    path : str or path-like
        The directory, e.g. next to the output store (``OUT.zarr.scratch``); its parent must exist. Or a URL
        (``s3://bucket/out.zarr.scratch``): a prefix of an object store, whose objects are removed likewise.

    Yields
    ------
    pathlib.Path or str
        ``path`` (the URL, for a URL).

    Raises
    ------
    GridfieldError
        If ``path`` exists and is not a directory, or holds anything but temporary stores.

    Examples
    --------
    >>> import dask.array as da, numpy as np, tempfile, os
    >>> occ = np.zeros((4, 6), bool); occ[1, 1] = True
    >>> where = os.path.join(tempfile.mkdtemp(), "out.zarr.scratch")
    >>> with scratch_dir(where) as s:
    ...     d = distance(da.from_array(occ, chunks=2), border="open", scratch=s).compute()
    >>> d[1], os.path.exists(where)
    (array([1., 0., 1., 2., 3., 4.]), False)
    >>> with scratch_dir("memory://doc/out.zarr.scratch") as s:   # a URL: an object store's prefix
    ...     d = distance(da.from_array(occ, chunks=2), border="open", scratch=s).compute()
    >>> d[1]
    array([1., 0., 1., 2., 3., 4.])
    """
    from ..core.errors import GridfieldError

    if _url(path):
        with _remote_scratch(str(path)) as url:
            yield url
        return
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise GridfieldError(f"{p}: exists and is not a directory; the scratch directory must be free")
    if p.exists():
        foreign = [e.name for e in p.iterdir() if not e.name.startswith(_SCRATCH_PREFIX)]
        if foreign:
            raise GridfieldError(f"{p}: exists and holds {shorten(foreign)}, not only temporary stores; "
                                 "choose another scratch directory")
        shutil.rmtree(p)
    p.mkdir()
    try:
        yield p
    finally:
        _remove(p)


def _url(path: object) -> bool:
    from ..io import is_url  # (io's helpers import nothing of chunked)

    return is_url(path)


def _fs(url: str) -> tuple[Any, str]:
    """The fsspec file system of a URL and the path in it (fsspec imported on first use)."""
    from ..io import url_fs

    fs, root = url_fs(url)
    return fs, root.rstrip("/")


@contextlib.contextmanager
def _remote_scratch(url: str) -> Iterator[str]:
    """:func:`scratch_dir` for a URL: the prefix is cleared of a killed run's temporary stores first
    (refused when it holds anything else) and removed on exit."""
    from ..core.errors import GridfieldError
    from ..io import redact, store_errors

    url = url.rstrip("/")
    fs, root = _fs(url)
    with store_errors(url):
        if fs.exists(root):
            names = {str(e).rstrip("/").rsplit("/", 1)[-1] for e in fs.ls(root, detail=False)}
            foreign = sorted(n for n in names if not n.startswith(_SCRATCH_PREFIX))
            if foreign:
                raise GridfieldError(f"{redact(url)}: exists and holds {shorten(foreign)}, not only temporary "
                                     "stores; choose another scratch prefix")
            _remove_remote(fs, root, wait=0.0)
    try:
        yield url
    except BaseException:  # the run's own error stands; the store may be out of reach (a dropped
        with contextlib.suppress(Exception):  # connection): what stays is cleared when the next run starts
            _remove_remote(fs, root)
        raise
    with store_errors(url):
        _remove_remote(fs, root)


def _remove_remote(fs: Any, root: str, wait: float = 10.0) -> None:
    """Remove every object under ``root``; again while tasks of a failed run, still finishing, add some
    (an error of the store ends it)."""
    import time

    deadline = time.monotonic() + wait
    while True:
        with contextlib.suppress(FileNotFoundError):
            fs.rm(root, recursive=True)
        fs.invalidate_cache()
        if not fs.exists(root) or time.monotonic() > deadline:
            return
        time.sleep(0.05)


def _remove(p: Path, wait: float = 10.0) -> None:
    """Remove ``p``; again while tasks of a failed run, still finishing, add files to it (they never make
    a directory: once it is gone, it stays gone)."""
    import time

    deadline = time.monotonic() + wait
    while True:
        shutil.rmtree(p, ignore_errors=True)
        if not p.exists() or time.monotonic() > deadline:
            return
        time.sleep(0.01)


def _scratch_path(scratch: object) -> Path | str:
    if not isinstance(scratch, str | os.PathLike):
        raise ArgumentTypeError(f"scratch must be a directory path, got {type(scratch).__name__} (or a URL string)")
    if _url(scratch):
        return str(scratch).rstrip("/")
    from ..io import local_path

    p = Path(local_path(scratch))
    if p.exists() and not p.is_dir():
        raise ParameterError(f"scratch {str(p)!r} is not a directory")
    p.mkdir(parents=True, exist_ok=True)
    return p


def _strip_width(rows: int, chunk_rows: int, chunk_cols: int) -> int:
    """The column pass's strip width: about one chunk's cells of whole columns (so that a task's memory
    does not grow with the map), at least 64 columns (fewer, larger files) unless the chunks are narrower,
    and the chunk width split into near-equal parts (when the split is exact, as for powers of two, no
    strip straddles two columns of chunks).

    Examples
    --------
    >>> _strip_width(8192, 1024, 1024), _strip_width(3000, 1024, 1024), _strip_width(100, 8, 5)
    (128, 341, 5)
    """
    want = max(min(chunk_cols, 64), min(chunk_cols, chunk_rows * chunk_cols // max(rows, 1)), 1)
    return chunk_cols // -(-chunk_cols // want)


def _strip_file(path: str, m: int, kind: str = "strip") -> str:
    """Strip ``m`` of the column pass (``kind="strip"``) or of its gathered labels (``"label"``)."""
    return f"{path}/{kind}-{m}.i32" if _url(path) else os.path.join(path, f"{kind}-{m}.i32")


def _gather_columns(vr: NDArray[np.int32], lab: NDArray[np.int32], outside: int) -> NDArray[np.int32]:
    """Whole columns: ``lab[vr[i, c], c]``, ``outside`` where ``vr`` is outside the grid."""
    rows = lab.shape[0]
    inside = (vr >= 0) & (vr < rows)
    cols = np.broadcast_to(np.arange(lab.shape[1]), vr.shape)
    out = np.full(vr.shape, outside, np.int32)
    out[inside] = lab[vr[inside], cols[inside]]
    return out


def _put_strip(path: str, final: str, a: NDArray[np.int32]) -> None:
    """``a`` (C order) as the raw strip ``final`` of the temporary store, whole or not at all."""
    if _url(path):  # one object, written whole by one request
        from ..io import store_errors

        fs, key = _fs(final)
        with store_errors(path):
            fs.pipe_file(key, a.tobytes())
        return
    aside = f"{final}.{os.getpid()}-{id(a):x}.tmp"
    try:
        with open(aside, "xb") as f:
            a.tofile(f)
        os.replace(aside, final)
    except FileNotFoundError:
        _gone(path)
        raise


def _strip_of(pieces: list[list[NDArray[Any]]], cuts: list[list[int]]) -> NDArray[Any]:
    """The strip's whole columns from the blocks of the column chunks it overlaps (``cuts``: its columns
    in each)."""
    return np.concatenate([np.concatenate([b[:, k0:k1] for (k0, k1), b in zip(cuts, row, strict=True)], axis=1)
                           for row in zip(*pieces, strict=True)], axis=0)


def _column_to_store(pieces: list[list[NDArray[np.bool_]]], cuts: list[list[int]], path: str, m: int,
                     wall: bool, labels: list[list[NDArray[np.int32]]] | None = None, outside: int = 0) -> int:
    """The column pass of strip ``m`` (whole columns), written to the temporary store as one raw ``int32``
    file of its rows in order: ``pieces[p]`` is a column of occupancy blocks (top to bottom) of which the
    strip holds the columns ``cuts[p]``. With ``labels`` (the same blocks of the obstacles' labels), also
    the label of each cell's column-nearest obstacle (``label[vr[i, c], c]``, ``outside`` beyond the grid),
    as the strip ``label-m``.

    The file appears whole or not at all (written aside, then renamed), so a task recomputed after a lost
    worker rewrites it safely; nothing here makes a directory, so a task still running after the run
    failed and the store was removed fails instead of bringing the store back."""
    occ8 = _strip_of(pieces, cuts).astype(bool, copy=False)
    vr = _column_pass(occ8, wall)
    del occ8
    _put_strip(path, _strip_file(path, m), vr)
    if labels is not None:
        _put_strip(path, _strip_file(path, m, "label"), _gather_columns(vr, _strip_of(labels, cuts), outside))
    return int(vr.shape[1])


def _gone(path: str) -> None:
    """A clear error when the temporary store is no longer there (else the caller re-raises)."""
    if _url(path):
        fs, root = _fs(path)
        fs.invalidate_cache()
        there = fs.exists(root)
    else:
        there = os.path.isdir(path)
    if not there:
        from ..core.errors import GridfieldError

        raise GridfieldError(f"{path}: the temporary store between the passes is gone; compute the results "
                             "inside the scratch_dir() block (or keep the scratch directory until they are done)")


def _barrier(done: list[int], path: str) -> str:
    """Every strip of the column pass is written: the store's path for the row-pass tasks."""
    return path


def _read_window(path: str, r0: int, r1: int, a: int, b: int, rows: int, cols: int, ws: int,
                 kind: str = "strip") -> NDArray[np.int32]:
    """Rows ``r0:r1``, columns ``a:b`` of the column pass (or its labels, ``kind="label"``), from the strips
    that hold them."""
    win = np.empty((r1 - r0, b - a), np.int32)
    for m in range(a // ws, -(-b // ws)):
        s0, s1 = m * ws, min(cols, (m + 1) * ws)
        if _url(path):
            buf = _read_remote_rows(path, m, r0, r1, s1 - s0, kind)
            lo, hi = max(a, s0), min(b, s1)
            win[:, lo - a:hi - a] = buf[:, lo - s0:hi - s0]
            continue
        buf = np.empty((r1 - r0, s1 - s0), np.int32)
        try:
            with open(_strip_file(path, m, kind), "rb") as f:
                f.seek(r0 * (s1 - s0) * 4)
                if f.readinto(buf.data.cast("B")) != buf.nbytes:
                    raise OSError(f"{_strip_file(path, m, kind)}: shorter than {rows} x {s1 - s0} int32")
        except FileNotFoundError:
            _gone(path)
            raise
        lo, hi = max(a, s0), min(b, s1)
        win[:, lo - a:hi - a] = buf[:, lo - s0:hi - s0]
    return win


def _read_remote_rows(path: str, m: int, r0: int, r1: int, width: int, kind: str = "strip") -> NDArray[np.int32]:
    """Rows ``r0:r1`` of strip ``m`` of a temporary store at a URL: one ranged read."""
    from ..io import store_error

    fs, key = _fs(_strip_file(path, m, kind))
    want = (r1 - r0) * width * 4
    try:
        data = fs.cat_file(key, start=r0 * width * 4, end=r1 * width * 4)
    except Exception as e:
        if isinstance(e, FileNotFoundError):
            _gone(path)
        clear = store_error(e, path)
        if clear is None:
            raise
        raise clear from None
    if len(data) != want:
        raise OSError(f"{_strip_file(path, m, kind)}: shorter than rows {r0}..{r1} x {width} int32")
    return np.frombuffer(data, np.int32).reshape(r1 - r0, width)


def _edt_block_task(path: str, r0: int, r1: int, c0: int, c1: int, ws: int, rows: int, cols: int,
                    wall: bool, res: float, nearest: bool,
                    outside: int | None = None) -> tuple[NDArray[Any], ...]:
    """One output chunk (rows ``r0:r1``, columns ``c0:c1``) of the row pass, from the column-pass rows of a
    window one strip wider on each side, read from the store (and re-read wider until every row's nearest
    candidates are inside it: ``_kernels_chunked.edt_block``). With ``outside`` (the label beyond the
    grid), also the label of each cell's nearest obstacle, ``L1[i, nc[i, j]]`` from the same window of the
    stored column labels."""
    kc = _kernel_chunked()
    shape = (r1 - r0, c1 - c0)
    d = np.empty(shape, np.float64)
    nr = np.empty(shape if nearest else (1, 1), np.int32)
    nc = np.empty(shape if nearest else (1, 1), np.int32)
    margin = ws
    while True:
        a, b = max(0, (c0 - margin) // ws * ws), min(cols, -(-(c1 + margin) // ws) * ws)
        win = _read_window(path, r0, r1, a, b, rows, cols, ws)
        if kc.edt_block(win, a, r0, rows, cols, wall, res, c0, d, nr, nc, nearest):
            if outside is None:
                return d, nr, nc
            del win
            l1 = _read_window(path, r0, r1, a, b, rows, cols, ws, "label")
            inside = (nc >= 0) & (nc < cols)
            lab = np.full(shape, outside, np.int32)
            lab[inside] = l1[np.nonzero(inside)[0], nc[inside] - a]
            return d, nr, nc, lab
        del win
        margin *= 4


def _via_store(occupied: Any, scratch: Path | str, wall: bool, res: float, nearest: bool,
               labels: Any = None, outside: int = 0) -> list[Any]:
    """The exact Euclidean graph through a temporary store in ``scratch``: the distance (and the nearest
    row and column; with ``labels``, a dask array of the obstacles' labels chunked as ``occupied``, also the
    nearest obstacle's label), chunked as ``occupied``."""
    import operator

    from dask.array import Array
    from dask.base import tokenize
    from dask.highlevelgraph import HighLevelGraph

    rows, cols = occupied.shape
    rc, cc = max(occupied.chunks[0]), max(occupied.chunks[1])
    ws = _strip_width(rows, rc, cc)
    if isinstance(scratch, str):  # a URL: an object store has no directories to make
        token = tokenize(occupied, wall, res, nearest, scratch, ws, labels, outside)
        path = f"{scratch}/{_SCRATCH_PREFIX}{token}"
    else:
        token = tokenize(occupied, wall, res, nearest, str(scratch.resolve()), ws, labels, outside)
        path = str(scratch.resolve() / f"{_SCRATCH_PREFIX}{token}")
        os.makedirs(path, exist_ok=True)

    # strip m is the columns m*ws .. of the store's chunks (no two tasks write one store chunk), sliced out
    # of the occupancy's column chunks it overlaps
    occ_w = occupied
    cname, bname, ename = (f"chunked-edt-{part}-{token}" for part in ("columns", "barrier", "block"))
    nrow = len(occ_w.chunks[0])
    cbounds = np.concatenate([[0], np.cumsum(occ_w.chunks[1])]).tolist()
    layer_c = {}
    for m, s0 in enumerate(range(0, cols, ws)):
        s1 = min(cols, s0 + ws)
        js = [j for j in range(len(cbounds) - 1) if cbounds[j] < s1 and cbounds[j + 1] > s0]
        cuts = [[max(s0, cbounds[j]) - cbounds[j], min(s1, cbounds[j + 1]) - cbounds[j]] for j in js]
        layer_c[(cname, m)] = (_column_to_store, [[(occ_w.name, i, j) for i in range(nrow)] for j in js], cuts,
                               path, m, wall,
                               None if labels is None else [[(labels.name, i, j) for i in range(nrow)] for j in js],
                               outside)
    layer_b = {bname: (_barrier, list(layer_c), path)}
    roff = np.concatenate([[0], np.cumsum(occupied.chunks[0])]).tolist()
    coff = np.concatenate([[0], np.cumsum(occupied.chunks[1])]).tolist()
    layer_e = {(ename, i, j): (_edt_block_task, bname, int(roff[i]), int(roff[i + 1]), int(coff[j]),
                               int(coff[j + 1]), ws, rows, cols, wall, res, nearest or labels is not None,
                               None if labels is None else outside)
               for i in range(len(roff) - 1) for j in range(len(coff) - 1)}
    below = {**occ_w.dask.layers, **({} if labels is None else labels.dask.layers)}
    below_deps = {**occ_w.dask.dependencies, **({} if labels is None else labels.dask.dependencies)}
    inputs = {occ_w.name} | (set() if labels is None else {labels.name})
    layers: dict[str, Any] = {**below, cname: layer_c, bname: layer_b, ename: layer_e}
    deps: dict[str, set[str]] = {**below_deps, cname: inputs, bname: {cname}, ename: {bname}}
    outs = []
    parts = ("distance", "nearest-row", "nearest-col", "label") if labels is not None else (
        ("distance", "nearest-row", "nearest-col")[:3 if nearest else 1])
    for k, part in enumerate(parts):
        pname = f"{ename}-{part}"
        layers[pname] = {(pname, i, j): (operator.getitem, (ename, i, j), k) for (_, i, j) in layer_e}
        deps[pname] = {ename}
        outs.append(pname)
    graph = HighLevelGraph(layers, deps)
    return [Array(graph, pname, occupied.chunks, dtype=dtype, meta=np.empty((0, 0), dtype))
            for pname, dtype in zip(outs, (np.float64, np.int32, np.int32, np.int32), strict=False)]
