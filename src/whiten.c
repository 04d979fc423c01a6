/* whiten.c - streamed whitening of epoch blocks: 3 x 3 covariance per epoch
 * (Cholesky), AR(p) per axis (exact Prais-Winsten), one set of normal
 * equations per group (docs/eqerr.md, "Tracking noise beyond a diagonal
 * K"). */
#include <float.h>

#include <cblas.h>

#include "igea/noise.h"
#include "internal.h"

struct igea_whiten {
    int N, p, G;
    double phi[3 * IGEA_NOISE_AR_MAX];
    double linv[3][IGEA_NOISE_AR_MAX][IGEA_NOISE_AR_MAX]; /* Gamma_p^-1/2, lower */
    double su[3];                                         /* 1 / sigma_u */
    /* state */
    double epoch; /* epochs since the reset */
    int group, k; /* current segment's group (-1: none) and its epochs */
    double *hist; /* 3 axes x p rows of N + 1: hist[(a p + j)(N + 1)] = u_(t-1-j) */
};

/* Yule-Walker of a unit-variance AR(p): rho_1..rho_p, the Cholesky factor of
 * the (p+1) x (p+1) autocorrelation matrix (positive definite iff
 * stationary), Gamma_p^-1/2 and 1/sigma_u. Returns 0 or 1 (not stationary). */
int igea__ar_setup(int p, const double *phi, double linv[][IGEA_NOISE_AR_MAX], double *su);
int igea__ar_setup(int p, const double *phi, double linv[][IGEA_NOISE_AR_MAX], double *su)
{
    double M[IGEA_NOISE_AR_MAX][IGEA_NOISE_AR_MAX + 1], rho[IGEA_NOISE_AR_MAX + 1];
    for (int k = 1; k <= p; k++) {
        for (int l = 1; l <= p; l++)
            M[k - 1][l - 1] = (k == l);
        M[k - 1][p] = 0.0;
        for (int j = 1; j <= p; j++) {
            int l = abs(k - j);
            if (l == 0)
                M[k - 1][p] += phi[j - 1];
            else
                M[k - 1][l - 1] -= phi[j - 1];
        }
    }
    for (int c = 0; c < p; c++) { /* Gauss-Jordan, partial pivoting */
        int piv = c;
        for (int r = c + 1; r < p; r++)
            if (fabs(M[r][c]) > fabs(M[piv][c]))
                piv = r;
        if (!(fabs(M[piv][c]) > 1e-12))
            return 1;
        for (int l = 0; l <= p; l++) {
            double t = M[c][l];
            M[c][l] = M[piv][l];
            M[piv][l] = t;
        }
        for (int r = 0; r < p; r++) {
            if (r == c)
                continue;
            double f = M[r][c] / M[c][c];
            for (int l = c; l <= p; l++)
                M[r][l] -= f * M[c][l];
        }
    }
    rho[0] = 1.0;
    for (int k = 1; k <= p; k++)
        rho[k] = M[k - 1][p] / M[k - 1][k - 1];
    double T[(IGEA_NOISE_AR_MAX + 1) * (IGEA_NOISE_AR_MAX + 1)];
    int n1 = p + 1;
    for (int j = 0; j < n1; j++)
        for (int i = 0; i < n1; i++)
            T[i + j * n1] = rho[abs(i - j)];
    if (igea__chol_lower(n1, T, n1, 0.0) != 0 || !(T[p + p * n1] > 1e-7))
        return 1;
    *su = 1.0 / T[p + p * n1]; /* last pivot: sigma_u */
    for (int i = 0; i < p; i++) /* inverse of the leading p x p factor */
        for (int j = 0; j <= i; j++) {
            double s = (i == j) ? 1.0 : 0.0;
            for (int l = j; l < i; l++)
                s -= T[i + l * n1] * linv[l][j];
            linv[i][j] = s / T[i + i * n1];
        }
    return 0;
}

