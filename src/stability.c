/* stability.c - block-mean 3-sigma statistic, Allan deviations with EDF
 * confidence intervals, noise identification (METHODS 3.4). */
#include <float.h>

#include "igea/stability.h"
#include "igea/stats.h"
#include "internal.h"
#include "stability_internal.h"

static double mean_of(size_t n, const double *y)
{
    igea__ksum k = {0.0, 0.0};
    for (size_t i = 0; i < n; i++)
        igea__ksum_add(&k, y[i]);
    return igea__ksum_get(&k) / (double)n;
}


int igea_stability_block(int n, const double *y, double fs, double block,
                         double *out)
{
    if (n < 2)
        return -1;
    if (!y)
        return -2;
    if (!(isfinite(fs) && fs > 0.0))
        return -3;
    if (!(isfinite(block) && block > 0.0))
        return -4;
    if (!out)
        return -5;
    double v = block * fs;
    if (!(v >= 0.5 && v <= (double)n))
        return -4;
    long nb = lround(v);
    long B = n / nb;
    if (B < 2)
        return -4;
    if (!igea__finite_vec(n, y, 1))
        return IGEA_ENONFINITE;
    double *m = igea__dalloc((size_t)B);
    if (!m)
        return IGEA_ENOMEM;
    for (long b = 0; b < B; b++)
        m[b] = mean_of((size_t)nb, y + (size_t)b * (size_t)nb);
    igea__stability_block_stats(B, m, nb, out);
    free(m);
    return 0;
}

void igea__stability_block_stats(long B, const double *m, long nb, double *out)
{
    double mm = mean_of((size_t)B, m);
    igea__ksum ss = {0, 0}, sd = {0, 0};
    for (long b = 0; b < B; b++) {
        double d = m[b] - mm;
        igea__ksum_add(&ss, d * d);
        if (b + 1 < B) {
            double e = m[b + 1] - m[b];
            igea__ksum_add(&sd, e * e);
        }
    }
    double sig = sqrt(igea__ksum_get(&ss) / (double)(B - 1));
    out[IGEA_STABILITY_BLOCK_3SIGMA] = 3.0 * sig;
    out[IGEA_STABILITY_BLOCK_SIGMA] = sig;
    out[IGEA_STABILITY_BLOCK_NBLOCK] = (double)B;
    out[IGEA_STABILITY_BLOCK_NSAMP] = (double)nb;
    out[IGEA_STABILITY_BLOCK_MEAN] = mm;
    out[IGEA_STABILITY_BLOCK_ADEV] = sqrt(igea__ksum_get(&sd) / (2.0 * (double)(B - 1)));
}

/* Terms (count) of an estimator with averaging factor m; <= 0: none. */
static long term_count(long n, long m, int kind)
{
    switch (kind) {
    case IGEA_STABILITY_ALLAN_OVERLAPPING: return n - 2 * m + 1;
    case IGEA_STABILITY_ALLAN_MODIFIED: return n - 3 * m + 2;
    default: return n / m - 1;
    }
}

/* EDF of the overlapping Allan variance, NIST SP 1065 Table 5 (Howe, Allan
 * and Barnes), N phase points, averaging factor m, noise exponent alpha. */
static double edf_oadev(double N, double m, int alpha)
{
    switch (alpha) {
    case IGEA_STABILITY_NOISE_WPM:
        return (N + 1.0) * (N - 2.0 * m) / (2.0 * (N - m));
    case IGEA_STABILITY_NOISE_FPM: {
        double a = log((N - 1.0) / (2.0 * m)), b = log((2.0 * m + 1.0) * (N - 1.0) / 4.0);
        return a * b > 0.0 ? exp(sqrt(a * b)) : NAN;
    }
    case IGEA_STABILITY_NOISE_WFM:
        return (3.0 * (N - 1.0) / (2.0 * m) - 2.0 * (N - 2.0) / N) * 4.0 * m * m /
               (4.0 * m * m + 5.0);
    case IGEA_STABILITY_NOISE_FFM:
        if (m == 1.0)
            return 2.0 * (N - 2.0) * (N - 2.0) / (2.3 * N - 4.9);
        return 5.0 * N * N / (4.0 * m * (N + 3.0 * m));
    default: /* RWFM */
        return (N - 2.0) / (m * (N - 3.0) * (N - 3.0)) *
               ((N - 1.0) * (N - 1.0) - 3.0 * m * (N - 1.0) + 4.0 * m * m);
    }
}

