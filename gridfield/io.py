"""Reading and writing maps, worlds and arrays (I/O only; no computation).

Supported inputs (:func:`read` picks by file name):

- world YAML (``bounds``/``obstacles``): :func:`read_world`
- ROS map_server YAML (``image``/``resolution``/``origin``): :func:`read_ros_map`
- bitmaps PNG, PGM, BMP: :func:`read_bitmap`
- Moving AI ``.map``: :func:`read_movingai_map`; scenarios ``.scen``: :func:`read_scen`
- ``.npz`` arrays written by gridfield: :func:`read_npz`
"""

from __future__ import annotations

import os
from pathlib import Path as FsPath
from typing import Any

import yaml

from .errors import MapFormatError
from .grid import GridMap
from .world import World, world_from_dict

__all__ = ["bundled_map", "read", "read_world", "read_yaml"]

PathLike = str | os.PathLike[str]


def bundled_map(name: str) -> FsPath:
    """Path of a map shipped with gridfield (``maps/`` in the source tree, ``gridfield/maps`` in a wheel).

    Examples
    --------
    >>> bundled_map("seed000.yaml").name
    'seed000.yaml'
    """
    from importlib import resources

    candidates = [resources.files("gridfield") / "maps", FsPath(__file__).resolve().parent.parent / "maps"]
    for base in candidates:
        p = FsPath(str(base)) / name
        if p.exists():
            return p
    raise MapFormatError(f"no bundled map named {name!r}")


def _check_file(path: PathLike) -> FsPath:
    p = FsPath(path)
    if not p.exists():
        raise MapFormatError(f"{p}: no such file")
    if p.is_dir():
        raise MapFormatError(f"{p}: is a directory, expected a map file")
    return p


def read_yaml(path: PathLike) -> Any:
    """Parse a YAML file, raising :class:`MapFormatError` with the file and line on bad syntax."""
    p = _check_file(path)
    try:
        text = p.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise MapFormatError(f"{p}: not a text (UTF-8) YAML file") from None
    except OSError as e:
        raise MapFormatError(f"{p}: cannot read: {e.strerror}") from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f" line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(e, "problem", None) or str(e).splitlines()[0]
        raise MapFormatError(f"{p}:{where}: invalid YAML: {problem}") from None
    if data is None:
        raise MapFormatError(f"{p}: the file is empty")
    return data


def read_world(path: PathLike) -> World:
    """Read a world YAML file (see :func:`gridfield.world.world_from_dict` for the keys).

    Examples
    --------
    >>> w = read_world(bundled_map("seed000.yaml"))
    >>> [ob.id for ob in w.obstacles], w.start, w.goal
    ([1, 2, 3], (1.0, 10.0), (22.0, 12.0))
    """
    data = read_yaml(path)
    return world_from_dict(data, source=str(path))


def read(path: PathLike, **options: Any) -> World | GridMap:
    """Read any supported map or world file; a world YAML gives a :class:`World`, the rest a :class:`GridMap`.

    ``options`` go to the format's reader (e.g. ``unknown="free"`` for ROS maps).
    """
    p = _check_file(path)
    suffix = p.suffix.lower()
    if suffix in (".yaml", ".yml"):
        data = read_yaml(p)
        if isinstance(data, dict) and "image" in data:
            return read_ros_map(p, **options)  # type: ignore[name-defined]
        return world_from_dict(data, source=str(p))
    if suffix in (".png", ".pgm", ".bmp"):
        return read_bitmap(p, **options)  # type: ignore[name-defined]
    if suffix == ".map":
        return read_movingai_map(p, **options)  # type: ignore[name-defined]
    if suffix == ".npz":
        return read_npz(p, **options)  # type: ignore[name-defined]
    raise MapFormatError(
        f"{p}: unknown map format {suffix!r}; expected a world or ROS map .yaml, a .png/.pgm/.bmp bitmap, "
        "a Moving AI .map or a gridfield .npz"
    )
