/* tests/test_redund.c - reliability, confidence distance, fusion, FDI and
 * the windowed check (METHODS 3.1-3.3). */
#include "testutil.h"

#include "igea/redund.h"
#include "igea/stats.h"

/* Out-of-memory loop (as tests/test_oom.c): this program's malloc fails
 * the k-th allocation inside a call, k = 0, 1, ... until the call
 * succeeds; each failure must be IGEA_ENOMEM with the outputs untouched.
 * Not under AddressSanitizer, which owns malloc. */
#include "oom.h"

#define S2 0.70710678118654752440
#define PI_ 3.14159265358979323846

/* ---- reliability -------------------------------------------------------- */

static void test_exponential(void **state)
{
    double R = SENTINEL, mtbf = SENTINEL;
    assert_int_equal(igea_redund_exponential(1e-4, 1000.0, &R, &mtbf), 0);
    assert_close(R, exp(-0.1), 1e-15);
    assert_close(mtbf, 1e4, 1e-15);
    assert_int_equal(igea_redund_exponential(0.0, 5.0, &R, &mtbf), 0);
    assert_true(R == 1.0 && isinf(mtbf));
    assert_int_equal(igea_redund_exponential(2e-3, 3.0, &R, NULL), 0);
    assert_close(R, exp(-6e-3), 1e-15);
    R = SENTINEL;
    assert_int_equal(igea_redund_exponential(-1.0, 1.0, &R, NULL), -1);
    assert_int_equal(igea_redund_exponential(NAN, 1.0, &R, NULL), -1);
    assert_int_equal(igea_redund_exponential(1.0, -1.0, &R, NULL), -2);
    assert_int_equal(igea_redund_exponential(1.0, INFINITY, &R, NULL), -2);
    assert_int_equal(igea_redund_exponential(1.0, 1.0, NULL, NULL), -3);
    assert_true(R == SENTINEL);
}

static void test_series_parallel_kofn(void **state)
{
    const double R[4] = {0.9, 0.8, 0.95, 0.7};
    double out = SENTINEL;
    assert_int_equal(igea_redund_reliability_series(4, R, &out), 0);
    assert_close(out, 0.9 * 0.8 * 0.95 * 0.7, 1e-15);
    assert_int_equal(igea_redund_reliability_parallel(4, R, &out), 0);
    assert_close(out, 1.0 - 0.1 * 0.2 * 0.05 * 0.3, 1e-15);
    /* k = n is series, k = 1 parallel */
    double s, p;
    igea_redund_reliability_series(4, R, &s);
    igea_redund_reliability_parallel(4, R, &p);
    assert_int_equal(igea_redund_reliability_kofn(4, 4, R, &out), 0);
    assert_close(out, s, 1e-14);
    assert_int_equal(igea_redund_reliability_kofn(4, 1, R, &out), 0);
    assert_close(out, p, 1e-14);
    /* 2-of-4 by explicit enumeration */
    double want = 0.0;
    for (int mask = 0; mask < 16; mask++) {
        int c = 0;
        double w = 1.0;
        for (int i = 0; i < 4; i++) {
            if (mask & (1 << i)) {
                c++;
                w *= R[i];
            } else {
                w *= 1.0 - R[i];
            }
        }
        if (c >= 2)
            want += w;
    }
    assert_int_equal(igea_redund_reliability_kofn(4, 2, R, &out), 0);
    assert_close(out, want, 1e-14);
    /* equal R: binomial closed form, 2-of-3 = 3r^2 - 2r^3 */
    const double r3[3] = {0.99, 0.99, 0.99};
    assert_int_equal(igea_redund_reliability_kofn(3, 2, r3, &out), 0);
    assert_close(out, 3 * 0.99 * 0.99 - 2 * 0.99 * 0.99 * 0.99, 1e-15);
    /* invalid arguments */
    out = SENTINEL;
    const double bad[2] = {0.5, 1.5}, nanv[2] = {0.5, NAN};
    assert_int_equal(igea_redund_reliability_series(0, R, &out), -1);
    assert_int_equal(igea_redund_reliability_series(2, NULL, &out), -2);
    assert_int_equal(igea_redund_reliability_series(2, R, NULL), -3);
    assert_int_equal(igea_redund_reliability_series(2, bad, &out), -2);
    assert_int_equal(igea_redund_reliability_series(2, nanv, &out), IGEA_ENONFINITE);
    assert_int_equal(igea_redund_reliability_parallel(0, R, &out), -1);
    assert_int_equal(igea_redund_reliability_parallel(2, NULL, &out), -2);
    assert_int_equal(igea_redund_reliability_parallel(2, R, NULL), -3);
    assert_int_equal(igea_redund_reliability_parallel(2, bad, &out), -2);
    assert_int_equal(igea_redund_reliability_parallel(2, nanv, &out), IGEA_ENONFINITE);
    assert_int_equal(igea_redund_reliability_kofn(0, 1, R, &out), -1);
    assert_int_equal(igea_redund_reliability_kofn(2, 0, R, &out), -2);
    assert_int_equal(igea_redund_reliability_kofn(2, 3, R, &out), -2);
    assert_int_equal(igea_redund_reliability_kofn(2, 1, NULL, &out), -3);
    assert_int_equal(igea_redund_reliability_kofn(2, 1, R, NULL), -4);
    assert_int_equal(igea_redund_reliability_kofn(2, 1, bad, &out), -3);
    assert_int_equal(igea_redund_reliability_kofn(2, 1, nanv, &out), IGEA_ENONFINITE);
    assert_true(out == SENTINEL);
}

/* Seed 002's accelerometers as printed in eq. (7), as a block diagram:
 * components X1..X4 (0-3), Y1 Y2 (4, 5), Z1 Z2 (6, 7), D (8). */
static void test_diagram(void **state)
{
    double R[9];
    for (int i = 0; i < 9; i++)
        R[i] = 0.995;
    const int type[6] = {IGEA_REDUND_RBD_PARALLEL, IGEA_REDUND_RBD_PARALLEL,
                         IGEA_REDUND_RBD_PARALLEL, IGEA_REDUND_RBD_SERIES,
                         IGEA_REDUND_RBD_PARALLEL, IGEA_REDUND_RBD_SERIES};
    /* b0 = X1..X4, b1 = Y pair, b2 = Z pair, b3 = b1 b2, b4 = D || b3,
     * b5 = b0 b4 */
    const int first[7] = {0, 4, 6, 8, 10, 12, 14};
    const int member[14] = {0, 1, 2, 3, 4, 5, 6, 7, 9 + 1, 9 + 2, 8, 9 + 3, 9 + 0, 9 + 4};
    double Rb[6];
    assert_int_equal(igea_redund_diagram(9, R, 6, type, NULL, first, member, Rb), 0);
    assert_close(Rb[5], 0.999999749378, 1e-12); /* METHODS 3.1 table */
    double q = 0.005;
    assert_close(Rb[5], (1 - pow(q, 4)) * (1 - q * (1 - pow(1 - q * q, 2))), 1e-15);
    /* 2-of-3 block over a series block */
    const double r2[4] = {0.9, 0.8, 0.7, 0.6};
    const int t2[2] = {IGEA_REDUND_RBD_SERIES, IGEA_REDUND_RBD_KOFN};
    const int k2[2] = {0, 2};
    const int f2[3] = {0, 2, 5};
    const int m2[5] = {0, 1, 2, 3, 4 + 0};
    assert_int_equal(igea_redund_diagram(4, r2, 2, t2, k2, f2, m2, Rb), 0);
    double a = 0.72, b = 0.7, c = 0.6;
    assert_close(Rb[0], a, 1e-15);
    assert_close(Rb[1], a * b * c + a * b * (1 - c) + a * (1 - b) * c + (1 - a) * b * c, 1e-14);
    /* invalid arguments */
    fill_sentinel(Rb, 6);
    const int mreuse[5] = {0, 1, 2, 3, 0};
    const int mfwd[5] = {0, 1, 2, 3, 4 + 1};
    const int fbad[3] = {0, 2, 2};
    const int f0[3] = {1, 2, 5};
    const int tbad[2] = {IGEA_REDUND_RBD_SERIES, 7};
    const int kbad[2] = {0, 4};
    const double rbad[4] = {0.9, 0.8, -0.1, 0.6}, rnan[4] = {0.9, NAN, 0.7, 0.6};
    assert_int_equal(igea_redund_diagram(0, r2, 2, t2, k2, f2, m2, Rb), -1);
    assert_int_equal(igea_redund_diagram(4, NULL, 2, t2, k2, f2, m2, Rb), -2);
    assert_int_equal(igea_redund_diagram(4, rbad, 2, t2, k2, f2, m2, Rb), -2);
    assert_int_equal(igea_redund_diagram(4, rnan, 2, t2, k2, f2, m2, Rb), IGEA_ENONFINITE);
    assert_int_equal(igea_redund_diagram(4, r2, 0, t2, k2, f2, m2, Rb), -3);
    assert_int_equal(igea_redund_diagram(4, r2, 2, NULL, k2, f2, m2, Rb), -4);
    assert_int_equal(igea_redund_diagram(4, r2, 2, tbad, k2, f2, m2, Rb), -4);
    assert_int_equal(igea_redund_diagram(4, r2, 2, t2, NULL, f2, m2, Rb), -5);
    assert_int_equal(igea_redund_diagram(4, r2, 2, t2, kbad, f2, m2, Rb), -5);
    assert_int_equal(igea_redund_diagram(4, r2, 2, t2, k2, NULL, m2, Rb), -6);
    assert_int_equal(igea_redund_diagram(4, r2, 2, t2, k2, fbad, m2, Rb), -6);
    assert_int_equal(igea_redund_diagram(4, r2, 2, t2, k2, f0, m2, Rb), -6);
    assert_int_equal(igea_redund_diagram(4, r2, 2, t2, k2, f2, NULL, Rb), -7);
    assert_int_equal(igea_redund_diagram(4, r2, 2, t2, k2, f2, mreuse, Rb), -7);
    assert_int_equal(igea_redund_diagram(4, r2, 2, t2, k2, f2, mfwd, Rb), -7);
    assert_int_equal(igea_redund_diagram(4, r2, 2, t2, k2, f2, m2, NULL), -8);
    assert_true(all_sentinel(Rb, 6));
}

