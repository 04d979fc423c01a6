/* bench/eqerr_blocks.c - the orders of work in the driver's pass 1 and
 * pass 2 on row-major blocks (180,000 x 74, the driver's blocks of 7,084
 * rows and igea_normal_accumulate's 1,771-row pieces), CPU time of each
 * variant, the fastest of R rounds, every round running every variant in
 * turn (S, 107 MB, is more than the last level cache holds: each pass reads
 * it from memory, as the driver's passes do):
 *
 *   cc -O2 bench/eqerr_blocks.c -o build/eqerr_blocks -lopenblas -lm
 *   OPENBLAS_NUM_THREADS=1 build/eqerr_blocks [R]
 *
 * pass 1: the NaN/Inf scan, dsyrk and dgemv per piece, the axis sums per
 * block (the previous driver); the same without the scan; the axis sums
 * per piece before its dsyrk (igea_eqerr_accumulate); a bare read of the
 * piece before its dsyrk; dsyrk alone, from memory and on one piece in
 * cache; the floor's column-major Trans call. pass 2: one dgemv per block
 * against pieces of 384 rows with the next piece prefetched
 * (igea_eqerr_residual), and on rows in cache; a bare read of S. Each
 * variant's checksum is printed: the variants of a pass give the same
 * bits. docs/validation.md ("The driver on a .npy flight") quotes it.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cblas.h>

enum { M = 180000, N = 74, BLOCK = 7084, PIECE = 1771, RPIECE = 384, NV = 11 };

static double cpu(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int finite_run(size_t n, const double *x)
{
    for (size_t i = 0; i + 8 <= n; i += 8) {
        const double *p = x + i;
        if (((p[0] * 0.0 + p[1] * 0.0) + (p[2] * 0.0 + p[3] * 0.0)) +
                ((p[4] * 0.0 + p[5] * 0.0) + (p[6] * 0.0 + p[7] * 0.0)) !=
            0.0)
            return 0;
    }
    return 1;
}

/* igea_eqerr_axis_sums' loop: per axis, count, sum of dw, sums of S */
static void axis_sums(int m, const double *S, const double *dw, int row0, double *t)
{
    int a = row0 % 3;
    for (int i = 0; i < m; i++) {
        double *u = t + a * (N + 2);
        const double *s = S + (size_t)i * N;
        u[0] += 1.0;
        u[1] += dw[i];
        for (int j = 0; j < N; j++)
            u[2 + j] += s[j];
        a = a == 2 ? 0 : a + 1;
    }
}

static double bare_read(size_t n, const double *p)
{
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    for (size_t k = 0; k + 4 <= n; k += 4)
        s0 += p[k], s1 += p[k + 1], s2 += p[k + 2], s3 += p[k + 3];
    return s0 + s1 + s2 + s3;
}

static const char *name[NV] = {
    "pass 1: scan, dsyrk+dgemv per piece, axis sums per block (previous driver)",
    "pass 1: dsyrk+dgemv per piece, axis sums per block (no scan)",
    "pass 1: axis sums per piece, then its dsyrk+dgemv (igea_eqerr_accumulate)",
    "pass 1: bare read of the piece, dsyrk+dgemv, axis sums per block",
    "dsyrk NoTrans on row-major pieces, from memory",
    "dsyrk NoTrans on one row-major piece in cache (x 102)",
    "dsyrk Trans, column-major, whole (the floor)",
    "pass 2: one dgemv per block, from memory (previous)",
    "pass 2: pieces of 384 rows, the next prefetched (igea_eqerr_residual)",
    "pass 2: one dgemv per block on rows in cache",
    "a bare read of S from memory"};

