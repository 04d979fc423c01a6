/* igea regress - the classical separation estimators (least squares,
 * ridge, principal components, Bayes, empirical-Bayes ridge) on the inputs
 * of igea eqerr, with the collinearity diagnostics (METHODS 0.3, 4.3). */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

enum { M_LS = IGEA_REGRESS_METHOD_LS, M_RIDGE = IGEA_REGRESS_METHOD_RIDGE,
       M_PCE = IGEA_REGRESS_METHOD_PCE, M_BAYES = IGEA_REGRESS_METHOD_BAYES,
       M_EBR = IGEA_REGRESS_METHOD_EBR };
#define METHOD_NAME(m) igea_choice_name(IGEA_CHOICE_REGRESS_METHOD, (m))

typedef struct {
    const char *S, *dw, *sigma, *spec, *prior_mean, *prior_cov, *rule, *out;
    double k, eig_min, lam_floor, rcond, alpha;
    int method, json, ncomp, have_method, have_k, have_ncomp, have_eig_min, rule_code;
} rg_args;

static rg_args A;
static const cli_opt options[] = {
    {"--method", CLI_OPT_CHOICE, &A.method, NULL, CLI_CHOICES(IGEA_CHOICE_REGRESS_METHOD), "the estimator (required)", &A.have_method},
    {"--S", CLI_OPT_STR, &A.S, NULL, "FILE", "environment functions, m rows x N columns", NULL},
    {"--dw", CLI_OPT_STR, &A.dw, NULL, "FILE", "velocity differences, m values", NULL},
    {"--sigma", CLI_OPT_STR, &A.sigma, NULL, "FILE|NUM", "row 1-sigma, m values or one number (default 1)", NULL},
    {"--spec", CLI_OPT_STR, &A.spec, NULL, "FILE", "N term specs (1-sigma): the estimators work on\nS diag(spec)", NULL},
    {"--rcond", CLI_OPT_NUM, &A.rcond, NULL, "R", "ls: relative singular-value cut (default max(m,N) eps)", NULL},
    {"--k", CLI_OPT_NUM, &A.k, NULL, "K", "ridge: the ridge constant (instead of --rule)", &A.have_k},
    {"--rule", CLI_OPT_STR, &A.rule, NULL, "NAME", "ridge: hkb|lw|gcv|loo (Hoerl-Kennard-Baldwin, Lawless-\n"
     "Wang, generalised cross-validation, leave-one-out;\ndefault gcv); ebr: sc|mm|ml2 (default sc)", NULL},
    {"--ncomp", CLI_OPT_INT, &A.ncomp, NULL, "N", "pce: keep N components", &A.have_ncomp},
    {"--eig-min", CLI_OPT_NUM, &A.eig_min, NULL, "E", "pce: keep the components with eigenvalue >= E\n"
     "(default 1: at least as precise as spec)", &A.have_eig_min},
    {"--prior-mean", CLI_OPT_STR, &A.prior_mean, NULL, "FILE", "bayes: prior mean, N values (default 0)", NULL},
    {"--prior-cov", CLI_OPT_STR, &A.prior_cov, NULL, "FILE", "bayes: prior covariance, N x N (default\ndiag(spec^2), needs --spec)", NULL},
    {"--lam-floor", CLI_OPT_NUM, &A.lam_floor, "0", "L", "ebr: lower bound on lambda", NULL},
    {"--alpha", CLI_OPT_NUM, &A.alpha, "0.05", "A", "ls: level of the confidence intervals (1 - A)", NULL},
    CLI_JSON_OPT(&A.json),
    CLI_OUT_OPT(&A.out),
    CLI_END};

