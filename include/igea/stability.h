/*
 * igea/stability.h - stability statistics of a sensor record (METHODS
 * 3.4): the block-mean ("100-second") 3-sigma statistic, overlapping,
 * modified and non-overlapping Allan deviation with confidence intervals
 * from equivalent degrees of freedom, and the identification of random
 * walk, bias instability and rate random walk from an Allan curve.
 *
 * The record y holds rate-type samples (a gyro's rate, an accelerometer's
 * acceleration; in frequency-stability terms "frequency data") taken at fs
 * samples per second. The Allan and Hadamard deviations of every tau of a
 * call are computed in one pass over the record (the integrated phase kept
 * block by block, each block as a double-double base and values relative
 * to it, in a ring as long as the longest lag: about 2 m_max doubles, 3
 * m_max for the modified kinds; sums of squares in blocks, the block totals
 * compensated; docs/stability.md "One pass").
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
 * overlapping ADEV with N = n + 1 phase points; NONOVERLAPPING uses
 * Greenhall and Riley's algorithm (F = m, S = 1, d = 2, N = n + 1, as
 * IGEA_STABILITY_ALLAN_ADEV of igea_stability_dev; earlier versions used
 * the Table 5 formulas with N = B + 1, m = 1); MODIFIED uses Greenhall and Riley's algorithm
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

/* The averaging times igea_stability_allan uses for tau: m = lround(tau fs)
 * samples (halves away from zero), used = m / fs.
 *  1 fs > 0; 2 ntau >= 1; 3 tau[ntau], each with 0.5 <= tau fs < 2^31;
 *  4 used[ntau] out (may be tau itself). Returns 0 or -i (used untouched). */
IGEA_API int igea_stability_taus_used(double fs, int ntau, const double *tau, double *used);

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

/* ---- Stable32's statistics on phase or frequency data (NIST SP 1065) ---- */

/* Kinds of igea_stability_dev, after the three above (which keep their
 * rate-data estimators and SP 1065 Table 5 EDFs in igea_stability_allan).
 * Definitions on the N phase points x_i (seconds of time error, or the
 * running integral of the rate record: x_0 = 0, x_{i+1} = x_i + y_i / fs),
 * tau0 = 1 / fs, tau = m tau0, D2_i = x_{i+2m} - 2 x_{i+m} + x_i,
 * D3_i = x_{i+3m} - 3 x_{i+2m} + 3 x_{i+m} - x_i (docs/stability.md):
 *  ADEV     sum over i = 0, m, 2m, ... of D2_i^2 / (2 M tau^2)   M = floor((N-1)/m) - 1
 *  OADEV    the same over every i                                M = N - 2m
 *  MDEV     sum_j (sum_{i=j}^{j+m-1} D2_i)^2 / (2 m^2 tau^2 M)   M = N - 3m + 1
 *  TDEV     tau MDEV / sqrt 3 (seconds)                          M = N - 3m + 1
 *  HDEV     sum over i = 0, m, ... of D3_i^2 / (6 M tau^2)       M = floor((N-1)/m) - 2
 *  OHDEV    the same over every i                                M = N - 3m
 *  TOTDEV   OADEV of the doubly reflected series x*_{-j} = 2x_0 - x_j,
 *           x*_{N-1+j} = 2x_{N-1} - x_{N-1-j}, over i = 1 .. N-2  M = N - 2, m <= N - 1
 *  MTOTDEV  per 3m-point subsequence: half-average slope removed, extended
 *           by even reflection to 9m points, mean of the 6m squared
 *           second differences of m-point means; / (2 tau^2)     M = N - 3m + 1
 *  TTOTDEV  tau MTOTDEV / sqrt 3                                 M = N - 3m + 1
 *  HTOTDEV  the same on the frequency y_i = (x_{i+1} - x_i) / tau0 with
 *           third differences / 6, divided by its bias 0.995, 0.851,
 *           0.771 for white, flicker, random-walk FM (white FM's for PM)
 *           at the noise type of the tau (OHDEV at m = 1)       M = N - 3m
 *  THEO1    sum_{i=0}^{N-m-1} sum_{d=0}^{m/2-1} [x_i - x_{i-d+m/2} + x_{i+m}
 *           - x_{i+d+m/2}]^2 / (m/2 - d) / (0.75 (N - m) (m tau0)^2), m even,
 *           reported at tau = 0.75 m tau0                        M = N - m
 *  MTIE     max over i of (max - min) of x_i .. x_{i+m} (seconds) M = N - m
 *  TIERMS   sqrt(mean (x_{i+m} - x_i)^2) (seconds)               M = N - m */
