/* tests/test_inserr.c - the linearised INS error model against closed
 * forms of the Schuler loop (Earth rate 0, stationary vehicle): the
 * response to a north accelerometer bias and an east gyro drift over 6 h,
 * the covariance of accelerometer white noise and of a random constant
 * bias; the argument checks. */
#include "testutil.h"

#include "igea/inserr.h"

#define NS IGEA_INSERR_N
#define PI 3.14159265358979323846
#define T6H 21600.0
#define NE 361 /* epochs: every minute over 6 h */

static void schuler_opts(double *o)
{
    igea_inserr_defaults(o);
    o[IGEA_INSERR_OPT_OMEGA] = 0.0;
    o[IGEA_INSERR_OPT_LAT] = 0.7;
}

static double ws_of(const double *o)
{
    return sqrt(o[IGEA_INSERR_OPT_G] / o[IGEA_INSERR_OPT_RADIUS]);
}

static void test_schuler_period(void **s)
{
    (void)s;
    double o[IGEA_INSERR_OPT_LEN];
    igea_inserr_defaults(o);
    /* 2 pi sqrt(R / g) with R = 6371008.8 m, g = 9.80665 m/s^2: 84.4 min */
    assert_close(2.0 * PI / ws_of(o) / 60.0, 84.4, 1e-3);
}

/* A north accelerometer bias b: dv_N' = g phi_E + b, phi_E' = -dv_N / R
 * give dN(t) = (b / g) R (1 - cos ws t), dv_N = (b / ws) sin ws t,
 * phi_E = -(b / g)(1 - cos ws t). */
static void test_north_acc_bias(void **s)
{
    (void)s;
    double o[IGEA_INSERR_OPT_LEN], x0[NS] = {0}, *x = malloc(sizeof(double) * NE * NS);
    schuler_opts(o);
    const double b = 1e-4, R = o[IGEA_INSERR_OPT_RADIUS], g = o[IGEA_INSERR_OPT_G];
    const double ws = ws_of(o), amp = 2.0 * b * R / g;
    x0[IGEA_INSERR_ACC] = b;
    assert_int_equal(igea_inserr_response(o, x0, T6H, NE, x), 0);
    for (int k = 0; k < NE; k++) {
        double t = k * T6H / (NE - 1), *xk = x + k * NS;
        assert_close_abs(xk[0], b / g * R * (1.0 - cos(ws * t)), 1e-6, 1e-6 * amp);
        assert_close_abs(xk[3], b / ws * sin(ws * t), 1e-6, 1e-6 * b / ws);
        assert_close_abs(xk[7], -b / g * (1.0 - cos(ws * t)), 1e-6, 1e-6 * 2.0 * b / g);
        assert_true(xk[1] == 0.0 && xk[4] == 0.0 && xk[2] == 0.0);
        assert_close(xk[IGEA_INSERR_ACC], b, 0.0);
    }
    free(x);
}

/* An east gyro drift eps (the gyro reads eps too high about east):
 * phi_E' = -dv_N / R - eps gives dN(t) = -R eps (t - sin(ws t) / ws),
 * the textbook R eps (t - sin(ws t) / ws) with the opposite sign because
 * the computed frame turns by -eps t about east (a positive east rotation
 * tips the north axis up). */
static void test_east_gyro_drift(void **s)
{
    (void)s;
    double o[IGEA_INSERR_OPT_LEN], x0[NS] = {0}, *x = malloc(sizeof(double) * NE * NS);
    schuler_opts(o);
    const double eps = 1e-7, R = o[IGEA_INSERR_OPT_RADIUS], ws = ws_of(o);
    x0[IGEA_INSERR_GYRO + 1] = eps;
    assert_int_equal(igea_inserr_response(o, x0, T6H, NE, x), 0);
    double scale = R * eps * T6H;
    for (int k = 0; k < NE; k++) {
        double t = k * T6H / (NE - 1), *xk = x + k * NS;
        double want = -R * eps * (t - sin(ws * t) / ws);
        assert_close_abs(xk[0], want, 1e-6, 1e-9 * scale);
        assert_close_abs(xk[3], -R * eps * (1.0 - cos(ws * t)), 1e-6, 1e-6 * R * eps);
    }
    free(x);
}

