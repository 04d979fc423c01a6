/* igea eqerr, igea test - the equivalent-error accuracy assessment
 * (seed 000, METHODS 1.2) from files, and judging saved results. */
#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char *flag_name(int flag)
{
    switch (flag) {
    case IGEA_STATS_SIGMAW_CONVERGED: return "converged";
    case IGEA_STATS_SIGMAW_NOT_ESTIMABLE: return "not_estimable";
    case IGEA_STATS_SIGMAW_NO_CONVERGENCE: return "no_convergence";
    default: return "off";
    }
}

/* The seed's Tables 1-2 plus the chi-square line (shared by both commands). */
static void report_components(FILE *f, int n, const double *xhat,
                              const double *lambda, const double *z,
                              const int *reject, double zc)
{
    fprintf(f, "%5s %13s %13s %11s %10s %9s  %s\n", "comp", "eigenvalue",
            "equiv_error", "precision", "threshold", "z", "verdict");
    for (int i = 0; i < n; i++) {
        if (reject[i] < 0)
            continue;
        double thr = sqrt(1.0 + 1.0 / lambda[i]) * zc;
        fprintf(f, "%5d %13.6e %13.6f %11.4e %10.4f %9.4f  %s\n", i + 1, lambda[i],
                xhat[i], 1.0 / sqrt(lambda[i]), thr, z[i],
                reject[i] ? "REJECT" : "pass");
    }
}

static void report_chi2(FILE *f, const double *info, double alpha)
{
    double T = info[IGEA_STATS_INFO_CHI2], crit = info[IGEA_STATS_INFO_CHI2_CRIT];
    fprintf(f, "chi-square: T = %.4f with %d dof; chi2_%g(%d) = %.3f; p-value %.4g -> %s\n",
            T, (int)info[IGEA_STATS_INFO_DOF], alpha, (int)info[IGEA_STATS_INFO_DOF], crit,
            info[IGEA_STATS_INFO_P_VALUE], T < crit ? "pass" : "REJECT");
    int nrej = (int)info[IGEA_STATS_INFO_N_REJECT];
    if (info[IGEA_STATS_INFO_PASSED] == 1.0)
        fprintf(f, "verdict: ACCEPTED - no component rejected and T < chi2 critical value "
                   "(alpha = %g)\n", alpha);
    else
        fprintf(f, "verdict: REJECTED - %d component(s) rejected%s (alpha = %g)\n", nrej,
                T < crit ? "" : ", chi-square test failed", alpha);
}

static void json_test_fields(FILE *f, const double *info)
{
    fprintf(f, "  \"n_test\": %d,\n  \"chi2\": ", (int)info[IGEA_STATS_INFO_N_TEST]);
    cli_json_num(f, info[IGEA_STATS_INFO_CHI2]);
    fprintf(f, ",\n  \"dof\": %d,\n  \"chi2_crit\": ", (int)info[IGEA_STATS_INFO_DOF]);
    cli_json_num(f, info[IGEA_STATS_INFO_CHI2_CRIT]);
    fputs(",\n  \"z_crit\": ", f);
    cli_json_num(f, info[IGEA_STATS_INFO_Z_CRIT]);
    fputs(",\n  \"p_value\": ", f);
    cli_json_num(f, info[IGEA_STATS_INFO_P_VALUE]);
    fprintf(f, ",\n  \"n_reject\": %d,\n  \"passed\": %s", (int)info[IGEA_STATS_INFO_N_REJECT],
            info[IGEA_STATS_INFO_PASSED] == 1.0 ? "true" : "false");
}

