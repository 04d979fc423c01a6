/* igea accel - dividing-head accelerometer calibration (seed 003). */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

typedef struct {
    const char *data, *prior, *out, *history;
    int model, method, rule, axis, json, refine, hyst, design, ieee, have_ieee, full;
    double lam_floor, scale_a, scale_b, tol, head_ratio, alpha;
} ac_args;

static ac_args A;

static const cli_opt options[] = {
    {"--data", CLI_OPT_STR, &A.data, NULL, "FILE", "the readings: angle (deg), A output, B output", NULL},
    {"--model", CLI_OPT_CHOICE, &A.model, "dual", CLI_CHOICES(IGEA_CHOICE_ACCEL_MODEL), "single reads the first two columns", NULL},
    {"--method", CLI_OPT_CHOICE, &A.method, "ls", CLI_CHOICES(IGEA_CHOICE_ACCEL_METHOD), "least squares, empirical-Bayes ridge, or joint\n"
     "(dual: radial g^2 and tangential equations with the\n"
     "head errors as nuisance, rank 10: K2 from the data)", NULL},
    {"--prior", CLI_OPT_STR, &A.prior, NULL, "FILE", "EBR prior scales tau_j, one per coefficient (9\n"
     "dual, 5 single), e.g. historical spreads", NULL},
    {"--history", CLI_OPT_STR, &A.history, NULL, "LIST", "--method ebr with the prior from earlier\n"
     "'igea accel --method joint --json' results of the\n"
     "same instrument type (comma-separated files):\n"
     "REML mean and spread, then the posterior, its sd\n"
     "with the uncertainty of the estimated prior\n"
     "(sd_plugin: taken as known), dof and interval", NULL},
    {"--full", CLI_OPT_FLAG, &A.full, NULL, NULL, "--history: a full instrument-to-instrument\n"
     "covariance Sigma (default: diagonal)", NULL},
    {"--alpha", CLI_OPT_NUM, &A.alpha, "0.05", "A", "--history: intervals at 1 - A", NULL},
    {"--rule", CLI_OPT_CHOICE, &A.rule, "sc", CLI_CHOICES(IGEA_CHOICE_REGRESS_EBR_RULE), "EBR rule for lambda (METHODS 4.3 eq. 17)", NULL},
    {"--lam-floor", CLI_OPT_NUM, &A.lam_floor, "0", "X", "EBR lower bound on lambda", NULL},
    {"--scale-a", CLI_OPT_NUM, &A.scale_a, "1", "K", "nominal scale factor of A (1: outputs in g)", NULL},
    {"--scale-b", CLI_OPT_NUM, &A.scale_b, "1", "K", "nominal scale factor of B", NULL},
    {"--tol", CLI_OPT_NUM, &A.tol, "1e-6", "DEG", "readings this close form one position", NULL},
    {"--axis", CLI_OPT_CHOICE, &A.axis, "pa", CLI_CHOICES(IGEA_CHOICE_ACCEL_AXIS), "rotation axis, names the cross-coupling Kio\n"
     "(pa, the door position) or Kip (oa)", NULL},
    {"--refine", CLI_OPT_FLAG, &A.refine, NULL, NULL, "dual: Gauss-Newton on the exact models (1)-(2)\n"
     "after the linear fit (for mg-level biases); the\nnull-space part of the fit is kept", NULL},
    {"--hysteresis", CLI_OPT_FLAG, &A.hyst, NULL, NULL, "also clockwise minus counter-clockwise per position\n"
     "with its sd from the repeated readings and the F test\n"
     "of zero hysteresis (directions from the row order:\n"
     "increasing angles = counter-clockwise)", NULL},
    {"--ieee", CLI_OPT_CHOICE, &A.ieee, NULL, CLI_CHOICES(IGEA_CHOICE_ACCEL_IEEE_METHOD),
     "fit the IEEE Std 1293 model instead (rows: angle,\n"
     "plane 0 IA-PA / 1 IA-OA, output), by least squares or\n"
     "the harmonic method (N >= 7 equispaced per plane)", &A.have_ieee},
    {"--design", CLI_OPT_FLAG, &A.design, NULL, NULL, "no fit: the D-criterion of the positions in --data\n"
     "(angle per row; with --ieee: angle, plane; the columns\n"
     "after those, a data file's readings, are not used) for\n"
     "--model and --method: (1/p) log det(M/n) of the\n"
     "information per reading, rank, per-coefficient variance\n"
     "factors", NULL},
    {"--head-ratio", CLI_OPT_NUM, &A.head_ratio, "0", "R", "--design --method joint: head-angle error sd over\n"
     "the output noise sd (1 arcsec / 1 ug: 4.85)", NULL},
    CLI_JSON_OPT(&A.json),
    CLI_OUT_OPT(&A.out),
    CLI_END};

