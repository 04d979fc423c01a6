/* noise_reml.c - phi and the group scales of igea_noise_eqerr by restricted
 * maximum likelihood (IGEA_NOISE_AR_REML; docs/eqerr.md, "phi by restricted
 * maximum likelihood" [D]): the score of the restricted likelihood of the
 * Prais-Winsten whitened rows, Fisher-scoring steps, and the observed
 * information of phi and the scales together for their standard errors. */

#include <cblas.h>

#include "igea/noise.h"
#include "internal.h"
#include "noise_job.h"

#define PMAX IGEA_NOISE_AR_MAX

int igea__ar_setup(int p, const double *phi, double linv[][IGEA_NOISE_AR_MAX], double *su);
/* noise.c */
int igea__noise_vce_iterate(int N, int G, const double *A, int lda, const double *b,
                            const double *wtw, double tol, int maxit, double *c,
                            double *red, double *x, int *iters, int *conv);

/* The coefficients of one axis's whitening and their derivatives: */
typedef struct {
    double rho[PMAX + 1];          /* autocorrelation rho_0 .. rho_p */
    double su;                     /* 1 / sigma_u */
    double linv[PMAX][PMAX];       /* Gamma_p^-1/2 (lower) */
    double dls[PMAX];              /* d log su / d phi_k */
    double dli[PMAX][PMAX][PMAX];  /* d linv[t][l] / d phi_k at [k][t][l] */
} ar_coef;

/* Solve the p x p system M x = r in place (Gaussian elimination with
 * partial pivoting, p <= 3). Returns 0 or 1 (singular). */
static int small_solve(int p, double M[][PMAX], double *r)
{
    double a[PMAX][PMAX + 1];
    for (int i = 0; i < p; i++) {
        for (int l = 0; l < p; l++)
            a[i][l] = M[i][l];
        a[i][p] = r[i];
    }
    for (int c = 0; c < p; c++) {
        int piv = c;
        for (int i = c + 1; i < p; i++)
            if (fabs(a[i][c]) > fabs(a[piv][c]))
                piv = i;
        if (!(fabs(a[piv][c]) > 1e-14))
            return 1;
        for (int l = 0; l <= p; l++) {
            double t = a[c][l];
            a[c][l] = a[piv][l];
            a[piv][l] = t;
        }
        for (int i = c + 1; i < p; i++) {
            double f = a[i][c] / a[c][c];
            for (int l = c; l <= p; l++)
                a[i][l] -= f * a[c][l];
        }
    }
    for (int i = p - 1; i >= 0; i--) {
        double s = a[i][p];
        for (int l = i + 1; l < p; l++)
            s -= a[i][l] * r[l];
        r[i] = s / a[i][i];
    }
    return 0;
}

/* The coefficients of AR(p) phi and their derivatives (docs/eqerr.md):
 * Yule-Walker rho_k = sum_j phi_j rho_|k-j| differentiated,
 * M d rho / d phi_m = (rho_|k-m|)_k with M the Yule-Walker matrix;
 * sigma_u^2 = 1 - sum_k phi_k rho_k; Gamma_p = L L', d(L^-1) =
 * -Phi(L^-1 dGamma L^-T) L^-1 with Phi the lower triangle, diagonal halved.
 * Returns 0 or 1 (not stationary). */
static int ar_coefs(int p, const double *phi, ar_coef *o)
{
    memset(o, 0, sizeof *o);
    if (igea__ar_setup(p, phi, o->linv, &o->su))
        return 1;
    double M[PMAX][PMAX], r[PMAX];
    for (int k = 1; k <= p; k++) {
        for (int l = 1; l <= p; l++)
            M[k - 1][l - 1] = (k == l);
        r[k - 1] = 0.0;
        for (int j = 1; j <= p; j++) {
            int l = abs(k - j);
            if (l == 0)
                r[k - 1] += phi[j - 1];
            else
                M[k - 1][l - 1] -= phi[j - 1];
        }
    }
    if (small_solve(p, M, r))
        return 1;
    o->rho[0] = 1.0;
    for (int k = 0; k < p; k++)
        o->rho[k + 1] = r[k];
    double s2 = 1.0 / (o->su * o->su); /* sigma_u^2 */
    for (int mm = 1; mm <= p; mm++) {
        double dr[PMAX];
        for (int k = 1; k <= p; k++)
            dr[k - 1] = o->rho[abs(k - mm)];
        if (small_solve(p, M, dr))
            return 1;
        double ds2 = -o->rho[mm];
        for (int k = 1; k <= p; k++)
            ds2 -= phi[k - 1] * dr[k - 1];
        o->dls[mm - 1] = -0.5 * ds2 / s2;
        /* X = Linv dGamma Linv', dGamma_il = d rho_|i-l| */
        double X[PMAX][PMAX], Y[PMAX][PMAX];
        for (int i = 0; i < p; i++)
            for (int l = 0; l < p; l++) {
                double s = 0.0;
                for (int q = 0; q <= i; q++)
                    for (int w = 0; w <= l; w++) {
                        int d = abs(q - w);
                        s += o->linv[i][q] * (d ? dr[d - 1] : 0.0) * o->linv[l][w];
                    }
                Y[i][l] = s;
            }
        for (int i = 0; i < p; i++)
            for (int l = 0; l < p; l++)
                X[i][l] = l < i ? Y[i][l] : l == i ? 0.5 * Y[i][l] : 0.0;
        for (int t = 0; t < p; t++)
            for (int l = 0; l < p; l++) {
                double s = 0.0;
                for (int q = l; q <= t; q++)
                    s += X[t][q] * o->linv[q][l];
                o->dli[mm - 1][t][l] = -s;
            }
    }
    return 0;
}

