/* inserr.c - the linearised INS error model in local-level NED axes on a
 * spherical Earth, its deterministic response and its covariance, by a
 * fixed-step classical Runge-Kutta integration (include/igea/inserr.h,
 * docs/inserr.md). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "igea/inserr.h"
#include "inserr_int.h"
#include "internal.h"

#define NS IGEA_INSERR_N
#define NS2 (IGEA_INSERR_N * IGEA_INSERR_N)
#define MAX_STEPS 1e7

int igea_inserr_defaults(double *opts)
{
    if (!opts)
        return -1;
    for (int i = 0; i < IGEA_INSERR_OPT_LEN; i++)
        opts[i] = 0.0;
    opts[IGEA_INSERR_OPT_RADIUS] = 6371008.8;
    opts[IGEA_INSERR_OPT_G] = 9.80665;
    opts[IGEA_INSERR_OPT_OMEGA] = 7.292115e-5;
    opts[IGEA_INSERR_OPT_STEP] = 1.0;
    return 0;
}

int igea_inserr_check_opts(const double *o)
{
    if (!o)
        return -1;
    for (int i = 0; i < IGEA_INSERR_OPT_LEN; i++)
        if (!isfinite(o[i]))
            return 1 + i;
    if (!(o[IGEA_INSERR_OPT_RADIUS] >= 1e5))
        return 1 + IGEA_INSERR_OPT_RADIUS;
    if (!(o[IGEA_INSERR_OPT_G] > 0))
        return 1 + IGEA_INSERR_OPT_G;
    if (!(o[IGEA_INSERR_OPT_OMEGA] >= 0))
        return 1 + IGEA_INSERR_OPT_OMEGA;
    if (!(fabs(o[IGEA_INSERR_OPT_LAT]) <= 1.5))
        return 1 + IGEA_INSERR_OPT_LAT;
    if (!(o[IGEA_INSERR_OPT_STEP] > 0 && o[IGEA_INSERR_OPT_STEP] <= 60))
        return 1 + IGEA_INSERR_OPT_STEP;
    if (o[IGEA_INSERR_OPT_VERTICAL] != 0 && o[IGEA_INSERR_OPT_VERTICAL] != 1)
        return 1 + IGEA_INSERR_OPT_VERTICAL;
    for (int i = IGEA_INSERR_OPT_ACC_TC; i <= IGEA_INSERR_OPT_GYRO_TC; i++)
        if (o[i] != 0 && !(o[i] >= 1 && o[i] <= 1e9))
            return 1 + i;
    return 0;
}

static void cross(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* The model's right-hand side for one state x (linear in x): the columns
 * of F are its values at the unit vectors. */
