/* normal.c - weighted normal equations, one dsyrk pass over the data. */
#include <cblas.h>

#include "igea/normal.h"
#include "internal.h"

/* Rows per internal block: the scaled copy of a block stays in cache. */
static int block_rows(int N)
{
    int rb = 65536 / (N > 0 ? N : 1);
    return IGEA_MAX(64, IGEA_MIN(rb, 4096));
}

int igea_normal_accumulate(int layout, int m, int N, const double *S, int lds,
                           const double *dw, const double *track_sigma,
                           int sigma_inc, const double *spec_sigma, double *A,
                           int lda, double *b, double *wtw)
{
    if (layout != IGEA_COLMAJOR && layout != IGEA_ROWMAJOR) return -1;
    if (m < 0) return -2;
    if (N < 1) return -3;
    if (!S && m > 0) return -4;
    if (lds < IGEA_MAX(1, layout == IGEA_COLMAJOR ? m : N)) return -5;
    if (!dw && m > 0) return -6;
    if (!track_sigma && m > 0) return -7;
    if (sigma_inc != 0 && sigma_inc != 1) return -8;
    if (!A) return -10;
    if (lda < N) return -11;
    if (!b) return -12;
    if (!wtw) return -13;
    if (spec_sigma) {
        int nf;
        if (!igea__positive_vec(N, spec_sigma, &nf))
            return nf ? IGEA_ENONFINITE : IGEA_ENONPOSITIVE;
    }
    if (m == 0)
        return 0;
    if (sigma_inc == 0 || m > 0) {
        int nf;
        if (!igea__positive_vec(sigma_inc ? m : 1, track_sigma, &nf))
            return nf ? IGEA_ENONFINITE : IGEA_ENONPOSITIVE;
    }

    const int rb = IGEA_MIN(block_rows(N), m);
    /* scratch: local A (N*N), b (N), scaled block (rb*N), weighted dw (rb) */
    size_t nn = (size_t)N * (size_t)N;
    double *work = igea__dalloc(nn + (size_t)N + (size_t)rb * (size_t)N + (size_t)rb);
    if (!work)
        return IGEA_ENOMEM;
    double *Al = work, *bl = Al + nn, *blk = bl + N, *wb = blk + (size_t)rb * N;
    memset(Al, 0, (nn + (size_t)N) * sizeof(double));
    igea__ksum ww = {0, 0};
    int bad = 0;

    for (int r0 = 0; r0 < m && !bad; r0 += rb) {
        int nr = IGEA_MIN(rb, m - r0);
        for (int i = 0; i < nr; i++) {
            double w = 1.0 / track_sigma[sigma_inc ? r0 + i : 0];
            wb[i] = dw[r0 + i] * w;
        }
        if (layout == IGEA_COLMAJOR) {
            for (int j = 0; j < N; j++) {
                const double *src = S + (size_t)j * lds + r0;
                double *dst = blk + (size_t)j * nr;
                double sc = spec_sigma ? spec_sigma[j] : 1.0;
                if (sigma_inc)
                    for (int i = 0; i < nr; i++)
                        dst[i] = src[i] * (sc / track_sigma[r0 + i]);
                else {
                    double f = sc / track_sigma[0];
                    for (int i = 0; i < nr; i++)
                        dst[i] = src[i] * f;
                }
            }
        } else {
            for (int i = 0; i < nr; i++) {
                const double *src = S + (size_t)(r0 + i) * lds;
                double w = 1.0 / track_sigma[sigma_inc ? r0 + i : 0];
                if (spec_sigma)
                    for (int j = 0; j < N; j++)
                        blk[i + (size_t)j * nr] = src[j] * spec_sigma[j] * w;
                else
                    for (int j = 0; j < N; j++)
                        blk[i + (size_t)j * nr] = src[j] * w;
            }
        }
        if (!igea__finite_mat(nr, N, blk, nr) || !igea__finite_vec(nr, wb, 1)) {
            bad = 1;
            break;
        }
        cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, N, nr, 1.0, blk, nr,
                    1.0, Al, N);
        cblas_dgemv(CblasColMajor, CblasTrans, nr, N, 1.0, blk, nr, wb, 1, 1.0,
                    bl, 1);
        for (int i = 0; i < nr; i++)
            igea__ksum_add(&ww, wb[i] * wb[i]);
    }
    if (bad) {
        free(work);
        return IGEA_ENONFINITE;
    }
    for (int j = 0; j < N; j++) {
        for (int i = j; i < N; i++) {
            double v = Al[i + (size_t)j * N];
            IGEA_AT(A, lda, i, j) += v;
            if (i != j)
                IGEA_AT(A, lda, j, i) += v;
        }
        b[j] += bl[j];
    }
    wtw[0] += igea__ksum_get(&ww);
    wtw[1] += m;
    free(work);
    return 0;
}
