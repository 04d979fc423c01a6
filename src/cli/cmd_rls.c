/* igea rls - recursive estimation of tool-error coefficients over a stream
 * of epochs (seed 001, METHODS 2): per-epoch estimates, anomaly flags and
 * compensated telemetry. */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

typedef struct {
    const char *data, *S, *dw, *sigma, *x0, *gamma0, *out;
    int k, p, variant, policy, every, json;
    double kappa, jump, forget;
    const char *plot; /* --plot FILE.svg */
} rls_args;

static rls_args A;

static const cli_opt options[] = {
    CLI_HEAD("input (text or .npy; streamed, so records longer than memory are fine):"),
    {"--data", CLI_OPT_STR, &A.data, NULL, "FILE", "one row per epoch: y_1..y_k, then the k x m block\n"
     "c row by row (c_11..c_1m, c_21..c_2m, ...): k + k m\ncolumns", NULL},
    {"--S", CLI_OPT_STR, &A.S, NULL, "FILE", "or the 'igea eqerr' layout: S with k rows per epoch\n"
     "(epoch-major, m columns), with --dw", NULL},
    {"--dw", CLI_OPT_STR, &A.dw, NULL, "FILE", "one value per row of S", NULL},
    {"--k", CLI_OPT_INT, &A.k, "3", "K", "observation rows per epoch (3: x, y, z)", NULL},
    {"--sigma", CLI_OPT_STR, &A.sigma, NULL, "FILE|NUM", "tracking 1-sigma per row: a number, a file of k\n"
     "values (the same every epoch) or, with --S/--dw, one\nvalue per row of S; default 1: y and c already\nwhitened", NULL},
    {"--x0", CLI_OPT_STR, &A.x0, NULL, "FILE", "initial estimate, m values (default 0)", NULL},
    {"--gamma0", CLI_OPT_STR, &A.gamma0, "1e6", "G", "initial Gamma (whitened units): a number g for g I,\n"
     "a file of m values (diagonal) or of m x m values\n(1e6: diffuse, then standard RLS is batch least\nsquares)", NULL},
    CLI_HEAD("\nestimator:"),
    {"--variant", CLI_OPT_CHOICE, &A.variant, "standard", CLI_CHOICES(IGEA_CHOICE_RLS_VARIANT), "the RLS variant", NULL},
    {"--p", CLI_OPT_INT, &A.p, "1", "P", "order of the polynomial / number of iterations", NULL},
    {"--forget", CLI_OPT_NUM, &A.forget, "1", "L", "forgetting factor 0 < L <= 1 (1: none)", NULL},
    {"--anomaly", CLI_OPT_CHOICE, &A.policy, "none", CLI_CHOICES(IGEA_CHOICE_RLS_ANOMALY), "none: flag only; replace: the patent's variant\n"
     "A (previous epoch's y); skip: no update at an\nanomalous epoch; isolate: variant B, the flagged\n"
     "rows are dropped from that epoch's update", NULL},
    {"--kappa", CLI_OPT_NUM, &A.kappa, "4", "K", "innovation test |e_j| > K sd", NULL},
    {"--jump", CLI_OPT_NUM, &A.jump, NULL, "J", "jump test |y_j - y_prev,j| > J (physical units;\n"
     "default off; catches telemetry dropouts to zero)", NULL},
    CLI_HEAD("\noutput: by default one line per epoch: epoch (from 0), action (0 updated,\n"
             "1 flagged, 2 replaced, 3 skipped, 4 isolated), k flags (bits: 1 innovation,\n"
             "2 jump, 4 missing, 8 row unused), m estimates, k compensated values y - c x;\n"
             "then '#' lines with the final estimate, its honest standard deviations and Q_p"),
    {"--every", CLI_OPT_INT, &A.every, "1", "N", "print every N-th epoch only (0: the final summary\nonly)", NULL},
    {"--json", CLI_OPT_FLAG, &A.json, NULL, NULL, "machine-readable output (same content)", NULL},
    CLI_OUT_OPT(&A.out),
    {"--plot", CLI_OPT_STR, &A.plot, NULL, "FILE.svg", "draw the estimates and their 3-sigma bands against\nthe epoch into an SVG picture", NULL},
    CLI_END};

