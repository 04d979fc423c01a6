/* stability_fit.c - IEEE Std 952 noise model fitted to a whole Allan
 * variance curve: weighted non-negative least squares with standard errors
 * (docs/stability.md). */
#include <float.h>

#include <gsl/gsl_fft_halfcomplex.h>
#include <gsl/gsl_fft_real.h>
#include <gsl/gsl_randist.h>

#include "igea/stability.h"
#include "internal.h"

#define P_ IGEA_STABILITY_FIT_LEN
#ifndef LR_CRIT
#define LR_CRIT 3.84
#endif

/* tau dependence of the five variance terms */
static void basis(double t, double *f)
{
    f[0] = 3.0 / (t * t);
    f[1] = 1.0 / t;
    f[2] = 2.0 * log(2.0) / 3.14159265358979323846;
    f[3] = t / 3.0;
    f[4] = t * t / 2.0;
}

/* Least squares on the columns of a (m x P_, column-major, lda m) listed in
 * idx[np]: z (P_, zero outside idx) and, when cov is not NULL, the inverse
 * of R^T R in cov (np x np). w: m (P_ + 1) doubles. Returns 0, or 1 when a
 * column is dependent on the others. */
static int ls_subset(int m, const double *a, const double *b, int np, const int *idx, double *z,
                     double *cov, double *w)
{
    double *q = w, *rhs = w + (size_t)m * P_, R[P_][P_] = {{0}};
    for (int k = 0; k < np; k++)
        memcpy(q + (size_t)k * m, a + (size_t)idx[k] * m, sizeof(double) * (size_t)m);
    memcpy(rhs, b, sizeof(double) * (size_t)m);
    for (int k = 0; k < np; k++) { /* Householder on column k */
        double *v = q + (size_t)k * m, nr = 0.0;
        for (int i = k; i < m; i++)
            nr = hypot(nr, v[i]);
        if (!(nr > 0.0))
            return 1;
        double alpha = v[k] > 0 ? -nr : nr;
        v[k] -= alpha;
        double vn = 0.0;
        for (int i = k; i < m; i++)
            vn += v[i] * v[i];
        for (int c = k + 1; c <= np; c++) {
            double *u = c < np ? q + (size_t)c * m : rhs, s = 0.0;
            for (int i = k; i < m; i++)
                s += v[i] * u[i];
            s = 2.0 * s / vn;
            for (int i = k; i < m; i++)
                u[i] -= s * v[i];
        }
        R[k][k] = alpha;
        for (int c = k + 1; c < np; c++)
            R[k][c] = q[(size_t)c * m + k];
    }
    for (int k = 0; k < np; k++)
        if (!(fabs(R[k][k]) > 1e-13 * fabs(R[0][0])))
            return 1;
    double x[P_];
    for (int k = np - 1; k >= 0; k--) {
        double s = rhs[k];
        for (int c = k + 1; c < np; c++)
            s -= R[k][c] * x[c];
        x[k] = s / R[k][k];
    }
    for (int k = 0; k < P_; k++)
        z[k] = 0.0;
    for (int k = 0; k < np; k++)
        z[idx[k]] = x[k];
    if (cov) { /* (R^T R)^-1 = R^-1 R^-T */
        double Ri[P_][P_] = {{0}};
        for (int c = 0; c < np; c++)
            for (int k = c; k >= 0; k--) {
                double s = k == c ? 1.0 : 0.0;
                for (int j = k + 1; j <= c; j++)
                    s -= R[k][j] * Ri[j][c];
                Ri[k][c] = s / R[k][k];
            }
        for (int i = 0; i < np; i++)
            for (int j = 0; j < np; j++) {
                double s = 0.0;
                for (int k = IGEA_MAX(i, j); k < np; k++)
                    s += Ri[i][k] * Ri[j][k];
                cov[i * np + j] = s;
            }
    }
    return 0;
}

