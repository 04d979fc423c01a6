/* triad.c - turntable-free calibration of an accelerometer triad: static
 * intervals by a windowed-variance threshold, Levenberg-Marquardt on
 * |T K (m - b)| = g (include/igea/triad.h, docs/calibration.md). */
#include <float.h>
#include <math.h>
#include <string.h>

#include "igea/triad.h"
#include "internal.h"

#define NP IGEA_TRIAD_NP
#define MIN_INTERVALS 12

int igea_triad_defaults(double *opts)
{
    if (!opts)
        return -1;
    for (int i = 0; i < IGEA_TRIAD_OPT_LEN; i++)
        opts[i] = 0.0;
    opts[IGEA_TRIAD_OPT_G] = 9.80665;
    opts[IGEA_TRIAD_OPT_WINDOW] = 2.0;
    opts[IGEA_TRIAD_OPT_INIT] = 30.0;
    opts[IGEA_TRIAD_OPT_MIN_STATIC] = 1.0;
    opts[IGEA_TRIAD_OPT_THRESHOLD] = 0.0;
    opts[IGEA_TRIAD_OPT_MAX_ITER] = 200.0;
    return 0;
}

int igea_triad_check_opts(const double *o)
{
    if (!o)
        return -1;
    for (int i = 0; i < IGEA_TRIAD_OPT_LEN; i++)
        if (!isfinite(o[i]))
            return 1 + i;
    static const int positive[] = {IGEA_TRIAD_OPT_G, IGEA_TRIAD_OPT_WINDOW, IGEA_TRIAD_OPT_INIT,
                                   IGEA_TRIAD_OPT_MIN_STATIC};
    for (size_t k = 0; k < sizeof positive / sizeof positive[0]; k++)
        if (!(o[positive[k]] > 0))
            return 1 + positive[k];
    if (!(o[IGEA_TRIAD_OPT_THRESHOLD] >= 0))
        return 1 + IGEA_TRIAD_OPT_THRESHOLD;
    double it = o[IGEA_TRIAD_OPT_MAX_ITER];
    if (!(it >= 1 && it <= 10000 && it == floor(it)))
        return 1 + IGEA_TRIAD_OPT_MAX_ITER;
    if (!(o[IGEA_TRIAD_OPT_EARTH_RATE] >= 0))
        return 1 + IGEA_TRIAD_OPT_EARTH_RATE;
    if (!(fabs(o[IGEA_TRIAD_OPT_LAT]) <= 90.0))
        return 1 + IGEA_TRIAD_OPT_LAT;
    return 0;
}

/* ---- the record ---------------------------------------------------------- */
typedef struct {
    int layout, n, lda;
    const double *a;
} record;

static double at(const record *r, int i, int j)
{
    return r->layout == IGEA_ROWMAJOR ? r->a[(size_t)i * r->lda + j]
                                      : r->a[i + (size_t)j * r->lda];
}

/* 0, or -i for the layout / n / acc / lda arguments (positions 1..4). */
static int record_check(int layout, int n, const double *acc, int lda, record *r)
{
    if (layout != IGEA_ROWMAJOR && layout != IGEA_COLMAJOR)
        return -1;
    if (n < 1)
        return -2;
    if (!acc)
        return -3;
    if (layout == IGEA_ROWMAJOR ? lda < 3 : lda < n)
        return -4;
    r->layout = layout, r->n = n, r->lda = lda, r->a = acc;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < 3; j++)
            if (!isfinite(at(r, i, j)))
                return IGEA_ENONFINITE;
    return 0;
}

/* Variance magnitude sqrt(sum_j var_j^2) of samples [i0, i1) (two-pass). */
static double zeta_of(const record *r, int i0, int i1)
{
    double z = 0.0;
    for (int j = 0; j < 3; j++) {
        igea__ksum s = {0.0, 0.0}, q = {0.0, 0.0};
        for (int i = i0; i < i1; i++)
            igea__ksum_add(&s, at(r, i, j));
        double mean = igea__ksum_get(&s) / (i1 - i0);
        for (int i = i0; i < i1; i++) {
            double d = at(r, i, j) - mean;
            igea__ksum_add(&q, d * d);
        }
        double v = igea__ksum_get(&q) / (i1 - i0 - 1);
        z += v * v;
    }
    return sqrt(z);
}

/* zeta_i over the centred window of w samples (odd); +Inf where the window
 * does not fit. O(n w). */
static void zeta_series(const record *r, int w, double *zeta)
{
    int half = w / 2;
    for (int i = 0; i < r->n; i++)
        zeta[i] = i < half || i + half >= r->n ? INFINITY : zeta_of(r, i - half, i + half + 1);
}

/* The static runs of zeta < thr of at least minlen samples; the first
 * maxint written. Returns the count. */
static int runs(const record *r, const double *zeta, double thr, int minlen, int maxint,
                int *start, int *end, double *means)
{
    int count = 0;
    for (int i = 0; i < r->n;) {
        if (!(zeta[i] < thr)) {
            i++;
            continue;
        }
        int j = i;
        while (j < r->n && zeta[j] < thr)
            j++;
        if (j - i >= minlen) {
            if (count < maxint) {
                if (start)
                    start[count] = i, end[count] = j;
                if (means)
                    for (int k = 0; k < 3; k++) {
                        igea__ksum s = {0.0, 0.0};
                        for (int t = i; t < j; t++)
                            igea__ksum_add(&s, at(r, t, k));
                        means[3 * (size_t)count + k] = igea__ksum_get(&s) / (j - i);
                    }
            }
            count++;
        }
        i = j;
    }
    return count;
}

static int window_samples(double fs, double window, int *w)
{
    double v = window * fs;
    if (!(v >= 2.0 && v < 1e9))
        return -1; /* at least 3 samples for a variance */
    long k = lround(v);
    *w = (int)(k % 2 ? k : k + 1);
    return 0;
}

int igea_triad_static(int layout, int n, const double *acc, int lda, double fs, double window,
                      double threshold, double min_static, int maxint, int *nint, int *start,
                      int *end, double *means)
{
    record r;
    int st = record_check(layout, n, acc, lda, &r), w;
    if (st < 0 && st != IGEA_ENONFINITE)
        return st;
    if (!(isfinite(fs) && fs > 0))
        return -5;
    if (!(isfinite(window) && window > 0) || window_samples(fs, window, &w) || w >= n)
        return -6;
    if (!(isfinite(threshold) && threshold > 0))
        return -7;
    double ml = min_static * fs;
    if (!(isfinite(min_static) && min_static > 0 && ml < 2147483647.0))
        return -8;
    if (maxint < 0)
        return -9;
    if (!nint)
        return -10;
    if ((start == NULL) != (end == NULL))
        return start ? -12 : -11;
    if (st)
        return st;
    double *zeta = igea__dalloc((size_t)n);
    if (!zeta)
        return IGEA_ENOMEM;
    zeta_series(&r, w, zeta);
    int minlen = (int)IGEA_MAX(1, lround(ml));
    *nint = runs(&r, zeta, threshold, minlen, maxint, start, end, means);
    free(zeta);
    return 0;
}

/* ---- the fit --------------------------------------------------------------- */
/* Residuals r_k = |T K (m_k - b)| - g and their Jacobian J (nint x 9). */
static void residuals(int nint, const double *m, double g, const double *th, double *r,
                      double *J)
{
    for (int k = 0; k < nint; k++) {
        const double *mk = m + 3 * (size_t)k;
        double u[3], w[3], c[3];
        for (int i = 0; i < 3; i++)
            u[i] = mk[i] - th[IGEA_TRIAD_BX + i], w[i] = th[IGEA_TRIAD_KX + i] * u[i];
        double tyx = th[IGEA_TRIAD_TYX], tzx = th[IGEA_TRIAD_TZX], tzy = th[IGEA_TRIAD_TZY];
        c[0] = w[0];
        c[1] = tyx * w[0] + w[1];
        c[2] = tzx * w[0] + tzy * w[1] + w[2];
        double nrm = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        r[k] = nrm - g;
        if (!J)
            continue;
        double e[3] = {c[0] / nrm, c[1] / nrm, c[2] / nrm};
        /* column j of T: e^T T e_j */
        double et[3] = {e[0] + tyx * e[1] + tzx * e[2], e[1] + tzy * e[2], e[2]};
        for (int j = 0; j < 3; j++) {
            IGEA_AT(J, nint, k, IGEA_TRIAD_BX + j) = -et[j] * th[IGEA_TRIAD_KX + j];
            IGEA_AT(J, nint, k, IGEA_TRIAD_KX + j) = et[j] * u[j];
        }
        IGEA_AT(J, nint, k, IGEA_TRIAD_TYX) = e[1] * w[0];
        IGEA_AT(J, nint, k, IGEA_TRIAD_TZX) = e[2] * w[0];
        IGEA_AT(J, nint, k, IGEA_TRIAD_TZY) = e[2] * w[1];
    }
}

