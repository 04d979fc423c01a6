/* src/internal.h - private helpers shared by the library sources.
 * Never installed; nothing here is API. */
#ifndef IGEA_INTERNAL_H
#define IGEA_INTERNAL_H

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_rng.h>

#include "igea/common.h"

/* Column-major element (i, j) of a matrix with leading dimension ld. */
#define IGEA_AT(a, ld, i, j) ((a)[(size_t)(i) + (size_t)(j) * (size_t)(ld)])

#define IGEA_MAX(a, b) ((a) > (b) ? (a) : (b))
#define IGEA_MIN(a, b) ((a) < (b) ? (a) : (b))

/* 1 if every x[i * inc], i < n, is finite. */
int igea__finite_vec(int n, const double *x, int inc);
/* Work items work(arg, k), k = 0..n-1, on up to nthreads threads (the calling
 * thread one of them; at most IGEA__THREADS_MAX): each thread takes the
 * next item not yet taken, so that a thread slowed by other work on its
 * core takes fewer; a thread that cannot start leaves its items to the
 * others. Items write only their own results, so what they compute does
 * not depend on which thread ran them. */
#define IGEA__THREADS_MAX 256
/* igea_normal_accumulate_threads without its argument checks (normal.c),
 * for a caller that made them. */
int igea__normal_accumulate_threads(int layout, int m, int N, const double *S, int lds,
                                    const double *dw, const double *track_sigma, int sigma_inc,
                                    const double *spec_sigma, double *A, int lda, double *b,
                                    double *wtw, int nthreads);
/* Every argument of igea_normal_accumulate_threads (normal.c): 0 or its
 * status. */
int igea__normal_check_threads(int layout, int m, int N, const double *S, int lds,
                               const double *dw, const double *track_sigma, int sigma_inc,
                               const double *spec_sigma, const double *A, int lda,
                               const double *b, const double *wtw, int nthreads);
/* igea_eqerr_accumulate after its argument checks (normal.c). */
int igea__normal_accumulate_sums(int layout, int m, int N, const double *S, int lds,
                                 const double *dw, const double *track_sigma, int sigma_inc,
                                 const double *spec_sigma, double *A, int lda, double *b,
                                 double *wtw, int nthreads, int row0, double *sums);
/* The per-axis sums of igea_eqerr_axis_sums over m rows into t (3 (N + 2)),
 * the first row on axis a (eqerr.c); and their status: 0 when t is
 * finite, else IGEA_ENONFINITE (S holds a NaN or Inf) or IGEA_EOVERFLOW. */
void igea__axis_rows(int layout, int m, int N, const double *S, int lds, const double *dw,
                     int a, double *t);
int igea__axis_status(int layout, int m, int N, const double *S, int lds, const double *t);
void igea__parallel_for(int n, int nthreads, void (*work)(void *arg, int k), void *arg);
/* 1 if every x[i], i < n, is finite (n may exceed INT_MAX). */
int igea__finite_run(size_t n, const double *x);
/* 1 if every element of the m x n column-major matrix is finite. */
int igea__finite_mat(int m, int n, const double *a, int lda);
/* 1 if every x[i] > 0 (and finite); sets *nonfinite if a NaN/Inf is met. */
int igea__positive_vec(int n, const double *x, int *nonfinite);

/* Standard deviations x[0..n-1]: 0 when every one is finite and within
 * >= IGEA_SIGMA_MIN; otherwise IGEA_ENONFINITE (a NaN or Inf),
 * IGEA_ENONPOSITIVE (a value <= 0) or IGEA_ERANGE (positive but below
 * IGEA_SIGMA_MIN), checked in that order over the whole vector. */
int igea__sigma_vec(int n, const double *x);

/* malloc of n doubles / ints (n >= 0; returns a valid pointer for n == 0),
 * NULL on overflow or failure. */
double *igea__dalloc(size_t n);
int *igea__ialloc(size_t n);

/* Symmetric eigen-decomposition with LAPACK dsyevd of the lower triangle of
 * the n x n matrix a (lda): w descending, v (ldv) the eigenvectors as
 * columns with the sign convention of METHODS 0.3 (largest-magnitude entry
 * positive). Returns 0, IGEA_ENOMEM or IGEA_ELAPACK. */
int igea__syev_desc(int n, const double *a, int lda, double *w, double *v,
                    int ldv);

/* Flip column j of v (ldv, n rows) so that its largest-magnitude entry is
 * positive; returns -1 if flipped, +1 otherwise. */
int igea__sign_fix(int n, double *v);

/* A GSL generator of type T seeded with seed, allocated without
 * gsl_rng_alloc, which calls GSL's (aborting) error handler when memory
 * runs out. NULL on allocation failure; free with igea__rng_free. */
gsl_rng *igea__rng_new(const gsl_rng_type *T, unsigned long seed);
void igea__rng_free(gsl_rng *r);

/* Platform gyro input/spin axis mapping: axes NULL gives the default
 * (input x,y,z; spin y,z,x); otherwise axes[0..2] are the input and
 * axes[3..5] the spin axes, each 0..2. Returns 0, or -1 for a bad entry. */
int igea__platform_axes(const int *axes, int *in_ax, int *spin_ax);

/* ---- dense kernels (linalg.c) ---- */

