/* igea simulate - a synthetic flight test: trajectory -> S -> dw, written
 * as the files 'igea eqerr' reads. The model is the library's
 * (igea_sim_model), built from the shared flight options (flight.c). */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

#define DEG (3.14159265358979323846 / 180.0)

typedef struct {
    const char *dir;
    int flight, save_traj, json, nonlinear, raw, frame;
    double lat, lon, height, azimuth, track_sigma_r, track_corr, track_cross;
} sm_args;

static sm_args A;
static const cli_opt options[] = {
    CLI_FLIGHT_MODEL_OPTIONS,
    CLI_FLIGHT_TRUTH_OPTIONS,
    CLI_FLIGHT_NOISE_OPTIONS,
    {"--flight", CLI_OPT_INT, &A.flight, "0", "F", "flight index within the seed", NULL},
    {"--nonlinear-truth", CLI_OPT_FLAG, &A.nonlinear, NULL, NULL, "dw from the full nonlinear navigation error with\n"
     "the true X (igea_sim_nonlinear) instead of\nS diag(spec) X", NULL},
    CLI_HEAD("raw range records (--raw):"),
    {"--raw", CLI_OPT_FLAG, &A.raw, NULL, NULL, "also write the raw records of the same flight:\n"
     "telemetry.txt, tracking.txt, dw_args.txt (and\ntraj.txt) for igea dw", NULL},
    {"--lat", CLI_OPT_NUM, &A.lat, "40.96", "DEG", "geodetic latitude of the true launch point", NULL},
    {"--lon", CLI_OPT_NUM, &A.lon, "100.29", "DEG", "its longitude", NULL},
    {"--height", CLI_OPT_NUM, &A.height, "1000", "M", "its ellipsoidal height", NULL},
    {"--azimuth", CLI_OPT_NUM, &A.azimuth, "30", "DEG", "firing azimuth, from north toward east", NULL},
    {"--frame", CLI_OPT_CHOICE, &A.frame, "ecef", CLI_CHOICES(IGEA_CHOICE_DW_FRAME), "the tracking's frame: ecef or le", NULL},
    {"--track-sigma-r", CLI_OPT_NUM, &A.track_sigma_r, "0", "M", "> 0: the tracking's own position and velocity errors\n"
     "(igea_sim_track_errors) instead of the flight's noise:\nposition 1-sigma M per axis, velocity the stated sigma;\n"
     "tracking.txt then holds the 6 x 6 covariance (28 columns)", NULL},
    {"--track-corr", CLI_OPT_NUM, &A.track_corr, "0", "R", "their correlation between neighbouring axes", NULL},
    {"--track-cross", CLI_OPT_NUM, &A.track_cross, "0", "C", "their position-velocity correlation", NULL},
    CLI_HEAD("output:"),
    {"--dir", CLI_OPT_STR, &A.dir, ".", "DIR", "output directory (must exist)", NULL},
    {"--save-traj", CLI_OPT_FLAG, &A.save_traj, NULL, NULL, "also write DIR/traj.txt", NULL},
    {"--json", CLI_OPT_FLAG, &A.json, NULL, NULL, "print a JSON summary", NULL},
    CLI_END};

static const cli_command command = {"simulate",
"usage: igea simulate [options] --dir DIR\n"
"\n"
"A synthetic flight test with known truth: a trajectory (the reference boost\n"
"of METHODS 5.6 or your file) -> environment functions S (igea envfun) -> the\n"
"true instrument errors X (N(0, I) in spec units, or set term by term) ->\n"
"dw = S diag(spec) X + tracking noise. Writes, into DIR:\n"
"  S.txt      raw environment functions (rows epoch-major x, y, z; '# names')\n"
"  dw.txt     velocity differences, one per row of S\n"
"  sigma.txt  the stated tracking 1-sigma of each row\n"
"  spec.txt   the 1-sigma spec of each term\n"
"  X.txt      the true X (spec units), one line per term: value name\n"
"  traj.txt   the trajectory, with --save-traj or --raw\n"
"With --raw, also the two records a range hands over (docs/pipeline.md,\n"
"section 8), of the same flight (same X, same tracking noise):\n"
"  telemetry.txt  t dvx dvy dvz [dthx dthy dthz]: increments with the\n"
"                 instrument errors (strapdown body axes, platform axes)\n"
"  tracking.txt   t x y z vx vy vz sigma of the true vehicle in --frame at\n"
"                 the epochs (any times in the trajectory), noise added\n"
"  dw_args.txt    the stated launch point, frame, system and lift-off\n"
"                 attitude as igea dw options: igea dw $(cat dw_args.txt) ...\n"
"  site_args.txt  the stated launch point alone, for igea envfun (its pos0_*\n"
"                 terms): igea envfun $(cat site_args.txt) ...\n"
"exactly the files 'igea eqerr' reads. The same --seed gives the same flight on\n"
"every machine; --flight F picks another flight of the same seed.\n"
"\n",
options,
"\n"
"example:\n"
"  mkdir -p flight && igea simulate --seed 7 --sigma-w 1.8 --dir flight\n"
"  cd flight && igea eqerr --S S.txt --dw dw.txt --sigma sigma.txt --spec spec.txt\n"
"  igea simulate --x gyro_bias_y=3 --seed 1 --dir flight   # one term at 3 x spec\n"
"  igea simulate --raw --system platform --terms all --dir flight && cd flight &&\n"
"  igea dw $(cat dw_args.txt) --telemetry telemetry.txt --tracking tracking.txt \\\n"
"      --out dw_raw.txt --sigma-out sigma_raw.txt\n"};

