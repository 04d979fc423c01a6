/* Tests of igea/stats.h and igea/common.h.
 * Reference values: scipy.stats 1.x (chi2.isf/ppf/sf/cdf, norm.ppf/cdf),
 * computed independently of GSL; the seed's Tables 1-2 (Xiao & Chen 2018). */
#include <float.h>

#include "testutil.h"

#include <gsl/gsl_errno.h>

#include "igea.h"

/* Counts calls of GSL's error handler: the library must never reach it. */
static int gsl_handler_calls;
static void counting_handler(const char *reason, const char *file, int line, int err)
{
    (void)reason, (void)file, (void)line, (void)err;
    gsl_handler_calls++;
}

static void test_version_and_strerror(void **state)
{
    assert_int_equal(igea_version_number(), IGEA_VERSION_NUMBER);
    assert_string_equal(igea_version(), IGEA_VERSION_STRING);
    int codes[] = {IGEA_OK, -3, IGEA_ENOMEM, IGEA_ENONFINITE, IGEA_ENONPOSITIVE,
                   IGEA_ESINGULAR, IGEA_ERANK, IGEA_ENOCONV, IGEA_ELAPACK, IGEA_EDOMAIN,
                   IGEA_ENOTESTABLE, IGEA_EDEPENDENT, IGEA_EEMPTY, 7, -5000};
    for (size_t i = 0; i < sizeof codes / sizeof codes[0]; i++) {
        const char *s = igea_strerror(codes[i]);
        assert_non_null(s);
        assert_true(strlen(s) > 5);
    }
    /* every named code has its own text */
    for (int a = -1020; a <= -1010; a++)
        for (int b = a + 1; b <= -1010; b++)
            assert_string_not_equal(igea_strerror(a), igea_strerror(b));
}

static void test_normal(void **state)
{
    double z, p;
    assert_int_equal(igea_stats_normal_quantile(0.995, &z), 0);
    assert_close(z, 2.5758293035489004, 1e-15);
    assert_int_equal(igea_stats_normal_cdf(-1.5, &p), 0);
    assert_close(p, 0.06680720126885807, 1e-14);
    assert_int_equal(igea_stats_normal_cdf(INFINITY, &p), 0);
    assert_true(p == 1.0);
    z = SENTINEL;
    assert_int_equal(igea_stats_normal_quantile(0.0, &z), -1);
    assert_int_equal(igea_stats_normal_quantile(1.0, &z), -1);
    assert_int_equal(igea_stats_normal_quantile(NAN, &z), -1);
    assert_int_equal(igea_stats_normal_quantile(1.5, &z), -1);
    assert_true(z == SENTINEL);
    assert_int_equal(igea_stats_normal_quantile(0.5, NULL), -2);
    assert_int_equal(igea_stats_normal_cdf(NAN, &p), -1);
    assert_int_equal(igea_stats_normal_cdf(0.0, NULL), -2);
}

static void test_chi2_values(void **state)
{
    double x;
    assert_int_equal(igea_stats_chi2_upper(0.01, 11, &x), 0);
    assert_close(x, 24.72497031131828, 1e-13); /* the seed's 24.725 */
    assert_int_equal(igea_stats_chi2_quantile(0.5, 1, &x), 0);
    assert_close(x, 0.454936423119572, 1e-13);
    assert_int_equal(igea_stats_chi2_quantile(1e-10, 10000, &x), 0);
    assert_close(x, 9126.511802423256, 1e-12);
    assert_int_equal(igea_stats_chi2_upper(0.01, 1e5, &x), 0);
    assert_close(x, 101043.31473677837, 1e-12);
    assert_int_equal(igea_stats_chi2_upper(1e-12, 3, &x), 0);
    assert_close(x, 58.919755683202155, 1e-12);
    assert_int_equal(igea_stats_chi2_quantile(1e-300, 2, &x), 0);
    assert_close(x, 2e-300, 1e-12);
    assert_int_equal(igea_stats_chi2_quantile(0.99, 0.01, &x), 0);
    assert_close(x, 0.16361202464505492, 1e-11);
    assert_int_equal(igea_stats_chi2_quantile(0.3, 0.01, &x), 0);
    assert_close(x, 2.9948907893119766e-105, 1e-10);
    double p;
    assert_int_equal(igea_stats_chi2_sf(13.269943, 11, &p), 0);
    assert_close(p, 0.2760488648920812, 1e-12);
    assert_int_equal(igea_stats_chi2_cdf(3.0, 2.5, &p), 0);
    assert_close(p, 0.6941503705541809, 1e-13);
    assert_int_equal(igea_stats_chi2_sf(20000, 20000, &p), 0);
    assert_close(p, 0.4986701916600448, 1e-12);
}

/* Inputs that abort the process through GSL's handler (gsl_cdf_chisq_Pinv
 * with dof 0; convergence failures at large dof) come back as codes or
 * values; the round trip P(Pinv(p)) = p holds over a wide grid. */
