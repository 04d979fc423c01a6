/* src/sim_raw.c - the raw range records of a simulated flight: telemetry
 * increments with the instrument errors applied and the tracking of the
 * true vehicle (igea_sim_raw, igea/sim.h; docs/pipeline.md section 8).
 * The instrument errors are the catalogue's (igea__term_unit), the true
 * vehicle is the navigation core's (igea_nav_step), the frames are
 * igea_nav_*'s. */
#include <limits.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "igea/envfun.h"
#include "igea/nav.h"
#include "igea/sim.h"
#include "internal.h"
#include "rotation.h"
#include "envfun_terms.h"
#include "sim_model.h"

/* The erroneous instruments: codes with errors by family, gyro axes, the
 * platform's attitude P (C_p^a) and drift at the previous sample. */
typedef struct {
    int system, nerr;
    const double *err;
    int in_ax[3], spin_ax[3], out_ax[3];
    int acc[IGEA_ENVFUN_TERM_END], gyro[IGEA_ENVFUN_TERM_END], size[IGEA_ENVFUN_TERM_END];
    int nacc, ngyro, nsize, lever;
    double P[9], eps_p[3];
} raw_inst;

static double err_of(const raw_inst *r, int code)
{
    return r->err && code < r->nerr ? r->err[code] : 0.0;
}

/* out = base + sum over codes of err u(f, w). */
static void add_errors(const raw_inst *r, const int *codes, int n, const double *f,
                       const double *w, const double *base, double *out)
{
    double u[3];
    memcpy(out, base, 3 * sizeof(double));
    for (int i = 0; i < n; i++) {
        igea__term_unit(codes[i], f, w, r->in_ax, r->spin_ax, r->out_ax, u);
        for (int a = 0; a < 3; a++)
            out[a] += r->err[codes[i]] * u[a];
    }
}

/* The codes with errors (0, or -6 for an error on a code not valid for
 * the system, -7 for bad axes). */
static int inst_init(raw_inst *r, int system, int nerr, const double *err, const int *axes)
{
    static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    int uses_out = 0;
    r->system = system;
    r->nerr = nerr;
    r->err = err;
    if (igea__term_lists(system, nerr, err, r->acc, &r->nacc, r->size, &r->nsize, r->gyro,
                         &r->ngyro, &r->lever, &uses_out))
        return -6;
    igea__platform_axes(NULL, r->in_ax, r->spin_ax);
    if (system == IGEA_ENVFUN_PLATFORM && igea__platform_axes(axes, r->in_ax, r->spin_ax))
        return -7;
    if (igea__out_axes(r->in_ax, r->spin_ax, r->out_ax) && uses_out)
        return -7;
    double a0[3];
    for (int a = 0; a < 3; a++) {
        a0[a] = system == IGEA_ENVFUN_PLATFORM ? err_of(r, IGEA_ENVFUN_TERM_ALIGN0_X + a) : 0.0;
        r->eps_p[a] = 0.0;
    }
    memcpy(r->P, I3, sizeof I3);
    igea__m3_exp(a0, r->P);
    return 0;
}

/* Sample k of traj: t, f, w. */
static double sample(const double *traj, int ldt, int k, double *f, double *w)
{
    for (int a = 0; a < 3; a++) {
        f[a] = IGEA_AT(traj, ldt, k, 1 + a);
        w[a] = IGEA_AT(traj, ldt, k, 4 + a);
    }
    return IGEA_AT(traj, ldt, k, 0);
}

/* The instrument outputs at sample k (h the step from k - 1): fh the
 * accelerometers (instrument axes), wh the gyros (strapdown). A platform's
 * axes drift over the step first (eps at the end predicted twice). */
