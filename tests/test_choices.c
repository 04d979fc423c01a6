/* Tests of igea_choice_name / igea_choice_code / igea_choice_codes: every
 * enumeration's names against its header macros (the pairs written here
 * from the headers), round trips, listing order and invalid arguments. */
#include <string.h>

#include "testutil.h"

#include "igea.h"

typedef struct {
    int kind, code;
    const char *name;
} pair;

/* Every macro of every enumeration, in listing order within a kind. */
static const pair expected[] = {
    {IGEA_CHOICE_EQERR_ROUTE, IGEA_EQERR_ROUTE_EIG, "eig"},
    {IGEA_CHOICE_EQERR_ROUTE, IGEA_EQERR_ROUTE_SVD, "svd"},
    {IGEA_CHOICE_REGRESS_RIDGE_RULE, IGEA_REGRESS_RIDGE_FIXED, "fixed"},
    {IGEA_CHOICE_REGRESS_RIDGE_RULE, IGEA_REGRESS_RIDGE_HKB, "hkb"},
    {IGEA_CHOICE_REGRESS_RIDGE_RULE, IGEA_REGRESS_RIDGE_LW, "lw"},
    {IGEA_CHOICE_REGRESS_RIDGE_RULE, IGEA_REGRESS_RIDGE_GCV, "gcv"},
    {IGEA_CHOICE_REGRESS_RIDGE_RULE, IGEA_REGRESS_RIDGE_LOO, "loo"},
    {IGEA_CHOICE_REGRESS_EBR_RULE, IGEA_REGRESS_EBR_SC, "sc"},
    {IGEA_CHOICE_REGRESS_EBR_RULE, IGEA_REGRESS_EBR_MM, "mm"},
    {IGEA_CHOICE_REGRESS_EBR_RULE, IGEA_REGRESS_EBR_ML2, "ml2"},
    {IGEA_CHOICE_ACCEL_MODEL, IGEA_ACCEL_SINGLE, "single"},
    {IGEA_CHOICE_ACCEL_MODEL, IGEA_ACCEL_DUAL, "dual"},
    {IGEA_CHOICE_ACCEL_METHOD, IGEA_ACCEL_LS, "ls"},
    {IGEA_CHOICE_ACCEL_METHOD, IGEA_ACCEL_EBR, "ebr"},
    {IGEA_CHOICE_ACCEL_METHOD, IGEA_ACCEL_JOINT, "joint"},
    {IGEA_CHOICE_ENVFUN_SYSTEM, IGEA_ENVFUN_STRAPDOWN, "strapdown"},
    {IGEA_CHOICE_ENVFUN_SYSTEM, IGEA_ENVFUN_PLATFORM, "platform"},
    {IGEA_CHOICE_ENVFUN_OUTPUT, IGEA_ENVFUN_VELOCITY, "velocity"},
    {IGEA_CHOICE_ENVFUN_OUTPUT, IGEA_ENVFUN_POSITION, "position"},
    {IGEA_CHOICE_ENVFUN_OUTPUT, IGEA_ENVFUN_VELOCITY_G, "velocity_g"},
    {IGEA_CHOICE_ENVFUN_OUTPUT, IGEA_ENVFUN_POSITION_G, "position_g"},
    {IGEA_CHOICE_SIM_GENERATOR, IGEA_SIM_MT19937, "mt19937"},
    {IGEA_CHOICE_SIM_GENERATOR, IGEA_SIM_RANLXD2, "ranlxd2"},
    {IGEA_CHOICE_SIM_GENERATOR, IGEA_SIM_XOSHIRO, "xoshiro"},
    {IGEA_CHOICE_RLS_VARIANT, IGEA_RLS_STANDARD, "standard"},
    {IGEA_CHOICE_RLS_VARIANT, IGEA_RLS_ITERATED, "iterated"},
    {IGEA_CHOICE_RLS_VARIANT, IGEA_RLS_POLYNOMIAL, "polynomial"},
    {IGEA_CHOICE_RLS_ANOMALY, IGEA_RLS_ANOMALY_NONE, "none"},
    {IGEA_CHOICE_RLS_ANOMALY, IGEA_RLS_ANOMALY_REPLACE, "replace"},
    {IGEA_CHOICE_RLS_ANOMALY, IGEA_RLS_ANOMALY_SKIP, "skip"},
    {IGEA_CHOICE_RLS_ANOMALY, IGEA_RLS_ANOMALY_ISOLATE, "isolate"},
    {IGEA_CHOICE_RLS_ACTION, IGEA_RLS_UPDATED, "updated"},
    {IGEA_CHOICE_RLS_ACTION, IGEA_RLS_FLAGGED, "flagged"},
    {IGEA_CHOICE_RLS_ACTION, IGEA_RLS_REPLACED, "replaced"},
    {IGEA_CHOICE_RLS_ACTION, IGEA_RLS_SKIPPED, "skipped"},
    {IGEA_CHOICE_RLS_ACTION, IGEA_RLS_ISOLATED, "isolated"},
    {IGEA_CHOICE_RLS_FLAG, IGEA_RLS_FLAG_INNOVATION, "innovation"},
    {IGEA_CHOICE_RLS_FLAG, IGEA_RLS_FLAG_JUMP, "jump"},
    {IGEA_CHOICE_RLS_FLAG, IGEA_RLS_FLAG_MISSING, "missing"},
    {IGEA_CHOICE_RLS_FLAG, IGEA_RLS_FLAG_UNUSED, "unused"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_OVERLAPPING, "overlapping"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_MODIFIED, "modified"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_NONOVERLAPPING, "nonoverlapping"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_ADEV, "adev"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_OADEV, "oadev"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_MDEV, "mdev"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_TDEV, "tdev"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_HDEV, "hdev"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_OHDEV, "ohdev"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_TOTDEV, "totdev"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_MTOTDEV, "mtotdev"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_TTOTDEV, "ttotdev"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_HTOTDEV, "htotdev"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_THEO1, "theo1"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_MTIE, "mtie"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_TIERMS, "tierms"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_THEOBR, "theobr"},
    {IGEA_CHOICE_STABILITY_KIND, IGEA_STABILITY_ALLAN_THEOH, "theoh"},
    {IGEA_CHOICE_STABILITY_NOISE, IGEA_STABILITY_NOISE_RWFM, "rwfm"},
    {IGEA_CHOICE_STABILITY_NOISE, IGEA_STABILITY_NOISE_FFM, "ffm"},
    {IGEA_CHOICE_STABILITY_NOISE, IGEA_STABILITY_NOISE_WFM, "wfm"},
    {IGEA_CHOICE_STABILITY_NOISE, IGEA_STABILITY_NOISE_FPM, "fpm"},
    {IGEA_CHOICE_STABILITY_NOISE, IGEA_STABILITY_NOISE_WPM, "wpm"},
    {IGEA_CHOICE_STABILITY_NOISE, IGEA_STABILITY_NOISE_AUTO, "auto"},
    {IGEA_CHOICE_STATS_SIGMAW_FLAG, IGEA_STATS_SIGMAW_CONVERGED, "converged"},
    {IGEA_CHOICE_STATS_SIGMAW_FLAG, IGEA_STATS_SIGMAW_NOT_ESTIMABLE, "not_estimable"},
    {IGEA_CHOICE_STATS_SIGMAW_FLAG, IGEA_STATS_SIGMAW_NO_CONVERGENCE, "no_convergence"},
    {IGEA_CHOICE_STATS_SIGMAW_FLAG, IGEA_STATS_SIGMAW_OFF, "off"},
    {IGEA_CHOICE_REDUND_RBD, IGEA_REDUND_RBD_SERIES, "series"},
    {IGEA_CHOICE_REDUND_RBD, IGEA_REDUND_RBD_PARALLEL, "parallel"},
    {IGEA_CHOICE_REDUND_RBD, IGEA_REDUND_RBD_KOFN, "kofn"},
    {IGEA_CHOICE_STATS_VERDICT, IGEA_STATS_VERDICT_SEED, "seed"},
    {IGEA_CHOICE_STATS_VERDICT, IGEA_STATS_VERDICT_CHI2, "chi2"},
    {IGEA_CHOICE_STATS_VERDICT, IGEA_STATS_VERDICT_EXACT, "exact"},
    {IGEA_CHOICE_STATS_VERDICT, IGEA_STATS_VERDICT_SIDAK, "sidak"},
    {IGEA_CHOICE_NOISE_AR_METHOD, IGEA_NOISE_AR_REML, "reml"},
    {IGEA_CHOICE_NOISE_AR_METHOD, IGEA_NOISE_AR_LS, "ls"},
    {IGEA_CHOICE_REGRESS_METHOD, IGEA_REGRESS_METHOD_LS, "ls"},
    {IGEA_CHOICE_REGRESS_METHOD, IGEA_REGRESS_METHOD_RIDGE, "ridge"},
    {IGEA_CHOICE_REGRESS_METHOD, IGEA_REGRESS_METHOD_PCE, "pce"},
    {IGEA_CHOICE_REGRESS_METHOD, IGEA_REGRESS_METHOD_BAYES, "bayes"},
    {IGEA_CHOICE_REGRESS_METHOD, IGEA_REGRESS_METHOD_EBR, "ebr"},
    {IGEA_CHOICE_ACCEL_AXIS, IGEA_ACCEL_AXIS_PA, "pa"},
    {IGEA_CHOICE_ACCEL_AXIS, IGEA_ACCEL_AXIS_OA, "oa"},
    {IGEA_CHOICE_IMPACT_MODEL, IGEA_IMPACT_KEPLER, "kepler"},
    {IGEA_CHOICE_IMPACT_MODEL, IGEA_IMPACT_J2, "j2"},
    {IGEA_CHOICE_IMPACT_CEP, IGEA_IMPACT_CEP_SUM, "sum"},
    {IGEA_CHOICE_IMPACT_CEP, IGEA_IMPACT_CEP_RMS, "rms"},
    {IGEA_CHOICE_STABILITY_DATA, IGEA_STABILITY_DATA_FREQ, "freq"},
    {IGEA_CHOICE_STABILITY_DATA, IGEA_STABILITY_DATA_PHASE, "phase"},
    {IGEA_CHOICE_STABILITY_TAUS, IGEA_STABILITY_TAUS_OCTAVE, "octave"},
    {IGEA_CHOICE_STABILITY_TAUS, IGEA_STABILITY_TAUS_DECADE, "decade"},
    {IGEA_CHOICE_STABILITY_TAUS, IGEA_STABILITY_TAUS_ALL, "all"},
    {IGEA_CHOICE_NAV_FRAME, IGEA_NAV_ECEF, "ecef"},
    {IGEA_CHOICE_NAV_FRAME, IGEA_NAV_LE, "le"},
    {IGEA_CHOICE_NAV_FRAME, IGEA_NAV_LI, "li"},
    {IGEA_CHOICE_NAV_GRAVITY, IGEA_NAV_GRAVITY_POINT_MASS, "point_mass"},
    {IGEA_CHOICE_NAV_GRAVITY, IGEA_NAV_GRAVITY_J2, "j2"},
    {IGEA_CHOICE_DW_KIND, IGEA_DW_APPARENT, "apparent"},
    {IGEA_CHOICE_DW_KIND, IGEA_DW_NAVIGATED, "navigated"},
    {IGEA_CHOICE_DW_FRAME, IGEA_NAV_ECEF, "ecef"},
    {IGEA_CHOICE_DW_FRAME, IGEA_NAV_LE, "le"},
    {IGEA_CHOICE_ACCEL_IEEE_METHOD, IGEA_ACCEL_LS, "ls"},
    {IGEA_CHOICE_ACCEL_IEEE_METHOD, IGEA_ACCEL_HARMONIC, "harmonic"},
    {IGEA_CHOICE_ACCEL_CRIT_MODEL, IGEA_ACCEL_SINGLE, "single"},
    {IGEA_CHOICE_ACCEL_CRIT_MODEL, IGEA_ACCEL_DUAL, "dual"},
    {IGEA_CHOICE_ACCEL_CRIT_MODEL, IGEA_ACCEL_IEEE, "ieee"},
};
/* Kinds are numbered from 1, not necessarily without gaps, below KIND_MAX;
 * UNKNOWN_KIND is none. */
