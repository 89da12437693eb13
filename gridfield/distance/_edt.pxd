# C-level declarations of gridfield/distance/_edt.pyx shared with the other kernel modules
# (cimported by _incremental.pyx and gridfield/chunked/_chunked.pyx, so that all of them use one
# compiled lower envelope).
from libc.stdint cimport int64_t

cdef bint _edt_1d(const int64_t* g, int64_t n, int64_t inf, int64_t* s, int64_t* t, int64_t* val,
                  int64_t* arg) noexcept nogil
