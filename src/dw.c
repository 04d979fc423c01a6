/* dw.c - telemetry minus tracking: apparent-velocity differences at the
 * tracking epochs in LI (igea/dw.h, docs/pipeline.md). */
#include <math.h>
#include <string.h>

#include "igea/dw.h"
#include "igea/envfun.h"
#include "igea/nav.h"
#include "internal.h"
#include "rotation.h"

#define T(k) tel[(size_t)(k)]
#define TEL(k, c) IGEA_AT(tel, ldtel, k, c)
#define TRK(k, c) IGEA_AT(trk, ldtrk, k, c)

typedef struct {
    const double *site, *q0, *tel, *trk;
    double tau;
    int system, kind, ntel, ldtel, tel_cols, frame, ntrk, ldtrk, trk_cols;
} dw_in;

static int check_args(const dw_in *a, const double *dw, const double *cov, const int *bad)
{
    double probe[3] = {0.0, 0.0, 0.0}, g[3];
    if (!a->site || igea_nav_gravity_li(a->site, IGEA_NAV_GRAVITY_J2, probe, g, NULL))
        return -1;
    int sd = a->system == IGEA_ENVFUN_STRAPDOWN;
    if (!sd && a->system != IGEA_ENVFUN_PLATFORM)
        return -2;
    if (a->kind != IGEA_DW_APPARENT && a->kind != IGEA_DW_NAVIGATED)
        return -3;
    if (sd && a->q0) {
        double n = 0.0;
        for (int i = 0; i < 4; i++)
            n += a->q0[i] * a->q0[i];
        if (!isfinite(n) || !(n > 1e-200))
            return -4;
    }
    if (!(fabs(a->tau) < 1e3))
        return -5;
    if (a->ntel < 2)
        return -6;
    if (!a->tel)
        return -7;
    if (a->ldtel < a->ntel)
        return -8;
    if (a->tel_cols != 7 && (sd || a->tel_cols != 4))
        return -9;
    if (a->frame != IGEA_NAV_LE && a->frame != IGEA_NAV_ECEF)
        return -10;
    if (a->ntrk < 1)
        return -11;
    if (!a->trk)
        return -12;
    if (a->ldtrk < a->ntrk)
        return -13;
    int tc = a->trk_cols;
    if (tc != 7 && tc != 8 && tc != 10 && tc != 13 && tc != 28)
        return -14;
    if (!dw)
        return -15;
    if (cov && tc == 7)
        return -16;
    if (!bad)
        return -18;
    return 0;
}

/* The 6 x 6 position-velocity covariance of a 28-column tracking row e
 * (columns 7..27: the upper triangle row by row of x y z vx vy vz). */
static void trk_cov6(const dw_in *a, int e, double *P)
{
    const double *trk = a->trk;
    int ldtrk = a->ldtrk, c = 7;
    for (int i = 0; i < 6; i++)
        for (int j = i; j < 6; j++, c++)
            P[6 * i + j] = P[6 * j + i] = TRK(e, c);
}

/* 1 if the symmetric 6 x 6 P is positive definite (Cholesky). */
static int chol_ok(const double *P)
{
    double L[36] = {0};
    for (int j = 0; j < 6; j++) {
        double d = P[7 * j];
        for (int k = 0; k < j; k++)
            d -= L[6 * j + k] * L[6 * j + k];
        if (!(d > 0.0))
            return 0;
        L[7 * j] = sqrt(d);
        for (int i = j + 1; i < 6; i++) {
            double v = P[6 * i + j];
            for (int k = 0; k < j; k++)
                v -= L[6 * i + k] * L[6 * j + k];
            L[6 * i + j] = v / L[7 * j];
        }
    }
    return 1;
}

