/* Tests of igea/eqerr.h. References: METHODS 1.6(a) (computed there with an
 * independent numpy/scipy implementation), the sigma_w pseudo-code of
 * METHODS 1.2 step 3 worked by hand on diagonal normal equations, closed
 * forms. */
#include "testutil.h"

#include "igea.h"
#include "internal.h"

/* ---- METHODS 1.6(a) ---------------------------------------------------- */
enum { M6 = 12, N6 = 4 };
static double S6[M6 * N6], dw6[M6];
static const double X6[N6] = {0.5, -1, 0.8, 0.3};

static void make6(void)
{
    for (int k = 0; k < 4; k++) {
        double t = k + 1;
        double rows[3][4] = {{t, 0.5 * t * t, 0, 0.1 * t},
                             {0, 0.2 * t, t, 0.1 * t + 0.01 * t * t},
                             {0.3 * t, 0, 0.1 * t * t, 0.1 * t}};
        for (int a = 0; a < 3; a++)
            for (int j = 0; j < 4; j++)
                S6[3 * k + a + j * M6] = rows[a][j];
    }
    for (int i = 0; i < M6; i++) {
        dw6[i] = 0.05 * cos(1.7 * i);
        for (int j = 0; j < N6; j++)
            dw6[i] += S6[i + j * M6] * X6[j];
    }
}

static const double lam6[4] = {4.7892162965e+04, 1.3446929088e+04, 1.4862431452e+03, 4.8248022104e+00};
static const double xh6[4] = {-0.5306467356, 0.8807047625, 0.9903378107, -0.5506797041};
static const double P6[4][4] = {{0.499739, -0.054682, 0.852116, -0.145496},
                                {0.860168, -0.070587, -0.504380, 0.027003},
                                {0.080865, 0.987116, -0.007619, -0.137861},
                                {0.061911, 0.132779, 0.139430, 0.979335}};
static const double z6[3] = {-0.5306412, 0.88067202, 0.99000481};
static const double ls6[4] = {0.6106609553, -1.0329878838, 0.8948191166, -0.3171307789};

static void check6(const double *lam, const double *P, int ldp, const double *xh,
                   const double *z, const int *rej, const double *info)
{
    for (int i = 0; i < 4; i++) {
        assert_close(lam[i], lam6[i], 1e-10);
        assert_close(xh[i], xh6[i], 1e-9);
        for (int j = 0; j < 4; j++)
            assert_close_abs(P[i + j * ldp], P6[i][j], 0, 0.6e-6);
    }
    for (int i = 0; i < 3; i++) {
        assert_close(z[i], z6[i], 1e-7);
        assert_int_equal(rej[i], 0);
    }
    assert_int_equal(rej[3], -1);
    assert_close(info[IGEA_STATS_INFO_CHI2], 2.0372728049, 1e-10);
    assert_int_equal((int)info[IGEA_STATS_INFO_N_TEST], 3);
    assert_int_equal((int)info[IGEA_STATS_INFO_RANK], 4);
    assert_true(info[IGEA_STATS_INFO_SCALE] == 1.0);
    assert_int_equal((int)info[IGEA_STATS_INFO_FLAG], IGEA_STATS_SIGMAW_OFF);
    /* P Xhat is the least-squares solution */
    for (int i = 0; i < 4; i++) {
        double x = 0;
        for (int k = 0; k < 4; k++)
            x += P[i + k * ldp] * xh[k];
        assert_close(x, ls6[i], 1e-9);
    }
}

static void test_methods_vector_both_routes(void **state)
{
    make6();
    double opts[IGEA_EQERR_OPT_LEN], lam[4], P[6 * 4], xh[4], z[4], info[IGEA_STATS_INFO_LEN],
        res[M6], rms[3], sig = 0.05;
    int rej[4];
    igea_eqerr_defaults(opts);
    opts[IGEA_EQERR_OPT_CORRECTION] = 0;
    fill_nan(P, 24);
    assert_int_equal(igea_eqerr_run(M6, N6, S6, M6, dw6, &sig, 0, NULL, opts, lam, P, 6, xh, z,
                                    rej, info, res, rms), 0);
    check6(lam, P, 6, xh, z, rej, info);
    /* residual = dw - S P_t Xhat_t (3 tested components) */
    double coef[4];
    assert_int_equal(igea_eqerr_coef(4, P, 6, xh, 3, NULL, coef), 0);
    for (int i = 0; i < 4; i++) {
        double c = 0;
        for (int k = 0; k < 3; k++)
            c += P[i + k * 6] * xh[k];
        assert_close(coef[i], c, 1e-15);
    }
    double ss[3] = {0, 0, 0};
    for (int i = 0; i < M6; i++) {
        double e = dw6[i];
        for (int j = 0; j < 4; j++)
            e -= S6[i + j * M6] * coef[j];
        assert_close_abs(res[i], e, 1e-12, 1e-15);
        ss[i % 3] += e * e;
    }
    for (int a = 0; a < 3; a++)
        assert_close(rms[a], sqrt(ss[a] / 4), 1e-12);

    opts[IGEA_EQERR_OPT_ROUTE] = IGEA_EQERR_ROUTE_SVD;
    fill_nan(P, 24);
    assert_int_equal(igea_eqerr_run(M6, N6, S6, M6, dw6, &sig, 0, NULL, opts, lam, P, 6, xh, z,
                                    rej, info, NULL, NULL), 0);
    check6(lam, P, 6, xh, z, rej, info);
}

/* Streamed: normal equations in blocks + solve equal the one-call run. */
static void test_streamed_equals_run(void **state)
{
    make6();
    double A[16] = {0}, b[4] = {0}, w[2] = {0, 0}, sig[M6], spec[4] = {1, 2, 0.5, 3};
    for (int i = 0; i < M6; i++)
        sig[i] = 0.05 * (1 + 0.1 * i);
    for (int r0 = 0; r0 < M6; r0 += 5) {
        int nr = r0 + 5 <= M6 ? 5 : M6 - r0;
        double blk[5 * 4];
        for (int i = 0; i < nr; i++)
            for (int j = 0; j < 4; j++)
                blk[i + j * nr] = S6[r0 + i + j * M6];
        assert_int_equal(igea_normal_accumulate(IGEA_COLMAJOR, nr, 4, blk, nr, dw6 + r0, sig + r0,
                                                1, spec, A, 4, b, w), 0);
    }
    double lam[4], P[16], xh[4], z[4], info[IGEA_STATS_INFO_LEN], lam2[4], P2[16], xh2[4], z2[4],
        info2[IGEA_STATS_INFO_LEN];
    int rej[4], rej2[4];
    assert_int_equal(igea_eqerr_solve(4, A, 4, b, NULL, lam, P, 4, xh, z, rej, info), 0);
    assert_int_equal(igea_eqerr_run(M6, 4, S6, M6, dw6, sig, 1, spec, NULL, lam2, P2, 4, xh2, z2,
                                    rej2, info2, NULL, NULL), 0);
    for (int i = 0; i < 4; i++) {
        assert_close(lam[i], lam2[i], 1e-12);
        assert_close(xh[i], xh2[i], 1e-10);
    }
    assert_close(info[IGEA_STATS_INFO_CHI2], info2[IGEA_STATS_INFO_CHI2], 1e-10);
}

/* ---- sigma_w iteration on diagonal normal equations ------------------------
 * A = diag(lam0), b_i = g_i sqrt(lam0_i): then P = I and g0_i = g_i. */
enum { ND = 10 };
static void diag_problem(const double *lam0, const double *g, double *A, double *b)
{
    memset(A, 0, sizeof(double) * ND * ND);
    for (int i = 0; i < ND; i++) {
        A[i + i * ND] = lam0[i];
        b[i] = g[i] * sqrt(lam0[i]);
    }
}

static void test_sigmaw_iteration(void **state)
{
    double A[ND * ND], b[ND], lam[ND], P[ND * ND], xh[ND], z[ND], info[IGEA_STATS_INFO_LEN];
    int rej[ND];
    /* Worked by hand (METHODS 1.2 step 3): it0: small set = 5 eigenvalues
     * <= 0.1 with g^2 = 4 -> sw2 = 4, c = 4. it1: 0.3/4 = 0.075 joins: sw2 =
     * (1 + 20)/4/6 = 0.875, c = 3.5. it2: sw2 = 21/3.5/6 = 1, same set ->
     * converged: 3 iterations, c = 3.5, 6 small. */
    const double lam0[ND] = {1e4, 1e3, 500, 100, 0.3, 0.05, 0.04, 0.03, 0.02, 0.01};
    const double g[ND] = {1, -1, 0.5, 0.2, 1, 2, -2, 2, -2, 2};
    diag_problem(lam0, g, A, b);
    assert_int_equal(igea_eqerr_solve(ND, A, ND, b, NULL, lam, P, ND, xh, z, rej, info), 0);
    assert_close(info[IGEA_STATS_INFO_SCALE], 3.5, 1e-14);
    assert_int_equal((int)info[IGEA_STATS_INFO_ITERATIONS], 3);
    assert_int_equal((int)info[IGEA_STATS_INFO_N_SMALL], 6);
    assert_int_equal((int)info[IGEA_STATS_INFO_FLAG], IGEA_STATS_SIGMAW_CONVERGED);
    for (int i = 0; i < ND; i++) {
        assert_close(lam[i], lam0[i] / 3.5, 1e-14);
        assert_close(xh[i], g[i] / sqrt(lam0[i]), 1e-14); /* unchanged by c */
    }
    /* tested: lambda >= 10 after scaling: 1e4, 1e3, 500, 100 -> 4 */
    assert_int_equal((int)info[IGEA_STATS_INFO_N_TEST], 4);
    double T = 0;
    for (int i = 0; i < 4; i++) {
        double zi = xh[i] / sqrt(1 + 3.5 / lam0[i]);
        assert_close(z[i], zi, 1e-14);
        T += zi * zi;
    }
    assert_close(info[IGEA_STATS_INFO_CHI2], T, 1e-14);

    double opts[IGEA_EQERR_OPT_LEN];
    /* one iteration only: no convergence, c kept at 4 */
    igea_eqerr_defaults(opts);
    opts[IGEA_EQERR_OPT_MAX_ITER] = 1;
    assert_int_equal(igea_eqerr_solve(ND, A, ND, b, opts, lam, P, ND, xh, z, rej, info), 0);
    assert_int_equal((int)info[IGEA_STATS_INFO_FLAG], IGEA_STATS_SIGMAW_NO_CONVERGENCE);
    assert_close(info[IGEA_STATS_INFO_SCALE], 4.0, 1e-14);
    /* n_min = 6: only 5 small eigenvalues at c = 1 -> not estimable, c = 1 */
    igea_eqerr_defaults(opts);
    opts[IGEA_EQERR_OPT_N_MIN] = 6;
    assert_int_equal(igea_eqerr_solve(ND, A, ND, b, opts, lam, P, ND, xh, z, rej, info), 0);
    assert_int_equal((int)info[IGEA_STATS_INFO_FLAG], IGEA_STATS_SIGMAW_NOT_ESTIMABLE);
    assert_true(info[IGEA_STATS_INFO_SCALE] == 1.0);
    assert_int_equal((int)info[IGEA_STATS_INFO_N_SMALL], 5);
    /* bias correction: sw2 = mean(g^2 - lambda) = 4 - 0.03 at it0 */
    igea_eqerr_defaults(opts);
    opts[IGEA_EQERR_OPT_BIAS_CORRECT] = 1;
    opts[IGEA_EQERR_OPT_MAX_ITER] = 1;
    assert_int_equal(igea_eqerr_solve(ND, A, ND, b, opts, lam, P, ND, xh, z, rej, info), 0);
    assert_close(info[IGEA_STATS_INFO_SCALE], 4.0 - 0.03, 1e-14);
    /* off */
    igea_eqerr_defaults(opts);
    opts[IGEA_EQERR_OPT_CORRECTION] = 0;
    assert_int_equal(igea_eqerr_solve(ND, A, ND, b, opts, lam, P, ND, xh, z, rej, info), 0);
    assert_int_equal((int)info[IGEA_STATS_INFO_FLAG], IGEA_STATS_SIGMAW_OFF);
    assert_int_equal((int)info[IGEA_STATS_INFO_ITERATIONS], 0);
}

