/* src/envfun.c - environment functions from a trajectory (METHODS 5). */
#include <limits.h>

#include "internal.h"
#include "rotation.h"

#include "igea/envfun.h"
#include "igea/nav.h"

#define EARTH_RADIUS 6371000.0
#define EARTH_MU 3.986004418e14

#include "envfun_terms.h"

/* ---- the term catalogue ------------------------------------------------ */

#define G0 9.80665                                   /* m/s^2 per g */
#define DEG_H (3.14159265358979323846 / 180.0 / 3600.0) /* rad/s per deg/h */

/* Systems of a term. */
enum { SYS_SD = 1, SYS_PF = 2, SYS_BOTH = 3 };

/* Factors of a unit error u = e_j prod(factors): F_X..F_Z a fixed axis of
 * f, F_J f_j, F_I/F_S/F_O gyro j's input/spin/output axis of f, F_ABS
 * |f_j|, F_W w_j, F_NO none. */
enum { F_X = 0, F_Y, F_Z, F_J, F_I, F_S, F_O, F_ABS, F_W, F_NO = -1 };

/* Name, unit, default 1-sigma spec, systems, family, axis j and factors of
 * every code, by code. */
typedef struct {
    const char *name, *unit;
    double spec;
    signed char sys, fam, j, m[3];
} term_def;

#define ACC IGEA__FAM_ACC
#define GYR IGEA__FAM_GYRO
#define ATT IGEA__FAM_ATT
#define TD(name, unit, spec, sys, fam, j, m0, m1, m2) \
    {name, unit, spec, sys, fam, j, {m0, m1, m2}}
#define AXES3(pre, unit, spec, sys, fam, m0, m1, m2)                 \
    TD(pre "x", unit, spec, sys, fam, 0, m0, m1, m2),                \
    TD(pre "y", unit, spec, sys, fam, 1, m0, m1, m2),                \
    TD(pre "z", unit, spec, sys, fam, 2, m0, m1, m2)
/* e_j times f_a, f_b (pairs in the order xy xz yx yz zx zy) */
#define PAIRS6(pre, unit, spec, ma, mb)                                        \
    TD(pre "xy", unit, spec, SYS_BOTH, ACC, 0, ma(0, 1), mb(0, 1), F_NO),      \
    TD(pre "xz", unit, spec, SYS_BOTH, ACC, 0, ma(0, 2), mb(0, 2), F_NO),      \
    TD(pre "yx", unit, spec, SYS_BOTH, ACC, 1, ma(1, 0), mb(1, 0), F_NO),      \
    TD(pre "yz", unit, spec, SYS_BOTH, ACC, 1, ma(1, 2), mb(1, 2), F_NO),      \
    TD(pre "zx", unit, spec, SYS_BOTH, ACC, 2, ma(2, 0), mb(2, 0), F_NO),      \
    TD(pre "zy", unit, spec, SYS_BOTH, ACC, 2, ma(2, 1), mb(2, 1), F_NO)
#define PJ(j, k) (j)
#define PK(j, k) (k)
#define PN(j, k) F_NO
#define SIZE3(pre, j)                                                          \
    TD(pre "x", "m", 0.01, SYS_SD, IGEA__FAM_SIZE, j, 0, F_NO, F_NO),          \
    TD(pre "y", "m", 0.01, SYS_SD, IGEA__FAM_SIZE, j, 1, F_NO, F_NO),          \
    TD(pre "z", "m", 0.01, SYS_SD, IGEA__FAM_SIZE, j, 2, F_NO, F_NO)

