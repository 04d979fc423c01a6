/* redund.c - redundant sensor sets: reliability, confidence-distance
 * consistency, fusion, parity-space FDI, windowed checks (METHODS 3.1-3.3). */
#include <float.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <lapacke.h>

#include "igea/redund.h"
#include "igea/stats.h"
#include "internal.h"

#define SQRT2 1.41421356237309504880

static int prob_ok(double p) { return p >= 0.0 && p <= 1.0; }

/* ---- reliability ------------------------------------------------------- */

int igea_redund_exponential(double lambda, double t, double *R, double *mtbf)
{
    if (!(isfinite(lambda) && lambda >= 0.0))
        return -1;
    if (!(isfinite(t) && t >= 0.0))
        return -2;
    if (!R)
        return -3;
    *R = exp(-lambda * t);
    if (mtbf)
        *mtbf = lambda > 0.0 ? 1.0 / lambda : INFINITY;
    return 0;
}

static int check_probs(int n, const double *R)
{
    for (int i = 0; i < n; i++)
        if (!prob_ok(R[i]))
            return 0;
    return 1;
}

/* Series / parallel of validated inputs. */
static double series_of(int n, const double *R)
{
    double p = 1.0;
    for (int i = 0; i < n; i++)
        p *= R[i];
    return p;
}
static double parallel_of(int n, const double *R)
{
    double q = 1.0;
    for (int i = 0; i < n; i++)
        q *= 1.0 - R[i];
    return 1.0 - q;
}
/* P(at least k of n work): Poisson-binomial recursion over the count of
 * working components, work[0..n]; complement used when k is small. */
static double kofn_of(int n, int k, const double *R, double *work)
{
    for (int j = 0; j <= n; j++)
        work[j] = 0.0;
    work[0] = 1.0;
    for (int i = 0; i < n; i++) {
        for (int j = i + 1; j >= 1; j--)
            work[j] = work[j] * (1.0 - R[i]) + work[j - 1] * R[i];
        work[0] *= 1.0 - R[i];
    }
    igea__ksum s = {0.0, 0.0};
    if (2 * k > n) {
        for (int j = k; j <= n; j++)
            igea__ksum_add(&s, work[j]);
        return igea__ksum_get(&s);
    }
    for (int j = 0; j < k; j++)
        igea__ksum_add(&s, work[j]);
    return 1.0 - igea__ksum_get(&s);
}

int igea_redund_reliability_series(int n, const double *R, double *out)
{
    if (n < 1)
        return -1;
    if (!R)
        return -2;
    if (!out)
        return -3;
    if (!igea__finite_vec(n, R, 1))
        return IGEA_ENONFINITE;
    if (!check_probs(n, R))
        return -2;
    *out = series_of(n, R);
    return 0;
}

int igea_redund_reliability_parallel(int n, const double *R, double *out)
{
    if (n < 1)
        return -1;
    if (!R)
        return -2;
    if (!out)
        return -3;
    if (!igea__finite_vec(n, R, 1))
        return IGEA_ENONFINITE;
    if (!check_probs(n, R))
        return -2;
    *out = parallel_of(n, R);
    return 0;
}

int igea_redund_reliability_kofn(int n, int k, const double *R, double *out)
{
    if (n < 1)
        return -1;
    if (k < 1 || k > n)
        return -2;
    if (!R)
        return -3;
    if (!out)
        return -4;
    if (!igea__finite_vec(n, R, 1))
        return IGEA_ENONFINITE;
    if (!check_probs(n, R))
        return -3;
    double *work = igea__dalloc((size_t)n + 1);
    if (!work)
        return IGEA_ENOMEM;
    *out = kofn_of(n, k, R, work);
    free(work);
    return 0;
}

int igea_redund_diagram(int ncomp, const double *R, int nblock,
                        const int *type, const int *k, const int *first,
                        const int *member, double *Rblock)
{
    if (ncomp < 1)
        return -1;
    if (!R)
        return -2;
    if (nblock < 1)
        return -3;
    if (!type)
        return -4;
    if (!first)
        return -6;
    if (!member)
        return -7;
    if (!Rblock)
        return -8;
    if (!igea__finite_vec(ncomp, R, 1))
        return IGEA_ENONFINITE;
    if (!check_probs(ncomp, R))
        return -2;
    for (int b = 0; b < nblock; b++) {
        if (type[b] < IGEA_REDUND_RBD_SERIES || type[b] > IGEA_REDUND_RBD_KOFN)
            return -4;
        if (type[b] == IGEA_REDUND_RBD_KOFN && !k)
            return -5;
    }
    if (first[0] != 0)
        return -6;
    for (int b = 0; b < nblock; b++)
        if (first[b + 1] <= first[b])
            return -6;
    int nmem = first[nblock];
    for (int b = 0; b < nblock; b++) {
        int cnt = first[b + 1] - first[b];
        if (type[b] == IGEA_REDUND_RBD_KOFN && (k[b] < 1 || k[b] > cnt))
            return -5;
    }
    size_t nnode = (size_t)ncomp + (size_t)nblock;
    int *used = igea__ialloc(nnode);
    double *val = igea__dalloc(nnode + (size_t)nmem + (size_t)nmem + 1);
    if (!used || !val) {
        free(used);
        free(val);
        return IGEA_ENOMEM;
    }
    memset(used, 0, nnode * sizeof(int));
    int status = 0;
    for (int b = 0; b < nblock && status == 0; b++)
        for (int j = first[b]; j < first[b + 1]; j++) {
            int mi = member[j];
            if (mi < 0 || mi >= ncomp + b || used[mi]) {
                status = -7;
                break;
            }
            used[mi] = 1;
        }
    if (status == 0) {
        double *mv = val + nnode, *work = mv + nmem;
        memcpy(val, R, (size_t)ncomp * sizeof(double));
        for (int b = 0; b < nblock; b++) {
            int cnt = first[b + 1] - first[b];
            for (int j = 0; j < cnt; j++)
                mv[j] = val[member[first[b] + j]];
            double r;
            if (type[b] == IGEA_REDUND_RBD_SERIES)
                r = series_of(cnt, mv);
            else if (type[b] == IGEA_REDUND_RBD_PARALLEL)
                r = parallel_of(cnt, mv);
            else
                r = kofn_of(cnt, k[b], mv, work);
            val[ncomp + b] = r;
        }
        memcpy(Rblock, val + ncomp, (size_t)nblock * sizeof(double));
    }
    free(used);
    free(val);
    return status;
}

