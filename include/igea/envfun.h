/*
 * igea/envfun.h - environment-function matrices S from a trajectory and an
 * instrument error-term catalogue (METHODS 5).
 *
 * The velocity environment function of error coefficient X_j is S_j(t) =
 * d dW(t) / d X_j (a 3-vector in the launch-inertial frame a): the
 * first-order change of the apparent velocity W = int f^a dt that one unit
 * of X_j causes. Stacked over tracking epochs (rows epoch-major x, y, z)
 * and multiplied by the 1-sigma spec of each term it is the S of seed 000
 * (igea_eqerr_run).
 *
 *  - Strapdown (METHODS 5.2): instrument errors in body axes. Accelerometer
 *    term u^b: S = int C u^b dt. Gyro term u^b: Phi_u = int C u^b dt,
 *    S = int Phi_u x f^a dt. Initial attitude phi0 = e_k: S = W x e_k.
 *  - Platform (METHODS 5.3): instrument errors along platform (= a) axes.
 *    Accelerometer term: S = int u dt. Gyro drift eps: alpha = int eps dt,
 *    S = int f^a x alpha dt. Initial alignment alpha0 = e_k: S = W x e_k.
 *
 * Integration: trapezoid rule at the telemetry rate over the samples
 * (METHODS 5.5: telemetry is never differentiated), then linear
 * interpolation to the tracking epochs. Position functions are the time
 * integrals of the velocity functions, optionally with the point-mass
 * gravity-gradient coupling of METHODS 5.4.
 *
 * Trajectory array (column-major nsamp x 11, leading dimension ldt), one
 * row per telemetry sample, the columns of the trajectory file:
 *   0 t [s] (strictly increasing), 1-3 specific force f [m/s^2], 4-6 body
 *   angular rate w [rad/s], 7-10 attitude quaternion q0 q1 q2 q3 (scalar
 *   first, body -> launch-inertial; normalised here).
 * Strapdown: f and w in body axes. Platform: f in launch-inertial axes;
 * w and q are ignored (need only be finite).
 *
 * Error terms are int codes IGEA_ENVFUN_TERM_*. Their stable names (acc_bias_x,
 * gyro_g_z, ...), units, default specs and the default term sets are kept
 * here only (igea_envfun_term_name ... igea_envfun_default_terms below);
 * the driver, the Python package and docs/terms.md read them.
 */
#ifndef IGEA_ENVFUN_H
#define IGEA_ENVFUN_H

#include "igea/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* System kinds. */
#define IGEA_ENVFUN_STRAPDOWN 0
#define IGEA_ENVFUN_PLATFORM 1

/* What the rows hold (argument 11 of igea_envfun_compute). */
#define IGEA_ENVFUN_VELOCITY 0   /* velocity functions (METHODS 5.2/5.3) */
#define IGEA_ENVFUN_POSITION 1   /* their time integrals (G = 0) */
#define IGEA_ENVFUN_VELOCITY_G 2 /* velocity with gravity-gradient coupling */
#define IGEA_ENVFUN_POSITION_G 3 /* position with gravity-gradient coupling */

/* Columns of the trajectory array. */
#define IGEA_ENVFUN_TRAJ_COLS 11

/* Error-term codes. Axis offsets: +0 x, +1 y, +2 z. "both": valid for both
 * systems; "sd": strapdown only; "pf": platform only. Units of one
 * coefficient: SI (m/s^2, rad/s, rad, dimensionless). */
