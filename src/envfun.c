/* src/envfun.c - environment functions from a trajectory (METHODS 5). */
#include <limits.h>

#include "internal.h"

#include "igea/envfun.h"

#define EARTH_RADIUS 6371000.0
#define EARTH_MU 3.986004418e14

/* Term families. */
enum { FAM_ACC = 0, FAM_GYRO = 1, FAM_ATT = 2 };

/* ---- the term catalogue ------------------------------------------------ */

#define G0 9.80665                                   /* m/s^2 per g */
#define DEG_H (3.14159265358979323846 / 180.0 / 3600.0) /* rad/s per deg/h */

/* Name, unit and default 1-sigma spec of every code, by code. */
static const struct {
    const char *name, *unit;
    double spec;
} TERMS[IGEA_ENVFUN_TERM_COUNT] = {
#define AXES3(pre, unit, spec) \
    {pre "x", unit, spec}, {pre "y", unit, spec}, {pre "z", unit, spec}
    AXES3("acc_bias_", "m/s^2", 1e-3 * G0),          /* 1 mg */
    AXES3("acc_scale_", "-", 1e-4),
    AXES3("acc_sq_", "1/(m/s^2)", 1e-5 / G0),        /* 10 ug/g^2 */
    {"acc_mis_xy", "-", 1e-4}, {"acc_mis_xz", "-", 1e-4},
    {"acc_mis_yx", "-", 1e-4}, {"acc_mis_yz", "-", 1e-4},
    {"acc_mis_zx", "-", 1e-4}, {"acc_mis_zy", "-", 1e-4},
    AXES3("gyro_bias_", "rad/s", 0.5 * DEG_H),       /* 0.5 deg/h */
    AXES3("gyro_g_", "rad/s/(m/s^2)", 0.5 * DEG_H / G0), /* 0.5 deg/h/g */
    AXES3("gyro_scale_", "-", 1e-4),
    AXES3("att0_", "rad", 1e-4),
    AXES3("gyro_gi_", "rad/s/(m/s^2)", 0.5 * DEG_H / G0),
    AXES3("gyro_gs_", "rad/s/(m/s^2)", 0.5 * DEG_H / G0),
    AXES3("align0_", "rad", 1e-4),
#undef AXES3
};

/* The 21-term models of METHODS 1.6(b) / 5.5, in model order. */
static const int DEFAULT_SD[IGEA_ENVFUN_DEFAULT_TERMS] = {
    IGEA_ENVFUN_TERM_ACC_BIAS_X, IGEA_ENVFUN_TERM_ACC_BIAS_X + 1, IGEA_ENVFUN_TERM_ACC_BIAS_X + 2,
    IGEA_ENVFUN_TERM_ACC_SCALE_X, IGEA_ENVFUN_TERM_ACC_SCALE_X + 1, IGEA_ENVFUN_TERM_ACC_SCALE_X + 2,
    IGEA_ENVFUN_TERM_ACC_MIS_XY, IGEA_ENVFUN_TERM_ACC_MIS_XZ, IGEA_ENVFUN_TERM_ACC_MIS_YX,
    IGEA_ENVFUN_TERM_ACC_MIS_YZ, IGEA_ENVFUN_TERM_ACC_MIS_ZX, IGEA_ENVFUN_TERM_ACC_MIS_ZY,
    IGEA_ENVFUN_TERM_GYRO_BIAS_X, IGEA_ENVFUN_TERM_GYRO_BIAS_X + 1, IGEA_ENVFUN_TERM_GYRO_BIAS_X + 2,
    IGEA_ENVFUN_TERM_GYRO_G_X, IGEA_ENVFUN_TERM_GYRO_G_X + 1, IGEA_ENVFUN_TERM_GYRO_G_X + 2,
    IGEA_ENVFUN_TERM_ATT0_X, IGEA_ENVFUN_TERM_ATT0_X + 1, IGEA_ENVFUN_TERM_ATT0_X + 2};
