/* Row loops of gridfield/distance/_chamfer.pyx and _edt.pyx, in C so that GCC vectorizes them for the CPU.
 *
 * The same arithmetic as the Cython loops they replace, in int32 (every value fits: distances in cells
 * stay below a few times rows + cols, rows below 2**30): GCC vectorizes int32 compare-selects at every
 * ISA level, while the int64 selects of the earlier loops only vectorized with AVX-512 (SSE2 has no
 * 64-bit compare), so the baseline build ran them scalar. Each function is compiled three times on
 * x86-64 Linux (x86-64-v4 / AVX2 / baseline, picked by the loader for the CPU), as in
 * _potential_rows.h. Integer arithmetic and one multiplication by the resolution: results are
 * bit-identical across the clones and to the earlier loops (no FMA: -ffp-contract=off in setup.py).
 */
#ifndef GRIDFIELD_BRUSHFIRE_ROWS_H
#define GRIDFIELD_BRUSHFIRE_ROWS_H

#include <math.h>
#include <stdint.h>
#if defined(__SSE2__)
#include <emmintrin.h> /* gf_scale_row's non-temporal stores (x86-64: always there) */
#endif

/* GF_NO_CLONES (a -D flag): one baseline copy of each function, to check it against the clones.
 * "unused": each kernel module calls only its own loops (the chamfer ones or the Euclidean ones); GCC
 * emits no code for the others either way, the attribute only spares the warning. */
#if defined(GF_NO_CLONES)
#define GF_BF_FN static inline
#elif defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__) && __GNUC__ >= 11
#define GF_BF_FN __attribute__((target_clones("arch=x86-64-v4", "avx2", "default"), unused)) static
#elif defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__)
#define GF_BF_FN __attribute__((target_clones("avx2", "default"), unused)) static
#else
#define GF_BF_FN static inline
#endif

static inline int32_t gf_min32(int32_t a, int32_t b) { return a < b ? a : b; }

/* Forward pass, one row: t[c] = 0 on an obstacle, else 1 + the least of the up-left, up, up-right
 * neighbours (conn8) or of the up neighbour. `up` is the previous row of steps, NULL for the first
 * row (every neighbour is then `edge_row`); the columns beside the grid count as `pad` (as the padded
 * row of the earlier loop). */
GF_BF_FN void gf_chamfer_fwd_pre(const int32_t *restrict up, int32_t edge_row, int32_t pad, const uint8_t *restrict occ,
                                 int32_t *restrict t, int64_t cols, int conn8) {
    const int n = (int)cols;
    if (up == NULL) {
        const int32_t inner = edge_row + 1;
        const int32_t side = (conn8 ? gf_min32(pad, edge_row) : edge_row) + 1;
        for (int c = 0; c < n; c++) t[c] = occ[c] ? 0 : inner;
        if (n > 0) {
            t[0] = occ[0] ? 0 : side;
            t[n - 1] = occ[n - 1] ? 0 : side;
        }
        return;
    }
    if (!conn8) {
        for (int c = 0; c < n; c++) t[c] = occ[c] ? 0 : up[c] + 1;
        return;
    }
    if (n == 1) {
        t[0] = occ[0] ? 0 : gf_min32(gf_min32(pad, up[0]), pad) + 1;
        return;
    }
    for (int c = 1; c < n - 1; c++) {
        const int32_t a = gf_min32(gf_min32(up[c - 1], up[c]), up[c + 1]) + 1;
        t[c] = occ[c] ? 0 : a;
    }
    t[0] = occ[0] ? 0 : gf_min32(gf_min32(pad, up[0]), up[1]) + 1;
    t[n - 1] = occ[n - 1] ? 0 : gf_min32(gf_min32(up[n - 2], up[n - 1]), pad) + 1;
}

