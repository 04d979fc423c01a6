/* tests/test_accel_ieee.c - the IEEE Std 1293 model (least squares and the
 * harmonic method) and the D-criterion of a schedule.
 * References: noise-free synthetic readings of the model written here with
 * known coefficients; closed-form variance factors of the harmonic
 * estimates (Var B0 = sigma^2 / N, Var S_k = Var C_k = 2 sigma^2 / N for
 * N >= 7 equispaced positions, docs/accel.md); the single model's
 * information per reading for equispaced N >= 5 (averages of sin^a cos^b,
 * a + b <= 4: <s^2> = 1/2, <s^4> = 3/8, <s^2 c^2> = 1/8), det 1/256; the
 * dual model's A^T A eigenvalues for 20 positions (METHODS 4.2). */
#include "testutil.h"

#include "igea/accel.h"

#define DEG (3.14159265358979323846 / 180.0)

/* K0 K1 K2 K3 Kip Kio delta_o delta_p: mg bias, 2.5 V/g, 30 ug/g^2 ... */
static const double Ktrue[8] = {2e-4, 2.5, 3e-5, -4e-6, 1e-5, -2e-5, 5e-5, -3e-5};

/* The model, written from its definition (accel.h). */
static double model_e(const double *K, double deg, int plane)
{
    double ai = sin(deg * DEG), x = cos(deg * DEG);
    double ap = plane == IGEA_ACCEL_PLANE_IAPA ? x : 0.0;
    double ao = plane == IGEA_ACCEL_PLANE_IAOA ? x : 0.0;
    return K[1] * (K[0] + ai + K[2] * ai * ai + K[3] * ai * ai * ai + K[4] * ai * ap +
                   K[5] * ai * ao + K[6] * ap - K[7] * ao);
}

/* N positions per plane: IA-PA from 0, IA-OA from start2. */
static int two_planes(int N, double start2, double *th, int *pl, double *e, const double *K)
{
    igea_accel_schedule(N, 0.0, th);
    igea_accel_schedule(N, start2, th + N);
    for (int i = 0; i < 2 * N; i++) {
        pl[i] = i < N ? IGEA_ACCEL_PLANE_IAPA : IGEA_ACCEL_PLANE_IAOA;
        e[i] = model_e(K, th[i], pl[i]);
    }
    return 2 * N;
}

static void test_ieee_noise_free(void **state)
{
    (void)state;
    double th[40], e[40], coef[8], sd[8], info[IGEA_ACCEL_INFO_LEN];
    int pl[40], flag[8];
    int n = two_planes(12, 7.5, th, pl, e, Ktrue);
    for (int m = 0; m < 2; m++) {
        int method = m ? IGEA_ACCEL_HARMONIC : IGEA_ACCEL_LS;
        assert_int_equal(igea_accel_ieee_fit(method, n, th, pl, e, coef, sd, NULL, 1, flag,
                                             info), 0);
        for (int j = 0; j < 8; j++) {
            /* absolute in g (rad) of the normalised output, 1e-13 */
            assert_close_abs(coef[j], Ktrue[j], 0, j == 1 ? 1e-12 : 1e-13);
            assert_int_equal(flag[j], IGEA_ACCEL_DATA);
        }
        assert_int_equal((int)info[IGEA_ACCEL_INFO_RANK], 8);
        assert_int_equal((int)info[IGEA_ACCEL_INFO_DOF], n - 8);
        assert_true(info[IGEA_ACCEL_INFO_SIGMA] < 1e-14);
    }
    /* an odd, unequal split: 7 positions in IA-PA, 9 in IA-OA from 10 deg */
    igea_accel_schedule(7, 0.0, th);
    igea_accel_schedule(9, 10.0, th + 7);
    for (int i = 0; i < 16; i++) {
        pl[i] = i < 7 ? 0 : 1;
        e[i] = model_e(Ktrue, th[i], pl[i]);
    }
    for (int m = 0; m < 2; m++) {
        assert_int_equal(igea_accel_ieee_fit(m ? IGEA_ACCEL_HARMONIC : IGEA_ACCEL_LS, 16, th,
                                             pl, e, coef, NULL, NULL, 1, NULL, NULL), 0);
        for (int j = 0; j < 8; j++)
            assert_close_abs(coef[j], Ktrue[j], 0, 1e-12);
    }
}

