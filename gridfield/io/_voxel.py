"""Voxel maps (3-D occupancy grids): Moving AI's 3-D benchmark (``.3dmap`` and ``.3dscen``, gzip-compressed
too), Patrick Min's ``.binvox`` and 3-D arrays (``.npy``, gridfield ``.npz``).

Every reader returns a :class:`~gridfield.core.grid.GridMap` of a voxel grid: the array is indexed
``[z, y, x]`` (``[layer, row, col]``), index 0 the lowest coordinate on every axis, voxel centres at
``origin + (index + 0.5) * resolution`` (``ARCHITECTURE.md``, "Conventions"). The size a header announces
is checked against the size guard (:func:`gridfield.core.limits.check_cells`) before anything of that size
is allocated, and the bodies are parsed with numpy, never one Python step per voxel.

Point clouds (PLY, ``.xyz``) voxelized at a resolution are read by :mod:`gridfield.io._pointcloud`.
"""

from __future__ import annotations

import io
import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path as FsPath
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from ..core.errors import MapFormatError, ParameterError, SizeLimitError, shorten
from ..core.grid import BORDERS, Grid, GridMap
from ..core.limits import check_cells
from ._common import (
    PathLike,
    _check_file,
    _choice,
    _decode_text,
    _open_binary,
    _read_bytes,
    gz_limit,
    is_gzip,
    read_errors,
)
from ._movingai import Scenarios
from ._occupancy import check_grey_options, raster_rule

__all__ = ["BINVOX_RULE", "MOVINGAI3D_RULE", "Scenarios3D", "read_3dmap", "read_binvox", "read_scen3d",
           "read_voxel_npy"]

#: The occupancy rule of a Moving AI ``.3dmap`` in words (``meta["occupancy_rule"]``).
MOVINGAI3D_RULE = "every voxel listed in the file is blocked; the rest free"
#: The occupancy rule of a ``.binvox`` file in words.
BINVOX_RULE = "set voxels (a non-zero run value) are obstacles"

#: Longest header line read (a ``voxel W H D`` line, a binvox header line) before it is refused.
HEADER_LINE_MAX = 4096
#: Most decimal digits of one coordinate of a ``.3dmap`` (a larger number lies outside any map anyway).
_DIGITS_MAX = 18

_WS = np.zeros(256, dtype=bool)
_WS[[9, 10, 11, 12, 13, 32]] = True
_DIGIT = np.zeros(256, dtype=bool)
_DIGIT[48:58] = True


# ----------------------------------------------------------------------------------------
# a table of non-negative integers, parsed from bytes (the body of a .3dmap)
# ----------------------------------------------------------------------------------------
def _token_at(body: bytes, i: int) -> str:
    """The whitespace-delimited token of ``body`` holding byte ``i``, as text for a message."""
    start = i
    while start > 0 and not _WS[body[start - 1]] and i - start < 40:
        start -= 1
    end = i
    while end < len(body) and not _WS[body[end]] and end - i < 40:
        end += 1
    return shorten(body[start:end].decode("utf-8", "replace"))


