/*
 * igea/impact.h - the impact point of a ballistic free flight, its
 * sensitivity to the burnout state, the error budget in miss distance and
 * the circular error probable (docs/impact.md).
 *
 * Frames. The burnout state is given in an Earth-centred Earth-fixed frame
 * (ECEF: z the rotation axis) at the burnout instant: position r0 (m) and
 * velocity v0 (m/s) relative to the rotating Earth. The free flight is
 * computed in the inertial frame that coincides with ECEF at burnout (the
 * inertial velocity is v0 + w x r0), and the impact point is returned in
 * ECEF at the impact instant. With omega = 0 all three frames are one.
 *
 * Models: IGEA_IMPACT_KEPLER, a spherical Earth of gravitational parameter
 * mu, in closed form (the Kepler ellipse from the burnout state to the
 * sphere |r| = radius, Lagrange f and g, the time of flight from the
 * eccentric anomaly); IGEA_IMPACT_J2, the same Earth with the J2 zonal term
 * (reference radius re), integrated numerically (classical Runge-Kutta of
 * step `step` s, the crossing of the sphere solved by Newton's method).
 *
 * The Jacobian of the impact (position, velocity, time) with respect to the
 * burnout state is, for Kepler, the exact derivative of the closed form
 * (forward-mode differentiation, no finite differences); for J2, central
 * differences of the integration. The miss is measured at the nominal
 * impact point along the downrange axis (the horizontal part of the impact
 * velocity) and the crossrange axis (to the right of it, downrange x up).
 */
#ifndef IGEA_IMPACT_H
#define IGEA_IMPACT_H

#include "igea/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Models (IGEA_CHOICE_IMPACT_MODEL: kepler j2). */
#define IGEA_IMPACT_KEPLER 0
#define IGEA_IMPACT_J2 1

/* Indices into opts[IGEA_IMPACT_OPT_LEN]; igea_impact_defaults fills them
 * (WGS-84 mu, J2, equatorial radius and Earth rate; the sphere of impact at
 * the mean radius 6371008.8 m). */
#define IGEA_IMPACT_OPT_MU 0     /* gravitational parameter, m^3/s^2: 3.986004418e14 */
#define IGEA_IMPACT_OPT_RADIUS 1 /* radius of the impact sphere, m: 6371008.8 */
#define IGEA_IMPACT_OPT_OMEGA 2  /* Earth rate, rad/s: 7.292115e-5 (0: no rotation) */
#define IGEA_IMPACT_OPT_J2 3     /* J2 (the J2 model only): 1.082629821313e-3 */
#define IGEA_IMPACT_OPT_RE 4     /* J2 reference radius, m: 6378137 */
#define IGEA_IMPACT_OPT_STEP 5   /* J2 integration step, s: 0.5 */
#define IGEA_IMPACT_OPT_TMAX 6   /* longest flight searched, s: 1e5 */
#define IGEA_IMPACT_OPT_LEN 16   /* slots 7.. reserved for additions (0) */

/* Rows of the impact Jacobian jac (IGEA_IMPACT_JAC_ROWS x 6, the columns
 * the burnout x y z vx vy vz). */
#define IGEA_IMPACT_JAC_POS 0 /* rows 0..2: impact position */
#define IGEA_IMPACT_JAC_VEL 3 /* rows 3..5: impact velocity (ECEF) */
#define IGEA_IMPACT_JAC_TIME 6 /* row 6: time of flight */
#define IGEA_IMPACT_JAC_ROWS 7

/* Approximate CEP rules (IGEA_CHOICE_IMPACT_CEP: sum rms), sigma_1 >=
 * sigma_2 the principal standard deviations; both exact for a circle. */
#define IGEA_IMPACT_CEP_SUM 0 /* 0.5887 (sigma_1 + sigma_2) */
#define IGEA_IMPACT_CEP_RMS 1 /* 1.1774 sqrt((sigma_1^2 + sigma_2^2) / 2) */

/* Fill opts[IGEA_IMPACT_OPT_LEN] with the defaults above. Returns 0, -1. */
IGEA_API int igea_impact_defaults(double *opts);

