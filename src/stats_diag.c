/* stats_diag.c - whiteness diagnostics of a residual series: Ljung-Box Q
 * and the Wald-Wolfowitz runs test, streamed (docs/eqerr.md, "Residual
 * diagnostics"). */
#include <float.h>

#include "igea/stats.h"
#include "internal.h"

/* Layout of state[IGEA_STATS_DIAG_STATE_LEN]. */
enum {
    ST_LAGS, ST_CENTER, ST_N, ST_SS, ST_ABOVE, ST_BELOW, ST_RUNS, ST_LAST, ST_MAGIC,
    ST_CROSS = 10 /* then the ring of the last lags deviations */
};
#define DIAG_MAGIC 7.0e7 /* marks an initialised state */
#define DIAG_CHUNK 512   /* igea_stats_diag_add's values per chunk */

int igea_stats_diag_init(int lags, double center, double *state)
{
    if (lags < 1 || lags > IGEA_STATS_DIAG_LAGS_MAX) return -1;
    if (!isfinite(center)) return -2;
    if (!state) return -3;
    for (int k = 0; k < IGEA_STATS_DIAG_STATE_LEN; k++)
        state[k] = 0.0;
    state[ST_LAGS] = lags;
    state[ST_CENTER] = center;
    state[ST_MAGIC] = DIAG_MAGIC;
    return 0;
}

/* 1 when state looks like one igea_stats_diag_init wrote. */
static int state_ok(const double *s)
{
    if (s[ST_MAGIC] != DIAG_MAGIC || !isfinite(s[ST_CENTER]))
        return 0;
    double L = s[ST_LAGS];
    if (!(L >= 1 && L <= IGEA_STATS_DIAG_LAGS_MAX && L == floor(L)))
        return 0;
    if (!(s[ST_N] >= 0 && s[ST_N] == floor(s[ST_N]) && s[ST_N] < 9e15))
        return 0;
    if (!(s[ST_LAST] == 0 || s[ST_LAST] == 1 || s[ST_LAST] == -1))
        return 0;
    return igea__finite_vec(IGEA_STATS_DIAG_STATE_LEN, s, 1);
}

