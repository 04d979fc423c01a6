/* igea envfun - environment-function matrix S of a trajectory file and a
 * list of error terms (METHODS 5). The term catalogue is the library's. */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

typedef struct {
    const char *traj, *terms, *epochs, *spec, *axes, *out;
    double step;
    int system, output, json, list;
} ef_args;

static ef_args A;

static const cli_opt options[] = {
    {"--traj", CLI_OPT_STR, &A.traj, NULL, "FILE", "the trajectory (required)", NULL},
    {"--terms", CLI_OPT_STR, &A.terms, NULL, "LIST", "comma-separated term names, 'default' (the 21-term\nmodel) or 'all' (required)", NULL},
    {"--list", CLI_OPT_FLAG, &A.list, NULL, NULL, "print the catalogue with default specs and units", NULL},
    {"--system", CLI_OPT_CHOICE, &A.system, "strapdown", CLI_CHOICES(IGEA_CHOICE_ENVFUN_SYSTEM), "the inertial system", NULL},
    {"--epochs", CLI_OPT_STR, &A.epochs, NULL, "FILE", "epoch times (s), non-decreasing, inside the trajectory", NULL},
    {"--epoch-step", CLI_OPT_NUM, &A.step, "1", "DT", "or one epoch every DT s after the first sample", NULL},
    {"--spec", CLI_OPT_STR, &A.spec, NULL, "default|FILE", "multiply the columns by 1-sigma specs (default: raw S)", NULL},
    {"--axes", CLI_OPT_STR, &A.axes, NULL, "I,I,I,S,S,S", "platform gyro input and spin axes (0..2; default\n0,1,2,1,2,0)", NULL},
    {"--output", CLI_OPT_CHOICE, &A.output, "velocity", CLI_CHOICES(IGEA_CHOICE_ENVFUN_OUTPUT),
     "the quantity (_g: with the point-mass gravity-gradient\ncoupling)", NULL},
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
"\n"
"options:\n",
options,
"\n"
"example:\n"
"  igea simulate --dir flight --save-traj        # writes flight/traj.txt, ...\n"
"  igea envfun --traj flight/traj.txt --terms acc_bias_x,gyro_bias_y,att0_z \\\n"
"      --epoch-step 1 --out S3.txt\n"
"  igea envfun --traj flight/traj.txt --terms default --out S.txt\n"};

static void list_terms(FILE *f)
{
    fprintf(f, "%-14s %-10s %-12s %s\n", "term", "systems", "default spec", "unit");
    for (int k = 0; k < IGEA_ENVFUN_TERM_COUNT; k++) {
        int sd = igea_envfun_term_valid(IGEA_ENVFUN_STRAPDOWN, k);
        int pf = igea_envfun_term_valid(IGEA_ENVFUN_PLATFORM, k);
        double spec = 0.0;
        igea_envfun_default_spec(sd ? IGEA_ENVFUN_STRAPDOWN : IGEA_ENVFUN_PLATFORM, k, &spec);
        fprintf(f, "%-14s %-10s %-12.5g %s\n", igea_envfun_term_name(k),
                sd && pf ? "both" : igea_choice_name(IGEA_CHOICE_ENVFUN_SYSTEM, sd ? IGEA_ENVFUN_STRAPDOWN : IGEA_ENVFUN_PLATFORM), spec, igea_envfun_term_unit(k));
    }
}

/* igea_envfun_compute's arguments 3 (the trajectory), 7 (the axes) and 9
 * (the epochs). */
#define ARG_TRAJ (-3)
#define ARG_AXES (-7)
#define ARG_EPOCHS (-9)

typedef struct {
    int *codes, nt, nsamp, nep, m, axes[6];
    double *traj, *ep, *spec, *S; /* S row-major */
    char *header;
} ef_run;

static int read_inputs(const ef_args *a, ef_run *r)
{
    int ec;
    if (a->axes && sscanf(a->axes, "%d,%d,%d,%d,%d,%d", &r->axes[0], &r->axes[1], &r->axes[2], &r->axes[3],
               &r->axes[4], &r->axes[5]) != 6) {
        cli_error("--axes: six comma-separated axis numbers 0..2");
        return CLI_USAGE;
    }
    if ((ec = cli_parse_terms(a->system, a->terms, &r->codes, &r->nt)) ||
        (ec = cli_read_traj(a->traj, &r->traj, &r->nsamp)) ||
        (ec = cli_epochs(a->epochs, a->step, r->traj[0], r->traj[r->nsamp - 1], &r->ep, &r->nep)))
        return ec;
    if (a->spec && (ec = cli_term_specs(a->system, r->codes, r->nt, a->spec, &r->spec)))
        return ec;
    r->m = 3 * r->nep;
    if (!(r->header = cli_term_header(r->codes, r->nt)))
        return cli_oom("the header");
    return CLI_OK;
}

static int compute(const ef_args *a, ef_run *r)
{
    int m = r->m, nt = r->nt;
    double *S = malloc(sizeof(double) * (size_t)m * nt);
    if (!S)
        return cli_oom("S");
    int st = igea_envfun_compute(a->system, r->nsamp, r->traj, r->nsamp, nt,
                                 r->codes, a->axes ? r->axes : NULL, r->nep, r->ep, r->spec,
                                 a->output, S, m);
    int ec = CLI_OK;
    if (st == ARG_EPOCHS) {
        cli_error("envfun: the epochs must be non-decreasing and inside [%g, %g] s", r->traj[0],
                  r->traj[r->nsamp - 1]);
        ec = CLI_DATAERR;
    } else if (st == ARG_TRAJ) {
        cli_error("%s: the time column must be strictly increasing", a->traj);
        ec = CLI_DATAERR;
    } else if (st == ARG_AXES) {
        cli_error("--axes: axis numbers are 0, 1, 2");
        ec = CLI_USAGE;
    } else {
        ec = cli_status(st, "envfun");
    }
    if (!ec && !(r->S = cli_rowmajor(S, m, nt)))
        ec = cli_oom("S");
    free(S);
    return ec;
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
                          r->S, r->m, r->nt, r->header);
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, stdout);
        cli_jint(&j, "rows", r->m);
        cli_jterms(&j, "terms", r->codes, r->nt);
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
        fprintf(stderr, "igea envfun: %d epochs x 3 axes, %d terms -> %s\n", r->nep, r->nt, a->out);
    return CLI_OK;
}

static void write_stdout(FILE *f, const ef_args *a, const ef_run *r)
{
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, f);
        cli_jterms(&j, "terms", r->codes, r->nt);
        cli_jrows(&j, "S", r->S, r->m, r->nt);
        cli_json_end(&j);
    } else {
        cli_write_matrix_body(f, 0, r->S, r->m, r->nt, r->header);
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
    if (!a.traj || !a.terms) {
        cli_error("envfun: --traj FILE and --terms are required (see --help)");
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
    return ec;
}