#define IGEA_ENVFUN_TERM_ACC_BIAS_X 0   /* both: accel bias K0j, 1 m/s^2 */
#define IGEA_ENVFUN_TERM_ACC_SCALE_X 3  /* both: accel scale K1j, u = e_j f_j */
#define IGEA_ENVFUN_TERM_ACC_SQ_X 6     /* both: accel 2nd order K2j, e_j f_j^2 */
#define IGEA_ENVFUN_TERM_ACC_MIS_XY 9   /* both: accel x senses f_y, e_x f_y */
#define IGEA_ENVFUN_TERM_ACC_MIS_XZ 10  /* both: e_x f_z */
#define IGEA_ENVFUN_TERM_ACC_MIS_YX 11  /* both: e_y f_x */
#define IGEA_ENVFUN_TERM_ACC_MIS_YZ 12  /* both: e_y f_z */
#define IGEA_ENVFUN_TERM_ACC_MIS_ZX 13  /* both: e_z f_x */
#define IGEA_ENVFUN_TERM_ACC_MIS_ZY 14  /* both: e_z f_y */
#define IGEA_ENVFUN_TERM_GYRO_BIAS_X 15 /* both: constant drift D0j, 1 rad/s */
#define IGEA_ENVFUN_TERM_GYRO_G_X 18    /* sd: drift e_j f_j (rad/s per m/s^2) */
#define IGEA_ENVFUN_TERM_GYRO_SCALE_X 21 /* sd: gyro scale factor, e_j w_j */
#define IGEA_ENVFUN_TERM_ATT0_X 24      /* sd: initial attitude error phi0 = e_k */
#define IGEA_ENVFUN_TERM_GYRO_GI_X 27   /* pf: drift e_j f_I(j) (input axis) */
#define IGEA_ENVFUN_TERM_GYRO_GS_X 30   /* pf: drift e_j f_S(j) (spin axis) */
#define IGEA_ENVFUN_TERM_ALIGN0_X 33    /* pf: initial alignment alpha0 = e_k */
#define IGEA_ENVFUN_TERM_COUNT 36       /* the first catalogue: codes 0 .. 35 (the
                                         * size of igea_sim_nonlinear's err);
                                         * code 36 is never a term */
/* The extended catalogue (codes 37 ..; see igea_envfun_term_count). Gyro j's
 * input, spin and output axes I(j), S(j), O(j): platform from `axes`
 * (O(j) the axis that is neither), strapdown body axes j, j+1, j+2 mod 3. */
#define IGEA_ENVFUN_TERM_GYRO_GO_X 37   /* both: drift e_j f_O(j) (output axis) */
#define IGEA_ENVFUN_TERM_GYRO_GII_X 40  /* both: drift e_j f_I^2 (rad/s/(m/s^2)^2) */
#define IGEA_ENVFUN_TERM_GYRO_GSS_X 43  /* both: drift e_j f_S^2 */
#define IGEA_ENVFUN_TERM_GYRO_GOO_X 46  /* both: drift e_j f_O^2 */
#define IGEA_ENVFUN_TERM_GYRO_GIS_X 49  /* both: drift e_j f_I f_S */
#define IGEA_ENVFUN_TERM_GYRO_GIO_X 52  /* both: drift e_j f_I f_O */
#define IGEA_ENVFUN_TERM_GYRO_GSO_X 55  /* both: drift e_j f_S f_O */
#define IGEA_ENVFUN_TERM_GYRO_GSPIN_X 58 /* sd: drift e_j f_S(j) (gyro_gspin_*) */
#define IGEA_ENVFUN_TERM_ACC_CUBE_X 61  /* both: accel 3rd order K3j, e_j f_j^3 */
#define IGEA_ENVFUN_TERM_ACC_ASYM_X 64  /* both: scale asymmetry, e_j |f_j| */
#define IGEA_ENVFUN_TERM_ACC_CROSS_XY 67 /* both: cross-coupling e_j f_j f_k, order
                                         * xy xz yx yz zx zy as ACC_MIS */
#define IGEA_ENVFUN_TERM_ACC_XSQ_XY 73  /* both: cross-axis square e_j f_k^2, same order */
#define IGEA_ENVFUN_TERM_ACC_XPROD_X 79 /* both: e_j f_k f_l (k, l the other axes) */
#define IGEA_ENVFUN_TERM_POS0_X 82      /* both: launch point error downrange (m) */
#define IGEA_ENVFUN_TERM_POS0_Z 83      /* both: launch point error cross-range (m) */
#define IGEA_ENVFUN_TERM_LEVER_X 84     /* both: lever arm IMU -> tracked point, body (m) */
#define IGEA_ENVFUN_TERM_SIZE_XX 87     /* sd: accel j displaced along body axis k
                                         * (size effect, m), order xx xy xz yx .. zz */
