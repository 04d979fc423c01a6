/* igea envfun - environment-function matrix S of a trajectory file and a
 * list of error terms (METHODS 5). The term catalogue is the library's. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

typedef struct {
    const char *traj, *terms, *epochs, *spec, *axes, *out, *term_file;
    double step, lat, lon, height, azimuth;
    int system, output, json, list, given_lat, given_lon, given_h, given_az;
} ef_args;

static ef_args A;

static const cli_opt options[] = {
    {"--traj", CLI_OPT_STR, &A.traj, NULL, "FILE", "the trajectory (required)", NULL},
    {"--terms", CLI_OPT_STR, &A.terms, NULL, "LIST", "comma-separated term names, 'default' (the 21-term\nmodel) or 'all' (required unless --term-file)", NULL},
    {"--term-file", CLI_OPT_STR, &A.term_file, NULL, "NAME=FILE,...", "user-defined terms: FILE rows 't u_x u_y u_z' at the\ntrajectory's samples, the unit error in instrument\naxes; NAME acc_* a specific-force error (m/s^2),\ngyro_* a rate or drift error (rad/s); columns after\n--terms", NULL},
    {"--list", CLI_OPT_FLAG, &A.list, NULL, NULL, "print the catalogue with default specs and units", NULL},
    {"--system", CLI_OPT_CHOICE, &A.system, "strapdown", CLI_CHOICES(IGEA_CHOICE_ENVFUN_SYSTEM), "the inertial system", NULL},
    {"--epochs", CLI_OPT_STR, &A.epochs, NULL, "FILE", "epoch times (s), non-decreasing, inside the trajectory", NULL},
    {"--epoch-step", CLI_OPT_NUM, &A.step, "1", "DT", "or one epoch every DT s after the first sample", NULL},
    {"--spec", CLI_OPT_STR, &A.spec, NULL, "default|FILE", "multiply the columns by 1-sigma specs (default: raw S)", NULL},
    {"--axes", CLI_OPT_STR, &A.axes, NULL, "I,I,I,S,S,S", "platform gyro input and spin axes (0..2; default\n0,1,2,1,2,0)", NULL},
    {"--output", CLI_OPT_CHOICE, &A.output, "velocity", CLI_CHOICES(IGEA_CHOICE_ENVFUN_OUTPUT),
     "the quantity (_g: with the gravity-gradient coupling,\npoint mass; J2 along the flown path with --lat,\n--lon, --azimuth)", NULL},
    {"--lat", CLI_OPT_NUM, &A.lat, NULL, "DEG", "the stated launch point (as igea dw's): latitude;\nwith --lon, --azimuth the launch-point terms pos0_*\nalso hold the pad velocity's error (docs/envfun.md)", &A.given_lat},
    {"--lon", CLI_OPT_NUM, &A.lon, NULL, "DEG", "its longitude", &A.given_lon},
    {"--height", CLI_OPT_NUM, &A.height, "0", "M", "its ellipsoidal height", &A.given_h},
    {"--azimuth", CLI_OPT_NUM, &A.azimuth, NULL, "DEG", "the firing azimuth, from north toward east", &A.given_az},
    {"--out", CLI_OPT_STR, &A.out, NULL, "FILE", "write S there (text with a '# names' header, or .npy)", NULL},
    {"--json", CLI_OPT_FLAG, &A.json, NULL, NULL, "machine-readable summary (with --out) or S as JSON", NULL},
    CLI_END};

static const cli_command command = {"envfun",
"usage: igea envfun --traj FILE --terms LIST [options]\n"
"\n"
"Environment-function matrix S of a flight (METHODS 5): column j holds the\n"
"change of the apparent velocity (launch-inertial frame) per unit of error\n"
"coefficient j, at each tracking epoch, rows epoch-major (x, y, z of epoch 0,\n"
"then epoch 1, ...). This is the S that 'igea eqerr' reads.\n"
"\n"
"The trajectory: text or .npy, one row per telemetry sample:\n"
"  t f_x f_y f_z w_x w_y w_z q0 q1 q2 q3\n"
"  (s, m/s^2, rad/s; specific force and rate in body axes for strapdown, force\n"
"  in launch-inertial axes for a platform, whose rate columns are ignored;\n"
"  q the attitude body -> launch-inertial, scalar first).\n"
"Integration is by the trapezoid rule at the telemetry rate (>= 10 Hz\n"
"recommended), then linear interpolation to the epochs.\n"
"'--terms all' is every term of the system (74 platform terms: the model of\n"
"seed 000; 86 strapdown). With --spec default a user term's spec is 1 (its\n"
"file holds the 1-sigma error).\n"
"\n"
"options:\n",
options,
"\n"
"example:\n"
"  igea simulate --dir flight --save-traj        # writes flight/traj.txt, ...\n"
"  igea envfun --traj flight/traj.txt --terms acc_bias_x,gyro_bias_y,att0_z \\\n"
"      --epoch-step 1 --out S3.txt\n"
"  igea envfun --traj flight/traj.txt --terms default --out S.txt\n"
"  igea envfun --traj flight/traj.txt --terms default \\\n"
"      --term-file acc_thermal=thermal.txt --out S22.txt\n"};

static void list_terms(FILE *f)
{
    fprintf(f, "%-14s %-10s %-12s %-16s %s\n", "term", "systems", "default spec", "unit",
            "equation");
    for (int k = 0; k < igea_envfun_term_count(); k++) {
        int sd = igea_envfun_term_valid(IGEA_ENVFUN_STRAPDOWN, k);
        int pf = igea_envfun_term_valid(IGEA_ENVFUN_PLATFORM, k);
        if (!sd && !pf)
            continue;
        double spec = 0.0;
        igea_envfun_default_spec(sd ? IGEA_ENVFUN_STRAPDOWN : IGEA_ENVFUN_PLATFORM, k, &spec);
        fprintf(f, "%-14s %-10s %-12.5g %-16s %s\n", igea_envfun_term_name(k),
                sd && pf ? "both" : igea_choice_name(IGEA_CHOICE_ENVFUN_SYSTEM, sd ? IGEA_ENVFUN_STRAPDOWN : IGEA_ENVFUN_PLATFORM), spec, igea_envfun_term_unit(k),
                igea_envfun_term_formula(k));
    }
}

/* igea_envfun_compute_user's arguments 3 (the trajectory), 7 (the axes)
 * and 13 (the epochs). */
