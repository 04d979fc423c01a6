/* tests/test_sim.c - reference trajectory, synthetic flights and the
 * Monte Carlo of the equivalent-error test (igea/sim.h). Statistical
 * checks use two-sided binomial (or normal-theory) bounds at a 1e-6
 * false-failure probability, so they cannot flake; the seeds are fixed
 * anyway, so every run draws the same numbers. */
#include "testutil.h"

#include <limits.h>
#include <pthread.h>

#include <gsl/gsl_cdf.h>

#include "igea/eqerr.h"
#include "igea/envfun.h"
#include "igea/noise.h"
#include "igea/sim.h"

/* Out-of-memory loop (as tests/test_oom.c): this program's malloc can fail
 * the n-th allocation; not under AddressSanitizer, which owns malloc. */
#include "oom.h"

#define G0 9.80665
#define DEG_H (3.14159265358979323846 / 180.0 / 3600.0)
#define M_EP 120
#define NT 21

/* 1 if count is inside the two-sided 1e-6 acceptance region of
 * Binomial(n, p) (each tail <= 0.5e-6). */
static int binom_ok(int count, int n, double p)
{
    double lo_tail = gsl_cdf_binomial_P((unsigned)count, p, (unsigned)n);
    double hi_tail = count > 0 ? gsl_cdf_binomial_Q((unsigned)(count - 1), p, (unsigned)n)
                               : 1.0;
    if (!(lo_tail > 0.5e-6 && hi_tail > 0.5e-6))
        print_error("count %d of %d outside the 1e-6 region of p = %g\n", count, n, p);
    return lo_tail > 0.5e-6 && hi_tail > 0.5e-6;
}

/* The 21-term strapdown model on the reference boost, epochs 1..120 s,
 * with the default specs of docs/envfun.md; tracking sigma 1 cm/s. */
static double S21[3 * M_EP * NT], SPEC21[NT], SIG = 0.01;
static int setup_model(void **state)
{
    int codes[NT], n = 0, k = 0;
    for (int a = 0; a < 3; a++) {
        codes[k] = IGEA_ENVFUN_TERM_ACC_BIAS_X + a;
        SPEC21[k++] = 1e-3 * G0;
    }
    for (int a = 0; a < 3; a++) {
        codes[k] = IGEA_ENVFUN_TERM_ACC_SCALE_X + a;
        SPEC21[k++] = 1e-4;
    }
    for (int a = 0; a < 6; a++) {
        codes[k] = IGEA_ENVFUN_TERM_ACC_MIS_XY + a;
        SPEC21[k++] = 1e-4;
    }
    for (int a = 0; a < 3; a++) {
        codes[k] = IGEA_ENVFUN_TERM_GYRO_BIAS_X + a;
        SPEC21[k++] = 0.5 * DEG_H;
    }
    for (int a = 0; a < 3; a++) {
        codes[k] = IGEA_ENVFUN_TERM_GYRO_G_X + a;
        SPEC21[k++] = 0.5 * DEG_H / G0;
    }
    for (int a = 0; a < 3; a++) {
        codes[k] = IGEA_ENVFUN_TERM_ATT0_X + a;
        SPEC21[k++] = 1e-4;
    }
    double ep[M_EP];
    for (int e = 0; e < M_EP; e++)
        ep[e] = e + 1.0;
    if (igea_sim_trajectory_length(120.0, 50.0, &n) != 0)
        return -1;
    double *tr = malloc(sizeof(double) * (size_t)n * IGEA_ENVFUN_TRAJ_COLS);
    if (!tr || igea_sim_trajectory(IGEA_ENVFUN_STRAPDOWN, 120.0, 50.0, n, tr, n) ||
        igea_envfun_compute(IGEA_ENVFUN_STRAPDOWN, n, tr, n, NT, codes, NULL,
                            M_EP, ep, NULL, IGEA_ENVFUN_VELOCITY, S21, 3 * M_EP))
        return -1;
    free(tr);
    return 0;
}

/* ---- trajectory ---------------------------------------------------------- */
/* ---- the model API through the argument lists of a single call -------- */

/* A model of S (m x N, ld lds) with these settings; status of the first
 * failing call. */
static int make_model(int m, int N, const double *S, int lds, const double *sig,
                      int sigma_inc, const double *spec, const double *xv,
                      const int *xf, const double *opts, igea_sim_model **md)
{
    int st = igea_sim_model_create(m, N, S, lds, md);
    if (st == 0)
        st = igea_sim_model_set_sigma(*md, sig, sigma_inc, 0.0);
    if (st == 0)
        st = igea_sim_model_set_spec(*md, spec);
    if (st == 0)
        st = igea_sim_model_set_truth(*md, xv, xf);
    if (st == 0)
        st = igea_sim_model_set_noise(*md, opts);
    if (st) {
        igea_sim_model_free(*md);
        *md = NULL;
    }
    return st;
}

static int sim_flight(int m, int N, const double *S, int lds, const double *sig,
                      int sigma_inc, const double *spec, const double *xv,
                      const int *xf, const double *opts, int seed, int flight,
                      double *x_true, double *dw)
{
    igea_sim_model *md = NULL;
    int st = make_model(m, N, S, lds, sig, sigma_inc, spec, xv, xf, opts, &md);
    if (st == 0)
        st = igea_sim_flight(md, seed, flight, x_true, dw);
    igea_sim_model_free(md);
    return st;
}

/* The Monte Carlo with the per-flight table split into its columns. */
static int sim_mc(int m, int N, const double *S, int lds, const double *sig,
                  int sigma_inc, const double *spec, const double *xv, const int *xf,
                  const double *opts, int seed, const double *eqo, int first, int nf,
                  int nthreads, double *counts, int *ct, int *cr, double *chi2,
                  int *dof, int *nrej, double *scale)
{
    igea_sim_model *md = NULL;
    double *tab = malloc(sizeof(double) * (size_t)(nf > 0 ? nf : 1) * IGEA_SIM_MC_TABLE_COLS);
    int st = tab ? make_model(m, N, S, lds, sig, sigma_inc, spec, xv, xf, opts, &md)
                 : IGEA_ENOMEM;
    if (st == 0)
        st = igea_sim_montecarlo(md, eqo, seed, first, nf, nthreads, counts, NULL, ct, cr,
                                 tab, nf);
    for (int f = 0; st == 0 && f < nf; f++) {
        if (chi2)
            chi2[f] = tab[f + (size_t)IGEA_SIM_MC_TABLE_CHI2 * nf];
        if (dof)
            dof[f] = (int)tab[f + (size_t)IGEA_SIM_MC_TABLE_DOF * nf];
        if (nrej)
            nrej[f] = (int)tab[f + (size_t)IGEA_SIM_MC_TABLE_N_REJECT * nf];
        if (scale)
            scale[f] = tab[f + (size_t)IGEA_SIM_MC_TABLE_SCALE * nf];
    }
    igea_sim_model_free(md);
    free(tab);
    return st;
}

static void test_trajectory(void **state)
{
    int n = 0;
    assert_int_equal(igea_sim_trajectory_length(120.0, 50.0, &n), 0);
    assert_int_equal(n, 6001);
    assert_int_equal(igea_sim_trajectory_length(0.0, 50.0, &n), -1);
    assert_int_equal(igea_sim_trajectory_length(10.0, -1.0, &n), -2);
    assert_int_equal(igea_sim_trajectory_length(10.0, 1.0, NULL), -3);
    n = 6001;
    int ld = n + 3;
    double *sd = malloc(sizeof(double) * (size_t)ld * IGEA_ENVFUN_TRAJ_COLS);
    double *pf = malloc(sizeof(double) * (size_t)n * IGEA_ENVFUN_TRAJ_COLS);
    fill_nan(sd, (size_t)ld * IGEA_ENVFUN_TRAJ_COLS);
    assert_int_equal(igea_sim_trajectory(IGEA_ENVFUN_STRAPDOWN, 120.0, 50.0, n, sd, ld), 0);
    assert_int_equal(igea_sim_trajectory(IGEA_ENVFUN_PLATFORM, 120.0, 50.0, n, pf, n), 0);
    for (int k = 0; k < n; k++) {
        double qn = 0, fb = 0, fa = 0;
        assert_close(sd[k], k / 50.0, 1e-15);
        for (int i = 0; i < 4; i++)
            qn += sd[k + (7 + i) * ld] * sd[k + (7 + i) * ld];
        assert_close(qn, 1.0, 1e-13);
        for (int i = 0; i < 3; i++) {
            fb += sd[k + (1 + i) * ld] * sd[k + (1 + i) * ld];
            fa += pf[k + (1 + i) * n] * pf[k + (1 + i) * n];
        }
        assert_close(fa, fb, 1e-12); /* platform force = C f_b */
        assert_true(sd[k + ld] >= 15.0 && sd[k + ld] <= 25.0);
    }
    for (int k = n; k < ld; k++)
        assert_true(isnan(sd[k]));
    /* body x starts vertical (force along launch y) and ends pitched over by
     * 60 deg (+- the wobble): elevation of the thrust axis ~30 deg */
    assert_close(pf[0 + 2 * n], 15.0, 1e-12);
    double fx = pf[(n - 1) + n], fy = pf[(n - 1) + 2 * n];
    double elev = atan2(fy, fx) * 180.0 / 3.14159265358979323846;
    assert_true(elev > 28.0 && elev < 32.0);
    assert_true(fx > 0.0); /* pitched downrange */
    /* invalid arguments */
    assert_int_equal(igea_sim_trajectory(2, 120.0, 50.0, n, pf, n), -1);
    assert_int_equal(igea_sim_trajectory(0, -1.0, 50.0, n, pf, n), -2);
    assert_int_equal(igea_sim_trajectory(0, 120.0, 0.0, n, pf, n), -3);
    assert_int_equal(igea_sim_trajectory(0, 120.0, 50.0, n - 1, pf, n), -4);
    assert_int_equal(igea_sim_trajectory(0, 120.0, 50.0, n, NULL, n), -5);
    assert_int_equal(igea_sim_trajectory(0, 120.0, 50.0, n, pf, n - 1), -6);
    free(sd);
    free(pf);
}

