/* src/envfun.c - environment functions from a trajectory (METHODS 5). */
#include <limits.h>

#include "internal.h"
#include "rotation.h"

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

/* Per-sample state of the integration: instrument-axis f, w, the attitude
 * C (strapdown) and the a-frame specific force fa. */
typedef struct {
    double t, f[3], w[3], C[9], fa[3];
} sample;

static void load_sample(int system, const double *traj, int ldt, int k,
                        sample *s)
{
    double q[4];
    s->t = IGEA_AT(traj, ldt, k, 0);
    for (int i = 0; i < 3; i++) {
        s->f[i] = IGEA_AT(traj, ldt, k, 1 + i);
        s->w[i] = IGEA_AT(traj, ldt, k, 4 + i);
    }
    if (system == IGEA_ENVFUN_PLATFORM) {
        memcpy(s->fa, s->f, sizeof s->fa);
        return;
    }
    for (int i = 0; i < 4; i++)
        q[i] = IGEA_AT(traj, ldt, k, 7 + i);
    igea__quat_dcm_unit(q, s->C);
    igea__m3_vec(s->C, s->f, s->fa, 0);
}

/* The state of the integration over the samples: per term 3-vectors
 * (nterms x 3 each) and the nominal trajectory of the gravity kinds. */
typedef struct {
    int system, nterms, output, grav;
    const int *terms;
    int in_ax[3], spin_ax[3];
    size_t nt3;
    double *vel;      /* S_j(t_k) velocity function */
    double *inner;    /* Phi_u or alpha of gyro terms */
    double *p_in;     /* previous inner integrand */
    double *p_out;    /* previous outer integrand */
    double *pos;      /* position (or gravity s_r) */
    double *sv;       /* gravity-coupled s_v */
    double *val;      /* output value at t_k */
    double *val_prev; /* output value at t_{k-1} */
    double *vel_prev;
    double Wv[3], rn[3], vn[3], gacc_prev[3], Gm[9];
} integ;

/* Argument checks of igea_envfun_compute: 0 or -i; the platform axes. */
static int check_args(int system, int nsamp, const double *traj, int ldt,
                      int nterms, const int *terms, const int *axes,
                      int nepochs, const double *epochs, int output,
                      const double *S, int lds, int *in_ax, int *spin_ax)
{
    int st;
    igea__platform_axes(NULL, in_ax, spin_ax);
    if ((st = igea__traj_args(system, nsamp, traj, ldt)) != 0)
        return st;
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
    return 0;
}

/* Data checks: finite values, positive specs, increasing times, epochs
 * inside the trajectory, quaternions of non-zero norm. */
static int check_data(int system, int nsamp, const double *traj, int ldt,
                      int nterms, const double *spec, int nepochs,
                      const double *epochs)
{
    int nf = 0;
    if (!igea__finite_mat(nsamp, IGEA_ENVFUN_TRAJ_COLS, traj, ldt) ||
        !igea__finite_vec(nepochs, epochs, 1))
        return IGEA_ENONFINITE;
    if (spec && !igea__positive_vec(nterms, spec, &nf))
        return nf ? IGEA_ENONFINITE : IGEA_ENONPOSITIVE;
    int bad = igea__traj_times(nsamp, traj, ldt, nepochs, epochs);
    if (bad)
        return bad == 1 ? -3 : -9;
    if (system == IGEA_ENVFUN_STRAPDOWN)
        for (int k = 0; k < nsamp; k++)
            if (!(igea__traj_qnorm2(traj, ldt, k) > 1e-200))
                return IGEA_EDOMAIN;
    return 0;
}

/* The a-frame unit error of term j at sample s (family ACC or GYRO). */
static void term_integrand(const integ *g, int j, const sample *s, double *cu)
{
    double u[3];
    term_unit(g->terms[j], s->f, s->w, g->in_ax, g->spin_ax, u);
    if (g->system == IGEA_ENVFUN_STRAPDOWN)
        igea__m3_vec(s->C, u, cu, 0);
    else
        memcpy(cu, u, sizeof u);
}

/* Initial integrands at sample 0 (the outer integrand of a gyro term
 * starts at 0: inner = 0). */
static void init_integrands(integ *g, const sample *s)
{
    for (int j = 0; j < g->nterms; j++)
        if (term_family(g->terms[j]) != FAM_ATT)
            term_integrand(g, j, s, g->p_in + 3 * (size_t)j);
}

