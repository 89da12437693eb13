# C-level declarations of gridfield/exact/_occlusion.pyx shared with the other kernel modules
# (cimported by _astar.pyx: the lazy A* runs the nearest-first visibility search from each corner it expands).
from libc.stdint cimport int32_t, int64_t, uint8_t

cdef enum:
    _NB = 1024  # angular bins of the occlusion table (N_BINS)


cdef struct Ext:  # run_extents of the padded array (each R x W, C-contiguous)
    const int32_t* hl
    const int32_t* hr
    const int32_t* vl
    const int32_t* vr


cdef struct Prune:  # the lazy search's filters of :func:`_visible_set` (NULL: none, every visible corner)
    double hx        # taut half-plane: only directions (dx, dy) with hx * dy - hy * dx >= 0
    double hy
    const uint8_t* closed  # corners already closed: not reported (:func:`_improves`)
    const double* g        # their best start distances so far: a corner is walked only if gu + d < g[j]
    double gu
    double best            # and only if gu + d + |j - goal| < best
    double gx
    double gy


cdef Ext _ext(tuple ext, int64_t R, int64_t W)
cdef int64_t _visible_set(const uint8_t* B, int64_t R, int64_t W, const Ext* ext, double px, double py,
                          double self_q, const double* vx, const double* vy, const double* qx, const double* qy,
                          const int64_t* bstart, const int64_t* bverts, int64_t nbx, int64_t nby, double bsize,
                          int64_t jmin, double* D, int64_t nb, double* part, int64_t* out_j,
                          double* out_d, const Prune* pr) noexcept nogil