static void test_sigmaw_clamp_and_converged_first(void **state)
{
    double A[ND * ND], b[ND], lam[ND], P[ND * ND], xh[ND], z[ND], info[IGEA_STATS_INFO_LEN], opts[IGEA_EQERR_OPT_LEN];
    int rej[ND];
    const double lam0[ND] = {1e4, 1e3, 500, 100, 0.3, 0.05, 0.04, 0.03, 0.02, 0.01};
    double g[ND] = {1, -1, 0.5, 0.2, 1, 0.5, -0.5, 0.5, -0.5, 0.5}; /* sw2 = 0.25 */
    diag_problem(lam0, g, A, b);
    igea_eqerr_defaults(opts);
    opts[IGEA_EQERR_OPT_CLAMP] = 1;
    assert_int_equal(igea_eqerr_solve(ND, A, ND, b, opts, lam, P, ND, xh, z, rej, info), 0);
    assert_true(info[IGEA_STATS_INFO_SCALE] == 1.0);
    assert_int_equal((int)info[IGEA_STATS_INFO_FLAG], IGEA_STATS_SIGMAW_CONVERGED);
    /* without the clamp c goes below 1: 0.25, then 0.3/0.25 = 1.2 leaves
     * the small set unchanged... at c = 0.25 only lam0 <= 0.025 are small
     * (2 < n_min): not estimable, c stays 0.25 */
    opts[IGEA_EQERR_OPT_CLAMP] = 0;
    assert_int_equal(igea_eqerr_solve(ND, A, ND, b, opts, lam, P, ND, xh, z, rej, info), 0);
    assert_close(info[IGEA_STATS_INFO_SCALE], 0.25, 1e-14);
    assert_int_equal((int)info[IGEA_STATS_INFO_FLAG], IGEA_STATS_SIGMAW_NOT_ESTIMABLE);
    assert_int_equal((int)info[IGEA_STATS_INFO_ITERATIONS], 2);
    /* sw2 within tol at the first iteration: converged at once, c = 1 */
    for (int i = 5; i < ND; i++)
        g[i] = (i % 2 ? 1.02 : -1.02);
    diag_problem(lam0, g, A, b);
    assert_int_equal(igea_eqerr_solve(ND, A, ND, b, NULL, lam, P, ND, xh, z, rej, info), 0);
    assert_true(info[IGEA_STATS_INFO_SCALE] == 1.0);
    assert_int_equal((int)info[IGEA_STATS_INFO_ITERATIONS], 1);
    assert_int_equal((int)info[IGEA_STATS_INFO_FLAG], IGEA_STATS_SIGMAW_CONVERGED);
}

/* Rank deficiency: a zero eigenvalue is neither estimated nor tested. */
static void test_rank_deficient(void **state)
{
    /* S with column 3 = column 1 + column 2 */
    enum { MR = 9, NR = 3 };
    double S[MR * NR], d[MR], sig = 1.0, lam[NR], P[NR * NR], xh[NR], z[NR], info[IGEA_STATS_INFO_LEN];
    int rej[NR];
    for (int i = 0; i < MR; i++) {
        S[i] = 10 * (i + 1);
        S[i + MR] = 10 * (i + 1) * (i + 1) * 0.1;
        S[i + 2 * MR] = S[i] + S[i + MR];
        d[i] = 0.3 * S[i] - 0.1 * S[i + MR] + 0.01 * cos(i);
    }
    double opts[IGEA_EQERR_OPT_LEN];
    igea_eqerr_defaults(opts);
    opts[IGEA_EQERR_OPT_CORRECTION] = 0;
    for (int route = 0; route < 2; route++) {
        opts[IGEA_EQERR_OPT_ROUTE] = route;
        assert_int_equal(igea_eqerr_run(MR, NR, S, MR, d, &sig, 0, NULL, opts, lam, P, NR, xh, z,
                                        rej, info, NULL, NULL), 0);
        assert_int_equal((int)info[IGEA_STATS_INFO_RANK], 2);
        assert_true(xh[2] == 0.0);
        assert_int_equal(rej[2], -1);
        assert_true(fabs(lam[2]) < 1e-9 * lam[0]);
        /* the null vector is (1, 1, -1)/sqrt 3 up to sign */
        assert_close(fabs(P[0 + 2 * NR]), 1 / sqrt(3.0), 1e-6);
    }
}

static void test_not_testable_and_invalid(void **state)
{
    make6();
    double A[16] = {0}, b[4] = {0}, w[2] = {0, 0}, sig = 100.0; /* imprecise: lambda < 10 */
    assert_int_equal(igea_normal_accumulate(IGEA_COLMAJOR, M6, 4, S6, M6, dw6, &sig, 0, NULL, A, 4, b, w), 0);
    double lam[4], P[16], xh[4], z[4], info[IGEA_STATS_INFO_LEN], opts[IGEA_EQERR_OPT_LEN];
    int rej[4];
    fill_sentinel(lam, 4);
    fill_sentinel(P, 16);
    fill_sentinel(info, IGEA_STATS_INFO_LEN);
    assert_int_equal(igea_eqerr_solve(4, A, 4, b, NULL, lam, P, 4, xh, z, rej, info), IGEA_ENOTESTABLE);
    assert_int_equal(igea_eqerr_solve(0, A, 4, b, NULL, lam, P, 4, xh, z, rej, info), -1);
    assert_int_equal(igea_eqerr_solve(4, NULL, 4, b, NULL, lam, P, 4, xh, z, rej, info), -2);
    assert_int_equal(igea_eqerr_solve(4, A, 3, b, NULL, lam, P, 4, xh, z, rej, info), -3);
    assert_int_equal(igea_eqerr_solve(4, A, 4, NULL, NULL, lam, P, 4, xh, z, rej, info), -4);
    igea_eqerr_defaults(opts);
    for (int k = 0; k < 12; k++) {
        double keep = opts[k];
        opts[k] = k == IGEA_EQERR_OPT_RANK_TOL ? 2.0 : (k == IGEA_EQERR_OPT_ROUTE ? 7 : -1.0);
        assert_int_equal(igea_eqerr_solve(4, A, 4, b, opts, lam, P, 4, xh, z, rej, info), -5);
        opts[k] = keep;
    }
    opts[3] = NAN;
    assert_int_equal(igea_eqerr_solve(4, A, 4, b, opts, lam, P, 4, xh, z, rej, info), -5);
    assert_int_equal(igea_eqerr_defaults(NULL), -1);
    assert_int_equal(igea_eqerr_solve(4, A, 4, b, NULL, NULL, P, 4, xh, z, rej, info), -6);
    assert_int_equal(igea_eqerr_solve(4, A, 4, b, NULL, lam, NULL, 4, xh, z, rej, info), -7);
    assert_int_equal(igea_eqerr_solve(4, A, 4, b, NULL, lam, P, 3, xh, z, rej, info), -8);
    assert_int_equal(igea_eqerr_solve(4, A, 4, b, NULL, lam, P, 4, NULL, z, rej, info), -9);
    assert_int_equal(igea_eqerr_solve(4, A, 4, b, NULL, lam, P, 4, xh, NULL, rej, info), -10);
    assert_int_equal(igea_eqerr_solve(4, A, 4, b, NULL, lam, P, 4, xh, z, NULL, info), -11);
    assert_int_equal(igea_eqerr_solve(4, A, 4, b, NULL, lam, P, 4, xh, z, rej, NULL), -12);
    A[5] = NAN;
    assert_int_equal(igea_eqerr_solve(4, A, 4, b, NULL, lam, P, 4, xh, z, rej, info), IGEA_ENONFINITE);
    assert_true(all_sentinel(lam, 4) && all_sentinel(P, 16) && all_sentinel(info, IGEA_STATS_INFO_LEN));

    /* igea_eqerr_run */
    double s1 = 0.05, spec[4] = {1, 1, 1, 1}, res[M6], rms[3];
#define RUN(m, n, S, lds, d, g, gi, sp, o, L, PP, ldp, X, Z, R, I) \
    igea_eqerr_run(m, n, S, lds, d, g, gi, sp, o, L, PP, ldp, X, Z, R, I, res, rms)
    assert_int_equal(RUN(0, 4, S6, M6, dw6, &s1, 0, NULL, NULL, lam, P, 4, xh, z, rej, info), -1);
    assert_int_equal(RUN(M6, 0, S6, M6, dw6, &s1, 0, NULL, NULL, lam, P, 4, xh, z, rej, info), -2);
    assert_int_equal(RUN(M6, 4, NULL, M6, dw6, &s1, 0, NULL, NULL, lam, P, 4, xh, z, rej, info), -3);
    assert_int_equal(RUN(M6, 4, S6, M6 - 1, dw6, &s1, 0, NULL, NULL, lam, P, 4, xh, z, rej, info), -4);
    assert_int_equal(RUN(M6, 4, S6, M6, NULL, &s1, 0, NULL, NULL, lam, P, 4, xh, z, rej, info), -5);
    assert_int_equal(RUN(M6, 4, S6, M6, dw6, NULL, 0, NULL, NULL, lam, P, 4, xh, z, rej, info), -6);
    assert_int_equal(RUN(M6, 4, S6, M6, dw6, &s1, 3, NULL, NULL, lam, P, 4, xh, z, rej, info), -7);
    opts[3] = 0;
    assert_int_equal(RUN(M6, 4, S6, M6, dw6, &s1, 0, NULL, opts, lam, P, 4, xh, z, rej, info), -9);
    assert_int_equal(RUN(M6, 4, S6, M6, dw6, &s1, 0, NULL, NULL, NULL, P, 4, xh, z, rej, info), -10);
    assert_int_equal(RUN(M6, 4, S6, M6, dw6, &s1, 0, NULL, NULL, lam, NULL, 4, xh, z, rej, info), -11);
    assert_int_equal(RUN(M6, 4, S6, M6, dw6, &s1, 0, NULL, NULL, lam, P, 3, xh, z, rej, info), -12);
    assert_int_equal(RUN(M6, 4, S6, M6, dw6, &s1, 0, NULL, NULL, lam, P, 4, NULL, z, rej, info), -13);
    assert_int_equal(RUN(M6, 4, S6, M6, dw6, &s1, 0, NULL, NULL, lam, P, 4, xh, NULL, rej, info), -14);
    assert_int_equal(RUN(M6, 4, S6, M6, dw6, &s1, 0, NULL, NULL, lam, P, 4, xh, z, NULL, info), -15);
    assert_int_equal(RUN(M6, 4, S6, M6, dw6, &s1, 0, NULL, NULL, lam, P, 4, xh, z, rej, NULL), -16);
    s1 = 0.0;
    assert_int_equal(RUN(M6, 4, S6, M6, dw6, &s1, 0, NULL, NULL, lam, P, 4, xh, z, rej, info), IGEA_ENONPOSITIVE);
    s1 = NAN;
    assert_int_equal(RUN(M6, 4, S6, M6, dw6, &s1, 0, NULL, NULL, lam, P, 4, xh, z, rej, info), IGEA_ENONFINITE);
    s1 = 0.05;
    spec[1] = -2;
    assert_int_equal(RUN(M6, 4, S6, M6, dw6, &s1, 0, spec, NULL, lam, P, 4, xh, z, rej, info), IGEA_ENONPOSITIVE);
    for (int route = 0; route < 2; route++) {
        igea_eqerr_defaults(opts);
        opts[IGEA_EQERR_OPT_ROUTE] = route;
        S6[7 + 2 * M6] = INFINITY;
        assert_int_equal(RUN(M6, 4, S6, M6, dw6, &s1, 0, NULL, opts, lam, P, 4, xh, z, rej, info), IGEA_ENONFINITE);
        make6();
        dw6[11] = NAN;
        assert_int_equal(RUN(M6, 4, S6, M6, dw6, &s1, 0, NULL, opts, lam, P, 4, xh, z, rej, info), IGEA_ENONFINITE);
        make6();
    }
    assert_true(all_sentinel(lam, 4) && all_sentinel(P, 16) && all_sentinel(info, IGEA_STATS_INFO_LEN));
#undef RUN
}

