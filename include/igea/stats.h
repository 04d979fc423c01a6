/*
 * igea/stats.h - normal and chi-square distributions, the equivalent-error
 * accuracy tests of seed 000 (METHODS 1.2 steps 4-6).
 *
 * Every routine validates its arguments before GSL sees them, so GSL's
 * abort-on-error handler never fires (on this GSL, gsl_cdf_chisq_Pinv
 * aborts the process for many valid inputs; igea inverts the regularised
 * incomplete gamma function itself, with a bracketed Newton iteration).
 */
#ifndef IGEA_STATS_H
#define IGEA_STATS_H

#include "igea/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest number of tested components (igea_stats_accuracy_test) and of
 * pooled degrees of freedom (igea_stats_pool). The distribution routines
 * below accept dof up to IGEA_STATS_CHI2_DOF_MAX. */
#define IGEA_STATS_DOF_MAX 1e5

/* Largest degrees of freedom accepted by the chi-square routines. P and Q
 * come from igea's own regularised incomplete gamma function in extended
 * precision (series for x < a + 1, continued fraction above, a = dof / 2,
 * the prefactor x^a e^-x / Gamma(a) from the deviation (x - a) / a and
 * Stirling's series; docs/regress.md, "Distributions"). Relative error of P, Q and the
 * quantiles against 50-digit references: below 1e-14 for dof <= 1e5
 * wherever the value is a normal double, below 1e-13 up to dof 1e7. */
#define IGEA_STATS_CHI2_DOF_MAX 1e7

/* Standard normal cdf Phi(x); x may be +-Inf. -1: x is NaN. */
IGEA_API int igea_stats_normal_cdf(double x, double *p);

/* Standard normal upper tail Q(x) = 1 - Phi(x) = erfc(x / sqrt 2) / 2,
 * with its relative accuracy in the far tail (extended-precision erfc):
 * relative error below 1e-15 wherever Q(x) is a normal double, the
 * correctly rounded subnormal down to the smallest positive double (x
 * about 38.5), 0 beyond. x may be +-Inf (Q 0, 1). Writes *q.
 * Returns 0, -1 (x NaN) or -2 (q missing). */
IGEA_API int igea_stats_normal_sf(double x, double *q);

/* Inverse error function, -1 < y < 1 (Giles' start + Newton steps on C99
 * erf; |erf(x) - y| at rounding level). -1: y outside (-1, 1). */
IGEA_API int igea_stats_erfinv(double y, double *x);
/* Lower quantile z = Phi^-1(p), 0 < p < 1. -1: p outside (0, 1). */
IGEA_API int igea_stats_normal_quantile(double p, double *z);

/* Chi-square cdf P(x; dof) and survival Q(x; dof) = 1 - P (the p-value
 * of a statistic x), x >= 0 (+Inf allowed), 0 < dof <= IGEA_STATS_CHI2_DOF_MAX
 * (accuracy above). Return 0, -1 (x NaN or negative), -2 (dof), -3 (output
 * pointer missing). */
IGEA_API int igea_stats_chi2_cdf(double x, double dof, double *p);
IGEA_API int igea_stats_chi2_sf(double x, double dof, double *q);
/* Lower quantile: P(x; dof) = p, 0 < p < 1. A quantile below the smallest
 * normal double (e.g. dof 0.01, p 1e-10) is returned as 0. */
IGEA_API int igea_stats_chi2_quantile(double p, double dof, double *x);
/* Upper alpha point chi2_alpha(dof) (the seed's notation): Q(x; dof) =
 * alpha, 0 < alpha < 1. chi2_0.01(11) = 24.725. */
IGEA_API int igea_stats_chi2_upper(double alpha, double dof, double *x);

/* Student's t upper tail Q(t; dof) = P(T > t), t may be +-Inf,
 * 0 < dof <= IGEA_STATS_CHI2_DOF_MAX: (1/2) I_{dof/(dof+t^2)}(dof/2, 1/2),
 * igea's own regularised incomplete beta in extended precision
 * (continued fraction; relative error about 1e-15 for dof <= 1e3, 1e-12
 * at dof 1e6 where lgamma differences dominate). Writes *q.
 * Returns 0, -1 (t NaN), -2 (dof), -3 (q missing), IGEA_ENOCONV. */
