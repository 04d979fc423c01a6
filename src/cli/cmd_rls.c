/* igea rls - recursive estimation of tool-error coefficients over a stream
 * of epochs (seed 001, METHODS 2): per-epoch estimates, anomaly flags and
 * compensated telemetry. */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static void rls_help(void)
{
    printf(
"usage: igea rls (--data FILE | --S FILE --dw FILE) [--k K] [options]\n"
"\n"
"Estimates the constant tool-error coefficients X of y_n = c_n X + v_n epoch by\n"
"epoch (recursive least squares, METHODS 2), as a real-time loop would: each\n"
"epoch's k observations (telemetry minus tracking) update the estimate once.\n"
"\n"
"input (text or .npy; streamed, so records longer than memory are fine):\n"
"  --data FILE    one row per epoch: y_1..y_k, then the k x m block c row by\n"
"                 row (c_11..c_1m, c_21..c_2m, ...): k + k m columns\n"
"  --S FILE --dw FILE   the 'igea eqerr' layout: S with k rows per epoch\n"
"                 (epoch-major, m columns), dw one value per row\n"
"  --k K          observation rows per epoch (default 3: x, y, z)\n"
"  --sigma S      tracking 1-sigma per row: a number, a file of k values (the\n"
"                 same every epoch) or, with --S/--dw, one value per row of S\n"
"                 (the eqerr sigma file); default 1: y and c already whitened\n"
"  --x0 FILE      initial estimate, m values (default 0)\n"
"  --gamma0 G     initial Gamma (whitened units): a number g for g I, a file\n"
"                 of m values (diagonal) or of m x m values (default 1e6:\n"
"                 diffuse, then standard RLS is batch least squares)\n"
"\n"
"estimator:\n"
"  --variant V    standard | iterated | polynomial (default standard)\n"
"  -p P           order of the polynomial / number of iterations (default 1)\n"
"  --forget L     forgetting factor 0 < L <= 1 (default 1: none)\n"
"  --anomaly A    none | replace | skip | isolate (default none: flag only)\n"
"                 replace: the patent's variant A (previous epoch's y);\n"
"                 skip: no update at an anomalous epoch; isolate: variant B,\n"
"                 the flagged rows are dropped from that epoch's update\n"
"  --kappa K      innovation test |e_j| > K sd (default 4)\n"
"  --jump J       jump test |y_j - y_prev,j| > J (physical units; default off;\n"
"                 catches telemetry dropouts to zero)\n"
"\n"
"output:\n"
"  default        one line per epoch: epoch, action (0 updated, 1 flagged,\n"
"                 2 replaced, 3 skipped, 4 isolated), k flags (bits: 1\n"
"                 innovation, 2 jump, 4 missing, 8 row unused), m estimates,\n"
"                 k compensated values y - c x; then '#' lines with the final\n"
"                 estimate, its honest standard deviations and Q_p\n"
"  --every N      print every N-th epoch only (0: the final summary only)\n"
"  --json         machine-readable output (same content)\n"
"  --out FILE     write there (atomically) instead of standard output\n"
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
"           --anomaly isolate --sigma 0.01\n");
}

typedef struct {
    const char *data, *S, *dw, *sigma, *x0, *gamma0, *out;
    int k, p, variant, policy, every, json;
    double kappa, jump, forget;
} rls_args;

static int pick(const char *opt, const char *v, const char *const *names, int n, int *out)
{
    for (int i = 0; i < n; i++)
        if (!strcmp(v, names[i])) {
            *out = i;
            return CLI_OK;
        }
    cli_error("rls: option %s: unknown value '%s' (see igea rls --help)", opt, v);
    return CLI_USAGE;
}

static int parse(int argc, char **argv, rls_args *a)
{
    static const char *const variants[] = {"standard", "iterated", "polynomial"};
    static const char *const policies[] = {"none", "replace", "skip", "isolate"};
    memset(a, 0, sizeof *a);
    a->k = 3;
    a->p = 1;
    a->kappa = 4.0;
    a->jump = INFINITY;
    a->forget = 1.0;
    a->every = 1;
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i], *v;
        int ec = CLI_OK;
