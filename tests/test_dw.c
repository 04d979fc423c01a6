/* tests/test_dw.c - telemetry minus tracking, closing the loop: a
 * reference flight integrated here (RK4 in ECEF with J2 gravity, Coriolis
 * and centrifugal terms), sampled into ideal telemetry increments and
 * ideal tracking, must give dW = 0; instrument errors injected into the
 * increments must give dW = S X to second order; a clock offset must give
 * dW = f tau and be recovered. */
#include "testutil.h"

#include "igea/dw.h"
#include "igea/envfun.h"
#include "igea/nav.h"

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)

/* WGS-84, NIMA TR8350.2 (3rd ed.) tables 3.1 and 3.3 (J2 = -sqrt(5) C20). */
static const double A84 = 6378137.0, F84 = 1.0 / 298.257223563, GM = 3.986004418e14;
static const double WE = 7.292115e-5, J2 = 1.082629821313e-3;

#define RATE 100                      /* telemetry, Hz */
#define SUB 2                         /* RK4 steps per telemetry record */
#define DUR 300                       /* s */
#define NREC (RATE * DUR + 1)         /* telemetry rows */
#define NSTEP ((NREC - 1) * SUB + 1)  /* RK4 grid points */
#define H (1.0 / (RATE * SUB))

static const double LAT = 40.96 * DEG, LON = 100.29 * DEG, HGT = 1000.0, AZ = 30.0 * DEG;

/* ---- the reference motion: body rate and specific force (body axes) ---- */
static void omega_b(double t, double *w)
{
    w[0] = 0.01 * sin(0.9 * t);
    w[1] = 0.005 * cos(1.7 * t);
    w[2] = -0.004 + 0.002 * sin(0.05 * t);
}
static void omega_int(double a, double b, double *d) /* int_a^b omega_b */
{
    d[0] = 0.01 * (cos(0.9 * a) - cos(0.9 * b)) / 0.9;
    d[1] = 0.005 * (sin(1.7 * b) - sin(1.7 * a)) / 1.7;
    d[2] = -0.004 * (b - a) + 0.002 * (cos(0.05 * a) - cos(0.05 * b)) / 0.05;
}
static void force_b(double t, double *f)
{
    f[0] = 20.0 + 5.0 * sin(0.02 * t);
    f[1] = 0.3 * sin(2.1 * t);
    f[2] = 0.2 * cos(0.8 * t);
}
static void force_int(double a, double b, double *d)
{
    d[0] = 20.0 * (b - a) + 5.0 * (cos(0.02 * a) - cos(0.02 * b)) / 0.02;
    d[1] = 0.3 * (cos(2.1 * a) - cos(2.1 * b)) / 2.1;
    d[2] = 0.2 * (sin(0.8 * b) - sin(0.8 * a)) / 0.8;
}

/* ---- the test's own frames and gravity -------------------------------- */
typedef struct {
    double C[9]; /* LE axes in ECEF (rows) */
    double r0[3];
} frames;

static void make_frames(frames *F)
{
    double e2 = F84 * (2 - F84), sl = sin(LAT), cl = cos(LAT), so = sin(LON), co = cos(LON);
    double N = A84 / sqrt(1 - e2 * sl * sl);
    F->r0[0] = (N + HGT) * cl * co;
    F->r0[1] = (N + HGT) * cl * so;
    F->r0[2] = (N * (1 - e2) + HGT) * sl;
    double e[3] = {-so, co, 0}, n[3] = {-sl * co, -sl * so, cl}, u[3] = {cl * co, cl * so, sl};
    for (int i = 0; i < 3; i++) {
        F->C[i] = cos(AZ) * n[i] + sin(AZ) * e[i];
        F->C[3 + i] = u[i];
    }
    const double *x = F->C, *y = F->C + 3;
    F->C[6] = x[1] * y[2] - x[2] * y[1];
    F->C[7] = x[2] * y[0] - x[0] * y[2];
    F->C[8] = x[0] * y[1] - x[1] * y[0];
}

/* J2 gravitation, textbook form (e.g. Vallado, Fundamentals of
 * Astrodynamics, eq. 8-30). */
static void grav(const double *r, double *g)
{
    double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2], rn = sqrt(r2);
    double k = 1.5 * J2 * A84 * A84 / r2, zz = r[2] * r[2] / r2, m = -GM / (r2 * rn);
    g[0] = m * r[0] * (1 + k * (1 - 5 * zz));
    g[1] = m * r[1] * (1 + k * (1 - 5 * zz));
    g[2] = m * r[2] * (1 + k * (3 - 5 * zz));
}

static void quat_dcm(const double *q, double *C) /* body -> LI */
{
    double a = q[0], b = q[1], c = q[2], d = q[3];
    C[0] = a * a + b * b - c * c - d * d; C[1] = 2 * (b * c - a * d); C[2] = 2 * (b * d + a * c);
    C[3] = 2 * (b * c + a * d); C[4] = a * a - b * b + c * c - d * d; C[5] = 2 * (c * d - a * b);
    C[6] = 2 * (b * d - a * c); C[7] = 2 * (c * d + a * b); C[8] = a * a - b * b - c * c + d * d;
}

