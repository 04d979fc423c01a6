/*
 * igea/redund.h - redundant inertial sensor sets (METHODS 3.1-3.3):
 * reliability (exponential components, series / parallel / k-out-of-n
 * blocks and block diagrams, the exact reliability of a sensor geometry
 * with its fault-detection and isolation capability), the confidence-
 * distance consistency check, the fusion set and the fused output,
 * parity-space fault detection and isolation, and the windowed check of a
 * multi-sensor record.
 *
 * Indices of sensors in outputs are 0-based (C); -1 means "none".
 * Matrices are column-major with a leading dimension; a matrix argument
 * given with leading dimension 0 where documented stands for one value
 * (its first element) used for every entry.
 */
#ifndef IGEA_REDUND_H
#define IGEA_REDUND_H

#include "igea/common.h"

/* Every sigma array here (sigma, sy, sz, ...) must hold values > 0
 * (IGEA_ENONPOSITIVE), finite (IGEA_ENONFINITE) and >= IGEA_SIGMA_MIN
 * (IGEA_ERANGE: the weights 1/sigma^2 of a smaller one overflow);
 * igea_redund_fuse returns IGEA_EOVERFLOW when its result is not finite. */

#ifdef __cplusplus
extern "C" {
#endif

/* ---- reliability (METHODS 3.1) ---------------------------------------- */

/*
 * Exponential component: R = exp(-lambda t), MTBF = 1 / lambda.
 *  1 lambda  failure rate >= 0, finite
 *  2 t       mission time >= 0, finite
 *  3 R       output reliability
 *  4 mtbf    output MTBF (+Inf for lambda = 0); may be NULL
 */
IGEA_API int igea_redund_exponential(double lambda, double t, double *R,
                                     double *mtbf);

/*
 * Series (all must work), parallel (one suffices) and k-out-of-n (at least
 * k of the n independent components work, exact for unequal R by the
 * Poisson-binomial recursion).
 * series / parallel: 1 n >= 1, 2 R (n reliabilities in [0, 1]), 3 out.
 * kofn: 1 n >= 1, 2 k (1 <= k <= n), 3 R, 4 out.
 * Returns 0, -i, IGEA_ENONFINITE (NaN in R), IGEA_ENOMEM (kofn).
 */
IGEA_API int igea_redund_reliability_series(int n, const double *R, double *out);
IGEA_API int igea_redund_reliability_parallel(int n, const double *R, double *out);
IGEA_API int igea_redund_reliability_kofn(int n, int k, const double *R, double *out);

/* Block types of igea_redund_diagram (reliability block diagram). */
#define IGEA_REDUND_RBD_SERIES 0
#define IGEA_REDUND_RBD_PARALLEL 1
#define IGEA_REDUND_RBD_KOFN 2

/*
 * A reliability block diagram of independent components, evaluated block
 * by block. Block b combines its members member[first[b]] ..
 * member[first[b+1] - 1]; a member index j < ncomp is component j, j >=
 * ncomp is block j - ncomp, which must come before b (so the diagram is a
 * tree evaluated in order; the system is normally the last block). Each
 * component or block may be a member of at most one block (shared members
 * would make blocks dependent).
 *  1 ncomp   components >= 1
 *  2 R       their ncomp reliabilities in [0, 1]
 *  3 nblock  blocks >= 1
 *  4 type    nblock IGEA_REDUND_RBD_* codes
 *  5 k       nblock values of k for KOFN blocks (others ignored); may be
 *            NULL when no block is KOFN
 *  6 first   nblock + 1 offsets into member, first[0] = 0, increasing
 *  7 member  first[nblock] member indices
 *  8 Rblock  output: nblock block reliabilities
 */
IGEA_API int igea_redund_diagram(int ncomp, const double *R, int nblock,
                                 const int *type, const int *k,
                                 const int *first, const int *member,
                                 double *Rblock);

/* Entries of the out array of igea_redund_seed002. */
#define IGEA_REDUND_SEED002_GYRO 0       /* (6) [1 - (1 - Re1)^2]^3 */
#define IGEA_REDUND_SEED002_ACC_EQ7 1    /* (7) as printed */
#define IGEA_REDUND_SEED002_SYS_EQ7 2    /* (8) with (7) */
#define IGEA_REDUND_SEED002_SYS_NO_D 3   /* X4, Y2, Z2 without the skew sensor: (10) */
#define IGEA_REDUND_SEED002_NONREDUND 4  /* (9) Re1^3 Re2^3 */
#define IGEA_REDUND_SEED002_SYS_EXACT 5  /* METHODS 3.2 exact geometric value */
#define IGEA_REDUND_SEED002_ACC_EXACT 6  /* exact accelerometer part */
#define IGEA_REDUND_SEED002_LEN 7

/*
 * The reliability figures of seed 002 (METHODS 3.1 table, 3.2) for gyro
 * reliability Re1 and accelerometer reliability Re2, both in [0, 1].
 *  3 out[IGEA_REDUND_SEED002_LEN]
 */
IGEA_API int igea_redund_seed002(double Re1, double Re2, double *out);

/* Entries of the out array of igea_redund_geometry. */
#define IGEA_REDUND_GEOM_SPAN 0     /* P(surviving axes span 3-D) */
#define IGEA_REDUND_GEOM_DETECT 1   /* ... and any further single fault is detectable */
#define IGEA_REDUND_GEOM_ISOLATE 2  /* ... and any further single fault is isolable */
#define IGEA_REDUND_GEOM_CLASSES 3  /* number of direction classes */
#define IGEA_REDUND_GEOM_LEN 4

/* Largest n for the detection / isolation enumeration (2^n subsets). */
#define IGEA_REDUND_GEOM_FDI_MAX 20
/* Largest number of direction classes for the span enumeration. */
#define IGEA_REDUND_GEOM_CLASS_MAX 24

/*
 * Exact reliability of a sensor geometry (METHODS 3.2): n sensors with
 * input axes h_k (rows of the n x 3 matrix axes; normalised here) and
 * independent survival probabilities R[k].
 *  SPAN: sum over surviving sets A of P(A) [rank H_A = 3], enumerated over
 *  direction classes (|h_k . h_l| > 1 - 1e-12: same class; class survival
 *  1 - prod(1 - R_k)); rank by dgesdd, s3 > 1e-10 s1.
 *  DETECT / ISOLATE (fdi = 1): enumerated over sensor subsets; with the
 *  projector P = I - U U^T onto the parity space of H_A (P = V^T V for the
 *  parity matrix V), a sensor's fault is detectable when its parity column
 *  is non-zero (P_kk > 1e-10) and two faults are distinguishable when their
 *  columns are not parallel (P_kl^2 < (1 - 1e-9) P_kk P_ll). The set counts
 *  for DETECT when every surviving sensor is detectable, for ISOLATE when
 *  in addition no two columns are parallel.
 *  1 n      sensors >= 1 (<= IGEA_REDUND_GEOM_FDI_MAX when fdi = 1)
 *  2 axes   n x 3, rows non-zero
 *  3 lda    >= max(1, n)
 *  4 R      n reliabilities in [0, 1]
 *  5 fdi    0: SPAN only (DETECT, ISOLATE set to NaN), 1: all
 *  6 out    [IGEA_REDUND_GEOM_LEN]
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EDOMAIN (a zero axis), IGEA_ENOMEM,
 * IGEA_ELAPACK.
 */
IGEA_API int igea_redund_geometry(int n, const double *axes, int lda,
                                  const double *R, int fdi, double *out);

/* ---- consistency and fusion (METHODS 3.3) ------------------------------ */

/*
 * Confidence-distance matrix (13): D_ij = |erf((x_j - x_i) / (sqrt2 s_i))|.
 *  1 n >= 1, 2 x[n] finite, 3 sigma[n] > 0, 4 D (n x n out), 5 ldd >= n.
 */
IGEA_API int igea_redund_confidence_distance(int n, const double *x,
                                             const double *sigma, double *D,
                                             int ldd);

/*
 * Thresholds in the measurement's units (METHODS 3.3): delta_ij = sqrt2
 * sigma_i erfinv(alpha_ij); |x_j - x_i| <= delta_ij is d_ij <= alpha_ij.
 *  1 n >= 1, 2 sigma[n] > 0, 3 alpha n x n in (0, 1), 4 lda >= n or 0 (one
 *  alpha[0] for all pairs), 5 delta (n x n out), 6 ldd >= n.
 */
IGEA_API int igea_redund_thresholds(int n, const double *sigma,
                                    const double *alpha, int lda,
                                    double *delta, int ldd);

/*
 * Relation matrix (15): r_ij = 1 when d_ij <= alpha_ij ("i supports j"),
 * else 0; r_ii = 1.
 *  1 n, 2 D (n x n, entries in [0, 1]), 3 ldd >= n, 4 alpha, 5 lda >= n or
 *  0, 6 r (n x n int out), 7 ldr >= n.
 */
IGEA_API int igea_redund_relation(int n, const double *D, int ldd,
                                  const double *alpha, int lda, int *r,
                                  int ldr);

/*
 * The same relation from physical thresholds: r_ij = [|x_j - x_i| <=
 * delta_ij]. 1 n, 2 x[n], 3 delta (n x n, >= 0), 4 ldd >= n or 0, 5 r,
 * 6 ldr >= n.
 */
IGEA_API int igea_redund_relation_delta(int n, const double *x,
                                        const double *delta, int ldd, int *r,
                                        int ldr);

/*
 * Fusion set (METHODS 3.3). Support sup_j = sum over i in F, i != j, of
 * r_ij; need = ceil((|F| - 1) / 2).
 *  iterative = 1: from F = all, remove the sensor of least support while
 *  that least support is below need (tie: the largest column sum of D
 *  within F; a remaining tie removes the highest index [D]).
 *  iterative = 0 (one shot): keep j iff sup_j >= need with F = all.
 *  1 n >= 1, 2 D, 3 ldd >= n, 4 alpha, 5 lda >= n or 0, 6 iterative 0/1,
 *  7 keep[n] out (1 kept, 0 excluded), 8 support[n] out (counts on the full
 *  set; may be NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENOMEM.
 */
IGEA_API int igea_redund_fusion_set(int n, const double *D, int ldd,
                                    const double *alpha, int lda,
                                    int iterative, int *keep, int *support);

/*
 * Fused value (16) over the sensors with keep[i] != 0 (keep NULL: all).
 *  weighted = 1: w_i = s_i^-2 / sum s^-2, fused sigma = (sum s^-2)^-1/2;
 *  weighted = 0: average, fused sigma = sqrt(sum s^2) / |F|.
 *  1 n, 2 x, 3 sigma (> 0), 4 keep, 5 weighted, 6 value, 7 fused_sigma
 *  (may be NULL). IGEA_EEMPTY when no sensor is kept.
 */
IGEA_API int igea_redund_fuse(int n, const double *x, const double *sigma,
                              const int *keep, int weighted, double *value,
                              double *fused_sigma);

/*
 * Probability that a healthy sensor i does not support a healthy sensor j
 * (a false alarm of one pair): |x_j - x_i| > sqrt2 sigma_i erfinv(alpha)
 * with x_j - x_i ~ N(0, noise_i^2 + noise_j^2):
 *   p = 1 - erf(delta / sqrt(2 (noise_i^2 + noise_j^2))).
 * With noise_i = noise_j = sigma_i / k this is the METHODS 3.3 table.
 *  1 sigma_i > 0, 2 noise_i > 0, 3 noise_j > 0, 4 0 < alpha < 1, 5 p.
 */
IGEA_API int igea_redund_false_alarm(double sigma_i, double noise_i,
                                     double noise_j, double alpha, double *p);

/*
 * Several virtual IMUs into one body frame before fusion:
 * out_g = C_g v_g, g = 0..ngroup-1.
 *  1 ngroup >= 1, 2 C: ngroup 3 x 3 column-major matrices one after the
 *  other (9 doubles each), 3 v: 3 x ngroup, 4 out: 3 x ngroup (may not
 *  alias v).
 */
IGEA_API int igea_redund_transform(int ngroup, const double *C,
                                   const double *v, double *out);

/* ---- parity-space fault detection and isolation ------------------------ */

/*
 * Parity matrix V ((m - q) x m, orthonormal rows, V H = 0) of m
 * measurements y = H x + e of a q-vector, from the full SVD of H (dgesdd):
 * the left singular vectors beyond q, each row flipped so that its largest-
 * magnitude entry is positive.
 *  1 m > q, 2 q >= 1, 3 H (m x q), 4 ldh >= m, 5 V out, 6 ldv >= m - q.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ERANK (rank H < q), IGEA_ENOMEM,
 * IGEA_ELAPACK.
 */
IGEA_API int igea_redund_parity(int m, int q, const double *H, int ldh,
                                double *V, int ldv);

/* Entries of the info array of igea_redund_fdi. */
#define IGEA_REDUND_FDI_STAT 0       /* p^T p of the whitened parity vector */
#define IGEA_REDUND_FDI_THRESHOLD 1  /* chi2_pfa(m - q) */
#define IGEA_REDUND_FDI_DOF 2        /* m - q */
#define IGEA_REDUND_FDI_P_VALUE 3    /* Q(stat; m - q) */
#define IGEA_REDUND_FDI_DETECTED 4   /* 1 if stat > threshold */
#define IGEA_REDUND_FDI_ISOLATED 5   /* 0-based sensor, -1 if none */
#define IGEA_REDUND_FDI_ISO_STAT 6   /* its isolation statistic (v_k^T p)^2 / |v_k|^2 */
#define IGEA_REDUND_FDI_ISOLABLE 7   /* 1 if no two parity columns are parallel */
#define IGEA_REDUND_FDI_LEN 8

/*
 * Generalized likelihood test (parity space) of one epoch: measurements
 * y = H x + e, e ~ N(0, diag(sigma^2)). Whitened H_w = H / sigma, y_w =
 * y / sigma; V the parity matrix of H_w; p = V y_w ~ N(0, I_{m-q}) without
 * fault. Detected when p^T p > chi2_pfa(m - q); then the isolated sensor
 * maximises (v_k^T p)^2 / (v_k^T v_k) over sensors with v_k != 0.
 *  1 m > q, 2 q >= 1, 3 H (m x q), 4 ldh >= m, 5 y[m], 6 sigma[m] > 0,
 *  7 0 < pfa < 1, 8 parity: out (m - q), may be NULL, 9 info
 *  [IGEA_REDUND_FDI_LEN], 10 isolated: out (0-based or -1), may be NULL.
 */
IGEA_API int igea_redund_fdi(int m, int q, const double *H, int ldh,
                             const double *y, const double *sigma, double pfa,
                             double *parity, double *info, int *isolated);

/*
 * Skew-sensor check of two 2-sensor channels (METHODS 3.3 [D]): Y and Z
 * cannot be decided by majority, so every pair (Y sensor i, Z sensor j) is
 * compared with the skew sensor D of axis (cy, cz) in the YZ plane:
 *   pi_ij = a_D - (cy a_y,i + cz a_z,j),
 *   fails when |pi_ij| > kappa sqrt(s_D^2 + cy^2 s_y,i^2 + cz^2 s_z,j^2).
 * A Y or Z sensor whose every pair fails is faulty; when all pairs fail,
 * D is the suspect instead [D] (faulty_d = 1, no Y or Z sensor flagged).
 *  1 ny >= 1, 2 ay[ny], 3 sy[ny] > 0, 4 nz >= 1, 5 az[nz], 6 sz[nz] > 0,
 *  7 ad, 8 sd > 0, 9 cy, 10 cz (cy^2 + cz^2 > 0; seed: 1/sqrt2 each), 11
 *  kappa > 0, 12 resid (ny x nz out, ld ny; may be NULL), 13 faulty_y[ny]
 *  out, 14 faulty_z[nz] out, 15 faulty_d out.
 */
IGEA_API int igea_redund_skew_check(int ny, const double *ay, const double *sy,
                                    int nz, const double *az, const double *sz,
                                    double ad, double sd, double cy, double cz,
                                    double kappa, double *resid, int *faulty_y,
                                    int *faulty_z, int *faulty_d);

/* ---- virtual IMUs (seed 002; src/redund_group.c) ----------------------- */

/* Fusion rules of igea_redund_group. */
#define IGEA_REDUND_GROUP_AVERAGE 0  /* the mean of the groups' outputs */
#define IGEA_REDUND_GROUP_WEIGHTED 1 /* per body axis, weights 1 / variance of
                                      * each group's output on that axis (the
                                      * weights w of seed 002 eq. 16) */
