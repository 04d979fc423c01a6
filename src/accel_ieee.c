/* accel_ieee.c - the IEEE Std 1293 single-axis model fitted to tumble
 * readings in the IA-PA and IA-OA planes by least squares and by the
 * harmonic (Fourier) method, and the D-criterion of a position schedule
 * for every accel model (docs/accel.md). */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "igea/accel.h"
#include "igea/regress.h"
#include "internal.h"
#include "accel_internal.h"

#define NPI IGEA_ACCEL_NP_IEEE
#define CRIT_MAXP 10

/* Row of the linear IEEE design at one reading (b order, see accel.h). */
static void ieee_row(double deg, int plane, double *row)
{
    double s, c;
    igea__accel_sincosd(deg, &s, &c);
    int pa = plane == IGEA_ACCEL_PLANE_IAPA;
    row[0] = 1.0;
    row[1] = s;
    row[2] = s * s;
    row[3] = s * s * s;
    row[IGEA_ACCEL_IEEE_KIP] = pa ? s * c : 0.0;
    row[IGEA_ACCEL_IEEE_KIO] = pa ? 0.0 : s * c;
    row[IGEA_ACCEL_IEEE_DO] = pa ? c : 0.0;
    row[IGEA_ACCEL_IEEE_DP] = pa ? 0.0 : c;
}

static void ieee_design(int n, const double *theta, const int *plane, double *A)
{
    double row[NPI];
    for (int i = 0; i < n; i++) {
        ieee_row(theta[i], plane[i], row);
        for (int j = 0; j < NPI; j++)
            A[(size_t)i + (size_t)j * n] = row[j];
    }
}

static int cmp_double(const void *p, const void *q)
{
    double a = *(const double *)p, b = *(const double *)q;
    return (a > b) - (a < b);
}

/* The readings of plane pl are N >= 7 distinct equispaced positions (one
 * reading each): 1, else 0. w: n doubles of workspace. */
static int equispaced(int n, const double *theta, const int *plane, int pl, double *w,
                      int *np_out)
{
    int N = 0;
    for (int i = 0; i < n; i++)
        if (plane[i] == pl) {
            double r = fmod(theta[i], 360.0);
            w[N++] = r < 0.0 ? r + 360.0 : r;
        }
    *np_out = N;
    if (N == 0)
        return 1;
    if (N < 7)
        return 0;
    qsort(w, (size_t)N, sizeof(double), cmp_double);
    double step = 360.0 / N;
    for (int k = 0; k < N; k++) {
        double gap = (k + 1 < N ? w[k + 1] : w[0] + 360.0) - w[k];
        if (fabs(gap - step) > 1e-9 * 360.0)
            return 0;
    }
    return 1;
}

/* Fourier coefficients of one plane: h = B0, S1, C1, S2, C2, S3. */
static void plane_harmonics(int n, const double *theta, const int *plane, const double *e,
                            int pl, int N, double *h)
{
    igea__ksum acc[6];
    memset(acc, 0, sizeof acc);
    for (int i = 0; i < n; i++) {
        if (plane[i] != pl)
            continue;
        double s1, c1, s2, c2, s3, c3;
        igea__accel_sincosd(theta[i], &s1, &c1);
        igea__accel_sincosd(2.0 * theta[i], &s2, &c2);
        igea__accel_sincosd(3.0 * theta[i], &s3, &c3);
        double t[6] = {e[i], e[i] * s1, e[i] * c1, e[i] * s2, e[i] * c2, e[i] * s3};
        for (int k = 0; k < 6; k++)
            igea__ksum_add(&acc[k], t[k]);
    }
    for (int k = 0; k < 6; k++)
        h[k] = igea__ksum_get(&acc[k]) * (k ? 2.0 : 1.0) / N;
}

/* The harmonic method: b from the pooled Fourier coefficients. Returns 0,
 * IGEA_EDOMAIN (a plane not equispaced or with < 7 positions), IGEA_ENOMEM. */