/* ---- flights -------------------------------------------------------------- */
static void test_flight_reproducible(void **state)
{
    int m = 3 * M_EP;
    double x1[NT], x2[NT], x3[NT], d1[3 * M_EP], d2[3 * M_EP], d3[3 * M_EP];
    double xv[NT] = {0};
    int xf[NT] = {0};
    assert_int_equal(sim_flight(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL,
                                     NULL, 42, 7, x1, d1), 0);
    assert_int_equal(sim_flight(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL,
                                     NULL, 42, 7, x2, d2), 0);
    assert_memory_equal(d1, d2, sizeof d1);
    assert_memory_equal(x1, x2, sizeof x1);
    assert_int_equal(sim_flight(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL,
                                     NULL, 42, 8, x3, d3), 0);
    assert_true(x3[0] != x1[0] && d3[5] != d1[5]);
    assert_int_equal(sim_flight(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL,
                                     NULL, 43, 7, x3, d3), 0);
    assert_true(x3[0] != x1[0]);
    /* fixing one term leaves the other terms' draws and the noise alone */
    xv[4] = 2.5;
    xf[4] = 1;
    assert_int_equal(sim_flight(m, NT, S21, m, &SIG, 0, SPEC21, xv, xf,
                                     NULL, 42, 7, x3, d3), 0);
    for (int j = 0; j < NT; j++)
        assert_true(x3[j] == (j == 4 ? 2.5 : x1[j]));
    /* dw - S D x is the same noise in both */
    for (int i = 0; i < m; i++) {
        double s1 = 0, s3 = 0;
        for (int j = 0; j < NT; j++) {
            s1 += S21[i + j * m] * SPEC21[j] * x1[j];
            s3 += S21[i + j * m] * SPEC21[j] * x3[j];
        }
        assert_close_abs(d3[i] - s3, d1[i] - s1, 1e-9, 1e-12);
    }
    /* ranlxd2: another stream, also reproducible */
    double opts[IGEA_SIM_OPT_LEN];
    igea_sim_defaults(opts);
    opts[IGEA_SIM_OPT_GENERATOR] = IGEA_SIM_RANLXD2;
    assert_int_equal(sim_flight(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL,
                                     opts, 42, 7, x2, d2), 0);
    assert_true(x2[0] != x1[0]);
    assert_int_equal(sim_flight(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL,
                                     opts, 42, 7, x3, d3), 0);
    assert_memory_equal(d2, d3, sizeof d2);
}

/* Noise statistics with S = 0 on a long record: sigma_w scale, AR(1),
 * growth, outliers (normal-theory bounds at > 5 sd). */
static void test_flight_noise(void **state)
{
    enum { ME = 20000, MR = 3 * ME };
    double *S0 = calloc(MR, sizeof(double)), *dw = malloc(MR * sizeof(double));
    double *sig = malloc(MR * sizeof(double)), opts[IGEA_SIM_OPT_LEN];
    for (int i = 0; i < MR; i++)
        sig[i] = 0.5 + (i % 7) * 0.1;
    igea_sim_defaults(opts);
    opts[IGEA_SIM_OPT_SIGMA_W] = 1.8;
    assert_int_equal(sim_flight(MR, 1, S0, MR, sig, 1, NULL, NULL, NULL, opts,
                                     1, 0, NULL, dw), 0);
    double v = 0;
    for (int i = 0; i < MR; i++)
        v += (dw[i] / sig[i]) * (dw[i] / sig[i]);
    v /= MR; /* E = 3.24, sd 3.24 sqrt(2/MR) = 0.0187 */
    assert_close_abs(v, 3.24, 0, 6 * 3.24 * sqrt(2.0 / MR));

    /* AR(1) phi = 0.6 per axis along epochs; unit variance kept */
    opts[IGEA_SIM_OPT_SIGMA_W] = 1.0;
    opts[IGEA_SIM_OPT_AR1] = 0.6;
    assert_int_equal(sim_flight(MR, 1, S0, MR, sig, 1, NULL, NULL, NULL, opts,
                                     2, 0, NULL, dw), 0);
    for (int a = 0; a < 3; a++) {
        double c1 = 0, c0 = 0;
        for (int e = 1; e < ME; e++) {
            double u = dw[3 * e + a] / sig[3 * e + a];
            double p = dw[3 * (e - 1) + a] / sig[3 * (e - 1) + a];
            c1 += u * p;
            c0 += u * u;
        }
        /* sd of the lag-1 estimate ~ sqrt((1 - phi^2)(1 + ...)/n) < 0.01 */
        assert_close_abs(c1 / c0, 0.6, 0, 0.05);
        assert_close_abs(c0 / (ME - 1), 1.0, 0, 0.1);
    }
    /* growth g = 2: the true sd triples from the first to the last epoch */
    opts[IGEA_SIM_OPT_AR1] = 0.0;
    opts[IGEA_SIM_OPT_GROWTH] = 2.0;
    assert_int_equal(sim_flight(MR, 1, S0, MR, sig, 1, NULL, NULL, NULL, opts,
                                     3, 0, NULL, dw), 0);
    double vf = 0, vl = 0;
    int nb = 3 * 2000;
    for (int i = 0; i < nb; i++) {
        double gf = 1.0 + 2.0 * (i / 3) / (double)(ME - 1);
        double gl = 1.0 + 2.0 * ((MR - 1 - i) / 3) / (double)(ME - 1);
        vf += pow(dw[i] / (sig[i] * gf), 2);
        vl += pow(dw[MR - 1 - i] / (sig[MR - 1 - i] * gl), 2);
    }
    assert_close_abs(vf / nb, 1.0, 0, 6 * sqrt(2.0 / nb));
    assert_close_abs(vl / nb, 1.0, 0, 6 * sqrt(2.0 / nb));
    /* outliers: p = 0.02, scale 10: rows beyond 5 sd are outliers with
     * probability 2 (1 - Phi(5 / sqrt(101))) (plus 5.7e-7 of normal rows) */
    opts[IGEA_SIM_OPT_GROWTH] = 0.0;
    opts[IGEA_SIM_OPT_OUTLIER_PROB] = 0.02;
    assert_int_equal(sim_flight(MR, 1, S0, MR, sig, 1, NULL, NULL, NULL, opts,
                                     4, 0, NULL, dw), 0);
    int big = 0;
    for (int i = 0; i < MR; i++)
        big += fabs(dw[i] / sig[i]) > 5.0;
    double p_big = 0.02 * 2.0 * gsl_cdf_ugaussian_Q(5.0 / sqrt(101.0)) +
                   0.98 * 2.0 * gsl_cdf_ugaussian_Q(5.0);
    assert_true(binom_ok(big, MR, p_big));
    free(S0);
    free(dw);
    free(sig);
}

static void test_flight_signal(void **state)
{
    int m = 3 * M_EP;
    double x[NT], dw[3 * M_EP], tiny = 1e-12;
    assert_int_equal(sim_flight(m, NT, S21, m, &tiny, 0, SPEC21, NULL, NULL,
                                     NULL, 5, 0, x, dw), 0);
    for (int i = 0; i < m; i++) {
        double s = 0;
        for (int j = 0; j < NT; j++)
            s += S21[i + j * m] * SPEC21[j] * x[j];
        assert_close_abs(dw[i], s, 1e-12, 1e-9);
    }
}