/* ---------------------------------------------------------------------- */
static void eqerr_help(void)
{
    printf(
"usage: igea eqerr --S FILE --dw FILE --sigma FILE|NUMBER [--spec FILE] [options]\n"
"\n"
"Equivalent-error accuracy assessment of one flight (seed 000; METHODS 1.2).\n"
"Model dw = S X + e: S holds one row per observation (epoch-major x, y, z rows)\n"
"and one column per instrument error term (the velocity environment functions,\n"
"per unit of each coefficient); dw the telemetry-minus-tracking velocity\n"
"differences; sigma the tracking 1-sigma per row (or one number for all rows);\n"
"spec the 1-sigma specification of each term, which scales S's columns so that\n"
"the errors are in multiples of spec (omit it if S is already scaled).\n"
"\n"
"The weighted normal matrix S'K^-1 S is decomposed (dsyevd); each component\n"
"with eigenvalue lambda_i >= lambda_test gives an equivalent error Xhat_i that is\n"
"N(0, 1 + 1/lambda_i) when the system is within spec. The tracking accuracy is\n"
"first corrected from the small eigenvalues (sigma_w, METHODS 1.2 step 3).\n"
"Each component is tested against z_{1-alpha/2} sqrt(1 + 1/lambda_i), and all\n"
"together by T = sum Xhat_i^2/(1 + 1/lambda_i) against chi2_alpha(n_test).\n"
"\n"
"Inputs: text (whitespace or commas, '#' comments) or .npy (float64), read in\n"
"row blocks twice (the decomposition, then the residuals): either route needs\n"
"O(N^2) memory whatever the flight length. One input may be '-', standard\n"
"input; a pipe or FIFO is copied to a temporary file for the second pass.\n"
"\n"
"options:\n"
"  --S FILE            environment functions, m rows x N columns\n"
"  --dw FILE           velocity differences, m values (one column)\n"
"  --sigma FILE|NUM    tracking 1-sigma per row (m values), or one number\n"
"  --spec FILE         N term specs (1-sigma), any layout\n"
"  --alpha A           significance level (default 0.01)\n"
"  --lambda-test L     test components with lambda >= L (default 10)\n"
"  --lambda-small L    small eigenvalues for sigma_w: lambda <= L (default 0.1)\n"
"  --n-min N           fewest small eigenvalues to estimate sigma_w (default 5)\n"
"  --tol T             stop when |sigma_w^2 - 1| <= T (default 0.05)\n"
"  --max-iter N        sigma_w iterations (default 10)\n"
"  --no-correction     do not correct the tracking accuracy\n"
"  --bias-correct      sigma_w^2 = mean(g^2 - lambda) over the small set\n"
"  --clamp             never make the tracking weights more optimistic (c >= 1)\n"
"  --z-crit Z          impose the normal critical value (e.g. 2.58 as in the\n"
"                      seed's tables) instead of the exact z_{1-alpha/2}\n"
"  --route eig|svd     normal matrix + dsyevd (default), or the SVD of the\n"
"                      weighted S through its streamed QR factor (dtpqrt):\n"
"                      resolves eigenvalues down to eps^2 lambda_1 instead of\n"
"                      eps lambda_1, at about twice the cost\n"
"  --residuals FILE    write the per-row residuals dw - S D P_t Xhat_t\n"
"  --json              machine-readable output (field names as igea.eqerr)\n"
"  --out FILE          write the report there (atomically) instead of stdout\n"
"\n"
"exit status: 0 accepted, 1 rejected, 64 usage, 65 bad input, 66 missing input,\n"
"70 numerical failure (e.g. no component precise enough to test), 74 I/O error.\n"
"\n"
"example (the bundled flight):\n"
"  cd examples/flight\n"
"  igea eqerr --S S.txt --dw dw.txt --sigma sigma.txt --spec spec.txt\n"
"  igea eqerr --S S.txt --dw dw.txt --sigma 0.01 --spec spec.txt --json --out f1.json\n");
}

typedef struct {
    const char *S, *dw, *sigma, *spec, *residuals, *out;
    double sigma_value;
    int sigma_is_number, json;
    double opts[IGEA_EQERR_OPT_LEN];
} eqerr_args;

/* Open the three streamed inputs in lockstep. */
typedef struct {
    cli_reader *S, *dw, *sig;
    int N;
    double *sbuf, *dbuf, *gbuf;
    long block;
} streams;

static void streams_close(streams *s)
{
    cli_reader_close(s->S);
    cli_reader_close(s->dw);
    cli_reader_close(s->sig);
    free(s->sbuf);
    free(s->dbuf);
    free(s->gbuf);
    memset(s, 0, sizeof *s);
}

static int streams_open(const eqerr_args *a, streams *s)
{
    memset(s, 0, sizeof *s);
    int ec = cli_reader_open_twice(a->S, &s->S);
    if (!ec)
        ec = cli_reader_open_twice(a->dw, &s->dw);
    if (!ec && !a->sigma_is_number)
        ec = cli_reader_open_twice(a->sigma, &s->sig);
    if (ec) {
        streams_close(s);
        return ec;
    }
    if (cli_reader_cols(s->dw) != 1) {
        cli_error("%s: dw must be one column, found %d", a->dw, cli_reader_cols(s->dw));
        streams_close(s);
        return CLI_DATAERR;
    }
    if (s->sig && cli_reader_cols(s->sig) != 1) {
        cli_error("%s: sigma must be one column, found %d", a->sigma, cli_reader_cols(s->sig));
        streams_close(s);
        return CLI_DATAERR;
    }
    s->N = cli_reader_cols(s->S);
    s->block = 1 + (4L << 20) / (8L * (s->N + 2)); /* about 4 MB of rows */
    s->block -= s->block % 3;
    if (s->block < 3)
        s->block = 3;
    s->sbuf = malloc((size_t)s->block * s->N * sizeof(double));
    s->dbuf = malloc((size_t)s->block * sizeof(double));
    s->gbuf = malloc((size_t)s->block * sizeof(double));
    if (!s->sbuf || !s->dbuf || !s->gbuf) {
        cli_error("out of memory (row blocks of %s)", a->S);
        streams_close(s);
        return CLI_SOFTWARE;
    }
    return CLI_OK;
}

/* All three again from their first row (the second pass). */
static int streams_rewind(streams *s)
{
    int ec = cli_reader_rewind(s->S);
    if (!ec)
        ec = cli_reader_rewind(s->dw);
    if (!ec && s->sig)
        ec = cli_reader_rewind(s->sig);
    return ec;
}

/* Next block of all three; *n rows (0 at the end). */
static int streams_next(const eqerr_args *a, streams *s, long *n)
{
    long ns, nd, ng;
    int ec = cli_reader_next(s->S, s->block, s->sbuf, &ns);
    if (!ec)
        ec = cli_reader_next(s->dw, s->block, s->dbuf, &nd);
    if (ec)
        return ec;
    if (s->sig) {
        ec = cli_reader_next(s->sig, s->block, s->gbuf, &ng);
        if (ec)
            return ec;
    } else {
        ng = ns;
        for (long i = 0; i < ns; i++)
            s->gbuf[i] = a->sigma_value;
    }
    if (ns != nd || ns != ng) {
        const char *shorter = nd < ns ? a->dw : (ng < ns ? a->sigma : a->S);
        cli_error("%s ends early: %s, %s%s%s must have the same number of rows", shorter,
                  a->S, a->dw, a->sigma_is_number ? "" : ", ", a->sigma_is_number ? "" : a->sigma);
        return CLI_DATAERR;
    }
    *n = ns;
    return CLI_OK;
}