#define IGEA_REDUND_GROUP_GLS 2      /* generalised least squares of the
                                      * distinct sensors of all groups [D] */

/*
 * Virtual IMUs made of single-axis sensors (one kind: accelerometers or
 * gyros), as seed 002 groups Ax1..Ax4 with the shared Ay, Az (docs/
 * redundancy.md, "Virtual IMUs"). Sensor i reads y_i = a_i . f + noise_i
 * (noise sd sigma_i, independent) with a_i its input axis from the
 * calibration, in the calibration's reference frame R (its length the
 * scale factor). Group g is the triad member[3g + 0..2] (its x, y, z
 * sensors); its frame F_g (rows: axes in R) is the triad's orthogonalised
 * frame: x along a_x, y in the plane of a_x and a_y, z = x cross y; its
 * compensated output in its own frame is v_g = M_g^-1 y_g, M_g = A_g F_g^T
 * (A_g the rows a_x, a_y, a_z); the body frame is group 0's (the seed
 * takes group 1's), reached by C_g = F_0 F_g^T: u_g = C_g v_g = F_0 A_g^-1 y_g.
 * The fused value is L y (L 3 x nsens by the rule), its covariance
 * L diag(sigma^2) L^T, which counts a sensor that several groups share
 * once; cov_indep is what treating the groups' outputs as independent
 * would state: sum_g W_g Cov(u_g) W_g^T (GLS: equal to cov).
 *  1 nsens >= 3; 2 axes (3 x nsens column-major, finite); 3 sigma[nsens]
 *  (> 0); 4 ngroup >= 1; 5 member (3 x ngroup ints, column-major: sensor
 *  indices 0 .. nsens - 1, distinct within a group); 6 y[nsens] the
 *  readings (finite); 7 fusion IGEA_REDUND_GROUP_*; outputs:
 *  8 frames (may be NULL): 9 x ngroup, C_g column-major, group g's frame
 *    to the body frame;
 *  9 group_out (may be NULL): 3 x ngroup, u_g;
 *  10 fused [3]; 11 cov [9] (3 x 3);
 *  12 cov_indep [9] (may be NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE (a sigma
 * below IGEA_SIGMA_MIN), IGEA_ESINGULAR (a group's axes not independent:
 * |det A_g| <= 1e-12 |a_x| |a_y| |a_z|), IGEA_ENOMEM; outputs untouched on
 * failure.
 */
