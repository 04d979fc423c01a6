/* igea nav - navigation error propagation: the linearised INS error model
 * in local-level NED axes driven by accelerometer biases and gyro drifts
 * (include/igea/inserr.h, docs/inserr.md). */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

#define DEG (3.14159265358979323846 / 180.0)
#define NS IGEA_INSERR_N

typedef struct {
    const char *acc, *gyro, *out, *noise[6]; /* acc N B K, gyro N B K */
    const char *plot;                        /* --plot FILE.svg */
    const char *telemetry, *q0, *pos0, *vel0, *att0;
    double lat, duration, opts[IGEA_INSERR_OPT_LEN], lon, height, azimuth;
    int epochs, json, system, gravity, every;
    /* given on the command line: the static model's options (STATIC_*) and
     * the trajectory's (TRAJ_*), each refused in the other mode */
    int given_static[9], given_traj[7];
} nv_args;

static nv_args A;

static const cli_opt options[] = {
    {"--lat", CLI_OPT_NUM, &A.lat, "0", "DEG", "latitude (degrees, |lat| <= 85.9)", NULL},
    {"--duration", CLI_OPT_NUM, &A.duration, "21600", "S", "length of the run (s)", &A.given_static[0]},
    {"--epochs", CLI_OPT_INT, &A.epochs, "361", "N", "output epochs, equally spaced from 0 to --duration", &A.given_static[1]},
    {"--step", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_STEP], CLI_DEF_LIB, "S", "longest Runge-Kutta step (s)", &A.given_static[2]},
    {"--acc-bias", CLI_OPT_STR, &A.acc, NULL, "N,E,D", "accelerometer biases along north, east, down\n(m/s^2, measured minus true; default 0)", NULL},
    {"--gyro-drift", CLI_OPT_STR, &A.gyro, NULL, "N,E,D", "gyro drifts about north, east, down (rad/s,\nmeasured minus true; default 0)", NULL},
    {"--radius", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_RADIUS], CLI_DEF_LIB, "R", "Earth radius (m)", &A.given_static[3]},
    {"--g", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_G], CLI_DEF_LIB, "G", "gravity (m/s^2)", &A.given_static[4]},
    {"--omega", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_OMEGA], CLI_DEF_LIB, "W", "Earth rate (rad/s; 0: none)", &A.given_static[5]},
    {"--vn", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_VN], CLI_DEF_LIB, "V", "north velocity of the vehicle (m/s)", &A.given_static[6]},
    {"--ve", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_VE], CLI_DEF_LIB, "V", "east velocity of the vehicle (m/s)", &A.given_static[7]},
    {"--vertical", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_VERTICAL], CLI_DEF_LIB, "0|1", "vertical channel: 0 aided (held), 1 free", &A.given_static[8]},
    CLI_HEAD("sensor noise (IEEE Std 952 coefficients, as igea stability --fit gives\n"
             "them for SI data; any of these adds the covariance to the report):"),
    {"--acc-vrw", CLI_OPT_STR, &A.noise[0], NULL, "N,E,D", "accelerometer white noise N, the velocity random\nwalk (m/s/sqrt(s))", NULL},
    {"--acc-bi", CLI_OPT_STR, &A.noise[1], NULL, "N,E,D", "accelerometer bias instability B (m/s^2): a\nGauss-Markov bias of correlation time --acc-tc", NULL},
    {"--acc-rrw", CLI_OPT_STR, &A.noise[2], NULL, "N,E,D", "accelerometer rate random walk K (m/s^2/sqrt(s))", NULL},
    {"--gyro-arw", CLI_OPT_STR, &A.noise[3], NULL, "N,E,D", "gyro white noise N, the angle random walk\n(rad/sqrt(s))", NULL},
    {"--gyro-bi", CLI_OPT_STR, &A.noise[4], NULL, "N,E,D", "gyro bias instability B (rad/s): a Gauss-Markov\ndrift of correlation time --gyro-tc", NULL},
    {"--gyro-rrw", CLI_OPT_STR, &A.noise[5], NULL, "N,E,D", "gyro rate random walk K (rad/s/sqrt(s))", NULL},
    {"--acc-tc", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_ACC_TC], CLI_DEF_LIB, "S", "accelerometer bias correlation time (s; 0: a\nconstant bias, which --acc-bi cannot use)", NULL},
    {"--gyro-tc", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_GYRO_TC], CLI_DEF_LIB, "S", "gyro drift correlation time (s; 0: constant)", NULL},
    CLI_HEAD("along a trajectory (launch-inertial frame; --lat is the launch latitude,\n"
             "--acc-bias, --gyro-drift and the noise are in instrument axes; with\n"
             "--acc-tc, --gyro-tc the bias states are Gauss-Markov):"),
    {"--telemetry", CLI_OPT_STR, &A.telemetry, NULL, "FILE", "error-free telemetry rows t dvx dvy dvz [dthx dthy\ndthz]: the reference trajectory the nav core flies", NULL},
    {"--lon", CLI_OPT_NUM, &A.lon, "0", "DEG", "longitude of the launch point", &A.given_traj[0]},
    {"--height", CLI_OPT_NUM, &A.height, "0", "M", "ellipsoidal height of the launch point", &A.given_traj[1]},
    {"--azimuth", CLI_OPT_NUM, &A.azimuth, "0", "DEG", "firing azimuth, from north toward east", &A.given_traj[2]},
    {"--system", CLI_OPT_CHOICE, &A.system, "strapdown", CLI_CHOICES(IGEA_CHOICE_ENVFUN_SYSTEM), "the inertial system", &A.given_traj[3]},
    {"--gravity", CLI_OPT_CHOICE, &A.gravity, "j2", CLI_CHOICES(IGEA_CHOICE_NAV_GRAVITY), "the navigation's gravity model", &A.given_traj[4]},
    {"--q0", CLI_OPT_STR, &A.q0, "1,0,0,0", "Q0,Q1,Q2,Q3", "strapdown attitude body -> launch-inertial at the\nrecord's start (scalar first)", &A.given_traj[5]},
    {"--pos0", CLI_OPT_STR, &A.pos0, NULL, "X,Y,Z", "initial position error in LI (m)", NULL},
    {"--vel0", CLI_OPT_STR, &A.vel0, NULL, "X,Y,Z", "initial velocity error in LI (m/s)", NULL},
    {"--att0", CLI_OPT_STR, &A.att0, NULL, "X,Y,Z", "initial attitude error in LI (rad)", NULL},
    {"--every", CLI_OPT_INT, &A.every, "1", "K", "output every K-th record (and the last)", &A.given_traj[6]},
    {"--plot", CLI_OPT_STR, &A.plot, NULL, "FILE.svg", "draw the position, velocity and attitude errors\nagainst time (with the noise options their +-1\nsigma bands) into an SVG picture", NULL},
    CLI_JSON_OPT(&A.json),
    CLI_OUT_OPT(&A.out),
    CLI_END};

