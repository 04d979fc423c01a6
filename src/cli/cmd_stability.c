/* igea stability - stability statistics of a static sensor record (METHODS
 * 3.4): the block-mean 3-sigma ("100-second variance"), Allan deviation and
 * Stable32's statistics on phase or frequency data with confidence
 * intervals, the IEEE Std 952 noise model fitted to the curve
 * (docs/stability.md). */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

typedef struct {
    const char *file, *taus, *out, *plot;
    double fs, block, conf;
    int column, column_given, kind, noise, json, phase, spacing, fit;
    int boot, seed; /* the --fit standard errors: bootstrap records, seed */
    int gaps;       /* NaN in the file is a gap */
} st_args;

static st_args A;

static const cli_opt options[] = {
    {"--data", CLI_OPT_STR, &A.file, NULL, "FILE", "the record: text or .npy ('-' for standard input)", NULL},
    {"--fs", CLI_OPT_NUM, &A.fs, NULL, "HZ", "sampling rate (required)", NULL},
    {"--column", CLI_OPT_INT, &A.column, "0", "K", "the record's column in a file of several (from 0)",
     &A.column_given},
    {"--block", CLI_OPT_NUM, &A.block, "100", "S", "block length in seconds", NULL},
    {"--kind", CLI_OPT_CHOICE, &A.kind, "overlapping", CLI_CHOICES(IGEA_CHOICE_STABILITY_KIND),
     "statistic: the rate-data Allan deviations\n(overlapping modified nonoverlapping) or\nStable32's (adev ... tierms)", NULL},
    {"--phase", CLI_OPT_FLAG, &A.phase, NULL, NULL, "the record is phase (time error, s), not\nfrequency (Stable32 kinds only)", NULL},
    {"--gaps", CLI_OPT_FLAG, &A.gaps, NULL, NULL, "the token NaN in the file is a gap (adev oadev\nmdev tdev hdev ohdev leave out the terms that\nhold one; other kinds refuse it); without\n--gaps NaN is refused", NULL},
    {"--taus", CLI_OPT_STR, &A.taus, NULL, "FILE", "averaging times (default: --spacing)", NULL},
    {"--spacing", CLI_OPT_CHOICE, &A.spacing, "octave", CLI_CHOICES(IGEA_CHOICE_STABILITY_TAUS),
     "generated averaging times (Stable32 kinds;\nthe rate-data kinds use octaves)", NULL},
    {"--fit", CLI_OPT_FLAG, &A.fit, NULL, NULL, "report the IEEE 952 fit in full (standard\nerrors, support)", NULL},
    {"--boot", CLI_OPT_INT, &A.boot, "100", "B", "--fit standard errors from B records simulated\nfrom the fitted model, each as long as the\nrecord (0: from the fit's weights, the points\ntaken as independent: faster, optimistic)", NULL},
    {"--seed", CLI_OPT_INT, &A.seed, "0", "N", "seed of the --boot records", NULL},
    {"--noise", CLI_OPT_CHOICE, &A.noise, "auto", CLI_CHOICES(IGEA_CHOICE_STABILITY_NOISE),
     "noise type for the intervals (auto: per tau\nfrom the lag-1 autocorrelation)", NULL},
    {"--conf", CLI_OPT_NUM, &A.conf, "0.683", "C", "confidence of the intervals, in (0, 1)", NULL},
    CLI_PROGRESS_OPTIONS,
    CLI_JSON_OPT(&A.json),
    CLI_OUT_OPT(&A.out),
    {"--plot", CLI_OPT_STR, &A.plot, NULL, "FILE.svg", "draw the deviation with its intervals on log-log\naxes (and the --fit terms) into an SVG picture", NULL},
    CLI_END};

