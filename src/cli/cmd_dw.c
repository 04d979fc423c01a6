/* igea dw - telemetry minus tracking: the apparent-velocity differences dW
 * at the tracking epochs, in the launch-inertial frame, from a raw
 * telemetry record and a tracking solution (igea/dw.h,
 * docs/pipeline.md). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

#define DEG (3.14159265358979323846 / 180.0)

typedef struct {
    const char *telemetry, *tracking, *q0, *out, *cov_out, *sigma_out, *offset_out, *k_out,
        *xcov_out;
    double lat, lon, height, azimuth, time_offset;
    int frame, system, kind, json, given_lat, given_lon, given_az;
} dw_args;

static dw_args A;

static const cli_opt options[] = {
    {"--telemetry", CLI_OPT_STR, &A.telemetry, NULL, "FILE", "telemetry rows t dvx dvy dvz [dthx dthy dthz] (required)", NULL},
    {"--tracking", CLI_OPT_STR, &A.tracking, NULL, "FILE", "tracking rows t x y z vx vy vz [accuracy] (required)", NULL},
    {"--lat", CLI_OPT_NUM, &A.lat, NULL, "DEG", "geodetic latitude of the launch point (required)", &A.given_lat},
    {"--lon", CLI_OPT_NUM, &A.lon, NULL, "DEG", "longitude of the launch point (required)", &A.given_lon},
    {"--height", CLI_OPT_NUM, &A.height, "0", "M", "ellipsoidal height of the launch point", NULL},
    {"--azimuth", CLI_OPT_NUM, &A.azimuth, NULL, "DEG", "firing azimuth, from north toward east (required)", &A.given_az},
    {"--frame", CLI_OPT_CHOICE, &A.frame, "le", CLI_CHOICES(IGEA_CHOICE_DW_FRAME), "the tracking's frame: le (launch-site Earth-fixed)\nor ecef", NULL},
    {"--system", CLI_OPT_CHOICE, &A.system, "strapdown", CLI_CHOICES(IGEA_CHOICE_ENVFUN_SYSTEM), "the inertial system", NULL},
    {"--kind", CLI_OPT_CHOICE, &A.kind, "apparent", CLI_CHOICES(IGEA_CHOICE_DW_KIND), "apparent: W_tel - W_trk (S from envfun --output\nvelocity); navigated: v_nav - v_trk (--output\nvelocity_g)", NULL},
    {"--q0", CLI_OPT_STR, &A.q0, "1,0,0,0", "Q0,Q1,Q2,Q3", "strapdown attitude body -> launch-inertial at\nlift-off (scalar first)", NULL},
    {"--time-offset", CLI_OPT_NUM, &A.time_offset, "0", "TAU", "telemetry clock offset (s): the record stamped s\nwas taken at tracking time s + TAU", NULL},
    {"--out", CLI_OPT_STR, &A.out, NULL, "FILE", "write dW there (3 rows per epoch, x y z; '-' is\nstandard output)", NULL},
    {"--cov-out", CLI_OPT_STR, &A.cov_out, NULL, "FILE", "the covariance of each epoch's dW in LI (the block\nK_ee: the tracking's, with 28 columns also through\nthe gravity integral), one row per epoch: c_xx c_xy\nc_xz c_yy c_yz c_zz", NULL},
    {"--k-out", CLI_OPT_STR, &A.k_out, NULL, "FILE", "the same covariance as igea eqerr --cov reads it (the\nblock K): one row per epoch, xx yx yy zx zy zz", NULL},
    {"--xcov-out", CLI_OPT_STR, &A.xcov_out, NULL, "FILE", "the covariance of each epoch's dW with every later\none's (the gravity integral's, 28-column tracking):\none row per epoch, x_xx x_xy x_xz x_yx .. x_zz", NULL},
    {"--sigma-out", CLI_OPT_STR, &A.sigma_out, NULL, "FILE", "its per-row 1-sigma (for igea eqerr --sigma)", NULL},
    {"--time-offset-out", CLI_OPT_STR, &A.offset_out, NULL, "FILE", "the column dW/dtau of a remaining clock offset\n(term time_offset, to append to S)", NULL},
    {"--json", CLI_OPT_FLAG, &A.json, NULL, NULL, "machine-readable summary (field names as igea.dw)", NULL},
    CLI_END};

static const cli_command command = {"dw",
"usage: igea dw --telemetry FILE --tracking FILE --lat DEG --lon DEG --azimuth DEG\n"
"               [--height M] [--frame le|ecef] [--system strapdown|platform]\n"
"               --out FILE [--cov-out FILE] [--k-out FILE] [--sigma-out FILE] [options]\n"
"\n"
"Telemetry minus tracking (docs/pipeline.md): the apparent-velocity\n"
"differences dW = W_telemetry - W_tracking at the tracking epochs, in the\n"
"launch-inertial frame LI (the launch-site frame frozen at lift-off: x along\n"
"the firing azimuth, y up, z to the right), rows epoch-major x, y, z: the dw\n"
"that 'igea eqerr' reads, with S from 'igea envfun'.\n"
"  W_telemetry = int f dt from the increments (strapdown: coning, sculling);\n"
"  W_tracking  = v_LI(t) - v_LI(0) - int J2 gravity along the tracked path.\n"
"\n"
"Telemetry: t dvx dvy dvz dthx dthy dthz (strapdown, body axes, m/s and rad)\n"
"or t dvx dvy dvz (platform, along LI); each row holds the increments since\n"
"the row before; the first row is lift-off (vehicle at rest on the pad).\n"
"Tracking: t x y z vx vy vz (m, m/s, in --frame) and the velocity accuracy:\n"
"nothing, one sigma, sigma_x sigma_y sigma_z, c_xx c_xy c_xz c_yy c_yz c_zz, or\n"
"the 6 x 6 covariance of x y z vx vy vz (21 values, its upper triangle row by\n"
"row; the position's part enters K through the Earth rate and, apparent kind,\n"
"through the gravity integral, which also correlates the epochs: --xcov-out).\n"
"Epochs may be unequally spaced, with gaps; each must lie in the telemetry span.\n"
"\n"
"options:\n",
options,
"\n"
"exit status: 0 ok, 64 usage, 65 bad input (an epoch outside the telemetry,\n"
"times not increasing, ...), 66 missing input, 70 numerical failure, 74 I/O error.\n"
"\n"
"example:\n"
"  igea dw --telemetry tel.txt --tracking trk.txt --lat 40.96 --lon 100.29 \\\n"
"      --azimuth 30 --frame ecef --out dw.txt --sigma-out sigma.txt\n"
"  igea eqerr --S S.txt --dw dw.txt --sigma sigma.txt --spec spec.txt\n"};

typedef struct {
    cli_matrix tel, trk;
    double *telc, *trkc, *dw, *cov, *xcov, *sigma, *col, *klow, q0[4], site[IGEA_NAV_SITE_LEN];
    int ntrk;
} dw_run;

/* A row-major file into a column-major array (malloc'd). */
static double *colmajor(const cli_matrix *m)
{
    double *c = malloc(sizeof(double) * (size_t)m->rows * (size_t)m->cols + 1);
    if (c)
        for (long i = 0; i < m->rows; i++)
            for (int j = 0; j < m->cols; j++)
                c[i + (size_t)m->rows * j] = m->v[i * m->cols + j];
    return c;
}