static double sumsq(int n, const double *r)
{
    igea__ksum s = {0.0, 0.0};
    for (int i = 0; i < n; i++)
        igea__ksum_add(&s, r[i] * r[i]);
    return igea__ksum_get(&s);
}

/* A = J^T J (9 x 9), grad = J^T r. */
static void normal_eq(int nint, const double *J, const double *r, double *A, double *grad)
{
    for (int a = 0; a < NP; a++) {
        double ga = 0.0;
        for (int k = 0; k < nint; k++)
            ga += IGEA_AT(J, nint, k, a) * r[k];
        grad[a] = ga;
        for (int b = 0; b <= a; b++) {
            double s = 0.0;
            for (int k = 0; k < nint; k++)
                s += IGEA_AT(J, nint, k, a) * IGEA_AT(J, nint, k, b);
            A[a + NP * b] = A[b + NP * a] = s;
        }
    }
}

/* Solve (A + lam diag(A)) x = rhs by Cholesky; 0 or IGEA_ESINGULAR. */
static int damped_solve(const double *A, double lam, const double *rhs, double *x)
{
    double L[NP * NP];
    memcpy(L, A, sizeof L);
    for (int i = 0; i < NP; i++)
        L[i + NP * i] *= 1.0 + lam;
    if (igea__chol_lower(NP, L, NP, 0.0))
        return IGEA_ESINGULAR;
    for (int i = 0; i < NP; i++) { /* L y = rhs */
        double s = rhs[i];
        for (int j = 0; j < i; j++)
            s -= L[i + NP * j] * x[j];
        x[i] = s / L[i + NP * i];
    }
    for (int i = NP - 1; i >= 0; i--) { /* L^T x = y */
        double s = x[i];
        for (int j = i + 1; j < NP; j++)
            s -= L[j + NP * i] * x[j];
        x[i] = s / L[i + NP * i];
    }
    return 0;
}

/* The parameters are identifiable when the scaled J^T J (unit diagonal)
 * has a Cholesky factor with every pivot^2 above 1e-8 (31 random attitudes
 * give a smallest eigenvalue near 0.3, 12 about 0.05; three attitudes
 * repeated, 1e-11). */
static int identifiable(const double *A)
{
    double S[NP * NP];
    for (int i = 0; i < NP; i++)
        if (!(A[i + NP * i] > 0))
            return 0;
    for (int j = 0; j < NP; j++)
        for (int i = 0; i < NP; i++)
            S[i + NP * j] = A[i + NP * j] / sqrt(A[i + NP * i] * A[j + NP * j]);
    if (igea__chol_lower(NP, S, NP, 0.0))
        return 0;
    for (int i = 0; i < NP; i++)
        if (!(S[i + NP * i] * S[i + NP * i] > 1e-8))
            return 0;
    return 1;
}

static void start_values(int nint, const double *m, double g, double *th, double *tmp)
{
    for (int k = 0; k < nint; k++) {
        const double *mk = m + 3 * (size_t)k;
        tmp[k] = sqrt(mk[0] * mk[0] + mk[1] * mk[1] + mk[2] * mk[2]);
    }
    /* median by insertion sort (nint is small) */
    for (int i = 1; i < nint; i++)
        for (int j = i; j > 0 && tmp[j - 1] > tmp[j]; j--) {
            double t = tmp[j];
            tmp[j] = tmp[j - 1], tmp[j - 1] = t;
        }
    double med = nint % 2 ? tmp[nint / 2] : 0.5 * (tmp[nint / 2 - 1] + tmp[nint / 2]);
    for (int i = 0; i < NP; i++)
        th[i] = 0.0;
    for (int i = 0; i < 3; i++)
        th[IGEA_TRIAD_KX + i] = med > 0 ? g / med : 1.0;
}

typedef struct {
    double theta[NP], A[NP * NP], cost, rms0;
    int iter;
} lm_state;

/* Residuals r (rows) at theta and, when J is not NULL, their Jacobian J
 * (rows x 9); 0, or IGEA_ENOMEM. */
typedef int (*lm_residuals)(const void *ctx, const double *theta, double *r, double *J);

typedef struct {
    int nint;
    const double *m;
    double g;
} acc_problem;

static int acc_residuals(const void *ctx, const double *th, double *r, double *J)
{
    const acc_problem *p = ctx;
    residuals(p->nint, p->m, p->g, th, r, J);
    return 0;
}

/* Levenberg-Marquardt from lm->theta on `rows` residuals; work: 2 rows (r,
 * r2) + 9 rows (J). */
static int lm_run(int rows, lm_residuals f, const void *ctx, int max_iter, lm_state *lm,
                  double *work)
{
    double *r = work, *r2 = r + rows, *J = r2 + rows, grad[NP], step[NP], trial[NP];
    int st = f(ctx, lm->theta, r, J);
    if (st)
        return st;
    lm->cost = sumsq(rows, r);
    lm->rms0 = sqrt(lm->cost / rows);
    double lam = 1e-3;
    for (lm->iter = 0; lm->iter < max_iter; lm->iter++) {
        normal_eq(rows, J, r, lm->A, grad);
        if (lm->cost == 0.0)
            return 0;
        for (int i = 0; i < NP; i++)
            grad[i] = -grad[i];
        int accepted = 0;
        while (!accepted) {
            if (lam > 1e20)
                return 0; /* no descent left: a minimum to rounding */
            if (damped_solve(lm->A, lam, grad, step)) {
                lam *= 10.0;
                continue;
            }
            for (int i = 0; i < NP; i++)
                trial[i] = lm->theta[i] + step[i];
            if ((st = f(ctx, trial, r2, NULL)))
                return st;
            double c2 = sumsq(rows, r2);
            if (isfinite(c2) && c2 < lm->cost) {
                double drop = lm->cost - c2;
                memcpy(lm->theta, trial, sizeof trial);
                lm->cost = c2;
                if ((st = f(ctx, lm->theta, r, J)))
                    return st;
                lam = fmax(lam / 10.0, 1e-12);
                accepted = 1;
                if (drop <= 1e-14 * c2) {
                    normal_eq(rows, J, r, lm->A, grad);
                    return 0;
                }
            } else {
                lam *= 10.0;
            }
        }
    }
    return IGEA_ENOCONV;
}

/* cov = s2 A^-1 (A positive definite). */
static int covariance(const double *A, double s2, double *cov, int ldc)
{
    double e[NP], x[NP];
    for (int j = 0; j < NP; j++) {
        for (int i = 0; i < NP; i++)
            e[i] = i == j;
        if (damped_solve(A, 0.0, e, x))
            return IGEA_ERANK;
        for (int i = 0; i < NP; i++)
            IGEA_AT(cov, ldc, i, j) = s2 * x[i];
    }
    return 0;
}

/* The fit on validated means: theta, cov (or NULL), info (or NULL). */
static int fit(int nint, const double *m, double g, const double *theta0, int max_iter,
               double *theta, double *cov, int ldc, double *info)
{
    lm_state lm;
    double *work = igea__dalloc((size_t)nint * (NP + 2));
    if (!work)
        return IGEA_ENOMEM;
    if (theta0)
        memcpy(lm.theta, theta0, sizeof lm.theta);
    else
        start_values(nint, m, g, lm.theta, work);
    acc_problem p = {nint, m, g};
    int st = lm_run(nint, acc_residuals, &p, max_iter, &lm, work);
    free(work);
    if ((!st || st == IGEA_ENOCONV) && !identifiable(lm.A))
        st = IGEA_ERANK; /* a wandering iteration on an undetermined problem */
    double s2 = lm.cost / (nint - NP), C[NP * NP];
    if (!st && cov)
        st = covariance(lm.A, s2, C, NP);
    for (int i = 0; !st && i < NP; i++)
        if (!isfinite(lm.theta[i]))
            st = IGEA_ENOCONV;
    if (st)
        return st;
    memcpy(theta, lm.theta, sizeof lm.theta);
    if (cov)
        for (int j = 0; j < NP; j++)
            for (int i = 0; i < NP; i++)
                IGEA_AT(cov, ldc, i, j) = C[i + NP * j];
    if (info) {
        for (int i = 0; i < IGEA_TRIAD_INFO_LEN; i++)
            info[i] = 0.0;
        info[IGEA_TRIAD_INFO_K] = info[IGEA_TRIAD_INFO_THRESHOLD] = NAN;
        info[IGEA_TRIAD_INFO_ZETA_INIT] = info[IGEA_TRIAD_INFO_MISFIT] = NAN;
        info[IGEA_TRIAD_INFO_INTERVALS] = nint;
        info[IGEA_TRIAD_INFO_RMS_BEFORE] = lm.rms0;
        info[IGEA_TRIAD_INFO_RMS_AFTER] = sqrt(lm.cost / nint);
        info[IGEA_TRIAD_INFO_SIGMA] = sqrt(s2);
        info[IGEA_TRIAD_INFO_ITERATIONS] = lm.iter;
    }
    return 0;
}