#define ARG_TRAJ (-3)
#define ARG_AXES (-7)
#define ARG_EPOCHS (-13)

typedef struct {
    int *codes, nt, nsamp, nep, m, axes[6], nu, *ukind;
    double *traj, *ep, *spec, *S; /* S row-major */
    double *user;                 /* nsamp x 3 nu column-major */
    double site[IGEA_NAV_SITE_LEN];
    int has_site;
    char *header, *ubuf;          /* ubuf: the NAME=FILE list, split */
    const char **names;           /* nt + nu column names */
} ef_run;

/* One NAME=FILE of --term-file into user term i: the kind from the name,
 * the unit error from the file (t matching the trajectory's samples). */
static int read_user_term(ef_run *r, int i, char *item)
{
    char *eq = strchr(item, '=');
    const char *name = item, *file = eq ? eq + 1 : NULL;
    if (eq)
        *eq = '\0';
    int kind = !strncmp(name, "acc_", 4) ? IGEA_ENVFUN_USER_ACC
               : !strncmp(name, "gyro_", 5) ? IGEA_ENVFUN_USER_GYRO : -1;
    if (!file || !*file || kind < 0 || strspn(name, "abcdefghijklmnopqrstuvwxyz0123456789_") != strlen(name) ||
        igea_envfun_term_code(IGEA_ENVFUN_STRAPDOWN, name) >= 0 ||
        igea_envfun_term_code(IGEA_ENVFUN_PLATFORM, name) >= 0) {
        cli_error("--term-file: '%s': NAME=FILE with NAME acc_* or gyro_* (lower case, digits, '_'), "
                  "not a catalogue term", name);
        return CLI_USAGE;
    }
    cli_matrix m;
    int ec = cli_read_matrix(file, &m);
    if (ec)
        return ec;
    if (m.cols != 4 || m.rows != r->nsamp) {
        cli_error("%s: a user term has 4 columns (t u_x u_y u_z) and one row per trajectory "
                  "sample (%d); found %ld x %d", file, r->nsamp, m.rows, m.cols);
        cli_matrix_free(&m);
        return CLI_DATAERR;
    }
    for (long k = 0; k < m.rows; k++) {
        double t = r->traj[k];
        if (!(fabs(m.v[4 * k] - t) <= 1e-9 * fmax(1.0, fabs(t)))) {
            cli_error("%s:%ld:1: t = %.17g is not the trajectory's sample time %.17g", file, k + 1,
                      m.v[4 * k], t);
            cli_matrix_free(&m);
            return CLI_DATAERR;
        }
        for (int a = 0; a < 3; a++)
            r->user[k + (size_t)r->nsamp * (3 * (size_t)i + a)] = m.v[4 * k + 1 + a];
    }
    cli_matrix_free(&m);
    r->ukind[i] = kind;
    r->names[r->nt + i] = name;
    return CLI_OK;
}

