"""Reading and writing maps, worlds and arrays (I/O only; no computation).

Supported inputs (:func:`read` picks by file name):

- world YAML (``bounds``/``obstacles``): :func:`read_world`
- ROS map_server YAML (``image``/``resolution``/``origin``): :func:`read_ros_map`
  (and :func:`ros_occupancy_values` for the raw OccupancyGrid values)
- bitmaps PNG, PGM (``P2`` ASCII and ``P5`` binary), BMP: :func:`read_bitmap`; grey levels, dark = occupied
- Moving AI ``.map``: :func:`read_movingai_map`; scenarios ``.scen``: :func:`read_scen`
- any of those text and bitmap files gzip-compressed (``arena.map.gz``, ``arena.map.scen.gz``, ``map.pgm.gz``,
  also as a ROS YAML's ``image``), decompressed within the size guard
- ``.npz`` arrays written by gridfield: :func:`read_npz`, :func:`read_npz_arrays`
- voxel maps (3-D grids, ``[z, y, x]``): Moving AI's 3-D benchmark ``.3dmap`` (:func:`read_3dmap`; also
  ``.3dmap.gz``) and its scenarios ``.3dscen`` (:func:`read_scen3d`, also through :func:`read_scen`), Patrick
  Min's ``.binvox`` (:func:`read_binvox`), 3-D ``.npy`` arrays (:func:`read_voxel_npy`) and ``.npz`` files,
  and point clouds voxelized at a resolution: PLY and ``.xyz`` (:func:`read_pointcloud`)
- maps larger than memory, read by chunks (a :class:`~gridfield.core.chunkcache.LazyGridMap`): BigTIFF /
  GeoTIFF ``.tif``/``.tiff`` (:func:`read_tiff`), ``.npy`` memory maps (:func:`read_npy`), plain Zarr arrays
  (:func:`read_zarr_array`); and gridfield's Zarr stores (``gridfield brushfire/field ... --out F.zarr``,
  :func:`write_store`), read as lazy maps, distance maps or fields (:func:`read_store`)

Occupancy of images and arrays (:data:`OCCUPANCY_RULES`, the ``occupancy`` option of :func:`read_bitmap`,
:func:`read_tiff`, :func:`read_npy` and :func:`read_zarr_array`; ``--occupancy`` on the command line), one
rule for every image, never guessed:

- ``"dark"``, the default of the images (PNG, PGM, BMP, TIFF): grey levels, dark = occupied. A value ``v`` of
  an image whose white is ``W`` (255 for 8 bits, 65535 for 16; 1 for a 1-bit TIFF) has occupancy
  ``(W - v) / W`` and is an obstacle above ``threshold`` (default 0.5); ``negate`` reads ``v / W`` (white =
  occupied); a min-is-white TIFF stores 0 as white (so a boolean array written by tifffile reads True =
  obstacle). Float and signed-integer rasters have no grey convention and are refused (MapFormatError
  naming the file and the option to give).
- ``"nonzero"``: any non-zero value is an obstacle (label rasters, masks; booleans True). The default of
  ``.npy`` and plain Zarr arrays, which are arrays in gridfield's row order, not images (their booleans are
  True = obstacle under either rule).

Every reader records the rule it applied in words in the map's ``meta["occupancy_rule"]`` (ROS maps their
thresholds, costmaps and OccupancyGrid messages their values); ``gridfield info`` prints it.

Nav2 costmaps (a raw-mode map YAML with a ``costmap:`` mapping, read as a
:class:`~gridfield.fields.costmap.Costmap`): :func:`read_costmap`, :func:`write_costmap`; the fields of a
``nav_msgs/OccupancyGrid``: :func:`from_occupancy_grid`, :func:`to_occupancy_grid`, and a message saved
as YAML (``ros2 topic echo --once /map``): :func:`read_occupancy_grid`.

Writers: :func:`write_bitmap`, :func:`write_ros_map`, :func:`write_npz`. Fields of
:mod:`gridfield.fields.potential` (arrays, goal, parameters, distance map): :func:`save_field` and
:func:`load_field`.

Orientation (see ``ARCHITECTURE.md``, "Conventions"): images are stored top row first; every image reader flips
them so that the image's top row becomes the highest y (row ``rows - 1``), exactly as ROS
map_server does. A Moving AI map's first map line is likewise the top of the world.

Every problem with an input file is raised as :class:`~gridfield.core.errors.MapFormatError`
naming the file (and the line, key or value at fault); errors of the underlying libraries
(Pillow, numpy, PyYAML) never escape.

Layout of the package (one format per module): ``_common`` (file checks), ``_occupancy`` (the occupancy
rules of images and arrays: option checks and the rule in words), ``_yaml`` (YAML and
world files, with the alias-bomb guard), ``_bitmap``, ``_ros``, ``_movingai``, ``_npz`` (also the
fields' :func:`save_field` / :func:`load_field`), ``_tiff`` (BigTIFF/GeoTIFF and ``.npy`` read by chunks),
``_zarr`` (gridfield's Zarr store and plain Zarr arrays), ``_voxel`` (voxel maps: Moving AI 3-D, binvox, 3-D
arrays), ``_pointcloud`` (PLY and ``.xyz`` voxelized); this ``__init__`` re-exports their public names and
holds :func:`read`, which picks the reader by file name, and :func:`bundled_map`. The submodules are
private: import from ``gridfield.io``.
"""

