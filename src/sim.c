/* src/sim.c - reference trajectory, synthetic flights, Monte Carlo of the
 * equivalent-error test (METHODS 1, 5.6). */
#include <float.h>
#include <limits.h>
#include <pthread.h>
#include <stdint.h>
#include <unistd.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "igea/eqerr.h"
#include "igea/normal.h"
#include "igea/envfun.h"
#include "igea/sim.h"
#include "igea/stats.h"
#include "internal.h"
#include "rotation.h"
#include "envfun_terms.h"
#include "igea/noise.h"
#include "sim_noise.h"
#include "sim_model.h"
#include "rng.h"

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

/* ---- the model ------------------------------------------------------------ */


#define SIM_SIGMA_DEFAULT 0.01

int igea_sim_check_opts(const double *opts)
{
    if (!opts)
        return -1;
    for (int i = 0; i < IGEA_SIM_OPT_LEN; i++)
        if (!isfinite(opts[i]))
            return 1 + i;
    if (!(opts[IGEA_SIM_OPT_SIGMA_W] > 0.0))
        return 1 + IGEA_SIM_OPT_SIGMA_W;
    if (!(fabs(opts[IGEA_SIM_OPT_AR1]) < 1.0))
        return 1 + IGEA_SIM_OPT_AR1;
    if (!(opts[IGEA_SIM_OPT_GROWTH] >= 0.0))
        return 1 + IGEA_SIM_OPT_GROWTH;
    if (!(opts[IGEA_SIM_OPT_OUTLIER_PROB] >= 0.0 && opts[IGEA_SIM_OPT_OUTLIER_PROB] <= 1.0))
        return 1 + IGEA_SIM_OPT_OUTLIER_PROB;
    if (!(opts[IGEA_SIM_OPT_OUTLIER_SCALE] >= 0.0))
        return 1 + IGEA_SIM_OPT_OUTLIER_SCALE;
    if (opts[IGEA_SIM_OPT_GENERATOR] != IGEA_SIM_MT19937 &&
        opts[IGEA_SIM_OPT_GENERATOR] != IGEA_SIM_RANLXD2 &&
        opts[IGEA_SIM_OPT_GENERATOR] != IGEA_SIM_XOSHIRO)
        return 1 + IGEA_SIM_OPT_GENERATOR;
    double bk = opts[IGEA_SIM_OPT_BATCH];
    if (!(bk >= 0 && bk <= IGEA_SIM_BATCH_MAX && bk == floor(bk)))
        return 1 + IGEA_SIM_OPT_BATCH;
    return igea__sim_noise_check(opts); /* slots 6..13, sim_noise.c */
}

void igea_sim_model_free(igea_sim_model *model)
{
    if (!model)
        return;
    free(model->S);
    free(model->sigma);
    free(model->spec);
    free(model->x_value);
    free(model->x_fixed);
    free(model->traj);
    free(model->epochs);
    free(model->terms);
    if (model->mc) {
        free(model->mc->data);
        pthread_mutex_destroy(&model->mc->lock);
        free(model->mc);
    }
    free(model);
}

/* Drop the Monte Carlo's kept set-up (sigma or specs changed). */
static void mc_cache_drop(igea_sim_model *model)
{
    free(model->mc->data);
    model->mc->data = NULL;
}

/* A model of m x N with its arrays allocated and the defaults set. */
static igea_sim_model *model_new(int m, int N)
{
    igea_sim_model *md = calloc(1, sizeof *md);
    if (!md)
        return NULL;
    md->m = m;
    md->N = N;
    md->S = igea__dalloc((size_t)m * (size_t)N);
    md->sigma = igea__dalloc((size_t)m);
    md->spec = igea__dalloc((size_t)N);
    md->x_value = igea__dalloc((size_t)N);
    md->x_fixed = igea__ialloc((size_t)N);
    igea__sim_cache *mc = calloc(1, sizeof *mc);
    if (mc && pthread_mutex_init(&mc->lock, NULL) == 0)
        md->mc = mc;
    else
        free(mc);
    if (!md->S || !md->sigma || !md->spec || !md->x_value || !md->x_fixed || !md->mc) {
        igea_sim_model_free(md);
        return NULL;
    }
    for (int i = 0; i < m; i++)
        md->sigma[i] = SIM_SIGMA_DEFAULT;
    for (int j = 0; j < N; j++) {
        md->spec[j] = 1.0;
        md->x_value[j] = 0.0;
        md->x_fixed[j] = 0;
    }
    igea_sim_defaults(md->opts);
    return md;
}

int igea_sim_model_create(int m, int N, const double *S, int lds,
                          igea_sim_model **model)
{
    if (model)
        *model = NULL;
    if (m < 3 || m % 3 != 0)
        return -1;
    if (N < 1 || (size_t)N > ((size_t)-1 / sizeof(double)) / (size_t)m)
        return -2;
    if (!S)
        return -3;
    if (lds < m)
        return -4;
    if (!model)
        return -5;
    if (!igea__finite_mat(m, N, S, lds))
        return IGEA_ENONFINITE;
    igea_sim_model *md = model_new(m, N);
    if (!md)
        return IGEA_ENOMEM;
    for (int j = 0; j < N; j++)
        memcpy(md->S + (size_t)j * (size_t)m, S + (size_t)j * (size_t)lds,
               (size_t)m * sizeof(double));
    *model = md;
    return 0;
}

int igea_sim_model_create_trajectory(int system, int nsamp, const double *traj,
                                     int ldt, int nterms, const int *terms,
                                     const int *axes, int nepochs,
                                     const double *epochs, igea_sim_model **model)
{
    if (!model)
        return -10;
    *model = NULL;
    if (nepochs < 1 || nepochs > INT_MAX / 3)
        return -8;
    if (nterms < 1)
        return -5;
    igea_sim_model *md = model_new(3 * nepochs, nterms);
    if (!md)
        return IGEA_ENOMEM;
    int m = 3 * nepochs;
    int st = igea_envfun_compute(system, nsamp, traj, ldt, nterms, terms, axes,
                                 nepochs, epochs, NULL, IGEA_ENVFUN_VELOCITY,
                                 md->S, m);
    if (st) {
        igea_sim_model_free(md);
        return st;
    }
    md->traj = igea__dalloc((size_t)nsamp * IGEA_ENVFUN_TRAJ_COLS);
    md->epochs = igea__dalloc((size_t)nepochs);
    md->terms = igea__ialloc((size_t)nterms);
    if (!md->traj || !md->epochs || !md->terms) {
        igea_sim_model_free(md);
        return IGEA_ENOMEM;
    }
    for (int c = 0; c < IGEA_ENVFUN_TRAJ_COLS; c++)
        memcpy(md->traj + (size_t)c * (size_t)nsamp, traj + (size_t)c * (size_t)ldt,
               (size_t)nsamp * sizeof(double));
    memcpy(md->epochs, epochs, (size_t)nepochs * sizeof(double));
    memcpy(md->terms, terms, (size_t)nterms * sizeof(int));
    for (int j = 0; j < nterms; j++)
        igea_envfun_default_spec(system, terms[j], &md->spec[j]);
    md->has_spec = 1;
    md->system = system;
    md->nsamp = nsamp;
    md->nepochs = nepochs;
    md->has_axes = axes != NULL;
    if (axes)
        memcpy(md->axes, axes, sizeof md->axes);
    *model = md;
    return 0;
}