/* Lawson-Hanson NNLS: x (P_) >= 0 minimising |a x - b|. */
static void nnls(int m, const double *a, const double *b, double *x, double *w)
{
    int inP[P_] = {0}, idx[P_], np = 0;
    double z[P_];
    for (int k = 0; k < P_; k++)
        x[k] = 0.0;
    double bn = 0.0;
    for (int i = 0; i < m; i++)
        bn = hypot(bn, b[i]);
    for (int outer = 0; outer < 3 * P_; outer++) {
        int t = -1;
        double best = 1e-12 * bn;
        for (int k = 0; k < P_; k++) {
            if (inP[k])
                continue;
            double g = 0.0; /* a_k . (b - a x) */
            for (int i = 0; i < m; i++) {
                double res = b[i];
                for (int c = 0; c < P_; c++)
                    res -= a[(size_t)c * m + i] * x[c];
                g += a[(size_t)k * m + i] * res;
            }
            if (g > best) {
                best = g;
                t = k;
            }
        }
        if (t < 0)
            break;
        inP[t] = 1;
        for (int inner = 0; inner < 3 * P_; inner++) {
            np = 0;
            for (int k = 0; k < P_; k++)
                if (inP[k])
                    idx[np++] = k;
            if (ls_subset(m, a, b, np, idx, z, NULL, w)) {
                inP[t] = 0; /* dependent column: leave it out */
                break;
            }
            double step = 1.0;
            int neg = 0;
            for (int k = 0; k < np; k++) {
                int c = idx[k];
                if (z[c] <= 0.0) {
                    neg = 1;
                    step = IGEA_MIN(step, x[c] / (x[c] - z[c]));
                }
            }
            if (!neg) {
                memcpy(x, z, sizeof z);
                break;
            }
            for (int k = 0; k < P_; k++) {
                x[k] += step * (z[k] - x[k]);
                if (inP[k] && x[k] <= 1e-300)
                    inP[k] = 0, x[k] = 0.0;
            }
        }
    }
}

/* Weighted design: row j of a = f(tau_j) / sd_j with unit-norm columns
 * (scale in cs), b_j = v_j / sd_j. */
static void design(int m, const double *tau, const double *v, const double *sd, int drop,
                   double *a, double *b, double *cs)
{
    for (int j = 0; j < m; j++) {
        double f[P_];
        basis(tau[j], f);
        for (int k = 0; k < P_; k++)
            a[(size_t)k * m + j] = f[k] / sd[j];
        b[j] = v[j] / sd[j];
    }
    for (int k = 0; k < P_; k++) {
        double s = 0.0;
        for (int j = 0; j < m; j++)
            s = hypot(s, a[(size_t)k * m + j]);
        cs[k] = k == drop ? 1.0 : s;
        for (int j = 0; j < m; j++)
            a[(size_t)k * m + j] = k == drop ? 0.0 : a[(size_t)k * m + j] / s;
    }
}

static int fit_check(int ntau, const double *tau, const double *adev, const double *edf,
                     const double *coef)
{
    if (ntau < 5)
        return -1;
    if (!tau)
        return -2;
    if (!adev)
        return -3;
    if (!edf)
        return -4;
    if (!coef)
        return -5;
    if (!igea__finite_vec(ntau, tau, 1) || !igea__finite_vec(ntau, adev, 1) ||
        !igea__finite_vec(ntau, edf, 1))
        return IGEA_ENONFINITE;
    for (int j = 0; j < ntau; j++) {
        if (!(tau[j] > 0.0))
            return -2;
        for (int i = 0; i < j; i++)
            if (tau[i] == tau[j])
                return -2;
        if (!(adev[j] > 0.0))
            return -3;
        if (!(edf[j] >= 1.0))
            return -4;
    }
    return 0;
}