int igea_redund_seed002(double Re1, double Re2, double *out)
{
    if (isnan(Re1) || !prob_ok(Re1))
        return -1;
    if (isnan(Re2) || !prob_ok(Re2))
        return -2;
    if (!out)
        return -3;
    double q1 = 1.0 - Re1, q2 = 1.0 - Re2;
    double gyro = pow(1.0 - q1 * q1, 3.0);
    double x4 = 1.0 - q2 * q2 * q2 * q2;
    double a = 1.0 - q2 * q2; /* a Y (or Z) pair */
    double acc7 = x4 * (1.0 - q2 * (1.0 - a * a));
    double accx = x4 * (a * a + 2.0 * a * (1.0 - a) * Re2);
    out[IGEA_REDUND_SEED002_GYRO] = gyro;
    out[IGEA_REDUND_SEED002_ACC_EQ7] = acc7;
    out[IGEA_REDUND_SEED002_SYS_EQ7] = gyro * acc7;
    out[IGEA_REDUND_SEED002_SYS_NO_D] = gyro * x4 * a * a;
    out[IGEA_REDUND_SEED002_NONREDUND] = Re1 * Re1 * Re1 * Re2 * Re2 * Re2;
    out[IGEA_REDUND_SEED002_SYS_EXACT] = gyro * accx;
    out[IGEA_REDUND_SEED002_ACC_EXACT] = accx;
    return 0;
}

/* ---- exact geometric reliability ----------------------------------------- */

#define GEOM_SAME_DIR (1.0 - 1e-12)
#define GEOM_RANK_TOL 1e-10
#define GEOM_ZERO_COL 1e-10
#define GEOM_PARALLEL 1e-9

/* Workspace for dgesdd on up to mmax x 3 matrices. */
typedef struct {
    double *work;
    lapack_int lwork;
    lapack_int iwork[24];
} svd3_ws;

static int svd3_init(svd3_ws *w, int mmax)
{
    double q1 = 0.0, q2 = 0.0, a[1] = {0}, s[3], u[1], vt[9];
    /* Workspace queries only: the arrays are not referenced. */
    lapack_int info = LAPACKE_dgesdd_work(LAPACK_COL_MAJOR, 'N', mmax, 3, a,
                                          mmax, s, u, mmax, vt, 3, &q1, -1,
                                          w->iwork);
    if (info == 0)
        info = LAPACKE_dgesdd_work(LAPACK_COL_MAJOR, 'S', mmax, 3, a, mmax, s,
                                   u, mmax, vt, 3, &q2, -1, w->iwork);
    if (info != 0)
        return IGEA_ELAPACK;
    w->lwork = (lapack_int)IGEA_MAX(q1, q2) + 16;
    w->work = igea__dalloc((size_t)w->lwork);
    return w->work ? 0 : IGEA_ENOMEM;
}

/* Unit axes h (n x 3, ld n) from the rows of axes; IGEA_EDOMAIN for a zero
 * axis. */
static int geom_unit_axes(int n, const double *axes, int lda, double *h)
{
    for (int k = 0; k < n; k++) {
        double nr = sqrt(IGEA_AT(axes, lda, k, 0) * IGEA_AT(axes, lda, k, 0) +
                         IGEA_AT(axes, lda, k, 1) * IGEA_AT(axes, lda, k, 1) +
                         IGEA_AT(axes, lda, k, 2) * IGEA_AT(axes, lda, k, 2));
        if (!(nr > 0.0))
            return IGEA_EDOMAIN;
        for (int c = 0; c < 3; c++)
            h[k + (size_t)c * n] = IGEA_AT(axes, lda, k, c) / nr;
    }
    return 0;
}

/* Direction classes of the unit axes: cdir (rows, ld n), cls[k] the class
 * of sensor k, rho the survival of each class (1 - prod (1 - R_k)).
 * Returns the number of classes. */
static int geom_classes(int n, const double *h, const double *R, double *cdir,
                        int *cls, double *rho)
{
    int d = 0;
    for (int k = 0; k < n; k++) {
        int found = -1;
        for (int c = 0; c < d && found < 0; c++) {
            double dot = 0.0;
            for (int e = 0; e < 3; e++)
                dot += h[k + (size_t)e * n] * cdir[c + (size_t)e * n];
            if (fabs(dot) > GEOM_SAME_DIR)
                found = c;
        }
        if (found < 0) {
            found = d++;
            for (int e = 0; e < 3; e++)
                cdir[found + (size_t)e * n] = h[k + (size_t)e * n];
            rho[found] = 1.0;
        }
        cls[k] = found;
        rho[found] *= 1.0 - R[k]; /* failure product for now */
    }
    for (int c = 0; c < d; c++)
        rho[c] = 1.0 - rho[c];
    return d;
}

/* Probability that the surviving classes span 3-space: the sum over the
 * subsets of the d classes that do (a, sv: scratch, ld n). */