static const cli_command command = {"regress",
"usage: igea regress --method ls|ridge|pce|bayes|ebr --S FILE --dw FILE\n"
"                    [--sigma FILE|NUMBER] [--spec FILE] [options]\n"
"\n"
"Classical error separation of one flight: estimates of every coefficient X of\n"
"dw = S X + e, with standard deviations and the collinearity diagnostics that\n"
"say which coefficients the data determine at all (METHODS 0.3, 4.3).\n"
"Inputs as for 'igea eqerr'. With --spec the estimators work on the\n"
"spec-scaled design S diag(spec), so ridge, PCE and EBR shrink every term in\n"
"multiples of its spec, and the Bayesian prior defaults to X ~ N(0,\n"
"diag(spec^2)) (the in-spec system); estimates are always reported in the\n"
"units of S's columns.\n"
"\n"
"methods:\n"
"  ls      weighted least squares; minimum-norm solution if rank-deficient\n"
"  ridge   (S'WS + kI)^-1 S'W dw, k given or by a rule\n"
"  pce     principal components\n"
"  bayes   posterior mean with prior X ~ N(mu, P), noise known (sigma)\n"
"  ebr     empirical-Bayes ridge, METHODS 4.3\n"
"\n"
"Every estimator uses the SVD of the weighted design, never S'S. Coefficients\n"
"with a component in the null space of the design are flagged PRIOR: the\n"
"flight carries no information on them, whatever an estimator prints.\n"
"\n"
"options:\n",
options,
"\n"
"exit status: 0 ok, 64 usage, 65 bad input (also a design the method cannot\n"
"use, e.g. ebr with rank < 3), 66 missing input, 70 numerical failure, 74 I/O\n"
"error.\n"
"\n"
"example (the bundled flight):\n"
"  cd examples/flight\n"
"  igea regress --method ebr --S S.txt --dw dw.txt --sigma sigma.txt --spec spec.txt\n"
"  igea regress --method ridge --rule hkb --S S.txt --dw dw.txt --sigma 0.01 --json\n"};

/* The method's own options, checked. */
static const char *check_method(rg_args *a)
{
    static char msg[CLI_CHOICE_TEXT + 64];
    char names[CLI_CHOICE_TEXT];
    int k = 0;
    if (!(a->alpha > 0 && a->alpha < 1))
        return "regress: --alpha must be in (0, 1)";
    switch (a->method) {
    case M_RIDGE:
        if (a->have_k && a->rule)
            return "regress: give --k or --rule, not both";
        if (a->have_k && !(a->k >= 0))
            return "regress: --k must be >= 0";
        if (a->rule && (igea_choice_code(IGEA_CHOICE_REGRESS_RIDGE_RULE, a->rule, &k) ||
                        k == IGEA_REGRESS_RIDGE_FIXED)) {
            snprintf(msg, sizeof msg, "regress: --rule '%s': ridge takes one of %s but fixed "
                     "(that is --k K)", a->rule,
                     cli_choice_names(IGEA_CHOICE_REGRESS_RIDGE_RULE, names, sizeof names));
            return msg;
        }
        a->rule_code = a->have_k ? IGEA_REGRESS_RIDGE_FIXED
                                 : a->rule ? k : IGEA_REGRESS_RIDGE_GCV;
        return NULL;
    case M_EBR:
        if (a->rule && igea_choice_code(IGEA_CHOICE_REGRESS_EBR_RULE, a->rule, &k)) {
            snprintf(msg, sizeof msg, "regress: --rule '%s': one of %s for ebr", a->rule,
                     cli_choice_names(IGEA_CHOICE_REGRESS_EBR_RULE, names, sizeof names));
            return msg;
        }
        a->rule_code = a->rule ? k : IGEA_REGRESS_EBR_SC;
        return a->lam_floor >= 0 ? NULL : "regress: --lam-floor must be >= 0";
    case M_PCE:
        if (a->have_ncomp && a->have_eig_min)
            return "regress: give --ncomp or --eig-min, not both";
        if ((a->have_ncomp && a->ncomp < 1) || (a->have_eig_min && !(a->eig_min > 0)))
            return "regress: --ncomp must be >= 1 and --eig-min > 0";
        return NULL;
    case M_BAYES:
        return !a->prior_cov && !a->spec
                   ? "regress: bayes needs --prior-cov FILE or --spec FILE (prior diag(spec^2))"
                   : NULL;
    default:
        return NULL;
    }
}

