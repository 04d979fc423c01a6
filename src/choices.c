/* choices.c - the names of the library's enumerations (IGEA_CHOICE_*): the
 * one table that the driver's options and the Python package's keywords
 * read. */
#include <string.h>

#include "igea.h"

typedef struct {
    int code;
    const char *name;
} choice;

#define END {0, NULL}
static const choice eqerr_route[] = {
    {IGEA_EQERR_ROUTE_EIG, "eig"}, {IGEA_EQERR_ROUTE_SVD, "svd"}, END};
static const choice ridge_rule[] = {
    {IGEA_REGRESS_RIDGE_FIXED, "fixed"}, {IGEA_REGRESS_RIDGE_HKB, "hkb"},
    {IGEA_REGRESS_RIDGE_LW, "lw"}, {IGEA_REGRESS_RIDGE_GCV, "gcv"}, {IGEA_REGRESS_RIDGE_LOO, "loo"},
    END};
static const choice ebr_rule[] = {
    {IGEA_REGRESS_EBR_SC, "sc"}, {IGEA_REGRESS_EBR_MM, "mm"}, {IGEA_REGRESS_EBR_ML2, "ml2"}, END};
static const choice accel_model[] = {
    {IGEA_ACCEL_SINGLE, "single"}, {IGEA_ACCEL_DUAL, "dual"}, END};
static const choice accel_method[] = {
    {IGEA_ACCEL_LS, "ls"}, {IGEA_ACCEL_EBR, "ebr"}, {IGEA_ACCEL_JOINT, "joint"}, END};
static const choice regress_method[] = {
    {IGEA_REGRESS_METHOD_LS, "ls"}, {IGEA_REGRESS_METHOD_RIDGE, "ridge"},
    {IGEA_REGRESS_METHOD_PCE, "pce"}, {IGEA_REGRESS_METHOD_BAYES, "bayes"},
    {IGEA_REGRESS_METHOD_EBR, "ebr"}, END};
static const choice accel_axis[] = {
    {IGEA_ACCEL_AXIS_PA, "pa"}, {IGEA_ACCEL_AXIS_OA, "oa"}, END};
static const choice impact_model[] = {
    {IGEA_IMPACT_KEPLER, "kepler"}, {IGEA_IMPACT_J2, "j2"}, END};
static const choice impact_cep[] = {
    {IGEA_IMPACT_CEP_SUM, "sum"}, {IGEA_IMPACT_CEP_RMS, "rms"}, END};
static const choice envfun_system[] = {
    {IGEA_ENVFUN_STRAPDOWN, "strapdown"}, {IGEA_ENVFUN_PLATFORM, "platform"}, END};
static const choice envfun_output[] = {
    {IGEA_ENVFUN_VELOCITY, "velocity"}, {IGEA_ENVFUN_POSITION, "position"},
    {IGEA_ENVFUN_VELOCITY_G, "velocity_g"}, {IGEA_ENVFUN_POSITION_G, "position_g"}, END};
static const choice sim_generator[] = {
    {IGEA_SIM_MT19937, "mt19937"}, {IGEA_SIM_RANLXD2, "ranlxd2"},
    {IGEA_SIM_XOSHIRO, "xoshiro"}, END};
static const choice rls_variant[] = {
    {IGEA_RLS_STANDARD, "standard"}, {IGEA_RLS_ITERATED, "iterated"},
    {IGEA_RLS_POLYNOMIAL, "polynomial"}, END};
static const choice rls_anomaly[] = {
    {IGEA_RLS_ANOMALY_NONE, "none"}, {IGEA_RLS_ANOMALY_REPLACE, "replace"},
    {IGEA_RLS_ANOMALY_SKIP, "skip"}, {IGEA_RLS_ANOMALY_ISOLATE, "isolate"}, END};
static const choice rls_action[] = {
    {IGEA_RLS_UPDATED, "updated"}, {IGEA_RLS_FLAGGED, "flagged"}, {IGEA_RLS_REPLACED, "replaced"},
    {IGEA_RLS_SKIPPED, "skipped"}, {IGEA_RLS_ISOLATED, "isolated"}, END};
