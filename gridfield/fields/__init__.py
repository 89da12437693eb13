"""Potential fields and navigation functions on grid maps: attractive/repulsive potentials, vortex
fields, the complete models (NF1 and friends), wavefront, fast marching, harmonic and star-world
navigation functions, Nav2 costmaps and NavFn, and the samplers the followers read fields with.

Its public names load on first use (``lazy_loader``; ``__init__.pyi`` lists them); the modules: :mod:`~gridfield.fields.costmap`, :mod:`~gridfield.fields.incremental`, :mod:`~gridfield.fields.navfield`, :mod:`~gridfield.fields.navfn`, :mod:`~gridfield.fields.navigation`, :mod:`~gridfield.fields.navtable`, :mod:`~gridfield.fields.potential`, :mod:`~gridfield.fields.potential_args`, :mod:`~gridfield.fields.sampler_args`, :mod:`~gridfield.fields.sampling`, :mod:`~gridfield.fields.vortex`.
"""

import lazy_loader as _lazy

__getattr__, __dir__, __all__ = _lazy.attach_stub(__name__, __file__)