static int parse(int argc, char **argv, rg_args *a)
{
    int ec = cli_parse(&command, argc, argv);
    *a = A;
    if (ec)
        return ec;
    if (!a->have_method || !a->S || !a->dw)
        return cli_usage("regress: --method, --S and --dw are required (see igea regress --help)");
    if (!(a->rcond < 1))
        return cli_usage("regress: --rcond must be < 1");
    return cli_usage(check_method(a));
}

/* Inputs, column-major for the library. */
typedef struct {
    int m, N;
    double *A, *y, *sig, *spec, *pm, *pc;
} rg_in;

static void in_free(rg_in *in)
{
    free(in->A);
    free(in->y);
    free(in->sig);
    free(in->spec);
    free(in->pm);
    free(in->pc);
}

static int read_inputs(const rg_args *a, rg_in *in)
{
    int ec = cli_read_colmajor(a->S, &in->A, &in->m, &in->N), m = in->m, N = in->N;
    if (ec)
        return ec;
    if ((ec = cli_read_vector(a->dw, m, "dw (one value per row of S)", &in->y, NULL)))
        return ec;
    if (a->sigma && (ec = cli_read_values(a->sigma, m, "--sigma (one per row of S)", &in->sig,
                                          NULL)))
        return ec;
    for (int i = 0; in->sig && i < m; i++)
        if (!(in->sig[i] > 0)) {
            cli_error("%s: row %d: sigma %g must be > 0", a->sigma, i + 1, in->sig[i]);
            return CLI_DATAERR;
        }
    if (a->spec && (ec = cli_read_vector(a->spec, N, "one spec per column of S", &in->spec, NULL)))
        return ec;
    for (int j = 0; in->spec && j < N; j++)
        if (!(in->spec[j] > 0)) {
            cli_error("%s: spec %d is %g; specs must be > 0", a->spec, j, in->spec[j]);
            return CLI_DATAERR;
        }
    if (a->prior_mean && (ec = cli_read_vector(a->prior_mean, N, "the prior mean", &in->pm, NULL)))
        return ec;
    if (a->prior_cov && (ec = cli_read_vector(a->prior_cov, (long)N * N,
                                              "the N x N prior covariance", &in->pc, NULL)))
        return ec;
    return CLI_OK;
}

typedef struct {
    int rank, count, *pd;
    double *x, *sd, *cov, *sdf, *shrink, *eig, *vif, *sdc;
    double scalar, sigma2, cond[IGEA_REGRESS_COND_LEN], info[IGEA_REGRESS_INFO_LEN];
    double *tv, *pv, *lo, *hi, *lev, *cd, dg[IGEA_REGRESS_DIAG_LEN];
    int have_diag;
    const char *count_name, *scalar_name;
} rg_out;

/* The estimator chosen, then sd = sqrt(diag(cov)) (least squares returns
 * it with the rank information). */