/* Finite data, sigmas positive, covariances positive definite. */
static int check_data(const dw_in *a)
{
    int used = a->system == IGEA_ENVFUN_STRAPDOWN ? 7 : 4;
    if (!igea__finite_mat(a->ntel, used, a->tel, a->ldtel) ||
        !igea__finite_mat(a->ntrk, a->trk_cols, a->trk, a->ldtrk))
        return IGEA_ENONFINITE;
    const double *trk = a->trk;
    int ldtrk = a->ldtrk;
    for (int e = 0; e < a->ntrk; e++) {
        if (a->trk_cols == 8 || a->trk_cols == 10) {
            for (int c = 7; c < a->trk_cols; c++)
                if (!(TRK(e, c) >= IGEA_SIGMA_MIN))
                    return IGEA_ENONPOSITIVE;
        } else if (a->trk_cols == 13) { /* leading minors of the 3 x 3 */
            double xx = TRK(e, 7), xy = TRK(e, 8), xz = TRK(e, 9), yy = TRK(e, 10);
            double yz = TRK(e, 11), zz = TRK(e, 12);
            double m2 = xx * yy - xy * xy;
            double m3 = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) +
                        xz * (xy * yz - yy * xz);
            if (!(xx > 0.0) || !(m2 > 0.0) || !(m3 > 0.0))
                return IGEA_ENONPOSITIVE;
        } else if (a->trk_cols == 28) {
            double P[36];
            trk_cov6(a, e, P);
            if (!chol_ok(P))
                return IGEA_ENONPOSITIVE;
        }
    }
    return 0;
}

/* Time order and span; *bad the offending row. */
static int check_times(const dw_in *a, int *bad)
{
    const double *tel = a->tel, *trk = a->trk;
    int ldtrk = a->ldtrk;
    for (int k = 1; k < a->ntel; k++)
        if (!(T(k) > T(k - 1))) {
            *bad = k;
            return IGEA_DW_ETELEMETRY;
        }
    for (int e = 1; e < a->ntrk; e++)
        if (!(TRK(e, 0) > TRK(e - 1, 0))) {
            *bad = e;
            return IGEA_DW_ETRACK;
        }
    double t0 = T(0) + a->tau, t1 = T(a->ntel - 1) + a->tau;
    for (int e = 0; e < a->ntrk; e++)
        if (TRK(e, 0) < t0 || TRK(e, 0) > t1) {
            *bad = e;
            return IGEA_DW_ESPAN;
        }
    return 0;
}

/* W and the navigated v at every telemetry record (6 ntel: W, v per
 * record). */
static int telemetry_w(const dw_in *a, double *W)
{
    double st[IGEA_NAV_STATE_LEN], dv[3], dth[3];
    const double *tel = a->tel;
    int ldtel = a->ldtel, sd = a->system == IGEA_ENVFUN_STRAPDOWN;
    int s = igea_nav_init(a->system, a->site, IGEA_NAV_GRAVITY_J2, 0, T(0), a->q0, NULL, NULL,
                          st);
    if (s)
        return s < 0 ? IGEA_ENONFINITE : s;
    memcpy(W, st + IGEA_NAV_STATE_W, 3 * sizeof *W);
    memcpy(W + 3, st + IGEA_NAV_STATE_V, 3 * sizeof *W);
    for (int k = 1; k < a->ntel; k++) {
        for (int i = 0; i < 3; i++) {
            dv[i] = TEL(k, 1 + i);
            dth[i] = sd ? TEL(k, 4 + i) : 0.0;
        }
        s = igea_nav_step(st, T(k), dv, dth);
        if (s)
            return IGEA_ENONFINITE;
        memcpy(W + 6 * (size_t)k, st + IGEA_NAV_STATE_W, 3 * sizeof *W);
        memcpy(W + 6 * (size_t)k + 3, st + IGEA_NAV_STATE_V, 3 * sizeof *W);
    }
    return 0;
}

/* A telemetry quantity (3 values per record at W[6 k + 0..2]) and its rate
 * at time x (telemetry clock). */
