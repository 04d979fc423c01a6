/* bench/eqerr_callgrind.c - igea_eqerr_run on an m x 74 flight for
 * instruction counts against one bare dsyrk (bench/syrk_callgrind.c):
 *
 *   cc -O2 -Iinclude bench/eqerr_callgrind.c -o build/eqerr_callgrind -Lbuild/lib -ligea \
 *      -lm -Wl,-rpath,$PWD/build/lib
 *   OPENBLAS_NUM_THREADS=1 valgrind --tool=callgrind --separate-threads=yes \
 *      --fair-sched=yes build/eqerr_callgrind 65536 2
 *
 *   callgrind_annotate --inclusive=yes callgrind.out.PID-01 | grep igea_eqerr_run
 *
 * The critical path on T >= 2 threads is igea_eqerr_run's inclusive count
 * in the calling thread's file (-01; it runs its share of the segments of
 * the normal equations and of the residual pass); the other threads'
 * files (-02 ..) hold pf_worker (mt_segment, rs_segment). The threads take
 * the segments as they come: --fair-sched=yes lets valgrind, which runs
 * one thread at a time, share them out as two cores would.
 *
 * Arguments: m rows, IGEA_EQERR_OPT_THREADS (default 1), any third
 * argument: also the verdict rule's overall size. Prints the status, chi2
 * and the CPU time of the call. docs/validation.md, "The normal equations
 * on two cores (eqerr)", quotes its counts.
 */
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include "igea.h"
#include <time.h>
int main(int argc, char **argv)
{
    int m = atoi(argv[1]), N = 74, th = argc > 2 ? atoi(argv[2]) : 1;
    double *S = malloc(sizeof(double) * m * N), *dw = malloc(sizeof(double) * m), *res = malloc(sizeof(double) * m);
    double *sg = malloc(sizeof(double) * m), spec[74];
    for (int j = 0; j < N; j++) {
        spec[j] = 1.0 + j * 0.01;
        for (int i = 0; i < m; i++) {
            double t = (i / 3) / (double)(m / 3);
            S[i + (size_t)j * m] = cos((j % 12 + 1) * t + j) * pow(t, 1 + j % 5) + 1e-3 * sin(1e3 * i + j);
        }
    }
    for (int i = 0; i < m; i++) { dw[i] = 0.01 * sin(7.0 * i); sg[i] = 0.01; }
    double opts[IGEA_EQERR_OPT_LEN], lam[74], P[74 * 74], eq[74], z[74], info[IGEA_STATS_INFO_LEN], rms[3];
    int rej[74];
    igea_eqerr_defaults(opts);
    opts[IGEA_EQERR_OPT_THREADS] = th;
    opts[IGEA_EQERR_OPT_OVERALL_SIZE] = argc > 3;
    clock_t c0 = clock();
    int st = igea_eqerr_run(m, N, S, m, dw, sg, 1, spec, opts, lam, P, N, eq, z, rej, info, res, rms);
    printf("st %d chi2 %.12g cpu %.3f s\n", st, info[IGEA_STATS_INFO_CHI2], (double)(clock() - c0) / CLOCKS_PER_SEC);
    return 0;
}
