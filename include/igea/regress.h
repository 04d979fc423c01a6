/*
 * igea/regress.h - classical error separation y = A x + e: weighted least
 * squares, ridge, principal-component, Bayesian and empirical-Bayes ridge
 * (EBR) estimators, and collinearity diagnostics (seeds 000 and 003;
 * METHODS 0.3, 4.3).
 *
 * Every estimator works on the thin SVD (LAPACK dgesdd) of the weighted
 * design diag(1/sigma) A, never on A^T A, so that exactly singular and
 * badly conditioned designs keep their digits: the numerical rank is
 * r = #{s_i > rcond * s_1}, rcond = max(m, N) * eps by default (METHODS
 * 0.3), and the directions beyond r (the null space) are never estimated
 * from the data: they are left at zero (minimum norm) or at the prior.
 *
 * Sizes: m rows (observations), N columns (terms); m < N (fewer rows than
 * terms) is accepted by every estimator. A is column-major with leading
 * dimension lda >= m. Outputs are untouched when a call fails.
 *
 * Every function takes, in the same places, sigma (m row standard
 * deviations > 0, or NULL: unit weights) and spec_sigma (N column scales
 * > 0, e.g. the 1-sigma specs of the terms, or NULL: none), as
 * igea_eqerr_run does. With spec_sigma the estimator works on the scaled
 * design A D, D = diag(spec_sigma), i.e. on the coefficients X / spec
 * (ridge, PCE and EBR then shrink every term in multiples of its spec,
 * and the Bayesian prior defaults to the in-spec system), and returns the
 * coefficients, their covariance and standard deviations in the caller's
 * units of A's columns: x = D x', cov = D cov' D. The tuning quantities
 * (ridge k, PCE eig_min, EBR lambda, the eigenvalues and eigenvectors of
 * igea_regress_collinearity) are those of the scaled problem. Residuals
 * y - A x do not depend on the scaling.
 *
 * Range: a sigma must be >= IGEA_SIGMA_MIN (2^-511, so that 1/sigma^2 is
 * finite), else IGEA_ERANGE; so must a spec_sigma. The canonical
 * quantities are formed without squaring singular values where the
 * estimator allows it (a design scaled by 1e-300 gives the scaled
 * answer), and a result that is not representable (a covariance of
 * 1e600, a ridge constant or an EBR lambda beyond the double range) is
 * IGEA_EOVERFLOW: no estimator returns 0 with a NaN or Inf in an output,
 * except the Inf values documented for igea_regress_collinearity.
 */
#ifndef IGEA_REGRESS_H
#define IGEA_REGRESS_H

#include "igea/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* EBR rules for the prior scale lambda (METHODS 4.3 steps 5-6). */
/* The estimators by name, for front ends that pick one (IGEA_CHOICE_REGRESS_METHOD:
 * ls ridge pce bayes ebr): igea_regress_ls, _ridge, _pce, _bayes, _ebr. */
#define IGEA_REGRESS_METHOD_LS 0
#define IGEA_REGRESS_METHOD_RIDGE 1
#define IGEA_REGRESS_METHOD_PCE 2
#define IGEA_REGRESS_METHOD_BAYES 3
#define IGEA_REGRESS_METHOD_EBR 4

#define IGEA_REGRESS_EBR_SC 0  /* Shinozaki-Chang rule, METHODS 4.3 eq. (17) */
#define IGEA_REGRESS_EBR_MM 1  /* unbiased moments: sum z_i^2/(1+l d_i) = r S/(m-r) */
#define IGEA_REGRESS_EBR_ML2 2 /* type-II maximum likelihood */

