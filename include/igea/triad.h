/*
 * igea/triad.h - turntable-free calibration of an IMU's accelerometer triad
 * from a raw record of static attitudes, and of its gyro triad from the
 * rotations between them (docs/calibration.md; the gyro below).
 *
 * The record is held still in a dozen or more different attitudes (a few
 * seconds each, in any order, the orientations unknown), after a first
 * static period. Static intervals are found by a windowed-variance
 * threshold; in each, the mean output m_k is one observation of gravity,
 * whose calibrated magnitude must equal the local g:
 *
 *   a = T K (m - b),   |a_k| = g for every interval k,
 *
 * b the biases (output units), K = diag(k_x, k_y, k_z) the scale factors
 * (output units to m/s^2 or g: whatever unit g is given in), and T the unit
 * lower-triangular non-orthogonality [1 0 0; t_yx 1 0; t_zx t_zy 1] (the
 * calibrated x axis is the sensor's x axis, y lies in the sensors' x-y
 * plane; the rotation of the whole triad is not observable from
 * magnitudes). The 9 parameters are fitted by Levenberg-Marquardt on the
 * residuals |a_k| - g, with their covariance sigma^2 (J^T J)^-1.
 */
#ifndef IGEA_TRIAD_H
#define IGEA_TRIAD_H

#include "igea/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The parameter vector theta[IGEA_TRIAD_NP]. */
#define IGEA_TRIAD_BX 0 /* biases b_x, b_y, b_z (output units) */
#define IGEA_TRIAD_BY 1
#define IGEA_TRIAD_BZ 2
#define IGEA_TRIAD_KX 3 /* scale factors k_x, k_y, k_z (g units per output unit) */
#define IGEA_TRIAD_KY 4
#define IGEA_TRIAD_KZ 5
#define IGEA_TRIAD_TYX 6 /* non-orthogonality t_yx, t_zx, t_zy (rad, small) */
#define IGEA_TRIAD_TZX 7
#define IGEA_TRIAD_TZY 8
#define IGEA_TRIAD_NP 9

/* Indices into opts[IGEA_TRIAD_OPT_LEN]; igea_triad_defaults fills them. */
#define IGEA_TRIAD_OPT_G 0          /* local gravity, in the calibrated unit: 9.80665 */
#define IGEA_TRIAD_OPT_WINDOW 1     /* variance window, s: 2 */
#define IGEA_TRIAD_OPT_INIT 2       /* the first static period, s: 30 */
#define IGEA_TRIAD_OPT_MIN_STATIC 3 /* shortest static interval used, s: 1 */
#define IGEA_TRIAD_OPT_THRESHOLD 4  /* 0: scan k = 1..10; > 0: this k (see below) */
#define IGEA_TRIAD_OPT_MAX_ITER 5   /* Levenberg-Marquardt iterations: 200 */
#define IGEA_TRIAD_OPT_EARTH_RATE 6 /* the Earth's rate in the gyro's calibrated unit
                                       (7.292115e-5 for rad/s); 0: not modelled (the
                                       default: the static rate is all bias) */
#define IGEA_TRIAD_OPT_LAT 7        /* latitude, deg, in [-90, 90]: 0 (with EARTH_RATE) */
#define IGEA_TRIAD_OPT_LEN 16       /* slots 8.. reserved for additions (0) */

/* Indices into info[IGEA_TRIAD_INFO_LEN]. */
#define IGEA_TRIAD_INFO_K 0          /* the threshold multiple k used */
#define IGEA_TRIAD_INFO_THRESHOLD 1  /* the threshold, k zeta_init (output units^2) */
#define IGEA_TRIAD_INFO_INTERVALS 2  /* static intervals fitted */
#define IGEA_TRIAD_INFO_RMS_BEFORE 3 /* rms of |a_k| - g with the start values */
#define IGEA_TRIAD_INFO_RMS_AFTER 4  /* rms of |a_k| - g after the fit */
#define IGEA_TRIAD_INFO_SIGMA 5      /* sqrt(sum r^2 / (intervals - 9)) */
#define IGEA_TRIAD_INFO_ITERATIONS 6 /* Levenberg-Marquardt iterations */
#define IGEA_TRIAD_INFO_ZETA_INIT 7  /* variance magnitude of the first static period */
#define IGEA_TRIAD_INFO_MISFIT 8     /* sigma over the sd the noise of the first static
                                        period predicts for the interval means (about 1;
                                        well above 1: intervals holding motion, a threshold
                                        too high, or a model that does not hold);
                                        igea_triad_calibrate only (NaN from igea_triad_fit) */
