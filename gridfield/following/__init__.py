"""Following a field: the step rules and the descent loop, the gradient follower, escapes from
local minima, basins of attraction and the diagnosis of a run that did not reach.

Its public names load on first use (``lazy_loader``; ``__init__.pyi`` lists them); the modules: :mod:`~gridfield.following.basins`, :mod:`~gridfield.following.descent`, :mod:`~gridfield.following.diagnose`, :mod:`~gridfield.following.escapes`, :mod:`~gridfield.following.follower`, :mod:`~gridfield.following.taut`.
"""

import lazy_loader as _lazy

__getattr__, __dir__, __all__ = _lazy.attach_stub(__name__, __file__)