/* EDF of the modified Allan variance: Greenhall and Riley, "Uncertainty of
 * stability variances based on finite differences" (PTTI 2003), eqs.
 * (7)-(10), case F = 1 (modified), stride S = m (overlapping), d = 2, with
 * their Table 1 for long records. sw is the generalised autocovariance of
 * the power-law phase noise, sx its filtered form, sz that of the second
 * difference. */
static double gh_sw(double t, int alpha)
{
    double a = fabs(t);
    switch (alpha) {
    case 2: return -a;
    case 1: return a > 0.0 ? t * t * log(a) : 0.0;
    case 0: return a * a * a;
    case -1: return a > 0.0 ? t * t * t * t * log(a) : 0.0;
    default: return a * a * a * a * a; /* -2 */
    }
}

static double gh_sx(double t, double F, int alpha)
{
    return F * F * (2.0 * gh_sw(t, alpha) - gh_sw(t - 1.0 / F, alpha) -
                    gh_sw(t + 1.0 / F, alpha));
}

static double gh_sz(double t, double F, int alpha)
{
    return 6.0 * gh_sx(t, F, alpha) - 4.0 * gh_sx(t - 1.0, F, alpha) -
           4.0 * gh_sx(t + 1.0, F, alpha) + gh_sx(t - 2.0, F, alpha) +
           gh_sx(t + 2.0, F, alpha);
}

static double gh_basic_sum(double J, double M, double S, double F, int alpha)
{
    double z0 = gh_sz(0.0, F, alpha), zJ = gh_sz(J / S, F, alpha);
    double s = z0 * z0 + (1.0 - J / M) * zJ * zJ;
    for (long j = 1; j < (long)J; j++) {
        double z = gh_sz((double)j / S, F, alpha);
        s += 2.0 * (1.0 - (double)j / M) * z * z;
    }
    return s;
}

static double edf_mdev(double N, double m, int alpha)
{
    /* Table 1, d = 2: (a0, a1) for alpha = 2, 1, 0, -1, -2 */
    static const double t1[5][2] = {{7.0 / 9.0, 0.5}, {0.997, 0.616}, {1.033, 0.607},
                                    {1.048, 0.534}, {1.302, 0.535}};
    const double Jmax = 100.0;
    double M = N - 3.0 * m + 1.0, J = IGEA_MIN(M, 3.0 * m), r = M / m;
    double z0 = gh_sz(0.0, 1.0, alpha);
    if (J <= Jmax)
        return z0 * z0 * M / gh_basic_sum(J, M, m, 1.0, alpha);
    if (r > 3.0) {
        const double *a = t1[2 - alpha];
        return r / (a[0] - a[1] / r);
    }
    return z0 * z0 * Jmax / gh_basic_sum(Jmax, Jmax, Jmax / r, 1.0, alpha);
}

/* The deviations d and term counts cw of the kind at every tau in one pass
 * over y (stability_pass.c); with al (not NULL) the lag-1 noise type at
 * every tau (IGEA_STABILITY_NOISE_AUTO: fewer than 32 means). Returns 0 or
 * IGEA_ENOMEM. */
static int allan_devs(int n, const double *y, double fs, int ntau, const double *tau,
                      int kind, double *d, int *cw, int *al)
{
    igea__aptau_spec *sp = calloc((size_t)ntau, sizeof *sp);
    igea__apass *p = NULL;
    if (!sp)
        return IGEA_ENOMEM;
    for (int j = 0; j < ntau; j++)
        igea__stability_pass_spec(kind, lround(tau[j] * fs), al != NULL, &sp[j]);
    int st = igea__apass_whole(0, ntau, sp, n, y, &p);
    if (!st && igea__apass_nonfinite(p))
        st = IGEA_ENONFINITE;
    for (int j = 0; j < ntau && !st; j++) {
        double ss;
        long cnt;
        igea__apass_get(p, j, &ss, &cnt);
        d[j] = igea__stability_pass_dev(kind, 0, fs, sp[j].m, ss, cnt);
        cw[j] = (int)cnt;
        if (al)
            al[j] = igea__apass_alpha(p, j);
    }
    igea__apass_free(p);
    free(sp);
    return st;
}

/* Equivalent degrees of freedom e and the chi-square interval [l, h] of
 * every deviation d at confidence conf (noise type given or identified per
 * tau). Returns 0 or IGEA_ENOCONV. */