static const cli_command command = {"stability",
"usage: igea stability --data FILE --fs HZ [options]\n"
"\n"
"Stability of a static record of one sensor (a gyro's rate, an\n"
"accelerometer's output) sampled at --fs Hz: one value per row; a file of\n"
"several columns needs --column K to pick the record.\n"
"\n"
"  block statistic  3 sigma of the means of non-overlapping --block-second\n"
"                   blocks (the seed's 100-second variance), with the Allan\n"
"                   deviation at the block length;\n"
"  Allan deviation  at octave averaging times (or the taus of --taus), of\n"
"                   --kind, with --conf intervals from equivalent degrees of\n"
"                   freedom (NIST SP 1065; the noise type per tau from the\n"
"                   lag-1 autocorrelation, or fixed with --noise);\n"
"  Stable32 kinds   adev oadev mdev tdev hdev ohdev totdev mtotdev ttotdev\n"
"                   htotdev theo1 theobr theoh mtie tierms (NIST SP 1065) of\n"
"                   frequency or, with --phase, phase data; the kind's EDF\n"
"                   (Greenhall's, Howe's total-family tables, Theo1's), the\n"
"                   noise type identified at each tau on its own (alpha);\n"
"  noise terms      the IEEE Std 952 model 3Q^2/tau^2 + N^2/tau + (2 ln2/pi) B^2\n"
"                   + K^2 tau/3 + R^2 tau^2/2 fitted to the whole Allan curve\n"
"                   (weights from the EDF, coefficients >= 0): quantisation Q,\n"
"                   random walk N, bias instability B, rate random walk K,\n"
"                   rate ramp R; '-' for a term the data do not support.\n"
"The record is read as a stream for the Allan and Hadamard kinds (the\n"
"rate-data kinds, and adev ... ohdev with --noise given): memory for the\n"
"longest lag, not the record; the others load it (the total family, Theo1\n"
"and MTIE need the whole record, the Stable32 noise identification too).\n"
"Progress (averaging times done, elapsed time, ETA) goes to stderr when it\n"
"is a terminal, or a line per 10 % with --progress; --quiet silences it.\n"
"\n"
"options:\n",
options,
"\n"
"exit status: 0 ok, 64 usage, 65 bad input, 66 missing input, 70 numerical\n"
"failure, 74 I/O error.\n"
"\n"
"example (6 h of a gyro at 1 kHz, 3-sigma of 100-s means, octave ADEV):\n"
"  igea stability --data gyro_x.npy --fs 1000 --block 100\n"
"  igea stability --data acc.txt --fs 10 --kind modified --json --out acc_stability.json\n"
"  igea stability --data clock_phase.txt --fs 1 --phase --kind tdev --spacing decade\n"
"  igea stability --data gyro_x.npy --fs 1000 --kind adev --fit\n"
"  igea stability --data clock_with_gaps.txt --fs 1 --phase --kind oadev --gaps\n"};

/* Kinds whose curve is an Allan variance (the IEEE 952 model's). */
static int fit_kind(int k)
{
    return k == IGEA_STABILITY_ALLAN_OVERLAPPING || k == IGEA_STABILITY_ALLAN_NONOVERLAPPING ||
           k == IGEA_STABILITY_ALLAN_ADEV || k == IGEA_STABILITY_ALLAN_OADEV ||
           k == IGEA_STABILITY_ALLAN_TOTDEV;
}

/* Kinds with an interval (all but MTIE and TIERMS). */
static int has_ci(int k) { return k != IGEA_STABILITY_ALLAN_MTIE && k != IGEA_STABILITY_ALLAN_TIERMS; }

static int parse(int argc, char **argv, st_args *a)
{
    int ec = cli_parse(&command, argc, argv);
    *a = A;
    if (ec)
        return ec;
    return cli_usage(!a->file || !(a->fs > 0)
                         ? "stability: --data FILE and --fs (> 0) are required (see igea stability --help)"
                     : a->column < 0 ? "stability: --column counts from 0"
                     : !(a->conf > 0 && a->conf < 1) ? "stability: --conf must lie in (0, 1)"
                     : a->phase && a->kind <= IGEA_STABILITY_ALLAN_NONOVERLAPPING
                         ? "stability: --phase needs a Stable32 kind (adev, oadev, mdev, ...); "
                           "overlapping, modified and nonoverlapping take rate data"
                     : a->boot < 0 || a->boot == 1 || a->boot > 1000000
                         ? "stability: --boot is 0 or 2 .. 1000000"
                     : a->seed < 0 ? "stability: --seed must be >= 0"
                     : a->fit && !fit_kind(a->kind)
                         ? "stability: --fit needs an Allan-variance kind (overlapping, "
                           "nonoverlapping, adev, oadev, totdev)"
                         : NULL);
}

static void num_or_dash(FILE *f, double v)
{
    if (isnan(v))
        fprintf(f, "%14s", "-");
    else
        fprintf(f, "%14.6e", v);
}

/* The file's reader (NaN a gap with --gaps) and the record's column. */
static int open_record(const st_args *a, cli_reader **r)
{
    int ec = a->gaps ? cli_reader_open_gaps(a->file, r) : cli_reader_open(a->file, r);
    if (ec)
        return ec;
    int cols = cli_reader_cols(*r);
    if (cols > 1 && !a->column_given) {
        cli_error("%s: %d columns; pick the record with --column K (0 to %d)", a->file, cols,
                  cols - 1);
        ec = CLI_USAGE;
    } else if (a->column >= cols) {
        cli_error("%s: has %d column(s), --column %d", a->file, cols, a->column);
        ec = CLI_USAGE;
    }
    if (ec) {
        cli_reader_close(*r);
        *r = NULL;
    }
    return ec;
}

