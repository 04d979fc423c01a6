/*
 * igea/sim.h - reproducible synthetic flights and the Monte Carlo check of
 * the equivalent-error accuracy test (METHODS 1 and 5.6).
 *
 *  - igea_sim_trajectory: the reference boost trajectory (METHODS 5.6:
 *    thrust 15-25 m/s^2 along body x, a pitch-over of 60 degrees, a small
 *    wobble; attitude propagated with exact quaternion exponentials), in
 *    the trajectory layout of igea/envfun.h.
 *  - igea_sim_flight: one synthetic flight dw = S D X + noise, X drawn
 *    N(0, I) in spec units or set term by term, tracking noise white with
 *    a true scale sigma_w, AR(1)-correlated, growing along the flight, with
 *    occasional outliers.
 *  - igea_sim_montecarlo: many flights generated and judged by the seed-000
 *    test (igea_eqerr_solve on the normal equations), with counts of
 *    rejections, optionally on several POSIX threads.
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
#define IGEA_SIM_OPT_GENERATOR 5     /* IGEA_SIM_MT19937 or IGEA_SIM_RANLXD2 */
#define IGEA_SIM_OPT_LEN 8

#define IGEA_SIM_MT19937 0 /* gsl_rng_mt19937 (default) */
#define IGEA_SIM_RANLXD2 1 /* gsl_rng_ranlxd2 (slower, luxury) */

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
 * One synthetic flight.
 *  1 m            rows, a multiple of 3 (epoch-major x, y, z), >= 3
 *  2 N            error terms, >= 1
 *  3 S            m x N column-major environment functions (raw units)
 *  4 lds          >= m
 *  5 track_sigma  stated tracking 1-sigma: m values (sigma_inc 1) or one
 *                 (sigma_inc 0), > 0
 *  6 sigma_inc    0 or 1
 *  7 spec_sigma   N specs (> 0) scaling the columns, or NULL
 *  8 x_value      N values (spec units) used for the fixed terms, or NULL
 *  9 x_fixed      N ints: 1 term j is X_j = x_value[j], 0 drawn N(0, 1);
 *                 NULL: all drawn. Non-NULL needs x_value.
 * 10 opts         IGEA_SIM_OPT_LEN values or NULL (defaults): sigma_w > 0,
 *                 |ar1| < 1, growth >= 0, 0 <= outlier_prob <= 1,
 *                 outlier_scale >= 0, generator 0 or 1
 * 11 seed         >= 0
 * 12 flight       >= 0, the flight index (its own random stream)
 * 13 x_true       N outputs (the X used, spec units), or NULL
 * 14 dw           m outputs: S D X + noise, noise_i = sigma_w
 *                 track_sigma_i (1 + g e/(M-1)) eps_i, eps AR(1) per axis
 *                 with unit variance, plus an outlier N(0, (scale sd_i)^2)
 *                 with probability outlier_prob
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE (a sigma
 * or spec below IGEA_SIGMA_MIN), IGEA_ENOMEM.
 */
IGEA_API int igea_sim_flight(int m, int N, const double *S, int lds,
                             const double *track_sigma, int sigma_inc,
                             const double *spec_sigma, const double *x_value,
                             const int *x_fixed, const double *opts, int seed,
                             int flight, double *x_true, double *dw);

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
#define IGEA_SIM_MC_LEN 8

/*
 * Monte Carlo: flights first_flight .. first_flight + nflights - 1 of
 * igea_sim_flight (arguments 1-11 as there), each judged by
 * igea_eqerr_solve on the normal equations of S, dw, track_sigma,
 * spec_sigma (eig route, whatever eq_opts' route).
 * 12 eq_opts      IGEA_EQERR_OPT_LEN values or NULL (igea_eqerr_defaults)
 * 13 first_flight >= 0
 * 14 nflights     >= 1
 * 15 nthreads     >= 0 (0: the number of online processors); results do
 *                 not depend on it
 * 16 counts       IGEA_SIM_MC_LEN outputs (above)
 * 17 comp_tested  N outputs or NULL: flights in which eigen-component i
 *                 (descending lambda) was tested
 * 18 comp_reject  N outputs or NULL: ... and rejected
 * 19 chi2         nflights outputs or NULL: T of each flight (0 if not
 *                 testable)
 * 20 dof          nflights outputs or NULL: |I_t| (0 if not testable)
 * 21 n_reject     nflights outputs or NULL: rejected components
 * 22 scale        nflights outputs or NULL: final c of each flight
 * Flights with nothing testable count in IGEA_SIM_MC_NOT_TESTABLE and pass.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE, IGEA_ENOMEM,
 * IGEA_ELAPACK (outputs untouched on failure).
 */
IGEA_API int igea_sim_montecarlo(int m, int N, const double *S, int lds,
                                 const double *track_sigma, int sigma_inc,
                                 const double *spec_sigma,
                                 const double *x_value, const int *x_fixed,
                                 const double *opts, int seed,
                                 const double *eq_opts, int first_flight,
                                 int nflights, int nthreads, double *counts,
                                 int *comp_tested, int *comp_reject,
                                 double *chi2, int *dof, int *n_reject,
                                 double *scale);

#ifdef __cplusplus
}
#endif
#endif