IGEA_API int igea_redund_group(int nsens, const double *axes, const double *sigma, int ngroup,
                               const int *member, const double *y, int fusion, double *frames,
                               double *group_out, double *fused, double *cov,
                               double *cov_indep);

/*
 * Table 1 of seed 002 ("100-s variance, 3 sigma"): the block statistic of
 * igea_stability_block for every sensor of a multi-sensor record and for
 * every fused channel (docs/redundancy.md, "Table 1").
 * The fused series of channel c is, sample by sample, the mean of the
 * sensors with channel[i] == c (weighted 0), or their weighted mean with
 * w_i = 1 / sigma_b,i^2, sigma_b,i each sensor's own block sigma (weighted
 * 1) [D].
 *  1 nsamp >= 2; 2 nsens >= 1; 3 y (nsamp x nsens column-major, finite);
 *  4 ldy >= nsamp; 5 fs > 0 (Hz); 6 block > 0 (s, at least two whole
 *  blocks); 7 channel[nsens]: each sensor's channel 0 .. nchan - 1, or -1
 *  (not fused); 8 nchan >= 1 (each channel with a sensor); 9 weighted 0 or
 *  1; outputs 10 sens_out (IGEA_STABILITY_BLOCK_LEN x nsens, sensor i at
 *  sens_out[6 i ..]), 11 fused_out (IGEA_STABILITY_BLOCK_LEN x nchan),
 *  12 fused (nsamp x nchan column-major, leading dimension nsamp: the
 *  fused series; may be NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EDOMAIN (weighted: a fused
 * sensor's block sigma is 0), IGEA_ENOMEM; outputs untouched on failure.
 */