/* Standard errors of c (scaled columns: cs) on the design a, b. */
static void fit_se(int m, const double *a, const double *b, const double *x, const double *cs,
                   double *sec, double *chi2, double *w)
{
    int idx[P_ + 1], np = 0;
    double cov[(P_ + 1) * (P_ + 1)], z[P_];
    for (int k = 0; k < P_; k++)
        if (x[k] > 0.0)
            idx[np++] = k;
    double rss = 0.0;
    for (int i = 0; i < m; i++) {
        double r = b[i];
        for (int k = 0; k < P_; k++)
            r -= a[(size_t)k * m + i] * x[k];
        rss += r * r;
    }
    *chi2 = rss;
    double scale = m > np && rss / (m - np) > 1.0 ? rss / (m - np) : 1.0;
    for (int k = 0; k < P_; k++) {
        int n2 = np, pos = -1;
        if (x[k] > 0.0) {
            for (int i = 0; i < np; i++)
                if (idx[i] == k)
                    pos = i;
        } else {
            idx[n2] = k;
            pos = n2++;
        }
        sec[k] = ls_subset(m, a, b, n2, idx, z, cov, w) ? INFINITY
                 : sqrt(cov[pos * n2 + pos] * scale) / cs[k];
    }
}

/* Gamma deviance sum edf_j ((v_j - mu_j) / mu_j - ln(v_j / mu_j)) of the fitted variances. */
static double deviance(int m, const double *tau, const double *v, const double *edf, const double *c)
{
    double D = 0.0;
    for (int j = 0; j < m; j++) {
        double f[P_], mu = 0.0;
        basis(tau[j], f);
        for (int k = 0; k < P_; k++)
            mu += f[k] * c[k];
        if (!(mu > 0.0))
            return INFINITY;
        D += edf[j] * ((v[j] - mu) / mu - log(v[j] / mu));
    }
    return D;
}

/* Maximum-likelihood fit (iteratively reweighted NNLS, the Fisher scoring
 * of a gamma model with identity link) without term `drop` (-1: all):
 * variance coefficients c; a, b, cs: the final weighted design. */
static void fit_run(int m, const double *tau, const double *v, const double *edf, int drop,
                    double *sd, double *a, double *b, double *cs, double *w, double *c)
{
    double x[P_];
    for (int j = 0; j < m; j++)
        sd[j] = v[j] * sqrt(2.0 / edf[j]);
    for (int it = 0; it < 12; it++) {
        design(m, tau, v, sd, drop, a, b, cs);
        nnls(m, a, b, x, w);
        for (int j = 0; j < m; j++) { /* the fitted variance sets the next weights */
            double f[P_], s = 0.0;
            basis(tau[j], f);
            for (int k = 0; k < P_; k++)
                s += f[k] * x[k] / cs[k];
            if (s > 0.0)
                sd[j] = s * sqrt(2.0 / edf[j]);
        }
    }
    design(m, tau, v, sd, drop, a, b, cs);
    nnls(m, a, b, x, w);
    for (int k = 0; k < P_; k++)
        c[k] = x[k] / cs[k];
}

