/*
 * igea/accel.h - accelerometer calibration in the gravity field on a
 * dividing head (seed 003; METHODS 4.1-4.3).
 *
 * The head turns about a horizontal axis (the pendulous axis PA in the
 * "door" position); at head angle theta the input axis IA of accelerometer
 * A senses g sin(phi), phi = theta + head error + installation angle.
 * Outputs are in g (raw volts divided by the nominal scale factor, see
 * igea_accel_to_g).
 *
 * Single model (METHODS 4.1), IGEA_ACCEL_SINGLE, 5 coefficients, observation
 * y = y_A - sin(theta), design row [1, s, c, s^2, s c] (s = sin theta,
 * c = cos theta):
 *     K = [K0, k1, delta0, K2, Kix]
 * (bias, scale-factor correction, installation angle about the rotation
 * axis in rad, second-order term, cross-coupling with the second in-plane
 * axis x: Kio when turning about PA, Kip when turning about OA). The head
 * errors enter as delta_theta cos(theta): the single model's accuracy limit.
 *
 * Orthogonal-dual g^2 model (METHODS 4.2), IGEA_ACCEL_DUAL, 9 coefficients,
 * B mounted at 90 deg + eta from A, observation
 * y = (y_A^2 + y_B^2 - 1) / 2, design row
 *     [s, c, s^2, c^2, -s c, s^3, c^3, s^2 c, -s c^2]
 * for K = [KA0, KB0, kA1, kB1, eta, KA2, KB2, KAix, KBix]. The head errors
 * cancel to first order, but the design has rank 7 (for 7 or more distinct
 * equispaced positions): the null space is spanned by
 * n1 = (KA0, KA2, KBix) = (-1, 1, -1) and n2 = (KB0, KB2, KAix) = (-1, 1, 1).
 * Only the estimable combinations (igea_accel_combinations)
 *     kA1, kB1, eta, KA0 + KA2, KA2 + KBix, KB0 + KB2, KB2 - KAix
 * are determined by a calibration; the individual KA0, KB0, KA2, KB2, KAix,
 * KBix are fixed by the minimum-norm convention (LS) or by the prior (EBR),
 * and every fit flags them so (IGEA_ACCEL_PRIOR).
 *
 * Status codes as everywhere in igea: 0 ok, -i argument i invalid,
 * IGEA_E* library-wide failures; outputs are untouched on failure.
 */
#ifndef IGEA_ACCEL_H
#define IGEA_ACCEL_H

#include "igea/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Models. */
#define IGEA_ACCEL_SINGLE 0
#define IGEA_ACCEL_DUAL 1

/* Coefficients per model and estimable combinations per model. */
#define IGEA_ACCEL_NP_SINGLE 5
#define IGEA_ACCEL_NP_DUAL 9
#define IGEA_ACCEL_NC_SINGLE 5
#define IGEA_ACCEL_NC_DUAL 7

/* Column order of the single model (METHODS 4.1). */
#define IGEA_ACCEL_K0 0
#define IGEA_ACCEL_K1 1
#define IGEA_ACCEL_DELTA0 2
#define IGEA_ACCEL_K2 3
#define IGEA_ACCEL_KIX 4

/* Column order of the dual model (METHODS 4.2, eq. 4). */
#define IGEA_ACCEL_KA0 0
#define IGEA_ACCEL_KB0 1
#define IGEA_ACCEL_KA1 2
#define IGEA_ACCEL_KB1 3
#define IGEA_ACCEL_ETA 4
#define IGEA_ACCEL_KA2 5
#define IGEA_ACCEL_KB2 6
#define IGEA_ACCEL_KAIX 7
#define IGEA_ACCEL_KBIX 8
/* Truth vectors of igea_accel_simulate: the 9 dual coefficients, then the
 * installation angle delta0 (rad). */
#define IGEA_ACCEL_SIM_DELTA0 9
#define IGEA_ACCEL_NP_SIM 10

/* Fit methods. */
#define IGEA_ACCEL_LS 0  /* least squares (minimum norm if rank-deficient) */
#define IGEA_ACCEL_EBR 1 /* empirical-Bayes ridge (METHODS 4.3) */
#define IGEA_ACCEL_JOINT 2 /* joint radial + tangential fit (igea_accel_joint;
                              not a method of igea_accel_fit) */

/* Flags per coefficient. */
#define IGEA_ACCEL_DATA 0  /* determined by the data */
#define IGEA_ACCEL_PRIOR 1 /* loads on the null space: fixed by the prior or
                              by the minimum-norm convention, not the data */

/* A coefficient is flagged IGEA_ACCEL_PRIOR when the norm of its
 * projection on the null space of the design exceeds this. */
#define IGEA_ACCEL_LOADING_TOL 1e-6

/* Indices into info[IGEA_ACCEL_INFO_LEN] (doubles). */
#define IGEA_ACCEL_INFO_RANK 0   /* numerical rank of the design */
#define IGEA_ACCEL_INFO_SIGMA 1  /* residual sd of the observation equation,
                                    sqrt(RSS / dof) (0 when dof = 0) */
#define IGEA_ACCEL_INFO_LAMBDA 2 /* EBR prior scale lambda hat (0 for LS) */
#define IGEA_ACCEL_INFO_RMS 3    /* residual root-mean-square */
#define IGEA_ACCEL_INFO_NOBS 4   /* observations used */
#define IGEA_ACCEL_INFO_DOF 5    /* observations - rank */
#define IGEA_ACCEL_INFO_ITER 6   /* Gauss-Newton iterations (refine) */
#define IGEA_ACCEL_INFO_STEP 7   /* last Gauss-Newton step, max-norm */
#define IGEA_ACCEL_INFO_LEN 8