static void instruments(raw_inst *r, int k, double h, const double *f, const double *w,
                        double *fh, double *wh)
{
    static const double zero[3] = {0, 0, 0};
    double fp[3], eps[3], v[3], R[9], Pn[9];
    if (r->system == IGEA_ENVFUN_STRAPDOWN) {
        add_errors(r, r->acc, r->nacc, f, w, f, fh);
        add_errors(r, r->gyro, r->ngyro, f, w, w, wh);
        return;
    }
    memcpy(Pn, r->P, sizeof Pn);
    for (int it = 0; k > 0 && it < 2; it++) {
        igea__m3_vec(Pn, f, fp, 1);
        add_errors(r, r->gyro, r->ngyro, fp, w, zero, eps);
        for (int a = 0; a < 3; a++)
            v[a] = 0.5 * h * (r->eps_p[a] + eps[a]);
        igea__m3_exp(v, R);
        igea__m3_mul(r->P, R, Pn);
    }
    memcpy(r->P, Pn, sizeof Pn);
    igea__m3_vec(r->P, f, fp, 1); /* f^p = C_a^p f^a */
    add_errors(r, r->acc, r->nacc, fp, w, fp, fh);
    add_errors(r, r->gyro, r->ngyro, fp, w, zero, r->eps_p);
    wh[0] = wh[1] = wh[2] = 0.0;
}

/* The telemetry record into tel (nsamp x cols, ld nsamp). */
static void telemetry(raw_inst *r, int nsamp, const double *traj, int ldt, double *tel)
{
    int cols = r->system == IGEA_ENVFUN_STRAPDOWN ? 7 : 4;
    double fh_p[3], wh_p[3], w_p[3], t_p = 0.0;
    for (int k = 0; k < nsamp; k++) {
        double f[3], w[3], fh[3], wh[3], t = sample(traj, ldt, k, f, w), h = t - t_p;
        instruments(r, k, h, f, w, fh, wh);
        IGEA_AT(tel, nsamp, k, 0) = t;
        for (int a = 0; a < 3; a++) {
            IGEA_AT(tel, nsamp, k, 1 + a) = k ? 0.5 * h * (fh_p[a] + fh[a]) : 0.0;
            if (cols == 7)
                IGEA_AT(tel, nsamp, k, 4 + a) = k ? 0.5 * h * (wh_p[a] + wh[a]) : 0.0;
        }
        for (int i = 0; k && i < r->nsize; i++) { /* tangential size effect */
            int kk, j = igea__term_axis(r->size[i], &kk);
            double dw[3], ek[3] = {0, 0, 0}, tg[3];
            for (int a = 0; a < 3; a++)
                dw[a] = w[a] - w_p[a];
            ek[kk] = 1.0;
            igea__cross(dw, ek, tg);
            IGEA_AT(tel, nsamp, k, 1 + j) += r->err[r->size[i]] * tg[j];
        }
        memcpy(fh_p, fh, sizeof fh);
        memcpy(wh_p, wh, sizeof wh);
        memcpy(w_p, w, sizeof w);
        t_p = t;
    }
}

/* The lever arm's offsets at time t in sample k's interval (s its
 * fraction from sample k - 1, 1 at k): C l (position), C (w x l), the
 * quaternion (normalised) and the rate linearly interpolated. */
static void lever(const raw_inst *r, const double *traj, int ldt, int k, double s,
                  double *dr, double *dv)
{
    double q[4], C[9], l[3], w[3], wl[3];
    int kp = k > 0 ? k - 1 : 0;
    for (int a = 0; a < 3; a++) {
        l[a] = err_of(r, IGEA_ENVFUN_TERM_LEVER_X + a);
        w[a] = (1.0 - s) * IGEA_AT(traj, ldt, kp, 4 + a) + s * IGEA_AT(traj, ldt, k, 4 + a);
    }
    for (int i = 0; i < 4; i++)
        q[i] = (1.0 - s) * IGEA_AT(traj, ldt, kp, 7 + i) + s * IGEA_AT(traj, ldt, k, 7 + i);
    igea__quat_dcm_unit(q, C);
    igea__cross(w, l, wl);
    igea__m3_vec(C, l, dr, 0);
    igea__m3_vec(C, wl, dv, 0);
}