/* Gravity step: the nominal trajectory v' = f^a + g(r), trapezoid with a
 * predicted end point; the gradient Gm at the mid-step position. */
static void gravity_step(integ *g, const sample *prev, const sample *cur, double h)
{
    double rp[3], gnew[3], rmid[3], vnew[3];
    for (int a = 0; a < 3; a++)
        rp[a] = g->rn[a] + h * g->vn[a] +
                0.5 * h * h * (prev->fa[a] + g->gacc_prev[a]);
    gravity(rp, gnew, NULL);
    for (int a = 0; a < 3; a++) {
        vnew[a] = g->vn[a] + 0.5 * h * (prev->fa[a] + g->gacc_prev[a] +
                                        cur->fa[a] + gnew[a]);
        rp[a] = g->rn[a] + 0.5 * h * (g->vn[a] + vnew[a]);
        rmid[a] = 0.5 * (g->rn[a] + rp[a]);
    }
    gravity(rmid, NULL, g->Gm);
    memcpy(g->rn, rp, sizeof g->rn);
    memcpy(g->vn, vnew, sizeof g->vn);
    gravity(g->rn, g->gacc_prev, NULL);
}

/* Term step: the velocity functions of every term at sample cur. */
static void term_step(integ *g, const sample *cur, double h)
{
    for (int j = 0; j < g->nterms; j++) {
        int fam = term_family(g->terms[j]);
        double *vj = g->vel + 3 * (size_t)j;
        double *ij = g->inner + 3 * (size_t)j;
        double *pi = g->p_in + 3 * (size_t)j;
        double *po = g->p_out + 3 * (size_t)j;
        double cu[3], co[3];
        if (fam == FAM_ATT) {
            int kax = (g->terms[j] >= IGEA_ENVFUN_TERM_ALIGN0_X)
                          ? g->terms[j] - IGEA_ENVFUN_TERM_ALIGN0_X
                          : g->terms[j] - IGEA_ENVFUN_TERM_ATT0_X;
            double ek[3] = {0, 0, 0};
            ek[kax] = 1.0;
            igea__cross(g->Wv, ek, vj);
            continue;
        }
        term_integrand(g, j, cur, cu);
        if (fam == FAM_ACC) {
            for (int a = 0; a < 3; a++)
                vj[a] += 0.5 * h * (pi[a] + cu[a]);
        } else {
            for (int a = 0; a < 3; a++)
                ij[a] += 0.5 * h * (pi[a] + cu[a]);
            if (g->system == IGEA_ENVFUN_STRAPDOWN)
                igea__cross(ij, cur->fa, co); /* Phi_u x f^a */
            else
                igea__cross(cur->fa, ij, co); /* f^a x alpha */
            for (int a = 0; a < 3; a++)
                vj[a] += 0.5 * h * (po[a] + co[a]);
            memcpy(po, co, sizeof co);
        }
        memcpy(pi, cu, sizeof cu);
    }
}

/* Output step: val <- the output kind at sample k (val_prev the one at
 * k - 1). */
