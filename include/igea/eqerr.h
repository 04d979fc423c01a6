/*
 * igea/eqerr.h - equivalent-error accuracy assessment of an inertial system
 * from flight-test velocity differences (seed 000; METHODS 1.2 steps 1-7).
 *
 * Model dw = S X + e, S (m x N) the velocity environment functions, columns
 * scaled to the 1-sigma specs so that X ~ N(0, I) when the system is within
 * spec. The normal matrix A = S^T K^-1 S = P diag(lambda) P^T (dsyevd,
 * descending) gives the equivalent errors Xhat_i = p_i^T b / lambda_i,
 * which are independent with Xhat_i ~ N(0, 1 + 1/lambda_i) under H0. The
 * tracking scale sigma_w is estimated from the small eigenvalues and K is
 * rescaled (K <- c K); the components with lambda_i >= lambda_test are then
 * tested one by one (normal) and together (chi-square).
 *
 * Three ways in:
 *  - igea_eqerr_run: whole matrices in memory, eig or SVD route, residuals;
 *  - streamed row blocks: igea_normal_accumulate + igea_eqerr_solve (eig
 *    route) or igea_normal_qr_accumulate + igea_eqerr_solve_qr (SVD
 *    route), then igea_eqerr_coef/igea_eqerr_residual in a second pass;
 *  - igea_stats_accuracy_test on published (Xhat, lambda) tables.
 */
#ifndef IGEA_EQERR_H
#define IGEA_EQERR_H

#include "igea/common.h"
#include "igea/normal.h"
#include "igea/stats.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Indices into opts[IGEA_EQERR_OPT_LEN]; igea_eqerr_defaults fills them. */
#define IGEA_EQERR_OPT_ALPHA 0        /* significance level, 0.01 */
#define IGEA_EQERR_OPT_LAMBDA_TEST 1  /* test components with lambda >= 10 */
#define IGEA_EQERR_OPT_LAMBDA_SMALL 2 /* small eigenvalues: lambda <= 0.1 */
#define IGEA_EQERR_OPT_N_MIN 3        /* at least 5 small eigenvalues */
#define IGEA_EQERR_OPT_TOL 4          /* stop when |sigma_w^2 - 1| <= 0.05 */
#define IGEA_EQERR_OPT_MAX_ITER 5     /* 10 */
#define IGEA_EQERR_OPT_CORRECTION 6      /* 1: correct sigma_w, 0: off */
#define IGEA_EQERR_OPT_RANK_TOL 7     /* 0: default (eig N*10*eps, svd max(m,N)*eps) */
#define IGEA_EQERR_OPT_BIAS_CORRECT 8 /* 1: sigma_w^2 = mean(g^2 - lambda) [D] */
#define IGEA_EQERR_OPT_CLAMP 9        /* 1: never let c fall below 1 [D] */
#define IGEA_EQERR_OPT_Z_CRIT 10      /* > 0: impose z_crit (2.58); 0 exact */
#define IGEA_EQERR_OPT_ROUTE 11       /* IGEA_EQERR_ROUTE_EIG or IGEA_EQERR_ROUTE_SVD */
#define IGEA_EQERR_OPT_VERDICT 12      /* overall verdict rule IGEA_STATS_VERDICT_*: 0 (SEED) */
#define IGEA_EQERR_OPT_OVERALL_SIZE 13 /* 1: also compute the rule's overall size, 0 (see below) */
#define IGEA_EQERR_OPT_VERDICT_N 14    /* n >= 1: slots 15-17 hold the rule's values for n */
#define IGEA_EQERR_OPT_VERDICT_A 15    /* precomputed threshold a on |z_i| (0: none) */
#define IGEA_EQERR_OPT_VERDICT_B 16    /* precomputed threshold b on T */
#define IGEA_EQERR_OPT_VERDICT_SIZE 17 /* precomputed overall size (0: not computed) */
#define IGEA_EQERR_OPT_THREADS 18     /* igea_eqerr_run's normal equations and residual
                                         pass (route eig): 0 or 1 one thread (the sums as
                                         before); n = 2 .. IGEA_EQERR_THREADS_MAX: rows in
                                         segments of IGEA_NORMAL_SEGMENT (8192), each
                                         summed on its own (its sums added in segment
                                         order), on n threads; the result is the same
                                         for every n >= 2 and equals one thread's to
                                         rounding */
