/* regress.c - least squares, ridge, principal-component, Bayesian and
 * empirical-Bayes ridge estimators and collinearity diagnostics (METHODS
 * 0.3, 4.3). Every estimator works on the thin SVD of the weighted design
 * (dgesdd), never on the normal matrix. */
#include <float.h>

#include <cblas.h>
#include <lapacke.h>

#include "igea/normal.h"
#include "igea/regress.h"
#include "igea/stats.h"
#include "internal.h"

/* ---- the canonical form ------------------------------------------------ */

/* Aw = diag(1/sigma) A diag(cs) = U diag(s) V^T, z = U^T yw. V is N x N
 * (columns, METHODS 0.3 signs; the columns beyond k = min(m, N) span the
 * rest of the null space), U is m x k. */
typedef struct {
    int m, N, k, r;
    double *U, *s, *V, *yw, *z;
    double *mem;
    /* qr: built from the QR factor of [Aw yw] (tall designs): U and yw are
     * not formed (NULL), z = U^T yw comes from Q^T yw, and rho2 =
     * ||yw - Q Q^T yw||^2, the part of yw outside the columns' span */
    int qr;
    double rho2;
    const double *R; /* qr: the factor [R q; 0 rho], (N + 1) x (N + 1) */
} canon;

static void canon_free(canon *c)
{
    free(c->mem);
    c->mem = NULL;
}

/* Common argument checks of (m, N, A, lda, y, sigma) at positions 1-6;
 * y may be NULL when allow_null_y. Returns 0 or -i. */
static int check_args(int m, int N, const double *A, int lda, const double *y,
                      int allow_null_y)
{
    if (m < 1)
        return -1;
    if (N < 1)
        return -2;
    if (!A)
        return -3;
    if (lda < m)
        return -4;
    if (!y && !allow_null_y)
        return -5;
    return 0;
}

/* Value checks after the -i checks: NaN/Inf, sigma > 0, column scale > 0. */
static int check_values(int m, int N, const double *A, int lda,
                        const double *y, const double *sigma,
                        const double *cs)
{
    if (!igea__finite_mat(m, N, A, lda))
        return IGEA_ENONFINITE;
    if (y && !igea__finite_vec(m, y, 1))
        return IGEA_ENONFINITE;
    int st = sigma ? igea__sigma_vec(m, sigma) : 0;
    if (st == 0 && cs)
        st = igea__sigma_vec(N, cs);
    return st;
}

/* s / (s^2 + k) for s > 0, k >= 0, without forming s^2 (which overflows or
 * underflows at the ends of the double range). */
static double ridge_factor(double s, double k)
{
    if (k == 0.0)
        return 1.0 / s;
    double q = s / sqrt(k); /* f = q / (1 + q^2) / sqrt(k) */
    double f = q > 1.0 ? (1.0 / q) / (1.0 + (1.0 / q) / q) : q / (1.0 + q * q);
    return f / sqrt(k);
}

/* d / (d + k) with d = s^2, without forming s^2. */
static double ridge_hat(double s, double rk)
{
    if (rk == 0.0)
        return 1.0;
    double q = rk / s; /* k / d = q^2 */
    return q < 1.0 ? 1.0 / (1.0 + q * q) : (1.0 / q) / ((1.0 / q) + q);
}

/* Rank cut of METHODS 0.3: s_i > rcond * s_1, rcond = max(m, N) eps. */
static int rank_of(int k, const double *s, double rcond, int m, int N)
{
    return igea__rank_cut(k, s, rcond > 0 ? rcond : IGEA_MAX(m, N) * DBL_EPSILON);
}

static int canon_make_full(int m, int N, const double *A, int lda, const double *y,
                           const double *sigma, const double *cs, double rcond,
                           canon *c)
{
    int k = IGEA_MIN(m, N);
    int ucols = m >= N ? N : m;
    size_t mn = (size_t)m * (size_t)N;
    size_t need = mn + (size_t)m * ucols + (size_t)k + (size_t)N * N +
                  2 * (size_t)m + (size_t)k;
    c->mem = igea__dalloc(need);
    if (!c->mem)
        return IGEA_ENOMEM;
    double *Aw = c->mem;
    c->U = Aw + mn;
    c->s = c->U + (size_t)m * ucols;
    c->V = c->s + k;
    c->yw = c->V + (size_t)N * N;
    c->z = c->yw + m;
    c->m = m;
    c->N = N;
    c->k = k;
    c->qr = 0;
    c->rho2 = 0.0;
    c->R = NULL;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < m; i++)
            Aw[i + (size_t)j * m] = IGEA_AT(A, lda, i, j) *
                                    (cs ? cs[j] : 1.0) /
                                    (sigma ? sigma[i] : 1.0);
    for (int i = 0; i < m; i++)
        c->yw[i] = y ? y[i] / (sigma ? sigma[i] : 1.0) : 0.0;
    /* Finite inputs, but the weighted data overflowed (y / sigma). */
    if (!igea__finite_mat(m, N, Aw, m) || !igea__finite_vec(m, c->yw, 1)) {
        canon_free(c);
        return IGEA_EOVERFLOW;
    }
    int st = igea__svd(m, N, Aw, c->s, c->U, 0, c->V);
    if (st == 0 && !igea__finite_vec(k, c->s, 1))
        st = IGEA_ELAPACK;
    if (st != 0) {
        canon_free(c);
        return st;
    }
    c->r = rank_of(k, c->s, rcond, m, N);
    for (int i = 0; i < k; i++)
        c->z[i] = cblas_ddot(m, c->U + (size_t)i * m, 1, c->yw, 1);
    return 0;
}

/* [D] A tall design (m >= IGEA__TALL N rows) through its QR factor first:
 * [Aw yw] = Q [R q; 0 rho] by the streamed Householder updates of
 * igea_normal_qr_accumulate (row blocks in cache: no m x N copy), then the
 * SVD R = U_R diag(s) V^T of the N x N factor. Aw = (Q U_R) diag(s) V^T is
 * then the thin SVD of Aw: the same s and V (Q has orthonormal columns),
 * U = Q U_R, which is never formed; z = U^T yw = U_R^T q, and the LS
 * residual outside the span of Q is rho (docs/regress.md, "Tall designs").
 * Returns 1 (not built: the full SVD must be used) when the column scales
 * are outside the range the streamed factor accepts. */
#define IGEA__TALL 2
static int canon_make_qr(int m, int N, const double *A, int lda, const double *y,
                         const double *sigma, const double *cs, double rcond, canon *c)
{
    size_t n1 = (size_t)N + 1, nn = (size_t)N * N;
    c->mem = igea__dalloc(n1 * n1 + 3 * nn + 2 * (size_t)N + (y ? 0 : (size_t)m));
    if (!c->mem)
        return IGEA_ENOMEM;
    double *R = c->mem, *Rc = R + n1 * n1, *UR = Rc + nn;
    c->V = UR + nn;
    c->s = c->V + nn;
    c->z = c->s + N;
    double *zero = c->z + N, one = 1.0, rows = 0.0;
    if (!y)
        memset(zero, 0, (size_t)m * sizeof(double));
    memset(R, 0, n1 * n1 * sizeof(double));
    c->m = m, c->N = N, c->k = N, c->qr = 1;
    c->U = c->yw = NULL;
    c->R = R;
    int st = igea_normal_qr_accumulate(IGEA_COLMAJOR, m, N, A, lda, y ? y : zero,
                                       sigma ? sigma : &one, sigma ? 1 : 0, cs, R, (int)n1,
                                       &rows);
    if (st == IGEA_ERANGE) { /* a column scale below IGEA_SIGMA_MIN */
        canon_free(c);
        return 1;
    }
    if (st == 0) {
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++)
                Rc[i + (size_t)j * N] = i <= j ? R[i + (size_t)j * n1] : 0.0;
        st = igea__svd(N, N, Rc, c->s, UR, 0, c->V);
    }
    if (st == 0 && !igea__finite_vec(N, c->s, 1))
        st = IGEA_ELAPACK;
    if (st != 0) {
        canon_free(c);
        return st < 0 && st > -1000 ? IGEA_EDOMAIN : st; /* arguments: checked before */
    }
    c->r = rank_of(N, c->s, rcond, m, N);
    const double *q = R + (size_t)N * n1;
    for (int i = 0; i < N; i++)
        c->z[i] = cblas_ddot(N, UR + (size_t)i * N, 1, q, 1);
    c->rho2 = R[N + (size_t)N * n1] * R[N + (size_t)N * n1];
    return 0;
}

/* The canonical form: through the QR factor for a tall design, unless the
 * caller needs U's rows (need_u), else the SVD of the weighted copy. */
static int canon_make_u(int m, int N, const double *A, int lda, const double *y,
                        const double *sigma, const double *cs, double rcond, int need_u,
                        canon *c)
{
    if (!need_u && m >= IGEA__TALL * N) {
        int st = canon_make_qr(m, N, A, lda, y, sigma, cs, rcond, c);
        if (st != 1)
            return st;
    }
    return canon_make_full(m, N, A, lda, y, sigma, cs, rcond, c);
}

static int canon_make(int m, int N, const double *A, int lda, const double *y,
                      const double *sigma, const double *cs, double rcond, canon *c)
{
    return canon_make_u(m, N, A, lda, y, sigma, cs, rcond, 0, c);
}

/* ||yw - U_r z_r||^2: the weighted residual sum of squares of LS (through
 * the QR factor: rho^2 plus the components of Q^T yw beyond the rank). */
static double canon_rss(const canon *c)
{
    igea__ksum acc = {0.0, 0.0};
    if (c->qr) {
        igea__ksum_add(&acc, c->rho2);
        for (int i = c->r; i < c->N; i++)
            igea__ksum_add(&acc, c->z[i] * c->z[i]);
        return igea__ksum_get(&acc);
    }
    for (int i = 0; i < c->m; i++) {
        double e = c->yw[i];
        for (int j = 0; j < c->r; j++)
            e -= c->U[i + (size_t)j * c->m] * c->z[j];
        igea__ksum_add(&acc, e * e);
    }
    return igea__ksum_get(&acc);
}

/* x = D V diag(f) z over i < n (f_i multiplies z_i), D = diag(cs) or I. */
static void canon_coef(const canon *c, int n, const double *f,
                       const double *cs, double *x)
{
    int N = c->N;
    for (int j = 0; j < N; j++) {
        igea__ksum acc = {0.0, 0.0};
        for (int i = 0; i < n; i++)
            igea__ksum_add(&acc, c->V[j + (size_t)i * N] * f[i] * c->z[i]);
        x[j] = igea__ksum_get(&acc) * (cs ? cs[j] : 1.0);
    }
}

/* cov = scale * D V diag(g) V^T D over i < n (g has n entries). */
static void canon_cov(const canon *c, int n, const double *g, double scale,
                      const double *cs, double *cov, int ldc)
{
    int N = c->N;
    for (int a = 0; a < N; a++)
        for (int b = 0; b <= a; b++) {
            double acc = 0.0;
            for (int i = 0; i < n; i++)
                acc += c->V[a + (size_t)i * N] * g[i] * c->V[b + (size_t)i * N];
            acc *= scale;
            if (cs)
                acc = acc * cs[a] * cs[b];
            IGEA_AT(cov, ldc, a, b) = acc;
            IGEA_AT(cov, ldc, b, a) = acc;
        }
}

/* Diagonal of the above, as standard deviations. */
static void canon_sd(const canon *c, int n, const double *g, double scale,
                     const double *cs, double *sd)
{
    int N = c->N;
    for (int a = 0; a < N; a++) {
        double acc = 0.0;
        for (int i = 0; i < n; i++) {
            double v = c->V[a + (size_t)i * N];
            acc += v * v * g[i];
        }
        sd[a] = sqrt(acc * scale) * (cs ? cs[a] : 1.0);
    }
}

/* residual = y - A x (unweighted). */
static void residual_of(int m, int N, const double *A, int lda,
                        const double *y, const double *x, double *res)
{
    memcpy(res, y, (size_t)m * sizeof(double));
    cblas_dgemv(CblasColMajor, CblasNoTrans, m, N, -1.0, A, lda, x, 1, 1.0,
                res, 1);
}

/* The design A D (m x N, ld m) in *own when spec is given: *A and *lda then
 * point to it; A itself otherwise (*own NULL). The product is rounded once,
 * as a caller scaling the columns would. Returns 0 or IGEA_ENOMEM. */
static int scaled_design(int m, int N, const double **A, int *lda,
                         const double *spec, double **own)
{
    *own = NULL;
    if (!spec)
        return 0;
    double *a = igea__dalloc((size_t)m * (size_t)N);
    if (!a)
        return IGEA_ENOMEM;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < m; i++)
            a[i + (size_t)j * m] = IGEA_AT(*A, *lda, i, j) * spec[j];
    *own = a;
    *A = a;
    *lda = m;
    return 0;
}

