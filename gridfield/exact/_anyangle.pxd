# C-level declarations of gridfield/exact/_anyangle.pyx shared with the other kernel modules
# (cimported by _occlusion.pyx and _astar.pyx: the array types, the segment walk that the
# occlusion-culled visibility falls back on, and the edge list that both visibility passes fill).
from libc.stdint cimport int32_t, int64_t, uint8_t

ctypedef const uint8_t[:, ::1] blk_t
ctypedef const double[::1] f64c_1d
ctypedef const int64_t[::1] i64c_1d


cdef inline double _dmax(double a, double b) noexcept nogil:
    return a if a > b else b


cdef inline double _dmin(double a, double b) noexcept nogil:
    return a if a < b else b


cdef bint _segment_free(const uint8_t* B, int64_t W, double px, double py, double qx, double qy) noexcept nogil


cdef struct Edges:  # a growable list of edges (i, j)
    int32_t* ei
    int32_t* ej
    int64_t m
    int64_t cap


cdef bint _edges_init(Edges* e) noexcept nogil
cdef bint _edges_reserve(Edges* e, int64_t need) noexcept nogil
cdef object _edges_out(Edges* e)