#define IGEA_EQERR_THREADS_MAX 256
#define IGEA_EQERR_OPT_LEN 32 /* slots 19.. reserved for additions (0) */

/*
 * The overall verdict (docs/eqerr.md, "Overall size of the verdict").
 * With n = n_test tested components the rule OPT_VERDICT gives a threshold
 * a on |z_i| and b on T = sum z_i^2 (igea_stats_verdict_thresholds): a
 * component is rejected when |z_i| > a, and the flight passes when none is
 * and T < b. SEED (the default): a = z_crit (z_{1-alpha/2} or OPT_Z_CRIT),
 * b = chi2_alpha(n), exactly the seed's test; CHI2: no component test (a =
 * +Inf, reject[] all 0), b = chi2_alpha(n); EXACT: both at one common level
 * so that the overall false-alarm probability is alpha; SIDAK: a at the
 * Sidak level 1 - (1 - alpha)^(1/n), b = chi2_alpha(n). OPT_Z_CRIT > 0 is
 * allowed with SEED only. reject[], info N_REJECT and PASSED are those of
 * the rule; info Z_CRIT and CHI2_CRIT keep their level-alpha meaning, and
 * info VERDICT, VERDICT_Z_CRIT, VERDICT_CHI2_CRIT and OVERALL_SIZE
 * (igea/stats.h) report the rule. The overall size needs the union-size
 * computation (5 ms for n = 7, 2 ms for n = 74 at alpha = 0.01; slower
 * where the fast route does not apply: docs/eqerr.md): EXACT
 * gets it from its thresholds and CHI2 has size alpha; for SEED and SIDAK
 * it is computed only with OPT_OVERALL_SIZE = 1 (else info OVERALL_SIZE is
 * 0, "not computed"; also 0 when n > IGEA_STATS_UNION_N_MAX). EXACT with n
 * > IGEA_STATS_UNION_N_MAX returns IGEA_EVERDICT. igea_sim_montecarlo
 * computes a rule's thresholds once per n_test and thread, not per flight.
 * A caller that judges many flights or pools of one n can do the same:
 * OPT_VERDICT_N = n and OPT_VERDICT_A, _B, _SIZE the values that
 * igea_stats_verdict_thresholds gives for this rule and alpha (a = 0 for
 * CHI2) are used, unchecked, whenever n_test = n (0: none, the default).
 */

#define IGEA_EQERR_ROUTE_EIG 0 /* normal matrix + dsyevd (streamable) */
#define IGEA_EQERR_ROUTE_SVD 1 /* SVD of the weighted S through its QR factor (dtpqrt
                          * + dgesdd), streamable */

/* Fill opts[IGEA_EQERR_OPT_LEN] with the defaults above. Returns 0, -1. */
IGEA_API int igea_eqerr_defaults(double *opts);

/*
 * Check opts[IGEA_EQERR_OPT_LEN] as igea_eqerr_solve, igea_eqerr_solve_qr,
 * igea_eqerr_run and igea_sim_montecarlo do: every slot finite (the
 * reserved ones included), 0 < alpha < 1, lambda_test > 0,
 * lambda_small > 0, n_min >= 1, tol > 0, 1 <= max_iter <= 1000, correct,
 * bias_correct and clamp 0 or 1, 0 <= rank_tol < 1, z_crit >= 0, route
 * IGEA_EQERR_ROUTE_EIG or IGEA_EQERR_ROUTE_SVD, verdict an
 * IGEA_STATS_VERDICT_* code (and z_crit 0 unless it is SEED: the slot
 * named is then verdict), overall_size 0 or 1, verdict_n a whole number
 * 0 .. IGEA_STATS_DOF_MAX, verdict_a >= 0, verdict_b > 0 and 0 <=
 * verdict_size <= 1 when verdict_n > 0. Returns 0 when they are
 * valid, else 1 + the first invalid slot (name it with
 * igea_opt_name(IGEA_MODULE_EQERR, status - 1)); -1 for opts NULL.
 */
IGEA_API int igea_eqerr_check_opts(const double *opts);

