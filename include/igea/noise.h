/*
 * igea/noise.h - tracking noise beyond a diagonal K for the equivalent-error
 * job (docs/eqerr.md, "Tracking noise beyond a diagonal K" [D]):
 *
 *  - igea_whiten_*: a small handle that whitens row blocks while they are
 *    streamed and adds them to the normal equations: each epoch's three
 *    rows (epoch-major x, y, z) by the Cholesky factor of its 3 x 3
 *    covariance (or by the row sigmas), then AR(p) serial correlation per
 *    axis (p <= 3) by the exact Prais-Winsten transform, whose state (the
 *    last p rows of each axis) the handle carries from one block to the
 *    next. Epochs carry a group label (a station, a flight phase); each
 *    group has its own normal equations, and a change of group restarts
 *    the AR filter (segments are independent).
 *  - igea_whiten_accumulate_xcov: the same handle for the whole K of igea
 *    dw, diagonal blocks and cross blocks between epochs (the rows
 *    differenced between epochs, a streamed block-tridiagonal Cholesky
 *    factor); igea_noise_eqerr_xcov the job on it.
 *  - igea_noise_ar_fit: phi per axis, with standard errors, by least
 *    squares of the residuals on their p lags.
 *  - igea_noise_vce: one scale c_g (sigma_w,g^2) per group by Helmert's
 *    variance-component estimation on the full-rank residuals.
 *  - igea_noise_eqerr: the whole job in memory: whitening, phi estimated
 *    and iterated with the group scales until both settle (Cochrane-Orcutt),
 *    optional per-group bias columns eliminated as nuisance terms, an
 *    optional robust route (iterated data snooping on the whitened
 *    residuals), then igea_eqerr_solve on the cleaned weighted normal
 *    equations.
 */
#ifndef IGEA_NOISE_H
#define IGEA_NOISE_H

#include "igea/common.h"
#include "igea/eqerr.h"

