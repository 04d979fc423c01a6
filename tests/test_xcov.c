/* Tests of igea_whiten_accumulate_xcov and igea_noise_eqerr_xcov (igea/noise.h):
 * the whole K of igea dw (diagonal blocks K_ee, cross blocks X_e = Cov(dW_e,
 * dW_f) for every f > e) against a dense generalised least squares written
 * here: K built as a 3M x 3M matrix, its Cholesky factor by the textbook
 * loop, the normal equations by forward substitution. */
#include "testutil.h"

#include "igea.h"

enum { MEP = 23, NT = 4, MR = 3 * MEP };

static unsigned seed_;
static double urand(void) /* [-1, 1) */
{
    seed_ = seed_ * 1103515245u + 12345u;
    return ((seed_ >> 8) & 0xffffff) / 8388608.0 - 1.0;
}

/* K of the dw structure: dW_e = E_e eps_e + sum_(j<e) G_j eps_j with eps_j
 * independent, cov Q_j (6 x 6): K_ee = R_e + E_e Q_e E_e', X_e = R_e + E_e Q_e
 * G_e', R_e = sum_(j<e) G_j Q_j G_j'. walk scales G. k6 lower by rows, x9
 * row-major, Kd the dense 3M x 3M (column-major). */
static void make_k(int M, double walk, double *k6, double *x9, double *Kd)
{
    double R[9] = {0};
    for (int e = 0; e < M; e++) {
        double F[36], Q[36], E[18], G[18], EQ[18], GQ[18], Ke[9], Xe[9];
        for (int i = 0; i < 36; i++)
            F[i] = urand();
        for (int i = 0; i < 6; i++) /* Q = F F' + 0.5 I */
            for (int j = 0; j < 6; j++) {
                double s = i == j ? 0.5 : 0.0;
                for (int k = 0; k < 6; k++)
                    s += F[i + 6 * k] * F[j + 6 * k];
                Q[i + 6 * j] = s;
            }
        for (int i = 0; i < 18; i++)
            E[i] = urand(), G[i] = walk * urand();
        for (int i = 0; i < 3; i++) /* EQ = E Q, GQ = G Q (3 x 6, row-major) */
            for (int j = 0; j < 6; j++) {
                double s = 0, t = 0;
                for (int k = 0; k < 6; k++)
                    s += E[6 * i + k] * Q[k + 6 * j], t += G[6 * i + k] * Q[k + 6 * j];
                EQ[6 * i + j] = s, GQ[6 * i + j] = t;
            }
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double a = 0, x = 0, r = 0;
                for (int k = 0; k < 6; k++) {
                    a += EQ[6 * i + k] * E[6 * j + k];
                    x += EQ[6 * i + k] * G[6 * j + k];
                    r += GQ[6 * i + k] * G[6 * j + k];
                }
                Ke[3 * i + j] = R[3 * i + j] + a;
                Xe[3 * i + j] = R[3 * i + j] + x;
                R[3 * i + j] += r;
            }
        double c6[6] = {Ke[0], Ke[3], Ke[4], Ke[6], Ke[7], Ke[8]};
        memcpy(k6 + 6 * e, c6, sizeof c6);
        memcpy(x9 + 9 * e, Xe, sizeof Xe);
    }
    const int n = 3 * M;
    for (int e = 0; e < M; e++)
        for (int f = 0; f < M; f++)
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) {
                    double v;
                    if (e == f) {
                        const double *c = k6 + 6 * e;
                        int r = i > j ? i : j, s = i > j ? j : i;
                        v = c[r * (r + 1) / 2 + s];
                    } else if (e < f) {
                        v = x9[9 * e + 3 * i + j];
                    } else {
                        v = x9[9 * f + 3 * j + i];
                    }
                    Kd[(3 * e + i) + (size_t)n * (3 * f + j)] = v;
                }
}

/* Lower Cholesky factor in place (column-major n x n); 0 or 1. */
static int chol(int n, double *A)
{
    for (int j = 0; j < n; j++) {
        double d = A[j + n * j];
        for (int k = 0; k < j; k++)
            d -= A[j + n * k] * A[j + n * k];
        if (!(d > 0))
            return 1;
        d = sqrt(d);
        A[j + n * j] = d;
        for (int i = j + 1; i < n; i++) {
            double s = A[i + n * j];
            for (int k = 0; k < j; k++)
                s -= A[i + n * k] * A[j + n * k];
            A[i + n * j] = s / d;
        }
    }
    return 0;
}