/* Back to the caller's units: x = D x' and cov = D cov' D (N x N, ldc), in
 * place; x or cov may be NULL, spec NULL does nothing. */
static void unscale(int N, const double *spec, double *x, double *cov, int ldc)
{
    if (!spec)
        return;
    for (int j = 0; j < N; j++) {
        if (x)
            x[j] *= spec[j];
        if (cov)
            for (int i = 0; i < N; i++)
                IGEA_AT(cov, ldc, i, j) = IGEA_AT(cov, ldc, i, j) * spec[i] * spec[j];
    }
}

/* The end of a fit: x' (xs) and its covariance cv (N x N, ld N; read only
 * when cov is given) back to the caller's units, every value checked
 * finite (IGEA_EOVERFLOW: finite inputs whose result left the double
 * range), then x, cov (ldc) and the residuals res (m) copied out. */
static int fit_out(int m, int N, const double *spec, double s2, double *xs,
                   double *cv, const double *res, double *x, double *cov, int ldc,
                   double *residual)
{
    unscale(N, spec, xs, cov ? cv : NULL, N);
    if (!igea__finite_vec(N, xs, 1) || !igea__finite_vec(m, res, 1) ||
        !isfinite(s2) || (cov && !igea__finite_mat(N, N, cv, N)))
        return IGEA_EOVERFLOW;
    memcpy(x, xs, (size_t)N * sizeof(double));
    if (cov)
        for (int j = 0; j < N; j++)
            memcpy(cov + (size_t)j * ldc, cv + (size_t)j * N, (size_t)N * sizeof(double));
    if (residual)
        memcpy(residual, res, (size_t)m * sizeof(double));
    return 0;
}

/* ---- iterative refinement ---------------------------------------------- */

/* Compensated (Neumaier) accumulation in long double of exact products:
 * a v for a double a and a long double v = vh + vl (vh its double
 * rounding), a vh = p + e exactly (fma), a vl to 2^-64 relative; the
 * sum keeps about 2^-120 relative to its terms, so the cancellation of
 * y - A x and A^T r at the least-squares solution costs nothing. */
typedef struct {
    long double s, c;
} xacc;

static void xacc_add(xacc *a, long double v)
{
    long double t = a->s + v;
    a->c += fabsl(a->s) >= fabsl(v) ? (a->s - t) + v : (v - t) + a->s;
    a->s = t;
}

static void xacc_prod(xacc *a, double x, long double v)
{
    double vh = (double)v, p = x * vh;
    xacc_add(a, p);
    xacc_add(a, fma(x, vh, -p));
    xacc_add(a, (long double)x * (v - vh));
}

/* y_i - sum_j A_ij x_j in extended precision (row i, x in long double),
 * unevaluated as s + c. */
static xacc row_resid(int N, const double *A, int lda, int i, double yi, const long double *x)
{
    xacc a = {yi, 0.0L};
    for (int j = 0; j < N; j++)
        xacc_prod(&a, -IGEA_AT(A, lda, i, j), x[j]);
    return a;
}

/* One correction of the augmented system [I B; B^T 0] [r; x'] = [yw; 0]
 * (Bjorck 1967), B = diag(1/sigma) A diag(cs) = U S V^T (full rank, k = N):
 * from the extended-precision residuals f = yw - r - B x', g = -B^T r,
 * dx' = V (S^-1 U^T f - S^-2 V^T g) and dr = f - U (U^T f - S^-1 V^T g).
 * Updates xl (A's units) and rl; returns max |dx'_j| / max |x'_j|. */
static double refine_step(int m, int N, const double *A, int lda, const double *y,
                          const double *sigma, const canon *c, const double *cs,
                          long double *xl, xacc *rl, double *wk)
{
    double *f = wk, *g = f + m, *u = g + N, *w = u + N, *t = w + N;
    for (int i = 0; i < m; i++) {
        xacc e = row_resid(N, A, lda, i, y[i], xl);
        long double es = e.s, ec = e.c;
        if (sigma) { /* e / sigma to about 2^-128 (fmal remainder) */
            es = e.s / sigma[i];
            ec = (fmal(-es, sigma[i], e.s) + e.c) / sigma[i];
        }
        f[i] = (double)(((es - rl[i].s) + ec) - rl[i].c);
    }
    /* r_i / sigma_i as q + q2 to about 2^-128 (fmal remainder), so that the
     * weights are not rounded where B^T r cancels */
    size_t off = (size_t)m + 4 * (size_t)N; /* after t[N], padded to 16 bytes */
    long double *q = (long double *)(void *)(wk + off + (off & 1));
    for (int i = 0; i < m; i++) {
        if (!sigma) {
            q[2 * i] = rl[i].s;
            q[2 * i + 1] = rl[i].c;
            continue;
        }
        long double qi = rl[i].s / sigma[i];
        q[2 * i] = qi;
        q[2 * i + 1] = (fmal(-qi, sigma[i], rl[i].s) + rl[i].c) / sigma[i];
    }
    for (int j = 0; j < N; j++) {
        xacc a = {0.0L, 0.0L};
        for (int i = 0; i < m; i++) {
            xacc_prod(&a, IGEA_AT(A, lda, i, j), q[2 * i]);
            xacc_prod(&a, IGEA_AT(A, lda, i, j), q[2 * i + 1]);
        }
        g[j] = (double)(-(a.s + a.c) * cs[j]);
    }
    cblas_dgemv(CblasColMajor, CblasTrans, m, N, 1.0, c->U, m, f, 1, 0.0, u, 1);
    cblas_dgemv(CblasColMajor, CblasTrans, N, N, 1.0, c->V, N, g, 1, 0.0, w, 1);
    for (int i = 0; i < N; i++) {
        w[i] /= c->s[i];
        t[i] = (u[i] - w[i]) / c->s[i];
        u[i] -= w[i];
    }
    double dmax = 0.0, xmax = 0.0;
    for (int j = 0; j < N; j++) {
        double dxs = cblas_ddot(N, c->V + j, N, t, 1);
        xl[j] += (long double)dxs * cs[j];
        dmax = IGEA_MAX(dmax, fabs(dxs));
        xmax = IGEA_MAX(xmax, fabs((double)(xl[j] / cs[j])));
    }
    for (int i = 0; i < m; i++)
        xacc_add(&rl[i], f[i] - cblas_ddot(N, c->U + i, m, u, 1));
    return xmax > 0.0 ? dmax / xmax : 0.0;
}

/* Iterative refinement of the full-rank LS solution x (A's units, in
 * place) with residuals in extended precision, until a correction is below
 * 2^-60 of x' or stops shrinking (at most IGEA_REGRESS_REFINE_MAX steps).
 * res[m] receives y - A x of the returned x, in extended precision and
 * rounded once. Returns the number of steps, or IGEA_ENOMEM. */
#define IGEA_REGRESS_REFINE_MAX 10
static int ls_refine(int m, int N, const double *A, int lda, const double *y,
                     const double *sigma, const canon *c, const double *cs, double *x,
                     double *res)
{
    /* long doubles first (16-byte aligned): xl[N], rl[m] (two each), then
     * the doubles f[m], g, u, w, t[N] and 2 m long doubles of refine_step */
    size_t nd = 2 * (size_t)N + 4 * (size_t)m + (size_t)m + 4 * (size_t)N;
    nd += nd & 1;
    double *mem = igea__dalloc(nd + 4 * (size_t)m);
    if (!mem)
        return IGEA_ENOMEM;
    long double *xl = (long double *)(void *)mem;
    xacc *rl = (xacc *)(void *)(mem + 2 * (size_t)N);
    double *wk = mem + 2 * (size_t)N + 4 * (size_t)m;
    for (int j = 0; j < N; j++)
        xl[j] = x[j];
    for (int i = 0; i < m; i++) {
        rl[i] = row_resid(N, A, lda, i, y[i], xl);
        if (sigma) {
            long double s0 = rl[i].s;
            rl[i].s = s0 / sigma[i];
            rl[i].c = (fmal(-rl[i].s, sigma[i], s0) + rl[i].c) / sigma[i];
        }
    }
    int it = 0;
    double prev = HUGE_VAL;
    while (it < IGEA_REGRESS_REFINE_MAX) {
        double d = refine_step(m, N, A, lda, y, sigma, c, cs, xl, rl, wk);
        it++;
        if (!(d > 0x1p-60) || d > 0.5 * prev)
            break;
        prev = d;
    }
    for (int j = 0; j < N; j++)
        x[j] = (double)xl[j];
    for (int j = 0; j < N; j++)
        xl[j] = x[j];
    for (int i = 0; i < m; i++) {
        xacc e = row_resid(N, A, lda, i, y[i], xl);
        res[i] = (double)(e.s + e.c);
    }
    free(mem);
    return it;
}

/* ---- refinement through the QR factor (tall designs) -------------------
 * [D] The corrections of refine_step with U's products formed from the
 * design itself: at full rank U = B V S^-1 (B = diag(1/sigma) A D), so
 * U^T f = S^-1 V^T (B^T f) and U u = B (V S^-1 u), one pass over A each
 * (dgemv) instead of an m x N U; and the extended precision as
 * double-double sums in plain doubles (products split exactly by Dekker's
 * method, sums compensated by Knuth's two-sum) instead of long double:
 * y - A x and A^T r keep about 2^-104 of their terms (docs/regress.md,
 * "Tall designs"). A product beyond about 2^996 cannot be split: the
 * refinement then stops and the unrefined solution stands (a non-finite
 * correction is never applied). */

/* a = hi + lo, hi with 26 significant bits (Dekker's splitting). */
static void dd_split(double a, double *hi, double *lo)
{
    double t = 134217729.0 * a; /* 2^27 + 1 */
    *hi = t - (t - a);
    *lo = a - *hi;
}

/* s + e = a + b exactly (Knuth). */
static void dd_two_sum(double a, double b, double *s, double *e)
{
    double t = a + b, bb = t - a;
    *e = (a - (t - bb)) + (b - bb);
    *s = t;
}

/* a b = p + e exactly, b given as its split bh + bl. */
static void dd_prod(double a, double b, double bh, double bl, double *p, double *e)
{
    double ah, al;
    dd_split(a, &ah, &al);
    *p = a * b;
    *e = ((ah * bh - *p) + ah * bl + al * bh) + al * bl;
}

/* h + l += a b (b split as bh + bl; the a blo term to 2^-53 of itself):
 * one row's step of dd_resid, written for two rows at a time below. */
#define DD_ROW(a, h, l)                                                                     \
    do {                                                                                    \
        double t_ = 134217729.0 * (a), ah_ = t_ - (t_ - (a)), al_ = (a) - ah_;              \
        double p_ = (a) * b, e_ = ((ah_ * bh - p_) + ah_ * bl + al_ * bh) + al_ * bl;       \
        double s_ = (h) + p_, bb_ = s_ - (h);                                               \
        (l) += (((h) - (s_ - bb_)) + (p_ - bb_) + e_) + (a) * blo;                          \
        (h) = s_;                                                                           \
    } while (0)

/* (h[i], l[i]) -= A[i, :] (xh + xl) over the rows, column by column (each
 * row's terms in column order), two independent rows per step (vector
 * registers where the compiler has them; the same operations as one). */
static void dd_resid(int m, int N, const double *A, int lda, const double *xh,
                     const double *xl, double *restrict h, double *restrict l)
{
    for (int j = 0; j < N; j++) {
        const double *restrict a = A + (size_t)j * lda;
        double bh, bl, b = -xh[j], blo = -xl[j];
        dd_split(b, &bh, &bl);
        int i = 0;
        for (; i + 2 <= m; i += 2) {
            double a0 = a[i], a1 = a[i + 1], h0 = h[i], h1 = h[i + 1], l0 = l[i], l1 = l[i + 1];
            DD_ROW(a0, h0, l0);
            DD_ROW(a1, h1, l1);
            h[i] = h0, h[i + 1] = h1, l[i] = l0, l[i + 1] = l1;
        }
        for (; i < m; i++)
            DD_ROW(a[i], h[i], l[i]);
    }
}

/* h + l divided by d as a double-double: (qh, ql). */
static void dd_div(double h, double l, double d, double *qh, double *ql)
{
    double q = h / d, dh, dl, p, e;
    dd_split(d, &dh, &dl);
    dd_prod(q, d, dh, dl, &p, &e);
    *qh = q;
    *ql = (((h - p) - e) + l) / d;
}

/* sh + sl += a q (q = qh + ql, qh split as qsh + qsl): one row's term of
 * dd_gradient. */
