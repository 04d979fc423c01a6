/* igea simulate - a synthetic flight test: trajectory -> S -> dw, written
 * as the files 'igea eqerr' reads. Also the model options that the
 * montecarlo command shares (simmodel_*). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

/* cmd_envfun.c */
double envfun_default_spec(int code);
const char *envfun_term_name(int code);
int envfun_parse_terms(int system, const char *list, int **codes, int *n);
int envfun_parse_system(const char *s, int *system);
int envfun_read_traj(const char *path, double **traj, int *nsamp);
char *envfun_header(const int *codes, int n);
int envfun_epochs(const char *file, double step, double t0, double t1, double **ep, int *n);

typedef struct {
    /* options */
    const char *traj_file, *terms, *epochs_file, *spec_file, *xlist;
    double duration, rate, step, sigma0, sigma_growth;
    int system, seed;
    double opts[IGEA_SIM_OPT_LEN];
    /* built */
    double *traj, *ep, *S, *sigma, *spec, *xval;
    int *codes, *xfix, nsamp, nep, m, N;
} simmodel;

void *simmodel_new(void)
{
    simmodel *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->terms = "default";
    s->duration = 120.0;
    s->rate = 50.0;
    s->step = 1.0;
    s->sigma0 = 0.01;
    s->system = IGEA_ENVFUN_STRAPDOWN;
    igea_sim_defaults(s->opts);
    return s;
}

void simmodel_free(void *p)
{
    simmodel *s = p;
    if (!s)
        return;
    free(s->traj);
    free(s->ep);
    free(s->S);
    free(s->sigma);
    free(s->spec);
    free(s->xval);
    free(s->codes);
    free(s->xfix);
    free(s);
}

/* Help text of the shared options. */
void simmodel_help(void)
{
    printf(
"flight model:\n"
"  --traj FILE         trajectory (t f3 w3 q4 rows, see igea envfun --help), or\n"
"  --duration S        the reference boost (METHODS 5.6) of S seconds (120)\n"
"  --rate HZ           sampled at HZ (50)\n"
"  --system KIND       strapdown (default) or platform\n"
"  --terms LIST        term names, 'default' (21-term model) or 'all'\n"
"  --epoch-step DT     tracking epochs every DT s (1), or --epochs FILE\n"
"  --spec FILE         1-sigma specs of the terms (default: igea envfun --list)\n"
"  --sigma S           stated tracking 1-sigma, m/s (0.01)\n"
"  --sigma-growth G    stated (and true) sigma grows by 1 + G e/(M-1) along the\n"
"                      epochs, as with range (0)\n"
"true errors:\n"
"  --x NAME=K,...      these terms at K x spec; the others drawn N(0, 1)\n"
"  --sigma-w W         true tracking noise = W x stated (1)\n"
"  --ar1 PHI           AR(1) correlation of the noise along epochs (0)\n"
"  --growth G          unstated noise growth: true sd x (1 + G e/(M-1)) (0)\n"
"  --outliers P        probability of an outlier per row (0)\n"
"  --outlier-scale K   outlier sd in row sds (10)\n"
"  --seed N            random seed (0); --generator mt19937|ranlxd2\n");
}

