"""Moving AI benchmark files: ``.map`` grids and ``.scen`` scenario lists (either gzip-compressed too:
``.map.gz``, ``.scen.gz``).

The scenario reader converts the benchmark's coordinates (y growing downward) to gridfield's world
points and cells, and keeps how each optimal length was printed, so that a computed length can be
compared with it to the printed precision (:meth:`Scenarios.tolerance`).
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path as FsPath
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from ..core.errors import MapFormatError, ParameterError, shorten
from ..core.grid import BORDERS, Grid, GridMap
from ..core.limits import check_cells
from ._common import PathLike, _check_file, _choice, _decode_text, _open_binary, _read_bytes, read_errors

# ----------------------------------------------------------------------------------------
# Moving AI benchmarks
# ----------------------------------------------------------------------------------------
#: The occupancy rule of a Moving AI map, in words (``meta["occupancy_rule"]``, said by ``gridfield info``).
MOVINGAI_RULE = "'.', 'G', 'S' free; the rest blocked"
_MAI_PASSABLE = b".GS"
_MAI_BLOCKED = b"@OTW"
_MAI_LUT = np.full(256, 2, dtype=np.uint8)  # 0 passable, 1 blocked, 2 invalid
_MAI_LUT[np.frombuffer(_MAI_PASSABLE, np.uint8)] = 0
_MAI_LUT[np.frombuffer(_MAI_BLOCKED, np.uint8)] = 1


def _text_lines(p: FsPath, what: str) -> list[str]:
    text = _decode_text(p, _read_bytes(p), what)
    return [ln[:-1] if ln.endswith("\r") else ln for ln in text.split("\n")]


#: Longest line of a ``.scen`` file, in bytes (a valid line is under 5 kB: nine fields, the map path at most
#: 4096 characters); a longer line is refused, naming it, before it is read whole.
SCEN_LINE_MAX = 65536
_SCEN_FIELD_MAX = 4096  # longest field (a path, PATH_MAX)
_SCEN_NAME_MAX = 255  # longest map file name (NAME_MAX): the names array is as wide as the longest one
_SCEN_FIELDS = ("bucket", "map", "width", "height", "start_x", "start_y", "goal_x", "goal_y", "optimal")


def _scen_lines(p: FsPath) -> Iterator[tuple[int, str]]:
    """The file's lines (0-based number, text without the line end), read one at a time: memory stays
    within :data:`SCEN_LINE_MAX` bytes per line whatever the file holds."""
    with read_errors(p), _open_binary(p) as f:
        for i in itertools.count():
            data = f.readline(SCEN_LINE_MAX + 1)
            if not data:
                return
            if len(data) > SCEN_LINE_MAX:
                raise MapFormatError(f"{p}: line {i + 1}: longer than {SCEN_LINE_MAX} bytes; not a Moving AI "
                                     "scenario line (nine short fields)")
            if data.endswith(b"\n"):
                data = data[:-1]
            try:
                text = data.decode("utf-8")
            except UnicodeDecodeError as e:
                raise MapFormatError(f"{p}: line {i + 1}: not a text Moving AI scenario file (byte "
                                     f"0x{data[e.start]:02x} is not UTF-8)") from None
            yield i, text[:-1] if text.endswith("\r") else text


def _map_header(p: Any, lines: list[str]) -> tuple[dict[str, str], int]:
    """The header of a Moving AI map (``type``, ``height``, ``width``, checked) and the index of its ``map`` line."""
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
    for key in ("height", "width"):
        v = header[key]
        if not v.isdigit() or int(v) <= 0:
            raise MapFormatError(f"{p}: '{key}' must be a positive integer, got {shorten(v)}")
    return header, map_line


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

    Returns
    -------
    GridMap
        Resolution 1, origin (0, 0); ``meta`` holds ``format="movingai"``, the header's ``type`` and the
        ``occupancy_rule``.

    Examples
    --------
    >>> from gridfield.io import bundled_map
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
    header, map_line = _map_header(p, lines)
    h, w = int(header["height"]), int(header["width"])
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
    meta = {"format": "movingai", "type": header["type"], "occupancy_rule": MOVINGAI_RULE}
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

    Examples
    --------
    >>> from gridfield.io import bundled_map, read_scen
    >>> s = read_scen(bundled_map("arena/arena.map.scen"))
    >>> s
    Scenarios(160 scenarios for 'arena.map', version '1')
    >>> s.goal_cell[0].tolist(), float(s.optimal[0]), bool(s.no_path.any())
    ([36, 1], 1.0, False)
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
        >>> from gridfield.io import bundled_map
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


def _scen_fields(p: Any, i: int, raw: str, ln: str, cols: list[list[Any]]) -> list[str]:
    """The 9 fields of data line ``i`` of a scenario file, checked and appended to ``cols``."""
    parts = raw.strip("\n").split("\t") if "\t" in raw else ln.split()
    parts = [s.strip() for s in parts]
    if len(parts) != 9:
        raise MapFormatError(
            f"{p}: line {i + 1}: expected 9 fields (bucket map width height start_x start_y goal_x goal_y "
            f"optimal), got {len(parts)}"
        )
    for j, s in enumerate(parts):
        if len(s) > _SCEN_FIELD_MAX:
            raise MapFormatError(f"{p}: line {i + 1}: the {_SCEN_FIELDS[j]} field is {len(s)} characters long; "
                                 f"a scenario field has at most {_SCEN_FIELD_MAX}")
        kind = np.float64 if j == 8 else np.int64 if j != 1 else None
        if kind is None:
            name = os.path.basename(s.replace("\\", "/"))
            if len(name) > _SCEN_NAME_MAX:
                raise MapFormatError(f"{p}: line {i + 1}: the map name is {len(name)} characters long; a file "
                                     f"name has at most {_SCEN_NAME_MAX}")
            cols[1].append(name)
            continue
        try:
            cols[j].append(kind(s))
        except (ValueError, OverflowError):
            what = "optimal length" if j == 8 else _SCEN_FIELDS[j]
            raise MapFormatError(f"{p}: line {i + 1}: {what} must be a number (in range), got {shorten(s)}") from None
    return parts


def read_scen(path: PathLike, *, map_height: int | None = None) -> Scenarios:
    """Read a Moving AI scenario file (``.scen``).

    All three variants are accepted: ``version 1`` tab-separated with 6 significant digits or
    with 8 decimals, and ``version 1.0`` space-separated with 2 decimals. Each data line holds
    ``bucket map width height start_x start_y goal_x goal_y optimal``.

    The file is read one line at a time, in linear time and memory bounded by the scenarios kept: a
    line longer than :data:`SCEN_LINE_MAX` bytes, a field longer than 4096 characters or a map file
    name longer than 255 is refused with a :class:`~gridfield.core.errors.MapFormatError` naming its line.

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
    >>> from gridfield.io import bundled_map
    >>> s = read_scen(bundled_map("arena/arena.map.scen"))
    >>> len(s), str(s.map_name[0]), s.version
    (160, 'arena.map', '1')
    >>> s.start_xy[0].tolist(), s.start_cell[0].tolist()  # first line: start (1, 11) on a 49-high map
    ([1.5, 37.5], [37, 1])
    """
    p = _check_file(path)
    version = ""
    cols: list[list[Any]] = [[] for _ in range(9)]
    numbers: list[int] = []
    decimals = 0
    for i, raw in _scen_lines(p):
        ln = raw.strip()
        if not ln:
            continue
        if not numbers and not version and ln.lower().startswith("version"):
            version = ln.split(None, 1)[1].strip() if len(ln.split()) > 1 else ""
            continue
        parts = _scen_fields(p, i, raw, ln, cols)
        dot = parts[8].find(".")
        decimals = max(decimals, len(parts[8]) - dot - 1 if dot >= 0 else 0)
        numbers.append(i + 1)
    if not numbers:
        raise MapFormatError(f"{p}: no scenarios in the file")
    line_no = np.array(numbers)
    ints = {k: np.array(cols[k], dtype=np.int64) for k in (0, 2, 3, 4, 5, 6, 7)}
    optimal = np.array(cols[8], dtype=np.float64)
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

    max_dp = decimals
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
    names = np.array(cols[1], dtype=str)
    return Scenarios(bucket, names, width, height, start_xy, goal_xy, start_cell, goal_cell, optimal, no_path,
                     version, precision, digits, str(path))  # type: ignore[arg-type]
