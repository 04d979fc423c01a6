/* src/sim.c - reference trajectory, synthetic flights, Monte Carlo of the
 * equivalent-error test (METHODS 1, 5.6). */
#include <limits.h>
#include <pthread.h>
#include <stdint.h>
#include <unistd.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "igea/eqerr.h"
#include "igea/envfun.h"
#include "igea/sim.h"
#include "internal.h"
#include "rotation.h"

#define SIM_PI 3.14159265358979323846

int igea_sim_defaults(double *opts)
{
    if (!opts)
        return -1;
    for (int i = 0; i < IGEA_SIM_OPT_LEN; i++)
        opts[i] = 0.0;
    opts[IGEA_SIM_OPT_SIGMA_W] = 1.0;
    opts[IGEA_SIM_OPT_OUTLIER_SCALE] = 10.0;
    opts[IGEA_SIM_OPT_GENERATOR] = IGEA_SIM_MT19937;
    return 0;
}

/* ---- reference trajectory -------------------------------------------- */

int igea_sim_trajectory_length(double duration, double rate, int *nsamp)
{
    if (!(duration > 0.0 && duration <= 1e5))
        return -1;
    if (!(rate > 0.0 && rate <= 1e4))
        return -2;
    if (!nsamp)
        return -3;
    double n = floor(duration * rate + 0.5) + 1.0;
    if (n < 2.0 || n > (double)INT_MAX)
        return -2;
    *nsamp = (int)n;
    return 0;
}

static void body_rate(double t, double T, double *w)
{
    double t1 = 0.08 * T, t2 = 0.92 * T, pr = 0.0;
    if (t >= t1 && t <= t2) {
        double s = sin(SIM_PI * (t - t1) / (t2 - t1));
        pr = 2.0 * SIM_PI / (3.0 * (t2 - t1)) * s * s;
    }
    w[0] = 0.02 * sin(2.0 * SIM_PI * 0.3 * t);
    w[1] = 0.01 * sin(2.0 * SIM_PI * 0.5 * t + 0.3);
    w[2] = -pr + 0.005 * cos(2.0 * SIM_PI * 0.4 * t);
}

static void body_force(double t, double T, double *f)
{
    f[0] = 15.0 + 10.0 * t / T;
    f[1] = 0.3 * sin(2.0 * SIM_PI * 0.25 * t);
    f[2] = 0.2 * cos(2.0 * SIM_PI * 0.17 * t);
}

int igea_sim_trajectory(int system, double duration, double rate, int nsamp,
                        double *traj, int ldt)
{
    int want = 0;
    if (system != IGEA_ENVFUN_STRAPDOWN && system != IGEA_ENVFUN_PLATFORM)
        return -1;
    if (!(duration > 0.0 && duration <= 1e5))
        return -2;
    if (igea_sim_trajectory_length(duration, rate, &want) != 0)
        return -3;
    if (nsamp != want)
        return -4;
    if (!traj)
        return -5;
    if (ldt < nsamp)
        return -6;
    const int sub = 8;
    double q[4] = {sqrt(0.5), 0.0, 0.0, sqrt(0.5)};
    for (int k = 0; k < nsamp; k++) {
        double t = k / rate, f[3], w[3], fa[3];
        if (k > 0) {
            double h = (t - (k - 1) / rate) / sub;
            for (int s = 0; s < sub; s++) {
                double tm = (k - 1) / rate + (s + 0.5) * h, wm[3], v[3];
                body_rate(tm, duration, wm);
                for (int a = 0; a < 3; a++)
                    v[a] = wm[a] * h;
                igea__quat_rotate(q, v);
            }
        }
        body_force(t, duration, f);
        body_rate(t, duration, w);
        IGEA_AT(traj, ldt, k, 0) = t;
        if (system == IGEA_ENVFUN_PLATFORM) {
            double C[9];
            igea__quat_dcm(q, C);
            igea__m3_vec(C, f, fa, 0);
            memcpy(f, fa, sizeof f);
        }
        for (int a = 0; a < 3; a++) {
            IGEA_AT(traj, ldt, k, 1 + a) = f[a];
            IGEA_AT(traj, ldt, k, 4 + a) = w[a];
        }
        for (int a = 0; a < 4; a++)
            IGEA_AT(traj, ldt, k, 7 + a) = q[a];
    }
    return 0;
}

