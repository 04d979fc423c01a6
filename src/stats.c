/* stats.c - distributions and the equivalent-error accuracy tests. */
#include <float.h>
#include <pthread.h>
#include <string.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_sf_gamma.h>

#include "igea/stats.h"
#include "internal.h"

static int dof_ok(double dof) { return dof > 0.0 && dof <= IGEA_STATS_CHI2_DOF_MAX; }

int igea_stats_normal_cdf(double x, double *p)
{
    if (isnan(x))
        return -1;
    if (!p)
        return -2;
    *p = isinf(x) ? (x > 0 ? 1.0 : 0.0) : gsl_cdf_ugaussian_P(x);
    return 0;
}

int igea_stats_normal_sf(double x, double *q)
{
    if (isnan(x))
        return -1;
    if (!q)
        return -2;
    if (isinf(x))
        *q = x > 0 ? 0.0 : 1.0;
    else
        *q = (double)(0.5L * erfcl((long double)x * 0.707106781186547524400844362104849039L));
    return 0;
}

int igea_stats_normal_quantile(double p, double *z)
{
    if (!(p > 0.0 && p < 1.0))
        return -1;
    if (!z)
        return -2;
    *z = gsl_cdf_ugaussian_Pinv(p);
    return 0;
}

/* The regularised incomplete gamma functions P(a, x) and Q(a, x) in long
 * double (docs/regress.md, "Distributions", "Chi-square distribution"). */

/* D(d) = d - log(1 + d) >= 0, without cancellation for small |d|. */
static long double igam_log1pmx(long double d)
{
    if (fabsl(d) >= 0.25L)
        return d - log1pl(d);
    long double s = 0.0L, p = d * d;
    for (int k = 2; k < 80; k++) {
        long double t = p / k;
        s += (k & 1) ? -t : t;
        if (fabsl(t) <= 1e-21L * s)
            break;
        p *= d;
    }
    return s;
}

/* Stirling remainder lgamma(a) - ((a - 1/2) log a - a + log(2 pi)/2), a >= 20. */
static long double igam_stirling(long double a)
{
    static const long double c[] = {1.0L / 12, -1.0L / 360, 1.0L / 1260, -1.0L / 1680,
                                    1.0L / 1188, -691.0L / 360360, 1.0L / 156,
                                    -3617.0L / 122400};
    long double r = 1.0L / (a * a), s = 0.0L, p = 1.0L / a;
    for (int k = 0; k < 8; k++, p *= r)
        s += c[k] * p;
    return s;
}

/* log Gamma(a) for a > 0, reentrant (lgammal writes the global signgam: a
 * data race between the threads of a Monte Carlo): log tgammal(a) below 20
 * (as accurate as lgammal there; Gamma(a) < 19! and the smallest dof / 2,
 * 2.5e-324, gives 4e323: no overflow in long double), Stirling's series
 * from 20. */
static long double lgamma_pos(long double a)
{
    if (a < 20.0L)
        return logl(tgammal(a));
    return (a - 0.5L) * logl(a) - a + 0.918938533204672741780329736406L /* log(2 pi)/2 */
           + igam_stirling(a);
}

/* x^a e^-x / Gamma(a), x > 0. For large a from the deviation d = (x - a)/a:
 * a log x - x - lgamma(a) = -a D(d) + log(a / 2 pi) / 2 - stirling(a). */
static long double igam_prefix(long double a, long double x)
{
    if (a < 20.0L)
        return expl(a * logl(x) - x - lgamma_pos(a));
    long double d = (x - a) / a;
    /* far from x = a, log(x / a) directly (1 + d has lost digits) */
    long double D = fabsl(d) < 0.5L ? igam_log1pmx(d) : d - logl(x / a);
    return expl(-a * D - igam_stirling(a)) * sqrtl(a / (2.0L * 3.14159265358979323846264338327950288L));
}

/* Series P(a, x) = x^a e^-x / Gamma(a + 1) sum_n x^n / ((a + 1)...(a + n)),
 * for x < a + 1. */
static long double igam_series(long double a, long double x)
{
    long double t = 1.0L, s = 1.0L, pre = igam_prefix(a, x);
    if (pre == 0.0L)
        return 0.0L;
    for (long n = 1; n < 10000000L; n++) {
        t *= x / (a + n);
        s += t;
        if (t <= 0.5L * LDBL_EPSILON * s)
            return pre / a * s;
    }
    return NAN;
}

/* Continued fraction (modified Lentz) Q(a, x) for x >= a + 1. */
static long double igam_cfrac(long double a, long double x)
{
    const long double tiny = 1e-4000L;
    long double b = x + 1.0L - a, c = 1.0L / tiny, d = 1.0L / b, h = d;
    long double pre = igam_prefix(a, x);
    if (pre == 0.0L)
        return 0.0L;
    for (long i = 1; i < 10000000L; i++) {
        long double an = -i * (i - a);
        b += 2.0L;
        d = an * d + b;
        if (fabsl(d) < tiny) d = tiny;
        c = b + an / c;
        if (fabsl(c) < tiny) c = tiny;
        d = 1.0L / d;
        long double del = d * c;
        h *= del;
        if (fabsl(del - 1.0L) <= 2.0L * LDBL_EPSILON)
            return pre * h;
    }
    return NAN;
}

/* P (upper = 0) or Q (upper = 1) for a > 0, x >= 0 (+Inf allowed). The side that
 * the series or continued fraction gives is the smaller one, or one of
 * moderate size, so that 1 - it in extended precision keeps the precision
 * of a double: for x < a + 1, Q >= a E1(1) ~ 0.22 a, so 1 - P loses
 * log10(1 / Q) of the 19 digits (below 1e-15 relative for a >= 5e-4). */
static double igam(double ad, double xd, int upper)
{
    long double a = ad, x = xd, v;
    if (!(xd > 0.0))
        return upper ? 1.0 : 0.0;
    if (isinf(xd))
        return upper ? 0.0 : 1.0;
    if (x >= a + 1.0L) {
        v = igam_cfrac(a, x);
        return (double)(upper ? v : 1.0L - v);
    }
    v = igam_series(a, x);
    return (double)(upper ? 1.0L - v : v);
}

/* Regularised incomplete beta I_x(a, b) for a, b > 0, x in [0, 1], with
 * y = 1 - x given separately (accurate when x is close to 1): the
 * continued fraction (modified Lentz) on the side x < (a + 1)/(a + b + 2),
 * the symmetry I_x(a, b) = 1 - I_y(b, a) on the other. Extended precision;
 * the prefactor's lgamma differences limit it to about 1e-13 relative at
 * a or b near 1e6. NaN when the fraction does not converge. */
