/* noise.c - AR(p) fit, Helmert variance components, and the equivalent-error
 * job with the noise models and the robust route (docs/eqerr.md,
 * "Tracking noise beyond a diagonal K"). */
#include <float.h>

#include <cblas.h>

#include "igea/noise.h"
#include "internal.h"
#include "noise_job.h"

/* The checks of slots 20..28 (igea_eqerr_check_opts): 0 or 1 + slot. */
int igea__noise_check_opts(const double *o);
int igea__noise_check_opts(const double *o)
{
    double p = o[IGEA_EQERR_OPT_AR];
    if (!(p >= 0 && p <= IGEA_NOISE_AR_MAX && p == floor(p))) return 1 + IGEA_EQERR_OPT_AR;
    if (o[IGEA_EQERR_OPT_AR_ESTIMATE] != 0 && o[IGEA_EQERR_OPT_AR_ESTIMATE] != 1) return 1 + IGEA_EQERR_OPT_AR_ESTIMATE;
    if (o[IGEA_EQERR_OPT_ROBUST] != 0 && o[IGEA_EQERR_OPT_ROBUST] != 1) return 1 + IGEA_EQERR_OPT_ROBUST;
    if (!(o[IGEA_EQERR_OPT_ROBUST_ALPHA] >= 0 && o[IGEA_EQERR_OPT_ROBUST_ALPHA] < 0.5)) return 1 + IGEA_EQERR_OPT_ROBUST_ALPHA;
    if (!(o[IGEA_EQERR_OPT_NOISE_TOL] >= 0 && o[IGEA_EQERR_OPT_NOISE_TOL] < 1)) return 1 + IGEA_EQERR_OPT_NOISE_TOL;
    double it = o[IGEA_EQERR_OPT_NOISE_MAX_ITER];
    if (!(it >= 0 && it <= 1000 && it == floor(it))) return 1 + IGEA_EQERR_OPT_NOISE_MAX_ITER;
    if (o[IGEA_EQERR_OPT_GROUP_BIAS] != 0 && o[IGEA_EQERR_OPT_GROUP_BIAS] != 1) return 1 + IGEA_EQERR_OPT_GROUP_BIAS;
    if (!(o[IGEA_EQERR_OPT_ROBUST_MAX] >= 0 && o[IGEA_EQERR_OPT_ROBUST_MAX] <= 0.5)) return 1 + IGEA_EQERR_OPT_ROBUST_MAX;
    if (o[IGEA_EQERR_OPT_AR_METHOD] != IGEA_NOISE_AR_REML && o[IGEA_EQERR_OPT_AR_METHOD] != IGEA_NOISE_AR_LS) return 1 + IGEA_EQERR_OPT_AR_METHOD;
    return 0;
}

/* 1 when the options ask for what only igea_noise_eqerr does. */
int igea__noise_opts_set(const double *o);
int igea__noise_opts_set(const double *o)
{
    return o[IGEA_EQERR_OPT_AR] != 0 || o[IGEA_EQERR_OPT_ROBUST] != 0 ||
           o[IGEA_EQERR_OPT_GROUP_BIAS] != 0;
}

/* ---- AR(p) fit ----------------------------------------------------------- */

/* Solve the p x p SPD system G x = r in place (Cholesky); ginv gets the
 * diagonal of G^-1. Returns 0 or 1 (singular). */
static int spd_solve(int p, double *G, double *r, double *ginv_diag)
{
    double L[9], e[3];
    memcpy(L, G, (size_t)p * p * sizeof(double));
    if (igea__chol_lower(p, L, p, 0.0) != 0 || !(L[0] > 0))
        return 1;
    for (int k = 0; k < p; k++) { /* column k of G^-1: solve L L' x = e_k */
        for (int i = 0; i < p; i++) {
            double s = (i == k);
            for (int l = 0; l < i; l++)
                s -= L[i + l * p] * e[l];
            e[i] = s / L[i + i * p];
        }
        for (int i = p - 1; i >= 0; i--) {
            double s = e[i];
            for (int l = i + 1; l < p; l++)
                s -= L[l + i * p] * e[l];
            e[i] = s / L[i + i * p];
        }
        ginv_diag[k] = e[k];
    }
    for (int i = 0; i < p; i++) {
        double s = r[i];
        for (int l = 0; l < i; l++)
            s -= L[i + l * p] * r[l];
        r[i] = s / L[i + i * p];
    }
    for (int i = p - 1; i >= 0; i--) {
        double s = r[i];
        for (int l = i + 1; l < p; l++)
            s -= L[l + i * p] * r[l];
        r[i] = s / L[i + i * p];
    }
    return 0;
}

