/* tests/test_stability.c - block 3-sigma, Allan deviations, EDF intervals,
 * noise identification (METHODS 3.4). */
#include "testutil.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "igea/stability.h"
#include "igea/stats.h"

/* Out-of-memory loop (as tests/test_oom.c); not under AddressSanitizer. */
#include "oom.h"

#include <fcntl.h>
#include <unistd.h>

/* stability_stream.c: igea_stability_stream_source with a ring of ring
 * blocks (a short record then reaches past it) */
struct igea_stability_stream;
int igea__stability_stream_source_ring(struct igea_stability_stream *h, int fd, double offset,
                                       int stride, long ring);

/* The NBS 1000-point frequency data set: x_{k+1} = 16807 x_k mod
 * 2^31 - 1, x_0 = 1234567890, y = x / (2^31 - 1) (Riley, "The calculation
 * of time domain frequency stability"; NIST SP 1065 section 12). */
static void nbs1000(double *y)
{
    long long x = 1234567890LL;
    for (int k = 0; k < 1000; k++) {
        y[k] = (double)x / 2147483647.0;
        x = (16807LL * x) % 2147483647LL;
    }
}

static void test_block(void **state)
{
    /* METHODS 3.4 test vector: 300 s at 1 Hz, blocks of 1, 2, 3 with a
     * +-0.5 alternating pattern -> block means 1, 2, 3, 3 sigma = 3 */
    double y[350], out[IGEA_STABILITY_BLOCK_LEN];
    for (int k = 0; k < 350; k++)
        y[k] = (k < 300 ? 1.0 + k / 100 : 100.0) + (k % 2 ? -0.5 : 0.5);
    assert_int_equal(igea_stability_block(350, y, 1.0, 100.0, out), 0);
    assert_close(out[IGEA_STABILITY_BLOCK_3SIGMA], 3.0, 1e-15);
    assert_close(out[IGEA_STABILITY_BLOCK_SIGMA], 1.0, 1e-15);
    assert_close(out[IGEA_STABILITY_BLOCK_NBLOCK], 3.0, 0);
    assert_close(out[IGEA_STABILITY_BLOCK_NSAMP], 100.0, 0);
    assert_close(out[IGEA_STABILITY_BLOCK_MEAN], 2.0, 1e-15);
    assert_close(out[IGEA_STABILITY_BLOCK_ADEV], sqrt(0.5), 1e-15);
    /* compensated sums: the same on a 1e9 offset */
    for (int k = 0; k < 350; k++)
        y[k] += 1e9;
    assert_int_equal(igea_stability_block(350, y, 1.0, 100.0, out), 0);
    assert_close(out[IGEA_STABILITY_BLOCK_3SIGMA], 3.0, 1e-12);
    /* white noise 1e-5 at 10 Hz for 6 h: 3 sigma ~ 3e-5 / sqrt(1000) */
    int n = 216000;
    double *w = malloc(sizeof(double) * n);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 7);
    for (int k = 0; k < n; k++)
        w[k] = 1.0 + gsl_ran_gaussian(r, 1e-5);
    gsl_rng_free(r);
    assert_int_equal(igea_stability_block(n, w, 10.0, 100.0, out), 0);
    assert_close(out[IGEA_STABILITY_BLOCK_NBLOCK], 216.0, 0);
    assert_close(out[IGEA_STABILITY_BLOCK_3SIGMA], 3e-5 / sqrt(1000.0), 0.2); /* sd ~5 % */
    /* invalid */
    fill_sentinel(out, IGEA_STABILITY_BLOCK_LEN);
    assert_int_equal(igea_stability_block(1, w, 10.0, 100.0, out), -1);
    assert_int_equal(igea_stability_block(n, NULL, 10.0, 100.0, out), -2);
    assert_int_equal(igea_stability_block(n, w, 0.0, 100.0, out), -3);
    assert_int_equal(igea_stability_block(n, w, NAN, 100.0, out), -3);
    assert_int_equal(igea_stability_block(n, w, 10.0, -1.0, out), -4);
    assert_int_equal(igea_stability_block(n, w, 10.0, 20000.0, out), -4); /* B = 1 */
    assert_int_equal(igea_stability_block(n, w, 10.0, 0.01, out), -4);    /* N_b = 0 */
    assert_int_equal(igea_stability_block(n, w, 10.0, 100.0, NULL), -5);
    w[100] = INFINITY;
    assert_int_equal(igea_stability_block(n, w, 10.0, 100.0, out), IGEA_ENONFINITE);
    assert_true(all_sentinel(out, IGEA_STABILITY_BLOCK_LEN));
    free(w);
}

static void test_allan_nbs(void **state)
{
    /* published values (7 digits): Riley's test suite Table III, NIST SP
     * 1065 p. 108, tau = 1, 10, 100 */
    double y[1000];
    nbs1000(y);
    const double tau[3] = {1, 10, 100};
    const double want[3][3] = {{2.922319e-01, 9.159953e-02, 3.241343e-02},  /* OADEV */
                               {2.922319e-01, 6.172376e-02, 2.170921e-02},  /* MDEV */
                               {2.922319e-01, 9.965736e-02, 3.897804e-02}}; /* ADEV */
    for (int kind = 0; kind < 3; kind++) {
        double dev[3];
        int cnt[3];
        assert_int_equal(igea_stability_allan(1000, y, 1.0, 3, tau, kind, IGEA_STABILITY_NOISE_WFM,
                                              0.683, dev, NULL, NULL, NULL, cnt), 0);
        for (int j = 0; j < 3; j++)
            assert_close(dev[j], want[kind][j], 2e-7);
        if (kind == IGEA_STABILITY_ALLAN_OVERLAPPING)
            assert_true(cnt[0] == 999 && cnt[1] == 981 && cnt[2] == 801);
        if (kind == IGEA_STABILITY_ALLAN_MODIFIED)
            assert_true(cnt[1] == 972 && cnt[2] == 702);
        if (kind == IGEA_STABILITY_ALLAN_NONOVERLAPPING)
            assert_true(cnt[1] == 99 && cnt[2] == 9);
    }
    /* the 9-point frequency set of the same suite, tau = 1, 2 */
    const double f[9] = {892, 809, 823, 798, 671, 644, 883, 903, 677};
    const double t2[2] = {1, 2};
    const double w2[3][2] = {{91.22945, 85.95287}, {91.22945, 74.78849}, {91.22945, 115.8082}};
    for (int kind = 0; kind < 3; kind++) {
        double dev[2];
        assert_int_equal(igea_stability_allan(9, f, 1.0, 2, t2, kind, IGEA_STABILITY_NOISE_WFM, 0.683,
                                              dev, NULL, NULL, NULL, NULL), 0);
        assert_close(dev[0], w2[kind][0], 1e-7);
        assert_close(dev[1], w2[kind][1], 5e-7);
    }
}

/* Direct definitions, O(n m), for comparison. */
static double direct_oadev(int n, const double *y, int m)
{
    double s = 0;
    int c = n - 2 * m + 1;
    for (int i = 0; i < c; i++) {
        double a = 0, b = 0;
        for (int k = 0; k < m; k++) {
            a += y[i + k];
            b += y[i + m + k];
        }
        s += (b - a) * (b - a);
    }
    return sqrt(s / (2.0 * m * m * c));
}
static double direct_mdev(int n, const double *y, int m)
{
    double s = 0;
    int c = n - 3 * m + 2;
    for (int j = 0; j < c; j++) {
        double in = 0;
        for (int i = j; i < j + m; i++) {
            double a = 0, b = 0;
            for (int k = 0; k < m; k++) {
                a += y[i + k];
                b += y[i + m + k];
            }
            in += b - a;
        }
        s += in * in;
    }
    return sqrt(s / (2.0 * m * m * m * m * c));
}

static void test_allan_direct_and_ramp(void **state)
{
    int n = 500;
    double y[500];
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 11);
    for (int k = 0; k < n; k++)
        y[k] = gsl_ran_gaussian(r, 1.0) + 0.01 * k;
    gsl_rng_free(r);
    const double tau[5] = {0.5, 1.5, 4.0, 12.5, 40.0}; /* fs = 2: m = 1, 3, 8, 25, 80 */
    const int m[5] = {1, 3, 8, 25, 80};
    double dev[5], dmod[5];
    assert_int_equal(igea_stability_allan(n, y, 2.0, 5, tau, IGEA_STABILITY_ALLAN_OVERLAPPING,
                                          IGEA_STABILITY_NOISE_WFM, 0.683, dev, NULL, NULL, NULL, NULL), 0);
    assert_int_equal(igea_stability_allan(n, y, 2.0, 5, tau, IGEA_STABILITY_ALLAN_MODIFIED,
                                          IGEA_STABILITY_NOISE_WFM, 0.683, dmod, NULL, NULL, NULL, NULL), 0);
    for (int j = 0; j < 5; j++) {
        assert_close(dev[j], direct_oadev(n, y, m[j]), 1e-12);
        assert_close(dmod[j], direct_mdev(n, y, m[j]), 1e-12);
    }
    /* a rate ramp y = R t on a large offset: sigma = R tau / sqrt2 for all
     * three kinds (closed form) */
    int nr = 4096;
    double *yr = malloc(sizeof(double) * nr);
    double fs = 8.0, R = 3e-4;
    for (int k = 0; k < nr; k++)
        yr[k] = 1e3 + R * k / fs;
    const double tr[4] = {0.125, 1.0, 16.0, 128.0};
    for (int kind = 0; kind < 3; kind++) {
        double d[4];
        assert_int_equal(igea_stability_allan(nr, yr, fs, 4, tr, kind, IGEA_STABILITY_NOISE_RWFM, 0.9,
                                              d, NULL, NULL, NULL, NULL), 0);
        for (int j = 0; j < 4; j++)
            assert_close(d[j], R * tr[j] / sqrt(2.0), 1e-8);
    }
    free(yr);
}

