/* linalg.c - the dense kernels shared by the modules: SVD with the
 * METHODS 0.3 signs and rank cut, Cholesky factor. */
#include <lapacke.h>

#include "internal.h"

int igea__svd(int m, int N, double *a, double *s, double *U, int full_u,
              double *V)
{
    int k = IGEA_MIN(m, N);
    char jobz = full_u || m < N ? 'A' : 'S';
    /* The _work entry point with igea's own workspace: the high-level one
     * allocates behind the library's back and prints when that fails. */
    lapack_int *iwork = malloc(sizeof(lapack_int) * (8 * (size_t)k + 1));
    if (!iwork)
        return IGEA_ENOMEM;
    double wq;
    int st = 0;
    lapack_int info = LAPACKE_dgesdd_work(LAPACK_COL_MAJOR, jobz, m, N, a, m,
                                          s, U, m, V, N, &wq, -1, iwork);
    if (info == 0) {
        size_t lw = (size_t)wq + 1;
        double *work = igea__dalloc(lw);
        if (!work)
            st = IGEA_ENOMEM;
        else {
            info = LAPACKE_dgesdd_work(LAPACK_COL_MAJOR, jobz, m, N, a, m, s,
                                       U, m, V, N, work, (lapack_int)lw,
                                       iwork);
            free(work);
        }
    }
    free(iwork);
    if (st == 0 && info != 0)
        st = IGEA_ELAPACK;
    if (st != 0)
        return st;
    /* V holds V^T: transpose in place into the columns v_i. */
    igea__transpose(N, V, N);
    for (int i = 0; i < N; i++) {
        int sg = igea__sign_fix(N, V + (size_t)i * N);
        if (sg < 0 && i < k)
            for (int r = 0; r < m; r++)
                U[r + (size_t)i * m] = -U[r + (size_t)i * m];
    }
    return 0;
}

int igea__rank_cut(int k, const double *s, double tol)
{
    int r = 0;
    if (k > 0 && s[0] > 0.0)
        while (r < k && s[r] > tol * s[0])
            r++;
    return r;
}

void igea__transpose(int n, double *a, int lda)
{
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++) {
            double t = a[i + (size_t)j * lda];
            a[i + (size_t)j * lda] = a[j + (size_t)i * lda];
            a[j + (size_t)i * lda] = t;
        }
}

int igea__chol_lower(int n, double *a, int lda, double shift)
{
    for (int j = 0; j < n; j++) {
        double d = shift + a[j + (size_t)j * lda];
        for (int l = 0; l < j; l++)
            d -= a[j + (size_t)l * lda] * a[j + (size_t)l * lda];
        if (!(d > 0.0) || !isfinite(d))
            return isfinite(d) ? IGEA_ESINGULAR : IGEA_ENONFINITE;
        d = sqrt(d);
        a[j + (size_t)j * lda] = d;
        for (int i = j + 1; i < n; i++) {
            double t = a[i + (size_t)j * lda];
            for (int l = 0; l < j; l++)
                t -= a[i + (size_t)l * lda] * a[j + (size_t)l * lda];
            a[i + (size_t)j * lda] = t / d;
        }
    }
    return 0;
}