def _int_table(p: FsPath, body: bytes, first_line: int, names: tuple[str, ...]) -> tuple[NDArray[np.int64],
                                                                                       NDArray[np.int64]]:
    """The non-blank lines of ``body`` (line ``first_line`` of the file first) as an ``(n, len(names))`` table
    of non-negative integers, and each row's line number; MapFormatError naming the line of a field that is not
    such an integer or of a line with another number of fields.

    Vectorized over the bytes: the digits' runs are the fields, their values are built digit position by digit
    position (at most :data:`_DIGITS_MAX` steps, each over all fields at once).
    """
    ncols = len(names)
    b = np.frombuffer(body, dtype=np.uint8)
    digit = _DIGIT[b]
    sep = _WS[b]
    plus = np.flatnonzero(b == 43)  # a '+' sign (as np.loadtxt takes it): after a separator, before a digit
    if plus.size:
        signed = plus[(plus + 1 < b.size) & _DIGIT[b[np.minimum(plus + 1, b.size - 1)]]
                      & ((plus == 0) | _WS[b[np.maximum(plus - 1, 0)]])]
        sep[signed] = True
    bad = ~(digit | sep)
    if bad.any():
        i = int(np.argmax(bad))
        line = first_line + body.count(b"\n", 0, i)
        raise MapFormatError(f"{p}: line {line}: coordinates must be non-negative integers, got {_token_at(body, i)}")
    if not digit.size:
        return np.zeros((0, ncols), dtype=np.int64), np.zeros(0, dtype=np.int64)
    edge = digit[1:] != digit[:-1]
    starts = np.flatnonzero(edge & digit[1:]) + 1
    ends = np.flatnonzero(edge & digit[:-1]) + 1
    if digit[0]:
        starts = np.concatenate(([0], starts))
    if digit[-1]:
        ends = np.concatenate((ends, [b.size]))
    del edge, digit, bad, sep
    if not starts.size:  # blank lines only
        return np.zeros((0, ncols), dtype=np.int64), np.zeros(0, dtype=np.int64)
    newlines = np.flatnonzero(b == 10)
    token_line = np.searchsorted(newlines, starts)  # 0-based line of the body
    del newlines
    change = np.flatnonzero(np.diff(token_line)) + 1
    first = np.concatenate(([0], change))
    counts = np.diff(np.concatenate((first, [token_line.size])))
    wrong = np.flatnonzero(counts != ncols)
    if wrong.size:
        k = int(first[wrong[0]])
        raise MapFormatError(f"{p}: line {first_line + int(token_line[k])}: expected {ncols} fields "
                             f"({' '.join(names)}), got {int(counts[wrong[0]])}")
    lengths = ends - starts
    width = int(lengths.max())
    if width > _DIGITS_MAX:
        k = int(np.argmax(lengths))
        raise MapFormatError(f"{p}: line {first_line + int(token_line[k])}: coordinate "
                             f"{_token_at(body, int(starts[k]))} is too large (more than {_DIGITS_MAX} digits)")
    values = np.zeros(starts.size, dtype=np.int64)
    for k in range(width):  # digit positions, right-aligned: a shorter field is padded with leading zeros
        at = ends - width + k
        d = b[np.maximum(at, 0)].astype(np.int64) - 48
        values = values * 10 + np.where(at >= starts, d, 0)
    return values.reshape(-1, ncols), token_line[::ncols] + first_line


#: Bytes of a ``.3dmap`` body parsed at a time (whole lines): the parse's memory is bounded by this, not by the
#: file (whose lines may repeat a voxel without end).
BLOCK_BYTES = 1 << 23


def _line_blocks(p: FsPath, offset: int, first_line: int) -> Iterator[tuple[bytes, int]]:
    """The bytes of ``p`` after its first ``offset`` in blocks of whole lines (about :data:`BLOCK_BYTES`
    each; a line longer than that is refused), each with the file's line number of its first line; a gzip file is
    decompressed as it goes, within :func:`~gridfield.io._common.gz_limit` bytes."""
    limit = gz_limit() if is_gzip(p) else None
    total = 0
    with read_errors(p), _open_binary(p) as f:
        if limit is None:
            f.seek(offset)
        else:
            f.read(offset)
        carry = b""
        while True:
            block = f.read(BLOCK_BYTES)
            total += len(block)
            if limit is not None and total > limit:
                raise SizeLimitError(f"{p}: decompresses to more than {limit} bytes, more than a map within the "
                                     "size guard holds (raise it with --max-cells or GRIDFIELD_MAX_CELLS)")
            data = carry + block
            cut = data.rfind(b"\n") + 1 if block else len(data)
            if not cut and len(data) > BLOCK_BYTES:
                raise MapFormatError(f"{p}: line {first_line}: longer than {BLOCK_BYTES} bytes; not a voxel line "
                                     "'x y z'")
            if cut:
                yield data[:cut], first_line
                first_line += data.count(b"\n", 0, cut)
            carry = data[cut:]
            if not block:
                return


def _loadtxt_block(chunk: bytes, ncols: int = 3) -> NDArray[np.int64] | None:
    """The whitespace-separated integers of ``chunk`` (whole lines) as an ``(n, ncols)`` table, by numpy's C
    parser (``np.loadtxt``; blank lines skipped), or None when it refuses them (a field that is no integer,
    lines of other lengths): :func:`_int_table` then finds what is wrong, naming the line."""
    if not chunk.strip():
        return np.zeros((0, ncols), dtype=np.int64)
    try:
        t = np.loadtxt(io.BytesIO(chunk), dtype=np.int64, ndmin=2, comments=None, encoding="latin-1")
    except (ValueError, OverflowError, TypeError):  # numpy's refusal of the text
        return None
    return t if t.shape[1:] == (ncols,) else None


def _header_line(p: FsPath, what: str) -> tuple[bytes, int, int]:
    """The first non-blank line of ``p`` (plain or gzip), and the bytes and lines it and the blank lines before
    it take, read at most :data:`HEADER_LINE_MAX` bytes at a time."""
    used = 0
    with read_errors(p), _open_binary(p) as f:
        for i in range(64):
            line = f.readline(HEADER_LINE_MAX + 1)
            if len(line) > HEADER_LINE_MAX:
                raise MapFormatError(f"{p}: line {i + 1}: longer than {HEADER_LINE_MAX} bytes; not a {what}")
            used += len(line)
            if not line:
                break
            if line.strip():
                return line, used, i + 1
    raise MapFormatError(f"{p}: empty file; a {what} starts with a header line")


