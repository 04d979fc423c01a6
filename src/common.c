/* common.c - status text, version, argument-check helpers, shared kernels. */
#include <stdint.h>

#include <gsl/gsl_errno.h>
#include <lapacke.h>

#include "igea/eqerr.h"
#include "igea/impact.h"
#include "igea/inserr.h"
#include "igea/triad.h"
#include "igea/noise.h"
#include "igea/sim.h"
#include "internal.h"

const char *igea_strerror(int status)
{
    if (status == IGEA_OK)
        return "success";
    if (status < 0 && status > -1000)
        return "invalid argument (the negated status is its 1-based position)";
    switch (status) {
    case IGEA_ENOMEM: return "out of memory";
    case IGEA_ENONFINITE: return "an input holds NaN or Inf";
    case IGEA_ENONPOSITIVE: return "a variance or standard deviation is zero or negative";
    case IGEA_ESINGULAR: return "a matrix is singular or not positive definite";
    case IGEA_ERANK: return "the problem is rank-deficient where full rank is needed";
    case IGEA_ENOCONV: return "an iteration did not converge";
    case IGEA_ELAPACK: return "LAPACK reported a failure";
    case IGEA_EDOMAIN: return "a value is outside its mathematical domain";
    case IGEA_ENOTESTABLE: return "no component is precise enough to be tested";
    case IGEA_EDEPENDENT: return "pooled flights are not independent (the same unit appears twice)";
    case IGEA_EEMPTY: return "no data (zero rows or zero terms)";
    case IGEA_ERANGE:
        return "a standard deviation is below 1.5e-154 (its inverse square, the weight, "
               "overflows): rescale the inputs (units?)";
    case IGEA_EOVERFLOW:
        return "a result overflowed or underflowed the double range although the inputs "
               "are finite: rescale the inputs (units?)";
    case IGEA_EFORMAT: return "an input file is not what its format says (malformed data)";
    case IGEA_EREAD: return "an input file cannot be opened or read";
    case IGEA_ETEMPFILE:
        return "a temporary copy of an input (for a second pass) cannot be written";
    case IGEA_DW_ESPAN: return "a tracking epoch is outside the telemetry span";
    case IGEA_DW_ETRACK: return "tracking epochs are not strictly increasing";
    case IGEA_DW_ETELEMETRY: return "telemetry times are not strictly increasing";
    case IGEA_EVERDICT:
        return "the verdict rule cannot be evaluated for this many tested components "
               "(more than IGEA_STATS_UNION_N_MAX = 200)";
    default: break;
    }
    if (status > 0)
        return "a routine-specific outcome (see the routine's documentation)";
    return "unknown status code";
}

int igea_status_class(int status)
{
    if (status >= 0)
        return IGEA_STATUS_OK;
    if (status > -1000)
        return IGEA_STATUS_ARGUMENT;
    switch (status) {
    case IGEA_ENONFINITE:
    case IGEA_ENONPOSITIVE:
    case IGEA_ESINGULAR:
    case IGEA_ERANK:
    case IGEA_EDOMAIN:
    case IGEA_ENOTESTABLE:
    case IGEA_EDEPENDENT:
    case IGEA_EEMPTY:
    case IGEA_ERANGE:
    case IGEA_EOVERFLOW:
    case IGEA_EFORMAT:
    case IGEA_DW_ESPAN:
    case IGEA_DW_ETRACK:
    case IGEA_DW_ETELEMETRY: return IGEA_STATUS_DATA;
    case IGEA_EREAD: return IGEA_STATUS_INPUT;
    case IGEA_ENOMEM:
    case IGEA_ETEMPFILE: return IGEA_STATUS_RESOURCE;
    default: return IGEA_STATUS_FAILURE;
    }
}

