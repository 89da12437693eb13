"""The bottom layer: grids and their maps, coordinates, errors, the parameter registry, the size and
time guards, paths and the other result types, the chunk cache of maps read by chunks.

It imports nothing else of gridfield; every other layer builds on it.

Its public names load on first use (``lazy_loader``; ``__init__.pyi`` lists them); the modules: :mod:`~gridfield.core.chunkcache`, :mod:`~gridfield.core.coords`, :mod:`~gridfield.core.errors`, :mod:`~gridfield.core.grid`, :mod:`~gridfield.core.limits`, :mod:`~gridfield.core.params`, :mod:`~gridfield.core.path`, :mod:`~gridfield.core.planner_table`, :mod:`~gridfield.core.results`.
"""

import lazy_loader as _lazy

__getattr__, __dir__, __all__ = _lazy.attach_stub(__name__, __file__)
