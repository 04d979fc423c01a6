/*
 * igea/normal.h - weighted normal equations (METHODS 1.2 step 0-1).
 *
 * For observations dw = S X + e with diagonal tracking covariance
 * K = diag(track_sigma^2) and columns of S scaled by the 1-sigma specs D =
 * diag(spec_sigma), this accumulates
 *     A += D S^T K^-1 S D,   b += D S^T K^-1 dw,
 *     wtw[0] += dw^T K^-1 dw,  wtw[1] += number of rows,
 * so a flight of any length can be streamed in row blocks with O(N^2)
 * memory: zero A (N x N), b (N) and wtw (2), then call once per block.
 * The whole of A is updated (both triangles).
 */
#ifndef IGEA_NORMAL_H
#define IGEA_NORMAL_H

#include "igea/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Layout of S (IGEA_COLMAJOR, IGEA_ROWMAJOR of igea/common.h):
 * IGEA_COLMAJOR: S is m x N column-major, lds >= max(1, m) (Fortran);
 * IGEA_ROWMAJOR: the array holds S^T, i.e. N x m column-major with
 * lds >= N, which is S stored row by row (C, numpy, .npy files). */

/*
 * Arguments (1-based positions, as the -i status names them):
 *  1 layout       IGEA_COLMAJOR or IGEA_ROWMAJOR
 *  2 m            rows in this block, >= 0 (0 is a no-op)
 *  3 N            error terms, >= 1
 *  4 S            the block, see layout
 *  5 lds          its leading dimension
 *  6 dw           m velocity differences
 *  7 track_sigma  tracking 1-sigma per row (sigma_inc = 1) or one value for
 *                 all rows (sigma_inc = 0); > 0 (IGEA_ENONPOSITIVE)  and
 *                 >= IGEA_SIGMA_MIN (IGEA_ERANGE)
 *  8 sigma_inc    0 or 1
 *  9 spec_sigma   N specs (> 0, >= IGEA_SIGMA_MIN), or NULL for no
 *                 column scaling
 * 10 A, 11 lda >= N, 12 b, 13 wtw[2]: running sums, updated in place
 *    (wtw[0] and wtw[1] finite and >= 0, else -13).
 * Returns 0, -i, IGEA_ENONFINITE (NaN/Inf in S, dw or sigma),
 * IGEA_ENONPOSITIVE, IGEA_ERANGE, IGEA_EOVERFLOW (S and dw are finite but
 * a weighted sum, or a running sum, overflowed: rescale the inputs),
 * IGEA_ENOMEM. On failure A, b, wtw are untouched.
 */
IGEA_API int igea_normal_accumulate(int layout, int m, int N, const double *S,
                                    int lds, const double *dw,
                                    const double *track_sigma, int sigma_inc,
                                    const double *spec_sigma, double *A,
                                    int lda, double *b, double *wtw);

/*
 * igea_normal_accumulate on several threads: the m rows in segments of
 * IGEA_NORMAL_SEGMENT rows, each accumulated by igea_normal_accumulate into
 * its own zeroed sums on one of nthreads threads (but for b of row-major
 * rows with one tracking sigma, a plain sum over the rows in order instead
 * of dgemv: the loop brings the rows into cache for dsyrk), the segments'
 * sums added in segment order, then to A, b, wtw. The result is the same for every
 * nthreads >= 2 (for the same m rows per call) and equals
 * igea_normal_accumulate's to rounding; nthreads 0 or 1 is
 * igea_normal_accumulate itself. The BLAS calls run on the threads made
 * here: a threaded BLAS should be set to one thread by the host (the library
 * never sets it).
 * Arguments 1-13 as igea_normal_accumulate (9 spec_sigma may be NULL: no
 * column scaling); 14 nthreads, 0 .. IGEA_NORMAL_THREADS_MAX (a thread that
 * cannot start: its segments run on the calling thread).
 * Returns igea_normal_accumulate's statuses (a failing segment: the first
 * one's), -14; on failure A, b, wtw are untouched.
 */
#define IGEA_NORMAL_SEGMENT 8192
#define IGEA_NORMAL_THREADS_MAX 256
IGEA_API int igea_normal_accumulate_threads(int layout, int m, int N, const double *S,
                                            int lds, const double *dw,
                                            const double *track_sigma, int sigma_inc,
                                            const double *spec_sigma, double *A, int lda,
                                            double *b, double *wtw, int nthreads);

/*
 * The same data as an orthogonal factorisation, for the accuracy (SVD)
 * route of METHODS 1.2-1.3 on flights of any length (TSQR): R is the
 * (N+1) x (N+1) upper-triangular factor of the weighted, spec-scaled
 * augmented matrix [D S' K^-1/2 ; dw' K^-1/2]' = [S~ w~], updated in place
 * per row block with LAPACK dtpqrt. Zero R (and *rows) before the first
 * block. Then R[0:N, 0:N] is the R of S~ (R'R = A, without squaring the
 * condition number), R[0:N, N] = Q' w~, and R[N, N]^2 the residual sum of
 * squares of the weighted least-squares fit. Only the upper triangle of R
 * is read or written.
 * Arguments 1-9 as igea_normal_accumulate; 10 R, 11 ldr >= N + 1,
 * 12 rows (a running row count, as wtw[1]: >= 0 and below 2^53, else
 * -12).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE,
 * IGEA_EOVERFLOW (finite data whose weighted rows or factor overflowed),
 * IGEA_ENOMEM, IGEA_ELAPACK; R and rows are untouched on failure.
 */
IGEA_API int igea_normal_qr_accumulate(int layout, int m, int N,
                                       const double *S, int lds,
                                       const double *dw,
                                       const double *track_sigma,
                                       int sigma_inc, const double *spec_sigma,
                                       double *R, int ldr, double *rows);

#ifdef __cplusplus
}
#endif
#endif
