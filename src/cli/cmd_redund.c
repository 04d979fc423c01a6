/* igea redund - redundant sensor sets (seed 002, METHODS 3.1-3.3):
 * reliability, one-epoch consistency check and fusion, the windowed check
 * of a record, parity-space fault detection and isolation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

typedef struct {
    const char *axes, *R, *x, *sigma, *data, *H, *y, *out, *groups, *channels;
    double re1, re2, alpha, fs, window, pfa, block;
    int json, one_shot, average, gls;
    const char *plot; /* --plot FILE.svg (fuse) */
} rd_args;

static rd_args A;
static const cli_opt options[] = {
    CLI_HEAD("reliability:"),
    {"--re1", CLI_OPT_NUM, &A.re1, "0.992", "R", "gyro reliability", NULL},
    {"--re2", CLI_OPT_NUM, &A.re2, "0.995", "R", "accelerometer reliability", NULL},
    {"--axes", CLI_OPT_STR, &A.axes, NULL, "FILE", "n rows of 3: each sensor's input axis", NULL},
    {"--R", CLI_OPT_STR, &A.R, NULL, "FILE|NUM", "with --axes: sensor reliabilities (n values or one)", NULL},
    CLI_HEAD("consistency, fuse, fdi:"),
    {"--x", CLI_OPT_STR, &A.x, NULL, "FILE", "consistency: n measurements of one quantity", NULL},
    {"--data", CLI_OPT_STR, &A.data, NULL, "FILE", "fuse: the record (rows = samples, columns = sensors)", NULL},
    {"--fs", CLI_OPT_NUM, &A.fs, "-1", "HZ", "fuse: sampling rate (required)", NULL},
    {"--window", CLI_OPT_NUM, &A.window, "1", "S", "fuse: window length in seconds", NULL},
    {"--H", CLI_OPT_STR, &A.H, NULL, "FILE", "fdi: measurement matrix, m rows of q (m > q)", NULL},
    {"--y", CLI_OPT_STR, &A.y, NULL, "FILE", "fdi: the m measurements of one epoch", NULL},
    {"--sigma", CLI_OPT_STR, &A.sigma, NULL, "FILE|NUM", "tolerances (consistency, fuse) or noise sds (fdi)", NULL},
    {"--alpha", CLI_OPT_NUM, &A.alpha, "0.7", "A", "relation threshold on d_ij", NULL},
    {"--one-shot", CLI_OPT_FLAG, &A.one_shot, NULL, NULL, "one-shot fusion set instead of the iterative majority", NULL},
    {"--average", CLI_OPT_FLAG, &A.average, NULL, NULL, "fuse: plain mean instead of the weighted one", NULL},
    {"--pfa", CLI_OPT_NUM, &A.pfa, "0.01", "P", "fdi: false-alarm probability", NULL},
    CLI_HEAD("group (virtual IMUs; --axes: the calibrated input axes, --y: one reading\n"
             "per sensor, --sigma: their noise sds, --average: the plain mean):"),
    {"--groups", CLI_OPT_STR, &A.groups, "0,4,6;1,5,7;2,4,6;3,5,7", "X,Y,Z;...", "group: the x, y, z sensor of each group (default:\nseed 002's Ax1..Ax4 = 0..3, Ay1 Ay2 = 4 5, Az1 Az2 = 6 7)", NULL},
    {"--gls", CLI_OPT_FLAG, &A.gls, NULL, NULL, "group: generalised least squares of the distinct\nsensors instead of the per-axis weighted mean", NULL},
    CLI_HEAD("stability (Table 1: --data the record, --fs, --average the plain mean):"),
    {"--channels", CLI_OPT_STR, &A.channels, NULL, "C,C,...", "stability: each column's fused channel (from 0;\n-1: not fused)", NULL},
    {"--block", CLI_OPT_NUM, &A.block, "100", "S", "stability: block length (s)", NULL},
    CLI_JSON_OPT(&A.json),
    CLI_OUT_OPT(&A.out),
    {"--plot", CLI_OPT_STR, &A.plot, NULL, "FILE.svg", "fuse: draw the fused output and the sensor-exclusion\ntimeline into an SVG picture", NULL},
    CLI_END};

