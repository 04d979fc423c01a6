/* accel_history.c - priors from the calibration history: the random-effects
 * model b_i = beta0 + u_i + e_i, u_i ~ N(0, Sigma) (Sigma diagonal),
 * e_i ~ N(0, V_i), fitted by restricted maximum likelihood (EM), and a
 * calibration fit with that prior (docs/accel.md, "Priors from the
 * calibration history"). */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "igea/accel.h"
#include "igea/regress.h"
#include "internal.h"

#define HP_MAXP 10

/* In-place Cholesky of the p x p SPD matrix a (ld p) and its inverse into
 * inv; log det into *ld. Returns 0 or IGEA_ESINGULAR. */
static int spd_inverse(int p, double *a, double *inv, double *ld)
{
    if (igea__chol_lower(p, a, p, 0.0) != 0)
        return IGEA_ESINGULAR;
    double s = 0.0;
    for (int j = 0; j < p; j++)
        s += 2.0 * log(a[j + j * p]);
    *ld = s;
    for (int c = 0; c < p; c++) { /* solve L L^T x = e_c */
        double x[HP_MAXP];
        for (int i = 0; i < p; i++) {
            double t = i == c ? 1.0 : 0.0;
            for (int k = 0; k < i; k++)
                t -= a[i + k * p] * x[k];
            x[i] = t / a[i + i * p];
        }
        for (int i = p - 1; i >= 0; i--) {
            double t = x[i];
            for (int k = i + 1; k < p; k++)
                t -= a[k + i * p] * x[k];
            x[i] = t / a[i + i * p];
        }
        for (int i = 0; i < p; i++)
            inv[i + c * p] = x[i];
    }
    return 0;
}

typedef struct {
    int m, p, ldb, ldv;
    const double *b, *V;
    double *W;        /* m blocks p x p: (Sigma + V_i)^-1 */
    double S[HP_MAXP * HP_MAXP], Sinv[HP_MAXP * HP_MAXP], beta[HP_MAXP];
    double loglik;
} hp_state;

/* W_i, S = sum W_i, beta0 = S^-1 sum W_i b_i, the REML log-likelihood. */
static int hp_weights(hp_state *h, const double *tau2)
{
    int p = h->p;
    double a[HP_MAXP * HP_MAXP], r[HP_MAXP] = {0}, ld, ldS, q = 0.0, lsum = 0.0;
    memset(h->S, 0, sizeof h->S);
    for (int i = 0; i < h->m; i++) {
        const double *Vi = h->V + (size_t)i * h->ldv * p;
        double *Wi = h->W + (size_t)i * p * p;
        for (int c = 0; c < p; c++)
            for (int k = 0; k < p; k++)
                a[k + c * p] = Vi[k + (size_t)c * h->ldv] + (k == c ? tau2[k] : 0.0);
        if (spd_inverse(p, a, Wi, &ld))
            return IGEA_ESINGULAR;
        lsum += ld;
        const double *bi = h->b + (size_t)i * h->ldb;
        for (int k = 0; k < p * p; k++)
            h->S[k] += Wi[k];
        for (int k = 0; k < p; k++)
            for (int c = 0; c < p; c++)
                r[k] += Wi[k + c * p] * bi[c];
    }
    memcpy(a, h->S, sizeof(double) * p * p);
    if (spd_inverse(p, a, h->Sinv, &ldS))
        return IGEA_ESINGULAR;
    for (int k = 0; k < p; k++) {
        double t = 0.0;
        for (int c = 0; c < p; c++)
            t += h->Sinv[k + c * p] * r[c];
        h->beta[k] = t;
    }
    for (int i = 0; i < h->m; i++) {
        const double *bi = h->b + (size_t)i * h->ldb, *Wi = h->W + (size_t)i * p * p;
        for (int k = 0; k < p; k++)
            for (int c = 0; c < p; c++)
                q += (bi[k] - h->beta[k]) * Wi[k + c * p] * (bi[c] - h->beta[c]);
    }
    h->loglik = -0.5 * (lsum + ldS + q);
    return 0;
}

/* One EM step: tau2_new_j = mean_i (uhat_ij^2 + C_i,jj), uhat_i =
 * Sigma W_i (b_i - beta0), C_i = Sigma - Sigma W_i Sigma + Sigma W_i S^-1
 * W_i Sigma. */