static int read_spec(const char *path, const char *S, int N, double **spec)
{
    cli_matrix m;
    int ec = cli_read_matrix(path, &m);
    if (ec)
        return ec;
    if (m.rows * m.cols != N) {
        cli_error("%s: %d columns, but %s holds %ld specs (one per column of S)", S, N, path,
                  m.rows * m.cols);
        cli_matrix_free(&m);
        return CLI_DATAERR;
    }
    for (int j = 0; j < N; j++)
        if (!(m.v[j] > 0)) {
            cli_error("%s: spec %d is %g; specs are 1-sigma values and must be > 0", path,
                      j + 1, m.v[j]);
            cli_matrix_free(&m);
            return CLI_DATAERR;
        }
    *spec = m.v;
    return CLI_OK;
}

static int check_sigma_block(const eqerr_args *a, const double *g, long n, long row0)
{
    if (a->sigma_is_number)
        return CLI_OK;
    for (long i = 0; i < n; i++)
        if (!(g[i] > 0)) {
            cli_error("%s: row %ld: tracking sigma %g must be > 0", a->sigma, row0 + i + 1, g[i]);
            return CLI_DATAERR;
        }
    return CLI_OK;
}

static int parse_eqerr(int argc, char **argv, eqerr_args *a)
{
    memset(a, 0, sizeof *a);
    igea_eqerr_defaults(a->opts);
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i], *v;
        int ec = CLI_OK;
        double x;
#define NEED() do { if (!(v = cli_optarg(argc, argv, &i))) return CLI_USAGE; } while (0)
#define DOPT(name, idx) else if (!strcmp(o, name)) { NEED(); if ((ec = cli_parse_double(o, v, &x))) return ec; a->opts[idx] = x; }
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) {
            eqerr_help();
            return -1;
        } else if (!strcmp(o, "--S")) { NEED(); a->S = v; }
        else if (!strcmp(o, "--dw")) { NEED(); a->dw = v; }
        else if (!strcmp(o, "--sigma")) {
            NEED();
            if ((ec = cli_file_or_positive(o, v, &a->sigma_is_number, &a->sigma_value)))
                return ec;
            a->sigma = v;
        }
        else if (!strcmp(o, "--spec")) { NEED(); a->spec = v; }
        else if (!strcmp(o, "--residuals")) { NEED(); a->residuals = v; }
        else if (!strcmp(o, "--out")) { NEED(); a->out = v; }
        DOPT("--alpha", IGEA_EQERR_OPT_ALPHA)
        DOPT("--lambda-test", IGEA_EQERR_OPT_LAMBDA_TEST)
        DOPT("--lambda-small", IGEA_EQERR_OPT_LAMBDA_SMALL)
        DOPT("--n-min", IGEA_EQERR_OPT_N_MIN)
        DOPT("--tol", IGEA_EQERR_OPT_TOL)
        DOPT("--max-iter", IGEA_EQERR_OPT_MAX_ITER)
        DOPT("--z-crit", IGEA_EQERR_OPT_Z_CRIT)
        else if (!strcmp(o, "--no-correction")) a->opts[IGEA_EQERR_OPT_CORRECT] = 0;
        else if (!strcmp(o, "--bias-correct")) a->opts[IGEA_EQERR_OPT_BIAS_CORRECT] = 1;
        else if (!strcmp(o, "--clamp")) a->opts[IGEA_EQERR_OPT_CLAMP] = 1;
        else if (!strcmp(o, "--json")) a->json = 1;
        else if (!strcmp(o, "--route")) {
            NEED();
            if (!strcmp(v, "eig")) a->opts[IGEA_EQERR_OPT_ROUTE] = IGEA_EQERR_ROUTE_EIG;
            else if (!strcmp(v, "svd")) a->opts[IGEA_EQERR_OPT_ROUTE] = IGEA_EQERR_ROUTE_SVD;
            else { cli_error("--route %s: expected eig or svd", v); return CLI_USAGE; }
        } else {
            cli_error("eqerr: unknown option '%s' (see igea eqerr --help)", o);
            return CLI_USAGE;
        }
