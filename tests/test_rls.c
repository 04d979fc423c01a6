/* tests/test_rls.c - recursive least squares (METHODS 2). */
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <lapacke.h>

#include "igea/rls.h"
#include "testutil.h"

/* The program's own malloc (as tests/test_oom.c) counts and can fail the
 * allocations made inside a call; not under AddressSanitizer, which owns
 * malloc itself. */
#include "oom.h"

/* ---- helpers ------------------------------------------------------------ */

static igea_rls *make(int m, int k, double g0, int variant, int p)
{
    double *g = calloc((size_t)m * m, sizeof(double));
    for (int i = 0; i < m; i++)
        g[i + (size_t)i * m] = g0;
    igea_rls *h = NULL;
    assert_int_equal(igea_rls_create(m, k, NULL, g, m, &h), 0);
    assert_non_null(h);
    assert_int_equal(igea_rls_set_variant(h, variant, p), 0);
    free(g);
    return h;
}

/* A random record: n epochs of k x m blocks (ROWS layout, lds = n k),
 * y = c X + noise * N(0, 1). */
typedef struct {
    int m, k, n;
    double *S, *y, *X;
} record;

static record make_record(int m, int k, int n, double noise, unsigned long seed)
{
    record r = {m, k, n, NULL, NULL, NULL};
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, seed);
    size_t nk = (size_t)n * k;
    r.S = malloc(nk * m * sizeof(double));
    r.y = malloc(nk * sizeof(double));
    r.X = malloc((size_t)m * sizeof(double));
    for (int i = 0; i < m; i++)
        r.X[i] = gsl_ran_gaussian(rng, 1.0);
    for (size_t t = 0; t < nk * m; t++)
        r.S[t] = gsl_ran_gaussian(rng, 1.0);
    for (size_t row = 0; row < nk; row++) {
        double s = 0.0;
        for (int i = 0; i < m; i++)
            s += r.S[row + (size_t)i * nk] * r.X[i];
        r.y[row] = s + noise * gsl_ran_gaussian(rng, 1.0);
    }
    gsl_rng_free(rng);
    return r;
}

static void free_record(record *r)
{
    free(r->S);
    free(r->y);
    free(r->X);
}

static void feed(igea_rls *h, const record *r, int from, int to)
{
    size_t nk = (size_t)r->n * r->k;
    for (int e = from; e < to; e++) {
        size_t row = (size_t)e * r->k;
        int st = igea_rls_update(h, r->S + row, (int)nk, r->y + row, NULL, NULL);
        assert_true(st == IGEA_RLS_UPDATED || st == IGEA_RLS_FLAGGED);
    }
}

static double maxdiff(int n, const double *a, const double *b)
{
    double d = 0.0;
    for (int i = 0; i < n; i++)
        d = fmax(d, fabs(a[i] - b[i]));
    return d;
}

/* ---- METHODS 2.9 test vector ------------------------------------------- */

static const double TV_C[3][6] = { /* c_n column-major 2 x 3 */
    {1, 0, 0, 1, 0.5, 1},
    {1, 0.5, 1, 0, 0, 1},
    {2, 0, 0, 1, 1, -1}};

static void tv_run(int variant, int p, double *x, double *q, double *gdiag)
{
    const double X[3] = {1, -2, 0.5};
    igea_rls *h = make(3, 2, 10.0, variant, p);
    for (int n = 0; n < 3; n++) {
        double y[2];
        for (int j = 0; j < 2; j++)
            y[j] = TV_C[n][j] * X[0] + TV_C[n][j + 2] * X[1] + TV_C[n][j + 4] * X[2];
        if (n == 1) {
            y[0] += 0.01;
            y[1] -= 0.02;
        }
        assert_int_equal(igea_rls_update(h, TV_C[n], 2, y, NULL, NULL), 0);
    }
    double g[9];
    assert_int_equal(igea_rls_get_x(h, x), 0);
    assert_int_equal(igea_rls_get_q(h, q), 0);
    assert_int_equal(igea_rls_get_gamma(h, g, 3), 0);
    for (int i = 0; i < 3; i++)
        gdiag[i] = g[i * 4];
    igea_rls_free(h);
}

static void test_vector(void **state)
{
    /* METHODS 2.9, printed to 10 decimals. */
    const double want_x[3][3] = {{0.9698200160, -1.9225225858, 0.5047218280},
                                 {1.0015784781, -2.0000818017, 0.4946678785},
                                 {1.0031741050, -2.0047921672, 0.4937185816}};
    const double want_q[3] = {0.0497347972, 0.0003977279, 0.0000182639};
    const double want_g[3] = {0.2526238883, 0.3488682506, 0.3500391066};
    const int variants[2] = {IGEA_RLS_POLYNOMIAL, IGEA_RLS_ITERATED};
    for (int v = 0; v < 2; v++)
        for (int p = 1; p <= 3; p++) {
            double x[3], q, gd[3];
            tv_run(variants[v], p, x, &q, gd);
            for (int i = 0; i < 3; i++) {
                assert_close_abs(x[i], want_x[p - 1][i], 0, 6e-11);
                assert_close_abs(gd[i], want_g[i], 0, 6e-11);
            }
            assert_close_abs(q, want_q[p - 1], 0, 6e-11);
        }
    double x[3], q, gd[3];
    tv_run(IGEA_RLS_STANDARD, 7, x, &q, gd); /* p ignored for standard */
    for (int i = 0; i < 3; i++)
        assert_close_abs(x[i], want_x[0][i], 0, 6e-11);
    assert_close_abs(q, want_q[0], 0, 6e-11);
}

/* ---- iterated == polynomial (METHODS 2.4 equivalence) ------------------ */