static long double ibeta_cf(long double a, long double b, long double x, long double y)
{
    const long double tiny = 1e-4000L;
    long double lf = a * logl(x) + b * logl(y) - (lgamma_pos(a) + lgamma_pos(b) - lgamma_pos(a + b));
    long double c = 1.0L, d = 1.0L - (a + b) * x / (a + 1.0L), h;
    if (fabsl(d) < tiny) d = tiny;
    d = 1.0L / d;
    h = d;
    for (long k = 1; k < 10000000L; k++) {
        long double m2 = 2.0L * k;
        long double aa = k * (b - k) * x / ((a + m2 - 1.0L) * (a + m2));
        d = 1.0L + aa * d;
        if (fabsl(d) < tiny) d = tiny;
        c = 1.0L + aa / c;
        if (fabsl(c) < tiny) c = tiny;
        d = 1.0L / d;
        h *= d * c;
        aa = -(a + k) * (a + b + k) * x / ((a + m2) * (a + m2 + 1.0L));
        d = 1.0L + aa * d;
        if (fabsl(d) < tiny) d = tiny;
        c = 1.0L + aa / c;
        if (fabsl(c) < tiny) c = tiny;
        d = 1.0L / d;
        long double del = d * c;
        h *= del;
        if (fabsl(del - 1.0L) <= 2.0L * LDBL_EPSILON)
            return expl(lf) * h / a;
    }
    return NAN;
}

static long double ibeta(long double a, long double b, long double x, long double y)
{
    if (x <= 0.0L)
        return 0.0L;
    if (y <= 0.0L)
        return 1.0L;
    if (x < (a + 1.0L) / (a + b + 2.0L))
        return ibeta_cf(a, b, x, y);
    return 1.0L - ibeta_cf(b, a, y, x);
}

/* Upper tail of Student's t with dof degrees of freedom, t finite. */
static double t_tail(double t, double dof)
{
    long double tl = fabs(t), x, y;
    if (tl > 1e150L) {
        x = ((long double)dof / tl) / tl;
        y = 1.0L - x;
    } else {
        long double t2 = tl * tl;
        x = dof / (dof + t2);
        y = t2 / (dof + t2);
    }
    long double h = 0.5L * ibeta(0.5L * dof, 0.5L, x, y);
    return (double)(t >= 0.0 ? h : 1.0L - h);
}

int igea_stats_t_sf(double t, double dof, double *q)
{
    if (isnan(t))
        return -1;
    if (!(dof > 0.0 && dof <= IGEA_STATS_CHI2_DOF_MAX))
        return -2;
    if (!q)
        return -3;
    double v = isinf(t) ? (t > 0 ? 0.0 : 1.0) : t_tail(t, dof);
    if (isnan(v))
        return IGEA_ENOCONV;
    *q = v;
    return 0;
}

int igea_stats_t_quantile(double p, double dof, double *t)
{
    if (!(p > 0.0 && p < 1.0))
        return -1;
    if (!(dof > 0.0 && dof <= IGEA_STATS_CHI2_DOF_MAX))
        return -2;
    if (!t)
        return -3;
    /* solve Q(u) = a, a = min(p, 1 - p) <= 1/2, u >= 0, by bisection */
    double a = p < 0.5 ? p : 1.0 - p, lo = 0.0, hi = 1.0;
    while (t_tail(hi, dof) > a) {
        lo = hi;
        hi *= 2.0;
        if (hi > 1e300)
            return IGEA_ENOCONV;
    }
    for (int it = 0; it < 2200 && hi - lo > 2.0 * DBL_EPSILON * hi; it++) {
        double mid = 0.5 * (lo + hi), v = t_tail(mid, dof);
        if (isnan(v))
            return IGEA_ENOCONV;
        if (v > a) lo = mid; else hi = mid;
    }
    double u = 0.5 * (lo + hi);
    *t = p < 0.5 ? -u : u;
    return 0;
}

int igea_stats_f_sf(double f, double d1, double d2, double *q)
{
    if (isnan(f) || f < 0.0)
        return -1;
    if (!(d1 > 0.0 && d1 <= IGEA_STATS_CHI2_DOF_MAX))
        return -2;
    if (!(d2 > 0.0 && d2 <= IGEA_STATS_CHI2_DOF_MAX))
        return -3;
    if (!q)
        return -4;
    double v;
    if (isinf(f))
        v = 0.0;
    else {
        long double fl = f, x, y;
        if (fl * d1 > 1e300L * d2) {
            x = (long double)d2 / (d1 * fl);
            y = 1.0L - x;
        } else {
            x = d2 / (d2 + d1 * fl);
            y = d1 * fl / (d2 + d1 * fl);
        }
        v = (double)ibeta(0.5L * d2, 0.5L * d1, x, y);
    }
    if (isnan(v))
        return IGEA_ENOCONV;
    *q = v;
    return 0;
}

/* P or Q of the chi-square distribution; x > 0 finite, dof validated. */
static double chi2_tail(double x, double dof, int upper)
{
    return igam(0.5 * dof, 0.5 * x, upper);
}

static int chi2_dist(double x, double dof, double *out, int upper)
{
    if (isnan(x) || x < 0.0)
        return -1;
    if (!dof_ok(dof))
        return -2;
    if (!out)
        return -3;
    double v;
    if (isinf(x))
        v = upper ? 0.0 : 1.0;
    else if (x == 0.0)
        v = upper ? 1.0 : 0.0;
    else
        v = chi2_tail(x, dof, upper);
    if (!isfinite(v))
        return IGEA_ENOCONV;
    *out = v;
    return 0;
}

int igea_stats_chi2_cdf(double x, double dof, double *p) { return chi2_dist(x, dof, p, 0); }
int igea_stats_chi2_sf(double x, double dof, double *q) { return chi2_dist(x, dof, q, 1); }

/* log of the chi-square density at x > 0. */
static double chi2_logpdf(double x, double dof)
{
    double a = 0.5 * dof;
    return (a - 1.0) * log(0.5 * x) - 0.5 * x - gsl_sf_lngamma(a) - 0.69314718055994530942;
}

/* Inversion state: G(t) = s (log tail(e^t) - log target), increasing. */
typedef struct {
    double dof, lt, s;
    int upper;
} chi2_inv;

static double chi2_g(const chi2_inv *q, double t)
{
    double v = chi2_tail(exp(t), q->dof, q->upper);
    return v > 0.0 ? q->s * (log(v) - q->lt) : (q->upper ? HUGE_VAL : -HUGE_VAL);
}

