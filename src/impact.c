/* impact.c - the impact point of a ballistic free flight (Kepler in closed
 * form, J2 integrated), its Jacobian, the miss budget and the CEP
 * (include/igea/impact.h, docs/impact.md). */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <string.h>

#include "igea/envfun.h"
#include "igea/impact.h"
#include "igea/nav.h"
#include "internal.h"
#include "rotation.h"

#define IMPACT_PI 3.14159265358979323846

int igea_impact_defaults(double *opts)
{
    if (!opts)
        return -1;
    for (int i = 0; i < IGEA_IMPACT_OPT_LEN; i++)
        opts[i] = 0.0;
    opts[IGEA_IMPACT_OPT_MU] = 3.986004418e14;
    opts[IGEA_IMPACT_OPT_RADIUS] = 6371008.8;
    opts[IGEA_IMPACT_OPT_OMEGA] = 7.292115e-5;
    opts[IGEA_IMPACT_OPT_J2] = 1.082629821313e-3;
    opts[IGEA_IMPACT_OPT_RE] = 6378137.0;
    opts[IGEA_IMPACT_OPT_STEP] = 0.5;
    opts[IGEA_IMPACT_OPT_TMAX] = 1e5;
    return 0;
}

int igea_impact_check_opts(const double *o)
{
    if (!o)
        return -1;
    for (int i = 0; i < IGEA_IMPACT_OPT_LEN; i++)
        if (!isfinite(o[i]))
            return 1 + i;
    if (!(o[IGEA_IMPACT_OPT_MU] > 0))
        return 1 + IGEA_IMPACT_OPT_MU;
    if (!(o[IGEA_IMPACT_OPT_RADIUS] > 0))
        return 1 + IGEA_IMPACT_OPT_RADIUS;
    if (!(o[IGEA_IMPACT_OPT_OMEGA] >= 0))
        return 1 + IGEA_IMPACT_OPT_OMEGA;
    if (!(o[IGEA_IMPACT_OPT_RE] > 0))
        return 1 + IGEA_IMPACT_OPT_RE;
    if (!(o[IGEA_IMPACT_OPT_STEP] > 0 && o[IGEA_IMPACT_OPT_STEP] <= 60))
        return 1 + IGEA_IMPACT_OPT_STEP;
    if (!(o[IGEA_IMPACT_OPT_TMAX] > 0))
        return 1 + IGEA_IMPACT_OPT_TMAX;
    return 0;
}

/* ---- forward-mode derivatives: a value and its 6 partials ---------------- */
#define ND 6
typedef struct {
    double v, d[ND];
} dn;

static dn dc(double c)
{
    dn r;
    r.v = c;
    for (int k = 0; k < ND; k++)
        r.d[k] = 0.0;
    return r;
}
/* f(a) with f'(a) = g */
static dn chain(dn a, double f, double g)
{
    dn r;
    r.v = f;
    for (int k = 0; k < ND; k++)
        r.d[k] = g * a.d[k];
    return r;
}
static dn add(dn a, dn b)
{
    a.v += b.v;
    for (int k = 0; k < ND; k++)
        a.d[k] += b.d[k];
    return a;
}
static dn sub(dn a, dn b)
{
    a.v -= b.v;
    for (int k = 0; k < ND; k++)
        a.d[k] -= b.d[k];
    return a;
}
static dn mul(dn a, dn b)
{
    dn r;
    r.v = a.v * b.v;
    for (int k = 0; k < ND; k++)
        r.d[k] = a.d[k] * b.v + a.v * b.d[k];
    return r;
}
static dn dvd(dn a, dn b)
{
    dn r;
    r.v = a.v / b.v;
    for (int k = 0; k < ND; k++)
        r.d[k] = (a.d[k] - r.v * b.d[k]) / b.v;
    return r;
}
static dn scl(dn a, double s) { return chain(a, a.v * s, s); }
static dn addc(dn a, double c)
{
    a.v += c;
    return a;
}
static dn dsqrt(dn a)
{
    double s = sqrt(a.v);
    return chain(a, s, 0.5 / s);
}
static dn dsin(dn a) { return chain(a, sin(a.v), cos(a.v)); }
static dn dcos(dn a) { return chain(a, cos(a.v), -sin(a.v)); }
static dn datan2(dn y, dn x)
{
    dn r;
    double n2 = x.v * x.v + y.v * y.v;
    r.v = atan2(y.v, x.v);
    for (int k = 0; k < ND; k++)
        r.d[k] = (x.v * y.d[k] - y.v * x.d[k]) / n2;
    return r;
}
static dn dot3(const dn *a, const dn *b) { return add(add(mul(a[0], b[0]), mul(a[1], b[1])), mul(a[2], b[2])); }
static void cross3(const dn *a, const dn *b, dn *c)
{
    c[0] = sub(mul(a[1], b[2]), mul(a[2], b[1]));
    c[1] = sub(mul(a[2], b[0]), mul(a[0], b[2]));
    c[2] = sub(mul(a[0], b[1]), mul(a[1], b[0]));
}

/* ECEF at impact from the inertial frame aligned with ECEF at burnout:
 * r_e = Rz(-theta) r_i, v_e = Rz(-theta) v_i - w x r_e, theta = w t. */
static void to_ecef(double w, dn t, const dn *ri, const dn *vi, dn *re, dn *ve)
{
    dn th = scl(t, w), c = dcos(th), s = dsin(th);
    re[0] = add(mul(ri[0], c), mul(ri[1], s));
    re[1] = sub(mul(ri[1], c), mul(ri[0], s));
    re[2] = ri[2];
    dn v0 = add(mul(vi[0], c), mul(vi[1], s)), v1 = sub(mul(vi[1], c), mul(vi[0], s));
    ve[0] = add(v0, scl(re[1], w)); /* - w x r = (w y, -w x, 0) */
    ve[1] = sub(v1, scl(re[0], w));
    ve[2] = vi[2];
}