int igea_triad_fit(int nint, const double *means, double g, const double *theta0, int max_iter,
                   double *theta, double *cov, int ldc, double *info)
{
    if (nint < MIN_INTERVALS)
        return -1;
    if (!means)
        return -2;
    if (!(isfinite(g) && g > 0))
        return -3;
    if (max_iter < 1)
        return -5;
    if (!theta)
        return -6;
    if (cov && ldc < NP)
        return -8;
    if (!igea__finite_vec(3 * nint, means, 1) || (theta0 && !igea__finite_vec(NP, theta0, 1)))
        return IGEA_ENONFINITE;
    return fit(nint, means, g, theta0, max_iter, theta, cov, ldc, info);
}

/* ---- the whole calibration --------------------------------------------------- */
typedef struct {
    double theta[NP], cov[NP * NP], info[IGEA_TRIAD_INFO_LEN];
} triad_result;

/* The fit at threshold multiple k: 1 when it is better than *best, 0
 * otherwise (a failed fit noted in *err), IGEA_ENOMEM. */
static int try_threshold(const record *r, const double *zeta, double z0, double k, int minlen,
                         const double *o, double *means, int maxint, triad_result *best,
                         int *have, int *err)
{
    int nint = runs(r, zeta, k * z0, minlen, maxint, NULL, NULL, means);
    if (nint < MIN_INTERVALS)
        return 0;
    nint = IGEA_MIN(nint, maxint);
    triad_result t;
    int st = fit(nint, means, o[IGEA_TRIAD_OPT_G], NULL, (int)o[IGEA_TRIAD_OPT_MAX_ITER],
                 t.theta, t.cov, NP, t.info);
    if (st == IGEA_ENOMEM)
        return st; /* never a different answer for want of memory */
    if (st) {
        *err = *err ? *err : st;
        return 0;
    }
    if (*have) {
        double nb = best->info[IGEA_TRIAD_INFO_INTERVALS], nt = t.info[IGEA_TRIAD_INFO_INTERVALS];
        if (nt < nb || (nt == nb && !(t.info[IGEA_TRIAD_INFO_SIGMA] <
                                      best->info[IGEA_TRIAD_INFO_SIGMA])))
            return 0;
    }
    t.info[IGEA_TRIAD_INFO_K] = k;
    t.info[IGEA_TRIAD_INFO_THRESHOLD] = k * z0;
    t.info[IGEA_TRIAD_INFO_ZETA_INIT] = z0;
    *best = t;
    *have = 1;
    return 1;
}

/* Per-axis sample variances of samples [i0, i1). */
static void variances(const record *r, int i0, int i1, double *v)
{
    for (int j = 0; j < 3; j++) {
        igea__ksum s = {0.0, 0.0}, q = {0.0, 0.0};
        for (int i = i0; i < i1; i++)
            igea__ksum_add(&s, at(r, i, j));
        double mean = igea__ksum_get(&s) / (i1 - i0);
        for (int i = i0; i < i1; i++) {
            double d = at(r, i, j) - mean;
            igea__ksum_add(&q, d * d);
        }
        v[j] = igea__ksum_get(&q) / (i1 - i0 - 1);
    }
}

/* The residual sd over the one the noise of the first `ninit` samples
 * predicts for the interval means: sd^2 = mean_k sum_j e_kj^2 k_j^2 var_j /
 * N_k (e_k the calibrated direction, N_k the interval's samples). */
static int acc_misfit(const record *r, const double *zeta, int ninit, int minlen, int maxint,
                      double *means, triad_result *best)
{
    int *se = igea__ialloc(2 * (size_t)maxint);
    if (!se)
        return IGEA_ENOMEM;
    int nint = IGEA_MIN(maxint, runs(r, zeta, best->info[IGEA_TRIAD_INFO_THRESHOLD], minlen,
                                     maxint, se, se + maxint, means));
    double v[3], p2 = 0.0, *th = best->theta;
    variances(r, 0, ninit, v);
    for (int k = 0; k < nint; k++) {
        double w[3], c[3];
        for (int j = 0; j < 3; j++)
            w[j] = th[IGEA_TRIAD_KX + j] * (means[3 * (size_t)k + j] - th[IGEA_TRIAD_BX + j]);
        c[0] = w[0], c[1] = th[IGEA_TRIAD_TYX] * w[0] + w[1];
        c[2] = th[IGEA_TRIAD_TZX] * w[0] + th[IGEA_TRIAD_TZY] * w[1] + w[2];
        double nc2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2], s = 0.0;
        for (int j = 0; j < 3; j++)
            s += c[j] * c[j] / nc2 * th[IGEA_TRIAD_KX + j] * th[IGEA_TRIAD_KX + j] * v[j];
        p2 += s / (se[maxint + k] - se[k]) / nint;
    }
    free(se);
    best->info[IGEA_TRIAD_INFO_MISFIT] = best->info[IGEA_TRIAD_INFO_SIGMA] / sqrt(p2);
    return 0;
}

int igea_triad_calibrate(int layout, int n, const double *acc, int lda, double fs,
                         const double *opts, double *theta, double *cov, int ldc, double *info)
{
    record r;
    int st = record_check(layout, n, acc, lda, &r), w;
    if (st < 0 && st != IGEA_ENONFINITE)
        return st;
    if (!(isfinite(fs) && fs > 0))
        return -5;
    if (igea_triad_check_opts(opts))
        return -6;
    if (!theta)
        return -7;
    if (cov && ldc < NP)
        return -9;
    if (st)
        return st;
    double ninit = opts[IGEA_TRIAD_OPT_INIT] * fs, nmin = opts[IGEA_TRIAD_OPT_MIN_STATIC] * fs;
    if (window_samples(fs, opts[IGEA_TRIAD_OPT_WINDOW], &w) || w >= n || !(ninit >= 2) ||
        ninit > n || !(nmin < 2147483647.0))
        return IGEA_EEMPTY;
    int minlen = (int)IGEA_MAX(1, lround(nmin)), maxint = n / minlen + 1;
    double z0 = zeta_of(&r, 0, (int)lround(ninit));
    double *zeta = igea__dalloc((size_t)n + 3 * (size_t)maxint);
    if (!zeta)
        return IGEA_ENOMEM;
    double *means = zeta + n;
    zeta_series(&r, w, zeta);
    triad_result best;
    int have = 0, err = 0;
    double k0 = opts[IGEA_TRIAD_OPT_THRESHOLD];
    for (int k = 1; k <= 10 && st >= 0; k++)
        if (k0 == 0 || k == 1)
            st = try_threshold(&r, zeta, z0, k0 > 0 ? k0 : (double)k, minlen, opts, means,
                               maxint, &best, &have, &err);
    if (st >= 0 && have)
        st = acc_misfit(&r, zeta, (int)lround(ninit), minlen, maxint, means, &best);
    free(zeta);
    if (st < 0)
        return st;
    if (!have)
        return err ? err : IGEA_EEMPTY;
    memcpy(theta, best.theta, sizeof best.theta);
    if (cov)
        for (int j = 0; j < NP; j++)
            for (int i = 0; i < NP; i++)
                IGEA_AT(cov, ldc, i, j) = best.cov[i + NP * j];
    if (info)
        memcpy(info, best.info, sizeof best.info);
    return 0;
}

/* The arguments of the two apply functions (theta of np values): 0, -i or
 * IGEA_ENONFINITE; the record in *r. */
static int apply_args(int layout, int n, const double *raw, int ldr, const double *theta,
                      int np, const double *cal, int ldc, record *r)
{
    int st = record_check(layout, n, raw, ldr, r);
    if (st < 0 && st != IGEA_ENONFINITE)
        return st;
    if (!theta)
        return -5;
    if (!cal)
        return -6;
    if (layout == IGEA_ROWMAJOR ? ldc < 3 : ldc < n)
        return -7;
    if (st || !igea__finite_vec(np, theta, 1))
        return IGEA_ENONFINITE;
    return 0;
}

/* Row i of the calibrated output. */
static void put_row(int layout, double *cal, int ldc, int i, const double *c)
{
    for (int j = 0; j < 3; j++) {
        if (layout == IGEA_ROWMAJOR)
            cal[(size_t)i * ldc + j] = c[j];
        else
            cal[i + (size_t)j * ldc] = c[j];
    }
}

int igea_triad_apply(int layout, int n, const double *raw, int ldr, const double *theta,
                     double *cal, int ldc)
{
    record r;
    int st = apply_args(layout, n, raw, ldr, theta, NP, cal, ldc, &r);
    if (st)
        return st;
    const double *t = theta;
    for (int i = 0; i < n; i++) {
        double w[3];
        for (int j = 0; j < 3; j++)
            w[j] = t[IGEA_TRIAD_KX + j] * (at(&r, i, j) - t[IGEA_TRIAD_BX + j]);
        double c[3] = {w[0], t[IGEA_TRIAD_TYX] * w[0] + w[1],
                       t[IGEA_TRIAD_TZX] * w[0] + t[IGEA_TRIAD_TZY] * w[1] + w[2]};
        put_row(layout, cal, ldc, i, c);
    }
    return 0;
}