static const cli_command command = {"redund",
"usage: igea redund reliability [--re1 R] [--re2 R] [--axes FILE --R FILE|NUMBER]\n"
"       igea redund consistency --x FILE --sigma FILE|NUMBER [--alpha A] [--one-shot]\n"
"       igea redund fuse --data FILE --fs HZ --sigma FILE|NUMBER [--window S]\n"
"                        [--alpha A] [--one-shot] [--average]\n"
"       igea redund fdi --H FILE --y FILE --sigma FILE|NUMBER [--pfa P]\n"
"       igea redund group --axes FILE --y FILE --sigma FILE|NUMBER [--groups LIST]\n"
"                         [--average | --gls]\n"
"       igea redund stability --data FILE --fs HZ --channels C,C,... [--block S]\n"
"                             [--average]\n"
"       (every form takes --json and --out FILE)\n"
"\n"
"Redundant inertial sensors (METHODS 3). Sensors are numbered from 0.\n"
"\n"
"reliability  Without --axes: the figures of seed 002 for gyro reliability\n"
"             --re1 and accelerometer reliability --re2: eq. (6), (7), (8), the\n"
"             quoted (10) (= without the skew sensor), the non-redundant (9)\n"
"             and the exact geometric value. With --axes and --R: P(the\n"
"             surviving axes span 3-D), and P(they can still detect / isolate\n"
"             a further single fault) from the parity matrix.\n"
"consistency  One epoch of n redundant measurements --x of one quantity with\n"
"             tolerances --sigma: the confidence-distance matrix D, the relation\n"
"             matrix (d_ij <= alpha), support counts, the fusion set (iterative\n"
"             majority; --one-shot) and the fused value and sigma. Choose sigma\n"
"             as a tolerance (about 3-5x the noise of x): with sigma equal to the\n"
"             noise, healthy pairs disagree 46 % of the time.\n"
"fuse         A record sampled at --fs Hz: the check of every window of\n"
"             --window seconds on the window means: which sensors were excluded\n"
"             when, and the fused output (weighted; --average for the mean).\n"
"fdi          Parity-space test of one epoch y = H x + e: chi-square detection\n"
"             at false-alarm probability --pfa and the isolated sensor.\n"
"group        Virtual IMUs (seed 002): each group's frame from its sensors'\n"
"             calibrated axes, unified into group 0's frame, each group's output\n"
"             and the fused one, with the covariance that counts a sensor shared\n"
"             by several groups once (cov) beside the one independent groups\n"
"             would state (cov_indep).\n"
"stability    Table 1 of seed 002: the 100-s variance (3 sigma of the means of\n"
"             --block-second blocks) of every column of --data and of every\n"
"             fused channel (the weighted mean of its columns, weights 1 / each\n"
"             column's block variance; --average: the plain mean).\n"
"\n"
"options:\n",
options,
"\n"
"exit status: 0 ok (a detected fault is reported, not an error), 64 usage,\n"
"65 bad input, 66 missing input, 70 numerical failure, 74 I/O error.\n"
"\n"
"examples:\n"
"  igea redund reliability\n"
"  printf '1.000010\\n1.000018\\n0.999995\\n1.010004\\n' > x.txt\n"
"  igea redund consistency --x x.txt --sigma 20e-6 --alpha 0.7\n"
"  igea redund fuse --data ax.npy --fs 100 --window 1 --sigma 20e-6 --json\n"};

enum { RELIABILITY, CONSISTENCY, FUSE, FDI, GROUP, STABILITY };

/* The subcommand's inputs, present. */
static const char *check_sub(int sub, const rd_args *a)
{
    if (sub == RELIABILITY && a->axes && !a->R)
        return "redund reliability: --axes needs --R";
    if (sub == CONSISTENCY && (!a->x || !a->sigma))
        return "redund consistency: --x and --sigma are required";
    if (sub == FUSE && (!a->data || !a->sigma || !(a->fs > 0)))
        return "redund fuse: --data, --fs (> 0) and --sigma are required";
    if (sub != FUSE && a->plot)
        return "redund: --plot draws redund fuse only";
    if (sub == FDI && (!a->H || !a->y || !a->sigma))
        return "redund fdi: --H, --y and --sigma are required";
    if (sub == GROUP && (!a->axes || !a->y || !a->sigma))
        return "redund group: --axes, --y and --sigma are required";
    if (sub == STABILITY && (!a->data || !a->channels || !(a->fs > 0) || !(a->block > 0)))
        return "redund stability: --data, --fs (> 0) and --channels are required, --block > 0";
    if (sub == GROUP && a->average && a->gls)
        return "redund group: --average and --gls exclude each other";
    return NULL;
}

