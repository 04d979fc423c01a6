/* igea eqerr, igea test - the equivalent-error accuracy assessment
 * (seed 000, METHODS 1.2) from files, and judging saved results. */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char *flag_name(int flag)
{
    return igea_choice_name(IGEA_CHOICE_STATS_SIGMAW_FLAG, flag);
}

static const char *verdict_name(const double *info)
{
    return igea_choice_name(IGEA_CHOICE_STATS_VERDICT, (int)info[IGEA_STATS_INFO_VERDICT]);
}

/* The seed's Tables 1-2 (shared by both commands): the tested components
 * (reject[i] >= 0) of n, thresholds at the verdict rule's z threshold. */
static void report_components(FILE *f, int n, const double *xhat,
                              const double *lambda, const double *z,
                              const int *reject, const double *info)
{
    double zc = info[IGEA_STATS_INFO_VERDICT_Z_CRIT], thr, prec;
    fprintf(f, "%5s %13s %13s %11s %10s %9s  %s\n", "comp", "eigenvalue",
            "equiv_error", "precision", "threshold", "z", "verdict");
    for (int i = 0; i < n; i++) {
        if (reject[i] < 0 || igea_eqerr_limits(1, &lambda[i], zc, &thr, &prec) != 0)
            continue;
        if (zc > 0)
            fprintf(f, "%5d %13.6e %13.6f %11.4e %10.4f %9.4f  %s\n", i, lambda[i],
                    xhat[i], prec, thr, z[i], reject[i] ? "REJECT" : "pass");
        else
            fprintf(f, "%5d %13.6e %13.6f %11.4e %10s %9.4f  %s\n", i, lambda[i], xhat[i],
                    prec, "-", z[i], "-");
    }
}

static void report_chi2(FILE *f, const double *info, double alpha)
{
    double T = info[IGEA_STATS_INFO_CHI2], crit = info[IGEA_STATS_INFO_VERDICT_CHI2_CRIT];
    int rule = (int)info[IGEA_STATS_INFO_VERDICT], dof = (int)info[IGEA_STATS_INFO_DOF];
    if (rule == IGEA_STATS_VERDICT_SEED)
        fprintf(f, "chi-square: T = %.4f with %d dof; chi2_%g(%d) = %.3f; p-value %.4g -> %s\n",
                T, dof, alpha, dof, crit, info[IGEA_STATS_INFO_P_VALUE],
                T < crit ? "pass" : "REJECT");
    else
        fprintf(f, "chi-square: T = %.4f with %d dof; threshold %.3f (rule %s); p-value %.4g "
                   "-> %s\n", T, dof, crit, verdict_name(info), info[IGEA_STATS_INFO_P_VALUE],
                T < crit ? "pass" : "REJECT");
    double size = info[IGEA_STATS_INFO_OVERALL_SIZE];
    char zt[32] = "none";
    if (info[IGEA_STATS_INFO_VERDICT_Z_CRIT] > 0)
        snprintf(zt, sizeof zt, "%.4f", info[IGEA_STATS_INFO_VERDICT_Z_CRIT]);
    if (size > 0)
        fprintf(f, "overall verdict rule %s: |z| threshold %s, chi-square threshold %.3f; "
                   "overall size %.6f at alpha = %g\n", verdict_name(info), zt, crit, size,
                alpha);
    else
        fprintf(f, "overall verdict rule %s: overall size not computed (more than %d tested "
                   "components)\n", verdict_name(info), IGEA_STATS_UNION_N_MAX);
    int nrej = (int)info[IGEA_STATS_INFO_N_REJECT];
    if (info[IGEA_STATS_INFO_PASSED] == 1.0)
        fprintf(f, "verdict: ACCEPTED - no component rejected and T < chi2 critical value "
                   "(alpha = %g)\n", alpha);
    else
        fprintf(f, "verdict: REJECTED - %d component(s) rejected%s (alpha = %g)\n", nrej,
                T < crit ? "" : ", chi-square test failed", alpha);
}

static void json_test_fields(cli_json *j, const double *info)
{
    cli_jint(j, "n_test", (long)info[IGEA_STATS_INFO_N_TEST]);
    cli_jnum(j, "chi2", info[IGEA_STATS_INFO_CHI2]);
    cli_jint(j, "dof", (long)info[IGEA_STATS_INFO_DOF]);
    cli_jnum(j, "chi2_crit", info[IGEA_STATS_INFO_CHI2_CRIT]);
    cli_jnum(j, "z_crit", info[IGEA_STATS_INFO_Z_CRIT]);
    cli_jnum(j, "p_value", info[IGEA_STATS_INFO_P_VALUE]);
    cli_jint(j, "n_reject", (long)info[IGEA_STATS_INFO_N_REJECT]);
    cli_jbool(j, "passed", info[IGEA_STATS_INFO_PASSED] == 1.0);
    cli_jstr(j, "verdict", verdict_name(info));
    if (info[IGEA_STATS_INFO_VERDICT_Z_CRIT] > 0)
        cli_jnum(j, "verdict_z_crit", info[IGEA_STATS_INFO_VERDICT_Z_CRIT]);
    else
        cli_jstr(j, "verdict_z_crit", NULL);
    cli_jnum(j, "verdict_chi2_crit", info[IGEA_STATS_INFO_VERDICT_CHI2_CRIT]);
    if (info[IGEA_STATS_INFO_OVERALL_SIZE] > 0)
        cli_jnum(j, "overall_size", info[IGEA_STATS_INFO_OVERALL_SIZE]);
    else
        cli_jstr(j, "overall_size", NULL);
}

static void json_verdicts(cli_json *j, const double *z, const int *reject, int n)
{
    cli_jnums(j, "z", z, n);
    cli_json_open(j, "reject", '[');
    for (int i = 0; i < n; i++)
        cli_jbool(j, NULL, reject[i] == 1);
    cli_json_close(j);
}

typedef struct {
    const char *S, *dw, *sigma, *spec, *residuals, *out;
    double sigma_value;
    int sigma_is_number, json, route;
    double opts[IGEA_EQERR_OPT_LEN];
    int verdict; /* IGEA_STATS_VERDICT_* */
    int ar_method; /* IGEA_NOISE_AR_*: how phi is estimated */
    int lags;    /* residual diagnostics: Ljung-Box lags */
    const char *names; /* --names LIST */
    const char *cov, *xcov, *groups, *ar_phi; /* the noise models (eqerr_noise.c) */
    int noise;                         /* 1: a noise option given */
    cli_noise_args na;                 /* their arguments */
    const char *plot; /* --plot FILE.svg */
    const char *burnout, *burnout_errors; /* --burnout, --burnout-errors: component miss */
    cli_burnout_args bo;                  /* or --burnout-time with --traj and the site */
} eqerr_args;

/* The overall verdict rule, the same option in eqerr and test. */
#define CLI_VERDICT_OPT(t)                                                                  \
    {"--verdict", CLI_OPT_CHOICE, t, "seed", CLI_CHOICES(IGEA_CHOICE_STATS_VERDICT),         \
     "overall verdict: the seed's (any |z| > z_{1-alpha/2} or\n"                           \
     "T >= chi2_alpha), the chi-square test alone, both at one\n"                          \
     "level so that the overall size is alpha (exact), or\n"                               \
     "Sidak components plus chi-square; the report states\nthe overall size", NULL}