#define IGEA_ENVFUN_TERM_END 96         /* the codes above are < 96 (fixed: codes a
                                         * later version adds are bounded by
                                         * igea_envfun_term_count()) */

/*
 * 1 if term code `term` is valid for system kind `system`, else 0
 * (also 0 for an unknown system or code).
 */
IGEA_API int igea_envfun_term_valid(int system, int term);

/*
 * The term catalogue (docs/terms.md is generated from these functions).
 *
 * igea_envfun_term_name: the stable name of term code `term` (acc_bias_x,
 * gyro_g_z, ...), a static string; "" for an unknown code, never NULL.
 */
IGEA_API const char *igea_envfun_term_name(int term);

/*
 * igea_envfun_term_unit: the SI unit of one coefficient of term code `term`,
 * a static string ("m/s^2", "rad/s", "rad/s/(m/s^2)", "1/(m/s^2)", "rad",
 * "-" for a dimensionless coefficient); "" for an unknown code, never NULL.
 */
IGEA_API const char *igea_envfun_term_unit(int term);

/*
 * igea_envfun_term_formula: the equation of term code `term`, a static
 * string: the unit error per unit coefficient ("u = e_j f_j^3" for an
 * accelerometer term, "eps = e_j f_I(j)" for a gyro rate error or platform
 * drift; j the first axis letter of the name, k the second) or the velocity
 * function itself ("S = W x e_j"); "" for an unknown code, never NULL.
 */
IGEA_API const char *igea_envfun_term_formula(int term);

/*
 * igea_envfun_term_code: the code of the term called `name` (exact,
 * case-sensitive) in the catalogue of system kind `system`.
 * Returns the code (>= 0), -1 (unknown system), -2 (name NULL, or not a term
 * of that system).
 */
IGEA_API int igea_envfun_term_code(int system, const char *name);

/*
 * igea_envfun_default_spec: the default 1-sigma spec of term code `term`
 * of system kind `system`, in the unit of igea_envfun_term_unit (1 mg for
 * accelerometer biases, 1e-4 for scale factors, misalignments and initial
 * attitude or alignment, 10 ug/g^2 for second-order terms, 0.5 deg/h for
 * gyro biases, 0.5 deg/h/g for g-sensitive drifts; the extended catalogue:
 * 0.5 deg/h/g^2 second-order drifts, 1 ug/g^3 K3, 2e-5 scale asymmetry,
 * 10 ug/g^2 cross-coupling terms, 10 m launch point, 0.1 m lever arm,
 * 0.01 m size effect).
 * Arguments: 1 system, 2 term (valid for the system), 3 spec (output).
 * Returns 0, -i (spec untouched).
 */
IGEA_API int igea_envfun_default_spec(int system, int term, double *spec);

/* Terms of the default models (igea_envfun_default_terms). */
#define IGEA_ENVFUN_DEFAULT_TERMS 21

/*
 * igea_envfun_default_terms: the default term set of system kind `system`
 * (the 21-term model of METHODS 1.6(b) / 5.5), the codes in model order.
 * Strapdown: acc_bias_*, acc_scale_*, acc_mis_*, gyro_bias_*, gyro_g_*,
 * att0_*; platform: acc_bias_*, acc_scale_*, gyro_bias_*, gyro_gi_*,
 * gyro_gs_*, align0_*, acc_sq_*.
 * Arguments: 1 system, 2 terms (output, cap ints), 3 cap >= the number of
 * terms (IGEA_ENVFUN_DEFAULT_TERMS; IGEA_ENVFUN_TERM_COUNT always suffices),
 * 4 n (output: the number of terms written).
 * Returns 0, -i (outputs untouched).
 */
IGEA_API int igea_envfun_default_terms(int system, int *terms, int cap, int *n);

/*
 * igea_envfun_term_count: one past the largest term code of this version
 * (IGEA_ENVFUN_TERM_END); codes below it with an empty name are not terms.
 */
IGEA_API int igea_envfun_term_count(void);