#define NEED() do { if (!(v = cli_optarg(argc, argv, &i))) return CLI_USAGE; } while (0)
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) {
            rls_help();
            return -1;
        } else if (!strcmp(o, "--data")) { NEED(); a->data = v; }
        else if (!strcmp(o, "--S")) { NEED(); a->S = v; }
        else if (!strcmp(o, "--dw")) { NEED(); a->dw = v; }
        else if (!strcmp(o, "--sigma")) { NEED(); a->sigma = v; }
        else if (!strcmp(o, "--x0")) { NEED(); a->x0 = v; }
        else if (!strcmp(o, "--gamma0")) { NEED(); a->gamma0 = v; }
        else if (!strcmp(o, "--out")) { NEED(); a->out = v; }
        else if (!strcmp(o, "--json")) a->json = 1;
        else if (!strcmp(o, "--k")) { NEED(); ec = cli_parse_int(o, v, &a->k); }
        else if (!strcmp(o, "-p") || !strcmp(o, "--p")) { NEED(); ec = cli_parse_int(o, v, &a->p); }
        else if (!strcmp(o, "--every")) { NEED(); ec = cli_parse_int(o, v, &a->every); }
        else if (!strcmp(o, "--kappa")) { NEED(); ec = cli_parse_double(o, v, &a->kappa); }
        else if (!strcmp(o, "--jump")) { NEED(); ec = cli_parse_double(o, v, &a->jump); }
        else if (!strcmp(o, "--forget")) { NEED(); ec = cli_parse_double(o, v, &a->forget); }
        else if (!strcmp(o, "--variant")) { NEED(); ec = pick(o, v, variants, 3, &a->variant); }
        else if (!strcmp(o, "--anomaly")) { NEED(); ec = pick(o, v, policies, 4, &a->policy); }
        else {
            cli_error("rls: unknown option '%s' (see igea rls --help)", o);
            return CLI_USAGE;
        }
        if (ec)
            return ec;