static char *join(const char *dir, const char *name)
{
    size_t n = strlen(dir) + strlen(name) + 2;
    char *p = malloc(n);
    if (p)
        snprintf(p, n, "%s/%s", dir, name);
    return p;
}

/* One flight of the model: x (N), dw (m), S row-major (m x N), sigma (m). */
typedef struct {
    double *x, *dw, *S, *sigma, *traj; /* traj: row-major, with --save-traj */
    char *header;
    double *tel, *trk, q0[4], site[IGEA_NAV_SITE_LEN]; /* --raw: row-major records */
    int tel_cols, trk_cols, tel_rows, ntrk;
} sm_run;

static int run_flight(const sm_args *a, const cli_flight_args *fa, cli_flight *f, sm_run *r)
{
    int m = f->m, N = f->N;
    double *S = malloc(sizeof(double) * (size_t)m * N);
    r->x = malloc(sizeof(double) * (size_t)N);
    r->dw = malloc(sizeof(double) * (size_t)m);
    r->sigma = malloc(sizeof(double) * (size_t)m);
    r->header = cli_term_header(f->codes, N);
    int ec = !S || !r->x || !r->dw || !r->sigma || !r->header ? cli_oom("the flight") : CLI_OK;
    int st = 0;
    if (!ec && a->nonlinear)
        st = igea_sim_model_set_nonlinear(f->model, 1);
    if (!ec && !st)
        st = igea_sim_flight(f->model, fa->seed, a->flight, r->x, r->dw);
    if (!ec && !st)
        st = igea_sim_model_get_s(f->model, S, m);
    if (!ec && !st)
        st = igea_sim_model_get_sigma(f->model, r->sigma);
    if (!ec)
        ec = cli_status(st, "simulate");
    if (!ec && !(r->S = cli_rowmajor(S, m, N)))
        ec = cli_oom("the flight");
    free(S);
    if (!ec && a->save_traj && !(r->traj = cli_rowmajor(f->traj, f->nsamp, IGEA_ENVFUN_TRAJ_COLS)))
        ec = cli_oom("the trajectory table");
    return ec;
}

/* The tracking noise of the flight: the same flight with every X fixed at 0
 * and the linear truth (the draws do not depend on the fixed values). */
static int flight_noise(const cli_flight_args *fa, const sm_args *a, cli_flight *f,
                        double *noise)
{
    double *zero = calloc((size_t)f->N, sizeof(double));
    int *fix = malloc(sizeof(int) * (size_t)f->N), st = 0;
    if (!zero || !fix) {
        free(zero);
        free(fix);
        return cli_oom("the noise");
    }
    for (int j = 0; j < f->N; j++)
        fix[j] = 1;
    st = igea_sim_model_set_nonlinear(f->model, 0);
    if (!st)
        st = igea_sim_model_set_truth(f->model, zero, fix);
    if (!st)
        st = igea_sim_flight(f->model, fa->seed, a->flight, NULL, noise);
    free(zero);
    free(fix);
    return cli_status(st, "simulate --raw");
}

/* The tracking rows t x y z vx vy vz and the stated sigma: one per epoch
 * when its three rows agree, else sigma_x sigma_y sigma_z. */
