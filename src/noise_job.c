/* noise_job.c - igea_noise_eqerr: the equivalent-error job with per-epoch
 * covariance, AR(p) estimated by Cochrane-Orcutt iteration with the group
 * scales, per-group bias columns and the data-snooping robust route
 * (docs/eqerr.md, "Tracking noise beyond a diagonal K"). */
#include <float.h>

#include <cblas.h>
#include <lapacke.h>

#include "igea/noise.h"
#include "igea/stats.h"
#include "internal.h"
#include "noise_job.h"

/* whiten.c */
int igea__ar_setup(int p, const double *phi, double linv[][IGEA_NOISE_AR_MAX], double *su);
/* noise.c */
int igea__noise_vce_iterate(int N, int G, const double *A, int lda, const double *b,
                            const double *wtw, double tol, int maxit, double *c,
                            double *red, double *x, int *iters, int *conv);
int igea__noise_vce_cov(int N, int G, const double *A, int lda, const double *wtw,
                        const double *c, double *cov);

typedef igea__njob njob; /* noise_job.h */

static double opt_or(const double *o, int slot, double dflt)
{
    return o[slot] > 0 ? o[slot] : dflt;
}

/* Stage 1: [S D | bias indicators | dw] whitened by cov or the sigmas. */
static int stage1_rows(njob *j, const double *S, int lds, const double *dw,
                       const double *sig, int inc, const double *cov, const double *xcov,
                       const double *spec)
{
    int m = j->m, N = j->N, Nt = j->Nt;
    double *Sx = igea__dalloc((size_t)m * Nt + (size_t)Nt * Nt + (size_t)Nt + 2);
    igea_whiten *w = NULL;
    int st = Sx ? igea_whiten_create(Nt, 0, NULL, 1, &w) : IGEA_ENOMEM;
    if (st == 0) {
        for (int c = 0; c < N; c++)
            for (int i = 0; i < m; i++)
                Sx[i + (size_t)c * m] = S[i + (size_t)c * lds] * (spec ? spec[c] : 1.0);
        for (int c = N; c < Nt; c++) {
            int g = (c - N) / 3, a = (c - N) % 3;
            for (int i = 0; i < m; i++)
                Sx[i + (size_t)c * m] =
                    (i % 3 == a && (j->group ? j->group[i / 3] : 0) == g) ? 1.0 : 0.0;
        }
        double *A1 = Sx + (size_t)m * Nt, *b1 = A1 + (size_t)Nt * Nt, *w1 = b1 + Nt;
        memset(A1, 0, ((size_t)Nt * Nt + Nt + 2) * sizeof(double));
        st = xcov ? igea_whiten_accumulate_xcov(w, IGEA_COLMAJOR, m, Sx, m, dw, cov, xcov,
                                                NULL, NULL, A1, Nt, b1, w1, j->U, NULL)
                  : igea_whiten_accumulate(w, IGEA_COLMAJOR, m, Sx, m, dw, sig, inc, cov, NULL,
                                           NULL, NULL, A1, Nt, b1, w1, j->U, NULL);
    }
    igea_whiten_free(w);
    free(Sx);
    return st;
}

int igea__noise_state(const njob *j, const double *phi, igea__nstate *s)
{
    int m = j->m, Nt = j->Nt, G = j->G;
    igea_whiten *w = NULL;
    s->valid = 0;
    igea__ndum_free(&s->d); /* V is rewritten whole: nothing to restore */
    int st = igea_whiten_create(Nt, j->p, phi, G, &w);
    if (st == -3)
        return IGEA_EDOMAIN; /* an estimated phi that is not stationary */
    if (st)
        return st;
    memset(s->A0, 0, (size_t)G * Nt * Nt * sizeof(double));
    memset(s->b0, 0, (size_t)G * Nt * sizeof(double));
    memset(s->wtw0, 0, 2 * (size_t)G * sizeof(double));
    double one = 1.0;
    st = igea_whiten_accumulate(w, IGEA_COLMAJOR, m, j->U, m, j->U + (size_t)Nt * m, &one,
                                0, NULL, j->group, NULL, NULL, s->A0, Nt, s->b0, s->wtw0,
                                s->V, NULL);
    igea_whiten_free(w);
    for (int k = 0; k < 3 * j->p; k++)
        s->phi[k] = phi[k];
    if (st == 0)
        st = igea__noise_dummies(j, s);
    s->valid = st == 0;
    return st;
}

void igea__noise_use(njob *j, int k)
{
    j->cur = k;
    j->V = j->st[k].V;
    j->A = j->st[k].A;
    j->b = j->st[k].b;
    j->wtw = j->st[k].wtw;
}

/* The current state at the job's phi (whitened again only when phi moved). */
static int state_at_phi(njob *j)
{
    igea__nstate *s = &j->st[j->cur];
    if (s->valid && memcmp(s->phi, j->phi, 3 * (size_t)j->p * sizeof(double)) == 0)
        return 0;
    return igea__noise_state(j, j->phi, s);
}

/* The stage-1 images of the axis indicators, W1 (m x 3): column a holds
 * L_e^-1 e_a at each epoch's rows (with the epochs' covariances only; the
 * sigmas scale a row, which changes no span). */
