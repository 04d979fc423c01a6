/* tests/test_inserr_li.c - the linearised INS error model in the
 * launch-inertial frame along a powered trajectory, against the full
 * nonlinear navigation of the nav core with the same errors (the
 * difference is second order: halving every error quarters it); the
 * covariance of gyro white noise against its closed form and of all four
 * noises against a Monte Carlo of the nonlinear navigation; the argument
 * checks. */
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "testutil.h"

#include "igea/envfun.h"
#include "igea/inserr.h"
#include "igea/nav.h"
#include "igea/sim.h"

#define NS IGEA_INSERR_N
#define DEG (3.14159265358979323846 / 180.0)
#define DUR 120.0  /* s of boost */
#define RATE 50.0  /* Hz */
#define NEP 7      /* epochs: every 20 s */

/* The reference boost (igea_sim_trajectory) as a strapdown telemetry
 * record: trapezoid increments of the sampled force and rate (the same
 * rule as igea_sim_raw), t in column 0. */
static double *boost_tel(int *nsamp, double *q0)
{
    int n;
    assert_int_equal(igea_sim_trajectory_length(DUR, RATE, &n), 0);
    double *traj = malloc(sizeof(double) * (size_t)n * 11), *tel = calloc((size_t)n * 7, sizeof(double));
    assert_int_equal(igea_sim_trajectory(IGEA_ENVFUN_STRAPDOWN, DUR, RATE, n, traj, n), 0);
    for (int k = 0; k < n; k++) {
        tel[k] = traj[k];
        if (k == 0)
            continue;
        double h = traj[k] - traj[k - 1];
        for (int c = 1; c <= 6; c++)
            tel[(size_t)c * n + k] = 0.5 * h * (traj[(size_t)c * n + k - 1] + traj[(size_t)c * n + k]);
    }
    for (int i = 0; i < 4; i++)
        q0[i] = traj[(size_t)(7 + i) * n];
    free(traj);
    *nsamp = n;
    return tel;
}

static void qmul(const double *a, const double *b, double *c)
{
    c[0] = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
    c[1] = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
    c[2] = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
    c[3] = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
}

static void qdcm(const double *q, double *C)
{
    double a = q[0], b = q[1], c = q[2], d = q[3];
    double n = a * a + b * b + c * c + d * d;
    C[0] = (a * a + b * b - c * c - d * d) / n, C[1] = 2 * (b * c - a * d) / n, C[2] = 2 * (b * d + a * c) / n;
    C[3] = 2 * (b * c + a * d) / n, C[4] = (a * a - b * b + c * c - d * d) / n, C[5] = 2 * (c * d - a * b) / n;
    C[6] = 2 * (b * d - a * c) / n, C[7] = 2 * (c * d + a * b) / n, C[8] = (a * a - b * b - c * c + d * d) / n;
}

/* The nonlinear navigation with errors e (x0 layout) minus the one
 * without, at the epochs: dr, dv (LI) and phi from C_e C^T = I - [phi x].
 * tc NULL: constant biases, b h per interval; else Gauss-Markov biases
 * b(t) = b e^(-t / T) (T = tc[0] accelerometers, tc[1] gyros), each
 * interval's increment getting the exact integral b T (e^(-t_{k-1} / T) -
 * e^(-t_k / T)). */