static const cli_command command = {"nav",
"usage: igea nav [--lat DEG] [--duration S] [--acc-bias N,E,D] [--gyro-drift N,E,D] [options]\n"
"       igea nav --telemetry FILE --lat DEG --lon DEG --azimuth DEG [--acc-bias X,Y,Z] [options]\n"
"\n"
"The position, velocity and attitude errors of an inertial navigation system\n"
"at rest (or moving slowly at --vn, --ve) on a spherical Earth, from constant\n"
"accelerometer biases and gyro drifts resolved in north-east-down axes: the\n"
"linearised error model with the Schuler loop (84.4 min), the Earth-rate\n"
"coupling (Foucault modulation, the 24-h mode) and the vertical channel aided\n"
"or free, integrated by fixed-step Runge-Kutta.\n"
"\n"
"options:\n",
options,
"\n"
"example (a north accelerometer bias of 1e-4 m/s^2 and an east gyro drift of\n"
"0.01 deg/h at 45 N, over 6 h):\n"
"  igea nav --lat 45 --acc-bias 1e-4,0,0 --gyro-drift 0,4.85e-8,0\n"
"  igea nav --lat 45 --acc-bias 1e-4,0,0 --json --out nav.json\n"
"along a trajectory (telemetry rows t dv dth of the error-free flight):\n"
"  igea nav --telemetry tel.txt --lat 40 --lon 100 --azimuth 60 --acc-bias 1e-4,0,0\n"
"  igea nav --telemetry tel.txt --lat 40 --lon 100 --azimuth 60 --gyro-bi 5e-8,5e-8,5e-8 \\\n"
"      --gyro-tc 600 --acc-vrw 1e-4,1e-4,1e-4\n"
"and with gyro noise (ARW 1e-6 rad/sqrt(s), bias instability 5e-8 rad/s with\n"
"a 600-s correlation time):\n"
"  igea nav --lat 45 --gyro-arw 1e-6,1e-6,1e-6 --gyro-bi 5e-8,5e-8,5e-8 --gyro-tc 600\n"};

