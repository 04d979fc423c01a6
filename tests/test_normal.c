/* Tests of igea/normal.h: the weighted normal equations against a direct
 * triple loop, in one call and in row blocks, both layouts. */
#include "testutil.h"

#include "igea.h"
#include "internal.h"

enum { M = 37, N = 5 };
static double S[M * N], dw[M], sig[M], spec[N];

static void make(void)
{
    for (int i = 0; i < M; i++) {
        for (int j = 0; j < N; j++)
            S[i + j * M] = sin(0.3 * i + 1.7 * j) + 0.01 * i * j;
        dw[i] = cos(0.11 * i);
        sig[i] = 0.5 + 0.01 * i;
    }
    for (int j = 0; j < N; j++)
        spec[j] = 1.0 + 0.5 * j;
}

/* Independent reference: A = D S' K^-1 S D by definition. */
static void reference(double *A, double *b, double *ww)
{
    *ww = 0;
    for (int j = 0; j < N; j++) {
        b[j] = 0;
        for (int k = 0; k < N; k++) {
            double a = 0;
            for (int i = 0; i < M; i++)
                a += S[i + j * M] * S[i + k * M] / (sig[i] * sig[i]);
            A[j + k * N] = a * spec[j] * spec[k];
        }
        for (int i = 0; i < M; i++)
            b[j] += S[i + j * M] * dw[i] / (sig[i] * sig[i]) * spec[j];
    }
    for (int i = 0; i < M; i++)
        *ww += dw[i] * dw[i] / (sig[i] * sig[i]);
}

static void test_whole_and_blocks(void **state)
{
    make();
    double Ar[N * N], br[N], wr, A[N * N], b[N], w[2];
    reference(Ar, br, &wr);
    memset(A, 0, sizeof A);
    memset(b, 0, sizeof b);
    w[0] = w[1] = 0;
    assert_int_equal(igea_normal_accumulate(IGEA_COLMAJOR, M, N, S, M, dw, sig, 1, spec, A, N, b, w), 0);
    for (int k = 0; k < N * N; k++)
        assert_close(A[k], Ar[k], 1e-13);
    for (int k = 0; k < N; k++)
        assert_close(b[k], br[k], 1e-13);
    assert_close(w[0], wr, 1e-14);
    assert_true(w[1] == M);
    /* the same in three blocks of rows (13 + 13 + 11), row-major storage */
    double St[M * N];
    for (int i = 0; i < M; i++)
        for (int j = 0; j < N; j++)
            St[j + i * N] = S[i + j * M];
    memset(A, 0, sizeof A);
    memset(b, 0, sizeof b);
    w[0] = w[1] = 0;
    for (int r0 = 0; r0 < M; r0 += 13) {
        int nr = r0 + 13 <= M ? 13 : M - r0;
        assert_int_equal(igea_normal_accumulate(IGEA_ROWMAJOR, nr, N, St + (size_t)r0 * N, N,
                                                dw + r0, sig + r0, 1, spec, A, N, b, w), 0);
    }
    for (int k = 0; k < N * N; k++)
        assert_close(A[k], Ar[k], 1e-13);
    for (int k = 0; k < N; k++)
        assert_close(b[k], br[k], 1e-13);
    assert_true(w[1] == M);
}

static void test_scalar_sigma_no_spec_padding(void **state)
{
    make();
    /* lds > m with NaN padding must not be read */
    enum { LDS = M + 3 };
    double Sp[LDS * N], A[N * N], b[N], w[2] = {0, 0}, s0 = 0.25;
    fill_nan(Sp, LDS * N);
    for (int j = 0; j < N; j++)
        for (int i = 0; i < M; i++)
            Sp[i + j * LDS] = S[i + j * M];
    memset(A, 0, sizeof A);
    memset(b, 0, sizeof b);
    assert_int_equal(igea_normal_accumulate(IGEA_COLMAJOR, M, N, Sp, LDS, dw, &s0, 0, NULL, A, N, b, w), 0);
    for (int j = 0; j < N; j++)
        for (int k = 0; k < N; k++) {
            double a = 0;
            for (int i = 0; i < M; i++)
                a += S[i + j * M] * S[i + k * M] / (s0 * s0);
            assert_close(A[j + k * N], a, 1e-13);
        }
    /* m = 0 is a no-op */
    double A0[N * N];
    memcpy(A0, A, sizeof A);
    assert_int_equal(igea_normal_accumulate(IGEA_COLMAJOR, 0, N, NULL, 1, NULL, NULL, 1, NULL, A, N, b, w), 0);
    assert_memory_equal(A, A0, sizeof A);
}