/* State: r_E (3), v_E (3), q body -> LI (4), W in LI (3). */
#define NX 13
static void deriv(const frames *F, double t, const double *x, double *dx)
{
    double wb[3], fb[3], Cq[9], fli[3], fI[3], fE[3], g[3];
    omega_b(t, wb);
    force_b(t, fb);
    const double *q = x + 6;
    dx[6] = 0.5 * (-q[1] * wb[0] - q[2] * wb[1] - q[3] * wb[2]);
    dx[7] = 0.5 * (q[0] * wb[0] + q[2] * wb[2] - q[3] * wb[1]);
    dx[8] = 0.5 * (q[0] * wb[1] - q[1] * wb[2] + q[3] * wb[0]);
    dx[9] = 0.5 * (q[0] * wb[2] + q[1] * wb[1] - q[2] * wb[0]);
    quat_dcm(q, Cq);
    for (int i = 0; i < 3; i++)
        fli[i] = Cq[3 * i] * fb[0] + Cq[3 * i + 1] * fb[1] + Cq[3 * i + 2] * fb[2];
    for (int i = 0; i < 3; i++) /* LI -> I (C^T), then I -> ECEF (rotation by -w t) */
        fI[i] = F->C[i] * fli[0] + F->C[3 + i] * fli[1] + F->C[6 + i] * fli[2];
    double c = cos(WE * t), s = sin(WE * t);
    fE[0] = c * fI[0] + s * fI[1];
    fE[1] = -s * fI[0] + c * fI[1];
    fE[2] = fI[2];
    grav(x, g);
    const double *r = x, *v = x + 3;
    for (int i = 0; i < 3; i++)
        dx[i] = v[i];
    /* a = f + g - 2 w x v - w x (w x r), w = (0, 0, WE) */
    dx[3] = fE[0] + g[0] + 2 * WE * v[1] + WE * WE * r[0];
    dx[4] = fE[1] + g[1] - 2 * WE * v[0] + WE * WE * r[1];
    dx[5] = fE[2] + g[2];
    for (int i = 0; i < 3; i++)
        dx[10 + i] = fli[i];
}

/* The reference flight on the RK4 grid (NSTEP x NX). */
static double *reference_flight(const frames *F)
{
    double *X = malloc((size_t)NSTEP * NX * sizeof *X);
    assert_non_null(X);
    double *x = X;
    memset(x, 0, NX * sizeof *x);
    memcpy(x, F->r0, 3 * sizeof *x);
    x[6] = cos(PI / 4); /* body x up: 90 degrees about LI z */
    x[9] = sin(PI / 4);
    for (int k = 1; k < NSTEP; k++) {
        const double *a = X + (size_t)(k - 1) * NX;
        double *b = X + (size_t)k * NX, t = (k - 1) * H, k1[NX], k2[NX], k3[NX], k4[NX], y[NX];
        deriv(F, t, a, k1);
        for (int i = 0; i < NX; i++) y[i] = a[i] + 0.5 * H * k1[i];
        deriv(F, t + 0.5 * H, y, k2);
        for (int i = 0; i < NX; i++) y[i] = a[i] + 0.5 * H * k2[i];
        deriv(F, t + 0.5 * H, y, k3);
        for (int i = 0; i < NX; i++) y[i] = a[i] + H * k3[i];
        deriv(F, t + H, y, k4);
        for (int i = 0; i < NX; i++)
            b[i] = a[i] + H / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    }
    return X;
}

/* ---- telemetry and tracking ------------------------------------------- */
typedef struct {
    frames F;
    double *X, site[IGEA_NAV_SITE_LEN], q0[4];
    int nep;
    double ep[400];
} flight;

static flight FL;

/* Epochs: every second to 300 s, a gap 150-154 s, and a few off the
 * telemetry records (between two samples) and unevenly spaced. */
static int make_epochs(double *ep, double last)
{
    int n = 0;
    ep[n++] = 0.5;
    for (int s = 1; s <= DUR; s++) {
        if ((s > 150 && s < 155) || s > last)
            continue;
        ep[n++] = s;
        if (s == 10 || s == 200 || s == 250)
            ep[n++] = s + 0.005 * (s == 10 ? 1 : s == 200 ? 7 : 101);
    }
    return n;
}

static int setup(void **state)
{
    (void)state;
    make_frames(&FL.F);
    FL.X = reference_flight(&FL.F);
    assert_int_equal(igea_nav_site(LAT, LON, HGT, AZ, FL.site), 0);
    FL.q0[0] = cos(PI / 4), FL.q0[1] = 0, FL.q0[2] = 0, FL.q0[3] = sin(PI / 4);
    FL.nep = make_epochs(FL.ep, DUR);
    return 0;
}
static int teardown(void **state)
{
    (void)state;
    free(FL.X);
    return 0;
}