static int read_inputs(const dw_args *a, dw_run *r)
{
    int ec;
    if (sscanf(a->q0, "%lf,%lf,%lf,%lf", &r->q0[0], &r->q0[1], &r->q0[2], &r->q0[3]) != 4) {
        cli_error("--q0: four comma-separated numbers");
        return CLI_USAGE;
    }
    if (igea_nav_site(a->lat * DEG, a->lon * DEG, a->height, a->azimuth * DEG, r->site)) {
        cli_error("--lat, --lon, --height, --azimuth: |lat| < 90, height > -6e6 m");
        return CLI_USAGE;
    }
    if ((ec = cli_read_matrix(a->telemetry, &r->tel)) || (ec = cli_read_matrix(a->tracking, &r->trk)))
        return ec;
    int tc = r->tel.cols, kc = r->trk.cols;
    if (a->system == IGEA_ENVFUN_STRAPDOWN ? tc != 7 : tc != 4 && tc != 7) {
        cli_error("%s: %d columns; a %s telemetry has %s", a->telemetry, tc,
                  igea_choice_name(IGEA_CHOICE_ENVFUN_SYSTEM, a->system),
                  a->system == IGEA_ENVFUN_STRAPDOWN ? "7 (t dv3 dth3)" : "4 (t dv3)");
        return CLI_DATAERR;
    }
    if (kc != 7 && kc != 8 && kc != 10 && kc != 13 && kc != 28) {
        cli_error("%s: %d columns; tracking has 7 (t r3 v3), 8 (+ sigma), 10 (+ 3 sigmas), "
                  "13 (+ velocity covariance) or 28 (+ 6 x 6 covariance)", a->tracking, kc);
        return CLI_DATAERR;
    }
    if (kc == 7 && (a->cov_out || a->sigma_out || a->k_out || a->xcov_out)) {
        cli_error("--cov-out, --k-out, --sigma-out, --xcov-out: %s holds no accuracy columns",
                  a->tracking);
        return CLI_USAGE;
    }
    if (r->tel.rows > 2147483647L || r->trk.rows > 715827882L)
        return cli_oom("the records");
    r->ntrk = (int)r->trk.rows;
    size_t m = 3 * (size_t)r->ntrk;
    r->telc = colmajor(&r->tel);
    r->trkc = colmajor(&r->trk);
    r->dw = malloc(sizeof(double) * m);
    r->col = malloc(sizeof(double) * m);
    r->cov = malloc(sizeof(double) * 2 * m);
    r->klow = malloc(sizeof(double) * 2 * m);
    r->xcov = malloc(sizeof(double) * 3 * m);
    r->sigma = malloc(sizeof(double) * m);
    if (!r->telc || !r->trkc || !r->dw || !r->col || !r->cov || !r->sigma || !r->klow ||
        !r->xcov)
        return cli_oom("the records");
    return CLI_OK;
}

