"""gridfield's ``.npz`` files: named grid arrays with their grid geometry, and whole fields.

Every array is sized from its ``.npy`` header (and checked against the size guard) before it is
loaded, and no file stays open. :func:`save_field` and :func:`load_field` store a
:class:`~gridfield.fields.potential.Field` (with its distance map) in the same format; they live here, with
the other ``.npz`` I/O, and :mod:`gridfield.fields.potential` re-exports them. ``potential`` imports this
package, never the reverse: ``Field`` and ``DistanceMap`` come from the leaf :mod:`gridfield.core.results`
(imported when :func:`load_field` runs).
"""

from __future__ import annotations

import json
import math
import zipfile
from collections.abc import Mapping
from pathlib import Path as FsPath
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ..core.errors import GridfieldError, MapFormatError, ParameterError, shorten
from ..core.grid import Grid, GridMap
from ..core.limits import check_cells
from ._common import PathLike, _check_file

if TYPE_CHECKING:
    from ..core.results import Field


#: Array names gridfield gives to the fields an ``.npz`` file may hold (others are allowed too).
NPZ_ARRAY_NAMES = ("occupied", "steps", "distance", "label", "gvd", "potential", "grad_x", "grad_y")
_NPZ_RESERVED = ("resolution", "origin", "border")
#: The entry holding a map's :attr:`GridMap.diagonals <gridfield.core.grid.GridMap.diagonals>`: one per 2x2 block
#: of cells, shape ``(rows - 1, cols - 1)``, not the grid's shape (written by ``diagonals=``).
_DIAGONALS = "diagonals"


def _block_shape(grid: Grid) -> tuple[int, int]:
    """The shape of a grid's 2x2 blocks, that of :attr:`GridMap.diagonals`."""
    return max(grid.rows - 1, 0), max(grid.cols - 1, 0)


def _diagonals_to_write(diagonals: Any, grid: Grid) -> NDArray[np.uint8]:
    """``diagonals=`` of the writers, checked as :class:`GridMap` checks it, as uint8."""
    d = np.asarray(diagonals)
    if d.shape != _block_shape(grid):
        raise ParameterError(f"diagonals has shape {d.shape}, but the grid's 2x2 blocks have shape "
                             f"{_block_shape(grid)}")
    if d.size and (not np.issubdtype(d.dtype, np.integer) or int(d.min()) < 0 or int(d.max()) > 3):
        raise ParameterError("diagonals must hold the bits 0 and 1 (values 0 to 3) of a uint8 array")
    return np.ascontiguousarray(d, dtype=np.uint8)


def _stored_diagonals(p: PathLike, d: NDArray[Any] | None, grid: Grid) -> NDArray[np.uint8] | None:
    """A file's ``diagonals`` entry checked against its grid (a :class:`MapFormatError` naming the file)."""
    if d is None:
        return None
    if d.dtype != np.uint8 or d.shape != _block_shape(grid):
        raise MapFormatError(
            f"{p}: array 'diagonals' must be a uint8 array of shape {_block_shape(grid)} (one entry per 2x2 block "
            f"of the grid's {grid.rows}x{grid.cols} cells), got dtype {d.dtype} and shape {d.shape}"
        )
    if d.size and int(d.max()) > 3:
        raise MapFormatError(f"{p}: array 'diagonals' must hold the bits 0 and 1 (values 0 to 3), found the value "
                             f"{int(d.max())}")
    return d