/* Invalid arguments of the model's setters: the model is left as it was. */
static void model_setters_invalid(igea_sim_model *md)
{
    int xf[NT] = {0};
    double x[NT] = {0}, bad_sig = -1.0, nan_sig = NAN;
    assert_int_equal(igea_sim_model_set_sigma(NULL, &SIG, 0, 0.0), -1);
    assert_int_equal(igea_sim_model_set_sigma(md, NULL, 0, 0.0), -2);
    assert_int_equal(igea_sim_model_set_sigma(md, &SIG, 2, 0.0), -3);
    assert_int_equal(igea_sim_model_set_sigma(md, &SIG, 0, -0.5), -4);
    assert_int_equal(igea_sim_model_set_sigma(md, &SIG, 0, NAN), -4);
    assert_int_equal(igea_sim_model_set_sigma(md, &bad_sig, 0, 0.0), IGEA_ENONPOSITIVE);
    assert_int_equal(igea_sim_model_set_sigma(md, &nan_sig, 0, 0.0), IGEA_ENONFINITE);
    double big = 1e308;
    assert_int_equal(igea_sim_model_set_sigma(md, &big, 0, 10.0), IGEA_ERANGE);
    double spec_bad[NT];
    memcpy(spec_bad, SPEC21, sizeof spec_bad);
    spec_bad[20] = 0.0;
    assert_int_equal(igea_sim_model_set_spec(NULL, SPEC21), -1);
    assert_int_equal(igea_sim_model_set_spec(md, spec_bad), IGEA_ENONPOSITIVE);
    assert_int_equal(igea_sim_model_set_truth(NULL, NULL, NULL), -1);
    assert_int_equal(igea_sim_model_set_truth(md, NULL, xf), -2);
    xf[3] = 2;
    assert_int_equal(igea_sim_model_set_truth(md, x, xf), -3);
    double xv[NT] = {0};
    int xf0[NT] = {0};
    xv[2] = INFINITY;
    assert_int_equal(igea_sim_model_set_truth(md, xv, xf0), IGEA_ENONFINITE);
}

/* Invalid arguments of the model's constructors, setters and flights
 * (statuses by argument position); a failure leaves outputs and the
 * model as they were. */
static void test_flight_invalid(void **state)
{
    int m = 3 * M_EP, mm = -1, nn = -1;
    double x[NT], dw[3 * M_EP], sg[3 * M_EP], d1[3 * M_EP], d2[3 * M_EP];
    igea_sim_model *md = (igea_sim_model *)&mm;
    fill_sentinel(dw, (size_t)m);
    fill_sentinel(x, NT);
    assert_int_equal(igea_sim_model_create(m - 1, NT, S21, m, &md), -1);
    assert_null(md);
    assert_int_equal(igea_sim_model_create(0, NT, S21, m, &md), -1);
    assert_int_equal(igea_sim_model_create(m, 0, S21, m, &md), -2);
    assert_int_equal(igea_sim_model_create(m, NT, NULL, m, &md), -3);
    assert_int_equal(igea_sim_model_create(m, NT, S21, m - 1, &md), -4);
    assert_int_equal(igea_sim_model_create(m, NT, S21, m, NULL), -5);
    double S1[6] = {1, 2, 3, 4, NAN, 6};
    assert_int_equal(igea_sim_model_create(3, 2, S1, 3, &md), IGEA_ENONFINITE);
    assert_null(md);
    assert_int_equal(make_model(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL, NULL, &md), 0);
    assert_int_equal(igea_sim_flight(md, 1, 0, x, d1), 0);
    model_setters_invalid(md);
    assert_int_equal(igea_sim_model_set_nonlinear(md, 1), -2); /* no trajectory */
    assert_int_equal(igea_sim_model_set_nonlinear(NULL, 0), -1);
    assert_int_equal(igea_sim_flight(NULL, 1, 0, x, dw), -1);
    assert_int_equal(igea_sim_flight(md, -1, 0, x, dw), -2);
    assert_int_equal(igea_sim_flight(md, 1, -1, x, dw), -3);
    assert_int_equal(igea_sim_flight(md, 1, 0, x, NULL), -5);
    assert_true(all_sentinel(dw, (size_t)m));
    /* the failed setters left the model as it was */
    fill_sentinel(x, NT);
    assert_int_equal(igea_sim_flight(md, 1, 0, x, d2), 0);
    assert_memory_equal(d1, d2, sizeof d1);
    assert_int_equal(igea_sim_model_get_size(md, &mm, &nn), 0);
    assert_true(mm == m && nn == NT);
    assert_int_equal(igea_sim_model_get_sigma(md, sg), 0);
    for (int i = 0; i < m; i++)
        assert_true(sg[i] == SIG);
    assert_int_equal(igea_sim_model_get_size(md, NULL, &nn), -2);
    assert_int_equal(igea_sim_model_get_s(md, dw, m - 1), -3);
    assert_int_equal(igea_sim_model_get_spec(md, NULL), -2);
    igea_sim_model_free(md);
    igea_sim_model_free(NULL);
}

/* igea_sim_check_opts and the noise setter. */
static void test_check_opts(void **state)
{
    double opts[IGEA_SIM_OPT_LEN], S1[6] = {1, 2, 3, 4, 5, 6};
    igea_sim_model *md = NULL;
    assert_int_equal(igea_sim_model_create(3, 2, S1, 3, &md), 0);
    igea_sim_defaults(opts);
    opts[IGEA_SIM_OPT_SIGMA_W] = 0.0;
    assert_int_equal(igea_sim_model_set_noise(md, opts), -2);
    assert_int_equal(igea_sim_check_opts(opts), 1 + IGEA_SIM_OPT_SIGMA_W);
    igea_sim_defaults(opts);
    opts[IGEA_SIM_OPT_AR1] = 1.0;
    assert_int_equal(igea_sim_model_set_noise(md, opts), -2);
    assert_int_equal(igea_sim_check_opts(opts), 1 + IGEA_SIM_OPT_AR1);
    igea_sim_defaults(opts);
    opts[IGEA_SIM_OPT_GROWTH] = -1.0;
    assert_int_equal(igea_sim_check_opts(opts), 1 + IGEA_SIM_OPT_GROWTH);
    igea_sim_defaults(opts);
    opts[IGEA_SIM_OPT_OUTLIER_PROB] = 1.5;
    assert_int_equal(igea_sim_model_set_noise(md, opts), -2);
    assert_int_equal(igea_sim_check_opts(opts), 1 + IGEA_SIM_OPT_OUTLIER_PROB);
    igea_sim_defaults(opts);
    opts[IGEA_SIM_OPT_OUTLIER_SCALE] = -1.0;
    assert_int_equal(igea_sim_check_opts(opts), 1 + IGEA_SIM_OPT_OUTLIER_SCALE);
    igea_sim_defaults(opts);
    opts[IGEA_SIM_OPT_GENERATOR] = 3;
    assert_int_equal(igea_sim_model_set_noise(md, opts), -2);
    assert_int_equal(igea_sim_check_opts(opts), 1 + IGEA_SIM_OPT_GENERATOR);
    opts[IGEA_SIM_OPT_GENERATOR] = NAN;
    assert_int_equal(igea_sim_check_opts(opts), 1 + IGEA_SIM_OPT_GENERATOR);
    igea_sim_defaults(opts);
    opts[7] = INFINITY; /* a reserved slot */
    assert_int_equal(igea_sim_check_opts(opts), 8);
    assert_int_equal(igea_sim_check_opts(NULL), -1);
    igea_sim_defaults(opts);
    assert_int_equal(igea_sim_check_opts(opts), 0);
    assert_int_equal(igea_sim_model_set_noise(md, opts), 0);
    assert_int_equal(igea_sim_model_set_noise(md, NULL), 0);
    assert_int_equal(igea_sim_model_set_noise(NULL, NULL), -1);
    igea_sim_model_free(md);
}

/* ---- Monte Carlo ----------------------------------------------------------- */
#define NF 300

static void run_mc(const double *opts, const double *eqo, int first, int nf,
                   int nthreads, double *counts, int *ct, int *cr, double *chi2,
                   int *dof, int *nrej, double *scale)
{
    int m = 3 * M_EP;
    assert_int_equal(sim_mc(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL,
                                         opts, 2024, eqo, first, nf, nthreads,
                                         counts, ct, cr, chi2, dof, nrej, scale), 0);
}

/* Results do not depend on the thread count or on chunking, and each
 * flight's verdict equals igea_eqerr_run on igea_sim_flight's data. */
