/*
 * igea/stability.h - stability statistics of a sensor record (METHODS
 * 3.4): the block-mean ("100-second") 3-sigma statistic, overlapping,
 * modified and non-overlapping Allan deviation with confidence intervals
 * from equivalent degrees of freedom, and the identification of random
 * walk, bias instability and rate random walk from an Allan curve.
 *
 * The record y holds rate-type samples (a gyro's rate, an accelerometer's
 * acceleration; in frequency-stability terms "frequency data") taken at fs
 * samples per second. All sums are compensated; the Allan routines need
 * no memory beyond their outputs (running window sums, O(n) per tau).
 */
#ifndef IGEA_STABILITY_H
#define IGEA_STABILITY_H

#include "igea/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Entries of the out array of igea_stability_block. */
#define IGEA_STABILITY_BLOCK_3SIGMA 0  /* 3 sigma_b */
#define IGEA_STABILITY_BLOCK_SIGMA 1   /* sigma_b: sample sd of the block means */
#define IGEA_STABILITY_BLOCK_NBLOCK 2  /* B, the number of whole blocks */
#define IGEA_STABILITY_BLOCK_NSAMP 3   /* N_b = round(block fs) samples per block */
#define IGEA_STABILITY_BLOCK_MEAN 4    /* mean of the block means */
#define IGEA_STABILITY_BLOCK_ADEV 5    /* sqrt(sum (m_{b+1} - m_b)^2 / (2 (B - 1))) */
#define IGEA_STABILITY_BLOCK_LEN 6

/*
 * Block-mean statistic (METHODS 3.4): N_b = round(block fs), B = floor(n /
 * N_b) non-overlapping blocks (a remainder is ignored), block means m_b,
 * sigma_b = sqrt(sum (m_b - mean)^2 / (B - 1)).
 *  1 n >= 2, 2 y[n] finite, 3 fs > 0, 4 block > 0 (seconds) with B >= 2,
 *  5 out[IGEA_STABILITY_BLOCK_LEN].
 */
IGEA_API int igea_stability_block(int n, const double *y, double fs,
                                  double block, double *out);

/* Allan variance kinds. */
#define IGEA_STABILITY_ALLAN_OVERLAPPING 0
#define IGEA_STABILITY_ALLAN_MODIFIED 1
#define IGEA_STABILITY_ALLAN_NONOVERLAPPING 2

/* Power-law noise exponents alpha of S_y(f) ~ f^alpha for the EDF, and
 * IGEA_STABILITY_NOISE_AUTO: identified per tau by the lag-1 autocorrelation of the
 * tau-averages (Riley and Greenhall 2004; with fewer than 32 averages the
 * type found at the previous tau, white FM at the first, is kept).
 * Inertial names: white FM = angle / velocity random walk, flicker FM =
 * bias instability, random-walk FM = rate random walk, white PM =
 * quantisation. */
#define IGEA_STABILITY_NOISE_WPM 2
#define IGEA_STABILITY_NOISE_FPM 1
#define IGEA_STABILITY_NOISE_WFM 0
#define IGEA_STABILITY_NOISE_FFM (-1)
#define IGEA_STABILITY_NOISE_RWFM (-2)
#define IGEA_STABILITY_NOISE_AUTO 99