int igea_sim_model_set_sigma(igea_sim_model *model, const double *track_sigma,
                             int sigma_inc, double growth)
{
    int st;
    if (!model)
        return -1;
    if (!track_sigma)
        return -2;
    if (sigma_inc != 0 && sigma_inc != 1)
        return -3;
    if (!(growth >= 0.0) || !isfinite(growth))
        return -4;
    int m = model->m, M = m / 3;
    if ((st = igea__sigma_vec(sigma_inc ? m : 1, track_sigma)) != 0)
        return st;
    for (int i = 0; i < m; i++) {
        int e = i / 3;
        double g = 1.0 + (M > 1 ? growth * e / (double)(M - 1) : 0.0);
        if (!isfinite(track_sigma[sigma_inc ? i : 0] * g))
            return IGEA_ERANGE;
    }
    for (int i = 0; i < m; i++) {
        int e = i / 3;
        double g = 1.0 + (M > 1 ? growth * e / (double)(M - 1) : 0.0);
        model->sigma[i] = track_sigma[sigma_inc ? i : 0] * g;
    }
    mc_cache_drop(model);
    return 0;
}

int igea_sim_model_set_spec(igea_sim_model *model, const double *spec_sigma)
{
    int st;
    if (!model)
        return -1;
    if (spec_sigma && (st = igea__sigma_vec(model->N, spec_sigma)) != 0)
        return st;
    for (int j = 0; j < model->N; j++)
        model->spec[j] = spec_sigma ? spec_sigma[j] : 1.0;
    model->has_spec = spec_sigma != NULL;
    mc_cache_drop(model);
    return 0;
}

int igea_sim_model_set_noise(igea_sim_model *model, const double *opts)
{
    if (!model)
        return -1;
    if (opts && igea_sim_check_opts(opts) != 0)
        return -2;
    if (opts)
        memcpy(model->opts, opts, sizeof model->opts);
    else
        igea_sim_defaults(model->opts);
    return 0;
}

int igea_sim_model_set_truth(igea_sim_model *model, const double *x_value,
                             const int *x_fixed)
{
    if (!model)
        return -1;
    if (x_fixed && !x_value)
        return -2;
    if (x_fixed)
        for (int j = 0; j < model->N; j++)
            if (x_fixed[j] != 0 && x_fixed[j] != 1)
                return -3;
    if (x_value && !igea__finite_vec(model->N, x_value, 1))
        return IGEA_ENONFINITE;
    for (int j = 0; j < model->N; j++) {
        model->x_value[j] = x_value ? x_value[j] : 0.0;
        model->x_fixed[j] = x_fixed ? x_fixed[j] : 0;
    }
    model->has_truth = x_fixed != NULL;
    return 0;
}

int igea_sim_model_set_nonlinear(igea_sim_model *model, int on)
{
    if (!model)
        return -1;
    if ((on != 0 && on != 1) || (on && !model->traj))
        return -2;
    model->nonlinear = on;
    return 0;
}

int igea_sim_model_get_size(const igea_sim_model *model, int *m, int *N)
{
    if (!model)
        return -1;
    if (!m)
        return -2;
    if (!N)
        return -3;
    *m = model->m;
    *N = model->N;
    return 0;
}

int igea_sim_model_get_s(const igea_sim_model *model, double *S, int lds)
{
    if (!model)
        return -1;
    if (!S)
        return -2;
    if (lds < model->m)
        return -3;
    for (int j = 0; j < model->N; j++)
        memcpy(S + (size_t)j * (size_t)lds, model->S + (size_t)j * (size_t)model->m,
               (size_t)model->m * sizeof(double));
    return 0;
}

int igea_sim_model_get_sigma(const igea_sim_model *model, double *track_sigma)
{
    if (!model)
        return -1;
    if (!track_sigma)
        return -2;
    memcpy(track_sigma, model->sigma, (size_t)model->m * sizeof(double));
    return 0;
}

int igea_sim_model_get_spec(const igea_sim_model *model, double *spec_sigma)
{
    if (!model)
        return -1;
    if (!spec_sigma)
        return -2;
    memcpy(spec_sigma, model->spec, (size_t)model->N * sizeof(double));
    return 0;
}

/* ---- flights ------------------------------------------------------------ */

unsigned long igea__sim_flight_seed(int seed, int flight)
{
    /* SplitMix64 of the pair (seed, flight) */
    uint64_t z = ((uint64_t)(unsigned)seed << 32) ^ (uint64_t)(unsigned)flight;
    z += 0x9E3779B97F4A7C15ULL;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return (unsigned long)(z & 0xFFFFFFFFUL); /* GSL seeds are 32-bit safe */
}

const gsl_rng_type *igea__sim_rng_type(const igea_sim_model *c)
{
    if (c->opts[IGEA_SIM_OPT_GENERATOR] == IGEA_SIM_XOSHIRO)
        return igea__xoshiro_type; /* rng.c */
    return c->opts[IGEA_SIM_OPT_GENERATOR] == IGEA_SIM_RANLXD2
               ? gsl_rng_ranlxd2
               : gsl_rng_mt19937;
}

/* The nonlinear truth in place of S D X in dw (m): dw += dW_nonlinear(X D)
 * - S D X. nl (m) is scratch. */
static int nonlinear_swap(const igea_sim_model *c, const double *x, double *nl,
                          double *dw)
{
    double err[IGEA_ENVFUN_TERM_END] = {0};
    int m = c->m, N = c->N;
    for (int j = 0; j < N; j++)
        err[c->terms[j]] += x[j] * c->spec[j];
    int st = igea_envfun_nonlinear(c->system, c->nsamp, c->traj, c->nsamp,
                                   IGEA_ENVFUN_TERM_END, err,
                                   c->has_axes ? c->axes : NULL, c->nepochs,
                                   c->epochs, nl);
    if (st)
        return st;
    for (int i = 0; i < m; i++) {
        double lin = 0.0;
        for (int j = 0; j < N; j++)
            lin += c->S[i + (size_t)j * m] * c->spec[j] * x[j];
        dw[i] += nl[i] - lin;
    }
    return 0;
}

void igea__sim_draw_truth(const igea_sim_model *c, gsl_rng *r, int seed, int flight,
                          double *x, double *xs)
{
    if (r->type == igea__xoshiro_type) { /* keyed streams: sim_batch.c */
        igea__sim_truth_xoshiro(c, r->state, seed, flight, x, xs);
        return;
    }
    gsl_rng_set(r, igea__sim_flight_seed(seed, flight));
    for (int j = 0; j < c->N; j++) {
        double g = gsl_ran_gaussian_ziggurat(r, 1.0);
        x[j] = c->x_fixed[j] ? c->x_value[j] : g;
        xs[j] = x[j] * c->spec[j];
    }
}

void igea__sim_draw_noise(const igea_sim_model *c, gsl_rng *r, double *dw)
{
    int m = c->m, M = m / 3;
    double sw = c->opts[IGEA_SIM_OPT_SIGMA_W];
    double phi = c->opts[IGEA_SIM_OPT_AR1];
    double growth = c->opts[IGEA_SIM_OPT_GROWTH];
    double p_out = c->opts[IGEA_SIM_OPT_OUTLIER_PROB];
    double out_scale = c->opts[IGEA_SIM_OPT_OUTLIER_SCALE];
    double innov = sqrt(1.0 - phi * phi), prev[3] = {0, 0, 0};
    if (!igea__sim_noise_plain(c->opts)) { /* AR(p), correlation, groups: sim_noise.c */
        igea__sim_noise_rows(c->opts, c->sigma, m, r, dw);
        return;
    }
    if (r->type == igea__xoshiro_type) { /* one normal per row: sim_batch.c */
        igea__sim_noise_xoshiro(c, r->state, dw);
        return;
    }
    for (int i = 0; i < m; i++) {
        int e = i / 3, a = i % 3;
        double g = gsl_ran_gaussian_ziggurat(r, 1.0);
        double u = gsl_rng_uniform(r);
        double go = gsl_ran_gaussian_ziggurat(r, 1.0);
        double eps = (e == 0) ? g : phi * prev[a] + innov * g;
        double sd = sw * c->sigma[i] *
                    (1.0 + (M > 1 ? growth * e / (double)(M - 1) : 0.0));
        prev[a] = eps;
        dw[i] += sd * eps;
        if (u < p_out)
            dw[i] += out_scale * sd * go;
    }
}