static const cli_command command = {"rls",
"usage: igea rls (--data FILE | --S FILE --dw FILE) [--k K] [options]\n"
"\n"
"Estimates the constant tool-error coefficients X of y_n = c_n X + v_n epoch by\n"
"epoch (recursive least squares, METHODS 2), as a real-time loop would: each\n"
"epoch's k observations (telemetry minus tracking) update the estimate once.\n"
"\n",
options,
"\n"
"Q_p falls as p grows by construction; it is not a measure of accuracy\n"
"(METHODS 2.6): read the honest standard deviations beside it.\n"
"\n"
"exit status: 0 ok, 64 usage, 65 bad input, 66 missing input, 70 numerical\n"
"failure, 74 I/O error.\n"
"\n"
"example (a 4-coefficient, 2-row record; the 3rd epoch's first row is bad):\n"
"  cat > rec.txt <<EOF\n"
"  # y1 y2  c11 c12 c13 c14  c21 c22 c23 c24\n"
"  1.0 2.0  1 0 0 0  0 1 0 0\n"
"  3.0 4.0  0 0 1 0  0 0 0 1\n"
"  9.0 5.0  1 1 0 0  0 1 1 0\n"
"  4.0 6.0  1 0 1 0  0 1 0 1\n"
"  EOF\n"
"  igea rls --data rec.txt --k 2 --gamma0 100 --variant polynomial -p 3 \\\n"
"           --anomaly isolate --sigma 0.01\n"};

static int parse(int argc, char **argv, rls_args *a)
{
    A.jump = INFINITY;
    int ec = cli_parse(&command, argc, argv);
    *a = A;
    if (ec)
        return ec;
    if (!a->data == !(a->S || a->dw) || (!a->data && !(a->S && a->dw))) {
        cli_error("rls: give either --data FILE or both --S FILE and --dw FILE");
        return CLI_USAGE;
    }
    if (a->k < 1) {
        cli_error("rls: --k %d: need at least one row per epoch", a->k);
        return CLI_USAGE;
    }
    if (a->p < 1 || a->p > 1000000) {
        cli_error("rls: --p %d: need 1 <= p <= 1000000", a->p);
        return CLI_USAGE;
    }
    if (a->every < 0) {
        cli_error("rls: --every %d: need N >= 0", a->every);
        return CLI_USAGE;
    }
    if (!(a->kappa > 0) || !(a->jump > 0) || !(a->forget > 0 && a->forget <= 1)) {
        cli_error("rls: need --kappa > 0, --jump > 0 and 0 < --forget <= 1");
        return CLI_USAGE;
    }
    return CLI_OK;
}

/* A number, or a file of exactly one of the allowed sizes (n1, n2: 0 = no). */
static int read_num_or_file(const char *what, const char *s, long n1, long n2,
                            double *num, cli_matrix *mat, int *is_num)
{
    char *end;
    double v = strtod(s, &end);
    if (end != s && *end == '\0') {
        if (!isfinite(v)) {
            cli_error("rls: %s %s: not a finite number", what, s);
            return CLI_USAGE;
        }
        *num = v;
        *is_num = 1;
        return CLI_OK;
    }
    *is_num = 0;
    int ec = cli_read_matrix(s, mat);
    if (ec)
        return ec;
    long cnt = mat->rows * mat->cols;
    if (cnt != n1 && cnt != n2) {
        if (n2)
            cli_error("%s: %s must hold %ld or %ld values, it holds %ld", s, what, n1, n2, cnt);
        else
            cli_error("%s: %s must hold %ld values, it holds %ld", s, what, n1, cnt);
        return CLI_DATAERR;
    }
    return CLI_OK;
}


/* The inputs: a streamed record (--data) or S and dw whole. */
typedef struct {
    cli_reader *rd;
    cli_matrix S, dw, sg, x0m, g0m;
    long m, n_epochs;
    double sig_num, g_num;
    int sig_is_num, sig_per_row, g_is_num;
} rls_in;

static void in_free(rls_in *in)
{
    cli_reader_close(in->rd);
    cli_matrix_free(&in->S);
    cli_matrix_free(&in->dw);
    cli_matrix_free(&in->sg);
    cli_matrix_free(&in->x0m);
    cli_matrix_free(&in->g0m);
}