/*
 * Weighted least squares by SVD (dgesdd) of diag(1/sigma) A D; minimum-norm
 * solution (in the scaled coefficients) if rank-deficient.
 *  1 m >= 1 rows; 2 N >= 1 terms; 3 A (m x N), 4 lda >= m; 5 y (m);
 *  6 sigma: m row standard deviations (> 0) or NULL (unweighted);
 *  7 spec_sigma: N column scales (> 0) or NULL (see above);
 *  8 rcond: relative singular-value cut, <= 0 for the default max(m,N)*eps
 *    (must be < 1);
 * Outputs:
 *  9 x[N] the (minimum-norm) solution;
 * 10 cov (N x N, may be NULL), 11 ldc >= N (ignored when cov is NULL):
 *    sigma2 * D pinv(D A^T W A D) D with W = diag(1/sigma^2);
 * 12 rank: numerical rank r;
 * 13 sigma2: residual variance RSS_w / (m - r) of the weighted residuals,
 *    0 if m == r;
 * 14 residual[m] (may be NULL): y - A x, unweighted.
 * The rank is judged, and a full-rank solution computed, on the columns of
 * diag(1/sigma) A scaled to unit norm (scale-free rank; NIST Filip keeps
 * 8 digits); a rank-deficient problem is solved on the unscaled SVD, which
 * gives the true minimum-norm solution. A full-rank solution is refined in
 * extended precision (igea_regress_ls_ex).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE (a sigma <= 0),
 * IGEA_ERANGE, IGEA_EOVERFLOW, IGEA_ENOMEM, IGEA_ELAPACK.
 */
IGEA_API int igea_regress_ls(int m, int N, const double *A, int lda,
                             const double *y, const double *sigma,
                             const double *spec_sigma, double rcond, double *x,
                             double *cov, int ldc, int *rank, double *sigma2,
                             double *residual);

/* Flags of igea_regress_ls_ex. */
#define IGEA_REGRESS_NO_REFINE 1 /* skip the extended-precision refinement */

/* Indices into info[IGEA_REGRESS_INFO_LEN] of igea_regress_ls_ex (doubles;
 * counts and flags are whole numbers). */
#define IGEA_REGRESS_INFO_RANK 0          /* numerical rank r */
#define IGEA_REGRESS_INFO_RCOND 1         /* relative cut used: s_i > rcond s_1 */
#define IGEA_REGRESS_INFO_TOL 2           /* absolute cut rcond * s_1 on the singular values */
#define IGEA_REGRESS_INFO_SCALED 3        /* 1: columns scaled internally to unit norm */
#define IGEA_REGRESS_INFO_REFINE_STEPS 4  /* refinement steps run (0: none) */
#define IGEA_REGRESS_INFO_COND 5          /* s_1 / s_r of the design the rank was judged on */
#define IGEA_REGRESS_INFO_LEN 16 /* slots 6.. reserved for additions */

/*
 * Weighted least squares as igea_regress_ls, with iterative refinement and
 * the rank information. At full rank the SVD solution is refined on the
 * augmented system [I B; B^T 0] [r; x'] = [y_w; 0] (Bjorck 1967), B the
 * column-equilibrated weighted design, with the residuals y_w - r - B x'
 * and B^T r accumulated in x86 extended precision (64-bit significand;
 * exact products by fma, compensated sums, r/sigma with its fmal
 * remainder) from the caller's A, y and sigma, until a correction is below 2^-60 of x' or
 * stops shrinking (at most 10 steps): x is then the least-squares
 * solution of the double-precision data to nearly the last digit
 * (docs/regress.md, "Least squares to the last digit"). igea_regress_ls
 * refines the same way. A rank-deficient problem is not refined.
 *  1 m >= 1, 2 N >= 1, 3 A (m x N), 4 lda >= m, 5 y (m), 6 sigma (m or
 *  NULL), 7 spec_sigma (N or NULL), 8 rcond (as igea_regress_ls);
 *  9 flags: 0 or IGEA_REGRESS_NO_REFINE;
 * Outputs:
 * 10 x[N]; 11 cov (N x N, may be NULL), 12 ldc >= N (ignored when cov is
 *    NULL), as igea_regress_ls;
 * 13 sd[N] (may be NULL): standard deviations sqrt(diag(cov));
 * 14 sigma2: RSS_w / (m - r) (0 if m == r);
 * 15 residual[m] (may be NULL): y - A x, unweighted (with refinement:
 *    computed in extended precision and rounded once);
 * 16 info[IGEA_REGRESS_INFO_LEN]: the IGEA_REGRESS_INFO_* entries, 0 in the
 *    reserved slots.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE,
 * IGEA_EOVERFLOW, IGEA_ENOMEM, IGEA_ELAPACK; outputs are written only on
 * success.
 */