IGEA_API int igea_redund_stability(int nsamp, int nsens, const double *y, int ldy, double fs,
                                   double block, const int *channel, int nchan, int weighted,
                                   double *sens_out, double *fused_out, double *fused);

/* ---- windowed check of a record ---------------------------------------- */

/* Number of windows: floor(nsamp / round(window fs)); -i on bad input
 * (1 nsamp >= 1, 2 fs > 0, 3 window > 0 with round(window fs) >= 1). */
IGEA_API int igea_redund_window_count(int nsamp, double fs, double window,
                                      int *nwin);

/* The window actually used: *samples = round(window fs) (halves away from
 * zero, as C's lround) and its length *seconds = samples / fs, the time
 * step of the window start times. 1 fs > 0, 2 window > 0 with
 * round(window fs) >= 1, 3 samples (may be NULL), 4 seconds (may be NULL).
 * Returns 0 or -i. */
IGEA_API int igea_redund_window_length(double fs, double window, int *samples,
                                       double *seconds);

/*
 * Windowed consistency check of nsens redundant sensors measuring the same
 * quantity (columns of y, nsamp x nsens): per window of round(window fs)
 * samples, the window means (compensated sums), the confidence-distance
 * matrix with sigma, the fusion set and the fused value and sigma.
 *  1 nsamp, 2 nsens >= 1, 3 y, 4 ldy >= nsamp, 5 fs > 0, 6 window > 0,
 *  7 sigma[nsens] > 0 (tolerances of the window means), 8 alpha, 9 lda
 *  (>= nsens or 0), 10 iterative, 11 weighted, 12 nwin (must equal
 *  igea_redund_window_count), 13 means (nsens x nwin, ld nsens; may be
 *  NULL), 14 excluded (nsens x nwin ints, ld nsens: 1 excluded), 15 fused
 *  [nwin], 16 fused_sigma [nwin] (may be NULL).
 */