/*
 * igea_envfun_all_terms: every term code valid for system kind `system`, in
 * code order (the driver's `--terms all`).
 * Arguments: 1 system, 2 terms (output, cap ints), 3 cap >= the number of
 * terms (IGEA_ENVFUN_TERM_END always suffices), 4 n (output: the number
 * written). Returns 0, -i (outputs untouched).
 */
IGEA_API int igea_envfun_all_terms(int system, int *terms, int cap, int *n);

/*
 * Environment-function matrix of a trajectory.
 * Arguments (1-based positions, as the -i status names them):
 *  1 system    IGEA_ENVFUN_STRAPDOWN or IGEA_ENVFUN_PLATFORM
 *  2 nsamp     telemetry samples, >= 2
 *  3 traj      nsamp x 11 column-major (see above), finite, t strictly
 *              increasing
 *  4 ldt       >= nsamp
 *  5 nterms    >= 1
 *  6 terms     nterms codes, each valid for the system
 *  7 axes      platform only: 6 ints, axes[j] the input axis I(j) and
 *              axes[3 + j] the spin axis S(j) of gyro j (values 0..2), or
 *              NULL for I(j) = j, S(j) = (j + 1) mod 3 [D]; ignored for
 *              strapdown; -7 also when a term reads the output axis O(j)
 *              of a gyro whose I(j) = S(j)
 *  8 nepochs   tracking epochs, >= 1
 *  9 epochs    nepochs times, non-decreasing, within [t_0, t_last]
 * 10 spec      nterms 1-sigma specs (> 0) multiplying the columns, or NULL
 * 11 output    IGEA_ENVFUN_VELOCITY, _POSITION, _VELOCITY_G, _POSITION_G
 *              (the _G kinds integrate METHODS 5.4 with the point-mass
 *              gravity gradient along the nominal position, computed from
 *              the launch point at radius 6371 km with mu = 3.986004418e14)
 * 12 S         output, 3 nepochs x nterms column-major, rows epoch-major
 *              (epoch e, axis a at row 3 e + a)
 * 13 lds       >= 3 nepochs
 * Returns 0, -i, IGEA_ENONFINITE (NaN/Inf in traj, epochs or spec),
 * IGEA_ENONPOSITIVE (a spec <= 0), IGEA_EDOMAIN (a quaternion of zero
 * norm; platform: only with lever_* terms, which read the attitude),
 * IGEA_ENOMEM. S is untouched on failure.
 */
IGEA_API int igea_envfun_compute(int system, int nsamp, const double *traj,
                                 int ldt, int nterms, const int *terms,
                                 const int *axes, int nepochs,
                                 const double *epochs, const double *spec,
                                 int output, double *S, int lds);

/* Kinds of a user-defined term (igea_envfun_compute_user). */
#define IGEA_ENVFUN_USER_ACC 0  /* a specific-force error, m/s^2 per unit */
#define IGEA_ENVFUN_USER_GYRO 1 /* a rate error (strapdown) or platform drift,
                                 * rad/s per unit */

/*
 * Environment-function matrix of catalogue terms and user-defined terms.
 * A user term is a sampled unit error u(t_k) in instrument axes (body axes
 * for strapdown, platform axes for a platform), one 3-vector per telemetry
 * sample, e.g. a thermal drift profile; it is propagated exactly like a
 * catalogue accelerometer term (S = int C u dt, platform int u dt) or gyro
 * term (S = int Phi_u x f^a dt, platform int f^a x alpha dt).
 * Arguments (1-based positions, as the -i status names them):
 *  1-4         system, nsamp, traj, ldt as igea_envfun_compute
 *  5 nterms    catalogue terms, >= 0 (nterms + nuser >= 1)
 *  6 terms     nterms codes valid for the system; may be NULL if nterms = 0
 *  7 axes      as igea_envfun_compute (platform only; -7 also when a term
 *              reads the output axis O(j) of a gyro whose I(j) = S(j))
 *  8 nuser     user terms, >= 0
 *  9 user_kind nuser kinds IGEA_ENVFUN_USER_ACC or _GYRO; may be NULL if
 *              nuser = 0
 * 10 user      nsamp x 3 nuser column-major: columns 3 i, 3 i + 1, 3 i + 2
 *              the x, y, z unit error of user term i at each sample; may be
 *              NULL if nuser = 0
 * 11 ldu       >= nsamp (when nuser > 0)
 * 12 nepochs, 13 epochs   as igea_envfun_compute
 * 14 spec      nterms + nuser 1-sigma specs (> 0), or NULL
 * 15 output    as igea_envfun_compute
 * 16 S         output, 3 nepochs x (nterms + nuser) column-major: the
 *              catalogue columns, then the user columns
 * 17 lds       >= 3 nepochs
 * Returns 0, -i, IGEA_ENONFINITE (NaN/Inf in traj, user, epochs or spec),
 * IGEA_ENONPOSITIVE, IGEA_EDOMAIN (a quaternion of zero norm where the
 * attitude is used: strapdown, or the platform's lever_* terms),
 * IGEA_ENOMEM. S is untouched on failure.
 */
