/* nav.c - WGS-84, the launch-site frames, gravity, strapdown and platform
 * navigation from increments (igea/nav.h, docs/pipeline.md). */
#include <math.h>
#include <string.h>

#include "igea/envfun.h"
#include "igea/nav.h"
#include "internal.h"
#include "rotation.h"

#define E2 (IGEA_NAV_F * (2.0 - IGEA_NAV_F)) /* first eccentricity squared */
#define HALF_PI 1.5707963267948966

static int finite3(const double *x) { return igea__finite_vec(3, x, 1); }

/* 1 if the site's slots are finite and its C is orthonormal. */
static int site_ok(const double *s)
{
    if (!s || !igea__finite_vec(IGEA_NAV_SITE_LEN, s, 1))
        return 0;
    const double *C = s + IGEA_NAV_SITE_C;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double d = C[3 * i] * C[3 * j] + C[3 * i + 1] * C[3 * j + 1] +
                       C[3 * i + 2] * C[3 * j + 2];
            if (fabs(d - (i == j)) > 1e-9)
                return 0;
        }
    return 1;
}

static int frame_ok(int f) { return f == IGEA_NAV_ECEF || f == IGEA_NAV_LE || f == IGEA_NAV_LI; }

int igea_nav_geodetic_to_ecef(double lat, double lon, double h, double *r)
{
    if (!(fabs(lat) <= HALF_PI))
        return -1;
    if (!isfinite(lon))
        return -2;
    if (!(h > -6e6) || !isfinite(h))
        return -3;
    if (!r)
        return -4;
    double s = sin(lat), c = cos(lat);
    double N = IGEA_NAV_A / sqrt(1.0 - E2 * s * s);
    r[0] = (N + h) * c * cos(lon);
    r[1] = (N + h) * c * sin(lon);
    r[2] = (N * (1.0 - E2) + h) * s;
    return 0;
}

int igea_nav_ecef_to_geodetic(const double *r, double *geo)
{
    if (!r || !finite3(r))
        return -1;
    double p = hypot(r[0], r[1]);
    if (!(hypot(p, r[2]) > 1e5))
        return -1;
    if (!geo)
        return -2;
    /* Fixed-point iteration on the latitude (contraction factor about e^2),
     * height from the projection onto the normal: valid at the poles. */
    double lat = atan2(r[2], p * (1.0 - E2)), N = IGEA_NAV_A, s = 0.0;
    for (int it = 0; it < 30; it++) {
        s = sin(lat);
        N = IGEA_NAV_A / sqrt(1.0 - E2 * s * s);
        double next = atan2(r[2] + E2 * N * s, p);
        if (next == lat)
            break;
        lat = next;
    }
    s = sin(lat);
    N = IGEA_NAV_A / sqrt(1.0 - E2 * s * s);
    geo[0] = lat;
    geo[1] = atan2(r[1], r[0]);
    geo[2] = p * cos(lat) + r[2] * s - N * (1.0 - E2 * s * s);
    return 0;
}

int igea_nav_site(double lat, double lon, double h, double azimuth, double *site)
{
    double r0[3];
    if (!(fabs(lat) < HALF_PI))
        return -1;
    int st = igea_nav_geodetic_to_ecef(lat, lon, h, r0);
    if (st)
        return st;
    if (!isfinite(azimuth))
        return -4;
    if (!site)
        return -5;
    double sl = sin(lat), cl = cos(lat), so = sin(lon), co = cos(lon);
    double sa = sin(azimuth), ca = cos(azimuth);
    double east[3] = {-so, co, 0.0}, north[3] = {-sl * co, -sl * so, cl};
    double up[3] = {cl * co, cl * so, sl}, x[3], z[3];
    for (int i = 0; i < 3; i++)
        x[i] = ca * north[i] + sa * east[i];
    igea__cross(x, up, z);
    site[IGEA_NAV_SITE_LAT] = lat;
    site[IGEA_NAV_SITE_LON] = lon;
    site[IGEA_NAV_SITE_H] = h;
    site[IGEA_NAV_SITE_AZ] = azimuth;
    memcpy(site + IGEA_NAV_SITE_R0, r0, sizeof r0);
    memcpy(site + IGEA_NAV_SITE_C, x, sizeof x);
    memcpy(site + IGEA_NAV_SITE_C + 3, up, sizeof up);
    memcpy(site + IGEA_NAV_SITE_C + 6, z, sizeof z);
    for (int i = IGEA_NAV_SITE_C + 9; i < IGEA_NAV_SITE_LEN; i++)
        site[i] = 0.0;
    return 0;
}