/* ---- flights ------------------------------------------------------------ */

static unsigned long flight_seed(int seed, int flight)
{
    /* SplitMix64 of the pair (seed, flight) */
    uint64_t z = ((uint64_t)(unsigned)seed << 32) ^ (uint64_t)(unsigned)flight;
    z += 0x9E3779B97F4A7C15ULL;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return (unsigned long)(z & 0xFFFFFFFFUL); /* GSL seeds are 32-bit safe */
}

typedef struct {
    int m, N, lds, sigma_inc;
    const double *S, *track_sigma, *spec, *x_value;
    const int *x_fixed;
    double opts[IGEA_SIM_OPT_LEN];
    int seed;
} flight_ctx;

/* Validate arguments 1-12 of igea_sim_flight / igea_sim_montecarlo. */
static int check_flight_args(int m, int N, const double *S, int lds,
                             const double *track_sigma, int sigma_inc,
                             const double *spec_sigma, const double *x_value,
                             const int *x_fixed, const double *opts, int seed,
                             flight_ctx *ctx)
{
    int nf = 0;
    if (m < 3 || m % 3 != 0)
        return -1;
    if (N < 1)
        return -2;
    if (!S)
        return -3;
    if (lds < m)
        return -4;
    if (!track_sigma)
        return -5;
    if (sigma_inc != 0 && sigma_inc != 1)
        return -6;
    if (x_fixed && !x_value)
        return -8;
    if (x_fixed)
        for (int j = 0; j < N; j++)
            if (x_fixed[j] != 0 && x_fixed[j] != 1)
                return -9;
    if (opts) {
        memcpy(ctx->opts, opts, sizeof ctx->opts);
        if (!igea__finite_vec(IGEA_SIM_OPT_LEN, opts, 1))
            return -10;
    } else {
        igea_sim_defaults(ctx->opts);
    }
    if (!(ctx->opts[IGEA_SIM_OPT_SIGMA_W] > 0.0) ||
        !(fabs(ctx->opts[IGEA_SIM_OPT_AR1]) < 1.0) ||
        !(ctx->opts[IGEA_SIM_OPT_GROWTH] >= 0.0) ||
        !(ctx->opts[IGEA_SIM_OPT_OUTLIER_PROB] >= 0.0 &&
          ctx->opts[IGEA_SIM_OPT_OUTLIER_PROB] <= 1.0) ||
        !(ctx->opts[IGEA_SIM_OPT_OUTLIER_SCALE] >= 0.0) ||
        (ctx->opts[IGEA_SIM_OPT_GENERATOR] != IGEA_SIM_MT19937 &&
         ctx->opts[IGEA_SIM_OPT_GENERATOR] != IGEA_SIM_RANLXD2))
        return -10;
    if (seed < 0)
        return -11;
    if (!igea__finite_mat(m, N, S, lds))
        return IGEA_ENONFINITE;
    if ((nf = igea__sigma_vec(sigma_inc ? m : 1, track_sigma)) != 0)
        return nf;
    if (spec_sigma && (nf = igea__sigma_vec(N, spec_sigma)) != 0)
        return nf;
    if (x_value && !igea__finite_vec(N, x_value, 1))
        return IGEA_ENONFINITE;
    ctx->m = m;
    ctx->N = N;
    ctx->S = S;
    ctx->lds = lds;
    ctx->track_sigma = track_sigma;
    ctx->sigma_inc = sigma_inc;
    ctx->spec = spec_sigma;
    ctx->x_value = x_value;
    ctx->x_fixed = x_fixed;
    ctx->seed = seed;
    return 0;
}

static const gsl_rng_type *rng_type(const flight_ctx *c)
{
    return c->opts[IGEA_SIM_OPT_GENERATOR] == IGEA_SIM_RANLXD2
               ? gsl_rng_ranlxd2
               : gsl_rng_mt19937;
}

