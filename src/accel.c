/* accel.c - dividing-head accelerometer calibration: schedules, single and
 * orthogonal-dual (g^2) designs, identifiability, fits through the regress
 * estimators, exact-model refinement, simulation (METHODS 4.1-4.3). */
#include <float.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <lapacke.h>

#include "igea/accel.h"
#include "igea/regress.h"
#include "internal.h"
#include "accel_internal.h"

#define ACCEL_PI 3.14159265358979323846
#define ACCEL_MAXP 10 /* the joint model (10); the null basis works up to this */

static int model_np(int model)
{
    return model == IGEA_ACCEL_SINGLE ? IGEA_ACCEL_NP_SINGLE : IGEA_ACCEL_NP_DUAL;
}

static int model_nc(int model)
{
    return model == IGEA_ACCEL_SINGLE ? IGEA_ACCEL_NC_SINGLE : IGEA_ACCEL_NC_DUAL;
}

static int model_ok(int model)
{
    return model == IGEA_ACCEL_SINGLE || model == IGEA_ACCEL_DUAL;
}

/* sin and cos of an angle in degrees, exact (0, +-1) at multiples of 90:
 * reduce to the nearest quadrant, then rotate. */
static void sincosd(double deg, double *s, double *c)
{
    double r = fmod(deg, 360.0);
    if (r < 0.0)
        r += 360.0;
    double q = floor(r / 90.0 + 0.5);
    double x = (r - 90.0 * q) * (ACCEL_PI / 180.0);
    double sx = sin(x), cx = cos(x);
    switch ((int)q % 4) {
    case 0: *s = sx; *c = cx; break;
    case 1: *s = cx; *c = -sx; break;
    case 2: *s = -sx; *c = -cx; break;
    default: *s = -cx; *c = sx; break;
    }
    if (*s == 0.0)
        *s = 0.0; /* no negative zeros */
    if (*c == 0.0)
        *c = 0.0;
}

/* Row of the design at one angle. */
static void design_row(int model, double deg, double *row)
{
    double s, c;
    sincosd(deg, &s, &c);
    if (model == IGEA_ACCEL_SINGLE) {
        row[0] = 1.0;
        row[1] = s;
        row[2] = c;
        row[3] = s * s;
        row[4] = s * c;
    } else {
        row[0] = s;
        row[1] = c;
        row[2] = s * s;
        row[3] = c * c;
        row[4] = -s * c;
        row[5] = s * s * s;
        row[6] = c * c * c;
        row[7] = s * s * c;
        row[8] = -s * c * c;
    }
}

static void tangential_row(double deg, double *row);

static void fill_design(int model, int n, const double *theta, double *A,
                        int lda)
{
    int np = model_np(model);
    double row[ACCEL_MAXP];
    for (int i = 0; i < n; i++) {
        design_row(model, theta[i], row);
        for (int j = 0; j < np; j++)
            IGEA_AT(A, lda, i, j) = row[j];
    }
}

static void fill_combinations(int model, double *C, int ldc)
{
    int np = model_np(model), nc = model_nc(model);
    for (int j = 0; j < nc; j++)
        for (int i = 0; i < np; i++)
            IGEA_AT(C, ldc, i, j) = 0.0;
    if (model == IGEA_ACCEL_SINGLE) {
        for (int j = 0; j < nc; j++)
            IGEA_AT(C, ldc, j, j) = 1.0;
        return;
    }
    IGEA_AT(C, ldc, IGEA_ACCEL_KA1, 0) = 1.0;
    IGEA_AT(C, ldc, IGEA_ACCEL_KB1, 1) = 1.0;
    IGEA_AT(C, ldc, IGEA_ACCEL_ETA, 2) = 1.0;
    IGEA_AT(C, ldc, IGEA_ACCEL_KA0, 3) = 1.0;
    IGEA_AT(C, ldc, IGEA_ACCEL_KA2, 3) = 1.0;
    IGEA_AT(C, ldc, IGEA_ACCEL_KA2, 4) = 1.0;
    IGEA_AT(C, ldc, IGEA_ACCEL_KBIX, 4) = 1.0;
    IGEA_AT(C, ldc, IGEA_ACCEL_KB0, 5) = 1.0;
    IGEA_AT(C, ldc, IGEA_ACCEL_KB2, 5) = 1.0;
    IGEA_AT(C, ldc, IGEA_ACCEL_KB2, 6) = 1.0;
    IGEA_AT(C, ldc, IGEA_ACCEL_KAIX, 6) = -1.0;
}

/*
 * Singular values s[N] (descending, 0 beyond min(m, N)) and all right
 * singular vectors V (N x N, columns) of the m x N matrix A (lda); rank
 * with the cut max(m, N) eps s_1 (METHODS 0.3). Returns 0, IGEA_ENOMEM,
 * IGEA_ELAPACK.
 */
static int svd_v(int m, int N, const double *A, int lda, double *s,
                 double *V, int *rank)
{
    int k = IGEA_MIN(m, N);
    int ucols = m >= N ? N : m;
    double *a = igea__dalloc((size_t)m * N + (size_t)m * ucols + (size_t)k);
    if (!a)
        return IGEA_ENOMEM;
    double *u = a + (size_t)m * N, *sv = u + (size_t)m * ucols;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < m; i++)
            a[(size_t)i + (size_t)j * m] = IGEA_AT(A, lda, i, j);
    int st = igea__svd(m, N, a, sv, u, 0, V);
    if (st == 0 && !igea__finite_vec(k, sv, 1))
        st = IGEA_ELAPACK;
    if (st == 0) {
        for (int i = 0; i < N; i++)
            s[i] = i < k ? sv[i] : 0.0;
        *rank = igea__rank_cut(k, s, (double)IGEA_MAX(m, N) * DBL_EPSILON);
    }
    free(a);
    return st;
}

/*
 * Canonical orthonormal basis of the null space spanned by V's columns
 * r..N-1 (N x N, ld N): reduced echelon form with column pivoting, then
 * Gram-Schmidt in order, first nonzero entry positive. Writes nb (N x N,
 * ld N): k = N - r columns, then zeros.
 */
static void null_canonical(int N, int r, const double *V, double *nb)
{
    int k = N - r;
    double M[ACCEL_MAXP * ACCEL_MAXP]; /* k x N, row-major */
    for (int i = 0; i < k; i++)
        for (int j = 0; j < N; j++)
            M[i * N + j] = V[(size_t)j + (size_t)(r + i) * N];
    int prow = 0;
    for (int col = 0; col < N && prow < k; col++) {
        int best = prow;
        for (int i = prow + 1; i < k; i++)
            if (fabs(M[i * N + col]) > fabs(M[best * N + col]))
                best = i;
        if (fabs(M[best * N + col]) <= 1e-10)
            continue;
        if (best != prow)
            for (int j = 0; j < N; j++) {
                double t = M[prow * N + j];
                M[prow * N + j] = M[best * N + j];
                M[best * N + j] = t;
            }
        double piv = M[prow * N + col];
        for (int j = 0; j < N; j++)
            M[prow * N + j] /= piv;
        for (int i = 0; i < k; i++) {
            if (i == prow)
                continue;
            double f = M[i * N + col];
            if (f != 0.0)
                for (int j = 0; j < N; j++)
                    M[i * N + j] -= f * M[prow * N + j];
        }
        M[prow * N + col] = 1.0;
        prow++;
    }
    for (int i = 0; i < k; i++) {
        double *v = M + i * N;
        for (int p = 0; p < i; p++) {
            const double *w = M + p * N;
            double d = 0.0;
            for (int j = 0; j < N; j++)
                d += v[j] * w[j];
            for (int j = 0; j < N; j++)
                v[j] -= d * w[j];
        }
        double nrm = 0.0;
        for (int j = 0; j < N; j++)
            nrm += v[j] * v[j];
        nrm = sqrt(nrm);
        int first = -1;
        for (int j = 0; j < N; j++) {
            v[j] /= nrm;
            if (fabs(v[j]) < 1e-15)
                v[j] = 0.0;
            if (first < 0 && fabs(v[j]) > 1e-12)
                first = j;
        }
        if (first >= 0 && v[first] < 0.0)
            for (int j = 0; j < N; j++)
                v[j] = -v[j];
    }
    for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++)
            nb[(size_t)j + (size_t)i * N] = i < k ? M[i * N + j] : 0.0;
}