static int stage1_images(njob *j)
{
    int m = j->m;
    double *E = igea__dalloc((size_t)m * 4 + 9 + 3 + 2);
    igea_whiten *w = NULL;
    int st = E ? igea_whiten_create(3, 0, NULL, 1, &w) : IGEA_ENOMEM;
    if (st == 0) {
        memset(E, 0, ((size_t)m * 4 + 14) * sizeof(double));
        for (int i = 0; i < m; i++)
            E[i + (size_t)(i % 3) * m] = 1.0;
        double *A = E + (size_t)m * 4, *b = A + 9, *wtw = b + 3;
        st = igea_whiten_accumulate(w, IGEA_COLMAJOR, m, E, m, E + (size_t)3 * m, NULL, 0,
                                    j->cov, NULL, NULL, NULL, A, 3, b, wtw, j->W1, NULL);
    }
    igea_whiten_free(w);
    free(E);
    return st;
}

static int cmp_abs(const void *a, const void *b)
{
    double x = fabs(*(const double *)a), y = fabs(*(const double *)b);
    return (x > y) - (x < y);
}

/* 1.4826 x the median |q_i| over the kept rows of group g; buf m scratch. */
static double mad_scale(const njob *j, int g, double *buf)
{
    int n = 0;
    for (int i = 0; i < j->m; i++)
        if (!j->mask[i] && (j->group ? j->group[i / 3] : 0) == g && isfinite(j->q[i]))
            buf[n++] = j->q[i];
    if (n == 0)
        return 0.0;
    qsort(buf, (size_t)n, sizeof(double), cmp_abs);
    double med = n % 2 ? fabs(buf[n / 2]) : 0.5 * (fabs(buf[n / 2 - 1]) + fabs(buf[n / 2]));
    return 1.4826 * med;
}

/* The w-test statistics, up to the scale, of the additive outlier at every
 * raw row not rejected (docs/eqerr.md, "Robust route"): with d_i the row's
 * whitened image, e~ the residual and X~_e the rows with the dummies
 * projected out (the current state),
 *   q_i = d_i'e~ / sqrt(d_i'(I - P_D)d_i - d_i'X~_e N^+ X~_e'd_i / c_g),
 * NaN where the denominator is <= 1e-10 d_i'd_i or the row is rejected. */
static int ao_stats(njob *j, int *rank)
{
    int m = j->m, Nt = j->Nt, G = j->G, cap = 3 * (j->p + 1);
    size_t nn = (size_t)Nt * Nt;
    double *Ntm = j->work, *F = Ntm + nn, *lam = F + nn, *t = lam + Nt;
    const igea__nstate *s = &j->st[j->cur];
    const igea__ndum *d = &s->d;
    igea__arrow co[3];
    if (igea__noise_arrows(j->p, s->phi, co))
        return IGEA_EDOMAIN;
    int r = igea__noise_pinv_factor(Nt, G, j->A, Nt, j->c, Ntm, lam, F);
    if (r < 0)
        return r;
    *rank = r;
    double *e = igea__dalloc((size_t)m + (size_t)r + (size_t)d->k + 2 * (size_t)cap);
    if (!e)
        return IGEA_ENOMEM;
    double *f = e + m, *u = f + r, *val = u + d->k;
    int rows[12], seen[12];
    for (int i = 0; i < Nt; i++) {
        double sb = 0.0;
        for (int g = 0; g < G; g++)
            sb += j->b[(size_t)g * Nt + i] / j->c[g];
        j->x[i] = sb;
    }
    cblas_dgemv(CblasColMajor, CblasTrans, Nt, r, 1.0, F, Nt, j->x, 1, 0.0, t, 1);
    cblas_dgemv(CblasColMajor, CblasNoTrans, Nt, r, 1.0, F, Nt, t, 1, 0.0, j->x, 1);
    if (r > 0) /* T = X~_e F, N^+ = F F' */
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, r, Nt, 1.0, j->V, m, F, Nt,
                    0.0, j->T, m);
    memcpy(e, j->V + (size_t)Nt * m, (size_t)m * sizeof(double));
    cblas_dgemv(CblasColMajor, CblasNoTrans, m, Nt, -1.0, j->V, m, j->x, 1, 1.0, e, 1);
    for (int i = 0; i < m; i++) {
        if (j->mask[i]) {
            j->q[i] = NAN;
            continue;
        }
        int n = igea__noise_ao_image(j, co, i, rows, val);
        double num = 0.0, dd = 0.0;
        for (int k = 0; k < r; k++)
            f[k] = 0.0;
        for (int l = 0; l < n; l++) {
            num += val[l] * e[rows[l]];
            dd += val[l] * val[l];
            for (int k = 0; k < r; k++)
                f[k] += val[l] * j->T[rows[l] + (size_t)k * m];
            seen[l] = 0;
        }
        double d0 = dd, h = 0.0;
        for (int l = 0; l < n; l++) { /* d_i'P_D d_i, block by block: |Q_b'd_i|^2 */
            int b = d->k ? d->rblk[rows[l]] : -1;
            if (b < 0 || seen[l])
                continue;
            int kb = d->boff[b + 1] - d->boff[b], nr = d->roff[b + 1] - d->roff[b];
            const double *Q = d->Q + d->qoff[b];
            for (int c = 0; c < kb; c++)
                u[c] = 0.0;
            for (int l2 = l; l2 < n; l2++)
                if (d->rblk[rows[l2]] == b) {
                    seen[l2] = 1;
                    for (int c = 0; c < kb; c++)
                        u[c] += val[l2] * Q[d->rpos[rows[l2]] + (size_t)c * nr];
                }
            for (int c = 0; c < kb; c++)
                dd -= u[c] * u[c];
        }
        for (int k = 0; k < r; k++)
            h += f[k] * f[k];
        h /= j->c[j->group ? j->group[i / 3] : 0];
        j->q[i] = dd - h > 1e-10 * d0 ? num / sqrt(dd - h) : NAN;
    }
    free(e);
    return 0;
}

