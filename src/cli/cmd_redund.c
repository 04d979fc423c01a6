/* igea redund - redundant sensor sets (seed 002, METHODS 3.1-3.3):
 * reliability, one-epoch consistency check and fusion, the windowed check
 * of a record, parity-space fault detection and isolation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static void redund_help(void)
{
    printf(
"usage: igea redund reliability [--re1 R] [--re2 R] [--axes FILE --R FILE|NUMBER]\n"
"       igea redund consistency --x FILE --sigma FILE|NUMBER [--alpha A] [--one-shot]\n"
"       igea redund fuse --record FILE --fs HZ --sigma FILE|NUMBER [--window S]\n"
"                        [--alpha A] [--one-shot] [--average]\n"
"       igea redund fdi --H FILE --y FILE --sigma FILE|NUMBER [--pfa P]\n"
"       (every form takes --json and --out FILE)\n"
"\n"
"Redundant inertial sensors (METHODS 3).\n"
"\n"
"reliability  Without --axes: the figures of seed 002 for gyro reliability\n"
"             --re1 (default 0.992) and accelerometer reliability --re2 (0.995):\n"
"             eq. (6), (7), (8), the quoted (10) (= without the skew sensor), the\n"
"             non-redundant (9) and the exact geometric value. With --axes (n\n"
"             rows of 3: each sensor's input axis) and --R (n values or one):\n"
"             P(the surviving axes span 3-D), and P(they can still detect /\n"
"             isolate a further single fault) from the parity matrix.\n"
"consistency  One epoch of n redundant measurements --x of one quantity with\n"
"             tolerances --sigma: the confidence-distance matrix D, the relation\n"
"             matrix (d_ij <= alpha, default 0.7), support counts, the fusion set\n"
"             (iterative majority; --one-shot) and the fused value and sigma.\n"
"             Choose sigma as a tolerance (about 3-5x the noise of x): with sigma\n"
"             equal to the noise, healthy pairs disagree 46 %% of the time.\n"
"fuse         A record (rows = samples at --fs Hz, columns = sensors): the\n"
"             check of every window of --window seconds (default 1) on the\n"
"             window means: which sensors were excluded when, and the fused\n"
"             output (weighted; --average for the plain mean).\n"
"fdi          Parity-space test of one epoch y = H x + e (H: m rows of q,\n"
"             m > q): chi-square detection at false-alarm probability --pfa\n"
"             (default 0.01) and the isolated sensor (numbered from 1).\n"
"\n"
"exit status: 0 ok (a detected fault is reported, not an error), 64 usage,\n"
"65 bad input, 66 missing input, 70 numerical failure, 74 I/O error.\n"
"\n"
"examples:\n"
"  igea redund reliability\n"
"  printf '1.000010\\n1.000018\\n0.999995\\n1.010004\\n' > x.txt\n"
"  igea redund consistency --x x.txt --sigma 20e-6 --alpha 0.7\n"
"  igea redund fuse --record ax.npy --fs 100 --window 1 --sigma 20e-6 --json\n");
}

typedef struct {
    const char *sub, *axes, *R, *x, *sigma, *record, *H, *y, *out;
    double re1, re2, alpha, fs, window, pfa;
    int json, one_shot, average;
} rd_args;

/* A file or a number: n values into *v (malloc). n < 0: take the file's. */
static int read_values(const char *what, const char *s, int *n, double **v)
{
    char *end;
    double d = strtod(s, &end);
    if (end != s && *end == '\0') {
        if (*n < 1) {
            cli_error("redund: %s must be a file here", what);
            return CLI_USAGE;
        }
        *v = malloc(sizeof(double) * (size_t)*n);
        if (!*v)
            return cli_oom(what);
        for (int i = 0; i < *n; i++)
            (*v)[i] = d;
        return CLI_OK;
    }
    cli_matrix m = {0};
    int ec = cli_read_matrix(s, &m);
    if (ec)
        return ec;
    long cnt = m.rows * m.cols;
    if (*n >= 1 && cnt != *n) {
        cli_error("%s: %s holds %ld values, expected %d", what, s, cnt, *n);
        cli_matrix_free(&m);
        return CLI_DATAERR;
    }
    *n = (int)cnt;
    *v = m.v;
    return CLI_OK;
}