static void test_allan_edf(void **state)
{
    double y[1000];
    nbs1000(y);
    const double tau[3] = {1, 10, 100};
    double dev[3], lo[3], hi[3], edf[3];
    assert_int_equal(igea_stability_allan(1000, y, 1.0, 3, tau, IGEA_STABILITY_ALLAN_OVERLAPPING,
                                          IGEA_STABILITY_NOISE_WFM, 0.683, dev, lo, hi, edf, NULL), 0);
    /* SP 1065 white FM: [3(N-1)/(2m) - 2(N-2)/N] 4m^2 / (4m^2 + 5), N = 1001 */
    for (int j = 0; j < 3; j++) {
        double N = 1001, m = tau[j];
        double e = (3 * (N - 1) / (2 * m) - 2 * (N - 2) / N) * 4 * m * m / (4 * m * m + 5);
        assert_close(edf[j], e, 1e-14);
        double qh, ql;
        igea_stats_chi2_quantile(0.5 + 0.683 / 2, e, &qh);
        igea_stats_chi2_quantile(0.5 - 0.683 / 2, e, &ql);
        assert_close(lo[j], dev[j] * sqrt(e / qh), 1e-14);
        assert_close(hi[j], dev[j] * sqrt(e / ql), 1e-14);
        assert_true(lo[j] < dev[j] && dev[j] < hi[j]);
    }
    assert_close(edf[0], 665.77955378, 1e-9);
    /* the other noise types (SP 1065 Table 5) at m = 10, N = 1001 */
    double N = 1001, m = 10, e;
    assert_int_equal(igea_stability_allan(1000, y, 1.0, 1, tau + 1, 0, IGEA_STABILITY_NOISE_WPM, 0.683,
                                          dev, NULL, NULL, &e, NULL), 0);
    assert_close(e, (N + 1) * (N - 2 * m) / (2 * (N - m)), 1e-14);
    assert_int_equal(igea_stability_allan(1000, y, 1.0, 1, tau + 1, 0, IGEA_STABILITY_NOISE_FPM, 0.683,
                                          dev, NULL, NULL, &e, NULL), 0);
    assert_close(e, exp(sqrt(log((N - 1) / (2 * m)) * log((2 * m + 1) * (N - 1) / 4))), 1e-14);
    assert_int_equal(igea_stability_allan(1000, y, 1.0, 1, tau + 1, 0, IGEA_STABILITY_NOISE_FFM, 0.683,
                                          dev, NULL, NULL, &e, NULL), 0);
    assert_close(e, 5 * N * N / (4 * m * (N + 3 * m)), 1e-14);
    assert_int_equal(igea_stability_allan(1000, y, 1.0, 1, tau, 0, IGEA_STABILITY_NOISE_FFM, 0.683,
                                          dev, NULL, NULL, &e, NULL), 0);
    assert_close(e, 2 * (N - 2) * (N - 2) / (2.3 * N - 4.9), 1e-14);
    assert_int_equal(igea_stability_allan(1000, y, 1.0, 1, tau + 1, 0, IGEA_STABILITY_NOISE_RWFM, 0.683,
                                          dev, NULL, NULL, &e, NULL), 0);
    assert_close(e, (N - 2) / (m * (N - 3) * (N - 3)) * ((N - 1) * (N - 1) - 3 * m * (N - 1) + 4 * m * m), 1e-14);
    /* non-overlapping: Greenhall and Riley's EDF (PTTI 2003; d = 2, F = m,
     * S = 1) on N = 1001 phase points at m = 100, white FM: 6.230769230769231,
     * from the independent Python port of the published algorithm
     * (gh_edf(0, 2, 100, 1001, False, False) in
     * tests/python/test_stability_dev.py) */
    assert_int_equal(igea_stability_allan(1000, y, 1.0, 1, tau + 2, IGEA_STABILITY_ALLAN_NONOVERLAPPING,
                                          IGEA_STABILITY_NOISE_WFM, 0.683, dev, NULL, NULL, &e, NULL), 0);
    assert_close(e, 6.230769230769231, 1e-12);
    /* modified: Greenhall's EDF against the exact EDF tr(C)^2 / |C|_F^2 of
     * the estimator's quadratic form (C its covariance), computed for n =
     * 300 white FM / white PM samples by direct matrix algebra (numpy) */
    double y3[300], em;
    for (int k = 0; k < 300; k++)
        y3[k] = sin(0.1 * k);
    const double m16 = 16, m40 = 40, m4 = 4, m1 = 1;
    assert_int_equal(igea_stability_allan(300, y3, 1.0, 1, &m16, IGEA_STABILITY_ALLAN_MODIFIED, IGEA_STABILITY_NOISE_WFM,
                                          0.683, dev, NULL, NULL, &em, NULL), 0);
    assert_close(em, 15.984003390423982, 3e-3);
    assert_int_equal(igea_stability_allan(300, y3, 1.0, 1, &m40, IGEA_STABILITY_ALLAN_MODIFIED, IGEA_STABILITY_NOISE_WFM,
                                          0.683, dev, NULL, NULL, &em, NULL), 0);
    assert_close(em, 5.0575394296789895, 1e-4);
    assert_int_equal(igea_stability_allan(300, y3, 1.0, 1, &m4, IGEA_STABILITY_ALLAN_MODIFIED, IGEA_STABILITY_NOISE_WPM,
                                          0.683, dev, NULL, NULL, &em, NULL), 0);
    assert_close(em, 85.9649620943241, 1e-10);
    /* m = 1: the overlapping formula (the estimators coincide) */
    assert_int_equal(igea_stability_allan(300, y3, 1.0, 1, &m1, IGEA_STABILITY_ALLAN_MODIFIED, IGEA_STABILITY_NOISE_WFM,
                                          0.683, dev, NULL, NULL, &em, NULL), 0);
    assert_close(em, (3.0 * 300 / 2 - 2.0 * 299 / 301) * 4.0 / 9.0, 1e-14);
    /* AUTO: white noise gives the white-FM EDF, a random walk the RWFM one */
    int n = 4096;
    double *w = malloc(sizeof(double) * n), *rw = malloc(sizeof(double) * n);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 3);
    double acc = 0;
    for (int k = 0; k < n; k++) {
        w[k] = gsl_ran_gaussian(r, 1.0);
        acc += gsl_ran_gaussian(r, 1.0);
        rw[k] = acc;
    }
    gsl_rng_free(r);
    const double t4[4] = {2, 4, 8, 16};
    double ea[4], ew[4], dv[4];
    assert_int_equal(igea_stability_allan(n, w, 1.0, 4, t4, 0, IGEA_STABILITY_NOISE_AUTO, 0.9, dv, NULL, NULL, ea, NULL), 0);
    assert_int_equal(igea_stability_allan(n, w, 1.0, 4, t4, 0, IGEA_STABILITY_NOISE_WFM, 0.9, dv, NULL, NULL, ew, NULL), 0);
    for (int j = 0; j < 4; j++)
        assert_close(ea[j], ew[j], 1e-15);
    assert_int_equal(igea_stability_allan(n, rw, 1.0, 4, t4, 0, IGEA_STABILITY_NOISE_AUTO, 0.9, dv, NULL, NULL, ea, NULL), 0);
    assert_int_equal(igea_stability_allan(n, rw, 1.0, 4, t4, 0, IGEA_STABILITY_NOISE_RWFM, 0.9, dv, NULL, NULL, ew, NULL), 0);
    for (int j = 0; j < 4; j++)
        assert_close(ea[j], ew[j], 1e-15);
    /* differenced white noise (white PM) gives the WPM one */
    for (int k = n - 1; k > 0; k--)
        w[k] -= w[k - 1];
    assert_int_equal(igea_stability_allan(n, w, 1.0, 4, t4, 0, IGEA_STABILITY_NOISE_AUTO, 0.9, dv, NULL, NULL, ea, NULL), 0);
    assert_int_equal(igea_stability_allan(n, w, 1.0, 4, t4, 0, IGEA_STABILITY_NOISE_WPM, 0.9, dv, NULL, NULL, ew, NULL), 0);
    for (int j = 0; j < 4; j++)
        assert_close(ea[j], ew[j], 1e-15);
    /* beyond 32 means the type of the last identified tau is kept */
    const double t2[2] = {64, 256};
    assert_int_equal(igea_stability_allan(n, w, 1.0, 2, t2, 0, IGEA_STABILITY_NOISE_AUTO, 0.9, dv, NULL, NULL, ea, NULL), 0);
    assert_int_equal(igea_stability_allan(n, w, 1.0, 2, t2, 0, IGEA_STABILITY_NOISE_WPM, 0.9, dv, NULL, NULL, ew, NULL), 0);
    assert_close(ea[1], ew[1], 1e-15);
    free(w);
    free(rw);
}

static void test_allan_args(void **state)
{
    double y[100];
    for (int k = 0; k < 100; k++)
        y[k] = sin(k);
    const double tau[2] = {1, 10};
    double dev[2], lo[2];
    int cnt[2];
    fill_sentinel(dev, 2);
    fill_sentinel(lo, 2);
    cnt[0] = cnt[1] = -3;
    const double t_bad[2] = {1, 51}, t_mod[2] = {1, 34}, t_neg[2] = {1, -1}, t_small[2] = {1, 0.1};
    assert_int_equal(igea_stability_allan(1, y, 1, 2, tau, 0, 0, 0.683, dev, lo, NULL, NULL, cnt), -1);
    assert_int_equal(igea_stability_allan(100, NULL, 1, 2, tau, 0, 0, 0.683, dev, lo, NULL, NULL, cnt), -2);
    assert_int_equal(igea_stability_allan(100, y, 0, 2, tau, 0, 0, 0.683, dev, lo, NULL, NULL, cnt), -3);
    assert_int_equal(igea_stability_allan(100, y, 1, 0, tau, 0, 0, 0.683, dev, lo, NULL, NULL, cnt), -4);
    assert_int_equal(igea_stability_allan(100, y, 1, 2, NULL, 0, 0, 0.683, dev, lo, NULL, NULL, cnt), -5);
    assert_int_equal(igea_stability_allan(100, y, 1, 2, t_bad, 0, 0, 0.683, dev, lo, NULL, NULL, cnt), -5);
    assert_int_equal(igea_stability_allan(100, y, 1, 2, t_mod, 1, 0, 0.683, dev, lo, NULL, NULL, cnt), -5);
    assert_int_equal(igea_stability_allan(100, y, 1, 2, t_neg, 0, 0, 0.683, dev, lo, NULL, NULL, cnt), -5);
    assert_int_equal(igea_stability_allan(100, y, 1, 2, t_small, 0, 0, 0.683, dev, lo, NULL, NULL, cnt), -5);
    assert_int_equal(igea_stability_allan(100, y, 1, 2, tau, 3, 0, 0.683, dev, lo, NULL, NULL, cnt), -6);
    assert_int_equal(igea_stability_allan(100, y, 1, 2, tau, 0, 3, 0.683, dev, lo, NULL, NULL, cnt), -7);
    assert_int_equal(igea_stability_allan(100, y, 1, 2, tau, 0, 0, 1.0, dev, lo, NULL, NULL, cnt), -8);
    assert_int_equal(igea_stability_allan(100, y, 1, 2, tau, 0, 0, 0.683, NULL, lo, NULL, NULL, cnt), -9);
    y[50] = NAN;
    assert_int_equal(igea_stability_allan(100, y, 1, 2, tau, 0, 0, 0.683, dev, lo, NULL, NULL, cnt), IGEA_ENONFINITE);
    assert_true(all_sentinel(dev, 2) && all_sentinel(lo, 2) && cnt[0] == -3);
    /* the largest admissible taus */
    y[50] = 0.3;
    const double t_max[1] = {50};
    assert_int_equal(igea_stability_allan(100, y, 1, 1, t_max, 0, 0, 0.683, dev, lo, NULL, NULL, cnt), 0);
    assert_int_equal(cnt[0], 1);
    const double t_m34[1] = {34}, t_m33[1] = {33};
    assert_int_equal(igea_stability_allan(100, y, 1, 1, t_m34, 1, 0, 0.683, dev, NULL, NULL, NULL, cnt), -5);
    assert_int_equal(igea_stability_allan(100, y, 1, 1, t_m33, 1, 0, 0.683, dev, NULL, NULL, NULL, cnt), 0);
    assert_int_equal(cnt[0], 3);
}