static void test_iterated_equals_polynomial(void **state)
{
    record r = make_record(6, 3, 200, 0.1, 11);
    for (int p = 1; p <= 10; p++) {
        igea_rls *hi = make(6, 3, 10.0, IGEA_RLS_ITERATED, p);
        igea_rls *hp = make(6, 3, 10.0, IGEA_RLS_POLYNOMIAL, p);
        feed(hi, &r, 0, r.n);
        feed(hp, &r, 0, r.n);
        double xi[6], xp[6], gi[36], gp[36], ci[36], cp[36], qi, qp;
        igea_rls_get_x(hi, xi);
        igea_rls_get_x(hp, xp);
        igea_rls_get_gamma(hi, gi, 6);
        igea_rls_get_gamma(hp, gp, 6);
        igea_rls_get_covariance(hi, ci, 6);
        igea_rls_get_covariance(hp, cp, 6);
        igea_rls_get_q(hi, &qi);
        igea_rls_get_q(hp, &qp);
        double xs = 0.0;
        for (int i = 0; i < 6; i++)
            xs = fmax(xs, fabs(xp[i]));
        assert_true(maxdiff(6, xi, xp) <= 1e-13 * xs);
        assert_true(maxdiff(36, gi, gp) == 0.0); /* same Gamma code path */
        assert_true(maxdiff(36, ci, cp) == 0.0);
        assert_close(qi, qp, 1e-11);
        if (p > 1) { /* the honest covariance exceeds Gamma (K is optimal) */
            double ti = 0.0, tg = 0.0;
            for (int i = 0; i < 6; i++) {
                ti += ci[i * 7];
                tg += gi[i * 7];
            }
            assert_true(ti > tg);
        } else {
            assert_true(maxdiff(36, ci, gi) == 0.0);
        }
        igea_rls_free(hi);
        igea_rls_free(hp);
    }
    free_record(&r);
}

/* Q_p decreases with p (METHODS 2.6 caution: by construction). */
static void test_q_decreases(void **state)
{
    record r = make_record(5, 3, 100, 0.1, 12);
    double prev = INFINITY;
    for (int p = 1; p <= 8; p++) {
        igea_rls *h = make(5, 3, 100.0, IGEA_RLS_POLYNOMIAL, p);
        feed(h, &r, 0, r.n);
        double q;
        igea_rls_get_q(h, &q);
        assert_true(q < prev);
        prev = q;
        igea_rls_free(h);
    }
    free_record(&r);
}

/* ---- batch least-squares limit ------------------------------------------ */

/* (S^T S + I / g0) x = S^T y by Cholesky: the exact batch estimate that
 * standard RLS from x0 = 0, Gamma_0 = g0 I reproduces. */