int main(int argc, char **argv)
{
    int rounds = argc > 1 ? atoi(argv[1]) : 7;
    double *R = malloc(sizeof(double) * M * N), *C = malloc(sizeof(double) * M * N);
    double *dw = malloc(sizeof(double) * M), *e = malloc(sizeof(double) * M);
    double coef[N], A[N * N], Ab[N * N], b[N], bb[N];
    double t[3 * (N + 2)], best[NV], sum[NV];
    if (!R || !C || !dw || !e)
        return 1;
    for (int i = 0; i < M; i++) {
        double tt = (i / 3) / (double)(M / 3);
        dw[i] = 0.01 * sin(7.0 * i);
        for (int j = 0; j < N; j++)
            R[(size_t)i * N + j] = C[i + (size_t)j * M] =
                cos((j % 12 + 1) * tt + j) * pow(tt, 1 + j % 5) + 1e-3 * sin(1e3 * i + j);
    }
    for (int j = 0; j < N; j++)
        coef[j] = 0.1 * cos(j);
    for (int v = 0; v < NV; v++)
        best[v] = 1e9;
    for (int r = 0; r < rounds; r++)
        for (int v = 0; v < NV; v++) {
            memset(A, 0, sizeof A), memset(b, 0, sizeof b), memset(t, 0, sizeof t);
            double acc = 0, c0 = cpu();
            if (v <= 4)
                for (int d0 = 0; d0 < M; d0 += BLOCK) {
                    int dn = M - d0 < BLOCK ? M - d0 : BLOCK;
                    const double *D = R + (size_t)d0 * N;
                    if (v == 0 && !finite_run((size_t)dn * N, D))
                        return 2;
                    memset(Ab, 0, sizeof Ab), memset(bb, 0, sizeof bb);
                    for (int p0 = 0; p0 < dn; p0 += PIECE) {
                        int n = dn - p0 < PIECE ? dn - p0 : PIECE;
                        const double *P = D + (size_t)p0 * N;
                        if (v == 2)
                            axis_sums(n, P, dw + d0 + p0, d0 + p0, t);
                        if (v == 3)
                            acc += bare_read((size_t)n * N, P);
                        cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, N, n, 1.0, P, N,
                                    1.0, Ab, N);
                        if (v != 4)
                            cblas_dgemv(CblasColMajor, CblasNoTrans, N, n, 1.0, P, N,
                                        dw + d0 + p0, 1, 1.0, bb, 1);
                    }
                    if (v <= 1 || v == 3)
                        axis_sums(dn, D, dw + d0, d0, t);
                    for (int k = 0; k < N * N; k++)
                        A[k] += Ab[k];
                    for (int k = 0; k < N; k++)
                        b[k] += bb[k];
                }
            if (v == 5) {
                c0 = cpu(); /* the piece is in cache after its first call */
                for (int k = 0; k < M / PIECE; k++)
                    cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, N, PIECE, 1.0, R, N,
                                1.0, A, N);
            }
            if (v == 6)
                cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, N, M, 1.0, C, M, 0.0, A, N);
            if (v >= 7 && v <= 9)
                for (int d0 = 0; d0 < M; d0 += BLOCK) {
                    int dn = M - d0 < BLOCK ? M - d0 : BLOCK;
                    const double *D = v == 9 ? R : R + (size_t)d0 * N;
                    memcpy(e + d0, dw + d0, sizeof(double) * dn);
                    if (v != 8) {
                        cblas_dgemv(CblasColMajor, CblasTrans, N, dn, -1.0, D, N, coef, 1, 1.0,
                                    e + d0, 1);
                        continue;
                    }
                    for (int i0 = 0; i0 < dn; i0 += RPIECE) {
                        int n = dn - i0 < RPIECE ? dn - i0 : RPIECE;
                        if (i0 + n < dn) {
                            const char *p = (const char *)(D + (size_t)(i0 + n) * N);
                            int n2 = dn - i0 - n < RPIECE ? dn - i0 - n : RPIECE;
                            for (size_t k = 0; k < (size_t)n2 * N * sizeof(double); k += 64)
                                __builtin_prefetch(p + k, 0, 3);
                        }
                        cblas_dgemv(CblasColMajor, CblasTrans, N, n, -1.0, D + (size_t)i0 * N,
                                    N, coef, 1, 1.0, e + d0 + i0, 1);
                    }
                }
            if (v == 10)
                acc = bare_read((size_t)M * N, R);
            double c = cpu() - c0;
            if (c < best[v])
                best[v] = c;
            double s = acc * 0.0;
            for (int k = 0; k < N * N; k++)
                s += A[k];
            for (int k = 0; k < N; k++)
                s += b[k];
            for (int k = 0; k < 3 * (N + 2); k++)
                s += t[k];
            if (v >= 7 && v <= 8)
                for (int i = 0; i < M; i++)
                    s += e[i];
            sum[v] = s;
        }
    printf("180,000 x 74 row-major, CPU time, fastest of %d rounds (OPENBLAS_NUM_THREADS=%s):\n",
           rounds, getenv("OPENBLAS_NUM_THREADS") ? getenv("OPENBLAS_NUM_THREADS") : "unset");
    for (int v = 0; v < NV; v++)
        printf("  %-76s %6.2f ms  (checksum %.17g)\n", name[v], best[v] * 1e3,
               v <= 3 || (v >= 7 && v <= 8) ? sum[v] : 0.0);
    return 0;
}