static void test_octave_taus(void **state)
{
    double tau[40];
    int nt = -1;
    assert_int_equal(igea_stability_octave_taus(1000, 1.0, 0, 40, tau, &nt), 0);
    assert_int_equal(nt, 9);
    assert_close(tau[8], 256.0, 0);
    assert_int_equal(igea_stability_octave_taus(1000, 4.0, 1, 40, tau, &nt), 0);
    assert_int_equal(nt, 9); /* m = 256 <= (n + 1) / 3 */
    assert_close(tau[8], 64.0, 0);
    assert_int_equal(igea_stability_octave_taus(1024, 1.0, 2, 40, tau, &nt), 0);
    assert_int_equal(nt, 10); /* m = 512 gives 2 blocks */
    assert_int_equal(igea_stability_octave_taus(1024, 1.0, 2, 3, tau, &nt), 0);
    assert_int_equal(nt, 3);
    nt = -1;
    assert_int_equal(igea_stability_octave_taus(1, 1.0, 0, 40, tau, &nt), -1);
    assert_int_equal(igea_stability_octave_taus(10, 0.0, 0, 40, tau, &nt), -2);
    assert_int_equal(igea_stability_octave_taus(10, 1.0, 5, 40, tau, &nt), -3);
    assert_int_equal(igea_stability_octave_taus(10, 1.0, 0, 0, tau, &nt), -4);
    assert_int_equal(igea_stability_octave_taus(10, 1.0, 0, 40, NULL, &nt), -5);
    assert_int_equal(igea_stability_octave_taus(10, 1.0, 0, 40, tau, NULL), -6);
    assert_int_equal(nt, -1);
}

static void test_noise_id(void **state)
{
    double tau[16], s[16], out[IGEA_STABILITY_NOISEID_LEN];
    /* pure terms: exact */
    for (int j = 0; j < 16; j++)
        tau[j] = pow(2.0, j - 4);
    double N = 3e-3, K = 2e-5, Q = 1e-4;
    for (int j = 0; j < 16; j++)
        s[j] = N / sqrt(tau[j]);
    assert_int_equal(igea_stability_noise_id(16, tau, s, out), 0);
    assert_close(out[IGEA_STABILITY_NOISEID_N], N, 1e-13);
    assert_true(isnan(out[IGEA_STABILITY_NOISEID_K]) && isnan(out[IGEA_STABILITY_NOISEID_B]) && isnan(out[IGEA_STABILITY_NOISEID_Q]));
    for (int j = 0; j < 16; j++)
        s[j] = K * sqrt(tau[j] / 3.0);
    assert_int_equal(igea_stability_noise_id(16, tau, s, out), 0);
    assert_close(out[IGEA_STABILITY_NOISEID_K], K, 1e-13);
    for (int j = 0; j < 16; j++)
        s[j] = sqrt(3.0) * Q / tau[j];
    assert_int_equal(igea_stability_noise_id(16, tau, s, out), 0);
    assert_close(out[IGEA_STABILITY_NOISEID_Q], Q, 1e-13);
    /* a gyro curve: ARW + bias instability (flat part) + RRW */
    double B = 1e-4, Nn = 1e-3, Kk = 1e-7;
    for (int j = 0; j < 16; j++)
        tau[j] = pow(4.0, j - 2);
    for (int j = 0; j < 16; j++)
        s[j] = sqrt(Nn * Nn / tau[j] + 0.4412712 * B * B + Kk * Kk * tau[j] / 3.0);
    assert_int_equal(igea_stability_noise_id(16, tau, s, out), 0);
    assert_close(out[IGEA_STABILITY_NOISEID_N], Nn, 0.02);
    assert_close(out[IGEA_STABILITY_NOISEID_K], Kk, 0.10);
    assert_close(out[IGEA_STABILITY_NOISEID_B], B, 0.10);
    assert_true(out[IGEA_STABILITY_NOISEID_B] >= B); /* the minimum lies above B's floor */
    /* invalid */
    fill_sentinel(out, IGEA_STABILITY_NOISEID_LEN);
    double tb[3] = {1, 1, 2}, sb[3] = {1, 0, 1}, sn[3] = {1, NAN, 1};
    assert_int_equal(igea_stability_noise_id(1, tau, s, out), -1);
    assert_int_equal(igea_stability_noise_id(3, NULL, s, out), -2);
    assert_int_equal(igea_stability_noise_id(3, tb, s, out), -2);
    assert_int_equal(igea_stability_noise_id(3, tau, NULL, out), -3);
    assert_int_equal(igea_stability_noise_id(3, tau, sb, out), -3);
    assert_int_equal(igea_stability_noise_id(3, tau, s, NULL), -4);
    assert_int_equal(igea_stability_noise_id(3, tau, sn, out), IGEA_ENONFINITE);
    assert_true(all_sentinel(out, IGEA_STABILITY_NOISEID_LEN));
}

#ifndef OOM_DISABLED
static void test_oom(void **state)
{
    double y[1000];
    nbs1000(y);
    const double tau[3] = {1, 10, 100};
    for (int kind = 0; kind < 3; kind++) {
        double ref[3], dev[3], lo[3], edf[3];
        int cnt[3], st, k;
        assert_int_equal(igea_stability_allan(1000, y, 1, 3, tau, kind, IGEA_STABILITY_NOISE_AUTO, 0.9,
                                              ref, NULL, NULL, NULL, NULL), 0);
        for (k = 0;; k++) {
            fill_sentinel(dev, 3);
            fill_sentinel(lo, 3);
            fill_sentinel(edf, 3);
            cnt[0] = -5;
            oom_calls = 0;
            oom_fail_at = k;
            st = igea_stability_allan(1000, y, 1, 3, tau, kind, IGEA_STABILITY_NOISE_AUTO, 0.9, dev, lo,
                                      NULL, edf, cnt);
            oom_fail_at = -1;
            if (st != IGEA_ENOMEM)
                break;
            assert_true(all_sentinel(dev, 3) && all_sentinel(lo, 3) && all_sentinel(edf, 3));
            assert_int_equal(cnt[0], -5);
        }
        assert_int_equal(st, 0);
        assert_true(k >= 1);
        for (int j = 0; j < 3; j++)
            assert_close(dev[j], ref[j], 0);
    }
    double out[IGEA_STABILITY_BLOCK_LEN];
    int st, k;
    for (k = 0;; k++) {
        fill_sentinel(out, IGEA_STABILITY_BLOCK_LEN);
        oom_calls = 0;
        oom_fail_at = k;
        st = igea_stability_block(1000, y, 1.0, 100.0, out);
        oom_fail_at = -1;
        if (st != IGEA_ENOMEM)
            break;
        assert_true(all_sentinel(out, IGEA_STABILITY_BLOCK_LEN));
    }
    assert_int_equal(st, 0);
    assert_true(k >= 1);
}
#endif

/* ---- igea_stability_dev: Stable32's statistics ---- */

/* Frequency data y[n] -> n + 1 phase points x (x_0 = 0, tau0 = 1). */
static void to_phase_1(int n, const double *y, double *x)
{
    x[0] = 0.0;
    for (int k = 0; k < n; k++)
        x[k + 1] = x[k] + y[k];
}

static void test_dev_nbs(void **state)
{
    /* the NBS 1000-point set at tau = 1, 10, 100: Riley's test suite Table
     * III / NIST SP 1065 p. 108 (7 digits; TOTDEV "doubly reflected",
     * HTOTDEV as published, bias-corrected) and the Stable32 v1.60 runs
     * carried by allantools' tests/nbs14/test_nbs14_1000point.py (5 digits;
     * MTOTDEV, TTOTDEV without bias correction; THEO1 at m = 10, 100, 1000,
     * i.e. tau = 0.75 m) */
    static const struct {
        int kind;
        double v[3], tol;
    } ref[] = {
        {IGEA_STABILITY_ALLAN_ADEV, {2.922319e-01, 9.965736e-02, 3.897804e-02}, 2e-6},
        {IGEA_STABILITY_ALLAN_OADEV, {2.922319e-01, 9.159953e-02, 3.241343e-02}, 2e-6},
        {IGEA_STABILITY_ALLAN_MDEV, {2.922319e-01, 6.172376e-02, 2.170921e-02}, 2e-6},
        {IGEA_STABILITY_ALLAN_TDEV, {1.687202e-01, 3.563623e-01, 1.253382e+00}, 2e-6},
        {IGEA_STABILITY_ALLAN_HDEV, {2.943883e-01, 1.052754e-01, 3.910860e-02}, 2e-6},
        {IGEA_STABILITY_ALLAN_OHDEV, {2.943883e-01, 9.581083e-02, 3.237638e-02}, 2e-6},
        {IGEA_STABILITY_ALLAN_TOTDEV, {2.922319e-01, 9.134743e-02, 3.406530e-02}, 2e-6},
        {IGEA_STABILITY_ALLAN_HTOTDEV, {2.943883e-01, 9.614787e-02, 3.058103e-02}, 2e-6},
        {IGEA_STABILITY_ALLAN_MTOTDEV, {2.0664e-01, 5.5529e-02, 1.9547e-02}, 5e-5},
        {IGEA_STABILITY_ALLAN_TTOTDEV, {1.1930e-01, 3.2060e-01, 1.1285e+00}, 5e-5},
        {IGEA_STABILITY_ALLAN_THEO1, {1.0757e-01, 3.1789e-02, 5.0524e-03}, 5e-5},
    };
    double y[1000], x[1001];
    nbs1000(y);
    to_phase_1(1000, y, x);
    for (size_t r = 0; r < sizeof ref / sizeof ref[0]; r++) {
        int k = ref[r].kind, theo = k == IGEA_STABILITY_ALLAN_THEO1;
        const double tau[3] = {theo ? 7.5 : 1, theo ? 75 : 10, theo ? 750 : 100};
        for (int type = 0; type < 2; type++) {
            double dev[3], tu[3];
            int cnt[3], al[3];
            const double *data = type == IGEA_STABILITY_DATA_PHASE ? x : y;
            int n = type == IGEA_STABILITY_DATA_PHASE ? 1001 : 1000;
            assert_int_equal(igea_stability_dev(n, data, 1.0, type, 3, tau, k, IGEA_STABILITY_NOISE_AUTO,
                                                0.683, dev, NULL, NULL, NULL, al, cnt, tu), 0);
            for (int j = 0; j < 3; j++) {
                assert_close(dev[j], ref[r].v[j], ref[r].tol);
                assert_close(tu[j], tau[j], 1e-15);
                assert_true(al[j] >= -2 && al[j] <= 2);
            }
        }
    }
    /* term counts of SP 1065 (N = 1001 phase points, m = 10) */
    static const int kinds[6] = {IGEA_STABILITY_ALLAN_ADEV, IGEA_STABILITY_ALLAN_OADEV, IGEA_STABILITY_ALLAN_MDEV,
                                 IGEA_STABILITY_ALLAN_HDEV, IGEA_STABILITY_ALLAN_OHDEV, IGEA_STABILITY_ALLAN_TOTDEV};
    static const int want[6] = {99, 981, 972, 98, 971, 999};
    const double t10 = 10;
    for (int i = 0; i < 6; i++) {
        double dv;
        int c;
        assert_int_equal(igea_stability_dev(1000, y, 1.0, 0, 1, &t10, kinds[i], 0, 0.683, &dv, NULL, NULL,
                                            NULL, NULL, &c, NULL), 0);
        assert_int_equal(c, want[i]);
    }
}

