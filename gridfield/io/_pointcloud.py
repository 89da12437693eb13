"""Point clouds voxelized at a resolution: PLY (ASCII, binary little and big endian; the ``vertex`` element's
``x y z``) and ASCII ``.xyz`` (``x y z`` per line, further columns ignored, ``#`` comments).

Both are parsed here with numpy (no PLY library needed): the PLY header names the vertex properties and
their types, a binary body is read as one structured array. Every voxel holding at least one point is
occupied (:func:`voxelize_points`).
"""

from __future__ import annotations

from pathlib import Path as FsPath
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.errors import MapFormatError, ParameterError, shorten
from ..core.grid import BORDERS, Grid, GridMap, check_resolution
from ..core.limits import check_cells
from ._common import PathLike, _check_file, _choice, _decode_text, _read_bytes

__all__ = ["POINTCLOUD_RULE", "read_pointcloud", "voxelize_points"]

#: The occupancy rule of a voxelized point cloud, in words (``meta["occupancy_rule"]``).
POINTCLOUD_RULE = "a voxel holding at least one point is an obstacle"
#: The formats :func:`read_pointcloud` reads, by suffix.
POINTCLOUD_SUFFIXES = (".ply", ".xyz")

_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
              "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
              "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}
_PLY_FORMATS = {"ascii": "", "binary_little_endian": "<", "binary_big_endian": ">"}
_PLY_HEADER_MAX = 1 << 16


def voxelize_points(points: ArrayLike, resolution: float, *, margin: int = 1, border: Literal["open", "wall"] = "open",
                    what: str = "point cloud") -> tuple[Grid, NDArray[np.bool_]]:
    """The voxel grid covering ``points`` at ``resolution`` and its occupancy: a voxel holding a point is occupied.

    The grid's lowest corner is the points' minimum less ``margin`` voxels on every axis, and it reaches
    ``margin`` voxels beyond the voxel of their maximum, so that free space surrounds the cloud (``margin=0``:
    the bounding box alone). A point on a voxel face belongs to the voxel above it (``floor``).

    Parameters
    ----------
    points : array_like, shape (N, 3)
        World points ``(x, y, z)``, finite, at least one.
    resolution : float
        The voxel edge length.
    margin : int
        Free voxels added around the points' bounding box on every side (default 1).
    border : {"open", "wall"}
    what : str
        For the messages (the file name).

    Returns
    -------
    grid : Grid
    occupied : ndarray of bool, shape ``grid.shape`` (``[z, y, x]``)

    Examples
    --------
    >>> grid, occ = voxelize_points([[0.0, 0.0, 0.0], [1.0, 0.25, 0.0]], 0.5)
    >>> grid.shape, grid.origin, np.argwhere(occ).tolist()
    ((3, 3, 5), (-0.5, -0.5, -0.5), [[1, 1, 1], [1, 1, 3]])
    """
    res = check_resolution(resolution)
    if isinstance(margin, bool) or not isinstance(margin, int | np.integer) or margin < 0:
        raise ParameterError(f"margin must be a non-negative integer (voxels), got {shorten(margin)}")
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 3 or not pts.shape[0]:
        raise MapFormatError(f"{what}: expected at least one point (x, y, z), got an array of shape {pts.shape}")
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    origin = lo - margin * res
    top = np.floor((hi - origin) / res)  # the voxel index of the highest point, per axis (x, y, z)
    sizes = top + 1 + margin
    check_cells(tuple(float(v) for v in sizes[::-1]), f"{what} at resolution {res:g} (extent "
                f"{' x '.join(f'{v:g}' for v in hi - lo)})")
    shape = tuple(int(v) for v in sizes[::-1])  # (layers, rows, cols)
    grid = Grid(shape, res, tuple(float(v) for v in origin), border)
    idx = np.floor((pts - origin) / res).astype(np.int64)
    np.clip(idx, 0, np.array(shape[::-1], dtype=np.int64) - 1, out=idx)  # rounding at the top face
    occupied = np.zeros(shape, dtype=bool)
    occupied[idx[:, 2], idx[:, 1], idx[:, 0]] = True
    return grid, occupied


