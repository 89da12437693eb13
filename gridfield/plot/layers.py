"""Deprecated: the drawing layers moved to the private module ``gridfield.plot._layers``.

``gridfield.plot.layers.Artists`` still works for one release, with a :class:`DeprecationWarning`:
import :class:`~gridfield.plot.Artists` (and the layers other code draws with,
:func:`~gridfield.plot.draw_outlines`, :func:`~gridfield.plot.frame_axes`,
:func:`~gridfield.plot.potential_scale`, :func:`~gridfield.plot.stall_points`,
:func:`~gridfield.plot.title_of`) from :mod:`gridfield.plot`.
"""

from __future__ import annotations

from typing import Any

__all__: list[str] = []

_MOVED = frozenset({"Artists", "OCCUPIED_COLOR"})


def __getattr__(name: str) -> Any:
    """``gridfield.plot.layers.Artists``: deprecated alias of :class:`gridfield.plot.Artists`."""
    if name in _MOVED:
        import warnings

        from . import _layers

        warnings.warn(f"gridfield.plot.layers.{name} is deprecated: import it from gridfield.plot",
                      DeprecationWarning, stacklevel=2)
        return getattr(_layers, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