#undef DOPT
#undef NEED
    }
    if (!a->S || !a->dw || !a->sigma) {
        cli_error("eqerr: --S, --dw and --sigma are required (see igea eqerr --help)");
        return CLI_USAGE;
    }
    const char *names[] = {"--alpha", "--lambda-test", "--lambda-small", "--n-min", "--tol",
                           "--max-iter"};
    double *o = a->opts;
    int bad = -1;
    if (!(o[IGEA_EQERR_OPT_ALPHA] > 0 && o[IGEA_EQERR_OPT_ALPHA] < 1)) bad = 0;
    else if (!(o[IGEA_EQERR_OPT_LAMBDA_TEST] > 0)) bad = 1;
    else if (!(o[IGEA_EQERR_OPT_LAMBDA_SMALL] > 0)) bad = 2;
    else if (!(o[IGEA_EQERR_OPT_N_MIN] >= 1) || o[IGEA_EQERR_OPT_N_MIN] != floor(o[IGEA_EQERR_OPT_N_MIN])) bad = 3;
    else if (!(o[IGEA_EQERR_OPT_TOL] > 0)) bad = 4;
    else if (!(o[IGEA_EQERR_OPT_MAX_ITER] >= 1 && o[IGEA_EQERR_OPT_MAX_ITER] <= 1000) ||
             o[IGEA_EQERR_OPT_MAX_ITER] != floor(o[IGEA_EQERR_OPT_MAX_ITER])) bad = 5;
    if (bad >= 0) {
        cli_error("eqerr: %s is out of range (alpha in (0,1); lambdas, tol > 0; n-min, "
                  "max-iter whole numbers >= 1)", names[bad]);
        return CLI_USAGE;
    }
    if (o[IGEA_EQERR_OPT_Z_CRIT] < 0) {
        cli_error("eqerr: --z-crit must be > 0");
        return CLI_USAGE;
    }
    return CLI_OK;
}

/* Results of one flight. */
typedef struct {
    int m, N;
    double *lambda, *P, *xhat, *z, *spec, info[IGEA_STATS_INFO_LEN], rms[3];
    int *reject;
} flight;

static void flight_free(flight *r)
{
    free(r->lambda);
    free(r->P);
    free(r->xhat);
    free(r->z);
    free(r->spec);
    free(r->reject);
}

static int flight_alloc(flight *r, int N)
{
    size_t n = (size_t)N;
    r->N = N;
    r->lambda = malloc(n * sizeof(double));
    r->P = malloc(n * n * sizeof(double));
    r->xhat = malloc(n * sizeof(double));
    r->z = malloc(n * sizeof(double));
    r->reject = malloc(n * sizeof(int));
    if (!r->lambda || !r->P || !r->xhat || !r->z || !r->reject)
        return cli_oom("the results");
    return CLI_OK;
}

static void json_head(FILE *f, const flight *r, const eqerr_args *a)
{
    int N = r->N;
    fputs("{\n  \"eigenvalues\": ", f);
    cli_json_array(f, r->lambda, N);
    fputs(",\n  \"eigenvectors\": [", f);
    for (int i = 0; i < N; i++) {
        fputs(i ? ",\n    [" : "\n    [", f);
        for (int j = 0; j < N; j++) {
            if (j)
                fputs(", ", f);
            cli_json_num(f, r->P[i + (size_t)j * N]);
        }
        fputc(']', f);
    }
    fprintf(f, "],\n  \"rank\": %d,\n  \"equiv_err\": ", (int)r->info[IGEA_STATS_INFO_RANK]);
    cli_json_array(f, r->xhat, N);
    int nt = (int)r->info[IGEA_STATS_INFO_N_TEST];
    fputs(",\n  \"z\": ", f);
    cli_json_array(f, r->z, nt);
    fputs(",\n  \"reject\": [", f);
    for (int i = 0; i < nt; i++)
        fprintf(f, "%s%s", i ? ", " : "", r->reject[i] == 1 ? "true" : "false");
    fputs("],\n", f);
    json_test_fields(f, r->info);
    fputs(",\n  \"scale\": ", f);
    cli_json_num(f, r->info[IGEA_STATS_INFO_SCALE]);
    fprintf(f, ",\n  \"iterations\": %d,\n  \"n_small\": %d,\n  \"flag\": \"%s\",\n",
            (int)r->info[IGEA_STATS_INFO_ITERATIONS], (int)r->info[IGEA_STATS_INFO_N_SMALL],
            flag_name((int)r->info[IGEA_STATS_INFO_FLAG]));
    fprintf(f, "  \"alpha\": %.17g,\n  \"lambda_test\": %.17g,\n  \"route\": \"%s\",\n"
               "  \"rows\": %d,\n  \"terms\": %d,\n",
            a->opts[IGEA_EQERR_OPT_ALPHA], a->opts[IGEA_EQERR_OPT_LAMBDA_TEST],
            a->opts[IGEA_EQERR_OPT_ROUTE] == IGEA_EQERR_ROUTE_SVD ? "svd" : "eig", r->m, N);
}