#define IGEA_STABILITY_ALLAN_ADEV 3
#define IGEA_STABILITY_ALLAN_OADEV 4
#define IGEA_STABILITY_ALLAN_MDEV 5
#define IGEA_STABILITY_ALLAN_TDEV 6
#define IGEA_STABILITY_ALLAN_HDEV 7
#define IGEA_STABILITY_ALLAN_OHDEV 8
#define IGEA_STABILITY_ALLAN_TOTDEV 9
#define IGEA_STABILITY_ALLAN_MTOTDEV 10
#define IGEA_STABILITY_ALLAN_TTOTDEV 11
#define IGEA_STABILITY_ALLAN_HTOTDEV 12
#define IGEA_STABILITY_ALLAN_THEO1 13
#define IGEA_STABILITY_ALLAN_MTIE 14
#define IGEA_STABILITY_ALLAN_TIERMS 15
/* THEOBR  Theo1 with its bias relative to the Allan variance removed (Taylor
 *          and Howe 2010): k Theo1(m), k = (1 / (n + 1)) sum_{i=0}^{n}
 *          AVAR(9 + 3i) / Theo1(12 + 4i) (the overlapping Allan variance
 *          and Theo1 at the same tau = (9 + 3i) tau0), n = floor(0.1 N / 3)
 *          - 3 >= 0 (N >= 90 phase points); m even, tau = 0.75 m tau0
 *                                                                M = N - m
 *  THEOH   the hybrid (Howe, Taylor and Tasset 2006): the overlapping Allan
 *          deviation at tau < k, THEOBR at tau >= k, k the largest tau0 2^j
 *          <= 0.2 (N - 1) tau0 (N >= 90)                  M as OADEV, THEOBR */
#define IGEA_STABILITY_ALLAN_THEOBR 16
#define IGEA_STABILITY_ALLAN_THEOH 17

/* Data types of igea_stability_dev (IGEA_CHOICE_STABILITY_DATA). */
#define IGEA_STABILITY_DATA_FREQ 0  /* rate / fractional-frequency samples y_i */
#define IGEA_STABILITY_DATA_PHASE 1 /* phase (time error) samples x_i, seconds */

