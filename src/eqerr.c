/* eqerr.c - equivalent-error separation, sigma_w correction, tests
 * (METHODS 1.2). */
#include <float.h>

#include <cblas.h>
#include <lapacke.h>

#include "igea/eqerr.h"
#include "internal.h"

int igea__noise_check_opts(const double *o); /* noise.c */
int igea__noise_opts_set(const double *o);   /* noise.c */

int igea_eqerr_defaults(double *opts)
{
    if (!opts)
        return -1;
    for (int k = 0; k < IGEA_EQERR_OPT_LEN; k++)
        opts[k] = 0.0;
    opts[IGEA_EQERR_OPT_ALPHA] = 0.01;
    opts[IGEA_EQERR_OPT_LAMBDA_TEST] = 10.0;
    opts[IGEA_EQERR_OPT_LAMBDA_SMALL] = 0.1;
    opts[IGEA_EQERR_OPT_N_MIN] = 5;
    opts[IGEA_EQERR_OPT_TOL] = 0.05;
    opts[IGEA_EQERR_OPT_MAX_ITER] = 10;
    opts[IGEA_EQERR_OPT_CORRECTION] = 1;
    opts[IGEA_EQERR_OPT_ROUTE] = IGEA_EQERR_ROUTE_EIG;
    return 0;
}

int igea_eqerr_check_opts(const double *o)
{
    if (!o)
        return -1;
    for (int k = 0; k < IGEA_EQERR_OPT_LEN; k++)
        if (!isfinite(o[k]))
            return k + 1;
    if (!(o[IGEA_EQERR_OPT_ALPHA] > 0 && o[IGEA_EQERR_OPT_ALPHA] < 1)) return 1 + IGEA_EQERR_OPT_ALPHA;
    if (!(o[IGEA_EQERR_OPT_LAMBDA_TEST] > 0)) return 1 + IGEA_EQERR_OPT_LAMBDA_TEST;
    if (!(o[IGEA_EQERR_OPT_LAMBDA_SMALL] > 0)) return 1 + IGEA_EQERR_OPT_LAMBDA_SMALL;
    if (!(o[IGEA_EQERR_OPT_N_MIN] >= 1)) return 1 + IGEA_EQERR_OPT_N_MIN;
    if (!(o[IGEA_EQERR_OPT_TOL] > 0)) return 1 + IGEA_EQERR_OPT_TOL;
    if (!(o[IGEA_EQERR_OPT_MAX_ITER] >= 1 && o[IGEA_EQERR_OPT_MAX_ITER] <= 1000)) return 1 + IGEA_EQERR_OPT_MAX_ITER;
    if (o[IGEA_EQERR_OPT_CORRECTION] != 0 && o[IGEA_EQERR_OPT_CORRECTION] != 1) return 1 + IGEA_EQERR_OPT_CORRECTION;
    if (!(o[IGEA_EQERR_OPT_RANK_TOL] >= 0 && o[IGEA_EQERR_OPT_RANK_TOL] < 1)) return 1 + IGEA_EQERR_OPT_RANK_TOL;
    if (o[IGEA_EQERR_OPT_BIAS_CORRECT] != 0 && o[IGEA_EQERR_OPT_BIAS_CORRECT] != 1) return 1 + IGEA_EQERR_OPT_BIAS_CORRECT;
    if (o[IGEA_EQERR_OPT_CLAMP] != 0 && o[IGEA_EQERR_OPT_CLAMP] != 1) return 1 + IGEA_EQERR_OPT_CLAMP;
    if (!(o[IGEA_EQERR_OPT_Z_CRIT] >= 0)) return 1 + IGEA_EQERR_OPT_Z_CRIT;
    if (o[IGEA_EQERR_OPT_ROUTE] != IGEA_EQERR_ROUTE_EIG && o[IGEA_EQERR_OPT_ROUTE] != IGEA_EQERR_ROUTE_SVD) return 1 + IGEA_EQERR_OPT_ROUTE;
    const double v = o[IGEA_EQERR_OPT_VERDICT];
    if (!(v == IGEA_STATS_VERDICT_SEED || v == IGEA_STATS_VERDICT_CHI2 || v == IGEA_STATS_VERDICT_EXACT || v == IGEA_STATS_VERDICT_SIDAK)) return 1 + IGEA_EQERR_OPT_VERDICT;
    if (v != IGEA_STATS_VERDICT_SEED && o[IGEA_EQERR_OPT_Z_CRIT] != 0) return 1 + IGEA_EQERR_OPT_VERDICT;
    if (o[IGEA_EQERR_OPT_OVERALL_SIZE] != 0 && o[IGEA_EQERR_OPT_OVERALL_SIZE] != 1) return 1 + IGEA_EQERR_OPT_OVERALL_SIZE;
    const double vn = o[IGEA_EQERR_OPT_VERDICT_N];
    if (!(vn >= 0 && vn <= IGEA_STATS_DOF_MAX && vn == floor(vn))) return 1 + IGEA_EQERR_OPT_VERDICT_N;
    if (vn > 0) {
        if (!(o[IGEA_EQERR_OPT_VERDICT_A] >= 0)) return 1 + IGEA_EQERR_OPT_VERDICT_A;
        if (!(o[IGEA_EQERR_OPT_VERDICT_B] > 0)) return 1 + IGEA_EQERR_OPT_VERDICT_B;
        if (!(o[IGEA_EQERR_OPT_VERDICT_SIZE] >= 0 && o[IGEA_EQERR_OPT_VERDICT_SIZE] <= 1)) return 1 + IGEA_EQERR_OPT_VERDICT_SIZE;
    }
    const double nt = o[IGEA_EQERR_OPT_THREADS];
    if (!(nt >= 0 && nt <= IGEA_EQERR_THREADS_MAX && nt == floor(nt))) return 1 + IGEA_EQERR_OPT_THREADS;
    return igea__noise_check_opts(o); /* slots 20..27, igea/noise.h */
}

/*
 * Thresholds a (on |z_i|; +Inf: none), b (on T) and the overall size
 * (0: not computed) of rule o[OPT_VERDICT] for n tested components; zc and
 * c2 are the level-alpha z_crit and chi2_alpha(n) of the accuracy test.
 * vc (4 doubles per n = 1..nv: computed flag, a, b, size; NULL: none) is a
 * caller's cache, read and filled here.
 */
