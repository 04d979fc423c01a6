/* stability_dev.c - Stable32's frequency-stability statistics on phase or
 * frequency data (NIST SP 1065), Greenhall and Riley's EDF, noise
 * identification per averaging time (docs/stability.md). */
#include <float.h>

#include "igea/stability.h"
#include "igea/stats.h"
#include "internal.h"
#include "stability_internal.h"


#define K_FIRST IGEA_STABILITY_ALLAN_ADEV
#define K_LAST IGEA_STABILITY_ALLAN_THEOH

/* Terms M of the kind on N phase points at averaging factor m (<= 0: none). */
static long dev_terms(int kind, long N, long m)
{
    switch (kind) {
    case IGEA_STABILITY_ALLAN_ADEV: return (N - 1) / m - 1;
    case IGEA_STABILITY_ALLAN_OADEV: return N - 2 * m;
    case IGEA_STABILITY_ALLAN_MDEV:
    case IGEA_STABILITY_ALLAN_TDEV:
    case IGEA_STABILITY_ALLAN_MTOTDEV:
    case IGEA_STABILITY_ALLAN_TTOTDEV: return N - 3 * m + 1;
    case IGEA_STABILITY_ALLAN_HDEV: return (N - 1) / m - 2;
    case IGEA_STABILITY_ALLAN_OHDEV:
    case IGEA_STABILITY_ALLAN_HTOTDEV: return N - 3 * m;
    case IGEA_STABILITY_ALLAN_TOTDEV: return m <= N - 1 ? N - 2 : 0;
    case IGEA_STABILITY_ALLAN_THEO1:
    case IGEA_STABILITY_ALLAN_THEOBR: return m % 2 == 0 && m <= N - 1 ? N - m : 0;
    default: return N - m; /* MTIE, TIERMS */
    }
}

static int theo_kind(int kind)
{
    return kind == IGEA_STABILITY_ALLAN_THEO1 || kind == IGEA_STABILITY_ALLAN_THEOBR;
}

/* THEOH: the switch k (in samples) from the Allan to the bias-removed Theo1
 * deviation, the largest power of 2 <= 0.2 (N - 1) (Howe 2006: the largest
 * tau <= 20 % of the record; the octave grid of tau0 [D]). */
static long theoh_switch(long N)
{
    long k = 1;
    while ((double)(2 * k) <= 0.2 * (double)(N - 1))
        k *= 2;
    return k;
}

/* The statistic that gives tau: the kind itself, or for THEOH the Allan
 * deviation (OADEV) below the switch and THEOBR from it on. */
static int sub_kind(int kind, double tau, double fs, long N)
{
    if (kind != IGEA_STABILITY_ALLAN_THEOH)
        return kind;
    double v = tau * fs, k = (double)theoh_switch(N);
    return v >= k * (1.0 - 1e-12) ? IGEA_STABILITY_ALLAN_THEOBR : IGEA_STABILITY_ALLAN_OADEV;
}

/* Averaging factor of tau: round(tau fs), THEO1 and THEOBR round(tau fs /
 * 0.75); 0 when out of range (kind: a sub_kind). */
static long dev_factor(int kind, double tau, double fs, long N)
{
    double v = tau * fs / (theo_kind(kind) ? 0.75 : 1.0);
    if (!(isfinite(tau) && tau > 0.0 && v >= 0.5 && v <= (double)N))
        return 0;
    return lround(v);
}

/* Second (d = 2) or third (d = 3) difference of x at i with spacing m. */
static inline double diff_at(const double *x, long i, long m, int d)
{
    if (d == 2)
        return (x[i + 2 * m] - x[i + m]) - (x[i + m] - x[i]);
    return ((x[i + 3 * m] - x[i + 2 * m]) - (x[i + 2 * m] - x[i + m])) -
           ((x[i + 2 * m] - x[i + m]) - (x[i + m] - x[i]));
}

/* Allan (d = 2) or Hadamard (d = 3) deviation, stride 1 or m. */
static double dev_diff(long N, const double *x, long m, long stride, int d, double tau)
{
    igea__sqacc a = {{0, 0}, 0, 0};
    long c = 0;
    for (long i = 0; i + d * m < N; i += stride, c++)
        igea__sqacc_add(&a, diff_at(x, i, m, d));
    return sqrt(igea__sqacc_get(&a) / ((d == 2 ? 2.0 : 6.0) * (double)c)) / tau;
}

/* Modified Allan deviation: running sums S_j of m second differences. */
static double dev_mod(long N, const double *x, long m, double tau)
{
    igea__ksum S = {0, 0};
    for (long i = 0; i < m; i++)
        igea__ksum_add(&S, diff_at(x, i, m, 2));
    long M = N - 3 * m + 1;
    igea__sqacc a = {{0, 0}, 0, 0};
    for (long j = 0; j < M; j++) {
        double s = igea__ksum_get(&S);
        igea__sqacc_add(&a, s);
        if (j + 1 < M) {
            igea__ksum_add(&S, diff_at(x, j + m, m, 2));
            igea__ksum_add(&S, -diff_at(x, j, m, 2));
        }
    }
    double md = (double)m;
    return sqrt(igea__sqacc_get(&a) / (2.0 * md * md * (double)M)) / tau;
}

/* Doubly reflected series of TOTDEV at index k in [-(N-2), 2N-3]. */
static inline double refl(long N, const double *x, long k)
{
    if (k < 0)
        return 2.0 * x[0] - x[-k];
    if (k > N - 1)
        return 2.0 * x[N - 1] - x[2 * (N - 1) - k];
    return x[k];
}

static double dev_tot(long N, const double *x, long m, double tau)
{
    igea__sqacc a = {{0, 0}, 0, 0};
    for (long i = 1; i <= N - 2; i++)
        igea__sqacc_add(&a, (refl(N, x, i + m) - refl(N, x, i)) - (refl(N, x, i) - refl(N, x, i - m)));
    return sqrt(igea__sqacc_get(&a) / (2.0 * (double)(N - 2))) / tau;
}

/* One 3m-point subsequence s (MTOTDEV: phase; HTOTDEV: frequency): the
 * half-average slope removed, even reflection to 9m points in w, and the
 * mean over the 6m positions of (sum1 - 2 sum2 + sum3)^2 / m^2 of three
 * adjacent m-point sums. */
static double tot_sub(const double *s, long m, double *w)
{
    long L = 3 * m, h1 = L / 2, h2 = L - L / 2;
    igea__ksum a = {0, 0}, b = {0, 0};
    for (long k = 0; k < h1; k++)
        igea__ksum_add(&a, s[k]);
    for (long k = h2; k < L; k++)
        igea__ksum_add(&b, s[k]);
    double slope = (igea__ksum_get(&b) / (double)(L - h2) - igea__ksum_get(&a) / (double)h1) /
                   (double)(L % 2 ? h1 + 1 : h1);
    for (long k = 0; k < L; k++) {
        double v = s[k] - slope * (double)(k - h1);
        w[L + k] = v;
        w[L - 1 - k] = v;
        w[3 * L - 1 - k] = v;
    }
    igea__ksum s1 = {0, 0}, s2 = {0, 0}, s3 = {0, 0};
    for (long k = 0; k < m; k++) {
        igea__ksum_add(&s1, w[k]);
        igea__ksum_add(&s2, w[m + k]);
        igea__ksum_add(&s3, w[2 * m + k]);
    }
    igea__sqacc acc = {{0, 0}, 0, 0};
    for (long j = 0; j < 6 * m; j++) {
        if (j > 0) {
            igea__ksum_add(&s1, w[j + m - 1] - w[j - 1]);
            igea__ksum_add(&s2, w[j + 2 * m - 1] - w[j + m - 1]);
            igea__ksum_add(&s3, w[j + 3 * m - 1] - w[j + 2 * m - 1]);
        }
        double g1 = igea__ksum_get(&s1), g2 = igea__ksum_get(&s2), g3 = igea__ksum_get(&s3);
        igea__sqacc_add(&acc, ((g3 - g2) - (g2 - g1)) / (double)m);
    }
    return igea__sqacc_get(&acc) / (6.0 * (double)m);
}