static void hp_em(const hp_state *h, const double *tau2, double *out)
{
    int p = h->p;
    for (int k = 0; k < p; k++)
        out[k] = 0.0;
    for (int i = 0; i < h->m; i++) {
        const double *bi = h->b + (size_t)i * h->ldb, *Wi = h->W + (size_t)i * p * p;
        for (int k = 0; k < p; k++) {
            double u = 0.0, g[HP_MAXP], q = 0.0;
            for (int c = 0; c < p; c++) {
                u += Wi[k + c * p] * (bi[c] - h->beta[c]);
                g[c] = Wi[c + k * p]; /* row k of W_i (symmetric) */
            }
            u *= tau2[k];
            for (int c = 0; c < p; c++)
                for (int d = 0; d < p; d++)
                    q += g[c] * h->Sinv[c + d * p] * g[d];
            double cv = tau2[k] - tau2[k] * Wi[k + k * p] * tau2[k] + tau2[k] * q * tau2[k];
            out[k] += u * u + cv;
        }
    }
    for (int k = 0; k < p; k++)
        out[k] /= h->m;
}

static int hist_check(int m, int p, const double *b, int ldb, const double *V, int ldv,
                      int max_iter, double tol, const double *beta0, const double *tau,
                      const double *cov0, int ldc)
{
    if (m < 2)
        return -1;
    if (p < 1 || p > HP_MAXP)
        return -2;
    if (!b)
        return -3;
    if (ldb < p)
        return -4;
    if (!V)
        return -5;
    if (ldv < p)
        return -6;
    if (max_iter < 1)
        return -7;
    if (!(tol > 0.0 && tol < 1.0))
        return -8;
    if (!beta0)
        return -9;
    if (!tau)
        return -10;
    if (cov0 ? ldc < p : ldc < 1)
        return -12;
    for (int i = 0; i < m; i++)
        if (!igea__finite_vec(p, b + (size_t)i * ldb, 1) ||
            !igea__finite_mat(p, p, V + (size_t)i * ldv * p, ldv))
            return IGEA_ENONFINITE;
    return 0;
}

/* Start: tau2 = max(sample variance - mean V_jj, mean V_jj / 100). */
static void hp_start(const hp_state *h, double *tau2, double *vbar)
{
    for (int k = 0; k < h->p; k++) {
        double mu = 0.0, ss = 0.0, vm = 0.0;
        for (int i = 0; i < h->m; i++)
            mu += h->b[k + (size_t)i * h->ldb];
        mu /= h->m;
        for (int i = 0; i < h->m; i++) {
            double d = h->b[k + (size_t)i * h->ldb] - mu;
            ss += d * d;
            vm += h->V[k + (size_t)k * h->ldv + (size_t)i * h->ldv * h->p];
        }
        vm /= h->m;
        vbar[k] = vm > 0.0 ? vm : DBL_MIN;
        tau2[k] = fmax(ss / (h->m - 1) - vm, vbar[k] / 100.0);
        if (!(tau2[k] > 0.0))
            tau2[k] = DBL_MIN;
    }
}

int igea_accel_history(int m, int p, const double *b, int ldb, const double *V, int ldv,
                       int max_iter, double tol, double *beta0, double *tau, double *cov0,
                       int ldc, double *info)
{
    int st = hist_check(m, p, b, ldb, V, ldv, max_iter, tol, beta0, tau, cov0, ldc);
    if (st)
        return st;
    hp_state h = {m, p, ldb, ldv, b, V, igea__dalloc((size_t)m * p * p), {0}, {0}, {0}, 0.0};
    if (!h.W)
        return IGEA_ENOMEM;
    double t2[HP_MAXP], nt[HP_MAXP], vbar[HP_MAXP];
    int it = 0, done = 0;
    double prev = -HUGE_VAL;
    hp_start(&h, t2, vbar);
    while (!st && !done && it < max_iter) {
        st = hp_weights(&h, t2);
        if (st)
            break;
        /* EM increases the likelihood monotonically; near tau_j = 0 it
         * creeps: stop when an iteration gains less than tol */
        if (h.loglik - prev < tol) {
            done = 1;
            break;
        }
        prev = h.loglik;
        hp_em(&h, t2, nt);
        it++;
        done = 1;
        for (int k = 0; k < p; k++) {
            if (fabs(sqrt(nt[k]) - sqrt(t2[k])) > tol * sqrt(vbar[k]))
                done = 0;
            t2[k] = nt[k] > 0.0 ? nt[k] : DBL_MIN;
        }
    }
    if (!st)
        st = done ? hp_weights(&h, t2) : IGEA_ENOCONV;
    if (!st && (!igea__finite_vec(p, h.beta, 1) || !isfinite(h.loglik)))
        st = IGEA_EOVERFLOW;
    if (!st) {
        memcpy(beta0, h.beta, (size_t)p * sizeof(double));
        for (int k = 0; k < p; k++)
            tau[k] = sqrt(t2[k]);
        if (cov0) /* the prior of a new instrument: Sigma + Cov(beta0 hat) */
            for (int c = 0; c < p; c++)
                for (int k = 0; k < p; k++)
                    cov0[k + (size_t)c * ldc] = h.Sinv[k + c * p] + (k == c ? t2[k] : 0.0);
        if (info) {
            info[IGEA_ACCEL_HIST_LOGLIK] = h.loglik;
            info[IGEA_ACCEL_HIST_ITER] = it;
        }
    }
    free(h.W);
    return st;
}