#define GS (0.5 * DEG_H / G0)        /* 0.5 deg/h/g */
#define GSS (0.5 * DEG_H / (G0 * G0)) /* 0.5 deg/h/g^2 */
#define US2 (1e-5 / G0)              /* 10 ug/g^2 */
static const term_def TERMS[IGEA_ENVFUN_TERM_END] = {
    AXES3("acc_bias_", "m/s^2", 1e-3 * G0, SYS_BOTH, ACC, F_NO, F_NO, F_NO),
    AXES3("acc_scale_", "-", 1e-4, SYS_BOTH, ACC, F_J, F_NO, F_NO),
    AXES3("acc_sq_", "1/(m/s^2)", US2, SYS_BOTH, ACC, F_J, F_J, F_NO),
    PAIRS6("acc_mis_", "-", 1e-4, PK, PN),
    AXES3("gyro_bias_", "rad/s", 0.5 * DEG_H, SYS_BOTH, GYR, F_NO, F_NO, F_NO),
    AXES3("gyro_g_", "rad/s/(m/s^2)", GS, SYS_SD, GYR, F_J, F_NO, F_NO),
    AXES3("gyro_scale_", "-", 1e-4, SYS_SD, GYR, F_W, F_NO, F_NO),
    AXES3("att0_", "rad", 1e-4, SYS_SD, ATT, F_NO, F_NO, F_NO),
    AXES3("gyro_gi_", "rad/s/(m/s^2)", GS, SYS_PF, GYR, F_I, F_NO, F_NO),
    AXES3("gyro_gs_", "rad/s/(m/s^2)", GS, SYS_PF, GYR, F_S, F_NO, F_NO),
    AXES3("align0_", "rad", 1e-4, SYS_PF, ATT, F_NO, F_NO, F_NO),
    TD("", "", 0.0, 0, IGEA__FAM_NONE, 0, F_NO, F_NO, F_NO), /* code 36 */
    AXES3("gyro_go_", "rad/s/(m/s^2)", GS, SYS_BOTH, GYR, F_O, F_NO, F_NO),
    AXES3("gyro_gii_", "rad/s/(m/s^2)^2", GSS, SYS_BOTH, GYR, F_I, F_I, F_NO),
    AXES3("gyro_gss_", "rad/s/(m/s^2)^2", GSS, SYS_BOTH, GYR, F_S, F_S, F_NO),
    AXES3("gyro_goo_", "rad/s/(m/s^2)^2", GSS, SYS_BOTH, GYR, F_O, F_O, F_NO),
    AXES3("gyro_gis_", "rad/s/(m/s^2)^2", GSS, SYS_BOTH, GYR, F_I, F_S, F_NO),
    AXES3("gyro_gio_", "rad/s/(m/s^2)^2", GSS, SYS_BOTH, GYR, F_I, F_O, F_NO),
    AXES3("gyro_gso_", "rad/s/(m/s^2)^2", GSS, SYS_BOTH, GYR, F_S, F_O, F_NO),
    AXES3("gyro_gspin_", "rad/s/(m/s^2)", GS, SYS_SD, GYR, F_S, F_NO, F_NO),
    AXES3("acc_cube_", "1/(m/s^2)^2", 1e-6 / (G0 * G0), SYS_BOTH, ACC, F_J, F_J, F_J),
    AXES3("acc_asym_", "-", 2e-5, SYS_BOTH, ACC, F_ABS, F_NO, F_NO),
    PAIRS6("acc_cross_", "1/(m/s^2)", US2, PJ, PK),
    PAIRS6("acc_xsq_", "1/(m/s^2)", US2, PK, PK),
    TD("acc_xprod_x", "1/(m/s^2)", US2, SYS_BOTH, ACC, 0, F_Y, F_Z, F_NO),
    TD("acc_xprod_y", "1/(m/s^2)", US2, SYS_BOTH, ACC, 1, F_X, F_Z, F_NO),
    TD("acc_xprod_z", "1/(m/s^2)", US2, SYS_BOTH, ACC, 2, F_X, F_Y, F_NO),
    TD("pos0_x", "m", 10.0, SYS_BOTH, IGEA__FAM_POS0, 0, F_NO, F_NO, F_NO),
    TD("pos0_z", "m", 10.0, SYS_BOTH, IGEA__FAM_POS0, 2, F_NO, F_NO, F_NO),
    AXES3("lever_", "m", 0.1, SYS_BOTH, IGEA__FAM_LEVER, F_NO, F_NO, F_NO),
    SIZE3("acc_size_x", 0), SIZE3("acc_size_y", 1), SIZE3("acc_size_z", 2),
};
#undef AXES3

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

/* The equation of each family (docs/terms.md), by name prefix: j is the
 * first axis letter of the name, k the second; u the accelerometer error,
 * eps the gyro rate error (strapdown, body axes) or platform drift, per
 * unit coefficient; I(j), S(j), O(j) gyro j's input, spin, output axes. */
static const struct {
    const char *prefix, *formula;
} FORMULAS[] = {
    {"acc_bias_", "u = e_j"},
    {"acc_scale_", "u = e_j f_j"},
    {"acc_sq_", "u = e_j f_j^2"},
    {"acc_mis_", "u = e_j f_k"},
    {"acc_cube_", "u = e_j f_j^3"},
    {"acc_asym_", "u = e_j |f_j|"},
    {"acc_cross_", "u = e_j f_j f_k"},
    {"acc_xsq_", "u = e_j f_k^2"},
    {"acc_xprod_", "u = e_j f_k f_l (k, l the other axes)"},
    {"acc_size_", "u = e_j (w' x e_k + w x (w x e_k))_j"},
    {"gyro_bias_", "eps = e_j"},
    {"gyro_g_", "eps = e_j f_j"},
    {"gyro_scale_", "eps = e_j w_j"},
    {"gyro_gi_", "eps = e_j f_I(j)"},
    {"gyro_gs_", "eps = e_j f_S(j)"},
    {"gyro_gspin_", "eps = e_j f_S(j)"},
    {"gyro_go_", "eps = e_j f_O(j)"},
    {"gyro_gii_", "eps = e_j f_I(j)^2"},
    {"gyro_gss_", "eps = e_j f_S(j)^2"},
    {"gyro_goo_", "eps = e_j f_O(j)^2"},
    {"gyro_gis_", "eps = e_j f_I(j) f_S(j)"},
    {"gyro_gio_", "eps = e_j f_I(j) f_O(j)"},
    {"gyro_gso_", "eps = e_j f_S(j) f_O(j)"},
    {"att0_", "phi0 = e_j: S = W x e_j"},
    {"align0_", "alpha0 = e_j: S = W x e_j"},
    {"pos0_x", "S = (W x e_z) / R"},
    {"pos0_z", "S = -(W x e_x) / R"},
    {"lever_", "S = -(C (w x e_j) - C_0 (w_0 x e_j))"},
};