/* MTOTDEV (hadamard = 0, x phase) or HTOTDEV (hadamard = 1, x frequency of
 * N - 1 samples); w holds 9m doubles. */
static double dev_mtot(long N, const double *x, long m, double tau, int hadamard, double *w)
{
    long len = hadamard ? N - 1 : N, M = len - 3 * m + 1;
    igea__ksum acc = {0, 0};
    for (long i = 0; i < M; i++)
        igea__ksum_add(&acc, tot_sub(x + i, m, w));
    double v = igea__ksum_get(&acc) / (double)M;
    return hadamard ? sqrt(v / 6.0) : sqrt(v / 2.0) / tau;
}

/* Theo1 variance at even m: the terms summed offset by offset (d = 0 ..
 * m/2 - 1, each over i with a vector kernel), weights 1 / (m/2 - d). */
static double theo1_var(long N, const double *x, long m, double tau0)
{
    long h = m / 2, L = N - m;
    igea__ksum acc = {0, 0};
    for (long d = 0; d < h; d++)
        igea__ksum_add(&acc, igea__ap_sumsq4(x, x + h - d, x + m, x + h + d, L) / (double)(h - d));
    double mt = (double)m * tau0;
    return igea__ksum_get(&acc) / (0.75 * (double)L * mt * mt);
}

static double dev_theo1(long N, const double *x, long m, double tau0)
{
    return sqrt(theo1_var(N, x, m, tau0));
}

/* TheoBR's bias factor (Taylor and Howe 2010): the mean over i = 0 .. n of
 * AVAR(m = 9 + 3i) / Theo1(m = 12 + 4i), n = floor(0.1 N / 3) - 3 (N >= 90). */
static double theobr_factor(long N, const double *x, double tau0, long *nrat)
{
    long n = (long)floor(0.1 * (double)N / 3.0) - 3;
    igea__ksum k = {0, 0};
    for (long i = 0; i <= n; i++) {
        long ma = 9 + 3 * i, mt = 12 + 4 * i;
        double a = dev_diff(N, x, ma, 1, 2, (double)ma * tau0);
        igea__ksum_add(&k, a * a / theo1_var(N, x, mt, tau0));
    }
    *nrat = n + 1;
    return igea__ksum_get(&k) / (double)(n + 1);
}

/* Theo1's bias AVAR / Theo1 at tau = r tau0 by noise type (Howe, Tasset and
 * Percival, "Theo1: characterization of very long-term frequency
 * stability", EFTF 2004, Table 1): a + b / r^c. */
static double theo1_bias(int a, double r)
{
    switch (a) {
    case IGEA_STABILITY_NOISE_WPM: return 0.09 + 0.74 / pow(r, 0.40);
    case IGEA_STABILITY_NOISE_FPM: return 0.14 + 0.82 / pow(r, 0.30);
    case IGEA_STABILITY_NOISE_WFM: return 1.0;
    case IGEA_STABILITY_NOISE_FFM: return 1.87 - 1.05 / pow(r, 0.79);
    default: return 2.70 - 1.53 / pow(r, 0.85);
    }
}

/* The noise type of TheoBR's factor kf: against the mean of the nominal bias
 * over the same taus (9 + 3i) tau0, i = 0 .. n - 1, boundaries at the
 * geometric means of neighbouring types [D]. */
static int theobr_alpha(double kf, long nrat)
{
    double e[5];
    for (int a = 2; a >= -2; a--) {
        igea__ksum s = {0, 0};
        for (long i = 0; i < nrat; i++)
            igea__ksum_add(&s, theo1_bias(a, 9.0 + 3.0 * (double)i));
        e[2 - a] = igea__ksum_get(&s) / (double)nrat;
    }
    for (int j = 0; j < 4; j++)
        if (kf < sqrt(e[j] * e[j + 1]))
            return 2 - j;
    return IGEA_STABILITY_NOISE_RWFM;
}

/* MTIE with monotonic queues of indices (q: 2N longs). */
static double dev_mtie(long N, const double *x, long m, long *q)
{
    long *qa = q, *qb = q + N, ha = 0, ta = 0, hb = 0, tb = 0;
    double best = 0.0;
    for (long k = 0; k < N; k++) {
        while (ta > ha && x[qa[ta - 1]] <= x[k])
            ta--;
        qa[ta++] = k;
        while (tb > hb && x[qb[tb - 1]] >= x[k])
            tb--;
        qb[tb++] = k;
        if (k >= m) {
            long i = k - m; /* window i .. k */
            while (qa[ha] < i)
                ha++;
            while (qb[hb] < i)
                hb++;
            double r = x[qa[ha]] - x[qb[hb]];
            if (r > best)
                best = r;
        }
    }
    return best;
}

static double dev_tierms(long N, const double *x, long m)
{
    igea__sqacc a = {{0, 0}, 0, 0};
    for (long i = 0; i + m < N; i++)
        igea__sqacc_add(&a, x[i + m] - x[i]);
    return sqrt(igea__sqacc_get(&a) / (double)(N - m));
}

/* The statistic at averaging factor m; y: the frequency (HTOTDEV), w: 9m
 * doubles, q: 2N longs. */
static double dev_one(int kind, long N, const double *x, const double *y, long m, double tau0,
                      double *w, long *q)
{
    double tau = (double)m * tau0;
    switch (kind) {
    case IGEA_STABILITY_ALLAN_ADEV: return dev_diff(N, x, m, m, 2, tau);
    case IGEA_STABILITY_ALLAN_OADEV: return dev_diff(N, x, m, 1, 2, tau);
    case IGEA_STABILITY_ALLAN_MDEV: return dev_mod(N, x, m, tau);
    case IGEA_STABILITY_ALLAN_TDEV: return tau * dev_mod(N, x, m, tau) / sqrt(3.0);
    case IGEA_STABILITY_ALLAN_HDEV: return dev_diff(N, x, m, m, 3, tau);
    case IGEA_STABILITY_ALLAN_OHDEV: return dev_diff(N, x, m, 1, 3, tau);
    case IGEA_STABILITY_ALLAN_TOTDEV: return dev_tot(N, x, m, tau);
    case IGEA_STABILITY_ALLAN_MTOTDEV: return dev_mtot(N, x, m, tau, 0, w);
    case IGEA_STABILITY_ALLAN_TTOTDEV: return tau * dev_mtot(N, x, m, tau, 0, w) / sqrt(3.0);
    case IGEA_STABILITY_ALLAN_HTOTDEV:
        return m == 1 ? dev_diff(N, x, 1, 1, 3, tau) : dev_mtot(N, y, m, tau, 1, w);
    case IGEA_STABILITY_ALLAN_THEO1: return dev_theo1(N, x, m, tau0);
    case IGEA_STABILITY_ALLAN_MTIE: return dev_mtie(N, x, m, q);
    default: return dev_tierms(N, x, m);
    }
}