static void test_seed002(void **state)
{
    double out[IGEA_REDUND_SEED002_LEN];
    assert_int_equal(igea_redund_seed002(0.992, 0.995, out), 0);
    /* METHODS 3.1 table and 3.2, to the digits printed */
    assert_close_abs(out[IGEA_REDUND_SEED002_NONREDUND], 0.9616217080, 0, 5e-11);
    assert_close_abs(out[IGEA_REDUND_SEED002_SYS_NO_D], 0.9997580219, 0, 5e-11);
    assert_close_abs(out[IGEA_REDUND_SEED002_SYS_EQ7], 0.9998077617, 0, 5e-11);
    assert_close_abs(out[IGEA_REDUND_SEED002_SYS_EXACT], 0.9998077611, 0, 5e-11);
    assert_close_abs(out[IGEA_REDUND_SEED002_GYRO], 0.999808012288, 0, 5e-13);
    assert_close_abs(out[IGEA_REDUND_SEED002_ACC_EQ7], 0.999999749378, 0, 5e-13);
    assert_close_abs(out[IGEA_REDUND_SEED002_ACC_EXACT], 0.999999748756, 0, 5e-13);
    /* eq. (7) overstates the exact value by exactly q^4 Re2 */
    assert_close(out[IGEA_REDUND_SEED002_ACC_EQ7] - out[IGEA_REDUND_SEED002_ACC_EXACT],
                 (1 - pow(0.005, 4)) * pow(0.005, 4) * 0.995, 1e-6);
    fill_sentinel(out, IGEA_REDUND_SEED002_LEN);
    assert_int_equal(igea_redund_seed002(1.2, 0.995, out), -1);
    assert_int_equal(igea_redund_seed002(NAN, 0.995, out), -1);
    assert_int_equal(igea_redund_seed002(0.9, -0.1, out), -2);
    assert_int_equal(igea_redund_seed002(0.9, 0.9, NULL), -3);
    assert_true(all_sentinel(out, IGEA_REDUND_SEED002_LEN));
}

/* ---- geometry ----------------------------------------------------------- */

/* Independent brute force: sensor subsets, rank 3 iff some triple has
 * |det| > 1e-9 (unit axes). */
static double brute_span(int n, const double *ax /* n x 3, ld n */, const double *R)
{
    double tot = 0.0;
    for (int mask = 0; mask < (1 << n); mask++) {
        double w = 1.0;
        int idx[32], c = 0;
        for (int k = 0; k < n; k++)
            if (mask & (1 << k)) {
                w *= R[k];
                idx[c++] = k;
            } else {
                w *= 1.0 - R[k];
            }
        int ok = 0;
        for (int a = 0; a < c && !ok; a++)
            for (int b = a + 1; b < c && !ok; b++)
                for (int e = b + 1; e < c && !ok; e++) {
                    const double *u0 = ax + idx[a], *u1 = ax + idx[b], *u2 = ax + idx[e];
                    double det = u0[0] * (u1[n] * u2[2 * n] - u1[2 * n] * u2[n]) -
                                 u0[n] * (u1[0] * u2[2 * n] - u1[2 * n] * u2[0]) +
                                 u0[2 * n] * (u1[0] * u2[n] - u1[n] * u2[0]);
                    if (fabs(det) > 1e-9)
                        ok = 1;
                }
        if (ok)
            tot += w;
    }
    return tot;
}

static void set_axis(double *ax, int ld, int k, double x, double y, double z)
{
    ax[k] = x;
    ax[k + ld] = y;
    ax[k + 2 * ld] = z;
}

static void test_geometry_seed(void **state)
{
    /* the 9 accelerometers: X x4, Y x2, Z x2, D in YOZ at 45 deg */
    double ax[9 * 3], R[9], out[IGEA_REDUND_GEOM_LEN];
    for (int k = 0; k < 4; k++)
        set_axis(ax, 9, k, 2.0, 0, 0); /* not unit: normalised inside */
    set_axis(ax, 9, 4, 0, 1, 0);
    set_axis(ax, 9, 5, 0, -1, 0); /* antiparallel is the same class */
    set_axis(ax, 9, 6, 0, 0, 1);
    set_axis(ax, 9, 7, 0, 0, 1);
    set_axis(ax, 9, 8, 0, S2, S2);
    for (int k = 0; k < 9; k++)
        R[k] = 0.995;
    assert_int_equal(igea_redund_geometry(9, ax, 9, R, 1, out), 0);
    assert_close_abs(out[IGEA_REDUND_GEOM_SPAN], 0.999999748756, 0, 5e-13);
    double q = 0.005, a = 1 - q * q;
    assert_close(out[IGEA_REDUND_GEOM_SPAN], (1 - pow(q, 4)) * (a * a + 2 * a * (1 - a) * 0.995), 1e-14);
    assert_close(out[IGEA_REDUND_GEOM_CLASSES], 4.0, 0);
    double unit[27];
    memcpy(unit, ax, sizeof unit);
    for (int k = 0; k < 4; k++)
        unit[k] = 1.0;
    assert_close(brute_span(9, unit, R), out[IGEA_REDUND_GEOM_SPAN], 1e-14);
    /* detect <= span, isolate <= detect; all nine healthy is isolable
     * (METHODS 3.2 extension), so isolate >= R^9 */
    assert_true(out[IGEA_REDUND_GEOM_DETECT] <= out[IGEA_REDUND_GEOM_SPAN]);
    assert_true(out[IGEA_REDUND_GEOM_ISOLATE] <= out[IGEA_REDUND_GEOM_DETECT]);
    assert_true(out[IGEA_REDUND_GEOM_ISOLATE] >= pow(0.995, 9));
    /* the gyros: 2 per axis; detection needs all six (a lone survivor of a
     * pair is essential), isolation never possible (a pair's parity columns
     * are antiparallel) */
    double g[6 * 3], Rg[6];
    for (int k = 0; k < 6; k++) {
        set_axis(g, 6, k, k / 2 == 0, k / 2 == 1, k / 2 == 2);
        Rg[k] = 0.992;
    }
    assert_int_equal(igea_redund_geometry(6, g, 6, Rg, 1, out), 0);
    assert_close_abs(out[IGEA_REDUND_GEOM_SPAN], 0.999808012288, 0, 5e-13);
    assert_close(out[IGEA_REDUND_GEOM_DETECT], pow(0.992, 6), 1e-13);
    assert_true(out[IGEA_REDUND_GEOM_ISOLATE] == 0.0);
    assert_int_equal(igea_redund_geometry(6, g, 6, Rg, 0, out), 0);
    assert_true(isnan(out[IGEA_REDUND_GEOM_DETECT]) && isnan(out[IGEA_REDUND_GEOM_ISOLATE]));
}

static void test_geometry_cone(void **state)
{
    /* 5 and 6 axes on a cone (half-angle 54.7356 deg): no three coplanar */
    for (int n = 4; n <= 6; n++) {
        double ax[6 * 3], R[6], out[IGEA_REDUND_GEOM_LEN];
        double c = 1.0 / sqrt(3.0), s = sqrt(2.0 / 3.0);
        for (int k = 0; k < n; k++) {
            double az = 2.0 * PI_ * k / n + 0.1 * k * k;
            set_axis(ax, n, k, s * cos(az), s * sin(az), c);
            R[k] = 0.9 + 0.01 * k;
        }
        assert_int_equal(igea_redund_geometry(n, ax, n, R, 1, out), 0);
        double k3, k4, all;
        igea_redund_reliability_kofn(n, 3, R, &k3);
        igea_redund_reliability_kofn(n, 4, R, &k4);
        igea_redund_reliability_series(n, R, &all);
        assert_close(out[IGEA_REDUND_GEOM_SPAN], k3, 1e-13);
        assert_close(out[IGEA_REDUND_GEOM_SPAN], brute_span(n, ax, R), 1e-13);
        assert_close(out[IGEA_REDUND_GEOM_DETECT], k4, 1e-13);
        if (n == 4) /* one parity relation: columns all parallel */
            assert_true(out[IGEA_REDUND_GEOM_ISOLATE] == 0.0);
        else if (n == 5) /* isolation needs all five */
            assert_close(out[IGEA_REDUND_GEOM_ISOLATE], all, 1e-13);
        else { /* needs at least five (any five on the cone isolate) */
            double k5;
            igea_redund_reliability_kofn(n, 5, R, &k5);
            assert_close(out[IGEA_REDUND_GEOM_ISOLATE], k5, 1e-13);
        }
    }
}

static void test_geometry_args(void **state)
{
    double ax[5 * 3], R[4] = {0.9, 0.9, 0.9, 0.9}, out[IGEA_REDUND_GEOM_LEN];
    fill_nan(ax, 15); /* ld 5 > n = 4: the padding row is NaN */
    set_axis(ax, 5, 0, 1, 0, 0);
    set_axis(ax, 5, 1, 0, 1, 0);
    set_axis(ax, 5, 2, 0, 0, 1);
    set_axis(ax, 5, 3, 1, 1, 1);
    assert_int_equal(igea_redund_geometry(4, ax, 5, R, 1, out), 0);
    assert_close(out[IGEA_REDUND_GEOM_SPAN], 4 * pow(0.9, 3) * 0.1 + pow(0.9, 4), 1e-14);
    assert_close(out[IGEA_REDUND_GEOM_DETECT], pow(0.9, 4), 1e-14);
    fill_sentinel(out, IGEA_REDUND_GEOM_LEN);
    double Rb[4] = {0.9, 1.1, 0.9, 0.9};
    assert_int_equal(igea_redund_geometry(0, ax, 5, R, 1, out), -1);
    assert_int_equal(igea_redund_geometry(21, ax, 21, R, 1, out), -1);
    assert_int_equal(igea_redund_geometry(4, NULL, 5, R, 1, out), -2);
    assert_int_equal(igea_redund_geometry(4, ax, 3, R, 1, out), -3);
    assert_int_equal(igea_redund_geometry(4, ax, 5, NULL, 1, out), -4);
    assert_int_equal(igea_redund_geometry(4, ax, 5, Rb, 1, out), -4);
    assert_int_equal(igea_redund_geometry(4, ax, 5, R, 2, out), -5);
    assert_int_equal(igea_redund_geometry(4, ax, 5, R, 1, NULL), -6);
    Rb[1] = NAN;
    assert_int_equal(igea_redund_geometry(4, ax, 5, Rb, 1, out), IGEA_ENONFINITE);
    set_axis(ax, 5, 2, 0, 0, 0);
    assert_int_equal(igea_redund_geometry(4, ax, 5, R, 1, out), IGEA_EDOMAIN);
    ax[2] = NAN;
    assert_int_equal(igea_redund_geometry(4, ax, 5, R, 1, out), IGEA_ENONFINITE);
    assert_true(all_sentinel(out, IGEA_REDUND_GEOM_LEN));
}