const char *igea_envfun_term_formula(int term)
{
    const char *name = igea_envfun_term_name(term);
    if (!*name)
        return "";
    for (size_t i = 0; i < sizeof FORMULAS / sizeof FORMULAS[0]; i++)
        if (!strncmp(name, FORMULAS[i].prefix, strlen(FORMULAS[i].prefix)))
            return FORMULAS[i].formula;
    return "";
}

int igea_envfun_term_count(void)
{
    return IGEA_ENVFUN_TERM_END;
}

const char *igea_envfun_term_name(int term)
{
    return (term >= 0 && term < IGEA_ENVFUN_TERM_END) ? TERMS[term].name : "";
}

const char *igea_envfun_term_unit(int term)
{
    return (term >= 0 && term < IGEA_ENVFUN_TERM_END) ? TERMS[term].unit : "";
}

int igea_envfun_term_code(int system, const char *name)
{
    if (system != IGEA_ENVFUN_STRAPDOWN && system != IGEA_ENVFUN_PLATFORM)
        return -1;
    if (!name || !*name)
        return -2;
    for (int k = 0; k < IGEA_ENVFUN_TERM_END; k++)
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

int igea_envfun_all_terms(int system, int *terms, int cap, int *n)
{
    int cnt = 0;
    if (system != IGEA_ENVFUN_STRAPDOWN && system != IGEA_ENVFUN_PLATFORM)
        return -1;
    if (!terms)
        return -2;
    for (int k = 0; k < IGEA_ENVFUN_TERM_END; k++)
        cnt += igea_envfun_term_valid(system, k);
    if (cap < cnt)
        return -3;
    if (!n)
        return -4;
    cnt = 0;
    for (int k = 0; k < IGEA_ENVFUN_TERM_END; k++)
        if (igea_envfun_term_valid(system, k))
            terms[cnt++] = k;
    *n = cnt;
    return 0;
}

int igea_envfun_term_valid(int system, int term)
{
    if (term < 0 || term >= IGEA_ENVFUN_TERM_END)
        return 0;
    if (system == IGEA_ENVFUN_STRAPDOWN)
        return (TERMS[term].sys & SYS_SD) != 0;
    if (system == IGEA_ENVFUN_PLATFORM)
        return (TERMS[term].sys & SYS_PF) != 0;
    return 0;
}

/* ---- the instrument-error model (envfun_terms.h) ------------------------ */

int igea__term_family(int term)
{
    return (term >= 0 && term < IGEA_ENVFUN_TERM_END) ? TERMS[term].fam
                                                       : IGEA__FAM_NONE;
}

int igea__term_axis(int term, int *k)
{
    *k = TERMS[term].fam == IGEA__FAM_SIZE ? TERMS[term].m[0] : -1;
    return TERMS[term].j;
}

int igea__term_uses_out(int term)
{
    const term_def *d = &TERMS[term];
    return d->fam == IGEA__FAM_GYRO &&
           (d->m[0] == F_O || d->m[1] == F_O || d->m[2] == F_O);
}

int igea__term_lists(int system, int nerr, const double *err, int *acc, int *nacc, int *size,
                     int *nsize, int *gyro, int *ngyro, int *lever, int *uses_out)
{
    *nacc = *nsize = *ngyro = *lever = *uses_out = 0;
    for (int k = 0; err && k < nerr; k++) {
        if (err[k] == 0.0)
            continue;
        if (!igea_envfun_term_valid(system, k))
            return -1;
        int fam = igea__term_family(k);
        if (fam == IGEA__FAM_ACC || fam == IGEA__FAM_SIZE)
            acc[(*nacc)++] = k;
        if (fam == IGEA__FAM_SIZE)
            size[(*nsize)++] = k;
        if (fam == IGEA__FAM_GYRO)
            gyro[(*ngyro)++] = k;
        *lever |= fam == IGEA__FAM_LEVER;
        *uses_out |= igea__term_uses_out(k);
    }
    return 0;
}

int igea__out_axes(const int *in, const int *spin, int *out)
{
    int st = 0;
    for (int j = 0; j < 3; j++) {
        if (in[j] == spin[j]) {
            out[j] = (in[j] + 2) % 3;
            st = -1;
        } else {
            out[j] = 3 - in[j] - spin[j];
        }
    }
    return st;
}

void igea__pos0_rotation(int term, double *theta)
{
    theta[0] = theta[1] = theta[2] = 0.0;
    if (term == IGEA_ENVFUN_TERM_POS0_X)
        theta[2] = -1.0 / EARTH_RADIUS;
    else if (term == IGEA_ENVFUN_TERM_POS0_Z)
        theta[0] = 1.0 / EARTH_RADIUS;
}

static double factor(int fc, int j, const double *f, const double *w,
                     const int *in, const int *spin, const int *out)
{
    switch (fc) {
    case F_J: return f[j];
    case F_I: return f[in[j]];
    case F_S: return f[spin[j]];
    case F_O: return f[out[j]];
    case F_ABS: return fabs(f[j]);
    case F_W: return w[j];
    case F_NO: return 1.0;
    default: return f[fc];
    }
}

void igea__term_unit(int term, const double *f, const double *w,
                     const int *in, const int *spin, const int *out, double *u)
{
    const term_def *d = &TERMS[term];
    int j = d->j;
    u[0] = u[1] = u[2] = 0.0;
    if (d->fam == IGEA__FAM_SIZE) {
        int k = d->m[0];
        double w2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        u[j] = w[j] * w[k] - (j == k ? w2 : 0.0); /* (w x (w x e_k))_j */
        return;
    }
    u[j] = factor(d->m[0], j, f, w, in, spin, out) *
           factor(d->m[1], j, f, w, in, spin, out) *
           factor(d->m[2], j, f, w, in, spin, out);
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

/* Per-sample state of the integration: index k, instrument-axis f, w, the
 * attitude C (strapdown; platform when a term needs the body attitude) and
 * the a-frame specific force fa. */
typedef struct {
    double t, f[3], w[3], C[9], fa[3];
    int k;
} sample;

/* The state of the integration over the samples: per column 3-vectors
 * (ncols x 3 each) and the nominal trajectory of the gravity kinds. Columns
 * 0 .. nb-1 are the catalogue terms, nb .. the user terms. */
typedef struct {
    int system, nterms, nb, output, grav, need_att;
    const int *terms, *ukind;
    const double *user;
    int ldu;
    int in_ax[3], spin_ax[3], out_ax[3];
    size_t nt3;
    double *vel;      /* S_j(t_k) velocity function */
    double *inner;    /* Phi_u or alpha of gyro terms */
    double *p_in;     /* previous inner integrand (lever: value at t_0) */
    double *p_out;    /* previous outer integrand */
    double *pos;      /* position (or gravity s_r) */
    double *sv;       /* gravity-coupled s_v */
    double *val;      /* output value at t_k */
    double *val_prev; /* output value at t_{k-1} */
    double *vel_prev;
    double Wv[3], rn[3], vn[3], gacc_prev[3], Gm[9];
    const double *site; /* the launch point (igea_nav_site) or NULL */
    double pad[6];      /* pad-velocity parts w_L x e_x, w_L x e_z of pos0_x, pos0_z */
    double theta[6];    /* their frame rotations per metre on the ellipsoid */
    double Gpad[9];     /* the J2 gravity gradient at the pad, LI axes */
} integ;

/* Gravity and its gradient at launch-frame r: with a site the J2 field of
 * the site in LI (dw's and the navigation's), else the point mass above. */
static void grav_at(const integ *g, const double *r, double *ga, double *G)
{
    double tmp[3];
    if (g->site && !igea_nav_gravity_li(g->site, IGEA_NAV_GRAVITY_J2, r, ga ? ga : tmp, G))
        return;
    gravity(r, ga, G);
}

static void load_sample(const integ *g, const double *traj, int ldt, int k,
                        sample *s)
{
    double q[4];
    s->k = k;
    s->t = IGEA_AT(traj, ldt, k, 0);
    for (int i = 0; i < 3; i++) {
        s->f[i] = IGEA_AT(traj, ldt, k, 1 + i);
        s->w[i] = IGEA_AT(traj, ldt, k, 4 + i);
    }
    if (g->system == IGEA_ENVFUN_PLATFORM)
        memcpy(s->fa, s->f, sizeof s->fa);
    if (g->system == IGEA_ENVFUN_PLATFORM && !g->need_att)
        return;
    for (int i = 0; i < 4; i++)
        q[i] = IGEA_AT(traj, ldt, k, 7 + i);
    igea__quat_dcm_unit(q, s->C);
    if (g->system == IGEA_ENVFUN_STRAPDOWN)
        igea__m3_vec(s->C, s->f, s->fa, 0);
}

/* Family of column j. */
static int col_family(const integ *g, int j)
{
    if (j >= g->nb)
        return g->ukind[j - g->nb] == IGEA_ENVFUN_USER_GYRO ? IGEA__FAM_GYRO
                                                            : IGEA__FAM_ACC;
    return igea__term_family(g->terms[j]);
}

/* Arguments of igea_envfun_compute_user (positions of that function): 0 or
 * -i; the gyro axes; need_att. */
static int check_args(int system, int nsamp, const double *traj, int ldt,
                      int nterms, const int *terms, const int *axes, int nuser,
                      const int *ukind, const double *user, int ldu,
                      int nepochs, const double *epochs, int output,
                      const double *S, int lds, integ *g)
{
    int st, uses_out = 0;
    igea__platform_axes(NULL, g->in_ax, g->spin_ax);
    if ((st = igea__traj_args(system, nsamp, traj, ldt)) != 0)
        return st;
    if (nterms < 0 || nterms > INT_MAX / 3 || (nterms == 0 && nuser <= 0))
        return -5;
    if (!terms && nterms > 0)
        return -6;
    g->need_att = 0;
    for (int j = 0; j < nterms; j++) {
        if (!igea_envfun_term_valid(system, terms[j]))
            return -6;
        g->need_att |= igea__term_family(terms[j]) == IGEA__FAM_LEVER;
        uses_out |= igea__term_uses_out(terms[j]);
    }
    if (system == IGEA_ENVFUN_PLATFORM && igea__platform_axes(axes, g->in_ax, g->spin_ax))
        return -7;
    if (igea__out_axes(g->in_ax, g->spin_ax, g->out_ax) && uses_out)
        return -7;
    if (nuser < 0 || nuser > INT_MAX / 3 - nterms)
        return -8;
    if (nuser > 0 && !ukind)
        return -9;
    for (int i = 0; i < nuser; i++)
        if (ukind[i] != IGEA_ENVFUN_USER_ACC && ukind[i] != IGEA_ENVFUN_USER_GYRO)
            return -9;
    if (nuser > 0 && !user)
        return -10;
    if (nuser > 0 && ldu < nsamp)
        return -11;
    if (nepochs < 1 || nepochs > INT_MAX / 3)
        return -12;
    if (!epochs)
        return -13;
    if (output < IGEA_ENVFUN_VELOCITY || output > IGEA_ENVFUN_POSITION_G)
        return -15;
    if (!S)
        return -16;
    if (lds < 3 * nepochs)
        return -17;
    return 0;
}

/* Data checks: finite values, positive specs, increasing times, epochs
 * inside the trajectory, quaternions of non-zero norm where used. */
static int check_data(const integ *g, int nsamp, const double *traj, int ldt,
                      const double *spec, int nepochs, const double *epochs)
{
    int nf = 0, nu = g->nterms - g->nb;
    if (!igea__finite_mat(nsamp, IGEA_ENVFUN_TRAJ_COLS, traj, ldt) ||
        !igea__finite_vec(nepochs, epochs, 1) ||
        (nu > 0 && !igea__finite_mat(nsamp, 3 * nu, g->user, g->ldu)))
        return IGEA_ENONFINITE;
    if (spec && !igea__positive_vec(g->nterms, spec, &nf))
        return nf ? IGEA_ENONFINITE : IGEA_ENONPOSITIVE;
    int bad = igea__traj_times(nsamp, traj, ldt, nepochs, epochs);
    if (bad)
        return bad == 1 ? -3 : -13;
    if (g->system == IGEA_ENVFUN_STRAPDOWN || g->need_att)
        for (int k = 0; k < nsamp; k++)
            if (!(igea__traj_qnorm2(traj, ldt, k) > 1e-200))
                return IGEA_EDOMAIN;
    return 0;
}

/* The a-frame unit error of column j at sample s (family ACC, GYRO or the
 * centripetal part of SIZE). */
static void term_integrand(const integ *g, int j, const sample *s, double *cu)
{
    double u[3];
    if (j >= g->nb) {
        size_t c = 3 * (size_t)(j - g->nb);
        for (int a = 0; a < 3; a++)
            u[a] = IGEA_AT(g->user, g->ldu, s->k, c + a);
    } else {
        igea__term_unit(g->terms[j], s->f, s->w, g->in_ax, g->spin_ax, g->out_ax, u);
    }
    if (g->system == IGEA_ENVFUN_STRAPDOWN)
        igea__m3_vec(s->C, u, cu, 0);
    else
        memcpy(cu, u, sizeof u);
}

/* C (w x e_k) of a lever-arm term at sample s. */
static void lever_rate(const sample *s, int k, double *out)
{
    double ek[3] = {0, 0, 0}, wx[3];
    ek[k] = 1.0;
    igea__cross(s->w, ek, wx);
    igea__m3_vec(s->C, wx, out, 0);
}

/* Initial integrands at sample 0 (the outer integrand of a gyro term
 * starts at 0: inner = 0; a lever term keeps its value at t_0). */
static void init_integrands(integ *g, const sample *s)
{
    for (int j = 0; j < g->nterms; j++) {
        int fam = col_family(g, j), k;
        if (fam == IGEA__FAM_ACC || fam == IGEA__FAM_GYRO || fam == IGEA__FAM_SIZE)
            term_integrand(g, j, s, g->p_in + 3 * (size_t)j);
        else if (fam == IGEA__FAM_LEVER)
            lever_rate(s, igea__term_axis(g->terms[j], &k), g->p_in + 3 * (size_t)j);
    }
}

/* Gravity step: the nominal trajectory v' = f^a + g(r), trapezoid with a
 * predicted end point; the gradient Gm at the mid-step position. */
static void gravity_step(integ *g, const sample *prev, const sample *cur, double h)
{
    double rp[3], gnew[3], rmid[3], vnew[3];
    for (int a = 0; a < 3; a++)
        rp[a] = g->rn[a] + h * g->vn[a] +
                0.5 * h * h * (prev->fa[a] + g->gacc_prev[a]);
    grav_at(g, rp, gnew, NULL);
    for (int a = 0; a < 3; a++) {
        vnew[a] = g->vn[a] + 0.5 * h * (prev->fa[a] + g->gacc_prev[a] +
                                        cur->fa[a] + gnew[a]);
        rp[a] = g->rn[a] + 0.5 * h * (g->vn[a] + vnew[a]);
        rmid[a] = 0.5 * (g->rn[a] + rp[a]);
    }
    grav_at(g, rmid, NULL, g->Gm);
    memcpy(g->rn, rp, sizeof g->rn);
    memcpy(g->vn, vnew, sizeof g->vn);
    grav_at(g, g->rn, g->gacc_prev, NULL);
}

/* Velocity function of a column that is a function of the sample (ATT:
 * W x e_k; POS0: theta x W; LEVER: -(C (w x e_k) - its value at t_0)). */
static void direct_step(integ *g, int j, int fam, const sample *cur, double *vj)
{
    int k, ax = igea__term_axis(g->terms[j], &k);
    double v[3] = {0, 0, 0};
    if (fam == IGEA__FAM_ATT) {
        v[ax] = 1.0;
        igea__cross(g->Wv, v, vj);
    } else if (fam == IGEA__FAM_POS0) {
        if (g->site)
            memcpy(v, g->theta + 3 * (ax == 2), sizeof v);
        else
            igea__pos0_rotation(g->terms[j], v);
        igea__cross(v, g->Wv, vj);
        for (int a = 0; g->site && a < 3; a++)
            vj[a] += g->pad[3 * (ax == 2) + a];
    } else {
        lever_rate(cur, ax, v);
        for (int a = 0; a < 3; a++)
            vj[a] = -(v[a] - g->p_in[3 * (size_t)j + a]);
    }
}

/* Term step: the velocity functions of every column at sample cur. */
static void term_step(integ *g, const sample *prev, const sample *cur, double h)
{
    for (int j = 0; j < g->nterms; j++) {
        int fam = col_family(g, j);
        double *vj = g->vel + 3 * (size_t)j;
        double *ij = g->inner + 3 * (size_t)j;
        double *pi = g->p_in + 3 * (size_t)j;
        double *po = g->p_out + 3 * (size_t)j;
        double cu[3], co[3];
        if (fam == IGEA__FAM_ATT || fam == IGEA__FAM_POS0 || fam == IGEA__FAM_LEVER) {
            direct_step(g, j, fam, cur, vj);
            continue;
        }
        term_integrand(g, j, cur, cu);
        if (fam == IGEA__FAM_SIZE) {
            /* tangential part: Stieltjes sum of e_j (dw x e_k)_j, C at the
             * mid-step (mean of the ends) */
            int k, ax = igea__term_axis(g->terms[j], &k);
            double dw[3], ek[3] = {0, 0, 0}, tg[3];
            for (int a = 0; a < 3; a++)
                dw[a] = cur->w[a] - prev->w[a];
            ek[k] = 1.0;
            igea__cross(dw, ek, tg);
            for (int a = 0; a < 3; a++)
                vj[a] += 0.5 * (prev->C[3 * a + ax] + cur->C[3 * a + ax]) * tg[ax];
        }
        if (fam != IGEA__FAM_GYRO) {
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
 * val (the value at t_0: zero but for a launch-point term with a site)
 * when h = 0; returns the next epoch. */
static int interpolate(const integ *g, int e, int nepochs, const double *epochs,
                       double t0, double t1, double *out, size_t mrows)
{
    while (e < nepochs && epochs[e] <= t1) {
        double wgt = t1 > t0 ? (epochs[e] - t0) / (t1 - t0) : 0.0;
        for (int j = 0; j < g->nterms; j++)
            for (int a = 0; a < 3; a++) {
                size_t i = 3 * (size_t)j + a;
                IGEA_AT(out, mrows, 3 * (size_t)e + a, j) =
                    t1 > t0 ? (1.0 - wgt) * g->val_prev[i] + wgt * g->val[i] : g->val[i];
            }
        e++;
    }
    return e;
}

/* With a site, the launch-point columns start at their pad velocity
 * w_L x e_k (the velocity function, the gravity-coupled velocity) and at
 * e_k (the gravity-coupled position: the navigation starts at the stated
 * point); the value at t_0 of the output kind. */
static void pad_start(integ *g)
{
    for (int j = 0; g->site && j < g->nb; j++) {
        if (igea__term_family(g->terms[j]) != IGEA__FAM_POS0)
            continue;
        int k, ax = igea__term_axis(g->terms[j], &k);
        double *vj = g->vel + 3 * (size_t)j;
        for (int a = 0; a < 3; a++) {
            vj[a] = g->pad[3 * (ax == 2) + a];
            g->sv[3 * (size_t)j + a] = vj[a];
            g->pos[3 * (size_t)j + a] = g->grav && a == ax ? 1.0 : 0.0;
        }
        const double *v0 = g->output == IGEA_ENVFUN_VELOCITY || g->output == IGEA_ENVFUN_VELOCITY_G
                               ? vj : g->pos + 3 * (size_t)j;
        memcpy(g->val + 3 * (size_t)j, v0, 3 * sizeof(double));
    }
}

/* With a site, the velocity kind's launch-point columns also hold the
 * gravity that the tracking's first interval integrates along a path
 * started at the stated point (igea/dw.h: the cubic Hermite path from the
 * pad at lift-off to the first epoch t_1; the vehicle was at -e_k in the
 * stated frame): int_0^1 h00 = 1/2, so (t_1 - t_0) G e_k / 2 at every
 * epoch, G the J2 gravity gradient at the pad (dw's gravity). */
static void first_interval(const integ *g, const double *traj, const double *epochs,
                           int nepochs, double *out, size_t mrows)
{
    double G[9], h = epochs[0] - traj[0];
    if (!g->site || g->output != IGEA_ENVFUN_VELOCITY || !(h > 0.0))
        return;
    memcpy(G, g->Gpad, sizeof G);
    for (int j = 0; j < g->nb; j++) {
        if (igea__term_family(g->terms[j]) != IGEA__FAM_POS0)
            continue;
        int k, ax = igea__term_axis(g->terms[j], &k);
        for (int e = 0; e < nepochs; e++)
            for (int a = 0; a < 3; a++)
                IGEA_AT(out, mrows, 3 * (size_t)e + a, j) += 0.5 * h * G[3 * a + ax];
    }
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

/* The integration of checked arguments into S. */
static int run(integ *g, int nsamp, const double *traj, int ldt, int nepochs,
               const double *epochs, const double *spec, double *S, int lds)
{
    int nterms = g->nterms;
    size_t nt3 = (size_t)nterms * 3, mrows = (size_t)nepochs * 3;
    double *work = igea__dalloc(nt3 * 9 + mrows * (size_t)nterms);
    if (!work)
        return IGEA_ENOMEM;
    memset(work, 0, nt3 * 9 * sizeof(double));
    g->grav = (g->output == IGEA_ENVFUN_VELOCITY_G || g->output == IGEA_ENVFUN_POSITION_G);
    g->nt3 = nt3;
    g->vel = work;
    g->inner = g->vel + nt3;
    g->p_in = g->inner + nt3;
    g->p_out = g->p_in + nt3;
    g->pos = g->p_out + nt3;
    g->sv = g->pos + nt3;
    g->val = g->sv + nt3;
    g->val_prev = g->val + nt3;
    g->vel_prev = g->val_prev + nt3;
    double *out = g->vel_prev + nt3; /* 3 nepochs x nterms, ld = mrows */
    for (int a = 0; a < 3; a++)
        g->Wv[a] = g->rn[a] = g->vn[a] = 0.0;
    if (g->site) { /* the nominal path leaves the pad with its inertial velocity w x r0 */
        double zero[3] = {0.0, 0.0, 0.0}, r0[3];
        igea_nav_transform(g->site, IGEA_NAV_LE, IGEA_NAV_LI, 0.0, zero, zero, r0, g->vn);
    }
    for (int i = 0; i < 9; i++)
        g->Gm[i] = 0.0;

    sample cur, prev;
    load_sample(g, traj, ldt, 0, &cur);
    grav_at(g, g->rn, g->gacc_prev, NULL);
    init_integrands(g, &cur);
    pad_start(g);
    /* epochs at t_0: everything is zero */
    int e = interpolate(g, 0, nepochs, epochs, cur.t, cur.t, out, mrows);
    for (int k = 1; k < nsamp && e < nepochs; k++) {
        prev = cur;
        load_sample(g, traj, ldt, k, &cur);
        double h = cur.t - prev.t;
        for (int a = 0; a < 3; a++)
            g->Wv[a] += 0.5 * h * (prev.fa[a] + cur.fa[a]);
        if (g->grav)
            gravity_step(g, &prev, &cur, h);
        memcpy(g->vel_prev, g->vel, nt3 * sizeof(double));
        term_step(g, &prev, &cur, h);
        output_step(g, h);
        /* epochs in (t_{k-1}, t_k]: linear interpolation */
        e = interpolate(g, e, nepochs, epochs, prev.t, cur.t, out, mrows);
    }
    first_interval(g, traj, epochs, nepochs, out, mrows);
    int st = scale_out(nterms, spec, out, mrows, S, lds);
    free(work);
    return st;
}

/* The launch-point terms' parts that the site gives (0, or -16): pad
 * velocities w_L x e_k and frame rotations theta = (b, 0, -a) per metre,
 * a x + b z the normal's change du = (d_n / (M + h)) n + (d_e / (N + h)) e
 * for a displacement e_k (d_n, d_e its north and east parts; M, N the
 * WGS-84 radii of curvature at the site's latitude). */
static int site_parts(const double *site, integ *g)
{
    double M[9], wl[3], zero[3] = {0.0, 0.0, 0.0}, g0[3];
    if (igea_nav_rotation(site, IGEA_NAV_ECEF, IGEA_NAV_LI, 0.0, M) ||
        igea_nav_gravity_li(site, IGEA_NAV_GRAVITY_J2, zero, g0, g->Gpad))
        return -16;
    for (int a = 0; a < 3; a++)
        wl[a] = M[3 * a + 2] * IGEA_NAV_OMEGA;
    double e2 = IGEA_NAV_F * (2.0 - IGEA_NAV_F), sl = sin(site[IGEA_NAV_SITE_LAT]);
    double w = sqrt(1.0 - e2 * sl * sl), h = site[IGEA_NAV_SITE_H];
    double im = 1.0 / (IGEA_NAV_A * (1.0 - e2) / (w * w * w) + h), in = 1.0 / (IGEA_NAV_A / w + h);
    double ca = cos(site[IGEA_NAV_SITE_AZ]), sa = sin(site[IGEA_NAV_SITE_AZ]);
    for (int k = 0; k < 2; k++) { /* e_x: (d_n, d_e) = (ca, sa); e_z: (-sa, ca) */
        double dn = k ? -sa : ca, de = k ? ca : sa, ek[3] = {k ? 0.0 : 1.0, 0.0, k ? 1.0 : 0.0};
        double a = ca * dn * im + sa * de * in, b = ca * de * in - sa * dn * im;
        igea__cross(wl, ek, g->pad + 3 * k);
        g->theta[3 * k] = b;
        g->theta[3 * k + 1] = 0.0;
        g->theta[3 * k + 2] = -a;
    }
    return 0;
}

/* igea_envfun_compute_user with a site (may be NULL): check_args'
 * positions up to 15, then site 16, S 17, lds 18. */
static int compute(int system, int nsamp, const double *traj, int ldt, int nterms,
                   const int *terms, const int *axes, int nuser, const int *user_kind,
                   const double *user, int ldu, int nepochs, const double *epochs,
                   const double *spec, int output, const double *site, double *S, int lds)
{
    integ g;
    int st = check_args(system, nsamp, traj, ldt, nterms, terms, axes, nuser,
                        user_kind, user, ldu, nepochs, epochs, output, S, lds, &g);
    if (st)
        return (st == -16 || st == -17) ? st - 1 : st;
    g.site = site;
    if (site && (st = site_parts(site, &g)) != 0)
        return st;
    g.system = system;
    g.nb = nterms;
    g.nterms = nterms + nuser;
    g.terms = terms;
    g.ukind = user_kind;
    g.user = user;
    g.ldu = ldu;
    g.output = output;
    if ((st = check_data(&g, nsamp, traj, ldt, spec, nepochs, epochs)) != 0)
        return st;
    return run(&g, nsamp, traj, ldt, nepochs, epochs, spec, S, lds);
}

int igea_envfun_compute_user(int system, int nsamp, const double *traj, int ldt,
                             int nterms, const int *terms, const int *axes,
                             int nuser, const int *user_kind, const double *user,
                             int ldu, int nepochs, const double *epochs,
                             const double *spec, int output, double *S, int lds)
{
    int st = compute(system, nsamp, traj, ldt, nterms, terms, axes, nuser, user_kind, user,
                     ldu, nepochs, epochs, spec, output, NULL, S, lds);
    return (st == -17 || st == -18) ? st + 1 : st;
}

int igea_envfun_compute_site(int system, int nsamp, const double *traj, int ldt,
                             int nterms, const int *terms, const int *axes,
                             int nuser, const int *user_kind, const double *user,
                             int ldu, int nepochs, const double *epochs,
                             const double *spec, int output, const double *site,
                             double *S, int lds)
{
    return compute(system, nsamp, traj, ldt, nterms, terms, axes, nuser, user_kind, user,
                   ldu, nepochs, epochs, spec, output, site, S, lds);
}

int igea_envfun_compute(int system, int nsamp, const double *traj, int ldt,
                        int nterms, const int *terms, const int *axes,
                        int nepochs, const double *epochs, const double *spec,
                        int output, double *S, int lds)
{
    /* positions 12 .. 17 of igea_envfun_compute_user are 8 .. 13 here */
    int st = igea__traj_args(system, nsamp, traj, ldt);
    if (st == 0 && nterms < 1)
        st = -5;
    if (st)
        return st;
    st = igea_envfun_compute_user(system, nsamp, traj, ldt, nterms, terms,
                                      axes, 0, NULL, NULL, nsamp, nepochs, epochs,
                                      spec, output, S, lds);
    return (st <= -12 && st >= -17) ? st + 4 : st;
}