static void test_padding_and_residual_args(void **state)
{
    make6();
    enum { LDS = M6 + 5 };
    double Sp[LDS * 4], lam[4], P[16], xh[4], z[4], info[IGEA_STATS_INFO_LEN], s1 = 0.05, opts[IGEA_EQERR_OPT_LEN];
    int rej[4];
    fill_nan(Sp, LDS * 4);
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < M6; i++)
            Sp[i + j * LDS] = S6[i + j * M6];
    igea_eqerr_defaults(opts);
    opts[IGEA_EQERR_OPT_CORRECTION] = 0;
    for (int route = 0; route < 2; route++) {
        opts[IGEA_EQERR_OPT_ROUTE] = route;
        assert_int_equal(igea_eqerr_run(M6, 4, Sp, LDS, dw6, &s1, 0, NULL, opts, lam, P, 4, xh, z,
                                        rej, info, NULL, NULL), 0);
        check6(lam, P, 4, xh, z, rej, info);
    }
    double coef[4] = {0.1, 0.2, 0.3, 0.4}, e[M6], ss[6] = {0};
    assert_int_equal(igea_eqerr_residual(IGEA_COLMAJOR, M6, 4, Sp, LDS, dw6, coef, 1, e, ss), 0);
    for (int i = 0; i < M6; i++) {
        double r = dw6[i];
        for (int j = 0; j < 4; j++)
            r -= S6[i + j * M6] * coef[j];
        assert_close_abs(e[i], r, 1e-14, 1e-15);
    }
    /* row0 = 1: the first row of the block is a y row */
    assert_true(ss[3] == 4 && ss[4] == 4 && ss[5] == 4);
    assert_close(ss[1], e[0] * e[0] + e[3] * e[3] + e[6] * e[6] + e[9] * e[9], 1e-14);
    assert_int_equal(igea_eqerr_residual(5, M6, 4, Sp, LDS, dw6, coef, 0, e, ss), -1);
    assert_int_equal(igea_eqerr_residual(0, -1, 4, Sp, LDS, dw6, coef, 0, e, ss), -2);
    assert_int_equal(igea_eqerr_residual(0, M6, 0, Sp, LDS, dw6, coef, 0, e, ss), -3);
    assert_int_equal(igea_eqerr_residual(0, M6, 4, NULL, LDS, dw6, coef, 0, e, ss), -4);
    assert_int_equal(igea_eqerr_residual(0, M6, 4, Sp, M6 - 1, dw6, coef, 0, e, ss), -5);
    assert_int_equal(igea_eqerr_residual(0, M6, 4, Sp, LDS, NULL, coef, 0, e, ss), -6);
    assert_int_equal(igea_eqerr_residual(0, M6, 4, Sp, LDS, dw6, NULL, 0, e, ss), -7);
    assert_int_equal(igea_eqerr_residual(0, M6, 4, Sp, LDS, dw6, coef, -1, e, ss), -8);
    coef[0] = NAN;
    assert_int_equal(igea_eqerr_residual(0, M6, 4, Sp, LDS, dw6, coef, 0, e, ss), IGEA_ENONFINITE);
    coef[0] = 0.1;
    assert_int_equal(igea_eqerr_coef(0, P, 4, xh, 3, NULL, coef), -1);
    assert_int_equal(igea_eqerr_coef(4, NULL, 4, xh, 3, NULL, coef), -2);
    assert_int_equal(igea_eqerr_coef(4, P, 3, xh, 3, NULL, coef), -3);
    assert_int_equal(igea_eqerr_coef(4, P, 4, NULL, 3, NULL, coef), -4);
    assert_int_equal(igea_eqerr_coef(4, P, 4, xh, 5, NULL, coef), -5);
    assert_int_equal(igea_eqerr_coef(4, P, 4, xh, 3, NULL, NULL), -7);
    double spec[4] = {1, 0, 1, 1};
    assert_int_equal(igea_eqerr_coef(4, P, 4, xh, 3, spec, coef), IGEA_ENONPOSITIVE);
}

/* METHODS 1.2 step 1: the SVD route resolves eigenvalues down to about
 * eps^2 lambda_1, the normal-equation route to about eps lambda_1. S is
 * built as U diag(s) V' with known singular values 1 .. 1e-7 (eigenvalues
 * down to 1e-14 lambda_1); U has orthonormal columns (a cosine basis),
 * V a Householder reflection. */
static void test_svd_route_resolves_small_eigenvalues(void **state)
{
    enum { MS = 400, NS = 6 };
    const double sv[NS] = {1.0, 1e-1, 1e-2, 1e-4, 1e-6, 1e-7};
    double *S = malloc(sizeof(double) * MS * NS), U[MS * NS], V[NS * NS], d[MS], h[NS];
    assert_non_null(S);
    for (int j = 0; j < NS; j++) /* orthonormal cosine columns */
        for (int i = 0; i < MS; i++)
            U[i + j * MS] = sqrt((j ? 2.0 : 1.0) / MS) * cos(3.14159265358979323846 * j * (i + 0.5) / MS);
    double hn = 0;
    for (int j = 0; j < NS; j++) {
        h[j] = 1.0 + j;
        hn += h[j] * h[j];
    }
    for (int i = 0; i < NS; i++)
        for (int j = 0; j < NS; j++)
            V[i + j * NS] = (i == j) - 2.0 * h[i] * h[j] / hn;
    for (int i = 0; i < MS; i++) {
        for (int j = 0; j < NS; j++) {
            double a = 0;
            for (int k = 0; k < NS; k++)
                a += U[i + k * MS] * sv[k] * V[j + k * NS];
            S[i + j * MS] = a;
        }
        d[i] = 0.0;
    }
    double opts[IGEA_EQERR_OPT_LEN], lam[NS], P[NS * NS], xh[NS], z[NS], info[IGEA_STATS_INFO_LEN], one = 1.0;
    int rej[NS];
    igea_eqerr_defaults(opts);
    opts[IGEA_EQERR_OPT_CORRECTION] = 0;
    opts[IGEA_EQERR_OPT_LAMBDA_TEST] = 1e-20;
    opts[IGEA_EQERR_OPT_RANK_TOL] = 1e-30;
    double err[2] = {0, 0};
    for (int route = 0; route < 2; route++) {
        opts[IGEA_EQERR_OPT_ROUTE] = route;
        assert_int_equal(igea_eqerr_run(MS, NS, S, MS, d, &one, 0, NULL, opts, lam, P, NS, xh, z,
                                        rej, info, NULL, NULL), 0);
        for (int i = 0; i < NS; i++)
            err[route] = fmax(err[route], fabs(lam[i] - sv[i] * sv[i]) / (sv[i] * sv[i]));
    }
    /* eig: 1e-14 lambda_1 is at the eps lambda_1 noise floor (1.6e-3
     * relative measured); svd: 1.3e-11 measured for the smallest */
    assert_true(err[IGEA_EQERR_ROUTE_EIG] > 1e-4);
    assert_true(err[IGEA_EQERR_ROUTE_SVD] < 1e-9);
    free(S);
}

static void test_solve_qr_args(void **state)
{
    double R[25] = {0}, lam[4], P[16], xh[4], z[4], info[IGEA_STATS_INFO_LEN], opts[IGEA_EQERR_OPT_LEN];
    int rej[4];
    for (int i = 0; i < 5; i++)
        R[i + 5 * i] = 10.0 - i;
    fill_sentinel(lam, 4);
    fill_sentinel(info, IGEA_STATS_INFO_LEN);
    assert_int_equal(igea_eqerr_solve_qr(0, R, 5, 9, NULL, lam, P, 4, xh, z, rej, info), -1);
    assert_int_equal(igea_eqerr_solve_qr(4, NULL, 5, 9, NULL, lam, P, 4, xh, z, rej, info), -2);
    assert_int_equal(igea_eqerr_solve_qr(4, R, 4, 9, NULL, lam, P, 4, xh, z, rej, info), -3);
    assert_int_equal(igea_eqerr_solve_qr(4, R, 5, 0.5, NULL, lam, P, 4, xh, z, rej, info), -4);
    igea_eqerr_defaults(opts);
    opts[IGEA_EQERR_OPT_ALPHA] = 2;
    assert_int_equal(igea_eqerr_solve_qr(4, R, 5, 9, opts, lam, P, 4, xh, z, rej, info), -5);
    assert_int_equal(igea_eqerr_solve_qr(4, R, 5, 9, NULL, NULL, P, 4, xh, z, rej, info), -6);
    assert_int_equal(igea_eqerr_solve_qr(4, R, 5, 9, NULL, lam, NULL, 4, xh, z, rej, info), -7);
    assert_int_equal(igea_eqerr_solve_qr(4, R, 5, 9, NULL, lam, P, 3, xh, z, rej, info), -8);
    assert_int_equal(igea_eqerr_solve_qr(4, R, 5, 9, NULL, lam, P, 4, NULL, z, rej, info), -9);
    assert_int_equal(igea_eqerr_solve_qr(4, R, 5, 9, NULL, lam, P, 4, xh, NULL, rej, info), -10);
    assert_int_equal(igea_eqerr_solve_qr(4, R, 5, 9, NULL, lam, P, 4, xh, z, NULL, info), -11);
    assert_int_equal(igea_eqerr_solve_qr(4, R, 5, 9, NULL, lam, P, 4, xh, z, rej, NULL), -12);
    R[2 + 5 * 4] = NAN; /* the Q'w column */
    assert_int_equal(igea_eqerr_solve_qr(4, R, 5, 9, NULL, lam, P, 4, xh, z, rej, info), IGEA_ENONFINITE);
    R[2 + 5 * 4] = 0.0;
    R[3 + 5 * 1] = NAN; /* below the diagonal: not read */
    assert_true(all_sentinel(lam, 4) && all_sentinel(info, IGEA_STATS_INFO_LEN));
    /* diagonal R: lambda = diag^2, Xhat = (Q'w)_i / R_ii */
    R[0 + 5 * 4] = 3.0;
    R[1 + 5 * 4] = -2.0;
    opts[IGEA_EQERR_OPT_ALPHA] = 0.01;
    opts[IGEA_EQERR_OPT_CORRECTION] = 0;
    assert_int_equal(igea_eqerr_solve_qr(4, R, 5, 9, opts, lam, P, 4, xh, z, rej, info), 0);
    assert_close(lam[0], 100.0, 1e-15);
    assert_close(lam[3], 49.0, 1e-15);
    assert_close(xh[0], 0.3, 1e-15);
    assert_close(xh[1], -2.0 / 9.0, 1e-15);
    assert_true(xh[2] == 0.0 && xh[3] == 0.0);
}

/* ---- overflow and sigma range ------------------------------------------ */

static void run_sentinel(int m, const double *S, const double *dw,
                         const double *sig, int inc, const double *spec,
                         double route, int want)
{
    double o[IGEA_EQERR_OPT_LEN], lam[N6], P[N6 * N6], xh[N6], z[N6],
        info[IGEA_STATS_INFO_LEN], res[M6], rms[3];
    int rej[N6] = {-7, -7, -7, -7};
    igea_eqerr_defaults(o);
    o[IGEA_EQERR_OPT_CORRECTION] = 0;
    o[IGEA_EQERR_OPT_ROUTE] = route;
    fill_sentinel(lam, N6);
    fill_sentinel(P, N6 * N6);
    fill_sentinel(xh, N6);
    fill_sentinel(z, N6);
    fill_sentinel(info, IGEA_STATS_INFO_LEN);
    fill_sentinel(res, M6);
    fill_sentinel(rms, 3);
    assert_int_equal(igea_eqerr_run(m, N6, S, m, dw, sig, inc, spec, o, lam, P,
                                    N6, xh, z, rej, info, res, rms), want);
    assert_true(all_sentinel(lam, N6) && all_sentinel(P, N6 * N6) &&
                all_sentinel(xh, N6) && all_sentinel(z, N6) &&
                all_sentinel(info, IGEA_STATS_INFO_LEN) && all_sentinel(res, M6) &&
                all_sentinel(rms, 3));
    for (int i = 0; i < N6; i++)
        assert_int_equal(rej[i], -7);
}