/* y = R(u) x (trans 0) or R(u)^T x (trans 1), R the rotation about z. */
static void rot_z(double u, const double *x, double *y, int trans)
{
    double c = cos(u), s = trans ? -sin(u) : sin(u), t0 = c * x[0] - s * x[1];
    y[1] = s * x[0] + c * x[1];
    y[0] = t0;
    y[2] = x[2];
}

/* Any frame -> ECEF (r, v in place). */
static void to_ecef(const double *site, int from, double t, double *r, double *v)
{
    const double *C = site + IGEA_NAV_SITE_C, *r0 = site + IGEA_NAV_SITE_R0;
    const double w[3] = {0.0, 0.0, IGEA_NAV_OMEGA};
    double wr[3];
    if (from == IGEA_NAV_ECEF)
        return;
    igea__m3_vec(C, r, r, 1);
    igea__m3_vec(C, v, v, 1);
    for (int i = 0; i < 3; i++)
        r[i] += r0[i];
    if (from == IGEA_NAV_LI) { /* r, v are inertial (I) now */
        rot_z(IGEA_NAV_OMEGA * t, r, r, 1);
        rot_z(IGEA_NAV_OMEGA * t, v, v, 1);
        igea__cross(w, r, wr);
        for (int i = 0; i < 3; i++)
            v[i] -= wr[i];
    }
}

/* ECEF -> any frame (in place). */
static void from_ecef(const double *site, int to, double t, double *r, double *v)
{
    const double *C = site + IGEA_NAV_SITE_C, *r0 = site + IGEA_NAV_SITE_R0;
    const double w[3] = {0.0, 0.0, IGEA_NAV_OMEGA};
    double wr[3];
    if (to == IGEA_NAV_ECEF)
        return;
    if (to == IGEA_NAV_LI) {
        igea__cross(w, r, wr);
        for (int i = 0; i < 3; i++)
            v[i] += wr[i];
        rot_z(IGEA_NAV_OMEGA * t, r, r, 0);
        rot_z(IGEA_NAV_OMEGA * t, v, v, 0);
    }
    for (int i = 0; i < 3; i++)
        r[i] -= r0[i];
    igea__m3_vec(C, r, r, 0);
    igea__m3_vec(C, v, v, 0);
}

int igea_nav_transform(const double *site, int from, int to, double t, const double *r_in,
                       const double *v_in, double *r_out, double *v_out)
{
    if (!site_ok(site))
        return -1;
    if (!frame_ok(from))
        return -2;
    if (!frame_ok(to))
        return -3;
    if (!isfinite(t))
        return -4;
    if (!r_in)
        return -5;
    if (!v_in)
        return -6;
    if (!r_out)
        return -7;
    if (!v_out)
        return -8;
    if (!finite3(r_in) || !finite3(v_in))
        return IGEA_ENONFINITE;
    double r[3] = {r_in[0], r_in[1], r_in[2]}, v[3] = {v_in[0], v_in[1], v_in[2]};
    to_ecef(site, from, t, r, v);
    from_ecef(site, to, t, r, v);
    if (!finite3(r) || !finite3(v))
        return IGEA_ENONFINITE;
    memcpy(r_out, r, sizeof r);
    memcpy(v_out, v, sizeof v);
    return 0;
}