static int verdict_rule(const double *o, int n, double zc, double c2, double *vc, int nv,
                        double *a, double *b, double *size)
{
    const int rule = (int)o[IGEA_EQERR_OPT_VERDICT];
    const double alpha = o[IGEA_EQERR_OPT_ALPHA];
    double *e = vc && n >= 1 && n <= nv ? vc + 4 * (size_t)(n - 1) : NULL;
    if (e && e[0] == 1.0) {
        *a = e[1], *b = e[2], *size = e[3];
        return 0;
    }
    if (n >= 1 && o[IGEA_EQERR_OPT_VERDICT_N] == n) { /* the caller's precomputed values */
        *a = o[IGEA_EQERR_OPT_VERDICT_A] > 0 ? o[IGEA_EQERR_OPT_VERDICT_A] : HUGE_VAL;
        *b = o[IGEA_EQERR_OPT_VERDICT_B];
        *size = o[IGEA_EQERR_OPT_VERDICT_SIZE];
        return 0;
    }
    int st = 0;
    *size = 0.0;
    *a = zc;
    *b = c2;
    if (rule == IGEA_STATS_VERDICT_CHI2) {
        *a = HUGE_VAL;
        *size = alpha;
    } else if (rule == IGEA_STATS_VERDICT_EXACT) {
        if (n > IGEA_STATS_UNION_N_MAX)
            return IGEA_EVERDICT;
        st = igea_stats_verdict_thresholds(rule, n, alpha, a, b, size);
    } else {
        if (rule == IGEA_STATS_VERDICT_SIDAK) {
            st = igea_stats_normal_quantile(-0.5 * expm1(log1p(-alpha) / n), a);
            *a = -*a;
        }
        if (st == 0 && o[IGEA_EQERR_OPT_OVERALL_SIZE] == 1 && n <= IGEA_STATS_UNION_N_MAX)
            st = igea_stats_union_size(n, *a, *b, size);
    }
    if (st < 0 && st > -1000)
        st = IGEA_ENOCONV; /* a quantile out of reach: cannot happen for valid alpha */
    if (st == 0 && e) {
        e[0] = 1.0, e[1] = *a, e[2] = *b, e[3] = *size;
    }
    return st;
}

/* The verdict of the rule on the accuracy test's z[0..n_test) and info:
 * reject[], N_REJECT, PASSED and the VERDICT slots rewritten. */
static int apply_verdict(const double *o, const double *z, int *reject, double *info,
                         double *vc, int nv)
{
    int n = (int)info[IGEA_STATS_INFO_N_TEST];
    double a, b, size;
    int st = verdict_rule(o, n, info[IGEA_STATS_INFO_Z_CRIT], info[IGEA_STATS_INFO_CHI2_CRIT],
                          vc, nv, &a, &b, &size);
    if (st)
        return st;
    int nrej = 0;
    for (int i = 0; i < n; i++) {
        reject[i] = fabs(z[i]) > a;
        nrej += reject[i];
    }
    info[IGEA_STATS_INFO_N_REJECT] = nrej;
    info[IGEA_STATS_INFO_PASSED] = nrej == 0 && info[IGEA_STATS_INFO_CHI2] < b;
    info[IGEA_STATS_INFO_VERDICT] = o[IGEA_EQERR_OPT_VERDICT];
    info[IGEA_STATS_INFO_VERDICT_Z_CRIT] = isfinite(a) ? a : 0.0;
    info[IGEA_STATS_INFO_VERDICT_CHI2_CRIT] = b;
    info[IGEA_STATS_INFO_OVERALL_SIZE] = size;
    return 0;
}

/*
 * Step 3 (sigma_w iteration, exactly the METHODS pseudo-code) and steps 4-5.
 * lam0[N] descending (at c = 1), g0[r] = p_i^T b / sqrt(lam0_i), xhat[r].
 * Writes lambda[N], z[N], reject[N] and info; returns 0 or a failure (the
 * outputs are then scratch owned by the caller, who discards them).
 */
static int sigmaw_and_test(int N, int r, const double *lam0, const double *g0,
                           const double *xhat, const double *o, double *vc, double *cc,
                           const double *den0, int want_p, double *lambda, double *z,
                           int *reject, double *info)
{
    double c = 1.0;
    int flag = IGEA_STATS_SIGMAW_OFF, iters = 0, nsmall = 0;
    if (o[IGEA_EQERR_OPT_CORRECTION] == 1) {
        const double lam_s = o[IGEA_EQERR_OPT_LAMBDA_SMALL];
        const int nmin = (int)o[IGEA_EQERR_OPT_N_MIN];
        const int maxit = (int)o[IGEA_EQERR_OPT_MAX_ITER];
        const int bias = o[IGEA_EQERR_OPT_BIAS_CORRECT] == 1;
        const int clamp = o[IGEA_EQERR_OPT_CLAMP] == 1;
        int prev_lo = -1; /* the small set is the suffix [lo, r) */
        flag = IGEA_STATS_SIGMAW_NO_CONVERGENCE;
        for (int it = 0; it < maxit; it++) {
            iters = it + 1;
            int lo = r;
            while (lo > 0 && lam0[lo - 1] / c <= lam_s)
                lo--;
            nsmall = r - lo;
            if (nsmall < nmin) {
                flag = IGEA_STATS_SIGMAW_NOT_ESTIMABLE;
                break;
            }
            igea__ksum acc = {0, 0};
            for (int i = lo; i < r; i++) {
                double g2 = g0[i] * g0[i] / c;
                igea__ksum_add(&acc, bias ? g2 - lam0[i] / c : g2);
            }
            double sw2 = igea__ksum_get(&acc) / nsmall;
            if (!(sw2 > 0.0) || !isfinite(sw2)) {
                flag = IGEA_STATS_SIGMAW_NOT_ESTIMABLE;
                break;
            }
            if (fabs(sw2 - 1.0) <= o[IGEA_EQERR_OPT_TOL] && (it == 0 || lo == prev_lo)) {
                flag = IGEA_STATS_SIGMAW_CONVERGED;
                break;
            }
            prev_lo = lo;
            double cn = c * sw2;
            if (clamp && cn < 1.0) {
                if (c == 1.0) {
                    flag = IGEA_STATS_SIGMAW_CONVERGED;
                    break;
                }
                cn = 1.0;
            }
            c = cn;
        }
    }
    for (int i = 0; i < N; i++)
        lambda[i] = lam0[i] / c;
    if (r == 0)
        return IGEA_ENOTESTABLE;
    /* at c = 1, lambda = lam0 to the bit: the caller's sqrt(1 + 1 / lam0) */
    int st = igea__stats_accuracy_cached(r, xhat, lambda, o[IGEA_EQERR_OPT_ALPHA],
                                         o[IGEA_EQERR_OPT_LAMBDA_TEST],
                                         o[IGEA_EQERR_OPT_Z_CRIT], cc,
                                         c == 1.0 ? den0 : NULL, want_p, z, reject, info);
    if (st != 0)
        return st < 0 && st > -1000 ? IGEA_EDOMAIN : st;
    for (int i = r; i < N; i++) {
        z[i] = 0.0;
        reject[i] = -1;
    }
    info[IGEA_STATS_INFO_RANK] = r;
    info[IGEA_STATS_INFO_SCALE] = c;
    info[IGEA_STATS_INFO_ITERATIONS] = iters;
    info[IGEA_STATS_INFO_N_SMALL] = nsmall;
    info[IGEA_STATS_INFO_FLAG] = flag;
    for (int k = IGEA_STATS_INFO_FLAG + 1; k < IGEA_STATS_INFO_LEN; k++)
        info[k] = 0.0;
    info[IGEA_STATS_INFO_SIGMA_W] = sqrt(c);
    return apply_verdict(o, z, reject, info, vc, N);
}

/* Scratch results, copied to the caller's arrays only on success. */
typedef struct {
    double *lam0, *V, *g0, *xhat, *lambda, *z, *info;
    int *reject;
} scratch;

static int scratch_alloc(scratch *s, int N)
{
    size_t n = (size_t)N;
    s->lam0 = igea__dalloc(n * n + 6 * n + IGEA_STATS_INFO_LEN);
    s->reject = igea__ialloc(n);
    if (!s->lam0 || !s->reject) {
        free(s->lam0);
        free(s->reject);
        return IGEA_ENOMEM;
    }
    s->V = s->lam0 + n;
    s->g0 = s->V + n * n;
    s->xhat = s->g0 + n;
    s->lambda = s->xhat + n;
    s->z = s->lambda + n;
    s->info = s->z + n;
    for (size_t i = 0; i < n; i++)
        s->xhat[i] = s->g0[i] = 0.0;
    return 0;
}