static void nonlinear_tc(const double *site, int n, const double *tel, const double *q0,
                         const double *e, const double *tc, const int *idx, double *d)
{
    double s0[IGEA_NAV_STATE_LEN], s1[IGEA_NAV_STATE_LEN], zero[3] = {0, 0, 0}, v0[3], r1[3], v1[3];
    double qe[4], q1[4], half = 0.0;
    for (int i = 0; i < 3; i++)
        half += e[6 + i] * e[6 + i];
    half = sqrt(half) / 2.0;
    /* q(-phi0): the rotation by -phi0 */
    double qp[4] = {cos(half), 0, 0, 0};
    for (int i = 0; i < 3; i++)
        qp[1 + i] = half > 0 ? -sin(half) * e[6 + i] / (2.0 * half) : 0.0;
    qmul(qp, q0, qe);
    assert_int_equal(igea_nav_transform(site, IGEA_NAV_LE, IGEA_NAV_LI, 0.0, zero, zero, r1, v0), 0);
    for (int i = 0; i < 3; i++)
        r1[i] = e[i], v1[i] = v0[i] + e[3 + i];
    assert_int_equal(igea_nav_init(0, site, IGEA_NAV_GRAVITY_J2, 0, 0.0, q0, NULL, NULL, s0), 0);
    assert_int_equal(igea_nav_init(0, site, IGEA_NAV_GRAVITY_J2, 0, 0.0, qe, r1, v1, s1), 0);
    for (int k = 0, j = 0; k < n && j < NEP; k++) {
        if (k > 0) {
            double dv[3], dth[3], dve[3], dthe[3], h = tel[k] - tel[k - 1];
            for (int i = 0; i < 3; i++) {
                dv[i] = tel[(size_t)(1 + i) * n + k], dth[i] = tel[(size_t)(4 + i) * n + k];
                double ia = h, ig = h;
                if (tc) {
                    ia = tc[0] * (exp(-tel[k - 1] / tc[0]) - exp(-tel[k] / tc[0]));
                    ig = tc[1] * (exp(-tel[k - 1] / tc[1]) - exp(-tel[k] / tc[1]));
                }
                dve[i] = dv[i] + e[9 + i] * ia, dthe[i] = dth[i] + e[12 + i] * ig;
            }
            assert_int_equal(igea_nav_step(s0, tel[k], dv, dth), 0);
            assert_int_equal(igea_nav_step(s1, tel[k], dve, dthe), 0);
        }
        if (idx[j] != k)
            continue;
        double C0[9], C1[9], M[9], *dj = d + (size_t)j * 9;
        for (int i = 0; i < 3; i++) {
            dj[i] = s1[IGEA_NAV_STATE_R + i] - s0[IGEA_NAV_STATE_R + i];
            dj[3 + i] = s1[IGEA_NAV_STATE_V + i] - s0[IGEA_NAV_STATE_V + i];
        }
        memcpy(q1, s1 + IGEA_NAV_STATE_Q, sizeof q1);
        qdcm(s0 + IGEA_NAV_STATE_Q, C0);
        qdcm(q1, C1);
        for (int a = 0; a < 3; a++) /* M = C1 C0^T */
            for (int b = 0; b < 3; b++)
                M[a * 3 + b] = C1[a * 3] * C0[b * 3] + C1[a * 3 + 1] * C0[b * 3 + 1] +
                               C1[a * 3 + 2] * C0[b * 3 + 2];
        dj[6] = (M[5] - M[7]) / 2.0, dj[7] = (M[6] - M[2]) / 2.0, dj[8] = (M[1] - M[3]) / 2.0;
        j++;
    }
}

static void nonlinear(const double *site, int n, const double *tel, const double *q0,
                      const double *e, const int *idx, double *d)
{
    nonlinear_tc(site, n, tel, q0, e, NULL, idx, d);
}

/* The largest |nonlinear - linear| of each block (position, velocity,
 * attitude) over the epochs, and the largest |linear| of each. */
static void discrepancy(const double *site, int n, const double *tel, const double *q0,
                        const double *e, const double *ep, const int *idx, double *dmax,
                        double *lmax)
{
    double x[NEP * NS], d[NEP * 9];
    assert_int_equal(igea_inserr_li_response(0, site, IGEA_NAV_GRAVITY_J2, n, tel, n, q0, NULL,
                                             NULL, e, NEP, ep, x), 0);
    nonlinear(site, n, tel, q0, e, idx, d);
    for (int b = 0; b < 3; b++)
        dmax[b] = lmax[b] = 0.0;
    for (int j = 0; j < NEP; j++)
        for (int i = 0; i < 9; i++) {
            dmax[i / 3] = fmax(dmax[i / 3], fabs(d[j * 9 + i] - x[j * NS + i]));
            lmax[i / 3] = fmax(lmax[i / 3], fabs(x[j * NS + i]));
        }
}