/* The scratch of one evaluation of the score. */
typedef struct {
    double *Nt, *F, *lam;    /* pseudo-inverse of sum A_g / c_g (Nt: then N^+ = F F') */
    double *Y2;              /* m x Nt: X~_e N^+ */
    double *x, *bb, *e, *v;  /* Nt, Nt, m (stage-1 residual), m (whitened residual) */
    double *H;               /* (p + 2) m: Y2.X~, Y2.U_S at lags 0..p */
    double *hv;              /* m: Y2.X~_e (the hat diagonal times c) */
    int r;                   /* the rank of the last fit */
} reml_ws;

static double *ws_alloc(const igea__njob *j, reml_ws *w)
{
    size_t m = (size_t)j->m, Nt = (size_t)j->Nt;
    size_t nd = 2 * Nt * Nt + Nt + m * Nt + 2 * Nt + 2 * m + (size_t)(j->p + 2) * m + m;
    double *d = igea__dalloc(nd);
    if (!d)
        return NULL;
    w->Nt = d;
    w->F = w->Nt + Nt * Nt;
    w->lam = w->F + Nt * Nt;
    w->Y2 = w->lam + Nt;
    w->x = w->Y2 + m * Nt;
    w->bb = w->x + Nt;
    w->e = w->bb + Nt;
    w->v = w->e + m;
    w->H = w->v + m;
    w->hv = w->H + (size_t)(j->p + 2) * m;
    return d;
}

/* x = F F' sum_g b_g / c_g and the rank r of the pseudo-inverse factor of
 * the state's N = sum A_g / c_g (into w). Returns r or a failure < 0. */
static int gls(const igea__njob *j, const igea__nstate *S, const double *c, reml_ws *w)
{
    const int Nt = j->Nt, G = j->G;
    int r = igea__noise_pinv_factor(Nt, G, S->A, Nt, c, w->Nt, w->lam, w->F);
    if (r < 0)
        return r;
    for (int i = 0; i < Nt; i++) {
        double t = 0.0;
        for (int g = 0; g < G; g++)
            t += S->b[(size_t)g * Nt + i] / c[g];
        w->bb[i] = t;
    }
    memset(w->x, 0, (size_t)Nt * sizeof(double));
    w->r = r;
    if (r > 0) {
        double *t = w->Y2; /* r doubles of scratch */
        cblas_dgemv(CblasColMajor, CblasTrans, Nt, r, 1.0, w->F, Nt, w->bb, 1, 0.0, t, 1);
        cblas_dgemv(CblasColMajor, CblasNoTrans, Nt, r, 1.0, w->F, Nt, t, 1, 0.0, w->x, 1);
    }
    return r;
}

static int lval(const igea__njob *j, const igea__nstate *S, double *c, int r, int prof,
                reml_ws *w, double *l);

/* The derivative of one axis's whitening coefficients by phi_(a,k) (the
 * other axes' are 0): row t < p d(Gamma_p^-1/2), later rows d su and
 * d(-su phi_l) = -su (dls_k phi_l + [l = k + 1]). */
static void darrows(int p, const ar_coef *ac, const double *phi, int a, int k, igea__arrow co[3])
{
    memset(co, 0, 3 * sizeof *co);
    for (int t = 0; t < p; t++)
        for (int s = 0; s <= t; s++)
            co[a].head[t][s] = ac[a].dli[k][t][s];
    co[a].diag = ac[a].su * ac[a].dls[k];
    for (int l = 1; l <= p; l++)
        co[a].lag[l] = -ac[a].su * (ac[a].dls[k] * phi[a * p + l - 1] + (l == k + 1));
}

/* The score of the restricted log-likelihood of the state S (its phi, the
 * dummies projected out; docs/eqerr.md)
 *   l = sum_i log T_ii - 1/2 sum_g n_g log c_g - sum_b log det R_b
 *       - 1/2 log pdet(sum_g N_g / c_g) - 1/2 sum_g Omega_g / c_g
 * (every row; n_g, N_g, Omega_g after the projection) at c: s[a p + k] =
 * dl / dphi_(a,k), s[3 p + g] = dl / dc_g; *lr (unless NULL) l itself
 * (lval). Returns 0, IGEA_EDOMAIN (phi not stationary) or a failure. */
