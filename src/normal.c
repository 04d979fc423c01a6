/* normal.c - weighted normal equations (one dsyrk pass over the data) and
 * the streamed QR factor of the same weighted data (dtpqrt). */
#include <float.h>

#include <cblas.h>
#include <lapacke.h>

#include "igea/normal.h"
#include "internal.h"

/* Rows per internal block: the scaled copy of a block stays in cache. */
static int block_rows(int N)
{
    int rb = 65536 / (N > 0 ? N : 1);
    return IGEA_MAX(64, IGEA_MIN(rb, 4096));
}

/* Arguments 1-8 (shapes and pointers) of both accumulators. */
static int check_dims(int layout, int m, int N, const double *S, int lds,
                      const double *dw, const double *track_sigma, int sigma_inc)
{
    if (layout != IGEA_COLMAJOR && layout != IGEA_ROWMAJOR) return -1;
    if (m < 0) return -2;
    if (N < 1) return -3;
    if (!S && m > 0) return -4;
    if (lds < IGEA_MAX(1, layout == IGEA_COLMAJOR ? m : N)) return -5;
    if (!dw && m > 0) return -6;
    if (!track_sigma && m > 0) return -7;
    if (sigma_inc != 0 && sigma_inc != 1) return -8;
    return 0;
}

/* The specs and tracking sigmas must be positive and finite. */
static int check_weights(int m, int N, const double *track_sigma, int sigma_inc,
                         const double *spec_sigma)
{
    int st = spec_sigma ? igea__sigma_vec(N, spec_sigma) : 0;
    if (st == 0 && m > 0)
        st = igea__sigma_vec(sigma_inc ? m : 1, track_sigma);
    return st;
}

/* The per-axis sums of igea_eqerr_axis_sums taken along (igea_eqerr_accumulate):
 * t (3 (N + 2)), a the axis of the next row. Each block of rows is summed
 * just before its dsyrk, which then finds the rows in cache. */
typedef struct {
    int a;
    double *t;
} axis_acc;

static void axis_block(int layout, int r0, int nr, int N, const double *S, int lds,
                       const double *dw, axis_acc *ax)
{
    if (!ax)
        return;
    const double *Sb = layout == IGEA_COLMAJOR ? S + r0 : S + (size_t)r0 * lds;
    igea__axis_rows(layout, nr, N, Sb, lds, dw + r0, ax->a, ax->t);
    ax->a = (int)((ax->a + (long long)nr) % 3);
}

/* Why a weighted result is not finite: IGEA_ENONFINITE when rows r0..r0+nr-1
 * of S or dw hold a NaN or Inf, IGEA_EOVERFLOW when they are all finite
 * (the weighted sums left the double range). */
static int nonfinite_cause(int layout, int r0, int nr, int N, const double *S,
                           int lds, const double *dw)
{
    int fin = layout == IGEA_COLMAJOR
                  ? igea__finite_mat(nr, N, S + r0, lds)
                  : igea__finite_mat(N, nr, S + (size_t)r0 * lds, lds);
    return fin && igea__finite_vec(nr, dw + r0, 1) ? IGEA_EOVERFLOW
                                                   : IGEA_ENONFINITE;
}

/* Rows r0..r0+nr-1 weighted and scaled into blk (nr x N, column-major, ld
 * nr), the weighted dw into wb; wt is nr doubles of scratch. */
static void weight_block(int layout, int r0, int nr, int N, const double *S,
                         int lds, const double *dw, const double *track_sigma,
                         int sigma_inc, const double *spec_sigma, double *blk,
                         double *wb, double *wt)
{
    for (int i = 0; i < nr; i++) {
        wt[i] = 1.0 / track_sigma[sigma_inc ? r0 + i : 0];
        wb[i] = dw[r0 + i] * wt[i];
    }
    if (layout == IGEA_COLMAJOR) {
        for (int j = 0; j < N; j++) {
            const double *src = S + (size_t)j * lds + r0;
            double *dst = blk + (size_t)j * nr;
            double sc = spec_sigma ? spec_sigma[j] : 1.0;
            for (int i = 0; i < nr; i++)
                dst[i] = src[i] * sc * wt[i];
        }
    } else {
        for (int i = 0; i < nr; i++) {
            const double *src = S + (size_t)(r0 + i) * lds;
            if (spec_sigma)
                for (int j = 0; j < N; j++)
                    blk[i + (size_t)j * nr] = src[j] * spec_sigma[j] * wt[i];
            else
                for (int j = 0; j < N; j++)
                    blk[i + (size_t)j * nr] = src[j] * wt[i];
        }
    }
}