#define DD_GRAD(a, qh, qsh, qsl, ql, sh, sl)                                                \
    do {                                                                                    \
        double t_ = 134217729.0 * (a), ah_ = t_ - (t_ - (a)), al_ = (a) - ah_;              \
        double p_ = (a) * (qh), e_ = ((ah_ * (qsh) - p_) + ah_ * (qsl) + al_ * (qsh)) +     \
                                     al_ * (qsl);                                           \
        double s_ = (sh) + p_, bb_ = s_ - (sh);                                             \
        (sl) += (((sh) - (s_ - bb_)) + (p_ - bb_) + e_) + (a) * (ql);                       \
        (sh) = s_;                                                                          \
    } while (0)

/* g[j] = -cs[j] sum_i A_ij (qh_i + ql_i), four independent double-double
 * sums per column (rows i mod 4), four rows per step; qh split as
 * qsh + qsl. */
static void dd_gradient(int m, int N, const double *A, int lda, const double *restrict qh,
                        const double *restrict ql, const double *restrict qsh,
                        const double *restrict qsl, const double *cs, double *g)
{
    for (int j = 0; j < N; j++) {
        const double *restrict a = A + (size_t)j * lda;
        double h0 = 0, h1 = 0, h2 = 0, h3 = 0, l0 = 0, l1 = 0, l2 = 0, l3 = 0;
        int i = 0;
        for (; i + 4 <= m; i += 4) {
            double a0 = a[i], a1 = a[i + 1], a2 = a[i + 2], a3 = a[i + 3];
            DD_GRAD(a0, qh[i], qsh[i], qsl[i], ql[i], h0, l0);
            DD_GRAD(a1, qh[i + 1], qsh[i + 1], qsl[i + 1], ql[i + 1], h1, l1);
            DD_GRAD(a2, qh[i + 2], qsh[i + 2], qsl[i + 2], ql[i + 2], h2, l2);
            DD_GRAD(a3, qh[i + 3], qsh[i + 3], qsl[i + 3], ql[i + 3], h3, l3);
        }
        double sh[4] = {h0, h1, h2, h3}, sl[4] = {l0, l1, l2, l3};
        for (; i < m; i++)
            DD_GRAD(a[i], qh[i], qsh[i], qsl[i], ql[i], sh[i & 3], sl[i & 3]);
        double hh = 0.0, ll = 0.0;
        for (int k = 0; k < 4; k++) {
            double s, t;
            dd_two_sum(hh, sh[k], &s, &t);
            ll += t + sl[k];
            hh = s;
        }
        g[j] = -(hh + ll) * cs[j];
    }
}

/* Iterative refinement of the full-rank LS solution x (A's units, in
 * place) through the QR canonical form, as ls_refine. res[m] receives
 * y - A x of the returned x, in double-double and rounded once. Returns the
 * number of steps, or IGEA_ENOMEM. */
static int ls_refine_qr(int m, int N, const double *A, int lda, const double *y,
                        const double *sigma, const canon *c, const double *cs, double *x,
                        double *res)
{
    /* rh, rl, qh, ql, f, h, l (m each), qs (2 m); xh, xl, u, w, t, v (N) */
    double *mem = igea__dalloc(9 * (size_t)m + 6 * (size_t)N);
    if (!mem)
        return IGEA_ENOMEM;
    double *rh = mem, *rl = rh + m, *qh = rl + m, *ql = qh + m, *f = ql + m, *h = f + m;
    double *l = h + m, *qs = l + m, *xh = qs + 2 * (size_t)m, *xl = xh + N, *u = xl + N;
    double *w = u + N, *t = w + N, *v = t + N;
    for (int j = 0; j < N; j++)
        xh[j] = x[j], xl[j] = 0.0;
    /* r = (y - A x) / sigma, double-double */
    memcpy(h, y, (size_t)m * sizeof(double));
    memset(l, 0, (size_t)m * sizeof(double));
    dd_resid(m, N, A, lda, xh, xl, h, l);
    for (int i = 0; i < m; i++) {
        if (sigma)
            dd_div(h[i], l[i], sigma[i], &rh[i], &rl[i]);
        else
            dd_two_sum(h[i], l[i], &rh[i], &rl[i]);
    }
    int it = 0, ok = 1;
    double prev = HUGE_VAL;
    while (it < IGEA_REGRESS_REFINE_MAX && ok) {
        /* f = (y - A x) / sigma - r: zero at the first step (r was just
         * computed from the same x) */
        if (it == 0) {
            memset(f, 0, (size_t)m * sizeof(double));
        } else {
            memcpy(h, y, (size_t)m * sizeof(double));
            memset(l, 0, (size_t)m * sizeof(double));
            dd_resid(m, N, A, lda, xh, xl, h, l);
            for (int i = 0; i < m; i++) {
                double ah = h[i], al = l[i];
                if (sigma)
                    dd_div(h[i], l[i], sigma[i], &ah, &al);
                f[i] = ((ah - rh[i]) + al) - rl[i];
            }
        }
        /* g = -B^T r */
        for (int i = 0; i < m; i++) {
            if (sigma)
                dd_div(rh[i], rl[i], sigma[i], &qh[i], &ql[i]);
            else
                qh[i] = rh[i], ql[i] = rl[i];
            dd_split(qh[i], &qs[i], &qs[m + i]);
        }
        dd_gradient(m, N, A, lda, qh, ql, qs, qs + m, cs, w);
        /* u = U^T f = S^-1 V^T D A^T (f / sigma) */
        for (int i = 0; i < m; i++)
            h[i] = sigma ? f[i] / sigma[i] : f[i];
        cblas_dgemv(CblasColMajor, CblasTrans, m, N, 1.0, A, lda, h, 1, 0.0, v, 1);
        for (int j = 0; j < N; j++)
            v[j] *= cs[j];
        cblas_dgemv(CblasColMajor, CblasTrans, N, N, 1.0, c->V, N, v, 1, 0.0, u, 1);
        cblas_dgemv(CblasColMajor, CblasTrans, N, N, 1.0, c->V, N, w, 1, 0.0, t, 1);
        for (int i = 0; i < N; i++) {
            u[i] /= c->s[i];
            double wi = t[i] / c->s[i];
            t[i] = (u[i] - wi) / c->s[i];
            u[i] -= wi;
        }
        /* dx' = V t; dr = f - U u, U u = diag(1/sigma) A D V S^-1 u */
        double dmax = 0.0, xmax = 0.0;
        for (int j = 0; j < N; j++) {
            double dxs = cblas_ddot(N, c->V + j, N, t, 1);
            ok = ok && isfinite(dxs);
            dmax = IGEA_MAX(dmax, fabs(dxs));
            w[j] = dxs;
        }
        for (int i = 0; i < N; i++)
            u[i] /= c->s[i];
        cblas_dgemv(CblasColMajor, CblasNoTrans, N, N, 1.0, c->V, N, u, 1, 0.0, v, 1);
        for (int j = 0; j < N; j++)
            v[j] *= cs[j];
        cblas_dgemv(CblasColMajor, CblasNoTrans, m, N, 1.0, A, lda, v, 1, 0.0, h, 1);
        for (int i = 0; i < m && ok; i++)
            ok = isfinite(f[i]) && isfinite(h[i]);
        if (!ok)
            break; /* nothing applied: the solution of the last step stands */
        for (int j = 0; j < N; j++) {
            double p, e, s2, e2, ch, cl;
            dd_split(cs[j], &ch, &cl);
            dd_prod(w[j], cs[j], ch, cl, &p, &e);
            dd_two_sum(xh[j], p, &s2, &e2);
            dd_two_sum(s2, xl[j] + e2 + e, &xh[j], &xl[j]);
            xmax = IGEA_MAX(xmax, fabs(xh[j] / cs[j]));
        }
        for (int i = 0; i < m; i++) {
            double d = f[i] - (sigma ? h[i] / sigma[i] : h[i]), s2, e2;
            dd_two_sum(rh[i], d, &s2, &e2);
            rl[i] += e2;
            rh[i] = s2;
        }
        it++;
        double d = xmax > 0.0 ? dmax / xmax : 0.0;
        if (!(d > 0x1p-60) || d > 0.5 * prev)
            break;
        prev = d;
    }
    for (int j = 0; j < N; j++)
        x[j] = xh[j] + xl[j];
    for (int j = 0; j < N; j++)
        xh[j] = x[j], xl[j] = 0.0;
    memcpy(h, y, (size_t)m * sizeof(double));
    memset(l, 0, (size_t)m * sizeof(double));
    dd_resid(m, N, A, lda, xh, xl, h, l);
    for (int i = 0; i < m; i++)
        res[i] = h[i] + l[i];
    if (!igea__finite_vec(m, res, 1)) /* products beyond the splitting's range */
        residual_of(m, N, A, lda, y, x, res);
    free(mem);
    return it;
}

/* ---- least squares ----------------------------------------------------- */

/* cs[j] = 1 / ||column j of diag(1/sigma) A||, without forming a norm
 * beyond DBL_MAX; a column whose scale is not representable is left
 * unscaled (1). */
static void equilibrate(int m, int N, const double *A, int lda, const double *sigma,
                        double *cs)
{
    for (int j = 0; j < N; j++) {
        double nrm = 0.0, sc = 0.0;
        for (int i = 0; i < m; i++) {
            double v = IGEA_AT(A, lda, i, j) / (sigma ? sigma[i] : 1.0);
            double av = fabs(v);
            if (av > sc) {
                nrm = nrm * (sc / av) * (sc / av) + 1.0;
                sc = av;
            } else if (av > 0)
                nrm += (av / sc) * (av / sc);
        }
        double inv = sc > 0 ? (1.0 / sc) / sqrt(nrm) : 1.0;
        cs[j] = isfinite(inv) && inv >= DBL_MIN ? inv : 1.0;
    }
}

static int canon_leverages(const canon *c, int m, int N, const double *A, int lda,
                           const double *sigma, const double *D, int r, double *h);

/* Options and extra outputs of ls_core (NULL sd/info/lev: none; lev: the
 * leverages of the canonical form the solution came from, m). */
typedef struct {
    int refine;
    double *sd, *info, *lev;
} ls_extra;

/* Standard deviations sqrt(diag(cov)) in the caller's units. */
static void ls_sd(const canon *c, int r, const double *g, double s2, const double *D,
                  const double *spec, double *sd)
{
    canon_sd(c, r, g, s2, D, sd);
    if (spec)
        for (int j = 0; j < c->N; j++)
            sd[j] *= spec[j];
}

/* The info[] entries of least squares. */
static void ls_info(const canon *c, double rcond, int scaled, int steps, double *info)
{
    for (int i = 0; i < IGEA_REGRESS_INFO_LEN; i++)
        info[i] = 0.0;
    double rc = rcond > 0 ? rcond : IGEA_MAX(c->m, c->N) * DBL_EPSILON;
    info[IGEA_REGRESS_INFO_RANK] = c->r;
    info[IGEA_REGRESS_INFO_RCOND] = rc;
    info[IGEA_REGRESS_INFO_TOL] = rc * c->s[0];
    info[IGEA_REGRESS_INFO_SCALED] = scaled;
    info[IGEA_REGRESS_INFO_REFINE_STEPS] = steps;
    info[IGEA_REGRESS_INFO_COND] = c->r > 0 && c->s[c->r - 1] > 0 ? c->s[0] / c->s[c->r - 1] : 0.0;
}

/* x, the residuals and s^2 of LS from the canonical form; at full rank
 * refined in extended precision when ex->refine (steps in *steps). */
static int ls_solve(int m, int N, const double *A, int lda, const double *y,
                    const double *sigma, const canon *c, const double *D, int refine,
                    double *g, double *xs, double *res, double *s2, int *steps)
{
    int r = c->r;
    for (int i = 0; i < r; i++)
        g[i] = 1.0 / c->s[i];
    canon_coef(c, r, g, D, xs);
    *steps = 0;
    if (refine && D && r == N) {
        int it = c->qr ? ls_refine_qr(m, N, A, lda, y, sigma, c, D, xs, res)
                       : ls_refine(m, N, A, lda, y, sigma, c, D, xs, res);
        if (it < 0)
            return it;
        *steps = it;
    } else
        residual_of(m, N, A, lda, y, xs, res);
    igea__ksum acc = {0.0, 0.0};
    for (int i = 0; i < m; i++) {
        double e = res[i] / (sigma ? sigma[i] : 1.0);
        igea__ksum_add(&acc, e * e);
    }
    *s2 = m > r ? igea__ksum_get(&acc) / (m - r) : 0.0;
    return 0;
}

/* Least squares on the (scaled) design A; spec only takes x and cov back to
 * the caller's units. */