static void test_chi2_no_abort_grid(void **state)
{
    gsl_error_handler_t *old = gsl_set_error_handler(counting_handler);
    gsl_handler_calls = 0;
    double x = SENTINEL;
    assert_int_equal(igea_stats_chi2_quantile(0.5, 0.0, &x), -2);
    assert_int_equal(igea_stats_chi2_quantile(1.5, 3.0, &x), -1);
    assert_int_equal(igea_stats_chi2_quantile(0.5, -1.0, &x), -2);
    assert_int_equal(igea_stats_chi2_quantile(0.5, NAN, &x), -2);
    assert_int_equal(igea_stats_chi2_quantile(0.5, 2e7, &x), -2);
    assert_int_equal(igea_stats_chi2_upper(0.0, 3.0, &x), -1);
    assert_int_equal(igea_stats_chi2_upper(0.5, 3.0, NULL), -3);
    assert_int_equal(igea_stats_chi2_quantile(0.5, 3.0, NULL), -3);
    assert_int_equal(igea_stats_chi2_cdf(-1.0, 3.0, &x), -1);
    assert_int_equal(igea_stats_chi2_cdf(NAN, 3.0, &x), -1);
    assert_int_equal(igea_stats_chi2_sf(1.0, 0.0, &x), -2);
    assert_int_equal(igea_stats_chi2_sf(1.0, 1.0, NULL), -3);
    assert_true(x == SENTINEL);
    const double ps[] = {1e-300, 1e-100, 1e-16, 1e-10, 1e-5, 0.01, 0.5, 0.99, 1 - 1e-10};
    const double dofs[] = {1e-3, 0.01, 0.1, 0.5, 1, 2, 11, 100, 1000, 1e4, 1e5};
    for (size_t j = 0; j < sizeof dofs / sizeof dofs[0]; j++)
        for (size_t i = 0; i < sizeof ps / sizeof ps[0]; i++) {
            double q, back;
            int st = igea_stats_chi2_quantile(ps[i], dofs[j], &q);
            if (st == IGEA_ENOCONV) /* a representable answer may not exist */
                continue;
            assert_int_equal(st, 0);
            if (q == 0.0) { /* underflow: only where x^(dof/2) ~ p cannot be a double */
                assert_true(log(ps[i]) / (0.5 * dofs[j]) < -700);
                continue;
            }
            if (ps[i] <= 0.5) {
                assert_int_equal(igea_stats_chi2_cdf(q, dofs[j], &back), 0);
                assert_close(back, ps[i], dofs[j] <= 1e4 ? 1e-9 : 1e-6);
            } else { /* 1 - p is exact for p >= 0.5 */
                assert_int_equal(igea_stats_chi2_sf(q, dofs[j], &back), 0);
                assert_close(back, 1.0 - ps[i], dofs[j] <= 1e4 ? 1e-9 : 1e-6);
            }
            assert_int_equal(igea_stats_chi2_upper(ps[i], dofs[j], &q), 0);
            assert_int_equal(igea_stats_chi2_sf(q, dofs[j], &back), 0);
            if (ps[i] <= 0.5)
                assert_close(back, ps[i], 1e-9);
        }
    /* cdf and sf over the whole domain: x from 1e-300 to 1e300 and around
     * the mean, every dof up to the documented maximum */
    for (size_t j = 0; j < sizeof dofs / sizeof dofs[0]; j++) {
        for (double xx = 1e-300; xx < 1e300; xx *= 1e3) {
            double p, q;
            assert_int_equal(igea_stats_chi2_cdf(xx, dofs[j], &p), 0);
            assert_int_equal(igea_stats_chi2_sf(xx, dofs[j], &q), 0);
            assert_true(p >= 0 && p <= 1 && q >= 0 && q <= 1);
        }
        for (double k = -40; k <= 40; k += 0.5) {
            double xx = dofs[j] + k * sqrt(2 * dofs[j]), p, q;
            if (xx <= 0)
                continue;
            assert_int_equal(igea_stats_chi2_cdf(xx, dofs[j], &p), 0);
            assert_int_equal(igea_stats_chi2_sf(xx, dofs[j], &q), 0);
            assert_close_abs(p + q, 1.0, 0, dofs[j] <= 1e4 ? 1e-12 : 1e-7);
        }
    }
    assert_int_equal(igea_stats_chi2_upper(0.01, IGEA_STATS_DOF_MAX, &x), 0);
    assert_int_equal(gsl_handler_calls, 0);
    gsl_set_error_handler(old);
}

/* Reference values: mpmath 1.3.0 at 50 significant digits, printed to 17,
 * by this script (P through 1F1, Q through mpmath's own gammainc):
 *   import mpmath; mpmath.mp.dps = 50
 *   def P(x, k):
 *       a = mpmath.mpf(k) / 2; z = mpmath.mpf(x) / 2
 *       return z**a * mpmath.exp(-z) / mpmath.gamma(a + 1) * \
 *              mpmath.hyp1f1(1, a + 1, z, maxterms=10**8)
 *   def Q(x, k):
 *       return mpmath.gammainc(mpmath.mpf(k) / 2, mpmath.mpf(x) / 2,
 *                              mpmath.inf, regularized=True)
 *   print(mpmath.nstr(P(9891, 1e4), 17), mpmath.nstr(Q(9891, 1e4), 17))
 * Quantiles: mpmath.findroot(g, (t0, t0 + 1e-3), solver='secant',
 * tol=1e-90) on g(t) = log(P(e^t, k) / p) (Q for the upper point), t0 the
 * log of the Wilson-Hilferty start; normal tail: erfc(x / sqrt(2)) / 2. */