# ----------------------------------------------------------------------------------------
# .npz arrays
# ----------------------------------------------------------------------------------------
def write_npz(path: PathLike, arrays: Mapping[str, NDArray[Any]], grid: Grid, *,
              diagonals: NDArray[np.uint8] | None = None) -> FsPath:
    """Write named arrays and their grid geometry to an ``.npz`` file (compressed).

    The file holds each array under its name (gridfield's names: ``occupied``, ``steps``,
    ``distance``, ``label``, ``gvd``, ``potential``, ``grad_x``, ``grad_y``; others are
    allowed), plus ``resolution`` (scalar), ``origin`` ``[x, y]`` and ``border`` (a string),
    and ``diagonals`` when given. Every array must have the grid's shape (extra trailing axes
    are allowed). The file is written to ``path`` exactly (numpy's habit of appending ``.npz``
    is not followed).

    Parameters
    ----------
    path : str or path-like
        The file to write (replaced if it exists).
    arrays : mapping of str to array
        Each array under its name: an identifier other than ``resolution``, ``origin`` and ``border``;
        numeric or boolean, of the grid's shape (trailing axes allowed).
    grid : Grid
        The geometry stored beside the arrays.
    diagonals : ndarray of uint8, shape ``(rows - 1, cols - 1)``, optional
        The :attr:`GridMap.diagonals <gridfield.core.grid.GridMap.diagonals>` of the map whose ``occupied``
        is written (a disc robot's configuration space: the diagonals it fits along through a corner),
        stored as the array ``diagonals``; :func:`read_npz` gives the map back with them, so that the
        grid planners make the same moves on it. None (the default): none stored.

    Returns
    -------
    pathlib.Path
        ``path``.

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
        if name == _DIAGONALS:
            raise ParameterError("a map's diagonals (one entry per 2x2 block of cells) are written with "
                                 "write_npz(..., diagonals=gridmap.diagonals), not among the grid-shaped arrays")
        if not isinstance(name, str) or not name.isidentifier() or name in _NPZ_RESERVED:
            raise ParameterError(
                f"array name {shorten(name)} is not allowed; use an identifier other than {', '.join(_NPZ_RESERVED)}"
            )
        a = np.asarray(value)
        if a.dtype == object:
            raise ParameterError(f"array {shorten(name)} has dtype object; only numeric and boolean arrays can be stored")
        if a.shape[:grid.ndim] != grid.shape:
            raise ParameterError(f"array {shorten(name)} has shape {a.shape}, but the grid has shape {grid.shape}")
        out[name] = a
    if not out:
        raise ParameterError("write_npz needs at least one array")
    if diagonals is not None:
        out[_DIAGONALS] = _diagonals_to_write(diagonals, grid)
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

    Raises :class:`MapFormatError` (or :class:`~gridfield.core.errors.SizeLimitError`) for anything
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
    :func:`save_field` adds) are returned too but do not set the grid's shape.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    arrays : dict of str to ndarray
        Every entry but the geometry (``resolution``, ``origin``, ``border``), by name; ``diagonals``,
        when the file holds it, is of the grid's block shape ``(rows - 1, cols - 1)`` (checked).
    grid : Grid
        Of the arrays' common shape (that of ``occupied`` when present), with the stored resolution,
        origin and border (``"open"`` when absent).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     f = write_npz(pathlib.Path(d) / "d.npz", {"distance": np.arange(6.0).reshape(2, 3)}, Grid((2, 3), 0.5))
    ...     arrays, grid = read_npz_arrays(f)
    >>> arrays["distance"].tolist(), grid.shape, grid.resolution
    ([[0.0, 1.0, 2.0], [3.0, 4.0, 5.0]], (2, 3), 0.5)
    """
    content = _npz_content(path)
    p = FsPath(path)
    if content.get("occupied", np.zeros(())).ndim == 3 and np.size(content.get("origin", ())) == 3:  # voxels (issue 44)
        from ._voxel import npz_voxel_arrays
        return npz_voxel_arrays(p, content)
    for key in ("resolution", "origin"):
        if key not in content:
            raise MapFormatError(f"{p}: no '{key}' array; a gridfield .npz holds resolution and origin beside the arrays")
    try:
        res = float(np.asarray(content.pop("resolution")).reshape(()))
        origin = np.asarray(content.pop("origin"), dtype=np.float64).reshape(2)
        border = str(np.asarray(content.pop("border", "open")).reshape(()))
    except (TypeError, ValueError) as e:
        raise MapFormatError(f"{p}: bad resolution, origin or border entry ({e})") from None
    # Grid-shaped arrays share one shape; 0-d/1-d entries (a goal, parameters as JSON) are metadata; the
    # diagonals (one per 2x2 block) are checked against the grid once it is known.
    shapes = {k: a.shape[:2] for k, a in content.items() if a.ndim >= 2 and k != _DIAGONALS}
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
    _stored_diagonals(p, content.get(_DIAGONALS), grid)
    return content, grid


#: The occupancy rule of a gridfield ``.npz`` map, in words (``meta["occupancy_rule"]``).
NPZ_RULE = "the file's occupied array (True or 1 = obstacle)"