/* ---- Greenhall and Riley's EDF (PTTI 2003, eqs. 7-13, Tables 1-3) ---- */

static double g_sw(double t, int a)
{
    double u = fabs(t);
    switch (a) {
    case 2: return -u;
    case 1: return u > 0.0 ? t * t * log(u) : 0.0;
    case 0: return u * u * u;
    case -1: return u > 0.0 ? t * t * t * t * log(u) : 0.0;
    case -2: return u * u * u * u * u;
    case -3: return u > 0.0 ? pow(t, 6) * log(u) : 0.0;
    default: return pow(u, 7);
    }
}

static double g_sx(double t, double F, int a)
{
    if (isinf(F))
        return g_sw(t, a + 2);
    return F * F * (2.0 * g_sw(t, a) - g_sw(t - 1.0 / F, a) - g_sw(t + 1.0 / F, a));
}

static double g_sz(double t, double F, int a, int d)
{
    static const double c[4][4] = {{0}, {2, -1}, {6, -4, 1}, {20, -15, 6, -1}};
    double s = c[d][0] * g_sx(t, F, a);
    for (int k = 1; k <= d; k++)
        s += c[d][k] * (g_sx(t - k, F, a) + g_sx(t + k, F, a));
    return s;
}

static double g_bsum(double J, double M, double S, double F, int a, int d)
{
    double z0 = g_sz(0.0, F, a, d), zJ = g_sz(J / S, F, a, d);
    double s = z0 * z0 + (1.0 - J / M) * zJ * zJ;
    for (long j = 1; j < (long)J; j++) {
        double z = g_sz((double)j / S, F, a, d);
        s += 2.0 * (1.0 - (double)j / M) * z * z;
    }
    return s;
}

/* EDF of unmodified white PM when ceil(M / S) <= d (Greenhall's case 4.1,
 * computed exactly: terms are binomial filters of white phase, correlated
 * only at lags that are multiples of m). */
static double edf_wpm_short(int d, double m, double S, double M)
{
    static const double c[4][7] = {{0}, {1, -2, 1}, {1, -3, 3, -1}, {1, -4, 6, -4, 1}};
    const double *cd = c[d - 1];
    double c0 = 0.0, den = M;
    for (int k = 0; k <= d; k++)
        c0 += cd[k] * cd[k];
    for (long l = 1; l < (long)M; l++) {
        double lag = (double)l * m / S; /* samples */
        double q = lag / m;
        if (q != floor(q) || q > d)
            continue;
        double r = 0.0;
        for (int k = 0; k + (int)q <= d; k++)
            r += cd[k] * cd[k + (int)q];
        r /= c0;
        den += 2.0 * (M - (double)l) * r * r;
    }
    return M * M / den;
}

double igea__stability_edf_greenhall(int a, int d, double m, double N, int overlapping,
                                     int modified)
{
    static const double t1[7][3][2] = {
        {{2. / 3, 1. / 3}, {7. / 9, 0.5}, {22. / 25, 2. / 3}}, {{0.840, 0.345}, {0.997, 0.616}, {1.141, 0.843}},
        {{1.079, 0.368}, {1.033, 0.607}, {1.184, 0.848}}, {{-1, -1}, {1.048, 0.534}, {1.180, 0.816}},
        {{-1, -1}, {1.302, 0.535}, {1.175, 0.777}}, {{-1, -1}, {-1, -1}, {1.194, 0.703}},
        {{-1, -1}, {-1, -1}, {1.489, 0.702}}};
    static const double t2[7][3][2] = {
        {{1.5, 0.5}, {35. / 18, 1.0}, {231. / 100, 1.5}}, {{78.6, 25.2}, {790., 410.}, {9950., 6520.}},
        {{2. / 3, 1. / 6}, {2. / 3, 1. / 3}, {7. / 9, 0.5}}, {{-1, -1}, {0.852, 0.375}, {0.997, 0.617}},
        {{-1, -1}, {1.079, 0.368}, {1.033, 0.607}}, {{-1, -1}, {-1, -1}, {1.053, 0.553}},
        {{-1, -1}, {-1, -1}, {1.302, 0.535}}};
    static const double t3[3][2] = {{6.0, 4.0}, {15.23, 12.0}, {47.8, 40.0}};
    const double Jmax = 100.0, inf = INFINITY;
    double F = modified ? 1.0 : m, S = overlapping ? m : 1.0;
    double L = m / F + m * d, M = 1.0 + floor(S * (N - L) / m);
    double J = IGEA_MIN(M, (d + 1) * S), r = M / S;
    int row = 2 - a, col = d - 1;
    if (modified) {
        double z0 = g_sz(0.0, 1.0, a, d);
        if (J <= Jmax)
            return z0 * z0 * M / g_bsum(J, M, S, 1.0, a, d);
        if (r > d + 1)
            return 1.0 / ((t1[row][col][0] - t1[row][col][1] / r) / r);
        return z0 * z0 * Jmax / g_bsum(Jmax, Jmax, Jmax / r, 1.0, a, d);
    }
    if (a <= 0) {
        if (J <= Jmax) {
            double mp = m * (d + 1) <= Jmax ? m : inf, z0 = g_sz(0.0, mp, a, d);
            return z0 * z0 * M / g_bsum(J, M, S, mp, a, d);
        }
        if (r > d + 1)
            return 1.0 / ((t2[row][col][0] - t2[row][col][1] / r) / r);
        double z0 = g_sz(0.0, inf, a, d);
        return z0 * z0 * Jmax / g_bsum(Jmax, Jmax, Jmax / r, inf, a, d);
    }
    if (a == 1) {
        double b = t3[col][0] + t3[col][1] * log(m);
        if (J <= Jmax) {
            double z0 = g_sz(0.0, m, 1, d);
            return z0 * z0 * M / g_bsum(J, M, S, m, 1, d);
        }
        if (r > d + 1)
            return 1.0 / ((t2[row][col][0] - t2[row][col][1] / r) / (b * b * r));
        return b * b * Jmax / g_bsum(Jmax, Jmax, Jmax / r, Jmax / r, 1, d);
    }
    if (ceil(r) <= d) /* a == 2 */
        return edf_wpm_short(d, m, S, M);
    double a0 = d == 2 ? 70.0 / 36.0 : 924.0 / 400.0; /* C(4d,2d) / C(2d,d)^2 */
    return 1.0 / ((a0 - 0.5 * d / r) / M);
}

/* EDF of Theo1 (and of THEOBR, whose factor is taken as exact) at even m
 * on N phase points (Howe and Peppler 2003; NIST SP 1065 section 5.5.4,
 * with r = 0.75 m, the averaging factor of the tau Theo1 reports). */
static double theo1_edf(int a, double N, double m)
{
    double r = 0.75 * m;
    switch (a) {
    case IGEA_STABILITY_NOISE_WPM:
        return 0.86 * (N + 1.0) * (N - 4.0 * r / 3.0) / (N - r) * (r / (r + 1.14));
    case IGEA_STABILITY_NOISE_FPM:
        return (4.798 * N * N - 6.374 * N * r + 12.387 * r) / (sqrt(r + 36.6) * (N - r)) *
               (r / (r + 0.3));
    case IGEA_STABILITY_NOISE_WFM:
        return ((4.1 * N + 0.8) / r - (3.1 * N + 6.5) / N) * (pow(r, 1.5) / (pow(r, 1.5) + 5.2));
    case IGEA_STABILITY_NOISE_FFM:
        return (2.0 * N * N - 1.3 * N * r - 3.5 * r) / (N * r) * (r * r * r / (r * r * r + 2.3));
    default: {
        double q = 4.4 * N - 1.0;
        return (4.4 * N - 2.0) / (2.9 * r) * (q * q - 8.6 * r * q + 11.4 * r * r) /
               ((4.4 * N - 3.0) * (4.4 * N - 3.0));
    }
    }
}

