/* bench/mc_callgrind.c - a small driver of igea_sim_montecarlo for
 * instruction counts (callgrind counts reproducibly on a loaded machine):
 *
 *   cc -O2 -Iinclude bench/mc_callgrind.c -o build/mc_callgrind -Lbuild/lib -ligea -lm \
 *      -Wl,-rpath,$PWD/build/lib
 *   OPENBLAS_NUM_THREADS=1 valgrind --tool=callgrind --separate-threads=yes \
 *      build/mc_callgrind 120 21 4000 2 2
 *
 * Arguments: M epochs, N terms, flights, generator (0 mt19937, 2 xoshiro),
 * threads (default 1), chunk (default all: the flights in calls of chunk
 * flights on one model, as the driver and igea.montecarlo run them). A
 * graded S (column scale 10^-1 .. 10, fixed LCG), stated sigma 0.01,
 * sigma_w 1.2, the batched path (automatic block).
 * docs/validation.md, "Keyed streams: generator xoshiro", quotes its counts.
 */
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include "igea.h"
int main(int argc, char **argv)
{
    int M = atoi(argv[1]), N = atoi(argv[2]), F = atoi(argv[3]), gen = atoi(argv[4]);
    int th = argc > 5 ? atoi(argv[5]) : 1, chunk = argc > 6 ? atoi(argv[6]) : F;
    int m = 3 * M;
    double *S = malloc(sizeof(double) * m * N);
    unsigned s = 1;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < m; i++) {
            s = s * 1103515245u + 12345u;
            S[i + j * m] = ((s >> 8) / 16777216.0 - 0.5) * pow(10.0, -1 + 2.0 * j / (N - 1)) * 0.1;
        }
    igea_sim_model *h;
    igea_sim_model_create(m, N, S, m, &h);
    double sg = 0.01, opts[IGEA_SIM_OPT_LEN], counts[IGEA_SIM_MC_LEN];
    igea_sim_model_set_sigma(h, &sg, 0, 0.0);
    igea_sim_defaults(opts);
    opts[IGEA_SIM_OPT_SIGMA_W] = 1.2;
    opts[IGEA_SIM_OPT_GENERATOR] = gen;
    igea_sim_model_set_noise(h, opts);
    double failed = 0;
    int st = 0;
    for (int f0 = 0; st == 0 && f0 < F; f0 += chunk) {
        int n = F - f0 < chunk ? F - f0 : chunk;
        st = igea_sim_montecarlo(h, NULL, 1, f0, n, th, counts, NULL, NULL, NULL, NULL, 0);
        failed += counts[IGEA_SIM_MC_FAILED];
    }
    printf("st %d failed %g\n", st, failed / F);
    return 0;
}
