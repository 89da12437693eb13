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
import re
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


# ---------------------------------------------------------------------------------------------
# URLs: inputs and outputs on an object store (s3://, gs://, memory://, ...) through fsspec
# ---------------------------------------------------------------------------------------------
_URL = re.compile(r"^(?P<scheme>[A-Za-z][A-Za-z0-9+.\-]*)://")
#: ``user:secret@`` in a URL's authority, and query parameters that carry credentials.
_USERINFO = re.compile(r"(?P<head>[A-Za-z][A-Za-z0-9+.\-]*://)[^/@\s]*@")
_SECRET_QUERY = re.compile(r"(?i)([?&][^=&\s]*(?:key|secret|token|signature|credential|password)[^=&\s]*=)[^&\s]*")
#: The environment variables whose values never appear in a message (:func:`redact`).
SECRET_VARIABLES = ("AWS_SECRET_ACCESS_KEY", "AWS_SESSION_TOKEN", "AWS_ACCESS_KEY_ID", "AWS_SECURITY_TOKEN",
                    "GOOGLE_APPLICATION_CREDENTIALS", "AZURE_STORAGE_KEY", "AZURE_STORAGE_SAS_TOKEN")


def is_url(path: object) -> bool:
    """Whether ``path`` is a URL that fsspec opens (``s3://``, ``gs://``, ``memory://``...), not a local path.

    A ``file://`` URL is a local path (:func:`local_path`), so it is not one.

    Parameters
    ----------
    path : object
        A path or URL.

    Returns
    -------
    bool

    Examples
    --------
    >>> is_url("s3://maps/big.tif"), is_url("memory://f.zarr"), is_url("file:///tmp/f.zarr"), is_url("maps/a.map")
    (True, True, False, False)
    """
    if not isinstance(path, str):
        return False
    m = _URL.match(path)
    return m is not None and m.group("scheme").lower() != "file"


def local_path(path: Any) -> Any:
    """``path`` with a ``file://`` prefix taken off (a local path, as the local readers and writers take);
    anything else unchanged.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    str or path-like

    Examples
    --------
    >>> local_path("file:///tmp/f.zarr"), local_path("s3://b/f.zarr"), local_path("f.zarr")
    ('/tmp/f.zarr', 's3://b/f.zarr', 'f.zarr')
    """
    if isinstance(path, str) and path[:7].lower() == "file://":
        return path[7:]
    return path


def redact(text: object) -> str:
    """``text`` without credentials: a URL's ``user:secret@``, credential query parameters, and the values of
    :data:`SECRET_VARIABLES` set in the environment become ``***``.

    Parameters
    ----------
    text : object
        A message, a URL, an exception.

    Returns
    -------
    str

    Examples
    --------
    >>> redact("s3://AKIA123:s3cr3t@fields/f.zarr: access denied")
    's3://***@fields/f.zarr: access denied'
    >>> redact("https://h/f.tif?X-Amz-Signature=abc&part=1")
    'https://h/f.tif?X-Amz-Signature=***&part=1'
    """
    s = _USERINFO.sub(r"\g<head>***@", str(text))
    s = _SECRET_QUERY.sub(r"\1***", s)
    for name in SECRET_VARIABLES:
        value = os.environ.get(name, "")
        if len(value) >= 4:
            s = s.replace(value, "***")
    return s