/* b += S^T x over nr row-major rows (lds apart), row after row: each b[j]
 * a plain sum in row order. */
static void rows_axpy(int nr, int N, const double *S, int lds, const double *x,
                      double *restrict b)
{
    for (int i = 0; i < nr; i++) {
        const double *restrict s = S + (size_t)i * lds;
        double a = x[i];
        for (int j = 0; j < N; j++)
            b[j] += a * s[j];
    }
}

/* One tracking sigma for every row: no copy of S, one dsyrk over the
 * caller's array and the weights applied to the N x N result Al (lower)
 * and bl; wb is m doubles of scratch, ww gathers w'w. seg: a segment of
 * the threaded sums (igea_normal_accumulate_threads, nthreads >= 2). */
static void accumulate_uniform(int layout, int m, int N, const double *S, int lds,
                               const double *dw, double sigma,
                               const double *spec_sigma, double *Al, double *bl,
                               double *wb, igea__ksum *ww, axis_acc *ax, int seg)
{
    double w = 1.0 / sigma;
    for (int i = 0; i < m; i++) {
        wb[i] = dw[i] * w;
        igea__ksum_add(ww, wb[i] * wb[i]);
        wb[i] *= w;
    }
    /* Row blocks of about 1 MB: dgemv finds the block dsyrk has just
     * brought into cache, so S is read from memory once. */
    const int ub = IGEA_MAX(256, (1 << 17) / N);
    for (int r0 = 0; r0 < m; r0 += ub) {
        int nr = IGEA_MIN(ub, m - r0);
        axis_block(layout, r0, nr, N, S, lds, dw, ax);
        if (layout == IGEA_COLMAJOR) {
            /* dgemv first: it reads the columns from memory a little
             * faster than dsyrk does, and dsyrk then finds them in cache
             * (180,000 x 74: 36.8 ms against 37.8 ms); the two sums are
             * apart, so the order changes no bit */
            const double *Sb = S + r0;
            cblas_dgemv(CblasColMajor, CblasTrans, nr, N, 1.0, Sb, lds, wb + r0, 1, 1.0, bl, 1);
            cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, N, nr, w * w, Sb, lds, 1.0, Al, N);
        } else if (seg) {
            /* [D] Row-major rows in a segment: b by rows first, a loop that
             * streams the rows from memory at its speed, so that dsyrk,
             * which waits for memory when it reads row-major rows first,
             * finds them in cache (180,000 x 74: 40.7 ms against 45.1 ms
             * for dsyrk then dgemv). One thread keeps dsyrk and dgemv, and
             * their bits. */
            const double *Sb = S + (size_t)r0 * lds;
            rows_axpy(nr, N, Sb, lds, wb + r0, bl);
            cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, N, nr, w * w, Sb, lds, 1.0, Al, N);
        } else {
            const double *Sb = S + (size_t)r0 * lds;
            cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, N, nr, w * w, Sb, lds, 1.0, Al, N);
            cblas_dgemv(CblasColMajor, CblasNoTrans, N, nr, 1.0, Sb, lds, wb + r0, 1, 1.0, bl, 1);
        }
    }
    if (spec_sigma) {
        for (int j = 0; j < N; j++) {
            for (int i = j; i < N; i++)
                Al[i + (size_t)j * N] *= spec_sigma[i] * spec_sigma[j];
            bl[j] *= spec_sigma[j];
        }
    }
}

/* Rows of different sigmas: weighted in cache-sized blocks of rb rows
 * (scratch: rb (N + 2) doubles). */