static const double chi2_ref[][4] = { /* x, dof, P, Q */
    {9891, 10000.0, 2.209922655604454e-1, 7.790077344395546e-1},
    {10000.0, 10000.0, 5.0188063403381736e-1, 4.9811936596618264e-1},
    {1.5, 0.001, 9.9982976056772074e-1, 1.7023943227925564e-4},
    {0.7171067811865475, 0.01, 9.9610791489081295e-1, 3.8920851091870492e-3},
    {1e-05, 1, 2.5231283168055979e-3, 9.974768716831944e-1},
    {62, 2, 9.9999999999996558e-1, 3.4424771084699765e-14},
    {3.0, 2.5, 6.9415037055418209e-1, 3.0584962944581791e-1},
    {13.269943, 11, 7.2395113510791883e-1, 2.7604886489208117e-1},
    {1e-20, 11, 7.675657150580713e-115, 1.0},
    {57.88854381999832, 40, 9.6665049858359753e-1, 3.3349501416402474e-2},
    {0.001, 0.1, 7.0242555337477799e-1, 2.9757444662522201e-1},
    {85.85786437626905, 100, 1.5775804281463344e-1, 8.4224195718536656e-1},
    {1200, 1000, 9.9998774405766938e-1, 1.2255942330622904e-5},
    {27550.51025721682, 30000.0, 4.1959438220689115e-25, 1.0},
    {101043.31473677837, 100000.0, 9.8999999999999993e-1, 1.000000000000007e-2},
    {99000, 100000.0, 1.2478315638082799e-2, 9.875216843619172e-1},
    {100000.0, 100000.0, 5.0059470810479331e-1, 4.9940529189520669e-1},
    {98000.5, 100000.0, 3.402847285553807e-6, 9.9999659715271445e-1},
    {103000, 100000.0, 9.9999999998471087e-1, 1.5289130117302352e-11},
    {120000.0, 100000.0, 1.0, 0.0}, /* Q = 1.1684697671564152e-386 */
    {80000.0, 100000.0, 0.0, 1.0}, /* P = 2.4796446433256449e-505 */
    {992928.9321881345, 1000000.0, 2.7023027943305786e-7, 9.9999972976972057e-1},
    {10000000.0, 10000000.0, 5.0005947080393784e-1, 4.9994052919606216e-1},
    {9990000.0, 10000000.0, 1.2654131885775518e-2, 9.8734586811422448e-1},
    {10134164.078649987, 10000000.0, 1.0, 2.6386611784143297e-196},
};
static const double chi2_qref[][4] = { /* p, dof, upper, x */
    {0.01, 11, 1, 2.4724970311318283e+1},
    {0.5, 1, 0, 4.5493642311957275e-1},
    {1e-10, 10000.0, 0, 9.1265118024232567e+3},
    {0.01, 100000.0, 1, 1.0104331473677837e+5},
    {1e-12, 3, 1, 5.8919755683202153e+1},
    {0.3, 0.01, 0, 2.9948907893113121e-105},
    {0.05, 100000.0, 0, 9.9265537878160643e+4},
    {1e-10, 100000.0, 1, 1.0287124188112092e+5},
    {0.5, 100000.0, 0, 9.9999333334123463e+4},
    {0.01, 1000000.0, 1, 1.0032928936864126e+6},
    {0.5, 10000000.0, 0, 9.9999993333333412e+6},
    {1e-06, 10000000.0, 1, 1.0021272358296907e+7},
};
static const double nsf_ref[][2] = { /* x, Q(x) */
    {8.3, 5.205569744890254e-17},
    {38, 2.8854283600687843e-316},
    {1.0, 1.5865525393145705e-1},
    {-1.5, 9.3319279873114193e-1},
    {20, 2.7536241186062337e-89},
    {37.5, 4.6053530095819548e-308},
    {30, 4.9067139271481871e-198},
};

static void check_rel(double got, double want, double tol)
{
    if (want >= DBL_MIN)
        assert_close(got, want, tol);
    else /* a subnormal or 0: the correctly rounded double */
        assert_true(got == want);
}

/* Relative error <= 1e-14 up to dof 1e5, documented 1e-13 up to 1e7. */
static void test_chi2_mpmath(void **state)
{
    for (size_t i = 0; i < sizeof chi2_ref / sizeof chi2_ref[0]; i++) {
        const double *r = chi2_ref[i];
        double tol = r[1] <= 1e5 ? 1e-14 : 1e-13, p = -1, q = -1;
        assert_int_equal(igea_stats_chi2_cdf(r[0], r[1], &p), 0);
        assert_int_equal(igea_stats_chi2_sf(r[0], r[1], &q), 0);
        check_rel(p, r[2], tol);
        check_rel(q, r[3], tol);
    }
    for (size_t i = 0; i < sizeof chi2_qref / sizeof chi2_qref[0]; i++) {
        const double *r = chi2_qref[i];
        double tol = r[1] <= 1e5 ? 1e-14 : 1e-13, x = -1;
        if (r[2] != 0.0)
            assert_int_equal(igea_stats_chi2_upper(r[0], r[1], &x), 0);
        else
            assert_int_equal(igea_stats_chi2_quantile(r[0], r[1], &x), 0);
        assert_close(x, r[3], tol);
    }
    double x = SENTINEL;
    assert_int_equal(igea_stats_chi2_cdf(1.0, IGEA_STATS_CHI2_DOF_MAX * 1.5, &x), -2);
    assert_true(x == SENTINEL);
}

static void test_normal_sf(void **state)
{
    for (size_t i = 0; i < sizeof nsf_ref / sizeof nsf_ref[0]; i++) {
        double q = -1;
        assert_int_equal(igea_stats_normal_sf(nsf_ref[i][0], &q), 0);
        check_rel(q, nsf_ref[i][1], 1e-15);
    }
    double q = -1;
    /* the smallest positive double 2^-1074 ~ 4.94e-324: Q(38.4674) ~ 4.95e-324 */
    assert_int_equal(igea_stats_normal_sf(38.4674, &q), 0);
    assert_true(q == 0x1p-1074);
    assert_int_equal(igea_stats_normal_sf(38.6, &q), 0);
    assert_true(q == 0.0);
    assert_int_equal(igea_stats_normal_sf(-INFINITY, &q), 0);
    assert_true(q == 1.0);
    assert_int_equal(igea_stats_normal_sf(INFINITY, &q), 0);
    assert_true(q == 0.0);
    q = SENTINEL;
    assert_int_equal(igea_stats_normal_sf(NAN, &q), -1);
    assert_true(q == SENTINEL);
    assert_int_equal(igea_stats_normal_sf(1.0, NULL), -2);
}

/* Student's t and F tails, t quantiles: mpmath 1.3.0, dps 50, through
 *   I_x(a, b) = x^a (1-x)^b / (a B(a, b)) 2F1(a + b, 1; a + 1; x)
 * (the symmetry 1 - I_{1-x}(b, a) for x > a / (a + b)),
 * Q_t(t; n) = I_{n/(n+t^2)}(n/2, 1/2) / 2, Q_F(f; d1, d2) =
 * I_{d2/(d2+d1 f)}(d2/2, d1/2); quantiles by mpmath.findroot to 1e-45.
 * Closed forms among them: Q_F(3; 2, 10) = 1.6^-5, Q_t(0.3; 1) =
 * 1/2 - atan(0.3)/pi (Cauchy). */
static const double t_ref[][3] = { /* t, dof, Q */
    {2.0, 10, 3.6694017385370183e-2},
    {-1.5, 3, 8.8470806737758847e-1},
    {30, 100, 4.1901662793441461e-52},
    {5, 1000.0, 3.3836281823243152e-7},
    {1e10, 10, 1.23046875e-96},
    {0.3, 1, 4.0722642092225766e-1},
    {3, 100000.0, 1.3502304420323596e-3},
};
static const double f_ref[][4] = { /* f, d1, d2, Q */
    {3.0, 2, 10, 9.5367431640625e-2},
    {0.5, 5, 30, 7.7373359370359489e-1},
    {50, 3, 37, 4.2874370267657257e-13},
    {1.2, 10, 100000.0, 2.8507256166706787e-1},
    {1e4, 1, 1000, 0.0}, /* 5.3228217077566136e-523 */
};
static const double tq_ref[][3] = { /* p, dof, t */
    {0.975, 10, 2.2281388519862742},
    {0.975, 1, 1.2706204736174693e+1},
    {0.995, 3, 5.8409093097333554},
    {0.025, 30, -2.0422724563012383},
    {0.975, 100000.0, 1.9599877075346093},
};