/* 1 when every result in the scratch is finite. */
static int scratch_finite(const scratch *s, int N)
{
    return igea__finite_vec(N, s->lambda, 1) && igea__finite_mat(N, N, s->V, N) &&
           igea__finite_vec(N, s->xhat, 1) && igea__finite_vec(N, s->z, 1) &&
           igea__finite_vec(IGEA_STATS_INFO_LEN, s->info, 1);
}

static void scratch_free(scratch *s)
{
    free(s->lam0);
    free(s->reject);
}

static void scratch_out(const scratch *s, int N, double *lambda, double *P,
                        int ldp, double *equiv_err, double *z, int *reject,
                        double *info)
{
    size_t n = (size_t)N;
    memcpy(lambda, s->lambda, n * sizeof(double));
    for (int j = 0; j < N; j++)
        memcpy(P + (size_t)j * ldp, s->V + (size_t)j * n, n * sizeof(double));
    memcpy(equiv_err, s->xhat, n * sizeof(double));
    memcpy(z, s->z, n * sizeof(double));
    memcpy(reject, s->reject, n * sizeof(int));
    memcpy(info, s->info, IGEA_STATS_INFO_LEN * sizeof(double));
}

/* The end of a solve with status st: the scratch results checked finite
 * (else IGEA_EOVERFLOW) and copied out, the scratch freed. */
static int scratch_finish(scratch *s, int st, int N, double *lambda, double *P,
                          int ldp, double *equiv_err, double *z, int *reject,
                          double *info)
{
    if (st == 0 && !scratch_finite(s, N))
        st = IGEA_EOVERFLOW;
    if (st == 0)
        scratch_out(s, N, lambda, P, ldp, equiv_err, z, reject, info);
    scratch_free(s);
    return st;
}

/* Eig route from normal equations into the scratch. */
static int solve_eig(int N, const double *A, int lda, const double *b,
                     const double *o, double *vc, scratch *s)
{
    int st = igea__syev_desc(N, A, lda, s->lam0, s->V, N);
    if (st != 0)
        return st;
    double tol = o[IGEA_EQERR_OPT_RANK_TOL] > 0 ? o[IGEA_EQERR_OPT_RANK_TOL]
                                                 : N * 10.0 * DBL_EPSILON;
    int r = igea__rank_cut(N, s->lam0, tol);
    for (int i = 0; i < r; i++) {
        double pb = cblas_ddot(N, s->V + (size_t)i * N, 1, b, 1);
        s->xhat[i] = pb / s->lam0[i];
        s->g0[i] = pb / sqrt(s->lam0[i]);
    }
    return sigmaw_and_test(N, r, s->lam0, s->g0, s->xhat, o, vc, NULL, NULL, 1, s->lambda, s->z,
                           s->reject, s->info);
}

/* Arguments 5-12, common to igea_eqerr_solve and igea_eqerr_solve_qr;
 * *opts NULL is replaced by the defaults written into dflt. */
static int check_solve_args(int N, const double **opts, double *dflt,
                            const double *lambda, const double *P, int ldp,
                            const double *equiv_err, const double *z,
                            const int *reject, const double *info)
{
    if (!*opts) {
        igea_eqerr_defaults(dflt);
        *opts = dflt;
    } else if (igea_eqerr_check_opts(*opts))
        return -5;
    if (!lambda) return -6;
    if (!P) return -7;
    if (ldp < N) return -8;
    if (!equiv_err) return -9;
    if (!z) return -10;
    if (!reject) return -11;
    if (!info) return -12;
    return 0;
}

int igea_eqerr_solve(int N, const double *A, int lda, const double *b,
                     const double *opts, double *lambda, double *P, int ldp,
                     double *equiv_err, double *z, int *reject, double *info)
{
    return igea__eqerr_solve_cached(N, A, lda, b, opts, NULL, lambda, P, ldp, equiv_err,
                                    z, reject, info);
}

int igea__eqerr_solve_cached(int N, const double *A, int lda, const double *b,
                             const double *opts, double *vcache, double *lambda, double *P,
                             int ldp, double *equiv_err, double *z, int *reject,
                             double *info)
{
    double dflt[IGEA_EQERR_OPT_LEN];
    if (N < 1) return -1;
    if (!A) return -2;
    if (lda < N) return -3;
    if (!b) return -4;
    int st = check_solve_args(N, &opts, dflt, lambda, P, ldp, equiv_err, z, reject, info);
    if (st)
        return st;
    for (int j = 0; j < N; j++)
        if (!igea__finite_vec(N - j, &IGEA_AT(A, lda, j, j), 1))
            return IGEA_ENONFINITE;
    if (!igea__finite_vec(N, b, 1))
        return IGEA_ENONFINITE;
    scratch s;
    if (scratch_alloc(&s, N))
        return IGEA_ENOMEM;
    st = solve_eig(N, A, lda, b, opts, vcache, &s);
    return scratch_finish(&s, st, N, lambda, P, ldp, equiv_err, z, reject, info);
}

/* SVD route from the QR factor R ((N+1) x (N+1), upper) of [S~ w~]: the
 * SVD of R[0:N, 0:N] = U diag(s) V' gives lambda = s^2, P = V, and
 * g_i = u_i' (Q' w~) = u_i' R[0:N, N] (METHODS 1.2 step 2, SVD form). */
static int solve_qr(int N, const double *R, int ldr, double rows, const double *o,
                    scratch *s)
{
    size_t nn = (size_t)N * N;
    double *Rc = igea__dalloc(2 * nn + (size_t)N);
    if (!Rc)
        return IGEA_ENOMEM;
    double *U = Rc + nn, *sv = U + nn;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++)
            Rc[i + (size_t)j * N] = i <= j ? IGEA_AT(R, ldr, i, j) : 0.0;
    /* V with the METHODS 0.3 signs, U's columns flipped with V's. */
    int st = igea__svd(N, N, Rc, sv, U, 0, s->V);
    if (st == 0) {
        double tol = o[IGEA_EQERR_OPT_RANK_TOL] > 0
                         ? sqrt(o[IGEA_EQERR_OPT_RANK_TOL])
                         : IGEA_MAX(rows, (double)N) * DBL_EPSILON;
        int r = igea__rank_cut(N, sv, tol);
        const double *qtw = &IGEA_AT(R, ldr, 0, N);
        for (int i = 0; i < N; i++) {
            s->lam0[i] = sv[i] * sv[i];
            if (i < r) {
                double g = 0.0;
                for (int k = 0; k < N; k++)
                    g += U[k + (size_t)i * N] * qtw[k];
                s->g0[i] = g;
                s->xhat[i] = s->g0[i] / sv[i];
            }
        }
        /* lambda = s^2 of a finite factor may leave the double range. */
        for (int i = 0; i < N; i++)
            if (!isfinite(s->lam0[i]) || (i < r && !(s->lam0[i] >= DBL_MIN)))
                st = IGEA_EOVERFLOW;
        if (st == 0)
            st = sigmaw_and_test(N, r, s->lam0, s->g0, s->xhat, o, NULL, NULL, NULL, 1, s->lambda,
                                 s->z, s->reject, s->info);
    }
    free(Rc);
    return st;
}