/* ---------------------------------------------------------------------- */

static int fp_check(int model, int n, const double *theta_deg, const double *ya,
                    const double *yb, const double *prior_mean, const double *prior_cov,
                    int ldp, const double *coef, const double *cov, int ldc)
{
    if (model != IGEA_ACCEL_SINGLE && model != IGEA_ACCEL_DUAL)
        return -1;
    if (n < 1)
        return -2;
    if (!theta_deg)
        return -3;
    if (!ya)
        return -4;
    if (model == IGEA_ACCEL_DUAL && !yb)
        return -5;
    int np = model == IGEA_ACCEL_DUAL ? IGEA_ACCEL_NP_DUAL : IGEA_ACCEL_NP_SINGLE;
    if (!prior_mean)
        return -6;
    if (!prior_cov)
        return -7;
    if (ldp < np)
        return -8;
    if (!coef)
        return -9;
    if (cov ? ldc < np : ldc < 1)
        return -12;
    if (!igea__finite_vec(n, theta_deg, 1) || !igea__finite_vec(n, ya, 1) ||
        (model == IGEA_ACCEL_DUAL && !igea__finite_vec(n, yb, 1)) ||
        !igea__finite_vec(np, prior_mean, 1) || !igea__finite_mat(np, np, prior_cov, ldp))
        return IGEA_ENONFINITE;
    return 0;
}

int igea_accel_fit_prior(int model, int n, const double *theta_deg, const double *ya,
                         const double *yb, const double *prior_mean, const double *prior_cov,
                         int ldp, double *coef, double *sd, double *cov, int ldc,
                         double *info)
{
    int st = fp_check(model, n, theta_deg, ya, yb, prior_mean, prior_cov, ldp, coef, cov, ldc);
    if (st)
        return st;
    int np = model == IGEA_ACCEL_DUAL ? IGEA_ACCEL_NP_DUAL : IGEA_ACCEL_NP_SINGLE, rank = 0;
    size_t nn = (size_t)n;
    double *A = igea__dalloc(nn * np + 3 * nn);
    if (!A)
        return IGEA_ENOMEM;
    double *y = A + nn * np, *sig = y + nn, *res = sig + nn;
    double x[HP_MAXP], cv[HP_MAXP * HP_MAXP], s2 = 0.0;
    st = igea_accel_design(model, n, theta_deg, A, n);
    if (!st)
        st = igea_accel_observe(model, n, theta_deg, ya, yb, y);
    /* sigma from the least-squares residual, then the posterior */
    if (!st)
        st = igea_regress_ls(n, np, A, n, y, NULL, NULL, 0.0, x, NULL, 1, &rank, &s2, NULL);
    if (!st && (n <= rank || !(s2 > 0.0)))
        st = IGEA_EDOMAIN;
    for (size_t i = 0; !st && i < nn; i++)
        sig[i] = sqrt(s2);
    if (!st)
        st = igea_regress_bayes(n, np, A, n, y, sig, NULL, prior_mean, prior_cov, ldp, x, cv,
                                np, res);
    if (!st && (!igea__finite_vec(np, x, 1) || !igea__finite_vec(np * np, cv, 1)))
        st = IGEA_EOVERFLOW;
    if (!st) {
        memcpy(coef, x, (size_t)np * sizeof(double));
        for (int j = 0; j < np; j++) {
            if (sd)
                sd[j] = sqrt(fmax(cv[j + j * np], 0.0));
            if (cov)
                memcpy(cov + (size_t)j * ldc, cv + (size_t)j * np, (size_t)np * sizeof(double));
        }
        if (info) {
            double rss = 0.0;
            for (size_t i = 0; i < nn; i++)
                rss += res[i] * res[i];
            for (int k = 0; k < IGEA_ACCEL_INFO_LEN; k++)
                info[k] = 0.0;
            info[IGEA_ACCEL_INFO_RANK] = rank;
            info[IGEA_ACCEL_INFO_SIGMA] = sqrt(s2);
            info[IGEA_ACCEL_INFO_RMS] = sqrt(rss / n);
            info[IGEA_ACCEL_INFO_NOBS] = n;
            info[IGEA_ACCEL_INFO_DOF] = n - rank;
        }
    }
    free(A);
    return st;
}