static int score(const igea__njob *j, const igea__nstate *S, const double *c, reml_ws *w,
                 double *s, double *lr)
{
    const int m = j->m, Nt = j->Nt, n1 = Nt + 1, G = j->G, p = j->p, M = j->M;
    const double *phi = S->phi, *V = S->V;
    const igea__ndum *d = &S->d;
    ar_coef ac[3];
    for (int a = 0; a < 3; a++)
        if (ar_coefs(p, phi + a * p, &ac[a]))
            return IGEA_EDOMAIN;
    size_t nkb = 0, nkn = 0; /* the largest block's nr kb + kb and kb (Nt + 1) */
    for (int b = 0; b < d->nblk; b++) {
        size_t kb = (size_t)(d->boff[b + 1] - d->boff[b]), nr = (size_t)(d->roff[b + 1] - d->roff[b]);
        nkb = nr * kb + kb > nkb ? nr * kb + kb : nkb;
        nkn = kb * n1 > nkn ? kb * n1 : nkn;
    }
    double *Kb = d->nblk ? igea__dalloc(nkb + nkn) : NULL, *Mb = Kb ? Kb + nkb : NULL;
    if (d->nblk && !Kb)
        return IGEA_ENOMEM;
    int r = gls(j, S, c, w);
    if (r < 0) {
        free(Kb);
        return r;
    }
    if (lr) { /* the likelihood at c (one group: at its profile, which c is to rounding) */
        double cc = c[0];
        int sl = lval(j, S, G == 1 ? &cc : (double *)c, r, G == 1, w, lr);
        if (sl) {
            free(Kb);
            return sl;
        }
    }
    /* Y2 = X~_e N^+ */
    memset(w->Y2, 0, (size_t)m * Nt * sizeof(double));
    if (r > 0) {
        cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, Nt, r, 1.0, w->F, Nt, 0.0, w->Nt,
                    Nt); /* N^+ = F F' over Nt's scratch, lower triangle */
        cblas_dsymm(CblasColMajor, CblasRight, CblasLower, m, Nt, 1.0, w->Nt, Nt, V, m, 0.0,
                    w->Y2, m);
    }
    /* e = U_w - U_S x - D delta (stage 1, the dummies' fit delta_b = R_b^-1
     * (Z_w - Z_S x) at their rows), v = V_w - V_S x (whitened, projected) */
    memcpy(w->e, j->U + (size_t)Nt * m, (size_t)m * sizeof(double));
    memcpy(w->v, V + (size_t)Nt * m, (size_t)m * sizeof(double));
    cblas_dgemv(CblasColMajor, CblasNoTrans, m, Nt, -1.0, j->U, m, w->x, 1, 1.0, w->e, 1);
    cblas_dgemv(CblasColMajor, CblasNoTrans, m, Nt, -1.0, V, m, w->x, 1, 1.0, w->v, 1);
    for (int b = 0; b < d->nblk; b++) {
        const int kb = d->boff[b + 1] - d->boff[b];
        const double *Z = d->Z + (size_t)d->boff[b] * n1, *R = d->R + d->roff2[b];
        double *dl = Mb; /* free until below */
        for (int l = 0; l < kb; l++) {
            double t = Z[l + (size_t)Nt * kb];
            for (int cc = 0; cc < Nt; cc++)
                t -= Z[l + (size_t)cc * kb] * w->x[cc];
            dl[l] = t;
        }
        for (int l = kb - 1; l >= 0; l--) { /* R delta = Z_w - Z_S x */
            double t = dl[l];
            for (int l2 = l + 1; l2 < kb; l2++)
                t -= R[l + (size_t)l2 * kb] * dl[l2];
            dl[l] = t / R[l + (size_t)l * kb];
        }
        for (int l = 0; l < kb; l++) {
            int i = j->rej[d->dblk[d->boff[b] + l]], e0 = i - i % 3, a = i % 3;
            for (int rr = a; rr < 3; rr++)
                if (j->W1 ? j->W1[e0 + rr + (size_t)a * m] != 0.0 : rr == a)
                    w->e[e0 + rr] -= dl[l] * (j->W1 ? j->W1[e0 + rr + (size_t)a * m] : 1.0);
        }
    }
    /* hv = Y2_i . X~_e,i; H[0] = Y2_i . X~_i (the rows before the projection),
     * H[1 + l] = Y2_i . U_S,(i - 3 l) */
    double *HV = w->H;
    memset(w->H, 0, (size_t)(p + 2) * m * sizeof(double));
    for (int cc = 0; cc < Nt; cc++) {
        const double *y2 = w->Y2 + (size_t)cc * m, *vc = V + (size_t)cc * m;
        const double *uc = j->U + (size_t)cc * m;
        for (int i = 0; i < m; i++)
            HV[i] += y2[i] * vc[i];
        for (int l = 0; l <= p; l++) {
            double *h = w->H + (size_t)(1 + l) * m;
            for (int i = 3 * l; i < m; i++)
                h[i] += y2[i] * uc[i - 3 * l];
        }
    }
    memcpy(w->hv, HV, (size_t)m * sizeof(double));
    for (int b = 0; b < d->nblk; b++) {
        const int nr = d->roff[b + 1] - d->roff[b];
        const double *v0 = d->V0 + (size_t)d->roff[b] * n1;
        for (int q = 0; q < nr; q++) {
            int i = d->rows[d->roff[b] + q];
            double t = 0.0;
            for (int cc = 0; cc < Nt; cc++)
                t += w->Y2[i + (size_t)cc * m] * v0[q + (size_t)cc * nr];
            HV[i] = t;
        }
    }
    for (int k = 0; k < 3 * p + G; k++)
        s[k] = 0.0;
    /* phi: each row's d log T_ii - (Y2_i . dX~_i + v_i dv_i) / c_g, dX~ = dT U_S,
     * dv = dT e */
    for (int a = 0; a < 3; a++) {
        const ar_coef *o = &ac[a];
        for (int ep = 0; ep < M; ep++) {
            const int g = j->group ? j->group[ep] : 0, t = j->segpos[ep], i = 3 * ep + a;
            const double ci = c[g], vi = w->v[i];
            for (int k = 0; k < p; k++) {
                double dlt, dxy, dv;
                if (t >= p) {
                    dlt = o->dls[k];
                    dxy = o->dls[k] * HV[i] - o->su * w->H[(size_t)(2 + k) * m + i];
                    dv = o->dls[k] * vi - o->su * w->e[i - 3 * (k + 1)];
                } else {
                    dlt = o->dli[k][t][t] / o->linv[t][t];
                    dxy = dv = 0.0;
                    for (int l = 0; l <= t; l++) {
                        dxy += o->dli[k][t][l] * w->H[(size_t)(1 + t - l) * m + i];
                        dv += o->dli[k][t][l] * w->e[i - 3 * (t - l)];
                    }
                }
                s[a * p + k] += dlt - (dxy + vi * dv) / ci;
            }
        }
    }
    /* the dummies: sum over their images' derivatives dD_b of
     * K_b = Y2 (R_b^-1 Z_S,b)' / c_g - Q_b R_b^-T (the projection's share of
     * log pdet and log det R_b) */
    for (int b = 0; b < d->nblk; b++) {
        const int kb = d->boff[b + 1] - d->boff[b], nr = d->roff[b + 1] - d->roff[b];
        const int *rw = d->rows + d->roff[b];
        const double *Z = d->Z + (size_t)d->boff[b] * n1, *R = d->R + d->roff2[b];
        const double *Q = d->Q + d->qoff[b];
        const double cg = c[j->group ? j->group[rw[0] / 3] : 0];
        for (int cc = 0; cc < Nt; cc++) /* Mb = R^-1 Z_S (kb x Nt) */
            for (int l = kb - 1; l >= 0; l--) {
                double t = Z[l + (size_t)cc * kb];
                for (int l2 = l + 1; l2 < kb; l2++)
                    t -= R[l + (size_t)l2 * kb] * Mb[l2 + (size_t)cc * kb];
                Mb[l + (size_t)cc * kb] = t / R[l + (size_t)l * kb];
            }
        for (int q = 0; q < nr; q++) {
            double *x = Kb + (size_t)nr * kb; /* (Q R^-T)_q. = (R^-1 Q_q.')' */
            for (int l = kb - 1; l >= 0; l--) {
                double t = Q[q + (size_t)l * nr];
                for (int l2 = l + 1; l2 < kb; l2++)
                    t -= R[l + (size_t)l2 * kb] * x[l2];
                x[l] = t / R[l + (size_t)l * kb];
            }
            for (int l = 0; l < kb; l++) {
                double t = 0.0;
                for (int cc = 0; cc < Nt; cc++)
                    t += w->Y2[rw[q] + (size_t)cc * m] * Mb[l + (size_t)cc * kb];
                Kb[q + (size_t)l * nr] = t / cg - x[l];
            }
        }
        for (int a = 0; a < 3; a++)
            for (int k = 0; k < p; k++) {
                igea__arrow dco[3];
                int rows[12];
                double val[12], t = 0.0;
                darrows(p, ac, phi, a, k, dco);
                for (int l = 0; l < kb; l++) {
                    int n = igea__noise_ao_image(j, dco, j->rej[d->dblk[d->boff[b] + l]], rows,
                                                 val);
                    for (int u = 0; u < n; u++)
                        t += val[u] * Kb[d->rpos[rows[u]] + (size_t)l * nr];
                }
                s[a * p + k] += t;
            }
    }
    /* c_g: (Omega_g + tr(N^+ N_g)) / (2 c_g^2) - n_g / (2 c_g), zero at Helmert's
     * fixed point Omega_g = c_g r_g */
    double *sc = s + 3 * p;
    for (int i = 0; i < m; i++) {
        int g = j->group ? j->group[i / 3] : 0;
        sc[g] += w->v[i] * w->v[i] + w->hv[i];
    }
    for (int g = 0; g < G; g++)
        sc[g] = 0.5 * (sc[g] / c[g] - S->wtw[2 * g + 1]) / c[g];
    free(Kb);
    return igea__finite_vec(3 * p + G, s, 1) ? 0 : IGEA_EOVERFLOW;
}

