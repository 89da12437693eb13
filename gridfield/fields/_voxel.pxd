"""Inline helpers of the voxel kernels (``_navigation3.pyx``, ``_voxelpath.pyx``): the array types and
the bounding-box move rule (compiled into each module that cimports them; no module state)."""

from libc.stdint cimport int64_t, uint8_t

ctypedef const uint8_t[:, :, :] mask3_t
ctypedef const double[:, :, :] val3_t


cdef inline bint _voxel_free(mask3_t free, int64_t k, int64_t r, int64_t c, bint periodic) noexcept nogil:
    """Whether voxel ``(k, r, c)`` is inside the grid (axis 0 wrapped when ``periodic``) and free."""
    cdef int64_t n0 = free.shape[0]
    if periodic:
        k = (k % n0 + n0) % n0
    elif k < 0 or k >= n0:
        return False
    if r < 0 or r >= free.shape[1] or c < 0 or c >= free.shape[2]:
        return False
    return free[k, r, c] != 0


cdef inline bint _move_ok(mask3_t free, int64_t k, int64_t r, int64_t c, int a, int b, int d,
                          bint periodic) noexcept nogil:
    """Whether the move ``(a, b, d)`` from ``(k, r, c)`` keeps its bounding box in free voxels."""
    cdef int ea, eb, ed
    for ea in range(2):
        for eb in range(2):
            for ed in range(2):
                if not _voxel_free(free, k + ea * a, r + eb * b, c + ed * d, periodic):
                    return False
    return True
