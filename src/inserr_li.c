/* inserr_li.c - the linearised INS error model in the launch-inertial
 * frame along the reference trajectory of the nav core: its deterministic
 * response and its covariance, one Runge-Kutta step per telemetry interval
 * (several where Gauss-Markov bias states need a shorter one) with the
 * coefficients frozen at the interval's values
 * (include/igea/inserr.h, docs/inserr.md). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "igea/envfun.h"
#include "igea/inserr.h"
#include "igea/nav.h"
#include "igea/sim.h"
#include "inserr_int.h"
#include "internal.h"
#include "rotation.h"

#define NS IGEA_INSERR_N
#define NS2 (IGEA_INSERR_N * IGEA_INSERR_N)
/* The most Runge-Kutta steps in one telemetry interval (its Gauss-Markov
 * states' step, igea__inserr_gm_step: a gap of 2.5e6 T) */
#define LI_MAX_SUB 1e7

/* The reference navigation and the telemetry it reads. */
typedef struct {
    int sd, nsamp, ldtel;
    const double *tel;
    double st[IGEA_NAV_STATE_LEN];
    double tc[2]; /* correlation times of the accelerometer and gyro bias states (0: none) */
} li_ref;

static double tel_at(const li_ref *r, int k, int col) { return r->tel[(size_t)col * (size_t)r->ldtel + (size_t)k]; }

/* Arguments 1-9 (system .. v0): 0 or -i; IGEA_ENONFINITE for a non-finite
 * telemetry value. On success r holds the reference at t_0. */
static int ref_init(li_ref *r, int system, const double *site, int gravity, int nsamp,
                    const double *tel, int ldtel, const double *q0, const double *r0,
                    const double *v0)
{
    if (system != IGEA_ENVFUN_STRAPDOWN && system != IGEA_ENVFUN_PLATFORM)
        return -1;
    if (nsamp < 2)
        return -4;
    if (!tel)
        return -5;
    if (ldtel < nsamp)
        return -6;
    r->sd = system == IGEA_ENVFUN_STRAPDOWN;
    r->tc[0] = r->tc[1] = 0.0;
    r->nsamp = nsamp;
    r->ldtel = ldtel;
    r->tel = tel;
    int cols = r->sd ? IGEA_SIM_RAW_TEL_STRAPDOWN : IGEA_SIM_RAW_TEL_PLATFORM;
    if (!igea__finite_mat(nsamp, cols, tel, ldtel))
        return IGEA_ENONFINITE;
    for (int k = 1; k < nsamp; k++)
        if (!(tel_at(r, k, 0) > tel_at(r, k - 1, 0)))
            return -5;
    if (!site)
        return -2;
    int st = igea_nav_init(system, site, gravity, 0, tel_at(r, 0, 0), q0, r0, v0, r->st);
    static const int arg[10] = {0, 1, 2, 3, 0, 5, 7, 8, 9, 0};
    if (st < 0 && st >= -9 && arg[-st])
        return -arg[-st];
    return st ? -2 : 0;
}

/* Advance the reference over interval k (t_{k-1}, t_k] and build its system
 * matrix A (15 x 15 row-major) and noise input B (the 3 x 3 blocks: Ca for
 * the accelerometer noise into dv, Cg for the gyro noise into phi). */