# ----------------------------------------------------------------------------------------
# Moving AI 3-D: .3dmap
# ----------------------------------------------------------------------------------------
def _voxel_header(p: FsPath, line: bytes) -> tuple[int, int, int]:
    """``voxel W H D`` checked: three positive integers."""
    text = line.decode("utf-8", "replace").strip()
    parts = text.split()
    if len(parts) != 4 or parts[0].lower() != "voxel":
        raise MapFormatError(f"{p}: line 1: expected the header 'voxel W H D' (width, height, depth in voxels), "
                             f"got {shorten(text[:60])}")
    dims = []
    for name, v in zip(("width", "height", "depth"), parts[1:], strict=True):
        if not (v.isascii() and v.isdigit()) or len(v) > _DIGITS_MAX or int(v) <= 0:
            raise MapFormatError(f"{p}: line 1: the header's {name} must be a positive integer, got {shorten(v)}")
        dims.append(int(v))
    return dims[0], dims[1], dims[2]


def read_3dmap(path: PathLike, *, border: Literal["open", "wall"] = "wall") -> GridMap:
    """Read a Moving AI 3-D voxel benchmark map (``.3dmap``, or gzip-compressed ``.3dmap.gz``).

    The format (Brewer and Sturtevant 2018, the Warframe maps): a header line ``voxel W H D``, then one line
    ``x y z`` (0-based integers) per blocked voxel; every voxel not listed is free, a voxel listed twice is
    blocked once. No axis is flipped: voxel ``(x, y, z)`` is ``occupied[z, y, x]``, the grid has resolution 1
    and origin (0, 0, 0), so its centre is the world point ``(x + 0.5, y + 0.5, z + 0.5)``.

    The header's size is checked against the size guard before anything is allocated (a
    ``voxel 1000000000 1000000000 1000000000`` header is refused at once, naming its byte estimate), and the
    body is parsed in blocks of :data:`BLOCK_BYTES` (memory bounded whatever the file's length) by numpy's C
    text parser (``np.loadtxt``; millions of lines in a fraction of a second) and checked with numpy; a block it
    refuses is read again by a vectorized parser of its bytes, which names the line.

    Parameters
    ----------
    path : str or path-like
    border : {"open", "wall"}
        Default "wall": the benchmark's worlds are closed (a path never leaves the map).

    Returns
    -------
    GridMap
        A voxel grid ``(D, H, W)``; ``meta`` holds ``format="movingai3d"``, ``occupancy_rule`` and
        ``blocked_lines`` (the voxel lines read, duplicates included).

    Raises
    ------
    MapFormatError
        Naming the file and the line: a missing or malformed header, a field that is not a non-negative
        integer, a line without exactly three fields, a voxel outside the header's size.
    SizeLimitError
        A header's size beyond the size guard.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "tiny.3dmap"
    >>> _ = f.write_text("voxel 4 3 2\\n3 0 1\\n0 2 0\\n")
    >>> m = read_3dmap(f)
    >>> m.shape, m.grid.origin, bool(m.occupied[1, 0, 3]), int(m.occupied.sum())
    ((2, 3, 4), (0.0, 0.0, 0.0), True, 2)
    >>> m.is_free([[3.5, 0.5, 1.5], [3.5, 0.5, 0.5]]).tolist()
    [False, True]
    """
    _choice("border", border, BORDERS)
    p = _check_file(path)
    line, used, header_lines = _header_line(p, "Moving AI 3-D map")
    w, h, d = _voxel_header(p, line)
    check_cells((d, h, w), f"{p} (.3dmap header 'voxel {w} {h} {d}')")
    occupied = np.zeros((d, h, w), dtype=bool)
    size = (w, h, d)
    blocked = 0
    for chunk, first_line in _line_blocks(p, used, header_lines + 1):
        table = _loadtxt_block(chunk)
        if table is None or (table.size and (table.min() < 0 or (table.max(axis=0) >= size).any())):
            # refused by np.loadtxt, or a voxel outside: the numpy parser of the bytes names the line at fault
            table, lines = _int_table(p, chunk, first_line, ("x", "y", "z"))
            outside = (table >= size).any(axis=1)
            if outside.any():
                k = int(np.argmax(outside))
                x, y, z = (int(v) for v in table[k])
                raise MapFormatError(f"{p}: line {int(lines[k])}: voxel ({x}, {y}, {z}) lies outside the map's "
                                     f"{w} x {h} x {d} voxels (header 'voxel {w} {h} {d}': x < {w}, y < {h}, "
                                     f"z < {d})")
        occupied[table[:, 2], table[:, 1], table[:, 0]] = True
        blocked += int(table.shape[0])
    meta = {"format": "movingai3d", "occupancy_rule": MOVINGAI3D_RULE, "blocked_lines": blocked}
    return GridMap(Grid((d, h, w), 1.0, (0.0, 0.0, 0.0), border), occupied, source=str(path), meta=meta)