/* The restricted log-likelihood of the state S (score()'s l, to a
 * constant) from the fit gls() left in w (rank r) at c. prof (one group):
 * c[0] is first replaced by its profile, the Helmert (REML) scale Omega /
 * (n - r), which does not depend on c there (the pseudo-determinant moves
 * by r log(c / c_new)). Returns 0 or a failure. */
static int lval(const igea__njob *j, const igea__nstate *S, double *c, int r, int prof,
                reml_ws *w, double *l)
{
    const int Nt = j->Nt, G = j->G, p = j->p;
    double v = -S->d.logdet, ld = 0.0, om[64];
    for (int k = 0; k < r; k++)
        ld += log(w->lam[k]);
    for (int g = 0; g < G; g++) {
        const double *Ag = S->A + (size_t)g * Nt * Nt, *bg = S->b + (size_t)g * Nt;
        double *Ax = w->bb;
        cblas_dsymv(CblasColMajor, CblasLower, Nt, 1.0, Ag, Nt, w->x, 1, 0.0, Ax, 1);
        om[g] = S->wtw[2 * g] - 2.0 * cblas_ddot(Nt, w->x, 1, bg, 1) +
                cblas_ddot(Nt, w->x, 1, Ax, 1);
    }
    if (prof && G == 1) {
        if (!(S->wtw[1] - r > 0.5))
            return IGEA_ERANK;
        if (!(om[0] > 0))
            return IGEA_EDOMAIN;
        double cn = om[0] / (S->wtw[1] - r);
        ld += r * log(c[0] / cn);
        c[0] = cn;
    }
    v -= 0.5 * ld;
    for (int g = 0; g < G; g++)
        v -= 0.5 * (S->wtw[2 * g + 1] * log(c[g]) + om[g] / c[g]);
    if (p > 0) { /* sum_i log T_ii: per axis, log (Gamma_p^-1/2)_tt for t < p, log su after */
        int cnt[PMAX + 1] = {0};
        for (int e = 0; e < j->M; e++)
            cnt[j->segpos[e] < p ? j->segpos[e] : p]++;
        for (int a = 0; a < 3; a++) {
            double li[PMAX][PMAX], su;
            if (igea__ar_setup(p, S->phi + a * p, li, &su))
                return IGEA_EDOMAIN;
            for (int t = 0; t < p; t++)
                v += cnt[t] * log(li[t][t]);
            v += cnt[p] * log(su);
        }
    }
    *l = v;
    return isfinite(v) ? 0 : IGEA_EOVERFLOW;
}