int igea_whiten_create(int N, int p, const double *phi, int ngroups, igea_whiten **w)
{
    if (w)
        *w = NULL;
    if (N < 1) return -1;
    if (p < 0 || p > IGEA_NOISE_AR_MAX) return -2;
    if (p > 0 && !phi) return -3;
    if (ngroups < 1) return -4;
    if (!w) return -5;
    if (p > 0 && !igea__finite_vec(3 * p, phi, 1))
        return IGEA_ENONFINITE;
    igea_whiten *h = calloc(1, sizeof *h);
    if (!h)
        return IGEA_ENOMEM;
    h->N = N;
    h->p = p;
    h->G = ngroups;
    for (int a = 0; a < 3; a++) {
        h->su[a] = 1.0;
        for (int k = 0; k < p; k++)
            h->phi[a * p + k] = phi[a * p + k];
        if (p > 0 && igea__ar_setup(p, phi + a * p, h->linv[a], &h->su[a])) {
            free(h);
            return -3;
        }
    }
    h->hist = igea__dalloc((size_t)3 * (p > 0 ? p : 1) * ((size_t)N + 1));
    if (!h->hist) {
        free(h);
        return IGEA_ENOMEM;
    }
    igea_whiten_reset(h);
    *w = h;
    return 0;
}

void igea_whiten_free(igea_whiten *w)
{
    if (!w)
        return;
    free(w->hist);
    free(w);
}

int igea_whiten_get_state(const igea_whiten *w, double *epochs, int *group)
{
    if (!w) return -1;
    if (!epochs) return -2;
    if (!group) return -3;
    *epochs = w->epoch;
    *group = w->group;
    return 0;
}

int igea_whiten_reset(igea_whiten *w)
{
    if (!w)
        return -1;
    w->epoch = 0;
    w->group = -1;
    w->k = 0;
    return 0;
}

/* The working copy of a call: the state, the group sums, the row buffer. */
typedef struct {
    const igea_whiten *h;
    double epoch;
    int group, k;
    double *hist, *Al, *bl, *buf, *y, *u, *white;
    igea__ksum *ww;
    double *nrows;
    int rb, nb, bg; /* buffer rows, rows held, their group */
} wjob;

/* Add the buffered rows (row-major, n1 = N + 1 per row: [s~_i, w~_i]) to
 * their group's sums. */
static void flush(wjob *j)
{
    int N = j->h->N, n = j->nb, n1 = N + 1;
    if (n == 0)
        return;
    double *Al = j->Al + (size_t)j->bg * N * N, *bl = j->bl + (size_t)j->bg * N;
    cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, N, n, 1.0, j->buf, n1, 1.0, Al, N);
    cblas_dgemv(CblasColMajor, CblasNoTrans, N, n, 1.0, j->buf, n1, j->buf + N, n1, 1.0, bl, 1);
    for (int i = 0; i < n; i++) {
        double wv = j->buf[(size_t)i * n1 + N];
        igea__ksum_add(&j->ww[j->bg], wv * wv);
    }
    j->nrows[j->bg] += n;
    j->nb = 0;
}

/* Stage 1 of epoch e: its three raw rows [S_i D, dw_i] whitened by the
 * Cholesky factor of its covariance (6 values) or by the row sigmas, into
 * u0, u1, u2 (N + 1 each). Returns 0, IGEA_ESINGULAR, IGEA_ENONFINITE. */