/*
 * Stable32's statistic `kind` at averaging times tau[j]: m_j = round(tau[j]
 * fs) (THEO1, THEOBR and THEOH's THEOBR part: m_j = round(tau[j] fs /
 * 0.75), even), with the noise type per
 * tau, the equivalent degrees of freedom and chi-square intervals.
 * Frequency data of n samples give N = n + 1 phase points (the mean rate is
 * removed first, which no statistic but MTIE and TIERMS sees; these two use
 * the record as it is). Noise type (noise = IGEA_STABILITY_NOISE_AUTO): at
 * each tau on its own (no other tau is consulted), the lag-1
 * autocorrelation r1 (Riley and Greenhall 2004) of the m-sample means less
 * their line (frequency data; alpha = -2 (delta + d)) or of the phase
 * decimated by m less its quadratic (phase data; alpha = 2 - 2 (delta +
 * d)), differenced d = 0, 1, 2 times until delta = r1 / (1 + r1) < 0.25,
 * delta rounded to halves, when at least 30 means exist; else, from 4
 * means, the B1 ratio (standard / Allan variance of the m-means) against
 * its power-law values (geometric-mean boundaries), white and flicker PM
 * told apart by R(n) = MVAR / AVAR (NIST SP 1065 section 5.6), and white
 * FM below 4 means [D] (THEO1 with N >= 90: the type of THEOBR's factor
 * there [D]); THEOBR (and THEOH's THEOBR part): one type for the record,
 * its factor k against the mean nominal Theo1 bias (Howe, Tasset, Percival
 * 2004) over the taus of k [D]; clamped to
 * -2 .. 2. EDF: Greenhall and Riley's algorithm (PTTI 2003; d = 2 for the
 * Allan kinds, d = 3 for the Hadamard kinds, F = 1 for MDEV/TDEV, stride m
 * for the overlapping ones); TOTDEV: SP 1065 Table 7, b N/m - c (white,
 * flicker, random-walk FM; the OADEV EDF for white and flicker PM, [D]);
 * MTOTDEV and TTOTDEV: SP 1065 Table 8; HTOTDEV: (N / m) / (b0 + b1 m /
 * N) (Howe et al. 2000, SP 1065) for m >= 16 and FM noise, OHDEV's below
 * and for PM [D]; THEO1 and THEOBR: Theo1's EDF (Howe and Peppler 2003, SP
 * 1065: r = 0.75 m, the factors r / (r + c) multiplying); THEOH: OADEV's
 * and Theo1's by part. An EDF below 1 is raised to 1. MTIE and TIERMS have
 * no interval: lo, hi and edf must be NULL for them (earlier versions also
 * required it for THEO1 and HTOTDEV). The interval is [s sqrt(edf /
 * chi2_{(1+conf)/2}), s sqrt(edf / chi2_{(1-conf)/2})].
 * Gaps: for ADEV, OADEV, MDEV, TDEV, HDEV and OHDEV a NaN in x is a gap
 * (allantools' gradev): a term that holds one (phase data: one of its
 * points; frequency data: one of the samples it spans, a gap counted as
 * the mean of the others when integrating) is left out, count is the
 * number of terms used, and the EDF is that of a record without gaps with
 * as many terms [D]; the noise identification sees gaps filled (frequency:
 * the mean; phase: the line between neighbours) [D]. A tau whose terms all
 * hold a gap, or a NaN for another kind, is IGEA_ENONFINITE.
 *  1 n >= 2 (THEOBR, THEOH: N >= 90 phase points), 2 x[n] finite (NaN: a
 *  gap, see above), 3 fs > 0 (samples per second), 4 data_type
 *  IGEA_STABILITY_DATA_*, 5 ntau >= 1, 6 tau[ntau] > 0 each with M >= 1
 *  (THEO1, THEOBR: m even), 7 kind IGEA_STABILITY_ALLAN_ADEV .. _THEOH, 8 noise
 *  IGEA_STABILITY_NOISE_*, 9 0 < conf < 1, 10 dev[ntau] out, 11 lo, 12 hi,
 *  13 edf (each ntau, may be NULL; NULL for MTIE, TIERMS),
 *  14 alpha (ntau ints: the noise exponent used at each tau, may be NULL),
 *  15 count (ntau ints: M, the terms used, may be NULL), 16 tau_used (ntau: m
 *  tau0, THEO1 and THEOBR 0.75 m tau0, may be NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENOMEM, IGEA_ENOCONV (a chi-square
 * quantile failed); outputs untouched on failure.
 */
IGEA_API int igea_stability_dev(int n, const double *x, double fs, int data_type, int ntau,
                                const double *tau, int kind, int noise, double conf,
                                double *dev, double *lo, double *hi, double *edf, int *alpha,
                                int *count, double *tau_used);

/* Spacings of igea_stability_taus (IGEA_CHOICE_STABILITY_TAUS). */
#define IGEA_STABILITY_TAUS_OCTAVE 0 /* m = 1, 2, 4, 8, ... */
#define IGEA_STABILITY_TAUS_DECADE 1 /* m = 1, 2, 4, 10, 20, 40, 100, ... */
#define IGEA_STABILITY_TAUS_ALL 2    /* m = 1, 2, 3, ... */