/* EDF of HTOTDEV (Howe et al., "A total estimator of the Hadamard function
 * used for GPS operations", PTTI 2000; NIST SP 1065 section 5.5.5): (N / m)
 * / (b0 + b1 m / N) for m >= 16 and white, flicker or random-walk FM; the
 * OHDEV EDF (Greenhall's) below m = 16 (as Stable32) and for PM noise [D]. */
static double htot_edf(int a, double N, double m)
{
    static const double b[3][2] = {{0.559, 1.004}, {0.868, 1.140}, {0.938, 1.696}};
    if (m < 16.0 || a > 0)
        return igea__stability_edf_greenhall(a, 3, m, N, 1, 0);
    return (N / m) / (b[-a][0] + b[-a][1] * m / N);
}

/* EDF of the kind (a sub_kind; NaN: no interval for this kind). */
static double dev_edf(int kind, int a, double N, double m)
{
    static const double t7[3][2] = {{1.50, 0.0}, {1.17, 0.22}, {0.93, 0.36}};
    static const double t8[5][2] = {{1.90, 2.1}, {1.20, 1.40}, {1.10, 1.2}, {0.85, 0.50}, {0.75, 0.31}};
    switch (kind) {
    case IGEA_STABILITY_ALLAN_ADEV: return igea__stability_edf_greenhall(a, 2, m, N, 0, 0);
    case IGEA_STABILITY_ALLAN_OADEV: return igea__stability_edf_greenhall(a, 2, m, N, 1, 0);
    case IGEA_STABILITY_ALLAN_MDEV:
    case IGEA_STABILITY_ALLAN_TDEV: return igea__stability_edf_greenhall(a, 2, m, N, 1, 1);
    case IGEA_STABILITY_ALLAN_HDEV: return igea__stability_edf_greenhall(a, 3, m, N, 0, 0);
    case IGEA_STABILITY_ALLAN_OHDEV: return igea__stability_edf_greenhall(a, 3, m, N, 1, 0);
    case IGEA_STABILITY_ALLAN_TOTDEV:
        if (a > 0)
            return igea__stability_edf_greenhall(a, 2, m, N, 1, 0);
        return t7[-a][0] * N / m - t7[-a][1];
    case IGEA_STABILITY_ALLAN_MTOTDEV:
    case IGEA_STABILITY_ALLAN_TTOTDEV: return t8[2 - a][0] * N / m - t8[2 - a][1];
    case IGEA_STABILITY_ALLAN_HTOTDEV: return htot_edf(a, N, m);
    case IGEA_STABILITY_ALLAN_THEO1:
    case IGEA_STABILITY_ALLAN_THEOBR: return theo1_edf(a, N, m);
    default: return NAN;
    }
}

/* ---- noise identification at one averaging factor ---- */

/* The series of the lag-1 identification at factor m, generated on the fly
 * from the phase (no copy of its length): u_k, k < K, the phase decimated
 * by m (phase data) or its m-sample differences (frequency data), less the
 * least-squares quadratic or line in k, differenced d times. */
typedef struct {
    const double *x;
    long m, K;
    int phase, d;
    double c, p2m, b0, b1, b2;
} nser;

static inline double nser_u(const nser *s, long k)
{
    return s->phase ? s->x[k * s->m] : s->x[(k + 1) * s->m] - s->x[k * s->m];
}

/* The detrended value at k (the subtraction of detrend2 / detrend1). */
static inline double nser_r(const nser *s, long k)
{
    double t = (double)k - s->c;
    return s->phase ? nser_u(s, k) - (s->b0 + s->b1 * t + s->b2 * (t * t - s->p2m))
                    : nser_u(s, k) - (s->b0 + s->b1 * t);
}

/* Element k of the series differenced d times ((r_{k+1} - r_k), ...). */
static inline double nser_at(const nser *s, long k)
{
    if (s->d == 0)
        return nser_r(s, k);
    if (s->d == 1)
        return nser_r(s, k + 1) - nser_r(s, k);
    return (nser_r(s, k + 2) - nser_r(s, k + 1)) - (nser_r(s, k + 1) - nser_r(s, k));
}

/* The least-squares quadratic (phase) or line in k of u (orthogonal
 * polynomials on k = 0 .. K-1). */
static void nser_trend(nser *s)
{
    double c = 0.5 * (double)(s->K - 1), Kd = (double)s->K;
    double p2m = (Kd * Kd - 1.0) / 12.0; /* mean of (k-c)^2 */
    igea__ksum s0 = {0, 0}, s1 = {0, 0}, s2 = {0, 0}, n1 = {0, 0}, n2 = {0, 0};
    for (long k = 0; k < s->K; k++) {
        double t = (double)k - c, q = t * t - p2m, z = nser_u(s, k);
        igea__ksum_add(&s0, z);
        igea__ksum_add(&s1, z * t);
        if (s->phase)
            igea__ksum_add(&s2, z * q);
        igea__ksum_add(&n1, t * t);
        if (s->phase)
            igea__ksum_add(&n2, q * q);
    }
    s->c = c;
    s->p2m = p2m;
    s->b0 = igea__ksum_get(&s0) / Kd;
    s->b1 = igea__ksum_get(&s1) / igea__ksum_get(&n1);
    double nq = igea__ksum_get(&n2);
    s->b2 = s->phase && nq > 0.0 ? igea__ksum_get(&s2) / nq : 0.0;
}

/* Lag-1 autocorrelation of the series' first K values. */
static double lag1(const nser *z, long K)
{
    igea__ksum s = {0, 0};
    for (long i = 0; i < K; i++)
        igea__ksum_add(&s, nser_at(z, i));
    double mu = igea__ksum_get(&s) / (double)K;
    igea__ksum num = {0, 0}, den = {0, 0};
    double u = nser_at(z, 0) - mu;
    for (long i = 0; i < K; i++) {
        igea__ksum_add(&den, u * u);
        if (i + 1 < K) {
            double v = nser_at(z, i + 1) - mu;
            igea__ksum_add(&num, u * v);
            u = v;
        }
    }
    double dd = igea__ksum_get(&den);
    return dd > 0.0 ? igea__ksum_get(&num) / dd : 0.0;
}

static double b1_theory(double N, int mu)
{
    switch (mu) {
    case 1: return N / 2.0;
    case 0: return N * log(N) / (2.0 * (N - 1.0) * log(2.0));
    case -1: return 1.0;
    default: return (N * N - 1.0) / (1.5 * N * (N - 1.0));
    }
}