static int stage1(int layout, int e, int N, const double *S, int lds, const double *dw,
                  const double *spec, const double *c6, const double *sig, double *u0,
                  double *u1, double *u2)
{
    double l00, l10, l11, l20, l21, l22;
    if (c6) {
        if (!igea__finite_vec(6, c6, 1))
            return IGEA_ENONFINITE;
        double d0 = c6[0];
        if (!(d0 > 0))
            return IGEA_ESINGULAR;
        l00 = sqrt(d0);
        l10 = c6[1] / l00;
        l20 = c6[3] / l00;
        double d1 = c6[2] - l10 * l10;
        if (!(d1 > 0))
            return IGEA_ESINGULAR;
        l11 = sqrt(d1);
        l21 = (c6[4] - l20 * l10) / l11;
        double d2 = c6[5] - l20 * l20 - l21 * l21;
        if (!(d2 > 0))
            return IGEA_ESINGULAR;
        l22 = sqrt(d2);
        if (!(l00 >= IGEA_SIGMA_MIN && l11 >= IGEA_SIGMA_MIN && l22 >= IGEA_SIGMA_MIN))
            return IGEA_ESINGULAR;
    } else {
        l00 = sig[0], l11 = sig[1], l22 = sig[2];
        l10 = l20 = l21 = 0.0;
    }
    const double r0 = 1.0 / l00, r1 = 1.0 / l11, r2 = 1.0 / l22;
    const size_t i0 = 3 * (size_t)e;
    for (int c = 0; c <= N; c++) {
        double y0, y1, y2;
        if (c == N) {
            y0 = dw[i0], y1 = dw[i0 + 1], y2 = dw[i0 + 2];
        } else {
            double sc = spec ? spec[c] : 1.0;
            if (layout == IGEA_COLMAJOR) {
                const double *col = S + (size_t)c * lds + i0;
                y0 = col[0] * sc, y1 = col[1] * sc, y2 = col[2] * sc;
            } else {
                const double *row = S + i0 * lds + c;
                y0 = row[0] * sc, y1 = row[lds] * sc, y2 = row[2 * (size_t)lds] * sc;
            }
        }
        double v0 = y0 * r0;
        double v1 = (y1 - l10 * v0) * r1;
        u0[c] = v0;
        u1[c] = v1;
        u2[c] = (y2 - l20 * v0 - l21 * v1) * r2;
    }
    return 0;
}

/* Stage 2 of one axis: the Prais-Winsten row v from u and the history, then
 * u pushed into the history. */
static void stage2(wjob *j, int a, const double *u, double *v)
{
    const igea_whiten *h = j->h;
    int p = h->p, n1 = h->N + 1, k = j->k;
    double *hs = j->hist + (size_t)a * p * n1;
    if (p == 0) {
        memcpy(v, u, (size_t)n1 * sizeof(double));
        return;
    }
    if (k < p) { /* v_k = sum_(l <= k) Linv[k][l] u_l, u_l = hist[k - 1 - l] */
        for (int c = 0; c < n1; c++) {
            double s = h->linv[a][k][k] * u[c];
            for (int l = 0; l < k; l++)
                s += h->linv[a][k][l] * hs[(size_t)(k - 1 - l) * n1 + c];
            v[c] = s;
        }
    } else if (p == 1) { /* the common case: one pass, history updated in place */
        const double f = h->phi[a], sc = h->su[a];
        for (int c = 0; c < n1; c++) {
            double uc = u[c];
            v[c] = (uc - f * hs[c]) * sc;
            hs[c] = uc;
        }
        return;
    } else {
        const double *ph = h->phi + a * p;
        for (int c = 0; c < n1; c++) {
            double s = u[c];
            for (int l = 0; l < p; l++)
                s -= ph[l] * hs[(size_t)l * n1 + c];
            v[c] = s * h->su[a];
        }
    }
    memmove(hs + n1, hs, (size_t)(p - 1) * n1 * sizeof(double));
    memcpy(hs, u, (size_t)n1 * sizeof(double));
}

/* Every epoch of the block through both stages into the job's sums (and
 * white). Returns 0 or a failure with *bad the epoch. */
