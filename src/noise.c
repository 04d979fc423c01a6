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

/* ---- Rejected rows as additive outliers ------------------------------------ */

int igea__ar_setup(int p, const double *phi, double linv[][IGEA_NOISE_AR_MAX], double *su);

int igea__noise_arrows(int p, const double *phi, igea__arrow co[3])
{
    memset(co, 0, 3 * sizeof *co);
    for (int a = 0; a < 3; a++) {
        double li[IGEA_NOISE_AR_MAX][IGEA_NOISE_AR_MAX], su;
        co[a].diag = 1.0; /* p = 0: no serial correlation, stage 2 is the identity */
        if (p == 0)
            continue;
        if (igea__ar_setup(p, phi + a * p, li, &su))
            return 1;
        for (int t = 0; t < p; t++)
            for (int s = 0; s <= t; s++)
                co[a].head[t][s] = li[t][s];
        co[a].diag = su;
        for (int l = 1; l <= p; l++)
            co[a].lag[l] = -su * phi[a * p + l - 1];
    }
    return 0;
}

int igea__noise_ao_image(const igea__njob *j, const igea__arrow co[3], int i, int *rows,
                         double *val)
{
    const int e = i / 3, a = i % 3, p = j->p, te = j->segpos[e];
    int n = 0;
    for (int l = 0; l <= p; l++) {
        const int el = e + l, t = te + l;
        if (el >= j->M || j->segpos[el] != t)
            break; /* the segment ended: the next epochs are independent */
        for (int r = 0; r < 3; r++) {
            if (j->W1 ? r < a : r != a)
                continue; /* L_e^-1 is lower triangular */
            double s1 = j->W1 ? j->W1[3 * (size_t)e + r + (size_t)a * j->m] : 1.0;
            double cf = t < p ? co[r].head[t][te] : (l == 0 ? co[r].diag : co[r].lag[l]);
            rows[n] = 3 * el + r;
            val[n++] = cf * s1;
        }
    }
    return n;
}

void igea__ndum_free(igea__ndum *d)
{
    free(d->dblk);
    free(d->Q);
    free(d->qoff);
    memset(d, 0, sizeof *d);
}