static void test_t_f_mpmath(void **state)
{
    double q;
    for (size_t i = 0; i < sizeof t_ref / sizeof t_ref[0]; i++) {
        assert_int_equal(igea_stats_t_sf(t_ref[i][0], t_ref[i][1], &q), 0);
        assert_close(q, t_ref[i][2], 1e-13);
    }
    for (size_t i = 0; i < sizeof f_ref / sizeof f_ref[0]; i++) {
        assert_int_equal(igea_stats_f_sf(f_ref[i][0], f_ref[i][1], f_ref[i][2], &q), 0);
        check_rel(q, f_ref[i][3], 1e-13);
    }
    for (size_t i = 0; i < sizeof tq_ref / sizeof tq_ref[0]; i++) {
        assert_int_equal(igea_stats_t_quantile(tq_ref[i][0], tq_ref[i][1], &q), 0);
        assert_close(q, tq_ref[i][2], 1e-14);
    }
    assert_close(0.5 - atan(0.3) / 3.14159265358979323846, t_ref[5][2], 1e-15);
    assert_int_equal(igea_stats_t_sf(INFINITY, 3, &q), 0);
    assert_true(q == 0.0);
    q = SENTINEL;
    assert_int_equal(igea_stats_t_sf(NAN, 3, &q), -1);
    assert_int_equal(igea_stats_t_sf(1, 0, &q), -2);
    assert_int_equal(igea_stats_f_sf(-1, 1, 1, &q), -1);
    assert_int_equal(igea_stats_f_sf(1, 1, 0, &q), -3);
    assert_int_equal(igea_stats_t_quantile(1.0, 3, &q), -1);
    assert_true(q == SENTINEL);
}

/* Seed 000, Table 1 -> Table 2 with the tabulated z = 2.58, and eq. (10). */
static const double tab_x[11] = {0.2833, -1.0819, 0.8138, 0.4933, 0.0526, 0.1372,
                                 0.8714, -0.8370, 2.5527, 1.7403, -0.3456};
static const double tab_l[11] = {2.42E+05, 9.03E+04, 7.24E+04, 1.56E+04, 2.05E+03, 1.79E+03,
                                 1.38E+03, 6.51E+02, 5.01E+02, 1.85E+02, 8.62E+01};

static void test_accuracy_seed_table(void **state)
{
    double z[11], info[IGEA_STATS_INFO_LEN];
    int rej[11];
    assert_int_equal(igea_stats_accuracy_test(11, tab_x, tab_l, 0.01, 10.0, 2.58, z, rej, info), 0);
    /* Table 2 thresholds sqrt(1 + 1/lambda) * 2.58 to 4 decimals */
    const double thr[11] = {2.5800, 2.5800, 2.5800, 2.5801, 2.5806, 2.5807,
                            2.5809, 2.5820, 2.5826, 2.5870, 2.5949};
    for (int i = 0; i < 11; i++) {
        double t = sqrt(1.0 + 1.0 / tab_l[i]) * info[IGEA_STATS_INFO_Z_CRIT];
        assert_true(fabs(t - thr[i]) < 0.5e-4);
        assert_int_equal(rej[i], 0);
    }
    assert_close(info[IGEA_STATS_INFO_CHI2], 13.2699, 0.5e-4 / 13.27); /* printed 13.2700 */
    assert_true(fabs(info[IGEA_STATS_INFO_CHI2] - 13.2699) < 0.5e-4);
    assert_int_equal((int)info[IGEA_STATS_INFO_DOF], 11);
    assert_close(info[IGEA_STATS_INFO_CHI2_CRIT], 24.72497031131828, 1e-13);
    assert_true(fabs(info[IGEA_STATS_INFO_P_VALUE] - 0.276) < 0.5e-3);
    assert_true(info[IGEA_STATS_INFO_PASSED] == 1.0);
    /* exact z: component 9 still passes, by about 1 % (METHODS 1.5) */
    assert_int_equal(igea_stats_accuracy_test(11, tab_x, tab_l, 0.01, 10.0, 0.0, z, rej, info), 0);
    assert_close(info[IGEA_STATS_INFO_Z_CRIT], 2.5758293035489004, 1e-15);
    assert_close(z[8], 2.5527 / sqrt(1.0 + 1.0 / 501.0), 1e-15);
    assert_true(fabs(z[8] - 2.5502) < 0.5e-4);
    assert_int_equal(rej[8], 0);
    /* at alpha = 0.05 component 9 is rejected */
    assert_int_equal(igea_stats_accuracy_test(11, tab_x, tab_l, 0.05, 10.0, 0.0, z, rej, info), 0);
    assert_int_equal(rej[8], 1);
    assert_int_equal((int)info[IGEA_STATS_INFO_N_REJECT], 1);
    assert_true(info[IGEA_STATS_INFO_PASSED] == 0.0);
    /* lambda_test = 200 keeps the first 9 */
    assert_int_equal(igea_stats_accuracy_test(11, tab_x, tab_l, 0.01, 200.0, 0.0, z, rej, info), 0);
    assert_int_equal((int)info[IGEA_STATS_INFO_N_TEST], 9);
    assert_int_equal(rej[9], -1);
    assert_int_equal(rej[10], -1);
}