static int geom_span(int n, int d, const double *cdir, const double *rho,
                     double *a, double *sv, svd3_ws *ws, double *span_out)
{
    igea__ksum span = {0.0, 0.0};
    unsigned long nsub = 1UL << d;
    for (unsigned long mask = 0; mask < nsub; mask++) {
        double w = 1.0;
        int cnt = 0;
        for (int c = 0; c < d; c++) {
            if (mask & (1UL << c)) {
                w *= rho[c];
                for (int e = 0; e < 3; e++)
                    a[cnt + (size_t)e * n] = cdir[c + (size_t)e * n];
                cnt++;
            } else {
                w *= 1.0 - rho[c];
            }
        }
        if (cnt < 3 || w == 0.0)
            continue;
        double u1[1], vt1[1];
        lapack_int info = LAPACKE_dgesdd_work(LAPACK_COL_MAJOR, 'N', cnt, 3, a, n,
                                              sv, u1, 1, vt1, 1, ws->work,
                                              ws->lwork, ws->iwork);
        if (info != 0)
            return IGEA_ELAPACK;
        if (sv[2] > GEOM_RANK_TOL * sv[0])
            igea__ksum_add(&span, w);
    }
    *span_out = igea__ksum_get(&span);
    return 0;
}

/* Detection and isolation of one subset of cnt >= 4 surviving sensors
 * (rows of a, ld n): parity projector P = I - U U^T from the thin SVD.
 * Sets *detect (every sensor seen by the parity space) and *isolate (no
 * two parity columns parallel); *rank3 0 when the subset does not span. */
static int geom_subset_fdi(int n, int cnt, double *a, double *sv, double *u,
                           double *P, double *vt, svd3_ws *ws, int *rank3,
                           int *detect, int *isolate)
{
    *rank3 = *detect = *isolate = 0;
    lapack_int info = LAPACKE_dgesdd_work(LAPACK_COL_MAJOR, 'S', cnt, 3, a, n, sv,
                                          u, n, vt, 3, ws->work, ws->lwork,
                                          ws->iwork);
    if (info != 0)
        return IGEA_ELAPACK;
    *rank3 = sv[2] > GEOM_RANK_TOL * sv[0];
    if (!*rank3)
        return 0;
    for (int j = 0; j < cnt; j++)
        for (int i = 0; i < cnt; i++) {
            double s = (i == j) ? 1.0 : 0.0;
            for (int e = 0; e < 3; e++)
                s -= u[i + (size_t)e * n] * u[j + (size_t)e * n];
            P[i + (size_t)j * n] = s;
        }
    int det = 1, iso = 1;
    for (int i = 0; i < cnt && det; i++)
        if (!(P[i + (size_t)i * n] > GEOM_ZERO_COL))
            det = 0;
    if (!det)
        return 0;
    for (int j = 0; j < cnt && iso; j++)
        for (int i = j + 1; i < cnt && iso; i++) {
            double pij = P[i + (size_t)j * n];
            if (pij * pij >= (1.0 - GEOM_PARALLEL) * P[i + (size_t)i * n] *
                                 P[j + (size_t)j * n])
                iso = 0;
        }
    *detect = 1;
    *isolate = iso;
    return 0;
}

/* Probabilities of detection and isolation: the sums over the subsets of
 * surviving sensors (h unit axes, a and sv scratch, ld n). */
static int geom_fdi(int n, const double *h, const double *R, double *a,
                    double *sv, svd3_ws *ws, double *det_out, double *iso_out)
{
    double *u = igea__dalloc((size_t)n * 3 + (size_t)n * (size_t)n + 9);
    int *idx = igea__ialloc((size_t)n);
    int status = !u || !idx ? IGEA_ENOMEM : 0;
    double *P = u ? u + (size_t)n * 3 : NULL, *vt = P ? P + (size_t)n * n : NULL;
    igea__ksum det = {0.0, 0.0}, iso = {0.0, 0.0};
    unsigned long nsub = 1UL << n;
    for (unsigned long mask = 0; mask < nsub && status == 0; mask++) {
        double w = 1.0;
        int cnt = 0;
        for (int k = 0; k < n; k++) {
            if (mask & (1UL << k)) {
                w *= R[k];
                for (int e = 0; e < 3; e++)
                    a[cnt + (size_t)e * n] = h[k + (size_t)e * n];
                idx[cnt++] = k;
            } else {
                w *= 1.0 - R[k];
            }
        }
        if (cnt < 4 || w == 0.0)
            continue; /* < 4 sensors: no parity relation */
        int rank3, detect, isolate;
        status = geom_subset_fdi(n, cnt, a, sv, u, P, vt, ws, &rank3, &detect, &isolate);
        if (detect)
            igea__ksum_add(&det, w);
        if (isolate)
            igea__ksum_add(&iso, w);
    }
    if (status == 0) {
        *det_out = igea__ksum_get(&det);
        *iso_out = igea__ksum_get(&iso);
    }
    free(u);
    free(idx);
    return status;
}

int igea_redund_geometry(int n, const double *axes, int lda, const double *R,
                         int fdi, double *out)
{
    if (n < 1)
        return -1;
    if (!axes)
        return -2;
    if (lda < IGEA_MAX(1, n))
        return -3;
    if (!R)
        return -4;
    if (fdi != 0 && fdi != 1)
        return -5;
    if (fdi && n > IGEA_REDUND_GEOM_FDI_MAX)
        return -1;
    if (!out)
        return -6;
    if (!igea__finite_mat(n, 3, axes, lda) || !igea__finite_vec(n, R, 1))
        return IGEA_ENONFINITE;
    if (!check_probs(n, R))
        return -4;

    double *h = igea__dalloc((size_t)n * 3 + (size_t)n * 3 + (size_t)n + 9 + (size_t)n * 3);
    int *cls = igea__ialloc((size_t)n);
    if (!h || !cls) {
        free(h);
        free(cls);
        return IGEA_ENOMEM;
    }
    double *cdir = h + (size_t)n * 3;   /* class directions, rows */
    double *rho = cdir + (size_t)n * 3; /* class survival */
    double *sv = rho + n;               /* singular values etc. */
    double *a = sv + 9;                 /* matrix for dgesdd, ld n */
    int status = geom_unit_axes(n, axes, lda, h), d = 0;
    if (status == 0)
        d = geom_classes(n, h, R, cdir, cls, rho);
    if (status == 0 && d > IGEA_REDUND_GEOM_CLASS_MAX)
        status = -1;
    svd3_ws ws = {NULL, 0, {0}};
    if (status == 0)
        status = svd3_init(&ws, IGEA_MAX(n, 3));
    double res[IGEA_REDUND_GEOM_LEN];
    if (status == 0) {
        status = geom_span(n, d, cdir, rho, a, sv, &ws, &res[IGEA_REDUND_GEOM_SPAN]);
        res[IGEA_REDUND_GEOM_DETECT] = NAN;
        res[IGEA_REDUND_GEOM_ISOLATE] = NAN;
        res[IGEA_REDUND_GEOM_CLASSES] = (double)d;
    }
    if (status == 0 && fdi)
        status = geom_fdi(n, h, R, a, sv, &ws, &res[IGEA_REDUND_GEOM_DETECT],
                          &res[IGEA_REDUND_GEOM_ISOLATE]);
    if (status == 0)
        memcpy(out, res, sizeof res);
    free(ws.work);
    free(h);
    free(cls);
    return status;
}