static int run_block(wjob *j, int layout, int m, const double *S, int lds,
                     const double *dw, const double *sig, int inc, const double *cov,
                     const int *group, const int *mask, const double *spec,
                     double *white, int *bad)
{
    int N = j->h->N, n1 = N + 1;
    double *vr = j->y; /* y, read by stage1, then holds a masked v row */
    for (int e = 0; e < m / 3; e++) {
        int g = group ? group[e] : 0;
        double s3[3];
        for (int a = 0; a < 3; a++)
            s3[a] = sig ? sig[inc ? 3 * e + a : 0] : 1.0;
        const int i0 = 3 * e;
        /* p = 0, whole epoch kept, same group, room: straight into the buffer */
        int direct = j->h->p == 0 && !white && !(mask && (mask[i0] | mask[i0 + 1] | mask[i0 + 2]));
        if (direct && j->nb > 0 && (j->bg != g || j->nb + 3 > j->rb))
            flush(j);
        double *u = direct ? j->buf + (size_t)j->nb * n1 : j->u;
        int st = stage1(layout, e, N, S, lds, dw, spec, cov ? cov + 6 * (size_t)e : NULL, s3,
                        u, u + n1, u + 2 * (size_t)n1);
        if (st) {
            *bad = (int)(j->epoch + e);
            return st;
        }
        if (direct) {
            j->bg = g;
            j->nb += 3;
            j->group = g;
            continue;
        }
        if (g != j->group) {
            j->group = g;
            j->k = 0;
        }
        for (int a = 0; a < 3; a++) {
            int i = 3 * e + a, keep = !(mask && mask[i]);
            if (keep && j->nb > 0 && (j->bg != g || j->nb == j->rb))
                flush(j);
            double *dst = keep ? j->buf + (size_t)j->nb * n1 : vr;
            stage2(j, a, j->u + (size_t)a * n1, dst);
            if (white)
                for (int c = 0; c < n1; c++)
                    white[i + (size_t)c * m] = dst[c];
            if (keep) {
                j->bg = g;
                j->nb++;
            }
        }
        j->k++;
    }
    flush(j);
    j->epoch += m / 3;
    return 0;
}

static int whiten_args(const igea_whiten *w, int layout, int m, const double *S, int lds,
                       const double *dw, const double *sig, int inc, const double *cov,
                       const int *group, const int *mask, const double *A, int lda,
                       const double *b, const double *wtw)
{
    if (!w) return -1;
    if (layout != IGEA_COLMAJOR && layout != IGEA_ROWMAJOR) return -2;
    if (m < 0 || m % 3) return -3;
    if (!S && m > 0) return -4;
    if (lds < IGEA_MAX(1, layout == IGEA_COLMAJOR ? m : w->N)) return -5;
    if (!dw && m > 0) return -6;
    if ((!sig && !cov && m > 0) || (sig && cov)) return -7;
    if (inc != 0 && inc != 1) return -8;
    for (int e = 0; group && e < m / 3; e++)
        if (group[e] < 0 || group[e] >= w->G) return -10;
    for (int i = 0; mask && i < m; i++)
        if (mask[i] != 0 && mask[i] != 1) return -11;
    if (!A) return -13;
    if (lda < w->N) return -14;
    if (!b) return -15;
    for (int g = 0; wtw && g < 2 * w->G; g++)
        if (!(wtw[g] >= 0.0 && wtw[g] <= DBL_MAX)) return -16;
    return wtw ? 0 : -16;
}

/* Add the job's sums to the caller's, or IGEA_EOVERFLOW (nothing written). */
static int add_sums(const wjob *j, double *A, int lda, double *b, double *wtw)
{
    int N = j->h->N, G = j->h->G;
    for (int pass = 0; pass < 2; pass++)
        for (int g = 0; g < G; g++) {
            const double *Al = j->Al + (size_t)g * N * N;
            double *Ag = A + (size_t)g * lda * N, *bg = b + (size_t)g * N;
            double ww = igea__ksum_get(&j->ww[g]);
            if (!pass && !isfinite(wtw[2 * g] + ww))
                return IGEA_EOVERFLOW;
            for (int c = 0; c < N; c++) {
                for (int r = c; r < N; r++) {
                    double v = Al[r + (size_t)c * N];
                    if (!pass && (!isfinite(IGEA_AT(Ag, lda, r, c) + v) ||
                                  !isfinite(IGEA_AT(Ag, lda, c, r) + v)))
                        return IGEA_EOVERFLOW;
                    if (pass) {
                        IGEA_AT(Ag, lda, r, c) += v;
                        if (r != c)
                            IGEA_AT(Ag, lda, c, r) += v;
                    }
                }
                if (!pass && !isfinite(bg[c] + j->bl[(size_t)g * N + c]))
                    return IGEA_EOVERFLOW;
                if (pass)
                    bg[c] += j->bl[(size_t)g * N + c];
            }
            if (pass) {
                wtw[2 * g] += ww;
                wtw[2 * g + 1] += j->nrows[g];
            }
        }
    return 0;
}

