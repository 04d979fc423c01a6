/* tests/test_accel_history.c - priors from the calibration history (REML
 * of the random-effects model) and the fit with a prior.
 * References: the balanced one-way random-effects model in closed form
 * (equal V_i = v: the REML estimate of tau^2 + v is the sample variance
 * s^2 with divisor m - 1, so tau^2 = s^2 - v when s^2 > v, beta0 the mean,
 * Cov(beta0) = s^2 / m); the single model's posterior with a diagonal prior
 * against the normal equations written here. */
#include "testutil.h"

#include "igea/accel.h"
#include "igea/stats.h"

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


/* The REML information in closed form for equal V_i (the balanced one-way
 * model): Omega_i = Sigma + V for all i, and I_ab = ((m - 1) / 2)
 * tr(Omega^-1 D_a Omega^-1 D_b) (P_R = (I - J/m) (x) Omega^-1). p = 1:
 * I = (m - 1) / (2 (tau^2 + v)^2); p = 2, full: the 3 x 3 matrix over
 * (Sigma_00, Sigma_10, Sigma_11) from the 2 x 2 inverse written here. */
static void test_information_balanced(void **state)
{
    (void)state;
    enum { M = 7 };
    double b[2 * M], V[4 * M], I1, I3[9], S1 = 1.3, v = 0.25;
    for (int i = 0; i < M; i++) {
        b[2 * i] = sin(1.1 * i), b[2 * i + 1] = cos(0.7 * i);
        V[i] = v;
    }
    assert_int_equal(igea_accel_history_information(M, 1, b, 1, V, 1, &S1, 1, 0, &I1, 1), 0);
    assert_close(I1, (M - 1) / (2.0 * (S1 + v) * (S1 + v)), 1e-12);
    const double Sg[4] = {0.5, 0.2, 0.2, 0.8}, Vb[4] = {0.1, 0.03, 0.03, 0.2};
    for (int i = 0; i < M; i++)
        for (int k = 0; k < 4; k++)
            V[4 * i + k] = Vb[k];
    assert_int_equal(igea_accel_history_information(M, 2, b, 2, V, 2, Sg, 2, 1, I3, 3), 0);
    double O[4], det, W[4];
    for (int k = 0; k < 4; k++)
        O[k] = Sg[k] + Vb[k];
    det = O[0] * O[3] - O[1] * O[2];
    W[0] = O[3] / det, W[3] = O[0] / det, W[1] = W[2] = -O[1] / det;
    /* D_0 = e0 e0', D_1 = e1 e0' + e0 e1', D_2 = e1 e1' (column-major 2 x 2) */
    const double D[3][4] = {{1, 0, 0, 0}, {0, 1, 1, 0}, {0, 0, 0, 1}};
    for (int a = 0; a < 3; a++)
        for (int c = 0; c < 3; c++) {
            double X[4], Y[4], t = 0.0; /* X = W D_a, Y = W D_c */
            for (int i = 0; i < 2; i++)
                for (int j = 0; j < 2; j++) {
                    X[i + 2 * j] = W[i] * D[a][2 * j] + W[i + 2] * D[a][1 + 2 * j];
                    Y[i + 2 * j] = W[i] * D[c][2 * j] + W[i + 2] * D[c][1 + 2 * j];
                }
            for (int i = 0; i < 2; i++)
                for (int j = 0; j < 2; j++)
                    t += X[i + 2 * j] * Y[j + 2 * i];
            assert_close(I3[a + 3 * c], 0.5 * (M - 1) * t, 1e-12);
        }
    /* refusals */
    assert_int_equal(igea_accel_history_information(1, 1, b, 1, V, 1, &S1, 1, 0, &I1, 1), -1);
    assert_int_equal(igea_accel_history_information(M, 11, b, 11, V, 11, &S1, 11, 0, &I1, 1),
                     -2);
    assert_int_equal(igea_accel_history_information(M, 2, b, 2, V, 2, Sg, 2, 2, I3, 3), -9);
    assert_int_equal(igea_accel_history_information(M, 2, b, 2, V, 2, Sg, 2, 1, I3, 2), -11);
    assert_int_equal(igea_accel_history_information(M, 2, b, 2, V, 2, Sg, 2, 1, NULL, 3), -10);
    double neg = -0.1;
    assert_int_equal(igea_accel_history_information(M, 1, b, 1, V, 1, &neg, 1, 0, &I1, 1),
                     IGEA_EDOMAIN);
}

/* A single-model history (all five coefficients data-determined) of M
 * calibrations with unequal diagonal V_i. */