/* ---- the gyroscope ------------------------------------------------------------- */
#define GP IGEA_TRIAD_GYRO_NP
#define DEG (180.0 / 3.14159265358979323846)

/* S = M K from p = (k_x, k_y, k_z, m_xy, m_xz, m_yx, m_yz, m_zx, m_zy). */
static void gyro_matrix(const double *p, double S[3][3])
{
    const double M[3][3] = {{1.0, p[3], p[4]}, {p[5], 1.0, p[6]}, {p[7], p[8], 1.0}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            S[i][j] = M[i][j] * p[j];
}

typedef struct {
    record r;               /* the gyro record */
    double h;               /* the sample interval 1 / fs */
    int m;                  /* rotations: the pairs of consecutive intervals */
    const int *start, *end; /* the static intervals (m + 1) */
    const double *v;        /* their unit gravity directions, 3 x (m + 1) */
    double b[3];            /* the gyro biases */
    double *R;              /* NULL, or 9 m: the rotations of the last residuals */
    const double *vs;       /* NULL, or 3 m: the start directions turned by the
                               Earth's rotation over each rotation (Earth rate) */
} gyro_problem;

/* d = q (x) (0, w) / 2 */
static void qdot(const double *q, const double *w, double *d)
{
    d[0] = 0.5 * (-q[1] * w[0] - q[2] * w[1] - q[3] * w[2]);
    d[1] = 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]);
    d[2] = 0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2]);
    d[3] = 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0]);
}

static void rate(const gyro_problem *g, double S[3][3], const double *b, int i, double *w)
{
    double u[3];
    for (int j = 0; j < 3; j++)
        u[j] = at(&g->r, i, j) - b[j];
    for (int j = 0; j < 3; j++)
        w[j] = S[j][0] * u[0] + S[j][1] * u[1] + S[j][2] * u[2];
}

/* The attitude of the body at the first static sample of interval k + 1 in
 * the body at the last sample of interval k: RK4 on q' = q (x) (0, w) / 2
 * with w linear between samples; R (row-major 3 x 3) maps the later body
 * axes into the earlier ones. */
static void rotation(const gyro_problem *g, double S[3][3], const double *b, int k, double *R)
{
    double q[4] = {1.0, 0.0, 0.0, 0.0}, w0[3], w1[3], wm[3], k1[4], k2[4], k3[4], k4[4], t[4];
    double h = g->h;
    int i0 = g->end[k] - 1, i1 = g->start[k + 1];
    rate(g, S, b, i0, w1);
    for (int i = i0; i < i1; i++) {
        memcpy(w0, w1, sizeof w0);
        rate(g, S, b, i + 1, w1);
        for (int j = 0; j < 3; j++)
            wm[j] = 0.5 * (w0[j] + w1[j]);
        qdot(q, w0, k1);
        for (int j = 0; j < 4; j++)
            t[j] = q[j] + 0.5 * h * k1[j];
        qdot(t, wm, k2);
        for (int j = 0; j < 4; j++)
            t[j] = q[j] + 0.5 * h * k2[j];
        qdot(t, wm, k3);
        for (int j = 0; j < 4; j++)
            t[j] = q[j] + h * k3[j];
        qdot(t, w1, k4);
        double nq = 0.0;
        for (int j = 0; j < 4; j++) {
            q[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
            nq += q[j] * q[j];
        }
        nq = sqrt(nq);
        for (int j = 0; j < 4; j++)
            q[j] /= nq;
    }
    double a = q[0], x = q[1], y = q[2], z = q[3];
    R[0] = 1 - 2 * (y * y + z * z), R[1] = 2 * (x * y - a * z), R[2] = 2 * (x * z + a * y);
    R[3] = 2 * (x * y + a * z), R[4] = 1 - 2 * (x * x + z * z), R[5] = 2 * (y * z - a * x);
    R[6] = 2 * (x * z - a * y), R[7] = 2 * (y * z + a * x), R[8] = 1 - 2 * (x * x + y * y);
}

/* r = v_{k+1} - R^T v_k for pair k (R stored when R is not NULL). */
static void pair_residual(const gyro_problem *g, const double *p, const double *b, int k,
                          double *r, double *Rout)
{
    double S[3][3], R[9];
    gyro_matrix(p, S);
    rotation(g, S, b, k, R);
    const double *v1 = g->v + 3 * (size_t)k + 3;
    const double *v0 = g->vs ? g->vs + 3 * (size_t)k : g->v + 3 * (size_t)k;
    for (int i = 0; i < 3; i++)
        r[i] = v1[i] - (R[i] * v0[0] + R[3 + i] * v0[1] + R[6 + i] * v0[2]);
    if (Rout)
        memcpy(Rout, R, sizeof R);
}

/* The steps of the central differences: 1e-6 of each scale factor, 1e-6
 * for the misalignments (rad). */
static double gyro_step(const double *p, int j)
{
    return j < 3 ? 1e-6 * fmax(fabs(p[j]), 1e-300) : 1e-6;
}

static int gyro_residuals(const void *ctx, const double *p, double *r, double *J)
{
    const gyro_problem *g = ctx;
    int rows = 3 * g->m;
    for (int k = 0; k < g->m; k++) {
        pair_residual(g, p, g->b, k, r + 3 * (size_t)k, g->R ? g->R + 9 * (size_t)k : NULL);
        for (int j = 0; J && j < NP; j++) {
            double pp[NP], rp[3], rm[3], hj = gyro_step(p, j);
            memcpy(pp, p, sizeof pp);
            pp[j] = p[j] + hj;
            pair_residual(g, pp, g->b, k, rp, NULL);
            pp[j] = p[j] - hj;
            pair_residual(g, pp, g->b, k, rm, NULL);
            for (int i = 0; i < 3; i++)
                IGEA_AT(J, rows, 3 * k + i, j) = (rp[i] - rm[i]) / (2.0 * hj);
        }
    }
    return 0;
}

/* The unit gravity directions v_k = c_k / |c_k|, c_k = T K (m_k - b), and,
 * when D is not NULL, dv_k / dtheta_a (D + 27 k: 3 x 9 column-major). */
static void directions(int nint, const double *m, const double *th, double *v, double *D)
{
    double tyx = th[IGEA_TRIAD_TYX], tzx = th[IGEA_TRIAD_TZX], tzy = th[IGEA_TRIAD_TZY];
    const double T[3][3] = {{1.0, 0.0, 0.0}, {tyx, 1.0, 0.0}, {tzx, tzy, 1.0}};
    for (int k = 0; k < nint; k++) {
        double u[3], w[3], c[3], dc[3][NP] = {{0.0}};
        for (int i = 0; i < 3; i++)
            u[i] = m[3 * (size_t)k + i] - th[IGEA_TRIAD_BX + i], w[i] = th[IGEA_TRIAD_KX + i] * u[i];
        for (int i = 0; i < 3; i++)
            c[i] = T[i][0] * w[0] + T[i][1] * w[1] + T[i][2] * w[2];
        double nc = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), *vk = v + 3 * (size_t)k;
        for (int i = 0; i < 3; i++)
            vk[i] = c[i] / nc;
        if (!D)
            continue;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                dc[i][IGEA_TRIAD_BX + j] = -T[i][j] * th[IGEA_TRIAD_KX + j];
                dc[i][IGEA_TRIAD_KX + j] = T[i][j] * u[j];
            }
        dc[1][IGEA_TRIAD_TYX] = w[0], dc[2][IGEA_TRIAD_TZX] = w[0], dc[2][IGEA_TRIAD_TZY] = w[1];
        double *Dk = D + 27 * (size_t)k;
        for (int j = 0; j < NP; j++) /* (I - v v^T) dc / |c| */
            for (int i = 0; i < 3; i++) {
                double vd = vk[0] * dc[0][j] + vk[1] * dc[1][j] + vk[2] * dc[2][j];
                Dk[i + 3 * j] = (dc[i][j] - vk[i] * vd) / nc;
            }
    }
}

/* The biases: the mean over every static sample; s2[3] the pooled
 * within-interval variances; rbar (3 nint) and cnt (nint), when not NULL,
 * each interval's means and samples; returns the number of static
 * samples. */
static int gyro_bias(const gyro_problem *g, int nint, double *b, double *s2, double *rbar,
                     double *cnt)
{
    int N = 0;
    igea__ksum tot[3] = {{0.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}}, ss[3] = {{0.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}};
    for (int k = 0; k < nint; k++) {
        int a = g->start[k], e = g->end[k];
        for (int j = 0; j < 3; j++) {
            igea__ksum s = {0.0, 0.0};
            for (int i = a; i < e; i++)
                igea__ksum_add(&s, at(&g->r, i, j));
            double mean = igea__ksum_get(&s) / (e - a);
            igea__ksum_add(&tot[j], igea__ksum_get(&s));
            if (rbar)
                rbar[3 * (size_t)k + j] = mean;
            for (int i = a; i < e; i++) {
                double d = at(&g->r, i, j) - mean;
                igea__ksum_add(&ss[j], d * d);
            }
        }
        N += e - a;
        if (cnt)
            cnt[k] = e - a;
    }
    for (int j = 0; j < 3; j++)
        b[j] = igea__ksum_get(&tot[j]) / N, s2[j] = igea__ksum_get(&ss[j]) / (N - nint);
    return N;
}