/* With noise, equispaced planes: the harmonic estimates are the LS ones,
 * and both report sd = sigma_hat sqrt(closed-form variance factor / n). */
static void test_ieee_harmonic_is_ls(void **state)
{
    (void)state;
    double th[48], e[48], c1[8], c2[8], s1[8], s2[8], i1[IGEA_ACCEL_INFO_LEN];
    double i2[IGEA_ACCEL_INFO_LEN], cov[64];
    int pl[48];
    int n = two_planes(24, 3.0, th, pl, e, Ktrue);
    unsigned long x = 12345;
    for (int i = 0; i < n; i++) { /* a deterministic +-1e-6 pattern */
        x = x * 6364136223846793005UL + 1442695040888963407UL;
        e[i] += 1e-6 * ((double)(x >> 11) / 9007199254740992.0 - 0.5);
    }
    assert_int_equal(igea_accel_ieee_fit(IGEA_ACCEL_LS, n, th, pl, e, c1, s1, cov, 8, NULL,
                                         i1), 0);
    assert_int_equal(igea_accel_ieee_fit(IGEA_ACCEL_HARMONIC, n, th, pl, e, c2, s2, NULL, 1,
                                         NULL, i2), 0);
    /* var factors per reading of b (n = 2N readings): b0 = B0 + C2: 1 + 2;
     * b1 = S1 + 3 S3: 2 + 18; b2 = -2 C2: 8; b3 = -4 S3: 32; Kip, Kio =
     * 2 S2 of one plane (2 / N = 4 / n): 16; delta = C1 of one plane: 4.
     * K_j = b_j / K1: divide the sd by K1 (to first order). */
    const double vf[8] = {3, 20, 8, 32, 16, 16, 4, 4};
    assert_close(i1[IGEA_ACCEL_INFO_SIGMA], i2[IGEA_ACCEL_INFO_SIGMA], 1e-10);
    for (int j = 0; j < 8; j++) {
        assert_close_abs(c2[j], c1[j], 1e-12, 1e-15);
        assert_close(s2[j], s1[j], 1e-9);
        double want = i1[IGEA_ACCEL_INFO_SIGMA] * sqrt(vf[j] / n) / (j == 1 ? 1.0 : Ktrue[1]);
        assert_close(s1[j], want, 1e-3);
        assert_close(sqrt(cov[j + 8 * j]), s1[j], 1e-12);
    }
}

/* Identifiability: one plane leaves Kio and delta_p undetermined; six
 * equispaced positions confound K1 with K3 (sin 3 theta = 0 there, so
 * s^3 = 3 s / 4: only K1 (1 + 3 K3 / 4) is determined). */