static const cli_command command = {"accel",
"usage: igea accel --data FILE [options]\n"
"\n"
"Calibrates accelerometers in the gravity field from a multi-position tumble\n"
"on a dividing head turning about a horizontal axis (METHODS 4.1-4.3).\n"
"\n"
"The data hold one row per reading: head angle (deg), A output, B output\n"
"(text or .npy; '#' comments). Rows of the clockwise and counter-clockwise\n"
"runs at the same angle are averaged, and the 360 deg reading is averaged\n"
"with the 0 deg one. Outputs are in g, or raw (e.g. volts) with\n"
"--scale-a/--scale-b, the nominal scale factors in output units per g.\n"
"\n"
"Models:\n"
"  dual    orthogonal pair, g^2 observation (y_A^2 + y_B^2 - 1)/2: the head\n"
"          angle errors cancel, but KA0, KA2, KBix and KB0, KB2, KAix are\n"
"          coupled (rank 7 of 9); their individual values are flagged PRIOR:\n"
"          they come from the minimum-norm convention (ls) or the prior (ebr),\n"
"          not from the data. The estimable combinations are reported with sds.\n"
"  single  accelerometer A alone, y_A - sin(theta) on [1, s, c, s^2, sc]: all\n"
"          five coefficients identifiable, head errors enter as noise.\n""  --ieee  the IEEE Std 1293 model E = K1 (K0 + a_i + K2 a_i^2 + K3 a_i^3 +\n"
"          Kip a_i a_p + Kio a_i a_o + delta_o a_p - delta_p a_o) of one\n"
"          accelerometer; rows: angle, plane (0: IA-PA, head axis along OA;\n"
"          1: IA-OA, head axis along PA), output (any unit); ls or harmonic\n"
"          (Fourier, N >= 7 equispaced positions per plane).\n"
"\n"
"options:\n",
options,
"\n"
"example (the seed's 20-position experiment, 0..360 deg both ways):\n"
"  igea accel --data examples/accel_dual.txt\n"
"  igea accel --method ebr --prior examples/accel_prior.txt --data examples/accel_dual.txt\n"
"  igea accel --model single --json --data examples/accel_dual.txt\n"
"  igea accel --method joint --data examples/accel_dual.txt\n"
"  igea accel --method ebr --history cal1.json,cal2.json,... --data new.txt\n""  igea accel --ieee harmonic --data tumble.txt\n"
"  igea accel --design --model single --data positions.txt\n"
"\n"
"exit status: 0 ok, 64 usage, 65 bad input, 66 missing input, 70 numerical\n"
"failure, 74 output error.\n"};