/* dr/db (rows x 3) by central differences of 1e-6 rad/s in the calibrated rate. */
static void bias_jacobian(const gyro_problem *g, const double *p, double *Jb)
{
    int rows = 3 * g->m;
    for (int j = 0; j < 3; j++) {
        double bp[3], rp[3], rm[3], hj = 1e-6 / fmax(fabs(p[j]), 1e-300);
        for (int k = 0; k < g->m; k++) {
            memcpy(bp, g->b, sizeof bp);
            bp[j] = g->b[j] + hj;
            pair_residual(g, p, bp, k, rp, NULL);
            bp[j] = g->b[j] - hj;
            pair_residual(g, p, bp, k, rm, NULL);
            for (int i = 0; i < 3; i++)
                IGEA_AT(Jb, rows, 3 * k + i, j) = (rp[i] - rm[i]) / (2.0 * hj);
        }
    }
}

/* dr/dtheta_a (rows x 9) from the direction derivatives D and the
 * rotations R: dr_k = dv_{k+1} - R_k^T dv_k. */
static void accel_jacobian(const gyro_problem *g, const double *D, double *Ja)
{
    int rows = 3 * g->m;
    for (int k = 0; k < g->m; k++) {
        const double *R = g->R + 9 * (size_t)k, *D0 = D + 27 * (size_t)k, *D1 = D0 + 27;
        for (int j = 0; j < NP; j++)
            for (int i = 0; i < 3; i++)
                IGEA_AT(Ja, rows, 3 * k + i, j) =
                    D1[i + 3 * j] -
                    (R[i] * D0[3 * j] + R[3 + i] * D0[1 + 3 * j] + R[6 + i] * D0[2 + 3 * j]);
    }
}

/* G = -(J^T J)^-1 J^T X for X (rows x nc): G (9 x nc, ld 9). */
static int sensitivity(int rows, const double *J, const double *A, const double *X, int nc,
                       double *G)
{
    for (int c = 0; c < nc; c++) {
        double rhs[NP], x[NP];
        for (int a = 0; a < NP; a++) {
            double s = 0.0;
            for (int k = 0; k < rows; k++)
                s += IGEA_AT(J, rows, k, a) * IGEA_AT(X, rows, k, c);
            rhs[a] = -s;
        }
        if (damped_solve(A, 0.0, rhs, x))
            return IGEA_ERANK;
        memcpy(G + NP * (size_t)c, x, sizeof x);
    }
    return 0;
}

/* C (9 x 9) += G V G^T for G (9 x nc) and V (nc x nc, ld nc). */
static void add_sandwich(const double *G, const double *V, int nc, double *C)
{
    for (int a = 0; a < NP; a++)
        for (int b = 0; b < NP; b++) {
            double s = 0.0;
            for (int i = 0; i < nc; i++)
                for (int j = 0; j < nc; j++)
                    s += G[a + NP * i] * V[i + nc * j] * G[b + NP * j];
            C[a + NP * b] += s;
        }
}

/* 1 when the rotations span the three axes: W = sum_k d_k d_k^T, d_k the
 * bias-free raw rate summed over rotation k, has its smallest eigenvalue
 * above 1e-4 trace(W) (random attitudes: 0.1 to 0.3; rotations about one
 * axis: the noise, 1e-7). */
static int rotations_span(const gyro_problem *g)
{
    double W[9] = {0.0};
    for (int k = 0; k < g->m; k++) {
        double d[3] = {0.0, 0.0, 0.0};
        for (int i = g->end[k] - 1; i <= g->start[k + 1]; i++)
            for (int j = 0; j < 3; j++)
                d[j] += at(&g->r, i, j) - g->b[j];
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                W[a + 3 * b] += d[a] * d[b];
    }
    double tr = W[0] + W[4] + W[8];
    return tr > 0 && !igea__chol_lower(3, W, 3, -1e-4 * tr);
}

/* The residual sd the gyro noise of the first static interval predicts:
 * sd^2 = mean_k L_k dt^2 mean_j k_j^2 var_j, L_k the steps of rotation k. */
static double gyro_predicted_sd(const gyro_problem *g, const double *p)
{
    double v[3], p2 = 0.0, kv = 0.0;
    variances(&g->r, g->start[0], g->end[0], v);
    for (int j = 0; j < 3; j++)
        kv += p[j] * p[j] * v[j] / 3.0;
    for (int k = 0; k < g->m; k++)
        p2 += (g->start[k + 1] - g->end[k] + 1) * g->h * g->h * kv / g->m;
    return sqrt(p2);
}

/* Assemble the 12 x 12 covariance (b, then p) from C_pp (9 x 9), C_pb
 * (9 x 3) and C_bb (3 x 3). */
static void gyro_cov_out(const double *Cpp, const double *Cpb, const double *Cbb, double *cov,
                         int ldc)
{
    for (int j = 0; j < GP; j++)
        for (int i = 0; i < GP; i++) {
            double c;
            if (i < 3 && j < 3)
                c = Cbb[i + 3 * j];
            else if (i >= 3 && j >= 3)
                c = Cpp[(i - 3) + NP * (j - 3)];
            else if (i >= 3)
                c = Cpb[(i - 3) + NP * j];
            else
                c = Cpb[(j - 3) + NP * i];
            IGEA_AT(cov, ldc, i, j) = c;
        }
}

typedef struct {
    double theta[GP], cov[GP * GP], info[IGEA_TRIAD_GYRO_INFO_LEN];
} gyro_result;

/* ---- the Earth's rate (docs/calibration.md, "The Earth's rate") ----------------
 * In static interval k the gyro reads b + S^-1 w_k, w_k = W sin(lat) v_k + h_k
 * (the Earth's rate in the body: its vertical part along the gravity
 * direction v_k, known; h_k the horizontal part, W cos(lat) towards north,
 * unknown without the heading). An Earth-fixed vector is carried from the
 * body of interval k to that of k + 1 by M_k = R_k^T E_k, E_k = exp([w_k x]
 * dt_k) the Earth's turn over the rotation's dt_k; so h_k = P_k G_k E0 x,
 * G_k = M_{k-1} ... M_0, E0 an orthonormal basis of the plane normal to v_0,
 * P_k = I - v_k v_k^T, and x (2) the horizontal rate at the first interval
 * in that basis. */