/* Telemetry (column-major NREC x 7): strapdown increments from the closed
 * forms, plus bias errors ab (m/s^2) and gb (rad/s) in body axes; platform
 * increments from the reference W along LI. Clock: stamps t - tau. */
static double *telemetry(int platform, const double *ab, const double *gb, double tau)
{
    double *tel = calloc((size_t)NREC * 7, sizeof *tel);
    assert_non_null(tel);
    for (int k = 0; k < NREC; k++) {
        double t1 = (double)k / RATE, t0 = (double)(k - 1) / RATE, dv[3], dth[3];
        tel[k] = t1 - tau;
        if (k == 0)
            continue;
        if (platform) {
            const double *w1 = FL.X + (size_t)k * SUB * NX + 10, *w0 = w1 - SUB * NX;
            for (int i = 0; i < 3; i++)
                dv[i] = w1[i] - w0[i] + (ab ? ab[i] / RATE : 0.0), dth[i] = 0.0;
        } else {
            force_int(t0, t1, dv);
            omega_int(t0, t1, dth);
            for (int i = 0; i < 3; i++) {
                dv[i] += ab ? ab[i] / RATE : 0.0;
                dth[i] += gb ? gb[i] / RATE : 0.0;
            }
        }
        for (int i = 0; i < 3; i++) {
            tel[k + (size_t)NREC * (1 + i)] = dv[i];
            tel[k + (size_t)NREC * (4 + i)] = dth[i];
        }
    }
    return tel;
}

/* Tracking (column-major nep x cols) in LE or ECEF, sigma columns 0.01. */
static double *tracking(int frame, int cols, const double *ep, int nep)
{
    double *trk = calloc((size_t)nep * cols, sizeof *trk);
    assert_non_null(trk);
    for (int e = 0; e < nep; e++) {
        long k = lround(ep[e] / H);
        assert_true(fabs(k * H - ep[e]) < 1e-9);
        const double *x = FL.X + (size_t)k * NX;
        double r[3], v[3];
        for (int i = 0; i < 3; i++) {
            double d[3] = {x[0] - FL.F.r0[0], x[1] - FL.F.r0[1], x[2] - FL.F.r0[2]};
            const double *c = FL.F.C + 3 * i;
            r[i] = frame == IGEA_NAV_ECEF ? x[i] : c[0] * d[0] + c[1] * d[1] + c[2] * d[2];
            v[i] = frame == IGEA_NAV_ECEF ? x[3 + i]
                                          : c[0] * x[3] + c[1] * x[4] + c[2] * x[5];
        }
        trk[e] = ep[e];
        for (int i = 0; i < 3; i++) {
            trk[e + (size_t)nep * (1 + i)] = r[i];
            trk[e + (size_t)nep * (4 + i)] = v[i];
        }
        for (int c = 7; c < cols; c++)
            trk[e + (size_t)nep * c] = 0.01 * (1 + (c - 7));
    }
    return trk;
}