/* Loading of vector c (length N) on the null space V[:, r:] (ld N). */
static double null_loading(int N, int r, const double *V, const double *c)
{
    double ss = 0.0;
    for (int i = r; i < N; i++) {
        double d = 0.0;
        for (int j = 0; j < N; j++)
            d += V[(size_t)j + (size_t)i * N] * c[j];
        ss += d * d;
    }
    return sqrt(ss);
}

/* The helpers above for the other accel_*.c files (accel_internal.h). */
void igea__accel_sincosd(double deg, double *s, double *c) { sincosd(deg, s, c); }
void igea__accel_row(int model, double deg, double *row)
{
    if (model == IGEA_ACCEL_JOINT) /* the tangential row of the joint model */
        tangential_row(deg, row);
    else
        design_row(model, deg, row);
}
int igea__accel_svd(int m, int N, const double *A, int lda, double *s, double *V, int *rank)
{
    return svd_v(m, N, A, lda, s, V, rank);
}
void igea__accel_null(int N, int r, const double *V, double *nb) { null_canonical(N, r, V, nb); }
double igea__accel_loading(int N, int r, const double *V, const double *c)
{
    return null_loading(N, r, V, c);
}

/* ---------------------------------------------------------------------- */

int igea_accel_schedule(int n, double start_deg, double *theta_deg)
{
    if (n < 1)
        return -1;
    if (!isfinite(start_deg))
        return -2;
    if (!theta_deg)
        return -3;
    for (int k = 0; k < n; k++)
        theta_deg[k] = start_deg + 360.0 * (double)k / (double)n;
    return 0;
}

typedef struct {
    double a;
    int idx;
} angle_idx;

static int cmp_angle(const void *p, const void *q)
{
    const angle_idx *x = p, *y = q;
    if (x->a < y->a)
        return -1;
    if (x->a > y->a)
        return 1;
    return x->idx < y->idx ? -1 : x->idx > y->idx;
}

/* The readings' angles in [0, 360) (within tol of 360 counted as 0), sorted
 * with their row indices (ties by row). */
static void sort_angles(int nrows, const double *angle_deg, double tol_deg, angle_idx *ai)
{
    for (int i = 0; i < nrows; i++) {
        double a = fmod(angle_deg[i], 360.0);
        if (a < 0.0)
            a += 360.0;
        if (a >= 360.0 - tol_deg && a > 0.0)
            a -= 360.0;
        ai[i].a = a;
        ai[i].idx = i;
    }
    qsort(ai, (size_t)nrows, sizeof *ai, cmp_angle);
}

int igea_accel_merge(int nrows, const double *angle_deg, const double *ya,
                     const double *yb, double tol_deg, double *theta_deg,
                     double *ya_mean, double *yb_mean, int *count, int *npos)
{
    if (nrows < 1)
        return -1;
    if (!angle_deg)
        return -2;
    if (!ya)
        return -3;
    if (!(tol_deg >= 0.0 && tol_deg < 45.0))
        return -5;
    if (!theta_deg)
        return -6;
    if (!ya_mean)
        return -7;
    if (yb && !yb_mean)
        return -8;
    if (!npos)
        return -10;
    if (!igea__finite_vec(nrows, angle_deg, 1) || !igea__finite_vec(nrows, ya, 1) ||
        (yb && !igea__finite_vec(nrows, yb, 1)))
        return IGEA_ENONFINITE;
    angle_idx *ai = malloc((size_t)nrows * sizeof *ai);
    double *tmp = igea__dalloc(3 * (size_t)nrows);
    int *cnt = igea__ialloc((size_t)nrows);
    if (!ai || !tmp || !cnt) {
        free(ai);
        free(tmp);
        free(cnt);
        return IGEA_ENOMEM;
    }
    sort_angles(nrows, angle_deg, tol_deg, ai);
    double *t = tmp, *ma = tmp + nrows, *mb = tmp + 2 * (size_t)nrows;
    int np = 0;
    for (int k = 0; k < nrows;) {
        int e = k + 1;
        while (e < nrows && ai[e].a - ai[k].a <= tol_deg)
            e++;
        double sa = 0.0, sy = 0.0, sb = 0.0;
        for (int q = k; q < e; q++) {
            sa += ai[q].a;
            sy += ya[ai[q].idx];
            if (yb)
                sb += yb[ai[q].idx];
        }
        double w = (double)(e - k);
        t[np] = sa / w;
        ma[np] = sy / w;
        mb[np] = sb / w;
        cnt[np] = e - k;
        np++;
        k = e;
    }
    memcpy(theta_deg, t, (size_t)np * sizeof(double));
    memcpy(ya_mean, ma, (size_t)np * sizeof(double));
    if (yb)
        memcpy(yb_mean, mb, (size_t)np * sizeof(double));
    if (count)
        memcpy(count, cnt, (size_t)np * sizeof(int));
    *npos = np;
    free(ai);
    free(tmp);
    free(cnt);
    return 0;
}

int igea_accel_to_g(int n, const double *raw, double scale, double *y)
{
    if (n < 1)
        return -1;
    if (!raw)
        return -2;
    if (!isfinite(scale) || scale == 0.0)
        return -3;
    if (!y)
        return -4;
    if (!igea__finite_vec(n, raw, 1))
        return IGEA_ENONFINITE;
    for (int i = 0; i < n; i++)
        y[i] = raw[i] / scale;
    return 0;
}

static void observe(int model, int n, const double *theta, const double *ya,
                    const double *yb, double *y)
{
    for (int i = 0; i < n; i++) {
        if (model == IGEA_ACCEL_SINGLE) {
            double s, c;
            sincosd(theta[i], &s, &c);
            y[i] = ya[i] - s;
        } else {
            /* (a^2 + b^2 - 1) / 2 with fma: the result is ~1e-4 of the
             * terms, so keep the rounding of the squares out of it. */
            double a2m = fma(ya[i], ya[i], -1.0);
            y[i] = 0.5 * fma(yb[i], yb[i], a2m);
        }
    }
}

int igea_accel_observe(int model, int n, const double *theta_deg,
                       const double *ya, const double *yb, double *y)
{
    if (!model_ok(model))
        return -1;
    if (n < 1)
        return -2;
    if (!theta_deg)
        return -3;
    if (!ya)
        return -4;
    if (model == IGEA_ACCEL_DUAL && !yb)
        return -5;
    if (!y)
        return -6;
    if (!igea__finite_vec(n, theta_deg, 1) || !igea__finite_vec(n, ya, 1) ||
        (model == IGEA_ACCEL_DUAL && !igea__finite_vec(n, yb, 1)))
        return IGEA_ENONFINITE;
    observe(model, n, theta_deg, ya, yb, y);
    return 0;
}

int igea_accel_design(int model, int n, const double *theta_deg, double *A,
                      int lda)
{
    if (!model_ok(model))
        return -1;
    if (n < 1)
        return -2;
    if (!theta_deg)
        return -3;
    if (!A)
        return -4;
    if (lda < n)
        return -5;
    if (!igea__finite_vec(n, theta_deg, 1))
        return IGEA_ENONFINITE;
    fill_design(model, n, theta_deg, A, lda);
    return 0;
}

int igea_accel_combinations(int model, double *C, int ldc)
{
    if (!model_ok(model))
        return -1;
    if (!C)
        return -2;
    if (ldc < model_np(model))
        return -3;
    fill_combinations(model, C, ldc);
    return 0;
}

static const char *const coef_dual[2][9] = {
    {"KA0", "KB0", "kA1", "kB1", "eta", "KA2", "KB2", "KAio", "KBio"},
    {"KA0", "KB0", "kA1", "kB1", "eta", "KA2", "KB2", "KAip", "KBip"}};
static const char *const coef_single[2][5] = {{"K0", "k1", "delta0", "K2", "Kio"},
                                              {"K0", "k1", "delta0", "K2", "Kip"}};