/* The next rows of the record's column into y (at most ROWS): *got, 0 at
 * the end. buf holds ROWS rows of the file. */
enum { ROWS = 8192 };
static int next_rows(const st_args *a, cli_reader *r, double *buf, double *y, long *got)
{
    int ec = cli_reader_next(r, ROWS, buf, got);
    if (ec)
        return ec;
    int cols = cli_reader_cols(r);
    for (long k = 0; k < *got; k++)
        y[k] = buf[(size_t)k * cols + a->column];
    return CLI_OK;
}

/* The whole record (the kinds that need it): *y, *n >= 2 samples. The
 * record alone is held: a .npy file's rows are known in advance (one array
 * of their number); a text file's array grows by doubling (the untouched
 * part of a large allocation is not resident) and is cut to the rows read. */
static int read_record(const st_args *a, double **y, int *n)
{
    cli_reader *r = NULL;
    int ec = open_record(a, &r);
    if (ec)
        return ec;
    long known = cli_reader_rows_known(r);
    long cap = known >= 2 && known <= 2147483647L ? known + ROWS : 0, rows = 0, got = 0;
    double *buf = malloc(sizeof(double) * ROWS * (size_t)cli_reader_cols(r)), *v = NULL;
    if (!buf || (cap && !(v = malloc(sizeof(double) * (size_t)cap))))
        ec = cli_oom("the record");
    while (!ec) {
        if (rows + ROWS > cap) {
            long nc = cap ? 2 * cap : 4 * ROWS;
            double *nv = nc <= 2147483647L + (long)ROWS ? realloc(v, sizeof(double) * (size_t)nc) : NULL;
            if (!nv) {
                ec = cli_oom("the record");
                break;
            }
            v = nv;
            cap = nc;
        }
        if ((ec = next_rows(a, r, buf, v + rows, &got)) || got == 0)
            break;
        rows += got;
    }
    if (!ec && (rows < 2 || rows > 2147483647L)) {
        cli_error("%s: needs at least 2 samples", a->file);
        ec = CLI_DATAERR;
    }
    free(buf);
    cli_reader_close(r);
    if (ec) {
        free(v);
        return ec;
    }
    if (rows < cap) { /* the unused tail returned */
        double *nv = realloc(v, sizeof(double) * (size_t)rows);
        if (nv)
            v = nv;
    }
    *y = v;
    *n = (int)rows;
    return CLI_OK;
}

/* The averaging times: --taus, or the octaves of the record. */
static int read_taus(const st_args *a, int n, int kind, double **tau, int *ntau)
{
    if (a->taus) {
        long cnt = 0;
        int ec = cli_read_vector(a->taus, -1, "the averaging times", tau, &cnt);
        *ntau = (int)cnt;
        return ec;
    }
    int cap = a->spacing == IGEA_STABILITY_TAUS_ALL ? n + 1 : 64;
    if (!(*tau = malloc(sizeof(double) * (size_t)cap)))
        return cli_oom("the averaging times");
    if (kind <= IGEA_STABILITY_ALLAN_NONOVERLAPPING)
        return cli_status(igea_stability_octave_taus(n, a->fs, kind, 64, *tau, ntau), "stability");
    return cli_status(igea_stability_taus(n, a->fs, a->phase, kind, a->spacing, cap, *tau, ntau),
                      "stability");
}

typedef struct {
    int n, ntau, have_block, have_fit;
    long gaps; /* NaN samples (--gaps) */
    double *tau, *dev, *lo, *hi, *edf;
    int *cnt, *alpha;
    double blk[IGEA_STABILITY_BLOCK_LEN], fit[IGEA_STABILITY_FIT_LEN], fit_se[IGEA_STABILITY_FIT_LEN];
    int fit_sup[IGEA_STABILITY_FIT_LEN];
    double fit_lo[IGEA_STABILITY_FIT_LEN], fit_hi[IGEA_STABILITY_FIT_LEN]; /* --boot interval */
    int have_boot;
    double fit_chi2;
} st_result;

/* the IEEE 952 terms in IGEA_STABILITY_FIT_* order */
static const char *const fit_keys[IGEA_STABILITY_FIT_LEN] = {
    "quantization", "random_walk", "bias_instability", "rate_random_walk", "rate_ramp"};