int igea_nav_rotation(const double *site, int from, int to, double t, double *M)
{
    if (!site_ok(site))
        return -1;
    if (!frame_ok(from))
        return -2;
    if (!frame_ok(to))
        return -3;
    if (!isfinite(t))
        return -4;
    if (!M)
        return -5;
    const double *C = site + IGEA_NAV_SITE_C;
    double out[9];
    for (int j = 0; j < 3; j++) { /* column j: the image of e_j */
        double v[3] = {j == 0, j == 1, j == 2};
        if (from != IGEA_NAV_ECEF)
            igea__m3_vec(C, v, v, 1);
        if (from == IGEA_NAV_LI)
            rot_z(IGEA_NAV_OMEGA * t, v, v, 1);
        if (to == IGEA_NAV_LI)
            rot_z(IGEA_NAV_OMEGA * t, v, v, 0);
        if (to != IGEA_NAV_ECEF)
            igea__m3_vec(C, v, v, 0);
        for (int i = 0; i < 3; i++)
            out[3 * i + j] = v[i];
    }
    memcpy(M, out, sizeof out);
    return 0;
}

/* Gravitation and gradient (Earth-centred, z polar): checked arguments. */
static void gravity(int model, const double *r, double *g, double *G)
{
    double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2], rn = sqrt(r2);
    double mu = IGEA_NAV_GM, ir3 = 1.0 / (r2 * rn), ir5 = ir3 / r2, ir7 = ir5 / r2;
    double k = model == IGEA_NAV_GRAVITY_J2 ? 1.5 * IGEA_NAV_J2 * IGEA_NAV_A * IGEA_NAV_A * mu
                                            : 0.0;
    double z = r[2], z2 = z * z;
    /* g = -mu r / r^3 - k (r / r^5 - 5 z^2 r / r^7 + 2 z e_z / r^5) */
    for (int i = 0; i < 3; i++)
        g[i] = -mu * r[i] * ir3 - k * (r[i] * ir5 - 5.0 * z2 * r[i] * ir7 +
                                       (i == 2 ? 2.0 * z * ir5 : 0.0));
    if (!G)
        return;
    double ir9 = ir7 / r2;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double dij = i == j, rr = r[i] * r[j];
            double pm = -mu * (dij * ir3 - 3.0 * rr * ir5);
            double t1 = dij * ir5 - 5.0 * rr * ir7;
            double t2 = -5.0 * (z2 * (dij * ir7 - 7.0 * rr * ir9) +
                                (j == 2 ? 2.0 * z * r[i] * ir7 : 0.0));
            double t3 = i == 2 ? 2.0 * ((j == 2) * ir5 - 5.0 * z * r[j] * ir7) : 0.0;
            G[3 * i + j] = pm - k * (t1 + t2 + t3);
        }
}

static int model_ok(int m) { return m == IGEA_NAV_GRAVITY_POINT_MASS || m == IGEA_NAV_GRAVITY_J2; }

int igea_nav_gravity(int model, const double *r, double *g, double *G)
{
    if (!model_ok(model))
        return -1;
    if (!r)
        return -2;
    if (!finite3(r))
        return IGEA_ENONFINITE;
    if (!(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] > 1e10))
        return -2;
    if (!g)
        return -3;
    double gg[3], GG[9];
    gravity(model, r, gg, GG);
    memcpy(g, gg, sizeof gg);
    if (G)
        memcpy(G, GG, sizeof GG);
    return 0;
}

/* g (and G) in LI at r_li: arguments checked, |r_I| > 1e5 checked here. */
static int gravity_li(const double *site, int model, const double *r_li, double *g, double *G)
{
    const double *C = site + IGEA_NAV_SITE_C, *r0 = site + IGEA_NAV_SITE_R0;
    double rI[3];
    igea__m3_vec(C, r_li, rI, 1);
    for (int i = 0; i < 3; i++)
        rI[i] += r0[i];
    if (!(rI[0] * rI[0] + rI[1] * rI[1] + rI[2] * rI[2] > 1e10))
        return 1;
    gravity(model, rI, g, G);
    igea__m3_vec(C, g, g, 0);
    if (G) {
        double CT[9];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                CT[3 * i + j] = C[3 * j + i];
        igea__m3_mul(C, G, G);
        igea__m3_mul(G, CT, G);
    }
    return 0;
}