/* Wilson-Hilferty start t = log x0; small-x series start where it fails. */
static double chi2_start(double target, double dof, int upper, double lt)
{
    double z = gsl_cdf_ugaussian_Pinv(upper ? 1.0 - target : target);
    double h = 2.0 / (9.0 * dof);
    double wh = 1.0 - h + z * sqrt(h);
    double x0;
    if (wh > 0.05)
        x0 = dof * wh * wh * wh;
    else {
        double a = 0.5 * dof;
        double lp = upper ? log1p(-target) : lt;
        x0 = 2.0 * exp((lp + gsl_sf_lngamma(a + 1.0)) / a);
    }
    if (!(x0 > 0.0) || !isfinite(x0))
        x0 = dof;
    return log(x0);
}

/* A bracket [lo, hi] around t with G(lo) <= 0 <= G(hi), by doubling
 * steps; IGEA_ENOCONV when none is found. */
static int chi2_bracket(const chi2_inv *q, double t, double *lo_out, double *hi_out,
                        double *glo_out, double *ghi_out)
{
    double lo = t, hi = t, glo, ghi, g = chi2_g(q, t);
    if (isnan(g))
        return IGEA_ENOCONV;
    glo = ghi = g;
    double step = 0.5;
    for (int k = 0; glo > 0.0; k++) {
        if (k > 200 || lo < -1500.0)
            return IGEA_ENOCONV;
        hi = lo;
        ghi = glo;
        lo -= step;
        step *= 2.0;
        glo = chi2_g(q, lo);
    }
    step = 0.5;
    for (int k = 0; ghi < 0.0; k++) {
        if (k > 200 || hi > 800.0)
            return IGEA_ENOCONV;
        lo = hi;
        glo = ghi;
        hi += step;
        step *= 2.0;
        ghi = chi2_g(q, hi);
    }
    *lo_out = lo;
    *hi_out = hi;
    *glo_out = glo;
    *ghi_out = ghi;
    return 0;
}

/*
 * Solve tail(x) = target for x > 0, where tail is P (upper = 0) or Q
 * (upper = 1) and 0 < target <= 0.5, so that the tail on the side being
 * matched is never close to 1 and its logarithm keeps full precision.
 * Newton on t = log x for F(t) = log tail(e^t) - log target, safeguarded
 * by a bracket that bisection falls back on.
 */
static int chi2_invert(double target, double dof, int upper, double *xout)
{
    /* F is increasing in t for P, decreasing for Q; use G = s*F, increasing. */
    const chi2_inv q = {dof, log(target), upper ? -1.0 : 1.0, upper};
    double t = chi2_start(target, dof, upper, q.lt);
    double lo, hi, glo, ghi, g;
    int st = chi2_bracket(&q, t, &lo, &hi, &glo, &ghi);
    if (st)
        return st;
    /* Now glo <= 0 <= ghi. */
    t = (glo == -HUGE_VAL || ghi == HUGE_VAL) ? 0.5 * (lo + hi) : t;
    if (t < lo || t > hi)
        t = 0.5 * (lo + hi);
    for (int it = 0; it < 300; it++) {
        double x = exp(t);
        double v = chi2_tail(x, dof, upper);
        if (!(v > 0.0)) {
            /* underflow of the tail: move towards the bracket's middle */
            if (upper) hi = t; else lo = t;
            t = 0.5 * (lo + hi);
            continue;
        }
        g = q.s * (log(v) - q.lt);
        if (g == 0.0)
            break;
        if (g < 0.0) lo = t; else hi = t;
        /* dG/dt = s * d log tail / dt = x * pdf(x) / tail (both tails). */
        double dg = exp(log(x) + chi2_logpdf(x, dof) - log(v));
        double tn = t - g / dg;
        if (!(tn > lo && tn < hi) || !isfinite(tn))
            tn = 0.5 * (lo + hi);
        double dt = fabs(tn - t);
        t = tn;
        if (dt <= 4.0 * DBL_EPSILON * IGEA_MAX(1.0, fabs(t)) || hi - lo <= 4.0 * DBL_EPSILON * IGEA_MAX(1.0, fabs(t)))
            break;
    }
    double x = exp(t);
    if (!isfinite(x))
        return IGEA_ENOCONV;
    /* A lower quantile below the smallest normal double (tiny dof and p):
     * the nearest representable answer is 0. */
    *xout = x < DBL_MIN ? 0.0 : x;
    return 0;
}

/* The x whose tail on side upper (0: P, 1: Q) is p: the smaller of the
 * two tails is inverted, where its logarithm keeps full precision. */
static int chi2_side_quantile(double p, double dof, int upper, double *x)
{
    if (!(p > 0.0 && p < 1.0))
        return -1;
    if (!dof_ok(dof))
        return -2;
    if (!x)
        return -3;
    double r;
    int st = p <= 0.5 ? chi2_invert(p, dof, upper, &r) : chi2_invert(1.0 - p, dof, !upper, &r);
    if (st == 0)
        *x = r;
    return st;
}

int igea_stats_chi2_quantile(double p, double dof, double *x)
{
    return chi2_side_quantile(p, dof, 0, x);
}

int igea_stats_chi2_upper(double alpha, double dof, double *x)
{
    return chi2_side_quantile(alpha, dof, 1, x);
}

/* Sum of non-negative finite terms, saturated: *sat = 1 and DBL_MAX when
 * the sum (or a term) exceeds the double range. */
typedef struct {
    igea__ksum k;
    int sat;
} sat_sum;

static void sat_add(sat_sum *t, double x)
{
    if (t->sat)
        return;
    if (!isfinite(x) || !isfinite(t->k.s + x)) {
        t->sat = 1;
        return;
    }
    igea__ksum_add(&t->k, x);
}

static double sat_get(const sat_sum *t)
{
    double v = t->sat ? DBL_MAX : igea__ksum_get(&t->k);
    return isfinite(v) ? v : DBL_MAX;
}

int igea_stats_accuracy_test(int n, const double *equiv_err,
                             const double *lambda, double alpha,
                             double lambda_test, double z_crit, double *z,
                             int *reject, double *info)
{
    return igea__stats_accuracy_cached(n, equiv_err, lambda, alpha, lambda_test, z_crit,
                                       NULL, NULL, 1, z, reject, info);
}