static int estimate(const rg_args *a, const rg_in *in, rg_out *r)
{
    int m = in->m, N = in->N, st;
    const double *A = in->A, *y = in->y, *sig = in->sig, *sp = in->spec;
    switch (a->method) {
    case M_LS:
        st = igea_regress_ls_ex(m, N, A, m, y, sig, sp, a->rcond, 0, r->x, r->cov, N, r->sd,
                                &r->sigma2, NULL, r->info);
        r->rank = (int)r->info[IGEA_REGRESS_INFO_RANK];
        break;
    case M_RIDGE:
        st = igea_regress_ridge_ex(m, N, A, m, y, sig, sp, a->rule_code, a->k, r->x, r->cov, N,
                                   &r->scalar, &r->sigma2, NULL, r->info);
        r->rank = (int)r->info[IGEA_REGRESS_INFO_RANK];
        r->scalar_name = "k";
        break;
    case M_PCE:
        st = igea_regress_pce_ex(m, N, A, m, y, sig, sp, a->have_ncomp ? a->ncomp : 0,
                                 a->have_eig_min ? a->eig_min : 1.0, r->x, r->cov, N, &r->count,
                                 &r->sigma2, NULL, r->info);
        r->rank = (int)r->info[IGEA_REGRESS_INFO_RANK];
        r->count_name = "ncomp";
        break;
    case M_BAYES:
        st = igea_regress_bayes(m, N, A, m, y, sig, sp, in->pm, in->pc, N, r->x, r->cov, N, NULL);
        r->sigma2 = 1.0;
        break;
    default:
        st = igea_regress_ebr(m, N, A, m, y, sig, sp, a->rule_code, a->lam_floor, r->x, r->cov,
                              N, &r->scalar, &r->rank, &r->sigma2, NULL, r->shrink, r->sdf);
        if (st == 0) /* the cut EBR applied to the same design */
            st = igea_regress_rank_info(m, N, A, m, sig, sp, 0.0, r->info);
        r->scalar_name = "lam";
        break;
    }
    if (st == 0 && a->method != M_LS)
        st = igea_regress_sd(N, r->cov, N, r->sd);
    if (st)
        return cli_status(st, METHOD_NAME(a->method));
    if (a->method == M_LS) { /* the diagnostics, when they are defined */
        /* x and sd again into unused scratch (shrink, sdf: EBR only) */
        st = igea_regress_ls_diag(m, N, A, m, y, sig, a->rcond, a->alpha, r->shrink, r->sdf, r->tv,
                                  r->pv, r->lo, r->hi, r->lev, r->cd, r->dg);
        r->have_diag = st == 0;
        if (st && st != IGEA_EDOMAIN)
            return cli_status(st, "ls: diagnostics");
    }
    return CLI_OK;
}

/* The statsmodels-OLS fields of least squares. */
static void json_diag(cli_json *j, int N, int m, double alpha, const rg_out *r)
{
    const double *d = r->dg;
    cli_jnum(j, "r2", d[IGEA_REGRESS_DIAG_R2]);
    cli_jnum(j, "r2_adj", d[IGEA_REGRESS_DIAG_R2_ADJ]);
    cli_jnum(j, "fvalue", d[IGEA_REGRESS_DIAG_FVALUE]);
    cli_jnum(j, "f_pvalue", d[IGEA_REGRESS_DIAG_F_PVALUE]);
    cli_jint(j, "df_model", (int)d[IGEA_REGRESS_DIAG_DF_MODEL]);
    cli_jint(j, "df_resid", (int)d[IGEA_REGRESS_DIAG_DF_RESID]);
    cli_jnums(j, "tvalues", r->tv, N);
    cli_jnums(j, "pvalues", r->pv, N);
    cli_jnum(j, "alpha", alpha);
    cli_jnums(j, "conf_int_lower", r->lo, N);
    cli_jnums(j, "conf_int_upper", r->hi, N);
    cli_jnum(j, "llf", d[IGEA_REGRESS_DIAG_LLF]);
    cli_jnum(j, "aic", d[IGEA_REGRESS_DIAG_AIC]);
    cli_jnum(j, "bic", d[IGEA_REGRESS_DIAG_BIC]);
    cli_jnums(j, "leverage", r->lev, m);
    cli_jnums(j, "cooks_d", r->cd, m);
    cli_jnum(j, "press", d[IGEA_REGRESS_DIAG_PRESS]);
    cli_jnum(j, "durbin_watson", d[IGEA_REGRESS_DIAG_DURBIN_WATSON]);
}

