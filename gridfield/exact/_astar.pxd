# C-level declarations of gridfield/exact/_astar.pyx shared with the other kernel modules
# (cimported by _polyanya.pyx, so that all the searches use one compiled binary heap).
from libc.stdint cimport int64_t


cdef struct Heap:
    double* k  # keys, a binary min-heap
    int64_t* v  # the value of each key
    int64_t size
    int64_t cap  # > 0: the arrays hold cap entries (grown by doubling)


cdef bint _heap_push(Heap* h, double f, int64_t j) noexcept nogil
cdef void _heap_pop(Heap* h) noexcept nogil