int igea__stats_accuracy_cached(int n, const double *equiv_err, const double *lambda,
                                double alpha, double lambda_test, double z_crit,
                                double *cc, const double *den, int want_p, double *z,
                                int *reject, double *info)
{
    if (n < 1) return -1;
    if (!equiv_err) return -2;
    if (!lambda) return -3;
    if (!(alpha > 0.0 && alpha < 1.0)) return -4;
    if (!(lambda_test > 0.0) || !isfinite(lambda_test)) return -5;
    if (!(z_crit >= 0.0) || !isfinite(z_crit)) return -6;
    if (!z) return -7;
    if (!reject) return -8;
    if (!info) return -9;
    if (!igea__finite_vec(n, equiv_err, 1) || !igea__finite_vec(n, lambda, 1))
        return IGEA_ENONFINITE;

    int ntest = 0;
    for (int i = 0; i < n; i++)
        if (lambda[i] >= lambda_test)
            ntest++;
    if (ntest == 0)
        return IGEA_ENOTESTABLE;
    if (ntest > IGEA_STATS_DOF_MAX)
        return -1;
    double zc = z_crit, crit, pval;
    if (zc == 0.0)
        zc = gsl_cdf_ugaussian_Qinv(0.5 * alpha);
    double *e = cc && ntest <= n ? cc + 2 * (size_t)(ntest - 1) : NULL;
    int st = 0;
    if (e && e[0] == 1.0)
        crit = e[1];
    else
        st = igea_stats_chi2_upper(alpha, (double)ntest, &crit);
    if (st != 0)
        return st;
    if (e)
        e[0] = 1.0, e[1] = crit;
    /* First pass: the statistic only; z_i = e_i / sqrt(1 + 1/lambda_i) is
     * finite (|z_i| <= |e_i|), z_i^2 and T may exceed the double range. */
    sat_sum t = {{0, 0}, 0};
    for (int i = 0; i < n; i++) {
        if (lambda[i] >= lambda_test) {
            double zi = equiv_err[i] / (den ? den[i] : sqrt(1.0 + 1.0 / lambda[i]));
            sat_add(&t, zi * zi);
        }
    }
    double T = sat_get(&t);
    if (t.sat || !want_p)
        pval = 0.0; /* Q(T) < Q(DBL_MAX) = 0 to double precision; or not asked */
    else {
        st = igea_stats_chi2_sf(T, (double)ntest, &pval);
        if (st != 0)
            return st < 0 && st > -1000 ? IGEA_ENOCONV : st;
    }
    /* Nothing can fail from here: the outputs are written. */
    int nrej = 0;
    for (int i = 0; i < n; i++) {
        if (lambda[i] >= lambda_test) {
            double zi = equiv_err[i] / (den ? den[i] : sqrt(1.0 + 1.0 / lambda[i]));
            z[i] = zi;
            reject[i] = fabs(zi) > zc;
            nrej += reject[i];
        } else {
            z[i] = 0.0;
            reject[i] = -1;
        }
    }
    for (int k = 0; k < IGEA_STATS_INFO_LEN; k++)
        if (k < IGEA_STATS_INFO_RANK)
            info[k] = 0.0;
    info[IGEA_STATS_INFO_N_TEST] = ntest;
    info[IGEA_STATS_INFO_CHI2] = T;
    info[IGEA_STATS_INFO_DOF] = ntest;
    info[IGEA_STATS_INFO_CHI2_CRIT] = crit;
    info[IGEA_STATS_INFO_Z_CRIT] = zc;
    info[IGEA_STATS_INFO_P_VALUE] = pval;
    info[IGEA_STATS_INFO_N_REJECT] = nrej;
    info[IGEA_STATS_INFO_PASSED] = (nrej == 0 && T < crit) ? 1.0 : 0.0;
    return 0;
}

int igea_stats_pool(int nflights, const double *chi2, const int *dof,
                    const int *n_reject, const int *unit_id, double alpha,
                    double *info)
{
    if (nflights < 1) return -1;
    if (!chi2) return -2;
    if (!dof) return -3;
    if (!n_reject) return -4;
    if (!(alpha > 0.0 && alpha < 1.0)) return -6;
    if (!info) return -7;
    if (!igea__finite_vec(nflights, chi2, 1))
        return IGEA_ENONFINITE;
    double dtot = 0.0;
    long nrej = 0;
    sat_sum t = {{0, 0}, 0};
    for (int f = 0; f < nflights; f++) {
        if (chi2[f] < 0.0) return -2;
        if (dof[f] < 1) return -3;
        if (n_reject[f] < 0) return -4;
        dtot += dof[f];
        nrej += n_reject[f];
        sat_add(&t, chi2[f]);
    }
    if (dtot > IGEA_STATS_DOF_MAX)
        return -3;
    if (unit_id)
        for (int f = 0; f < nflights; f++)
            for (int g = f + 1; g < nflights; g++)
                if (unit_id[f] == unit_id[g])
                    return IGEA_EDEPENDENT;
    double T = sat_get(&t), crit, pval = 0.0;
    int st = igea_stats_chi2_upper(alpha, dtot, &crit);
    if (st == 0 && !t.sat)
        st = igea_stats_chi2_sf(T, dtot, &pval);
    if (st != 0)
        return st < 0 && st > -1000 ? IGEA_ENOCONV : st;
    for (int k = 0; k < IGEA_STATS_INFO_LEN; k++)
        info[k] = 0.0;
    info[IGEA_STATS_INFO_N_TEST] = dtot;
    info[IGEA_STATS_INFO_CHI2] = T;
    info[IGEA_STATS_INFO_DOF] = dtot;
    info[IGEA_STATS_INFO_CHI2_CRIT] = crit;
    info[IGEA_STATS_INFO_Z_CRIT] = gsl_cdf_ugaussian_Qinv(0.5 * alpha);
    info[IGEA_STATS_INFO_P_VALUE] = pval;
    info[IGEA_STATS_INFO_N_REJECT] = (double)nrej;
    info[IGEA_STATS_INFO_PASSED] = (nrej == 0 && T < crit) ? 1.0 : 0.0;
    info[IGEA_STATS_INFO_N_FLIGHTS] = nflights;
    return 0;
}

/* ---- inverse error function ------------------------------------------ */

#define TWO_OVER_SQRTPI 1.12837916709551257390