static int parse(int argc, char **argv, rd_args *a, int *sub)
{
    if (argc > 1 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        cli_help(stdout, &command);
        return CLI_HELP;
    }
    if (argc < 2 || argv[1][0] == '-') {
        cli_error("redund: a subcommand is required: reliability, consistency, fuse, fdi, group or stability");
        return CLI_USAGE;
    }
    if (cli_pick("redund", argv[1], "reliability|consistency|fuse|fdi|group|stability", sub))
        return CLI_USAGE;
    int ec = cli_parse(&command, argc - 1, argv + 1);
    *a = A;
    if (ec)
        return ec;
    if (!(a->alpha > 0 && a->alpha < 1) || !(a->pfa > 0 && a->pfa < 1))
        return cli_usage("redund: --alpha and --pfa must lie in (0, 1)");
    if (!(a->re1 >= 0 && a->re1 <= 1) || !(a->re2 >= 0 && a->re2 <= 1))
        return cli_usage("redund: --re1 and --re2 must lie in [0, 1]");
    if (!(a->window > 0))
        return cli_usage("redund: --window must be > 0");
    return cli_usage(check_sub(*sub, a));
}

static int report_seed002(const rd_args *a, FILE *f)
{
    double r[IGEA_REDUND_SEED002_LEN];
    int st = igea_redund_seed002(a->re1, a->re2, r);
    if (st)
        return cli_status(st, "redund reliability: --re1/--re2 in [0, 1]");
    static const char *names[IGEA_REDUND_SEED002_LEN] = {
        "gyro_eq6", "acc_eq7", "system_eq8_with_eq7", "system_without_skew_eq10",
        "non_redundant_eq9", "system_exact", "acc_exact"};
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, f);
        cli_jnum(&j, "re1", a->re1);
        cli_jnum(&j, "re2", a->re2);
        for (int k = 0; k < IGEA_REDUND_SEED002_LEN; k++)
            cli_jnum(&j, names[k], r[k]);
        cli_json_end(&j);
        return CLI_OK;
    }
    fprintf(f, "seed 002 reliability, Re1 = %g (gyros), Re2 = %g (accelerometers)\n", a->re1, a->re2);
    fprintf(f, "  gyros, 2 per axis (6)                  %.10f\n", r[0]);
    fprintf(f, "  accelerometers as printed (7)          %.12f\n", r[1]);
    fprintf(f, "  system (8) with (7)                    %.10f\n", r[2]);
    fprintf(f, "  system without the skew sensor (10)    %.10f   <- the quoted value\n", r[3]);
    fprintf(f, "  non-redundant (9)                      %.10f\n", r[4]);
    fprintf(f, "  system, exact geometric                %.10f\n", r[5]);
    fprintf(f, "(7) counts 'only the skew sensor D survives' as working; the exact\n"
               "value does not: one skewed axis cannot measure two components.)\n");
    return CLI_OK;
}

static int report_geometry(const rd_args *a, FILE *f)
{
    double *axc = NULL, *R = NULL, g[IGEA_REDUND_GEOM_LEN];
    int n, cols, ec = cli_read_colmajor(a->axes, &axc, &n, &cols);
    if (!ec && (cols != 3 || n < 1 || n > IGEA_REDUND_GEOM_FDI_MAX)) {
        cli_error("%s: expected 1 to %d rows of 3 (one input axis per sensor)", a->axes,
                  IGEA_REDUND_GEOM_FDI_MAX);
        ec = CLI_DATAERR;
    }
    if (!ec && !(ec = cli_read_values(a->R, n, "--R", &R, NULL)))
        ec = cli_status(igea_redund_geometry(n, axc, n, R, 1, g), "redund reliability");
    free(axc);
    free(R);
    if (ec)
        return ec;
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, f);
        cli_jint(&j, "sensors", n);
        cli_jint(&j, "classes", (long)g[3]);
        cli_jnum(&j, "span", g[0]);
        cli_jnum(&j, "detect", g[1]);
        cli_jnum(&j, "isolate", g[2]);
        cli_json_end(&j);
        return CLI_OK;
    }
    fprintf(f, "%d sensors in %d direction classes\n", n, (int)g[3]);
    fprintf(f, "  P(surviving axes span 3-D)                  %.12f\n", g[0]);
    fprintf(f, "  P(... and a further fault is detectable)    %.12f\n", g[1]);
    fprintf(f, "  P(... and a further fault is isolable)      %.12f\n", g[2]);
    return CLI_OK;
}