#define IGEA_TRIAD_INFO_LEN 16

/* Fill opts[IGEA_TRIAD_OPT_LEN] with the defaults above. Returns 0, -1. */
IGEA_API int igea_triad_defaults(double *opts);

/*
 * Check opts[IGEA_TRIAD_OPT_LEN]: every slot finite (the reserved ones
 * included), g > 0, window > 0, init > 0, min_static > 0, threshold >= 0,
 * 1 <= max_iter <= 10000, earth_rate >= 0, -90 <= lat <= 90. Returns 0, -1 for a NULL opts, else 1 + the
 * first bad slot (igea_opt_name(IGEA_MODULE_TRIAD, slot) names it).
 */
IGEA_API int igea_triad_check_opts(const double *opts);

/*
 * Static intervals of a 3-axis record: zeta_i, the magnitude of the
 * per-axis variances over the window of round(window fs) samples (odd:
 * one more when even) centred on sample i (sqrt(var_x^2 + var_y^2 +
 * var_z^2); window fs >= 2); the samples with zeta_i < threshold; their maximal runs of at
 * least round(min_static fs) samples; the mean of the outputs over each.
 *  1 layout IGEA_ROWMAJOR (sample i, axis j at acc[i lda + j], lda >= 3)
 *  or IGEA_COLMAJOR (acc[i + j lda], lda >= n); 2 n samples (> the window);
 *  3 acc; 4 lda; 5 fs > 0 (Hz); 6 window > 0 (s); 7 threshold > 0
 *  (output units^2); 8 min_static > 0 (s); 9 maxint >= 0: room in the
 *  outputs. Outputs: 10 nint: the number of intervals found (it may exceed
 *  maxint: only the first maxint are written); 11 start[maxint], 12
 *  end[maxint]: sample ranges start <= i < end (both NULL, or neither); 13 means
 *  (3 x maxint, column k the mean output of interval k) (may be NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENOMEM.
 */
IGEA_API int igea_triad_static(int layout, int n, const double *acc, int lda, double fs,
                               double window, double threshold, double min_static,
                               int maxint, int *nint, int *start, int *end, double *means);

/*
 * Fit theta to the static means: 1 nint >= 12 intervals; 2 means (3 x
 * nint, column-major, ld 3); 3 g > 0; 4 theta0[9] the start (may be NULL:
 * zero biases and non-orthogonality, every scale g / median |m_k|); 5
 * max_iter >= 1. Outputs: 6 theta[9]; 7 cov (9 x 9, ldc) the covariance
 * sigma^2 (J^T J)^-1 (may be NULL); 8 ldc >= 9; 9 info[IGEA_TRIAD_INFO_LEN]
 * (may be NULL; slots K, THRESHOLD, ZETA_INIT and MISFIT set to NaN).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ERANK (the attitudes do not
 * determine the 9 parameters: J^T J singular), IGEA_ENOCONV, IGEA_ENOMEM.
 */
IGEA_API int igea_triad_fit(int nint, const double *means, double g, const double *theta0,
                            int max_iter, double *theta, double *cov, int ldc, double *info);

/*
 * The whole calibration from a raw record: zeta_init, the variance
 * magnitude over the first `init` seconds; for k = opts[THRESHOLD] (or
 * each k = 1, ..., 10 when it is 0) the static intervals at threshold
 * k zeta_init and the fit; with the scan, the k that finds the most
 * static intervals (at least 12), and among those the smallest residual sd
 * sigma = sqrt(sum r^2 / (intervals - 9)). (A low threshold breaks the
 * static periods into fragments and keeps fewer of them; a smallest
 * residual alone would favour such fits with fewer observations.)
 *  1 layout, 2 n, 3 acc, 4 lda as igea_triad_static; 5 fs > 0; 6 opts
 *  [IGEA_TRIAD_OPT_LEN]. Outputs: 7 theta[9]; 8 cov (9 x 9, ldc; may be
 *  NULL); 9 ldc >= 9; 10 info[IGEA_TRIAD_INFO_LEN] (may be NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EEMPTY (no threshold gives 12
 * static intervals, or the record is shorter than init), IGEA_ERANK,
 * IGEA_ENOCONV, IGEA_ENOMEM.
 */
