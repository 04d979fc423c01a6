/* igea simulate - a synthetic flight test: trajectory -> S -> dw, written
 * as the files 'igea eqerr' reads. The model is the library's
 * (igea_sim_model), built from the shared flight options (flight.c). */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

typedef struct {
    const char *dir;
    int flight, save_traj, json, nonlinear;
} sm_args;

static sm_args A;
static const cli_opt options[] = {
    CLI_FLIGHT_MODEL_OPTIONS,
    CLI_FLIGHT_TRUTH_OPTIONS,
    CLI_FLIGHT_NOISE_OPTIONS,
    {"--flight", CLI_OPT_INT, &A.flight, "0", "F", "flight index within the seed", NULL},
    {"--nonlinear-truth", CLI_OPT_FLAG, &A.nonlinear, NULL, NULL, "dw from the full nonlinear navigation error with\n"
     "the true X (igea_sim_nonlinear) instead of\nS diag(spec) X", NULL},
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
"  traj.txt   the trajectory, with --save-traj\n"
"exactly the files 'igea eqerr' reads. The same --seed gives the same flight on\n"
"every machine; --flight F picks another flight of the same seed.\n"
"\n",
options,
"\n"
"example:\n"
"  mkdir -p flight && igea simulate --seed 7 --sigma-w 1.8 --dir flight\n"
"  cd flight && igea eqerr --S S.txt --dw dw.txt --sigma sigma.txt --spec spec.txt\n"
"  igea simulate --x gyro_bias_y=3 --seed 1 --dir flight   # one term at 3 x spec\n"};

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
    cli_json_end(&j);
}

/* All files go to temporaries first and replace the old set only when
 * every one is complete (and the JSON summary has been written). */
static int commit_files(const sm_args *a, const cli_flight_args *fa, const cli_flight *f,
                        const sm_run *r)
{
    static const char *const names[6] = {"S.txt", "dw.txt", "sigma.txt", "spec.txt", "X.txt",
                                         "traj.txt"};
    cli_out outs[6];
    int nout = a->save_traj ? 6 : 5, nopen = 0, ec = CLI_OK;
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
    if (a.flight < 0) {
        cli_error("--flight must be >= 0");
        return CLI_USAGE;
    }
    cli_flight f;
    sm_run r;
    memset(&r, 0, sizeof r);
    if (!(ec = cli_flight_build(&fa, &f, "simulate")) && !(ec = run_flight(&a, &fa, &f, &r)) &&
        !(ec = commit_files(&a, &fa, &f, &r)) && !a.json)
        fprintf(stderr, "igea simulate: %d epochs x 3 axes, %d terms, seed %d flight %d -> "
                "%s/{S,dw,sigma,spec,X}.txt\n", f.nep, f.N, fa.seed, a.flight, a.dir);
    free(r.x);
    free(r.dw);
    free(r.S);
    free(r.sigma);
    free(r.traj);
    free(r.header);
    cli_flight_free(&f);
    return ec;
}