static int do_reliability(const rd_args *a, FILE *f)
{
    return a->axes ? report_geometry(a, f) : report_seed002(a, f);
}

typedef struct {
    int n, *r, *sup, *keep, *keep1;
    double *x, *s, *D, fused, fsig;
} consistency;

static void report_consistency(const rd_args *a, FILE *f, const consistency *c)
{
    int n = c->n;
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, f);
        cli_jint(&j, "n", n);
        cli_jnum(&j, "alpha", a->alpha);
        cli_jmatrix(&j, "D", c->D, NULL, n, n, 1, n);
        cli_jmatrix(&j, "relation", NULL, c->r, n, n, 1, n);
        cli_jints(&j, "support", c->sup, n);
        cli_jints(&j, "fusion_set", c->keep, n);
        cli_jints(&j, "fusion_set_one_shot", c->keep1, n);
        cli_jnum(&j, "fused", c->fused);
        cli_jnum(&j, "fused_sigma", c->fsig);
        cli_json_end(&j);
        return;
    }
    fprintf(f, "confidence-distance matrix D (row i: d_ij, i supports j when d_ij <= %g)\n", a->alpha);
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < n; k++)
            fprintf(f, " %7.4f", c->D[i + (size_t)k * n]);
        fprintf(f, "\n");
    }
    fprintf(f, "relation matrix\n");
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < n; k++)
            fprintf(f, " %d", c->r[i + (size_t)k * n]);
        fprintf(f, "\n");
    }
    fprintf(f, "%6s %8s %10s %10s\n", "sensor", "support", "iterative", "one-shot");
    for (int k = 0; k < n; k++)
        fprintf(f, "%6d %8d %10s %10s\n", k, c->sup[k], c->keep[k] ? "kept" : "EXCLUDED",
                c->keep1[k] ? "kept" : "EXCLUDED");
    fprintf(f, "fused (%s, %s set) = %.12g, sigma %.6g\n", a->average ? "average" : "weighted",
            a->one_shot ? "one-shot" : "iterative", c->fused, c->fsig);
}

static int do_consistency(const rd_args *a, FILE *f)
{
    consistency c;
    memset(&c, 0, sizeof c);
    long n;
    int ec = cli_read_values(a->x, -1, "--x", &c.x, &n), st;
    if (!ec && n > 64) {
        cli_error("%s: at most 64 measurements", a->x);
        ec = CLI_DATAERR;
    }
    c.n = (int)n;
    if (!ec)
        ec = cli_read_values(a->sigma, n, "--sigma", &c.s, NULL);
    size_t nn = (size_t)n * n;
    if (!ec && (!(c.D = malloc(sizeof(double) * nn)) ||
                !(c.r = malloc(sizeof(int) * (nn + 3 * (size_t)n)))))
        ec = cli_oom("the consistency tables");
    if (!ec) {
        c.sup = c.r + nn, c.keep = c.sup + n, c.keep1 = c.keep + n;
        if ((st = igea_redund_confidence_distance(c.n, c.x, c.s, c.D, c.n)) ||
            (st = igea_redund_relation(c.n, c.D, c.n, &a->alpha, 0, c.r, c.n)) ||
            (st = igea_redund_fusion_set(c.n, c.D, c.n, &a->alpha, 0, 1, c.keep, c.sup)) ||
            (st = igea_redund_fusion_set(c.n, c.D, c.n, &a->alpha, 0, 0, c.keep1, NULL)) ||
            (st = igea_redund_fuse(c.n, c.x, c.s, a->one_shot ? c.keep1 : c.keep, !a->average,
                                   &c.fused, &c.fsig)))
            ec = cli_status(st, "redund consistency (sigma > 0, 0 < alpha < 1)");
    }
    if (!ec)
        report_consistency(a, f, &c);
    free(c.x);
    free(c.s);
    free(c.D);
    free(c.r);
    return ec;
}