from __future__ import annotations

import inspect
import os
from collections.abc import Callable, Mapping
from pathlib import Path as FsPath
from typing import Any

from ..core.errors import MapFormatError, ParameterError, shorten
from ..core.grid import GridMap
from ..geometry.world import world_from_dict
from ._bitmap import UNKNOWN_CHOICES as UNKNOWN_CHOICES
from ._bitmap import read_bitmap, write_bitmap
from ._common import PathLike as PathLike
from ._common import _check_file, inner_suffix, is_gzip, is_url, local_path, redact, store_error, store_errors, url_fs
from ._costmap import from_occupancy_grid, read_costmap, read_occupancy_grid, to_occupancy_grid, write_costmap
from ._costmap import is_costmap_yaml as _is_costmap_yaml
from ._costmap import is_occupancy_grid_yaml as _is_occupancy_grid_yaml
from ._movingai import Scenarios, read_movingai_map
from ._movingai import read_scen as _read_scen_2d
from ._npz import NPZ_ARRAY_NAMES, load_field, read_npz, read_npz_arrays, save_field, write_npz
from ._occupancy import OCCUPANCY_RULES as OCCUPANCY_RULES
from ._pointcloud import read_pointcloud
from ._ros import ROS_MODES as ROS_MODES
from ._ros import SEMANTICS as SEMANTICS
from ._ros import read_ros_map, ros_occupancy_values, write_ros_map
from ._tiff import read_npy, read_tiff
from ._voxel import Scenarios3D, npy_ndim, read_3dmap, read_binvox, read_scen3d, read_voxel_npy
from ._yaml import YAML_EXPANDED_LIMIT as YAML_EXPANDED_LIMIT
from ._yaml import read_world, read_yaml
from ._zarr import STORE_ARRAYS, read_store, read_zarr, read_zarr_array, write_store

__all__ = [
    "NPZ_ARRAY_NAMES",
    "OCCUPANCY_RULES",
    "STORE_ARRAYS",
    "Scenarios",
    "Scenarios3D",
    "bundled_map",
    "from_occupancy_grid",
    "is_url",
    "load_field",
    "local_path",
    "read",
    "read_3dmap",
    "read_binvox",
    "read_bitmap",
    "read_costmap",
    "read_movingai_map",
    "read_npy",
    "read_npz",
    "read_npz_arrays",
    "read_occupancy_grid",
    "read_pointcloud",
    "read_ros_map",
    "read_scen",
    "read_scen3d",
    "read_store",
    "read_tiff",
    "read_voxel_npy",
    "read_world",
    "read_yaml",
    "read_zarr",
    "read_zarr_array",
    "redact",
    "ros_occupancy_values",
    "save_field",
    "store_error",
    "store_errors",
    "to_occupancy_grid",
    "url_fs",
    "write_bitmap",
    "write_costmap",
    "write_npz",
    "write_ros_map",
    "write_store",
]