/*
 * Check opts[IGEA_IMPACT_OPT_LEN]: every slot finite (the reserved ones
 * included), mu > 0, radius > 0, omega >= 0, re > 0, 0 < step <= 60,
 * tmax > 0. Returns 0 when they are valid, -1 for a NULL opts, else 1 +
 * the first bad slot (igea_opt_name(IGEA_MODULE_IMPACT, slot) names it).
 */
IGEA_API int igea_impact_check_opts(const double *opts);

/*
 * The impact point of the free flight from a burnout state.
 *  1 model IGEA_IMPACT_KEPLER or IGEA_IMPACT_J2; 2 opts
 *  [IGEA_IMPACT_OPT_LEN] (igea_impact_check_opts); 3 r0[3] burnout
 *  position (ECEF, m; |r0| >= radius); 4 v0[3] burnout velocity (ECEF, m/s).
 * Outputs: 5 rf[3] impact position (ECEF at impact, |rf| = radius); 6 vf[3]
 *  impact velocity (ECEF, relative to the Earth) (may be NULL); 7 tf time of
 *  flight (s) (may be NULL); 8 jac (IGEA_IMPACT_JAC_ROWS x 6, column-major)
 *  the derivatives of rf, vf and tf with respect to (r0, v0) (may be NULL);
 *  9 ldj >= IGEA_IMPACT_JAC_ROWS (read only when jac is not NULL).
 * Returns 0, -i, IGEA_ENONFINITE, or IGEA_EDOMAIN (outputs untouched) when
 * the flight does not come down to the sphere: an orbit or escape (Kepler:
 * energy >= 0 or the perigee above the sphere; J2: no crossing within
 * tmax), a burnout below the sphere, or a burnout with zero angular
 * momentum (vertical flight: the impact direction is undefined).
 */
IGEA_API int igea_impact_point(int model, const double *opts, const double *r0,
                               const double *v0, double *rf, double *vf, double *tf,
                               double *jac, int ldj);

/*
 * The downrange and crossrange unit vectors at an impact point: down = the
 * part of vf perpendicular to rf, normalised; cross = down x rf / |rf| (to
 * the right of the direction of flight).
 *  1 rf[3] impact position, 2 vf[3] impact velocity; outputs 3 down[3],
 *  4 cross[3].
 * Returns 0, -i, IGEA_ENONFINITE, or IGEA_EDOMAIN when vf is vertical or
 * rf is zero.
 */
IGEA_API int igea_impact_axes(const double *rf, const double *vf, double *down,
                              double *cross);

/*
 * The miss Jacobian G (2 x 6, column-major): row 0 downrange, row 1
 * crossrange (m per unit of the burnout x y z vx vy vz), G = [down cross]^T
 * J_pos with J_pos the position rows of jac and the axes of
 * igea_impact_axes at (rf, vf).
 *  1 jac (IGEA_IMPACT_JAC_ROWS x 6), 2 ldj >= IGEA_IMPACT_JAC_ROWS, 3 rf[3],
 *  4 vf[3]; outputs 5 G, 6 ldg >= 2.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EDOMAIN (as igea_impact_axes).
 */
IGEA_API int igea_impact_miss_jacobian(const double *jac, int ldj, const double *rf,
                                       const double *vf, double *G, int ldg);

/*
 * The error budget in miss distance. Column j of E (6 x n) is the burnout
 * state error (x y z vx vy vz) caused by error term j at its 1-sigma level
 * (e.g. the position and velocity environment functions at burnout times
 * the spec), the terms independent.
 *  1 n >= 1 terms; 2 G (2 x 6, igea_impact_miss_jacobian); 3 ldg >= 2;
 *  4 E; 5 lde >= 6. Outputs: 6 miss (2 x n, ld 2): downrange and crossrange
 *  miss of each term; 7 cov[4] (2 x 2, column-major): sum over terms of
 *  miss_j miss_j^T; 8 share[n]: |miss_j|^2 / sum_k |miss_k|^2 (0 for all
 *  when every miss is 0) (may be NULL).
 * Returns 0, -i, IGEA_ENONFINITE.
 */
IGEA_API int igea_impact_budget(int n, const double *G, int ldg, const double *E, int lde,
                                double *miss, double *cov, double *share);

