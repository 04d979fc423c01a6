/* tests/test_sim_raw.c - the raw records of a simulated flight
 * (igea_sim_raw): without errors and noise igea_dw_compute of the records
 * gives dW = 0 (below 1e-6 m/s); the tracking noise given comes back in dW
 * as it was given; injected instrument errors give dW = S X (envfun, the
 * linear model, computed independently of the records) to second order:
 * halving the errors quarters |dW - S X|; refusals name the argument. */
#include "testutil.h"

#include "igea/dw.h"
#include "igea/envfun.h"
#include "igea/nav.h"
#include "igea/sim.h"

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)
#define DUR 120.0
#define RATE 50.0
#define NEP 120

static double *TRAJ[2];
static int NS;
static double SITE[IGEA_NAV_SITE_LEN], EP[NEP];

static int setup(void **state)
{
    (void)state;
    if (igea_sim_trajectory_length(DUR, RATE, &NS))
        return -1;
    for (int s = 0; s < 2; s++) {
        TRAJ[s] = malloc(sizeof(double) * (size_t)NS * IGEA_ENVFUN_TRAJ_COLS);
        if (!TRAJ[s] || igea_sim_trajectory(s, DUR, RATE, NS, TRAJ[s], NS))
            return -1;
    }
    for (int e = 0; e < NEP; e++)
        EP[e] = e + 1.0;
    return igea_nav_site(40.96 * DEG, 100.29 * DEG, 1000.0, 30.0 * DEG, SITE);
}

static int teardown(void **state)
{
    (void)state;
    free(TRAJ[0]);
    free(TRAJ[1]);
    return 0;
}

/* dW of the raw records of system s with errors err (by code, may be NULL)
 * and noise (may be NULL), tracking in frame. */
static void raw_dw(int s, int frame, const double *err, const double *noise, double *dw)
{
    int cols = s == IGEA_ENVFUN_STRAPDOWN ? IGEA_SIM_RAW_TEL_STRAPDOWN : IGEA_SIM_RAW_TEL_PLATFORM;
    double *tel = malloc(sizeof(double) * (size_t)NS * 7), trk[NEP * 7], q0[4];
    double so[IGEA_NAV_SITE_LEN], cov[6 * NEP], col[3 * NEP], tk[NEP * 8];
    int bad = -1;
    assert_non_null(tel);
    assert_int_equal(igea_sim_raw(s, NS, TRAJ[s], NS, IGEA_ENVFUN_TERM_END, err, NULL, SITE,
                                  frame, NEP, EP, noise, tel, NS, trk, NEP, q0, so), 0);
    /* with a sigma column and both optional outputs (igea dw's way) */
    memcpy(tk, trk, sizeof trk);
    for (int e = 0; e < NEP; e++)
        tk[7 * NEP + e] = 0.01;
    assert_int_equal(igea_dw_compute(so, s, IGEA_DW_APPARENT, q0, 0.0, NS, tel, NS, cols,
                                     frame, NEP, tk, NEP, 8, dw, cov, col, &bad), 0);
    free(tel);
}

static double max_abs(int n, const double *x)
{
    double m = 0.0;
    for (int i = 0; i < n; i++)
        m = fmax(m, fabs(x[i]));
    return m;
}

static void test_ideal(void **state)
{
    (void)state;
    double dw[3 * NEP];
    for (int s = 0; s < 2; s++)
        for (int fr = 0; fr < 2; fr++) {
            raw_dw(s, fr == 0 ? IGEA_NAV_ECEF : IGEA_NAV_LE, NULL, NULL, dw);
            assert_true(max_abs(3 * NEP, dw) < 1e-6);
        }
}

static void test_noise(void **state)
{
    (void)state;
    double dw[3 * NEP], nz[3 * NEP];
    for (int i = 0; i < 3 * NEP; i++)
        nz[i] = 0.01 * sin(1.3 * i + 0.2); /* any values: they come back as given */
    for (int s = 0; s < 2; s++) {
        raw_dw(s, IGEA_NAV_ECEF, NULL, nz, dw);
        for (int i = 0; i < 3 * NEP; i++)
            assert_close_abs(dw[i], nz[i], 0.0, 1e-6);
    }
}

/* max |dW(err) - S X| over the rows, S from igea_envfun_compute. */
static double discrepancy(int s, const int *codes, const double *x, int n, double scale)
{
    double err[IGEA_ENVFUN_TERM_END] = {0}, dw[3 * NEP], S[3 * NEP * 8], d = 0.0;
    assert_true(n <= 8);
    for (int j = 0; j < n; j++)
        err[codes[j]] = scale * x[j];
    raw_dw(s, IGEA_NAV_ECEF, err, NULL, dw);
    assert_int_equal(igea_envfun_compute(s, NS, TRAJ[s], NS, n, codes, NULL, NEP, EP, NULL,
                                         IGEA_ENVFUN_VELOCITY, S, 3 * NEP), 0);
    for (int i = 0; i < 3 * NEP; i++) {
        double sx = 0.0;
        for (int j = 0; j < n; j++)
            sx += S[i + 3 * NEP * j] * err[codes[j]];
        d = fmax(d, fabs(dw[i] - sx));
    }
    return d;
}