/*
 * Position schedule: n equally spaced head angles
 * theta_deg[k] = start_deg + 360 k / n, k = 0..n-1 (the 360 deg reading,
 * which repeats 0 deg, is not part of it).
 *  1 n >= 1; 2 start_deg finite; 3 theta_deg[n] output.
 * Returns 0 or -i.
 */
IGEA_API int igea_accel_schedule(int n, double start_deg, double *theta_deg);

/*
 * Merge the readings of one calibration into one value per position: the
 * clockwise and counter-clockwise runs are averaged per position, and the
 * 360 deg reading is averaged with the 0 deg one (angles are compared
 * modulo 360). Readings whose angles differ by at most tol_deg (after
 * sorting) form one position; the position's angle is the mean of its
 * readings' angles reduced to [-tol_deg, 360 - tol_deg).
 *  1 nrows >= 1 readings; 2 angle_deg[nrows] head angles (any order);
 *  3 ya[nrows] A outputs; 4 yb[nrows] B outputs or NULL (single model);
 *  5 tol_deg: 0 <= tol_deg < 45;
 * Outputs (capacity nrows each; positions in ascending angle):
 *  6 theta_deg, 7 ya_mean, 8 yb_mean (NULL when yb is NULL),
 *  9 count[nrows] readings per position (may be NULL), 10 npos.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENOMEM.
 */
IGEA_API int igea_accel_merge(int nrows, const double *angle_deg,
                              const double *ya, const double *yb,
                              double tol_deg, double *theta_deg,
                              double *ya_mean, double *yb_mean, int *count,
                              int *npos);

/*
 * Raw outputs to g: y[i] = raw[i] / scale (scale = the nominal scale factor
 * in output units per g, e.g. V/g; its sign carries the polarity).
 *  1 n >= 1; 2 raw[n]; 3 scale finite and != 0; 4 y[n] (may alias raw).
 * Returns 0, -i, IGEA_ENONFINITE.
 */
IGEA_API int igea_accel_to_g(int n, const double *raw, double scale,
                             double *y);

/*
 * Observation of the linear model: single y = y_A - sin(theta); dual
 * y = (y_A^2 + y_B^2 - 1) / 2 (METHODS 4.2 eq. 3), outputs in g.
 *  1 model; 2 n >= 1; 3 theta_deg[n]; 4 ya[n]; 5 yb[n] (dual; ignored and
 *  may be NULL for single); 6 y[n].
 * Returns 0, -i, IGEA_ENONFINITE.
 */
IGEA_API int igea_accel_observe(int model, int n, const double *theta_deg,
                                const double *ya, const double *yb, double *y);

/*
 * Design matrix (n x np column-major, np = 5 single / 9 dual) in the
 * column order above.
 *  1 model; 2 n >= 1 positions; 3 theta_deg[n]; 4 A; 5 lda >= n.
 * Returns 0, -i, IGEA_ENONFINITE.
 */
IGEA_API int igea_accel_design(int model, int n, const double *theta_deg,
                               double *A, int lda);

/*
 * The model's estimable combinations as the columns of C (np x nc): the
 * identity for the single model (nc = 5); for the dual model (nc = 7) the
 * columns are kA1, kB1, eta, KA0 + KA2, KA2 + KBix, KB0 + KB2, KB2 - KAix.
 *  1 model; 2 C; 3 ldc >= np.
 * Returns 0 or -i.
 */
IGEA_API int igea_accel_combinations(int model, double *C, int ldc);

/* The axis the dividing head turns about (IGEA_CHOICE_ACCEL_AXIS: pa oa):
 * it names the cross-coupling coefficient the rotation excites (turning
 * about the pendulous axis PA gives Kio, about the output axis OA Kip). */
#define IGEA_ACCEL_AXIS_PA 0
#define IGEA_ACCEL_AXIS_OA 1

/*
 * Names and units of the model's coefficients and combinations, static
 * strings (like igea_strerror): coefficient j (0 <= j < np) of model for
 * rotation axis `axis` ("KA0", ..., "KAio"); combination k (0 <= k < nc,
 * the columns of igea_accel_combinations: "KA0+KA2", ...); the unit of
 * coefficient j ("g", "" for a scale factor, "rad", "g/g^2"). "" for an
 * unknown model, axis or index. igea_accel_coef_name and
 * igea_accel_coef_unit also name the IEEE Std 1293 model's coefficients
 * (model IGEA_ACCEL_IEEE, below; any axis): "K0", "K1", "K2", "K3", "Kip",
 * "Kio", "delta_o", "delta_p"; K1's unit is "out/g" (output units per g).
 */
IGEA_API const char *igea_accel_coef_name(int model, int axis, int j);
IGEA_API const char *igea_accel_comb_name(int model, int axis, int k);
IGEA_API const char *igea_accel_coef_unit(int model, int j);

/*
 * The estimable combinations of a coefficient vector, comb = C^T coef with
 * C of igea_accel_combinations: 1 model; 2 coef[np]; 3 comb[nc] (output).
 * Returns 0, -i, or IGEA_ENONFINITE (comb untouched) when coef holds NaN
 * or Inf.
 */
IGEA_API int igea_accel_combine(int model, const double *coef, double *comb);