IGEA_API int igea_envfun_compute_user(int system, int nsamp, const double *traj,
                                      int ldt, int nterms, const int *terms,
                                      const int *axes, int nuser,
                                      const int *user_kind, const double *user,
                                      int ldu, int nepochs, const double *epochs,
                                      const double *spec, int output, double *S,
                                      int lds);

/*
 * igea_envfun_compute_user with the launch point (docs/envfun.md, "Launch
 * point" [D]): the launch-point columns pos0_x, pos0_z then also hold the
 * stated pad velocity's error w_L x e_k per metre (w_L the Earth rate in
 * launch axes, e_k downrange or cross-range): the range's tracking counts
 * W from the pad velocity w x r0 of the stated point, the vehicle left the
 * true one. A constant in the velocity kinds (also at t_0), c t in the
 * position, and in the gravity-coupled kinds the initial velocity error
 * w_L x e_k with the initial position error e_k. The other columns are
 * those of igea_envfun_compute_user, but for the gravity-coupled kinds'
 * gradient: the site's J2 field along the nominal path that leaves the pad
 * with its inertial velocity w x r0 (the navigation's start).
 * Arguments (1-based positions, as the -i status names them):
 *  1-15        as igea_envfun_compute_user (positions 1-15)
 * 16 site      IGEA_NAV_SITE_LEN values (igea_nav_site, igea/nav.h): the
 *              stated launch point; may be NULL: igea_envfun_compute_user
 * 17 S         output, 3 nepochs x (nterms + nuser) column-major
 * 18 lds       >= 3 nepochs
 * Returns as igea_envfun_compute_user (-16 a site that igea_nav_rotation
 * refuses). S is untouched on failure.
 */
IGEA_API int igea_envfun_compute_site(int system, int nsamp, const double *traj,
                                      int ldt, int nterms, const int *terms,
                                      const int *axes, int nuser,
                                      const int *user_kind, const double *user,
                                      int ldu, int nepochs, const double *epochs,
                                      const double *spec, int output,
                                      const double *site, double *S, int lds);

/*
 * The nonlinear truth model of the whole catalogue: igea_sim_nonlinear
 * (igea/sim.h) with the errors of every code below nerr (METHODS 5.6; the
 * new families as documented in docs/envfun.md: launch-point errors read
 * the reference velocity in the rotated launch frame exp(-[theta x]), the
 * lever arm adds -(C (w x l) - its value at t_0), the size effect adds
 * e_j (w' x r + w x (w x r))_j with w' dt the rate increment).
 *  1 system, 2 nsamp, 3 traj, 4 ldt   as igea_sim_nonlinear
 *  5 nerr       IGEA_ENVFUN_TERM_COUNT <= nerr <= igea_envfun_term_count()
 *  6 err        nerr values: the error of each code in SI units; codes not
 *               valid for the system must be 0
 *  7 axes, 8 nepochs, 9 epochs, 10 dW as igea_sim_nonlinear
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EDOMAIN (zero quaternion),
 * IGEA_ENOMEM (dW untouched on failure).
 */
IGEA_API int igea_envfun_nonlinear(int system, int nsamp, const double *traj,
                                   int ldt, int nerr, const double *err,
                                   const int *axes, int nepochs,
                                   const double *epochs, double *dW);

#ifdef __cplusplus
}
#endif
#endif