static int parse(int argc, char **argv, ac_args *a)
{
    int ec = cli_parse(&command, argc, argv);
    *a = A;
    if (ec)
        return ec;
    return cli_usage(!a->data ? "accel: --data FILE is required (see igea accel --help)"
                     : a->scale_a == 0.0 || a->scale_b == 0.0 ? "accel: a scale factor must not be 0"
                     : !(a->tol >= 0.0 && a->tol < 45.0) ? "accel: --tol must be in [0, 45) degrees"
                     : a->lam_floor < 0.0 ? "accel: --lam-floor must be >= 0"
                     : a->refine && a->model != IGEA_ACCEL_DUAL
                         ? "accel: --refine needs the dual model"
                     : a->prior && a->method != IGEA_ACCEL_EBR
                         ? "accel: --prior needs --method ebr"
                     : a->history && (a->method != IGEA_ACCEL_EBR || a->prior || a->refine)
                         ? "accel: --history needs --method ebr, without --prior or --refine"
                     : a->full && !a->history ? "accel: --full needs --history"
                     : !(a->alpha > 0.0 && a->alpha < 1.0) ? "accel: --alpha must be in (0, 1)"
                     : a->method == IGEA_ACCEL_JOINT && a->model != IGEA_ACCEL_DUAL
                         ? "accel: --method joint needs the dual model"
                     : a->have_ieee && a->method != IGEA_ACCEL_LS
                         ? "accel: --ieee takes its method as its value (ls or harmonic), "
                           "not --method"
                     : (a->have_ieee || a->design) && (a->refine || a->hyst || a->prior)
                         ? "accel: --refine, --hysteresis and --prior do not combine with "
                           "--ieee or --design"
                     : !(a->head_ratio >= 0.0) ? "accel: --head-ratio must be >= 0"
                     : a->method == IGEA_ACCEL_JOINT && a->refine
                         ? "accel: --refine keeps the null-space part of a dual fit; it does not "
                           "combine with --method joint" : NULL);
}

typedef struct {
    int dual, np, nc, nr, npos;
    const char *names[10], *cnames[7], *units[10];
    double *ang, *ya, *yb, *th, *ma, *mb, *phi; /* nr each */
    int *cnt;
    double tau[9], coef[10], sd[10], cmb[7], csd[7], info[IGEA_ACCEL_INFO_LEN], comp[2];
    double cov[100]; /* joint: the 10 x 10 covariance */
    double pmean[9], pcov[81]; /* --history: the prior */
    double sdp[9], sdof[9], ci[18], hinfo[IGEA_ACCEL_HFIT_LEN];
    int nhist;
    double rcoef[9], rsd[9], rcmb[7], rinfo[IGEA_ACCEL_INFO_LEN];
    int flag[10];
    /* hysteresis of A and B: angle, diff, sd (nr each), counts, test */
    double *h_th, *h_d[2], *h_sd[2], h_test[2][IGEA_ACCEL_HYST_LEN];
    int *h_ncw[2], *h_nccw[2], h_npos;
} ac_run;

static void setup(const ac_args *a, ac_run *r)
{
    r->dual = a->model == IGEA_ACCEL_DUAL;
    r->np = r->dual ? IGEA_ACCEL_NP_DUAL : IGEA_ACCEL_NP_SINGLE;
    r->nc = r->dual ? IGEA_ACCEL_NC_DUAL : IGEA_ACCEL_NC_SINGLE;
    for (int j = 0; j < r->np; j++) {
        r->names[j] = igea_accel_coef_name(a->model, a->axis, j);
        r->units[j] = igea_accel_coef_unit(a->model, j);
    }
    for (int k = 0; k < r->nc; k++)
        r->cnames[k] = igea_accel_comb_name(a->model, a->axis, k);
    if (a->method == IGEA_ACCEL_JOINT) { /* the 9 dual coefficients and delta0 */
        r->np = IGEA_ACCEL_NP_JOINT;
        r->names[9] = igea_accel_coef_name(IGEA_ACCEL_SINGLE, a->axis, IGEA_ACCEL_DELTA0);
        r->units[9] = igea_accel_coef_unit(IGEA_ACCEL_SINGLE, IGEA_ACCEL_DELTA0);
    }
}