IGEA_API int igea_regress_ls_ex(int m, int N, const double *A, int lda,
                                const double *y, const double *sigma,
                                const double *spec_sigma, double rcond, int flags,
                                double *x, double *cov, int ldc, double *sd,
                                double *sigma2, double *residual, double *info);

/*
 * The rank information of diag(1/sigma) A D (D = diag(spec_sigma) or I),
 * the design igea_regress_ebr, igea_regress_collinearity and (without
 * automatic scaling) ridge and PCE judge the rank on: r = #{s_i > rcond
 * s_1}. 1 m >= 1, 2 N >= 1, 3 A (m x N), 4 lda >= m, 5 sigma (m row sds,
 * may be NULL), 6 spec_sigma (N scales, may be NULL), 7 rcond (< 1; <= 0
 * for the default max(m, N) eps), 8 info[IGEA_REGRESS_INFO_LEN] (output):
 * RANK, RCOND, TOL = rcond s_1, COND = s_1 / s_r; SCALED and REFINE_STEPS 0.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE,
 * IGEA_EOVERFLOW, IGEA_ENOMEM, IGEA_ELAPACK; info is written only on
 * success.
 */
IGEA_API int igea_regress_rank_info(int m, int N, const double *A, int lda,
                                    const double *sigma, const double *spec_sigma,
                                    double rcond, double *info);

/*
 * Standard deviations sd[j] = sqrt(cov[j][j]) of an estimator's covariance
 * (N x N, column-major, leading dimension ldc >= N; only the diagonal is
 * read). 1 N >= 1, 2 cov, 3 ldc, 4 sd[N] (output, written only on success).
 * Returns 0, -i, IGEA_ENONFINITE (a diagonal entry NaN or Inf) or
 * IGEA_EDOMAIN (a negative diagonal entry).
 */
IGEA_API int igea_regress_sd(int N, const double *cov, int ldc, double *sd);

/* Indices into diag[IGEA_REGRESS_DIAG_LEN] of igea_regress_ls_diag. */
#define IGEA_REGRESS_DIAG_R2 0             /* 1 - SSR / TSS */
#define IGEA_REGRESS_DIAG_R2_ADJ 1         /* 1 - (m - c) / (m - r) (1 - R2) */
#define IGEA_REGRESS_DIAG_FVALUE 2         /* (ESS / df_model) / (SSR / df_resid) */
#define IGEA_REGRESS_DIAG_F_PVALUE 3       /* P(F(df_model, df_resid) > F) */
#define IGEA_REGRESS_DIAG_AIC 4            /* -2 llf + 2 r */
#define IGEA_REGRESS_DIAG_BIC 5            /* -2 llf + log(m) r */
#define IGEA_REGRESS_DIAG_LLF 6            /* Gaussian log-likelihood */
#define IGEA_REGRESS_DIAG_PRESS 7          /* sum (e_i / (1 - h_i))^2 */
#define IGEA_REGRESS_DIAG_DURBIN_WATSON 8  /* sum (e_i - e_{i-1})^2 / SSR */
#define IGEA_REGRESS_DIAG_DF_MODEL 9       /* r - c */
#define IGEA_REGRESS_DIAG_DF_RESID 10      /* m - r */
#define IGEA_REGRESS_DIAG_CONSTANT 11      /* c: 1 when a column is constant (intercept) */
#define IGEA_REGRESS_DIAG_T_CRIT 12        /* t_{1 - alpha/2}(df_resid) */
#define IGEA_REGRESS_DIAG_SSR 13           /* sum of squared weighted residuals */
#define IGEA_REGRESS_DIAG_TSS 14           /* total sum of squares (centred when c = 1) */
#define IGEA_REGRESS_DIAG_RANK 15          /* r */
#define IGEA_REGRESS_DIAG_LEN 24 /* slots 16.. reserved for additions */