static void telemetry_at(const double *tel, const double *W, int n, double x, double *w,
                         double *f)
{
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) { /* T(lo) <= x <= T(hi) */
        int mid = lo + (hi - lo) / 2;
        if (T(mid) <= x)
            lo = mid;
        else
            hi = mid;
    }
    int np = n < 4 ? n : 4, first = lo - 1;
    if (first > n - np)
        first = n - np;
    if (first < 0)
        first = 0;
    for (int i = 0; i < 3; i++)
        w[i] = f[i] = 0.0;
    for (int j = first; j < first + np; j++) { /* Lagrange basis l_j and l_j' */
        double l = 1.0, dl = 0.0;
        for (int m = first; m < first + np; m++) {
            if (m == j)
                continue;
            double den = T(j) - T(m);
            dl = dl * (x - T(m)) / den + l / den;
            l *= (x - T(m)) / den;
        }
        for (int i = 0; i < 3; i++) {
            w[i] += l * W[6 * (size_t)j + i];
            f[i] += dl * W[6 * (size_t)j + i];
        }
    }
}

/* 4-point Gauss-Legendre on [-1, 1]. */
static const double xs[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                             0.8611363115940526};
static const double ws[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                             0.3478548451374538};

/* int g dt along the cubic Hermite path from (r0, v0) to (r1, v1) over h. */
static int gravity_integral(const double *site, double h, const double *r0, const double *v0,
                            const double *r1, const double *v1, double *ig)
{
    for (int i = 0; i < 3; i++)
        ig[i] = 0.0;
    for (int q = 0; q < 4; q++) {
        double s = 0.5 * (1.0 + xs[q]), s2 = s * s, s3 = s2 * s, r[3], g[3];
        double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
               h11 = s3 - s2;
        for (int i = 0; i < 3; i++)
            r[i] = h00 * r0[i] + h10 * h * v0[i] + h01 * r1[i] + h11 * h * v1[i];
        if (igea_nav_gravity_li(site, IGEA_NAV_GRAVITY_J2, r, g, NULL))
            return IGEA_ENONFINITE;
        for (int i = 0; i < 3; i++)
            ig[i] += 0.5 * h * ws[q] * g[i];
    }
    return 0;
}

/* The partials of gravity_integral (row-major 3 x 3 each, the same
 * quadrature): J[0] by r0, J[1] by v0, J[2] by r1, J[3] by v1, i.e.
 * (h / 2) sum_q w_q G(r(s_q)) times h00, h h10, h01, h h11 at s_q. */
static int gravity_partials(const double *site, double h, const double *r0, const double *v0,
                            const double *r1, const double *v1, double J[4][9])
{
    memset(J, 0, 4 * sizeof J[0]);
    for (int q = 0; q < 4; q++) {
        double s = 0.5 * (1.0 + xs[q]), s2 = s * s, s3 = s2 * s, r[3], g[3], G[9];
        double c[4] = {2 * s3 - 3 * s2 + 1, h * (s3 - 2 * s2 + s), -2 * s3 + 3 * s2,
                       h * (s3 - s2)};
        for (int i = 0; i < 3; i++)
            r[i] = c[0] * r0[i] + c[1] * v0[i] + c[2] * r1[i] + c[3] * v1[i];
        if (igea_nav_gravity_li(site, IGEA_NAV_GRAVITY_J2, r, g, G))
            return IGEA_ENONFINITE;
        for (int k = 0; k < 4; k++)
            for (int i = 0; i < 9; i++)
                J[k][i] += 0.5 * h * ws[q] * c[k] * G[i];
    }
    return 0;
}

/* The velocity covariance of tracking row e in the tracking frame (9). */
static void trk_cov(const dw_in *a, int e, double *P)
{
    const double *trk = a->trk;
    int ldtrk = a->ldtrk;
    memset(P, 0, 9 * sizeof *P);
    if (a->trk_cols == 8 || a->trk_cols == 10)
        for (int i = 0; i < 3; i++) {
            double s = TRK(e, a->trk_cols == 8 ? 7 : 7 + i);
            P[4 * i] = s * s;
        }
    else {
        static const int idx[9] = {7, 8, 9, 8, 10, 11, 9, 11, 12};
        for (int i = 0; i < 9; i++)
            P[i] = TRK(e, idx[i]);
    }
}

/* The Jacobian (6 x 6 row-major) of the frame change of a tracked
 * position and velocity into LI at time since lift-off ts (affine in r
 * and v): dr_LI = M dr, dv_LI = M dv + M [w_f x] dr, w_f the Earth rate in
 * the tracking axes, M = igea_nav_rotation (docs/pipeline.md 1.2). */