static void test_overflow_is_not_nonfinite(void **state)
{
    (void)state;
    make6();
    /* S * 1e200, every value finite: the weighted normal matrix (~1e400)
     * overflows. That is IGEA_EOVERFLOW on both routes, not "an input
     * holds NaN or Inf". */
    double Sb[M6 * N6], sig[M6];
    for (int i = 0; i < M6 * N6; i++)
        Sb[i] = S6[i] * 1e200;
    for (int i = 0; i < M6; i++)
        sig[i] = 0.05;
    assert_true(igea__finite_mat(M6, N6, Sb, M6));
    run_sentinel(M6, Sb, dw6, sig, 1, NULL, IGEA_EQERR_ROUTE_EIG, IGEA_EOVERFLOW);
    run_sentinel(M6, Sb, dw6, sig, 0, NULL, IGEA_EQERR_ROUTE_EIG, IGEA_EOVERFLOW);
    run_sentinel(M6, Sb, dw6, sig, 1, NULL, IGEA_EQERR_ROUTE_SVD, IGEA_EOVERFLOW);
    /* A NaN is still a NaN. */
    Sb[5] = NAN;
    run_sentinel(M6, Sb, dw6, sig, 1, NULL, IGEA_EQERR_ROUTE_EIG, IGEA_ENONFINITE);
    run_sentinel(M6, Sb, dw6, sig, 0, NULL, IGEA_EQERR_ROUTE_EIG, IGEA_ENONFINITE);
    run_sentinel(M6, Sb, dw6, sig, 1, NULL, IGEA_EQERR_ROUTE_SVD, IGEA_ENONFINITE);
    /* Finite S, specs of 1e160: the scaled data overflow. */
    double spec[N6] = {1e160, 1e160, 1e160, 1e160};
    run_sentinel(M6, S6, dw6, sig, 1, spec, IGEA_EQERR_ROUTE_EIG, IGEA_EOVERFLOW);
    run_sentinel(M6, S6, dw6, sig, 1, spec, IGEA_EQERR_ROUTE_SVD, IGEA_EOVERFLOW);
}