static int ls_core(int m, int N, const double *A, int lda, const double *y,
                   const double *sigma, const double *spec, double rcond,
                   double *x, double *cov, int ldc, int *rank, double *sigma2,
                   double *residual, const ls_extra *ex)
{
    int st;
    /* [D] Column equilibration: the rank is judged and, at full rank, the
     * solution computed on diag(1/sigma) A D_c with D_c = 1/||column||
     * (scale-invariant rank; this keeps NIST Filip at ~8 digits). At rank
     * deficiency the unscaled SVD gives the minimum-norm solution. */
    size_t nn = cov ? (size_t)N * (size_t)N : 0;
    double *cs = igea__dalloc(4 * (size_t)N + (size_t)m + nn);
    if (!cs)
        return IGEA_ENOMEM;
    double *xs = cs + N, *res = xs + N, *g = res + m, *sdt = g + N, *cv = sdt + N;
    equilibrate(m, N, A, lda, sigma, cs);
    canon c;
    st = canon_make(m, N, A, lda, y, sigma, cs, rcond, &c);
    if (st) {
        free(cs);
        return st;
    }
    const double *D = cs;
    if (c.r < N) {
        canon_free(&c);
        st = canon_make(m, N, A, lda, y, sigma, NULL, rcond, &c);
        if (st) {
            free(cs);
            return st;
        }
        D = NULL;
    }
    int r = c.r, steps;
    double s2;
    st = ls_solve(m, N, A, lda, y, sigma, &c, D, ex->refine, g, xs, res, &s2, &steps);
    if (st == 0) {
        for (int i = 0; i < r; i++)
            g[i] = 1.0 / c.s[i] / c.s[i];
        if (cov)
            canon_cov(&c, r, g, s2, D, cv, N);
        ls_sd(&c, r, g, s2, D, spec, sdt);
        st = igea__finite_vec(N, sdt, 1) ? 0 : IGEA_EOVERFLOW;
    }
    if (st == 0)
        st = fit_out(m, N, spec, s2, xs, cv, res, x, cov, ldc, residual);
    if (st == 0 && ex->lev)
        st = canon_leverages(&c, m, N, A, lda, sigma, D, r, ex->lev);
    if (st == 0) {
        *rank = r;
        *sigma2 = s2;
        if (ex->sd)
            memcpy(ex->sd, sdt, (size_t)N * sizeof(double));
        if (ex->info)
            ls_info(&c, rcond, D != NULL, steps, ex->info);
    }
    canon_free(&c);
    free(cs);
    return st;
}

/* Checks common to igea_regress_ls and igea_regress_ls_ex (positions of
 * igea_regress_ls; the caller shifts them). */
static int ls_check(int m, int N, const double *A, int lda, const double *y, double rcond,
                    const double *x, const double *cov, int ldc)
{
    int st = check_args(m, N, A, lda, y, 0);
    if (st)
        return st;
    if (isnan(rcond) || rcond >= 1.0)
        return -8;
    if (!x)
        return -9;
    if (cov && ldc < N)
        return -11;
    return 0;
}

int igea_regress_ls(int m, int N, const double *A, int lda, const double *y,
                    const double *sigma, const double *spec_sigma, double rcond,
                    double *x, double *cov, int ldc, int *rank, double *sigma2,
                    double *residual)
{
    int st = ls_check(m, N, A, lda, y, rcond, x, cov, ldc);
    if (st)
        return st;
    if (!rank)
        return -12;
    if (!sigma2)
        return -13;
    st = check_values(m, N, A, lda, y, sigma, spec_sigma);
    if (st)
        return st;
    double *own;
    if (scaled_design(m, N, &A, &lda, spec_sigma, &own))
        return IGEA_ENOMEM;
    const ls_extra ex = {1, NULL, NULL, NULL};
    st = ls_core(m, N, A, lda, y, sigma, spec_sigma, rcond, x, cov, ldc, rank,
                 sigma2, residual, &ex);
    free(own);
    return st;
}

int igea_regress_ls_ex(int m, int N, const double *A, int lda, const double *y,
                       const double *sigma, const double *spec_sigma, double rcond,
                       int flags, double *x, double *cov, int ldc, double *sd,
                       double *sigma2, double *residual, double *info)
{
    int st = ls_check(m, N, A, lda, y, rcond, x, cov, ldc);
    if (st)
        return st < -8 ? st - 1 : st;
    if (flags & ~IGEA_REGRESS_NO_REFINE)
        return -9;
    if (!sigma2)
        return -14;
    if (!info)
        return -16;
    st = check_values(m, N, A, lda, y, sigma, spec_sigma);
    if (st)
        return st;
    double *own;
    if (scaled_design(m, N, &A, &lda, spec_sigma, &own))
        return IGEA_ENOMEM;
    const ls_extra ex = {!(flags & IGEA_REGRESS_NO_REFINE), sd, info, NULL};
    int rank;
    st = ls_core(m, N, A, lda, y, sigma, spec_sigma, rcond, x, cov, ldc, &rank,
                 sigma2, residual, &ex);
    free(own);
    return st;
}

int igea_regress_rank_info(int m, int N, const double *A, int lda, const double *sigma,
                           const double *spec_sigma, double rcond, double *info)
{
    int st = check_args(m, N, A, lda, NULL, 1);
    if (st)
        return st;
    if (isnan(rcond) || rcond >= 1.0)
        return -7;
    if (!info)
        return -8;
    if ((st = check_values(m, N, A, lda, NULL, sigma, spec_sigma)))
        return st;
    canon c;
    if ((st = canon_make(m, N, A, lda, NULL, sigma, spec_sigma, rcond, &c)))
        return st;
    ls_info(&c, rcond, 0, 0, info);
    canon_free(&c);
    return 0;
}

int igea_regress_sd(int N, const double *cov, int ldc, double *sd)
{
    if (N < 1)
        return -1;
    if (!cov)
        return -2;
    if (ldc < N)
        return -3;
    if (!sd)
        return -4;
    for (int j = 0; j < N; j++) {
        double v = cov[j + (size_t)j * ldc];
        if (!isfinite(v))
            return IGEA_ENONFINITE;
        if (v < 0.0)
            return IGEA_EDOMAIN;
    }
    for (int j = 0; j < N; j++)
        sd[j] = sqrt(cov[j + (size_t)j * ldc]);
    return 0;
}

/* ---- regression diagnostics -------------------------------------------- */

/* 1 when some column of A is constant and nonzero (a model intercept). */
static int has_constant(int m, int N, const double *A, int lda)
{
    for (int j = 0; j < N; j++) {
        double v = IGEA_AT(A, lda, 0, j);
        int same = v != 0.0;
        for (int i = 1; same && i < m; i++)
            same = IGEA_AT(A, lda, i, j) == v;
        if (same)
            return 1;
    }
    return 0;
}

/* Leverages h_i = sum_{k<r} U_ik^2 of the weighted design, the rank
 * judged as igea_regress_ls does (column-equilibrated at full rank). A
 * tall design of full rank through its QR factor [D]: B = Q_1 R, so the
 * leverages are the squared row norms of Q_1 = B R^-1, each row by a
 * triangular solve with R (dtrsm over row blocks, no m x N U), whose
 * relative error is about eps s_1 / s_N; this route is taken where
 * s_1 / s_N <= IGEA__LEV_COND (h to about 1e-12), else U from the SVD of
 * the weighted copy. */
#define IGEA__LEV_COND 1e4
#define IGEA__LEV_ROWS 1024
static void leverages_qr(const canon *c, int m, int N, const double *A, int lda,
                         const double *sigma, const double *cs, double *W, double *h)
{
    for (int i0 = 0; i0 < m; i0 += IGEA__LEV_ROWS) {
        int nb = IGEA_MIN(IGEA__LEV_ROWS, m - i0);
        for (int j = 0; j < N; j++)
            for (int i = 0; i < nb; i++)
                W[i + (size_t)j * nb] = IGEA_AT(A, lda, i0 + i, j) * (cs ? cs[j] : 1.0) /
                                        (sigma ? sigma[i0 + i] : 1.0);
        cblas_dtrsm(CblasColMajor, CblasRight, CblasUpper, CblasNoTrans, CblasNonUnit, nb, N,
                    1.0, c->R, N + 1, W, nb);
        for (int i = 0; i < nb; i++)
            h[i0 + i] = 0.0;
        for (int j = 0; j < N; j++)
            for (int i = 0; i < nb; i++)
                h[i0 + i] += W[i + (size_t)j * nb] * W[i + (size_t)j * nb];
    }
}

/* The leverages of the first r columns of c's U into h (m): through the
 * QR factor at full rank where the conditioning allows (leverages_qr), else from U,
 * made by the SVD of the weighted copy when c has none (D the column scale
 * c was made with). */
static int canon_leverages(const canon *c, int m, int N, const double *A, int lda,
                           const double *sigma, const double *D, int r, double *h)
{
    int rr = IGEA_MIN(r, c->k), st = 0;
    if (c->qr && rr == N && c->s[0] <= IGEA__LEV_COND * c->s[N - 1]) {
        double *W = igea__dalloc((size_t)IGEA__LEV_ROWS * N);
        if (!W)
            return IGEA_ENOMEM;
        leverages_qr(c, m, N, A, lda, sigma, D, W, h);
        free(W);
        return 0;
    }
    canon u;
    const canon *cu = c;
    if (c->qr) {
        if ((st = canon_make_u(m, N, A, lda, NULL, sigma, D, 0.0, 1, &u)))
            return st;
        cu = &u;
    }
    for (int i = 0; i < m; i++) {
        double a = 0.0;
        for (int k = 0; k < rr; k++)
            a += cu->U[i + (size_t)k * m] * cu->U[i + (size_t)k * m];
        h[i] = a;
    }
    if (cu == &u)
        canon_free(&u);
    return 0;
}

/* The scalar diagnostics from the weighted residuals e, the weights, the
 * leverages h (statsmodels' OLS/WLS conventions, docs/regress.md). */
static int diag_scalars(int m, const double *y, const double *sigma, const double *e,
                        const double *h, int r, int kc, double *d)
{
    long double sw = 0, swy = 0, ssr = 0, tss = 0, lw = 0, dw = 0, press = 0;
    for (int i = 0; i < m; i++) {
        long double w = sigma ? 1.0L / ((long double)sigma[i] * sigma[i]) : 1.0L;
        sw += w;
        swy += w * y[i];
        ssr += (long double)e[i] * e[i];
        lw += logl(w);
        if (i > 0)
            dw += ((long double)e[i] - e[i - 1]) * ((long double)e[i] - e[i - 1]);
        press += ((long double)e[i] / (1.0L - h[i])) * ((long double)e[i] / (1.0L - h[i]));
    }
    long double ybar = kc ? swy / sw : 0.0L;
    for (int i = 0; i < m; i++) {
        long double w = sigma ? 1.0L / ((long double)sigma[i] * sigma[i]) : 1.0L;
        tss += w * (y[i] - ybar) * (y[i] - ybar);
    }
    if (!(tss > 0) || !(ssr > 0))
        return IGEA_EDOMAIN;
    int dfm = r - kc, dfr = m - r;
    long double ess = tss > ssr ? tss - ssr : 0.0L, n = m;
    double F = dfm > 0 ? (double)((ess / dfm) / (ssr / dfr)) : 0.0, pf = 1.0;
    if (dfm > 0 && igea_stats_f_sf(F, dfm, dfr, &pf))
        return IGEA_EDOMAIN;
    long double llf = -0.5L * n * (logl(2.0L * 3.14159265358979323846264338327950288L * ssr / n)
                                   + 1.0L) + 0.5L * lw;
    d[IGEA_REGRESS_DIAG_R2] = (double)(1.0L - ssr / tss);
    d[IGEA_REGRESS_DIAG_R2_ADJ] = (double)(1.0L - (n - kc) / dfr * (ssr / tss));
    d[IGEA_REGRESS_DIAG_FVALUE] = F;
    d[IGEA_REGRESS_DIAG_F_PVALUE] = pf;
    d[IGEA_REGRESS_DIAG_LLF] = (double)llf;
    d[IGEA_REGRESS_DIAG_AIC] = (double)(-2.0L * llf + 2.0L * r);
    d[IGEA_REGRESS_DIAG_BIC] = (double)(-2.0L * llf + logl(n) * r);
    d[IGEA_REGRESS_DIAG_PRESS] = (double)press;
    d[IGEA_REGRESS_DIAG_DURBIN_WATSON] = (double)(dw / ssr);
    d[IGEA_REGRESS_DIAG_DF_MODEL] = dfm;
    d[IGEA_REGRESS_DIAG_DF_RESID] = dfr;
    d[IGEA_REGRESS_DIAG_CONSTANT] = kc;
    d[IGEA_REGRESS_DIAG_SSR] = (double)ssr;
    d[IGEA_REGRESS_DIAG_TSS] = (double)tss;
    return 0;
}