/*
 * Identifiability of a position schedule: singular values, rank, null
 * space, and each coefficient's and each combination's loading on the null
 * space (the norm of its projection; 0 = determined by the data).
 *  1 model; 2 n >= 1; 3 theta_deg[n];
 * Outputs:
 *  4 sv[np] singular values of the design, descending (0 beyond min(n, np));
 *  5 null (np x np), 6 ldn >= np: the first np - rank columns are an
 *    orthonormal null-space basis in canonical form [D] (reduced echelon
 *    form of the basis, orthonormalised in order; each vector's first
 *    nonzero entry positive), the remaining columns are 0; null may be NULL
 *    (ldn >= 1 then);
 *  7 loading[np] (may be NULL); 8 comb_loading[nc] (may be NULL), the
 *    loading of each combination of igea_accel_combinations divided by its
 *    norm; 9 rank (numerical rank, cut max(n, np) eps s_1; METHODS 0.3).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENOMEM, IGEA_ELAPACK.
 */
IGEA_API int igea_accel_analyze(int model, int n, const double *theta_deg,
                                double *sv, double *null, int ldn,
                                double *loading, double *comb_loading,
                                int *rank);

/*
 * Fit a calibration: the linear model's observations and design (above),
 * then least squares (igea_regress_ls: minimum norm when rank-deficient) or
 * EBR (igea_regress_ebr, METHODS 4.3).
 *  1 model: IGEA_ACCEL_SINGLE or IGEA_ACCEL_DUAL;
 *  2 method: IGEA_ACCEL_LS or IGEA_ACCEL_EBR;
 *  3 n >= 1 positions (EBR needs n > rank and rank >= 3);
 *  4 theta_deg[n] head angles; 5 ya[n] A outputs in g;
 *  6 yb[n] B outputs in g (dual; ignored and may be NULL for single);
 *  7 prior_scale: np historical spreads tau_j > 0 for EBR (prior
 *    beta_j ~ N(0, lambda sigma^2 tau_j^2)) or NULL (isotropic); ignored
 *    for LS;
 *  8 rule: IGEA_REGRESS_EBR_SC, IGEA_REGRESS_EBR_MM or IGEA_REGRESS_EBR_ML2 (EBR; ignored for LS);
 *  9 lam_floor >= 0 (EBR; ignored for LS);
 * Outputs:
 * 10 coef[np] in the model's column order;
 * 11 sd[np] (may be NULL): LS sqrt(diag(sigma^2 pinv(A^T A))) (the spread
 *    of the minimum-norm estimate); EBR the posterior sd of
 *    igea_regress_ebr (a null direction keeps its prior variance). For a
 *    coefficient flagged IGEA_ACCEL_PRIOR neither is an uncertainty of the
 *    coefficient itself, which the data do not determine;
 * 12 flag[np] (may be NULL): IGEA_ACCEL_DATA or IGEA_ACCEL_PRIOR;
 * 13 comb[nc] (may be NULL): the estimable combinations C^T coef;
 * 14 comb_sd[nc] (may be NULL): their standard deviations (LS:
 *    sqrt(sigma^2 c^T pinv(A^T A) c); EBR: sqrt(c^T Cov_post c), the
 *    posterior of METHODS 4.3 step 7); NaN for a combination that is not estimable with these
 *    positions (comb_loading > IGEA_ACCEL_LOADING_TOL); sd and comb_sd
 *    are NaN when n == rank (no residual to estimate sigma from);
 * 15 info[IGEA_ACCEL_INFO_LEN] (may be NULL).
 * Every other output is finite on success (else IGEA_EOVERFLOW).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE (a prior scale <= 0),
 * IGEA_ERANGE (a prior scale below IGEA_SIGMA_MIN), IGEA_ERANK,
 * IGEA_EDOMAIN (EBR without residual), IGEA_ENOCONV, IGEA_EOVERFLOW,
 * IGEA_ENOMEM, IGEA_ELAPACK (the last six from igea_regress_*).
 */
IGEA_API int igea_accel_fit(int model, int method, int n,
                            const double *theta_deg, const double *ya,
                            const double *yb, const double *prior_scale,
                            int rule, double lam_floor, double *coef,
                            double *sd, int *flag, double *comb,
                            double *comb_sd, double *info);

/*
 * Gauss-Newton refinement of a dual calibration on the exact model (1)-(2)
 * of METHODS 4.2, for mg-level biases where the first-order g^2 model's
 * neglected terms (~ coefficient^2) matter [D]. Unknowns: the coefficients
 * and the actual angle phi_n of every position (head error and installation
 * angle included), fitted to both outputs. The null-space part of coef0
 * (with respect to the linear design) is kept fixed: only the estimable
 * directions and the angles move, so that the refinement never invents
 * information the data do not hold.
 *  1 n >= 1 positions (2 n > n + rank for a residual); 2 theta_deg[n];
 *  3 ya[n], 4 yb[n] outputs in g; 5 coef0[9] start (e.g. an LS or EBR fit);
 *  6 max_iter >= 1; 7 tol > 0: stop when the max-norm of a step (g, rad)
 *    is <= tol;
 * Outputs: 8 coef[9]; 9 sd[9] (may be NULL): from the final Jacobian, 0 in
 * the fixed null directions; 10 phi_deg[n] (may be NULL): fitted angles;
 * 11 info (may be NULL): rank, sigma (per output), -, rms, nobs = 2n,
 * dof, iterations, last step.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENOCONV (no convergence within
 * max_iter), IGEA_ENOMEM, IGEA_ELAPACK.
 */
IGEA_API int igea_accel_refine(int n, const double *theta_deg,
                               const double *ya, const double *yb,
                               const double *coef0, int max_iter, double tol,
                               double *coef, double *sd, double *phi_deg,
                               double *info);