static const char *const comb_dual[2][7] = {
    {"kA1", "kB1", "eta", "KA0+KA2", "KA2+KBio", "KB0+KB2", "KB2-KAio"},
    {"kA1", "kB1", "eta", "KA0+KA2", "KA2+KBip", "KB0+KB2", "KB2-KAip"}};
static const char *const unit_dual[9] = {"g", "g", "", "", "rad", "g/g^2", "g/g^2",
                                         "g/g^2", "g/g^2"};
static const char *const unit_single[5] = {"g", "", "rad", "g/g^2", "g/g^2"};

static int axis_ok(int axis) { return axis == IGEA_ACCEL_AXIS_PA || axis == IGEA_ACCEL_AXIS_OA; }

static const char *const coef_ieee[IGEA_ACCEL_NP_IEEE] = {
    "K0", "K1", "K2", "K3", "Kip", "Kio", "delta_o", "delta_p"};
static const char *const unit_ieee[IGEA_ACCEL_NP_IEEE] = {
    "g", "out/g", "g/g^2", "g/g^3", "g/g^2", "g/g^2", "rad", "rad"};

const char *igea_accel_coef_name(int model, int axis, int j)
{
    if (model == IGEA_ACCEL_IEEE) /* both planes: the names do not depend on axis */
        return axis_ok(axis) && j >= 0 && j < IGEA_ACCEL_NP_IEEE ? coef_ieee[j] : "";
    if (!model_ok(model) || !axis_ok(axis) || j < 0 || j >= model_np(model))
        return "";
    return model == IGEA_ACCEL_DUAL ? coef_dual[axis][j] : coef_single[axis][j];
}

const char *igea_accel_comb_name(int model, int axis, int k)
{
    if (!model_ok(model) || !axis_ok(axis) || k < 0)
        return "";
    if (model == IGEA_ACCEL_DUAL)
        return k < IGEA_ACCEL_NC_DUAL ? comb_dual[axis][k] : "";
    return k < IGEA_ACCEL_NC_SINGLE ? coef_single[axis][k] : "";
}

const char *igea_accel_coef_unit(int model, int j)
{
    if (model == IGEA_ACCEL_IEEE)
        return j >= 0 && j < IGEA_ACCEL_NP_IEEE ? unit_ieee[j] : "";
    if (!model_ok(model) || j < 0 || j >= model_np(model))
        return "";
    return model == IGEA_ACCEL_DUAL ? unit_dual[j] : unit_single[j];
}

int igea_accel_combine(int model, const double *coef, double *comb)
{
    if (!model_ok(model))
        return -1;
    if (!coef)
        return -2;
    if (!comb)
        return -3;
    const int np = model_np(model);
    const int nc = model == IGEA_ACCEL_DUAL ? IGEA_ACCEL_NC_DUAL : IGEA_ACCEL_NC_SINGLE;
    for (int j = 0; j < np; j++)
        if (!isfinite(coef[j]))
            return IGEA_ENONFINITE;
    double C[IGEA_ACCEL_NP_DUAL * IGEA_ACCEL_NC_DUAL];
    fill_combinations(model, C, np);
    for (int k = 0; k < nc; k++) {
        double v = 0.0;
        for (int j = 0; j < np; j++)
            v += C[j + (size_t)k * np] * coef[j];
        comb[k] = v;
    }
    return 0;
}

/* SVD of the model's design at theta: s, V (np x np), rank. */
static int design_svd(int model, int n, const double *theta, double *s,
                      double *V, int *rank)
{
    int np = model_np(model);
    double *A = igea__dalloc((size_t)n * np);
    if (!A)
        return IGEA_ENOMEM;
    fill_design(model, n, theta, A, n);
    int st = svd_v(n, np, A, n, s, V, rank);
    free(A);
    return st;
}

int igea_accel_analyze(int model, int n, const double *theta_deg, double *sv,
                       double *null, int ldn, double *loading,
                       double *comb_loading, int *rank)
{
    if (!model_ok(model))
        return -1;
    if (n < 1)
        return -2;
    if (!theta_deg)
        return -3;
    if (!sv)
        return -4;
    int np = model_np(model), nc = model_nc(model);
    if (null ? ldn < np : ldn < 1)
        return -6;
    if (!rank)
        return -9;
    if (!igea__finite_vec(n, theta_deg, 1))
        return IGEA_ENONFINITE;
    double s[ACCEL_MAXP], V[ACCEL_MAXP * ACCEL_MAXP], nb[ACCEL_MAXP * ACCEL_MAXP];
    double C[ACCEL_MAXP * ACCEL_MAXP];
    int r;
    int st = design_svd(model, n, theta_deg, s, V, &r);
    if (st != 0)
        return st;
    memcpy(sv, s, (size_t)np * sizeof(double));
    if (null) {
        null_canonical(np, r, V, nb);
        for (int j = 0; j < np; j++)
            memcpy(null + (size_t)j * ldn, nb + (size_t)j * np,
                   (size_t)np * sizeof(double));
    }
    if (loading) {
        for (int j = 0; j < np; j++) {
            double e[ACCEL_MAXP] = {0};
            e[j] = 1.0;
            loading[j] = null_loading(np, r, V, e);
        }
    }
    if (comb_loading) {
        fill_combinations(model, C, np);
        for (int j = 0; j < nc; j++) {
            const double *c = C + (size_t)j * np;
            double nrm = 0.0;
            for (int i = 0; i < np; i++)
                nrm += c[i] * c[i];
            comb_loading[j] = null_loading(np, r, V, c) / sqrt(nrm);
        }
    }
    *rank = r;
    return 0;
}

/* ---------------------------------------------------------------------- */

/* Arguments of igea_accel_fit: 0, -i, or the status of the data. */
static int fit_check(int model, int method, int n, const double *theta_deg,
                     const double *ya, const double *yb, const double *prior_scale,
                     int rule, double lam_floor, const double *coef)
{
    if (!model_ok(model))
        return -1;
    if (method != IGEA_ACCEL_LS && method != IGEA_ACCEL_EBR)
        return -2;
    if (n < 1)
        return -3;
    if (!theta_deg)
        return -4;
    if (!ya)
        return -5;
    if (model == IGEA_ACCEL_DUAL && !yb)
        return -6;
    int ebr = method == IGEA_ACCEL_EBR;
    if (ebr && rule != IGEA_REGRESS_EBR_SC && rule != IGEA_REGRESS_EBR_MM &&
        rule != IGEA_REGRESS_EBR_ML2)
        return -8;
    if (ebr && !(lam_floor >= 0.0 && isfinite(lam_floor)))
        return -9;
    if (!coef)
        return -10;
    if (!igea__finite_vec(n, theta_deg, 1) || !igea__finite_vec(n, ya, 1) ||
        (model == IGEA_ACCEL_DUAL && !igea__finite_vec(n, yb, 1)))
        return IGEA_ENONFINITE;
    if (ebr && prior_scale)
        return igea__sigma_vec(model_np(model), prior_scale);
    return 0;
}

/* Which coefficients the data determine (the null space of the design A
 * itself, not of A D_s: flg), the combinations C^T x (cmb) and their sds
 * sqrt(c^T cov c) (cmbsd; NaN when not estimable). cov is LS's sigma^2
 * pinv(A^T A) or EBR's posterior (METHODS 4.3 step 7). */