IGEA_API int igea_redund_monitor(int nsamp, int nsens, const double *y,
                                      int ldy, double fs, double window,
                                      const double *sigma, const double *alpha,
                                      int lda, int iterative, int weighted,
                                      int nwin, double *means, int *excluded,
                                      double *fused, double *fused_sigma);

/*
 * The exclusion intervals of igea_redund_monitor's excluded table: each run
 * of consecutive windows in which a sensor was excluded, sensor after
 * sensor (0-based, ascending), runs in time order. Interval k is sensor
 * sensor[k], windows win_start[k] .. win_end[k] - 1 (0-based, end
 * exclusive), times t_start[k] = win_start[k] step and t_end[k] =
 * win_end[k] step with step = round(window fs) / fs, the window length in
 * seconds.
 *  1 nsens >= 1, 2 nwin >= 1, 3 excluded (nsens x nwin ints, ld nsens, as
 *  written by igea_redund_monitor: 0 or 1), 4 fs > 0, 5 window > 0 (as
 *  given to igea_redund_monitor), 6 maxiv >= 0: the room in the five
 *  output arrays (nsens ((nwin + 1) / 2) always suffices; 0 with the
 *  arrays NULL asks for the count alone), 7 niv (out): the number of
 *  intervals, 8 sensor[maxiv], 9 win_start[maxiv], 10 win_end[maxiv],
 *  11 t_start[maxiv], 12 t_end[maxiv] (outputs; t_start and t_end may be
 *  NULL).
 * Returns 0, -i (-6 when the intervals do not fit in maxiv > 0; nothing
 * is written then).
 */
IGEA_API int igea_redund_monitor_intervals(int nsens, int nwin,
                                           const int *excluded, double fs,
                                           double window, int maxiv, int *niv,
                                           int *sensor, int *win_start,
                                           int *win_end, double *t_start,
                                           double *t_end);

/*
 * Simulated static record for the check: y_ki = level_i + noise_i N(0,1),
 * plus fault_bias on sensor fault_sensor for t0 <= k / fs < t1. Draws from
 * GSL's mt19937 seeded with seed, sensor after sensor per sample.
 *  1 nsamp >= 1, 2 nsens >= 1, 3 fs > 0, 4 level[nsens], 5 noise[nsens]
 *  >= 0, 6 fault_sensor (0-based, -1 none), 7 t0, 8 t1, 9 fault_bias, 10
 *  seed >= 0, 11 y (nsamp x nsens out), 12 ldy >= nsamp.
 */
IGEA_API int igea_redund_simulate(int nsamp, int nsens, double fs,
                                  const double *level, const double *noise,
                                  int fault_sensor, double t0, double t1,
                                  double fault_bias, int seed, double *y,
                                  int ldy);

#ifdef __cplusplus
}
#endif
#endif