/*
 * Simulate one calibration of an orthogonal pair with the exact models
 * (1)-(2): phi = theta + delta_theta + delta0, delta_theta ~ N(0,
 * head_sd^2) drawn per reading, y_A = eq. (1) at phi, y_B = eq. (2) at
 * phi + eta, plus independent N(0, noise_sd^2) noise on each output.
 * Random numbers from a GSL Mersenne twister (gsl_rng_mt19937) seeded with
 * seed; the same seed gives the same calibration on every platform.
 *  1 n >= 1 readings; 2 theta_deg[n]; 3 truth[IGEA_ACCEL_NP_SIM] (the 9 dual
 *  coefficients, then delta0 in rad); 4 head_sd >= 0 in rad (1 arcsec =
 *  4.8481e-6 rad); 5 noise_sd >= 0 in g; 6 seed >= 0;
 *  7 ya[n], 8 yb[n] outputs in g (yb may be NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENOMEM.
 */
IGEA_API int igea_accel_simulate(int n, const double *theta_deg,
                                 const double *truth, double head_sd,
                                 double noise_sd, int seed, double *ya,
                                 double *yb);

/* ---------------------------------------------------------------------- */
/* Applying a calibration, hysteresis, and the joint model. */

/*
 * Apply a calibration to raw outputs: the outputs are converted to g with
 * the nominal scale factors (y = raw / scale, as igea_accel_to_g), and the
 * calibrated model is inverted for the acceleration [D].
 *  Single model (coef[5] = K0, k1, delta0, K2, Kix of igea_accel_fit):
 *    y_A = K0 + (1 + k1) u + delta0 v + K2 u^2 + Kix u v
 *  is solved for u, the acceleration (g) along the reference input axis,
 *  given v, the acceleration along the reference cross axis (cross[n], g;
 *  NULL: v = 0, which leaves the delta0 and Kix terms uncompensated).
 *  Dual model (coef[9] in the dual column order; delta0 is not part of
 *  the pair's model): the exact models (1)-(2) of METHODS 4.2,
 *    y_A = KA0 + (1 + kA1) u + KA2 u^2 + KAix u v,
 *    y_B = KB0 + (1 + kB1) b + KB2 b^2 - KBix b w,
 *    b = v cos(eta) - u sin(eta), w = u cos(eta) + v sin(eta),
 *  are solved together for (u, v), the in-plane acceleration along A's
 *  input axis and along the perpendicular towards B (at theta:
 *  u = sin(phi), v = cos(phi)).
 *  Newton's method from u = y_A, v = y_B (single: v given), at most 50
 *  steps, until a step is <= 4 eps max(1, |u|, |v|).
 *  1 model; 2 n >= 1; 3 raw_a[n] A outputs; 4 raw_b[n] B outputs (dual;
 *  ignored and may be NULL for single); 5 scale_a, 6 scale_b: nominal
 *  scale factors (output units per g, finite, != 0; 1 for outputs in g;
 *  scale_b ignored for single); 7 coef[np]; 8 cross[n] (single; may be
 *  NULL; ignored for dual);
 * Outputs: 9 u[n]; 10 v[n] (dual; may be NULL; ignored for single).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENOCONV (no solution near the
 * outputs: a singular Jacobian or no convergence, e.g. K2 so large that the
 * quadratic has no real root there).
 */
IGEA_API int igea_accel_apply(int model, int n, const double *raw_a,
                              const double *raw_b, double scale_a,
                              double scale_b, const double *coef,
                              const double *cross, double *u, double *v);

/* Indices into the test[IGEA_ACCEL_HYST_LEN] output of
 * igea_accel_hysteresis (doubles). */
#define IGEA_ACCEL_HYST_F 0     /* F = sum_k (d_k / sd_k)^2 / P */
#define IGEA_ACCEL_HYST_DF1 1   /* P, the positions */
#define IGEA_ACCEL_HYST_DF2 2   /* N - 2P, dof of the pooled variance */
#define IGEA_ACCEL_HYST_P 3     /* p-value, Q_F(F; P, N - 2P) */
#define IGEA_ACCEL_HYST_SIGMA 4 /* pooled within-position sd s_p (output units) */
#define IGEA_ACCEL_HYST_LEN 5

/*
 * Hysteresis: clockwise minus counter-clockwise mean per position, with its
 * sd from the repeated readings, and the test of zero hysteresis [D].
 * Readings are grouped into positions as igea_accel_merge does; within
 * each position the clockwise and counter-clockwise readings form two
 * cells. d_k = mean_cw - mean_ccw; the within-cell variance is pooled over
 * all cells, s_p^2 = sum (y - cell mean)^2 / (N - 2P), and
 * sd_k = s_p sqrt(1/n_cw + 1/n_ccw). Test: F = sum_k (d_k / sd_k)^2 / P,
 * referred to F(P, N - 2P) (exact for independent normal readings of equal
 * variance; P F -> chi-square(P) as N - 2P grows).
 *  1 nrows >= 1; 2 angle_deg[nrows]; 3 dir[nrows]: > 0 clockwise, < 0
 *  counter-clockwise, 0 invalid; NULL: from the row order, the
 *  convention of the seed's runs (angles increase counter-clockwise):
 *  rows within tol_deg of the previous row (modulo 360) form a block; a
 *  block takes the direction of the step into it (the shorter way round;
 *  the first block: of the step out of it), and a block where the
 *  direction reverses (the 360 deg turnaround) is split, its first
 *  ceil(len/2) rows going with the incoming run, the rest with the next;
 *  4 y[nrows] outputs (any unit); 5 tol_deg: 0 <= tol_deg < 45;
 * Outputs (capacity nrows each; positions in ascending angle):
 *  6 theta_deg, 7 diff, 8 diff_sd (may be NULL), 9 n_cw (may be NULL),
 *  10 n_ccw (may be NULL), 11 npos, 12 test[IGEA_ACCEL_HYST_LEN] (may be
 *  NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EDOMAIN (a position without
 * readings in both directions, no change of angle with dir NULL, or
 * N - 2P < 1: no repeated readings to estimate the sd from), IGEA_ENOMEM.
 */