/*
 * Steps 1-5 from the normal equations (eig route).
 *  1 N >= 1; 2 A (N x N, lower triangle read), 3 lda >= N; 4 b (N);
 *  5 opts (IGEA_EQERR_OPT_LEN values, or NULL for the defaults);
 * Outputs (caller-owned):
 *  6 lambda[N]  eigenvalues, descending, divided by the final scale c
 *  7 P (N x N), 8 ldp >= N: eigenvectors as columns (METHODS 0.3 signs)
 *  9 equiv_err[N]: Xhat_i for i < rank, 0 beyond
 * 10 z[N]: z_i for tested components (a prefix, i < n_test), 0 beyond
 * 11 reject[N]: 1 rejected, 0 accepted, -1 not tested
 * 12 info[IGEA_STATS_INFO_LEN]: see igea/stats.h (rank, c, iterations, ...)
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENOTESTABLE (no lambda >= lambda_test;
 * nothing is written), IGEA_EVERDICT (the rule cannot be evaluated for
 * n_test components), IGEA_ENOCONV (the rule's thresholds), IGEA_EOVERFLOW (a result, e.g. lambda = s^2 on the
 * SVD route, is not a finite double: rescale the inputs), IGEA_ENOMEM,
 * IGEA_ELAPACK. Every output is finite on success.
 */
IGEA_API int igea_eqerr_solve(int N, const double *A, int lda, const double *b,
                              const double *opts, double *lambda, double *P,
                              int ldp, double *equiv_err, double *z,
                              int *reject, double *info);

/*
 * Steps 1-5 on the SVD route from the streamed QR factor of
 * igea_normal_qr_accumulate: R ((N+1) x (N+1), upper triangle read, ldr >=
 * N + 1) and rows (its row count, >= 1, which sets the rank threshold
 * s_i > max(rows, N) eps s_1). The eigenvalues s_i^2 are resolved down to
 * about eps^2 lambda_1 instead of eps lambda_1 (METHODS 1.2 step 1).
 * Arguments: 1 N, 2 R, 3 ldr, 4 rows, 5 opts (or NULL), 6-12 as
 * igea_eqerr_solve. Same returns.
 */
IGEA_API int igea_eqerr_solve_qr(int N, const double *R, int ldr, double rows,
                                 const double *opts, double *lambda, double *P,
                                 int ldp, double *equiv_err, double *z,
                                 int *reject, double *info);

/*
 * Everything from whole matrices: S (m x N column-major, lds >= m), dw (m),
 * track_sigma (m values, or 1 with sigma_inc = 0), spec_sigma (N or NULL),
 * opts (NULL: defaults; OPT_ROUTE picks eig or SVD). Outputs as
 * igea_eqerr_solve (arguments 10-16 there are 10-16 here), plus
 * 17 residual[m] (dw - S D P_t Xhat_t, physical units) or NULL and
 * 18 rms[3] (per axis x, y, z of epoch-major rows) or NULL.
 *  arguments: 1 m, 2 N, 3 S, 4 lds, 5 dw, 6 track_sigma, 7 sigma_inc,
 *  8 spec_sigma, 9 opts, 10 lambda, 11 P, 12 ldp, 13 equiv_err, 14 z,
 *  15 reject, 16 info, 17 residual, 18 rms.
 * Returns those of igea_eqerr_solve and igea_normal_accumulate:
 * IGEA_ENONFINITE (NaN or Inf in S, dw or a sigma), IGEA_ENONPOSITIVE,
 * IGEA_ERANGE (a sigma or spec below IGEA_SIGMA_MIN), IGEA_EOVERFLOW
 * (finite inputs whose weighted normal matrix or factor overflowed, e.g.
 * S in the wrong units), ...; nothing is written on failure.
 */
IGEA_API int igea_eqerr_run(int m, int N, const double *S, int lds,
                            const double *dw, const double *track_sigma,
                            int sigma_inc, const double *spec_sigma,
                            const double *opts, double *lambda, double *P,
                            int ldp, double *equiv_err, double *z, int *reject,
                            double *info, double *residual, double *rms);

/*
 * igea_eqerr_run with S in either layout (igea/normal.h): 1 layout
 * IGEA_COLMAJOR (S m x N, lds >= m: igea_eqerr_run itself, the same bits)
 * or IGEA_ROWMAJOR (S stored row by row, as C and numpy keep an (m, N)
 * array, lds >= N: no transposed copy is needed). The other arguments are
 * igea_eqerr_run's, one place later: 2 m, 3 N, 4 S, 5 lds, 6 dw[m],
 * 7 track_sigma (m values, or 1 with sigma_inc = 0), 8 sigma_inc,
 * 9 spec_sigma[N] or NULL, 10 opts (or NULL: defaults), 11 lambda[N],
 * 12 P (N x N), 13 ldp >= N, 14 equiv_err[N], 15 z[N], 16 reject[N],
 * 17 info[IGEA_STATS_INFO_LEN], 18 residual[m] or NULL, 19 rms[3] or NULL.
 * The two layouts accumulate the same sums in other orders: their results
 * agree to rounding. Same returns (-1: the layout).
 */
