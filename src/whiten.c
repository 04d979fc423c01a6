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
    double *hist; /* 3 axes x (N + 1) columns x p: hist[(a (N + 1) + c) p + j] = stage 1 of
                     the segment's epoch k - p + j (oldest first), column c, axis a */
    /* igea_whiten_accumulate_xcov's state (the whole K with its cross blocks) */
    int xmode; /* since the reset: 0 no epoch, 1 igea_whiten_accumulate's, 2 the xcov one's */
    double xs[21]; /* the last epoch's K_ee (lower, by rows), X_e (row-major) and
                      M = E C~^-1 E' of the next (xcoef1) */
    double *xprev; /* 3 x (N + 1 rounded up to 4): the predictions p of the next epoch's
                      rows (row-major; 0 in the padding) */
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
    h->xprev = igea__dalloc((size_t)3 * (((size_t)N + 4) / 4 * 4));
    if (!h->hist || !h->xprev) {
        free(h->hist);
        free(h->xprev);
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
    free(w->xprev);
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
    w->xmode = 0;
    return 0;
}

/* The working copy of a call: the state, the group sums, and the chunk
 * buffers. A chunk is up to E consecutive epochs of one group; it is
 * whitened column by column into blk (3 n x (N + 1), column-major, its
 * rows axis-major: row a n + q is axis a of the chunk's epoch q), which
 * one dsyrk and one dgemv add to the group's sums. */
typedef struct {
    const igea_whiten *h;
    double epoch;
    int group, k;
    double *hist, *Al, *bl, *nrows;
    igea__ksum *ww;
    int E;       /* epochs per chunk */
    double *blk; /* 3 E x (N + 1) */
    double *co;  /* 6 E: stage-1 coefficients r0 r1 r2 l10 l20 l21 of each epoch */
    double *u;   /* 3 (p + E): stage 1 of one column, each axis after its p carried values */
    /* igea_whiten_accumulate_xcov: blk holds the chunk's rows row-major (3 n x (N + 1)),
       co 15 coefficients per epoch, hist the carried rows (6 (N + 1)) */
    double xs[21];              /* the previous epoch's K_ee, X_e and M (xcoef1) */
    int xld;                    /* the row length of blk: N + 1 rounded up to 4 */
    double *xA;                 /* (N + 1) x (N + 1): the sums of [S~ w~]' [S~ w~] */
} wjob;

/* Stage-1 coefficients of the chunk's n epochs (from e0 of the call), in
 * six arrays of E: the inverse pivots r0, r1, r2 and l10, l20, l21 of the
 * epoch's Cholesky factor (6 covariance values), or the inverse row sigmas
 * (r0, r1, r2 only). Returns 0, IGEA_ESINGULAR or IGEA_ENONFINITE with
 * *bad the epoch (of the call). */
static int coefs(wjob *j, int e0, int n, const double *cov, const double *sig, int inc,
                 int *bad)
{
    const int E = j->E;
    double *r0 = j->co, *r1 = r0 + E, *r2 = r1 + E, *l10 = r2 + E, *l20 = l10 + E, *l21 = l20 + E;
    for (int q = 0; q < n; q++) {
        const size_t e = (size_t)e0 + q;
        if (!cov) {
            r0[q] = 1.0 / sig[inc ? 3 * e : 0];
            r1[q] = 1.0 / sig[inc ? 3 * e + 1 : 0];
            r2[q] = 1.0 / sig[inc ? 3 * e + 2 : 0];
            continue;
        }
        const double *c6 = cov + 6 * e;
        int st = 0;
        double d0 = c6[0], d1, d2, a00, a10, a11, a20, a21, a22;
        double fin = 0.0; /* 0 when the six values are finite, NaN otherwise */
        for (int k = 0; k < 6; k++)
            fin += c6[k] - c6[k];
        if (fin != 0.0)
            st = IGEA_ENONFINITE;
        else if (!(d0 > 0))
            st = IGEA_ESINGULAR;
        if (st == 0) {
            a00 = sqrt(d0);
            a10 = c6[1] / a00;
            a20 = c6[3] / a00;
            d1 = c6[2] - a10 * a10;
            if (!(d1 > 0))
                st = IGEA_ESINGULAR;
        }
        if (st == 0) {
            a11 = sqrt(d1);
            a21 = (c6[4] - a20 * a10) / a11;
            d2 = c6[5] - a20 * a20 - a21 * a21;
            if (!(d2 > 0))
                st = IGEA_ESINGULAR;
        }
        if (st == 0) {
            a22 = sqrt(d2);
            if (!(a00 >= IGEA_SIGMA_MIN && a11 >= IGEA_SIGMA_MIN && a22 >= IGEA_SIGMA_MIN))
                st = IGEA_ESINGULAR;
        }
        if (st) {
            *bad = e0 + q;
            return st;
        }
        r0[q] = 1.0 / a00, r1[q] = 1.0 / a11, r2[q] = 1.0 / a22;
        l10[q] = a10, l20[q] = a20, l21[q] = a21;
    }
    return 0;
}