/* 1 when epoch t of axis a and its p predecessors are usable. */
static int lag_ok(int t, int a, int p, const int *group, const int *mask)
{
    if (t < p)
        return 0;
    for (int l = 0; l <= p; l++) {
        if (group && group[t - l] != group[t])
            return 0;
        if (mask && mask[3 * (t - l) + a])
            return 0;
    }
    return 1;
}

int igea_noise_ar_fit(int M, int p, const double *resid, const int *group,
                      const int *mask, double *phi, double *se)
{
    if (M < 1) return -1;
    if (p < 1 || p > IGEA_NOISE_AR_MAX) return -2;
    if (!resid) return -3;
    if (!phi) return -6;
    if (!se) return -7;
    if (!igea__finite_vec(3 * M, resid, 1))
        return IGEA_ENONFINITE;
    double ph[9], sd[9];
    for (int a = 0; a < 3; a++) {
        double G[9] = {0}, r[3] = {0}, yy = 0.0, gd[3];
        int n = 0;
        for (int t = 0; t < M; t++) {
            if (!lag_ok(t, a, p, group, mask))
                continue;
            double y = resid[3 * t + a];
            for (int k = 0; k < p; k++) {
                double xk = resid[3 * (t - 1 - k) + a];
                r[k] += xk * y;
                for (int l = 0; l < p; l++)
                    G[k + l * p] += xk * resid[3 * (t - 1 - l) + a];
            }
            yy += y * y;
            n++;
        }
        double Gc[9], rc[3];
        memcpy(Gc, G, sizeof G);
        memcpy(rc, r, sizeof r);
        if (n <= p || spd_solve(p, Gc, rc, gd))
            return IGEA_ERANK;
        /* RSS = y'y - phi' X'y (normal equations) */
        double rss = yy;
        for (int k = 0; k < p; k++)
            rss -= rc[k] * r[k];
        double s2 = fmax(rss, 0.0) / (n - p);
        for (int k = 0; k < p; k++) {
            ph[a * p + k] = rc[k];
            sd[a * p + k] = sqrt(s2 * gd[k]);
        }
    }
    if (!igea__finite_vec(3 * p, ph, 1) || !igea__finite_vec(3 * p, sd, 1))
        return IGEA_EOVERFLOW;
    memcpy(phi, ph, (size_t)3 * p * sizeof(double));
    memcpy(se, sd, (size_t)3 * p * sizeof(double));
    return 0;
}

/* ---- Helmert variance components ---------------------------------------- */

/* The pseudo-inverse factor of N = sum A_g / c_g: F (N x r) with N^+ = F
 * F'; V (N x N) and lam (N) scratch. Returns the rank or a failure < 0
 * (noise_job.h). */
int igea__noise_pinv_factor(int N, int G, const double *A, int lda, const double *c,
                            double *Nt, double *lam, double *F)
{
    for (int j = 0; j < N; j++)
        for (int i = j; i < N; i++) {
            double s = 0.0;
            for (int g = 0; g < G; g++)
                s += IGEA_AT(A + (size_t)g * lda * N, lda, i, j) / c[g];
            Nt[i + (size_t)j * N] = s;
        }
    int st = igea__syev_desc(N, Nt, N, lam, F, N);
    if (st)
        return st;
    int r = igea__rank_cut(N, lam, N * 10.0 * DBL_EPSILON);
    for (int k = 0; k < r; k++)
        cblas_dscal(N, 1.0 / sqrt(lam[k]), F + (size_t)k * N, 1);
    return r;
}

/* x = F F' sum b_g / c_g. t (N) scratch. */
static void pinv_apply(int N, int G, int r, const double *F, const double *b,
                       const double *c, double *t, double *x)
{
    for (int i = 0; i < N; i++) {
        double s = 0.0;
        for (int g = 0; g < G; g++)
            s += b[(size_t)g * N + i] / c[g];
        x[i] = s;
    }
    cblas_dgemv(CblasColMajor, CblasTrans, N, r, 1.0, F, N, x, 1, 0.0, t, 1);
    cblas_dgemv(CblasColMajor, CblasNoTrans, N, r, 1.0, F, N, t, 1, 0.0, x, 1);
}

/* One Helmert step: Omega_g, r_g and the new c_g from the current c.
 * work: N^2 (Nt) + N^2 (F) + 3 N. Returns 0 or a failure. */
