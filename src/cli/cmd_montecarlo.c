/* igea montecarlo - many simulated flights judged by the equivalent-error
 * test: its size (false-alarm rate) and power, with 99% intervals. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

/* cmd_simulate.c / cmd_envfun.c */
void *simmodel_new(void);
void simmodel_free(void *p);
void simmodel_help(void);
int simmodel_option(void *p, int argc, char **argv, int *i);
int simmodel_build(void *p);
void simmodel_get(void *p, int *m, int *N, const double **S, const double **sigma,
                  const double **spec, const double **xval, const int **xfix,
                  const double **opts, int *seed, const int **codes);
int simmodel_status(int st, const char *context);
const char *envfun_term_name(int code);

/* Wilson score interval of k successes in n at 99% (z = 2.5758). */
static void wilson(double k, double n, double *lo, double *hi)
{
    double z = 2.5758293035489004, p = k / n, z2 = z * z / n;
    double c = (p + z2 / 2) / (1 + z2);
    double h = z * sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z2);
    *lo = fmax(0.0, c - h);
    *hi = fmin(1.0, c + h);
}

static void montecarlo_help(void)
{
    printf(
"usage: igea montecarlo [options]\n"
"\n"
"Monte Carlo proof of the equivalent-error test (seed 000): simulates many\n"
"flights with known truth (as 'igea simulate') and judges each with the test\n"
"of 'igea eqerr' (eig route), reporting how often the verdict is 'out of\n"
"spec', the chi-square and per-component rejection rates with 99%% (Wilson)\n"
"intervals, and the mean sigma_w^2 estimate. With the truth in spec (X ~ N(0,\n"
"I), sigma_w = 1) the rates are the test's size; with a term set to K x spec\n"
"(--x) they are its power. Flight f uses the random stream (seed, f): results\n"
"do not depend on --threads.\n"
"\n");
    simmodel_help();
    printf(
"your own flight geometry (instead of the model above):\n"
"  --S FILE            S (rows epoch-major, one column per term), as igea eqerr\n"
"  --sigma-file FILE   stated tracking 1-sigma per row\n"
"  --spec-file FILE    1-sigma spec per term (X ~ N(0, I); --x does not apply)\n"
"test:\n"
"  --flights N         number of flights (2000)\n"
"  --first F           index of the first flight (0)\n"
"  --threads T         worker threads, 0 = all processors (0)\n"
"  --alpha A           significance level (0.01)\n"
"  --lambda-test L     test components with lambda >= L (10)\n"
"  --no-correct        no tracking-accuracy (sigma_w) correction\n"
"  --bias-correct      sigma_w^2 = mean(g^2 - lambda) [D]\n"
"  --pool F            also pool consecutive groups of F flights (METHODS 1.2\n"
"                      step 6) and report the pooled verdict rate\n"
"output:\n"
"  --out FILE          per-flight table: flight chi2 dof n_reject c\n"
"  --json              machine-readable summary\n"
"Progress goes to stderr when it is a terminal.\n"
"\n"
"example:\n"
"  igea montecarlo --flights 2000 --seed 1                      # size\n"
"  igea montecarlo --flights 2000 --sigma-w 1.8 --no-correct    # misstated sigma\n"
"  igea montecarlo --flights 1000 --x gyro_bias_y=2 --pool 4    # power, pooled\n"
"  igea montecarlo --S S.txt --sigma-file sigma.txt --spec-file spec.txt\n");
}