/* ---- consistency -------------------------------------------------------- */

static const double TV_X[4] = {1.000010, 1.000018, 0.999995, 1.000004};
static const double TV_S[4] = {20e-6, 20e-6, 20e-6, 20e-6};

static void test_confidence_distance(void **state)
{
    /* METHODS 3.3 test vector, padded ld 5 */
    double D[5 * 4];
    fill_nan(D, 20);
    assert_int_equal(igea_redund_confidence_distance(4, TV_X, TV_S, D, 5), 0);
    const double want[4][4] = {{0, .3108, .5467, .2358},
                               {.3108, 0, .7499, .5161},
                               {.5467, .7499, 0, .3473},
                               {.2358, .5161, .3473, 0}};
    for (int i = 0; i < 4; i++) {
        assert_true(isnan(D[4 + 5 * i])); /* padding untouched */
        for (int j = 0; j < 4; j++)
            assert_close_abs(D[i + 5 * j], want[i][j], 0, 5e-5);
    }
    /* (12) by numerical integration (Simpson) equals (13); unequal sigmas
     * make D asymmetric */
    const double x[3] = {0.3, -1.1, 2.0}, s[3] = {0.5, 1.7, 0.9};
    double D3[9];
    assert_int_equal(igea_redund_confidence_distance(3, x, s, D3, 3), 0);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int nst = 2000;
            double a = x[i], b = x[j], h = (b - a) / nst, sum = 0.0;
            for (int k = 0; k <= nst; k++) {
                double t = a + k * h, wgt = (k == 0 || k == nst) ? 1 : (k % 2 ? 4 : 2);
                sum += wgt * exp(-(t - x[i]) * (t - x[i]) / (2 * s[i] * s[i])) /
                       (sqrt(2 * PI_) * s[i]);
            }
            assert_close_abs(D3[i + 3 * j], fabs(2.0 * sum * h / 3.0), 1e-10, 1e-13);
        }
    assert_true(fabs(D3[1] - D3[3]) > 0.1);
    /* invalid */
    double Dx[16];
    fill_sentinel(Dx, 16);
    const double xn[4] = {1, NAN, 1, 1}, s0[4] = {1, 0, 1, 1}, sn[4] = {1, 1, NAN, 1};
    assert_int_equal(igea_redund_confidence_distance(0, TV_X, TV_S, Dx, 4), -1);
    assert_int_equal(igea_redund_confidence_distance(4, NULL, TV_S, Dx, 4), -2);
    assert_int_equal(igea_redund_confidence_distance(4, TV_X, NULL, Dx, 4), -3);
    assert_int_equal(igea_redund_confidence_distance(4, TV_X, TV_S, NULL, 4), -4);
    assert_int_equal(igea_redund_confidence_distance(4, TV_X, TV_S, Dx, 3), -5);
    assert_int_equal(igea_redund_confidence_distance(4, xn, TV_S, Dx, 4), IGEA_ENONFINITE);
    assert_int_equal(igea_redund_confidence_distance(4, TV_X, s0, Dx, 4), IGEA_ENONPOSITIVE);
    assert_int_equal(igea_redund_confidence_distance(4, TV_X, sn, Dx, 4), IGEA_ENONFINITE);
    assert_true(all_sentinel(Dx, 16));
}

static void test_thresholds_relation(void **state)
{
    double D[16], delta[16], alpha = 0.7;
    int r[16], r2[16];
    igea_redund_confidence_distance(4, TV_X, TV_S, D, 4);
    assert_int_equal(igea_redund_thresholds(4, TV_S, &alpha, 0, delta, 4), 0);
    assert_close(delta[1], sqrt(2.0) * 20e-6 * 0.73286907795921685, 1e-15);
    assert_int_equal(igea_redund_relation(4, D, 4, &alpha, 0, r, 4), 0);
    assert_int_equal(igea_redund_relation_delta(4, TV_X, delta, 4, r2, 4), 0);
    const int want[16] = {1, 1, 1, 1, 1, 1, 0, 1, 1, 0, 1, 1, 1, 1, 1, 1};
    for (int i = 0; i < 16; i++) {
        assert_int_equal(r[i], want[i]);
        assert_int_equal(r2[i], want[i]);
    }
    /* a full alpha matrix with ld 5 and NaN padding: alpha_23 = 0.76 lets
     * sensor 2 (0-based 1) support 3 */
    double A[20];
    fill_nan(A, 20);
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++)
            A[i + 5 * j] = 0.7;
    A[1 + 5 * 2] = 0.76;
    assert_int_equal(igea_redund_relation(4, D, 4, A, 5, r, 4), 0);
    assert_int_equal(r[1 + 4 * 2], 1);
    assert_int_equal(r[2 + 4 * 1], 0);
    assert_int_equal(igea_redund_thresholds(4, TV_S, A, 5, delta, 4), 0);
    assert_int_equal(igea_redund_relation_delta(4, TV_X, delta, 4, r2, 4), 0);
    for (int i = 0; i < 16; i++)
        assert_int_equal(r[i], r2[i]);
    /* a scalar delta (ldd 0) */
    double d1 = 1e-5;
    assert_int_equal(igea_redund_relation_delta(4, TV_X, &d1, 0, r2, 4), 0);
    assert_int_equal(r2[0 + 4 * 1], 1); /* |18 - 10| <= 10 */
    assert_int_equal(r2[1 + 4 * 2], 0); /* 23 > 10 */
    /* invalid */
    int rs[16];
    for (int i = 0; i < 16; i++)
        rs[i] = -7;
    double ab = 1.0, an = NAN, Dbad[16];
    memcpy(Dbad, D, sizeof D);
    Dbad[5] = 1.5;
    fill_sentinel(delta, 16);
    assert_int_equal(igea_redund_thresholds(0, TV_S, &alpha, 0, delta, 4), -1);
    assert_int_equal(igea_redund_thresholds(4, NULL, &alpha, 0, delta, 4), -2);
    assert_int_equal(igea_redund_thresholds(4, TV_S, NULL, 0, delta, 4), -3);
    assert_int_equal(igea_redund_thresholds(4, TV_S, &ab, 0, delta, 4), -3);
    assert_int_equal(igea_redund_thresholds(4, TV_S, &an, 0, delta, 4), IGEA_ENONFINITE);
    assert_int_equal(igea_redund_thresholds(4, TV_S, A, 3, delta, 4), -4);
    assert_int_equal(igea_redund_thresholds(4, TV_S, &alpha, 0, NULL, 4), -5);
    assert_int_equal(igea_redund_thresholds(4, TV_S, &alpha, 0, delta, 3), -6);
    assert_true(all_sentinel(delta, 16));
    assert_int_equal(igea_redund_relation(0, D, 4, &alpha, 0, rs, 4), -1);
    assert_int_equal(igea_redund_relation(4, NULL, 4, &alpha, 0, rs, 4), -2);
    assert_int_equal(igea_redund_relation(4, Dbad, 4, &alpha, 0, rs, 4), -2);
    assert_int_equal(igea_redund_relation(4, D, 3, &alpha, 0, rs, 4), -3);
    assert_int_equal(igea_redund_relation(4, D, 4, NULL, 0, rs, 4), -4);
    assert_int_equal(igea_redund_relation(4, D, 4, &ab, 0, rs, 4), -4);
    assert_int_equal(igea_redund_relation(4, D, 4, A, 2, rs, 4), -5);
    assert_int_equal(igea_redund_relation(4, D, 4, &alpha, 0, NULL, 4), -6);
    assert_int_equal(igea_redund_relation(4, D, 4, &alpha, 0, rs, 3), -7);
    Dbad[5] = NAN;
    assert_int_equal(igea_redund_relation(4, Dbad, 4, &alpha, 0, rs, 4), IGEA_ENONFINITE);
    double dneg = -1.0, xn[4] = {1, 1, NAN, 1};
    assert_int_equal(igea_redund_relation_delta(0, TV_X, &d1, 0, rs, 4), -1);
    assert_int_equal(igea_redund_relation_delta(4, NULL, &d1, 0, rs, 4), -2);
    assert_int_equal(igea_redund_relation_delta(4, TV_X, NULL, 0, rs, 4), -3);
    assert_int_equal(igea_redund_relation_delta(4, TV_X, &dneg, 0, rs, 4), -3);
    assert_int_equal(igea_redund_relation_delta(4, TV_X, &an, 0, rs, 4), IGEA_ENONFINITE);
    assert_int_equal(igea_redund_relation_delta(4, TV_X, delta, 2, rs, 4), -4);
    assert_int_equal(igea_redund_relation_delta(4, TV_X, &d1, 0, NULL, 4), -5);
    assert_int_equal(igea_redund_relation_delta(4, TV_X, &d1, 0, rs, 2), -6);
    assert_int_equal(igea_redund_relation_delta(4, xn, &d1, 0, rs, 4), IGEA_ENONFINITE);
    for (int i = 0; i < 16; i++)
        assert_int_equal(rs[i], -7);
}

