/* stability_internal.h - what the stability sources share (not exported). */
#ifndef IGEA_STABILITY_INTERNAL_H
#define IGEA_STABILITY_INTERNAL_H

#include "internal.h"

/* Greenhall and Riley's EDF (PTTI 2003) of a difference variance: noise
 * exponent a (-2 .. 2), difference order d (2 Allan, 3 Hadamard), averaging
 * factor m, N phase points, overlapping (stride m) or not, modified (F = 1)
 * or not (F = m). stability_dev.c. */
double igea__stability_edf_greenhall(int a, int d, double m, double N, int overlapping,
                                     int modified);

/* ---- one pass over a record for every tau (stability_pass.c) ---- */

#define IGEA__AP_BLOCK 1024 /* phase points per block */
#define IGEA__AP_SRC_RING 1024 /* blocks a stream's ring keeps when older values
                                * can be read back (8 MB) */
#define IGEA__AP_AV 2       /* second differences x_e - 2 x_{e-m} + x_{e-2m} */
#define IGEA__AP_HV 3       /* third differences */
#define IGEA__AP_MV 4       /* sums of m second differences (modified) */

typedef struct {
    double hi, lo;
} igea__apdd;

/* Lag-1 sums of one series less its first value sh. */
typedef struct {
    double n, sh, first, last, prev;
    igea__ksum s, ss, lag;
} igea__apacf;

/* One averaging time: factor m, the difference (IGEA__AP_*), stride 1
 * (overlapping) or 0 (the terms whose last point is a multiple of m), acf 1
 * to push the m-sample means to the lag-1 noise identification. */
typedef struct {
    long m;
    int type, stride, acf;
} igea__aptau_spec;

typedef struct igea__apass igea__apass;

/* A pass over phase points (phase 1) or rate samples (phase 0: integrated,
 * the mean of the first block removed) for ntau averaging times, fed as a
 * stream (its ring of raw values as long as the longest lag); nhint the
 * points expected (0: unknown; the rings grow as needed). Returns 0 or
 * IGEA_ENOMEM. */
int igea__apass_new(int phase, int ntau, const igea__aptau_spec *spec, long nhint,
                    igea__apass **out);
/* The same pass run over a whole record v of n values, read in place (no
 * ring of raw values; the results equal those of the stream bit for bit).
 * Returns 0 or IGEA_ENOMEM. */
int igea__apass_whole(int phase, int ntau, const igea__aptau_spec *spec, long n,
                      const double *v, igea__apass **out);
/* A stream's values read back from a file (before the first value is
 * fed): value i at byte off + i stride of fd; the ring then stops at ring
 * blocks and older values are read with pread, each block checked against
 * the bits fed (docs/stability.md, "The driver's stream"). Without a lag
 * beyond ring blocks nothing changes. Returns 0, -1 (a whole-record pass,
 * values already fed, or a source already set), IGEA_ENOMEM. */
int igea__apass_source(igea__apass *p, int fd, double off, long stride, long ring);
/* igea_stability_stream_source with a ring of ring blocks (at least the deferred blocks and 8). */
struct igea_stability_stream;
int igea__stability_stream_source_ring(struct igea_stability_stream *h, int fd, double offset,
                                       int stride, long ring);
/* n more values; 0, IGEA_ENOMEM (a ring that could not grow), IGEA_EREAD (a
 * value read back could not be read or was not the one fed), -1 after end. */
int igea__apass_feed(igea__apass *p, long n, const double *v);
/* The end of the record: the last block's terms. 0, IGEA_ENOMEM or IGEA_EREAD. */
int igea__apass_end(igea__apass *p);
/* Sum of the squared terms of tau j (phase units: the rate samples' sums)
 * and their count. */
void igea__apass_get(const igea__apass *p, int j, double *sumsq, long *count);
/* The lag-1 noise type of tau j from its m-sample means (acf set), or
 * IGEA_STABILITY_NOISE_AUTO with fewer than 32 means. */
int igea__apass_alpha(const igea__apass *p, int j);
/* Phase points seen; the offset removed from rate samples. */
long igea__apass_points(const igea__apass *p);
/* 1 when a fed value was NaN or infinite (the sums are then meaningless). */
int igea__apass_nonfinite(const igea__apass *p);
double igea__apass_offset(const igea__apass *p);
void igea__apass_free(igea__apass *p);

/* Sum over len values of ((a - b) + (c - e))^2 (Theo1's terms). */
double igea__ap_sumsq4(const double *a, const double *b, const double *c, const double *e,
                       long len);

/* ---- what stability.c, stability_dev.c and the stream share ---- */

/* The block statistic of B >= 2 block means of nb samples into out
 * (IGEA_STABILITY_BLOCK_LEN). stability.c. */
void igea__stability_block_stats(long B, const double *means, long nb, double *out);
/* EDF and intervals of the rate-data kinds (igea_stability_allan's rules,
 * the noise type of a tau with too few means carried from the tau before).
 * stability.c. 0 or IGEA_ENOCONV. */
int igea__stability_allan_intervals(int n, double fs, int ntau, const double *tau, int kind,
                                    int noise, double conf, const int *al, const double *d,
                                    double *l, double *h, double *e);
/* igea_stability_dev's factor of tau, term count and EDF (stability_dev.c). */
long igea__stability_dev_factor(int kind, double tau, double fs, long N);
long igea__stability_dev_terms(int kind, long N, long m);
double igea__stability_dev_edf(int kind, int alpha, double N, double m);
/* The pass's setting of tau of an Allan or Hadamard kind (rate-data or
 * Stable32), and the deviation from its sum of squares and count. */
void igea__stability_pass_spec(int kind, long m, int acf, igea__aptau_spec *sp);
double igea__stability_pass_dev(int kind, int phase, double fs, long m, double ss, long cnt);

#endif