/* ---- consistency -------------------------------------------------------- */

/* alpha_ij with lda = 0 meaning one value. */
static double alpha_at(const double *alpha, int lda, int i, int j)
{
    return lda == 0 ? alpha[0] : IGEA_AT(alpha, lda, i, j);
}

/* Validate an alpha argument: 0 ok, -1 bad value, IGEA_ENONFINITE. */
static int check_alpha(int n, const double *alpha, int lda)
{
    int cnt = lda == 0 ? 1 : n;
    for (int j = 0; j < cnt; j++)
        for (int i = 0; i < cnt; i++) {
            double a = alpha_at(alpha, lda, i, j);
            if (isnan(a))
                return IGEA_ENONFINITE;
            if (!(a > 0.0 && a < 1.0))
                return -1;
        }
    return 0;
}

/* Sigma check: 0 ok, IGEA_ENONFINITE, IGEA_ENONPOSITIVE or IGEA_ERANGE
 * (below IGEA_SIGMA_MIN: 1/sigma^2 weights the data). */
static int check_sigma(int n, const double *sigma)
{
    return igea__sigma_vec(n, sigma);
}

static void cdm_fill(int n, const double *x, const double *sigma, double *D,
                     int ldd)
{
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            IGEA_AT(D, ldd, i, j) =
                i == j ? 0.0 : fabs(erf((x[j] - x[i]) / (SQRT2 * sigma[i])));
}

int igea_redund_confidence_distance(int n, const double *x,
                                    const double *sigma, double *D, int ldd)
{
    if (n < 1)
        return -1;
    if (!x)
        return -2;
    if (!sigma)
        return -3;
    if (!D)
        return -4;
    if (ldd < n)
        return -5;
    if (!igea__finite_vec(n, x, 1))
        return IGEA_ENONFINITE;
    int st = check_sigma(n, sigma);
    if (st)
        return st;
    cdm_fill(n, x, sigma, D, ldd);
    return 0;
}

int igea_redund_thresholds(int n, const double *sigma, const double *alpha,
                           int lda, double *delta, int ldd)
{
    if (n < 1)
        return -1;
    if (!sigma)
        return -2;
    if (!alpha)
        return -3;
    if (lda != 0 && lda < n)
        return -4;
    if (!delta)
        return -5;
    if (ldd < n)
        return -6;
    int st = check_sigma(n, sigma);
    if (st)
        return st;
    st = check_alpha(n, alpha, lda);
    if (st)
        return st == -1 ? -3 : st;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            IGEA_AT(delta, ldd, i, j) =
                SQRT2 * sigma[i] * igea__erfinv(alpha_at(alpha, lda, i, j));
    return 0;
}

static int check_D(int n, const double *D, int ldd)
{
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            double d = IGEA_AT(D, ldd, i, j);
            if (isnan(d))
                return IGEA_ENONFINITE;
            if (!(d >= 0.0 && d <= 1.0))
                return -1;
        }
    return 0;
}

int igea_redund_relation(int n, const double *D, int ldd, const double *alpha,
                         int lda, int *r, int ldr)
{
    if (n < 1)
        return -1;
    if (!D)
        return -2;
    if (ldd < n)
        return -3;
    if (!alpha)
        return -4;
    if (lda != 0 && lda < n)
        return -5;
    if (!r)
        return -6;
    if (ldr < n)
        return -7;
    int st = check_D(n, D, ldd);
    if (st)
        return st == -1 ? -2 : st;
    st = check_alpha(n, alpha, lda);
    if (st)
        return st == -1 ? -4 : st;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            IGEA_AT(r, ldr, i, j) =
                (i == j || IGEA_AT(D, ldd, i, j) <= alpha_at(alpha, lda, i, j)) ? 1 : 0;
    return 0;
}

int igea_redund_relation_delta(int n, const double *x, const double *delta,
                               int ldd, int *r, int ldr)
{
    if (n < 1)
        return -1;
    if (!x)
        return -2;
    if (!delta)
        return -3;
    if (ldd != 0 && ldd < n)
        return -4;
    if (!r)
        return -5;
    if (ldr < n)
        return -6;
    if (!igea__finite_vec(n, x, 1))
        return IGEA_ENONFINITE;
    int cnt = ldd == 0 ? 1 : n;
    for (int j = 0; j < cnt; j++)
        for (int i = 0; i < cnt; i++) {
            double d = alpha_at(delta, ldd, i, j);
            if (isnan(d))
                return IGEA_ENONFINITE;
            if (!(d >= 0.0))
                return -3;
        }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            IGEA_AT(r, ldr, i, j) =
                (i == j || fabs(x[j] - x[i]) <= alpha_at(delta, ldd, i, j)) ? 1 : 0;
    return 0;
}

/* Fusion set of validated inputs; inF[n] scratch-free output (1/0),
 * support[n] counts on the full set. */