#ifdef __cplusplus
extern "C" {
#endif

#define IGEA_NOISE_AR_MAX 3 /* highest AR order */

/* Options of igea_noise_eqerr in the eqerr options array (slots 20..28 of
 * opts[IGEA_EQERR_OPT_LEN]; 0 in every slot is the seed's white noise).
 * igea_eqerr_check_opts checks them; igea_eqerr_run refuses (-9) options
 * that ask for AR, robust or bias columns, which only igea_noise_eqerr
 * and igea_sim_montecarlo do. */
#define IGEA_EQERR_OPT_AR 20     /* p = 0..3: AR(p) per axis, 0 white */
#define IGEA_EQERR_OPT_AR_ESTIMATE 21  /* 1: phi estimated from the residuals
                                          (Cochrane-Orcutt), 0: phi given */
#define IGEA_EQERR_OPT_ROBUST 22       /* 1: data snooping on the whitened residuals */
#define IGEA_EQERR_OPT_ROBUST_ALPHA 23 /* alpha_0 of the w-test, 0 < a < 0.5; 0: 0.001 */
#define IGEA_EQERR_OPT_NOISE_TOL 24    /* phi and c_g settle: |d phi|, |dc/c| <= tol; 0: 1e-3 */
#define IGEA_EQERR_OPT_NOISE_MAX_ITER 25 /* outer iterations, 0..1000; 0: 50 */
#define IGEA_EQERR_OPT_GROUP_BIAS 26   /* 1: per-group, per-axis bias columns (nuisance) */
#define IGEA_EQERR_OPT_ROBUST_MAX 27   /* most rows rejected, a fraction of m; 0: 0.05 */
#define IGEA_EQERR_OPT_AR_METHOD 28    /* how phi is estimated (AR_ESTIMATE 1):
                                          IGEA_NOISE_AR_REML (0, the default) or
                                          IGEA_NOISE_AR_LS */

/* Estimators of phi (IGEA_EQERR_OPT_AR_METHOD; names IGEA_CHOICE_NOISE_AR_METHOD):
 *  REML  (the default) the restricted (residual) maximum likelihood of phi
 *        and the group scales together: the likelihood of the exactly
 *        whitened (Prais-Winsten) rows with the N terms integrated out,
 *        maximised by quasi-Newton steps from the LS start; its score has
 *        expectation zero, so the fitted terms leave no O(N/M) bias [D].
 *        ar_out's standard errors and group_out's IGEA_NOISE_GROUP_SE_REML
 *        come from the inverse of the observed information of phi and the
 *        scales together: a scale's standard error includes phi-hat's
 *        uncertainty (docs/eqerr.md).
 *  LS    least squares of the stage-1 residuals on their p lags, alternated
 *        with the generalised least-squares fit (Cochrane-Orcutt); for p = 1
 *        Kendall's small-sample correction phi + (1 + 3 phi)/(M - 1). The
 *        residuals of a fit of N terms bias phi-hat low by O(N/M) (igea's
 *        only estimator before REML). */
#define IGEA_NOISE_AR_REML 0
#define IGEA_NOISE_AR_LS 1

/* Entries of info[IGEA_STATS_INFO_LEN] that igea_noise_eqerr adds. */
#define IGEA_STATS_INFO_NOISE_ITERATIONS 22 /* outer (phi, c_g, snooping) iterations */
#define IGEA_STATS_INFO_NOISE_CONVERGED 23  /* 1: phi and c_g settled */
#define IGEA_STATS_INFO_N_OUTLIERS 24       /* rows rejected by the robust route */
#define IGEA_STATS_INFO_N_GROUPS 25         /* groups */
#define IGEA_STATS_INFO_N_NUISANCE 26       /* bias columns eliminated */
#define IGEA_STATS_INFO_AR_ORDER 27         /* p */
#define IGEA_STATS_INFO_ROBUST_CRIT 28      /* w-test critical value z_{1-alpha_0/2} */

/* Layout of ar_out of igea_noise_eqerr: phi of lag k + 1 of axis a at
 * ar_out[3 a + k], its standard error at ar_out[9 + 3 a + k] (k < p; the
 * other entries 0). */
#define IGEA_NOISE_AR_OUT_LEN 18
/* Columns of group_out (ngroups x IGEA_NOISE_GROUP_COLS, row-major: group g
 * at group_out + g IGEA_NOISE_GROUP_COLS). */
#define IGEA_NOISE_GROUP_SCALE 0  /* c_g = sigma_w,g^2 (Helmert) */
#define IGEA_NOISE_GROUP_SE 1     /* its standard error, c_g sqrt(2 / r_g) */
#define IGEA_NOISE_GROUP_REDUND 2 /* r_g = n_g - tr(N^+ N_g) / c_g */
#define IGEA_NOISE_GROUP_ROWS 3   /* rows of the group used (after rejections) */
#define IGEA_NOISE_GROUP_BIAS 4   /* 4..6: bias x, y, z (dw units; 0 without bias columns) */
#define IGEA_NOISE_GROUP_SE_REML 7 /* standard error of c_g from the inverse REML
                                      information of all the scales
                                      (igea_noise_vce_cov), the covariance
                                      between groups included [D]; with phi
                                      estimated by IGEA_NOISE_AR_REML, of the
                                      scales and phi together */
#define IGEA_NOISE_GROUP_COLS 8

typedef struct igea_whiten igea_whiten;

/*
 * A whitener for N columns, AR order p and ngroups groups.
 *  1 N        columns of S, >= 1
 *  2 p        AR order 0..IGEA_NOISE_AR_MAX (0: no serial correlation)
 *  3 phi      3 p coefficients, axis-major (phi[a p + k]: lag k + 1 of
 *             axis a), each axis stationary (the roots of 1 - sum phi_k z^k
 *             outside the unit circle, checked by a positive definite
 *             Toeplitz autocorrelation matrix); may be NULL when p = 0
 *  4 ngroups  >= 1
 *  5 w        output: the new handle (NULL on failure)
 * Returns 0, -i (-3 also for a phi that is not stationary),
 * IGEA_ENONFINITE (phi NaN/Inf), IGEA_ENOMEM.
 */
IGEA_API int igea_whiten_create(int N, int p, const double *phi, int ngroups,
                                igea_whiten **w);

/* Release a whitener (NULL is a no-op). */
IGEA_API void igea_whiten_free(igea_whiten *w);

/* The epochs whitened since the last reset (*epochs) and the group of the
 * last one (*group, -1 before the first). Returns 0, -i. */
IGEA_API int igea_whiten_get_state(const igea_whiten *w, double *epochs, int *group);

/* Forget the carried rows: the next block starts a new flight (epoch 0).
 * Returns 0, -1. */
IGEA_API int igea_whiten_reset(igea_whiten *w);

/*
 * Whiten a block of whole epochs and add it to the group normal equations.
 * Row i of the flight is [S_i D, dw_i]; epoch e (rows 3e, 3e+1, 3e+2, axes
 * x, y, z) is whitened by L_e^-1 with C_e = L_e L_e' its covariance (or by
 * 1/sigma_i per row), then each axis a by the Prais-Winsten transform of
 * its AR(p): the first p epochs of a segment by the inverse Cholesky factor
 * of the p x p autocorrelation matrix, later ones by (u_t - sum_k phi_ak
 * u_(t-k)) / sigma_u,a, sigma_u,a^2 = 1 - sum_k phi_ak rho_ak (unit
 * stationary variance, so K is the covariance of the noise).
 *  1 w            the handle
 *  2 layout       IGEA_COLMAJOR or IGEA_ROWMAJOR (as igea/normal.h)
 *  3 m            rows in this block, a multiple of 3, >= 0 (0: no-op)
 *  4 S, 5 lds     the block (m x N), see layout
 *  6 dw           m velocity differences
 *  7 track_sigma  m row sigmas (sigma_inc 1) or one (sigma_inc 0), > 0 and
 *                 >= IGEA_SIGMA_MIN; must be NULL when cov is given
 *  8 sigma_inc    0 or 1
 *  9 cov          6 m / 3 values or NULL: per epoch the lower triangle of
 *                 its 3 x 3 covariance row by row (c_xx, c_yx, c_yy, c_zx,
 *                 c_zy, c_zz), dw units squared
 * 10 group        m / 3 group labels 0 .. ngroups - 1 per epoch, or NULL
 *                 (all 0)
 * 11 mask         m ints or NULL: 1 leaves the whitened row out of the
 *                 sums (a rejected row; the filter still carries it), 0
 *                 keeps it
 * 12 spec_sigma   N specs (> 0, >= IGEA_SIGMA_MIN), or NULL (D = I)
 * 13 A, 14 lda    ngroups blocks N x N (block g at A + g lda N), lda >= N,
 *                 updated in place (both triangles)
 * 15 b            ngroups x N (group g at b + g N), updated
 * 16 wtw          2 ngroups: w'w and the row count per group, updated
 *                 (finite, >= 0)
 * 17 white        m x (N + 1) column-major (ld m) outputs or NULL: the
 *                 whitened rows [S~ w~] of the block, masked ones included
 * 18 bad_epoch    output or NULL: on IGEA_ESINGULAR, the epoch (counted
 *                 from the last reset) whose covariance is not positive
 *                 definite
 * Returns 0, -i (-1 also for a handle igea_whiten_accumulate_xcov has used
 * since its last reset), IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE,
 * IGEA_ESINGULAR (a covariance not positive definite), IGEA_EOVERFLOW,
 * IGEA_ENOMEM. On failure A, b, wtw, white and the handle's state are
 * untouched.
 */
IGEA_API int igea_whiten_accumulate(igea_whiten *w, int layout, int m,
                                    const double *S, int lds, const double *dw,
                                    const double *track_sigma, int sigma_inc,
                                    const double *cov, const int *group,
                                    const int *mask, const double *spec_sigma,
                                    double *A, int lda, double *b, double *wtw,
                                    double *white, int *bad_epoch);

/*
 * The whole covariance K of dW as igea_dw_compute_k gives it: the diagonal
 * blocks K_ee and, for every pair of epochs e < f, Cov(dW_e, dW_f) = X_e
 * (the same block for every later f; K_fe = X_e'), whitened exactly while
 * streamed (docs/eqerr.md, "The whole K: cross blocks between epochs" [D]).
 * The rows differenced between consecutive epochs, d_0 = y_0, d_f = y_f -
 * y_(f-1) (y_f the epoch's three rows of [S D, dw]; the model stays d =
 * (Delta S D) X + noise), have the block-tridiagonal covariance C_ff =
 * K_ff - X_(f-1) - X_(f-1)' + K_(f-1,f-1), C_(f,f-1) = X_(f-1)' -
 * K_(f-1,f-1); with its block Cholesky factor B_f = C_(f,f-1) L_(f-1)^-T,
 * L_f L_f' = C_ff - B_f B_f', the whitened rows of epoch f are w_f = L_f^-1
 * (d_f - B_f w_(f-1)): the standardised innovations of dW_f given every
 * earlier epoch, so w'w = dW' K^-1 dW and the sums are S' K^-1 S etc. of the
 * full K, in O(m N^2) time and O(N^2 + N E) memory whatever the flight's
 * length. A pivot^2 of L_f at or below IGEA_WHITEN_XCOV_RTOL times
 * K_ff,aa + K_(f-1,f-1),aa (the conditional variance of the epoch's axis a
 * given the earlier epochs and axes, against the magnitudes it is computed
 * from: rounding would dominate it) is refused as IGEA_ESINGULAR, naming
 * the epoch (K singular or nearly so there, or the blocks not those of one
 * positive definite K).
 *  1 w           a handle of igea_whiten_create with p = 0 and ngroups = 1,
 *                fresh or reset, or used only by this function since (-1
 *                otherwise); its state carries the last epoch's rows, K_ee,
 *                X_e and factor, so blocks of any size give the same sums
 *  2 layout      IGEA_COLMAJOR or IGEA_ROWMAJOR (as igea/normal.h)
 *  3 m           rows in this block, a multiple of 3, >= 0 (0: no-op)
 *  4 S, 5 lds    the block (m x N), see layout
 *  6 dw          m velocity differences
 *  7 cov         6 m / 3 values: per epoch the lower triangle of K_ee row by
 *                row (c_xx, c_yx, c_yy, c_zx, c_zy, c_zz; igea dw --k-out),
 *                dw units squared
 *  8 xcov        9 m / 3 values: per epoch X_e row-major (row i the axis of
 *                dW_e, column j that of dW_f, f > e; igea dw --xcov-out,
 *                igea_dw_compute_k's xcov); the flight's last epoch's is
 *                not used (none later) but must be finite
 *  9 mask        m ints or NULL: 1 leaves the whitened row out of the sums
 *                (the recursion still carries it), 0 keeps it
 * 10 spec_sigma  N specs (> 0, >= IGEA_SIGMA_MIN), or NULL (D = I)
 * 11 A, 12 lda   N x N, lda >= N, updated in place (both triangles)
 * 13 b           N, updated
 * 14 wtw         2: w'w and the row count, updated (finite, >= 0)
 * 15 white       m x (N + 1) column-major (ld m) outputs or NULL: the
 *                whitened rows [S~ w~] of the block, masked ones included
 * 16 bad_epoch   output or NULL: on IGEA_ESINGULAR, the epoch (counted from
 *                the last reset) refused
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE (specs),
 * IGEA_ESINGULAR, IGEA_EOVERFLOW, IGEA_ENOMEM. On failure A, b, wtw, white
 * and the handle's state are untouched. igea_whiten_accumulate refuses (-1)
 * a handle this function has used since its last reset.
 */
#define IGEA_WHITEN_XCOV_RTOL 1e-10
IGEA_API int igea_whiten_accumulate_xcov(igea_whiten *w, int layout, int m,
                                         const double *S, int lds, const double *dw,
                                         const double *cov, const double *xcov,
                                         const int *mask, const double *spec_sigma,
                                         double *A, int lda, double *b, double *wtw,
                                         double *white, int *bad_epoch);

/*
 * AR(p) coefficients per axis from residuals by least squares on their
 * lags: for axis a, y_t = u_(3t+a) regressed on y_(t-1) .. y_(t-p) over the
 * epochs t whose p predecessors are in the same segment (same group, no
 * change between) and none masked; phi = (X'X)^-1 X'y, s^2 = RSS / (n -
 * p), se_k = s sqrt((X'X)^-1_kk).
 *  1 M       epochs, >= 1
 *  2 p       1 .. IGEA_NOISE_AR_MAX
 *  3 resid   3 M residuals (epoch-major x, y, z) in units of the first
 *            whitening stage (covariance or sigma, not AR)
 *  4 group   M labels or NULL, 5 mask 3 M ints or NULL (1: left out)
 *  6 phi     3 p outputs (axis-major), 7 se 3 p outputs
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ERANK (an axis with n <= p usable
 * epochs or singular X'X); outputs untouched on failure.
 */
IGEA_API int igea_noise_ar_fit(int M, int p, const double *resid,
                               const int *group, const int *mask, double *phi,
                               double *se);

/*
 * Helmert variance components of G groups from their normal equations
 * (as igea_whiten_accumulate leaves them): c_g <- Omega_g / r_g with
 * Omega_g = w_g'w_g - 2 x'b_g + x'N_g x and r_g = n_g - tr(N^+ N_g)/c_g,
 * x = N^+ sum b_g/c_g, N = sum N_g/c_g (pseudo-inverse at rank tolerance
 * N 10 eps), iterated from c = 1 until max |c_new/c - 1| <= tol.
 *  1 N, 2 G >= 1, 3 A (G blocks N x N, lower triangles read), 4 lda >= N,
 *  5 b (G x N), 6 wtw (2 G), 7 tol > 0, 8 max_iter 1..1000
 *  9 scale  G outputs c_g, 10 se G outputs (c_g sqrt(2 / r_g)), 11 redund
 *  G outputs r_g, 12 x N outputs (the last N^+ b), 13 iterations (output)
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ERANK (a group with r_g <= 0),
 * IGEA_EDOMAIN (Omega_g <= 0), IGEA_ENOCONV, IGEA_ENOMEM, IGEA_ELAPACK;
 * outputs untouched on failure.
 */
IGEA_API int igea_noise_vce(int N, int G, const double *A, int lda,
                            const double *b, const double *wtw, double tol,
                            int max_iter, double *scale, double *se,
                            double *redund, double *x, int *iterations);

/*
 * The covariance of the variance components: the inverse of the REML
 * (Fisher) information of the scales c of G groups at the given scales,
 * I_gh = (delta_gh (n_g - 2 tr(Q N_g) / c_g) / c_g^2
 *         + tr(Q N_g Q N_h) / (c_g^2 c_h^2)) / 2,
 * Q = (sum_g N_g / c_g)^+ (pseudo-inverse at rank tolerance N 10 eps), N_g
 * the group's normal matrix, n_g its rows; with one group 2 c^2 / r. The
 * standard error of c_g is sqrt(cov[g + g G]) [D] (docs/eqerr.md).
 *  1 N >= 1, 2 G >= 1
 *  3 A       G blocks N x N (block g at A + g lda N), lower triangles read
 *  4 lda     >= N
 *  5 wtw     2 G: only the row counts wtw[2 g + 1] (>= 0) are read
 *  6 scale   G scales c_g > 0 (as igea_noise_vce returns them)
 *  7 cov     G x G output (symmetric, column-major), units c^2
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ERANK (information not positive
 * definite), IGEA_EOVERFLOW, IGEA_ENOMEM, IGEA_ELAPACK; cov untouched on
 * failure.
 */
IGEA_API int igea_noise_vce_cov(int N, int G, const double *A, int lda,
                                const double *wtw, const double *scale,
                                double *cov);

/*
 * The equivalent-error job with the noise models, in memory.
 *  1 m (a multiple of 3, >= 3), 2 N >= 1, 3 S (m x N column-major), 4 lds
 *  >= m, 5 dw (m), 6 track_sigma, 7 sigma_inc, 8 cov (as
 *  igea_whiten_accumulate: one of track_sigma and cov is NULL), 9 group
 *  (m / 3 labels or NULL), 10 ngroups >= 1 (groups with no epoch are
 *  refused, -9), 11 spec_sigma (N or NULL), 12 phi (3 p given
 *  coefficients, axis-major, or NULL: 0; the start when phi is estimated),
 *  13 opts (IGEA_EQERR_OPT_LEN or NULL; slots 20..28 above).
 * Outputs as igea_eqerr_solve: 14 lambda, 15 P, 16 ldp, 17 equiv_err,
 * 18 z, 19 reject, 20 info (with the entries above), and
 * 21 ar_out   IGEA_NOISE_AR_OUT_LEN or NULL (layout above; se 0 when phi
 *             is given)
 * 22 group_out ngroups x IGEA_NOISE_GROUP_COLS or NULL (above)
 * 23 row_w    m or NULL: the w-statistic of each row the robust route
 *             rejected (|w| > z_{1-alpha_0/2}, info ROBUST_CRIT), 0 for
 *             kept rows
 * With one group its scale is reported but the weights are the seed's
 * (the sigma_w correction of opts); with two or more the groups are
 * weighted by 1/c_g and the seed's correction runs on top.
 * Returns those of igea_whiten_accumulate, igea_noise_ar_fit (IGEA_EDOMAIN:
 * an estimated phi not stationary), igea_noise_vce, igea_eqerr_solve;
 * outputs untouched on failure.
 */
IGEA_API int igea_noise_eqerr(int m, int N, const double *S, int lds,
                              const double *dw, const double *track_sigma,
                              int sigma_inc, const double *cov,
                              const int *group, int ngroups,
                              const double *spec_sigma, const double *phi,
                              const double *opts, double *lambda, double *P,
                              int ldp, double *equiv_err, double *z,
                              int *reject, double *info, double *ar_out,
                              double *group_out, double *row_w);

/*
 * igea_noise_eqerr with the whitened residuals of the flight.
 *  1 m .. 23 row_w  as igea_noise_eqerr: 1 m, 2 N, 3 S, 4 lds, 5 dw,
 *  6 track_sigma, 7 sigma_inc, 8 cov, 9 group (may be NULL), 10 ngroups,
 *  11 spec_sigma (may be NULL), 12 phi (may be NULL), 13 opts (may be
 *  NULL), 14 lambda, 15 P, 16 ldp, 17 equiv_err, 18 z, 19 reject, 20 info,
 *  21 ar_out (may be NULL), 22 group_out (may be NULL), 23 row_w (may be
 *  NULL)
 * 24 resid  m outputs: the whitened residuals of the final full-rank fit,
 *           e~_i = (w~_i - S~_i x) / sqrt(c_g), with [S~ w~] the rows
 *           whitened by the covariance (or sigmas) and the final AR filter,
 *           x the generalised least-squares solution of all terms (bias
 *           columns included) at the final phi, group scales and rejections,
 *           c_g the scale of row i's group (1 with one group); rows the
 *           robust route rejected are included (row_w != 0). Units: the
 *           stated tracking 1-sigma (dimensionless).
 * Returns those of igea_noise_eqerr, -24; outputs untouched on failure.
 */
IGEA_API int igea_noise_eqerr_resid(int m, int N, const double *S, int lds,
                                    const double *dw, const double *track_sigma,
                                    int sigma_inc, const double *cov,
                                    const int *group, int ngroups,
                                    const double *spec_sigma, const double *phi,
                                    const double *opts, double *lambda,
                                    double *P, int ldp, double *equiv_err,
                                    double *z, int *reject, double *info,
                                    double *ar_out, double *group_out,
                                    double *row_w, double *resid);

/*
 * igea_noise_eqerr_resid with the whole K of igea dw: the diagonal blocks
 * K_ee and the cross blocks X_e (igea_whiten_accumulate_xcov) instead of
 * one 3 x 3 block per epoch. What combines with them: the seed's sigma_w
 * correction (one scale of the whole K), the robust route (data snooping
 * on the whitened rows, which are the standardised innovations of each
 * epoch given the earlier ones), per-flight bias columns
 * (IGEA_EQERR_OPT_GROUP_BIAS, one group). What does not: AR(p) on top
 * (opts[IGEA_EQERR_OPT_AR] != 0: -9; K is already the noise's whole
 * covariance) and groups (none here: a scale per station of a covariance
 * whose random walk runs across the stations is not defined).
 *  1 m (a multiple of 3, >= 3), 2 N >= 1, 3 S (m x N column-major), 4 lds
 *  >= m, 5 dw (m), 6 cov (6 m / 3: K_ee, as igea_whiten_accumulate_xcov),
 *  7 xcov (9 m / 3: X_e, as igea_whiten_accumulate_xcov), 8 spec_sigma (N
 *  or NULL), 9 opts (IGEA_EQERR_OPT_LEN or NULL)
 * Outputs as igea_noise_eqerr_resid: 10 lambda, 11 P, 12 ldp, 13 equiv_err,
 * 14 z, 15 reject, 16 info, 17 group_out (1 x IGEA_NOISE_GROUP_COLS or
 * NULL), 18 row_w (m or NULL: the w of each whitened row the robust route
 * rejected), 19 resid (m or NULL: the whitened residuals of the final
 * full-rank fit, (w~_i - S~_i x), w~ the innovations above).
 * Returns those of igea_whiten_accumulate_xcov (IGEA_ESINGULAR: the
 * differenced covariance not positive definite, or nearly so, at an epoch;
 * igea_whiten_accumulate_xcov's bad_epoch names it) and of
 * igea_noise_eqerr; outputs untouched on failure.
 */
IGEA_API int igea_noise_eqerr_xcov(int m, int N, const double *S, int lds,
                                   const double *dw, const double *cov,
                                   const double *xcov, const double *spec_sigma,
                                   const double *opts, double *lambda, double *P,
                                   int ldp, double *equiv_err, double *z,
                                   int *reject, double *info, double *group_out,
                                   double *row_w, double *resid);

#ifdef __cplusplus
}
#endif
#endif
