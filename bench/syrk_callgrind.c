/* bench/syrk_callgrind.c - the floor of bench/eqerr_callgrind.c: one
 * cblas_dsyrk of a 65536 x 74 column-major matrix.
 *   cc -O2 bench/syrk_callgrind.c -o build/syrk_callgrind -lopenblas
 *   OPENBLAS_NUM_THREADS=1 valgrind --tool=callgrind build/syrk_callgrind
 */
#include <stdlib.h>
#include <cblas.h>
int main(void) { int m = 65536, N = 74; double *S = calloc((size_t)m * N, 8), *C = calloc(N * N, 8);
for (size_t i = 0; i < (size_t)m * N; i++) S[i] = (double)(i % 7) - 3.0;
cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, N, m, 1.0, S, m, 0.0, C, N); return C[3] > 1e300; }
