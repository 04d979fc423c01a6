/* igea montecarlo - many simulated flights judged by the equivalent-error
 * test: its size (false-alarm rate) and power, with 99% intervals. The
 * model, the flights, the verdicts and the intervals are the library's. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

typedef struct {
    const char *S, *out;
    int flights, first, threads, pool, json;
    double eqo[IGEA_EQERR_OPT_LEN];
    int verdict; /* IGEA_STATS_VERDICT_* */
    int ar_given; /* --ar-given: the judge is told the true phi */
    int ar_method; /* --ar-method: IGEA_NOISE_AR_* */
    const char *plot; /* --plot FILE.svg */
} mc_args;

static mc_args A;
static const cli_opt options[] = {
    CLI_FLIGHT_MODEL_OPTIONS,
    CLI_FLIGHT_TRUTH_OPTIONS,
    CLI_FLIGHT_NOISE_OPTIONS,
    CLI_HEAD("judged with the noise models:"),
    {"--judge-noise", CLI_OPT_DSET, &cli_flight_opts.opts[IGEA_SIM_OPT_JUDGE_NOISE], NULL, NULL, "tell the judge the covariance and the groups\n(igea eqerr --cov --groups)", NULL},
    {"--ar", CLI_OPT_NUM, &A.eqo[IGEA_EQERR_OPT_AR], NULL, "P", "judge with AR(P), phi estimated (igea eqerr --ar)", NULL},
    {"--ar-given", CLI_OPT_FLAG, &A.ar_given, NULL, NULL, "with --ar: phi given (the true one)", NULL},
    {"--ar-method", CLI_OPT_CHOICE, &A.ar_method, NULL, CLI_CHOICES(IGEA_CHOICE_NOISE_AR_METHOD),
     "with --ar: how the judge estimates phi (igea eqerr\n--ar-method; default reml)", NULL},
    {"--robust", CLI_OPT_DSET, &A.eqo[IGEA_EQERR_OPT_ROBUST], NULL, NULL, "judge with the robust route (igea eqerr --robust)", NULL},
    {"--robust-alpha", CLI_OPT_NUM, &A.eqo[IGEA_EQERR_OPT_ROBUST_ALPHA], NULL, "A", "level of the w-test per row (0: 0.001)", NULL},
    {"--group-bias", CLI_OPT_DSET, &A.eqo[IGEA_EQERR_OPT_GROUP_BIAS], NULL, NULL, "judge with per-group bias columns", NULL},
    CLI_HEAD("your own flight geometry (instead of the model above):"),
    {"--S", CLI_OPT_STR, &A.S, NULL, "FILE", "S (rows epoch-major, one column per term), as igea\n"
     "eqerr, with --sigma FILE|NUM and --spec FILE (X ~\nN(0, I); --x does not apply)", NULL},
    CLI_HEAD("test:"),
    {"--flights", CLI_OPT_INT, &A.flights, "2000", "N", "number of flights", NULL},
    {"--first-flight", CLI_OPT_INT, &A.first, "0", "F", "index of the first flight", NULL},
    {"--threads", CLI_OPT_INT, &A.threads, "0", "T", "worker threads, 0 = all processors", NULL},
    CLI_PROGRESS_OPTIONS,
    {"--alpha", CLI_OPT_NUM, &A.eqo[IGEA_EQERR_OPT_ALPHA], CLI_DEF_LIB, "A", "significance level", NULL},
    {"--lambda-test", CLI_OPT_NUM, &A.eqo[IGEA_EQERR_OPT_LAMBDA_TEST], CLI_DEF_LIB, "L", "test components with lambda >= L", NULL},
    {"--no-correction", CLI_OPT_DCLEAR, &A.eqo[IGEA_EQERR_OPT_CORRECTION], NULL, NULL, "no tracking-accuracy (sigma_w) correction", NULL},
    {"--bias-correct", CLI_OPT_DSET, &A.eqo[IGEA_EQERR_OPT_BIAS_CORRECT], NULL, NULL, "sigma_w^2 = mean(g^2 - lambda) [D]", NULL},
    {"--pool", CLI_OPT_INT, &A.pool, "0", "F", "also pool consecutive groups of F flights (METHODS\n"
     "1.2 step 6), each judged by the --verdict rule for its\npooled components (as igea test), "
     "and report the\npooled verdict rate and the rule's overall size", NULL},
    {"--verdict", CLI_OPT_CHOICE, &A.verdict, "seed", CLI_CHOICES(IGEA_CHOICE_STATS_VERDICT),
     "overall verdict rule counted as 'out of spec' (as igea\neqerr --verdict), for the flights and the pools", NULL},
    CLI_HEAD("output:"),
    {"--out", CLI_OPT_STR, &A.out, NULL, "FILE", "per-flight table: flight chi2 dof n_reject scale", NULL},
    {"--json", CLI_OPT_FLAG, &A.json, NULL, NULL, "machine-readable summary", NULL},
    {"--plot", CLI_OPT_STR, &A.plot, NULL, "FILE.svg", "draw the per-component rejection rates with their\n99% intervals into an SVG picture", NULL},
    CLI_END};