static void text_report(FILE *f, const flight *r, const eqerr_args *a)
{
    const double *info = r->info;
    fprintf(f, "igea eqerr: %s (%d rows x %d terms), tracking sigma %s%s%s\n", a->S, r->m,
            r->N, a->sigma, a->spec ? ", specs " : ", S already in spec units",
            a->spec ? a->spec : "");
    fprintf(f, "route %s: rank %d of %d; lambda_1 = %.6e; %d component(s) with lambda >= %g "
               "tested\n\n",
            a->opts[IGEA_EQERR_OPT_ROUTE] == IGEA_EQERR_ROUTE_SVD ? "svd" : "eig",
            (int)info[IGEA_STATS_INFO_RANK], r->N, r->lambda[0], (int)info[IGEA_STATS_INFO_N_TEST],
            a->opts[IGEA_EQERR_OPT_LAMBDA_TEST]);
    report_components(f, r->N, r->xhat, r->lambda, r->z, r->reject, info[IGEA_STATS_INFO_Z_CRIT]);
    fprintf(f, "(threshold = sqrt(1 + 1/lambda) z_crit, z_crit = %.6f; precision = "
               "lambda^-1/2)\n\n", info[IGEA_STATS_INFO_Z_CRIT]);
    int flag = (int)info[IGEA_STATS_INFO_FLAG];
    if (flag == IGEA_STATS_SIGMAW_OFF)
        fprintf(f, "tracking-accuracy correction: off (c = 1)\n");
    else
        fprintf(f, "tracking-accuracy correction: c = %.6g (sigma_w = %.4f), %d iteration(s), "
                   "%d small eigenvalue(s) <= %g, %s\n",
                info[IGEA_STATS_INFO_SCALE], sqrt(info[IGEA_STATS_INFO_SCALE]),
                (int)info[IGEA_STATS_INFO_ITERATIONS], (int)info[IGEA_STATS_INFO_N_SMALL],
                a->opts[IGEA_EQERR_OPT_LAMBDA_SMALL], flag_name(flag));
    fprintf(f, "residual RMS per axis (x, y, z): %.6g %.6g %.6g\n", r->rms[0], r->rms[1],
            r->rms[2]);
    report_chi2(f, info, a->opts[IGEA_EQERR_OPT_ALPHA]);
}

/* Streamed, either route: pass 1 normal equations (eig) or the QR factor
 * of the weighted data (SVD), pass 2 residuals. */
static int run_streamed(const eqerr_args *a, flight *r, cli_out *res_out, cli_out *json_out)
{
    streams s;
    int ec = streams_open(a, &s);
    if (ec)
        return ec;
    int N = s.N;
    if ((ec = flight_alloc(r, N)))
        goto done;
    if (a->spec && (ec = read_spec(a->spec, a->S, N, &r->spec)))
        goto done;
    const int svd = a->opts[IGEA_EQERR_OPT_ROUTE] == IGEA_EQERR_ROUTE_SVD;
    /* eig: A (N x N), b (N), wtw (2); svd: R ((N+1) x (N+1)), row count */
    double *A = calloc((size_t)(N + 1) * (N + 1) + N + 2, sizeof(double));
    if (!A) {
        ec = cli_oom("the normal matrix");
        goto done;
    }
    double *b = A + (size_t)N * N, *wtw = b + N, qrows = 0.0;
    long rows = 0, n;
    for (;;) {
        if ((ec = streams_next(a, &s, &n)) || n == 0)
            break;
        if ((ec = check_sigma_block(a, s.gbuf, n, rows)))
            break;
        int st = svd ? igea_normal_qr_accumulate(IGEA_ROWMAJOR, (int)n, N, s.sbuf, N, s.dbuf,
                                                 s.gbuf, 1, r->spec, A, N + 1, &qrows)
                     : igea_normal_accumulate(IGEA_ROWMAJOR, (int)n, N, s.sbuf, N, s.dbuf,
                                              s.gbuf, 1, r->spec, A, N, b, wtw);
        if (st) {
            ec = cli_status(st, st == IGEA_ENONFINITE ? "eqerr: rows with NaN/Inf" : "eqerr");
            break;
        }
        rows += n;
        if (rows > 2147483647L) {
            cli_error("%s: more than 2^31-1 rows", a->S);
            ec = CLI_DATAERR;
            break;
        }
    }
    if (!ec && rows == 0) {
        cli_error("%s: no rows", a->S);
        ec = CLI_DATAERR;
    }
    if (!ec) {
        r->m = (int)rows;
        int st = svd ? igea_eqerr_solve_qr(N, A, N + 1, qrows, a->opts, r->lambda, r->P, N,
                                           r->xhat, r->z, r->reject, r->info)
                     : igea_eqerr_solve(N, A, N, b, a->opts, r->lambda, r->P, N, r->xhat,
                                        r->z, r->reject, r->info);
        if (st)
            ec = cli_status(st, "eqerr");
    }
    free(A);
    if (ec)
        goto done;

    /* Pass 2: residuals. */
    double *coef = malloc((size_t)N * sizeof(double));
    double *e = malloc((size_t)s.block * sizeof(double));
    if (!coef || !e) {
        free(coef);
        free(e);
        cli_error("out of memory (residuals of %s)", a->S);
        ec = CLI_SOFTWARE;
        goto done;
    }
    igea_eqerr_coef(N, r->P, N, r->xhat, (int)r->info[IGEA_STATS_INFO_N_TEST], r->spec, coef);
    if ((ec = streams_rewind(&s))) {
        free(coef);
        free(e);
        goto done;
    }
    double ss[6] = {0, 0, 0, 0, 0, 0};
    long row0 = 0;
    if (json_out) {
        json_head(json_out->f, r, a);
        fputs("  \"residual\": [", json_out->f);
    }
    for (;;) {
        if ((ec = streams_next(a, &s, &n)) || n == 0)
            break;
        int st = igea_eqerr_residual(IGEA_ROWMAJOR, (int)n, N, s.sbuf, N, s.dbuf, coef,
                                     (int)row0, e, ss);
        if (st) {
            ec = cli_status(st, "eqerr residuals");
            break;
        }
        for (long i = 0; i < n; i++) {
            if (res_out)
                fprintf(res_out->f, "%.17g\n", e[i]);
            if (json_out) {
                if (row0 + i)
                    fputs(", ", json_out->f);
                cli_json_num(json_out->f, e[i]);
            }
        }
        row0 += n;
    }
    for (int k = 0; k < 3; k++)
        r->rms[k] = ss[3 + k] > 0 ? sqrt(ss[k] / ss[3 + k]) : 0.0;
    free(coef);
    free(e);
done:
    streams_close(&s);
    return ec;
}

