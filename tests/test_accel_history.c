/* tests/test_accel_history.c - priors from the calibration history (REML
 * of the random-effects model) and the fit with a prior.
 * References: the balanced one-way random-effects model in closed form
 * (equal V_i = v: the REML estimate of tau^2 + v is the sample variance
 * s^2 with divisor m - 1, so tau^2 = s^2 - v when s^2 > v, beta0 the mean,
 * Cov(beta0) = s^2 / m); the single model's posterior with a diagonal prior
 * against the normal equations written here. */
#include "testutil.h"

#include "igea/accel.h"

static void test_history_balanced_closed_form(void **state)
{
    (void)state;
    const double b[6] = {1.0, 3.0, -2.0, 4.5, 0.5, 2.0};
    const double v = 0.25;
    double V[6], beta0, tau, pc, info[IGEA_ACCEL_HIST_LEN];
    double mean = 0.0, ss = 0.0;
    for (int i = 0; i < 6; i++) {
        V[i] = v;
        mean += b[i] / 6.0;
    }
    for (int i = 0; i < 6; i++)
        ss += (b[i] - mean) * (b[i] - mean);
    double s2 = ss / 5.0;
    assert_int_equal(igea_accel_history(6, 1, b, 1, V, 1, 100000, 1e-12, &beta0, &tau, &pc, 1,
                                        info), 0);
    assert_close(beta0, mean, 1e-12);
    assert_close(tau * tau, s2 - v, 1e-8);
    assert_close(pc, s2 - v + s2 / 6.0, 1e-8);
    assert_true(info[IGEA_ACCEL_HIST_ITER] >= 1);
}

/* Two coefficients with a correlated V_i: the diagonal blocks decouple only
 * when V_i is diagonal; here check the diagonal case per coordinate against
 * the closed form, with different v per coordinate. */
static void test_history_two_coefficients(void **state)
{
    (void)state;
    enum { M = 8 };
    double b[2 * M], V[4 * M], beta0[2], tau[2], pc[4];
    double mean[2] = {0, 0}, ss[2] = {0, 0};
    const double v[2] = {0.01, 4.0};
    for (int i = 0; i < M; i++) {
        b[2 * i] = 1.0 + 0.3 * sin(1.7 * i);
        b[2 * i + 1] = -5.0 + 6.0 * cos(2.3 * i);
        V[4 * i] = v[0], V[4 * i + 1] = V[4 * i + 2] = 0.0, V[4 * i + 3] = v[1];
        mean[0] += b[2 * i] / M, mean[1] += b[2 * i + 1] / M;
    }
    for (int i = 0; i < M; i++)
        for (int k = 0; k < 2; k++)
            ss[k] += (b[2 * i + k] - mean[k]) * (b[2 * i + k] - mean[k]);
    assert_int_equal(igea_accel_history(M, 2, b, 2, V, 2, 100000, 1e-12, beta0, tau, pc, 2,
                                        NULL), 0);
    for (int k = 0; k < 2; k++) {
        assert_close(beta0[k], mean[k], 1e-10);
        assert_close(tau[k] * tau[k], ss[k] / (M - 1) - v[k], 1e-7);
    }
    assert_close_abs(pc[1], 0.0, 0, 1e-12);
}

/* Full Sigma, balanced: with equal V_i = V the REML estimate of Sigma + V
 * is the sample covariance S (divisor m - 1), Sigma = S - V when that is
 * positive semi-definite. */