static const cli_command command = {"montecarlo",
"usage: igea montecarlo [options]\n"
"\n"
"Monte Carlo proof of the equivalent-error test (seed 000): simulates many\n"
"flights with known truth (as 'igea simulate') and judges each with the test\n"
"of 'igea eqerr' (eig route), reporting how often the verdict is 'out of\n"
"spec', the chi-square and per-component rejection rates with 99% (Wilson)\n"
"intervals (the four rates also with their exact Clopper-Pearson ones), and the mean sigma_w^2 estimate. With the truth in spec (X ~ N(0,\n"
"I), sigma_w = 1) the rates are the test's size; with a term set to K x spec\n"
"(--x) they are its power. Flight f uses the random stream (seed, f): results\n"
"do not depend on --threads.\n"
"\n",
options,
"Progress (flights done, elapsed time, ETA) goes to stderr when it is a\n"
"terminal, or a line per 10 % with --progress; --quiet silences it.\n"
"\n"
"example:\n"
"  igea montecarlo --flights 2000 --seed 1                       # size\n"
"  igea montecarlo --flights 2000 --sigma-w 1.8 --no-correction  # misstated sigma\n"
"  igea montecarlo --flights 1000 --x gyro_bias_y=2 --pool 4     # power, pooled\n"
"  igea montecarlo --S S.txt --sigma sigma.txt --spec spec.txt\n"};

/* A model of the flight geometry of --S, --sigma and --spec. */
static int own_geometry(const mc_args *a, const cli_flight_args *fa, cli_flight *f)
{
    memset(f, 0, sizeof *f);
    if (!fa->spec) {
        cli_error("montecarlo: --S needs --sigma FILE|NUM and --spec FILE");
        return CLI_USAGE;
    }
    if (fa->x) {
        cli_error("montecarlo: --x applies to the simulated model, not to --S files");
        return CLI_USAGE;
    }
    cli_matrix S;
    int ec = cli_read_matrix(a->S, &S);
    if (ec)
        return ec;
    if (S.rows % 3 != 0 || S.rows > 100000000L) {
        cli_error("montecarlo: S must have 3 rows per epoch (%ld x %d)", S.rows, S.cols);
        cli_matrix_free(&S);
        return CLI_DATAERR;
    }
    f->m = (int)S.rows, f->N = S.cols, f->nep = f->m / 3;
    double *Sc = malloc(sizeof(double) * (size_t)f->m * f->N);
    if (!Sc) {
        cli_matrix_free(&S);
        return cli_oom("the flight geometry");
    }
    for (int i = 0; i < f->m; i++)
        for (int j = 0; j < f->N; j++)
            Sc[i + (size_t)j * f->m] = S.v[(size_t)i * f->N + j];
    cli_matrix_free(&S);
    int st = igea_sim_model_create(f->m, f->N, Sc, f->m, &f->model);
    free(Sc);
    if ((ec = cli_status(st, "montecarlo")) ||
        (ec = cli_read_vector(fa->spec, f->N, "one spec per column of S", &f->spec, NULL)))
        return ec;
    return cli_flight_set(fa, f, "montecarlo");
}

typedef struct {
    double counts[IGEA_SIM_MC_LEN], rates[IGEA_SIM_MC_RATES_LEN], *table;
    double pooled[IGEA_SIM_POOL_LEN], pool_cp[2]; /* the pools' rate, its exact interval */
    int *ct, *cr;
    double cp99[8]; /* the four counts' exact 99 % intervals (igea_sim_interval_cp) */
} mc_result;