def _float_rows(p: FsPath, rows: list[tuple[int, list[str]]], what: str) -> NDArray[np.float64]:
    """The first three fields of each ``(line number, fields)`` row as floats, finite; MapFormatError naming the line."""
    short = next(((n, f) for n, f in rows if len(f) < 3), None)
    if short is not None:
        raise MapFormatError(f"{p}: line {short[0]}: expected x y z (three numbers), got {len(short[1])} field"
                             f"{'s' if len(short[1]) != 1 else ''}")
    try:
        pts = np.array([f[:3] for _, f in rows], dtype=np.float64)
    except ValueError:
        for n, f in rows:  # the error path only: find the line
            for s in f[:3]:
                try:
                    float(s)
                except ValueError:
                    raise MapFormatError(f"{p}: line {n}: {what} coordinates must be numbers, got {shorten(s)}") from None
        raise  # pragma: no cover - numpy and float agree
    bad = ~np.isfinite(pts).all(axis=1)
    if bad.any():
        k = int(np.argmax(bad))
        raise MapFormatError(f"{p}: line {rows[k][0]}: point ({', '.join(rows[k][1][:3])}) is not finite")
    return pts.reshape(-1, 3)


def _xyz_points(p: FsPath) -> NDArray[np.float64]:
    text = _decode_text(p, _read_bytes(p), ".xyz point cloud")
    rows = []
    for i, ln in enumerate(text.split("\n")):  # one step per point (not per voxel)
        fields = ln.split("#", 1)[0].split()
        if fields:
            rows.append((i + 1, fields))
    if not rows:
        raise MapFormatError(f"{p}: no points in the file (lines 'x y z')")
    return _float_rows(p, rows, ".xyz")


def _ply_header(p: FsPath, data: bytes) -> tuple[str, int, list[tuple[str, int, list[tuple[str, str]]]], int]:
    """A PLY header: its format, the line the body starts on, its elements (name, count, properties) and the
    byte offset of the body."""
    end = data.find(b"end_header", 0, _PLY_HEADER_MAX)
    if not data.startswith(b"ply") or end < 0:
        raise MapFormatError(f"{p}: not a PLY file (it must start with 'ply' and have an 'end_header' line within "
                             f"{_PLY_HEADER_MAX} bytes)")
    nl = data.find(b"\n", end)
    offset = len(data) if nl < 0 else nl + 1
    lines = data[:offset].decode("ascii", "replace").split("\n")
    fmt = ""
    elements: list[tuple[str, int, list[tuple[str, str]]]] = []
    for i, raw in enumerate(lines[1:], start=2):
        parts = raw.split()
        if not parts or parts[0] in ("comment", "obj_info", "end_header"):
            continue
        if parts[0] == "format":
            if len(parts) != 3 or parts[1] not in _PLY_FORMATS:
                raise MapFormatError(f"{p}: line {i}: expected 'format ascii|binary_little_endian|binary_big_endian "
                                     f"1.0', got {shorten(raw.strip()[:60])}")
            fmt = parts[1]
        elif parts[0] == "element" and len(parts) == 3 and parts[2].isascii() and parts[2].isdigit() and len(
                parts[2]) <= 18:
            elements.append((parts[1], int(parts[2]), []))
        elif parts[0] == "property" and elements and len(parts) == 3 and parts[1] in _PLY_TYPES:
            elements[-1][2].append((parts[2], _PLY_TYPES[parts[1]]))
        elif parts[0] == "property" and elements and len(parts) == 5 and parts[1] == "list":
            elements[-1][2].append((parts[4], "list"))
        else:
            raise MapFormatError(f"{p}: line {i}: not a PLY header line: {shorten(raw.strip()[:60])}")
    if not fmt:
        raise MapFormatError(f"{p}: the PLY header has no 'format' line")
    return fmt, len(lines), elements, offset