static void test_nonlinear_second_order(void **s)
{
    (void)s;
    int n;
    double q0[4], site[IGEA_NAV_SITE_LEN], ep[NEP], d1[3], d2[3], l1[3], l2[3];
    double *tel = boost_tel(&n, q0);
    int idx[NEP];
    assert_int_equal(igea_nav_site(40.0 * DEG, 100.0 * DEG, 1000.0, 60.0 * DEG, site), 0);
    for (int j = 0; j < NEP; j++)
        ep[j] = j * DUR / (NEP - 1), idx[j] = (int)(ep[j] * RATE + 0.5);
    /* 5 m, 0.1 m/s, 0.2 mrad initial errors; ~200 ug biases; ~3 deg/h drifts */
    double e[NS] = {5.0, -3.0, 2.0, 0.1, -0.05, 0.08, 1e-4, -2e-4, 1.5e-4,
                    2e-3, -1e-3, 1.5e-3, 1e-5, -2e-5, 1.5e-5}, h[NS];
    for (int i = 0; i < NS; i++)
        h[i] = e[i] / 2.0;
    discrepancy(site, n, tel, q0, e, ep, idx, d1, l1);
    discrepancy(site, n, tel, q0, h, ep, idx, d2, l2);
    for (int b = 0; b < 3; b++) {
        /* the linear response is linear: halving the errors halves it */
        assert_close(l2[b], l1[b] / 2.0, 1e-12);
        /* the model captures the response to better than 1 % ... */
        assert_true(d1[b] < 1e-2 * l1[b]);
        /* ... and what it misses is second order: the ratio is 4 */
        double ratio = d1[b] / d2[b];
        assert_true(ratio > 3.8 && ratio < 4.2);
    }
    free(tel);
}

/* Gyro white noise of density q on every body axis: phi' = -C w with C a
 * rotation and the noise isotropic gives P_phi(t) = q t I whatever the
 * trajectory; a random constant x accelerometer bias of variance s2 gives
 * P_b = s2 and the covariance of the response columns. */
static void test_gyro_white_noise(void **s)
{
    (void)s;
    int n;
    double q0[4], site[IGEA_NAV_SITE_LEN], ep[NEP], qn[IGEA_INSERR_NQ] = {0};
    double *tel = boost_tel(&n, q0), *P = malloc(sizeof(double) * NEP * NS * NS);
    assert_int_equal(igea_nav_site(40.0 * DEG, 100.0 * DEG, 1000.0, 60.0 * DEG, site), 0);
    for (int j = 0; j < NEP; j++)
        ep[j] = j * DUR / (NEP - 1);
    const double qg = 1e-12;
    qn[3] = qn[4] = qn[5] = qg;
    assert_int_equal(igea_inserr_li_covariance(0, site, IGEA_NAV_GRAVITY_J2, n, tel, n, q0, NULL,
                                               NULL, NULL, qn, NEP, ep, P), 0);
    for (int j = 0; j < NEP; j++) {
        const double *Pj = P + (size_t)j * NS * NS;
        for (int a = 6; a < 9; a++)
            for (int b = 6; b < 9; b++)
                assert_close_abs(Pj[a * NS + b], a == b ? qg * ep[j] : 0.0, 1e-9, 1e-9 * qg * DUR);
    }
    free(P);
    free(tel);
}

/* One noisy nonlinear navigation along the record (the reference s0 run
 * alongside) to the last sample: the noises of q sampled exactly over each
 * interval h: white noise integrates to N(0, q h); a random-walk bias
 * b(t) = b_{k-1} + W(t) integrates to b_{k-1} h + I with (I, dW) jointly
 * normal, var dW = K h, var I = K h^3 / 3, cov = K h^2 / 2, i.e.
 * I = (h / 2) dW + sqrt(K h^3 / 12) z. Writes dr, dv, phi at the end. */