static const choice rls_flag[] = {
    {IGEA_RLS_FLAG_INNOVATION, "innovation"}, {IGEA_RLS_FLAG_JUMP, "jump"},
    {IGEA_RLS_FLAG_MISSING, "missing"}, {IGEA_RLS_FLAG_UNUSED, "unused"}, END};
static const choice stability_kind[] = {
    {IGEA_STABILITY_ALLAN_OVERLAPPING, "overlapping"}, {IGEA_STABILITY_ALLAN_MODIFIED, "modified"},
    {IGEA_STABILITY_ALLAN_NONOVERLAPPING, "nonoverlapping"}, {IGEA_STABILITY_ALLAN_ADEV, "adev"},
    {IGEA_STABILITY_ALLAN_OADEV, "oadev"}, {IGEA_STABILITY_ALLAN_MDEV, "mdev"},
    {IGEA_STABILITY_ALLAN_TDEV, "tdev"}, {IGEA_STABILITY_ALLAN_HDEV, "hdev"},
    {IGEA_STABILITY_ALLAN_OHDEV, "ohdev"}, {IGEA_STABILITY_ALLAN_TOTDEV, "totdev"},
    {IGEA_STABILITY_ALLAN_MTOTDEV, "mtotdev"}, {IGEA_STABILITY_ALLAN_TTOTDEV, "ttotdev"},
    {IGEA_STABILITY_ALLAN_HTOTDEV, "htotdev"}, {IGEA_STABILITY_ALLAN_THEO1, "theo1"},
    {IGEA_STABILITY_ALLAN_MTIE, "mtie"}, {IGEA_STABILITY_ALLAN_TIERMS, "tierms"},
    {IGEA_STABILITY_ALLAN_THEOBR, "theobr"}, {IGEA_STABILITY_ALLAN_THEOH, "theoh"}, END};
static const choice stability_data[] = {
    {IGEA_STABILITY_DATA_FREQ, "freq"}, {IGEA_STABILITY_DATA_PHASE, "phase"}, END};
static const choice stability_taus[] = {
    {IGEA_STABILITY_TAUS_OCTAVE, "octave"}, {IGEA_STABILITY_TAUS_DECADE, "decade"},
    {IGEA_STABILITY_TAUS_ALL, "all"}, END};
static const choice stability_noise[] = {
    {IGEA_STABILITY_NOISE_RWFM, "rwfm"}, {IGEA_STABILITY_NOISE_FFM, "ffm"},
    {IGEA_STABILITY_NOISE_WFM, "wfm"}, {IGEA_STABILITY_NOISE_FPM, "fpm"},
    {IGEA_STABILITY_NOISE_WPM, "wpm"}, {IGEA_STABILITY_NOISE_AUTO, "auto"}, END};
static const choice sigmaw_flag[] = {
    {IGEA_STATS_SIGMAW_CONVERGED, "converged"}, {IGEA_STATS_SIGMAW_NOT_ESTIMABLE, "not_estimable"},
    {IGEA_STATS_SIGMAW_NO_CONVERGENCE, "no_convergence"}, {IGEA_STATS_SIGMAW_OFF, "off"}, END};
static const choice stats_verdict[] = {
    {IGEA_STATS_VERDICT_SEED, "seed"}, {IGEA_STATS_VERDICT_CHI2, "chi2"},
    {IGEA_STATS_VERDICT_EXACT, "exact"}, {IGEA_STATS_VERDICT_SIDAK, "sidak"}, END};
static const choice noise_ar_method[] = {
    {IGEA_NOISE_AR_REML, "reml"}, {IGEA_NOISE_AR_LS, "ls"}, END};
static const choice nav_frame[] = {
    {IGEA_NAV_ECEF, "ecef"}, {IGEA_NAV_LE, "le"}, {IGEA_NAV_LI, "li"}, END};
static const choice nav_gravity[] = {
    {IGEA_NAV_GRAVITY_POINT_MASS, "point_mass"}, {IGEA_NAV_GRAVITY_J2, "j2"}, END};
static const choice dw_frame[] = {{IGEA_NAV_ECEF, "ecef"}, {IGEA_NAV_LE, "le"}, END};
static const choice dw_kind[] = {
    {IGEA_DW_APPARENT, "apparent"}, {IGEA_DW_NAVIGATED, "navigated"}, END};
