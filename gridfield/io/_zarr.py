"""The gridfield Zarr store: maps, distance maps and fields larger than memory, written chunk by chunk.

A store is a Zarr (v3) group directory. Its root attribute ``gridfield`` holds the grid metadata
(:data:`FORMAT`, ``version``, ``kind`` = ``"map"``, ``"distance"`` or ``"field"``, ``shape``,
``resolution``, ``origin``, ``border``, ``chunks``, ``occupied_cells`` and, as the kind has them,
``metric``, ``saturate``, ``goal`` and ``params`` (JSON text)); its arrays are among
:data:`STORE_ARRAYS`, all chunked alike, and, for a disc robot's configuration space, ``diagonals``
(:attr:`GridMap.diagonals <gridfield.core.grid.GridMap.diagonals>`, uint8, one per 2x2 block of cells: shape
``(rows - 1, cols - 1)``, chunked as the others). :func:`read_store` returns the usual result types (a
:class:`~gridfield.core.chunkcache.LazyGridMap`, a :class:`~gridfield.distance.brushfire.DistanceMap`, a
:class:`~gridfield.fields.potential.Field`) whose arrays are :class:`~gridfield.core.chunkcache.LazyArray` views of
the Zarr arrays sharing one chunk cache: nothing is read whole.

:func:`write_store` never leaves a half-written store under the final name: it writes ``NAME.partial/``,
marks every chunk it completes in ``NAME.partial/.progress/``, and renames the directory when every chunk
of every array is there. A run that stops (an exception, a kill) leaves the ``.partial`` directory; a
re-run with the same arguments (the same ``resume_key``) writes only the chunks not yet marked.

A store may also be a URL (``s3://bucket/f.zarr``, ``gs://``, ``memory://``; fsspec and the file system's
package, the ``[s3]`` extra, imported only then; credentials from the environment). An object store has no
atomic rename, so there the store is written under its final name, its root holding the attribute
``gridfield_partial`` (the run's key) and its marks under ``.progress/`` until every chunk is written; then
one write of the root's attributes replaces ``gridfield_partial`` by the grid metadata, and the marks are
removed. :func:`read_store` refuses a store without the metadata (an interrupted write), and a re-run resumes
it as it resumes a local ``.partial``. Errors of the store (a missing bucket, a denied write, a dropped
connection) are one :class:`~gridfield.core.errors.GridfieldError` naming the URL without its credentials.

zarr is an optional dependency (the ``[dask]`` extra), imported inside the functions.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
from collections.abc import Callable, Mapping
from pathlib import Path as FsPath
from typing import Any, Literal

import numpy as np

from .._version import __version__
from ..core.chunkcache import DEFAULT_BUDGET, ChunkCache, LazyArray, LazyGridMap, Raster, lazy_grid
from ..core.errors import GridfieldError, MapFormatError, ParameterError, shorten
from ..core.grid import Grid
from ..core.results import DistanceMap, Field
from ._common import PathLike, is_url, local_path, redact, store_errors, url_fs
from ._occupancy import check_grey_options, raster_rule

__all__ = ["FORMAT", "STORE_ARRAYS", "chunk_counter", "is_store", "read_store", "read_zarr", "read_zarr_array", "write_store"]

#: The store format's version (``attrs["gridfield"]["format"]``).
FORMAT = 1
#: The arrays a store may hold, and their dtypes.
STORE_ARRAYS: dict[str, str] = {
    "occupied": "bool", "distance": "float64", "nearest_row": "int32", "nearest_col": "int32",
    "U": "float64", "dUdx": "float64", "dUdy": "float64",
}
#: The array of a map's :attr:`GridMap.diagonals <gridfield.core.grid.GridMap.diagonals>` (``write_store(...,
#: diagonals=)``): one entry per 2x2 block of cells, of shape ``(rows - 1, cols - 1)``.
DIAGONALS = "diagonals"
KINDS = ("map", "distance", "field")
#: The occupancy rule of a store's map (its ``meta["occupancy_rule"]``): the stored booleans.
STORE_RULE = "the store's occupied array (True = obstacle)"
_MARK = "gridfield"
_PROGRESS = ".progress"


def _zarr() -> Any:
    try:
        import zarr
    except ImportError:  # pragma: no cover - the [dask] extra installs it
        raise GridfieldError("Zarr stores need the zarr package: pip install 'gridfield[dask]'") from None
    return zarr


def is_store(path: PathLike) -> bool:
    """Whether ``path`` is a Zarr directory (a ``zarr.json`` at its root), gridfield's or not.

    Examples
    --------
    >>> is_store("no/such/dir.zarr"), is_store("memory://no/such.zarr")
    (False, False)
    """
    path = local_path(path)
    if is_url(path):
        fs, root = url_fs(str(path))
        with store_errors(str(path)):
            fs.invalidate_cache(root)  # (a listing cached before another process wrote the store)
            return bool(fs.exists(f"{root.rstrip('/')}/zarr.json"))
    p = FsPath(path)
    return p.is_dir() and (p / "zarr.json").is_file()


# ---------------------------------------------------------------------------------------------
# writing
# ---------------------------------------------------------------------------------------------
def _done_mark(progress: FsPath, name: str, i: int, j: int) -> FsPath:
    return progress / f"{name}.{i}.{j}"


def _mark_done(progress: FsPath, name: str, i: int, j: int) -> None:
    """Record that chunk ``(i, j)`` of ``name`` is written (called after the chunk's data is on disk)."""
    _done_mark(progress, name, i, j).touch()


def write_store(path: PathLike, arrays: Mapping[str, Any], grid: Grid, *, kind: str,
                attrs: Mapping[str, Any] | None = None, chunks: int | tuple[int, int] | None = None,
                resume_key: str = "", scheduler: Any = "threads", diagonals: Any = None) -> FsPath | str:
    """Write arrays (dask or numpy) and the grid metadata to a gridfield Zarr store, chunk by chunk.

    Parameters
    ----------
    path : str or path-like
        The store's directory (conventionally ``*.zarr``), or its URL (``s3://bucket/f.zarr``, see the module
        notes); it must not exist yet (but for an interrupted write of the same run, resumed).
    arrays : mapping
        Arrays named as in :data:`STORE_ARRAYS`, each of the grid's shape: dask arrays (computed
        chunk by chunk, all in one graph) or numpy arrays.
    grid : Grid
    kind : {"map", "distance", "field"}
    attrs : mapping, optional
        Further metadata: ``metric``, ``saturate`` (distance and field), ``goal`` and ``params``
        (field); JSON values.
    chunks : int or (int, int), optional
        The chunk shape of the store; default the first dask array's chunks (1024 for numpy).
    resume_key : str
        Identifies the run: a ``NAME.partial`` left by an interrupted run with the same key is
        resumed, one with another key is refused.
    scheduler : str or distributed.Client
        How dask computes: ``"threads"``, ``"synchronous"`` or a client.
    diagonals : array of uint8, shape ``(rows - 1, cols - 1)``, optional
        The :attr:`GridMap.diagonals <gridfield.core.grid.GridMap.diagonals>` of the map whose ``occupied`` is
        written (a disc robot's configuration space), stored as the array ``diagonals``: :func:`read_store`
        gives the map back with them. Numpy or dask.

    Returns
    -------
    pathlib.Path or str
        ``path`` (the URL as given, for a URL).

    Raises
    ------
    ParameterError
        Unknown array names, wrong shapes or kind.
    GridfieldError
        ``path`` exists, or a ``.partial`` (an interrupted store at a URL) of another run is in the way; an
        object store's error (missing bucket, denied write, dropped connection).

    Examples
    --------
    >>> import tempfile, numpy as np
    >>> from gridfield.core.grid import Grid
    >>> d = tempfile.mkdtemp()
    >>> occ = np.zeros((6, 5), bool); occ[2, 3] = True
    >>> p = write_store(f"{d}/m.zarr", {"occupied": occ}, Grid((6, 5), 0.5), kind="map", chunks=4)
    >>> m = read_store(p)
    >>> m.shape, bool(m.occupied[2, 3]), m.occupied.chunks
    ((6, 5), True, (4, 4))
    >>> u = write_store("memory://doc/m.zarr", {"occupied": occ}, Grid((6, 5), 0.5), kind="map", chunks=4)
    >>> bool(read_store(u).occupied[2, 3])
    True
    """
    try:
        import dask
        import dask.array as da
    except ImportError:  # pragma: no cover - the [dask] extra installs it
        raise GridfieldError("writing a Zarr store needs dask: pip install 'gridfield[dask]'") from None

    zarr = _zarr()
    path = local_path(path)
    if is_url(path):
        with store_errors(str(path)):
            _write_remote(zarr, dask, da, str(path), arrays, grid, kind, attrs, chunks, resume_key, scheduler,
                          diagonals)
        return str(path)
    out, ch, lazy = _check_write(path, arrays, grid, kind, chunks, da)
    if diagonals is not None:
        lazy[DIAGONALS] = _check_diagonals(diagonals, grid, ch, da)
    partial = out.with_name(out.name + ".partial")
    progress = partial / _PROGRESS
    meta = _metadata(grid, kind, ch, attrs)
    group = _open_partial(zarr, partial, progress, grid, ch, lazy, meta, resume_key)
    _write_chunks(dask, group, progress, ch, lazy, scheduler)
    # every chunk is written: the metadata, then the rename makes the store appear whole (a stop before
    # the rename leaves a .partial that resumes with nothing left to write; after it, the bookkeeping
    # left inside the store is harmless and removed next)
    occ_cells = _count(lazy["occupied"], scheduler)
    group.attrs[_MARK] = {**meta, "occupied_cells": occ_cells}
    _publish(partial, out)
    done = zarr.open_group(str(out), mode="a")
    if "gridfield_partial" in done.attrs:
        del done.attrs["gridfield_partial"]
    shutil.rmtree(out / _PROGRESS, ignore_errors=True)
    return out


def _check_write(path: PathLike, arrays: Mapping[str, Any], grid: Grid, kind: str,
                 chunks: int | tuple[int, int] | None, da: Any,
                 remote: bool = False) -> tuple[FsPath, tuple[int, int], dict[str, Any]]:
    """write_store's checks: the kind, the array names and shapes, the (local) target; the chunk shape and
    the arrays as dask arrays of the store's dtypes and chunks."""
    if kind not in KINDS:
        raise ParameterError(f"kind must be one of {', '.join(map(repr, KINDS))}, got {shorten(kind)}")
    if DIAGONALS in arrays:
        raise ParameterError("a map's diagonals (one entry per 2x2 block of cells) are written with "
                             "write_store(..., diagonals=gridmap.diagonals), not among the grid-shaped arrays")
    bad = sorted(set(arrays) - set(STORE_ARRAYS))
    if bad:
        raise ParameterError(f"a gridfield store holds the arrays {', '.join(STORE_ARRAYS)}; not {', '.join(bad)}")
    if "occupied" not in arrays:
        raise ParameterError("a gridfield store needs the 'occupied' array")
    out = FsPath(str(path))
    if not remote and out.exists():
        raise GridfieldError(f"{out}: already exists; remove it or choose another --out")
    if not remote and not out.resolve().parent.is_dir():
        raise GridfieldError(f"{out}: the folder {out.parent} does not exist")
    if chunks is None:
        first = next((a for a in arrays.values() if isinstance(a, da.Array)), None)
        chunks = (first.chunksize[0], first.chunksize[1]) if first is not None else (1024, 1024)
    c: Any = chunks
    ch = (int(c), int(c)) if np.ndim(c) == 0 else (int(c[0]), int(c[1]))
    if min(ch) < 1:
        raise ParameterError(f"chunks must be positive, got {shorten(chunks)}")
    ch = (min(ch[0], grid.rows), min(ch[1], grid.cols))
    lazy: dict[str, Any] = {}
    for name, a in arrays.items():
        if tuple(a.shape) != grid.shape:
            raise ParameterError(f"array {name!r} has shape {tuple(a.shape)}, but the grid has shape {grid.shape}")
        a = a if isinstance(a, da.Array) else da.from_array(np.asarray(a), chunks=ch)
        lazy[name] = a.astype(STORE_ARRAYS[name]).rechunk(ch)
    return out, ch, lazy


def _check_diagonals(diagonals: Any, grid: Grid, ch: tuple[int, int], da: Any) -> Any:
    """``diagonals=`` of write_store as a dask array of uint8 in the store's chunks (its shape and, for a numpy
    array, its values checked as :class:`~gridfield.core.grid.GridMap` checks them)."""
    want = (max(grid.rows - 1, 0), max(grid.cols - 1, 0))
    if tuple(diagonals.shape) != want:
        raise ParameterError(f"diagonals has shape {tuple(diagonals.shape)}, but the grid's 2x2 blocks have shape "
                             f"{want}")
    if not isinstance(diagonals, da.Array):
        d = np.asarray(diagonals)
        if d.size and (not np.issubdtype(d.dtype, np.integer) or int(d.min()) < 0 or int(d.max()) > 3):
            raise ParameterError("diagonals must hold the bits 0 and 1 (values 0 to 3) of a uint8 array")
        diagonals = da.from_array(d, chunks=ch)
    return diagonals.astype(np.uint8).rechunk(ch)


def _open_partial(zarr: Any, partial: FsPath, progress: FsPath, grid: Grid, ch: tuple[int, int],
                  lazy: Mapping[str, Any], meta: Mapping[str, Any], resume_key: str) -> Any:
    """The ``.partial`` group to write into: a new one, or the one an interrupted run with the same
    arguments left (refused when its arguments differ)."""
    if partial.exists():
        try:
            old = dict(zarr.open_group(str(partial), mode="r").attrs).get("gridfield_partial", {})
        except Exception:
            old = {}
        if (old.get("resume_key") != resume_key or old.get("meta") != meta
                or sorted(old.get("arrays", [])) != sorted(lazy)):
            raise GridfieldError(f"{partial}: holds an interrupted run with other arguments; remove it to start over")
        group = zarr.open_group(str(partial), mode="a")
    else:
        group = zarr.open_group(str(partial), mode="w")
        for name, a in lazy.items():
            group.create_array(name, shape=tuple(a.shape), chunks=ch, dtype=STORE_ARRAYS.get(name, "uint8"),
                               fill_value=False if name == "occupied" else 0)
        group.attrs["gridfield_partial"] = {"resume_key": resume_key, "meta": dict(meta), "arrays": sorted(lazy)}
        progress.mkdir()
    return group


class _RemoteMarks:
    """The progress marks of a store at a URL: empty objects ``ROOT/.progress/NAME.I.J`` (picklable: the
    write tasks carry it to the workers)."""

    def __init__(self, fs: Any, root: str) -> None:
        self.fs, self.dir = fs, f"{root.rstrip('/')}/{_PROGRESS}"

    def mark(self, name: str, i: int, j: int) -> None:
        self.fs.pipe_file(f"{self.dir}/{name}.{i}.{j}", b"")

    def done(self) -> set[str]:
        """The marks there are, as ``NAME.I.J``, listed once."""
        self.fs.invalidate_cache()
        try:
            found = self.fs.find(self.dir)
        except FileNotFoundError:
            return set()
        return {str(f).rstrip("/").rsplit("/", 1)[-1] for f in found}

    def remove(self) -> None:
        with contextlib.suppress(FileNotFoundError):
            self.fs.rm(self.dir, recursive=True)
        self.fs.invalidate_cache()


def _write_chunks(dask: Any, group: Any, progress: FsPath | _RemoteMarks, ch: tuple[int, int],
                  lazy: Mapping[str, Any], scheduler: Any) -> None:
    """Compute and write every chunk not yet marked done, marking each after its data is written."""
    targets = {name: group[name] for name in lazy}
    remote = isinstance(progress, _RemoteMarks)

    def write_block(block: np.ndarray, name: str, i: int, j: int) -> int:
        r0, c0 = i * ch[0], j * ch[1]
        targets[name][r0:r0 + block.shape[0], c0:c0 + block.shape[1]] = block
        if isinstance(progress, _RemoteMarks):
            progress.mark(name, i, j)
        else:
            _mark_done(progress, name, i, j)
        return 1

    tasks = []
    write = dask.delayed(write_block, pure=False)
    done = progress.done() if isinstance(progress, _RemoteMarks) else (
        set(os.listdir(progress)) if progress.is_dir() else set())
    for name, a in lazy.items():
        blocks = a.to_delayed()  # one Delayed per chunk, sharing one graph
        for i in range(blocks.shape[0]):
            for j in range(blocks.shape[1]):
                mark = f"{name}.{i}.{j}" if remote else _done_mark(progress, name, i, j).name  # type: ignore[arg-type]
                if mark not in done:
                    tasks.append(write(blocks[i, j], name, i, j))
    if tasks:
        kw = {"scheduler": scheduler} if isinstance(scheduler, str) else {"scheduler": scheduler.get}
        dask.compute(*tasks, **kw)


def _write_remote(zarr: Any, dask: Any, da: Any, url: str, arrays: Mapping[str, Any], grid: Grid, kind: str,
                  attrs: Mapping[str, Any] | None, chunks: int | tuple[int, int] | None, resume_key: str,
                  scheduler: Any, diagonals: Any) -> None:
    """write_store at a URL: in place under the final name (an object store renames nothing atomically),
    ``gridfield_partial`` and the ``.progress/`` marks standing for the local ``.partial`` until the end."""
    _, ch, lazy = _check_write(url, arrays, grid, kind, chunks, da, remote=True)
    if diagonals is not None:
        lazy[DIAGONALS] = _check_diagonals(diagonals, grid, ch, da)
    fs, root = url_fs(url)
    root = root.rstrip("/")
    marks = _RemoteMarks(fs, root)
    meta = _metadata(grid, kind, ch, attrs)
    shown = redact(url)
    started = {"resume_key": resume_key, "meta": dict(meta), "arrays": sorted(lazy)}
    if fs.exists(f"{root}/zarr.json"):
        old = dict(zarr.open_group(url, mode="r").attrs)
        if _MARK in old:
            raise GridfieldError(f"{shown}: already exists; remove it or choose another --out")
        if "gridfield_partial" not in old:
            raise GridfieldError(f"{shown}: already exists and is not a gridfield store; choose another --out")
        if old["gridfield_partial"] != json.loads(json.dumps(started)):
            raise GridfieldError(f"{shown}: holds an interrupted run with other arguments; remove it to start over")
        group = zarr.open_group(url, mode="a")
    else:
        group = zarr.open_group(url, mode="w")
        for name, a in lazy.items():
            group.create_array(name, shape=tuple(a.shape), chunks=ch, dtype=STORE_ARRAYS.get(name, "uint8"),
                               fill_value=False if name == "occupied" else 0)
        group.attrs["gridfield_partial"] = started
    _write_chunks(dask, group, marks, ch, lazy, scheduler)
    occ_cells = _count(lazy["occupied"], scheduler)
    done = {k: v for k, v in dict(group.attrs).items() if k != "gridfield_partial"}
    group.attrs.put({**done, _MARK: {**meta, "occupied_cells": occ_cells}})  # one write: complete
    marks.remove()


def _publish(partial: FsPath, out: FsPath) -> None:
    """The rename that makes a complete store appear under its name (atomic on one file system)."""
    os.replace(partial, out)


def _count(occ: Any, scheduler: Any) -> int:
    import dask.array as da  # write_store checked that dask is there (the [dask] extra)

    n = da.count_nonzero(occ)
    kw = {"scheduler": scheduler} if isinstance(scheduler, str) else {"scheduler": scheduler.get}
    return int(n.compute(**kw))


def _metadata(grid: Grid, kind: str, ch: tuple[int, int], attrs: Mapping[str, Any] | None) -> dict[str, Any]:
    meta: dict[str, Any] = {
        "format": FORMAT, "version": __version__, "kind": kind, "shape": list(grid.shape),
        "resolution": grid.resolution, "origin": list(grid.origin), "border": grid.border, "chunks": list(ch),
    }
    extra = dict(attrs or {})
    if "params" in extra:  # resolved parameters may hold inf or None: kept as JSON text
        extra["params"] = json.dumps(extra["params"], default=_json_default)
    if "goal" in extra:
        extra["goal"] = [float(v) for v in extra["goal"]]
    meta.update(extra)
    plain: dict[str, Any] = json.loads(json.dumps(meta, default=_json_default))
    return plain


def _json_default(v: Any) -> Any:
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, tuple | np.ndarray):
        return list(v)
    raise TypeError(f"not JSON: {type(v).__name__}")