static void noisy_run(const double *site, int n, const double *tel, const double *q0,
                      const double *qn, gsl_rng *rng, double *d)
{
    double s0[IGEA_NAV_STATE_LEN], s1[IGEA_NAV_STATE_LEN], ba[3] = {0}, bg[3] = {0};
    assert_int_equal(igea_nav_init(0, site, IGEA_NAV_GRAVITY_J2, 0, 0.0, q0, NULL, NULL, s0), 0);
    memcpy(s1, s0, sizeof s1);
    for (int k = 1; k < n; k++) {
        double dv[3], dth[3], dve[3], dthe[3], h = tel[k] - tel[k - 1];
        for (int i = 0; i < 3; i++) {
            dv[i] = tel[(size_t)(1 + i) * n + k], dth[i] = tel[(size_t)(4 + i) * n + k];
            double wa = sqrt(qn[6 + i] * h) * gsl_ran_ugaussian(rng);
            double wg = sqrt(qn[9 + i] * h) * gsl_ran_ugaussian(rng);
            double ia = 0.5 * h * wa + sqrt(qn[6 + i] * h * h * h / 12.0) * gsl_ran_ugaussian(rng);
            double ig = 0.5 * h * wg + sqrt(qn[9 + i] * h * h * h / 12.0) * gsl_ran_ugaussian(rng);
            dve[i] = dv[i] + sqrt(qn[i] * h) * gsl_ran_ugaussian(rng) + ba[i] * h + ia;
            dthe[i] = dth[i] + sqrt(qn[3 + i] * h) * gsl_ran_ugaussian(rng) + bg[i] * h + ig;
            ba[i] += wa, bg[i] += wg;
        }
        assert_int_equal(igea_nav_step(s0, tel[k], dv, dth), 0);
        assert_int_equal(igea_nav_step(s1, tel[k], dve, dthe), 0);
    }
    double C0[9], C1[9], M[9];
    for (int i = 0; i < 3; i++) {
        d[i] = s1[IGEA_NAV_STATE_R + i] - s0[IGEA_NAV_STATE_R + i];
        d[3 + i] = s1[IGEA_NAV_STATE_V + i] - s0[IGEA_NAV_STATE_V + i];
    }
    qdcm(s0 + IGEA_NAV_STATE_Q, C0);
    qdcm(s1 + IGEA_NAV_STATE_Q, C1);
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            M[a * 3 + b] = C1[a * 3] * C0[b * 3] + C1[a * 3 + 1] * C0[b * 3 + 1] +
                           C1[a * 3 + 2] * C0[b * 3 + 2];
    d[6] = (M[5] - M[7]) / 2.0, d[7] = (M[6] - M[2]) / 2.0, d[8] = (M[1] - M[3]) / 2.0;
}

/* The covariance of accelerometer and gyro white noise and of both bias
 * random walks (different densities per axis) against MC runs of the
 * nonlinear navigation over 60 s of the boost: each of the 9 variances of
 * position, velocity and attitude at the end, estimated with the known
 * mean 0 as s2 = sum d^2 / MC, satisfies MC s2 / sigma^2 ~ chi^2(MC); the
 * two-sided 1e-4 interval by the Wilson-Hilferty approximation,
 * (1 - 2 / (9 MC) -+ z sqrt(2 / (9 MC)))^3, z = 3.8906 (for MC = 1000:
 * 0.835 .. 1.184). Seed 18 of gsl's mt19937. Rerun larger with -DMC=N. */
#ifndef MC
#define MC 1000
#endif
static void test_noise_montecarlo(void **s)
{
    (void)s;
    int n, nr;
    double q0[4], site[IGEA_NAV_SITE_LEN], ep[1] = {60.0}, P[NS * NS];
    double *tel = boost_tel(&n, q0);
    nr = (int)(60.0 * RATE) + 1; /* the first 60 s: the leading rows of the record */
    double *t2 = malloc(sizeof(double) * (size_t)nr * 7);
    for (int c = 0; c < 7; c++)
        memcpy(t2 + (size_t)c * nr, tel + (size_t)c * n, sizeof(double) * (size_t)nr);
    assert_int_equal(igea_nav_site(40.0 * DEG, 100.0 * DEG, 1000.0, 60.0 * DEG, site), 0);
    /* VRW 1e-3 m/s/sqrt(s); ARW 1e-5 rad/sqrt(s); K 1e-5 m/s^2/sqrt(s), 1e-7 rad/s/sqrt(s) */
    const double qn[IGEA_INSERR_NQ] = {1e-6, 2e-6, 0.5e-6, 1e-10, 0.5e-10, 2e-10,
                                       1e-10, 2e-10, 1e-10, 1e-14, 1e-14, 2e-14};
    assert_int_equal(igea_inserr_li_covariance(0, site, IGEA_NAV_GRAVITY_J2, nr, t2, nr, q0,
                                               NULL, NULL, NULL, qn, 1, ep, P), 0);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 18);
    double ss[9] = {0}, d[9];
    for (int m = 0; m < MC; m++) {
        noisy_run(site, nr, t2, q0, qn, rng, d);
        for (int i = 0; i < 9; i++)
            ss[i] += d[i] * d[i];
    }
    const double z = 3.8906, c = 2.0 / (9.0 * MC);
    const double lo = pow(1.0 - c - z * sqrt(c), 3), hi = pow(1.0 - c + z * sqrt(c), 3);
    for (int i = 0; i < 9; i++) {
        double ratio = ss[i] / MC / P[i * NS + i];
        if (getenv("IGEA_TEST_VERBOSE"))
            fprintf(stderr, "component %d: MC variance / covariance %.4f (%.3f .. %.3f)\n", i,
                    ratio, lo, hi);
        assert_true(ratio > lo && ratio < hi);
    }
    gsl_rng_free(rng);
    free(t2);
    free(tel);
}