static void test_accuracy_invalid(void **state)
{
    double z[11], info[IGEA_STATS_INFO_LEN], x[2] = {1.0, NAN}, l[2] = {100, 100};
    int rej[11];
    fill_sentinel(info, IGEA_STATS_INFO_LEN);
    assert_int_equal(igea_stats_accuracy_test(0, tab_x, tab_l, 0.01, 10, 0, z, rej, info), -1);
    assert_int_equal(igea_stats_accuracy_test(11, NULL, tab_l, 0.01, 10, 0, z, rej, info), -2);
    assert_int_equal(igea_stats_accuracy_test(11, tab_x, NULL, 0.01, 10, 0, z, rej, info), -3);
    assert_int_equal(igea_stats_accuracy_test(11, tab_x, tab_l, 1.0, 10, 0, z, rej, info), -4);
    assert_int_equal(igea_stats_accuracy_test(11, tab_x, tab_l, 0.01, 0, 0, z, rej, info), -5);
    assert_int_equal(igea_stats_accuracy_test(11, tab_x, tab_l, 0.01, 10, -1, z, rej, info), -6);
    assert_int_equal(igea_stats_accuracy_test(11, tab_x, tab_l, 0.01, 10, 0, NULL, rej, info), -7);
    assert_int_equal(igea_stats_accuracy_test(11, tab_x, tab_l, 0.01, 10, 0, z, NULL, info), -8);
    assert_int_equal(igea_stats_accuracy_test(11, tab_x, tab_l, 0.01, 10, 0, z, rej, NULL), -9);
    assert_int_equal(igea_stats_accuracy_test(2, x, l, 0.01, 10, 0, z, rej, info), IGEA_ENONFINITE);
    assert_int_equal(igea_stats_accuracy_test(11, tab_x, tab_l, 0.01, 1e6, 0, z, rej, info),
                     IGEA_ENOTESTABLE);
    assert_true(all_sentinel(info, IGEA_STATS_INFO_LEN));
}

static void test_pool(void **state)
{
    /* METHODS 1.6(b) illustration: three flights, T = 4.88 + 2.54 + 5.42 =
     * 12.84 with 7 + 6 + 7 = 20 dof against chi2_0.01(20) = 37.566. */
    double T[3] = {4.88, 2.54, 5.42}, info[IGEA_STATS_INFO_LEN];
    int dof[3] = {7, 6, 7}, nrej[3] = {0, 0, 0}, ids[3] = {11, 12, 13}, same[3] = {11, 12, 11};
    assert_int_equal(igea_stats_pool(3, T, dof, nrej, ids, 0.01, info), 0);
    assert_close(info[IGEA_STATS_INFO_CHI2], 12.84, 1e-15);
    assert_int_equal((int)info[IGEA_STATS_INFO_DOF], 20);
    assert_close(info[IGEA_STATS_INFO_CHI2_CRIT], 37.56623478662507, 1e-12);
    assert_true(info[IGEA_STATS_INFO_PASSED] == 1.0);
    assert_int_equal((int)info[IGEA_STATS_INFO_N_FLIGHTS], 3);
    nrej[1] = 1; /* one rejected component anywhere rejects the system */
    assert_int_equal(igea_stats_pool(3, T, dof, nrej, NULL, 0.01, info), 0);
    assert_true(info[IGEA_STATS_INFO_PASSED] == 0.0);
    nrej[1] = 0;
    fill_sentinel(info, IGEA_STATS_INFO_LEN);
    assert_int_equal(igea_stats_pool(3, T, dof, nrej, same, 0.01, info), IGEA_EDEPENDENT);
    assert_int_equal(igea_stats_pool(0, T, dof, nrej, NULL, 0.01, info), -1);
    assert_int_equal(igea_stats_pool(3, NULL, dof, nrej, NULL, 0.01, info), -2);
    assert_int_equal(igea_stats_pool(3, T, NULL, nrej, NULL, 0.01, info), -3);
    assert_int_equal(igea_stats_pool(3, T, dof, NULL, NULL, 0.01, info), -4);
    assert_int_equal(igea_stats_pool(3, T, dof, nrej, NULL, 0.0, info), -6);
    assert_int_equal(igea_stats_pool(3, T, dof, nrej, NULL, 0.01, NULL), -7);
    T[0] = -1;
    assert_int_equal(igea_stats_pool(3, T, dof, nrej, NULL, 0.01, info), -2);
    T[0] = NAN;
    assert_int_equal(igea_stats_pool(3, T, dof, nrej, NULL, 0.01, info), IGEA_ENONFINITE);
    T[0] = 4.88;
    dof[0] = 0;
    assert_int_equal(igea_stats_pool(3, T, dof, nrej, NULL, 0.01, info), -3);
    assert_true(all_sentinel(info, IGEA_STATS_INFO_LEN));
}