/*
 * Weighted least squares (igea_regress_ls, refined) with the regression
 * diagnostics statsmodels' OLS and WLS report, on the caller's design
 * (docs/regress.md, "Regression diagnostics"). With weights w_i =
 * 1/sigma_i^2 (1 without sigma) and the weighted residuals
 * e_i = (y_i - A_i x) / sigma_i: SSR = sum e_i^2; c = 1 when some column
 * of A is constant and nonzero, and then TSS = sum w_i (y_i - ybar_w)^2
 * (ybar_w the weighted mean), else TSS = sum w_i y_i^2 (uncentred);
 * ESS = TSS - SSR; r the rank; llf = -m/2 (log(2 pi SSR / m) + 1) +
 * (1/2) sum log w_i; the leverages h_i = diag of the hat matrix of
 * diag(1/sigma) A; t_j = x_j / sd_j with p_j = 2 Q_t(|t_j|; m - r);
 * confidence limits x_j -+ t_{1-alpha/2}(m - r) sd_j; Cook's distance
 * D_i = e_i^2 / (s^2 (1 - h_i)) h_i / (1 - h_i) / N, s^2 = SSR / (m - r).
 * A coefficient with sd 0 (a zero column) has t 0 and p 1; F is 0 and its
 * p-value 1 when df_model = 0.
 *  1 m, 2 N, 3 A (m x N), 4 lda >= m, 5 y (m), 6 sigma (m row sds > 0, may
 *  be NULL), 7 rcond (as igea_regress_ls), 8 alpha in (0, 1) (0.05: 95 %
 *  intervals);
 * Outputs: 9 x[N]; 10 sd[N]; 11 tvalues[N], 12 pvalues[N], 13 ci_lower[N],
 *  14 ci_upper[N], 15 leverage[m], 16 cooks_d[m] (each may be NULL);
 *  17 diag[IGEA_REGRESS_DIAG_LEN] (the IGEA_REGRESS_DIAG_* entries).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE,
 * IGEA_EDOMAIN (no residual degrees of freedom, an exact fit SSR = 0, TSS
 * = 0, an observation with leverage 1, or more than 1e7 degrees of
 * freedom), IGEA_EOVERFLOW, IGEA_ENOMEM, IGEA_ELAPACK; outputs are written
 * only on success.
 */
IGEA_API int igea_regress_ls_diag(int m, int N, const double *A, int lda, const double *y,
                                  const double *sigma, double rcond, double alpha, double *x,
                                  double *sd, double *tvalues, double *pvalues,
                                  double *ci_lower, double *ci_upper, double *leverage,
                                  double *cooks_d, double *diag);

/*
 * igea_regress_ls_ex and igea_regress_ls_diag in one fit [D]: the design is
 * factored once (hosts that want both, e.g. Python's igea.ls, pay for one
 * fit and the leverages instead of two fits). The fit's outputs (9 flags,
 * 11-17) are those of igea_regress_ls_ex with the same arguments, bit for
 * bit; the diagnostics (18-24) are igea_regress_ls_diag's, computed on
 * that fit: with spec_sigma NULL and flags 0 bit for bit those of
 * igea_regress_ls_diag (the same fit), with spec_sigma from the fit of
 * A D mapped back to A's units (t = x / sd and the leverages do not depend
 * on the columns' scale: equal to igea_regress_ls_diag's to rounding); with
 * IGEA_REGRESS_NO_REFINE from the unrefined fit.
 *  1 m, 2 N, 3 A (m x N), 4 lda >= m, 5 y (m), 6 sigma (m or NULL),
 *  7 spec_sigma (N or NULL), 8 rcond, 9 flags (as igea_regress_ls_ex),
 * 10 alpha in (0, 1) (as igea_regress_ls_diag);
 * Outputs: 11 x[N]; 12 cov (N x N, may be NULL), 13 ldc >= N (ignored when
 *  cov is NULL); 14 sd[N] (may be NULL); 15 sigma2; 16 residual[m] (may be
 *  NULL); 17 info[IGEA_REGRESS_INFO_LEN]; 18 tvalues[N], 19 pvalues[N],
 *  20 ci_lower[N], 21 ci_upper[N], 22 leverage[m], 23 cooks_d[m] (each may
 *  be NULL); 24 diag[IGEA_REGRESS_DIAG_LEN].
 * Returns 0 (everything written); IGEA_REGRESS_NO_DIAG (> 0) when the fit
 * succeeded but the diagnostics are not defined (igea_regress_ls_diag's
 * IGEA_EDOMAIN cases: no residual degrees of freedom, an exact fit, TSS =
 * 0, a leverage 1, more than 1e7 degrees of freedom): the fit's outputs
 * 11-17 are written, 18-24 untouched; or -i, IGEA_ENONFINITE,
 * IGEA_ENONPOSITIVE, IGEA_ERANGE, IGEA_EOVERFLOW, IGEA_ENOMEM,
 * IGEA_ELAPACK with nothing written.
 */