static int ref_step(li_ref *r, int k, double *A, double *Ca, double *Cg)
{
    double prev[IGEA_NAV_STATE_LEN], dv[3], dth[3], qm[4], G[9], g[3], rm[3];
    memcpy(prev, r->st, sizeof prev);
    for (int i = 0; i < 3; i++) {
        dv[i] = tel_at(r, k, 1 + i);
        dth[i] = r->sd ? tel_at(r, k, 4 + i) : 0.0;
    }
    double h = tel_at(r, k, 0) - tel_at(r, k - 1, 0);
    int st = igea_nav_step(r->st, tel_at(r, k, 0), dv, r->sd ? dth : NULL);
    if (st)
        return st == IGEA_ENONFINITE ? st : -5;
    for (int i = 0; i < 4; i++)
        qm[i] = prev[IGEA_NAV_STATE_Q + i] + r->st[IGEA_NAV_STATE_Q + i];
    for (int i = 0; i < 3; i++)
        rm[i] = 0.5 * (prev[IGEA_NAV_STATE_R + i] + r->st[IGEA_NAV_STATE_R + i]);
    if (igea_nav_gravity_li(r->st + IGEA_NAV_STATE_SITE, (int)r->st[IGEA_NAV_STATE_GRAVITY], rm,
                            g, G))
        return IGEA_ENONFINITE;
    igea__quat_dcm_unit(qm, Ca);
    memset(A, 0, sizeof(double) * NS2);
    double f[3];
    for (int i = 0; i < 3; i++)
        f[i] = (r->st[IGEA_NAV_STATE_W + i] - prev[IGEA_NAV_STATE_W + i]) / h;
    for (int i = 0; i < 3; i++) {
        A[i * NS + 3 + i] = 1.0;
        for (int j = 0; j < 3; j++) {
            A[(3 + i) * NS + j] = G[i * 3 + j];
            A[(3 + i) * NS + 9 + j] = Ca[i * 3 + j];
            Cg[i * 3 + j] = r->sd ? -Ca[i * 3 + j] : (i == j ? 1.0 : 0.0);
            A[(6 + i) * NS + 12 + j] = Cg[i * 3 + j];
        }
    }
    /* Gauss-Markov bias states: d(b)/dt = -b / T */
    for (int i = 0; i < 6; i++)
        A[(9 + i) * NS + 9 + i] = r->tc[i / 3] > 0 ? -1.0 / r->tc[i / 3] : 0.0;
    /* f x phi = [f x] phi */
    A[3 * NS + 7] = -f[2];
    A[3 * NS + 8] = f[1];
    A[4 * NS + 6] = f[2];
    A[4 * NS + 8] = -f[0];
    A[5 * NS + 6] = -f[1];
    A[5 * NS + 7] = f[0];
    return 0;
}

/* Q = B diag(q) B^T: the blocks C diag(q_a) C^T (dv), Cg diag(q_g) Cg^T
 * (phi), diag(q_ba), diag(q_bg). */
static void noise_matrix(const double *q, const double *Ca, const double *Cg, double *Q)
{
    memset(Q, 0, sizeof(double) * NS2);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            for (int l = 0; l < 3; l++) {
                Q[(3 + i) * NS + 3 + j] += Ca[i * 3 + l] * q[l] * Ca[j * 3 + l];
                Q[(6 + i) * NS + 6 + j] += Cg[i * 3 + l] * q[3 + l] * Cg[j * 3 + l];
            }
    for (int i = 0; i < 6; i++)
        Q[(9 + i) * NS + 9 + i] = q[6 + i];
}

/* The sample index of each epoch (increasing, each within 1e-9 s of a
 * sample time): 0 or 1 (an epoch that is not). */
static int epoch_index(const li_ref *r, int nepochs, const double *epochs, int *idx)
{
    int k = 0;
    for (int j = 0; j < nepochs; j++) {
        if (!isfinite(epochs[j]) || (j > 0 && !(epochs[j] > epochs[j - 1])))
            return 1;
        while (k < r->nsamp && tel_at(r, k, 0) < epochs[j] - 1e-9)
            k++;
        if (k == r->nsamp || fabs(tel_at(r, k, 0) - epochs[j]) > 1e-9)
            return 1;
        idx[j] = k;
    }
    return 0;
}

/* Propagate y (m values: the state or the covariance) along the record,
 * storing it at the epochs' samples into out (nepochs x m). */
static int propagate(li_ref *r, const double *q, int m, double *y, int nepochs,
                     const int *idx, double *out)
{
    double A[NS2], Q[NS2], Ca[9], Cg[9];
    double *buf = igea__dalloc((size_t)nepochs * (size_t)m);
    if (!buf)
        return IGEA_ENOMEM;
    int j = 0, st = 0;
    for (int k = 0; k < r->nsamp && j < nepochs && !st; k++) {
        if (k > 0 && !(st = ref_step(r, k, A, Ca, Cg))) {
            if (q)
                noise_matrix(q, Ca, Cg, Q);
            /* one step per interval, cut to the Gauss-Markov states' step */
            double h = tel_at(r, k, 0) - tel_at(r, k - 1, 0);
            double sub = ceil(h / igea__inserr_gm_step(r->tc) * (1.0 - 1e-12));
            int ns = sub > 1 ? (int)fmin(sub, LI_MAX_SUB) : 1;
            for (int i = 0; i < ns; i++)
                igea__inserr_rk4(A, Q, m, h / ns, y);
            if (!igea__finite_vec(m, y, 1))
                st = IGEA_EOVERFLOW;
        }
        if (!st && idx[j] == k)
            memcpy(buf + (size_t)j++ * (size_t)m, y, sizeof(double) * (size_t)m);
    }
    if (!st)
        memcpy(out, buf, sizeof(double) * (size_t)nepochs * (size_t)m);
    free(buf);
    return st;
}