/* A fitted term, NaN (null, '-') when not supported. */
static double term_or_nan(const st_result *r, int k)
{
    return r->have_fit && r->fit_sup[k] ? r->fit[k] : NAN;
}

static void json_report(FILE *f, const st_args *a, const st_result *r)
{
    const double *b = r->blk;
    cli_json j;
    cli_json_begin(&j, f);
    cli_jint(&j, "samples", r->n);
    cli_jnum(&j, "fs", a->fs);
    if (r->have_block) {
        cli_json_open(&j, "block", '{');
        cli_jnum(&j, "seconds", b[IGEA_STABILITY_BLOCK_NSAMP] / a->fs);
        cli_jnum(&j, "three_sigma", b[IGEA_STABILITY_BLOCK_3SIGMA]);
        cli_jnum(&j, "sigma", b[IGEA_STABILITY_BLOCK_SIGMA]);
        cli_jint(&j, "nblock", (long)b[IGEA_STABILITY_BLOCK_NBLOCK]);
        cli_jnum(&j, "mean", b[IGEA_STABILITY_BLOCK_MEAN]);
        cli_jnum(&j, "adev", b[IGEA_STABILITY_BLOCK_ADEV]);
        cli_json_close(&j);
    } else {
        cli_jstr(&j, "block", NULL);
    }
    int ci = has_ci(a->kind), legacy = a->kind <= IGEA_STABILITY_ALLAN_NONOVERLAPPING;
    cli_jstr(&j, "kind", igea_choice_name(IGEA_CHOICE_STABILITY_KIND, a->kind));
    cli_jstr(&j, "data_type", a->phase ? "phase" : "freq");
    cli_jnum(&j, "conf", a->conf);
    cli_jnums(&j, "taus", r->tau, r->ntau);
    cli_jnums(&j, "dev", r->dev, r->ntau);
    if (ci) {
        cli_jnums(&j, "lo", r->lo, r->ntau);
        cli_jnums(&j, "hi", r->hi, r->ntau);
        cli_jnums(&j, "edf", r->edf, r->ntau);
    } else {
        cli_jstr(&j, "lo", NULL);
        cli_jstr(&j, "hi", NULL);
        cli_jstr(&j, "edf", NULL);
    }
    if (legacy)
        cli_jstr(&j, "alpha", NULL);
    else
        cli_jints(&j, "alpha", r->alpha, r->ntau);
    cli_jints(&j, "count", r->cnt, r->ntau);
    cli_json_open(&j, "noise", '{');
    for (int k = 0; k < IGEA_STABILITY_FIT_LEN; k++)
        cli_jnum(&j, fit_keys[k], term_or_nan(r, k));
    cli_json_close(&j);
    if (r->have_fit) {
        cli_json_open(&j, "fit", '{');
        cli_jstrs(&j, "terms", fit_keys, IGEA_STABILITY_FIT_LEN);
        cli_jnums(&j, "value", r->fit, IGEA_STABILITY_FIT_LEN);
        cli_jnums(&j, "se", r->fit_se, IGEA_STABILITY_FIT_LEN);
        cli_jbools(&j, "supported", r->fit_sup, IGEA_STABILITY_FIT_LEN);
        cli_jnum(&j, "chi2", r->fit_chi2);
        cli_jint(&j, "boot", r->have_boot ? a->boot : 0);
        if (r->have_boot) {
            cli_jnums(&j, "lo", r->fit_lo, IGEA_STABILITY_FIT_LEN);
            cli_jnums(&j, "hi", r->fit_hi, IGEA_STABILITY_FIT_LEN);
        }
        cli_json_close(&j);
    } else {
        cli_jstr(&j, "fit", NULL);
    }
    cli_json_end(&j);
}

