/* sim_interval.c - the exact (Clopper-Pearson) interval of a Monte Carlo
 * rate (docs/validation.md, "Intervals"). */
#include <float.h>

#include "igea/sim.h"
#include "igea/stats.h"
#include "internal.h"

/* I_x(a, b), the regularised incomplete beta, through the F tail of
 * igea_stats_f_sf: Q(f; 2b, 2a) = I_{2a / (2a + 2b f)}(a, b), f = a (1 - x)
 * / (b x). 0 < x < 1; a, b validated. Returns 0 or IGEA_ENOCONV. */
static int ibeta_x(double x, double a, double b, double *v)
{
    double f = a * (1.0 - x) / (b * x);
    return igea_stats_f_sf(f, 2.0 * b, 2.0 * a, v) ? IGEA_ENOCONV : 0;
}

/* The x in (0, 1) with I_x(a, b) = p, by bisection to 4 ulp (the function
 * is increasing in x). Returns 0 or IGEA_ENOCONV. */
static int ibeta_solve(double a, double b, double p, double *x)
{
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 400 && hi - lo > 4.0 * DBL_EPSILON * hi; it++) {
        double mid = 0.5 * (lo + hi), v;
        if (mid <= lo || mid >= hi)
            break;
        if (ibeta_x(mid, a, b, &v))
            return IGEA_ENOCONV;
        if (v < p)
            lo = mid;
        else
            hi = mid;
    }
    *x = 0.5 * (lo + hi);
    return 0;
}

int igea_sim_interval_cp(double k, double n, double level, double *lohi)
{
    if (!(k >= 0.0) || !isfinite(k) || k != floor(k) || (n > 0.0 && k > n))
        return -1;
    if (!(n > 0.0) || !(n <= IGEA_SIM_INTERVAL_CP_NMAX) || n != floor(n))
        return -2;
    if (!(level > 0.0 && level < 1.0))
        return -3;
    if (!lohi)
        return -4;
    double a2 = 0.5 * (1.0 - level), lo = 0.0, hi = 1.0;
    if (k > 0 && ibeta_solve(k, n - k + 1.0, a2, &lo))
        return IGEA_ENOCONV;
    if (k < n && ibeta_solve(k + 1.0, n - k, 1.0 - a2, &hi))
        return IGEA_ENOCONV;
    lohi[0] = lo;
    lohi[1] = hi;
    return 0;
}