static int vce_step(int N, int G, const double *A, int lda, const double *b,
                    const double *wtw, const double *c, double *cn, double *red,
                    double *x, double *work)
{
    size_t nn = (size_t)N * N;
    double *Nt = work, *F = Nt + nn, *lam = F + nn, *t = lam + N, *Ax = t + N;
    int r = igea__noise_pinv_factor(N, G, A, lda, c, Nt, lam, F);
    if (r < 0)
        return r;
    pinv_apply(N, G, r, F, b, c, t, x);
    for (int g = 0; g < G; g++) {
        const double *Ag = A + (size_t)g * lda * N;
        cblas_dsymv(CblasColMajor, CblasLower, N, 1.0, Ag, lda, x, 1, 0.0, Ax, 1);
        double om = wtw[2 * g] - 2.0 * cblas_ddot(N, x, 1, b + (size_t)g * N, 1) +
                    cblas_ddot(N, x, 1, Ax, 1);
        double tr = 0.0; /* tr(F' A_g F) */
        for (int k = 0; k < r; k++) {
            cblas_dsymv(CblasColMajor, CblasLower, N, 1.0, Ag, lda, F + (size_t)k * N, 1,
                        0.0, Ax, 1);
            tr += cblas_ddot(N, F + (size_t)k * N, 1, Ax, 1);
        }
        red[g] = wtw[2 * g + 1] - tr / c[g];
        if (!(red[g] > 0.5))
            return IGEA_ERANK;
        if (!(om > 0.0) || !isfinite(om))
            return isfinite(om) ? IGEA_EDOMAIN : IGEA_EOVERFLOW;
        cn[g] = om / red[g];
    }
    return 0;
}

/* The iteration; *conv 1 when it settled. Outputs c, red, x (G, G, N). */
int igea__noise_vce_iterate(int N, int G, const double *A, int lda, const double *b,
                            const double *wtw, double tol, int maxit, double *c,
                            double *red, double *x, int *iters, int *conv);
int igea__noise_vce_iterate(int N, int G, const double *A, int lda, const double *b,
                       const double *wtw, double tol, int maxit, double *c,
                       double *red, double *x, int *iters, int *conv)
{
    double *work = igea__dalloc(2 * (size_t)N * N + 3 * (size_t)N + (size_t)G);
    if (!work)
        return IGEA_ENOMEM;
    double *cn = work + 2 * (size_t)N * N + 3 * (size_t)N;
    int st = 0;
    *conv = 0;
    for (int g = 0; g < G; g++)
        c[g] = 1.0;
    for (int it = 0; it < maxit && st == 0; it++) {
        *iters = it + 1;
        st = vce_step(N, G, A, lda, b, wtw, c, cn, red, x, work);
        if (st)
            break;
        double d = 0.0;
        for (int g = 0; g < G; g++) {
            d = fmax(d, fabs(cn[g] / c[g] - 1.0));
            c[g] = cn[g];
        }
        if (d <= tol) {
            *conv = 1;
            break;
        }
    }
    /* red and x belong to the scales before the last update: recompute */
    if (st == 0)
        st = vce_step(N, G, A, lda, b, wtw, c, cn, red, x, work);
    free(work);
    return st;
}

int igea_noise_vce(int N, int G, const double *A, int lda, const double *b,
                   const double *wtw, double tol, int max_iter, double *scale,
                   double *se, double *redund, double *x, int *iterations)
{
    if (N < 1) return -1;
    if (G < 1) return -2;
    if (!A) return -3;
    if (lda < N) return -4;
    if (!b) return -5;
    if (!wtw) return -6;
    if (!(tol > 0) || !isfinite(tol)) return -7;
    if (max_iter < 1 || max_iter > 1000) return -8;
    if (!scale) return -9;
    if (!se) return -10;
    if (!redund) return -11;
    if (!x) return -12;
    if (!iterations) return -13;
    for (int g = 0; g < G; g++) {
        const double *Ag = A + (size_t)g * lda * N;
        for (int j = 0; j < N; j++)
            if (!igea__finite_vec(N - j, &IGEA_AT(Ag, lda, j, j), 1))
                return IGEA_ENONFINITE;
    }
    if (!igea__finite_vec(G * N, b, 1) || !igea__finite_vec(2 * G, wtw, 1))
        return IGEA_ENONFINITE;
    double *w = igea__dalloc(2 * (size_t)G + (size_t)N);
    if (!w)
        return IGEA_ENOMEM;
    double *c = w, *red = c + G, *xx = red + G;
    int it = 0, conv = 0;
    int st = igea__noise_vce_iterate(N, G, A, lda, b, wtw, tol, max_iter, c, red, xx, &it, &conv);
    if (st == 0 && !conv)
        st = IGEA_ENOCONV;
    if (st == 0) {
        for (int g = 0; g < G; g++) {
            scale[g] = c[g];
            se[g] = c[g] * sqrt(2.0 / red[g]);
            redund[g] = red[g];
        }
        memcpy(x, xx, (size_t)N * sizeof(double));
        *iterations = it;
    }
    free(w);
    return st;
}

/* ---- REML covariance of the variance components --------------------------- */

/* Inverse of the G x G SPD matrix in place (column-major), by its
 * Cholesky factor; L (G^2) scratch. Returns 0 or IGEA_ERANK. */