/* The flights in chunks of a tenth (at most 1000 flights; the chunks
 * depend on --flights only, never on the progress shown): one library call
 * per chunk, its counts added; the means over the testable flights are
 * those of one call over all flights, summed flight by flight from the
 * table (mean_size to rounding: the library sums it flight by flight within
 * a call, the chunks add their means). */
static int run_flights(const mc_args *a, const cli_flight_args *fa, const cli_flight *f,
                       mc_result *r)
{
    int N = f->N, nf = a->flights, chunk = nf / 10 + (nf % 10 != 0), ec = CLI_OK;
    chunk = chunk > 1000 ? 1000 : chunk;
    int *ct1 = malloc((size_t)N * sizeof(int)), *cr1 = malloc((size_t)N * sizeof(int));
    cli_progress pr;
    ec = cli_progress_start(&pr, "montecarlo", "flights", nf);
    if (!ec && (!ct1 || !cr1))
        ec = cli_oom("the component counts");
    double *c = r->counts, sum_size = 0, outliers = 0;
    for (int done = 0; !ec && done < nf; done += chunk) {
        int n = nf - done < chunk ? nf - done : chunk;
        double c1[IGEA_SIM_MC_LEN];
        int st = igea_sim_montecarlo_ex(f->model, a->eqo, fa->seed, a->first + done, n,
                                        a->threads, c1, NULL, ct1, cr1, r->table + done, nf,
                                        IGEA_SIM_MC_TABLE_COLS_Z);
        if ((ec = cli_status(st, "montecarlo")))
            break;
        for (int k = IGEA_SIM_MC_FLIGHTS; k <= IGEA_SIM_MC_NOT_TESTABLE; k++)
            c[k] += c1[k];
        c[IGEA_SIM_MC_SCALE_COVERED] += c1[IGEA_SIM_MC_SCALE_COVERED]; /* noise judge */
        c[IGEA_SIM_MC_SIGMA_COVERED] += c1[IGEA_SIM_MC_SIGMA_COVERED];
        outliers += floor(c1[IGEA_SIM_MC_MEAN_OUTLIERS] * n + 0.5);  /* a count per chunk */
        sum_size += (c1[IGEA_SIM_MC_FLIGHTS] - c1[IGEA_SIM_MC_NOT_TESTABLE]) *
                    c1[IGEA_SIM_MC_MEAN_SIZE];
        for (int j = 0; j < N; j++)
            r->ct[j] += ct1[j], r->cr[j] += cr1[j];
        cli_progress_update(&pr, done + n);
    }
    cli_progress_end(&pr);
    free(ct1);
    free(cr1);
    double sum_scale = 0, sum_tested = 0, nt = 0;
    for (int i = 0; i < nf; i++) /* the library's order: flight by flight */
        if (isfinite(r->table[i + IGEA_SIM_MC_TABLE_SCALE * (size_t)nf])) {
            sum_scale += r->table[i + IGEA_SIM_MC_TABLE_SCALE * (size_t)nf];
            sum_tested += r->table[i + IGEA_SIM_MC_TABLE_DOF * (size_t)nf];
            nt++;
        }
    c[IGEA_SIM_MC_MEAN_SCALE] = nt > 0 ? sum_scale / nt : NAN;
    c[IGEA_SIM_MC_MEAN_TESTED] = nt > 0 ? sum_tested / nt : 0;
    c[IGEA_SIM_MC_MEAN_SIZE] = nt > 0 ? sum_size / nt : 0;
    c[IGEA_SIM_MC_MEAN_OUTLIERS] = outliers / nf;
    for (int k = 0; !ec && k < 4; k++) {
        r->rates[3 * k] = c[IGEA_SIM_MC_FAILED + k] / c[IGEA_SIM_MC_FLIGHTS];
        ec = cli_status(igea_sim_interval(c[IGEA_SIM_MC_FAILED + k], c[IGEA_SIM_MC_FLIGHTS],
                                          r->rates + 3 * k + 1), "montecarlo");
    }
    for (int k = 0; !ec && k < 4; k++) /* the exact Clopper-Pearson interval beside Wilson's */
        ec = cli_status(igea_sim_interval_cp(c[IGEA_SIM_MC_FAILED + k], c[IGEA_SIM_MC_FLIGHTS],
                                             0.99, r->cp99 + 2 * k), "montecarlo");
    return ec;
}