int igea_stability_fit(int ntau, const double *tau, const double *adev, const double *edf,
                       double *coef, double *se, int *supported, double *chi2)
{
    int st = fit_check(ntau, tau, adev, edf, coef);
    if (st)
        return st;
    size_t m = (size_t)ntau;
    double *buf = igea__dalloc(m * (2 * P_ + 4));
    if (!buf)
        return IGEA_ENOMEM;
    double *a = buf, *b = a + m * P_, *v = b + m, *sd = v + m, *w = sd + m;
    double c[P_], cd[P_], x[P_], cs[P_], sec[P_], c2 = 0.0, lr[P_];
    for (size_t j = 0; j < m; j++)
        v[j] = adev[j] * adev[j];
    for (int k = 0; k < P_; k++) { /* likelihood ratio of each term */
        fit_run(ntau, tau, v, edf, k, sd, a, b, cs, w, cd);
        lr[k] = deviance(ntau, tau, v, edf, cd);
    }
    fit_run(ntau, tau, v, edf, -1, sd, a, b, cs, w, c);
    double D = deviance(ntau, tau, v, edf, c);
    for (int k = 0; k < P_; k++)
        x[k] = c[k] * cs[k];
    fit_se(ntau, a, b, x, cs, sec, &c2, w);
    int np = 0;
    for (int k = 0; k < P_; k++)
        np += c[k] > 0.0;
    double phi = ntau > np && D / (ntau - np) > 1.0 ? D / (ntau - np) : 1.0;
    double out[P_], oe[P_];
    int sup[P_];
    for (int k = 0; k < P_; k++) {
        sup[k] = c[k] > 0.0 && (lr[k] - D) / phi > LR_CRIT;
        out[k] = c[k] > 0.0 ? sqrt(c[k]) : 0.0;
        oe[k] = c[k] > 0.0 ? sec[k] / (2.0 * sqrt(c[k])) : sqrt(sec[k]);
    }
    memcpy(coef, out, sizeof out);
    if (se)
        memcpy(se, oe, sizeof oe);
    if (supported)
        memcpy(supported, sup, sizeof sup);
    if (chi2)
        *chi2 = c2;
    free(buf);
    return 0;
}

/* ---- standard errors by a parametric bootstrap of the record ---- */

/* Kasdin and Walter's flicker-FM filter h_k = h_{k-1} (k - 1/2) / k of
 * length n, zero-padded to P (a power of 2), as its radix-2 real FFT. */
static void flicker_filter(size_t n, size_t P, double *H)
{
    H[0] = 1.0;
    for (size_t k = 1; k < P; k++)
        H[k] = k < n ? H[k - 1] * ((double)k - 0.5) / (double)k : 0.0;
    gsl_fft_real_radix2_transform(H, 1, P);
}

/* One record y[n] at fs of the model c = (Q^2, N^2, B^2, K^2, R^2): white
 * phase Q (x_i = Q u_i, y = dx fs), white rate N sqrt(fs), flicker rate B
 * (unit white noise through the filter H, P points; w: P doubles), random
 * walk with steps K / sqrt(fs), ramp R t. */
static void boot_record(size_t n, double fs, const double *c, size_t P, const double *H,
                        double *w, gsl_rng *r, double *y)
{
    double Q = sqrt(c[0]), N = sqrt(c[1] * fs), B = sqrt(c[2]), K = sqrt(c[3] / fs);
    double R = sqrt(c[4]), u0 = Q > 0.0 ? gsl_ran_gaussian_ziggurat(r, 1.0) : 0.0, rw = 0.0;
    for (size_t i = 0; i < n; i++) {
        double v = R * (double)i / fs;
        if (Q > 0.0) {
            double u1 = gsl_ran_gaussian_ziggurat(r, 1.0);
            v += Q * (u1 - u0) * fs;
            u0 = u1;
        }
        if (N > 0.0)
            v += N * gsl_ran_gaussian_ziggurat(r, 1.0);
        if (K > 0.0) {
            rw += K * gsl_ran_gaussian_ziggurat(r, 1.0);
            v += rw;
        }
        y[i] = v;
    }
    if (!(B > 0.0))
        return;
    for (size_t k = 0; k < P; k++)
        w[k] = k < n ? gsl_ran_gaussian_ziggurat(r, 1.0) : 0.0;
    gsl_fft_real_radix2_transform(w, 1, P);
    w[0] *= H[0];
    w[P / 2] *= H[P / 2];
    for (size_t k = 1; k < P / 2; k++) { /* halfcomplex product */
        double ar = w[k], ai = w[P - k], br = H[k], bi = H[P - k];
        w[k] = ar * br - ai * bi;
        w[P - k] = ar * bi + ai * br;
    }
    gsl_fft_halfcomplex_radix2_inverse(w, 1, P);
    for (size_t i = 0; i < n; i++)
        y[i] += B * w[i];
}