/* The Kepler flight in closed form (docs/impact.md): the state at the
 * crossing of |r| = R on the way down, by the rotation of the burnout
 * radial/transverse frame through the true-anomaly change, and the time of
 * flight from the eccentric anomalies. */
static int kepler(const double *o, const dn *r0, const dn *v0, dn *rf, dn *vf, dn *tf)
{
    const double mu = o[IGEA_IMPACT_OPT_MU], R = o[IGEA_IMPACT_OPT_RADIUS];
    const double w = o[IGEA_IMPACT_OPT_OMEGA];
    dn vi[3] = {sub(v0[0], scl(r0[1], w)), add(v0[1], scl(r0[0], w)), v0[2]};
    dn r = dsqrt(dot3(r0, r0)), h[3];
    if (!(r.v >= R))
        return IGEA_EDOMAIN;
    cross3(r0, vi, h);
    dn h2 = dot3(h, h), rv = dot3(r0, vi);
    dn energy = sub(scl(dot3(vi, vi), 0.5), dvd(dc(mu), r));
    if (!(h2.v > 0) || !(energy.v < 0))
        return IGEA_EDOMAIN;
    dn p = scl(h2, 1.0 / mu), hm = dsqrt(h2);
    dn ec0 = addc(dvd(p, r), -1.0);                        /* e cos nu0 */
    dn es0 = dvd(mul(rv, dsqrt(scl(p, 1.0 / mu))), r);     /* e sin nu0 */
    dn cf = addc(scl(p, 1.0 / R), -1.0);                   /* e cos nuf */
    /* e^2 - cf^2 = (ec0 - cf)(ec0 + cf) + es0^2, without the cancellation of
     * e^2 ~ cf^2 ~ 1 on a short flight (p << R) */
    dn pr = dvd(p, r), pR = scl(p, 1.0 / R);
    dn disc = add(mul(sub(pr, pR), addc(add(pr, pR), -2.0)), mul(es0, es0));
    if (!(disc.v > 0))
        return IGEA_EDOMAIN; /* the perigee is at or above the sphere */
    dn esf = scl(dsqrt(disc), -1.0);                       /* descending */
    dn dnu = sub(datan2(esf, cf), datan2(es0, ec0));
    if (dnu.v < 0)
        dnu = addc(dnu, 2.0 * IMPACT_PI);
    /* burnout frame: u0 = r0 / r, t0 = h x r0 / (|h| r) */
    dn u0[3], t0[3], hr[3];
    cross3(h, r0, hr);
    dn hmr = mul(hm, r);
    for (int i = 0; i < 3; i++)
        u0[i] = dvd(r0[i], r), t0[i] = dvd(hr[i], hmr);
    dn c = dcos(dnu), s = dsin(dnu);
    dn vr = mul(dsqrt(dvd(dc(mu), p)), esf), vt = scl(hm, 1.0 / R);
    dn ri[3], vfi[3];
    for (int i = 0; i < 3; i++) {
        dn uf = add(mul(c, u0[i]), mul(s, t0[i]));
        dn tfv = sub(mul(c, t0[i]), mul(s, u0[i]));
        ri[i] = scl(uf, R);
        vfi[i] = add(mul(vr, uf), mul(vt, tfv));
    }
    /* eccentric anomalies: e cos E = 1 - r/a, e sin E = r.v / sqrt(mu a) */
    dn a = dvd(dc(-0.5 * mu), energy), sma = dsqrt(scl(a, mu));
    dn eE0s = dvd(rv, sma), eE0c = sub(dc(1.0), dvd(r, a));
    dn eEfs = dvd(scl(vr, R), sma), eEfc = sub(dc(1.0), dvd(dc(R), a));
    dn dE = sub(datan2(eEfs, eEfc), datan2(eE0s, eE0c));
    if (dE.v < 0)
        dE = addc(dE, 2.0 * IMPACT_PI);
    dn nmean = dsqrt(dvd(dc(mu), mul(a, mul(a, a))));
    *tf = dvd(sub(dE, sub(eEfs, eE0s)), nmean);
    to_ecef(w, *tf, ri, vfi, rf, vf);
    return 0;
}

/* ---- the J2 model, integrated ---------------------------------------------- */
static void accel(const double *o, const double *r, double *acc)
{
    const double mu = o[IGEA_IMPACT_OPT_MU], j2 = o[IGEA_IMPACT_OPT_J2];
    const double re = o[IGEA_IMPACT_OPT_RE];
    double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2], rn = sqrt(r2);
    double pm = -mu / (r2 * rn), z2 = r[2] * r[2] / r2;
    double k = -1.5 * j2 * mu * re * re / (r2 * r2 * rn);
    acc[0] = r[0] * (pm + k * (1.0 - 5.0 * z2));
    acc[1] = r[1] * (pm + k * (1.0 - 5.0 * z2));
    acc[2] = r[2] * (pm + k * (3.0 - 5.0 * z2));
}

static void deriv(const double *o, const double *s, double *ds)
{
    ds[0] = s[3], ds[1] = s[4], ds[2] = s[5];
    accel(o, s, ds + 3);
}