/* The same statistics for the rejected rows, each as if it were not
 * rejected (the others kept), into wq[q] for rej[q]: the t-statistic of its
 * dummy's coefficient, which equals the w-test of the row added to the
 * model without it. Per block, delta = R^-1 (Z_w - Z_S x) and
 *   var(delta) = c_g R^-1 R^-T + M N^+ M',  M = R^-1 Z_S
 * (Q'e and the fit x are independent); wq = delta / sqrt(var / c_g). F (N^+ =
 * F F', rank r) and x as ao_stats left them. */
static int ao_back(const njob *j, int r, double *wq)
{
    const int Nt = j->Nt, n1 = Nt + 1;
    const double *F = j->work + (size_t)Nt * Nt;
    const igea__ndum *d = &j->st[j->cur].d;
    int kmax = 0;
    for (int b = 0; b < d->nblk; b++)
        kmax = IGEA_MAX(kmax, d->boff[b + 1] - d->boff[b]);
    double *Mb = igea__dalloc((size_t)kmax * (n1 + (size_t)r + (size_t)kmax + 1));
    if (!Mb)
        return IGEA_ENOMEM;
    for (int b = 0; b < d->nblk; b++) {
        const int kb = d->boff[b + 1] - d->boff[b];
        const double *Z = d->Z + (size_t)d->boff[b] * n1, *R = d->R + d->roff2[b];
        double *MF = Mb + (size_t)kb * n1, *Ri = MF + (size_t)kb * r, *del = Ri + (size_t)kb * kb;
        const double cg = j->c[j->group ? j->group[d->rows[d->roff[b]] / 3] : 0];
        for (int l = 0; l < kb; l++) { /* Z_w - Z_S x */
            double t = Z[l + (size_t)Nt * kb];
            for (int cc = 0; cc < Nt; cc++)
                t -= Z[l + (size_t)cc * kb] * j->x[cc];
            del[l] = t;
        }
        for (int cc = 0; cc <= kb + Nt; cc++) /* R^-1 [Z_S, I, Z_w - Z_S x] */
            for (int l = kb - 1; l >= 0; l--) {
                double t = cc < Nt ? Z[l + (size_t)cc * kb] : cc < Nt + kb ? (l == cc - Nt) : del[l];
                double *out = cc < Nt ? Mb + (size_t)cc * kb
                                      : cc < Nt + kb ? Ri + (size_t)(cc - Nt) * kb : del;
                for (int l2 = l + 1; l2 < kb; l2++)
                    t -= R[l + (size_t)l2 * kb] * out[l2];
                out[l] = t / R[l + (size_t)l * kb];
            }
        if (r > 0)
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, kb, r, Nt, 1.0, Mb, kb, F,
                        Nt, 0.0, MF, kb);
        for (int l = 0; l < kb; l++) {
            double v = 0.0;
            for (int l2 = 0; l2 < kb; l2++)
                v += Ri[l + (size_t)l2 * kb] * Ri[l + (size_t)l2 * kb];
            v *= cg;
            for (int k = 0; k < r; k++)
                v += MF[l + (size_t)k * kb] * MF[l + (size_t)k * kb];
            wq[d->dblk[d->boff[b] + l]] = v > 0 ? del[l] / sqrt(v / cg) : NAN;
        }
    }
    free(Mb);
    return 0;
}

/* The stage-1 rows a rejected raw row touches (its epoch's, where L_e^-1 e_a
 * is not 0), from the list. */
static void mask1_of(njob *j)
{
    memset(j->mask1, 0, (size_t)j->m * sizeof(int));
    for (int q = 0; q < j->nrej; q++) {
        int i = j->rej[q], a = i % 3, e0 = i - a;
        for (int r = a; r < 3; r++)
            if (j->W1 ? j->W1[e0 + r + (size_t)a * j->m] != 0.0 : r == a)
                j->mask1[e0 + r] = 1;
    }
}

/* Reject raw row i with statistic w (add = 1: a new dummy) or take back the
 * rejected row rej[i] (add = 0), then project the dummies out at the current
 * phi again. */
