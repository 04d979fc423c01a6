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
#include "igea/stats.h"
#include "internal.h"

#define HP_MAXP 10

/* The inverse of the k x k SPD matrix a (destroyed) into inv; work k
 * doubles. Returns 0 or IGEA_ESINGULAR. */
static int spd_inv(int k, double *a, double *inv, double *work)
{
    if (igea__chol_lower(k, a, k, 0.0) != 0)
        return IGEA_ESINGULAR;
    for (int c = 0; c < k; c++) {
        for (int i = 0; i < k; i++) {
            double t = i == c ? 1.0 : 0.0;
            for (int l = 0; l < i; l++)
                t -= a[i + l * k] * work[l];
            work[i] = t / a[i + i * k];
        }
        for (int i = k - 1; i >= 0; i--) {
            double t = work[i];
            for (int l = i + 1; l < k; l++)
                t -= a[l + i * k] * work[l];
            work[i] = t / a[i + i * k];
        }
        for (int i = 0; i < k; i++)
            inv[i + c * k] = work[i];
    }
    return 0;
}

/* In-place Cholesky of the p x p SPD matrix a (ld p) and its inverse into
 * inv; log det into *ld. Returns 0 or IGEA_ESINGULAR. */
static int spd_inverse(int p, double *a, double *inv, double *ld)
{
    double x[HP_MAXP];
    if (spd_inv(p, a, inv, x) != 0)
        return IGEA_ESINGULAR;
    double s = 0.0;
    for (int j = 0; j < p; j++)
        s += 2.0 * log(a[j + j * p]);
    *ld = s;
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

/* Arguments 1-5 of a fit on one calibration's readings (model, n,
 * theta_deg, ya, yb): 0 or -1 .. -5. */
static int readings_check(int model, int n, const double *theta_deg, const double *ya,
                          const double *yb)
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
    return 0;
}