static void json_report(FILE *f, const rg_args *a, const rg_in *in, const rg_out *r)
{
    int N = in->N;
    cli_json j;
    cli_json_begin(&j, f);
    cli_jstr(&j, "method", METHOD_NAME(a->method));
    cli_jint(&j, "rows", in->m);
    cli_jint(&j, "n_terms", N);
    cli_jint(&j, "rank", r->rank);
    cli_jnums(&j, "x", r->x, N);
    cli_jnums(&j, "sd", r->sd, N);
    if (r->scalar_name)
        cli_jnum(&j, r->scalar_name, r->scalar);
    if (r->count_name)
        cli_jint(&j, r->count_name, r->count);
    if (a->method == M_EBR) {
        cli_jnums(&j, "sd_frequentist", r->sdf, N);
        cli_jnums(&j, "shrink", r->shrink, N);
    }
    cli_jnum(&j, "sigma2", r->sigma2);
    if (r->have_diag)
        json_diag(&j, N, in->m, a->alpha, r);
    if (a->method != M_BAYES)
        cli_jnum(&j, "rank_tol", r->info[IGEA_REGRESS_INFO_TOL]);
    if (a->method == M_LS)
        cli_jint(&j, "refine_steps", (int)r->info[IGEA_REGRESS_INFO_REFINE_STEPS]);
    if (a->method == M_RIDGE || a->method == M_PCE)
        cli_jint(&j, "scaled", (int)r->info[IGEA_REGRESS_INFO_SCALED]);
    cli_jnum(&j, "cond", r->cond[IGEA_REGRESS_COND_ALL]);
    cli_jnum(&j, "cond_estimable", r->cond[IGEA_REGRESS_COND_ESTIMABLE]);
    cli_jnums(&j, "eigenvalues", r->eig, N);
    cli_jnums(&j, "vif", r->vif, N);
    cli_jnums(&j, "sd_comb", r->sdc, N);
    cli_jbools(&j, "prior_determined", r->pd, N);
    cli_json_end(&j);
}

static void text_table(FILE *f, int N, const rg_out *r, int ebr)
{
    fprintf(f, "%5s %16s %14s", "term", "estimate", "sd");
    if (ebr)
        fprintf(f, " %14s", "sd_frequentist");
    fprintf(f, " %12s  %s\n", "VIF", "determined by");
    for (int j = 0; j < N; j++) {
        fprintf(f, "%5d %16.8e %14.6e", j, r->x[j], r->sd[j]);
        if (ebr)
            fprintf(f, " %14.6e", r->sdf[j]);
        fprintf(f, " %12.5g  %s\n", r->vif[j], r->pd[j] ? "PRIOR (null space)" : "data");
    }
    fprintf(f, "\neigenvalues of the (scaled) normal matrix and sd of each estimable "
               "combination v_i'X:\n");
    for (int i = 0; i < N; i++) {
        if (i < r->rank)
            fprintf(f, "%5d %14.6e %14.6e\n", i, r->eig[i], r->sdc[i]);
        else
            fprintf(f, "%5d %14.6e %14s\n", i, r->eig[i], "null space");
    }
}