/* x <- L^-1 x (forward substitution). */
static void fsub(int n, const double *L, double *x)
{
    for (int i = 0; i < n; i++) {
        double s = x[i];
        for (int k = 0; k < i; k++)
            s -= L[i + n * k] * x[k];
        x[i] = s / L[i + n * i];
    }
}

/* The dense reference: Z = L^-1 [S D, dw] (n x (N + 1), column-major), and
 * the normal equations A = Z_S' Z_S, b = Z_S' Z_w, ww = Z_w' Z_w. */
static void dense_gls(int n, int N, const double *Kd, const double *S, const double *dw,
                      const double *spec, double *Z, double *A, double *b, double *ww)
{
    double *L = malloc(sizeof(double) * n * n);
    assert_non_null(L);
    memcpy(L, Kd, sizeof(double) * n * n);
    assert_int_equal(chol(n, L), 0);
    for (int c = 0; c <= N; c++) {
        for (int i = 0; i < n; i++)
            Z[i + n * c] = c == N ? dw[i] : S[i + n * c] * (spec ? spec[c] : 1.0);
        fsub(n, L, Z + n * c);
    }
    for (int r = 0; r <= N; r++)
        for (int c = 0; c <= N; c++) {
            double s = 0;
            for (int i = 0; i < n; i++)
                s += Z[i + n * r] * Z[i + n * c];
            if (r < N && c < N)
                A[r + N * c] = s;
            else if (r < N && c == N)
                b[r] = s;
            else if (r == N && c == N)
                *ww = s;
        }
    free(L);
}

static double S_[MR * NT], dw_[MR], spec_[NT], k6_[6 * MEP], x9_[9 * MEP], Kd_[MR * MR];

static void make_flight(unsigned seed, double walk)
{
    seed_ = seed;
    for (int i = 0; i < MR * NT; i++)
        S_[i] = urand();
    for (int i = 0; i < MR; i++)
        dw_[i] = urand();
    for (int j = 0; j < NT; j++)
        spec_[j] = 1.0 + 0.3 * j;
    make_k(MEP, walk, k6_, x9_, Kd_);
}

/* Stream the flight through a fresh whitener in blocks of the given epochs,
 * in the given layout; sums into A, b, wtw, whitened rows into Z. */
static int stream(int layout, const int *cuts, int ncut, const int *mask, double *A,
                  double *b, double *wtw, double *Z)
{
    igea_whiten *w = NULL;
    assert_int_equal(igea_whiten_create(NT, 0, NULL, 1, &w), 0);
    double Sr[MR * NT], zb[MR * (NT + 1)];
    for (int i = 0; i < MR; i++) /* row-major copy */
        for (int c = 0; c < NT; c++)
            Sr[c + NT * i] = S_[i + MR * c];
    int st = 0, e0 = 0;
    for (int k = 0; k <= ncut && st == 0; k++) {
        int e1 = k < ncut ? cuts[k] : MEP, m = 3 * (e1 - e0);
        const double *Sb = layout == IGEA_COLMAJOR ? S_ + 3 * e0 : Sr + NT * 3 * e0;
        int lds = layout == IGEA_COLMAJOR ? MR : NT;
        st = igea_whiten_accumulate_xcov(w, layout, m, Sb, lds, dw_ + 3 * e0, k6_ + 6 * e0,
                                         x9_ + 9 * e0, mask ? mask + 3 * e0 : NULL, spec_, A, NT,
                                         b, wtw, zb, NULL);
        for (int c = 0; c <= NT && st == 0; c++)
            memcpy(Z + MR * c + 3 * e0, zb + (size_t)m * c, sizeof(double) * m);
        e0 = e1;
    }
    igea_whiten_free(w);
    return st;
}

/* The sums and the whitened rows equal the dense GLS with the full K, in
 * one block and cut anywhere, both layouts: the whitened rows are those
 * of the inverse Cholesky factor of the whole K (the unique lower
 * triangular whitening with a positive diagonal). */