/* Generate flight `flight` into x (N) and dw (m); xs (N) is scratch, nl
 * (m) scratch of the nonlinear truth. */
static int gen_flight(const igea_sim_model *c, gsl_rng *r, int seed, int flight,
                      double *x, double *xs, double *nl, double *dw)
{
    int m = c->m, N = c->N;
    igea__sim_draw_truth(c, r, seed, flight, x, xs);
    for (int i = 0; i < m; i++)
        dw[i] = 0.0;
    for (int j = 0; j < N; j++) {
        const double *col = c->S + (size_t)j * (size_t)m;
        for (int i = 0; i < m; i++)
            dw[i] += col[i] * xs[j];
    }
    igea__sim_draw_noise(c, r, dw);
    return c->nonlinear ? nonlinear_swap(c, x, nl, dw) : 0;
}

int igea_sim_flight(const igea_sim_model *model, int seed, int flight,
                    double *x_true, double *dw)
{
    if (!model)
        return -1;
    if (seed < 0)
        return -2;
    if (flight < 0)
        return -3;
    if (!dw)
        return -5;
    int m = model->m, N = model->N;
    double *work = igea__dalloc(2 * (size_t)m + 2 * (size_t)N);
    if (!work)
        return IGEA_ENOMEM;
    gsl_rng *r = igea__rng_new(igea__sim_rng_type(model), 0);
    if (!r) {
        free(work);
        return IGEA_ENOMEM;
    }
    int st = gen_flight(model, r, seed, flight, work + m, work + m + N,
                        work + m + 2 * (size_t)N, work);
    igea__rng_free(r);
    if (st == 0 && !igea__finite_vec(m, work, 1))
        st = IGEA_ENONFINITE;
    if (st == 0) {
        memcpy(dw, work, (size_t)m * sizeof(double));
        if (x_true)
            memcpy(x_true, work + m, (size_t)N * sizeof(double));
    }
    free(work);
    return st;
}

/* ---- Monte Carlo -------------------------------------------------------- */

int igea_sim_interval(double k, double n, double *lohi)
{
    if (!(k >= 0.0) || !isfinite(k) || (n > 0.0 && k > n))
        return -1;
    if (!(n > 0.0) || !isfinite(n))
        return -2;
    if (!lohi)
        return -3;
    /* Wilson score interval at 99 % */
    double z = 2.5758293035489004, p = k / n, z2 = z * z / n;
    double c = (p + z2 / 2) / (1 + z2);
    double h = z * sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z2);
    lohi[0] = fmax(0.0, c - h);
    lohi[1] = fmin(1.0, c + h);
    return 0;
}

/* A Monte Carlo run as its threads share it (read only but for the queue
 * and each flight's own outputs); each thread's counts and caches are its
 * own (mc_worker), so nothing written per flight shares a cache line with
 * another thread's. */
typedef struct {
    const igea_sim_model *c;
    const double *Sw; /* K^-1/2 S D, m x N */
    const double *A;  /* Sw^T Sw, N x N */
    const double *eq_opts;
    int seed, first;
    /* per-flight results (indexed from 0); fsize: info OVERALL_SIZE (0 if
     * not testable), summed in flight order */
    double *chi2, *scale, *zmax, *fsize;
    int *dof, *nrej, *status;
    int *cnt; /* tested, rejected (N each): the threads' counts added at their end */
    pthread_mutex_t *cnt_lock;
    igea__sim_queue *q;
    /* judged by igea_noise_eqerr (sim_noise.c): what the judge is told */
    int noise, ngroups;
    const double *cov; /* 6 per epoch, or NULL: the stated sigmas */
    const int *group;
    double phi[9];
    int *covered, *nout; /* per flight */
} mc_job;

/* Flights a thread takes at a time on the flight-by-flight path. */
#define MC_PORTION 8

/* igea_noise_eqerr on flight f; the rest as mc_judge. */
static int mc_judge_noise(const mc_job *jb, int f, const double *dw, double *lam, double *P,
                          double *xhat, double *z, int *rej, double *info)
{
    const igea_sim_model *c = jb->c;
    double go[2 * IGEA_NOISE_GROUP_COLS];
    int p = (int)jb->eq_opts[IGEA_EQERR_OPT_AR];
    int given = p > 0 && jb->eq_opts[IGEA_EQERR_OPT_AR_ESTIMATE] != 1;
    int st = igea_noise_eqerr(c->m, c->N, c->S, c->m, dw, jb->cov ? NULL : c->sigma, 1,
                              jb->cov, jb->group, jb->ngroups, c->spec, given ? jb->phi : NULL,
                              jb->eq_opts, lam, P, c->N, xhat, z, rej, info, NULL, go, NULL);
    jb->covered[f] = 0;
    jb->nout[f] = 0;
    if (st == 0) {
        double sw[2] = {c->opts[IGEA_SIM_OPT_SIGMA_W], c->opts[IGEA_SIM_OPT_SIGMA_W2] > 0
                                                           ? c->opts[IGEA_SIM_OPT_SIGMA_W2]
                                                           : c->opts[IGEA_SIM_OPT_SIGMA_W]};
        int ok = 1, lok = 1; /* bit 1: the log-scale cover (IGEA_SIM_MC_SIGMA_COVERED) */
        for (int g = 0; g < jb->ngroups; g++) {
            const double *o = go + g * IGEA_NOISE_GROUP_COLS;
            double cg = o[IGEA_NOISE_GROUP_SCALE], t = sw[g] * sw[g];
            ok = ok && fabs(cg - t) <= 3 * o[IGEA_NOISE_GROUP_SE];
            lok = lok && fabs(log(cg / t)) <= 3 * o[IGEA_NOISE_GROUP_SE_REML] / cg;
        }
        jb->covered[f] = ok | (lok << 1);
        jb->nout[f] = (int)info[IGEA_STATS_INFO_N_OUTLIERS];
    }
    return st;
}

/* Judge flight f of a job from its dw, its components counted in cnt (the
 * thread's own, 2 N); scratch w (m + 5 N + N^2 + IGEA_STATS_INFO_LEN
 * doubles), rej (N ints), vcache the thread's cache of the verdict rule
 * (4 N, eqerr.c). Returns 0 or the failure. */