/* The true state at epoch time te in (t_{k-1}, t_k]: at t_k the state st
 * itself, else a partial step from the state prev at t_{k-1} with the
 * increments of the linear interpolants of f and w (what the trapezoid
 * increments integrate) over (t_{k-1}, te]; *s the fraction. */
static int state_at(const raw_inst *r, const double *traj, int ldt, int k, double te,
                    const double *prev, const double *st, double *out, double *s)
{
    double tk = IGEA_AT(traj, ldt, k, 0);
    memcpy(out, st, IGEA_NAV_STATE_LEN * sizeof(double));
    *s = 1.0;
    if (k == 0 || fabs(te - tk) <= 1e-9)
        return 0;
    double tp = IGEA_AT(traj, ldt, k - 1, 0), h = te - tp, dv[3], dth[3];
    *s = h / (tk - tp);
    for (int a = 0; a < 3; a++) {
        double f0 = IGEA_AT(traj, ldt, k - 1, 1 + a), f1 = IGEA_AT(traj, ldt, k, 1 + a);
        double w0 = IGEA_AT(traj, ldt, k - 1, 4 + a), w1 = IGEA_AT(traj, ldt, k, 4 + a);
        dv[a] = 0.5 * h * (2.0 * f0 + *s * (f1 - f0));
        dth[a] = 0.5 * h * (2.0 * w0 + *s * (w1 - w0));
    }
    memcpy(out, prev, IGEA_NAV_STATE_LEN * sizeof(double));
    return igea_nav_step(out, te, dv, r->system == IGEA_ENVFUN_STRAPDOWN ? dth : NULL);
}

/* The tracked point of epoch e (true state sx, fraction s of sample k's
 * interval) minus the noise, in frame, into row e of trk. */
static int track_row(const raw_inst *r, const double *traj, int ldt, const double *site,
                     int frame, int nepochs, int e, double te, int k, double s,
                     const double *sx, const double *dl0, const double *noise, double *trk)
{
    double rr[3], vv[3], dr[3] = {0, 0, 0}, dl[3] = {0, 0, 0};
    if (r->lever)
        lever(r, traj, ldt, k, s, dr, dl);
    for (int a = 0; a < 3; a++) {
        rr[a] = sx[IGEA_NAV_STATE_R + a] + dr[a];
        vv[a] = sx[IGEA_NAV_STATE_V + a] + dl[a] - dl0[a] - (noise ? noise[3 * e + a] : 0.0);
    }
    int st = igea_nav_transform(site, IGEA_NAV_LI, frame, te, rr, vv, rr, vv);
    IGEA_AT(trk, nepochs, e, 0) = te;
    for (int a = 0; a < 3; a++) {
        IGEA_AT(trk, nepochs, e, 1 + a) = rr[a];
        IGEA_AT(trk, nepochs, e, 4 + a) = vv[a];
    }
    return st;
}

/* The true vehicle: the navigation of the error-free increments (the
 * trapezoids of f, w) from the true site; at each epoch (any time in the
 * trajectory's span: ep[e] the sample k with t_{k-1} < t_e <= t_k, 0 at
 * t_0) its tracked point (the lever arm's velocity counted from lift-off,
 * where the vehicle is at rest on the pad) minus the noise, in frame. */