static int change_row(njob *j, int add, int i, double w)
{
    if (add) {
        int n = j->nrej;
        while (n > 0 && j->rej[n - 1] > i) {
            j->rej[n] = j->rej[n - 1];
            n--;
        }
        j->rej[n] = i;
        j->nrej++;
        j->row_w[i] = w;
        j->mask[i] = 1;
    } else {
        int r = j->rej[i];
        j->row_w[r] = 0.0;
        j->mask[r] = 0;
        for (int q = i; q + 1 < j->nrej; q++)
            j->rej[q] = j->rej[q + 1];
        j->nrej--;
    }
    mask1_of(j);
    return igea__noise_dummies(j, &j->st[j->cur]);
}

/* Data snooping at the current state: the largest |w| of the rows kept is
 * rejected while it exceeds the critical value, one row at a time; then the
 * rejected row of smallest |w| (as if kept) is taken back while it does not
 * exceed it, and the rejection resumes; until neither changes the rows.
 * *nchg: the rows rejected or taken back. */
static int snoop(njob *j, int *nchg)
{
    double *buf = j->T; /* reused after ao_stats' products: m doubles */
    double scale[64];   /* ngroups <= 64 (checked) */
    double *wq = igea__dalloc((size_t)j->maxrej + 1);
    int *moved = igea__ialloc((size_t)j->m); /* 1 rejected, 2 taken back in this call */
    int st = wq && moved ? 0 : IGEA_ENOMEM;
    *nchg = 0;
    if (moved)
        memset(moved, 0, (size_t)j->m * sizeof(int));
    for (;st == 0;) {
        int r = 0, imax = -1, qmin = -1;
        double wmax = 0.0, wmin = 0.0;
        if ((st = ao_stats(j, &r)))
            break;
        for (int g = 0; g < j->G; g++)
            scale[g] = mad_scale(j, g, buf);
        for (int i = 0; i < j->m; i++) {
            double s = scale[j->group ? j->group[i / 3] : 0];
            if (!isfinite(j->q[i]) || !(s > 0) || moved[i] == 2)
                continue;
            double w = j->q[i] / s;
            if (fabs(w) > fabs(wmax)) {
                wmax = w;
                imax = i;
            }
        }
        if (imax >= 0 && fabs(wmax) > j->kcrit && j->nrej < j->maxrej) {
            moved[imax] = 1;
            if ((st = change_row(j, 1, imax, wmax)))
                break;
            (*nchg)++;
            continue;
        }
        /* backward: the weakest rejected row */
        if (j->nrej == 0 || (st = ao_back(j, r, wq)))
            break;
        for (int q = 0; q < j->nrej; q++) {
            double s = scale[j->group ? j->group[j->rej[q] / 3] : 0];
            double w = s > 0 ? wq[q] / s : NAN;
            if (isfinite(w) && moved[j->rej[q]] != 1 && (qmin < 0 || fabs(w) < fabs(wmin))) {
                wmin = w;
                qmin = q;
            }
        }
        if (qmin < 0 || fabs(wmin) > j->kcrit)
            break;
        moved[j->rej[qmin]] = 2;
        if ((st = change_row(j, 0, qmin, 0.0)))
            break;
        (*nchg)++;
    }
    free(wq);
    free(moved);
    return st;
}

/* phi re-estimated from the stage-1 residuals U_w - U_S x (for p = 1 with
 * Kendall's correction when kendall is 1; kendall 0 is REML's start, made
 * stationary); *d the largest change. */
static int ar_update(njob *j, int kendall, double *d)
{
    int m = j->m, Nt = j->Nt;
    double *r = j->q, ph[9], se[9];
    memcpy(r, j->U + (size_t)Nt * m, (size_t)m * sizeof(double));
    cblas_dgemv(CblasColMajor, CblasNoTrans, m, Nt, -1.0, j->U, m, j->x, 1, 1.0, r, 1);
    int st = igea_noise_ar_fit(j->M, j->p, r, j->group, j->mask1, ph, se);
    if (st)
        return st;
    if (j->p == 1 && kendall) /* Kendall's small-sample correction, kept inside |phi| <= 0.995 */
        for (int a = 0; a < 3; a++) {
            double n = j->M - 1.0;
            if (n > 3)
                ph[a] += (1.0 + 3.0 * ph[a]) / n;
            ph[a] = fmax(-0.995, fmin(0.995, ph[a]));
        }
    if (!kendall) /* the REML start: shrunk toward 0 into the stationary region */
        for (int a = 0; a < 3; a++) {
            double li[IGEA_NOISE_AR_MAX][IGEA_NOISE_AR_MAX], su;
            for (int t = 0; t < 200 && igea__ar_setup(j->p, ph + a * j->p, li, &su); t++)
                for (int k = 0; k < j->p; k++)
                    ph[a * j->p + k] *= 0.95;
        }
    *d = 0.0;
    for (int k = 0; k < 3 * j->p; k++) {
        *d = fmax(*d, fabs(ph[k] - j->phi[k]));
        j->phi[k] = ph[k];
        j->se[k] = se[k];
    }
    return 0;
}