static int compute(const dw_args *a, dw_run *r)
{
    int bad = -1, kc = r->trk.cols;
    int st = igea_dw_compute_k(r->site, a->system, a->kind, r->q0, a->time_offset,
                               (int)r->tel.rows, r->telc, (int)r->tel.rows, r->tel.cols, a->frame,
                               r->ntrk, r->trkc, r->ntrk, kc, r->dw, kc > 7 ? r->cov : NULL,
                               kc > 7 ? r->xcov : NULL, r->col, &bad);
    const double *t = r->telc, *k = r->trkc;
    long nt = r->tel.rows;
    switch (st) {
    case IGEA_DW_ESPAN:
        cli_error("%s: data row %d (epoch %d, t = %.17g s) is outside the telemetry span "
                  "[%.17g, %.17g] s (time offset %g s)", a->tracking, bad + 1, bad, k[bad],
                  t[0] + a->time_offset, t[nt - 1] + a->time_offset, a->time_offset);
        return CLI_DATAERR;
    case IGEA_DW_ETRACK:
        cli_error("%s: data row %d (epoch %d): t = %.17g s does not follow %.17g s", a->tracking,
                  bad + 1, bad, k[bad], k[bad - 1]);
        return CLI_DATAERR;
    case IGEA_DW_ETELEMETRY:
        cli_error("%s: data row %d: t = %.17g s does not follow %.17g s", a->telemetry, bad + 1,
                  t[bad], t[bad - 1]);
        return CLI_DATAERR;
    case -10:
        cli_error("--frame: the tracking is in le or ecef");
        return CLI_USAGE;
    case -5:
        cli_error("--time-offset: |TAU| < 1000 s");
        return CLI_USAGE;
    case -6:
        cli_error("%s: a lift-off row and at least one record are needed", a->telemetry);
        return CLI_DATAERR;
    case -4:
        cli_error("--q0: a non-zero quaternion");
        return CLI_USAGE;
    case IGEA_ENONPOSITIVE:
        cli_error("%s: a sigma is not positive or a covariance not positive definite",
                  a->tracking);
        return CLI_DATAERR;
    default:
        break;
    }
    if (st == IGEA_ENONFINITE)
        cli_error("%s, %s: NaN or Inf in the records or the result", a->telemetry, a->tracking);
    if (st == IGEA_ENONFINITE)
        return CLI_DATAERR;
    if (!st && kc > 7)
        st = igea_dw_summary(r->ntrk, r->dw, r->cov, r->sigma, NULL, NULL);
    return cli_status(st, "dw");
}

