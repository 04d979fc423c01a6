/* bench/syrk_callgrind.c - the floor of bench/eqerr_callgrind.c: one
 * cblas_dsyrk of an m x 74 column-major matrix (m: the argument, 65536 by
 * default).
 *   cc -O2 bench/syrk_callgrind.c -o build/syrk_callgrind -lopenblas
 *   OPENBLAS_NUM_THREADS=1 valgrind --tool=callgrind build/syrk_callgrind [m]
 */
#include <stdlib.h>
#include <cblas.h>
int main(int argc, char **argv) { int m = argc > 1 ? atoi(argv[1]) : 65536, N = 74; double *S = calloc((size_t)m * N, 8), *C = calloc(N * N, 8);
for (size_t i = 0; i < (size_t)m * N; i++) S[i] = (double)(i % 7) - 3.0;
cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, N, m, 1.0, S, m, 0.0, C, N); return C[3] > 1e300; }