typedef struct {
    int nwin, nc, niv, *ex, *iv; /* iv: sensor, win_start, win_end (3 x maxiv) */
    double *means, *fused, *fsig, *t, step; /* t: t_start, t_end (2 x maxiv) */
} fuse_run;

static void report_fuse(const rd_args *a, FILE *f, const fuse_run *r)
{
    int nwin = r->nwin, nc = r->nc, m = nc * ((nwin + 1) / 2);
    const int *sensor = r->iv;
    const double *t0 = r->t, *t1 = r->t + m;
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, f);
        cli_jint(&j, "windows", nwin);
        cli_jint(&j, "sensors", nc);
        cli_jnum(&j, "window", r->step);
        cli_json_open(&j, "exclusions", '[');
        for (int k = 0; k < r->niv; k++) {
            cli_json_open(&j, NULL, '{');
            cli_jint(&j, "sensor", sensor[k]);
            cli_jnum(&j, "from", t0[k]);
            cli_jnum(&j, "to", t1[k]);
            cli_json_close(&j);
        }
        cli_json_close(&j);
        cli_jnums(&j, "fused", r->fused, nwin);
        cli_jnums(&j, "fused_sigma", r->fsig, nwin);
        cli_json_end(&j);
        return;
    }
    fprintf(f, "%d windows of %g s, %d sensors, alpha %g\n", nwin, r->step, nc, a->alpha);
    for (int k = 0; k < r->niv; k++)
        fprintf(f, "sensor %d excluded from %g s to %g s\n", sensor[k], t0[k], t1[k]);
    if (!r->niv)
        fprintf(f, "no sensor excluded\n");
    fprintf(f, "%10s %20s %12s  excluded\n", "t (s)", "fused", "sigma");
    for (int w = 0; w < nwin; w++) {
        fprintf(f, "%10g %20.12g %12.4g ", w * r->step, r->fused[w], r->fsig[w]);
        for (int c = 0; c < nc; c++)
            if (r->ex[c + (size_t)w * nc])
                fprintf(f, " %d", c);
        fprintf(f, "\n");
    }
}

/* The windowed check and its exclusion intervals. */
static int run_fuse(const rd_args *a, const double *y, int ns, const double *s, fuse_run *r)
{
    int nwin = r->nwin, nc = r->nc, m = nc * ((nwin + 1) / 2);
    double *means = r->means = malloc(sizeof(double) * (size_t)nwin * (nc + 2));
    r->ex = malloc(sizeof(int) * (size_t)nwin * nc);
    r->iv = malloc(sizeof(int) * 3 * (size_t)m);
    r->t = malloc(sizeof(double) * 2 * (size_t)m);
    int ec = !means || !r->ex || !r->iv || !r->t ? cli_oom("the consistency tables") : CLI_OK;
    if (!ec) {
        r->fused = means + (size_t)nwin * nc;
        r->fsig = r->fused + nwin;
        int st = igea_redund_monitor(ns, nc, y, ns, a->fs, a->window, s, &a->alpha, 0,
                                     !a->one_shot, !a->average, nwin, means, r->ex, r->fused,
                                     r->fsig);
        if (!st)
            st = igea_redund_monitor_intervals(nc, nwin, r->ex, a->fs, a->window, m, &r->niv,
                                               r->iv, r->iv + m, r->iv + 2 * m, r->t, r->t + m);
        ec = cli_status(st, "redund fuse");
    }
    return ec;
}

static int do_fuse(const rd_args *a, FILE *f)
{
    double *y = NULL, *s = NULL;
    fuse_run r;
    memset(&r, 0, sizeof r);
    int ns = 0, ec = cli_read_colmajor(a->data, &y, &ns, &r.nc);
    if (!ec && r.nc > 64) {
        cli_error("%s: too large (at most 64 sensors)", a->data);
        ec = CLI_DATAERR;
    }
    if (!ec)
        ec = cli_read_values(a->sigma, r.nc, "--sigma", &s, NULL);
    if (!ec && (igea_redund_window_count(ns, a->fs, a->window, &r.nwin) || r.nwin < 1)) {
        cli_error("redund fuse: --window %g s at --fs %g Hz gives no whole window of %d samples",
                  a->window, a->fs, ns);
        ec = CLI_USAGE;
    }
    if (!ec && !(ec = run_fuse(a, y, ns, s, &r))) {
        igea_redund_window_length(a->fs, a->window, NULL, &r.step);
        int m = r.nc * ((r.nwin + 1) / 2); /* the picture first: on its failure no report */
        if (!a->plot || !(ec = cli_svg_fuse(a->plot, r.nwin, r.step, r.fused, r.fsig, r.nc,
                                            r.niv, r.iv, r.t, r.t + m)))
            report_fuse(a, f, &r);
    }
    free(r.means);
    free(y);
    free(s);
    free(r.ex);
    free(r.iv);
    free(r.t);
    return ec;
}

