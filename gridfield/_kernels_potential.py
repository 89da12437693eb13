"""Compiled kernels of the potentials: the fused attractive + nearest-obstacle repulsive pass.

Only kernels live here; parameters, models and the :class:`~gridfield.potential.Field` are in
:mod:`gridfield.potential`. Arrays follow the grid conventions (``[row, col]``, row 0 at the
lowest y, cell centres at ``origin + (col + 0.5, row + 0.5) * res``).
"""

import math

import numba
import numpy as np
from numba import njit, prange

__all__ = ["_attractive_kernel", "_khatib_kernel", "_rep_accumulate", "get_num_threads", "set_num_threads"]

get_num_threads = numba.get_num_threads
set_num_threads = numba.set_num_threads

_JIT = {"cache": True, "error_model": "numpy", "nogil": True}


@njit(inline="always", **_JIT)
def _rep_distance(fr, fc, res, metric, sat, far):  # pragma: no cover - compiled
    """``(D, |offset| in cells)`` for a nearest obstacle cell ``(fr, fc)`` cells away, after saturation."""
    length = math.sqrt(fr * fr + fc * fc)
    if metric == 0:
        dist = length * res
    elif metric == 1:
        dist = max(abs(fr), abs(fc)) * res
    else:
        dist = (abs(fr) + abs(fc)) * res
    return (far if dist >= sat else dist), length


@njit(inline="always", **_JIT)
def _attraction(d2, zeta, d_star, ds2, conic):  # pragma: no cover - compiled
    """``(U, k)`` of the attractive potential at squared distance ``d2`` from the goal, with
    ``grad U = k * (p - goal)``: quadratic within ``d_star`` (``ds2 = d_star**2``; ``inf``: everywhere,
    ``0``: the goal only), beyond it conic (``conic``: ``zeta*d``, the ``d_star = 0`` case) or the
    combined ``d_star*zeta*d - 0.5*zeta*d_star**2``. Selects, no jumps, so that callers' loops vectorize."""
    d = math.sqrt(d2)
    quad = d2 <= ds2
    u = 0.5 * zeta * d2 if quad else (zeta * d if conic else zeta * d_star * d - 0.5 * zeta * ds2)
    k = zeta if quad else (zeta / d if conic else zeta * d_star / d)
    return u, k


@njit(parallel=True, **_JIT)
def _attractive_kernel(x0, y0, res, goal_x, goal_y, zeta, d_star, conic, U, GX, GY):  # pragma: no cover
    """Attractive potential; branch-free (selects, no jumps) so that LLVM vectorizes the inner loop."""
    rows, cols = U.shape
    ds2 = d_star * d_star
    for r in prange(rows):
        dy = y0 + (r + 0.5) * res - goal_y
        for c in range(cols):
            dx = x0 + (c + 0.5) * res - goal_x
            u, k = _attraction(dx * dx + dy * dy, zeta, d_star, ds2, conic)
            U[r, c] = u
            GX[r, c] = k * dx
            GY[r, c] = k * dy


@njit(parallel=True, **_JIT)
def _khatib_kernel(occ, nr, nc, x0, y0, res, goal_x, goal_y, zeta, d_star, conic,
                   metric, eta, q_star, ipow, sat, far, U, GX, GY):  # pragma: no cover - compiled
    """Attractive + nearest-obstacle repulsive potential and gradient in one fused pass.

    Branch-free: every cell computes both terms and selects, so the inner loop vectorizes (a
    version with ``if``/``continue`` ran 8 times slower). The repulsive force is
    ``eta*(1/D - 1/q_star)/D**ipow`` for ``ipow`` in 0..4 (pass ``eta = 0`` for no repulsion);
    there is deliberately no float ``**``: other powers go through :func:`_rep_accumulate`.
    """
    rows, cols = occ.shape
    ds2 = d_star * d_star
    inv_q = 1.0 / q_star
    for r in prange(rows):
        dy = y0 + (r + 0.5) * res - goal_y
        for c in range(cols):
            # attractive
            dx = x0 + (c + 0.5) * res - goal_x
            u, k = _attraction(dx * dx + dy * dy, zeta, d_star, ds2, conic)
            gx = k * dx
            gy = k * dy
            # repulsive, from the nearest obstacle cell
            a = nr[r, c]
            b = nc[r, c]
            fr = float(r - a)
            fc = float(c - b)
            free = not occ[r, c]
            dist, length = _rep_distance(fr, fc, res, metric, sat, far)
            inside = free and (a != -1 or b != -1) and dist < q_star
            dist = dist if inside else 1.0
            length = length if inside else 1.0
            inv_d = 1.0 / dist
            s = inv_d - inv_q
            inv_d2 = inv_d * inv_d
            den = 1.0 if ipow == 0 else (inv_d if ipow == 1 else (inv_d2 if ipow == 2 else (
                inv_d2 * inv_d if ipow == 3 else inv_d2 * inv_d2)))
            m = eta * s * den / length  # |force| / |offset in cells|
            U[r, c] = (u + 0.5 * eta * s * s if inside else u) if free else np.inf
            GX[r, c] = (gx - m * fc if inside else gx) if free else 0.0
            GY[r, c] = (gy - m * fr if inside else gy) if free else 0.0


@njit(**_JIT)
def _rep_accumulate(occ, nr, nc, r_off, c_off, res, metric, eta, q_star, ipow, power, sat, far,
                    U, GX, GY):  # pragma: no cover - compiled
    """Add a repulsive term over a window (all arrays are that window), for any power.

    ``nr``/``nc`` are nearest obstacle cells in a frame shifted by ``(r_off, c_off)`` from the
    window's; ``(-1, -1)`` in the grid frame means "no obstacle". ``ipow < 0``: use the float ``power``.
    """
    rows, cols = occ.shape
    inv_q = 1.0 / q_star
    for r in range(rows):
        for c in range(cols):
            if occ[r, c]:
                continue
            a = nr[r, c]
            b = nc[r, c]
            if a == -1 and b == -1:
                continue
            fr = float(r + r_off - a)
            fc = float(c + c_off - b)
            dist, length = _rep_distance(fr, fc, res, metric, sat, far)
            if dist < q_star:
                s = 1.0 / dist - inv_q
                if ipow >= 0:
                    den = 1.0
                    for _ in range(ipow):
                        den *= dist
                else:
                    den = dist**power
                k = eta * s / (den * length)
                U[r, c] += 0.5 * eta * s * s
                GX[r, c] -= k * fc
                GY[r, c] -= k * fr