#define IGEA_REGRESS_NO_DIAG 1
IGEA_API int igea_regress_ls_full(int m, int N, const double *A, int lda, const double *y,
                                  const double *sigma, const double *spec_sigma, double rcond,
                                  int flags, double alpha, double *x, double *cov, int ldc,
                                  double *sd, double *sigma2, double *residual, double *info,
                                  double *tvalues, double *pvalues, double *ci_lower,
                                  double *ci_upper, double *leverage, double *cooks_d,
                                  double *diag);

/*
 * Empirical-Bayes ridge exactly as METHODS 4.3 on the whitened rows
 * diag(1/sigma) A, y / sigma: canonical form of diag(1/sigma) A D (thin
 * SVD, rank r with the default cut of METHODS 0.3), lambda* from the rule's
 * equation solved by Brent (positive-part rule: 0 when there is no root),
 * lambda hat = max(lambda*, lam_floor), theta_i = lambda d_i /
 * (1 + lambda d_i) x_i, beta = D V theta. D = diag(spec_sigma) is the
 * prior scale of METHODS 4.3 (prior beta_j ~ N(0, lambda sigma^2 s_j^2)).
 *  1 m rows, 2 N terms, 3 A (m x N), 4 lda >= m, 5 y (m);
 *  6 sigma: m row standard deviations (> 0) or NULL (unit);
 *  7 spec_sigma: N prior scales s_j > 0 or NULL (D = I);
 *  8 rule: IGEA_REGRESS_EBR_SC, IGEA_REGRESS_EBR_MM or IGEA_REGRESS_EBR_ML2;
 *  9 lam_floor >= 0, finite.
 * Outputs:
 * 10 x[N]: beta;
 * 11 cov (N x N, may be NULL), 12 ldc >= N (ignored when cov is NULL): the
 *    posterior covariance sigma^2 D V diag(lambda / (1 + lambda d_i)) V^T D
 *    over all N directions, d_i = 0 beyond r: a null direction keeps its
 *    prior variance lambda sigma^2, so a prior-determined coefficient shows
 *    it (METHODS 4.3 step 7; the posterior sd is sqrt of its diagonal);
 * 13 lam: lambda hat; 14 rank r;
 * 15 sigma2: sigma^2 = S / (m - r), S the weighted residual sum of squares
 *    of the canonical form;
 * 16 residual[m] (may be NULL): y - A beta, unweighted;
 * 17 shrink[N] (may be NULL): lambda d_i / (1 + lambda d_i) for the first
 *    r canonical components (d_i descending), 0 beyond;
 * 18 sd_freq[N] (may be NULL): frequentist standard deviations with lambda
 *    fixed (diagonal of sigma^2 D V diag(lambda^2 d_i / (1 + lambda d_i)^2)
 *    V^T D).
 * lambda is solved on the design scaled by 1/s_1 and returned in the
 * units of the scaled problem (lambda' / s_1^2); IGEA_EOVERFLOW when it is
 * not a normal double.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE (a sigma or prior
 * scale <= 0), IGEA_ERANGE, IGEA_ERANK (rank r < 3), IGEA_EDOMAIN (m == r
 * or an exact fit, S = 0: no residual to estimate sigma^2 from),
 * IGEA_ENOCONV, IGEA_EOVERFLOW, IGEA_ENOMEM, IGEA_ELAPACK.
 */
IGEA_API int igea_regress_ebr(int m, int N, const double *A, int lda,
                              const double *y, const double *sigma,
                              const double *spec_sigma, int rule,
                              double lam_floor, double *x, double *cov,
                              int ldc, double *lam, int *rank, double *sigma2,
                              double *residual, double *shrink,
                              double *sd_freq);

