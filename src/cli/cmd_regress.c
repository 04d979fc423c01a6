/* igea regress - the classical separation estimators (least squares,
 * ridge, principal components, Bayes, empirical-Bayes ridge) on the inputs
 * of igea eqerr, with the collinearity diagnostics (METHODS 0.3, 4.3). */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static void regress_help(void)
{
    printf(
"usage: igea regress --method ls|ridge|pce|bayes|ebr --S FILE --dw FILE\n"
"                    [--sigma FILE|NUMBER] [--spec FILE] [options]\n"
"\n"
"Classical error separation of one flight: estimates of every coefficient X of\n"
"dw = S X + e, with standard deviations and the collinearity diagnostics that\n"
"say which coefficients the data determine at all (METHODS 0.3, 4.3).\n"
"Inputs as for 'igea eqerr': S (m rows x N terms), dw (m values), sigma (the\n"
"row 1-sigma, a file or one number; default 1) and spec (N 1-sigma specs).\n"
"With --spec the estimators work on the spec-scaled design S diag(spec), so\n"
"ridge, PCE and EBR shrink every term in multiples of its spec, and the\n"
"Bayesian prior defaults to X ~ N(0, diag(spec^2)) (the in-spec system);\n"
"estimates are always reported in the units of S's columns.\n"
"\n"
"Every estimator uses the SVD of the weighted design, never S'S. Coefficients\n"
"with a component in the null space of the design are flagged PRIOR: the\n"
"flight carries no information on them, whatever an estimator prints.\n"
"\n"
"methods and their options:\n"
"  ls      weighted least squares; minimum-norm solution if rank-deficient\n"
"          --rcond R      relative singular-value cut (default max(m,N) eps)\n"
"  ridge   (S'WS + kI)^-1 S'W dw\n"
"          --k K | --rule hkb|lw|gcv|loo   (Hoerl-Kennard-Baldwin, Lawless-\n"
"          Wang, generalised cross-validation, leave-one-out; default gcv)\n"
"  pce     principal components: --ncomp N | --eig-min E (default: all\n"
"          components with eigenvalue >= 1, i.e. at least as precise as spec)\n"
"  bayes   posterior mean with prior X ~ N(mu, P), noise known (sigma):\n"
"          --prior-mean FILE (N values, default 0), --prior-cov FILE (N x N;\n"
"          default diag(spec^2), needs --spec)\n"
"  ebr     empirical-Bayes ridge, METHODS 4.3: --rule sc|mm|ml2 (default sc),\n"
"          --lam-floor L (default 0); rows are whitened by sigma first\n"
"\n"
"other options:\n"
"  --json         machine-readable output\n"
"  --out FILE     write the report there (atomically) instead of stdout\n"
"\n"
"exit status: 0 ok, 64 usage, 65 bad input, 66 missing input, 70 numerical\n"
"failure (e.g. ebr with rank < 3), 74 I/O error.\n"
"\n"
"example (the bundled flight):\n"
"  cd examples/flight\n"
"  igea regress --method ebr --S S.txt --dw dw.txt --sigma sigma.txt --spec spec.txt\n"
"  igea regress --method ridge --rule hkb --S S.txt --dw dw.txt --sigma 0.01 --json\n");
}

typedef struct {
    const char *method, *S, *dw, *sigma, *spec, *prior_mean, *prior_cov, *rule, *out;
    double sigma_value, k, eig_min, lam_floor, rcond;
    int sigma_is_number, json, ncomp, have_k, have_ncomp, have_eig_min;
} rg_args;

static int parse(int argc, char **argv, rg_args *a)
{
    memset(a, 0, sizeof *a);
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i], *v;
        int ec;