/* t, p, confidence limits per coefficient and Cook's distances. */
static int diag_coef(int m, int N, const double *x, const double *sd, const double *e,
                     const double *h, double s2, int dfr, double alpha, double *w, double *d)
{
    double tc;
    if (igea_stats_t_quantile(1.0 - 0.5 * alpha, dfr, &tc))
        return IGEA_EDOMAIN;
    double *t = w, *p = t + N, *lo = p + N, *hi = lo + N, *cd = hi + N;
    for (int j = 0; j < N; j++) {
        t[j] = sd[j] > 0 ? x[j] / sd[j] : 0.0;
        double q = 0.5;
        if (sd[j] > 0 && igea_stats_t_sf(fabs(t[j]), dfr, &q))
            return IGEA_EDOMAIN;
        p[j] = 2.0 * q;
        lo[j] = x[j] - tc * sd[j];
        hi[j] = x[j] + tc * sd[j];
    }
    for (int i = 0; i < m; i++) {
        double ri2 = e[i] * e[i] / (s2 * (1.0 - h[i]));
        cd[i] = ri2 / N * h[i] / (1.0 - h[i]);
    }
    d[IGEA_REGRESS_DIAG_T_CRIT] = tc;
    return igea__finite_vec(4 * N + m, w, 1) ? 0 : IGEA_EOVERFLOW;
}

/* The diagnostics of a fit: x, sd (the caller's units), res its unweighted
 * residuals, h its leverages, rank, s2; e (m) receives the weighted
 * residuals, w the coefficient and observation arrays, dg the scalars.
 * IGEA_EDOMAIN when they are not defined. */
static int diag_of_fit(int m, int N, const double *A, int lda, const double *y,
                       const double *sigma, double alpha, const double *xs, const double *sd,
                       const double *res, const double *h, int rank, double s2, double *e,
                       double *w, double *dg)
{
    if (m - rank < 1 || !(s2 > 0.0))
        return IGEA_EDOMAIN;
    for (int i = 0; i < m; i++)
        e[i] = sigma ? res[i] / sigma[i] : res[i];
    for (int i = 0; i < m; i++)
        if (!(h[i] < 1.0 - 1e-10))
            return IGEA_EDOMAIN;
    for (int i = 0; i < IGEA_REGRESS_DIAG_LEN; i++)
        dg[i] = 0.0;
    int st = diag_scalars(m, y, sigma, e, h, rank, has_constant(m, N, A, lda), dg);
    if (st == 0)
        st = diag_coef(m, N, xs, sd, e, h, s2, m - rank, alpha, w, dg);
    dg[IGEA_REGRESS_DIAG_RANK] = rank;
    if (st == 0 && !igea__finite_vec(IGEA_REGRESS_DIAG_LEN, dg, 1))
        st = IGEA_EOVERFLOW;
    return st;
}

/* The diagnostics into scratch (x, sd, e, h, coefficient and observation
 * arrays w, dg); the caller copies them out. */
static int diag_run(int m, int N, const double *A, int lda, const double *y,
                    const double *sigma, double rcond, double alpha, double *xs, double *sd,
                    double *e, double *h, double *w, double *dg)
{
    double s2, info[IGEA_REGRESS_INFO_LEN];
    const ls_extra ex = {1, sd, info, h}; /* the leverages of the fit's own form */
    int rank;
    int st = ls_core(m, N, A, lda, y, sigma, NULL, rcond, xs, NULL, 0, &rank, &s2, e, &ex);
    if (st)
        return st;
    return diag_of_fit(m, N, A, lda, y, sigma, alpha, xs, sd, e, h, rank, s2, e, w, dg);
}

static void copy_opt(double *dst, const double *src, int n)
{
    if (dst)
        memcpy(dst, src, (size_t)n * sizeof(double));
}

int igea_regress_ls_diag(int m, int N, const double *A, int lda, const double *y,
                         const double *sigma, double rcond, double alpha, double *x,
                         double *sd, double *tvalues, double *pvalues, double *ci_lower,
                         double *ci_upper, double *leverage, double *cooks_d, double *diag)
{
    int st = check_args(m, N, A, lda, y, 0);
    if (st)
        return st;
    if (isnan(rcond) || rcond >= 1.0)
        return -7;
    if (!(alpha > 0.0 && alpha < 1.0))
        return -8;
    if (!x)
        return -9;
    if (!sd)
        return -10;
    if (!diag)
        return -17;
    if ((st = check_values(m, N, A, lda, y, sigma, NULL)))
        return st;
    double *mem = igea__dalloc(6 * (size_t)N + 3 * (size_t)m + IGEA_REGRESS_DIAG_LEN);
    if (!mem)
        return IGEA_ENOMEM;
    double *xs = mem, *sds = xs + N, *e = sds + N, *h = e + m, *w = h + m;
    double *dg = w + 4 * (size_t)N + m;
    st = diag_run(m, N, A, lda, y, sigma, rcond, alpha, xs, sds, e, h, w, dg);
    if (st == 0) {
        memcpy(x, xs, (size_t)N * sizeof(double));
        memcpy(sd, sds, (size_t)N * sizeof(double));
        copy_opt(tvalues, w, N);
        copy_opt(pvalues, w + N, N);
        copy_opt(ci_lower, w + 2 * N, N);
        copy_opt(ci_upper, w + 3 * N, N);
        copy_opt(leverage, h, m);
        copy_opt(cooks_d, w + 4 * N, m);
        memcpy(diag, dg, IGEA_REGRESS_DIAG_LEN * sizeof(double));
    }
    free(mem);
    return st;
}

int igea_regress_ls_full(int m, int N, const double *A, int lda, const double *y,
                         const double *sigma, const double *spec_sigma, double rcond, int flags,
                         double alpha, double *x, double *cov, int ldc, double *sd,
                         double *sigma2, double *residual, double *info, double *tvalues,
                         double *pvalues, double *ci_lower, double *ci_upper, double *leverage,
                         double *cooks_d, double *diag)
{
    int st = check_args(m, N, A, lda, y, 0);
    if (st)
        return st;
    if (isnan(rcond) || rcond >= 1.0) return -8;
    if (flags & ~IGEA_REGRESS_NO_REFINE) return -9;
    if (!(alpha > 0.0 && alpha < 1.0)) return -10;
    if (!x) return -11;
    if (cov && ldc < N) return -13;
    if (!sigma2) return -15;
    if (!info) return -17;
    if (!diag) return -24;
    if ((st = check_values(m, N, A, lda, y, sigma, spec_sigma)))
        return st;
    const double *As = A;
    int las = lda;
    double *own;
    if (scaled_design(m, N, &As, &las, spec_sigma, &own))
        return IGEA_ENOMEM;
    size_t n = (size_t)N, mm = (size_t)m;
    /* the fit's x, cov, sd, residuals, leverages; the weighted residuals,
     * the diagnostics' arrays (4 N + m) and scalars; info */
    double *mem = igea__dalloc(3 * n + n * n + 3 * mm + 4 * n + mm + IGEA_REGRESS_DIAG_LEN +
                               IGEA_REGRESS_INFO_LEN);
    if (!mem) {
        free(own);
        return IGEA_ENOMEM;
    }
    double *xs = mem, *sds = xs + n, *cv = sds + n, *res = cv + n * n, *h = res + mm;
    double *e = h + mm, *w = e + mm, *dg = w + 4 * n + mm, *inf = dg + IGEA_REGRESS_DIAG_LEN;
    const ls_extra ex = {!(flags & IGEA_REGRESS_NO_REFINE), sds, inf, h};
    int rank;
    double s2;
    st = ls_core(m, N, As, las, y, sigma, spec_sigma, rcond, xs, cov ? cv : NULL, N, &rank, &s2,
                 res, &ex);
    free(own);
    if (st == 0) {
        int ds = diag_of_fit(m, N, A, lda, y, sigma, alpha, xs, sds, res, h, rank, s2, e, w, dg);
        st = ds == IGEA_EDOMAIN ? IGEA_REGRESS_NO_DIAG : ds;
    }
    if (st >= 0) {
        memcpy(x, xs, n * sizeof(double));
        for (int j = 0; cov && j < N; j++)
            memcpy(cov + (size_t)j * ldc, cv + (size_t)j * n, n * sizeof(double));
        copy_opt(sd, sds, N);
        *sigma2 = s2;
        copy_opt(residual, res, m);
        memcpy(info, inf, IGEA_REGRESS_INFO_LEN * sizeof(double));
    }
    if (st == 0) {
        copy_opt(tvalues, w, N);
        copy_opt(pvalues, w + N, N);
        copy_opt(ci_lower, w + 2 * n, N);
        copy_opt(ci_upper, w + 3 * n, N);
        copy_opt(leverage, h, m);
        copy_opt(cooks_d, w + 4 * n, m);
        memcpy(diag, dg, IGEA_REGRESS_DIAG_LEN * sizeof(double));
    }
    free(mem);
    return st;
}

/* ---- scalar root finding and minimisation ------------------------------ */

typedef double (*scalar_fn)(double, const void *);