#: The formats also read gzip-compressed (``arena.map.gz``): the text and bitmap ones decoded here.
GZ_FORMATS = (".map", ".pgm", ".png", ".bmp", ".3dmap")


def bundled_map(name: str) -> FsPath:
    """Path of a map shipped with gridfield (``maps/`` in the source tree, ``gridfield/maps`` in a wheel).

    Parameters
    ----------
    name : str
        File name relative to the maps folder, e.g. ``"seed000.yaml"`` or ``"arena/arena.map"``.

    Returns
    -------
    pathlib.Path
        The file's path: in the installed package when it is there, else in the source tree's ``maps/``.

    Raises
    ------
    MapFormatError
        When no bundled map has that name.

    Examples
    --------
    >>> bundled_map("seed000.yaml").name
    'seed000.yaml'
    """
    from importlib import resources

    candidates = [resources.files("gridfield") / "maps", FsPath(__file__).resolve().parents[2] / "maps"]
    for base in candidates:
        p = FsPath(str(base)) / name
        if p.exists():
            return p
    raise MapFormatError(f"no bundled map named {shorten(name)}")


# ----------------------------------------------------------------------------------------
# dispatch
# ----------------------------------------------------------------------------------------
def read_scen(path: PathLike, *, map_height: int | None = None) -> Scenarios:
    """Read a Moving AI scenario file: a 2-D ``.scen`` (the reader of ``gridfield.io._movingai``) or, by its
    suffix, a 3-D ``.3dscen`` (:func:`read_scen3d`, giving a :class:`Scenarios3D`); either gzip-compressed too.

    A 2-D file's coordinates are converted to gridfield's y-up rows (its y grows downward); 2-D files of
    all three variants are read (``version 1`` tab-separated with 6 significant digits or 8 decimals,
    ``version 1.0`` with 2 decimals), one line at a time: a line longer than ``SCEN_LINE_MAX`` bytes, a field
    longer than 4096 characters or a map name longer than 255 is refused naming its line.

    Parameters
    ----------
    path : str or path-like
    map_height : int, optional
        2-D files: the height of the map the scenarios belong to; every line's height column must match it
        (by default each line's own is used). A ``.3dscen`` names no map size: it is not checked there
        (give :func:`read_scen3d` ``shape=``).

    Returns
    -------
    Scenarios
        A :class:`Scenarios3D` for a ``.3dscen``.

    Examples
    --------
    >>> s = read_scen(bundled_map("arena/arena.map.scen"))
    >>> len(s), str(s.map_name[0]), s.version
    (160, 'arena.map', '1')
    >>> s.start_xy[0].tolist(), s.start_cell[0].tolist()  # first line: start (1, 11) on a 49-high map
    ([1.5, 37.5], [37, 1])
    """
    if isinstance(path, str | os.PathLike) and inner_suffix(FsPath(path)) == ".3dscen":
        return read_scen3d(path)
    return _read_scen_2d(path, map_height=map_height)


def _check_options(reader: Callable[..., Any], options: Mapping[str, Any], p: FsPath, what: str) -> None:
    accepted = [n for n, prm in inspect.signature(reader).parameters.items() if prm.kind is prm.KEYWORD_ONLY]
    bad = sorted(set(options) - set(accepted))
    if bad:
        takes = f"it takes {', '.join(accepted)}" if accepted else "it takes no options"
        verb = "do not apply" if len(bad) > 1 else "does not apply"
        raise ParameterError(f"{p}: option{'s' if len(bad) > 1 else ''} {', '.join(bad)} {verb} to a {what}; {takes}")