static int tracking_rows(const cli_flight *f, const double *trk, sm_run *r)
{
    int three = 0;
    for (int e = 0; e < f->nep; e++)
        three |= r->sigma[3 * e] != r->sigma[3 * e + 1] || r->sigma[3 * e] != r->sigma[3 * e + 2];
    r->trk_cols = three ? 10 : 8;
    if (!(r->trk = malloc(sizeof(double) * (size_t)f->nep * (size_t)r->trk_cols)))
        return cli_oom("the tracking record");
    for (int e = 0; e < f->nep; e++) {
        double *row = r->trk + (size_t)e * r->trk_cols;
        for (int k = 0; k < IGEA_SIM_RAW_TRK_COLS; k++)
            row[k] = trk[e + (size_t)k * f->nep];
        for (int k = 0; k < r->trk_cols - IGEA_SIM_RAW_TRK_COLS; k++)
            row[IGEA_SIM_RAW_TRK_COLS + k] = r->sigma[3 * e + k];
    }
    return CLI_OK;
}

/* --raw with --track-sigma-r: the tracking's own errors and its 6 x 6
 * covariance (igea_sim_track_errors, igea_sim_raw_track); tel the
 * telemetry buffer (ns x tel_cols), r->trk the 28-column rows. */
static int raw_track(const sm_args *a, const cli_flight_args *fa, const cli_flight *f,
                     sm_run *r, const double *err, const double *site, double *tel)
{
    int ne = f->nep, ns = f->nsamp, st;
    double *sv = malloc(sizeof(double) * ne), *acc = malloc(sizeof(double) * 21 * ne);
    double *te = malloc(sizeof(double) * 6 * ne), *trk = malloc(sizeof(double) * 28 * ne);
    int ec = !sv || !acc || !te || !trk ? cli_oom("the tracking errors") : CLI_OK;
    for (int e = 0; !ec && e < ne; e++)
        sv[e] = r->sigma[3 * e];
    if (!ec) {
        st = igea_sim_track_errors(ne, sv, a->track_sigma_r, a->track_corr, a->track_cross,
                                   fa->seed, a->flight, acc, te);
        if (st == -3 || st == -4 || st == -5)
            cli_error("--track-%s: %s", st == -3 ? "sigma-r" : st == -4 ? "corr" : "cross",
                      st == -3 ? "a position sigma > 0 (m)" : "a correlation in (-1, 1)");
        ec = st == -3 || st == -4 || st == -5 ? CLI_USAGE : cli_status(st, "simulate --raw");
    }
    if (!ec) {
        st = igea_sim_raw_track(fa->system, ns, f->traj, ns, igea_envfun_term_count(), err, NULL,
                                site, a->frame, ne, f->ep, te, 21, acc, tel, ns, trk, ne,
                                r->q0, r->site);
        if (st == -11)
            cli_error("simulate --raw: the tracking epochs must increase and lie inside the "
                      "trajectory");
        ec = st == -11 ? CLI_DATAERR : cli_status(st, "simulate --raw");
    }
    r->trk_cols = 28;
    if (!ec && !(r->trk = cli_rowmajor(trk, ne, 28)))
        ec = cli_oom("the tracking record");
    free(sv);
    free(acc);
    free(te);
    free(trk);
    return ec;
}

/* --raw: the records of the flight just run (x true, in spec units). */
static int run_raw(const sm_args *a, const cli_flight_args *fa, cli_flight *f, sm_run *r)
{
    int ne = igea_envfun_term_count(), ns = f->nsamp, st;
    r->tel_cols = fa->system == IGEA_ENVFUN_STRAPDOWN ? IGEA_SIM_RAW_TEL_STRAPDOWN
                                                      : IGEA_SIM_RAW_TEL_PLATFORM;
    double *err = calloc((size_t)ne, sizeof(double)), *noise = malloc(sizeof(double) * f->m);
    double *tel = malloc(sizeof(double) * (size_t)ns * r->tel_cols);
    double *trk = malloc(sizeof(double) * (size_t)f->nep * IGEA_SIM_RAW_TRK_COLS);
    double site[IGEA_NAV_SITE_LEN];
    int ec = !err || !noise || !tel || !trk ? cli_oom("the raw records") : CLI_OK;
    if (!ec && a->frame == IGEA_NAV_LI) {
        cli_error("--frame: a tracking record is in ecef or le");
        ec = CLI_USAGE;
    }
    if (!ec && (st = igea_nav_site(a->lat * DEG, a->lon * DEG, a->height, a->azimuth * DEG, site))) {
        cli_error("--%s: not a launch point", st == -1 ? "lat" : st == -2 ? "lon" : "height");
        ec = CLI_USAGE;
    }
    if (!ec)
        ec = flight_noise(fa, a, f, noise);
    for (int j = 0; !ec && j < f->N; j++)
        err[f->codes[j]] = r->x[j] * f->spec[j];
    int tracked = !ec && a->track_sigma_r > 0.0;
    if (tracked)
        ec = raw_track(a, fa, f, r, err, site, tel);
    if (!ec && !tracked) {
        st = igea_sim_raw(fa->system, ns, f->traj, ns, ne, err, NULL, site, a->frame, f->nep,
                          f->ep, noise, tel, ns, trk, f->nep, r->q0, r->site);
        if (st == -11)
            cli_error("simulate --raw: the tracking epochs must increase and lie inside the "
                      "trajectory");
        ec = st == -11 ? CLI_DATAERR : cli_status(st, "simulate --raw");
    }
    r->tel_rows = ns;
    r->ntrk = f->nep;
    if (!ec && !(r->tel = cli_rowmajor(tel, ns, r->tel_cols)))
        ec = cli_oom("the telemetry record");
    if (!ec && !tracked)
        ec = tracking_rows(f, trk, r);
    free(err);
    free(noise);
    free(tel);
    free(trk);
    return ec;
}