static eqerr_args EA;
#define EQ_OPT(slot) (&EA.opts[IGEA_EQERR_OPT_##slot])
static const cli_opt eqerr_options[] = {
    {"--S", CLI_OPT_STR, &EA.S, NULL, "FILE", "environment functions, m rows x N columns", NULL},
    {"--dw", CLI_OPT_STR, &EA.dw, NULL, "FILE", "velocity differences, m values (one column)", NULL},
    {"--sigma", CLI_OPT_STR, &EA.sigma, NULL, "FILE|NUM", "tracking 1-sigma per row (m values), or one number", NULL},
    {"--spec", CLI_OPT_STR, &EA.spec, NULL, "FILE", "N term specs (1-sigma), any layout", NULL},
    {"--alpha", CLI_OPT_NUM, EQ_OPT(ALPHA), CLI_DEF_LIB, "A", "significance level", NULL},
    {"--lambda-test", CLI_OPT_NUM, EQ_OPT(LAMBDA_TEST), CLI_DEF_LIB, "L", "test components with lambda >= L", NULL},
    {"--lambda-small", CLI_OPT_NUM, EQ_OPT(LAMBDA_SMALL), CLI_DEF_LIB, "L", "small eigenvalues for sigma_w: lambda <= L", NULL},
    {"--n-min", CLI_OPT_NUM, EQ_OPT(N_MIN), CLI_DEF_LIB, "N", "fewest small eigenvalues to estimate sigma_w", NULL},
    {"--tol", CLI_OPT_NUM, EQ_OPT(TOL), CLI_DEF_LIB, "T", "stop when |sigma_w^2 - 1| <= T", NULL},
    {"--max-iter", CLI_OPT_NUM, EQ_OPT(MAX_ITER), CLI_DEF_LIB, "N", "sigma_w iterations", NULL},
    {"--no-correction", CLI_OPT_DCLEAR, EQ_OPT(CORRECTION), NULL, NULL, "do not correct the tracking accuracy", NULL},
    {"--bias-correct", CLI_OPT_DSET, EQ_OPT(BIAS_CORRECT), NULL, NULL, "sigma_w^2 = mean(g^2 - lambda) over the small set", NULL},
    {"--clamp", CLI_OPT_DSET, EQ_OPT(CLAMP), NULL, NULL, "never make the tracking weights more optimistic\n(c >= 1)", NULL},
    {"--z-crit", CLI_OPT_NUM, EQ_OPT(Z_CRIT), NULL, "Z", "impose the normal critical value (e.g. 2.58 as in\nthe seed's tables) instead of the exact z_{1-alpha/2}", NULL},
    {"--route", CLI_OPT_CHOICE, &EA.route, "eig", CLI_CHOICES(IGEA_CHOICE_EQERR_ROUTE), "normal matrix + dsyevd, or the SVD of the weighted\n"
     "S through its streamed QR factor (dtpqrt): resolves\neigenvalues down to eps^2 lambda_1 instead of eps\n"
     "lambda_1, at about twice the cost", NULL},
    {"--cov", CLI_OPT_STR, &EA.cov, NULL, "FILE", "3x3 tracking covariance per epoch instead of --sigma:\n"
     "one line of 6 lower-triangle entries (xx yx yy zx zy zz)", NULL},
    {"--xcov", CLI_OPT_STR, &EA.xcov, NULL, "FILE", "with --cov: the cross blocks X_e = Cov(dW_e, dW_f),\n"
     "f > e, of igea dw --xcov-out (9 entries per epoch,\nrow-major): judge with the whole K", NULL},
    {"--ar", CLI_OPT_NUM, EQ_OPT(AR), NULL, "P", "AR(P) tracking noise per axis (P <= 3), phi estimated\n"
     "from the residuals and iterated with the group scales", NULL},
    {"--ar-phi", CLI_OPT_STR, &EA.ar_phi, NULL, "a,b,c", "AR coefficients given (lags 1.., every axis)", NULL},
    {"--ar-method", CLI_OPT_CHOICE, &EA.ar_method, NULL, CLI_CHOICES(IGEA_CHOICE_NOISE_AR_METHOD),
     "with --ar: phi by restricted maximum likelihood\n(default; free of the bias of the fitted terms, and\n"
     "each scale's se includes phi's) or by least squares\nof the residuals (Cochrane-Orcutt)", NULL},
    {"--groups", CLI_OPT_STR, &EA.groups, NULL, "FILE", "group label 0..G-1 per epoch (station, phase): one\n"
     "sigma_w per group (Helmert variance components)", NULL},
    {"--group-bias", CLI_OPT_DSET, EQ_OPT(GROUP_BIAS), NULL, NULL, "per-group x, y, z bias columns (nuisance, not tested)", NULL},
    {"--robust", CLI_OPT_DSET, EQ_OPT(ROBUST), NULL, NULL, "reject outlying rows by data snooping (w-test)", NULL},
    {"--robust-alpha", CLI_OPT_NUM, EQ_OPT(ROBUST_ALPHA), NULL, "A", "level of the w-test per row (0: 0.001)", NULL},
    {"--threads", CLI_OPT_NUM, EQ_OPT(THREADS), NULL, "T", "normal equations and residuals on T threads (route\neig; 0 or 1: one; the driver's blocks keep two\nbusy); results equal for T >= 2 and to one thread's\nto rounding", NULL},
    {"--residuals", CLI_OPT_STR, &EA.residuals, NULL, "FILE", "write epoch, axis, residual per row: dw - S D P_t Xhat_t\n(whitened, with the noise models)", NULL},
    {"--burnout", CLI_OPT_STR, &EA.burnout, NULL, "X,Y,Z,VX,VY,VZ", "with --burnout-errors: the nominal burnout state\n"
     "(ECEF, m and m/s, as igea impact); the report adds the\nmiss (Kepler) of each tested component", NULL},
    {"--burnout-errors", CLI_OPT_STR, &EA.burnout_errors, NULL, "FILE", "6 rows (x y z vx vy vz, ECEF) by N columns: the\n"
     "burnout state error per unit of each column of S as\njudged (times its spec with --spec)", NULL},
    CLI_BURNOUT_OPTIONS(EA.bo, "the errors of S's terms (named by --names or its\n"
                        "header) there: the miss of each tested component,\n"
                        "instead of --burnout and --burnout-errors"),
    CLI_VERDICT_OPT(&EA.verdict),
    {"--names", CLI_OPT_STR, &EA.names, NULL, "LIST", "comma-separated term names, one per column of S\n"
     "(default: the '# name name ...' header of a text S, as\nigea envfun and simulate write it)", NULL},
    {"--lags", CLI_OPT_INT, &EA.lags, "20", "L", "residual whiteness per axis: Ljung-Box Q over L\n"
     "lags, and the runs test on the signs about the mean", NULL},
    {"--json", CLI_OPT_FLAG, &EA.json, NULL, NULL, "machine-readable output (field names as igea.eqerr)", NULL},
    CLI_PROGRESS_OPTIONS,
    CLI_OUT_OPT(&EA.out),
    {"--plot", CLI_OPT_STR, &EA.plot, NULL, "FILE.svg", "draw the residuals per axis against the epoch and\nthe eigenvalue spectrum with lambda_test and\nlambda_small into an SVG picture", NULL},
    CLI_END};

static const cli_command eqerr_command = {"eqerr",
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
"--verdict chooses the overall rule (exact: both tests at one level, overall\n"
"false-alarm probability alpha); the report states the rule's overall size,\n"
"the terms behind each tested component (named by --names or the S header)\n"
"and the residuals' whiteness per axis (Ljung-Box, runs test).\n"
"\n"
"Inputs: text (whitespace or commas, '#' comments) or .npy (float64), read in\n"
"row blocks twice (the decomposition, then the residuals): either route needs\n"
"O(N^2) memory whatever the flight length. One input may be '-', standard\n"
"input; a pipe or FIFO is copied to a temporary file for the second pass.\n"
"Progress (rows read in the first pass; in the second a percentage, elapsed\n"
"time and ETA) goes to stderr when it is a terminal, or with --progress.\n"
"\n"
"options:\n",
eqerr_options,
"\n"
"exit status: 0 accepted, 1 rejected, 64 usage, 65 bad input (also data that\n"
"cannot be judged, e.g. no component precise enough to test), 66 missing input,\n"
"70 numerical failure (no convergence), 74 I/O error.\n"
"\n"
"example (the bundled flight):\n"
"  cd examples/flight\n"
"  igea eqerr --S S.txt --dw dw.txt --sigma sigma.txt --spec spec.txt\n"
"  igea eqerr --S S.txt --dw dw.txt --sigma 0.01 --spec spec.txt --json --out f1.json\n"};

static int parse_noise(eqerr_args *a);

static int parse_eqerr(int argc, char **argv, eqerr_args *a)
{
    memset(&EA, 0, sizeof EA);
    igea_eqerr_defaults(EA.opts);
    EA.ar_method = -1; /* not given: the library's default */
    int ec = cli_parse(&eqerr_command, argc, argv);
    *a = EA;
    if (ec)
        return ec;
    if (!a->S || !a->dw || (!a->sigma && !a->cov)) {
        cli_error("eqerr: --S, --dw and --sigma are required (see igea eqerr --help)");
        return CLI_USAGE;
    }
    if (a->cov && a->sigma) {
        cli_error("eqerr: --cov and --sigma are alternatives");
        return CLI_USAGE;
    }
    if (a->sigma && (ec = cli_file_or_positive("--sigma", a->sigma, &a->sigma_is_number, &a->sigma_value)))
        return ec;
    if (a->opts[IGEA_EQERR_OPT_AR] != 0 && !a->ar_phi)
        a->opts[IGEA_EQERR_OPT_AR_ESTIMATE] = 1;
    a->opts[IGEA_EQERR_OPT_ROUTE] = a->route;
    a->opts[IGEA_EQERR_OPT_VERDICT] = a->verdict;
    a->opts[IGEA_EQERR_OPT_OVERALL_SIZE] = 1;
    if (a->ar_method >= 0 && (a->opts[IGEA_EQERR_OPT_AR] == 0 || a->ar_phi)) {
        cli_error("eqerr: --ar-method %s estimates phi: it needs --ar P (not --ar-phi)",
                  igea_choice_name(IGEA_CHOICE_NOISE_AR_METHOD, a->ar_method));
        return CLI_USAGE;
    }
    if (a->ar_method >= 0)
        a->opts[IGEA_EQERR_OPT_AR_METHOD] = a->ar_method;
    if (a->lags < 1 || a->lags > IGEA_STATS_DIAG_LAGS_MAX) {
        cli_error("eqerr: --lags %d: from 1 to %d", a->lags, IGEA_STATS_DIAG_LAGS_MAX);
        return CLI_USAGE;
    }
    if ((ec = parse_noise(a)))
        return ec;
    if ((ec = cli_burnout_check("eqerr", &a->bo)))
        return ec;
    if (a->bo.given_time && (a->burnout || a->burnout_errors)) {
        cli_error("eqerr: --burnout-time and --burnout, --burnout-errors are alternatives");
        return CLI_USAGE;
    }
    return cli_check_opts("eqerr", IGEA_MODULE_EQERR, igea_eqerr_check_opts(a->opts));
}

/* The noise models: any of their options takes the in-memory route
 * (eqerr_noise.c), whose decomposition is the normal matrix's. */