static void text_report(FILE *f, const st_args *a, const st_result *r)
{
    const double *b = r->blk;
    fprintf(f, "%s: %d samples at %g Hz (%.6g s)\n", a->file, r->n, a->fs, r->n / a->fs);
    if (r->have_block)
        fprintf(f, "%g-s blocks: 3 sigma = %.6e (sigma %.6e of %d block means; mean "
                   "%.12g; Allan deviation at %g s %.6e)\n",
                b[IGEA_STABILITY_BLOCK_NSAMP] / a->fs, b[IGEA_STABILITY_BLOCK_3SIGMA],
                b[IGEA_STABILITY_BLOCK_SIGMA], (int)b[IGEA_STABILITY_BLOCK_NBLOCK],
                b[IGEA_STABILITY_BLOCK_MEAN], b[IGEA_STABILITY_BLOCK_NSAMP] / a->fs,
                b[IGEA_STABILITY_BLOCK_ADEV]);
    else if (r->gaps)
        fprintf(f, "%g-s blocks: not computed (the record holds gaps)\n", a->block);
    else
        fprintf(f, "%g-s blocks: the record holds fewer than 2 blocks\n", a->block);
    if (r->gaps)
        fprintf(f, "gaps: %ld samples are NaN; the terms that hold one are left out (terms)\n",
                r->gaps);
    int ci = has_ci(a->kind), legacy = a->kind <= IGEA_STABILITY_ALLAN_NONOVERLAPPING;
    const char *kn = igea_choice_name(IGEA_CHOICE_STABILITY_KIND, a->kind);
    if (legacy)
        fprintf(f, "\n%s Allan deviation, %.1f %% intervals\n", kn, 100 * a->conf);
    else
        fprintf(f, "\n%s of %s data, %.1f %% intervals\n", kn, a->phase ? "phase" : "frequency",
                100 * a->conf);
    fprintf(f, "%12s %14s %14s %14s %9s %10s%s\n", "tau (s)", "deviation", "low", "high", "edf",
            "terms", legacy ? "" : "  alpha");
    for (int j = 0; j < r->ntau; j++) {
        fprintf(f, "%12.6g %14.6e", r->tau[j], r->dev[j]);
        if (ci)
            fprintf(f, " %14.6e %14.6e %9.1f", r->lo[j], r->hi[j], r->edf[j]);
        else
            fprintf(f, " %14s %14s %9s", "-", "-", "-");
        fprintf(f, " %10d", r->cnt[j]);
        if (!legacy)
            fprintf(f, "  %5d", r->alpha[j]);
        fprintf(f, "\n");
    }
    if (!r->have_fit)
        return;
    fprintf(f, "\nnoise terms, IEEE Std 952 fit (units of the data; '-': not supported)\n");
    static const char *label[IGEA_STABILITY_FIT_LEN] = {
        "quantisation Q (x s)", "random walk N (x sqrt s)", "bias instability B",
        "rate random walk K (/ sqrt s)", "rate ramp R (/ s)"};
    for (int k = 0; k < IGEA_STABILITY_FIT_LEN; k++) {
        fprintf(f, "  %-30s", label[k]);
        num_or_dash(f, term_or_nan(r, k));
        if (a->fit)
            fprintf(f, "   fit %.6e +- %.3e", r->fit[k], r->fit_se[k]);
        if (r->have_boot)
            fprintf(f, "  [%.3e, %.3e]", r->fit_lo[k], r->fit_hi[k]);
        fprintf(f, "\n");
    }
}

/* igea_stability_block's argument 4 (the block length) is refused when the
 * record holds fewer than 2 blocks: reported, not an error. */
#define BLOCK_ARG_LENGTH (-4)
/* igea_stability_allan's argument 5, igea_stability_dev's 6: a tau out of
 * the record's range. */
#define ALLAN_ARG_TAUS (-5)
#define DEV_ARG_TAUS (-6)

/* The IEEE 952 fit of the curve (kinds of fit_kind, >= 5 taus). */
static int fit_curve(const st_args *a, st_result *r)
{
    r->have_fit = 0;
    if (!fit_kind(a->kind) || r->ntau < 5)
        return CLI_OK;
    /* --fit: the standard errors by the bootstrap (on the rate samples
     * behind phase data) */
    int n = a->phase ? r->n - 1 : r->n;
    int st = a->fit && a->boot > 0 && n >= 2
                 ? igea_stability_fit_boot(n, a->fs, a->kind, r->ntau, r->tau, r->dev, r->edf,
                                           a->boot, a->seed, a->conf, r->fit, r->fit_se,
                                           r->fit_lo, r->fit_hi, r->fit_sup, &r->fit_chi2)
                 : igea_stability_fit(r->ntau, r->tau, r->dev, r->edf, r->fit, r->fit_se,
                                      r->fit_sup, &r->fit_chi2);
    if (st)
        return cli_status(st, "stability: IEEE 952 fit");
    r->have_fit = 1;
    r->have_boot = a->fit && a->boot > 0 && n >= 2;
    return CLI_OK;
}