#define NEED() do { if (!(v = cli_optarg(argc, argv, &i))) return CLI_USAGE; } while (0)
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) {
            regress_help();
            return -1;
        } else if (!strcmp(o, "--method")) { NEED(); a->method = v; }
        else if (!strcmp(o, "--S")) { NEED(); a->S = v; }
        else if (!strcmp(o, "--dw")) { NEED(); a->dw = v; }
        else if (!strcmp(o, "--spec")) { NEED(); a->spec = v; }
        else if (!strcmp(o, "--prior-mean")) { NEED(); a->prior_mean = v; }
        else if (!strcmp(o, "--prior-cov")) { NEED(); a->prior_cov = v; }
        else if (!strcmp(o, "--rule")) { NEED(); a->rule = v; }
        else if (!strcmp(o, "--out")) { NEED(); a->out = v; }
        else if (!strcmp(o, "--json")) a->json = 1;
        else if (!strcmp(o, "--sigma")) {
            NEED();
            if ((ec = cli_file_or_positive(o, v, &a->sigma_is_number, &a->sigma_value)))
                return ec;
            a->sigma = v;
        } else if (!strcmp(o, "--k")) {
            NEED();
            if ((ec = cli_parse_double(o, v, &a->k)))
                return ec;
            a->have_k = 1;
        } else if (!strcmp(o, "--eig-min")) {
            NEED();
            if ((ec = cli_parse_double(o, v, &a->eig_min)))
                return ec;
            a->have_eig_min = 1;
        } else if (!strcmp(o, "--lam-floor")) {
            NEED();
            if ((ec = cli_parse_double(o, v, &a->lam_floor)))
                return ec;
        } else if (!strcmp(o, "--rcond")) {
            NEED();
            if ((ec = cli_parse_double(o, v, &a->rcond)))
                return ec;
        } else if (!strcmp(o, "--ncomp")) {
            NEED();
            if ((ec = cli_parse_int(o, v, &a->ncomp)))
                return ec;
            a->have_ncomp = 1;
        } else {
            cli_error("regress: unknown option '%s' (see igea regress --help)", o);
            return CLI_USAGE;
        }
#undef NEED
    }
    if (!a->method || !a->S || !a->dw) {
        cli_error("regress: --method, --S and --dw are required (see igea regress --help)");
        return CLI_USAGE;
    }
    const char *ms[] = {"ls", "ridge", "pce", "bayes", "ebr"};
    int ok = 0;
    for (int i = 0; i < 5; i++)
        ok |= !strcmp(a->method, ms[i]);
    if (!ok) {
        cli_error("regress: --method %s: expected ls, ridge, pce, bayes or ebr", a->method);
        return CLI_USAGE;
    }
    if (!strcmp(a->method, "ridge")) {
        if (a->have_k && a->rule) {
            cli_error("regress: give --k or --rule, not both");
            return CLI_USAGE;
        }
        if (a->have_k && !(a->k >= 0)) {
            cli_error("regress: --k must be >= 0");
            return CLI_USAGE;
        }
        if (a->rule && strcmp(a->rule, "hkb") && strcmp(a->rule, "lw") &&
            strcmp(a->rule, "gcv") && strcmp(a->rule, "loo")) {
            cli_error("regress: --rule %s: expected hkb, lw, gcv or loo for ridge", a->rule);
            return CLI_USAGE;
        }
    }
    if (!strcmp(a->method, "ebr")) {
        if (a->rule && strcmp(a->rule, "sc") && strcmp(a->rule, "mm") && strcmp(a->rule, "ml2")) {
            cli_error("regress: --rule %s: expected sc, mm or ml2 for ebr", a->rule);
            return CLI_USAGE;
        }
        if (!(a->lam_floor >= 0)) {
            cli_error("regress: --lam-floor must be >= 0");
            return CLI_USAGE;
        }
    }
    if (!strcmp(a->method, "pce")) {
        if (a->have_ncomp && a->have_eig_min) {
            cli_error("regress: give --ncomp or --eig-min, not both");
            return CLI_USAGE;
        }
        if ((a->have_ncomp && a->ncomp < 1) || (a->have_eig_min && !(a->eig_min > 0))) {
            cli_error("regress: --ncomp must be >= 1 and --eig-min > 0");
            return CLI_USAGE;
        }
    }
    if (!strcmp(a->method, "bayes") && !a->prior_cov && !a->spec) {
        cli_error("regress: bayes needs --prior-cov FILE or --spec FILE (prior diag(spec^2))");
        return CLI_USAGE;
    }
    if (!(a->rcond < 1)) {
        cli_error("regress: --rcond must be < 1");
        return CLI_USAGE;
    }
    return CLI_OK;
}