static void fusion_core(int n, const double *D, int ldd, const double *alpha,
                        int lda, int iterative, int *inF, int *support)
{
    for (int j = 0; j < n; j++) {
        int s = 0;
        for (int i = 0; i < n; i++)
            if (i != j && IGEA_AT(D, ldd, i, j) <= alpha_at(alpha, lda, i, j))
                s++;
        support[j] = s;
        inF[j] = 1;
    }
    int size = n;
    if (!iterative) {
        int need = n / 2; /* ceil((n - 1) / 2) */
        for (int j = 0; j < n; j++)
            inF[j] = support[j] >= need;
        return;
    }
    for (;;) {
        int need = size / 2, worst = -1, minsup = n + 1;
        double worst_d = -1.0;
        for (int j = 0; j < n; j++) {
            if (!inF[j])
                continue;
            int s = 0;
            double dsum = 0.0;
            for (int i = 0; i < n; i++)
                if (i != j && inF[i]) {
                    double d = IGEA_AT(D, ldd, i, j);
                    dsum += d;
                    if (d <= alpha_at(alpha, lda, i, j))
                        s++;
                }
            if (s < minsup || (s == minsup && dsum >= worst_d)) {
                minsup = s;
                worst = j;
                worst_d = dsum;
            }
        }
        if (minsup >= need || worst < 0)
            break;
        inF[worst] = 0;
        size--;
    }
}

int igea_redund_fusion_set(int n, const double *D, int ldd,
                           const double *alpha, int lda, int iterative,
                           int *keep, int *support)
{
    if (n < 1)
        return -1;
    if (!D)
        return -2;
    if (ldd < n)
        return -3;
    if (!alpha)
        return -4;
    if (lda != 0 && lda < n)
        return -5;
    if (iterative != 0 && iterative != 1)
        return -6;
    if (!keep)
        return -7;
    int st = check_D(n, D, ldd);
    if (st)
        return st == -1 ? -2 : st;
    st = check_alpha(n, alpha, lda);
    if (st)
        return st == -1 ? -4 : st;
    int *w = igea__ialloc(2 * (size_t)n);
    if (!w)
        return IGEA_ENOMEM;
    fusion_core(n, D, ldd, alpha, lda, iterative, w, w + n);
    memcpy(keep, w, (size_t)n * sizeof(int));
    if (support)
        memcpy(support, w + n, (size_t)n * sizeof(int));
    free(w);
    return 0;
}

/* Fusion of validated inputs; returns the count used. */
static int fuse_core(int n, const double *x, size_t incx, const double *sigma,
                     const int *keep, int weighted, double *value, double *fsig)
{
    igea__ksum num = {0, 0}, den = {0, 0};
    int cnt = 0;
    for (int i = 0; i < n; i++) {
        if (keep && !keep[i])
            continue;
        cnt++;
        double xi = x[(size_t)i * incx];
        if (weighted) {
            double w = 1.0 / (sigma[i] * sigma[i]);
            igea__ksum_add(&num, w * xi);
            igea__ksum_add(&den, w);
        } else {
            igea__ksum_add(&num, xi);
            igea__ksum_add(&den, sigma[i] * sigma[i]);
        }
    }
    if (cnt == 0)
        return 0;
    if (weighted) {
        double s = igea__ksum_get(&den);
        *value = igea__ksum_get(&num) / s;
        *fsig = 1.0 / sqrt(s);
    } else {
        *value = igea__ksum_get(&num) / cnt;
        *fsig = sqrt(igea__ksum_get(&den)) / cnt;
    }
    return cnt;
}

int igea_redund_fuse(int n, const double *x, const double *sigma,
                     const int *keep, int weighted, double *value,
                     double *fused_sigma)
{
    if (n < 1)
        return -1;
    if (!x)
        return -2;
    if (!sigma)
        return -3;
    if (weighted != 0 && weighted != 1)
        return -5;
    if (!value)
        return -6;
    if (!igea__finite_vec(n, x, 1))
        return IGEA_ENONFINITE;
    int st = check_sigma(n, sigma);
    if (st)
        return st;
    double v, s;
    if (fuse_core(n, x, 1, sigma, keep, weighted, &v, &s) == 0)
        return IGEA_EEMPTY;
    if (!isfinite(v) || !isfinite(s))
        return IGEA_EOVERFLOW;
    *value = v;
    if (fused_sigma)
        *fused_sigma = s;
    return 0;
}

int igea_redund_false_alarm(double sigma_i, double noise_i, double noise_j,
                            double alpha, double *p)
{
    if (!(isfinite(sigma_i) && sigma_i > 0.0))
        return -1;
    if (!(isfinite(noise_i) && noise_i > 0.0))
        return -2;
    if (!(isfinite(noise_j) && noise_j > 0.0))
        return -3;
    if (!(alpha > 0.0 && alpha < 1.0))
        return -4;
    if (!p)
        return -5;
    double delta = SQRT2 * sigma_i * igea__erfinv(alpha);
    *p = erfc(delta / sqrt(2.0 * (noise_i * noise_i + noise_j * noise_j)));
    return 0;
}

int igea_redund_transform(int ngroup, const double *C, const double *v,
                          double *out)
{
    if (ngroup < 1)
        return -1;
    if (!C)
        return -2;
    if (!v)
        return -3;
    if (!out)
        return -4;
    if (!igea__finite_vec(9 * ngroup, C, 1) || !igea__finite_vec(3 * ngroup, v, 1))
        return IGEA_ENONFINITE;
    for (int g = 0; g < ngroup; g++) {
        const double *c = C + (size_t)9 * g, *vg = v + (size_t)3 * g;
        double *o = out + (size_t)3 * g;
        for (int i = 0; i < 3; i++)
            o[i] = c[i] * vg[0] + c[i + 3] * vg[1] + c[i + 6] * vg[2];
    }
    return 0;
}

/* ---- parity space ------------------------------------------------------- */

/* Full left singular vectors of the m x q matrix a (ld m, overwritten):
 * U (m x m), s (q). Returns 0, IGEA_ERANK, IGEA_ENOMEM, IGEA_ELAPACK. */