# ---------------------------------------------------------------------------------------------
# reading
# ---------------------------------------------------------------------------------------------
def read_store(path: PathLike, *, cache_bytes: int = DEFAULT_BUDGET) -> Any:
    """Read a gridfield Zarr store as lazy results: a map, a distance map or a field.

    Parameters
    ----------
    path : str or path-like
        A store written by :func:`write_store` (``gridfield brushfire/field ... --out F.zarr``), a directory
        or a URL (``s3://bucket/f.zarr``).
    cache_bytes : int
        The byte budget of the chunk cache the arrays share.

    Returns
    -------
    LazyGridMap, DistanceMap or Field
        By the store's ``kind``; every array is a :class:`~gridfield.core.chunkcache.LazyArray`.
        A distance map has ``steps``, ``label`` and ``gvd`` None. The map's ``diagonals`` are those the
        store holds (a LazyArray, read whole by ``to_gridmap()``), else None.

    Raises
    ------
    MapFormatError
        Not a Zarr directory, no gridfield metadata, an unknown format version, missing arrays, or a
        ``diagonals`` array that is not uint8 of the grid's block shape ``(rows - 1, cols - 1)``.

    Examples
    --------
    >>> import tempfile, numpy as np
    >>> from gridfield.core.grid import Grid
    >>> d = tempfile.mkdtemp()
    >>> occ = np.zeros((4, 4), bool); occ[0, 0] = True
    >>> dist = np.hypot(*np.indices((4, 4)))
    >>> p = write_store(f"{d}/d.zarr", {"occupied": occ, "distance": dist}, Grid((4, 4), 1.0), kind="distance",
    ...                 attrs={"metric": "euclidean"}, chunks=2)
    >>> dm = read_store(p)
    >>> type(dm).__name__, dm.metric, float(dm.distance[3, 3]) == float(np.hypot(3, 3))
    ('DistanceMap', 'euclidean', True)
    """
    zarr = _zarr()
    p = _place(path)
    with store_errors(str(p)):
        node, meta = _open_store(zarr, p)
    grid, kind = _store_grid(p, meta)
    need = {"map": ["occupied"], "distance": ["occupied", "distance"], "field": ["occupied", "U", "dUdx", "dUdy"]}
    if kind not in need:
        raise MapFormatError(f"{p}: unknown store kind {shorten(kind)}")
    names = set(node.array_keys())
    missing = [n for n in need[kind] if n not in names]
    if missing:
        raise MapFormatError(f"{p}: a {kind} store without the array{'s' if len(missing) > 1 else ''} "
                             f"{', '.join(missing)}")
    cache = ChunkCache(cache_bytes)

    def lazy(name: str, **kw: Any) -> Any:  # a LazyArray standing in for the result types' ndarrays
        a = node[name]
        if tuple(a.shape) != grid.shape:
            raise MapFormatError(f"{p}: array {name} has shape {tuple(a.shape)}, the grid {grid.shape}")
        return LazyArray(a, cache=cache, name=name, **kw)

    gm = LazyGridMap(grid, lazy("occupied", nonzero=meta.get("occupied_cells")), source=f"{p}",
                     meta={"store": dict(meta), "format": "store", "occupancy_rule": STORE_RULE},
                     diagonals=_stored_diagonals(p, node, names, grid, cache))
    if kind == "map":
        return gm
    dmap = None
    if "distance" in names:
        sat = meta.get("saturate")
        dmap = DistanceMap(gm, 8, meta.get("metric", "euclidean"), None, lazy("distance"),
                           lazy("nearest_row") if "nearest_row" in names else None,
                           lazy("nearest_col") if "nearest_col" in names else None, None, None,
                           saturate=None if sat is None else float(sat))
    if kind == "distance":
        return dmap
    params = json.loads(meta["params"]) if isinstance(meta.get("params"), str) else {}
    goal = meta.get("goal")
    if goal is None:
        raise MapFormatError(f"{p}: a field store without a goal")
    return Field(gm, lazy("U"), lazy("dUdx"), lazy("dUdy"), (goal[0], goal[1]), params, dmap)