static void test_dev_tie(void **state)
{
    /* hand-computed: x = 0 3 1 4 1 5 9 2 6, m = 2: ranges of the windows of
     * 3 points 3 3 3 4 8 7 7 (MTIE 8); x_{i+2} - x_i = 1 1 0 1 8 -3 -3
     * (TIERMS sqrt(85 / 7)) */
    const double x[9] = {0, 3, 1, 4, 1, 5, 9, 2, 6}, t2 = 2;
    double d;
    int c;
    assert_int_equal(igea_stability_dev(9, x, 1.0, 1, 1, &t2, IGEA_STABILITY_ALLAN_MTIE, 0, 0.683, &d, NULL,
                                        NULL, NULL, NULL, &c, NULL), 0);
    assert_close(d, 8.0, 0);
    assert_int_equal(c, 7);
    assert_int_equal(igea_stability_dev(9, x, 1.0, 1, 1, &t2, IGEA_STABILITY_ALLAN_TIERMS, 0, 0.683, &d, NULL,
                                        NULL, NULL, NULL, &c, NULL), 0);
    assert_close(d, sqrt(85.0 / 7.0), 1e-15);
    /* frequency data: the record as it is (a constant rate 2 at fs = 4 ->
     * x_{i+m} - x_i = 2 m / 4) */
    double y[20];
    for (int k = 0; k < 20; k++)
        y[k] = 2.0;
    const double t1 = 1.0; /* m = 4 */
    assert_int_equal(igea_stability_dev(20, y, 4.0, 0, 1, &t1, IGEA_STABILITY_ALLAN_MTIE, 0, 0.683, &d, NULL,
                                        NULL, NULL, NULL, &c, NULL), 0);
    assert_close(d, 2.0, 1e-15);
    assert_int_equal(c, 17);
}

static void test_dev_edf(void **state)
{
    /* Greenhall's EDF for the non-overlapping ADEV, N = 19983 phase points,
     * m = 2048, random-walk FM: 7.21 (Stable32's Min/Max Sigma ratios 0.816
     * and 1.416 at 68.27 %); white noise record, seed-independent (the EDF
     * depends on N, m and alpha only) */
    int n = 19982;
    double *y = malloc(sizeof(double) * n);
    for (int k = 0; k < n; k++)
        y[k] = sin(0.37 * k) + cos(1.1 * k * k);
    const double t = 2048, conf = 0.68268949213708585;
    double d, lo, hi, e;
    int al;
    assert_int_equal(igea_stability_dev(n, y, 1.0, 0, 1, &t, IGEA_STABILITY_ALLAN_ADEV, IGEA_STABILITY_NOISE_RWFM,
                                        conf, &d, &lo, &hi, &e, &al, NULL, NULL), 0);
    assert_close(e, 7.21, 2e-3);
    assert_close(lo / d, 0.816, 1e-3);
    assert_close(hi / d, 1.416, 1e-3);
    assert_int_equal(al, IGEA_STABILITY_NOISE_RWFM);
    double ql, qh;
    igea_stats_chi2_quantile(0.5 + conf / 2, e, &qh);
    igea_stats_chi2_quantile(0.5 - conf / 2, e, &ql);
    assert_close(lo, d * sqrt(e / qh), 1e-14);
    assert_close(hi, d * sqrt(e / ql), 1e-14);
    /* TOTDEV: SP 1065 Table 7, b N / m - c; MTOTDEV: Table 8 */
    const double t10 = 10;
    assert_int_equal(igea_stability_dev(1000, y, 1.0, 0, 1, &t10, IGEA_STABILITY_ALLAN_TOTDEV, IGEA_STABILITY_NOISE_FFM,
                                        0.9, &d, &lo, &hi, &e, NULL, NULL, NULL), 0);
    assert_close(e, 1.17 * 1001 / 10 - 0.22, 1e-14);
    assert_int_equal(igea_stability_dev(1000, y, 1.0, 0, 1, &t10, IGEA_STABILITY_ALLAN_MTOTDEV, IGEA_STABILITY_NOISE_WPM,
                                        0.9, &d, &lo, &hi, &e, NULL, NULL, NULL), 0);
    assert_close(e, 1.90 * 1001 / 10 - 2.1, 1e-14);
    /* THEO1: the EDF of Howe and Peppler (NIST SP 1065), r = 0.75 m, the
     * formula written out here: white FM, N = 1001, m = 10 (tau 7.5) */
    assert_int_equal(igea_stability_dev(1000, y, 1.0, 0, 1, &t10, IGEA_STABILITY_ALLAN_THEO1, 0, 0.9, &d, &lo,
                                        NULL, NULL, NULL, NULL, NULL), -6); /* m = 13 odd */
    const double t75 = 7.5;
    assert_int_equal(igea_stability_dev(1000, y, 1.0, 0, 1, &t75, IGEA_STABILITY_ALLAN_THEO1,
                                        IGEA_STABILITY_NOISE_WFM, 0.9, &d, &lo, &hi, &e, NULL, NULL, NULL), 0);
    {
        double N = 1001, r = 7.5;
        assert_close(e, ((4.1 * N + 0.8) / r - (3.1 * N + 6.5) / N) * pow(r, 1.5) / (pow(r, 1.5) + 5.2),
                     1e-13);
    }
    /* HTOTDEV, m = 20, flicker FM: (N / m) / (b0 + b1 m / N), (0.868, 1.140) */
    const double t20 = 20;
    assert_int_equal(igea_stability_dev(1000, y, 1.0, 0, 1, &t20, IGEA_STABILITY_ALLAN_HTOTDEV,
                                        IGEA_STABILITY_NOISE_FFM, 0.9, &d, &lo, &hi, &e, NULL, NULL, NULL), 0);
    assert_close(e, (1001.0 / 20) / (0.868 + 1.140 * 20 / 1001.0), 1e-13);
    /* no interval for MTIE and TIERMS: lo, hi, edf must be NULL */
    assert_int_equal(igea_stability_dev(1000, y, 1.0, 0, 1, &t10, IGEA_STABILITY_ALLAN_TIERMS, 0, 0.9, &d, &lo,
                                        NULL, NULL, NULL, NULL, NULL), -11);
    assert_int_equal(igea_stability_dev(1000, y, 1.0, 0, 1, &t10, IGEA_STABILITY_ALLAN_MTIE, 0, 0.9, &d, NULL,
                                        &hi, NULL, NULL, NULL, NULL), -12);
    assert_int_equal(igea_stability_dev(1000, y, 1.0, 0, 1, &t10, IGEA_STABILITY_ALLAN_MTIE, 0, 0.9, &d, NULL,
                                        NULL, &e, NULL, NULL, NULL), -13);
    free(y);
}

/* Power-law noise of exponent alpha (2, 0, -2) as frequency data. */
static void powerlaw(gsl_rng *r, int n, int alpha, double *y)
{
    double acc = 0, prev = gsl_ran_gaussian(r, 1.0);
    for (int k = 0; k < n; k++) {
        double w = gsl_ran_gaussian(r, 1.0);
        acc += w;
        y[k] = alpha == 2 ? w - prev : alpha == 0 ? w : acc;
        prev = w;
    }
}

static void test_dev_noise_id(void **state)
{
    /* white PM, white FM and random-walk FM identified at m = 1 .. 64 (at
     * least 30 decimated points: the lag-1 method) in 20 records each;
     * rate of a wrong type below 10 % (Riley and Greenhall report the lag-1
     * method near-perfect at these lengths) */
    int n = 4096, bad = 0, tot = 0;
    double *y = malloc(sizeof(double) * n);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 11);
    const double taus[7] = {1, 2, 4, 8, 16, 32, 64};
    static const int types[3] = {2, 0, -2};
    for (int t = 0; t < 3; t++)
        for (int rep = 0; rep < 20; rep++) {
            powerlaw(r, n, types[t], y);
            double d[7];
            int al[7];
            assert_int_equal(igea_stability_dev(n, y, 1.0, 0, 7, taus, IGEA_STABILITY_ALLAN_OADEV,
                                                IGEA_STABILITY_NOISE_AUTO, 0.683, d, NULL, NULL, NULL, al,
                                                NULL, NULL), 0);
            for (int j = 0; j < 7; j++, tot++)
                bad += al[j] != types[t];
            /* each tau on its own gives the same type as in the list */
            for (int j = 0; j < 7; j += 3) {
                double d1;
                int a1;
                assert_int_equal(igea_stability_dev(n, y, 1.0, 0, 1, taus + j, IGEA_STABILITY_ALLAN_OADEV,
                                                    IGEA_STABILITY_NOISE_AUTO, 0.683, &d1, NULL, NULL, NULL, &a1,
                                                    NULL, NULL), 0);
                assert_int_equal(a1, al[j]);
                assert_close(d1, d[j], 0);
            }
        }
    assert_true(bad < tot / 10);
    /* B1 branch (fewer than 30 points): white FM at m = 256 (16 averages),
     * 40 records, B1 between its white-FM neighbours in most of them */
    int ok = 0;
    const double t256 = 256;
    for (int rep = 0; rep < 40; rep++) {
        powerlaw(r, n, 0, y);
        double d;
        int a;
        assert_int_equal(igea_stability_dev(n, y, 1.0, 0, 1, &t256, IGEA_STABILITY_ALLAN_OADEV,
                                            IGEA_STABILITY_NOISE_AUTO, 0.683, &d, NULL, NULL, NULL, &a, NULL,
                                            NULL), 0);
        ok += a == 0;
    }
    assert_true(ok >= 20);
    gsl_rng_free(r);
    free(y);
}