enum { NPAIRS = sizeof expected / sizeof expected[0], KIND_MAX = 256, UNKNOWN_KIND = 4096 };

/* Every macro's name gives the macro's code and back. */
static void test_macros(void **state)
{
    (void)state;
    for (int i = 0; i < NPAIRS; i++) {
        const pair *p = &expected[i];
        int code = 12345;
        assert_int_equal(igea_choice_code(p->kind, p->name, &code), 0);
        assert_int_equal(code, p->code);
        assert_string_equal(igea_choice_name(p->kind, p->code), p->name);
    }
}

/* Each kind lists exactly the macros above, in their order, and every
 * listed code round-trips code -> name -> code. */
static void test_listing(void **state)
{
    (void)state;
    int total = 0;
    for (int kind = 1; kind < KIND_MAX; kind++) {
        int codes[32], n = igea_choice_codes(kind, NULL, 0);
        if (n == -1)
            continue; /* no such kind: then no macro pair names it */
        assert_true(n >= 2 && n <= 32);
        assert_int_equal(igea_choice_codes(kind, codes, 32), n);
        int k = 0;
        for (int i = 0; i < NPAIRS; i++)
            if (expected[i].kind == kind) {
                assert_true(k < n);
                assert_int_equal(codes[k], expected[i].code);
                k++;
            }
        assert_int_equal(k, n);
        for (int i = 0; i < n; i++) {
            const char *name = igea_choice_name(kind, codes[i]);
            int code = 12345;
            assert_true(name[0] != '\0');
            assert_int_equal(igea_choice_code(kind, name, &code), 0);
            assert_int_equal(code, codes[i]);
        }
        /* a short buffer gets the first codes, the count is the whole */
        int one[2] = {777, 777};
        assert_int_equal(igea_choice_codes(kind, one, 1), n);
        assert_int_equal(one[0], codes[0]);
        assert_int_equal(one[1], 777);
        total += n;
    }
    assert_int_equal(total, NPAIRS);
}