static void test_equals_dense_gls(void **state)
{
    (void)state;
    static const double walks[] = {0.0, 0.3, 1.5};
    for (int t = 0; t < 3; t++) {
        make_flight(11u + t, walks[t]);
        double Ar[NT * NT], br[NT], wr, Zr[MR * (NT + 1)];
        dense_gls(MR, NT, Kd_, S_, dw_, spec_, Zr, Ar, br, &wr);
        static const int cuts[][4] = {{MEP, MEP, MEP, MEP}, {1, 2, 9, 22}, {5, 11, 12, 17}};
        for (int layout = 0; layout < 2; layout++)
            for (int c = 0; c < 3; c++) {
                double A[NT * NT] = {0}, b[NT] = {0}, wtw[2] = {0}, Z[MR * (NT + 1)];
                assert_int_equal(stream(layout ? IGEA_ROWMAJOR : IGEA_COLMAJOR, cuts[c],
                                        c ? 4 : 0, NULL, A, b, wtw, Z),
                                 0);
                for (int i = 0; i < NT * NT; i++)
                    assert_close_abs(A[i], Ar[i], 1e-10, 1e-12 * fabs(Ar[0]));
                for (int i = 0; i < NT; i++)
                    assert_close_abs(b[i], br[i], 1e-10, 1e-12 * fabs(Ar[0]));
                assert_close(wtw[0], wr, 1e-10);
                assert_true(wtw[1] == MR);
                for (int i = 0; i < MR * (NT + 1); i++)
                    assert_close_abs(Z[i], Zr[i], 1e-10, 1e-12);
            }
    }
}

/* A masked row leaves the sums (the recursion still carries it): the sums
 * equal the dense ones without that whitened row. */
static void test_mask(void **state)
{
    (void)state;
    make_flight(21u, 0.7);
    double Ar[NT * NT], br[NT], wr, Zr[MR * (NT + 1)];
    dense_gls(MR, NT, Kd_, S_, dw_, spec_, Zr, Ar, br, &wr);
    int mask[MR] = {0};
    mask[4] = mask[40] = mask[MR - 1] = 1;
    for (int i = 0; i < MR; i++)
        if (mask[i]) {
            for (int r = 0; r < NT; r++) {
                for (int c = 0; c < NT; c++)
                    Ar[r + NT * c] -= Zr[i + MR * r] * Zr[i + MR * c];
                br[r] -= Zr[i + MR * r] * Zr[i + MR * NT];
            }
            wr -= Zr[i + MR * NT] * Zr[i + MR * NT];
        }
    static const int cuts[] = {3, 14};
    double A[NT * NT] = {0}, b[NT] = {0}, wtw[2] = {0}, Z[MR * (NT + 1)];
    assert_int_equal(stream(IGEA_COLMAJOR, cuts, 2, mask, A, b, wtw, Z), 0);
    for (int i = 0; i < NT * NT; i++)
        assert_close_abs(A[i], Ar[i], 1e-10, 1e-12 * fabs(Ar[0]));
    for (int i = 0; i < NT; i++)
        assert_close_abs(b[i], br[i], 1e-10, 1e-12 * fabs(Ar[0]));
    assert_close(wtw[0], wr, 1e-10);
    assert_true(wtw[1] == MR - 3);
    for (int i = 0; i < MR * (NT + 1); i++) /* masked rows reported whitened too */
        assert_close_abs(Z[i], Zr[i], 1e-10, 1e-12);
}

/* A pure random walk: dW_e = sum_(j<=e) u_j, u_j of covariance q_j I, so
 * K_ee = X_e = (sum_(j<=e) q_j) I and the differenced rows are the u_j. */
static void walk_k(int E, const double *q, double *k6, double *x9)
{
    double tot = 0;
    for (int e = 0; e < E; e++) {
        tot += q[e];
        double c6[6] = {tot, 0, tot, 0, 0, tot};
        memcpy(k6 + 6 * e, c6, sizeof c6);
        for (int k = 0; k < 9; k++)
            x9[9 * e + k] = k % 4 == 0 ? tot : 0.0;
    }
}