static void test_invalid(void **state)
{
    make();
    double A[N * N], b[N], w[2];
    fill_sentinel(A, N * N);
    fill_sentinel(b, N);
    fill_sentinel(w, 2);
#define ACC(l, m, n, s, lds, d, g, gi, sp, a, lda, bb, ww) \
    igea_normal_accumulate(l, m, n, s, lds, d, g, gi, sp, a, lda, bb, ww)
    assert_int_equal(ACC(2, M, N, S, M, dw, sig, 1, spec, A, N, b, w), -1);
    assert_int_equal(ACC(0, -1, N, S, M, dw, sig, 1, spec, A, N, b, w), -2);
    assert_int_equal(ACC(0, M, 0, S, M, dw, sig, 1, spec, A, N, b, w), -3);
    assert_int_equal(ACC(0, M, N, NULL, M, dw, sig, 1, spec, A, N, b, w), -4);
    assert_int_equal(ACC(0, M, N, S, M - 1, dw, sig, 1, spec, A, N, b, w), -5);
    assert_int_equal(ACC(1, M, N, S, N - 1, dw, sig, 1, spec, A, N, b, w), -5);
    assert_int_equal(ACC(0, M, N, S, M, NULL, sig, 1, spec, A, N, b, w), -6);
    assert_int_equal(ACC(0, M, N, S, M, dw, NULL, 1, spec, A, N, b, w), -7);
    assert_int_equal(ACC(0, M, N, S, M, dw, sig, 2, spec, A, N, b, w), -8);
    assert_int_equal(ACC(0, M, N, S, M, dw, sig, 1, spec, NULL, N, b, w), -10);
    assert_int_equal(ACC(0, M, N, S, M, dw, sig, 1, spec, A, N - 1, b, w), -11);
    assert_int_equal(ACC(0, M, N, S, M, dw, sig, 1, spec, A, N, NULL, w), -12);
    assert_int_equal(ACC(0, M, N, S, M, dw, sig, 1, spec, A, N, b, NULL), -13);
    spec[2] = 0.0;
    assert_int_equal(ACC(0, M, N, S, M, dw, sig, 1, spec, A, N, b, w), IGEA_ENONPOSITIVE);
    spec[2] = NAN;
    assert_int_equal(ACC(0, M, N, S, M, dw, sig, 1, spec, A, N, b, w), IGEA_ENONFINITE);
    make();
    sig[30] = -1.0;
    assert_int_equal(ACC(0, M, N, S, M, dw, sig, 1, spec, A, N, b, w), IGEA_ENONPOSITIVE);
    sig[30] = INFINITY;
    assert_int_equal(ACC(0, M, N, S, M, dw, sig, 1, spec, A, N, b, w), IGEA_ENONFINITE);
    make();
    S[M - 1 + 3 * M] = NAN; /* last row: the first blocks were fine */
    assert_int_equal(ACC(0, M, N, S, M, dw, sig, 1, spec, A, N, b, w), IGEA_ENONFINITE);
    make();
    dw[5] = INFINITY;
    assert_int_equal(ACC(0, M, N, S, M, dw, sig, 1, spec, A, N, b, w), IGEA_ENONFINITE);
    /* the same with one sigma for all rows (no copy of S is made) */
    double s0 = 0.5, eq[M];
    for (int i = 0; i < M; i++)
        eq[i] = 0.5;
    make();
    S[M - 1 + 3 * M] = NAN;
    assert_int_equal(ACC(0, M, N, S, M, dw, &s0, 0, spec, A, N, b, w), IGEA_ENONFINITE);
    assert_int_equal(ACC(0, M, N, S, M, dw, eq, 1, NULL, A, N, b, w), IGEA_ENONFINITE);
    make();
    S[3] = -INFINITY;
    assert_int_equal(ACC(1, M, N, S, N, dw, &s0, 0, NULL, A, N, b, w), IGEA_ENONFINITE);
    make();
    dw[0] = NAN;
    assert_int_equal(ACC(0, M, N, S, M, dw, &s0, 0, spec, A, N, b, w), IGEA_ENONFINITE);
    assert_true(all_sentinel(A, N * N) && all_sentinel(b, N) && all_sentinel(w, 2));
#undef ACC
}