/* The filter of one axis (p >= 1) after its segment's first p epochs: v_q = (u_q -
 * sum_l phi_l u_(q-1-l)) su for q < n, u[-p .. -1] the values before.
 * Written two rows at a time: the compiler's basic-block vectoriser
 * (-O2) turns each pair into vector operations. */
static void ar_filter(int p, const double *restrict u, int n, double *restrict v,
                      const double *ph, double su)
{
    int q = 0;
    const double f0 = ph[0], f1 = p > 1 ? ph[1] : 0.0, f2 = p > 2 ? ph[2] : 0.0;
    if (p == 1)
        for (; q + 1 < n; q += 2) {
            double s0 = u[q], s1 = u[q + 1];
            s0 -= f0 * u[q - 1], s1 -= f0 * u[q];
            v[q] = s0 * su, v[q + 1] = s1 * su;
        }
    else if (p == 2)
        for (; q + 1 < n; q += 2) {
            double s0 = u[q], s1 = u[q + 1];
            s0 -= f0 * u[q - 1], s1 -= f0 * u[q];
            s0 -= f1 * u[q - 2], s1 -= f1 * u[q - 1];
            v[q] = s0 * su, v[q + 1] = s1 * su;
        }
    else
        for (; q + 1 < n; q += 2) {
            double s0 = u[q], s1 = u[q + 1];
            s0 -= f0 * u[q - 1], s1 -= f0 * u[q];
            s0 -= f1 * u[q - 2], s1 -= f1 * u[q - 1];
            s0 -= f2 * u[q - 3], s1 -= f2 * u[q - 2];
            v[q] = s0 * su, v[q + 1] = s1 * su;
        }
    for (; q < n; q++) {
        double s = u[q];
        for (int l = 0; l < p; l++)
            s -= ph[l] * u[q - 1 - l];
        v[q] = s * su;
    }
}

/* Stage 1 of n epochs of one column (x[3 q st + a] row a of epoch q,
 * scaled by sc) by the epochs' Cholesky factors or row sigmas into u0,
 * u1, u2; two epochs at a time, as ar_filter. */
static void stage1(int usecov, const double *restrict x, size_t st, double sc,
                   const double *restrict co, int E, int n, double *restrict u0,
                   double *restrict u1, double *restrict u2)
{
    const double *r0 = co, *r1 = r0 + E, *r2 = r1 + E, *l10 = r2 + E, *l20 = l10 + E,
                 *l21 = l20 + E;
    int q = 0;
    if (usecov) {
        if (st == 1)
            for (; q + 1 < n; q += 2) {
                const double *xq = x + 3 * (size_t)q;
                double y00 = xq[0] * sc, y01 = xq[3] * sc;
                double y10 = xq[1] * sc, y11 = xq[4] * sc;
                double y20 = xq[2] * sc, y21 = xq[5] * sc;
                double v00 = y00 * r0[q], v01 = y01 * r0[q + 1];
                double v10 = (y10 - l10[q] * v00) * r1[q];
                double v11 = (y11 - l10[q + 1] * v01) * r1[q + 1];
                u0[q] = v00, u0[q + 1] = v01;
                u1[q] = v10, u1[q + 1] = v11;
                u2[q] = (y20 - l20[q] * v00 - l21[q] * v10) * r2[q];
                u2[q + 1] = (y21 - l20[q + 1] * v01 - l21[q + 1] * v11) * r2[q + 1];
            }
        for (; q < n; q++) {
            const double *xq = x + 3 * (size_t)q * st;
            double y0 = xq[0] * sc, y1 = xq[st] * sc, y2 = xq[2 * st] * sc;
            double v0 = y0 * r0[q], v1 = (y1 - l10[q] * v0) * r1[q];
            u0[q] = v0, u1[q] = v1;
            u2[q] = (y2 - l20[q] * v0 - l21[q] * v1) * r2[q];
        }
        return;
    }
    if (st == 1)
        for (; q + 1 < n; q += 2) {
            const double *xq = x + 3 * (size_t)q;
            u0[q] = xq[0] * sc * r0[q], u0[q + 1] = xq[3] * sc * r0[q + 1];
            u1[q] = xq[1] * sc * r1[q], u1[q + 1] = xq[4] * sc * r1[q + 1];
            u2[q] = xq[2] * sc * r2[q], u2[q + 1] = xq[5] * sc * r2[q + 1];
        }
    for (; q < n; q++) {
        const double *xq = x + 3 * (size_t)q * st;
        u0[q] = xq[0] * sc * r0[q];
        u1[q] = xq[st] * sc * r1[q];
        u2[q] = xq[2 * st] * sc * r2[q];
    }
}