static void accumulate_blocks(int layout, int m, int N, const double *S, int lds,
                              const double *dw, const double *track_sigma,
                              int sigma_inc, const double *spec_sigma, int rb,
                              double *Al, double *bl, double *scratch, igea__ksum *ww,
                              axis_acc *ax)
{
    double *blk = scratch, *wb = blk + (size_t)rb * N, *wt = wb + rb;
    for (int r0 = 0; r0 < m; r0 += rb) {
        int nr = IGEA_MIN(rb, m - r0);
        axis_block(layout, r0, nr, N, S, lds, dw, ax);
        weight_block(layout, r0, nr, N, S, lds, dw, track_sigma, sigma_inc,
                     spec_sigma, blk, wb, wt);
        cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, N, nr, 1.0, blk, nr, 1.0, Al, N);
        cblas_dgemv(CblasColMajor, CblasTrans, nr, N, 1.0, blk, nr, wb, 1, 1.0, bl, 1);
        for (int i = 0; i < nr; i++)
            igea__ksum_add(ww, wb[i] * wb[i]);
    }
}

/* Add Al (lower, N x N), bl and ww to the running A (both triangles), b
 * and wtw, or IGEA_EOVERFLOW (checked before any write). */
static int add_running(int m, int N, const double *Al, const double *bl, double ww,
                       double *A, int lda, double *b, double *wtw)
{
    int over = !isfinite(wtw[0] + ww);
    for (int j = 0; j < N && !over; j++) {
        over = !isfinite(b[j] + bl[j]);
        for (int i = j; i < N && !over; i++) {
            double v = Al[i + (size_t)j * N];
            over = !isfinite(IGEA_AT(A, lda, i, j) + v) ||
                   (i != j && !isfinite(IGEA_AT(A, lda, j, i) + v));
        }
    }
    if (over)
        return IGEA_EOVERFLOW;
    for (int j = 0; j < N; j++) {
        for (int i = j; i < N; i++) {
            double v = Al[i + (size_t)j * N];
            IGEA_AT(A, lda, i, j) += v;
            if (i != j)
                IGEA_AT(A, lda, j, i) += v;
        }
        b[j] += bl[j];
    }
    wtw[0] += ww;
    wtw[1] += m;
    return 0;
}

/* Every argument of igea_normal_accumulate (and of the threaded form). */
static int check_accumulate(int layout, int m, int N, const double *S, int lds,
                            const double *dw, const double *track_sigma, int sigma_inc,
                            const double *spec_sigma, const double *A, int lda,
                            const double *b, const double *wtw)
{
    int st = check_dims(layout, m, N, S, lds, dw, track_sigma, sigma_inc);
    if (st) return st;
    if (!A) return -10;
    if (lda < N) return -11;
    if (!b) return -12;
    if (!wtw || !(wtw[0] >= 0.0 && wtw[0] <= DBL_MAX) ||
        !(wtw[1] >= 0.0 && wtw[1] < 0x1p53))
        return -13;
    return check_weights(m, N, track_sigma, sigma_inc, spec_sigma);
}

/* igea_normal_accumulate after its checks, with the axis sums ax taken
 * along (NULL: none; their status after the normal equations', before
 * anything is written to A, b, wtw). */