/* The options of one mode given in the other, in the order of given_static
 * and given_traj: refused (the mode would ignore them). */
static const char *const static_names[9] = {"--duration", "--epochs", "--step", "--radius",
                                            "--g", "--omega", "--vn", "--ve", "--vertical"};
static const char *const traj_names[10] = {"--lon", "--height", "--azimuth", "--system",
                                           "--gravity", "--q0", "--every", "--pos0",
                                           "--vel0", "--att0"};

static int check_mode(const nv_args *a)
{
    if (a->telemetry) {
        for (int i = 0; i < 9; i++)
            if (a->given_static[i]) {
                cli_error("nav --telemetry: %s is of the static model (along a trajectory the "
                          "Earth is the nav core's and the epochs are the record's)",
                          static_names[i]);
                return CLI_USAGE;
            }
        return CLI_OK;
    }
    const char *s3[3] = {a->pos0, a->vel0, a->att0};
    for (int i = 0; i < 10; i++)
        if (i < 7 ? a->given_traj[i] : s3[i - 7] != NULL) {
            cli_error("nav: %s is of the model along a trajectory: it needs --telemetry",
                      traj_names[i]);
            return CLI_USAGE;
        }
    return CLI_OK;
}

static int read_triple(const char *opt, const char *arg, double *v)
{
    if (!arg)
        return CLI_OK;
    char **items;
    int n, ec = cli_split_list(arg, &items, &n);
    if (ec)
        return ec;
    if (n != 3) {
        cli_error("%s: %d numbers; three are needed", opt, n);
        ec = CLI_USAGE;
    }
    for (int i = 0; i < n && !ec; i++)
        ec = cli_parse_double(opt, items[i], &v[i]);
    free(items);
    return ec;
}

static void json_report(FILE *f, const nv_args *a, const double *x0, const double *x,
                        const double *P)
{
    cli_json j;
    cli_json_begin(&j, f);
    cli_jnum(&j, "lat", a->lat);
    cli_jnum(&j, "duration", a->duration);
    cli_jnums(&j, "acc_bias", x0 + IGEA_INSERR_ACC, 3);
    cli_jnums(&j, "gyro_drift", x0 + IGEA_INSERR_GYRO, 3);
    cli_json_open(&j, "time", '[');
    for (int k = 0; k < a->epochs; k++)
        cli_jnum(&j, NULL, k * a->duration / (a->epochs - 1));
    cli_json_close(&j);
    cli_jmatrix(&j, "position", x + IGEA_INSERR_POS, NULL, a->epochs, 3, NS, 1);
    cli_jmatrix(&j, "velocity", x + IGEA_INSERR_VEL, NULL, a->epochs, 3, NS, 1);
    cli_jmatrix(&j, "attitude", x + IGEA_INSERR_ATT, NULL, a->epochs, 3, NS, 1);
    if (P) {
        cli_json_open(&j, "covariance", '[');
        for (int k = 0; k < a->epochs; k++)
            cli_jmatrix(&j, NULL, P + (size_t)k * NS * NS, NULL, NS, NS, NS, 1);
        cli_json_close(&j);
    }
    cli_json_end(&j);
}

static void text_variances(FILE *f, const nv_args *a, const double *P)
{
    fprintf(f, "# variances of the errors from the sensor noise (NED; m^2, (m/s)^2, rad^2)\n");
    fprintf(f, "# %10s %14s %14s %14s %12s %12s %12s %12s %12s %12s\n", "t", "var_dN",
            "var_dE", "var_dD", "var_dvN", "var_dvE", "var_dvD", "var_phiN", "var_phiE",
            "var_phiD");
    for (int k = 0; k < a->epochs; k++) {
        const double *Pk = P + (size_t)k * NS * NS;
        fprintf(f, "%12.3f", k * a->duration / (a->epochs - 1));
        for (int i = 0; i < 9; i++)
            fprintf(f, i < 3 ? " %14.6g" : " %12.5g", Pk[i * NS + i]);
        fprintf(f, "\n");
    }
}

