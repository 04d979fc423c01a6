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
#define IGEA_ENVFUN_TERM_COUNT 36       /* codes are 0 .. IGEA_ENVFUN_TERM_COUNT - 1 */

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
 * gyro biases, 0.5 deg/h/g for g-sensitive drifts).
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
 *              strapdown
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
 * norm), IGEA_ENOMEM. S is untouched on failure.
 */
IGEA_API int igea_envfun_compute(int system, int nsamp, const double *traj,
                                 int ldt, int nterms, const int *terms,
                                 const int *axes, int nepochs,
                                 const double *epochs, const double *spec,
                                 int output, double *S, int lds);

#ifdef __cplusplus
}
#endif
#endif
