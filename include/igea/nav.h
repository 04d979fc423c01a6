/*
 * igea/nav.h - navigation core: the WGS-84 ellipsoid, the launch-site
 * frames, J2 gravity with its gradient, and strapdown and platform
 * navigation from velocity and angle increments (docs/pipeline.md).
 *
 * Frames (all right-handed, metres, seconds):
 *  - ECEF: Earth-centred Earth-fixed (WGS-84), z the polar axis.
 *  - LE, the launch-site Earth-fixed frame: origin the launch point; x
 *    horizontal (normal to the ellipsoid's normal) along the firing
 *    azimuth A (from north toward east), y up along the geodetic normal,
 *    z = x cross y (to the right of the firing direction). Its axes in
 *    ECEF are the rows of the site matrix C: v_LE = C v_ECEF.
 *  - LI, the launch-inertial frame: the LE frame frozen at lift-off
 *    (t = 0), then fixed in inertial space; the launch-inertial frame a of
 *    igea/envfun.h (METHODS 5.1). An inertial frame I that coincides with
 *    ECEF at lift-off gives r_I = R(w t) r_ECEF with R(u) the rotation by u
 *    about z (Earth rate w = IGEA_NAV_OMEGA) and r_LI = C (r_I - r0).
 *
 * Times given to the frame functions are seconds since lift-off.
 *
 * A site array (IGEA_NAV_SITE_LEN doubles, written by igea_nav_site)
 * holds the launch point and the frame matrix: lat, lon, height, azimuth,
 * then r0 (ECEF, 3), then C (3 x 3 row-major). Functions taking a site
 * refuse one whose slots are not finite or whose C is not orthonormal.
 *
 * Navigation keeps its state in a caller-owned array (IGEA_NAV_STATE_LEN
 * doubles: constant memory whatever the record length; copy it to keep a
 * snapshot), set by igea_nav_init and advanced one telemetry record at a
 * time by igea_nav_step. Its slots IGEA_NAV_STATE_* may be read; writing
 * them is the caller's risk (igea_nav_step refuses a state that is not
 * finite or whose kind slots are not valid). Strapdown state in LI:
 * quaternion q (scalar first, body -> LI), velocity v, position r,
 * apparent velocity W = int f dt.
 */
#ifndef IGEA_NAV_H
#define IGEA_NAV_H

#include "igea/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* WGS-84 (NIMA TR8350.2, 3rd edition, 2000, tables 3.1 and 3.3). */
#define IGEA_NAV_A 6378137.0                  /* semi-major axis, m */
#define IGEA_NAV_F 3.3528106647474805e-3     /* flattening, 1 / 298.257223563 */
#define IGEA_NAV_GM 3.986004418e14            /* m^3/s^2, atmosphere included */
#define IGEA_NAV_OMEGA 7.292115e-5            /* Earth rate, rad/s */
#define IGEA_NAV_J2 1.082629821313e-3         /* -sqrt(5) C20, C20 = -4.84166774985e-4 */

/* Frames (IGEA_CHOICE_NAV_FRAME: ecef le li). */
#define IGEA_NAV_ECEF 0
#define IGEA_NAV_LE 1
#define IGEA_NAV_LI 2

/* Gravity models (IGEA_CHOICE_NAV_GRAVITY: point_mass j2). */
#define IGEA_NAV_GRAVITY_POINT_MASS 0
#define IGEA_NAV_GRAVITY_J2 1

/* System kinds: IGEA_ENVFUN_STRAPDOWN (0) and IGEA_ENVFUN_PLATFORM (1). */

/* Flags of igea_nav_init (bits; 0 is the full algorithm). */
#define IGEA_NAV_NO_CONING 1   /* attitude from the plain increment sum */
#define IGEA_NAV_NO_SCULLING 2 /* velocity without the sculling term */