/* Column c of the chunk (epochs e0 .. e0 + n - 1 of the call) through both
 * stages into blk: stage 1 (y = [S D, dw] of the epoch whitened by its
 * Cholesky factor or the row sigmas) into u after each axis's p carried
 * stage-1 values, then the Prais-Winsten filter of each axis (the inverse
 * Cholesky factor of Gamma_p for the segment's first p epochs, (u_t -
 * sum_k phi_k u_(t-k)) sigma_u^-1 after them), the last p stage-1 values
 * carried to the next chunk. The arithmetic is the row-by-row transform's,
 * operation for operation. */
static void column(wjob *j, int c, int layout, int e0, int n, const double *S, int lds,
                   const double *dw, const double *spec, int usecov)
{
    const igea_whiten *h = j->h;
    const int N = h->N, n1 = N + 1, p = h->p, ldb = 3 * n, E = j->E;
    const size_t i0 = 3 * (size_t)e0;
    const double *x;
    size_t st = 1;
    double sc = 1.0; /* dw is not scaled: sc = 1, exact */
    if (c == N) {
        x = dw + i0;
    } else {
        sc = spec ? spec[c] : 1.0;
        if (layout == IGEA_COLMAJOR)
            x = S + (size_t)c * lds + i0;
        else
            x = S + i0 * lds + c, st = (size_t)lds;
    }
    double *col = j->blk + (size_t)c * ldb, *u[3];
    if (p == 0) { /* no serial correlation: stage 1 straight into the column */
        stage1(usecov, x, st, sc, j->co, E, n, col, col + n, col + 2 * (size_t)n);
        return;
    }
    for (int a = 0; a < 3; a++) {
        u[a] = j->u + (size_t)a * (p + E) + p;
        memcpy(u[a] - p, j->hist + ((size_t)a * n1 + c) * p, (size_t)p * sizeof(double));
    }
    stage1(usecov, x, st, sc, j->co, E, n, u[0], u[1], u[2]);
    for (int a = 0; a < 3; a++) { /* stage 2 into rows a n .. a n + n - 1 */
        const double *ua = u[a];
        double *v = col + (size_t)a * n;
        int q = 0;
        for (; q < n && j->k + q < p; q++) { /* the segment's first p epochs */
            const int t = j->k + q;
            double s = h->linv[a][t][t] * ua[q];
            for (int l = 0; l < t; l++)
                s += h->linv[a][t][l] * ua[q - t + l];
            v[q] = s;
        }
        ar_filter(p, ua + q, n - q, v + q, h->phi + a * p, h->su[a]);
        /* carry the last p stage-1 values (with older ones when n < p) */
        memcpy(j->hist + ((size_t)a * n1 + c) * p, ua + n - p, (size_t)p * sizeof(double));
    }
}

/* Add the chunk's whitened rows (blk, 3 n rows) to group g's sums, the
 * rows masked in the call (mask + 3 e0) left out. */
static void chunk_sums(wjob *j, int g, int e0, int n, const int *mask)
{
    const int N = j->h->N, ldb = 3 * n;
    double *w = j->blk + (size_t)N * ldb;
    int kept = ldb;
    if (mask) /* a masked row becomes zeros: it adds nothing to A, b or w'w */
        for (int q = 0; q < n; q++)
            for (int a = 0; a < 3; a++)
                if (mask[3 * ((size_t)e0 + q) + a]) {
                    for (int c = 0; c <= N; c++)
                        j->blk[(size_t)a * n + q + (size_t)c * ldb] = 0.0;
                    kept--;
                }
    if (kept == 0)
        return;
    double *Al = j->Al + (size_t)g * N * N, *bl = j->bl + (size_t)g * N;
    cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, N, ldb, 1.0, j->blk, ldb, 1.0, Al, N);
    cblas_dgemv(CblasColMajor, CblasTrans, ldb, N, 1.0, j->blk, ldb, w, 1, 1.0, bl, 1);
    for (int i = 0; i < ldb; i++)
        igea__ksum_add(&j->ww[g], w[i] * w[i]);
    j->nrows[g] += kept;
}

/* Every epoch of the block through both stages into the job's sums (and
 * white, m x (N + 1), ld m). Returns 0 or a failure with *bad the epoch. */