IGEA_API int igea_triad_calibrate(int layout, int n, const double *acc, int lda, double fs,
                                  const double *opts, double *theta, double *cov, int ldc,
                                  double *info);

/*
 * Apply a calibration: cal_i = T K (raw_i - b) for n samples.
 *  1 layout, 2 n >= 1, 3 raw, 4 ldr (as igea_triad_static); 5 theta[9];
 *  outputs 6 cal, 7 ldc (the same layout; cal may be raw with ldc = ldr).
 * Returns 0, -i, IGEA_ENONFINITE.
 */
IGEA_API int igea_triad_apply(int layout, int n, const double *raw, int ldr,
                              const double *theta, double *cal, int ldc);


/* ---- the gyroscope triad ---------------------------------------------------
 * The calibrated rate is w = M K (r - b): b the biases (raw units), K =
 * diag(k_x, k_y, k_z) the scale factors (rad/s, or the unit of the rate,
 * per raw unit), M the unit-diagonal misalignment [1 m_xy m_xz; m_yx 1 m_yz;
 * m_zx m_zy 1] (rad, small) referred to the calibrated accelerometer axes:
 * scale + 6 misalignments, the same as a full 3 x 3 matrix S = M K (k_j =
 * S_jj, m_ij = S_ij / S_jj). b is the mean of the gyro over every static
 * interval (the earth's rate, 7.3e-5 rad/s at most, is taken as bias and
 * noise; igea_triad_gyro_fit_earth models it); the 9 others are fitted by
 * Levenberg-Marquardt so that the rotation integrated (quaternion RK4, w
 * linear between samples) from the last sample of each static interval to
 * the first of the next carries
 * the gravity direction seen by the calibrated accelerometer in the first
 * onto that of the second: residuals v_{k+1} - R_k^T v_k (3 per rotation).
 * The covariance: sigma^2 (J^T J)^-1, sigma^2 = sum r^2 / (2 m - 9) (m
 * rotations; two of the three components of each residual are free), plus
 * the accelerometer's and the biases' covariances carried through the
 * fit's linearisation (docs/calibration.md). The gyro record must be in
 * units where the scale factors are near 1 (the fit starts at K = I, M = I):
 * raw counts times a nominal scale factor. */

/* The gyro parameter vector theta_g[IGEA_TRIAD_GYRO_NP]. */
#define IGEA_TRIAD_GYRO_BX 0 /* biases b_x, b_y, b_z (raw units) */
#define IGEA_TRIAD_GYRO_BY 1
#define IGEA_TRIAD_GYRO_BZ 2
#define IGEA_TRIAD_GYRO_KX 3 /* scale factors k_x, k_y, k_z */
#define IGEA_TRIAD_GYRO_KY 4
#define IGEA_TRIAD_GYRO_KZ 5
#define IGEA_TRIAD_GYRO_MXY 6 /* misalignments m_xy, m_xz, m_yx, m_yz, m_zx, m_zy (rad) */
#define IGEA_TRIAD_GYRO_MXZ 7
#define IGEA_TRIAD_GYRO_MYX 8
#define IGEA_TRIAD_GYRO_MYZ 9
#define IGEA_TRIAD_GYRO_MZX 10
#define IGEA_TRIAD_GYRO_MZY 11
#define IGEA_TRIAD_GYRO_NP 12