/* North accelerometer white noise of density q: the impulse response of
 * dv_N is cos ws (t - s), of dN sin ws (t - s) / ws, so
 * var dv_N = q (t / 2 + sin(2 ws t) / (4 ws)),
 * var dN = q / ws^2 (t / 2 - sin(2 ws t) / (4 ws)),
 * cov(dN, dv_N) = q sin^2(ws t) / (2 ws^2).
 * A random constant north bias of variance
 * s2 (P0) adds s2 ((R / g)(1 - cos ws t))^2 to var dN. */
static void test_white_noise_covariance(void **s)
{
    (void)s;
    double o[IGEA_INSERR_OPT_LEN], q[IGEA_INSERR_NQ] = {0}, P0[NS * NS] = {0};
    double *P = malloc(sizeof(double) * NE * NS * NS);
    schuler_opts(o);
    const double qa = 2.5e-9, s2 = 1e-8, R = o[IGEA_INSERR_OPT_RADIUS];
    const double g = o[IGEA_INSERR_OPT_G], ws = ws_of(o);
    q[0] = qa;
    P0[IGEA_INSERR_ACC * NS + IGEA_INSERR_ACC] = s2;
    assert_int_equal(igea_inserr_covariance(o, P0, q, T6H, NE, P), 0);
    for (int k = 1; k < NE; k++) {
        double t = k * T6H / (NE - 1), *Pk = P + (size_t)k * NS * NS;
        double c = R / g * (1.0 - cos(ws * t));
        double vN = qa / (ws * ws) * (t / 2.0 - sin(2.0 * ws * t) / (4.0 * ws)) + s2 * c * c;
        double vV = qa * (t / 2.0 + sin(2.0 * ws * t) / (4.0 * ws)) +
                    s2 * pow(sin(ws * t) / ws, 2);
        double cNV = qa * pow(sin(ws * t), 2) / (2.0 * ws * ws) +
                     s2 * c * sin(ws * t) / ws;
        assert_close_abs(Pk[0], vN, 1e-6, 1e-9 * qa * T6H / (ws * ws));
        assert_close_abs(Pk[3 * NS + 3], vV, 1e-6, 1e-9 * qa * T6H);
        assert_close_abs(Pk[3], cNV, 1e-6, 1e-9 * qa * T6H / ws);
        assert_true(Pk[3] == Pk[3 * NS]);
        assert_true(Pk[NS + 1] == 0.0); /* nothing drives the east channel */
    }
    free(P);
}

static void test_invalid(void **s)
{
    (void)s;
    double o[IGEA_INSERR_OPT_LEN], x0[NS] = {0}, x[2 * NS], q[IGEA_INSERR_NQ] = {0};
    double P0[NS * NS] = {0}, P[2 * NS * NS], F[NS * NS];
    igea_inserr_defaults(o);
    assert_int_equal(igea_inserr_defaults(NULL), -1);
    assert_int_equal(igea_inserr_check_opts(NULL), -1);
    assert_int_equal(igea_inserr_check_opts(o), 0);
    o[IGEA_INSERR_OPT_LAT] = 1.6;
    assert_int_equal(igea_inserr_check_opts(o), 1 + IGEA_INSERR_OPT_LAT);
    assert_int_equal(igea_inserr_matrix(o, F), -1);
    o[IGEA_INSERR_OPT_LAT] = 0.0;
    o[IGEA_INSERR_OPT_VERTICAL] = 0.5;
    assert_int_equal(igea_inserr_check_opts(o), 1 + IGEA_INSERR_OPT_VERTICAL);
    o[IGEA_INSERR_OPT_VERTICAL] = 0.0;
    o[12] = NAN;
    assert_int_equal(igea_inserr_check_opts(o), 13);
    o[12] = 0.0;
    fill_sentinel(x, 2 * NS);
    assert_int_equal(igea_inserr_response(o, NULL, 10.0, 2, x), -2);
    assert_int_equal(igea_inserr_response(o, x0, 0.0, 2, x), -3);
    assert_int_equal(igea_inserr_response(o, x0, 1e8, 2, x), -3); /* > 1e7 steps */
    assert_int_equal(igea_inserr_response(o, x0, 10.0, 1, x), -4);
    assert_int_equal(igea_inserr_response(o, x0, 10.0, 2, NULL), -5);
    x0[4] = INFINITY;
    assert_int_equal(igea_inserr_response(o, x0, 10.0, 2, x), IGEA_ENONFINITE);
    x0[4] = 0.0;
    assert_true(all_sentinel(x, 2 * NS));
    fill_sentinel(P, 2 * NS * NS);
    assert_int_equal(igea_inserr_covariance(o, NULL, NULL, 10.0, 2, P), -3);
    assert_int_equal(igea_inserr_covariance(o, NULL, q, 10.0, 2, NULL), -6);
    q[3] = -1.0;
    assert_int_equal(igea_inserr_covariance(o, NULL, q, 10.0, 2, P), IGEA_ENONPOSITIVE);
    q[3] = 0.0;
    P0[1] = 1.0;
    assert_int_equal(igea_inserr_covariance(o, P0, q, 10.0, 2, P), IGEA_EDOMAIN);
    P0[NS] = 1.0, P0[0] = -1.0;
    assert_int_equal(igea_inserr_covariance(o, P0, q, 10.0, 2, P), IGEA_ENONPOSITIVE);
    assert_true(all_sentinel(P, 2 * NS * NS));
    /* a free vertical channel diverges as exp(t sqrt(2 g / R)): over 1e6 s
     * it overflows, and the status says so */
    double *big = malloc(sizeof(double) * 11 * NS);
    o[IGEA_INSERR_OPT_VERTICAL] = 1.0;
    o[IGEA_INSERR_OPT_STEP] = 10.0;
    x0[2] = 1.0;
    fill_sentinel(big, 11 * NS);
    assert_int_equal(igea_inserr_response(o, x0, 1e6, 11, big), IGEA_EOVERFLOW);
    assert_true(all_sentinel(big, 11 * NS));
    free(big);
}