static int loglik(const igea__njob *j, const igea__nstate *S, double *c, int prof, reml_ws *w,
                  double *l)
{
    int r = gls(j, S, c, w);
    return r < 0 ? r : lval(j, S, c, r, prof, w, l);
}

/* Rows per group g and axis a (n[3 g + a]), less the rejected rows (each
 * takes one degree of freedom). */
static void kept_counts(const igea__njob *j, double *n)
{
    memset(n, 0, 3 * (size_t)j->G * sizeof(double));
    for (int i = 0; i < j->m; i++)
        n[3 * (j->group ? j->group[i / 3] : 0) + i % 3] += j->mask[i] ? 0.0 : 1.0;
}

/* The expected information of phi with the scales profiled out, to first
 * order in the rows (docs/eqerr.md): I_(ak,bl) = delta_ab n_a (2 dls_ak
 * dls_al + su_a^2 rho_a,|k-l|) - 2 dls_ak dls_bl sum_g n_ga n_gb / n_g,
 * into S (3 p x 3 p, column-major). */
static void profile_info(const igea__njob *j, const ar_coef *ac, const double *n, double *S)
{
    int p = j->p, q = 3 * p;
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < p; k++)
            for (int b = 0; b < 3; b++)
                for (int l = 0; l < p; l++) {
                    double cross = 0.0, na = 0.0;
                    for (int g = 0; g < j->G; g++) {
                        double ng = n[3 * g] + n[3 * g + 1] + n[3 * g + 2];
                        if (ng > 0)
                            cross += n[3 * g + a] * n[3 * g + b] / ng;
                        na += n[3 * g + a];
                    }
                    double v = -2.0 * ac[a].dls[k] * ac[b].dls[l] * cross;
                    if (a == b)
                        v += na * (2.0 * ac[a].dls[k] * ac[a].dls[l] +
                                   ac[a].su * ac[a].su * ac[a].rho[abs(k - l)]);
                    S[(a * p + k) + (size_t)(b * p + l) * q] = v;
                }
}

/* Solve the q x q SPD system S x = r (S destroyed: its Cholesky factor).
 * Returns 0 or 1 (not positive definite). */
static int spd_solve(int q, double *S, double *r)
{
    if (igea__chol_lower(q, S, q, 0.0) != 0)
        return 1;
    for (int i = 0; i < q; i++) {
        double t = r[i];
        for (int l = 0; l < i; l++)
            t -= S[i + (size_t)l * q] * r[l];
        r[i] = t / S[i + (size_t)i * q];
    }
    for (int i = q - 1; i >= 0; i--) {
        double t = r[i];
        for (int l = i + 1; l < q; l++)
            t -= S[l + (size_t)i * q] * r[l];
        r[i] = t / S[i + (size_t)i * q];
    }
    return 0;
}