/* SVD a = U diag(s) V^T of the m x N matrix a (ld m, destroyed) by dgesdd
 * with igea-owned workspace. s[min(m, N)] descending; U (ld m): the first
 * min(m, N) left singular vectors, or all m with full_u (U then m x m;
 * when m < N U is m x m either way); V (N x N, ld N): all N right
 * singular vectors as columns (those beyond min(m, N) complete the null
 * space), each with the METHODS 0.3 sign (largest-magnitude entry
 * positive), U's first min(m, N) columns flipped with them. Returns 0,
 * IGEA_ENOMEM or IGEA_ELAPACK (s is not checked for finiteness). */
int igea__svd(int m, int N, double *a, double *s, double *U, int full_u,
              double *V);

/* The METHODS 0.3 rank cut of k descending values: #{s_i > tol s_1}, 0
 * when s_1 <= 0. The default tol of an SVD is max(m, N) eps. */
int igea__rank_cut(int k, const double *s, double tol);

/* In-place transpose of the n x n matrix a (lda). */
void igea__transpose(int n, double *a, int lda);

/* Cholesky a + shift I = L L^T in place: the lower triangle of a (lda) is
 * read and overwritten by L, the upper one is not touched; no allocation.
 * Returns 0, IGEA_ESINGULAR (a pivot <= 0: not positive definite) or
 * IGEA_ENONFINITE (a pivot NaN or Inf). */
int igea__chol_lower(int n, double *a, int lda, double shift);

/* The chi-square interval of a deviation d with edf equivalent degrees of
 * freedom (clamped to [1, IGEA_STATS_DOF_MAX]) at confidence conf:
 * [d sqrt(e / chi2_{(1+conf)/2}), d sqrt(e / chi2_{(1-conf)/2})], *e the edf
 * used (stability.c). 0 or IGEA_ENOCONV. */
int igea__edf_interval(double d, double edf, double conf, double *lo, double *hi, double *e);
/* erf^-1(y) of a validated y in (-1, 1) (stats.c; igea_stats_erfinv). */
double igea__erfinv(double y);

/* Neumaier compensated sum. */
typedef struct {
    double s, c;
} igea__ksum;
static inline void igea__ksum_add(igea__ksum *k, double x)
{
    double t = k->s + x;
    if (fabs(k->s) >= fabs(x))
        k->c += (k->s - t) + x;
    else
        k->c += (x - t) + k->s;
    k->s = t;
}
static inline double igea__ksum_get(const igea__ksum *k) { return k->s + k->c; }

/* A sum of squares accumulated in blocks of 1024 plain sums, the block
 * totals compensated (the stability statistics). */
typedef struct {
    igea__ksum tot;
    double part;
    int cnt;
} igea__sqacc;
static inline void igea__sqacc_add(igea__sqacc *a, double v)
{
    a->part += v * v;
    if (++a->cnt == 1024) {
        igea__ksum_add(&a->tot, a->part);
        a->part = 0.0;
        a->cnt = 0;
    }
}
static inline double igea__sqacc_get(const igea__sqacc *a)
{
    igea__ksum t = a->tot;
    igea__ksum_add(&t, a->part);
    return igea__ksum_get(&t);
}

/* igea_eqerr_solve with a cache of the verdict rule's thresholds (eqerr.c):
 * vcache NULL, or 4 N doubles, zeros at first, kept between the calls of
 * one thread with the same options (igea_sim_montecarlo). */
int igea__eqerr_solve_cached(int N, const double *A, int lda, const double *b,
                             const double *opts, double *vcache, double *lambda, double *P,
                             int ldp, double *equiv_err, double *z, int *reject,
                             double *info);

/* Steps 3-5 of igea__eqerr_solve_cached from a decomposition done once
 * (eqerr.c): lam0 (N, descending, the rank cut of the eig route) and pb
 * (N) the projections p_i^T b; work 3 N doubles; vcache 6 N doubles (the
 * verdict rule's 4 N, then chi2_alpha's 2 N), zeros at first, kept between
 * the calls of one thread; writes z, reject (N) and info; the same statuses
 * (IGEA_ENONFINITE for a non-finite pb). pre NULL, or 2 N doubles computed
 * once for lam0: sqrt(lam0[i]), then sqrt(1 + 1 / lam0[i]) (the same
 * expressions as computed here: the same bits); want_p 0 leaves the
 * p-value out of info (P_VALUE 0). */
int igea__eqerr_solve_projected(int N, const double *lam0, const double *pre, int want_p,
                                const double *pb, const double *opts, double *vcache,
                                double *work, double *z, int *reject, double *info);

/* igea_stats_accuracy_test (stats.c) with a cache of chi2_alpha(n_test):
 * cc NULL, or 2 n doubles, zeros at first, kept between the calls of one
 * thread with the same alpha (the batched Monte Carlo); den NULL, or
 * den[i] = sqrt(1 + 1 / lambda[i]) computed by the caller (the same
 * expression: the same bits); want_p 0 leaves the p-value out (P_VALUE 0:
 * for callers that do not read it). */
int igea__stats_accuracy_cached(int n, const double *equiv_err, const double *lambda,
                                double alpha, double lambda_test, double z_crit,
                                double *cc, const double *den, int want_p, double *z,
                                int *reject, double *info);

/* n bytes of fd from byte off into p (pread, retried on EINTR; the
 * descriptor's position unused): 0, or IGEA_EREAD on an error or the end of
 * the file before n bytes (io_src.c). */
int igea__pread_full(int fd, void *p, size_t n, long long off);

#endif