/* The vertical channel, free: dD'' = (2 g / R) dD from dD(0) = d gives
 * dD = d cosh(t sqrt(2 g / R)) (Earth rate 0, no other error). */
static void test_vertical_free(void **s)
{
    (void)s;
    double o[IGEA_INSERR_OPT_LEN], x0[NS] = {0}, x[11 * NS];
    schuler_opts(o);
    o[IGEA_INSERR_OPT_VERTICAL] = 1.0;
    x0[2] = 1.0;
    const double k = sqrt(2.0 * o[IGEA_INSERR_OPT_G] / o[IGEA_INSERR_OPT_RADIUS]);
    assert_int_equal(igea_inserr_response(o, x0, 3600.0, 11, x), 0);
    for (int j = 0; j < 11; j++)
        assert_close(x[j * NS + 2], cosh(k * 360.0 * j), 1e-6);
    o[IGEA_INSERR_OPT_VERTICAL] = 0.0; /* aided: held */
    assert_int_equal(igea_inserr_response(o, x0, 3600.0, 11, x), 0);
    assert_true(x[10 * NS + 2] == 1.0 && x[10 * NS + 5] == 0.0);
}

/* IEEE 952 coefficients: white noise N alone equals igea_inserr_covariance
 * with q = N^2 (the closed form of test_white_noise_covariance covers
 * that); a stationary Gauss-Markov bias of an east gyro, B > 0 with T:
 * var eps_E stays s^2 = (1.07600 B)^2 (sqrt(2 ln 2 / pi) / 0.6173643,
 * tabulated from the maximisation in docs/inserr.md); the refusals. */