/* out = exp([w x] dt) v (Rodrigues); out may be v. */
static void earth_turn(const double *w, double dt, const double *v, double *out)
{
    double n = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (!(n > 0.0)) {
        memmove(out, v, 3 * sizeof(double));
        return;
    }
    double u[3] = {w[0] / n, w[1] / n, w[2] / n}, c = cos(n * dt), s = sin(n * dt);
    double uv = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    double x[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    double o[3];
    for (int i = 0; i < 3; i++)
        o[i] = v[i] * c + x[i] * s + u[i] * uv * (1.0 - c);
    memcpy(out, o, sizeof o);
}

/* E0 (3 x 2, column-major): an orthonormal basis of the plane normal to v. */
static void earth_plane(const double *v, double *E0)
{
    int a = 0;
    for (int i = 1; i < 3; i++)
        if (fabs(v[i]) < fabs(v[a]))
            a = i;
    double e[3] = {0.0, 0.0, 0.0}, d;
    e[a] = 1.0;
    d = v[a];
    for (int i = 0; i < 3; i++)
        e[i] -= d * v[i];
    d = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    for (int i = 0; i < 3; i++)
        E0[i] = e[i] / d;
    E0[3] = v[1] * E0[2] - v[2] * E0[1];
    E0[4] = v[2] * E0[0] - v[0] * E0[2];
    E0[5] = v[0] * E0[1] - v[1] * E0[0];
}

typedef struct {
    double rate, sinl, cosl; /* the Earth's rate (rate units) and the latitude; rate 0: none */
    double *G;               /* 9 nint: the chain G_k (row-major) */
    double *hk, *vs;         /* 3 nint, 3 m */
    double *rbar, *cnt;      /* 3 nint, nint: the static means and their samples */
    double E0[6], x[2], Cbx[25];
    int iter;
} earth_state;

static double rot_dt(const gyro_problem *g, int k)
{
    return (g->start[k + 1] - (g->end[k] - 1)) * g->h;
}

/* h_k and the turned start directions vs_k at x. */
static void earth_dirs(const gyro_problem *g, int nint, earth_state *e, const double *x)
{
    for (int k = 0; k < nint; k++) {
        const double *G = e->G + 9 * (size_t)k, *v = g->v + 3 * (size_t)k;
        double y[3], *h = e->hk + 3 * (size_t)k;
        for (int i = 0; i < 3; i++) {
            double s = 0.0;
            for (int c = 0; c < 3; c++)
                s += G[3 * i + c] * (e->E0[c] * x[0] + e->E0[3 + c] * x[1]);
            y[i] = s;
        }
        double vy = v[0] * y[0] + v[1] * y[1] + v[2] * y[2];
        for (int i = 0; i < 3; i++)
            h[i] = y[i] - vy * v[i];
        if (k == nint - 1)
            break;
        double w[3];
        for (int i = 0; i < 3; i++)
            w[i] = e->rate * e->sinl * v[i] + h[i];
        earth_turn(w, rot_dt(g, k), v, e->vs + 3 * (size_t)k);
    }
}

/* The chain G_k from the rotations g->R (at the fitted p) and h_k. */
static void earth_chain(const gyro_problem *g, int nint, earth_state *e)
{
    double *G = e->G;
    for (int i = 0; i < 9; i++)
        G[i] = i % 4 == 0;
    for (int k = 0; k + 1 < nint; k++) {
        const double *R = g->R + 9 * (size_t)k, *v = g->v + 3 * (size_t)k, *h = e->hk + 3 * (size_t)k;
        double w[3], M[9], col[3], t[3];
        for (int i = 0; i < 3; i++)
            w[i] = e->rate * e->sinl * v[i] + h[i];
        for (int c = 0; c < 3; c++) { /* column c of M = R^T E e_c */
            for (int i = 0; i < 3; i++)
                col[i] = i == c;
            earth_turn(w, rot_dt(g, k), col, t);
            for (int i = 0; i < 3; i++)
                M[3 * i + c] = R[i] * t[0] + R[3 + i] * t[1] + R[6 + i] * t[2];
        }
        double *Gn = G + 9 * (size_t)(k + 1), *Gk = G + 9 * (size_t)k;
        for (int i = 0; i < 3; i++)
            for (int c = 0; c < 3; c++)
                Gn[3 * i + c] = M[3 * i] * Gk[c] + M[3 * i + 1] * Gk[3 + c] + M[3 * i + 2] * Gk[6 + c];
    }
}

/* The inverse of the 3 x 3 S (row-major 2-d array) by cofactors. */
static int inverse3(double S[3][3], double Si[3][3])
{
    double det = S[0][0] * (S[1][1] * S[2][2] - S[1][2] * S[2][1]) -
                 S[0][1] * (S[1][0] * S[2][2] - S[1][2] * S[2][0]) +
                 S[0][2] * (S[1][0] * S[2][1] - S[1][1] * S[2][0]);
    if (!(fabs(det) > 0.0) || !isfinite(det))
        return IGEA_ESINGULAR;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int a = (j + 1) % 3, b = (j + 2) % 3, c = (i + 1) % 3, d = (i + 2) % 3;
            Si[i][j] = (S[a][c] * S[b][d] - S[a][d] * S[b][c]) / det;
        }
    return 0;
}

/* The biases and x by weighted least squares on the static means,
 *   rbar_k - S^-1 W sin(lat) v_k = b + S^-1 P_k G_k E0 x,
 * weights N_k / s2_j; (b, x) into bx, their covariance into e->Cbx.
 * IGEA_ERANK when the attitudes do not separate b from x. */
static int earth_static(const gyro_problem *g, int nint, earth_state *e, const double *p,
                        const double *s2, double *bx)
{
    double S[3][3], Si[3][3], Nm[25] = {0.0}, rhs[5] = {0.0};
    gyro_matrix(p, S);
    if (inverse3(S, Si))
        return IGEA_ERANK;
    for (int k = 0; k < nint; k++) {
        const double *G = e->G + 9 * (size_t)k, *v = g->v + 3 * (size_t)k;
        double GE[3][2], PGE[3][2], H[3][2], sv[3];
        for (int i = 0; i < 3; i++)
            for (int c = 0; c < 2; c++)
                GE[i][c] = G[3 * i] * e->E0[3 * c] + G[3 * i + 1] * e->E0[3 * c + 1] +
                           G[3 * i + 2] * e->E0[3 * c + 2];
        for (int c = 0; c < 2; c++) {
            double vg = v[0] * GE[0][c] + v[1] * GE[1][c] + v[2] * GE[2][c];
            for (int i = 0; i < 3; i++)
                PGE[i][c] = GE[i][c] - vg * v[i];
        }
        for (int i = 0; i < 3; i++) {
            sv[i] = e->rate * e->sinl * (Si[i][0] * v[0] + Si[i][1] * v[1] + Si[i][2] * v[2]);
            for (int c = 0; c < 2; c++)
                H[i][c] = Si[i][0] * PGE[0][c] + Si[i][1] * PGE[1][c] + Si[i][2] * PGE[2][c];
        }
        for (int j = 0; j < 3; j++) {
            double a[5] = {j == 0, j == 1, j == 2, H[j][0], H[j][1]};
            double w = e->cnt[k] / s2[j], y = e->rbar[3 * (size_t)k + j] - sv[j];
            for (int r = 0; r < 5; r++) {
                rhs[r] += w * a[r] * y;
                for (int c = 0; c < 5; c++)
                    Nm[r + 5 * c] += w * a[r] * a[c];
            }
        }
    }
    double L[25], col[5];
    memcpy(L, Nm, sizeof L);
    for (int i = 0; i < 5; i++) /* pivot test on the unit-diagonal scaling */
        if (!(Nm[i + 5 * i] > 0.0))
            return IGEA_ERANK;
    for (int j = 0; j < 5; j++)
        for (int i = 0; i < 5; i++)
            L[i + 5 * j] = Nm[i + 5 * j] / sqrt(Nm[i + 5 * i] * Nm[j + 5 * j]);
    if (igea__chol_lower(5, L, 5, 0.0))
        return IGEA_ERANK;
    for (int i = 0; i < 5; i++)
        if (!(L[i + 5 * i] * L[i + 5 * i] > 1e-8))
            return IGEA_ERANK;
    for (int c = 0; c < 5; c++) { /* Cbx = Nm^-1 through the scaled factor */
        for (int i = 0; i < 5; i++) {
            double t = (i == c) / sqrt(Nm[i + 5 * i]);
            for (int l = 0; l < i; l++)
                t -= L[i + 5 * l] * col[l];
            col[i] = t / L[i + 5 * i];
        }
        for (int i = 4; i >= 0; i--) {
            double t = col[i];
            for (int l = i + 1; l < 5; l++)
                t -= L[l + 5 * i] * col[l];
            col[i] = t / L[i + 5 * i];
        }
        for (int i = 0; i < 5; i++)
            e->Cbx[i + 5 * c] = col[i] / sqrt(Nm[i + 5 * i]);
    }
    for (int i = 0; i < 5; i++) {
        double t = 0.0;
        for (int c = 0; c < 5; c++)
            t += e->Cbx[i + 5 * c] * rhs[c];
        bx[i] = t;
    }
    return 0;
}

/* dr/dx (rows x 2) by central differences of 1e-3 of the Earth's rate. */
static void earth_jacobian(gyro_problem *g, int nint, earth_state *e, const double *p, double *Jx)
{
    int rows = 3 * g->m;
    for (int c = 0; c < 2; c++) {
        double xp[2] = {e->x[0], e->x[1]}, rp[3], rm[3], hc = 1e-3 * e->rate;
        double *vsp = Jx + (size_t)rows * 2; /* scratch: 2 x 3 m after Jx */
        xp[c] = e->x[c] + hc;
        earth_dirs(g, nint, e, xp);
        memcpy(vsp, e->vs, sizeof(double) * 3 * (size_t)g->m);
        xp[c] = e->x[c] - hc;
        earth_dirs(g, nint, e, xp);
        double *vsm = vsp + 3 * (size_t)g->m;
        memcpy(vsm, e->vs, sizeof(double) * 3 * (size_t)g->m);
        const double *keep = g->vs;
        for (int k = 0; k < g->m; k++) {
            g->vs = vsp;
            pair_residual(g, p, g->b, k, rp, NULL);
            g->vs = vsm;
            pair_residual(g, p, g->b, k, rm, NULL);
            for (int i = 0; i < 3; i++)
                IGEA_AT(Jx, rows, 3 * k + i, c) = (rp[i] - rm[i]) / (2.0 * hc);
        }
        g->vs = keep;
    }
    earth_dirs(g, nint, e, e->x);
}