int cmd_eqerr(int argc, char **argv)
{
    if (cli_one_stdin(argc, argv))
        return CLI_USAGE;
    eqerr_args a;
    int ec = parse_eqerr(argc, argv, &a);
    if (ec)
        return ec < 0 ? CLI_OK : ec;
    cli_out out = CLI_OUT_INIT, res = CLI_OUT_INIT;
    if ((ec = cli_out_open(&out, a.out)))
        return ec;
    if (a.residuals && (ec = cli_out_open(&res, a.residuals))) {
        cli_out_abort(&out);
        return ec;
    }
    flight r;
    memset(&r, 0, sizeof r);
    /* With --json the document goes to a temporary stream first when it is
     * stdout, so that a failure never leaves half a document behind. */
    FILE *jf = NULL;
    cli_out jo = CLI_OUT_INIT;
    if (a.json) {
        errno = 0;
        jf = out.f == stdout ? tmpfile() : out.f;
        if (!jf) {
            if (errno == ENOMEM)
                ec = cli_oom("a temporary file for the JSON document");
            else {
                cli_error("cannot create a temporary file: %s", strerror(errno));
                ec = CLI_IOERR;
            }
        }
        jo.f = jf;
    }
    if (!ec)
        ec = run_streamed(&a, &r, a.residuals ? &res : NULL, a.json ? &jo : NULL);
    if (!ec) {
        if (a.json) {
            fputs("],\n  \"rms\": ", jf);
            cli_json_array(jf, r.rms, 3);
            fputs("\n}\n", jf);
            if (jf != out.f) {
                char buf[65536];
                size_t k;
                if (fflush(jf) != 0 || ferror(jf) || fseek(jf, 0, SEEK_SET) != 0) {
                    cli_error("writing a temporary file: %s", strerror(errno));
                    ec = errno == ENOMEM ? CLI_SOFTWARE : CLI_IOERR;
                }
                while (!ec && (k = fread(buf, 1, sizeof buf, jf)) > 0)
                    fwrite(buf, 1, k, out.f);
                if (!ec && ferror(jf)) {
                    cli_error("reading back a temporary file: %s", strerror(errno));
                    ec = CLI_IOERR;
                }
            }
        } else
            text_report(out.f, &r, &a);
    }
    if (jf && jf != out.f)
        fclose(jf);
    if (!ec) {
        /* the report and the residuals replace their old files together */
        cli_out both[2];
        both[0] = out;
        both[1] = res;
        ec = cli_out_commit_all(both, a.residuals ? 2 : 1);
        out = both[0];
        res = both[1];
    }
    if (ec) {
        cli_out_abort(&out);
        cli_out_abort(&res);
        flight_free(&r);
        return ec;
    }
    int passed = r.info[IGEA_STATS_INFO_PASSED] == 1.0;
    flight_free(&r);
    return passed ? CLI_OK : CLI_REJECT;
}

/* ---------------------------------------------------------------------- */
static void test_help(void)
{
    printf(
"usage: igea test --table FILE [options]\n"
"       igea test [--unit-ids LIST] [options] RESULT.json...\n"
"\n"
"Judges saved equivalent-error results (seed 000; METHODS 1.2 steps 4-6).\n"
"\n"
"--table FILE: a table of equivalent errors and their eigenvalues, like the\n"
"seed's Table 1: two columns (Xhat, lambda), or three or four columns\n"
"(component number, Xhat, lambda[, precision]). Every component with\n"
"lambda >= lambda_test is tested against z_{1-alpha/2} sqrt(1 + 1/lambda), and\n"
"all of them together by T = sum Xhat^2/(1 + 1/lambda) against chi2_alpha.\n"
"\n"
"RESULT.json...: outputs of 'igea eqerr --json' for independent flights, pooled:\n"
"T_tot = sum T_f with sum of the dof; accepted iff no component of any flight\n"
"is rejected and T_tot < chi2_alpha(dof_tot). Flights of the same inertial unit\n"
"are not independent: give --unit-ids (one id per file, e.g. 7,8,9) to have\n"
"that checked.\n"
"\n"
"options:\n"
"  --alpha A          significance level (default 0.01)\n"
"  --lambda-test L    (--table) test components with lambda >= L (default 10)\n"
"  --z-crit Z         (--table) impose z_crit, e.g. 2.58 as the seed's tables\n"
"  --unit-ids LIST    comma-separated unit ids, one per RESULT.json\n"
"  --json             machine-readable output\n"
"  --out FILE         write there (atomically) instead of stdout\n"
"\n"
"exit status: 0 accepted, 1 rejected, 64 usage, 65 bad input, 66 missing input.\n"
"\n"
"examples:\n"
"  igea test --table examples/seed000_table1.txt --z-crit 2.58\n"
"  igea test --unit-ids 1,2,3 f1.json f2.json f3.json\n");
}

