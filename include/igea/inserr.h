/*
 * igea/inserr.h - the linearised error model of an inertial navigation
 * system in the local-level frame (docs/inserr.md): position, velocity and
 * attitude errors driven by accelerometer biases and gyro drifts, with the
 * gravity feedback (Schuler), the Earth-rate coupling (Foucault, the 24-h
 * mode) and the Coriolis and transport-rate terms of a slowly moving
 * vehicle; the deterministic response to given sensor errors and the
 * covariance for white and random-walk sensor noise.
 *
 * Frame and Earth: local-level north-east-down (NED) axes on a spherical
 * Earth of radius R (default the mean radius 6371008.8 m) with gravity g
 * along down (default 9.80665 m/s^2: Schuler period 2 pi sqrt(R/g) =
 * 5064 s = 84.4 min), Earth rate w, latitude L and a constant velocity
 * (vn, ve) (0 for a stationary vehicle). The coefficients are frozen at
 * those values (a vehicle that moves slowly compared with R: L and the
 * velocity are taken constant over the run).
 *
 * The state (IGEA_INSERR_N = 15 values, in this order):
 *   0..2  dr   position error N E D, m (computed minus true; dN = R dL,
 *              dE = R cos L dlon, dD = -dh)
 *   3..5  dv   velocity error N E D, m/s
 *   6..8  phi  attitude error N E D, rad: the computed body-to-NED matrix
 *              is (I - [phi x]) C (the phi-angle model)
 *   9..11 b    accelerometer bias N E D, m/s^2 (measured minus true
 *              specific force, resolved in NED; held constant, or a random
 *              walk)
 *   12..14 eps gyro drift N E D, rad/s (measured minus true rate, in NED)
 * The model dx/dt = F x + G w (w white, spectral densities q) is
 *   d(dr)/dt  = dv + (v_N dD, v_E tan L dN + v_E dD, 0) / R
 *   d(dv)/dt  = f x phi + b - (2 W + rho) x dv - (2 dW + drho) x v + dg
 *   d(phi)/dt = -(W + rho) x phi + dW + drho - eps
 *   d(b)/dt = w_b, d(eps)/dt = w_eps
 * with W = w (cos L, 0, -sin L), rho = (v_E, -v_N, -v_E tan L) / R, the
 * specific force f = (2 W + rho) x v - (0, 0, g), dW = w dN / R (-sin L, 0,
 * -cos L), drho = (dv_E + v_E dD / R, -dv_N - v_N dD / R, -dv_E tan L -
 * v_E dN / (R cos^2 L) - v_E tan L dD / R) / R and dg = (0, 0, 2 g dD / R)
 * (docs/inserr.md gives the derivation). The white noises w enter as:
 * accelerometer white noise into d(dv)/dt (+1), gyro white noise into
 * d(phi)/dt (-1), and the bias random walks into d(b)/dt and d(eps)/dt.
 *
 * Vertical channel (IGEA_INSERR_OPT_VERTICAL): 0 (default), aided: dD and
 * dv_D are held at their initial values (their rows of F are zero and no
 * noise enters them), the usual horizontal analysis; 1, free: the rows
 * above with the gravity gradient 2 g / R, which diverges with the time
 * constant sqrt(R / (2 g)) = 570 s.
 *
 * Integration: the classical fourth-order Runge-Kutta method of the linear
 * system (and of the covariance equation dP/dt = F P + P F^T + G Q G^T) with
 * a fixed step: each interval between output epochs is cut into the least
 * number of equal steps not longer than IGEA_INSERR_OPT_STEP, nor than a
 * quarter of the shortest correlation time > 0 (IGEA_INSERR_OPT_ACC_TC,
 * _GYRO_TC: the Gauss-Markov bias states, on which a longer step is
 * inaccurate and beyond 2.785 T diverges) [D]; "step" below is that step.
 */
#ifndef IGEA_INSERR_H
#define IGEA_INSERR_H

#include "igea/common.h"