/* The raw records and the igea dw options of the stated launch point. */
static void write_raw(cli_out *outs, const sm_args *a, const cli_flight_args *fa,
                      const sm_run *r)
{
    static const char *const sg[2] = {"sigma", "sigma_x sigma_y sigma_z"};
    static const char *const su[2] = {"m/s", "m/s m/s m/s"};
    int sd = fa->system == IGEA_ENVFUN_STRAPDOWN, three = r->trk_cols == 10;
    fprintf(outs[0].f, "# names t dvx dvy dvz%s\n# units s m/s m/s m/s%s\n",
            sd ? " dthx dthy dthz" : "", sd ? " rad rad rad" : "");
    cli_write_matrix_body(outs[0].f, 0, r->tel, r->tel_rows, r->tel_cols, NULL);
    if (r->trk_cols == 28) {
        static const char *const v[6] = {"x", "y", "z", "vx", "vy", "vz"};
        fputs("# names t x y z vx vy vz", outs[1].f);
        for (int i = 0; i < 6; i++)
            for (int j = i; j < 6; j++)
                fprintf(outs[1].f, " c_%s_%s", v[i], v[j]);
        fputs("\n# units s m m m m/s m/s m/s (the 6 x 6 position-velocity covariance: m^2, "
              "m^2/s, m^2/s^2)\n", outs[1].f);
    } else {
        fprintf(outs[1].f, "# names t x y z vx vy vz %s\n# units s m m m m/s m/s m/s %s\n",
                sg[three], su[three]);
    }
    cli_write_matrix_body(outs[1].f, 0, r->trk, r->ntrk, r->trk_cols, NULL);
    fprintf(outs[2].f, "--lat %.17g --lon %.17g --height %.17g --azimuth %.17g --frame %s "
            "--system %s --q0 %.17g,%.17g,%.17g,%.17g\n",
            r->site[IGEA_NAV_SITE_LAT] / DEG, r->site[IGEA_NAV_SITE_LON] / DEG,
            r->site[IGEA_NAV_SITE_H], r->site[IGEA_NAV_SITE_AZ] / DEG,
            a->frame == IGEA_NAV_ECEF ? "ecef" : "le", sd ? "strapdown" : "platform",
            r->q0[0], r->q0[1], r->q0[2], r->q0[3]);
    fprintf(outs[3].f, "--lat %.17g --lon %.17g --height %.17g --azimuth %.17g\n",
            r->site[IGEA_NAV_SITE_LAT] / DEG, r->site[IGEA_NAV_SITE_LON] / DEG,
            r->site[IGEA_NAV_SITE_H], r->site[IGEA_NAV_SITE_AZ] / DEG);
}