static void cross3(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static double max_abs(const double *x, int n)
{
    double m = 0.0;
    for (int i = 0; i < n; i++)
        m = fmax(m, fabs(x[i]));
    return m;
}

static int KIND = IGEA_DW_APPARENT;

static int run_dw(int platform, const double *tel, int frame, const double *trk, int nep,
                  int cols, double tau, double *dw, double *cov, double *f)
{
    int bad = 7;
    int s = igea_dw_compute(FL.site, platform ? IGEA_ENVFUN_PLATFORM : IGEA_ENVFUN_STRAPDOWN,
                            KIND, FL.q0, tau, NREC, tel, NREC, 7, frame, nep, trk, nep, cols, dw, cov,
                            f, &bad);
    if (!s)
        assert_int_equal(bad, -1);
    return s;
}

/* ---- ideal records: dW = 0 ------------------------------------------------ */
static void test_closed_loop(void **state)
{
    (void)state;
    KIND = IGEA_DW_APPARENT;
    for (int platform = 0; platform < 2; platform++)
        for (int frame = 0; frame < 2; frame++) {
            double *tel = telemetry(platform, NULL, NULL, 0.0);
            double *trk = tracking(frame, 8, FL.ep, FL.nep);
            double dw[3 * 400], cov[6 * 400];
            assert_int_equal(run_dw(platform, tel, frame, trk, FL.nep, 8, 0.0, dw, cov, NULL), 0);
            double m = max_abs(dw, 3 * FL.nep);
            int at = 0;
            for (int r = 0; r < 3 * FL.nep; r++)
                if (fabs(dw[r]) == m)
                    at = r / 3;
            print_message("closed loop, %s, tracking in %s: max |dW| = %.3e m/s over %d epochs "
                          "(at t = %g s)\n", platform ? "platform" : "strapdown",
                          frame ? "LE" : "ECEF", m, FL.nep, FL.ep[at]);
            assert_true(m < 1e-6);
            for (int e = 0; e < FL.nep; e++) { /* isotropic sigma stays isotropic */
                assert_close(cov[6 * e], 1e-4, 1e-12);
                assert_close(cov[6 * e + 3], 1e-4, 1e-12);
                assert_close(cov[6 * e + 5], 1e-4, 1e-12);
                assert_close_abs(cov[6 * e + 1], 0.0, 0.0, 1e-16);
            }
            free(tel);
            free(trk);
        }
}

/* ---- instrument errors: dW = S X to second order ------------------------ */
/* The environment functions of the same flight (igea_envfun_compute_site
 * on the reference trajectory at the telemetry rate; site NULL: without
 * the launch point, igea_envfun_compute_user). */
static void envfun_S(const int *terms, int nt, int output, const double *site, double *S)
{
    double *traj = malloc((size_t)NREC * 11 * sizeof *traj);
    assert_non_null(traj);
    for (int k = 0; k < NREC; k++) {
        double t = (double)k / RATE, fb[3], wb[3];
        const double *x = FL.X + (size_t)k * SUB * NX;
        force_b(t, fb);
        omega_b(t, wb);
        traj[k] = t;
        for (int i = 0; i < 3; i++) {
            traj[k + (size_t)NREC * (1 + i)] = fb[i];
            traj[k + (size_t)NREC * (4 + i)] = wb[i];
        }
        for (int i = 0; i < 4; i++)
            traj[k + (size_t)NREC * (7 + i)] = x[6 + i];
    }
    assert_int_equal(igea_envfun_compute_site(IGEA_ENVFUN_STRAPDOWN, NREC, traj, NREC, nt,
                                              terms, NULL, 0, NULL, NULL, NREC, FL.nep, FL.ep,
                                              NULL, output, site, S, 3 * FL.nep), 0);
    free(traj);
}

static void dw_with_errors(double scale, const double *ab, const double *gb, double *dw)
{
    double a[3], g[3];
    for (int i = 0; i < 3; i++)
        a[i] = scale * ab[i], g[i] = scale * gb[i];
    double *tel = telemetry(0, a, g, 0.0), *trk = tracking(IGEA_NAV_LE, 7, FL.ep, FL.nep);
    assert_int_equal(run_dw(0, tel, IGEA_NAV_LE, trk, FL.nep, 7, 0.0, dw, NULL, NULL), 0);
    free(tel);
    free(trk);
}

/* Apparent kind against envfun's velocity functions, navigated kind against
 * its velocity functions with the gravity-gradient coupling, given the
 * launch point (site: the J2 gradient along the nominal path that leaves
 * the pad at its inertial velocity) or not (site NULL: a point-mass
 * gradient along a path from rest at a 6371-km radius). Returns the odd
 * part's departure from S X relative to max |S X|. */
static double instrument_errors(int kind, const double *site)
{
    KIND = kind;
    /* accelerometer biases ~0.1 mg, gyro drifts ~0.2 deg/h */
    const double ab[3] = {1e-3, -7e-4, 5e-4}, gb[3] = {1e-6, -8e-7, 1.2e-6};
    const int terms[6] = {IGEA_ENVFUN_TERM_ACC_BIAS_X, IGEA_ENVFUN_TERM_ACC_BIAS_X + 1,
                          IGEA_ENVFUN_TERM_ACC_BIAS_X + 2, IGEA_ENVFUN_TERM_GYRO_BIAS_X,
                          IGEA_ENVFUN_TERM_GYRO_BIAS_X + 1, IGEA_ENVFUN_TERM_GYRO_BIAS_X + 2};
    int m = 3 * FL.nep;
    double *S = malloc((size_t)m * 6 * sizeof *S), *buf = malloc((size_t)m * 6 * sizeof *buf);
    assert_non_null(S);
    assert_non_null(buf);
    envfun_S(terms, 6, kind == IGEA_DW_APPARENT ? IGEA_ENVFUN_VELOCITY : IGEA_ENVFUN_VELOCITY_G,
             site, S);
    double *d1 = buf, *dm = buf + m, *d2 = buf + 2 * m, *dm2 = buf + 3 * m, *sx = buf + 4 * m;
    double X[6] = {ab[0], ab[1], ab[2], gb[0], gb[1], gb[2]};
    for (int r = 0; r < m; r++) {
        sx[r] = 0.0;
        for (int j = 0; j < 6; j++)
            sx[r] += S[r + (size_t)m * j] * X[j];
    }
    dw_with_errors(1.0, ab, gb, d1);
    dw_with_errors(-1.0, ab, gb, dm);
    dw_with_errors(0.5, ab, gb, d2);
    dw_with_errors(-0.5, ab, gb, dm2);
    /* odd part: the linear effect; even part: the second-order one */
    double lin_err = 0.0, big = 0.0, q1 = 0.0, q2 = 0.0, disc1 = 0.0, disc2 = 0.0;
    for (int r = 0; r < m; r++) {
        lin_err = fmax(lin_err, fabs(0.5 * (d1[r] - dm[r]) - sx[r]));
        big = fmax(big, fabs(sx[r]));
        q1 = fmax(q1, fabs(0.5 * (d1[r] + dm[r])));
        q2 = fmax(q2, fabs(0.5 * (d2[r] + dm2[r])));
        disc1 = fmax(disc1, fabs(d1[r] - sx[r]));
        disc2 = fmax(disc2, fabs(d2[r] - 0.5 * sx[r]));
    }
    print_message("%s%s, errors: max |S X| %.4g m/s; odd part - S X %.3e; even part %.3e (X), "
                  "%.3e (X/2), ratio %.3f; |dW - S X| %.3e (X), %.3e (X/2), ratio %.3f\n",
                  kind == IGEA_DW_APPARENT ? "apparent" : "navigated",
                  site ? " (site)" : "", big, lin_err, q1, q2, q1 / q2, disc1, disc2,
                  disc1 / disc2);
    assert_true(big > 0.1);
    assert_true(q1 / q2 > 3.8 && q1 / q2 < 4.2); /* second order */
    if (kind == IGEA_DW_APPARENT || site) {
        assert_true(lin_err < 1e-4 * big); /* envfun's trapezoid sums agree with the flight */
        assert_true(disc1 / disc2 > 3.6 && disc1 / disc2 < 4.4); /* second order */
    }
    free(S);
    free(buf);
    KIND = IGEA_DW_APPARENT;
    return lin_err / big;
}

static void test_instrument_errors(void **state)
{
    (void)state;
    instrument_errors(IGEA_DW_APPARENT, NULL);
}

/* The navigated kind couples the errors through gravity: with the launch
 * point the linear model is complete (odd part - S X 1.3e-8 m/s of 0.78,
 * measured; the discrepancy quarters when the errors halve). Without it
 * envfun's point-mass gradient along a path from rest misses by 3.0e-4 m/s
 * (3.9e-4 of the effect): the pad's 350 m/s in LI puts that path 105 km
 * off the flown one after 300 s, turning the gradient by 1.6e-2 rad (with
 * the site's J2 gradient but the path from rest, measured: 2.9e-4 m/s). */
static void test_instrument_errors_navigated(void **state)
{
    (void)state;
    double with = instrument_errors(IGEA_DW_NAVIGATED, FL.site);
    double without = instrument_errors(IGEA_DW_NAVIGATED, NULL);
    assert_true(with < 1e-7);
    assert_true(without > 1e-4 && without < 1e-3);
}

/* Navigated velocity from ideal records: v_nav - v_trk, limited by the
 * trapezoid position step (its gravity error G dr). */
static void test_closed_loop_navigated(void **state)
{
    (void)state;
    KIND = IGEA_DW_NAVIGATED;
    for (int platform = 0; platform < 2; platform++) {
        double *tel = telemetry(platform, NULL, NULL, 0.0);
        double *trk = tracking(IGEA_NAV_ECEF, 7, FL.ep, FL.nep);
        double dw[3 * 400];
        assert_int_equal(run_dw(platform, tel, IGEA_NAV_ECEF, trk, FL.nep, 7, 0.0, dw, NULL,
                                NULL), 0);
        double m = max_abs(dw, 3 * FL.nep);
        print_message("closed loop, navigated, %s: max |dV| = %.3e m/s\n",
                      platform ? "platform" : "strapdown", m);
        assert_true(m < 1e-5);
        free(tel);
        free(trk);
    }
    KIND = IGEA_DW_APPARENT;
}

/* ---- clock offset: dW = f tau, recovered ------------------------------- */
/* A remaining offset tau moves the telemetry (W_tel(t) -> W(t + tau)) and
 * the lift-off time that fixes LI (by -tau): to first order dW = [f(t) -
 * f_pad - w x W(t)] tau, with f_pad = w x v_pad - g(0) the specific force
 * at rest on the pad and w the Earth rate in LI (the frame turned by w
 * tau). The leading term is f(t) - f_pad; w x W is a few percent. */
static void clock_run(double tau, const double *ep, int nep, double *dw, double *col)
{
    double *tel = telemetry(0, NULL, NULL, tau), *trk = tracking(IGEA_NAV_ECEF, 7, ep, nep);
    assert_int_equal(run_dw(0, tel, IGEA_NAV_ECEF, trk, nep, 7, 0.0, dw, NULL, col), 0);
    free(tel);
    free(trk);
}

static void test_clock_offset(void **state)
{
    (void)state;
    KIND = IGEA_DW_APPARENT;
    double ep[400], tau = 5e-3;
    int nep = make_epochs(ep, DUR - 1); /* the last second lies beyond the shifted record */
    double dw[3 * 400], col[3 * 400], dw2[3 * 400], col2[3 * 400];
    clock_run(tau, ep, nep, dw, col);
    clock_run(0.5 * tau, ep, nep, dw2, col2);
    double num = 0.0, den = 0.0, res = 0.0, res2 = 0.0, dev = 0.0, fmax_ = 0.0;
    /* the test's own first-order column */
    double fb[3], gI[3], g0[3], w[3], rc[3], vpad[3], fpad[3];
    const double *C = FL.F.C;
    grav(FL.F.r0, gI);
    for (int i = 0; i < 3; i++) {
        g0[i] = C[3 * i] * gI[0] + C[3 * i + 1] * gI[1] + C[3 * i + 2] * gI[2];
        rc[i] = C[3 * i] * FL.F.r0[0] + C[3 * i + 1] * FL.F.r0[1] + C[3 * i + 2] * FL.F.r0[2];
        w[i] = WE * C[3 * i + 2];
    }
    cross3(w, rc, vpad);
    cross3(w, vpad, fpad);
    for (int i = 0; i < 3; i++)
        fpad[i] -= g0[i];
    for (int e = 0; e < nep; e++) {
        double Cq[9], fl[3], wW[3];
        long k = lround(ep[e] / H);
        quat_dcm(FL.X + (size_t)k * NX + 6, Cq);
        force_b(ep[e], fb);
        cross3(w, FL.X + (size_t)k * NX + 10, wW);
        for (int i = 0; i < 3; i++) {
            fl[i] = Cq[3 * i] * fb[0] + Cq[3 * i + 1] * fb[1] + Cq[3 * i + 2] * fb[2];
            dev = fmax(dev, fabs(col[3 * e + i] - (fl[i] - fpad[i] - wW[i])));
            fmax_ = fmax(fmax_, fabs(fl[i]));
        }
    }
    for (int r = 0; r < 3 * nep; r++) {
        num += col[r] * dw[r];
        den += col[r] * col[r];
        res = fmax(res, fabs(dw[r] - col[r] * tau));
        res2 = fmax(res2, fabs(dw2[r] - col2[r] * 0.5 * tau));
    }
    double that = num / den;
    print_message("clock offset 5 ms: estimated %.6f ms; max |dW - col tau| %.3e (5 ms), %.3e "
                  "(2.5 ms), ratio %.2f; max |col - (f - f_pad - w x W)| %.3e of %.3g m/s^2\n",
                  1e3 * that, res, res2, res / res2, dev, fmax_);
    assert_close(that, tau, 1e-3);
    assert_true(res / res2 > 3.5);             /* the rest is second order */
    assert_true(dev < 1e-3 * fmax_); /* 1.3e-4 measured: the pad node of the path */
    /* given the offset, the difference vanishes */
    double *tel = telemetry(0, NULL, NULL, tau), *trk = tracking(IGEA_NAV_ECEF, 7, ep, nep);
    assert_int_equal(run_dw(0, tel, IGEA_NAV_ECEF, trk, nep, 7, tau, dw, NULL, NULL), 0);
    assert_true(max_abs(dw, 3 * nep) < 1e-6);
    free(tel);
    free(trk);
}

/* ---- covariance rotation and refusals ----------------------------------- */
static void test_covariance(void **state)
{
    (void)state;
    KIND = IGEA_DW_APPARENT;
    double ep[3] = {0.0, 100.0, 250.0};
    double *tel = telemetry(0, NULL, NULL, 0.0), *trk = tracking(IGEA_NAV_LE, 13, ep, 3);
    /* a full covariance: c_xx c_xy c_xz c_yy c_yz c_zz */
    const double P[6] = {4e-4, 1e-4, -5e-5, 9e-4, 2e-5, 1e-4};
    for (int e = 0; e < 3; e++)
        for (int c = 0; c < 6; c++)
            trk[e + 3 * (7 + c)] = P[c];
    double dw[9], cov[18];
    assert_int_equal(run_dw(0, tel, IGEA_NAV_LE, trk, 3, 13, 0.0, dw, cov, NULL), 0);
    double Pm[9] = {P[0], P[1], P[2], P[1], P[3], P[4], P[2], P[4], P[5]};
    for (int e = 0; e < 3; e++) {
        /* LE -> LI after t: M = C R(w t) C^T, R the rotation about ECEF z */
        double t = ep[e], c = cos(WE * t), s = sin(WE * t), R[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
        double M[9], T1[9], Q[9];
        const double *C = FL.F.C;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double a = 0.0;
                for (int k = 0; k < 3; k++)
                    for (int l = 0; l < 3; l++)
                        a += C[3 * i + k] * R[3 * k + l] * C[3 * j + l];
                M[3 * i + j] = a;
            }
        for (int i = 0; i < 9; i++)
            T1[i] = 0.0;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                for (int k = 0; k < 3; k++)
                    T1[3 * i + j] += M[3 * i + k] * Pm[3 * k + j];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                Q[3 * i + j] = 0.0;
                for (int k = 0; k < 3; k++)
                    Q[3 * i + j] += T1[3 * i + k] * M[3 * j + k];
            }
        const int up[6] = {0, 1, 2, 4, 5, 8};
        for (int k = 0; k < 6; k++)
            assert_close_abs(cov[6 * e + k], Q[up[k]], 1e-9, 1e-18);
    }
    trk[0 + 3 * 10] = -1.0; /* c_yy < 0: not positive definite */
    double keep[9];
    memcpy(keep, dw, sizeof keep);
    assert_int_equal(run_dw(0, tel, IGEA_NAV_LE, trk, 3, 13, 0.0, dw, cov, NULL),
                     IGEA_ENONPOSITIVE);
    assert_memory_equal(dw, keep, sizeof keep);
    free(tel);
    free(trk);
}