static int read_user_terms(const char *list, ef_run *r)
{
    int n = 1;
    for (const char *p = list; *p; p++)
        n += *p == ',';
    if (!(r->ubuf = malloc(strlen(list) + 1)) || !(r->ukind = malloc(sizeof(int) * (size_t)n)) ||
        !(r->user = malloc(sizeof(double) * 3 * (size_t)n * (size_t)r->nsamp)) ||
        !(r->names = malloc(sizeof(char *) * (size_t)(r->nt + n))))
        return cli_oom("the user terms");
    strcpy(r->ubuf, list);
    for (int j = 0; j < r->nt; j++)
        r->names[j] = igea_envfun_term_name(r->codes[j]);
    char *item = r->ubuf;
    for (int i = 0; i < n; i++) {
        char *c = strchr(item, ',');
        if (c)
            *c = '\0';
        int ec = read_user_term(r, i, item);
        if (ec)
            return ec;
        for (int k = 0; k < r->nt + i; k++)
            if (!strcmp(r->names[k], r->names[r->nt + i])) {
                cli_error("--term-file: '%s' named twice", r->names[k]);
                return CLI_USAGE;
            }
        item = c ? c + 1 : item;
    }
    r->nu = n;
    return CLI_OK;
}

/* --spec: the catalogue's specs and 1 for user terms (default), or a
 * file of one per column. */
static int read_specs(const ef_args *a, ef_run *r)
{
    if (strcmp(a->spec, "default"))
        return cli_read_vector(a->spec, r->nt + r->nu, "one spec per term", &r->spec, NULL);
    if (!(r->spec = malloc(sizeof(double) * (size_t)(r->nt + r->nu))))
        return cli_oom("the term specs");
    for (int j = 0; j < r->nt + r->nu; j++)
        r->spec[j] = 1.0;
    for (int j = 0; j < r->nt; j++)
        igea_envfun_default_spec(a->system, r->codes[j], &r->spec[j]);
    return CLI_OK;
}

/* "name name ..." of the columns. */
static char *column_header(const ef_run *r)
{
    if (!r->nu)
        return cli_term_header(r->codes, r->nt);
    size_t len = 1;
    for (int j = 0; j < r->nt + r->nu; j++)
        len += strlen(r->names[j]) + 1;
    char *h = malloc(len);
    if (!h)
        return NULL;
    h[0] = '\0';
    for (int j = 0; j < r->nt + r->nu; j++) {
        if (j)
            strcat(h, " ");
        strcat(h, r->names[j]);
    }
    return h;
}

/* The stated launch point of --lat, --lon, --height, --azimuth (all or
 * none of lat, lon, azimuth). */
static int read_site(const ef_args *a, ef_run *r)
{
    const double deg = 3.14159265358979323846 / 180.0;
    int n = a->given_lat + a->given_lon + a->given_az;
    r->has_site = n == 3;
    if (n == 0 && !a->given_h)
        return CLI_OK;
    if (n != 3) {
        cli_error("--lat, --lon, --azimuth: give all three (the stated launch point) or none");
        return CLI_USAGE;
    }
    if (igea_nav_site(a->lat * deg, a->lon * deg, a->height, a->azimuth * deg, r->site)) {
        cli_error("--lat, --lon, --height, --azimuth: |lat| < 90, height > -6e6 m");
        return CLI_USAGE;
    }
    return CLI_OK;
}

static int read_inputs(const ef_args *a, ef_run *r)
{
    int ec;
    if (a->axes && sscanf(a->axes, "%d,%d,%d,%d,%d,%d", &r->axes[0], &r->axes[1], &r->axes[2], &r->axes[3],
               &r->axes[4], &r->axes[5]) != 6) {
        cli_error("--axes: six comma-separated axis numbers 0..2");
        return CLI_USAGE;
    }
    if ((a->terms && (ec = cli_parse_terms(a->system, a->terms, &r->codes, &r->nt))) ||
        (ec = cli_read_traj(a->traj, &r->traj, &r->nsamp)) ||
        (ec = cli_epochs(a->epochs, a->step, r->traj[0], r->traj[r->nsamp - 1], &r->ep, &r->nep)))
        return ec;
    if (a->term_file && (ec = read_user_terms(a->term_file, r)))
        return ec;
    if (a->spec && (ec = read_specs(a, r)))
        return ec;
    if ((ec = read_site(a, r)))
        return ec;
    r->m = 3 * r->nep;
    if (!(r->header = column_header(r)))
        return cli_oom("the header");
    return CLI_OK;
}