# ----------------------------------------------------------------------------------------
# Moving AI 3-D: .3dscen
# ----------------------------------------------------------------------------------------
def _empty3() -> NDArray[np.int64]:
    return np.zeros((0, 3), dtype=np.int64)


@dataclass(frozen=True, eq=False)
class Scenarios3D(Scenarios):
    """The scenarios of a Moving AI 3-D ``.3dscen`` file, one array entry per scenario.

    A :class:`~gridfield.io.Scenarios` whose points and cells have three coordinates: ``start_xy`` and
    ``goal_xy`` are the world points ``(x + 0.5, y + 0.5, z + 0.5)`` of the voxels (no axis flipped, as in
    :func:`read_3dmap`), ``start_cell`` and ``goal_cell`` the cells ``(layer, row, col) = (z, y, x)``. The
    file names no bucket nor map size: ``bucket`` is 0, ``width`` and ``height`` are those of ``shape``
    given to :func:`read_scen3d` (else 0), and :attr:`depth` likewise. ``no_path`` is
    ``optimal == 0`` with start != goal. :meth:`~gridfield.io.Scenarios.tolerance` applies to ``optimal``
    as printed.

    Attributes
    ----------
    start_voxel, goal_voxel : ndarray of int64, shape (N, 3)
        The file's voxel coordinates ``(x, y, z)``.
    ratio : ndarray of float64
        The file's last column: the optimal cost over the straight-line (3-D octile) estimate.
    depth : ndarray of int64
        The map depth (layers) of ``shape``, else 0.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "tiny.3dmap.3dscen"
    >>> _ = f.write_text("version 1\\ntiny.3dmap\\n0 0 0 2 1 1 2.41421 1.0\\n")
    >>> s = read_scen3d(f)
    >>> s, s.start_xy[0].tolist(), s.goal_cell[0].tolist(), float(s.optimal[0])
    (Scenarios3D(1 scenarios for 'tiny.3dmap', version '1'), [0.5, 0.5, 0.5], [1, 1, 2], 2.41421)
    """

    start_voxel: NDArray[np.int64] = field(default_factory=_empty3)
    goal_voxel: NDArray[np.int64] = field(default_factory=_empty3)
    ratio: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    depth: NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, dtype=np.int64))

    @property
    def start(self) -> NDArray[np.int64]:
        """The start voxels ``(x, y, z)``: :attr:`start_voxel`."""
        return self.start_voxel

    @property
    def goal(self) -> NDArray[np.int64]:
        """The goal voxels ``(x, y, z)``: :attr:`goal_voxel`."""
        return self.goal_voxel

    def __repr__(self) -> str:
        name = str(self.map_name[0]) if len(self) else ""
        return f"Scenarios3D({len(self)} scenarios for {name!r}, version {self.version!r})"


_SCEN3D_FIELDS = ("sx", "sy", "sz", "gx", "gy", "gz", "optimal_cost", "ratio")