/* Site array. */
#define IGEA_NAV_SITE_LAT 0 /* geodetic latitude, rad */
#define IGEA_NAV_SITE_LON 1 /* longitude, rad */
#define IGEA_NAV_SITE_H 2   /* ellipsoidal height, m */
#define IGEA_NAV_SITE_AZ 3  /* firing azimuth from north toward east, rad */
#define IGEA_NAV_SITE_R0 4  /* launch point in ECEF (3), m */
#define IGEA_NAV_SITE_C 7   /* LE axes in ECEF, rows x y z (9) */
#define IGEA_NAV_SITE_LEN 16

/* State array. */
#define IGEA_NAV_STATE_SYSTEM 0  /* system kind */
#define IGEA_NAV_STATE_GRAVITY 1 /* gravity model */
#define IGEA_NAV_STATE_FLAGS 2   /* IGEA_NAV_NO_* bits */
#define IGEA_NAV_STATE_T 3       /* time of the state, s */
#define IGEA_NAV_STATE_R 4       /* position in LI (3), m */
#define IGEA_NAV_STATE_V 7       /* velocity in LI (3), m/s */
#define IGEA_NAV_STATE_Q 10      /* attitude quaternion body -> LI (4; platform 1 0 0 0) */
#define IGEA_NAV_STATE_W 14      /* apparent velocity int f dt in LI (3), m/s */
#define IGEA_NAV_STATE_DTH 17    /* previous angle increment (3), rad */
#define IGEA_NAV_STATE_DV 20     /* previous velocity increment (3), m/s */
#define IGEA_NAV_STATE_SITE 23   /* the site (IGEA_NAV_SITE_LEN) */
#define IGEA_NAV_STATE_LEN 40

/*
 * Geodetic latitude, longitude and ellipsoidal height -> ECEF position.
 * Arguments: 1 lat (rad, |lat| <= pi/2), 2 lon (rad, finite), 3 h (m, >
 * -6e6), 4 r (output, 3 values, m).
 * Returns 0 or -i (r untouched).
 */
IGEA_API int igea_nav_geodetic_to_ecef(double lat, double lon, double h, double *r);

/*
 * ECEF position -> geodetic latitude, longitude (in (-pi, pi]) and height
 * (iterated to convergence in double precision).
 * Arguments: 1 r (3 values, m, finite, sqrt(x^2 + y^2 + z^2) > 1e5), 2 geo
 * (output, 3 values: lat rad, lon rad, h m).
 * Returns 0 or -i (geo untouched).
 */
IGEA_API int igea_nav_ecef_to_geodetic(const double *r, double *geo);

/*
 * The site array of a launch point and firing azimuth.
 * Arguments: 1 lat (rad, |lat| < pi/2), 2 lon (rad, finite), 3 h (m, >
 * -6e6), 4 azimuth (rad, finite), 5 site (output, IGEA_NAV_SITE_LEN).
 * Returns 0 or -i (site untouched).
 */
IGEA_API int igea_nav_site(double lat, double lon, double h, double azimuth, double *site);

/*
 * A position and velocity from one frame to another at time t since
 * lift-off (the Earth having turned by IGEA_NAV_OMEGA t).
 * Arguments: 1 site (IGEA_NAV_SITE_LEN), 2 from, 3 to (IGEA_NAV_ECEF,
 * _LE, _LI), 4 t (s, finite), 5 r_in (3, m), 6 v_in (3, m/s), 7 r_out
 * (output, 3), 8 v_out (output, 3). r_out and v_out may alias r_in and
 * v_in.
 * Returns 0, -i or IGEA_ENONFINITE (an input holds NaN or Inf) with the
 * outputs untouched.
 */
IGEA_API int igea_nav_transform(const double *site, int from, int to, double t,
                                const double *r_in, const double *v_in, double *r_out,
                                double *v_out);

/*
 * The 3 x 3 matrix M with v_to = M v_from for a velocity error (the
 * velocity part of igea_nav_transform's Jacobian; a rotation) at time t
 * since lift-off.
 * Arguments: 1 site, 2 from, 3 to, 4 t (s, finite), 5 M (output, 9,
 * row-major).
 * Returns 0 or -i (M untouched).
 */