/*
 * Allan deviation at averaging times tau[j] (m_j = round(tau[j] fs) >= 1
 * samples; the tau actually used is m_j / fs).
 *  OVERLAPPING: s^2 = sum_{i=0}^{n-2m} (A_{i+m} - A_i)^2 / (2 m^2 (n-2m+1)),
 *    A_i = sum_{k=i}^{i+m-1} y_k                        (count n - 2m + 1)
 *  MODIFIED: s^2 = sum_j (sum_{i=j}^{j+m-1} (A_{i+m} - A_i))^2
 *    / (2 m^4 (n-3m+2))                                 (count n - 3m + 2)
 *  NONOVERLAPPING: block means of m samples, s^2 = sum (m_{b+1} - m_b)^2 /
 *    (2 (B - 1))                                        (count B - 1)
 * EDF: the approximations of NIST SP 1065 (Table 5, Howe et al.) for the
 * overlapping ADEV with N = n + 1 phase points; NONOVERLAPPING uses them
 * with N = B + 1, m = 1; MODIFIED uses Greenhall and Riley's algorithm
 * (PTTI 2003, F = 1, S = m, d = 2, their Table 1 beyond J = 100), and the
 * overlapping formula at m = 1 where the two estimators coincide. An EDF
 * below 1 is raised to 1. The interval is
 * [s sqrt(edf / chi2_{(1+conf)/2}(edf)), s sqrt(edf / chi2_{(1-conf)/2}(edf))]
 * with lower chi-square quantiles.
 *  1 n >= 2, 2 y[n] finite, 3 fs > 0, 4 ntau >= 1, 5 tau[ntau] > 0 each
 *  with count >= 1, 6 kind IGEA_STABILITY_ALLAN_*, 7 noise IGEA_STABILITY_NOISE_*, 8 0 < conf
 *  < 1 (0.683 for 1 sigma), 9 dev[ntau] out, 10 lo, 11 hi, 12 edf (each
 *  ntau, may be NULL), 13 count (ntau ints, may be NULL).
 */
IGEA_API int igea_stability_allan(int n, const double *y, double fs, int ntau,
                                  const double *tau, int kind, int noise,
                                  double conf, double *dev, double *lo,
                                  double *hi, double *edf, int *count);

/* Octave averaging times tau = 2^k / fs, k = 0, 1, ... while the kind's
 * count stays >= 1 (and at most ntau_max of them).
 *  1 n >= 2, 2 fs > 0, 3 kind, 4 ntau_max >= 1, 5 tau out, 6 ntau out. */
IGEA_API int igea_stability_octave_taus(int n, double fs, int kind,
                                        int ntau_max, double *tau, int *ntau);

/* Entries of the out array of igea_stability_noise_id. */
#define IGEA_STABILITY_NOISEID_N 0        /* random walk coefficient: sigma(1 s) of the -1/2 line */
#define IGEA_STABILITY_NOISEID_N_TAU 1    /* tau where the -1/2 slope was read */
#define IGEA_STABILITY_NOISEID_B 2        /* bias instability: min sigma / sqrt(2 ln2 / pi) */
#define IGEA_STABILITY_NOISEID_B_TAU 3    /* tau of the minimum */
#define IGEA_STABILITY_NOISEID_K 4        /* rate random walk: sigma(3 s) of the +1/2 line */
#define IGEA_STABILITY_NOISEID_K_TAU 5
#define IGEA_STABILITY_NOISEID_Q 6        /* quantisation: sigma(sqrt3 s) of the -1 line */
#define IGEA_STABILITY_NOISEID_Q_TAU 7
#define IGEA_STABILITY_NOISEID_LEN 8

/*
 * Noise terms from an Allan deviation curve (IEEE Std 952 slope method):
 * over each pair of neighbouring points the log-log slope; for -1 and -1/2
 * the shortest-tau pair within 0.1 of the slope (the most precise point of
 * that region), else, and for +1/2, the pair nearest to the slope (within
 * 0.15), gives the coefficient from the geometric means of the pair:
 * Q = s tau / sqrt3,
 * N = s sqrt(tau), K = s sqrt(3 / tau); B = min s / 0.664282 when the
 * minimum is interior. Terms not identified are NaN (their tau too).
 *  1 ntau >= 2, 2 tau (increasing, > 0), 3 adev (> 0), 4 out.
 */
IGEA_API int igea_stability_noise_id(int ntau, const double *tau,
                                     const double *adev, double *out);

#ifdef __cplusplus
}
#endif
#endif