static void output_step(integ *g, double h)
{
    size_t nt3 = g->nt3;
    memcpy(g->val_prev, g->val, nt3 * sizeof(double));
    if (g->output == IGEA_ENVFUN_VELOCITY) {
        memcpy(g->val, g->vel, nt3 * sizeof(double));
    } else if (g->output == IGEA_ENVFUN_POSITION) {
        for (size_t i = 0; i < nt3; i++)
            g->pos[i] += 0.5 * h * (g->vel_prev[i] + g->vel[i]);
        memcpy(g->val, g->pos, nt3 * sizeof(double));
    } else {
        const double *Gm = g->Gm;
        for (int j = 0; j < g->nterms; j++) {
            double *r = g->pos + 3 * (size_t)j, *v = g->sv + 3 * (size_t)j;
            double dS[3], rm[3], vnew[3];
            for (int a = 0; a < 3; a++) {
                dS[a] = g->vel[3 * (size_t)j + a] - g->vel_prev[3 * (size_t)j + a];
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
            memcpy(g->val + 3 * (size_t)j,
                   g->output == IGEA_ENVFUN_VELOCITY_G ? v : r,
                   3 * sizeof(double));
        }
    }
}

/* Epoch interpolation: rows of the epochs e.. in (t0, t1] (weight of val),
 * zero at t_0 when h = 0; returns the next epoch. */
static int interpolate(const integ *g, int e, int nepochs, const double *epochs,
                       double t0, double t1, double *out, size_t mrows)
{
    while (e < nepochs && epochs[e] <= t1) {
        double wgt = t1 > t0 ? (epochs[e] - t0) / (t1 - t0) : 0.0;
        for (int j = 0; j < g->nterms; j++)
            for (int a = 0; a < 3; a++) {
                size_t i = 3 * (size_t)j + a;
                IGEA_AT(out, mrows, 3 * (size_t)e + a, j) =
                    t1 > t0 ? (1.0 - wgt) * g->val_prev[i] + wgt * g->val[i] : 0.0;
            }
        e++;
    }
    return e;
}

/* Scale the columns by spec into S: IGEA_ENONFINITE (S untouched) if a
 * value overflows. */
static int scale_out(int nterms, const double *spec, const double *out,
                     size_t mrows, double *S, int lds)
{
    for (int j = 0; j < nterms; j++) {
        double s = spec ? spec[j] : 1.0;
        for (size_t i = 0; i < mrows; i++)
            if (!isfinite(IGEA_AT(out, mrows, i, j) * s))
                return IGEA_ENONFINITE;
    }
    for (int j = 0; j < nterms; j++) {
        double s = spec ? spec[j] : 1.0;
        for (size_t i = 0; i < mrows; i++)
            IGEA_AT(S, lds, i, j) = IGEA_AT(out, mrows, i, j) * s;
    }
    return IGEA_OK;
}

int igea_envfun_compute(int system, int nsamp, const double *traj, int ldt,
                        int nterms, const int *terms, const int *axes,
                        int nepochs, const double *epochs, const double *spec,
                        int output, double *S, int lds)
{
    integ g;
    int st = check_args(system, nsamp, traj, ldt, nterms, terms, axes, nepochs,
                        epochs, output, S, lds, g.in_ax, g.spin_ax);
    if (st == 0)
        st = check_data(system, nsamp, traj, ldt, nterms, spec, nepochs, epochs);
    if (st)
        return st;

    size_t nt3 = (size_t)nterms * 3, mrows = (size_t)nepochs * 3;
    double *work = igea__dalloc(nt3 * 9 + mrows * (size_t)nterms);
    if (!work)
        return IGEA_ENOMEM;
    memset(work, 0, nt3 * 9 * sizeof(double));
    g.system = system;
    g.nterms = nterms;
    g.terms = terms;
    g.output = output;
    g.grav = (output == IGEA_ENVFUN_VELOCITY_G || output == IGEA_ENVFUN_POSITION_G);
    g.nt3 = nt3;
    g.vel = work;
    g.inner = g.vel + nt3;
    g.p_in = g.inner + nt3;
    g.p_out = g.p_in + nt3;
    g.pos = g.p_out + nt3;
    g.sv = g.pos + nt3;
    g.val = g.sv + nt3;
    g.val_prev = g.val + nt3;
    g.vel_prev = g.val_prev + nt3;
    double *out = g.vel_prev + nt3; /* 3 nepochs x nterms, ld = mrows */
    for (int a = 0; a < 3; a++)
        g.Wv[a] = g.rn[a] = g.vn[a] = 0.0;
    for (int i = 0; i < 9; i++)
        g.Gm[i] = 0.0;

    sample cur, prev;
    load_sample(system, traj, ldt, 0, &cur);
    gravity(g.rn, g.gacc_prev, NULL);
    init_integrands(&g, &cur);
    /* epochs at t_0: everything is zero */
    int e = interpolate(&g, 0, nepochs, epochs, cur.t, cur.t, out, mrows);
    for (int k = 1; k < nsamp && e < nepochs; k++) {
        prev = cur;
        load_sample(system, traj, ldt, k, &cur);
        double h = cur.t - prev.t;
        for (int a = 0; a < 3; a++)
            g.Wv[a] += 0.5 * h * (prev.fa[a] + cur.fa[a]);
        if (g.grav)
            gravity_step(&g, &prev, &cur, h);
        memcpy(g.vel_prev, g.vel, nt3 * sizeof(double));
        term_step(&g, &cur, h);
        output_step(&g, h);
        /* epochs in (t_{k-1}, t_k]: linear interpolation */
        e = interpolate(&g, e, nepochs, epochs, prev.t, cur.t, out, mrows);
    }
    st = scale_out(nterms, spec, out, mrows, S, lds);
    free(work);
    return st;
}