static int fp_check(int model, int n, const double *theta_deg, const double *ya,
                    const double *yb, const double *prior_mean, const double *prior_cov,
                    int ldp, const double *coef, const double *cov, int ldc)
{
    int st0 = readings_check(model, n, theta_deg, ya, yb);
    if (st0)
        return st0;
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

/* ---------------------------------------------------------------------- */
/* The fit with the uncertainty of the estimated prior (docs/accel.md,
 * "The uncertainty of the estimated prior"). Notation: p coefficients; the
 * q variance parameters theta_a = Sigma_{k_a l_a} (k_a >= l_a; the diagonal
 * only, q = p, for a diagonal Sigma); D_a = dSigma/dtheta_a (1 at (k, l) and
 * (l, k)); W_i = (Sigma + V_i)^-1, Q = (sum W_i)^-1, P = Sigma + Q. */

#define HF_MAXQ (HP_MAXP * (HP_MAXP + 1) / 2)
#define HF_FLOOR 0.2 /* smallest bias factor f (the correction at most 1/0.2) */

typedef struct {
    int m, p, q, full, nus;
    const double *b, *V;
    int ldb, ldv;
    double M[HP_MAXP * HP_MAXP], My[HP_MAXP]; /* A^T A / s2 and A^T y / s2 at s2 = 1 */
    int dk[HF_MAXQ], dl[HF_MAXQ];
    double *W, *K4, *K4Z, *F, *Pa, *Ft, *Pt, *Et, *tmp, *I, *Ii, *Iw, *g, *d, *vq;
} hf_work;

typedef struct {
    double t[HP_MAXP], C[HP_MAXP * HP_MAXP], mse[HP_MAXP * HP_MAXP], f[HP_MAXP];
    double Lam[HP_MAXP * HP_MAXP], B[HP_MAXP * HP_MAXP];
    int capped;
} hf_out;

/* c = a b for p x p column-major matrices (c distinct from a and b);
 * ta / tb: use a^T / b^T. */
static void mm(int p, const double *a, int ta, const double *b, int tb, double *c)
{
    for (int j = 0; j < p; j++)
        for (int i = 0; i < p; i++) {
            double s = 0.0;
            for (int k = 0; k < p; k++)
                s += (ta ? a[k + i * p] : a[i + k * p]) * (tb ? b[j + k * p] : b[k + j * p]);
            c[i + j * p] = s;
        }
}

/* The directions: Sigma_kk (diagonal); Sigma_kl, k >= l, by columns (full). */
static void hf_dirs(hf_work *h)
{
    int a = 0;
    for (int l = 0; l < h->p; l++)
        for (int k = l; k < (h->full ? h->p : l + 1); k++, a++)
            h->dk[a] = k, h->dl[a] = l;
    h->q = a;
}

/* The expected REML information of theta at Sigma (Sig, p x p), with the
 * weights W_i, Q, beta0 and the per-direction sums F_a = sum W_i D_a W_i and
 * g_a = sum W_i D_a W_i (b_i - beta0) left in h (Q, beta0 out). */
static int hf_info(hf_work *h, const double *Sig, double *Q, double *beta0)
{
    int p = h->p, m = h->m, q = h->q, st;
    size_t pp = (size_t)p * p, p4 = pp * pp;
    double a[HP_MAXP * HP_MAXP], S[HP_MAXP * HP_MAXP] = {0}, r[HP_MAXP] = {0}, ld;
    for (int i = 0; i < m; i++) {
        const double *Vi = h->V + (size_t)i * h->ldv * p;
        double *Wi = h->W + i * pp;
        for (int c = 0; c < p; c++)
            for (int k = 0; k < p; k++)
                a[k + c * p] = Vi[k + (size_t)c * h->ldv] + Sig[k + c * p];
        if ((st = spd_inverse(p, a, Wi, &ld)))
            return st;
        const double *bi = h->b + (size_t)i * h->ldb;
        for (size_t k = 0; k < pp; k++)
            S[k] += Wi[k];
        for (int k = 0; k < p; k++)
            for (int c = 0; c < p; c++)
                r[k] += Wi[k + c * p] * bi[c];
    }
    memcpy(a, S, sizeof(double) * pp);
    if ((st = spd_inverse(p, a, Q, &ld)))
        return st;
    for (int k = 0; k < p; k++) {
        double t = 0.0;
        for (int c = 0; c < p; c++)
            t += Q[k + c * p] * r[c];
        beta0[k] = t;
    }
    memset(h->K4, 0, sizeof(double) * p4);
    memset(h->K4Z, 0, sizeof(double) * p4);
    memset(h->g, 0, sizeof(double) * (size_t)q * p);
    for (int i = 0; i < m; i++) {
        const double *Wi = h->W + i * pp, *bi = h->b + (size_t)i * h->ldb;
        double Z[HP_MAXP * HP_MAXP], u[HP_MAXP], e[HP_MAXP];
        mm(p, Q, 0, Wi, 0, a);
        mm(p, Wi, 0, a, 0, Z); /* W Q W */
        for (int k = 0; k < p; k++)
            e[k] = bi[k] - beta0[k];
        for (int k = 0; k < p; k++) {
            double t = 0.0;
            for (int c = 0; c < p; c++)
                t += Wi[k + c * p] * e[c];
            u[k] = t;
        }
        /* K4[t,k,l,s] += W[t,k] W[l,s], K4Z[t,k,l,s] += W[t,k] Z[l,s] */
        for (size_t ls = 0; ls < pp; ls++) {
            double wl = Wi[ls], zl = Z[ls];
            double *k4 = h->K4 + ls * pp, *k4z = h->K4Z + ls * pp;
            for (size_t tk = 0; tk < pp; tk++) {
                k4[tk] += Wi[tk] * wl;
                k4z[tk] += Wi[tk] * zl;
            }
        }
        for (int x = 0; x < q; x++) { /* g_a += W D_a W (b_i - beta0) */
            int k = h->dk[x], l = h->dl[x];
            double *gx = h->g + (size_t)x * p;
            for (int c = 0; c < p; c++)
                gx[c] += Wi[c + k * p] * u[l] + (k != l ? Wi[c + l * p] * u[k] : 0.0);
        }
    }
#define K4AT(K, t_, k_, l_, s_) (K)[(t_) + (size_t)p * ((k_) + (size_t)p * ((l_) + (size_t)p * (s_)))]
    for (int x = 0; x < q; x++) { /* F_a[r,c] = sum over (k,l) in a of K4[r,k,l,c] */
        int k = h->dk[x], l = h->dl[x];
        double *Fx = h->F + x * pp;
        for (int c = 0; c < p; c++)
            for (int rr = 0; rr < p; rr++)
                Fx[rr + c * p] = K4AT(h->K4, rr, k, l, c) + (k != l ? K4AT(h->K4, rr, l, k, c) : 0.0);
    }
    for (int x = 0; x < q; x++) /* Q F_a into tmp */
        mm(p, Q, 0, h->F + x * pp, 0, h->tmp + x * pp);
    for (int x = 0; x < q; x++)
        for (int y = 0; y <= x; y++) {
            int ka = h->dk[x], la = h->dl[x], kb = h->dk[y], lb = h->dl[y];
            int pa[2][2] = {{ka, la}, {la, ka}}, pb[2][2] = {{kb, lb}, {lb, kb}};
            int na = ka != la ? 2 : 1, nb = kb != lb ? 2 : 1;
            double t1 = 0.0, t2 = 0.0, t3 = 0.0;
            for (int u = 0; u < na; u++)
                for (int v = 0; v < nb; v++) { /* tr(X e_k e_l' Y e_s e_t') = X[t,k] Y[l,s] */
                    int kk = pa[u][0], ll = pa[u][1], ss = pb[v][0], tt = pb[v][1];
                    t1 += K4AT(h->K4, tt, kk, ll, ss);
                    t2 += K4AT(h->K4Z, tt, kk, ll, ss);
                }
            const double *X = h->tmp + x * pp, *Y = h->tmp + y * pp;
            for (int c = 0; c < p; c++)
                for (int rr = 0; rr < p; rr++)
                    t3 += X[rr + c * p] * Y[c + rr * p];
            h->I[x + (size_t)y * q] = h->I[y + (size_t)x * q] = 0.5 * (t1 - 2.0 * t2 + t3);
        }
#undef K4AT
    return 0;
}

/* Workspace of hf_work for m calibrations of p coefficients, q parameters. */
static double *hf_alloc(hf_work *h)
{
    size_t pp = (size_t)h->p * h->p, q = (size_t)h->q;
    double *w = igea__dalloc((size_t)h->m * pp + 2 * pp * pp + 6 * q * pp + 3 * q * q +
                             2 * q * h->p + q);
    if (!w)
        return NULL;
    h->W = w, h->K4 = h->W + (size_t)h->m * pp, h->K4Z = h->K4 + pp * pp;
    h->F = h->K4Z + pp * pp, h->Pa = h->F + q * pp, h->Ft = h->Pa + q * pp;
    h->Pt = h->Ft + q * pp, h->Et = h->Pt + q * pp, h->tmp = h->Et + q * pp;
    h->I = h->tmp + q * pp, h->Ii = h->I + q * q, h->Iw = h->Ii + q * q;
    h->g = h->Iw + q * q, h->d = h->g + q * h->p, h->vq = h->d + q * h->p;
    return w;
}

/* I^-1 into h->Ii. */
static int hf_invert_info(hf_work *h)
{
    memcpy(h->Iw, h->I, sizeof(double) * (size_t)h->q * h->q);
    return spd_inv(h->q, h->Iw, h->Ii, h->vq);
}

/*
 * The posterior at (Sigma, s2) and its corrections (docs/accel.md):
 * C = (A^T A / s2 + P^-1)^-1, t = C (A^T y / s2 + P^-1 beta0), R = C P^-1,
 * P_a = dP/dtheta_a = D_a + Q F_a Q;
 *  Lambda = sum_ab I^ab d_a d_b^T + (2 s2^2 / nus) d_s d_s^T, the observed
 *    derivatives d_a = dt/dtheta_a = R (P_a P^-1 (t - beta0) - Q g_a) and
 *    d_s = dt/ds2 = -C A^T (y - A t) / s2^2;
 *  B = (1/2) sum_ab I^ab d2C/dtheta_a dtheta_b + (1/2) Var(s2) d2C/ds2^2
 *    = (1/2) [R Y R^T + (R Y R^T)^T + R Q (X + X^T - 2 H) Q R^T]
 *      - (2 / nus) C M C P^-1 C (symmetrised), M = A^T A / s2,
 *    Y = sum_a Pt_a (R^T - I) P^-1 P_a, X = sum_a Ft_a Q F_a,
 *    H = sum_i W_i (sum_a D_a W_i Et_a) W_i (tilde: sum_b I^ab ...);
 *  f_j = max((C_jj + B_jj) / C_jj, HF_FLOOR),
 *  mse_jk = (C_jk + Lambda_jk) / sqrt(f_j f_k).
 */
static int hf_eval(hf_work *h, const double *Sig, double s2, hf_out *o)
{
    int p = h->p, q = h->q, st;
    size_t pp = (size_t)p * p;
    double Q[HP_MAXP * HP_MAXP], beta0[HP_MAXP], P[HP_MAXP * HP_MAXP], Pi[HP_MAXP * HP_MAXP];
    double a[HP_MAXP * HP_MAXP], b[HP_MAXP * HP_MAXP], c[HP_MAXP * HP_MAXP], R[HP_MAXP * HP_MAXP];
    double Y[HP_MAXP * HP_MAXP] = {0}, X[HP_MAXP * HP_MAXP] = {0}, H[HP_MAXP * HP_MAXP] = {0};
    double z[HP_MAXP], v[HP_MAXP], ds[HP_MAXP], ld;
    double *C = o->C;
    if ((st = hf_info(h, Sig, Q, beta0)) || (st = hf_invert_info(h)))
        return st;
    for (size_t k = 0; k < pp; k++)
        a[k] = Sig[k] + Q[k];
    memcpy(P, a, sizeof P);
    if ((st = spd_inverse(p, a, Pi, &ld)))
        return st;
    for (size_t k = 0; k < pp; k++)
        a[k] = h->M[k] / s2 + Pi[k];
    if ((st = spd_inverse(p, a, C, &ld)))
        return st;
    for (int k = 0; k < p; k++) {
        double s = 0.0;
        for (int l = 0; l < p; l++)
            s += Pi[k + l * p] * beta0[l];
        v[k] = h->My[k] / s2 + s;
    }
    for (int k = 0; k < p; k++) {
        double s = 0.0;
        for (int l = 0; l < p; l++)
            s += C[k + l * p] * v[l];
        o->t[k] = s;
    }
    mm(p, C, 0, Pi, 0, R);
    for (int x = 0; x < q; x++) { /* P_a = D_a + Q F_a Q */
        double *Px = h->Pa + x * pp;
        mm(p, Q, 0, h->F + x * pp, 0, a);
        mm(p, a, 0, Q, 0, Px);
        Px[h->dk[x] + h->dl[x] * p] += 1.0;
        if (h->dk[x] != h->dl[x])
            Px[h->dl[x] + h->dk[x] * p] += 1.0;
    }
    for (int x = 0; x < q; x++) { /* the tilde sums */
        double *Ftx = h->Ft + x * pp, *Ptx = h->Pt + x * pp, *Etx = h->Et + x * pp;
        memset(Ftx, 0, sizeof(double) * pp);
        memset(Ptx, 0, sizeof(double) * pp);
        memset(Etx, 0, sizeof(double) * pp);
        for (int y = 0; y < q; y++) {
            double w = h->Ii[x + (size_t)y * q];
            const double *Fy = h->F + y * pp, *Py = h->Pa + y * pp;
            for (size_t k = 0; k < pp; k++)
                Ftx[k] += w * Fy[k], Ptx[k] += w * Py[k];
            Etx[h->dk[y] + h->dl[y] * p] += w;
            if (h->dk[y] != h->dl[y])
                Etx[h->dl[y] + h->dk[y] * p] += w;
        }
    }
    /* Lambda: the observed derivatives of t */
    for (int k = 0; k < p; k++)
        v[k] = o->t[k] - beta0[k];
    for (int k = 0; k < p; k++) {
        double s = 0.0;
        for (int l = 0; l < p; l++)
            s += Pi[k + l * p] * v[l];
        z[k] = s;
    }
    for (int x = 0; x < q; x++) {
        const double *Px = h->Pa + x * pp, *gx = h->g + (size_t)x * p;
        double w[HP_MAXP];
        for (int k = 0; k < p; k++) {
            double s = 0.0;
            for (int l = 0; l < p; l++)
                s += Px[k + l * p] * z[l] - Q[k + l * p] * gx[l];
            w[k] = s;
        }
        for (int k = 0; k < p; k++) {
            double s = 0.0;
            for (int l = 0; l < p; l++)
                s += R[k + l * p] * w[l];
            h->d[(size_t)x * p + k] = s;
        }
    }
    for (int k = 0; k < p; k++) { /* A^T (y - A t) = A^T y - A^T A t */
        double s = h->My[k];
        for (int l = 0; l < p; l++)
            s -= h->M[k + l * p] * o->t[l];
        v[k] = s;
    }
    for (int k = 0; k < p; k++) {
        double s = 0.0;
        for (int l = 0; l < p; l++)
            s += C[k + l * p] * v[l];
        ds[k] = -s / (s2 * s2);
    }
    for (int j = 0; j < p; j++)
        for (int k = 0; k < p; k++) {
            double s = 2.0 * s2 * s2 / h->nus * ds[j] * ds[k];
            for (int x = 0; x < q; x++) {
                double dxk = 0.0;
                for (int y = 0; y < q; y++)
                    dxk += h->Ii[x + (size_t)y * q] * h->d[(size_t)y * p + k];
                s += h->d[(size_t)x * p + j] * dxk;
            }
            o->Lam[j + k * p] = s;
        }
    /* B: Y with K = (R^T - I) P^-1, X, H */
    for (int k = 0; k < p; k++)
        for (int l = 0; l < p; l++)
            a[k + l * p] = R[l + k * p] - (k == l);
    mm(p, a, 0, Pi, 0, b); /* b = (R^T - I) P^-1 */
    for (int x = 0; x < q; x++) {
        mm(p, h->Pt + x * pp, 0, b, 0, a);
        mm(p, a, 0, h->Pa + x * pp, 0, c);
        for (size_t k = 0; k < pp; k++)
            Y[k] += c[k];
        mm(p, h->Ft + x * pp, 0, Q, 0, a);
        mm(p, a, 0, h->F + x * pp, 0, c);
        for (size_t k = 0; k < pp; k++)
            X[k] += c[k];
    }
    for (int i = 0; i < h->m; i++) {
        const double *Wi = h->W + i * pp;
        double N[HP_MAXP * HP_MAXP] = {0};
        for (int x = 0; x < q; x++) { /* rows k, l of D_a W_i Et_a */
            int k = h->dk[x], l = h->dl[x];
            const double *E = h->Et + x * pp;
            for (int cc = 0; cc < p; cc++) {
                double sk = 0.0, sl = 0.0;
                for (int e = 0; e < p; e++) {
                    sk += Wi[l + e * p] * E[e + cc * p];
                    sl += Wi[k + e * p] * E[e + cc * p];
                }
                N[k + cc * p] += sk;
                if (k != l)
                    N[l + cc * p] += sl;
            }
        }
        mm(p, Wi, 0, N, 0, a);
        mm(p, a, 0, Wi, 0, c);
        for (size_t k = 0; k < pp; k++)
            H[k] += c[k];
    }
    for (int k = 0; k < p; k++) /* X + X^T - 2 H */
        for (int l = 0; l < p; l++)
            a[k + l * p] = X[k + l * p] + X[l + k * p] - 2.0 * H[k + l * p];
    mm(p, Q, 0, a, 0, b);
    mm(p, b, 0, Q, 0, c); /* Q (X + X^T - 2H) Q */
    for (int k = 0; k < p; k++)
        for (int l = 0; l < p; l++)
            a[k + l * p] = c[k + l * p] + Y[k + l * p] + Y[l + k * p];
    mm(p, R, 0, a, 0, b);
    mm(p, b, 0, R, 1, X); /* X = R (Y + Y^T + Q(..)Q) R^T */
    for (size_t k = 0; k < pp; k++) /* the s2 part: C M C P^-1 C */
        a[k] = h->M[k] / s2;
    mm(p, C, 0, a, 0, b);
    mm(p, b, 0, C, 0, c);
    mm(p, c, 0, Pi, 0, b);
    mm(p, b, 0, C, 0, c);
    for (int k = 0; k < p; k++)
        for (int l = 0; l < p; l++)
            o->B[k + l * p] = 0.25 * (X[k + l * p] + X[l + k * p]) -
                              (c[k + l * p] + c[l + k * p]) / h->nus;
    o->capped = 0;
    for (int j = 0; j < p; j++) {
        double cj = C[j + j * p], f = (cj + o->B[j + j * p]) / cj;
        if (!(f >= HF_FLOOR)) {
            f = HF_FLOOR;
            o->capped++;
        }
        o->f[j] = f;
    }
    for (int j = 0; j < p; j++)
        for (int k = 0; k < p; k++)
            o->mse[j + k * p] = (C[j + k * p] + o->Lam[j + k * p]) / sqrt(o->f[j] * o->f[k]);
    return 0;
}

/* The history arguments shared by the two functions below (positions
 * 1..8 there: m, b, ldb, V, ldv, sigma_u, lds, full, shifted by off). */
static int hf_check_history(int m, int p, const double *b, int ldb, const double *V, int ldv,
                            const double *sigma_u, int lds, int full, int off)
{
    if (m < 2)
        return -(off + 1);
    if (!b)
        return -(off + 2);
    if (ldb < p)
        return -(off + 3);
    if (!V)
        return -(off + 4);
    if (ldv < p)
        return -(off + 5);
    if (!sigma_u)
        return -(off + 6);
    if (lds < p)
        return -(off + 7);
    if (full != 0 && full != 1)
        return -(off + 8);
    return 0;
}

static int hf_finite_history(int m, int p, const double *b, int ldb, const double *V, int ldv,
                             const double *sigma_u, int lds)
{
    for (int i = 0; i < m; i++)
        if (!igea__finite_vec(p, b + (size_t)i * ldb, 1) ||
            !igea__finite_mat(p, p, V + (size_t)i * ldv * p, ldv))
            return IGEA_ENONFINITE;
    return igea__finite_mat(p, p, sigma_u, lds) ? 0 : IGEA_ENONFINITE;
}

/* Sigma from sigma_u: the diagonal (full = 0) or the lower triangle
 * mirrored; IGEA_EDOMAIN for a negative variance. */
static int hf_sigma(int p, const double *sigma_u, int lds, int full, double *Sig)
{
    for (int l = 0; l < p; l++)
        for (int k = 0; k < p; k++) {
            double x = k == l ? sigma_u[k + (size_t)l * lds]
                       : !full ? 0.0
                       : k > l ? sigma_u[k + (size_t)l * lds] : sigma_u[l + (size_t)k * lds];
            Sig[k + l * p] = x;
        }
    for (int k = 0; k < p; k++)
        if (!(Sig[k + k * p] >= 0.0))
            return IGEA_EDOMAIN;
    return 0;
}

int igea_accel_history_information(int m, int p, const double *b, int ldb, const double *V,
                                   int ldv, const double *sigma_u, int lds, int full,
                                   double *info, int ldi)
{
    if (m < 2)
        return -1;
    if (p < 1 || p > HP_MAXP)
        return -2;
    int st = hf_check_history(m, p, b, ldb, V, ldv, sigma_u, lds, full, 1);
    if (st)
        return st; /* b .. full are arguments 3 .. 9 */
    hf_work h = {.m = m, .p = p, .full = full, .b = b, .V = V, .ldb = ldb, .ldv = ldv};
    hf_dirs(&h);
    if (!info)
        return -10;
    if (ldi < h.q)
        return -11;
    if ((st = hf_finite_history(m, p, b, ldb, V, ldv, sigma_u, lds)))
        return st;
    double Sig[HP_MAXP * HP_MAXP], Q[HP_MAXP * HP_MAXP], beta0[HP_MAXP];
    if ((st = hf_sigma(p, sigma_u, lds, full, Sig)))
        return st;
    double *w = hf_alloc(&h);
    if (!w)
        return IGEA_ENOMEM;
    st = hf_info(&h, Sig, Q, beta0);
    if (!st && !igea__finite_vec(h.q * h.q, h.I, 1))
        st = IGEA_EOVERFLOW;
    for (int y = 0; !st && y < h.q; y++)
        memcpy(info + (size_t)y * ldi, h.I + (size_t)y * h.q, sizeof(double) * (size_t)h.q);
    free(w);
    return st;
}

int igea_accel_fit_history(int model, int n, const double *theta_deg, const double *ya,
                           const double *yb, int m, const double *b, int ldb, const double *V,
                           int ldv, const double *sigma_u, int lds, int full, double alpha,
                           double *coef, double *sd, double *sd_plugin, double *dof,
                           double *ci, double *cov, int ldc, double *info)
{
    int st0 = readings_check(model, n, theta_deg, ya, yb);
    if (st0)
        return st0;
    int p = model == IGEA_ACCEL_DUAL ? IGEA_ACCEL_NP_DUAL : IGEA_ACCEL_NP_SINGLE;
    int st = hf_check_history(m, p, b, ldb, V, ldv, sigma_u, lds, full, 5);
    if (st)
        return st;
    if (!(alpha > 0.0 && alpha < 1.0))
        return -14;
    if (!coef)
        return -15;
    if (cov ? ldc < p : ldc < 1)
        return -21;
    if (!igea__finite_vec(n, theta_deg, 1) || !igea__finite_vec(n, ya, 1) ||
        (model == IGEA_ACCEL_DUAL && !igea__finite_vec(n, yb, 1)))
        return IGEA_ENONFINITE;
    if ((st = hf_finite_history(m, p, b, ldb, V, ldv, sigma_u, lds)))
        return st;
    double Sig[HP_MAXP * HP_MAXP];
    if ((st = hf_sigma(p, sigma_u, lds, full, Sig)))
        return st;
    hf_work h = {.m = m, .p = p, .full = full, .b = b, .V = V, .ldb = ldb, .ldv = ldv};
    hf_dirs(&h);
    size_t nn = (size_t)n;
    double *A = igea__dalloc(nn * p + 2 * nn), *w = A ? hf_alloc(&h) : NULL;
    hf_out *o = w ? malloc(3 * sizeof *o) : NULL;
    double *Ii0 = o ? igea__dalloc((size_t)h.q * h.q + (size_t)(h.q + 1) * p) : NULL;
    if (!Ii0) {
        free(A), free(w), free(o);
        return IGEA_ENOMEM;
    }
    double *y = A + nn * p, *res = y + nn, x[HP_MAXP], s2 = 0.0;
    int rank = 0;
    st = igea_accel_design(model, n, theta_deg, A, n);
    if (!st)
        st = igea_accel_observe(model, n, theta_deg, ya, yb, y);
    if (!st)
        st = igea_regress_ls(n, p, A, n, y, NULL, NULL, 0.0, x, NULL, 1, &rank, &s2, res);
    if (!st && (n <= rank || !(s2 > 0.0)))
        st = IGEA_EDOMAIN;
    if (!st) {
        h.nus = n - rank;
        for (int k = 0; k < p; k++) {
            double s = 0.0;
            for (size_t i = 0; i < nn; i++)
                s += A[i + k * nn] * y[i];
            h.My[k] = s;
            for (int l = 0; l < p; l++) {
                double t = 0.0;
                for (size_t i = 0; i < nn; i++)
                    t += A[i + k * nn] * A[i + l * nn];
                h.M[k + l * p] = t;
            }
        }
        st = hf_eval(&h, Sig, s2, o);
    }
    /* the Satterthwaite degrees of freedom of mse_jj: its gradient in
     * (theta, s2) by central differences of 1e-4 of each parameter's sd */
    double *g = Ii0 + (size_t)h.q * h.q;
    if (!st)
        memcpy(Ii0, h.Ii, sizeof(double) * (size_t)h.q * h.q);
    for (int a = 0; !st && a <= h.q; a++) {
        double Sp[HP_MAXP * HP_MAXP], Sm[HP_MAXP * HP_MAXP], sp = s2, sm = s2, step;
        memcpy(Sp, Sig, sizeof Sp);
        memcpy(Sm, Sig, sizeof Sm);
        if (a < h.q) {
            int k = h.dk[a], l = h.dl[a];
            step = 1e-4 * sqrt(Ii0[a + (size_t)a * h.q]);
            Sp[k + l * p] += step, Sm[k + l * p] -= step;
            if (k != l)
                Sp[l + k * p] += step, Sm[l + k * p] -= step;
        } else {
            step = 1e-4 * s2 * sqrt(2.0 / h.nus);
            sp += step, sm -= step;
        }
        if (!(step > 0.0))
            st = IGEA_EOVERFLOW;
        if (!st)
            st = hf_eval(&h, Sp, sp, o + 1);
        if (!st)
            st = hf_eval(&h, Sm, sm, o + 2);
        for (int j = 0; !st && j < p; j++)
            g[(size_t)a * p + j] = (o[1].mse[j + j * p] - o[2].mse[j + j * p]) / (2.0 * step);
    }
    double nu[HP_MAXP], tq[HP_MAXP];
    for (int j = 0; !st && j < p; j++) {
        double var = 2.0 * s2 * s2 / h.nus * g[(size_t)h.q * p + j] * g[(size_t)h.q * p + j];
        for (int a = 0; a < h.q; a++)
            for (int c = 0; c < h.q; c++)
                var += g[(size_t)a * p + j] * Ii0[a + (size_t)c * h.q] * g[(size_t)c * p + j];
        double mj = o->mse[j + j * p];
        nu[j] = var > 0.0 ? 2.0 * mj * mj / var : IGEA_STATS_DOF_MAX;
        nu[j] = fmin(fmax(nu[j], 1.0), IGEA_STATS_DOF_MAX);
        if (!(mj > 0.0) || igea_stats_t_quantile(1.0 - 0.5 * alpha, nu[j], &tq[j]))
            st = IGEA_EOVERFLOW;
    }
    if (!st && (!igea__finite_vec(p, o->t, 1) || !igea__finite_vec(p * p, o->mse, 1) ||
                !igea__finite_vec(p * p, o->C, 1)))
        st = IGEA_EOVERFLOW;
    if (!st) {
        double rss = 0.0;
        for (size_t i = 0; i < nn; i++) {
            double r = y[i];
            for (int k = 0; k < p; k++)
                r -= A[i + k * nn] * o->t[k];
            rss += r * r;
        }
        memcpy(coef, o->t, sizeof(double) * (size_t)p);
        for (int j = 0; j < p; j++) {
            double sj = sqrt(o->mse[j + j * p]);
            if (sd)
                sd[j] = sj;
            if (sd_plugin)
                sd_plugin[j] = sqrt(fmax(o->C[j + j * p], 0.0));
            if (dof)
                dof[j] = nu[j];
            if (ci)
                ci[j] = o->t[j] - tq[j] * sj, ci[p + j] = o->t[j] + tq[j] * sj;
            if (cov)
                memcpy(cov + (size_t)j * ldc, o->mse + (size_t)j * p, sizeof(double) * (size_t)p);
        }
        if (info) {
            for (int k = 0; k < IGEA_ACCEL_HFIT_LEN; k++)
                info[k] = 0.0;
            info[IGEA_ACCEL_INFO_RANK] = rank;
            info[IGEA_ACCEL_INFO_SIGMA] = sqrt(s2);
            info[IGEA_ACCEL_INFO_RMS] = sqrt(rss / n);
            info[IGEA_ACCEL_INFO_NOBS] = n;
            info[IGEA_ACCEL_INFO_DOF] = n - rank;
            info[IGEA_ACCEL_HFIT_NTHETA] = h.q;
            info[IGEA_ACCEL_HFIT_CAPPED] = o->capped;
        }
    }
    free(A), free(w), free(o), free(Ii0);
    return st;
}