static int parse_noise(eqerr_args *a)
{
    a->noise = a->cov || a->groups || a->ar_phi || a->opts[IGEA_EQERR_OPT_AR] != 0 ||
               a->opts[IGEA_EQERR_OPT_ROBUST] != 0 || a->opts[IGEA_EQERR_OPT_GROUP_BIAS] != 0;
    if (a->xcov && !a->cov) {
        cli_error("eqerr: --xcov FILE needs --cov FILE, the diagonal blocks K_ee of the same K "
                  "(igea dw --k-out)");
        return CLI_USAGE;
    }
    if (a->xcov && (a->ar_phi || a->opts[IGEA_EQERR_OPT_AR] != 0)) {
        cli_error("eqerr: --xcov: K with its cross blocks is the noise's whole covariance; AR "
                  "noise on top of it (--ar, --ar-phi) is not supported");
        return CLI_USAGE;
    }
    if (a->xcov && a->groups) {
        cli_error("eqerr: --xcov: the cross blocks couple every epoch with every later one, "
                  "across stations; one scale per group (--groups) is not supported with them");
        return CLI_USAGE;
    }
    if (!a->noise)
        return CLI_OK;
    if (a->route != IGEA_EQERR_ROUTE_EIG) {
        cli_error("eqerr: --route svd is not available with the noise models (--cov, --ar, "
                  "--ar-phi, --groups, --group-bias, --robust)");
        return CLI_USAGE;
    }
    if (a->plot) {
        cli_error("eqerr: --plot is not drawn with the noise models");
        return CLI_USAGE;
    }
    cli_noise_args na = {a->S, a->dw, a->sigma, a->spec, a->cov, a->groups, a->json, 0, {0},
                         a->opts, a->xcov};
    int p = 0, ec = CLI_OK;
    if (a->ar_phi && !(ec = cli_noise_parse_phi(a->ar_phi, na.phi, &p))) {
        a->opts[IGEA_EQERR_OPT_AR] = p;
        na.p_given = 1;
    }
    a->na = na;
    return ec;
}

/* Open the three streamed inputs in lockstep. Each block is a view of
 * the rows (cli_reader_view: a .npy file in place through a memory map,
 * else the reader's own buffer), so that both passes read S where it
 * lies. S's views are not scanned for NaN and Inf by the reader: the
 * library's pass over the block refuses them (IGEA_ENONFINITE), and any
 * failure met in a block checks S's view first (s_failed), so that the
 * messages and their order are those of a checked view. */
typedef struct {
    cli_reader *S, *dw, *sig;
    int N;
    const double *srows, *drows, *grows; /* the current block */
    double *gbuf;                        /* --sigma given as a number */
    long block, seen; /* rows per block; rows read since the (re)start */
} streams;

static void streams_close(streams *s)
{
    cli_reader_close(s->S);
    cli_reader_close(s->dw);
    cli_reader_close(s->sig);
    free(s->gbuf);
    memset(s, 0, sizeof *s);
}

static int streams_open(const eqerr_args *a, streams *s)
{
    memset(s, 0, sizeof *s);
    int ec = cli_reader_open_unchecked(a->S, &s->S);
    if (!ec)
        ec = cli_reader_open_twice(a->dw, &s->dw);
    if (!ec && !a->sigma_is_number)
        ec = cli_reader_open_twice(a->sigma, &s->sig);
    for (int k = 0; !ec && k < 2; k++) {
        cli_reader *rd = k ? s->sig : s->dw;
        if (rd && cli_reader_cols(rd) != 1) {
            cli_error("%s: %s must be one column, found %d", k ? a->sigma : a->dw,
                      k ? "sigma" : "dw", cli_reader_cols(rd));
            ec = CLI_DATAERR;
        }
    }
    if (!ec) {
        s->N = cli_reader_cols(s->S);
        s->block = 1 + (4L << 20) / (8L * (s->N + 2)); /* about 4 MB of rows */
        /* --threads T >= 2: blocks of four segments whatever T (the same
         * sums for every T; the threads take the segments as they come) */
        long seg4 = 4L * IGEA_NORMAL_SEGMENT;
        if (a->opts[IGEA_EQERR_OPT_THREADS] > 1 && a->route == IGEA_EQERR_ROUTE_EIG &&
            s->block < seg4)
            s->block = seg4;
        s->block -= s->block % 3;
        if (s->block < 3)
            s->block = 3;
        if (a->sigma_is_number) {
            if (!(s->gbuf = malloc((size_t)s->block * sizeof(double)))) {
                cli_error("out of memory (row blocks of %s)", a->S);
                ec = CLI_SOFTWARE;
            }
            for (long i = 0; !ec && i < s->block; i++)
                s->gbuf[i] = a->sigma_value;
        }
    }
    if (ec)
        streams_close(s);
    return ec;
}

/* All three again from their first row (the second pass). */
static int streams_rewind(streams *s)
{
    int ec = cli_reader_rewind(s->S);
    s->seen = 0;
    if (!ec)
        ec = cli_reader_rewind(s->dw);
    if (!ec && s->sig)
        ec = cli_reader_rewind(s->sig);
    return ec;
}

/* Before a failure in the current block is reported: S's rows checked
 * (a NaN or Inf in them is reported instead, as their reader would have
 * when it handed them out). CLI_OK when they are finite. */
static int s_failed(streams *s)
{
    return cli_reader_view_check(s->S);
}