static void text_report(FILE *f, const nv_args *a, const double *x, const double *P)
{
    fprintf(f, "# INS errors at latitude %g deg (NED; m, m/s, rad)\n", a->lat);
    fprintf(f, "# %10s %14s %14s %14s %12s %12s %12s %12s %12s %12s\n", "t", "dN", "dE",
            "dD", "dvN", "dvE", "dvD", "phiN", "phiE", "phiD");
    for (int k = 0; k < a->epochs; k++) {
        const double *xk = x + (size_t)k * NS;
        fprintf(f, "%12.3f", k * a->duration / (a->epochs - 1));
        for (int i = 0; i < 9; i++)
            fprintf(f, i < 3 ? " %14.6g" : " %12.5g", xk[i]);
        fprintf(f, "\n");
    }
    if (P)
        text_variances(f, a, P);
}

/* The noise triples: 0 and *any = 1 when one was given. */
static int read_noise(const nv_args *a, double *acc, double *gyro, int *any)
{
    static const char *const names[6] = {"--acc-vrw", "--acc-bi", "--acc-rrw",
                                         "--gyro-arw", "--gyro-bi", "--gyro-rrw"};
    static const int slot[3] = {IGEA_INSERR_NOISE_N, IGEA_INSERR_NOISE_B, IGEA_INSERR_NOISE_K};
    int ec = CLI_OK;
    *any = 0;
    for (int i = 0; i < 6 && !ec; i++) {
        *any |= a->noise[i] != NULL;
        ec = read_triple(names[i], a->noise[i], (i < 3 ? acc : gyro) + slot[i % 3]);
    }
    for (int i = 0; i < 6 && !ec; i++)
        for (int k = 0; k < 3; k++)
            if (((i < 3 ? acc : gyro)[slot[i % 3] + k]) < 0) {
                cli_error("%s: the coefficients must not be negative", names[i]);
                return CLI_USAGE;
            }
    if (!ec && (a->noise[1] && !(a->opts[IGEA_INSERR_OPT_ACC_TC] > 0))) {
        cli_error("--acc-bi: needs --acc-tc (the correlation time of the Gauss-Markov bias)");
        ec = CLI_USAGE;
    }
    if (!ec && (a->noise[4] && !(a->opts[IGEA_INSERR_OPT_GYRO_TC] > 0))) {
        cli_error("--gyro-bi: needs --gyro-tc (the correlation time of the Gauss-Markov drift)");
        ec = CLI_USAGE;
    }
    return ec;
}

/* ---- along a trajectory ------------------------------------------------ */

typedef struct {
    double *tel, *ep, *x, *P, site[IGEA_NAV_SITE_LEN], q0[4], x0[NS];
    double acc[IGEA_INSERR_NOISE_LEN], gyro[IGEA_INSERR_NOISE_LEN];
    int n, cols, ne, noisy;
} nv_traj;

static void traj_json(FILE *f, const nv_args *a, const nv_traj *r)
{
    cli_json j;
    cli_json_begin(&j, f);
    cli_jstr(&j, "system", a->system == IGEA_ENVFUN_STRAPDOWN ? "strapdown" : "platform");
    cli_jnums(&j, "time", r->ep, r->ne);
    cli_jmatrix(&j, "position", r->x + IGEA_INSERR_POS, NULL, r->ne, 3, NS, 1);
    cli_jmatrix(&j, "velocity", r->x + IGEA_INSERR_VEL, NULL, r->ne, 3, NS, 1);
    cli_jmatrix(&j, "attitude", r->x + IGEA_INSERR_ATT, NULL, r->ne, 3, NS, 1);
    if (r->P) {
        cli_json_open(&j, "covariance", '[');
        for (int k = 0; k < r->ne; k++)
            cli_jmatrix(&j, NULL, r->P + (size_t)k * NS * NS, NULL, NS, NS, NS, 1);
        cli_json_close(&j);
    }
    cli_json_end(&j);
}