/* Backward pass, one row: t[c] = min(s[c], 1 + the least of the down neighbours), `down` as `up` above. */
GF_BF_FN void gf_chamfer_bwd_pre(const int32_t *restrict down, int32_t edge_row, int32_t pad,
                                 const int32_t *restrict s, int32_t *restrict t, int64_t cols, int conn8) {
    const int n = (int)cols;
    if (down == NULL) {
        const int32_t inner = edge_row + 1;
        const int32_t side = (conn8 ? gf_min32(pad, edge_row) : edge_row) + 1;
        for (int c = 0; c < n; c++) t[c] = gf_min32(inner, s[c]);
        if (n > 0) {
            t[0] = gf_min32(side, s[0]);
            t[n - 1] = gf_min32(side, s[n - 1]);
        }
        return;
    }
    if (!conn8) {
        for (int c = 0; c < n; c++) t[c] = gf_min32(down[c] + 1, s[c]);
        return;
    }
    if (n == 1) {
        t[0] = gf_min32(gf_min32(gf_min32(pad, down[0]), pad) + 1, s[0]);
        return;
    }
    for (int c = 1; c < n - 1; c++) {
        const int32_t a = gf_min32(gf_min32(down[c - 1], down[c]), down[c + 1]) + 1;
        t[c] = gf_min32(a, s[c]);
    }
    t[0] = gf_min32(gf_min32(gf_min32(pad, down[0]), down[1]) + 1, s[0]);
    t[n - 1] = gf_min32(gf_min32(gf_min32(down[n - 2], down[n - 1]), pad) + 1, s[n - 1]);
}

/* distance = steps * resolution, one row.
 * stream: non-temporal stores (SSE2 movntpd; d 16-byte aligned, else plain stores): the line is not
 *   read for ownership first, and the row does not evict the steps the pass still reads. For grids
 *   far larger than the caches (the caller decides), whose distance is not read back soon.
 *   4096^2 chessboard, steps + distance, 1 thread, in one process alternating: 40-41 ms CPU with the
 *   prefetch below, 34-36 ms streamed (the earlier trial of streaming, in the README, predates both).
 * otherwise, if `next_d` is not NULL, the distance row written next is prefetched for writing, a
 *   line for every line written here (the backward pass writes its rows from the bottom up, which
 *   the hardware prefetcher does not foresee: 43-47 -> 38-41 ms). Prefetching the steps row read
 *   next, or the forward pass's next row for writing, gained nothing. */
GF_BF_FN void gf_scale_row(const int32_t *restrict s, double res, double *restrict d, int64_t cols,
                           const double *next_d, int stream) {
    const int n = (int)cols;
    int c = 0;
#if defined(__SSE2__)
    if (stream && ((uintptr_t)d & 15) == 0) {
        const __m128d rv = _mm_set1_pd(res);
        for (; c + 4 <= n; c += 4) {
            __m128i x;
            __builtin_memcpy(&x, s + c, sizeof x);
            const __m128d lo = _mm_cvtepi32_pd(x);
            const __m128d hi = _mm_cvtepi32_pd(_mm_unpackhi_epi64(x, x));
            _mm_stream_pd(d + c, _mm_mul_pd(lo, rv));
            _mm_stream_pd(d + c + 2, _mm_mul_pd(hi, rv));
        }
        _mm_sfence();
    } else
#else
    (void)stream;
#endif
    if (next_d != NULL) {
        for (; c + 16 <= n; c += 16) {
            __builtin_prefetch(next_d + c, 1, 3);
            __builtin_prefetch(next_d + c + 8, 1, 3);
            for (int j = 0; j < 16; j++) d[c + j] = (double)s[c + j] * res;
        }
    }
    for (; c < n; c++) d[c] = (double)s[c] * res;
}

/* Column pass, downward step: vrow[c] = r on an obstacle, else the row above's value (columns c0:c1). */
GF_BF_FN void gf_column_down(const uint8_t *restrict occ, const int32_t *restrict prev, int32_t *restrict vrow,
                             int32_t r, int64_t c0, int64_t c1) {
    for (int c = (int)c0; c < (int)c1; c++) vrow[c] = occ[c] ? r : prev[c];
}

/* Column pass, upward step: keep the nearest obstacle above (vrow) unless the one below (prev) is
 * strictly nearer. Rows are below 2**30 and the sentinels +-2**30: no difference overflows. */