static int mc_judge(const mc_job *jb, int f, const double *dw, double *w, int *rej,
                    double *vcache, int *cnt)
{
    const igea_sim_model *c = jb->c;
    int m = c->m, N = c->N;
    double *wdw = w, *b = wdw + m, *lam = b + N, *xhat = lam + N, *P = xhat + N;
    double *z = P + (size_t)N * N, *info = z + N;
    int st;
    if (jb->noise) {
        st = mc_judge_noise(jb, f, dw, lam, P, xhat, z, rej, info);
    } else {
        for (int i = 0; i < m; i++)
            wdw[i] = dw[i] / c->sigma[i];
        for (int j = 0; j < N; j++) {
            const double *col = jb->Sw + (size_t)j * (size_t)m;
            double acc = 0.0;
            for (int i = 0; i < m; i++)
                acc += col[i] * wdw[i];
            b[j] = acc;
        }
        st = igea__eqerr_solve_cached(N, jb->A, N, b, jb->eq_opts, vcache, lam, P, N, xhat,
                                      z, rej, info);
    }
    jb->status[f] = st;
    jb->zmax[f] = 0.0;
    jb->fsize[f] = 0.0;
    if (st == IGEA_ENOTESTABLE) {
        jb->chi2[f] = 0.0;
        jb->dof[f] = 0;
        jb->nrej[f] = 0;
        jb->scale[f] = NAN;
        return 0;
    }
    if (st < 0)
        return (st > -1000) ? -2 : st; /* -5: the eqerr options */
    jb->zmax[f] = igea__sim_zmax(N, z, rej);
    jb->chi2[f] = info[IGEA_STATS_INFO_CHI2];
    jb->dof[f] = (int)info[IGEA_STATS_INFO_DOF];
    jb->nrej[f] = (int)info[IGEA_STATS_INFO_N_REJECT];
    jb->scale[f] = info[IGEA_STATS_INFO_SCALE];
    jb->status[f] = info[IGEA_STATS_INFO_CHI2] >= info[IGEA_STATS_INFO_VERDICT_CHI2_CRIT]
                        ? 1 : 0; /* chi-square rejected (by the verdict rule) */
    jb->fsize[f] = info[IGEA_STATS_INFO_OVERALL_SIZE];
    for (int i = 0; i < N; i++) {
        cnt[i] += rej[i] >= 0;
        cnt[N + i] += rej[i] == 1;
    }
    return 0;
}

static void *mc_worker(void *arg)
{
    const mc_job *jb = arg;
    const igea_sim_model *c = jb->c;
    int m = c->m, N = c->N, f0, n;
    size_t nn = (size_t)N * N;
    double *w = igea__dalloc(3 * (size_t)m + 11 * (size_t)N + nn +
                             IGEA_STATS_INFO_LEN);
    int *rej = igea__ialloc(3 * (size_t)N);
    gsl_rng *r = (w && rej) ? igea__rng_new(igea__sim_rng_type(c), 0) : NULL;
    if (!r) {
        free(w);
        free(rej);
        igea__sim_queue_fail(jb->q, -1, IGEA_ENOMEM); /* before every flight */
        return NULL;
    }
    double *dw = w, *nl = dw + m, *x = nl + m, *xs = x + N, *judge = xs + N;
    double *vcache = w + 3 * (size_t)m + 7 * (size_t)N + nn + IGEA_STATS_INFO_LEN;
    int *cnt = rej + N;
    memset(vcache, 0, 4 * (size_t)N * sizeof(double));
    memset(cnt, 0, 2 * (size_t)N * sizeof(int));
    while ((n = igea__sim_queue_take(jb->q, MC_PORTION, 1, &f0)) > 0)
        for (int f = f0; f < f0 + n; f++) {
            int st = gen_flight(c, r, jb->seed, jb->first + f, x, xs, nl, dw);
            if (st == 0)
                st = mc_judge(jb, f, dw, judge, rej, vcache, cnt);
            if (st) {
                igea__sim_queue_fail(jb->q, f, st);
                break;
            }
        }
    pthread_mutex_lock(jb->cnt_lock);
    for (int i = 0; i < 2 * N; i++)
        jb->cnt[i] += cnt[i];
    pthread_mutex_unlock(jb->cnt_lock);
    igea__rng_free(r);
    free(w);
    free(rej);
    return NULL;
}

/* Run the job on nthreads threads, the calling thread one of them (a
 * thread that cannot start leaves its share to the others). */
static void mc_run(mc_job *jb, int nthreads)
{
    pthread_t *tid = calloc((size_t)nthreads, sizeof *tid);
    int nstarted = 0;
    for (int t = 1; tid && t < nthreads; t++) {
        if (pthread_create(&tid[t], NULL, mc_worker, jb) != 0)
            break;
        nstarted = t;
    }
    mc_worker(jb);
    for (int t = 1; t <= nstarted; t++)
        pthread_join(tid[t], NULL);
    free(tid);
}