/* The readings (angle, A[, B]) and the prior scales. */
static int read_inputs(const ac_args *a, ac_run *r)
{
    cli_matrix in = {0};
    int ec = cli_read_matrix(a->data, &in);
    if (ec)
        return ec;
    if (in.cols < (r->dual ? 3 : 2)) {
        cli_error("%s: %d column(s); expected angle, A output%s per row", a->data, in.cols,
                  r->dual ? ", B output" : "");
        ec = CLI_DATAERR;
    } else if (in.rows > 10000000L) {
        cli_error("%s: too many rows", a->data);
        ec = CLI_DATAERR;
    } else if (!(r->ang = malloc((size_t)in.rows * 7 * sizeof(double) + 1)) ||
               !(r->cnt = malloc((size_t)in.rows * sizeof(int) + 1))) {
        ec = cli_oom("the readings");
    }
    if (ec) {
        cli_matrix_free(&in);
        return ec;
    }
    int nr = r->nr = (int)in.rows;
    r->ya = r->ang + nr, r->yb = r->ya + nr, r->th = r->yb + nr, r->ma = r->th + nr;
    r->mb = r->ma + nr, r->phi = r->mb + nr;
    for (int i = 0; i < nr; i++) {
        r->ang[i] = in.v[(size_t)i * in.cols];
        r->ya[i] = in.v[(size_t)i * in.cols + 1];
        r->yb[i] = r->dual ? in.v[(size_t)i * in.cols + 2] : 0.0;
    }
    cli_matrix_free(&in);
    if (a->prior) {
        double *p;
        if ((ec = cli_read_vector(a->prior, r->np, "the prior (one scale per coefficient)", &p,
                                  NULL)))
            return ec;
        memcpy(r->tau, p, (size_t)r->np * sizeof(double));
        free(p);
    }
    return CLI_OK;
}

/* CW - CCW per position of each output (outputs in g). */
static int hysteresis(const ac_args *a, ac_run *r)
{
    int nr = r->nr, no = r->dual ? 2 : 1;
    size_t nn = (size_t)nr;
    if (!(r->h_th = malloc(nn * 5 * sizeof(double))) ||
        !(r->h_ncw[0] = malloc(nn * 4 * sizeof(int))))
        return cli_oom("the hysteresis");
    r->h_d[0] = r->h_th + nn, r->h_d[1] = r->h_d[0] + nn;
    r->h_sd[0] = r->h_d[1] + nn, r->h_sd[1] = r->h_sd[0] + nn;
    r->h_ncw[1] = r->h_ncw[0] + nn, r->h_nccw[0] = r->h_ncw[1] + nn;
    r->h_nccw[1] = r->h_nccw[0] + nn;
    for (int o = 0; o < no; o++) {
        int st = igea_accel_hysteresis(nr, r->ang, NULL, o ? r->yb : r->ya, a->tol, r->h_th,
                                       r->h_d[o], r->h_sd[o], r->h_ncw[o], r->h_nccw[o],
                                       &r->h_npos, r->h_test[o]);
        if (st)
            return cli_status(st, "accel --hysteresis");
    }
    return CLI_OK;
}

/* --method ebr --history: the prior from the files (REML, diagonal or
 * --full Sigma), the posterior with the uncertainty of that estimated
 * prior, and which coefficients the data determine (the others: from the
 * prior). */