static int uf_find(int *par, int x)
{
    while (par[x] != x)
        x = par[x] = par[par[x]];
    return x;
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* Block b of d (its dummies' images in img / cnt, cap entries each) into Q_b,
 * R_b by modified Gram-Schmidt, twice (Giraud et al. 2005: twice is enough);
 * 0 or IGEA_ERANK (an image in the span of the others: cannot happen for
 * distinct rows, T and L_e being invertible). */
static int block_qr(igea__ndum *d, int b, const int *img, const double *val, const int *cnt,
                    int cap)
{
    const int kb = d->boff[b + 1] - d->boff[b], nr = d->roff[b + 1] - d->roff[b];
    double *Q = d->Q + d->qoff[b], *R = d->R + d->roff2[b];
    memset(Q, 0, (size_t)nr * kb * sizeof(double));
    memset(R, 0, (size_t)kb * kb * sizeof(double));
    for (int c = 0; c < kb; c++) {
        int q = d->dblk[d->boff[b] + c];
        double *v = Q + (size_t)c * nr, n0 = 0.0;
        for (int t = 0; t < cnt[q]; t++) {
            v[d->rpos[img[q * cap + t]]] = val[q * cap + t];
            n0 += val[q * cap + t] * val[q * cap + t];
        }
        for (int pass = 0; pass < 2; pass++)
            for (int cc = 0; cc < c; cc++) {
                double r = cblas_ddot(nr, Q + (size_t)cc * nr, 1, v, 1);
                cblas_daxpy(nr, -r, Q + (size_t)cc * nr, 1, v, 1);
                R[cc + (size_t)c * kb] += r;
            }
        double nv = cblas_dnrm2(nr, v, 1);
        if (!(nv > 1e-12 * sqrt(n0)))
            return IGEA_ERANK;
        R[c + (size_t)c * kb] = nv;
        cblas_dscal(nr, 1.0 / nv, v, 1);
        d->logdet += log(nv);
    }
    return 0;
}

int igea__noise_dummies(const igea__njob *j, igea__nstate *s)
{
    const int m = j->m, Nt = j->Nt, n1 = Nt + 1, G = j->G, k = j->nrej;
    const int cap = 3 * (j->p + 1);
    igea__ndum *d = &s->d;
    for (int b = 0; b < d->nblk; b++) { /* the rows before the last projection */
        int nr = d->roff[b + 1] - d->roff[b];
        const double *v0 = d->V0 + (size_t)d->roff[b] * n1;
        for (int q = 0; q < nr; q++)
            for (int c = 0; c < n1; c++)
                s->V[d->rows[d->roff[b] + q] + (size_t)c * m] = v0[q + (size_t)c * nr];
    }
    igea__ndum_free(d);
    memcpy(s->A, s->A0, (size_t)G * Nt * Nt * sizeof(double));
    memcpy(s->b, s->b0, (size_t)G * Nt * sizeof(double));
    memcpy(s->wtw, s->wtw0, 2 * (size_t)G * sizeof(double));
    if (k == 0)
        return 0;
    igea__arrow co[3];
    if (igea__noise_arrows(j->p, s->phi, co))
        return IGEA_EDOMAIN;
    /* the images and their blocks (union-find over shared rows) */
    size_t ni = (size_t)k * cap * 2 + 4 * (size_t)k + 3 + 2 * (size_t)m;
    int *iw = igea__ialloc(ni);
    double *val = igea__dalloc((size_t)k * cap);
    if (!iw || !val) {
        free(iw);
        free(val);
        return IGEA_ENOMEM;
    }
    int *img = iw, *cnt = img + (size_t)k * cap, *par = cnt + k, *bid = par + k,
        *broot = bid + k, *own = broot + k, *rbuf = own + m, *tmpm = rbuf + (size_t)k * cap;
    (void)tmpm;
    for (int i = 0; i < m; i++)
        own[i] = -1;
    for (int q = 0; q < k; q++) {
        cnt[q] = igea__noise_ao_image(j, co, j->rej[q], img + (size_t)q * cap,
                                      val + (size_t)q * cap);
        par[q] = q;
        broot[q] = -1;
        for (int t = 0; t < cnt[q]; t++) {
            int r = img[(size_t)q * cap + t];
            if (own[r] >= 0) {
                int x = uf_find(par, q), y = uf_find(par, own[r]);
                if (x != y)
                    par[x > y ? x : y] = x < y ? x : y;
            }
            own[r] = q;
        }
    }
    int nblk = 0;
    for (int q = 0; q < k; q++) {
        int r = uf_find(par, q);
        if (broot[r] < 0)
            broot[r] = nblk++;
        bid[q] = broot[r];
    }
    /* sizes: dummies per block, then rows per block (sorted, unique) */
    int st = 0;
    d->nblk = nblk;
    d->k = k;
    d->dblk = igea__ialloc((size_t)k + 2 * ((size_t)nblk + 1) + (size_t)k * cap + 2 * (size_t)m);
    d->qoff = malloc(2 * ((size_t)nblk + 1) * sizeof(size_t));
    if (!d->dblk || !d->qoff) {
        st = IGEA_ENOMEM;
        goto done;
    }
    d->boff = d->dblk + k;
    d->roff = d->boff + nblk + 1;
    d->rows = d->roff + nblk + 1;
    d->rblk = d->rows + (size_t)k * cap;
    d->rpos = d->rblk + m;
    d->roff2 = d->qoff + nblk + 1;
    memset(d->boff, 0, ((size_t)nblk + 1) * sizeof(int));
    for (int q = 0; q < k; q++)
        d->boff[bid[q] + 1]++;
    for (int b = 0; b < nblk; b++)
        d->boff[b + 1] += d->boff[b];
    for (int b = 0, *fill = par; b < nblk; b++) /* par reused as the fill pointers */
        fill[b] = d->boff[b];
    for (int q = 0; q < k; q++)
        d->dblk[par[bid[q]]++] = q;
    for (int i = 0; i < m; i++)
        d->rblk[i] = d->rpos[i] = -1;
    d->roff[0] = 0;
    size_t nq = 0, nR = 0;
    for (int b = 0; b < nblk; b++) {
        int nr = 0;
        for (int c = d->boff[b]; c < d->boff[b + 1]; c++) {
            int q = d->dblk[c];
            for (int t = 0; t < cnt[q]; t++)
                rbuf[nr++] = img[(size_t)q * cap + t];
        }
        qsort(rbuf, (size_t)nr, sizeof(int), cmp_int);
        int u = 0;
        for (int t = 0; t < nr; t++)
            if (t == 0 || rbuf[t] != rbuf[t - 1])
                rbuf[u++] = rbuf[t];
        for (int t = 0; t < u; t++) {
            d->rows[d->roff[b] + t] = rbuf[t];
            d->rblk[rbuf[t]] = b;
            d->rpos[rbuf[t]] = t;
        }
        d->roff[b + 1] = d->roff[b] + u;
        int kb = d->boff[b + 1] - d->boff[b];
        d->qoff[b] = nq;
        d->roff2[b] = nR;
        nq += (size_t)u * kb;
        nR += (size_t)kb * kb;
    }
    d->qoff[nblk] = nq;
    d->roff2[nblk] = nR;
    size_t nrow = (size_t)d->roff[nblk];
    d->Q = igea__dalloc(nq + nR + (size_t)k * n1 + nrow * n1);
    if (!d->Q) {
        st = IGEA_ENOMEM;
        goto done;
    }
    d->R = d->Q + nq;
    d->Z = d->R + nR;
    d->V0 = d->Z + (size_t)k * n1;
    for (int b = 0; b < nblk && st == 0; b++) {
        const int kb = d->boff[b + 1] - d->boff[b], nr = d->roff[b + 1] - d->roff[b];
        const int *rw = d->rows + d->roff[b];
        double *v0 = d->V0 + (size_t)d->roff[b] * n1, *Z = d->Z + (size_t)d->boff[b] * n1;
        const double *Q = d->Q + d->qoff[b];
        if ((st = block_qr(d, b, img, val, cnt, cap)))
            break;
        for (int c = 0; c < n1; c++)
            for (int q = 0; q < nr; q++)
                v0[q + (size_t)c * nr] = s->V[rw[q] + (size_t)c * m];
        /* Z = Q' V0; the rows (I - Q Q') V0 */
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, kb, n1, nr, 1.0, Q, nr, v0, nr,
                    0.0, Z, kb);
        for (int c = 0; c < n1; c++)
            for (int q = 0; q < nr; q++) {
                double t = v0[q + (size_t)c * nr];
                for (int l = 0; l < kb; l++)
                    t -= Q[q + (size_t)l * nr] * Z[l + (size_t)c * kb];
                s->V[rw[q] + (size_t)c * m] = t;
            }
        /* the group sums lose Z'Z, one row count per dummy */
        int g = j->group ? j->group[rw[0] / 3] : 0;
        double *Ag = s->A + (size_t)g * Nt * Nt, *bg = s->b + (size_t)g * Nt;
        const double *zw = Z + (size_t)Nt * kb;
        for (int c = 0; c < Nt; c++) {
            const double *zc = Z + (size_t)c * kb;
            for (int r = c; r < Nt; r++) {
                double t = cblas_ddot(kb, Z + (size_t)r * kb, 1, zc, 1);
                Ag[r + (size_t)c * Nt] -= t;
                if (r != c)
                    Ag[c + (size_t)r * Nt] -= t;
            }
            bg[c] -= cblas_ddot(kb, zc, 1, zw, 1);
        }
        s->wtw[2 * g] = fmax(0.0, s->wtw[2 * g] - cblas_ddot(kb, zw, 1, zw, 1));
        s->wtw[2 * g + 1] -= kb;
    }
done:
    free(iw);
    free(val);
    if (st) /* the rows are those before any projection: nothing to restore */
        igea__ndum_free(d);
    return st;
}