const char *igea_opt_name(int module, int slot)
{
    static const char *const eqerr[IGEA_EQERR_OPT_LEN] = {
        [IGEA_EQERR_OPT_ALPHA] = "alpha",
        [IGEA_EQERR_OPT_LAMBDA_TEST] = "lambda_test",
        [IGEA_EQERR_OPT_LAMBDA_SMALL] = "lambda_small",
        [IGEA_EQERR_OPT_N_MIN] = "n_min",
        [IGEA_EQERR_OPT_TOL] = "tol",
        [IGEA_EQERR_OPT_MAX_ITER] = "max_iter",
        [IGEA_EQERR_OPT_CORRECTION] = "correction",
        [IGEA_EQERR_OPT_RANK_TOL] = "rank_tol",
        [IGEA_EQERR_OPT_BIAS_CORRECT] = "bias_correct",
        [IGEA_EQERR_OPT_CLAMP] = "clamp",
        [IGEA_EQERR_OPT_Z_CRIT] = "z_crit",
        [IGEA_EQERR_OPT_ROUTE] = "route",
        [IGEA_EQERR_OPT_VERDICT] = "verdict",
        [IGEA_EQERR_OPT_OVERALL_SIZE] = "overall_size",
        [IGEA_EQERR_OPT_VERDICT_N] = "verdict_n",
        [IGEA_EQERR_OPT_VERDICT_A] = "verdict_a",
        [IGEA_EQERR_OPT_VERDICT_B] = "verdict_b",
        [IGEA_EQERR_OPT_VERDICT_SIZE] = "verdict_size",
        [IGEA_EQERR_OPT_THREADS] = "threads",
        [IGEA_EQERR_OPT_AR] = "ar", /* igea/noise.h, 20..28 */
        [IGEA_EQERR_OPT_AR_ESTIMATE] = "ar_estimate",
        [IGEA_EQERR_OPT_ROBUST] = "robust",
        [IGEA_EQERR_OPT_ROBUST_ALPHA] = "robust_alpha",
        [IGEA_EQERR_OPT_NOISE_TOL] = "noise_tol",
        [IGEA_EQERR_OPT_NOISE_MAX_ITER] = "noise_max_iter",
        [IGEA_EQERR_OPT_GROUP_BIAS] = "group_bias",
        [IGEA_EQERR_OPT_ROBUST_MAX] = "robust_max",
        [IGEA_EQERR_OPT_AR_METHOD] = "ar_method",
    };
    static const char *const sim[IGEA_SIM_OPT_LEN] = {
        [IGEA_SIM_OPT_SIGMA_W] = "sigma_w",
        [IGEA_SIM_OPT_AR1] = "ar1",
        [IGEA_SIM_OPT_GROWTH] = "growth",
        [IGEA_SIM_OPT_OUTLIER_PROB] = "outlier_prob",
        [IGEA_SIM_OPT_OUTLIER_SCALE] = "outlier_scale",
        [IGEA_SIM_OPT_GENERATOR] = "generator",
        [IGEA_SIM_OPT_AR2] = "ar2", /* noise models, 6..13 */
        [IGEA_SIM_OPT_AR3] = "ar3",
        [IGEA_SIM_OPT_CORR] = "corr",
        [IGEA_SIM_OPT_GROUP_SPLIT] = "group_split",
        [IGEA_SIM_OPT_SIGMA_W2] = "sigma_w2",
        [IGEA_SIM_OPT_BIAS0] = "bias0",
        [IGEA_SIM_OPT_BIAS1] = "bias1",
        [IGEA_SIM_OPT_JUDGE_NOISE] = "judge_noise",
        [IGEA_SIM_OPT_BATCH] = "batch",
    };
    static const char *const impact[IGEA_IMPACT_OPT_LEN] = {
        [IGEA_IMPACT_OPT_MU] = "mu",         [IGEA_IMPACT_OPT_RADIUS] = "radius",
        [IGEA_IMPACT_OPT_OMEGA] = "omega",   [IGEA_IMPACT_OPT_J2] = "j2",
        [IGEA_IMPACT_OPT_RE] = "re",         [IGEA_IMPACT_OPT_STEP] = "step",
        [IGEA_IMPACT_OPT_TMAX] = "tmax",
    };
    static const char *const triad[IGEA_TRIAD_OPT_LEN] = {
        [IGEA_TRIAD_OPT_G] = "g",                   [IGEA_TRIAD_OPT_WINDOW] = "window",
        [IGEA_TRIAD_OPT_INIT] = "init",             [IGEA_TRIAD_OPT_MIN_STATIC] = "min_static",
        [IGEA_TRIAD_OPT_THRESHOLD] = "threshold",   [IGEA_TRIAD_OPT_MAX_ITER] = "max_iter",
        [IGEA_TRIAD_OPT_EARTH_RATE] = "earth_rate", [IGEA_TRIAD_OPT_LAT] = "lat",
    };
    static const char *const inserr[IGEA_INSERR_OPT_LEN] = {
        [IGEA_INSERR_OPT_RADIUS] = "radius", [IGEA_INSERR_OPT_G] = "g",
        [IGEA_INSERR_OPT_OMEGA] = "omega",   [IGEA_INSERR_OPT_LAT] = "lat",
        [IGEA_INSERR_OPT_VN] = "vn",         [IGEA_INSERR_OPT_VE] = "ve",
        [IGEA_INSERR_OPT_STEP] = "step",     [IGEA_INSERR_OPT_VERTICAL] = "vertical",
        [IGEA_INSERR_OPT_ACC_TC] = "acc_tc", [IGEA_INSERR_OPT_GYRO_TC] = "gyro_tc",
    };
    const char *const *names;
    int len;
    switch (module) {
    case IGEA_MODULE_INSERR: names = inserr; len = IGEA_INSERR_OPT_LEN; break;
    case IGEA_MODULE_TRIAD: names = triad; len = IGEA_TRIAD_OPT_LEN; break;
    case IGEA_MODULE_IMPACT: names = impact; len = IGEA_IMPACT_OPT_LEN; break;
    case IGEA_MODULE_EQERR: names = eqerr; len = IGEA_EQERR_OPT_LEN; break;
    case IGEA_MODULE_SIM: names = sim; len = IGEA_SIM_OPT_LEN; break;
    default: return "";
    }
    if (slot < 0 || slot >= len)
        return "";
    return names[slot] ? names[slot] : "reserved";
}