static void frame_jacobian(const dw_in *a, double ts, double *T6)
{
    const double *C = a->site + IGEA_NAV_SITE_C;
    double M[9], w[3];
    igea_nav_rotation(a->site, a->frame, IGEA_NAV_LI, ts, M);
    for (int i = 0; i < 3; i++)
        w[i] = a->frame == IGEA_NAV_ECEF ? (i == 2) * IGEA_NAV_OMEGA : C[3 * i + 2] * IGEA_NAV_OMEGA;
    memset(T6, 0, 36 * sizeof *T6);
    for (int i = 0; i < 3; i++) { /* column j of M [w x] is M (w x e_j) */
        for (int j = 0; j < 3; j++) {
            double ej[3] = {0, 0, 0}, wx[3];
            ej[j] = 1.0;
            igea__cross(w, ej, wx);
            T6[6 * i + j] = T6[6 * (3 + i) + 3 + j] = M[3 * i + j];
            T6[6 * (3 + i) + j] = M[3 * i] * wx[0] + M[3 * i + 1] * wx[1] + M[3 * i + 2] * wx[2];
        }
    }
}

/* out (n_a x n_b, row-major) = A Q B^T, A n_a x 6, Q 6 x 6, B n_b x 6. */
static void aqbt(int na, const double *A, const double *Q, int nb, const double *B, double *out)
{
    double AQ[36];
    for (int i = 0; i < na; i++)
        for (int j = 0; j < 6; j++) {
            AQ[6 * i + j] = 0.0;
            for (int k = 0; k < 6; k++)
                AQ[6 * i + j] += A[6 * i + k] * Q[6 * k + j];
        }
    for (int i = 0; i < na; i++)
        for (int j = 0; j < nb; j++) {
            out[nb * i + j] = 0.0;
            for (int k = 0; k < 6; k++)
                out[nb * i + j] += AQ[6 * i + k] * B[6 * j + k];
        }
}

/* The upper triangle xx xy xz yy yz zz of the symmetric part of R (3 x 3). */
static void upper6(const double *R, double *out)
{
    out[0] = R[0], out[1] = 0.5 * (R[1] + R[3]), out[2] = 0.5 * (R[2] + R[6]);
    out[3] = R[4], out[4] = 0.5 * (R[5] + R[7]), out[5] = R[8];
}

/* LI covariance (upper triangle, 6) of row e at time since lift-off ts:
 * A P A^T, A the velocity rows of the frame change: A = M with a velocity
 * covariance, [M [w_f x], M] (frame_jacobian's rows 3-5) with the 6 x 6. */
static void li_cov(const dw_in *a, int e, double ts, double *out)
{
    double P[36] = {0}, A[18] = {0}, R[9];
    if (a->trk_cols == 28) {
        double T6[36];
        frame_jacobian(a, ts, T6);
        memcpy(A, T6 + 18, sizeof A);
        trk_cov6(a, e, P);
    } else {
        double M[9], P3[9];
        igea_nav_rotation(a->site, a->frame, IGEA_NAV_LI, ts, M);
        trk_cov(a, e, P3);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                A[6 * i + 3 + j] = M[3 * i + j];
                P[6 * (3 + i) + 3 + j] = P3[3 * i + j];
            }
    }
    aqbt(3, A, P, 3, A, R);
    upper6(R, out);
}

/* The tracking position's part of K through the gravity integral
 * (apparent kind, 28 columns; docs/pipeline.md 4.2 [D]). With e_j = (dr_j,
 * dv_j) the LI errors of epoch j (covariance Q_j = T P_j T^T, T the frame
 * Jacobian) and [a_i^s b_i^s], [a_i^e b_i^e] the partials of interval i's
 * gravity integral by its start and end node (the pad, the start of
 * interval 0, has no error): dW_e = -dv_e + sum_{i <= e} I_i gives
 * d dW_e / d e_e = E_e = [a_e^e, b_e^e - I] and, for every e > j,
 * d dW_e / d e_j = Gam_j = [a_j^e + a_{j+1}^s, b_j^e + b_{j+1}^s], the
 * same for all later epochs. So cov_e = R_e + E_e Q_e E_e^T and, for f > e,
 * Cov(dW_e, dW_f) = X_e = R_e + E_e Q_e Gam_e^T, R_e = sum_{j < e} Gam_j
 * Q_j Gam_j^T (a running sum). Overwrites the cov slots of res; xc (9 per
 * epoch, may be NULL) gets X_e, 0 for the last epoch. */