/* Next block of all three; *n rows (0 at the end). */
static int streams_next(const eqerr_args *a, streams *s, long *n)
{
    long ns, nd, ng;
    int ec = cli_reader_view(s->S, s->block, &s->srows, &ns);
    if (!ec)
        ec = cli_reader_view_after(s->dw, s->block, &s->drows, &nd, s->S);
    if (ec)
        return ec;
    if (s->sig) {
        ec = cli_reader_view_after(s->sig, s->block, &s->grows, &ng, s->S);
        if (ec)
            return ec;
    } else {
        ng = ns;
        s->grows = s->gbuf;
    }
    if ((ns != nd || ns != ng) && (ec = s_failed(s)))
        return ec;
    if (ns != nd && s->seen == 0 && ns < s->block && nd < s->block && nd == s->N) {
        cli_error("%s has %ld rows and %d columns; %s has %ld values: transposed?", a->S, ns,
                  s->N, a->dw, nd);
        return CLI_DATAERR;
    }
    if (ns != nd || ns != ng) {
        const char *shorter = nd < ns ? a->dw : (ng < ns ? a->sigma : a->S);
        cli_error("%s ends early: %s, %s%s%s must have the same number of rows", shorter,
                  a->S, a->dw, a->sigma_is_number ? "" : ", ", a->sigma_is_number ? "" : a->sigma);
        return CLI_DATAERR;
    }
    *n = ns;
    s->seen += ns;
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

static int check_sigma_block(const eqerr_args *a, streams *s, const double *g, long n,
                             long row0)
{
    if (a->sigma_is_number)
        return CLI_OK;
    for (long i = 0; i < n; i++)
        if (!(g[i] > 0)) {
            int ec = s_failed(s);
            if (ec)
                return ec;
            cli_error("%s: row %ld: tracking sigma %g must be > 0", a->sigma, row0 + i + 1, g[i]);
            return CLI_DATAERR;
        }
    return CLI_OK;
}

/* Results of one flight. */
typedef struct {
    int m, N;
    double *lambda, *P, *xhat, *z, *spec, info[IGEA_STATS_INFO_LEN], rms[3];
    int *reject;
    /* residual diagnostics: pass-1 sums per axis, the three streamed states,
     * their results and statuses (0: computed) */
    double *sums, *dstate, diag[3 * IGEA_STATS_DIAG_LEN];
    int diag_st[3];
    /* named components: term names (NULL: column_j), shares, loadings and
     * the terms by descending share of the tested components */
    char **names;
    double *share, *loading;
    int *order;
    /* the noise models (eqerr_noise.c): their results, the whitened
     * residuals in nr.resid; NULL nr.lambda for the plain route */
    cli_noise_result nr;
    double *cmiss; /* --burnout: 2 x n_test miss of the tested components (m) */
    double burnout[6]; /* the burnout state of the miss (ECEF) */
} flight;

static void flight_free(flight *r)
{
    free(r->lambda); /* P, xhat and z are in its block */
    free(r->spec);
    free(r->reject);
    free(r->sums);
    free(r->names);
    free(r->share); /* loading and order are in its block */
    cli_noise_result_free(&r->nr);
    free(r->cmiss);
}

static int flight_alloc(flight *r, int N)
{
    size_t n = (size_t)N;
    r->N = N;
    r->lambda = malloc((n * n + 3 * n) * sizeof(double));
    r->reject = malloc(n * sizeof(int));
    r->sums = calloc(3 * (n + 2) + 3 * IGEA_STATS_DIAG_STATE_LEN, sizeof(double));
    if (!r->lambda || !r->reject || !r->sums)
        return cli_oom("the results");
    r->dstate = r->sums + 3 * (n + 2);
    r->P = r->lambda + n, r->xhat = r->P + n * n, r->z = r->xhat + n;
    return CLI_OK;
}

/* A '#' line of S naming its N columns: N identifiers (names into the
 * block *out, as cli_split_list's), or 0. */
static int names_from_line(const char *line, int N, char ***out)
{
    size_t len = strlen(line);
    char **v = malloc(sizeof(char *) * (size_t)N + len + 1);
    if (!v)
        return cli_oom("the term names");
    char *text = (char *)(v + N);
    memcpy(text, line, len + 1);
    int k = 0;
    for (char *t = strtok(text, " \t,\r\n"); t; t = strtok(NULL, " \t,\r\n")) {
        int ok = k < N && (isalpha((unsigned char)t[0]) || t[0] == '_');
        for (const char *c = t; ok && *c; c++)
            ok = isalnum((unsigned char)*c) || *c == '_';
        if (!ok) {
            k = -1;
            break;
        }
        v[k++] = t;
    }
    if (k != N) {
        free(v);
        return CLI_OK;
    }
    *out = v;
    return CLI_OK;
}

/* The term names: --names, else the header of a text S, else none. */
static int read_names(const eqerr_args *a, int N, char ***names)
{
    *names = NULL;
    if (a->names) {
        int n, ec = cli_split_list(a->names, names, &n);
        if (!ec && n != N) {
            cli_error("--names: %d names, but %s has %d columns", n, a->S, N);
            free(*names);
            *names = NULL;
            ec = CLI_USAGE;
        }
        return ec;
    }
    size_t ls = strlen(a->S);
    if (!strcmp(a->S, "-") || (ls >= 4 && !strcmp(a->S + ls - 4, ".npy")))
        return CLI_OK;
    FILE *f = fopen(a->S, "r");
    if (!f)
        return CLI_OK; /* a pipe already consumed: no header names */
    char *line = NULL;
    size_t cap = 0;
    int ec = CLI_OK;
    while (!ec && !*names && getline(&line, &cap, f) > 0 && line[0] == '#')
        ec = names_from_line(line + 1, N, names);
    free(line);
    fclose(f);
    return ec;
}

/* The shares, loadings and order of the tested components, and the names. */
static int components_compute(const eqerr_args *a, flight *r)
{
    int N = r->N, nt = (int)r->info[IGEA_STATS_INFO_N_TEST];
    size_t n = (size_t)N * (nt > 0 ? nt : 1);
    int ec = read_names(a, N, &r->names);
    if (ec)
        return ec;
    r->share = malloc(2 * n * sizeof(double) + n * sizeof(int));
    if (!r->share)
        return cli_oom("the components");
    r->loading = r->share + n;
    r->order = (int *)(r->loading + n);
    return cli_status(igea_eqerr_components(N, r->P, N, nt, r->spec, r->share, r->loading,
                                            r->order), "eqerr components");
}

static void term_name(const flight *r, int j, char *buf, size_t size)
{
    if (r->names)
        snprintf(buf, size, "%s", r->names[j]);
    else
        snprintf(buf, size, "column_%d", j);
}

/* Named components, text: the terms with a share >= 1 % per tested
 * component, the candidates (share >= 10 %) of a rejected one. */
static void text_components(FILE *f, const flight *r)
{
    int N = r->N, nt = (int)r->info[IGEA_STATS_INFO_N_TEST];
    char nm[128];
    fprintf(f, "named components (share p_ij^2 of each term >= 1%%; loading spec_j p_ij in the "
               "term's units per unit of equiv_error):\n");
    for (int i = 0; i < nt; i++) {
        const double *sh = r->share + (size_t)i * N, *ld = r->loading + (size_t)i * N;
        const int *o = r->order + (size_t)i * N;
        fprintf(f, "%5d %s", i, r->reject[i] == 1 ? "REJECT candidates:" : "terms:");
        for (int k = 0; k < N && sh[o[k]] >= (r->reject[i] == 1 ? IGEA_EQERR_CANDIDATE_SHARE : 0.01); k++) {
            term_name(r, o[k], nm, sizeof nm);
            fprintf(f, "%s %s %.2f (%+.4g)", k ? "," : "", nm, sh[o[k]], ld[o[k]]);
        }
        fputc('\n', f);
    }
}

/* Named components, JSON: components [{index lambda z reject terms
 * [[name, share], ...] (descending) loading [per column] candidates}]. */
static void json_components(cli_json *j, const flight *r)
{
    int N = r->N, nt = (int)r->info[IGEA_STATS_INFO_N_TEST];
    char nm[128];
    cli_json_open(j, "components", '[');
    for (int i = 0; i < nt; i++) {
        const double *sh = r->share + (size_t)i * N;
        const int *o = r->order + (size_t)i * N;
        cli_json_open(j, NULL, '{');
        cli_jint(j, "index", i);
        cli_jnum(j, "lambda", r->lambda[i]);
        cli_jnum(j, "z", r->z[i]);
        cli_jbool(j, "reject", r->reject[i] == 1);
        cli_json_open(j, "terms", '[');
        for (int k = 0; k < N; k++) {
            term_name(r, o[k], nm, sizeof nm);
            cli_json_open(j, NULL, '[');
            cli_jstr(j, NULL, nm);
            cli_jnum(j, NULL, sh[o[k]]);
            cli_json_close(j);
        }
        cli_json_close(j);
        cli_jnums(j, "loading", r->loading + (size_t)i * N, N);
        cli_json_open(j, "candidates", '[');
        for (int k = 0; k < N && sh[o[k]] >= IGEA_EQERR_CANDIDATE_SHARE; k++) {
            term_name(r, o[k], nm, sizeof nm);
            cli_jstr(j, NULL, nm);
        }
        cli_json_close(j);
        cli_json_close(j);
    }
    cli_json_close(j);
}

/* Residual whiteness per axis, text. */
static void text_whiteness(FILE *f, const flight *r, int lags)
{
    fprintf(f, "residual whiteness per axis%s (Ljung-Box over %d lags; runs test on the "
               "signs about the axis mean):\n",
            r->nr.lambda ? " of the whitened residuals, epochs with a rejected row left out"
                         : "", lags);
    for (int k = 0; k < 3; k++) {
        const double *d = r->diag + k * IGEA_STATS_DIAG_LEN;
        if (r->diag_st[k]) {
            fprintf(f, "  %c: not computed (%s)\n", "xyz"[k],
                    r->diag_st[k] == IGEA_EEMPTY ? "fewer than lags + 2 epochs"
                                                 : "constant residuals");
            continue;
        }
        fprintf(f, "  %c: Q = %.4g, p-value %.4g; %d runs (%d above, %d below), z = %.3f, "
                   "p-value %.4g\n", "xyz"[k], d[IGEA_STATS_DIAG_LB_Q], d[IGEA_STATS_DIAG_LB_P],
                (int)d[IGEA_STATS_DIAG_RUNS], (int)d[IGEA_STATS_DIAG_N_ABOVE],
                (int)d[IGEA_STATS_DIAG_N_BELOW], d[IGEA_STATS_DIAG_RUNS_Z],
                d[IGEA_STATS_DIAG_RUNS_P]);
    }
}

/* Residual whiteness per axis, JSON: "whiteness": [{...} or null per axis]. */
static void json_whiteness(cli_json *j, const flight *r)
{
    cli_json_open(j, "whiteness", '[');
    for (int k = 0; k < 3; k++) {
        const double *d = r->diag + k * IGEA_STATS_DIAG_LEN;
        if (r->diag_st[k]) {
            cli_jstr(j, NULL, NULL);
            continue;
        }
        cli_json_open(j, NULL, '{');
        cli_jint(j, "axis", k);
        cli_jint(j, "n", (long)d[IGEA_STATS_DIAG_N]);
        cli_jint(j, "lags", (long)d[IGEA_STATS_DIAG_LB_LAGS]);
        cli_jnum(j, "ljung_box", d[IGEA_STATS_DIAG_LB_Q]);
        cli_jnum(j, "ljung_box_p", d[IGEA_STATS_DIAG_LB_P]);
        cli_jint(j, "runs", (long)d[IGEA_STATS_DIAG_RUNS]);
        cli_jint(j, "n_above", (long)d[IGEA_STATS_DIAG_N_ABOVE]);
        cli_jint(j, "n_below", (long)d[IGEA_STATS_DIAG_N_BELOW]);
        cli_jnum(j, "runs_z", d[IGEA_STATS_DIAG_RUNS_Z]);
        cli_jnum(j, "runs_p", d[IGEA_STATS_DIAG_RUNS_P]);
        cli_json_close(j);
    }
    cli_json_close(j);
}

/* The document up to the residuals, whose array is left open. */
static void json_head(cli_json *j, const flight *r, const eqerr_args *a)
{
    int N = r->N, nt = (int)r->info[IGEA_STATS_INFO_N_TEST];
    cli_jnums(j, "eigenvalues", r->lambda, N);
    cli_jmatrix(j, "eigenvectors", r->P, NULL, N, N, 1, N);
    cli_jint(j, "rank", (long)r->info[IGEA_STATS_INFO_RANK]);
    cli_jnums(j, "equiv_err", r->xhat, N);
    json_verdicts(j, r->z, r->reject, nt);
    json_test_fields(j, r->info);
    cli_jnum(j, "scale", r->info[IGEA_STATS_INFO_SCALE]);
    cli_jint(j, "iterations", (long)r->info[IGEA_STATS_INFO_ITERATIONS]);
    cli_jint(j, "n_small", (long)r->info[IGEA_STATS_INFO_N_SMALL]);
    cli_jstr(j, "flag", flag_name((int)r->info[IGEA_STATS_INFO_FLAG]));
    cli_jnum(j, "alpha", a->opts[IGEA_EQERR_OPT_ALPHA]);
    cli_jnum(j, "lambda_test", a->opts[IGEA_EQERR_OPT_LAMBDA_TEST]);
    cli_jstr(j, "route", igea_choice_name(IGEA_CHOICE_EQERR_ROUTE, a->route));
    cli_jint(j, "rows", r->m);
    cli_jint(j, "n_terms", N);
    cli_jbool(j, "residual_whitened", r->nr.lambda != NULL);
    cli_json_open(j, "residual", '[');
}

static void text_component_miss(FILE *f, const eqerr_args *a, const flight *r);

static void text_report(FILE *f, const flight *r, const eqerr_args *a)
{
    const double *info = r->info;
    fprintf(f, "igea eqerr: %s (%d rows x %d terms), %s %s%s%s\n", a->S, r->m, r->N,
            a->cov ? "3x3 covariance per epoch from" : "tracking sigma",
            a->cov ? a->cov : a->sigma, a->spec ? ", specs " : ", S already in spec units",
            a->spec ? a->spec : "");
    fprintf(f, "route %s: rank %d of %d; lambda_1 = %.6e; %d component(s) with lambda >= %g "
               "tested\n\n",
            igea_choice_name(IGEA_CHOICE_EQERR_ROUTE, (int)a->opts[IGEA_EQERR_OPT_ROUTE]),
            (int)info[IGEA_STATS_INFO_RANK], r->N, r->lambda[0], (int)info[IGEA_STATS_INFO_N_TEST],
            a->opts[IGEA_EQERR_OPT_LAMBDA_TEST]);
    report_components(f, r->N, r->xhat, r->lambda, r->z, r->reject, info);
    if (info[IGEA_STATS_INFO_VERDICT_Z_CRIT] > 0)
        fprintf(f, "(threshold = sqrt(1 + 1/lambda) z_crit, z_crit = %.6f; precision = "
                   "lambda^-1/2)\n\n", info[IGEA_STATS_INFO_VERDICT_Z_CRIT]);
    else
        fprintf(f, "(no component test under the chi2 rule; precision = lambda^-1/2)\n\n");
    text_components(f, r);
    if (r->cmiss)
        text_component_miss(f, a, r);
    fputc('\n', f);
    int flag = (int)info[IGEA_STATS_INFO_FLAG];
    if (flag == IGEA_STATS_SIGMAW_OFF)
        fprintf(f, "tracking-accuracy correction: off (c = 1)\n");
    else
        fprintf(f, "tracking-accuracy correction: c = %.6g (sigma_w = %.4f), %d iteration(s), "
                   "%d small eigenvalue(s) <= %g, %s\n",
                info[IGEA_STATS_INFO_SCALE], info[IGEA_STATS_INFO_SIGMA_W],
                (int)info[IGEA_STATS_INFO_ITERATIONS], (int)info[IGEA_STATS_INFO_N_SMALL],
                a->opts[IGEA_EQERR_OPT_LAMBDA_SMALL], flag_name(flag));
    fprintf(f, "residual RMS per axis (x, y, z)%s: %.6g %.6g %.6g\n",
            r->nr.lambda ? " of the whitened residuals" : "", r->rms[0], r->rms[1], r->rms[2]);
    text_whiteness(f, r, a->lags);
    if (r->nr.lambda)
        cli_noise_text(f, &a->na, &r->nr);
    report_chi2(f, info, a->opts[IGEA_EQERR_OPT_ALPHA]);
}

/* Pass 1, either route: the normal equations (eig) or the QR factor of the
 * weighted data (svd), then the decomposition and the test. */
static int pass_solve(const eqerr_args *a, streams *s, flight *r)
{
    int N = s->N, ec = CLI_OK;
    const int svd = a->route == IGEA_EQERR_ROUTE_SVD;
    /* eig: A (N x N), b (N), wtw (2); svd: R ((N+1) x (N+1)), row count */
    double *A = calloc((size_t)(N + 1) * (N + 1) + N + 2, sizeof(double));
    if (!A)
        return cli_oom("the normal matrix");
    double *b = A + (size_t)N * N, *wtw = b + N, qrows = 0.0;
    long rows = 0, n;
    cli_progress pr;
    if ((ec = cli_progress_start(&pr, "eqerr", "rows read (pass 1 of 2)", CLI_PROGRESS_UNKNOWN))) {
        free(A);
        return ec;
    }
    while (!(ec = streams_next(a, s, &n)) && n > 0) {
        cli_progress_count(&pr, (double)(rows + n));
        if ((ec = check_sigma_block(a, s, s->grows, n, rows)))
            break;
        /* eig: the normal equations and the axis sums in one pass over the
         * block, which also refuses a NaN or Inf of S's unchecked view */
        int st = svd ? igea_normal_qr_accumulate(IGEA_ROWMAJOR, (int)n, N, s->srows, N, s->drows,
                                                 s->grows, 1, r->spec, A, N + 1, &qrows)
                     : igea_eqerr_accumulate(IGEA_ROWMAJOR, (int)n, N, s->srows, N, s->drows,
                                             s->grows, 1, r->spec, A, N, b, wtw,
                                             (int)a->opts[IGEA_EQERR_OPT_THREADS], (int)rows,
                                             r->sums);
        if (!st && svd)
            st = igea_eqerr_axis_sums(IGEA_ROWMAJOR, (int)n, N, s->srows, N, s->drows, (int)rows,
                                      r->sums);
        if (st && (ec = s_failed(s)))
            break;
        if (st) {
            ec = cli_status(st, st == IGEA_ENONFINITE ? "eqerr: rows with NaN/Inf" : "eqerr");
            break;
        }
        if ((rows += n) > 2147483647L) {
            cli_error("%s: more than 2^31-1 rows", a->S);
            ec = CLI_DATAERR;
            break;
        }
    }
    cli_progress_end(&pr);
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
        ec = cli_status(st, "eqerr");
    }
    free(A);
    return ec;
}