static void model_rhs(const double *o, const double *x, double *dx)
{
    const double R = o[IGEA_INSERR_OPT_RADIUS], g = o[IGEA_INSERR_OPT_G];
    const double w = o[IGEA_INSERR_OPT_OMEGA], L = o[IGEA_INSERR_OPT_LAT];
    const double vn = o[IGEA_INSERR_OPT_VN], ve = o[IGEA_INSERR_OPT_VE];
    const double sl = sin(L), cl = cos(L), tl = tan(L);
    const double *dr = x, *dv = x + 3, *phi = x + 6, *b = x + 9, *eps = x + 12;
    const double v[3] = {vn, ve, 0.0};
    const double W[3] = {w * cl, 0.0, -w * sl};
    const double rho[3] = {ve / R, -vn / R, -ve * tl / R};
    const double dW[3] = {-w * sl * dr[0] / R, 0.0, -w * cl * dr[0] / R};
    const double drho[3] = {(dv[1] + ve * dr[2] / R) / R, (-dv[0] - vn * dr[2] / R) / R,
                            (-dv[1] * tl - ve * dr[0] / (R * cl * cl) - ve * tl * dr[2] / R) / R};
    double a[3], c1[3], c2[3], c3[3], f[3];
    for (int i = 0; i < 3; i++)
        a[i] = 2.0 * W[i] + rho[i];
    cross(a, v, f);
    f[2] -= g;
    dx[0] = dv[0] + vn * dr[2] / R;
    dx[1] = dv[1] + (ve * tl * dr[0] + ve * dr[2]) / R;
    dx[2] = dv[2];
    cross(f, phi, c1);
    cross(a, dv, c2);
    for (int i = 0; i < 3; i++)
        c3[i] = 2.0 * dW[i] + drho[i];
    double c4[3];
    cross(c3, v, c4);
    for (int i = 0; i < 3; i++)
        dx[3 + i] = c1[i] + b[i] - c2[i] - c4[i];
    dx[5] += 2.0 * g * dr[2] / R;
    for (int i = 0; i < 3; i++)
        a[i] = W[i] + rho[i];
    cross(a, phi, c1);
    for (int i = 0; i < 3; i++)
        dx[6 + i] = -c1[i] + dW[i] + drho[i] - eps[i];
    const double ta = o[IGEA_INSERR_OPT_ACC_TC], tg = o[IGEA_INSERR_OPT_GYRO_TC];
    for (int i = 0; i < 3; i++) {
        dx[9 + i] = ta > 0 ? -b[i] / ta : 0.0;
        dx[12 + i] = tg > 0 ? -eps[i] / tg : 0.0;
    }
    if (o[IGEA_INSERR_OPT_VERTICAL] == 0)
        dx[2] = dx[5] = 0.0;
}

static void build_matrix(const double *o, double *F)
{
    double e[NS], col[NS];
    for (int j = 0; j < NS; j++) {
        memset(e, 0, sizeof e);
        e[j] = 1.0;
        model_rhs(o, e, col);
        for (int i = 0; i < NS; i++)
            F[i * NS + j] = col[i];
    }
}

int igea_inserr_matrix(const double *opts, double *F)
{
    if (!opts || igea_inserr_check_opts(opts))
        return -1;
    if (!F)
        return -2;
    build_matrix(opts, F);
    return 0;
}

/* out = F x (n-vector) */
static void matvec(const double *F, const double *x, double *out)
{
    for (int i = 0; i < NS; i++) {
        double s = 0.0;
        for (int j = 0; j < NS; j++)
            s += F[i * NS + j] * x[j];
        out[i] = s;
    }
}

/* out = F P + P F^T + Q, P and Q symmetric (F's zeros skipped: F is sparse) */
static void lyap(const double *F, const double *P, const double *Q, double *out)
{
    double M[NS2];
    for (int i = 0; i < NS; i++)
        for (int j = 0; j < NS; j++) {
            double s = 0.0;
            for (int k = 0; k < NS; k++)
                if (F[i * NS + k] != 0.0)
                    s += F[i * NS + k] * P[k * NS + j];
            M[i * NS + j] = s;
        }
    for (int i = 0; i < NS; i++)
        for (int j = 0; j < NS; j++)
            out[i * NS + j] = M[i * NS + j] + M[j * NS + i] + Q[i * NS + j];
}

double igea__inserr_gm_step(const double *tc)
{
    double t = HUGE_VAL;
    for (int i = 0; i < 2; i++)
        if (tc[i] > 0)
            t = fmin(t, tc[i]);
    return t / 4.0;
}

void igea__inserr_rk4(const double *F, const double *Q, int m, double h, double *y)
{
    double k[4][NS2], t[NS2];
    static const double c[3] = {0.5, 0.5, 1.0};
    const double *in = y;
    for (int s = 0; s < 4; s++) {
        if (m == NS)
            matvec(F, in, k[s]);
        else
            lyap(F, in, Q, k[s]);
        if (s < 3) {
            for (int i = 0; i < m; i++)
                t[i] = y[i] + c[s] * h * k[s][i];
            in = t;
        }
    }
    for (int i = 0; i < m; i++)
        y[i] += h / 6.0 * (k[0][i] + 2.0 * k[1][i] + 2.0 * k[2][i] + k[3][i]);
}

/* The longest Runge-Kutta step: opts' STEP, cut to a quarter of the
 * shortest correlation time of the Gauss-Markov bias states. */