int cmd_montecarlo(int argc, char **argv)
{
    if (cli_one_stdin(argc, argv))
        return CLI_USAGE;
    void *mdl = simmodel_new();
    int nflights = 2000, first = 0, nthreads = 0, pool = 0, json = 0, ec = CLI_OK;
    double eqo[IGEA_EQERR_OPT_LEN];
    const char *out = NULL, *S_file = NULL, *sigma_arg = NULL, *spec_file = NULL;
    if (!mdl) {
        cli_error("out of memory");
        return CLI_SOFTWARE;
    }
    igea_eqerr_defaults(eqo);
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i], *v;
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) { montecarlo_help(); simmodel_free(mdl); return CLI_OK; }
        int r = simmodel_option(mdl, argc, argv, &i);
        if (r >= 0) {
            if (r) { simmodel_free(mdl); return r; }
            continue;
        }
        int *iv = NULL;
        double *dv = NULL;
        if (!strcmp(o, "--flights")) iv = &nflights;
        else if (!strcmp(o, "--first")) iv = &first;
        else if (!strcmp(o, "--threads")) iv = &nthreads;
        else if (!strcmp(o, "--pool")) iv = &pool;
        else if (!strcmp(o, "--alpha")) dv = &eqo[IGEA_EQERR_OPT_ALPHA];
        else if (!strcmp(o, "--lambda-test")) dv = &eqo[IGEA_EQERR_OPT_LAMBDA_TEST];
        else if (!strcmp(o, "--no-correct")) { eqo[IGEA_EQERR_OPT_CORRECT] = 0; continue; }
        else if (!strcmp(o, "--bias-correct")) { eqo[IGEA_EQERR_OPT_BIAS_CORRECT] = 1; continue; }
        else if (!strcmp(o, "--json")) { json = 1; continue; }
        else if (!strcmp(o, "--out") || !strcmp(o, "--S") || !strcmp(o, "--sigma-file") ||
                 !strcmp(o, "--spec-file")) {
            const char **dst = !strcmp(o, "--out") ? &out : !strcmp(o, "--S") ? &S_file
                             : !strcmp(o, "--sigma-file") ? &sigma_arg : &spec_file;
            if (!(*dst = cli_optarg(argc, argv, &i))) { simmodel_free(mdl); return CLI_USAGE; }
            continue;
        } else {
            cli_error("montecarlo: unknown option %s (see --help)", o);
            simmodel_free(mdl);
            return CLI_USAGE;
        }
        if (!(v = cli_optarg(argc, argv, &i)) ||
            (iv ? cli_parse_int(o + 2, v, iv) : cli_parse_double(o + 2, v, dv))) {
            simmodel_free(mdl);
            return CLI_USAGE;
        }
    }
    if (nflights < 1 || first < 0 || nthreads < 0 || pool < 0 ||
        !(eqo[IGEA_EQERR_OPT_ALPHA] > 0 && eqo[IGEA_EQERR_OPT_ALPHA] < 1)) {
        cli_error("montecarlo: --flights >= 1, --first >= 0, --threads >= 0, --pool >= 0, "
                  "0 < --alpha < 1");
        simmodel_free(mdl);
        return CLI_USAGE;
    }
    if ((ec = simmodel_build(mdl))) {
        simmodel_free(mdl);
        return ec;
    }
    int m, N, seed;
    const double *S, *sigma, *spec, *xval, *opts;
    const int *xfix, *codes;
    simmodel_get(mdl, &m, &N, &S, &sigma, &spec, &xval, &xfix, &opts, &seed, &codes);
    /* a flight geometry of your own: S, sigma and spec from files */
    double *fS = NULL, *fsig = NULL, *fspec = NULL, *fx = NULL;
    int *ffix = NULL;
    if (S_file) {
        cli_matrix a, b, c;
        int e2;
        if (!sigma_arg || !spec_file) {
            cli_error("montecarlo: --S needs --sigma-file and --spec-file");
            simmodel_free(mdl);
            return CLI_USAGE;
        }
        if ((e2 = cli_read_matrix(S_file, &a))) { simmodel_free(mdl); return e2; }
        if ((e2 = cli_read_matrix(sigma_arg, &b))) { cli_matrix_free(&a); simmodel_free(mdl); return e2; }
        if ((e2 = cli_read_matrix(spec_file, &c))) {
            cli_matrix_free(&a); cli_matrix_free(&b); simmodel_free(mdl); return e2;
        }
        int bad = a.rows % 3 != 0 || a.rows > 100000000L || b.rows * b.cols != a.rows ||
                  c.rows * c.cols != a.cols;
        if (bad)
            cli_error("montecarlo: S must have 3 rows per epoch, sigma one value per row of S "
                      "and spec one per column (%ld x %d, %ld, %ld)", a.rows, a.cols,
                      b.rows * b.cols, c.rows * c.cols);
        m = (int)a.rows;
        N = a.cols;
        fS = bad ? NULL : malloc(sizeof(double) * (size_t)m * N);
        fx = calloc((size_t)N + 1, sizeof(double));
        ffix = calloc((size_t)N + 1, sizeof(int));
        if (!bad && fS && fx && ffix)
            for (int i = 0; i < m; i++)
                for (int j = 0; j < N; j++)
                    fS[i + (size_t)j * m] = a.v[(size_t)i * N + j];
        cli_matrix_free(&a);
        fsig = b.v;
        fspec = c.v;
        if (bad || !fS || !fx || !ffix) {
            free(fS); free(fsig); free(fspec); free(fx); free(ffix);
            simmodel_free(mdl);
            return bad ? CLI_DATAERR : cli_oom("the flight geometry");
        }
        int mfix = 0, mN, mm, ms;
        const double *d1, *d2, *d3, *d4, *d5;
        const int *i1, *i2;
        simmodel_get(mdl, &mm, &mN, &d1, &d2, &d3, &d4, &i1, &d5, &ms, &i2);
        for (int j = 0; j < mN; j++)
            mfix |= i1[j];
        if (mfix) {
            cli_error("montecarlo: --x applies to the simulated model, not to --S files");
            free(fS); free(fsig); free(fspec); free(fx); free(ffix);
            simmodel_free(mdl);
            return CLI_USAGE;
        }
        S = fS;
        sigma = fsig;
        spec = fspec;
        xval = fx;
        xfix = ffix;
    }
    int anyfix = 0;
    for (int j = 0; j < N; j++)
        anyfix |= xfix[j];

    cli_out o = CLI_OUT_INIT;
    size_t nf = (size_t)nflights;
    double *chi2 = malloc(nf * sizeof(double)), *scale = malloc(nf * sizeof(double));
    int *dof = malloc(nf * sizeof(int)), *nrej = malloc(nf * sizeof(int));
    int *ct = calloc((size_t)N, sizeof(int)), *cr = calloc((size_t)N, sizeof(int));
    int *ct1 = malloc((size_t)N * sizeof(int)), *cr1 = malloc((size_t)N * sizeof(int));
    if (!chi2 || !scale || !dof || !nrej || !ct || !cr || !ct1 || !cr1) {
        ec = cli_oom("the per-flight tables");
        goto done;
    }
    /* The per-flight table's temporary exists from the start: a run that
     * fails or is killed leaves the old file as it was. */
    if (out && (ec = cli_out_open(&o, out)))
        goto done;
    double tot[IGEA_SIM_MC_LEN] = {0};
    int tty = isatty(2), chunk = 1000;
    for (int done_f = 0; done_f < nflights; done_f += chunk) {
        int n = nflights - done_f < chunk ? nflights - done_f : chunk;
        double c[IGEA_SIM_MC_LEN];
        int st = igea_sim_montecarlo(m, N, S, m, sigma, 1, spec, xval, anyfix ? xfix : NULL,
                                     opts, seed, eqo, first + done_f, n, nthreads, c, ct1,
                                     cr1, chi2 + done_f, dof + done_f, nrej + done_f,
                                     scale + done_f);
        if (st == -12) {
            cli_error("montecarlo: invalid test options");
            ec = CLI_USAGE;
            goto done;
        }
        if ((ec = simmodel_status(st, "montecarlo")))
            goto done;
        for (int k = IGEA_SIM_MC_FLIGHTS; k <= IGEA_SIM_MC_NOT_TESTABLE; k++)
            tot[k] += c[k];
        for (int j = 0; j < N; j++) {
            ct[j] += ct1[j];
            cr[j] += cr1[j];
        }
        if (tty && nflights > chunk)
            fprintf(stderr, "\rigea montecarlo: %d / %d flights", done_f + n, nflights);
    }
    if (tty && nflights > chunk)
        fputc('\n', stderr);
    {
        double sc = 0, sd = 0;
        int nt = 0;
        for (size_t f = 0; f < nf; f++)
            if (dof[f] > 0) {
                sc += scale[f];
                sd += dof[f];
                nt++;
            }
        tot[IGEA_SIM_MC_MEAN_SCALE] = nt ? sc / nt : NAN;
        tot[IGEA_SIM_MC_MEAN_TESTED] = nt ? sd / nt : 0;
    }
    /* pooled verdicts */
    int npools = 0, pool_fail = 0;
    if (pool > 0) {
        double *pc = malloc((size_t)pool * sizeof(double));
        int *pd = malloc((size_t)pool * sizeof(int)), *pr = malloc((size_t)pool * sizeof(int));
        if (!pc || !pd || !pr) {
            free(pc); free(pd); free(pr);
            ec = cli_oom("the pooled verdicts");
            goto done;
        }
        for (int g = 0; g + pool <= nflights; g += pool) {
            int k = 0;
            for (int f = g; f < g + pool; f++)
                if (dof[f] > 0) {
                    pc[k] = chi2[f];
                    pd[k] = dof[f];
                    pr[k] = nrej[f];
                    k++;
                }
            npools++;
            if (k == 0)
                continue;
            double info[IGEA_STATS_INFO_LEN];
            int st = igea_stats_pool(k, pc, pd, pr, NULL, eqo[IGEA_EQERR_OPT_ALPHA], info);
            if (st == 0 && info[IGEA_STATS_INFO_PASSED] != 1.0)
                pool_fail++;
        }
        free(pc); free(pd); free(pr);
    }
    if (out) {
        fprintf(o.f, "# flight chi2 dof n_reject c   (seed %d)\n", seed);
        for (size_t f = 0; f < nf; f++)
            fprintf(o.f, "%d %.17g %d %d %.17g\n", first + (int)f, chi2[f], dof[f], nrej[f],
                    scale[f]);
        if ((ec = cli_out_commit(&o)))
            goto done;
    }
    double alpha = eqo[IGEA_EQERR_OPT_ALPHA], n = tot[IGEA_SIM_MC_FLIGHTS], lo, hi;
    const char *labels[4] = {"failed", "chi2_reject", "any_reject", "not_testable"};
    if (json) {
        printf("{\n  \"flights\": %d,\n  \"seed\": %d,\n  \"first\": %d,\n  \"alpha\": ",
               nflights, seed, first);
        cli_json_num(stdout, alpha);
        printf(",\n  \"correct_tracking\": %s,\n  \"sigma_w\": ",
               eqo[IGEA_EQERR_OPT_CORRECT] != 0 ? "true" : "false");
        cli_json_num(stdout, opts[IGEA_SIM_OPT_SIGMA_W]);
        for (int k = 0; k < 4; k++) {
            double cnt = tot[IGEA_SIM_MC_FAILED + k];
            wilson(cnt, n, &lo, &hi);
            printf(",\n  \"%s\": {\"count\": %d, \"rate\": ", labels[k], (int)cnt);
            cli_json_num(stdout, cnt / n);
            printf(", \"ci99\": [");
            cli_json_num(stdout, lo);
            printf(", ");
            cli_json_num(stdout, hi);
            printf("]}");
        }
        printf(",\n  \"mean_c\": ");
        cli_json_num(stdout, tot[IGEA_SIM_MC_MEAN_SCALE]);
        printf(",\n  \"mean_tested\": ");
        cli_json_num(stdout, tot[IGEA_SIM_MC_MEAN_TESTED]);
        printf(",\n  \"comp_tested\": ");
        cli_json_iarray(stdout, ct, N);
        printf(",\n  \"comp_reject\": ");
        cli_json_iarray(stdout, cr, N);
        if (pool > 0) {
            printf(",\n  \"pool\": {\"size\": %d, \"pools\": %d, \"failed\": %d}", pool,
                   npools, pool_fail);
        }
        printf("\n}\n");
    } else {
        printf("igea montecarlo: %d flights (seed %d, first %d), %d rows x %d terms\n",
               nflights, seed, first, m, N);
        printf("truth: sigma_w %g, ar1 %g, growth %g, outliers %g", opts[IGEA_SIM_OPT_SIGMA_W],
               opts[IGEA_SIM_OPT_AR1], opts[IGEA_SIM_OPT_GROWTH],
               opts[IGEA_SIM_OPT_OUTLIER_PROB]);
        for (int j = 0; j < N; j++)
            if (xfix[j])
                printf(", %s = %g x spec", envfun_term_name(codes[j]), xval[j]);
        printf("; test: alpha %g, sigma_w correction %s\n\n", alpha,
               eqo[IGEA_EQERR_OPT_CORRECT] != 0 ? "on" : "off");
        printf("%-26s %7s %8s   %s\n", "", "count", "rate", "99% interval");
        const char *names[4] = {"verdict 'out of spec'", "chi-square rejected",
                                "a component rejected", "nothing testable"};
        for (int k = 0; k < 4; k++) {
            double cnt = tot[IGEA_SIM_MC_FAILED + k];
            wilson(cnt, n, &lo, &hi);
            printf("%-26s %7d %8.4f   [%.4f, %.4f]\n", names[k], (int)cnt, cnt / n, lo, hi);
        }
        printf("mean c (sigma_w^2 estimate) %.4f; mean components tested %.2f\n\n",
               tot[IGEA_SIM_MC_MEAN_SCALE], tot[IGEA_SIM_MC_MEAN_TESTED]);
        printf("%9s %8s %8s %8s   %s\n", "component", "tested", "rejected", "rate",
               "99% interval");
        for (int j = 0; j < N; j++) {
            if (!ct[j])
                continue;
            wilson(cr[j], ct[j], &lo, &hi);
            printf("%9d %8d %8d %8.4f   [%.4f, %.4f]\n", j + 1, ct[j], cr[j],
                   (double)cr[j] / ct[j], lo, hi);
        }
        if (pool > 0 && npools > 0) {
            wilson(pool_fail, npools, &lo, &hi);
            printf("\npooled over %d flights: %d of %d pools 'out of spec' (%.4f, 99%% "
                   "interval [%.4f, %.4f])\n", pool, pool_fail, npools,
                   (double)pool_fail / npools, lo, hi);
        }
    }
done:
    cli_out_abort(&o);
    free(chi2);
    free(scale);
    free(dof);
    free(nrej);
    free(ct);
    free(cr);
    free(ct1);
    free(cr1);
    free(fS);
    free(fsig);
    free(fspec);
    free(fx);
    free(ffix);
    simmodel_free(mdl);
    return ec;
}