static int run_block(wjob *j, int layout, int m, const double *S, int lds,
                     const double *dw, const double *sig, int inc, const double *cov,
                     const int *group, const int *mask, const double *spec,
                     double *white, int *bad)
{
    const int N = j->h->N, n1 = N + 1, M = m / 3;
    for (int e0 = 0; e0 < M;) {
        int g = group ? group[e0] : 0;
        if (g != j->group) { /* a new segment: the filter restarts */
            j->group = g;
            j->k = 0;
        }
        int e1 = e0 + 1;
        while (e1 < M && e1 - e0 < j->E && (!group || group[e1] == g))
            e1++;
        const int n = e1 - e0, ldb = 3 * n;
        int st = coefs(j, e0, n, cov, sig, inc, bad);
        if (st) {
            *bad += (int)j->epoch;
            return st;
        }
        for (int c = 0; c < n1; c++)
            column(j, c, layout, e0, n, S, lds, dw, spec, cov != NULL);
        if (white)
            for (int c = 0; c < n1; c++)
                for (int a = 0; a < 3; a++) {
                    const double *v = j->blk + (size_t)c * ldb + (size_t)a * n;
                    double *o = white + (size_t)c * m + 3 * (size_t)e0 + a;
                    for (int q = 0; q < n; q++)
                        o[3 * (size_t)q] = v[q];
                }
        chunk_sums(j, g, e0, n, mask);
        j->k = IGEA_MIN(j->k + n, 1 << 30); /* only k < p matters */
        e0 = e1;
    }
    j->epoch += M;
    return 0;
}

static int whiten_args(const igea_whiten *w, int layout, int m, const double *S, int lds,
                       const double *dw, const double *sig, int inc, const double *cov,
                       const int *group, const int *mask, const double *A, int lda,
                       const double *b, const double *wtw)
{
    if (!w || w->xmode == 2) return -1;
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
    /* chunks of about 64 Ki doubles, as igea_normal_accumulate's blocks */
    int E = IGEA_MIN(IGEA_MAX(22, 65536 / (3 * n1)), m / 3);
    size_t nh = (size_t)3 * (p > 0 ? p : 1) * n1;
    size_t nd = nh + (size_t)G * N * N + (size_t)G * N + G + (size_t)3 * E * n1 +
                (size_t)6 * E + (size_t)3 * (p + E) + (white ? (size_t)m * n1 : 0);
    double *work = igea__dalloc(nd);
    igea__ksum *ww = calloc((size_t)G, sizeof *ww);
    if (!work || !ww) {
        free(work);
        free(ww);
        return IGEA_ENOMEM;
    }
    wjob j;
    memset(&j, 0, sizeof j);
    j.h = w, j.epoch = w->epoch, j.group = w->group, j.k = w->k, j.hist = work, j.ww = ww;
    j.E = E;
    memcpy(j.hist, w->hist, nh * sizeof(double));
    j.Al = j.hist + nh;
    j.bl = j.Al + (size_t)G * N * N;
    j.nrows = j.bl + (size_t)G * N;
    j.blk = j.nrows + G;
    j.co = j.blk + (size_t)3 * E * n1;
    j.u = j.co + (size_t)6 * E;
    double *jwhite = white ? j.u + (size_t)3 * (p + E) : NULL;
    memset(j.Al, 0, ((size_t)G * N * N + (size_t)G * N + G) * sizeof(double));
    int bad = -1;
    st = run_block(&j, layout, m, S, lds, dw, track_sigma, sigma_inc, cov, group, mask,
                   spec_sigma, jwhite, &bad);
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
                memcpy(white + (size_t)c * m, jwhite + (size_t)c * m, (size_t)m * sizeof(double));
        memcpy(w->hist, j.hist, nh * sizeof(double));
        w->epoch = j.epoch;
        w->group = j.group;
        w->k = j.k;
        w->xmode = 1;
    } else if (st == IGEA_ESINGULAR && bad_epoch)
        *bad_epoch = bad;
    free(work);
    free(ww);
    return st;
}

/* ---- the whole K: diagonal blocks K_ee and cross blocks X_e ----------------
 * (docs/eqerr.md, "The whole K of igea dw: cross blocks between epochs"
 * [D]). The
 * rows differenced between epochs, d_f = y_f - y_(f-1) (d_0 = y_0), have
 * the block-tridiagonal covariance C_ff = K_ff - X_(f-1) - X_(f-1)' +
 * K_(f-1,f-1), C_(f,f-1) = E_f = X_(f-1)' - K_(f-1,f-1); its block Cholesky
 * factor: B_f = E_f L_(f-1)^-T, L_f L_f' = C_ff - B_f B_f'; the whitened
 * rows w_f = L_f^-1 (d_f - B_f w_(f-1)). Streamed as w_f = L_f^-1 r_f with
 * r_f = y_f - p_f and the prediction p_(f+1) = y_f + H_(f+1) r_f, H_(f+1) =
 * B_(f+1) L_f^-1 (since B_f w_(f-1) = H_f r_(f-1)): one carried 3-vector
 * per column. */