/* dw' K^-1 dw of that walk: the sum of the squared differences over q_e. */
static double walk_ww(int E, const double *q, const double *dw)
{
    double s = 0;
    for (int i = 0; i < 3 * E; i++) {
        double d = dw[i] - (i >= 3 ? dw[i - 3] : 0.0);
        s += d * d / q[i / 3];
    }
    return s;
}

/* Cross blocks that are not those of one positive definite K: refused at
 * the epoch where the differenced covariance given the earlier epochs
 * stops being positive definite, outputs and handle untouched (a later
 * valid call gives the sums of a fresh one). The same for an epoch whose
 * conditional variance is below IGEA_WHITEN_XCOV_RTOL of its variance. */
static void test_refusals(void **state)
{
    (void)state;
    /* a pure random walk: dW_e = sum_(j<=e) u_j, u_j of covariance q_j I:
       K_ee = X_e = (sum_(j<=e) q_j) I; the differenced rows are the u_j */
    enum { E = 8 };
    double k6[6 * E], x9[9 * E], S[3 * E * 2], dw[3 * E], A[4], b[2], wtw[2];
    double q[E] = {1, 0.5, 2, 1, 1, 0.3, 1, 1};
    seed_ = 5u;
    for (int i = 0; i < 6 * E; i++)
        S[i] = urand();
    for (int i = 0; i < 3 * E; i++)
        dw[i] = urand();
    walk_k(E, q, k6, x9);
    igea_whiten *w = NULL;
    assert_int_equal(igea_whiten_create(2, 0, NULL, 1, &w), 0);
    /* the reference: the differenced rows scaled by 1/sqrt(q_e) */
    double Ar[4] = {0}, br[2] = {0}, wr = 0;
    for (int e = 0; e < E; e++)
        for (int a = 0; a < 3; a++) {
            int i = 3 * e + a;
            double z[3];
            for (int c = 0; c < 3; c++) {
                const double *x = c < 2 ? S + 3 * E * c : dw;
                z[c] = (x[i] - (e ? x[i - 3] : 0.0)) / sqrt(q[e]);
            }
            for (int r = 0; r < 2; r++) {
                for (int c = 0; c < 2; c++)
                    Ar[r + 2 * c] += z[r] * z[c];
                br[r] += z[r] * z[2];
            }
            wr += z[2] * z[2];
        }
    /* X_4 too large: the increment of epoch 5 would have a negative variance */
    double x4 = x9[9 * 4];
    x9[9 * 4] = x9[9 * 4 + 4] = x9[9 * 4 + 8] = x4 + 0.6 * q[5] + 0.5 * (k6[6 * 5] - x4);
    fill_sentinel(A, 4), fill_sentinel(b, 2), fill_sentinel(wtw, 2);
    int bad = -1;
    assert_int_equal(igea_whiten_accumulate_xcov(w, IGEA_COLMAJOR, 3 * E, S, 3 * E, dw, k6, x9,
                                                 NULL, NULL, A, 2, b, wtw, NULL, &bad),
                     IGEA_ESINGULAR);
    assert_int_equal(bad, 5);
    assert_true(all_sentinel(A, 4) && all_sentinel(b, 2) && all_sentinel(wtw, 2));
    x9[9 * 4] = x9[9 * 4 + 4] = x9[9 * 4 + 8] = x4;
    /* a nearly singular epoch: the increment of epoch 6 at 1e-12 of K_55 */
    double q6 = q[6];
    q[6] = 1e-12 * (k6[30]);
    walk_k(E, q, k6, x9);
    bad = -1;
    assert_int_equal(igea_whiten_accumulate_xcov(w, IGEA_COLMAJOR, 3 * E, S, 3 * E, dw, k6, x9,
                                                 NULL, NULL, A, 2, b, wtw, NULL, &bad),
                     IGEA_ESINGULAR);
    assert_int_equal(bad, 6);
    assert_true(all_sentinel(A, 4) && all_sentinel(b, 2) && all_sentinel(wtw, 2));
    /* at 1e-8 it is judged (the conditional variance is then 1e-8 / 2 of the
       magnitudes it is computed from) */
    q[6] = 1e-8 * (k6[30]);
    walk_k(E, q, k6, x9);
    double A2[4] = {0}, b2[2] = {0}, w2[2] = {0};
    assert_int_equal(igea_whiten_accumulate_xcov(w, IGEA_COLMAJOR, 3 * E, S, 3 * E, dw, k6, x9,
                                                 NULL, NULL, A2, 2, b2, w2, NULL, &bad),
                     0);
    assert_close(w2[0], walk_ww(E, q, dw), 1e-6);
    igea_whiten_reset(w);
    q[6] = q6;
    walk_k(E, q, k6, x9);
    /* after the refusals the handle is as fresh: the exact sums */
    memset(A, 0, sizeof A), memset(b, 0, sizeof b), memset(wtw, 0, sizeof wtw);
    assert_int_equal(igea_whiten_accumulate_xcov(w, IGEA_COLMAJOR, 3 * E, S, 3 * E, dw, k6, x9,
                                                 NULL, NULL, A, 2, b, wtw, NULL, &bad),
                     0);
    for (int i = 0; i < 4; i++)
        assert_close(A[i], Ar[i], 1e-12);
    for (int i = 0; i < 2; i++)
        assert_close(b[i], br[i], 1e-12);
    assert_close(wtw[0], wr, 1e-12);
    /* NaN in a cross block: IGEA_ENONFINITE */
    igea_whiten_reset(w);
    x9[9 * 3 + 1] = NAN;
    assert_int_equal(igea_whiten_accumulate_xcov(w, IGEA_COLMAJOR, 3 * E, S, 3 * E, dw, k6, x9,
                                                 NULL, NULL, A, 2, b, wtw, NULL, &bad),
                     IGEA_ENONFINITE);
    x9[9 * 3 + 1] = 0.0;
    /* one handle, one kind of accumulation since its reset */
    double one = 1.0;
    igea_whiten_reset(w);
    assert_int_equal(igea_whiten_accumulate(w, IGEA_COLMAJOR, 3, S, 3 * E, dw, &one, 0, NULL,
                                            NULL, NULL, NULL, A, 2, b, wtw, NULL, NULL),
                     0);
    assert_int_equal(igea_whiten_accumulate_xcov(w, IGEA_COLMAJOR, 3, S, 3 * E, dw, k6, x9,
                                                 NULL, NULL, A, 2, b, wtw, NULL, NULL),
                     -1);
    igea_whiten_reset(w);
    assert_int_equal(igea_whiten_accumulate_xcov(w, IGEA_COLMAJOR, 3, S, 3 * E, dw, k6, x9,
                                                 NULL, NULL, A, 2, b, wtw, NULL, NULL),
                     0);
    assert_int_equal(igea_whiten_accumulate(w, IGEA_COLMAJOR, 3, S, 3 * E, dw, &one, 0, NULL,
                                            NULL, NULL, NULL, A, 2, b, wtw, NULL, NULL),
                     -1);
    igea_whiten_free(w);
    double phi[3] = {0.5, 0.5, 0.5};
    assert_int_equal(igea_whiten_create(2, 1, phi, 1, &w), 0); /* AR: not for the whole K */
    assert_int_equal(igea_whiten_accumulate_xcov(w, IGEA_COLMAJOR, 3, S, 3 * E, dw, k6, x9,
                                                 NULL, NULL, A, 2, b, wtw, NULL, NULL),
                     -1);
    igea_whiten_free(w);
    assert_int_equal(igea_whiten_create(2, 0, NULL, 2, &w), 0); /* groups: neither */
    assert_int_equal(igea_whiten_accumulate_xcov(w, IGEA_COLMAJOR, 3, S, 3 * E, dw, k6, x9,
                                                 NULL, NULL, A, 2, b, wtw, NULL, NULL),
                     -1);
    igea_whiten_free(w);
}