static void rk4(const double *o, const double *s, double h, double *out)
{
    double k1[6], k2[6], k3[6], k4[6], t[6];
    deriv(o, s, k1);
    for (int i = 0; i < 6; i++)
        t[i] = s[i] + 0.5 * h * k1[i];
    deriv(o, t, k2);
    for (int i = 0; i < 6; i++)
        t[i] = s[i] + 0.5 * h * k2[i];
    deriv(o, t, k3);
    for (int i = 0; i < 6; i++)
        t[i] = s[i] + h * k3[i];
    deriv(o, t, k4);
    for (int i = 0; i < 6; i++)
        out[i] = s[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
}

static double radius_of(const double *s) { return sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]); }

/* Newton on tau in (0, h] for |r(rk4(s, tau))| = R; *out the state there. */
static void crossing(const double *o, const double *s, const double *s1, double h,
                     double *tau_out, double *out)
{
    const double R = o[IGEA_IMPACT_OPT_RADIUS];
    double g0 = radius_of(s) - R, g1 = radius_of(s1) - R;
    double tau = g0 > 0 ? h * g0 / (g0 - g1) : 0.0;
    for (int it = 0; it < 50; it++) {
        rk4(o, s, tau, out);
        double rn = radius_of(out), g = rn - R;
        double gd = (out[0] * out[3] + out[1] * out[4] + out[2] * out[5]) / rn;
        double step = g / gd;
        if (!(fabs(step) <= h))
            step = step > 0 ? 0.5 * tau : -0.5 * (h - tau);
        tau -= step;
        if (tau < 0)
            tau = 0;
        if (tau > h)
            tau = h;
        if (fabs(step) <= 4.0 * DBL_EPSILON * (tau + DBL_MIN))
            break;
    }
    rk4(o, s, tau, out);
    *tau_out = tau;
}

/* The J2 flight from the burnout state (ECEF) to the sphere: inertial
 * state at the crossing and the time of flight. */
static int j2_flight(const double *o, const double *r0, const double *v0, double *sf, double *tf)
{
    const double R = o[IGEA_IMPACT_OPT_RADIUS], w = o[IGEA_IMPACT_OPT_OMEGA];
    const double h = o[IGEA_IMPACT_OPT_STEP], tmax = o[IGEA_IMPACT_OPT_TMAX];
    double s[6] = {r0[0], r0[1], r0[2], v0[0] - w * r0[1], v0[1] + w * r0[0], v0[2]}, s1[6];
    if (!(radius_of(s) >= R))
        return IGEA_EDOMAIN;
    if (radius_of(s) == R && s[0] * s[3] + s[1] * s[4] + s[2] * s[5] < 0) {
        memcpy(sf, s, sizeof s);
        *tf = 0.0;
        return 0;
    }
    for (long k = 0; k * h <= tmax; k++) {
        rk4(o, s, h, s1);
        if (!isfinite(s1[0]) || !isfinite(s1[3]))
            return IGEA_EDOMAIN;
        if (radius_of(s1) < R) {
            double tau;
            crossing(o, s, s1, h, &tau, sf);
            *tf = (double)k * h + tau;
            return 0;
        }
        memcpy(s, s1, sizeof s);
    }
    return IGEA_EDOMAIN;
}

static void j2_ecef(const double *o, const double *sf, double tf, double *rf, double *vf)
{
    dn t = dc(tf), ri[3], vi[3], re[3], ve[3];
    for (int i = 0; i < 3; i++)
        ri[i] = dc(sf[i]), vi[i] = dc(sf[3 + i]);
    to_ecef(o[IGEA_IMPACT_OPT_OMEGA], t, ri, vi, re, ve);
    for (int i = 0; i < 3; i++)
        rf[i] = re[i].v, vf[i] = ve[i].v;
}

/* One J2 impact: the 7 outputs (rf, vf, tf) in out. */
static int j2_impact(const double *o, const double *r0, const double *v0, double *out)
{
    double sf[6], tf;
    int st = j2_flight(o, r0, v0, sf, &tf);
    if (st)
        return st;
    j2_ecef(o, sf, tf, out, out + 3);
    out[6] = tf;
    return 0;
}

/* Central differences of j2_impact: steps 1e-6 |r0| and 1e-6 max(|v0|, 1). */
static int j2_jacobian(const double *o, const double *r0, const double *v0, double *jac, int ldj)
{
    double x[6] = {r0[0], r0[1], r0[2], v0[0], v0[1], v0[2]};
    double hr = 1e-6 * radius_of(x), hv = 1e-6 * fmax(radius_of(x + 3), 1.0);
    for (int k = 0; k < 6; k++) {
        double xp[6], xm[6], fp[7], fm[7], d = k < 3 ? hr : hv;
        memcpy(xp, x, sizeof x), memcpy(xm, x, sizeof x);
        xp[k] += d, xm[k] -= d;
        int st = j2_impact(o, xp, xp + 3, fp);
        if (!st)
            st = j2_impact(o, xm, xm + 3, fm);
        if (st)
            return st;
        for (int i = 0; i < IGEA_IMPACT_JAC_ROWS; i++)
            IGEA_AT(jac, ldj, i, k) = (fp[i] - fm[i]) / (2.0 * d);
    }
    return 0;
}

static int finite_n(const double *x, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(x[i]))
            return 0;
    return 1;
}

/* The miss Jacobian G (2 x 6) and n columns of burnout errors E (6 each)
 * all finite. */
static int finite_ge(const double *G, int ldg, const double *E, int lde, int n)
{
    for (int k = 0; k < 6; k++)
        if (!isfinite(IGEA_AT(G, ldg, 0, k)) || !isfinite(IGEA_AT(G, ldg, 1, k)))
            return 0;
    for (int j = 0; j < n; j++)
        if (!finite_n(E + (size_t)j * lde, 6))
            return 0;
    return 1;
}

