/*
 * igea/dw.h - telemetry minus tracking: the apparent-velocity differences
 * dW of seed 000 (METHODS 1.1, model dW = S X + e) at the tracking epochs,
 * in the launch-inertial frame LI, from the raw records (docs/pipeline.md).
 *
 *   dW(t) = W_tel(t) - W_trk(t),
 *   W_trk(t) = v_LI(t) - v_LI(0) - int_0^t g_J2(r_LI) dt  (tracking),
 *   W_tel(t) = int_0^t f dt (telemetry navigation, igea/nav.h),
 *
 * t = 0 being lift-off, where the vehicle is at the launch point at rest on
 * the Earth (v_LI(0) = w x r0 in LI) and W = 0. The gravity integral
 * follows the tracked path: between consecutive epochs (and from lift-off
 * to the first) the path is the cubic Hermite interpolant of the tracked
 * LI positions and velocities, integrated with 4-point Gauss-Legendre
 * (error O(h^4) in the position, h the epoch spacing: gaps and unequal
 * spacing are allowed, a long gap costs accuracy). The telemetry's W is
 * summed exactly at its record times and interpolated between them by the
 * cubic Lagrange polynomial through the four nearest records (fewer when
 * the record has fewer).
 *
 * Navigated kind: dV(t) = v_nav(t) - v_LI(t), the telemetry's navigated
 * LI velocity (igea_nav_step with J2 gravity from the pad state at
 * lift-off; cubic Lagrange between records) minus the tracked one; its
 * error model is the velocity with the gravity-gradient coupling of
 * METHODS 5.4 (envfun's IGEA_ENVFUN_VELOCITY_G).
 *
 * Clock offset tau: the telemetry record stamped s was taken at tracking
 * time s + tau (lift-off, the first record, is at tracking time t_0 +
 * tau). A given time_offset is applied; the first-order effect of a
 * remaining offset tau is dW = dw_dtau tau, dw_dtau = f(t) - f_pad - w x
 * W(t) to first order (f_pad the specific force at rest on the pad, w the
 * Earth rate: the offset also moves lift-off and so turns LI), whose
 * leading term is f: an estimable column to append to S (term
 * time_offset). It is computed as the exact partial of this map, by
 * central differences in time_offset with a 1 ms step.
 *
 * Telemetry array (column-major ntel x tel_cols, leading dimension ldtel):
 * row k holds t_k (s, strictly increasing) and the increments over
 * (t_{k-1}, t_k]; row 0 is lift-off (its increments are not used).
 * Strapdown: tel_cols = 7, t dvx dvy dvz (body, m/s) dthx dthy dthz (body,
 * rad). Platform: tel_cols = 4 or 7, t dvx dvy dvz along LI (= platform)
 * axes; columns 4-6 are not read.
 *
 * Tracking array (column-major ntrk x trk_cols, leading dimension ldtrk):
 * t x y z vx vy vz (s, m, m/s; frame IGEA_NAV_LE or IGEA_NAV_ECEF; t
 * strictly increasing, inside the telemetry span [t_0 + tau, t_last + tau]),
 * then the velocity accuracy: trk_cols 7 none; 8 one sigma (all axes);
 * 10 sigma_x sigma_y sigma_z; 13 the covariance c_xx c_xy c_xz c_yy c_yz
 * c_zz (m^2/s^2, positive definite); 28 the 6 x 6 covariance of the
 * position and velocity (x y z vx vy vz; m^2, m^2/s, m^2/s^2), its upper
 * triangle row by row (21 values: c_x_x c_x_y .. c_x_vz c_y_y .. c_vz_vz),
 * positive definite. The covariance is rotated into LI (the velocity part
 * of the frame change; with 28 columns also the position's through the
 * Earth rate, dv_LI = M (dv + w_f x dr), w_f the Earth rate in the
 * tracking axes; igea_dw_compute leaves out the position's contribution
 * through the gravity integral, which igea_dw_compute_k adds).
 */
#ifndef IGEA_DW_H
#define IGEA_DW_H

#include "igea/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Kinds of velocity difference (IGEA_CHOICE_DW_KIND: apparent navigated). */
#define IGEA_DW_APPARENT 0  /* W_tel - W_trk (METHODS 1.1; envfun's velocity S) */
#define IGEA_DW_NAVIGATED 1 /* v_nav - v_trk (envfun's velocity_g S) */