/* The job with the whole K equals igea_noise_eqerr on the rows whitened
 * here by the dense Cholesky factor (sigma 1): eigenvalues, equivalent
 * errors, z and the chi-square; AR options refused. */
static void test_noise_job(void **state)
{
    (void)state;
    make_flight(31u, 1.0);
    /* dw = S D x + L u: a flight within spec (scaled so components are tested) */
    double *L = malloc(sizeof(double) * MR * MR), Z[MR * (NT + 1)], Ar[NT * NT], br[NT], wr;
    assert_non_null(L);
    memcpy(L, Kd_, sizeof(double) * MR * MR);
    assert_int_equal(chol(MR, L), 0);
    for (int i = 0; i < MR * NT; i++)
        S_[i] *= 30.0;
    for (int i = 0; i < MR; i++) {
        double s = 0;
        for (int k = 0; k <= i; k++)
            s += L[i + MR * k] * urand();
        for (int c = 0; c < NT; c++)
            s += S_[i + MR * c] * spec_[c] * 0.5 * urand();
        dw_[i] = s;
    }
    free(L);
    dense_gls(MR, NT, Kd_, S_, dw_, spec_, Z, Ar, br, &wr);
    double opts[IGEA_EQERR_OPT_LEN];
    igea_eqerr_defaults(opts);
    double lam[NT], P[NT * NT], xh[NT], z[NT], info[IGEA_STATS_INFO_LEN], go[IGEA_NOISE_GROUP_COLS];
    double lam2[NT], P2[NT * NT], xh2[NT], z2[NT], info2[IGEA_STATS_INFO_LEN], one = 1.0;
    double rw[MR], res[MR];
    int rej[NT], rej2[NT];
    assert_int_equal(igea_noise_eqerr_xcov(MR, NT, S_, MR, dw_, k6_, x9_, spec_, opts, lam, P,
                                           NT, xh, z, rej, info, go, rw, res),
                     0);
    /* the reference: the dense whitened rows (spec already applied) */
    assert_int_equal(igea_noise_eqerr(MR, NT, Z, MR, Z + MR * NT, &one, 0, NULL, NULL, 1, NULL,
                                      NULL, opts, lam2, P2, NT, xh2, z2, rej2, info2, NULL,
                                      NULL, NULL),
                     0);
    for (int i = 0; i < NT; i++) {
        assert_close(lam[i], lam2[i], 1e-10);
        assert_close_abs(fabs(xh[i]), fabs(xh2[i]), 1e-10, 1e-12);
        assert_int_equal(rej[i], rej2[i]);
    }
    assert_true(info[IGEA_STATS_INFO_N_TEST] == info2[IGEA_STATS_INFO_N_TEST]);
    assert_true(info[IGEA_STATS_INFO_N_TEST] >= 1);
    assert_close(info[IGEA_STATS_INFO_CHI2], info2[IGEA_STATS_INFO_CHI2], 1e-10);
    assert_close(info[IGEA_STATS_INFO_SCALE], info2[IGEA_STATS_INFO_SCALE], 1e-10);
    assert_true(info[IGEA_STATS_INFO_PASSED] == info2[IGEA_STATS_INFO_PASSED]);
    /* the eigenvalues are those of the dense normal matrix's (trace check) */
    double tr = 0, trr = 0;
    for (int i = 0; i < NT; i++)
        tr += lam[i], trr += Ar[i + NT * i];
    assert_close(tr, trr, 1e-10);
    /* the whitened residuals are the dense ones of the full-rank fit */
    double x[NT];
    {
        double C[NT * NT];
        memcpy(C, Ar, sizeof C);
        assert_int_equal(chol(NT, C), 0);
        memcpy(x, br, sizeof x);
        fsub(NT, C, x);
        for (int i = NT - 1; i >= 0; i--) { /* back substitution with C' */
            double s = x[i];
            for (int k = i + 1; k < NT; k++)
                s -= C[k + NT * i] * x[k];
            x[i] = s / C[i + NT * i];
        }
    }
    for (int i = 0; i < MR; i++) {
        double e = Z[i + MR * NT];
        for (int c = 0; c < NT; c++)
            e -= Z[i + MR * c] * x[c];
        assert_close_abs(res[i], e, 1e-9, 1e-11);
    }
    opts[IGEA_EQERR_OPT_AR] = 1;
    fill_sentinel(lam, NT);
    assert_int_equal(igea_noise_eqerr_xcov(MR, NT, S_, MR, dw_, k6_, x9_, spec_, opts, lam, P,
                                           NT, xh, z, rej, info, go, rw, res),
                     -9);
    assert_true(all_sentinel(lam, NT));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_equals_dense_gls),
        cmocka_unit_test(test_mask),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_noise_job),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