IGEA_API int igea_stats_t_sf(double t, double dof, double *q);
/* Lower quantile of Student's t: P(T <= t) = p, 0 < p < 1, dof as
 * igea_stats_t_sf; bisection on the tail to 2 ulp. Writes *t.
 * Returns 0, -1 (p), -2 (dof), -3 (t missing), IGEA_ENOCONV. */
IGEA_API int igea_stats_t_quantile(double p, double dof, double *t);
/* F distribution upper tail P(F > f; d1, d2) = I_{d2/(d2+d1 f)}(d2/2, d1/2),
 * f >= 0 (+Inf allowed), 0 < d1, d2 <= IGEA_STATS_CHI2_DOF_MAX; accuracy as
 * igea_stats_t_sf. Writes *q.
 * Returns 0, -1 (f NaN or negative), -2 (d1), -3 (d2), -4 (q missing),
 * IGEA_ENOCONV. */
IGEA_API int igea_stats_f_sf(double f, double d1, double d2, double *q);

/* Indices into the info[IGEA_STATS_INFO_LEN] array that the accuracy tests and
 * igea_eqerr_* fill (doubles; counts and flags are whole numbers). */
#define IGEA_STATS_INFO_N_TEST 0     /* components tested, |I_t| */
#define IGEA_STATS_INFO_CHI2 1       /* T = sum z_i^2 over I_t */
#define IGEA_STATS_INFO_DOF 2        /* its degrees of freedom */
#define IGEA_STATS_INFO_CHI2_CRIT 3  /* chi2_alpha(dof) */
#define IGEA_STATS_INFO_Z_CRIT 4     /* z_{1-alpha/2} (or the caller's value) */
#define IGEA_STATS_INFO_P_VALUE 5    /* Q(T; dof) */
#define IGEA_STATS_INFO_N_REJECT 6   /* components with |z_i| > z_crit */
#define IGEA_STATS_INFO_PASSED 7     /* 1: no rejection and T < chi2_crit */
#define IGEA_STATS_INFO_RANK 8       /* numerical rank r (igea_eqerr_*) */
#define IGEA_STATS_INFO_SCALE 9      /* c: K was multiplied by c (sigma_w^2) */
#define IGEA_STATS_INFO_ITERATIONS 10 /* sigma_w iterations run */
#define IGEA_STATS_INFO_N_SMALL 11   /* |I_small| of the last iteration */
#define IGEA_STATS_INFO_FLAG 12      /* IGEA_STATS_SIGMAW_* */
#define IGEA_STATS_INFO_N_FLIGHTS 13 /* flights pooled (igea_stats_pool) */
#define IGEA_STATS_INFO_LEN 32 /* slots 14.. reserved for additions */

/* Outcome of the tracking-accuracy (sigma_w) correction. */
#define IGEA_STATS_SIGMAW_CONVERGED 0
#define IGEA_STATS_SIGMAW_NOT_ESTIMABLE 1 /* fewer than n_min small eigenvalues */
#define IGEA_STATS_SIGMAW_NO_CONVERGENCE 2
#define IGEA_STATS_SIGMAW_OFF 3

/*
 * Per-component normal tests and the chi-square test (METHODS 1.2 steps 4
 * and 5) of n equivalent errors equiv_err[i] with eigenvalues lambda[i]:
 * component i is tested when lambda[i] >= lambda_test, z_i =
 * equiv_err[i] / sqrt(1 + 1/lambda[i]) and it is rejected when |z_i| >
 * z_crit = z_{1-alpha/2}; T = sum z_i^2 is compared with chi2_alpha(|I_t|).
 *   n >= 1; equiv_err, lambda: n values, finite; 0 < alpha < 1;
 *   lambda_test > 0; z_crit: > 0 to impose a critical value (e.g. 2.58,
 *   the seed's tabulated z_0.995), 0 to use the exact quantile.
 * Outputs: z[n] (z_i for tested components, 0 elsewhere), reject[n] (1
 * rejected, 0 accepted, -1 not tested), info[IGEA_STATS_INFO_LEN] (entries 0-7).
 * Large finite values are data: z_i is always finite (|z_i| <= |e_i|);
 * when T exceeds the double range (e.g. an equivalent error of 1e300) it
 * is saturated at DBL_MAX with P_VALUE 0 and PASSED 0 (rejected), never
 * Inf or NaN. Outputs are written only on success.
 * Returns 0, -i (-1 also when more than IGEA_STATS_DOF_MAX components are
 * tested), IGEA_ENONFINITE, IGEA_ENOCONV, or IGEA_ENOTESTABLE when no
 * lambda[i] reaches lambda_test.
 */
