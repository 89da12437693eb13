/* Row loops of gridfield/_kernels_potential.pyx, in C so that GCC vectorizes them.
 *
 * GCC vectorizes a loop only if it can turn every branch into a select; it gives up on a ladder of
 * more than about two selects on loop-invariant values (the repulsive power) and on int64 -> double
 * conversions (no packed instruction before AVX-512). So: the loop counter is an int, coordinates
 * are converted from int32, the metric is two 2-way selects, and the power is unswitched by hand
 * (one copy of the loop per power 0..4). The arithmetic, operation by operation, is that of the
 * reference kernels: results are bit-identical (no FMA contraction: see setup.py's flags).
 */
#ifndef GRIDFIELD_POTENTIAL_ROWS_H
#define GRIDFIELD_POTENTIAL_ROWS_H

#include <math.h>
#include <stdint.h>

/* On x86-64 with GCC, the row loops are compiled three times (AVX-512 as x86-64-v4, AVX2, baseline SSE2)
 * and the loader picks one for the CPU (ifunc). No FMA contraction in any of them (-ffp-contract=off in
 * setup.py; FMA is never implied without it), so the results stay bit-identical across the clones.
 * The x86-64-v4 clone and the occupancy in its own pass (below) are there for speed: single-threaded,
 * the AVX2 clone alone took about twice as long (the figures: benchmarks/README.md, "The last two
 * ports, side by side with numba"). */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__) && __GNUC__ >= 11
#define GF_ROW_FN __attribute__((target_clones("arch=x86-64-v4", "avx2", "default"))) static
#elif defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__)
#define GF_ROW_FN __attribute__((target_clones("avx2", "default"))) static /* GCC < 11: no x86-64-v4 name */
#else
#define GF_ROW_FN static inline
#endif

GF_ROW_FN void gf_attractive_row(int64_t r, int64_t cols, double x0, double y0, double res, double goal_x,
                                     double goal_y, double zeta, double d_star, double ds2, int conic,
                                     double *restrict U, double *restrict GX, double *restrict GY) {
    const double dy = y0 + ((double)r + 0.5) * res - goal_y;
    const int n = (int)cols;
    for (int c = 0; c < n; c++) {
        const double dx = x0 + ((double)c + 0.5) * res - goal_x;
        const double d2 = dx * dx + dy * dy;
        const double d = sqrt(d2);
        const int quad = d2 <= ds2;
        const double kc = zeta / d, kb = zeta * d_star / d;
        const double uq = 0.5 * zeta * d2, uc = zeta * d, ub = zeta * d_star * d - 0.5 * zeta * ds2;
        const double k = quad ? zeta : (conic ? kc : kb);
        const double u = quad ? uq : (conic ? uc : ub);
        U[c] = u;
        GX[c] = k * dx;
        GY[c] = k * dy;
    }
}

/* DEN: the expression of 1/D**ipow from inv_d, inv_d2 (as in the reference kernel). Columns c0..c1-1 of
 * row r; the row arrays start at column 0 (the full kernel passes 0, cols; the incremental window
 * update of gridfield/_kernels_incremental.pyx a column range). */