/* A long flight (more rows than one internal block) equals its halves. */
static void test_long_flight(void **state)
{
    enum { ML = 50000, NL = 3 };
    double *Sl = malloc(sizeof(double) * ML * NL), *d = malloc(sizeof(double) * ML);
    assert_non_null(Sl);
    assert_non_null(d);
    for (int i = 0; i < ML; i++) {
        for (int j = 0; j < NL; j++)
            Sl[i + (size_t)j * ML] = pow(i / (double)ML, j);
        d[i] = 1.0;
    }
    double s1 = 1.0, A[NL * NL] = {0}, b[NL] = {0}, w[2] = {0, 0};
    assert_int_equal(igea_normal_accumulate(IGEA_COLMAJOR, ML, NL, Sl, ML, d, &s1, 0, NULL, A, NL, b, w), 0);
    /* sum_i (i/ML)^(j+k), compensated reference */
    for (int j = 0; j < NL; j++)
        for (int k = 0; k < NL; k++) {
            long double ref = 0;
            for (int i = 0; i < ML; i++)
                ref += powl((long double)i / ML, j + k);
            assert_close(A[j + k * NL], (double)ref, 1e-12);
        }
    assert_close(w[0], ML, 1e-15);
    free(Sl);
    free(d);
}

/* The QR factor of [S~ w~]: R'R reproduces the normal equations and
 * R[N,N]^2 the weighted residual sum of squares, in one call or in blocks. */
static void test_qr_factor(void **state)
{
    make();
    enum { N1 = N + 1 };
    double Ar[N * N], br[N], wr, R[N1 * N1], R2[N1 * N1], rows = 0, rows2 = 0;
    reference(Ar, br, &wr);
    memset(R, 0, sizeof R);
    memset(R2, 0, sizeof R2);
    assert_int_equal(igea_normal_qr_accumulate(IGEA_COLMAJOR, M, N, S, M, dw, sig, 1, spec, R, N1, &rows), 0);
    assert_true(rows == M);
    double St[M * N];
    for (int i = 0; i < M; i++)
        for (int j = 0; j < N; j++)
            St[j + i * N] = S[i + j * M];
    for (int r0 = 0; r0 < M; r0 += 4) { /* blocks shorter than N + 1 rows */
        int nr = r0 + 4 <= M ? 4 : M - r0;
        assert_int_equal(igea_normal_qr_accumulate(IGEA_ROWMAJOR, nr, N, St + (size_t)r0 * N, N,
                                                   dw + r0, sig + r0, 1, spec, R2, N1, &rows2), 0);
    }
    for (const double *Rx = R; Rx; Rx = Rx == R ? R2 : NULL) {
        for (int j = 0; j < N; j++) {
            for (int k = 0; k < N; k++) {
                double a = 0;
                for (int i = 0; i <= (j < k ? j : k); i++)
                    a += Rx[i + j * N1] * Rx[i + k * N1];
                assert_close(a, Ar[j + k * N], 1e-12);
            }
            double bj = 0; /* b = R' (Q' w~) */
            for (int i = 0; i <= j; i++)
                bj += Rx[i + j * N1] * Rx[i + N * N1];
            assert_close(bj, br[j], 1e-12);
        }
        /* |w~|^2 = |Q'w~|^2 + R[N,N]^2 */
        double ww = 0;
        for (int i = 0; i <= N; i++)
            ww += Rx[i + N * N1] * Rx[i + N * N1];
        assert_close(ww, wr, 1e-12);
    }
    /* invalid arguments and faults leave R untouched */
    double Rs[N1 * N1], rs = SENTINEL;
    fill_sentinel(Rs, N1 * N1);
    assert_int_equal(igea_normal_qr_accumulate(3, M, N, S, M, dw, sig, 1, spec, Rs, N1, &rs), -1);
    assert_int_equal(igea_normal_qr_accumulate(0, M, N, S, M - 1, dw, sig, 1, spec, Rs, N1, &rs), -5);
    assert_int_equal(igea_normal_qr_accumulate(0, M, N, S, M, dw, sig, 1, spec, NULL, N1, &rs), -10);
    assert_int_equal(igea_normal_qr_accumulate(0, M, N, S, M, dw, sig, 1, spec, Rs, N, &rs), -11);
    assert_int_equal(igea_normal_qr_accumulate(0, M, N, S, M, dw, sig, 1, spec, Rs, N1, NULL), -12);
    sig[3] = 0.0;
    assert_int_equal(igea_normal_qr_accumulate(0, M, N, S, M, dw, sig, 1, spec, Rs, N1, &rs), IGEA_ENONPOSITIVE);
    make();
    S[M - 2 + 4 * M] = NAN;
    assert_int_equal(igea_normal_qr_accumulate(0, M, N, S, M, dw, sig, 1, spec, Rs, N1, &rs), IGEA_ENONFINITE);
    make();
    assert_true(all_sentinel(Rs, N1 * N1) && rs == SENTINEL);
}

