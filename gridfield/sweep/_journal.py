"""The rows file of a sweep as a journal: locked, repaired when opened, appended one whole row at a time.

Why a journal and not a CSV written at the end: a sweep may be killed at any moment (SIGKILL, out
of memory, a lost node) and must resume with exactly one row per run. Each row is one ``write`` of
one complete line to a file opened in append mode, so a crash at any byte leaves at most a partial
last line, which the next open cuts off (its run is done again); damaged or duplicate lines are
dropped the same way. The lock stops two sweeps from interleaving rows in one file.
"""

from __future__ import annotations

import csv
import json
import math
import os
import stat
import time
from collections.abc import Mapping, Sequence
from pathlib import Path as FsPath
from typing import Any

from ..core.errors import GridfieldError, shorten

#: Columns of the rows file, in order.
COLUMNS = ("map", "planner", "params", "start_x", "start_y", "goal_x", "goal_y", "status", "length",
           "optimal", "steps", "ms", "optimal_any_angle")

#: Columns of rows files written before ``optimal_any_angle`` existed (resumed: the column is added).
_OLD_COLUMNS = COLUMNS[:-1]


def _row_key(fields: Mapping[str, str]) -> tuple[str, ...]:
    return (fields["map"], fields["planner"], fields["params"],
            *(f"{float(fields[k]):.9g}" for k in ("start_x", "start_y", "goal_x", "goal_y")))


def _format_row(row: Mapping[str, Any]) -> bytes:
    import io as _io

    buf = _io.StringIO()
    values = [row.get(c, math.nan if c == "optimal_any_angle" else "") for c in COLUMNS]  # an optional column
    csv.writer(buf, lineterminator="\n").writerow([" ".join(v.split()) if isinstance(v, str) else v for v in values])
    return buf.getvalue().encode("utf-8")


def _parse_row(line: str, columns: Sequence[str] = COLUMNS) -> dict[str, str] | None:
    """The row on one complete line (of a file with these ``columns``; the columns it lacks are
    ``nan``), or None when the line is damaged."""
    try:
        fields = next(csv.reader([line]))
    except (csv.Error, StopIteration):
        return None
    if len(fields) != len(columns):
        return None
    row = dict.fromkeys(COLUMNS, "nan")
    row.update(zip(columns, fields, strict=True))
    try:
        _row_key(row)
        float(row["length"]), float(row["optimal"]), int(row["steps"]), float(row["ms"])
        float(row["optimal_any_angle"])
        json.loads(row["params"])
    except (ValueError, TypeError):
        return None
    if not row["status"] or not row["planner"]:
        return None
    return row