static int history_fit(const ac_args *a, ac_run *r)
{
    double load[9], sv[9], tau[9], su[81], *b, *V;
    int rank, np = r->np, ec = cli_accel_history_read(a->history, np, &b, &V, &r->nhist);
    if (ec)
        return ec;
    /* a full Sigma's EM creeps towards a singular estimate with short
     * histories (26469 iterations for 14 calibrations in the tests) */
    int st = a->full ? igea_accel_history_full(r->nhist, np, b, np, V, np, 200000, 1e-8,
                                               r->pmean, su, np, r->pcov, np, NULL)
                     : igea_accel_history(r->nhist, np, b, np, V, np, 20000, 1e-8, r->pmean, tau,
                                          r->pcov, np, NULL);
    for (int j = 0; !st && !a->full && j < np; j++)
        for (int k = 0; k < np; k++)
            su[k + j * np] = k == j ? tau[j] * tau[j] : 0.0;
    if (!st)
        st = igea_accel_fit_history(a->model, r->npos, r->th, r->ma, r->dual ? r->mb : NULL,
                                    r->nhist, b, np, V, np, su, np, a->full, a->alpha, r->coef,
                                    r->sd, r->sdp, r->sdof, r->ci, NULL, 1, r->hinfo);
    free(b);
    for (int k = 0; !st && k < IGEA_ACCEL_INFO_LEN; k++)
        r->info[k] = r->hinfo[k];
    if (!st)
        st = igea_accel_analyze(a->model, r->npos, r->th, sv, NULL, 1, load, NULL, &rank);
    for (int j = 0; !st && j < np; j++)
        r->flag[j] = load[j] > IGEA_ACCEL_LOADING_TOL;
    r->nc = 0; /* the posterior's combinations are not reported */
    return cli_status(st, "accel --history");
}

/* Scale to g, merge the positions, fit, and refine. */
static int compute(const ac_args *a, ac_run *r)
{
    int nr = r->nr, ec;
    int st = igea_accel_to_g(nr, r->ya, a->scale_a, r->ya);
    if (!st && r->dual)
        st = igea_accel_to_g(nr, r->yb, a->scale_b, r->yb);
    if (st)
        return cli_status(st, "accel");
    if (a->hyst && (ec = hysteresis(a, r)))
        return ec;
    if (!st)
        st = igea_accel_merge(nr, r->ang, r->ya, r->dual ? r->yb : NULL, a->tol, r->th, r->ma,
                              r->dual ? r->mb : NULL, r->cnt, &r->npos);
    if (!st && a->method == IGEA_ACCEL_JOINT) {
        st = igea_accel_joint(r->npos, r->th, r->ma, r->mb, r->coef, r->sd, r->cov, 10, r->comp,
                              r->cmb, r->csd, r->info);
        memset(r->flag, 0, sizeof r->flag);
    } else if (!st && a->history) {
        return history_fit(a, r);
    } else if (!st)
        st = igea_accel_fit(a->model, a->method, r->npos, r->th,
                            r->ma, r->mb, a->prior ? r->tau : NULL, a->rule,
                            a->lam_floor, r->coef, r->sd, r->flag, r->cmb, r->csd, r->info);
    if (st)
        return cli_status(st, "accel");
    if (!a->refine)
        return CLI_OK;
    st = igea_accel_refine(r->npos, r->th, r->ma, r->mb, r->coef, 100, 1e-13, r->rcoef, r->rsd,
                           r->phi, r->rinfo);
    if (!st)
        st = igea_accel_combine(IGEA_ACCEL_DUAL, r->rcoef, r->rcmb);
    return cli_status(st, "accel --refine");
}