static int tracking(const raw_inst *r, int nsamp, const double *traj, int ldt,
                    const double *site, int frame, int nepochs, const double *epochs,
                    const int *ep, const double *noise, double *trk)
{
    double st[IGEA_NAV_STATE_LEN], prev[IGEA_NAV_STATE_LEN], sx[IGEA_NAV_STATE_LEN], q[4];
    double f_p[3], w_p[3], dr0[3] = {0, 0, 0}, dl0[3] = {0, 0, 0};
    if (r->lever)
        lever(r, traj, ldt, 0, 1.0, dr0, dl0);
    for (int i = 0; i < 4; i++)
        q[i] = IGEA_AT(traj, ldt, 0, 7 + i);
    int s = igea_nav_init(r->system, site, IGEA_NAV_GRAVITY_J2, 0, 0.0, q, NULL, NULL, st);
    sample(traj, ldt, 0, f_p, w_p);
    for (int k = 0, e = 0; !s && k < nsamp && e < nepochs; k++) {
        double f[3], w[3], dv[3], dth[3], t = sample(traj, ldt, k, f, w), fr;
        for (int a = 0; k && a < 3; a++) {
            dv[a] = 0.5 * (t - st[IGEA_NAV_STATE_T]) * (f_p[a] + f[a]);
            dth[a] = 0.5 * (t - st[IGEA_NAV_STATE_T]) * (w_p[a] + w[a]);
        }
        memcpy(prev, st, sizeof st);
        if (k)
            s = igea_nav_step(st, t, dv, r->system == IGEA_ENVFUN_STRAPDOWN ? dth : NULL);
        memcpy(f_p, f, sizeof f);
        memcpy(w_p, w, sizeof w);
        for (; !s && e < nepochs && ep[e] == k; e++) {
            s = state_at(r, traj, ldt, k, epochs[e], prev, st, sx, &fr);
            if (!s) /* a time within 1e-9 s of a sample is the sample's */
                s = track_row(r, traj, ldt, site, frame, nepochs, e, fr < 1.0 ? epochs[e] : t,
                              k, fr, sx, dl0, noise, trk);
        }
    }
    return s == 0 ? 0 : (s == IGEA_ENONFINITE ? s : IGEA_EDOMAIN);
}

/* The stated launch point: moved by pos0_x downrange and pos0_z
 * cross-range at the same height, the azimuth that of the true downrange
 * direction in the new horizontal. */
static int stated_site(const raw_inst *r, const double *site, double *out)
{
    double d = err_of(r, IGEA_ENVFUN_TERM_POS0_X), c = err_of(r, IGEA_ENVFUN_TERM_POS0_Z);
    const double *C = site + IGEA_NAV_SITE_C;
    double p[3], geo[3];
    if (d == 0.0 && c == 0.0) {
        memcpy(out, site, IGEA_NAV_SITE_LEN * sizeof(double));
        return 0;
    }
    for (int a = 0; a < 3; a++)
        p[a] = site[IGEA_NAV_SITE_R0 + a] + C[a] * d + C[6 + a] * c;
    if (igea_nav_ecef_to_geodetic(p, geo))
        return IGEA_EDOMAIN;
    double sl = sin(geo[0]), cl = cos(geo[0]), so = sin(geo[1]), co = cos(geo[1]);
    double east[3] = {-so, co, 0}, north[3] = {-sl * co, -sl * so, cl}, xe = 0, xn = 0;
    for (int a = 0; a < 3; a++) {
        xe += C[a] * east[a];
        xn += C[a] * north[a];
    }
    return igea_nav_site(geo[0], geo[1], site[IGEA_NAV_SITE_H], atan2(xe, xn), out)
               ? IGEA_EDOMAIN : 0;
}

/* Arguments 1-18 but the data: 0 or -i. */
static int raw_args(int system, int nsamp, const double *traj, int ldt, int nerr,
                    const double *site, int frame, int nepochs, const double *epochs,
                    const double *tel, int ldtel, const double *trk, int ldtrk,
                    const double *q0, const double *site_out)
{
    double M[9];
    int st = igea__traj_args(system, nsamp, traj, ldt);
    if (st)
        return st;
    if (nerr < IGEA_ENVFUN_TERM_COUNT || nerr > igea_envfun_term_count())
        return -5;
    if (!site || igea_nav_rotation(site, IGEA_NAV_LI, IGEA_NAV_ECEF, 0.0, M))
        return -8;
    if (frame != IGEA_NAV_ECEF && frame != IGEA_NAV_LE)
        return -9;
    if (nepochs < 1 || nepochs > INT_MAX / 3)
        return -10;
    if (!epochs)
        return -11;
    if (!tel)
        return -13;
    if (ldtel < nsamp)
        return -14;
    if (!trk)
        return -15;
    if (ldtrk < nepochs)
        return -16;
    return !q0 ? -17 : !site_out ? -18 : 0;
}