#define HM 8
static void single_history(double *b, double *V, double vscale)
{
    const double mu[5] = {2e-4, 1e-4, -5e-5, 3e-5, 1e-5};
    for (int i = 0; i < HM; i++)
        for (int k = 0; k < 5; k++) {
            b[5 * i + k] = mu[k] * (1.0 + 0.3 * sin(1.3 * i + 0.7 * k));
            for (int c = 0; c < 5; c++)
                V[25 * i + k + 5 * c] = k == c ? vscale * 1e-12 * (1.0 + 0.2 * i) : 0.0;
        }
}

static void single_readings(double *th, double *ya)
{
    igea_accel_schedule(12, 5.0, th);
    for (int i = 0; i < 12; i++) {
        double s = sin(th[i] * 3.14159265358979323846 / 180.0);
        ya[i] = s + 2e-4 + 1e-4 * s * s + 1e-6 * cos(7.0 * i);
    }
}

/* The plug-in part is igea_accel_fit_prior's posterior with the prior of
 * igea_accel_history (coef, sd_plugin); the interval is coef -+ t(dof) sd. */
static void test_fit_history_plugin_and_interval(void **state)
{
    (void)state;
    double b[5 * HM], V[25 * HM], th[12], ya[12], beta0[5], tau[5], pc[25], Sg[25] = {0};
    double coef[5], sd[5], sdp[5], dof[5], ci[10], info[IGEA_ACCEL_HFIT_LEN], c2[5], s2[5];
    single_history(b, V, 1.0);
    single_readings(th, ya);
    assert_int_equal(igea_accel_history(HM, 5, b, 5, V, 5, 100000, 1e-12, beta0, tau, pc, 5,
                                        NULL), 0);
    for (int k = 0; k < 5; k++)
        Sg[k + 5 * k] = tau[k] * tau[k];
    assert_int_equal(igea_accel_fit_history(IGEA_ACCEL_SINGLE, 12, th, ya, NULL, HM, b, 5, V, 5,
                                            Sg, 5, 0, 0.05, coef, sd, sdp, dof, ci, NULL, 1,
                                            info), 0);
    assert_int_equal(igea_accel_fit_prior(IGEA_ACCEL_SINGLE, 12, th, ya, NULL, beta0, pc, 5, c2,
                                          s2, NULL, 1, NULL), 0);
    for (int j = 0; j < 5; j++) {
        double t;
        assert_close(coef[j], c2[j], 1e-9);
        assert_close(sdp[j], s2[j], 1e-9);
        assert_true(dof[j] >= 1.0 && sd[j] > 0.0);
        assert_int_equal(igea_stats_t_quantile(0.975, dof[j], &t), 0);
        assert_close(ci[j], coef[j] - t * sd[j], 1e-12);
        assert_close(ci[5 + j], coef[j] + t * sd[j], 1e-12);
    }
    assert_int_equal((int)info[IGEA_ACCEL_HFIT_NTHETA], 5);
    assert_int_equal((int)info[IGEA_ACCEL_INFO_DOF], 7);
}

/* A prior far wider than the data: the data determine every coefficient,
 * the posterior is least squares, sd = sd_plugin (nothing of the prior's
 * uncertainty reaches them) and the dof are those of the residual
 * variance, n - 5 = 7 (Var s2^2 = 2 s2^2 / 7 carried to sd^2 ~ s2). */
static void test_fit_history_weak_prior(void **state)
{
    (void)state;
    double b[5 * HM], V[25 * HM], th[12], ya[12], Sg[25] = {0};
    double coef[5], sd[5], sdp[5], dof[5];
    single_history(b, V, 1.0);
    single_readings(th, ya);
    for (int k = 0; k < 5; k++)
        Sg[k + 5 * k] = 1e-2;
    assert_int_equal(igea_accel_fit_history(IGEA_ACCEL_SINGLE, 12, th, ya, NULL, HM, b, 5, V, 5,
                                            Sg, 5, 1, 0.01, coef, sd, sdp, dof, NULL, NULL, 1,
                                            NULL), 0);
    for (int j = 0; j < 5; j++) {
        assert_close(sd[j], sdp[j], 1e-6);
        assert_close(dof[j], 7.0, 1e-4);
    }
}