static void test_mc_threads(void **state)
{
    double c1[IGEA_SIM_MC_LEN], c2[IGEA_SIM_MC_LEN], c3[IGEA_SIM_MC_LEN];
    int ct1[NT], cr1[NT], ct2[NT], cr2[NT], d1[NF], d2[NF], n1[NF], n2[NF];
    double x1[NF], x2[NF], s1[NF], s2[NF];
    run_mc(NULL, NULL, 0, NF, 1, c1, ct1, cr1, x1, d1, n1, s1);
    run_mc(NULL, NULL, 0, NF, 2, c2, ct2, cr2, x2, d2, n2, s2);
    assert_memory_equal(c1, c2, sizeof c1);
    assert_memory_equal(ct1, ct2, sizeof ct1);
    assert_memory_equal(cr1, cr2, sizeof cr1);
    assert_memory_equal(x1, x2, sizeof x1);
    assert_memory_equal(s1, s2, sizeof s1);
    assert_memory_equal(d1, d2, sizeof d1);
    assert_memory_equal(n1, n2, sizeof n1);
    run_mc(NULL, NULL, 0, NF, 3, c3, NULL, NULL, NULL, NULL, NULL, NULL);
    assert_memory_equal(c1, c3, sizeof c1);
    /* chunk: flights 100..299 alone */
    run_mc(NULL, NULL, 100, NF - 100, 2, c3, NULL, NULL, x2, d2, n2, s2);
    assert_memory_equal(x1 + 100, x2, (NF - 100) * sizeof(double));
    assert_memory_equal(n1 + 100, n2, (NF - 100) * sizeof(int));
    assert_true(c1[IGEA_SIM_MC_FLIGHTS] == NF);
    /* independent route: flight f through igea_sim_flight + igea_eqerr_run */
    int m = 3 * M_EP;
    for (int f = 0; f < 5; f++) {
        double dw[3 * M_EP], lam[NT], P[NT * NT], xh[NT], z[NT], info[IGEA_STATS_INFO_LEN];
        int rej[NT];
        assert_int_equal(sim_flight(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL,
                                         NULL, 2024, f, NULL, dw), 0);
        assert_int_equal(igea_eqerr_run(m, NT, S21, m, dw, &SIG, 0, SPEC21, NULL, lam,
                                        P, NT, xh, z, rej, info, NULL, NULL), 0);
        assert_close(x1[f], info[IGEA_STATS_INFO_CHI2], 1e-10); /* the same normal equations */
        assert_int_equal(d1[f], (int)info[IGEA_STATS_INFO_DOF]);
        assert_int_equal(n1[f], (int)info[IGEA_STATS_INFO_N_REJECT]);
        assert_close(s1[f], info[IGEA_STATS_INFO_SCALE], 1e-6);
    }
}

/* Study 1 (small): sigma_w = 1, X ~ N(0, I), no sigma_w correction, alpha
 * = 0.1: every component test and the chi-square test have exact size
 * alpha; counts must lie in the binomial 1e-6 regions. */
static void test_mc_size(void **state)
{
    double counts[IGEA_SIM_MC_LEN], eqo[IGEA_EQERR_OPT_LEN];
    int ct[NT], cr[NT];
    igea_eqerr_defaults(eqo);
    eqo[IGEA_EQERR_OPT_ALPHA] = 0.1;
    eqo[IGEA_EQERR_OPT_CORRECTION] = 0;
    run_mc(NULL, eqo, 0, NF, 0, counts, ct, cr, NULL, NULL, NULL, NULL);
    print_message("size: chi2 rejected %g of %d, any component %g\n",
                  counts[IGEA_SIM_MC_CHI2_REJECT], NF, counts[IGEA_SIM_MC_ANY_REJECT]);
    assert_true(binom_ok((int)counts[IGEA_SIM_MC_CHI2_REJECT], NF, 0.1));
    int ntested = 0;
    for (int i = 0; i < NT; i++) {
        if (ct[i] == 0)
            continue;
        ntested++;
        assert_int_equal(ct[i], NF); /* fixed test set when c = 1 */
        assert_true(binom_ok(cr[i], NF, 0.1));
    }
    assert_int_equal(ntested, 7);
    assert_true(counts[IGEA_SIM_MC_MEAN_SCALE] == 1.0);
    assert_int_equal((int)counts[IGEA_SIM_MC_NOT_TESTABLE], 0);
}

/* Study 2 (small): true sigma_w = 10, stated 1. Without the correction
 * the weakest tested component (lambda_7) rejects with probability
 * 2 Q(z / sqrt(1 + 100 / lambda_7)) >> alpha; with it, c ~ 100 and the
 * chi-square test is back near alpha. */
static void test_mc_misstated(void **state)
{
    double counts[IGEA_SIM_MC_LEN], eqo[IGEA_EQERR_OPT_LEN], opts[IGEA_SIM_OPT_LEN];
    int ct[NT], cr[NT], m = 3 * M_EP;
    double scale[NF];
    igea_sim_defaults(opts);
    opts[IGEA_SIM_OPT_SIGMA_W] = 10.0;
    igea_eqerr_defaults(eqo);
    eqo[IGEA_EQERR_OPT_ALPHA] = 0.1;
    eqo[IGEA_EQERR_OPT_CORRECTION] = 0;
    /* lambda of the weighted, scaled S (does not depend on dw) */
    double dw[3 * M_EP], lam[NT], P[NT * NT], xh[NT], z[NT], info[IGEA_STATS_INFO_LEN];
    int rej[NT];
    sim_flight(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL, NULL, 1, 0, NULL, dw);
    assert_int_equal(igea_eqerr_run(m, NT, S21, m, dw, &SIG, 0, SPEC21, eqo, lam, P,
                                    NT, xh, z, rej, info, NULL, NULL), 0);
    int last = (int)info[IGEA_STATS_INFO_N_TEST] - 1;
    double zc = info[IGEA_STATS_INFO_Z_CRIT];
    /* X_i ~ N(0, 1 + sigma_w^2 / lambda_i): z_i = Xhat_i / sqrt(1 + 1/lambda_i) */
    double sd = sqrt((1.0 + 100.0 / lam[last]) / (1.0 + 1.0 / lam[last]));
    double p_last = 2.0 * gsl_cdf_ugaussian_Q(zc / sd);
    run_mc(opts, eqo, 0, NF, 0, counts, ct, cr, NULL, NULL, NULL, NULL);
    print_message("misstated: lambda_%d = %.4g, component rejection %d of %d "
                  "(exact p %.4f)\n", last + 1, lam[last], cr[last], NF, p_last);
    assert_true(p_last > 0.3);
    assert_true(binom_ok(cr[last], NF, p_last));
    double uncorrected = counts[IGEA_SIM_MC_FAILED];
    eqo[IGEA_EQERR_OPT_CORRECTION] = 1;
    run_mc(opts, eqo, 0, NF, 0, counts, ct, cr, NULL, NULL, NULL, scale);
    print_message("misstated: failed %g uncorrected, %g corrected; mean c %.4g\n",
                  uncorrected, counts[IGEA_SIM_MC_FAILED], counts[IGEA_SIM_MC_MEAN_SCALE]);
    /* c estimates sigma_w^2 = 100 from ~12 small eigenvalues (relative sd
     * ~ sqrt(2/12) per flight, /sqrt(300) for the mean: 2.4 %) */
    assert_close(counts[IGEA_SIM_MC_MEAN_SCALE], 100.0, 0.15);
    /* family-wise size at alpha = 0.1 with 5-7 components is 0.4-0.5; the
     * uncorrected run fails ~0.74 of the flights */
    assert_true(counts[IGEA_SIM_MC_FAILED] < 0.75 * uncorrected);
}

/* lds > m with NaN padding: same flights and verdicts as lds = m. */
static void test_lds_padding(void **state)
{
    int m = 3 * M_EP, ld = m + 5;
    double *Sp = malloc(sizeof(double) * (size_t)ld * NT);
    double d1[3 * M_EP], d2[3 * M_EP], c1[IGEA_SIM_MC_LEN], c2[IGEA_SIM_MC_LEN], x1[50], x2[50];
    fill_nan(Sp, (size_t)ld * NT);
    for (int j = 0; j < NT; j++)
        memcpy(Sp + (size_t)j * ld, S21 + (size_t)j * m, sizeof(double) * m);
    assert_int_equal(sim_flight(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL, NULL,
                                     9, 3, NULL, d1), 0);
    assert_int_equal(sim_flight(m, NT, Sp, ld, &SIG, 0, SPEC21, NULL, NULL, NULL,
                                     9, 3, NULL, d2), 0);
    assert_memory_equal(d1, d2, sizeof d1);
    assert_int_equal(sim_mc(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL, NULL,
                                         9, NULL, 0, 50, 1, c1, NULL, NULL, x1, NULL,
                                         NULL, NULL), 0);
    assert_int_equal(sim_mc(m, NT, Sp, ld, &SIG, 0, SPEC21, NULL, NULL, NULL,
                                         9, NULL, 0, 50, 2, c2, NULL, NULL, x2, NULL,
                                         NULL, NULL), 0);
    assert_memory_equal(c1, c2, sizeof c1);
    assert_memory_equal(x1, x2, sizeof x1);
    free(Sp);
}