/* The residual diagnostics' states, about each axis's residual mean. */
static int diag_start(const eqerr_args *a, flight *r, const double *coef)
{
    double mean[3];
    int st = igea_eqerr_residual_mean(r->N, r->sums, coef, mean);
    for (int k = 0; !st && k < 3; k++)
        st = igea_stats_diag_init(a->lags, mean[k], r->dstate + k * IGEA_STATS_DIAG_STATE_LEN);
    return cli_status(st, "eqerr residual diagnostics");
}

/* The residuals file, either route: one line per row, epoch, axis (0 x,
 * 1 y, 2 z) and the residual, under a '#' header. */
static void residual_header(FILE *res, int whitened)
{
    if (res)
        fprintf(res, "# epoch axis %s\n", whitened ? "whitened_residual" : "residual");
}

static void residual_line(FILE *res, cli_json *j, long row, double e)
{
    if (res)
        fprintf(res, "%ld %ld %.17g\n", row / 3, row % 3, e);
    if (j)
        cli_jnum(j, NULL, e);
}

/* Pass 2: the residuals, to the residuals file and into the JSON document. */
static int pass_residuals(const eqerr_args *a, streams *s, flight *r, FILE *res, cli_json *j)
{
    int N = s->N, ec;
    double *coef = malloc((size_t)N * sizeof(double));
    double *e = malloc((size_t)s->block * sizeof(double));
    if (!coef || !e) {
        free(coef);
        free(e);
        cli_error("out of memory (residuals of %s)", a->S);
        return CLI_SOFTWARE;
    }
    igea_eqerr_coef(N, r->P, N, r->xhat, (int)r->info[IGEA_STATS_INFO_N_TEST], r->spec, coef);
    if ((ec = diag_start(a, r, coef))) {
        free(coef);
        free(e);
        return ec;
    }
    double ss[6] = {0, 0, 0, 0, 0, 0};
    long row0 = 0, n;
    /* --threads T >= 2 (route eig): each block's residuals on T threads,
     * in the segments of pass 1 (the same results for every T >= 2) */
    int nth = a->route == IGEA_EQERR_ROUTE_SVD ? 1 : (int)a->opts[IGEA_EQERR_OPT_THREADS];
    if (j)
        json_head(j, r, a);
    residual_header(res, 0);
    cli_progress pr; /* (--progress with --quiet was refused in pass 1) */
    cli_progress_start(&pr, "eqerr", "rows, pass 2 of 2", r->m);
    while (!(ec = streams_next(a, s, &n)) && n > 0) {
        cli_progress_update(&pr, (double)(row0 + n));
        int st = igea_eqerr_residual_threads(IGEA_ROWMAJOR, (int)n, N, s->srows, N, s->drows,
                                             coef, (int)row0, e, ss, nth);
        if (!st)
            st = igea_eqerr_diag_add((int)n, e, (int)row0, r->dstate);
        if (st && (ec = s_failed(s)))
            break;
        if (st) {
            ec = cli_status(st, "eqerr residuals");
            break;
        }
        for (long i = 0; i < n; i++)
            residual_line(res, j, row0 + i, e[i]);
        row0 += n;
    }
    cli_progress_end(&pr);
    if (!ec)
        ec = cli_status(igea_eqerr_axis_rms(ss, r->rms), "eqerr residuals");
    for (int k = 0; !ec && k < 3; k++)
        r->diag_st[k] = igea_stats_diag_result(r->dstate + k * IGEA_STATS_DIAG_STATE_LEN,
                                               r->diag + k * IGEA_STATS_DIAG_LEN);
    free(coef);
    free(e);
    return ec;
}