def _stored_diagonals(p: FsPath, node: Any, names: set[str], grid: Any, cache: ChunkCache) -> Any:
    """The store's ``diagonals`` as a LazyArray (None when it has none), its shape and dtype checked."""
    if DIAGONALS not in names:
        return None
    a = node[DIAGONALS]
    want = (max(grid.rows - 1, 0), max(grid.cols - 1, 0))
    if tuple(a.shape) != want or np.dtype(a.dtype) != np.uint8:
        raise MapFormatError(f"{p}: array 'diagonals' must be a uint8 array of shape {want} (one entry per 2x2 "
                             f"block of the grid's {grid.rows}x{grid.cols} cells), got dtype {np.dtype(a.dtype)} "
                             f"and shape {tuple(a.shape)}")
    return LazyArray(a, cache=cache, name=DIAGONALS)


class _Url(str):
    """A store's URL, shown without its credentials (``str()`` is the URL itself, for opening it)."""

    __slots__ = ()

    def __format__(self, spec: str) -> str:
        return redact(str.__str__(self))

    @property
    def name(self) -> str:
        return self.rstrip("/").rsplit("/", 1)[-1]


def _place(path: PathLike) -> Any:
    """A local path as a ``pathlib.Path``, a URL as :class:`_Url` (its messages redacted)."""
    path = local_path(path)
    return _Url(path) if is_url(path) else FsPath(path)