/* Generate flight `flight` into x (N) and dw (m); xs (N) is scratch. */
static void gen_flight(const flight_ctx *c, gsl_rng *r, int flight, double *x,
                       double *xs, double *dw)
{
    int m = c->m, N = c->N, M = m / 3;
    double sw = c->opts[IGEA_SIM_OPT_SIGMA_W];
    double phi = c->opts[IGEA_SIM_OPT_AR1];
    double growth = c->opts[IGEA_SIM_OPT_GROWTH];
    double p_out = c->opts[IGEA_SIM_OPT_OUTLIER_PROB];
    double out_scale = c->opts[IGEA_SIM_OPT_OUTLIER_SCALE];
    double innov = sqrt(1.0 - phi * phi), prev[3] = {0, 0, 0};

    gsl_rng_set(r, flight_seed(c->seed, flight));
    for (int j = 0; j < N; j++) {
        double g = gsl_ran_gaussian_ziggurat(r, 1.0);
        x[j] = (c->x_fixed && c->x_fixed[j]) ? c->x_value[j] : g;
        xs[j] = x[j] * (c->spec ? c->spec[j] : 1.0);
    }
    for (int i = 0; i < m; i++)
        dw[i] = 0.0;
    for (int j = 0; j < N; j++) {
        const double *col = c->S + (size_t)j * (size_t)c->lds;
        for (int i = 0; i < m; i++)
            dw[i] += col[i] * xs[j];
    }
    for (int i = 0; i < m; i++) {
        int e = i / 3, a = i % 3;
        double g = gsl_ran_gaussian_ziggurat(r, 1.0);
        double u = gsl_rng_uniform(r);
        double go = gsl_ran_gaussian_ziggurat(r, 1.0);
        double eps = (e == 0) ? g : phi * prev[a] + innov * g;
        double sd = sw * c->track_sigma[c->sigma_inc ? i : 0] *
                    (1.0 + (M > 1 ? growth * e / (double)(M - 1) : 0.0));
        prev[a] = eps;
        dw[i] += sd * eps;
        if (u < p_out)
            dw[i] += out_scale * sd * go;
    }
}

int igea_sim_flight(int m, int N, const double *S, int lds,
                    const double *track_sigma, int sigma_inc,
                    const double *spec_sigma, const double *x_value,
                    const int *x_fixed, const double *opts, int seed,
                    int flight, double *x_true, double *dw)
{
    flight_ctx c;
    int st = check_flight_args(m, N, S, lds, track_sigma, sigma_inc,
                               spec_sigma, x_value, x_fixed, opts, seed, &c);
    if (st)
        return st;
    if (flight < 0)
        return -12;
    if (!dw)
        return -14;
    double *work = igea__dalloc((size_t)m + 2 * (size_t)N);
    if (!work)
        return IGEA_ENOMEM;
    gsl_rng *r = igea__rng_new(rng_type(&c), 0);
    if (!r) {
        free(work);
        return IGEA_ENOMEM;
    }
    gen_flight(&c, r, flight, work + m, work + m + N, work);
    igea__rng_free(r);
    if (!igea__finite_vec(m, work, 1)) {
        free(work);
        return IGEA_ENONFINITE;
    }
    memcpy(dw, work, (size_t)m * sizeof(double));
    if (x_true)
        memcpy(x_true, work + m, (size_t)N * sizeof(double));
    free(work);
    return 0;
}

/* ---- Monte Carlo -------------------------------------------------------- */

typedef struct {
    const flight_ctx *c;
    const double *Sw; /* K^-1/2 S D, m x N */
    const double *A;  /* Sw^T Sw, N x N */
    const double *eq_opts;
    int first, nflights, thread, nthreads;
    /* per-flight results (indexed from 0) */
    double *chi2, *scale;
    int *dof, *nrej, *status;
    /* per-thread component counts */
    int *tested, *rejected;
    int fail; /* a status < 0 other than ENOTESTABLE */
} mc_job;