static const int DEFAULT_PF[IGEA_ENVFUN_DEFAULT_TERMS] = {
    IGEA_ENVFUN_TERM_ACC_BIAS_X, IGEA_ENVFUN_TERM_ACC_BIAS_X + 1, IGEA_ENVFUN_TERM_ACC_BIAS_X + 2,
    IGEA_ENVFUN_TERM_ACC_SCALE_X, IGEA_ENVFUN_TERM_ACC_SCALE_X + 1, IGEA_ENVFUN_TERM_ACC_SCALE_X + 2,
    IGEA_ENVFUN_TERM_GYRO_BIAS_X, IGEA_ENVFUN_TERM_GYRO_BIAS_X + 1, IGEA_ENVFUN_TERM_GYRO_BIAS_X + 2,
    IGEA_ENVFUN_TERM_GYRO_GI_X, IGEA_ENVFUN_TERM_GYRO_GI_X + 1, IGEA_ENVFUN_TERM_GYRO_GI_X + 2,
    IGEA_ENVFUN_TERM_GYRO_GS_X, IGEA_ENVFUN_TERM_GYRO_GS_X + 1, IGEA_ENVFUN_TERM_GYRO_GS_X + 2,
    IGEA_ENVFUN_TERM_ALIGN0_X, IGEA_ENVFUN_TERM_ALIGN0_X + 1, IGEA_ENVFUN_TERM_ALIGN0_X + 2,
    IGEA_ENVFUN_TERM_ACC_SQ_X, IGEA_ENVFUN_TERM_ACC_SQ_X + 1, IGEA_ENVFUN_TERM_ACC_SQ_X + 2};

const char *igea_envfun_term_name(int term)
{
    return (term >= 0 && term < IGEA_ENVFUN_TERM_COUNT) ? TERMS[term].name : "";
}

const char *igea_envfun_term_unit(int term)
{
    return (term >= 0 && term < IGEA_ENVFUN_TERM_COUNT) ? TERMS[term].unit : "";
}

int igea_envfun_term_code(int system, const char *name)
{
    if (system != IGEA_ENVFUN_STRAPDOWN && system != IGEA_ENVFUN_PLATFORM)
        return -1;
    if (!name)
        return -2;
    for (int k = 0; k < IGEA_ENVFUN_TERM_COUNT; k++)
        if (!strcmp(TERMS[k].name, name) && igea_envfun_term_valid(system, k))
            return k;
    return -2;
}

int igea_envfun_default_spec(int system, int term, double *spec)
{
    if (system != IGEA_ENVFUN_STRAPDOWN && system != IGEA_ENVFUN_PLATFORM)
        return -1;
    if (!igea_envfun_term_valid(system, term))
        return -2;
    if (!spec)
        return -3;
    *spec = TERMS[term].spec;
    return 0;
}

int igea_envfun_default_terms(int system, int *terms, int cap, int *n)
{
    if (system != IGEA_ENVFUN_STRAPDOWN && system != IGEA_ENVFUN_PLATFORM)
        return -1;
    if (!terms)
        return -2;
    if (cap < IGEA_ENVFUN_DEFAULT_TERMS)
        return -3;
    if (!n)
        return -4;
    memcpy(terms, system == IGEA_ENVFUN_STRAPDOWN ? DEFAULT_SD : DEFAULT_PF,
           sizeof DEFAULT_SD);
    *n = IGEA_ENVFUN_DEFAULT_TERMS;
    return 0;
}

int igea_envfun_term_valid(int system, int term)
{
    if (term < 0 || term >= IGEA_ENVFUN_TERM_COUNT)
        return 0;
    if (system == IGEA_ENVFUN_STRAPDOWN)
        return term < IGEA_ENVFUN_TERM_GYRO_GI_X;
    if (system == IGEA_ENVFUN_PLATFORM)
        return term < IGEA_ENVFUN_TERM_GYRO_G_X || term >= IGEA_ENVFUN_TERM_GYRO_GI_X;
    return 0;
}

static int term_family(int term)
{
    if (term < IGEA_ENVFUN_TERM_GYRO_BIAS_X)
        return FAM_ACC;
    if ((term >= IGEA_ENVFUN_TERM_ATT0_X && term < IGEA_ENVFUN_TERM_GYRO_GI_X) ||
        term >= IGEA_ENVFUN_TERM_ALIGN0_X)
        return FAM_ATT;
    return FAM_GYRO;
}

/* Instrument error per unit coefficient of an accelerometer or gyro term
 * (family ACC or GYRO), u (3), from the sample's specific force f and
 * angular rate w in instrument axes; in_ax/spin_ax: platform gyro axes. */