static void test_fusion_set(void **state)
{
    double D[16], alpha = 0.7, x[4];
    int keep[4], sup[4];
    igea_redund_confidence_distance(4, TV_X, TV_S, D, 4);
    assert_int_equal(igea_redund_fusion_set(4, D, 4, &alpha, 0, 1, keep, sup), 0);
    for (int i = 0; i < 4; i++)
        assert_int_equal(keep[i], 1);
    const int sup0[4] = {3, 2, 2, 3};
    for (int i = 0; i < 4; i++)
        assert_int_equal(sup[i], sup0[i]);
    /* the fault injection: Ax4 + 10 mg */
    memcpy(x, TV_X, sizeof x);
    x[3] += 0.010;
    igea_redund_confidence_distance(4, x, TV_S, D, 4);
    for (int i = 0; i < 3; i++)
        assert_close(D[i + 4 * 3], 1.0, 1e-15);
    assert_int_equal(igea_redund_fusion_set(4, D, 4, &alpha, 0, 1, keep, sup), 0);
    const int keep1[4] = {1, 1, 1, 0}, sup1[4] = {2, 1, 1, 0};
    for (int i = 0; i < 4; i++) {
        assert_int_equal(keep[i], keep1[i]);
        assert_int_equal(sup[i], sup1[i]);
    }
    assert_int_equal(igea_redund_fusion_set(4, D, 4, &alpha, 0, 0, keep, NULL), 0);
    const int keep0[4] = {1, 0, 0, 0}; /* one shot keeps only sensor 1 */
    for (int i = 0; i < 4; i++)
        assert_int_equal(keep[i], keep0[i]);
    /* ties: two sensors that disagree with equal sigma: the higher index
     * goes; with unequal sigma the one whose column sum of D is larger */
    const double x2[2] = {0.0, 1.0}, s2[2] = {0.1, 0.1}, s3[2] = {0.1, 0.5};
    double D2[4];
    igea_redund_confidence_distance(2, x2, s2, D2, 2);
    assert_int_equal(igea_redund_fusion_set(2, D2, 2, &alpha, 0, 1, keep, NULL), 0);
    assert_true(keep[0] == 1 && keep[1] == 0);
    igea_redund_confidence_distance(2, x2, s3, D2, 2);
    /* column 0 holds d_10 (sigma 0.5: 0.954), column 1 d_01 (sigma 0.1: 1) */
    assert_int_equal(igea_redund_fusion_set(2, D2, 2, &alpha, 0, 1, keep, NULL), 0);
    assert_true(keep[0] == 1 && keep[1] == 0);
    D2[1] = 0.9999999;
    D2[2] = 0.5; /* 0 supports 1 now; 1 does not support 0 */
    assert_int_equal(igea_redund_fusion_set(2, D2, 2, &alpha, 0, 1, keep, NULL), 0);
    assert_true(keep[0] == 0 && keep[1] == 1);
    /* a single sensor is its own fusion set */
    double d1 = 0.0;
    assert_int_equal(igea_redund_fusion_set(1, &d1, 1, &alpha, 0, 1, keep, sup), 0);
    assert_true(keep[0] == 1 && sup[0] == 0);
    /* invalid */
    int ks[4] = {-5, -5, -5, -5};
    double ab = 0.0;
    assert_int_equal(igea_redund_fusion_set(0, D, 4, &alpha, 0, 1, ks, NULL), -1);
    assert_int_equal(igea_redund_fusion_set(4, NULL, 4, &alpha, 0, 1, ks, NULL), -2);
    assert_int_equal(igea_redund_fusion_set(4, D, 3, &alpha, 0, 1, ks, NULL), -3);
    assert_int_equal(igea_redund_fusion_set(4, D, 4, NULL, 0, 1, ks, NULL), -4);
    assert_int_equal(igea_redund_fusion_set(4, D, 4, &ab, 0, 1, ks, NULL), -4);
    assert_int_equal(igea_redund_fusion_set(4, D, 4, &alpha, 1, 1, ks, NULL), -5);
    assert_int_equal(igea_redund_fusion_set(4, D, 4, &alpha, 0, 2, ks, NULL), -6);
    assert_int_equal(igea_redund_fusion_set(4, D, 4, &alpha, 0, 1, NULL, NULL), -7);
    D[6] = NAN;
    assert_int_equal(igea_redund_fusion_set(4, D, 4, &alpha, 0, 1, ks, NULL), IGEA_ENONFINITE);
    D[6] = -0.5;
    assert_int_equal(igea_redund_fusion_set(4, D, 4, &alpha, 0, 1, ks, NULL), -2);
    for (int i = 0; i < 4; i++)
        assert_int_equal(ks[i], -5);
}

static void test_fuse(void **state)
{
    double v = SENTINEL, s = SENTINEL;
    assert_int_equal(igea_redund_fuse(4, TV_X, TV_S, NULL, 1, &v, &s), 0);
    assert_close_abs(v, 1.0000068, 0, 5e-8); /* METHODS 3.3 */
    assert_close(v, (TV_X[0] + TV_X[1] + TV_X[2] + TV_X[3]) / 4, 1e-15);
    assert_close(s, 10e-6, 1e-14);
    double x[4];
    memcpy(x, TV_X, sizeof x);
    x[3] += 0.010;
    const int keep[4] = {1, 1, 1, 0};
    assert_int_equal(igea_redund_fuse(4, x, TV_S, keep, 1, &v, NULL), 0);
    assert_close_abs(v, 1.0000077, 0, 5e-8);
    /* unequal sigmas: inverse-variance weights vs average */
    const double xs[3] = {1.0, 2.0, 4.0}, ss[3] = {1.0, 2.0, 4.0};
    assert_int_equal(igea_redund_fuse(3, xs, ss, NULL, 1, &v, &s), 0);
    double w0 = 1, w1 = 0.25, w2 = 1.0 / 16;
    assert_close(v, (w0 * 1 + w1 * 2 + w2 * 4) / (w0 + w1 + w2), 1e-15);
    assert_close(s, 1.0 / sqrt(w0 + w1 + w2), 1e-15);
    assert_int_equal(igea_redund_fuse(3, xs, ss, NULL, 0, &v, &s), 0);
    assert_close(v, 7.0 / 3.0, 1e-15);
    assert_close(s, sqrt(21.0) / 3.0, 1e-15);
    /* invalid */
    const int none[3] = {0, 0, 0};
    const double xn[3] = {1, NAN, 2}, s0[3] = {1, -1, 1};
    v = SENTINEL;
    s = SENTINEL;
    assert_int_equal(igea_redund_fuse(0, xs, ss, NULL, 1, &v, &s), -1);
    assert_int_equal(igea_redund_fuse(3, NULL, ss, NULL, 1, &v, &s), -2);
    assert_int_equal(igea_redund_fuse(3, xs, NULL, NULL, 1, &v, &s), -3);
    assert_int_equal(igea_redund_fuse(3, xs, ss, NULL, 3, &v, &s), -5);
    assert_int_equal(igea_redund_fuse(3, xs, ss, NULL, 1, NULL, &s), -6);
    assert_int_equal(igea_redund_fuse(3, xn, ss, NULL, 1, &v, &s), IGEA_ENONFINITE);
    assert_int_equal(igea_redund_fuse(3, xs, s0, NULL, 1, &v, &s), IGEA_ENONPOSITIVE);
    assert_int_equal(igea_redund_fuse(3, xs, ss, none, 1, &v, &s), IGEA_EEMPTY);
    assert_true(v == SENTINEL && s == SENTINEL);
}

static void test_false_alarm(void **state)
{
    /* METHODS 3.3 table, alpha 0.7, sigma_i = k sigma_e */
    double p = SENTINEL;
    assert_int_equal(igea_redund_false_alarm(1.0, 1.0, 1.0, 0.7, &p), 0);
    assert_close_abs(p, 0.464, 0, 5e-4);
    assert_int_equal(igea_redund_false_alarm(3.0, 1.0, 1.0, 0.7, &p), 0);
    assert_close_abs(p, 0.028, 0, 5e-4);
    assert_int_equal(igea_redund_false_alarm(4.5e-6, 1e-6, 1e-6, 0.7, &p), 0);
    assert_close_abs(p, 9.7e-4, 0, 5e-6);
    /* closed form 1 - erf(k erfinv(alpha) / sqrt2), unequal noises */
    assert_int_equal(igea_redund_false_alarm(2.0, 1.0, 2.0, 0.9, &p), 0);
    double ei;
    igea_stats_erfinv(0.9, &ei);
    assert_close(p, 1.0 - erf(sqrt(2.0) * 2.0 * ei / sqrt(2.0 * 5.0)), 1e-13);
    p = SENTINEL;
    assert_int_equal(igea_redund_false_alarm(0.0, 1, 1, 0.7, &p), -1);
    assert_int_equal(igea_redund_false_alarm(NAN, 1, 1, 0.7, &p), -1);
    assert_int_equal(igea_redund_false_alarm(1, -1, 1, 0.7, &p), -2);
    assert_int_equal(igea_redund_false_alarm(1, 1, 0, 0.7, &p), -3);
    assert_int_equal(igea_redund_false_alarm(1, 1, 1, 1.0, &p), -4);
    assert_int_equal(igea_redund_false_alarm(1, 1, 1, NAN, &p), -4);
    assert_int_equal(igea_redund_false_alarm(1, 1, 1, 0.7, NULL), -5);
    assert_true(p == SENTINEL);
}