/* Helmert scales of the current sums (c, red, x of the job). */
static int vce_settle(njob *j, double tol, int *conv)
{
    int it = 0;
    /* the same iteration as igea_noise_vce (noise.c) */
    return igea__noise_vce_iterate(j->Nt, j->G, j->A, j->Nt, j->b, j->wtw, tol, 200,
                                   j->c, j->red, j->x, &it, conv);
}

/* The outer iteration: stage 2 at phi, snooping, Helmert, a step in phi,
 * until they settle (*conv 1). */
static int outer(njob *j, const double *o, int *iters, int *conv)
{
    const int est = o[IGEA_EQERR_OPT_AR_ESTIMATE] == 1 && j->p > 0;
    const int reml = est && o[IGEA_EQERR_OPT_AR_METHOD] == IGEA_NOISE_AR_REML;
    const int robust = o[IGEA_EQERR_OPT_ROBUST] == 1;
    const double tol = opt_or(o, IGEA_EQERR_OPT_NOISE_TOL, 1e-3);
    const int maxit = (int)opt_or(o, IGEA_EQERR_OPT_NOISE_MAX_ITER, 50);
    int st = 0;
    *conv = 0;
    for (int g = 0; g < j->G; g++)
        j->c[g] = 1.0;
    if (robust && j->W1 && (st = stage1_images(j)))
        return st;
    /* the rows are tested at the start and then only where phi and the
     * scales have settled for the rows kept: a test at a phi still far from
     * the data's (the least-squares start, biased low) rejects good rows */
    int settled = 0;
    for (int it = 0; it < maxit && st == 0; it++) {
        int nnew = 0, vconv = 0, tested = 0;
        double dphi = 0.0, dc = 0.0;
        *iters = it + 1;
        double cprev[64];
        for (int g = 0; g < j->G; g++)
            cprev[g] = j->c[g];
        if ((st = state_at_phi(j)))
            break;
        if (robust && (it == 0 || !est || settled)) {
            if ((st = snoop(j, &nnew)))
                break;
            tested = 1;
        }
        if (nnew > 0) /* the likelihood changed: REML restarts its curvature */
            j->reml_have = 0;
        if ((st = vce_settle(j, tol * 0.1, &vconv)))
            break;
        for (int g = 0; g < j->G && j->G > 1; g++)
            dc = fmax(dc, fabs(j->c[g] / cprev[g] - 1.0));
        /* REML: quasi-Newton steps from the least-squares start (docs/eqerr.md) */
        if (est && (st = reml && it > 0 ? igea__noise_reml_step(j, tol, &dphi)
                                        : ar_update(j, !reml, &dphi)))
            break;
        settled = dphi <= tol && dc <= tol && vconv && (nnew == 0 || !est);
        if (settled && nnew == 0 && (tested || !robust)) {
            *conv = 1;
            break;
        }
    }
    /* the sums of the last phi estimate (the one reported) */
    if (st == 0 && est && (st = state_at_phi(j)) == 0) {
        int vconv = 0;
        st = vce_settle(j, tol * 0.1, &vconv);
        *conv = *conv && vconv;
    }
    if (st == 0 && reml) /* phi's and the scales' se from their joint information */
        st = igea__noise_reml_se(j);
    return st;
}

/* The final weighted normal equations of the N terms: sum A_g / c_g (c = 1
 * for one group), the bias columns eliminated (Schur complement with the
 * pseudo-inverse of their block). Ar (N x N), br (N); scratch work. */
static int reduce(const njob *j, double *Ar, double *br)
{
    int Nt = j->Nt, N = j->N, nb = j->nb, G = j->G;
    size_t nn = (size_t)Nt * Nt;
    double *At = igea__dalloc(nn + Nt + 2 * (size_t)nb * nb + (size_t)nb + (size_t)N * nb);
    if (!At)
        return IGEA_ENOMEM;
    double *bt = At + nn, *An = bt + Nt, *F = An + (size_t)nb * nb, *lam = F + (size_t)nb * nb;
    double *Y = lam + nb;
    for (size_t k = 0; k < nn; k++) {
        double s = 0.0;
        for (int g = 0; g < G; g++)
            s += j->A[(size_t)g * nn + k] / (G > 1 ? j->c[g] : 1.0);
        At[k] = s;
    }
    for (int i = 0; i < Nt; i++) {
        double s = 0.0;
        for (int g = 0; g < G; g++)
            s += j->b[(size_t)g * Nt + i] / (G > 1 ? j->c[g] : 1.0);
        bt[i] = s;
    }
    for (int c = 0; c < N; c++) {
        memcpy(Ar + (size_t)c * N, At + (size_t)c * Nt, (size_t)N * sizeof(double));
        br[c] = bt[c];
    }
    int st = 0;
    if (nb > 0) {
        for (int c = 0; c < nb; c++)
            for (int i = 0; i < nb; i++)
                An[i + (size_t)c * nb] = At[(N + i) + (size_t)(N + c) * Nt];
        st = igea__syev_desc(nb, An, nb, lam, F, nb);
        int r = st ? 0 : igea__rank_cut(nb, lam, nb * 10.0 * DBL_EPSILON);
        for (int k = 0; k < r; k++)
            cblas_dscal(nb, 1.0 / sqrt(lam[k]), F + (size_t)k * nb, 1);
        if (st == 0 && r > 0) {
            /* Y = A_tn F (N x r); Ar -= Y Y'; br -= Y F' b_n */
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, N, r, nb, 1.0,
                        At + (size_t)N * Nt, Nt, F, nb, 0.0, Y, N);
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, N, N, r, -1.0, Y, N, Y, N,
                        1.0, Ar, N);
            double t[3 * 64];
            cblas_dgemv(CblasColMajor, CblasTrans, nb, r, 1.0, F, nb, bt + N, 1, 0.0, t, 1);
            cblas_dgemv(CblasColMajor, CblasNoTrans, N, r, -1.0, Y, N, t, 1, 1.0, br, 1);
        }
    }
    free(At);
    return st;
}

