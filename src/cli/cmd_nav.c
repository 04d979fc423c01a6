/* igea nav - navigation error propagation: the linearised INS error model
 * in local-level NED axes driven by accelerometer biases and gyro drifts
 * (include/igea/inserr.h, docs/inserr.md). */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

#define DEG (3.14159265358979323846 / 180.0)
#define NS IGEA_INSERR_N

typedef struct {
    const char *acc, *gyro, *out;
    double lat, duration, opts[IGEA_INSERR_OPT_LEN];
    int epochs, json;
} nv_args;

static nv_args A;

static const cli_opt options[] = {
    {"--lat", CLI_OPT_NUM, &A.lat, "0", "DEG", "latitude (degrees, |lat| <= 85.9)", NULL},
    {"--duration", CLI_OPT_NUM, &A.duration, "21600", "S", "length of the run (s)", NULL},
    {"--epochs", CLI_OPT_INT, &A.epochs, "361", "N", "output epochs, equally spaced from 0 to --duration", NULL},
    {"--step", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_STEP], CLI_DEF_LIB, "S", "longest Runge-Kutta step (s)", NULL},
    {"--acc-bias", CLI_OPT_STR, &A.acc, NULL, "N,E,D", "accelerometer biases along north, east, down\n(m/s^2, measured minus true; default 0)", NULL},
    {"--gyro-drift", CLI_OPT_STR, &A.gyro, NULL, "N,E,D", "gyro drifts about north, east, down (rad/s,\nmeasured minus true; default 0)", NULL},
    {"--radius", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_RADIUS], CLI_DEF_LIB, "R", "Earth radius (m)", NULL},
    {"--g", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_G], CLI_DEF_LIB, "G", "gravity (m/s^2)", NULL},
    {"--omega", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_OMEGA], CLI_DEF_LIB, "W", "Earth rate (rad/s; 0: none)", NULL},
    {"--vn", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_VN], CLI_DEF_LIB, "V", "north velocity of the vehicle (m/s)", NULL},
    {"--ve", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_VE], CLI_DEF_LIB, "V", "east velocity of the vehicle (m/s)", NULL},
    {"--vertical", CLI_OPT_NUM, &A.opts[IGEA_INSERR_OPT_VERTICAL], CLI_DEF_LIB, "0|1", "vertical channel: 0 aided (held), 1 free", NULL},
    CLI_JSON_OPT(&A.json),
    CLI_OUT_OPT(&A.out),
    CLI_END};

static const cli_command command = {"nav",
"usage: igea nav [--lat DEG] [--duration S] [--acc-bias N,E,D] [--gyro-drift N,E,D] [options]\n"
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
"  igea nav --lat 45 --acc-bias 1e-4,0,0 --json --out nav.json\n"};

static int read_triple(const char *opt, const char *arg, double *v)
{
    if (!arg)
        return CLI_OK;
    char **items;
    int n, ec = cli_split_list(arg, &items, &n);
    if (ec)
        return ec;
    if (n != 3) {
        cli_error("%s: %d numbers; three are needed (north,east,down)", opt, n);
        ec = CLI_USAGE;
    }
    for (int i = 0; i < n && !ec; i++)
        ec = cli_parse_double(opt, items[i], &v[i]);
    free(items);
    return ec;
}

static void json_report(FILE *f, const nv_args *a, const double *x0, const double *x)
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
    cli_json_end(&j);
}

static void text_report(FILE *f, const nv_args *a, const double *x)
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
}

int cmd_nav(int argc, char **argv)
{
    igea_inserr_defaults(A.opts);
    int ec = cli_parse(&command, argc, argv);
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    nv_args a = A;
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
    double *x = malloc(sizeof(double) * NS * (size_t)a.epochs);
    if (!x)
        return cli_oom("the error history");
    int st = igea_inserr_response(a.opts, x0, a.duration, a.epochs, x);
    if (st == -3) {
        cli_error("nav: --duration / --step exceeds 1e7 steps");
        ec = CLI_USAGE;
    } else if (st == IGEA_EOVERFLOW) {
        cli_error("nav: the errors overflow (a free vertical channel diverges; use --vertical 0)");
        ec = CLI_DATAERR;
    } else {
        ec = cli_status(st, "nav");
    }
    if (!ec) {
        cli_out o;
        if (!(ec = cli_out_open(&o, a.out))) {
            if (a.json)
                json_report(o.f, &a, x0, x);
            else
                text_report(o.f, &a, x);
            ec = cli_out_commit(&o);
        }
    }
    free(x);
    return ec;
}