/* Brent's zeroin on [a, b] with f(a) f(b) <= 0; tolerance 4 eps |x|. */
static double brent_root(scalar_fn f, const void *ctx, double a, double b,
                         double fa, double fb, int *ok)
{
    double c = a, fc = fa, d = b - a, e = d;
    *ok = 0;
    for (int it = 0; it < 300; it++) {
        if ((fb > 0 && fc > 0) || (fb < 0 && fc < 0)) {
            c = a;
            fc = fa;
            d = e = b - a;
        }
        if (fabs(fc) < fabs(fb)) {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        double tol = 2.0 * DBL_EPSILON * fabs(b) + 1e-300;
        double xm = 0.5 * (c - b);
        if (fabs(xm) <= tol || fb == 0.0) {
            *ok = 1;
            return b;
        }
        if (fabs(e) >= tol && fabs(fa) > fabs(fb)) {
            double s = fb / fa, p, q;
            if (a == c) {
                p = 2.0 * xm * s;
                q = 1.0 - s;
            } else {
                double qq = fa / fc, rr = fb / fc;
                p = s * (2.0 * xm * qq * (qq - rr) - (b - a) * (rr - 1.0));
                q = (qq - 1.0) * (rr - 1.0) * (s - 1.0);
            }
            if (p > 0)
                q = -q;
            else
                p = -p;
            if (2.0 * p < IGEA_MIN(3.0 * xm * q - fabs(tol * q), fabs(e * q))) {
                e = d;
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        a = b;
        fa = fb;
        b += fabs(d) > tol ? d : (xm > 0 ? tol : -tol);
        fb = f(b, ctx);
    }
    return b;
}

/* Minimise f over t in [lo, hi] on a grid of n points and a golden-section
 * refinement between the neighbours of the best point. */
static double grid_golden_min(scalar_fn f, const void *ctx, double lo,
                              double hi, int n)
{
    double best = lo, fbest = f(lo, ctx);
    int ib = 0;
    for (int i = 1; i < n; i++) {
        double t = lo + (hi - lo) * i / (n - 1);
        double v = f(t, ctx);
        if (v < fbest) {
            fbest = v;
            best = t;
            ib = i;
        }
    }
    double a = lo + (hi - lo) * IGEA_MAX(ib - 1, 0) / (n - 1);
    double b = lo + (hi - lo) * IGEA_MIN(ib + 1, n - 1) / (n - 1);
    const double gr = 0.6180339887498949;
    double x1 = b - gr * (b - a), x2 = a + gr * (b - a);
    double f1 = f(x1, ctx), f2 = f(x2, ctx);
    for (int it = 0; it < 80 && b - a > 1e-12 * (1.0 + fabs(a)); it++) {
        if (f1 < f2) {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - gr * (b - a);
            f1 = f(x1, ctx);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + gr * (b - a);
            f2 = f(x2, ctx);
        }
    }
    double t = f1 < f2 ? x1 : x2, ft = IGEA_MIN(f1, f2);
    return ft < fbest ? t : best;
}

/* ---- EBR --------------------------------------------------------------- */

typedef struct {
    int r;
    const double *d, *z2;
    double target, s2hat;
} ebr_ctx;

/* sum z_i^2 / (1 + lambda d_i) - target (decreasing in lambda). */
static double ebr_moment(double lam, const void *p)
{
    const ebr_ctx *q = p;
    igea__ksum acc = {0.0, 0.0};
    for (int i = 0; i < q->r; i++)
        igea__ksum_add(&acc, q->z2[i] / fma(lam, q->d[i], 1.0));
    return igea__ksum_get(&acc) - q->target;
}

/* Derivative of the type-II log likelihood (times 2, sign kept). */
static double ebr_ml2_grad(double lam, const void *p)
{
    const ebr_ctx *q = p;
    igea__ksum acc = {0.0, 0.0};
    for (int i = 0; i < q->r; i++) {
        double w = fma(lam, q->d[i], 1.0);
        igea__ksum_add(&acc,
                       q->d[i] / w * (q->z2[i] / (q->s2hat * w) - 1.0));
    }
    return igea__ksum_get(&acc);
}

static double ebr_ml2_negll(double lam, const void *p)
{
    const ebr_ctx *q = p;
    double acc = 0.0;
    for (int i = 0; i < q->r; i++) {
        double w = fma(lam, q->d[i], 1.0);
        acc += log(w) + q->z2[i] / (q->s2hat * w);
    }
    return acc;
}

/* lambda* of the rule; 0 by the positive-part rule when there is no root. */
static int ebr_lambda(int rule, ebr_ctx *q, double *lam)
{
    if (rule == IGEA_REGRESS_EBR_ML2) {
        /* The maximiser lies in [0, lmax]: beyond lmax every term of the
         * gradient is negative. Grid on log scale, then Brent on the
         * gradient's sign change next to the best grid point. */
        double lmax = 0.0;
        for (int i = 0; i < q->r; i++)
            lmax = IGEA_MAX(lmax, (q->z2[i] / q->s2hat - 1.0) / q->d[i]);
        if (!(lmax > 0.0)) {
            *lam = 0.0;
            return 0;
        }
        const int n = 241;
        double best = 0.0, fbest = ebr_ml2_negll(0.0, q);
        int ib = -1;
        double grid[241];
        for (int i = 0; i < n; i++) {
            grid[i] = lmax * pow(10.0, -16.0 * (n - 1 - i) / (n - 1));
            double v = ebr_ml2_negll(grid[i], q);
            if (v < fbest) {
                fbest = v;
                best = grid[i];
                ib = i;
            }
        }
        if (ib < 0) {
            *lam = 0.0;
            return 0;
        }
        double a = ib > 0 ? grid[ib - 1] : 0.0;
        double b = ib < n - 1 ? grid[ib + 1] : lmax;
        double ga = ebr_ml2_grad(a, q), gb = ebr_ml2_grad(b, q);
        if (ga > 0 && gb < 0) {
            int ok;
            double t = brent_root(ebr_ml2_grad, q, a, b, ga, gb, &ok);
            if (ok && ebr_ml2_negll(t, q) <= fbest)
                best = t;
        }
        *lam = best;
        return 0;
    }
    double f0 = ebr_moment(0.0, q);
    if (!(f0 > 0.0)) {
        *lam = 0.0; /* positive-part rule */
        return 0;
    }
    double lo = 0.0, hi = 1.0 / q->d[0], fhi = ebr_moment(hi, q);
    int grow = 0;
    while (fhi > 0.0) {
        lo = hi;
        f0 = fhi;
        hi *= 10.0;
        fhi = ebr_moment(hi, q);
        if (++grow > 700 || !isfinite(hi))
            return IGEA_ENOCONV;
    }
    int ok;
    double t = brent_root(ebr_moment, q, lo, hi, f0, fhi, &ok);
    if (!ok)
        return IGEA_ENOCONV;
    *lam = t;
    return 0;
}

/* The weighted residual sum of squares S and lambda hat of METHODS 4.3
 * steps 4-6 on the canonical form c (rank r >= 3, m > r): d_i = (s_i /
 * s_1)^2 and z2_i = z_i^2 into d and z2, lambda hat in the units of the
 * scaled problem (*lh) and of the form scaled by 1/s_1 (*lhs). */
static int ebr_fit(const canon *c, int rule, double lam_floor, double *d,
                   double *z2, double *S_out, double *lh, double *lhs)
{
    int m = c->m, r = c->r;
    if (r < 3)
        return IGEA_ERANK;
    double S = canon_rss(c);
    if (m <= r || !(S > 0.0))
        return IGEA_EDOMAIN;
    if (!isfinite(S))
        return IGEA_EOVERFLOW;
    /* The canonical form is solved on the design scaled by 1/s_1 (d_i =
     * (s_i / s_1)^2 in (0, 1]): lambda d_i, the shrinkage and the
     * equations of every rule are unchanged by a scale of A, and lambda
     * itself is lambda' / s_1^2. */
    double s1 = c->s[0], lstar = 0.0;
    for (int i = 0; i < r; i++) {
        double q = c->s[i] / s1;
        d[i] = q * q;
        z2[i] = c->z[i] * c->z[i];
    }
    if (!igea__finite_vec(r, z2, 1))
        return IGEA_EOVERFLOW;
    ebr_ctx q = {r, d, z2, 0.0, S / (m - r)};
    if (rule == IGEA_REGRESS_EBR_SC)
        q.target = (double)(r - 2) * S / (double)(m - r + 2);
    else if (rule == IGEA_REGRESS_EBR_MM)
        q.target = (double)r * S / (double)(m - r);
    int st = ebr_lambda(rule, &q, &lstar);
    if (st)
        return st;
    *lh = IGEA_MAX(lstar / s1 / s1, lam_floor);
    *lhs = *lh * s1 * s1;
    if (!isfinite(*lh) || !isfinite(*lhs) || (lstar > 0.0 && !(*lh > 0.0)))
        return IGEA_EOVERFLOW;
    *S_out = S;
    return 0;
}

/* Scratch results of EBR, copied to the caller's arrays on success. */
typedef struct {
    double *d, *z2, *f, *g, *bt, *sp, *freq, *res, *cv;
} ebr_out;

/* beta, the shrinkage, the posterior covariance and the frequentist sds
 * (METHODS 4.3 steps 7-8) from lambda hat, into the scratch. */
static void ebr_results(const canon *c, const double *spec, double lhs,
                        double s2, int want_cov, ebr_out *o)
{
    int N = c->N, r = c->r;
    double s1 = c->s[0];
    for (int i = 0; i < r; i++) {
        double den = fma(lhs, o->d[i], 1.0);
        o->sp[i] = lhs * o->d[i] / den;
        o->f[i] = o->sp[i] / c->s[i]; /* theta_i = f_i z_i */
    }
    canon_coef(c, r, o->f, spec, o->bt);
    /* Posterior: every direction, d_i = 0 beyond r (the prior variance);
     * the variances carry the factor 1 / s_1^2 of the scaled form. */
    if (want_cov) {
        for (int i = 0; i < N; i++) {
            double di = i < r ? o->d[i] : 0.0;
            o->g[i] = lhs / fma(lhs, di, 1.0);
        }
        canon_cov(c, N, o->g, s2, spec, o->cv, N);
        for (size_t k = 0; k < (size_t)N * N; k++)
            o->cv[k] = o->cv[k] / s1 / s1;
    }
    for (int i = 0; i < r; i++) {
        double den = fma(lhs, o->d[i], 1.0);
        o->g[i] = lhs * lhs * o->d[i] / (den * den);
    }
    canon_sd(c, r, o->g, s2, spec, o->freq);
    for (int i = 0; i < N; i++)
        o->freq[i] /= s1;
}

int igea_regress_ebr(int m, int N, const double *A, int lda, const double *y,
                     const double *sigma, const double *spec_sigma, int rule,
                     double lam_floor, double *x, double *cov, int ldc,
                     double *lam, int *rank, double *sigma2, double *residual,
                     double *shrink, double *sd_freq)
{
    int st = check_args(m, N, A, lda, y, 0);
    if (st)
        return st;
    if (rule != IGEA_REGRESS_EBR_SC && rule != IGEA_REGRESS_EBR_MM && rule != IGEA_REGRESS_EBR_ML2)
        return -8;
    if (!(lam_floor >= 0.0) || !isfinite(lam_floor))
        return -9;
    if (!x)
        return -10;
    if (cov && ldc < N)
        return -12;
    if (!lam)
        return -13;
    if (!rank)
        return -14;
    if (!sigma2)
        return -15;
    st = check_values(m, N, A, lda, y, sigma, spec_sigma);
    if (st)
        return st;
    canon c;
    st = canon_make(m, N, A, lda, y, sigma, spec_sigma, 0.0, &c);
    if (st)
        return st;
    size_t n = (size_t)N, nn = cov ? n * n : 0;
    double *w = igea__dalloc(7 * n + (size_t)m + nn + 2);
    if (!w) {
        canon_free(&c);
        return IGEA_ENOMEM;
    }
    ebr_out o = {w, w + n, w + 2 * n, w + 3 * n, w + 4 * n, w + 5 * n, w + 6 * n,
                 w + 7 * n, w + 7 * n + m};
    double S = 0.0, lh = 0.0, lhs = 0.0;
    st = ebr_fit(&c, rule, lam_floor, o.d, o.z2, &S, &lh, &lhs);
    int r = c.r;
    double s2 = st == 0 ? S / (m - r) : 0.0;
    if (st == 0) {
        ebr_results(&c, spec_sigma, lhs, s2, cov != NULL, &o);
        residual_of(m, N, A, lda, y, o.bt, o.res);
        if (!igea__finite_vec(N, o.bt, 1) || !igea__finite_vec(r, o.sp, 1) ||
            !igea__finite_vec(m, o.res, 1) || !isfinite(s2) ||
            (cov && !igea__finite_mat(N, N, o.cv, N)) ||
            (sd_freq && !igea__finite_vec(N, o.freq, 1)))
            st = IGEA_EOVERFLOW;
    }
    if (st == 0) {
        memcpy(x, o.bt, n * sizeof(double));
        if (cov)
            for (int j = 0; j < N; j++)
                memcpy(cov + (size_t)j * ldc, o.cv + (size_t)j * N, n * sizeof(double));
        *lam = lh;
        *rank = r;
        *sigma2 = s2;
        if (residual)
            memcpy(residual, o.res, (size_t)m * sizeof(double));
        if (shrink)
            for (int i = 0; i < N; i++)
                shrink[i] = i < r ? o.sp[i] : 0.0;
        if (sd_freq)
            memcpy(sd_freq, o.freq, n * sizeof(double));
    }
    free(w);
    canon_free(&c);
    return st;
}

/* ---- ridge ------------------------------------------------------------- */

typedef struct {
    const canon *c;
    double rss_ls;
    int loo;
} ridge_ctx;

/* GCV or LOO criterion as a function of t = log10 k; every term depends on
 * d_i / (d_i + k) alone, formed from s_i / sqrt(k) (no s_i^2). */
static double ridge_crit(double t, const void *p)
{
    const ridge_ctx *q = p;
    const canon *c = q->c;
    double rk = pow(10.0, 0.5 * t);
    int m = c->m, r = c->r;
    if (!q->loo) {
        igea__ksum rss = {q->rss_ls, 0.0};
        double edf = 0.0;
        for (int i = 0; i < r; i++) {
            double h = ridge_hat(c->s[i], rk), sh = (1.0 - h) * c->z[i];
            igea__ksum_add(&rss, sh * sh);
            edf += h;
        }
        double den = m - edf;
        if (!(den > 0.0))
            return HUGE_VAL;
        return m * (igea__ksum_get(&rss) / den / den);
    }
    igea__ksum press = {0.0, 0.0};
    for (int j = 0; j < m; j++) {
        double e = c->yw[j], h = 0.0;
        for (int i = 0; i < r; i++) {
            double f = ridge_hat(c->s[i], rk);
            double u = c->U[j + (size_t)i * m];
            e -= u * f * c->z[i];
            h += u * u * f;
        }
        if (!(h < 1.0))
            return HUGE_VAL;
        double v = e / (1.0 - h);
        igea__ksum_add(&press, v * v);
    }
    return igea__ksum_get(&press);
}

/* Euclidean norm without overflow or underflow of the squares. */
static double norm2(int n, const double *x)
{
    double sc = 0.0, ss = 1.0;
    for (int i = 0; i < n; i++) {
        double a = fabs(x[i]);
        if (a == 0.0)
            continue;
        if (a > sc) {
            ss = 1.0 + ss * (sc / a) * (sc / a);
            sc = a;
        } else
            ss += (a / sc) * (a / sc);
    }
    return sc * sqrt(ss);
}

/* sqrt(k) of a ridge rule on the canonical form (rss its LS residual sum
 * of squares, s2 = rss / (m - r)); f and xs are scratch (N each). Returns
 * 0 or IGEA_EDOMAIN (HKB/LW without residual or with x_LS = 0). */
static int ridge_rule_rk(const canon *c, int rule, double rss, double s2,
                         double *f, double *xs, double *rk)
{
    int m = c->m, N = c->N, r = c->r;
    if (rule == IGEA_REGRESS_RIDGE_HKB || rule == IGEA_REGRESS_RIDGE_LW) {
        for (int i = 0; i < r; i++)
            f[i] = 1.0 / c->s[i];
        canon_coef(c, r, f, NULL, xs);
        double den = rule == IGEA_REGRESS_RIDGE_HKB ? norm2(N, xs) : norm2(r, c->z);
        if (m <= r || !(den > 0.0))
            return IGEA_EDOMAIN;
        *rk = sqrt((double)r * s2) / den;
    } else if (rule == IGEA_REGRESS_RIDGE_GCV || rule == IGEA_REGRESS_RIDGE_LOO) {
        if (r == 0)
            *rk = 0.0;
        else {
            ridge_ctx q = {c, rss, rule == IGEA_REGRESS_RIDGE_LOO};
            double t0 = 2.0 * log10(c->s[0]);
            *rk = pow(10.0, 0.5 * grid_golden_min(ridge_crit, &q, t0 - 12.0,
                                                  t0 + 4.0, 161));
        }
    }
    return 0;
}

static int ridge_core(int m, int N, const double *A, int lda, const double *y,
                      const double *sigma, const double *spec, int rule,
                      double k, double *x, double *cov, int ldc,
                      double *k_used, double *sigma2, double *residual, double *info)
{
    canon c; /* the LOO rule reads U's rows */
    int st = canon_make_u(m, N, A, lda, y, sigma, NULL, 0.0, rule == IGEA_REGRESS_RIDGE_LOO, &c);
    if (st)
        return st;
    int r = c.r;
    double rss = canon_rss(&c);
    double s2 = m > r ? rss / (m - r) : 0.0;
    /* Scratch: f, g (N each), x (N), residual (m), cov (N x N). */
    size_t nn = cov ? (size_t)N * (size_t)N : 0;
    double *w = igea__dalloc(3 * (size_t)N + (size_t)m + nn);
    if (!w) {
        canon_free(&c);
        return IGEA_ENOMEM;
    }
    double *f = w, *g = w + N, *xs = g + N, *res = xs + N, *cv = res + m;
    if (!isfinite(rss))
        st = IGEA_EOVERFLOW;
    /* The rules find rk = sqrt(k), which stays representable where k
     * itself may not be; k_used = rk^2 must then be. */
    double rk = sqrt(k);
    if (st == 0)
        st = ridge_rule_rk(&c, rule, rss, s2, f, xs, &rk);
    double kk = rule == IGEA_REGRESS_RIDGE_FIXED ? k : rk * rk;
    if (st == 0 && (!isfinite(kk) || (rk > 0.0 && kk < DBL_MIN)))
        st = IGEA_EOVERFLOW;
    if (st == 0) {
        for (int i = 0; i < r; i++) {
            f[i] = ridge_factor(c.s[i], kk);
            g[i] = f[i] * f[i]; /* d / (d + k)^2 */
        }
        /* Everything into scratch; the caller's arrays are written last. */
        canon_coef(&c, r, f, NULL, xs);
        if (cov)
            canon_cov(&c, r, g, s2, NULL, cv, N);
        residual_of(m, N, A, lda, y, xs, res);
        st = fit_out(m, N, spec, s2, xs, cv, res, x, cov, ldc, residual);
    }
    if (st == 0) {
        *k_used = kk;
        *sigma2 = s2;
        if (info)
            ls_info(&c, 0.0, 0, 0, info);
    }
    free(w);
    canon_free(&c);
    return st;
}

/* Argument checks of igea_regress_ridge (and _ex). */
static int ridge_check(int m, int N, const double *A, int lda, const double *y, int rule,
                       double k, const double *x, const double *cov, int ldc,
                       const double *k_used, const double *sigma2)
{
    int st = check_args(m, N, A, lda, y, 0);
    if (st)
        return st;
    if (rule < IGEA_REGRESS_RIDGE_FIXED || rule > IGEA_REGRESS_RIDGE_LOO)
        return -8;
    if (rule == IGEA_REGRESS_RIDGE_FIXED && !(k >= 0.0 && isfinite(k)))
        return -9;
    if (!x)
        return -10;
    if (cov && ldc < N)
        return -12;
    if (!k_used)
        return -13;
    if (!sigma2)
        return -14;
    return 0;
}

int igea_regress_ridge(int m, int N, const double *A, int lda,
                       const double *y, const double *sigma,
                       const double *spec_sigma, int rule, double k, double *x,
                       double *cov, int ldc, double *k_used, double *sigma2,
                       double *residual)
{
    int st = ridge_check(m, N, A, lda, y, rule, k, x, cov, ldc, k_used, sigma2);
    if (st)
        return st;
    st = check_values(m, N, A, lda, y, sigma, spec_sigma);
    if (st)
        return st;
    double *own;
    if (scaled_design(m, N, &A, &lda, spec_sigma, &own))
        return IGEA_ENOMEM;
    st = ridge_core(m, N, A, lda, y, sigma, spec_sigma, rule, k, x, cov, ldc,
                    k_used, sigma2, residual, NULL);
    free(own);
    return st;
}

int igea_regress_ridge_trace(int m, int N, const double *A, int lda,
                             const double *y, const double *sigma,
                             const double *spec_sigma, int nk, const double *k,
                             double *X, int ldx, double *edf)
{
    int st = check_args(m, N, A, lda, y, 0);
    if (st)
        return st;
    if (nk < 1)
        return -8;
    if (!k)
        return -9;
    for (int j = 0; j < nk; j++)
        if (!(k[j] >= 0.0 && isfinite(k[j])))
            return -9;
    if (!X)
        return -10;
    if (ldx < N)
        return -11;
    st = check_values(m, N, A, lda, y, sigma, spec_sigma);
    if (st)
        return st;
    /* The scaled design A D is the canonical form's column scale cs = D:
     * the same rounded products as a copy of A D. */
    canon c;
    st = canon_make(m, N, A, lda, y, sigma, spec_sigma, 0.0, &c);
    if (st)
        return st;
    /* Scratch: f (N), the trace (N x nk) and edf (nk): the caller's arrays
     * are written only when every value is finite. */
    double *f = igea__dalloc((size_t)N + ((size_t)N + 1) * (size_t)nk);
    if (!f) {
        canon_free(&c);
        return IGEA_ENOMEM;
    }
    double *Xs = f + N, *es = Xs + (size_t)N * nk;
    for (int j = 0; j < nk; j++) {
        double e = 0.0, rk = sqrt(k[j]);
        for (int i = 0; i < c.r; i++) {
            f[i] = ridge_factor(c.s[i], k[j]);
            e += ridge_hat(c.s[i], rk);
        }
        canon_coef(&c, c.r, f, NULL, Xs + (size_t)j * N);
        unscale(N, spec_sigma, Xs + (size_t)j * N, NULL, 0);
        es[j] = e;
    }
    st = igea__finite_mat(N, nk, Xs, N) ? 0 : IGEA_EOVERFLOW;
    if (st == 0) {
        for (int j = 0; j < nk; j++)
            memcpy(X + (size_t)j * ldx, Xs + (size_t)j * N,
                   (size_t)N * sizeof(double));
        if (edf)
            memcpy(edf, es, (size_t)nk * sizeof(double));
    }
    free(f);
    canon_free(&c);
    return st;
}

/* ---- principal components ---------------------------------------------- */

static int pce_core(int m, int N, const double *A, int lda, const double *y,
                    const double *sigma, const double *spec, int ncomp,
                    double eig_min, double *x, double *cov, int ldc,
                    int *nused, double *sigma2, double *residual, double *info)
{
    canon c;
    int st = canon_make(m, N, A, lda, y, sigma, NULL, 0.0, &c);
    if (st)
        return st;
    int r = c.r, n = 0;
    if (ncomp > 0)
        n = IGEA_MIN(ncomp, r);
    else {
        /* d_i >= eig_min as s_i >= sqrt(eig_min): no s_i^2 to overflow. */
        double smin = sqrt(eig_min);
        while (n < r && c.s[n] >= smin)
            n++;
    }
    double s2 = m > r ? canon_rss(&c) / (m - r) : 0.0;
    size_t nn = cov ? (size_t)N * (size_t)N : 0;
    double *w = igea__dalloc(3 * (size_t)N + (size_t)m + nn);
    if (!w) {
        canon_free(&c);
        return IGEA_ENOMEM;
    }
    double *f = w, *g = w + N, *xs = g + N, *res = xs + N, *cv = res + m;
    for (int i = 0; i < n; i++) {
        f[i] = 1.0 / c.s[i];
        g[i] = f[i] * f[i];
    }
    canon_coef(&c, n, f, NULL, xs);
    if (cov)
        canon_cov(&c, n, g, s2, NULL, cv, N);
    residual_of(m, N, A, lda, y, xs, res);
    st = fit_out(m, N, spec, s2, xs, cv, res, x, cov, ldc, residual);
    if (st == 0) {
        *nused = n;
        *sigma2 = s2;
        if (info)
            ls_info(&c, 0.0, 0, 0, info);
    }
    free(w);
    canon_free(&c);
    return st;
}

/* Argument checks of igea_regress_pce (and _ex). */
static int pce_check(int m, int N, const double *A, int lda, const double *y, int ncomp,
                     double eig_min, const double *x, const double *cov, int ldc,
                     const int *nused, const double *sigma2)
{
    int st = check_args(m, N, A, lda, y, 0);
    if (st)
        return st;
    if (ncomp < 0)
        return -8;
    if (ncomp == 0 && !(eig_min > 0.0 && isfinite(eig_min)))
        return -9;
    if (!x)
        return -10;
    if (cov && ldc < N)
        return -12;
    if (!nused)
        return -13;
    if (!sigma2)
        return -14;
    return 0;
}

int igea_regress_pce(int m, int N, const double *A, int lda, const double *y,
                     const double *sigma, const double *spec_sigma, int ncomp,
                     double eig_min, double *x, double *cov, int ldc,
                     int *nused, double *sigma2, double *residual)
{
    int st = pce_check(m, N, A, lda, y, ncomp, eig_min, x, cov, ldc, nused, sigma2);
    if (st)
        return st;
    st = check_values(m, N, A, lda, y, sigma, spec_sigma);
    if (st)
        return st;
    double *own;
    if (scaled_design(m, N, &A, &lda, spec_sigma, &own))
        return IGEA_ENOMEM;
    st = pce_core(m, N, A, lda, y, sigma, spec_sigma, ncomp, eig_min, x, cov,
                  ldc, nused, sigma2, residual, NULL);
    free(own);
    return st;
}

/* ---- automatic column scaling (ridge_ex, pce_ex) ----------------------- */

/* The scales the _ex estimators work with: spec (or 1) times, when the
 * column norms of diag(1/sigma) A diag(spec) differ by more than
 * IGEA_REGRESS_SCALE_RATIO, 1 / norm (a column of norm 0 has scale 1,
 * equilibrate). *sp then points to an igea-owned array (*own_sp, to
 * free), else to spec. */
static int auto_scale(int m, int N, const double *A, int lda, const double *sigma,
                      const double *spec, const double **sp, double **own_sp, int *scaled)
{
    double *cs = igea__dalloc((size_t)N);
    const double *Ad = A;
    int ld = lda;
    double *own;
    *own_sp = NULL;
    *sp = spec;
    *scaled = 0;
    if (!cs || scaled_design(m, N, &Ad, &ld, spec, &own)) {
        free(cs);
        return IGEA_ENOMEM;
    }
    equilibrate(m, N, Ad, ld, sigma, cs);
    free(own);
    double lo = HUGE_VAL, hi = 0.0;
    for (int j = 0; j < N; j++) {
        lo = IGEA_MIN(lo, cs[j]);
        hi = IGEA_MAX(hi, cs[j]);
    }
    if (hi > IGEA_REGRESS_SCALE_RATIO * lo) {
        for (int j = 0; j < N; j++)
            cs[j] *= spec ? spec[j] : 1.0;
        *own_sp = cs;
        *sp = cs;
        *scaled = 1;
        return 0;
    }
    free(cs);
    return 0;
}

/* The automatic column scaling and the scaled design of the _ex estimators:
 * *sp the scales to use (spec_sigma or igea's), *A and *lda the design to pass;
 * free(*own) and free(*own_sp) afterwards. 0 or IGEA_ENOMEM (nothing kept). */
static int scaled_inputs(int m, int N, const double **A, int *lda, const double *sigma,
                         const double *spec_sigma, const double **sp, double **own_sp,
                         double **own, int *scaled)
{
    if (auto_scale(m, N, *A, *lda, sigma, spec_sigma, sp, own_sp, scaled))
        return IGEA_ENOMEM;
    if (scaled_design(m, N, A, lda, *sp, own)) {
        free(*own_sp);
        return IGEA_ENOMEM;
    }
    return 0;
}

int igea_regress_ridge_ex(int m, int N, const double *A, int lda, const double *y,
                          const double *sigma, const double *spec_sigma, int rule, double k,
                          double *x, double *cov, int ldc, double *k_used, double *sigma2,
                          double *residual, double *info)
{
    int st = ridge_check(m, N, A, lda, y, rule, k, x, cov, ldc, k_used, sigma2);
    if (st)
        return st;
    if (!info)
        return -16;
    st = check_values(m, N, A, lda, y, sigma, spec_sigma);
    if (st)
        return st;
    const double *sp;
    double *own_sp, *own;
    int scaled;
    if (scaled_inputs(m, N, &A, &lda, sigma, spec_sigma, &sp, &own_sp, &own, &scaled))
        return IGEA_ENOMEM;
    st = ridge_core(m, N, A, lda, y, sigma, sp, rule, k, x, cov, ldc, k_used, sigma2,
                    residual, info);
    if (st == 0)
        info[IGEA_REGRESS_INFO_SCALED] = scaled;
    free(own);
    free(own_sp);
    return st;
}

int igea_regress_pce_ex(int m, int N, const double *A, int lda, const double *y,
                        const double *sigma, const double *spec_sigma, int ncomp,
                        double eig_min, double *x, double *cov, int ldc, int *nused,
                        double *sigma2, double *residual, double *info)
{
    int st = pce_check(m, N, A, lda, y, ncomp, eig_min, x, cov, ldc, nused, sigma2);
    if (st)
        return st;
    if (!info)
        return -16;
    st = check_values(m, N, A, lda, y, sigma, spec_sigma);
    if (st)
        return st;
    const double *sp;
    double *own_sp, *own;
    int scaled;
    if (scaled_inputs(m, N, &A, &lda, sigma, spec_sigma, &sp, &own_sp, &own, &scaled))
        return IGEA_ENOMEM;
    st = pce_core(m, N, A, lda, y, sigma, sp, ncomp, eig_min, x, cov, ldc, nused, sigma2,
                  residual, info);
    if (st == 0)
        info[IGEA_REGRESS_INFO_SCALED] = scaled;
    free(own);
    free(own_sp);
    return st;
}


/* ---- Bayes --------------------------------------------------------------- */

/* Bayes on the (scaled) design A with the (scaled) prior: prior_cov the
 * lower triangle of P (ldp), or NULL for the identity. */
static int bayes_core(int m, int N, const double *A, int lda, const double *y,
                      const double *sigma, const double *spec,
                      const double *prior_mean, const double *prior_cov,
                      int ldp, double *x, double *cov, int ldc,
                      double *residual)
{
    int st = 0;
    size_t nn = (size_t)N * N, mn = (size_t)m * N;
    double *w = igea__dalloc(nn + mn + 2 * (size_t)m + 5 * (size_t)N + nn);
    if (!w)
        return IGEA_ENOMEM;
    double *L = w, *M = L + nn, *yr = M + mn, *res = yr + m, *t = res + m,
           *f = t + N, *g = f + N, *xs = g + N, *tmp = xs + N, *C = tmp + N;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++)
            L[i + (size_t)j * N] = i < j ? 0.0
                                   : prior_cov ? IGEA_AT(prior_cov, ldp, i, j)
                                   : i == j ? 1.0 : 0.0;
    lapack_int info = LAPACKE_dpotrf_work(LAPACK_COL_MAJOR, 'L', N, L, N);
    if (info != 0) {
        free(w);
        return info > 0 ? IGEA_ESINGULAR : IGEA_ELAPACK;
    }
    for (int j = 0; j < N; j++)
        for (int i = 0; i < m; i++)
            M[i + (size_t)j * m] = IGEA_AT(A, lda, i, j);
    cblas_dtrmm(CblasColMajor, CblasRight, CblasLower, CblasNoTrans,
                CblasNonUnit, m, N, 1.0, L, N, M, m);
    memcpy(yr, y, (size_t)m * sizeof(double));
    if (prior_mean)
        cblas_dgemv(CblasColMajor, CblasNoTrans, m, N, -1.0, A, lda,
                    prior_mean, 1, 1.0, yr, 1);
    canon c;
    st = canon_make(m, N, M, m, yr, sigma, NULL, 0.0, &c);
    if (st) {
        free(w);
        return st;
    }
    /* t = V diag(s / (d + 1)) z, cov_t = V diag(1 / (d + 1)) V^T. */
    for (int i = 0; i < N; i++) {
        double si = i < c.k ? c.s[i] : 0.0, ui = si > 1.0 ? 1.0 / si : 0.0;
        f[i] = si > 0.0 ? ridge_factor(si, 1.0) : 0.0; /* s / (d + 1) */
        g[i] = si > 1.0 ? ui * ui / (1.0 + ui * ui) : 1.0 / (1.0 + si * si);
    }
    canon_coef(&c, c.k, f, NULL, t);
    for (int j = 0; j < N; j++) {
        double v = prior_mean ? prior_mean[j] : 0.0;
        for (int i = 0; i <= j; i++)
            v += L[j + (size_t)i * N] * t[i];
        xs[j] = v;
    }
    if (cov) {
        canon_cov(&c, N, g, 1.0, NULL, C, N);
        /* cov = L C L^T */
        cblas_dtrmm(CblasColMajor, CblasLeft, CblasLower, CblasNoTrans,
                    CblasNonUnit, N, N, 1.0, L, N, C, N);
        cblas_dtrmm(CblasColMajor, CblasRight, CblasLower, CblasTrans,
                    CblasNonUnit, N, N, 1.0, L, N, C, N);
    }
    (void)tmp;
    residual_of(m, N, A, lda, y, xs, res);
    unscale(N, spec, xs, cov ? C : NULL, N);
    if (!igea__finite_vec(N, xs, 1) || !igea__finite_vec(m, res, 1) ||
        (cov && !igea__finite_mat(N, N, C, N)))
        st = IGEA_EOVERFLOW;
    if (st == 0) {
        if (cov)
            for (int j = 0; j < N; j++)
                for (int i = 0; i < N; i++)
                    IGEA_AT(cov, ldc, i, j) =
                        0.5 * (C[i + (size_t)j * N] + C[j + (size_t)i * N]);
        memcpy(x, xs, (size_t)N * sizeof(double));
        if (residual)
            memcpy(residual, res, (size_t)m * sizeof(double));
    }
    canon_free(&c);
    free(w);
    return st;
}

int igea_regress_bayes(int m, int N, const double *A, int lda,
                       const double *y, const double *sigma,
                       const double *spec_sigma, const double *prior_mean,
                       const double *prior_cov, int ldp, double *x,
                       double *cov, int ldc, double *residual)
{
    int st = check_args(m, N, A, lda, y, 0);
    if (st)
        return st;
    if (prior_cov && ldp < N)
        return -10;
    if (!x)
        return -11;
    if (cov && ldc < N)
        return -13;
    st = check_values(m, N, A, lda, y, sigma, spec_sigma);
    if (st)
        return st;
    if (prior_mean && !igea__finite_vec(N, prior_mean, 1))
        return IGEA_ENONFINITE;
    for (int j = 0; j < N && prior_cov; j++)
        if (!igea__finite_vec(N - j, prior_cov + j + (size_t)j * ldp, 1))
            return IGEA_ENONFINITE;
    double *own, *pr = NULL;
    if (scaled_design(m, N, &A, &lda, spec_sigma, &own))
        return IGEA_ENOMEM;
    if (spec_sigma && (prior_mean || prior_cov)) {
        /* The prior of the scaled coefficients X / spec. */
        size_t n = (size_t)N;
        pr = igea__dalloc(n + n * n);
        if (!pr) {
            free(own);
            return IGEA_ENOMEM;
        }
        for (int i = 0; i < N; i++) {
            pr[i] = prior_mean ? prior_mean[i] / spec_sigma[i] : 0.0;
            for (int j = 0; j <= i && prior_cov; j++)
                pr[n + i + (size_t)j * n] =
                    IGEA_AT(prior_cov, ldp, i, j) / (spec_sigma[i] * spec_sigma[j]);
        }
        prior_mean = prior_mean ? pr : NULL;
        prior_cov = prior_cov ? pr + n : NULL;
        ldp = N;
    }
    st = bayes_core(m, N, A, lda, y, sigma, spec_sigma, prior_mean, prior_cov,
                    ldp, x, cov, ldc, residual);
    free(pr);
    free(own);
    return st;
}

/* ---- diagnostics ----------------------------------------------------------- */

/* The eigenvalues ev, VIFs vf, combination sds sc and prior-determined
 * flags pdw (N each) of the canonical form with noise variance s2; every
 * value of the estimable part representable, else IGEA_EOVERFLOW. */
static int coll_tables(const canon *c, double s2, double *ev, double *vf, double *sc,
                       int *pdw)
{
    int N = c->N, r = c->r, k = c->k;
    for (int i = 0; i < N; i++)
        ev[i] = i < k ? c->s[i] * c->s[i] : 0.0;
    /* The eigenvalues of the estimable part must be normal numbers. */
    if (!isfinite(s2))
        return IGEA_EOVERFLOW;
    for (int i = 0; i < k; i++)
        if (!isfinite(ev[i]) || (i < r && !(ev[i] >= DBL_MIN)))
            return IGEA_EOVERFLOW;
    for (int j = 0; j < N; j++) {
        double nul = 0.0, bjj = 0.0, pjj = 0.0;
        for (int i = 0; i < N; i++) {
            double v = c->V[j + (size_t)i * N];
            if (i >= r)
                nul += v * v;
            else {
                bjj += v * v * ev[i];
                pjj += v * v / ev[i];
            }
        }
        pdw[j] = nul > IGEA_REGRESS_NULL_TOL;
        vf[j] = pdw[j] ? INFINITY : bjj * pjj;
        if (!pdw[j] && !isfinite(vf[j]))
            return IGEA_EOVERFLOW;
    }
    for (int i = 0; i < N; i++) {
        sc[i] = i < r ? sqrt(s2) / c->s[i] : INFINITY;
        if (i < r && !isfinite(sc[i]))
            return IGEA_EOVERFLOW;
    }
    return 0;
}

int igea_regress_collinearity(int m, int N, const double *A, int lda,
                              const double *y, const double *sigma,
                              const double *spec_sigma, double rcond,
                              double *cond, int *rank, double *eig, double *V,
                              int ldv, double *vif, double *sd_comb,
                              int *prior_det)
{
    int st = check_args(m, N, A, lda, y, 1);
    if (st)
        return st;
    if (isnan(rcond) || rcond >= 1.0)
        return -8;
    if (!cond)
        return -9;
    if (!rank)
        return -10;
    if (!eig)
        return -11;
    if (V && ldv < N)
        return -13;
    st = check_values(m, N, A, lda, y, sigma, spec_sigma);
    if (st)
        return st;
    /* The diagnostics of A D: the canonical form's column scale. */
    canon c;
    st = canon_make(m, N, A, lda, y, sigma, spec_sigma, rcond, &c);
    if (st)
        return st;
    int r = c.r, k = c.k;
    double s2 = 1.0;
    if (y)
        s2 = m > r ? canon_rss(&c) / (m - r) : 0.0;
    double *w = igea__dalloc(3 * (size_t)N);
    int *pdw = igea__ialloc((size_t)N);
    if (!w || !pdw) {
        free(w);
        free(pdw);
        canon_free(&c);
        return IGEA_ENOMEM;
    }
    double *ev = w, *vf = ev + N, *sc = vf + N;
    double s1 = k > 0 ? c.s[0] : 0.0, smin = m >= N ? c.s[N - 1] : 0.0;
    double cd[2];
    cd[0] = smin > 0.0 ? s1 / smin : INFINITY;
    cd[1] = r > 0 ? s1 / c.s[r - 1] : INFINITY;
    st = coll_tables(&c, s2, ev, vf, sc, pdw);
    if (st == 0) {
        cond[0] = cd[0];
        cond[1] = cd[1];
        *rank = r;
        memcpy(eig, ev, (size_t)N * sizeof(double));
        if (V)
            for (int j = 0; j < N; j++)
                memcpy(V + (size_t)j * ldv, c.V + (size_t)j * N,
                       (size_t)N * sizeof(double));
        if (prior_det)
            memcpy(prior_det, pdw, (size_t)N * sizeof(int));
        if (vif)
            memcpy(vif, vf, (size_t)N * sizeof(double));
        if (sd_comb)
            memcpy(sd_comb, sc, (size_t)N * sizeof(double));
    }
    free(w);
    free(pdw);
    canon_free(&c);
    return st;
}