/* The record's sizes: m coefficients, the epochs (-1: streamed, unknown). */
static int open_inputs(const rls_args *a, rls_in *in)
{
    const int k = a->k;
    int ec;
    in->n_epochs = -1;
    if (a->data) {
        if ((ec = cli_reader_open(a->data, &in->rd)))
            return ec;
        int cols = cli_reader_cols(in->rd);
        if (cols <= k || (cols - k) % k != 0) {
            cli_error("%s: %d columns; with --k %d an epoch row needs k + k m columns", a->data,
                      cols, k);
            return CLI_DATAERR;
        }
        in->m = (cols - k) / k;
        return CLI_OK;
    }
    if ((ec = cli_read_matrix(a->S, &in->S)) || (ec = cli_read_matrix(a->dw, &in->dw)))
        return ec;
    if (in->dw.rows * in->dw.cols != in->S.rows || in->S.rows % k != 0) {
        cli_error("%s, %s: S has %ld rows, dw %ld values; both must be the same multiple "
                  "of --k %d", a->S, a->dw, in->S.rows, in->dw.rows * in->dw.cols, k);
        return CLI_DATAERR;
    }
    in->m = in->S.cols;
    in->n_epochs = in->S.rows / k;
    if (in->n_epochs > 2147483647L) {
        cli_error("%s: too many epochs", a->S);
        return CLI_DATAERR;
    }
    return CLI_OK;
}

/* --sigma, --gamma0 and --x0. */
static int read_priors(const rls_args *a, rls_in *in)
{
    const int k = a->k;
    const long m = in->m;
    double dummy;
    int xnum = 0, ec;
    in->sig_num = 1.0;
    in->sig_is_num = 1;
    /* --sigma: k values (every epoch), or with --S/--dw one per row of S */
    if (a->sigma && (ec = read_num_or_file("--sigma", a->sigma, k, a->data ? 0 : in->n_epochs * k,
                                           &in->sig_num, &in->sg, &in->sig_is_num)))
        return ec;
    in->sig_per_row = !in->sig_is_num && in->sg.rows * in->sg.cols != k;
    if (in->sig_per_row)
        for (long t = 0; t < in->n_epochs * k; t++)
            if (!(in->sg.v[t] > 0)) {
                cli_error("%s: sigma of row %ld is %g; must be > 0", a->sigma, t + 1, in->sg.v[t]);
                return CLI_DATAERR;
            }
    if (a->sigma && in->sig_is_num && !(in->sig_num > 0)) {
        cli_error("rls: --sigma %s: must be > 0", a->sigma);
        return CLI_USAGE;
    }
    if ((ec = read_num_or_file("--gamma0", a->gamma0, m, m * m, &in->g_num, &in->g0m,
                               &in->g_is_num)))
        return ec;
    if (a->x0 && (ec = read_num_or_file("--x0", a->x0, m, 0, &dummy, &in->x0m, &xnum)))
        return ec;
    if (a->x0 && xnum) {
        cli_error("rls: --x0 needs a file of %ld values", m);
        return CLI_USAGE;
    }
    return CLI_OK;
}

/* The filter with its initial state and options; sig: the k row sigmas
 * when they are the same every epoch. */
static int make_filter(const rls_args *a, const rls_in *in, double *sig, igea_rls **h)
{
    const int k = a->k;
    const long m = in->m;
    double *g0 = calloc((size_t)(m * m), sizeof(double)), *jump = malloc((size_t)k * sizeof(double));
    int ec = !g0 || !jump ? cli_oom("the initial state") : CLI_OK;
    for (long i = 0; !ec && i < m; i++)
        for (long j = 0; j < m; j++)
            g0[i + j * m] = in->g_is_num ? (i == j ? in->g_num : 0.0)
                            : in->g0m.rows * in->g0m.cols == m ? (i == j ? in->g0m.v[i] : 0.0)
                            : in->g0m.v[i * m + j]; /* row-major; symmetric, lower read */
    for (int j = 0; !ec && j < k; j++) {
        sig[j] = in->sig_is_num ? in->sig_num : in->sg.v[j];
        if (!in->sig_per_row && !(sig[j] > 0)) {
            cli_error("%s: sigma %d is %g; must be > 0", a->sigma, j, sig[j]);
            ec = CLI_DATAERR;
        }
        jump[j] = a->jump;
    }
    int st = 0;
    if (!ec && (st = igea_rls_create((int)m, k, a->x0 ? in->x0m.v : NULL, g0, (int)m, h)))
        ec = cli_status(st, "rls: initial state (x0, gamma0)");
    if (!ec && ((st = igea_rls_set_variant(*h, a->variant, a->p)) ||
                (st = igea_rls_set_anomaly(*h, a->policy, a->kappa, isfinite(a->jump) ? jump : NULL)) ||
                (st = igea_rls_set_forget(*h, a->forget))))
        ec = cli_status(st, "rls: options");
    free(g0);
    free(jump);
    return ec;
}

typedef struct {
    FILE *f;
    cli_json j;
    int json, m, k, every;
    cli_svg_rows *plot; /* --plot: every epoch's estimate and sd, or NULL */
} printer;