IGEA_API int igea_eqerr_run_layout(int layout, int m, int N, const double *S, int lds,
                                   const double *dw, const double *track_sigma, int sigma_inc,
                                   const double *spec_sigma, const double *opts,
                                   double *lambda, double *P, int ldp, double *equiv_err,
                                   double *z, int *reject, double *info, double *residual,
                                   double *rms);

/*
 * The fitted coefficients in physical units of the raw S columns:
 * coef = D P_t Xhat_t, the sum over the n_test tested components (n_test =
 * info[IGEA_STATS_INFO_N_TEST]); spec_sigma may be NULL (D = I).
 * Arguments: 1 N, 2 P, 3 ldp, 4 equiv_err, 5 n_test (0..N), 6 spec_sigma,
 * 7 coef[N]. Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE,
 * IGEA_ERANGE, IGEA_EOVERFLOW (a coefficient beyond the double range).
 */
IGEA_API int igea_eqerr_coef(int N, const double *P, int ldp,
                             const double *equiv_err, int n_test,
                             const double *spec_sigma, double *coef);

/*
 * Residuals of a block of rows, residual = dw - S coef, for a second pass
 * over a streamed flight. row0 is the index of the block's first row in the
 * flight (rows are epoch-major x, y, z: axis = row % 3); axis_ss (6 values,
 * or NULL) accumulates the sums of squares per axis [0..2] and the row
 * counts [3..5], so rms_a = sqrt(axis_ss[a] / axis_ss[3 + a]).
 * Arguments: 1 layout, 2 m, 3 N, 4 S, 5 lds, 6 dw, 7 coef, 8 row0 >= 0,
 * 9 residual[m] (or NULL), 10 axis_ss.
 * Returns 0, -i, IGEA_ENONFINITE (NaN/Inf in the inputs), IGEA_EOVERFLOW
 * (finite inputs, a residual or a sum of squares overflowed), IGEA_ENOMEM;
 * residual and axis_ss are untouched on failure.
 */
IGEA_API int igea_eqerr_residual(int layout, int m, int N, const double *S,
                                 int lds, const double *dw, const double *coef,
                                 int row0, double *residual, double *axis_ss);

/*
 * igea_eqerr_residual on nthreads threads [D]. Arguments: 1 layout, 2 m,
 * 3 N, 4 S, 5 lds, 6 dw, 7 coef, 8 row0, 9 residual[m] (or NULL), 10
 * axis_ss[6] (or NULL), as igea_eqerr_residual's; 11 nthreads, 0 ..
 * IGEA_NORMAL_THREADS_MAX. With nthreads 0 or 1 it is
 * igea_eqerr_residual, bit for bit. With nthreads >= 2 the rows are cut
 * into segments of IGEA_NORMAL_SEGMENT rows from the block's first row,
 * handed to the threads as they ask for them; each segment's residuals
 * are those of its own matrix-vector product, and its per-axis sums of
 * squares, in row order, are added to axis_ss in segment order. The
 * results are therefore the same for every nthreads >= 2 and equal
 * igea_eqerr_residual's to rounding. The BLAS calls are made
 * on each thread: with an OpenBLAS of several threads of its own, set it to
 * one while this runs. Returns as igea_eqerr_residual; residual and
 * axis_ss are untouched on failure.
 */
IGEA_API int igea_eqerr_residual_threads(int layout, int m, int N, const double *S,
                                         int lds, const double *dw, const double *coef,
                                         int row0, double *residual, double *axis_ss,
                                         int nthreads);