static int kepler_impact(const double *o, const double *r0, const double *v0, double *out,
                         double *jac, int ldj)
{
    dn r[3], v[3], rf[3], vf[3], tf;
    for (int i = 0; i < 3; i++) {
        r[i] = dc(r0[i]), v[i] = dc(v0[i]);
        r[i].d[i] = 1.0, v[i].d[3 + i] = 1.0;
    }
    int st = kepler(o, r, v, rf, vf, &tf);
    if (st)
        return st;
    dn all[7] = {rf[0], rf[1], rf[2], vf[0], vf[1], vf[2], tf};
    for (int i = 0; i < 7; i++) {
        if (!isfinite(all[i].v) || !finite_n(all[i].d, ND))
            return IGEA_EDOMAIN;
        out[i] = all[i].v;
    }
    if (jac)
        for (int i = 0; i < 7; i++)
            for (int k = 0; k < ND; k++)
                IGEA_AT(jac, ldj, i, k) = all[i].d[k];
    return 0;
}

int igea_impact_point(int model, const double *opts, const double *r0, const double *v0,
                      double *rf, double *vf, double *tf, double *jac, int ldj)
{
    if (model != IGEA_IMPACT_KEPLER && model != IGEA_IMPACT_J2)
        return -1;
    if (igea_impact_check_opts(opts))
        return -2;
    if (!r0)
        return -3;
    if (!v0)
        return -4;
    if (!rf)
        return -5;
    if (jac && ldj < IGEA_IMPACT_JAC_ROWS)
        return -9;
    if (!finite_n(r0, 3) || !finite_n(v0, 3))
        return IGEA_ENONFINITE;
    double out[7], J[IGEA_IMPACT_JAC_ROWS * 6];
    int st = model == IGEA_IMPACT_KEPLER
                 ? kepler_impact(opts, r0, v0, out, jac ? J : NULL, IGEA_IMPACT_JAC_ROWS)
                 : j2_impact(opts, r0, v0, out);
    if (!st && jac && model == IGEA_IMPACT_J2)
        st = j2_jacobian(opts, r0, v0, J, IGEA_IMPACT_JAC_ROWS);
    if (!st && jac && !finite_n(J, IGEA_IMPACT_JAC_ROWS * 6))
        st = IGEA_EDOMAIN;
    if (st)
        return st;
    memcpy(rf, out, 3 * sizeof(double));
    if (vf)
        memcpy(vf, out + 3, 3 * sizeof(double));
    if (tf)
        *tf = out[6];
    if (jac)
        for (int k = 0; k < 6; k++)
            for (int i = 0; i < IGEA_IMPACT_JAC_ROWS; i++)
                IGEA_AT(jac, ldj, i, k) = J[i + k * IGEA_IMPACT_JAC_ROWS];
    return 0;
}

/* ---- miss axes, Jacobian, budget ------------------------------------------- */
static int axes(const double *rf, const double *vf, double *down, double *cross)
{
    double rn = radius_of(rf);
    if (!(rn > 0))
        return IGEA_EDOMAIN;
    double u[3] = {rf[0] / rn, rf[1] / rn, rf[2] / rn};
    double vu = vf[0] * u[0] + vf[1] * u[1] + vf[2] * u[2];
    double d[3] = {vf[0] - vu * u[0], vf[1] - vu * u[1], vf[2] - vu * u[2]};
    double dn_ = radius_of(d);
    if (!(dn_ > 1e-12 * radius_of(vf)) || !(dn_ > 0))
        return IGEA_EDOMAIN;
    for (int i = 0; i < 3; i++)
        d[i] /= dn_;
    down[0] = d[0], down[1] = d[1], down[2] = d[2];
    cross[0] = d[1] * u[2] - d[2] * u[1];
    cross[1] = d[2] * u[0] - d[0] * u[2];
    cross[2] = d[0] * u[1] - d[1] * u[0];
    return 0;
}

int igea_impact_axes(const double *rf, const double *vf, double *down, double *cross)
{
    if (!rf)
        return -1;
    if (!vf)
        return -2;
    if (!down)
        return -3;
    if (!cross)
        return -4;
    if (!finite_n(rf, 3) || !finite_n(vf, 3))
        return IGEA_ENONFINITE;
    double d[3], c[3];
    int st = axes(rf, vf, d, c);
    if (st)
        return st;
    memcpy(down, d, sizeof d), memcpy(cross, c, sizeof c);
    return 0;
}

int igea_impact_miss_jacobian(const double *jac, int ldj, const double *rf, const double *vf,
                              double *G, int ldg)
{
    if (!jac)
        return -1;
    if (ldj < IGEA_IMPACT_JAC_ROWS)
        return -2;
    if (!rf)
        return -3;
    if (!vf)
        return -4;
    if (!G)
        return -5;
    if (ldg < 2)
        return -6;
    for (int k = 0; k < 6; k++)
        for (int i = 0; i < 3; i++)
            if (!isfinite(IGEA_AT(jac, ldj, IGEA_IMPACT_JAC_POS + i, k)))
                return IGEA_ENONFINITE;
    if (!finite_n(rf, 3) || !finite_n(vf, 3))
        return IGEA_ENONFINITE;
    double d[3], c[3];
    int st = axes(rf, vf, d, c);
    if (st)
        return st;
    for (int k = 0; k < 6; k++) {
        double gd = 0.0, gc = 0.0;
        for (int i = 0; i < 3; i++) {
            double j = IGEA_AT(jac, ldj, IGEA_IMPACT_JAC_POS + i, k);
            gd += d[i] * j, gc += c[i] * j;
        }
        IGEA_AT(G, ldg, 0, k) = gd, IGEA_AT(G, ldg, 1, k) = gc;
    }
    return 0;
}