static int harmonic_b(int n, const double *theta, const int *plane, const double *e,
                      double *b)
{
    double *w = igea__dalloc((size_t)n);
    if (!w)
        return IGEA_ENOMEM;
    int N[2];
    int ok = equispaced(n, theta, plane, IGEA_ACCEL_PLANE_IAPA, w, &N[0]) &&
             equispaced(n, theta, plane, IGEA_ACCEL_PLANE_IAOA, w, &N[1]);
    free(w);
    if (!ok)
        return IGEA_EDOMAIN;
    double h[2][6] = {{0}}, B0 = 0, S1 = 0, C2 = 0, S3 = 0;
    for (int p = 0; p < 2; p++) {
        if (!N[p])
            continue;
        plane_harmonics(n, theta, plane, e, p, N[p], h[p]);
        double wt = (double)N[p] / (N[0] + N[1]);
        B0 += wt * h[p][0], S1 += wt * h[p][1], C2 += wt * h[p][4], S3 += wt * h[p][5];
    }
    /* E/K1 = K0 + s + K2 s^2 + K3 s^3 + Kx sc + d c with s^2 = (1 - cos 2t)/2,
     * s^3 = (3 sin t - sin 3t)/4, sc = sin 2t / 2 (docs/accel.md). */
    b[3] = -4.0 * S3;
    b[1] = S1 + 3.0 * S3;
    b[2] = -2.0 * C2;
    b[0] = B0 + C2;
    b[IGEA_ACCEL_IEEE_KIP] = 2.0 * h[0][3];
    b[IGEA_ACCEL_IEEE_KIO] = 2.0 * h[1][3];
    b[IGEA_ACCEL_IEEE_DO] = h[0][2];
    b[IGEA_ACCEL_IEEE_DP] = h[1][2];
    return 0;
}

static int ieee_check(int method, int n, const double *theta_deg, const int *plane,
                      const double *e, const double *coef, const double *cov, int ldc)
{
    if (method != IGEA_ACCEL_LS && method != IGEA_ACCEL_HARMONIC)
        return -1;
    if (n < 1)
        return -2;
    if (!theta_deg)
        return -3;
    if (!plane)
        return -4;
    for (int i = 0; i < n; i++)
        if (plane[i] != IGEA_ACCEL_PLANE_IAPA && plane[i] != IGEA_ACCEL_PLANE_IAOA)
            return -4;
    if (!e)
        return -5;
    if (!coef)
        return -6;
    if (cov ? ldc < NPI : ldc < 1)
        return -9;
    if (!igea__finite_vec(n, theta_deg, 1) || !igea__finite_vec(n, e, 1))
        return IGEA_ENONFINITE;
    return 0;
}

/* b -> K and the delta-method covariance cK = J cb J^T. */
static void ieee_transform(const double *b, const double *cb, double *K, double *cK)
{
    double J[NPI * NPI] = {0}, T[NPI * NPI];
    double b1 = b[IGEA_ACCEL_IEEE_K1];
    for (int j = 0; j < NPI; j++) {
        double sg = j == IGEA_ACCEL_IEEE_DP ? -1.0 : 1.0;
        if (j == IGEA_ACCEL_IEEE_K1) {
            K[j] = b1;
            J[j + j * NPI] = 1.0;
            continue;
        }
        K[j] = sg * b[j] / b1;
        J[j + j * NPI] = sg / b1;
        J[j + IGEA_ACCEL_IEEE_K1 * NPI] = -K[j] / b1;
    }
    for (int i = 0; i < NPI; i++) /* T = J cb */
        for (int j = 0; j < NPI; j++) {
            double t = 0.0;
            for (int k = 0; k < NPI; k++)
                t += J[i + k * NPI] * cb[k + j * NPI];
            T[i + j * NPI] = t;
        }
    for (int i = 0; i < NPI; i++) /* cK = T J^T */
        for (int j = 0; j < NPI; j++) {
            double t = 0.0;
            for (int k = 0; k < NPI; k++)
                t += T[i + k * NPI] * J[j + k * NPI];
            cK[i + j * NPI] = t;
        }
}

/* Flags of the linear design's null space, residual info. */
static int ieee_identify(int n, const double *A, const double *e, const double *b, int *flg,
                         double *inf, int *rank)
{
    double s[NPI], V[NPI * NPI];
    int st = igea__accel_svd(n, NPI, A, n, s, V, rank);
    if (st)
        return st;
    for (int j = 0; j < NPI; j++) {
        double u[NPI] = {0};
        u[j] = 1.0;
        flg[j] = igea__accel_loading(NPI, *rank, V, u) > IGEA_ACCEL_LOADING_TOL
                     ? IGEA_ACCEL_PRIOR : IGEA_ACCEL_DATA;
    }
    igea__ksum rss = {0, 0};
    for (int i = 0; i < n; i++) {
        double f = 0.0;
        for (int j = 0; j < NPI; j++)
            f += A[(size_t)i + (size_t)j * n] * b[j];
        igea__ksum_add(&rss, (e[i] - f) * (e[i] - f));
    }
    double ss = igea__ksum_get(&rss);
    for (int k = 0; k < IGEA_ACCEL_INFO_LEN; k++)
        inf[k] = 0.0;
    inf[IGEA_ACCEL_INFO_RANK] = *rank;
    inf[IGEA_ACCEL_INFO_SIGMA] = n > *rank ? sqrt(ss / (n - *rank)) : 0.0;
    inf[IGEA_ACCEL_INFO_RMS] = sqrt(ss / n);
    inf[IGEA_ACCEL_INFO_NOBS] = n;
    inf[IGEA_ACCEL_INFO_DOF] = n - *rank;
    return 0;
}