GF_BF_FN void gf_column_up(const int32_t *restrict prev, int32_t *restrict vrow, int32_t r, int64_t c0, int64_t c1) {
    for (int c = (int)c0; c < (int)c1; c++) {
        const int32_t a = vrow[c], b = prev[c];
        vrow[c] = (b - r) < (r - a) ? b : a;
    }
}

/* Row pass input: g[c + 1] = min(|r - v[c]|, inf), rowv[c + 1] = v[c] (int64, for the envelope). */
GF_BF_FN void gf_edt_gather(const int32_t *restrict v, int32_t r, int32_t inf, int64_t *restrict g,
                            int64_t *restrict rowv, int64_t cols) {
    const int n = (int)cols;
    for (int c = 0; c < n; c++) {
        const int32_t x = v[c];
        const int32_t d = r >= x ? r - x : x - r;
        g[c + 1] = d < inf ? d : inf;
        rowv[c + 1] = x;
    }
}

/* Row pass output: distance = sqrt(val) * res. */
GF_BF_FN void gf_edt_distance(const int64_t *restrict val, double res, double *restrict d, int64_t cols) {
    const int n = (int)cols;
    for (int c = 0; c < n; c++) d[c] = sqrt((double)val[c]) * res;
}

/* Row pass of the Euclidean transform, local window (the common case: obstacles nearby).
 *
 * The exact answer of a cell x is the least f_s(x) = (x - s)**2 + g_s**2 over the sites s, ties to the
 * smallest s (what the lower envelope gives: checked against brute force). Every site farther than
 * K columns has f >= (K + 1)**2 = T, so if some site within K columns has f < T, the least f over the
 * 2K + 1 sites of the window is the exact answer, tie included. The window is one branch-free min
 * over 2K + 1 shifted rows, in int16 (GCC vectorizes it at every ISA level): the key
 * f * 16 + (d + K) orders by f, then by the site's column (d = s - x in -K..K), and g is clamped to
 * K + 1 (a clamped site has f >= T: it never decides a cell the window vouches for). Cells whose
 * window minimum is >= T are exceptions, solved by the caller (exact search or the envelope).
 *
 * Padded layout: site s (0 = the column left of the grid, n + 1 = right of it, c + 1 = column c) is
 * h[s + K - 1], for s in 1 - K .. n + K (n + 2K values); the caller fills the pad. */
#define GF_EDT_K 4
#define GF_EDT_W (2 * GF_EDT_K + 1)
#define GF_EDT_T ((GF_EDT_K + 1) * (GF_EDT_K + 1))
_Static_assert(GF_EDT_K >= 1 && GF_EDT_K <= 7, "the keys hold d + K in 4 bits and 16 * f in int16");

/* rv[c + 1] = v[c] (the row's nearest obstacle rows, kept: v may be overwritten by the outputs),
 * h[c + K] = 16 * min(|r - v[c]|, K + 1)**2 (blocks of 16 in vector registers: the int32 -> int16
 * loop stayed scalar). */
typedef int16_t gf_v16s __attribute__((vector_size(32)));
typedef int32_t gf_v16i __attribute__((vector_size(64)));

GF_BF_FN void gf_edt_local_gather(const int32_t *restrict v, int32_t r, int32_t *restrict rv, int16_t *restrict h,
                                  int64_t cols) {
    const int n = (int)cols;
    const int nb = n / 16 * 16;
    int c;
    __builtin_memcpy(rv + 1, v, (size_t)n * sizeof(int32_t));
    for (c = 0; c < nb; c += 16) {
        gf_v16i x, d, e;
        __builtin_memcpy(&x, v + c, sizeof x);
        const gf_v16i ge = x <= r;
        d = (ge & (r - x)) | (~ge & (x - r));
        const gf_v16i lt = d < GF_EDT_K + 1;
        e = (lt & d) | (~lt & (GF_EDT_K + 1));
        const gf_v16s o = __builtin_convertvector(e * e * 16, gf_v16s);
        __builtin_memcpy(h + c + GF_EDT_K, &o, sizeof o);
    }
    for (; c < n; c++) {
        const int32_t x = v[c];
        const int32_t d = r >= x ? r - x : x - r;
        const int32_t e = d < GF_EDT_K + 1 ? d : GF_EDT_K + 1;
        h[c + GF_EDT_K] = (int16_t)(e * e * 16);
    }
}