static void write_table(FILE *f, const mc_args *a, const cli_flight_args *fa, const mc_result *r)
{
    int nf = a->flights;
    const double *t = r->table;
    fprintf(f, "# flight chi2 dof n_reject scale   (seed %d)\n", fa->seed);
    for (int i = 0; i < nf; i++)
        fprintf(f, "%d %.17g %d %d %.17g\n", a->first + i, t[i + IGEA_SIM_MC_TABLE_CHI2 * nf],
                (int)t[i + IGEA_SIM_MC_TABLE_DOF * nf], (int)t[i + IGEA_SIM_MC_TABLE_N_REJECT * nf],
                t[i + IGEA_SIM_MC_TABLE_SCALE * nf]);
}

static const char *const rate_keys[4] = {"failed", "chi2_reject", "any_reject", "not_testable"};

static void json_report(FILE *out, const mc_args *a, const cli_flight_args *fa,
                        const cli_flight *f, const mc_result *r)
{
    double opts[IGEA_SIM_OPT_LEN];
    cli_flight_noise(fa, opts);
    cli_json j;
    cli_json_begin(&j, out);
    cli_jint(&j, "flights", a->flights);
    cli_jint(&j, "seed", fa->seed);
    cli_jint(&j, "first_flight", a->first);
    cli_jnum(&j, "alpha", a->eqo[IGEA_EQERR_OPT_ALPHA]);
    cli_jbool(&j, "correction", a->eqo[IGEA_EQERR_OPT_CORRECTION] != 0);
    cli_jstr(&j, "verdict", igea_choice_name(IGEA_CHOICE_STATS_VERDICT, a->verdict));
    cli_jnum(&j, "mean_size", r->counts[IGEA_SIM_MC_MEAN_SIZE]);
    cli_jnum(&j, "sigma_w", opts[IGEA_SIM_OPT_SIGMA_W]);
    for (int k = 0; k < 4; k++) {
        cli_json_open(&j, rate_keys[k], '{');
        cli_jint(&j, "count", (long)r->counts[IGEA_SIM_MC_FAILED + k]);
        cli_jnum(&j, "rate", r->rates[3 * k]);
        cli_jnums(&j, "ci99", r->rates + 3 * k + 1, 2);
        cli_jnums(&j, "ci99_cp", r->cp99 + 2 * k, 2);
        cli_json_close(&j);
    }
    cli_jnum(&j, "mean_scale", r->counts[IGEA_SIM_MC_MEAN_SCALE]);
    cli_jnum(&j, "mean_tested", r->counts[IGEA_SIM_MC_MEAN_TESTED]);
    cli_jint(&j, "scale_covered", (long)r->counts[IGEA_SIM_MC_SCALE_COVERED]);
    cli_jint(&j, "sigma_covered", (long)r->counts[IGEA_SIM_MC_SIGMA_COVERED]);
    cli_jnum(&j, "mean_outliers", r->counts[IGEA_SIM_MC_MEAN_OUTLIERS]);
    cli_jints(&j, "comp_tested", r->ct, f->N);
    cli_jints(&j, "comp_reject", r->cr, f->N);
    if (a->pool > 0) {
        cli_json_open(&j, "pool", '{');
        cli_jint(&j, "size", a->pool);
        cli_jint(&j, "pools", (long)r->pooled[IGEA_SIM_POOL_POOLS]);
        cli_jint(&j, "failed", (long)r->pooled[IGEA_SIM_POOL_FAILED]);
        cli_jnum(&j, "rate", r->pooled[IGEA_SIM_POOL_RATE]);
        cli_jnums(&j, "ci99", r->pooled + IGEA_SIM_POOL_CI99_LO, 2);
        cli_jnums(&j, "ci99_cp", r->pool_cp, 2);
        cli_jnum(&j, "mean_size", r->pooled[IGEA_SIM_POOL_MEAN_SIZE]);
        cli_json_close(&j);
    }
    cli_json_end(&j);
}