static int parse(int argc, char **argv, rd_args *a)
{
    memset(a, 0, sizeof *a);
    a->re1 = 0.992;
    a->re2 = 0.995;
    a->alpha = 0.7;
    a->window = 1.0;
    a->pfa = 0.01;
    a->fs = -1.0;
    int i = 1;
    if (argc > 1 && argv[1][0] != '-') {
        a->sub = argv[1];
        i = 2;
    }
    for (; i < argc; i++) {
        const char *o = argv[i], *v;
        int ec;
#define NEED() do { if (!(v = cli_optarg(argc, argv, &i))) return CLI_USAGE; } while (0)
#define DBL(field) do { NEED(); if ((ec = cli_parse_double(o, v, &a->field))) return ec; } while (0)
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) {
            redund_help();
            return -1;
        } else if (!strcmp(o, "--axes")) { NEED(); a->axes = v; }
        else if (!strcmp(o, "--R")) { NEED(); a->R = v; }
        else if (!strcmp(o, "--x")) { NEED(); a->x = v; }
        else if (!strcmp(o, "--sigma")) { NEED(); a->sigma = v; }
        else if (!strcmp(o, "--record")) { NEED(); a->record = v; }
        else if (!strcmp(o, "--H")) { NEED(); a->H = v; }
        else if (!strcmp(o, "--y")) { NEED(); a->y = v; }
        else if (!strcmp(o, "--out")) { NEED(); a->out = v; }
        else if (!strcmp(o, "--re1")) DBL(re1);
        else if (!strcmp(o, "--re2")) DBL(re2);
        else if (!strcmp(o, "--alpha")) DBL(alpha);
        else if (!strcmp(o, "--fs")) DBL(fs);
        else if (!strcmp(o, "--window")) DBL(window);
        else if (!strcmp(o, "--pfa")) DBL(pfa);
        else if (!strcmp(o, "--json")) a->json = 1;
        else if (!strcmp(o, "--one-shot")) a->one_shot = 1;
        else if (!strcmp(o, "--average")) a->average = 1;
        else {
            cli_error("redund: unknown option '%s' (see igea redund --help)", o);
            return CLI_USAGE;
        }
#undef DBL
#undef NEED
    }
    if (!(a->alpha > 0 && a->alpha < 1) || !(a->pfa > 0 && a->pfa < 1)) {
        cli_error("redund: --alpha and --pfa must lie in (0, 1)");
        return CLI_USAGE;
    }
    if (!(a->re1 >= 0 && a->re1 <= 1) || !(a->re2 >= 0 && a->re2 <= 1)) {
        cli_error("redund: --re1 and --re2 must lie in [0, 1]");
        return CLI_USAGE;
    }
    if (!(a->window > 0)) {
        cli_error("redund: --window must be > 0");
        return CLI_USAGE;
    }
    if (!a->sub) {
        cli_error("redund: a subcommand is required: reliability, consistency, fuse or fdi");
        return CLI_USAGE;
    }
    if (strcmp(a->sub, "reliability") && strcmp(a->sub, "consistency") &&
        strcmp(a->sub, "fuse") && strcmp(a->sub, "fdi")) {
        cli_error("redund: unknown subcommand '%s' (reliability, consistency, fuse, fdi)", a->sub);
        return CLI_USAGE;
    }
    if (!strcmp(a->sub, "reliability") && a->axes && !a->R) {
        cli_error("redund reliability: --axes needs --R");
        return CLI_USAGE;
    }
    if (!strcmp(a->sub, "consistency") && (!a->x || !a->sigma)) {
        cli_error("redund consistency: --x and --sigma are required");
        return CLI_USAGE;
    }
    if (!strcmp(a->sub, "fuse") && (!a->record || !a->sigma || !(a->fs > 0))) {
        cli_error("redund fuse: --record, --fs (> 0) and --sigma are required");
        return CLI_USAGE;
    }
    if (!strcmp(a->sub, "fdi") && (!a->H || !a->y || !a->sigma)) {
        cli_error("redund fdi: --H, --y and --sigma are required");
        return CLI_USAGE;
    }
    return CLI_OK;
}

static int open_out(const rd_args *a, cli_out *o) { return cli_out_open(o, a->out); }