/* Ridge rules for k (the ridge constant added to the normal matrix). */
#define IGEA_REGRESS_RIDGE_FIXED 0 /* k given by the caller */
#define IGEA_REGRESS_RIDGE_HKB 1   /* Hoerl-Kennard-Baldwin: k = r s^2 / |x_LS|^2 */
#define IGEA_REGRESS_RIDGE_LW 2    /* Lawless-Wang: k = r s^2 / |A_w x_LS|^2 */
#define IGEA_REGRESS_RIDGE_GCV 3   /* minimise m RSS(k) / (m - tr H(k))^2 */
#define IGEA_REGRESS_RIDGE_LOO 4   /* minimise sum (e_i / (1 - h_ii(k)))^2 */

/*
 * Ridge regression x' = (B + k I)^-1 D A^T W y, x = D x', on the design
 * A D (no centring; without spec_sigma scale the columns first if the
 * terms have different units), W = diag(1/sigma^2), B = D A^T W A D.
 *  1 m, 2 N, 3 A, 4 lda >= m, 5 y (m), 6 sigma (m or NULL), 7 spec_sigma
 *  (N or NULL); 8 rule: IGEA_REGRESS_RIDGE_*; 9 k >= 0 (read for
 *  IGEA_REGRESS_RIDGE_FIXED only);
 * Outputs: 10 x[N]; 11 cov (N x N or NULL): s^2 D (B + kI)^-1 B (B + kI)^-1
 *  D; 12 ldc >= N when cov is given; 13 k_used; 14 sigma2: s^2, the
 *  least-squares residual variance RSS_w / (m - r) (0 if m == r);
 *  15 residual[m] (y - A x, or NULL).
 * The GCV and LOO searches minimise over log10 k in [log10(d_1) - 12,
 * log10(d_1) + 4] (d_1 the largest eigenvalue of B): a 161-point grid, then
 * golden section next to the best grid point.
 * The rules compute sqrt(k), so a k_used that is not a normal double (e.g.
 * HKB on a design scaled by 1e-300, k ~ 1e-600) is IGEA_EOVERFLOW.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE,
 * IGEA_EDOMAIN (HKB/LW with m == r, or x_LS = 0), IGEA_EOVERFLOW,
 * IGEA_ENOMEM, IGEA_ELAPACK.
 */
IGEA_API int igea_regress_ridge(int m, int N, const double *A, int lda,
                                const double *y, const double *sigma,
                                const double *spec_sigma, int rule, double k,
                                double *x, double *cov, int ldc,
                                double *k_used, double *sigma2,
                                double *residual);

/*
 * Ridge trace: x(k_j) for nk values k[j] >= 0 (k = 0: minimum-norm LS).
 *  1 m, 2 N, 3 A, 4 lda, 5 y, 6 sigma (or NULL), 7 spec_sigma (or NULL),
 *  8 nk >= 1, 9 k[nk]; 10 X (N x nk, column j = x(k_j)), 11 ldx >= N;
 * 12 edf[nk] (effective degrees of freedom tr H(k) = sum d_i/(d_i + k), or
 *    NULL).
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE,
 * IGEA_EOVERFLOW, IGEA_ENOMEM, IGEA_ELAPACK.
 */
IGEA_API int igea_regress_ridge_trace(int m, int N, const double *A, int lda,
                                      const double *y, const double *sigma,
                                      const double *spec_sigma, int nk,
                                      const double *k, double *X, int ldx,
                                      double *edf);

/*
 * Principal-component estimation: x = sum over the kept components i of
 * v_i (u_i^T y_w) / s_i, the components being the eigenvectors of
 * B = D A^T W A D (eigenvalues d_i = s_i^2, descending) within the
 * numerical rank r, x = D x'.
 *  1 m, 2 N, 3 A, 4 lda, 5 y, 6 sigma (or NULL), 7 spec_sigma (or NULL);
 *  8 ncomp >= 0: keep the min(ncomp, r) largest; 0: keep those with
 *    d_i >= eig_min; 9 eig_min > 0 (read when ncomp == 0);
 * Outputs: 10 x[N]; 11 cov (or NULL): s^2 D (sum v_i v_i^T / d_i) D over
 *  the kept components; 12 ldc; 13 nused: components kept; 14 sigma2: s^2
 *  of least squares (as igea_regress_ridge); 15 residual[m] or NULL.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE,
 * IGEA_EOVERFLOW, IGEA_ENOMEM, IGEA_ELAPACK.
 */