static void *mc_worker(void *arg)
{
    mc_job *jb = arg;
    const flight_ctx *c = jb->c;
    int m = c->m, N = c->N;
    size_t nn = (size_t)N * N;
    double *w = igea__dalloc(2 * (size_t)m + 6 * (size_t)N + nn +
                             IGEA_STATS_INFO_LEN);
    int *rej = igea__ialloc((size_t)N);
    gsl_rng *r = (w && rej) ? igea__rng_new(rng_type(c), 0) : NULL;
    if (!r) {
        free(w);
        free(rej);
        jb->fail = IGEA_ENOMEM;
        return NULL;
    }
    double *dw = w, *wdw = dw + m, *x = wdw + m, *xs = x + N, *b = xs + N;
    double *lam = b + N, *xhat = lam + N, *P = xhat + N, *z = P + nn;
    double *info = z + N;
    for (int f = jb->thread; f < jb->nflights; f += jb->nthreads) {
        gen_flight(c, r, jb->first + f, x, xs, dw);
        for (int i = 0; i < m; i++)
            wdw[i] = dw[i] / c->track_sigma[c->sigma_inc ? i : 0];
        for (int j = 0; j < N; j++) {
            const double *col = jb->Sw + (size_t)j * (size_t)m;
            double acc = 0.0;
            for (int i = 0; i < m; i++)
                acc += col[i] * wdw[i];
            b[j] = acc;
        }
        int st = igea_eqerr_solve(N, jb->A, N, b, jb->eq_opts, lam, P, N,
                                  xhat, z, rej, info);
        jb->status[f] = st;
        if (st == IGEA_ENOTESTABLE) {
            jb->chi2[f] = 0.0;
            jb->dof[f] = 0;
            jb->nrej[f] = 0;
            jb->scale[f] = NAN;
            continue;
        }
        if (st < 0) {
            jb->fail = (st > -1000) ? -12 : st; /* -5: the eqerr options */
            break;
        }
        jb->chi2[f] = info[IGEA_STATS_INFO_CHI2];
        jb->dof[f] = (int)info[IGEA_STATS_INFO_DOF];
        jb->nrej[f] = (int)info[IGEA_STATS_INFO_N_REJECT];
        jb->scale[f] = info[IGEA_STATS_INFO_SCALE];
        jb->status[f] = info[IGEA_STATS_INFO_CHI2] >= info[IGEA_STATS_INFO_CHI2_CRIT]
                            ? 1 : 0; /* chi-square rejected */
        for (int i = 0; i < N; i++) {
            if (rej[i] >= 0)
                jb->tested[i]++;
            if (rej[i] == 1)
                jb->rejected[i]++;
        }
    }
    igea__rng_free(r);
    free(w);
    free(rej);
    return NULL;
}