/* Sixteen lags k .. k + 15 at once: cross[k + q - 1] += d[i] d[i - k - q]
 * for every element i of the chunk that reaches lag k + q (i >= k + q -
 * H), in element order, as element by element: the first elements of the
 * shorter lags one by one, then four vectors of four lags, lane l of
 * vector v holding lag k + 4 v + 3 - l, so that its d[i - k - q] are one
 * contiguous load (each lane is the same product and sum as the scalar
 * one: the same bits) [D]. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && \
    !defined(IGEA_NO_CLONES)
#define DG_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define DG_CLONES
#endif
#if defined(__GNUC__)
typedef double dg_v4 __attribute__((vector_size(32), aligned(8)));
#define DG_LD(p) (*(const dg_v4 *)(const void *)(p))
#define DG_VEC 1
#else
#define DG_VEC 0
#endif

#if DG_VEC
DG_CLONES static void lag16(const double *d, int H, int nc, int k, double *cross)
{
    int from = k + 15 - H > 0 ? k + 15 - H : 0;
    for (int q = 0; q < 15; q++)
        for (int i = k + q - H > 0 ? k + q - H : 0; i < from && i < nc; i++)
            cross[k + q - 1] += d[i] * d[i - k - q];
    dg_v4 s[4];
    for (int v = 0; v < 4; v++)
        for (int l = 0; l < 4; l++)
            s[v][l] = cross[k + 4 * v + 3 - l - 1];
    for (int i = from; i < nc; i++) {
        const double x = d[i];
        const dg_v4 b = {x, x, x, x};
        const double *p = d + i - k - 3;
        s[0] += b * DG_LD(p);
        s[1] += b * DG_LD(p - 4);
        s[2] += b * DG_LD(p - 8);
        s[3] += b * DG_LD(p - 12);
    }
    for (int v = 0; v < 4; v++)
        for (int l = 0; l < 4; l++)
            cross[k + 4 * v + 3 - l - 1] = s[v][l];
}
#endif

int igea_stats_diag_add(int n, const double *x, int incx, double *state)
{
    if (n < 0) return -1;
    if (!x && n > 0) return -2;
    if (incx < 1) return -3;
    if (!state) return -4;
    if (!state_ok(state)) return -4;
    for (int i = 0; i < n; i++)
        if (!isfinite(x[(size_t)i * incx]))
            return IGEA_ENONFINITE;
    double t[IGEA_STATS_DIAG_STATE_LEN];
    memcpy(t, state, sizeof t);
    const int L = (int)t[ST_LAGS];
    const double c = t[ST_CENTER];
    double *cross = t + ST_CROSS, *ring = cross + L;
    long long cnt = (long long)t[ST_N];
    int last = (int)t[ST_LAST];
    double ss = t[ST_SS];
    long long above = 0, below = 0, runs = 0; /* added to the state's counts at the end */
    /* The deviations in chunks, after the (up to L) deviations before
     * them in order in dev[]; each cross[k - 1] then gets d_i times the
     * deviation k before it for every element i of the chunk in element
     * order, as element by element, so the sums are the same; the lags
     * sixteen (lag16), then four at a time (independent sums). The deviation of element k sits
     * at ring[k % L] between calls. */
    double dev[DIAG_CHUNK + IGEA_STATS_DIAG_LAGS_MAX];
    for (int i0 = 0; i0 < n; i0 += DIAG_CHUNK) {
        int nc = n - i0 < DIAG_CHUNK ? n - i0 : DIAG_CHUNK;
        int H = cnt < L ? (int)cnt : L; /* deviations held before the chunk */
        for (int h = 0; h < H; h++)
            dev[h] = ring[(cnt - H + h) % L];
        double *d = dev + H;
        for (int i = 0; i < nc; i++) {
            double v = x[(size_t)(i0 + i) * incx] - c;
            d[i] = v;
            ss += v * v;
            /* without branches (the signs of residuals are unpredictable);
             * a value at the centre is dropped */
            int pos = v > 0, neg = v < 0, sg = pos - neg;
            above += pos;
            below += neg;
            runs += (sg != 0) & (sg != last);
            last = sg ? sg : last;
        }
        /* element i of the chunk reaches lag k when k <= H + i */
        int k = 1;
#if DG_VEC
        for (; k + 15 <= L; k += 16)
            lag16(d, H, nc, k, cross);
#endif
        for (; k + 3 <= L; k += 4) {
            int from = k + 3 - H > 0 ? k + 3 - H : 0;
            for (int q = 0; q < 3; q++) /* the first elements of the shorter lags */
                for (int i = k + q - H > 0 ? k + q - H : 0; i < from && i < nc; i++)
                    cross[k + q - 1] += d[i] * d[i - k - q];
            double s0 = cross[k - 1], s1 = cross[k], s2 = cross[k + 1], s3 = cross[k + 2];
            for (int i = from; i < nc; i++) {
                s0 += d[i] * d[i - k];
                s1 += d[i] * d[i - k - 1];
                s2 += d[i] * d[i - k - 2];
                s3 += d[i] * d[i - k - 3];
            }
            cross[k - 1] = s0, cross[k] = s1, cross[k + 1] = s2, cross[k + 2] = s3;
        }
        for (; k <= L; k++) {
            double s0 = cross[k - 1];
            for (int i = k - H > 0 ? k - H : 0; i < nc; i++)
                s0 += d[i] * d[i - k];
            cross[k - 1] = s0;
        }
        for (int i = nc > L ? nc - L : 0; i < nc; i++)
            ring[(cnt + i) % L] = d[i];
        cnt += nc;
    }
    t[ST_N] = (double)cnt;
    t[ST_SS] = ss;
    t[ST_ABOVE] += (double)above, t[ST_BELOW] += (double)below, t[ST_RUNS] += (double)runs;
    t[ST_LAST] = last;
    if (!igea__finite_vec(IGEA_STATS_DIAG_STATE_LEN, t, 1))
        return IGEA_EOVERFLOW;
    memcpy(state, t, sizeof t);
    return 0;
}

