"""Distance maps: the brushfire (8-connected wavefront; exact Euclidean with nearest obstacle and
labels; chessboard, taxicab) and its incremental update, with their compiled kernels beside them
(``_brushfire.pyx``, ``_incremental.pyx``).

Its public names load on first use (``lazy_loader``; ``__init__.pyi`` lists them); the modules: :mod:`~gridfield.distance.brushfire`, :mod:`~gridfield.distance.incremental`.
"""

import lazy_loader as _lazy

__getattr__, __dir__, __all__ = _lazy.attach_stub(__name__, __file__)