/* Counts, rates and the means from the per-flight results. */
static void mc_counts(int nflights, const int *f_status, const int *f_nrej,
                      const int *f_dof, const double *f_scale, double *res,
                      double *rates)
{
    double sum_c = 0.0, sum_t = 0.0;
    int n_c = 0;
    for (int k = 0; k < IGEA_SIM_MC_LEN; k++)
        res[k] = 0.0;
    res[IGEA_SIM_MC_FLIGHTS] = nflights;
    for (int f = 0; f < nflights; f++) {
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
    for (int k = IGEA_SIM_MC_FAILED; k <= IGEA_SIM_MC_NOT_TESTABLE; k++) {
        double *r = rates + 3 * (k - IGEA_SIM_MC_FAILED);
        r[0] = res[k] / nflights;
        igea_sim_interval(res[k], nflights, r + 1);
    }
}

/* The whitened, spec-scaled S (m x N) and its normal matrix A (N x N, by
 * igea_normal_accumulate); zeros (m + N) is scratch. */
static int mc_normal(const igea_sim_model *c, double *Sw, double *A, double *zeros)
{
    int m = c->m, N = c->N;
    double wtw[2] = {0.0, 0.0};
    for (int j = 0; j < N; j++)
        for (int i = 0; i < m; i++)
            IGEA_AT(Sw, m, i, j) = IGEA_AT(c->S, m, i, j) * c->spec[j] / c->sigma[i];
    memset(A, 0, (size_t)N * N * sizeof(double));
    memset(zeros, 0, ((size_t)m + N) * sizeof(double));
    return igea_normal_accumulate(IGEA_COLMAJOR, m, N, c->S, m, zeros, c->sigma, 1,
                                  c->spec, A, N, zeros + m, wtw);
}

/* The set-up of the model into s (mapped on data, igea__sim_setup_map)
 * but Q: Sw and A (mc_normal; zeros m + N scratch), V and lam0
 * (igea__syev_desc, descending), L = V diag(lam0). */
static int mc_setup(const igea_sim_model *c, const igea__sim_setup *s, double *zeros)
{
    int N = c->N;
    size_t nn = (size_t)N * N;
    int st = mc_normal(c, s->Sw, s->A, zeros);
    if (st == 0) {
        st = igea__syev_desc(N, s->A, N, s->lam0, s->V, N);
        if (st < 0 && st > -1000)
            st = -2;
    }
    for (size_t k = 0; st == 0 && k < nn; k++)
        s->L[k] = s->V[k] * s->lam0[k / (size_t)N];
    return st;
}

/* The outputs of a successful run. */
static void mc_write(const mc_job *jb, int N, int nflights, double *counts, double *rates,
                     int *comp_tested, int *comp_reject, double *table, int ldt, int ncols)
{
    double res[IGEA_SIM_MC_LEN], rt[IGEA_SIM_MC_RATES_LEN];
    mc_counts(nflights, jb->status, jb->nrej, jb->dof, jb->scale, res, rt);
    double size_sum = 0.0, ntestable = nflights - res[IGEA_SIM_MC_NOT_TESTABLE];
    for (int f = 0; f < nflights; f++) /* in flight order: the same for every thread count */
        size_sum += jb->fsize[f];
    res[IGEA_SIM_MC_MEAN_SIZE] = ntestable > 0 ? size_sum / ntestable : 0.0;
    if (jb->noise) {
        double cov_n = 0, out_n = 0, sig_n = 0;
        for (int f = 0; f < nflights; f++) {
            cov_n += jb->covered[f] & 1;
            sig_n += jb->covered[f] >> 1;
            out_n += jb->nout[f];
        }
        res[IGEA_SIM_MC_SCALE_COVERED] = cov_n;
        res[IGEA_SIM_MC_SIGMA_COVERED] = sig_n;
        res[IGEA_SIM_MC_MEAN_OUTLIERS] = out_n / nflights;
    }
    memcpy(counts, res, sizeof res);
    if (rates)
        memcpy(rates, rt, sizeof rt);
    if (comp_tested)
        memcpy(comp_tested, jb->cnt, (size_t)N * sizeof(int));
    if (comp_reject)
        memcpy(comp_reject, jb->cnt + N, (size_t)N * sizeof(int));
    if (table)
        for (int f = 0; f < nflights; f++) {
            IGEA_AT(table, ldt, f, IGEA_SIM_MC_TABLE_CHI2) = jb->chi2[f];
            IGEA_AT(table, ldt, f, IGEA_SIM_MC_TABLE_DOF) = jb->dof[f];
            IGEA_AT(table, ldt, f, IGEA_SIM_MC_TABLE_N_REJECT) = jb->nrej[f];
            IGEA_AT(table, ldt, f, IGEA_SIM_MC_TABLE_SCALE) = jb->scale[f];
            if (ncols > IGEA_SIM_MC_TABLE_ZMAX)
                IGEA_AT(table, ldt, f, IGEA_SIM_MC_TABLE_ZMAX) = jb->zmax[f];
        }
}

/* igea_sim_montecarlo after its argument checks. The set-up is the one the
 * model keeps (the first run that completes publishes its own). */
static int mc_main(const igea_sim_model *c, const double *eqo, int seed,
                   int first, int nflights, int nthreads, double *counts,
                   double *rates, int *comp_tested, int *comp_reject,
                   double *table, int ldt, int ncols)
{
    int m = c->m, N = c->N;
    size_t nn = (size_t)N * N, nf = (size_t)nflights;
    size_t nsetup = 2 * (size_t)m * N + 3 * nn + (size_t)N;
    pthread_mutex_lock(&c->mc->lock);
    double *kept = c->mc->data;
    pthread_mutex_unlock(&c->mc->lock);
    double *own = kept ? NULL : igea__dalloc(nsetup);
    double *dwork = igea__dalloc((size_t)m + N + 4 * nf + 2 * (size_t)m);
    int *iwork = igea__ialloc(5 * nf + 2 * (size_t)N + (size_t)m / 3);
    igea__sim_queue q;
    pthread_mutex_t cnt_lock;
    int st = dwork && iwork && (kept || own) ? igea__sim_queue_init(&q, nflights, nthreads)
                                             : IGEA_ENOMEM;
    if (st == 0 && pthread_mutex_init(&cnt_lock, NULL) != 0) {
        igea__sim_queue_destroy(&q);
        st = IGEA_ENOMEM;
    }
    if (st == 0) {
        igea__sim_setup su;
        igea__sim_setup_map(&su, kept ? kept : own, m, N);
        double *zeros = dwork, *f_chi2 = zeros + m + N, *f_scale = f_chi2 + nf;
        int *f_dof = iwork, *f_nrej = f_dof + nf, *f_status = f_nrej + nf;
        int *cnt = f_status + nf;
        memset(cnt, 0, 2 * (size_t)N * sizeof(int));
        int *f_cov = cnt + 2 * (size_t)N, *f_nout = f_cov + nf, *grp = f_nout + nf;
        double *cov6 = f_scale + nf, *f_zmax = cov6 + 2 * (size_t)m, *f_size = f_zmax + nf;
        double phi[9] = {0};
        int noise = igea__sim_noise_judged(c->opts, eqo), ngroups = 1;
        int usecov = igea__sim_judge_stated(c->opts, eqo, m, c->sigma, cov6, grp, &ngroups, phi);
        mc_job jb = {c, su.Sw, su.A, eqo, seed, first, f_chi2, f_scale, f_zmax, f_size,
                     f_dof, f_nrej, f_status, cnt, &cnt_lock, &q,
                     noise, ngroups, usecov ? cov6 : NULL, grp, {0}, f_cov, f_nout};
        memcpy(jb.phi, phi, sizeof phi);
        int block = (int)c->opts[IGEA_SIM_OPT_BATCH];
        int batched = !noise && !c->nonlinear && block != 1;
        if (own && !batched) /* the batched path runs it beside its threads' first draws */
            st = mc_setup(c, &su, zeros);
        if (st == 0 && batched) { /* batched: sim_batch.c */
            st = igea__sim_mc_batch(c, &su, own ? mc_setup : NULL, zeros, kept != NULL, eqo,
                                    seed, first, nflights, nthreads,
                                    block ? block : IGEA_SIM_BATCH_DEFAULT, f_chi2, f_scale,
                                    f_zmax, f_size, f_dof, f_nrej, f_status, cnt);
        } else if (st == 0) {
            if (own)
                igea__sim_setup_q(&su, m, N);
            mc_run(&jb, nthreads);
            st = q.fail;
        }
        if (st == 0)
            mc_write(&jb, N, nflights, counts, rates, comp_tested, comp_reject, table, ldt,
                     ncols);
        pthread_mutex_destroy(&cnt_lock);
        igea__sim_queue_destroy(&q);
    }
    if (st == 0 && own) { /* kept for the later runs, unless another run's is */
        pthread_mutex_lock(&c->mc->lock);
        if (!c->mc->data) {
            c->mc->data = own;
            own = NULL;
        }
        pthread_mutex_unlock(&c->mc->lock);
    }
    free(own);
    free(dwork);
    free(iwork);
    return st;
}

/* igea_sim_montecarlo and igea_sim_montecarlo_ex: checks, then mc_main. */
static int mc_entry(const igea_sim_model *model, const double *eq_opts, int seed,
                    int first_flight, int nflights, int nthreads, double *counts,
                    double *rates, int *comp_tested, int *comp_reject, double *table,
                    int ldt, int ncols)
{
    double eqo[IGEA_EQERR_OPT_LEN];
    if (!model)
        return -1;
    if (eq_opts && igea_eqerr_check_opts(eq_opts) != 0)
        return -2;
    if (seed < 0)
        return -3;
    if (first_flight < 0)
        return -4;
    if (nflights < 1 || nflights > INT_MAX - first_flight)
        return -5;
    if (nthreads < 0)
        return -6;
    if (!counts)
        return -7;
    if (table && ldt < nflights)
        return -12;
    if (table && ncols != IGEA_SIM_MC_TABLE_COLS && ncols != IGEA_SIM_MC_TABLE_COLS_Z)
        return -13;
    if (eq_opts)
        memcpy(eqo, eq_opts, sizeof eqo);
    else
        igea_eqerr_defaults(eqo);
    if (nthreads == 0) {
        long np = sysconf(_SC_NPROCESSORS_ONLN);
        nthreads = np > 0 ? (int)IGEA_MIN(np, 64) : 1;
    }
    nthreads = IGEA_MIN(IGEA_MIN(nthreads, nflights), 256);
    return mc_main(model, eqo, seed, first_flight, nflights, nthreads, counts,
                   rates, comp_tested, comp_reject, table, ldt, ncols);
}

int igea_sim_montecarlo(const igea_sim_model *model, const double *eq_opts,
                        int seed, int first_flight, int nflights, int nthreads,
                        double *counts, double *rates, int *comp_tested,
                        int *comp_reject, double *table, int ldt)
{
    return mc_entry(model, eq_opts, seed, first_flight, nflights, nthreads, counts, rates,
                    comp_tested, comp_reject, table, ldt, IGEA_SIM_MC_TABLE_COLS);
}

int igea_sim_montecarlo_ex(const igea_sim_model *model, const double *eq_opts, int seed,
                           int first_flight, int nflights, int nthreads, double *counts,
                           double *rates, int *comp_tested, int *comp_reject, double *table,
                           int ldt, int ncols)
{
    return mc_entry(model, eq_opts, seed, first_flight, nflights, nthreads, counts, rates,
                    comp_tested, comp_reject, table, ldt, ncols);
}

/* ---- pooled verdicts ------------------------------------------------------ */

/* The table's CHI2, DOF and N_REJECT (igea_sim_pool) or ZMAX
 * (igea_sim_pool_ex, zmax 1) columns as the pools read them: 0,
 * IGEA_ENONFINITE or -2. */
static int pool_check(int nflights, const double *T, const double *D,
                      const double *R, int zmax)
{
    if (!igea__finite_vec(nflights, T, 1) || !igea__finite_vec(nflights, D, 1) ||
        !igea__finite_vec(nflights, R, 1))
        return IGEA_ENONFINITE;
    for (int f = 0; f < nflights; f++) {
        if (!(D[f] >= 0.0 && D[f] <= IGEA_STATS_DOF_MAX && D[f] == floor(D[f])))
            return -2;
        if (!zmax && !(R[f] >= 0.0 && R[f] <= D[f] && R[f] == floor(R[f])))
            return -2;
        if (zmax && (!(R[f] >= 0.0) || (D[f] == 0.0 && R[f] != 0.0)))
            return -2;
        if (!(T[f] >= 0.0) || (D[f] == 0.0 && T[f] != 0.0))
            return -2;
    }
    return 0;
}

/* The pooled verdict of the flights T, D, R [0, size): *failed 1 when "out
 * of spec"; scratch pc (size doubles), pd, pr (size ints). */
static int pool_group(int size, const double *T, const double *D, const double *R,
                      double alpha, double *pc, int *pd, int *pr, int *failed)
{
    int k = 0;
    double dsum = 0.0;
    for (int f = 0; f < size; f++)
        if (D[f] > 0.0) {
            pc[k] = T[f];
            pd[k] = (int)D[f];
            pr[k] = (int)R[f];
            dsum += D[f];
            k++;
        }
    *failed = 0;
    if (k == 0)
        return 0;
    if (dsum > IGEA_STATS_DOF_MAX)
        return -4;
    double info[IGEA_STATS_INFO_LEN];
    int st = igea_stats_pool(k, pc, pd, pr, NULL, alpha, info);
    if (st < 0)
        return st > -1000 ? -2 : st;
    *failed = info[IGEA_STATS_INFO_PASSED] != 1.0;
    return 0;
}

/* The pooled study's counts, rate and 99 % interval into pooled (the other
 * slots 0). */
static void pool_counts(int npools, int nfail, double *pooled)
{
    double lohi[2] = {NAN, NAN};
    if (npools > 0)
        igea_sim_interval(nfail, npools, lohi);
    for (int k = 0; k < IGEA_SIM_POOL_LEN; k++)
        pooled[k] = 0.0;
    pooled[IGEA_SIM_POOL_POOLS] = npools;
    pooled[IGEA_SIM_POOL_FAILED] = nfail;
    pooled[IGEA_SIM_POOL_RATE] = npools > 0 ? (double)nfail / npools : NAN;
    pooled[IGEA_SIM_POOL_CI99_LO] = lohi[0];
    pooled[IGEA_SIM_POOL_CI99_HI] = lohi[1];
}

int igea_sim_pool(int nflights, const double *table, int ldt, int size,
                  double alpha, double *pooled)
{
    if (nflights < 1)
        return -1;
    if (!table)
        return -2;
    if (ldt < nflights)
        return -3;
    if (size < 1)
        return -4;
    if (!(alpha > 0.0 && alpha < 1.0))
        return -5;
    if (!pooled)
        return -6;
    const double *T = table + (size_t)IGEA_SIM_MC_TABLE_CHI2 * (size_t)ldt;
    const double *D = table + (size_t)IGEA_SIM_MC_TABLE_DOF * (size_t)ldt;
    const double *R = table + (size_t)IGEA_SIM_MC_TABLE_N_REJECT * (size_t)ldt;
    int st = pool_check(nflights, T, D, R, 0);
    if (st)
        return st;
    int npools = nflights / size, nfail = 0;
    if (npools > 0) {
        double *pc = igea__dalloc((size_t)size);
        int *pd = igea__ialloc(2 * (size_t)size);
        st = pc && pd ? 0 : IGEA_ENOMEM;
        for (int g = 0; st == 0 && g < npools; g++) {
            size_t f0 = (size_t)g * (size_t)size;
            int failed = 0;
            st = pool_group(size, T + f0, D + f0, R + f0, alpha, pc, pd, pd + size,
                            &failed);
            nfail += failed;
        }
        free(pc);
        free(pd);
        if (st)
            return st;
    }
    pool_counts(npools, nfail, pooled);
    return 0;
}

/* The thresholds of the rule eqo for n pooled components as igea_eqerr_pool
 * applies them: th[0] = a (HUGE_VAL: no component test), th[1] = b, th[2]
 * = the overall size (0: not computed); zeros (n doubles of 0) are the z
 * it is asked about. Returns 0 or igea_eqerr_pool's failure. */
static int pool_rule(int n, const double *eqo, const double *zeros, double *th)
{
    double chi2 = 0.0, info[IGEA_STATS_INFO_LEN];
    int dof = n;
    int st = igea_eqerr_pool(1, &chi2, &dof, zeros, NULL, eqo, NULL, info);
    if (st)
        return st < 0 && st > -1000 ? IGEA_ENOCONV : st; /* arguments checked before */
    th[0] = info[IGEA_STATS_INFO_VERDICT_Z_CRIT] > 0 ? info[IGEA_STATS_INFO_VERDICT_Z_CRIT]
                                                   : HUGE_VAL;
    th[1] = info[IGEA_STATS_INFO_VERDICT_CHI2_CRIT];
    th[2] = info[IGEA_STATS_INFO_OVERALL_SIZE];
    return 0;
}

/* The pooled components of the groups (their summed DOF), each group's
 * in dsum[g]; the largest in *nmax. Returns 0 or -4 (above
 * IGEA_STATS_DOF_MAX). */
static int pool_dofs(int npools, int size, const double *D, int *dsum, int *nmax)
{
    *nmax = 0;
    for (int g = 0; g < npools; g++) {
        double d = 0.0;
        for (int f = 0; f < size; f++)
            d += D[(size_t)g * size + f];
        if (d > IGEA_STATS_DOF_MAX)
            return -4;
        dsum[g] = (int)d;
        *nmax = IGEA_MAX(*nmax, dsum[g]);
    }
    return 0;
}

/* The verdicts of the groups by the thresholds th (4 per n: computed
 * flag, a, b, size; filled here on first use): *nfail groups out of spec,
 * *size_sum their sizes, *size_ok 0 when a size is not computed. */
static int pool_groups(int npools, int size, const double *T, const double *D,
                       const double *Z, const int *dsum, const double *eqo,
                       const double *zeros, double *th, int *nfail, int *ntest,
                       double *size_sum, int *size_ok)
{
    for (int g = 0; g < npools; g++) {
        int n = dsum[g];
        if (n == 0)
            continue; /* no testable flight: passes */
        double *e = th + 4 * (size_t)(n - 1);
        int st = e[0] == 1.0 ? 0 : pool_rule(n, eqo, zeros, e + 1);
        if (st)
            return st;
        e[0] = 1.0;
        igea__ksum t = {0, 0};
        int sat = 0;
        double zm = 0.0;
        for (int f = 0; f < size; f++) { /* igea_stats_pool's saturating sum */
            size_t k = (size_t)g * size + f;
            if (D[k] == 0.0)
                continue;
            zm = fmax(zm, Z[k]);
            if (!sat && isfinite(t.s + T[k]))
                igea__ksum_add(&t, T[k]);
            else
                sat = 1;
        }
        double Tt = sat ? DBL_MAX : igea__ksum_get(&t);
        if (!isfinite(Tt))
            Tt = DBL_MAX;
        *nfail += zm > e[1] || Tt >= e[2];
        *ntest += 1;
        *size_sum += e[3];
        *size_ok = *size_ok && e[3] > 0.0;
    }
    return 0;
}

int igea_sim_pool_ex(int nflights, const double *table, int ldt, int size,
                     const double *eq_opts, double *pooled)
{
    double eqo[IGEA_EQERR_OPT_LEN];
    if (nflights < 1)
        return -1;
    if (!table)
        return -2;
    if (ldt < nflights)
        return -3;
    if (size < 1)
        return -4;
    if (eq_opts && igea_eqerr_check_opts(eq_opts) != 0)
        return -5;
    if (!pooled)
        return -6;
    if (eq_opts)
        memcpy(eqo, eq_opts, sizeof eqo);
    else
        igea_eqerr_defaults(eqo);
    eqo[IGEA_EQERR_OPT_VERDICT_N] = 0; /* the rule computed for each n */
    const double *T = table + (size_t)IGEA_SIM_MC_TABLE_CHI2 * (size_t)ldt;
    const double *D = table + (size_t)IGEA_SIM_MC_TABLE_DOF * (size_t)ldt;
    const double *Z = table + (size_t)IGEA_SIM_MC_TABLE_ZMAX * (size_t)ldt;
    int st = pool_check(nflights, T, D, Z, 1);
    if (st)
        return st;
    int npools = nflights / size, nfail = 0, ntest = 0, size_ok = 1, nmax = 0;
    double size_sum = 0.0;
    if (npools > 0) {
        int *dsum = igea__ialloc((size_t)npools);
        st = dsum ? pool_dofs(npools, size, D, dsum, &nmax) : IGEA_ENOMEM;
        double *th = st == 0 ? igea__dalloc(5 * (size_t)IGEA_MAX(nmax, 1)) : NULL;
        if (st == 0 && !th)
            st = IGEA_ENOMEM;
        if (st == 0) {
            memset(th, 0, 5 * (size_t)IGEA_MAX(nmax, 1) * sizeof(double));
            st = pool_groups(npools, size, T, D, Z, dsum, eqo, th + 4 * (size_t)IGEA_MAX(nmax, 1),
                             th, &nfail, &ntest, &size_sum, &size_ok);
        }
        free(dsum);
        free(th);
        if (st)
            return st;
    }
    pool_counts(npools, nfail, pooled);
    pooled[IGEA_SIM_POOL_MEAN_SIZE] =
        npools == 0 ? NAN : (ntest > 0 && size_ok ? size_sum / ntest : 0.0);
    return 0;
}

/* ---- nonlinear truth model ------------------------------------------------ */

/* Codes with a non-zero error, by family, of igea_envfun_nonlinear. */
#define NL_MAXC IGEA_ENVFUN_TERM_END

/* The state of the two navigations of igea_sim_nonlinear: C the reference
 * attitude (strapdown) or identity, Ch the erroneous attitude (strapdown)
 * or the platform's C_p^a; the previous sample's values (_p) and the
 * apparent velocities W (reference) and Wh (erroneous); the codes with
 * errors (acc: accelerometer and size-effect terms, gyro: rate or drift
 * terms, size: size effect), the lever arm l (body), its C (w x l) at t_0,
 * the launch-frame rotation theta. */
typedef struct {
    const double *err;
    int in_ax[3], spin_ax[3], out_ax[3];
    int acc[NL_MAXC], gyro[NL_MAXC], size[NL_MAXC], nacc, ngyro, nsize, lever;
    double C[9], Ch[9], Chp[9];
    double W[3], Wh[3], fa_p[3], fh_p[3], w_p[3], wh_p[3], d_p[3];
    double l[3], lv0[3], theta[3];
    double t_p;
} nav_state;

/* f + the accelerometer errors (instrument axes); w the body rate. */
static void acc_errors(const nav_state *n, const double *f, const double *w,
                       double *out)
{
    double u[3];
    memcpy(out, f, 3 * sizeof(double));
    for (int i = 0; i < n->nacc; i++) {
        int k = n->acc[i];
        igea__term_unit(k, f, w, n->in_ax, n->spin_ax, n->out_ax, u);
        for (int a = 0; a < 3; a++)
            out[a] += n->err[k] * u[a];
    }
}

/* The gyro errors (strapdown rate error or platform drift) from the
 * instrument-axis force f and rate w. */
static void gyro_errors(const nav_state *n, const double *f, const double *w,
                        double *eps)
{
    double u[3];
    eps[0] = eps[1] = eps[2] = 0.0;
    for (int i = 0; i < n->ngyro; i++) {
        int k = n->gyro[i];
        igea__term_unit(k, f, w, n->in_ax, n->spin_ax, n->out_ax, u);
        for (int a = 0; a < 3; a++)
            eps[a] += n->err[k] * u[a];
    }
}

/* Arguments and data of igea_envfun_nonlinear: 0, -i, IGEA_ENONFINITE,
 * IGEA_EDOMAIN; the gyro axes and the codes with errors. */
static int nonlinear_check(int system, int nsamp, const double *traj, int ldt,
                           int nerr, const double *err, const int *axes,
                           int nepochs, const double *epochs, const double *dW,
                           nav_state *n)
{
    int st, uses_out = 0;
    igea__platform_axes(NULL, n->in_ax, n->spin_ax);
    if ((st = igea__traj_args(system, nsamp, traj, ldt)) != 0)
        return st;
    if (nerr < IGEA_ENVFUN_TERM_COUNT || nerr > IGEA_ENVFUN_TERM_END)
        return -5;
    if (!err)
        return -6;
    if (igea__term_lists(system, nerr, err, n->acc, &n->nacc, n->size, &n->nsize, n->gyro,
                         &n->ngyro, &n->lever, &uses_out))
        return -6;
    if (system == IGEA_ENVFUN_PLATFORM && igea__platform_axes(axes, n->in_ax, n->spin_ax))
        return -7;
    if (igea__out_axes(n->in_ax, n->spin_ax, n->out_ax) && uses_out)
        return -7;
    if (nepochs < 1 || nepochs > INT_MAX / 3)
        return -8;
    if (!epochs)
        return -9;
    if (!dW)
        return -10;
    if (!igea__finite_mat(nsamp, IGEA_ENVFUN_TRAJ_COLS, traj, ldt) ||
        !igea__finite_vec(nerr, err, 1) ||
        !igea__finite_vec(nepochs, epochs, 1))
        return IGEA_ENONFINITE;
    int bad = igea__traj_times(nsamp, traj, ldt, nepochs, epochs);
    if (bad)
        return bad == 1 ? -3 : -9;
    for (int k = 0; k < nsamp; k++)
        if ((k == 0 && system == IGEA_ENVFUN_STRAPDOWN) || n->lever)
            if (!(igea__traj_qnorm2(traj, ldt, k) > 1e-200))
                return IGEA_EDOMAIN;
    return 0;
}

/* C(q_k) (w_k x l): the lever arm's velocity at sample k. */
static void lever_velocity(const nav_state *n, const double *traj, int ldt,
                           int k, double *v)
{
    double q[4], C[9], w[3], wl[3];
    for (int i = 0; i < 4; i++)
        q[i] = IGEA_AT(traj, ldt, k, 7 + i);
    for (int i = 0; i < 3; i++)
        w[i] = IGEA_AT(traj, ldt, k, 4 + i);
    igea__quat_dcm_unit(q, C);
    igea__cross(w, n->l, wl);
    igea__m3_vec(C, wl, v, 0);
}

/* Initial attitudes: strapdown C(0) and exp(-[phi0 x]) C(0); platform the
 * identity and exp([alpha0 x]); the lever arm and the launch-frame
 * rotation. */
static void nav_init(int system, int nerr, const double *traj, int ldt,
                     nav_state *n)
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
    memcpy(n->Chp, n->Ch, sizeof n->Ch);
    for (int a = 0; a < 3; a++) {
        n->W[a] = n->Wh[a] = n->fa_p[a] = n->fh_p[a] = n->w_p[a] = n->wh_p[a] =
            n->d_p[a] = n->theta[a] = n->lv0[a] = 0.0;
        n->l[a] = nerr > IGEA_ENVFUN_TERM_LEVER_X + a ? n->err[IGEA_ENVFUN_TERM_LEVER_X + a] : 0.0;
    }
    for (int k = IGEA_ENVFUN_TERM_POS0_X; k <= IGEA_ENVFUN_TERM_POS0_Z && k < nerr; k++) {
        double th[3];
        igea__pos0_rotation(k, th);
        for (int a = 0; a < 3; a++)
            n->theta[a] += n->err[k] * th[a];
    }
    if (n->lever)
        lever_velocity(n, traj, ldt, 0, n->lv0);
    n->t_p = 0.0;
}