/* The deviation of the kind at tau on the rate record y. */
static int boot_dev(int n, const double *y, double fs, int kind, int ntau, const double *tau,
                    double *dev)
{
    if (kind <= IGEA_STABILITY_ALLAN_NONOVERLAPPING)
        return igea_stability_allan(n, y, fs, ntau, tau, kind, IGEA_STABILITY_NOISE_WFM, 0.5, dev,
                                    NULL, NULL, NULL, NULL);
    return igea_stability_dev(n, y, fs, IGEA_STABILITY_DATA_FREQ, ntau, tau, kind,
                              IGEA_STABILITY_NOISE_WFM, 0.5, dev, NULL, NULL, NULL, NULL, NULL,
                              NULL);
}

/* Variance coefficients c of the maximum-likelihood fit of adev (workspace
 * buf of ntau (2 P_ + 4) doubles). */
static void fit_coef(int ntau, const double *tau, const double *adev, const double *edf,
                     double *buf, double *c)
{
    size_t m = (size_t)ntau;
    double *a = buf, *b = a + m * P_, *v = b + m, *sd = v + m, *w = sd + m, cs[P_];
    for (size_t j = 0; j < m; j++)
        v[j] = adev[j] * adev[j];
    fit_run(ntau, tau, v, edf, -1, sd, a, b, cs, w, c);
}

static int boot_check(int n, double fs, int kind, int ntau, const double *tau, int nboot,
                      int seed, double conf, const double *coef)
{
    if (n < 2)
        return -1;
    if (!(isfinite(fs) && fs > 0.0))
        return -2;
    if (kind != IGEA_STABILITY_ALLAN_OVERLAPPING && kind != IGEA_STABILITY_ALLAN_NONOVERLAPPING &&
        kind != IGEA_STABILITY_ALLAN_ADEV && kind != IGEA_STABILITY_ALLAN_OADEV &&
        kind != IGEA_STABILITY_ALLAN_TOTDEV)
        return -3;
    if (ntau < 5)
        return -4;
    if (!tau)
        return -5;
    for (int j = 0; j < ntau; j++) { /* m = round(tau fs) with at least one term */
        double v = tau[j] * fs;
        if (!(isfinite(v) && v >= 0.5 && v <= (double)n))
            return -5;
        long m = lround(v), cnt = kind == IGEA_STABILITY_ALLAN_OVERLAPPING ? n - 2 * m + 1
                                  : kind == IGEA_STABILITY_ALLAN_OADEV     ? n + 1 - 2 * m
                                  : kind == IGEA_STABILITY_ALLAN_TOTDEV    ? 1
                                                                           : n / m - 1;
        if (cnt < 1)
            return -5;
    }
    if (nboot < 2 || nboot > 1000000)
        return -8;
    if (seed < 0)
        return -9;
    if (!(conf > 0.0 && conf < 1.0))
        return -10;
    if (!coef)
        return -11;
    return 0;
}