#ifdef __cplusplus
extern "C" {
#endif

#define IGEA_INSERR_N 15  /* state size */
#define IGEA_INSERR_NQ 12 /* white noises: acc N E D, gyro N E D, acc RW N E D, gyro RW N E D */

/* State slots. */
#define IGEA_INSERR_POS 0   /* position error N E D (3), m */
#define IGEA_INSERR_VEL 3   /* velocity error N E D (3), m/s */
#define IGEA_INSERR_ATT 6   /* attitude error N E D (3), rad */
#define IGEA_INSERR_ACC 9   /* accelerometer bias N E D (3), m/s^2 */
#define IGEA_INSERR_GYRO 12 /* gyro drift N E D (3), rad/s */

/* Indices into opts[IGEA_INSERR_OPT_LEN]; igea_inserr_defaults fills them. */
#define IGEA_INSERR_OPT_RADIUS 0   /* Earth radius R, m: 6371008.8 */
#define IGEA_INSERR_OPT_G 1        /* gravity g, m/s^2: 9.80665 */
#define IGEA_INSERR_OPT_OMEGA 2    /* Earth rate, rad/s: 7.292115e-5 (0: none) */
#define IGEA_INSERR_OPT_LAT 3      /* latitude L, rad: 0 */
#define IGEA_INSERR_OPT_VN 4       /* north velocity, m/s: 0 */
#define IGEA_INSERR_OPT_VE 5       /* east velocity, m/s: 0 */
#define IGEA_INSERR_OPT_STEP 6     /* longest integration step, s: 1 */
#define IGEA_INSERR_OPT_VERTICAL 7 /* vertical channel: 0 aided (held), 1 free: 0 */
#define IGEA_INSERR_OPT_ACC_TC 8   /* accelerometer bias correlation time, s: 0 (none) */
#define IGEA_INSERR_OPT_GYRO_TC 9  /* gyro drift correlation time, s: 0 (none) */
#define IGEA_INSERR_OPT_LEN 16     /* slots 10.. reserved for additions (0) */

/* Correlation times (IGEA_INSERR_OPT_ACC_TC, _GYRO_TC): 0 (the default)
 * keeps the bias states constant or random walks as above; T > 0 makes
 * them first-order Gauss-Markov processes, d(b)/dt = -b / T + w_b (the
 * row of F gets -1 / T), whose stationary variance is q T / 2 for a
 * driving density q. */

/* Fill opts[IGEA_INSERR_OPT_LEN] with the defaults above. Returns 0, -1. */
IGEA_API int igea_inserr_defaults(double *opts);

/*
 * Check opts[IGEA_INSERR_OPT_LEN]: every slot finite (the reserved ones
 * included), radius >= 1e5, g > 0, omega >= 0, |lat| <= 1.5 rad (89.9 deg:
 * tan L is used), 0 < step <= 60, vertical 0 or 1, acc_tc and gyro_tc 0 or
 * in [1, 1e9] s. Returns 0 when they are
 * valid, -1 for a NULL opts, else 1 + the first bad slot
 * (igea_opt_name(IGEA_MODULE_INSERR, slot) names it).
 */
IGEA_API int igea_inserr_check_opts(const double *opts);

/*
 * The system matrix of the model above.
 *  1 opts [IGEA_INSERR_OPT_LEN] (igea_inserr_check_opts); output 2 F
 *  (IGEA_INSERR_N x IGEA_INSERR_N = 225 values, row-major: dx_i/dt =
 *  sum_j F[i * 15 + j] x_j).
 * Returns 0 or -i (opts invalid, F missing); F untouched on failure.
 */
IGEA_API int igea_inserr_matrix(const double *opts, double *F);

/*
 * The deterministic error response from an initial state.
 *  1 opts [IGEA_INSERR_OPT_LEN] (igea_inserr_check_opts); 2 x0
 *  [IGEA_INSERR_N] the state at t = 0 (initial errors, the accelerometer
 *  biases in slots 9..11 and the gyro drifts in slots 12..14); 3 duration
 *  (s, > 0, duration / step <= 1e7); 4 n >= 2 output epochs t_k = k
 *  duration / (n - 1), k = 0 .. n - 1; output 5 x (n x IGEA_INSERR_N,
 *  row-major: the state at epoch k in x[15 k .. 15 k + 14]; x[0..14] = x0).
 * Returns 0, -i, IGEA_ENONFINITE (x0 holds NaN or Inf), IGEA_ENOMEM or
 * IGEA_EOVERFLOW (the response overflows, e.g. a free vertical channel
 * over days); x untouched on failure.
 */
IGEA_API int igea_inserr_response(const double *opts, const double *x0, double duration,
                                  int n, double *x);

/*
 * The error covariance for white and random-walk sensor noise:
 * dP/dt = F P + P F^T + G diag(q) G^T from P(0) = P0.
 *  1 opts [IGEA_INSERR_OPT_LEN]; 2 P0 (IGEA_INSERR_N x IGEA_INSERR_N,
 *  symmetric to 1e-12 relative, non-negative diagonal; may be NULL: 0, or
 *  e.g. diag with the variances of the constant biases in slots 9..14);
 *  3 q [IGEA_INSERR_NQ] two-sided spectral densities, each >= 0:
 *  accelerometer white noise N E D ((m/s^2)^2 s = (m/s)^2/s, the square
 *  of the velocity random walk), gyro white noise N E D ((rad/s)^2 s, the
 *  square of the angle random walk), accelerometer bias random walk N E D
 *  ((m/s^2)^2 / s), gyro drift random walk N E D ((rad/s)^2 / s);
 *  4 duration (s, > 0, duration / step <= 1e7); 5 n >= 2 epochs as
 *  igea_inserr_response; output 6 P (n x 225 values, P(t_k) row-major at
 *  P[225 k ..]).
 * Returns 0, -i, IGEA_ENONFINITE (P0 or q holds NaN or Inf),
 * IGEA_ENONPOSITIVE (a negative q or a negative diagonal of P0),
 * IGEA_EDOMAIN (P0 not symmetric), IGEA_ENOMEM or IGEA_EOVERFLOW; P
 * untouched on failure.
 */
IGEA_API int igea_inserr_covariance(const double *opts, const double *P0, const double *q,
                                    double duration, int n, double *P);

/* Layout of the noise arrays of igea_inserr_noise_covariance: per
 * instrument triad (accelerometers or gyros) the IEEE Std 952 coefficients
 * of igea_stability_fit for each axis N E D, in SI units. */
#define IGEA_INSERR_NOISE_N 0 /* random walk N (3): m/s/sqrt(s) (VRW), rad/sqrt(s) (ARW) */
#define IGEA_INSERR_NOISE_B 3 /* bias instability B (3): m/s^2, rad/s */
#define IGEA_INSERR_NOISE_K 6 /* rate random walk K (3): m/s^2/sqrt(s), rad/s/sqrt(s) */
#define IGEA_INSERR_NOISE_LEN 9

/*
 * The error covariance for sensor noise given as IEEE Std 952 coefficients
 * (docs/inserr.md, "Noise from an Allan fit"). Each instrument axis is the
 * sum of three independent processes: white noise of density N^2, a
 * random-walk bias of density K^2, and for bias instability a stationary
 * first-order Gauss-Markov bias of correlation time T (the slot
 * IGEA_INSERR_OPT_ACC_TC or _GYRO_TC of opts) and standard deviation
 * s = B sqrt(2 ln2 / pi) / 0.61736 = 1.07600 B (its Allan deviation peaks at
 * 0.61736 s at tau = 1.8926 T, matched to the flicker floor B sqrt(2 ln 2 /
 * pi) of B) [D]. The model being linear, P is the sum of two runs of
 * igea_inserr_covariance: one with the white and random-walk densities
 * (q = N^2, K^2, both correlation times 0) from P0, one with the
 * Gauss-Markov driving densities 2 s^2 / T from the stationary P0 = diag(s^2)
 * on the bias states.
 *  1 opts [IGEA_INSERR_OPT_LEN] (igea_inserr_check_opts; the correlation
 *  times are read here only, > 0 where a B is > 0); 2 P0 (15 x 15 as
 *  igea_inserr_covariance, e.g. the random constant biases; may be NULL:
 *  0); 3 acc [IGEA_INSERR_NOISE_LEN] the accelerometers' N, B, K along N E
 *  D; 4 gyro [IGEA_INSERR_NOISE_LEN] the gyros' (about N E D), each >= 0;
 *  5 duration (s, > 0, duration / step <= 1e7); 6 n >= 2 epochs as
 *  igea_inserr_response; output 7 P (n x 225 values).
 * Returns 0, -i, IGEA_ENONFINITE (NaN or Inf in P0, acc or gyro),
 * IGEA_ENONPOSITIVE (a negative coefficient or diagonal of P0),
 * IGEA_EDOMAIN (P0 not symmetric, or a B > 0 whose correlation time is
 * 0), IGEA_ENOMEM or IGEA_EOVERFLOW; P untouched on failure.
 */
IGEA_API int igea_inserr_noise_covariance(const double *opts, const double *P0,
                                          const double *acc, const double *gyro,
                                          double duration, int n, double *P);

/* ---- along a trajectory, in the launch-inertial frame (src/inserr_li.c) --
 *
 * The same 15 states resolved in the launch-inertial frame LI of
 * igea/nav.h, propagated along the reference trajectory that the nav core
 * (igea_nav_init, igea_nav_step, the full algorithm) computes from an
 * error-free telemetry record (docs/inserr.md, "Along a trajectory"):
 *   0..2  dr   position error in LI, m (computed minus true)
 *   3..5  dv   velocity error in LI, m/s
 *   6..8  phi  attitude error in LI, rad: the computed body-to-LI matrix is
 *              (I - [phi x]) C (platform: phi is the platform's rotation
 *              away from the LI axes)
 *   9..11 b    accelerometer bias, m/s^2: body axes (strapdown) or
 *              platform axes (platform); constant or a random walk
 *   12..14 eps gyro drift, rad/s, the same axes (measured minus true rate;
 *              platform: the platform's drift rate)
 * The model, with C(t) the reference body-to-LI matrix (platform: I), f(t)
 * the reference specific force in LI and G(t) the gravity gradient
 * (igea_nav_gravity_li, the point-mass or J2 model of the navigation) at
 * the reference position:
 *   d(dr)/dt = dv
 *   d(dv)/dt = f x phi + C b + G dr
 *   d(phi)/dt = -C eps (strapdown), +eps (platform)
 *   d(b)/dt = w_b, d(eps)/dt = w_eps
 * Over each telemetry interval (t_{k-1}, t_k] the coefficients are frozen
 * at the interval's values: f = (W_k - W_{k-1}) / h from the nav core's
 * apparent velocity, C from the normalised mean of the two quaternions, G
 * at the mean position; one classical Runge-Kutta step per interval
 * (with the Gauss-Markov states below, equal steps not longer than a
 * quarter of the shortest correlation time [D]).
 * White noises (q below) enter d(dv)/dt through C (accelerometer), d(phi)/dt
 * through -C (strapdown gyro) or I (platform gyro), and d(b)/dt, d(eps)/dt.
 *
 * The telemetry record tel (column-major nsamp x 7 strapdown: t dvx dvy dvz
 * dthx dthy dthz in body axes, or nsamp x 4 platform: t dvx dvy dvz along
 * platform axes; the layout of igea_sim_raw, leading dimension ldtel >=
 * nsamp; row 0 holds t_0, its increments are ignored; times strictly
 * increasing) and the initial state (q0 body -> LI, may be NULL: 1 0 0 0,
 * platform ignored; r0 LI position, may be NULL: the launch point; v0 LI
 * velocity, may be NULL: the launch point's inertial velocity; as
 * igea_nav_init at t_0) give the reference. Output epochs: nepochs >= 1
 * increasing times, each within 1e-9 s of a sample time of tel.
 */

/*
 * The deterministic error response along a trajectory.
 *  1 system (IGEA_ENVFUN_STRAPDOWN 0 or IGEA_ENVFUN_PLATFORM 1); 2 site
 *  (IGEA_NAV_SITE_LEN, igea_nav_site); 3 gravity (IGEA_NAV_GRAVITY_POINT_MASS
 *  or IGEA_NAV_GRAVITY_J2); 4 nsamp >= 2; 5 tel (see above); 6 ldtel >=
 *  nsamp; 7 q0 [4] (may be NULL); 8 r0 [3] m (may be NULL); 9 v0 [3] m/s
 *  (may be NULL); 10 x0 [IGEA_INSERR_N] the state at t_0 (initial errors,
 *  the biases and drifts); 11 nepochs >= 1; 12 epochs [nepochs] s; output
 *  13 x (nepochs x IGEA_INSERR_N row-major: the state at epoch j in
 *  x[15 j .. 15 j + 14]).
 * Returns 0, -i, IGEA_ENONFINITE (tel, q0, r0, v0 or x0 holds NaN or Inf,
 * or the reference navigation would), IGEA_ENOMEM or IGEA_EOVERFLOW; x
 * untouched on failure.
 */
IGEA_API int igea_inserr_li_response(int system, const double *site, int gravity, int nsamp,
                                     const double *tel, int ldtel, const double *q0,
                                     const double *r0, const double *v0, const double *x0,
                                     int nepochs, const double *epochs, double *x);

/*
 * The error covariance along a trajectory: dP/dt = A P + P A^T + B diag(q)
 * B^T over each interval, from P(t_0) = P0.
 *  1 system, 2 site, 3 gravity, 4 nsamp, 5 tel, 6 ldtel as
 *  igea_inserr_li_response; 7 q0 [4] (may be NULL); 8 r0 [3] m (may be
 *  NULL); 9 v0 [3] m/s (may be NULL); 10 P0 (IGEA_INSERR_N x IGEA_INSERR_N,
 *  symmetric to 1e-12 relative, non-negative diagonal; may be NULL: 0);
 *  11 q [IGEA_INSERR_NQ] two-sided spectral densities, each >= 0, per axis
 *  of the instruments (body or platform axes): accelerometer white noise
 *  x y z ((m/s^2)^2 s = (m/s)^2/s, the square of the velocity random walk
 *  N), gyro white noise x y z ((rad/s)^2 s, the square of the angle random
 *  walk N), accelerometer bias random walk x y z ((m/s^2)^2 / s, K^2), gyro
 *  drift random walk x y z ((rad/s)^2 / s, K^2); 12 nepochs >= 1; 13 epochs
 *  [nepochs] s; output 14 P (nepochs x 225 values, P at epoch j row-major
 *  at P[225 j ..]).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE (a negative q or a
 * negative diagonal of P0), IGEA_EDOMAIN (P0 not symmetric), IGEA_ENOMEM
 * or IGEA_EOVERFLOW; P untouched on failure.
 */
IGEA_API int igea_inserr_li_covariance(int system, const double *site, int gravity, int nsamp,
                                       const double *tel, int ldtel, const double *q0,
                                       const double *r0, const double *v0, const double *P0,
                                       const double *q, int nepochs, const double *epochs,
                                       double *P);

/*
 * Gauss-Markov bias states along a trajectory [D] (docs/inserr.md, "Along
 * a trajectory": bias instability). The functions below take the options
 * array of the local-level model (argument 4, opts [IGEA_INSERR_OPT_LEN],
 * checked by igea_inserr_check_opts) and read from it only the correlation
 * times IGEA_INSERR_OPT_ACC_TC and _GYRO_TC (the Earth and the trajectory
 * are the nav core's: radius, g, omega, lat, the velocities, step and
 * vertical do not apply here). A correlation time T > 0 makes the three
 * bias states of those instruments first-order Gauss-Markov processes,
 *   d(b)/dt = -b / T + w_b   (the row of A gets -1 / T),
 * whose driving density is the q slot of that bias random walk and whose
 * stationary variance is q T / 2; 0 keeps them constant or random walks,
 * as igea_inserr_li_response and _covariance (which equal the functions
 * below with both times 0). The other arguments, one position further on,
 * are those of igea_inserr_li_response and _covariance.
 */

/*
 * The deterministic error response along a trajectory with Gauss-Markov
 * bias states: an initial bias b0 of x0 decays as b0 e^(-t / T).
 *  1 system, 2 site, 3 gravity as igea_inserr_li_response; 4 opts; 5 nsamp,
 *  6 tel, 7 ldtel; 8 q0 [4] (may be NULL), 9 r0 [3] (may be NULL), 10 v0
 *  [3] (may be NULL); 11 x0 [IGEA_INSERR_N]; 12 nepochs, 13 epochs; output
 *  14 x (nepochs x IGEA_INSERR_N row-major): as igea_inserr_li_response's
 *  arguments 4-13.
 * Returns as igea_inserr_li_response (its positions from 4 on one further;
 * -4 invalid opts); x untouched on failure.
 */
IGEA_API int igea_inserr_li_response_opts(int system, const double *site, int gravity,
                                          const double *opts, int nsamp, const double *tel,
                                          int ldtel, const double *q0, const double *r0,
                                          const double *v0, const double *x0, int nepochs,
                                          const double *epochs, double *x);

/*
 * The error covariance along a trajectory with Gauss-Markov bias states:
 * dP/dt = A P + P A^T + B diag(q) B^T over each interval from P(t_0) = P0,
 * the bias slots of q (6..11) the driving densities of the bias states
 * whose correlation time is > 0.
 *  1 system, 2 site, 3 gravity; 4 opts; 5 nsamp, 6 tel, 7 ldtel; 8 q0 [4]
 *  (may be NULL), 9 r0 [3] (may be NULL), 10 v0 [3] (may be NULL); 11 P0
 *  (may be NULL: 0); 12 q [IGEA_INSERR_NQ]; 13 nepochs, 14 epochs; output
 *  15 P: as igea_inserr_li_covariance's arguments 4-14.
 * Returns as igea_inserr_li_covariance (its positions from 4 on one
 * further; -4 invalid opts); P untouched on failure.
 */
IGEA_API int igea_inserr_li_covariance_opts(int system, const double *site, int gravity,
                                            const double *opts, int nsamp, const double *tel,
                                            int ldtel, const double *q0, const double *r0,
                                            const double *v0, const double *P0,
                                            const double *q, int nepochs,
                                            const double *epochs, double *P);

/*
 * The error covariance along a trajectory for sensor noise given as IEEE
 * Std 952 coefficients per instrument axis (the stability module's noise
 * fit), as igea_inserr_noise_covariance does for the local-level model:
 * white noise of density N^2, a random-walk bias of density K^2, and for
 * bias instability B a stationary Gauss-Markov bias of correlation time T
 * (opts' ACC_TC or GYRO_TC) and standard deviation s = 1.07600 B (its Allan
 * deviation peaks at the flicker floor B sqrt(2 ln 2 / pi)) [D]. The model
 * being linear, P is the sum of two runs of igea_inserr_li_covariance_opts:
 * the densities N^2, K^2 with both correlation times 0 from P0, and the
 * Gauss-Markov driving densities 2 s^2 / T from the stationary
 * P0 = diag(s^2) on the bias states.
 *  1 system, 2 site, 3 gravity; 4 opts (the correlation times, > 0 where a
 *  B is > 0); 5 nsamp, 6 tel, 7 ldtel, 8 q0 [4] (may be NULL), 9 r0 [3]
 *  (may be NULL), 10 v0 [3] (may be NULL) as igea_inserr_li_response; 11 P0 (15 x 15 as
 *  igea_inserr_li_covariance, e.g. random constant biases; may be NULL: 0);
 *  12 acc [IGEA_INSERR_NOISE_LEN] the accelerometers' N (m/s/sqrt(s)),
 *  B (m/s^2), K (m/s^2/sqrt(s)) for the instrument axes x y z (body axes
 *  for a strapdown system, platform axes for a platform); 13 gyro
 *  [IGEA_INSERR_NOISE_LEN] the gyros' N (rad/sqrt(s)), B (rad/s),
 *  K (rad/s/sqrt(s)), each >= 0; 14 nepochs >= 1; 15 epochs [nepochs] as
 *  igea_inserr_li_response; output 16 P (nepochs x 225 values, row-major
 *  at P[225 j ..]).
 * Returns 0, -i, IGEA_ENONFINITE (NaN or Inf in tel, q0, r0, v0, P0, acc
 * or gyro, or the reference navigation), IGEA_ENONPOSITIVE (a negative
 * coefficient or diagonal of P0), IGEA_EDOMAIN (P0 not symmetric, or a
 * B > 0 whose correlation time is 0), IGEA_ENOMEM or IGEA_EOVERFLOW; P
 * untouched on failure.
 */
IGEA_API int igea_inserr_li_noise_covariance(int system, const double *site, int gravity,
                                             const double *opts, int nsamp,
                                             const double *tel, int ldtel, const double *q0,
                                             const double *r0, const double *v0,
                                             const double *P0, const double *acc,
                                             const double *gyro, int nepochs,
                                             const double *epochs, double *P);

#ifdef __cplusplus
}
#endif
#endif