static void json_report(FILE *f, const ac_args *a, const ac_run *r)
{
    cli_json j;
    cli_json_begin(&j, f);
    cli_jstr(&j, "model", igea_choice_name(IGEA_CHOICE_ACCEL_MODEL, a->model));
    cli_jstr(&j, "method", igea_choice_name(IGEA_CHOICE_ACCEL_METHOD, a->method));
    cli_jint(&j, "positions", r->npos);
    cli_jint(&j, "readings", r->nr);
    cli_jnums(&j, "theta_deg", r->th, r->npos);
    cli_jints(&j, "readings_per_position", r->cnt, r->npos);
    cli_jstrs(&j, "names", r->names, r->np);
    cli_jnums(&j, "coef", r->coef, r->np);
    cli_jnums(&j, "sd", r->sd, r->np);
    cli_json_open(&j, "flags", '[');
    for (int i = 0; i < r->np; i++)
        cli_jstr(&j, NULL, r->flag[i] ? "prior" : "data");
    cli_json_close(&j);
    cli_jstrs(&j, "comb_names", r->cnames, r->nc);
    cli_jnums(&j, "comb", r->cmb, r->nc);
    cli_jnums(&j, "comb_sd", r->csd, r->nc);
    cli_jint(&j, "rank", (long)r->info[IGEA_ACCEL_INFO_RANK]);
    cli_jint(&j, "dof", (long)r->info[IGEA_ACCEL_INFO_DOF]);
    cli_jnum(&j, "sigma", r->info[IGEA_ACCEL_INFO_SIGMA]);
    cli_jnum(&j, "rms", r->info[IGEA_ACCEL_INFO_RMS]);
    cli_jnum(&j, "lam", r->info[IGEA_ACCEL_INFO_LAMBDA]);
    if (a->method == IGEA_ACCEL_JOINT) {
        cli_jnum(&j, "sd_radial", r->comp[IGEA_ACCEL_JOINT_SD_RADIAL]);
        cli_jnum(&j, "sd_angle", r->comp[IGEA_ACCEL_JOINT_SD_ANGLE]);
        cli_jrows(&j, "cov", r->cov, IGEA_ACCEL_NP_JOINT, IGEA_ACCEL_NP_JOINT);
    }
    if (a->history) {
        cli_jint(&j, "history", r->nhist);
        cli_jbool(&j, "full", a->full);
        cli_jnum(&j, "alpha", a->alpha);
        cli_jnums(&j, "prior_mean", r->pmean, r->np);
        cli_jrows(&j, "prior_cov", r->pcov, r->np, r->np);
        cli_jnums(&j, "sd_plugin", r->sdp, r->np);
        cli_jnums(&j, "sd_dof", r->sdof, r->np);
        cli_jnums(&j, "conf_int_lower", r->ci, r->np);
        cli_jnums(&j, "conf_int_upper", r->ci + r->np, r->np);
        cli_jint(&j, "capped", (long)r->hinfo[IGEA_ACCEL_HFIT_CAPPED]);
    }
    if (a->hyst)
        for (int o = 0; o < (r->dual ? 2 : 1); o++) {
            const double *t = r->h_test[o];
            cli_json_open(&j, o ? "hysteresis_b" : "hysteresis_a", '{');
            cli_jnums(&j, "theta_deg", r->h_th, r->h_npos);
            cli_jnums(&j, "diff", r->h_d[o], r->h_npos);
            cli_jnums(&j, "diff_sd", r->h_sd[o], r->h_npos);
            cli_jints(&j, "n_cw", r->h_ncw[o], r->h_npos);
            cli_jints(&j, "n_ccw", r->h_nccw[o], r->h_npos);
            cli_jnum(&j, "f", t[IGEA_ACCEL_HYST_F]);
            cli_jint(&j, "df1", (long)t[IGEA_ACCEL_HYST_DF1]);
            cli_jint(&j, "df2", (long)t[IGEA_ACCEL_HYST_DF2]);
            cli_jnum(&j, "p", t[IGEA_ACCEL_HYST_P]);
            cli_jnum(&j, "sigma", t[IGEA_ACCEL_HYST_SIGMA]);
            cli_json_close(&j);
        }
    if (a->refine) {
        cli_json_open(&j, "refined", '{');
        cli_jnums(&j, "coef", r->rcoef, IGEA_ACCEL_NP_DUAL);
        cli_jnums(&j, "sd", r->rsd, IGEA_ACCEL_NP_DUAL);
        cli_jnums(&j, "comb", r->rcmb, r->nc);
        cli_jnums(&j, "phi_deg", r->phi, r->npos);
        cli_jint(&j, "iterations", (long)r->rinfo[IGEA_ACCEL_INFO_ITER]);
        cli_jnum(&j, "sigma", r->rinfo[IGEA_ACCEL_INFO_SIGMA]);
    }
    cli_json_end(&j);
}