static int full_u(int m, int q, double *a, double *U, double *s)
{
    double *v = igea__dalloc((size_t)q * (size_t)q);
    if (!v)
        return IGEA_ENOMEM;
    int st = igea__svd(m, q, a, s, U, 1, v);
    free(v);
    if (st == 0 && igea__rank_cut(q, s, (double)IGEA_MAX(m, q) * DBL_EPSILON) < q)
        st = IGEA_ERANK;
    return st;
}

/* V ((m - q) x m, ld ldv) from U with the row sign convention. */
static void parity_from_u(int m, int q, const double *U, double *V, int ldv)
{
    double *row = (double *)U; /* columns of U beyond q are the rows of V */
    for (int r = 0; r < m - q; r++) {
        const double *col = row + (size_t)(q + r) * m;
        int imax = 0;
        for (int i = 1; i < m; i++)
            if (fabs(col[i]) > fabs(col[imax]))
                imax = i;
        double sg = col[imax] < 0.0 ? -1.0 : 1.0;
        for (int i = 0; i < m; i++)
            IGEA_AT(V, ldv, r, i) = sg * col[i];
    }
}

int igea_redund_parity(int m, int q, const double *H, int ldh, double *V,
                       int ldv)
{
    if (q < 1)
        return -2;
    if (m <= q)
        return -1;
    if (!H)
        return -3;
    if (ldh < m)
        return -4;
    if (!V)
        return -5;
    if (ldv < m - q)
        return -6;
    if (!igea__finite_mat(m, q, H, ldh))
        return IGEA_ENONFINITE;
    double *a = igea__dalloc((size_t)m * q + (size_t)m * m + (size_t)q);
    if (!a)
        return IGEA_ENOMEM;
    double *U = a + (size_t)m * q, *s = U + (size_t)m * m;
    for (int j = 0; j < q; j++)
        for (int i = 0; i < m; i++)
            a[i + (size_t)j * m] = IGEA_AT(H, ldh, i, j);
    int st = full_u(m, q, a, U, s);
    if (st == 0)
        parity_from_u(m, q, U, V, ldv);
    free(a);
    return st;
}

/* Isolation on the parity vector p (dof) with V (dof x m, ld dof): the
 * sensor whose parity column explains p best (returned, with its
 * statistic), and whether every pair of columns can be told apart. */
static int fdi_isolate(int m, int dof, const double *V, const double *p,
                       int *isolable_out, double *best_out)
{
    int best = -1, isolable = 1;
    double best_stat = 0.0;
    for (int k = 0; k < m; k++) {
        double nk = 0.0, vp = 0.0;
        for (int r = 0; r < dof; r++) {
            nk += V[r + (size_t)k * dof] * V[r + (size_t)k * dof];
            vp += V[r + (size_t)k * dof] * p[r];
        }
        if (!(nk > GEOM_ZERO_COL)) {
            isolable = 0;
            continue;
        }
        for (int l = k + 1; l < m; l++) {
            double nl = 0.0, kl = 0.0;
            for (int r = 0; r < dof; r++) {
                nl += V[r + (size_t)l * dof] * V[r + (size_t)l * dof];
                kl += V[r + (size_t)k * dof] * V[r + (size_t)l * dof];
            }
            if (kl * kl >= (1.0 - GEOM_PARALLEL) * nk * nl)
                isolable = 0;
        }
        double sk = vp * vp / nk;
        if (best < 0 || sk > best_stat) {
            best = k;
            best_stat = sk;
        }
    }
    *isolable_out = isolable;
    *best_out = best_stat;
    return best;
}

int igea_redund_fdi(int m, int q, const double *H, int ldh, const double *y,
                    const double *sigma, double pfa, double *parity,
                    double *info, int *isolated)
{
    if (q < 1)
        return -2;
    if (m <= q)
        return -1;
    if (!H)
        return -3;
    if (ldh < m)
        return -4;
    if (!y)
        return -5;
    if (!sigma)
        return -6;
    if (!(pfa > 0.0 && pfa < 1.0))
        return -7;
    if (!info)
        return -9;
    if (!igea__finite_mat(m, q, H, ldh) || !igea__finite_vec(m, y, 1))
        return IGEA_ENONFINITE;
    int st = check_sigma(m, sigma);
    if (st)
        return st;
    int dof = m - q;
    double thr;
    st = igea_stats_chi2_upper(pfa, (double)dof, &thr);
    if (st)
        return st < 0 && st > -1000 ? -7 : st;
    double *a = igea__dalloc((size_t)m * q + (size_t)m * m + (size_t)q +
                             (size_t)dof * m + (size_t)dof);
    if (!a)
        return IGEA_ENOMEM;
    double *U = a + (size_t)m * q, *s = U + (size_t)m * m;
    double *V = s + q, *p = V + (size_t)dof * m;
    for (int j = 0; j < q; j++)
        for (int i = 0; i < m; i++)
            a[i + (size_t)j * m] = IGEA_AT(H, ldh, i, j) / sigma[i];
    st = full_u(m, q, a, U, s);
    if (st) {
        free(a);
        return st;
    }
    parity_from_u(m, q, U, V, dof);
    igea__ksum stat = {0, 0};
    for (int r = 0; r < dof; r++) {
        igea__ksum pr = {0, 0};
        for (int i = 0; i < m; i++)
            igea__ksum_add(&pr, V[r + (size_t)i * dof] * (y[i] / sigma[i]));
        p[r] = igea__ksum_get(&pr);
        igea__ksum_add(&stat, p[r] * p[r]);
    }
    double T = igea__ksum_get(&stat), pval;
    st = igea_stats_chi2_sf(T, (double)dof, &pval);
    if (st) {
        free(a);
        return IGEA_ENOCONV;
    }
    int isolable;
    double best_stat;
    int best = fdi_isolate(m, dof, V, p, &isolable, &best_stat);
    int detected = T > thr;
    if (!detected)
        best = -1;
    info[IGEA_REDUND_FDI_STAT] = T;
    info[IGEA_REDUND_FDI_THRESHOLD] = thr;
    info[IGEA_REDUND_FDI_DOF] = (double)dof;
    info[IGEA_REDUND_FDI_P_VALUE] = pval;
    info[IGEA_REDUND_FDI_DETECTED] = detected;
    info[IGEA_REDUND_FDI_ISOLATED] = (double)best;
    info[IGEA_REDUND_FDI_ISO_STAT] = best >= 0 ? best_stat : 0.0;
    info[IGEA_REDUND_FDI_ISOLABLE] = isolable;
    if (parity)
        memcpy(parity, p, (size_t)dof * sizeof(double));
    if (isolated)
        *isolated = best;
    free(a);
    return 0;
}

