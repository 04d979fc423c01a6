/* Recursive estimation from C: METHODS 2.9's three-epoch test vector with
 * polynomial RLS of order p = 1, 2, 3, then an outlier isolated.
 * Build against an installed igea:
 *   cc rls_example.c $(pkg-config --cflags --libs igea) -o rls_example
 * Prints x_3, Q_p and diag(Gamma_3); exits 0 when they match METHODS 2.9. */
#include <math.h>
#include <stdio.h>

#include <igea.h>

int main(void)
{
    const double X[3] = {1, -2, 0.5};
    const double c[3][6] = {{1, 0, 0, 1, 0.5, 1}, /* c_n, 2 x 3 column-major */
                            {1, 0.5, 1, 0, 0, 1},
                            {2, 0, 0, 1, 1, -1}};
    const double want_x1[3] = {0.9698200160, 1.0015784781, 1.0031741050};
    const double gamma0[9] = {10, 0, 0, 0, 10, 0, 0, 0, 10};
    int bad = 0;
    for (int p = 1; p <= 3; p++) {
        igea_rls *h;
        int st = igea_rls_create(3, 2, NULL, gamma0, 3, &h);
        if (st == 0)
            st = igea_rls_set_variant(h, IGEA_RLS_POLYNOMIAL, p);
        if (st != 0) {
            fprintf(stderr, "rls: %s\n", igea_strerror(st));
            return 2;
        }
        for (int n = 0; n < 3; n++) {
            double y[2];
            for (int j = 0; j < 2; j++)
                y[j] = c[n][j] * X[0] + c[n][j + 2] * X[1] + c[n][j + 4] * X[2];
            if (n == 1) {
                y[0] += 0.01;
                y[1] -= 0.02;
            }
            st = igea_rls_update(h, c[n], 2, y, NULL, NULL);
            if (st < 0) {
                fprintf(stderr, "rls: epoch %d: %s\n", n + 1, igea_strerror(st));
                return 2;
            }
        }
        double x[3], g[9], q;
        igea_rls_get_x(h, x);
        igea_rls_get_gamma(h, g, 3);
        igea_rls_get_q(h, &q);
        printf("p=%d: x3 = [%.10f %.10f %.10f]  Q_p = %.10f  diag(Gamma_3) = [%.10f %.10f %.10f]\n",
               p, x[0], x[1], x[2], q, g[0], g[4], g[8]);
        if (fabs(x[0] - want_x1[p - 1]) > 6e-11)
            bad = 1;
        igea_rls_free(h);
    }

    /* An outlier in row 2 of a fourth epoch is isolated: flags and action. */
    igea_rls *h;
    igea_rls_create(3, 2, NULL, gamma0, 3, &h);
    igea_rls_set_anomaly(h, IGEA_RLS_ANOMALY_ISOLATE, 4.0, NULL);
    const double sigma[2] = {0.01, 0.01};
    for (int n = 0; n < 4; n++) {
        const double *cn = c[n % 3];
        double y[2];
        for (int j = 0; j < 2; j++)
            y[j] = cn[j] * X[0] + cn[j + 2] * X[1] + cn[j + 4] * X[2];
        if (n == 3)
            y[1] += 1.0; /* 100 sigma */
        int flags[2];
        int act = igea_rls_update(h, cn, 2, y, sigma, flags);
        printf("epoch %d: action %d, flags %d %d\n", n + 1, act, flags[0], flags[1]);
        if (n == 3 && (act != IGEA_RLS_ISOLATED || !(flags[1] & IGEA_RLS_FLAG_INNOVATION)))
            bad = 1;
    }
    igea_rls_free(h);
    return bad;
}