static void test_transform(void **state)
{
    /* group 0: identity; group 1: 90 deg about z (x -> y) */
    const double C[18] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, -1, 0, 0, 0, 0, 1};
    const double v[6] = {1, 2, 3, 1, 2, 3};
    double out[6];
    assert_int_equal(igea_redund_transform(2, C, v, out), 0);
    const double want[6] = {1, 2, 3, -2, 1, 3};
    for (int i = 0; i < 6; i++)
        assert_close_abs(out[i], want[i], 0, 1e-15);
    fill_sentinel(out, 6);
    double Cn[18];
    memcpy(Cn, C, sizeof C);
    Cn[4] = NAN;
    assert_int_equal(igea_redund_transform(0, C, v, out), -1);
    assert_int_equal(igea_redund_transform(2, NULL, v, out), -2);
    assert_int_equal(igea_redund_transform(2, C, NULL, out), -3);
    assert_int_equal(igea_redund_transform(2, C, v, NULL), -4);
    assert_int_equal(igea_redund_transform(2, Cn, v, out), IGEA_ENONFINITE);
    assert_true(all_sentinel(out, 6));
}

/* ---- parity space ------------------------------------------------------- */

/* 6 axes on a cone: m x 3, ld ldh */
static void cone6(double *H, int ldh)
{
    double c = 1.0 / sqrt(3.0), s = sqrt(2.0 / 3.0);
    for (int k = 0; k < 6; k++) {
        double az = 2.0 * PI_ * k / 6.0 + 0.1 * k * k;
        set_axis(H, ldh, k, s * cos(az), s * sin(az), c);
    }
}

static void test_parity(void **state)
{
    double H[7 * 3], V[4 * 6];
    fill_nan(H, 21);
    fill_nan(V, 24);
    cone6(H, 7);
    assert_int_equal(igea_redund_parity(6, 3, H, 7, V, 4), 0);
    for (int r = 0; r < 3; r++) {
        assert_true(isnan(V[3 + 4 * r])); /* padding row untouched */
        /* V H = 0 */
        for (int c = 0; c < 3; c++) {
            double s = 0;
            for (int i = 0; i < 6; i++)
                s += V[r + 4 * i] * H[i + 7 * c];
            assert_close_abs(s, 0.0, 0, 1e-14);
        }
        /* orthonormal rows, largest entry positive */
        int imax = 0;
        for (int i = 0; i < 6; i++)
            if (fabs(V[r + 4 * i]) > fabs(V[r + 4 * imax]))
                imax = i;
        assert_true(V[r + 4 * imax] > 0);
        for (int r2 = 0; r2 < 3; r2++) {
            double s = 0;
            for (int i = 0; i < 6; i++)
                s += V[r + 4 * i] * V[r2 + 4 * i];
            assert_close_abs(s, r == r2 ? 1.0 : 0.0, 0, 1e-14);
        }
    }
    /* the YZ plane of seed 002: Y1 Y2 Z1 Z2 D, q = 2: the parity space
     * holds a_D - (a_y + a_z)/sqrt2 */
    double Hp[5 * 2] = {1, 1, 0, 0, S2, 0, 0, 1, 1, S2}, Vp[3 * 5];
    assert_int_equal(igea_redund_parity(5, 2, Hp, 5, Vp, 3), 0);
    const double rel[5] = {-0.5 * S2, -0.5 * S2, -0.5 * S2, -0.5 * S2, 1.0};
    /* rel is orthogonal to range(H): its projection on the rows of Vp
     * restores it */
    for (int i = 0; i < 5; i++) {
        double s = 0;
        for (int r = 0; r < 3; r++) {
            double c = 0;
            for (int k = 0; k < 5; k++)
                c += Vp[r + 3 * k] * rel[k];
            s += c * Vp[r + 3 * i];
        }
        assert_close_abs(s, rel[i], 0, 1e-14);
    }
    /* rank deficient: all axes in a plane */
    double Hr[4 * 3] = {1, 0, 1, 1, 0, 1, 1, 2, 0, 0, 0, 0};
    fill_sentinel(V, 24);
    assert_int_equal(igea_redund_parity(4, 3, Hr, 4, V, 1), IGEA_ERANK);
    assert_int_equal(igea_redund_parity(3, 3, H, 7, V, 4), -1);
    assert_int_equal(igea_redund_parity(6, 0, H, 7, V, 4), -2);
    assert_int_equal(igea_redund_parity(6, 3, NULL, 7, V, 4), -3);
    assert_int_equal(igea_redund_parity(6, 3, H, 5, V, 4), -4);
    assert_int_equal(igea_redund_parity(6, 3, H, 7, NULL, 4), -5);
    assert_int_equal(igea_redund_parity(6, 3, H, 7, V, 2), -6);
    H[2] = NAN;
    assert_int_equal(igea_redund_parity(6, 3, H, 7, V, 4), IGEA_ENONFINITE);
    assert_true(all_sentinel(V, 24));
}

static void test_fdi(void **state)
{
    double H[6 * 3], y[6], sig[6], info[IGEA_REDUND_FDI_LEN], par[3];
    int iso = -9;
    cone6(H, 6);
    const double xt[3] = {0.1, -0.2, 9.8};
    for (int i = 0; i < 6; i++) {
        y[i] = H[i] * xt[0] + H[i + 6] * xt[1] + H[i + 12] * xt[2];
        sig[i] = 1e-3 * (1 + 0.2 * i);
    }
    assert_int_equal(igea_redund_fdi(6, 3, H, 6, y, sig, 0.01, par, info, &iso), 0);
    assert_close_abs(info[IGEA_REDUND_FDI_STAT], 0.0, 0, 1e-20);
    assert_close(info[IGEA_REDUND_FDI_THRESHOLD], 11.344866730144373, 1e-12); /* chi2_0.01(3) */
    assert_close(info[IGEA_REDUND_FDI_DOF], 3.0, 0);
    assert_true(info[IGEA_REDUND_FDI_DETECTED] == 0.0 && iso == -1);
    assert_true(info[IGEA_REDUND_FDI_ISOLATED] == -1.0 && info[IGEA_REDUND_FDI_ISOLABLE] == 1.0);
    /* a bias of 8 sigma on each sensor in turn: detected and isolated, with
     * the statistic (b / sigma_k)^2 P_kk of the whitened projector */
    for (int k = 0; k < 6; k++) {
        double yf[6];
        memcpy(yf, y, sizeof y);
        yf[k] += 8.0 * sig[k];
        assert_int_equal(igea_redund_fdi(6, 3, H, 6, yf, sig, 0.01, par, info, &iso), 0);
        assert_int_equal(iso, k);
        assert_true(info[IGEA_REDUND_FDI_DETECTED] == 1.0);
        double Vw[18];
        double Hw[18];
        for (int c = 0; c < 3; c++)
            for (int i = 0; i < 6; i++)
                Hw[i + 6 * c] = H[i + 6 * c] / sig[i];
        igea_redund_parity(6, 3, Hw, 6, Vw, 3);
        double pkk = 0;
        for (int r = 0; r < 3; r++)
            pkk += Vw[r + 3 * k] * Vw[r + 3 * k];
        assert_close(info[IGEA_REDUND_FDI_STAT], 64.0 * pkk, 1e-10);
        assert_close(info[IGEA_REDUND_FDI_ISO_STAT], 64.0 * pkk, 1e-10);
        double sf;
        igea_stats_chi2_sf(64.0 * pkk, 3.0, &sf);
        assert_close(info[IGEA_REDUND_FDI_P_VALUE], sf, 1e-8);
    }
    /* 4 sensors: detection but no isolation (one parity relation) */
    double H4[12] = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1}, y4[4] = {0, 0, 0, 0.1},
           s4[4] = {1e-3, 1e-3, 1e-3, 1e-3};
    assert_int_equal(igea_redund_fdi(4, 3, H4, 4, y4, s4, 0.001, NULL, info, NULL), 0);
    assert_true(info[IGEA_REDUND_FDI_DETECTED] == 1.0 && info[IGEA_REDUND_FDI_ISOLABLE] == 0.0);
    /* invalid */
    double ys[6];
    memcpy(ys, y, sizeof y);
    fill_sentinel(info, IGEA_REDUND_FDI_LEN);
    fill_sentinel(par, 3);
    iso = -9;
    double sb[6] = {1, 1, 0, 1, 1, 1};
    assert_int_equal(igea_redund_fdi(3, 3, H, 6, y, sig, 0.01, par, info, &iso), -1);
    assert_int_equal(igea_redund_fdi(6, 0, H, 6, y, sig, 0.01, par, info, &iso), -2);
    assert_int_equal(igea_redund_fdi(6, 3, NULL, 6, y, sig, 0.01, par, info, &iso), -3);
    assert_int_equal(igea_redund_fdi(6, 3, H, 5, y, sig, 0.01, par, info, &iso), -4);
    assert_int_equal(igea_redund_fdi(6, 3, H, 6, NULL, sig, 0.01, par, info, &iso), -5);
    assert_int_equal(igea_redund_fdi(6, 3, H, 6, y, NULL, 0.01, par, info, &iso), -6);
    assert_int_equal(igea_redund_fdi(6, 3, H, 6, y, sig, 0.0, par, info, &iso), -7);
    assert_int_equal(igea_redund_fdi(6, 3, H, 6, y, sig, 1.0, par, info, &iso), -7);
    assert_int_equal(igea_redund_fdi(6, 3, H, 6, y, sig, 0.01, par, NULL, &iso), -9);
    assert_int_equal(igea_redund_fdi(6, 3, H, 6, y, sb, 0.01, par, info, &iso), IGEA_ENONPOSITIVE);
    ys[2] = NAN;
    assert_int_equal(igea_redund_fdi(6, 3, H, 6, ys, sig, 0.01, par, info, &iso), IGEA_ENONFINITE);
    assert_true(all_sentinel(info, IGEA_REDUND_FDI_LEN) && all_sentinel(par, 3) && iso == -9);
}

static void test_fdi_yz_plane(void **state)
{
    /* seed 002's YZ plane: Y1 Y2 Z1 Z2 D (q = 2): 3 parity relations, any
     * single fault isolated (METHODS 3.2 extension) */
    double H[10] = {1, 1, 0, 0, S2, 0, 0, 1, 1, S2}, sig[5] = {1e-3, 1e-3, 1e-3, 1e-3, 1e-3};
    double y0[5], info[IGEA_REDUND_FDI_LEN];
    for (int i = 0; i < 5; i++)
        y0[i] = 0.3 * H[i] - 0.2 * H[i + 5];
    for (int k = 0; k < 5; k++) {
        double y[5];
        int iso = -9;
        memcpy(y, y0, sizeof y);
        y[k] += 0.01;
        assert_int_equal(igea_redund_fdi(5, 2, H, 5, y, sig, 0.001, NULL, info, &iso), 0);
        assert_int_equal(iso, k);
        assert_true(info[IGEA_REDUND_FDI_ISOLABLE] == 1.0 && info[IGEA_REDUND_FDI_DOF] == 3.0);
    }
}