/* The deviations at taus j0 .. j0 + nt - 1. */
static int deviations(const st_args *a, const double *y, st_result *r, int j0, int nt)
{
    int kind = a->kind, ci = has_ci(kind);
    if (kind <= IGEA_STABILITY_ALLAN_NONOVERLAPPING)
        return igea_stability_allan(r->n, y, a->fs, nt, r->tau + j0, kind, a->noise, a->conf,
                                    r->dev + j0, r->lo + j0, r->hi + j0, r->edf + j0,
                                    r->cnt + j0);
    return igea_stability_dev(r->n, y, a->fs, a->phase, nt, r->tau + j0, kind, a->noise, a->conf,
                              r->dev + j0, ci ? r->lo + j0 : NULL, ci ? r->hi + j0 : NULL,
                              ci ? r->edf + j0 : NULL, r->alpha + j0, r->cnt + j0, r->tau + j0);
}

/* With progress shown, the taus from j on computed in one call: one, or for
 * the rate-data kinds with the noise type identified (auto) also the taus
 * after it with fewer than 32 tau-averages, which keep the type of the tau
 * before them (igea/stability.h): the same numbers as one call for all. */
static int group(const st_args *a, const st_result *r, int j)
{
    int nt = 1;
    if (a->kind > IGEA_STABILITY_ALLAN_NONOVERLAPPING || a->noise != IGEA_STABILITY_NOISE_AUTO)
        return nt;
    for (; j + nt < r->ntau; nt++) {
        double m = floor(r->tau[j + nt] * a->fs + 0.5);
        if (!(m >= 1) || floor(r->n / m) >= 32)
            break;
    }
    return nt;
}

static const char *const kind_gaps =
    "the gap-resistant kinds are adev oadev mdev tdev hdev ohdev";

/* A tau out of the record's range (igea_stability_allan's argument 5,
 * igea_stability_dev's 6, a stream's IGEA_EEMPTY). */
static int tau_range_error(void)
{
    cli_error("stability: a tau is shorter than 1 sample or too long for the record (theo1, "
              "theobr: tau = 0.75 m / fs, m even)");
    return CLI_DATAERR;
}

static int compute(const st_args *a, const double *y, st_result *r)
{
    int kind = a->kind, st = 0;
    for (int i = 0; i < r->n; i++)
        r->gaps += isnan(y[i]) != 0;
    if (r->gaps && !(kind >= IGEA_STABILITY_ALLAN_ADEV && kind <= IGEA_STABILITY_ALLAN_OHDEV)) {
        cli_error("%s: %ld gaps (NaN): --kind %s takes no gaps; %s", a->file, r->gaps,
                  igea_choice_name(IGEA_CHOICE_STABILITY_KIND, kind), kind_gaps);
        return CLI_DATAERR;
    }
    if (r->gaps == r->n) {
        cli_error("%s: every sample is a gap (NaN)", a->file);
        return CLI_DATAERR;
    }
    if (!r->gaps) { /* the block statistic takes no gaps: not computed then */
        st = igea_stability_block(r->n, y, a->fs, a->block, r->blk);
        r->have_block = st == 0;
        if (st && st != BLOCK_ARG_LENGTH)
            return cli_status(st, "stability: block statistic");
    }
    /* the taus on the sample grid, as the library uses them (a tau off
     * the record's range is left for igea_stability_allan to refuse) */
    if (kind <= IGEA_STABILITY_ALLAN_NONOVERLAPPING)
        igea_stability_taus_used(a->fs, r->ntau, r->tau, r->tau);
    /* with progress shown, the taus in groups (group()) */
    cli_progress pr;
    int ec = cli_progress_start(&pr, "stability", "averaging times", r->ntau);
    if (ec)
        return ec;
    st = 0;
    if (!pr.mode || r->ntau < 1)
        st = deviations(a, y, r, 0, r->ntau);
    for (int j = 0, nt; pr.mode && !st && j < r->ntau; j += nt) {
        nt = group(a, r, j);
        if (!(st = deviations(a, y, r, j, nt)))
            cli_progress_update(&pr, j + nt);
    }
    cli_progress_end(&pr);
    if (st == DEV_ARG_TAUS || (st == ALLAN_ARG_TAUS && kind <= IGEA_STABILITY_ALLAN_NONOVERLAPPING))
        return tau_range_error();
    if (st == -1 && (kind == IGEA_STABILITY_ALLAN_THEOBR || kind == IGEA_STABILITY_ALLAN_THEOH)) {
        cli_error("%s: --kind %s needs at least 90 phase points (TheoBR's bias factor)", a->file,
                  igea_choice_name(IGEA_CHOICE_STABILITY_KIND, kind));
        return CLI_DATAERR;
    }
    if (st == IGEA_ENONFINITE && r->gaps) {
        cli_error("%s: a tau whose terms all hold a gap (NaN)", a->file);
        return CLI_DATAERR;
    }
    if (st)
        return cli_status(st, "stability: deviation");
    return fit_curve(a, r);
}