IGEA_API int igea_regress_pce(int m, int N, const double *A, int lda,
                              const double *y, const double *sigma,
                              const double *spec_sigma, int ncomp,
                              double eig_min, double *x, double *cov, int ldc,
                              int *nused, double *sigma2, double *residual);

/* Column-norm ratio above which igea_regress_ridge_ex and
 * igea_regress_pce_ex scale the columns internally [D]. */
#define IGEA_REGRESS_SCALE_RATIO 1e8

/*
 * igea_regress_ridge with the rank information and automatic column
 * scaling. When the column norms of diag(1/sigma) A D (D = diag(spec_sigma)
 * or I) differ by more than IGEA_REGRESS_SCALE_RATIO, the estimator works
 * on the columns scaled to unit norm (D' = D diag(1/||column||), as if
 * spec_sigma were D'), so that the numerical rank is not lost to the
 * scales (an unscaled design with norms 1 and 1e-9 drops the second
 * direction at the rank cut); info[IGEA_REGRESS_INFO_SCALED] is then 1 and
 * k, k_used and the ridge penalty are those of the scaled problem. x, cov
 * and residual are in the caller's units as always.
 *  1 m, 2 N, 3 A, 4 lda >= m, 5 y (m), 6 sigma (m, may be NULL), 7 spec_sigma
 *  (N, may be NULL), 8 rule, 9 k (read for IGEA_REGRESS_RIDGE_FIXED only),
 *  as igea_regress_ridge;
 * Outputs: 10 x[N]; 11 cov (N x N, may be NULL), 12 ldc; 13 k_used;
 *  14 sigma2; 15 residual[m] (may be NULL), as igea_regress_ridge;
 * 16 info[IGEA_REGRESS_INFO_LEN] (output): RANK, RCOND (the default cut
 *    max(m, N) eps), TOL (the absolute cut on the singular values of the
 *    design worked on), SCALED, COND (s_1 / s_r); REFINE_STEPS 0.
 * Returns as igea_regress_ridge, and -16 when info is NULL.
 */
IGEA_API int igea_regress_ridge_ex(int m, int N, const double *A, int lda,
                                   const double *y, const double *sigma,
                                   const double *spec_sigma, int rule, double k,
                                   double *x, double *cov, int ldc, double *k_used,
                                   double *sigma2, double *residual, double *info);

/*
 * igea_regress_pce with the rank information and the automatic column
 * scaling of igea_regress_ridge_ex (eig_min and the components are then
 * those of the scaled design).
 *  1 m, 2 N, 3 A, 4 lda >= m, 5 y (m), 6 sigma (m, may be NULL), 7 spec_sigma
 *  (N, may be NULL), 8 ncomp >= 0, 9 eig_min (read when ncomp == 0), as
 *  igea_regress_pce;
 * Outputs: 10 x[N]; 11 cov (N x N, may be NULL), 12 ldc; 13 nused;
 *  14 sigma2; 15 residual[m] (may be NULL), as igea_regress_pce;
 * 16 info[IGEA_REGRESS_INFO_LEN] (output) as igea_regress_ridge_ex.
 * Returns as igea_regress_pce, and -16 when info is NULL.
 */
IGEA_API int igea_regress_pce_ex(int m, int N, const double *A, int lda, const double *y,
                                 const double *sigma, const double *spec_sigma, int ncomp,
                                 double eig_min, double *x, double *cov, int ldc, int *nused,
                                 double *sigma2, double *residual, double *info);