int igea_impact_budget(int n, const double *G, int ldg, const double *E, int lde, double *miss,
                       double *cov, double *share)
{
    if (n < 1)
        return -1;
    if (!G)
        return -2;
    if (ldg < 2)
        return -3;
    if (!E)
        return -4;
    if (lde < 6)
        return -5;
    if (!miss)
        return -6;
    if (!cov)
        return -7;
    if (!finite_ge(G, ldg, E, lde, n))
        return IGEA_ENONFINITE;
    double s00 = 0.0, s01 = 0.0, s11 = 0.0;
    for (int j = 0; j < n; j++) {
        double md = 0.0, mc = 0.0;
        for (int k = 0; k < 6; k++) {
            md += IGEA_AT(G, ldg, 0, k) * IGEA_AT(E, lde, k, j);
            mc += IGEA_AT(G, ldg, 1, k) * IGEA_AT(E, lde, k, j);
        }
        s00 += md * md, s01 += md * mc, s11 += mc * mc;
        if (!isfinite(s00) || !isfinite(s11))
            return IGEA_EOVERFLOW;
    }
    double tot = s00 + s11;
    for (int j = 0; j < n; j++) {
        double md = 0.0, mc = 0.0;
        for (int k = 0; k < 6; k++) {
            md += IGEA_AT(G, ldg, 0, k) * IGEA_AT(E, lde, k, j);
            mc += IGEA_AT(G, ldg, 1, k) * IGEA_AT(E, lde, k, j);
        }
        miss[2 * (size_t)j] = md, miss[2 * (size_t)j + 1] = mc;
        if (share)
            share[j] = tot > 0 ? (md * md + mc * mc) / tot : 0.0;
    }
    cov[0] = s00, cov[1] = s01, cov[2] = s01, cov[3] = s11;
    return 0;
}

/* ---- circle probability and CEP ---------------------------------------------- */
/* The principal variances s1 >= s2 >= 0 of a 2 x 2 covariance. */
static int principal(const double *cov, double *s1, double *s2)
{
    if (!finite_n(cov, 4))
        return IGEA_ENONFINITE;
    double a = cov[0], b = cov[1], d = cov[3];
    if (a < 0 || d < 0)
        return IGEA_ENONPOSITIVE;
    double big = fmax(fmax(fabs(a), fabs(d)), fabs(b));
    if (fabs(cov[1] - cov[2]) > 1e-12 * big)
        return IGEA_EDOMAIN;
    double half = 0.5 * (a - d), disc = hypot(half, b);
    double l1 = 0.5 * (a + d) + disc;
    double det = a * d - b * b;
    if (det < -1e-12 * l1 * l1)
        return IGEA_EDOMAIN;
    *s1 = l1;
    *s2 = l1 > 0 ? fmax(det, 0.0) / l1 : 0.0;
    return 0;
}

/* P(r) for principal variances s1 >= s2 > 0 or s2 = 0 (docs/impact.md):
 * r^2 > s2, Craig's elliptical form (1/pi) int_0^pi -expm1(-r^2 / (2 s(t)));
 * else the polar form (1 / (sigma1 sigma2)) mean of -expm1(-r^2 q / 2) / q
 * with q = cos^2 / s1 + sin^2 / s2. Periodic trapezoids, n doubled. */
static double circle_term(int craig, double s1, double s2, double r2, double t)
{
    double c = cos(t), s = sin(t);
    if (craig) {
        double v = s1 * c * c + s2 * s * s;
        return v > 0 ? -expm1(-r2 / (2.0 * v)) : 1.0;
    }
    double q = c * c / s1 + s * s / s2;
    return -expm1(-0.5 * r2 * q) / q;
}

static int circle_p(double s1, double s2, double r, double *p)
{
    if (r == 0 || s1 == 0) {
        *p = s1 == 0 ? 1.0 : 0.0;
        return 0;
    }
    if (s2 == 0) { /* a line: P(|x1| <= r) */
        *p = erf(r / sqrt(2.0 * s1));
        return 0;
    }
    const double r2 = r * r;
    const int craig = r2 > s2;
    const double norm = craig ? 1.0 : 1.0 / sqrt(s1 * s2);
    long n = 8;
    igea__ksum sum = {0.0, 0.0};
    for (long k = 0; k < n; k++)
        igea__ksum_add(&sum, circle_term(craig, s1, s2, r2, IMPACT_PI * (double)k / (double)n));
    double prev = norm * igea__ksum_get(&sum) / (double)n;
    for (; n <= (1L << 24); n *= 2) {
        for (long k = 0; k < n; k++)
            igea__ksum_add(&sum, circle_term(craig, s1, s2, r2,
                                             IMPACT_PI * (2.0 * (double)k + 1.0) / (2.0 * (double)n)));
        double cur = norm * igea__ksum_get(&sum) / (2.0 * (double)n);
        if (fabs(cur - prev) <= 4.0 * DBL_EPSILON * cur) {
            *p = fmin(cur, 1.0);
            return 0;
        }
        prev = cur;
    }
    return IGEA_ENOCONV;
}

int igea_impact_circle_prob(const double *cov, double r, double *prob)
{
    if (!cov)
        return -1;
    if (!(r >= 0) || isinf(r))
        return isnan(r) || isinf(r) ? IGEA_ENONFINITE : -2;
    if (!prob)
        return -3;
    double s1, s2, p;
    int st = principal(cov, &s1, &s2);
    if (!st)
        st = circle_p(s1, s2, r, &p);
    if (st)
        return st;
    *prob = p;
    return 0;
}