IGEA_API int igea_stats_accuracy_test(int n, const double *equiv_err,
                                      const double *lambda, double alpha,
                                      double lambda_test, double z_crit,
                                      double *z, int *reject, double *info);

/*
 * Pooling over independent flights (METHODS 1.2 step 6): T_tot = sum of
 * chi2[f], dof_tot = sum of dof[f]; passed iff no flight has a rejected
 * component (n_reject[f] == 0) and T_tot < chi2_alpha(dof_tot).
 *   nflights >= 1; chi2[f] >= 0; dof[f] >= 1; n_reject[f] >= 0;
 *   unit_id: NULL, or the inertial unit flown in each flight: a unit that
 *   appears twice makes the flights dependent and the call returns
 *   IGEA_EDEPENDENT; 0 < alpha < 1.
 * Output info: N_TEST (= dof_tot), CHI2, DOF, CHI2_CRIT, Z_CRIT, P_VALUE,
 * N_REJECT (sum), PASSED, N_FLIGHTS. A T_tot beyond the double range (two
 * chi2 of 1e308) is saturated at DBL_MAX with P_VALUE 0 and PASSED 0.
 * Returns 0, -i (-3 also when dof_tot > IGEA_STATS_DOF_MAX),
 * IGEA_ENONFINITE, IGEA_EDEPENDENT, IGEA_ENOCONV; info is written only on
 * success.
 */
IGEA_API int igea_stats_pool(int nflights, const double *chi2, const int *dof,
                             const int *n_reject, const int *unit_id,
                             double alpha, double *info);

/*
 * Overall size of the verdict. Under H0 the tested z_1..z_n are
 * independent N(0, 1); the verdict "out of spec if max |z_i| > a or
 * sum z_i^2 > b" has the false-alarm probability
 *   size = P(max |z_i| > a or sum z_i^2 > b)
 *        = Q(b; n) + P(max |z_i| > a and sum z_i^2 <= b),
 * which igea_stats_union_size computes (docs/eqerr.md, "Overall size of
 * the verdict"). 1 <= n <= IGEA_STATS_UNION_N_MAX; a > 0 and b > 0, +Inf
 * allowed (a = +Inf: no component test, the size is Q(b; n); b = +Inf: no
 * chi-square test, 1 - (2 Phi(a) - 1)^n). Closed forms where the ball
 * and the cube nest (a^2 >= b: Q(b; n); b >= n a^2 or n = 1:
 * 1 - (2 Phi(a) - 1)^n); otherwise the second term by inclusion-exclusion
 * over the components that exceed a when it is accurate (n - floor(b/a^2)
 * >= 8 and no term C(n, j) eps^j above 1e4, eps = P(|z| > a): the sum of
 * the excesses by FFT convolution on grids of step about 0.01, 0.02, 0.04
 * and Richardson's extrapolation; docs/eqerr.md), else by the recursion over
 * k = 1..n of D_k(s) = P(max_{i<=k} |z_i| > a, sum_{i<=k} z_i^2 <= s^2)
 * on panels in s = sqrt(t) of 10 Gauss-Legendre nodes (width <= 0.25,
 * split at the breakpoints a sqrt(j) where the ball meets the cube's
 * faces and graded geometrically towards them), each step a
 * Gauss-Legendre quadrature over the angle of the new z_k, split where
 * the interpolant changes panel. Accuracy: absolute error below 1e-11
 * (1e-8 promised; the recursion checked against closed forms, independent
 * quadratures and a mesh four times finer, the two routes against each
 * other to 5e-12 on 191 cases n = 8..200); the chi-square tail Q(b; n) is
 * exact, so small sizes keep their relative accuracy. Cost at the seed's
 * thresholds (alpha 0.01, a = 3): 6 ms for n = 7, 6 ms for n = 20, 17 ms
 * for n = 50, 48 ms for n = 74, 0.26 s for n = 200 (inclusion-exclusion);
 * the recursion, where it is used, O(n P^2) with P about 4 sqrt(b) + 5
 * min(n, b / a^2) panels: 16 s for n = 100, a = 1.5, b = 120. The sizes
 * computed are kept for the process (64 of them, keyed by n, a, b exactly:
 * a repeated call returns the same value at once). Allocates with igea's
 * allocator (IGEA_ENOMEM).
 * Returns 0, -i, IGEA_ENOMEM or IGEA_ENOCONV; size is written only on
 * success.
 */
