/* src/rng.h - igea's own random streams (src/rng.c): xoshiro256++ keyed
 * by (seed, flight) through SplitMix64, and a ziggurat normal on it.
 * Internal; the generator is also a gsl_rng_type so that every part of the
 * simulation that draws through GSL (the noise models) can use it. */
#ifndef IGEA_RNG_H
#define IGEA_RNG_H

#include <math.h>
#include <stdint.h>

#include <gsl/gsl_rng.h>

/* The state: four 64-bit words, never all zero. */
typedef struct {
    uint64_t s[4];
} igea__xoshiro;

/* The GSL type (name "xoshiro256++"): get gives the top 32 bits of the
 * next output, get_double its top 53 bits in [0, 1). Its set(seed) is the
 * keyed seeding with flight 0; use igea__xoshiro_key for a flight. */
extern const gsl_rng_type *igea__xoshiro_type;

/* Seed st for stream `seed`, flight `flight` (both >= 0): s[0..3] are four
 * successive SplitMix64 outputs from the 64-bit key seed * 2^32 + flight,
 * so that every (seed, flight) starts from its own point. */
void igea__xoshiro_key(igea__xoshiro *st, int seed, int flight);

/* The next 64-bit output of xoshiro256++ (Blackman and Vigna 2019). */
static inline uint64_t igea__xoshiro_next(igea__xoshiro *st)
{
    uint64_t *s = st->s;
    uint64_t a = s[0] + s[3];
    uint64_t r = ((a << 23) | (a >> 41)) + s[0];
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = (s[3] << 45) | (s[3] >> 19);
    return r;
}

/* A uniform in [0, 1) with 53 random bits. */
static inline double igea__xoshiro_uniform(igea__xoshiro *st)
{
    return (double)(igea__xoshiro_next(st) >> 11) * 0x1.0p-53;
}

/* The ziggurat's tables (rng.c; filled by the first igea__xoshiro_key):
 * igea__zig_x[i] the right edge of layer i, igea__zig_ratio[i] =
 * igea__zig_x[i + 1] / igea__zig_x[i]. */
#define IGEA__ZIG_C 128
extern double igea__zig_x[IGEA__ZIG_C + 1], igea__zig_ratio[IGEA__ZIG_C];

/* The ziggurat's rare cases (rng.c): the try b in layer i outside its
 * rectangle, then new tries until one is accepted. */
double igea__xoshiro_normal_slow(igea__xoshiro *st, uint64_t b);

/* A standard normal: Doornik's (2005) ziggurat with 128 layers on one
 * 64-bit output per try (the layer from its low 7 bits, a uniform in
 * [-1, 1) from its top 53 as a signed integer), the tail by Marsaglia's
 * (1964) method. The rectangles take about 99 % of the tries: inline here. */
static inline double igea__xoshiro_normal(igea__xoshiro *st)
{
    uint64_t b = igea__xoshiro_next(st);
    double u = (double)((int64_t)b >> 11) * 0x1.0p-52;
    unsigned i = (unsigned)(b & (IGEA__ZIG_C - 1));
    if (fabs(u) < igea__zig_ratio[i])
        return u * igea__zig_x[i];
    return igea__xoshiro_normal_slow(st, b);
}

/* n standard normals into z, those of n calls of igea__xoshiro_normal (the
 * same values; the state kept in registers through the loop: rng.c). */
void igea__xoshiro_normals(igea__xoshiro *st, int n, double *z);

#endif