static void term_unit(int term, const double *f, const double *w,
                      const int *in_ax, const int *spin_ax, double *u)
{
    static const int mis_j[6] = {0, 0, 1, 1, 2, 2};
    static const int mis_k[6] = {1, 2, 0, 2, 0, 1};
    int j;
    u[0] = u[1] = u[2] = 0.0;
    if (term < IGEA_ENVFUN_TERM_ACC_SCALE_X) {
        u[term] = 1.0;
    } else if (term < IGEA_ENVFUN_TERM_ACC_SQ_X) {
        j = term - IGEA_ENVFUN_TERM_ACC_SCALE_X;
        u[j] = f[j];
    } else if (term < IGEA_ENVFUN_TERM_ACC_MIS_XY) {
        j = term - IGEA_ENVFUN_TERM_ACC_SQ_X;
        u[j] = f[j] * f[j];
    } else if (term < IGEA_ENVFUN_TERM_GYRO_BIAS_X) {
        j = term - IGEA_ENVFUN_TERM_ACC_MIS_XY;
        u[mis_j[j]] = f[mis_k[j]];
    } else if (term < IGEA_ENVFUN_TERM_GYRO_G_X) {
        u[term - IGEA_ENVFUN_TERM_GYRO_BIAS_X] = 1.0;
    } else if (term < IGEA_ENVFUN_TERM_GYRO_SCALE_X) {
        j = term - IGEA_ENVFUN_TERM_GYRO_G_X;
        u[j] = f[j];
    } else if (term < IGEA_ENVFUN_TERM_ATT0_X) {
        j = term - IGEA_ENVFUN_TERM_GYRO_SCALE_X;
        u[j] = w[j];
    } else if (term >= IGEA_ENVFUN_TERM_GYRO_GI_X && term < IGEA_ENVFUN_TERM_GYRO_GS_X) {
        j = term - IGEA_ENVFUN_TERM_GYRO_GI_X;
        u[j] = f[in_ax[j]];
    } else if (term >= IGEA_ENVFUN_TERM_GYRO_GS_X && term < IGEA_ENVFUN_TERM_ALIGN0_X) {
        j = term - IGEA_ENVFUN_TERM_GYRO_GS_X;
        u[j] = f[spin_ax[j]];
    }
}