/* The sample of every epoch: k with t_{k-1} < t_e <= t_k (0 at t_0; a
 * time within 1e-9 s of a sample is that sample's); 0, IGEA_ENONFINITE or
 * -11 (not increasing, or outside [t_0, t_last]). */
static int epoch_samples(int nsamp, const double *traj, int ldt, int nepochs,
                         const double *epochs, int *ep)
{
    if (!igea__finite_vec(nepochs, epochs, 1))
        return IGEA_ENONFINITE;
    for (int e = 0, k = 0; e < nepochs; e++) {
        if (e > 0 && !(epochs[e] > epochs[e - 1]))
            return -11;
        if (epochs[e] < IGEA_AT(traj, ldt, 0, 0) - 1e-9)
            return -11;
        while (k < nsamp && IGEA_AT(traj, ldt, k, 0) < epochs[e] - 1e-9)
            k++;
        if (k == nsamp)
            return -11;
        ep[e] = k;
    }
    return 0;
}

/* Data checks: 0, -3, -6, -7, -11, -12, IGEA_ENONFINITE, IGEA_EDOMAIN. */
static int raw_data(raw_inst *r, int system, int nsamp, const double *traj, int ldt,
                    int nerr, const double *err, const int *axes, int nepochs,
                    const double *epochs, const double *noise, int *ep)
{
    int st = inst_init(r, system, nerr, err, axes);
    if (st)
        return st;
    if (!igea__finite_mat(nsamp, IGEA_ENVFUN_TRAJ_COLS, traj, ldt) ||
        (err && !igea__finite_vec(nerr, err, 1)) ||
        (noise && !igea__finite_vec(3 * nepochs, noise, 1)))
        return IGEA_ENONFINITE;
    if (igea__traj_times(nsamp, traj, ldt, 0, NULL) || IGEA_AT(traj, ldt, 0, 0) != 0.0)
        return -3;
    if ((st = epoch_samples(nsamp, traj, ldt, nepochs, epochs, ep)) != 0)
        return st;
    for (int k = 0; k < nsamp; k++)
        if ((k == 0 && system == IGEA_ENVFUN_STRAPDOWN) || r->lever)
            if (!(igea__traj_qnorm2(traj, ldt, k) > 1e-200))
                return IGEA_EDOMAIN;
    return 0;
}