/* Averaging times m / fs (THEO1: 0.75 m / fs, m = 2, 4, 8, ... or even
 * steps) of a spacing while the kind has M >= 1 terms, at most ntau_max.
 *  1 n >= 2 samples, 2 fs > 0, 3 data_type, 4 kind (any IGEA_STABILITY_ALLAN_*;
 *  the first three count on rate samples as igea_stability_octave_taus and
 *  give none for phase data), 5
 *  spacing IGEA_STABILITY_TAUS_*, 6 ntau_max >= 1, 7 tau[ntau_max] out, 8
 *  ntau out (>= 0). Returns 0 or -i. */
IGEA_API int igea_stability_taus(int n, double fs, int data_type, int kind, int spacing,
                                 int ntau_max, double *tau, int *ntau);

/* ---- the record as a stream (a driver reading a file in blocks) ---- */

typedef struct igea_stability_stream igea_stability_stream;

/*
 * A stream of samples for the Allan and Hadamard kinds, whose results equal
 * those of igea_stability_allan (kind IGEA_STABILITY_ALLAN_OVERLAPPING,
 * _MODIFIED, _NONOVERLAPPING: rate data) or igea_stability_dev (_ADEV,
 * _OADEV, _MDEV, _TDEV, _HDEV, _OHDEV on data_type data) on the whole
 * record, bit for bit (the same one pass), without holding the record:
 * memory is a ring of about 2 m_max (3 m_max for the modified kinds)
 * doubles plus the block means of the block statistic. The averaging times
 * are tau[ntau] (ntau >= 1; an average with no term by the end of the
 * record makes the result IGEA_EEMPTY), or with ntau = 0 and tau NULL the
 * octave or decade spacing (IGEA_STABILITY_TAUS_OCTAVE, _DECADE; the rate
 * kinds octaves only), every one that has a term at the end (the ring then
 * grows with the record up to the longest lag). The noise type for the EDF
 * is given, or IGEA_STABILITY_NOISE_AUTO for the rate kinds only (their
 * lag-1 identification from the tau-means, in the pass; the Stable32 kinds
 * identify it on the whole record: igea_stability_dev). block > 0 adds
 * igea_stability_block's statistic of blocks of block seconds (0: none).
 * NaN and infinity are refused by the feed (no gaps: igea_stability_dev
 * takes them).
 *  1 fs > 0, 2 data_type IGEA_STABILITY_DATA_* (PHASE only for the Stable32
 *  kinds), 3 kind (above), 4 noise IGEA_STABILITY_NOISE_* (AUTO only for
 *  the rate kinds), 5 0 < conf < 1, 6 ntau >= 0, 7 tau[ntau] > 0 with
 *  round(tau fs) >= 1 (NULL with ntau = 0), 8 spacing IGEA_STABILITY_TAUS_OCTAVE or
 *  _DECADE (used when ntau = 0),
 *  9 block >= 0 (seconds), 10 out: the new stream (*out NULL on failure).
 * Returns 0, -i, IGEA_ENOMEM.
 */
IGEA_API int igea_stability_stream_create(double fs, int data_type, int kind, int noise,
                                          double conf, int ntau, const double *tau, int spacing,
                                          double block, igea_stability_stream **out);
/* Release a stream (h may be NULL). */
IGEA_API void igea_stability_stream_free(igea_stability_stream *h);
/*
 * Let the stream read back from a file the values its long lags need, so
 * that it holds 1024 blocks of 1024 values (8 MB), not the longest lag:
 * value i of the record (the i-th fed, from 0) is the double in this
 * machine's byte order at byte offset + i stride of fd. Once the lags
 * reach further back than that ring, older values are read with pread
 * (fd's position is neither used nor moved; fd stays open, the caller's,
 * until the stream is freed) a window at a time, and each block read back
 * is checked against the bits of the values fed: a value that cannot be
 * read, or differs from the one fed (the file changed, a wrong offset or
 * stride), makes the feed or the result return IGEA_EREAD, and the stream
 * unusable. The results are those without a source, bit for bit. Call it
 * before the first feed; without a lag beyond the ring nothing changes.
 *  1 h (nothing fed yet), 2 fd >= 0, 3 offset >= 0 (bytes, an exact
 *  integer), 4 8 <= stride <= 131072 (bytes).
 * Returns 0, -i, IGEA_ENOMEM.
 */