int igea_sim_montecarlo(int m, int N, const double *S, int lds,
                        const double *track_sigma, int sigma_inc,
                        const double *spec_sigma, const double *x_value,
                        const int *x_fixed, const double *opts, int seed,
                        const double *eq_opts, int first_flight, int nflights,
                        int nthreads, double *counts, int *comp_tested,
                        int *comp_reject, double *chi2, int *dof,
                        int *n_reject, double *scale)
{
    flight_ctx c;
    double eqo[IGEA_EQERR_OPT_LEN];
    int st = check_flight_args(m, N, S, lds, track_sigma, sigma_inc,
                               spec_sigma, x_value, x_fixed, opts, seed, &c);
    if (st)
        return st;
    if (eq_opts) {
        if (!igea__finite_vec(IGEA_EQERR_OPT_LEN, eq_opts, 1))
            return -12;
        memcpy(eqo, eq_opts, sizeof eqo);
    } else {
        igea_eqerr_defaults(eqo);
    }
    if (first_flight < 0)
        return -13;
    if (nflights < 1 || nflights > INT_MAX - first_flight)
        return -14;
    if (nthreads < 0)
        return -15;
    if (!counts)
        return -16;
    if (nthreads == 0) {
        long np = sysconf(_SC_NPROCESSORS_ONLN);
        nthreads = np > 0 ? (int)IGEA_MIN(np, 64) : 1;
    }
    if (nthreads > nflights)
        nthreads = nflights;
    if (nthreads > 256)
        nthreads = 256;

    size_t nn = (size_t)N * N, nf = (size_t)nflights;
    double *dwork = igea__dalloc((size_t)m * N + nn + 2 * nf);
    int *iwork = igea__ialloc(3 * nf + 2 * (size_t)N * nthreads);
    mc_job *jobs = calloc((size_t)nthreads, sizeof *jobs);
    pthread_t *tid = calloc((size_t)nthreads, sizeof *tid);
    if (!dwork || !iwork || !jobs || !tid) {
        free(dwork);
        free(iwork);
        free(jobs);
        free(tid);
        return IGEA_ENOMEM;
    }
    double *Sw = dwork, *A = Sw + (size_t)m * N, *f_chi2 = A + nn;
    double *f_scale = f_chi2 + nf;
    int *f_dof = iwork, *f_nrej = f_dof + nf, *f_status = f_nrej + nf;
    int *cnt = f_status + nf;
    memset(cnt, 0, 2 * (size_t)N * nthreads * sizeof(int));

    /* whitened, spec-scaled S and its normal matrix (both triangles) */
    for (int j = 0; j < N; j++) {
        double s = spec_sigma ? spec_sigma[j] : 1.0;
        for (int i = 0; i < m; i++)
            IGEA_AT(Sw, m, i, j) =
                IGEA_AT(S, lds, i, j) * s / track_sigma[sigma_inc ? i : 0];
    }
    for (int j = 0; j < N; j++)
        for (int k = 0; k <= j; k++) {
            igea__ksum acc = {0.0, 0.0};
            for (int i = 0; i < m; i++)
                igea__ksum_add(&acc, IGEA_AT(Sw, m, i, j) * IGEA_AT(Sw, m, i, k));
            IGEA_AT(A, N, j, k) = IGEA_AT(A, N, k, j) = igea__ksum_get(&acc);
        }

    int nstarted = 0;
    for (int t = 0; t < nthreads; t++) {
        mc_job *jb = &jobs[t];
        jb->c = &c;
        jb->Sw = Sw;
        jb->A = A;
        jb->eq_opts = eqo;
        jb->first = first_flight;
        jb->nflights = nflights;
        jb->thread = t;
        jb->nthreads = nthreads;
        jb->chi2 = f_chi2;
        jb->scale = f_scale;
        jb->dof = f_dof;
        jb->nrej = f_nrej;
        jb->status = f_status;
        jb->tested = cnt + 2 * (size_t)N * t;
        jb->rejected = jb->tested + N;
        jb->fail = 0;
    }
    if (nthreads == 1) {
        mc_worker(&jobs[0]);
        nstarted = 1;
    } else {
        for (int t = 0; t < nthreads; t++) {
            if (pthread_create(&tid[t], NULL, mc_worker, &jobs[t]) != 0)
                break;
            nstarted++;
        }
        for (int t = 0; t < nstarted; t++)
            pthread_join(tid[t], NULL);
        /* threads that could not start: run their share here */
        for (int t = nstarted; t < nthreads; t++)
            mc_worker(&jobs[t]);
    }
    st = 0;
    for (int t = 0; t < nthreads; t++)
        if (jobs[t].fail)
            st = jobs[t].fail;

    if (st == 0) {
        double res[IGEA_SIM_MC_LEN] = {0};
        double sum_c = 0.0, sum_t = 0.0;
        int n_c = 0;
        res[IGEA_SIM_MC_FLIGHTS] = nflights;
        for (size_t f = 0; f < nf; f++) {
            if (f_status[f] == IGEA_ENOTESTABLE) {
                res[IGEA_SIM_MC_NOT_TESTABLE] += 1;
                continue;
            }
            if (f_status[f] == 1)
                res[IGEA_SIM_MC_CHI2_REJECT] += 1;
            if (f_nrej[f] > 0)
                res[IGEA_SIM_MC_ANY_REJECT] += 1;
            if (f_status[f] == 1 || f_nrej[f] > 0)
                res[IGEA_SIM_MC_FAILED] += 1;
            sum_c += f_scale[f];
            sum_t += f_dof[f];
            n_c++;
        }
        res[IGEA_SIM_MC_MEAN_SCALE] = n_c ? sum_c / n_c : NAN;
        res[IGEA_SIM_MC_MEAN_TESTED] = n_c ? sum_t / n_c : 0.0;
        memcpy(counts, res, sizeof res);
        for (int i = 0; i < N; i++) {
            int te = 0, re = 0;
            for (int t = 0; t < nthreads; t++) {
                te += cnt[2 * (size_t)N * t + i];
                re += cnt[2 * (size_t)N * t + N + i];
            }
            if (comp_tested)
                comp_tested[i] = te;
            if (comp_reject)
                comp_reject[i] = re;
        }
        if (chi2)
            memcpy(chi2, f_chi2, nf * sizeof(double));
        if (scale)
            memcpy(scale, f_scale, nf * sizeof(double));
        if (dof)
            memcpy(dof, f_dof, nf * sizeof(int));
        if (n_reject)
            memcpy(n_reject, f_nrej, nf * sizeof(int));
    }
    free(dwork);
    free(iwork);
    free(jobs);
    free(tid);
    return st;
}