static void print_header(printer *pr, const rls_args *a)
{
    FILE *f = pr->f;
    int p = a->variant ? a->p : 1;
    if (pr->json) {
        cli_json_begin(&pr->j, f);
        cli_jint(&pr->j, "m", pr->m);
        cli_jint(&pr->j, "k", pr->k);
        cli_jstr(&pr->j, "variant", igea_choice_name(IGEA_CHOICE_RLS_VARIANT, a->variant));
        cli_jint(&pr->j, "p", p);
        cli_jstr(&pr->j, "anomaly", igea_choice_name(IGEA_CHOICE_RLS_ANOMALY, a->policy));
        cli_jnum(&pr->j, "kappa", a->kappa);
        cli_jnum(&pr->j, "forget", a->forget);
        cli_json_open(&pr->j, "epochs", '[');
        return;
    }
    fprintf(f, "# igea rls: m = %d, k = %d, %s RLS, p = %d, anomaly %s, kappa %g, forget %g\n"
               "# epoch action", pr->m, pr->k, igea_choice_name(IGEA_CHOICE_RLS_VARIANT, a->variant), p, igea_choice_name(IGEA_CHOICE_RLS_ANOMALY, a->policy), a->kappa,
            a->forget);
    for (int j = 0; j < pr->k; j++)
        fprintf(f, " flag%d", j);
    for (int i = 0; i < pr->m; i++)
        fprintf(f, " x%d", i);
    for (int j = 0; j < pr->k; j++)
        fprintf(f, " comp%d", j);
    fputc('\n', f);
}

static void print_epoch(printer *pr, long e, int act, const int *fl, const double *x,
                        const double *comp)
{
    if (pr->every == 0 || (e + 1) % pr->every != 0)
        return;
    FILE *f = pr->f;
    if (pr->json) {
        cli_json_open(&pr->j, NULL, '{');
        cli_jint(&pr->j, "epoch", e);
        cli_jstr(&pr->j, "action", igea_choice_name(IGEA_CHOICE_RLS_ACTION, act));
        cli_jints(&pr->j, "flags", fl, pr->k);
        cli_jnums(&pr->j, "x", x, pr->m);
        cli_jnums(&pr->j, "compensated", comp, pr->k);
        cli_json_close(&pr->j);
        return;
    }
    fprintf(f, "%ld %d", e, act);
    for (int j = 0; j < pr->k; j++)
        fprintf(f, " %d", fl[j]);
    for (int i = 0; i < pr->m; i++)
        fprintf(f, " %.17g", x[i]);
    for (int j = 0; j < pr->k; j++)
        fprintf(f, " %.17g", comp[j]);
    fputc('\n', f);
}

/* The final estimate; x, sd: m values, cov: m x m scratch. */
static void print_summary(printer *pr, igea_rls *h, double *x, double *sd, double *cov)
{
    const int m = pr->m;
    double q;
    int cnt[IGEA_RLS_COUNT_LEN];
    igea_rls_get_q(h, &q);
    igea_rls_get_counts(h, cnt);
    igea_rls_get_x(h, x);
    igea_rls_get_covariance(h, cov, m);
    igea_rls_get_sd(h, sd);
    if (!pr->json) {
        fprintf(pr->f, "# epochs %d, updated %d, anomalous %d; Q_p = %.6g over %d rows "
                       "(whitened; not a measure of accuracy)\n",
                cnt[IGEA_RLS_COUNT_EPOCHS], cnt[IGEA_RLS_COUNT_UPDATES],
                cnt[IGEA_RLS_COUNT_ANOMALOUS], q, cnt[IGEA_RLS_COUNT_ROWS]);
        fprintf(pr->f, "# %5s %24s %14s\n", "coef", "estimate", "sd (honest)");
        for (int i = 0; i < m; i++)
            fprintf(pr->f, "# %5d %24.17g %14.6g\n", i, x[i], sd[i]);
        return;
    }
    cli_json *j = &pr->j;
    cli_json_close(j);
    cli_jnums(j, "x", x, m);
    cli_jnums(j, "sd", sd, m);
    cli_jrows(j, "covariance", cov, m, m);
    igea_rls_get_gamma(h, cov, m);
    cli_jrows(j, "gamma", cov, m, m);
    cli_jnum(j, "q", q);
    cli_jint(j, "n_epochs", cnt[IGEA_RLS_COUNT_EPOCHS]);
    cli_jint(j, "updates", cnt[IGEA_RLS_COUNT_UPDATES]);
    cli_jint(j, "anomalous", cnt[IGEA_RLS_COUNT_ANOMALOUS]);
    cli_jint(j, "rows", cnt[IGEA_RLS_COUNT_ROWS]);
    cli_json_end(j);
}