def _read_url(url: str, options: Mapping[str, Any]) -> Any:
    """A map at a URL: a Zarr store or array, a (Big)TIFF/GeoTIFF or a ``.npy``, read by chunks."""
    suffix = FsPath(url.rstrip("/").rsplit("/", 1)[-1]).suffix.lower()
    readers: dict[str, tuple[Callable[..., Any], str]] = {
        ".zarr": (read_zarr, "Zarr store"), ".tif": (read_tiff, "TIFF raster"), ".tiff": (read_tiff, "TIFF raster"),
        ".npy": (read_npy, ".npy array")}
    if suffix not in readers:
        raise MapFormatError(f"{redact(url)}: a map at a URL is a .zarr store, a .tif/.tiff raster or a .npy array, "
                             f"not {shorten(suffix or 'a name without a suffix')}")
    reader, what = readers[suffix]
    if reader is not read_zarr:
        _check_options(reader, options, redact(url), what)  # type: ignore[arg-type]
    return reader(url, **options)


def _map_in_folder(folder: FsPath) -> FsPath:
    """The one map file of ``folder`` (a ``.yaml``/``.yml``, else a ``.map``), as a ROS map ships in its
    own folder; MapFormatError naming the candidates when there are several or none."""
    maps = sorted(q for q in folder.iterdir() if q.suffix.lower() in (".yaml", ".yml") and q.is_file())
    maps = maps or sorted(q for q in folder.iterdir() if inner_suffix(q) == ".map" and q.is_file())
    if len(maps) == 1:
        return maps[0]
    if not maps:
        raise MapFormatError(f"{folder}: is a directory with no map file (.yaml or .map) in it; give the map file")
    names = ", ".join(q.name for q in maps[:6]) + (", ..." if len(maps) > 6 else "")
    raise MapFormatError(f"{folder}: is a directory with {len(maps)} map files ({names}); give one of them")


def _voxel_reader(p: FsPath, suffix: str) -> tuple[Callable[..., GridMap], str] | None:
    """The reader of a voxel map file and its kind in words, by suffix (a ``.npy`` by its header's ndim)."""
    if suffix == ".npy":
        return (read_voxel_npy, "3-D .npy array") if npy_ndim(p) == 3 else None
    return {".3dmap": (read_3dmap, "Moving AI 3-D map"), ".binvox": (read_binvox, "binvox file"),
            ".ply": (read_pointcloud, "point cloud"), ".xyz": (read_pointcloud, "point cloud")}.get(suffix)


def _read_yaml_map(p: FsPath, options: dict[str, Any]) -> Any:
    """:func:`read` of a ``.yaml`` file: a Nav2 costmap, an OccupancyGrid message, a ROS map or a world."""
    data = read_yaml(p)
    if _is_costmap_yaml(data):  # a Nav2 costmap (write_costmap): its costs, not thresholded
        _check_options(read_costmap, options, p, "costmap YAML")
        return read_costmap(p)
    if _is_occupancy_grid_yaml(data):  # a nav_msgs/OccupancyGrid message (ros2 topic echo --once /map)
        _check_options(read_occupancy_grid, options, p, "OccupancyGrid message YAML")
        return read_occupancy_grid(p, **options)
    # a ROS map YAML names its image; one that lacks it still has an origin (a world has bounds instead)
    if isinstance(data, dict) and ("image" in data or ("origin" in data and "bounds" not in data)):
        _check_options(read_ros_map, options, p, "ROS map YAML")
        return read_ros_map(p, **options)
    if options:
        raise ParameterError(
            f"{p}: option{'s' if len(options) > 1 else ''} {', '.join(sorted(options))} "
            f"{'do' if len(options) > 1 else 'does'} not apply to a world file (a world is rasterized later, e.g. by gridfield.geometry.rasterize.as_gridmap)"
        )
    return world_from_dict(data, source=str(p))