/* The runs test of a state: z and its two-sided p-value (normal
 * approximation to the Wald-Wolfowitz distribution). */
static void runs_z(double n1, double n2, double runs, double *z, double *p)
{
    double n = n1 + n2;
    *z = 0.0;
    *p = 1.0;
    if (n1 < 1 || n2 < 1)
        return; /* one sign only: no test, one run */
    double mu = 2.0 * n1 * n2 / n + 1.0;
    double var = 2.0 * n1 * n2 * (2.0 * n1 * n2 - n) / (n * n * (n - 1.0));
    if (!(var > 0))
        return;
    *z = (runs - mu) / sqrt(var);
    *p = erfc(fabs(*z) / sqrt(2.0));
}

int igea_stats_diag_result(const double *state, double *out)
{
    if (!state || !state_ok(state)) return -1;
    if (!out) return -2;
    const int L = (int)state[ST_LAGS];
    const double n = state[ST_N], ss = state[ST_SS];
    if (n < L + 2.0)
        return IGEA_EEMPTY;
    if (!(ss > 0))
        return IGEA_EDOMAIN; /* a constant series: no autocorrelation */
    double Q = 0.0;
    for (int k = 1; k <= L; k++) {
        double r = state[ST_CROSS + k - 1] / ss;
        Q += r * r / (n - k);
    }
    Q *= n * (n + 2.0);
    double p;
    int st = igea_stats_chi2_sf(Q, (double)L, &p);
    if (st != 0)
        return st < 0 && st > -1000 ? IGEA_EOVERFLOW : st;
    double z, pr;
    runs_z(state[ST_ABOVE], state[ST_BELOW], state[ST_RUNS], &z, &pr);
    if (!isfinite(Q) || !isfinite(z))
        return IGEA_EOVERFLOW;
    for (int k = 0; k < IGEA_STATS_DIAG_LEN; k++)
        out[k] = 0.0;
    out[IGEA_STATS_DIAG_N] = n;
    out[IGEA_STATS_DIAG_LB_Q] = Q;
    out[IGEA_STATS_DIAG_LB_LAGS] = L;
    out[IGEA_STATS_DIAG_LB_P] = p;
    out[IGEA_STATS_DIAG_RUNS] = state[ST_RUNS];
    out[IGEA_STATS_DIAG_N_ABOVE] = state[ST_ABOVE];
    out[IGEA_STATS_DIAG_N_BELOW] = state[ST_BELOW];
    out[IGEA_STATS_DIAG_RUNS_Z] = z;
    out[IGEA_STATS_DIAG_RUNS_P] = pr;
    out[IGEA_STATS_DIAG_CENTER] = state[ST_CENTER];
    return 0;
}

int igea_stats_whiteness(int n, const double *x, int incx, int lags, double *out)
{
    if (n < 1) return -1;
    if (!x) return -2;
    if (incx < 1) return -3;
    if (lags < 1 || lags > IGEA_STATS_DIAG_LAGS_MAX) return -4;
    if (!out) return -5;
    igea__ksum acc = {0, 0};
    for (int i = 0; i < n; i++) {
        double v = x[(size_t)i * incx];
        if (!isfinite(v))
            return IGEA_ENONFINITE;
        igea__ksum_add(&acc, v / n);
    }
    double mean = igea__ksum_get(&acc);
    if (!isfinite(mean))
        return IGEA_EOVERFLOW;
    double s[IGEA_STATS_DIAG_STATE_LEN];
    igea_stats_diag_init(lags, mean, s);
    int st = igea_stats_diag_add(n, x, incx, s);
    return st ? st : igea_stats_diag_result(s, out);
}