/* The tracking position errors through the gravity integral
 * (igea_dw_compute_k): 28-column tracking in ECEF, position sigma 20 m,
 * velocity 1e-3 m/s, uncorrelated, epochs every second. The position
 * error of epoch j moves the integral over the intervals on either side
 * of it by about h G(r_j) dr_j, a step of a random walk that every later
 * epoch shares: the block X_e = Cov(dW_e, dW_f > e) grows from e1 to e2
 * by sigma_r^2 h^2 sum_j G_j^2 (the trace rotation-free: sum_j tr G_j^2),
 * G here the central differences of this test's own J2 gravity at the
 * reference flight's positions. dW is that of igea_dw_compute bit for
 * bit; the navigated kind (no gravity integral) keeps igea_dw_compute's
 * covariance and X = 0; the refusals of xcov without cov (-17) and of a
 * NULL bad (-19). */
static void test_covariance_gravity(void **state)
{
    (void)state;
    enum { NE = 140 };
    const double sr = 20.0, sv = 1e-3;
    double ep[NE], dw0[3 * NE], dw[3 * NE], c0[6 * NE], c[6 * NE], x[9 * NE];
    for (int e = 0; e < NE; e++)
        ep[e] = e + 1.0;
    double *tel = telemetry(0, NULL, NULL, 0.0), *trk = tracking(IGEA_NAV_ECEF, 28, ep, NE);
    for (int e = 0; e < NE; e++)
        for (int i = 0, col = 7; i < 6; i++)
            for (int j = i; j < 6; j++, col++)
                trk[e + (size_t)NE * col] = i != j ? 0.0 : i < 3 ? sr * sr : sv * sv;
    int bad = 7, sd = IGEA_ENVFUN_STRAPDOWN;
    for (int kind = 0; kind < 2; kind++) {
        assert_int_equal(igea_dw_compute(FL.site, sd, kind, FL.q0, 0.0, NREC, tel, NREC, 7,
                                         IGEA_NAV_ECEF, NE, trk, NE, 28, dw0, c0, NULL, &bad), 0);
        assert_int_equal(igea_dw_compute_k(FL.site, sd, kind, FL.q0, 0.0, NREC, tel, NREC, 7,
                                           IGEA_NAV_ECEF, NE, trk, NE, 28, dw, c, x, NULL, &bad),
                         0);
        assert_int_equal(bad, -1);
        assert_memory_equal(dw, dw0, sizeof dw);
        if (kind == IGEA_DW_NAVIGATED) {
            assert_memory_equal(c, c0, sizeof c);
            for (int i = 0; i < 9 * NE; i++)
                assert_true(x[i] == 0.0);
        }
    }
    /* the apparent kind */
    assert_int_equal(igea_dw_compute(FL.site, sd, IGEA_DW_APPARENT, FL.q0, 0.0, NREC, tel, NREC,
                                     7, IGEA_NAV_ECEF, NE, trk, NE, 28, dw0, c0, NULL, &bad), 0);
    assert_int_equal(igea_dw_compute_k(FL.site, sd, IGEA_DW_APPARENT, FL.q0, 0.0, NREC, tel,
                                       NREC, 7, IGEA_NAV_ECEF, NE, trk, NE, 28, dw, c, x, NULL,
                                       &bad), 0);
    const int e1 = 19, e2 = 119;
    double sum = 0.0;
    for (int j = e1 + 1; j <= e2; j++) { /* steps j = e1 + 1 .. e2 */
        const double *xs = FL.X + (size_t)lround(ep[j] / H) * NX;
        double G[9];
        for (int k = 0; k < 3; k++) {
            double rp[3] = {xs[0], xs[1], xs[2]}, rm[3] = {xs[0], xs[1], xs[2]}, gp[3], gm[3];
            rp[k] += 1.0;
            rm[k] -= 1.0;
            grav(rp, gp);
            grav(rm, gm);
            for (int i = 0; i < 3; i++)
                G[3 * i + k] = 0.5 * (gp[i] - gm[i]);
        }
        for (int i = 0; i < 9; i++)
            sum += G[i] * G[(i % 3) * 3 + i / 3]; /* tr(G G^T) */
    }
    double want = sr * sr * sum, got = 0.0, grow = 0.0;
    for (int i = 0; i < 3; i++)
        got += x[9 * e2 + 4 * i] - x[9 * e1 + 4 * i];
    for (int e = 1; e < NE; e++) /* the gravity part adds variance, growing */
        grow = fmax(grow, (c[6 * e] + c[6 * e + 3] + c[6 * e + 5]) -
                              (c0[6 * e] + c0[6 * e + 3] + c0[6 * e + 5]));
    print_message("gravity integral in K: tr(X_%d - X_%d) %.6e m^2/s^2, sigma_r^2 sum tr G^2 "
                  "%.6e (ratio %.5f); the diagonal blocks gain up to %.3e\n", e2, e1, got, want,
                  got / want, grow);
    assert_close(got, want, 2e-3);
    assert_true(grow > 0.5 * want);
    /* refusals; outputs untouched */
    double keep[3 * NE];
    memcpy(keep, dw, sizeof keep);
    assert_int_equal(igea_dw_compute_k(FL.site, sd, IGEA_DW_APPARENT, FL.q0, 0.0, NREC, tel,
                                       NREC, 7, IGEA_NAV_ECEF, NE, trk, NE, 28, dw, NULL, x,
                                       NULL, &bad), -17);
    assert_int_equal(igea_dw_compute_k(FL.site, sd, IGEA_DW_APPARENT, FL.q0, 0.0, NREC, tel,
                                       NREC, 7, IGEA_NAV_ECEF, NE, trk, NE, 28, dw, c, x, NULL,
                                       NULL), -19);
    assert_int_equal(igea_dw_compute_k(FL.site, sd, IGEA_DW_APPARENT, FL.q0, 0.0, NREC, tel,
                                       NREC, 7, IGEA_NAV_ECEF, NE, trk, NE, 7, dw, c, x, NULL,
                                       &bad), -16);
    assert_memory_equal(dw, keep, sizeof keep);
    free(tel);
    free(trk);
}

