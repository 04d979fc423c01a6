/*
 * igea/rls.h - recursive estimation of guidance tool-error coefficients,
 * epoch by epoch (seed 001; METHODS 2.1-2.8).
 *
 * Model y_n = c_n X + v_n: y (k values) telemetry minus tracking at epoch n,
 * c_n (k x m) the environment functions, X (m) the constant coefficients,
 * v white noise of standard deviation track_sigma (per row). Each row is
 * divided by its track_sigma first (METHODS 2.1), so every formula below is
 * in whitened units with unit noise.
 *
 * The state lives in an opaque handle holding xhat (m), Gamma (m x m) and
 * all scratch memory; it is allocated once by igea_rls_create, and no other
 * call allocates (a real-time loop may call igea_rls_update at every epoch).
 * Per epoch, with A = c Gamma c^T and Sigma_e = I + A = W diag(1 + a) W^T
 * (Jacobi eigen-decomposition of the k x k matrix, METHODS 2.8):
 *   K    = Gamma c^T W diag(1 / (1 + a)) W^T                    (2.2)
 *   K_p  = Gamma c^T W diag(f_p(a)) W^T,
 *          f_p(a) = -expm1(-p log1p(a)) / a, f_p(0) = p           (2.4, 2.8)
 *   xhat <- xhat + K_p (y - c xhat)               polynomial RLS (2.4)
 *   xhat <- p times xhat + K (y - c xhat)         iterated RLS (2.3)
 *   Gamma <- Gamma - K Sigma_e K^T = Gamma - V V^T,
 *            V = Gamma c^T W diag((1 + a)^-1/2)     symmetric form (2.8)
 *   P     <- (I - K_p c) P (I - K_p c)^T + K_p K_p^T   Joseph form, the
 *            honest covariance of xhat (2.4), evaluated factored as
 *            P - Z1 Z1^T + Z2 Z2^T, I + c P c^T = L L^T, Z1 = P c^T L^-T,
 *            Z2 = (K_p - P c^T (I + c P c^T)^-1) L
 * The patent's (c K)^-1 is never formed, so a zero or tiny c Gamma c^T (the
 * environment functions vanish at lift-off) is handled. Standard RLS is the
 * case p = 1 of both forms; then P equals Gamma and is not computed twice.
 * Gamma and P stay symmetric (the lower triangle is authoritative) and
 * positive definite: an update that would make a diagonal element <= 0 is
 * refused.
 *
 * Forgetting factor lambda (0 < lambda <= 1, default 1) [D]: before each
 * update Gamma <- Gamma / lambda (and P <- P / lambda), the exponentially
 * weighted least squares of weight lambda^(age) per epoch.
 *
 * Anomalies (METHODS 2.7) [D detector]: row j is flagged when
 *   |e_j| > kappa sqrt((Sigma_e)_jj), e = y - c xhat (innovation test), or
 *   |y_j - yprev_j| > jump_max_j (jump test, physical units; yprev_j is the
 *   last value of row j used in an update), or
 *   y_j is NaN or Inf (a dropout; accepted only when a policy is set).
 * Policies: NONE (flag only, update with the data), REPLACE (the patent's
 * variant A: an anomalous epoch's y is replaced by the previous epoch's
 * whole y; skipped when there is none yet), SKIP (the epoch leaves the state
 * unchanged), ISOLATE (variant B: the flagged rows are deleted and the
 * update runs on the k' = k - |J| others; all rows flagged -> skip).
 *
 * Q_p (METHODS 2.6) accumulates the a-posteriori whitened residual sum
 * ||y - c xhat_new||^2 over the rows used in each update. It decreases with p
 * by construction and is not a measure of accuracy: read P beside it.
 *
 * Thread safety: every function is reentrant; a handle belongs to one
 * thread at a time. Outputs and the handle's state are untouched when a
 * call fails.
 */
#ifndef IGEA_RLS_H
#define IGEA_RLS_H

#include "igea/common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct igea_rls igea_rls;

/* Variants (igea_rls_set_variant). */
#define IGEA_RLS_STANDARD 0   /* METHODS 2.2 (p is taken as 1) */
#define IGEA_RLS_ITERATED 1   /* METHODS 2.3, p iterations with one gain */
#define IGEA_RLS_POLYNOMIAL 2 /* METHODS 2.4, gain K_p of order p */

/* Anomaly policies (igea_rls_set_anomaly). */
#define IGEA_RLS_ANOMALY_NONE 0    /* flag only; NaN/Inf y is an error */
#define IGEA_RLS_ANOMALY_REPLACE 1 /* variant A: y <- previous epoch's y */
#define IGEA_RLS_ANOMALY_SKIP 2    /* no update at an anomalous epoch */
#define IGEA_RLS_ANOMALY_ISOLATE 3 /* variant B: drop the flagged rows */