/* Value of top-level key "name" in our own JSON output. */
static int json_number(const char *doc, const char *key, double *out)
{
    char pat[64];
    snprintf(pat, sizeof pat, "\"%s\":", key);
    const char *p = strstr(doc, pat);
    if (!p)
        return -1;
    p += strlen(pat);
    while (*p == ' ')
        p++;
    if (!strncmp(p, "true", 4)) { *out = 1; return 0; }
    if (!strncmp(p, "false", 5)) { *out = 0; return 0; }
    char *end;
    double v = strtod(p, &end);
    if (end == p)
        return -1;
    *out = v;
    return 0;
}

/* A JSON count: a whole number in [0, INT_MAX]. */
static int is_count(double v)
{
    return isfinite(v) && v >= 0 && v <= INT_MAX && v == floor(v);
}

/* The whole of a result file ("-": standard input). */
static char *slurp(const char *path, int *ec)
{
    int is_stdin = !strcmp(path, "-");
    FILE *f = is_stdin ? stdin : fopen(path, "rb");
    if (!f) {
        int e = errno;
        if (e == ENOMEM)
            *ec = cli_oom(path);
        else {
            cli_error("%s: %s", path, strerror(e));
            *ec = CLI_NOINPUT;
        }
        return NULL;
    }
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    size_t k;
    int nul = 0;
    while (buf && (k = fread(buf + n, 1, cap - n, f)) > 0) {
        if (memchr(buf + n, '\0', k)) {
            nul = 1; /* binary data: refused at once, not read to the end */
            break;
        }
        n += k;
        if (n == cap) {
            char *nb = realloc(buf, 2 * cap + 1);
            if (!nb) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = nb;
            cap *= 2;
        }
    }
    int bad = buf && ferror(f), e = errno;
    if (!is_stdin)
        fclose(f);
    if (!buf) {
        *ec = cli_oom(path);
        return NULL;
    }
    if (bad) {
        free(buf);
        *ec = e == ENOMEM ? cli_oom(path) : CLI_NOINPUT;
        if (e != ENOMEM)
            cli_error("%s: read error: %s", path, strerror(e));
        return NULL;
    }
    if (nul) {
        free(buf);
        cli_error("%s: a NUL byte in a JSON result (binary data?)", path);
        *ec = CLI_DATAERR;
        return NULL;
    }
    buf[n] = '\0';
    return buf;
}