#define GF_KHATIB_ROW(NAME, DEN)                                                                              \
    GF_ROW_FN void NAME(int64_t r, int64_t c0, int64_t c1, const uint8_t *restrict occ,                     \
                            const int32_t *restrict nr,                                                       \
                            const int32_t *restrict nc, double x0, double y0, double res, double goal_x,      \
                            double goal_y, double zeta, double d_star, double ds2, int conic, int metric,     \
                            double eta, double q_star, double inv_q, double sat, double far,                  \
                            double *restrict U, double *restrict GX, double *restrict GY) {                   \
        const double dy = y0 + ((double)r + 0.5) * res - goal_y;                                             \
        const double rf = (double)(int32_t)r;                                                                 \
        const int n = (int)c1;                                                                                \
        for (int c = (int)c0; c < n; c++) {                                                                   \
            /* attractive */                                                                                  \
            const double dx = x0 + ((double)c + 0.5) * res - goal_x;                                         \
            const double d2 = dx * dx + dy * dy;                                                              \
            const double d = sqrt(d2);                                                                        \
            const int quad = d2 <= ds2;                                                                       \
            const double kc = zeta / d, kb = zeta * d_star / d;                                               \
            const double uq = 0.5 * zeta * d2, uc = zeta * d, ub = zeta * d_star * d - 0.5 * zeta * ds2;      \
            const double k = quad ? zeta : (conic ? kc : kb);                                                 \
            const double u = quad ? uq : (conic ? uc : ub);                                                   \
            const double gx = k * dx, gy = k * dy;                                                            \
            /* repulsive, from the nearest obstacle cell */                                                   \
            const int32_t a = nr[c], b = nc[c];                                                               \
            const double fr = rf - (double)a, fc = (double)c - (double)b;                                     \
            double length = sqrt(fr * fr + fc * fc);                                                          \
            const double afr = fabs(fr), afc = fabs(fc);                                                      \
            const double e0 = length * res, e1 = (afr > afc ? afr : afc) * res, e2 = (afr + afc) * res;       \
            double dist = metric == 1 ? e1 : e0;                                                              \
            dist = metric == 2 ? e2 : dist;                                                                   \
            dist = dist >= sat ? far : dist;                                                                  \
            const int inside = ((a != -1) | (b != -1)) & (dist < q_star);                                     \
            dist = inside ? dist : 1.0;                                                                       \
            length = inside ? length : 1.0;                                                                   \
            const double inv_d = 1.0 / dist;                                                                  \
            const double s = inv_d - inv_q;                                                                   \
            const double inv_d2 = inv_d * inv_d;                                                              \
            const double den = (DEN);                                                                         \
            const double m = eta * s * den / length; /* |force| / |offset in cells| */                        \
            const double ui = u + 0.5 * eta * s * s, gxi = gx - m * fc, gyi = gy - m * fr;                   \
            U[c] = inside ? ui : u;                                                                           \
            GX[c] = inside ? gxi : gx;                                                                        \
            GY[c] = inside ? gyi : gy;                                                                        \
        }                                                                                                     \
        /* the occupied cells, in a second pass over the row (still in cache): keeping the uint8 */           \
        /* occupancy out of the loop above lets GCC vectorize it at the width of its doubles (not 16 lanes, */ \
        /* which spilled the double arithmetic) */                                                            \
        for (int c = (int)c0; c < n; c++) {                                                                   \
            const int o = occ[c] != 0;                                                                        \
            U[c] = o ? INFINITY : U[c];                                                                       \
            GX[c] = o ? 0.0 : GX[c];                                                                          \
            GY[c] = o ? 0.0 : GY[c];                                                                          \
        }                                                                                                     \
    }

GF_KHATIB_ROW(gf_khatib_row_p0, 1.0)
GF_KHATIB_ROW(gf_khatib_row_p1, inv_d)
GF_KHATIB_ROW(gf_khatib_row_p2, inv_d2)
GF_KHATIB_ROW(gf_khatib_row_p3, inv_d2 * inv_d)
GF_KHATIB_ROW(gf_khatib_row_p4, inv_d2 * inv_d2)

static inline void gf_khatib_row(int64_t r, int64_t c0, int64_t c1, const uint8_t *occ, const int32_t *nr, const int32_t *nc,
                                 double x0, double y0, double res, double goal_x, double goal_y, double zeta,
                                 double d_star, double ds2, int conic, int metric, double eta, double q_star,
                                 double inv_q, int ipow, double sat, double far, double *U, double *GX, double *GY) {
    switch (ipow) {
    case 0:
        gf_khatib_row_p0(r, c0, c1, occ, nr, nc, x0, y0, res, goal_x, goal_y, zeta, d_star, ds2, conic, metric, eta,
                         q_star, inv_q, sat, far, U, GX, GY);
        break;
    case 1:
        gf_khatib_row_p1(r, c0, c1, occ, nr, nc, x0, y0, res, goal_x, goal_y, zeta, d_star, ds2, conic, metric, eta,
                         q_star, inv_q, sat, far, U, GX, GY);
        break;
    case 2:
        gf_khatib_row_p2(r, c0, c1, occ, nr, nc, x0, y0, res, goal_x, goal_y, zeta, d_star, ds2, conic, metric, eta,
                         q_star, inv_q, sat, far, U, GX, GY);
        break;
    case 3:
        gf_khatib_row_p3(r, c0, c1, occ, nr, nc, x0, y0, res, goal_x, goal_y, zeta, d_star, ds2, conic, metric, eta,
                         q_star, inv_q, sat, far, U, GX, GY);
        break;
    default:
        gf_khatib_row_p4(r, c0, c1, occ, nr, nc, x0, y0, res, goal_x, goal_y, zeta, d_star, ds2, conic, metric, eta,
                         q_star, inv_q, sat, far, U, GX, GY);
        break;
    }
}

#endif
