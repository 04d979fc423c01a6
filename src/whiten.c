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
    wjob j = {w, w->epoch, w->group, w->k, work, NULL, NULL, NULL, ww, E, NULL, NULL, NULL};
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
    } else if (st == IGEA_ESINGULAR && bad_epoch)
        *bad_epoch = bad;
    free(work);
    free(ww);
    return st;
}