def _open_store(zarr: Any, p: Any) -> tuple[Any, dict[str, Any]]:
    """The store's root group and its gridfield metadata, or a MapFormatError saying what is not there."""
    if isinstance(p, _Url):
        if not is_store(p):
            raise MapFormatError(f"{p}: no such store (no zarr.json there)")
    else:
        partial = p.with_name(p.name + ".partial")
        if not p.exists():
            hint = f" ({partial} is an interrupted write: re-run the command to resume it)" if partial.exists() else ""
            raise MapFormatError(f"{p}: no such store{hint}")
        if not is_store(p):
            raise MapFormatError(f"{p}: not a Zarr store (no zarr.json)")
    try:
        node = zarr.open(str(p), mode="r")
    except Exception as e:
        raise MapFormatError(f"{p}: cannot open as a Zarr store: {shorten(redact(e))}") from None
    if not isinstance(node, zarr.Group):
        raise MapFormatError(f"{p}: a Zarr array, not a gridfield store; read it with "
                             "gridfield.io.read(path, resolution=...) as an occupancy raster")
    meta = dict(node.attrs).get(_MARK)
    if not isinstance(meta, dict) and "gridfield_partial" in node.attrs:
        raise MapFormatError(f"{p}: an interrupted write (not every chunk is there): re-run the command that "
                             "wrote it to resume it")
    if not isinstance(meta, dict):
        raise MapFormatError(f"{p}: a Zarr store without gridfield grid metadata (no {_MARK!r} attribute in its "
                             "root group); gridfield writes stores with gridfield.io.write_store or --out F.zarr")
    if meta.get("format") != FORMAT:
        raise MapFormatError(f"{p}: gridfield store format {shorten(meta.get('format'))}; this gridfield reads "
                             f"format {FORMAT}")
    return node, meta