int igea_sim_raw(int system, int nsamp, const double *traj, int ldt, int nerr,
                 const double *err, const int *axes, const double *site, int frame,
                 int nepochs, const double *epochs, const double *noise, double *tel,
                 int ldtel, double *trk, int ldtrk, double *q0, double *site_out)
{
    int st = raw_args(system, nsamp, traj, ldt, nerr, site, frame, nepochs, epochs, tel,
                      ldtel, trk, ldtrk, q0, site_out);
    if (st)
        return st;
    raw_inst *r = malloc(sizeof *r);
    int cols = system == IGEA_ENVFUN_STRAPDOWN ? 7 : 4, *ep = igea__ialloc((size_t)nepochs);
    double *tb = igea__dalloc((size_t)nsamp * 7), *kb = igea__dalloc((size_t)nepochs * 7);
    double q[4], so[IGEA_NAV_SITE_LEN];
    if (!r || !ep || !tb || !kb)
        st = IGEA_ENOMEM;
    if (!st)
        st = raw_data(r, system, nsamp, traj, ldt, nerr, err, axes, nepochs, epochs, noise, ep);
    if (!st) {
        telemetry(r, nsamp, traj, ldt, tb);
        st = tracking(r, nsamp, traj, ldt, site, frame, nepochs, epochs, ep, noise, kb);
    }
    if (!st)
        st = stated_site(r, site, so);
    if (!st) {
        double v[3];
        for (int i = 0; i < 4; i++)
            q[i] = system == IGEA_ENVFUN_STRAPDOWN ? IGEA_AT(traj, ldt, 0, 7 + i) : (i == 0);
        if (system == IGEA_ENVFUN_STRAPDOWN) { /* exp(-[phi0 x]) C = C exp(-[C^T phi0 x]) */
            double C[9], phi[3];
            igea__quat_dcm_unit(q, C);
            for (int a = 0; a < 3; a++)
                phi[a] = -err_of(r, IGEA_ENVFUN_TERM_ATT0_X + a);
            igea__m3_vec(C, phi, v, 1);
            igea__quat_rotate(q, v);
        }
    }
    if (!st && (!igea__finite_vec(nsamp * cols, tb, 1) || !igea__finite_vec(7 * nepochs, kb, 1)))
        st = IGEA_ENONFINITE;
    if (!st) {
        for (int j = 0; j < cols; j++)
            memcpy(tel + (size_t)j * ldtel, tb + (size_t)j * nsamp, nsamp * sizeof(double));
        for (int j = 0; j < 7; j++)
            memcpy(trk + (size_t)j * ldtrk, kb + (size_t)j * nepochs, nepochs * sizeof(double));
        memcpy(q0, q, sizeof q);
        memcpy(site_out, so, sizeof so);
    }
    free(r);
    free(ep);
    free(tb);
    free(kb);
    return st;
}

int igea_sim_raw_track(int system, int nsamp, const double *traj, int ldt, int nerr,
                       const double *err, const int *axes, const double *site, int frame,
                       int nepochs, const double *epochs, const double *trk_err, int acc_cols,
                       const double *acc, double *tel, int ldtel, double *trk, int ldtrk,
                       double *q0, double *site_out)
{
    if (acc_cols != 0 && acc_cols != 1 && acc_cols != 3 && acc_cols != 6 && acc_cols != 21)
        return -13;
    if (acc_cols > 0 && !acc)
        return -14;
    if (!trk)
        return -17;
    if (nepochs >= 1 && ldtrk < nepochs)
        return -18;
    if (nepochs >= 1 && nepochs <= INT_MAX / 21) {
        if (trk_err && !igea__finite_vec(6 * nepochs, trk_err, 1))
            return -12;
        if (acc_cols > 0 && !igea__finite_vec(acc_cols * nepochs, acc, 1))
            return -14;
    }
    double *kb = nepochs >= 1 && nepochs <= INT_MAX / 21 ? igea__dalloc((size_t)nepochs * 7) : NULL;
    if (!kb && nepochs >= 1 && nepochs <= INT_MAX / 21)
        return IGEA_ENOMEM;
    int st = igea_sim_raw(system, nsamp, traj, ldt, nerr, err, axes, site, frame, nepochs,
                          epochs, NULL, tel, ldtel, kb, nepochs, q0, site_out);
    if (st == 0) {
        for (int e = 0; e < nepochs; e++) {
            IGEA_AT(trk, ldtrk, e, 0) = IGEA_AT(kb, nepochs, e, 0);
            for (int c = 1; c < 7; c++)
                IGEA_AT(trk, ldtrk, e, c) =
                    IGEA_AT(kb, nepochs, e, c) + (trk_err ? trk_err[6 * (size_t)e + c - 1] : 0.0);
            for (int c = 0; c < acc_cols; c++)
                IGEA_AT(trk, ldtrk, e, 7 + c) = acc[(size_t)acc_cols * e + c];
        }
    }
    free(kb);
    if (st == -13 || st == -14)
        return st - 2;
    return st == -17 || st == -18 ? st - 2 : st;
}

