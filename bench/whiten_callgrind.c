/* bench/whiten_callgrind.c - instruction counts of the streamed
 * accumulations that bench/bench_whiten.py times, one variant per run:
 *
 *   cc -O2 -Iinclude bench/whiten_callgrind.c -o build/whiten_callgrind -Lbuild/lib -ligea \
 *      -lm -Wl,-rpath,$PWD/build/lib
 *   for v in 0 1 2 3; do OPENBLAS_NUM_THREADS=1 valgrind --tool=callgrind \
 *      --callgrind-out-file=cg.$v build/whiten_callgrind $v 60000 21; done
 *   callgrind_annotate --inclusive=yes cg.V | grep -E 'igea_(normal|whiten)_accumulate'
 *
 * Variant 0: igea_normal_accumulate with per-row sigmas (today's); 1:
 * igea_whiten_accumulate with a 3 x 3 covariance per epoch; 2: the same
 * with AR(1) per axis; 3: row sigmas, AR(3) per axis, two groups; 4:
 * igea_whiten_accumulate_xcov, the 3 x 3 blocks plus a random walk
 * R_e = 1e-4 e I (K_ee = C + R_e, X_e = R_e).
 * Arguments: variant, rows m, terms N; the rows stream in blocks of a
 * tenth. The inclusive count of the accumulation (summed over its calls)
 * is the figure; the data generation is not in it. docs/validation.md,
 * "Cost of whitening", quotes the counts.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "igea/noise.h"
#include "igea/normal.h"

int main(int argc, char **argv)
{
    int v = argc > 1 ? atoi(argv[1]) : 0, m = argc > 2 ? atoi(argv[2]) : 60000;
    int N = argc > 3 ? atoi(argv[3]) : 21;
    m -= m % 3;
    int blk = m / 10 - (m / 10) % 3, M = m / 3, G = v == 3 ? 2 : 1, p = v == 2 ? 1 : v == 3 ? 3 : 0;
    double *S = malloc(sizeof(double) * (size_t)m * N), *dw = malloc(sizeof(double) * m);
    double *sig = malloc(sizeof(double) * m), *cov = malloc(sizeof(double) * 2 * (size_t)m);
    double *xcov = calloc(3 * (size_t)m, sizeof(double));
    double *spec = malloc(sizeof(double) * N), *A = calloc((size_t)G * N * N, sizeof(double));
    double *b = calloc((size_t)G * N, sizeof(double)), wtw[4] = {0};
    int *grp = malloc(sizeof(int) * M);
    if (!S || !dw || !sig || !cov || !xcov || !spec || !A || !b || !grp)
        return 2;
    unsigned s = 1;
    for (size_t i = 0; i < (size_t)m * N; i++) {
        s = s * 1103515245u + 12345u;
        S[i] = ((s >> 8) & 0xffff) / 65536.0 - 0.5;
    }
    for (int i = 0; i < m; i++) {
        s = s * 1103515245u + 12345u;
        dw[i] = ((s >> 8) & 0xffff) / 65536.0;
        sig[i] = 0.5 + ((s >> 4) & 0xff) / 256.0;
    }
    for (int e = 0; e < M; e++) {
        double c6[6] = {1, 0.3, 1, 0.2, 0.4, 1};
        memcpy(cov + 6 * (size_t)e, c6, sizeof c6);
        grp[e] = e >= M / 2;
        if (v == 4) {
            double r = 1e-4 * e;
            cov[6 * (size_t)e] += r, cov[6 * (size_t)e + 2] += r, cov[6 * (size_t)e + 5] += r;
            xcov[9 * (size_t)e] = xcov[9 * (size_t)e + 4] = xcov[9 * (size_t)e + 8] = r;
        }
    }
    for (int j = 0; j < N; j++)
        spec[j] = 1.0;
    double phi[9] = {0.5, 0.5, 0.5};
    if (p == 3)
        for (int a = 0; a < 3; a++)
            phi[3 * a] = 0.5, phi[3 * a + 1] = 0.2, phi[3 * a + 2] = 0.1;
    igea_whiten *w = NULL;
    if (v > 0 && igea_whiten_create(N, p, phi, G, &w))
        return 2;
    int st = 0;
    for (int r0 = 0; r0 < m && st == 0; r0 += blk) {
        int nr = m - r0 < blk ? m - r0 : blk;
        if (v == 4)
            st = igea_whiten_accumulate_xcov(w, IGEA_COLMAJOR, nr, S + r0, m, dw + r0,
                                             cov + 2 * r0, xcov + 3 * r0, NULL, spec, A, N, b,
                                             wtw, NULL, NULL);
        else if (v == 0)
            st = igea_normal_accumulate(IGEA_COLMAJOR, nr, N, S + r0, m, dw + r0, sig + r0, 1,
                                        spec, A, N, b, wtw);
        else
            st = igea_whiten_accumulate(w, IGEA_COLMAJOR, nr, S + r0, m, dw + r0,
                                        v == 3 ? sig + r0 : NULL, 1, v == 3 ? NULL : cov + 2 * r0,
                                        v == 3 ? grp + r0 / 3 : NULL, NULL, spec, A, N, b, wtw,
                                        NULL, NULL);
    }
    printf("variant %d, %d x %d: status %d, A[1] %.17g\n", v, m, N, st, A[1]);
    igea_whiten_free(w);
    free(S), free(dw), free(sig), free(cov), free(xcov), free(spec), free(A), free(b), free(grp);
    return st != 0;
}