/* Read a file holding exactly n numbers (any layout). */
static int read_n(const char *path, long n, const char *what, double **out)
{
    cli_matrix m;
    int ec = cli_read_matrix(path, &m);
    if (ec)
        return ec;
    if (m.rows * m.cols != n) {
        cli_error("%s: %ld values, but %s needs %ld", path, m.rows * m.cols, what, n);
        cli_matrix_free(&m);
        return CLI_DATAERR;
    }
    *out = m.v;
    return CLI_OK;
}

typedef struct {
    int m, N, rank, count;
    double *x, *sd, *extra1, *shrink, *eig, *vif, *sdc;
    int *pd;
    double scalar, sigma2, cond[2];
    const char *count_name, *scalar_name, *extra1_name;
} rg_out;

static void json_report(FILE *f, const rg_args *a, const rg_out *r)
{
    fprintf(f, "{\n  \"method\": \"%s\",\n  \"rows\": %d,\n  \"terms\": %d,\n  \"rank\": %d,\n",
            a->method, r->m, r->N, r->rank);
    fputs("  \"x\": ", f);
    cli_json_array(f, r->x, r->N);
    fputs(",\n  \"sd\": ", f);
    cli_json_array(f, r->sd, r->N);
    if (r->scalar_name) {
        fprintf(f, ",\n  \"%s\": ", r->scalar_name);
        cli_json_num(f, r->scalar);
    }
    if (r->count_name)
        fprintf(f, ",\n  \"%s\": %d", r->count_name, r->count);
    if (r->extra1_name) {
        fprintf(f, ",\n  \"%s\": ", r->extra1_name);
        cli_json_array(f, r->extra1, r->N);
    }
    if (r->shrink) {
        fputs(",\n  \"shrink\": ", f);
        cli_json_array(f, r->shrink, r->N);
    }
    fputs(",\n  \"sigma2\": ", f);
    cli_json_num(f, r->sigma2);
    fputs(",\n  \"cond\": ", f);
    cli_json_num(f, r->cond[0]);
    fputs(",\n  \"cond_estimable\": ", f);
    cli_json_num(f, r->cond[1]);
    fputs(",\n  \"eigenvalues\": ", f);
    cli_json_array(f, r->eig, r->N);
    fputs(",\n  \"vif\": ", f);
    cli_json_array(f, r->vif, r->N);
    fputs(",\n  \"sd_comb\": ", f);
    cli_json_array(f, r->sdc, r->N);
    fputs(",\n  \"prior_determined\": [", f);
    for (int j = 0; j < r->N; j++)
        fprintf(f, "%s%s", j ? ", " : "", r->pd[j] ? "true" : "false");
    fputs("]\n}\n", f);
}

static void text_report(FILE *f, const rg_args *a, const rg_out *r)
{
    fprintf(f, "igea regress --method %s: %s (%d rows x %d terms)%s%s\n", a->method, a->S,
            r->m, r->N, a->spec ? ", spec-scaled by " : "", a->spec ? a->spec : "");
    fprintf(f, "rank %d of %d; condition number %.4e (estimable part %.4e); residual "
               "variance %.6g\n", r->rank, r->N, r->cond[0], r->cond[1], r->sigma2);
    if (r->scalar_name)
        fprintf(f, "%s = %.10g\n", r->scalar_name, r->scalar);
    if (r->count_name)
        fprintf(f, "%s = %d\n", r->count_name, r->count);
    if (r->shrink) {
        fputs("shrink factors of the canonical components:", f);
        for (int i = 0; i < r->rank; i++)
            fprintf(f, " %.5f", r->shrink[i]);
        fputc('\n', f);
    }
    fputc('\n', f);
    fprintf(f, "%5s %16s %14s", "term", "estimate", "sd");
    if (r->extra1_name)
        fprintf(f, " %14s", r->extra1_name);
    fprintf(f, " %12s  %s\n", "VIF", "determined by");
    for (int j = 0; j < r->N; j++) {
        fprintf(f, "%5d %16.8e %14.6e", j + 1, r->x[j], r->sd[j]);
        if (r->extra1_name)
            fprintf(f, " %14.6e", r->extra1[j]);
        fprintf(f, " %12.5g  %s\n", r->vif[j], r->pd[j] ? "PRIOR (null space)" : "data");
    }
    fprintf(f, "\neigenvalues of the (scaled) normal matrix and sd of each estimable "
               "combination v_i'X:\n");
    for (int i = 0; i < r->N; i++) {
        if (i < r->rank)
            fprintf(f, "%5d %14.6e %14.6e\n", i + 1, r->eig[i], r->sdc[i]);
        else
            fprintf(f, "%5d %14.6e %14s\n", i + 1, r->eig[i], "null space");
    }
    int npd = 0;
    for (int j = 0; j < r->N; j++)
        npd += r->pd[j];
    if (npd)
        fprintf(f, "\n%d coefficient(s) marked PRIOR have a component in the null space: the "
                   "flight does\nnot determine them; their estimates come from the method's "
                   "prior or minimum-norm convention.\n", npd);
}