/* One epoch's 15 coefficients into co, from its K_ee (k6) and X_e (x9)
 * and the state x carried from the previous epoch (21 values: its K lower
 * by rows, its X row-major, and M_f = E_f C~_(f-1)^-1 E_f' lower by rows;
 * all 0 before the flight's first epoch), then replaced: with C~_f =
 * L_f L_f' = U D U' (U unit lower triangular, D = diag(d_k)),
 *   co[0..2] = 1 / sqrt(d_k), co[3..5] = u10 u20 u21 (w = D^-1/2 U^-1 r),
 *   co[6..14] = H_(f+1) = E_(f+1) C~_f^-1 by rows, E_(f+1) = X_f' - K_ff,
 * and M_(f+1) = H_(f+1) E_(f+1)'. The chain from one epoch to the next
 * holds three divisions and no square root (LDL' rather than L L'), so
 * that the processor overlaps it with the columns. Returns 0 or
 * IGEA_ESINGULAR: a pivot d_k <= IGEA_WHITEN_XCOV_RTOL x (K_ff,kk +
 * K_(f-1,f-1),kk), below IGEA_SIGMA_MIN^2 or not finite (also when K_ee or
 * the X_e before it holds NaN or Inf: xrun tells the two apart). */
#if defined(__GNUC__)
#define XC_INLINE static inline __attribute__((always_inline))
#else
#define XC_INLINE static inline
#endif
XC_INLINE int xcoef1(double *restrict x, const double *restrict k6, const double *restrict x9,
                     double *restrict co)
{
    const double K0 = k6[0], K1 = k6[1], K2 = k6[2], K3 = k6[3], K4 = k6[4], K5 = k6[5];
    const double X0 = x9[0], X1 = x9[1], X2 = x9[2], X3 = x9[3], X4 = x9[4], X5 = x9[5],
                 X6 = x9[6], X7 = x9[7], X8 = x9[8];
    /* C~_f = K_ff - X_(f-1) - X_(f-1)' + K_(f-1,f-1) - M_f */
    const double c00 = K0 + ((x[0] - 2.0 * x[6]) - x[15]);
    const double c10 = K1 + ((x[1] - x[9] - x[7]) - x[16]);
    const double c11 = K2 + ((x[2] - 2.0 * x[10]) - x[17]);
    const double c20 = K3 + ((x[3] - x[12] - x[8]) - x[18]);
    const double c21 = K4 + ((x[4] - x[13] - x[11]) - x[19]);
    const double c22 = K5 + ((x[5] - 2.0 * x[14]) - x[20]);
    const double f0 = K0 + x[0], f1 = K2 + x[2], f2 = K5 + x[5]; /* the pivots' magnitudes */
    /* U D U' */
    const double d0 = c00, i0 = 1.0 / d0, u10 = c10 * i0, u20 = c20 * i0;
    const double d1 = c11 - u10 * c10, i1 = 1.0 / d1, t21 = c21 - u20 * c10, u21 = t21 * i1;
    const double d2 = (c22 - u20 * c20) - u21 * t21, i2 = 1.0 / d2;
    if (!(d0 > IGEA_WHITEN_XCOV_RTOL * f0 && d1 > IGEA_WHITEN_XCOV_RTOL * f1 &&
          d2 > IGEA_WHITEN_XCOV_RTOL * f2))
        return IGEA_ESINGULAR;
    if (!(d0 >= IGEA_SIGMA_MIN * IGEA_SIGMA_MIN && d1 >= IGEA_SIGMA_MIN * IGEA_SIGMA_MIN &&
          d2 >= IGEA_SIGMA_MIN * IGEA_SIGMA_MIN && d0 <= DBL_MAX && d1 <= DBL_MAX &&
          d2 <= DBL_MAX))
        return IGEA_ESINGULAR;
    co[0] = sqrt(i0), co[1] = sqrt(i1), co[2] = sqrt(i2);
    co[3] = u10, co[4] = u20, co[5] = u21;
    /* E = X_f' - K_ff; V = E U^-T (row r: U v = e_r); Z = V D^-1; H = Z U^-1 (row r:
       U' h = z_r); M = Z V' */
#define XC_HROW(r, e0, e1, e2, Z0, Z1, Z2, V0, V1, V2)                                         \
    const double V0 = (e0), V1 = (e1) - u10 * V0, V2 = ((e2) - u20 * V0) - u21 * V1;           \
    const double Z0 = V0 * i0, Z1 = V1 * i1, Z2 = V2 * i2;                                     \
    do {                                                                                       \
        const double h1_ = Z1 - u21 * Z2;                                                      \
        co[6 + 3 * (r)] = (Z0 - u10 * h1_) - u20 * Z2, co[7 + 3 * (r)] = h1_;                  \
        co[8 + 3 * (r)] = Z2;                                                                  \
    } while (0)
    XC_HROW(0, X0 - K0, X3 - K1, X6 - K3, za0, za1, za2, va0, va1, va2);
    XC_HROW(1, X1 - K1, X4 - K2, X7 - K4, zb0, zb1, zb2, vb0, vb1, vb2);
    XC_HROW(2, X2 - K3, X5 - K4, X8 - K5, zc0, zc1, zc2, vc0, vc1, vc2);
#undef XC_HROW
    x[15] = za0 * va0 + za1 * va1 + za2 * va2;
    x[16] = zb0 * va0 + zb1 * va1 + zb2 * va2;
    x[17] = zb0 * vb0 + zb1 * vb1 + zb2 * vb2;
    x[18] = zc0 * va0 + zc1 * va1 + zc2 * va2;
    x[19] = zc0 * vb0 + zc1 * vb1 + zc2 * vb2;
    x[20] = zc0 * vc0 + zc1 * vc1 + zc2 * vc2;
    x[0] = K0, x[1] = K1, x[2] = K2, x[3] = K3, x[4] = K4, x[5] = K5;
    x[6] = X0, x[7] = X1, x[8] = X2, x[9] = X3, x[10] = X4, x[11] = X5, x[12] = X6;
    x[13] = X7, x[14] = X8;
    return 0;
}