static void test_nonlinear_invalid(void **state)
{
    enum { NS = 4 };
    double tr[NS * IGEA_ENVFUN_TRAJ_COLS], ep[2] = {0.5, 1.0}, dW[6], err[IGEA_ENVFUN_TERM_COUNT] = {0};
    int axes[6] = {0, 1, 2, 1, 2, 3};
    for (int k = 0; k < NS; k++) {
        tr[k] = k;
        for (int c = 1; c < IGEA_ENVFUN_TRAJ_COLS; c++)
            tr[k + c * NS] = (c == 7) ? 1.0 : 0.1 * c;
    }
    fill_sentinel(dW, 6);
#define NL(...) igea_sim_nonlinear(__VA_ARGS__)
    assert_int_equal(NL(2, NS, tr, NS, err, NULL, 2, ep, dW), -1);
    assert_int_equal(NL(0, 1, tr, NS, err, NULL, 2, ep, dW), -2);
    assert_int_equal(NL(0, NS, NULL, NS, err, NULL, 2, ep, dW), -3);
    assert_int_equal(NL(0, NS, tr, NS - 1, err, NULL, 2, ep, dW), -4);
    assert_int_equal(NL(0, NS, tr, NS, NULL, NULL, 2, ep, dW), -5);
    err[IGEA_ENVFUN_TERM_ALIGN0_X] = 1e-4; /* a platform term in a strapdown run */
    assert_int_equal(NL(0, NS, tr, NS, err, NULL, 2, ep, dW), -5);
    err[IGEA_ENVFUN_TERM_ALIGN0_X] = 0.0;
    assert_int_equal(NL(1, NS, tr, NS, err, axes, 2, ep, dW), -6);
    assert_int_equal(NL(0, NS, tr, NS, err, NULL, 0, ep, dW), -7);
    assert_int_equal(NL(0, NS, tr, NS, err, NULL, 2, NULL, dW), -8);
    double ep_bad[2] = {1.0, 0.5};
    assert_int_equal(NL(0, NS, tr, NS, err, NULL, 2, ep_bad, dW), -8);
    assert_int_equal(NL(0, NS, tr, NS, err, NULL, 2, ep, NULL), -9);
    err[0] = NAN;
    assert_int_equal(NL(0, NS, tr, NS, err, NULL, 2, ep, dW), IGEA_ENONFINITE);
    err[0] = 0.0;
    tr[7 * NS] = 0.0; /* zero quaternion at t_0 (q1..q3 = 0.8, 0.9, 1.0) */
    tr[8 * NS] = tr[9 * NS] = tr[10 * NS] = 0.0;
    assert_int_equal(NL(0, NS, tr, NS, err, NULL, 2, ep, dW), IGEA_EDOMAIN);
    assert_true(all_sentinel(dW, 6));
    err[0] = 0.01; /* platform: bias only, dW = 0.01 t e_x exactly */
    assert_int_equal(NL(1, NS, tr, NS, err, NULL, 2, ep, dW), 0);
    assert_close(dW[0], 0.005, 1e-13);
    assert_close(dW[3], 0.01, 1e-13);
    assert_true(dW[1] == 0.0 && dW[5] == 0.0);
#undef NL
}

/* The truth model and S X agree to second order on the 21-term model. */
static void test_nonlinear_vs_linear(void **state)
{
    int n = 0, m = 3 * M_EP, codes[NT], k = 0;
    for (int c = 0; c < IGEA_ENVFUN_TERM_GYRO_SCALE_X; c++)
        if (c < IGEA_ENVFUN_TERM_ACC_SQ_X || c >= IGEA_ENVFUN_TERM_ACC_MIS_XY)
            codes[k++] = c;
    for (int a = 0; a < 3; a++)
        codes[k++] = IGEA_ENVFUN_TERM_ATT0_X + a;
    igea_sim_trajectory_length(120.0, 50.0, &n);
    double *tr = malloc(sizeof(double) * (size_t)n * IGEA_ENVFUN_TRAJ_COLS);
    igea_sim_trajectory(IGEA_ENVFUN_STRAPDOWN, 120.0, 50.0, n, tr, n);
    double x[NT], dw[3 * M_EP], err[IGEA_ENVFUN_TERM_COUNT] = {0}, ep[M_EP], nl[3 * M_EP], tiny = 1e-15;
    for (int e = 0; e < M_EP; e++)
        ep[e] = e + 1.0;
    /* X ~ N(0, I) in spec units: linear part from igea_sim_flight, no noise */
    assert_int_equal(sim_flight(m, NT, S21, m, &tiny, 0, SPEC21, NULL, NULL, NULL, 3, 0,
                                     x, dw), 0);
    for (int j = 0; j < NT; j++)
        err[codes[j]] = x[j] * SPEC21[j];
    assert_int_equal(igea_sim_nonlinear(IGEA_ENVFUN_STRAPDOWN, n, tr, n, err, NULL, M_EP,
                                        ep, nl), 0);
    double md = 0, mn = 0;
    for (int i = 0; i < m; i++) {
        md = fmax(md, fabs(nl[i] - dw[i]));
        mn = fmax(mn, fabs(nl[i]));
    }
    print_message("truth model vs S X (21 terms, X ~ N(0, I)): max |dW| %.3g m/s, "
                  "rel discrepancy %.3g\n", mn, md / mn);
    assert_true(mn > 0.1);
    assert_true(md / mn < 1e-3);
    free(tr);
}

/* Fail the 1st, 2nd, ... allocation of each call until it succeeds: every
 * failure is IGEA_ENOMEM with the outputs untouched, the success equals an
 * unconstrained call. GSL's default (aborting) handler stays in place:
 * the library must not reach it. */
static void test_oom(void **state)
{
#ifdef OOM_DISABLED
    skip();
#else
    enum { F = 20 };
    int m = 3 * M_EP, n = 0;
    double ref[IGEA_SIM_MC_LEN], c[IGEA_SIM_MC_LEN], x[NT], dw[3 * M_EP], dref[3 * M_EP];
    assert_int_equal(sim_mc(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL, NULL, 1,
                                         NULL, 0, F, 2, ref, NULL, NULL, NULL, NULL, NULL,
                                         NULL), 0);
    int st, fails = 0;
    for (long k = 0;; k++) {
        fill_sentinel(c, IGEA_SIM_MC_LEN);
        oom_calls = 0;
        oom_fail_at = k;
        st = sim_mc(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL, NULL, 1, NULL,
                                 0, F, 2, c, NULL, NULL, NULL, NULL, NULL, NULL);
        oom_fail_at = -1;
        if (st == 0)
            break;
        fails++;
        assert_int_equal(st, IGEA_ENOMEM);
        assert_true(all_sentinel(c, IGEA_SIM_MC_LEN));
        assert_true(k < 1000);
    }
    assert_true(fails >= 3);
    assert_memory_equal(c, ref, sizeof c);

    assert_int_equal(sim_flight(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL, NULL, 1, 0,
                                     NULL, dref), 0);
    for (long k = 0;; k++) {
        fill_sentinel(dw, (size_t)m);
        oom_calls = 0;
        oom_fail_at = k;
        st = sim_flight(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL, NULL, 1, 0, x, dw);
        oom_fail_at = -1;
        if (st == 0)
            break;
        assert_int_equal(st, IGEA_ENOMEM);
        assert_true(all_sentinel(dw, (size_t)m));
    }
    assert_memory_equal(dw, dref, sizeof dw);

    assert_int_equal(igea_sim_trajectory_length(10.0, 10.0, &n), 0);
    double tr[101 * IGEA_ENVFUN_TRAJ_COLS], ep[10], S1[30 * 3], S2[30 * 3], nl1[30], nl2[30];
    double err[IGEA_ENVFUN_TERM_COUNT] = {0};
    int codes[3] = {IGEA_ENVFUN_TERM_ACC_BIAS_X, IGEA_ENVFUN_TERM_GYRO_BIAS_X + 1, IGEA_ENVFUN_TERM_ATT0_X};
    err[IGEA_ENVFUN_TERM_GYRO_BIAS_X] = 1e-5;
    assert_int_equal(igea_sim_trajectory(0, 10.0, 10.0, n, tr, n), 0);
    for (int e = 0; e < 10; e++)
        ep[e] = e + 0.5;
    assert_int_equal(igea_envfun_compute(0, n, tr, n, 3, codes, NULL, 10, ep, NULL,
                                         IGEA_ENVFUN_POSITION_G, S1, 30), 0);
    assert_int_equal(igea_sim_nonlinear(0, n, tr, n, err, NULL, 10, ep, nl1), 0);
    for (long k = 0;; k++) {
        fill_sentinel(S2, 90);
        fill_sentinel(nl2, 30);
        oom_calls = 0;
        oom_fail_at = k;
        st = igea_envfun_compute(0, n, tr, n, 3, codes, NULL, 10, ep, NULL,
                                 IGEA_ENVFUN_POSITION_G, S2, 30);
        int st2 = igea_sim_nonlinear(0, n, tr, n, err, NULL, 10, ep, nl2);
        oom_fail_at = -1;
        if (st == 0 && st2 == 0)
            break;
        if (st) {
            assert_int_equal(st, IGEA_ENOMEM);
            assert_true(all_sentinel(S2, 90));
        }
        if (st2) {
            assert_int_equal(st2, IGEA_ENOMEM);
            assert_true(all_sentinel(nl2, 30));
        }
    }
    assert_memory_equal(S1, S2, sizeof S1);
    assert_memory_equal(nl1, nl2, sizeof nl1);
#endif
}

static void test_defaults(void **state)
{
    double o[IGEA_SIM_OPT_LEN];
    fill_sentinel(o, IGEA_SIM_OPT_LEN);
    assert_int_equal(igea_sim_defaults(NULL), -1);
    assert_int_equal(igea_sim_defaults(o), 0);
    assert_true(o[IGEA_SIM_OPT_SIGMA_W] == 1.0 && o[IGEA_SIM_OPT_AR1] == 0.0 &&
                o[IGEA_SIM_OPT_GROWTH] == 0.0 && o[IGEA_SIM_OPT_OUTLIER_PROB] == 0.0 &&
                o[IGEA_SIM_OPT_OUTLIER_SCALE] == 10.0 &&
                o[IGEA_SIM_OPT_GENERATOR] == IGEA_SIM_MT19937 && o[6] == 0.0 && o[7] == 0.0);
}