IGEA_API int igea_accel_hysteresis(int nrows, const double *angle_deg,
                                   const int *dir, const double *y,
                                   double tol_deg, double *theta_deg,
                                   double *diff, double *diff_sd, int *n_cw,
                                   int *n_ccw, int *npos, double *test);

/* Coefficients of the joint model: the 9 dual coefficients, then delta0. */
#define IGEA_ACCEL_NP_JOINT 10
/* Indices into comp_sd[IGEA_ACCEL_JOINT_NCOMP] of igea_accel_joint. */
#define IGEA_ACCEL_JOINT_SD_RADIAL 0  /* sd of the g^2 (radial) equation */
#define IGEA_ACCEL_JOINT_SD_ANGLE 1   /* sd of the tangential equation */
#define IGEA_ACCEL_JOINT_NCOMP 2

/*
 * Joint fit of an orthogonal pair [D]: single model A, single model B and
 * the dual g^2 equation stacked, with the head-angle error of each position
 * as a random nuisance effect (docs/accel.md, "The joint model"). Per
 * position, with r_A = y_A - s, r_B = y_B - c, the readings are rotated
 * into the radial equation (the g^2 observation (y_A^2 + y_B^2 - 1)/2,
 * free of head errors, noise variance sigma^2) and the tangential
 * equation z = c r_A - s r_B (the head error enters as itself: variance
 * sigma^2 + sigma_head^2); the two are independent. The variances are
 * estimated from each equation's own least-squares residual, and the
 * stacked weighted least squares has rank 10 for 7 or more distinct
 * equispaced positions: every coefficient, K2 included, is determined by
 * the data.
 *  1 n >= 1 positions (n >= 10 and a residual in each equation); 2
 *  theta_deg[n]; 3 ya[n], 4 yb[n] outputs in g (one per position, e.g.
 *  igea_accel_merge);
 * Outputs: 5 coef[10] (dual order, then delta0 in rad); 6 sd[10] (may be
 * NULL): sqrt(diag((A^T W A)^-1)) with the estimated weights; 7 cov
 * (10 x 10, may be NULL), 8 ldc >= 10 (>= 1 when cov is NULL); 9
 * comp_sd[IGEA_ACCEL_JOINT_NCOMP] (may be NULL): the two equations' sds
 * (g); 10 comb[7] (may be NULL), 11 comb_sd[7] (may be NULL): the estimable
 * combinations of igea_accel_combinations and their sds sqrt(c^T cov c),
 * for comparison with the dual fit; 12 info (may be NULL): rank, sigma =
 * sqrt(weighted RSS / dof), -, rms (weighted), nobs = 2n, dof = 2n - rank.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ERANK (rank < 10), IGEA_EDOMAIN (an
 * equation without residual, or a zero residual variance), IGEA_EOVERFLOW,
 * IGEA_ENOMEM, IGEA_ELAPACK.
 */
IGEA_API int igea_accel_joint(int n, const double *theta_deg,
                              const double *ya, const double *yb,
                              double *coef, double *sd, double *cov, int ldc,
                              double *comp_sd, double *comb, double *comb_sd,
                              double *info);

/* ---------------------------------------------------------------------- */
/* The IEEE Std 1293 single-axis model and the design criterion. */

/* The model for igea_accel_ieee_fit and igea_accel_criterion (not a model
 * of igea_accel_fit; IGEA_CHOICE_ACCEL_CRIT_MODEL: single dual ieee). */
#define IGEA_ACCEL_IEEE 2
/* The harmonic (Fourier) method of IEEE Std 1293's tumble-test annex
 * (igea_accel_ieee_fit; IGEA_CHOICE_ACCEL_IEEE_METHOD: ls harmonic). */
#define IGEA_ACCEL_HARMONIC 3

/* Coefficients of the IEEE Std 1293 model, in this order: the output is
 *   E = K1 (K0 + a_i + K2 a_i^2 + K3 a_i^3 + Kip a_i a_p + Kio a_i a_o
 *           + delta_o a_p - delta_p a_o)
 * (a_i, a_p, a_o: acceleration along the input, pendulous and output axes,
 * in g; K1 in output units per g; K0 g; K2 g/g^2; K3 g/g^3; Kip, Kio
 * g/g^2; delta_o, delta_p rad: the input axis's misalignment towards PA
 * and OA). */
#define IGEA_ACCEL_NP_IEEE 8
#define IGEA_ACCEL_IEEE_K0 0
#define IGEA_ACCEL_IEEE_K1 1
#define IGEA_ACCEL_IEEE_K2 2
#define IGEA_ACCEL_IEEE_K3 3
#define IGEA_ACCEL_IEEE_KIP 4
#define IGEA_ACCEL_IEEE_KIO 5
#define IGEA_ACCEL_IEEE_DO 6
#define IGEA_ACCEL_IEEE_DP 7

/* The two standard tumble orientations (plane[] of igea_accel_ieee_fit):
 * at head angle theta, a_i = sin theta and
 *  IA-PA plane (head axis along OA): a_p = cos theta, a_o = 0;
 *  IA-OA plane (head axis along PA): a_o = cos theta, a_p = 0. */