int igea__stability_allan_intervals(int n, double fs, int ntau, const double *tau, int kind,
                                    int noise, double conf, const int *al, const double *d,
                                    double *l, double *h, double *e)
{
    int last_alpha = IGEA_STABILITY_NOISE_WFM;
    for (int j = 0; j < ntau; j++) {
        int alpha = noise;
        if (noise == IGEA_STABILITY_NOISE_AUTO) {
            alpha = al[j];
            if (alpha == IGEA_STABILITY_NOISE_AUTO)
                alpha = last_alpha; /* too few means: keep the last type */
            last_alpha = alpha;
        }
        double m = (double)lround(tau[j] * fs), N = (double)n + 1.0, ev;
        if (kind == IGEA_STABILITY_ALLAN_NONOVERLAPPING) /* Greenhall's, as kind ADEV */
            ev = igea__stability_edf_greenhall(alpha, 2, m, N, 0, 0);
        else /* the modified variance equals the overlapping one at m = 1 */
            ev = kind == IGEA_STABILITY_ALLAN_MODIFIED && m > 1.0 ? edf_mdev(N, m, alpha)
                                                                : edf_oadev(N, m, alpha);
        if (igea__edf_interval(d[j], ev, conf, &l[j], &h[j], &e[j]))
            return IGEA_ENOCONV;
    }
    return 0;
}

int igea__edf_interval(double d, double edf, double conf, double *lo, double *hi, double *e)
{
    double ev = edf >= 1.0 ? edf : 1.0;
    if (ev > IGEA_STATS_DOF_MAX)
        ev = IGEA_STATS_DOF_MAX;
    double chi_hi, chi_lo;
    int s1 = igea_stats_chi2_quantile(0.5 * (1.0 + conf), ev, &chi_hi);
    int s2 = igea_stats_chi2_quantile(0.5 * (1.0 - conf), ev, &chi_lo);
    if (s1 || s2 || !(chi_lo > 0.0))
        return IGEA_ENOCONV;
    *e = ev;
    *lo = d * sqrt(ev / chi_hi);
    *hi = d * sqrt(ev / chi_lo);
    return 0;
}

int igea_stability_allan(int n, const double *y, double fs, int ntau,
                         const double *tau, int kind, int noise, double conf,
                         double *dev, double *lo, double *hi, double *edf,
                         int *count)
{
    if (n < 2)
        return -1;
    if (!y)
        return -2;
    if (!(isfinite(fs) && fs > 0.0))
        return -3;
    if (ntau < 1)
        return -4;
    if (!tau)
        return -5;
    if (kind < IGEA_STABILITY_ALLAN_OVERLAPPING || kind > IGEA_STABILITY_ALLAN_NONOVERLAPPING)
        return -6;
    if (!(noise == IGEA_STABILITY_NOISE_AUTO ||
          (noise >= IGEA_STABILITY_NOISE_RWFM && noise <= IGEA_STABILITY_NOISE_WPM)))
        return -7;
    if (!(conf > 0.0 && conf < 1.0))
        return -8;
    if (!dev)
        return -9;
    for (int j = 0; j < ntau; j++) {
        double v = tau[j] * fs;
        if (!(isfinite(tau[j]) && tau[j] > 0.0 && v >= 0.5 && v <= (double)n))
            return -5;
        if (term_count(n, lround(v), kind) < 1)
            return -5;
    }
    double *w = igea__dalloc(4 * (size_t)ntau);
    int *cw = igea__ialloc(2 * (size_t)ntau), *al = cw + ntau;
    if (!w || !cw) {
        free(w);
        free(cw);
        return IGEA_ENOMEM;
    }
    double *d = w, *l = w + ntau, *h = l + ntau, *e = h + ntau;
    int status = allan_devs(n, y, fs, ntau, tau, kind, d, cw,
                            noise == IGEA_STABILITY_NOISE_AUTO ? al : NULL);
    if (!status)
        status = igea__stability_allan_intervals(n, fs, ntau, tau, kind, noise, conf, al, d, l,
                                                 h, e);
    if (status == 0) {
        size_t sz = (size_t)ntau * sizeof(double);
        memcpy(dev, d, sz);
        if (lo)
            memcpy(lo, l, sz);
        if (hi)
            memcpy(hi, h, sz);
        if (edf)
            memcpy(edf, e, sz);
        if (count)
            memcpy(count, cw, (size_t)ntau * sizeof(int));
    }
    free(w);
    free(cw);
    return status;
}