static int do_reliability(const rd_args *a)
{
    cli_out o;
    int ec, st;
    if (!a->axes) {
        double r[IGEA_REDUND_SEED002_LEN];
        if ((st = igea_redund_seed002(a->re1, a->re2, r)))
            return cli_status(st, "redund reliability: --re1/--re2 in [0, 1]");
        if ((ec = open_out(a, &o)))
            return ec;
        static const char *names[IGEA_REDUND_SEED002_LEN] = {
            "gyro_eq6", "acc_eq7", "system_eq8_with_eq7", "system_without_skew_eq10",
            "non_redundant_eq9", "system_exact", "acc_exact"};
        if (a->json) {
            fprintf(o.f, "{\n  \"re1\": %.17g,\n  \"re2\": %.17g", a->re1, a->re2);
            for (int k = 0; k < IGEA_REDUND_SEED002_LEN; k++) {
                fprintf(o.f, ",\n  \"%s\": ", names[k]);
                cli_json_num(o.f, r[k]);
            }
            fprintf(o.f, "\n}\n");
        } else {
            fprintf(o.f, "seed 002 reliability, Re1 = %g (gyros), Re2 = %g (accelerometers)\n",
                    a->re1, a->re2);
            fprintf(o.f, "  gyros, 2 per axis (6)                  %.10f\n", r[0]);
            fprintf(o.f, "  accelerometers as printed (7)          %.12f\n", r[1]);
            fprintf(o.f, "  system (8) with (7)                    %.10f\n", r[2]);
            fprintf(o.f, "  system without the skew sensor (10)    %.10f   <- the quoted value\n", r[3]);
            fprintf(o.f, "  non-redundant (9)                      %.10f\n", r[4]);
            fprintf(o.f, "  system, exact geometric                %.10f\n", r[5]);
            fprintf(o.f, "(7) counts 'only the skew sensor D survives' as working; the exact\n"
                         "value does not: one skewed axis cannot measure two components.)\n");
        }
        return cli_out_commit(&o);
    }
    cli_matrix ax = {0};
    double *R = NULL, *axc = NULL;
    if ((ec = cli_read_matrix(a->axes, &ax)))
        return ec;
    if (ax.cols != 3 || ax.rows < 1 || ax.rows > IGEA_REDUND_GEOM_FDI_MAX) {
        cli_error("%s: expected 1 to %d rows of 3 (one input axis per sensor)", a->axes,
                  IGEA_REDUND_GEOM_FDI_MAX);
        cli_matrix_free(&ax);
        return CLI_DATAERR;
    }
    int n = (int)ax.rows;
    axc = malloc(sizeof(double) * 3 * (size_t)n);
    if (!axc) {
        cli_matrix_free(&ax);
        return cli_oom("the sensor axes");
    }
    for (int k = 0; k < n; k++)
        for (int c = 0; c < 3; c++)
            axc[k + (size_t)c * n] = ax.v[(size_t)k * 3 + c];
    cli_matrix_free(&ax);
    if ((ec = read_values("--R", a->R, &n, &R))) {
        free(axc);
        return ec;
    }
    double g[IGEA_REDUND_GEOM_LEN];
    st = igea_redund_geometry(n, axc, n, R, 1, g);
    free(axc);
    free(R);
    if (st)
        return cli_status(st, "redund reliability");
    if ((ec = open_out(a, &o)))
        return ec;
    if (a->json) {
        fprintf(o.f, "{\n  \"sensors\": %d,\n  \"classes\": %d,\n  \"span\": ", n, (int)g[3]);
        cli_json_num(o.f, g[0]);
        fprintf(o.f, ",\n  \"detect\": ");
        cli_json_num(o.f, g[1]);
        fprintf(o.f, ",\n  \"isolate\": ");
        cli_json_num(o.f, g[2]);
        fprintf(o.f, "\n}\n");
    } else {
        fprintf(o.f, "%d sensors in %d direction classes\n", n, (int)g[3]);
        fprintf(o.f, "  P(surviving axes span 3-D)                  %.12f\n", g[0]);
        fprintf(o.f, "  P(... and a further fault is detectable)    %.12f\n", g[1]);
        fprintf(o.f, "  P(... and a further fault is isolable)      %.12f\n", g[2]);
    }
    return cli_out_commit(&o);
}