const char *igea_version(void) { return IGEA_VERSION_STRING; }
int igea_version_number(void) { return IGEA_VERSION_NUMBER; }

int igea_init(void)
{
    gsl_set_error_handler_off();
    return 0;
}

/* 1 when x[0..n) holds no NaN or Inf: x * 0 is NaN exactly for those, and
 * eight such products summed pairwise are independent of each other (no
 * chain of additions through one accumulator), one test per eight. */
int igea__finite_run(size_t n, const double *x)
{
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const double *p = x + i;
        double s = ((p[0] * 0.0 + p[1] * 0.0) + (p[2] * 0.0 + p[3] * 0.0)) +
                   ((p[4] * 0.0 + p[5] * 0.0) + (p[6] * 0.0 + p[7] * 0.0));
        if (s != 0.0)
            return 0;
    }
    for (; i < n; i++)
        if (!isfinite(x[i]))
            return 0;
    return 1;
}

int igea__finite_vec(int n, const double *x, int inc)
{
    if (inc == 1)
        return n <= 0 || igea__finite_run((size_t)n, x);
    for (int i = 0; i < n; i++)
        if (!isfinite(x[(size_t)i * (size_t)inc]))
            return 0;
    return 1;
}

int igea__finite_mat(int m, int n, const double *a, int lda)
{
    if (m <= 0 || n <= 0)
        return 1;
    if (lda == m) /* contiguous: one run */
        return igea__finite_run((size_t)m * (size_t)n, a);
    for (int j = 0; j < n; j++)
        if (!igea__finite_run((size_t)m, a + (size_t)j * (size_t)lda))
            return 0;
    return 1;
}

int igea__positive_vec(int n, const double *x, int *nonfinite)
{
    *nonfinite = 0;
    for (int i = 0; i < n; i++) {
        if (!isfinite(x[i])) {
            *nonfinite = 1;
            return 0;
        }
    }
    for (int i = 0; i < n; i++)
        if (!(x[i] > 0.0))
            return 0;
    return 1;
}