/* Both passes over the streamed inputs. */
static int run_streamed(const eqerr_args *a, flight *r, FILE *res, cli_json *j)
{
    streams s;
    int ec = streams_open(a, &s);
    if (!ec)
        ec = flight_alloc(r, s.N);
    if (!ec && a->spec)
        ec = read_spec(a->spec, a->S, s.N, &r->spec);
    /* the library's threads, each with a one-thread BLAS */
    int blas = !ec && a->opts[IGEA_EQERR_OPT_THREADS] > 1 ? cli_blas_threads(1) : 0;
    if (!ec)
        ec = pass_solve(a, &s, r);
    if (!ec)
        ec = streams_rewind(&s);
    if (!ec)
        ec = pass_residuals(a, &s, r, res, j);
    cli_blas_threads(blas);
    streams_close(&s);
    return ec;
}

/* The whiteness and RMS of the whitened residuals, the epochs holding a
 * row the robust route rejected left out (the series closed up). */
static int noise_diag(const eqerr_args *a, flight *r)
{
    const cli_noise_result *nr = &r->nr;
    double *e = malloc((size_t)nr->m * sizeof(double)), ss[6] = {0, 0, 0, 0, 0, 0};
    if (!e)
        return cli_oom("the whitened residuals");
    int k = 0, st = 0;
    for (int ep = 0; ep < nr->m / 3; ep++) {
        const double *w = nr->row_w + 3 * ep;
        if (w[0] != 0 || w[1] != 0 || w[2] != 0)
            continue;
        for (int ax = 0; ax < 3; ax++, k++) {
            e[k] = nr->resid[3 * ep + ax];
            ss[ax] += e[k] * e[k];
            ss[3 + ax] += 1;
        }
    }
    st = igea_eqerr_axis_rms(ss, r->rms);
    if (!st && k > 0)
        st = igea_eqerr_diag(k, e, a->lags, r->diag, r->diag_st);
    for (int ax = 0; ax < 3 && k == 0; ax++)
        r->diag_st[ax] = IGEA_EEMPTY;
    free(e);
    return cli_status(st, "eqerr residual diagnostics");
}

/* The noise models: the flight in memory (eqerr_noise.c), its results
 * into the flight that the plain route's report reads. */
static int run_noise(const eqerr_args *a, flight *r, FILE *res, cli_json *j)
{
    cli_progress pr; /* one library call: no progress, but the options are checked */
    int ec = cli_progress_start(&pr, "eqerr", "rows", 0);
    if (ec)
        return ec;
    ec = cli_eqerr_noise(&a->na, &r->nr);
    if (!ec)
        ec = flight_alloc(r, r->nr.N);
    size_t n = (size_t)r->nr.N;
    if (!ec && r->nr.spec && !(r->spec = malloc(n * sizeof(double))))
        ec = cli_oom("the specs");
    if (ec)
        return ec;
    r->m = r->nr.m;
    memcpy(r->lambda, r->nr.lambda, (n * n + 3 * n) * sizeof(double)); /* lambda P xhat z */
    memcpy(r->reject, r->nr.reject, n * sizeof(int));
    memcpy(r->info, r->nr.info, sizeof r->info);
    if (r->spec)
        memcpy(r->spec, r->nr.spec, n * sizeof(double));
    if ((ec = noise_diag(a, r)))
        return ec;
    if (j)
        json_head(j, r, a);
    residual_header(res, 1);
    for (long i = 0; i < r->m; i++)
        residual_line(res, j, i, r->nr.resid[i]);
    return CLI_OK;
}

/* With --json to standard output the document is written to a temporary
 * stream first, so that a failure never leaves half a document behind. */
static int json_stream(FILE *out, FILE **jf)
{
    errno = 0;
    *jf = out == stdout ? tmpfile() : out;
    if (*jf)
        return CLI_OK;
    if (errno == ENOMEM)
        return cli_oom("a temporary file for the JSON document");
    cli_error("cannot create a temporary file: %s", strerror(errno));
    return CLI_IOERR;
}

static int json_copy(FILE *jf, FILE *out)
{
    char buf[65536];
    size_t k;
    if (jf == out)
        return CLI_OK;
    if (fflush(jf) != 0 || ferror(jf) || fseek(jf, 0, SEEK_SET) != 0) {
        cli_error("writing a temporary file: %s", strerror(errno));
        return errno == ENOMEM ? CLI_SOFTWARE : CLI_IOERR;
    }
    while ((k = fread(buf, 1, sizeof buf, jf)) > 0)
        fwrite(buf, 1, k, out);
    if (ferror(jf)) {
        cli_error("reading back a temporary file: %s", strerror(errno));
        return CLI_IOERR;
    }
    return CLI_OK;
}

/* --burnout with --burnout-errors: the state and E as given. */
static int burnout_given(const eqerr_args *a, const flight *r, double *s, double **E)
{
    int rows = 0, cols = 0, n = 0, ec;
    char **items = NULL;
    if (!a->burnout != !a->burnout_errors) {
        cli_error("--burnout, --burnout-errors: give both (the component miss) or neither");
        return CLI_USAGE;
    }
    if ((ec = cli_split_list(a->burnout, &items, &n)))
        return ec;
    if (n != 6) {
        cli_error("--burnout: %d numbers; six are needed (x,y,z,vx,vy,vz)", n);
        ec = CLI_USAGE;
    }
    for (int i = 0; !ec && i < 6; i++)
        ec = cli_parse_double("--burnout", items[i], &s[i]);
    free(items);
    if (!ec && !(ec = cli_read_colmajor(a->burnout_errors, E, &rows, &cols)) &&
        (rows != 6 || cols != r->N)) {
        cli_error("%s: %d x %d; the burnout errors are 6 rows (x y z vx vy vz) by the %d "
                  "columns of S", a->burnout_errors, rows, cols, r->N);
        ec = CLI_DATAERR;
    }
    return ec;
}

/* --burnout-time: the state and E of S's named terms at its specs
 * (igea_impact_burnout). */
static int burnout_traj(const eqerr_args *a, const flight *r, double *s, double **E)
{
    int *codes = malloc(sizeof(int) * (size_t)r->N);
    if (!codes || !(*E = malloc(sizeof(double) * 6 * (size_t)r->N))) {
        free(codes);
        return cli_oom("the burnout errors");
    }
    int ec = r->names ? CLI_OK : cli_usage("--burnout-time: the columns of S need their term "
                                           "names (--names, or the '# name ...' header of S)");
    for (int j = 0; j < r->N && !ec; j++)
        if ((codes[j] = igea_envfun_term_code(a->bo.system, r->names[j])) < 0) {
            cli_error("--burnout-time: column %d of S is '%s', not a %s term of the catalogue "
                      "(give --burnout and --burnout-errors)", j, r->names[j],
                      igea_choice_name(IGEA_CHOICE_ENVFUN_SYSTEM, a->bo.system));
            ec = CLI_USAGE;
        }
    if (!ec)
        ec = cli_burnout_compute(&a->bo, r->N, codes, r->spec, s, *E);
    free(codes);
    return ec;
}

/* The downrange and crossrange miss of each tested component
 * (igea_impact_component_miss, Kepler impact from the burnout). */
static int component_miss(const eqerr_args *a, flight *r)
{
    int nt = (int)r->info[IGEA_STATS_INFO_N_TEST], ec;
    double opts[IGEA_IMPACT_OPT_LEN], rf[3], vf[3], jac[IGEA_IMPACT_JAC_ROWS * 6], G[12];
    double *E = NULL, *s = r->burnout;
    ec = a->bo.given_time ? burnout_traj(a, r, s, &E) : burnout_given(a, r, s, &E);
    if (!ec && nt > 0 && !(r->cmiss = malloc(sizeof(double) * 2 * (size_t)nt)))
        ec = cli_oom("the component miss");
    if (!ec && nt > 0) {
        igea_impact_defaults(opts);
        int st = igea_impact_point(IGEA_IMPACT_KEPLER, opts, s, s + 3, rf, vf, NULL, jac,
                                   IGEA_IMPACT_JAC_ROWS);
        if (!st)
            st = igea_impact_miss_jacobian(jac, IGEA_IMPACT_JAC_ROWS, rf, vf, G, 2);
        if (!st)
            st = igea_impact_component_miss(r->N, nt, G, 2, E, 6, r->P, r->N, r->xhat, r->cmiss);
        if (st == IGEA_EDOMAIN)
            cli_error("%s: the flight does not come down to the Earth",
                      a->bo.given_time ? "--burnout-time" : "--burnout");
        ec = st == IGEA_EDOMAIN ? CLI_DATAERR : cli_status(st, "eqerr: the component miss");
    }
    free(E);
    return ec;
}

static void text_component_miss(FILE *f, const eqerr_args *a, const flight *r)
{
    int nt = (int)r->info[IGEA_STATS_INFO_N_TEST];
    const double *b = r->burnout;
    if (a->bo.given_time)
        fprintf(f, "burnout at %g s of %s (ECEF): %.3f %.3f %.3f m, %.4f %.4f %.4f m/s\n",
                a->bo.time, a->bo.traj, b[0], b[1], b[2], b[3], b[4], b[5]);
    fprintf(f, "miss at impact of each tested component at its equivalent error (Kepler, from "
               "%s):\n", a->bo.given_time ? "--burnout-time" : "--burnout");
    for (int i = 0; i < nt; i++)
        fprintf(f, "  %3d  %10.4g m downrange  %10.4g m crossrange%s\n", i, r->cmiss[2 * i],
                r->cmiss[2 * i + 1], r->reject[i] == 1 ? "  (rejected)" : "");
}