/* B1 / R(n) identification on K - 1 >= 4 averages of m samples. */
static int noise_b1(long N, const double *x, long m, double tau0, long K)
{
    long Kf = K - 1;
    double z[30];
    for (long k = 0; k < Kf; k++)
        z[k] = (x[(k + 1) * m] - x[k * m]) / ((double)m * tau0);
    igea__ksum s = {0, 0};
    for (long k = 0; k < Kf; k++)
        igea__ksum_add(&s, z[k]);
    double mu = igea__ksum_get(&s) / (double)Kf;
    igea__ksum v = {0, 0}, av = {0, 0};
    for (long k = 0; k < Kf; k++) {
        igea__ksum_add(&v, (z[k] - mu) * (z[k] - mu));
        if (k + 1 < Kf)
            igea__ksum_add(&av, (z[k + 1] - z[k]) * (z[k + 1] - z[k]));
    }
    double avar = igea__ksum_get(&av) / (2.0 * (double)(Kf - 1));
    double b1 = avar > 0.0 ? igea__ksum_get(&v) / (double)(Kf - 1) / avar : 1.0;
    for (int u = 1; u >= -1; u--)
        if (b1 > sqrt(b1_theory((double)Kf, u) * b1_theory((double)Kf, u - 1)))
            return -u - 1;
    /* white or flicker PM: R(n) = MVAR / AVAR against 1/m and Greenhall's FPM value */
    if (N - 3 * m + 1 < 1 || m == 1)
        return IGEA_STABILITY_NOISE_WPM;
    double tau = (double)m * tau0, md = dev_mod(N, x, m, tau), oa = dev_diff(N, x, m, 1, 2, tau);
    double rn = oa > 0.0 ? md * md / (oa * oa) : 0.0;
    const double pi = 3.14159265358979323846;
    double rf = (3.0 * log(256.0 / 27.0) / (8.0 * pi * pi)) /
                ((1.038 + 3.0 * log(pi * (double)m)) / (4.0 * pi * pi));
    return rn > sqrt(rf / (double)m) ? IGEA_STABILITY_NOISE_FPM : IGEA_STABILITY_NOISE_WPM;
}

/* Noise exponent alpha at averaging factor m. Frequency data: the
 * m-sample means, linear trend removed, alpha = -2 (delta + d); phase
 * data: the phase decimated by m, quadratic trend removed, alpha = 2 - 2
 * (delta + d) (allantools' autocorr_noise_id). */
static int noise_at(long N, const double *x, long m, double tau0, int phase)
{
    long K = (N - 1) / m + 1;
    if (K < 31) /* fewer than 30 means (or 31 phase points) */
        return K - 1 >= 4 ? noise_b1(N, x, m, tau0, K) : IGEA_STABILITY_NOISE_WFM;
    nser z = {x, m, phase ? K : K - 1, phase, 0, 0, 0, 0, 0, 0};
    nser_trend(&z);
    for (int d = 0;; d++) {
        z.d = d;
        double r1 = lag1(&z, z.K - d), delta = r1 / (1.0 + r1);
        if (delta < 0.25 || d == 2) {
            long a = (phase ? 2 : 0) - 2 * d - lround(2.0 * delta);
            return (int)IGEA_MAX(-2, IGEA_MIN(2, a));
        }
    }
}

/* ---- gaps (NaN) in ADEV, OADEV, MDEV, TDEV, HDEV, OHDEV ---- */

static int gap_kind(int kind)
{
    return kind >= IGEA_STABILITY_ALLAN_ADEV && kind <= IGEA_STABILITY_ALLAN_OHDEV;
}

/* P[k]: the gaps among the first k samples (frequency data: y_0 .. y_{k-1},
 * phase data: x_0 .. x_{k-1}). */
typedef struct {
    const long *P;
    int phase;
} gap_map;

/* 1 when the difference of order d at phase point i, spacing m, uses no gap:
 * frequency data, no gap among y_i .. y_{i+dm-1}; phase data, none of its d
 * + 1 points. */
static inline int gap_term_ok(const gap_map *g, long i, long m, int d)
{
    if (!g->phase)
        return g->P[i + d * m] == g->P[i];
    for (int k = 0; k <= d; k++)
        if (g->P[i + k * m + 1] != g->P[i + k * m])
            return 0;
    return 1;
}

/* Gap-resistant Allan (d = 2) or Hadamard (d = 3) deviation: the terms
 * holding a gap are skipped; *used, the terms summed. */
static double gap_diff(long N, const double *x, long m, long stride, int d, double tau,
                       const gap_map *g, long *used)
{
    igea__sqacc a = {{0, 0}, 0, 0};
    long c = 0;
    for (long i = 0; i + d * m < N; i += stride)
        if (gap_term_ok(g, i, m, d)) {
            igea__sqacc_add(&a, diff_at(x, i, m, d));
            c++;
        }
    *used = c;
    return c ? sqrt(igea__sqacc_get(&a) / ((d == 2 ? 2.0 : 6.0) * (double)c)) / tau : NAN;
}

/* Gap-resistant MDEV: term j (m second differences, samples j .. j + 3m -
 * 1 of either data type) skipped when it holds a gap. */
static double gap_mod(long N, const double *x, long m, double tau, const gap_map *g, long *used)
{
    igea__ksum S = {0, 0};
    for (long i = 0; i < m; i++)
        igea__ksum_add(&S, gap_term_ok(g, i, m, 2) ? diff_at(x, i, m, 2) : 0.0);
    long M = N - 3 * m + 1, c = 0, span = g->phase ? 3 * m : 3 * m - 1;
    igea__sqacc a = {{0, 0}, 0, 0};
    for (long j = 0; j < M; j++) {
        if (g->P[j + span] == g->P[j]) {
            igea__sqacc_add(&a, igea__ksum_get(&S));
            c++;
        }
        if (j + 1 < M) {
            if (gap_term_ok(g, j + m, m, 2))
                igea__ksum_add(&S, diff_at(x, j + m, m, 2));
            if (gap_term_ok(g, j, m, 2))
                igea__ksum_add(&S, -diff_at(x, j, m, 2));
        }
    }
    *used = c;
    double md = (double)m;
    return c ? sqrt(igea__sqacc_get(&a) / (2.0 * md * md * (double)c)) / tau : NAN;
}

static double gap_one(int kind, long N, const double *x, long m, double tau0, const gap_map *g,
                      long *used)
{
    double tau = (double)m * tau0;
    switch (kind) {
    case IGEA_STABILITY_ALLAN_ADEV: return gap_diff(N, x, m, m, 2, tau, g, used);
    case IGEA_STABILITY_ALLAN_OADEV: return gap_diff(N, x, m, 1, 2, tau, g, used);
    case IGEA_STABILITY_ALLAN_MDEV: return gap_mod(N, x, m, tau, g, used);
    case IGEA_STABILITY_ALLAN_TDEV: return tau * gap_mod(N, x, m, tau, g, used) / sqrt(3.0);
    case IGEA_STABILITY_ALLAN_HDEV: return gap_diff(N, x, m, m, 3, tau, g, used);
    default: return gap_diff(N, x, m, 1, 3, tau, g, used); /* OHDEV */
    }
}

/* The phase points N' whose record without gaps has `used` terms (the
 * inverse of dev_terms), for the EDF [D]. */
static long gap_points(int kind, long used, long m)
{
    switch (kind) {
    case IGEA_STABILITY_ALLAN_ADEV: return (used + 1) * m + 1;
    case IGEA_STABILITY_ALLAN_OADEV: return used + 2 * m;
    case IGEA_STABILITY_ALLAN_HDEV: return (used + 2) * m + 1;
    case IGEA_STABILITY_ALLAN_OHDEV: return used + 3 * m;
    default: return used + 3 * m - 1; /* MDEV, TDEV */
    }
}

/* Scan of the record: IGEA_ENONFINITE for an infinity, for a NaN when the
 * kind takes no gaps, or when every sample is NaN; *gaps, the NaNs. */