static void text_components(FILE *out, const cli_flight *f, const mc_result *r)
{
    double lohi[2];
    fprintf(out, "%9s %8s %8s %8s   %s\n", "component", "tested", "rejected", "rate",
            "99% interval");
    for (int j = 0; j < f->N; j++) {
        if (!r->ct[j] || igea_sim_interval(r->cr[j], r->ct[j], lohi))
            continue;
        fprintf(out, "%9d %8d %8d %8.4f   [%.4f, %.4f]\n", j, r->ct[j], r->cr[j],
                (double)r->cr[j] / r->ct[j], lohi[0], lohi[1]);
    }
}

static void text_report(FILE *out, const mc_args *a, const cli_flight_args *fa,
                        const cli_flight *f, const mc_result *r)
{
    double opts[IGEA_SIM_OPT_LEN];
    const double *p = r->pooled;
    cli_flight_noise(fa, opts);
    fprintf(out, "igea montecarlo: %d flights (seed %d, first %d), %d rows x %d terms\n",
            a->flights, fa->seed, a->first, f->m, f->N);
    fprintf(out, "truth: sigma_w %g, ar1 %g, growth %g, outliers %g", opts[IGEA_SIM_OPT_SIGMA_W],
            opts[IGEA_SIM_OPT_AR1], opts[IGEA_SIM_OPT_GROWTH], opts[IGEA_SIM_OPT_OUTLIER_PROB]);
    for (int j = 0; f->xfix && j < f->N; j++)
        if (f->xfix[j])
            fprintf(out, ", %s = %g x spec", igea_envfun_term_name(f->codes[j]), f->xval[j]);
    fprintf(out, "; test: alpha %g, sigma_w correction %s\n\n", a->eqo[IGEA_EQERR_OPT_ALPHA],
            a->eqo[IGEA_EQERR_OPT_CORRECTION] != 0 ? "on" : "off");
    fprintf(out, "%-26s %7s %8s   %-18s   %s\n", "", "count", "rate", "99% interval",
            "99% exact (Clopper-Pearson)");
    static const char *const names[4] = {"verdict 'out of spec'", "chi-square rejected",
                                         "a component rejected", "nothing testable"};
    for (int k = 0; k < 4; k++)
        fprintf(out, "%-26s %7d %8.4f   [%.4f, %.4f]   [%.4f, %.4f]\n", names[k],
                (int)r->counts[IGEA_SIM_MC_FAILED + k], r->rates[3 * k], r->rates[3 * k + 1],
                r->rates[3 * k + 2], r->cp99[2 * k], r->cp99[2 * k + 1]);
    fprintf(out, "mean c (sigma_w^2 estimate) %.4f; mean components tested %.2f\n",
            r->counts[IGEA_SIM_MC_MEAN_SCALE], r->counts[IGEA_SIM_MC_MEAN_TESTED]);
    fprintf(out, "verdict rule %s: mean overall size over the testable flights %.6f\n\n",
            igea_choice_name(IGEA_CHOICE_STATS_VERDICT, a->verdict),
            r->counts[IGEA_SIM_MC_MEAN_SIZE]);
    text_components(out, f, r);
    if (a->pool > 0 && p[IGEA_SIM_POOL_POOLS] > 0)
        fprintf(out, "\npooled over %d flights: %d of %d pools 'out of spec' (%.4f, 99%% "
                     "interval [%.4f, %.4f], exact [%.4f, %.4f]); verdict rule %s: mean "
                     "overall size of the pooled rule %.6f\n", a->pool,
                (int)p[IGEA_SIM_POOL_FAILED], (int)p[IGEA_SIM_POOL_POOLS], p[IGEA_SIM_POOL_RATE],
                p[IGEA_SIM_POOL_CI99_LO], p[IGEA_SIM_POOL_CI99_HI], r->pool_cp[0], r->pool_cp[1],
                igea_choice_name(IGEA_CHOICE_STATS_VERDICT, a->verdict),
                p[IGEA_SIM_POOL_MEAN_SIZE]);
}

/* The pooled verdicts of --pool by the --verdict rule (igea_sim_pool_ex) and
 * the exact interval of their rate. */