#define IGEA_ACCEL_PLANE_IAPA 0
#define IGEA_ACCEL_PLANE_IAOA 1

/*
 * Fit the IEEE Std 1293 model to tumble readings in one or both standard
 * planes (docs/accel.md, "The IEEE Std 1293 model") [D]. The model is
 * linear in b = K1 (K0, 1, K2, K3, Kip, Kio, delta_o, -delta_p), design
 * row [1, s, s^2, s^3, sc, sc, c, c] with the sc and c columns of the
 * other plane zero (s = sin theta, c = cos theta); b is estimated, then
 * K1 = b_1, K_j = +-b_j / b_1, covariance J Cov(b) J^T (J = dK/db).
 *  1 method: IGEA_ACCEL_LS (least squares, igea_regress_ls, minimum norm
 *    when rank-deficient) or IGEA_ACCEL_HARMONIC (the Fourier
 *    coefficients B0, S1, C1, S2, C2, S3 of each plane, pooled over the
 *    planes by their number of positions; needs, in each plane with
 *    readings, one reading per position at N >= 7 distinct equispaced
 *    positions; then it equals least squares);
 *  2 n >= 1 readings; 3 theta_deg[n] head angles; 4 plane[n]:
 *    IGEA_ACCEL_PLANE_IAPA or IGEA_ACCEL_PLANE_IAOA per reading;
 *  5 e[n] outputs (any unit; K1 comes out in that unit per g);
 * Outputs: 6 coef[8] in the order above; 7 sd[8] (may be NULL); 8 cov
 *  (8 x 8, may be NULL), 9 ldc >= 8 (>= 1 when cov is NULL): delta-method
 *  covariance with sigma^2 = RSS / (n - rank); sd and cov NaN when
 *  n == rank; 10 flag[8] (may be NULL): IGEA_ACCEL_DATA, or
 *  IGEA_ACCEL_PRIOR for a coefficient the schedule does not determine
 *  (its loading on the design's null space > IGEA_ACCEL_LOADING_TOL; its
 *  value is the minimum-norm convention's, e.g. 0 for Kio and delta_p
 *  without IA-OA readings); 11 info[IGEA_ACCEL_INFO_LEN] (may be NULL):
 *  rank, sigma (output units), -, rms, nobs = n, dof = n - rank.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EDOMAIN (harmonic: a plane not
 * equispaced or with fewer than 7 positions; K1 estimated as 0),
 * IGEA_EOVERFLOW, IGEA_ENOMEM, IGEA_ELAPACK.
 */
IGEA_API int igea_accel_ieee_fit(int method, int n, const double *theta_deg,
                                 const int *plane, const double *e, double *coef,
                                 double *sd, double *cov, int ldc, int *flag,
                                 double *info);

/*
 * D-criterion of a position schedule [D]: the information matrix
 * M = A^T W A of the model's linear design for unit noise (sigma = 1),
 * normalised per reading, logdet = (1/r) sum_{i<r} log(lambda_i(M / n))
 * (r = rank; for a full-rank schedule (1/np) log det(M / n), the log of the
 * geometric-mean eigenvalue; a schedule of lower rank has det 0, and its
 * logdet is that of the estimable part only: compare ranks first), and
 * the per-reading variance factors varfac_j = n [M^+]_jj, so that
 * sd_j = sigma sqrt(varfac_j / n).
 *  1 model: IGEA_ACCEL_SINGLE (5), IGEA_ACCEL_DUAL (9), IGEA_ACCEL_IEEE (8);
 *  2 method: IGEA_ACCEL_LS or IGEA_ACCEL_EBR (the data's information);
 *    IGEA_ACCEL_JOINT (dual only: the radial rows plus the tangential rows
 *    weighted 1 / (1 + head_ratio^2), 10 coefficients with delta0);
 *    IGEA_ACCEL_HARMONIC (IEEE only; the same information as LS);
 *  3 n >= 1 readings; 4 theta_deg[n]; 5 plane[n] (IEEE; ignored and may
 *    be NULL otherwise);
 *  6 head_ratio >= 0: sigma_head / sigma (joint; ignored otherwise);
 * Outputs: 7 logdet; 8 varfac[np] (may be NULL); for a coefficient flagged
 *  IGEA_ACCEL_PRIOR it is the minimum-norm spread, not an uncertainty;
 *  9 flag[np] (may be NULL): IGEA_ACCEL_DATA / IGEA_ACCEL_PRIOR as in
 *  igea_accel_fit; 10 rank.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ERANK (rank 0), IGEA_EOVERFLOW,
 * IGEA_ENOMEM, IGEA_ELAPACK.
 */
IGEA_API int igea_accel_criterion(int model, int method, int n, const double *theta_deg,
                                  const int *plane, double head_ratio, double *logdet,
                                  double *varfac, int *flag, int *rank);

/* ---------------------------------------------------------------------- */
/* Priors from the calibration history. */

/* Indices into info[IGEA_ACCEL_HIST_LEN] of igea_accel_history. */
#define IGEA_ACCEL_HIST_LOGLIK 0 /* restricted log-likelihood at the estimate
                                    (without the constant -(m - 1) p log(2 pi) / 2) */
#define IGEA_ACCEL_HIST_ITER 1   /* EM iterations */
#define IGEA_ACCEL_HIST_LEN 2