static void write_files(cli_out *outs, const sm_args *a, const cli_flight_args *fa,
                        const cli_flight *f, const sm_run *r)
{
    cli_write_matrix_body(outs[0].f, 0, r->S, f->m, f->N, r->header);
    cli_write_matrix_body(outs[1].f, 0, r->dw, f->m, 1, "dw (m/s), rows epoch-major x, y, z");
    cli_write_matrix_body(outs[2].f, 0, r->sigma, f->m, 1, "stated tracking 1-sigma (m/s) per row");
    cli_write_matrix_body(outs[3].f, 0, f->spec, f->N, 1, r->header);
    fprintf(outs[4].f, "# true X (spec units) and term name; seed %d flight %d\n", fa->seed,
            a->flight);
    for (int j = 0; j < f->N; j++)
        fprintf(outs[4].f, "%.17g # %s\n", r->x[j], igea_envfun_term_name(f->codes[j]));
    if (a->save_traj)
        cli_write_matrix_body(outs[5].f, 0, r->traj, f->nsamp, IGEA_ENVFUN_TRAJ_COLS,
                              "t f_x f_y f_z w_x w_y w_z q0 q1 q2 q3");
    if (a->raw)
        write_raw(outs + 6, a, fa, r);
}

static void json_summary(FILE *out, const sm_args *a, const cli_flight_args *fa,
                         const cli_flight *f, const sm_run *r)
{
    cli_json j;
    cli_json_begin(&j, out);
    cli_jstr(&j, "dir", a->dir);
    cli_jint(&j, "rows", f->m);
    cli_jint(&j, "seed", fa->seed);
    cli_jint(&j, "flight", a->flight);
    cli_jterms(&j, "terms", f->codes, f->N);
    cli_jnums(&j, "x_true", r->x, f->N);
    if (a->raw) {
        cli_jnum(&j, "lat", r->site[IGEA_NAV_SITE_LAT] / DEG);
        cli_jnum(&j, "lon", r->site[IGEA_NAV_SITE_LON] / DEG);
        cli_jnum(&j, "height", r->site[IGEA_NAV_SITE_H]);
        cli_jnum(&j, "azimuth", r->site[IGEA_NAV_SITE_AZ] / DEG);
        cli_jnums(&j, "q0", r->q0, 4);
    }
    cli_json_end(&j);
}

/* All files go to temporaries first and replace the old set only when
 * every one is complete (and the JSON summary has been written). */
static int commit_files(const sm_args *a, const cli_flight_args *fa, const cli_flight *f,
                        const sm_run *r)
{
    static const char *const names[10] = {"S.txt", "dw.txt", "sigma.txt", "spec.txt", "X.txt",
                                          "traj.txt", "telemetry.txt", "tracking.txt",
                                          "dw_args.txt", "site_args.txt"};
    cli_out outs[10];
    int nout = a->raw ? 10 : a->save_traj ? 6 : 5, nopen = 0, ec = CLI_OK;
    for (int k = 0; !ec && k < nout; k++) {
        char *path = join(a->dir, names[k]);
        outs[k] = (cli_out)CLI_OUT_INIT;
        ec = path ? cli_out_open(&outs[k], path) : cli_oom("an output path");
        nopen += !ec;
        free(path);
    }
    if (!ec) {
        write_files(outs, a, fa, f, r);
        if (a->json) {
            json_summary(stdout, a, fa, f, r);
            ec = cli_stdout_check();
        }
    }
    if (!ec)
        return cli_out_commit_all(outs, nout);
    for (int k = 0; k < nopen; k++)
        cli_out_abort(&outs[k]);
    return ec;
}

int cmd_simulate(int argc, char **argv)
{
    cli_flight_defaults();
    int ec = cli_parse(&command, argc, argv);
    sm_args a = A;
    cli_flight_args fa = cli_flight_opts;
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    a.save_traj |= a.raw;
    if (a.flight < 0) {
        cli_error("--flight must be >= 0");
        return CLI_USAGE;
    }
    cli_flight f;
    sm_run r;
    memset(&r, 0, sizeof r);
    if (!(ec = cli_flight_build(&fa, &f, "simulate")) && !(ec = run_flight(&a, &fa, &f, &r)) &&
        !(ec = a.raw ? run_raw(&a, &fa, &f, &r) : CLI_OK) &&
        !(ec = commit_files(&a, &fa, &f, &r)) && !a.json)
        fprintf(stderr, "igea simulate: %d epochs x 3 axes, %d terms, seed %d flight %d -> "
                "%s/{S,dw,sigma,spec,X%s}.txt\n", f.nep, f.N, fa.seed, a.flight, a.dir,
                a.raw ? ",traj,telemetry,tracking,dw_args,site_args" : a.save_traj ? ",traj" : "");
    free(r.x);
    free(r.dw);
    free(r.S);
    free(r.sigma);
    free(r.traj);
    free(r.header);
    free(r.tel);
    free(r.trk);
    cli_flight_free(&f);
    return ec;
}