/* -1: not a model option; otherwise an exit code. */
int simmodel_option(void *p, int argc, char **argv, int *i)
{
    simmodel *s = p;
    const char *o = argv[*i], *v;
    struct { const char *name; double *dst; } dbl[] = {
        {"--duration", &s->duration}, {"--rate", &s->rate}, {"--epoch-step", &s->step},
        {"--sigma", &s->sigma0}, {"--sigma-growth", &s->sigma_growth},
        {"--sigma-w", &s->opts[IGEA_SIM_OPT_SIGMA_W]}, {"--ar1", &s->opts[IGEA_SIM_OPT_AR1]},
        {"--growth", &s->opts[IGEA_SIM_OPT_GROWTH]},
        {"--outliers", &s->opts[IGEA_SIM_OPT_OUTLIER_PROB]},
        {"--outlier-scale", &s->opts[IGEA_SIM_OPT_OUTLIER_SCALE]}};
    for (size_t k = 0; k < sizeof dbl / sizeof dbl[0]; k++)
        if (!strcmp(o, dbl[k].name)) {
            if (!(v = cli_optarg(argc, argv, i)))
                return CLI_USAGE;
            return cli_parse_double(dbl[k].name + 2, v, dbl[k].dst);
        }
    const char **str = NULL;
    if (!strcmp(o, "--traj")) str = &s->traj_file;
    else if (!strcmp(o, "--terms")) str = &s->terms;
    else if (!strcmp(o, "--epochs")) str = &s->epochs_file;
    else if (!strcmp(o, "--spec")) str = &s->spec_file;
    else if (!strcmp(o, "--x")) str = &s->xlist;
    if (str) {
        if (!(*str = cli_optarg(argc, argv, i)))
            return CLI_USAGE;
        return CLI_OK;
    }
    if (!strcmp(o, "--seed")) {
        if (!(v = cli_optarg(argc, argv, i)))
            return CLI_USAGE;
        int ec = cli_parse_int("seed", v, &s->seed);
        if (!ec && s->seed < 0) {
            cli_error("--seed must be >= 0");
            return CLI_USAGE;
        }
        return ec;
    }
    if (!strcmp(o, "--system")) {
        if (!(v = cli_optarg(argc, argv, i)))
            return CLI_USAGE;
        return envfun_parse_system(v, &s->system);
    }
    if (!strcmp(o, "--generator")) {
        if (!(v = cli_optarg(argc, argv, i)))
            return CLI_USAGE;
        if (!strcmp(v, "mt19937")) s->opts[IGEA_SIM_OPT_GENERATOR] = IGEA_SIM_MT19937;
        else if (!strcmp(v, "ranlxd2")) s->opts[IGEA_SIM_OPT_GENERATOR] = IGEA_SIM_RANLXD2;
        else {
            cli_error("--generator: mt19937 or ranlxd2");
            return CLI_USAGE;
        }
        return CLI_OK;
    }
    return -1;
}