def _store_grid(p: FsPath, meta: Mapping[str, Any]) -> tuple[Any, Any]:
    """The (lazy) grid and the kind the metadata describe."""
    try:
        grid = lazy_grid(tuple(meta["shape"]), meta["resolution"], tuple(meta["origin"]), meta["border"])
        kind = meta["kind"]
    except (KeyError, TypeError) as e:
        raise MapFormatError(f"{p}: gridfield metadata lacks {shorten(str(e))}") from None
    except GridfieldError as e:
        raise MapFormatError(f"{p}: gridfield metadata: {e}") from None
    return grid, kind


def chunk_counter(obj: Any) -> Callable[[], int]:
    """``n()`` -> the number of chunk tiles decoded so far by the cache behind a result of
    :func:`read_store` (for reports and tests)."""
    gm = getattr(obj, "map", obj)
    cache = gm.occupied.cache
    return lambda: cache.reads


def read_zarr_array(path: PathLike, *, resolution: float = 1.0, origin: Any = (0.0, 0.0),
                    border: str = "open", occupancy: Literal["dark", "nonzero"] = "nonzero", threshold: float = 0.5,
                    negate: bool = False) -> LazyGridMap:
    """Read a plain 2-D Zarr array (not a gridfield store) as a lazy occupancy map; row 0 = lowest y, read
    by its own chunks. An array, like a ``.npy`` (:func:`read_npy`): non-zero = obstacle by default,
    ``occupancy="dark"`` for unsigned grey levels (0 = black = obstacle).

    Parameters
    ----------
    path : str or path-like
        A Zarr array directory.
    resolution : float
    origin : (x, y)
    border : {"open", "wall"}
    occupancy : {"nonzero", "dark"}
        ``"nonzero"`` (default): booleans as they are, numbers non-zero = obstacle; ``"dark"``: grey levels.
    threshold : float in [0, 1]
        Occupancy above which a value is an obstacle (``"dark"`` only).
    negate : bool
        White is occupied (``"dark"`` only).

    Returns
    -------
    LazyGridMap
        ``meta`` holds ``format="zarr_array"`` and ``occupancy_rule``.

    Examples
    --------
    >>> import tempfile, numpy as np, zarr
    >>> d = tempfile.mkdtemp() + "/occ.zarr"
    >>> z = zarr.open_array(d, mode="w", shape=(4, 4), chunks=(2, 2), dtype="uint8")
    >>> z[1, 2] = 1
    >>> m = read_zarr_array(d, resolution=0.5)
    >>> bool(m.occupied[1, 2]), m.occupied.chunks, m.meta["occupancy_rule"]
    (True, (2, 2), 'non-zero = obstacle')
    """
    rule_name, thr, neg = check_grey_options(occupancy, threshold, negate, path)
    zarr = _zarr()
    p = _place(path)
    try:
        with store_errors(str(p)):
            z = zarr.open_array(str(p), mode="r")
    except GridfieldError:
        raise
    except Exception as e:
        raise MapFormatError(f"{p}: not a readable Zarr array: {shorten(redact(e))}") from None
    if z.ndim != 2 or z.dtype.kind not in "biuf":
        raise MapFormatError(f"{p}: expected a 2-D array of booleans or numbers, got shape {z.shape}, dtype {z.dtype}")
    rule = raster_rule(p, z.dtype, rule_name, thr, neg, image=False)
    try:
        grid = lazy_grid(tuple(z.shape), resolution, tuple(origin), border)
    except GridfieldError as e:
        raise type(e)(f"{p}: {e}") from None
    return LazyGridMap(grid, LazyArray(Raster(z, rule=rule), name="occupied"), source=f"{p}",
                       meta={"format": "zarr_array", "occupancy_rule": rule.text})