/* ---- nonlinear truth model ------------------------------------------------ */

static void acc_errors(const double *err, const double *f, double *out)
{
    static const int mj[6] = {0, 0, 1, 1, 2, 2}, mk[6] = {1, 2, 0, 2, 0, 1};
    for (int a = 0; a < 3; a++)
        out[a] = f[a] + err[IGEA_ENVFUN_TERM_ACC_BIAS_X + a] +
                 err[IGEA_ENVFUN_TERM_ACC_SCALE_X + a] * f[a] +
                 err[IGEA_ENVFUN_TERM_ACC_SQ_X + a] * f[a] * f[a];
    for (int i = 0; i < 6; i++)
        out[mj[i]] += err[IGEA_ENVFUN_TERM_ACC_MIS_XY + i] * f[mk[i]];
}

/* The state of the two navigations of igea_sim_nonlinear: C the reference
 * attitude (strapdown) or identity, Ch the erroneous attitude (strapdown)
 * or the platform's C_p^a; the previous sample's values (_p) and the
 * apparent velocities W (reference) and Wh (erroneous). */
typedef struct {
    const double *err;
    int in_ax[3], spin_ax[3];
    double C[9], Ch[9];
    double W[3], Wh[3], fa_p[3], fh_p[3], w_p[3], wh_p[3], d_p[3];
    double t_p;
} nav_state;

/* Arguments and data of igea_sim_nonlinear: 0, -i, IGEA_ENONFINITE,
 * IGEA_EDOMAIN; the platform axes. */
static int nonlinear_check(int system, int nsamp, const double *traj, int ldt,
                           const double *err, const int *axes, int nepochs,
                           const double *epochs, const double *dW, int *in_ax,
                           int *spin_ax)
{
    igea__platform_axes(NULL, in_ax, spin_ax);
    if (system != IGEA_ENVFUN_STRAPDOWN && system != IGEA_ENVFUN_PLATFORM)
        return -1;
    if (nsamp < 2)
        return -2;
    if (!traj)
        return -3;
    if (ldt < nsamp)
        return -4;
    if (!err)
        return -5;
    for (int k = 0; k < IGEA_ENVFUN_TERM_COUNT; k++)
        if (err[k] != 0.0 && !igea_envfun_term_valid(system, k))
            return -5;
    if (system == IGEA_ENVFUN_PLATFORM && igea__platform_axes(axes, in_ax, spin_ax))
        return -6;
    if (nepochs < 1 || nepochs > INT_MAX / 3)
        return -7;
    if (!epochs)
        return -8;
    if (!dW)
        return -9;
    if (!igea__finite_mat(nsamp, IGEA_ENVFUN_TRAJ_COLS, traj, ldt) ||
        !igea__finite_vec(IGEA_ENVFUN_TERM_COUNT, err, 1) ||
        !igea__finite_vec(nepochs, epochs, 1))
        return IGEA_ENONFINITE;
    for (int k = 1; k < nsamp; k++)
        if (!(IGEA_AT(traj, ldt, k, 0) > IGEA_AT(traj, ldt, k - 1, 0)))
            return -3;
    for (int e = 0; e < nepochs; e++)
        if (epochs[e] < IGEA_AT(traj, ldt, 0, 0) ||
            epochs[e] > IGEA_AT(traj, ldt, nsamp - 1, 0) ||
            (e > 0 && epochs[e] < epochs[e - 1]))
            return -8;
    double nq = 0.0;
    for (int i = 0; i < 4; i++)
        nq += IGEA_AT(traj, ldt, 0, 7 + i) * IGEA_AT(traj, ldt, 0, 7 + i);
    if (system == IGEA_ENVFUN_STRAPDOWN && !(nq > 1e-200))
        return IGEA_EDOMAIN;
    return 0;
}