static void test_overflow_and_range(void **state)
{
    (void)state;
    make();
    double Sb[M * N], A[N * N], b[N], ww[2], R[(N + 1) * (N + 1)], rows;
    for (int i = 0; i < M * N; i++)
        Sb[i] = S[i] * 1e200;
    for (int layout = 0; layout < 2; layout++) {
        /* the row-major view of the same numbers: S^T, N x M */
        double St[M * N];
        for (int i = 0; i < M; i++)
            for (int j = 0; j < N; j++)
                St[j + i * N] = Sb[i + j * M];
        const double *X = layout == IGEA_COLMAJOR ? Sb : St;
        int ld = layout == IGEA_COLMAJOR ? M : N;
        for (int inc = 0; inc < 2; inc++) {
            fill_sentinel(A, N * N);
            fill_sentinel(b, N);
            fill_sentinel(ww, 2);
            assert_int_equal(igea_normal_accumulate(layout, M, N, X, ld, dw, sig,
                                                    inc, NULL, A, N, b, ww),
                             IGEA_EOVERFLOW);
            assert_true(all_sentinel(A, N * N) && all_sentinel(b, N) &&
                        all_sentinel(ww, 2));
        }
        /* QR: the blocks are finite, the factor (~1e200 sqrt(m)) too; with
         * 1e307 the weighted rows themselves overflow. */
        double Sc[M * N];
        for (int i = 0; i < M * N; i++)
            Sc[i] = (layout == IGEA_COLMAJOR ? S[i] : 0.0) * 1e307;
        if (layout == IGEA_ROWMAJOR)
            for (int i = 0; i < M; i++)
                for (int j = 0; j < N; j++)
                    Sc[j + i * N] = S[i + j * M] * 1e307;
        fill_sentinel(R, (N + 1) * (N + 1));
        rows = SENTINEL;
        assert_int_equal(igea_normal_qr_accumulate(layout, M, N, Sc, ld, dw, sig,
                                                   1, spec, R, N + 1, &rows),
                         IGEA_EOVERFLOW);
        assert_true(all_sentinel(R, (N + 1) * (N + 1)) && rows == SENTINEL);
    }
    /* A running row count that is not finite and >= 0 is refused. */
    const double badrows[4] = {NAN, INFINITY, -INFINITY, -1.0};
    for (int t = 0; t < 4; t++) {
        fill_sentinel(R, (N + 1) * (N + 1));
        rows = badrows[t];
        assert_int_equal(igea_normal_qr_accumulate(IGEA_COLMAJOR, M, N, S, M, dw,
                                                   sig, 1, NULL, R, N + 1, &rows),
                         -12);
        assert_true(all_sentinel(R, (N + 1) * (N + 1)));
    }
    rows = 0.0;
    /* So is a negative or non-finite running sum in wtw. */
    for (int t = 0; t < 4; t++)
        for (int w = 0; w < 2; w++) {
            double wt[2] = {0.0, 0.0};
            wt[w] = badrows[t];
            fill_sentinel(A, N * N);
            assert_int_equal(igea_normal_accumulate(IGEA_COLMAJOR, M, N, S, M, dw,
                                                    sig, 1, NULL, A, N, b, wt),
                             -13);
            assert_true(all_sentinel(A, N * N));
        }
    /* The running sums overflowing on a later block: untouched too. */
    memset(A, 0, sizeof A);
    memset(b, 0, sizeof b);
    memset(ww, 0, sizeof ww);
    A[0] = 1.7e308;
    double A0[N * N];
    memcpy(A0, A, sizeof A);
    double big[M];
    for (int i = 0; i < M; i++)
        big[i] = 1.0;
    double Sbig[M * N];
    for (int i = 0; i < M * N; i++)
        Sbig[i] = 1e153;
    assert_int_equal(igea_normal_accumulate(IGEA_COLMAJOR, M, N, Sbig, M, big,
                                            big, 0, NULL, A, N, b, ww),
                     IGEA_EOVERFLOW);
    assert_true(memcmp(A, A0, sizeof A) == 0 && b[0] == 0.0 && ww[0] == 0.0);
    /* A sigma below 2^-511 (here denormal) is out of range, in either
     * accumulator, per row or as one value, and as a spec. */
    double sg[M];
    memcpy(sg, sig, sizeof sg);
    sg[7] = 1e-310;
    fill_sentinel(A, N * N);
    assert_int_equal(igea_normal_accumulate(IGEA_COLMAJOR, M, N, S, M, dw, sg, 1,
                                            NULL, A, N, b, ww), IGEA_ERANGE);
    assert_int_equal(igea_normal_qr_accumulate(IGEA_COLMAJOR, M, N, S, M, dw, sg,
                                               1, NULL, R, N + 1, &rows),
                     IGEA_ERANGE);
    double one = 1e-160;
    assert_int_equal(igea_normal_accumulate(IGEA_COLMAJOR, M, N, S, M, dw, &one,
                                            0, NULL, A, N, b, ww), IGEA_ERANGE);
    double sp[N];
    memcpy(sp, spec, sizeof sp);
    sp[2] = 2e-320;
    assert_int_equal(igea_normal_accumulate(IGEA_COLMAJOR, M, N, S, M, dw, sig, 1,
                                            sp, A, N, b, ww), IGEA_ERANGE);
    assert_true(all_sentinel(A, N * N));
    /* The smallest accepted sigma works and gives finite sums. */
    one = IGEA_SIGMA_MIN;
    memset(A, 0, sizeof A);
    memset(b, 0, sizeof b);
    memset(ww, 0, sizeof ww);
    double Ss[M * N], ds[M];
    for (int i = 0; i < M * N; i++)
        Ss[i] = S[i] * 1e-160;
    for (int i = 0; i < M; i++)
        ds[i] = dw[i] * 1e-160;
    assert_int_equal(igea_normal_accumulate(IGEA_COLMAJOR, M, N, Ss, M, ds, &one,
                                            0, NULL, A, N, b, ww), 0);
    assert_true(igea__finite_mat(N, N, A, N));
}