static const choice redund_rbd[] = {
    {IGEA_REDUND_RBD_SERIES, "series"}, {IGEA_REDUND_RBD_PARALLEL, "parallel"},
    {IGEA_REDUND_RBD_KOFN, "kofn"}, END};

static const choice accel_ieee_method[] = {
    {IGEA_ACCEL_LS, "ls"}, {IGEA_ACCEL_HARMONIC, "harmonic"}, END};
static const choice accel_crit_model[] = {
    {IGEA_ACCEL_SINGLE, "single"}, {IGEA_ACCEL_DUAL, "dual"}, {IGEA_ACCEL_IEEE, "ieee"}, END};

/* The table of a kind, or NULL. */
static const choice *table(int kind)
{
    switch (kind) {
    case IGEA_CHOICE_EQERR_ROUTE: return eqerr_route;
    case IGEA_CHOICE_REGRESS_RIDGE_RULE: return ridge_rule;
    case IGEA_CHOICE_REGRESS_EBR_RULE: return ebr_rule;
    case IGEA_CHOICE_ACCEL_MODEL: return accel_model;
    case IGEA_CHOICE_ACCEL_METHOD: return accel_method;
    case IGEA_CHOICE_ACCEL_AXIS: return accel_axis;
    case IGEA_CHOICE_REGRESS_METHOD: return regress_method;
    case IGEA_CHOICE_IMPACT_MODEL: return impact_model;
    case IGEA_CHOICE_IMPACT_CEP: return impact_cep;
    case IGEA_CHOICE_ENVFUN_SYSTEM: return envfun_system;
    case IGEA_CHOICE_ENVFUN_OUTPUT: return envfun_output;
    case IGEA_CHOICE_SIM_GENERATOR: return sim_generator;
    case IGEA_CHOICE_RLS_VARIANT: return rls_variant;
    case IGEA_CHOICE_RLS_ANOMALY: return rls_anomaly;
    case IGEA_CHOICE_RLS_ACTION: return rls_action;
    case IGEA_CHOICE_RLS_FLAG: return rls_flag;
    case IGEA_CHOICE_STABILITY_KIND: return stability_kind;
    case IGEA_CHOICE_STABILITY_NOISE: return stability_noise;
    case IGEA_CHOICE_STATS_SIGMAW_FLAG: return sigmaw_flag;
    case IGEA_CHOICE_REDUND_RBD: return redund_rbd;
    case IGEA_CHOICE_STATS_VERDICT: return stats_verdict;
    case IGEA_CHOICE_NOISE_AR_METHOD: return noise_ar_method;
    case IGEA_CHOICE_STABILITY_DATA: return stability_data;
    case IGEA_CHOICE_STABILITY_TAUS: return stability_taus;
    case IGEA_CHOICE_NAV_FRAME: return nav_frame;
    case IGEA_CHOICE_NAV_GRAVITY: return nav_gravity;
    case IGEA_CHOICE_DW_KIND: return dw_kind;
    case IGEA_CHOICE_DW_FRAME: return dw_frame;
    case IGEA_CHOICE_ACCEL_IEEE_METHOD: return accel_ieee_method;
    case IGEA_CHOICE_ACCEL_CRIT_MODEL: return accel_crit_model;
    default: return NULL;
    }
}

const char *igea_choice_name(int kind, int code)
{
    const choice *t = table(kind);
    for (; t && t->name; t++)
        if (t->code == code)
            return t->name;
    return "";
}

int igea_choice_code(int kind, const char *name, int *code)
{
    const choice *t = table(kind);
    if (!t)
        return -1;
    if (!name)
        return -2;
    if (!code)
        return -3;
    for (; t->name; t++)
        if (!strcmp(t->name, name)) {
            *code = t->code;
            return 0;
        }
    return -2;
}

int igea_choice_codes(int kind, int *codes, int len)
{
    const choice *t = table(kind);
    if (!t)
        return -1;
    if (len < 0)
        return -3;
    if (!codes && len > 0)
        return -2;
    int n = 0;
    for (; t[n].name; n++)
        if (n < len)
            codes[n] = t[n].code;
    return n;
}
