/* The equivalent-error test from C: METHODS 1.6(a)'s 4-epoch example.
 * Build against an installed igea:
 *   cc eqerr_example.c $(pkg-config --cflags --libs igea) -lm -o eqerr_example
 * Static (libigea.a and its dependencies' static libraries):
 *   cc -static eqerr_example.c $(pkg-config --static --cflags --libs igea) -o eqerr_example
 * Prints eigenvalues, equivalent errors and the verdict; exits 0 when
 * accepted, 3 when T is not METHODS 1.6(a)'s value, 2 on an error. */
#include <math.h>
#include <stdio.h>

#include <igea.h>

int main(void)
{
    enum { M = 12, N = 4 };
    double S[M * N], dw[M], sigma = 0.05;            /* column-major S */
    const double X[N] = {0.5, -1.0, 0.8, 0.3};
    for (int k = 0; k < 4; k++) {
        double t = k + 1;
        double rows[3][N] = {{t, 0.5 * t * t, 0, 0.1 * t},
                             {0, 0.2 * t, t, 0.1 * t + 0.01 * t * t},
                             {0.3 * t, 0, 0.1 * t * t, 0.1 * t}};
        for (int a = 0; a < 3; a++)
            for (int j = 0; j < N; j++)
                S[3 * k + a + j * M] = rows[a][j];
    }
    for (int i = 0; i < M; i++) {
        dw[i] = 0.05 * cos(1.7 * i);
        for (int j = 0; j < N; j++)
            dw[i] += S[i + j * M] * X[j];
    }
    double opts[IGEA_EQERR_OPT_LEN], lambda[N], P[N * N], xhat[N], z[N], info[IGEA_STATS_INFO_LEN];
    int reject[N];
    igea_eqerr_defaults(opts);
    opts[IGEA_EQERR_OPT_CORRECTION] = 0; /* 12 rows: too few small eigenvalues */
    int st = igea_eqerr_run(M, N, S, M, dw, &sigma, 0, NULL, opts, lambda, P, N, xhat, z,
                            reject, info, NULL, NULL);
    if (st != 0) {
        fprintf(stderr, "igea_eqerr_run: %s (%d)\n", igea_strerror(st), st);
        return 2;
    }
    for (int i = 0; i < N; i++)
        printf("lambda %.10e  Xhat % .10f  %s\n", lambda[i], xhat[i],
               reject[i] < 0 ? "not tested" : reject[i] ? "REJECT" : "pass");
    printf("T = %.10f with %d dof, critical %.3f: %s\n", info[IGEA_STATS_INFO_CHI2],
           (int)info[IGEA_STATS_INFO_DOF], info[IGEA_STATS_INFO_CHI2_CRIT],
           info[IGEA_STATS_INFO_PASSED] == 1.0 ? "accepted" : "rejected");
    /* METHODS 1.6(a): T = 2.0372728049 */
    return fabs(info[IGEA_STATS_INFO_CHI2] - 2.0372728049) < 1e-9 ? 0 : 3;
}