static int job_args(int m, int N, const double *S, int lds, const double *dw,
                    const double *sig, int inc, const double *cov, const int *group,
                    int G, const double *opts)
{
    if (m < 3 || m % 3) return -1;
    if (N < 1) return -2;
    if (!S) return -3;
    if (lds < m) return -4;
    if (!dw) return -5;
    if ((!sig && !cov) || (sig && cov)) return -6;
    if (inc != 0 && inc != 1) return -7;
    if (G < 1 || G > 64) return -10;
    if (G > 1 && !group) return -9;
    for (int g = 0; g < G; g++) {
        int n = 0;
        for (int e = 0; e < m / 3 && !n; e++)
            n = (group ? group[e] : 0) == g;
        if (!n) return -9;
    }
    for (int e = 0; group && e < m / 3; e++)
        if (group[e] < 0 || group[e] >= G) return -9;
    if (opts && igea_eqerr_check_opts(opts)) return -13;
    return 0;
}

static void job_free(njob *j)
{
    for (int k = 0; k < 2; k++)
        igea__ndum_free(&j->st[k].d);
    free(j->U);
    free(j->mask);
}

/* The sums of a state at s (G Nt^2 + G Nt + 2 G, twice); V at v. */
static double *state_place(igea__nstate *s, double *v, double *p, size_t m, size_t n1, size_t G,
                           size_t Nt)
{
    s->V = v;
    (void)m;
    (void)n1;
    s->A = p;
    s->b = s->A + G * Nt * Nt;
    s->wtw = s->b + G * Nt;
    s->A0 = s->wtw + 2 * G;
    s->b0 = s->A0 + G * Nt * Nt;
    s->wtw0 = s->b0 + G * Nt;
    return s->wtw0 + 2 * G;
}

/* The job's arrays: two states when phi is estimated by REML (the trial
 * point of its line search), the stage-1 images W1 for the robust route
 * with the epochs' covariances. */
static int job_alloc(njob *j, const double *o)
{
    const int two = o[IGEA_EQERR_OPT_AR_ESTIMATE] == 1 && j->p > 0 &&
                    o[IGEA_EQERR_OPT_AR_METHOD] == IGEA_NOISE_AR_REML;
    const int images = o[IGEA_EQERR_OPT_ROBUST] == 1 && j->cov;
    size_t m = (size_t)j->m, n1 = (size_t)j->Nt + 1, G = (size_t)j->G, Nt = (size_t)j->Nt;
    size_t ns = 2 * (G * Nt * Nt + G * Nt + 2 * G), nst = two ? 2 : 1;
    size_t nd = (1 + nst) * m * n1 + nst * ns + 2 * G + Nt + (2 * Nt * Nt + 3 * Nt) + m * Nt +
                2 * m + G + (images ? 4 * m : 0);
    j->U = igea__dalloc(nd);
    j->mask = igea__ialloc(3 * m + (size_t)j->M + 1);
    if (!j->U || !j->mask) {
        job_free(j);
        return IGEA_ENOMEM;
    }
    memset(j->U, 0, nd * sizeof(double));
    memset(j->mask, 0, (3 * m + (size_t)j->M + 1) * sizeof(int));
    j->mask1 = j->mask + m;
    j->rej = j->mask1 + m;
    j->segpos = j->rej + m;
    for (int e = 0; e < j->M; e++) /* a change of group starts a segment */
        j->segpos[e] = e > 0 && (!j->group || j->group[e] == j->group[e - 1])
                           ? j->segpos[e - 1] + 1 : 0;
    double *p = j->U + m * n1;
    for (size_t k = 0; k < nst; k++) {
        double *v = p;
        p = state_place(&j->st[k], v, v + m * n1, m, n1, G, Nt);
    }
    j->c = p;
    j->red = j->c + G;
    j->x = j->red + G;
    j->work = j->x + Nt;
    j->T = j->work + 2 * Nt * Nt + 3 * Nt;
    j->q = j->T + m * Nt;
    j->row_w = j->q + m;
    j->reml_se = NULL; /* set (row_w + m, G doubles) by igea__noise_reml_se */
    j->W1 = images ? j->row_w + m + G : NULL;
    igea__noise_use(j, 0);
    return 0;
}