static void test_history_full_balanced(void **state)
{
    (void)state;
    enum { M = 9 };
    double b[2 * M], V[4 * M], beta0[2], Sg[4], pc[4], info[IGEA_ACCEL_HIST_LEN];
    const double v[4] = {0.02, 0.005, 0.005, 0.03};
    double mean[2] = {0, 0}, S[4] = {0, 0, 0, 0};
    for (int i = 0; i < M; i++) {
        double z1 = sin(1.3 * i + 0.2), z2 = cos(2.1 * i);
        b[2 * i] = 1.0 + z1, b[2 * i + 1] = -1.0 + 0.8 * z1 + 0.6 * z2;
        for (int k = 0; k < 4; k++)
            V[4 * i + k] = v[k];
        mean[0] += b[2 * i] / M, mean[1] += b[2 * i + 1] / M;
    }
    for (int i = 0; i < M; i++)
        for (int k = 0; k < 2; k++)
            for (int c = 0; c < 2; c++)
                S[k + 2 * c] += (b[2 * i + k] - mean[k]) * (b[2 * i + c] - mean[c]) / (M - 1);
    assert_int_equal(igea_accel_history_full(M, 2, b, 2, V, 2, 200000, 1e-13, beta0, Sg, 2, pc,
                                             2, info), 0);
    for (int k = 0; k < 4; k++)
        assert_close(Sg[k], S[k] - v[k], 1e-6);
    assert_close(beta0[0], mean[0], 1e-10);
    assert_close(pc[1], S[1] - v[1] + S[1] / M, 1e-6);
    assert_int_equal(igea_accel_history_full(M, 2, b, 2, V, 2, 10, 1e-8, beta0, Sg, 1, pc, 2,
                                             info), -11);
    assert_int_equal(igea_accel_history_full(M, 2, b, 2, V, 2, 10, 1e-8, beta0, Sg, 2, pc, 1,
                                             info), -13);
    assert_int_equal(igea_accel_history_full(M, 2, b, 2, V, 2, 10, 1e-8, beta0, NULL, 2, pc, 2,
                                             info), -10);
}

static void test_history_invalid(void **state)
{
    (void)state;
    double b[4] = {1, 2, 3, 4}, V[4] = {1, 1, 1, 1}, beta0 = SENTINEL, tau = SENTINEL, pc;
    assert_int_equal(igea_accel_history(1, 1, b, 1, V, 1, 10, 1e-8, &beta0, &tau, NULL, 1,
                                        NULL), -1);
    assert_int_equal(igea_accel_history(4, 0, b, 1, V, 1, 10, 1e-8, &beta0, &tau, NULL, 1,
                                        NULL), -2);
    assert_int_equal(igea_accel_history(4, 11, b, 11, V, 11, 10, 1e-8, &beta0, &tau, NULL, 1,
                                        NULL), -2);
    assert_int_equal(igea_accel_history(4, 1, NULL, 1, V, 1, 10, 1e-8, &beta0, &tau, NULL, 1,
                                        NULL), -3);
    assert_int_equal(igea_accel_history(4, 1, b, 0, V, 1, 10, 1e-8, &beta0, &tau, NULL, 1,
                                        NULL), -4);
    assert_int_equal(igea_accel_history(4, 1, b, 1, NULL, 1, 10, 1e-8, &beta0, &tau, NULL, 1,
                                        NULL), -5);
    assert_int_equal(igea_accel_history(4, 1, b, 1, V, 0, 10, 1e-8, &beta0, &tau, NULL, 1,
                                        NULL), -6);
    assert_int_equal(igea_accel_history(4, 1, b, 1, V, 1, 0, 1e-8, &beta0, &tau, NULL, 1,
                                        NULL), -7);
    assert_int_equal(igea_accel_history(4, 1, b, 1, V, 1, 10, 0.0, &beta0, &tau, NULL, 1,
                                        NULL), -8);
    assert_int_equal(igea_accel_history(4, 1, b, 1, V, 1, 10, NAN, &beta0, &tau, NULL, 1,
                                        NULL), -8);
    assert_int_equal(igea_accel_history(4, 1, b, 1, V, 1, 10, 1e-8, NULL, &tau, NULL, 1,
                                        NULL), -9);
    assert_int_equal(igea_accel_history(4, 1, b, 1, V, 1, 10, 1e-8, &beta0, NULL, NULL, 1,
                                        NULL), -10);
    assert_int_equal(igea_accel_history(4, 1, b, 1, V, 1, 10, 1e-8, &beta0, &tau, &pc, 0,
                                        NULL), -12);
    b[2] = NAN;
    assert_int_equal(igea_accel_history(4, 1, b, 1, V, 1, 10, 1e-8, &beta0, &tau, NULL, 1,
                                        NULL), IGEA_ENONFINITE);
    b[2] = 3.0;
    V[1] = -2.0; /* not positive definite even with tau */
    assert_int_equal(igea_accel_history(4, 1, b, 1, V, 1, 10, 1e-8, &beta0, &tau, NULL, 1,
                                        NULL), IGEA_ESINGULAR);
    V[1] = 0.1, V[2] = 3.0; /* unbalanced: the start is not the fixed point */
    assert_int_equal(igea_accel_history(4, 1, b, 1, V, 1, 1, 1e-15, &beta0, &tau, NULL, 1,
                                        NULL), IGEA_ENOCONV);
    assert_true(beta0 == SENTINEL && tau == SENTINEL);
}