def read_scen3d(path: PathLike, *, shape: tuple[int, int, int] | None = None) -> Scenarios3D:
    """Read a Moving AI 3-D scenario file (``.3dscen``, or gzip-compressed ``.3dscen.gz``).

    The format: a line ``version 1``, a line naming the map file, then one line per scenario
    ``sx sy sz gx gy gz optimal_cost ratio``: the start and goal voxels (0-based integers), the optimal
    26-connected cost (moves of 1, sqrt 2 and sqrt 3) and its ratio to the straight-line estimate.

    Parameters
    ----------
    path : str or path-like
    shape : (layers, rows, cols), optional
        The map's voxel grid shape ``(D, H, W)`` (``GridMap.shape`` of :func:`read_3dmap`): every start
        and goal must lie inside it. By default the coordinates are only checked to be non-negative.

    Returns
    -------
    Scenarios3D

    Raises
    ------
    MapFormatError
        Naming the file and the line: no ``version`` line or map name, a line without eight fields, a
        coordinate that is not a non-negative integer (or lies outside ``shape``), a cost or ratio that is
        not a finite number >= 0.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "tiny.3dmap.3dscen"
    >>> _ = f.write_text("version 1\\ntiny.3dmap\\n3 0 1 0 0 0 3.41421 1.17\\n")
    >>> s = read_scen3d(f, shape=(2, 3, 4))
    >>> len(s), str(s.map_name[0]), s.start_voxel[0].tolist(), s.start_cell[0].tolist()
    (1, 'tiny.3dmap', [3, 0, 1], [1, 0, 3])
    """
    p = _check_file(path)
    text = _decode_text(p, _read_bytes(p), "Moving AI 3-D scenario")
    lines = [(i + 1, ln.strip()) for i, ln in enumerate(text.split("\n")) if ln.strip()]
    if not lines or lines[0][1].split()[0].lower() != "version":
        got = shorten(lines[0][1][:60]) if lines else "an empty file"
        raise MapFormatError(f"{p}: line {lines[0][0] if lines else 1}: expected 'version 1' first (a Moving AI "
                             f"3-D scenario file), got {got}")
    parts = lines[0][1].split()
    version = parts[1] if len(parts) > 1 else ""
    if len(lines) < 2 or len(lines[1][1].split()) != 1:
        where = f"line {lines[1][0]}" if len(lines) > 1 else f"line {lines[0][0] + 1}"
        raise MapFormatError(f"{p}: {where}: expected the map's file name (one word) after the version line")
    name = lines[1][1].replace("\\", "/").rsplit("/", 1)[-1]
    body = lines[2:]
    if not body:
        raise MapFormatError(f"{p}: no scenarios in the file")
    fields = [ln.split() for _, ln in body]
    counts = np.fromiter((len(f) for f in fields), dtype=np.int64, count=len(fields))
    wrong = np.flatnonzero(counts != 8)
    if wrong.size:
        k = int(wrong[0])
        raise MapFormatError(f"{p}: line {body[k][0]}: expected 8 fields ({' '.join(_SCEN3D_FIELDS)}), "
                             f"got {int(counts[k])}")
    coords = np.zeros((len(fields), 6), dtype=np.int64)
    costs = np.zeros((len(fields), 2), dtype=np.float64)
    decimals = 0
    for k, row in enumerate(fields):  # one step per scenario line (not per voxel)
        for j in range(6):
            try:
                coords[k, j] = int(row[j])
            except (ValueError, OverflowError):
                raise MapFormatError(f"{p}: line {body[k][0]}: {_SCEN3D_FIELDS[j]} must be an integer, got "
                                     f"{shorten(row[j])}") from None
        for j in (6, 7):
            try:
                costs[k, j - 6] = float(row[j])
            except ValueError:
                raise MapFormatError(f"{p}: line {body[k][0]}: {_SCEN3D_FIELDS[j]} must be a number, got "
                                     f"{shorten(row[j])}") from None
        dot = row[6].find(".")
        decimals = max(decimals, len(row[6]) - dot - 1 if dot >= 0 else 0)
    line_no = np.array([n for n, _ in body], dtype=np.int64)
    limit = np.full(3, np.iinfo(np.int64).max, dtype=np.int64)
    if shape is not None:
        try:
            dims = [int(v) for v in shape]
        except (TypeError, ValueError):
            dims = []
        if len(dims) != 3 or min(dims) <= 0:
            raise ParameterError(f"shape must be three positive integers (layers, rows, cols), got {shorten(shape)}")
        limit = np.array(dims[::-1], dtype=np.int64)  # along x, y, z
    outside = ((coords < 0) | (coords >= np.tile(limit, 2))).any(axis=1)
    if outside.any():
        k = int(np.argmax(outside))
        size = " x ".join(map(str, limit)) + " map" if shape is not None else "map (coordinates are >= 0)"
        raise MapFormatError(f"{p}: line {line_no[k]}: start ({', '.join(map(str, coords[k, :3]))}) or goal "
                             f"({', '.join(map(str, coords[k, 3:]))}) lies outside the {size}")
    bad_cost = ~np.isfinite(costs).all(axis=1) | (costs < 0).any(axis=1)
    if bad_cost.any():
        k = int(np.argmax(bad_cost))
        raise MapFormatError(f"{p}: line {line_no[k]}: optimal_cost and ratio must be finite numbers >= 0")
    n = len(fields)
    start, goal = coords[:, :3], coords[:, 3:]
    w, h, dd = (int(v) for v in limit) if shape is not None else (0, 0, 0)
    optimal = costs[:, 0].copy()
    precision: Literal["significant", "decimals"] = "decimals" if decimals >= 7 else "significant"
    return Scenarios3D(
        np.zeros(n, dtype=np.int64), np.array([name] * n, dtype=str), np.full(n, w, dtype=np.int64),
        np.full(n, h, dtype=np.int64), start.astype(np.float64) + 0.5, goal.astype(np.float64) + 0.5, np.ascontiguousarray(start[:, ::-1]),
        np.ascontiguousarray(goal[:, ::-1]), optimal, (optimal == 0) & (start != goal).any(axis=1), version,
        precision, decimals if precision == "decimals" else 6, str(path),
        start_voxel=np.ascontiguousarray(start), goal_voxel=np.ascontiguousarray(goal), ratio=costs[:, 1].copy(),
        depth=np.full(n, dd, dtype=np.int64))