static void test_dev_args(void **state)
{
    double y[100], d[2], lo[2];
    int al[2];
    for (int k = 0; k < 100; k++)
        y[k] = sin(k);
    const double tau[2] = {1, 10}, tbig[1] = {50};
    const int K = IGEA_STABILITY_ALLAN_OADEV;
    fill_sentinel(d, 2);
    fill_sentinel(lo, 2);
    al[0] = -7;
    assert_int_equal(igea_stability_dev(1, y, 1, 0, 2, tau, K, 0, 0.9, d, lo, NULL, NULL, al, NULL, NULL), -1);
    assert_int_equal(igea_stability_dev(100, NULL, 1, 0, 2, tau, K, 0, 0.9, d, lo, NULL, NULL, al, NULL, NULL), -2);
    assert_int_equal(igea_stability_dev(100, y, 0, 0, 2, tau, K, 0, 0.9, d, lo, NULL, NULL, al, NULL, NULL), -3);
    assert_int_equal(igea_stability_dev(100, y, 1, 2, 2, tau, K, 0, 0.9, d, lo, NULL, NULL, al, NULL, NULL), -4);
    assert_int_equal(igea_stability_dev(100, y, 1, 0, 0, tau, K, 0, 0.9, d, lo, NULL, NULL, al, NULL, NULL), -5);
    assert_int_equal(igea_stability_dev(100, y, 1, 0, 2, NULL, K, 0, 0.9, d, lo, NULL, NULL, al, NULL, NULL), -6);
    assert_int_equal(igea_stability_dev(100, y, 1, 0, 1, tbig, K, 0, 0.9, d, lo, NULL, NULL, al, NULL, NULL), 0);
    assert_int_equal(igea_stability_dev(100, y, 1, 1, 1, tbig, K, 0, 0.9, d, lo, NULL, NULL, al, NULL, NULL), -6);
    assert_int_equal(igea_stability_dev(100, y, 1, 0, 2, tau, 2, 0, 0.9, d, lo, NULL, NULL, al, NULL, NULL), -7);
    assert_int_equal(igea_stability_dev(100, y, 1, 0, 2, tau, 18, 0, 0.9, d, lo, NULL, NULL, al, NULL, NULL), -7);
    /* THEOBR and THEOH need N >= 90 phase points (TheoBR's factor) */
    const double t3 = 3;
    assert_int_equal(igea_stability_dev(88, y, 1, 0, 1, &t3, IGEA_STABILITY_ALLAN_THEOBR, 0, 0.9, d, lo, NULL,
                                        NULL, al, NULL, NULL), -1);
    assert_int_equal(igea_stability_dev(89, y, 1, 1, 1, &t3, IGEA_STABILITY_ALLAN_THEOH, 0, 0.9, d, lo, NULL,
                                        NULL, al, NULL, NULL), -1);
    assert_int_equal(igea_stability_dev(90, y, 1, 1, 1, &t3, IGEA_STABILITY_ALLAN_THEOH, 0, 0.9, d, lo, NULL,
                                        NULL, al, NULL, NULL), 0);
    assert_int_equal(igea_stability_dev(100, y, 1, 0, 2, tau, K, 5, 0.9, d, lo, NULL, NULL, al, NULL, NULL), -8);
    assert_int_equal(igea_stability_dev(100, y, 1, 0, 2, tau, K, 0, 1.0, d, lo, NULL, NULL, al, NULL, NULL), -9);
    assert_int_equal(igea_stability_dev(100, y, 1, 0, 2, tau, K, 0, 0.9, NULL, lo, NULL, NULL, al, NULL, NULL), -10);
    fill_sentinel(d, 2);
    fill_sentinel(lo, 2);
    al[0] = -7;
    /* an infinity is refused; a NaN is a gap for the Allan and Hadamard
     * kinds only (tests/python/test_stability_dev.py checks the gap values) */
    y[3] = INFINITY;
    assert_int_equal(igea_stability_dev(100, y, 1, 0, 2, tau, K, 0, 0.9, d, lo, NULL, NULL, al, NULL, NULL),
                     IGEA_ENONFINITE);
    y[3] = NAN;
    assert_int_equal(igea_stability_dev(100, y, 1, 0, 2, tau, IGEA_STABILITY_ALLAN_TOTDEV, 0, 0.9, d, lo,
                                        NULL, NULL, al, NULL, NULL), IGEA_ENONFINITE);
    assert_true(all_sentinel(d, 2) && all_sentinel(lo, 2) && al[0] == -7);
    int cg[2];
    assert_int_equal(igea_stability_dev(100, y, 1, 0, 2, tau, IGEA_STABILITY_ALLAN_OADEV, 0, 0.9, d, lo,
                                        NULL, NULL, al, cg, NULL), 0);
    assert_true(isfinite(d[0]) && isfinite(d[1]) && lo[0] < d[0]);
    assert_int_equal(cg[0], 101 - 2 - 2); /* m = 1: y_3 is in the terms at i = 2 and 3 */
    for (int k = 0; k < 100; k++)
        y[k] = NAN;
    assert_int_equal(igea_stability_dev(100, y, 1, 0, 2, tau, IGEA_STABILITY_ALLAN_OADEV, 0, 0.9, d, lo,
                                        NULL, NULL, al, cg, NULL), IGEA_ENONFINITE);
    /* a linear phase (constant frequency) has zero Allan deviation, and the
     * quadratic phase of a frequency ramp R gives R tau / sqrt 2 */
    double x[200];
    for (int k = 0; k < 200; k++)
        x[k] = 3e-3 * k * k / 2.0;
    const double t5 = 5;
    assert_int_equal(igea_stability_dev(200, x, 1, 1, 1, &t5, K, 0, 0.9, d, NULL, NULL, NULL, NULL, NULL, NULL), 0);
    assert_close(d[0], 3e-3 * 5 / sqrt(2.0), 1e-11);
}

static void test_dev_taus(void **state)
{
    double tau[64];
    int nt = -1;
    assert_int_equal(igea_stability_taus(1000, 1.0, 0, IGEA_STABILITY_ALLAN_OADEV, IGEA_STABILITY_TAUS_OCTAVE,
                                         64, tau, &nt), 0);
    assert_int_equal(nt, 9); /* m = 256: N - 2m = 489 */
    assert_int_equal(igea_stability_taus(1000, 1.0, 0, IGEA_STABILITY_ALLAN_MDEV, IGEA_STABILITY_TAUS_DECADE,
                                         64, tau, &nt), 0);
    assert_int_equal(nt, 8); /* 1 2 4 10 20 40 100 200 (m <= 333) */
    assert_close(tau[7], 200.0, 0);
    assert_int_equal(igea_stability_taus(1000, 2.0, 1, IGEA_STABILITY_ALLAN_THEO1, IGEA_STABILITY_TAUS_ALL, 64,
                                         tau, &nt), 0);
    assert_int_equal(nt, 64);
    assert_close(tau[1], 0.75 * 4 / 2.0, 1e-15);
    assert_int_equal(igea_stability_taus(1000, 1.0, 1, IGEA_STABILITY_ALLAN_OVERLAPPING,
                                         IGEA_STABILITY_TAUS_OCTAVE, 64, tau, &nt), 0);
    assert_int_equal(nt, 0);
    assert_int_equal(igea_stability_taus(1, 1.0, 0, 4, 0, 64, tau, &nt), -1);
    assert_int_equal(igea_stability_taus(10, 0.0, 0, 4, 0, 64, tau, &nt), -2);
    assert_int_equal(igea_stability_taus(10, 1.0, 3, 4, 0, 64, tau, &nt), -3);
    assert_int_equal(igea_stability_taus(10, 1.0, 0, 18, 0, 64, tau, &nt), -4);
    /* THEOH: octave Allan taus below the switch k = 128 (0.2 (N - 1) = 200),
     * then Theo taus 0.75 m from m = 2 ceil(128 / 1.5) = 172 */
    assert_int_equal(igea_stability_taus(1000, 1.0, 0, IGEA_STABILITY_ALLAN_THEOH, IGEA_STABILITY_TAUS_OCTAVE,
                                         64, tau, &nt), 0);
    assert_int_equal(nt, 10); /* 1 .. 64, then m = 172, 344, 688 */
    assert_close(tau[6], 64.0, 0);
    assert_close(tau[7], 0.75 * 172, 1e-15);
    assert_close(tau[9], 0.75 * 688, 1e-15);
    assert_int_equal(igea_stability_taus(80, 1.0, 1, IGEA_STABILITY_ALLAN_THEOBR, IGEA_STABILITY_TAUS_OCTAVE,
                                         64, tau, &nt), 0);
    assert_int_equal(nt, 0); /* fewer than 90 points */
    assert_int_equal(igea_stability_taus(10, 1.0, 0, 4, 3, 64, tau, &nt), -5);
    assert_int_equal(igea_stability_taus(10, 1.0, 0, 4, 0, 0, tau, &nt), -6);
    assert_int_equal(igea_stability_taus(10, 1.0, 0, 4, 0, 64, NULL, &nt), -7);
    assert_int_equal(igea_stability_taus(10, 1.0, 0, 4, 0, 64, tau, NULL), -8);
}

/* The stream: argument checks, the end of the record, and results equal to
 * the whole-record call bit for bit (tests/python/test_stability_stream.py
 * covers every kind and piece size). */