static int compute(const ef_args *a, ef_run *r)
{
    int m = r->m, nt = r->nt + r->nu;
    double *S = malloc(sizeof(double) * (size_t)m * nt);
    if (!S)
        return cli_oom("S");
    int st = igea_envfun_compute_site(a->system, r->nsamp, r->traj, r->nsamp, r->nt, r->codes,
                                      a->axes ? r->axes : NULL, r->nu, r->ukind, r->user,
                                      r->nsamp, r->nep, r->ep, r->spec, a->output,
                                      r->has_site ? r->site : NULL, S, m);
    int ec = CLI_OK;
    if (st == ARG_EPOCHS) {
        cli_error("envfun: the epochs must be non-decreasing and inside [%g, %g] s", r->traj[0],
                  r->traj[r->nsamp - 1]);
        ec = CLI_DATAERR;
    } else if (st == ARG_TRAJ) {
        cli_error("%s: the time column must be strictly increasing", a->traj);
        ec = CLI_DATAERR;
    } else if (st == ARG_AXES) {
        cli_error("--axes: axis numbers are 0, 1, 2, and a gyro's input and spin axes differ "
                  "when a term reads its output axis");
        ec = CLI_USAGE;
    } else if (st == IGEA_ENONFINITE && r->nu) {
        cli_error("envfun: NaN or Inf in the trajectory, a --term-file, the epochs or the specs");
        ec = CLI_DATAERR;
    } else {
        ec = cli_status(st, "envfun");
    }
    if (!ec && !(r->S = cli_rowmajor(S, m, nt)))
        ec = cli_oom("S");
    free(S);
    return ec;
}

/* The "terms" key: the column names. */
static void json_terms(cli_json *j, const ef_run *r)
{
    if (r->nu)
        cli_jstrs(j, "terms", r->names, r->nt + r->nu);
    else
        cli_jterms(j, "terms", r->codes, r->nt);
}

/* S to --out, with a summary on standard output (checked before the file
 * is committed: a run whose summary is lost keeps the old file). */
static int write_file(const ef_args *a, const ef_run *r)
{
    cli_out o;
    int ec = cli_out_open(&o, a->out);
    if (ec)
        return ec;
    size_t len = strlen(a->out);
    cli_write_matrix_body(o.f, o.f != stdout && len >= 4 && !strcmp(a->out + len - 4, ".npy"),
                          r->S, r->m, r->nt + r->nu, r->header);
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, stdout);
        cli_jint(&j, "rows", r->m);
        json_terms(&j, r);
        cli_jstr(&j, "out", a->out);
        cli_json_end(&j);
        if ((ec = cli_stdout_check())) {
            cli_out_abort(&o);
            return ec;
        }
    }
    if ((ec = cli_out_commit(&o)))
        return ec;
    if (!a->json)
        fprintf(stderr, "igea envfun: %d epochs x 3 axes, %d terms -> %s\n", r->nep, r->nt + r->nu, a->out);
    return CLI_OK;
}

static void write_stdout(FILE *f, const ef_args *a, const ef_run *r)
{
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, f);
        json_terms(&j, r);
        cli_jrows(&j, "S", r->S, r->m, r->nt + r->nu);
        cli_json_end(&j);
    } else {
        cli_write_matrix_body(f, 0, r->S, r->m, r->nt + r->nu, r->header);
    }
}

int cmd_envfun(int argc, char **argv)
{
    int ec = cli_parse(&command, argc, argv);
    ef_args a = A;
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    if (a.list) {
        list_terms(stdout);
        return CLI_OK;
    }
    if (!a.traj || (!a.terms && !a.term_file)) {
        cli_error("envfun: --traj FILE and --terms (or --term-file) are required (see --help)");
        return CLI_USAGE;
    }
    ef_run r;
    memset(&r, 0, sizeof r);
    if (!(ec = read_inputs(&a, &r)) && !(ec = compute(&a, &r))) {
        if (a.out) {
            ec = write_file(&a, &r);
        } else {
            cli_out o;
            if (!(ec = cli_out_open(&o, NULL))) {
                write_stdout(o.f, &a, &r);
                ec = cli_out_commit(&o);
            }
        }
    }
    free(r.codes);
    free(r.traj);
    free(r.ep);
    free(r.spec);
    free(r.S);
    free(r.header);
    free(r.ubuf);
    free(r.ukind);
    free(r.user);
    free(r.names);
    return ec;
}