static int gap_scan(int n, const double *x, int kind, long *gaps)
{
    long c = 0;
    for (int i = 0; i < n; i++) {
        if (isinf(x[i]))
            return IGEA_ENONFINITE;
        c += isnan(x[i]) != 0;
    }
    if (c && (!gap_kind(kind) || c == n))
        return IGEA_ENONFINITE;
    *gaps = c;
    return 0;
}

/* Phase points of a record with gaps, and the gap counts P (n + 1 longs):
 * frequency data integrated with a gap counted as the mean of the others
 * (it enters no term that is kept); phase data less its first value, a gap
 * filled by the line between its neighbours (only the noise
 * identification sees the filled values) [D]. */
static double *gap_phase(int n, const double *v, double fs, int type, long *P, long *N)
{
    long Np = type == IGEA_STABILITY_DATA_PHASE ? n : (long)n + 1;
    double *x = igea__dalloc((size_t)Np);
    if (!x)
        return NULL;
    P[0] = 0;
    for (int i = 0; i < n; i++)
        P[i + 1] = P[i] + (isnan(v[i]) != 0);
    if (type == IGEA_STABILITY_DATA_PHASE) {
        long a = -1; /* the last finite point */
        for (long i = 0; i < Np; i++) {
            if (isnan(v[i]))
                continue;
            double base = v[i], va = a < 0 ? v[i] : v[a];
            for (long k = a + 1; k <= i; k++)
                x[k] = a < 0 ? v[i] : va + (base - va) * (double)(k - a) / (double)(i - a);
            a = i;
        }
        for (long k = a + 1; k < Np; k++)
            x[k] = v[a];
        double x0 = x[0];
        for (long i = 0; i < Np; i++)
            x[i] -= x0;
    } else {
        igea__ksum mu = {0, 0}, k = {0, 0};
        for (int i = 0; i < n; i++)
            if (!isnan(v[i]))
                igea__ksum_add(&mu, v[i]);
        double mm = igea__ksum_get(&mu) / (double)(n - P[n]);
        x[0] = 0.0;
        for (int i = 0; i < n; i++) {
            if (!isnan(v[i]))
                igea__ksum_add(&k, v[i] - mm);
            x[i + 1] = igea__ksum_get(&k) / fs;
        }
    }
    *N = Np;
    return x;
}

/* ---- what the stream (stability_stream.c) shares ---- */

long igea__stability_dev_factor(int kind, double tau, double fs, long N)
{
    return dev_factor(kind, tau, fs, N);
}

long igea__stability_dev_terms(int kind, long N, long m) { return dev_terms(kind, N, m); }

double igea__stability_dev_edf(int kind, int alpha, double N, double m)
{
    return dev_edf(kind, alpha, N, m);
}

void igea__stability_pass_spec(int kind, long m, int acf, igea__aptau_spec *sp)
{
    int had = kind == IGEA_STABILITY_ALLAN_HDEV || kind == IGEA_STABILITY_ALLAN_OHDEV;
    int mod = kind == IGEA_STABILITY_ALLAN_MDEV || kind == IGEA_STABILITY_ALLAN_TDEV ||
              kind == IGEA_STABILITY_ALLAN_MODIFIED;
    sp->m = m;
    sp->type = mod ? IGEA__AP_MV : had ? IGEA__AP_HV : IGEA__AP_AV;
    sp->stride = kind != IGEA_STABILITY_ALLAN_ADEV && kind != IGEA_STABILITY_ALLAN_HDEV &&
                 kind != IGEA_STABILITY_ALLAN_NONOVERLAPPING;
    sp->acf = acf;
}

double igea__stability_pass_dev(int kind, int phase, double fs, long m, double ss, long cnt)
{
    int had = kind == IGEA_STABILITY_ALLAN_HDEV || kind == IGEA_STABILITY_ALLAN_OHDEV;
    int mod = kind == IGEA_STABILITY_ALLAN_MDEV || kind == IGEA_STABILITY_ALLAN_TDEV ||
              kind == IGEA_STABILITY_ALLAN_MODIFIED;
    double md = (double)m, tau = md / fs;
    /* phase data in seconds: / tau^2; frequency: the samples' sums / m^2 */
    double sc = phase ? tau * tau : md * md;
    double var = ss / ((had ? 6.0 : 2.0) * (double)cnt * sc);
    if (mod)
        var /= md * md;
    double d = sqrt(var);
    return kind == IGEA_STABILITY_ALLAN_TDEV ? d * tau / sqrt(3.0) : d;
}

/* ---- one pass for the Allan and Hadamard kinds (stability_pass.c) ---- */

/* The deviations d of ADEV .. OHDEV at the factors m[ntau] of the record v
 * (n frequency samples or phase points) in one pass. 0 or IGEA_ENOMEM. */
static int dev_pass(int n, const double *v, double fs, int data_type, int kind, int ntau,
                    const long *m, double *d)
{
    igea__aptau_spec *sp = calloc((size_t)ntau, sizeof *sp);
    igea__apass *p = NULL;
    if (!sp)
        return IGEA_ENOMEM;
    for (int j = 0; j < ntau; j++)
        igea__stability_pass_spec(kind, m[j], 0, &sp[j]);
    int phase = data_type == IGEA_STABILITY_DATA_PHASE;
    int st = igea__apass_whole(phase, ntau, sp, n, v, &p);
    for (int j = 0; j < ntau && !st; j++) {
        double ss;
        long cnt;
        igea__apass_get(p, j, &ss, &cnt);
        d[j] = igea__stability_pass_dev(kind, phase, fs, m[j], ss, cnt);
    }
    igea__apass_free(p);
    free(sp);
    return st;
}

/* ---- the entry points ---- */

/* Mean of Htotvar / Hvar by noise type (Howe et al.; Stable32 divides it
 * out): white, flicker, random-walk FM 0.995, 0.851, 0.771; the white-FM
 * value for white and flicker PM [D]. */
static double htot_bias(int a)
{
    return a == IGEA_STABILITY_NOISE_FFM ? 0.851 : a == IGEA_STABILITY_NOISE_RWFM ? 0.771 : 0.995;
}

/* Phase points of the record (N of them): phase data less its first value;
 * frequency data integrated (mean removed unless raw). */
static double *to_phase(int n, const double *v, double fs, int type, int raw, long *N)
{
    long Np = type == IGEA_STABILITY_DATA_PHASE ? n : (long)n + 1;
    double *x = igea__dalloc((size_t)Np);
    if (!x)
        return NULL;
    if (type == IGEA_STABILITY_DATA_PHASE) {
        for (long i = 0; i < Np; i++)
            x[i] = v[i] - v[0];
    } else {
        igea__ksum mu = {0, 0}, k = {0, 0};
        for (int i = 0; i < n && !raw; i++)
            igea__ksum_add(&mu, v[i]);
        double mm = raw ? 0.0 : igea__ksum_get(&mu) / (double)n;
        x[0] = 0.0;
        for (int i = 0; i < n; i++) {
            igea__ksum_add(&k, v[i] - mm);
            x[i + 1] = igea__ksum_get(&k) / fs;
        }
    }
    *N = Np;
    return x;
}