/* The residuals p_ij = ad - (cy ay_i + cz az_j) (r, ny x nz) against
 * kappa times their sd: a sensor is suspect when every residual through it
 * fails (fy, fz); when all fail, the diagonal sensor is (returns 1, fy and
 * fz cleared). */
static int skew_table(int ny, const double *ay, const double *sy, int nz,
                      const double *az, const double *sz, double ad, double sd,
                      double cy, double cz, double kappa, double *r, int *fy,
                      int *fz)
{
    size_t nfail = 0;
    for (int i = 0; i < ny; i++)
        fy[i] = 1;
    for (int j = 0; j < nz; j++)
        fz[j] = 1;
    for (int j = 0; j < nz; j++)
        for (int i = 0; i < ny; i++) {
            double pij = ad - (cy * ay[i] + cz * az[j]);
            double thr = kappa * sqrt(sd * sd + cy * cy * sy[i] * sy[i] +
                                      cz * cz * sz[j] * sz[j]);
            r[i + (size_t)j * ny] = pij;
            if (fabs(pij) > thr) {
                nfail++;
            } else {
                fy[i] = 0;
                fz[j] = 0;
            }
        }
    int dsus = nfail == (size_t)ny * (size_t)nz;
    if (dsus) {
        for (int i = 0; i < ny; i++)
            fy[i] = 0;
        for (int j = 0; j < nz; j++)
            fz[j] = 0;
    }
    return dsus;
}

int igea_redund_skew_check(int ny, const double *ay, const double *sy, int nz,
                           const double *az, const double *sz, double ad,
                           double sd, double cy, double cz, double kappa,
                           double *resid, int *faulty_y, int *faulty_z,
                           int *faulty_d)
{
    if (ny < 1)
        return -1;
    if (!ay)
        return -2;
    if (!sy)
        return -3;
    if (nz < 1)
        return -4;
    if (!az)
        return -5;
    if (!sz)
        return -6;
    if (!(isfinite(sd) && sd > 0.0))
        return isnan(sd) ? IGEA_ENONFINITE : -8;
    if (!isfinite(cy))
        return -9;
    if (!isfinite(cz) || !(cy * cy + cz * cz > 0.0))
        return -10;
    if (!(isfinite(kappa) && kappa > 0.0))
        return -11;
    if (!faulty_y)
        return -13;
    if (!faulty_z)
        return -14;
    if (!faulty_d)
        return -15;
    if (!isfinite(ad) || !igea__finite_vec(ny, ay, 1) || !igea__finite_vec(nz, az, 1))
        return IGEA_ENONFINITE;
    int st = check_sigma(ny, sy);
    if (st == 0)
        st = check_sigma(nz, sz);
    if (st)
        return st;
    size_t np_ = (size_t)ny * (size_t)nz;
    double *r = igea__dalloc(np_);
    int *fy = igea__ialloc((size_t)ny + (size_t)nz);
    if (!r || !fy) {
        free(r);
        free(fy);
        return IGEA_ENOMEM;
    }
    int *fz = fy + ny;
    int dsus = skew_table(ny, ay, sy, nz, az, sz, ad, sd, cy, cz, kappa, r, fy, fz);
    if (resid)
        memcpy(resid, r, np_ * sizeof(double));
    memcpy(faulty_y, fy, (size_t)ny * sizeof(int));
    memcpy(faulty_z, fz, (size_t)nz * sizeof(int));
    *faulty_d = dsus;
    free(r);
    free(fy);
    return 0;
}

/* ---- windowed check ---------------------------------------------------- */

static int window_len(double fs, double window, long *nw)
{
    double v = window * fs;
    if (!(v >= 0.5 && v < 2147483647.0))
        return -1;
    *nw = lround(v);
    return 0;
}

int igea_redund_window_count(int nsamp, double fs, double window, int *nwin)
{
    if (nsamp < 1)
        return -1;
    if (!(isfinite(fs) && fs > 0.0))
        return -2;
    long nw;
    if (!(isfinite(window) && window > 0.0) || window_len(fs, window, &nw))
        return -3;
    if (!nwin)
        return -4;
    *nwin = (int)(nsamp / nw);
    return 0;
}

int igea_redund_window_length(double fs, double window, int *samples, double *seconds)
{
    if (!(isfinite(fs) && fs > 0.0))
        return -1;
    long nw;
    if (!(isfinite(window) && window > 0.0) || window_len(fs, window, &nw))
        return -2;
    if (samples)
        *samples = (int)nw;
    if (seconds)
        *seconds = (double)nw / fs;
    return 0;
}

