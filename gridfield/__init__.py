"""gridfield: grid-based robot path planning with brushfire distance maps and potential fields.

The curated API, importable from the top level (each name loads its module on first use through
``lazy_loader``, so ``import gridfield`` stays light; ``gridfield/__init__.pyi`` lists them for editors,
mypy and the loader)::

    import gridfield as gf

    world = gf.read(gf.bundled_map("seed000.yaml"))      # a World (or a GridMap for map files)
    path = gf.plan("potential", world, world.start, world.goal)
    gm = gf.rasterize(world, 0.1)                          # -> GridMap
    dmap = gf.brushfire(gm)                                # -> DistanceMap
    field = gf.build_field(gm, world.goal)                 # -> Field
    path = gf.follow(field, world.start)                   # -> Path

The layers, each a subpackage that imports only those below it (ARCHITECTURE.md; ``lint-imports``)::

    core -> geometry -> distance -> fields -> io -> chunked -> following -> exact
         -> planners -> compare -> plot / sweep -> explore / demo -> cli

Heavy modules (matplotlib, scipy.ndimage, the compiled kernels) are imported only when used.

Examples
--------
>>> import gridfield as gf
>>> gf.plan("wavefront", gf.GridMap(gf.Grid((1, 4), 1.0), [[0, 0, 0, 0]]), (0.5, 0.5), (3.5, 0.5)).status
'reached'
"""

import lazy_loader as _lazy

from ._version import __version__ as __version__

__getattr__, _lazy_dir, __all__ = _lazy.attach_stub(__name__, __file__)
__all__ = sorted({*__all__, "__version__"})


def __dir__() -> list[str]:
    return list(__all__)