/* Indices into info_g[IGEA_TRIAD_GYRO_INFO_LEN]. */
#define IGEA_TRIAD_GYRO_INFO_PAIRS 0          /* rotations fitted (intervals - 1) */
#define IGEA_TRIAD_GYRO_INFO_RMS_BEFORE 1     /* rms |v_{k+1} - R_k^T v_k| at K = I, M = I (rad) */
#define IGEA_TRIAD_GYRO_INFO_RMS_AFTER 2      /* the same after the fit (rad) */
#define IGEA_TRIAD_GYRO_INFO_SIGMA 3          /* sqrt(sum r^2 / (2 m - 9)) (rad) */
#define IGEA_TRIAD_GYRO_INFO_ITERATIONS 4     /* Levenberg-Marquardt iterations */
#define IGEA_TRIAD_GYRO_INFO_STATIC_SAMPLES 5 /* samples the biases are the mean of */
#define IGEA_TRIAD_GYRO_INFO_NOISE_X 6        /* pooled within-interval sd per axis (raw units) */
#define IGEA_TRIAD_GYRO_INFO_NOISE_Y 7
#define IGEA_TRIAD_GYRO_INFO_NOISE_Z 8
#define IGEA_TRIAD_GYRO_INFO_MISFIT 9         /* sigma over the sd the gyro noise of the first
                                                 interval predicts (mean over the rotations of
                                                 steps dt^2 mean_j k_j^2 var_j); about 1, well
                                                 above: motion in the intervals or a model that
                                                 does not hold */
/* With the Earth's rate (igea_triad_gyro_fit_earth, or EARTH_RATE > 0 in
 * igea_triad_calibrate_imu's opts; 0 otherwise): */
#define IGEA_TRIAD_GYRO_INFO_EARTH_H 10    /* |x|, the horizontal Earth rate estimated
                                              from the static intervals (about
                                              W cos(lat): a check) */
#define IGEA_TRIAD_GYRO_INFO_EARTH_H_SD 11 /* its sd */
#define IGEA_TRIAD_GYRO_INFO_HEADING 12    /* the heading of the calibrated x axis in
                                              the first static interval, deg from
                                              north towards east, in [0, 360) */
#define IGEA_TRIAD_GYRO_INFO_HEADING_SD 13 /* its sd, deg */
#define IGEA_TRIAD_GYRO_INFO_EARTH_ITER 14 /* alternations of the rotation fit and the
                                              static least squares */
#define IGEA_TRIAD_GYRO_INFO_LEN 16

/*
 * Fit the gyro parameters to a record and its static intervals.
 *  1 layout IGEA_ROWMAJOR or IGEA_COLMAJOR, 2 n samples >= 1, 3 gyro (n x
 *  3 raw rates, as acc of igea_triad_static), 4 ldg; 5 fs > 0 (Hz): the
 *  rate samples are 1/fs apart; 6 nint >= 12 static intervals, 7 start
 *  [nint] and 8 end[nint]: sample ranges start <= i < end, increasing,
 *  each at least 2 samples, end <= n (igea_triad_static's); 9 means (3 x
 *  nint, ld 3): the mean raw accelerometer output of each interval; 10
 *  theta_a[9] the accelerometer calibration (igea_triad_fit's); 11 cov_a (9
 *  x 9, ldca) its covariance (may be NULL: not carried into cov); 12 ldca
 *  >= 9 (when cov_a); 13 max_iter >= 1. Outputs: 14 theta[12] (b, k, m);
 *  15 cov (12 x 12, ldc; may be NULL); 16 ldc >= 12 (when cov); 17
 *  info[IGEA_TRIAD_GYRO_INFO_LEN] (may be NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ERANK (the rotations do not span
 * the three axes: the smallest eigenvalue of sum_k d_k d_k^T, d_k the
 * bias-free raw rate summed over rotation k, below 1e-4 of its trace; or
 * they do not determine the 9 parameters), IGEA_ENOCONV, IGEA_ENOMEM.
 */
IGEA_API int igea_triad_gyro_fit(int layout, int n, const double *gyro, int ldg, double fs,
                                 int nint, const int *start, const int *end, const double *means,
                                 const double *theta_a, const double *cov_a, int ldca,
                                 int max_iter, double *theta, double *cov, int ldc, double *info);