static void test_invalid(void **s)
{
    (void)s;
    int n;
    double q0[4], site[IGEA_NAV_SITE_LEN], ep[2] = {0.0, 1.0}, x0[NS] = {0}, x[2 * NS];
    double qn[IGEA_INSERR_NQ] = {0}, P[2 * NS * NS], P0[NS * NS] = {0};
    double *tel = boost_tel(&n, q0);
    assert_int_equal(igea_nav_site(0.5, 1.0, 0.0, 0.2, site), 0);
    fill_sentinel(x, 2 * NS);
    assert_int_equal(igea_inserr_li_response(2, site, 1, n, tel, n, q0, NULL, NULL, x0, 2, ep, x), -1);
    assert_int_equal(igea_inserr_li_response(0, NULL, 1, n, tel, n, q0, NULL, NULL, x0, 2, ep, x), -2);
    assert_int_equal(igea_inserr_li_response(0, site, 5, n, tel, n, q0, NULL, NULL, x0, 2, ep, x), -3);
    assert_int_equal(igea_inserr_li_response(0, site, 1, 1, tel, n, q0, NULL, NULL, x0, 2, ep, x), -4);
    assert_int_equal(igea_inserr_li_response(0, site, 1, n, NULL, n, q0, NULL, NULL, x0, 2, ep, x), -5);
    assert_int_equal(igea_inserr_li_response(0, site, 1, n, tel, n - 1, q0, NULL, NULL, x0, 2, ep, x), -6);
    assert_int_equal(igea_inserr_li_response(0, site, 1, n, tel, n, q0, NULL, NULL, NULL, 2, ep, x), -10);
    assert_int_equal(igea_inserr_li_response(0, site, 1, n, tel, n, q0, NULL, NULL, x0, 0, ep, x), -11);
    ep[1] = 1.01; /* not a sample time */
    assert_int_equal(igea_inserr_li_response(0, site, 1, n, tel, n, q0, NULL, NULL, x0, 2, ep, x), -12);
    ep[1] = DUR + 1.0; /* after the record */
    assert_int_equal(igea_inserr_li_response(0, site, 1, n, tel, n, q0, NULL, NULL, x0, 2, ep, x), -12);
    ep[1] = 1.0;
    assert_int_equal(igea_inserr_li_response(0, site, 1, n, tel, n, q0, NULL, NULL, x0, 2, ep, NULL), -13);
    tel[n + 5] = NAN;
    assert_int_equal(igea_inserr_li_response(0, site, 1, n, tel, n, q0, NULL, NULL, x0, 2, ep, x), IGEA_ENONFINITE);
    tel[n + 5] = 0.0;
    double t5 = tel[5];
    tel[5] = tel[4]; /* times not increasing */
    assert_int_equal(igea_inserr_li_response(0, site, 1, n, tel, n, q0, NULL, NULL, x0, 2, ep, x), -5);
    tel[5] = t5;
    x0[3] = INFINITY;
    assert_int_equal(igea_inserr_li_response(0, site, 1, n, tel, n, q0, NULL, NULL, x0, 2, ep, x), IGEA_ENONFINITE);
    x0[3] = 0.0;
    assert_true(all_sentinel(x, 2 * NS));
    fill_sentinel(P, 2 * NS * NS);
    assert_int_equal(igea_inserr_li_covariance(0, site, 1, n, tel, n, q0, NULL, NULL, NULL, NULL, 2, ep, P), -11);
    assert_int_equal(igea_inserr_li_covariance(0, site, 1, n, tel, n, q0, NULL, NULL, NULL, qn, 2, ep, NULL), -14);
    qn[7] = -1.0;
    assert_int_equal(igea_inserr_li_covariance(0, site, 1, n, tel, n, q0, NULL, NULL, NULL, qn, 2, ep, P), IGEA_ENONPOSITIVE);
    qn[7] = 0.0;
    P0[1] = 1.0;
    assert_int_equal(igea_inserr_li_covariance(0, site, 1, n, tel, n, q0, NULL, NULL, P0, qn, 2, ep, P), IGEA_EDOMAIN);
    assert_true(all_sentinel(P, 2 * NS * NS));
    P0[1] = 0.0;
    assert_int_equal(igea_inserr_li_covariance(0, site, 1, n, tel, n, q0, NULL, NULL, P0, qn, 2, ep, P), 0);
    free(tel);
}