static void test_mc_invalid(void **state)
{
    int m = 3 * M_EP;
    double counts[IGEA_SIM_MC_LEN], eqo[IGEA_EQERR_OPT_LEN], tab[10 * 4];
    igea_sim_model *md = NULL;
    fill_sentinel(counts, IGEA_SIM_MC_LEN);
    fill_sentinel(tab, 40);
    assert_int_equal(make_model(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL, NULL, &md), 0);
#define MC(...) igea_sim_montecarlo(__VA_ARGS__)
    assert_int_equal(MC(NULL, NULL, 1, 0, 10, 1, counts, NULL, NULL, NULL, NULL, 1), -1);
    igea_eqerr_defaults(eqo);
    eqo[IGEA_EQERR_OPT_ALPHA] = NAN;
    assert_int_equal(MC(md, eqo, 1, 0, 10, 1, counts, NULL, NULL, NULL, NULL, 1), -2);
    eqo[IGEA_EQERR_OPT_ALPHA] = 1.5;
    assert_int_equal(MC(md, eqo, 1, 0, 10, 2, counts, NULL, NULL, NULL, NULL, 1), -2);
    assert_int_equal(MC(md, NULL, -3, 0, 10, 1, counts, NULL, NULL, NULL, NULL, 1), -3);
    assert_int_equal(MC(md, NULL, 1, -1, 10, 1, counts, NULL, NULL, NULL, NULL, 1), -4);
    assert_int_equal(MC(md, NULL, 1, 0, 0, 1, counts, NULL, NULL, NULL, NULL, 1), -5);
    assert_int_equal(MC(md, NULL, 1, INT_MAX, 2, 1, counts, NULL, NULL, NULL, NULL, 1), -5);
    assert_int_equal(MC(md, NULL, 1, 0, 10, -1, counts, NULL, NULL, NULL, NULL, 1), -6);
    assert_int_equal(MC(md, NULL, 1, 0, 10, 1, NULL, NULL, NULL, NULL, NULL, 1), -7);
    assert_int_equal(MC(md, NULL, 1, 0, 10, 1, counts, NULL, NULL, NULL, tab, 9), -12);
    assert_true(all_sentinel(counts, IGEA_SIM_MC_LEN));
    assert_true(all_sentinel(tab, 40));
    /* NULL table: ldt is not read */
    assert_int_equal(MC(md, NULL, 1, 0, 10, 1, counts, NULL, NULL, NULL, NULL, 0), 0);
    igea_sim_model_free(md);
    /* all-zero S: nothing testable, every flight passes */
    double S0[30] = {0}, one = 1.0, rates[IGEA_SIM_MC_RATES_LEN];
    assert_int_equal(make_model(6, 5, S0, 6, &one, 0, NULL, NULL, NULL, NULL, &md), 0);
    assert_int_equal(MC(md, NULL, 1, 0, 10, 1, counts, rates, NULL, NULL, tab, 10), 0);
    assert_true(counts[IGEA_SIM_MC_NOT_TESTABLE] == 10 && counts[IGEA_SIM_MC_FAILED] == 0);
    assert_true(isnan(counts[IGEA_SIM_MC_MEAN_SCALE]));
    assert_true(rates[3 * (IGEA_SIM_MC_NOT_TESTABLE - 1)] == 1.0);
    for (int f = 0; f < 10; f++)
        assert_true(tab[f] == 0.0 && tab[10 + f] == 0.0 && isnan(tab[30 + f]));
    igea_sim_model_free(md);
#undef MC
}

/* A model of a trajectory: S and specs as igea_envfun_compute and the
 * catalogue give them, the stated sigma grown by 1 + g e/(M-1), the
 * nonlinear truth equal to the linear flight with S D X replaced by
 * igea_sim_nonlinear of X D; the 99 % Wilson interval in closed cases. */
static void test_model_trajectory(void **state)
{
    enum { NE = 20 };
    int n = 0, codes[3] = {IGEA_ENVFUN_TERM_ACC_BIAS_X, IGEA_ENVFUN_TERM_GYRO_BIAS_X + 1,
                           IGEA_ENVFUN_TERM_ATT0_X + 2};
    assert_int_equal(igea_sim_trajectory_length(40.0, 20.0, &n), 0);
    double *tr = malloc(sizeof(double) * (size_t)n * IGEA_ENVFUN_TRAJ_COLS);
    double ep[NE], S[3 * NE * 3], Sm[3 * NE * 3], sp[3], sg[3 * NE], x[3], dl[3 * NE];
    double dn[3 * NE], nl[3 * NE], err[IGEA_ENVFUN_TERM_COUNT] = {0}, s0 = 0.02;
    assert_non_null(tr);
    assert_int_equal(igea_sim_trajectory(0, 40.0, 20.0, n, tr, n), 0);
    for (int e = 0; e < NE; e++)
        ep[e] = 2.0 * (e + 1);
    igea_sim_model *md = NULL;
    assert_int_equal(igea_sim_model_create_trajectory(0, n, tr, n, 3, codes, NULL, NE, ep,
                                                      &md), 0);
    assert_int_equal(igea_envfun_compute(0, n, tr, n, 3, codes, NULL, NE, ep, NULL,
                                         IGEA_ENVFUN_VELOCITY, S, 3 * NE), 0);
    assert_int_equal(igea_sim_model_get_s(md, Sm, 3 * NE), 0);
    assert_memory_equal(S, Sm, sizeof S);
    assert_int_equal(igea_sim_model_get_spec(md, sp), 0);
    assert_close(sp[0], 1e-3 * 9.80665, 1e-15);
    assert_close(sp[1], 0.5 * 3.14159265358979323846 / 180.0 / 3600.0, 1e-15);
    assert_close(sp[2], 1e-4, 1e-15);
    assert_int_equal(igea_sim_model_set_sigma(md, &s0, 0, 0.5), 0);
    assert_int_equal(igea_sim_model_get_sigma(md, sg), 0);
    for (int i = 0; i < 3 * NE; i++)
        assert_close(sg[i], s0 * (1.0 + 0.5 * (i / 3) / (NE - 1.0)), 1e-15);
    /* truth 20 x spec: second-order effects visible */
    double xv[3] = {20.0, -20.0, 20.0};
    int xf[3] = {1, 1, 1};
    assert_int_equal(igea_sim_model_set_truth(md, xv, xf), 0);
    assert_int_equal(igea_sim_flight(md, 5, 2, x, dl), 0);
    assert_int_equal(igea_sim_model_set_nonlinear(md, 1), 0);
    assert_int_equal(igea_sim_flight(md, 5, 2, x, dn), 0);
    for (int j = 0; j < 3; j++)
        err[codes[j]] = xv[j] * sp[j];
    assert_int_equal(igea_sim_nonlinear(0, n, tr, n, err, NULL, NE, ep, nl), 0);
    double maxd = 0.0;
    for (int i = 0; i < 3 * NE; i++) {
        double lin = 0.0;
        for (int j = 0; j < 3; j++)
            lin += S[i + 3 * NE * j] * sp[j] * xv[j];
        assert_close_abs(dn[i], dl[i] - lin + nl[i], 0.0, 1e-12);
        maxd = fmax(maxd, fabs(nl[i] - lin));
    }
    assert_true(maxd > 1e-6); /* the swap changed dw */
    igea_sim_model_free(md);
    free(tr);

    double lh[2];
    assert_int_equal(igea_sim_interval(0.0, 10.0, lh), 0);
    double z2 = 2.5758293035489004 * 2.5758293035489004;
    assert_close_abs(lh[0], 0.0, 0.0, 1e-15);
    assert_close(lh[1], z2 / (10.0 + z2), 1e-14);
    assert_int_equal(igea_sim_interval(10.0, 10.0, lh), 0);
    assert_close(lh[0], 10.0 / (10.0 + z2), 1e-14);
    assert_close(lh[1], 1.0, 1e-15);
    assert_int_equal(igea_sim_interval(11.0, 10.0, lh), -1);
    assert_int_equal(igea_sim_interval(1.0, 0.0, lh), -2);
    assert_int_equal(igea_sim_interval(1.0, 10.0, NULL), -3);
}

/* ---- pooled verdicts ------------------------------------------------------ */

/* The pooled verdicts written out: groups [g size, (g + 1) size) of the
 * testable rows, "out of spec" when a row has a rejection or the chi-square
 * sum reaches the upper alpha quantile of chi2(summed dof) (GSL); the rate
 * and its 99 % Wilson score interval in closed form. */