def _ply_points(p: FsPath) -> NDArray[np.float64]:
    data = _read_bytes(p)
    fmt, body_line, elements, offset = _ply_header(p, data)
    names = [e[0] for e in elements]
    if "vertex" not in names:
        raise MapFormatError(f"{p}: the PLY header has no 'element vertex' (it has {', '.join(names) or 'none'})")
    k = names.index("vertex")
    _, count, props = elements[k]
    pnames = [n for n, _ in props]
    missing = [a for a in "xyz" if a not in pnames]
    if missing:
        raise MapFormatError(f"{p}: the PLY vertex element has no property {', '.join(missing)} "
                             f"(it has {', '.join(pnames) or 'none'})")
    if not count:
        raise MapFormatError(f"{p}: the PLY file has no vertices (element vertex 0)")
    before = elements[:k]
    if fmt == "ascii":
        text = data[offset:].decode("ascii", "replace").split("\n")
        skip = sum(e[1] for e in before)  # elements before the vertices: one line per item
        rows = [(body_line + i, ln.split()) for i, ln in enumerate(text) if ln.strip()][skip:skip + count]
        if len(rows) < count:
            raise MapFormatError(f"{p}: truncated PLY file: the header says {count} vertices, the file holds "
                                 f"{len(rows)}")
        cols = [pnames.index(a) for a in "xyz"]
        if any(t == "list" for _, t in props):
            raise MapFormatError(f"{p}: a PLY vertex element with list properties is not read")
        wrong = next(((n, f) for n, f in rows if len(f) != len(props)), None)
        if wrong is not None:
            raise MapFormatError(f"{p}: line {wrong[0]}: expected {len(props)} vertex values "
                                 f"({' '.join(pnames)}), got {len(wrong[1])}")
        return _float_rows(p, [(n, [f[c] for c in cols]) for n, f in rows], "PLY vertex")
    if any(t == "list" for e in [*before, elements[k]] for _, t in e[2]):
        raise MapFormatError(f"{p}: a binary PLY whose vertices follow or hold list properties is not read "
                             "(vertex-only files, or vertices first, are)")
    order = _PLY_FORMATS[fmt]
    skip_bytes = sum(e[1] * np.dtype([(n, order + t) for n, t in e[2]]).itemsize for e in before)
    dtype = np.dtype([(n, order + t) for n, t in props])
    need = offset + skip_bytes + count * dtype.itemsize
    if len(data) < need:
        raise MapFormatError(f"{p}: truncated PLY file: {count} vertices of {dtype.itemsize} bytes need {need} "
                             f"bytes, the file has {len(data)}")
    v = np.frombuffer(data, dtype=dtype, count=count, offset=offset + skip_bytes)
    pts = np.stack([v[a].astype(np.float64) for a in "xyz"], axis=1)
    bad = ~np.isfinite(pts).all(axis=1)
    if bad.any():
        raise MapFormatError(f"{p}: vertex {int(np.argmax(bad))} is not finite ({', '.join(map(str, pts[bad][0]))})")
    return pts


def read_pointcloud(path: PathLike, *, resolution: float | None = None, margin: int = 1,
                    border: Literal["open", "wall"] = "open") -> GridMap:
    """Read a point cloud (``.ply`` or ``.xyz``) voxelized at ``resolution``: a voxel holding a point is occupied.

    PLY: ASCII or binary (little or big endian), the ``vertex`` element's ``x``, ``y``, ``z`` properties (any
    numeric type; other properties and elements after the vertices ignored). ``.xyz``: one ``x y z`` per line,
    further columns ignored, ``#`` starts a comment. The grid covers the points' bounding box plus ``margin``
    voxels on every side (:func:`voxelize_points`); its size is checked against the size guard before it is
    allocated, so a resolution too fine for the cloud's extent is refused at once.

    Parameters
    ----------
    path : str or path-like
    resolution : float
        The voxel edge length: required (a point cloud has none; ``--resolution`` on the command line).
    margin : int
        Free voxels around the bounding box (default 1).
    border : {"open", "wall"}

    Returns
    -------
    GridMap
        ``meta`` holds ``format`` (``"ply"`` or ``"xyz"``), ``occupancy_rule`` and ``points`` (their number).

    Raises
    ------
    ParameterError
        No resolution.
    MapFormatError
        Naming the file (and line): a malformed header or line, a coordinate that is not a finite number, a
        truncated file, no points.
    SizeLimitError
        Too many voxels at that resolution.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "cloud.xyz"
    >>> _ = f.write_text("# x y z intensity\\n0 0 0 9\\n1.0 0.2 0.0 9\\n")
    >>> m = read_pointcloud(f, resolution=0.5)
    >>> m.shape, int(m.occupied.sum()), m.is_free([[1.1, 0.1, 0.1], [0.6, 0.1, 0.1]]).tolist()
    ((3, 3, 5), 2, [False, True])
    """
    _choice("border", border, BORDERS)
    p = _check_file(path)
    suffix = FsPath(p.stem).suffix.lower() if p.suffix.lower() == ".gz" else p.suffix.lower()
    if resolution is None:
        raise ParameterError(f"{p}: a point cloud needs a resolution (the voxel size): give resolution=R "
                             "(--resolution R)")
    res = check_resolution(resolution)
    if suffix == ".ply":
        pts = _ply_points(p)
    elif suffix == ".xyz":
        pts = _xyz_points(p)
    else:
        raise MapFormatError(f"{p}: not a point cloud file (.ply or .xyz)")
    grid, occupied = voxelize_points(pts, res, margin=margin, border=border, what=str(p))
    meta: dict[str, Any] = {"format": suffix[1:], "occupancy_rule": POINTCLOUD_RULE, "points": int(pts.shape[0])}
    return GridMap(grid, occupied, source=str(path), meta=meta)