static void test_ieee_identifiability(void **state)
{
    (void)state;
    double th[20], e[20], coef[8], sd[8], info[IGEA_ACCEL_INFO_LEN];
    int pl[20] = {0}, flag[8];
    igea_accel_schedule(12, 0.0, th);
    for (int i = 0; i < 12; i++)
        e[i] = model_e(Ktrue, th[i], 0);
    assert_int_equal(igea_accel_ieee_fit(IGEA_ACCEL_LS, 12, th, pl, e, coef, sd, NULL, 1, flag,
                                         info), 0);
    const int want1[8] = {0, 0, 0, 0, 0, 1, 0, 1};
    for (int j = 0; j < 8; j++)
        assert_int_equal(flag[j], want1[j] ? IGEA_ACCEL_PRIOR : IGEA_ACCEL_DATA);
    assert_int_equal((int)info[IGEA_ACCEL_INFO_RANK], 6);
    assert_true(coef[IGEA_ACCEL_IEEE_KIO] == 0.0 && coef[IGEA_ACCEL_IEEE_DP] == 0.0);
    assert_close_abs(coef[IGEA_ACCEL_IEEE_KIP], Ktrue[4], 0, 1e-13);

    igea_accel_schedule(6, 0.0, th);
    for (int i = 0; i < 6; i++)
        e[i] = model_e(Ktrue, th[i], 0);
    int rank;
    double ld, vf[8];
    assert_int_equal(igea_accel_criterion(IGEA_ACCEL_IEEE, IGEA_ACCEL_LS, 6, th, pl, 0.0, &ld,
                                          vf, flag, &rank), 0);
    assert_int_equal(rank, 5);
    const int want2[8] = {0, 1, 0, 1, 0, 1, 0, 1};
    for (int j = 0; j < 8; j++)
        assert_int_equal(flag[j], want2[j] ? IGEA_ACCEL_PRIOR : IGEA_ACCEL_DATA);
    /* the fit (6 readings, rank 5): K1 (1 + 3 K3 / 4) is what the data hold */
    assert_int_equal(igea_accel_ieee_fit(IGEA_ACCEL_LS, 6, th, pl, e, coef, NULL, NULL, 1, flag,
                                         NULL), 0);
    assert_close(coef[1] * (1 + 0.75 * coef[3]), Ktrue[1] * (1 + 0.75 * Ktrue[3]), 1e-13);
    /* the harmonic method refuses N < 7 and unequal spacing */
    assert_int_equal(igea_accel_ieee_fit(IGEA_ACCEL_HARMONIC, 6, th, pl, e, coef, NULL, NULL, 1,
                                         NULL, NULL), IGEA_EDOMAIN);
    igea_accel_schedule(8, 0.0, th);
    th[3] += 1.0;
    for (int i = 0; i < 8; i++)
        e[i] = model_e(Ktrue, th[i], 0);
    assert_int_equal(igea_accel_ieee_fit(IGEA_ACCEL_HARMONIC, 8, th, pl, e, coef, NULL, NULL, 1,
                                         NULL, NULL), IGEA_EDOMAIN);
    assert_int_equal(igea_accel_ieee_fit(IGEA_ACCEL_LS, 8, th, pl, e, coef, NULL, NULL, 1, NULL,
                                         NULL), 0);
}

static void test_ieee_invalid(void **state)
{
    (void)state;
    double th[8], e[8], coef[8], sd[8], cov[64];
    int pl[8] = {0}, flag[8];
    igea_accel_schedule(8, 0.0, th);
    for (int i = 0; i < 8; i++)
        e[i] = model_e(Ktrue, th[i], 0);
    fill_sentinel(coef, 8);
    fill_sentinel(sd, 8);
    assert_int_equal(igea_accel_ieee_fit(7, 8, th, pl, e, coef, sd, NULL, 1, flag, NULL), -1);
    assert_int_equal(igea_accel_ieee_fit(0, 0, th, pl, e, coef, sd, NULL, 1, flag, NULL), -2);
    assert_int_equal(igea_accel_ieee_fit(0, 8, NULL, pl, e, coef, sd, NULL, 1, flag, NULL), -3);
    assert_int_equal(igea_accel_ieee_fit(0, 8, th, NULL, e, coef, sd, NULL, 1, flag, NULL), -4);
    pl[2] = 2;
    assert_int_equal(igea_accel_ieee_fit(0, 8, th, pl, e, coef, sd, NULL, 1, flag, NULL), -4);
    pl[2] = 0;
    assert_int_equal(igea_accel_ieee_fit(0, 8, th, pl, NULL, coef, sd, NULL, 1, flag, NULL), -5);
    assert_int_equal(igea_accel_ieee_fit(0, 8, th, pl, e, NULL, sd, NULL, 1, flag, NULL), -6);
    assert_int_equal(igea_accel_ieee_fit(0, 8, th, pl, e, coef, sd, cov, 7, flag, NULL), -9);
    assert_int_equal(igea_accel_ieee_fit(0, 8, th, pl, e, coef, sd, NULL, 0, flag, NULL), -9);
    e[4] = NAN;
    assert_int_equal(igea_accel_ieee_fit(0, 8, th, pl, e, coef, sd, NULL, 1, flag, NULL),
                     IGEA_ENONFINITE);
    e[4] = 0.0;
    th[1] = INFINITY;
    assert_int_equal(igea_accel_ieee_fit(0, 8, th, pl, e, coef, sd, NULL, 1, flag, NULL),
                     IGEA_ENONFINITE);
    igea_accel_schedule(8, 0.0, th);
    for (int i = 0; i < 8; i++) /* all outputs 0: K1 estimated as 0 */
        e[i] = 0.0;
    assert_int_equal(igea_accel_ieee_fit(0, 8, th, pl, e, coef, sd, NULL, 1, flag, NULL),
                     IGEA_EDOMAIN);
    assert_true(all_sentinel(coef, 8) && all_sentinel(sd, 8));
    /* no residual: sds NaN (documented), coefficients finite */
    for (int i = 0; i < 8; i++)
        e[i] = model_e(Ktrue, th[i], 0);
    int pl6[6] = {0};
    double th6[6] = {0, 45, 90, 180, 225, 300};
    assert_int_equal(igea_accel_ieee_fit(0, 6, th6, pl6, e, coef, sd, NULL, 1, flag, NULL), 0);
    assert_true(isnan(sd[0]) && isfinite(coef[0]));
}

