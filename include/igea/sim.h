/*
 * igea/sim.h - reproducible synthetic flights and the Monte Carlo check of
 * the equivalent-error accuracy test (METHODS 1 and 5.6).
 *
 *  - igea_sim_trajectory: the reference boost trajectory (METHODS 5.6:
 *    thrust 15-25 m/s^2 along body x, a pitch-over of 60 degrees, a small
 *    wobble; attitude propagated with exact quaternion exponentials), in
 *    the trajectory layout of igea/envfun.h.
 *  - igea_sim_model_*: the simulation model (a handle): flight geometry,
 *    stated sigma, specs, true noise, true X, linear or nonlinear truth.
 *  - igea_sim_flight: one synthetic flight dw = S D X + noise, X drawn
 *    N(0, I) in spec units or set term by term, tracking noise white with
 *    a true scale sigma_w, AR(1)-correlated, growing along the flight, with
 *    occasional outliers.
 *  - igea_sim_montecarlo: many flights generated and judged by the seed-000
 *    test (igea_eqerr_solve on the normal equations), with counts of
 *    rejections, optionally on several POSIX threads.
 *  - igea_sim_pool: the pooled verdicts of consecutive groups of the
 *    Monte Carlo's flights (METHODS 1.2 step 6) and their rate.
 *
 * Reproducibility: every random number comes from a GSL generator seeded
 * from the caller's seed and the flight index (a SplitMix64 hash of the
 * two), one generator per thread re-seeded for every flight. A flight's
 * draws therefore depend only on (seed, flight), never on the thread that
 * runs it or the number of threads: results are identical for any thread
 * count, and flights f0..f1 of a long run can be recomputed alone.
 * Draw order in a flight: N normals for X (drawn even for fixed terms, so
 * that fixing a term leaves the others' draws unchanged), then per row one
 * normal for the noise, one uniform and one normal for the outlier.
 *
 * Out of memory: every allocation, the generators' included (they are not
 * made by gsl_rng_alloc, whose failure path calls GSL's aborting handler),
 * gives IGEA_ENOMEM with the outputs untouched (tested by an
 * allocation-failure loop), with or without igea_init().
 */
#ifndef IGEA_SIM_H
#define IGEA_SIM_H

#include "igea/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Indices into the simulation options opts[IGEA_SIM_OPT_LEN]. */
#define IGEA_SIM_OPT_SIGMA_W 0       /* true tracking scale sigma_w, 1 */
#define IGEA_SIM_OPT_AR1 1           /* AR(1) coefficient along epochs, 0 */
#define IGEA_SIM_OPT_GROWTH 2        /* true sd x (1 + g e/(M-1)), 0 [D] */
#define IGEA_SIM_OPT_OUTLIER_PROB 3  /* probability of an outlier per row, 0 */
#define IGEA_SIM_OPT_OUTLIER_SCALE 4 /* outlier sd / row sd, 10 */
#define IGEA_SIM_OPT_GENERATOR 5     /* IGEA_SIM_MT19937, IGEA_SIM_RANLXD2 or IGEA_SIM_XOSHIRO */
/* Noise models beyond white (docs/eqerr.md, "Tracking noise beyond a
 * diagonal K"; all 0 by default, which leaves every flight unchanged): */
#define IGEA_SIM_OPT_AR2 6          /* AR lag-2 coefficient (lag 1: AR1), 0 */
#define IGEA_SIM_OPT_AR3 7          /* AR lag-3 coefficient, 0; (ar1, ar2, ar3) stationary */
#define IGEA_SIM_OPT_CORR 8         /* |r| < 1: per-epoch 3x3 correlation [[1 r r^2][r 1 r]
                                       [r^2 r 1]] with r ramping 0 .. CORR along the epochs */
#define IGEA_SIM_OPT_GROUP_SPLIT 9  /* 0: one group; in (0, 1): epochs e < SPLIT M are group
                                       0, the others group 1 (the AR restarts there) */
#define IGEA_SIM_OPT_SIGMA_W2 10    /* true sigma_w of group 1 (0: SIGMA_W) */
#define IGEA_SIM_OPT_BIAS0 11       /* bias of group 0 rows, in stated sigmas, 0 */
#define IGEA_SIM_OPT_BIAS1 12       /* bias of group 1 rows, in stated sigmas, 0 */
#define IGEA_SIM_OPT_JUDGE_NOISE 13 /* 1: the Monte Carlo judges with the noise model
                                       stated (igea_noise_eqerr with the per-epoch
                                       covariance and the groups); 0: the seed's diagonal K
                                       (the eqerr options AR_ORDER, ROBUST, GROUP_BIAS also
                                       select igea_noise_eqerr) */