/* key[c] = min over j in 0..2K of h[c + j] + 16 * (j - K)**2 + j (site c + 1 + j - K). Blocks of 16
 * cells in vector registers (GCC vector extensions: the plain loop nest stayed scalar). The keys of
 * different j differ in their low bits, so the minimum is that of the (f, site) pairs. */
GF_BF_FN void gf_edt_local_keys(const int16_t *restrict h, int16_t *restrict key, int64_t cols) {
    const int n = (int)cols;
    const int nb = n / 16 * 16;
    int c;
    for (c = 0; c < nb; c += 16) {
        gf_v16s acc, x;
        __builtin_memcpy(&acc, h + c, sizeof acc);
        acc += (int16_t)(GF_EDT_K * GF_EDT_K * 16);
        for (int j = 1; j < GF_EDT_W; j++) {
            __builtin_memcpy(&x, h + c + j, sizeof x);
            x += (int16_t)((j - GF_EDT_K) * (j - GF_EDT_K) * 16 + j);
            const gf_v16s lt = x < acc;
            acc = (lt & x) | (~lt & acc);
        }
        __builtin_memcpy(key + c, &acc, sizeof acc);
    }
    for (; c < n; c++) {
        int16_t k = INT16_MAX;
        for (int j = 0; j < GF_EDT_W; j++) {
            const int16_t cand = (int16_t)(h[c + j] + ((j - GF_EDT_K) * (j - GF_EDT_K) * 16 + j));
            k = cand < k ? cand : k;
        }
        key[c] = k;
    }
}

/* From the keys: distance = sqrt(f) * res (as gf_edt_distance), ncol = the winning site's column;
 * returns the number of exceptions (f >= T; their outputs are to be overwritten). */
GF_BF_FN int gf_edt_local_out(const int16_t *restrict key, double res, double *restrict d, int32_t *restrict ncol,
                              int64_t cols) {
    const int n = (int)cols;
    int bad = 0;
    for (int c = 0; c < n; c++) {
        const int32_t k = key[c];
        const int32_t f = k >> 4;
        d[c] = sqrt((double)f) * res;
        ncol[c] = c + (k & 15) - GF_EDT_K;
        bad += f >= GF_EDT_T;
    }
    return bad;
}

/* nrow[c] = rv[ncol[c] + 1]: the row of each cell's nearest obstacle (rv as gf_edt_local_gather's,
 * rv[0] = rv[n + 1] = r for the wall columns). */
GF_BF_FN void gf_edt_local_rows(const int32_t *restrict rv, const int32_t *restrict ncol, int32_t *restrict nrow,
                                int64_t cols) {
    const int n = (int)cols;
    for (int c = 0; c < n; c++) nrow[c] = rv[ncol[c] + 1];
}

/* The horizontal scans of the chamfer passes as a prefix (suffix) minimum, which vectorizes:
 *   right: s[c] = min(t[c], s[c - 1] + 1), s[-1] = edge  <=>  s[c] = c + min(edge + 1, min_{j <= c} (t[j] - j))
 *   left:  s[c] = min(t[c], s[c + 1] + 1), s[n] = edge   <=>  s[c] = -c + min(edge + n, min_{j >= c} (t[j] + j))
 * Exact integer identities, so the values are those of the recurrences. Blocks of 8: first the
 * minimum within each block in registers (log steps of shifted minima), then one pass carrying the
 * running minimum from block to block (one scalar min per block: the only serial chain). */
typedef int32_t gf_v8i __attribute__((vector_size(32)));
#define GF_V8_MIN(a, b) (((a) < (b)) & (a)) | (~((a) < (b)) & (b))