/* Per-row flag bits written by igea_rls_update (flags[j]). */
#define IGEA_RLS_FLAG_INNOVATION 1 /* |e_j| > kappa sqrt((I + A)_jj) */
#define IGEA_RLS_FLAG_JUMP 2       /* |y_j - yprev_j| > jump_max_j */
#define IGEA_RLS_FLAG_MISSING 4    /* y_j is NaN or Inf (dropout) */
#define IGEA_RLS_FLAG_UNUSED 8     /* the row did not enter the update */

/* Non-negative returns of igea_rls_update: what was done at the epoch. */
#define IGEA_RLS_UPDATED 0  /* no row flagged; normal update */
#define IGEA_RLS_FLAGGED 1  /* rows flagged, policy NONE: normal update */
#define IGEA_RLS_REPLACED 2 /* policy REPLACE: updated with previous y */
#define IGEA_RLS_SKIPPED 3  /* no update (SKIP, or nothing left to use) */
#define IGEA_RLS_ISOLATED 4 /* policy ISOLATE: updated with the other rows */

/* Indices into counts[IGEA_RLS_COUNT_LEN] (igea_rls_get_counts). */
#define IGEA_RLS_COUNT_EPOCHS 0    /* successful igea_rls_update calls */
#define IGEA_RLS_COUNT_UPDATES 1   /* epochs that changed the state */
#define IGEA_RLS_COUNT_ANOMALOUS 2 /* epochs with at least one flagged row */
#define IGEA_RLS_COUNT_ROWS 3      /* rows summed into Q_p */
#define IGEA_RLS_COUNT_LEN 4

/*
 * Create the estimator state.
 *  1 m >= 1 coefficients; 2 k >= 1 observation rows per epoch;
 *  3 x0 (m values; NULL: zeros) the initial estimate xhat_0;
 *  4 gamma0 (m x m, lower triangle read) Gamma_0, symmetric positive
 *    definite, in whitened units; 5 ldg >= m; 6 out: the new handle
 *    (set to NULL on failure).
 * Defaults: standard RLS, p = 1, anomaly policy NONE, kappa = 4, no jump
 * test, lambda = 1.
 * Returns 0, -i, IGEA_ENONFINITE, IGEA_ESINGULAR (Gamma_0 not positive
 * definite), IGEA_ENOMEM.
 */
IGEA_API int igea_rls_create(int m, int k, const double *x0,
                             const double *gamma0, int ldg, igea_rls **out);

/* Release a handle; NULL is accepted. */
IGEA_API void igea_rls_free(igea_rls *h);

/*
 * Choose the variant: 1 h; 2 variant (IGEA_RLS_STANDARD, _ITERATED,
 * _POLYNOMIAL); 3 p >= 1 (order / iterations, at most 1000000; ignored for
 * STANDARD). Returns 0 or -i.
 */
IGEA_API int igea_rls_set_variant(igea_rls *h, int variant, int p);

/*
 * Anomaly handling: 1 h; 2 policy (IGEA_RLS_ANOMALY_*); 3 kappa > 0 (the
 * innovation threshold in standard deviations; +Inf switches the innovation
 * test off); 4 jump_max (k values > 0, +Inf for no test on that row; NULL:
 * no jump test). Returns 0, -i (-4 also for a NaN or non-positive entry).
 */
IGEA_API int igea_rls_set_anomaly(igea_rls *h, int policy, double kappa,
                                  const double *jump_max);

/*
 * Whether to track the honest covariance P (default 1). P costs as much as
 * Gamma per epoch when p > 1; a loop that needs only xhat may switch it off.
 * Then igea_rls_get_covariance returns IGEA_EDOMAIN once a p > 1 gain has
 * been used. 1 h; 2 track (1 or 0). Returns 0, -i, or IGEA_EDOMAIN when
 * called after the first update (the choice holds for the whole record).
 */
IGEA_API int igea_rls_set_covariance(igea_rls *h, int track);

/* Forgetting factor: 1 h; 2 0 < forget <= 1. Returns 0 or -i. */
IGEA_API int igea_rls_set_forget(igea_rls *h, double forget);

/*
 * One epoch.
 *  1 h; 2 c (k x m, column-major) the environment functions; 3 ldc >= k;
 *  4 y (k values) telemetry minus tracking; NaN/Inf marks a dropout, allowed
 *    only when an anomaly policy other than NONE is set;
 *  5 track_sigma (k values > 0, the noise standard deviation of each row;
 *    NULL: unit noise, y and c already whitened);
 *  6 flags (k ints, or NULL): IGEA_RLS_FLAG_* bits of each row.
 * Returns what was done (IGEA_RLS_UPDATED, _FLAGGED, _REPLACED, _SKIPPED,
 * _ISOLATED), or -i, IGEA_ENONFINITE (NaN/Inf in c, or in y without a
 * policy, or a non-finite result), IGEA_ENONPOSITIVE (track_sigma <= 0),
 * IGEA_ERANGE (a track_sigma below IGEA_SIGMA_MIN: its weight overflows),
 * IGEA_ESINGULAR (the update would make Gamma or P lose positive
 * definiteness); on failure the state and flags are untouched.
 */
