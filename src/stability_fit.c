/* stability_fit.c - IEEE Std 952 noise model fitted to a whole Allan
 * variance curve: weighted non-negative least squares with standard errors
 * (docs/stability.md). */
#include <float.h>

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