static int dev_check(int n, const double *x, double fs, int data_type, int ntau,
                     const double *tau, int kind, int noise, double conf, const double *dev,
                     const double *lo, const double *hi, const double *edf)
{
    if (n < 2)
        return -1;
    if (!x)
        return -2;
    if (!(isfinite(fs) && fs > 0.0))
        return -3;
    if (data_type != IGEA_STABILITY_DATA_FREQ && data_type != IGEA_STABILITY_DATA_PHASE)
        return -4;
    if (ntau < 1)
        return -5;
    if (!tau)
        return -6;
    if (kind < K_FIRST || kind > K_LAST)
        return -7;
    long N = data_type == IGEA_STABILITY_DATA_PHASE ? n : (long)n + 1;
    if ((kind == IGEA_STABILITY_ALLAN_THEOBR || kind == IGEA_STABILITY_ALLAN_THEOH) && N < 90)
        return -1; /* TheoBR's factor needs n = floor(0.1 N / 3) - 3 >= 0 */
    for (int j = 0; j < ntau; j++) {
        int sk = sub_kind(kind, tau[j], fs, N);
        long m = dev_factor(sk, tau[j], fs, N);
        if (m < 1 || dev_terms(sk, N, m) < 1)
            return -6;
    }
    if (!(noise == IGEA_STABILITY_NOISE_AUTO ||
          (noise >= IGEA_STABILITY_NOISE_RWFM && noise <= IGEA_STABILITY_NOISE_WPM)))
        return -8;
    if (!(conf > 0.0 && conf < 1.0))
        return -9;
    if (!dev)
        return -10;
    int noci = kind == IGEA_STABILITY_ALLAN_MTIE || kind == IGEA_STABILITY_ALLAN_TIERMS;
    if (noci && lo)
        return -11;
    if (noci && hi)
        return -12;
    if (noci && edf)
        return -13;
    return 0;
}

/* EDF and interval of every tau (alpha already set; sk the statistic of
 * each tau); with gaps, the EDF of the record without gaps that has the
 * terms used. */
static int dev_intervals(const int *sk, long N, int ntau, const long *m, const int *al,
                         double conf, int gaps, const long *used, const double *d, double *l,
                         double *h, double *e)
{
    for (int j = 0; j < ntau; j++) {
        double Nj = (double)(gaps ? gap_points(sk[j], used[j], m[j]) : N);
        double ev = dev_edf(sk[j], al[j], Nj, (double)m[j]);
        if (igea__edf_interval(d[j], ev, conf, &l[j], &h[j], &e[j]))
            return IGEA_ENOCONV;
    }
    return 0;
}

/* Workspace: phase x (not for the Allan and Hadamard kinds with the noise
 * type given), frequency y (HTOTDEV), 9 m_max doubles, 2N longs (MTIE),
 * n + 1 gap counts (gaps); per
 * tau: m, the terms used, alpha, the statistic (THEOH: OADEV or THEOBR),
 * and 4 ntau doubles of results. */
typedef struct {
    double *x, *y, *w, *r;
    long *q, *m, *P, *used;
    int *al, *sk;
} dev_ws;

static void ws_free(dev_ws *s)
{
    free(s->x);
    free(s->y);
    free(s->w);
    free(s->r);
    free(s->q);
    free(s->m);
    free(s->P);
    free(s->used);
    free(s->al);
    free(s->sk);
}

static int ws_alloc(dev_ws *s, int kind, long N, int ntau, long mmax)
{
    int tot = kind >= IGEA_STABILITY_ALLAN_MTOTDEV && kind <= IGEA_STABILITY_ALLAN_HTOTDEV;
    s->w = tot ? igea__dalloc(9 * (size_t)mmax) : NULL;
    s->y = kind == IGEA_STABILITY_ALLAN_HTOTDEV ? igea__dalloc((size_t)N) : NULL;
    s->q = kind == IGEA_STABILITY_ALLAN_MTIE ? malloc(2 * (size_t)N * sizeof(long)) : NULL;
    s->r = igea__dalloc(4 * (size_t)ntau);
    s->m = malloc((size_t)ntau * sizeof(long));
    s->used = malloc((size_t)ntau * sizeof(long));
    s->al = igea__ialloc((size_t)ntau);
    s->sk = igea__ialloc((size_t)ntau);
    if ((tot && !s->w) || (kind == IGEA_STABILITY_ALLAN_HTOTDEV && !s->y) ||
        (kind == IGEA_STABILITY_ALLAN_MTIE && !s->q) || !s->r || !s->m || !s->used || !s->al ||
        !s->sk)
        return IGEA_ENOMEM;
    return 0;
}

/* The phase points of the record (with gaps: and their counts in s->P). */
static int dev_phase(int n, const double *x, double fs, int data_type, int kind, long gaps,
                     dev_ws *s, long *N)
{
    int raw = kind == IGEA_STABILITY_ALLAN_MTIE || kind == IGEA_STABILITY_ALLAN_TIERMS;
    if (gaps) {
        s->P = malloc(((size_t)n + 1) * sizeof(long));
        s->x = s->P ? gap_phase(n, x, fs, data_type, s->P, N) : NULL;
    } else {
        s->x = to_phase(n, x, fs, data_type, raw, N);
    }
    return s->x ? 0 : IGEA_ENOMEM;
}

/* Copy the results of ntau taus out (the arguments of igea_stability_dev). */
static void dev_output(const dev_ws *s, int ntau, double tau0, double *dev, double *lo,
                       double *hi, double *edf, int *alpha, int *count, double *tau_used)
{
    size_t sz = (size_t)ntau * sizeof(double);
    const double *d = s->r, *l = d + ntau, *h = l + ntau, *e = h + ntau;
    memcpy(dev, d, sz);
    if (lo)
        memcpy(lo, l, sz);
    if (hi)
        memcpy(hi, h, sz);
    if (edf)
        memcpy(edf, e, sz);
    for (int j = 0; j < ntau; j++) {
        if (alpha)
            alpha[j] = s->al[j];
        if (count)
            count[j] = (int)s->used[j];
        if (tau_used)
            tau_used[j] = (double)s->m[j] * tau0 * (theo_kind(s->sk[j]) ? 0.75 : 1.0);
    }
}

/* The Allan parts of THEOH (the taus whose statistic is OADEV) in one pass. */
static int theoh_avar(int n, const double *x, double fs, int data_type, int ntau, const dev_ws *s,
                      double *d)
{
    long *m = malloc((size_t)ntau * sizeof(long));
    double *v = igea__dalloc((size_t)ntau);
    int k = 0, st = 0;
    if (!m || !v)
        st = IGEA_ENOMEM;
    for (int j = 0; j < ntau && !st; j++)
        if (s->sk[j] == IGEA_STABILITY_ALLAN_OADEV)
            m[k++] = s->m[j];
    if (!st && k)
        st = dev_pass(n, x, fs, data_type, IGEA_STABILITY_ALLAN_OADEV, k, m, v);
    for (int j = 0, i = 0; j < ntau && !st; j++)
        if (s->sk[j] == IGEA_STABILITY_ALLAN_OADEV)
            d[j] = v[i++];
    free(m);
    free(v);
    return st;
}