static void traj_text(FILE *f, const nv_traj *r)
{
    fprintf(f, "# INS errors along the trajectory (launch-inertial x y z; m, m/s, rad)\n");
    fprintf(f, "# %10s %14s %14s %14s %12s %12s %12s %12s %12s %12s\n", "t", "dx", "dy", "dz",
            "dvx", "dvy", "dvz", "phix", "phiy", "phiz");
    for (int k = 0; k < r->ne; k++) {
        fprintf(f, "%12.3f", r->ep[k]);
        for (int i = 0; i < 9; i++)
            fprintf(f, i < 3 ? " %14.6g" : " %12.5g", r->x[(size_t)k * NS + i]);
        fprintf(f, "\n");
    }
    for (int k = 0; r->P && k < r->ne; k++) {
        if (!k)
            fprintf(f, "# variances of the errors from the sensor noise\n# %10s %14s %14s "
                       "%14s %12s %12s %12s %12s %12s %12s\n", "t", "var_dx", "var_dy",
                    "var_dz", "var_dvx", "var_dvy", "var_dvz", "var_phix", "var_phiy",
                    "var_phiz");
        fprintf(f, "%12.3f", r->ep[k]);
        for (int i = 0; i < 9; i++)
            fprintf(f, i < 3 ? " %14.6g" : " %12.5g", r->P[(size_t)k * NS * NS + i * (NS + 1)]);
        fprintf(f, "\n");
    }
}

/* The inputs of the trajectory mode: site, q0, the errors, the noise
 * coefficients (bias instability: the Gauss-Markov states of --acc-tc,
 * --gyro-tc), epochs. */
static int traj_inputs(const nv_args *a, nv_traj *r)
{
    int ec;
    if ((ec = cli_check_opts("nav", IGEA_MODULE_INSERR, igea_inserr_check_opts(a->opts))))
        return ec;
    if (a->every < 1)
        return cli_usage("nav: --every must be at least 1");
    if (igea_nav_site(a->lat * DEG, a->lon * DEG, a->height, a->azimuth * DEG, r->site))
        return cli_usage("nav: --lat, --lon, --height or --azimuth out of range");
    if (sscanf(a->q0, "%lf,%lf,%lf,%lf", &r->q0[0], &r->q0[1], &r->q0[2], &r->q0[3]) != 4)
        return cli_usage("--q0: four comma-separated numbers");
    if ((ec = read_triple("--pos0", a->pos0, r->x0)) ||
        (ec = read_triple("--vel0", a->vel0, r->x0 + 3)) ||
        (ec = read_triple("--att0", a->att0, r->x0 + 6)) ||
        (ec = read_triple("--acc-bias", a->acc, r->x0 + IGEA_INSERR_ACC)) ||
        (ec = read_triple("--gyro-drift", a->gyro, r->x0 + IGEA_INSERR_GYRO)))
        return ec;
    if ((ec = read_noise(a, r->acc, r->gyro, &r->noisy)))
        return ec;
    if ((ec = cli_read_colmajor(a->telemetry, &r->tel, &r->n, &r->cols)))
        return ec;
    int need = a->system == IGEA_ENVFUN_STRAPDOWN ? 7 : 4;
    if (r->cols != need || r->n < 2) {
        cli_error("%s: %d columns; the %s telemetry has %d (t dv%s), at least 2 rows",
                  a->telemetry, r->cols, need == 7 ? "strapdown" : "platform", need,
                  need == 7 ? " dth" : "");
        return CLI_DATAERR;
    }
    r->ne = (r->n - 1) / a->every + 1 + ((r->n - 1) % a->every ? 1 : 0);
    if (!(r->ep = malloc(sizeof(double) * (size_t)r->ne)))
        return cli_oom("the epochs");
    for (int k = 0; k < r->ne; k++)
        r->ep[k] = r->tel[k == r->ne - 1 ? (size_t)r->n - 1 : (size_t)k * a->every];
    return CLI_OK;
}

static int traj_run(const nv_args *a, nv_traj *r)
{
    if (!(r->x = malloc(sizeof(double) * NS * (size_t)r->ne)) ||
        (r->noisy && !(r->P = malloc(sizeof(double) * NS * NS * (size_t)r->ne))))
        return cli_oom("the error history");
    int st = igea_inserr_li_response_opts(a->system, r->site, a->gravity, a->opts, r->n, r->tel,
                                          r->n, r->q0, NULL, NULL, r->x0, r->ne, r->ep, r->x);
    if (!st && r->P)
        st = igea_inserr_li_noise_covariance(a->system, r->site, a->gravity, a->opts, r->n,
                                             r->tel, r->n, r->q0, NULL, NULL, NULL, r->acc,
                                             r->gyro, r->ne, r->ep, r->P);
    if (st == -6) {
        cli_error("%s: the times must increase strictly", a->telemetry);
        return CLI_DATAERR;
    }
    if (st == -8) {
        cli_error("--q0: a non-zero quaternion");
        return CLI_USAGE;
    }
    return cli_status(st, "nav --telemetry");
}