/* ---- Gauss-Markov bias states --------------------------------------------- */

/* igea_inserr_li_response_opts with correlation times 40 s (accelerometers)
 * and 25 s (gyros) against the nonlinear navigation with decaying biases:
 * below 1 % of the response, second order (halving the errors quarters the
 * mismatch); the bias states are b0 e^(-t / T) to the Runge-Kutta
 * truncation (1e-10 relative). */
static void test_gm_response_second_order(void **s)
{
    (void)s;
    int n, idx[NEP];
    double q0[4], site[IGEA_NAV_SITE_LEN], ep[NEP], opts[IGEA_INSERR_OPT_LEN];
    double *tel = boost_tel(&n, q0);
    assert_int_equal(igea_nav_site(40.0 * DEG, 100.0 * DEG, 1000.0, 60.0 * DEG, site), 0);
    assert_int_equal(igea_inserr_defaults(opts), 0);
    opts[IGEA_INSERR_OPT_ACC_TC] = 40.0;
    opts[IGEA_INSERR_OPT_GYRO_TC] = 25.0;
    const double tc[2] = {40.0, 25.0};
    for (int j = 0; j < NEP; j++)
        ep[j] = j * DUR / (NEP - 1), idx[j] = (int)(ep[j] * RATE + 0.5);
    double e[NS] = {5.0, -3.0, 2.0, 0.1, -0.05, 0.08, 1e-4, -2e-4, 1.5e-4,
                    4e-3, -2e-3, 3e-3, 3e-5, -4e-5, 3e-5};
    double dmax[2][3], lmax[2][3];
    for (int pass = 0; pass < 2; pass++) {
        double x[NEP * NS], d[NEP * 9], es[NS];
        for (int i = 0; i < NS; i++)
            es[i] = pass ? e[i] / 2.0 : e[i];
        assert_int_equal(igea_inserr_li_response_opts(0, site, IGEA_NAV_GRAVITY_J2, opts, n, tel,
                                                      n, q0, NULL, NULL, es, NEP, ep, x), 0);
        nonlinear_tc(site, n, tel, q0, es, tc, idx, d);
        for (int b = 0; b < 3; b++)
            dmax[pass][b] = lmax[pass][b] = 0.0;
        for (int j = 0; j < NEP; j++) {
            for (int i = 0; i < 9; i++) {
                dmax[pass][i / 3] = fmax(dmax[pass][i / 3], fabs(d[j * 9 + i] - x[j * NS + i]));
                lmax[pass][i / 3] = fmax(lmax[pass][i / 3], fabs(x[j * NS + i]));
            }
            for (int i = 9; i < 15; i++)
                assert_close(x[j * NS + i], es[i] * exp(-ep[j] / tc[(i - 9) / 3]), 1e-10);
        }
    }
    for (int b = 0; b < 3; b++) {
        double ratio = dmax[0][b] / dmax[1][b];
        if (getenv("IGEA_TEST_VERBOSE"))
            fprintf(stderr, "block %d: response %.4g, mismatch %.4g, halved %.4g, ratio %.4f\n",
                    b, lmax[0][b], dmax[0][b], dmax[1][b], ratio);
        assert_true(dmax[0][b] < 1e-2 * lmax[0][b]);
        assert_true(ratio > 3.8 && ratio < 4.2);
    }
    free(tel);
}

/* Closed forms of the bias block: a Gauss-Markov state from P0 = 0 driven
 * by q has variance q T / 2 (1 - e^(-2 t / T)); the noise of an Allan fit
 * has s^2 + K^2 t, s = 1.07600 B (stationary from the start); with B = 0
 * the noise covariance is igea_inserr_li_covariance's with q = N^2, K^2
 * bit for bit, and with every correlation time 0 the _opts functions are
 * the plain ones. */
