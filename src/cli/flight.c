/* flight.c - the pieces of a flight that envfun, simulate and montecarlo
 * share: term lists (the library's catalogue), trajectories, epochs, specs,
 * and the flight-model options with the igea_sim_model built from them. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

int cli_parse_terms(int system, const char *list, int **codes, int *n)
{
    int cap = igea_envfun_term_count(), cnt = 0;
    for (const char *p = list; *p; p++)
        cap += *p == ',';
    int *c = malloc(sizeof(int) * (size_t)cap);
    if (!c)
        return cli_oom("the term list");
    if (!strcmp(list, "default")) {
        igea_envfun_default_terms(system, c, cap, &cnt);
    } else if (!strcmp(list, "all")) {
        igea_envfun_all_terms(system, c, cap, &cnt);
    } else {
        char name[64];
        for (const char *p = list; *p;) {
            const char *e = strchr(p, ',');
            size_t len = e ? (size_t)(e - p) : strlen(p);
            snprintf(name, sizeof name, "%.*s", (int)(len < sizeof name ? len : sizeof name - 1), p);
            int k = len < sizeof name ? igea_envfun_term_code(system, name) : -2;
            if (k < 0) {
                cli_error("--terms: '%.*s' is not a %s term (see igea envfun --list)", (int)len, p,
                          igea_choice_name(IGEA_CHOICE_ENVFUN_SYSTEM, system));
                free(c);
                return CLI_USAGE;
            }
            c[cnt++] = k;
            p = e ? e + 1 : p + len;
        }
    }
    if (cnt == 0) {
        cli_error("--terms: empty list");
        free(c);
        return CLI_USAGE;
    }
    *codes = c;
    *n = cnt;
    return CLI_OK;
}

int cli_read_traj(const char *path, double **traj, int *nsamp)
{
    cli_matrix m;
    int ec = cli_read_matrix(path, &m);
    if (ec)
        return ec;
    if (m.cols != IGEA_ENVFUN_TRAJ_COLS || m.rows < 2 || m.rows > 100000000L) {
        cli_error("%s: a trajectory has 11 columns (t f_x f_y f_z w_x w_y w_z q0 q1 q2 q3) "
                  "and at least 2 rows; found %ld x %d", path, m.rows, m.cols);
        cli_matrix_free(&m);
        return CLI_DATAERR;
    }
    double *t = malloc(sizeof(double) * (size_t)m.rows * IGEA_ENVFUN_TRAJ_COLS);
    if (!t) {
        cli_matrix_free(&m);
        return cli_oom("the trajectory");
    }
    for (long k = 0; k < m.rows; k++)
        for (int c = 0; c < IGEA_ENVFUN_TRAJ_COLS; c++)
            t[k + (size_t)c * (size_t)m.rows] = m.v[k * IGEA_ENVFUN_TRAJ_COLS + c];
    *nsamp = (int)m.rows;
    *traj = t;
    cli_matrix_free(&m);
    return CLI_OK;
}

char *cli_term_header(const int *codes, int n)
{
    size_t len = 2;
    for (int j = 0; j < n; j++)
        len += strlen(igea_envfun_term_name(codes[j])) + 1;
    char *h = malloc(len + 1);
    if (!h)
        return NULL;
    h[0] = '\0';
    for (int j = 0; j < n; j++) {
        if (j)
            strcat(h, " ");
        strcat(h, igea_envfun_term_name(codes[j]));
    }
    return h;
}

int cli_epochs(const char *file, double step, double t0, double t1, double **ep, int *n)
{
    if (file) {
        long cnt;
        int ec = cli_read_vector(file, -1, "the epochs", ep, &cnt);
        *n = (int)cnt;
        return ec;
    }
    if (!(step > 0)) {
        cli_error("--epoch-step must be > 0");
        return CLI_USAGE;
    }
    long cnt = (long)floor((t1 - t0) / step + 1e-9);
    if (cnt < 1 || cnt > 10000000L) {
        cli_error("--epoch-step %g gives %ld epochs in [%g, %g]", step, cnt, t0, t1);
        return CLI_USAGE;
    }
    double *e = malloc(sizeof(double) * (size_t)cnt);
    if (!e)
        return cli_oom("the epochs");
    for (long i = 0; i < cnt; i++)
        e[i] = fmin(t0 + (double)(i + 1) * step, t1);
    *ep = e;
    *n = (int)cnt;
    return CLI_OK;
}

int cli_term_specs(int system, const int *codes, int n, const char *arg, double **spec)
{
    if (strcmp(arg, "default"))
        return cli_read_vector(arg, n, "one spec per term", spec, NULL);
    if (!(*spec = malloc(sizeof(double) * (size_t)n)))
        return cli_oom("the term specs");
    for (int j = 0; j < n; j++)
        igea_envfun_default_spec(system, codes[j], &(*spec)[j]);
    return CLI_OK;
}

/* ---- the flight model ---------------------------------------------------- */
cli_flight_args cli_flight_opts;

void cli_flight_defaults(void)
{
    igea_sim_defaults(cli_flight_opts.opts);
}

void cli_flight_free(cli_flight *f)
{
    free(f->traj);
    free(f->ep);
    free(f->spec);
    free(f->codes);
    free(f->xval);
    free(f->xfix);
    igea_sim_model_free(f->model);
    memset(f, 0, sizeof *f);
}

