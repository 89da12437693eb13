"""How a map and a field reach the compiled follower kernels (:mod:`gridfield.fields._samplers`):
contiguous occupancy with the grid's origin and resolution, and contiguous float64 gradients.

Private: shared by :mod:`gridfield.fields.sampling` (the samplers) and :mod:`gridfield.follow` (the batch
follower), so that both pass the kernels the same arguments.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from ..core.grid import GridMap
    from ..core.results import GradientField

__all__ = ["gradient_arrays", "grid_args"]


def grid_args(gridmap: GridMap) -> tuple[NDArray[np.bool_], float, float, float]:
    """The occupancy (C-contiguous bool), the origin's x and y and the resolution of ``gridmap``.

    Examples
    --------
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ, x0, y0, res = grid_args(GridMap(Grid((2, 3), 0.5, origin=(1.0, 2.0)), np.zeros((2, 3), bool)))
    >>> occ.flags.c_contiguous, x0, y0, res
    (True, 1.0, 2.0, 0.5)
    """
    g = gridmap.grid
    occ = np.ascontiguousarray(gridmap.occupied, dtype=np.bool_)
    return occ, float(g.origin[0]), float(g.origin[1]), float(g.resolution)


def gradient_arrays(field: GradientField) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``field.grad_x`` and ``field.grad_y`` as C-contiguous float64 arrays (no copy when they are).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> gx, gy = gradient_arrays(SimpleNamespace(grad_x=np.ones((2, 2), np.float32), grad_y=np.zeros((2, 2))))
    >>> gx.dtype, gy.dtype
    (dtype('float64'), dtype('float64'))
    """
    return (np.ascontiguousarray(field.grad_x, dtype=np.float64),
            np.ascontiguousarray(field.grad_y, dtype=np.float64))
