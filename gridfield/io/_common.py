"""What every reader shares: the file checks, byte and text reading, and the option check.

Each reader opens its file through :func:`_check_file` and :func:`_read_bytes`, so that a missing
file, a directory, a FIFO or device (refused before it is opened: reading a FIFO would block) or an
unreadable file gives the same :class:`~gridfield.core.errors.MapFormatError`
whatever the format.

A file whose name ends in ``.gz`` is read through gzip (:func:`_read_bytes`, :func:`_open_binary`): the
text and bitmap formats (Moving AI ``.map.gz`` and ``.scen.gz``, ``.pgm.gz``, a ROS YAML whose ``image``
is one) are read compressed. What it decompresses to is bounded (:func:`gz_limit`), so a small file that
inflates without end is refused, naming its size, before it fills memory.
"""

from __future__ import annotations

import contextlib
import gzip
import os
import stat
import zlib
from collections.abc import Iterator
from pathlib import Path as FsPath
from typing import Any

from ..core.errors import MapFormatError, ParameterError, shorten

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


def is_gzip(p: FsPath) -> bool:
    """Whether ``p`` names a gzip-compressed file (by its ``.gz`` suffix)."""
    return p.suffix.lower() == ".gz"


def inner_suffix(p: FsPath) -> str:
    """The format suffix of ``p``, lower case: that of the name without ``.gz`` for a compressed file
    (``"arena.map.gz"`` -> ``".map"``)."""
    return FsPath(p.stem).suffix.lower() if is_gzip(p) else p.suffix.lower()


#: Bytes a compressed cell may take once decompressed (a 16-bit PGM pixel is 2, a map character 1 and its
#: line end); with a megabyte for headers and comments this bounds every decompression by the size guard.
GZ_BYTES_PER_CELL = 4


def gz_limit() -> int:
    """Most bytes a ``.gz`` input may decompress to: :data:`GZ_BYTES_PER_CELL` per cell of the size guard
    (:func:`gridfield.core.limits.max_cells`) plus 1 MiB."""
    from ..core.limits import max_cells

    return GZ_BYTES_PER_CELL * max_cells() + (1 << 20)


def _open_binary(p: FsPath) -> Any:
    """``p`` opened for binary reading, through gzip when its name ends in ``.gz``."""
    return gzip.open(p, "rb") if is_gzip(p) else open(p, "rb")


@contextlib.contextmanager
def read_errors(p: FsPath) -> Iterator[None]:
    """Reading ``p`` (plain or gzip) inside: an unreadable file, a file that is not gzip, is cut short or
    holds corrupt compressed data becomes one :class:`~gridfield.errors.MapFormatError` naming it."""
    try:
        yield
    except gzip.BadGzipFile:
        raise MapFormatError(f"{p}: not a gzip file (its name ends in .gz)") from None
    except EOFError:
        raise MapFormatError(f"{p}: truncated gzip file (it ends before its compressed data does)") from None
    except OSError as e:
        raise MapFormatError(f"{p}: cannot read: {e.strerror or e}") from None
    except zlib.error as e:
        raise MapFormatError(f"{p}: corrupt gzip data: {shorten(str(e))}") from None


def _read_bytes(p: FsPath) -> bytes:
    """The file's bytes (decompressed for a ``.gz`` name, at most :func:`gz_limit` of them)."""
    if not is_gzip(p):
        with read_errors(p):
            return p.read_bytes()
    from ..core.errors import SizeLimitError

    limit = gz_limit()
    with read_errors(p), gzip.open(p, "rb") as f:
        data = f.read(limit + 1)
    if len(data) > limit:
        raise SizeLimitError(f"{p}: decompresses to more than {limit} bytes, more than a map within the size "
                             "guard holds (raise it with --max-cells or GRIDFIELD_MAX_CELLS)")
    return data


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