IGEA_API int igea_nav_rotation(const double *site, int from, int to, double t, double *M);

/*
 * Gravitation (no centrifugal term) at a position in Earth-centred axes
 * with z the polar axis (ECEF, or the inertial frame I), and its gradient.
 * Arguments: 1 model (IGEA_NAV_GRAVITY_POINT_MASS or IGEA_NAV_GRAVITY_J2), 2 r (3,
 * m, |r| > 1e5), 3 g (output, 3, m/s^2), 4 G (output, 9 row-major,
 * dg_i/dr_j in 1/s^2; may be NULL).
 * Returns 0, -i or IGEA_ENONFINITE (outputs untouched).
 */
IGEA_API int igea_nav_gravity(int model, const double *r, double *g, double *G);

/*
 * The same at a position in LI: g_LI = C g(r0 + C^T r_li), G_LI = C G C^T
 * (the polar axis is fixed in LI, so the result does not depend on time).
 * Arguments: 1 site, 2 model, 3 r_li (3, m), 4 g (output, 3), 5 G
 * (output, 9; may be NULL).
 * Returns 0, -i or IGEA_ENONFINITE (outputs untouched).
 */
IGEA_API int igea_nav_gravity_li(const double *site, int model, const double *r_li,
                                 double *g, double *G);

/*
 * Start a navigation at time t0 (s since lift-off).
 * Arguments: 1 system (IGEA_ENVFUN_STRAPDOWN or IGEA_ENVFUN_PLATFORM),
 * 2 site, 3 gravity (IGEA_NAV_GRAVITY_POINT_MASS or IGEA_NAV_GRAVITY_J2), 4 flags
 * (IGEA_NAV_NO_* bits, 0 .. 3; platform: ignored), 5 t0 (s, finite), 6 q0
 * (4 values, body -> LI, |q0| > 0, normalised here; may be NULL: 1 0 0 0;
 * platform: ignored), 7 r0 (3 values, LI position at t0, m; may be NULL:
 * the launch point, 0), 8 v0 (3 values, LI velocity at t0, m/s; may be
 * NULL: the launch point's inertial velocity w x r0 in LI), 9 state
 * (output, IGEA_NAV_STATE_LEN). W starts at 0, the previous increments at
 * 0.
 * Returns 0 or -i (state untouched).
 */
IGEA_API int igea_nav_init(int system, const double *site, int gravity, int flags, double t0,
                           const double *q0, const double *r0, const double *v0,
                           double *state);

/*
 * One telemetry record: the increments over (t_prev, t], t_prev the state's
 * time. Strapdown (body axes, Savage's two-sample algorithm with the
 * previous record): rotation vector phi = dth + (dth_prev x dth) / 12,
 * q <- q exp(phi / 2); velocity increment in LI C(t_prev) (dv + c1 dth x
 * dv + c2 dth x (dth x dv) + (dth_prev x dv + dv_prev x dth) / 12), with
 * c1 = (1 - cos a) / a^2, c2 = (1 - sin a / a) / a^2, a = |dth| (the
 * rotation compensation exact for constant rates). Platform: dv is along LI
 * axes. Then W += that increment, v += it + g(r_mid) (t - t_prev) (gravity
 * at the predicted mid-interval position), r += (v_prev + v) (t -
 * t_prev) / 2 (trapezoid).
 * Arguments: 1 state (input-output), 2 t (s, > the state's time), 3 dv (3
 * values, m/s), 4 dth (3 values, rad; may be NULL: no rotation; platform:
 * ignored).
 * Returns 0, -i (arguments or a state that igea_nav_init did not make) or
 * IGEA_ENONFINITE (an increment holds NaN or Inf, or the result would);
 * the state is untouched on failure.
 */
IGEA_API int igea_nav_step(double *state, double t, const double *dv, const double *dth);

#ifdef __cplusplus
}
#endif
#endif