int igea_stability_dev(int n, const double *x, double fs, int data_type, int ntau,
                       const double *tau, int kind, int noise, double conf, double *dev,
                       double *lo, double *hi, double *edf, int *alpha, int *count,
                       double *tau_used)
{
    int st = dev_check(n, x, fs, data_type, ntau, tau, kind, noise, conf, dev, lo, hi, edf);
    long N = 0, mmax = 1, gaps = 0;
    if (st || (st = gap_scan(n, x, kind, &gaps)))
        return st;
    dev_ws s = {0};
    int htot = kind == IGEA_STABILITY_ALLAN_HTOTDEV, need_ci = lo || hi || edf;
    int need_id = (need_ci || alpha || htot) && noise == IGEA_STABILITY_NOISE_AUTO;
    /* the Allan and Hadamard kinds with the noise type given read the
     * record itself in their pass: no phase copy */
    N = data_type == IGEA_STABILITY_DATA_PHASE ? n : (long)n + 1;
    if (!(gap_kind(kind) && !gaps && !need_id) &&
        (st = dev_phase(n, x, fs, data_type, kind, gaps, &s, &N))) {
        ws_free(&s);
        return st;
    }
    for (int j = 0; j < ntau; j++) {
        int sk = sub_kind(kind, tau[j], fs, N);
        mmax = IGEA_MAX(mmax, dev_factor(sk, tau[j], fs, N));
    }
    if ((st = ws_alloc(&s, kind, N, ntau, mmax))) {
        ws_free(&s);
        return st;
    }
    double tau0 = 1.0 / fs, *d = s.r, *l = d + ntau, *h = l + ntau, *e = h + ntau;
    gap_map g = {s.P, data_type == IGEA_STABILITY_DATA_PHASE};
    if (s.y)
        for (long i = 0; i + 1 < N; i++)
            s.y[i] = (s.x[i + 1] - s.x[i]) * fs;
    int br = 0, br_alpha = noise;
    double kf = 1.0;
    for (int j = 0; j < ntau; j++) {
        s.sk[j] = sub_kind(kind, tau[j], fs, N);
        s.m[j] = dev_factor(s.sk[j], tau[j], fs, N);
        s.used[j] = dev_terms(s.sk[j], N, s.m[j]);
        br = br || s.sk[j] == IGEA_STABILITY_ALLAN_THEOBR;
    }
    if (br) { /* TheoBR's factor, and its noise type */
        long nrat;
        kf = theobr_factor(N, s.x, tau0, &nrat);
        if (noise == IGEA_STABILITY_NOISE_AUTO)
            br_alpha = theobr_alpha(kf, nrat);
    }
    int pass = !gaps && gap_kind(kind); /* the Allan and Hadamard kinds: one pass */
    if (pass && (st = dev_pass(n, x, fs, data_type, kind, ntau, s.m, d)))
        goto out;
    if (kind == IGEA_STABILITY_ALLAN_THEOH && (st = theoh_avar(n, x, fs, data_type, ntau, &s, d)))
        goto out;
    for (int j = 0; j < ntau; j++) {
        int sk = s.sk[j];
        if (sk == IGEA_STABILITY_ALLAN_THEOBR)
            d[j] = sqrt(kf * theo1_var(N, s.x, s.m[j], tau0));
        else if (!pass && kind != IGEA_STABILITY_ALLAN_THEOH)
            d[j] = gaps ? gap_one(kind, N, s.x, s.m[j], tau0, &g, &s.used[j])
                        : dev_one(kind, N, s.x, s.y, s.m[j], tau0, s.w, s.q);
        if (gaps && s.used[j] < 1)
            st = IGEA_ENONFINITE; /* every term of this tau holds a gap */
        if (sk == IGEA_STABILITY_ALLAN_THEOBR)
            s.al[j] = br_alpha;
        else
            s.al[j] = need_id ? noise_at(N, s.x, s.m[j], tau0, data_type) : noise;
        if (need_id && kind == IGEA_STABILITY_ALLAN_THEO1 && (N - 1) / s.m[j] < 4 && N >= 90) {
            /* Theo1 beyond a quarter of the record: fewer than 4 averages
             * for the lag-1 or B1 methods; the type of TheoBR's bias factor
             * [D] */
            if (!br) {
                long nrat;
                kf = theobr_factor(N, s.x, tau0, &nrat);
                br_alpha = theobr_alpha(kf, nrat);
                br = 1;
            }
            s.al[j] = br_alpha;
        }
        if (htot && s.m[j] > 1)
            d[j] /= sqrt(htot_bias(s.al[j]));
    }
    if (need_ci && !st)
        st = dev_intervals(s.sk, N, ntau, s.m, s.al, conf, gaps != 0, s.used, d, l, h, e);
    for (int j = 0; j < ntau && !st; j++)
        if (!isfinite(d[j]))
            st = IGEA_ENOCONV;
    if (!st)
        dev_output(&s, ntau, tau0, dev, lo, hi, edf, alpha, count, tau_used);
out:
    ws_free(&s);
    return st;
}

/* Next averaging factor of the spacing after m. */
static long next_factor(long m, int spacing, int even)
{
    if (spacing == IGEA_STABILITY_TAUS_ALL)
        return m + (even ? 2 : 1);
    if (spacing == IGEA_STABILITY_TAUS_OCTAVE)
        return 2 * m;
    long p = 1;
    while (p * 10 <= m)
        p *= 10;
    long lead = m / p; /* 1, 2, 4 */
    return lead == 1 ? 2 * p : lead == 2 ? 4 * p : 10 * p;
}

int igea_stability_taus(int n, double fs, int data_type, int kind, int spacing, int ntau_max,
                        double *tau, int *ntau)
{
    if (n < 2)
        return -1;
    if (!(isfinite(fs) && fs > 0.0))
        return -2;
    if (data_type != IGEA_STABILITY_DATA_FREQ && data_type != IGEA_STABILITY_DATA_PHASE)
        return -3;
    if (kind < IGEA_STABILITY_ALLAN_OVERLAPPING || kind > K_LAST)
        return -4;
    if (spacing < IGEA_STABILITY_TAUS_OCTAVE || spacing > IGEA_STABILITY_TAUS_ALL)
        return -5;
    if (ntau_max < 1)
        return -6;
    if (!tau)
        return -7;
    if (!ntau)
        return -8;
    int theo = theo_kind(kind), k = 0;
    long N = data_type == IGEA_STABILITY_DATA_PHASE ? n : (long)n + 1;
    if ((kind == IGEA_STABILITY_ALLAN_THEOBR || kind == IGEA_STABILITY_ALLAN_THEOH) && N < 90) {
        *ntau = 0;
        return 0;
    }
    if (kind == IGEA_STABILITY_ALLAN_THEOH) {
        /* the Allan deviation below the switch, THEOBR from it on */
        long ks = theoh_switch(N), m;
        for (m = 1; k < ntau_max && m < ks && N - 2 * m >= 1; m = next_factor(m, spacing, 0))
            tau[k++] = (double)m / fs;
        for (m = 2 * (long)ceil((double)ks / 1.5); k < ntau_max && m <= N - 1;
             m = next_factor(m, spacing, 1))
            tau[k++] = (double)m / fs * 0.75;
        *ntau = k;
        return 0;
    }
    for (long m = theo ? 2 : 1; k < ntau_max && m <= N; m = next_factor(m, spacing, theo)) {
        long M;
        if (kind <= IGEA_STABILITY_ALLAN_NONOVERLAPPING) {
            long nr = N - 1; /* rate samples */
            M = kind == IGEA_STABILITY_ALLAN_OVERLAPPING ? nr - 2 * m + 1
                : kind == IGEA_STABILITY_ALLAN_MODIFIED  ? nr - 3 * m + 2
                                                         : nr / m - 1;
            if (data_type == IGEA_STABILITY_DATA_PHASE)
                M = -1; /* the rate-data kinds take no phase */
        } else {
            M = theo && m % 2 ? 0 : dev_terms(kind, N, m);
        }
        if (M < 1)
            break;
        tau[k++] = (double)m / fs * (theo ? 0.75 : 1.0);
    }
    *ntau = k;
    return 0;
}