int igea_redund_monitor_intervals(int nsens, int nwin, const int *excluded,
                                  double fs, double window, int maxiv,
                                  int *niv, int *sensor, int *win_start,
                                  int *win_end, double *t_start, double *t_end)
{
    long nw;
    if (nsens < 1)
        return -1;
    if (nwin < 1)
        return -2;
    if (!excluded)
        return -3;
    if (!(isfinite(fs) && fs > 0.0))
        return -4;
    if (!(isfinite(window) && window > 0.0) || window_len(fs, window, &nw))
        return -5;
    if (maxiv < 0)
        return -6;
    if (!niv)
        return -7;
    if (maxiv > 0 && !sensor)
        return -8;
    if (maxiv > 0 && !win_start)
        return -9;
    if (maxiv > 0 && !win_end)
        return -10;
    size_t n = (size_t)nsens * (size_t)nwin;
    for (size_t k = 0; k < n; k++)
        if (excluded[k] != 0 && excluded[k] != 1)
            return -3;
    /* count first: nothing is written when the intervals do not fit */
    int count = 0;
    for (int s = 0; s < nsens; s++)
        for (int w = 0; w < nwin; w++)
            count += excluded[s + (size_t)w * nsens] &&
                     (w == 0 || !excluded[s + (size_t)(w - 1) * nsens]);
    if (maxiv > 0 && count > maxiv)
        return -6;
    *niv = count;
    if (maxiv == 0)
        return 0;
    double step = (double)nw / fs;
    int k = 0;
    for (int s = 0; s < nsens; s++)
        for (int w = 0; w < nwin; w++) {
            if (!excluded[s + (size_t)w * nsens] ||
                (w > 0 && excluded[s + (size_t)(w - 1) * nsens]))
                continue;
            int e = w;
            while (e < nwin && excluded[s + (size_t)e * nsens])
                e++;
            sensor[k] = s;
            win_start[k] = w;
            win_end[k] = e;
            if (t_start)
                t_start[k] = w * step;
            if (t_end)
                t_end[k] = e * step;
            k++;
        }
    return 0;
}

int igea_redund_monitor(int nsamp, int nsens, const double *y, int ldy,
                             double fs, double window, const double *sigma,
                             const double *alpha, int lda, int iterative,
                             int weighted, int nwin, double *means,
                             int *excluded, double *fused, double *fused_sigma)
{
    int expect;
    if (nsamp < 1)
        return -1;
    if (nsens < 1)
        return -2;
    if (!y)
        return -3;
    if (ldy < nsamp)
        return -4;
    if (!(isfinite(fs) && fs > 0.0))
        return -5;
    if (igea_redund_window_count(nsamp, fs, window, &expect) != 0)
        return -6;
    if (!sigma)
        return -7;
    if (!alpha)
        return -8;
    if (lda != 0 && lda < nsens)
        return -9;
    if (iterative != 0 && iterative != 1)
        return -10;
    if (weighted != 0 && weighted != 1)
        return -11;
    if (nwin != expect || nwin < 1)
        return -12;
    if (!excluded)
        return -14;
    if (!fused)
        return -15;
    if (!igea__finite_mat(nsamp, nsens, y, ldy))
        return IGEA_ENONFINITE;
    int st = check_sigma(nsens, sigma);
    if (st)
        return st;
    st = check_alpha(nsens, alpha, lda);
    if (st)
        return st == -1 ? -8 : st;
    long nw = 1;
    window_len(fs, window, &nw);
    size_t nn = (size_t)nsens;
    double *mv = igea__dalloc(nn * (size_t)nwin + nn * nn + 2 * (size_t)nwin);
    int *ex = igea__ialloc(nn * (size_t)nwin + 2 * nn);
    if (!mv || !ex) {
        free(mv);
        free(ex);
        return IGEA_ENOMEM;
    }
    double *D = mv + nn * (size_t)nwin, *fv = D + nn * nn, *fs2 = fv + nwin;
    int *inF = ex + nn * (size_t)nwin, *sup = inF + nn;
    for (int w = 0; w < nwin; w++) {
        double *xm = mv + nn * (size_t)w;
        for (int s = 0; s < nsens; s++) {
            igea__ksum acc = {0, 0};
            const double *col = y + (size_t)s * (size_t)ldy + (size_t)w * (size_t)nw;
            for (long k = 0; k < nw; k++)
                igea__ksum_add(&acc, col[k]);
            xm[s] = igea__ksum_get(&acc) / (double)nw;
        }
        cdm_fill(nsens, xm, sigma, D, nsens);
        fusion_core(nsens, D, nsens, alpha, lda, iterative, inF, sup);
        for (int s = 0; s < nsens; s++)
            ex[s + nn * (size_t)w] = !inF[s];
        fuse_core(nsens, xm, 1, sigma, inF, weighted, &fv[w], &fs2[w]);
    }
    if (means)
        memcpy(means, mv, nn * (size_t)nwin * sizeof(double));
    memcpy(excluded, ex, nn * (size_t)nwin * sizeof(int));
    memcpy(fused, fv, (size_t)nwin * sizeof(double));
    if (fused_sigma)
        memcpy(fused_sigma, fs2, (size_t)nwin * sizeof(double));
    free(mv);
    free(ex);
    return 0;
}

int igea_redund_simulate(int nsamp, int nsens, double fs, const double *level,
                         const double *noise, int fault_sensor, double t0,
                         double t1, double fault_bias, int seed, double *y,
                         int ldy)
{
    if (nsamp < 1)
        return -1;
    if (nsens < 1)
        return -2;
    if (!(isfinite(fs) && fs > 0.0))
        return -3;
    if (!level)
        return -4;
    if (!noise)
        return -5;
    if (fault_sensor < -1 || fault_sensor >= nsens)
        return -6;
    if (isnan(t0))
        return -7;
    if (isnan(t1))
        return -8;
    if (!isfinite(fault_bias))
        return -9;
    if (seed < 0)
        return -10;
    if (!y)
        return -11;
    if (ldy < nsamp)
        return -12;
    if (!igea__finite_vec(nsens, level, 1) || !igea__finite_vec(nsens, noise, 1))
        return IGEA_ENONFINITE;
    for (int s = 0; s < nsens; s++)
        if (noise[s] < 0.0)
            return -5;
    gsl_rng *rng = igea__rng_new(gsl_rng_mt19937, (unsigned long)seed);
    if (!rng)
        return IGEA_ENOMEM;
    for (int k = 0; k < nsamp; k++) {
        double t = (double)k / fs;
        for (int s = 0; s < nsens; s++) {
            double v = level[s] + gsl_ran_gaussian_ziggurat(rng, 1.0) * noise[s];
            if (s == fault_sensor && t >= t0 && t < t1)
                v += fault_bias;
            IGEA_AT(y, ldy, k, s) = v;
        }
    }
    igea__rng_free(rng);
    return 0;
}