/* P (6 x 6 row-major) of igea_sim_track_errors with velocity sigma sv. */
static void track_cov(double sr, double sv, double rho, double c, double *P)
{
    double R[9] = {1, rho, rho * rho, rho, 1, rho, rho * rho, rho, 1}, s[2] = {sr, sv};
    for (int bi = 0; bi < 2; bi++)
        for (int bj = 0; bj < 2; bj++)
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    P[6 * (3 * bi + i) + 3 * bj + j] =
                        (bi == bj ? 1.0 : c) * s[bi] * s[bj] * R[3 * i + j];
}

/* Lower Cholesky factor L of the 6 x 6 P (0, or -1 if not positive). */
static int chol6(const double *P, double *L)
{
    memset(L, 0, 36 * sizeof *L);
    for (int j = 0; j < 6; j++) {
        double d = P[7 * j];
        for (int k = 0; k < j; k++)
            d -= L[6 * j + k] * L[6 * j + k];
        if (!(d > 0.0))
            return -1;
        L[7 * j] = sqrt(d);
        for (int i = j + 1; i < 6; i++) {
            double v = P[6 * i + j];
            for (int k = 0; k < j; k++)
                v -= L[6 * i + k] * L[6 * j + k];
            L[6 * i + j] = v / L[7 * j];
        }
    }
    return 0;
}

int igea_sim_track_errors(int nepochs, const double *sigma_v, double sigma_r, double rho,
                          double cross, int seed, int flight, double *acc, double *err)
{
    if (nepochs < 1 || nepochs > INT_MAX / 21)
        return -1;
    if (!sigma_v)
        return -2;
    if (!(sigma_r > 0.0) || !isfinite(sigma_r))
        return isnan(sigma_r) || isinf(sigma_r) ? IGEA_ENONFINITE : -3;
    if (!(fabs(rho) < 1.0))
        return isnan(rho) ? IGEA_ENONFINITE : -4;
    if (!(fabs(cross) < 1.0))
        return isnan(cross) ? IGEA_ENONFINITE : -5;
    if (seed < 0)
        return -6;
    if (flight < 0)
        return -7;
    if (!acc)
        return -8;
    if (!igea__finite_vec(nepochs, sigma_v, 1))
        return IGEA_ENONFINITE;
    for (int e = 0; e < nepochs; e++)
        if (!(sigma_v[e] > 0.0))
            return -2;
    double *a = igea__dalloc(27 * (size_t)nepochs), P[36], L[36];
    gsl_rng *g = igea__rng_new(gsl_rng_mt19937, igea__sim_flight_seed(seed, flight) ^ 0x5EEDUL);
    int st = !a || !g ? IGEA_ENOMEM : 0;
    for (int e = 0; !st && e < nepochs; e++) {
        track_cov(sigma_r, sigma_v[e], rho, cross, P);
        if (chol6(P, L)) {
            st = IGEA_ENONFINITE; /* underflow of a tiny sigma product */
            break;
        }
        double z[6], *ae = a + 21 * (size_t)e, *ee = a + 21 * (size_t)nepochs + 6 * (size_t)e;
        for (int i = 0, c = 0; i < 6; i++)
            for (int j = i; j < 6; j++)
                ae[c++] = P[6 * i + j];
        for (int i = 0; i < 6; i++)
            z[i] = gsl_ran_gaussian(g, 1.0);
        for (int i = 0; i < 6; i++) {
            ee[i] = 0.0;
            for (int k = 0; k <= i; k++)
                ee[i] += L[6 * i + k] * z[k];
        }
    }
    if (!st && !igea__finite_vec(27 * nepochs, a, 1))
        st = IGEA_ENONFINITE;
    if (!st) {
        memcpy(acc, a, 21 * (size_t)nepochs * sizeof *acc);
        if (err)
            memcpy(err, a + 21 * (size_t)nepochs, 6 * (size_t)nepochs * sizeof *err);
    }
    free(a);
    igea__rng_free(g);
    return st;
}