static void pool_by_hand(int nf, const double *tab, int ldt, int size, double alpha,
                         double *want)
{
    int npools = nf / size, nfail = 0;
    for (int g = 0; g < npools; g++) {
        double T = 0.0, dof = 0.0, nrej = 0.0;
        for (int f = g * size; f < (g + 1) * size; f++) {
            if (tab[f + ldt * IGEA_SIM_MC_TABLE_DOF] == 0.0)
                continue;
            T += tab[f + ldt * IGEA_SIM_MC_TABLE_CHI2];
            dof += tab[f + ldt * IGEA_SIM_MC_TABLE_DOF];
            nrej += tab[f + ldt * IGEA_SIM_MC_TABLE_N_REJECT];
        }
        if (dof > 0 && (nrej > 0 || T >= gsl_cdf_chisq_Qinv(alpha, dof)))
            nfail++;
    }
    for (int k = 0; k < IGEA_SIM_POOL_LEN; k++)
        want[k] = 0.0;
    want[IGEA_SIM_POOL_POOLS] = npools;
    want[IGEA_SIM_POOL_FAILED] = nfail;
    if (npools == 0) {
        want[IGEA_SIM_POOL_RATE] = want[IGEA_SIM_POOL_CI99_LO] = want[IGEA_SIM_POOL_CI99_HI] = NAN;
        return;
    }
    double n = npools, p = nfail / n, z = gsl_cdf_ugaussian_Pinv(0.995), z2 = z * z;
    double mid = (p + z2 / (2 * n)) / (1 + z2 / n);
    double half = z / (1 + z2 / n) * sqrt(p * (1 - p) / n + z2 / (4 * n * n));
    want[IGEA_SIM_POOL_RATE] = p;
    want[IGEA_SIM_POOL_CI99_LO] = fmax(0.0, mid - half);
    want[IGEA_SIM_POOL_CI99_HI] = fmin(1.0, mid + half);
}

static void assert_pooled(const double *got, const double *want)
{
    for (int k = 0; k < IGEA_SIM_POOL_LEN; k++) {
        if (isnan(want[k]))
            assert_true(isnan(got[k]));
        else if (k == IGEA_SIM_POOL_CI99_LO || k == IGEA_SIM_POOL_CI99_HI)
            assert_close_abs(got[k], want[k], 1e-12, 1e-15);
        else
            assert_true(got[k] == want[k]);
    }
}

/* The pooled verdicts of a Monte Carlo table (misstated sigma_w: many
 * groups fail, some pass) equal the hand computation for several group
 * sizes, a partial last group left out, and a padded table. */
static void test_pool(void **state)
{
    enum { F = 100, LDT = F + 3 };
    int m = 3 * M_EP;
    double opts[IGEA_SIM_OPT_LEN], eqo[IGEA_EQERR_OPT_LEN], counts[IGEA_SIM_MC_LEN];
    double tab[LDT * IGEA_SIM_MC_TABLE_COLS], got[IGEA_SIM_POOL_LEN], want[IGEA_SIM_POOL_LEN];
    igea_sim_defaults(opts);
    opts[IGEA_SIM_OPT_SIGMA_W] = 1.3;
    igea_eqerr_defaults(eqo);
    eqo[IGEA_EQERR_OPT_CORRECTION] = 0;
    igea_sim_model *md = NULL;
    assert_int_equal(make_model(m, NT, S21, m, &SIG, 0, SPEC21, NULL, NULL, opts, &md), 0);
    fill_nan(tab, LDT * IGEA_SIM_MC_TABLE_COLS);
    assert_int_equal(igea_sim_montecarlo(md, eqo, 77, 0, F, 2, counts, NULL, NULL, NULL, tab,
                                         LDT), 0);
    igea_sim_model_free(md);
    int seen_fail = 0, seen_pass = 0;
    static const int sizes[] = {1, 3, 7, 10, 33, 100, 101};
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++) {
        int size = sizes[i];
        pool_by_hand(F, tab, LDT, size, 0.01, want);
        fill_sentinel(got, IGEA_SIM_POOL_LEN);
        assert_int_equal(igea_sim_pool(F, tab, LDT, size, 0.01, got), 0);
        assert_pooled(got, want);
        assert_int_equal((int)got[IGEA_SIM_POOL_POOLS], F / size);
        if (got[IGEA_SIM_POOL_FAILED] > 0)
            seen_fail = 1;
        if (got[IGEA_SIM_POOL_FAILED] < got[IGEA_SIM_POOL_POOLS])
            seen_pass = 1;
    }
    assert_true(seen_fail && seen_pass);
    /* size 1: every flight its own group, the pooled verdict is the flight's */
    assert_int_equal(igea_sim_pool(F, tab, LDT, 1, 0.01, got), 0);
    assert_true(got[IGEA_SIM_POOL_FAILED] == counts[IGEA_SIM_MC_FAILED]);
    /* another alpha changes the chi-square part only */
    pool_by_hand(F, tab, LDT, 4, 0.2, want);
    assert_int_equal(igea_sim_pool(F, tab, LDT, 4, 0.2, got), 0);
    assert_pooled(got, want);

    /* a table by hand, groups of 2 rows: rows 0, 1 pool to T = 6 < chi2_0.01(6)
     * = 16.81; rows 2, 3 hold nothing testable (a group that passes); row 4
     * alone, T = 17 >= chi2_0.01(3) = 11.34, fails its group {4, 5}, or is
     * left out in a partial group when there are 5 rows */
    double h[6 * IGEA_SIM_MC_TABLE_COLS] = {
        /* chi2 */ 2.0, 4.0, 0.0, 0.0, 17.0, 0.0,
        /* dof  */ 3.0, 3.0, 0.0, 0.0, 3.0, 0.0,
        /* nrej */ 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        /* scale */ 1.0, 1.0, NAN, NAN, 1.0, NAN};
    assert_int_equal(igea_sim_pool(5, h, 6, 2, 0.01, got), 0);
    assert_true(got[IGEA_SIM_POOL_POOLS] == 2 && got[IGEA_SIM_POOL_FAILED] == 0);
    assert_true(got[IGEA_SIM_POOL_RATE] == 0.0);
    assert_int_equal(igea_sim_pool(6, h, 6, 2, 0.01, got), 0);
    assert_true(got[IGEA_SIM_POOL_POOLS] == 3 && got[IGEA_SIM_POOL_FAILED] == 1);
    assert_close(got[IGEA_SIM_POOL_RATE], 1.0 / 3.0, 1e-15);
    h[11] = 4.0; /* row 5 tested (T 0): 17 < chi2_0.01(7) = 18.48, the group passes */
    assert_int_equal(igea_sim_pool(6, h, 6, 2, 0.01, got), 0);
    assert_true(got[IGEA_SIM_POOL_FAILED] == 0);
    h[13] = 1.0; /* a rejected component in row 1 fails group 0 whatever its chi-square */
    assert_int_equal(igea_sim_pool(6, h, 6, 2, 0.01, got), 0);
    assert_true(got[IGEA_SIM_POOL_FAILED] == 1 && got[IGEA_SIM_POOL_POOLS] == 3);
    pool_by_hand(6, h, 6, 2, 0.01, want);
    assert_pooled(got, want);
    /* no group: size > nflights */
    fill_sentinel(got, IGEA_SIM_POOL_LEN);
    assert_int_equal(igea_sim_pool(6, h, 6, 7, 0.01, got), 0);
    assert_true(got[IGEA_SIM_POOL_POOLS] == 0 && got[IGEA_SIM_POOL_FAILED] == 0);
    assert_true(isnan(got[IGEA_SIM_POOL_RATE]) && isnan(got[IGEA_SIM_POOL_CI99_LO]) &&
                isnan(got[IGEA_SIM_POOL_CI99_HI]));
}