/* Copy the results out (all checked finite by the caller). */
static void ieee_out(const double *K, const double *cK, int nan_sd, const int *flg,
                     const double *inf, double *coef, double *sd, double *cov, int ldc,
                     int *flag, double *info)
{
    memcpy(coef, K, NPI * sizeof(double));
    for (int j = 0; j < NPI; j++) {
        if (sd)
            sd[j] = nan_sd ? NAN : sqrt(fmax(cK[j + j * NPI], 0.0));
        if (cov)
            for (int i = 0; i < NPI; i++)
                cov[(size_t)i + (size_t)j * ldc] = nan_sd ? NAN : cK[i + j * NPI];
    }
    if (flag)
        memcpy(flag, flg, NPI * sizeof(int));
    if (info)
        memcpy(info, inf, IGEA_ACCEL_INFO_LEN * sizeof(double));
}

int igea_accel_ieee_fit(int method, int n, const double *theta_deg, const int *plane,
                        const double *e, double *coef, double *sd, double *cov, int ldc,
                        int *flag, double *info)
{
    int st = ieee_check(method, n, theta_deg, plane, e, coef, cov, ldc);
    if (st)
        return st;
    double *A = igea__dalloc((size_t)n * NPI);
    if (!A)
        return IGEA_ENOMEM;
    double b[NPI], cb[NPI * NPI], K[NPI], cK[NPI * NPI], inf[IGEA_ACCEL_INFO_LEN], s2;
    int flg[NPI], rank = 0, rk;
    ieee_design(n, theta_deg, plane, A);
    /* LS always: its covariance (pinv) serves both methods; for equispaced
     * planes the Fourier coefficients are the LS solution. */
    st = igea_regress_ls(n, NPI, A, n, e, NULL, NULL, 0.0, b, cb, NPI, &rk, &s2, NULL);
    if (!st && method == IGEA_ACCEL_HARMONIC)
        st = harmonic_b(n, theta_deg, plane, e, b);
    if (!st)
        st = ieee_identify(n, A, e, b, flg, inf, &rank);
    if (st)
        goto done;
    if (!(b[IGEA_ACCEL_IEEE_K1] != 0.0)) {
        st = IGEA_EDOMAIN;
        goto done;
    }
    /* the covariance with the sigma^2 of the b actually returned */
    double sig2 = inf[IGEA_ACCEL_INFO_SIGMA] * inf[IGEA_ACCEL_INFO_SIGMA];
    for (int k = 0; k < NPI * NPI; k++)
        cb[k] = s2 > 0.0 ? cb[k] / s2 * sig2 : 0.0;
    if (s2 == 0.0 && n > rank) /* an exact fit: sigma 0, covariance 0 */
        memset(cb, 0, sizeof cb);
    ieee_transform(b, cb, K, cK);
    if (!igea__finite_vec(NPI, K, 1) || !igea__finite_vec(NPI * NPI, cK, 1) ||
        !igea__finite_vec(IGEA_ACCEL_INFO_LEN, inf, 1)) {
        st = IGEA_EOVERFLOW;
        goto done;
    }
    ieee_out(K, cK, n == rank, flg, inf, coef, sd, cov, ldc, flag, info);
done:
    free(A);
    return st;
}

/* ---------------------------------------------------------------------- */
/* The D-criterion. */

static int crit_np(int model, int method)
{
    if (model == IGEA_ACCEL_SINGLE)
        return IGEA_ACCEL_NP_SINGLE;
    if (model == IGEA_ACCEL_IEEE)
        return NPI;
    return method == IGEA_ACCEL_JOINT ? IGEA_ACCEL_NP_JOINT : IGEA_ACCEL_NP_DUAL;
}