static void test_sigma_range(void **state)
{
    (void)state;
    make6();
    double sig[M6];
    for (int i = 0; i < M6; i++)
        sig[i] = 0.05;
    /* A denormal tracking sigma: named as out of range, both routes, per
     * row and as the single value; also a denormal spec. */
    sig[4] = 5e-320;
    run_sentinel(M6, S6, dw6, sig, 1, NULL, IGEA_EQERR_ROUTE_EIG, IGEA_ERANGE);
    run_sentinel(M6, S6, dw6, sig, 1, NULL, IGEA_EQERR_ROUTE_SVD, IGEA_ERANGE);
    sig[0] = 1e-155;
    run_sentinel(M6, S6, dw6, sig, 0, NULL, IGEA_EQERR_ROUTE_EIG, IGEA_ERANGE);
    sig[0] = sig[4] = 0.05;
    double spec[N6] = {1, 1, 4e-320, 1};
    run_sentinel(M6, S6, dw6, sig, 1, spec, IGEA_EQERR_ROUTE_EIG, IGEA_ERANGE);
    /* NaN and non-positive keep their statuses. */
    sig[2] = -1;
    run_sentinel(M6, S6, dw6, sig, 1, NULL, IGEA_EQERR_ROUTE_EIG, IGEA_ENONPOSITIVE);
    sig[2] = NAN;
    run_sentinel(M6, S6, dw6, sig, 1, NULL, IGEA_EQERR_ROUTE_EIG, IGEA_ENONFINITE);
    double P[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    double xh[4] = {1, 2, 3, 4}, coef[4];
    fill_sentinel(coef, 4);
    assert_int_equal(igea_eqerr_coef(4, P, 4, xh, 4, spec, coef), IGEA_ERANGE);
    assert_true(all_sentinel(coef, 4));
}

/* igea_eqerr_check_opts: 0 for the defaults, 1 + the slot for each rule of
 * the header; igea_opt_name spells the slot as its macro does. */
static void test_check_opts_and_names(void **state)
{
    double o[IGEA_EQERR_OPT_LEN];
    assert_int_equal(igea_eqerr_check_opts(NULL), -1);
    assert_int_equal(igea_eqerr_defaults(o), 0);
    assert_int_equal(igea_eqerr_check_opts(o), 0);
    static const struct { int slot; double bad, good; const char *name; } rule[] = {
        {IGEA_EQERR_OPT_ALPHA, 1.0, 0.999, "alpha"},
        {IGEA_EQERR_OPT_LAMBDA_TEST, 0.0, 1e-300, "lambda_test"},
        {IGEA_EQERR_OPT_LAMBDA_SMALL, -1.0, 5.0, "lambda_small"},
        {IGEA_EQERR_OPT_N_MIN, 0.5, 1.0, "n_min"},
        {IGEA_EQERR_OPT_TOL, 0.0, 1.0, "tol"},
        {IGEA_EQERR_OPT_MAX_ITER, 1001.0, 1000.0, "max_iter"},
        {IGEA_EQERR_OPT_CORRECTION, 0.5, 0.0, "correction"},
        {IGEA_EQERR_OPT_RANK_TOL, 1.0, 0.5, "rank_tol"},
        {IGEA_EQERR_OPT_BIAS_CORRECT, 2.0, 1.0, "bias_correct"},
        {IGEA_EQERR_OPT_CLAMP, -1.0, 1.0, "clamp"},
        {IGEA_EQERR_OPT_Z_CRIT, -0.1, 2.58, "z_crit"},
        {IGEA_EQERR_OPT_ROUTE, 2.0, IGEA_EQERR_ROUTE_SVD, "route"},
    };
    for (size_t k = 0; k < sizeof rule / sizeof rule[0]; k++) {
        igea_eqerr_defaults(o);
        o[rule[k].slot] = rule[k].good;
        assert_int_equal(igea_eqerr_check_opts(o), 0);
        o[rule[k].slot] = rule[k].bad;
        assert_int_equal(igea_eqerr_check_opts(o), 1 + rule[k].slot);
        o[rule[k].slot] = NAN;
        assert_int_equal(igea_eqerr_check_opts(o), 1 + rule[k].slot);
        assert_string_equal(igea_opt_name(IGEA_MODULE_EQERR, rule[k].slot), rule[k].name);
    }
    /* the first invalid slot is reported; reserved slots must be finite */
    igea_eqerr_defaults(o);
    o[IGEA_EQERR_OPT_TOL] = -1;
    o[IGEA_EQERR_OPT_ALPHA] = 2;
    assert_int_equal(igea_eqerr_check_opts(o), 1 + IGEA_EQERR_OPT_ALPHA);
    igea_eqerr_defaults(o);
    o[IGEA_EQERR_OPT_LEN - 1] = INFINITY;
    assert_int_equal(igea_eqerr_check_opts(o), IGEA_EQERR_OPT_LEN);
    assert_string_equal(igea_opt_name(IGEA_MODULE_EQERR, IGEA_EQERR_OPT_LEN - 1), "reserved");
    /* the solvers refuse what the check refuses, as their opts argument */
    double A[4] = {100, 0, 0, 50}, b[2] = {1, 2}, lam[2], P[4], xh[2], z[2], info[IGEA_STATS_INFO_LEN];
    int rej[2];
    igea_eqerr_defaults(o);
    o[IGEA_EQERR_OPT_CLAMP] = 3;
    assert_int_equal(igea_eqerr_solve(2, A, 2, b, o, lam, P, 2, xh, z, rej, info), -5);
    /* simulation slots and unknown ones */
    static const char *const simn[] = {"sigma_w", "ar1", "growth", "outlier_prob",
                                       "outlier_scale", "generator"};
    assert_int_equal(IGEA_SIM_OPT_SIGMA_W, 0);
    assert_int_equal(IGEA_SIM_OPT_GENERATOR, 5);
    for (int k = 0; k < 6; k++)
        assert_string_equal(igea_opt_name(IGEA_MODULE_SIM, k), simn[k]);
    assert_string_equal(igea_opt_name(IGEA_MODULE_SIM, IGEA_SIM_OPT_LEN - 1), "reserved");
    assert_string_equal(igea_opt_name(IGEA_MODULE_SIM, IGEA_SIM_OPT_LEN), "");
    assert_string_equal(igea_opt_name(IGEA_MODULE_EQERR, IGEA_EQERR_OPT_LEN), "");
    assert_string_equal(igea_opt_name(IGEA_MODULE_EQERR, -1), "");
    assert_string_equal(igea_opt_name(0, 0), "");
    assert_string_equal(igea_opt_name(3, 0), "");
}

/* ---- overall verdict rules ----------------------------------------------- */
/* Diagonal normal equations: lambda = A_ii, P = I, z_i = b_i / lambda_i /
 * sqrt(1 + 1/lambda_i); b is chosen for the z below. Reference values
 * (scipy 1.17): z_0.995 = norm.isf(0.005) = 2.575829303548901 (the seed's
 * 2.58), chi2_0.01(5) = chi2.isf(0.01, 5) = 15.086272469388991 (Abramowitz
 * & Stegun Table 26.8: 15.086), Sidak level g = 1 - 0.99^(1/5) =
 * 0.002008048338574153 and norm.isf(g / 2) = 3.089039359975515. */
enum { NV = 6 };
static const double lamv[NV] = {1e4, 1e3, 100, 50, 20, 1};
static const double zv[5] = {2.7, -1.0, 0.5, -3.0, 0.2};

static int solve_rule(int rule, double *z, int *rej, double *info)
{
    double A[NV * NV] = {0}, b[NV], o[IGEA_EQERR_OPT_LEN], lam[NV], P[NV * NV], xh[NV];
    for (int i = 0; i < NV; i++) {
        A[i + i * NV] = lamv[i];
        b[i] = (i < 5 ? zv[i] : 0.3) * sqrt(1 + 1 / lamv[i]) * lamv[i];
    }
    igea_eqerr_defaults(o);
    o[IGEA_EQERR_OPT_CORRECTION] = 0;
    o[IGEA_EQERR_OPT_VERDICT] = rule;
    o[IGEA_EQERR_OPT_OVERALL_SIZE] = 1;
    return igea_eqerr_solve(NV, A, NV, b, o, lam, P, NV, xh, z, rej, info);
}

static void test_verdict_rules(void **state)
{
    (void)state;
    double z[NV], info[IGEA_STATS_INFO_LEN];
    int rej[NV];
    const double zc = 2.575829303548901, c5 = 15.086272469388991, T = 2.7 * 2.7 + 1 + 0.25 + 9 + 0.04;
    /* seed: components 0 and 3 beyond 2.5758 */
    assert_int_equal(solve_rule(IGEA_STATS_VERDICT_SEED, z, rej, info), 0);
    assert_int_equal((int)info[IGEA_STATS_INFO_N_TEST], 5);
    for (int i = 0; i < 5; i++)
        assert_close(z[i], zv[i], 1e-12);
    assert_close(info[IGEA_STATS_INFO_CHI2], T, 1e-12);
    assert_int_equal(rej[0] + rej[3], 2);
    assert_int_equal(rej[1] + rej[2] + rej[4], 0);
    assert_int_equal(rej[5], -1);
    assert_int_equal((int)info[IGEA_STATS_INFO_PASSED], 0);
    assert_int_equal((int)info[IGEA_STATS_INFO_VERDICT], IGEA_STATS_VERDICT_SEED);
    assert_close(info[IGEA_STATS_INFO_VERDICT_Z_CRIT], zc, 1e-12);
    assert_close(info[IGEA_STATS_INFO_VERDICT_CHI2_CRIT], c5, 1e-10);
    /* the seed's size for n = 5 lies between its two parts' and their sum */
    double g = info[IGEA_STATS_INFO_OVERALL_SIZE], cube = 1 - pow(1 - 0.01, 5);
    assert_true(g > cube && g < cube + 0.01);
    /* chi2 alone: no component test, T = 17.54 >= 15.086 rejects */
    assert_int_equal(solve_rule(IGEA_STATS_VERDICT_CHI2, z, rej, info), 0);
    for (int i = 0; i < 5; i++)
        assert_int_equal(rej[i], 0);
    assert_int_equal((int)info[IGEA_STATS_INFO_N_REJECT], 0);
    assert_int_equal((int)info[IGEA_STATS_INFO_PASSED], T < c5);
    assert_true(info[IGEA_STATS_INFO_VERDICT_Z_CRIT] == 0.0);
    assert_close(info[IGEA_STATS_INFO_OVERALL_SIZE], 0.01, 1e-15);
    /* Sidak: no component beyond 3.089 (|z| = 3.0 passes); T >= 15.086 rejects */
    assert_int_equal(solve_rule(IGEA_STATS_VERDICT_SIDAK, z, rej, info), 0);
    assert_close(info[IGEA_STATS_INFO_VERDICT_Z_CRIT], 3.089039359975515, 1e-10);
    assert_close(info[IGEA_STATS_INFO_VERDICT_CHI2_CRIT], c5, 1e-10);
    assert_int_equal((int)info[IGEA_STATS_INFO_N_REJECT], 0);
    assert_int_equal((int)info[IGEA_STATS_INFO_PASSED], 0); /* T >= 15.086 */
    /* exact: size alpha, both thresholds at one level g */
    assert_int_equal(solve_rule(IGEA_STATS_VERDICT_EXACT, z, rej, info), 0);
    assert_close(info[IGEA_STATS_INFO_OVERALL_SIZE], 0.01, 1e-10);
    double a = info[IGEA_STATS_INFO_VERDICT_Z_CRIT], b = info[IGEA_STATS_INFO_VERDICT_CHI2_CRIT];
    double pa, qb;
    igea_stats_normal_cdf(-a, &pa);
    igea_stats_chi2_sf(b, 5, &qb);
    assert_close(2 * pa, qb, 1e-9);
    assert_true(a > zc && b > c5 && 2 * pa > 0.01 / 6 && 2 * pa < 0.01);
    assert_int_equal((int)info[IGEA_STATS_INFO_PASSED], !(3.0 > a) && T < b);
}

static void test_verdict_limits_and_cache(void **state)
{
    (void)state;
    double o[IGEA_EQERR_OPT_LEN];
    igea_eqerr_defaults(o);
    o[IGEA_EQERR_OPT_VERDICT] = IGEA_STATS_VERDICT_EXACT;
    assert_int_equal(igea_eqerr_check_opts(o), 0);
    o[IGEA_EQERR_OPT_Z_CRIT] = 2.58; /* an imposed z_crit is the seed's rule only */
    assert_int_equal(igea_eqerr_check_opts(o), 1 + IGEA_EQERR_OPT_VERDICT);
    o[IGEA_EQERR_OPT_Z_CRIT] = 0;
    o[IGEA_EQERR_OPT_VERDICT] = 4;
    assert_int_equal(igea_eqerr_check_opts(o), 1 + IGEA_EQERR_OPT_VERDICT);
    o[IGEA_EQERR_OPT_VERDICT] = 0;
    o[IGEA_EQERR_OPT_OVERALL_SIZE] = 0.5;
    assert_int_equal(igea_eqerr_check_opts(o), 1 + IGEA_EQERR_OPT_OVERALL_SIZE);
    assert_string_equal(igea_opt_name(IGEA_MODULE_EQERR, IGEA_EQERR_OPT_VERDICT), "verdict");
    assert_string_equal(igea_opt_name(IGEA_MODULE_EQERR, IGEA_EQERR_OPT_OVERALL_SIZE),
                        "overall_size");
    /* 201 tested components: beyond the union-size quadrature */
    enum { NB = 201 };
    double *A = calloc(NB * NB, sizeof(double)), *P = malloc(NB * NB * sizeof(double));
    double b[NB], lam[NB], xh[NB], z[NB], info[IGEA_STATS_INFO_LEN], info2[IGEA_STATS_INFO_LEN];
    int rej[NB];
    for (int i = 0; i < NB; i++) {
        A[i + i * NB] = 100.0 + i;
        b[i] = 0.1 * (i % 7) - 0.3;
    }
    igea_eqerr_defaults(o);
    o[IGEA_EQERR_OPT_CORRECTION] = 0;
    o[IGEA_EQERR_OPT_OVERALL_SIZE] = 1;
    assert_int_equal(igea_eqerr_solve(NB, A, NB, b, o, lam, P, NB, xh, z, rej, info), 0);
    assert_true(info[IGEA_STATS_INFO_OVERALL_SIZE] == 0.0); /* not computed */
    assert_close(info[IGEA_STATS_INFO_SIGMA_W], 1.0, 0);
    o[IGEA_EQERR_OPT_VERDICT] = IGEA_STATS_VERDICT_EXACT;
    info2[0] = -7;
    assert_int_equal(igea_eqerr_solve(NB, A, NB, b, o, lam, P, NB, xh, z, rej, info2),
                     IGEA_EVERDICT);
    assert_true(info2[0] == -7);
    assert_true(strlen(igea_strerror(IGEA_EVERDICT)) > 20);
    free(A);
    free(P);
    /* the thread cache gives the uncached answer */
    double A3[9] = {400, 0, 0, 0, 90, 0, 0, 0, 30}, b3[3] = {900, -150, 40}, cache[12] = {0};
    double l3[3], P3[9], x3[3], z3[3], i1[IGEA_STATS_INFO_LEN], i2[IGEA_STATS_INFO_LEN];
    int r3[3];
    igea_eqerr_defaults(o);
    o[IGEA_EQERR_OPT_CORRECTION] = 0;
    o[IGEA_EQERR_OPT_VERDICT] = IGEA_STATS_VERDICT_EXACT;
    assert_int_equal(igea_eqerr_solve(3, A3, 3, b3, o, l3, P3, 3, x3, z3, r3, i1), 0);
    for (int rep = 0; rep < 2; rep++) {
        assert_int_equal(igea__eqerr_solve_cached(3, A3, 3, b3, o, cache, l3, P3, 3, x3, z3, r3,
                                                  i2), 0);
        assert_memory_equal(i1, i2, sizeof i1);
    }
    assert_true(cache[4 * 2] == 1.0 && cache[0] == 0.0);
    /* the caller's precomputed thresholds for n = 5 are used as given */
    double z5[NV], info5[IGEA_STATS_INFO_LEN], A5[NV * NV] = {0}, b5[NV], l5[NV], P5[NV * NV];
    double x5[NV];
    int r5[NV];
    for (int i = 0; i < NV; i++) {
        A5[i + i * NV] = lamv[i];
        b5[i] = (i < 5 ? zv[i] : 0.3) * sqrt(1 + 1 / lamv[i]) * lamv[i];
    }
    igea_eqerr_defaults(o);
    o[IGEA_EQERR_OPT_CORRECTION] = 0;
    o[IGEA_EQERR_OPT_VERDICT] = IGEA_STATS_VERDICT_EXACT;
    o[IGEA_EQERR_OPT_VERDICT_N] = 5;
    o[IGEA_EQERR_OPT_VERDICT_A] = 2.9;
    o[IGEA_EQERR_OPT_VERDICT_B] = 100.0;
    o[IGEA_EQERR_OPT_VERDICT_SIZE] = 0.25;
    assert_int_equal(igea_eqerr_solve(NV, A5, NV, b5, o, l5, P5, NV, x5, z5, r5, info5), 0);
    assert_int_equal((int)info5[IGEA_STATS_INFO_N_REJECT], 1); /* only |z| = 3.0 > 2.9 */
    assert_true(info5[IGEA_STATS_INFO_OVERALL_SIZE] == 0.25);
    o[IGEA_EQERR_OPT_VERDICT_N] = 4; /* for another n: ignored, the rule's own */
    assert_int_equal(igea_eqerr_solve(NV, A5, NV, b5, o, l5, P5, NV, x5, z5, r5, info5), 0);
    assert_close(info5[IGEA_STATS_INFO_OVERALL_SIZE], 0.01, 1e-10);
    o[IGEA_EQERR_OPT_VERDICT_N] = 2.5;
    assert_int_equal(igea_eqerr_check_opts(o), 1 + IGEA_EQERR_OPT_VERDICT_N);
    o[IGEA_EQERR_OPT_VERDICT_N] = 3;
    o[IGEA_EQERR_OPT_VERDICT_B] = 0;
    assert_int_equal(igea_eqerr_check_opts(o), 1 + IGEA_EQERR_OPT_VERDICT_B);
    assert_string_equal(igea_opt_name(IGEA_MODULE_EQERR, IGEA_EQERR_OPT_VERDICT_SIZE),
                        "verdict_size");
}

static void test_pool_rule(void **state)
{
    (void)state;
    /* two flights of 2 and 3 components */
    double chi2[2] = {2.7 * 2.7 + 1.0, 0.25 + 9.0 + 0.04}, zall[5] = {2.7, -1, 0.5, -3, 0.2};
    int dof[2] = {2, 3}, rej[5], uid[2] = {4, 4};
    double o[IGEA_EQERR_OPT_LEN], info[IGEA_STATS_INFO_LEN];
    igea_eqerr_defaults(o);
    o[IGEA_EQERR_OPT_OVERALL_SIZE] = 1;
    assert_int_equal(igea_eqerr_pool(2, chi2, dof, zall, NULL, o, rej, info), 0);
    assert_int_equal((int)info[IGEA_STATS_INFO_DOF], 5);
    assert_close(info[IGEA_STATS_INFO_CHI2], chi2[0] + chi2[1], 1e-15);
    assert_close(info[IGEA_STATS_INFO_VERDICT_CHI2_CRIT], 15.086272469388991, 1e-10);
    assert_int_equal((int)info[IGEA_STATS_INFO_N_REJECT], 2);
    assert_int_equal(rej[0] + rej[3], 2);
    assert_int_equal((int)info[IGEA_STATS_INFO_N_FLIGHTS], 2);
    /* the same as the seed's pooling of the flights' own rejections */
    int nrej[2] = {1, 1};
    double i0[IGEA_STATS_INFO_LEN];
    assert_int_equal(igea_stats_pool(2, chi2, dof, nrej, NULL, 0.01, i0), 0);
    assert_true(i0[IGEA_STATS_INFO_PASSED] == info[IGEA_STATS_INFO_PASSED]);
    /* the same as one flight of 5 with the same z (a diagonal solve) */
    double z[NV], i5[IGEA_STATS_INFO_LEN];
    int r5[NV];
    assert_int_equal(solve_rule(IGEA_STATS_VERDICT_SEED, z, r5, i5), 0);
    assert_close(info[IGEA_STATS_INFO_OVERALL_SIZE], i5[IGEA_STATS_INFO_OVERALL_SIZE], 1e-12);
    o[IGEA_EQERR_OPT_VERDICT] = IGEA_STATS_VERDICT_SIDAK;
    assert_int_equal(igea_eqerr_pool(2, chi2, dof, zall, NULL, o, NULL, info), 0);
    assert_close(info[IGEA_STATS_INFO_VERDICT_Z_CRIT], 3.089039359975515, 1e-10);
    assert_int_equal((int)info[IGEA_STATS_INFO_N_REJECT], 0);
    assert_int_equal(igea_eqerr_pool(2, chi2, dof, zall, uid, o, NULL, info), IGEA_EDEPENDENT);
    zall[4] = NAN;
    assert_int_equal(igea_eqerr_pool(2, chi2, dof, zall, NULL, o, NULL, info), IGEA_ENONFINITE);
    dof[1] = 0;
    assert_int_equal(igea_eqerr_pool(2, chi2, dof, zall, NULL, o, NULL, info), -3);
}

static void test_limits_and_rms(void **state)
{
    (void)state;
    double lam[2] = {3.0, 0.25}, thr[2], prec[2];
    assert_int_equal(igea_eqerr_limits(2, lam, 2.0, thr, prec), 0);
    assert_close(thr[0], 2.0 * sqrt(4.0 / 3.0), 1e-15);
    assert_close(thr[1], 2.0 * sqrt(5.0), 1e-15);
    assert_close(prec[0], 1 / sqrt(3.0), 1e-15);
    assert_close(prec[1], 2.0, 1e-15);
    lam[1] = 0;
    assert_int_equal(igea_eqerr_limits(2, lam, 2.0, thr, NULL), IGEA_ENONPOSITIVE);
    double ss[6] = {8, 27, 0, 2, 3, 0}, rms[3];
    assert_int_equal(igea_eqerr_axis_rms(ss, rms), 0);
    assert_close(rms[0], 2.0, 1e-15);
    assert_close(rms[1], 3.0, 1e-15);
    assert_true(rms[2] == 0.0);
    ss[0] = -1;
    assert_int_equal(igea_eqerr_axis_rms(ss, rms), -1);
}

/* ---- residual diagnostics ------------------------------------------------- */
/* x_t = (-1)^t, n = 10, centre 0: r_k = (-1)^k (n - k) / n, so Ljung-Box
 * over L = 3 lags is Q = (n + 2)/n sum_{k<=3} (n - k) = 1.2 * 24 = 28.8;
 * 10 runs of 5 + 5 signs: mean 6, variance 2*25*40/(100*9) = 20/9,
 * z = 4 / sqrt(20/9) = 2.6832815729997477. */
static void test_diag_closed_form(void **state)
{
    (void)state;
    double x[10], s[IGEA_STATS_DIAG_STATE_LEN], out[IGEA_STATS_DIAG_LEN], q;
    for (int t = 0; t < 10; t++)
        x[t] = t % 2 ? -1.0 : 1.0;
    assert_int_equal(igea_stats_diag_init(3, 0.0, s), 0);
    assert_int_equal(igea_stats_diag_add(4, x, 1, s), 0);  /* in two blocks */
    assert_int_equal(igea_stats_diag_add(6, x + 4, 1, s), 0);
    assert_int_equal(igea_stats_diag_result(s, out), 0);
    assert_close(out[IGEA_STATS_DIAG_LB_Q], 28.8, 1e-14);
    igea_stats_chi2_sf(28.8, 3, &q);
    assert_close(out[IGEA_STATS_DIAG_LB_P], q, 1e-14);
    assert_int_equal((int)out[IGEA_STATS_DIAG_RUNS], 10);
    assert_int_equal((int)out[IGEA_STATS_DIAG_N_ABOVE], 5);
    assert_int_equal((int)out[IGEA_STATS_DIAG_N_BELOW], 5);
    assert_close(out[IGEA_STATS_DIAG_RUNS_Z], 2.6832815729997477, 1e-14);
    assert_close(out[IGEA_STATS_DIAG_RUNS_P], erfc(2.6832815729997477 / sqrt(2.0)), 1e-13);
    /* about its own mean (0 here) in one call: the same */
    double o2[IGEA_STATS_DIAG_LEN];
    assert_int_equal(igea_stats_whiteness(10, x, 1, 3, o2), 0);
    assert_memory_equal(out, o2, sizeof out);
    /* too short, constant, NaN, a state never initialised */
    assert_int_equal(igea_stats_whiteness(4, x, 1, 3, o2), IGEA_EEMPTY);
    double c[6] = {2, 2, 2, 2, 2, 2};
    assert_int_equal(igea_stats_whiteness(6, c, 1, 2, o2), IGEA_EDOMAIN);
    x[3] = NAN;
    assert_int_equal(igea_stats_diag_add(10, x, 1, s), IGEA_ENONFINITE);
    double junk[IGEA_STATS_DIAG_STATE_LEN] = {0};
    assert_int_equal(igea_stats_diag_add(1, c, 1, junk), -4);
    assert_int_equal(igea_stats_diag_init(IGEA_STATS_DIAG_LAGS_MAX + 1, 0, s), -1);
}

/* The per-axis routing: rows epoch-major x, y, z in blocks starting at any
 * row give the in-memory per-axis results; the residual mean from the
 * pass-1 sums is the mean of the residuals. */
static void test_eqerr_diag_streamed(void **state)
{
    (void)state;
    enum { MR = 300, NR = 2 };
    double S[MR * NR], dw[MR], coef[NR] = {0.7, -0.2}, e[MR], sums[3 * (NR + 2)] = {0};
    for (int i = 0; i < MR; i++) {
        S[i] = 1.0 + (i % 3);
        S[i + MR] = sin(0.1 * i);
        dw[i] = 0.7 * S[i] - 0.2 * S[i + MR] + 0.01 * cos(1.3 * i * i) + 0.001 * (i % 3);
    }
    assert_int_equal(igea_eqerr_residual(IGEA_COLMAJOR, MR, NR, S, MR, dw, coef, 0, e, NULL), 0);
    double out[3 * IGEA_STATS_DIAG_LEN], mean[3], st[3 * IGEA_STATS_DIAG_STATE_LEN];
    int ast[3];
    assert_int_equal(igea_eqerr_diag(MR, e, 7, out, ast), 0);
    assert_int_equal(ast[0] + ast[1] + ast[2], 0);
    /* pass 1 in two blocks of 101 and 199 rows (row-major copies) */
    double Sr[MR * NR];
    for (int i = 0; i < MR; i++)
        for (int j = 0; j < NR; j++)
            Sr[j + i * NR] = S[i + j * MR];
    assert_int_equal(igea_eqerr_axis_sums(IGEA_ROWMAJOR, 101, NR, Sr, NR, dw, 0, sums), 0);
    assert_int_equal(igea_eqerr_axis_sums(IGEA_ROWMAJOR, 199, NR, Sr + 101 * NR, NR, dw + 101,
                                          101, sums), 0);
    assert_int_equal(igea_eqerr_residual_mean(NR, sums, coef, mean), 0);
    for (int a = 0; a < 3; a++) {
        double m = 0;
        for (int i = a; i < MR; i += 3)
            m += e[i] / 100;
        assert_close_abs(mean[a], m, 1e-9, 1e-15);
        igea_stats_diag_init(7, mean[a], st + a * IGEA_STATS_DIAG_STATE_LEN);
    }
    assert_int_equal(igea_eqerr_diag_add(101, e, 0, st), 0);
    assert_int_equal(igea_eqerr_diag_add(98, e + 101, 101, st), 0);
    assert_int_equal(igea_eqerr_diag_add(101, e + 199, 199, st), 0);
    for (int a = 0; a < 3; a++) {
        double r[IGEA_STATS_DIAG_LEN];
        const double *w = out + a * IGEA_STATS_DIAG_LEN;
        assert_int_equal(igea_stats_diag_result(st + a * IGEA_STATS_DIAG_STATE_LEN, r), 0);
        assert_int_equal((int)r[IGEA_STATS_DIAG_N], 100);
        assert_close(r[IGEA_STATS_DIAG_LB_Q], w[IGEA_STATS_DIAG_LB_Q], 1e-9);
        assert_true(r[IGEA_STATS_DIAG_RUNS] == w[IGEA_STATS_DIAG_RUNS]);
    }
    /* an axis with too few values is reported, not an error */
    assert_int_equal(igea_eqerr_diag(20, e, 7, out, ast), 0);
    assert_int_equal(ast[0], IGEA_EEMPTY);
}

/* Pass-1 axis sums of 7 columns (not a multiple of the four added at a
 * time): both layouts the same bits and the sums of the definition; a NaN,
 * or +Inf and -Inf in one column and axis, is IGEA_ENONFINITE, finite data
 * whose sum overflows IGEA_EOVERFLOW, the sums untouched on failure. */
static void test_axis_sums_statuses(void **state)
{
    (void)state;
    enum { MS = 11, NS = 7 };
    double S[MS * NS], Sr[MS * NS], dw[MS], a[3 * (NS + 2)] = {0}, b[3 * (NS + 2)] = {0};
    for (int i = 0; i < MS; i++) {
        dw[i] = 0.5 * i;
        for (int j = 0; j < NS; j++)
            S[i + j * MS] = Sr[j + i * NS] = 1.0 / (1 + i + 3 * j);
    }
    assert_int_equal(igea_eqerr_axis_sums(IGEA_COLMAJOR, MS, NS, S, MS, dw, 2, a), 0);
    assert_int_equal(igea_eqerr_axis_sums(IGEA_ROWMAJOR, MS, NS, Sr, NS, dw, 2, b), 0);
    assert_memory_equal(a, b, sizeof a);
    for (int ax = 0; ax < 3; ax++) { /* row i has axis (2 + i) % 3 */
        const double *u = a + ax * (NS + 2);
        double cnt = 0, sd = 0, s6 = 0;
        for (int i = 0; i < MS; i++)
            if ((2 + i) % 3 == ax)
                cnt += 1, sd += dw[i], s6 += S[i + 6 * MS];
        assert_true(u[0] == cnt && u[1] == sd && u[2 + 6] == s6);
    }
    memcpy(b, a, sizeof a);
    Sr[5 * NS + 6] = NAN;
    assert_int_equal(igea_eqerr_axis_sums(IGEA_ROWMAJOR, MS, NS, Sr, NS, dw, 0, b),
                     IGEA_ENONFINITE);
    Sr[5 * NS + 6] = INFINITY, Sr[8 * NS + 6] = -INFINITY; /* rows 5 and 8: one axis */
    assert_int_equal(igea_eqerr_axis_sums(IGEA_ROWMAJOR, MS, NS, Sr, NS, dw, 0, b),
                     IGEA_ENONFINITE);
    Sr[5 * NS + 6] = Sr[8 * NS + 6] = 1.5e308;
    assert_int_equal(igea_eqerr_axis_sums(IGEA_ROWMAJOR, MS, NS, Sr, NS, dw, 0, b),
                     IGEA_EOVERFLOW);
    assert_memory_equal(a, b, sizeof a);
}

/* igea_eqerr_accumulate: the normal equations and the axis sums of a block
 * in one pass. On 0 and 1 threads it gives the bits of
 * igea_normal_accumulate_threads followed by igea_eqerr_axis_sums, block
 * by block (blocks of 7001 rows: the axis turns inside them), in both
 * layouts, with one sigma, a per-row sigma equal everywhere and different
 * ones; on 2, 3 and 5 threads (20,000 rows a block, in segments of
 * IGEA_NORMAL_SEGMENT) one result, equal to those to rounding, the axis
 * sums to 1e-13 of sums in long double in row order written here. A NaN
 * or Inf anywhere, also where the weights underflow so that the normal
 * equations cannot see it (sigma 1e170: (1/sigma)^2 = 0), is
 * IGEA_ENONFINITE, an overflow IGEA_EOVERFLOW, everything untouched. */
static void test_accumulate_one_pass(void **state)
{
    (void)state;
    enum { MA = 20000, NA = 9, BA = 7001, W3 = 3 * (NA + 2) };
    double *S = malloc(sizeof(double) * MA * NA), *Sr = malloc(sizeof(double) * MA * NA);
    double *dw = malloc(sizeof(double) * MA), *sg = malloc(sizeof(double) * MA), spec[NA];
    assert_non_null(S && Sr && dw && sg);
    for (int j = 0; j < NA; j++)
        spec[j] = 0.5 + 0.25 * j;
    for (int i = 0; i < MA; i++) {
        dw[i] = 0.01 * sin(3.0 * i);
        for (int j = 0; j < NA; j++)
            S[i + (size_t)j * MA] = Sr[(size_t)i * NA + j] =
                cos(1e-3 * (j + 1) * i + j) + 1e-2 * sin(7.0 * i * (j + 1));
    }
    for (int kind = 0; kind < 3; kind++) { /* one sigma, per row equal, per row */
        int inc = kind > 0;
        for (int i = 0; i < MA; i++)
            sg[i] = kind == 2 ? 0.01 * (1.0 + 0.5 * sin(0.1 * i)) : 0.01;
        for (int lay = 0; lay < 2; lay++) {
            int layout = lay ? IGEA_ROWMAJOR : IGEA_COLMAJOR, lds = lay ? NA : MA;
            const double *X = lay ? Sr : S;
            for (int th = 0; th <= 1; th++) {
                double A[2][NA * NA], b[2][NA], w[2][2], u[2][W3];
                memset(A, 0, sizeof A), memset(b, 0, sizeof b), memset(w, 0, sizeof w);
                memset(u, 0, sizeof u);
                for (int r0 = 0; r0 < MA; r0 += BA) {
                    int n = MA - r0 < BA ? MA - r0 : BA;
                    const double *Xb = lay ? X + (size_t)r0 * NA : X + r0;
                    assert_int_equal(igea_normal_accumulate_threads(layout, n, NA, Xb, lds, dw + r0,
                                                                    sg + (inc ? r0 : 0), inc,
                                                                    spec, A[0], NA, b[0], w[0],
                                                                    th), 0);
                    assert_int_equal(igea_eqerr_axis_sums(layout, n, NA, Xb, lds, dw + r0, r0,
                                                          u[0]), 0);
                    assert_int_equal(igea_eqerr_accumulate(layout, n, NA, Xb, lds, dw + r0,
                                                           sg + (inc ? r0 : 0), inc, spec, A[1],
                                                           NA, b[1], w[1], th, r0, u[1]), 0);
                }
                assert_memory_equal(A[0], A[1], sizeof A[0]);
                assert_memory_equal(b[0], b[1], sizeof b[0]);
                assert_memory_equal(w[0], w[1], sizeof w[0]);
                assert_memory_equal(u[0], u[1], sizeof u[0]);
            }
            /* threads: one block of 20,000 rows from row 2 of the flight */
            double A1[NA * NA] = {0}, b1[NA] = {0}, w1[2] = {0}, u1[W3] = {0};
            assert_int_equal(igea_eqerr_accumulate(layout, MA, NA, X, lds, dw, sg, inc, spec,
                                                   A1, NA, b1, w1, 1, 2, u1), 0);
            double At[NA * NA], bt[NA], wt[2], ut[W3];
            for (int th = 2; th <= 5; th += th == 3 ? 2 : 1) {
                double A2[NA * NA] = {0}, b2[NA] = {0}, w2[2] = {0}, u2[W3] = {0};
                assert_int_equal(igea_eqerr_accumulate(layout, MA, NA, X, lds, dw, sg, inc, spec,
                                                       A2, NA, b2, w2, th, 2, u2), 0);
                if (th == 2) {
                    memcpy(At, A2, sizeof At), memcpy(bt, b2, sizeof bt);
                    memcpy(wt, w2, sizeof wt), memcpy(ut, u2, sizeof ut);
                    for (int k = 0; k < NA * NA; k++)
                        assert_close_abs(A2[k], A1[k], 1e-13, 1e-13 * A1[0]);
                    for (int k = 0; k < NA; k++)
                        assert_close_abs(b2[k], b1[k], 1e-12, 1e-12 * fabs(b1[0]));
                    assert_close(w2[0], w1[0], 1e-13);
                    assert_true(w2[1] == MA);
                } else {
                    assert_memory_equal(A2, At, sizeof At);
                    assert_memory_equal(b2, bt, sizeof bt);
                    assert_memory_equal(w2, wt, sizeof wt);
                    assert_memory_equal(u2, ut, sizeof ut);
                }
            }
            /* the axis sums against long double sums in row order (row 0
             * of the block is row 2 of the flight: axis z) */
            for (int a = 0; a < 3; a++) {
                long double cnt = 0, sd = 0, sj[NA] = {0};
                for (int i = 0; i < MA; i++) {
                    if ((i + 2) % 3 != a)
                        continue;
                    cnt += 1, sd += dw[i];
                    for (int j = 0; j < NA; j++)
                        sj[j] += S[i + (size_t)j * MA];
                }
                const double *v = ut + a * (NA + 2);
                assert_true(v[0] == (double)cnt);
                assert_close_abs(v[1], (double)sd, 1e-13, 1e-15);
                for (int j = 0; j < NA; j++) {
                    assert_close_abs(v[2 + j], (double)sj[j], 1e-13, 1e-13 * cnt);
                    assert_close_abs(u1[a * (NA + 2) + 2 + j], (double)sj[j], 1e-13, 1e-13 * cnt);
                }
            }
        }
    }
    /* failures: untouched outputs */
    double A[NA * NA], b[NA], w[2], u[W3], keep[NA * NA + NA + 2 + W3];
    for (int k = 0; k < NA * NA; k++)
        A[k] = 0.5 * k;
    for (int k = 0; k < NA; k++)
        b[k] = k;
    w[0] = 3, w[1] = 7;
    for (int k = 0; k < W3; k++)
        u[k] = k % (NA + 2) == 0 ? 4.0 : 0.25 * k;
    memcpy(keep, A, sizeof A), memcpy(keep + NA * NA, b, sizeof b);
    memcpy(keep + NA * NA + NA, w, sizeof w), memcpy(keep + NA * NA + NA + 2, u, sizeof u);
#define UNTOUCHED()                                                                          \
    do {                                                                                     \
        assert_memory_equal(A, keep, sizeof A);                                              \
        assert_memory_equal(b, keep + NA * NA, sizeof b);                                    \
        assert_memory_equal(w, keep + NA * NA + NA, sizeof w);                               \
        assert_memory_equal(u, keep + NA * NA + NA + 2, sizeof u);                           \
    } while (0)
    double big = 1e170;
    for (int th = 1; th <= 2; th++) {
        Sr[(size_t)17000 * NA + 4] = NAN;
        assert_int_equal(igea_eqerr_accumulate(IGEA_ROWMAJOR, MA, NA, Sr, NA, dw, sg, 1, spec, A,
                                               NA, b, w, th, 0, u), IGEA_ENONFINITE);
        UNTOUCHED();
        assert_int_equal(igea_eqerr_accumulate(IGEA_ROWMAJOR, MA, NA, Sr, NA, dw, &big, 0, spec,
                                               A, NA, b, w, th, 0, u), IGEA_ENONFINITE);
        UNTOUCHED();
        Sr[(size_t)17000 * NA + 4] = -INFINITY;
        assert_int_equal(igea_eqerr_accumulate(IGEA_ROWMAJOR, MA, NA, Sr, NA, dw, &big, 0, spec,
                                               A, NA, b, w, th, 0, u), IGEA_ENONFINITE);
        UNTOUCHED();
        Sr[(size_t)17000 * NA + 4] = 1e200; /* its square overflows */
        assert_int_equal(igea_eqerr_accumulate(IGEA_ROWMAJOR, MA, NA, Sr, NA, dw, sg, 1, spec, A,
                                               NA, b, w, th, 0, u), IGEA_EOVERFLOW);
        UNTOUCHED();
        Sr[(size_t)17000 * NA + 4] = 1.0;
    }
    /* arguments: 14 nthreads, 15 row0, 16 sums (finite, counts >= 0) */
    assert_int_equal(igea_eqerr_accumulate(IGEA_ROWMAJOR, MA, NA, Sr, NA, dw, sg, 1, spec, A, NA,
                                           b, w, -1, 0, u), -14);
    assert_int_equal(igea_eqerr_accumulate(IGEA_ROWMAJOR, MA, NA, Sr, NA, dw, sg, 1, spec, A, NA,
                                           b, w, 1, -1, u), -15);
    assert_int_equal(igea_eqerr_accumulate(IGEA_ROWMAJOR, MA, NA, Sr, NA, dw, sg, 1, spec, A, NA,
                                           b, w, 1, 0, NULL), -16);
    u[NA + 2] = -1;
    assert_int_equal(igea_eqerr_accumulate(IGEA_ROWMAJOR, MA, NA, Sr, NA, dw, sg, 1, spec, A, NA,
                                           b, w, 1, 0, u), -16);
    u[NA + 2] = NAN;
    assert_int_equal(igea_eqerr_accumulate(IGEA_ROWMAJOR, MA, NA, Sr, NA, dw, sg, 1, spec, A, NA,
                                           b, w, 1, 0, u), IGEA_ENONFINITE);
#undef UNTOUCHED
    free(S), free(Sr), free(dw), free(sg);
}

/* igea_eqerr_run_layout: column-major is igea_eqerr_run itself (the same
 * bits); the same flight stored row by row gives the same results to
 * rounding on both routes and on 1 and 3 threads (segments of
 * IGEA_NORMAL_SEGMENT rows: 40,000 rows are five); its statuses are
 * igea_eqerr_run's shifted by the layout argument. */
/* igea_eqerr_residual_threads: 3 segments of IGEA_NORMAL_SEGMENT rows and
 * a part, both layouts, row0 = 2 and axis sums that start from nonzero
 * values. The residuals against long double dot products, the axis sums
 * against the header's definition (each segment's squares of the returned
 * residuals in row order, the segments added in order, bit for bit) and
 * against long double sums; the same bits on 2, 3 and 4 threads; 0 and 1
 * thread are igea_eqerr_residual's bits. */
static void test_residual_threads(void **state)
{
    enum { SEG = IGEA_NORMAL_SEGMENT, M = 3 * SEG + 1001, N = 5, R0 = 2 };
    double *S = malloc(sizeof(double) * M * N), *Sr = malloc(sizeof(double) * M * N);
    double *dw = malloc(sizeof(double) * M), *e = malloc(sizeof(double) * M);
    double *e1 = malloc(sizeof(double) * M), *ek = malloc(sizeof(double) * M);
    assert_non_null(S); assert_non_null(Sr); assert_non_null(dw);
    assert_non_null(e); assert_non_null(e1); assert_non_null(ek);
    const double coef[N] = {0.7, -1.3, 0.25, 2.0, -0.05}, ss0[6] = {0.5, 0.25, 0.125, 7, 8, 9};
    unsigned long long x = 12345;
    for (int i = 0; i < M; i++) {
        for (int j = 0; j < N; j++) {
            x = x * 6364136223846793005ULL + 1442695040888963407ULL;
            double v = (double)(x >> 11) / 9007199254740992.0 - 0.5;
            S[i + (size_t)j * M] = v;
            Sr[(size_t)i * N + j] = v;
        }
        dw[i] = 0.3 * sin(0.01 * i);
    }
    for (int layout = 0; layout < 2; layout++) {
        const double *SS = layout == IGEA_COLMAJOR ? S : Sr;
        int lds = layout == IGEA_COLMAJOR ? M : N;
        double ss[6], ss1[6], ssk[6];
        memcpy(ss, ss0, sizeof ss);
        assert_int_equal(igea_eqerr_residual_threads(layout, M, N, SS, lds, dw, coef, R0, e, ss, 2), 0);
        long double tl[3] = {0, 0, 0};
        for (int i = 0; i < M; i++) {
            long double r = dw[i];
            for (int j = 0; j < N; j++)
                r -= (long double)S[i + (size_t)j * M] * coef[j];
            assert_close_abs(e[i], (double)r, 1e-14, 1e-15);
            tl[(R0 + i) % 3] += r * r;
        }
        double def[6];
        memcpy(def, ss0, sizeof def);
        for (int k = 0; k * SEG < M; k++) {
            double t[3] = {0, 0, 0};
            for (int i = k * SEG; i < M && i < (k + 1) * SEG; i++)
                t[(R0 + i) % 3] += e[i] * e[i];
            for (int a = 0; a < 3; a++)
                def[a] += t[a];
        }
        for (int a = 0; a < 3; a++) {
            assert_true(ss[a] == def[a]);
            assert_close(ss[a], (double)(ss0[a] + tl[a]), 1e-13);
            assert_true(ss[3 + a] == ss0[3 + a] + (M - ((a - R0 + 3) % 3) + 2) / 3);
        }
        for (int th = 3; th <= 4; th++) {
            memcpy(ssk, ss0, sizeof ssk);
            assert_int_equal(igea_eqerr_residual_threads(layout, M, N, SS, lds, dw, coef, R0, ek, ssk, th), 0);
            assert_memory_equal(ek, e, sizeof(double) * M);
            assert_memory_equal(ssk, ss, sizeof ss);
        }
        for (int th = 0; th <= 1; th++) {
            memcpy(ss1, ss0, sizeof ss1);
            memcpy(ssk, ss0, sizeof ssk);
            assert_int_equal(igea_eqerr_residual(layout, M, N, SS, lds, dw, coef, R0, e1, ss1), 0);
            assert_int_equal(igea_eqerr_residual_threads(layout, M, N, SS, lds, dw, coef, R0, ek, ssk, th), 0);
            assert_memory_equal(ek, e1, sizeof(double) * M);
            assert_memory_equal(ssk, ss1, sizeof ss1);
            for (int a = 0; a < 3; a++)
                assert_close(ssk[a], ss[a], 1e-13);
        }
        /* failures leave the outputs as they were */
        for (int i = 0; i < M; i++)
            ek[i] = -1.0;
        memcpy(ssk, ss0, sizeof ssk);
        dw[M - 3] = NAN;
        assert_int_equal(igea_eqerr_residual_threads(layout, M, N, SS, lds, dw, coef, R0, ek, ssk, 2), IGEA_ENONFINITE);
        dw[M - 3] = 1e200; /* a residual of 1e200: its square overflows */
        assert_int_equal(igea_eqerr_residual_threads(layout, M, N, SS, lds, dw, coef, R0, ek, ssk, 2), IGEA_EOVERFLOW);
        assert_true(ek[0] == -1.0 && ek[M - 1] == -1.0);
        assert_memory_equal(ssk, ss0, sizeof ss0);
        /* without the sums only a residual beyond the double range fails,
         * as in igea_eqerr_residual */
        assert_int_equal(igea_eqerr_residual_threads(layout, M, N, SS, lds, dw, coef, R0, ek, NULL, 2), 0);
        assert_int_equal(igea_eqerr_residual(layout, M, N, SS, lds, dw, coef, R0, e1, NULL), 0);
        assert_true(ek[M - 3] == e1[M - 3] && ek[M - 3] > 9e199);
        assert_memory_equal(ek, e, sizeof(double) * (M - 3));
        dw[M - 3] = 0.3 * sin(0.01 * (M - 3));
        assert_int_equal(igea_eqerr_residual_threads(layout, M, N, SS, lds, dw, coef, R0, ek, ssk, -1), -11);
        assert_int_equal(igea_eqerr_residual_threads(layout, M, N, SS, lds, dw, coef, R0, ek, ssk, IGEA_NORMAL_THREADS_MAX + 1), -11);
        assert_int_equal(igea_eqerr_residual_threads(layout, M, N, SS, lds, dw, coef, -1, ek, ssk, 2), -8);
        assert_int_equal(igea_eqerr_residual_threads(layout, M, N, SS, lds, dw, coef, -1, ek, ssk, -1), -8);
        assert_int_equal(igea_eqerr_residual_threads(layout, 0, N, SS, lds, dw, coef, R0, ek, ssk, 2), 0);
    }
    assert_int_equal(igea_eqerr_residual_threads(7, M, N, S, M, dw, coef, R0, e, NULL, 2), -1);
    free(S); free(Sr); free(dw); free(e); free(e1); free(ek);
}

static void test_run_layout(void **state)
{
    (void)state;
    enum { ML = 40000, NL = 6 };
    double *S = malloc(sizeof(double) * ML * NL), *Sr = malloc(sizeof(double) * ML * NL);
    double *dw = malloc(sizeof(double) * ML), *r1 = malloc(sizeof(double) * ML);
    double *r2 = malloc(sizeof(double) * ML), sig = 0.02, spec[NL];
    assert_non_null(S && Sr && dw && r1 && r2);
    for (int j = 0; j < NL; j++)
        spec[j] = 0.5 + 0.3 * j;
    for (int i = 0; i < ML; i++) {
        double t = (double)(i / 3) / (ML / 3);
        dw[i] = 0.02 * sin(1e3 * i);
        for (int j = 0; j < NL; j++) {
            double v = cos((j + 1) * t + j) * pow(t, j % 3) + 1e-3 * sin(7.0 * i + j);
            S[i + (size_t)j * ML] = Sr[(size_t)i * NL + j] = v;
            dw[i] += v * spec[j] * (j % 2 ? 1 : -1);
        }
    }
    double opts[IGEA_EQERR_OPT_LEN], lam[2][NL], P[2][NL * NL], xh[2][NL], z[2][NL];
    double info[2][IGEA_STATS_INFO_LEN], rms[2][3];
    int rej[2][NL];
    igea_eqerr_defaults(opts);
    for (int route = 0; route < 2; route++)
        for (int th = 1; th <= 3; th += 2) {
            opts[IGEA_EQERR_OPT_ROUTE] = route;
            opts[IGEA_EQERR_OPT_THREADS] = th;
            assert_int_equal(igea_eqerr_run(ML, NL, S, ML, dw, &sig, 0, spec, opts, lam[0], P[0],
                                            NL, xh[0], z[0], rej[0], info[0], r1, rms[0]), 0);
            assert_int_equal(igea_eqerr_run_layout(IGEA_COLMAJOR, ML, NL, S, ML, dw, &sig, 0, spec,
                                                   opts, lam[1], P[1], NL, xh[1], z[1], rej[1],
                                                   info[1], r2, rms[1]), 0);
            assert_memory_equal(lam[0], lam[1], sizeof lam[0]);
            assert_memory_equal(info[0], info[1], sizeof info[0]);
            assert_memory_equal(r1, r2, sizeof(double) * ML);
            assert_int_equal(igea_eqerr_run_layout(IGEA_ROWMAJOR, ML, NL, Sr, NL, dw, &sig, 0, spec,
                                                   opts, lam[1], P[1], NL, xh[1], z[1], rej[1],
                                                   info[1], r2, rms[1]), 0);
            for (int k = 0; k < NL; k++) {
                assert_close(lam[1][k], lam[0][k], 1e-9 * lam[0][0] / lam[0][k]);
                assert_close_abs(z[1][k], z[0][k], 1e-6, 1e-6);
            }
            assert_close(info[1][IGEA_STATS_INFO_CHI2], info[0][IGEA_STATS_INFO_CHI2], 1e-6);
            for (int i = 0; i < ML; i += 997)
                assert_close_abs(r2[i], r1[i], 1e-9, 1e-12);
            for (int a = 0; a < 3; a++)
                assert_close(rms[1][a], rms[0][a], 1e-9);
        }
    opts[IGEA_EQERR_OPT_THREADS] = 1;
    assert_int_equal(igea_eqerr_run_layout(7, ML, NL, Sr, NL, dw, &sig, 0, spec, opts, lam[1],
                                           P[1], NL, xh[1], z[1], rej[1], info[1], r2, rms[1]),
                     -1);
    assert_int_equal(igea_eqerr_run_layout(IGEA_ROWMAJOR, 0, NL, Sr, NL, dw, &sig, 0, spec, opts,
                                           lam[1], P[1], NL, xh[1], z[1], rej[1], info[1], r2,
                                           rms[1]),
                     -2);
    assert_int_equal(igea_eqerr_run_layout(IGEA_ROWMAJOR, ML, NL, Sr, NL - 1, dw, &sig, 0, spec,
                                           opts, lam[1], P[1], NL, xh[1], z[1], rej[1], info[1],
                                           r2, rms[1]),
                     -5);
    assert_int_equal(igea_eqerr_run_layout(IGEA_COLMAJOR, ML, NL, S, NL, dw, &sig, 0, spec, opts,
                                           lam[1], P[1], NL, xh[1], z[1], rej[1], info[1], r2,
                                           rms[1]),
                     -5);
    assert_int_equal(igea_eqerr_run_layout(IGEA_ROWMAJOR, ML, NL, Sr, NL, dw, &sig, 0, spec, opts,
                                           lam[1], P[1], NL, xh[1], z[1], rej[1], NULL, r2, rms[1]),
                     -17);
    Sr[(size_t)(ML - 5) * NL + 2] = NAN; /* in the last segment */
    opts[IGEA_EQERR_OPT_THREADS] = 3;
    assert_int_equal(igea_eqerr_run_layout(IGEA_ROWMAJOR, ML, NL, Sr, NL, dw, &sig, 0, spec, opts,
                                           lam[1], P[1], NL, xh[1], z[1], rej[1], info[1], r2,
                                           rms[1]),
                     IGEA_ENONFINITE);
    free(S), free(Sr), free(dw), free(r1), free(r2);
}

/* Components of a rotation: p_0 = (0.6, 0.8, 0), p_1 = (0.8, -0.6, 0):
 * shares 0.36, 0.64, 0; loadings spec_j p_ij. */
static void test_components_closed_form(void **state)
{
    (void)state;
    double P[9] = {0.6, 0.8, 0, 0.8, -0.6, 0, 0, 0, 1}, spec[3] = {2, 0.5, 1};
    double share[6], load[6];
    int order[6];
    assert_int_equal(igea_eqerr_components(3, P, 3, 2, spec, share, load, order), 0);
    assert_close(share[0], 0.36, 1e-15);
    assert_close(share[1], 0.64, 1e-15);
    assert_true(share[2] == 0.0);
    assert_close(share[3], 0.64, 1e-15);
    assert_close(load[0], 1.2, 1e-15);
    assert_close(load[1], 0.4, 1e-15);
    assert_close(load[4], -0.3, 1e-15);
    assert_int_equal(order[0], 1);
    assert_int_equal(order[1], 0);
    assert_int_equal(order[2], 2);
    assert_int_equal(order[3], 0);
    assert_int_equal(order[4], 1);
    assert_int_equal(igea_eqerr_components(3, P, 3, 2, NULL, share, NULL, NULL), 0);
    spec[1] = 0;
    share[0] = -1;
    assert_int_equal(igea_eqerr_components(3, P, 3, 2, spec, share, load, order),
                     IGEA_ENONPOSITIVE);
    assert_true(share[0] == -1);
    assert_int_equal(igea_eqerr_components(3, P, 3, 4, NULL, share, NULL, NULL), -4);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_methods_vector_both_routes),
        cmocka_unit_test(test_streamed_equals_run),
        cmocka_unit_test(test_sigmaw_iteration),
        cmocka_unit_test(test_sigmaw_clamp_and_converged_first),
        cmocka_unit_test(test_rank_deficient),
        cmocka_unit_test(test_not_testable_and_invalid),
        cmocka_unit_test(test_padding_and_residual_args),
        cmocka_unit_test(test_svd_route_resolves_small_eigenvalues),
        cmocka_unit_test(test_solve_qr_args),
        cmocka_unit_test(test_overflow_is_not_nonfinite),
        cmocka_unit_test(test_sigma_range),
        cmocka_unit_test(test_check_opts_and_names),
        cmocka_unit_test(test_verdict_rules),
        cmocka_unit_test(test_verdict_limits_and_cache),
        cmocka_unit_test(test_pool_rule),
        cmocka_unit_test(test_limits_and_rms),
        cmocka_unit_test(test_diag_closed_form),
        cmocka_unit_test(test_eqerr_diag_streamed),
        cmocka_unit_test(test_axis_sums_statuses),
        cmocka_unit_test(test_accumulate_one_pass),
        cmocka_unit_test(test_run_layout),
        cmocka_unit_test(test_residual_threads),
        cmocka_unit_test(test_components_closed_form),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