/* igea_normal_accumulate_threads as its header defines it: segments of
 * IGEA_NORMAL_SEGMENT (8192) rows from the block's first, each summed as
 * igea_normal_accumulate sums it into zeroed sums, the segments' sums
 * added in segment order. With per-row sigmas (weighted copies) that is
 * igea_normal_accumulate itself on each segment, bit for bit on 2, 3 and 4
 * threads; with one sigma on row-major rows A and w'w are its bits and b,
 * a plain sum over the rows, agrees with it to 1e-14 (and the same on 2, 3
 * and 4 threads). Both against the long double definition to 1e-13. */
static void test_threads_segments(void **state)
{
    (void)state;
    enum { MT = 3 * 8192 + 1000, NT = 6 };
    assert_int_equal(IGEA_NORMAL_SEGMENT, 8192);
    double *St = malloc(sizeof(double) * MT * NT), *d = malloc(sizeof(double) * MT);
    double *g = malloc(sizeof(double) * MT), sp[NT];
    assert_non_null(St && d && g);
    for (int j = 0; j < NT; j++)
        sp[j] = 0.5 + 0.1 * j;
    for (int i = 0; i < MT; i++) {
        for (int j = 0; j < NT; j++)
            St[(size_t)i * NT + j] = cos(1e-4 * (j + 1) * i + j) + 1e-3 * sin(5.0 * i);
        d[i] = sin(0.01 * i);
    }
    for (int uni = 0; uni < 2; uni++) {
        for (int i = 0; i < MT; i++)
            g[i] = uni ? 0.01 : 0.01 * (1.0 + 0.25 * cos(0.3 * i));
        /* the definition, segment by segment */
        double Al[NT * NT] = {0}, bl[NT] = {0}, wl[2] = {0, 0}, b0[NT];
        for (int r0 = 0; r0 < MT; r0 += IGEA_NORMAL_SEGMENT) {
            int n = MT - r0 < IGEA_NORMAL_SEGMENT ? MT - r0 : IGEA_NORMAL_SEGMENT;
            double Ak[NT * NT] = {0}, bk[NT] = {0}, wk[2] = {0, 0};
            assert_int_equal(igea_normal_accumulate(IGEA_ROWMAJOR, n, NT, St + (size_t)r0 * NT,
                                                    NT, d + r0, g + r0, 1, sp, Ak, NT, bk, wk),
                             0);
            for (int j = 0; j < NT; j++) {
                for (int i = j; i < NT; i++)
                    Al[i + j * NT] += Ak[i + j * NT];
                bl[j] += bk[j];
            }
            wl[0] += wk[0];
        }
        for (int th = 2; th <= 4; th++) {
            double A[NT * NT] = {0}, b[NT] = {0}, w[2] = {0, 0};
            assert_int_equal(igea_normal_accumulate_threads(IGEA_ROWMAJOR, MT, NT, St, NT, d, g,
                                                            1, sp, A, NT, b, w, th), 0);
            for (int j = 0; j < NT; j++)
                for (int i = j; i < NT; i++) {
                    assert_true(A[i + j * NT] == Al[i + j * NT]);
                    assert_true(A[j + i * NT] == Al[i + j * NT]);
                }
            if (uni) {
                for (int j = 0; j < NT; j++)
                    assert_close_abs(b[j], bl[j], 1e-14, 1e-14 * fabs(bl[0]));
                if (th == 2)
                    memcpy(b0, b, sizeof b0);
                assert_memory_equal(b, b0, sizeof b0);
            } else {
                assert_memory_equal(b, bl, sizeof b);
            }
            assert_true(w[0] == wl[0] && w[1] == MT);
            for (int j = 0; j < NT; j++) {
                long double rb = 0;
                for (int i = 0; i < MT; i++)
                    rb += (long double)St[(size_t)i * NT + j] * d[i] / ((long double)g[i] * g[i]) *
                          sp[j];
                assert_close_abs(b[j], (double)rb, 1e-13, 1e-13 * fabs(b[0]));
                for (int k = 0; k <= j; k++) {
                    long double ref = 0;
                    for (int i = 0; i < MT; i++)
                        ref += (long double)St[(size_t)i * NT + j] * St[(size_t)i * NT + k] /
                               ((long double)g[i] * g[i]) * sp[j] * sp[k];
                    assert_close_abs(A[j + k * NT], (double)ref, 1e-13, 1e-13 * fabs(A[0]));
                }
            }
        }
    }
    free(St), free(d), free(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_whole_and_blocks),
        cmocka_unit_test(test_scalar_sigma_no_spec_padding),
        cmocka_unit_test(test_invalid),
        cmocka_unit_test(test_long_flight),
        cmocka_unit_test(test_qr_factor),
        cmocka_unit_test(test_overflow_and_range),
        cmocka_unit_test(test_threads_segments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