static void text_report(FILE *f, const rg_args *a, const rg_in *in, const rg_out *r)
{
    int N = in->N, npd = 0;
    fprintf(f, "igea regress --method %s: %s (%d rows x %d terms)%s%s\n",
            METHOD_NAME(a->method), a->S, in->m, N, a->spec ? ", spec-scaled by " : "",
            a->spec ? a->spec : "");
    fprintf(f, "rank %d of %d; condition number %.4e (estimable part %.4e); residual "
               "variance %.6g\n", r->rank, N, r->cond[IGEA_REGRESS_COND_ALL],
               r->cond[IGEA_REGRESS_COND_ESTIMABLE], r->sigma2);
    if (a->method == M_LS)
        fprintf(f, "rank cut: singular values of the column-scaled design above %.3e; "
                   "%d refinement steps in extended precision\n",
                r->info[IGEA_REGRESS_INFO_TOL], (int)r->info[IGEA_REGRESS_INFO_REFINE_STEPS]);
    if ((a->method == M_RIDGE || a->method == M_PCE) && r->info[IGEA_REGRESS_INFO_SCALED])
        fprintf(f, "column norms differ by more than %.0e: columns scaled to unit norm "
                   "internally (the tuning constant is that of the scaled design)\n",
                IGEA_REGRESS_SCALE_RATIO);
    if (a->method == M_RIDGE || a->method == M_PCE || a->method == M_EBR)
        fprintf(f, "rank cut: singular values above %.3e\n", r->info[IGEA_REGRESS_INFO_TOL]);
    if (r->scalar_name)
        fprintf(f, "%s = %.10g\n", r->scalar_name, r->scalar);
    if (r->count_name)
        fprintf(f, "%s = %d\n", r->count_name, r->count);
    if (a->method == M_EBR) {
        fputs("shrink factors of the canonical components:", f);
        for (int i = 0; i < r->rank; i++)
            fprintf(f, " %.5f", r->shrink[i]);
        fputc('\n', f);
    }
    if (r->have_diag) {
        const double *d = r->dg;
        fprintf(f, "R2 %.6f, adjusted %.6f; F(%d, %d) = %.6g, p = %.4g; AIC %.6g, BIC %.6g; "
                   "Durbin-Watson %.4f; PRESS %.6g\n", d[IGEA_REGRESS_DIAG_R2],
                d[IGEA_REGRESS_DIAG_R2_ADJ], (int)d[IGEA_REGRESS_DIAG_DF_MODEL],
                (int)d[IGEA_REGRESS_DIAG_DF_RESID], d[IGEA_REGRESS_DIAG_FVALUE],
                d[IGEA_REGRESS_DIAG_F_PVALUE], d[IGEA_REGRESS_DIAG_AIC],
                d[IGEA_REGRESS_DIAG_BIC], d[IGEA_REGRESS_DIAG_DURBIN_WATSON],
                d[IGEA_REGRESS_DIAG_PRESS]);
        fprintf(f, "%5s %12s %12s %16s %16s\n", "term", "t", "P>|t|", "lower", "upper");
        for (int j = 0; j < N; j++)
            fprintf(f, "%5d %12.4f %12.4g %16.8e %16.8e\n", j, r->tv[j], r->pv[j], r->lo[j],
                    r->hi[j]);
    } else if (a->method == M_LS)
        fputs("R2, F, t tests: not defined (no residual degrees of freedom, an exact fit or "
              "an observation of leverage 1)\n", f);
    fputc('\n', f);
    text_table(f, N, r, a->method == M_EBR);
    for (int j = 0; j < N; j++)
        npd += r->pd[j];
    if (npd)
        fprintf(f, "\n%d coefficient(s) marked PRIOR have a component in the null space: the "
                   "flight does\nnot determine them; their estimates come from the method's "
                   "prior or minimum-norm convention.\n", npd);
}

int cmd_regress(int argc, char **argv)
{
    rg_args a;
    int ec = parse(argc, argv, &a);
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    rg_in in = {0};
    rg_out r = {0};
    double *work = NULL;
    if ((ec = read_inputs(&a, &in)))
        goto done;
    int N = in.N;
    work = malloc(((size_t)N * N + 13 * (size_t)N + 2 * (size_t)in.m) * sizeof(double));
    r.pd = malloc((size_t)N * sizeof(int));
    if (!work || !r.pd) {
        ec = cli_oom("the results");
        goto done;
    }
    r.cov = work, r.x = r.cov + (size_t)N * N, r.sd = r.x + N, r.sdf = r.sd + N;
    r.shrink = r.sdf + N, r.eig = r.shrink + N, r.vif = r.eig + N, r.sdc = r.vif + N;
    r.tv = r.sdc + N, r.pv = r.tv + N, r.lo = r.pv + N, r.hi = r.lo + N, r.lev = r.hi + N;
    r.cd = r.lev + in.m;
    int st = igea_regress_collinearity(in.m, N, in.A, in.m, in.y, in.sig, in.spec, a.rcond,
                                       r.cond, &r.rank, r.eig, NULL, 1, r.vif, r.sdc, r.pd);
    if ((ec = cli_status(st, "regress: diagnostics")) || (ec = estimate(&a, &in, &r)))
        goto done;
    cli_out o;
    if ((ec = cli_out_open(&o, a.out)))
        goto done;
    (a.json ? json_report : text_report)(o.f, &a, &in, &r);
    ec = cli_out_commit(&o);
done:
    in_free(&in);
    free(work);
    free(r.pd);
    return ec;
}