/* The summary: epochs, records, the largest |dW| and the rms per axis. */
static void summary(FILE *f, const dw_args *a, const dw_run *r)
{
    double mx = 0.0, rms[3] = {0.0, 0.0, 0.0};
    igea_dw_summary(r->ntrk, r->dw, NULL, NULL, &mx, rms); /* dw checked finite */
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, f);
        cli_jint(&j, "n_epochs", r->ntrk);
        cli_jint(&j, "rows", 3L * r->ntrk);
        cli_jint(&j, "samples", r->tel.rows);
        cli_jnum(&j, "max_abs", mx);
        cli_jnums(&j, "rms", rms, 3);
        cli_jstr(&j, "out", a->out);
        cli_json_end(&j);
    } else {
        fprintf(f, "igea dw: %d epochs (%d rows), %ld telemetry records; max |dW| %.6g m/s, "
                   "rms x y z %.6g %.6g %.6g m/s\n", r->ntrk, 3 * r->ntrk, r->tel.rows, mx,
                rms[0], rms[1], rms[2]);
    }
}

static int write_outputs(const dw_args *a, const dw_run *r)
{
    cli_out o[6] = {CLI_OUT_INIT, CLI_OUT_INIT, CLI_OUT_INIT,
                    CLI_OUT_INIT, CLI_OUT_INIT, CLI_OUT_INIT};
    const char *paths[6] = {a->out, a->cov_out, a->sigma_out, a->offset_out, a->k_out,
                            a->xcov_out};
    const double *data[6] = {r->dw, r->cov, r->sigma, r->col, r->klow, r->xcov};
    const int cols[6] = {1, 6, 1, 1, 6, 9};
    const char *head[6] = {
        "names dw\n# units m/s\n# rows epoch-major x y z, launch-inertial axes",
        "names c_xx c_xy c_xz c_yy c_yz c_zz\n# units m^2/s^2\n# one row per epoch, launch-inertial axes",
        "names sigma\n# units m/s\n# rows epoch-major x y z",
        "names time_offset\n# units m/s^2 (dW per s of clock offset)\n# rows epoch-major x y z",
        "names c_xx c_yx c_yy c_zx c_zy c_zz\n# units m^2/s^2\n# one row per epoch, launch-inertial "
        "axes: the block K of igea eqerr --cov",
        "names x_xx x_xy x_xz x_yx x_yy x_yz x_zx x_zy x_zz\n# units m^2/s^2\n# row e: Cov(dW_e, "
        "dW_f) for every later epoch f (row axis of dW_e, column axis of dW_f), launch-inertial "
        "axes; 0 in the last row"};
    for (int e = 0; a->k_out && e < r->ntrk; e++) { /* xx xy xz yy yz zz -> xx yx yy zx zy zz */
        static const int perm[6] = {0, 1, 3, 2, 4, 5};
        for (int i = 0; i < 6; i++)
            r->klow[6 * (size_t)e + i] = r->cov[6 * (size_t)e + perm[i]];
    }
    int n = 0, ec = CLI_OK;
    for (int i = 0; i < 6 && !ec; i++) {
        if (!paths[i])
            continue;
        if ((ec = cli_out_open(&o[n], paths[i])))
            break;
        size_t len = strlen(paths[i]);
        int npy = o[n].f != stdout && len >= 4 && !strcmp(paths[i] + len - 4, ".npy");
        long rows = i == 1 || i >= 4 ? r->ntrk : 3L * r->ntrk;
        cli_write_matrix_body(o[n].f, npy, data[i], rows, cols[i], head[i]);
        n++;
    }
    if (!ec) {
        int to_stdout = 0;
        for (int i = 0; i < 6; i++)
            to_stdout |= paths[i] && !strcmp(paths[i], "-");
        summary(to_stdout ? stderr : stdout, a, r);
        ec = cli_stdout_check();
    }
    if (ec) {
        for (int i = 0; i < n; i++)
            cli_out_abort(&o[i]);
        return ec;
    }
    return cli_out_commit_all(o, n);
}

int cmd_dw(int argc, char **argv)
{
    memset(&A, 0, sizeof A);
    int ec = cli_parse(&command, argc, argv);
    dw_args a = A;
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    if (!a.telemetry || !a.tracking || !a.given_lat || !a.given_lon || !a.given_az || !a.out) {
        cli_error("dw: --telemetry, --tracking, --lat, --lon, --azimuth and --out are required "
                  "(see igea dw --help)");
        return CLI_USAGE;
    }
    dw_run r;
    memset(&r, 0, sizeof r);
    if (!(ec = read_inputs(&a, &r)) && !(ec = compute(&a, &r)))
        ec = write_outputs(&a, &r);
    cli_matrix_free(&r.tel);
    cli_matrix_free(&r.trk);
    free(r.telc);
    free(r.trkc);
    free(r.dw);
    free(r.cov);
    free(r.klow);
    free(r.xcov);
    free(r.sigma);
    free(r.col);
    return ec;
}
