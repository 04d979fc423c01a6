/* tests/test_envfun.c - environment functions (METHODS 5) against closed
 * forms and against full nonlinear strapdown and platform error
 * simulations written here (METHODS 5.6). */
#include "testutil.h"

#include "igea/envfun.h"
#include "igea/nav.h"
#include "igea/sim.h"
#include "rotation.h"

#define DEG (3.14159265358979323846 / 180.0)
#define G0 9.80665

/* ---- small 3-D helpers (row-major 3x3) ---------------------------------- */
static void m3_mul(const double *a, const double *b, double *c)
{
    double t[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            t[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] +
                           a[3 * i + 2] * b[6 + j];
    memcpy(c, t, sizeof t);
}
static void m3_vec(const double *a, const double *x, double *y)
{
    double t[3];
    for (int i = 0; i < 3; i++)
        t[i] = a[3 * i] * x[0] + a[3 * i + 1] * x[1] + a[3 * i + 2] * x[2];
    memcpy(y, t, sizeof t);
}
static void m3_tvec(const double *a, const double *x, double *y)
{
    double t[3];
    for (int i = 0; i < 3; i++)
        t[i] = a[i] * x[0] + a[3 + i] * x[1] + a[6 + i] * x[2];
    memcpy(y, t, sizeof t);
}
/* exp([v x]) by its power series sum K^n / n! (independent of the
 * library's closed-form Rodrigues kernel). */
static void m3_exp(const double *v, double *R)
{
    double K[9] = {0, -v[2], v[1], v[2], 0, -v[0], -v[1], v[0], 0};
    double T[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(R, T, sizeof T);
    for (int n = 1; n < 60; n++) {
        double mx = 0.0;
        m3_mul(T, K, T);
        for (int i = 0; i < 9; i++) {
            T[i] /= n;
            R[i] += T[i];
            mx = fmax(mx, fabs(T[i]));
        }
        if (mx < 1e-300 || (n > 3 && mx < 1e-18))
            break;
    }
}
/* Direction cosines of a quaternion (any norm > 0) by the axis-angle
 * formula C = cos(t) I + (1 - cos(t)) n n^T + sin(t) [n x], t = 2 atan2(|v|,
 * q0), n = v / |v| (independent of the library's quaternion polynomial). */
static void q_dcm(const double *q0, double *C)
{
    double vn = sqrt(q0[1] * q0[1] + q0[2] * q0[2] + q0[3] * q0[3]);
    double t = 2.0 * atan2(vn, q0[0]), c = cos(t), s = sin(t);
    double n[3] = {0, 0, 0};
    if (vn > 0)
        for (int i = 0; i < 3; i++)
            n[i] = q0[1 + i] / vn;
    double N[9] = {0, -n[2], n[1], n[2], 0, -n[0], -n[1], n[0], 0};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            C[3 * i + j] = (i == j ? c : 0.0) + (1.0 - c) * n[i] * n[j] + s * N[3 * i + j];
}

/* Instrument errors, indexed by term code, in SI units (METHODS 5.6 sizes). */
static void error_sizes(double *err)
{
    double gyro = 0.5 * DEG / 3600.0;
    for (int k = 0; k < IGEA_ENVFUN_TERM_COUNT; k++)
        err[k] = 0.0;
    for (int a = 0; a < 3; a++) {
        err[IGEA_ENVFUN_TERM_ACC_BIAS_X + a] = 1e-3 * G0 * (a == 1 ? -0.8 : 1.0);
        err[IGEA_ENVFUN_TERM_ACC_SCALE_X + a] = 1e-4 * (a == 2 ? -1.0 : 1.0);
        err[IGEA_ENVFUN_TERM_ACC_SQ_X + a] = 1e-5 / G0;
        err[IGEA_ENVFUN_TERM_GYRO_BIAS_X + a] = gyro * (a == 0 ? -1.0 : 1.0);
        err[IGEA_ENVFUN_TERM_GYRO_G_X + a] = gyro / G0;
        err[IGEA_ENVFUN_TERM_GYRO_SCALE_X + a] = 1e-4;
        err[IGEA_ENVFUN_TERM_ATT0_X + a] = 1e-4 * (a == 1 ? -1.0 : 1.0);
        err[IGEA_ENVFUN_TERM_GYRO_GI_X + a] = gyro / G0;
        err[IGEA_ENVFUN_TERM_GYRO_GS_X + a] = -gyro / G0;
        err[IGEA_ENVFUN_TERM_ALIGN0_X + a] = 1e-4 * (a == 0 ? -1.0 : 1.0);
    }
    for (int k = IGEA_ENVFUN_TERM_ACC_MIS_XY; k <= IGEA_ENVFUN_TERM_ACC_MIS_ZY; k++)
        err[k] = 1e-4 * ((k % 2) ? 1.0 : -1.0);
}

/* Accelerometer reading with errors err (by code) of true force f. */
static void acc_read(const double *err, const double *f, double *out)
{
    static const int mj[6] = {0, 0, 1, 1, 2, 2}, mk[6] = {1, 2, 0, 2, 0, 1};
    for (int a = 0; a < 3; a++)
        out[a] = f[a] + err[IGEA_ENVFUN_TERM_ACC_BIAS_X + a] +
                 err[IGEA_ENVFUN_TERM_ACC_SCALE_X + a] * f[a] +
                 err[IGEA_ENVFUN_TERM_ACC_SQ_X + a] * f[a] * f[a];
    for (int i = 0; i < 6; i++)
        out[mj[i]] += err[IGEA_ENVFUN_TERM_ACC_MIS_XY + i] * f[mk[i]];
}

/* Full nonlinear strapdown navigation with errors err; dW (3 x nsamp,
 * sample-major) = computed - error-free apparent velocity. */
static void nonlinear_strapdown(const double *tr, int n, const double *err,
                                double *dW)
{
    double C[9], Ch[9], W[3] = {0, 0, 0}, Wh[3] = {0, 0, 0};
    double fa_p[3], fh_p[3], w_p[3], wh_p[3], phi0[3], E[9];
    {
        double q[4];
        for (int i = 0; i < 4; i++)
            q[i] = tr[(size_t)(7 + i) * n];
        q_dcm(q, C);
    }
    for (int a = 0; a < 3; a++)
        phi0[a] = -err[IGEA_ENVFUN_TERM_ATT0_X + a];
    m3_exp(phi0, E); /* Chat = exp(-[phi0 x]) C */
    m3_mul(E, C, Ch);
    for (int k = 0; k < n; k++) {
        double f[3], w[3], fh[3], wh[3], fa[3], fha[3];
        for (int a = 0; a < 3; a++) {
            f[a] = tr[k + (size_t)(1 + a) * n];
            w[a] = tr[k + (size_t)(4 + a) * n];
        }
        acc_read(err, f, fh);
        for (int a = 0; a < 3; a++)
            wh[a] = w[a] + err[IGEA_ENVFUN_TERM_GYRO_BIAS_X + a] +
                    err[IGEA_ENVFUN_TERM_GYRO_G_X + a] * f[a] +
                    err[IGEA_ENVFUN_TERM_GYRO_SCALE_X + a] * w[a];
        if (k > 0) {
            double h = tr[k] - tr[k - 1], v[3], vh[3], R[9];
            for (int a = 0; a < 3; a++) {
                v[a] = 0.5 * h * (w_p[a] + w[a]);
                vh[a] = 0.5 * h * (wh_p[a] + wh[a]);
            }
            m3_exp(v, R);
            m3_mul(C, R, C);
            m3_exp(vh, R);
            m3_mul(Ch, R, Ch);
        }
        m3_vec(C, f, fa);
        m3_vec(Ch, fh, fha);
        if (k > 0) {
            double h = tr[k] - tr[k - 1];
            for (int a = 0; a < 3; a++) {
                W[a] += 0.5 * h * (fa_p[a] + fa[a]);
                Wh[a] += 0.5 * h * (fh_p[a] + fha[a]);
            }
        }
        for (int a = 0; a < 3; a++) {
            dW[3 * (size_t)k + a] = Wh[a] - W[a];
            fa_p[a] = fa[a];
            fh_p[a] = fha[a];
            w_p[a] = w[a];
            wh_p[a] = wh[a];
        }
    }
}

/* Full nonlinear platform navigation: the platform (C_p^a) starts rotated
 * by alpha0 and drifts at eps (platform axes); accelerometers read the
 * platform-axis force with errors; the navigator takes it as inertial.
 * With grav, also integrates v' = f + g(r) (true and computed) and
 * returns velocity (dV) and position (dR) errors; else dV = dW. */
static void gravity_pm(const double *r, double *g)
{
    double p[3] = {r[0], r[1] + 6371000.0, r[2]};
    double n = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int a = 0; a < 3; a++)
        g[a] = -3.986004418e14 * p[a] / (n * n * n);
}
static void nonlinear_platform(const double *tr, int n, const double *err,
                               const int *in_ax, const int *spin_ax, int grav,
                               double *dV, double *dR)
{
    double P[9], a0[3], W[3] = {0, 0, 0}, Wh[3] = {0, 0, 0};
    double fa_p[3] = {0}, fh_p[3] = {0}, eps_p[3] = {0};
    double r[3] = {0, 0, 0}, v[3] = {0, 0, 0}, rh[3] = {0, 0, 0}, vh[3] = {0, 0, 0};
    for (int a = 0; a < 3; a++)
        a0[a] = err[IGEA_ENVFUN_TERM_ALIGN0_X + a];
    m3_exp(a0, P); /* C_p^a = exp([alpha0 x]) */
    for (int k = 0; k < n; k++) {
        double fa[3], fp[3], fh[3], eps[3];
        for (int a = 0; a < 3; a++)
            fa[a] = tr[k + (size_t)(1 + a) * n];
        if (k > 0) {
            /* drift over the step: predictor for eps at k */
            double h = tr[k] - tr[k - 1], rv[3], R[9], Pt[9], fpk[3], ek[3];
            memcpy(Pt, P, sizeof Pt);
            for (int it = 0; it < 2; it++) {
                m3_tvec(Pt, fa, fpk);
                for (int j = 0; j < 3; j++)
                    ek[j] = err[IGEA_ENVFUN_TERM_GYRO_BIAS_X + j] +
                            err[IGEA_ENVFUN_TERM_GYRO_GI_X + j] * fpk[in_ax[j]] +
                            err[IGEA_ENVFUN_TERM_GYRO_GS_X + j] * fpk[spin_ax[j]];
                for (int j = 0; j < 3; j++)
                    rv[j] = 0.5 * h * (eps_p[j] + ek[j]);
                m3_exp(rv, R);
                m3_mul(P, R, Pt);
            }
            memcpy(P, Pt, sizeof Pt);
        }
        m3_tvec(P, fa, fp); /* f^p = C_a^p f^a */
        acc_read(err, fp, fh);
        for (int j = 0; j < 3; j++)
            eps[j] = err[IGEA_ENVFUN_TERM_GYRO_BIAS_X + j] +
                     err[IGEA_ENVFUN_TERM_GYRO_GI_X + j] * fp[in_ax[j]] +
                     err[IGEA_ENVFUN_TERM_GYRO_GS_X + j] * fp[spin_ax[j]];
        if (k > 0) {
            double h = tr[k] - tr[k - 1];
            if (grav) { /* velocity Verlet, true and computed */
                double g[3], gh[3];
                gravity_pm(r, g);
                gravity_pm(rh, gh);
                for (int a = 0; a < 3; a++) {
                    v[a] += 0.5 * h * (fa_p[a] + g[a]);
                    vh[a] += 0.5 * h * (fh_p[a] + gh[a]);
                    r[a] += h * v[a];
                    rh[a] += h * vh[a];
                }
                gravity_pm(r, g);
                gravity_pm(rh, gh);
                for (int a = 0; a < 3; a++) {
                    v[a] += 0.5 * h * (fa[a] + g[a]);
                    vh[a] += 0.5 * h * (fh[a] + gh[a]);
                }
            }
            for (int a = 0; a < 3; a++) {
                W[a] += 0.5 * h * (fa_p[a] + fa[a]);
                Wh[a] += 0.5 * h * (fh_p[a] + fh[a]);
            }
        }
        for (int a = 0; a < 3; a++) {
            dV[3 * (size_t)k + a] = grav ? vh[a] - v[a] : Wh[a] - W[a];
            if (dR)
                dR[3 * (size_t)k + a] = rh[a] - r[a];
            fa_p[a] = fa[a];
            fh_p[a] = fh[a];
            eps_p[a] = eps[a];
        }
    }
}

/* ---- fixtures ------------------------------------------------------------ */
#define T_DUR 120.0
#define RATE 50.0
#define N_EP 121 /* epochs 0, 1, ..., 120 s */

static double *make_traj(int system, int *n)
{
    assert_int_equal(igea_sim_trajectory_length(T_DUR, RATE, n), 0);
    double *tr = malloc(sizeof(double) * (size_t)*n * IGEA_ENVFUN_TRAJ_COLS);
    assert_non_null(tr);
    assert_int_equal(igea_sim_trajectory(system, T_DUR, RATE, *n, tr, *n), 0);
    return tr;
}

static int all_terms(int system, int *codes)
{
    int n = 0;
    for (int k = 0; k < IGEA_ENVFUN_TERM_COUNT; k++)
        if (igea_envfun_term_valid(system, k))
            codes[n++] = k;
    return n;
}

/* Compare S (scaled by the error sizes) with the nonlinear errors dWn at
 * epochs = integer seconds (sample index e * RATE): each term alone and
 * all together. Returns the worst relative discrepancies. */
static void compare_terms(int system, double scale, const int *codes, int nt,
                          double *worst_single, double *worst_all,
                          double *final_norm)
{
    int n;
    double *tr = make_traj(system, &n), err[IGEA_ENVFUN_TERM_COUNT];
    double ep[N_EP], spec[IGEA_ENVFUN_TERM_COUNT];
    int m = 3 * N_EP;
    double *S = malloc(sizeof(double) * (size_t)m * nt);
    double *dW = malloc(sizeof(double) * 3 * (size_t)n);
    double one[IGEA_ENVFUN_TERM_COUNT];
    assert_non_null(S);
    assert_non_null(dW);
    error_sizes(err);
    for (int k = 0; k < IGEA_ENVFUN_TERM_COUNT; k++)
        err[k] *= scale;
    for (int e = 0; e < N_EP; e++)
        ep[e] = e;
    for (int j = 0; j < nt; j++)
        spec[j] = fabs(err[codes[j]]); /* X_j = sign of the error */
    assert_int_equal(igea_envfun_compute(system, n, tr, n, nt, codes, NULL,
                                         N_EP, ep, spec, IGEA_ENVFUN_VELOCITY,
                                         S, m),
                     0);
    int in_ax[3] = {0, 1, 2}, spin_ax[3] = {1, 2, 0};
    *worst_single = 0.0;
    for (int j = -1; j < nt; j++) {
        /* j = -1: all terms together */
        for (int k = 0; k < IGEA_ENVFUN_TERM_COUNT; k++)
            one[k] = 0.0;
        for (int c = 0; c < nt; c++)
            if (j < 0 || c == j)
                one[codes[c]] = err[codes[c]];
        if (system == IGEA_ENVFUN_STRAPDOWN)
            nonlinear_strapdown(tr, n, one, dW);
        else
            nonlinear_platform(tr, n, one, in_ax, spin_ax, 0, dW, NULL);
        double maxd = 0.0, maxn = 0.0;
        for (int e = 0; e < N_EP; e++) {
            size_t k = (size_t)(e * (int)RATE);
            for (int a = 0; a < 3; a++) {
                double lin = 0.0;
                for (int c = 0; c < nt; c++)
                    if (j < 0 || c == j)
                        lin += S[3 * e + a + (size_t)c * m] *
                               (err[codes[c]] < 0 ? -1.0 : 1.0);
                double nl = dW[3 * k + a];
                maxd = fmax(maxd, fabs(lin - nl));
                maxn = fmax(maxn, fabs(nl));
            }
        }
        double rel = maxd / maxn;
        if (j < 0) {
            *worst_all = rel;
            double fn = 0.0;
            for (int a = 0; a < 3; a++)
                fn += dW[3 * (size_t)(n - 1) + a] * dW[3 * (size_t)(n - 1) + a];
            *final_norm = sqrt(fn);
        } else {
            if (rel > *worst_single)
                *worst_single = rel;
            if (rel > 5e-4)
                print_error("term code %d: relative discrepancy %.3g\n",
                            codes[j], rel);
        }
        assert_true(maxn > 1e-7); /* every term visibly moves W */
    }
    free(S);
    free(dW);
    free(tr);
}

static void compare(int system, double scale, double *worst_single,
                    double *worst_all, double *final_norm)
{
    int codes[IGEA_ENVFUN_TERM_COUNT], nt = all_terms(system, codes);
    compare_terms(system, scale, codes, nt, worst_single, worst_all, final_norm);
}

/* The 21-term strapdown model of METHODS 5.5/5.6 (no acc_sq, gyro_scale):
 * METHODS 5.6 reports 8.4e-5 relative (all terms), 1.5e-4 worst single,
 * for its own trajectory and error signs; here 4.2e-4 and 1.3e-4, second
 * order in the error sizes (see check_system). */
static void test_strapdown21_vs_nonlinear(void **state)
{
    int codes[21], k = 0;
    double ws, wa, fn;
    for (int c = 0; c < IGEA_ENVFUN_TERM_GYRO_SCALE_X; c++)
        if (c < IGEA_ENVFUN_TERM_ACC_SQ_X || c >= IGEA_ENVFUN_TERM_ACC_MIS_XY)
            codes[k++] = c;
    for (int a = 0; a < 3; a++)
        codes[k++] = IGEA_ENVFUN_TERM_ATT0_X + a;
    assert_int_equal(k, 21);
    compare_terms(IGEA_ENVFUN_STRAPDOWN, 1.0, codes, 21, &ws, &wa, &fn);
    print_message("strapdown, 21 terms: final |dW| %.3g m/s, all terms rel %.3g, "
                  "worst single term rel %.3g\n", fn, wa, ws);
    assert_true(wa < 6e-4);
    assert_true(ws < 3e-4);
}

/* The discrepancy is second order: halving every error halves the
 * relative discrepancy (a wrong sign or integral would leave it O(1)). */
static void check_system(int system, const char *name)
{
    double ws, wa, fn, ws2, wa2, fn2;
    compare(system, 1.0, &ws, &wa, &fn);
    compare(system, 0.5, &ws2, &wa2, &fn2);
    print_message("%s: final |dW| %.3g m/s, all 27 terms rel %.3g, worst "
                  "single term rel %.3g; errors halved: %.3g, %.3g\n",
                  name, fn, wa, ws, wa2, ws2);
    assert_true(fn > 0.5);
    assert_true(wa < 6e-4);
    assert_true(ws < 3e-4);
    assert_true(wa2 / wa > 0.4 && wa2 / wa < 0.6);
    assert_true(ws2 / ws > 0.4 && ws2 / ws < 0.6);
}

static void test_strapdown_vs_nonlinear(void **state)
{
    check_system(IGEA_ENVFUN_STRAPDOWN, "strapdown");
}

static void test_platform_vs_nonlinear(void **state)
{
    check_system(IGEA_ENVFUN_PLATFORM, "platform");
}

/* igea_sim_nonlinear (the library's truth model) agrees with the
 * simulations written here to rounding: both implement the same physics
 * independently. */
static void test_library_truth_model(void **state)
{
    for (int system = 0; system < 2; system++) {
        int n, in_ax[3] = {0, 1, 2}, spin_ax[3] = {1, 2, 0};
        double *tr = make_traj(system, &n), err[IGEA_ENVFUN_TERM_COUNT], ep[N_EP];
        double *dW = malloc(sizeof(double) * 3 * (size_t)n), lib[3 * N_EP];
        error_sizes(err);
        for (int k = 0; k < IGEA_ENVFUN_TERM_COUNT; k++)
            if (!igea_envfun_term_valid(system, k))
                err[k] = 0.0;
        for (int e = 0; e < N_EP; e++)
            ep[e] = e;
        if (system == IGEA_ENVFUN_STRAPDOWN)
            nonlinear_strapdown(tr, n, err, dW);
        else
            nonlinear_platform(tr, n, err, in_ax, spin_ax, 0, dW, NULL);
        assert_int_equal(igea_sim_nonlinear(system, n, tr, n, err, NULL, N_EP, ep, lib), 0);
        double md = 0, mn = 0;
        for (int e = 0; e < N_EP; e++)
            for (int a = 0; a < 3; a++) {
                double ref = dW[3 * (size_t)(e * (int)RATE) + a];
                md = fmax(md, fabs(lib[3 * e + a] - ref));
                mn = fmax(mn, fabs(ref));
            }
        assert_true(md <= 1e-9 * mn);
        /* no errors: exactly zero */
        double zero[IGEA_ENVFUN_TERM_COUNT] = {0};
        assert_int_equal(igea_sim_nonlinear(system, n, tr, n, zero, NULL, N_EP, ep, lib), 0);
        for (int i = 0; i < 3 * N_EP; i++)
            assert_true(lib[i] == 0.0);
        free(dW);
        free(tr);
    }
}

/* Gravity-gradient coupling (METHODS 5.4): platform accelerometer biases
 * (exactly linear in W) against a nonlinear navigation with point-mass
 * gravity; the uncoupled position function must miss by much more. */
static void test_gravity_coupling(void **state)
{
    int n, codes[3] = {IGEA_ENVFUN_TERM_ACC_BIAS_X, IGEA_ENVFUN_TERM_ACC_BIAS_X + 1,
                       IGEA_ENVFUN_TERM_ACC_BIAS_X + 2};
    int in_ax[3] = {0, 1, 2}, spin_ax[3] = {1, 2, 0};
    double *tr = make_traj(IGEA_ENVFUN_PLATFORM, &n), err[IGEA_ENVFUN_TERM_COUNT];
    double ep[N_EP], spec[3], S[4][3 * N_EP];
    double *dV = malloc(sizeof(double) * 3 * (size_t)n);
    double *dR = malloc(sizeof(double) * 3 * (size_t)n);
    error_sizes(err);
    for (int k = 0; k < IGEA_ENVFUN_TERM_COUNT; k++)
        if (k > IGEA_ENVFUN_TERM_ACC_BIAS_X + 2)
            err[k] = 0.0;
    for (int a = 0; a < 3; a++)
        spec[a] = fabs(err[codes[a]]);
    for (int e = 0; e < N_EP; e++)
        ep[e] = e;
    for (int o = 0; o < 4; o++) {
        double full[3 * N_EP * 3];
        assert_int_equal(igea_envfun_compute(IGEA_ENVFUN_PLATFORM, n, tr, n, 3,
                                             codes, NULL, N_EP, ep, spec, o,
                                             full, 3 * N_EP),
                         0);
        for (int i = 0; i < 3 * N_EP; i++)
            S[o][i] = full[i] * (err[codes[0]] < 0 ? -1 : 1) +
                      full[i + 3 * N_EP] * (err[codes[1]] < 0 ? -1 : 1) +
                      full[i + 6 * N_EP] * (err[codes[2]] < 0 ? -1 : 1);
    }
    nonlinear_platform(tr, n, err, in_ax, spin_ax, 1, dV, dR);
    double dv_g = 0, dr_g = 0, dv_0 = 0, dr_0 = 0, nv = 0, nr = 0;
    for (int e = 0; e < N_EP; e++)
        for (int a = 0; a < 3; a++) {
            size_t k = 3 * (size_t)(e * (int)RATE) + a;
            dv_g = fmax(dv_g, fabs(S[IGEA_ENVFUN_VELOCITY_G][3 * e + a] - dV[k]));
            dr_g = fmax(dr_g, fabs(S[IGEA_ENVFUN_POSITION_G][3 * e + a] - dR[k]));
            dv_0 = fmax(dv_0, fabs(S[IGEA_ENVFUN_VELOCITY][3 * e + a] - dV[k]));
            dr_0 = fmax(dr_0, fabs(S[IGEA_ENVFUN_POSITION][3 * e + a] - dR[k]));
            nv = fmax(nv, fabs(dV[k]));
            nr = fmax(nr, fabs(dR[k]));
        }
    print_message("gravity: velocity rel %.3g (uncoupled %.3g), position rel "
                  "%.3g (uncoupled %.3g)\n", dv_g / nv, dv_0 / nv, dr_g / nr,
                  dr_0 / nr);
    assert_true(dv_g / nv < 2e-5);
    assert_true(dr_g / nr < 2e-5);
    assert_true(dv_0 / nv > 1e-3);
    assert_true(dr_0 / nr > 3e-4);
    free(dV);
    free(dR);
    free(tr);
}

/* Closed forms on a constant-force, non-rotating trajectory (METHODS 5.2,
 * 5.3): bias t e_j, scale W_j e_j, gyro bias t^2/2 (e_j x f) (strapdown)
 * or t^2/2 (f x e_j) (platform), attitude W x e_k; position = t^3/6 etc. */
static void test_closed_forms(void **state)
{
    enum { NS = 11 };
    double tr[NS * IGEA_ENVFUN_TRAJ_COLS], f[3] = {3.0, -2.0, 12.0};
    for (int k = 0; k < NS; k++) {
        tr[k] = 0.5 * k;
        for (int a = 0; a < 3; a++) {
            tr[k + (1 + a) * NS] = f[a];
            tr[k + (4 + a) * NS] = 0.0;
        }
        tr[k + 7 * NS] = 2.0; /* unnormalised identity quaternion */
        tr[k + 8 * NS] = tr[k + 9 * NS] = tr[k + 10 * NS] = 0.0;
    }
    double ep[2] = {1.75, 5.0}; /* 1.75 s lies between samples */
    int sd[4] = {IGEA_ENVFUN_TERM_ACC_BIAS_X + 1, IGEA_ENVFUN_TERM_ACC_SCALE_X + 2,
                 IGEA_ENVFUN_TERM_GYRO_BIAS_X, IGEA_ENVFUN_TERM_ATT0_X + 1};
    int pf[4] = {IGEA_ENVFUN_TERM_ACC_BIAS_X + 1, IGEA_ENVFUN_TERM_ACC_MIS_XZ,
                 IGEA_ENVFUN_TERM_GYRO_BIAS_X, IGEA_ENVFUN_TERM_ALIGN0_X + 1};
    double S[6 * 4];
    assert_int_equal(igea_envfun_compute(IGEA_ENVFUN_STRAPDOWN, NS, tr, NS, 4,
                                         sd, NULL, 2, ep, NULL,
                                         IGEA_ENVFUN_VELOCITY, S, 6),
                     0);
    double t = 5.0, W[3] = {f[0] * t, f[1] * t, f[2] * t};
    assert_close(S[3 + 1], t, 1e-14);
    assert_close(S[6 + 3 + 2], f[2] * t, 1e-14);
    /* gyro x bias: t^2/2 (e_x x f) = t^2/2 (0, -f_z, f_y) */
    assert_close(S[12 + 3 + 1], -0.5 * t * t * f[2], 1e-14);
    assert_close(S[12 + 3 + 2], 0.5 * t * t * f[1], 1e-14);
    assert_close_abs(S[12 + 3 + 0], 0.0, 0, 1e-12);
    /* att0 y: W x e_y = (-W_z, 0, W_x) */
    assert_close(S[18 + 3 + 0], -W[2], 1e-14);
    assert_close(S[18 + 3 + 2], W[0], 1e-14);
    /* linear interpolation at 1.75 s of the bias column (exact: linear) */
    assert_close(S[1], 1.75, 1e-14);
    /* interpolation of a quadratic (gyro) between samples 1.5 and 2.0 */
    assert_close(S[12 + 1], -0.5 * f[2] * (0.5 * (1.5 * 1.5 + 2.0 * 2.0)), 1e-14);

    assert_int_equal(igea_envfun_compute(IGEA_ENVFUN_PLATFORM, NS, tr, NS, 4,
                                         pf, NULL, 2, ep, NULL,
                                         IGEA_ENVFUN_VELOCITY, S, 6),
                     0);
    assert_close(S[3 + 1], t, 1e-14);
    assert_close(S[6 + 3 + 0], W[2], 1e-14); /* mis xz: W_z e_x */
    /* f x e_x = (0, f_z, -f_y) */
    assert_close(S[12 + 3 + 1], 0.5 * t * t * f[2], 1e-14);
    assert_close(S[12 + 3 + 2], -0.5 * t * t * f[1], 1e-14);
    assert_close(S[18 + 3 + 0], -W[2], 1e-14);

    /* position without gravity: bias t^2/2 (exact for trapezoid of linear) */
    assert_int_equal(igea_envfun_compute(IGEA_ENVFUN_PLATFORM, NS, tr, NS, 4,
                                         pf, NULL, 2, ep, NULL,
                                         IGEA_ENVFUN_POSITION, S, 6),
                     0);
    assert_close(S[3 + 1], 0.5 * t * t, 1e-14);
}

/* Spec scaling multiplies columns; lds > m leaves NaN padding alone. */
static void test_spec_lds(void **state)
{
    int n, codes[IGEA_ENVFUN_TERM_COUNT], nt = all_terms(IGEA_ENVFUN_STRAPDOWN, codes);
    double *tr = make_traj(IGEA_ENVFUN_STRAPDOWN, &n);
    double ep[5] = {0.0, 10.01, 33.3, 33.3, 120.0}, spec[IGEA_ENVFUN_TERM_COUNT];
    int m = 15, ld = 19;
    double *S1 = malloc(sizeof(double) * m * nt);
    double *S2 = malloc(sizeof(double) * ld * nt);
    for (int j = 0; j < nt; j++)
        spec[j] = 0.5 + j;
    assert_int_equal(igea_envfun_compute(IGEA_ENVFUN_STRAPDOWN, n, tr, n, nt,
                                         codes, NULL, 5, ep, NULL, 0, S1, m), 0);
    fill_nan(S2, (size_t)ld * nt);
    assert_int_equal(igea_envfun_compute(IGEA_ENVFUN_STRAPDOWN, n, tr, n, nt,
                                         codes, NULL, 5, ep, spec, 0, S2, ld), 0);
    for (int j = 0; j < nt; j++) {
        for (int i = 0; i < 3; i++)
            assert_true(S1[i + j * m] == 0.0); /* epoch at t_0 */
        for (int i = 0; i < m; i++)
            assert_close_abs(S2[i + j * ld], S1[i + j * m] * spec[j], 1e-15, 1e-300);
        for (int i = m; i < ld; i++)
            assert_true(isnan(S2[i + j * ld]));
        for (int i = 0; i < 3; i++) /* repeated epoch, repeated row */
            assert_true(S1[6 + i + j * m] == S1[9 + i + j * m]);
    }
    free(S1);
    free(S2);
    free(tr);
}

static void test_term_valid(void **state)
{
    assert_int_equal(igea_envfun_term_valid(IGEA_ENVFUN_STRAPDOWN, IGEA_ENVFUN_TERM_ATT0_X + 2), 1);
    assert_int_equal(igea_envfun_term_valid(IGEA_ENVFUN_STRAPDOWN, IGEA_ENVFUN_TERM_ALIGN0_X), 0);
    assert_int_equal(igea_envfun_term_valid(IGEA_ENVFUN_PLATFORM, IGEA_ENVFUN_TERM_GYRO_G_X), 0);
    assert_int_equal(igea_envfun_term_valid(IGEA_ENVFUN_PLATFORM, IGEA_ENVFUN_TERM_GYRO_GS_X + 2), 1);
    assert_int_equal(igea_envfun_term_valid(IGEA_ENVFUN_PLATFORM, IGEA_ENVFUN_TERM_ACC_MIS_ZY), 1);
    assert_int_equal(igea_envfun_term_valid(2, 0), 0);
    assert_int_equal(igea_envfun_term_valid(0, -1), 0);
    assert_int_equal(igea_envfun_term_valid(0, IGEA_ENVFUN_TERM_COUNT), 0);
    int a = 0, b = 0;
    for (int k = 0; k < IGEA_ENVFUN_TERM_COUNT; k++) {
        a += igea_envfun_term_valid(0, k);
        b += igea_envfun_term_valid(1, k);
    }
    assert_int_equal(a, 27);
    assert_int_equal(b, 27);
}

/* Every -i path, NaN, non-positive spec, zero quaternion; S untouched. */
static void test_invalid(void **state)
{
    enum { NS = 4 };
    double tr[NS * IGEA_ENVFUN_TRAJ_COLS], ep[2] = {0.5, 1.0}, S[6 * 2], spec[2] = {1, 1};
    int codes[2] = {0, IGEA_ENVFUN_TERM_GYRO_BIAS_X}, bad[2] = {0, IGEA_ENVFUN_TERM_ALIGN0_X};
    int axes[6] = {0, 1, 2, 1, 2, 3};
    for (int k = 0; k < NS; k++) {
        tr[k] = k;
        for (int c = 1; c < IGEA_ENVFUN_TRAJ_COLS; c++)
            tr[k + c * NS] = (c == 7) ? 1.0 : 0.1 * c;
    }
    fill_sentinel(S, 12);
#define EF(...) igea_envfun_compute(__VA_ARGS__)
    assert_int_equal(EF(2, NS, tr, NS, 2, codes, NULL, 2, ep, NULL, 0, S, 6), -1);
    assert_int_equal(EF(0, 1, tr, NS, 2, codes, NULL, 2, ep, NULL, 0, S, 6), -2);
    assert_int_equal(EF(0, NS, NULL, NS, 2, codes, NULL, 2, ep, NULL, 0, S, 6), -3);
    assert_int_equal(EF(0, NS, tr, NS - 1, 2, codes, NULL, 2, ep, NULL, 0, S, 6), -4);
    assert_int_equal(EF(0, NS, tr, NS, 0, codes, NULL, 2, ep, NULL, 0, S, 6), -5);
    assert_int_equal(EF(0, NS, tr, NS, 2, NULL, NULL, 2, ep, NULL, 0, S, 6), -6);
    assert_int_equal(EF(0, NS, tr, NS, 2, bad, NULL, 2, ep, NULL, 0, S, 6), -6);
    assert_int_equal(EF(1, NS, tr, NS, 2, codes, axes, 2, ep, NULL, 0, S, 6), -7);
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, axes, 2, ep, NULL, 0, S, 6), 0);
    fill_sentinel(S, 12);
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, NULL, 0, ep, NULL, 0, S, 6), -8);
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, NULL, 2, NULL, NULL, 0, S, 6), -9);
    double ep_bad[2] = {1.0, 0.5}, ep_out[2] = {0.5, 3.5};
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, NULL, 2, ep_bad, NULL, 0, S, 6), -9);
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, NULL, 2, ep_out, NULL, 0, S, 6), -9);
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, NULL, 2, ep, NULL, 4, S, 6), -11);
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, NULL, 2, ep, NULL, -1, S, 6), -11);
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, NULL, 2, ep, NULL, 0, NULL, 6), -12);
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, NULL, 2, ep, NULL, 0, S, 5), -13);
    spec[1] = 0.0;
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, NULL, 2, ep, spec, 0, S, 6),
                     IGEA_ENONPOSITIVE);
    spec[1] = NAN;
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, NULL, 2, ep, spec, 0, S, 6),
                     IGEA_ENONFINITE);
    double ep_nan[2] = {0.5, NAN};
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, NULL, 2, ep_nan, NULL, 0, S, 6),
                     IGEA_ENONFINITE);
    tr[2 + 5 * NS] = NAN;
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, NULL, 2, ep, NULL, 0, S, 6),
                     IGEA_ENONFINITE);
    tr[2 + 5 * NS] = 0.5;
    tr[2] = 1.0; /* t not increasing */
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, NULL, 2, ep, NULL, 0, S, 6), -3);
    tr[2] = 2.0;
    tr[1 + 7 * NS] = 0.0; /* zero quaternion (q1..q3 = 0.8, 0.9, 1.0 here) */
    tr[1 + 8 * NS] = tr[1 + 9 * NS] = tr[1 + 10 * NS] = 0.0;
    assert_int_equal(EF(0, NS, tr, NS, 2, codes, NULL, 2, ep, NULL, 0, S, 6),
                     IGEA_EDOMAIN);
    /* a platform ignores the quaternion */
    int pcodes[2] = {0, IGEA_ENVFUN_TERM_ALIGN0_X};
    assert_true(all_sentinel(S, 12));
    assert_int_equal(EF(1, NS, tr, NS, 2, pcodes, NULL, 2, ep, NULL, 0, S, 6), 0);