/* "component_miss": [[downrange, crossrange] per tested component]. */
static void json_component_miss(cli_json *j, const eqerr_args *a, const flight *r)
{
    cli_jnums(j, "burnout", r->burnout, 6);
    if (a->bo.given_time)
        cli_jnum(j, "burnout_time", a->bo.time);
    cli_json_open(j, "component_miss", '[');
    for (int i = 0; i < (int)r->info[IGEA_STATS_INFO_N_TEST]; i++)
        cli_jnums(j, NULL, r->cmiss + 2 * i, 2);
    cli_json_close(j);
}

/* The report (and the residuals) from the two passes. */
static int eqerr_report(const eqerr_args *a, flight *r, cli_out *out, cli_out *res)
{
    FILE *jf = NULL;
    cli_json j;
    int ec = a->json ? json_stream(out->f, &jf) : CLI_OK;
    if (jf)
        cli_json_begin(&j, jf);
    if (!ec)
        ec = (a->noise ? run_noise : run_streamed)(a, r, res->f, jf ? &j : NULL); /* NULL: none */
    if (!ec)
        ec = components_compute(a, r);
    if (!ec && (a->burnout || a->burnout_errors || a->bo.given_time))
        ec = component_miss(a, r);
    if (!ec && jf) {
        cli_json_close(&j);
        cli_jnums(&j, "rms", r->rms, 3);
        json_whiteness(&j, r);
        json_components(&j, r);
        if (r->cmiss)
            json_component_miss(&j, a, r);
        if (r->nr.lambda)
            cli_noise_json(&j, &r->nr);
        cli_json_end(&j);
        ec = json_copy(jf, out->f);
    } else if (!ec) {
        text_report(out->f, r, a);
    }
    if (jf && jf != out->f)
        fclose(jf);
    return ec;
}

int cmd_eqerr(int argc, char **argv)
{
    eqerr_args a;
    int ec = parse_eqerr(argc, argv, &a);
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    cli_out both[2] = {CLI_OUT_INIT, CLI_OUT_INIT};
    if ((ec = cli_out_open(&both[0], a.out)))
        return ec;
    if (a.residuals && (ec = cli_out_open(&both[1], a.residuals))) {
        cli_out_abort(&both[0]);
        return ec;
    }
    if (a.plot && !a.residuals && !(both[1].f = tmpfile())) { /* the residuals to draw */
        cli_out_abort(&both[0]);
        cli_error("eqerr: --plot: cannot create a temporary file");
        return CLI_IOERR;
    }
    flight r;
    memset(&r, 0, sizeof r);
    ec = eqerr_report(&a, &r, &both[0], &both[1]);
    if (!ec && a.plot)
        ec = cli_svg_eqerr(a.plot, &both[1], r.N, r.lambda, a.opts[IGEA_EQERR_OPT_LAMBDA_TEST],
                           a.opts[IGEA_EQERR_OPT_LAMBDA_SMALL]);
    if (a.plot && !a.residuals)
        cli_out_abort(&both[1]);
    /* the report and the residuals replace their old files together */
    if (!ec)
        ec = cli_out_commit_all(both, a.residuals ? 2 : 1);
    if (ec) {
        cli_out_abort(&both[0]);
        cli_out_abort(&both[1]);
    }
    int passed = r.info[IGEA_STATS_INFO_PASSED] == 1.0;
    flight_free(&r);
    return ec ? ec : passed ? CLI_OK : CLI_REJECT;
}

/* ---------------------------------------------------------------------- */
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

typedef struct {
    const char *table, *results, *units, *out;
    double alpha, lambda_test, zcrit;
    int json;
    int verdict; /* IGEA_STATS_VERDICT_* */
} test_args;

static test_args TA;
static const cli_opt test_options[] = {
    {"--table", CLI_OPT_STR, &TA.table, NULL, "FILE", "a table of (Xhat, lambda), as the seed's Table 1", NULL},
    {"--results", CLI_OPT_STR, &TA.results, NULL, "LIST", "comma-separated 'igea eqerr --json' results to pool", NULL},
    {"--unit-ids", CLI_OPT_STR, &TA.units, NULL, "LIST", "comma-separated unit ids, one per result", NULL},
    {"--alpha", CLI_OPT_NUM, &TA.alpha, "0.01", "A", "significance level", NULL},
    {"--lambda-test", CLI_OPT_NUM, &TA.lambda_test, "10", "L", "(--table) test components with lambda >= L", NULL},
    {"--z-crit", CLI_OPT_NUM, &TA.zcrit, NULL, "Z", "(--table) impose z_crit, e.g. 2.58 as the seed's tables", NULL},
    CLI_VERDICT_OPT(&TA.verdict),
    CLI_JSON_OPT(&TA.json),
    CLI_OUT_OPT(&TA.out),
    CLI_END};

static const cli_command test_command = {"test",
"usage: igea test --table FILE [options]\n"
"       igea test --results LIST [--unit-ids LIST] [options]\n"
"\n"
"Judges saved equivalent-error results (seed 000; METHODS 1.2 steps 4-6).\n"
"\n"
"--table FILE: a table of equivalent errors and their eigenvalues, like the\n"
"seed's Table 1: two columns (Xhat, lambda), or three or four columns\n"
"(component number, Xhat, lambda[, precision]). Every component with\n"
"lambda >= lambda_test is tested against z_{1-alpha/2} sqrt(1 + 1/lambda), and\n"
"all of them together by T = sum Xhat^2/(1 + 1/lambda) against chi2_alpha.\n"
"\n"
"--results LIST: outputs of 'igea eqerr --json' for independent flights, pooled:\n"
"T_tot = sum T_f with sum of the dof; accepted iff no component of any flight\n"
"is rejected and T_tot < chi2_alpha(dof_tot). Flights of the same inertial unit\n"
"are not independent: give --unit-ids (one id per file, e.g. 7,8,9) to have\n"
"that checked.\n"
"\n"
"options:\n",
test_options,
"\n"
"exit status: 0 accepted, 1 rejected, 64 usage, 65 bad input, 66 missing input.\n"
"\n"
"examples:\n"
"  igea test --table examples/seed000_table1.txt --z-crit 2.58\n"
"  igea test --unit-ids 1,2,3 --results f1.json,f2.json,f3.json\n"};

/* What the test judged: a table (n rows) or nfiles saved results. */
typedef struct {
    int n, nfiles, *rej, *dof, *nrej, *uid;
    double *x, *lam, *z, *chi2;
    double *zall; /* the pooled flights' z (--verdict other than seed) */
    int nz;
    char **files;
} test_run;

/* The eqerr options of the test command (alpha, z_crit, verdict). */
static void test_opts(const test_args *a, double *opts)
{
    igea_eqerr_defaults(opts);
    opts[IGEA_EQERR_OPT_ALPHA] = a->alpha;
    opts[IGEA_EQERR_OPT_Z_CRIT] = a->zcrit;
    opts[IGEA_EQERR_OPT_VERDICT] = a->verdict;
    opts[IGEA_EQERR_OPT_OVERALL_SIZE] = 1;
}

/* The verdict rule on the table's tested components (a pool of one). */
static int test_table_verdict(const test_args *a, test_run *r, double *info)
{
    double opts[IGEA_EQERR_OPT_LEN], T = info[IGEA_STATS_INFO_CHI2];
    int k = 0, dof = (int)info[IGEA_STATS_INFO_N_TEST];
    test_opts(a, opts);
    double *zt = malloc(sizeof(double) * r->n);
    int *rt = malloc(sizeof(int) * r->n);
    int ec = zt && rt ? CLI_OK : cli_oom("the table");
    for (int i = 0; !ec && i < r->n; i++)
        if (r->rej[i] >= 0)
            zt[k++] = r->z[i];
    if (!ec)
        ec = cli_status(igea_eqerr_pool(1, &T, &dof, zt, NULL, opts, rt, info), "test");
    for (int i = 0, q = 0; !ec && i < r->n; i++)
        if (r->rej[i] >= 0)
            r->rej[i] = rt[q++];
    free(zt);
    free(rt);
    return ec;
}

/* --table: the accuracy test of a table of (Xhat, lambda). */
static int test_table(const test_args *a, test_run *r, double *info)
{
    cli_matrix t;
    int ec = cli_read_matrix(a->table, &t);
    if (ec)
        return ec;
    int c0 = t.cols == 2 ? 0 : 1;
    if (t.cols < 2 || t.cols > 4 || t.rows > 100000) {
        cli_error("%s: expected 2 columns (Xhat, lambda) or 3-4 (n, Xhat, lambda[, precision]), "
                  "found %d", a->table, t.cols);
        cli_matrix_free(&t);
        return CLI_DATAERR;
    }
    int n = r->n = (int)t.rows;
    r->x = malloc(sizeof(double) * n), r->lam = malloc(sizeof(double) * n);
    r->z = malloc(sizeof(double) * n);
    r->rej = malloc(sizeof(int) * n);
    ec = (!r->x || !r->lam || !r->z || !r->rej) ? cli_oom("the table") : CLI_OK;
    for (int i = 0; !ec && i < n; i++) {
        r->x[i] = t.v[(size_t)i * t.cols + c0];
        r->lam[i] = t.v[(size_t)i * t.cols + c0 + 1];
        if (!(r->lam[i] > 0)) {
            cli_error("%s: row %d: eigenvalue %g must be > 0", a->table, i + 1, r->lam[i]);
            ec = CLI_DATAERR;
        }
    }
    cli_matrix_free(&t);
    if (ec)
        return ec;
    ec = cli_status(igea_stats_accuracy_test(n, r->x, r->lam, a->alpha, a->lambda_test,
                                             a->zcrit, r->z, r->rej, info), "test");
    return ec ? ec : test_table_verdict(a, r, info);
}