static void report_fdi(const rd_args *a, FILE *f, const double *info, int iso, const double *par,
                       int npar)
{
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, f);
        cli_jnum(&j, "statistic", info[IGEA_REDUND_FDI_STAT]);
        cli_jnum(&j, "threshold", info[IGEA_REDUND_FDI_THRESHOLD]);
        cli_jint(&j, "dof", (long)info[IGEA_REDUND_FDI_DOF]);
        cli_jnum(&j, "p_value", info[IGEA_REDUND_FDI_P_VALUE]);
        cli_jbool(&j, "detected", info[IGEA_REDUND_FDI_DETECTED] != 0);
        cli_jint(&j, "isolated", iso);
        cli_jbool(&j, "isolable", info[IGEA_REDUND_FDI_ISOLABLE] != 0);
        cli_jnums(&j, "parity", par, npar);
        cli_json_end(&j);
        return;
    }
    fprintf(f, "parity statistic %.6g, threshold chi2_%g(%d) = %.6g, p-value %.4g\n",
            info[IGEA_REDUND_FDI_STAT], a->pfa, (int)info[IGEA_REDUND_FDI_DOF],
            info[IGEA_REDUND_FDI_THRESHOLD], info[IGEA_REDUND_FDI_P_VALUE]);
    if (!info[IGEA_REDUND_FDI_DETECTED])
        fprintf(f, "no fault detected\n");
    else if (!info[IGEA_REDUND_FDI_ISOLABLE])
        fprintf(f, "FAULT DETECTED; this geometry cannot isolate a single fault "
                   "(most likely sensor %d)\n", iso);
    else
        fprintf(f, "FAULT DETECTED, isolated sensor %d\n", iso);
}

static int do_fdi(const rd_args *a, FILE *f)
{
    double *H = NULL, *y = NULL, *s = NULL, *par = NULL, info[IGEA_REDUND_FDI_LEN];
    int m = 0, q = 0, iso = -1, ec = cli_read_colmajor(a->H, &H, &m, &q);
    if (!ec && (m <= q || m > 1000)) {
        cli_error("%s: H needs more rows than columns (m > q), at most 1000 rows", a->H);
        ec = CLI_DATAERR;
    }
    if (!ec && !(par = malloc(sizeof(double) * (size_t)(m - q))))
        ec = cli_oom("the parity vector");
    if (!ec && !(ec = cli_read_values(a->y, m, "--y", &y, NULL)) &&
        !(ec = cli_read_values(a->sigma, m, "--sigma", &s, NULL)))
        ec = cli_status(igea_redund_fdi(m, q, H, m, y, s, a->pfa, par, info, &iso), "redund fdi");
    if (!ec)
        report_fdi(a, f, info, iso, par, m - q);
    free(H);
    free(par);
    free(y);
    free(s);
    return ec;
}

/* --groups "x,y,z;x,y,z;...": 3 ngroup sensor indices (checked by the
 * library against the number of sensors). */
static int read_groups(const char *arg, int **member, int *ngroup)
{
    int n = 1;
    for (const char *p = arg; *p; p++)
        n += *p == ';';
    int *m = malloc(sizeof(int) * 3 * (size_t)n), g = 0;
    if (!m)
        return cli_oom("the groups");
    const char *p = arg;
    for (g = 0; g < n; g++)
        for (int k = 0; k < 3; k++) {
            char *end;
            long v = strtol(p, &end, 10);
            char want = k < 2 ? ',' : (g < n - 1 ? ';' : '\0');
            if (end == p || v < 0 || v > 100000 || *end != want) {
                free(m);
                cli_error("--groups '%s': expected x,y,z sensor indices (from 0) per group, "
                          "groups separated by ';'", arg);
                return CLI_USAGE;
            }
            m[3 * g + k] = (int)v;
            p = end + 1;
        }
    *member = m;
    *ngroup = n;
    return CLI_OK;
}

