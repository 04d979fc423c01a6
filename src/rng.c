/* src/rng.c - xoshiro256++ keyed per flight, and its ziggurat normal
 * (docs/validation.md, "Keyed streams: generator xoshiro").
 *
 * xoshiro256++: D. Blackman, S. Vigna, "Scrambled linear pseudorandom
 * number generators", ACM TOMS 47 (2021), the reference code of
 * prng.di.unimi.it. SplitMix64: G. Steele, D. Lea, C. Flood, "Fast
 * splittable pseudorandom number generators", OOPSLA 2014. Ziggurat:
 * G. Marsaglia, W. W. Tsang, J. Stat. Softw. 5(8) 2000, in the form of
 * J. A. Doornik, "An improved ziggurat method to generate normal random
 * samples" (2005): independent bits for the layer and the uniform, 128
 * layers, R = 3.442619855899, V = 9.91256303526217e-3. */
#include <math.h>
#include <pthread.h>

#include "rng.h"

#define ZIG_C IGEA__ZIG_C
#define ZIG_R 3.442619855899
#define ZIG_V 9.91256303526217e-3

/* x[0] = V / f(R) is the base's width (rectangle and tail). */
double igea__zig_x[ZIG_C + 1], igea__zig_ratio[ZIG_C];
static pthread_once_t zig_once = PTHREAD_ONCE_INIT;

static void zig_init(void)
{
    double f = exp(-0.5 * ZIG_R * ZIG_R);
    igea__zig_x[0] = ZIG_V / f;
    igea__zig_x[1] = ZIG_R;
    igea__zig_x[ZIG_C] = 0.0;
    for (int i = 2; i < ZIG_C; i++) {
        igea__zig_x[i] = sqrt(-2.0 * log(ZIG_V / igea__zig_x[i - 1] + f));
        f = exp(-0.5 * igea__zig_x[i] * igea__zig_x[i]);
    }
    for (int i = 0; i < ZIG_C; i++)
        igea__zig_ratio[i] = igea__zig_x[i + 1] / igea__zig_x[i];
}

static uint64_t splitmix64(uint64_t *x)
{
    uint64_t z = (*x += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

static void key64(igea__xoshiro *st, uint64_t key)
{
    for (int i = 0; i < 4; i++)
        st->s[i] = splitmix64(&key);
    if (!(st->s[0] | st->s[1] | st->s[2] | st->s[3]))
        st->s[0] = 1; /* the one forbidden state */
    pthread_once(&zig_once, zig_init);
}

void igea__xoshiro_key(igea__xoshiro *st, int seed, int flight)
{
    key64(st, ((uint64_t)(unsigned)seed << 32) | (uint64_t)(unsigned)flight);
}

/* A uniform in (0, 1): the log of the tail never sees 0. */
static double open_uniform(igea__xoshiro *st)
{
    return ((double)(igea__xoshiro_next(st) >> 11) + 0.5) * 0x1.0p-53;
}

static double zig_tail(igea__xoshiro *st, int negative)
{
    double x, y;
    do {
        x = log(open_uniform(st)) / ZIG_R;
        y = log(open_uniform(st));
    } while (-2.0 * y < x * x);
    return negative ? x - ZIG_R : ZIG_R - x;
}

/* One try b: in its rectangle (the inline path's test, for the tries made
 * here), the base's tail, or a wedge (accepted under the density). */
static int zig_try(igea__xoshiro *st, uint64_t b, double *z)
{
    double u = (double)((int64_t)b >> 11) * 0x1.0p-52;
    unsigned i = (unsigned)(b & (ZIG_C - 1));
    if (fabs(u) < igea__zig_ratio[i]) {
        *z = u * igea__zig_x[i];
        return 1;
    }
    if (i == 0) {
        *z = zig_tail(st, u < 0.0);
        return 1;
    }
    double x = u * igea__zig_x[i];
    double f0 = exp(-0.5 * (igea__zig_x[i] * igea__zig_x[i] - x * x));
    double f1 = exp(-0.5 * (igea__zig_x[i + 1] * igea__zig_x[i + 1] - x * x));
    *z = x;
    return f1 + igea__xoshiro_uniform(st) * (f0 - f1) < 1.0;
}

double igea__xoshiro_normal_slow(igea__xoshiro *st, uint64_t b)
{
    double z;
    while (!zig_try(st, b, &z))
        b = igea__xoshiro_next(st);
    return z;
}

/* igea__xoshiro_normal's steps with the four words in locals: the inline
 * form keeps the state in memory around the loop (its address goes to the
 * rare path), a store-to-load chain on every draw. */
void igea__xoshiro_normals(igea__xoshiro *st, int n, double *z)
{
    uint64_t s0 = st->s[0], s1 = st->s[1], s2 = st->s[2], s3 = st->s[3];
    for (int k = 0; k < n; k++) {
        uint64_t a = s0 + s3;
        uint64_t b = ((a << 23) | (a >> 41)) + s0;
        uint64_t t = s1 << 17;
        s2 ^= s0;
        s3 ^= s1;
        s1 ^= s2;
        s0 ^= s3;
        s2 ^= t;
        s3 = (s3 << 45) | (s3 >> 19);
        double u = (double)((int64_t)b >> 11) * 0x1.0p-52;
        unsigned i = (unsigned)(b & (ZIG_C - 1));
        if (fabs(u) < igea__zig_ratio[i]) {
            z[k] = u * igea__zig_x[i];
            continue;
        }
        igea__xoshiro w = {{s0, s1, s2, s3}};
        z[k] = igea__xoshiro_normal_slow(&w, b);
        s0 = w.s[0], s1 = w.s[1], s2 = w.s[2], s3 = w.s[3];
    }
    st->s[0] = s0, st->s[1] = s1, st->s[2] = s2, st->s[3] = s3;
}

/* ---- the GSL face ------------------------------------------------------ */

static void gsl_set(void *state, unsigned long seed)
{
    key64(state, (uint64_t)seed << 32);
}

static unsigned long gsl_get(void *state)
{
    return (unsigned long)(igea__xoshiro_next(state) >> 32);
}

static double gsl_get_double(void *state)
{
    return igea__xoshiro_uniform(state);
}

static const gsl_rng_type xoshiro_type = {"xoshiro256++", 0xFFFFFFFFUL, 0,
                                          sizeof(igea__xoshiro), gsl_set, gsl_get,
                                          gsl_get_double};
const gsl_rng_type *igea__xoshiro_type = &xoshiro_type;