int igea_impact_cep(const double *cov, double prob, double *radius)
{
    if (!cov)
        return -1;
    if (!(prob > 0 && prob < 1))
        return -2;
    if (!radius)
        return -3;
    double s1, s2;
    int st = principal(cov, &s1, &s2);
    if (st)
        return st;
    if (s1 == 0) {
        *radius = 0.0;
        return 0;
    }
    /* P(|x1| <= r) >= P(r) >= the circle of s1: the root lies in
     * [sqrt(s1) z_{(1+p)/2}, sqrt(s1) sqrt(-2 ln(1 - p))] */
    double lo = sqrt(2.0 * s1) * igea__erfinv(prob), hi = sqrt(-2.0 * s1 * log1p(-prob));
    lo *= 1.0 - 8.0 * DBL_EPSILON, hi *= 1.0 + 8.0 * DBL_EPSILON;
    for (int it = 0; it < 200 && hi - lo > 2.0 * DBL_EPSILON * hi; it++) {
        double mid = 0.5 * (lo + hi), p;
        if ((st = circle_p(s1, s2, mid, &p)))
            return st;
        if (p < prob)
            lo = mid;
        else
            hi = mid;
    }
    *radius = 0.5 * (lo + hi);
    return 0;
}

int igea_impact_cep_approx(const double *cov, int rule, double *radius)
{
    if (!cov)
        return -1;
    if (rule != IGEA_IMPACT_CEP_SUM && rule != IGEA_IMPACT_CEP_RMS)
        return -2;
    if (!radius)
        return -3;
    double s1, s2;
    int st = principal(cov, &s1, &s2);
    if (st)
        return st;
    *radius = rule == IGEA_IMPACT_CEP_SUM ? 0.5887 * (sqrt(s1) + sqrt(s2))
                                          : 1.1774 * sqrt(0.5 * (s1 + s2));
    return 0;
}

/* ---- the circle about the aim point (a biased miss) ------------------- */

/* Normal probability of [lo, hi] for mean mu, sd s (s > 0), without the
 * cancellation of Phi(hi) - Phi(lo) in a tail. */
static double interval_prob(double lo, double hi, double mu, double s)
{
    double a = (lo - mu) / (s * sqrt(2.0)), b = (hi - mu) / (s * sqrt(2.0));
    if (a > 0)
        return 0.5 * (erfc(a) - erfc(b));
    if (b < 0)
        return 0.5 * (erfc(-b) - erfc(-a));
    return 0.5 * (erf(b) - erf(a));
}

/* P(|x| <= r), x ~ N(mu, diag(s1, s2)) in the principal axes (s1 >= s2):
 * x1 = r cos t, P = int_0^pi phi1(r cos t) P(|x2| <= r sin t) r sin t dt,
 * whose even 2 pi-periodic extension is smooth: trapezoids from a step
 * that resolves the smaller sd (dx1, d(r sin t) <= r pi / n <= sd2 / 4),
 * n doubled until two values agree to 4 ulp; s2 = 0 in closed form. */
static int offset_p(double s1, double s2, double m1, double m2, double r, double *p)
{
    if (s1 == 0 || r == 0) {
        *p = hypot(m1, m2) <= r ? 1.0 : 0.0;
        return 0;
    }
    double sd1 = sqrt(s1), sd2 = sqrt(s2), prev = -1.0;
    if (s2 == 0) { /* x2 = m2: |x1| <= sqrt(r^2 - m2^2) */
        double h = r >= fabs(m2) ? sqrt((r - fabs(m2)) * (r + fabs(m2))) : -1.0;
        *p = h < 0 ? 0.0 : interval_prob(-h, h, m1, sd1);
        return 0;
    }
    double need = 4.0 * IMPACT_PI * r / sd2;
    if (!(need < (double)(1L << 23)))
        return IGEA_ENOCONV;
    long n0 = 64;
    while ((double)n0 < need)
        n0 *= 2;
    igea__ksum sum = {0.0, 0.0};
    for (long n = n0; n <= (1L << 24); n *= 2) {
        for (long k = 1; k < n; k += n == n0 ? 1 : 2) {
            double t = IMPACT_PI * (double)k / (double)n, c = cos(t), s = sin(t);
            double z = (r * c - m1) / sd1, w = r * s;
            igea__ksum_add(&sum, exp(-0.5 * z * z) / (sd1 * sqrt(2.0 * IMPACT_PI)) *
                                     interval_prob(-w, w, m2, sd2) * w);
        }
        double cur = IMPACT_PI / (double)n * igea__ksum_get(&sum);
        if (n > n0 && fabs(cur - prev) <= 4.0 * DBL_EPSILON * cur + 1e-300) {
            *p = fmin(fmax(cur, 0.0), 1.0);
            return 0;
        }
        prev = cur;
    }
    return IGEA_ENOCONV;
}

/* Principal variances and the mean in the principal axes. */
static int offset_axes(const double *cov, const double *mean, double *s1, double *s2,
                       double *m1, double *m2)
{
    int st = principal(cov, s1, s2);
    if (st)
        return st;
    if (!finite_n(mean, 2))
        return IGEA_ENONFINITE;
    double phi = 0.5 * atan2(2.0 * cov[1], cov[0] - cov[3]), c = cos(phi), s = sin(phi);
    *m1 = c * mean[0] + s * mean[1];
    *m2 = -s * mean[0] + c * mean[1];
    return 0;
}

int igea_impact_circle_prob_offset(const double *cov, const double *mean, double r,
                                   double *prob)
{
    if (!cov)
        return -1;
    if (!mean)
        return -2;
    if (!(r >= 0) || isinf(r))
        return isnan(r) || isinf(r) ? IGEA_ENONFINITE : -3;
    if (!prob)
        return -4;
    double s1, s2, m1, m2, p;
    int st = offset_axes(cov, mean, &s1, &s2, &m1, &m2);
    if (!st)
        st = offset_p(s1, s2, m1, m2, r, &p);
    if (st)
        return st;
    *prob = p;
    return 0;
}