GF_BF_FN void gf_scan_right(const int32_t *restrict t, int32_t *restrict s, int64_t cols, int32_t edge) {
    const int n = (int)cols;
    const gf_v8i iota = {0, 1, 2, 3, 4, 5, 6, 7};
    const gf_v8i big = {INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX};
    const gf_v8i sh1 = {8, 0, 1, 2, 3, 4, 5, 6}, sh2 = {8, 8, 0, 1, 2, 3, 4, 5}, sh4 = {8, 8, 8, 8, 0, 1, 2, 3};
    const int nb = n / 8 * 8;
    int c;
    for (c = 0; c < nb; c += 8) {
        gf_v8i x, y;
        __builtin_memcpy(&x, t + c, sizeof x);
        x -= iota + c;
        y = __builtin_shuffle(x, big, sh1);
        x = GF_V8_MIN(x, y);
        y = __builtin_shuffle(x, big, sh2);
        x = GF_V8_MIN(x, y);
        y = __builtin_shuffle(x, big, sh4);
        x = GF_V8_MIN(x, y);
        __builtin_memcpy(s + c, &x, sizeof x);
    }
    int32_t carry = edge + 1;
    for (c = 0; c < nb; c += 8) {
        gf_v8i x;
        const int32_t last = s[c + 7];
        __builtin_memcpy(&x, s + c, sizeof x);
        const gf_v8i cv = big * 0 + carry;
        x = GF_V8_MIN(x, cv);
        x += iota + c;
        __builtin_memcpy(s + c, &x, sizeof x);
        carry = gf_min32(carry, last);
    }
    for (c = nb; c < n; c++) {
        carry = gf_min32(carry, t[c] - c);
        s[c] = carry + c;
    }
}

GF_BF_FN void gf_scan_left(const int32_t *restrict t, int32_t *restrict s, int64_t cols, int32_t edge) {
    const int n = (int)cols;
    const gf_v8i iota = {0, 1, 2, 3, 4, 5, 6, 7};
    const gf_v8i big = {INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX};
    const gf_v8i sh1 = {1, 2, 3, 4, 5, 6, 7, 8}, sh2 = {2, 3, 4, 5, 6, 7, 8, 8}, sh4 = {4, 5, 6, 7, 8, 8, 8, 8};
    const int head = n % 8; /* blocks of 8 end at n; the first `head` cells are done last, one by one */
    int c;
    for (c = head; c < n; c += 8) {
        gf_v8i x, y;
        __builtin_memcpy(&x, t + c, sizeof x);
        x += iota + c;
        y = __builtin_shuffle(x, big, sh1);
        x = GF_V8_MIN(x, y);
        y = __builtin_shuffle(x, big, sh2);
        x = GF_V8_MIN(x, y);
        y = __builtin_shuffle(x, big, sh4);
        x = GF_V8_MIN(x, y);
        __builtin_memcpy(s + c, &x, sizeof x);
    }
    int32_t carry = edge + n;
    for (c = n - 8; c >= head; c -= 8) {
        gf_v8i x;
        const int32_t first = s[c];
        __builtin_memcpy(&x, s + c, sizeof x);
        const gf_v8i cv = big * 0 + carry;
        x = GF_V8_MIN(x, cv);
        x -= iota + c;
        __builtin_memcpy(s + c, &x, sizeof x);
        carry = gf_min32(carry, first);
    }
    for (c = head - 1; c >= 0; c--) {
        carry = gf_min32(carry, t[c] + c);
        s[c] = carry - c;
    }
}

/* Memory of the large output arrays (see _take / _release in _brushfire.pyx): anonymous
 * mappings on Linux, advised for transparent huge pages as numpy advises its own large arrays; malloc
 * elsewhere. gf_map returns NULL when out of memory. */
#if defined(__linux__)
#include <sys/mman.h>
static inline void *gf_map(size_t n) {
    void *p = mmap(NULL, n, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) return NULL;
#ifdef MADV_HUGEPAGE
    madvise(p, n, MADV_HUGEPAGE);
#endif
    return p;
}
static inline void gf_unmap(void *p, size_t n) { munmap(p, n); }
#else
#include <stdlib.h>
static inline void *gf_map(size_t n) { return malloc(n); }
static inline void gf_unmap(void *p, size_t n) { (void)n; free(p); }
#endif

#endif