static int fit_identify(int model, int n, const double *A, const double *x,
                        const double *cov, int *flg, double *cmb, double *cmbsd)
{
    int np = model_np(model), nc = model_nc(model), r = 0;
    double s[ACCEL_MAXP], V[ACCEL_MAXP * ACCEL_MAXP], C[ACCEL_MAXP * ACCEL_MAXP];
    int st = svd_v(n, np, A, n, s, V, &r);
    if (st != 0)
        return st;
    for (int j = 0; j < np; j++) {
        double e[ACCEL_MAXP] = {0};
        e[j] = 1.0;
        flg[j] = null_loading(np, r, V, e) > IGEA_ACCEL_LOADING_TOL ? IGEA_ACCEL_PRIOR
                                                                     : IGEA_ACCEL_DATA;
    }
    fill_combinations(model, C, np);
    for (int k = 0; k < nc; k++) {
        const double *c = C + (size_t)k * np;
        double v = 0.0, nrm = 0.0;
        for (int j = 0; j < np; j++) {
            v += c[j] * x[j];
            nrm += c[j] * c[j];
        }
        cmb[k] = v;
        if (null_loading(np, r, V, c) / sqrt(nrm) > IGEA_ACCEL_LOADING_TOL) {
            cmbsd[k] = NAN;
            continue;
        }
        double var = 0.0;
        for (int i = 0; i < np; i++)
            for (int j = 0; j < np; j++)
                var += c[i] * cov[i + j * np] * c[j];
        cmbsd[k] = sqrt(fmax(var, 0.0));
    }
    return 0;
}

/* info of a fit: the residuals of the fit actually returned. */
static void fit_info(int n, int np, const double *A, const double *y, const double *x,
                     int rank_ls, double sigma2, double lam, double *inf)
{
    size_t nn = (size_t)n;
    igea__ksum rss = {0, 0};
    for (size_t i = 0; i < nn; i++) {
        double f = 0.0;
        for (int j = 0; j < np; j++)
            f += A[i + j * nn] * x[j];
        double e = y[i] - f;
        igea__ksum_add(&rss, e * e);
    }
    inf[IGEA_ACCEL_INFO_RANK] = rank_ls;
    inf[IGEA_ACCEL_INFO_SIGMA] = sqrt(sigma2);
    inf[IGEA_ACCEL_INFO_LAMBDA] = lam;
    inf[IGEA_ACCEL_INFO_RMS] = sqrt(igea__ksum_get(&rss) / (double)n);
    inf[IGEA_ACCEL_INFO_NOBS] = n;
    inf[IGEA_ACCEL_INFO_DOF] = n - rank_ls;
    inf[IGEA_ACCEL_INFO_ITER] = 0;
    inf[IGEA_ACCEL_INFO_STEP] = 0;
}

int igea_accel_fit(int model, int method, int n, const double *theta_deg,
                   const double *ya, const double *yb,
                   const double *prior_scale, int rule, double lam_floor,
                   double *coef, double *sd, int *flag, double *comb,
                   double *comb_sd, double *info)
{
    int st = fit_check(model, method, n, theta_deg, ya, yb, prior_scale, rule,
                       lam_floor, coef);
    if (st)
        return st;
    int ebr = method == IGEA_ACCEL_EBR;
    int np = model_np(model), nc = model_nc(model);
    size_t nn = (size_t)n;
    double *A = igea__dalloc(nn * np + 2 * nn);
    if (!A)
        return IGEA_ENOMEM;
    double *y = A + nn * np, *res = y + nn;
    fill_design(model, n, theta_deg, A, n);
    observe(model, n, theta_deg, ya, yb, y);

    double x[ACCEL_MAXP], cov[ACCEL_MAXP * ACCEL_MAXP], sdv[ACCEL_MAXP];
    double cmb[ACCEL_MAXP], cmbsd[ACCEL_MAXP], inf[IGEA_ACCEL_INFO_LEN];
    int flg[ACCEL_MAXP];
    int rank_ls = 0;
    double sigma2 = 0.0, lam = 0.0;
    /* LS always: the solution for LS, sigma^2 = S / (n - r) for both. */
    st = igea_regress_ls(n, np, A, n, y, NULL, NULL, 0.0, x, cov, np, &rank_ls,
                             &sigma2, res);
    if (st != 0)
        goto done;
    if (ebr) {
        /* EBR's solution and posterior covariance replace LS's. */
        int rank_ebr;
        double s2_ebr;
        st = igea_regress_ebr(n, np, A, n, y, NULL, prior_scale, rule, lam_floor, x,
                              cov, np, &lam, &rank_ebr, &s2_ebr, NULL, NULL, NULL);
        if (st != 0)
            goto done;
    }
    for (int j = 0; j < np; j++)
        sdv[j] = sqrt(fmax(cov[j + j * np], 0.0));
    st = fit_identify(model, n, A, x, cov, flg, cmb, cmbsd);
    if (st != 0)
        goto done;
    /* No residual degrees of freedom: sigma is unknown, so are the sds. */
    if (n == rank_ls) {
        for (int j = 0; j < np; j++)
            sdv[j] = NAN;
        for (int k = 0; k < nc; k++)
            cmbsd[k] = NAN;
    }
    fit_info(n, np, A, y, x, rank_ls, sigma2, ebr ? lam : 0.0, inf);
    /* Every output finite except the documented NaN of a standard
     * deviation that cannot be estimated. */
    if (!igea__finite_vec(np, x, 1) || !igea__finite_vec(nc, cmb, 1) ||
        !igea__finite_vec(IGEA_ACCEL_INFO_LEN, inf, 1)) {
        st = IGEA_EOVERFLOW;
        goto done;
    }
    for (int j = 0; j < np; j++)
        if (isinf(sdv[j]) || (isnan(sdv[j]) && n != rank_ls)) {
            st = IGEA_EOVERFLOW;
            goto done;
        }

    memcpy(coef, x, (size_t)np * sizeof(double));
    if (sd)
        memcpy(sd, sdv, (size_t)np * sizeof(double));
    if (flag)
        memcpy(flag, flg, (size_t)np * sizeof(int));
    if (comb)
        memcpy(comb, cmb, (size_t)nc * sizeof(double));
    if (comb_sd)
        memcpy(comb_sd, cmbsd, (size_t)nc * sizeof(double));
    if (info)
        memcpy(info, inf, sizeof inf);
done:
    free(A);
    return st;
}

/* ---------------------------------------------------------------------- */

/* Exact models (1)-(2) at angle phi (rad) for coefficients K (dual order):
 * values and derivatives with respect to phi. */
static void exact_models(const double *K, double phi, double *fa, double *fb,
                         double *dfa, double *dfb, double *ja, double *jb)
{
    double sa = sin(phi), ca = cos(phi);
    double b = phi + K[IGEA_ACCEL_ETA];
    double sb = sin(b), cb = cos(b);
    *fa = K[IGEA_ACCEL_KA0] + (1.0 + K[IGEA_ACCEL_KA1]) * sa +
          K[IGEA_ACCEL_KA2] * sa * sa + K[IGEA_ACCEL_KAIX] * sa * ca;
    *fb = K[IGEA_ACCEL_KB0] + (1.0 + K[IGEA_ACCEL_KB1]) * cb +
          K[IGEA_ACCEL_KB2] * cb * cb - K[IGEA_ACCEL_KBIX] * cb * sb;
    *dfa = (1.0 + K[IGEA_ACCEL_KA1]) * ca + 2.0 * K[IGEA_ACCEL_KA2] * sa * ca +
           K[IGEA_ACCEL_KAIX] * (ca * ca - sa * sa);
    *dfb = -(1.0 + K[IGEA_ACCEL_KB1]) * sb - 2.0 * K[IGEA_ACCEL_KB2] * cb * sb -
           K[IGEA_ACCEL_KBIX] * (cb * cb - sb * sb);
    if (ja) {
        for (int j = 0; j < IGEA_ACCEL_NP_DUAL; j++)
            ja[j] = jb[j] = 0.0;
        ja[IGEA_ACCEL_KA0] = 1.0;
        ja[IGEA_ACCEL_KA1] = sa;
        ja[IGEA_ACCEL_KA2] = sa * sa;
        ja[IGEA_ACCEL_KAIX] = sa * ca;
        jb[IGEA_ACCEL_KB0] = 1.0;
        jb[IGEA_ACCEL_KB1] = cb;
        jb[IGEA_ACCEL_ETA] = *dfb;
        jb[IGEA_ACCEL_KB2] = cb * cb;
        jb[IGEA_ACCEL_KBIX] = -cb * sb;
    }
}

/* Coefficients K = coef0 + V_r u of the parameters p = (u[r], angle
 * offsets[n]). */
