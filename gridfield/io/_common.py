"""What every reader shares: the file checks, byte and text reading, and the option check.

Each reader opens its file through :func:`_check_file` and :func:`_read_bytes`, so that a missing
file, a directory, a FIFO or device (refused before it is opened: reading a FIFO would block) or an
unreadable file gives the same :class:`~gridfield.errors.MapFormatError`
whatever the format.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path as FsPath
from typing import Any

from ..errors import MapFormatError, ParameterError, shorten

PathLike = str | os.PathLike[str]


def _check_file(path: PathLike) -> FsPath:
    try:
        p = FsPath(path)
    except TypeError:
        raise MapFormatError(f"expected a file name, got {shorten(path)}") from None
    if not p.exists():
        raise MapFormatError(f"{p}: no such file")
    if p.is_dir():
        raise MapFormatError(f"{p}: is a directory, expected a map file")
    _check_regular(p)
    return p


def _check_regular(p: FsPath, what: str = "") -> None:
    """Refuse a FIFO, socket or device before it is opened (reading a FIFO blocks until a writer comes)."""
    try:
        mode = p.stat().st_mode
    except OSError as e:
        raise MapFormatError(f"{what}{p}: cannot read: {e.strerror or e}") from None
    if not stat.S_ISREG(mode):
        kind = ("a FIFO (named pipe)" if stat.S_ISFIFO(mode) else "a socket" if stat.S_ISSOCK(mode) else
                "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else "not a regular file")
        raise MapFormatError(f"{what}{p}: is {kind}, expected a regular file")


def _read_bytes(p: FsPath) -> bytes:
    try:
        return p.read_bytes()
    except OSError as e:
        raise MapFormatError(f"{p}: cannot read: {e.strerror or e}") from None


def _choice(name: str, value: Any, choices: tuple[str, ...]) -> str:
    if value not in choices:
        raise ParameterError(f"{name} must be one of {', '.join(map(repr, choices))}, got {shorten(value)}")
    chosen: str = value  # one of the choices
    return chosen


def _decode_text(p: FsPath, data: bytes, what: str) -> str:
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data[: e.start].count(b"\n") + 1
        raise MapFormatError(f"{p}: line {line}: not a text {what} file (byte 0x{data[e.start]:02x} is not UTF-8)") from None