static void batch_ls(const record *r, double g0, double *x, double *Ainv)
{
    int m = r->m;
    size_t nk = (size_t)r->n * r->k;
    double *A = calloc((size_t)m * m, sizeof(double));
    for (int i = 0; i < m; i++) {
        x[i] = 0.0;
        for (size_t t = 0; t < nk; t++)
            x[i] += r->S[t + i * nk] * r->y[t];
        for (int j = 0; j < m; j++) {
            double s = i == j ? 1.0 / g0 : 0.0;
            for (size_t t = 0; t < nk; t++)
                s += r->S[t + i * nk] * r->S[t + j * nk];
            A[i + (size_t)j * m] = s;
        }
    }
    assert_int_equal(LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', m, A, m), 0);
    assert_int_equal(LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', m, 1, A, m, x, m), 0);
    if (Ainv) {
        assert_int_equal(LAPACKE_dpotri(LAPACK_COL_MAJOR, 'L', m, A, m), 0);
        for (int j = 0; j < m; j++)
            for (int i = j; i < m; i++)
                Ainv[i + (size_t)j * m] = Ainv[j + (size_t)i * m] = A[i + (size_t)j * m];
    }
    free(A);
}

static void test_batch_limit(void **state)
{
    /* No noise, diffuse Gamma_0: RLS (p = 1) reaches X, and equals the batch
     * estimate with the same prior to rounding. */
    record r = make_record(5, 2, 40, 0.0, 13);
    const double g0 = 1e6;
    igea_rls *h = make(5, 2, g0, IGEA_RLS_STANDARD, 1);
    feed(h, &r, 0, r.n);
    double x[5], xb[5], g[25], gb[25];
    igea_rls_get_x(h, x);
    igea_rls_get_gamma(h, g, 5);
    batch_ls(&r, g0, xb, gb);
    for (int i = 0; i < 5; i++) {
        assert_close_abs(x[i], r.X[i], 0, 1e-7);
        assert_close_abs(x[i], xb[i], 0, 1e-7);
    }
    for (int t = 0; t < 25; t++)
        assert_close_abs(g[t], gb[t], 1e-6, 1e-9);
    igea_rls_free(h);
    free_record(&r);

    /* With noise and a moderate prior: RLS == batch (S^T S + I/g0)^-1 S^T y. */
    r = make_record(5, 3, 60, 0.3, 14);
    h = make(5, 3, 4.0, IGEA_RLS_STANDARD, 1);
    feed(h, &r, 0, r.n);
    igea_rls_get_x(h, x);
    igea_rls_get_gamma(h, g, 5);
    batch_ls(&r, 4.0, xb, gb);
    for (int i = 0; i < 5; i++)
        assert_close_abs(x[i], xb[i], 0, 1e-12);
    for (int t = 0; t < 25; t++)
        assert_close_abs(g[t], gb[t], 1e-10, 1e-15);
    igea_rls_free(h);
    free_record(&r);
}

/* Forgetting factor: RLS with lambda equals the exponentially weighted batch
 * estimate, weights lambda^(n-1-e) and prior weight lambda^n / g0. */
static void test_forget(void **state)
{
    record r = make_record(4, 2, 50, 0.2, 15);
    const double lam = 0.95, g0 = 3.0;
    igea_rls *h = make(4, 2, g0, IGEA_RLS_STANDARD, 1);
    assert_int_equal(igea_rls_set_forget(h, lam), 0);
    feed(h, &r, 0, r.n);
    double x[4];
    igea_rls_get_x(h, x);
    int m = 4, n = r.n;
    size_t nk = (size_t)n * 2;
    double A[16], b[4];
    for (int i = 0; i < m; i++) {
        b[i] = 0.0;
        for (int j = 0; j < m; j++)
            A[i + j * m] = i == j ? pow(lam, n) / g0 : 0.0;
    }
    for (size_t t = 0; t < nk; t++) {
        double w = pow(lam, n - 1 - (int)(t / 2));
        for (int i = 0; i < m; i++) {
            b[i] += w * r.S[t + i * nk] * r.y[t];
            for (int j = 0; j < m; j++)
                A[i + j * m] += w * r.S[t + i * nk] * r.S[t + j * nk];
        }
    }
    assert_int_equal(LAPACKE_dposv(LAPACK_COL_MAJOR, 'L', m, 1, A, m, b, m), 0);
    for (int i = 0; i < m; i++)
        assert_close_abs(x[i], b[i], 0, 1e-12);
    igea_rls_free(h);
    free_record(&r);
}

/* c = 0 at lift-off: no update, no NaN, any p (no (cK)^-1). */
static void test_zero_c(void **state)
{
    const double c0[6] = {0, 0, 0, 0, 0, 0}, y0[2] = {0.5, -0.25};
    for (int v = 0; v < 3; v++) {
        igea_rls *h = make(3, 2, 10.0, v, 5);
        assert_int_equal(igea_rls_update(h, c0, 2, y0, NULL, NULL), 0);
        double x[3], g[9], q;
        igea_rls_get_x(h, x);
        igea_rls_get_gamma(h, g, 3);
        igea_rls_get_q(h, &q);
        for (int i = 0; i < 3; i++)
            assert_true(x[i] == 0.0);
        for (int i = 0; i < 9; i++)
            assert_true(g[i] == (i % 4 == 0 ? 10.0 : 0.0));
        assert_close(q, 0.25 + 0.0625, 1e-15);
        /* tiny c: the polynomial gain tends to p times the standard one */
        const double ct[6] = {1e-12, 0, 0, 1e-12, 0, 0}, yt[2] = {1, 0};
        assert_int_equal(igea_rls_update(h, ct, 2, yt, NULL, NULL), 0);
        igea_rls_get_x(h, x);
        assert_close(x[0], v == IGEA_RLS_STANDARD ? 1e-11 : 5e-11, 1e-9);
        igea_rls_free(h);
    }
}

/* Whitening by track_sigma equals dividing c and y by sigma beforehand. */
static void test_whitening(void **state)
{
    record r = make_record(4, 3, 30, 0.5, 16);
    const double sig[3] = {0.5, 2.0, 4.0};
    igea_rls *h1 = make(4, 3, 10.0, IGEA_RLS_POLYNOMIAL, 3);
    igea_rls *h2 = make(4, 3, 10.0, IGEA_RLS_POLYNOMIAL, 3);
    size_t nk = (size_t)r.n * 3;
    for (int e = 0; e < r.n; e++) {
        double c[12], y[3];
        for (int j = 0; j < 3; j++) {
            y[j] = r.y[e * 3 + j] / sig[j];
            for (int i = 0; i < 4; i++)
                c[j + 3 * i] = r.S[e * 3 + j + i * nk] / sig[j];
        }
        assert_int_equal(igea_rls_update(h1, r.S + e * 3, (int)nk, r.y + e * 3, sig, NULL), 0);
        assert_int_equal(igea_rls_update(h2, c, 3, y, NULL, NULL), 0);
    }
    double x1[4], x2[4], q1, q2;
    igea_rls_get_x(h1, x1);
    igea_rls_get_x(h2, x2);
    igea_rls_get_q(h1, &q1);
    igea_rls_get_q(h2, &q2);
    for (int i = 0; i < 4; i++)
        assert_close_abs(x1[i], x2[i], 1e-12, 1e-14);
    assert_close(q1, q2, 1e-12);
    igea_rls_free(h1);
    igea_rls_free(h2);
    free_record(&r);
}

/* ---- anomalies ----------------------------------------------------------- */

static void get_state(igea_rls *h, int m, double *x, double *g)
{
    igea_rls_get_x(h, x);
    igea_rls_get_gamma(h, g, m);
}

static void test_anomaly_policies(void **state)
{
    const int m = 4, k = 3, n = 120;
    record r = make_record(m, k, n, 0.0, 17);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 99);
    size_t nk = (size_t)n * k;
    const double sig[3] = {0.01, 0.01, 0.01};
    for (size_t t = 0; t < nk; t++)
        r.y[t] += 0.01 * gsl_ran_gaussian(rng, 1.0);
    gsl_rng_free(rng);
    double *yb = malloc(nk * sizeof(double));
    memcpy(yb, r.y, nk * sizeof(double));
    yb[60 * k + 1] += 1.0;       /* outlier in row 1 at epoch 60 (100 sigma) */
    for (int j = 0; j < k; j++)  /* whole epoch 90 bad */
        yb[90 * k + j] -= 2.0;

    for (int pol = 0; pol <= IGEA_RLS_ANOMALY_ISOLATE; pol++) {
        igea_rls *h = make(m, k, 100.0, IGEA_RLS_POLYNOMIAL, 2);
        igea_rls *ref = make(m, k, 100.0, IGEA_RLS_POLYNOMIAL, 2);
        assert_int_equal(igea_rls_set_anomaly(h, pol, 4.0, NULL), 0);
        int nflagged = 0;
        double ylast[3] = {0, 0, 0};
        for (int e = 0; e < n; e++) {
            int fl[3];
            int act = igea_rls_update(h, r.S + e * k, (int)nk, yb + e * k, sig, fl);
            assert_true(act >= 0);
            int bad = e == 60 || e == 90;
            /* bad epochs are always flagged; good ones are not, unless policy
             * NONE let the first outlier corrupt the estimate */
            int check = bad || (e > 10 && (pol >= IGEA_RLS_ANOMALY_SKIP || e < 60));
            if (check && (act != 0) != bad)
                fail_msg("policy %d epoch %d: action %d flags %d %d %d", pol, e, act, fl[0], fl[1], fl[2]);
            if (act != 0)
                nflagged++;
            if (bad) { /* the bad epochs and what each policy does there */
                if (e == 60)
                    assert_true(fl[1] & IGEA_RLS_FLAG_INNOVATION);
                for (int j = 0; j < k; j++)
                    if (e == 90)
                        assert_true(fl[j] & IGEA_RLS_FLAG_INNOVATION);
                const int want[4][2] = {{IGEA_RLS_FLAGGED, IGEA_RLS_FLAGGED},
                                        {IGEA_RLS_REPLACED, IGEA_RLS_REPLACED},
                                        {IGEA_RLS_SKIPPED, IGEA_RLS_SKIPPED},
                                        {IGEA_RLS_ISOLATED, IGEA_RLS_SKIPPED}};
                assert_int_equal(act, want[pol][e == 90]);
                if (pol == IGEA_RLS_ANOMALY_ISOLATE && e == 60) {
                    assert_true(fl[1] & IGEA_RLS_FLAG_UNUSED);
                    assert_false(fl[0] & IGEA_RLS_FLAG_UNUSED);
                }
            }
            /* the reference: what the action means, done by hand */
            double ysub[3], sref[3] = {0.01, 0.01, 0.01};
            memcpy(ysub, yb + e * k, sizeof ysub);
            if (act == IGEA_RLS_REPLACED)
                memcpy(ysub, ylast, sizeof ysub);
            if (act == IGEA_RLS_ISOLATED)
                for (int j = 0; j < k; j++)
                    if (fl[j] & IGEA_RLS_FLAG_UNUSED)
                        sref[j] = 1e200; /* a row of infinite noise is no row */
            if (act == IGEA_RLS_SKIPPED) {
                for (int j = 0; j < k; j++)
                    assert_true(fl[j] & IGEA_RLS_FLAG_UNUSED);
            } else {
                assert_true(igea_rls_update(ref, r.S + e * k, (int)nk, ysub, sref, NULL) >= 0);
                for (int j = 0; j < k; j++)
                    if (sref[j] < 1.0)
                        ylast[j] = ysub[j];
            }
        }
        assert_true(nflagged >= 2 && (nflagged == 2 || pol < IGEA_RLS_ANOMALY_SKIP));
        double x[4], g[16], xr[4], gr[16];
        get_state(h, m, x, g);
        get_state(ref, m, xr, gr);
        for (int i = 0; i < m; i++)
            assert_close_abs(x[i], xr[i], 1e-9, 1e-12);
        for (int t = 0; t < m * m; t++)
            assert_close_abs(g[t], gr[t], 1e-9, 1e-15);
        int cnt[IGEA_RLS_COUNT_LEN];
        igea_rls_get_counts(h, cnt);
        assert_int_equal(cnt[IGEA_RLS_COUNT_EPOCHS], n);
        assert_int_equal(cnt[IGEA_RLS_COUNT_ANOMALOUS], nflagged);
        if (pol == IGEA_RLS_ANOMALY_SKIP)
            assert_int_equal(cnt[IGEA_RLS_COUNT_UPDATES], n - 2);
        /* SKIP and ISOLATE end near X; NONE is pulled away (REPLACE pairs
         * y_n with c_n+1, harmless only for smooth c: no claim here) */
        double err = 0.0;
        for (int i = 0; i < m; i++)
            err = fmax(err, fabs(x[i] - r.X[i]));
        if (pol == IGEA_RLS_ANOMALY_NONE)
            assert_true(err > 5e-3);
        else if (pol != IGEA_RLS_ANOMALY_REPLACE)
            assert_true(err < 5e-3);
        igea_rls_free(h);
        igea_rls_free(ref);
    }
    free(yb);
    free_record(&r);
}

static void test_dropouts(void **state)
{
    /* Telemetry drops out: NaN rows and a stretch of zeros (jump test). */
    const int m = 3, k = 2, n = 60;
    record r = make_record(m, k, n, 0.0, 18);
    size_t nk = (size_t)n * k;
    for (size_t t = 0; t < nk; t++)
        r.y[t] += 50.0; /* y far from 0, so a zeroed row is a jump */
    /* y = c X + 50 is inconsistent with the model: use c' = [c, 1] by
     * appending a bias column (X_bias = 50). */
    double *S2 = malloc(nk * (m + 1) * sizeof(double));
    memcpy(S2, r.S, nk * m * sizeof(double));
    for (size_t t = 0; t < nk; t++)
        S2[t + nk * m] = 1.0;
    r.y[20 * k + 0] = NAN;
    r.y[30 * k + 1] = 0.0;
    r.y[31 * k + 1] = 0.0;
    const double jump[2] = {20.0, 20.0};
    igea_rls *h = make(m + 1, k, 1e8, IGEA_RLS_STANDARD, 1);
    igea_rls *h0 = make(m + 1, k, 1e8, IGEA_RLS_STANDARD, 1);
    assert_int_equal(igea_rls_set_anomaly(h, IGEA_RLS_ANOMALY_ISOLATE, INFINITY, jump), 0);
    double x0[4], g0[16], x1[4], g1[16];
    for (int e = 0; e < n; e++) {
        int fl[2] = {-1, -1};
        if (e == 20) { /* policy NONE refuses a NaN and leaves the state */
            get_state(h0, m + 1, x0, g0);
            assert_int_equal(igea_rls_update(h0, S2 + e * k, (int)nk, r.y + e * k, NULL, fl),
                             IGEA_ENONFINITE);
            get_state(h0, m + 1, x1, g1);
            assert_true(maxdiff(4, x0, x1) == 0.0 && maxdiff(16, g0, g1) == 0.0);
            assert_int_equal(fl[0], -1);
        } else {
            igea_rls_update(h0, S2 + e * k, (int)nk, r.y + e * k, NULL, NULL);
        }
        int act = igea_rls_update(h, S2 + e * k, (int)nk, r.y + e * k, NULL, fl);
        if (e == 20) {
            assert_int_equal(act, IGEA_RLS_ISOLATED);
            assert_int_equal(fl[0], IGEA_RLS_FLAG_MISSING | IGEA_RLS_FLAG_UNUSED);
            assert_int_equal(fl[1], 0);
        } else if (e == 30 || e == 31) {
            assert_int_equal(act, IGEA_RLS_ISOLATED);
            assert_int_equal(fl[1], IGEA_RLS_FLAG_JUMP | IGEA_RLS_FLAG_UNUSED);
        } else {
            assert_int_equal(act, IGEA_RLS_UPDATED);
        }
    }
    double x[4];
    igea_rls_get_x(h, x);
    for (int i = 0; i < m; i++)
        assert_close_abs(x[i], r.X[i], 0, 1e-6);
    assert_close_abs(x[m], 50.0, 0, 1e-6);
    /* SKIP with a NaN: the whole epoch is skipped */
    assert_int_equal(igea_rls_set_anomaly(h, IGEA_RLS_ANOMALY_SKIP, 4.0, NULL), 0);
    const double ynan[2] = {NAN, 1.0};
    int fl[2];
    get_state(h, m + 1, x0, g0);
    assert_int_equal(igea_rls_update(h, S2, (int)nk, ynan, NULL, fl), IGEA_RLS_SKIPPED);
    get_state(h, m + 1, x1, g1);
    assert_true(maxdiff(4, x0, x1) == 0.0 && maxdiff(16, g0, g1) == 0.0);
    assert_int_equal(fl[0], IGEA_RLS_FLAG_MISSING | IGEA_RLS_FLAG_UNUSED);
    assert_true(fl[1] & IGEA_RLS_FLAG_UNUSED);
    /* REPLACE at the very first epoch has no previous y: skipped */
    igea_rls *h2 = make(m + 1, k, 1e4, IGEA_RLS_STANDARD, 1);
    igea_rls_set_anomaly(h2, IGEA_RLS_ANOMALY_REPLACE, 4.0, NULL);
    assert_int_equal(igea_rls_update(h2, S2, (int)nk, ynan, NULL, fl), IGEA_RLS_SKIPPED);
    assert_int_equal(igea_rls_update(h2, S2, (int)nk, r.y, NULL, fl), IGEA_RLS_UPDATED);
    assert_int_equal(igea_rls_update(h2, S2 + k, (int)nk, ynan, NULL, fl), IGEA_RLS_REPLACED);
    igea_rls_free(h);
    igea_rls_free(h0);
    igea_rls_free(h2);
    free(S2);
    free_record(&r);
}

/* ---- layouts, long runs, compensation ----------------------------------- */

static void test_run_layouts(void **state)
{
    const int m = 5, k = 3, n = 40;
    record r = make_record(m, k, n, 0.1, 19);
    size_t nk = (size_t)n * k;
    r.y[7 * k] += 100.0;
    /* BLOCKS layout with lds = m + 2 and NaN padding */
    int lb = m + 2;
    double *B = malloc((size_t)lb * nk * sizeof(double));
    fill_nan(B, (size_t)lb * nk);
    for (size_t t = 0; t < nk; t++)
        for (int i = 0; i < m; i++)
            B[i + t * lb] = r.S[t + i * nk];
    /* ROWS layout with lds = nk + 3 and NaN padding */
    int lr = (int)nk + 3;
    double *R = malloc((size_t)lr * m * sizeof(double));
    fill_nan(R, (size_t)lr * m);
    for (int i = 0; i < m; i++)
        memcpy(R + (size_t)i * lr, r.S + i * nk, nk * sizeof(double));
    const double sig[3] = {0.1, 0.2, 0.3};
    double *xo[3];
    int *fo[3], *ao[3];
    for (int v = 0; v < 3; v++) {
        xo[v] = malloc((size_t)(m + 1) * n * sizeof(double));
        fill_nan(xo[v], (size_t)(m + 1) * n);
        fo[v] = calloc(nk, sizeof(int));
        ao[v] = calloc((size_t)n, sizeof(int));
        igea_rls *h = make(m, k, 10.0, IGEA_RLS_ITERATED, 4);
        igea_rls_set_anomaly(h, IGEA_RLS_ANOMALY_ISOLATE, 4.0, NULL);
        int done = -1;
        if (v == 0)
            assert_int_equal(igea_rls_run(h, n, IGEA_COLMAJOR, R, lr, r.y, sig, 0,
                                          xo[v], m + 1, fo[v], ao[v], &done), 0);
        else if (v == 1)
            assert_int_equal(igea_rls_run(h, n, IGEA_ROWMAJOR, B, lb, r.y, sig, 0,
                                          xo[v], m + 1, fo[v], ao[v], &done), 0);
        else {
            for (int e = 0; e < n; e++) {
                ao[v][e] = igea_rls_update(h, r.S + e * k, (int)nk, r.y + e * k, sig, fo[v] + e * k);
                igea_rls_get_x(h, xo[v] + (size_t)e * (m + 1));
            }
            done = n;
        }
        assert_int_equal(done, n);
        igea_rls_free(h);
    }
    for (int e = 0; e < n; e++) {
        for (int i = 0; i < m; i++) {
            assert_true(xo[0][i + e * (m + 1)] == xo[2][i + e * (m + 1)]);
            assert_true(xo[1][i + e * (m + 1)] == xo[2][i + e * (m + 1)]);
        }
        assert_true(isnan(xo[0][m + e * (m + 1)])); /* ldx padding untouched */
        assert_int_equal(ao[0][e], ao[2][e]);
        assert_int_equal(ao[1][e], ao[2][e]);
    }
    assert_int_equal(ao[2][7], IGEA_RLS_ISOLATED);
    assert_true(memcmp(fo[0], fo[2], nk * sizeof(int)) == 0);
    assert_true(memcmp(fo[1], fo[2], nk * sizeof(int)) == 0);
    for (int v = 0; v < 3; v++) {
        free(xo[v]);
        free(fo[v]);
        free(ao[v]);
    }
    /* a failing epoch stops the run: epochs before it are done */
    R[5 * k + 1] = NAN;
    igea_rls *h = make(m, k, 10.0, IGEA_RLS_STANDARD, 1);
    int done = -1;
    assert_int_equal(igea_rls_run(h, n, IGEA_COLMAJOR, R, lr, r.y, NULL, 0,
                                  NULL, m, NULL, NULL, &done), IGEA_ENONFINITE);
    assert_int_equal(done, 5);
    int cnt[4];
    igea_rls_get_counts(h, cnt);
    assert_int_equal(cnt[IGEA_RLS_COUNT_EPOCHS], 5);
    igea_rls_free(h);
    free(B);
    free(R);
    free_record(&r);
}

static void test_long_run_pd(void **state)
{
    /* 20000 epochs with forgetting and p = 5: Gamma and P stay symmetric
     * positive definite and the estimate stays on X. */
    const int m = 12, k = 3, n = 20000;
    record r = make_record(m, k, n, 0.01, 20);
    igea_rls *h = make(m, k, 1e6, IGEA_RLS_POLYNOMIAL, 5);
    igea_rls_set_forget(h, 0.999);
    int done;
    assert_int_equal(igea_rls_run(h, n, IGEA_COLMAJOR, r.S, n * k, r.y, NULL, 0,
                                  NULL, m, NULL, NULL, &done), 0);
    double g[144], c[144], x[12];
    igea_rls_get_gamma(h, g, m);
    igea_rls_get_covariance(h, c, m);
    igea_rls_get_x(h, x);
    for (int i = 0; i < m; i++) {
        assert_close_abs(x[i], r.X[i], 0, 5e-3);
        /* Gamma is the covariance of the optimal gain: P >= Gamma */
        assert_true(c[i * (m + 1)] > g[i * (m + 1)]);
    }
    assert_int_equal(LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', m, g, m), 0);
    assert_int_equal(LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', m, c, m), 0);
    igea_rls_free(h);
    free_record(&r);
}

static void test_compensate(void **state)
{
    const double x0[2] = {2.0, -1.0}, g0[4] = {1, 0, 0, 1};
    igea_rls *h = NULL;
    assert_int_equal(igea_rls_create(2, 3, x0, g0, 2, &h), 0);
    const double c[8] = {1, 2, 3, NAN, 0.5, 0, -1, NAN}; /* 3 x 2, ldc 4 */
    const double y[3] = {10, 20, 30};
    double yh[3];
    assert_int_equal(igea_rls_compensate(h, c, 4, y, yh), 0);
    assert_close(yh[0], 10 - (2 * 1 - 0.5), 1e-15);
    assert_close(yh[1], 20 - (2 * 2 - 0), 1e-15);
    assert_close(yh[2], 30 - (2 * 3 + 1), 1e-15);
    fill_sentinel(yh, 3);
    assert_int_equal(igea_rls_compensate(NULL, c, 4, y, yh), -1);
    assert_int_equal(igea_rls_compensate(h, NULL, 4, y, yh), -2);
    assert_int_equal(igea_rls_compensate(h, c, 2, y, yh), -3);
    assert_int_equal(igea_rls_compensate(h, c, 4, NULL, yh), -4);
    assert_int_equal(igea_rls_compensate(h, c, 4, y, NULL), -5);
    /* ldc 3: the second column starts at c[3] = NaN */
    assert_int_equal(igea_rls_compensate(h, c, 3, y, yh), IGEA_ENONFINITE);
    assert_true(all_sentinel(yh, 3));
    igea_rls_free(h);
}

/* ---- invalid arguments --------------------------------------------------- */

static void test_create_args(void **state)
{
    double g[3 * 4]; /* 3 x 3 with ldg 4: NaN padding and NaN upper triangle */
    fill_nan(g, 12);
    for (int j = 0; j < 3; j++)
        for (int i = j; i < 3; i++)
            g[i + 4 * j] = i == j ? 2.0 : 0.5;
    const double x0[3] = {1, 2, 3};
    igea_rls *h = (igea_rls *)&h;
    assert_int_equal(igea_rls_create(0, 2, x0, g, 4, &h), -1);
    assert_null(h);
    assert_int_equal(igea_rls_create(3, 0, x0, g, 4, &h), -2);
    assert_int_equal(igea_rls_create(3, 2, x0, NULL, 4, &h), -4);
    assert_int_equal(igea_rls_create(3, 2, x0, g, 2, &h), -5);
    assert_int_equal(igea_rls_create(3, 2, x0, g, 4, NULL), -6);
    assert_int_equal(igea_rls_create(3, 2, x0, g, 4, &h), 0);
    double gg[9], x[3];
    igea_rls_get_gamma(h, gg, 3);
    igea_rls_get_x(h, x);
    assert_true(gg[3] == 0.5 && gg[1] == 0.5 && gg[0] == 2.0);
    assert_true(x[2] == 3.0);
    igea_rls_free(h);
    igea_rls_free(NULL);
    const double xn[3] = {1, NAN, 3};
    assert_int_equal(igea_rls_create(3, 2, xn, g, 4, &h), IGEA_ENONFINITE);
    g[1] = INFINITY;
    assert_int_equal(igea_rls_create(3, 2, x0, g, 4, &h), IGEA_ENONFINITE);
    g[1] = 3.0; /* |offdiag| > sqrt(2 * 2): indefinite */
    assert_int_equal(igea_rls_create(3, 2, x0, g, 4, &h), IGEA_ESINGULAR);
    assert_null(h);
    g[1] = 0.5;
    g[0] = 0.0;
    assert_int_equal(igea_rls_create(3, 2, x0, g, 4, &h), IGEA_ESINGULAR);
}

static void test_setter_args(void **state)
{
    igea_rls *h = make(3, 2, 1.0, IGEA_RLS_STANDARD, 1);
    assert_int_equal(igea_rls_set_variant(NULL, 0, 1), -1);
    assert_int_equal(igea_rls_set_variant(h, 3, 1), -2);
    assert_int_equal(igea_rls_set_variant(h, -1, 1), -2);
    assert_int_equal(igea_rls_set_variant(h, 2, 0), -3);
    assert_int_equal(igea_rls_set_variant(h, 2, 1000001), -3);
    const double jm[2] = {1.0, 0.0}, jn[2] = {NAN, 1.0}, jok[2] = {1.0, INFINITY};
    assert_int_equal(igea_rls_set_anomaly(NULL, 0, 4, NULL), -1);
    assert_int_equal(igea_rls_set_anomaly(h, 4, 4, NULL), -2);
    assert_int_equal(igea_rls_set_anomaly(h, -1, 4, NULL), -2);
    assert_int_equal(igea_rls_set_anomaly(h, 0, 0.0, NULL), -3);
    assert_int_equal(igea_rls_set_anomaly(h, 0, NAN, NULL), -3);
    assert_int_equal(igea_rls_set_anomaly(h, 0, 4, jm), -4);
    assert_int_equal(igea_rls_set_anomaly(h, 0, 4, jn), -4);
    assert_int_equal(igea_rls_set_anomaly(h, 1, INFINITY, jok), 0);
    assert_int_equal(igea_rls_set_forget(NULL, 1.0), -1);
    assert_int_equal(igea_rls_set_forget(h, 0.0), -2);
    assert_int_equal(igea_rls_set_forget(h, 1.5), -2);
    assert_int_equal(igea_rls_set_forget(h, NAN), -2);
    assert_int_equal(igea_rls_set_forget(h, 1.0), 0);
    double x[3], g[9], q;
    int cnt[4], mm, kk;
    assert_int_equal(igea_rls_get_x(NULL, x), -1);
    assert_int_equal(igea_rls_get_x(h, NULL), -2);
    assert_int_equal(igea_rls_get_gamma(NULL, g, 3), -1);
    assert_int_equal(igea_rls_get_gamma(h, NULL, 3), -2);
    assert_int_equal(igea_rls_get_gamma(h, g, 2), -3);
    assert_int_equal(igea_rls_get_covariance(NULL, g, 3), -1);
    assert_int_equal(igea_rls_get_covariance(h, NULL, 3), -2);
    assert_int_equal(igea_rls_get_covariance(h, g, 2), -3);
    assert_int_equal(igea_rls_get_q(NULL, &q), -1);
    assert_int_equal(igea_rls_get_q(h, NULL), -2);
    assert_int_equal(igea_rls_get_counts(NULL, cnt), -1);
    assert_int_equal(igea_rls_get_counts(h, NULL), -2);
    assert_int_equal(igea_rls_get_size(NULL, &mm, &kk), -1);
    assert_int_equal(igea_rls_get_size(h, &mm, &kk), 0);
    assert_int_equal(mm, 3);
    assert_int_equal(kk, 2);
    igea_rls_free(h);
}

static void test_update_args(void **state)
{
    igea_rls *h = make(3, 2, 1.0, IGEA_RLS_POLYNOMIAL, 3);
    double c[9] = {1, 2, NAN, 0, 1, NAN, 1, 1, NAN}; /* 2 x 3, ldc 3 */
    double y[2] = {1, 2}, sig[2] = {1, 2};
    int fl[2] = {-7, -7};
    assert_int_equal(igea_rls_update(NULL, c, 3, y, sig, fl), -1);
    assert_int_equal(igea_rls_update(h, NULL, 3, y, sig, fl), -2);
    assert_int_equal(igea_rls_update(h, c, 1, y, sig, fl), -3);
    assert_int_equal(igea_rls_update(h, c, 3, NULL, sig, fl), -4);
    assert_int_equal(igea_rls_update(h, c, 2, y, sig, fl), IGEA_ENONFINITE); /* reads NaN */
    sig[1] = 0.0;
    assert_int_equal(igea_rls_update(h, c, 3, y, sig, fl), IGEA_ENONPOSITIVE);
    sig[1] = -1.0;
    assert_int_equal(igea_rls_update(h, c, 3, y, sig, fl), IGEA_ENONPOSITIVE);
    sig[1] = NAN;
    assert_int_equal(igea_rls_update(h, c, 3, y, sig, fl), IGEA_ENONFINITE);
    sig[1] = 2.0;
    y[0] = INFINITY;
    assert_int_equal(igea_rls_update(h, c, 3, y, sig, fl), IGEA_ENONFINITE);
    y[0] = 1.0;
    c[1] = NAN;
    assert_int_equal(igea_rls_update(h, c, 3, y, sig, fl), IGEA_ENONFINITE);
    c[1] = 2.0;
    assert_int_equal(fl[0], -7); /* flags untouched on failure */
    int cnt[4];
    igea_rls_get_counts(h, cnt);
    assert_int_equal(cnt[IGEA_RLS_COUNT_EPOCHS], 0);
    double x[3], g[9];
    igea_rls_get_x(h, x);
    igea_rls_get_gamma(h, g, 3);
    assert_true(x[0] == 0.0 && g[0] == 1.0 && g[1] == 0.0);
    assert_int_equal(igea_rls_update(h, c, 3, y, sig, fl), 0);
    assert_int_equal(fl[0], 0);
    /* a non-finite result (overflowing data) is refused, state kept */
    double big[6] = {1e200, 0, 0, 1e200, 0, 0}, yb[2] = {1e300, 1e300};
    igea_rls_get_x(h, x);
    assert_true(igea_rls_update(h, big, 2, yb, NULL, fl) < 0);
    double x2[3];
    igea_rls_get_x(h, x2);
    assert_true(maxdiff(3, x, x2) == 0.0);
    /* run arguments */
    int done = 7;
    assert_int_equal(igea_rls_run(NULL, 1, 0, c, 2, y, NULL, 0, NULL, 3, NULL, NULL, &done), -1);
    assert_int_equal(done, 7); /* an invalid argument leaves n_done untouched */
    assert_int_equal(igea_rls_run(h, -1, 0, c, 2, y, NULL, 0, NULL, 3, NULL, NULL, &done), -2);
    assert_int_equal(igea_rls_run(h, 1, 0, c, 2, y, sig, 2, NULL, 3, NULL, NULL, &done), -8);
    assert_int_equal(done, 7);
    assert_int_equal(igea_rls_run(h, -1, 0, c, 2, y, NULL, 0, NULL, 3, NULL, NULL, NULL), -2);
    assert_int_equal(igea_rls_run(h, 1, 2, c, 2, y, NULL, 0, NULL, 3, NULL, NULL, NULL), -3);
    assert_int_equal(igea_rls_run(h, 1, 0, NULL, 2, y, NULL, 0, NULL, 3, NULL, NULL, NULL), -4);
    assert_int_equal(igea_rls_run(h, 1, 0, c, 1, y, NULL, 0, NULL, 3, NULL, NULL, NULL), -5);
    assert_int_equal(igea_rls_run(h, 1, 1, c, 2, y, NULL, 0, NULL, 3, NULL, NULL, NULL), -5);
    assert_int_equal(igea_rls_run(h, 1, 0, c, 2, NULL, NULL, 0, NULL, 3, NULL, NULL, NULL), -6);
    assert_int_equal(igea_rls_run(h, 1, 0, c, 2, y, sig, 2, NULL, 3, NULL, NULL, NULL), -8);
    double xo[3];
    assert_int_equal(igea_rls_run(h, 1, 0, c, 2, y, NULL, 0, xo, 2, NULL, NULL, NULL), -10);
    assert_int_equal(igea_rls_run(h, 0, 0, NULL, 1, NULL, NULL, 0, NULL, 3, NULL, NULL, &done), 0);
    assert_int_equal(done, 0);
    igea_rls_free(h);
}

/* Switching the honest covariance off changes neither xhat nor Gamma. */
static void test_covariance_switch(void **state)
{
    record r = make_record(5, 3, 50, 0.1, 21);
    igea_rls *h1 = make(5, 3, 10.0, IGEA_RLS_POLYNOMIAL, 4);
    igea_rls *h2 = make(5, 3, 10.0, IGEA_RLS_POLYNOMIAL, 4);
    assert_int_equal(igea_rls_set_covariance(NULL, 0), -1);
    assert_int_equal(igea_rls_set_covariance(h2, 2), -2);
    assert_int_equal(igea_rls_set_covariance(h2, 0), 0);
    double cv[25];
    assert_int_equal(igea_rls_get_covariance(h2, cv, 5), 0); /* still Gamma_0 */
    feed(h1, &r, 0, r.n);
    feed(h2, &r, 0, r.n);
    assert_int_equal(igea_rls_set_covariance(h2, 1), IGEA_EDOMAIN);
    double x1[5], x2[5], g1[25], g2[25];
    get_state(h1, 5, x1, g1);
    get_state(h2, 5, x2, g2);
    assert_true(maxdiff(5, x1, x2) == 0.0 && maxdiff(25, g1, g2) == 0.0);
    fill_sentinel(cv, 25);
    assert_int_equal(igea_rls_get_covariance(h2, NULL, 5), -2);
    assert_int_equal(igea_rls_get_covariance(h2, cv, 4), -3);
    assert_int_equal(igea_rls_get_covariance(h2, cv, 5), IGEA_EDOMAIN);
    assert_true(all_sentinel(cv, 25));
    assert_int_equal(igea_rls_get_covariance(h1, cv, 5), 0);
    igea_rls_free(h1);
    igea_rls_free(h2);
    free_record(&r);
}

/* igea_rls_create fails cleanly at each of its allocations; afterwards
 * igea_rls_update and igea_rls_run allocate nothing. */
static void test_allocation(void **state)
{
#ifdef OOM_DISABLED
    skip();
#else
    oom_fail_at = 0; /* probe: under valgrind this malloc is not ours */
    oom_calls = 0;
    void *(*volatile call_malloc)(size_t) = malloc; /* not elided by the compiler */
    void *probe = call_malloc(16);
    oom_fail_at = -1;
    if (probe) {
        free(probe);
        skip();
    }
    double g[16] = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2};
    igea_rls *h = NULL;
    int ok = 0;
    for (long k = 0; k < 10 && !ok; k++) {
        h = (igea_rls *)&h;
        oom_fail_at = k;
        oom_calls = 0;
        int st = igea_rls_create(4, 2, NULL, g, 4, &h);
        oom_fail_at = -1;
        if (st == 0) {
            ok = 1;
            assert_true(k >= 1); /* at least one allocation was failed first */
        } else {
            assert_int_equal(st, IGEA_ENOMEM);
            assert_null(h);
        }
    }
    assert_true(ok);
    record r = make_record(4, 2, 50, 0.1, 22);
    igea_rls_set_variant(h, IGEA_RLS_POLYNOMIAL, 5);
    igea_rls_set_anomaly(h, IGEA_RLS_ANOMALY_ISOLATE, 4.0, NULL);
    feed(h, &r, 0, 1); /* BLAS may set itself up on its first call */
    oom_fail_at = 1000000;
    oom_calls = 0;
    feed(h, &r, 1, 40);
    int done;
    assert_int_equal(igea_rls_run(h, 10, IGEA_COLMAJOR, r.S + 80, 100, r.y + 80, NULL,
                                  0, NULL, 4, NULL, NULL, &done), 0);
    long during = oom_calls;
    oom_fail_at = -1;
    assert_int_equal(during, 0);
    igea_rls_free(h);
    free_record(&r);
#endif
}

static void test_sigma_range(void **state)
{
    (void)state;
    /* A denormal tracking sigma: IGEA_ERANGE (its weight 1/sigma^2 would be
     * Inf), the state untouched; 2^-511 is accepted. */
    igea_rls *h = make(2, 2, 1e4, IGEA_RLS_STANDARD, 1);
    double c[4] = {1, 0, 0.5, 1}, y[2] = {0.3, -0.2}, x0[2], x1[2];
    assert_int_equal(igea_rls_get_x(h, x0), 0);
    const double bad[3] = {4e-320, 1e-160, 0x1p-512};
    for (int t = 0; t < 3; t++) {
        double sg[2] = {0.1, bad[t]};
        assert_int_equal(igea_rls_update(h, c, 2, y, sg, NULL), IGEA_ERANGE);
        assert_int_equal(igea_rls_get_x(h, x1), 0);
        assert_true(x1[0] == x0[0] && x1[1] == x0[1]);
    }
    double sg[2] = {0.1, IGEA_SIGMA_MIN * 1e150};
    assert_true(igea_rls_update(h, c, 2, y, sg, NULL) >= 0);
    igea_rls_free(h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vector),
        cmocka_unit_test(test_iterated_equals_polynomial),
        cmocka_unit_test(test_q_decreases),
        cmocka_unit_test(test_batch_limit),
        cmocka_unit_test(test_forget),
        cmocka_unit_test(test_zero_c),
        cmocka_unit_test(test_whitening),
        cmocka_unit_test(test_anomaly_policies),
        cmocka_unit_test(test_dropouts),
        cmocka_unit_test(test_run_layouts),
        cmocka_unit_test(test_long_run_pd),
        cmocka_unit_test(test_compensate),
        cmocka_unit_test(test_covariance_switch),
        cmocka_unit_test(test_allocation),
        cmocka_unit_test(test_create_args),
        cmocka_unit_test(test_setter_args),
        cmocka_unit_test(test_update_args),
        cmocka_unit_test(test_sigma_range),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