def read_npz(path: PathLike) -> GridMap:
    """Read the occupancy grid (array ``occupied``) of a gridfield ``.npz`` file.

    Parameters
    ----------
    path : str or path-like
        An ``.npz`` written by :func:`write_npz` with an ``occupied`` array (booleans, or 0/1).

    Returns
    -------
    GridMap
        ``meta`` holds ``format="npz"`` and the names of the file's arrays; :attr:`~GridMap.diagonals`
        those the file holds (written by ``write_npz(..., diagonals=)``), else None.

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
    meta = {"format": "npz", "arrays": sorted(arrays), "occupancy_rule": NPZ_RULE}
    return GridMap(grid, occ, source=str(path), meta=meta, diagonals=arrays.get(_DIAGONALS))


# ----------------------------------------------------------------------------------------------
# fields (gridfield.fields.potential.Field): save_field / load_field
# ----------------------------------------------------------------------------------------------
_DMAP_ARRAYS = ("steps", "distance", "nearest_row", "nearest_col", "label", "gvd")


def _json_value(v: Any) -> Any:
    """numpy scalars (and anything else json does not know) as plain values."""
    return v.item() if isinstance(v, np.generic) else str(v)


def save_field(path: PathLike, field: Field) -> None:
    """Write a :class:`Field` to an ``.npz`` file that :func:`load_field` reads back.

    The file holds gridfield's arrays by name (``occupied``, ``potential``, ``grad_x``, ``grad_y``,
    and when the field has a distance map ``steps``, ``distance``, ``label``, ``gvd``,
    ``nearest_row``, ``nearest_col``), plus ``resolution``, ``origin``, ``border``, ``goal`` and
    ``params`` (a JSON string; ``inf`` is written as ``Infinity``), and the map's ``obstacle_id`` and
    ``diagonals`` when it has them.

    Parameters
    ----------
    path : str or path-like
        The file to write (replaced if it exists; written to exactly this name).
    field : Field
        A field of :mod:`gridfield.fields.potential` (e.g. from :func:`~gridfield.fields.potential.build_field`).

    Returns
    -------
    None

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from gridfield.fields.potential import build_field
    >>> occ = np.zeros((3, 3), bool); occ[1, 1] = True
    >>> f = build_field(GridMap(Grid((3, 3), 1.0), occ), (0.5, 0.5))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     save_field(pathlib.Path(d) / "f.npz", f)
    ...     g = load_field(pathlib.Path(d) / "f.npz")
    >>> np.array_equal(g.potential, f.potential), g.goal, g.params == f.params
    (True, (0.5, 0.5), True)
    """
    grid = field.grid
    arrays: dict[str, Any] = {"occupied": field.map.occupied, "potential": field.potential,
                              "grad_x": field.grad_x, "grad_y": field.grad_y}
    meta: dict[str, Any] = {}
    if field.distance is not None:
        d = field.distance
        arrays.update({k: getattr(d, k) for k in _DMAP_ARRAYS if getattr(d, k) is not None})
        meta = {"connectivity": d.connectivity, "metric": d.metric, "saturate": d.saturate, "far": d.far}
    if field.map.obstacle_id is not None:
        arrays["obstacle_id"] = field.map.obstacle_id
    if field.map.diagonals is not None:
        arrays[_DIAGONALS] = _diagonals_to_write(field.map.diagonals, grid)
    try:
        with open(path, "wb") as fh:
            np.savez_compressed(
                fh, **arrays, resolution=np.float64(grid.resolution), origin=np.asarray(grid.origin, np.float64),
                border=np.asarray(grid.border), goal=np.asarray(field.goal, np.float64),
                params=np.asarray(json.dumps(field.params, default=_json_value)), distance_meta=np.asarray(json.dumps(meta)),
            )
    except OSError as e:
        raise GridfieldError(f"{path}: cannot write: {e.strerror or e}") from None


def load_field(path: PathLike) -> Field:
    """Read a :class:`Field` written by :func:`save_field` (see there for an example).

    Every array is sized from its header before it is loaded; a file that is not such a field file
    raises :class:`~gridfield.core.errors.MapFormatError` naming what is missing or damaged.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    Field
        With the stored map (occupancy, obstacle ids and diagonals), arrays, goal and parameters, and its
        distance map when one was saved.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from gridfield.fields.potential import build_field
    >>> f = build_field(GridMap(Grid((2, 4), 0.5), np.zeros((2, 4), bool)), (0.25, 0.25))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     save_field(pathlib.Path(d) / "f.npz", f)
    ...     g = load_field(pathlib.Path(d) / "f.npz")
    >>> g.grid == f.grid, np.array_equal(g.grad_x, f.grad_x), np.array_equal(g.distance.distance, f.distance.distance)
    (True, True, True)
    """
    from ..core.errors import SizeLimitError
    from ..core.results import DistanceMap, Field

    content = _npz_content(path)  # issue 17: every array sized from its header first; no file left open
    missing = [k for k in ("occupied", "potential", "grad_x", "grad_y", "resolution", "origin", "goal", "params")
               if k not in content]
    if missing:
        raise MapFormatError(f"{path}: not a field file written by save_field (missing {', '.join(missing)})")
    try:
        origin = content["origin"].astype(np.float64).reshape(2)
        grid = Grid(content["occupied"].shape, float(content["resolution"]), (float(origin[0]), float(origin[1])),
                    str(content.get("border", "open")))  # type: ignore[arg-type]
        params = json.loads(str(content["params"]))
        meta = json.loads(str(content.get("distance_meta", "{}")))
        goal = content["goal"].astype(np.float64).reshape(2)
        gridmap = GridMap(grid, content["occupied"], content.get("obstacle_id"), source=str(path),
                          diagonals=_stored_diagonals(path, content.get(_DIAGONALS), grid))
        dmap = None
        if meta and "distance" in content:  # steps, labels, GVD, nearest: optional
            dmap = DistanceMap(gridmap, int(meta["connectivity"]), str(meta["metric"]), content.get("steps"),
                               content["distance"], content.get("nearest_row"), content.get("nearest_col"),
                               content.get("label"), content.get("gvd"), meta.get("saturate"),
                               float(meta.get("far", math.inf)))
        return Field(gridmap, content["potential"], content["grad_x"], content["grad_y"], (goal[0], goal[1]), params,
                     dmap)
    except (SizeLimitError, MapFormatError):  # the latter names the file and the entry already
        raise
    except (ValueError, TypeError, KeyError, IndexError, AttributeError) as e:  # ParameterError included
        raise MapFormatError(f"{path}: damaged field file ({type(e).__name__}: {e})") from None