static void cross(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* Direction cosine matrix C (row-major 3x3, v_a = C v_b) of a unit
 * quaternion (scalar first). */
static void quat_dcm(const double *q, double *C)
{
    double a = q[0], b = q[1], c = q[2], d = q[3];
    C[0] = a * a + b * b - c * c - d * d;
    C[1] = 2.0 * (b * c - a * d);
    C[2] = 2.0 * (b * d + a * c);
    C[3] = 2.0 * (b * c + a * d);
    C[4] = a * a - b * b + c * c - d * d;
    C[5] = 2.0 * (c * d - a * b);
    C[6] = 2.0 * (b * d - a * c);
    C[7] = 2.0 * (c * d + a * b);
    C[8] = a * a - b * b - c * c + d * d;
}

static void mat_vec(const double *C, const double *x, double *y)
{
    y[0] = C[0] * x[0] + C[1] * x[1] + C[2] * x[2];
    y[1] = C[3] * x[0] + C[4] * x[1] + C[5] * x[2];
    y[2] = C[6] * x[0] + C[7] * x[1] + C[8] * x[2];
}

/* Point-mass gravity g and its gradient G (row-major 3x3) at launch-frame
 * position r (launch point at the origin, y up, earth centre at -R e_y). */
static void gravity(const double *r, double *g, double *G)
{
    double p[3] = {r[0], r[1] + EARTH_RADIUS, r[2]};
    double n = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    double k = EARTH_MU / (n * n * n);
    for (int i = 0; i < 3; i++) {
        if (g)
            g[i] = -k * p[i];
        if (G)
            for (int j = 0; j < 3; j++)
                G[3 * i + j] =
                    k * (3.0 * p[i] * p[j] / (n * n) - (i == j ? 1.0 : 0.0));
    }
}

/* Per-sample state of the integration: instrument-axis f, w, the a-frame
 * specific force fa. */
typedef struct {
    double t, f[3], w[3], fa[3];
} sample;

static void load_sample(int system, const double *traj, int ldt, int k,
                        sample *s)
{
    double q[4], C[9], nq = 0.0;
    s->t = IGEA_AT(traj, ldt, k, 0);
    for (int i = 0; i < 3; i++) {
        s->f[i] = IGEA_AT(traj, ldt, k, 1 + i);
        s->w[i] = IGEA_AT(traj, ldt, k, 4 + i);
    }
    if (system == IGEA_ENVFUN_PLATFORM) {
        memcpy(s->fa, s->f, sizeof s->fa);
        return;
    }
    for (int i = 0; i < 4; i++) {
        q[i] = IGEA_AT(traj, ldt, k, 7 + i);
        nq += q[i] * q[i];
    }
    nq = sqrt(nq);
    for (int i = 0; i < 4; i++)
        q[i] /= nq;
    quat_dcm(q, C);
    mat_vec(C, s->f, s->fa);
}

int igea_envfun_compute(int system, int nsamp, const double *traj, int ldt,
                        int nterms, const int *terms, const int *axes,
                        int nepochs, const double *epochs, const double *spec,
                        int output, double *S, int lds)
{
    int in_ax[3], spin_ax[3];
    igea__platform_axes(NULL, in_ax, spin_ax);
    int nf = 0, st = IGEA_OK;

    if (system != IGEA_ENVFUN_STRAPDOWN && system != IGEA_ENVFUN_PLATFORM)
        return -1;
    if (nsamp < 2)
        return -2;
    if (!traj)
        return -3;
    if (ldt < nsamp)
        return -4;
    if (nterms < 1)
        return -5;
    if (!terms)
        return -6;
    for (int j = 0; j < nterms; j++)
        if (!igea_envfun_term_valid(system, terms[j]))
            return -6;
    if (system == IGEA_ENVFUN_PLATFORM && igea__platform_axes(axes, in_ax, spin_ax))
        return -7;
    if (nepochs < 1 || nepochs > INT_MAX / 3)
        return -8;
    if (!epochs)
        return -9;
    if (output < IGEA_ENVFUN_VELOCITY || output > IGEA_ENVFUN_POSITION_G)
        return -11;
    if (!S)
        return -12;
    if (lds < 3 * nepochs)
        return -13;

    /* data checks */
    if (!igea__finite_mat(nsamp, IGEA_ENVFUN_TRAJ_COLS, traj, ldt) ||
        !igea__finite_vec(nepochs, epochs, 1))
        return IGEA_ENONFINITE;
    if (spec && !igea__positive_vec(nterms, spec, &nf))
        return nf ? IGEA_ENONFINITE : IGEA_ENONPOSITIVE;
    for (int k = 1; k < nsamp; k++)
        if (!(IGEA_AT(traj, ldt, k, 0) > IGEA_AT(traj, ldt, k - 1, 0)))
            return -3;
    for (int e = 0; e < nepochs; e++) {
        if (epochs[e] < IGEA_AT(traj, ldt, 0, 0) ||
            epochs[e] > IGEA_AT(traj, ldt, nsamp - 1, 0))
            return -9;
        if (e > 0 && epochs[e] < epochs[e - 1])
            return -9;
    }
    if (system == IGEA_ENVFUN_STRAPDOWN)
        for (int k = 0; k < nsamp; k++) {
            double nq = 0.0;
            for (int i = 0; i < 4; i++)
                nq += IGEA_AT(traj, ldt, k, 7 + i) * IGEA_AT(traj, ldt, k, 7 + i);
            if (!(nq > 1e-200))
                return IGEA_EDOMAIN;
        }

    /* scratch: per term 3-vectors */
    size_t nt3 = (size_t)nterms * 3;
    size_t mrows = (size_t)nepochs * 3;
    double *work = igea__dalloc(nt3 * 9 + mrows * (size_t)nterms);
    if (!work)
        return IGEA_ENOMEM;
    double *vel = work;            /* S_j(t_k) velocity function */
    double *inner = vel + nt3;     /* Phi_u or alpha of gyro terms */
    double *p_in = inner + nt3;    /* previous inner integrand */
    double *p_out = p_in + nt3;    /* previous outer integrand */
    double *pos = p_out + nt3;     /* position (or gravity s_r) */
    double *sv = pos + nt3;        /* gravity-coupled s_v */
    double *val = sv + nt3;        /* output value at t_k */
    double *val_prev = val + nt3;  /* output value at t_{k-1} */
    double *vel_prev = val_prev + nt3;
    double *out = vel_prev + nt3;  /* 3 nepochs x nterms, ld = mrows */
    memset(work, 0, nt3 * 9 * sizeof(double));

    sample cur, prev;
    double Wv[3] = {0, 0, 0}, rn[3] = {0, 0, 0}, vn[3] = {0, 0, 0};
    double gacc_prev[3];
    int e = 0;
    int grav = (output == IGEA_ENVFUN_VELOCITY_G ||
                output == IGEA_ENVFUN_POSITION_G);

    load_sample(system, traj, ldt, 0, &cur);
    gravity(rn, gacc_prev, NULL);
    /* initial integrands */
    for (int j = 0; j < nterms; j++) {
        int fam = term_family(terms[j]);
        double u[3], cu[3];
        if (fam == FAM_ATT)
            continue;
        term_unit(terms[j], cur.f, cur.w, in_ax, spin_ax, u);
        if (system == IGEA_ENVFUN_STRAPDOWN) {
            double q[4], C[9], nq = 0.0;
            for (int i = 0; i < 4; i++) {
                q[i] = IGEA_AT(traj, ldt, 0, 7 + i);
                nq += q[i] * q[i];
            }
            nq = sqrt(nq);
            for (int i = 0; i < 4; i++)
                q[i] /= nq;
            quat_dcm(q, C);
            mat_vec(C, u, cu);
        } else {
            memcpy(cu, u, sizeof cu);
        }
        memcpy(p_in + 3 * (size_t)j, cu, sizeof cu);
        /* outer integrand of a gyro term starts at 0 (inner = 0) */
    }
    /* epochs at t_0: everything is zero */
    while (e < nepochs && epochs[e] <= cur.t) {
        for (int j = 0; j < nterms; j++)
            for (int a = 0; a < 3; a++)
                IGEA_AT(out, mrows, 3 * (size_t)e + a, j) = 0.0;
        e++;
    }

    for (int k = 1; k < nsamp && e < nepochs; k++) {
        double C[9], h, Gm[9];
        prev = cur;
        load_sample(system, traj, ldt, k, &cur);
        h = cur.t - prev.t;
        if (system == IGEA_ENVFUN_STRAPDOWN) {
            double q[4], nq = 0.0;
            for (int i = 0; i < 4; i++) {
                q[i] = IGEA_AT(traj, ldt, k, 7 + i);
                nq += q[i] * q[i];
            }
            nq = sqrt(nq);
            for (int i = 0; i < 4; i++)
                q[i] /= nq;
            quat_dcm(q, C);
        }
        for (int a = 0; a < 3; a++)
            Wv[a] += 0.5 * h * (prev.fa[a] + cur.fa[a]);
        if (grav) {
            /* nominal trajectory: v' = f^a + g(r), trapezoid with a
             * predicted end point; G at the mid-step position */
            double rp[3], gnew[3], rmid[3], vnew[3];
            for (int a = 0; a < 3; a++)
                rp[a] = rn[a] + h * vn[a] +
                        0.5 * h * h * (prev.fa[a] + gacc_prev[a]);
            gravity(rp, gnew, NULL);
            for (int a = 0; a < 3; a++) {
                vnew[a] = vn[a] + 0.5 * h * (prev.fa[a] + gacc_prev[a] +
                                             cur.fa[a] + gnew[a]);
                rp[a] = rn[a] + 0.5 * h * (vn[a] + vnew[a]);
                rmid[a] = 0.5 * (rn[a] + rp[a]);
            }
            gravity(rmid, NULL, Gm);
            memcpy(rn, rp, sizeof rn);
            memcpy(vn, vnew, sizeof vn);
            gravity(rn, gacc_prev, NULL);
        }
        memcpy(vel_prev, vel, nt3 * sizeof(double));
        for (int j = 0; j < nterms; j++) {
            int fam = term_family(terms[j]);
            double *vj = vel + 3 * (size_t)j;
            double *ij = inner + 3 * (size_t)j;
            double *pi = p_in + 3 * (size_t)j;
            double *po = p_out + 3 * (size_t)j;
            double u[3], cu[3], co[3];
            if (fam == FAM_ATT) {
                int kax = (terms[j] >= IGEA_ENVFUN_TERM_ALIGN0_X)
                              ? terms[j] - IGEA_ENVFUN_TERM_ALIGN0_X
                              : terms[j] - IGEA_ENVFUN_TERM_ATT0_X;
                double ek[3] = {0, 0, 0};
                ek[kax] = 1.0;
                cross(Wv, ek, vj);
                continue;
            }
            term_unit(terms[j], cur.f, cur.w, in_ax, spin_ax, u);
            if (system == IGEA_ENVFUN_STRAPDOWN)
                mat_vec(C, u, cu);
            else
                memcpy(cu, u, sizeof cu);
            if (fam == FAM_ACC) {
                for (int a = 0; a < 3; a++)
                    vj[a] += 0.5 * h * (pi[a] + cu[a]);
            } else {
                for (int a = 0; a < 3; a++)
                    ij[a] += 0.5 * h * (pi[a] + cu[a]);
                if (system == IGEA_ENVFUN_STRAPDOWN)
                    cross(ij, cur.fa, co); /* Phi_u x f^a */
                else
                    cross(cur.fa, ij, co); /* f^a x alpha */
                for (int a = 0; a < 3; a++)
                    vj[a] += 0.5 * h * (po[a] + co[a]);
                memcpy(po, co, sizeof co);
            }
            memcpy(pi, cu, sizeof cu);
        }
        /* output kind */
        memcpy(val_prev, val, nt3 * sizeof(double));
        if (output == IGEA_ENVFUN_VELOCITY) {
            memcpy(val, vel, nt3 * sizeof(double));
        } else if (output == IGEA_ENVFUN_POSITION) {
            for (size_t i = 0; i < nt3; i++)
                pos[i] += 0.5 * h * (vel_prev[i] + vel[i]);
            memcpy(val, pos, nt3 * sizeof(double));
        } else {
            for (int j = 0; j < nterms; j++) {
                double *r = pos + 3 * (size_t)j, *v = sv + 3 * (size_t)j;
                double dS[3], rm[3], vnew[3];
                for (int a = 0; a < 3; a++) {
                    dS[a] = vel[3 * (size_t)j + a] - vel_prev[3 * (size_t)j + a];
                    rm[a] = r[a] + 0.5 * h * v[a] + 0.25 * h * dS[a];
                }
                for (int a = 0; a < 3; a++)
                    vnew[a] = v[a] + dS[a] +
                              h * (Gm[3 * a] * rm[0] + Gm[3 * a + 1] * rm[1] +
                                   Gm[3 * a + 2] * rm[2]);
                for (int a = 0; a < 3; a++) {
                    r[a] += 0.5 * h * (v[a] + vnew[a]);
                    v[a] = vnew[a];
                }
                memcpy(val + 3 * (size_t)j,
                       output == IGEA_ENVFUN_VELOCITY_G ? v : r,
                       3 * sizeof(double));
            }
        }
        /* epochs in (t_{k-1}, t_k]: linear interpolation */
        while (e < nepochs && epochs[e] <= cur.t) {
            double wgt = (epochs[e] - prev.t) / h;
            for (int j = 0; j < nterms; j++)
                for (int a = 0; a < 3; a++) {
                    size_t i = 3 * (size_t)j + a;
                    IGEA_AT(out, mrows, 3 * (size_t)e + a, j) =
                        (1.0 - wgt) * val_prev[i] + wgt * val[i];
                }
            e++;
        }
    }

    /* scale and copy out */
    for (int j = 0; j < nterms; j++) {
        double s = spec ? spec[j] : 1.0;
        for (size_t i = 0; i < mrows; i++) {
            double v = IGEA_AT(out, mrows, i, j) * s;
            if (!isfinite(v))
                st = IGEA_ENONFINITE;
        }
    }
    if (st == IGEA_OK)
        for (int j = 0; j < nterms; j++) {
            double s = spec ? spec[j] : 1.0;
            for (size_t i = 0; i < mrows; i++)
                IGEA_AT(S, lds, i, j) = IGEA_AT(out, mrows, i, j) * s;
        }
    free(work);
    return st;
}