/* Build trajectory, S (raw, column-major), sigma, spec and the X settings. */
int simmodel_build(void *p)
{
    simmodel *s = p;
    int ec, st;
    if (s->traj_file) {
        if ((ec = envfun_read_traj(s->traj_file, &s->traj, &s->nsamp)))
            return ec;
    } else {
        st = igea_sim_trajectory_length(s->duration, s->rate, &s->nsamp);
        if (st) {
            cli_error("--duration must be in (0, 1e5] s and --rate in (0, 1e4] Hz");
            return CLI_USAGE;
        }
        s->traj = malloc(sizeof(double) * (size_t)s->nsamp * IGEA_ENVFUN_TRAJ_COLS);
        if (!s->traj) {
            cli_error("out of memory");
            return CLI_SOFTWARE;
        }
        st = igea_sim_trajectory(s->system, s->duration, s->rate, s->nsamp, s->traj, s->nsamp);
        if ((ec = cli_status(st, "simulate: trajectory")))
            return ec;
    }
    if ((ec = envfun_parse_terms(s->system, s->terms, &s->codes, &s->N)))
        return ec;
    if ((ec = envfun_epochs(s->epochs_file, s->step, s->traj[0], s->traj[s->nsamp - 1],
                            &s->ep, &s->nep)))
        return ec;
    s->m = 3 * s->nep;
    s->S = malloc(sizeof(double) * (size_t)s->m * s->N);
    s->sigma = malloc(sizeof(double) * (size_t)s->m);
    s->spec = malloc(sizeof(double) * (size_t)s->N);
    s->xval = calloc((size_t)s->N, sizeof(double));
    s->xfix = calloc((size_t)s->N, sizeof(int));
    if (!s->S || !s->sigma || !s->spec || !s->xval || !s->xfix) {
        cli_error("out of memory");
        return CLI_SOFTWARE;
    }
    st = igea_envfun_compute(s->system, s->nsamp, s->traj, s->nsamp, s->N, s->codes, NULL,
                             s->nep, s->ep, NULL, IGEA_ENVFUN_VELOCITY, s->S, s->m);
    if (st == -9) {
        cli_error("simulate: the epochs must be non-decreasing and inside the trajectory");
        return CLI_DATAERR;
    }
    if ((ec = cli_status(st, "simulate: envfun")))
        return ec;
    if (!(s->sigma0 > 0) || !(s->sigma_growth >= 0)) {
        cli_error("--sigma must be > 0 and --sigma-growth >= 0");
        return CLI_USAGE;
    }
    for (int e = 0; e < s->nep; e++) {
        double g = 1.0 + (s->nep > 1 ? s->sigma_growth * e / (double)(s->nep - 1) : 0.0);
        for (int a = 0; a < 3; a++)
            s->sigma[3 * e + a] = s->sigma0 * g;
    }
    if (s->spec_file) {
        cli_matrix sm;
        if ((ec = cli_read_matrix(s->spec_file, &sm)))
            return ec;
        if (sm.rows * sm.cols != s->N) {
            cli_error("%s: %ld specs for %d terms", s->spec_file, sm.rows * sm.cols, s->N);
            cli_matrix_free(&sm);
            return CLI_DATAERR;
        }
        memcpy(s->spec, sm.v, sizeof(double) * (size_t)s->N);
        cli_matrix_free(&sm);
    } else {
        for (int j = 0; j < s->N; j++)
            s->spec[j] = envfun_default_spec(s->codes[j]);
    }
    if (s->xlist) {
        const char *q = s->xlist;
        while (*q) {
            const char *eq = strchr(q, '='), *comma = strchr(q, ',');
            size_t len = comma ? (size_t)(comma - q) : strlen(q);
            int found = -1;
            if (eq && (!comma || eq < comma))
                for (int j = 0; j < s->N; j++)
                    if (strlen(envfun_term_name(s->codes[j])) == (size_t)(eq - q) &&
                        !strncmp(envfun_term_name(s->codes[j]), q, (size_t)(eq - q)))
                        found = j;
            if (found < 0) {
                cli_error("--x: '%.*s' is not NAME=K with NAME one of the terms", (int)len, q);
                return CLI_USAGE;
            }
            char buf[64];
            size_t vl = len - (size_t)(eq - q) - 1;
            if (vl >= sizeof buf) vl = sizeof buf - 1;
            memcpy(buf, eq + 1, vl);
            buf[vl] = 0;
            if ((ec = cli_parse_double("x", buf, &s->xval[found])))
                return ec;
            s->xfix[found] = 1;
            q += len;
            if (*q == ',')
                q++;
        }
    }
    return CLI_OK;
}

/* Accessors for cmd_montecarlo.c. */
void simmodel_get(void *p, int *m, int *N, const double **S, const double **sigma,
                  const double **spec, const double **xval, const int **xfix,
                  const double **opts, int *seed, const int **codes)
{
    simmodel *s = p;
    *m = s->m;
    *N = s->N;
    *S = s->S;
    *sigma = s->sigma;
    *spec = s->spec;
    *xval = s->xval;
    *xfix = s->xfix;
    *opts = s->opts;
    *seed = s->seed;
    *codes = s->codes;
}

/* Map a library status of igea_sim_* about the options to a message. */
int simmodel_status(int st, const char *context)
{
    if (st == -10) {
        cli_error("%s: invalid noise options (sigma-w > 0, |ar1| < 1, growth >= 0, "
                  "0 <= outliers <= 1, outlier-scale >= 0)", context);
        return CLI_USAGE;
    }
    return cli_status(st, context);
}