/* The single model with a diagonal prior: the posterior mean solves
 * (A^T A / s^2 + P^-1) x = A^T y / s^2 + P^-1 mu, s^2 the LS residual
 * variance; the normal equations are solved here by Gaussian elimination. */
static void test_fit_prior_single(void **state)
{
    (void)state;
    enum { N = 12, P = 5 };
    double th[N], ya[N], A[N * P], y[N], mu[P] = {1e-4, 2e-4, -1e-4, 3e-5, 0.0};
    double Pc[P * P] = {0}, coef[P], sd[P], info[IGEA_ACCEL_INFO_LEN];
    igea_accel_schedule(N, 5.0, th);
    for (int i = 0; i < N; i++) {
        double s = sin(th[i] * 3.14159265358979323846 / 180.0);
        ya[i] = s + 2e-4 + 1e-4 * s * s + 1e-6 * cos(7.0 * i);
    }
    for (int j = 0; j < P; j++)
        Pc[j + j * P] = 1e-10 * (j + 1);
    assert_int_equal(igea_accel_fit_prior(IGEA_ACCEL_SINGLE, N, th, ya, NULL, mu, Pc, P, coef, sd,
                                          NULL, 1, info), 0);
    igea_accel_design(IGEA_ACCEL_SINGLE, N, th, A, N);
    igea_accel_observe(IGEA_ACCEL_SINGLE, N, th, ya, NULL, y);
    double s2 = info[IGEA_ACCEL_INFO_SIGMA] * info[IGEA_ACCEL_INFO_SIGMA];
    double M[P][P + 1];
    for (int a = 0; a < P; a++) {
        for (int c = 0; c < P; c++) {
            double t = 0.0;
            for (int i = 0; i < N; i++)
                t += A[i + a * N] * A[i + c * N];
            M[a][c] = t / s2 + (a == c ? 1.0 / Pc[a + a * P] : 0.0);
        }
        double r = 0.0;
        for (int i = 0; i < N; i++)
            r += A[i + a * N] * y[i];
        M[a][P] = r / s2 + mu[a] / Pc[a + a * P];
    }
    for (int k = 0; k < P; k++) /* elimination without pivoting: M is SPD */
        for (int a = k + 1; a < P; a++) {
            double f = M[a][k] / M[k][k];
            for (int c = k; c <= P; c++)
                M[a][c] -= f * M[k][c];
        }
    double x[P];
    for (int a = P - 1; a >= 0; a--) {
        double t = M[a][P];
        for (int c = a + 1; c < P; c++)
            t -= M[a][c] * x[c];
        x[a] = t / M[a][a];
    }
    for (int j = 0; j < P; j++)
        assert_close_abs(coef[j], x[j], 1e-8, 1e-16);
    assert_int_equal((int)info[IGEA_ACCEL_INFO_RANK], P);
    /* refusals */
    assert_int_equal(igea_accel_fit_prior(3, N, th, ya, NULL, mu, Pc, P, coef, sd, NULL, 1,
                                          NULL), -1);
    assert_int_equal(igea_accel_fit_prior(IGEA_ACCEL_DUAL, N, th, ya, NULL, mu, Pc, 9, coef, sd,
                                          NULL, 1, NULL), -5);
    assert_int_equal(igea_accel_fit_prior(IGEA_ACCEL_SINGLE, N, th, ya, NULL, mu, Pc, 4, coef,
                                          sd, NULL, 1, NULL), -8);
    Pc[0] = -1.0;
    fill_sentinel(coef, P);
    assert_int_equal(igea_accel_fit_prior(IGEA_ACCEL_SINGLE, N, th, ya, NULL, mu, Pc, P, coef,
                                          sd, NULL, 1, NULL), IGEA_ESINGULAR);
    assert_true(all_sentinel(coef, P));
    Pc[0] = 1e-10;
    assert_int_equal(igea_accel_fit_prior(IGEA_ACCEL_SINGLE, 5, th, ya, NULL, mu, Pc, P, coef,
                                          sd, NULL, 1, NULL), IGEA_EDOMAIN);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_history_balanced_closed_form),
        cmocka_unit_test(test_history_two_coefficients),
        cmocka_unit_test(test_history_full_balanced),
        cmocka_unit_test(test_history_invalid),
        cmocka_unit_test(test_fit_prior_single),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