static double rk_step(const double *o)
{
    const double tc[2] = {o[IGEA_INSERR_OPT_ACC_TC], o[IGEA_INSERR_OPT_GYRO_TC]};
    return fmin(o[IGEA_INSERR_OPT_STEP], igea__inserr_gm_step(tc));
}

/* Integrate y (m values) over n - 1 equal intervals of the duration into
 * out (n x m), through a scratch copy; IGEA_EOVERFLOW on a non-finite
 * value. */
static int propagate(const double *o, const double *Q, int m, const double *y0,
                     double duration, int n, double *out)
{
    double F[NS2], y[NS2];
    build_matrix(o, F);
    double dt = duration / (n - 1), step = rk_step(o);
    double sub = ceil(dt / step * (1.0 - 1e-12));
    int ms = sub < 1 ? 1 : (int)sub;
    double h = dt / ms;
    double *buf = igea__dalloc((size_t)n * (size_t)m);
    if (!buf)
        return IGEA_ENOMEM;
    memcpy(y, y0, sizeof(double) * (size_t)m);
    memcpy(buf, y, sizeof(double) * (size_t)m);
    for (int k = 1; k < n; k++) {
        for (int s = 0; s < ms; s++)
            igea__inserr_rk4(F, Q, m, h, y);
        if (!igea__finite_vec(m, y, 1)) {
            free(buf);
            return IGEA_EOVERFLOW;
        }
        memcpy(buf + (size_t)k * (size_t)m, y, sizeof(double) * (size_t)m);
    }
    memcpy(out, buf, sizeof(double) * (size_t)n * (size_t)m);
    free(buf);
    return 0;
}

static int check_span(const double *o, double duration, int n, int iarg_d, int iarg_n)
{
    if (!(isfinite(duration) && duration > 0) || duration / rk_step(o) > MAX_STEPS)
        return -iarg_d;
    if (n < 2)
        return -iarg_n;
    return 0;
}

int igea_inserr_response(const double *opts, const double *x0, double duration, int n,
                         double *x)
{
    if (!opts || igea_inserr_check_opts(opts))
        return -1;
    if (!x0)
        return -2;
    int st = check_span(opts, duration, n, 3, 4);
    if (st)
        return st;
    if (!x)
        return -5;
    if (!igea__finite_vec(NS, x0, 1))
        return IGEA_ENONFINITE;
    return propagate(opts, NULL, NS, x0, duration, n, x);
}

int igea__inserr_check_p0(const double *P0)
{
    if (!igea__finite_vec(NS2, P0, 1))
        return IGEA_ENONFINITE;
    for (int i = 0; i < NS; i++) {
        if (P0[i * NS + i] < 0)
            return IGEA_ENONPOSITIVE;
        for (int j = 0; j < i; j++) {
            double a = P0[i * NS + j], b = P0[j * NS + i];
            if (fabs(a - b) > 1e-12 * fmax(fabs(a), fabs(b)))
                return IGEA_EDOMAIN;
        }
    }
    return 0;
}

int igea_inserr_covariance(const double *opts, const double *P0, const double *q,
                           double duration, int n, double *P)
{
    if (!opts || igea_inserr_check_opts(opts))
        return -1;
    if (!q)
        return -3;
    int st = check_span(opts, duration, n, 4, 5);
    if (st)
        return st;
    if (!P)
        return -6;
    if (P0 && (st = igea__inserr_check_p0(P0)))
        return st;
    if (!igea__finite_vec(IGEA_INSERR_NQ, q, 1))
        return IGEA_ENONFINITE;
    double qd[NS] = {0}, p[NS2];
    for (int i = 0; i < IGEA_INSERR_NQ; i++) {
        if (q[i] < 0)
            return IGEA_ENONPOSITIVE;
        qd[3 + i] = q[i];
    }
    if (opts[IGEA_INSERR_OPT_VERTICAL] == 0)
        qd[5] = 0.0;
    if (P0) {
        for (int i = 0; i < NS; i++)
            for (int j = 0; j < NS; j++)
                p[i * NS + j] = 0.5 * (P0[i * NS + j] + P0[j * NS + i]);
    } else {
        memset(p, 0, sizeof p);
    }
    double Q[NS2] = {0};
    for (int i = 0; i < NS; i++)
        Q[i * NS + i] = qd[i];
    return propagate(opts, Q, NS2, p, duration, n, P);
}