/* ---------------------------------------------------------------------- */
static void simulate_help(void)
{
    printf(
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
"  traj.txt   the trajectory, with --save-traj\n"
"exactly the files 'igea eqerr' reads. The same --seed gives the same flight on\n"
"every machine; --flight F picks another flight of the same seed.\n"
"\n");
    simmodel_help();
    printf(
"  --flight F          flight index within the seed (0)\n"
"  --nonlinear-truth   dw from the full nonlinear navigation error with the true\n"
"                      X (igea_sim_nonlinear) instead of S diag(spec) X\n"
"output:\n"
"  --dir DIR           output directory (must exist; default .)\n"
"  --save-traj         also write DIR/traj.txt\n"
"  --json              print a JSON summary\n"
"\n"
"example:\n"
"  mkdir -p flight && igea simulate --seed 7 --sigma-w 1.8 --dir flight\n"
"  cd flight && igea eqerr --S S.txt --dw dw.txt --sigma sigma.txt --spec spec.txt\n"
"  igea simulate --x gyro_bias_y=3 --seed 1 --dir flight   # one term at 3 x spec\n");
}

static char *join(const char *dir, const char *name)
{
    size_t n = strlen(dir) + strlen(name) + 2;
    char *p = malloc(n);
    if (p)
        snprintf(p, n, "%s/%s", dir, name);
    return p;
}

