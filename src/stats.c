/* stats.c - distributions and the equivalent-error accuracy tests. */
#include <float.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_sf_gamma.h>

#include "igea/stats.h"
#include "internal.h"

static int dof_ok(double dof) { return dof > 0.0 && dof <= IGEA_STATS_DOF_MAX; }

int igea_stats_normal_cdf(double x, double *p)
{
    if (isnan(x))
        return -1;
    if (!p)
        return -2;
    *p = isinf(x) ? (x > 0 ? 1.0 : 0.0) : gsl_cdf_ugaussian_P(x);
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

/* P or Q of the chi-square distribution; x >= 0 finite, dof validated.
 * gsl_sf_gamma_inc_[PQ]_e never reach the error handler for a > 0, x >= 0. */
static double chi2_tail(double x, double dof, int upper)
{
    gsl_sf_result r;
    int st = upper ? gsl_sf_gamma_inc_Q_e(0.5 * dof, 0.5 * x, &r)
                   : gsl_sf_gamma_inc_P_e(0.5 * dof, 0.5 * x, &r);
    if (st != 0)
        return NAN;
    return r.val;
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
    int st = igea_stats_chi2_upper(alpha, (double)ntest, &crit);
    if (st != 0)
        return st;
    /* First pass: the statistic only; z_i = e_i / sqrt(1 + 1/lambda_i) is
     * finite (|z_i| <= |e_i|), z_i^2 and T may exceed the double range. */
    sat_sum t = {{0, 0}, 0};
    for (int i = 0; i < n; i++) {
        if (lambda[i] >= lambda_test) {
            double zi = equiv_err[i] / sqrt(1.0 + 1.0 / lambda[i]);
            sat_add(&t, zi * zi);
        }
    }
    double T = sat_get(&t);
    if (t.sat)
        pval = 0.0; /* Q(T) < Q(DBL_MAX) = 0 to double precision */
    else {
        st = igea_stats_chi2_sf(T, (double)ntest, &pval);
        if (st != 0)
            return st < 0 && st > -1000 ? IGEA_ENOCONV : st;
    }
    /* Nothing can fail from here: the outputs are written. */
    int nrej = 0;
    for (int i = 0; i < n; i++) {
        if (lambda[i] >= lambda_test) {
            double zi = equiv_err[i] / sqrt(1.0 + 1.0 / lambda[i]);
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