static void test_skew_check(void **state)
{
    /* Y1 Y2, Z1 Z2 and D at 45 deg: a_D = (a_y + a_z) / sqrt2 */
    double ay[2] = {0.3, 0.3}, az[2] = {-0.2, -0.2}, s[2] = {1e-3, 1e-3};
    double ad = (0.3 - 0.2) * S2, r[4];
    int fy[2] = {-1, -1}, fz[2] = {-1, -1}, fd = -1;
    assert_int_equal(igea_redund_skew_check(2, ay, s, 2, az, s, ad, 1e-3, S2, S2, 3.0, r, fy, fz, &fd), 0);
    assert_true(fy[0] == 0 && fy[1] == 0 && fz[0] == 0 && fz[1] == 0 && fd == 0);
    for (int i = 0; i < 4; i++)
        assert_close_abs(r[i], 0.0, 0, 1e-15);
    ay[1] += 0.01; /* Y2 faulty: both of its pairs fail */
    assert_int_equal(igea_redund_skew_check(2, ay, s, 2, az, s, ad, 1e-3, S2, S2, 3.0, r, fy, fz, &fd), 0);
    assert_true(fy[0] == 0 && fy[1] == 1 && fz[0] == 0 && fz[1] == 0 && fd == 0);
    assert_close(r[1], -0.01 * S2, 1e-10); /* pi_{Y2,Z1} */
    az[0] += 0.01; /* and Z1: (Y1, Z2) still passes */
    assert_int_equal(igea_redund_skew_check(2, ay, s, 2, az, s, ad, 1e-3, S2, S2, 3.0, NULL, fy, fz, &fd), 0);
    assert_true(fy[0] == 0 && fy[1] == 1 && fz[0] == 1 && fz[1] == 0 && fd == 0);
    ay[1] -= 0.01;
    az[0] -= 0.01; /* D faulty: every pair fails, D is the suspect */
    assert_int_equal(igea_redund_skew_check(2, ay, s, 2, az, s, ad + 0.01, 1e-3, S2, S2, 3.0, NULL, fy, fz, &fd), 0);
    assert_true(fy[0] == 0 && fy[1] == 0 && fz[0] == 0 && fz[1] == 0 && fd == 1);
    /* threshold: |pi| = 3.0 sqrt(s_D^2 + s^2/2 + s^2/2) passes, just above fails */
    double thr = 3.0 * sqrt(2.0) * 1e-3;
    assert_int_equal(igea_redund_skew_check(1, ay, s, 1, az, s, ad + 0.999 * thr, 1e-3, S2, S2, 3.0, NULL, fy, fz, &fd), 0);
    assert_true(fd == 0);
    assert_int_equal(igea_redund_skew_check(1, ay, s, 1, az, s, ad + 1.001 * thr, 1e-3, S2, S2, 3.0, NULL, fy, fz, &fd), 0);
    assert_true(fd == 1);
    /* invalid */
    fy[0] = fy[1] = fz[0] = fz[1] = fd = -7;
    double sb[2] = {1e-3, 0.0}, an[2] = {NAN, 0};
    assert_int_equal(igea_redund_skew_check(0, ay, s, 2, az, s, ad, 1e-3, S2, S2, 3, NULL, fy, fz, &fd), -1);
    assert_int_equal(igea_redund_skew_check(2, NULL, s, 2, az, s, ad, 1e-3, S2, S2, 3, NULL, fy, fz, &fd), -2);
    assert_int_equal(igea_redund_skew_check(2, ay, NULL, 2, az, s, ad, 1e-3, S2, S2, 3, NULL, fy, fz, &fd), -3);
    assert_int_equal(igea_redund_skew_check(2, ay, s, 0, az, s, ad, 1e-3, S2, S2, 3, NULL, fy, fz, &fd), -4);
    assert_int_equal(igea_redund_skew_check(2, ay, s, 2, NULL, s, ad, 1e-3, S2, S2, 3, NULL, fy, fz, &fd), -5);
    assert_int_equal(igea_redund_skew_check(2, ay, s, 2, az, NULL, ad, 1e-3, S2, S2, 3, NULL, fy, fz, &fd), -6);
    assert_int_equal(igea_redund_skew_check(2, ay, s, 2, az, s, ad, 0.0, S2, S2, 3, NULL, fy, fz, &fd), -8);
    assert_int_equal(igea_redund_skew_check(2, ay, s, 2, az, s, ad, 1e-3, NAN, S2, 3, NULL, fy, fz, &fd), -9);
    assert_int_equal(igea_redund_skew_check(2, ay, s, 2, az, s, ad, 1e-3, 0, 0, 3, NULL, fy, fz, &fd), -10);
    assert_int_equal(igea_redund_skew_check(2, ay, s, 2, az, s, ad, 1e-3, S2, S2, 0, NULL, fy, fz, &fd), -11);
    assert_int_equal(igea_redund_skew_check(2, ay, s, 2, az, s, ad, 1e-3, S2, S2, 3, NULL, NULL, fz, &fd), -13);
    assert_int_equal(igea_redund_skew_check(2, ay, s, 2, az, s, ad, 1e-3, S2, S2, 3, NULL, fy, NULL, &fd), -14);
    assert_int_equal(igea_redund_skew_check(2, ay, s, 2, az, s, ad, 1e-3, S2, S2, 3, NULL, fy, fz, NULL), -15);
    assert_int_equal(igea_redund_skew_check(2, an, s, 2, az, s, ad, 1e-3, S2, S2, 3, NULL, fy, fz, &fd), IGEA_ENONFINITE);
    assert_int_equal(igea_redund_skew_check(2, ay, s, 2, az, s, NAN, 1e-3, S2, S2, 3, NULL, fy, fz, &fd), IGEA_ENONFINITE);
    assert_int_equal(igea_redund_skew_check(2, ay, sb, 2, az, s, ad, 1e-3, S2, S2, 3, NULL, fy, fz, &fd), IGEA_ENONPOSITIVE);
    assert_true(fy[0] == -7 && fy[1] == -7 && fz[0] == -7 && fz[1] == -7 && fd == -7);
}

/* ---- the seed's experiment ---------------------------------------------- */