/*
 * Pooled verdict of independent flights (METHODS 1.2 step 6) by the rule
 * IGEA_EQERR_OPT_VERDICT: under H0 the z of all the flights' tested
 * components are independent N(0, 1), so the pooled test is the rule for
 * n = dof_tot = sum of dof[f] components: out of spec when some |z| > a
 * or T_tot = sum of chi2[f] >= b (a, b the rule's thresholds for n; SEED:
 * a = z_{1-alpha/2} or OPT_Z_CRIT, b = chi2_alpha(dof_tot), igea_stats_pool's
 * verdict).
 *  1 nflights >= 1
 *  2 chi2[nflights]  T of each flight, finite, >= 0
 *  3 dof[nflights]   its tested components, >= 1 (sum <= IGEA_STATS_DOF_MAX)
 *  4 z[sum of dof]   the flights' z, flight after flight, finite
 *  5 unit_id[nflights] or NULL: the inertial unit of each flight; a unit
 *    that appears twice returns IGEA_EDEPENDENT
 *  6 opts  IGEA_EQERR_OPT_LEN values or NULL (defaults): alpha, z_crit,
 *    verdict and overall_size are read
 *  7 reject: one flag per z (1 where |z| > a, else 0), or NULL
 *  8 info[IGEA_STATS_INFO_LEN]: as igea_stats_pool, N_REJECT the
 *    components beyond a, PASSED the rule's, VERDICT, VERDICT_Z_CRIT,
 *    VERDICT_CHI2_CRIT and OVERALL_SIZE for n = dof_tot.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EDEPENDENT, IGEA_EVERDICT, IGEA_ENOCONV,
 * IGEA_ENOMEM; reject and info are written only on success. With
 * nflights = 1 it is the rule's verdict on one table of tested z.
 */
IGEA_API int igea_eqerr_pool(int nflights, const double *chi2, const int *dof,
                             const double *z, const int *unit_id, const double *opts,
                             int *reject, double *info);

/*
 * The seed's Table 1 columns of n components: threshold[i] = sqrt(1 +
 * 1/lambda_i) z_crit, the bound on |Xhat_i| (z_crit: the seed's, or the
 * rule's info VERDICT_Z_CRIT), and precision[i] = lambda_i^-1/2, the
 * standard deviation of Xhat_i from the tracking noise alone.
 * Arguments: 1 n >= 1, 2 lambda[n] (> 0), 3 z_crit (finite, >= 0),
 * 4 threshold[n] or NULL, 5 precision[n] or NULL.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE (a lambda <= 0).
 */
IGEA_API int igea_eqerr_limits(int n, const double *lambda, double z_crit,
                               double *threshold, double *precision);

/*
 * Per-axis residual RMS from the sums axis_ss[6] that igea_eqerr_residual
 * accumulates (sums of squares [0..2], row counts [3..5]): rms[a] =
 * sqrt(axis_ss[a] / axis_ss[3 + a]), 0 for an axis without rows.
 * Arguments: 1 axis_ss (6 finite values >= 0), 2 rms[3].
 * Returns 0, -i, IGEA_ENONFINITE.
 */
IGEA_API int igea_eqerr_axis_rms(const double *axis_ss, double *rms);

/*
 * Residual whiteness per axis (x, y, z of epoch-major rows: axis = row %
 * 3): Ljung-Box Q over L lags and the runs test on the signs about the
 * axis's mean (igea/stats.h, igea_stats_diag_*). In memory:
 * igea_eqerr_diag. Streamed over a flight read twice: pass 1
 * igea_eqerr_axis_sums on each block; after the solve, coef
 * (igea_eqerr_coef) and igea_eqerr_residual_mean give each axis's residual
 * mean; igea_stats_diag_init per axis about it; pass 2
 * igea_eqerr_diag_add on each block of residuals; igea_stats_diag_result
 * per axis.
 */

/* Pass-1 sums per axis of a block of rows: for axis a, sums[a (N + 2)] +=
 * rows, [a (N + 2) + 1] += sum of dw, [a (N + 2) + 2 + j] += sum of S_j.
 * Arguments: 1 layout, 2 m >= 0, 3 N >= 1, 4 S, 5 lds, 6 dw (m), 7 row0 >=
 * 0 (the block's first row in the flight), 8 sums[3 (N + 2)] (input-output,
 * zeros at first; counts >= 0). Returns 0, -i, IGEA_ENONFINITE,
 * IGEA_EOVERFLOW, IGEA_ENOMEM; sums untouched on failure. */
IGEA_API int igea_eqerr_axis_sums(int layout, int m, int N, const double *S, int lds,
                                  const double *dw, int row0, double *sums);