int igea__inserr_noise_args(const double *acc, const double *gyro)
{
    if (!igea__finite_vec(IGEA_INSERR_NOISE_LEN, acc, 1) ||
        !igea__finite_vec(IGEA_INSERR_NOISE_LEN, gyro, 1))
        return IGEA_ENONFINITE;
    for (int i = 0; i < IGEA_INSERR_NOISE_LEN; i++)
        if (acc[i] < 0 || gyro[i] < 0)
            return IGEA_ENONPOSITIVE;
    return 0;
}

int igea__inserr_noise_split(const double *tc, const double *acc, const double *gyro,
                             double *qw, double *qg, double *P0g, int *any)
{
    const double *tri[2] = {acc, gyro};
    *any = 0;
    for (int i = 0; i < IGEA_INSERR_NQ; i++)
        qw[i] = qg[i] = 0.0;
    for (int s = 0; s < 2; s++)
        for (int i = 0; i < 3; i++) {
            double n = tri[s][IGEA_INSERR_NOISE_N + i], k = tri[s][IGEA_INSERR_NOISE_K + i];
            qw[3 * s + i] = n * n;
            qw[6 + 3 * s + i] = k * k;
            double sd = IGEA__INSERR_GM_OF_B * tri[s][IGEA_INSERR_NOISE_B + i];
            if (sd == 0)
                continue;
            if (!(tc[s] > 0))
                return IGEA_EDOMAIN;
            qg[6 + 3 * s + i] = 2.0 * sd * sd / tc[s];
            P0g[(9 + 3 * s + i) * (NS + 1)] = sd * sd;
            *any = 1;
        }
    return 0;
}

int igea_inserr_noise_covariance(const double *opts, const double *P0, const double *acc,
                                 const double *gyro, double duration, int n, double *P)
{
    if (!opts || igea_inserr_check_opts(opts))
        return -1;
    if (!acc)
        return -3;
    if (!gyro)
        return -4;
    int st = check_span(opts, duration, n, 5, 6);
    if (st)
        return st;
    if (!P)
        return -7;
    if ((P0 && (st = igea__inserr_check_p0(P0))) || (st = igea__inserr_noise_args(acc, gyro)))
        return st;
    double qw[IGEA_INSERR_NQ], qg[IGEA_INSERR_NQ], o0[IGEA_INSERR_OPT_LEN];
    const double tc[2] = {opts[IGEA_INSERR_OPT_ACC_TC], opts[IGEA_INSERR_OPT_GYRO_TC]};
    double *pg = calloc(NS2, sizeof *pg);
    if (!pg)
        return IGEA_ENOMEM;
    int any;
    if ((st = igea__inserr_noise_split(tc, acc, gyro, qw, qg, pg, &any))) {
        free(pg);
        return st;
    }
    memcpy(o0, opts, sizeof o0);
    o0[IGEA_INSERR_OPT_ACC_TC] = o0[IGEA_INSERR_OPT_GYRO_TC] = 0.0;
    size_t m = (size_t)n * NS2;
    double *buf = igea__dalloc(2 * m);
    if (!buf) {
        free(pg);
        return IGEA_ENOMEM;
    }
    st = igea_inserr_covariance(o0, P0, qw, duration, n, buf);
    if (!st && any)
        st = igea_inserr_covariance(opts, pg, qg, duration, n, buf + m);
    if (!st) {
        for (size_t i = 0; i < m; i++)
            buf[i] += any ? buf[m + i] : 0.0;
        memcpy(P, buf, sizeof(double) * m);
    }
    free(buf);
    free(pg);
    return st;
}