def url_fs(url: str) -> tuple[Any, str]:
    """The fsspec file system of ``url`` and the path inside it; credentials come from the environment
    (AWS variables, fsspec's configuration), never from gridfield. fsspec (and the file system's package,
    e.g. s3fs) is imported here, on first use.

    Parameters
    ----------
    url : str
        ``s3://bucket/key``, ``gs://...``, ``memory://...``.

    Returns
    -------
    (fsspec.AbstractFileSystem, str)
        The file system (fsspec's cached instance) and the path in it.

    Raises
    ------
    GridfieldError
        If fsspec or the file system's package is not installed (naming the extra), or the URL is malformed.

    Examples
    --------
    >>> fs, path = url_fs("memory://maps/a.zarr")
    >>> type(fs).__name__, path
    ('MemoryFileSystem', '/maps/a.zarr')
    """
    from ..core.errors import GridfieldError

    scheme = url.split("://", 1)[0].lower()
    try:
        import fsspec.core
    except ImportError:
        raise GridfieldError(f"{redact(url)}: a URL needs fsspec: pip install 'gridfield[s3]' (fsspec and s3fs; "
                             "another file system's package beside it, e.g. gcsfs for gs://)") from None
    try:
        fs, path = fsspec.core.url_to_fs(url)
    except ImportError as e:
        raise GridfieldError(f"{redact(url)}: the {scheme}:// file system needs its package ({redact(e)}); for s3:// "
                             "pip install 'gridfield[s3]'") from None
    except (ValueError, TypeError) as e:
        raise GridfieldError(f"{redact(url)}: not a URL fsspec opens: {redact(e)}") from None
    return fs, str(path)


def store_error(e: BaseException, where: str) -> Exception | None:
    """One clear :class:`~gridfield.core.errors.GridfieldError` (credentials redacted) for an error of an
    object store reached at the URL ``where``: a missing bucket or object, a denied access, a dropped
    connection; None for any other error (the caller re-raises it).

    Parameters
    ----------
    e : BaseException
        The error raised by the store's client (s3fs, botocore, aiohttp, fsspec).
    where : str
        The URL being read or written (shown redacted).

    Returns
    -------
    GridfieldError or None

    Examples
    --------
    >>> store_error(PermissionError("Access Denied"), "s3://k:secret@b/f.zarr")
    GridfieldError('s3://***@b/f.zarr: access denied (Access Denied); check the credentials in the environment (AWS_* variables, fsspec configuration) and the bucket policy')
    >>> store_error(ValueError("x"), "s3://b/f.zarr") is None
    True
    """
    from ..core.errors import GridfieldError

    url = redact(where)
    why = " ".join(redact(e).split())[:200] or type(e).__name__
    if isinstance(e, GridfieldError):
        return None
    if isinstance(e, PermissionError):
        return GridfieldError(f"{url}: access denied ({why}); check the credentials in the environment "
                              "(AWS_* variables, fsspec configuration) and the bucket policy")
    if isinstance(e, FileNotFoundError):
        return GridfieldError(f"{url}: no such bucket or object ({why})")
    names = {c.__name__ for c in type(e).__mro__}
    if isinstance(e, ConnectionError | TimeoutError) or any(
            n in names for n in ("EndpointConnectionError", "ConnectionClosedError", "ClientConnectionError",
                                 "ClientConnectorError", "ServerDisconnectedError", "ReadTimeoutError",
                                 "ConnectTimeoutError", "ClientOSError", "ResponseStreamingError")):
        return GridfieldError(f"{url}: the connection to the object store failed ({why})")
    if isinstance(e, OSError) or any(c.__module__.split(".")[0] in _STORE_PACKAGES for c in type(e).__mro__):
        return GridfieldError(f"{url}: the object store refused the request ({why})")
    return None


#: The packages whose errors are the object store's (any of them: :func:`store_error`).
_STORE_PACKAGES = frozenset({"botocore", "aiobotocore", "s3fs", "gcsfs", "adlfs", "aiohttp", "fsspec"})


@contextlib.contextmanager
def store_errors(where: str) -> Iterator[None]:
    """Inside: an object store's error at ``where`` becomes one clear error (:func:`store_error`).

    Parameters
    ----------
    where : str
        The URL being read or written (shown redacted).

    Yields
    ------
    None

    Examples
    --------
    >>> with store_errors("s3://no-such-bucket/f.zarr"):
    ...     raise FileNotFoundError("The specified bucket does not exist")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.GridfieldError: s3://no-such-bucket/f.zarr: no such bucket or object (The specified bucket does not exist)
    """
    try:
        yield
    except Exception as e:
        clear = store_error(e, where)
        if clear is None:
            raise
        raise clear from None