static void refine_coef(int r, const double *V, const double *coef0,
                        const double *p, double *K)
{
    const int np = IGEA_ACCEL_NP_DUAL;
    for (int j = 0; j < np; j++) {
        K[j] = coef0[j];
        for (int q = 0; q < r; q++)
            K[j] += V[j + (size_t)q * np] * p[q];
    }
}

/* Residuals res (2n: A outputs, then B) of the exact models at p and their
 * Jacobian J (2n x (r + n)) with respect to p. */
static void refine_jacobian(int n, int r, const double *V, const double *coef0,
                            const double *psi, const double *ya, const double *yb,
                            const double *p, double *J, double *res)
{
    const int np = IGEA_ACCEL_NP_DUAL;
    size_t nn = (size_t)n, m = 2 * nn, nu = (size_t)r + nn;
    double K[ACCEL_MAXP], ja[ACCEL_MAXP], jb[ACCEL_MAXP];
    refine_coef(r, V, coef0, p, K);
    for (size_t i = 0; i < m * nu; i++)
        J[i] = 0.0;
    for (size_t i = 0; i < nn; i++) {
        double fa, fb, dfa, dfb;
        exact_models(K, psi[i] + p[r + i], &fa, &fb, &dfa, &dfb, ja, jb);
        res[i] = ya[i] - fa;
        res[nn + i] = yb[i] - fb;
        for (int q = 0; q < r; q++) {
            double ua = 0.0, ub = 0.0;
            for (int j = 0; j < np; j++) {
                ua += ja[j] * V[j + (size_t)q * np];
                ub += jb[j] * V[j + (size_t)q * np];
            }
            J[i + q * m] = ua;
            J[nn + i + q * m] = ub;
        }
        J[i + (r + i) * m] = dfa;
        J[nn + i + (r + i) * m] = dfb;
    }
}

/* The converged coefficients out, their sds sdo from the covariance cv
 * (nu x nu) of p, and the residual sum of squares. */
static void refine_result(int n, int r, const double *V, const double *coef0,
                          const double *psi, const double *ya, const double *yb,
                          const double *p, const double *cv, double *out,
                          double *sdo, double *rss_out)
{
    const int np = IGEA_ACCEL_NP_DUAL;
    size_t nn = (size_t)n, nu = (size_t)r + nn;
    igea__ksum rss = {0, 0};
    refine_coef(r, V, coef0, p, out);
    for (int j = 0; j < np; j++) {
        double v = 0.0;
        for (int a = 0; a < r; a++)
            for (int b = 0; b < r; b++)
                v += V[j + (size_t)a * np] * cv[a + (size_t)b * nu] * V[j + (size_t)b * np];
        sdo[j] = sqrt(fmax(v, 0.0));
    }
    for (size_t i = 0; i < nn; i++) {
        double fa, fb, dfa, dfb;
        exact_models(out, psi[i] + p[r + i], &fa, &fb, &dfa, &dfb, NULL, NULL);
        igea__ksum_add(&rss, (ya[i] - fa) * (ya[i] - fa));
        igea__ksum_add(&rss, (yb[i] - fb) * (yb[i] - fb));
    }
    *rss_out = igea__ksum_get(&rss);
}

/* Start: u = 0, angles from the outputs themselves (y_A ~ sin phi, y_B ~
 * cos phi), as offsets from the nominal angles psi (rad). */
static void refine_start(int n, int r, const double *theta_deg, const double *ya,
                         const double *yb, double *p, double *psi)
{
    for (int i = 0; i < r + n; i++)
        p[i] = 0.0;
    for (int i = 0; i < n; i++) {
        double th = fmod(theta_deg[i], 360.0) * (ACCEL_PI / 180.0);
        double d = atan2(ya[i], yb[i]) - th;
        d = remainder(d, 2.0 * ACCEL_PI);
        p[r + i] = d;
        psi[i] = th;
    }
}

typedef struct {
    int n, r;
    const double *V, *coef0, *psi, *ya, *yb;
} refine_data;

/* Gauss-Newton on p until the largest step is <= tol: each step the
 * minimum-norm least-squares solution dp of J dp = res (its covariance in
 * cv). Returns 0, IGEA_ENOCONV or a failure of igea_regress_ls. */
static int refine_gauss_newton(const refine_data *d, int max_iter, double tol, double *p,
                               double *J, double *res, double *rres, double *dp,
                               double *cv, int *it_out, int *rk, double *step_out,
                               double *sigma2)
{
    size_t m = 2 * (size_t)d->n, nu = (size_t)d->r + (size_t)d->n;
    for (int it = 1; it <= max_iter; it++) {
        refine_jacobian(d->n, d->r, d->V, d->coef0, d->psi, d->ya, d->yb, p, J, res);
        int st = igea_regress_ls((int)m, (int)nu, J, (int)m, res, NULL, NULL, 0.0, dp, cv,
                                 (int)nu, rk, sigma2, rres);
        if (st != 0)
            return st;
        double step = 0.0;
        for (size_t i = 0; i < nu; i++) {
            p[i] += dp[i];
            step = fmax(step, fabs(dp[i]));
        }
        *it_out = it;
        *step_out = step;
        if (step <= tol)
            return 0;
    }
    return IGEA_ENOCONV;
}

int igea_accel_refine(int n, const double *theta_deg, const double *ya,
                      const double *yb, const double *coef0, int max_iter,
                      double tol, double *coef, double *sd, double *phi_deg,
                      double *info)
{
    const int np = IGEA_ACCEL_NP_DUAL;
    if (n < 1)
        return -1;
    if (!theta_deg)
        return -2;
    if (!ya)
        return -3;
    if (!yb)
        return -4;
    if (!coef0)
        return -5;
    if (max_iter < 1)
        return -6;
    if (!(tol > 0.0) || !isfinite(tol))
        return -7;
    if (!coef)
        return -8;
    if (!igea__finite_vec(n, theta_deg, 1) || !igea__finite_vec(n, ya, 1) ||
        !igea__finite_vec(n, yb, 1) || !igea__finite_vec(np, coef0, 1))
        return IGEA_ENONFINITE;

    double s[ACCEL_MAXP], V[ACCEL_MAXP * ACCEL_MAXP];
    int r;
    int st = design_svd(IGEA_ACCEL_DUAL, n, theta_deg, s, V, &r);
    if (st != 0)
        return st;
    size_t nn = (size_t)n, m = 2 * nn, nu = (size_t)r + nn;
    double *J = igea__dalloc(m * nu + 2 * m + 2 * nu + nu * nu + nn);
    if (!J)
        return IGEA_ENOMEM;
    double *res = J + m * nu, *rres = res + m, *p = rres + m, *dp = p + nu,
           *cv = dp + nu, *psi = cv + nu * nu;
    refine_start(n, r, theta_deg, ya, yb, p, psi);
    int it = 0, rk = 0;
    double step = 0.0, sigma2 = 0.0;
    const refine_data d = {n, r, V, coef0, psi, ya, yb};
    st = refine_gauss_newton(&d, max_iter, tol, p, J, res, rres, dp, cv, &it, &rk, &step,
                             &sigma2);
    if (st != 0)
        goto done;
    {
        double out[ACCEL_MAXP], sdo[ACCEL_MAXP], rss;
        refine_result(n, r, V, coef0, psi, ya, yb, p, cv, out, sdo, &rss);
        if (!igea__finite_vec(np, out, 1) || !igea__finite_vec(np, sdo, 1) ||
            !igea__finite_vec((int)nu, p, 1) || !isfinite(sigma2) || !isfinite(rss)) {
            st = IGEA_EOVERFLOW;
            goto done;
        }
        memcpy(coef, out, (size_t)np * sizeof(double));
        if (sd)
            memcpy(sd, sdo, (size_t)np * sizeof(double));
        if (phi_deg)
            for (size_t i = 0; i < nn; i++)
                phi_deg[i] = theta_deg[i] + p[r + i] * (180.0 / ACCEL_PI);
        if (info) {
            info[IGEA_ACCEL_INFO_RANK] = r;
            info[IGEA_ACCEL_INFO_SIGMA] = sqrt(sigma2);
            info[IGEA_ACCEL_INFO_LAMBDA] = 0.0;
            info[IGEA_ACCEL_INFO_RMS] = sqrt(rss / (double)m);
            info[IGEA_ACCEL_INFO_NOBS] = (double)m;
            info[IGEA_ACCEL_INFO_DOF] = (double)m - (double)rk;
            info[IGEA_ACCEL_INFO_ITER] = it;
            info[IGEA_ACCEL_INFO_STEP] = step;
        }
    }
done:
    free(J);
    return st;
}