/* The numbers of the top-level array "key" of our own JSON output: *z
 * (malloc'd), *n of them; -1 when absent or not an array of numbers. */
static int json_numbers(const char *doc, const char *key, double **z, int *n)
{
    char pat[64];
    snprintf(pat, sizeof pat, "\"%s\":", key);
    const char *p = strstr(doc, pat);
    if (!p)
        return -1;
    p += strlen(pat);
    while (*p == ' ')
        p++;
    if (*p++ != '[')
        return -1;
    int cap = 16, k = 0;
    double *v = malloc(sizeof(double) * cap);
    while (v) {
        while (*p == ' ' || *p == '\n')
            p++;
        if (*p == ']' && k == 0)
            break;
        char *end;
        double x = strtod(p, &end);
        if (end == p)
            break;
        if (k == cap) {
            double *nv = cap < (1 << 24) ? realloc(v, sizeof(double) * (cap *= 2)) : NULL;
            if (!nv) {
                free(v);
                return -2;
            }
            v = nv;
        }
        v[k++] = x;
        for (p = end; *p == ' ' || *p == '\n'; p++)
            ;
        if (*p != ',')
            break;
        p++;
    }
    if (!v)
        return -2;
    if (*p != ']') {
        free(v);
        return -1;
    }
    *z = v;
    *n = k;
    return 0;
}

/* The "z" array of a saved result (dof values) appended to r->zall. */
static int read_result_z(const char *path, const char *doc, int dof, test_run *r)
{
    double *z = NULL;
    int n = 0, st = json_numbers(doc, "z", &z, &n);
    if (st == -2)
        return cli_oom(path);
    if (st || n != dof) {
        cli_error("%s: no \"z\" array of %d numbers (needed by --verdict other than seed)",
                  path, dof);
        free(z);
        return CLI_DATAERR;
    }
    double *nz = realloc(r->zall, sizeof(double) * ((size_t)r->nz + n + 1));
    if (!nz) {
        free(z);
        return cli_oom(path);
    }
    r->zall = nz;
    memcpy(r->zall + r->nz, z, sizeof(double) * n);
    r->nz += n;
    free(z);
    return CLI_OK;
}

/* chi2, dof and n_reject of one saved result (and its z when r). */
static int read_result(const char *path, double *chi2, int *dof, int *nrej, test_run *run)
{
    int ec = CLI_OK;
    char *doc = slurp(path, &ec);
    if (!doc)
        return ec;
    double T, d, r;
    if (json_number(doc, "chi2", &T) || json_number(doc, "dof", &d) ||
        json_number(doc, "n_reject", &r)) {
        cli_error("%s: not an 'igea eqerr --json' result (chi2, dof, n_reject missing)", path);
        ec = CLI_DATAERR;
    } else if (!(isfinite(T) && T >= 0)) {
        cli_error("%s: \"chi2\": %g is not a chi-square value (finite, >= 0)", path, T);
        ec = CLI_DATAERR;
    } else if (!is_count(d) || !is_count(r)) {
        cli_error("%s: \"%s\": %.17g is not a count (a whole number from 0 to %d)", path,
                  is_count(d) ? "n_reject" : "dof", is_count(d) ? r : d, INT_MAX);
        ec = CLI_DATAERR;
    } else {
        *chi2 = T;
        *dof = (int)d;
        *nrej = (int)r;
        if (run)
            ec = read_result_z(path, doc, *dof, run);
    }
    free(doc);
    return ec;
}

/* --unit-ids: one whole number per result file. */
static int read_unit_ids(const char *units, int nfiles, int *uid)
{
    const char *p = units;
    for (int f = 0; f < nfiles; f++) {
        char *end;
        long v = strtol(p, &end, 10);
        if (end == p || (*end != ',' && *end != '\0') || (*end == '\0' && f + 1 < nfiles)) {
            cli_error("--unit-ids %s: expected %d comma-separated whole numbers", units, nfiles);
            return CLI_USAGE;
        }
        uid[f] = (int)v;
        p = *end ? end + 1 : end;
    }
    if (*p) {
        cli_error("--unit-ids %s: more ids than result files (%d)", units, nfiles);
        return CLI_USAGE;
    }
    return CLI_OK;
}

/* --results: pool independent flights. */
static int test_pool(const test_args *a, test_run *r, double *info)
{
    int ec = cli_split_list(a->results, &r->files, &r->nfiles), nf = r->nfiles;
    if (ec)
        return ec;
    r->chi2 = malloc(sizeof(double) * nf);
    r->dof = malloc(sizeof(int) * nf), r->nrej = malloc(sizeof(int) * nf);
    r->uid = a->units ? malloc(sizeof(int) * nf) : NULL;
    ec = (!r->chi2 || !r->dof || !r->nrej || (a->units && !r->uid)) ? cli_oom("the pooled flights")
                                                                    : CLI_OK;
    if (!ec && a->units)
        ec = read_unit_ids(a->units, nf, r->uid);
    const int seed = a->verdict == IGEA_STATS_VERDICT_SEED;
    for (int f = 0; !ec && f < nf; f++)
        ec = read_result(r->files[f], &r->chi2[f], &r->dof[f], &r->nrej[f], seed ? NULL : r);
    if (ec)
        return ec;
    if (!seed) {
        double opts[IGEA_EQERR_OPT_LEN];
        test_opts(a, opts);
        return cli_status(igea_eqerr_pool(nf, r->chi2, r->dof, r->zall, r->uid, opts, NULL,
                                          info), "test");
    }
    /* the seed's pooling of the flights' own rejections, and its overall size */
    ec = cli_status(igea_stats_pool(nf, r->chi2, r->dof, r->nrej, r->uid, a->alpha, info),
                    "test");
    int n = (int)info[IGEA_STATS_INFO_DOF];
    double ta, tb, size = 0.0;
    if (!ec && n <= IGEA_STATS_UNION_N_MAX)
        ec = cli_status(igea_stats_verdict_thresholds(IGEA_STATS_VERDICT_SEED, n, a->alpha, &ta,
                                                      &tb, &size), "test");
    info[IGEA_STATS_INFO_VERDICT] = IGEA_STATS_VERDICT_SEED;
    info[IGEA_STATS_INFO_VERDICT_Z_CRIT] = info[IGEA_STATS_INFO_Z_CRIT];
    info[IGEA_STATS_INFO_VERDICT_CHI2_CRIT] = info[IGEA_STATS_INFO_CHI2_CRIT];
    info[IGEA_STATS_INFO_OVERALL_SIZE] = size;
    return ec;
}

static void test_report(FILE *f, const test_args *a, test_run *r, const double *info)
{
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, f);
        if (a->table) {
            int k = 0; /* the tested components, in order */
            for (int i = 0; i < r->n; i++)
                if (r->rej[i] >= 0)
                    r->z[k] = r->z[i], r->rej[k++] = r->rej[i];
            json_verdicts(&j, r->z, r->rej, k);
        } else {
            cli_jint(&j, "flights", r->nfiles);
        }
        json_test_fields(&j, info);
        cli_json_end(&j);
        return;
    }
    if (a->table) {
        fprintf(f, "igea test: %s, %d component(s), %d with lambda >= %g tested\n\n", a->table,
                r->n, (int)info[IGEA_STATS_INFO_N_TEST], a->lambda_test);
        report_components(f, r->n, r->x, r->lam, r->z, r->rej, info);
        fprintf(f, "(threshold = sqrt(1 + 1/lambda) z_crit, z_crit = %.6f)\n\n",
                info[IGEA_STATS_INFO_VERDICT_Z_CRIT]);
    } else {
        fprintf(f, "igea test: %d flight(s) pooled\n", r->nfiles);
        for (int k = 0; k < r->nfiles; k++)
            fprintf(f, "  %-30s T = %9.4f  dof %3d  rejected components %d\n", r->files[k],
                    r->chi2[k], r->dof[k], r->nrej[k]);
    }
    report_chi2(f, info, a->alpha);
}

int cmd_test(int argc, char **argv)
{
    int ec = cli_parse(&test_command, argc, argv);
    test_args a = TA;
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    if (!(a.alpha > 0 && a.alpha < 1) || !(a.lambda_test > 0) || a.zcrit < 0)
        return cli_usage("test: --alpha must be in (0, 1), --lambda-test > 0, --z-crit > 0");
    if (a.zcrit > 0 && a.verdict != IGEA_STATS_VERDICT_SEED)
        return cli_usage("test: --z-crit imposes the seed's component threshold: only with "
                         "--verdict seed");
    if ((a.table != NULL) == (a.results != NULL))
        return cli_usage("test: give either --table FILE or --results LIST (see igea test --help)");
    double info[IGEA_STATS_INFO_LEN];
    test_run r;
    memset(&r, 0, sizeof r);
    cli_out out;
    if (!(ec = a.table ? test_table(&a, &r, info) : test_pool(&a, &r, info)) &&
        !(ec = cli_out_open(&out, a.out))) {
        test_report(out.f, &a, &r, info);
        ec = cli_out_commit(&out);
    }
    free(r.x);
    free(r.lam);
    free(r.z);
    free(r.rej);
    free(r.chi2);
    free(r.dof);
    free(r.nrej);
    free(r.uid);
    free(r.files);
    free(r.zall);
    return ec ? ec : info[IGEA_STATS_INFO_PASSED] == 1.0 ? CLI_OK : CLI_REJECT;
}