int igea__sigma_vec(int n, const double *x)
{
    int nf;
    if (!igea__positive_vec(n, x, &nf))
        return nf ? IGEA_ENONFINITE : IGEA_ENONPOSITIVE;
    for (int i = 0; i < n; i++)
        if (!(x[i] >= IGEA_SIGMA_MIN))
            return IGEA_ERANGE;
    return 0;
}

double *igea__dalloc(size_t n)
{
    if (n > SIZE_MAX / sizeof(double) - 1)
        return NULL;
    return malloc((n ? n : 1) * sizeof(double));
}

int *igea__ialloc(size_t n)
{
    if (n > SIZE_MAX / sizeof(int) - 1)
        return NULL;
    return malloc((n ? n : 1) * sizeof(int));
}

int igea__sign_fix(int n, double *v)
{
    int imax = 0;
    for (int i = 1; i < n; i++)
        if (fabs(v[i]) > fabs(v[imax]))
            imax = i;
    if (n > 0 && v[imax] < 0.0) {
        for (int i = 0; i < n; i++)
            v[i] = -v[i];
        return -1;
    }
    return 1;
}

int igea__syev_desc(int n, const double *a, int lda, double *w, double *v,
                    int ldv)
{
    if (n == 0)
        return 0;
    double *z = igea__dalloc((size_t)n * (size_t)n + (size_t)n);
    if (!z)
        return IGEA_ENOMEM;
    double *wa = z + (size_t)n * (size_t)n;
    for (int j = 0; j < n; j++)
        for (int i = j; i < n; i++)
            z[i + (size_t)j * n] = IGEA_AT(a, lda, i, j);
    /* Workspace query, then the real call. */
    double wq;
    lapack_int iwq;
    lapack_int info = LAPACKE_dsyevd_work(LAPACK_COL_MAJOR, 'V', 'L', n, z, n,
                                          wa, &wq, -1, &iwq, -1);
    if (info != 0) {
        free(z);
        return IGEA_ELAPACK;
    }
    size_t lwork = (size_t)wq + 1;
    size_t liwork = (size_t)iwq + 1;
    double *work = igea__dalloc(lwork);
    lapack_int *iwork = malloc(liwork * sizeof(lapack_int));
    if (!work || !iwork) {
        free(work);
        free(iwork);
        free(z);
        return IGEA_ENOMEM;
    }
    info = LAPACKE_dsyevd_work(LAPACK_COL_MAJOR, 'V', 'L', n, z, n, wa, work,
                               (lapack_int)lwork, iwork, (lapack_int)liwork);
    free(work);
    free(iwork);
    if (info != 0) {
        free(z);
        return IGEA_ELAPACK;
    }
    for (int k = 0; k < n; k++) {
        int src = n - 1 - k;
        w[k] = wa[src];
        double *dst = v + (size_t)k * (size_t)ldv;
        memcpy(dst, z + (size_t)src * n, (size_t)n * sizeof(double));
        igea__sign_fix(n, dst);
    }
    free(z);
    return 0;
}

gsl_rng *igea__rng_new(const gsl_rng_type *T, unsigned long seed)
{
    gsl_rng *r = malloc(sizeof *r);
    if (!r)
        return NULL;
    r->type = T;
    r->state = malloc(T->size ? T->size : 1);
    if (!r->state) {
        free(r);
        return NULL;
    }
    gsl_rng_set(r, seed);
    return r;
}

void igea__rng_free(gsl_rng *r)
{
    if (r) {
        free(r->state);
        free(r);
    }
}

int igea__platform_axes(const int *axes, int *in_ax, int *spin_ax)
{
    for (int j = 0; j < 3; j++) {
        in_ax[j] = j;
        spin_ax[j] = (j + 1) % 3;
    }
    if (!axes)
        return 0;
    for (int j = 0; j < 6; j++)
        if (axes[j] < 0 || axes[j] > 2)
            return -1;
    for (int j = 0; j < 3; j++) {
        in_ax[j] = axes[j];
        spin_ax[j] = axes[3 + j];
    }
    return 0;
}