class _Journal:
    """The rows file of a sweep, held locked while the sweep runs.

    On open it is repaired: a partial last line (a crash mid-write) is cut off, damaged or
    duplicate lines are dropped (their runs are done again), and the header is written if
    missing. Each row is then appended with a single ``write`` of the whole line to a file opened
    in append mode, so that a crash at any byte leaves at most one partial last line.
    """

    def __init__(self, path: FsPath) -> None:
        self.path = path
        self.notes: list[str] = []
        self._check_regular(path)
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            self.fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_APPEND | getattr(os, "O_BINARY", 0), 0o644)
        except OSError as e:
            raise GridfieldError(f"{path}: cannot open the rows file: {e.strerror or e}") from None
        try:
            self._lock()
            self.rows, self.keys = self._recover()
        except BaseException:
            os.close(self.fd)
            raise
        self._synced = time.monotonic()

    @staticmethod
    def check_unlocked(path: FsPath) -> None:
        """Raise now if another sweep holds the lock on ``path`` (the lock itself is taken later)."""
        _Journal._check_regular(path)
        try:
            fd = os.open(path, os.O_RDONLY | getattr(os, "O_BINARY", 0))
        except OSError:
            return  # no file yet (or unreadable: opening it for the sweep will say so)
        try:
            _Journal._lock_fd(fd, path)
        finally:
            os.close(fd)

    @staticmethod
    def _check_regular(path: FsPath) -> None:
        """An existing rows file must be a regular file: opening a FIFO would block the sweep."""
        try:
            mode = os.stat(path).st_mode
        except OSError:
            return  # no file yet (or unreadable: opening it says so)
        if not stat.S_ISREG(mode):
            raise GridfieldError(f"{path}: the rows file exists and is not a regular file (a FIFO, socket, device "
                                 "or directory); give another output")

    def _lock(self) -> None:
        self._lock_fd(self.fd, self.path)

    @staticmethod
    def _lock_fd(fd: int, path: FsPath) -> None:
        busy = GridfieldError(
            f"{path}: another sweep is writing this rows file (it is locked); wait for it to finish, "
            "or give this sweep another --out"
        )
        try:
            import fcntl
        except ImportError:  # pragma: no cover - Windows
            import msvcrt

            try:
                msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)  # type: ignore[attr-defined]  # msvcrt: Windows only
            except OSError:
                raise busy from None
            return
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            raise busy from None

    def _read_all(self) -> bytes:
        size = os.fstat(self.fd).st_size
        chunks, pos = [], 0
        while pos < size:
            chunk = os.pread(self.fd, min(size - pos, 1 << 24), pos)
            if not chunk:
                break
            chunks.append(chunk)
            pos += len(chunk)
        return b"".join(chunks)

    def _write(self, data: bytes) -> None:
        view = memoryview(data)
        while view:
            n = os.write(self.fd, view)
            view = view[n:]

    def _recover(self) -> tuple[list[dict[str, str]], set[tuple[str, ...]]]:
        data = self._read_all()
        end = data.rfind(b"\n") + 1
        if end < len(data):  # a partial last line: the run it belonged to is done again
            os.ftruncate(self.fd, end)
            self.notes.append(f"removed a partial last line ({len(data) - end} bytes) left by an interrupted write")
            data = data[:end]
        header = ",".join(COLUMNS)
        if not data:
            self._write((header + "\n").encode())
            return [], set()
        text = data.decode("utf-8", errors="replace")
        lines = [ln[:-1] if ln.endswith("\r") else ln for ln in text.split("\n")[:-1]]
        # a rows file of an earlier version (no optimal_any_angle column) is rewritten with the column
        old = lines[0] == ",".join(_OLD_COLUMNS)
        if lines[0] != header and not old:
            raise GridfieldError(
                f"{self.path}: not a rows file of this sweep version (its first line is {shorten(lines[0][:200])}, "
                f"expected {header!r}); give another --out"
            )
        columns = _OLD_COLUMNS if old else COLUMNS
        rows: list[dict[str, str]] = []
        keys: set[tuple[str, ...]] = set()
        damaged = duplicate = 0
        for ln in lines[1:]:
            row = _parse_row(ln, columns)
            if row is None:
                damaged += 1
                continue
            key = _row_key(row)
            if key in keys:
                duplicate += 1
                continue
            keys.add(key)
            rows.append(row)
        if damaged or duplicate or old or data.endswith(b"\r\n"):
            # rewrite the file with the good rows only (a crash here loses rows, which are then redone)
            os.ftruncate(self.fd, 0)
            self._write(b"".join([(header + "\n").encode(), *(_format_row(r) for r in rows)]))
            os.fsync(self.fd)
            if old:
                self.notes.append("added the column optimal_any_angle (nan in the rows written before it)")
            if damaged:
                self.notes.append(f"dropped {damaged} damaged line(s); their runs are done again")
            if duplicate:
                self.notes.append(f"dropped {duplicate} duplicate row(s)")
        return rows, keys

    def append(self, row: Mapping[str, Any]) -> bool:
        """Write one row (whole, in one write); False if a row of that run is already there."""
        line = _format_row(row)
        parsed = _parse_row(line.decode("utf-8")[:-1])
        if parsed is None:  # pragma: no cover - run_one always makes well-formed rows
            raise GridfieldError(f"internal error: a sweep row cannot be written: {shorten(row)}")
        key = _row_key(parsed)
        if key in self.keys:
            return False
        self._write(line)
        self.keys.add(key)
        self.rows.append(parsed)
        if time.monotonic() - self._synced > 1.0:
            os.fsync(self.fd)
            self._synced = time.monotonic()
        return True

    def close(self) -> None:
        if self.fd >= 0:
            try:
                os.fsync(self.fd)
            finally:
                os.close(self.fd)  # releases the lock
                self.fd = -1