/* ---------------------------------------------------------------------- */

int igea_accel_simulate(int n, const double *theta_deg, const double *truth,
                        double head_sd, double noise_sd, int seed, double *ya,
                        double *yb)
{
    if (n < 1)
        return -1;
    if (!theta_deg)
        return -2;
    if (!truth)
        return -3;
    if (!(head_sd >= 0.0) || !isfinite(head_sd))
        return -4;
    if (!(noise_sd >= 0.0) || !isfinite(noise_sd))
        return -5;
    if (seed < 0)
        return -6;
    if (!ya)
        return -7;
    if (!igea__finite_vec(n, theta_deg, 1) ||
        !igea__finite_vec(IGEA_ACCEL_NP_SIM, truth, 1))
        return IGEA_ENONFINITE;
    double *buf = igea__dalloc(2 * (size_t)n);
    if (!buf)
        return IGEA_ENOMEM;
    gsl_rng *rng = igea__rng_new(gsl_rng_mt19937, 0);
    if (!rng) {
        free(buf);
        return IGEA_ENOMEM;
    }
    gsl_rng_set(rng, (unsigned long)seed);
    for (int i = 0; i < n; i++) {
        double dth = head_sd > 0.0 ? gsl_ran_gaussian(rng, head_sd) : 0.0;
        double ea = noise_sd > 0.0 ? gsl_ran_gaussian(rng, noise_sd) : 0.0;
        double eb = noise_sd > 0.0 ? gsl_ran_gaussian(rng, noise_sd) : 0.0;
        double th = fmod(theta_deg[i], 360.0) * (ACCEL_PI / 180.0);
        double phi = th + dth + truth[IGEA_ACCEL_SIM_DELTA0];
        double fa, fb, dfa, dfb;
        exact_models(truth, phi, &fa, &fb, &dfa, &dfb, NULL, NULL);
        buf[i] = fa + ea;
        buf[n + i] = fb + eb;
    }
    igea__rng_free(rng);
    memcpy(ya, buf, (size_t)n * sizeof(double));
    if (yb)
        memcpy(yb, buf + n, (size_t)n * sizeof(double));
    free(buf);
    return 0;
}

/* ---------------------------------------------------------------------- */
/* Applying a calibration. */

#define APPLY_MAXIT 50

/* Single model: solve y = K0 + (1 + k1) u + d0 v + K2 u^2 + Kix u v for u
 * by Newton from u = y. Returns 0 or IGEA_ENOCONV. */
static int apply_single(const double *K, double y, double v, double *u_out)
{
    double u = y;
    for (int it = 0; it < APPLY_MAXIT; it++) {
        double f = K[IGEA_ACCEL_K0] + (1.0 + K[IGEA_ACCEL_K1]) * u +
                   K[IGEA_ACCEL_DELTA0] * v + K[IGEA_ACCEL_K2] * u * u +
                   K[IGEA_ACCEL_KIX] * u * v - y;
        double df = 1.0 + K[IGEA_ACCEL_K1] + 2.0 * K[IGEA_ACCEL_K2] * u +
                    K[IGEA_ACCEL_KIX] * v;
        if (!(fabs(df) > 0.0) || !isfinite(f))
            return IGEA_ENOCONV;
        double du = f / df;
        u -= du;
        if (!isfinite(u))
            return IGEA_ENOCONV;
        if (fabs(du) <= 4.0 * DBL_EPSILON * fmax(1.0, fmax(fabs(u), fabs(v)))) {
            *u_out = u;
            return 0;
        }
    }
    return IGEA_ENOCONV;
}

/* Dual pair: the exact models (1)-(2) as functions of the in-plane
 * acceleration (u along A's input axis, v perpendicular towards B), and
 * their Jacobian. */
static void apply_dual_eval(const double *K, double ce, double se, double u, double v,
                            double *fa, double *fb, double *J)
{
    double b = v * ce - u * se, w = u * ce + v * se;
    *fa = K[IGEA_ACCEL_KA0] + (1.0 + K[IGEA_ACCEL_KA1]) * u + K[IGEA_ACCEL_KA2] * u * u +
          K[IGEA_ACCEL_KAIX] * u * v;
    *fb = K[IGEA_ACCEL_KB0] + (1.0 + K[IGEA_ACCEL_KB1]) * b + K[IGEA_ACCEL_KB2] * b * b -
          K[IGEA_ACCEL_KBIX] * b * w;
    double dfb_db = 1.0 + K[IGEA_ACCEL_KB1] + 2.0 * K[IGEA_ACCEL_KB2] * b -
                    K[IGEA_ACCEL_KBIX] * w;
    double dfb_dw = -K[IGEA_ACCEL_KBIX] * b;
    J[0] = 1.0 + K[IGEA_ACCEL_KA1] + 2.0 * K[IGEA_ACCEL_KA2] * u + K[IGEA_ACCEL_KAIX] * v;
    J[1] = K[IGEA_ACCEL_KAIX] * u;
    J[2] = -dfb_db * se + dfb_dw * ce; /* d fb / du */
    J[3] = dfb_db * ce + dfb_dw * se;  /* d fb / dv */
}

static int apply_dual(const double *K, double ya, double yb, double *u_out, double *v_out)
{
    double ce = cos(K[IGEA_ACCEL_ETA]), se = sin(K[IGEA_ACCEL_ETA]);
    double u = ya, v = yb;
    for (int it = 0; it < APPLY_MAXIT; it++) {
        double fa, fb, J[4];
        apply_dual_eval(K, ce, se, u, v, &fa, &fb, J);
        fa -= ya;
        fb -= yb;
        double det = J[0] * J[3] - J[1] * J[2];
        if (!(fabs(det) > 0.0) || !isfinite(det) || !isfinite(fa) || !isfinite(fb))
            return IGEA_ENOCONV;
        double du = (J[3] * fa - J[1] * fb) / det;
        double dv = (J[0] * fb - J[2] * fa) / det;
        u -= du;
        v -= dv;
        if (!isfinite(u) || !isfinite(v))
            return IGEA_ENOCONV;
        double big = fmax(1.0, fmax(fabs(u), fabs(v)));
        if (fmax(fabs(du), fabs(dv)) <= 4.0 * DBL_EPSILON * big) {
            *u_out = u;
            *v_out = v;
            return 0;
        }
    }
    return IGEA_ENOCONV;
}

static int apply_check(int model, int n, const double *raw_a, const double *raw_b,
                       double scale_a, double scale_b, const double *coef,
                       const double *cross, const double *u)
{
    if (!model_ok(model))
        return -1;
    if (n < 1)
        return -2;
    if (!raw_a)
        return -3;
    int dual = model == IGEA_ACCEL_DUAL;
    if (dual && !raw_b)
        return -4;
    if (!isfinite(scale_a) || scale_a == 0.0)
        return -5;
    if (dual && (!isfinite(scale_b) || scale_b == 0.0))
        return -6;
    if (!coef)
        return -7;
    if (!u)
        return -9;
    if (!igea__finite_vec(n, raw_a, 1) || (dual && !igea__finite_vec(n, raw_b, 1)) ||
        !igea__finite_vec(model_np(model), coef, 1) ||
        (!dual && cross && !igea__finite_vec(n, cross, 1)))
        return IGEA_ENONFINITE;
    return 0;
}