static void test_series_experiment(void **state)
{
    /* 4 X accelerometers at 1 g + a few ug, 30 ug noise at 100 Hz, 200 s;
     * 10 mg on Ax4 from 100 s to 120 s; 1-s windows, sigma 20 ug (a
     * tolerance, METHODS 3.3), alpha 0.7, iterative, weighted */
    const int fs = 100, T = 200, n = fs * T;
    const double level[4] = {1.000004, 1.000001, 0.999998, 1.000003};
    const double noise[4] = {30e-6, 30e-6, 30e-6, 30e-6};
    const double sigma[4] = {20e-6, 20e-6, 20e-6, 20e-6};
    double *y = malloc(sizeof(double) * (size_t)n * 4);
    assert_non_null(y);
    assert_int_equal(igea_redund_simulate(n, 4, fs, level, noise, 3, 100.0, 120.0, 0.010, 2024, y, n), 0);
    int nwin = 0;
    assert_int_equal(igea_redund_window_count(n, fs, 1.0, &nwin), 0);
    assert_int_equal(nwin, 200);
    double *means = malloc(sizeof(double) * 4 * 200), fused[200], fsig[200], alpha = 0.7;
    int *ex = malloc(sizeof(int) * 4 * 200);
    assert_int_equal(igea_redund_monitor(n, 4, y, n, fs, 1.0, sigma, &alpha, 0, 1, 1, nwin,
                                              means, ex, fused, fsig), 0);
    for (int w = 0; w < nwin; w++) {
        int faulty = w >= 100 && w < 120;
        for (int s = 0; s < 4; s++)
            assert_int_equal(ex[s + 4 * w], (s == 3 && faulty) ? 1 : 0);
        assert_close_abs(fused[w], 1.0000015, 0, 10e-6);
        assert_close(fsig[w], faulty ? 20e-6 / sqrt(3.0) : 10e-6, 1e-12);
        /* window means against a direct mean */
        double m = 0;
        for (int k = 0; k < fs; k++)
            m += y[(size_t)w * fs + k + (size_t)n * 2];
        assert_close(means[2 + 4 * w], m / fs, 1e-14);
    }
    /* one interval: sensor 3 (0-based), windows 100..119, 100 s to 120 s */
    int niv = -1, isn[8], iw0[8], iw1[8];
    double it0[8], it1[8];
    assert_int_equal(igea_redund_monitor_intervals(4, nwin, ex, fs, 1.0, 8, &niv, isn, iw0, iw1,
                                                   it0, it1), 0);
    assert_int_equal(niv, 1);
    assert_int_equal(isn[0], 3);
    assert_int_equal(iw0[0], 100);
    assert_int_equal(iw1[0], 120);
    assert_true(it0[0] == 100.0 && it1[0] == 120.0);
    /* the same record is reproduced by the same seed; another seed differs */
    double *y2 = malloc(sizeof(double) * (size_t)n * 4);
    igea_redund_simulate(n, 4, fs, level, noise, 3, 100.0, 120.0, 0.010, 2024, y2, n);
    assert_memory_equal(y, y2, sizeof(double) * (size_t)n * 4);
    igea_redund_simulate(n, 4, fs, level, noise, 3, 100.0, 120.0, 0.010, 2025, y2, n);
    assert_true(y[7] != y2[7]);
    /* the fault sits exactly on samples 10000..11999 of sensor 3 */
    assert_true(fabs(y[3 * (size_t)n + 9999] - 1.0) < 1e-3);
    assert_true(fabs(y[3 * (size_t)n + 10000] - 1.010) < 1e-3);
    assert_true(fabs(y[3 * (size_t)n + 11999] - 1.010) < 1e-3);
    assert_true(fabs(y[3 * (size_t)n + 12000] - 1.0) < 1e-3);
    /* invalid */
    double fz[200];
    fill_sentinel(fz, 200);
    double ab = 1.5, sb[4] = {1, 1, 0, 1};
    assert_int_equal(igea_redund_monitor(0, 4, y, n, fs, 1.0, sigma, &alpha, 0, 1, 1, nwin, NULL, ex, fz, NULL), -1);
    assert_int_equal(igea_redund_monitor(n, 0, y, n, fs, 1.0, sigma, &alpha, 0, 1, 1, nwin, NULL, ex, fz, NULL), -2);
    assert_int_equal(igea_redund_monitor(n, 4, NULL, n, fs, 1.0, sigma, &alpha, 0, 1, 1, nwin, NULL, ex, fz, NULL), -3);
    assert_int_equal(igea_redund_monitor(n, 4, y, n - 1, fs, 1.0, sigma, &alpha, 0, 1, 1, nwin, NULL, ex, fz, NULL), -4);
    assert_int_equal(igea_redund_monitor(n, 4, y, n, 0.0, 1.0, sigma, &alpha, 0, 1, 1, nwin, NULL, ex, fz, NULL), -5);
    assert_int_equal(igea_redund_monitor(n, 4, y, n, fs, 0.0, sigma, &alpha, 0, 1, 1, nwin, NULL, ex, fz, NULL), -6);
    assert_int_equal(igea_redund_monitor(n, 4, y, n, fs, 1.0, NULL, &alpha, 0, 1, 1, nwin, NULL, ex, fz, NULL), -7);
    assert_int_equal(igea_redund_monitor(n, 4, y, n, fs, 1.0, sigma, NULL, 0, 1, 1, nwin, NULL, ex, fz, NULL), -8);
    assert_int_equal(igea_redund_monitor(n, 4, y, n, fs, 1.0, sigma, &ab, 0, 1, 1, nwin, NULL, ex, fz, NULL), -8);
    assert_int_equal(igea_redund_monitor(n, 4, y, n, fs, 1.0, sigma, &alpha, 2, 1, 1, nwin, NULL, ex, fz, NULL), -9);
    assert_int_equal(igea_redund_monitor(n, 4, y, n, fs, 1.0, sigma, &alpha, 0, 3, 1, nwin, NULL, ex, fz, NULL), -10);
    assert_int_equal(igea_redund_monitor(n, 4, y, n, fs, 1.0, sigma, &alpha, 0, 1, 3, nwin, NULL, ex, fz, NULL), -11);
    assert_int_equal(igea_redund_monitor(n, 4, y, n, fs, 1.0, sigma, &alpha, 0, 1, 1, 199, NULL, ex, fz, NULL), -12);
    assert_int_equal(igea_redund_monitor(n, 4, y, n, fs, 1.0, sigma, &alpha, 0, 1, 1, nwin, NULL, NULL, fz, NULL), -14);
    assert_int_equal(igea_redund_monitor(n, 4, y, n, fs, 1.0, sigma, &alpha, 0, 1, 1, nwin, NULL, ex, NULL, NULL), -15);
    assert_int_equal(igea_redund_monitor(n, 4, y, n, fs, 1.0, sb, &alpha, 0, 1, 1, nwin, NULL, ex, fz, NULL), IGEA_ENONPOSITIVE);
    y[5] = NAN;
    assert_int_equal(igea_redund_monitor(n, 4, y, n, fs, 1.0, sigma, &alpha, 0, 1, 1, nwin, NULL, ex, fz, NULL), IGEA_ENONFINITE);
    assert_true(all_sentinel(fz, 200));
    assert_int_equal(igea_redund_window_count(0, 1.0, 1.0, &nwin), -1);
    assert_int_equal(igea_redund_window_count(5, NAN, 1.0, &nwin), -2);
    assert_int_equal(igea_redund_window_count(5, 1.0, 0.1, &nwin), -3);
    assert_int_equal(igea_redund_window_count(5, 1.0, 1.0, NULL), -4);
    free(y);
    free(y2);
    free(means);
    free(ex);
}

static void test_simulate_args(void **state)
{
    double y[12], lv[2] = {1, 2}, nz[2] = {0, 0.1}, nb[2] = {1, -1}, ln[2] = {NAN, 1};
    fill_sentinel(y, 12);
    assert_int_equal(igea_redund_simulate(0, 2, 1, lv, nz, 0, 0, 1, 1, 1, y, 6), -1);
    assert_int_equal(igea_redund_simulate(6, 0, 1, lv, nz, 0, 0, 1, 1, 1, y, 6), -2);
    assert_int_equal(igea_redund_simulate(6, 2, 0, lv, nz, 0, 0, 1, 1, 1, y, 6), -3);
    assert_int_equal(igea_redund_simulate(6, 2, 1, NULL, nz, 0, 0, 1, 1, 1, y, 6), -4);
    assert_int_equal(igea_redund_simulate(6, 2, 1, lv, NULL, 0, 0, 1, 1, 1, y, 6), -5);
    assert_int_equal(igea_redund_simulate(6, 2, 1, lv, nb, 0, 0, 1, 1, 1, y, 6), -5);
    assert_int_equal(igea_redund_simulate(6, 2, 1, lv, nz, 2, 0, 1, 1, 1, y, 6), -6);
    assert_int_equal(igea_redund_simulate(6, 2, 1, lv, nz, 0, NAN, 1, 1, 1, y, 6), -7);
    assert_int_equal(igea_redund_simulate(6, 2, 1, lv, nz, 0, 0, NAN, 1, 1, y, 6), -8);
    assert_int_equal(igea_redund_simulate(6, 2, 1, lv, nz, 0, 0, 1, INFINITY, 1, y, 6), -9);
    assert_int_equal(igea_redund_simulate(6, 2, 1, lv, nz, 0, 0, 1, 1, -1, y, 6), -10);
    assert_int_equal(igea_redund_simulate(6, 2, 1, lv, nz, 0, 0, 1, 1, 1, NULL, 6), -11);
    assert_int_equal(igea_redund_simulate(6, 2, 1, lv, nz, 0, 0, 1, 1, 1, y, 5), -12);
    assert_int_equal(igea_redund_simulate(6, 2, 1, ln, nz, 0, 0, 1, 1, 1, y, 6), IGEA_ENONFINITE);
    assert_true(all_sentinel(y, 12));
    /* noiseless sensor 0 with a fault over [2 s, 4 s) */
    assert_int_equal(igea_redund_simulate(6, 2, 1, lv, nz, 0, 2, 4, 0.5, 1, y, 6), 0);
    const double want[6] = {1, 1, 1.5, 1.5, 1, 1};
    for (int k = 0; k < 6; k++)
        assert_close(y[k], want[k], 0);
}