IGEA_API int igea_rls_update(igea_rls *h, const double *c, int ldc,
                             const double *y, const double *track_sigma,
                             int *flags);

/* Layouts of a whole record (igea_rls_run): IGEA_COLMAJOR, IGEA_ROWMAJOR of
 * igea/common.h, read as below. */

/*
 * A whole record of n epochs, processed in turn by igea_rls_update.
 *  1 h; 2 n >= 0 epochs; 3 layout:
 *    IGEA_COLMAJOR: S is (n k) x m column-major, 5 lds >= max(1, n k),
 *      rows e k .. e k + k - 1 are epoch e's c (the eqerr layout: S and dw
 *      of a flight with k rows per epoch, epoch-major);
 *    IGEA_ROWMAJOR: S holds n blocks c_e^T (m x k column-major,
 *      5 lds >= m), block e starting at S + e k lds (a C-order array of
 *      shape (n, k, m) with lds = m); the faster layout;
 *  4 S; 6 dw (n k values, y of the epochs in turn); 7 track_sigma (n k
 *  values with 8 sigma_inc = 1, or k values with sigma_inc = 0 for the same
 *  sigma at every epoch, or NULL: unit noise); 9 x_out (m x n, column e =
 *  xhat after epoch e, or NULL); 10 ldx >= m; 11 flags (n k ints, or NULL);
 *  12 actions (n ints, or NULL): what igea_rls_update returned for each
 *  epoch; 13 n_done (or NULL): number of epochs processed.
 * Returns 0, -i (this function's arguments, checked before any epoch), or
 * the first failing epoch's IGEA_E* status; the epochs before it are
 * processed and their outputs written, the failing epoch and the ones
 * after it are not (*n_done tells how many were: it is written, 0 first,
 * once the arguments are valid, also when an epoch fails; a -i status
 * leaves it untouched).
 */
IGEA_API int igea_rls_run(igea_rls *h, int n, int layout, const double *S,
                          int lds, const double *dw, const double *track_sigma,
                          int sigma_inc, double *x_out, int ldx, int *flags,
                          int *actions, int *n_done);

/* Current estimate: 1 h; 2 x (m values). Returns 0 or -i. */
IGEA_API int igea_rls_get_x(const igea_rls *h, double *x);

/* Gamma, full symmetric matrix: 1 h; 2 gamma (m x m); 3 ldg >= m. */
IGEA_API int igea_rls_get_gamma(const igea_rls *h, double *gamma, int ldg);

/* The honest covariance P of xhat (Joseph form with the gain actually
 * used, METHODS 2.4; equals Gamma for p = 1): 1 h; 2 cov (m x m); 3 ldc >= m.
 * Returns 0, -i, or IGEA_EDOMAIN if P was not tracked (igea_rls_set_covariance)
 * and is no longer Gamma. */
IGEA_API int igea_rls_get_covariance(const igea_rls *h, double *cov, int ldc);

/* Standard deviations of xhat, sd[i] = sqrt(P_ii) of the honest covariance
 * (igea_rls_get_covariance): 1 h; 2 sd (m values). Returns 0, -i, or
 * IGEA_EDOMAIN (sd untouched) if P was not tracked and is no longer Gamma
 * (or a diagonal element is not a finite non-negative number). */
IGEA_API int igea_rls_get_sd(const igea_rls *h, double *sd);

/* Q_p so far (METHODS 2.6, whitened units): 1 h; 2 q. Returns 0 or -i. */
IGEA_API int igea_rls_get_q(const igea_rls *h, double *q);

/* Counters: 1 h; 2 counts[IGEA_RLS_COUNT_LEN]. Returns 0 or -i. */
IGEA_API int igea_rls_get_counts(const igea_rls *h, int *counts);

/* Sizes: 1 h; 2 m (or NULL); 3 k (or NULL). Returns 0 or -1. */
IGEA_API int igea_rls_get_size(const igea_rls *h, int *m, int *k);

/*
 * Compensated telemetry (METHODS 2.5), physical units: yhat = y - c xhat
 * with the current estimate. 1 h; 2 c (k x m); 3 ldc >= k; 4 y (k);
 * 5 yhat (k). Returns 0, -i, IGEA_ENONFINITE.
 */
IGEA_API int igea_rls_compensate(const igea_rls *h, const double *c, int ldc,
                                 const double *y, double *yhat);

#ifdef __cplusplus
}
#endif
#endif