/* The kinds the driver streams: the Allan and Hadamard ones whose noise
 * type needs no whole record (the rate-data kinds identify it in their
 * pass; the Stable32 kinds when it is given), no gaps, no 'all' spacing. */
static int streamed(const st_args *a)
{
    int rate = a->kind <= IGEA_STABILITY_ALLAN_NONOVERLAPPING;
    int pass = a->kind >= IGEA_STABILITY_ALLAN_ADEV && a->kind <= IGEA_STABILITY_ALLAN_OHDEV;
    return !a->gaps && (rate || (pass && a->noise != IGEA_STABILITY_NOISE_AUTO)) &&
           (a->taus || rate || a->spacing != IGEA_STABILITY_TAUS_ALL);
}

/* A .npy file read where it is: the stream reads the values of its long
 * lags back from the file (igea_stability_stream_source, a descriptor of
 * its own in *fd) instead of holding them; otherwise (text, a pipe, a
 * failure to open the file again) it holds them. */
static int stream_source(const st_args *a, cli_reader *rd, igea_stability_stream *h, int *fd)
{
    double data;
    int fortran, cols = cli_reader_cols(rd);
    long rows = cli_reader_rows_known(rd);
    const unsigned short one = 1; /* '<f8' is this machine's double: little-endian */
    if (*(const unsigned char *)&one != 1 || !cli_reader_npy_data(rd, &data, &fortran) || rows < 0)
        return CLI_OK;
    double off = data + 8.0 * a->column * (cols > 1 && fortran ? (double)rows : 1.0);
    long stride = cols > 1 && !fortran ? 8L * cols : 8L;
    if (stride > 131072)
        return CLI_OK;
    int f;
    do
        f = open(a->file, O_RDONLY | O_CLOEXEC);
    while (f < 0 && errno == EINTR);
    if (f < 0)
        return CLI_OK;
    int st = igea_stability_stream_source(h, f, off, (int)stride);
    if (st) {
        close(f);
        return st == IGEA_ENOMEM ? cli_oom("the record's windows")
                                 : cli_status(st, "stability: stream");
    }
    *fd = f;
    return CLI_OK;
}

/* A stream's failure st: a value read back from the file that is not the
 * one read before, or cannot be read, is the file's fault. */
static int stream_failed(const st_args *a, int st, const char *what)
{
    if (st != IGEA_EREAD)
        return cli_status(st, what);
    cli_error("%s: a value read back from the file is not the one read before, or cannot be "
              "read (the file changed while it was read?)",
              a->file);
    return CLI_DATAERR;
}

/* The record read in blocks and fed to a stream (igea_stability_stream_*):
 * memory for the longest lag, not for the record (a .npy file: 8 MB and
 * the lags read back, stream_source). */