/* The chunk's rows [S D, dw] (epochs e0 .. e0 + n - 1 of the call) into
 * blk, row-major (row 3 q + a, ld j->xld: N + 1 rounded up to a multiple
 * of 4; the columns after dw are zeroed once per call and stay 0); a
 * column-major S two columns at a time, so that each pair of reads fills
 * adjacent entries of a row. */
static void xfill(wjob *j, int layout, int e0, int n, const double *S, int lds,
                  const double *dw, const double *spec)
{
    const int N = j->h->N, ld = j->xld, R = 3 * n;
    const size_t i0 = 3 * (size_t)e0;
    double *T = j->blk;
    if (layout == IGEA_ROWMAJOR) {
        for (int i = 0; i < R; i++) {
            const double *x = S + (i0 + i) * lds;
            double *t = T + (size_t)i * ld;
            if (spec)
                for (int c = 0; c < N; c++)
                    t[c] = x[c] * spec[c];
            else
                memcpy(t, x, (size_t)N * sizeof(double));
            t[N] = dw[i0 + i];
        }
        return;
    }
    int c = 0;
    for (; c + 1 < N; c += 2) {
        const double *xa = S + (size_t)c * lds + i0, *xb = xa + lds;
        const double sa = spec ? spec[c] : 1.0, sb = spec ? spec[c + 1] : 1.0;
        double *t = T + c;
        for (int i = 0; i < R; i += 3, t += 3 * (size_t)ld) {
            t[0] = xa[i] * sa, t[1] = xb[i] * sb;
            t[ld] = xa[i + 1] * sa, t[ld + 1] = xb[i + 1] * sb;
            t[2 * ld] = xa[i + 2] * sa, t[2 * ld + 1] = xb[i + 2] * sb;
        }
    }
    for (; c <= N; c++) { /* the last column of S when N is odd, and dw */
        const double *x = c == N ? dw + i0 : S + (size_t)c * lds + i0;
        const double sc = c == N || !spec ? 1.0 : spec[c];
        double *t = T + c;
        for (int i = 0; i < R; i += 3, t += 3 * (size_t)ld) {
            t[0] = x[i] * sc;
            t[ld] = x[i + 1] * sc;
            t[2 * ld] = x[i + 2] * sc;
        }
    }
}