/* The (weighted) design: n rows, or 2n for the joint model. */
static void crit_design(int model, int method, int n, const double *theta, const int *plane,
                        double head_ratio, double *A, int m)
{
    int np = crit_np(model, method);
    double row[CRIT_MAXP];
    double wt = 1.0 / sqrt(1.0 + head_ratio * head_ratio);
    for (int i = 0; i < n; i++) {
        if (model == IGEA_ACCEL_IEEE)
            ieee_row(theta[i], plane[i], row);
        else {
            row[CRIT_MAXP - 1] = 0.0; /* joint: delta0 is not in the radial row */
            igea__accel_row(model, theta[i], row);
        }
        for (int j = 0; j < np; j++)
            A[(size_t)i + (size_t)j * m] = row[j];
        if (method != IGEA_ACCEL_JOINT)
            continue;
        igea__accel_row(IGEA_ACCEL_JOINT, theta[i], row);
        for (int j = 0; j < np; j++)
            A[(size_t)(n + i) + (size_t)j * m] = wt * row[j];
    }
}

static int crit_check(int model, int method, int n, const double *theta_deg,
                      const int *plane, double head_ratio, const double *logdet,
                      const int *rank)
{
    if (model != IGEA_ACCEL_SINGLE && model != IGEA_ACCEL_DUAL && model != IGEA_ACCEL_IEEE)
        return -1;
    if (!(method == IGEA_ACCEL_LS || method == IGEA_ACCEL_EBR ||
          (method == IGEA_ACCEL_JOINT && model == IGEA_ACCEL_DUAL) ||
          (method == IGEA_ACCEL_HARMONIC && model == IGEA_ACCEL_IEEE)))
        return -2;
    if (n < 1)
        return -3;
    if (!theta_deg)
        return -4;
    if (model == IGEA_ACCEL_IEEE) {
        if (!plane)
            return -5;
        for (int i = 0; i < n; i++)
            if (plane[i] != IGEA_ACCEL_PLANE_IAPA && plane[i] != IGEA_ACCEL_PLANE_IAOA)
                return -5;
    }
    if (method == IGEA_ACCEL_JOINT && !(head_ratio >= 0.0 && isfinite(head_ratio)))
        return -6;
    if (!logdet)
        return -7;
    if (!rank)
        return -10;
    if (!igea__finite_vec(n, theta_deg, 1))
        return IGEA_ENONFINITE;
    return 0;
}

int igea_accel_criterion(int model, int method, int n, const double *theta_deg,
                         const int *plane, double head_ratio, double *logdet,
                         double *varfac, int *flag, int *rank)
{
    int st = crit_check(model, method, n, theta_deg, plane, head_ratio, logdet, rank);
    if (st)
        return st;
    int np = crit_np(model, method), m = method == IGEA_ACCEL_JOINT ? 2 * n : n, r = 0;
    double *A = igea__dalloc((size_t)m * np);
    if (!A)
        return IGEA_ENOMEM;
    double s[CRIT_MAXP], V[CRIT_MAXP * CRIT_MAXP], vf[CRIT_MAXP], ld = 0.0;
    int flg[CRIT_MAXP];
    crit_design(model, method, n, theta_deg, plane, head_ratio, A, m);
    st = igea__accel_svd(m, np, A, m, s, V, &r);
    free(A);
    if (st)
        return st;
    if (r == 0)
        return IGEA_ERANK;
    for (int i = 0; i < r; i++) /* eigenvalues of M / n: s_i^2 / n */
        ld += log(s[i] * s[i] / n);
    for (int j = 0; j < np; j++) {
        double u[CRIT_MAXP] = {0}, v = 0.0;
        for (int i = 0; i < r; i++)
            v += V[j + i * np] * V[j + i * np] / (s[i] * s[i] / n);
        vf[j] = v;
        u[j] = 1.0;
        flg[j] = igea__accel_loading(np, r, V, u) > IGEA_ACCEL_LOADING_TOL ? IGEA_ACCEL_PRIOR
                                                                           : IGEA_ACCEL_DATA;
    }
    ld /= r;
    if (!isfinite(ld) || !igea__finite_vec(np, vf, 1))
        return IGEA_EOVERFLOW;
    *logdet = ld;
    if (varfac)
        memcpy(varfac, vf, (size_t)np * sizeof(double));
    if (flag)
        memcpy(flag, flg, (size_t)np * sizeof(int));
    *rank = r;
    return 0;
}