/* Initial attitudes: strapdown C(0) and exp(-[phi0 x]) C(0); platform the
 * identity and exp([alpha0 x]). */
static void nav_init(int system, const double *traj, int ldt, nav_state *n)
{
    static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    double q[4], v0[3], E[9];
    memcpy(n->C, I3, sizeof I3);
    if (system == IGEA_ENVFUN_STRAPDOWN) {
        for (int i = 0; i < 4; i++)
            q[i] = IGEA_AT(traj, ldt, 0, 7 + i);
        igea__quat_dcm_unit(q, n->C);
        for (int i = 0; i < 3; i++)
            v0[i] = -n->err[IGEA_ENVFUN_TERM_ATT0_X + i];
        igea__m3_exp(v0, E);
        igea__m3_mul(E, n->C, n->Ch);
    } else {
        for (int i = 0; i < 3; i++)
            v0[i] = n->err[IGEA_ENVFUN_TERM_ALIGN0_X + i];
        igea__m3_exp(v0, n->Ch);
    }
    for (int a = 0; a < 3; a++)
        n->W[a] = n->Wh[a] = n->fa_p[a] = n->fh_p[a] = n->w_p[a] = n->wh_p[a] =
            n->d_p[a] = 0.0;
    n->t_p = 0.0;
}

/* Strapdown step at sample k (time t, body f and w): both attitudes
 * propagated with the trapezoid mean rates; fa the reference a-frame
 * force, fh the erroneous one, wh the erroneous rate. */
static void strapdown_step(nav_state *n, int k, double t, const double *f,
                           const double *w, double *fa, double *fh, double *wh)
{
    const double *err = n->err;
    double fb_h[3];
    for (int a = 0; a < 3; a++)
        wh[a] = w[a] + err[IGEA_ENVFUN_TERM_GYRO_BIAS_X + a] +
                err[IGEA_ENVFUN_TERM_GYRO_G_X + a] * f[a] +
                err[IGEA_ENVFUN_TERM_GYRO_SCALE_X + a] * w[a];
    if (k > 0) {
        double h = t - n->t_p, v[3], R[9];
        for (int a = 0; a < 3; a++)
            v[a] = 0.5 * h * (n->w_p[a] + w[a]);
        igea__m3_exp(v, R);
        igea__m3_mul(n->C, R, n->C);
        for (int a = 0; a < 3; a++)
            v[a] = 0.5 * h * (n->wh_p[a] + wh[a]);
        igea__m3_exp(v, R);
        igea__m3_mul(n->Ch, R, n->Ch);
    }
    acc_errors(err, f, fb_h);
    igea__m3_vec(n->C, f, fa, 0);
    igea__m3_vec(n->Ch, fb_h, fh, 0);
}