/* The nboot bootstrap coefficients sqrt c, rep[b * P_ + k]. */
static int boot_loop(int n, double fs, int kind, int ntau, const double *tau, const double *edf,
                     int nboot, gsl_rng *r, const double *c, double *rep)
{
    size_t P = 2;
    while (P < 2 * (size_t)n)
        P *= 2;
    double *buf = igea__dalloc((size_t)n + 2 * P + (size_t)ntau * (2 * P_ + 5));
    if (!buf)
        return IGEA_ENOMEM;
    double *y = buf, *H = y + n, *w = H + P, *dev = w + P, *fb = dev + ntau, cb[P_];
    if (c[2] > 0.0)
        flicker_filter((size_t)n, P, H);
    int st = 0;
    for (int b = 0; b < nboot && !st; b++) {
        boot_record((size_t)n, fs, c, P, H, w, r, y);
        if ((st = boot_dev(n, y, fs, kind, ntau, tau, dev)))
            break;
        for (int j = 0; j < ntau && !st; j++)
            if (!(dev[j] > 0.0))
                st = IGEA_ENOCONV;
        if (st)
            break;
        fit_coef(ntau, tau, dev, edf, fb, cb);
        for (int k = 0; k < P_; k++)
            rep[(size_t)b * P_ + k] = cb[k] > 0.0 ? sqrt(cb[k]) : 0.0;
    }
    free(buf);
    return st;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Quantile p of the sorted v[n] (linear interpolation, Hyndman-Fan 7). */
static double quantile(int n, const double *v, double p)
{
    double h = (n - 1) * p, f = floor(h);
    int i = (int)f;
    return i + 1 < n ? v[i] + (h - f) * (v[i + 1] - v[i]) : v[n - 1];
}

/* se (sd of the replicas) and the interval [lo, hi] of term k from the
 * replicas rep (column k, stride P_; col: nboot doubles of workspace):
 * est^2 / q_{(1+conf)/2}, est^2 / q_{(1-conf)/2} of the replicas (the
 * ratio est / truth taken as pivotal), [0, q_{(1+conf)/2}] when est = 0. */
static void boot_summary(int nboot, const double *rep, int k, double est, double conf,
                         double *col, double *se, double *lo, double *hi)
{
    double mu = 0.0, ss = 0.0;
    for (int b = 0; b < nboot; b++) { /* Welford */
        double v = rep[(size_t)b * P_ + k], d = v - mu;
        col[b] = v;
        mu += d / (double)(b + 1);
        ss += d * (v - mu);
    }
    *se = sqrt(ss / (double)(nboot - 1));
    qsort(col, (size_t)nboot, sizeof(double), cmp_double);
    double qh = quantile(nboot, col, 0.5 * (1.0 + conf)), ql = quantile(nboot, col, 0.5 * (1.0 - conf));
    if (!(est > 0.0)) {
        *lo = 0.0;
        *hi = qh;
        return;
    }
    *lo = qh > 0.0 ? est * est / qh : 0.0;
    *hi = ql > 0.0 ? est * est / ql : INFINITY;
}

int igea_stability_fit_boot(int n, double fs, int kind, int ntau, const double *tau,
                            const double *adev, const double *edf, int nboot, int seed,
                            double conf, double *coef, double *se, double *lo, double *hi,
                            int *supported, double *chi2)
{
    int st = boot_check(n, fs, kind, ntau, tau, nboot, seed, conf, coef);
    if (st)
        return st;
    double out[P_], c2, c[P_], oe[P_], ol[P_], oh[P_];
    int sup[P_];
    st = igea_stability_fit(ntau, tau, adev, edf, out, NULL, sup, &c2);
    if (st) /* the fit's arguments 2, 3, 4 are ours 5, 6, 7 */
        return st >= -4 && st <= -2 ? st - 3 : st;
    for (int k = 0; k < P_; k++)
        c[k] = out[k] * out[k];
    double *rep = igea__dalloc((size_t)nboot * (P_ + 1));
    gsl_rng *r = rep ? igea__rng_new(gsl_rng_mt19937, (unsigned long)seed) : NULL;
    if (!r) {
        free(rep);
        return IGEA_ENOMEM;
    }
    st = boot_loop(n, fs, kind, ntau, tau, edf, nboot, r, c, rep);
    igea__rng_free(r);
    for (int k = 0; k < P_ && !st; k++)
        boot_summary(nboot, rep, k, out[k], conf, rep + (size_t)nboot * P_, &oe[k], &ol[k], &oh[k]);
    free(rep);
    if (st)
        return st == IGEA_ENOMEM ? st : IGEA_ENOCONV;
    memcpy(coef, out, sizeof out);
    if (se)
        memcpy(se, oe, sizeof oe);
    if (lo)
        memcpy(lo, ol, sizeof ol);
    if (hi)
        memcpy(hi, oh, sizeof oh);
    if (supported)
        memcpy(supported, sup, sizeof sup);
    if (chi2)
        *chi2 = c2;
    return 0;
}