int igea_nav_gravity_li(const double *site, int model, const double *r_li, double *g,
                        double *G)
{
    if (!site_ok(site))
        return -1;
    if (!model_ok(model))
        return -2;
    if (!r_li)
        return -3;
    if (!finite3(r_li))
        return IGEA_ENONFINITE;
    if (!g)
        return -4;
    double gg[3], GG[9];
    if (gravity_li(site, model, r_li, gg, G ? GG : NULL))
        return -3;
    memcpy(g, gg, sizeof gg);
    if (G)
        memcpy(G, GG, sizeof GG);
    return 0;
}

int igea_nav_init(int system, const double *site, int gravity_model, int flags, double t0,
                  const double *q0, const double *r0, const double *v0, double *state)
{
    if (system != IGEA_ENVFUN_STRAPDOWN && system != IGEA_ENVFUN_PLATFORM)
        return -1;
    if (!site_ok(site))
        return -2;
    if (!model_ok(gravity_model))
        return -3;
    if (flags < 0 || flags > (IGEA_NAV_NO_CONING | IGEA_NAV_NO_SCULLING))
        return -4;
    if (!isfinite(t0))
        return -5;
    double q[4] = {1.0, 0.0, 0.0, 0.0}, r[3] = {0.0, 0.0, 0.0}, v[3] = {0.0, 0.0, 0.0};
    if (q0 && system == IGEA_ENVFUN_STRAPDOWN) {
        double n = 0.0;
        if (!igea__finite_vec(4, q0, 1))
            return -6;
        for (int i = 0; i < 4; i++)
            n += q0[i] * q0[i];
        if (!(n > 1e-200))
            return -6;
        n = sqrt(n);
        for (int i = 0; i < 4; i++)
            q[i] = q0[i] / n;
    }
    if (r0 && !finite3(r0))
        return -7;
    if (v0 && !finite3(v0))
        return -8;
    if (!state)
        return -9;
    double zero[3] = {0.0, 0.0, 0.0};
    if (r0)
        memcpy(r, r0, sizeof r);
    if (v0)
        memcpy(v, v0, sizeof v);
    else
        igea_nav_transform(site, IGEA_NAV_LE, IGEA_NAV_LI, 0.0, zero, zero, zero, v);
    memset(state, 0, IGEA_NAV_STATE_LEN * sizeof *state);
    state[IGEA_NAV_STATE_SYSTEM] = system;
    state[IGEA_NAV_STATE_GRAVITY] = gravity_model;
    state[IGEA_NAV_STATE_FLAGS] = flags;
    state[IGEA_NAV_STATE_T] = t0;
    memcpy(state + IGEA_NAV_STATE_R, r, sizeof r);
    memcpy(state + IGEA_NAV_STATE_V, v, sizeof v);
    memcpy(state + IGEA_NAV_STATE_Q, q, sizeof q);
    memcpy(state + IGEA_NAV_STATE_SITE, site, IGEA_NAV_SITE_LEN * sizeof *site);
    return 0;
}

/* 1 if the state is one igea_nav_init could have made. */
static int state_ok(const double *s)
{
    if (!s || !igea__finite_vec(IGEA_NAV_STATE_LEN, s, 1))
        return 0;
    double sys = s[IGEA_NAV_STATE_SYSTEM], gm = s[IGEA_NAV_STATE_GRAVITY];
    double fl = s[IGEA_NAV_STATE_FLAGS];
    if ((sys != IGEA_ENVFUN_STRAPDOWN && sys != IGEA_ENVFUN_PLATFORM) ||
        (gm != IGEA_NAV_GRAVITY_POINT_MASS && gm != IGEA_NAV_GRAVITY_J2) ||
        (fl != 0 && fl != 1 && fl != 2 && fl != 3))
        return 0;
    const double *q = s + IGEA_NAV_STATE_Q;
    double n = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    return fabs(n - 1.0) < 1e-6 && site_ok(s + IGEA_NAV_STATE_SITE);
}