static void report_group(const rd_args *a, FILE *f, int ng, const double *fr, const double *u,
                         const double *fu, const double *cov, const double *ci)
{
    const char *rule = a->gls ? "gls" : a->average ? "average" : "weighted";
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, f);
        cli_jstr(&j, "fusion", rule);
        cli_json_open(&j, "frames", '[');
        for (int g = 0; g < ng; g++)
            cli_jmatrix(&j, NULL, fr + 9 * g, NULL, 3, 3, 1, 3);
        cli_json_close(&j);
        cli_jmatrix(&j, "group_out", u, NULL, ng, 3, 3, 1);
        cli_jnums(&j, "fused", fu, 3);
        cli_jmatrix(&j, "cov", cov, NULL, 3, 3, 1, 3);
        cli_jmatrix(&j, "cov_indep", ci, NULL, 3, 3, 1, 3);
        cli_json_end(&j);
        return;
    }
    fprintf(f, "# virtual IMUs in group 0's frame (fusion %s)\n", rule);
    for (int g = 0; g < ng; g++)
        fprintf(f, "group %d: %.10g %.10g %.10g\n", g, u[3 * g], u[3 * g + 1], u[3 * g + 2]);
    fprintf(f, "fused:   %.10g %.10g %.10g\n", fu[0], fu[1], fu[2]);
    fprintf(f, "# variances of the fused axes: shared sensors counted once, and as if\n"
               "# the groups were independent\n");
    for (int i = 0; i < 3; i++)
        fprintf(f, "var %c: %.6g (independent: %.6g)\n", "xyz"[i], cov[4 * i], ci[4 * i]);
}

static int do_group(const rd_args *a, FILE *f)
{
    double *ax = NULL, *y = NULL, *s = NULL, *buf = NULL;
    int *mem = NULL, n = 0, cols = 0, ng = 0, ec = cli_read_colmajor(a->axes, &ax, &n, &cols);
    if (!ec && (cols != 3 || n < 3)) {
        cli_error("%s: the axes need 3 columns and at least 3 rows", a->axes);
        ec = CLI_DATAERR;
    }
    if (!ec)
        ec = read_groups(a->groups, &mem, &ng);
    if (!ec && !(ec = cli_read_values(a->y, n, "--y", &y, NULL)))
        ec = cli_read_values(a->sigma, n, "--sigma", &s, NULL);
    if (!ec && !(buf = malloc(sizeof(double) * (12 * (size_t)ng + 3 * (size_t)n + 21))))
        ec = cli_oom("the group results");
    if (!ec) {
        double *axr = buf + 12 * (size_t)ng + 21; /* row i = axis i: 3 x n column-major */
        for (int i = 0; i < n; i++)
            for (int j = 0; j < 3; j++)
                axr[3 * i + j] = ax[(size_t)j * n + i];
        int rule = a->gls ? IGEA_REDUND_GROUP_GLS
                          : a->average ? IGEA_REDUND_GROUP_AVERAGE : IGEA_REDUND_GROUP_WEIGHTED;
        int st = igea_redund_group(n, axr, s, ng, mem, y, rule, buf, buf + 9 * ng,
                                   buf + 12 * ng, buf + 12 * ng + 3, buf + 12 * ng + 12);
        if (st == -5)
            ec = cli_usage("--groups: a sensor index beyond the --axes rows, or a sensor twice "
                           "in a group");
        else if (st == IGEA_ESINGULAR)
            ec = (cli_error("redund group: a group's three axes are not independent"),
                  CLI_DATAERR);
        else
            ec = cli_status(st, "redund group");
    }
    if (!ec)
        report_group(a, f, ng, buf, buf + 9 * ng, buf + 12 * ng, buf + 12 * ng + 3,
                     buf + 12 * ng + 12);
    free(ax);
    free(y);
    free(s);
    free(mem);
    free(buf);
    return ec;
}

static void json_blocks(cli_json *j, const char *key, const double *o, int n)
{
    cli_json_open(j, key, '[');
    for (int i = 0; i < n; i++)
        cli_jnum(j, NULL, o[(size_t)i * IGEA_STABILITY_BLOCK_LEN]);
    cli_json_close(j);
}