# ----------------------------------------------------------------------------------------
# binvox
# ----------------------------------------------------------------------------------------
def _binvox_header(p: FsPath, data: bytes) -> tuple[tuple[int, int, int], tuple[float, float, float], float, int]:
    """The dims, translate, scale of a binvox header and the offset of its data."""
    pos = 0
    line_no = 0
    dims: tuple[int, int, int] | None = None
    translate = (0.0, 0.0, 0.0)
    scale = 1.0
    while True:
        end = data.find(b"\n", pos, pos + HEADER_LINE_MAX + 1)
        line_no += 1
        if end < 0:
            raise MapFormatError(f"{p}: line {line_no}: the binvox header ends before its 'data' line"
                                 if len(data) - pos <= HEADER_LINE_MAX else
                                 f"{p}: line {line_no}: longer than {HEADER_LINE_MAX} bytes; not a binvox header line")
        text = data[pos:end].decode("ascii", "replace").strip()
        pos = end + 1
        parts = text.split()
        if line_no == 1:
            if len(parts) != 2 or parts[0] != "#binvox" or parts[1] not in ("1", "2"):
                raise MapFormatError(f"{p}: line 1: expected '#binvox 1' (a binvox file), got {shorten(text[:40])}")
            continue
        if not parts:
            continue
        key = parts[0].lower()
        if key == "data" and len(parts) == 1:
            break
        if (key, len(parts)) not in (("dim", 4), ("translate", 4), ("scale", 2)):
            raise MapFormatError(f"{p}: line {line_no}: expected a binvox header line 'dim D H W', "
                                 f"'translate tx ty tz', 'scale s' or 'data', got {shorten(text[:60])}")
        try:
            if key == "dim":
                d = tuple(int(v) for v in parts[1:])
                if min(d) <= 0 or max(len(v) for v in parts[1:]) > _DIGITS_MAX:
                    raise ValueError
                dims = (d[0], d[1], d[2])
            elif key == "translate":
                t = tuple(float(v) for v in parts[1:])
                if not all(math.isfinite(v) for v in t):
                    raise ValueError
                translate = (t[0], t[1], t[2])
            else:
                scale = float(parts[1])
                if not (math.isfinite(scale) and scale > 0):
                    raise ValueError
        except ValueError:
            what = {"dim": "three positive integers", "translate": "three finite numbers",
                    "scale": "a positive number"}[key]
            raise MapFormatError(f"{p}: line {line_no}: '{key}' needs {what}, got {shorten(text[:60])}") from None
    if dims is None:
        raise MapFormatError(f"{p}: the binvox header has no 'dim' line before 'data' (line {line_no})")
    return dims, translate, scale, pos