int igea_accel_apply(int model, int n, const double *raw_a, const double *raw_b,
                     double scale_a, double scale_b, const double *coef,
                     const double *cross, double *u, double *v)
{
    int st = apply_check(model, n, raw_a, raw_b, scale_a, scale_b, coef, cross, u);
    if (st)
        return st;
    int dual = model == IGEA_ACCEL_DUAL;
    double *buf = igea__dalloc(2 * (size_t)n);
    if (!buf)
        return IGEA_ENOMEM;
    for (int i = 0; i < n && st == 0; i++) {
        double ya = raw_a[i] / scale_a;
        if (dual)
            st = apply_dual(coef, ya, raw_b[i] / scale_b, buf + i, buf + n + i);
        else
            st = apply_single(coef, ya, cross ? cross[i] : 0.0, buf + i);
    }
    if (st == 0) {
        memcpy(u, buf, (size_t)n * sizeof(double));
        if (dual && v)
            memcpy(v, buf + n, (size_t)n * sizeof(double));
    }
    free(buf);
    return st;
}

/* ---------------------------------------------------------------------- */
/* Hysteresis: clockwise minus counter-clockwise per position. */

/* Directions from the row order (see the header): +1 clockwise (angle
 * decreasing), -1 counter-clockwise. Rows within tol of the previous row
 * form a block; a block takes the direction of the step into it (the first
 * block: out of it); a block where the direction reverses is split, its
 * first ceil(len / 2) rows going with the incoming run. Returns 0 or
 * IGEA_EDOMAIN (no change of angle at all). */
static int hyst_directions(int n, const double *ang, double tol, int *d)
{
    int any = 0;
    for (int b = 0, din = 0; b < n;) {
        int e = b + 1, dout = 0;
        while (e < n && fabs(remainder(ang[e] - ang[e - 1], 360.0)) <= tol)
            e++;
        if (e < n)
            dout = remainder(ang[e] - ang[e - 1], 360.0) > 0.0 ? -1 : 1;
        int len = e - b, first = din ? din : dout;
        int split = (din && dout && din != dout) ? (len + 1) / 2 : len;
        for (int i = b; i < e; i++)
            d[i] = i - b < split ? first : dout;
        any |= dout != 0;
        din = dout;
        b = e;
    }
    return any ? 0 : IGEA_EDOMAIN;
}

typedef struct {
    double t, d, sd;
    int ncw, nccw;
} hyst_pos;

/* Group sorted readings into positions; per position the cell means and
 * the within-cell sum of squares (added to *ss). Returns the number of
 * positions or IGEA_EDOMAIN (a position lacking a direction). */
static int hyst_group(int n, const angle_idx *ai, const int *d, const double *y, double tol,
                      hyst_pos *pos, double *ss)
{
    int np = 0;
    igea__ksum acc = {0, 0};
    for (int k = 0; k < n;) {
        int e = k + 1;
        while (e < n && ai[e].a - ai[k].a <= tol)
            e++;
        double sa = 0.0, sum[2] = {0, 0};
        int cnt[2] = {0, 0};
        for (int q = k; q < e; q++) {
            int c = d[ai[q].idx] > 0 ? 0 : 1;
            sa += ai[q].a;
            sum[c] += y[ai[q].idx];
            cnt[c]++;
        }
        if (!cnt[0] || !cnt[1])
            return IGEA_EDOMAIN;
        double m0 = sum[0] / cnt[0], m1 = sum[1] / cnt[1];
        for (int q = k; q < e; q++) {
            double r = y[ai[q].idx] - (d[ai[q].idx] > 0 ? m0 : m1);
            igea__ksum_add(&acc, r * r);
        }
        pos[np].t = sa / (double)(e - k);
        pos[np].d = m0 - m1;
        pos[np].ncw = cnt[0];
        pos[np].nccw = cnt[1];
        np++;
        k = e;
    }
    *ss = igea__ksum_get(&acc);
    return np;
}

static int hyst_check(int nrows, const double *angle_deg, const int *dir, const double *y,
                      double tol_deg, const double *theta_deg, const double *diff,
                      const int *npos)
{
    if (nrows < 1)
        return -1;
    if (!angle_deg)
        return -2;
    if (!y)
        return -4;
    if (!(tol_deg >= 0.0 && tol_deg < 45.0))
        return -5;
    if (!theta_deg)
        return -6;
    if (!diff)
        return -7;
    if (!npos)
        return -11;
    if (dir)
        for (int i = 0; i < nrows; i++)
            if (dir[i] == 0)
                return -3;
    if (!igea__finite_vec(nrows, angle_deg, 1) || !igea__finite_vec(nrows, y, 1))
        return IGEA_ENONFINITE;
    return 0;
}

/* The test of zero hysteresis from the positions and the pooled sum of
 * squares; fills pos[].sd. Returns 0 or IGEA_EDOMAIN. */
static int hyst_test(int nrows, int np, double ss, hyst_pos *pos, double *tst)
{
    int df2 = nrows - 2 * np;
    if (df2 < 1)
        return IGEA_EDOMAIN;
    double s2 = ss / df2, chi = 0.0;
    if (!(s2 > 0.0) || !isfinite(s2))
        return IGEA_EDOMAIN;
    for (int k = 0; k < np; k++) {
        pos[k].sd = sqrt(s2 * (1.0 / pos[k].ncw + 1.0 / pos[k].nccw));
        double z = pos[k].d / pos[k].sd;
        chi += z * z;
    }
    double F = chi / np;
    if (!isfinite(F))
        return IGEA_EDOMAIN;
    tst[IGEA_ACCEL_HYST_F] = F;
    tst[IGEA_ACCEL_HYST_DF1] = np;
    tst[IGEA_ACCEL_HYST_DF2] = df2;
    tst[IGEA_ACCEL_HYST_P] = gsl_cdf_fdist_Q(F, np, df2);
    tst[IGEA_ACCEL_HYST_SIGMA] = sqrt(s2);
    return 0;
}

int igea_accel_hysteresis(int nrows, const double *angle_deg, const int *dir,
                          const double *y, double tol_deg, double *theta_deg,
                          double *diff, double *diff_sd, int *n_cw, int *n_ccw,
                          int *npos, double *test)
{
    int st = hyst_check(nrows, angle_deg, dir, y, tol_deg, theta_deg, diff, npos);
    if (st)
        return st;
    angle_idx *ai = malloc((size_t)nrows * sizeof *ai);
    hyst_pos *pos = malloc((size_t)nrows * sizeof *pos);
    int *d = igea__ialloc((size_t)nrows);
    if (!ai || !pos || !d) {
        st = IGEA_ENOMEM;
        goto done;
    }
    if (dir)
        for (int i = 0; i < nrows; i++)
            d[i] = dir[i] > 0 ? 1 : -1;
    else if ((st = hyst_directions(nrows, angle_deg, tol_deg, d)) != 0)
        goto done;
    sort_angles(nrows, angle_deg, tol_deg, ai);
    double ss = 0.0, tst[IGEA_ACCEL_HYST_LEN];
    int np = hyst_group(nrows, ai, d, y, tol_deg, pos, &ss);
    if (np < 0) {
        st = np;
        goto done;
    }
    if ((st = hyst_test(nrows, np, ss, pos, tst)) != 0)
        goto done;
    for (int k = 0; k < np; k++) {
        theta_deg[k] = pos[k].t;
        diff[k] = pos[k].d;
        if (diff_sd)
            diff_sd[k] = pos[k].sd;
        if (n_cw)
            n_cw[k] = pos[k].ncw;
        if (n_ccw)
            n_ccw[k] = pos[k].nccw;
    }
    *npos = np;
    if (test)
        memcpy(test, tst, sizeof tst);
done:
    free(ai);
    free(pos);
    free(d);
    return st;
}

/* ---------------------------------------------------------------------- */
/* The joint model: radial (g^2) and tangential equations stacked. */

/* Tangential row at one angle: z = c r_A - s r_B (docs/accel.md). */
static void tangential_row(double deg, double *row)
{
    double s, c;
    sincosd(deg, &s, &c);
    row[IGEA_ACCEL_KA0] = c;
    row[IGEA_ACCEL_KB0] = -s;
    row[IGEA_ACCEL_KA1] = s * c;
    row[IGEA_ACCEL_KB1] = -s * c;
    row[IGEA_ACCEL_ETA] = s * s;
    row[IGEA_ACCEL_KA2] = s * s * c;
    row[IGEA_ACCEL_KB2] = -s * c * c;
    row[IGEA_ACCEL_KAIX] = s * c * c;
    row[IGEA_ACCEL_KBIX] = s * s * c;
    row[IGEA_ACCEL_SIM_DELTA0] = 1.0;
}