int igea_eqerr_solve_qr(int N, const double *R, int ldr, double rows, const double *opts,
                        double *lambda, double *P, int ldp, double *equiv_err, double *z,
                        int *reject, double *info)
{
    double dflt[IGEA_EQERR_OPT_LEN];
    if (N < 1) return -1;
    if (!R) return -2;
    if (ldr < N + 1) return -3;
    if (!(rows >= 1.0) || !isfinite(rows)) return -4;
    int st = check_solve_args(N, &opts, dflt, lambda, P, ldp, equiv_err, z, reject, info);
    if (st)
        return st;
    for (int j = 0; j <= N; j++)
        if (!igea__finite_vec(j + 1, &IGEA_AT(R, ldr, 0, j), 1))
            return IGEA_ENONFINITE;
    scratch s;
    if (scratch_alloc(&s, N))
        return IGEA_ENOMEM;
    st = solve_qr(N, R, ldr, rows, opts, &s);
    return scratch_finish(&s, st, N, lambda, P, ldp, equiv_err, z, reject, info);
}

int igea_eqerr_coef(int N, const double *P, int ldp, const double *equiv_err,
                    int n_test, const double *spec_sigma, double *coef)
{
    if (N < 1) return -1;
    if (!P) return -2;
    if (ldp < N) return -3;
    if (!equiv_err) return -4;
    if (n_test < 0 || n_test > N) return -5;
    if (!coef) return -7;
    if (!igea__finite_mat(N, n_test, P, ldp) || !igea__finite_vec(n_test, equiv_err, 1))
        return IGEA_ENONFINITE;
    if (spec_sigma) {
        int st = igea__sigma_vec(N, spec_sigma);
        if (st)
            return st;
    }
    for (int i = 0; i < N; i++) {
        double acc = 0.0;
        for (int k = 0; k < n_test; k++)
            acc += IGEA_AT(P, ldp, i, k) * equiv_err[k];
        if (!isfinite(acc * (spec_sigma ? spec_sigma[i] : 1.0)))
            return IGEA_EOVERFLOW;
    }
    for (int i = 0; i < N; i++) {
        double acc = 0.0;
        for (int k = 0; k < n_test; k++)
            acc += IGEA_AT(P, ldp, i, k) * equiv_err[k];
        coef[i] = acc * (spec_sigma ? spec_sigma[i] : 1.0);
    }
    return 0;
}

/* e (m) -= S coef for row-major S (m rows, lds apart) [D]: each residual
 * its own dot product, in eight lanes (term j in lane j mod 8; the terms
 * past the last multiple of 8 added to lane 0 in order), the lanes combined
 * as ((0 + 1) + (2 + 3)) + ((4 + 5) + (6 + 7)), then subtracted from e: the
 * bits of a row depend on that row and coef only, never on the block it is
 * in, the thread that runs it or the processor's vector width (the vector
 * form computes the same lanes). The rows stream from memory in order
 * (dgemv's transposed kernel took 1.7x the time of one read of S here). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && \
    !defined(IGEA_NO_CLONES)
#define RD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define RD_CLONES
#endif
#if defined(__GNUC__)
typedef double rd_v4 __attribute__((vector_size(32), aligned(8)));
#define RD_LD(p) (*(const rd_v4 *)(const void *)(p))
#endif

static inline double rd_comb(double s0, double s1, double s2, double s3, double s4, double s5,
                             double s6, double s7)
{
    return ((s0 + s1) + (s2 + s3)) + ((s4 + s5) + (s6 + s7));
}

RD_CLONES static void rows_dot(int m, int N, const double *S, int lds, const double *coef,
                               double *e)
{
    const int n8 = N & ~7;
    for (int i = 0; i < m; i++) {
        const double *r = S + (size_t)i * lds;
#if defined(__GNUC__)
        rd_v4 va = {0, 0, 0, 0}, vb = {0, 0, 0, 0};
        for (int j = 0; j < n8; j += 8) {
            va += RD_LD(r + j) * RD_LD(coef + j);
            vb += RD_LD(r + j + 4) * RD_LD(coef + j + 4);
        }
        double s0 = va[0], s1 = va[1], s2 = va[2], s3 = va[3], s4 = vb[0], s5 = vb[1],
               s6 = vb[2], s7 = vb[3];
#else
        double s0 = 0, s1 = 0, s2 = 0, s3 = 0, s4 = 0, s5 = 0, s6 = 0, s7 = 0;
        for (int j = 0; j < n8; j += 8) {
            s0 += r[j] * coef[j];
            s1 += r[j + 1] * coef[j + 1];
            s2 += r[j + 2] * coef[j + 2];
            s3 += r[j + 3] * coef[j + 3];
            s4 += r[j + 4] * coef[j + 4];
            s5 += r[j + 5] * coef[j + 5];
            s6 += r[j + 6] * coef[j + 6];
            s7 += r[j + 7] * coef[j + 7];
        }
#endif
        for (int j = n8; j < N; j++)
            s0 += r[j] * coef[j];
        e[i] -= rd_comb(s0, s1, s2, s3, s4, s5, s6, s7);
    }
}

/* igea_eqerr_residual after its checks (m >= 1): the residuals into e (m),
 * the per-axis sums added to t (NULL: none); 0 or the status (e and t
 * then hold partial results). */
static int residual_into(int layout, int m, int N, const double *S, int lds, const double *dw,
                         const double *coef, int row0, double *e, double *t)
{
    memcpy(e, dw, (size_t)m * sizeof(double));
    if (layout == IGEA_COLMAJOR)
        cblas_dgemv(CblasColMajor, CblasNoTrans, m, N, -1.0, S, lds, coef, 1,
                    1.0, e, 1);
    else
        rows_dot(m, N, S, lds, coef, e);
    if (!igea__finite_vec(m, e, 1))
        return (layout == IGEA_COLMAJOR ? igea__finite_mat(m, N, S, lds)
                                        : igea__finite_mat(N, m, S, lds))
                   ? IGEA_EOVERFLOW
                   : IGEA_ENONFINITE;
    if (!t)
        return 0;
    /* per axis, its rows' squares in row order */
    for (int i0 = 0; i0 < 3 && i0 < m; i0++) {
        int a = (int)(((long long)row0 + i0) % 3);
        double acc = t[a];
        for (int i = i0; i < m; i += 3)
            acc += e[i] * e[i];
        t[a] = acc;
        t[3 + a] += (double)((m - i0 + 2) / 3);
    }
    return igea__finite_vec(3, t, 1) ? 0 : IGEA_EOVERFLOW;
}

/* igea_eqerr_residual's checks of its arguments 1-8 and of coef and dw. */
static int residual_check(int layout, int m, int N, const double *S, int lds,
                          const double *dw, const double *coef, int row0)
{
    if (layout != IGEA_COLMAJOR && layout != IGEA_ROWMAJOR) return -1;
    if (m < 0) return -2;
    if (N < 1) return -3;
    if (!S && m > 0) return -4;
    if (lds < IGEA_MAX(1, layout == IGEA_COLMAJOR ? m : N)) return -5;
    if (!dw && m > 0) return -6;
    if (!coef) return -7;
    if (row0 < 0) return -8;
    if (!igea__finite_vec(N, coef, 1) || !igea__finite_vec(m, dw, 1))
        return IGEA_ENONFINITE;
    return 0;
}