def read_binvox(path: PathLike, *, border: Literal["open", "wall"] = "open") -> GridMap:
    """Read a ``.binvox`` voxel file (Patrick Min's binvox; its specification: patrickmin.com/binvox).

    The header is ``#binvox 1``, ``dim d d d``, optionally ``translate tx ty tz`` and ``scale s``, and
    ``data``; then pairs of bytes (value, count): run lengths of the voxels in the format's order, **y
    fastest, then z, then x** (voxel ``(i, j, k)`` = ``(x, y, z)`` at index ``i * d * d + k * d + j``). Any
    non-zero value is set (version 2 files store values up to 255).

    The voxel ``(i, j, k)`` has its centre at ``translate + scale * ((i, j, k) + 0.5) / d``: the grid's
    origin is ``translate`` and its resolution ``scale / d`` (without those lines: the unit cube, origin 0,
    resolution ``1 / d``), and the voxel is ``occupied[k, j, i]`` (``[z, y, x]``).

    Parameters
    ----------
    path : str or path-like
    border : {"open", "wall"}
        Default "open" (a model voxelized in free space).

    Returns
    -------
    GridMap
        A voxel grid ``(d, d, d)``; ``meta`` holds ``format="binvox"``, ``occupancy_rule``, ``version``.

    Raises
    ------
    MapFormatError
        Naming the file (and the header line): a malformed header, dims that are not equal (gridfield's
        voxels are cubes, the format says they "should all be equal"), data cut short (an odd number of
        bytes) or run lengths whose total is not ``d * d * d``.
    SizeLimitError
        ``dim`` beyond the size guard (checked before the voxels are decoded).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "cube.binvox"
    >>> head = b"#binvox 1\\ndim 2 2 2\\ntranslate 1 2 3\\nscale 4\\ndata\\n"
    >>> _ = f.write_bytes(head + bytes([0, 1, 1, 1, 0, 6]))  # index 1: x 0, z 0, y 1
    >>> m = read_binvox(f)
    >>> m.grid.resolution, m.grid.origin, m.occupied[0, 1, 0].item(), int(m.occupied.sum())
    (2.0, (1.0, 2.0, 3.0), True, 1)
    """
    _choice("border", border, BORDERS)
    p = _check_file(path)
    with read_errors(p), open(p, "rb") as f:
        head = f.read(16 * HEADER_LINE_MAX)
    dims, translate, scale, offset = _binvox_header(p, head)
    version = head.split(None, 2)[1].decode("ascii")
    if len(set(dims)) != 1:
        raise MapFormatError(f"{p}: binvox dims {dims[0]} {dims[1]} {dims[2]} are not equal; gridfield reads cubic "
                             "grids of cubic voxels (the format's dims 'should all be equal')")
    d = dims[0]
    check_cells((d, d, d), f"{p} (binvox header 'dim {d} {d} {d}')")
    with read_errors(p), open(p, "rb") as f:
        f.seek(offset)
        body = f.read(2 * d**3 + 3)  # at most one pair per voxel (and a stray line end)
    if len(body) % 2:
        if body.endswith(b"\n") and len(body) > 1:
            body = body[:-1]
        else:
            raise MapFormatError(f"{p}: truncated binvox data: {len(body)} bytes, not whole (value, count) pairs")
    pairs = np.frombuffer(body, dtype=np.uint8).reshape(-1, 2)
    total = int(pairs[:, 1].sum(dtype=np.int64))
    if total != d**3:
        short = "truncated binvox data: " if total < d**3 else ""
        raise MapFormatError(f"{p}: {short}the run lengths add up to {total} voxels, but 'dim {d} {d} {d}' "
                             f"has {d**3}")
    flat = np.repeat(pairs[:, 0] != 0, pairs[:, 1])  # [x, z, y] order, y fastest
    occupied = np.ascontiguousarray(flat.reshape(d, d, d).transpose(1, 2, 0))  # [z, y, x]
    grid = Grid((d, d, d), scale / d, translate, border)
    meta = {"format": "binvox", "occupancy_rule": BINVOX_RULE, "version": version}
    return GridMap(grid, occupied, source=str(path), meta=meta)


# ----------------------------------------------------------------------------------------
# 3-D arrays: .npy and gridfield .npz
# ----------------------------------------------------------------------------------------
def npy_ndim(p: FsPath) -> int:
    """The number of dimensions a ``.npy`` file's header announces (0 when it is no readable ``.npy``: its
    reader then says why)."""
    try:
        with open(p, "rb") as f:
            version = np.lib.format.read_magic(f)
            shape = (np.lib.format.read_array_header_1_0(f) if version == (1, 0)
                     else np.lib.format.read_array_header_2_0(f))[0]
        return len(shape)
    except Exception:  # anything but a readable header: read_npy reports it
        return 0


