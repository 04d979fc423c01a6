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

/* Levenberg-Marquardt from lm->theta; work: nint (r) + nint (r2) + 9 nint (J). */
static int lm_run(int nint, const double *m, double g, int max_iter, lm_state *lm, double *work)
{
    double *r = work, *r2 = r + nint, *J = r2 + nint, grad[NP], step[NP], trial[NP];
    residuals(nint, m, g, lm->theta, r, J);
    lm->cost = sumsq(nint, r);
    lm->rms0 = sqrt(lm->cost / nint);
    double lam = 1e-3;
    for (lm->iter = 0; lm->iter < max_iter; lm->iter++) {
        normal_eq(nint, J, r, lm->A, grad);
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
            residuals(nint, m, g, trial, r2, NULL);
            double c2 = sumsq(nint, r2);
            if (isfinite(c2) && c2 < lm->cost) {
                double drop = lm->cost - c2;
                memcpy(lm->theta, trial, sizeof trial);
                lm->cost = c2;
                residuals(nint, m, g, lm->theta, r, J);
                lam = fmax(lam / 10.0, 1e-12);
                accepted = 1;
                if (drop <= 1e-14 * c2) {
                    normal_eq(nint, J, r, lm->A, grad);
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
    int st = lm_run(nint, m, g, max_iter, &lm, work);
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
        info[IGEA_TRIAD_INFO_ZETA_INIT] = NAN;
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

int igea_triad_apply(int layout, int n, const double *raw, int ldr, const double *theta,
                     double *cal, int ldc)
{
    record r;
    int st = record_check(layout, n, raw, ldr, &r);
    if (st < 0 && st != IGEA_ENONFINITE)
        return st;
    if (!theta)
        return -5;
    if (!cal)
        return -6;
    if (layout == IGEA_ROWMAJOR ? ldc < 3 : ldc < n)
        return -7;
    if (st || !igea__finite_vec(NP, theta, 1))
        return IGEA_ENONFINITE;
    const double *t = theta;
    for (int i = 0; i < n; i++) {
        double w[3];
        for (int j = 0; j < 3; j++)
            w[j] = t[IGEA_TRIAD_KX + j] * (at(&r, i, j) - t[IGEA_TRIAD_BX + j]);
        double c[3] = {w[0], t[IGEA_TRIAD_TYX] * w[0] + w[1],
                       t[IGEA_TRIAD_TZX] * w[0] + t[IGEA_TRIAD_TZY] * w[1] + w[2]};
        for (int j = 0; j < 3; j++) {
            if (layout == IGEA_ROWMAJOR)
                cal[(size_t)i * ldc + j] = c[j];
            else
                cal[i + (size_t)j * ldc] = c[j];
        }
    }
    return 0;
}