static int k_gravity(const dw_in *a, double *res, double *xc)
{
    const double *trk = a->trk, *tel = a->tel, zero[3] = {0.0, 0.0, 0.0};
    int ldtrk = a->ldtrk, prev = 0;
    double tl = T(0) + a->tau, rp[3], vp[3], tp = tl, R[9] = {0}, Qp[36], Ep[18], Aep[18];
    igea_nav_transform(a->site, IGEA_NAV_LE, IGEA_NAV_LI, 0.0, zero, zero, rp, vp);
    for (int e = 0; e < a->ntrk; e++) {
        double te = TRK(e, 0), r[3], v[3], rl[3], vl[3], T6[36], P[36], Q[36], J[4][9];
        double As[18] = {0}, Ae[18] = {0}, E[18], D[9];
        for (int i = 0; i < 3; i++) {
            r[i] = TRK(e, 1 + i);
            v[i] = TRK(e, 4 + i);
        }
        if (igea_nav_transform(a->site, a->frame, IGEA_NAV_LI, te - tl, r, v, rl, vl))
            return IGEA_ENONFINITE;
        frame_jacobian(a, te - tl, T6);
        trk_cov6(a, e, P);
        aqbt(6, T6, P, 6, T6, Q);
        if (te > tp) {
            if (gravity_partials(a->site, te - tp, rp, vp, rl, vl, J))
                return IGEA_ENONFINITE;
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) {
                    As[6 * i + j] = J[0][3 * i + j];
                    As[6 * i + 3 + j] = J[1][3 * i + j];
                    Ae[6 * i + j] = J[2][3 * i + j];
                    Ae[6 * i + 3 + j] = J[3][3 * i + j];
                }
        }
        if (prev) { /* epoch e - 1: its Gam, X and its share of R */
            double Gam[18], X[9], S[9];
            for (int i = 0; i < 18; i++)
                Gam[i] = Aep[i] + As[i];
            aqbt(3, Ep, Qp, 3, Gam, X);
            aqbt(3, Gam, Qp, 3, Gam, S);
            for (int i = 0; i < 9; i++) {
                X[i] += R[i];
                R[i] += S[i];
            }
            if (xc)
                memcpy(xc + 9 * (size_t)(e - 1), X, sizeof X);
        }
        memcpy(E, Ae, sizeof E);
        for (int i = 0; i < 3; i++)
            E[6 * i + 3 + i] -= 1.0;
        aqbt(3, E, Q, 3, E, D);
        for (int i = 0; i < 9; i++)
            D[i] += R[i];
        upper6(D, res + 12 * (size_t)e + 3);
        memcpy(Qp, Q, sizeof Q);
        memcpy(Ep, E, sizeof E);
        memcpy(Aep, Ae, sizeof Ae);
        prev = 1;
        memcpy(rp, rl, sizeof rp);
        memcpy(vp, vl, sizeof vp);
        tp = te;
    }
    if (xc)
        memset(xc + 9 * (size_t)(a->ntrk - 1), 0, 9 * sizeof *xc);
    return 0;
}