int igea_eqerr_residual(int layout, int m, int N, const double *S, int lds,
                        const double *dw, const double *coef, int row0,
                        double *residual, double *axis_ss)
{
    int st0 = residual_check(layout, m, N, S, lds, dw, coef, row0);
    if (st0 || m == 0)
        return st0;
    double *e = igea__dalloc((size_t)m), t[6];
    if (!e)
        return IGEA_ENOMEM;
    if (axis_ss)
        memcpy(t, axis_ss, sizeof t);
    int st = residual_into(layout, m, N, S, lds, dw, coef, row0, e, axis_ss ? t : NULL);
    if (st == 0 && axis_ss)
        memcpy(axis_ss, t, sizeof t);
    if (st == 0 && residual)
        memcpy(residual, e, (size_t)m * sizeof(double));
    free(e);
    return st;
}

/* igea_eqerr_run's SVD route: the QR factor of the weighted [S D, dw],
 * then solve_qr. */
static int run_svd(int layout, int m, int N, const double *S, int lds, const double *dw,
                   const double *track_sigma, int sigma_inc,
                   const double *spec_sigma, const double *opts, scratch *s)
{
    size_t n1 = (size_t)N + 1;
    double *R = igea__dalloc(n1 * n1), rows = 0.0;
    if (!R)
        return IGEA_ENOMEM;
    memset(R, 0, n1 * n1 * sizeof(double));
    int st = igea_normal_qr_accumulate(layout, m, N, S, lds, dw, track_sigma,
                                       sigma_inc, spec_sigma, R, (int)n1, &rows);
    if (st < 0 && st > -1000)
        st = IGEA_EDOMAIN; /* cannot happen: arguments checked above */
    if (st == 0)
        st = solve_qr(N, R, (int)n1, rows, opts, s);
    free(R);
    return st;
}

/* igea_eqerr_run's eig route: the normal equations, then solve_eig. */
static int run_eig(int layout, int m, int N, const double *S, int lds, const double *dw,
                   const double *track_sigma, int sigma_inc,
                   const double *spec_sigma, const double *opts, scratch *s)
{
    size_t nn = (size_t)N * N;
    double *A = igea__dalloc(nn + N + 2);
    if (!A)
        return IGEA_ENOMEM;
    double *b = A + nn, *wtw = b + N;
    memset(A, 0, (nn + N + 2) * sizeof(double));
    /* the arguments and sigmas were checked by igea_eqerr_run */
    int st = igea__normal_accumulate_threads(layout, m, N, S, lds, dw, track_sigma,
                                             sigma_inc, spec_sigma, A, N, b, wtw,
                                             (int)opts[IGEA_EQERR_OPT_THREADS]);
    if (st < 0 && st > -1000)
        st = IGEA_EDOMAIN; /* cannot happen: arguments checked above */
    if (st == 0)
        st = solve_eig(N, A, N, b, opts, NULL, s);
    free(A);
    return st;
}

/* ---- the residual pass on several threads ---------------------------------- */

/* The segments of igea_normal_accumulate_threads (IGEA_NORMAL_SEGMENT rows):
 * each segment's residuals by its own dgemv and its per-axis sums into its
 * own 6 slots, whatever thread runs it; the sums are added in segment order
 * afterwards, so the result does not depend on the thread count. */
typedef struct {
    int layout, m, N, lds, nseg, row0;
    const double *S, *dw, *coef;
    double *e, *part; /* e: m; part: nseg x 6, each segment's axis_ss */
} rs_job;

/* Segment k: its residuals, and per axis a (row r0 + i of the block,
 * (row0 + r0 + i) mod 3 = a) the sum of their squares in row order and
 * their count. A non-finite dw or residual makes the sums non-finite:
 * rs_sum finds out why. */
static void rs_segment(void *arg, int k)
{
    const rs_job *jb = arg;
    int r0 = k * IGEA_NORMAL_SEGMENT, nr = IGEA_MIN(IGEA_NORMAL_SEGMENT, jb->m - r0);
    double *e = jb->e + r0, *t = jb->part + 6 * (size_t)k;
    memcpy(e, jb->dw + r0, (size_t)nr * sizeof(double));
    if (jb->layout == IGEA_COLMAJOR)
        cblas_dgemv(CblasColMajor, CblasNoTrans, nr, jb->N, -1.0, jb->S + r0, jb->lds,
                    jb->coef, 1, 1.0, e, 1);
    else
        rows_dot(nr, jb->N, jb->S + (size_t)r0 * jb->lds, jb->lds, jb->coef, e);
    for (int i0 = 0; i0 < 3 && i0 < nr; i0++) {
        int a = (int)(((long long)jb->row0 + r0 + i0) % 3);
        double acc = 0.0;
        for (int i = i0; i < nr; i += 3)
            acc += e[i] * e[i];
        t[a] = acc;
        t[3 + a] = (double)((nr - i0 + 2) / 3);
    }
}

/* The segments' sums added in segment order to ss (input-output); when
 * they are not finite, igea_eqerr_residual's status: a non-finite dw, or a
 * non-finite residual from a non-finite S: IGEA_ENONFINITE; else
 * IGEA_EOVERFLOW. */
static int rs_sum(const rs_job *jb, double *ss)
{
    double t[6];
    memcpy(t, ss, sizeof t);
    for (int k = 0; k < jb->nseg; k++)
        for (int j = 0; j < 6; j++)
            t[j] += jb->part[6 * (size_t)k + j];
    if (igea__finite_vec(3, t, 1)) {
        memcpy(ss, t, sizeof t);
        return 0;
    }
    if (!igea__finite_vec(jb->m, jb->dw, 1))
        return IGEA_ENONFINITE;
    if (!igea__finite_vec(jb->m, jb->e, 1) &&
        !(jb->layout == IGEA_COLMAJOR ? igea__finite_mat(jb->m, jb->N, jb->S, jb->lds)
                                      : igea__finite_mat(jb->N, jb->m, jb->S, jb->lds)))
        return IGEA_ENONFINITE;
    return IGEA_EOVERFLOW;
}

/* igea_eqerr_residual on nthreads >= 2 threads after its checks (m >= 1),
 * the segments' sums added to ss: e (m, scratch) and ss (6) hold the
 * results on success; ss is untouched on failure. */
static int residual_threads(int layout, int m, int N, const double *S, int lds,
                            const double *dw, const double *coef, int row0, double *e,
                            double *ss, int nthreads)
{
    if (!igea__finite_vec(N, coef, 1))
        return IGEA_ENONFINITE;
    int nseg = (m + IGEA_NORMAL_SEGMENT - 1) / IGEA_NORMAL_SEGMENT;
    double *part = igea__dalloc(6 * (size_t)nseg);
    int st = IGEA_ENOMEM;
    if (part) {
        memset(part, 0, 6 * (size_t)nseg * sizeof(double));
        rs_job jb = {layout, m, N, lds, nseg, row0, S, dw, coef, e, part};
        igea__parallel_for(nseg, nthreads, rs_segment, &jb);
        st = rs_sum(&jb, ss);
    }
    free(part);
    return st;
}

/* The residuals copied out segment by segment on the threads (the pages of
 * a fresh output are first touched there too). */