/* The fit on a validated problem; the workspace: gyro_work(nint). */
static int gyro_run(gyro_problem *g, int nint, const double *means, const double *theta_a,
                    const double *cov_a, int max_iter, earth_state *e, double *work,
                    gyro_result *out)
{
    int m = nint - 1, rows = 3 * m, st, earth = e && e->rate > 0.0;
    double *v = work, *D = v + 3 * (size_t)nint, *R = D + 27 * (size_t)nint;
    double *lw = R + 9 * (size_t)m, *Ja = lw + 11 * (size_t)rows, *Jb = Ja + 9 * (size_t)rows;
    double *r = lw, *J = lw + 2 * (size_t)rows, s2[3], vb[3];
    double *ew = Jb + 3 * (size_t)rows; /* the Earth's: 9 + 3 + 3 + 1 nint, 3 m, 5 + 6 rows */
    directions(nint, means, theta_a, v, D);
    g->v = v, g->m = m, g->R = NULL, g->vs = NULL;
    int N = gyro_bias(g, nint, g->b, s2, earth ? ew + 15 * (size_t)nint : NULL,
                      earth ? ew + 18 * (size_t)nint : NULL);
    for (int j = 0; j < 3; j++)
        vb[j] = s2[j] / N;
    if (!rotations_span(g))
        return IGEA_ERANK;
    lm_state lm;
    for (int j = 0; j < NP; j++)
        lm.theta[j] = j < 3 ? 1.0 : 0.0;
    double rms0 = NAN, *Jbx = ew + 19 * (size_t)nint + 3 * (size_t)m;
    if (earth) {
        e->G = ew, e->hk = ew + 9 * (size_t)nint, e->vs = ew + 12 * (size_t)nint;
        e->rbar = ew + 15 * (size_t)nint, e->cnt = ew + 18 * (size_t)nint;
        e->x[0] = e->x[1] = 0.0;
        earth_plane(v, e->E0);
        for (int k = 0; k < nint; k++) /* no chain yet: x = 0 gives h = 0 */
            for (int i = 0; i < 9; i++)
                e->G[9 * (size_t)k + i] = i % 4 == 0;
        earth_dirs(g, nint, e, e->x);
        g->vs = e->vs;
    }
    for (int it = 0;; it++) {
        st = lm_run(rows, gyro_residuals, g, max_iter, &lm, lw);
        if ((!st || st == IGEA_ENOCONV) && !identifiable(lm.A))
            st = IGEA_ERANK;
        if (st)
            return st;
        if (it == 0)
            rms0 = sqrt(lm.rms0 * lm.rms0 * 3.0);
        if (!earth)
            break;
        /* the rotations at p, the chain, then b and x from the static means */
        double bx[5], dmax = 0.0;
        g->R = R;
        gyro_residuals(g, lm.theta, r, NULL);
        earth_chain(g, nint, e);
        if ((st = earth_static(g, nint, e, lm.theta, s2, bx)))
            return st;
        for (int i = 0; i < 5; i++) {
            double old = i < 3 ? g->b[i] : e->x[i - 3];
            dmax = fmax(dmax, fabs(bx[i] - old) / sqrt(e->Cbx[i + 5 * i]));
        }
        memcpy(g->b, bx, 3 * sizeof(double));
        e->x[0] = bx[3], e->x[1] = bx[4];
        earth_dirs(g, nint, e, e->x);
        e->iter = it + 1;
        if (dmax < 1e-3)
            break;
        if (it >= 50)
            return IGEA_ENOCONV;
    }
    double s2f = lm.cost / (2 * m - NP);
    double Cpp[NP * NP], Gb[NP * 5], Ga[NP * NP], Cpb[NP * 3], Cbb[9];
    g->R = R;
    gyro_residuals(g, lm.theta, r, J);
    double grad[NP], Vb[9] = {vb[0], 0.0, 0.0, 0.0, vb[1], 0.0, 0.0, 0.0, vb[2]};
    normal_eq(rows, J, r, lm.A, grad);
    if ((st = covariance(lm.A, s2f, Cpp, NP)))
        return st;
    if (!earth) {
        bias_jacobian(g, lm.theta, Jb);
        if ((st = sensitivity(rows, J, lm.A, Jb, 3, Gb)))
            return st;
        add_sandwich(Gb, Vb, 3, Cpp);
        for (int j = 0; j < 3; j++)
            for (int i = 0; i < NP; i++)
                Cpb[i + NP * j] = Gb[i + NP * j] * vb[j];
        memcpy(Cbb, Vb, sizeof Cbb);
    } else { /* (b, x) together: G = -(J^T J)^-1 J^T [dr/db dr/dx] */
        double GC[NP * 5];
        bias_jacobian(g, lm.theta, Jbx);
        earth_jacobian(g, nint, e, lm.theta, Jbx + 3 * (size_t)rows);
        if ((st = sensitivity(rows, J, lm.A, Jbx, 5, Gb)))
            return st;
        add_sandwich(Gb, e->Cbx, 5, Cpp);
        for (int j = 0; j < 5; j++)
            for (int i = 0; i < NP; i++) {
                double t = 0.0;
                for (int l = 0; l < 5; l++)
                    t += Gb[i + NP * l] * e->Cbx[l + 5 * j];
                GC[i + NP * j] = t;
            }
        memcpy(Cpb, GC, sizeof Cpb);
        for (int j = 0; j < 3; j++)
            for (int i = 0; i < 3; i++)
                Cbb[i + 3 * j] = e->Cbx[i + 5 * j];
    }
    if (cov_a) {
        accel_jacobian(g, D, Ja);
        if ((st = sensitivity(rows, J, lm.A, Ja, NP, Ga)))
            return st;
        add_sandwich(Ga, cov_a, NP, Cpp);
    }
    memcpy(out->theta, g->b, sizeof g->b);
    memcpy(out->theta + 3, lm.theta, sizeof lm.theta);
    gyro_cov_out(Cpp, Cpb, Cbb, out->cov, GP);
    double *f = out->info;
    for (int i = 0; i < IGEA_TRIAD_GYRO_INFO_LEN; i++)
        f[i] = 0.0;
    f[IGEA_TRIAD_GYRO_INFO_PAIRS] = m;
    f[IGEA_TRIAD_GYRO_INFO_RMS_BEFORE] = rms0;
    f[IGEA_TRIAD_GYRO_INFO_RMS_AFTER] = sqrt(lm.cost / m);
    f[IGEA_TRIAD_GYRO_INFO_SIGMA] = sqrt(s2f);
    f[IGEA_TRIAD_GYRO_INFO_ITERATIONS] = lm.iter;
    f[IGEA_TRIAD_GYRO_INFO_STATIC_SAMPLES] = N;
    for (int j = 0; j < 3; j++)
        f[IGEA_TRIAD_GYRO_INFO_NOISE_X + j] = sqrt(s2[j]);
    f[IGEA_TRIAD_GYRO_INFO_MISFIT] = sqrt(s2f) / gyro_predicted_sd(g, lm.theta);
    if (earth) {
        double x0 = e->x[0], x1 = e->x[1], nx = hypot(x0, x1), *C = e->Cbx;
        double cxx = (x0 * x0 * C[18] + 2 * x0 * x1 * C[23] + x1 * x1 * C[24]) / (nx * nx);
        double cphi = (x1 * x1 * C[18] - 2 * x0 * x1 * C[23] + x0 * x0 * C[24]) / (nx * nx * nx * nx);
        double nb[3], eb[3], *v0 = v;
        for (int i = 0; i < 3; i++) /* north in the body of interval 0, then east = n x up */
            nb[i] = (e->E0[i] * x0 + e->E0[3 + i] * x1) / nx;
        eb[0] = nb[1] * v0[2] - nb[2] * v0[1];
        eb[1] = nb[2] * v0[0] - nb[0] * v0[2];
        eb[2] = nb[0] * v0[1] - nb[1] * v0[0];
        double psi = atan2(eb[0], nb[0]) * DEG;
        f[IGEA_TRIAD_GYRO_INFO_EARTH_H] = nx;
        f[IGEA_TRIAD_GYRO_INFO_EARTH_H_SD] = sqrt(cxx);
        f[IGEA_TRIAD_GYRO_INFO_HEADING] = psi < 0.0 ? psi + 360.0 : psi;
        f[IGEA_TRIAD_GYRO_INFO_HEADING_SD] = sqrt(cphi) * DEG;
        f[IGEA_TRIAD_GYRO_INFO_EARTH_ITER] = e->iter;
    }
    for (int i = 0; i < GP; i++)
        if (!isfinite(out->theta[i]) || !isfinite(out->cov[i + GP * i]))
            return IGEA_ENOCONV;
    return 0;
}

/* 0, or -7 / -8 for static intervals that are not increasing ranges of at
 * least 2 samples inside n samples. */
static int check_intervals(int n, int nint, const int *start, const int *end)
{
    for (int k = 0; k < nint; k++) {
        if (start[k] < (k ? end[k - 1] : 0))
            return -7;
        if (end[k] < start[k] + 2 || end[k] > n)
            return -8;
    }
    return 0;
}

static double *gyro_work(int nint)
{
    size_t m = (size_t)nint - 1;
    return igea__dalloc(49 * (size_t)nint + 9 * m + 23 * 3 * m + 24 * m);
}