/* Stacked design J (2n x 10, ld 2n) and observations z (2n): rows 0..n-1
 * radial, n..2n-1 tangential. */
static void joint_system(int n, const double *theta, const double *ya, const double *yb,
                         double *J, double *z)
{
    size_t m = 2 * (size_t)n;
    double row[IGEA_ACCEL_NP_JOINT];
    observe(IGEA_ACCEL_DUAL, n, theta, ya, yb, z);
    for (int i = 0; i < n; i++) {
        double s, c;
        design_row(IGEA_ACCEL_DUAL, theta[i], row);
        row[IGEA_ACCEL_SIM_DELTA0] = 0.0;
        for (int j = 0; j < IGEA_ACCEL_NP_JOINT; j++)
            J[i + j * m] = row[j];
        tangential_row(theta[i], row);
        for (int j = 0; j < IGEA_ACCEL_NP_JOINT; j++)
            J[n + i + j * m] = row[j];
        sincosd(theta[i], &s, &c);
        z[n + i] = c * (ya[i] - s) - s * (yb[i] - c);
    }
}

/* Residual variance of one block (rows off..off+n-1 of J, z) by LS.
 * Returns 0, IGEA_EDOMAIN (no residual or zero variance) or a status of
 * igea_regress_ls. */
static int joint_block_var(int n, const double *J, int ldj, const double *z, double *work,
                           double *var)
{
    const int np = IGEA_ACCEL_NP_JOINT;
    double x[IGEA_ACCEL_NP_JOINT];
    int rank = 0;
    for (int j = 0; j < np; j++)
        memcpy(work + (size_t)j * n, J + (size_t)j * ldj, (size_t)n * sizeof(double));
    int st = igea_regress_ls(n, np, work, n, z, NULL, NULL, 0.0, x, NULL, 1, &rank, var,
                             NULL);
    if (st)
        return st;
    if (rank >= n || !(*var > 0.0) || !isfinite(*var))
        return IGEA_EDOMAIN;
    return 0;
}

static int joint_check(int n, const double *theta_deg, const double *ya, const double *yb,
                       const double *coef, const double *cov, int ldc)
{
    if (n < 1)
        return -1;
    if (!theta_deg)
        return -2;
    if (!ya)
        return -3;
    if (!yb)
        return -4;
    if (!coef)
        return -5;
    if (cov ? ldc < IGEA_ACCEL_NP_JOINT : ldc < 1)
        return -8;
    if (!igea__finite_vec(n, theta_deg, 1) || !igea__finite_vec(n, ya, 1) ||
        !igea__finite_vec(n, yb, 1))
        return IGEA_ENONFINITE;
    return 0;
}

/* The weighted stacked solve: x, the unscaled covariance cv = (J^T W J)^-1,
 * info. */
static int joint_solve(int n, const double *J, const double *z, const double *vars,
                       double *w, double *x, double *cv, double *inf)
{
    const int np = IGEA_ACCEL_NP_JOINT;
    size_t m = 2 * (size_t)n;
    double *sig = w, *res = w + m;
    for (size_t i = 0; i < m; i++)
        sig[i] = sqrt(vars[i < (size_t)n ? 0 : 1]);
    int rank = 0;
    double s2 = 0.0;
    int st = igea_regress_ls((int)m, np, J, (int)m, z, sig, NULL, 0.0, x, cv, np, &rank, &s2,
                             res);
    if (st)
        return st;
    if (rank < np)
        return IGEA_ERANK;
    if (!(s2 > 0.0) || !isfinite(s2))
        return IGEA_EDOMAIN;
    for (int i = 0; i < np * np; i++)
        cv[i] /= s2;
    igea__ksum rss = {0, 0};
    for (size_t i = 0; i < m; i++)
        igea__ksum_add(&rss, res[i] * res[i] / (sig[i] * sig[i]));
    for (int k = 0; k < IGEA_ACCEL_INFO_LEN; k++)
        inf[k] = 0.0;
    inf[IGEA_ACCEL_INFO_RANK] = rank;
    inf[IGEA_ACCEL_INFO_SIGMA] = sqrt(s2);
    inf[IGEA_ACCEL_INFO_RMS] = sqrt(igea__ksum_get(&rss) / (double)m);
    inf[IGEA_ACCEL_INFO_NOBS] = (double)m;
    inf[IGEA_ACCEL_INFO_DOF] = (double)m - rank;
    return 0;
}

/* Combinations C^T x and their sds sqrt(c^T cv c) (cv 10 x 10, ld 10; the
 * combinations involve the 9 dual coefficients only). */
static void joint_combinations(const double *x, const double *cv, double *comb,
                               double *comb_sd)
{
    const int np = IGEA_ACCEL_NP_DUAL, ld = IGEA_ACCEL_NP_JOINT;
    double C[IGEA_ACCEL_NP_DUAL * IGEA_ACCEL_NC_DUAL];
    fill_combinations(IGEA_ACCEL_DUAL, C, np);
    for (int k = 0; k < IGEA_ACCEL_NC_DUAL; k++) {
        const double *c = C + (size_t)k * np;
        double v = 0.0, var = 0.0;
        for (int i = 0; i < np; i++) {
            v += c[i] * x[i];
            for (int j = 0; j < np; j++)
                var += c[i] * cv[i + j * ld] * c[j];
        }
        if (comb)
            comb[k] = v;
        if (comb_sd)
            comb_sd[k] = sqrt(fmax(var, 0.0));
    }
}

int igea_accel_joint(int n, const double *theta_deg, const double *ya, const double *yb,
                     double *coef, double *sd, double *cov, int ldc, double *comp_sd,
                     double *comb, double *comb_sd, double *info)
{
    const int np = IGEA_ACCEL_NP_JOINT;
    int st = joint_check(n, theta_deg, ya, yb, coef, cov, ldc);
    if (st)
        return st;
    if (n < np)
        return IGEA_ERANK;
    size_t m = 2 * (size_t)n;
    double *J = igea__dalloc(m * np + m + (size_t)n * np + 2 * m);
    if (!J)
        return IGEA_ENOMEM;
    double *z = J + m * np, *work = z + m, *w = work + (size_t)n * np;
    double vars[2], x[IGEA_ACCEL_NP_JOINT], cv[IGEA_ACCEL_NP_JOINT * IGEA_ACCEL_NP_JOINT];
    double inf[IGEA_ACCEL_INFO_LEN], sdv[IGEA_ACCEL_NP_JOINT];
    joint_system(n, theta_deg, ya, yb, J, z);
    st = joint_block_var(n, J, (int)m, z, work, &vars[0]);
    if (!st)
        st = joint_block_var(n, J + n, (int)m, z + n, work, &vars[1]);
    if (!st)
        st = joint_solve(n, J, z, vars, w, x, cv, inf);
    if (st)
        goto done;
    for (int j = 0; j < np; j++)
        sdv[j] = sqrt(fmax(cv[j + j * np], 0.0));
    if (!igea__finite_vec(np, x, 1) || !igea__finite_vec(np, sdv, 1) ||
        !igea__finite_vec(np * np, cv, 1) || !igea__finite_vec(IGEA_ACCEL_INFO_LEN, inf, 1)) {
        st = IGEA_EOVERFLOW;
        goto done;
    }
    memcpy(coef, x, sizeof x);
    if (sd)
        memcpy(sd, sdv, sizeof sdv);
    if (cov)
        for (int j = 0; j < np; j++)
            memcpy(cov + (size_t)j * ldc, cv + (size_t)j * np, np * sizeof(double));
    if (comp_sd) {
        comp_sd[IGEA_ACCEL_JOINT_SD_RADIAL] = sqrt(vars[0]);
        comp_sd[IGEA_ACCEL_JOINT_SD_ANGLE] = sqrt(vars[1]);
    }
    if (comb || comb_sd)
        joint_combinations(x, cv, comb, comb_sd);
    if (info)
        memcpy(info, inf, sizeof inf);
done:
    free(J);
    return st;
}
