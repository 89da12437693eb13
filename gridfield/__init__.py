"""gridfield: grid-based robot path planning with brushfire distance maps and potential fields.

The curated API, importable from the top level (each name loads its module on first use, so
``import gridfield`` stays light; ``gridfield/__init__.pyi`` declares them for editors and mypy)::

    import gridfield as gf

    world = gf.read(gf.bundled_map("seed000.yaml"))      # a World (or a GridMap for map files)
    path = gf.plan("potential", world, world.start, world.goal)
    gm = gf.rasterize(world, 0.1)                          # -> GridMap
    dmap = gf.brushfire(gm)                                # -> DistanceMap
    field = gf.build_field(gm, world.goal)                 # -> Field
    path = gf.follow(field, world.start)                   # -> Path

``gf.brushfire``, ``gf.follow`` and ``gf.rasterize`` are the modules of those names, callable as their
main function: ``import gridfield.brushfire as bf`` and ``bf.DistanceMap`` keep working, and
``gf.brushfire(gm)`` calls :func:`gridfield.brushfire.brushfire`.

Pipeline (the layers of ARCHITECTURE.md, enforced by ``lint-imports``)::

    io / world / grid -> rasterize / cspace -> brushfire -> potential -> follow -> planners -> plot

Heavy modules (matplotlib, scipy.ndimage, the compiled kernels) are imported only when used.

Examples
--------
>>> import gridfield as gf
>>> gf.plan("wavefront", gf.GridMap(gf.Grid((1, 4), 1.0), [[0, 0, 0, 0]]), (0.5, 0.5), (3.5, 0.5)).status
'reached'
"""

from __future__ import annotations

import importlib
import sys
import types
from typing import Any

#: The submodules that are also callable as their main function (same name): ``gridfield.brushfire(gm)``.
_CALLABLE_MODULES = ("brushfire", "follow", "rasterize")


class _CallableModule(types.ModuleType):
    """A submodule callable as the function of its own name (``gridfield.follow(...)`` is ``follow.follow(...)``)."""

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return getattr(self, self.__name__.rpartition(".")[2])(*args, **kwargs)


class _Package(types.ModuleType):
    """The ``gridfield`` package: a submodule of :data:`_CALLABLE_MODULES` becomes callable when it is
    imported (the import machinery sets it on the package; every way of importing it passes here)."""

    def __setattr__(self, name: str, value: Any) -> None:
        if name in _CALLABLE_MODULES and type(value) is types.ModuleType:
            value.__class__ = _CallableModule
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package

# the names every module uses (cheap; ``X as X``: re-exported)
from ._version import __version__ as __version__  # noqa: E402
from .errors import GridfieldError as GridfieldError  # noqa: E402
from .errors import MapFormatError as MapFormatError  # noqa: E402
from .errors import ParameterError as ParameterError  # noqa: E402
from .grid import Grid as Grid  # noqa: E402
from .grid import GridMap as GridMap  # noqa: E402
from .path import Path as Path  # noqa: E402

#: name -> the module that defines it (relative to gridfield), imported on first use.
_LAZY: dict[str, str] = {
    # reading and writing
    "read": "io", "read_world": "io", "bundled_map": "io", "save_field": "io", "load_field": "io",
    # maps
    "World": "world", "apply_robot": "cspace",
    # distance maps, fields, following
    "DistanceMap": "_results", "Field": "_results", "GradientField": "_results", "build_field": "potential", "follow_many": "follow",
    # navigation functions
    "NavigationField": "navigation", "navigation_field": "navigation", "wavefront": "navigation",
    # planning
    "plan": "planners", "plan_with_field": "planners", "Plan": "planners", "PLANNERS": "planners",
}

__all__ = sorted(["Grid", "GridMap", "GridfieldError", "MapFormatError", "ParameterError", "Path", "__version__",
                  *_LAZY, *_CALLABLE_MODULES])


def __getattr__(name: str) -> Any:
    if name in _CALLABLE_MODULES:
        return importlib.import_module(f"{__name__}.{name}")  # (set on the package, callable, by the import)
    if name in _LAZY:
        value = getattr(importlib.import_module(f"{__name__}.{_LAZY[name]}"), name)
        globals()[name] = value  # later look-ups skip this function
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