typedef struct {
    const double *e;
    double *out;
    int m;
} cp_job;

static void cp_segment(void *arg, int k)
{
    const cp_job *jb = arg;
    size_t r0 = (size_t)k * IGEA_NORMAL_SEGMENT;
    size_t nr = (size_t)IGEA_MIN(IGEA_NORMAL_SEGMENT, jb->m - (int)r0);
    memcpy(jb->out + r0, jb->e + r0, nr * sizeof(double));
}

static void copy_out(int m, const double *e, double *out, int nthreads)
{
    cp_job jb = {e, out, m};
    if (nthreads >= 2)
        igea__parallel_for((m + IGEA_NORMAL_SEGMENT - 1) / IGEA_NORMAL_SEGMENT, nthreads,
                           cp_segment, &jb);
    else
        memcpy(out, e, (size_t)m * sizeof(double));
}

/* Residuals e (m) and the per-axis sums ss of the fit in the scratch; the
 * route eig's thread count (IGEA_EQERR_OPT_THREADS) >= 2: on that many
 * threads, in the normal equations' segments. */
static int run_residuals(int layout, int m, int N, const double *S, int lds, const double *dw,
                         const double *spec_sigma, const double *opts, const scratch *s,
                         double *coef, double *e, double *ss)
{
    int st = igea_eqerr_coef(N, s->V, N, s->xhat, (int)s->info[IGEA_STATS_INFO_N_TEST],
                             spec_sigma, coef);
    int nthreads = opts[IGEA_EQERR_OPT_ROUTE] == IGEA_EQERR_ROUTE_SVD
                       ? 1
                       : (int)opts[IGEA_EQERR_OPT_THREADS];
    if (st == 0 && nthreads >= 2)
        st = residual_threads(layout, m, N, S, lds, dw, coef, 0, e, ss, nthreads);
    else if (st == 0 && (!igea__finite_vec(N, coef, 1) || !igea__finite_vec(m, dw, 1)))
        st = IGEA_ENONFINITE;
    else if (st == 0) /* igea_eqerr_residual, into e itself */
        st = residual_into(layout, m, N, S, lds, dw, coef, 0, e, ss);
    return st;
}

int igea_eqerr_residual_threads(int layout, int m, int N, const double *S, int lds,
                                const double *dw, const double *coef, int row0,
                                double *residual, double *axis_ss, int nthreads)
{
    if (nthreads <= 1 && nthreads >= 0)
        return igea_eqerr_residual(layout, m, N, S, lds, dw, coef, row0, residual, axis_ss);
    int st0 = residual_check(layout, m, N, S, lds, dw, coef, row0);
    if (st0 < 0)
        return st0;
    if (nthreads < 0 || nthreads > IGEA_NORMAL_THREADS_MAX)
        return -11;
    if (st0 || m == 0)
        return st0;
    double *e = igea__dalloc((size_t)m), t[6] = {0, 0, 0, 0, 0, 0};
    if (!e)
        return IGEA_ENOMEM;
    if (axis_ss)
        memcpy(t, axis_ss, sizeof t);
    int st = residual_threads(layout, m, N, S, lds, dw, coef, row0, e, t, nthreads);
    /* without axis_ss, as igea_eqerr_residual: only a residual that is
     * not finite fails (the sums of squares may overflow) */
    if (!axis_ss && st == IGEA_EOVERFLOW && igea__finite_vec(m, e, 1))
        st = 0;
    if (st == 0 && axis_ss)
        memcpy(axis_ss, t, sizeof t);
    if (st == 0 && residual)
        memcpy(residual, e, (size_t)m * sizeof(double));
    free(e);
    return st;
}

/* igea_eqerr_run in either layout; the statuses -i of its arguments are
 * -(i + off) (off = 1 for igea_eqerr_run_layout, whose first argument is
 * the layout). */
static int run_layout(int layout, int off, int m, int N, const double *S, int lds,
                      const double *dw, const double *track_sigma, int sigma_inc,
                      const double *spec_sigma, const double *opts, double *lambda, double *P,
                      int ldp, double *equiv_err, double *z, int *reject, double *info,
                      double *residual, double *rms)
{
    double dflt[IGEA_EQERR_OPT_LEN];
    if (m < 1) return -1 - off;
    if (N < 1) return -2 - off;
    if (!S) return -3 - off;
    if (lds < (layout == IGEA_COLMAJOR ? m : N)) return -4 - off;
    if (!dw) return -5 - off;
    if (!track_sigma) return -6 - off;
    if (sigma_inc != 0 && sigma_inc != 1) return -7 - off;
    if (!opts) {
        igea_eqerr_defaults(dflt);
        opts = dflt;
    } else if (igea_eqerr_check_opts(opts) || igea__noise_opts_set(opts))
        return -9 - off; /* AR, robust, bias columns: igea_noise_eqerr */
    if (!lambda) return -10 - off;
    if (!P) return -11 - off;
    if (ldp < N) return -12 - off;
    if (!equiv_err) return -13 - off;
    if (!z) return -14 - off;
    if (!reject) return -15 - off;
    if (!info) return -16 - off;
    int st = igea__sigma_vec(sigma_inc ? m : 1, track_sigma);
    if (st == 0 && spec_sigma)
        st = igea__sigma_vec(N, spec_sigma);
    if (st)
        return st;

    scratch s;
    if (scratch_alloc(&s, N))
        return IGEA_ENOMEM;
    st = opts[IGEA_EQERR_OPT_ROUTE] == IGEA_EQERR_ROUTE_SVD
             ? run_svd(layout, m, N, S, lds, dw, track_sigma, sigma_inc, spec_sigma, opts, &s)
             : run_eig(layout, m, N, S, lds, dw, track_sigma, sigma_inc, spec_sigma, opts, &s);
    if (st == 0 && !scratch_finite(&s, N))
        st = IGEA_EOVERFLOW;
    double *coef = NULL, *e = NULL, ss[6] = {0, 0, 0, 0, 0, 0};
    if (st == 0 && (residual || rms)) {
        coef = igea__dalloc((size_t)N);
        e = igea__dalloc((size_t)m);
        st = !coef || !e ? IGEA_ENOMEM
                         : run_residuals(layout, m, N, S, lds, dw, spec_sigma, opts, &s, coef,
                                         e, ss);
    }
    if (st == 0) {
        scratch_out(&s, N, lambda, P, ldp, equiv_err, z, reject, info);
        if (residual)
            copy_out(m, e, residual,
                     opts[IGEA_EQERR_OPT_ROUTE] == IGEA_EQERR_ROUTE_SVD
                         ? 1
                         : (int)opts[IGEA_EQERR_OPT_THREADS]);
        if (rms)
            for (int a = 0; a < 3; a++)
                rms[a] = ss[3 + a] > 0 ? sqrt(ss[a] / ss[3 + a]) : 0.0;
    }
    free(coef);
    free(e);
    scratch_free(&s);
    return st;
}

int igea_eqerr_run(int m, int N, const double *S, int lds, const double *dw,
                   const double *track_sigma, int sigma_inc,
                   const double *spec_sigma, const double *opts,
                   double *lambda, double *P, int ldp, double *equiv_err,
                   double *z, int *reject, double *info, double *residual,
                   double *rms)
{
    return run_layout(IGEA_COLMAJOR, 0, m, N, S, lds, dw, track_sigma, sigma_inc, spec_sigma,
                      opts, lambda, P, ldp, equiv_err, z, reject, info, residual, rms);
}