/*
 * Velocity differences at the tracking epochs.
 * Arguments (1-based positions, as the -i status names them):
 *  1 site        IGEA_NAV_SITE_LEN values (igea_nav_site)
 *  2 system      IGEA_ENVFUN_STRAPDOWN or IGEA_ENVFUN_PLATFORM
 *  3 kind        IGEA_DW_APPARENT or IGEA_DW_NAVIGATED (see above)
 *  4 q0          4 values, the attitude body -> LI at lift-off (normalised
 *                here); may be NULL: 1 0 0 0; platform: ignored
 *  5 time_offset tau (s, finite, |tau| < 1e3)
 *  6 ntel        telemetry records, >= 2
 *  7 tel         ntel x tel_cols (see above)
 *  8 ldtel       >= ntel
 *  9 tel_cols    7 (strapdown) or 4 or 7 (platform)
 * 10 frame       IGEA_NAV_LE or IGEA_NAV_ECEF, the tracking's frame
 * 11 ntrk        tracking epochs, >= 1
 * 12 trk         ntrk x trk_cols (see above)
 * 13 ldtrk       >= ntrk
 * 14 trk_cols    7, 8, 10, 13 or 28
 * 15 dw          output, 3 ntrk: dW epoch-major (x, y, z of epoch 0, ...),
 *                m/s, LI axes: the rows igea_eqerr_run reads
 * 16 cov         output, 6 ntrk: the LI covariance of epoch e at cov[6 e ..
 *                6 e + 5] as c_xx c_xy c_xz c_yy c_yz c_zz; may be NULL
 *                (and must be NULL when trk_cols is 7)
 * 17 dw_dtau     output, 3 ntrk, epoch-major: dW / dtau (m/s^2, see above);
 *                may be NULL
 * 18 bad         output, 1 int: on IGEA_DW_ESPAN or IGEA_DW_ETRACK the
 *                offending tracking row (0-based), on IGEA_DW_ETELEMETRY the
 *                telemetry row; -1 on success
 * Returns 0, -i (outputs untouched), IGEA_ENOMEM, IGEA_ENONFINITE (an input
 * or a result not finite), IGEA_ENONPOSITIVE (a sigma <= 0 or a covariance
 * not positive definite), IGEA_DW_ESPAN, IGEA_DW_ETRACK,
 * IGEA_DW_ETELEMETRY (those three write only bad; other outputs untouched).
 */
IGEA_API int igea_dw_compute(const double *site, int system, int kind, const double *q0,
                             double time_offset, int ntel, const double *tel, int ldtel,
                             int tel_cols, int frame, int ntrk, const double *trk, int ldtrk,
                             int trk_cols, double *dw, double *cov, double *dw_dtau,
                             int *bad);

/*
 * igea_dw_compute with the tracking position error's effect through the
 * gravity integral in the covariance (docs/pipeline.md 4.2 [D]): in the
 * apparent kind with a 6 x 6 tracking covariance (trk_cols 28), the
 * position errors dr_j of every epoch j <= e move the integral of gravity
 * along the tracked path up to epoch e by the partials of its cubic
 * Hermite quadrature (about G dr h per interval, G the J2 gradient, h the
 * epoch spacing), so dW_e's covariance gains a running sum over the
 * earlier epochs and dW of different epochs are correlated: for e < f,
 * Cov(dW_e, dW_f) = X_e, the same block for every later epoch f. The
 * covariance of the stacked dW (3 ntrk) is then the matrix with diagonal
 * blocks cov_e and blocks X_min(e,f) (transposed below the diagonal): not
 * block-diagonal. Tracking errors of different epochs are taken as
 * independent. Other kinds and tracking files: cov as igea_dw_compute and
 * X_e = 0 (the navigated kind has no gravity integral; without the
 * position covariance there is nothing to propagate).
 * Arguments (1-based positions, as the -i status names them):
 *  1-14        as igea_dw_compute
 * 15 dw        output of 3 ntrk values: dW epoch-major, as igea_dw_compute
 * 16 cov       output of 6 ntrk values: per epoch the whole 3 x 3
 *              covariance of dW_e (c_xx c_xy c_xz c_yy c_yz c_zz, the
 *              gravity integral's part included); may be NULL (and must be
 *              NULL when trk_cols is 7)
 * 17 xcov      output, 9 ntrk: X_e row-major at xcov[9 e .. 9 e + 8] (row
 *              i the x, y, z of dW_e, column j those of dW_f, f > e, m^2/s^2);
 *              the last epoch's is 0 (none later); may be NULL (and must be
 *              NULL when cov is NULL)
 * 18 dw_dtau   output of 3 ntrk values, epoch-major: dW / dtau as
 *              igea_dw_compute's 17; may be NULL
 * 19 bad       output, 1 int: as igea_dw_compute's 18
 * Returns as igea_dw_compute (outputs untouched on failure).
 */
IGEA_API int igea_dw_compute_k(const double *site, int system, int kind, const double *q0,
                               double time_offset, int ntel, const double *tel, int ldtel,
                               int tel_cols, int frame, int ntrk, const double *trk, int ldtrk,
                               int trk_cols, double *dw, double *cov, double *xcov,
                               double *dw_dtau, int *bad);

/*
 * The summary of a result of igea_dw_compute:
 *  1 ntrk >= 1 epochs; 2 dw (3 ntrk, epoch-major); 3 cov (6 ntrk, as
 *  igea_dw_compute writes them: xx yx zx yy zy zz per epoch; may be NULL).
 * Outputs: 4 sigma (3 ntrk: the square roots of each epoch's xx, yy, zz;
 *  may be NULL; not written without cov); 5 max_abs, the largest |dW| (may
 *  be NULL); 6 rms[3], the rms of dW per axis (compensated sums; may be NULL).
 * Returns 0, -i, IGEA_ENONFINITE (NaN or Inf in dw or cov) or
 * IGEA_ENONPOSITIVE (a negative variance); outputs untouched on failure.
 */
IGEA_API int igea_dw_summary(int ntrk, const double *dw, const double *cov, double *sigma,
                             double *max_abs, double *rms);

#ifdef __cplusplus
}
#endif
#endif