/* The recursion over the chunk's n epochs, every column of a row at once:
 * r = y - p, w = L^-1 r into y, p = y + H r (p the carried predictions,
 * 3 x n1 row-major). Four columns per step in GCC's vector extension
 * (built for AVX2 beside the baseline, as stability_pass.c's kernels; the
 * same operations in the same order in every lane and in the scalar tail,
 * no contraction into fused multiply-adds under ISO C: the results do not
 * depend on the clone). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && \
    !defined(IGEA_NO_CLONES)
#define XC_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define XC_CLONES
#endif
#if defined(__GNUC__)
typedef double xc_v4 __attribute__((vector_size(32), aligned(8)));
#define XC_LD(p) (*(const xc_v4 *)(const void *)(p))
#define XC_ST(p, v) (*(xc_v4 *)(void *)(p) = (v))
#define XC_VEC 1
#else
#define XC_VEC 0
#endif

XC_CLONES static int xrec(wjob *j, int n, double *T, const double *cov, const double *xcov,
                          int *bad)
{
    const int n1 = j->xld; /* the row length: the padding columns stay 0 */
    double *p0 = j->hist, *p1 = p0 + n1, *p2 = p1 + n1;
    double xs[21];
    memcpy(xs, j->xs, sizeof xs);
    int st = xcoef1(xs, cov, xcov, j->co);
    *bad = 0;
    for (int q = 0; q < n && st == 0; q++) {
        const double *co = j->co + 15 * (q & 1);
        double *y0 = T + 3 * (size_t)q * n1, *y1 = y0 + n1, *y2 = y1 + n1;
        const double g0 = co[0], g1 = co[1], g2 = co[2], l10 = co[3], l20 = co[4],
                     l21 = co[5], h00 = co[6], h01 = co[7], h02 = co[8], h10 = co[9],
                     h11 = co[10], h12 = co[11], h20 = co[12], h21 = co[13], h22 = co[14];
        /* the next epoch's coefficients, independent of this epoch's columns: the
           processor overlaps their chain with the columns below */
        if (q + 1 < n && (st = xcoef1(xs, cov + 6 * ((size_t)q + 1), xcov + 9 * ((size_t)q + 1),
                                      j->co + 15 * ((q + 1) & 1))))
            *bad = q + 1;
        int c = 0;
#if XC_VEC
        for (; c + 4 <= n1; c += 4) {
            const xc_v4 Y0 = XC_LD(y0 + c), Y1 = XC_LD(y1 + c), Y2 = XC_LD(y2 + c);
            const xc_v4 R0 = Y0 - XC_LD(p0 + c), R1 = Y1 - XC_LD(p1 + c),
                        R2 = Y2 - XC_LD(p2 + c);
            const xc_v4 V1 = R1 - l10 * R0;
            XC_ST(y0 + c, R0 * g0);
            XC_ST(y1 + c, V1 * g1);
            XC_ST(y2 + c, ((R2 - l20 * R0) - l21 * V1) * g2);
            XC_ST(p0 + c, Y0 + h00 * R0 + h01 * R1 + h02 * R2);
            XC_ST(p1 + c, Y1 + h10 * R0 + h11 * R1 + h12 * R2);
            XC_ST(p2 + c, Y2 + h20 * R0 + h21 * R1 + h22 * R2);
        }
#endif
        for (; c < n1; c++) {
            const double Y0 = y0[c], Y1 = y1[c], Y2 = y2[c];
            const double R0 = Y0 - p0[c], R1 = Y1 - p1[c], R2 = Y2 - p2[c];
            const double V1 = R1 - l10 * R0;
            y0[c] = R0 * g0;
            y1[c] = V1 * g1;
            y2[c] = ((R2 - l20 * R0) - l21 * V1) * g2;
            p0[c] = Y0 + h00 * R0 + h01 * R1 + h02 * R2;
            p1[c] = Y1 + h10 * R0 + h11 * R1 + h12 * R2;
            p2[c] = Y2 + h20 * R0 + h21 * R1 + h22 * R2;
        }
    }
    if (st == 0)
        memcpy(j->xs, xs, sizeof xs);
    return st;
}

/* Every epoch of the block through the streamed block Cholesky into the
 * job's sums (and white, m x (N + 1), ld m): per chunk the rows transposed
 * into blk, the recursion with the epochs' coefficients, then one dsyrk of
 * [S~ w~] (A and b) and the compensated w'w. */
static int xrun(wjob *j, int layout, int m, const double *S, int lds, const double *dw,
                const double *cov, const double *xcov, const int *mask, const double *spec,
                double *white, int *bad)
{
    const int N = j->h->N, n1 = N + 1, ld = j->xld, M = m / 3;
    for (int e0 = 0; e0 < M; e0 += j->E) {
        const int n = IGEA_MIN(j->E, M - e0), R = 3 * n;
        const size_t i0 = 3 * (size_t)e0;
        xfill(j, layout, e0, n, S, lds, dw, spec);
        double *T = j->blk;
        int st = xrec(j, n, T, cov + 6 * (size_t)e0, xcov + 9 * (size_t)e0, bad);
        if (st) {
            /* a NaN or Inf in K_ee or the X_e before it makes the pivots of epoch e
               fail (X of the call's last epoch is checked by the caller) */
            const size_t e = (size_t)e0 + *bad;
            if (!igea__finite_vec(6, cov + 6 * e, 1) ||
                (e > 0 && !igea__finite_vec(9, xcov + 9 * (e - 1), 1)))
                return IGEA_ENONFINITE;
            *bad += e0 + (int)j->epoch;
            return st;
        }
        for (int c = 0; white && c < n1; c++)
            for (int i = 0; i < R; i++)
                white[(size_t)c * m + i0 + i] = T[(size_t)i * ld + c];
        int kept = R;
        for (int i = 0; mask && i < R; i++) /* a masked row adds nothing */
            if (mask[i0 + i]) {
                memset(T + (size_t)i * ld, 0, (size_t)n1 * sizeof(double));
                kept--;
            }
        if (kept > 0) { /* [S~ w~]' [S~ w~]: A and, in its last row, b */
            cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, n1, R, 1.0, T, ld, 1.0,
                        j->xA, n1);
            for (int i = 0; i < R; i++)
                igea__ksum_add(&j->ww[0], T[(size_t)i * ld + N] * T[(size_t)i * ld + N]);
            j->nrows[0] += kept;
        }
    }
    j->epoch += M;
    return 0;
}