static int nav_trajectory(const nv_args *a)
{
    nv_traj r;
    memset(&r, 0, sizeof r);
    int ec = traj_inputs(a, &r);
    if (!ec)
        ec = traj_run(a, &r);
    if (!ec && a->plot) { /* the picture first: on its failure no report */
        char what[160];
        snprintf(what, sizeof what, "along %s, launch-inertial axes", a->telemetry);
        ec = cli_svg_nav(a->plot, what, 1, r.ne, r.ep, 0, r.x, r.P);
    }
    if (!ec) {
        cli_out o;
        if (!(ec = cli_out_open(&o, a->out))) {
            if (a->json)
                traj_json(o.f, a, &r);
            else
                traj_text(o.f, &r);
            ec = cli_out_commit(&o);
        }
    }
    free(r.tel);
    free(r.ep);
    free(r.x);
    free(r.P);
    return ec;
}

int cmd_nav(int argc, char **argv)
{
    igea_inserr_defaults(A.opts);
    int ec = cli_parse(&command, argc, argv);
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    nv_args a = A;
    if ((ec = check_mode(&a)))
        return ec;
    if (a.telemetry)
        return nav_trajectory(&a);
    if (!(fabs(a.lat) <= 85.9))
        return cli_usage("nav: --lat must lie in [-85.9, 85.9] degrees");
    if (!(a.duration > 0))
        return cli_usage("nav: --duration must be positive");
    if (a.epochs < 2)
        return cli_usage("nav: --epochs must be at least 2");
    a.opts[IGEA_INSERR_OPT_LAT] = a.lat * DEG;
    if ((ec = cli_check_opts("nav", IGEA_MODULE_INSERR, igea_inserr_check_opts(a.opts))))
        return ec;
    double x0[NS] = {0};
    if ((ec = read_triple("--acc-bias", a.acc, x0 + IGEA_INSERR_ACC)) ||
        (ec = read_triple("--gyro-drift", a.gyro, x0 + IGEA_INSERR_GYRO)))
        return ec;
    double acc[IGEA_INSERR_NOISE_LEN] = {0}, gyro[IGEA_INSERR_NOISE_LEN] = {0};
    int noisy;
    if ((ec = read_noise(&a, acc, gyro, &noisy)))
        return ec;
    double *x = malloc(sizeof(double) * NS * (size_t)a.epochs), *P = NULL;
    if (noisy && x && !(P = malloc(sizeof(double) * NS * NS * (size_t)a.epochs))) {
        free(x);
        x = NULL;
    }
    if (!x)
        return cli_oom("the error history");
    int st = igea_inserr_response(a.opts, x0, a.duration, a.epochs, x);
    if (!st && P)
        st = igea_inserr_noise_covariance(a.opts, NULL, acc, gyro, a.duration, a.epochs, P);
    if (st == -3) {
        cli_error("nav: --duration / --step exceeds 1e7 steps");
        ec = CLI_USAGE;
    } else if (st == IGEA_EOVERFLOW) {
        cli_error("nav: the errors overflow (a free vertical channel diverges; use --vertical 0)");
        ec = CLI_DATAERR;
    } else {
        ec = cli_status(st, "nav");
    }
    if (!ec && a.plot) { /* the picture first: on its failure no report */
        char what[96];
        snprintf(what, sizeof what, "latitude %g deg, north east down", a.lat);
        ec = cli_svg_nav(a.plot, what, 0, a.epochs, NULL, a.duration / (a.epochs - 1), x, P);
    }
    if (!ec) {
        cli_out o;
        if (!(ec = cli_out_open(&o, a.out))) {
            if (a.json)
                json_report(o.f, &a, x0, x, P);
            else
                text_report(o.f, &a, x, P);
            ec = cli_out_commit(&o);
        }
    }
    free(P);
    free(x);
    return ec;
}