static void report_stability(const rd_args *a, FILE *f, int ns, const int *ch, int nc,
                             const double *so, const double *fo)
{
    const int L = IGEA_STABILITY_BLOCK_LEN;
    double sec = so[IGEA_STABILITY_BLOCK_NSAMP] / a->fs;
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, f);
        cli_jnum(&j, "block_seconds", sec);
        cli_jints(&j, "channel", ch, ns);
        json_blocks(&j, "three_sigma", so + IGEA_STABILITY_BLOCK_3SIGMA, ns);
        json_blocks(&j, "sigma", so + IGEA_STABILITY_BLOCK_SIGMA, ns);
        json_blocks(&j, "fused_three_sigma", fo + IGEA_STABILITY_BLOCK_3SIGMA, nc);
        json_blocks(&j, "fused_sigma", fo + IGEA_STABILITY_BLOCK_SIGMA, nc);
        cli_json_end(&j);
        return;
    }
    fprintf(f, "# %g-s variance (3 sigma of the block means, %d blocks; fused: %s mean)\n", sec,
            (int)so[IGEA_STABILITY_BLOCK_NBLOCK], a->average ? "plain" : "weighted");
    for (int i = 0; i < ns; i++)
        fprintf(f, "column %d (channel %d): %.6g\n", i, ch[i], so[(size_t)L * i]);
    for (int c = 0; c < nc; c++)
        fprintf(f, "fused channel %d: %.6g\n", c, fo[(size_t)L * c]);
}

static int do_stability(const rd_args *a, FILE *f)
{
    double *y = NULL, *so = NULL;
    int n = 0, ns = 0, nc = 0, *ch = NULL, ec = cli_read_colmajor(a->data, &y, &n, &ns);
    char **items = NULL;
    int ni = 0;
    if (!ec && !(ec = cli_split_list(a->channels, &items, &ni)) && ni != ns) {
        cli_error("--channels: %d values for the %d columns of %s", ni, ns, a->data);
        ec = CLI_USAGE;
    }
    if (!ec && !(ch = malloc(sizeof(int) * (size_t)ns)))
        ec = cli_oom("the channels");
    for (int i = 0; i < ni && !ec; i++) {
        char *end;
        long v = strtol(items[i], &end, 10);
        if (*end || end == items[i] || v < -1 || v >= ns)
            ec = cli_usage("--channels: each value a channel number from 0, or -1");
        else
            ch[i] = (int)v, nc = v + 1 > nc ? (int)v + 1 : nc;
    }
    if (!ec && !(so = malloc(sizeof(double) * IGEA_STABILITY_BLOCK_LEN * (size_t)(ns + nc))))
        ec = cli_oom("the block statistics");
    if (!ec) {
        int st = igea_redund_stability(n, ns, y, n, a->fs, a->block, ch, nc, !a->average, so,
                                       so + (size_t)IGEA_STABILITY_BLOCK_LEN * ns, NULL);
        if (st == -8)
            ec = cli_usage("--channels: every channel from 0 to the largest needs a column");
        else if (st == -6)
            ec = cli_usage("redund stability: the record holds fewer than two whole --block blocks");
        else if (st == IGEA_EDOMAIN)
            ec = (cli_error("redund stability: a constant column cannot be weighted (use "
                            "--average)"), CLI_DATAERR);
        else
            ec = cli_status(st, "redund stability");
    }
    if (!ec)
        report_stability(a, f, ns, ch, nc, so, so + (size_t)IGEA_STABILITY_BLOCK_LEN * ns);
    free(items);
    free(y);
    free(ch);
    free(so);
    return ec;
}

int cmd_redund(int argc, char **argv)
{
    rd_args a;
    int sub, ec = parse(argc, argv, &a, &sub);
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    static int (*const run[])(const rd_args *, FILE *) = {do_reliability, do_consistency,
                                                          do_fuse, do_fdi, do_group,
                                                          do_stability};
    /* the report goes to a temporary first: a failed run leaves no part */
    cli_out o;
    if ((ec = cli_out_open(&o, a.out)))
        return ec;
    if ((ec = run[sub](&a, o.f))) {
        cli_out_abort(&o);
        return ec;
    }
    return cli_out_commit(&o);
}