/* dW and cov of every epoch into res (12 per epoch; slots 9-11 free). */
static int epochs(const dw_in *a, const double *W, double *res)
{
    const double *trk = a->trk, *tel = a->tel, zero[3] = {0.0, 0.0, 0.0};
    int ldtrk = a->ldtrk;
    double tl = T(0) + a->tau, rp[3], vp[3], vpad[3], ig[3] = {0.0, 0.0, 0.0}, tp = tl;
    igea_nav_transform(a->site, IGEA_NAV_LE, IGEA_NAV_LI, 0.0, zero, zero, rp, vpad);
    memcpy(vp, vpad, sizeof vp);
    for (int e = 0; e < a->ntrk; e++) {
        double te = TRK(e, 0), r[3], v[3], rl[3], vl[3], dig[3], w[3], f[3];
        for (int i = 0; i < 3; i++) {
            r[i] = TRK(e, 1 + i);
            v[i] = TRK(e, 4 + i);
        }
        if (igea_nav_transform(a->site, a->frame, IGEA_NAV_LI, te - tl, r, v, rl, vl))
            return IGEA_ENONFINITE;
        if (te > tp && a->kind == IGEA_DW_APPARENT) {
            if (gravity_integral(a->site, te - tp, rp, vp, rl, vl, dig))
                return IGEA_ENONFINITE;
            for (int i = 0; i < 3; i++)
                ig[i] += dig[i];
        }
        double *o = res + 12 * (size_t)e;
        if (a->kind == IGEA_DW_APPARENT) {
            telemetry_at(tel, W, a->ntel, te - a->tau, w, f);
            for (int i = 0; i < 3; i++)
                o[i] = w[i] - (vl[i] - vpad[i] - ig[i]);
        } else {
            telemetry_at(tel, W + 3, a->ntel, te - a->tau, w, f);
            for (int i = 0; i < 3; i++)
                o[i] = w[i] - vl[i];
        }
        if (a->trk_cols > 7)
            li_cov(a, e, te - tl, o + 3);
        memcpy(rp, rl, sizeof rp);
        memcpy(vp, vl, sizeof vp);
        tp = te;
    }
    return 0;
}

/* dW/dtau of a remaining offset tau (the data's clock minus the given
 * time_offset): minus the derivative in time_offset, by central
 * differences of the whole map (step DW_DTAU_STEP), the exact partial of
 * the implemented dW, whose leading term is f. */
#define DW_DTAU_STEP 1e-3
static int offset_column(const dw_in *a, const double *W, double *res)
{
    double *tmp = igea__dalloc(24 * (size_t)a->ntrk);
    if (!tmp)
        return IGEA_ENOMEM;
    dw_in p = *a, m = *a;
    p.tau += DW_DTAU_STEP;
    m.tau -= DW_DTAU_STEP;
    int s = epochs(&p, W, tmp);
    if (!s)
        s = epochs(&m, W, tmp + 12 * (size_t)a->ntrk);
    for (int e = 0; !s && e < a->ntrk; e++)
        for (int i = 0; i < 3; i++)
            res[12 * (size_t)e + 9 + i] =
                (tmp[12 * ((size_t)a->ntrk + e) + i] - tmp[12 * (size_t)e + i]) /
                (2.0 * DW_DTAU_STEP);
    free(tmp);
    return s;
}

/* igea_dw_compute(_k) of checked arguments; xcov (may be NULL) asks for
 * the gravity integral's part of K (k 1: igea_dw_compute_k). */