int igea_eqerr_run_layout(int layout, int m, int N, const double *S, int lds,
                          const double *dw, const double *track_sigma, int sigma_inc,
                          const double *spec_sigma, const double *opts, double *lambda,
                          double *P, int ldp, double *equiv_err, double *z, int *reject,
                          double *info, double *residual, double *rms)
{
    if (layout != IGEA_COLMAJOR && layout != IGEA_ROWMAJOR)
        return -1;
    return run_layout(layout, 1, m, N, S, lds, dw, track_sigma, sigma_inc, spec_sigma, opts,
                      lambda, P, ldp, equiv_err, z, reject, info, residual, rms);
}

/* ---- pooled verdict, report quantities ------------------------------------ */

int igea_eqerr_pool(int nflights, const double *chi2, const int *dof, const double *z,
                    const int *unit_id, const double *opts, int *reject, double *info)
{
    double dflt[IGEA_EQERR_OPT_LEN];
    if (nflights < 1) return -1;
    if (!chi2) return -2;
    if (!dof) return -3;
    if (!z) return -4;
    if (!opts) {
        igea_eqerr_defaults(dflt);
        opts = dflt;
    } else if (igea_eqerr_check_opts(opts))
        return -6;
    if (!info) return -8;
    double ntot = 0.0;
    for (int f = 0; f < nflights; f++) {
        if (dof[f] < 1) return -3;
        ntot += dof[f];
    }
    if (ntot > IGEA_STATS_DOF_MAX) return -3;
    if (!igea__finite_vec((int)ntot, z, 1))
        return IGEA_ENONFINITE;
    int *nrej0 = igea__ialloc((size_t)nflights);
    if (!nrej0)
        return IGEA_ENOMEM;
    memset(nrej0, 0, (size_t)nflights * sizeof(int));
    double t[IGEA_STATS_INFO_LEN];
    int st = igea_stats_pool(nflights, chi2, dof, nrej0, unit_id,
                             opts[IGEA_EQERR_OPT_ALPHA], t);
    free(nrej0);
    if (st < 0 && st > -1000)
        return st == -4 ? IGEA_EDOMAIN : st; /* -1, -2 (chi2 < 0), -3, -5 as ours */
    if (st)
        return st;
    if (opts[IGEA_EQERR_OPT_Z_CRIT] > 0)
        t[IGEA_STATS_INFO_Z_CRIT] = opts[IGEA_EQERR_OPT_Z_CRIT];
    int n = (int)ntot;
    int *rej = igea__ialloc((size_t)n);
    if (!rej)
        return IGEA_ENOMEM;
    st = apply_verdict(opts, z, rej, t, NULL, 0);
    if (st == 0 && reject)
        memcpy(reject, rej, (size_t)n * sizeof(int));
    free(rej);
    if (st)
        return st;
    memcpy(info, t, sizeof t);
    return 0;
}

int igea_eqerr_limits(int n, const double *lambda, double z_crit, double *threshold,
                      double *precision)
{
    if (n < 1) return -1;
    if (!lambda) return -2;
    if (!(z_crit >= 0) || !isfinite(z_crit)) return -3;
    for (int i = 0; i < n; i++)
        if (!(lambda[i] > 0) || !isfinite(lambda[i]))
            return isfinite(lambda[i]) ? IGEA_ENONPOSITIVE : IGEA_ENONFINITE;
    for (int i = 0; i < n; i++) {
        if (threshold)
            threshold[i] = sqrt(1.0 + 1.0 / lambda[i]) * z_crit;
        if (precision)
            precision[i] = 1.0 / sqrt(lambda[i]);
    }
    return 0;
}

int igea_eqerr_axis_rms(const double *axis_ss, double *rms)
{
    if (!axis_ss) return -1;
    if (!rms) return -2;
    if (!igea__finite_vec(6, axis_ss, 1))
        return IGEA_ENONFINITE;
    for (int a = 0; a < 6; a++)
        if (axis_ss[a] < 0)
            return -1;
    for (int a = 0; a < 3; a++)
        rms[a] = axis_ss[3 + a] > 0 ? sqrt(axis_ss[a] / axis_ss[3 + a]) : 0.0;
    return 0;
}

/* ---- residual diagnostics per axis ------------------------------------------ */

/* u[j] += s[j], j < N, four at a time (vector registers where the
 * compiler has them: each u[j] is its own sum). */
static void axis_add_row(int N, const double *restrict s, double *restrict u)
{
    int j = 0;
    for (; j + 4 <= N; j += 4) {
        u[j] += s[j];
        u[j + 1] += s[j + 1];
        u[j + 2] += s[j + 2];
        u[j + 3] += s[j + 3];
    }
    for (; j < N; j++)
        u[j] += s[j];
}

void igea__axis_rows(int layout, int m, int N, const double *S, int lds, const double *dw,
                     int a, double *t)
{
    const size_t w = (size_t)N + 2;
    for (int i = 0; i < m; i++) {
        double *u = t + (size_t)a * w;
        u[0] += 1.0;
        u[1] += dw[i];
        if (layout == IGEA_ROWMAJOR)
            axis_add_row(N, S + (size_t)i * lds, u + 2);
        else
            for (int j = 0; j < N; j++)
                u[2 + j] += IGEA_AT(S, lds, i, j);
        a = a == 2 ? 0 : a + 1;
    }
}

int igea__axis_status(int layout, int m, int N, const double *S, int lds, const double *t)
{
    if (igea__finite_vec(3 * (N + 2), t, 1))
        return 0;
    return (layout == IGEA_COLMAJOR ? igea__finite_mat(m, N, S, lds)
                                    : igea__finite_mat(N, m, S, lds))
               ? IGEA_EOVERFLOW
               : IGEA_ENONFINITE;
}

int igea_eqerr_axis_sums(int layout, int m, int N, const double *S, int lds,
                         const double *dw, int row0, double *sums)
{
    if (layout != IGEA_COLMAJOR && layout != IGEA_ROWMAJOR) return -1;
    if (m < 0) return -2;
    if (N < 1) return -3;
    if (!S && m > 0) return -4;
    if (lds < IGEA_MAX(1, layout == IGEA_COLMAJOR ? m : N)) return -5;
    if (!dw && m > 0) return -6;
    if (row0 < 0) return -7;
    if (!sums) return -8;
    const size_t w = (size_t)N + 2;
    if (!igea__finite_vec(3 * (int)w, sums, 1) || !igea__finite_vec(m, dw, 1))
        return IGEA_ENONFINITE;
    for (int a = 0; a < 3; a++)
        if (!(sums[a * w] >= 0))
            return -8;
    double *t = igea__dalloc(3 * w);
    if (!t)
        return IGEA_ENOMEM;
    memcpy(t, sums, 3 * w * sizeof(double));
    /* Each sum adds its rows in row order (the same bits however the loop
     * is arranged); a NaN or Inf in S makes its sum non-finite, which is
     * told apart from an overflow of finite data by a scan on that path
     * only. */
    igea__axis_rows(layout, m, N, S, lds, dw, (int)((long long)row0 % 3), t);
    int st = igea__axis_status(layout, m, N, S, lds, t);
    if (st == 0)
        memcpy(sums, t, 3 * w * sizeof(double));
    free(t);
    return st;
}

