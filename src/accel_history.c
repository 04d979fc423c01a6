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

/* W_i = (Sigma + V_i)^-1 (Sig p x p), S = sum W_i, beta0 = S^-1 sum W_i
 * b_i, the REML log-likelihood. */
static int hp_weights(hp_state *h, const double *Sig)
{
    int p = h->p;
    double a[HP_MAXP * HP_MAXP], r[HP_MAXP] = {0}, ld, ldS, q = 0.0, lsum = 0.0;
    memset(h->S, 0, sizeof h->S);
    for (int i = 0; i < h->m; i++) {
        const double *Vi = h->V + (size_t)i * h->ldv * p;
        double *Wi = h->W + (size_t)i * p * p;
        for (int c = 0; c < p; c++)
            for (int k = 0; k < p; k++)
                a[k + c * p] = Vi[k + (size_t)c * h->ldv] + Sig[k + c * p];
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

/* One EM step (beta0 integrated out): out = mean_i (uhat_i uhat_i^T + C_i),
 * uhat_i = Sigma W_i (b_i - beta0), C_i = Sigma - G_i Sigma + G_i S^-1 G_i^T,
 * G_i = Sigma W_i (all p x p). */
static void hp_em(const hp_state *h, const double *Sig, double *out)
{
    int p = h->p;
    double G[HP_MAXP * HP_MAXP], T[HP_MAXP * HP_MAXP], u[HP_MAXP], r[HP_MAXP];
    memset(out, 0, sizeof(double) * p * p);
    for (int i = 0; i < h->m; i++) {
        const double *bi = h->b + (size_t)i * h->ldb, *Wi = h->W + (size_t)i * p * p;
        for (int k = 0; k < p; k++)
            r[k] = bi[k] - h->beta[k];
        for (int k = 0; k < p; k++)
            for (int c = 0; c < p; c++) {
                double t = 0.0;
                for (int d = 0; d < p; d++)
                    t += Sig[k + d * p] * Wi[d + c * p];
                G[k + c * p] = t;
            }
        for (int k = 0; k < p; k++) {
            double t = 0.0;
            for (int c = 0; c < p; c++)
                t += G[k + c * p] * r[c];
            u[k] = t;
        }
        for (int k = 0; k < p; k++) /* T = G S^-1 - Sigma... row k of G (S^-1 G^T - Sigma) */
            for (int c = 0; c < p; c++) {
                double t = 0.0;
                for (int d = 0; d < p; d++)
                    t += h->Sinv[k + d * p] * G[c + d * p];
                T[k + c * p] = t - Sig[k + c * p]; /* (S^-1 G^T - Sigma)_kc */
            }
        for (int k = 0; k < p; k++)
            for (int c = 0; c < p; c++) {
                double t = 0.0;
                for (int d = 0; d < p; d++)
                    t += G[k + d * p] * T[d + c * p];
                out[k + c * p] += u[k] * u[c] + Sig[k + c * p] + t;
            }
    }
    for (int k = 0; k < p * p; k++)
        out[k] /= h->m;
    for (int k = 0; k < p; k++) /* symmetric to rounding */
        for (int c = 0; c < k; c++)
            out[k + c * p] = out[c + k * p] = 0.5 * (out[k + c * p] + out[c + k * p]);
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

/* EM from the start of hp_start until converged (full: Sigma p x p, else
 * diagonal); h->beta, h->Sinv, h->loglik at the result. Returns 0,
 * IGEA_ESINGULAR, IGEA_ENOCONV. */
static int hp_run(hp_state *h, int full, int max_iter, double tol, double *Sig, int *iters)
{
    int p = h->p, it = 0, done = 0, st = 0;
    double t2[HP_MAXP], vbar[HP_MAXP], nw[HP_MAXP * HP_MAXP], prev = -HUGE_VAL;
    hp_start(h, t2, vbar);
    memset(Sig, 0, sizeof(double) * p * p);
    for (int k = 0; k < p; k++)
        Sig[k + k * p] = t2[k];
    while (!done && it < max_iter) {
        if ((st = hp_weights(h, Sig)))
            return st;
        /* EM raises the likelihood monotonically; towards a boundary
         * estimate (tau_j = 0) it creeps: stop when a step gains < tol */
        if (h->loglik - prev < tol)
            break;
        prev = h->loglik;
        hp_em(h, Sig, nw);
        it++;
        done = 1;
        for (int k = 0; k < p; k++)
            for (int c = 0; c < p; c++) {
                double *o = Sig + k + c * p, x = k == c || full ? nw[k + c * p] : 0.0;
                if (k == c) {
                    x = x > 0.0 ? x : DBL_MIN;
                    if (fabs(sqrt(x) - sqrt(*o)) > tol * sqrt(vbar[k]))
                        done = 0;
                } else if (fabs(x - *o) > tol * sqrt(vbar[k] * vbar[c])) {
                    done = 0;
                }
                *o = x;
            }
    }
    *iters = it;
    if (it >= max_iter && !done)
        return IGEA_ENOCONV;
    return hp_weights(h, Sig);
}

/* Both entry points: Sig_out (p x p, lds) or tau (p) of the estimate. */
static int hp_fit(int m, int p, const double *b, int ldb, const double *V, int ldv,
                  int max_iter, double tol, int full, double *beta0, double *tau,
                  double *Sig_out, int lds, double *prior_cov, int ldc, double *info)
{
    hp_state h = {m, p, ldb, ldv, b, V, igea__dalloc((size_t)m * p * p), {0}, {0}, {0}, 0.0};
    if (!h.W)
        return IGEA_ENOMEM;
    double Sig[HP_MAXP * HP_MAXP];
    int it = 0;
    int st = hp_run(&h, full, max_iter, tol, Sig, &it);
    if (!st && (!igea__finite_vec(p, h.beta, 1) || !isfinite(h.loglik) ||
                !igea__finite_vec(p * p, Sig, 1)))
        st = IGEA_EOVERFLOW;
    if (!st) {
        memcpy(beta0, h.beta, (size_t)p * sizeof(double));
        for (int c = 0; c < p; c++) {
            if (tau)
                tau[c] = sqrt(Sig[c + c * p]);
            if (Sig_out)
                memcpy(Sig_out + (size_t)c * lds, Sig + c * p, (size_t)p * sizeof(double));
            if (prior_cov) /* the prior of a new instrument: Sigma + Cov(beta0 hat) */
                for (int k = 0; k < p; k++)
                    prior_cov[k + (size_t)c * ldc] = h.Sinv[k + c * p] + Sig[k + c * p];
        }
        if (info) {
            info[IGEA_ACCEL_HIST_LOGLIK] = h.loglik;
            info[IGEA_ACCEL_HIST_ITER] = it;
        }
    }
    free(h.W);
    return st;
}

int igea_accel_history(int m, int p, const double *b, int ldb, const double *V, int ldv,
                       int max_iter, double tol, double *beta0, double *tau, double *cov0,
                       int ldc, double *info)
{
    int st = hist_check(m, p, b, ldb, V, ldv, max_iter, tol, beta0, tau, cov0, ldc);
    if (st)
        return st;
    return hp_fit(m, p, b, ldb, V, ldv, max_iter, tol, 0, beta0, tau, NULL, 1, cov0, ldc,
                  info);
}

int igea_accel_history_full(int m, int p, const double *b, int ldb, const double *V, int ldv,
                            int max_iter, double tol, double *beta0, double *sigma_u,
                            int lds, double *prior_cov, int ldc, double *info)
{
    int st = hist_check(m, p, b, ldb, V, ldv, max_iter, tol, beta0, sigma_u, prior_cov, ldc);
    if (st)
        return st == -12 ? -13 : st;
    if (lds < p)
        return -11;
    return hp_fit(m, p, b, ldb, V, ldv, max_iter, tol, 1, beta0, NULL, sigma_u, lds, prior_cov,
                  ldc, info);
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
