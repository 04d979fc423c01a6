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

int igea__noise_stage2(const njob *j, const double *phi, double *V, double *A, double *b,
                       double *wtw)
{
    int m = j->m, Nt = j->Nt, G = j->G;
    igea_whiten *w = NULL;
    int st = igea_whiten_create(Nt, j->p, phi, G, &w);
    if (st == -3)
        return IGEA_EDOMAIN; /* an estimated phi that is not stationary */
    if (st)
        return st;
    memset(A, 0, (size_t)G * Nt * Nt * sizeof(double));
    memset(b, 0, (size_t)G * Nt * sizeof(double));
    memset(wtw, 0, 2 * (size_t)G * sizeof(double));
    double one = 1.0;
    st = igea_whiten_accumulate(w, IGEA_COLMAJOR, m, j->U, m, j->U + (size_t)Nt * m, &one,
                                0, NULL, j->group, j->mask, NULL, A, Nt, b, wtw, V, NULL);
    igea_whiten_free(w);
    return st;
}

/* Stage 2 with the current phi and mask into V and the group sums. */
static int stage2_sums(njob *j)
{
    return igea__noise_stage2(j, j->phi, j->V, j->A, j->b, j->wtw);
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

/* Standardised residuals q_i = e_i / sqrt(1 - h_ii) of the kept rows (NaN
 * where 1 - h_ii <= 1e-10 or masked) at the current c. */
static int std_residuals(njob *j)
{
    int m = j->m, Nt = j->Nt, G = j->G;
    size_t nn = (size_t)Nt * Nt;
    double *Ntm = j->work, *F = Ntm + nn, *lam = F + nn, *t = lam + Nt;
    int r = 0;
    for (int g = 0; g < G; g++) /* pinv of sum A_g / c_g */
        for (int cc = 0; cc < Nt; cc++)
            for (int i = cc; i < Nt; i++)
                Ntm[i + (size_t)cc * Nt] = (g ? Ntm[i + (size_t)cc * Nt] : 0.0) +
                                           j->A[(size_t)g * nn + i + (size_t)cc * Nt] / j->c[g];
    int st = igea__syev_desc(Nt, Ntm, Nt, lam, F, Nt);
    if (st)
        return st;
    r = igea__rank_cut(Nt, lam, Nt * 10.0 * DBL_EPSILON);
    for (int k = 0; k < r; k++)
        cblas_dscal(Nt, 1.0 / sqrt(lam[k]), F + (size_t)k * Nt, 1);
    for (int i = 0; i < Nt; i++) {
        double s = 0.0;
        for (int g = 0; g < G; g++)
            s += j->b[(size_t)g * Nt + i] / j->c[g];
        j->x[i] = s;
    }
    cblas_dgemv(CblasColMajor, CblasTrans, Nt, r, 1.0, F, Nt, j->x, 1, 0.0, t, 1);
    cblas_dgemv(CblasColMajor, CblasNoTrans, Nt, r, 1.0, F, Nt, t, 1, 0.0, j->x, 1);
    if (r > 0)
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, r, Nt, 1.0, j->V, m, F, Nt,
                    0.0, j->T, m);
    const double *wv = j->V + (size_t)Nt * m;
    for (int i = 0; i < m; i++)
        j->q[i] = wv[i];
    cblas_dgemv(CblasColMajor, CblasNoTrans, m, Nt, -1.0, j->V, m, j->x, 1, 1.0, j->q, 1);
    for (int i = 0; i < m; i++) {
        double h = 0.0;
        for (int k = 0; k < r; k++)
            h += j->T[i + (size_t)k * m] * j->T[i + (size_t)k * m];
        h /= j->c[j->group ? j->group[i / 3] : 0];
        j->q[i] = (j->mask[i] || !(1.0 - h > 1e-10)) ? NAN : j->q[i] / sqrt(1.0 - h);
    }
    return 0;
}

/* Remove whitened row i from its group's sums. */
static void downdate(njob *j, int i)
{
    int m = j->m, Nt = j->Nt, g = j->group ? j->group[i / 3] : 0;
    double *Ag = j->A + (size_t)g * Nt * Nt, *bg = j->b + (size_t)g * Nt;
    const double *wv = j->V + (size_t)Nt * m;
    for (int cc = 0; cc < Nt; cc++) {
        double vc = j->V[i + (size_t)cc * m];
        for (int r = 0; r < Nt; r++)
            Ag[r + (size_t)cc * Nt] -= j->V[i + (size_t)r * m] * vc;
        bg[cc] -= vc * wv[i];
    }
    j->wtw[2 * g] = fmax(0.0, j->wtw[2 * g] - wv[i] * wv[i]);
    j->wtw[2 * g + 1] -= 1.0;
    j->mask[i] = 1;
}