/* Strapdown step at sample k (time t, body f and w): both attitudes
 * propagated with the trapezoid mean rates; fa the reference a-frame
 * force, fh the erroneous one, wh the erroneous rate. */
static void strapdown_step(nav_state *n, int k, double t, const double *f,
                           const double *w, double *fa, double *fh, double *wh)
{
    double fb_h[3];
    gyro_errors(n, f, w, wh);
    for (int a = 0; a < 3; a++)
        wh[a] += w[a];
    memcpy(n->Chp, n->Ch, sizeof n->Ch);
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
    acc_errors(n, f, w, fb_h);
    igea__m3_vec(n->C, f, fa, 0);
    igea__m3_vec(n->Ch, fb_h, fh, 0);
}

/* Size effect, tangential part, over the step to sample k: the increment
 * sum_j r e_j ((w_k - w_{k-1}) x e_k)_j of the erroneous velocity, rotated
 * by the mean of the erroneous attitudes at the step's ends. */
static void size_step(nav_state *n, const double *w)
{
    for (int i = 0; i < n->nsize; i++) {
        int kk, j = igea__term_axis(n->size[i], &kk);
        double dw[3], ek[3] = {0, 0, 0}, tg[3];
        for (int a = 0; a < 3; a++)
            dw[a] = w[a] - n->w_p[a];
        ek[kk] = 1.0;
        igea__cross(dw, ek, tg);
        for (int a = 0; a < 3; a++)
            n->Wh[a] += n->err[n->size[i]] * 0.5 *
                        (n->Chp[3 * a + j] + n->Ch[3 * a + j]) * tg[j];
    }
}