IGEA_API int igea_stability_stream_source(igea_stability_stream *h, int fd, double offset,
                                          int stride);
/* The next n >= 0 samples v[n] (rate samples, or phase points for phase
 * data; at most 2^31 - 1 in all). Returns 0, -1 (h NULL), -2 (n < 0), -3
 * (v NULL with n > 0), IGEA_ENONFINITE (a NaN or infinity in v: nothing of
 * v is fed), IGEA_EEMPTY (the stream has ended: its results were asked
 * for), IGEA_ENOMEM (the ring could not grow: the stream is then unusable,
 * and every later call returns IGEA_ENOMEM), IGEA_EREAD (with a source: a
 * value read back, as IGEA_ENOMEM). */
IGEA_API int igea_stability_stream_feed(igea_stability_stream *h, int n, const double *v);
/* The samples fed so far (*n, an exact integer). Returns 0, -1, -2. */
IGEA_API int igea_stability_stream_samples(const igea_stability_stream *h, double *n);
/*
 * The results at the end of the record: *ntau averaging times (at most
 * ntau_max) in tau (the tau used: m / fs), dev, lo, hi, edf (each may be
 * NULL), alpha (the noise exponent used, may be NULL), count (the terms,
 * may be NULL), and block (IGEA_STABILITY_BLOCK_LEN doubles, may be NULL:
 * igea_stability_block's statistic; with fewer than 2 whole blocks
 * block[IGEA_STABILITY_BLOCK_NBLOCK] holds their number, 0 or 1, and the
 * other entries NaN). The record ends with the first call (later feeds
 * are refused); the results may be asked for again.
 *  1 h, 2 ntau_max >= 1, 3 ntau out (one int), 4 tau[ntau_max] out, 5
 *  dev[ntau_max] out, 6 lo[ntau_max], 7 hi[ntau_max], 8 edf[ntau_max], 9
 *  alpha[ntau_max], 10 count[ntau_max] (each may be NULL), 11
 *  block[IGEA_STABILITY_BLOCK_LEN] (may be NULL).
 * Returns 0, -i, IGEA_EEMPTY (fewer than 2 samples, a given tau without a
 * term, or more taus than ntau_max), IGEA_ENONFINITE (a NaN or infinity
 * was fed), IGEA_ENOMEM, IGEA_ENOCONV, IGEA_EREAD (with a source: a value
 * read back); outputs untouched on failure.
 */
IGEA_API int igea_stability_stream_result(igea_stability_stream *h, int ntau_max, int *ntau,
                                          double *tau, double *dev, double *lo, double *hi,
                                          double *edf, int *alpha, int *count, double *block);

/* Terms of igea_stability_fit: the Allan variance of IEEE Std 952 (Annex C)
 * sigma^2(tau) = 3 Q^2 / tau^2 + N^2 / tau + (2 ln2 / pi) B^2 + K^2 tau / 3
 * + R^2 tau^2 / 2. With y in u (deg/h, m/s^2, ...) and tau in s: Q in u s
 * (quantisation), N in u sqrt(s) (angle / velocity random walk), B in u
 * (bias instability), K in u / sqrt(s) (rate random walk), R in u / s (rate
 * ramp). */
#define IGEA_STABILITY_FIT_Q 0
#define IGEA_STABILITY_FIT_N 1
#define IGEA_STABILITY_FIT_B 2
#define IGEA_STABILITY_FIT_K 3
#define IGEA_STABILITY_FIT_R 4
#define IGEA_STABILITY_FIT_LEN 5