int cmd_test(int argc, char **argv)
{
    if (cli_one_stdin(argc, argv))
        return CLI_USAGE;
    const char *table = NULL, *outp = NULL, *units = NULL;
    double alpha = 0.01, lambda_test = 10.0, zcrit = 0.0;
    int json = 0, nfiles = 0, ec;
    char **files = calloc((size_t)argc + 1, sizeof(char *));
    if (!files)
        return cli_oom("the file list");
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i], *v;
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) {
            test_help();
            free(files);
            return CLI_OK;
        }
        if (!strcmp(o, "--table") || !strcmp(o, "--out") || !strcmp(o, "--unit-ids") ||
            !strcmp(o, "--alpha") || !strcmp(o, "--lambda-test") || !strcmp(o, "--z-crit")) {
            if (!(v = cli_optarg(argc, argv, &i))) {
                free(files);
                return CLI_USAGE;
            }
            ec = CLI_OK;
            if (!strcmp(o, "--table")) table = v;
            else if (!strcmp(o, "--out")) outp = v;
            else if (!strcmp(o, "--unit-ids")) units = v;
            else if (!strcmp(o, "--alpha")) ec = cli_parse_double(o, v, &alpha);
            else if (!strcmp(o, "--lambda-test")) ec = cli_parse_double(o, v, &lambda_test);
            else ec = cli_parse_double(o, v, &zcrit);
            if (ec) {
                free(files);
                return ec;
            }
        } else if (!strcmp(o, "--json"))
            json = 1;
        else if (o[0] == '-' && o[1]) {
            cli_error("test: unknown option '%s' (see igea test --help)", o);
            free(files);
            return CLI_USAGE;
        } else
            files[nfiles++] = argv[i];
    }
    if (!(alpha > 0 && alpha < 1) || !(lambda_test > 0) || zcrit < 0) {
        cli_error("test: --alpha must be in (0, 1), --lambda-test > 0, --z-crit > 0");
        free(files);
        return CLI_USAGE;
    }
    if ((table != NULL) == (nfiles > 0)) {
        cli_error("test: give either --table FILE or RESULT.json files (see igea test --help)");
        free(files);
        return CLI_USAGE;
    }
    double info[IGEA_STATS_INFO_LEN];
    cli_out out;
    if (table) {
        cli_matrix t;
        if ((ec = cli_read_matrix(table, &t))) {
            free(files);
            return ec;
        }
        int c0 = t.cols == 2 ? 0 : 1;
        if (t.cols < 2 || t.cols > 4 || t.rows > 100000) {
            cli_error("%s: expected 2 columns (Xhat, lambda) or 3-4 (n, Xhat, lambda[, precision]), "
                      "found %d", table, t.cols);
            cli_matrix_free(&t);
            free(files);
            return CLI_DATAERR;
        }
        int n = (int)t.rows;
        double *x = malloc(sizeof(double) * n), *lam = malloc(sizeof(double) * n);
        double *z = malloc(sizeof(double) * n);
        int *rej = malloc(sizeof(int) * n);
        ec = (!x || !lam || !z || !rej) ? cli_oom("the table") : CLI_OK;
        for (int i = 0; !ec && i < n; i++) {
            x[i] = t.v[(size_t)i * t.cols + c0];
            lam[i] = t.v[(size_t)i * t.cols + c0 + 1];
            if (!(lam[i] > 0)) {
                cli_error("%s: row %d: eigenvalue %g must be > 0", table, i + 1, lam[i]);
                ec = CLI_DATAERR;
            }
        }
        if (!ec) {
            int st = igea_stats_accuracy_test(n, x, lam, alpha, lambda_test, zcrit, z, rej, info);
            if (st)
                ec = cli_status(st, "test");
        }
        if (!ec && !(ec = cli_out_open(&out, outp))) {
            if (json) {
                fputs("{\n  \"z\": [", out.f);
                int k = 0;
                for (int i = 0; i < n; i++)
                    if (rej[i] >= 0) {
                        fputs(k++ ? ", " : "", out.f);
                        cli_json_num(out.f, z[i]);
                    }
                fputs("],\n  \"reject\": [", out.f);
                k = 0;
                for (int i = 0; i < n; i++)
                    if (rej[i] >= 0)
                        fprintf(out.f, "%s%s", k++ ? ", " : "", rej[i] ? "true" : "false");
                fputs("],\n", out.f);
                json_test_fields(out.f, info);
                fputs("\n}\n", out.f);
            } else {
                fprintf(out.f, "igea test: %s, %d component(s), %d with lambda >= %g tested\n\n",
                        table, n, (int)info[IGEA_STATS_INFO_N_TEST], lambda_test);
                report_components(out.f, n, x, lam, z, rej, info[IGEA_STATS_INFO_Z_CRIT]);
                fprintf(out.f, "(threshold = sqrt(1 + 1/lambda) z_crit, z_crit = %.6f)\n\n",
                        info[IGEA_STATS_INFO_Z_CRIT]);
                report_chi2(out.f, info, alpha);
            }
            ec = cli_out_commit(&out);
        }
        free(x);
        free(lam);
        free(z);
        free(rej);
        cli_matrix_free(&t);
    } else {
        double *chi2 = malloc(sizeof(double) * nfiles);
        int *dof = malloc(sizeof(int) * nfiles), *nrej = malloc(sizeof(int) * nfiles);
        int *uid = units ? malloc(sizeof(int) * nfiles) : NULL;
        ec = (!chi2 || !dof || !nrej || (units && !uid)) ? cli_oom("the pooled flights")
                                                          : CLI_OK;
        if (!ec && units) {
            const char *p = units;
            for (int f = 0; f < nfiles; f++) {
                char *end;
                long v = strtol(p, &end, 10);
                if (end == p || (*end != ',' && *end != '\0') || (*end == '\0' && f + 1 < nfiles)) {
                    cli_error("--unit-ids %s: expected %d comma-separated whole numbers", units, nfiles);
                    ec = CLI_USAGE;
                    break;
                }
                uid[f] = (int)v;
                p = *end ? end + 1 : end;
            }
            if (!ec && *p) {
                cli_error("--unit-ids %s: more ids than result files (%d)", units, nfiles);
                ec = CLI_USAGE;
            }
        }
        for (int f = 0; !ec && f < nfiles; f++) {
            char *doc = slurp(files[f], &ec);
            if (!doc)
                break;
            double T, d, r;
            if (json_number(doc, "chi2", &T) || json_number(doc, "dof", &d) ||
                json_number(doc, "n_reject", &r)) {
                cli_error("%s: not an 'igea eqerr --json' result (chi2, dof, n_reject missing)",
                          files[f]);
                ec = CLI_DATAERR;
            } else if (!(isfinite(T) && T >= 0)) {
                cli_error("%s: \"chi2\": %g is not a chi-square value (finite, >= 0)",
                          files[f], T);
                ec = CLI_DATAERR;
            } else if (!is_count(d) || !is_count(r)) {
                cli_error("%s: \"%s\": %.17g is not a count (a whole number from 0 to %d)",
                          files[f], is_count(d) ? "n_reject" : "dof", is_count(d) ? r : d,
                          INT_MAX);
                ec = CLI_DATAERR;
            } else {
                chi2[f] = T;
                dof[f] = (int)d;
                nrej[f] = (int)r;
            }
            free(doc);
        }
        if (!ec) {
            int st = igea_stats_pool(nfiles, chi2, dof, nrej, uid, alpha, info);
            if (st)
                ec = cli_status(st, "test");
        }
        if (!ec && !(ec = cli_out_open(&out, outp))) {
            if (json) {
                fprintf(out.f, "{\n  \"flights\": %d,\n", nfiles);
                json_test_fields(out.f, info);
                fputs("\n}\n", out.f);
            } else {
                fprintf(out.f, "igea test: %d flight(s) pooled\n", nfiles);
                for (int f = 0; f < nfiles; f++)
                    fprintf(out.f, "  %-30s T = %9.4f  dof %3d  rejected components %d\n",
                            files[f], chi2[f], dof[f], nrej[f]);
                report_chi2(out.f, info, alpha);
            }
            ec = cli_out_commit(&out);
        }
        free(chi2);
        free(dof);
        free(nrej);
        free(uid);
    }
    free(files);
    if (ec)
        return ec;
    return info[IGEA_STATS_INFO_PASSED] == 1.0 ? CLI_OK : CLI_REJECT;
}