/*
 * Prior of an instrument type from the calibration history [D]: m earlier
 * calibrations of instruments of the type, estimates b_i with covariances
 * V_i, under the random-effects model
 *     b_i = beta0 + u_i + e_i,  u_i ~ N(0, Sigma),  e_i ~ N(0, V_i),
 * Sigma = diag(tau^2) (instrument-to-instrument spread), fitted by
 * restricted maximum likelihood (REML; beta0 integrated out) with the EM
 * algorithm (docs/accel.md, "Priors from the calibration history"). Every
 * coefficient must be determined by each calibration (e.g. joint fits, or
 * single-model fits): a minimum-norm value of a coefficient flagged
 * IGEA_ACCEL_PRIOR is not an estimate of it.
 *  1 m >= 2 calibrations; 2 p: 1 <= p <= 10 coefficients;
 *  3 b (p x m, column i = calibration i), 4 ldb >= p;
 *  5 V: m covariance blocks, block i at V + i ldv p (p x p, column-major,
 *    ld ldv), each symmetric positive semi-definite; 6 ldv >= p;
 *  7 max_iter >= 1 EM iterations (e.g. 20000); 8 tol in (0, 1): stop when
 *    every |change of tau_j| <= tol sqrt(mean_i V_i,jj), or when an
 *    iteration raises the restricted log-likelihood by less than tol (EM
 *    creeps towards an estimate tau_j = 0 on the boundary) (e.g. 1e-8);
 * Outputs: 9 beta0[p] (the generalised-least-squares mean at the estimate);
 *  10 tau[p] (prior sds, sqrt of Sigma's diagonal); 11 prior_cov (p x p,
 *  may be NULL), 12 ldc >= p (>= 1 when prior_cov is NULL): the prior for
 *  a new instrument of the type, Sigma + Cov(beta0 hat), Cov(beta0 hat) =
 *  (sum_i (Sigma + V_i)^-1)^-1; 13 info[IGEA_ACCEL_HIST_LEN] (may be NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ESINGULAR (Sigma + V_i not positive
 * definite), IGEA_ENOCONV (max_iter reached), IGEA_EOVERFLOW, IGEA_ENOMEM.
 */
IGEA_API int igea_accel_history(int m, int p, const double *b, int ldb, const double *V,
                                int ldv, int max_iter, double tol, double *beta0, double *tau,
                                double *prior_cov, int ldc, double *info);

/*
 * The same with a full (p x p) Sigma: the EM's M-step keeps the whole
 * mean of uhat_i uhat_i^T + C_i (docs/accel.md) [D]. Arguments 1-9 as
 * igea_accel_history; outputs 10 sigma_u (p x p, Sigma, symmetric), 11 lds
 * >= p; 12 prior_cov (p x p, may be NULL): Sigma + Cov(beta0 hat), 13 ldc
 * >= p (>= 1 when prior_cov is NULL); 14 info[IGEA_ACCEL_HIST_LEN] (may be
 * NULL). The stopping rule compares every entry's change with tol
 * sqrt(mean V_jj mean V_kk) (the diagonal's sds as in igea_accel_history).
 * Returns as igea_accel_history.
 */
IGEA_API int igea_accel_history_full(int m, int p, const double *b, int ldb, const double *V,
                                     int ldv, int max_iter, double tol, double *beta0,
                                     double *sigma_u, int lds, double *prior_cov, int ldc,
                                     double *info);

/*
 * A calibration fit with a normal prior N(prior_mean, prior_cov) on the
 * coefficients (e.g. from igea_accel_history) [D]: sigma^2 = RSS / (n - r)
 * of the least-squares fit, then the posterior of igea_regress_bayes,
 *     cov = (A^T A / sigma^2 + P^-1)^-1,  coef = cov (A^T y / sigma^2 + P^-1 mu).
 * The prior fixes the directions the data do not determine (the dual
 * model's null space) and shrinks the others.
 *  1 model: IGEA_ACCEL_SINGLE or IGEA_ACCEL_DUAL; 2 n >= 1 positions (n >
 *  rank); 3 theta_deg[n]; 4 ya[n]; 5 yb[n] (dual; ignored and may be NULL
 *  for single); 6 prior_mean[np]; 7 prior_cov (np x np, positive definite,
 *  lower triangle read), 8 ldp >= np;
 * Outputs: 9 coef[np]; 10 sd[np] (may be NULL): posterior sds; 11 cov
 *  (np x np, may be NULL), 12 ldc >= np (>= 1 when cov is NULL);
 *  13 info[IGEA_ACCEL_INFO_LEN] (may be NULL): rank (of the design),
 *  sigma (least squares), -, rms of the posterior residual, nobs, dof.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EDOMAIN (no residual to estimate
 * sigma), IGEA_ESINGULAR (prior_cov not positive definite),
 * IGEA_EOVERFLOW, IGEA_ENOMEM, IGEA_ELAPACK.
 */
IGEA_API int igea_accel_fit_prior(int model, int n, const double *theta_deg,
                                  const double *ya, const double *yb,
                                  const double *prior_mean, const double *prior_cov, int ldp,
                                  double *coef, double *sd, double *cov, int ldc,
                                  double *info);

/* ---------------------------------------------------------------------- */
/* The uncertainty of the estimated prior (docs/accel.md, "The uncertainty
 * of the estimated prior"). The variance parameters theta of Sigma: its
 * diagonal Sigma_00, ..., Sigma_(p-1)(p-1) (q = p) for a diagonal Sigma,
 * or its lower triangle by columns Sigma_00, Sigma_10, ..., Sigma_(p-1)0,
 * Sigma_11, ... (q = p (p + 1) / 2) for a full one. */