/*
 * Weighted least-squares fit of the whole Allan variance curve adev[j]^2 at
 * tau[j] to the five terms, with non-negative variance coefficients c = (Q^2,
 * N^2, B^2, K^2, R^2) (Lawson and Hanson's NNLS on unit-norm columns,
 * Householder QR). The weight of point j is edf[j] / (2 s_j^4), s_j^2 the
 * fitted variance at tau[j], iterated 12 times from the observed one: the
 * Fisher scoring of the maximum-likelihood fit when each estimate is
 * s_j^2 chi2_edf / edf. Covariance of the positive coefficients
 * (A^T W A)^-1, times chi2 / (ntau - p) when that exceeds 1 (the points of
 * one curve are correlated) [D]; a zero coefficient gets the standard
 * error it would have when fitted with the positive ones. A term is
 * supported when its coefficient is positive and the likelihood ratio of
 * the fit with and without it, sum edf_j ((v_j - mu_j) / mu_j - ln(v_j /
 * mu_j)) (gamma deviance) divided by max(1, deviance / (ntau - p)),
 * exceeds 3.84 [D].
 *  1 ntau >= 5, 2 tau[ntau] (> 0, distinct), 3 adev[ntau] (> 0), 4 edf[ntau]
 *  (>= 1), 5 coef[IGEA_STABILITY_FIT_LEN] out: sqrt(c_k) (0 for a zero
 *  coefficient), 6 se[IGEA_STABILITY_FIT_LEN] out: se(c_k) / (2 sqrt(c_k)),
 *  or sqrt(se(c_k)) for a zero coefficient (may be NULL), 7
 *  supported[IGEA_STABILITY_FIT_LEN] out (1 or 0, may be NULL), 8 chi2 out:
 *  the weighted residual sum of squares (may be NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENOMEM; outputs untouched on
 * failure.
 */
IGEA_API int igea_stability_fit(int ntau, const double *tau, const double *adev,
                                const double *edf, double *coef, double *se, int *supported,
                                double *chi2);

/*
 * igea_stability_fit of the curve adev[j] (edf[j]) at tau[j] of a rate
 * record of n samples at fs, with standard errors and intervals from a
 * parametric bootstrap [D]: nboot records of n samples are simulated from
 * the fitted model (white phase Q, white rate N, Kasdin and Walter's
 * flicker rate B, random walk K, ramp R; GSL's MT19937 seeded with seed, so
 * the result is a function of the arguments), the same statistic `kind` is
 * computed on each at the same tau and fitted with the same edf. se is the
 * sample standard deviation of the nboot fitted coefficients; [lo, hi] the
 * interval at confidence conf from the ratio coefficient / truth taken as
 * pivotal: est^2 / q_{(1+conf)/2}, est^2 / q_{(1-conf)/2} with q the
 * replicas' quantiles (hi = INFINITY when q_{(1-conf)/2} = 0; [0,
 * q_{(1+conf)/2}] for est = 0). Both carry the correlation of the
 * estimates at different tau, which igea_stability_fit's se (independent
 * points) leaves out. coef, supported and chi2 are igea_stability_fit's.
 * Cost: nboot times the statistic on n samples, plus two FFTs of the next
 * power of 2 >= 2n per record when B > 0.
 *  1 n >= 2 (the record's samples), 2 fs > 0 (samples per second), 3 kind:
 *  IGEA_STABILITY_ALLAN_OVERLAPPING, _NONOVERLAPPING, _ADEV, _OADEV or
 *  _TOTDEV (frequency data), 4 ntau >= 5, 5 tau[ntau] (s; > 0, distinct,
 *  round(tau fs) with at least one term on n samples), 6 adev[ntau] (> 0),
 *  7 edf[ntau] (>= 1), 8 nboot (2 .. 1e6; >= 200 for 95 % intervals), 9
 *  seed >= 0, 10 conf in (0, 1), 11 coef[IGEA_STABILITY_FIT_LEN] out, 12
 *  se, 13 lo, 14 hi (each IGEA_STABILITY_FIT_LEN out, may be NULL), 15
 *  supported[IGEA_STABILITY_FIT_LEN] out (may be NULL), 16 chi2 out (may be
 *  NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENOMEM, IGEA_ENOCONV (a simulated
 * curve had a zero deviation); outputs untouched on failure.
 */
IGEA_API int igea_stability_fit_boot(int n, double fs, int kind, int ntau, const double *tau,
                                     const double *adev, const double *edf, int nboot, int seed,
                                     double conf, double *coef, double *se, double *lo,
                                     double *hi, int *supported, double *chi2);

#ifdef __cplusplus
}
#endif
#endif