/* Instrument errors at about 5 x spec: the discrepancy is second order. */
static void test_errors_second_order(void **state)
{
    (void)state;
    static const int pf[6] = {IGEA_ENVFUN_TERM_ACC_BIAS_X + 1, IGEA_ENVFUN_TERM_ACC_SCALE_X,
                              IGEA_ENVFUN_TERM_GYRO_BIAS_X + 2, IGEA_ENVFUN_TERM_GYRO_GI_X,
                              IGEA_ENVFUN_TERM_ALIGN0_X, IGEA_ENVFUN_TERM_LEVER_X + 1};
    static const double xp[6] = {5e-2, 5e-4, 1.2e-5, 1.2e-6, 5e-4, 0.5};
    static const int sd[6] = {IGEA_ENVFUN_TERM_ACC_BIAS_X, IGEA_ENVFUN_TERM_ACC_MIS_XY,
                              IGEA_ENVFUN_TERM_GYRO_BIAS_X + 1, IGEA_ENVFUN_TERM_GYRO_G_X + 2,
                              IGEA_ENVFUN_TERM_ATT0_X + 2, IGEA_ENVFUN_TERM_GYRO_SCALE_X};
    static const double xs[6] = {5e-2, 5e-4, 1.2e-5, 1.2e-6, 5e-4, 5e-4};
    for (int s = 0; s < 2; s++) {
        const int *c = s == IGEA_ENVFUN_PLATFORM ? pf : sd;
        const double *x = s == IGEA_ENVFUN_PLATFORM ? xp : xs;
        double d1 = discrepancy(s, c, x, 6, 1.0), d2 = discrepancy(s, c, x, 6, 0.5);
        print_message("system %d: |dW - SX| %.3g (X), %.3g (X/2), ratio %.3f\n", s, d1, d2,
                      d1 / d2);
        assert_true(d1 / d2 > 3.5 && d1 / d2 < 4.5);
        assert_true(d1 < 0.05);
    }
}

static void test_refusals(void **state)
{
    (void)state;
    double tel[4 * 10], trk[7], q0[4], so[IGEA_NAV_SITE_LEN], ep = 1.0, half = 0.5;
    double err[IGEA_ENVFUN_TERM_END] = {0};
    const double *T = TRAJ[1];
    int P = IGEA_ENVFUN_PLATFORM, E = IGEA_NAV_ECEF;
    assert_int_equal(igea_sim_raw(7, NS, T, NS, IGEA_ENVFUN_TERM_END, NULL, NULL, SITE, E, 1,
                                  &ep, NULL, tel, 10, trk, 1, q0, so), -1);
    assert_int_equal(igea_sim_raw(P, NS, T, NS, 3, NULL, NULL, SITE, E, 1, &ep, NULL, tel,
                                  NS, trk, 1, q0, so), -5);
    assert_int_equal(igea_sim_raw(P, NS, T, NS, IGEA_ENVFUN_TERM_END, NULL, NULL, NULL, E, 1,
                                  &ep, NULL, tel, NS, trk, 1, q0, so), -8);
    assert_int_equal(igea_sim_raw(P, NS, T, NS, IGEA_ENVFUN_TERM_END, NULL, NULL, SITE,
                                  IGEA_NAV_LI, 1, &ep, NULL, tel, NS, trk, 1, q0, so), -9);
    assert_int_equal(igea_sim_raw(P, NS, T, NS, IGEA_ENVFUN_TERM_END, NULL, NULL, SITE, E, 1,
                                  &ep, NULL, tel, 9, trk, 1, q0, so), -14);
    /* an epoch between samples; an error on a strapdown-only term */
    double *big = malloc(sizeof(double) * (size_t)NS * 4);
    assert_non_null(big);
    double ep2 = 0.011;
    assert_int_equal(igea_sim_raw(P, NS, T, NS, IGEA_ENVFUN_TERM_END, NULL, NULL, SITE, E, 1,
                                  &ep2, NULL, big, NS, trk, 1, q0, so), -11);
    err[IGEA_ENVFUN_TERM_ATT0_X] = 1e-4;
    assert_int_equal(igea_sim_raw(P, NS, T, NS, IGEA_ENVFUN_TERM_END, err, NULL, SITE, E, 1,
                                  &half, NULL, big, NS, trk, 1, q0, so), -6);
    err[IGEA_ENVFUN_TERM_ATT0_X] = NAN;
    assert_int_equal(igea_sim_raw(IGEA_ENVFUN_STRAPDOWN, NS, TRAJ[0], NS, IGEA_ENVFUN_TERM_END,
                                  err, NULL, SITE, E, 1, &half, NULL, big, NS, trk, 1, q0, so),
                     IGEA_ENONFINITE);
    free(big);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ideal),
        cmocka_unit_test(test_noise),
        cmocka_unit_test(test_errors_second_order),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