static void test_large_finite_values(void **state)
{
    (void)state;
    /* An equivalent error of 1e300: z_1 = 1e300 / sqrt(1.01) is a double,
     * z_1^2 and T are not: T saturates at DBL_MAX, p = 0, rejected (was
     * status -1 after z and reject were written). */
    double e[2] = {1e300, 0.5}, lam[2] = {100, 50}, z[2], info[IGEA_STATS_INFO_LEN];
    int rej[2];
    assert_int_equal(igea_stats_accuracy_test(2, e, lam, 0.01, 10, 0, z, rej,
                                              info), 0);
    assert_close(z[0], 1e300 / sqrt(1.01), 1e-15);
    assert_close(z[1], 0.5 / sqrt(1.02), 1e-15);
    assert_int_equal(rej[0], 1);
    assert_int_equal(rej[1], 0);
    assert_true(info[IGEA_STATS_INFO_CHI2] == DBL_MAX);
    assert_true(info[IGEA_STATS_INFO_P_VALUE] == 0.0);
    assert_true(info[IGEA_STATS_INFO_PASSED] == 0.0);
    assert_true(info[IGEA_STATS_INFO_N_REJECT] == 1.0);
    assert_close(info[IGEA_STATS_INFO_CHI2_CRIT], 9.2103403719761836, 1e-12);
    for (int k = 0; k < IGEA_STATS_INFO_RANK; k++)
        assert_true(isfinite(info[k]));
    /* Large but summable: T = 1e300 / 1.01 + 0.25 / 1.02 exactly as a
     * double; Q(T; 2) = exp(-T / 2) = 0. */
    e[0] = 1e150;
    assert_int_equal(igea_stats_accuracy_test(2, e, lam, 0.01, 10, 0, z, rej,
                                              info), 0);
    assert_close(info[IGEA_STATS_INFO_CHI2], 1e300 / 1.01, 1e-15);
    assert_true(info[IGEA_STATS_INFO_P_VALUE] == 0.0 && info[IGEA_STATS_INFO_PASSED] == 0.0);
    /* Pooling two chi-squares of 1e308: the sum overflows, the verdict is
     * a rejection with p = 0 (was status -1). */
    double c2[2] = {1e308, 1e308};
    int dof[2] = {3, 4}, nr[2] = {0, 0};
    assert_int_equal(igea_stats_pool(2, c2, dof, nr, NULL, 0.01, info), 0);
    assert_true(info[IGEA_STATS_INFO_CHI2] == DBL_MAX);
    assert_true(info[IGEA_STATS_INFO_P_VALUE] == 0.0);
    assert_true(info[IGEA_STATS_INFO_PASSED] == 0.0);
    assert_true(info[IGEA_STATS_INFO_DOF] == 7.0);
    /* One large finite chi-square: summed exactly, p = 0. */
    c2[0] = 1e300;
    c2[1] = 2.0;
    assert_int_equal(igea_stats_pool(2, c2, dof, nr, NULL, 0.01, info), 0);
    assert_true(info[IGEA_STATS_INFO_CHI2] == 1e300);
    assert_true(info[IGEA_STATS_INFO_P_VALUE] == 0.0 && info[IGEA_STATS_INFO_PASSED] == 0.0);
    /* Failures write nothing. */
    double zs[2], is[IGEA_STATS_INFO_LEN];
    int rs[2] = {-7, -7};
    fill_sentinel(zs, 2);
    fill_sentinel(is, IGEA_STATS_INFO_LEN);
    e[1] = NAN;
    assert_int_equal(igea_stats_accuracy_test(2, e, lam, 0.01, 10, 0, zs, rs, is),
                     IGEA_ENONFINITE);
    assert_true(all_sentinel(zs, 2) && all_sentinel(is, IGEA_STATS_INFO_LEN) &&
                rs[0] == -7 && rs[1] == -7);
    /* More tested components than the chi-square routines accept: the
     * count is named, not the equivalent errors. */
    int nbig = (int)IGEA_STATS_DOF_MAX + 1;
    double *eb = malloc(sizeof(double) * nbig), *lb = malloc(sizeof(double) * nbig);
    double *zb = malloc(sizeof(double) * nbig);
    int *rb = malloc(sizeof(int) * nbig);
    assert_non_null(eb && lb && zb && rb);
    for (int i = 0; i < nbig; i++) {
        eb[i] = 0.1;
        lb[i] = 100.0;
    }
    fill_sentinel(zb, nbig);
    assert_int_equal(igea_stats_accuracy_test(nbig, eb, lb, 0.01, 10, 0, zb, rb,
                                              is), -1);
    assert_true(all_sentinel(zb, nbig) && all_sentinel(is, IGEA_STATS_INFO_LEN));
    free(eb);
    free(lb);
    free(zb);
    free(rb);
    int dbig[2] = {60000, 60000};
    c2[0] = c2[1] = 1.0;
    assert_int_equal(igea_stats_pool(2, c2, dbig, nr, NULL, 0.01, is), -3);
    assert_true(all_sentinel(is, IGEA_STATS_INFO_LEN));
    /* The new statuses have their own text. */
    assert_true(strstr(igea_strerror(IGEA_EOVERFLOW), "overflow") != NULL);
    assert_true(strcmp(igea_strerror(IGEA_EOVERFLOW),
                       igea_strerror(IGEA_ENONFINITE)) != 0);
    assert_true(strstr(igea_strerror(IGEA_ERANGE), "standard deviation") != NULL);
}

static void test_erfinv(void **state)
{
    double x = SENTINEL;
    assert_int_equal(igea_stats_erfinv(0.5, &x), 0);
    assert_close(x, 0.47693627620446987338, 2e-16); /* erfinv(1/2), DLMF 7.17 */
    assert_int_equal(igea_stats_erfinv(0.0, &x), 0);
    assert_true(x == 0.0);
    for (double y = -0.999; y < 1.0; y += 0.0123) {
        assert_int_equal(igea_stats_erfinv(y, &x), 0);
        assert_close_abs(erf(x), y, 4e-16, 1e-300);
    }
    /* the tail, through erfc: the start is poor here, Newton fixes it */
    const double q[4] = {1e-6, 1e-10, 1e-14, 1e-15};
    for (int i = 0; i < 4; i++) {
        assert_int_equal(igea_stats_erfinv(1.0 - q[i], &x), 0);
        assert_close(erfc(x), 1.0 - (1.0 - q[i]), 1e-13);
        assert_int_equal(igea_stats_erfinv(-(1.0 - q[i]), &x), 0);
        assert_close(erfc(-x), 1.0 - (1.0 - q[i]), 1e-13);
    }
    x = SENTINEL;
    assert_int_equal(igea_stats_erfinv(1.0, &x), -1);
    assert_int_equal(igea_stats_erfinv(-1.0, &x), -1);
    assert_int_equal(igea_stats_erfinv(NAN, &x), -1);
    assert_int_equal(igea_stats_erfinv(0.3, NULL), -2);
    assert_true(x == SENTINEL);
}

/* ---- overall size of the verdict, against independent computations */

static double un_phi(double z) { return exp(-0.5 * z * z) / sqrt(2.0 * 3.14159265358979323846); }
static double un_erf2(double x) { return erf(x / sqrt(2.0)); } /* 2 Phi(x) - 1 */

/* 1 - size for n = 2: int_{-a}^{a} phi(z) (2 Phi(min(a, sqrt(b - z^2))) - 1) dz
 * by composite Simpson on [0, c] and [c, min(a, sqrt b)], c = sqrt(b - a^2). */
static double un_g2(double a, double b, double z)
{
    double r = b - z * z;
    if (r <= 0.0)
        return 0.0;
    double t = sqrt(r);
    return un_phi(z) * un_erf2(t < a ? t : a);
}

static double un_simpson2(double a, double b, double lo, double hi)
{
    const int m = 20000;
    double h = (hi - lo) / m, sum = un_g2(a, b, lo) + un_g2(a, b, hi);
    for (int i = 1; i < m; i++)
        sum += (i % 2 ? 4.0 : 2.0) * un_g2(a, b, lo + i * h);
    return sum * h / 3.0;
}