#define IGEA_SIM_OPT_BATCH 14 /* Monte Carlo flights per block when S and the stated K
                                 are common to the flights (igea_sim_montecarlo judging
                                 with the seed's diagonal K, linear truth): 0 automatic
                                 (IGEA_SIM_BATCH_DEFAULT), 1 flight by flight, 2 ..
                                 IGEA_SIM_BATCH_MAX (rounded up to a multiple of 32);
                                 the batched results do not depend on it nor on the
                                 threads, and equal the flight-by-flight ones to
                                 rounding (docs/validation.md) */
#define IGEA_SIM_BATCH_DEFAULT 64
#define IGEA_SIM_BATCH_MAX 4096
#define IGEA_SIM_OPT_LEN 32 /* slots 15.. reserved for additions (0) */

#define IGEA_SIM_MT19937 0 /* gsl_rng_mt19937 (default) */
#define IGEA_SIM_RANLXD2 1 /* gsl_rng_ranlxd2 (slower, luxury) */
#define IGEA_SIM_XOSHIRO 2 /* igea's xoshiro256++ keyed by (seed, flight), a
                              ziggurat normal, one normal per row (and the
                              outlier's two draws only when outlier_prob > 0):
                              the fast streams of the Monte Carlo
                              (docs/validation.md) */

/* Fill opts[IGEA_SIM_OPT_LEN] with the defaults above. Returns 0, -1. */
IGEA_API int igea_sim_defaults(double *opts);

/*
 * Number of samples of the reference trajectory: floor(duration * rate +
 * 0.5) + 1 (t = 0, 1/rate, ..., duration).
 * Arguments: 1 duration > 0 [s] (<= 1e5), 2 rate > 0 [Hz] (<= 1e4),
 * 3 nsamp (output). Returns 0, -i.
 */
IGEA_API int igea_sim_trajectory_length(double duration, double rate,
                                        int *nsamp);

/*
 * The reference boost trajectory, nsamp x 11 column-major (t, f, w, q),
 * specific force and rate in body axes (system IGEA_ENVFUN_STRAPDOWN) or
 * the specific force in launch-inertial axes (IGEA_ENVFUN_PLATFORM, the
 * rate columns then hold the body rate, which a platform ignores).
 * Launch frame: x downrange, y up, z completing; body x (thrust axis)
 * starts vertical. Thrust 15 + 10 t/T m/s^2; pitch rate 60 deg spread as
 * sin^2 over [0.08 T, 0.92 T]; wobble rates of 0.005-0.02 rad/s and lateral
 * forces of 0.2-0.3 m/s^2.
 * Arguments: 1 system, 2 duration, 3 rate, 4 nsamp (from
 * igea_sim_trajectory_length), 5 traj, 6 ldt >= nsamp.
 */
IGEA_API int igea_sim_trajectory(int system, double duration, double rate,
                                 int nsamp, double *traj, int ldt);

/*
 * Check opts[IGEA_SIM_OPT_LEN] as the model does: every slot finite (the
 * reserved ones included), sigma_w > 0, |ar1| < 1, growth >= 0, 0 <=
 * outlier_prob <= 1, outlier_scale >= 0, generator IGEA_SIM_MT19937,
 * IGEA_SIM_RANLXD2 or IGEA_SIM_XOSHIRO, (ar1, ar2, ar3) stationary, |corr| < 1, 0 <= group_split
 * < 1, sigma_w2 >= 0, judge_noise 0 or 1. Returns 0 when they are valid, else 1 + the first
 * invalid slot (igea_opt_name(IGEA_MODULE_SIM, status - 1) names it); -1
 * for opts NULL.
 */
IGEA_API int igea_sim_check_opts(const double *opts);

/*
 * The simulation model: an opaque handle holding the flight geometry (S, m
 * rows epoch-major x, y, z, N terms, raw units), the stated tracking sigma,
 * the 1-sigma specs, the true noise (opts), the true X (fixed terms) and,
 * for a model made from a trajectory, the trajectory, terms and epochs of
 * the nonlinear truth. A handle is not shared between threads while a
 * setter runs; flights and Monte Carlo runs only read it, but for one
 * thing: the first Monte Carlo run that completes keeps its set-up in the
 * handle (the weighted S, its normal matrix, their eigen-decomposition and
 * product, (2 m + 3 N + 1) N doubles, under a lock), so that the later runs
 * of the model (the chunks of a long study) skip it, with the same results
 * bit for bit; setting the stated sigma or the specs drops it.
 *
 * Defaults: stated sigma 0.01 m/s on every row, no growth [D]; specs 1
 * (igea_sim_model_create) or the catalogue's (igea_envfun_default_spec,
 * igea_sim_model_create_trajectory); igea_sim_defaults noise; every X
 * drawn N(0, 1); linear truth S D X.
 */
typedef struct igea_sim_model igea_sim_model;

/*
 * A model of a given flight geometry (no trajectory: no nonlinear truth).
 *  1 m      rows, a multiple of 3, >= 3
 *  2 N      terms, >= 1
 *  3 S      m x N column-major, finite (copied)
 *  4 lds    >= m
 *  5 model  output: the new handle (NULL on failure)
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENOMEM.
 */
IGEA_API int igea_sim_model_create(int m, int N, const double *S, int lds,
                                   igea_sim_model **model);

/*
 * A model of a trajectory: S = igea_envfun_compute(system, ..., velocity,
 * no spec) at the epochs, specs the catalogue's defaults; the trajectory,
 * terms, axes and epochs are copied for the nonlinear truth.
 * Arguments 1-9 as igea_envfun_compute's 1-9, 10 model (output).
 * Returns 0, -i, the statuses of igea_envfun_compute, IGEA_ENOMEM.
 */
IGEA_API int igea_sim_model_create_trajectory(int system, int nsamp,
                                              const double *traj, int ldt,
                                              int nterms, const int *terms,
                                              const int *axes, int nepochs,
                                              const double *epochs,
                                              igea_sim_model **model);

/* Release a model (NULL is a no-op). */
IGEA_API void igea_sim_model_free(igea_sim_model *model);

/*
 * Stated tracking 1-sigma: track_sigma m values (sigma_inc 1) or one
 * (sigma_inc 0), > 0 and >= IGEA_SIGMA_MIN, grown along the epochs as
 * with range: row i of epoch e gets track_sigma_i (1 + growth e/(M-1)), M
 * = m/3 epochs; growth >= 0. The grown values are what the flights are
 * judged with (igea_sim_model_get_sigma).
 * Arguments: 1 model, 2 track_sigma, 3 sigma_inc, 4 growth.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE (a sigma
 * below IGEA_SIGMA_MIN, or a grown sigma overflowing); the model is
 * unchanged on failure.
 */
IGEA_API int igea_sim_model_set_sigma(igea_sim_model *model,
                                      const double *track_sigma,
                                      int sigma_inc, double growth);

/*
 * 1-sigma specs scaling the columns: N values (> 0, >= IGEA_SIGMA_MIN),
 * or NULL for none (1). Arguments: 1 model, 2 spec_sigma.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE.
 */
IGEA_API int igea_sim_model_set_spec(igea_sim_model *model,
                                     const double *spec_sigma);

/*
 * The true tracking noise: opts[IGEA_SIM_OPT_LEN] (checked as
 * igea_sim_check_opts), or NULL for igea_sim_defaults.
 * Arguments: 1 model, 2 opts. Returns 0, -i.
 */
IGEA_API int igea_sim_model_set_noise(igea_sim_model *model, const double *opts);

/*
 * The true X: x_fixed N ints, 1 term j is X_j = x_value[j] (spec units,
 * finite), 0 drawn N(0, 1); both NULL: all drawn (x_fixed non-NULL needs
 * x_value). Arguments: 1 model, 2 x_value, 3 x_fixed.
 * Returns 0, -i, IGEA_ENONFINITE.
 */
IGEA_API int igea_sim_model_set_truth(igea_sim_model *model,
                                      const double *x_value,
                                      const int *x_fixed);

/*
 * Nonlinear truth (on 1) or linear (0, the default): with it a flight's
 * dw is igea_sim_nonlinear of the true errors X D (by term code) instead
 * of S D X, with the same noise. Needs a model made by
 * igea_sim_model_create_trajectory.
 * Arguments: 1 model, 2 on (0 or 1). Returns 0, -i.
 */
IGEA_API int igea_sim_model_set_nonlinear(igea_sim_model *model, int on);

/* Rows m and terms N of the model. Returns 0, -i. */
IGEA_API int igea_sim_model_get_size(const igea_sim_model *model, int *m,
                                     int *N);

/* S (m x N, raw units) into S with leading dimension lds >= m.
 * Returns 0, -i. */
IGEA_API int igea_sim_model_get_s(const igea_sim_model *model, double *S,
                                  int lds);

/* The m stated tracking sigmas (growth applied). Returns 0, -i. */
IGEA_API int igea_sim_model_get_sigma(const igea_sim_model *model,
                                      double *track_sigma);

/* The N specs (1 where none were set). Returns 0, -i. */
IGEA_API int igea_sim_model_get_spec(const igea_sim_model *model,
                                     double *spec_sigma);

/*
 * One synthetic flight of the model.
 *  1 model
 *  2 seed     >= 0
 *  3 flight   >= 0, the flight index (its own random stream)
 *  4 x_true   N outputs (the X used, spec units), or NULL
 *  5 dw       m outputs: S D X (or the nonlinear truth) + noise, noise_i =
 *             sigma_w track_sigma_i (1 + g e/(M-1)) eps_i, eps AR(1) per
 *             axis with unit variance, plus an outlier N(0, (scale sd_i)^2)
 *             with probability outlier_prob
 * Returns 0, -i, IGEA_ENONFINITE, the statuses of igea_sim_nonlinear,
 * IGEA_ENOMEM (outputs untouched on failure).
 */
IGEA_API int igea_sim_flight(const igea_sim_model *model, int seed, int flight,
                             double *x_true, double *dw);

/*
 * Velocity error of a full nonlinear navigation with the instrument errors
 * err (METHODS 5.6): the truth-model counterpart of S X, second-order
 * accurate where S X is first-order. Strapdown: the computed attitude
 * starts at exp(-[phi0 x]) C(0) and is propagated with the erroneous rates
 * (exact rotation-vector exponentials of the trapezoid mean rate per step);
 * the erroneous specific force is rotated with it and integrated; a
 * reference navigation without errors uses the same algorithm, so dW =
 * computed - reference carries no algorithm error. Platform: the platform
 * starts rotated by alpha0 and drifts at eps computed from the
 * platform-axis force (the same exponentials); the accelerometers read the
 * rotated force with their errors and the navigator takes it as inertial.
 *  1 system     IGEA_ENVFUN_STRAPDOWN or IGEA_ENVFUN_PLATFORM
 *  2 nsamp >= 2, 3 traj (nsamp x 11, igea/envfun.h), 4 ldt >= nsamp
 *  5 err        IGEA_ENVFUN_TERM_COUNT values: the error of every term by code, in
 *               SI units (e.g. err[IGEA_ENVFUN_TERM_ACC_BIAS_X] = 9.8e-3); terms
 *               not valid for the system must be 0
 *  6 axes       platform gyro axes as igea_envfun_compute, or NULL
 *  7 nepochs >= 1, 8 epochs (non-decreasing, inside the trajectory)
 *  9 dW         3 nepochs outputs, epoch-major (x, y, z), linear
 *               interpolation between samples
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EDOMAIN (zero quaternion),
 * IGEA_ENOMEM.
 */
IGEA_API int igea_sim_nonlinear(int system, int nsamp, const double *traj,
                                int ldt, const double *err, const int *axes,
                                int nepochs, const double *epochs,
                                double *dW);

/* Indices into counts[IGEA_SIM_MC_LEN] of igea_sim_montecarlo. */
#define IGEA_SIM_MC_FLIGHTS 0      /* flights run */
#define IGEA_SIM_MC_FAILED 1       /* verdict "out of spec": any rejection */
#define IGEA_SIM_MC_CHI2_REJECT 2  /* T >= chi2_alpha(|I_t|) */
#define IGEA_SIM_MC_ANY_REJECT 3   /* at least one component |z_i| > z_crit */
#define IGEA_SIM_MC_NOT_TESTABLE 4 /* no component with lambda >= lambda_test */
#define IGEA_SIM_MC_MEAN_SCALE 5   /* mean of the final scale c (sigma_w^2) */
#define IGEA_SIM_MC_MEAN_TESTED 6  /* mean |I_t| */
#define IGEA_SIM_MC_MEAN_SIZE 7    /* mean overall size of the verdict rule (info
                                    * OVERALL_SIZE; 0 if not computed) */
#define IGEA_SIM_MC_SIGMA_COVERED 8 /* judged by igea_noise_eqerr: flights whose every
                                       group's sigma_w,g-hat = sqrt(c_g) is within 3
                                       standard errors of its truth on the log scale,
                                       |ln c_g - ln sigma_w,g^2| <= 3 se / c_g with se
                                       the REML one (IGEA_NOISE_GROUP_SE_REML) [D] */
#define IGEA_SIM_MC_SCALE_COVERED 12 /* judged by igea_noise_eqerr: flights whose every
                                        group scale c_g is within 3 standard errors of
                                        its truth sigma_w,g^2 */
#define IGEA_SIM_MC_MEAN_OUTLIERS 13 /* mean rows rejected by the robust route */
#define IGEA_SIM_MC_LEN 16 /* slots 9..11, 14.. reserved for additions */

/* rates[IGEA_SIM_MC_RATES_LEN]: for each count k of IGEA_SIM_MC_FAILED ..
 * IGEA_SIM_MC_NOT_TESTABLE, rates[3 (k - 1)] = count / flights and
 * rates[3 (k - 1) + 1], [+ 2] its 99 % interval (igea_sim_interval). */
#define IGEA_SIM_MC_RATES_LEN 12

/* Columns of the per-flight table of igea_sim_montecarlo. */
#define IGEA_SIM_MC_TABLE_CHI2 0     /* T (0 if not testable) */
#define IGEA_SIM_MC_TABLE_DOF 1      /* |I_t| (0 if not testable) */
#define IGEA_SIM_MC_TABLE_N_REJECT 2 /* rejected components */
#define IGEA_SIM_MC_TABLE_SCALE 3    /* final c (NaN if not testable) */
#define IGEA_SIM_MC_TABLE_COLS 4
/* A fifth column, in the tables of IGEA_SIM_MC_TABLE_COLS_Z columns that
 * igea_sim_montecarlo_ex writes and igea_sim_pool_ex reads: */
#define IGEA_SIM_MC_TABLE_ZMAX 4 /* the largest |z_i| over the tested components
                                    (0 if not testable): a component of the
                                    flight is beyond a threshold a iff ZMAX > a */
#define IGEA_SIM_MC_TABLE_COLS_Z 5

/*
 * The 99 % Wilson score interval of a rate of k successes in n trials
 * (z = 2.5758293035489004), clipped to [0, 1]: the interval of the Monte
 * Carlo rates. Arguments: 1 k (0 <= k <= n), 2 n (> 0), 3 lohi (2
 * outputs). Returns 0, -i.
 */
IGEA_API int igea_sim_interval(double k, double n, double *lohi);

/*
 * The exact (Clopper-Pearson) interval of a rate of k successes in n
 * trials at confidence level: [B((1 - level)/2; k, n - k + 1),
 * B((1 + level)/2; k + 1, n - k)] with B(p; a, b) the beta quantile (0 when
 * k = 0, 1 when k = n), by bisection on igea's regularised incomplete beta
 * (igea_stats_f_sf) to 4 ulp: relative accuracy about 1e-11 up to n = 1e5,
 * 1e-9 near the largest n. igea_sim_interval (Wilson) is unchanged.
 *  1 k      successes, a whole number, 0 <= k <= n
 *  2 n      trials, a whole number, 1 <= n <= IGEA_SIM_INTERVAL_CP_NMAX
 *  3 level  confidence, 0 < level < 1 (0.99: the 99 % interval)
 *  4 lohi   2 outputs: the lower and the upper end
 * Returns 0, -i, IGEA_ENOCONV; lohi untouched on failure.
 */
#define IGEA_SIM_INTERVAL_CP_NMAX 4999999.0
IGEA_API int igea_sim_interval_cp(double k, double n, double level, double *lohi);

/*
 * Monte Carlo: flights first_flight .. first_flight + nflights - 1 of
 * igea_sim_flight, each judged by igea_eqerr_solve on the normal equations
 * (igea_normal_accumulate) of the model's S, stated sigma and specs (eig
 * route, whatever eq_opts' route).
 *  1 model
 *  2 eq_opts      IGEA_EQERR_OPT_LEN values or NULL (igea_eqerr_defaults)
 *  3 seed         >= 0
 *  4 first_flight >= 0
 *  5 nflights     >= 1
 *  6 nthreads     >= 0 (0: the number of online processors); results do
 *                 not depend on it (bit for bit: each thread takes the next
 *                 flights when it is free, the means are summed in flight
 *                 order, a failure is the lowest failing flight's)
 *  7 counts       IGEA_SIM_MC_LEN outputs (above); the means are over the
 *                 testable flights (IGEA_SIM_MC_MEAN_SCALE NaN if none)
 *  8 rates        IGEA_SIM_MC_RATES_LEN outputs (above), or NULL
 *  9 comp_tested  N outputs or NULL: flights in which eigen-component i
 *                 (descending lambda) was tested
 * 10 comp_reject  N outputs or NULL: ... and rejected
 * 11 table        nflights x IGEA_SIM_MC_TABLE_COLS outputs (column-major,
 *                 row f the flight first_flight + f), or NULL
 * 12 ldt          >= nflights (ignored when table is NULL)
 * Flights with nothing testable count in IGEA_SIM_MC_NOT_TESTABLE and pass.
 * Returns 0, -i (-2 also for eqerr options that igea_eqerr_check_opts
 * refuses), IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE, IGEA_EOVERFLOW,
 * IGEA_ENOMEM, IGEA_ELAPACK (outputs untouched on failure).
 */
IGEA_API int igea_sim_montecarlo(const igea_sim_model *model,
                                 const double *eq_opts, int seed,
                                 int first_flight, int nflights, int nthreads,
                                 double *counts, double *rates,
                                 int *comp_tested, int *comp_reject,
                                 double *table, int ldt);

/*
 * igea_sim_montecarlo with a wider per-flight table: arguments 1-12 as
 * igea_sim_montecarlo's, and
 * 13 ncols  IGEA_SIM_MC_TABLE_COLS (the table of igea_sim_montecarlo) or
 *           IGEA_SIM_MC_TABLE_COLS_Z (also IGEA_SIM_MC_TABLE_ZMAX, what
 *           igea_sim_pool_ex reads); ignored when table is NULL.
 * Every other output, and the table's first four columns, are those of
 * igea_sim_montecarlo bit for bit (the same paths, blocks and threads).
 * Returns as igea_sim_montecarlo (-13 for another ncols).
 */
IGEA_API int igea_sim_montecarlo_ex(const igea_sim_model *model, const double *eq_opts,
                                    int seed, int first_flight, int nflights, int nthreads,
                                    double *counts, double *rates, int *comp_tested,
                                    int *comp_reject, double *table, int ldt, int ncols);

/* Indices into pooled[IGEA_SIM_POOL_LEN] of igea_sim_pool. */
#define IGEA_SIM_POOL_POOLS 0   /* groups judged: floor(nflights / size) */
#define IGEA_SIM_POOL_FAILED 1  /* groups whose pooled verdict is "out of spec" */
#define IGEA_SIM_POOL_RATE 2    /* FAILED / POOLS */
#define IGEA_SIM_POOL_CI99_LO 3 /* its 99 % interval (igea_sim_interval) */
#define IGEA_SIM_POOL_CI99_HI 4
#define IGEA_SIM_POOL_MEAN_SIZE 5 /* igea_sim_pool_ex: mean overall size of the pooled rule
                                     (igea_sim_pool: 0) */
#define IGEA_SIM_POOL_LEN 8

/*
 * Pooled verdicts of a Monte Carlo run (METHODS 1.2 step 6): the rows of a
 * per-flight table of igea_sim_montecarlo taken in consecutive groups of
 * size flights (rows 0 .. size - 1, size .. 2 size - 1, ...; a last group
 * of fewer than size rows is left out), each group judged by
 * igea_stats_pool on its testable flights (DOF > 0): "out of spec" when a
 * flight of the group has a rejected component or the summed chi-square
 * reaches chi2_alpha(summed dof). A group with no testable flight passes,
 * as a flight with nothing testable does.
 *  1 nflights  >= 1, rows of the table
 *  2 table     nflights x IGEA_SIM_MC_TABLE_COLS, column-major, as
 *              igea_sim_montecarlo writes it; read are CHI2 (finite, >= 0,
 *              0 where DOF is 0), DOF (an integer, 0 .. IGEA_STATS_DOF_MAX)
 *              and N_REJECT (an integer, 0 .. DOF), not SCALE
 *  3 ldt       >= nflights
 *  4 size      >= 1, flights per group
 *  5 alpha     0 < alpha < 1, the level of the pooled chi-square test (the
 *              flights' own: IGEA_EQERR_OPT_ALPHA of the run)
 *  6 pooled    IGEA_SIM_POOL_LEN outputs (above; the unnamed slots 0). When
 *              size > nflights there is no group: POOLS and FAILED 0, RATE
 *              and its interval NaN.
 * Returns 0, -i (-2 also for a table entry out of its range, -4 also when
 * a group's summed dof exceeds IGEA_STATS_DOF_MAX), IGEA_ENONFINITE,
 * IGEA_ENOCONV, IGEA_ENOMEM (outputs untouched on failure).
 */
IGEA_API int igea_sim_pool(int nflights, const double *table, int ldt,
                           int size, double alpha, double *pooled);

/*
 * Pooled verdicts by the overall verdict rule of eq_opts (docs/eqerr.md,
 * "The rule in the main job"; igea_eqerr_pool's rule): the rows of a table
 * of igea_sim_montecarlo_ex (IGEA_SIM_MC_TABLE_COLS_Z columns) in
 * consecutive groups of size flights as igea_sim_pool takes them. A
 * group's testable flights (DOF > 0) pool n = dof_tot = the sum of their
 * DOF components: with a and b the rule's thresholds for n (those of
 * igea_eqerr_pool: SEED a = z_{1-alpha/2} or OPT_Z_CRIT, b =
 * chi2_alpha(n); CHI2 no a; EXACT both at the level that makes the
 * union's size alpha; SIDAK a at the Sidak level of n), the group is "out
 * of spec" when the largest ZMAX of its flights exceeds a or T_tot = the
 * sum of their CHI2 (summed as igea_stats_pool sums it) reaches b: the
 * verdict igea_eqerr_pool gives on the flights' z, which only the largest
 * |z| of each flight decides. A group with no testable flight passes. With
 * SEED it counts what igea_sim_pool counts on flights judged by SEED.
 *  1 nflights  >= 1, rows of the table
 *  2 table     nflights x IGEA_SIM_MC_TABLE_COLS_Z, column-major, as
 *              igea_sim_montecarlo_ex writes it; read are CHI2 (finite, >=
 *              0, 0 where DOF is 0), DOF (an integer, 0 ..
 *              IGEA_STATS_DOF_MAX) and ZMAX (finite, >= 0, 0 where DOF is 0)
 *  3 ldt       >= nflights
 *  4 size      >= 1, flights per group
 *  5 eq_opts   IGEA_EQERR_OPT_LEN values or NULL (igea_eqerr_defaults):
 *              alpha, z_crit, verdict and overall_size are read (those of
 *              the run: the flights' own rule)
 *  6 pooled    IGEA_SIM_POOL_LEN outputs: as igea_sim_pool's, and
 *              MEAN_SIZE the mean over the groups with a testable flight
 *              of the rule's overall size for their n (info OVERALL_SIZE of
 *              igea_eqerr_pool: CHI2 alpha, EXACT alpha to 1e-12, SEED and
 *              SIDAK the union size when overall_size is 1; 0 when it is
 *              not computed for some group: overall_size 0, or n >
 *              IGEA_STATS_UNION_N_MAX). No group: POOLS and FAILED 0, RATE,
 *              its interval and MEAN_SIZE NaN.
 * The rule's thresholds are computed once per distinct n (EXACT about 12
 * union sizes each). Returns 0, -i (-2 also for a table entry out of its
 * range, -4 also when a group's summed dof exceeds IGEA_STATS_DOF_MAX, -5
 * for options igea_eqerr_check_opts refuses), IGEA_ENONFINITE, IGEA_EVERDICT
 * (EXACT for a group of more than IGEA_STATS_UNION_N_MAX components),
 * IGEA_ENOCONV, IGEA_ENOMEM (outputs untouched on failure).
 */
IGEA_API int igea_sim_pool_ex(int nflights, const double *table, int ldt, int size,
                              const double *eq_opts, double *pooled);

/* ---- raw range records of a simulated flight (src/sim_raw.c) ------------ */

/* Columns of the raw records of igea_sim_raw. */
#define IGEA_SIM_RAW_TEL_STRAPDOWN 7 /* t dvx dvy dvz dthx dthy dthz (body axes) */
#define IGEA_SIM_RAW_TEL_PLATFORM 4  /* t dvx dvy dvz (stabilised = LI axes) */
#define IGEA_SIM_RAW_TRK_COLS 7      /* t x y z vx vy vz */

/*
 * The two raw records a range hands over for a simulated flight
 * (docs/pipeline.md, section 8): the telemetry (the instruments' increments
 * at the trajectory rate, with the instrument errors err applied) and the
 * tracking (the true vehicle, or its tracked point, in frame at the
 * epochs, minus the velocity noise given), plus the launch point and the
 * lift-off attitude as the range states them (with the launch-point and
 * initial-attitude errors of err). The true vehicle is the navigation
 * (igea_nav_step, J2) of the error-free increments from the true site; so
 * igea_dw_compute of the records without errors and noise gives dW = 0 up
 * to its own gravity-integral and interpolation error.
 * Increments over (t_{k-1}, t_k]: trapezoids of the sampled instrument
 * outputs, dv = h (f^_{k-1} + f^_k) / 2, dth = h (w^_{k-1} + w^_k) / 2;
 * f^, w^ the trajectory's f, w with the errors of igea_envfun_nonlinear
 * (igea__term_unit of every code whose err is not 0; the size effect's
 * tangential part as r (dw_k x e_k)_j; a platform's force read in its
 * drifting axes P, P_0 = exp([alpha0 x]), P' = P [eps x] by the same
 * trapezoid-exponential step, eps from the platform-axis force).
 * Launch-point errors pos0_x, pos0_z (m) move the stated launch point by
 * that much downrange and cross-range at the same height, the stated
 * azimuth keeping the true downrange direction; the lever arm l (body, m)
 * puts the tracked point at r + C(q) l, v + C(q) (w x l).
 * Arguments:
 *  1 system   IGEA_ENVFUN_STRAPDOWN or IGEA_ENVFUN_PLATFORM
 *  2 nsamp    >= 2; 3 traj (nsamp x 11, igea/envfun.h, t_0 = 0 the
 *             lift-off); 4 ldt >= nsamp
 *  5 nerr     IGEA_ENVFUN_TERM_COUNT <= nerr <= igea_envfun_term_count()
 *  6 err      nerr values: the true error of each code, SI units (codes
 *             not valid for the system must be 0); may be NULL: none
 *  7 axes     platform gyro axes as igea_envfun_compute, or NULL
 *  8 site     the true launch point (IGEA_NAV_SITE_LEN, igea_nav_site)
 *  9 frame    IGEA_NAV_ECEF or IGEA_NAV_LE, the tracking's frame
 * 10 nepochs  >= 1; 11 epochs: increasing, inside [t_0, t_last] (any
 *             times: between samples t_{k-1} < t_e < t_k the true state is
 *             a partial navigation step from t_{k-1} with the increments of
 *             the linear interpolants of f and w over (t_{k-1}, t_e], the
 *             lever arm's attitude and rate interpolated linearly; a time
 *             within 1e-9 s of a sample is the sample's)
 * 12 noise    3 nepochs values: the velocity noise of dW in LI, epoch-major
 *             (the tracking velocity gets -noise, rotated into frame); may
 *             be NULL: none
 * 13 tel      output, nsamp x IGEA_SIM_RAW_TEL_* column-major (row 0: t_0,
 *             zero increments); 14 ldtel >= nsamp
 * 15 trk      output, nepochs x IGEA_SIM_RAW_TRK_COLS column-major;
 *             16 ldtrk >= nepochs
 * 17 q0       output, 4: the stated attitude body -> LI at lift-off
 *             (strapdown, with att0; platform 1 0 0 0)
 * 18 site_out output, IGEA_NAV_SITE_LEN: the stated launch point
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EDOMAIN (a zero quaternion),
 * IGEA_ENOMEM; outputs untouched on failure.
 */
IGEA_API int igea_sim_raw(int system, int nsamp, const double *traj, int ldt, int nerr,
                          const double *err, const int *axes, const double *site,
                          int frame, int nepochs, const double *epochs,
                          const double *noise, double *tel, int ldtel, double *trk,
                          int ldtrk, double *q0, double *site_out);

/*
 * igea_sim_raw with the tracking's own errors and accuracy columns
 * (docs/pipeline.md section 8): the tracked position and velocity of
 * epoch e get the errors trk_err[6 e .. 6 e + 5] (dx dy dz dvx dvy dvz,
 * m and m/s, in the tracking's frame: what a tracking system measures
 * wrong) and row e's accuracy columns are acc[acc_cols e .. acc_cols e +
 * acc_cols - 1] as igea_dw_compute reads them after t x y z vx vy vz (1: one
 * sigma; 3: sigma_x sigma_y sigma_z; 6: the velocity covariance c_xx c_xy
 * c_xz c_yy c_yz c_zz; 21: the 6 x 6 position-velocity covariance, upper
 * triangle row by row), copied as given (the caller states them; they
 * are not checked against the errors).
 * Arguments: 1-11 as igea_sim_raw (positions 1-11)
 * 12 trk_err  6 nepochs values (finite), epoch-major; may be NULL: none
 * 13 acc_cols 0, 1, 3, 6 or 21
 * 14 acc      acc_cols nepochs values (finite), epoch-major; may be NULL
 *             only when acc_cols is 0
 * 15 tel, 16 ldtel  as igea_sim_raw
 * 17 trk      output, nepochs x (IGEA_SIM_RAW_TRK_COLS + acc_cols)
 *             column-major; 18 ldtrk >= nepochs
 * 19 q0, 20 site_out as igea_sim_raw
 * Returns as igea_sim_raw (-12 also a non-finite trk_err, -14 a
 * non-finite acc); outputs untouched on failure.
 */
IGEA_API int igea_sim_raw_track(int system, int nsamp, const double *traj, int ldt, int nerr,
                                const double *err, const int *axes, const double *site,
                                int frame, int nepochs, const double *epochs,
                                const double *trk_err, int acc_cols, const double *acc,
                                double *tel, int ldtel, double *trk, int ldtrk, double *q0,
                                double *site_out);

/*
 * A tracking error model for igea_sim_raw_track (docs/pipeline.md section
 * 8) [D]: per epoch the 6 x 6 covariance of the position and velocity
 * errors in the tracking axes,
 *   P_e = [[s_r^2 R, c s_r s_v,e R], [c s_r s_v,e R, s_v,e^2 R]],
 *   R = [[1 r r^2], [r 1 r], [r^2 r 1]]
 * (positive definite for |r| < 1, |c| < 1), and a draw err_e = L_e z, L_e
 * its Cholesky factor, z standard normal from the MT19937 generator of
 * (seed, flight) (a stream of its own, not the flight's noise).
 * Arguments:
 *  1 nepochs  >= 1
 *  2 sigma_v  nepochs values > 0: the velocity 1-sigma per axis, m/s
 *  3 sigma_r  > 0, the position 1-sigma per axis, m
 *  4 rho      |rho| < 1, the correlation between neighbouring axes
 *  5 cross    |cross| < 1, the position-velocity correlation per axis pair
 *  6 seed, 7 flight   >= 0 (as igea_sim_flight)
 *  8 acc      output, 21 nepochs: P_e's upper triangle row by row (x y z
 *             vx vy vz), epoch-major: igea_sim_raw_track's acc with
 *             acc_cols 21
 *  9 err      output, 6 nepochs: the draws dx dy dz dvx dvy dvz, epoch-major;
 *             may be NULL
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENOMEM; outputs untouched on
 * failure.
 */
IGEA_API int igea_sim_track_errors(int nepochs, const double *sigma_v, double sigma_r,
                                   double rho, double cross, int seed, int flight,
                                   double *acc, double *err);

#ifdef __cplusplus
}
#endif
#endif