/*
 * The expected REML information of theta [D]:
 *     I_ab = (1/2) tr(P_R dOmega/dtheta_a P_R dOmega/dtheta_b),
 * Omega = blockdiag(Sigma + V_i), P_R = Omega^-1 - Omega^-1 X (X^T Omega^-1
 * X)^-1 X^T Omega^-1 (X the stacked identities of beta0); I^-1 is the
 * large-sample covariance of the REML estimate (its sds: sqrt(diag I^-1)).
 *  1 m >= 2 calibrations; 2 p: 1 <= p <= 10; 3 b (p x m), 4 ldb >= p; 5 V
 *  (m blocks p x p, as igea_accel_history), 6 ldv >= p; 7 sigma_u (p x p,
 *  ld lds): Sigma (only its diagonal read when full = 0, its lower
 *  triangle when full = 1), 8 lds >= p; 9 full: 0 diagonal, 1 full;
 * Output: 10 info (q x q, symmetric), 11 ldi >= q.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EDOMAIN (a negative variance on
 * Sigma's diagonal), IGEA_ESINGULAR (Sigma + V_i not positive definite),
 * IGEA_EOVERFLOW, IGEA_ENOMEM.
 */
IGEA_API int igea_accel_history_information(int m, int p, const double *b, int ldb,
                                            const double *V, int ldv, const double *sigma_u,
                                            int lds, int full, double *info, int ldi);

/* Indices into info[IGEA_ACCEL_HFIT_LEN] of igea_accel_fit_history: slots
 * 0..7 as IGEA_ACCEL_INFO_* (RANK, SIGMA, RMS, NOBS, DOF of the new
 * calibration's least squares; LAMBDA, ITER, STEP 0), then: */
#define IGEA_ACCEL_HFIT_NTHETA 8 /* q, the variance parameters of Sigma */
#define IGEA_ACCEL_HFIT_CAPPED 9 /* coefficients whose bias factor f_j was
                                    raised to its floor 0.2 (the history is
                                    too short for their correction) */
#define IGEA_ACCEL_HFIT_LEN 10

/*
 * A calibration fitted with the prior from the calibration history, with
 * the uncertainty of that estimated prior [D]. The posterior mean coef and
 * the plug-in covariance C are those of igea_accel_fit_prior with the prior
 * N(beta0, Sigma + Q), beta0 = Q sum_i W_i b_i, Q = (sum_i W_i)^-1,
 * W_i = (Sigma + V_i)^-1 (Sigma the REML estimate of igea_accel_history
 * or igea_accel_history_full, whose prior_cov is Sigma + Q); C treats
 * Sigma and the calibration's residual variance s2 (on n - rank degrees of
 * freedom) as known. The reported mean squared error adds what their
 * estimation costs, per coefficient j:
 *     mse_jj = (C_jj + Lambda_jj) / f_j,   f_j = max(1 + B_jj / C_jj, 0.2),
 * Lambda = sum_ab Cov(theta)_ab (dcoef/dtheta_a)(dcoef/dtheta_b)^T (the
 * observed derivatives; Cov(theta) = I^-1 of
 * igea_accel_history_information, and 2 s2^2 / (n - rank) for s2), B the
 * second-order bias (1/2) sum_ab Cov_ab d2C/dtheta_a dtheta_b of the plug-in
 * C (divided out: exact for a Wishart conditional variance); dof_j the
 * Satterthwaite degrees of freedom 2 mse_jj^2 / Var(mse_jj), Var by the
 * delta method (central differences of mse_jj in theta and s2); the
 * interval coef_j -+ t_{dof_j, 1 - alpha/2} sqrt(mse_jj).
 *  1 model: IGEA_ACCEL_SINGLE or IGEA_ACCEL_DUAL; 2 n >= 1 positions (n >
 *  rank); 3 theta_deg[n]; 4 ya[n]; 5 yb[n] (dual; ignored and may be NULL
 *  for single); 6 m >= 2 earlier calibrations; 7 b (np x m), 8 ldb >= np;
 *  9 V (m blocks np x np, as igea_accel_history), 10 ldv >= np; 11
 *  sigma_u (np x np): the REML Sigma (only the diagonal read when full =
 *  0, the lower triangle when full = 1), 12 lds >= np; 13 full: 0 or 1;
 *  14 alpha in (0, 1): intervals at 1 - alpha;
 * Outputs: 15 coef[np]; 16 sd[np] (may be NULL): sqrt(mse_jj); 17
 *  sd_plugin[np] (may be NULL): sqrt(C_jj), the sd of
 *  igea_accel_fit_prior; 18 dof[np] (may be NULL), in [1, 1e5]; 19
 *  ci[2 np] (may be NULL): lower limits, then upper limits; 20 cov (np x
 *  np, may be NULL): (C + Lambda)_jk / sqrt(f_j f_k); 21 ldc >= np (>= 1
 *  when cov is NULL); 22 info[IGEA_ACCEL_HFIT_LEN] (may be NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EDOMAIN (no residual to estimate s2
 * from, or a negative variance in sigma_u), IGEA_ESINGULAR (Sigma + V_i,
 * Sigma + Q or the information not positive definite), IGEA_EOVERFLOW,
 * IGEA_ENOMEM, IGEA_ELAPACK.
 */
IGEA_API int igea_accel_fit_history(int model, int n, const double *theta_deg,
                                    const double *ya, const double *yb, int m, const double *b,
                                    int ldb, const double *V, int ldv, const double *sigma_u,
                                    int lds, int full, double alpha, double *coef, double *sd,
                                    double *sd_plugin, double *dof, double *ci, double *cov,
                                    int ldc, double *info);

#ifdef __cplusplus
}
#endif
#endif