static void text_refined(FILE *f, const ac_run *r)
{
    fprintf(f, "\nexact-model refinement (%d iterations, residual sd %.3e g per output):\n",
            (int)r->rinfo[IGEA_ACCEL_INFO_ITER], r->rinfo[IGEA_ACCEL_INFO_SIGMA]);
    for (int j = 0; j < IGEA_ACCEL_NP_DUAL; j++)
        fprintf(f, "%-9s %15.6e %12.3e  %s\n", r->names[j], r->rcoef[j], r->rsd[j],
                r->flag[j] ? "null part kept from the fit" : "data");
    for (int k = 0; k < r->nc; k++)
        fprintf(f, "%-9s %15.6e\n", r->cnames[k], r->rcmb[k]);
}

static void text_hysteresis(FILE *f, const ac_run *r)
{
    for (int o = 0; o < (r->dual ? 2 : 1); o++) {
        const double *t = r->h_test[o];
        fprintf(f, "\nhysteresis of %c (clockwise - counter-clockwise): F = %.4g on (%d, %d), "
                   "p = %.4g; pooled sd %.3e g\n%9s %14s %12s %4s %4s\n",
                o ? 'B' : 'A', t[IGEA_ACCEL_HYST_F], (int)t[IGEA_ACCEL_HYST_DF1],
                (int)t[IGEA_ACCEL_HYST_DF2], t[IGEA_ACCEL_HYST_P], t[IGEA_ACCEL_HYST_SIGMA],
                "theta", "cw - ccw", "sd", "ncw", "nccw");
        for (int k = 0; k < r->h_npos; k++)
            fprintf(f, "%9.3f %14.6e %12.3e %4d %4d\n", r->h_th[k], r->h_d[o][k],
                    r->h_sd[o][k], r->h_ncw[o][k], r->h_nccw[o][k]);
    }
}

/* --history: sd with the uncertainty of the estimated prior, the plug-in
 * sd, the dof and the interval. */
static void text_history(FILE *f, const ac_args *a, const ac_run *r)
{
    fprintf(f, "\n\n%-9s %-6s %15s %11s %11s %6s  %-31s %s\n", "coef", "unit", "estimate", "sd",
            "sd_plugin", "dof", "interval", "determined by");
    int anyprior = 0;
    for (int j = 0; j < r->np; j++) {
        char iv[64];
        snprintf(iv, sizeof iv, "[%.6e, %.6e]", r->ci[j], r->ci[r->np + j]);
        fprintf(f, "%-9s %-6s %15.6e %11.3e %11.3e %6.1f  %-31s %s\n", r->names[j], r->units[j],
                r->coef[j], r->sd[j], r->sdp[j], r->sdof[j], iv, r->flag[j] ? "PRIOR" : "data");
        anyprior |= r->flag[j];
    }
    fprintf(f, "sd: root mean squared error with the uncertainty of the estimated prior and of "
               "the\nresidual variance; sd_plugin takes them as known; interval: estimate -+ "
               "t(dof) sd\nat %g %%.\n", 100.0 * (1.0 - a->alpha));
    if ((int)r->hinfo[IGEA_ACCEL_HFIT_CAPPED])
        fprintf(f, "WARNING: the history is too short for the correction of %d coefficient(s): "
                   "its\nfactor was capped at 5 (see docs/accel.md).\n",
                (int)r->hinfo[IGEA_ACCEL_HFIT_CAPPED]);
    if (anyprior)
        fprintf(f, "PRIOR: the calibration holds no information on these coefficients one by "
                   "one;\ntheir values and sds combine it with the prior of the instrument type\n"
                   "(REML from the --history files).\n");
}