def read_voxel_npy(path: PathLike, *, resolution: float = 1.0, origin: Any = (0.0, 0.0, 0.0),
                   border: Literal["open", "wall"] = "open", occupancy: Literal["dark", "nonzero"] = "nonzero",
                   threshold: float = 0.5, negate: bool = False) -> GridMap:
    """Read a 3-D ``.npy`` array as a voxel map (``[z, y, x]``, index 0 the lowest coordinate on every axis).

    The rules of :func:`~gridfield.io.read_npy` (an array, not an image): booleans True = obstacle, numbers
    non-zero = obstacle (``occupancy="nonzero"``, the default); ``occupancy="dark"`` reads unsigned integers
    as grey levels. The array is sized from its header against the size guard, then read whole (a voxel map
    is not read by chunks). :func:`~gridfield.io.read` picks this reader for a ``.npy`` of three dimensions.

    Parameters
    ----------
    path : str or path-like
        A 3-D ``.npy`` array of booleans or numbers.
    resolution : float
        The voxel edge length.
    origin : (x, y, z)
        The lowest corner of voxel ``[0, 0, 0]``.
    border : {"open", "wall"}
    occupancy : {"nonzero", "dark"}
    threshold : float in [0, 1]
        ``"dark"`` only.
    negate : bool
        ``"dark"`` only.

    Returns
    -------
    GridMap
        ``meta`` holds ``format="npy"`` and ``occupancy_rule``.

    Examples
    --------
    >>> import tempfile, numpy as np
    >>> f = tempfile.mkdtemp() + "/v.npy"
    >>> a = np.zeros((2, 3, 4), np.uint8); a[1, 2, 3] = 7
    >>> np.save(f, a)
    >>> m = read_voxel_npy(f, resolution=0.5, origin=(0, 0, 10))
    >>> m.shape, m.grid.bounds, m.is_free([[1.75, 1.25, 10.75]]).tolist(), m.meta["occupancy_rule"]
    ((2, 3, 4), (0.0, 0.0, 10.0, 2.0, 1.5, 11.0), [False], 'non-zero = obstacle')
    """
    rule_name, thr, neg = check_grey_options(occupancy, threshold, negate, path)
    p = _check_file(path)
    try:
        a = np.load(p, mmap_mode="r", allow_pickle=False)
    except (OSError, ValueError, EOFError) as e:
        raise MapFormatError(f"{p}: not a readable .npy array: {shorten(str(e))}") from None
    if not isinstance(a, np.ndarray) or a.ndim != 3:
        raise MapFormatError(f"{p}: expected a 3-D voxel array [z, y, x], got shape {shorten(getattr(a, 'shape', '?'))}")
    if a.dtype.kind not in "biuf":
        raise MapFormatError(f"{p}: expected booleans or numbers, got dtype {a.dtype}")
    check_cells(a.shape, f"{p} (.npy header)")
    rule = raster_rule(p, a.dtype, rule_name, thr, neg, image=False)
    grid = Grid(tuple(int(s) for s in a.shape), resolution, origin, border)
    occupied = np.ascontiguousarray(rule(np.asarray(a)))
    return GridMap(grid, occupied, source=str(path), meta={"format": "npy", "occupancy_rule": rule.text})


def npz_voxel_arrays(p: FsPath, content: dict[str, NDArray[Any]]) -> tuple[dict[str, NDArray[Any]], Grid]:
    """The arrays of a gridfield ``.npz`` whose ``occupied`` is 3-D, and their voxel :class:`Grid` (the
    geometry entries ``resolution``, ``origin`` ``[x, y, z]``, ``border`` checked and removed), as
    :func:`~gridfield.io.read_npz_arrays` gives them for a map.

    Parameters
    ----------
    p : pathlib.Path
        The file, for the messages.
    content : dict of str to ndarray
        Every array of the file (sized from their headers by the caller).

    Returns
    -------
    arrays : dict of str to ndarray
    grid : Grid

    Examples
    --------
    >>> content = {"occupied": np.zeros((2, 3, 4), bool), "resolution": np.float64(0.5),
    ...            "origin": np.array([0.0, 1.0, 2.0]), "border": np.array("open")}
    >>> arrays, grid = npz_voxel_arrays(FsPath("v.npz"), content)
    >>> sorted(arrays), grid.shape, grid.origin
    (['occupied'], (2, 3, 4), (0.0, 1.0, 2.0))
    """
    content = dict(content)
    for key in ("resolution", "origin"):
        if key not in content:
            raise MapFormatError(f"{p}: no '{key}' array; a gridfield .npz holds resolution and origin beside the arrays")
    try:
        res = float(np.asarray(content.pop("resolution")).reshape(()))
        origin = np.asarray(content.pop("origin"), dtype=np.float64).reshape(-1)
        border = str(np.asarray(content.pop("border", "open")).reshape(()))
    except (TypeError, ValueError) as e:
        raise MapFormatError(f"{p}: bad resolution, origin or border entry ({e})") from None
    shape = content["occupied"].shape
    bad = {k: a.shape for k, a in content.items() if a.ndim >= 3 and a.shape[:3] != shape}
    if bad:
        raise MapFormatError(f"{p}: arrays have different shapes from the voxel grid's {shape}: {bad}")
    if origin.size != 3:
        raise MapFormatError(f"{p}: a voxel grid's origin is three numbers (x, y, z), got {origin.size}")
    try:
        grid = Grid(shape, res, (float(origin[0]), float(origin[1]), float(origin[2])), border)  # type: ignore[arg-type]
    except ParameterError as e:
        raise MapFormatError(f"{p}: {e}") from None
    return content, grid