#undef EF
}

/* The library's rotation kernels (src/rotation.c) against independent
 * formulas: the axis-angle DCM, the exponential series, and the attitude
 * ODE dq/dt = q (0, w) / 2 integrated by RK4 in small steps. */
static void qmul_w(const double *q, const double *w, double *dq)
{
    dq[0] = 0.5 * (-q[1] * w[0] - q[2] * w[1] - q[3] * w[2]);
    dq[1] = 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]);
    dq[2] = 0.5 * (q[0] * w[1] - q[1] * w[2] + q[3] * w[0]);
    dq[3] = 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0]);
}

static void test_rotation_kernels(void **state)
{
    (void)state;
    const double qs[4][4] = {{1, 0, 0, 0}, {0.5, -0.5, 0.5, 0.5},
                             {0.9, 0.1, -0.3, 0.2}, {-0.2, 0.7, 0.1, -0.4}};
    const double vs[4][3] = {{0, 0, 0}, {1e-9, -2e-9, 3e-9}, {0.3, -0.2, 0.1},
                             {1.5, 2.0, -0.5}};
    double C[9], Cr[9], R[9], Rr[9], y[3], yr[3];
    for (int k = 0; k < 4; k++) {
        double n = sqrt(qs[k][0] * qs[k][0] + qs[k][1] * qs[k][1] + qs[k][2] * qs[k][2] +
                        qs[k][3] * qs[k][3]), u[4];
        for (int i = 0; i < 4; i++)
            u[i] = qs[k][i] / n;
        q_dcm(qs[k], Cr);
        igea__quat_dcm(u, C);
        for (int i = 0; i < 9; i++)
            assert_close_abs(C[i], Cr[i], 0.0, 1e-14);
        igea__quat_dcm_unit(qs[k], C); /* not normalised on input */
        for (int i = 0; i < 9; i++)
            assert_close_abs(C[i], Cr[i], 0.0, 1e-14);
        igea__m3_exp(vs[k], R);
        m3_exp(vs[k], Rr);
        for (int i = 0; i < 9; i++)
            assert_close_abs(R[i], Rr[i], 0.0, 1e-14);
        /* y = C x and C^T x; the cross product */
        const double x[3] = {0.3, -1.2, 2.5};
        igea__m3_vec(Cr, x, y, 0);
        for (int i = 0; i < 3; i++) {
            yr[i] = Cr[3 * i] * x[0] + Cr[3 * i + 1] * x[1] + Cr[3 * i + 2] * x[2];
            assert_close_abs(y[i], yr[i], 0.0, 1e-14);
        }
        igea__m3_vec(Cr, x, y, 1);
        for (int i = 0; i < 3; i++) {
            yr[i] = Cr[i] * x[0] + Cr[3 + i] * x[1] + Cr[6 + i] * x[2];
            assert_close_abs(y[i], yr[i], 0.0, 1e-14);
        }
        igea__cross(vs[3], x, y);
        assert_close_abs(y[0], 2.0 * 2.5 - (-0.5) * (-1.2), 0.0, 1e-14);
        assert_close_abs(y[1], -0.5 * 0.3 - 1.5 * 2.5, 0.0, 1e-14);
        assert_close_abs(y[2], 1.5 * (-1.2) - 2.0 * 0.3, 0.0, 1e-14);
        /* q * exp(v / 2): the ODE with the constant rate v over unit time */
        double q[4], qi[4];
        memcpy(q, u, sizeof q);
        memcpy(qi, u, sizeof qi);
        igea__quat_rotate(q, vs[k]);
        const int nstep = 2000;
        const double h = 1.0 / nstep;
        for (int s = 0; s < nstep; s++) {
            double k1[4], k2[4], k3[4], k4[4], t[4];
            qmul_w(qi, vs[k], k1);
            for (int i = 0; i < 4; i++) t[i] = qi[i] + 0.5 * h * k1[i];
            qmul_w(t, vs[k], k2);
            for (int i = 0; i < 4; i++) t[i] = qi[i] + 0.5 * h * k2[i];
            qmul_w(t, vs[k], k3);
            for (int i = 0; i < 4; i++) t[i] = qi[i] + h * k3[i];
            qmul_w(t, vs[k], k4);
            for (int i = 0; i < 4; i++)
                qi[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        for (int i = 0; i < 4; i++)
            assert_close_abs(q[i], qi[i], 0.0, 1e-12);
        /* the body-frame rotation composes on the right: C(q exp) = C(q) R */
        q_dcm(q, C);
        m3_mul(Cr, Rr, R);
        for (int i = 0; i < 9; i++)
            assert_close_abs(C[i], R[i], 0.0, 1e-13);
    }
}

/* The catalogue: names, units and default specs of docs/envfun.md (values
 * written here from the document's units: 1 mg, 10 ug/g^2, 0.5 deg/h,
 * 0.5 deg/h/g, 1e-4), default term sets and the name <-> code mapping. */
static void test_catalogue(void **state)
{
    (void)state;
    assert_string_equal(igea_envfun_term_name(IGEA_ENVFUN_TERM_ACC_BIAS_X), "acc_bias_x");
    assert_string_equal(igea_envfun_term_name(IGEA_ENVFUN_TERM_ACC_MIS_YZ), "acc_mis_yz");
    assert_string_equal(igea_envfun_term_name(IGEA_ENVFUN_TERM_GYRO_G_X + 2), "gyro_g_z");
    assert_string_equal(igea_envfun_term_name(IGEA_ENVFUN_TERM_ALIGN0_X + 2), "align0_z");
    assert_string_equal(igea_envfun_term_name(-1), "");
    assert_string_equal(igea_envfun_term_name(IGEA_ENVFUN_TERM_COUNT), "");
    assert_string_equal(igea_envfun_term_unit(IGEA_ENVFUN_TERM_ACC_BIAS_X + 1), "m/s^2");
    assert_string_equal(igea_envfun_term_unit(IGEA_ENVFUN_TERM_ACC_SQ_X), "1/(m/s^2)");
    assert_string_equal(igea_envfun_term_unit(IGEA_ENVFUN_TERM_GYRO_BIAS_X), "rad/s");
    assert_string_equal(igea_envfun_term_unit(IGEA_ENVFUN_TERM_GYRO_GS_X), "rad/s/(m/s^2)");
    assert_string_equal(igea_envfun_term_unit(IGEA_ENVFUN_TERM_ATT0_X), "rad");
    assert_string_equal(igea_envfun_term_unit(IGEA_ENVFUN_TERM_GYRO_SCALE_X), "-");
    assert_string_equal(igea_envfun_term_unit(12345), "");

    /* every name maps back to its code in the systems it is valid for */
    for (int k = 0; k < IGEA_ENVFUN_TERM_COUNT; k++)
        for (int sys = 0; sys < 2; sys++) {
            int c = igea_envfun_term_code(sys, igea_envfun_term_name(k));
            assert_int_equal(c, igea_envfun_term_valid(sys, k) ? k : -2);
        }
    assert_int_equal(igea_envfun_term_code(IGEA_ENVFUN_PLATFORM, "att0_x"), -2);
    assert_int_equal(igea_envfun_term_code(IGEA_ENVFUN_STRAPDOWN, "ACC_BIAS_X"), -2);
    assert_int_equal(igea_envfun_term_code(IGEA_ENVFUN_STRAPDOWN, "acc_bias_"), -2);
    assert_int_equal(igea_envfun_term_code(IGEA_ENVFUN_STRAPDOWN, ""), -2);
    assert_int_equal(igea_envfun_term_code(IGEA_ENVFUN_STRAPDOWN, NULL), -2);
    assert_int_equal(igea_envfun_term_code(7, "acc_bias_x"), -1);
}

/* Default specs (the document's units) and default term sets. */
static void test_catalogue_defaults(void **state)
{
    (void)state;
    static const char *const sd21[21] = {
        "acc_bias_x", "acc_bias_y", "acc_bias_z", "acc_scale_x", "acc_scale_y",
        "acc_scale_z", "acc_mis_xy", "acc_mis_xz", "acc_mis_yx", "acc_mis_yz",
        "acc_mis_zx", "acc_mis_zy", "gyro_bias_x", "gyro_bias_y", "gyro_bias_z",
        "gyro_g_x", "gyro_g_y", "gyro_g_z", "att0_x", "att0_y", "att0_z"};
    static const char *const pf21[21] = {
        "acc_bias_x", "acc_bias_y", "acc_bias_z", "acc_scale_x", "acc_scale_y",
        "acc_scale_z", "gyro_bias_x", "gyro_bias_y", "gyro_bias_z", "gyro_gi_x",
        "gyro_gi_y", "gyro_gi_z", "gyro_gs_x", "gyro_gs_y", "gyro_gs_z", "align0_x",
        "align0_y", "align0_z", "acc_sq_x", "acc_sq_y", "acc_sq_z"};
    int codes[IGEA_ENVFUN_TERM_COUNT], n = -1;
    double sp = -1.0, degh = DEG / 3600.0;
    struct { int sys; const char *name; double spec; } want[] = {
        {0, "acc_bias_y", 9.80665e-3}, {1, "acc_scale_z", 1e-4},
        {1, "acc_sq_x", 1e-5 / 9.80665}, {0, "acc_mis_zx", 1e-4},
        {0, "gyro_bias_x", 0.5 * degh}, {0, "gyro_g_y", 0.5 * degh / 9.80665},
        {0, "gyro_scale_x", 1e-4}, {0, "att0_z", 1e-4},
        {1, "gyro_gi_z", 0.5 * degh / 9.80665}, {1, "gyro_gs_x", 0.5 * degh / 9.80665},
        {1, "align0_y", 1e-4}};
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
        int c = igea_envfun_term_code(want[i].sys, want[i].name);
        assert_true(c >= 0);
        assert_int_equal(igea_envfun_default_spec(want[i].sys, c, &sp), 0);
        assert_close(sp, want[i].spec, 1e-15 * want[i].spec);
    }
    sp = -1.0;
    assert_int_equal(igea_envfun_default_spec(IGEA_ENVFUN_PLATFORM, IGEA_ENVFUN_TERM_ATT0_X,
                                              &sp), -2);
    assert_int_equal(igea_envfun_default_spec(2, 0, &sp), -1);
    assert_int_equal(igea_envfun_default_spec(0, 0, NULL), -3);
    assert_true(sp == -1.0);

    for (int sys = 0; sys < 2; sys++) {
        const char *const *want21 = sys == IGEA_ENVFUN_STRAPDOWN ? sd21 : pf21;
        n = -1;
        assert_int_equal(igea_envfun_default_terms(sys, codes, IGEA_ENVFUN_TERM_COUNT, &n), 0);
        assert_int_equal(n, 21);
        for (int j = 0; j < 21; j++)
            assert_string_equal(igea_envfun_term_name(codes[j]), want21[j]);
    }
    n = -1;
    codes[0] = -7;
    assert_int_equal(igea_envfun_default_terms(0, codes, 20, &n), -3);
    assert_int_equal(igea_envfun_default_terms(0, NULL, 21, &n), -2);
    assert_int_equal(igea_envfun_default_terms(0, codes, 21, NULL), -4);
    assert_int_equal(igea_envfun_default_terms(-1, codes, 21, &n), -1);
    assert_true(n == -1 && codes[0] == -7);
    assert_int_equal(igea_envfun_default_terms(1, codes, 21, &n), 0);
    assert_int_equal(n, 21);
}

/* ---- the extended catalogue ------------------------------------------- */

/* Relative discrepancy max|S e - dW_nl| / max|dW_nl| over the epochs of the
 * errors err (nerr = IGEA_ENVFUN_TERM_END) of the codes codes[0..nt-1]
 * (S raw, one column per code). */
static double rel_discrepancy(int system, const double *tr, int n, const double *S,
                              int m, const int *codes, int nt, const double *err,
                              const double *ep, int nep, double *absd)
{
    double *dW = malloc(sizeof(double) * (size_t)m);
    assert_non_null(dW);
    assert_int_equal(igea_envfun_nonlinear(system, n, tr, n, IGEA_ENVFUN_TERM_END, err,
                                           NULL, nep, ep, dW),
                     0);
    double maxd = 0.0, maxn = 0.0;
    for (int i = 0; i < m; i++) {
        double lin = 0.0;
        for (int c = 0; c < nt; c++)
            lin += S[i + (size_t)c * m] * err[codes[c]];
        maxd = fmax(maxd, fabs(lin - dW[i]));
        maxn = fmax(maxn, fabs(dW[i]));
    }
    free(dW);
    assert_true(maxn > 0.0);
    *absd = maxd;
    return maxd / maxn;
}

/* Rewrite the quaternions of a strapdown trajectory as the rates propagate
 * them in the truth model (q_k = q_{k-1} (cos |v|/2, sin |v|/2 v/|v|), v
 * the trapezoid mean rate times the step), so that S reads the attitude
 * the truth flies and the comparison carries no attitude-discretisation
 * floor. */
static void consistent_quaternions(double *tr, int n)
{
    double q[4];
    for (int i = 0; i < 4; i++)
        q[i] = tr[(size_t)(7 + i) * n];
    for (int k = 1; k < n; k++) {
        double h = tr[k] - tr[k - 1], v[3], p[4], r[4];
        for (int a = 0; a < 3; a++)
            v[a] = 0.5 * h * (tr[k - 1 + (size_t)(4 + a) * n] + tr[k + (size_t)(4 + a) * n]);
        double th = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        double sc = th > 0 ? sin(0.5 * th) / th : 0.5;
        r[0] = cos(0.5 * th);
        for (int a = 0; a < 3; a++)
            r[1 + a] = sc * v[a];
        p[0] = q[0] * r[0] - q[1] * r[1] - q[2] * r[2] - q[3] * r[3];
        p[1] = q[0] * r[1] + q[1] * r[0] + q[2] * r[3] - q[3] * r[2];
        p[2] = q[0] * r[2] - q[1] * r[3] + q[2] * r[0] + q[3] * r[1];
        p[3] = q[0] * r[3] + q[1] * r[2] - q[2] * r[1] + q[3] * r[0];
        memcpy(q, p, sizeof q);
        for (int i = 0; i < 4; i++)
            tr[k + (size_t)(7 + i) * n] = q[i];
    }
}

/* Every term of the catalogue alone, and all together, against the
 * nonlinear truth model at the default 1-sigma sizes (signs alternating
 * +, -, +0.8) and at half of them: where the discrepancy is second order
 * it halves (ratio 2 +- 10 %). Where the truth is linear in the
 * coefficient (accelerometer-type errors without an attitude error, the
 * lever arm) or its second-order part is below the floor, the discrepancy
 * stays within the floor at both sizes: 1e-9 m/s (rounding: the truth's
 * Wh - W cancels W of 3e3 m/s) or 2e-5 relative (the O(h^2) difference
 * between the truth's exact rotation per step and the trapezoid double
 * integral of S); a wrong sign or integral would be O(1). The strapdown
 * trajectory's quaternions are first made those the truth flies. */
static void check_catalogue(int system, const char *name)
{
    int n, codes[IGEA_ENVFUN_TERM_END], nt = 0, worst = -1;
    assert_int_equal(igea_envfun_all_terms(system, codes, IGEA_ENVFUN_TERM_END, &nt), 0);
    double *tr = make_traj(system, &n), ep[N_EP], err[IGEA_ENVFUN_TERM_END];
    double sz[IGEA_ENVFUN_TERM_END], worst_rel = 0.0, worst_ratio = 0.0;
    int m = 3 * N_EP, nlin = 0;
    double *S = malloc(sizeof(double) * (size_t)m * nt);
    assert_non_null(S);
    if (system == IGEA_ENVFUN_STRAPDOWN)
        consistent_quaternions(tr, n);
    for (int e = 0; e < N_EP; e++)
        ep[e] = e;
    assert_int_equal(igea_envfun_compute(system, n, tr, n, nt, codes, NULL, N_EP, ep, NULL,
                                         IGEA_ENVFUN_VELOCITY, S, m),
                     0);
    for (int c = 0; c < nt; c++) {
        assert_int_equal(igea_envfun_default_spec(system, codes[c], &sz[codes[c]]), 0);
        sz[codes[c]] *= (c % 3 == 1) ? -1.0 : (c % 3 == 2 ? 0.8 : 1.0);
    }
    for (int j = -1; j < nt; j++) {
        double rel[2], absd[2];
        for (int h = 0; h < 2; h++) {
            for (int k = 0; k < IGEA_ENVFUN_TERM_END; k++)
                err[k] = 0.0;
            for (int c = 0; c < nt; c++)
                if (j < 0 || c == j)
                    err[codes[c]] = sz[codes[c]] * (h ? 0.5 : 1.0);
            rel[h] = rel_discrepancy(system, tr, n, S, m, codes, nt, err, ep, N_EP, &absd[h]);
        }
        const char *nm = j < 0 ? "(all)" : igea_envfun_term_name(codes[j]);
        if (getenv("SHOWALL")) print_message("%s %s %.3g %.3g\n", name, nm, rel[0], rel[1]);
        double ratio = rel[0] / rel[1];
        if (!(ratio > 1.8 && ratio < 2.2)) {
            /* linear in the truth: the floor of rounding and of the
             * trajectory's own attitude (the strapdown truth propagates
             * C from the rates, S reads the quaternions) */
            int floor_ok = (rel[0] < 2e-5 && rel[1] < 2e-5) || (absd[0] < 1e-9 && absd[1] < 1e-9);
            if (!floor_ok)
                print_error("%s %s: rel %.3g, halved %.3g (%.3g m/s)\n", name, nm,
                            rel[0], rel[1], absd[0]);
            assert_true(floor_ok);
            nlin++;
            continue;
        }
        assert_true(rel[0] < (j < 0 ? 5e-3 : 1e-3));
        if (j >= 0 && rel[0] > worst_rel) {
            worst_rel = rel[0];
            worst = codes[j];
            worst_ratio = ratio;
        }
        if (j < 0)
            print_message("%s, all %d terms: rel %.3g, halved ratio %.3f\n", name, nt,
                          rel[0], ratio);
    }
    print_message("%s: %d terms, %d linear in the truth; worst term %s rel %.3g "
                  "(halved: ratio %.3f)\n", name, nt, nlin, igea_envfun_term_name(worst),
                  worst_rel, worst_ratio);
    free(S);
    free(tr);
}

static void test_catalogue_vs_nonlinear(void **state)
{
    (void)state;
    check_catalogue(IGEA_ENVFUN_PLATFORM, "platform");
    check_catalogue(IGEA_ENVFUN_STRAPDOWN, "strapdown");
}

/* The extended catalogue: counts (74 platform terms: the size of seed
 * 000's platform model), names, the gap at code 36, the all-terms set. */
static void test_catalogue_extended(void **state)
{
    (void)state;
    int codes[IGEA_ENVFUN_TERM_END], n = -1, a = 0, b = 0;
    assert_int_equal(igea_envfun_term_count(), IGEA_ENVFUN_TERM_END);
    for (int k = 0; k < IGEA_ENVFUN_TERM_END; k++) {
        a += igea_envfun_term_valid(IGEA_ENVFUN_STRAPDOWN, k);
        b += igea_envfun_term_valid(IGEA_ENVFUN_PLATFORM, k);
        int named = igea_envfun_term_name(k)[0] != '\0';
        assert_int_equal(named, igea_envfun_term_valid(0, k) || igea_envfun_term_valid(1, k));
        for (int sys = 0; sys < 2; sys++)
            if (named)
                assert_int_equal(igea_envfun_term_code(sys, igea_envfun_term_name(k)),
                                 igea_envfun_term_valid(sys, k) ? k : -2);
    }
    assert_int_equal(b, 74);
    assert_int_equal(a, 86);
    assert_string_equal(igea_envfun_term_name(IGEA_ENVFUN_TERM_COUNT), "");
    assert_string_equal(igea_envfun_term_name(IGEA_ENVFUN_TERM_END), "");
    assert_string_equal(igea_envfun_term_name(IGEA_ENVFUN_TERM_GYRO_GIO_X + 1), "gyro_gio_y");
    assert_string_equal(igea_envfun_term_name(IGEA_ENVFUN_TERM_ACC_CROSS_XY + 3), "acc_cross_yz");
    assert_string_equal(igea_envfun_term_name(IGEA_ENVFUN_TERM_ACC_XSQ_XY + 4), "acc_xsq_zx");
    assert_string_equal(igea_envfun_term_name(IGEA_ENVFUN_TERM_SIZE_XX + 5), "acc_size_yz");
    assert_string_equal(igea_envfun_term_name(IGEA_ENVFUN_TERM_POS0_Z), "pos0_z");
    assert_string_equal(igea_envfun_term_unit(IGEA_ENVFUN_TERM_GYRO_GSS_X), "rad/s/(m/s^2)^2");
    assert_string_equal(igea_envfun_term_unit(IGEA_ENVFUN_TERM_LEVER_X), "m");
    assert_string_equal(igea_envfun_term_formula(IGEA_ENVFUN_TERM_ACC_CUBE_X + 1), "u = e_j f_j^3");
    assert_string_equal(igea_envfun_term_formula(IGEA_ENVFUN_TERM_GYRO_GIO_X), "eps = e_j f_I(j) f_O(j)");
    assert_string_equal(igea_envfun_term_formula(IGEA_ENVFUN_TERM_GYRO_G_X), "eps = e_j f_j");
    assert_string_equal(igea_envfun_term_formula(IGEA_ENVFUN_TERM_POS0_Z), "S = -(W x e_x) / R");
    assert_string_equal(igea_envfun_term_formula(IGEA_ENVFUN_TERM_COUNT), "");
    assert_string_equal(igea_envfun_term_formula(-3), "");
    for (int k = 0; k < IGEA_ENVFUN_TERM_END; k++) /* every term has its equation */
        assert_int_equal(igea_envfun_term_formula(k)[0] != '\0', igea_envfun_term_name(k)[0] != '\0');
    assert_int_equal(igea_envfun_term_valid(IGEA_ENVFUN_PLATFORM, IGEA_ENVFUN_TERM_SIZE_XX), 0);
    assert_int_equal(igea_envfun_term_valid(IGEA_ENVFUN_PLATFORM, IGEA_ENVFUN_TERM_GYRO_GSPIN_X), 0);
    assert_int_equal(igea_envfun_term_valid(IGEA_ENVFUN_STRAPDOWN, IGEA_ENVFUN_TERM_GYRO_GSPIN_X), 1);
    assert_int_equal(igea_envfun_all_terms(IGEA_ENVFUN_PLATFORM, codes, IGEA_ENVFUN_TERM_END, &n), 0);
    assert_int_equal(n, 74);
    n = -1;
    codes[0] = -7;
    assert_int_equal(igea_envfun_all_terms(IGEA_ENVFUN_PLATFORM, codes, 73, &n), -3);
    assert_int_equal(igea_envfun_all_terms(IGEA_ENVFUN_PLATFORM, NULL, 96, &n), -2);
    assert_int_equal(igea_envfun_all_terms(IGEA_ENVFUN_PLATFORM, codes, 96, NULL), -4);
    assert_int_equal(igea_envfun_all_terms(5, codes, 96, &n), -1);
    assert_true(n == -1 && codes[0] == -7);
}

/* A constant-force (or constant-rate) trajectory of NS samples at dt. */
static double *const_traj(int ns, double dt, const double *f, const double *w,
                          double wz_rot)
{
    double *tr = malloc(sizeof(double) * (size_t)ns * IGEA_ENVFUN_TRAJ_COLS);
    assert_non_null(tr);
    for (int k = 0; k < ns; k++) {
        double t = dt * k;
        tr[k] = t;
        for (int a = 0; a < 3; a++) {
            tr[k + (1 + a) * ns] = f[a];
            tr[k + (4 + a) * ns] = w[a];
        }
        /* attitude: rotation by wz_rot t about z */
        tr[k + 7 * ns] = cos(0.5 * wz_rot * t);
        tr[k + 8 * ns] = tr[k + 9 * ns] = 0.0;
        tr[k + 10 * ns] = sin(0.5 * wz_rot * t);
    }
    return tr;
}

/* Closed forms of the new families on a constant-force, non-rotating
 * platform trajectory, written from the unit errors of docs/envfun.md:
 * K3 f_j^3 t e_j, asymmetry |f_j| t e_j, cross-coupling f_j f_k t e_j,
 * drift q(f) constant -> S = t^2/2 q (f x e_j), pos0_x (W x e_z) / R. */
static void test_closed_forms_extended(void **state)
{
    (void)state;
    enum { NS = 11 };
    double f[3] = {3.0, -2.0, 12.0}, w0[3] = {0, 0, 0}, t = 5.0, R = 6371000.0;
    double *tr = const_traj(NS, 0.5, f, w0, 0.0);
    int pf[6] = {IGEA_ENVFUN_TERM_ACC_CUBE_X + 2, IGEA_ENVFUN_TERM_ACC_ASYM_X + 1,
                 IGEA_ENVFUN_TERM_ACC_CROSS_XY + 1, IGEA_ENVFUN_TERM_GYRO_GII_X,
                 IGEA_ENVFUN_TERM_GYRO_GO_X, IGEA_ENVFUN_TERM_POS0_X};
    double ep[1] = {t}, S[3 * 6];
    assert_int_equal(igea_envfun_compute(IGEA_ENVFUN_PLATFORM, NS, tr, NS, 6, pf, NULL, 1,
                                         ep, NULL, IGEA_ENVFUN_VELOCITY, S, 3),
                     0);
    assert_close(S[0 * 3 + 2], f[2] * f[2] * f[2] * t, 1e-14);
    assert_close(S[1 * 3 + 1], 2.0 * t, 1e-14);
    assert_close(S[2 * 3 + 0], f[0] * f[2] * t, 1e-14); /* acc_cross_xz */
    /* gyro x, I = x: q = f_x^2; f x e_x = (0, f_z, -f_y) */
    assert_close(S[3 * 3 + 1], 0.5 * t * t * f[0] * f[0] * f[2], 1e-14);
    assert_close(S[3 * 3 + 2], -0.5 * t * t * f[0] * f[0] * f[1], 1e-14);
    /* gyro x, default I = x, S = y: O = z */
    assert_close(S[4 * 3 + 1], 0.5 * t * t * f[2] * f[2], 1e-14);
    /* pos0_x: (W x e_z) / R = (W_y, -W_x, 0) / R */
    assert_close(S[5 * 3 + 0], f[1] * t / R, 1e-14);
    assert_close(S[5 * 3 + 1], -f[0] * t / R, 1e-14);
    /* the same gyro drift through the nonlinear truth model: the exact
     * rotation differs from t^2/2 eps (f x e_x) by O(eps t) relative */
    double err[IGEA_ENVFUN_TERM_END] = {0}, dW[3], eps = 1e-6;
    err[IGEA_ENVFUN_TERM_GYRO_BIAS_X] = eps;
    assert_int_equal(igea_envfun_nonlinear(IGEA_ENVFUN_PLATFORM, NS, tr, NS,
                                           IGEA_ENVFUN_TERM_END, err, NULL, 1, ep, dW),
                     0);
    assert_close(dW[1], 0.5 * eps * t * t * f[2], 1e-4);
    assert_close(dW[2], -0.5 * eps * t * t * f[1], 1e-4);
    /* a constant accelerometer bias on a static (1 g) platform: b t */
    double fg[3] = {0.0, 9.80665, 0.0};
    double *ts = const_traj(NS, 0.5, fg, w0, 0.0);
    err[IGEA_ENVFUN_TERM_GYRO_BIAS_X] = 0.0;
    err[IGEA_ENVFUN_TERM_ACC_BIAS_X + 1] = 1e-3;
    assert_int_equal(igea_envfun_nonlinear(IGEA_ENVFUN_PLATFORM, NS, ts, NS,
                                           IGEA_ENVFUN_TERM_END, err, NULL, 1, ep, dW),
                     0);
    assert_close(dW[1], 1e-3 * t, 1e-11); /* W +- b t: cancellation of 1e4 */
    free(ts);
    free(tr);
}

/* Lever arm and size effect on a body turning at a constant rate w about
 * z (attitude R_z(w t)): lever_x: -(C(t) - C(0)) (w x e_x) =
 * -w (-sin wt, cos wt - 1, 0); size effect of accelerometer x displaced
 * along x: centripetal -w^2 e_x, S = int C (-w^2 e_x) = -w (sin wt,
 * 1 - cos wt, 0) (trapezoid error O(h^2)). */
static void test_lever_size_closed_forms(void **state)
{
    (void)state;
    enum { NS = 2001 };
    double wz = 0.2, f[3] = {0, 0, 0}, w[3] = {0, 0, wz}, t = 10.0;
    double *tr = const_traj(NS, t / (NS - 1), f, w, wz);
    int codes[2] = {IGEA_ENVFUN_TERM_LEVER_X, IGEA_ENVFUN_TERM_SIZE_XX};
    double ep[1] = {t}, S[6];
    assert_int_equal(igea_envfun_compute(IGEA_ENVFUN_STRAPDOWN, NS, tr, NS, 2, codes, NULL, 1,
                                         ep, NULL, IGEA_ENVFUN_VELOCITY, S, 3),
                     0);
    double c = cos(wz * t), s = sin(wz * t);
    assert_close(S[0], wz * s, 1e-13);
    assert_close(S[1], -wz * (c - 1.0), 1e-13);
    assert_close(S[3], -wz * s, 1e-6);
    assert_close(S[4], -wz * (1.0 - c), 1e-6);
    /* platform lever arm: the same geometry from the body attitude */
    assert_int_equal(igea_envfun_compute(IGEA_ENVFUN_PLATFORM, NS, tr, NS, 1, codes, NULL, 1,
                                         ep, NULL, IGEA_ENVFUN_VELOCITY, S, 3),
                     0);
    assert_close(S[0], wz * s, 1e-13);
    free(tr);
}

/* User-defined terms: a constant series equals the catalogue's bias
 * column; a thermal-like profile u = e_x sin(a t) on a platform gives
 * S_x = (1 - cos a t) / a (trapezoid error O(h^2)); gyro kind = drift. */
static void test_user_terms(void **state)
{
    (void)state;
    enum { NS = 4001 };
    double f[3] = {3.0, -2.0, 12.0}, w0[3] = {0.01, 0, 0}, T = 40.0, a = 0.3;
    double *tr = const_traj(NS, T / (NS - 1), f, w0, 0.01);
    double *u = malloc(sizeof(double) * NS * 9), ep[2] = {13.3, T};
    int kind[3] = {IGEA_ENVFUN_USER_ACC, IGEA_ENVFUN_USER_GYRO, IGEA_ENVFUN_USER_ACC};
    int codes[2] = {IGEA_ENVFUN_TERM_ACC_BIAS_X + 1, IGEA_ENVFUN_TERM_GYRO_BIAS_X + 2};
    assert_non_null(u);
    for (int k = 0; k < NS; k++) {
        double t = tr[k];
        for (int c = 0; c < 9; c++)
            u[k + (size_t)c * NS] = 0.0;
        u[k + 0 * NS] = sin(a * t); /* user 0: x */
        u[k + 5 * NS] = 1.0;        /* user 1: z, a constant drift */
        u[k + 7 * NS] = 1.0;        /* user 2: y, a constant bias */
    }
    double S[6 * 5], R[6 * 2];
    for (int sys = 0; sys < 2; sys++) {
        assert_int_equal(igea_envfun_compute_user(sys, NS, tr, NS, 2, codes, NULL, 3, kind, u,
                                                  NS, 2, ep, NULL, IGEA_ENVFUN_VELOCITY, S, 6),
                         0);
        assert_int_equal(igea_envfun_compute(sys, NS, tr, NS, 2, codes, NULL, 2, ep, NULL,
                                             IGEA_ENVFUN_VELOCITY, R, 6),
                         0);
        for (int i = 0; i < 6; i++) {
            assert_true(S[i] == R[i] && S[6 + i] == R[6 + i]);
            assert_close_abs(S[24 + i], R[i], 1e-14, 1e-15); /* user 2 = acc_bias_y */
            assert_close_abs(S[18 + i], R[6 + i], 1e-14, 1e-15); /* user 1 = gyro_bias_z */
        }
        if (sys == IGEA_ENVFUN_PLATFORM)
            for (int e = 0; e < 2; e++)
                assert_close(S[12 + 3 * e], (1.0 - cos(a * ep[e])) / a, 1e-6);
    }
    /* nterms = 0, user terms only; argument errors */
    assert_int_equal(igea_envfun_compute_user(1, NS, tr, NS, 0, NULL, NULL, 1, kind, u, NS, 2,
                                              ep, NULL, IGEA_ENVFUN_VELOCITY, S, 6), 0);
    assert_close(S[0], (1.0 - cos(a * ep[0])) / a, 1e-6);
    fill_sentinel(S, 30);
    int badk[1] = {2};
#define EU(nt, nu, kd, uu, ldu, lds) \
    igea_envfun_compute_user(1, NS, tr, NS, nt, codes, NULL, nu, kd, uu, ldu, 2, ep, NULL, 0, S, lds)
    assert_int_equal(EU(0, 0, kind, u, NS, 6), -5);
    assert_int_equal(EU(-1, 1, kind, u, NS, 6), -5);
    assert_int_equal(EU(1, -1, kind, u, NS, 6), -8);
    assert_int_equal(EU(1, 1, NULL, u, NS, 6), -9);
    assert_int_equal(EU(1, 1, badk, u, NS, 6), -9);
    assert_int_equal(EU(1, 1, kind, NULL, NS, 6), -10);
    assert_int_equal(EU(1, 1, kind, u, NS - 1, 6), -11);
    assert_int_equal(EU(1, 1, kind, u, NS, 5), -17);
    u[17] = NAN;
    assert_int_equal(EU(1, 1, kind, u, NS, 6), IGEA_ENONFINITE);
#undef EU
    assert_true(all_sentinel(S, 30));
    free(u);
    free(tr);
}

/* The two models of a launch-point error. The truth model
 * (igea_envfun_nonlinear) is the sphere model of the columns without a
 * site: the reference W read in the launch frame turned by theta =
 * (dz / R, 0, -dx / R), R = 6371 km, dW = W - exp(-[theta x]) W exactly
 * (W the trapezoid of the platform force, written here), and those
 * columns agree with it to second order (halving d quarters the rest).
 * The site's columns (igea_envfun_compute_site) are another model, whose
 * truth is the raw records (tests/test_sim_raw.c): against the sphere
 * truth they differ by the pad velocity's w_L x d and more. */
static void test_launch_point_models(void **state)
{
    (void)state;
    int ns, codes[2] = {IGEA_ENVFUN_TERM_POS0_X, IGEA_ENVFUN_TERM_POS0_Z};
    assert_int_equal(igea_sim_trajectory_length(120.0, 50.0, &ns), 0);
    double *tr = malloc(sizeof(double) * (size_t)ns * IGEA_ENVFUN_TRAJ_COLS);
    double ep[120], dW[360], S[720], Ss[720], site[IGEA_NAV_SITE_LEN], d[2];
    assert_non_null(tr);
    assert_int_equal(igea_sim_trajectory(IGEA_ENVFUN_PLATFORM, 120.0, 50.0, ns, tr, ns), 0);
    assert_int_equal(igea_nav_site(40.96 * DEG, 100.29 * DEG, 1000.0, 30.0 * DEG, site), 0);
    for (int e = 0; e < 120; e++)
        ep[e] = e + 1.0;
    assert_int_equal(igea_envfun_compute(IGEA_ENVFUN_PLATFORM, ns, tr, ns, 2, codes, NULL, 120,
                                         ep, NULL, IGEA_ENVFUN_VELOCITY, S, 360), 0);
    assert_int_equal(igea_envfun_compute_site(IGEA_ENVFUN_PLATFORM, ns, tr, ns, 2, codes, NULL,
                                              0, NULL, NULL, ns, 120, ep, NULL,
                                              IGEA_ENVFUN_VELOCITY, site, Ss, 360), 0);
    double miss_site = 0.0;
    for (int h = 0; h < 2; h++) {
        double dx = h ? 25.0 : 50.0, dz = h ? -15.0 : -30.0, R = 6371000.0;
        double err[IGEA_ENVFUN_TERM_END] = {0}, mt[3] = {-dz / R, 0.0, dx / R}, Rm[9];
        double W[3] = {0, 0, 0}, closed = 0.0;
        err[codes[0]] = dx;
        err[codes[1]] = dz;
        assert_int_equal(igea_envfun_nonlinear(IGEA_ENVFUN_PLATFORM, ns, tr, ns,
                                               IGEA_ENVFUN_TERM_END, err, NULL, 120, ep, dW), 0);
        m3_exp(mt, Rm);
        d[h] = 0.0;
        for (int k = 1, e = 0; k < ns && e < 120; k++) {
            for (int a = 0; a < 3; a++)
                W[a] += 0.5 * (tr[k] - tr[k - 1]) *
                        (tr[k + (size_t)ns * (1 + a)] + tr[k - 1 + (size_t)ns * (1 + a)]);
            if (fabs(tr[k] - ep[e]) > 1e-9)
                continue;
            double RW[3];
            m3_vec(Rm, W, RW);
            for (int a = 0; a < 3; a++) {
                size_t i = 3 * (size_t)e + a;
                closed = fmax(closed, fabs(dW[i] - (W[a] - RW[a])));
                d[h] = fmax(d[h], fabs(dW[i] - S[i] * dx - S[i + 360] * dz));
                if (!h)
                    miss_site = fmax(miss_site, fabs(dW[i] - Ss[i] * dx - Ss[i + 360] * dz));
            }
            e++;
        }
        assert_true(closed < 1e-9);
    }
    print_message("launch point (50, -30) m: sphere truth - sphere columns %.3g, halved %.3g "
                  "(ratio %.3f); sphere truth - site columns %.3g m/s\n", d[0], d[1],
                  d[0] / d[1], miss_site);
    assert_true(d[0] / d[1] > 3.6 && d[0] / d[1] < 4.4 && d[0] < 1e-6);
    assert_true(miss_site > 2e-3);
    free(tr);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_term_valid),
        cmocka_unit_test(test_catalogue),
        cmocka_unit_test(test_catalogue_defaults),
        cmocka_unit_test(test_rotation_kernels),
        cmocka_unit_test(test_closed_forms),
        cmocka_unit_test(test_spec_lds),
        cmocka_unit_test(test_invalid),
        cmocka_unit_test(test_strapdown_vs_nonlinear),
        cmocka_unit_test(test_strapdown21_vs_nonlinear),
        cmocka_unit_test(test_platform_vs_nonlinear),
        cmocka_unit_test(test_gravity_coupling),
        cmocka_unit_test(test_library_truth_model),
        cmocka_unit_test(test_catalogue_extended),
        cmocka_unit_test(test_closed_forms_extended),
        cmocka_unit_test(test_lever_size_closed_forms),
        cmocka_unit_test(test_user_terms),
        cmocka_unit_test(test_catalogue_vs_nonlinear),
        cmocka_unit_test(test_launch_point_models),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