static void test_stream(void **state)
{
    double y[2000], tau[16], dev[16], ref[16], lo[16], b[IGEA_STABILITY_BLOCK_LEN];
    int nt = -1, cnt[16];
    for (int k = 0; k < 2000; k++)
        y[k] = sin(0.37 * k) + 0.2 * sin(0.011 * k * k);
    igea_stability_stream *h = NULL;
    const double t3[3] = {0.1, 1.0, 5.0};
    assert_int_equal(igea_stability_stream_create(0, 0, 0, 0, 0.683, 0, NULL, 0, 0, &h), -1);
    assert_int_equal(igea_stability_stream_create(10, 1, 0, 0, 0.683, 0, NULL, 0, 0, &h), -2);
    assert_int_equal(igea_stability_stream_create(10, 0, 9, 0, 0.683, 0, NULL, 0, 0, &h), -3);
    assert_int_equal(igea_stability_stream_create(10, 0, 4, 99, 0.683, 0, NULL, 0, 0, &h), -4);
    assert_int_equal(igea_stability_stream_create(10, 0, 0, 0, 1.0, 0, NULL, 0, 0, &h), -5);
    assert_int_equal(igea_stability_stream_create(10, 0, 0, 0, 0.683, -1, NULL, 0, 0, &h), -6);
    assert_int_equal(igea_stability_stream_create(10, 0, 0, 0, 0.683, 3, NULL, 0, 0, &h), -7);
    assert_int_equal(igea_stability_stream_create(10, 0, 0, 0, 0.683, 0, NULL, 2, 0, &h), -8);
    assert_int_equal(igea_stability_stream_create(10, 0, 0, 0, 0.683, 0, NULL, 0, -1, &h), -9);
    assert_int_equal(igea_stability_stream_create(10, 0, 0, 0, 0.683, 0, NULL, 0, 0, NULL), -10);
    assert_null(h);
    assert_int_equal(igea_stability_stream_create(10, 0, IGEA_STABILITY_ALLAN_OVERLAPPING,
                                                  IGEA_STABILITY_NOISE_AUTO, 0.683, 3, t3, 0, 20.0, &h),
                     0);
    for (int k = 0; k < 2000; k += 300)
        assert_int_equal(igea_stability_stream_feed(h, k + 300 <= 2000 ? 300 : 2000 - k, y + k), 0);
    double ns = 0;
    assert_int_equal(igea_stability_stream_samples(h, &ns), 0);
    assert_true(ns == 2000);
    assert_int_equal(igea_stability_stream_feed(h, -1, y), -2);
    assert_int_equal(igea_stability_stream_feed(h, 3, NULL), -3);
    assert_int_equal(igea_stability_stream_result(h, 2, &nt, tau, dev, NULL, NULL, NULL, NULL, cnt, b),
                     IGEA_EEMPTY); /* 3 taus do not fit in 2 */
    assert_int_equal(igea_stability_stream_result(h, 16, &nt, tau, dev, lo, NULL, NULL, NULL, cnt, b), 0);
    assert_int_equal(nt, 3);
    assert_int_equal(igea_stability_stream_feed(h, 1, y), IGEA_EEMPTY); /* ended */
    assert_int_equal(igea_stability_allan(2000, y, 10, 3, t3, IGEA_STABILITY_ALLAN_OVERLAPPING,
                                          IGEA_STABILITY_NOISE_AUTO, 0.683, ref, NULL, NULL, NULL, NULL),
                     0);
    for (int j = 0; j < 3; j++)
        assert_true(dev[j] == ref[j] && lo[j] < dev[j]);
    double blk[IGEA_STABILITY_BLOCK_LEN];
    assert_int_equal(igea_stability_block(2000, y, 10, 20.0, blk), 0);
    assert_memory_equal(b, blk, sizeof blk);
    igea_stability_stream_free(h);
    igea_stability_stream_free(NULL);
}


/* Long lags (beyond the pass's small ring of 256 blocks: the running sums of
 * the raw values' differences from exact anchors, on the block grid and
 * off it) and short ones: the whole-record calls equal the stream bit for
 * bit for any piece size, every Allan and Hadamard kind, both data types,
 * noise type given and identified (a white record, and a random walk whose
 * shortest taus ask for their means' differences); the overlapping and
 * modified deviations equal sums of the definitions in long double. */
static void stream_all(int n, const double *v, double fs, int dt, int kind, int noise, int nt,
                       const double *tau, int piece, double *out)
{
    igea_stability_stream *h = NULL;
    int k = -1, cnt[8], al[8];
    assert_int_equal(igea_stability_stream_create(fs, dt, kind, noise, 0.683, nt, tau, 0, 0.0, &h), 0);
    for (int i = 0; i < n; i += piece)
        assert_int_equal(igea_stability_stream_feed(h, i + piece <= n ? piece : n - i, v + i), 0);
    double t[8];
    assert_int_equal(igea_stability_stream_result(h, 8, &k, t, out, out + 8, out + 16, out + 24, al,
                                                  cnt, NULL),
                     0);
    assert_int_equal(k, nt);
    for (int j = 0; j < nt; j++)
        out[32 + j] = cnt[j];
    igea_stability_stream_free(h);
}

static long double ld_oadev(int n, const double *y, long m, int modified)
{
    long double mu = 0, *X = malloc(sizeof(long double) * ((size_t)n + 2));
    for (int i = 0; i < n; i++)
        mu += y[i];
    mu /= n;
    X[0] = 0;
    for (int i = 0; i < n; i++)
        X[i + 1] = X[i] + ((long double)y[i] - mu);
    long double s = 0;
    long M = 0;
    if (!modified) {
        for (long e = 2 * m; e <= n; e++, M++) {
            long double d = X[e] - 2 * X[e - m] + X[e - 2 * m];
            s += d * d;
        }
        free(X);
        return sqrtl(s / (2.0L * M * m * m));
    }
    long double *W = malloc(sizeof(long double) * ((size_t)n + 3));
    W[0] = 0;
    for (int i = 0; i <= n; i++)
        W[i + 1] = W[i] + X[i];
    for (long e = 3 * m; e <= n + 1; e++, M++) {
        long double d = W[e] - 3 * W[e - m] + 3 * W[e - 2 * m] - W[e - 3 * m];
        s += d * d;
    }
    free(X);
    free(W);
    return sqrtl(s / (2.0L * M * m * m * m * m));
}

static void test_long_lags(void **state)
{
    const int n = 420000;
    double *y = malloc(sizeof(double) * n), *x = malloc(sizeof(double) * n);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 17);
    /* m = 1, 3, 1000, 4096, 100000 (off the grid, long for the modified
     * kinds), 131072 (on the grid, long), 150000 (off the grid, long) */
    const double tau[7] = {1, 3, 1000, 4096, 100000, 131072, 150000};
    static const int pieces[3] = {1, 1000, 65536};
    for (int rec = 0; rec < 2; rec++) {
        double rw = 0, ph = 0;
        for (int i = 0; i < n; i++) {
            rw += gsl_ran_gaussian(r, rec ? 1.0 : 1e-3);
            y[i] = 1e6 + (rec ? 0.0 : gsl_ran_gaussian(r, 1.0)) + rw;
            x[i] = (ph += y[i] - 1e6) * 1e-3;
        }
        for (int kind = IGEA_STABILITY_ALLAN_OVERLAPPING; kind <= IGEA_STABILITY_ALLAN_NONOVERLAPPING; kind++)
            for (int noise = 0; noise < 2; noise++) {
                int nz = noise ? IGEA_STABILITY_NOISE_AUTO : IGEA_STABILITY_NOISE_WFM, nt = 7;
                if (kind == IGEA_STABILITY_ALLAN_OVERLAPPING)
                    nt = 7;
                else if (kind == IGEA_STABILITY_ALLAN_MODIFIED)
                    nt = 6; /* 3 m <= n */
                double ref[40], got[40];
                int cnt[8];
                assert_int_equal(igea_stability_allan(n, y, 1.0, nt, tau, kind, nz, 0.683, ref, ref + 8,
                                                      ref + 16, ref + 24, cnt),
                                 0);
                for (int j = 0; j < nt; j++)
                    ref[32 + j] = cnt[j];
                for (int pi = 0; pi < 3; pi++) {
                    if (pieces[pi] == 1 && (rec || noise))
                        continue;
                    stream_all(n, y, 1.0, 0, kind, nz, nt, tau, pieces[pi], got);
                    for (int j = 0; j < nt; j++)
                        for (int f = 0; f < 5; f++)
                            assert_true(got[8 * f + j] == ref[8 * f + j]);
                }
                if (kind == IGEA_STABILITY_ALLAN_NONOVERLAPPING)
                    continue;
                for (int j = 0; j < nt; j++) /* the modified kinds' short taus on a rate
                                              * that wanders: the running sums' magnitude
                                              * (docs/stability.md, "Precision") */
                    assert_close(ref[j], (double)ld_oadev(n, y, lround(tau[j]), kind),
                                 rec && kind == IGEA_STABILITY_ALLAN_MODIFIED && tau[j] < 10 ? 1e-8 : 1e-12);
            }
        for (int kind = IGEA_STABILITY_ALLAN_ADEV; kind <= IGEA_STABILITY_ALLAN_OHDEV; kind++)
            for (int dt = 0; dt < 2; dt++) {
                const double *v = dt ? x : y;
                int nt = kind == IGEA_STABILITY_ALLAN_ADEV || kind == IGEA_STABILITY_ALLAN_OADEV ? 7 : 6;
                double ref[40], got[40], lo[8], hi[8], e[8];
                int cnt[8];
                assert_int_equal(igea_stability_dev(n, v, 1.0, dt, nt, tau, kind, IGEA_STABILITY_NOISE_FFM,
                                                    0.683, ref, lo, hi, e, NULL, cnt, NULL),
                                 0);
                stream_all(n, v, 1.0, dt, kind, IGEA_STABILITY_NOISE_FFM, nt, tau, 1000, got);
                for (int j = 0; j < nt; j++)
                    assert_true(got[j] == ref[j] && got[8 + j] == lo[j] && got[16 + j] == hi[j] &&
                                got[24 + j] == e[j] && got[32 + j] == cnt[j]);
            }
    }
    gsl_rng_free(r);
    free(y);
    free(x);
}

/* v[n] written to a temporary file as column col of cols (C order: the
 * row's values side by side; fortran: the columns one after the other)
 * after hdr bytes of zeros; the descriptor, the file unlinked. */