/*
 * Bayesian estimation with a normal prior x ~ N(mu, P) (e.g. from ground
 * calibration) and known noise: y = A x + e, e ~ N(0, diag(sigma^2))
 * (sigma NULL: unit variance). Posterior mean and covariance
 *   cov = (A^T W A + P^-1)^-1, x = cov (A^T W y + P^-1 mu),
 * computed without inverting P: P = L L^T (dpotrf), x = mu + L t and the
 * SVD of diag(1/sigma) A L (a singular design is fine; P must be SPD).
 * With spec_sigma the prior is taken to the scaled coefficients X / spec
 * (mu_j / s_j, P_ij / (s_i s_j)) and the results back (x = D x',
 * cov = D cov' D).
 *  1 m, 2 N, 3 A, 4 lda, 5 y, 6 sigma (or NULL), 7 spec_sigma (or NULL);
 *  8 prior_mean (N, or NULL for 0); 9 prior_cov (N x N, lower triangle
 *  read), or NULL for P = D^2 = diag(spec_sigma^2) (the in-spec system;
 *  the identity without spec_sigma); 10 ldp >= N when prior_cov is given;
 * Outputs: 11 x[N]; 12 cov (or NULL), 13 ldc; 14 residual[m] or NULL.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE,
 * IGEA_ESINGULAR (P not positive definite), IGEA_EOVERFLOW, IGEA_ENOMEM,
 * IGEA_ELAPACK.
 */
IGEA_API int igea_regress_bayes(int m, int N, const double *A, int lda,
                                const double *y, const double *sigma,
                                const double *spec_sigma,
                                const double *prior_mean,
                                const double *prior_cov, int ldp, double *x,
                                double *cov, int ldc, double *residual);

/* Threshold [D] on the squared null-space component of a unit coefficient
 * direction e_j above which coefficient j is flagged prior-determined. */
#define IGEA_REGRESS_NULL_TOL 1e-8

/* Indices into cond[IGEA_REGRESS_COND_LEN] of igea_regress_collinearity. */
#define IGEA_REGRESS_COND_ALL 0       /* s_1 / s_min */
#define IGEA_REGRESS_COND_ESTIMABLE 1 /* s_1 / s_r */
#define IGEA_REGRESS_COND_LEN 2

/*
 * Collinearity diagnostics of B = D A^T W A D from the SVD of
 * diag(1/sigma) A D (D = diag(spec_sigma) or I: with spec_sigma, the
 * diagnostics of the coefficients in spec units X / spec).
 *  1 m, 2 N, 3 A, 4 lda; 5 y (m, or NULL: the noise scale is then 1, the
 *  sigmas being taken as known); 6 sigma (or NULL); 7 spec_sigma (or
 *  NULL); 8 rcond (as igea_regress_ls);
 * Outputs:
 *  9 cond[IGEA_REGRESS_COND_LEN]: [IGEA_REGRESS_COND_ALL] s_1 / s_min over
 *    min(m, N) singular values (Inf if s_min is 0 or m < N) and
 *    [IGEA_REGRESS_COND_ESTIMABLE] s_1 / s_r, the condition of the
 *    estimable part;
 * 10 rank r;
 * 11 eig[N]: eigenvalues d_i = s_i^2 of B, descending (0 beyond min(m,N));
 * 12 V (N x N or NULL), 13 ldv: the eigenvectors v_i as columns (METHODS
 *    0.3 signs); v_1..v_r are the estimable combinations, v_{r+1}..v_N span
 *    the null space;
 * 14 vif[N] (or NULL): uncentred variance-inflation factors B_jj pinv(B)_jj,
 *    Inf for a prior-determined coefficient;
 * 15 sd_comb[N] (or NULL): standard deviation s / s_i of the estimable
 *    combination v_i^T x' for i < r (s^2 = RSS_w / (m - r) from y, or 1),
 *    Inf beyond r;
 * 16 prior_det[N] (or NULL): 1 when coefficient j has a null-space
 *    component (sum_{i >= r} V_ji^2 > IGEA_REGRESS_NULL_TOL): the data do
 *    not determine it, any estimate of it alone comes from a prior or a
 *    minimum-norm convention (METHODS 4.3 caveat); 0 otherwise.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ENONPOSITIVE, IGEA_ERANGE,
 * IGEA_EOVERFLOW, IGEA_ENOMEM, IGEA_ELAPACK.
 */
IGEA_API int igea_regress_collinearity(int m, int N, const double *A, int lda,
                                       const double *y, const double *sigma,
                                       const double *spec_sigma, double rcond, double *cond, int *rank,
                                       double *eig, double *V, int ldv,
                                       double *vif, double *sd_comb,
                                       int *prior_det);

#ifdef __cplusplus
}
#endif
#endif