void cli_flight_noise(const cli_flight_args *a, double *opts)
{
    memcpy(opts, a->opts, sizeof a->opts);
    opts[IGEA_SIM_OPT_GENERATOR] = a->generator;
}

/* --x NAME=K,...: terms fixed at K x spec. */
static int parse_truth(const char *list, cli_flight *f)
{
    if (!(f->xval = calloc((size_t)f->N, sizeof(double))) ||
        !(f->xfix = calloc((size_t)f->N, sizeof(int))))
        return cli_oom("the true errors");
    for (const char *q = list; *q;) {
        const char *eq = strchr(q, '='), *comma = strchr(q, ',');
        size_t len = comma ? (size_t)(comma - q) : strlen(q);
        int found = -1;
        for (int j = 0; eq && (!comma || eq < comma) && j < f->N; j++) {
            const char *nm = igea_envfun_term_name(f->codes[j]);
            if (strlen(nm) == (size_t)(eq - q) && !strncmp(nm, q, (size_t)(eq - q)))
                found = j;
        }
        if (found < 0) {
            cli_error("--x: '%.*s' is not NAME=K with NAME one of the terms", (int)len, q);
            return CLI_USAGE;
        }
        char buf[64];
        snprintf(buf, sizeof buf, "%.*s", (int)(len - (size_t)(eq - q) - 1), eq + 1);
        int ec = cli_parse_double("--x", buf, &f->xval[found]);
        if (ec)
            return ec;
        f->xfix[found] = 1;
        q += len;
        if (*q == ',')
            q++;
    }
    return CLI_OK;
}

/* The trajectory: a file or the reference boost. */
static int make_trajectory(const cli_flight_args *a, cli_flight *f)
{
    if (a->traj)
        return cli_read_traj(a->traj, &f->traj, &f->nsamp);
    if (igea_sim_trajectory_length(a->duration, a->rate, &f->nsamp)) {
        cli_error("--duration must be in (0, 1e5] s and --rate in (0, 1e4] Hz");
        return CLI_USAGE;
    }
    if (!(f->traj = malloc(sizeof(double) * (size_t)f->nsamp * IGEA_ENVFUN_TRAJ_COLS)))
        return cli_oom("the trajectory");
    return cli_status(igea_sim_trajectory(a->system, a->duration, a->rate, f->nsamp, f->traj,
                                          f->nsamp), "trajectory");
}

/* igea_envfun_compute's argument 9, the epochs (also for
 * igea_sim_model_create_trajectory, whose arguments 1-9 are the same). */
#define ENVFUN_ARG_EPOCHS (-9)

int cli_flight_set(const cli_flight_args *a, cli_flight *f, const char *cmd)
{
    double opts[IGEA_SIM_OPT_LEN], *sigma;
    int ec = cli_read_values(a->sigma, f->m, "--sigma (one per row of S)", &sigma, NULL);
    if (ec)
        return ec;
    cli_flight_noise(a, opts);
    int st = igea_sim_model_set_sigma(f->model, sigma, 1, a->sigma_growth);
    free(sigma);
    if (st == 0)
        st = igea_sim_model_set_spec(f->model, f->spec);
    if (st == 0)
        st = igea_sim_model_set_truth(f->model, f->xval, f->xfix);
    if (st == 0)
        st = igea_sim_model_set_noise(f->model, opts);
    return cli_status(st, cmd);
}

int cli_flight_build(const cli_flight_args *a, cli_flight *f, const char *cmd)
{
    int ec;
    memset(f, 0, sizeof *f);
    if (!(a->sigma_growth >= 0)) {
        cli_error("--sigma-growth must be >= 0");
        return CLI_USAGE;
    }
    double opts[IGEA_SIM_OPT_LEN];
    cli_flight_noise(a, opts);
    if (a->seed < 0) {
        cli_error("--seed must be >= 0");
        return CLI_USAGE;
    }
    if ((ec = cli_check_opts(cmd, IGEA_MODULE_SIM, igea_sim_check_opts(opts))))
        return ec;
    if ((ec = make_trajectory(a, f)) || (ec = cli_parse_terms(a->system, a->terms, &f->codes,
                                                                &f->N)))
        return ec;
    if ((ec = cli_epochs(a->epochs, a->step, f->traj[0], f->traj[f->nsamp - 1], &f->ep, &f->nep)))
        return ec;
    f->m = 3 * f->nep;
    if (a->spec && (ec = cli_read_vector(a->spec, f->N, "one spec per term", &f->spec, NULL)))
        return ec;
    if (a->x && (ec = parse_truth(a->x, f)))
        return ec;
    int st = igea_sim_model_create_trajectory(a->system, f->nsamp, f->traj, f->nsamp, f->N,
                                              f->codes, NULL, f->nep, f->ep, &f->model);
    if (st == ENVFUN_ARG_EPOCHS) {
        cli_error("%s: the epochs must be non-decreasing and inside the trajectory", cmd);
        return CLI_DATAERR;
    }
    if ((ec = cli_status(st, cmd)))
        return ec;
    if (!a->spec) {
        /* the model's own (the catalogue's defaults), kept for the reports */
        if (!(f->spec = malloc(sizeof(double) * (size_t)f->N)))
            return cli_oom("the specs");
        igea_sim_model_get_spec(f->model, f->spec);
    }
    return cli_flight_set(a, f, cmd);
}