/* 1 when every axis of phi (3 p) is stationary. */
static int stationary(int p, const double *phi)
{
    double li[PMAX][PMAX], su;
    for (int a = 0; a < 3; a++)
        if (igea__ar_setup(p, phi + a * p, li, &su))
            return 0;
    return 1;
}

/* H += y y' / y's - H s s' H / s'H s (BFGS), when the curvature y's > 0. */
static void bfgs(int q, double *H, const double *sv, const double *yv)
{
    double Hs[9], sHs = 0.0, ys = 0.0, nn = 0.0, ny = 0.0;
    for (int r = 0; r < q; r++) {
        Hs[r] = 0.0;
        for (int c = 0; c < q; c++)
            Hs[r] += H[r + (size_t)c * q] * sv[c];
        sHs += sv[r] * Hs[r];
        ys += yv[r] * sv[r];
        nn += sv[r] * sv[r];
        ny += yv[r] * yv[r];
    }
    if (!(ys > 1e-10 * sqrt(nn * ny)) || !(sHs > 0))
        return;
    for (int r = 0; r < q; r++)
        for (int c = 0; c < q; c++)
            H[r + (size_t)c * q] += yv[r] * yv[c] / ys - Hs[r] * Hs[c] / sHs;
}

/* AR(p) coefficients from z_k = atanh(kappa_k), kappa the partial
 * autocorrelations, by the Levinson recursion a_k^(k) = kappa_k, a_i^(k) =
 * a_i^(k-1) - kappa_k a_(k-i)^(k-1); Jz (p x p, [i + l p] = d phi_i / d z_l).
 * Every z gives a stationary phi (Barndorff-Nielsen & Schou 1973, Jones
 * 1980). */
static void phi_of_z(int p, const double *z, double *phi, double *Jz)
{
    double a[PMAX] = {0}, da[PMAX][PMAX] = {{0}};
    for (int k = 0; k < p; k++) {
        double kap = tanh(z[k]), dk = 1.0 - kap * kap;
        double na[PMAX], nda[PMAX][PMAX];
        for (int i = 0; i < k; i++) {
            na[i] = a[i] - kap * a[k - 1 - i];
            for (int l = 0; l < p; l++)
                nda[i][l] = da[i][l] - kap * da[k - 1 - i][l] - (l == k ? dk * a[k - 1 - i] : 0.0);
        }
        na[k] = kap;
        for (int l = 0; l < p; l++)
            nda[k][l] = l == k ? dk : 0.0;
        for (int i = 0; i <= k; i++) {
            a[i] = na[i];
            for (int l = 0; l < p; l++)
                da[i][l] = nda[i][l];
        }
    }
    for (int i = 0; i < p; i++) {
        phi[i] = a[i];
        for (int l = 0; l < p; l++)
            Jz[i + l * p] = da[i][l];
    }
}

/* The inverse (step-down recursion): z of a stationary phi. Returns 0 or 1
 * (a partial autocorrelation outside (-1, 1)). */
static int z_of_phi(int p, const double *phi, double *z)
{
    double a[PMAX];
    memcpy(a, phi, (size_t)p * sizeof(double));
    for (int k = p - 1; k >= 0; k--) {
        double kap = a[k];
        if (!(fabs(kap) < 1.0))
            return 1;
        z[k] = atanh(kap);
        double na[PMAX];
        for (int i = 0; i < k; i++)
            na[i] = (a[i] + kap * a[k - 1 - i]) / (1.0 - kap * kap);
        memcpy(a, na, (size_t)k * sizeof(double));
    }
    return 0;
}