/* Outputs of a successful job beyond those of igea_eqerr_solve. */
static void job_out(const njob *j, int iters, int conv, const double *ccov, double *info,
                    double *ar_out, double *group_out, double *row_w)
{
    info[IGEA_STATS_INFO_NOISE_ITERATIONS] = iters;
    info[IGEA_STATS_INFO_NOISE_CONVERGED] = conv;
    info[IGEA_STATS_INFO_N_OUTLIERS] = j->nrej;
    info[IGEA_STATS_INFO_N_GROUPS] = j->G;
    info[IGEA_STATS_INFO_N_NUISANCE] = j->nb;
    info[IGEA_STATS_INFO_AR_ORDER] = j->p;
    info[IGEA_STATS_INFO_ROBUST_CRIT] = j->kcrit;
    if (ar_out) {
        for (int k = 0; k < IGEA_NOISE_AR_OUT_LEN; k++)
            ar_out[k] = 0.0;
        for (int a = 0; a < 3; a++)
            for (int k = 0; k < j->p; k++) {
                ar_out[3 * a + k] = j->phi[a * j->p + k];
                ar_out[9 + 3 * a + k] = j->se[a * j->p + k];
            }
    }
    for (int g = 0; group_out && g < j->G; g++) {
        double *o = group_out + (size_t)g * IGEA_NOISE_GROUP_COLS;
        for (int k = 0; k < IGEA_NOISE_GROUP_COLS; k++)
            o[k] = 0.0;
        o[IGEA_NOISE_GROUP_SCALE] = j->c[g];
        o[IGEA_NOISE_GROUP_SE] = j->c[g] * sqrt(2.0 / j->red[g]);
        o[IGEA_NOISE_GROUP_REDUND] = j->red[g];
        o[IGEA_NOISE_GROUP_SE_REML] = j->reml_se ? j->reml_se[g] : sqrt(ccov[g + (size_t)g * j->G]);
        o[IGEA_NOISE_GROUP_ROWS] = j->wtw[2 * g + 1];
        for (int a = 0; a < 3 && j->nb; a++)
            o[IGEA_NOISE_GROUP_BIAS + a] = j->x[j->N + 3 * g + a];
    }
    if (row_w)
        memcpy(row_w, j->row_w, (size_t)j->m * sizeof(double));
}

/* The whitened residuals of the final full-rank fit: (w~_i - S~_i x) / sqrt(c_g)
 * (c_g only with two or more groups); a rejected row's is that of its row
 * before the dummies were projected out (its one-step prediction error). */
static void job_resid(const njob *j, double *resid)
{
    int m = j->m, Nt = j->Nt;
    const igea__ndum *d = &j->st[j->cur].d;
    for (int i = 0; i < m; i++) {
        const double *v = j->V + i;
        size_t ld = (size_t)m;
        if (j->mask[i] && d->k && d->rblk[i] >= 0) {
            int b = d->rblk[i];
            ld = (size_t)(d->roff[b + 1] - d->roff[b]);
            v = d->V0 + (size_t)d->roff[b] * (Nt + 1) + d->rpos[i];
        }
        double e = v[(size_t)Nt * ld];
        for (int c = 0; c < Nt; c++)
            e -= v[(size_t)c * ld] * j->x[c];
        int g = j->group ? j->group[i / 3] : 0;
        resid[i] = j->G > 1 ? e / sqrt(j->c[g]) : e;
    }
}

static int noise_job(int m, int N, const double *S, int lds, const double *dw,
                     const double *track_sigma, int sigma_inc, const double *cov,
                     const double *xcov, const int *group, int ngroups,
                     const double *spec_sigma, const double *phi, const double *opts,
                     double *lambda, double *P, int ldp, double *equiv_err, double *z,
                     int *reject, double *info, double *ar_out, double *group_out,
                     double *row_w, double *resid);

int igea_noise_eqerr(int m, int N, const double *S, int lds, const double *dw,
                     const double *track_sigma, int sigma_inc, const double *cov,
                     const int *group, int ngroups, const double *spec_sigma,
                     const double *phi, const double *opts, double *lambda, double *P,
                     int ldp, double *equiv_err, double *z, int *reject, double *info,
                     double *ar_out, double *group_out, double *row_w)
{
    return noise_job(m, N, S, lds, dw, track_sigma, sigma_inc, cov, NULL, group, ngroups,
                     spec_sigma, phi, opts, lambda, P, ldp, equiv_err, z, reject, info, ar_out, group_out,
                     row_w, NULL);
}

int igea_noise_eqerr_resid(int m, int N, const double *S, int lds, const double *dw,
                           const double *track_sigma, int sigma_inc, const double *cov,
                           const int *group, int ngroups, const double *spec_sigma,
                           const double *phi, const double *opts, double *lambda, double *P,
                           int ldp, double *equiv_err, double *z, int *reject, double *info,
                           double *ar_out, double *group_out, double *row_w, double *resid)
{
    if (!resid)
        return -24;
    return noise_job(m, N, S, lds, dw, track_sigma, sigma_inc, cov, NULL, group, ngroups,
                     spec_sigma, phi, opts, lambda, P, ldp, equiv_err, z, reject, info, ar_out, group_out,
                     row_w, resid);
}

