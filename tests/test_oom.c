/* Out-of-memory loop (as SQLite's): fail the 1st, 2nd, ... allocation made
 * inside a call until the call succeeds. Every failure must return
 * IGEA_ENOMEM with the outputs untouched, and the final success must give
 * the same results as an unconstrained call. The program's own malloc
 * replaces the C library's (glibc's __libc_malloc does the real work), so
 * the library's allocations can be failed one by one. Not built under
 * AddressSanitizer, which owns malloc itself. */
#include "testutil.h"

#include "igea.h"

#include "oom.h"

#ifndef OOM_DISABLED
enum { M = 30, N = 4 };
static double S[M * N], dw[M];

static void make(void)
{
    for (int i = 0; i < M; i++) {
        for (int j = 0; j < N; j++)
            S[i + j * M] = pow(0.1 * (i + 1), j) + 0.01 * sin(i + j);
        dw[i] = 0.3 * S[i] - 0.2 * S[i + M] + 0.05 * S[i + 2 * M] + 0.001 * cos(3.0 * i);
    }
}

static void oom_loop_run(int route, int nsig)
{
    make();
    double sig[M], opts[IGEA_EQERR_OPT_LEN];
    for (int i = 0; i < M; i++)
        sig[i] = nsig ? 0.001 * (1 + 0.01 * i) : 0.001;
    igea_eqerr_defaults(opts);
    opts[IGEA_EQERR_OPT_CORRECTION] = 0;
    opts[IGEA_EQERR_OPT_ROUTE] = route;
    double lam0[N], P0[N * N], x0[N], z0[N], info0[IGEA_STATS_INFO_LEN], res0[M], rms0[3];
    int rej0[N];
    assert_int_equal(igea_eqerr_run(M, N, S, M, dw, sig, 1, NULL, opts, lam0, P0, N, x0, z0, rej0,
                                    info0, res0, rms0), 0);
    int failures = 0;
    for (long k = 0; k < 1000; k++) {
        double lam[N], P[N * N], x[N], z[N], info[IGEA_STATS_INFO_LEN], res[M], rms[3];
        int rej[N];
        fill_sentinel(lam, N);
        fill_sentinel(P, N * N);
        fill_sentinel(info, IGEA_STATS_INFO_LEN);
        fill_sentinel(res, M);
        oom_calls = 0;
        oom_fail_at = k;
        int st = igea_eqerr_run(M, N, S, M, dw, sig, 1, NULL, opts, lam, P, N, x, z, rej, info, res, rms);
        oom_fail_at = -1;
        if (st == 0) {
            assert_true(oom_calls <= k); /* no allocation was failed */
            assert_memory_equal(lam, lam0, sizeof lam);
            assert_memory_equal(res, res0, sizeof res);
            break;
        }
        failures++;
        assert_int_equal(st, IGEA_ENOMEM);
        assert_true(all_sentinel(lam, N) && all_sentinel(P, N * N) &&
                    all_sentinel(info, IGEA_STATS_INFO_LEN) && all_sentinel(res, M));
    }
    assert_true(failures >= 2); /* the loop did fail allocations */
}

static void test_oom_eig(void **state) { oom_loop_run(IGEA_EQERR_ROUTE_EIG, 1); }
static void test_oom_eig_uniform(void **state) { oom_loop_run(IGEA_EQERR_ROUTE_EIG, 0); }
static void test_oom_svd(void **state) { oom_loop_run(IGEA_EQERR_ROUTE_SVD, 1); }

static void test_oom_normal(void **state)
{
    make();
    double s1 = 0.5, A[N * N], b[N], w[2];
    fill_sentinel(A, N * N);
    fill_sentinel(b, N);
    fill_sentinel(w, 2);
    oom_calls = 0;
    oom_fail_at = 0;
    int st = igea_normal_accumulate(IGEA_COLMAJOR, M, N, S, M, dw, &s1, 0, NULL, A, N, b, w);
    oom_fail_at = -1;
    assert_int_equal(st, IGEA_ENOMEM);
    assert_true(all_sentinel(A, N * N) && all_sentinel(b, N) && all_sentinel(w, 2));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_oom_eig),
        cmocka_unit_test(test_oom_eig_uniform),
        cmocka_unit_test(test_oom_svd),
        cmocka_unit_test(test_oom_normal),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
#else
int main(void)
{
    printf("test_oom: skipped under AddressSanitizer (it replaces malloc itself)\n");
    return 0;
}
#endif