def read_zarr(path: PathLike, **options: Any) -> Any:
    """A Zarr directory: a gridfield store (:func:`read_store`; it takes ``cache_bytes`` only) or a plain
    2-D array (:func:`read_zarr_array`).

    Parameters
    ----------
    path : str or path-like
        The Zarr directory.
    **options
        ``cache_bytes`` for a store; ``resolution``, ``origin``, ``border``, ``occupancy``, ``threshold``,
        ``negate`` for a plain array.

    Returns
    -------
    LazyGridMap, DistanceMap or Field
        What :func:`read_store` or :func:`read_zarr_array` returns.

    Examples
    --------
    >>> read_zarr("no/such.zarr")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.MapFormatError: no/such.zarr: no such store
    """
    zarr = _zarr()
    p = _place(path)
    if not is_store(p):
        return read_store(p, **options)  # its error names what is missing
    try:
        with store_errors(str(p)):
            node = zarr.open(str(p), mode="r")
    except GridfieldError:
        raise
    except Exception as e:
        raise MapFormatError(f"{p}: cannot open as a Zarr store: {shorten(redact(e))}") from None
    if isinstance(node, zarr.Array):
        return read_zarr_array(p, **options)
    bad = sorted(set(options) - {"cache_bytes"})
    if bad:
        raise ParameterError(f"{p}: option{'s' if len(bad) > 1 else ''} {', '.join(bad)} "
                             f"{'do' if len(bad) > 1 else 'does'} not apply to a gridfield store (its grid is stored)")
    return read_store(p, **options)