/* igea_triad_gyro_fit(_earth): the outputs theta, cov, ldc are arguments
 * 14.. (off = 0) or 16.. (off = 2). */
static int gyro_fit(int layout, int n, const double *gyro, int ldg, double fs, int nint,
                    const int *start, const int *end, const double *means,
                    const double *theta_a, const double *cov_a, int ldca, int max_iter,
                    earth_state *e, int off, double *theta, double *cov, int ldc, double *info)
{
    gyro_problem g;
    int st = record_check(layout, n, gyro, ldg, &g.r);
    if (st < 0 && st != IGEA_ENONFINITE)
        return st;
    if (!(isfinite(fs) && fs > 0))
        return -5;
    if (nint < MIN_INTERVALS)
        return -6;
    if (!start)
        return -7;
    if (!end)
        return -8;
    int ci = check_intervals(n, nint, start, end);
    if (ci)
        return ci;
    if (!means)
        return -9;
    if (!theta_a)
        return -10;
    if (cov_a && ldca < NP)
        return -12;
    if (max_iter < 1)
        return -13;
    if (off && !(isfinite(e->rate) && e->rate >= 0.0))
        return -14;
    if (off && !(e->sinl >= -1.0 && e->sinl <= 1.0)) /* NaN or beyond +-90 deg */
        return -15;
    if (!theta)
        return -(14 + off);
    if (cov && ldc < GP)
        return -(16 + off);
    if (st || !igea__finite_vec(3 * nint, means, 1) || !igea__finite_vec(NP, theta_a, 1) ||
        (cov_a && !igea__finite_mat(NP, NP, cov_a, ldca)))
        return IGEA_ENONFINITE;
    double ca[NP * NP];
    for (int j = 0; cov_a && j < NP; j++)
        for (int i = 0; i < NP; i++)
            ca[i + NP * j] = IGEA_AT(cov_a, ldca, i, j);
    double *work = gyro_work(nint);
    gyro_result *res = malloc(sizeof *res);
    if (!work || !res) {
        free(work), free(res);
        return IGEA_ENOMEM;
    }
    g.h = 1.0 / fs, g.start = start, g.end = end;
    st = gyro_run(&g, nint, means, theta_a, cov_a ? ca : NULL, max_iter, e, work, res);
    if (!st) {
        memcpy(theta, res->theta, sizeof res->theta);
        for (int j = 0; cov && j < GP; j++)
            for (int i = 0; i < GP; i++)
                IGEA_AT(cov, ldc, i, j) = res->cov[i + GP * j];
        if (info)
            memcpy(info, res->info, sizeof res->info);
    }
    free(work), free(res);
    return st;
}

int igea_triad_gyro_fit(int layout, int n, const double *gyro, int ldg, double fs, int nint,
                        const int *start, const int *end, const double *means,
                        const double *theta_a, const double *cov_a, int ldca, int max_iter,
                        double *theta, double *cov, int ldc, double *info)
{
    return gyro_fit(layout, n, gyro, ldg, fs, nint, start, end, means, theta_a, cov_a, ldca,
                    max_iter, NULL, 0, theta, cov, ldc, info);
}

/* The Earth model of a rate (rate units) and a latitude (deg): sinl NaN
 * for a latitude outside [-90, 90] or not finite. */
static earth_state earth_model(double rate, double lat_deg)
{
    earth_state e;
    memset(&e, 0, sizeof e);
    e.rate = rate;
    e.sinl = isfinite(lat_deg) && fabs(lat_deg) <= 90.0 ? sin(lat_deg / DEG) : NAN;
    e.cosl = cos(lat_deg / DEG);
    return e;
}

int igea_triad_gyro_fit_earth(int layout, int n, const double *gyro, int ldg, double fs,
                              int nint, const int *start, const int *end, const double *means,
                              const double *theta_a, const double *cov_a, int ldca, int max_iter,
                              double earth_rate, double lat_deg, double *theta, double *cov,
                              int ldc, double *info)
{
    earth_state e = earth_model(earth_rate, lat_deg);
    return gyro_fit(layout, n, gyro, ldg, fs, nint, start, end, means, theta_a, cov_a, ldca,
                    max_iter, &e, 2, theta, cov, ldc, info);
}

/* The static intervals and means at the threshold the accelerometer fit
 * chose; *nint their count. */
static int imu_intervals(int layout, int n, const double *acc, int lda, double fs,
                         const double *opts, double threshold, int *nint, int **se,
                         double **means)
{
    int cnt = 0;
    int st = igea_triad_static(layout, n, acc, lda, fs, opts[IGEA_TRIAD_OPT_WINDOW], threshold,
                               opts[IGEA_TRIAD_OPT_MIN_STATIC], 0, &cnt, NULL, NULL, NULL);
    if (st)
        return st;
    *se = igea__ialloc(2 * (size_t)cnt + 1);
    *means = igea__dalloc(3 * (size_t)cnt + 1);
    if (!*se || !*means)
        return IGEA_ENOMEM;
    *nint = cnt;
    return igea_triad_static(layout, n, acc, lda, fs, opts[IGEA_TRIAD_OPT_WINDOW], threshold,
                             opts[IGEA_TRIAD_OPT_MIN_STATIC], cnt, &cnt, *se, *se + cnt,
                             *means);
}

int igea_triad_calibrate_imu(int layout, int n, const double *acc, int lda, const double *gyro,
                             int ldg, double fs, const double *opts, double *theta_a,
                             double *cov_a, int ldca, double *theta_g, double *cov_g, int ldcg,
                             double *info_a, double *info_g)
{
    record ra, rg;
    int sa = record_check(layout, n, acc, lda, &ra), sg;
    if (sa < 0 && sa != IGEA_ENONFINITE)
        return sa;
    sg = record_check(layout, n, gyro, ldg, &rg);
    if (sg == -3)
        return -5;
    if (sg == -4)
        return -6;
    if (!(isfinite(fs) && fs > 0))
        return -7;
    if (igea_triad_check_opts(opts))
        return -8;
    if (!theta_a)
        return -9;
    if (cov_a && ldca < NP)
        return -11;
    if (!theta_g)
        return -12;
    if (cov_g && ldcg < GP)
        return -14;
    if (sa || sg)
        return IGEA_ENONFINITE;
    double ta[NP], ca[NP * NP], ia[IGEA_TRIAD_INFO_LEN], *means = NULL;
    int *se = NULL, nint = 0;
    int st = igea_triad_calibrate(layout, n, acc, lda, fs, opts, ta, ca, NP, ia);
    if (!st)
        st = imu_intervals(layout, n, acc, lda, fs, opts, ia[IGEA_TRIAD_INFO_THRESHOLD], &nint,
                           &se, &means);
    if (!st && check_intervals(n, nint, se, se + nint))
        st = IGEA_EEMPTY; /* single-sample intervals: no gyro noise estimate */
    gyro_result *res = st ? NULL : malloc(sizeof *res);
    double *work = st ? NULL : gyro_work(nint);
    if (!st && (!res || !work))
        st = IGEA_ENOMEM;
    if (!st) {
        gyro_problem g = {rg, 1.0 / fs, 0, se, se + nint, NULL, {0.0, 0.0, 0.0}, NULL, NULL};
        earth_state e = earth_model(opts[IGEA_TRIAD_OPT_EARTH_RATE], opts[IGEA_TRIAD_OPT_LAT]);
        st = gyro_run(&g, nint, means, ta, ca, (int)opts[IGEA_TRIAD_OPT_MAX_ITER], &e, work,
                      res);
    }
    if (!st) {
        memcpy(theta_a, ta, sizeof ta);
        memcpy(theta_g, res->theta, sizeof res->theta);
        for (int j = 0; cov_a && j < NP; j++)
            for (int i = 0; i < NP; i++)
                IGEA_AT(cov_a, ldca, i, j) = ca[i + NP * j];
        for (int j = 0; cov_g && j < GP; j++)
            for (int i = 0; i < GP; i++)
                IGEA_AT(cov_g, ldcg, i, j) = res->cov[i + GP * j];
        if (info_a)
            memcpy(info_a, ia, sizeof ia);
        if (info_g)
            memcpy(info_g, res->info, sizeof res->info);
    }
    free(se), free(means), free(res), free(work);
    return st;
}

int igea_triad_gyro_apply(int layout, int n, const double *raw, int ldr, const double *theta,
                          double *cal, int ldc)
{
    record r;
    int st = apply_args(layout, n, raw, ldr, theta, GP, cal, ldc, &r);
    if (st)
        return st;
    double S[3][3];
    gyro_matrix(theta + 3, S);
    for (int i = 0; i < n; i++) {
        double u[3], w[3];
        for (int j = 0; j < 3; j++)
            u[j] = at(&r, i, j) - theta[j];
        for (int j = 0; j < 3; j++)
            w[j] = S[j][0] * u[0] + S[j][1] * u[1] + S[j][2] * u[2];
        put_row(layout, cal, ldc, i, w);
    }
    return 0;
}