static int spd_inverse(int G, double *Im, double *L)
{
    memcpy(L, Im, (size_t)G * G * sizeof(double));
    if (igea__chol_lower(G, L, G, 0.0) != 0)
        return IGEA_ERANK;
    for (int k = 0; k < G; k++) { /* column k: L L' x = e_k */
        double *x = Im + (size_t)k * G;
        for (int i = 0; i < G; i++) {
            double s = (i == k);
            for (int l = 0; l < i; l++)
                s -= L[i + (size_t)l * G] * x[l];
            x[i] = s / L[i + (size_t)i * G];
        }
        for (int i = G - 1; i >= 0; i--) {
            double s = x[i];
            for (int l = i + 1; l < G; l++)
                s -= L[l + (size_t)i * G] * x[l];
            x[i] = s / L[i + (size_t)i * G];
        }
    }
    return 0;
}

/* The inverse REML information of the scales c (G) of the groups' normal
 * equations A (G blocks, lower triangles, lda) and row counts wtw[2g + 1]:
 * I_gh = (delta_gh (n_g - 2 tr(Q N_g) / c_g) / c_g^2 + tr(Q N_g Q N_h) /
 * (c_g^2 c_h^2)) / 2, Q = (sum N_g / c_g)^+, into cov (G x G). */
int igea__noise_vce_cov(int N, int G, const double *A, int lda, const double *wtw,
                        const double *c, double *cov);
int igea__noise_vce_cov(int N, int G, const double *A, int lda, const double *wtw,
                        const double *c, double *cov)
{
    size_t nn = (size_t)N * N;
    double *Nt = igea__dalloc((2 + (size_t)G) * nn + (size_t)N + 2 * (size_t)G * G + G);
    if (!Nt)
        return IGEA_ENOMEM;
    double *F = Nt + nn, *K = F + nn, *lam = K + (size_t)G * nn, *Im = lam + N;
    double *L = Im + (size_t)G * G, *tr = L + (size_t)G * G;
    int r = igea__noise_pinv_factor(N, G, A, lda, c, Nt, lam, F), st = r < 0 ? r : 0;
    for (int g = 0; st == 0 && g < G; g++) { /* K_g = F' N_g F (r x r), T in Nt */
        double *Kg = K + (size_t)g * r * r;
        if (r == 0)
            break;
        cblas_dsymm(CblasColMajor, CblasLeft, CblasLower, N, r, 1.0, A + (size_t)g * lda * N,
                    lda, F, N, 0.0, Nt, N);
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, r, N, 1.0, F, N, Nt, N, 0.0,
                    Kg, r);
        tr[g] = 0.0;
        for (int k = 0; k < r; k++)
            tr[g] += Kg[k + (size_t)k * r];
    }
    for (int g = 0; st == 0 && g < G; g++)
        for (int h = 0; h < G; h++) {
            double t = r ? cblas_ddot(r * r, K + (size_t)g * r * r, 1, K + (size_t)h * r * r, 1)
                         : 0.0;
            double v = t / (c[g] * c[g] * c[h] * c[h]);
            if (g == h)
                v += (wtw[2 * g + 1] - 2.0 * (r ? tr[g] : 0.0) / c[g]) / (c[g] * c[g]);
            Im[g + (size_t)h * G] = 0.5 * v;
        }
    if (st == 0)
        st = spd_inverse(G, Im, L);
    if (st == 0 && !igea__finite_vec(G * G, Im, 1))
        st = IGEA_EOVERFLOW;
    if (st == 0)
        memcpy(cov, Im, (size_t)G * G * sizeof(double));
    free(Nt);
    return st;
}

int igea_noise_vce_cov(int N, int G, const double *A, int lda, const double *wtw,
                       const double *scale, double *cov)
{
    if (N < 1) return -1;
    if (G < 1) return -2;
    if (!A) return -3;
    if (lda < N) return -4;
    if (!wtw) return -5;
    if (!scale) return -6;
    if (!cov) return -7;
    for (int g = 0; g < G; g++) {
        const double *Ag = A + (size_t)g * lda * N;
        for (int j = 0; j < N; j++)
            if (!igea__finite_vec(N - j, &IGEA_AT(Ag, lda, j, j), 1))
                return IGEA_ENONFINITE;
    }
    for (int g = 0; g < G; g++) {
        if (!isfinite(wtw[2 * g]) || !isfinite(wtw[2 * g + 1]) || !isfinite(scale[g]))
            return IGEA_ENONFINITE;
        if (!(wtw[2 * g + 1] >= 0)) return -5;
        if (!(scale[g] > 0)) return -6;
    }
    return igea__noise_vce_cov(N, G, A, lda, wtw, scale, cov);
}
