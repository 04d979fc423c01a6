/* tests/test_nav.c - the navigation core against closed forms: WGS-84
 * geodetic <-> ECEF, the launch-site frames and Earth rotation, J2
 * gravity and its gradient, the coning and sculling corrections, and the
 * position integration against an RK4 written here. */
#include "testutil.h"

#include "igea/envfun.h"
#include "igea/nav.h"

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)

/* WGS-84 defining constants, NIMA TR8350.2 (3rd ed., 2000) table 3.1;
 * semi-minor axis b = 6356752.3142 m from its table 3.3. */
static const double A84 = 6378137.0, F84 = 1.0 / 298.257223563, B84 = 6356752.3142;
static const double GM84 = 3.986004418e14, W84 = 7.292115e-5;

static void cross(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* ---- WGS-84 ------------------------------------------------------------ */

/* A point of the meridian ellipse by its reduced latitude beta (tan beta =
 * (1 - f) tan phi), raised by h along the normal: an independent
 * construction of the geodetic -> ECEF map. */
static void ellipse_point(double phi, double lam, double h, double *r)
{
    double b = A84 * (1.0 - F84), beta = atan((1.0 - F84) * tan(phi));
    double p = A84 * cos(beta) + h * cos(phi), z = b * sin(beta) + h * sin(phi);
    r[0] = p * cos(lam);
    r[1] = p * sin(lam);
    r[2] = z;
}

static void test_geodetic_points(void **state)
{
    (void)state;
    double r[3];
    assert_int_equal(igea_nav_geodetic_to_ecef(0.0, 0.0, 0.0, r), 0);
    assert_close(r[0], A84, 1e-15);
    assert_close_abs(r[1], 0.0, 0.0, 1e-9);
    assert_close_abs(r[2], 0.0, 0.0, 1e-9);
    assert_int_equal(igea_nav_geodetic_to_ecef(PI / 2, 0.3, 100.0, r), 0);
    assert_close_abs(r[2], B84 + 100.0, 0.0, 1e-4); /* TR8350.2's b to 0.1 mm */
    assert_close_abs(hypot(r[0], r[1]), 0.0, 0.0, 1e-6);
    const double pts[][3] = {{45.0, 10.0, 0.0}, {33.3, 44.4, 6000.0}, {-41.0, -170.0, 2.5e5},
                             {89.9, 123.0, -400.0}, {28.5, 100.3, 1.2e6}};
    for (size_t i = 0; i < sizeof pts / sizeof pts[0]; i++) {
        double want[3], geo[3];
        ellipse_point(pts[i][0] * DEG, pts[i][1] * DEG, pts[i][2], want);
        assert_int_equal(igea_nav_geodetic_to_ecef(pts[i][0] * DEG, pts[i][1] * DEG,
                                                   pts[i][2], r), 0);
        for (int k = 0; k < 3; k++)
            assert_close_abs(r[k], want[k], 0.0, 1e-7);
        assert_int_equal(igea_nav_ecef_to_geodetic(want, geo), 0);
        assert_close_abs(geo[0], pts[i][0] * DEG, 0.0, 1e-13);
        assert_close_abs(geo[1], pts[i][1] * DEG, 0.0, 1e-13);
        assert_close_abs(geo[2], pts[i][2], 0.0, 1e-7);
    }
    double geo[3], pole[3] = {0.0, 0.0, -B84 - 10.0};
    assert_int_equal(igea_nav_ecef_to_geodetic(pole, geo), 0);
    assert_close_abs(geo[0], -PI / 2, 0.0, 1e-13);
    assert_close_abs(geo[2], 10.0, 0.0, 1e-4);
}

static void test_geodetic_invalid(void **state)
{
    (void)state;
    double r[3] = {SENTINEL, SENTINEL, SENTINEL}, small[3] = {1.0, 2.0, 3.0};
    assert_int_equal(igea_nav_geodetic_to_ecef(2.0, 0.0, 0.0, r), -1);
    assert_int_equal(igea_nav_geodetic_to_ecef(0.0, NAN, 0.0, r), -2);
    assert_int_equal(igea_nav_geodetic_to_ecef(0.0, 0.0, -7e6, r), -3);
    assert_int_equal(igea_nav_geodetic_to_ecef(0.0, 0.0, 0.0, NULL), -4);
    assert_int_equal(igea_nav_ecef_to_geodetic(small, r), -1);
    assert_true(all_sentinel(r, 3));
}

/* ---- frames ------------------------------------------------------------- */

static void site(double az, double *s)
{
    assert_int_equal(igea_nav_site(40.96 * DEG, 100.29 * DEG, 1000.0, az, s), 0);
}

static void test_site_axes(void **state)
{
    (void)state;
    double s[IGEA_NAV_SITE_LEN], lat = 40.96 * DEG, lon = 100.29 * DEG;
    site(90.0 * DEG, s);
    const double *C = s + IGEA_NAV_SITE_C;
    /* firing due east: x = east, y = the geodetic normal, z = south */
    double east[3] = {-sin(lon), cos(lon), 0.0};
    double up[3] = {cos(lat) * cos(lon), cos(lat) * sin(lon), sin(lat)};
    for (int i = 0; i < 3; i++) {
        assert_close_abs(C[i], east[i], 0.0, 1e-15);
        assert_close_abs(C[3 + i], up[i], 0.0, 1e-15);
    }
    site(0.0, s); /* due north: z = north x up = east */
    for (int i = 0; i < 3; i++)
        assert_close_abs(C[6 + i], east[i], 0.0, 1e-15);
    double r0[3];
    igea_nav_geodetic_to_ecef(lat, lon, 1000.0, r0);
    for (int i = 0; i < 3; i++)
        assert_close(s[IGEA_NAV_SITE_R0 + i], r0[i], 1e-15);
}

/* A point fixed on the Earth, seen in LI: it turns about the polar axis
 * (C e_z in LI) at the Earth rate, around the Earth's centre (-C r0 in LI),
 * and comes back after 2 pi / w. */
static void test_earth_rotation(void **state)
{
    (void)state;
    double s[IGEA_NAV_SITE_LEN], rl[3] = {1000.0, 2000.0, -500.0}, vz[3] = {0, 0, 0};
    site(30.0 * DEG, s);
    const double *C = s + IGEA_NAV_SITE_C, *r0 = s + IGEA_NAV_SITE_R0;
    double axis[3] = {C[2], C[5], C[8]}, centre[3];
    for (int i = 0; i < 3; i++)
        centre[i] = -(C[3 * i] * r0[0] + C[3 * i + 1] * r0[1] + C[3 * i + 2] * r0[2]);
    const double ts[] = {0.0, 37.5, 300.0, 2.0 * PI / W84};
    for (size_t k = 0; k < 4; k++) {
        double r[3], v[3], rel[3], want_v[3], w[3];
        assert_int_equal(igea_nav_transform(s, IGEA_NAV_LE, IGEA_NAV_LI, ts[k], rl, vz, r, v), 0);
        for (int i = 0; i < 3; i++) {
            rel[i] = r[i] - centre[i];
            w[i] = W84 * axis[i];
        }
        cross(w, rel, want_v);
        for (int i = 0; i < 3; i++)
            assert_close_abs(v[i], want_v[i], 0.0, 1e-9);
        /* angle turned: the component normal to the axis rotates by w t */
        double rel0[3];
        for (int i = 0; i < 3; i++)
            rel0[i] = rl[i] - centre[i];
        double d0 = rel0[0] * axis[0] + rel0[1] * axis[1] + rel0[2] * axis[2];
        double d1 = rel[0] * axis[0] + rel[1] * axis[1] + rel[2] * axis[2];
        assert_close_abs(d1, d0, 0.0, 1e-7);
        double p0[3], p1[3], c[3];
        for (int i = 0; i < 3; i++) {
            p0[i] = rel0[i] - d0 * axis[i];
            p1[i] = rel[i] - d1 * axis[i];
        }
        cross(p0, p1, c);
        double ang = atan2(c[0] * axis[0] + c[1] * axis[1] + c[2] * axis[2],
                           p0[0] * p1[0] + p0[1] * p1[1] + p0[2] * p1[2]);
        double want = remainder(W84 * ts[k], 2.0 * PI);
        assert_close_abs(ang, want, 0.0, 1e-12);
        /* and back through ECEF */
        double re[3], ve[3], rb[3], vb[3];
        assert_int_equal(igea_nav_transform(s, IGEA_NAV_LI, IGEA_NAV_ECEF, ts[k], r, v, re, ve), 0);
        assert_int_equal(igea_nav_transform(s, IGEA_NAV_ECEF, IGEA_NAV_LE, ts[k], re, ve, rb, vb), 0);
        for (int i = 0; i < 3; i++) {
            assert_close_abs(rb[i], rl[i], 0.0, 1e-7);
            assert_close_abs(vb[i], 0.0, 0.0, 1e-10);
        }
    }
}

/* The velocity rotation equals the transform's Jacobian in v. */
static void test_rotation_matrix(void **state)
{
    (void)state;
    double s[IGEA_NAV_SITE_LEN], r[3] = {5e4, 8e4, 1e3}, v[3] = {1e3, 2e3, -300.0};
    site(-20.0 * DEG, s);
    for (int from = 0; from < 3; from++)
        for (int to = 0; to < 3; to++) {
            double M[9], r1[3], v1[3], r2[3], v2[3], dv[3] = {0.3, -0.2, 0.7};
            assert_int_equal(igea_nav_rotation(s, from, to, 123.0, M), 0);
            double v2in[3] = {v[0] + dv[0], v[1] + dv[1], v[2] + dv[2]};
            igea_nav_transform(s, from, to, 123.0, r, v, r1, v1);
            igea_nav_transform(s, from, to, 123.0, r, v2in, r2, v2);
            for (int i = 0; i < 3; i++)
                assert_close_abs(v2[i] - v1[i], M[3 * i] * dv[0] + M[3 * i + 1] * dv[1] +
                                 M[3 * i + 2] * dv[2], 0.0, 1e-9);
        }
}

/* ---- gravity ----------------------------------------------------------- */

static void test_gravity_closed_forms(void **state)
{
    (void)state;
    double g[3], G[9], J2 = 1.082629821313e-3;
    double req[3] = {A84, 0.0, 0.0}, rp[3] = {0.0, 0.0, B84};
    /* equator: g_r = -mu/a^2 (1 + 3/2 J2); pole: -mu/b^2 (1 - 3 J2 (a/b)^2) */
    assert_int_equal(igea_nav_gravity(IGEA_NAV_GRAVITY_J2, req, g, G), 0);
    assert_close(g[0], -GM84 / (A84 * A84) * (1.0 + 1.5 * J2), 1e-14);
    assert_close(g[0], -9.8143, 1e-4); /* the familiar equatorial gravitation */
    assert_int_equal(igea_nav_gravity(IGEA_NAV_GRAVITY_J2, rp, g, G), 0);
    assert_close(g[2], -GM84 / (B84 * B84) * (1.0 - 3.0 * J2 * (A84 / B84) * (A84 / B84)),
                 1e-14);
    assert_int_equal(igea_nav_gravity(IGEA_NAV_GRAVITY_POINT_MASS, req, g, NULL), 0);
    assert_close(g[0], -GM84 / (A84 * A84), 1e-15);
}

/* The gradient against central differences of g, its symmetry, and
 * Laplace's equation (trace 0 outside the masses). */
static void test_gravity_gradient(void **state)
{
    (void)state;
    double r[3] = {-2.1e6, 4.7e6, 4.3e6};
    for (int model = 0; model < 2; model++) {
        double g[3], G[9];
        assert_int_equal(igea_nav_gravity(model, r, g, G), 0);
        for (int j = 0; j < 3; j++) {
            double rp[3] = {r[0], r[1], r[2]}, rm[3] = {r[0], r[1], r[2]}, gp[3], gm[3];
            rp[j] += 10.0;
            rm[j] -= 10.0;
            igea_nav_gravity(model, rp, gp, NULL);
            igea_nav_gravity(model, rm, gm, NULL);
            for (int i = 0; i < 3; i++)
                assert_close_abs(G[3 * i + j], (gp[i] - gm[i]) / 20.0, 1e-6, 1e-14);
        }
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                assert_close_abs(G[3 * i + j], G[3 * j + i], 0.0, 1e-20);
        assert_close_abs(G[0] + G[4] + G[8], 0.0, 0.0, 1e-19);
    }
}

/* ---- coning ------------------------------------------------------------- */

/* Classical coning, q(t) = [cos(b/2), 0, sin(b/2) cos Wt, sin(b/2) sin Wt]:
 * body rate w = (-W (1 - cos b), -W sin b sin Wt, W sin b cos Wt). Per
 * record of length T (u = W T) the true rotation vector exceeds the
 * increment sum along x by (sin^2 b / 2)(u - sin u) (from int alpha x w /
 * 2), and the correction (dth_prev x dth)/12 supplies (sin^2 b / 12)(2 sin
 * u - sin 2u): the residual drift per record is sin^2 b [(u - sin u)/2 -
 * (2 sin u - sin 2u)/12] = sin^2 b u^5 / 60 + O(u^7) (first record: no
 * previous increment, the whole (u - sin u)/2). */
static double coning_drift(int flags, double beta, double u, int n)
{
    double s[IGEA_NAV_SITE_LEN], st[IGEA_NAV_STATE_LEN], Om = 2.0, T = u / Om;
    site(0.0, s);
    double q0[4] = {cos(beta / 2), 0.0, sin(beta / 2), 0.0}, zero[3] = {0, 0, 0};
    assert_int_equal(igea_nav_init(IGEA_ENVFUN_STRAPDOWN, s, IGEA_NAV_GRAVITY_J2, flags, 0.0,
                                   q0, NULL, NULL, st), 0);
    for (int k = 1; k <= n; k++) {
        double t0 = (k - 1) * T, t1 = k * T;
        double dth[3] = {-Om * (1 - cos(beta)) * T, sin(beta) * (cos(Om * t1) - cos(Om * t0)),
                         sin(beta) * (sin(Om * t1) - sin(Om * t0))};
        assert_int_equal(igea_nav_step(st, t1, zero, dth), 0);
    }
    double t = n * T, c = cos(beta / 2), sb = sin(beta / 2);
    double qt[4] = {c, 0.0, sb * cos(Om * t), sb * sin(Om * t)}, *q = st + IGEA_NAV_STATE_Q;
    /* x part of conj(qt) q, doubled: the drift about body x */
    double ex = qt[0] * q[1] - qt[1] * q[0] - (qt[2] * q[3] - qt[3] * q[2]);
    return 2.0 * ex;
}

static void test_coning(void **state)
{
    (void)state;
    double beta = 0.02, u = 0.1, s2 = sin(beta) * sin(beta);
    int n = 2000;
    double full = 0.5 * (u - sin(u)), corr = (2 * sin(u) - sin(2 * u)) / 12.0;
    double want = -(s2 * (n - 1) * (full - corr) + s2 * full);
    double want_plain = -s2 * n * full;
    assert_close(coning_drift(0, beta, u, n), want, 2e-3);
    assert_close(coning_drift(IGEA_NAV_NO_CONING, beta, u, n), want_plain, 2e-3);
    assert_close(full - corr, pow(u, 5) / 60.0, 2e-3); /* the u^5 law */
}

/* ---- sculling ------------------------------------------------------------ */

/* J1 by its power series (|x| < 1). */
static double bessel_j1(double x)
{
    double term = x / 2, sum = 0.0;
    for (int m = 0; m < 30; m++) {
        sum += term;
        term *= -(x / 2) * (x / 2) / ((m + 1.0) * (m + 2.0));
    }
    return sum;
}

/* Angular oscillation theta0 sin Wt about x with specific force A sin Wt
 * along body y: f_z in LI = A sin Wt sin(theta0 sin Wt), whose mean is A
 * J1(theta0); after n periods W = (0, 0, n P A J1(theta0)). Returns the
 * error |W - that| of the navigation at rate 1/T. */
static double sculling_error(int flags, int per_period, int periods)
{
    double s[IGEA_NAV_SITE_LEN], st[IGEA_NAV_STATE_LEN], Om = 2 * PI * 5.0, th0 = 0.01,
           A = 2.0;
    double P = 2 * PI / Om, T = P / per_period;
    site(0.0, s);
    assert_int_equal(igea_nav_init(IGEA_ENVFUN_STRAPDOWN, s, IGEA_NAV_GRAVITY_J2, flags, 0.0,
                                   NULL, NULL, NULL, st), 0);
    for (int k = 1; k <= per_period * periods; k++) {
        double t0 = (k - 1) * T, t1 = k * T;
        double dth[3] = {th0 * (sin(Om * t1) - sin(Om * t0)), 0.0, 0.0};
        double dv[3] = {0.0, A / Om * (cos(Om * t0) - cos(Om * t1)), 0.0};
        assert_int_equal(igea_nav_step(st, t1, dv, dth), 0);
    }
    const double *W = st + IGEA_NAV_STATE_W;
    double want = periods * P * A * bessel_j1(th0);
    return sqrt(W[0] * W[0] + W[1] * W[1] + (W[2] - want) * (W[2] - want));
}

static void test_sculling(void **state)
{
    (void)state;
    double rect = 10 * (2 * PI / (2 * PI * 5.0)) * 2.0 * bessel_j1(0.01); /* 0.02 m/s */
    double plain = sculling_error(IGEA_NAV_NO_SCULLING, 20, 10);
    double e20 = sculling_error(0, 20, 10), e40 = sculling_error(0, 40, 10);
    print_message("sculling: rectified %.3e m/s; error plain %.3e, corrected %.3e (20/period), "
                  "%.3e (40/period)\n", rect, plain, e20, e40);
    /* the rotation compensation alone leaves a rectified error of a few
     * percent of the effect; the sculling term removes all but the start-up
     * record's (no previous increment), which falls at least as T^3 */
    assert_true(plain > 0.01 * rect);
    assert_true(e20 < 0.05 * plain);
    assert_true(e20 / e40 > 8.0);
}

/* ---- position integration -------------------------------------------- */

/* Ballistic flight (no specific force) from the pad with 2 km/s up: the
 * platform navigation against an RK4 of the point-mass motion in the
 * inertial frame I written here (step 1 ms). */
static void grav_pm(const double *r, double *a)
{
    double n = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    for (int i = 0; i < 3; i++)
        a[i] = -GM84 * r[i] / (n * n * n);
}

static void test_ballistic(void **state)
{
    (void)state;
    double s[IGEA_NAV_SITE_LEN], st[IGEA_NAV_STATE_LEN], zero[3] = {0, 0, 0};
    site(45.0 * DEG, s);
    const double *C = s + IGEA_NAV_SITE_C, *r0 = s + IGEA_NAV_SITE_R0;
    double vli[3] = {0.0, 2000.0, 0.0}, rli[3], vpad[3];
    igea_nav_transform(s, IGEA_NAV_LE, IGEA_NAV_LI, 0.0, zero, zero, rli, vpad);
    for (int i = 0; i < 3; i++)
        vli[i] += vpad[i];
    assert_int_equal(igea_nav_init(IGEA_ENVFUN_PLATFORM, s, IGEA_NAV_GRAVITY_POINT_MASS, 0, 0.0,
                                   NULL, NULL, vli, st), 0);
    for (int k = 1; k <= 30000; k++) /* 100 Hz, 300 s */
        assert_int_equal(igea_nav_step(st, k * 0.01, zero, NULL), 0);
    /* reference in I: r_I = r0 + C^T r_LI */
    double x[6];
    for (int i = 0; i < 3; i++) {
        x[i] = r0[i];
        x[3 + i] = C[i] * vli[0] + C[3 + i] * vli[1] + C[6 + i] * vli[2];
    }
    double h = 1e-3;
    for (int k = 0; k < 300000; k++) {
        double k1[6], k2[6], k3[6], k4[6], y[6];
        memcpy(k1, x + 3, 3 * sizeof(double)); grav_pm(x, k1 + 3);
        for (int i = 0; i < 6; i++) y[i] = x[i] + 0.5 * h * k1[i];
        memcpy(k2, y + 3, 3 * sizeof(double)); grav_pm(y, k2 + 3);
        for (int i = 0; i < 6; i++) y[i] = x[i] + 0.5 * h * k2[i];
        memcpy(k3, y + 3, 3 * sizeof(double)); grav_pm(y, k3 + 3);
        for (int i = 0; i < 6; i++) y[i] = x[i] + h * k3[i];
        memcpy(k4, y + 3, 3 * sizeof(double)); grav_pm(y, k4 + 3);
        for (int i = 0; i < 6; i++)
            x[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    }
    for (int i = 0; i < 3; i++) {
        double d[3] = {x[0] - r0[0], x[1] - r0[1], x[2] - r0[2]};
        double rw = C[3 * i] * d[0] + C[3 * i + 1] * d[1] + C[3 * i + 2] * d[2];
        double vw = C[3 * i] * x[3] + C[3 * i + 1] * x[4] + C[3 * i + 2] * x[5];
        /* trapezoid: error about h^2/12 |change of acceleration| t ~ 1e-3 m */
        assert_close_abs(st[IGEA_NAV_STATE_R + i], rw, 0.0, 5e-3);
        assert_close_abs(st[IGEA_NAV_STATE_V + i], vw, 0.0, 1e-5);
        assert_close_abs(st[IGEA_NAV_STATE_W + i], 0.0, 0.0, 0.0);
    }
}

static void test_step_invalid(void **state)
{
    (void)state;
    double s[IGEA_NAV_SITE_LEN], st[IGEA_NAV_STATE_LEN], copy[IGEA_NAV_STATE_LEN];
    double dv[3] = {1, 2, 3}, bad[3] = {NAN, 0, 0};
    site(0.0, s);
    assert_int_equal(igea_nav_init(5, s, 0, 0, 0.0, NULL, NULL, NULL, st), -1);
    assert_int_equal(igea_nav_init(0, s, 0, 4, 0.0, NULL, NULL, NULL, st), -4);
    double q0[4] = {0, 0, 0, 0};
    assert_int_equal(igea_nav_init(0, s, 0, 0, 0.0, q0, NULL, NULL, st), -6);
    assert_int_equal(igea_nav_init(0, s, 0, 0, 1.0, NULL, NULL, NULL, st), 0);
    memcpy(copy, st, sizeof st);
    assert_int_equal(igea_nav_step(st, 1.0, dv, NULL), -2); /* not after the state */
    assert_int_equal(igea_nav_step(st, 1.1, bad, NULL), IGEA_ENONFINITE);
    assert_int_equal(igea_nav_step(st, 1.1, NULL, NULL), -3);
    assert_memory_equal(st, copy, sizeof st);
    st[IGEA_NAV_STATE_SYSTEM] = 7;
    assert_int_equal(igea_nav_step(st, 1.1, dv, NULL), -1);
    s[IGEA_NAV_SITE_C] += 0.1; /* C no longer orthonormal */
    assert_int_equal(igea_nav_init(0, s, 0, 0, 0.0, NULL, NULL, NULL, st), -2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_geodetic_points),  cmocka_unit_test(test_geodetic_invalid),
        cmocka_unit_test(test_site_axes),        cmocka_unit_test(test_earth_rotation),
        cmocka_unit_test(test_rotation_matrix),  cmocka_unit_test(test_gravity_closed_forms),
        cmocka_unit_test(test_gravity_gradient), cmocka_unit_test(test_coning),
        cmocka_unit_test(test_sculling),         cmocka_unit_test(test_ballistic),
        cmocka_unit_test(test_step_invalid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