double igea__erfinv(double y)
{
    if (y == 0.0)
        return 0.0;
    double ay = fabs(y);
    /* Giles (2010), single-precision approximation as the start. */
    double w = -log((1.0 - ay) * (1.0 + ay)), p;
    if (w < 5.0) {
        w -= 2.5;
        p = 2.81022636e-08;
        p = 3.43273939e-07 + p * w;
        p = -3.5233877e-06 + p * w;
        p = -4.39150654e-06 + p * w;
        p = 0.00021858087 + p * w;
        p = -0.00125372503 + p * w;
        p = -0.00417768164 + p * w;
        p = 0.246640727 + p * w;
        p = 1.50140941 + p * w;
    } else {
        w = sqrt(w) - 3.0;
        p = -0.000200214257;
        p = 0.000100950558 + p * w;
        p = 0.00134934322 + p * w;
        p = -0.00367342844 + p * w;
        p = 0.00573950773 + p * w;
        p = -0.0076224613 + p * w;
        p = 0.00943887047 + p * w;
        p = 1.00167406 + p * w;
        p = 2.83297682 + p * w;
    }
    double x = p * ay;
    /* Newton steps (the start is within ~1% far in the tail, ~1e-7
     * elsewhere, so 2-5 steps); for ay > 0.5 on erfc(x) = 1 - ay (exact by Sterbenz),
     * which keeps the relative accuracy in the tail. */
    for (int it = 0; it < 12; it++) {
        double dens = TWO_OVER_SQRTPI * exp(-x * x);
        if (!(dens > 0.0))
            break;
        double dx = ay > 0.5 ? (erfc(x) - (1.0 - ay)) / dens /* erfc' = -dens */
                             : -(erf(x) - ay) / dens;
        x += dx;
        if (fabs(dx) <= 1e-16 * x)
            break;
    }
    return y < 0.0 ? -x : x;
}

int igea_stats_erfinv(double y, double *x)
{
    if (!(y > -1.0 && y < 1.0))
        return -1;
    if (!x)
        return -2;
    *x = igea__erfinv(y);
    return 0;
}

/* ---- Overall size of the verdict (docs/eqerr.md, "Overall size of the
 * verdict"). D_k(s) = P(sum_{i<=k} z_i^2 <= s^2 and max |z_i| > a),
 * C_k(s) = P(chi2_k <= s^2); with z_k = s sin(theta), s' = s cos(theta):
 *   D_k(s) = int_0^tmax 2 phi(z) D_{k-1}(s') s' dtheta
 *          + int_tmax^{pi/2} 2 phi(z) C_{k-1}(s') s' dtheta,
 * tmax = asin(min(1, a / s)). D_{k-1} and C_{k-1} live on panels in s
 * (UNION_M Gauss-Legendre nodes each, barycentric interpolation), split at
 * the breakpoints a sqrt(j) and graded geometrically towards each of them;
 * the theta integral is split where s' crosses a panel boundary or
 * sqrt(s^2 - a^2), UNION_M nodes per piece. */
#define UNION_M 10
#define UNION_H 0.25    /* widest panel in s */
#define UNION_GRADE 4   /* graded panels after each breakpoint */
#define UNION_RATIO 0.25
#define UNION_TINY 1e-30 /* a panel whose values all lie below it is skipped */
#define UNION_PI 3.14159265358979323846
#define UNION_SQRT1_2 0.70710678118654752440
#define UNION_INV_SQRT2PI 0.39894228040143267794

typedef struct {
    double x[UNION_M], w[UNION_M], bw[UNION_M];
    const double *bnd; /* P + 1 panel boundaries in s */
    int P;
    double a;
} union_grid;