#define IGEA_STATS_UNION_N_MAX 200
IGEA_API int igea_stats_union_size(int n, double a, double b, double *size);

/* Rules of the overall verdict, for igea_stats_verdict_thresholds. */
#define IGEA_STATS_VERDICT_SEED 0  /* a = z_{1-alpha/2}, b = chi2_alpha(n) (seed 000) */
#define IGEA_STATS_VERDICT_CHI2 1  /* a = +Inf, b = chi2_alpha(n): the chi-square test alone */
#define IGEA_STATS_VERDICT_EXACT 2 /* a = z_{1-g/2}, b = chi2_g(n), size(g) = alpha */
#define IGEA_STATS_VERDICT_SIDAK 3 /* a at the Sidak level 1-(1-alpha)^(1/n), b = chi2_alpha(n) */

/*
 * Thresholds a (on |z_i|) and b (on sum z_i^2) of the overall verdict
 * `rule` (IGEA_STATS_VERDICT_*) for n tested components at level alpha,
 * and the rule's true size (igea_stats_union_size; EXACT evaluates it
 * about 12 times). SEED: the seed's
 * thresholds, size above alpha (0.070 for n = 7, alpha = 0.01). CHI2: size
 * alpha. EXACT: both tests at one common level g, found by root finding
 * in log g on [alpha / (n + 1), alpha] (the union bound brackets it) so
 * that the size is alpha to 1e-12 relative (or g to 1e-11 relative); a
 * and b are then z_{1-g/2} and chi2_g(n) (n = 1: g = alpha). SIDAK: the
 * component tests at g = 1 - (1 - alpha)^(1/n), two-sided, plus the
 * chi-square test at alpha; size a little above alpha.
 *   1 <= n <= IGEA_STATS_UNION_N_MAX; 0 < alpha < 1 (sizes are absolute to
 *   1e-10: an alpha below 1e-8 is not meaningful for EXACT).
 * Returns 0, -i, IGEA_ENOMEM or IGEA_ENOCONV; a, b, size are written only
 * on success.
 */
IGEA_API int igea_stats_verdict_thresholds(int rule, int n, double alpha, double *a,
                                           double *b, double *size);

/* ---- Overall verdict of igea_eqerr_* and residual diagnostics ---------- */

/* info[] slots of the overall verdict rule (IGEA_EQERR_OPT_VERDICT) that
 * igea_eqerr_solve, _solve_qr, _run and igea_eqerr_pool fill. */
#define IGEA_STATS_INFO_VERDICT 14           /* the rule, IGEA_STATS_VERDICT_* */
#define IGEA_STATS_INFO_VERDICT_Z_CRIT 15    /* its threshold a on |z_i| (0: none, CHI2) */
#define IGEA_STATS_INFO_VERDICT_CHI2_CRIT 16 /* its threshold b on T */
#define IGEA_STATS_INFO_OVERALL_SIZE 17      /* P(out of spec | H0) (0: not computed) */
#define IGEA_STATS_INFO_SIGMA_W 18           /* sqrt(SCALE): the tracking-scale estimate */