/* Invalid arguments and table entries: the status, the outputs untouched. */
static void test_pool_invalid(void **state)
{
    double got[IGEA_SIM_POOL_LEN], t[4 * IGEA_SIM_MC_TABLE_COLS];
    /* rows 0..3 of a table with ldt 4: chi2, dof, n_reject, scale */
    static const double t0[4 * IGEA_SIM_MC_TABLE_COLS] = {
        2.0, 1.0, 0.0, 5.0, 3.0, 2.0, 0.0, 4.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, NAN, 1.0};
    fill_sentinel(got, IGEA_SIM_POOL_LEN);
#define POOL(...) igea_sim_pool(__VA_ARGS__)
    assert_int_equal(POOL(0, t0, 4, 2, 0.01, got), -1);
    assert_int_equal(POOL(-1, t0, 4, 2, 0.01, got), -1);
    assert_int_equal(POOL(4, NULL, 4, 2, 0.01, got), -2);
    assert_int_equal(POOL(4, t0, 3, 2, 0.01, got), -3);
    assert_int_equal(POOL(4, t0, 4, 0, 0.01, got), -4);
    assert_int_equal(POOL(4, t0, 4, INT_MIN, 0.01, got), -4);
    assert_int_equal(POOL(4, t0, 4, 2, 0.0, got), -5);
    assert_int_equal(POOL(4, t0, 4, 2, 1.0, got), -5);
    assert_int_equal(POOL(4, t0, 4, 2, NAN, got), -5);
    assert_true(all_sentinel(got, IGEA_SIM_POOL_LEN));
    assert_int_equal(POOL(4, t0, 4, 2, 0.01, NULL), -6);
    /* the entries, each broken in turn (the partial group's rows included) */
    struct { int at; double v; int st; } bad[] = {
        {0, NAN, IGEA_ENONFINITE}, {3, INFINITY, IGEA_ENONFINITE},
        {4, NAN, IGEA_ENONFINITE}, {9, -INFINITY, IGEA_ENONFINITE},
        {0, -1.0, -2},           /* chi2 < 0 */
        {2, 1.0, -2},            /* chi2 > 0 where nothing was tested */
        {5, 2.5, -2},            /* dof not an integer */
        {7, -1.0, -2},           /* dof < 0 */
        {7, 2e5, -2},            /* dof > IGEA_STATS_DOF_MAX */
        {9, 3.0, -2},            /* n_reject > dof */
        {8, 0.5, -2},            /* n_reject not an integer */
        {11, -1.0, -2},          /* n_reject < 0 */
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        memcpy(t, t0, sizeof t);
        t[bad[i].at] = bad[i].v;
        assert_int_equal(POOL(4, t, 4, 2, 0.01, got), bad[i].st);
        assert_true(all_sentinel(got, IGEA_SIM_POOL_LEN));
    }
    /* the scale column is not read; a group's dof beyond IGEA_STATS_DOF_MAX is refused */
    memcpy(t, t0, sizeof t);
    t[12] = NAN, t[13] = INFINITY;
    assert_int_equal(POOL(4, t, 4, 2, 0.01, got), 0);
    fill_sentinel(got, IGEA_SIM_POOL_LEN);
    t[4] = t[5] = 6e4;
    assert_int_equal(POOL(4, t, 4, 2, 0.01, got), -4);
    assert_true(all_sentinel(got, IGEA_SIM_POOL_LEN));
    assert_int_equal(POOL(4, t, 4, 1, 0.01, got), 0); /* groups of one: 6e4 each */
#undef POOL
#ifndef OOM_DISABLED
    double ref[IGEA_SIM_POOL_LEN];
    assert_int_equal(igea_sim_pool(4, t0, 4, 2, 0.01, ref), 0);
    int fails = 0;
    for (long k = 0;; k++) {
        fill_sentinel(got, IGEA_SIM_POOL_LEN);
        OOM_ARM(k);
        int st = igea_sim_pool(4, t0, 4, 2, 0.01, got);
        OOM_DISARM();
        if (st == 0)
            break;
        fails++;
        assert_int_equal(st, IGEA_ENOMEM);
        assert_true(all_sentinel(got, IGEA_SIM_POOL_LEN));
        assert_true(k < 100);
    }
    assert_true(fails >= 1);
    assert_memory_equal(got, ref, sizeof got);
#endif
}

/* ---- one model handle shared by concurrent Monte Carlo runs ------------- */

/* A run of igea_sim_montecarlo_ex on a model that other threads use at the
 * same time (the set-up the handle keeps: sim.h). */
#define SH_NF 96
#define SH_RUNS 4
/* flights of a run: fewer with the robust judge (e = 1), which is slower */
#define SH_NF_OF(e) ((e) ? 6 : SH_NF)
typedef struct {
    const igea_sim_model *md;
    const double *eqo;
    int nthreads, nf, st;
    double counts[IGEA_SIM_MC_LEN], table[SH_NF * IGEA_SIM_MC_TABLE_COLS_Z];
    int ct[NT], cr[NT];
} sh_run;

static void *sh_worker(void *arg)
{
    sh_run *r = arg;
    r->st = igea_sim_montecarlo_ex(r->md, r->eqo, 31, 7, r->nf, r->nthreads, r->counts, NULL,
                                   r->ct, r->cr, r->table, r->nf, IGEA_SIM_MC_TABLE_COLS_Z);
    return NULL;
}

static void sh_assert_same(const sh_run *a, const sh_run *b)
{
    assert_int_equal(a->st, 0);
    assert_int_equal(b->st, 0);
    assert_memory_equal(a->counts, b->counts, sizeof a->counts);
    assert_memory_equal(a->table, b->table, sizeof a->table);
    assert_memory_equal(a->ct, b->ct, sizeof a->ct);
    assert_memory_equal(a->cr, b->cr, sizeof a->cr);
}

/* A model of the 21-term S with the noise options and stated sigma sig. */
static igea_sim_model *sh_model(int batch, double sig)
{
    double opts[IGEA_SIM_OPT_LEN];
    igea_sim_model *md = NULL;
    igea_sim_defaults(opts);
    opts[IGEA_SIM_OPT_SIGMA_W] = 1.2;
    opts[IGEA_SIM_OPT_BATCH] = batch;
    int m = 3 * M_EP;
    assert_int_equal(make_model(m, NT, S21, m, &sig, 0, SPEC21, NULL, NULL, opts, &md), 0);
    return md;
}

/* DESIGN.md: every function is safe to call from many threads at once. Runs
 * on one model handle from SH_RUNS threads at once, before anything is kept
 * (every run computes its own set-up, the first to complete keeps it) and
 * after, on the batched and the flight-by-flight paths (the robust judge,
 * in the same rounds), equal bit for bit the same runs on fresh models one
 * after the other; a new stated sigma then gives the fresh model's results
 * of that sigma. */
#ifdef __GNUC__
extern void openblas_set_num_threads(int) __attribute__((weak));
extern int openblas_get_num_threads(void) __attribute__((weak));
#else
static void (*openblas_set_num_threads)(int) = NULL;
static int (*openblas_get_num_threads)(void) = NULL;
#endif

static void test_mc_shared_model(void **state)
{
    /* OpenBLAS on one thread, as the driver runs the Monte Carlo: its own
     * pool, woken from several threads at once, spins on 2 cores */
    int blas = openblas_get_num_threads ? openblas_get_num_threads() : 0;
    if (blas && openblas_set_num_threads)
        openblas_set_num_threads(1);
    double eq_plain[IGEA_EQERR_OPT_LEN], eq_robust[IGEA_EQERR_OPT_LEN];
    igea_eqerr_defaults(eq_plain);
    igea_eqerr_defaults(eq_robust);
    eq_robust[IGEA_EQERR_OPT_ROBUST] = 1;
    const double *eqs[2] = {eq_plain, eq_robust};
    static sh_run ref[2][2], run[SH_RUNS], ref2;
    for (int batch = 0; batch < 2; batch++) /* 0: batched (default), 1: flight by flight */
        for (int e = 0; e < 2; e++) {
            igea_sim_model *md = sh_model(batch, SIG);
            ref[batch][e] = (sh_run){md, eqs[e], 1, SH_NF_OF(e), -1, {0}, {0}, {0}, {0}};
            sh_worker(&ref[batch][e]);
            igea_sim_model_free(md);
        }
    for (int batch = 0; batch < 2; batch++) {
        igea_sim_model *md = sh_model(batch, SIG);
        for (int round = 0; round < 3; round++) { /* round 0: nothing kept yet */
            pthread_t tid[SH_RUNS];
            for (int k = 0; k < SH_RUNS; k++) {
                run[k] = (sh_run){md, eqs[k % 2], 1 + (k / 2) % 2, SH_NF_OF(k % 2), -1, {0}, {0}, {0}, {0}};
                assert_int_equal(pthread_create(&tid[k], NULL, sh_worker, &run[k]), 0);
            }
            for (int k = 0; k < SH_RUNS; k++)
                pthread_join(tid[k], NULL);
            for (int k = 0; k < SH_RUNS; k++)
                sh_assert_same(&run[k], &ref[batch][k % 2]);
        }
        /* another stated sigma: what was kept is dropped */
        double sig2 = 2 * SIG;
        assert_int_equal(igea_sim_model_set_sigma(md, &sig2, 0, 0.0), 0);
        igea_sim_model *fresh = sh_model(batch, sig2);
        ref2 = (sh_run){fresh, eq_plain, 1, SH_NF, -1, {0}, {0}, {0}, {0}};
        sh_worker(&ref2);
        run[0] = (sh_run){md, eq_plain, 2, SH_NF, -1, {0}, {0}, {0}, {0}};
        sh_worker(&run[0]);
        sh_assert_same(&run[0], &ref2);
        assert_memory_not_equal(ref2.table, ref[batch][0].table, sizeof ref2.table);
        igea_sim_model_free(fresh);
        igea_sim_model_free(md);
    }
    if (blas && openblas_set_num_threads)
        openblas_set_num_threads(blas);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_trajectory),
        cmocka_unit_test(test_flight_reproducible),
        cmocka_unit_test(test_flight_noise),
        cmocka_unit_test(test_flight_signal),
        cmocka_unit_test(test_flight_invalid),
        cmocka_unit_test(test_check_opts),
        cmocka_unit_test(test_mc_threads),
        cmocka_unit_test(test_mc_size),
        cmocka_unit_test(test_mc_misstated),
        cmocka_unit_test(test_mc_invalid),
        cmocka_unit_test(test_lds_padding),
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_oom),
        cmocka_unit_test(test_nonlinear_invalid),
        cmocka_unit_test(test_nonlinear_vs_linear),
        cmocka_unit_test(test_model_trajectory),
        cmocka_unit_test(test_pool),
        cmocka_unit_test(test_pool_invalid),
        cmocka_unit_test(test_mc_shared_model),
    };
    return cmocka_run_group_tests(tests, setup_model, NULL);
}