/* Epoch e's y[k] and c (k x m, column-major) from a record row or S, dw. */
static void epoch_data(const rls_args *a, const rls_in *in, const double *row, long e, double *y,
                       double *c)
{
    const int k = a->k;
    const long m = in->m;
    for (int j = 0; j < k; j++) {
        long srow = e * k + j;
        y[j] = row ? row[j] : in->dw.v[srow];
        for (long i = 0; i < m; i++)
            c[j + i * k] = row ? row[k + j * m + i] : in->S.v[srow * m + i];
    }
}

/* Every epoch through the filter, printed as it goes; *ne epochs. */
static int run_stream(const rls_args *a, rls_in *in, igea_rls *h, printer *pr, double *sig,
                      double *work, long *ne)
{
    const int k = a->k;
    const long m = in->m, block = 256, cols = k + (long)k * m;
    double *y = work, *comp = y + k, *x = comp + k, *c = x + m;
    int *fl = malloc((size_t)k * sizeof(int)), ec = CLI_OK;
    double *buf = a->data ? malloc((size_t)(block * cols) * sizeof(double)) : NULL;
    if (!fl || (a->data && !buf))
        ec = cli_oom("the epochs");
    long e = 0, nread = 0;
    while (!ec) {
        if (a->data)
            ec = cli_reader_next(in->rd, block, buf, &nread);
        else
            nread = in->n_epochs - e < block ? in->n_epochs - e : block;
        if (ec || nread == 0)
            break;
        for (long r = 0; r < nread && !ec; r++, e++) {
            epoch_data(a, in, a->data ? buf + r * cols : NULL, e, y, c);
            if (in->sig_per_row)
                memcpy(sig, in->sg.v + e * k, (size_t)k * sizeof(double));
            int act = igea_rls_update(h, c, k, y, sig, fl);
            if (act < 0) {
                char ctx[64];
                snprintf(ctx, sizeof ctx, "rls: epoch %ld", e);
                ec = cli_status(act, ctx);
                break;
            }
            igea_rls_get_x(h, x);
            igea_rls_compensate(h, c, k, y, comp);
            print_epoch(pr, e, act, fl, x, comp);
            if (pr->plot && (ec = cli_svg_rls_add(pr->plot, h, pr->m)))
                break;
        }
    }
    free(fl);
    free(buf);
    *ne = e;
    return ec;
}

int cmd_rls(int argc, char **argv)
{
    rls_args a;
    int ec = parse(argc, argv, &a);
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    const int k = a.k;
    rls_in in;
    memset(&in, 0, sizeof in);
    double *work = NULL;
    igea_rls *h = NULL;
    cli_out out = CLI_OUT_INIT;
    cli_svg_rows rows = {NULL, 0, 0}; /* --plot */
    int out_open = 0;
    long m, ne = 0;
    if ((ec = open_inputs(&a, &in)) || (ec = read_priors(&a, &in)))
        goto done;
    m = in.m;
    /* sig (k), y (k), comp (k), x (m), c (k m), then m x m for the summary */
    if (!(work = malloc((size_t)(3 * k + m + k * m + m * m) * sizeof(double)))) {
        ec = cli_oom("the filter");
        goto done;
    }
    if ((ec = make_filter(&a, &in, work, &h)) || (ec = cli_out_open(&out, a.out)))
        goto done;
    out_open = 1;
    printer pr;
    pr.f = out.f, pr.json = a.json, pr.m = (int)m, pr.k = k, pr.every = a.every;
    pr.plot = a.plot ? &rows : NULL;
    print_header(&pr, &a);
    if ((ec = run_stream(&a, &in, h, &pr, work, work + k, &ne)))
        goto done;
    if (ne == 0) {
        cli_error("rls: no epochs in the input");
        ec = CLI_DATAERR;
        goto done;
    }
    /* sd in the first m of the k m values of c, free after the last epoch */
    print_summary(&pr, h, work + 3 * k, work + 3 * k + m, work + 3 * k + m + k * m);
    if (a.plot && (ec = cli_svg_rls(a.plot, &rows, (int)m)))
        goto done;
    ec = cli_out_commit(&out);
    out_open = 0;
done:
    free(rows.v);
    if (out_open)
        cli_out_abort(&out);
    igea_rls_free(h);
    in_free(&in);
    free(work);
    return ec;
}
