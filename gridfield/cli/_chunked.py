"""What ``brushfire`` and ``field`` share on their chunked path (``--chunks N --out F.zarr [--scheduler A]``):
the options, the lazy input as a dask array, the scheduler, the resume key and the store.

The input and ``--out`` may be URLs (``s3://bucket/f.zarr``, ``gs://``, ``memory://``; the ``[s3]`` extra):
then the temporary store between the Euclidean passes is the prefix ``OUT.zarr.scratch`` beside the store in
the same bucket, so workers that share no disk meet through the object store, and URLs are shown without
credentials."""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import json
import math
import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

#: Seconds to wait for a dask scheduler given with ``--scheduler`` before giving up.
CONNECT_TIMEOUT = 5.0
DEFAULT_CHUNKS = 4096


def _chunks(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive whole number of cells, got {text!r}") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"expected a positive whole number of cells, got {text!r}")
    return v


def add_chunk_arguments(p: argparse.ArgumentParser) -> None:
    """``--chunks``, ``--out`` and ``--scheduler``."""
    p.add_argument("--out", metavar="F.zarr",
                   help="compute chunk by chunk (dask) and write the arrays and the grid metadata to the Zarr store "
                        "F.zarr, for maps larger than memory (BigTIFF/GeoTIFF, .npy, Zarr inputs are read by chunks); "
                        "an interrupted run leaves F.zarr.partial, which the same command resumes; F.zarr and the map "
                        "may be URLs such as s3://bucket/f.zarr (pip install 'gridfield[s3]'; credentials from the "
                        "environment), where an interrupted store is resumed in place")
    p.add_argument("--chunks", type=_chunks, default=None, metavar="N",
                   help=f"chunk size in cells of the chunked computation and the store (default {DEFAULT_CHUNKS}; "
                        "with --out)")
    p.add_argument("--scheduler", metavar="ADDRESS", default=None,
                   help="dask scheduler to compute on, e.g. tcp://127.0.0.1:8786 (default: threads in this process)")


def chunked(args: argparse.Namespace) -> bool:
    """Whether the command runs on its chunked path; refuses the options that only apply to one path."""
    from ..core.errors import ParameterError

    if args.out is None:
        for opt in ("chunks", "scheduler"):
            if getattr(args, opt) is not None:
                raise ParameterError(f"--{opt} applies to the chunked computation; pass --out F.zarr too")
        return False
    from ..io import is_url, local_path, redact

    args.out = local_path(args.out)
    if not str(args.out).rstrip("/").lower().endswith(".zarr"):
        raise ParameterError(f"--out {redact(args.out)}: a Zarr store's name ends in .zarr")
    for opt in ("npz", "plot", "surface", "basins"):
        if getattr(args, opt, None) is not None:
            raise ParameterError(f"--{opt} holds the whole map in memory; it does not combine with --out")
    from ..core.errors import GridfieldError

    if is_url(args.out):
        args.out = str(args.out).rstrip("/")
        _check_remote_out(args.out)
    elif Path(args.out).exists():
        raise GridfieldError(f"{args.out}: already exists; remove it or choose another --out")
    elif not Path(args.out).resolve().parent.is_dir():
        raise GridfieldError(f"{args.out}: the folder {Path(args.out).parent} does not exist")
    if args.chunks is None:
        args.chunks = DEFAULT_CHUNKS
    return True


def _check_remote_out(url: str) -> None:
    """An ``--out`` URL: refused when a complete store (or anything but an interrupted one) is there."""
    from ..core.errors import GridfieldError
    from ..io import redact, store_errors, url_fs

    fs, root = url_fs(url)
    with store_errors(url):
        if not fs.exists(f"{root}/zarr.json"):
            return
        import json

        attrs = json.loads(fs.cat_file(f"{root}/zarr.json")).get("attributes", {})
    if "gridfield" in attrs or "gridfield_partial" not in attrs:
        raise GridfieldError(f"{redact(url)}: already exists; remove it or choose another --out")


def check_halo(args: argparse.Namespace, saturate: float | None, resolution: float) -> None:
    """Chunks smaller than the saturation halo (``ceil(saturate / resolution) + 1`` cells) are refused."""
    from ..core.errors import ParameterError

    if saturate is None or not math.isfinite(saturate):
        return
    halo = math.ceil(saturate / resolution) + 1
    if args.chunks < halo:
        raise ParameterError(f"--chunks {args.chunks} is smaller than the saturation halo: saturate {saturate:g} at "
                             f"resolution {resolution:g} reaches {halo} cells; use --chunks {halo} or more")


def lazy_occupancy(args: argparse.Namespace, target: Any) -> tuple[Any, Any]:
    """The map's grid and its occupancy as a dask array of ``--chunks`` chunks (read by chunks for the
    BigTIFF/GeoTIFF, ``.npy`` and Zarr inputs; an in-memory map otherwise)."""
    import numpy as np

    from ..core.chunkcache import LazyGridMap
    from ..core.errors import ParameterError
    from ..core.grid import GridMap

    try:
        import dask.array as da
    except ImportError:  # pragma: no cover - the [dask] extra installs it
        raise ParameterError("--out (the chunked computation) needs dask: pip install 'gridfield[dask]'") from None
    if isinstance(target, LazyGridMap):
        src = target.occupied._source  # the Raster: read a chunk at a time, never whole
        occ = da.from_array(src, chunks=(args.chunks, args.chunks), asarray=True, lock=False,
                            meta=np.empty((0, 0), bool), name=f"occupied-{resume_token(args)}")
        return target.grid, occ
    if isinstance(target, GridMap):
        if target.grid.ndim != 2:
            raise ParameterError(f"{args.map} is a voxel grid: the chunked computation (--chunks, --out) is 2-D; "
                                 "leave them out to compute it in memory")
        return target.grid, da.from_array(np.asarray(target.occupied), chunks=(args.chunks, args.chunks))
    raise ParameterError(f"{args.map}: expected a map to compute on, got a {type(target).__name__}")


def resume_token(args: argparse.Namespace, **extra: Any) -> str:
    """What identifies a chunked run: the input file (path, size, modification time; for a URL its size and
    ETag or modification time) and the options."""
    from ..io import is_url, local_path

    ident: list[Any]
    if is_url(args.map):
        ident = [str(args.map), *_url_identity(str(args.map))]
    else:
        p = Path(local_path(args.map))
        try:
            st = p.stat()
            ident = [str(p.resolve()), st.st_size, st.st_mtime_ns]
        except OSError:
            ident = [str(p)]
    keys = {k: v for k, v in vars(args).items() if not k.startswith("_") and k not in ("scheduler", "out")}
    text = json.dumps([ident, keys, extra], sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def _url_identity(url: str) -> list[Any]:
    """A URL's object (or a Zarr store's ``zarr.json``): its size and its ETag or modification time."""
    from ..io import url_fs

    fs, root = url_fs(url)
    try:
        key = f"{root}/zarr.json" if root.rstrip("/").lower().endswith(".zarr") else root
        info = fs.info(key)
    except Exception:  # (reading the map names what is wrong with it)
        return []
    return [info.get("size"), str(info.get("ETag") or info.get("LastModified") or info.get("mtime") or "")]


@contextlib.contextmanager
def scheduler(args: argparse.Namespace) -> Iterator[Any]:
    """The dask scheduler: ``"threads"``, or a client of ``--scheduler ADDRESS`` (one clear error when it
    cannot be reached within :data:`CONNECT_TIMEOUT` seconds)."""
    from ..core.errors import GridfieldError

    if args.scheduler is None:
        yield "threads"
        return
    try:
        from distributed import Client
    except ImportError:  # pragma: no cover - the [dask] extra installs it
        raise GridfieldError("--scheduler needs dask.distributed: pip install 'gridfield[dask]'") from None
    try:
        client = Client(args.scheduler, timeout=CONNECT_TIMEOUT, set_as_default=False)
    except (OSError, TimeoutError, ValueError, TypeError) as e:
        why = str(e).splitlines()[0] if str(e) else type(e).__name__
        raise GridfieldError(f"cannot reach the dask scheduler at {args.scheduler} within {CONNECT_TIMEOUT:g} s "
                             f"({why})") from None
    try:
        yield client
    finally:
        client.close()


@contextlib.contextmanager
def scratch(args: argparse.Namespace) -> Iterator[Path]:
    """``OUT.zarr.scratch``: the directory of the temporary store between the exact Euclidean brushfire's
    passes (:func:`gridfield.chunked.scratch_dir`), next to the output, removed when the command ends (also
    on error; one that a killed run left is removed when the next run starts). Never inside the store. For
    an ``--out`` URL it is the prefix of that name in the same bucket: every worker reaches it."""
    from ..chunked import scratch_dir

    with scratch_dir(f"{args.out}.scratch") as tmp:
        yield tmp


def write(args: argparse.Namespace, arrays: dict[str, Any], grid: Any, kind: str, attrs: dict[str, Any],
          sched: Any, diagonals: Any = None) -> int:
    """Write the store (with the map's ``diagonals``, a disc robot's, when it has them); returns the number of
    chunks per array."""
    from ..core.errors import GridfieldError
    from ..io import write_store

    try:
        write_store(args.out, arrays, grid, kind=kind, attrs=attrs, chunks=args.chunks, resume_key=resume_token(args),
                    scheduler=sched, diagonals=diagonals)
    except GridfieldError as e:
        note = partial_note(args) if "already exists" not in str(e) and "other arguments" not in str(e) else ""
        raise type(e)(f"{e}{note}") from None
    per_array: int = math.ceil(grid.rows / args.chunks) * math.ceil(grid.cols / args.chunks)
    return per_array


def partial_note(args: argparse.Namespace) -> str:
    """How to resume, for an error raised during the write."""
    from ..io import is_url

    if is_url(args.out):  # (the store may be out of reach: not looked at)
        return " (the chunks written stay in the store: run the same command again to resume)"
    partial = Path(str(args.out) + ".partial")
    return f" ({partial} keeps the chunks written: run the same command again to resume)" if os.path.isdir(partial) else ""