/*
 * The same with the Earth's rate (docs/calibration.md, "The Earth's rate")
 * [D]: in static interval k the gyro reads b + S^-1 w_k with w_k the
 * Earth's rate in the body, W sin(lat) v_k along the calibrated gravity
 * direction v_k (known) plus a horizontal part h_k (W cos(lat) towards
 * north: it needs the heading, which is not known). The rotation between
 * intervals k and k + 1 carries an Earth-fixed vector as M_k = R_k^T E_k,
 * E_k = exp([w_k x] dt_k) the Earth's turn during it, so that every h_k =
 * P_k G_k E0 x follows from one horizontal vector x (2 numbers) at the
 * first interval (G_k = M_{k-1} ... M_0, E0 a basis of the plane normal to
 * v_0, P_k = I - v_k v_k^T). The fit alternates Levenberg-Marquardt on the
 * residuals v_{k+1} - R_k^T E_k v_k (with b, x) and the weighted least
 * squares of the static means rbar_k - S^-1 W sin(lat) v_k = b + S^-1 P_k
 * G_k E0 x (weights N_k / s2_j) for b and x, until b and x move by less
 * than 1e-3 of their sds. cov: C_bb from that least squares, C_pp with
 * (b, x)'s covariance carried through the fit's linearisation.
 * Arguments 1-13 as igea_triad_gyro_fit (11 cov_a may be NULL: not
 * carried into cov), and 14 earth_rate >= 0 (the Earth's rate in the
 * gyro's calibrated unit, 7.292115e-5 for rad/s; 0: igea_triad_gyro_fit's
 * model), 15 lat_deg in [-90, 90]; outputs 16
 * theta[12], 17 cov (12 x 12, ldc; may be NULL), 18 ldc >= 12 (when cov),
 * 19 info[IGEA_TRIAD_GYRO_INFO_LEN] (may be NULL; its EARTH_* and
 * HEADING* slots set).
 * Returns as igea_triad_gyro_fit; IGEA_ERANK also when the attitudes do
 * not separate the biases from the horizontal Earth rate (the static
 * least squares' scaled pivot^2 below 1e-8), IGEA_ENOCONV when the
 * alternation does not settle in 50 rounds.
 */
IGEA_API int igea_triad_gyro_fit_earth(int layout, int n, const double *gyro, int ldg, double fs,
                                       int nint, const int *start, const int *end,
                                       const double *means, const double *theta_a,
                                       const double *cov_a, int ldca, int max_iter,
                                       double earth_rate, double lat_deg, double *theta,
                                       double *cov, int ldc, double *info);

/*
 * The whole IMU from one record: igea_triad_calibrate on acc, the static
 * intervals at the threshold it chose, then igea_triad_gyro_fit with the
 * accelerometer's covariance (igea_triad_gyro_fit_earth's model when
 * opts[IGEA_TRIAD_OPT_EARTH_RATE] > 0).
 *  1 layout, 2 n, 3 acc, 4 lda as igea_triad_static; 5 gyro (n x 3, the
 *  same instants and layout), 6 ldg; 7 fs > 0; 8 opts[IGEA_TRIAD_OPT_LEN].
 *  Outputs: 9 theta_a[9]; 10 cov_a (9 x 9, ldca; may be NULL); 11 ldca >= 9
 *  (when cov_a); 12 theta_g[12]; 13 cov_g (12 x 12, ldcg; may be NULL); 14
 *  ldcg >= 12 (when cov_g); 15 info_a[IGEA_TRIAD_INFO_LEN] (may be NULL);
 *  16 info_g[IGEA_TRIAD_GYRO_INFO_LEN] (may be NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EEMPTY (as igea_triad_calibrate, or
 * intervals of one sample), IGEA_ERANK, IGEA_ENOCONV, IGEA_ENOMEM.
 */
IGEA_API int igea_triad_calibrate_imu(int layout, int n, const double *acc, int lda,
                                      const double *gyro, int ldg, double fs, const double *opts,
                                      double *theta_a, double *cov_a, int ldca, double *theta_g,
                                      double *cov_g, int ldcg, double *info_a, double *info_g);

/*
 * Apply a gyro calibration: w_i = M K (raw_i - b) for n samples.
 *  1 layout, 2 n >= 1, 3 raw, 4 ldr (as igea_triad_static); 5 theta[12];
 *  outputs 6 cal, 7 ldc (the same layout; cal may be raw with ldc = ldr).
 * Returns 0, -i, IGEA_ENONFINITE.
 */
IGEA_API int igea_triad_gyro_apply(int layout, int n, const double *raw, int ldr,
                                   const double *theta, double *cal, int ldc);

#ifdef __cplusplus
}
#endif

#endif