static int stream_record(const st_args *a, st_result *r)
{
    double *tin = NULL;
    int nin = 0, ec = CLI_OK, st;
    cli_reader *rd = NULL;
    if (a->taus) {
        long cnt = 0;
        if ((ec = cli_read_vector(a->taus, -1, "the averaging times", &tin, &cnt)))
            return ec;
        nin = (int)cnt;
    }
    if ((ec = open_record(a, &rd))) {
        free(tin);
        return ec;
    }
    /* the samples known in advance (.npy): the generated taus exactly, so
     * that the ring holds the longest lag that has a term, not the record */
    long known = cli_reader_rows_known(rd);
    if (!a->taus && known >= 2 && known <= 2147483647L) {
        int cnt = 0;
        if (!(tin = malloc(sizeof(double) * 64))) {
            cli_reader_close(rd);
            return cli_oom("the averaging times");
        }
        st = a->kind <= IGEA_STABILITY_ALLAN_NONOVERLAPPING
                 ? igea_stability_octave_taus((int)known, a->fs, a->kind, 64, tin, &cnt)
                 : igea_stability_taus((int)known, a->fs, a->phase, a->kind, a->spacing, 64, tin,
                                       &cnt);
        if (st || cnt < 1) {
            free(tin);
            tin = NULL;
            cnt = 0;
        }
        nin = cnt;
    }
    int cap = nin > 64 ? nin : 64;
    r->tau = malloc(sizeof(double) * (size_t)cap);
    r->dev = malloc(sizeof(double) * 4 * (size_t)cap);
    r->cnt = malloc(sizeof(int) * 2 * (size_t)cap);
    if (!r->tau || !r->dev || !r->cnt) {
        free(tin);
        cli_reader_close(rd);
        return cli_oom("the deviations");
    }
    r->lo = r->dev + cap, r->hi = r->lo + cap, r->edf = r->hi + cap;
    r->alpha = r->cnt + cap;
    igea_stability_stream *h = NULL;
    double *buf = NULL, *y = NULL;
    int sfd = -1;
    /* a block shorter than half a sample: no block statistic (as the
     * whole-record path, where igea_stability_block refuses it) */
    double blk = a->block * a->fs >= 0.5 ? a->block : 0.0;
    st = igea_stability_stream_create(a->fs, a->phase, a->kind, a->noise, a->conf, nin, tin,
                                      a->spacing, blk, &h);
    free(tin);
    cli_progress pr;
    if (st == -7)
        ec = tau_range_error();
    else if (st)
        ec = cli_status(st, "stability: stream");
    if (!ec)
        ec = stream_source(a, rd, h, &sfd);
    if (ec || (ec = cli_progress_start(&pr, "stability", "samples read", CLI_PROGRESS_UNKNOWN)))
        goto done;
    buf = malloc(sizeof(double) * ROWS * (size_t)cli_reader_cols(rd));
    y = malloc(sizeof(double) * ROWS);
    if (!buf || !y)
        ec = cli_oom("the record");
    double total = 0;
    for (long got = 0; !ec;) {
        if ((ec = next_rows(a, rd, buf, y, &got)) || got == 0)
            break;
        if ((st = igea_stability_stream_feed(h, (int)got, y)))
            ec = stream_failed(a, st, "stability: stream");
        total += (double)got;
        cli_progress_count(&pr, total);
    }
    cli_progress_end(&pr);
    if (!ec && (total < 2 || total > 2147483647.0)) {
        cli_error("%s: needs at least 2 samples", a->file);
        ec = CLI_DATAERR;
    }
    if (!ec) {
        r->n = (int)total;
        st = igea_stability_stream_result(h, cap, &r->ntau, r->tau, r->dev, r->lo, r->hi, r->edf,
                                          r->alpha, r->cnt, r->blk);
        if (st == IGEA_ENONFINITE) {
            cli_error("%s: NaN or Inf in the record", a->file);
            ec = CLI_DATAERR;
        } else if (st == IGEA_EEMPTY) {
            ec = tau_range_error();
        } else if (st) {
            ec = stream_failed(a, st, "stability: deviation");
        }
    }
    if (!ec) {
        r->have_block = r->blk[IGEA_STABILITY_BLOCK_NBLOCK] >= 2;
        ec = fit_curve(a, r);
    }
done:
    free(buf);
    free(y);
    cli_reader_close(rd);
    igea_stability_stream_free(h);
    if (sfd >= 0)
        close(sfd);
    return ec;
}

int cmd_stability(int argc, char **argv)
{
    st_args a;
    int ec = parse(argc, argv, &a);
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    st_result r = {0};
    double *y = NULL;
    if (streamed(&a)) {
        if ((ec = stream_record(&a, &r)))
            goto done;
    } else {
        if ((ec = read_record(&a, &y, &r.n)) || (ec = read_taus(&a, r.n, a.kind, &r.tau,
                                                                &r.ntau)))
            goto done;
        size_t nt = (size_t)(r.ntau > 0 ? r.ntau : 1);
        r.dev = malloc(sizeof(double) * 4 * nt);
        r.cnt = malloc(sizeof(int) * 2 * nt);
        if (!r.dev || !r.cnt) {
            ec = cli_oom("the deviations");
            goto done;
        }
        r.lo = r.dev + r.ntau, r.hi = r.lo + r.ntau, r.edf = r.hi + r.ntau;
        r.alpha = r.cnt + r.ntau;
        if ((ec = compute(&a, y, &r)))
            goto done;
    }
    cli_out o;
    if ((ec = cli_out_open(&o, a.out)))
        goto done;
    int ci = has_ci(a.kind); /* the picture first: on its failure no report */
    if (a.plot && (ec = cli_svg_stability(a.plot, a.file,
                                          igea_choice_name(IGEA_CHOICE_STABILITY_KIND, a.kind),
                                          r.ntau, r.tau, r.dev, ci ? r.lo : NULL, ci ? r.hi : NULL,
                                          a.fit && r.have_fit ? r.fit : NULL, r.fit_sup))) {
        cli_out_abort(&o);
        goto done;
    }
    (a.json ? json_report : text_report)(o.f, &a, &r);
    ec = cli_out_commit(&o);
done:
    free(y);
    free(r.tau);
    free(r.dev);
    free(r.cnt);
    return ec;
}