static int pool_flights(const mc_args *a, mc_result *r)
{
    const double *p = r->pooled;
    int ec = cli_status(igea_sim_pool_ex(a->flights, r->table, a->flights, a->pool, a->eqo,
                                         r->pooled), "montecarlo");
    r->pool_cp[0] = r->pool_cp[1] = NAN;
    if (!ec && p[IGEA_SIM_POOL_POOLS] > 0)
        ec = cli_status(igea_sim_interval_cp(p[IGEA_SIM_POOL_FAILED], p[IGEA_SIM_POOL_POOLS],
                                             0.99, r->pool_cp), "montecarlo");
    return ec;
}

static int parse(int argc, char **argv, mc_args *a, cli_flight_args *fa)
{
    cli_flight_defaults();
    igea_eqerr_defaults(A.eqo);
    A.ar_method = -1; /* not given: the library's default */
    int ec = cli_parse(&command, argc, argv);
    if (A.eqo[IGEA_EQERR_OPT_AR] != 0 && !A.ar_given)
        A.eqo[IGEA_EQERR_OPT_AR_ESTIMATE] = 1;
    if (A.ar_method >= 0)
        A.eqo[IGEA_EQERR_OPT_AR_METHOD] = A.ar_method;
    *a = A;
    *fa = cli_flight_opts;
    if (ec)
        return ec;
    if (a->flights < 1 || a->first < 0 || a->threads < 0 || a->pool < 0) {
        cli_error("montecarlo: --flights >= 1, --first-flight >= 0, --threads >= 0, --pool >= 0");
        return CLI_USAGE;
    }
    if (a->pool > a->flights) {
        cli_error("montecarlo: --pool %d pools more flights than --flights %d gives", a->pool,
                  a->flights);
        return CLI_USAGE;
    }
    if (a->ar_method >= 0 && (a->eqo[IGEA_EQERR_OPT_AR] == 0 || a->ar_given)) {
        cli_error("montecarlo: --ar-method %s estimates phi: it needs --ar P (not --ar-given)",
                  igea_choice_name(IGEA_CHOICE_NOISE_AR_METHOD, a->ar_method));
        return CLI_USAGE;
    }
    a->eqo[IGEA_EQERR_OPT_VERDICT] = a->verdict;
    a->eqo[IGEA_EQERR_OPT_OVERALL_SIZE] = 1;
    return cli_check_opts("montecarlo", IGEA_MODULE_EQERR, igea_eqerr_check_opts(a->eqo));
}

int cmd_montecarlo(int argc, char **argv)
{
    mc_args a;
    cli_flight_args fa;
    int ec = parse(argc, argv, &a, &fa);
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    cli_flight f;
    mc_result r;
    memset(&r, 0, sizeof r);
    cli_out table = CLI_OUT_INIT, rep = CLI_OUT_INIT;
    if ((ec = a.S ? own_geometry(&a, &fa, &f) : cli_flight_build(&fa, &f, "montecarlo")))
        goto done;
    r.table = malloc(sizeof(double) * (size_t)a.flights * IGEA_SIM_MC_TABLE_COLS_Z);
    r.ct = calloc((size_t)f.N, sizeof(int));
    r.cr = calloc((size_t)f.N, sizeof(int));
    if (!r.table || !r.ct || !r.cr) {
        ec = cli_oom("the per-flight tables");
        goto done;
    }
    /* The per-flight table's temporary exists from the start: a run that
     * fails or is killed leaves the old file as it was. */
    if (a.out && (ec = cli_out_open(&table, a.out)))
        goto done;
    /* the flights run in threads of their own: OpenBLAS in each one thread */
    int blas = cli_blas_threads(1);
    ec = run_flights(&a, &fa, &f, &r);
    cli_blas_threads(blas);
    if (ec)
        goto done;
    if (a.pool > 0 && (ec = pool_flights(&a, &r)))
        goto done;
    if (a.plot && (ec = cli_svg_montecarlo(a.plot, a.flights, f.N, r.ct, r.cr,
                                           a.eqo[IGEA_EQERR_OPT_ALPHA])))
        goto done;
    if (a.out) {
        write_table(table.f, &a, &fa, &r);
        if ((ec = cli_out_commit(&table)))
            goto done;
    }
    if (!(ec = cli_out_open(&rep, NULL))) {
        (a.json ? json_report : text_report)(rep.f, &a, &fa, &f, &r);
        ec = cli_out_commit(&rep);
    }
done:
    cli_out_abort(&table);
    free(r.table);
    free(r.ct);
    free(r.cr);
    cli_flight_free(&f);
    return ec;
}