int cmd_simulate(int argc, char **argv)
{
    if (cli_one_stdin(argc, argv))
        return CLI_USAGE;
    void *mdl = simmodel_new();
    const char *dir = ".";
    int flight = 0, save_traj = 0, json = 0, nonlin = 0, ec = CLI_OK;
    if (!mdl) {
        cli_error("out of memory");
        return CLI_SOFTWARE;
    }
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i], *v;
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) { simulate_help(); simmodel_free(mdl); return CLI_OK; }
        int r = simmodel_option(mdl, argc, argv, &i);
        if (r >= 0) {
            if (r) { simmodel_free(mdl); return r; }
            continue;
        }
        if (!strcmp(o, "--dir")) {
            if (!(dir = cli_optarg(argc, argv, &i))) { simmodel_free(mdl); return CLI_USAGE; }
        } else if (!strcmp(o, "--flight")) {
            if (!(v = cli_optarg(argc, argv, &i)) || cli_parse_int("flight", v, &flight)) {
                simmodel_free(mdl);
                return CLI_USAGE;
            }
        } else if (!strcmp(o, "--save-traj")) save_traj = 1;
        else if (!strcmp(o, "--nonlinear-truth")) nonlin = 1;
        else if (!strcmp(o, "--json")) json = 1;
        else {
            cli_error("simulate: unknown option %s (see --help)", o);
            simmodel_free(mdl);
            return CLI_USAGE;
        }
    }
    simmodel *s = mdl;
    double *dw = NULL, *x = NULL, *Srow = NULL, *trow = NULL;
    char *header = NULL, *path = NULL;
    cli_out outs[6];
    int nopen = 0;
    if ((ec = simmodel_build(mdl)))
        goto done;
    if (flight < 0) {
        cli_error("--flight must be >= 0");
        ec = CLI_USAGE;
        goto done;
    }
    dw = malloc(sizeof(double) * (size_t)s->m);
    x = malloc(sizeof(double) * (size_t)s->N);
    Srow = malloc(sizeof(double) * (size_t)s->m * s->N);
    header = envfun_header(s->codes, s->N);
    if (!dw || !x || !Srow || !header) { cli_error("out of memory"); ec = CLI_SOFTWARE; goto done; }
    int st = igea_sim_flight(s->m, s->N, s->S, s->m, s->sigma, 1, s->spec, s->xval, s->xfix,
                             s->opts, s->seed, flight, x, dw);
    if ((ec = simmodel_status(st, "simulate")))
        goto done;
    if (nonlin) {
        double err[IGEA_ENVFUN_TERM_COUNT] = {0};
        double *nl = malloc(sizeof(double) * (size_t)s->m);
        if (!nl) { cli_error("out of memory"); ec = CLI_SOFTWARE; goto done; }
        for (int j = 0; j < s->N; j++)
            err[s->codes[j]] += x[j] * s->spec[j];
        st = igea_sim_nonlinear(s->system, s->nsamp, s->traj, s->nsamp, err, NULL, s->nep,
                                s->ep, nl);
        if ((ec = cli_status(st, "simulate: nonlinear truth"))) {
            free(nl);
            goto done;
        }
        for (int i = 0; i < s->m; i++) {
            double lin = 0.0;
            for (int j = 0; j < s->N; j++)
                lin += s->S[i + (size_t)j * s->m] * s->spec[j] * x[j];
            dw[i] += nl[i] - lin;
        }
        free(nl);
    }
    for (int i = 0; i < s->m; i++)
        for (int j = 0; j < s->N; j++)
            Srow[(size_t)i * s->N + j] = s->S[i + (size_t)j * s->m];
    if (save_traj) {
        trow = malloc(sizeof(double) * (size_t)s->nsamp * IGEA_ENVFUN_TRAJ_COLS);
        if (!trow) { ec = cli_oom("the trajectory table"); goto done; }
        for (int k = 0; k < s->nsamp; k++)
            for (int c = 0; c < IGEA_ENVFUN_TRAJ_COLS; c++)
                trow[(size_t)k * IGEA_ENVFUN_TRAJ_COLS + c] = s->traj[k + (size_t)c * s->nsamp];
    }
    /* All files go to temporaries first and replace the old set only when
     * every one is complete. */
    static const char *const names[6] = {"S.txt", "dw.txt", "sigma.txt", "spec.txt", "X.txt",
                                         "traj.txt"};
    int nout = save_traj ? 6 : 5;
    for (int k = 0; k < 6; k++)
        outs[k] = (cli_out)CLI_OUT_INIT;
    for (int k = 0; k < nout; k++) {
        free(path);
        if (!(path = join(dir, names[k]))) { ec = cli_oom("an output path"); goto done; }
        if ((ec = cli_out_open(&outs[k], path)))
            goto done;
        nopen = k + 1;
    }
    cli_write_matrix_body(outs[0].f, 0, Srow, s->m, s->N, header);
    cli_write_matrix_body(outs[1].f, 0, dw, s->m, 1, "dw (m/s), rows epoch-major x, y, z");
    cli_write_matrix_body(outs[2].f, 0, s->sigma, s->m, 1,
                          "stated tracking 1-sigma (m/s) per row");
    cli_write_matrix_body(outs[3].f, 0, s->spec, s->N, 1, header);
    fprintf(outs[4].f, "# true X (spec units) and term name; seed %d flight %d\n", s->seed,
            flight);
    for (int j = 0; j < s->N; j++)
        fprintf(outs[4].f, "%.17g # %s\n", x[j], envfun_term_name(s->codes[j]));
    if (save_traj)
        cli_write_matrix_body(outs[5].f, 0, trow, s->nsamp, IGEA_ENVFUN_TRAJ_COLS,
                              "t f_x f_y f_z w_x w_y w_z q0 q1 q2 q3");
    if (json) {
        printf("{\n  \"dir\": ");
        cli_json_str(stdout, dir);
        printf(",\n  \"rows\": %d,\n  \"seed\": %d,\n  \"flight\": %d,\n  \"terms\": [",
               s->m, s->seed, flight);
        for (int j = 0; j < s->N; j++) {
            if (j) fputs(", ", stdout);
            cli_json_str(stdout, envfun_term_name(s->codes[j]));
        }
        printf("],\n  \"x_true\": ");
        cli_json_array(stdout, x, s->N);
        printf("\n}\n");
        /* a run whose summary is lost keeps the old files */
        if ((ec = cli_stdout_check()))
            goto done;
    }
    nopen = 0;
    if ((ec = cli_out_commit_all(outs, nout)))
        goto done;
    if (!json) {
        fprintf(stderr, "igea simulate: %d epochs x 3 axes, %d terms, seed %d flight %d -> "
                "%s/{S,dw,sigma,spec,X}.txt\n", s->nep, s->N, s->seed, flight, dir);
    }
done:
    for (int k = 0; k < nopen; k++)
        cli_out_abort(&outs[k]);
    free(dw);
    free(x);
    free(Srow);
    free(trow);
    free(header);
    free(path);
    simmodel_free(mdl);
    return ec;
}