/* Platform step at sample k (time t, inertial force f): the platform
 * drifts over the step (eps at the end predicted twice); the
 * accelerometers read the rotated force with their errors (fh), wh the
 * drift rate at the sample. */
static void platform_step(nav_state *n, int k, double t, const double *f,
                          const double *w, double *fa, double *fh, double *wh)
{
    double fp[3];
    memcpy(fa, f, 3 * sizeof(double));
    if (k > 0) {
        double h = t - n->t_p, P[9], ek[3], fpk[3], v[3], R[9];
        memcpy(P, n->Ch, sizeof P);
        for (int it = 0; it < 2; it++) {
            igea__m3_vec(P, fa, fpk, 1);
            gyro_errors(n, fpk, w, ek);
            for (int j = 0; j < 3; j++)
                v[j] = 0.5 * h * (n->wh_p[j] + ek[j]);
            igea__m3_exp(v, R);
            igea__m3_mul(n->Ch, R, P);
        }
        memcpy(n->Ch, P, sizeof P);
    }
    igea__m3_vec(n->Ch, fa, fp, 1); /* f^p = C_a^p f^a */
    acc_errors(n, fp, w, fh);
    gyro_errors(n, fp, w, wh);
}

/* The velocity difference at sample k: Wh minus the tracking's apparent
 * velocity (the reference W read in the rotated launch frame, plus the
 * lever arm's velocity change). */