static int accumulate_ax(int layout, int m, int N, const double *S, int lds, const double *dw,
                         const double *track_sigma, int sigma_inc, const double *spec_sigma,
                         double *A, int lda, double *b, double *wtw, axis_acc *ax, int seg)
{
    if (m == 0)
        return 0;
    /* One tracking sigma for every row (the common case), or rows weighted
     * in cache-sized blocks. */
    int uniform = 1;
    if (sigma_inc)
        for (int i = 1; i < m && uniform; i++)
            uniform = track_sigma[i] == track_sigma[0];
    const int rb = uniform ? 0 : IGEA_MIN(block_rows(N), m);
    size_t nn = (size_t)N * (size_t)N;
    size_t nw = uniform ? (size_t)m : (size_t)rb * ((size_t)N + 2);
    double *work = igea__dalloc(nn + (size_t)N + nw);
    if (!work)
        return IGEA_ENOMEM;
    double *Al = work, *bl = Al + nn;
    memset(Al, 0, (nn + (size_t)N) * sizeof(double));
    igea__ksum ww = {0, 0};
    if (uniform)
        accumulate_uniform(layout, m, N, S, lds, dw, track_sigma[0], spec_sigma, Al, bl,
                           bl + N, &ww, ax, seg);
    else
        accumulate_blocks(layout, m, N, S, lds, dw, track_sigma, sigma_inc, spec_sigma,
                          rb, Al, bl, bl + N, &ww, ax);
    /* A NaN or Inf anywhere in S or dw reaches a diagonal element of A (a
     * sum of squares, which cannot cancel), b or w'w: one O(N) check; so
     * does an overflow of the weighted sums of finite data, told apart by a
     * scan of the inputs on that failure path only. */
    int st;
    if (!igea__finite_vec(N, Al, N + 1) || !igea__finite_vec(N, bl, 1) ||
        !isfinite(igea__ksum_get(&ww)))
        st = nonfinite_cause(layout, 0, m, N, S, lds, dw);
    else if (!ax || !(st = igea__axis_status(layout, m, N, S, lds, ax->t)))
        st = add_running(m, N, Al, bl, igea__ksum_get(&ww), A, lda, b, wtw);
    free(work);
    return st;
}

int igea_normal_accumulate(int layout, int m, int N, const double *S, int lds,
                           const double *dw, const double *track_sigma,
                           int sigma_inc, const double *spec_sigma, double *A,
                           int lda, double *b, double *wtw)
{
    int st = check_accumulate(layout, m, N, S, lds, dw, track_sigma, sigma_inc, spec_sigma,
                              A, lda, b, wtw);
    if (st)
        return st;
    return accumulate_ax(layout, m, N, S, lds, dw, track_sigma, sigma_inc, spec_sigma, A,
                         lda, b, wtw, NULL, 0);
}

int igea_normal_qr_accumulate(int layout, int m, int N, const double *S,
                              int lds, const double *dw,
                              const double *track_sigma, int sigma_inc,
                              const double *spec_sigma, double *R, int ldr,
                              double *rows)
{
    int st = check_dims(layout, m, N, S, lds, dw, track_sigma, sigma_inc);
    if (st) return st;
    if (!R) return -10;
    if (ldr < N + 1) return -11;
    if (!rows || !(*rows >= 0.0 && *rows < 0x1p53)) return -12;
    if ((st = check_weights(m, N, track_sigma, sigma_inc, spec_sigma)))
        return st;
    if (m == 0)
        return 0;
    const int n1 = N + 1, nb = IGEA_MIN(32, n1);
    const int rb = IGEA_MIN(IGEA_MAX(block_rows(N), n1), m);
    size_t rr = (size_t)n1 * n1;
    /* scratch: R copy, block [S~ w~] (rb x n1), T (nb x n1), work (nb x n1),
     * weights (rb) */
    double *work = igea__dalloc(rr + (size_t)rb * n1 + 2 * (size_t)nb * n1 + (size_t)rb);
    if (!work)
        return IGEA_ENOMEM;
    double *Rl = work, *blk = Rl + rr, *T = blk + (size_t)rb * n1, *tw = T + (size_t)nb * n1;
    double *wt = tw + (size_t)nb * n1;
    for (int j = 0; j < n1; j++)
        for (int i = 0; i < n1; i++)
            Rl[i + (size_t)j * n1] = i <= j ? IGEA_AT(R, ldr, i, j) : 0.0;
    for (int r0 = 0; r0 < m && st == 0; r0 += rb) {
        int nr = IGEA_MIN(rb, m - r0);
        weight_block(layout, r0, nr, N, S, lds, dw, track_sigma, sigma_inc, spec_sigma,
                     blk, blk + (size_t)N * nr, wt);
        if (!igea__finite_mat(nr, n1, blk, nr)) {
            st = nonfinite_cause(layout, r0, nr, N, S, lds, dw);
            break;
        }
        if (LAPACKE_dtpqrt_work(LAPACK_COL_MAJOR, nr, n1, 0, nb, Rl, n1, blk, nr, T, nb, tw) != 0)
            st = IGEA_ELAPACK;
    }
    if (st == 0 && !igea__finite_mat(n1, n1, Rl, n1))
        st = IGEA_EOVERFLOW; /* every block was finite */
    if (st == 0) {
        for (int j = 0; j < n1; j++)
            for (int i = 0; i <= j; i++)
                IGEA_AT(R, ldr, i, j) = Rl[i + (size_t)j * n1];
        *rows += m;
    }
    free(work);
    return st;
}