/*
 * Pass 1 of a streamed flight in one pass over the block's rows [D]:
 * igea_normal_accumulate_threads (arguments 1-14) and igea_eqerr_axis_sums
 * (15 row0 >= 0, 16 sums[3 (N + 2)], as its 7 and 8) on the same m rows.
 * Each piece of rows is summed per axis just before its dsyrk, which then
 * reads it from cache, and the axis sums stand for a scan of S for NaN
 * and Inf: a caller that hands S over unchecked (a .npy viewed with
 * IGEA_IO_UNCHECKED, igea/io.h) learns of a non-finite value from
 * IGEA_ENONFINITE. With nthreads 0 or 1 the results are those of the two
 * functions called in turn, bit for bit; with nthreads >= 2 each segment of
 * IGEA_NORMAL_SEGMENT rows has its own axis sums too, added in segment
 * order, so they are the same for every nthreads >= 2 and equal the
 * one-thread sums to rounding.
 * Returns 0, -i, the statuses of the two (the normal equations' first:
 * IGEA_ENONFINITE when S, dw or sigma holds a NaN or Inf, IGEA_ENONPOSITIVE,
 * IGEA_ERANGE, IGEA_EOVERFLOW, IGEA_ENOMEM); A, b, wtw and sums are all
 * untouched on failure.
 */
IGEA_API int igea_eqerr_accumulate(int layout, int m, int N, const double *S, int lds,
                                   const double *dw, const double *track_sigma,
                                   int sigma_inc, const double *spec_sigma, double *A,
                                   int lda, double *b, double *wtw, int nthreads, int row0,
                                   double *sums);

/* Mean residual per axis from those sums and the coefficients coef[N]:
 * mean[a] = (sum dw - sum_j (sum S_j) coef_j) / rows, 0 for an axis
 * without rows. Arguments: 1 N, 2 sums[3 (N + 2)], 3 coef[N], 4 mean[3].
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EOVERFLOW. */
IGEA_API int igea_eqerr_residual_mean(int N, const double *sums, const double *coef,
                                      double *mean);

/* Pass 2: a block of m residuals (rows row0 .. row0 + m - 1) into the three
 * states, state[3 IGEA_STATS_DIAG_STATE_LEN] (axis a's at a
 * IGEA_STATS_DIAG_STATE_LEN, each from igea_stats_diag_init; -4
 * otherwise). Arguments: 1 m >= 0, 2 residual, 3 row0 >= 0, 4 state.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EOVERFLOW; state untouched on
 * failure. */
IGEA_API int igea_eqerr_diag_add(int m, const double *residual, int row0, double *state);

/* Both tests per axis of m residuals in memory (row 0 is axis x), each
 * about its axis's mean: out[3 IGEA_STATS_DIAG_LEN], axis a's at a
 * IGEA_STATS_DIAG_LEN; axis_status[3]: 0, or IGEA_EEMPTY (fewer than lags
 * + 2 values on that axis) or IGEA_EDOMAIN (the axis constant), whose out
 * block is then zeros but for its count N. Arguments: 1 m >= 1, 2
 * residual, 3 lags (1 .. IGEA_STATS_DIAG_LAGS_MAX), 4 out, 5 axis_status.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_EOVERFLOW; out and axis_status are
 * written only on success. */
IGEA_API int igea_eqerr_diag(int m, const double *residual, int lags, double *out,
                             int *axis_status);

/*
 * Named components [D]: component i (eigenvector p_i of the spec-scaled
 * normal matrix) as a pattern of the N error terms. share[j + i N] =
 * p_ij^2, the share of term j in component i (the shares of a component
 * sum to 1: p_i has unit norm); loading[j + i N] = spec_j p_ij, the
 * physical error of term j (in its own units) that one unit of the
 * equivalent error Xhat_i stands for (p_ij when spec_sigma is NULL);
 * order[k + i N] = the term of the k-th largest share (ties by index).
 * The terms with share >= IGEA_EQERR_CANDIDATE_SHARE are the candidate
 * causes a rejected component is traced to.
 * Arguments: 1 N >= 1, 2 P (N x N, the eigenvectors of igea_eqerr_*),
 * 3 ldp >= N, 4 ncomp (0..N, e.g. n_test), 5 spec_sigma[N] or NULL,
 * 6 share[N ncomp], 7 loading[N ncomp] or NULL, 8 order[N ncomp] or NULL.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE (a spec),
 * IGEA_EOVERFLOW (a loading beyond the double range); nothing is written
 * on failure.
 */
#define IGEA_EQERR_CANDIDATE_SHARE 0.10
IGEA_API int igea_eqerr_components(int N, const double *P, int ldp, int ncomp,
                                   const double *spec_sigma, double *share,
                                   double *loading, int *order);

#ifdef __cplusplus
}
#endif
#endif