/* The LI velocity increment and the new quaternion of a strapdown record. */
static void strapdown_increment(const double *s, const double *dv, const double *dth,
                                double *dw, double *q)
{
    int flags = (int)s[IGEA_NAV_STATE_FLAGS];
    const double *pth = s + IGEA_NAV_STATE_DTH, *pdv = s + IGEA_NAV_STATE_DV;
    double C[9], rot[3], a[3], b[3], u[3], phi[3];
    igea__quat_dcm(s + IGEA_NAV_STATE_Q, C);
    /* rotation compensation, exact for constant rates over the record
     * (Savage 2000, 7.2.2.2): (1 - cos a)/a^2 dth x dv + (1 - sin a / a)/a^2
     * dth x (dth x dv), a = |dth| */
    double a2 = dth[0] * dth[0] + dth[1] * dth[1] + dth[2] * dth[2], c1, c2, rr[3];
    if (a2 < 1e-6) {
        c1 = 0.5 - a2 / 24.0 + a2 * a2 / 720.0;
        c2 = 1.0 / 6.0 - a2 / 120.0 + a2 * a2 / 5040.0;
    } else {
        double al = sqrt(a2);
        c1 = (1.0 - cos(al)) / a2;
        c2 = (1.0 - sin(al) / al) / a2;
    }
    igea__cross(dth, dv, rot);
    igea__cross(dth, rot, rr);
    for (int i = 0; i < 3; i++)
        u[i] = dv[i] + c1 * rot[i] + c2 * rr[i];
    if (!(flags & IGEA_NAV_NO_SCULLING)) {
        igea__cross(pth, dv, a);
        igea__cross(pdv, dth, b);
        for (int i = 0; i < 3; i++)
            u[i] += (a[i] + b[i]) / 12.0;
    }
    igea__m3_vec(C, u, dw, 0);
    memcpy(phi, dth, sizeof phi);
    if (!(flags & IGEA_NAV_NO_CONING)) {
        igea__cross(pth, dth, a);
        for (int i = 0; i < 3; i++)
            phi[i] += a[i] / 12.0;
    }
    memcpy(q, s + IGEA_NAV_STATE_Q, 4 * sizeof *q);
    igea__quat_rotate(q, phi);
}

int igea_nav_step(double *state, double t, const double *dv, const double *dth)
{
    if (!state_ok(state))
        return -1;
    double t0 = state[IGEA_NAV_STATE_T], h = t - t0;
    if (!isfinite(t) || !(h > 0.0) || !isfinite(h))
        return -2;
    if (!dv)
        return -3;
    if (!finite3(dv) || (dth && !finite3(dth)))
        return IGEA_ENONFINITE;
    const double zero[3] = {0.0, 0.0, 0.0}, *site = state + IGEA_NAV_STATE_SITE;
    int sd = state[IGEA_NAV_STATE_SYSTEM] == IGEA_ENVFUN_STRAPDOWN;
    int gm = (int)state[IGEA_NAV_STATE_GRAVITY];
    const double *th = sd && dth ? dth : zero;
    double s[IGEA_NAV_STATE_LEN], dw[3], g0[3], g[3], rm[3];
    memcpy(s, state, sizeof s);
    if (sd)
        strapdown_increment(state, dv, th, dw, s + IGEA_NAV_STATE_Q);
    else
        memcpy(dw, dv, sizeof dw);
    double *r = s + IGEA_NAV_STATE_R, *v = s + IGEA_NAV_STATE_V;
    if (gravity_li(site, gm, r, g0, NULL))
        return IGEA_ENONFINITE;
    for (int i = 0; i < 3; i++)
        rm[i] = r[i] + 0.5 * h * v[i] + 0.125 * h * (dw[i] + g0[i] * h);
    if (gravity_li(site, gm, rm, g, NULL))
        return IGEA_ENONFINITE;
    for (int i = 0; i < 3; i++) {
        double vn = v[i] + dw[i] + g[i] * h;
        r[i] += 0.5 * h * (v[i] + vn);
        v[i] = vn;
        s[IGEA_NAV_STATE_W + i] += dw[i];
        s[IGEA_NAV_STATE_DTH + i] = th[i];
        s[IGEA_NAV_STATE_DV + i] = dv[i];
    }
    s[IGEA_NAV_STATE_T] = t;
    if (!igea__finite_vec(IGEA_NAV_STATE_LEN, s, 1))
        return IGEA_ENONFINITE;
    memcpy(state, s, sizeof s);
    return 0;
}