/* Platform drift rate eps from the platform-axis force fp. */
static void platform_drift(const nav_state *n, const double *fp, double *eps)
{
    const double *err = n->err;
    for (int j = 0; j < 3; j++)
        eps[j] = err[IGEA_ENVFUN_TERM_GYRO_BIAS_X + j] +
                 err[IGEA_ENVFUN_TERM_GYRO_GI_X + j] * fp[n->in_ax[j]] +
                 err[IGEA_ENVFUN_TERM_GYRO_GS_X + j] * fp[n->spin_ax[j]];
}

/* Platform step at sample k (time t, inertial force f): the platform
 * drifts over the step (eps at the end predicted twice); the
 * accelerometers read the rotated force with their errors (fh), wh the
 * drift rate at the sample. */
static void platform_step(nav_state *n, int k, double t, const double *f,
                          double *fa, double *fh, double *wh)
{
    double fp[3];
    memcpy(fa, f, 3 * sizeof(double));
    if (k > 0) {
        double h = t - n->t_p, P[9], ek[3], fpk[3], v[3], R[9];
        memcpy(P, n->Ch, sizeof P);
        for (int it = 0; it < 2; it++) {
            igea__m3_vec(P, fa, fpk, 1);
            platform_drift(n, fpk, ek);
            for (int j = 0; j < 3; j++)
                v[j] = 0.5 * h * (n->wh_p[j] + ek[j]);
            igea__m3_exp(v, R);
            igea__m3_mul(n->Ch, R, P);
        }
        memcpy(n->Ch, P, sizeof P);
    }
    igea__m3_vec(n->Ch, fa, fp, 1); /* f^p = C_a^p f^a */
    acc_errors(n->err, fp, fh);
    platform_drift(n, fp, wh);
}

int igea_sim_nonlinear(int system, int nsamp, const double *traj, int ldt,
                       const double *err, const int *axes, int nepochs,
                       const double *epochs, double *dW)
{
    nav_state n;
    int st = nonlinear_check(system, nsamp, traj, ldt, err, axes, nepochs,
                             epochs, dW, n.in_ax, n.spin_ax);
    if (st)
        return st;
    double *out = igea__dalloc(3 * (size_t)nepochs);
    if (!out)
        return IGEA_ENOMEM;
    n.err = err;
    nav_init(system, traj, ldt, &n);
    int e = 0;
    for (int k = 0; k < nsamp && e < nepochs; k++) {
        double t = IGEA_AT(traj, ldt, k, 0), f[3], w[3], fa[3], fh[3], wh[3], d[3];
        for (int a = 0; a < 3; a++) {
            f[a] = IGEA_AT(traj, ldt, k, 1 + a);
            w[a] = IGEA_AT(traj, ldt, k, 4 + a);
        }
        if (system == IGEA_ENVFUN_STRAPDOWN)
            strapdown_step(&n, k, t, f, w, fa, fh, wh);
        else
            platform_step(&n, k, t, f, fa, fh, wh);
        if (k > 0) {
            double h = t - n.t_p;
            for (int a = 0; a < 3; a++) {
                n.W[a] += 0.5 * h * (n.fa_p[a] + fa[a]);
                n.Wh[a] += 0.5 * h * (n.fh_p[a] + fh[a]);
            }
        }
        for (int a = 0; a < 3; a++)
            d[a] = n.Wh[a] - n.W[a];
        while (e < nepochs && epochs[e] <= t) {
            double wgt = (k == 0) ? 1.0 : (epochs[e] - n.t_p) / (t - n.t_p);
            for (int a = 0; a < 3; a++)
                out[3 * (size_t)e + a] = (1.0 - wgt) * n.d_p[a] + wgt * d[a];
            e++;
        }
        memcpy(n.fa_p, fa, sizeof fa);
        memcpy(n.fh_p, fh, sizeof fh);
        memcpy(n.w_p, w, sizeof w);
        memcpy(n.wh_p, wh, sizeof wh);
        memcpy(n.d_p, d, sizeof d);
        n.t_p = t;
    }
    st = igea__finite_vec(3 * nepochs, out, 1) ? 0 : IGEA_ENONFINITE;
    if (st == 0)
        memcpy(dW, out, 3 * (size_t)nepochs * sizeof(double));
    free(out);
    return st;
}