static void json_imatrix(FILE *f, const int *r, int n)
{
    fprintf(f, "[");
    for (int i = 0; i < n; i++) {
        int row[64];
        for (int j = 0; j < n && j < 64; j++)
            row[j] = r[i + (size_t)j * n];
        fprintf(f, "%s", i ? ", " : "");
        cli_json_iarray(f, row, n);
    }
    fprintf(f, "]");
}

static int do_consistency(const rd_args *a)
{
    int n = -1, ec, st;
    double *x = NULL, *s = NULL;
    if ((ec = read_values("--x", a->x, &n, &x)))
        return ec;
    if (n > 64) {
        cli_error("%s: at most 64 measurements", a->x);
        free(x);
        return CLI_DATAERR;
    }
    if ((ec = read_values("--sigma", a->sigma, &n, &s))) {
        free(x);
        return ec;
    }
    size_t nn = (size_t)n * n;
    double *D = malloc(sizeof(double) * nn);
    int *r = malloc(sizeof(int) * (nn + 3 * (size_t)n));
    double fused = 0, fsig = 0;
    if (!D || !r) {
        ec = cli_oom("the reliability tables");
        goto done;
    }
    int *sup = r + nn, *keep = sup + n, *keep1 = keep + n;
    if ((st = igea_redund_confidence_distance(n, x, s, D, n)) ||
        (st = igea_redund_relation(n, D, n, &a->alpha, 0, r, n)) ||
        (st = igea_redund_fusion_set(n, D, n, &a->alpha, 0, 1, keep, sup)) ||
        (st = igea_redund_fusion_set(n, D, n, &a->alpha, 0, 0, keep1, NULL)) ||
        (st = igea_redund_fuse(n, x, s, a->one_shot ? keep1 : keep, !a->average, &fused, &fsig))) {
        ec = cli_status(st, "redund consistency (sigma > 0, 0 < alpha < 1)");
        goto done;
    }
    cli_out o;
    if ((ec = open_out(a, &o)))
        goto done;
    if (a->json) {
        fprintf(o.f, "{\n  \"n\": %d,\n  \"alpha\": %.17g,\n  \"D\": [", n, a->alpha);
        for (int i = 0; i < n; i++) {
            double row[64];
            for (int j = 0; j < n; j++)
                row[j] = D[i + (size_t)j * n];
            fprintf(o.f, "%s", i ? ", " : "");
            cli_json_array(o.f, row, n);
        }
        fprintf(o.f, "],\n  \"relation\": ");
        json_imatrix(o.f, r, n);
        fprintf(o.f, ",\n  \"support\": ");
        cli_json_iarray(o.f, sup, n);
        fprintf(o.f, ",\n  \"fusion_set\": ");
        cli_json_iarray(o.f, keep, n);
        fprintf(o.f, ",\n  \"fusion_set_one_shot\": ");
        cli_json_iarray(o.f, keep1, n);
        fprintf(o.f, ",\n  \"fused\": ");
        cli_json_num(o.f, fused);
        fprintf(o.f, ",\n  \"fused_sigma\": ");
        cli_json_num(o.f, fsig);
        fprintf(o.f, "\n}\n");
    } else {
        fprintf(o.f, "confidence-distance matrix D (row i: d_ij, i supports j when d_ij <= %g)\n",
                a->alpha);
        for (int i = 0; i < n; i++) {
            for (int j = 0; j < n; j++)
                fprintf(o.f, " %7.4f", D[i + (size_t)j * n]);
            fprintf(o.f, "\n");
        }
        fprintf(o.f, "relation matrix\n");
        for (int i = 0; i < n; i++) {
            for (int j = 0; j < n; j++)
                fprintf(o.f, " %d", r[i + (size_t)j * n]);
            fprintf(o.f, "\n");
        }
        fprintf(o.f, "%6s %8s %10s %10s\n", "sensor", "support", "iterative", "one-shot");
        for (int j = 0; j < n; j++)
            fprintf(o.f, "%6d %8d %10s %10s\n", j + 1, sup[j], keep[j] ? "kept" : "EXCLUDED",
                    keep1[j] ? "kept" : "EXCLUDED");
        fprintf(o.f, "fused (%s, %s set) = %.12g, sigma %.6g\n",
                a->average ? "average" : "weighted", a->one_shot ? "one-shot" : "iterative",
                fused, fsig);
    }
    ec = cli_out_commit(&o);
done:
    free(x);
    free(s);
    free(D);
    free(r);
    return ec;
}