/* The checks of the epochs (arguments ie, ie + 1) and the run. */
static int run(li_ref *r, const double *q, int m, double *y, int nepochs, const double *epochs,
               double *out, int ie)
{
    if (nepochs < 1)
        return -ie;
    if (!epochs)
        return -(ie + 1);
    if (!out)
        return -(ie + 2);
    int *idx = igea__ialloc((size_t)nepochs);
    if (!idx)
        return IGEA_ENOMEM;
    int st = epoch_index(r, nepochs, epochs, idx) ? -(ie + 1) : 0;
    if (!st)
        st = propagate(r, q, m, y, nepochs, idx, out);
    free(idx);
    return st;
}

int igea_inserr_li_response(int system, const double *site, int gravity, int nsamp,
                            const double *tel, int ldtel, const double *q0, const double *r0,
                            const double *v0, const double *x0, int nepochs,
                            const double *epochs, double *x)
{
    li_ref r;
    int st = ref_init(&r, system, site, gravity, nsamp, tel, ldtel, q0, r0, v0);
    if (st)
        return st;
    if (!x0)
        return -10;
    if (!igea__finite_vec(NS, x0, 1))
        return IGEA_ENONFINITE;
    double y[NS];
    memcpy(y, x0, sizeof y);
    return run(&r, NULL, NS, y, nepochs, epochs, x, 11);
}

int igea_inserr_li_covariance(int system, const double *site, int gravity, int nsamp,
                              const double *tel, int ldtel, const double *q0,
                              const double *r0, const double *v0, const double *P0,
                              const double *q, int nepochs, const double *epochs, double *P)
{
    li_ref r;
    int st = ref_init(&r, system, site, gravity, nsamp, tel, ldtel, q0, r0, v0);
    if (st)
        return st;
    if (!q)
        return -11;
    if (P0 && (st = igea__inserr_check_p0(P0)))
        return st;
    if (!igea__finite_vec(IGEA_INSERR_NQ, q, 1))
        return IGEA_ENONFINITE;
    for (int i = 0; i < IGEA_INSERR_NQ; i++)
        if (q[i] < 0)
            return IGEA_ENONPOSITIVE;
    double p[NS2];
    for (int i = 0; i < NS2; i++)
        p[i] = P0 ? 0.5 * (P0[i] + P0[(i % NS) * NS + i / NS]) : 0.0;
    return run(&r, q, NS2, p, nepochs, epochs, P, 12);
}

/* ---- Gauss-Markov bias states and the noise of an Allan fit [D] ---------- */

/* ref_init for the functions with opts at position 4: the positions from 4
 * on are one further; the correlation times from opts. */
static int ref_init_opts(li_ref *r, int system, const double *site, int gravity,
                         const double *opts, int nsamp, const double *tel, int ldtel,
                         const double *q0, const double *r0, const double *v0)
{
    if (system != IGEA_ENVFUN_STRAPDOWN && system != IGEA_ENVFUN_PLATFORM)
        return -1;
    if (!site)
        return -2;
    if (gravity != IGEA_NAV_GRAVITY_POINT_MASS && gravity != IGEA_NAV_GRAVITY_J2)
        return -3;
    if (!opts || igea_inserr_check_opts(opts))
        return -4;
    int st = ref_init(r, system, site, gravity, nsamp, tel, ldtel, q0, r0, v0);
    if (st <= -4 && st >= -9)
        return st - 1;
    if (st)
        return st;
    r->tc[0] = opts[IGEA_INSERR_OPT_ACC_TC];
    r->tc[1] = opts[IGEA_INSERR_OPT_GYRO_TC];
    return 0;
}