/* ---- the normal equations on several threads ---------------------------- */

/* Rows per segment: each segment has its own sums, whatever thread runs
 * it, so that the result does not depend on the thread count. */
#define MT_SEGMENT IGEA_NORMAL_SEGMENT

typedef struct {
    int layout, m, N, lds, sigma_inc, nseg, row0;
    const double *S, *dw, *track_sigma, *spec_sigma;
    double *part; /* nseg x stride: each segment's A, b, wtw (and axis sums) */
    size_t stride;
    int sums;     /* 1: the axis sums too (igea_eqerr_accumulate) */
    int *status;  /* nseg */
} mt_job;

/* Segment k into its own sums, whatever thread runs it (the arguments were
 * checked for the whole block). */
static void mt_segment(void *arg, int k)
{
    const mt_job *jb = arg;
    size_t N = (size_t)jb->N;
    int r0 = k * MT_SEGMENT, nr = IGEA_MIN(MT_SEGMENT, jb->m - r0);
    const double *Sk = jb->layout == IGEA_COLMAJOR ? jb->S + r0 : jb->S + (size_t)r0 * jb->lds;
    double *Ak = jb->part + (size_t)k * jb->stride;
    memset(Ak, 0, jb->stride * sizeof(double)); /* here, on the segment's thread [D] */
    axis_acc ax = {(int)(((long long)jb->row0 + r0) % 3), Ak + N * N + N + 2};
    jb->status[k] = accumulate_ax(jb->layout, nr, jb->N, Sk, jb->lds, jb->dw + r0,
                                  jb->track_sigma + (jb->sigma_inc ? r0 : 0), jb->sigma_inc,
                                  jb->spec_sigma, Ak, jb->N, Ak + N * N, Ak + N * N + N,
                                  jb->sums ? &ax : NULL, 1);
}

/* The segments' sums in segment order into Al (lower), bl, *ww and (with
 * the axis sums) t; the first failing segment's status, or 0. */
static int mt_sum(const mt_job *jb, double *Al, double *bl, double *ww, double *t)
{
    size_t N = (size_t)jb->N;
    for (int k = 0; k < jb->nseg; k++)
        if (jb->status[k])
            return jb->status[k];
    memset(Al, 0, (N * N + N) * sizeof(double));
    *ww = 0.0;
    for (int k = 0; k < jb->nseg; k++) {
        const double *Ak = jb->part + (size_t)k * jb->stride;
        for (size_t j = 0; j < N; j++)
            for (size_t i = j; i < N; i++)
                Al[i + j * N] += Ak[i + j * N];
        for (size_t j = 0; j < N; j++)
            bl[j] += Ak[N * N + j];
        *ww += Ak[N * N + N];
        for (size_t j = 0; jb->sums && j < 3 * (N + 2); j++)
            t[j] += Ak[N * N + N + 2 + j];
    }
    return 0;
}

/* The normal equations (and with sums the axis sums, t a copy of them) on
 * nthreads >= 2 threads, after the argument checks. */