int igea_impact_cep_offset(const double *cov, const double *mean, double prob,
                           double *radius)
{
    if (!cov)
        return -1;
    if (!mean)
        return -2;
    if (!(prob > 0 && prob < 1))
        return -3;
    if (!radius)
        return -4;
    double s1, s2, m1, m2;
    int st = offset_axes(cov, mean, &s1, &s2, &m1, &m2);
    if (st)
        return st;
    double d = hypot(m1, m2);
    if (s1 == 0) {
        *radius = d;
        return 0;
    }
    /* P(|x| <= d + R) >= P(|x - mu| <= R) >= 1 - exp(-R^2 / (2 s1)) */
    double lo = 0.0, hi = (d + sqrt(-2.0 * s1 * log1p(-prob))) * (1.0 + 8.0 * DBL_EPSILON);
    for (int it = 0; it < 200 && hi - lo > 2.0 * DBL_EPSILON * hi; it++) {
        double mid = 0.5 * (lo + hi), p;
        if ((st = offset_p(s1, s2, m1, m2, mid, &p)))
            return st;
        if (p < prob)
            lo = mid;
        else
            hi = mid;
    }
    *radius = 0.5 * (lo + hi);
    return 0;
}

/* ---- the miss of the equivalent-error components ---------------------- */

int igea_impact_component_miss(int N, int n, const double *G, int ldg, const double *E,
                               int lde, const double *P, int ldp, const double *equiv,
                               double *miss)
{
    if (N < 1)
        return -1;
    if (n < 1)
        return -2;
    if (!G)
        return -3;
    if (ldg < 2)
        return -4;
    if (!E)
        return -5;
    if (lde < 6)
        return -6;
    if (!P)
        return -7;
    if (ldp < N)
        return -8;
    if (!equiv)
        return -9;
    if (!miss)
        return -10;
    if (!finite_ge(G, ldg, E, lde, N))
        return IGEA_ENONFINITE;
    for (int i = 0; i < n; i++)
        if (!finite_n(P + (size_t)i * ldp, N) || !isfinite(equiv[i]))
            return IGEA_ENONFINITE;
    double *out = igea__dalloc(2 * (size_t)n);
    if (!out)
        return IGEA_ENOMEM;
    for (int i = 0; i < n; i++) {
        double md = 0.0, mc = 0.0;
        for (int j = 0; j < N; j++) { /* (G E)_j p_ji */
            double pj = IGEA_AT(P, ldp, j, i), gd = 0.0, gc = 0.0;
            for (int k = 0; k < 6; k++) {
                gd += IGEA_AT(G, ldg, 0, k) * IGEA_AT(E, lde, k, j);
                gc += IGEA_AT(G, ldg, 1, k) * IGEA_AT(E, lde, k, j);
            }
            md += gd * pj, mc += gc * pj;
        }
        out[2 * i] = md * equiv[i];
        out[2 * i + 1] = mc * equiv[i];
    }
    int st = finite_n(out, 2 * n) ? 0 : IGEA_ENONFINITE;
    if (!st)
        memcpy(miss, out, 2 * (size_t)n * sizeof *miss);
    free(out);
    return st;
}

/* ---- the burnout state and its errors from a trajectory [D] --------------- */

/* Sample k of traj: t, f, w. */
static double traj_sample(const double *traj, int ldt, int k, double *f, double *w)
{
    for (int a = 0; a < 3; a++) {
        f[a] = IGEA_AT(traj, ldt, k, 1 + a);
        w[a] = IGEA_AT(traj, ldt, k, 4 + a);
    }
    return IGEA_AT(traj, ldt, k, 0);
}

/* The error-free navigation of the trajectory from the site to tb (checked
 * to lie in [t_0, t_last]): the increments are the trapezoids of the
 * sampled f and w over each interval (igea_sim_raw's telemetry), the last
 * interval cut at tb with the linear interpolants; the LI state at tb into
 * ECEF. 0 or IGEA_ENONFINITE. */
static int burnout_state(int system, int nsamp, const double *traj, int ldt,
                         const double *site, double tb, double *state)
{
    double st[IGEA_NAV_STATE_LEN], q[4], fp[3], wp[3], t0 = IGEA_AT(traj, ldt, 0, 0);
    int sd = system == IGEA_ENVFUN_STRAPDOWN;
    for (int i = 0; i < 4; i++)
        q[i] = IGEA_AT(traj, ldt, 0, 7 + i);
    if (igea_nav_init(system, site, IGEA_NAV_GRAVITY_J2, 0, t0, sd ? q : NULL, NULL, NULL, st))
        return IGEA_ENONFINITE;
    traj_sample(traj, ldt, 0, fp, wp);
    for (int k = 1; k < nsamp && st[IGEA_NAV_STATE_T] < tb - 1e-9; k++) {
        double f[3], w[3], dv[3], dth[3], tp = st[IGEA_NAV_STATE_T];
        double t = traj_sample(traj, ldt, k, f, w), s = 1.0;
        if (t > tb && fabs(t - tb) > 1e-9) { /* a partial step to tb */
            s = (tb - tp) / (t - tp);
            for (int a = 0; a < 3; a++) {
                f[a] = fp[a] + s * (f[a] - fp[a]);
                w[a] = wp[a] + s * (w[a] - wp[a]);
            }
            t = tb;
        }
        for (int a = 0; a < 3; a++) {
            dv[a] = 0.5 * (t - tp) * (fp[a] + f[a]);
            dth[a] = 0.5 * (t - tp) * (wp[a] + w[a]);
        }
        if (igea_nav_step(st, t, dv, sd ? dth : NULL))
            return IGEA_ENONFINITE;
        memcpy(fp, f, sizeof fp);
        memcpy(wp, w, sizeof wp);
    }
    double r[3], v[3];
    if (igea_nav_transform(site, IGEA_NAV_LI, IGEA_NAV_ECEF, st[IGEA_NAV_STATE_T] - t0,
                           st + IGEA_NAV_STATE_R, st + IGEA_NAV_STATE_V, r, v))
        return IGEA_ENONFINITE;
    memcpy(state, r, sizeof r);
    memcpy(state + 3, v, sizeof v);
    return finite_n(state, 6) ? 0 : IGEA_ENONFINITE;
}