int igea_stability_octave_taus(int n, double fs, int kind, int ntau_max,
                               double *tau, int *ntau)
{
    if (n < 2)
        return -1;
    if (!(isfinite(fs) && fs > 0.0))
        return -2;
    if (kind < IGEA_STABILITY_ALLAN_OVERLAPPING || kind > IGEA_STABILITY_ALLAN_NONOVERLAPPING)
        return -3;
    if (ntau_max < 1)
        return -4;
    if (!tau)
        return -5;
    if (!ntau)
        return -6;
    int k = 0;
    for (long m = 1; k < ntau_max && m <= n && term_count(n, m, kind) >= 1; m *= 2)
        tau[k++] = (double)m / fs;
    *ntau = k;
    return 0;
}

int igea_stability_noise_id(int ntau, const double *tau, const double *adev,
                            double *out)
{
    if (ntau < 2)
        return -1;
    if (!tau)
        return -2;
    if (!adev)
        return -3;
    if (!out)
        return -4;
    if (!igea__finite_vec(ntau, tau, 1) || !igea__finite_vec(ntau, adev, 1))
        return IGEA_ENONFINITE;
    for (int j = 0; j < ntau; j++) {
        if (!(tau[j] > 0.0) || (j > 0 && !(tau[j] > tau[j - 1])))
            return -2;
        if (!(adev[j] > 0.0))
            return -3;
    }
    static const double target[3] = {-1.0, -0.5, 0.5};
    double res[IGEA_STABILITY_NOISEID_LEN];
    for (int t = 0; t < 3; t++) {
        /* Q and N: the shortest-tau pair within 0.1 of the slope (the most
         * precise point of that region); otherwise, and for K, the pair
         * nearest to the slope within 0.15. */
        int best = -1;
        double bd = 0.15;
        for (int j = 0; j + 1 < ntau && t < 2; j++) {
            double s = log(adev[j + 1] / adev[j]) / log(tau[j + 1] / tau[j]);
            if (fabs(s - target[t]) <= 0.1) {
                best = j;
                break;
            }
        }
        for (int j = 0; j + 1 < ntau && best < 0; j++) {
            double s = log(adev[j + 1] / adev[j]) / log(tau[j + 1] / tau[j]);
            if (fabs(s - target[t]) <= bd) {
                bd = fabs(s - target[t]);
                best = j;
            }
        }
        double val = NAN, at = NAN;
        if (best >= 0) {
            at = sqrt(tau[best] * tau[best + 1]);
            double sg = sqrt(adev[best] * adev[best + 1]);
            if (t == 0)
                val = sg * at / sqrt(3.0);
            else if (t == 1)
                val = sg * sqrt(at);
            else
                val = sg * sqrt(3.0 / at);
        }
        int slot = t == 0 ? IGEA_STABILITY_NOISEID_Q : t == 1 ? IGEA_STABILITY_NOISEID_N : IGEA_STABILITY_NOISEID_K;
        res[slot] = val;
        res[slot + 1] = at;
    }
    int jmin = 0;
    for (int j = 1; j < ntau; j++)
        if (adev[j] < adev[jmin])
            jmin = j;
    if (jmin > 0 && jmin < ntau - 1) {
        res[IGEA_STABILITY_NOISEID_B] = adev[jmin] / 0.66428090415820634 /* sqrt(2 ln2 / pi) */;
        res[IGEA_STABILITY_NOISEID_B_TAU] = tau[jmin];
    } else {
        res[IGEA_STABILITY_NOISEID_B] = NAN;
        res[IGEA_STABILITY_NOISEID_B_TAU] = NAN;
    }
    memcpy(out, res, sizeof res);
    return 0;
}

int igea_stability_taus_used(double fs, int ntau, const double *tau, double *used)
{
    if (!(isfinite(fs) && fs > 0))
        return -1;
    if (ntau < 1)
        return -2;
    if (!tau)
        return -3;
    if (!used)
        return -4;
    for (int j = 0; j < ntau; j++) {
        double v = tau[j] * fs;
        if (!(v >= 0.5 && v < 2147483648.0))
            return -3;
    }
    for (int j = 0; j < ntau; j++)
        used[j] = (double)lround(tau[j] * fs) / fs;
    return 0;
}