int igea__noise_reml_step(igea__njob *j, double tol, double *d)
{
    const int p = j->p, q = 3 * p, G = j->G;
    reml_ws w;
    double *mem = ws_alloc(j, &w);
    double *n = igea__dalloc(3 * (size_t)G + (size_t)q + G);
    if (!mem || !n) {
        free(mem);
        free(n);
        return IGEA_ENOMEM;
    }
    double *s = n + 3 * (size_t)G, S[9 * 9], step[9], z[9], sz[9], Jz[3][PMAX * PMAX];
    ar_coef ac[3];
    double l0 = 0.0;
    int st = score(j, &j->st[j->cur], j->c, &w, s, G == 1 ? &l0 : NULL);
    for (int a = 0; st == 0 && a < 3; a++)
        if (ar_coefs(p, j->phi + a * p, &ac[a]) || z_of_phi(p, j->phi + a * p, z + a * p))
            st = IGEA_EDOMAIN;
    if (st == 0) {
        /* the score in z: Jz' s; the expected information: Jz' I Jz */
        double ph[PMAX];
        for (int a = 0; a < 3; a++)
            phi_of_z(p, z + a * p, ph, Jz[a]);
        for (int a = 0; a < 3; a++)
            for (int l = 0; l < p; l++) {
                sz[a * p + l] = 0.0;
                for (int i = 0; i < p; i++)
                    sz[a * p + l] += Jz[a][i + l * p] * s[a * p + i];
            }
        if (j->reml_have) { /* the profile's curvature along the last step */
            double sv[9], yv[9];
            for (int k = 0; k < q; k++) {
                sv[k] = z[k] - j->reml_z[k];
                yv[k] = j->reml_s[k] - sz[k];
            }
            bfgs(q, j->reml_H, sv, yv);
        }
        for (int tries = 0; tries < 2; tries++) {
            if (!j->reml_have || tries) {
                kept_counts(j, n);
                profile_info(j, ac, n, S);
                for (int a = 0; a < 3; a++) /* Jz' S Jz, block by block */
                    for (int b = 0; b < 3; b++)
                        for (int k = 0; k < p; k++)
                            for (int l = 0; l < p; l++) {
                                double t = 0.0;
                                for (int i = 0; i < p; i++)
                                    for (int r = 0; r < p; r++)
                                        t += Jz[a][i + k * p] * S[(a * p + i) + (size_t)(b * p + r) * q] *
                                             Jz[b][r + l * p];
                                j->reml_H[(a * p + k) + (size_t)(b * p + l) * q] = t;
                            }
            }
            memcpy(S, j->reml_H, (size_t)q * q * sizeof(double));
            memcpy(step, sz, (size_t)q * sizeof(double));
            if (spd_solve(q, S, step) == 0)
                break;
            st = tries ? IGEA_ERANK : 0;
        }
        memcpy(j->reml_z, z, (size_t)q * sizeof(double));
        memcpy(j->reml_s, sz, (size_t)q * sizeof(double));
        j->reml_have = 1;
    }
    if (st == 0) {
        /* a step of at most 1 in z, halved until the profile restricted
         * likelihood rises enough (Armijo, 1e-4 of the slope); phi(z) is
         * stationary for every z, the check guards the far tail (sigma_u
         * below 1e-7). The accepted trial state becomes the job's. */
        double big = 0.0, slope = 0.0, np[9], Jt[PMAX * PMAX];
        for (int k = 0; k < q; k++)
            big = fmax(big, fabs(step[k]));
        for (int k = 0; big > 1.0 && k < q; k++)
            step[k] /= big;
        for (int k = 0; k < q; k++)
            slope += sz[k] * step[k];
        double *ct = n, *rt = ct + G, *xt = igea__dalloc((size_t)j->Nt);
        int vit = 0, vconv = 0;
        if (!xt)
            st = IGEA_ENOMEM;
        /* several groups: the profile at the current phi as tight as at the
         * trial points (one group: score() gave l0 at its profile) */
        if (st == 0 && G > 1)
            st = igea__noise_vce_iterate(j->Nt, G, j->A, j->Nt, j->b, j->wtw, 1e-8, 200, ct, rt,
                                         xt, &vit, &vconv);
        if (st == 0 && G > 1)
            st = loglik(j, &j->st[j->cur], ct, 0, &w, &l0);
        *d = 0.0;
        igea__nstate *tr = &j->st[1 - j->cur];
        for (int h = 0; h < 40 && st == 0 && slope > 0; h++) {
            double zn[9], l1 = 0.0;
            for (int k = 0; k < q; k++)
                zn[k] = z[k] + step[k];
            for (int a = 0; a < 3; a++)
                phi_of_z(p, zn + a * p, np + a * p, Jt);
            double dn = 0.0;
            for (int k = 0; k < q; k++)
                dn = fmax(dn, fabs(np[k] - j->phi[k]));
            if (h > 0 && dn < 0.01 * tol)
                break; /* no cut rises: the maximum, to rounding */
            int ok = stationary(p, np);
            if (ok) {
                int s2 = igea__noise_state(j, np, tr);
                if (s2 == 0 && G > 1)
                    s2 = igea__noise_vce_iterate(j->Nt, G, tr->A, j->Nt, tr->b, tr->wtw,
                                                 1e-8, 200, ct, rt, xt, &vit, &vconv);
                if (G == 1)
                    ct[0] = j->c[0];
                if (s2 == 0)
                    s2 = loglik(j, tr, ct, G == 1, &w, &l1);
                if (s2 == 0 && G == 1) { /* the Helmert scale's redundancy and fit */
                    rt[0] = tr->wtw[1] - w.r;
                    memcpy(xt, w.x, (size_t)j->Nt * sizeof(double));
                }
                if (s2 != 0 && s2 != IGEA_EDOMAIN && s2 != IGEA_ERANK && s2 != IGEA_EOVERFLOW)
                    st = s2;
                ok = s2 == 0 && l1 >= l0 + 1e-4 * slope;
            }
            if (st == 0 && ok) {
                for (int k = 0; k < q; k++) {
                    *d = fmax(*d, fabs(np[k] - j->phi[k]));
                    j->phi[k] = np[k];
                }
                for (int g = 0; g < G; g++)
                    j->c[g] = ct[g], j->red[g] = rt[g];
                memcpy(j->x, xt, (size_t)j->Nt * sizeof(double));
                igea__noise_use(j, 1 - j->cur);
                break;
            }
            for (int k = 0; k < q; k++)
                step[k] *= 0.5;
            slope *= 0.5;
        }
        free(xt);
    }
    free(mem);
    free(n);
    return st;
}