static int noise_job(int m, int N, const double *S, int lds, const double *dw,
                     const double *track_sigma, int sigma_inc, const double *cov,
                     const double *xcov, const int *group, int ngroups,
                     const double *spec_sigma, const double *phi, const double *opts,
                     double *lambda, double *P, int ldp, double *equiv_err, double *z,
                     int *reject, double *info, double *ar_out, double *group_out,
                     double *row_w, double *resid)
{
    double dflt[IGEA_EQERR_OPT_LEN];
    int st = job_args(m, N, S, lds, dw, track_sigma, sigma_inc, cov, group, ngroups, opts);
    if (st)
        return st;
    if (!opts) {
        igea_eqerr_defaults(dflt);
        opts = dflt;
    }
    if (!lambda) return -14;
    if (!P) return -15;
    if (ldp < N) return -16;
    if (!equiv_err) return -17;
    if (!z) return -18;
    if (!reject) return -19;
    if (!info) return -20;
    njob j;
    memset(&j, 0, sizeof j);
    j.m = m;
    j.N = N;
    j.M = m / 3;
    j.G = ngroups;
    j.group = group;
    j.cov = cov;
    j.p = (int)opts[IGEA_EQERR_OPT_AR];
    j.nb = opts[IGEA_EQERR_OPT_GROUP_BIAS] == 1 ? 3 * ngroups : 0;
    j.Nt = N + j.nb;
    if (j.p > 0 && phi && !igea__finite_vec(3 * j.p, phi, 1))
        return IGEA_ENONFINITE;
    for (int k = 0; k < 3 * j.p; k++)
        j.phi[k] = phi ? phi[k] : 0.0;
    if (j.p > 0 && opts[IGEA_EQERR_OPT_AR_ESTIMATE] != 1) {
        igea_whiten *w = NULL;
        st = igea_whiten_create(1, j.p, j.phi, 1, &w);
        igea_whiten_free(w);
        if (st == -3)
            return -12;
        if (st)
            return st;
    }
    if (spec_sigma && (st = igea__sigma_vec(N, spec_sigma)))
        return st;
    double a0 = opt_or(opts, IGEA_EQERR_OPT_ROBUST_ALPHA, 1e-3);
    igea_stats_normal_quantile(1.0 - a0 / 2.0, &j.kcrit);
    j.maxrej = (int)floor(opt_or(opts, IGEA_EQERR_OPT_ROBUST_MAX, 0.05) * m);
    if ((st = job_alloc(&j, opts)))
        return st;
    double *Ar = igea__dalloc((size_t)N * N + (size_t)N + (size_t)ngroups * ngroups);
    int iters = 0, conv = 0;
    st = Ar ? stage1_rows(&j, S, lds, dw, track_sigma, sigma_inc, cov, xcov, spec_sigma)
            : IGEA_ENOMEM;
    if (st == 0)
        st = outer(&j, opts, &iters, &conv);
    double *ccov = Ar ? Ar + (size_t)N * N + N : NULL;
    if (st == 0) /* before reduce: j.A holds the groups' sums of the final fit */
        st = igea__noise_vce_cov(j.Nt, j.G, j.A, j.Nt, j.wtw, j.c, ccov);
    if (st == 0)
        st = reduce(&j, Ar, Ar + (size_t)N * N);
    if (st == 0) {
        double inf[IGEA_STATS_INFO_LEN];
        st = igea_eqerr_solve(N, Ar, N, Ar + (size_t)N * N, opts, lambda, P, ldp, equiv_err,
                              z, reject, inf);
        if (st == 0) {
            memcpy(info, inf, sizeof inf);
            job_out(&j, iters, conv, ccov, info, ar_out, group_out, row_w);
            if (resid)
                job_resid(&j, resid);
        }
    }
    free(Ar);
    job_free(&j);
    return st;
}

int igea_noise_eqerr_xcov(int m, int N, const double *S, int lds, const double *dw,
                          const double *cov, const double *xcov, const double *spec_sigma,
                          const double *opts, double *lambda, double *P, int ldp,
                          double *equiv_err, double *z, int *reject, double *info,
                          double *group_out, double *row_w, double *resid)
{
    if (m < 3 || m % 3) return -1;
    if (N < 1) return -2;
    if (!S) return -3;
    if (lds < m) return -4;
    if (!dw) return -5;
    if (!cov) return -6;
    if (!xcov) return -7;
    if (opts && (igea_eqerr_check_opts(opts) || opts[IGEA_EQERR_OPT_AR] != 0)) return -9;
    if (!lambda) return -10;
    if (!P) return -11;
    if (ldp < N) return -12;
    if (!equiv_err) return -13;
    if (!z) return -14;
    if (!reject) return -15;
    if (!info) return -16;
    return noise_job(m, N, S, lds, dw, NULL, 1, cov, xcov, NULL, 1, spec_sigma, NULL, opts,
                     lambda, P, ldp, equiv_err, z, reject, info, NULL, group_out, row_w, resid);
}