static double un_size2(double a, double b)
{
    double top = a < sqrt(b) ? a : sqrt(b);
    double c = b > a * a ? sqrt(b - a * a) : 0.0;
    if (c > top)
        c = top;
    return 1.0 - 2.0 * (un_simpson2(a, b, 0.0, c) + un_simpson2(a, b, c, top));
}

static void test_union_size(void **state)
{
    (void)state;
    double v;
    /* n = 1: 1 - P(|z| <= min(a, sqrt b)), also with b <= a^2 */
    const double a1[5] = {2.0, 2.0, 1.5, INFINITY, 1.96};
    const double b1[5] = {9.0, 2.0, 2.25, 3.84, INFINITY};
    for (int i = 0; i < 5; i++) {
        double m = a1[i] < sqrt(b1[i]) ? a1[i] : sqrt(b1[i]);
        assert_int_equal(igea_stats_union_size(1, a1[i], b1[i], &v), 0);
        assert_close(v, erfc(m / sqrt(2.0)), 1e-13);
    }
    /* a = Inf: the chi-square sf, closed forms for dof 3, 4, 6 */
    assert_int_equal(igea_stats_union_size(4, INFINITY, 13.28, &v), 0);
    assert_close(v, exp(-6.64) * (1.0 + 6.64), 1e-13);
    assert_int_equal(igea_stats_union_size(6, INFINITY, 16.81, &v), 0);
    assert_close(v, exp(-8.405) * (1.0 + 8.405 + 8.405 * 8.405 / 2.0), 1e-13);
    /* b <= a^2: the component tests are implied, the chi-square sf */
    assert_int_equal(igea_stats_union_size(3, 4.0, 11.34, &v), 0);
    assert_close(v, erfc(sqrt(11.34 / 2.0)) + sqrt(2.0 * 11.34 / 3.14159265358979323846) *
                        exp(-11.34 / 2.0), 1e-12);
    /* b = Inf: 1 - (2 Phi(a) - 1)^n */
    assert_int_equal(igea_stats_union_size(7, 2.5758293035489004, INFINITY, &v), 0);
    assert_close(v, 1.0 - pow(un_erf2(2.5758293035489004), 7.0), 1e-12);
    assert_int_equal(igea_stats_union_size(3, INFINITY, INFINITY, &v), 0);
    assert_true(v == 0.0);
    /* n = 2 in the crossing regime a^2 < b < 2 a^2, against the 1-D integral */
    const double a2[6] = {2.5758293035489004, 2.0, 1.0, 3.0, 1.5, 2.5758293035489004};
    const double b2[6] = {9.210340371976182, 5.0, 1.5, 17.0, 4.0, 6.7};
    for (int i = 0; i < 6; i++) {
        assert_int_equal(igea_stats_union_size(2, a2[i], b2[i], &v), 0);
        assert_close_abs(v, un_size2(a2[i], b2[i]), 0.0, 1e-10);
    }
    /* b >= n a^2: the chi-square test is implied */
    assert_int_equal(igea_stats_union_size(2, 1.0, 2.0, &v), 0);
    assert_close(v, 1.0 - pow(un_erf2(1.0), 2.0), 1e-13);
    /* monotone in n and between the bounds max(Q, 1 - p^n) <= size <= sum */
    double prev = 0.0;
    for (int n = 2; n <= 12; n++) {
        double b, qb, lo, hi;
        assert_int_equal(igea_stats_chi2_upper(0.01, (double)n, &b), 0);
        qb = 0.01;
        lo = 1.0 - pow(un_erf2(2.5758293035489004), (double)n);
        lo = lo > qb ? lo : qb;
        hi = qb + n * 0.01;
        assert_int_equal(igea_stats_union_size(n, 2.5758293035489004, b, &v), 0);
        assert_true(v >= lo - 1e-12 && v <= hi && v > prev);
        prev = v;
    }
}

static void test_union_size_invalid(void **state)
{
    (void)state;
    double v = SENTINEL;
    assert_int_equal(igea_stats_union_size(0, 2.0, 9.0, &v), -1);
    assert_int_equal(igea_stats_union_size(IGEA_STATS_UNION_N_MAX + 1, 2.0, 9.0, &v), -1);
    assert_int_equal(igea_stats_union_size(-3, 2.0, 9.0, &v), -1);
    assert_int_equal(igea_stats_union_size(2, 0.0, 9.0, &v), -2);
    assert_int_equal(igea_stats_union_size(2, -1.0, 9.0, &v), -2);
    assert_int_equal(igea_stats_union_size(2, NAN, 9.0, &v), -2);
    assert_int_equal(igea_stats_union_size(2, -INFINITY, 9.0, &v), -2);
    assert_int_equal(igea_stats_union_size(2, 2.0, 0.0, &v), -3);
    assert_int_equal(igea_stats_union_size(2, 2.0, NAN, &v), -3);
    assert_int_equal(igea_stats_union_size(2, 2.0, -INFINITY, &v), -3);
    assert_int_equal(igea_stats_union_size(2, 2.0, 9.0, NULL), -4);
    assert_true(v == SENTINEL);
}