#undef NEED
    }
    if (!a->data == !(a->S || a->dw) || (!a->data && !(a->S && a->dw))) {
        cli_error("rls: give either --data FILE or both --S FILE and --dw FILE");
        return CLI_USAGE;
    }
    if (a->k < 1) {
        cli_error("rls: --k %d: need at least one row per epoch", a->k);
        return CLI_USAGE;
    }
    if (a->p < 1 || a->p > 1000000) {
        cli_error("rls: -p %d: need 1 <= p <= 1000000", a->p);
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

static const char *const action_name[] = {"updated", "flagged", "replaced", "skipped", "isolated"};

typedef struct {
    FILE *f;
    int json, m, k, every, first;
} printer;

static void print_epoch(printer *pr, long e, int act, const int *fl, const double *x,
                        const double *comp)
{
    if (pr->every == 0 || (e + 1) % pr->every != 0)
        return;
    FILE *f = pr->f;
    if (pr->json) {
        fprintf(f, "%s\n    {\"epoch\": %ld, \"action\": \"%s\", \"flags\": ",
                pr->first ? "" : ",", e + 1, action_name[act]);
        cli_json_iarray(f, fl, pr->k);
        fputs(", \"x\": ", f);
        cli_json_array(f, x, pr->m);
        fputs(", \"compensated\": ", f);
        cli_json_array(f, comp, pr->k);
        fputc('}', f);
    } else {
        fprintf(f, "%ld %d", e + 1, act);
        for (int j = 0; j < pr->k; j++)
            fprintf(f, " %d", fl[j]);
        for (int i = 0; i < pr->m; i++)
            fprintf(f, " %.17g", x[i]);
        for (int j = 0; j < pr->k; j++)
            fprintf(f, " %.17g", comp[j]);
        fputc('\n', f);
    }
    pr->first = 0;
}

int cmd_rls(int argc, char **argv)
{
    if (cli_one_stdin(argc, argv))
        return CLI_USAGE;
    rls_args a;
    int ec = parse(argc, argv, &a);
    if (ec < 0)
        return CLI_OK;
    if (ec)
        return ec;
    static const char *const vname[] = {"standard", "iterated", "polynomial"};
    static const char *const pname[] = {"none", "replace", "skip", "isolate"};
    const int k = a.k;
    cli_reader *rd = NULL;
    cli_matrix S = {0, 0, 0}, dw = {0, 0, 0}, sg = {0, 0, 0}, x0m = {0, 0, 0}, g0m = {0, 0, 0};
    double *buf = NULL, *g0 = NULL, *work = NULL, *jump = NULL;
    int *fl = NULL;
    igea_rls *h = NULL;
    cli_out out = CLI_OUT_INIT;
    int out_open = 0;
    long m = 0, n_epochs = -1;

    /* sizes */
    if (a.data) {
        if ((ec = cli_reader_open(a.data, &rd)))
            goto done;
        int cols = cli_reader_cols(rd);
        if (cols <= k || (cols - k) % k != 0) {
            cli_error("%s: %d columns; with --k %d an epoch row needs k + k m columns", a.data,
                      cols, k);
            ec = CLI_DATAERR;
            goto done;
        }
        m = (cols - k) / k;
    } else {
        if ((ec = cli_read_matrix(a.S, &S)) || (ec = cli_read_matrix(a.dw, &dw)))
            goto done;
        if (dw.rows * dw.cols != S.rows || S.rows % k != 0) {
            cli_error("%s, %s: S has %ld rows, dw %ld values; both must be the same multiple "
                      "of --k %d", a.S, a.dw, S.rows, dw.rows * dw.cols, k);
            ec = CLI_DATAERR;
            goto done;
        }
        m = S.cols;
        n_epochs = S.rows / k;
        if (n_epochs > 2147483647L) {
            cli_error("%s: too many epochs", a.S);
            ec = CLI_DATAERR;
            goto done;
        }
    }
    /* prior and sigma */
    double sig_num = 1.0, g_num = 1e6, dummy;
    int sig_is_num = 1, g_is_num = 1, xnum = 0;
    /* --sigma: k values (every epoch), or with --S/--dw one per row of S */
    if (a.sigma && (ec = read_num_or_file("--sigma", a.sigma, k, a.data ? 0 : n_epochs * k,
                                          &sig_num, &sg, &sig_is_num)))
        goto done;
    const int sig_per_row = !sig_is_num && sg.rows * sg.cols != k;
    if (sig_per_row)
        for (long t = 0; t < n_epochs * k; t++)
            if (!(sg.v[t] > 0)) {
                cli_error("%s: sigma of row %ld is %g; must be > 0", a.sigma, t + 1, sg.v[t]);
                ec = CLI_DATAERR;
                goto done;
            }
    if (a.sigma && sig_is_num && !(sig_num > 0)) {
        cli_error("rls: --sigma %s: must be > 0", a.sigma);
        ec = CLI_USAGE;
        goto done;
    }
    if (a.gamma0 && (ec = read_num_or_file("--gamma0", a.gamma0, m, m * m, &g_num, &g0m, &g_is_num)))
        goto done;
    if (a.x0 && (ec = read_num_or_file("--x0", a.x0, m, 0, &dummy, &x0m, &xnum)))
        goto done;
    if (a.x0 && xnum) {
        cli_error("rls: --x0 needs a file of %ld values", m);
        ec = CLI_USAGE;
        goto done;
    }
    g0 = calloc((size_t)(m * m), sizeof(double));
    work = malloc((size_t)(3 * k + 2 * m + k * m + (long)k * (m + 1)) * sizeof(double));
    fl = malloc((size_t)k * sizeof(int));
    jump = malloc((size_t)k * sizeof(double));
    if (!g0 || !work || !fl || !jump) {
        cli_error("out of memory");
        ec = CLI_SOFTWARE;
        goto done;
    }
    for (long i = 0; i < m; i++)
        for (long j = 0; j < m; j++) {
            double v;
            if (g_is_num)
                v = i == j ? g_num : 0.0;
            else if (g0m.rows * g0m.cols == m)
                v = i == j ? g0m.v[i] : 0.0;
            else
                v = g0m.v[i * m + j]; /* row-major; symmetric, lower read */
            g0[i + j * m] = v;
        }
    double *sig = work, *y = sig + k, *comp = y + k, *x = comp + k, *c = x + m, *row = c + k * m;
    (void)row;
    for (int j = 0; j < k; j++) {
        sig[j] = sig_is_num ? sig_num : sg.v[j];
        if (!sig_per_row && !(sig[j] > 0)) {
            cli_error("%s: sigma %d is %g; must be > 0", a.sigma, j + 1, sig[j]);
            ec = CLI_DATAERR;
            goto done;
        }
        jump[j] = a.jump;
    }
    int st = igea_rls_create((int)m, k, a.x0 ? x0m.v : NULL, g0, (int)m, &h);
    if (st) {
        ec = cli_status(st, "rls: initial state (x0, gamma0)");
        goto done;
    }
    if ((st = igea_rls_set_variant(h, a.variant, a.p)) ||
        (st = igea_rls_set_anomaly(h, a.policy, a.kappa, isfinite(a.jump) ? jump : NULL)) ||
        (st = igea_rls_set_forget(h, a.forget))) {
        ec = cli_status(st, "rls: options");
        goto done;
    }
    if ((ec = cli_out_open(&out, a.out)))
        goto done;
    out_open = 1;
    printer pr = {out.f, a.json, (int)m, k, a.every, 1};
    if (a.json)
        fprintf(out.f, "{\"m\": %ld, \"k\": %d, \"variant\": \"%s\", \"p\": %d, "
                       "\"anomaly\": \"%s\", \"kappa\": %.17g, \"forget\": %.17g,\n  \"epochs\": [",
                m, k, vname[a.variant], a.variant ? a.p : 1, pname[a.policy], a.kappa, a.forget);
    else {
        fprintf(out.f, "# igea rls: m = %ld, k = %d, %s RLS, p = %d, anomaly %s, kappa %g, "
                       "forget %g\n# epoch action", m, k, vname[a.variant],
                a.variant ? a.p : 1, pname[a.policy], a.kappa, a.forget);
        for (int j = 0; j < k; j++)
            fprintf(out.f, " flag%d", j + 1);
        for (long i = 0; i < m; i++)
            fprintf(out.f, " x%ld", i + 1);
        for (int j = 0; j < k; j++)
            fprintf(out.f, " comp%d", j + 1);
        fputc('\n', out.f);
    }

    /* the stream */
    const long block = 256;
    long cols = a.data ? k + (long)k * m : 0;
    if (a.data) {
        buf = malloc((size_t)(block * cols) * sizeof(double));
        if (!buf) {
            cli_error("out of memory");
            ec = CLI_SOFTWARE;
            goto done;
        }
    }
    long e = 0;
    for (;;) {
        long nread = 0;
        if (a.data) {
            if ((ec = cli_reader_next(rd, block, buf, &nread)))
                goto done;
        } else {
            nread = n_epochs - e < block ? n_epochs - e : block;
        }
        if (nread == 0)
            break;
        for (long r = 0; r < nread; r++, e++) {
            if (a.data) {
                const double *v = buf + r * cols;
                for (int j = 0; j < k; j++) {
                    y[j] = v[j];
                    for (long i = 0; i < m; i++)
                        c[j + i * k] = v[k + j * m + i];
                }
            } else {
                for (int j = 0; j < k; j++) {
                    long srow = e * k + j;
                    y[j] = dw.v[srow];
                    for (long i = 0; i < m; i++)
                        c[j + i * k] = S.v[srow * m + i];
                }
            }
            if (sig_per_row)
                memcpy(sig, sg.v + e * k, (size_t)k * sizeof(double));
            int act = igea_rls_update(h, c, k, y, sig, fl);
            if (act < 0) {
                char ctx[64];
                snprintf(ctx, sizeof ctx, "rls: epoch %ld", e + 1);
                ec = cli_status(act, ctx);
                goto done;
            }
            igea_rls_get_x(h, x);
            igea_rls_compensate(h, c, k, y, comp);
            print_epoch(&pr, e, act, fl, x, comp);
        }
    }
    if (e == 0) {
        cli_error("rls: no epochs in the input");
        ec = CLI_DATAERR;
        goto done;
    }

    /* final summary */
    {
        double q, *cov = g0; /* reuse */
        int cnt[IGEA_RLS_COUNT_LEN];
        igea_rls_get_q(h, &q);
        igea_rls_get_counts(h, cnt);
        igea_rls_get_x(h, x);
        igea_rls_get_covariance(h, cov, (int)m);
        FILE *f = out.f;
        if (a.json) {
            fputs("\n  ],\n  \"x\": ", f);
            cli_json_array(f, x, m);
            fputs(",\n  \"sd\": [", f);
            for (long i = 0; i < m; i++) {
                fputs(i ? ", " : "", f);
                cli_json_num(f, sqrt(cov[i + i * m]));
            }
            fputs("],\n  \"covariance\": [", f);
            for (long i = 0; i < m; i++) {
                fputs(i ? ",\n    " : "\n    ", f);
                cli_json_array(f, cov + i * m, m);
            }
            igea_rls_get_gamma(h, cov, (int)m);
            fputs("],\n  \"gamma\": [", f);
            for (long i = 0; i < m; i++) {
                fputs(i ? ",\n    " : "\n    ", f);
                cli_json_array(f, cov + i * m, m);
            }
            fprintf(f, "],\n  \"q\": %.17g, \"n_epochs\": %d, \"updates\": %d, \"anomalous\": %d, "
                       "\"rows\": %d}\n", q, cnt[0], cnt[1], cnt[2], cnt[3]);
        } else {
            fprintf(f, "# epochs %d, updated %d, anomalous %d; Q_p = %.6g over %d rows "
                       "(whitened; not a measure of accuracy)\n",
                    cnt[0], cnt[1], cnt[2], q, cnt[3]);
            fprintf(f, "# %5s %24s %14s\n", "coef", "estimate", "sd (honest)");
            for (long i = 0; i < m; i++)
                fprintf(f, "# %5ld %24.17g %14.6g\n", i + 1, x[i], sqrt(cov[i + i * m]));
        }
    }
    ec = cli_out_commit(&out);
    out_open = 0;
done:
    if (out_open)
        cli_out_abort(&out);
    igea_rls_free(h);
    cli_reader_close(rd);
    cli_matrix_free(&S);
    cli_matrix_free(&dw);
    cli_matrix_free(&sg);
    cli_matrix_free(&x0m);
    cli_matrix_free(&g0m);
    free(buf);
    free(g0);
    free(work);
    free(fl);
    free(jump);
    return ec;
}