static int source_file(const double *v, int n, int hdr, int cols, int col, int fortran)
{
    char path[] = "/tmp/igea_srcXXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    unlink(path);
    size_t len = (size_t)hdr + (size_t)n * cols * sizeof(double);
    unsigned char *b = calloc(1, len);
    for (int i = 0; i < n; i++)
        for (int c = 0; c < cols; c++) {
            double x = c == col ? v[i] : -1.0 - i - c;
            size_t at = fortran ? (size_t)c * n + i : (size_t)i * cols + c;
            memcpy(b + hdr + at * sizeof(double), &x, sizeof x);
        }
    assert_int_equal(write(fd, b, len), (ssize_t)len);
    free(b);
    return fd;
}

/* A stream with a source of ring blocks over fd (offset, stride), fed in
 * pieces: its results (dev, lo, hi, edf, count) into out[40]; the status
 * of the first failing call. */
static int stream_src(int n, const double *v, int dt, int kind, int noise, int nt,
                      const double *tau, int fd, double off, int stride, long ring, int piece,
                      double *out, int modify_at, int truncate_at)
{
    igea_stability_stream *h = NULL;
    int k = -1, cnt[8], al[8], st = 0;
    assert_int_equal(igea_stability_stream_create(1.0, dt, kind, noise, 0.683, nt, tau, 0, 0.0, &h), 0);
    assert_int_equal(igea__stability_stream_source_ring(h, fd, off, stride, ring), 0);
    for (int i = 0; i < n && !st; i += piece) {
        if (modify_at >= 0 && i == 0) { /* the file differs from the values fed */
            double x = v[modify_at] + 1.0;
            assert_int_equal(pwrite(fd, &x, sizeof x, (off_t)(off + (double)modify_at * stride)),
                             (ssize_t)sizeof x);
        }
        if (truncate_at >= 0 && i == 0)
            assert_int_equal(ftruncate(fd, (off_t)(off + (double)truncate_at * stride)), 0);
        st = igea_stability_stream_feed(h, i + piece <= n ? piece : n - i, v + i);
    }
    double t[8];
    int st2 = igea_stability_stream_result(h, 8, &k, t, out, out + 8, out + 16, out + 24, al,
                                           cnt, NULL);
    if (!st && !st2) {
        assert_int_equal(k, nt);
        for (int j = 0; j < nt; j++)
            out[32 + j] = cnt[j];
    }
    if (st) /* a failed stream stays failed */
        assert_int_equal(st2, st);
    igea_stability_stream_free(h);
    return st ? st : st2;
}

/* The stream reading its long lags back from a file (the smallest ring, 72 blocks,
 * every lag beyond it read back): the whole-record results bit for bit,
 * for every Allan and Hadamard kind, both data types, lags on the block
 * grid and off it, the record alone in its file or a column of a table in
 * either order behind a header; a value changed in the file, a file cut
 * short, a wrong stride: IGEA_EREAD, never other values. */
static void test_stream_source(void **state)
{
    (void)state;
    const int n = 420000;
    double *y = malloc(sizeof(double) * n), *x = malloc(sizeof(double) * n);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 29);
    double rw = 0, ph = 0;
    for (int i = 0; i < n; i++) {
        rw += gsl_ran_gaussian(r, 1e-2);
        y[i] = 3.0 + gsl_ran_gaussian(r, 1.0) + rw;
        x[i] = (ph += y[i] - 3.0) * 1e-3;
    }
    /* m = 1, 3, 1000 (the pass's small ring), 131072 (long, on the block
     * grid), 100000, 150000 (long, off it) */
    const double tau[6] = {1, 3, 1000, 100000, 131072, 150000};
    static const int lay[4][4] = {{0, 1, 0, 0}, {56, 1, 0, 0}, {128, 3, 1, 0}, {64, 2, 1, 1}};
    for (int L = 0; L < 4; L++)
        for (int dt = 0; dt < 2; dt++) {
            const double *v = dt ? x : y;
            int hdr = lay[L][0], cols = lay[L][1], col = lay[L][2], fo = lay[L][3];
            int fd = source_file(v, n, hdr, cols, col, fo);
            double off = hdr + 8.0 * col * (fo ? n : 1);
            int stride = fo ? 8 : 8 * cols;
            int k0 = dt ? IGEA_STABILITY_ALLAN_ADEV : IGEA_STABILITY_ALLAN_OVERLAPPING;
            int k1 = dt ? IGEA_STABILITY_ALLAN_OHDEV : IGEA_STABILITY_ALLAN_OHDEV;
            for (int kind = k0; kind <= k1; kind++) {
                int rate = kind <= IGEA_STABILITY_ALLAN_NONOVERLAPPING;
                int nt = kind == IGEA_STABILITY_ALLAN_ADEV || kind == IGEA_STABILITY_ALLAN_OADEV ||
                                 kind == IGEA_STABILITY_ALLAN_OVERLAPPING ||
                                 kind == IGEA_STABILITY_ALLAN_NONOVERLAPPING
                             ? 6 : 5;
                int nz = rate && L % 2 ? IGEA_STABILITY_NOISE_AUTO : IGEA_STABILITY_NOISE_WFM;
                double ref[40], got[40], lo[8], hi[8], e[8];
                int cnt[8];
                if (rate)
                    assert_int_equal(igea_stability_allan(n, v, 1.0, nt, tau, kind, nz, 0.683, ref,
                                                          lo, hi, e, cnt),
                                     0);
                else
                    assert_int_equal(igea_stability_dev(n, v, 1.0, dt, nt, tau, kind, nz, 0.683, ref,
                                                        lo, hi, e, NULL, cnt, NULL),
                                     0);
                assert_int_equal(stream_src(n, v, dt, kind, nz, nt, tau, fd, off, stride, 8,
                                            L == 2 ? 777 : 4096, got, -1, -1),
                                 0);
                for (int j = 0; j < nt; j++)
                    assert_true(got[j] == ref[j] && got[8 + j] == lo[j] && got[16 + j] == hi[j] &&
                                got[24 + j] == e[j] && got[32 + j] == cnt[j]);
            }
            if (L == 1 && dt == 0) {
                double got[40];
                /* a value in the file other than the one fed (the file changed) */
                assert_int_equal(stream_src(n, v, 0, IGEA_STABILITY_ALLAN_MODIFIED,
                                            IGEA_STABILITY_NOISE_WFM, 5, tau, fd, off, stride, 8,
                                            1000, got, 5, -1),
                                 IGEA_EREAD);
                double back = v[5]; /* put back: the file is the record again */
                assert_int_equal(pwrite(fd, &back, 8, (off_t)(off + 40)), 8);
                /* a wrong stride: other values */
                assert_int_equal(stream_src(n, v, 0, IGEA_STABILITY_ALLAN_OVERLAPPING,
                                            IGEA_STABILITY_NOISE_WFM, 6, tau, fd, off, 16, 8, 1000,
                                            got, -1, -1),
                                 IGEA_EREAD);
                /* the file cut short */
                assert_int_equal(stream_src(n, v, 0, IGEA_STABILITY_ALLAN_OVERLAPPING,
                                            IGEA_STABILITY_NOISE_WFM, 6, tau, fd, off, stride, 8,
                                            1000, got, -1, 3000),
                                 IGEA_EREAD);
            }
            close(fd);
        }
    /* arguments; a stream whose lags stay in the ring never reads */
    igea_stability_stream *h = NULL;
    assert_int_equal(igea_stability_stream_source(NULL, 0, 0, 8), -1);
    assert_int_equal(igea_stability_stream_create(1.0, 0, IGEA_STABILITY_ALLAN_OVERLAPPING,
                                                  IGEA_STABILITY_NOISE_WFM, 0.683, 3, tau, 0, 0, &h),
                     0);
    assert_int_equal(igea_stability_stream_source(h, -1, 0, 8), -2);
    assert_int_equal(igea_stability_stream_source(h, 0, -8, 8), -3);
    assert_int_equal(igea_stability_stream_source(h, 0, 0.5, 8), -3);
    assert_int_equal(igea_stability_stream_source(h, 0, 0, 4), -4);
    assert_int_equal(igea_stability_stream_source(h, 0, 0, 131080), -4);
    int nul = open("/dev/null", O_RDONLY);
    assert_int_equal(igea_stability_stream_source(h, nul, 0, 8), 0);
    assert_int_equal(igea_stability_stream_feed(h, n, y), 0);
    assert_int_equal(igea_stability_stream_source(h, nul, 0, 8), -1); /* after a feed */
    double d[8], ref[8];
    int k;
    assert_int_equal(igea_stability_stream_result(h, 8, &k, NULL, d, NULL, NULL, NULL, NULL, NULL,
                                                  NULL),
                     -4);
    double t[8];
    assert_int_equal(igea_stability_stream_result(h, 8, &k, t, d, NULL, NULL, NULL, NULL, NULL,
                                                  NULL),
                     0);
    assert_int_equal(igea_stability_allan(n, y, 1.0, 3, tau, IGEA_STABILITY_ALLAN_OVERLAPPING,
                                          IGEA_STABILITY_NOISE_WFM, 0.683, ref, NULL, NULL, NULL,
                                          NULL),
                     0);
    for (int j = 0; j < 3; j++)
        assert_true(d[j] == ref[j]);
    close(nul);
    igea_stability_stream_free(h);
    gsl_rng_free(r);
    free(y);
    free(x);
}

#ifndef OOM_DISABLED
/* Allocation failures in the stream: refused cleanly, later calls too. */
static void test_stream_oom(void **state)
{
    double y[3000], tau[16], dev[16];
    int nt;
    for (int k = 0; k < 3000; k++)
        y[k] = cos(0.2 * k) + 1e-3 * k;
    for (int k = 0; k < 40; k++) {
        igea_stability_stream *h = NULL;
        OOM_ARM(k);
        int st = igea_stability_stream_create(1, 0, IGEA_STABILITY_ALLAN_MODIFIED, IGEA_STABILITY_NOISE_AUTO,
                                              0.683, 0, NULL, 0, 5.0, &h), fed = 0;
        for (int i = 0; !st && i < 3000; i += 500)
            st = igea_stability_stream_feed(h, 500, y + i);
        if (!st) {
            fed = 1;
            fill_sentinel(dev, 16);
            st = igea_stability_stream_result(h, 16, &nt, tau, dev, NULL, NULL, NULL, NULL, NULL, NULL);
            if (st)
                assert_true(all_sentinel(dev, 16));
        }
        OOM_DISARM();
        assert_true(st == 0 || st == IGEA_ENOMEM);
        if (st && h && !fed) /* a stream whose feed failed stays failed */
            assert_int_equal(igea_stability_stream_feed(h, 1, y), IGEA_ENOMEM);
        assert_true(st || nt >= 5);
        igea_stability_stream_free(h);
    }
}
#endif