static int compute(const dw_in *a, int k, double *dw, double *cov, double *xcov,
                   double *dw_dtau, int *bad)
{
    int s, where = -1, ntrk = a->ntrk;
    if ((s = check_data(a)))
        return s;
    if ((s = check_times(a, &where))) {
        *bad = where;
        return s;
    }
    double *W = igea__dalloc(6 * (size_t)a->ntel), *res = igea__dalloc(12 * (size_t)ntrk);
    double *xc = xcov ? igea__dalloc(9 * (size_t)ntrk) : NULL;
    if (!W || !res || (xcov && !xc)) {
        free(W);
        free(res);
        free(xc);
        return IGEA_ENOMEM;
    }
    /* the covariance and clock slots are written only when asked for: zero
     * them so that the finiteness check below never reads garbage */
    memset(res, 0, 12 * (size_t)ntrk * sizeof *res);
    if (xc)
        memset(xc, 0, 9 * (size_t)ntrk * sizeof *xc);
    s = telemetry_w(a, W);
    if (!s)
        s = epochs(a, W, res);
    if (!s && k && cov && a->trk_cols == 28 && a->kind == IGEA_DW_APPARENT)
        s = k_gravity(a, res, xc);
    if (!s && dw_dtau)
        s = offset_column(a, W, res);
    for (size_t i = 0; !s && i < 12 * (size_t)ntrk; i++)
        if (!isfinite(res[i]))
            s = IGEA_ENONFINITE;
    if (!s && xc && !igea__finite_vec(9 * ntrk, xc, 1))
        s = IGEA_ENONFINITE;
    if (!s) {
        for (int e = 0; e < ntrk; e++) {
            const double *o = res + 12 * (size_t)e;
            memcpy(dw + 3 * (size_t)e, o, 3 * sizeof *dw);
            if (cov)
                memcpy(cov + 6 * (size_t)e, o + 3, 6 * sizeof *cov);
            if (dw_dtau)
                memcpy(dw_dtau + 3 * (size_t)e, o + 9, 3 * sizeof *dw_dtau);
        }
        if (xcov)
            memcpy(xcov, xc, 9 * (size_t)ntrk * sizeof *xcov);
        *bad = -1;
    }
    free(W);
    free(res);
    free(xc);
    return s;
}

int igea_dw_compute(const double *site, int system, int kind, const double *q0,
                    double time_offset, int ntel, const double *tel, int ldtel, int tel_cols, int frame, int ntrk,
                    const double *trk, int ldtrk, int trk_cols, double *dw, double *cov,
                    double *dw_dtau, int *bad)
{
    dw_in a = {site, q0, tel, trk, time_offset, system, kind, ntel, ldtel, tel_cols, frame,
               ntrk, ldtrk, trk_cols};
    int s = check_args(&a, dw, cov, bad);
    return s ? s : compute(&a, 0, dw, cov, NULL, dw_dtau, bad);
}

int igea_dw_compute_k(const double *site, int system, int kind, const double *q0,
                      double time_offset, int ntel, const double *tel, int ldtel, int tel_cols,
                      int frame, int ntrk, const double *trk, int ldtrk, int trk_cols,
                      double *dw, double *cov, double *xcov, double *dw_dtau, int *bad)
{
    dw_in a = {site, q0, tel, trk, time_offset, system, kind, ntel, ldtel, tel_cols, frame,
               ntrk, ldtrk, trk_cols};
    int unused, s = check_args(&a, dw, cov, bad ? bad : &unused);
    if (s == 0 && xcov && !cov)
        s = -17;
    if (s == 0 && !bad)
        s = -19;
    return s ? s : compute(&a, 1, dw, cov, xcov, dw_dtau, bad);
}

int igea_dw_summary(int ntrk, const double *dw, const double *cov, double *sigma,
                    double *max_abs, double *rms)
{
    if (ntrk < 1)
        return -1;
    if (!dw)
        return -2;
    if (!igea__finite_vec(3 * ntrk, dw, 1) || (cov && !igea__finite_vec(6 * ntrk, cov, 1)))
        return IGEA_ENONFINITE;
    static const int diag[3] = {0, 3, 5};
    for (int e = 0; cov && e < ntrk; e++)
        for (int i = 0; i < 3; i++)
            if (cov[6 * (size_t)e + diag[i]] < 0)
                return IGEA_ENONPOSITIVE;
    double mx = 0.0;
    igea__ksum ss[3] = {{0.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}};
    for (int e = 0; e < ntrk; e++)
        for (int i = 0; i < 3; i++) {
            double d = dw[3 * (size_t)e + i];
            mx = fmax(mx, fabs(d));
            igea__ksum_add(&ss[i], d * d);
        }
    if (sigma && cov)
        for (int e = 0; e < ntrk; e++)
            for (int i = 0; i < 3; i++)
                sigma[3 * (size_t)e + i] = sqrt(cov[6 * (size_t)e + diag[i]]);
    if (max_abs)
        *max_abs = mx;
    if (rms)
        for (int i = 0; i < 3; i++)
            rms[i] = sqrt(igea__ksum_get(&ss[i]) / ntrk);
    return 0;
}