static int do_fuse(const rd_args *a)
{
    cli_matrix m = {0};
    int ec, st, nwin = 0;
    if ((ec = cli_read_matrix(a->record, &m)))
        return ec;
    if (m.rows > 2147483647L || m.cols > 64) {
        cli_error("%s: too large (at most 64 sensors)", a->record);
        cli_matrix_free(&m);
        return CLI_DATAERR;
    }
    int ns = (int)m.rows, nc = m.cols;
    double *y = malloc(sizeof(double) * (size_t)ns * nc), *s = NULL;
    double *means = NULL, *fused = NULL, *fsig = NULL;
    int *ex = NULL;
    if (!y) {
        ec = cli_oom("the record");
        goto done;
    }
    for (int k = 0; k < ns; k++)
        for (int c = 0; c < nc; c++)
            y[k + (size_t)c * ns] = m.v[(size_t)k * nc + c];
    if ((ec = read_values("--sigma", a->sigma, &nc, &s)))
        goto done;
    if ((st = igea_redund_window_count(ns, a->fs, a->window, &nwin)) || nwin < 1) {
        cli_error("redund fuse: --window %g s at --fs %g Hz gives no whole window of %d samples",
                  a->window, a->fs, ns);
        ec = CLI_USAGE;
        goto done;
    }
    means = malloc(sizeof(double) * (size_t)nwin * (nc + 2));
    ex = malloc(sizeof(int) * (size_t)nwin * nc);
    if (!means || !ex) {
        ec = cli_oom("the consistency tables");
        goto done;
    }
    fused = means + (size_t)nwin * nc;
    fsig = fused + nwin;
    st = igea_redund_monitor(ns, nc, y, ns, a->fs, a->window, s, &a->alpha, 0,
                                  !a->one_shot, !a->average, nwin, means, ex, fused, fsig);
    if (st) {
        ec = cli_status(st, "redund fuse");
        goto done;
    }
    double step = (double)lround(a->window * a->fs) / a->fs;
    cli_out o;
    if ((ec = open_out(a, &o)))
        goto done;
    if (a->json) {
        fprintf(o.f, "{\n  \"windows\": %d,\n  \"sensors\": %d,\n  \"window\": %.17g,\n"
                     "  \"exclusions\": [", nwin, nc, step);
    } else {
        fprintf(o.f, "%d windows of %g s, %d sensors, alpha %g\n", nwin, step, nc, a->alpha);
    }
    int first = 1, any = 0;
    for (int c = 0; c < nc; c++)
        for (int w = 0; w < nwin; w++) {
            if (!ex[c + (size_t)w * nc] || (w > 0 && ex[c + (size_t)(w - 1) * nc]))
                continue;
            int e = w;
            while (e < nwin && ex[c + (size_t)e * nc])
                e++;
            any = 1;
            if (a->json) {
                fprintf(o.f, "%s{\"sensor\": %d, \"from\": %.17g, \"to\": %.17g}",
                        first ? "" : ", ", c + 1, w * step, e * step);
            } else {
                fprintf(o.f, "sensor %d excluded from %g s to %g s\n", c + 1, w * step, e * step);
            }
            first = 0;
        }
    if (a->json) {
        fprintf(o.f, "],\n  \"fused\": ");
        cli_json_array(o.f, fused, nwin);
        fprintf(o.f, ",\n  \"fused_sigma\": ");
        cli_json_array(o.f, fsig, nwin);
        fprintf(o.f, "\n}\n");
    } else {
        if (!any)
            fprintf(o.f, "no sensor excluded\n");
        fprintf(o.f, "%10s %20s %12s  excluded\n", "t (s)", "fused", "sigma");
        for (int w = 0; w < nwin; w++) {
            fprintf(o.f, "%10g %20.12g %12.4g ", w * step, fused[w], fsig[w]);
            for (int c = 0; c < nc; c++)
                if (ex[c + (size_t)w * nc])
                    fprintf(o.f, " %d", c + 1);
            fprintf(o.f, "\n");
        }
    }
    ec = cli_out_commit(&o);
done:
    cli_matrix_free(&m);
    free(y);
    free(s);
    free(means);
    free(ex);
    return ec;
}