/* Single model: every equispaced N >= 5, from any start angle, has M / n =
 * [[1,0,0,1/2,0],[0,1/2,0,0,0],[0,0,1/2,0,0],[1/2,0,0,3/8,0],
 * [0,0,0,0,1/8]]: det 1/256, inverse diagonal (3, 2, 2, 8, 8). */
static void test_criterion_single_equispaced(void **state)
{
    (void)state;
    double th[64], ld, vf[5];
    int flag[5], rank;
    const double vfw[5] = {3, 2, 2, 8, 8};
    for (int N = 5; N <= 64; N += 1 + N / 8) {
        for (int k = 0; k < 3; k++) {
            igea_accel_schedule(N, 17.0 * k, th);
            assert_int_equal(igea_accel_criterion(IGEA_ACCEL_SINGLE, IGEA_ACCEL_LS, N, th, NULL,
                                                  0.0, &ld, vf, flag, &rank), 0);
            assert_int_equal(rank, 5);
            assert_close(ld, log(1.0 / 256.0) / 5.0, 1e-12);
            for (int j = 0; j < 5; j++) {
                assert_close(vf[j], vfw[j], 1e-11);
                assert_int_equal(flag[j], IGEA_ACCEL_DATA);
            }
        }
    }
    /* N = 4 (multiples of 90 deg): the s c column vanishes, rank 4, Kix
     * not determined */
    igea_accel_schedule(4, 0.0, th);
    assert_int_equal(igea_accel_criterion(IGEA_ACCEL_SINGLE, IGEA_ACCEL_LS, 4, th, NULL, 0.0,
                                          &ld, vf, flag, &rank), 0);
    assert_int_equal(rank, 4);
    assert_int_equal(flag[IGEA_ACCEL_KIX], IGEA_ACCEL_PRIOR);
    /* an unequal schedule (positions crowded in one half) has a lower det */
    for (int i = 0; i < 10; i++)
        th[i] = 18.0 * i;
    assert_int_equal(igea_accel_criterion(IGEA_ACCEL_SINGLE, IGEA_ACCEL_LS, 10, th, NULL, 0.0,
                                          &ld, vf, flag, &rank), 0);
    assert_true(ld < log(1.0 / 256.0) / 5.0 - 0.1);
}

/* Dual model, 20 positions: rank 7, the nonzero eigenvalues of A^T A are
 * (17.5 +- sqrt(231.25))/2 (twice each), 10, 5, 2.5 (METHODS 4.2). */