int cmd_regress(int argc, char **argv)
{
    if (cli_one_stdin(argc, argv))
        return CLI_USAGE;
    rg_args a;
    int ec = parse(argc, argv, &a);
    if (ec < 0)
        return CLI_OK;
    if (ec)
        return ec;
    cli_matrix S = {0, 0, 0}, dw = {0, 0, 0}, sg = {0, 0, 0};
    double *spec = NULL, *pm = NULL, *pc = NULL, *work = NULL;
    int *pd = NULL;
    if ((ec = cli_read_matrix(a.S, &S)) || (ec = cli_read_matrix(a.dw, &dw)))
        goto done;
    if (a.sigma && !a.sigma_is_number && (ec = cli_read_matrix(a.sigma, &sg)))
        goto done;
    if (dw.cols != 1 || dw.rows != S.rows ||
        (a.sigma && !a.sigma_is_number && (sg.cols != 1 || sg.rows != S.rows))) {
        cli_error("%s%s%s: dw and sigma must be single columns with as many rows as %s (%ld)",
                  a.dw, a.sigma && !a.sigma_is_number ? ", " : "",
                  a.sigma && !a.sigma_is_number ? a.sigma : "", a.S, S.rows);
        ec = CLI_DATAERR;
        goto done;
    }
    if (S.rows > 2147483647L) {
        cli_error("%s: too many rows", a.S);
        ec = CLI_DATAERR;
        goto done;
    }
    int m = (int)S.rows, N = S.cols;
    if (a.spec && (ec = read_n(a.spec, N, "one spec per column of S", &spec)))
        goto done;
    if (spec)
        for (int j = 0; j < N; j++)
            if (!(spec[j] > 0)) {
                cli_error("%s: spec %d is %g; specs must be > 0", a.spec, j + 1, spec[j]);
                ec = CLI_DATAERR;
                goto done;
            }
    if (a.prior_mean && (ec = read_n(a.prior_mean, N, "the prior mean", &pm)))
        goto done;
    if (a.prior_cov && (ec = read_n(a.prior_cov, (long)N * N, "the N x N prior covariance", &pc)))
        goto done;
    size_t nn = (size_t)N * N, mn = (size_t)m * N;
    work = malloc((mn + 3 * (size_t)m + nn * 2 + 12 * (size_t)N) * sizeof(double));
    pd = malloc((size_t)N * sizeof(int));
    if (!work || !pd) {
        cli_error("out of memory");
        ec = CLI_SOFTWARE;
        goto done;
    }
    double *A = work, *y = A + mn, *sig = y + m, *res = sig + m, *cov = res + m, *P = cov + nn,
           *x = P + nn, *sd = x + N, *e1 = sd + N, *e2 = e1 + N, *eig = e2 + N, *vif = eig + N,
           *sdc = vif + N, *mu = sdc + N;
    /* A = S diag(spec), column-major. */
    for (int i = 0; i < m; i++) {
        y[i] = dw.v[i];
        sig[i] = !a.sigma ? 1.0 : (a.sigma_is_number ? a.sigma_value : sg.v[i]);
        for (int j = 0; j < N; j++)
            A[i + (size_t)j * m] = S.v[(size_t)i * N + j] * (spec ? spec[j] : 1.0);
    }
    for (int i = 0; i < m; i++)
        if (!(sig[i] > 0)) {
            cli_error("%s: row %d: sigma %g must be > 0", a.sigma, i + 1, sig[i]);
            ec = CLI_DATAERR;
            goto done;
        }
    rg_out r;
    memset(&r, 0, sizeof r);
    r.m = m;
    r.N = N;
    r.x = x;
    r.sd = sd;
    r.extra1 = e1;
    r.eig = eig;
    r.vif = vif;
    r.sdc = sdc;
    r.pd = pd;
    int st = igea_regress_collinearity(m, N, A, m, y, sig, NULL, a.rcond, r.cond, &r.rank, eig, NULL,
                                       1, vif, sdc, pd);
    if (st) {
        ec = cli_status(st, "regress: diagnostics");
        goto done;
    }
    int have_cov = 1;
    if (!strcmp(a.method, "ls")) {
        st = igea_regress_ls(m, N, A, m, y, sig, NULL, a.rcond, x, cov, N, &r.rank, &r.sigma2, res);
    } else if (!strcmp(a.method, "ridge")) {
        int rule = a.have_k ? IGEA_REGRESS_RIDGE_FIXED
                   : !a.rule || !strcmp(a.rule, "gcv") ? IGEA_REGRESS_RIDGE_GCV
                   : !strcmp(a.rule, "hkb") ? IGEA_REGRESS_RIDGE_HKB
                   : !strcmp(a.rule, "lw") ? IGEA_REGRESS_RIDGE_LW : IGEA_REGRESS_RIDGE_LOO;
        st = igea_regress_ridge(m, N, A, m, y, sig, NULL, rule, a.k, x, cov, N, &r.scalar, &r.sigma2,
                                res);
        r.scalar_name = "k";
    } else if (!strcmp(a.method, "pce")) {
        int nc = a.have_ncomp ? a.ncomp : 0;
        double em = a.have_eig_min ? a.eig_min : 1.0;
        st = igea_regress_pce(m, N, A, m, y, sig, NULL, nc, em, x, cov, N, &r.count, &r.sigma2, res);
        r.count_name = "ncomp";
    } else if (!strcmp(a.method, "bayes")) {
        /* prior on the scaled coefficients X/spec */
        for (int i = 0; i < N; i++) {
            mu[i] = pm ? pm[i] / (spec ? spec[i] : 1.0) : 0.0;
            for (int j = 0; j < N; j++)
                P[i + (size_t)j * N] =
                    pc ? pc[(size_t)i * N + j] / ((spec ? spec[i] : 1.0) * (spec ? spec[j] : 1.0))
                       : (i == j ? 1.0 : 0.0);
        }
        st = igea_regress_bayes(m, N, A, m, y, sig, NULL, mu, P, N, x, cov, N, res);
        r.sigma2 = 1.0;
    } else {
        int rule = !a.rule || !strcmp(a.rule, "sc") ? IGEA_REGRESS_EBR_SC
                   : !strcmp(a.rule, "mm") ? IGEA_REGRESS_EBR_MM : IGEA_REGRESS_EBR_ML2;
        st = igea_regress_ebr(m, N, A, m, y, sig, NULL, rule, a.lam_floor, x, cov, N,
                              &r.scalar, &r.rank, &r.sigma2, NULL, e2, e1);
        r.scalar_name = "lambda";
        r.extra1_name = "sd_frequentist";
        r.shrink = e2;
    }
    if (st) {
        ec = cli_status(st, a.method);
        goto done;
    }
    if (have_cov)
        for (int j = 0; j < N; j++)
            sd[j] = sqrt(cov[j + (size_t)j * N]);
    /* back to the units of S's columns */
    for (int j = 0; j < N; j++) {
        double s = spec ? spec[j] : 1.0;
        x[j] *= s;
        sd[j] *= s;
        if (r.extra1_name)
            e1[j] *= s;
    }
    cli_out o;
    if ((ec = cli_out_open(&o, a.out)))
        goto done;
    if (a.json)
        json_report(o.f, &a, &r);
    else
        text_report(o.f, &a, &r);
    ec = cli_out_commit(&o);
done:
    cli_matrix_free(&S);
    cli_matrix_free(&dw);
    cli_matrix_free(&sg);
    free(spec);
    free(pm);
    free(pc);
    free(work);
    free(pd);
    return ec;
}