/* P_m(x) by the three-term recurrence, and P_m'(x) into *dp. */
static double legendre(int m, double x, double *dp)
{
    double p0 = 1.0, p1 = x;
    for (int k = 2; k <= m; k++) {
        double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    *dp = m * (x * p1 - p0) / (x * x - 1.0);
    return p1;
}

/* Gauss-Legendre nodes and weights on [-1, 1] by Newton's iteration on
 * P_M, and the barycentric weights of interpolation at those nodes. */
static void union_rule(union_grid *g)
{
    const int m = UNION_M;
    for (int i = 0; i < m; i++) {
        double x = cos(UNION_PI * (i + 0.75) / (m + 0.5)), dp;
        for (int it = 0; it < 100; it++) {
            double dx = legendre(m, x, &dp) / dp;
            x -= dx;
            if (fabs(dx) < 1e-16)
                break;
        }
        legendre(m, x, &dp);
        g->x[i] = x;
        g->w[i] = 2.0 / ((1.0 - x * x) * dp * dp);
        g->bw[i] = (i % 2 ? -1.0 : 1.0) * sqrt((1.0 - x * x) * g->w[i]);
    }
}

/* Panel boundaries on [0, S] (bnd NULL: count only); returns P. */
static int union_panels(double a, double S, int n, double *bnd)
{
    int P = 0;
    double lo = 0.0;
    if (bnd)
        bnd[0] = 0.0;
    for (int j = 1;; j++) {
        double hi = j <= n - 1 ? a * sqrt((double)j) : S;
        if (hi > S)
            hi = S;
        if (hi > lo) {
            double x = lo;
            if (j > 1)
                for (int l = UNION_GRADE; l >= 1; l--) {
                    x = lo + (hi - lo) * pow(UNION_RATIO, l);
                    P++;
                    if (bnd)
                        bnd[P] = x;
                }
            int u = (int)ceil((hi - x) / UNION_H);
            if (u < 1)
                u = 1;
            for (int i = 1; i <= u; i++) {
                P++;
                if (bnd)
                    bnd[P] = i == u ? hi : x + (hi - x) * i / u;
            }
        }
        if (hi >= S)
            break;
        lo = hi;
    }
    return P;
}

/* Interpolant of the values f[UNION_M] of panel q at s. */
static double union_interp(const union_grid *g, int q, const double *f, double s)
{
    double mid = 0.5 * (g->bnd[q] + g->bnd[q + 1]), half = 0.5 * (g->bnd[q + 1] - g->bnd[q]);
    double t = (s - mid) / half, num = 0.0, den = 0.0;
    for (int i = 0; i < UNION_M; i++) {
        double d = t - g->x[i];
        if (d == 0.0)
            return f[i];
        num += g->bw[i] * f[i] / d;
        den += g->bw[i] / d;
    }
    return num / den;
}

/* theta of s' = u on the circle of radius s: acos(u / s), well conditioned. */
static double union_theta(double s, double u) { return atan2(sqrt((s - u) * (s + u)), u); }

/* int over s' in [u0, u1] (inside panel q) of 2 phi(z) f(s') s' dtheta. */
static double union_piece(const union_grid *g, int q, const double *f, double s, double u0,
                          double u1)
{
    double big = 0.0;
    for (int i = 0; i < UNION_M; i++)
        if (fabs(f[i]) > big)
            big = fabs(f[i]);
    if (!(big >= UNION_TINY) || !(u1 > u0))
        return 0.0;
    double t0 = union_theta(s, u1), t1 = union_theta(s, u0);
    double mid = 0.5 * (t0 + t1), half = 0.5 * (t1 - t0), sum = 0.0;
    for (int i = 0; i < UNION_M; i++) {
        double th = mid + half * g->x[i];
        double z = s * sin(th), sp = s * cos(th);
        sum += g->w[i] * exp(-0.5 * z * z) * union_interp(g, q, f, sp) * sp;
    }
    return 2.0 * UNION_INV_SQRT2PI * half * sum;
}

/* D_k(s) from the node values D = D_{k-1}, C = C_{k-1}. */
static double union_step(const union_grid *g, double s, const double *D, const double *C)
{
    double a = g->a, ucut = s > a ? sqrt((s - a) * (s + a)) : 0.0, sum = 0.0;
    for (int q = 0; q < g->P && g->bnd[q] < s; q++) {
        double lo = g->bnd[q], hi = g->bnd[q + 1] < s ? g->bnd[q + 1] : s;
        if (hi > ucut)
            sum += union_piece(g, q, D + (size_t)q * UNION_M, s, lo > ucut ? lo : ucut, hi);
        if (lo < ucut)
            sum += union_piece(g, q, C + (size_t)q * UNION_M, s, lo, hi < ucut ? hi : ucut);
    }
    return sum;
}

/* C_k at the nodes: P(chi2_k <= s^2). */
static int union_chi2_nodes(const union_grid *g, int k, double *C)
{
    for (int q = 0; q < g->P; q++) {
        double mid = 0.5 * (g->bnd[q] + g->bnd[q + 1]), half = 0.5 * (g->bnd[q + 1] - g->bnd[q]);
        for (int i = 0; i < UNION_M; i++) {
            double s = mid + half * g->x[i];
            double v = k == 1 ? erf(s * UNION_SQRT1_2) : chi2_tail(s * s, (double)k, 0);
            if (!isfinite(v))
                return IGEA_ENOCONV;
            C[(size_t)q * UNION_M + i] = v;
        }
    }
    return 0;
}

/* P(max |z_i| > a, sum z_i^2 <= b) for n >= 2, a^2 < b < n a^2. */
static int union_cross(int n, double a, double b, double *out)
{
    union_grid g;
    double S = sqrt(b);
    union_rule(&g);
    g.a = a;
    g.P = union_panels(a, S, n, NULL);
    size_t N = (size_t)g.P * UNION_M;
    double *mem = igea__dalloc(3 * N + (size_t)g.P + 1);
    if (!mem)
        return IGEA_ENOMEM;
    double *D0 = mem, *D1 = mem + N, *C = mem + 2 * N, *bnd = mem + 3 * N;
    union_panels(a, S, n, bnd);
    g.bnd = bnd;
    double ea = erfc(a * UNION_SQRT1_2);
    for (int q = 0; q < g.P; q++) {
        double mid = 0.5 * (bnd[q] + bnd[q + 1]), half = 0.5 * (bnd[q + 1] - bnd[q]);
        for (int i = 0; i < UNION_M; i++) {
            double s = mid + half * g.x[i];
            D0[(size_t)q * UNION_M + i] = s > a ? ea - erfc(s * UNION_SQRT1_2) : 0.0;
        }
    }
    int st = union_chi2_nodes(&g, 1, C);
    for (int k = 2; k < n && st == 0; k++) {
        for (int q = 0; q < g.P; q++) {
            double mid = 0.5 * (bnd[q] + bnd[q + 1]), half = 0.5 * (bnd[q + 1] - bnd[q]);
            for (int i = 0; i < UNION_M; i++)
                D1[(size_t)q * UNION_M + i] = union_step(&g, mid + half * g.x[i], D0, C);
        }
        double *t = D0;
        D0 = D1;
        D1 = t;
        st = union_chi2_nodes(&g, k, C);
    }
    double v = st == 0 ? union_step(&g, S, D0, C) : NAN;
    free(mem);
    if (st != 0)
        return st;
    if (!isfinite(v))
        return IGEA_ENOCONV;
    *out = v < 0.0 ? 0.0 : v;
    return 0;
}

/* ---- The same second term by inclusion-exclusion over the components
 * that exceed a [D] (docs/eqerr.md): with eps = P(|z| > a) and W_j the sum
 * of j excesses z^2 - a^2 of components conditioned on |z| > a (density
 * h(w) = exp(-(a^2 + w) / 2) / (eps sqrt(2 pi (a^2 + w))), analytic on
 * w > -a^2),
 *   P(max |z_i| > a, sum z_i^2 <= b)
 *     = sum_{j=1}^{J} (-1)^{j+1} C(n, j) eps^j E_j,
 *   E_j = E[F_{n-j}(c_j - W_j)] = int_0^{c_j} g_j(w) F_{n-j}(c_j - w) dw,
 * J = floor(b / a^2) (no more components can exceed a inside the ball),
 * c_j = b - j a^2, F_k the chi-square cdf, g_1 = h, g_{j+1} = g_j * h.
 * Every g_j is analytic on a neighbourhood of [0, C], C = c_1, whose only
 * singularity near it is that of h at -a^2: each is held by its values at
 * p Chebyshev points of [0, C] (the interpolant converges like rho^-p,
 * rho = z + sqrt(z^2 - 1), z = 1 + 2 a^2 / C: the Bernstein ellipse
 * through -a^2), so the convolution is one p x p matrix (Nystrom): row i
 * integrates the interpolant times h(x_i - l) over [0, x_i] by p-point
 * Gauss-Legendre, and each E_j is a p-point Gauss-Legendre sum over
 * [0, c_j]. Used where it is accurate: n - J >= 8 (F_{n-j} vanishes to
 * order >= 4 where the integral ends) and the largest term C(n, j) eps^j
 * <= 1e4 (cancellation costs at most 4 digits); elsewhere the recursion
 * above. At n = 74 and the seed's thresholds (alpha 0.01) p = 72 and the
 * whole sum takes about a millisecond. */
#define IE_MIN_FREE 8
#define IE_MAX_TERM 1e4
#define IE_DIGITS 38.0 /* rho^-p <= e^-38, 3e-17 */
#define IE_P_MIN 24
#define IE_P_MAX 320

/* Gauss-Legendre nodes t[q] and weights w[q] on [-1, 1], q even, by
 * Newton's iteration on P_q (the node pairs +-t share a weight). */
static void ie_gauss(int q, double *t, double *w)
{
    for (int i = 0; i < q / 2; i++) {
        double x = cos(UNION_PI * (i + 0.75) / (q + 0.5)), dp, dx;
        int it = 0;
        do {
            dx = legendre(q, x, &dp) / dp;
            x -= dx;
        } while (fabs(dx) > 1e-15 && ++it < 20);
        legendre(q, x, &dp);
        t[i] = x, t[q - 1 - i] = -x;
        w[i] = w[q - 1 - i] = 2.0 / ((1.0 - x * x) * dp * dp);
    }
}

/* The excess density h at w >= 0. */
static double ie_h(double w, double a2, double eps)
{
    return exp(-0.5 * (a2 + w)) / (eps * sqrt(2.0 * UNION_PI * (a2 + w)));
}

/* The interpolant of the values g at the nodes x (barycentric weights
 * bw) at u. */
static double ie_interp(int p, const double *x, const double *bw, const double *g, double u)
{
    double num = 0.0, den = 0.0;
    for (int k = 0; k < p; k++) {
        double d = u - x[k];
        if (d == 0.0)
            return g[k];
        double c = bw[k] / d;
        num += c * g[k];
        den += c;
    }
    return num / den;
}

/* E_j, j = 1..J, into E[0..J): the Chebyshev grid of p points on
 * [0, C], mem of p (p + 6) doubles. */
static void ie_expect(int n, double a2, double b, double eps, int J, int p, double *mem,
                      double *E)
{
    const double C = b - a2;
    double *x = mem, *bw = x + p, *t = bw + p, *w = t + p, *g = w + p, *gn = g + p;
    double *M = gn + p, *c = M + (size_t)p * p;
    for (int i = 0; i < p; i++) {
        double s = sin(0.5 * UNION_PI * i / (p - 1));
        x[i] = C * s * s;
        bw[i] = (i % 2 ? -1.0 : 1.0) * (i == 0 || i == p - 1 ? 0.5 : 1.0);
        g[i] = ie_h(x[i], a2, eps);
    }
    ie_gauss(p, t, w);
    /* M[i][k] = int_0^{x_i} l_k(l) h(x_i - l) dl, l_k the Lagrange basis */
    memset(M, 0, (size_t)p * p * sizeof(double));
    for (int i = 1; i < p; i++) {
        double *Mi = M + (size_t)i * p;
        for (int r = 0; r < p; r++) {
            double l = 0.5 * x[i] * (1.0 + t[r]);
            double f = 0.5 * x[i] * w[r] * ie_h(0.5 * x[i] * (1.0 - t[r]), a2, eps), den = 0.0;
            int hit = -1;
            for (int k = 0; k < p; k++) {
                double d = l - x[k];
                if (d == 0.0)
                    hit = k;
                c[k] = bw[k] / (d == 0.0 ? 1.0 : d);
                den += c[k];
            }
            if (hit >= 0) {
                Mi[hit] += f;
                continue;
            }
            f /= den;
            for (int k = 0; k < p; k++)
                Mi[k] += f * c[k];
        }
    }
    for (int j = 1; j <= J; j++) {
        double cj = b - j * a2, sum = 0.0;
        for (int r = 0; r < p && cj > 0.0; r++) {
            double u = 0.5 * cj * (1.0 + t[r]);
            sum += w[r] * ie_interp(p, x, bw, g, u) * chi2_tail(0.5 * cj * (1.0 - t[r]), n - j, 0);
        }
        E[j - 1] = 0.5 * cj * sum;
        if (j == J)
            break;
        for (int i = 0; i < p; i++) {
            const double *Mi = M + (size_t)i * p;
            double acc = 0.0;
            for (int k = 0; k < p; k++)
                acc += Mi[k] * g[k];
            gn[i] = acc;
        }
        memcpy(g, gn, (size_t)p * sizeof(double));
    }
}

/* The second term by inclusion-exclusion; 1 (and *out) when it applies,
 * 0 when the recursion must be used, or a status < 0. */
static int union_ie(int n, double a, double b, double *out)
{
    double a2 = a * a;
    int J = (int)floor(b / a2);
    if (J < 1 || n - J < IE_MIN_FREE)
        return 0;
    double eps = erfc(a * UNION_SQRT1_2), leps = log(eps), big = 0.0;
    double lgn = gsl_sf_lngamma(n + 1.0);
    for (int j = 1; j <= J; j++) {
        double t = lgn - gsl_sf_lngamma(j + 1.0) - gsl_sf_lngamma(n - j + 1.0) + j * leps;
        big = t > big ? t : big;
    }
    if (big > log(IE_MAX_TERM))
        return 0;
    const double C = b - a2;
    if (!(C > 0.0)) { /* b = a^2: J = 1 and the only integral is empty */
        *out = 0.0;
        return 1;
    }
    double z = 1.0 + 2.0 * a2 / C, rho = z + sqrt(z * z - 1.0);
    double pd = ceil(IE_DIGITS / log(rho)) + 8.0;
    if (!(pd <= IE_P_MAX))
        return 0;
    int p = pd < IE_P_MIN ? IE_P_MIN : (int)pd;
    p += p % 2;
    double *mem = igea__dalloc((size_t)p * (p + 7) + (size_t)J);
    if (!mem)
        return IGEA_ENOMEM;
    double *E = mem + (size_t)p * (p + 7);
    ie_expect(n, a2, b, eps, J, p, mem, E);
    /* C(n, j) eps^j by their ratios (relative error j ulps): exp of the
     * log-gamma differences would carry lgamma(n + 1)'s absolute error, 1e-13
     * relative at n = 150, into terms up to IE_MAX_TERM */
    double wj = 1.0;
    igea__ksum acc = {0, 0};
    for (int j = 1; j <= J; j++) {
        wj *= eps * (double)(n - j + 1) / (double)j;
        igea__ksum_add(&acc, (j % 2 ? 1.0 : -1.0) * wj * E[j - 1]);
    }
    double sum = igea__ksum_get(&acc);
    free(mem);
    if (!isfinite(sum))
        return IGEA_ENOCONV;
    *out = sum < 0.0 ? 0.0 : sum;
    return 1;
}

/* The sizes computed by union_cross, kept for the process: the same
 * (n, a, b) is asked for again and again (every eqerr call with the same
 * number of tested components and rule, the Monte Carlo's noise judge),
 * and one evaluation costs about 2 s of CPU at n = 74. Keyed by the exact
 * bits of a and b, so a hit returns exactly what the computation returns;
 * a mutex makes it thread-safe, a ring of UNION_MEMO entries bounds it. */
#define UNION_MEMO 64
static struct {
    int n;
    double a, b, q;
} union_memo[UNION_MEMO];
static int union_memo_len, union_memo_next;
static pthread_mutex_t union_memo_lock = PTHREAD_MUTEX_INITIALIZER;

static int union_memo_get(int n, double a, double b, double *q)
{
    int hit = 0;
    pthread_mutex_lock(&union_memo_lock);
    for (int i = 0; i < union_memo_len && !hit; i++)
        if (union_memo[i].n == n && !memcmp(&union_memo[i].a, &a, sizeof a) &&
            !memcmp(&union_memo[i].b, &b, sizeof b)) {
            *q = union_memo[i].q;
            hit = 1;
        }
    pthread_mutex_unlock(&union_memo_lock);
    return hit;
}

static void union_memo_put(int n, double a, double b, double q)
{
    pthread_mutex_lock(&union_memo_lock);
    union_memo[union_memo_next].n = n;
    union_memo[union_memo_next].a = a;
    union_memo[union_memo_next].b = b;
    union_memo[union_memo_next].q = q;
    union_memo_next = (union_memo_next + 1) % UNION_MEMO;
    if (union_memo_len < UNION_MEMO)
        union_memo_len++;
    pthread_mutex_unlock(&union_memo_lock);
}

int igea_stats_union_size(int n, double a, double b, double *size)
{
    if (n < 1 || n > IGEA_STATS_UNION_N_MAX)
        return -1;
    if (isnan(a) || a <= 0.0)
        return -2;
    if (isnan(b) || b <= 0.0)
        return -3;
    if (!size)
        return -4;
    double v, q;
    if (isinf(a) && isinf(b))
        v = 0.0;
    else if (isinf(b) || b >= n * (a * a)) {
        /* 1 - (1 - P(|z| > a))^n */
        v = -expm1(n * log1p(-erfc(a * UNION_SQRT1_2)));
    } else if (a * a >= b) {
        v = chi2_tail(b, (double)n, 1);
    } else {
        if (!union_memo_get(n, a, b, &q)) {
            int st = union_ie(n, a, b, &q);
            if (st == 0)
                st = union_cross(n, a, b, &q);
            else if (st == 1)
                st = 0;
            if (st != 0)
                return st;
            union_memo_put(n, a, b, q);
        }
        v = chi2_tail(b, (double)n, 1) + q;
    }
    if (!isfinite(v))
        return IGEA_ENOCONV;
    *size = v > 1.0 ? 1.0 : v;
    return 0;
}

/* Thresholds of level g: a = z_{1-g/2} (as -z_{g/2}, exact for small g),
 * b = chi2_g(n). */
static int verdict_level(int n, double g, double *a, double *b)
{
    int st = igea_stats_normal_quantile(0.5 * g, a);
    if (st != 0)
        return IGEA_ENOCONV;
    *a = -*a;
    st = igea_stats_chi2_upper(g, (double)n, b);
    return st < 0 && st > -10 ? IGEA_ENOCONV : st;
}

/* The exact rule's common level g: size(a(g), b(g)) = alpha; *pa, *pb,
 * *ps its thresholds and size. */
static int exact_level(int n, double alpha, double *pa, double *pb, double *ps)
{
    double ta, tb, ts;
    int st;
    /* size(g) increases from <= alpha at g = alpha / (n + 1) (the
     * union bound) to >= alpha at g = alpha: false position (Illinois)
     * on log g. */
    double lo = log(alpha / (n + 1)), hi = log(alpha), flo, fhi, sa, sb, ss;
    st = verdict_level(n, exp(lo), &sa, &sb);
    if (st == 0)
        st = igea_stats_union_size(n, sa, sb, &ss);
    if (st != 0)
        return st;
    flo = ss - alpha;
    st = verdict_level(n, exp(hi), &ta, &tb);
    if (st == 0)
        st = igea_stats_union_size(n, ta, tb, &ts);
    if (st != 0)
        return st;
    fhi = ts - alpha;
    if (n == 1 || fhi <= 0.0) {
        /* n = 1: a^2 = b, the size is g */
    } else if (flo >= 0.0) {
        st = verdict_level(n, exp(lo), &ta, &tb);
        ts = ss;
    } else {
        int side = 0;
        for (int it = 0;; it++) {
            if (it > 200)
                return IGEA_ENOCONV;
            double x = (lo * fhi - hi * flo) / (fhi - flo);
            if (!(x > lo && x < hi) || it % 4 == 3)
                x = 0.5 * (lo + hi); /* a bisection now and then bounds the count */
            st = verdict_level(n, exp(x), &ta, &tb);
            if (st == 0)
                st = igea_stats_union_size(n, ta, tb, &ts);
            if (st != 0)
                return st;
            double f = ts - alpha;
            if (fabs(f) <= 1e-12 * alpha || hi - lo <= 1e-11)
                break;
            if (f < 0.0) {
                lo = x;
                flo = f;
                if (side == -1)
                    fhi *= 0.5;
                side = -1;
            } else {
                hi = x;
                fhi = f;
                if (side == 1)
                    flo *= 0.5;
                side = 1;
            }
        }
    }
    *pa = ta, *pb = tb, *ps = ts;
    return 0;
}

int igea_stats_verdict_thresholds(int rule, int n, double alpha, double *a, double *b,
                                  double *size)
{
    if (rule < IGEA_STATS_VERDICT_SEED || rule > IGEA_STATS_VERDICT_SIDAK)
        return -1;
    if (n < 1 || n > IGEA_STATS_UNION_N_MAX)
        return -2;
    if (!(alpha > 0.0 && alpha < 1.0))
        return -3;
    if (!a)
        return -4;
    if (!b)
        return -5;
    if (!size)
        return -6;
    double ta, tb, ts;
    int st;
    if (rule == IGEA_STATS_VERDICT_CHI2) {
        st = igea_stats_chi2_upper(alpha, (double)n, &tb);
        if (st != 0)
            return IGEA_ENOCONV;
        ta = HUGE_VAL;
        ts = alpha;
    } else if (rule == IGEA_STATS_VERDICT_SEED || rule == IGEA_STATS_VERDICT_SIDAK) {
        st = verdict_level(n, alpha, &ta, &tb);
        if (st == 0 && rule == IGEA_STATS_VERDICT_SIDAK) {
            double gs = -expm1(log1p(-alpha) / n);
            st = igea_stats_normal_quantile(0.5 * gs, &ta);
            ta = -ta;
            if (st != 0)
                st = IGEA_ENOCONV;
        }
        if (st == 0)
            st = igea_stats_union_size(n, ta, tb, &ts);
        if (st != 0)
            return st;
    } else {
        st = exact_level(n, alpha, &ta, &tb, &ts);
        if (st != 0)
            return st;
    }
    *a = ta;
    *b = tb;
    *size = ts;
    return 0;
}