static void test_refusals(void **state)
{
    (void)state;
    double ep[3] = {10.0, 20.0, 30.0}, dw[9], keep[9];
    double *tel = telemetry(0, NULL, NULL, 0.0), *trk = tracking(IGEA_NAV_LE, 7, ep, 3);
    fill_sentinel(dw, 9);
    memcpy(keep, dw, sizeof keep);
    int bad = 99, sd = IGEA_ENVFUN_STRAPDOWN;
    trk[2] = 400.0; /* epoch 2 after the telemetry */
    assert_int_equal(igea_dw_compute(FL.site, sd, IGEA_DW_APPARENT, FL.q0, 0.0, NREC, tel, NREC, 7, IGEA_NAV_LE,
                                     3, trk, 3, 7, dw, NULL, NULL, &bad), IGEA_DW_ESPAN);
    assert_int_equal(bad, 2);
    trk[2] = 30.0;
    trk[1] = 5.0; /* epoch 1 before epoch 0 */
    assert_int_equal(igea_dw_compute(FL.site, sd, IGEA_DW_APPARENT, FL.q0, 0.0, NREC, tel, NREC, 7, IGEA_NAV_LE,
                                     3, trk, 3, 7, dw, NULL, NULL, &bad), IGEA_DW_ETRACK);
    assert_int_equal(bad, 1);
    trk[1] = 20.0;
    tel[17] = tel[16]; /* telemetry row 17 repeats a time */
    assert_int_equal(igea_dw_compute(FL.site, sd, IGEA_DW_APPARENT, FL.q0, 0.0, NREC, tel, NREC, 7, IGEA_NAV_LE,
                                     3, trk, 3, 7, dw, NULL, NULL, &bad), IGEA_DW_ETELEMETRY);
    assert_int_equal(bad, 17);
    tel[17] = 0.17;
    tel[5 + NREC] = NAN;
    assert_int_equal(igea_dw_compute(FL.site, sd, IGEA_DW_APPARENT, FL.q0, 0.0, NREC, tel, NREC, 7, IGEA_NAV_LE,
                                     3, trk, 3, 7, dw, NULL, NULL, &bad), IGEA_ENONFINITE);
    tel[5 + NREC] = 0.2;
    double cov[18];
    assert_int_equal(igea_dw_compute(FL.site, sd, IGEA_DW_APPARENT, FL.q0, 0.0, NREC, tel, NREC, 4, IGEA_NAV_LE,
                                     3, trk, 3, 7, dw, NULL, NULL, &bad), -9);
    assert_int_equal(igea_dw_compute(FL.site, sd, IGEA_DW_APPARENT, FL.q0, 0.0, NREC, tel, NREC, 7, IGEA_NAV_LE,
                                     3, trk, 3, 7, dw, cov, NULL, &bad), -16);
    assert_int_equal(igea_dw_compute(FL.site, sd, IGEA_DW_APPARENT, FL.q0, 0.0, NREC, tel, NREC, 7, IGEA_NAV_LI,
                                     3, trk, 3, 7, dw, NULL, NULL, &bad), -10);
    assert_memory_equal(dw, keep, sizeof keep);
    free(tel);
    free(trk);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_closed_loop),  cmocka_unit_test(test_instrument_errors),
        cmocka_unit_test(test_closed_loop_navigated),
        cmocka_unit_test(test_instrument_errors_navigated),
        cmocka_unit_test(test_clock_offset), cmocka_unit_test(test_covariance),
        cmocka_unit_test(test_covariance_gravity),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