static void text_report(FILE *f, const ac_args *a, const ac_run *r)
{
    int ls = a->method == IGEA_ACCEL_LS, joint = a->method == IGEA_ACCEL_JOINT;
    fprintf(f, "igea accel: %s model, %s; %d readings -> %d positions; rank %d, dof %d\n",
            igea_choice_name(IGEA_CHOICE_ACCEL_MODEL, a->model),
            ls ? "least squares" : joint ? "joint radial + tangential fit"
                                         : "empirical-Bayes ridge", r->nr,
            r->npos, (int)r->info[IGEA_ACCEL_INFO_RANK], (int)r->info[IGEA_ACCEL_INFO_DOF]);
    if (joint)
        fprintf(f, "equation sds: radial (g^2) %.3e g, tangential %.3e g; weighted residual "
                   "sd %.4f", r->comp[IGEA_ACCEL_JOINT_SD_RADIAL],
                r->comp[IGEA_ACCEL_JOINT_SD_ANGLE], r->info[IGEA_ACCEL_INFO_SIGMA]);
    else
        fprintf(f, "residual sd %.3e g, rms %.3e g", r->info[IGEA_ACCEL_INFO_SIGMA],
                r->info[IGEA_ACCEL_INFO_RMS]);
    if (a->history)
        fprintf(f, "; prior from %d earlier calibrations (REML, %s Sigma)", r->nhist,
                a->full ? "full" : "diagonal");
    else if (!ls && !joint)
        fprintf(f, ", lambda %.6g%s", r->info[IGEA_ACCEL_INFO_LAMBDA],
                a->prior ? " (prior-scaled)" : " (isotropic prior)");
    if (a->history) {
        text_history(f, a, r);
        return;
    }
    fprintf(f, "\n\n%-9s %-6s %15s %12s  %s\n", "coef", "unit", "estimate", "sd", "determined by");
    int anyprior = 0;
    for (int j = 0; j < r->np; j++) {
        fprintf(f, "%-9s %-6s %15.6e %12.3e  %s\n", r->names[j], r->units[j], r->coef[j],
                r->sd[j], r->flag[j] ? (ls ? "PRIOR (minimum-norm convention)"
                                           : "PRIOR (not from the data)") : "data");
        anyprior |= r->flag[j];
    }
    if (anyprior)
        fprintf(f, "PRIOR: the calibration holds no information on these coefficients "
                   "one by one;\ntheir values and sds follow the %s, not the instrument: "
                   "use the estimable\ncombinations below.\n",
                ls ? "minimum-norm convention" : "prior");
    if (r->nc)
        fprintf(f, "\n%-9s %15s %12s\n", "estimable", "estimate", "sd");
    for (int k = 0; k < r->nc; k++)
        fprintf(f, "%-9s %15.6e %12.3e\n", r->cnames[k], r->cmb[k], r->csd[k]);
    if (a->hyst)
        text_hysteresis(f, r);
    if (a->refine)
        text_refined(f, r);
}

int cmd_accel(int argc, char **argv)
{
    ac_args a;
    int ec = parse(argc, argv, &a);
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    if (a.design || a.have_ieee) {
        cli_accel_args x = {a.data, a.out, a.have_ieee ? IGEA_ACCEL_IEEE : a.model,
                            a.have_ieee ? a.ieee : a.method, a.axis, a.json, a.tol,
                            a.head_ratio};
        return a.design ? cli_accel_design(&x) : cli_accel_ieee(&x);
    }
    ac_run r = {0};
    setup(&a, &r);
    cli_out o;
    if (!(ec = read_inputs(&a, &r)) && !(ec = compute(&a, &r)) && !(ec = cli_out_open(&o, a.out))) {
        (a.json ? json_report : text_report)(o.f, &a, &r);
        ec = cli_out_commit(&o);
    }
    free(r.ang);
    free(r.cnt);
    free(r.h_th);
    free(r.h_ncw[0]);
    return ec;
}
