"""Vector worlds and the geometry on them: obstacles and robots (:class:`World`), convex polygons,
the rasterizer (world -> :class:`~gridfield.core.grid.GridMap`), grid maps as polygons and the
robot's configuration space (:mod:`gridfield.geometry.cspace`).

Its public names load on first use (``lazy_loader``; ``__init__.pyi`` lists them); the modules: :mod:`~gridfield.geometry.cspace`, :mod:`~gridfield.geometry.gridpoly`, :mod:`~gridfield.geometry.rasterize`, :mod:`~gridfield.geometry.world`.
"""

import lazy_loader as _lazy

__getattr__, __dir__, __all__ = _lazy.attach_stub(__name__, __file__)