/* Iterated data snooping (one row at a time); *nnew rows rejected. */
static int snoop(njob *j, int *nnew)
{
    double *buf = j->T; /* reused after std_residuals' h: m doubles */
    double scale[64]; /* ngroups <= 64 (checked) */
    *nnew = 0;
    while (j->nrej < j->maxrej) {
        int st = std_residuals(j);
        if (st)
            return st;
        for (int g = 0; g < j->G; g++)
            scale[g] = mad_scale(j, g, buf);
        int imax = -1;
        double wmax = 0.0;
        for (int i = 0; i < j->m; i++) {
            double s = scale[j->group ? j->group[i / 3] : 0];
            if (!isfinite(j->q[i]) || !(s > 0))
                continue;
            double w = j->q[i] / s;
            if (fabs(w) > fabs(wmax)) {
                wmax = w;
                imax = i;
            }
        }
        if (imax < 0 || !(fabs(wmax) > j->kcrit))
            break;
        j->row_w[imax] = wmax;
        downdate(j, imax);
        j->nrej++;
        (*nnew)++;
    }
    return 0;
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
    int st = igea_noise_ar_fit(j->M, j->p, r, j->group, j->mask, ph, se);
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

/* The outer iteration: stage 2, snooping, Helmert, phi, until they settle
 * (*conv 1). */
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
    for (int it = 0; it < maxit && st == 0; it++) {
        int nnew = 0, vconv = 0;
        double dphi = 0.0, dc = 0.0;
        *iters = it + 1;
        double cprev[64];
        for (int g = 0; g < j->G; g++)
            cprev[g] = j->c[g];
        if ((st = stage2_sums(j)))
            break;
        if (robust && (st = snoop(j, &nnew)))
            break;
        if (nnew > 0) /* the likelihood changed: REML restarts its curvature */
            j->reml_have = 0;
        if ((st = vce_settle(j, tol * 0.1, &vconv)))
            break;
        for (int g = 0; g < j->G && j->G > 1; g++)
            dc = fmax(dc, fabs(j->c[g] / cprev[g] - 1.0));
        /* REML: Fisher scoring from the least-squares start (docs/eqerr.md) */
        if (est && (st = reml && it > 0 ? igea__noise_reml_step(j, &dphi)
                                        : ar_update(j, !reml, &dphi)))
            break;
        if (dphi <= tol && dc <= tol && nnew == 0 && vconv) {
            *conv = 1;
            break;
        }
    }
    /* the sums of the last phi estimate (the one reported) */
    if (st == 0 && est && (st = stage2_sums(j)) == 0) {
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
    free(j->U);
    free(j->mask);
}

static int job_alloc(njob *j)
{
    size_t m = (size_t)j->m, n1 = (size_t)j->Nt + 1, G = (size_t)j->G, Nt = (size_t)j->Nt;
    size_t nd = 2 * m * n1 + G * Nt * Nt + G * Nt + 4 * G + Nt + (2 * Nt * Nt + 3 * Nt) +
                m * Nt + 2 * m + G;
    j->U = igea__dalloc(nd);
    j->mask = igea__ialloc(m);
    if (!j->U || !j->mask) {
        job_free(j);
        return IGEA_ENOMEM;
    }
    memset(j->U, 0, nd * sizeof(double));
    memset(j->mask, 0, m * sizeof(int));
    j->V = j->U + m * n1;
    j->A = j->V + m * n1;
    j->b = j->A + G * Nt * Nt;
    j->wtw = j->b + G * Nt;
    j->c = j->wtw + 2 * G;
    j->red = j->c + G;
    j->x = j->red + G;
    j->work = j->x + Nt;
    j->T = j->work + 2 * Nt * Nt + 3 * Nt;
    j->q = j->T + m * Nt;
    j->row_w = j->q + m;
    j->reml_se = NULL; /* set (row_w + m, G doubles) by igea__noise_reml_se */
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
 * (c_g only with two or more groups), rejected rows included. */
static void job_resid(const njob *j, double *resid)
{
    int m = j->m, Nt = j->Nt;
    for (int i = 0; i < m; i++) {
        double e = j->V[i + (size_t)Nt * m];
        for (int c = 0; c < Nt; c++)
            e -= j->V[i + (size_t)c * m] * j->x[c];
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
    if ((st = job_alloc(&j)))
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