/*
 * Probability that a zero-mean normal 2-vector of covariance cov lies in
 * the circle of radius r about the mean:
 *   P(r) = 1 - (1/pi) int_0^pi exp(-r^2 / (2 (s1 cos^2 t + s2 sin^2 t))) dt
 * (s1 >= s2 the eigenvalues; Craig's form, exact), by the periodic
 * trapezoidal rule refined until two successive values agree to 2 ulp.
 *  1 cov[4] (2 x 2, column-major, symmetric positive semi-definite); 2 r
 *  >= 0; output 3 prob.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE (a negative variance),
 * IGEA_EDOMAIN (cov not symmetric to 1e-12 relative, or not positive
 * semi-definite).
 */
IGEA_API int igea_impact_circle_prob(const double *cov, double r, double *prob);

/*
 * The radius of the circle about the mean that holds probability prob
 * (0.5: the CEP), the root of igea_impact_circle_prob to full precision.
 *  1 cov[4] as igea_impact_circle_prob; 2 0 < prob < 1; output 3 radius
 *  (0 when cov is zero). Returns as igea_impact_circle_prob.
 */
IGEA_API int igea_impact_cep(const double *cov, double prob, double *radius);

/*
 * A usual approximation of the CEP (prob 0.5): 1 cov[4] as above; 2 rule
 * IGEA_IMPACT_CEP_SUM or IGEA_IMPACT_CEP_RMS; output 3 radius. Their
 * errors against igea_impact_cep are stated in docs/impact.md. Returns as
 * igea_impact_circle_prob, or -2 for an unknown rule.
 */
IGEA_API int igea_impact_cep_approx(const double *cov, int rule, double *radius);

/*
 * The probability that a normal 2-vector of covariance cov and mean `mean`
 * (the miss's offset, e.g. its mean downrange and crossrange) lies within
 * the circle of radius r about the origin (the aim point) [D]: in the
 * principal axes (variances s1 >= s2, the mean (m1, m2)), with x1 = r cos t,
 *   P(r) = int_0^pi phi(r cos t; m1, s1) P(|x2| <= r sin t) r sin t dt,
 * whose even periodic extension is smooth: the trapezoidal rule, refined
 * until two successive values agree to 4 ulp (docs/impact.md). A zero mean
 * gives igea_impact_circle_prob's value.
 *  1 cov[4] as igea_impact_circle_prob; 2 mean[2] (finite); 3 r >= 0;
 *  output 4 prob.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_EDOMAIN (as
 * igea_impact_circle_prob), IGEA_ENOCONV (outputs untouched on failure).
 */
IGEA_API int igea_impact_circle_prob_offset(const double *cov, const double *mean, double r,
                                            double *prob);

/*
 * The radius of the circle about the origin (the aim point) holding
 * probability prob of a miss of covariance cov and mean `mean`: the biased
 * CEP (prob 0.5), the root of igea_impact_circle_prob_offset to full
 * precision (bisection in [0, |mean| + sqrt(-2 s1 ln(1 - prob))]).
 *  1 cov[4]; 2 mean[2]; 3 0 < prob < 1; output 4 radius (|mean| when cov
 *  is zero). Returns as igea_impact_circle_prob_offset.
 */
IGEA_API int igea_impact_cep_offset(const double *cov, const double *mean, double prob,
                                    double *radius);

/*
 * The miss distance that each equivalent-error component corresponds to
 * (docs/impact.md): component i of the accuracy test (igea/eqerr.h: the
 * direction p_i, an eigenvector of the normal matrix, and its equivalent
 * error x_i, both in the units of S's columns) is the error vector p_i x_i
 * of the terms, whose burnout state error is E p_i x_i and whose miss is
 *   miss_i = G E p_i x_i   (downrange, crossrange; m).
 *  1 N >= 1 terms (S's columns); 2 n >= 1 components
 *  3 G (2 x 6, igea_impact_miss_jacobian), 4 ldg >= 2
 *  5 E (6 x N column-major): the burnout state error (x y z vx vy vz, ECEF
 *    at burnout) per unit of each column of S (e.g. envfun's position and
 *    velocity functions at the burnout time, turned into ECEF), 6 lde >= 6
 *  7 P (N x n column-major): the components' directions, 8 ldp >= N
 *  9 equiv[n]: their equivalent errors
 * 10 miss (output, 2 x n, ld 2): downrange and crossrange miss of each
 * Returns 0, -i, IGEA_ENONFINITE (an input or a result), IGEA_ENOMEM; miss
 * untouched on failure.
 */