static void test_gm_covariance_closed_forms(void **s)
{
    (void)s;
    int n;
    double q0[4], site[IGEA_NAV_SITE_LEN], ep[NEP], opts[IGEA_INSERR_OPT_LEN];
    double *tel = boost_tel(&n, q0);
    double *P = malloc(sizeof(double) * NEP * NS * NS), *P2 = malloc(sizeof(double) * NEP * NS * NS);
    assert_int_equal(igea_nav_site(40.0 * DEG, 100.0 * DEG, 1000.0, 60.0 * DEG, site), 0);
    assert_int_equal(igea_inserr_defaults(opts), 0);
    for (int j = 0; j < NEP; j++)
        ep[j] = j * DUR / (NEP - 1);
    /* the plain functions are the _opts ones with both times 0 */
    const double qn[IGEA_INSERR_NQ] = {1e-6, 2e-6, 0.5e-6, 1e-10, 0.5e-10, 2e-10,
                                       1e-10, 2e-10, 1e-10, 1e-14, 1e-14, 2e-14};
    double x0[NS] = {1, 2, 3, 0.1, 0.2, 0.3, 1e-4, 2e-4, 3e-4, 1e-3, 2e-3, 3e-3, 1e-5, 2e-5, 3e-5};
    double x1[NEP * NS], x2[NEP * NS];
    assert_int_equal(igea_inserr_li_response(0, site, 1, n, tel, n, q0, NULL, NULL, x0, NEP, ep, x1), 0);
    assert_int_equal(igea_inserr_li_response_opts(0, site, 1, opts, n, tel, n, q0, NULL, NULL, x0, NEP, ep, x2), 0);
    assert_memory_equal(x1, x2, sizeof x1);
    assert_int_equal(igea_inserr_li_covariance(0, site, 1, n, tel, n, q0, NULL, NULL, NULL, qn, NEP, ep, P), 0);
    assert_int_equal(igea_inserr_li_covariance_opts(0, site, 1, opts, n, tel, n, q0, NULL, NULL, NULL, qn, NEP, ep, P2), 0);
    assert_memory_equal(P, P2, sizeof(double) * NEP * NS * NS);
    /* N and K only: the noise covariance is the covariance of q = N^2, K^2 */
    double acc[IGEA_INSERR_NOISE_LEN] = {0}, gyro[IGEA_INSERR_NOISE_LEN] = {0};
    for (int i = 0; i < 3; i++) {
        acc[IGEA_INSERR_NOISE_N + i] = sqrt(qn[i]), gyro[IGEA_INSERR_NOISE_N + i] = sqrt(qn[3 + i]);
        acc[IGEA_INSERR_NOISE_K + i] = sqrt(qn[6 + i]), gyro[IGEA_INSERR_NOISE_K + i] = sqrt(qn[9 + i]);
    }
    double qs[IGEA_INSERR_NQ];
    for (int i = 0; i < 3; i++) {
        qs[i] = acc[i] * acc[i], qs[3 + i] = gyro[i] * gyro[i];
        qs[6 + i] = acc[6 + i] * acc[6 + i], qs[9 + i] = gyro[6 + i] * gyro[6 + i];
    }
    assert_int_equal(igea_inserr_li_covariance(0, site, 1, n, tel, n, q0, NULL, NULL, NULL, qs, NEP, ep, P), 0);
    assert_int_equal(igea_inserr_li_noise_covariance(0, site, 1, opts, n, tel, n, q0, NULL, NULL, NULL, acc, gyro, NEP, ep, P2), 0);
    assert_memory_equal(P, P2, sizeof(double) * NEP * NS * NS);
    /* a Gauss-Markov state from 0 */
    opts[IGEA_INSERR_OPT_ACC_TC] = 30.0;
    opts[IGEA_INSERR_OPT_GYRO_TC] = 70.0;
    double qg[IGEA_INSERR_NQ] = {0};
    qg[7] = 4e-9, qg[11] = 3e-15;
    assert_int_equal(igea_inserr_li_covariance_opts(0, site, 1, opts, n, tel, n, q0, NULL, NULL, NULL, qg, NEP, ep, P), 0);
    for (int j = 0; j < NEP; j++) {
        const double *Pj = P + (size_t)j * NS * NS;
        assert_close(Pj[10 * NS + 10], 4e-9 * 30.0 / 2.0 * (1.0 - exp(-2.0 * ep[j] / 30.0)), 1e-9);
        assert_close(Pj[14 * NS + 14], 3e-15 * 70.0 / 2.0 * (1.0 - exp(-2.0 * ep[j] / 70.0)), 1e-9);
        assert_true(Pj[9 * NS + 9] == 0.0 && (j == 0 || Pj[0] > 0.0));
    }
    /* bias instability: stationary s^2, plus K^2 t */
    acc[IGEA_INSERR_NOISE_B + 1] = 5e-5, gyro[IGEA_INSERR_NOISE_B + 2] = 2e-7;
    assert_int_equal(igea_inserr_li_noise_covariance(0, site, 1, opts, n, tel, n, q0, NULL, NULL, NULL, acc, gyro, NEP, ep, P), 0);
    /* s = 1.07600 B (docs/inserr.md; tests/python/test_inserr_noise.py
     * recomputes the Allan peak): s^2 to 1e-5 */
    const double sa = 1.07600 * 5e-5, sg = 1.07600 * 2e-7;
    for (int j = 0; j < NEP; j++) {
        const double *Pj = P + (size_t)j * NS * NS;
        assert_close(Pj[10 * NS + 10], sa * sa + qn[7] * ep[j], 1e-5);
        assert_close(Pj[14 * NS + 14], sg * sg + qn[11] * ep[j], 1e-5);
        assert_close(Pj[9 * NS + 9], qn[6] * ep[j], 1e-12);
    }
    /* a B > 0 without its correlation time */
    opts[IGEA_INSERR_OPT_GYRO_TC] = 0.0;
    fill_sentinel(P, NEP * NS * NS);
    assert_int_equal(igea_inserr_li_noise_covariance(0, site, 1, opts, n, tel, n, q0, NULL, NULL, NULL, acc, gyro, NEP, ep, P), IGEA_EDOMAIN);
    assert_true(all_sentinel(P, NEP * NS * NS));
    /* arguments: opts at 4, the others one further */
    opts[IGEA_INSERR_OPT_GYRO_TC] = 0.5; /* not 0 nor in [1, 1e9] */
    assert_int_equal(igea_inserr_li_response_opts(0, site, 1, opts, n, tel, n, q0, NULL, NULL, x0, NEP, ep, x2), -4);
    opts[IGEA_INSERR_OPT_GYRO_TC] = 70.0;
    assert_int_equal(igea_inserr_li_response_opts(0, site, 1, opts, 1, tel, n, q0, NULL, NULL, x0, NEP, ep, x2), -5);
    assert_int_equal(igea_inserr_li_response_opts(0, site, 1, opts, n, tel, n - 1, q0, NULL, NULL, x0, NEP, ep, x2), -7);
    assert_int_equal(igea_inserr_li_response_opts(0, site, 1, opts, n, tel, n, q0, NULL, NULL, NULL, NEP, ep, x2), -11);
    assert_int_equal(igea_inserr_li_covariance_opts(0, site, 1, opts, n, tel, n, q0, NULL, NULL, NULL, NULL, NEP, ep, P), -12);
    assert_int_equal(igea_inserr_li_noise_covariance(0, site, 1, opts, n, tel, n, q0, NULL, NULL, NULL, acc, NULL, NEP, ep, P), -13);
    assert_int_equal(igea_inserr_li_noise_covariance(0, site, 1, opts, n, tel, n, q0, NULL, NULL, NULL, acc, gyro, 0, ep, P), -14);
    ep[1] = 1.01;
    assert_int_equal(igea_inserr_li_noise_covariance(0, site, 1, opts, n, tel, n, q0, NULL, NULL, NULL, acc, gyro, NEP, ep, P), -15);
    free(P);
    free(P2);
    free(tel);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nonlinear_second_order),
        cmocka_unit_test(test_gyro_white_noise),
        cmocka_unit_test(test_noise_montecarlo),
        cmocka_unit_test(test_invalid),
        cmocka_unit_test(test_gm_response_second_order),
        cmocka_unit_test(test_gm_covariance_closed_forms),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