/* Inverse of the q x q SPD matrix J in place (Cholesky); L (q^2) scratch.
 * Returns 0 or 1 (not positive definite). */
static int spd_inverse(int q, double *J, double *L)
{
    memcpy(L, J, (size_t)q * q * sizeof(double));
    if (igea__chol_lower(q, L, q, 0.0) != 0)
        return 1;
    for (int k = 0; k < q; k++) {
        double *x = J + (size_t)k * q;
        for (int i = 0; i < q; i++) {
            double t = (i == k);
            for (int l = 0; l < i; l++)
                t -= L[i + (size_t)l * q] * x[l];
            x[i] = t / L[i + (size_t)i * q];
        }
        for (int i = q - 1; i >= 0; i--) {
            double t = x[i];
            for (int l = i + 1; l < q; l++)
                t -= L[l + (size_t)i * q] * x[l];
            x[i] = t / L[i + (size_t)i * q];
        }
    }
    return 0;
}

/* The trial state at phi = th (when isphi; else nothing to do). */
static int at(const igea__njob *j, const double *th, int isphi, igea__nstate *tr)
{
    if (!isphi)
        return 0;
    return stationary(j->p, th) ? igea__noise_state(j, th, tr) : IGEA_EDOMAIN;
}

int igea__noise_reml_se(igea__njob *j)
{
    const int p = j->p, G = j->G, q = 3 * p + G;
    reml_ws w;
    double *mem = ws_alloc(j, &w);
    double *J = igea__dalloc(3 * (size_t)q * q + 4 * (size_t)q + 3 * (size_t)G);
    if (!mem || !J) {
        free(mem);
        free(J);
        return IGEA_ENOMEM;
    }
    double *L = J + (size_t)q * q, *sp = L + (size_t)q * q, *sm = sp + q, *s0 = sm + q;
    double *th = s0 + q, *n = th + q, *S = n + 3 * (size_t)G;
    memcpy(th, j->phi, 3 * (size_t)p * sizeof(double));
    memcpy(th + 3 * p, j->c, (size_t)G * sizeof(double));
    int st = score(j, &j->st[j->cur], j->c, &w, s0, NULL);
    igea__nstate *tr = &j->st[1 - j->cur]; /* the state at a moved phi */
    /* observed information -d score / d theta by central differences of the
     * analytic score (one-sided where phi +- h leaves the stationary region) */
    for (int col = 0; st == 0 && col < q; col++) {
        int isphi = col < 3 * p;
        double h = isphi ? 1e-5 : 1e-5 * th[col];
        double *tp = L; /* theta + h, reused */
        int up = 1, dn = 1;
        memcpy(tp, th, (size_t)q * sizeof(double));
        tp[col] = th[col] + h;
        int su = at(j, tp, isphi, tr);
        if (su == 0)
            su = score(j, isphi ? tr : &j->st[j->cur], tp + 3 * p, &w, sp, NULL);
        if (su == IGEA_EDOMAIN)
            up = 0;
        else if (su)
            st = su;
        tp[col] = th[col] - h;
        int sd = st ? 0 : at(j, tp, isphi, tr);
        if (st == 0 && sd == 0)
            sd = score(j, isphi ? tr : &j->st[j->cur], tp + 3 * p, &w, sm, NULL);
        if (sd == IGEA_EDOMAIN)
            dn = 0;
        else if (sd)
            st = sd;
        if (st)
            break;
        if (!up && !dn) {
            st = IGEA_EDOMAIN;
            break;
        }
        const double *hi = up ? sp : s0, *lo = dn ? sm : s0;
        double span = (up ? h : 0.0) + (dn ? h : 0.0);
        for (int r = 0; r < q; r++)
            J[r + (size_t)col * q] = -(hi[r] - lo[r]) / span;
    }
    if (st == 0) {
        for (int r = 0; r < q; r++) /* symmetrise */
            for (int col = r + 1; col < q; col++) {
                double v = 0.5 * (J[r + (size_t)col * q] + J[col + (size_t)r * q]);
                J[r + (size_t)col * q] = J[col + (size_t)r * q] = v;
            }
        if (spd_inverse(q, J, L) == 0 && igea__finite_vec(q * q, J, 1)) {
            for (int k = 0; k < 3 * p; k++)
                j->se[k] = sqrt(J[k + (size_t)k * q]);
            j->reml_se = j->row_w + j->m;
            for (int g = 0; g < G; g++)
                j->reml_se[g] = sqrt(J[(3 * p + g) * (size_t)(q + 1)]);
        } else {
            /* not positive definite (phi at the edge of the stationary
             * region): phi's se from the profile expected information, the
             * scales' from theirs alone (igea_noise_vce_cov) */
            ar_coef ac[3];
            for (int a = 0; a < 3; a++)
                ar_coefs(p, j->phi + a * p, &ac[a]);
            kept_counts(j, n);
            profile_info(j, ac, n, S);
            if (spd_inverse(3 * p, S, L) == 0)
                for (int k = 0; k < 3 * p; k++)
                    j->se[k] = sqrt(S[k + (size_t)k * 3 * p]);
        }
    }
    free(mem);
    free(J);
    return st;
}