IGEA_API int igea_impact_component_miss(int N, int n, const double *G, int ldg,
                                        const double *E, int lde, const double *P, int ldp,
                                        const double *equiv, double *miss);

/*
 * The burnout state and the burnout state error of each error term, from a
 * trajectory, its launch point and a burnout time [D] (docs/impact.md,
 * "From a burnout time").
 * The state: the nav core (igea/nav.h) flies the trajectory from the
 * launch point (igea_nav_init at t_0, the lift-off: the pad's inertial
 * velocity, J2 gravity, the attitude the trajectory's first quaternion)
 * with the trapezoid increments of the sampled f and w (igea_sim_raw's
 * telemetry), the interval holding tb cut there with the linear
 * interpolants of f and w (a sample within 1e-9 s of tb is taken as tb);
 * its LI position and velocity at tb are turned into ECEF at tb - t_0
 * (igea_nav_transform: the Earth has turned by w (tb - t_0); the velocity
 * relative to the Earth), the burnout of igea_impact_point.
 * The errors: column j of E is the navigation's burnout error (computed
 * minus true) per unit of term j (times spec_j): the gravity-coupled
 * position and velocity environment functions of the term at tb
 * (igea_envfun_compute_site, IGEA_ENVFUN_POSITION_G and _VELOCITY_G with
 * the site: a navigation computes gravity at its erroneous position, so
 * the burnout error holds G dr besides the integrated apparent velocity),
 * turned into ECEF with M = igea_nav_rotation(site, LI, ECEF, tb - t_0):
 *   dr_E = M dr_LI,   dv_E = M dv_LI - w x dr_E   (w = IGEA_NAV_OMEGA e_z).
 * The miss of term j is then G E_j (igea_impact_budget,
 * igea_impact_component_miss): the error of the impact point predicted
 * from the navigated burnout state.
 *  1 system (IGEA_ENVFUN_STRAPDOWN or IGEA_ENVFUN_PLATFORM), 2 nsamp >= 2,
 *  3 traj (nsamp x 11 column-major, igea/envfun.h: finite, t strictly
 *  increasing, t_0 the lift-off; strapdown quaternions of non-zero norm),
 *  4 ldt >= nsamp: as igea_envfun_compute
 *  5 nterms >= 0 (0: the state only)
 *  6 terms: nterms codes valid for the system (may be NULL when nterms is 0)
 *  7 axes: platform gyro axes as igea_envfun_compute, or NULL
 *  8 spec: nterms 1-sigma specs (> 0) multiplying the columns, or NULL
 *  9 site: IGEA_NAV_SITE_LEN values (igea_nav_site), the launch point
 * 10 tb: the burnout time, s, in [t_0, t_last] of traj
 * Outputs: 11 state[6]: x y z (m) vx vy vz (m/s, relative to the Earth),
 *  ECEF at tb; 12 E (6 x nterms column-major, rows x y z vx vy vz; not
 *  written when nterms is 0, may then be NULL); 13 lde >= 6 (read only
 *  when nterms > 0).
 * Returns 0, -i (-10: tb outside the trajectory), IGEA_ENONFINITE (traj
 * or spec holds NaN or Inf, tb is NaN, or a result would), IGEA_ENONPOSITIVE
 * (a spec <= 0), IGEA_EDOMAIN (a quaternion of zero norm where it is read),
 * IGEA_ENOMEM; outputs untouched on failure.
 */
IGEA_API int igea_impact_burnout(int system, int nsamp, const double *traj, int ldt, int nterms,
                                 const int *terms, const int *axes, const double *spec,
                                 const double *site, double tb, double *state, double *E,
                                 int lde);

#ifdef __cplusplus
}
#endif

#endif
