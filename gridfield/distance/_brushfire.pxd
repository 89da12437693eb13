# C-level declarations of gridfield/distance/_brushfire.pyx shared with the other brushfire kernels
# (cimported by _chamfer.pyx and _edt.pyx): the array types and inline helpers, compiled into each
# module that cimports them -- among them the label gather of each row, which _brushfire's label pass
# and the Euclidean row pass of _edt.pyx both run (inline, as before the split: no call per row).
from libc.stdint cimport int32_t, int64_t, uint8_t
from libc.stdlib cimport malloc

ctypedef const uint8_t[:, ::1] occ_t
ctypedef int32_t[:, ::1] i32_2d
ctypedef double[:, ::1] f64_2d


cdef inline int64_t _lmin(int64_t a, int64_t b) noexcept nogil:
    return a if a < b else b


cdef inline int64_t _lmax(int64_t a, int64_t b) noexcept nogil:
    return a if a > b else b


cdef inline void* _alloc(size_t n) noexcept nogil:
    return malloc(n if n > 0 else 1)


cdef inline void _gather_labels32(const int32_t* nr, const int32_t* nc, int64_t n, int64_t rows, int64_t cols,
                                  const int32_t* flat, const int32_t* comp_map, bint use_map,
                                  int32_t* out) noexcept nogil:
    """``out[c]`` = label of the cell ``(nr[c], nc[c])``: ``flat[nr * cols + nc]``, mapped through
    ``comp_map`` if ``use_map``. ``flat`` is the label grid raveled plus one last element for any cell
    outside the grid (the wall), so that the loop is a plain gather."""
    cdef int64_t outside = rows * cols, c, a, b, inside
    if use_map:
        for c in range(n):
            a = nr[c]
            b = nc[c]
            inside = (a >= 0) & (a < rows) & (b >= 0) & (b < cols)
            out[c] = comp_map[flat[outside + (a * cols + b - outside) * inside]]
    else:
        for c in range(n):
            a = nr[c]
            b = nc[c]
            inside = (a >= 0) & (a < rows) & (b >= 0) & (b < cols)
            out[c] = flat[outside + (a * cols + b - outside) * inside]
