"""Exact-geometry planners on the same worlds: the continuous potential field, the visibility graph
and any-angle paths on grids (Polyanya), with their compiled kernels.

Its public names load on first use (``lazy_loader``; ``__init__.pyi`` lists them); the modules: :mod:`~gridfield.exact.anyangle`, :mod:`~gridfield.exact.continuous`, :mod:`~gridfield.exact.visibility`.
"""

import lazy_loader as _lazy

__getattr__, __dir__, __all__ = _lazy.attach_stub(__name__, __file__)