static void test_fit_history_invalid(void **state)
{
    (void)state;
    double b[5 * HM], V[25 * HM], th[12], ya[12], Sg[25] = {0}, coef[5], ci[10], cov[25];
    single_history(b, V, 1.0);
    single_readings(th, ya);
    for (int k = 0; k < 5; k++)
        Sg[k + 5 * k] = 1e-10;
#define FH(model, n, t, y, yb, m, bb, ldb, VV, ldv, S, lds, full, alpha, c, ldc)                 \
    igea_accel_fit_history(model, n, t, y, yb, m, bb, ldb, VV, ldv, S, lds, full, alpha, c, NULL, \
                           NULL, NULL, ci, cov, ldc, NULL)
    assert_int_equal(FH(2, 12, th, ya, NULL, HM, b, 5, V, 5, Sg, 5, 0, 0.05, coef, 5), -1);
    assert_int_equal(FH(0, 0, th, ya, NULL, HM, b, 5, V, 5, Sg, 5, 0, 0.05, coef, 5), -2);
    assert_int_equal(FH(0, 12, NULL, ya, NULL, HM, b, 5, V, 5, Sg, 5, 0, 0.05, coef, 5), -3);
    assert_int_equal(FH(0, 12, th, NULL, NULL, HM, b, 5, V, 5, Sg, 5, 0, 0.05, coef, 5), -4);
    assert_int_equal(FH(1, 12, th, ya, NULL, HM, b, 5, V, 5, Sg, 5, 0, 0.05, coef, 5), -5);
    assert_int_equal(FH(0, 12, th, ya, NULL, 1, b, 5, V, 5, Sg, 5, 0, 0.05, coef, 5), -6);
    assert_int_equal(FH(0, 12, th, ya, NULL, HM, NULL, 5, V, 5, Sg, 5, 0, 0.05, coef, 5), -7);
    assert_int_equal(FH(0, 12, th, ya, NULL, HM, b, 4, V, 5, Sg, 5, 0, 0.05, coef, 5), -8);
    assert_int_equal(FH(0, 12, th, ya, NULL, HM, b, 5, NULL, 5, Sg, 5, 0, 0.05, coef, 5), -9);
    assert_int_equal(FH(0, 12, th, ya, NULL, HM, b, 5, V, 4, Sg, 5, 0, 0.05, coef, 5), -10);
    assert_int_equal(FH(0, 12, th, ya, NULL, HM, b, 5, V, 5, NULL, 5, 0, 0.05, coef, 5), -11);
    assert_int_equal(FH(0, 12, th, ya, NULL, HM, b, 5, V, 5, Sg, 4, 0, 0.05, coef, 5), -12);
    assert_int_equal(FH(0, 12, th, ya, NULL, HM, b, 5, V, 5, Sg, 5, 3, 0.05, coef, 5), -13);
    assert_int_equal(FH(0, 12, th, ya, NULL, HM, b, 5, V, 5, Sg, 5, 0, 1.0, coef, 5), -14);
    assert_int_equal(FH(0, 12, th, ya, NULL, HM, b, 5, V, 5, Sg, 5, 0, NAN, coef, 5), -14);
    assert_int_equal(FH(0, 12, th, ya, NULL, HM, b, 5, V, 5, Sg, 5, 0, 0.05, NULL, 5), -15);
    assert_int_equal(FH(0, 12, th, ya, NULL, HM, b, 5, V, 5, Sg, 5, 0, 0.05, coef, 4), -21);
    fill_sentinel(coef, 5);
    fill_sentinel(ci, 10);
    Sg[6] = -1e-10; /* a negative variance */
    assert_int_equal(FH(0, 12, th, ya, NULL, HM, b, 5, V, 5, Sg, 5, 0, 0.05, coef, 5),
                     IGEA_EDOMAIN);
    Sg[6] = 1e-10;
    b[3] = NAN;
    assert_int_equal(FH(0, 12, th, ya, NULL, HM, b, 5, V, 5, Sg, 5, 0, 0.05, coef, 5),
                     IGEA_ENONFINITE);
    b[3] = 1e-4;
    assert_int_equal(FH(0, 5, th, ya, NULL, HM, b, 5, V, 5, Sg, 5, 0, 0.05, coef, 5),
                     IGEA_EDOMAIN); /* n = rank: no residual */
    assert_true(all_sentinel(coef, 5) && all_sentinel(ci, 10));
#undef FH
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_history_balanced_closed_form),
        cmocka_unit_test(test_history_two_coefficients),
        cmocka_unit_test(test_history_full_balanced),
        cmocka_unit_test(test_history_invalid),
        cmocka_unit_test(test_fit_prior_single),
        cmocka_unit_test(test_information_balanced),
        cmocka_unit_test(test_fit_history_plugin_and_interval),
        cmocka_unit_test(test_fit_history_weak_prior),
        cmocka_unit_test(test_fit_history_invalid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