int igea_inserr_li_response_opts(int system, const double *site, int gravity,
                                 const double *opts, int nsamp, const double *tel, int ldtel,
                                 const double *q0, const double *r0, const double *v0,
                                 const double *x0, int nepochs, const double *epochs,
                                 double *x)
{
    li_ref r;
    int st = ref_init_opts(&r, system, site, gravity, opts, nsamp, tel, ldtel, q0, r0, v0);
    if (st)
        return st;
    if (!x0)
        return -11;
    if (!igea__finite_vec(NS, x0, 1))
        return IGEA_ENONFINITE;
    double y[NS];
    memcpy(y, x0, sizeof y);
    return run(&r, NULL, NS, y, nepochs, epochs, x, 12);
}

/* q (IGEA_INSERR_NQ) finite and >= 0: 0 or a status. */
static int check_q(const double *q)
{
    if (!igea__finite_vec(IGEA_INSERR_NQ, q, 1))
        return IGEA_ENONFINITE;
    for (int i = 0; i < IGEA_INSERR_NQ; i++)
        if (q[i] < 0)
            return IGEA_ENONPOSITIVE;
    return 0;
}

int igea_inserr_li_covariance_opts(int system, const double *site, int gravity,
                                   const double *opts, int nsamp, const double *tel,
                                   int ldtel, const double *q0, const double *r0,
                                   const double *v0, const double *P0, const double *q,
                                   int nepochs, const double *epochs, double *P)
{
    li_ref r;
    int st = ref_init_opts(&r, system, site, gravity, opts, nsamp, tel, ldtel, q0, r0, v0);
    if (st)
        return st;
    if (!q)
        return -12;
    if ((P0 && (st = igea__inserr_check_p0(P0))) || (st = check_q(q)))
        return st;
    double p[NS2];
    for (int i = 0; i < NS2; i++)
        p[i] = P0 ? 0.5 * (P0[i] + P0[(i % NS) * NS + i / NS]) : 0.0;
    return run(&r, q, NS2, p, nepochs, epochs, P, 13);
}

int igea_inserr_li_noise_covariance(int system, const double *site, int gravity,
                                    const double *opts, int nsamp, const double *tel,
                                    int ldtel, const double *q0, const double *r0,
                                    const double *v0, const double *P0, const double *acc,
                                    const double *gyro, int nepochs, const double *epochs,
                                    double *P)
{
    li_ref r;
    int st = ref_init_opts(&r, system, site, gravity, opts, nsamp, tel, ldtel, q0, r0, v0);
    if (st)
        return st;
    if (!acc)
        return -12;
    if (!gyro)
        return -13;
    if (nepochs < 1)
        return -14;
    if (!epochs)
        return -15;
    if (!P)
        return -16;
    if ((P0 && (st = igea__inserr_check_p0(P0))) || (st = igea__inserr_noise_args(acc, gyro)))
        return st;
    double qw[IGEA_INSERR_NQ], qg[IGEA_INSERR_NQ], *pg = calloc(NS2, sizeof *pg);
    if (!pg)
        return IGEA_ENOMEM;
    int any;
    if ((st = igea__inserr_noise_split(r.tc, acc, gyro, qw, qg, pg, &any))) {
        free(pg);
        return st;
    }
    size_t m = (size_t)nepochs * NS2;
    double *buf = igea__dalloc(2 * m), p[NS2];
    if (!buf) {
        free(pg);
        return IGEA_ENOMEM;
    }
    /* the white noises and random walks with the bias states held (T = 0),
     * from P0; then the Gauss-Markov biases, stationary from the start */
    li_ref w = r;
    w.tc[0] = w.tc[1] = 0.0;
    for (int i = 0; i < NS2; i++)
        p[i] = P0 ? 0.5 * (P0[i] + P0[(i % NS) * NS + i / NS]) : 0.0;
    st = run(&w, qw, NS2, p, nepochs, epochs, buf, 14);
    if (!st && any)
        st = run(&r, qg, NS2, pg, nepochs, epochs, buf + m, 14);
    if (!st) {
        for (size_t i = 0; any && i < m; i++)
            buf[i] += buf[m + i];
        memcpy(P, buf, sizeof(double) * m);
    }
    free(buf);
    free(pg);
    return st;
}