static void test_criterion_dual(void **state)
{
    (void)state;
    double th[20], ld, vf[10];
    int flag[10], rank;
    igea_accel_schedule(20, 0.0, th);
    assert_int_equal(igea_accel_criterion(IGEA_ACCEL_DUAL, IGEA_ACCEL_EBR, 20, th, NULL, 0.0,
                                          &ld, vf, flag, &rank), 0);
    assert_int_equal(rank, 7);
    double r = sqrt(231.25), want = 0.0;
    const double lam[7] = {(17.5 + r) / 2, (17.5 + r) / 2, (17.5 - r) / 2, (17.5 - r) / 2, 10,
                           5, 2.5};
    for (int i = 0; i < 7; i++)
        want += log(lam[i] / 20.0);
    assert_close(ld, want / 7.0, 1e-12);
    assert_int_equal(flag[IGEA_ACCEL_KA1], IGEA_ACCEL_DATA);
    assert_int_equal(flag[IGEA_ACCEL_KA2], IGEA_ACCEL_PRIOR);
    /* joint: rank 10, every coefficient determined; a larger head error
     * lowers the information */
    double ld1, ld2;
    assert_int_equal(igea_accel_criterion(IGEA_ACCEL_DUAL, IGEA_ACCEL_JOINT, 20, th, NULL, 1.0,
                                          &ld1, vf, flag, &rank), 0);
    assert_int_equal(rank, 10);
    for (int j = 0; j < 10; j++)
        assert_int_equal(flag[j], IGEA_ACCEL_DATA);
    assert_int_equal(igea_accel_criterion(IGEA_ACCEL_DUAL, IGEA_ACCEL_JOINT, 20, th, NULL, 5.0,
                                          &ld2, vf, flag, &rank), 0);
    assert_true(ld2 < ld1);
}

static void test_criterion_invalid(void **state)
{
    (void)state;
    double th[8], ld = SENTINEL, vf[8];
    int pl[8] = {0}, flag[8], rank = -7;
    igea_accel_schedule(8, 0.0, th);
    fill_sentinel(vf, 8);
    assert_int_equal(igea_accel_criterion(5, 0, 8, th, pl, 0, &ld, vf, flag, &rank), -1);
    assert_int_equal(igea_accel_criterion(IGEA_ACCEL_SINGLE, IGEA_ACCEL_JOINT, 8, th, pl, 0,
                                          &ld, vf, flag, &rank), -2);
    assert_int_equal(igea_accel_criterion(IGEA_ACCEL_DUAL, IGEA_ACCEL_HARMONIC, 8, th, pl, 0,
                                          &ld, vf, flag, &rank), -2);
    assert_int_equal(igea_accel_criterion(0, 0, 0, th, pl, 0, &ld, vf, flag, &rank), -3);
    assert_int_equal(igea_accel_criterion(0, 0, 8, NULL, pl, 0, &ld, vf, flag, &rank), -4);
    assert_int_equal(igea_accel_criterion(IGEA_ACCEL_IEEE, 0, 8, th, NULL, 0, &ld, vf, flag,
                                          &rank), -5);
    pl[3] = -1;
    assert_int_equal(igea_accel_criterion(IGEA_ACCEL_IEEE, 0, 8, th, pl, 0, &ld, vf, flag,
                                          &rank), -5);
    assert_int_equal(igea_accel_criterion(IGEA_ACCEL_DUAL, IGEA_ACCEL_JOINT, 8, th, NULL, -1,
                                          &ld, vf, flag, &rank), -6);
    assert_int_equal(igea_accel_criterion(IGEA_ACCEL_DUAL, IGEA_ACCEL_JOINT, 8, th, NULL, NAN,
                                          &ld, vf, flag, &rank), -6);
    assert_int_equal(igea_accel_criterion(0, 0, 8, th, NULL, 0, NULL, vf, flag, &rank), -7);
    assert_int_equal(igea_accel_criterion(0, 0, 8, th, NULL, 0, &ld, vf, flag, NULL), -10);
    th[2] = NAN;
    assert_int_equal(igea_accel_criterion(0, 0, 8, th, NULL, 0, &ld, vf, flag, &rank),
                     IGEA_ENONFINITE);
    assert_true(ld == SENTINEL && rank == -7 && all_sentinel(vf, 8));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ieee_noise_free),
        cmocka_unit_test(test_ieee_harmonic_is_ls),
        cmocka_unit_test(test_ieee_identifiability),
        cmocka_unit_test(test_ieee_invalid),
        cmocka_unit_test(test_criterion_single_equispaced),
        cmocka_unit_test(test_criterion_dual),
        cmocka_unit_test(test_criterion_invalid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