static void test_verdict_thresholds(void **state)
{
    (void)state;
    double a, b, s, ref;
    const double z995 = 2.5758293035489004;
    /* SEED: today's thresholds with their true size */
    assert_int_equal(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_SEED, 2, 0.01, &a, &b, &s), 0);
    assert_close(a, z995, 1e-14);
    assert_close(b, -2.0 * log(0.01), 1e-13); /* chi2_alpha(2) = -2 log alpha */
    assert_close_abs(s, un_size2(z995, -2.0 * log(0.01)), 0.0, 1e-10);
    assert_int_equal(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_SEED, 7, 0.01, &a, &b, &s), 0);
    assert_close(b, 18.475306906582357, 1e-12);
    assert_true(s > 0.06 && s < 0.08);
    /* CHI2: no component test */
    assert_int_equal(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_CHI2, 4, 0.05, &a, &b, &s), 0);
    assert_true(isinf(a) && a > 0);
    assert_close(exp(-b / 2.0) * (1.0 + b / 2.0), 0.05, 1e-12);
    assert_true(s == 0.05);
    /* EXACT: one common level g with size alpha (n = 2 by the integral) */
    const double al[2] = {0.01, 0.05};
    for (int i = 0; i < 2; i++) {
        assert_int_equal(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_EXACT, 2, al[i], &a, &b, &s), 0);
        double g = erfc(a / sqrt(2.0));
        assert_true(g < al[i] && g > al[i] / 3.0);
        assert_close(b, -2.0 * log(g), 1e-10);
        assert_close(s, al[i], 1e-10);
        assert_close_abs(un_size2(a, b), al[i], 0.0, 1e-10);
    }
    assert_int_equal(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_EXACT, 1, 0.01, &a, &b, &s), 0);
    assert_close(a, z995, 1e-13);
    assert_close(b, z995 * z995, 1e-12);
    assert_close(s, 0.01, 1e-12);
    /* SIDAK: component level 1 - sqrt(1 - alpha) for n = 2 */
    assert_int_equal(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_SIDAK, 2, 0.01, &a, &b, &s), 0);
    assert_close(erfc(a / sqrt(2.0)), 1.0 - sqrt(0.99), 1e-11);
    assert_close(b, -2.0 * log(0.01), 1e-13);
    ref = un_size2(a, b);
    assert_close_abs(s, ref, 0.0, 1e-10);
    assert_true(s > 0.01 && s < 0.02);
    /* invalid arguments leave the outputs untouched */
    a = b = s = SENTINEL;
    assert_int_equal(igea_stats_verdict_thresholds(-1, 2, 0.01, &a, &b, &s), -1);
    assert_int_equal(igea_stats_verdict_thresholds(4, 2, 0.01, &a, &b, &s), -1);
    assert_int_equal(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_EXACT, 0, 0.01, &a, &b, &s), -2);
    assert_int_equal(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_EXACT,
                                                   IGEA_STATS_UNION_N_MAX + 1, 0.01, &a, &b, &s), -2);
    assert_int_equal(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_EXACT, 2, 0.0, &a, &b, &s), -3);
    assert_int_equal(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_EXACT, 2, 1.0, &a, &b, &s), -3);
    assert_int_equal(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_EXACT, 2, NAN, &a, &b, &s), -3);
    assert_int_equal(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_EXACT, 2, 0.01, NULL, &b, &s), -4);
    assert_int_equal(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_EXACT, 2, 0.01, &a, NULL, &s), -5);
    assert_int_equal(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_EXACT, 2, 0.01, &a, &b, NULL), -6);
    assert_true(a == SENTINEL && b == SENTINEL && s == SENTINEL);
}

/* The streamed whiteness state does not depend on how the series is cut
 * into calls (every lagged product is added in element order, whatever
 * the chunks: the same bits), with a stride, and its Ljung-Box Q and runs
 * count are those of the definitions written out here: Q = n (n + 2)
 * sum_k r_k^2 / (n - k), r_k = sum_i d_i d_{i-k} / sum_i d_i^2, d about
 * the centre; runs = 1 + sign changes of the nonzero deviations. */
static void test_diag_chunks(void **state)
{
    (void)state;
    enum { N = 3000 };
    static double x[2 * N], d[N];
    unsigned long long u = 12345;
    double prev = 0.0;
    for (int i = 0; i < N; i++) {
        u = u * 6364136223846793005ULL + 1442695040888963407ULL;
        prev = 0.6 * prev + (double)(u >> 11) / 9007199254740992.0 - 0.5; /* AR(1) */
        x[2 * i] = prev;
        x[2 * i + 1] = 1e9; /* every other value: skipped by incx = 2 */
    }
    const double c = 0.01;
    const int lags[] = {1, 3, 20, 100}, cuts[] = {1, 2, 5, 511, 512, 513, 1500, N};
    for (size_t l = 0; l < sizeof lags / sizeof *lags; l++) {
        int L = lags[l];
        double ref[IGEA_STATS_DIAG_LEN];
        for (size_t k = 0; k < sizeof cuts / sizeof *cuts; k++) {
            double st[IGEA_STATS_DIAG_STATE_LEN], out[IGEA_STATS_DIAG_LEN];
            assert_int_equal(igea_stats_diag_init(L, c, st), 0);
            for (int i0 = 0; i0 < N; i0 += cuts[k]) {
                int nc = N - i0 < cuts[k] ? N - i0 : cuts[k];
                assert_int_equal(igea_stats_diag_add(nc, x + 2 * i0, 2, st), 0);
            }
            assert_int_equal(igea_stats_diag_result(st, out), 0);
            if (k == 0)
                memcpy(ref, out, sizeof ref);
            else
                assert_memory_equal(out, ref, sizeof ref);
        }
        double ss = 0.0, q = 0.0;
        int runs = 1;
        for (int i = 0; i < N; i++) {
            d[i] = x[2 * i] - c;
            ss += d[i] * d[i];
            runs += i > 0 && (d[i] > 0) != (d[i - 1] > 0);
        }
        for (int k = 1; k <= L; k++) {
            double ck = 0.0;
            for (int i = k; i < N; i++)
                ck += d[i] * d[i - k];
            q += (ck / ss) * (ck / ss) / (N - k);
        }
        q *= (double)N * (N + 2);
        assert_close(ref[IGEA_STATS_DIAG_LB_Q], q, 1e-12 * q);
        assert_int_equal((int)ref[IGEA_STATS_DIAG_RUNS], runs);
        assert_int_equal((int)ref[IGEA_STATS_DIAG_N], N);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_erfinv),
        cmocka_unit_test(test_version_and_strerror),
        cmocka_unit_test(test_normal),
        cmocka_unit_test(test_chi2_values),
        cmocka_unit_test(test_chi2_no_abort_grid),
        cmocka_unit_test(test_chi2_mpmath),
        cmocka_unit_test(test_normal_sf),
        cmocka_unit_test(test_t_f_mpmath),
        cmocka_unit_test(test_accuracy_seed_table),
        cmocka_unit_test(test_accuracy_invalid),
        cmocka_unit_test(test_pool),
        cmocka_unit_test(test_large_finite_values),
        cmocka_unit_test(test_union_size),
        cmocka_unit_test(test_union_size_invalid),
        cmocka_unit_test(test_verdict_thresholds),
        cmocka_unit_test(test_diag_chunks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