int igea_whiten_accumulate_xcov(igea_whiten *w, int layout, int m, const double *S, int lds,
                                const double *dw, const double *cov, const double *xcov,
                                const int *mask, const double *spec_sigma, double *A, int lda,
                                double *b, double *wtw, double *white, int *bad_epoch)
{
    if (!w || w->p != 0 || w->G != 1 || w->xmode == 1) return -1;
    if (layout != IGEA_COLMAJOR && layout != IGEA_ROWMAJOR) return -2;
    if (m < 0 || m % 3) return -3;
    if (!S && m > 0) return -4;
    if (lds < IGEA_MAX(1, layout == IGEA_COLMAJOR ? m : w->N)) return -5;
    if (!dw && m > 0) return -6;
    if (!cov && m > 0) return -7;
    if (!xcov && m > 0) return -8;
    for (int i = 0; mask && i < m; i++)
        if (mask[i] != 0 && mask[i] != 1) return -9;
    if (!A) return -11;
    if (lda < w->N) return -12;
    if (!b) return -13;
    if (!wtw || !(wtw[0] >= 0.0 && wtw[0] <= DBL_MAX) || !(wtw[1] >= 0.0 && wtw[1] <= DBL_MAX))
        return -14;
    int st;
    if (spec_sigma && (st = igea__sigma_vec(w->N, spec_sigma)))
        return st;
    if (m == 0)
        return 0;
    const int N = w->N, n1 = N + 1, ld = (n1 + 3) / 4 * 4;
    const int E = IGEA_MIN(IGEA_MAX(22, 32768 / (3 * ld)), m / 3);
    const size_t nh = 3 * (size_t)ld; /* the carried predictions (0 in the padding) */
    size_t nd = nh + (size_t)N * N + (size_t)N + 1 + (size_t)3 * E * ld + 30 +
                (size_t)n1 * n1 + (white ? (size_t)m * n1 : 0);
    double *work = igea__dalloc(nd);
    igea__ksum *ww = calloc(1, sizeof *ww);
    if (!work || !ww) {
        free(work);
        free(ww);
        return IGEA_ENOMEM;
    }
    wjob j;
    memset(&j, 0, sizeof j);
    j.h = w, j.epoch = w->epoch, j.group = 0, j.hist = work, j.ww = ww, j.E = E, j.xld = ld;
    if (w->xmode == 0) { /* the flight's first epoch: nothing before it */
        memset(j.hist, 0, nh * sizeof(double));
    } else {
        memcpy(j.hist, w->xprev, nh * sizeof(double));
        memcpy(j.xs, w->xs, sizeof j.xs);
    }
    j.Al = j.hist + nh;
    j.bl = j.Al + (size_t)N * N;
    j.nrows = j.bl + N;
    j.blk = j.nrows + 1;
    j.co = j.blk + (size_t)3 * E * ld;
    j.xA = j.co + 30;
    double *jwhite = white ? j.xA + (size_t)n1 * n1 : NULL;
    memset(j.Al, 0, ((size_t)N * N + N + 1) * sizeof(double));
    memset(j.xA, 0, (size_t)n1 * n1 * sizeof(double));
    for (int i = 0; i < 3 * E && ld > n1; i++) /* the padding: 0 through the recursion */
        memset(j.blk + (size_t)i * ld + n1, 0, (size_t)(ld - n1) * sizeof(double));
    int bad = -1;
    /* the last epoch's X_e only reaches the next call's pivots: checked here */
    st = igea__finite_vec(9, xcov + 9 * ((size_t)m / 3 - 1), 1) ? 0 : IGEA_ENONFINITE;
    if (st == 0)
        st = xrun(&j, layout, m, S, lds, dw, cov, xcov, mask, spec_sigma, jwhite, &bad);
    for (int c = 0; c < N; c++) { /* A and b out of the sums of [S~ w~] */
        memcpy(j.Al + (size_t)c * N + c, j.xA + (size_t)c * n1 + c,
               (size_t)(N - c) * sizeof(double));
        j.bl[c] = j.xA[(size_t)c * n1 + N];
    }
    if (st == IGEA_ENONFINITE || (st == 0 && !sums_finite(&j)))
        st = (igea__finite_vec(m, dw, 1) &&
              (layout == IGEA_COLMAJOR ? igea__finite_mat(m, N, S, lds)
                                       : igea__finite_mat(N, m, S, lds)) &&
              igea__finite_vec(2 * m, cov, 1) && igea__finite_vec(3 * m, xcov, 1))
                 ? IGEA_EOVERFLOW
                 : IGEA_ENONFINITE;
    if (st == 0 && white && !igea__finite_mat(m, n1, jwhite, m))
        st = IGEA_EOVERFLOW;
    if (st == 0)
        st = add_sums(&j, A, lda, b, wtw);
    if (st == 0) {
        if (white)
            memcpy(white, jwhite, (size_t)m * n1 * sizeof(double));
        memcpy(w->xprev, j.hist, nh * sizeof(double));
        memcpy(w->xs, j.xs, sizeof j.xs);
        w->epoch = j.epoch;
        w->group = 0;
        w->k = 0;
        w->xmode = 2;
    } else if (st == IGEA_ESINGULAR && bad_epoch)
        *bad_epoch = bad;
    free(work);
    free(ww);
    return st;
}