/*
 * Whiteness of a residual series x_1..x_n about a centre c (its mean):
 * d_t = x_t - c,
 *  - Ljung-Box Q = n (n + 2) sum_{k=1..L} r_k^2 / (n - k), r_k = sum_t
 *    d_t d_{t+k} / sum_t d_t^2, against chi-square with L dof (p-value
 *    Q(Q; L); no degrees of freedom are removed for the fitted terms);
 *  - Wald-Wolfowitz runs test on the signs of d_t (about the mean; values
 *    equal to c are dropped): R runs among n1 above and n2 below, mean
 *    2 n1 n2 / (n1 + n2) + 1, variance 2 n1 n2 (2 n1 n2 - n') / (n'^2 (n' - 1)),
 *    n' = n1 + n2, z = (R - mean) / sd and the two-sided normal p-value
 *    (too few runs: positive serial correlation, z < 0). z = 0, p = 1 when
 *    one sign is missing.
 * Streamed: igea_stats_diag_init, then igea_stats_diag_add over the series'
 * blocks in order, then igea_stats_diag_result; igea_stats_whiteness does
 * all three about the series' own mean.
 */
#define IGEA_STATS_DIAG_LAGS_MAX 100
#define IGEA_STATS_DIAG_STATE_LEN (10 + 2 * IGEA_STATS_DIAG_LAGS_MAX)

/* Indices into out[IGEA_STATS_DIAG_LEN] of igea_stats_diag_result. */
#define IGEA_STATS_DIAG_N 0        /* values in the series */
#define IGEA_STATS_DIAG_LB_Q 1     /* Ljung-Box Q */
#define IGEA_STATS_DIAG_LB_LAGS 2  /* L, its degrees of freedom */
#define IGEA_STATS_DIAG_LB_P 3     /* Q(Q; L) */
#define IGEA_STATS_DIAG_RUNS 4     /* R */
#define IGEA_STATS_DIAG_N_ABOVE 5  /* n1: values above the centre */
#define IGEA_STATS_DIAG_N_BELOW 6  /* n2: values below */
#define IGEA_STATS_DIAG_RUNS_Z 7   /* z of R */
#define IGEA_STATS_DIAG_RUNS_P 8   /* two-sided p-value of z */
#define IGEA_STATS_DIAG_CENTER 9   /* c */
#define IGEA_STATS_DIAG_LEN 12

/* Start a streamed diagnostic: 1 lags L (1 .. IGEA_STATS_DIAG_LAGS_MAX),
 * 2 center c (finite; the series' mean), 3 state[IGEA_STATS_DIAG_STATE_LEN]
 * (written). Returns 0, -i. */
IGEA_API int igea_stats_diag_init(int lags, double center, double *state);

/* Add the next n values x[0], x[incx], ... of the series. 1 n >= 0,
 * 2 x (n values), 3 incx >= 1, 4 state (of igea_stats_diag_init; -4 for
 * one it did not write). Returns 0, -i, IGEA_ENONFINITE, IGEA_EOVERFLOW;
 * state is untouched on failure. */
IGEA_API int igea_stats_diag_add(int n, const double *x, int incx, double *state);

/* The statistics of the values added so far: 1 state, 2 out[IGEA_STATS_DIAG_LEN]
 * (above; the unnamed slots 0). Returns 0, -i, IGEA_EEMPTY (fewer than L + 2
 * values), IGEA_EDOMAIN (every value at the centre), IGEA_EOVERFLOW; out
 * is written only on success. */
IGEA_API int igea_stats_diag_result(const double *state, double *out);

/* Both tests of n values x[0], x[incx], ... about their mean: 1 n >= 1,
 * 2 x, 3 incx >= 1, 4 lags (1 .. IGEA_STATS_DIAG_LAGS_MAX), 5 out[IGEA_STATS_DIAG_LEN].
 * Returns those of igea_stats_diag_add and _result. */
IGEA_API int igea_stats_whiteness(int n, const double *x, int incx, int lags, double *out);

#ifdef __cplusplus
}
#endif
#endif
