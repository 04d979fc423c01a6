/* tests/test_redund_group.c - virtual IMUs and Table 1: closed forms of
 * seed 002's grouping with ideal axes (the fused variances s^2/4, s^2/2,
 * s^2/2 and the independent-groups figure s^2/4), a group rotated by a
 * known angle, the block statistic of a fused channel of two sensors with
 * opposite noise (0 exactly); the refusals. */
#include "testutil.h"

#include "igea/redund.h"
#include "igea/stability.h"

/* seed 002: Ax1..Ax4 (0..3), Ay1 Ay2 (4 5), Az1 Az2 (6 7) */
static const int GROUPS[12] = {0, 4, 6, 1, 5, 7, 2, 4, 6, 3, 5, 7};

static void ideal_axes(double *ax)
{
    static const int dir[8] = {0, 0, 0, 0, 1, 1, 2, 2};
    for (int i = 0; i < 8; i++)
        for (int j = 0; j < 3; j++)
            ax[3 * i + j] = dir[i] == j ? 1.0 : 0.0;
}

static void test_seed002_closed_forms(void **s)
{
    (void)s;
    double ax[24], sg[8], y[8], fr[36], u[12], f[3], cov[9], ci[9];
    ideal_axes(ax);
    const double sd = 2e-5;
    for (int i = 0; i < 8; i++)
        sg[i] = sd, y[i] = 0.1 * (i + 1);
    for (int rule = 0; rule <= 2; rule++) {
        assert_int_equal(igea_redund_group(8, ax, sg, 4, GROUPS, y, rule, fr, u, f, cov, ci), 0);
        assert_close(cov[0], sd * sd / 4, 1e-12);
        assert_close(cov[4], sd * sd / 2, 1e-12);
        assert_close(cov[8], sd * sd / 2, 1e-12);
        if (rule != IGEA_REDUND_GROUP_GLS)
            assert_close(ci[4], sd * sd / 4, 1e-12);
        /* x: the mean of the four X readings; y: of Ay1, Ay2 */
        assert_close(f[0], 0.25, 1e-12);
        assert_close(f[1], 0.55, 1e-12);
        assert_close(f[2], 0.75, 1e-12);
        for (int g = 0; g < 4; g++)
            for (int k = 0; k < 9; k++)
                assert_close_abs(fr[9 * g + k], k % 4 == 0 ? 1.0 : 0.0, 0, 1e-15);
    }
}

/* Group 1's whole triad turned by 0.3 rad about z in the reference frame:
 * C_1 maps its frame back onto group 0's: the rotation by +0.3 about z
 * (column-major), and its output in the body frame equals group 0's for
 * the same specific force. */
static void test_rotated_group(void **s)
{
    (void)s;
    const double c = cos(0.3), sn = sin(0.3), fz[3] = {0.2, -0.4, 9.8};
    double ax[18] = {1, 0, 0, 0, 1, 0, 0, 0, 1, c, sn, 0, -sn, c, 0, 0, 0, 1};
    double sg[6] = {1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4}, y[6], fr[18], u[6], f[3], cov[9];
    int mem[6] = {0, 1, 2, 3, 4, 5};
    for (int i = 0; i < 6; i++)
        y[i] = ax[3 * i] * fz[0] + ax[3 * i + 1] * fz[1] + ax[3 * i + 2] * fz[2];
    assert_int_equal(igea_redund_group(6, ax, sg, 2, mem, y, 0, fr, u, f, cov, NULL), 0);
    const double want[9] = {c, sn, 0, -sn, c, 0, 0, 0, 1}; /* columns of Rz(0.3) */
    for (int k = 0; k < 9; k++)
        assert_close_abs(fr[9 + k], want[k], 0, 1e-15);
    for (int i = 0; i < 3; i++) {
        assert_close(u[3 + i], fz[i], 1e-13);
        assert_close(f[i], fz[i], 1e-13);
    }
}

static void test_group_refusals(void **s)
{
    (void)s;
    double ax[24], sg[8], y[8] = {0}, f[3], cov[9], f0[3] = {7, 7, 7};
    ideal_axes(ax);
    for (int i = 0; i < 8; i++)
        sg[i] = 1e-4;
    int bad[3] = {0, 0, 6};
    memcpy(f, f0, sizeof f);
    assert_int_equal(igea_redund_group(8, ax, sg, 1, bad, y, 0, NULL, NULL, f, cov, NULL), -5);
    int dep[3] = {0, 1, 4}; /* Ax1, Ax2 parallel */
    assert_int_equal(igea_redund_group(8, ax, sg, 1, dep, y, 0, NULL, NULL, f, cov, NULL),
                     IGEA_ESINGULAR);
    assert_int_equal(igea_redund_group(8, ax, sg, 4, GROUPS, y, 3, NULL, NULL, f, cov, NULL), -7);
    sg[3] = 0.0;
    assert_int_equal(igea_redund_group(8, ax, sg, 4, GROUPS, y, 0, NULL, NULL, f, cov, NULL),
                     IGEA_ENONPOSITIVE);
    assert_memory_equal(f, f0, sizeof f);
}

/* Two sensors of one channel with noise e and -e: the fused series is the
 * constant level, block sigma 0; each sensor's 3 sigma is 3 x the sd of
 * the block means of +-1 alternating blocks (computed here). */
static void test_stability_table(void **s)
{
    (void)s;
    enum { N = 400 };
    double y[2 * N], so[2 * IGEA_STABILITY_BLOCK_LEN], fo[IGEA_STABILITY_BLOCK_LEN], fs_[N];
    int ch[2] = {0, 0};
    for (int k = 0; k < N; k++) {
        double e = (k / 50) % 2 ? 1e-3 : -1e-3; /* 5-s blocks of 50 samples: means +-1e-3 */
        y[k] = 5.0 + e, y[N + k] = 5.0 - e;
    }
    assert_int_equal(igea_redund_stability(N, 2, y, N, 10.0, 5.0, ch, 1, 0, so, fo, fs_), 0);
    const double m2 = 8.0 * 1e-6 / 7.0; /* 8 block means +-1e-3: variance, ddof 1 */
    assert_close(so[IGEA_STABILITY_BLOCK_3SIGMA], 3.0 * sqrt(m2), 1e-12);
    assert_close_abs(fo[IGEA_STABILITY_BLOCK_SIGMA], 0.0, 0, 1e-12);
    assert_close(fs_[17], 5.0, 1e-15);
    int ch2[2] = {0, 2};
    assert_int_equal(igea_redund_stability(N, 2, y, N, 10.0, 5.0, ch2, 3, 0, so, fo, NULL), -8);
    assert_int_equal(igea_redund_stability(N, 2, y, N, 10.0, 30.0, ch, 1, 0, so, fo, NULL), -6);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_seed002_closed_forms),
        cmocka_unit_test(test_rotated_group),
        cmocka_unit_test(test_group_refusals),
        cmocka_unit_test(test_stability_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