static void test_noise_covariance(void **s)
{
    (void)s;
    double o[IGEA_INSERR_OPT_LEN], acc[IGEA_INSERR_NOISE_LEN] = {0};
    double gyro[IGEA_INSERR_NOISE_LEN] = {0}, P[3 * NS * NS], Q[3 * NS * NS];
    double q[IGEA_INSERR_NQ] = {0};
    schuler_opts(o);
    acc[IGEA_INSERR_NOISE_N] = 1e-4;
    q[0] = 1e-8;
    assert_int_equal(igea_inserr_noise_covariance(o, NULL, acc, gyro, 600.0, 3, P), 0);
    assert_int_equal(igea_inserr_covariance(o, NULL, q, 600.0, 3, Q), 0);
    for (int i = 0; i < 3 * NS * NS; i++)
        assert_close_abs(P[i], Q[i], 1e-12, 1e-300);
    gyro[IGEA_INSERR_NOISE_B + 1] = 1e-7;
    fill_sentinel(P, 3 * NS * NS);
    assert_int_equal(igea_inserr_noise_covariance(o, NULL, acc, gyro, 600.0, 3, P), IGEA_EDOMAIN);
    assert_true(all_sentinel(P, 3 * NS * NS));
    o[IGEA_INSERR_OPT_GYRO_TC] = 0.5;
    assert_int_equal(igea_inserr_check_opts(o), 1 + IGEA_INSERR_OPT_GYRO_TC);
    o[IGEA_INSERR_OPT_GYRO_TC] = 300.0;
    assert_int_equal(igea_inserr_noise_covariance(o, NULL, acc, gyro, 600.0, 3, P), 0);
    const double sd = 1.07600 * 1e-7;
    for (int k = 0; k < 3; k++)
        assert_close(P[k * NS * NS + 13 * NS + 13], sd * sd, 1e-4);
    assert_int_equal(igea_inserr_noise_covariance(NULL, NULL, acc, gyro, 600.0, 3, P), -1);
    assert_int_equal(igea_inserr_noise_covariance(o, NULL, NULL, gyro, 600.0, 3, P), -3);
    assert_int_equal(igea_inserr_noise_covariance(o, NULL, acc, NULL, 600.0, 3, P), -4);
    assert_int_equal(igea_inserr_noise_covariance(o, NULL, acc, gyro, 0.0, 3, P), -5);
    assert_int_equal(igea_inserr_noise_covariance(o, NULL, acc, gyro, 600.0, 1, P), -6);
    assert_int_equal(igea_inserr_noise_covariance(o, NULL, acc, gyro, 600.0, 3, NULL), -7);
    acc[7] = -1.0;
    assert_int_equal(igea_inserr_noise_covariance(o, NULL, acc, gyro, 600.0, 3, Q), IGEA_ENONPOSITIVE);
    acc[7] = NAN;
    assert_int_equal(igea_inserr_noise_covariance(o, NULL, acc, gyro, 600.0, 3, Q), IGEA_ENONFINITE);
}

/* A north accelerometer bias that decays, Gauss-Markov of correlation
 * time T = 2 s, integrated with the user's longest step of 10 s (five
 * times T): b = b0 e^(-t/T); v' = g phi + b, phi' = -v / R give v'' +
 * ws^2 v = b', v(0) = 0, v'(0) = b0: v = A (e^(-t/T) - cos ws t) + D sin
 * ws t, A = -b0 T / (1 + ws^2 T^2), D = (b0 + A / T) / ws. The step is cut
 * to T / 4 (RK4 diverges beyond 2.79 T: 1e46 m after 200 s). */
static void test_gauss_markov_long_step(void **s)
{
    (void)s;
    enum { NG = 31 };
    double o[IGEA_INSERR_OPT_LEN], x0[NS] = {0}, x[NG * NS];
    schuler_opts(o);
    const double b0 = 1e-4, T = 2.0, ws = ws_of(o), dur = 600.0;
    const double A = -b0 * T / (1.0 + ws * ws * T * T), D = (b0 + A / T) / ws;
    o[IGEA_INSERR_OPT_ACC_TC] = T;
    o[IGEA_INSERR_OPT_STEP] = 10.0;
    x0[IGEA_INSERR_ACC] = b0;
    assert_int_equal(igea_inserr_response(o, x0, dur, NG, x), 0);
    for (int k = 0; k < NG; k++) {
        double t = k * dur / (NG - 1), *xk = x + k * NS;
        assert_close_abs(xk[IGEA_INSERR_ACC], b0 * exp(-t / T), 1e-4, 1e-6 * b0);
        assert_close_abs(xk[3], A * (exp(-t / T) - cos(ws * t)) + D * sin(ws * t), 1e-4,
                         1e-6 * b0 * T);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_schuler_period),  cmocka_unit_test(test_north_acc_bias),
        cmocka_unit_test(test_east_gyro_drift), cmocka_unit_test(test_white_noise_covariance),
        cmocka_unit_test(test_invalid),         cmocka_unit_test(test_vertical_free),
        cmocka_unit_test(test_noise_covariance), cmocka_unit_test(test_gauss_markov_long_step),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