static int do_fdi(const rd_args *a)
{
    cli_matrix h = {0};
    int ec, st;
    if ((ec = cli_read_matrix(a->H, &h)))
        return ec;
    int m = (int)h.rows, q = h.cols;
    if (m <= q || m > 1000) {
        cli_error("%s: H needs more rows than columns (m > q), at most 1000 rows", a->H);
        cli_matrix_free(&h);
        return CLI_DATAERR;
    }
    double *H = malloc(sizeof(double) * (size_t)m * q), *y = NULL, *s = NULL;
    double *par = malloc(sizeof(double) * (size_t)(m - q)), info[IGEA_REDUND_FDI_LEN];
    int iso = -1;
    if (!H || !par) {
        ec = cli_oom("the parity tables");
        goto done;
    }
    for (int i = 0; i < m; i++)
        for (int c = 0; c < q; c++)
            H[i + (size_t)c * m] = h.v[(size_t)i * q + c];
    if ((ec = read_values("--y", a->y, &m, &y)) || (ec = read_values("--sigma", a->sigma, &m, &s)))
        goto done;
    if ((st = igea_redund_fdi(m, q, H, m, y, s, a->pfa, par, info, &iso))) {
        ec = cli_status(st, "redund fdi");
        goto done;
    }
    cli_out o;
    if ((ec = open_out(a, &o)))
        goto done;
    if (a->json) {
        fprintf(o.f, "{\n  \"statistic\": ");
        cli_json_num(o.f, info[IGEA_REDUND_FDI_STAT]);
        fprintf(o.f, ",\n  \"threshold\": ");
        cli_json_num(o.f, info[IGEA_REDUND_FDI_THRESHOLD]);
        fprintf(o.f, ",\n  \"dof\": %d,\n  \"p_value\": ", (int)info[IGEA_REDUND_FDI_DOF]);
        cli_json_num(o.f, info[IGEA_REDUND_FDI_P_VALUE]);
        fprintf(o.f, ",\n  \"detected\": %s,\n  \"isolated\": %d,\n  \"isolable\": %s,\n"
                     "  \"parity\": ", info[IGEA_REDUND_FDI_DETECTED] ? "true" : "false",
                iso >= 0 ? iso + 1 : 0, info[IGEA_REDUND_FDI_ISOLABLE] ? "true" : "false");
        cli_json_array(o.f, par, m - q);
        fprintf(o.f, "\n}\n");
    } else {
        fprintf(o.f, "parity statistic %.6g, threshold chi2_%g(%d) = %.6g, p-value %.4g\n",
                info[IGEA_REDUND_FDI_STAT], a->pfa, (int)info[IGEA_REDUND_FDI_DOF], info[IGEA_REDUND_FDI_THRESHOLD],
                info[IGEA_REDUND_FDI_P_VALUE]);
        if (!info[IGEA_REDUND_FDI_DETECTED])
            fprintf(o.f, "no fault detected\n");
        else if (!info[IGEA_REDUND_FDI_ISOLABLE])
            fprintf(o.f, "FAULT DETECTED; this geometry cannot isolate a single fault "
                         "(most likely sensor %d)\n", iso + 1);
        else
            fprintf(o.f, "FAULT DETECTED, isolated sensor %d\n", iso + 1);
    }
    ec = cli_out_commit(&o);
done:
    cli_matrix_free(&h);
    free(H);
    free(par);
    free(y);
    free(s);
    return ec;
}

int cmd_redund(int argc, char **argv)
{
    if (cli_one_stdin(argc, argv))
        return CLI_USAGE;
    rd_args a;
    int ec = parse(argc, argv, &a);
    if (ec < 0)
        return CLI_OK;
    if (ec)
        return ec;
    if (!strcmp(a.sub, "reliability"))
        return do_reliability(&a);
    if (!strcmp(a.sub, "consistency"))
        return do_consistency(&a);
    if (!strcmp(a.sub, "fuse"))
        return do_fuse(&a);
    return do_fdi(&a);
}