static int accumulate_mt(int layout, int m, int N, const double *S, int lds, const double *dw,
                         const double *track_sigma, int sigma_inc, const double *spec_sigma,
                         double *A, int lda, double *b, double *wtw, int nthreads, int row0,
                         double *t)
{
    if (m == 0)
        return 0;
    int nseg = (m + MT_SEGMENT - 1) / MT_SEGMENT;
    size_t nn = (size_t)N * N, stride = nn + (size_t)N + 2 + (t ? 3 * ((size_t)N + 2) : 0);
    double *part = igea__dalloc((size_t)nseg * stride + nn + (size_t)N);
    int *status = igea__ialloc((size_t)nseg);
    int st = IGEA_ENOMEM;
    if (part && status) {
        mt_job jb = {layout, m, N, lds, sigma_inc, nseg, row0, S, dw, track_sigma, spec_sigma,
                     part, stride, t != NULL, status};
        igea__parallel_for(nseg, nthreads, mt_segment, &jb);
        double *Al = part + (size_t)nseg * stride, ww;
        st = mt_sum(&jb, Al, Al + nn, &ww, t);
        if (st == 0 && t)
            st = igea__axis_status(layout, m, N, S, lds, t);
        if (st == 0)
            st = add_running(m, N, Al, Al + nn, ww, A, lda, b, wtw);
    }
    free(part);
    free(status);
    return st;
}

/* igea_normal_accumulate_threads after its argument checks. */
int igea__normal_accumulate_threads(int layout, int m, int N, const double *S, int lds,
                                    const double *dw, const double *track_sigma, int sigma_inc,
                                    const double *spec_sigma, double *A, int lda, double *b,
                                    double *wtw, int nthreads)
{
    if (nthreads <= 1)
        return accumulate_ax(layout, m, N, S, lds, dw, track_sigma, sigma_inc, spec_sigma, A,
                             lda, b, wtw, NULL, 0);
    return accumulate_mt(layout, m, N, S, lds, dw, track_sigma, sigma_inc, spec_sigma, A, lda,
                         b, wtw, nthreads, 0, NULL);
}

int igea__normal_accumulate_sums(int layout, int m, int N, const double *S, int lds,
                                 const double *dw, const double *track_sigma, int sigma_inc,
                                 const double *spec_sigma, double *A, int lda, double *b,
                                 double *wtw, int nthreads, int row0, double *sums)
{
    size_t w3 = 3 * ((size_t)N + 2);
    double *t = igea__dalloc(w3);
    if (!t)
        return IGEA_ENOMEM;
    memcpy(t, sums, w3 * sizeof(double));
    int st;
    if (nthreads <= 1) {
        axis_acc ax = {(int)((long long)row0 % 3), t};
        st = accumulate_ax(layout, m, N, S, lds, dw, track_sigma, sigma_inc, spec_sigma, A,
                           lda, b, wtw, &ax, 0);
    } else {
        st = accumulate_mt(layout, m, N, S, lds, dw, track_sigma, sigma_inc, spec_sigma, A,
                           lda, b, wtw, nthreads, row0, t);
    }
    if (st == 0)
        memcpy(sums, t, w3 * sizeof(double));
    free(t);
    return st;
}

/* Every argument of igea_normal_accumulate_threads. */
int igea__normal_check_threads(int layout, int m, int N, const double *S, int lds,
                               const double *dw, const double *track_sigma, int sigma_inc,
                               const double *spec_sigma, const double *A, int lda,
                               const double *b, const double *wtw, int nthreads)
{
    int st = check_accumulate(layout, m, N, S, lds, dw, track_sigma, sigma_inc, spec_sigma,
                              A, lda, b, wtw);
    if (st)
        return st;
    if (nthreads < 0 || nthreads > IGEA_NORMAL_THREADS_MAX)
        return -14;
    return 0;
}

int igea_normal_accumulate_threads(int layout, int m, int N, const double *S, int lds,
                                   const double *dw, const double *track_sigma, int sigma_inc,
                                   const double *spec_sigma, double *A, int lda, double *b,
                                   double *wtw, int nthreads)
{
    int st = igea__normal_check_threads(layout, m, N, S, lds, dw, track_sigma, sigma_inc,
                                        spec_sigma, A, lda, b, wtw, nthreads);
    if (st)
        return st;
    return igea__normal_accumulate_threads(layout, m, N, S, lds, dw, track_sigma, sigma_inc,
                                           spec_sigma, A, lda, b, wtw, nthreads);
}