def read(path: PathLike, **options: Any) -> Any:
    """Read any supported map or world file; a world YAML gives a :class:`World`, the rest a :class:`GridMap`
    (a lazy one for the formats read by chunks; a gridfield Zarr store gives what it holds).

    ``options`` go to the format's reader (e.g. ``unknown="free"`` for ROS maps, ``resolution``
    for bitmaps, ``occupancy="nonzero"`` for a label image or array). Options whose value is ``None`` mean "the default" and are dropped; an
    option the format's reader does not take raises :class:`ParameterError`.

    Parameters
    ----------
    path : str or path-like
        ``.yaml``/``.yml`` (a world, a Nav2 costmap (:func:`read_costmap`) when it has a ``costmap:`` key, or a ROS map when it names an ``image`` or has an ``origin`` but no
        ``bounds``), ``.png``/``.pgm``/``.bmp``, ``.map`` (Moving AI), ``.npz`` (gridfield),
        ``.tif``/``.tiff`` (BigTIFF/GeoTIFF), ``.npy`` or a ``.zarr`` directory (a gridfield store or a
        plain array), the last three read by chunks; or a folder holding one map file (a ROS map's
        folder: its ``.yaml``), read as that file. A ``.map``, ``.pgm``, ``.png`` or ``.bmp`` file may be
        gzip-compressed (``arena.map.gz``). Voxel maps: ``.3dmap`` (Moving AI 3-D, also ``.3dmap.gz``),
        ``.binvox``, ``.ply``/``.xyz`` point clouds (``resolution=`` required), a 3-D ``.npy``.
    **options
        Keyword options of the format's reader (:func:`read_ros_map`, :func:`read_bitmap`,
        :func:`read_movingai_map`, :func:`read_tiff`, :func:`read_npy`, :func:`read_zarr_array`,
        :func:`read_3dmap`, :func:`read_binvox`, :func:`read_pointcloud`, :func:`read_voxel_npy`; a world
        file and ``.npz`` take none).

    Returns
    -------
    World, GridMap, LazyGridMap, DistanceMap or Field
        What the format's reader returns.

    Examples
    --------
    >>> type(read(bundled_map("seed000.yaml"))).__name__, read(bundled_map("arena/arena.map")).shape
    ('World', (49, 49))
    """
    options = {k: v for k, v in options.items() if v is not None}
    path = local_path(path)
    if is_url(path):  # s3://, gs://, memory://...: the formats read by chunks (fsspec)
        return _read_url(str(path), options)
    if isinstance(path, str | os.PathLike) and (
            (FsPath(path).suffix.lower() == ".zarr" and not FsPath(path).is_file())
            or (FsPath(path) / "zarr.json").is_file()):
        return read_zarr(path, **options)  # a directory: a Zarr store or array
    if isinstance(path, str | os.PathLike) and FsPath(path).is_dir():
        path = _map_in_folder(FsPath(path))  # a ROS map's folder (map.yaml + map.pgm), say
    p = _check_file(path)
    suffix = inner_suffix(p)
    if is_gzip(p) and suffix not in GZ_FORMATS:
        raise MapFormatError(
            f"{p}: gzip-compressed maps are read for {', '.join(f + '.gz' for f in GZ_FORMATS)}; "
            f"decompress this {shorten(suffix or 'file')} first")
    reader: Callable[..., GridMap]
    if suffix in (".yaml", ".yml"):
        return _read_yaml_map(p, options)
    if suffix in (".png", ".pgm", ".bmp"):
        reader, what = read_bitmap, "bitmap"
    elif suffix == ".map":
        reader, what = read_movingai_map, "Moving AI map"
    elif suffix == ".npz":
        reader, what = read_npz, "gridfield .npz file"
    elif (voxel := _voxel_reader(p, suffix)) is not None:  # a voxel map (issue 44)
        reader, what = voxel
    elif suffix in (".tif", ".tiff"):
        reader, what = read_tiff, "TIFF raster"
    elif suffix == ".npy":
        reader, what = read_npy, ".npy array"
    else:
        raise MapFormatError(
            f"{p}: unknown map format {shorten(suffix)}; expected a world or ROS map .yaml, a .png/.pgm/.bmp bitmap, "
            "a Moving AI .map or .3dmap, a gridfield .npz, a .tif/.tiff raster, a .npy array, a .binvox file, a "
            ".ply/.xyz point cloud or a .zarr store"
        )
    _check_options(reader, options, p, what)
    return reader(p, **options)