/* The gravity-coupled position and velocity functions at tb (LI) into
 * ECEF (6 x nterms, ld 6): dr_E = M dr, dv_E = M dv - w x dr_E. The
 * statuses of igea_envfun_compute_site in this function's positions. */
static int burnout_errors(int system, int nsamp, const double *traj, int ldt, int nterms,
                          const int *terms, const int *axes, const double *spec,
                          const double *site, double tb, double *E)
{
    double *S = igea__dalloc(6 * (size_t)nterms), M[9];
    if (!S)
        return IGEA_ENOMEM;
    int st = 0;
    for (int kind = 0; kind < 2 && !st; kind++)
        st = igea_envfun_compute_site(system, nsamp, traj, ldt, nterms, terms, axes, 0, NULL,
                                      NULL, nsamp, 1, &tb, spec,
                                      kind ? IGEA_ENVFUN_VELOCITY_G : IGEA_ENVFUN_POSITION_G,
                                      site, S + 3 * (size_t)nterms * kind, 3);
    if (st == -14 || st == -16) /* spec, site */
        st = st == -14 ? -8 : -9;
    else if (st == -13) /* the epoch: tb */
        st = -10;
    if (!st && igea_nav_rotation(site, IGEA_NAV_LI, IGEA_NAV_ECEF, tb - IGEA_AT(traj, ldt, 0, 0),
                                 M))
        st = -9;
    for (int j = 0; j < nterms && !st; j++) {
        const double *dr = S + 3 * (size_t)j, *dv = S + 3 * ((size_t)nterms + j);
        double *e = E + 6 * (size_t)j;
        for (int a = 0; a < 3; a++) {
            e[a] = M[3 * a] * dr[0] + M[3 * a + 1] * dr[1] + M[3 * a + 2] * dr[2];
            e[3 + a] = M[3 * a] * dv[0] + M[3 * a + 1] * dv[1] + M[3 * a + 2] * dv[2];
        }
        e[3] += IGEA_NAV_OMEGA * e[1]; /* - w x dr_E, w = (0, 0, omega) */
        e[4] -= IGEA_NAV_OMEGA * e[0];
        if (!finite_n(e, 6))
            st = IGEA_ENONFINITE;
    }
    free(S);
    return st;
}

int igea_impact_burnout(int system, int nsamp, const double *traj, int ldt, int nterms,
                        const int *terms, const int *axes, const double *spec,
                        const double *site, double tb, double *state, double *E, int lde)
{
    int st0 = igea__traj_args(system, nsamp, traj, ldt);
    if (st0)
        return st0;
    if (nterms < 0 || nterms > INT_MAX / 6)
        return -5;
    if (nterms > 0 && !terms)
        return -6;
    double M[9];
    if (igea_nav_rotation(site, IGEA_NAV_LI, IGEA_NAV_ECEF, 0.0, M))
        return -9;
    if (!state)
        return -11;
    if (nterms > 0 && !E)
        return -12;
    if (nterms > 0 && lde < 6)
        return -13;
    for (int j = 0; j < nterms; j++)
        if (!igea_envfun_term_valid(system, terms[j]))
            return -6;
    if (!igea__finite_mat(nsamp, IGEA_ENVFUN_TRAJ_COLS, traj, ldt))
        return IGEA_ENONFINITE;
    for (int k = 1; k < nsamp; k++)
        if (!(IGEA_AT(traj, ldt, k, 0) > IGEA_AT(traj, ldt, k - 1, 0)))
            return -3;
    if (!(tb >= IGEA_AT(traj, ldt, 0, 0) && tb <= IGEA_AT(traj, ldt, nsamp - 1, 0)))
        return isnan(tb) ? IGEA_ENONFINITE : -10;
    if (system == IGEA_ENVFUN_STRAPDOWN)
        for (int k = 0; k < nsamp; k++) {
            double n2 = 0.0;
            for (int i = 0; i < 4; i++)
                n2 += IGEA_AT(traj, ldt, k, 7 + i) * IGEA_AT(traj, ldt, k, 7 + i);
            if (!(n2 > 1e-200))
                return IGEA_EDOMAIN;
        }
    double s[6], *e = NULL;
    if (nterms > 0 && !(e = igea__dalloc(6 * (size_t)nterms)))
        return IGEA_ENOMEM;
    int st = burnout_state(system, nsamp, traj, ldt, site, tb, s);
    if (!st && nterms > 0)
        st = burnout_errors(system, nsamp, traj, ldt, nterms, terms, axes, spec, site, tb, e);
    if (!st) {
        memcpy(state, s, sizeof s);
        for (int j = 0; j < nterms; j++)
            memcpy(E + (size_t)j * (size_t)lde, e + 6 * (size_t)j, 6 * sizeof(double));
    }
    free(e);
    return st;
}