/* 1 when the sums of the job are finite. */
static int sums_finite(const wjob *j)
{
    int N = j->h->N, G = j->h->G;
    for (int g = 0; g < G; g++)
        if (!igea__finite_vec(N, j->Al + (size_t)g * N * N, N + 1) ||
            !igea__finite_vec(N, j->bl + (size_t)g * N, 1) ||
            !isfinite(igea__ksum_get(&j->ww[g])))
            return 0;
    return 1;
}

int igea_whiten_accumulate(igea_whiten *w, int layout, int m, const double *S, int lds,
                           const double *dw, const double *track_sigma, int sigma_inc,
                           const double *cov, const int *group, const int *mask,
                           const double *spec_sigma, double *A, int lda, double *b,
                           double *wtw, double *white, int *bad_epoch)
{
    int st = whiten_args(w, layout, m, S, lds, dw, track_sigma, sigma_inc, cov, group,
                         mask, A, lda, b, wtw);
    if (st)
        return st;
    if (spec_sigma && (st = igea__sigma_vec(w->N, spec_sigma)))
        return st;
    if (m > 0 && track_sigma && (st = igea__sigma_vec(sigma_inc ? m : 1, track_sigma)))
        return st;
    if (m == 0)
        return 0;
    int N = w->N, G = w->G, n1 = N + 1, p = w->p;
    int rb = IGEA_MIN(IGEA_MAX(64, 65536 / n1), m);
    size_t nh = (size_t)3 * (p > 0 ? p : 1) * n1;
    size_t nd = nh + (size_t)G * N * N + (size_t)G * N + (size_t)rb * n1 + 6 * (size_t)n1 + G +
                (white ? (size_t)m * n1 : 0);
    double *work = igea__dalloc(nd);
    igea__ksum *ww = calloc((size_t)G, sizeof *ww);
    if (!work || !ww) {
        free(work);
        free(ww);
        return IGEA_ENOMEM;
    }
    wjob j = {w, w->epoch, w->group, w->k, work, NULL, NULL, NULL, NULL, NULL, NULL, ww,
              NULL, rb, 0, 0};
    memcpy(j.hist, w->hist, nh * sizeof(double));
    j.Al = j.hist + nh;
    j.bl = j.Al + (size_t)G * N * N;
    j.buf = j.bl + (size_t)G * N;
    j.y = j.buf + (size_t)rb * n1;
    j.u = j.y + 3 * (size_t)n1;
    j.nrows = j.u + 3 * (size_t)n1;
    j.white = white ? j.nrows + G : NULL;
    memset(j.Al, 0, ((size_t)G * N * N + (size_t)G * N) * sizeof(double));
    memset(j.nrows, 0, (size_t)G * sizeof(double));
    int bad = -1;
    st = run_block(&j, layout, m, S, lds, dw, track_sigma, sigma_inc, cov, group, mask,
                   spec_sigma, j.white, &bad);
    if (st == IGEA_ENONFINITE || (st == 0 && !sums_finite(&j)))
        st = (igea__finite_vec(m, dw, 1) &&
              (layout == IGEA_COLMAJOR ? igea__finite_mat(m, N, S, lds)
                                       : igea__finite_mat(N, m, S, lds)) &&
              (!cov || igea__finite_vec(2 * m, cov, 1)))
                 ? IGEA_EOVERFLOW
                 : IGEA_ENONFINITE;
    if (st == 0)
        st = add_sums(&j, A, lda, b, wtw);
    if (st == 0) {
        if (white)
            for (int c = 0; c < n1; c++)
                memcpy(white + (size_t)c * m, j.white + (size_t)c * m, (size_t)m * sizeof(double));
        memcpy(w->hist, j.hist, nh * sizeof(double));
        w->epoch = j.epoch;
        w->group = j.group;
        w->k = j.k;
    } else if (st == IGEA_ESINGULAR && bad_epoch)
        *bad_epoch = bad;
    free(work);
    free(ww);
    return st;
}