static void test_invalid(void **state)
{
    (void)state;
    int code = 777, codes[4];
    /* unknown kinds */
    assert_string_equal(igea_choice_name(0, 0), "");
    assert_string_equal(igea_choice_name(UNKNOWN_KIND, 0), "");
    assert_int_equal(igea_choice_code(0, "eig", &code), -1);
    assert_int_equal(igea_choice_code(UNKNOWN_KIND, "eig", &code), -1);
    assert_int_equal(igea_choice_codes(0, codes, 4), -1);
    assert_int_equal(igea_choice_codes(-5, NULL, 0), -1);
    /* unknown codes and names */
    assert_string_equal(igea_choice_name(IGEA_CHOICE_EQERR_ROUTE, 2), "");
    assert_string_equal(igea_choice_name(IGEA_CHOICE_EQERR_ROUTE, -1), "");
    assert_string_equal(igea_choice_name(IGEA_CHOICE_RLS_FLAG, 3), "");
    assert_int_equal(igea_choice_code(IGEA_CHOICE_EQERR_ROUTE, "SVD", &code), -2);
    assert_int_equal(igea_choice_code(IGEA_CHOICE_EQERR_ROUTE, "sv", &code), -2);
    assert_int_equal(igea_choice_code(IGEA_CHOICE_EQERR_ROUTE, "svdx", &code), -2);
    assert_int_equal(igea_choice_code(IGEA_CHOICE_EQERR_ROUTE, "", &code), -2);
    assert_int_equal(igea_choice_code(IGEA_CHOICE_EQERR_ROUTE, NULL, &code), -2);
    assert_int_equal(igea_choice_code(IGEA_CHOICE_REGRESS_EBR_RULE, "hkb", &code), -2);
    assert_int_equal(igea_choice_code(IGEA_CHOICE_EQERR_ROUTE, "svd", NULL), -3);
    assert_int_equal(code, 777); /* untouched by every failure */
    assert_int_equal(igea_choice_codes(IGEA_CHOICE_EQERR_ROUTE, NULL, 1), -2);
    assert_int_equal(igea_choice_codes(IGEA_CHOICE_EQERR_ROUTE, codes, -1), -3);
    /* a negative code is a code, not a status */
    assert_int_equal(igea_choice_code(IGEA_CHOICE_STABILITY_NOISE, "rwfm", &code), 0);
    assert_int_equal(code, -2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_macros),
        cmocka_unit_test(test_listing),
        cmocka_unit_test(test_invalid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