#ifndef OOM_DISABLED
static void test_dev_oom(void **state)
{
    double y[300], d[2], lo[2];
    for (int k = 0; k < 300; k++)
        y[k] = sin(0.3 * k) + 0.01 * k;
    const double tau[2] = {2, 8};
    static const int kinds[3] = {IGEA_STABILITY_ALLAN_MTOTDEV, IGEA_STABILITY_ALLAN_HTOTDEV, IGEA_STABILITY_ALLAN_MTIE};
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 12; k++) {
            fill_sentinel(d, 2);
            OOM_ARM(k);
            int st = igea_stability_dev(300, y, 1, 0, 2, tau, kinds[i], IGEA_STABILITY_NOISE_AUTO, 0.9, d,
                                        i == 0 ? lo : NULL, NULL, NULL, NULL, NULL, NULL);
            OOM_DISARM();
            assert_true(st == 0 || st == IGEA_ENOMEM);
            if (st)
                assert_true(all_sentinel(d, 2));
        }
}
#endif

static void test_fit(void **state)
{
    /* exact IEEE 952 curves (Annex C): the five coefficients back to 1e-8;
     * one term alone: the others zero and not supported */
    double tau[20], ad[20], edf[20], c[5], se[5], chi2 = -1;
    int sup[5];
    const double Q = 1e-4, N = 3e-3, B = 2e-4, K = 5e-6, R = 1e-8, pi = 3.14159265358979323846;
    for (int j = 0; j < 20; j++) {
        double t = pow(2.0, j - 6);
        tau[j] = t;
        ad[j] = sqrt(3 * Q * Q / (t * t) + N * N / t + 2 * log(2.0) / pi * B * B + K * K * t / 3 +
                     R * R * t * t / 2);
        edf[j] = 50.0;
    }
    assert_int_equal(igea_stability_fit(20, tau, ad, edf, c, se, sup, &chi2), 0);
    const double want[5] = {Q, N, B, K, R};
    for (int k = 0; k < 5; k++)
        assert_close(c[k], want[k], 1e-8);
    assert_true(chi2 >= 0 && chi2 < 1e-20);
    for (int j = 0; j < 20; j++)
        ad[j] = K * sqrt(tau[j] / 3);
    assert_int_equal(igea_stability_fit(20, tau, ad, edf, c, se, sup, NULL), 0);
    assert_close(c[IGEA_STABILITY_FIT_K], K, 1e-10);
    for (int k = 0; k < 5; k++) {
        assert_int_equal(sup[k], k == IGEA_STABILITY_FIT_K);
        assert_true(k == IGEA_STABILITY_FIT_K || c[k] == 0.0);
        assert_true(se[k] > 0.0 && isfinite(se[k]));
    }
    /* se of K alone: se(K^2) = (sum w f^2)^-1/2, w = edf / (2 sigma^4), f = tau / 3 */
    double s = 0;
    for (int j = 0; j < 20; j++) {
        double v = K * K * tau[j] / 3;
        s += 50.0 / (2 * v * v) * (tau[j] / 3) * (tau[j] / 3);
    }
    assert_close(se[IGEA_STABILITY_FIT_K], 1.0 / sqrt(s) / (2 * K), 1e-8);
    /* invalid */
    fill_sentinel(c, 5);
    assert_int_equal(igea_stability_fit(4, tau, ad, edf, c, se, sup, NULL), -1);
    assert_int_equal(igea_stability_fit(20, NULL, ad, edf, c, se, sup, NULL), -2);
    assert_int_equal(igea_stability_fit(20, tau, NULL, edf, c, se, sup, NULL), -3);
    assert_int_equal(igea_stability_fit(20, tau, ad, NULL, c, se, sup, NULL), -4);
    assert_int_equal(igea_stability_fit(20, tau, ad, edf, NULL, se, sup, NULL), -5);
    tau[3] = tau[2];
    assert_int_equal(igea_stability_fit(20, tau, ad, edf, c, se, sup, NULL), -2);
    tau[3] = 2 * tau[2];
    ad[5] = 0;
    assert_int_equal(igea_stability_fit(20, tau, ad, edf, c, se, sup, NULL), -3);
    ad[5] = 1e-6;
    edf[2] = 0.5;
    assert_int_equal(igea_stability_fit(20, tau, ad, edf, c, se, sup, NULL), -4);
    edf[2] = NAN;
    assert_int_equal(igea_stability_fit(20, tau, ad, edf, c, se, sup, NULL), IGEA_ENONFINITE);
    assert_true(all_sentinel(c, 5));
}

static void test_fit_boot(void **state)
{
    /* an exact white-rate curve on 4096 samples at 10 Hz: the point fit is
     * igea_stability_fit's; the bootstrap is a function of its arguments;
     * se of N near the sampling sd of N from the octave ADEV (checked
     * against independent records in tests/python/test_stability_dev.py) */
    const int n = 4096;
    const double fs = 10.0, N = 2e-3;
    double tau[12], ad[12], edf[12], c[5], c0[5], se[5], se2[5], lo[5], hi[5], chi2;
    int sup[5], ntau = 0;
    assert_int_equal(igea_stability_taus(n, fs, 0, IGEA_STABILITY_ALLAN_ADEV, 0, 12, tau, &ntau), 0);
    assert_true(ntau == 12);
    for (int j = 0; j < ntau; j++) {
        ad[j] = N / sqrt(tau[j]);
        edf[j] = (double)n / (tau[j] * fs) - 1.0;
    }
    assert_int_equal(igea_stability_fit(ntau, tau, ad, edf, c0, NULL, NULL, NULL), 0);
    assert_int_equal(igea_stability_fit_boot(n, fs, IGEA_STABILITY_ALLAN_ADEV, ntau, tau, ad, edf,
                                             50, 7, 0.9, c, se, lo, hi, sup, &chi2), 0);
    for (int k = 0; k < 5; k++)
        assert_true(c[k] == c0[k]);
    assert_true(se[1] > 0.0 && lo[1] < N && N < hi[1]);
    assert_true(se[1] < 0.1 * N); /* about 1.6 % here */
    assert_int_equal(igea_stability_fit_boot(n, fs, IGEA_STABILITY_ALLAN_ADEV, ntau, tau, ad, edf,
                                             50, 7, 0.9, c, se2, NULL, NULL, NULL, NULL), 0);
    for (int k = 0; k < 5; k++)
        assert_true(se2[k] == se[k]);
    assert_int_equal(igea_stability_fit_boot(n, fs, IGEA_STABILITY_ALLAN_ADEV, ntau, tau, ad, edf,
                                             50, 8, 0.9, c, se2, NULL, NULL, NULL, NULL), 0);
    assert_true(se2[1] != se[1]);
    /* invalid */
    fill_sentinel(c, 5);
    fill_sentinel(se, 5);
    const int K = IGEA_STABILITY_ALLAN_ADEV;
    assert_int_equal(igea_stability_fit_boot(1, fs, K, ntau, tau, ad, edf, 50, 7, 0.9, c, se, lo, hi, sup, NULL), -1);
    assert_int_equal(igea_stability_fit_boot(n, 0.0, K, ntau, tau, ad, edf, 50, 7, 0.9, c, se, lo, hi, sup, NULL), -2);
    assert_int_equal(igea_stability_fit_boot(n, fs, IGEA_STABILITY_ALLAN_MDEV, ntau, tau, ad, edf, 50, 7, 0.9, c, se, lo, hi, sup, NULL), -3);
    assert_int_equal(igea_stability_fit_boot(n, fs, K, 4, tau, ad, edf, 50, 7, 0.9, c, se, lo, hi, sup, NULL), -4);
    assert_int_equal(igea_stability_fit_boot(n, fs, K, ntau, NULL, ad, edf, 50, 7, 0.9, c, se, lo, hi, sup, NULL), -5);
    assert_int_equal(igea_stability_fit_boot(100, fs, K, ntau, tau, ad, edf, 50, 7, 0.9, c, se, lo, hi, sup, NULL), -5);
    assert_int_equal(igea_stability_fit_boot(n, fs, K, ntau, tau, NULL, edf, 50, 7, 0.9, c, se, lo, hi, sup, NULL), -6);
    assert_int_equal(igea_stability_fit_boot(n, fs, K, ntau, tau, ad, NULL, 50, 7, 0.9, c, se, lo, hi, sup, NULL), -7);
    assert_int_equal(igea_stability_fit_boot(n, fs, K, ntau, tau, ad, edf, 1, 7, 0.9, c, se, lo, hi, sup, NULL), -8);
    assert_int_equal(igea_stability_fit_boot(n, fs, K, ntau, tau, ad, edf, 50, -1, 0.9, c, se, lo, hi, sup, NULL), -9);
    assert_int_equal(igea_stability_fit_boot(n, fs, K, ntau, tau, ad, edf, 50, 7, 1.0, c, se, lo, hi, sup, NULL), -10);
    assert_int_equal(igea_stability_fit_boot(n, fs, K, ntau, tau, ad, edf, 50, 7, 0.9, NULL, se, lo, hi, sup, NULL), -11);
    ad[3] = -1.0;
    assert_int_equal(igea_stability_fit_boot(n, fs, K, ntau, tau, ad, edf, 50, 7, 0.9, c, se, lo, hi, sup, NULL), -6);
    ad[3] = NAN;
    assert_int_equal(igea_stability_fit_boot(n, fs, K, ntau, tau, ad, edf, 50, 7, 0.9, c, se, lo, hi, sup, NULL), IGEA_ENONFINITE);
    assert_true(all_sentinel(c, 5) && all_sentinel(se, 5));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_block),
        cmocka_unit_test(test_allan_nbs),
        cmocka_unit_test(test_allan_direct_and_ramp),
        cmocka_unit_test(test_allan_edf),
        cmocka_unit_test(test_allan_args),
        cmocka_unit_test(test_octave_taus),
        cmocka_unit_test(test_noise_id),
        cmocka_unit_test(test_dev_nbs),
        cmocka_unit_test(test_dev_tie),
        cmocka_unit_test(test_dev_edf),
        cmocka_unit_test(test_dev_noise_id),
        cmocka_unit_test(test_dev_args),
        cmocka_unit_test(test_dev_taus),
        cmocka_unit_test(test_fit),
        cmocka_unit_test(test_fit_boot),
        cmocka_unit_test(test_stream),
        cmocka_unit_test(test_stream_source),
        cmocka_unit_test(test_long_lags),
#ifndef OOM_DISABLED
        cmocka_unit_test(test_oom),
        cmocka_unit_test(test_dev_oom),
        cmocka_unit_test(test_stream_oom),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