#ifndef OOM_DISABLED
static void test_oom(void **state)
{
    /* geometry with fdi */
    double ax[6 * 3], R[6], ref[IGEA_REDUND_GEOM_LEN], out[IGEA_REDUND_GEOM_LEN];
    double c = 1.0 / sqrt(3.0), sn = sqrt(2.0 / 3.0);
    for (int k = 0; k < 6; k++) {
        set_axis(ax, 6, k, sn * cos(1.1 * k), sn * sin(1.1 * k), c);
        R[k] = 0.95;
    }
    assert_int_equal(igea_redund_geometry(6, ax, 6, R, 1, ref), 0);
    int k, st, nfail = 0;
    for (k = 0;; k++) {
        fill_sentinel(out, IGEA_REDUND_GEOM_LEN);
        OOM_ARM(k);
        st = igea_redund_geometry(6, ax, 6, R, 1, out);
        OOM_DISARM();
        if (st != IGEA_ENOMEM)
            break;
        nfail++;
        assert_true(all_sentinel(out, IGEA_REDUND_GEOM_LEN));
    }
    assert_int_equal(st, 0);
    assert_true(nfail >= 2);
    for (int i = 0; i < IGEA_REDUND_GEOM_LEN; i++)
        assert_close(out[i], ref[i], 0);
    /* fusion set, kofn, diagram */
    double D[16], alpha = 0.7, x[4] = {1.000010, 1.000018, 0.999995, 1.010004}, sg[4] = {2e-5, 2e-5, 2e-5, 2e-5};
    igea_redund_confidence_distance(4, x, sg, D, 4);
    int keep[4];
    for (k = 0;; k++) {
        keep[0] = keep[1] = keep[2] = keep[3] = -3;
        OOM_ARM(k);
        st = igea_redund_fusion_set(4, D, 4, &alpha, 0, 1, keep, NULL);
        OOM_DISARM();
        if (st != IGEA_ENOMEM)
            break;
        assert_true(keep[0] == -3 && keep[3] == -3);
    }
    assert_true(st == 0 && keep[3] == 0 && keep[0] == 1);
    double v = SENTINEL;
    for (k = 0;; k++) {
        OOM_ARM(k);
        st = igea_redund_reliability_kofn(6, 4, R, &v);
        OOM_DISARM();
        if (st != IGEA_ENOMEM)
            break;
        assert_true(v == SENTINEL);
    }
    assert_int_equal(st, 0);
    const int type[2] = {IGEA_REDUND_RBD_PARALLEL, IGEA_REDUND_RBD_SERIES}, first[3] = {0, 2, 4},
              member[4] = {0, 1, 6, 2};
    double Rb[2] = {SENTINEL, SENTINEL};
    for (k = 0;; k++) {
        OOM_ARM(k);
        st = igea_redund_diagram(6, R, 2, type, NULL, first, member, Rb);
        OOM_DISARM();
        if (st != IGEA_ENOMEM)
            break;
        assert_true(all_sentinel(Rb, 2));
    }
    assert_int_equal(st, 0);
    assert_close(Rb[1], (1 - 0.05 * 0.05) * 0.95, 1e-15);
    /* parity and fdi */
    double H[18], V[18], y[6], sig[6], info[IGEA_REDUND_FDI_LEN];
    cone6(H, 6);
    for (int i = 0; i < 6; i++) {
        y[i] = H[i] + (i == 4 ? 0.02 : 0.0);
        sig[i] = 1e-3;
    }
    for (k = 0;; k++) {
        fill_sentinel(V, 18);
        OOM_ARM(k);
        st = igea_redund_parity(6, 3, H, 6, V, 3);
        OOM_DISARM();
        if (st != IGEA_ENOMEM)
            break;
        assert_true(all_sentinel(V, 18));
    }
    assert_int_equal(st, 0);
    int iso = -9;
    for (k = 0;; k++) {
        fill_sentinel(info, IGEA_REDUND_FDI_LEN);
        OOM_ARM(k);
        st = igea_redund_fdi(6, 3, H, 6, y, sig, 0.01, NULL, info, &iso);
        OOM_DISARM();
        if (st != IGEA_ENOMEM)
            break;
        assert_true(all_sentinel(info, IGEA_REDUND_FDI_LEN) && iso == -9);
    }
    assert_true(st == 0 && iso == 4);
    /* skew check */
    double ay[2] = {0.3, 0.31}, az[2] = {-0.2, -0.2}, s2[2] = {1e-3, 1e-3};
    int fy[2] = {-7, -7}, fz[2] = {-7, -7}, fd = -7;
    for (k = 0;; k++) {
        OOM_ARM(k);
        st = igea_redund_skew_check(2, ay, s2, 2, az, s2, 0.1 * S2, 1e-3, S2, S2, 3, NULL, fy, fz, &fd);
        OOM_DISARM();
        if (st != IGEA_ENOMEM)
            break;
        assert_true(fy[0] == -7 && fz[1] == -7 && fd == -7);
    }
    assert_true(st == 0 && fy[1] == 1 && fd == 0);
    /* simulate and the windowed check */
    enum { NS = 400 };
    double rec[NS * 3], lv[3] = {1, 1, 1}, nz[3] = {1e-5, 1e-5, 1e-5};
    for (k = 0;; k++) {
        fill_sentinel(rec, NS * 3);
        OOM_ARM(k);
        st = igea_redund_simulate(NS, 3, 100, lv, nz, 2, 1.0, 2.0, 0.01, 5, rec, NS);
        OOM_DISARM();
        if (st != IGEA_ENOMEM)
            break;
        assert_true(all_sentinel(rec, NS * 3));
    }
    assert_int_equal(st, 0);
    double fused[4], s3[3] = {5e-5, 5e-5, 5e-5};
    int ex[12];
    for (k = 0;; k++) {
        fill_sentinel(fused, 4);
        OOM_ARM(k);
        st = igea_redund_monitor(NS, 3, rec, NS, 100, 1.0, s3, &alpha, 0, 1, 1, 4, NULL, ex, fused, NULL);
        OOM_DISARM();
        if (st != IGEA_ENOMEM)
            break;
        assert_true(all_sentinel(fused, 4));
    }
    assert_int_equal(st, 0);
    assert_true(ex[2 + 3 * 1] == 1 && ex[2 + 3 * 0] == 0);
}
#endif

static void test_sigma_range(void **state)
{
    (void)state;
    /* Sigmas below 2^-511 (a denormal one, say): IGEA_ERANGE, outputs
     * untouched, in every routine that weights by 1/sigma^2 or whitens. */
    double x[3] = {1.0, 1.1, 0.9}, sg[3] = {0.1, 5e-320, 0.2}, v = SENTINEL,
           s = SENTINEL, D[9];
    fill_sentinel(D, 9);
    assert_int_equal(igea_redund_fuse(3, x, sg, NULL, 1, &v, &s), IGEA_ERANGE);
    assert_int_equal(igea_redund_fuse(3, x, sg, NULL, 0, &v, &s), IGEA_ERANGE);
    assert_int_equal(igea_redund_confidence_distance(3, x, sg, D, 3), IGEA_ERANGE);
    assert_true(v == SENTINEL && s == SENTINEL && all_sentinel(D, 9));
    double H[8] = {1, 1, 1, 1, 0, 1, 2, 3}, y[4] = {1, 2, 3, 4.1},
           sg4[4] = {1, 1, 1e-155, 1}, par[2], info[8];
    fill_sentinel(par, 2);
    fill_sentinel(info, 8);
    int iso = -7;
    assert_int_equal(igea_redund_fdi(4, 2, H, 4, y, sg4, 0.01, par, info, &iso),
                     IGEA_ERANGE);
    assert_true(all_sentinel(par, 2) && all_sentinel(info, 8) && iso == -7);
    /* The smallest accepted value works. */
    sg[1] = IGEA_SIGMA_MIN;
    assert_int_equal(igea_redund_fuse(3, x, sg, NULL, 1, &v, &s), 0);
    assert_close(v, 1.1, 1e-12);
    assert_close(s, IGEA_SIGMA_MIN, 1e-12);
}

/* Exclusion intervals of a hand-written table: 3 sensors x 6 windows of
 * round(0.25 x 10) = 3 samples at 10 Hz, i.e. 0.3 s. */
static void test_monitor_intervals(void **state)
{
    /* excluded[s + 3 w]: sensor 0 in windows 0-1 and 4; sensor 1 never;
     * sensor 2 in windows 2..5 (to the end) */
    static const int ex[18] = {1, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 1, 0, 1, 0, 0, 1};
    int n = -1, sn[9], w0[9], w1[9];
    double t0[9], t1[9];
    assert_int_equal(igea_redund_monitor_intervals(3, 6, ex, 10.0, 0.25, 0, &n, NULL, NULL, NULL,
                                                   NULL, NULL), 0);
    assert_int_equal(n, 3);
    n = -1;
    assert_int_equal(igea_redund_monitor_intervals(3, 6, ex, 10.0, 0.25, 9, &n, sn, w0, w1, t0,
                                                   t1), 0);
    assert_int_equal(n, 3);
    const int es[3] = {0, 0, 2}, e0[3] = {0, 4, 2}, e1[3] = {2, 5, 6};
    for (int k = 0; k < 3; k++) {
        assert_int_equal(sn[k], es[k]);
        assert_int_equal(w0[k], e0[k]);
        assert_int_equal(w1[k], e1[k]);
        assert_close(t0[k], 0.3 * e0[k], 1e-15);
        assert_close(t1[k], 0.3 * e1[k], 1e-15);
    }
    /* times may be omitted */
    assert_int_equal(igea_redund_monitor_intervals(3, 6, ex, 10.0, 0.25, 3, &n, sn, w0, w1, NULL,
                                                   NULL), 0);
    /* too little room: -6, nothing written */
    int z[2] = {-7, -7};
    n = -1;
    assert_int_equal(igea_redund_monitor_intervals(3, 6, ex, 10.0, 0.25, 2, &n, z, z, z, NULL,
                                                   NULL), -6);
    assert_true(n == -1 && z[0] == -7 && z[1] == -7);
    /* invalid arguments */
    assert_int_equal(igea_redund_monitor_intervals(0, 6, ex, 10.0, 0.25, 9, &n, sn, w0, w1, t0, t1), -1);
    assert_int_equal(igea_redund_monitor_intervals(3, 0, ex, 10.0, 0.25, 9, &n, sn, w0, w1, t0, t1), -2);
    assert_int_equal(igea_redund_monitor_intervals(3, 6, NULL, 10.0, 0.25, 9, &n, sn, w0, w1, t0, t1), -3);
    int bad[18];
    memcpy(bad, ex, sizeof bad);
    bad[7] = 2;
    assert_int_equal(igea_redund_monitor_intervals(3, 6, bad, 10.0, 0.25, 9, &n, sn, w0, w1, t0, t1), -3);
    assert_int_equal(igea_redund_monitor_intervals(3, 6, ex, 0.0, 0.25, 9, &n, sn, w0, w1, t0, t1), -4);
    assert_int_equal(igea_redund_monitor_intervals(3, 6, ex, 10.0, 0.01, 9, &n, sn, w0, w1, t0, t1), -5);
    assert_int_equal(igea_redund_monitor_intervals(3, 6, ex, 10.0, 0.25, -1, &n, sn, w0, w1, t0, t1), -6);
    assert_int_equal(igea_redund_monitor_intervals(3, 6, ex, 10.0, 0.25, 9, NULL, sn, w0, w1, t0, t1), -7);
    assert_int_equal(igea_redund_monitor_intervals(3, 6, ex, 10.0, 0.25, 9, &n, NULL, w0, w1, t0, t1), -8);
    assert_int_equal(igea_redund_monitor_intervals(3, 6, ex, 10.0, 0.25, 9, &n, sn, NULL, w1, t0, t1), -9);
    assert_int_equal(igea_redund_monitor_intervals(3, 6, ex, 10.0, 0.25, 9, &n, sn, w0, NULL, t0, t1), -10);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_monitor_intervals),
        cmocka_unit_test(test_exponential),
        cmocka_unit_test(test_series_parallel_kofn),
        cmocka_unit_test(test_diagram),
        cmocka_unit_test(test_seed002),
        cmocka_unit_test(test_geometry_seed),
        cmocka_unit_test(test_geometry_cone),
        cmocka_unit_test(test_geometry_args),
        cmocka_unit_test(test_confidence_distance),
        cmocka_unit_test(test_thresholds_relation),
        cmocka_unit_test(test_fusion_set),
        cmocka_unit_test(test_fuse),
        cmocka_unit_test(test_false_alarm),
        cmocka_unit_test(test_transform),
        cmocka_unit_test(test_parity),
        cmocka_unit_test(test_fdi),
        cmocka_unit_test(test_fdi_yz_plane),
        cmocka_unit_test(test_skew_check),
        cmocka_unit_test(test_series_experiment),
        cmocka_unit_test(test_simulate_args),
        cmocka_unit_test(test_sigma_range),
#ifndef OOM_DISABLED
        cmocka_unit_test(test_oom),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