int igea_eqerr_accumulate(int layout, int m, int N, const double *S, int lds,
                          const double *dw, const double *track_sigma, int sigma_inc,
                          const double *spec_sigma, double *A, int lda, double *b,
                          double *wtw, int nthreads, int row0, double *sums)
{
    int st = igea__normal_check_threads(layout, m, N, S, lds, dw, track_sigma, sigma_inc,
                                        spec_sigma, A, lda, b, wtw, nthreads);
    if (st)
        return st;
    if (row0 < 0) return -15;
    if (!sums) return -16;
    const size_t w = (size_t)N + 2;
    if (!igea__finite_vec(3 * (int)w, sums, 1))
        return IGEA_ENONFINITE;
    for (int a = 0; a < 3; a++)
        if (!(sums[a * w] >= 0))
            return -16;
    if (m == 0)
        return 0;
    return igea__normal_accumulate_sums(layout, m, N, S, lds, dw, track_sigma, sigma_inc,
                                        spec_sigma, A, lda, b, wtw, nthreads, row0, sums);
}

int igea_eqerr_residual_mean(int N, const double *sums, const double *coef, double *mean)
{
    if (N < 1) return -1;
    if (!sums) return -2;
    if (!coef) return -3;
    if (!mean) return -4;
    const size_t w = (size_t)N + 2;
    if (!igea__finite_vec(3 * (int)w, sums, 1) || !igea__finite_vec(N, coef, 1))
        return IGEA_ENONFINITE;
    double mu[3];
    for (int a = 0; a < 3; a++) {
        const double *u = sums + a * w;
        if (!(u[0] >= 0))
            return -2;
        igea__ksum acc = {0, 0};
        igea__ksum_add(&acc, u[1]);
        for (int j = 0; j < N; j++)
            igea__ksum_add(&acc, -u[2 + j] * coef[j]);
        mu[a] = u[0] > 0 ? igea__ksum_get(&acc) / u[0] : 0.0;
        if (!isfinite(mu[a]))
            return IGEA_EOVERFLOW;
    }
    memcpy(mean, mu, sizeof mu);
    return 0;
}

int igea_eqerr_diag_add(int m, const double *residual, int row0, double *state)
{
    if (m < 0) return -1;
    if (!residual && m > 0) return -2;
    if (row0 < 0) return -3;
    if (!state) return -4;
    double t[3 * IGEA_STATS_DIAG_STATE_LEN];
    memcpy(t, state, sizeof t);
    for (int a = 0; a < 3; a++) {
        int off = (int)((3 - (long long)row0 % 3 + a) % 3);
        int cnt = m > off ? (m - off + 2) / 3 : 0;
        int st = igea_stats_diag_add(cnt, cnt ? residual + off : residual, 3,
                                     t + a * IGEA_STATS_DIAG_STATE_LEN);
        if (st)
            return st == -4 ? -4 : st < 0 && st > -1000 ? IGEA_EDOMAIN : st;
    }
    memcpy(state, t, sizeof t);
    return 0;
}

int igea_eqerr_diag(int m, const double *residual, int lags, double *out, int *axis_status)
{
    if (m < 1) return -1;
    if (!residual) return -2;
    if (lags < 1 || lags > IGEA_STATS_DIAG_LAGS_MAX) return -3;
    if (!out) return -4;
    if (!axis_status) return -5;
    double t[3 * IGEA_STATS_DIAG_LEN];
    int ast[3];
    memset(t, 0, sizeof t);
    for (int a = 0; a < 3; a++) {
        int cnt = m > a ? (m - a + 2) / 3 : 0;
        int st = cnt ? igea_stats_whiteness(cnt, residual + a, 3, lags,
                                            t + a * IGEA_STATS_DIAG_LEN)
                     : IGEA_EEMPTY;
        if (st == IGEA_EEMPTY || st == IGEA_EDOMAIN) {
            ast[a] = st;
            t[a * IGEA_STATS_DIAG_LEN + IGEA_STATS_DIAG_N] = cnt;
        } else if (st) {
            return st < 0 && st > -1000 ? IGEA_EDOMAIN : st;
        } else {
            ast[a] = 0;
        }
    }
    memcpy(out, t, sizeof t);
    memcpy(axis_status, ast, sizeof ast);
    return 0;
}

/* ---- named components -------------------------------------------------------- */

int igea_eqerr_components(int N, const double *P, int ldp, int ncomp,
                          const double *spec_sigma, double *share, double *loading,
                          int *order)
{
    if (N < 1) return -1;
    if (!P) return -2;
    if (ldp < N) return -3;
    if (ncomp < 0 || ncomp > N) return -4;
    if (!share) return -6;
    if (!igea__finite_mat(N, ncomp, P, ldp))
        return IGEA_ENONFINITE;
    if (spec_sigma) {
        int st = igea__sigma_vec(N, spec_sigma);
        if (st)
            return st;
    }
    for (int i = 0; i < ncomp; i++)
        for (int j = 0; j < N; j++)
            if (!isfinite(IGEA_AT(P, ldp, j, i) * (spec_sigma ? spec_sigma[j] : 1.0)))
                return IGEA_EOVERFLOW;
    for (int i = 0; i < ncomp; i++) {
        double *sh = share + (size_t)i * N;
        for (int j = 0; j < N; j++) {
            double p = IGEA_AT(P, ldp, j, i);
            sh[j] = p * p;
            if (loading)
                loading[j + (size_t)i * N] = p * (spec_sigma ? spec_sigma[j] : 1.0);
        }
        if (!order)
            continue;
        int *o = order + (size_t)i * N;
        for (int j = 0; j < N; j++) { /* insertion sort: descending share, then index */
            int k = j;
            while (k > 0 && sh[o[k - 1]] < sh[j])
                o[k] = o[k - 1], k--;
            o[k] = j;
        }
    }
    return 0;
}

int igea__eqerr_solve_projected(int N, const double *lam0, const double *pre, int want_p,
                                const double *pb, const double *opts, double *vcache,
                                double *work, double *z, int *reject, double *info)
{
    double *g0 = work, *xhat = g0 + N, *lambda = xhat + N;
    double tol = opts[IGEA_EQERR_OPT_RANK_TOL] > 0 ? opts[IGEA_EQERR_OPT_RANK_TOL]
                                                    : N * 10.0 * DBL_EPSILON;
    int r = igea__rank_cut(N, lam0, tol);
    if (!igea__finite_vec(N, pb, 1))
        return IGEA_ENONFINITE;
    for (int i = 0; i < N; i++) {
        xhat[i] = i < r ? pb[i] / lam0[i] : 0.0;
        g0[i] = i < r ? pb[i] / (pre ? pre[i] : sqrt(lam0[i])) : 0.0;
    }
    int st = sigmaw_and_test(N, r, lam0, g0, xhat, opts, vcache, vcache + 4 * (size_t)N,
                             pre ? pre + N : NULL, want_p, lambda, z, reject, info);
    if (st == 0 && !(igea__finite_vec(N, lambda, 1) && igea__finite_vec(N, xhat, 1) &&
                     igea__finite_vec(N, z, 1) &&
                     igea__finite_vec(IGEA_STATS_INFO_LEN, info, 1)))
        st = IGEA_EOVERFLOW;
    return st;
}