static void nonlinear_diff(const nav_state *n, const double *traj, int ldt,
                           int k, double *d)
{
    double mt[3], R[9], Wt[3];
    for (int a = 0; a < 3; a++)
        mt[a] = -n->theta[a];
    igea__m3_exp(mt, R);
    igea__m3_vec(R, n->W, Wt, 0);
    if (n->lever) {
        double lv[3];
        lever_velocity(n, traj, ldt, k, lv);
        for (int a = 0; a < 3; a++)
            Wt[a] += lv[a] - n->lv0[a];
    }
    for (int a = 0; a < 3; a++)
        d[a] = n->Wh[a] - Wt[a];
}

int igea_envfun_nonlinear(int system, int nsamp, const double *traj, int ldt,
                          int nerr, const double *err, const int *axes,
                          int nepochs, const double *epochs, double *dW)
{
    nav_state n;
    int st = nonlinear_check(system, nsamp, traj, ldt, nerr, err, axes, nepochs,
                             epochs, dW, &n);
    if (st)
        return st;
    double *out = igea__dalloc(3 * (size_t)nepochs);
    if (!out)
        return IGEA_ENOMEM;
    n.err = err;
    nav_init(system, nerr, traj, ldt, &n);
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
            platform_step(&n, k, t, f, w, fa, fh, wh);
        if (k > 0) {
            double h = t - n.t_p;
            for (int a = 0; a < 3; a++) {
                n.W[a] += 0.5 * h * (n.fa_p[a] + fa[a]);
                n.Wh[a] += 0.5 * h * (n.fh_p[a] + fh[a]);
            }
            size_step(&n, w);
        }
        nonlinear_diff(&n, traj, ldt, k, d);
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

int igea_sim_nonlinear(int system, int nsamp, const double *traj, int ldt,
                       const double *err, const int *axes, int nepochs,
                       const double *epochs, double *dW)
{
    /* positions 6 .. 10 of igea_envfun_nonlinear are 5 .. 9 here */
    int st = igea_envfun_nonlinear(system, nsamp, traj, ldt, IGEA_ENVFUN_TERM_COUNT,
                                   err, axes, nepochs, epochs, dW);
    return (st <= -6 && st >= -10) ? st + 1 : st;
}
