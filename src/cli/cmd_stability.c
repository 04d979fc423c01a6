/* igea stability - stability statistics of a static sensor record (METHODS
 * 3.4): the block-mean 3-sigma ("100-second variance"), Allan deviation
 * with confidence intervals, noise terms read from the curve. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static void stability_help(void)
{
    printf(
"usage: igea stability FILE --fs HZ [--column K] [--block S]\n"
"                      [--kind overlapping|modified|nonoverlapping]\n"
"                      [--taus FILE] [--noise auto|wpm|fpm|wfm|ffm|rwfm]\n"
"                      [--conf C] [--json] [--out FILE]\n"
"\n"
"Stability of a static record of one sensor (a gyro's rate, an\n"
"accelerometer's output) sampled at --fs Hz: FILE is text or .npy ('-' for\n"
"standard input), one value per row; a file of several columns needs\n"
"--column K (from 1, as cut -f) to pick the record.\n"
"\n"
"  block statistic  3 sigma of the means of non-overlapping --block-second\n"
"                   blocks (default 100: the seed's 100-second variance), with\n"
"                   the Allan deviation at the block length;\n"
"  Allan deviation  at octave averaging times (or the taus of --taus), of\n"
"                   --kind (default overlapping), with --conf (default 0.683)\n"
"                   intervals from equivalent degrees of freedom (NIST SP 1065;\n"
"                   the noise type per tau from the lag-1 autocorrelation, or\n"
"                   fixed with --noise);\n"
"  noise terms      random walk N (value of the -1/2 line at 1 s), bias\n"
"                   instability B (min / 0.664), rate random walk K (the +1/2\n"
"                   line at 3 s), quantisation Q; '-' where the curve shows no\n"
"                   such slope.\n"
"All sums are compensated and the Allan routines need O(1) extra memory.\n"
"\n"
"exit status: 0 ok, 64 usage, 65 bad input, 66 missing input, 70 numerical\n"
"failure, 74 I/O error.\n"
"\n"
"example (6 h of a gyro at 1 kHz, 3-sigma of 100-s means, octave ADEV):\n"
"  igea stability gyro_x.npy --fs 1000 --block 100\n"
"  igea stability acc.txt --fs 10 --kind modified --json --out acc_stability.json\n");
}

typedef struct {
    const char *file, *taus, *kind, *noise, *out;
    double fs, block, conf;
    int column, column_given, json;
} st_args;

static int parse(int argc, char **argv, st_args *a)
{
    memset(a, 0, sizeof *a);
    a->block = 100.0;
    a->conf = 0.683;
    a->column = 1;
    a->kind = "overlapping";
    a->noise = "auto";
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i], *v;
        int ec;
#define NEED() do { if (!(v = cli_optarg(argc, argv, &i))) return CLI_USAGE; } while (0)
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) {
            stability_help();
            return -1;
        } else if (!strcmp(o, "--fs")) {
            NEED();
            if ((ec = cli_parse_double(o, v, &a->fs)))
                return ec;
        } else if (!strcmp(o, "--block")) {
            NEED();
            if ((ec = cli_parse_double(o, v, &a->block)))
                return ec;
        } else if (!strcmp(o, "--conf")) {
            NEED();
            if ((ec = cli_parse_double(o, v, &a->conf)))
                return ec;
        } else if (!strcmp(o, "--column")) {
            NEED();
            if ((ec = cli_parse_int(o, v, &a->column)))
                return ec;
            a->column_given = 1;
        } else if (!strcmp(o, "--kind")) { NEED(); a->kind = v; }
        else if (!strcmp(o, "--noise")) { NEED(); a->noise = v; }
        else if (!strcmp(o, "--taus")) { NEED(); a->taus = v; }
        else if (!strcmp(o, "--out")) { NEED(); a->out = v; }
        else if (!strcmp(o, "--json")) a->json = 1;
        else if (o[0] == '-' && o[1] != '\0') {
            cli_error("stability: unknown option '%s' (see igea stability --help)", o);
            return CLI_USAGE;
        } else if (!a->file) {
            a->file = o;
        } else {
            cli_error("stability: one input file only ('%s')", o);
            return CLI_USAGE;
        }
#undef NEED
    }
    if (!a->file || !(a->fs > 0)) {
        cli_error("stability: an input FILE and --fs (> 0) are required (see igea stability --help)");
        return CLI_USAGE;
    }
    if (a->column < 1) {
        cli_error("stability: --column counts from 1");
        return CLI_USAGE;
    }
    if (!(a->conf > 0 && a->conf < 1)) {
        cli_error("stability: --conf must lie in (0, 1)");
        return CLI_USAGE;
    }
    return CLI_OK;
}

static int kind_code(const char *k)
{
    if (!strcmp(k, "overlapping")) return IGEA_STABILITY_ALLAN_OVERLAPPING;
    if (!strcmp(k, "modified")) return IGEA_STABILITY_ALLAN_MODIFIED;
    if (!strcmp(k, "nonoverlapping")) return IGEA_STABILITY_ALLAN_NONOVERLAPPING;
    return -100;
}

static int noise_code(const char *k)
{
    static const char *names[] = {"rwfm", "ffm", "wfm", "fpm", "wpm"};
    if (!strcmp(k, "auto"))
        return IGEA_STABILITY_NOISE_AUTO;
    for (int i = 0; i < 5; i++)
        if (!strcmp(k, names[i]))
            return i - 2;
    return -100;
}

static void num_or_dash(FILE *f, double v)
{
    if (isnan(v))
        fprintf(f, "%14s", "-");
    else
        fprintf(f, "%14.6e", v);
}

int cmd_stability(int argc, char **argv)
{
    if (cli_one_stdin(argc, argv))
        return CLI_USAGE;
    st_args a;
    int ec = parse(argc, argv, &a);
    if (ec < 0)
        return CLI_OK;
    if (ec)
        return ec;
    int kind = kind_code(a.kind), noise = noise_code(a.noise);
    if (kind < 0) {
        cli_error("stability: --kind %s: expected overlapping, modified or nonoverlapping", a.kind);
        return CLI_USAGE;
    }
    if (noise == -100) {
        cli_error("stability: --noise %s: expected auto, wpm, fpm, wfm, ffm or rwfm", a.noise);
        return CLI_USAGE;
    }
    cli_matrix m = {0}, tm = {0};
    double *y = NULL, *tau = NULL, *dev = NULL;
    int *cnt = NULL;
    if ((ec = cli_read_matrix(a.file, &m)))
        return ec;
    if (m.cols > 1 && !a.column_given) {
        cli_error("%s: %d columns; pick the record with --column K (1 to %d)", a.file, m.cols,
                  m.cols);
        ec = CLI_USAGE;
        goto done;
    }
    if (a.column > m.cols) {
        cli_error("%s: has %d column(s), --column %d", a.file, m.cols, a.column);
        ec = CLI_USAGE;
        goto done;
    }
    if (m.rows < 2 || m.rows > 2147483647L) {
        cli_error("%s: needs at least 2 samples", a.file);
        ec = CLI_DATAERR;
        goto done;
    }
    int n = (int)m.rows, ntau = 0;
    if (m.cols == 1) {
        y = m.v;
        m.v = NULL;
    } else {
        y = malloc(sizeof(double) * (size_t)n);
        if (!y) {
            ec = cli_oom("the record");
            goto done;
        }
        for (int k = 0; k < n; k++)
            y[k] = m.v[(size_t)k * m.cols + (a.column - 1)];
    }
    cli_matrix_free(&m);
    if (a.taus) {
        if ((ec = cli_read_matrix(a.taus, &tm)))
            goto done;
        ntau = (int)(tm.rows * tm.cols);
        tau = tm.v;
        tm.v = NULL;
    } else {
        tau = malloc(sizeof(double) * 64);
        if (!tau) {
            ec = cli_oom("the averaging times");
            goto done;
        }
        int st = igea_stability_octave_taus(n, a.fs, kind, 64, tau, &ntau);
        if (st) {
            ec = cli_status(st, "stability");
            goto done;
        }
    }
    dev = malloc(sizeof(double) * 4 * (size_t)(ntau > 0 ? ntau : 1));
    cnt = malloc(sizeof(int) * (size_t)(ntau > 0 ? ntau : 1));
    if (!dev || !cnt) {
        ec = cli_oom("the deviations");
        goto done;
    }
    double *lo = dev + ntau, *hi = lo + ntau, *edf = hi + ntau;
    double blk[IGEA_STABILITY_BLOCK_LEN], nid[IGEA_STABILITY_NOISEID_LEN];
    int st = igea_stability_block(n, y, a.fs, a.block, blk), have_block = st == 0;
    if (st && st != -4) {
        ec = cli_status(st, "stability: block statistic");
        goto done;
    }
    st = igea_stability_allan(n, y, a.fs, ntau, tau, kind, noise, a.conf, dev, lo, hi, edf, cnt);
    if (st) {
        ec = cli_status(st, st == -5 ? "stability: a tau is shorter than 1 sample or too long "
                                       "for the record" : "stability: Allan deviation");
        goto done;
    }
    int have_nid = ntau >= 2 && igea_stability_noise_id(ntau, tau, dev, nid) == 0;
    cli_out o;
    if ((ec = cli_out_open(&o, a.out)))
        goto done;
    static const char *nn[4] = {"random_walk", "bias_instability", "rate_random_walk",
                                "quantization"};
    static const int ni[4] = {IGEA_STABILITY_NOISEID_N, IGEA_STABILITY_NOISEID_B, IGEA_STABILITY_NOISEID_K, IGEA_STABILITY_NOISEID_Q};
    for (int j = 0; j < ntau; j++)
        tau[j] = (double)lround(tau[j] * a.fs) / a.fs;
    if (a.json) {
        fprintf(o.f, "{\n  \"samples\": %d,\n  \"fs\": %.17g,\n  \"block\": ", n, a.fs);
        if (have_block) {
            fprintf(o.f, "{\"seconds\": %.17g, \"three_sigma\": %.17g, \"sigma\": %.17g, "
                         "\"nblock\": %d, \"mean\": %.17g, \"adev\": %.17g}",
                    blk[IGEA_STABILITY_BLOCK_NSAMP] / a.fs, blk[IGEA_STABILITY_BLOCK_3SIGMA], blk[IGEA_STABILITY_BLOCK_SIGMA],
                    (int)blk[IGEA_STABILITY_BLOCK_NBLOCK], blk[IGEA_STABILITY_BLOCK_MEAN], blk[IGEA_STABILITY_BLOCK_ADEV]);
        } else {
            fprintf(o.f, "null");
        }
        fprintf(o.f, ",\n  \"kind\": \"%s\",\n  \"conf\": %.17g,\n  \"taus\": ", a.kind, a.conf);
        cli_json_array(o.f, tau, ntau);
        fprintf(o.f, ",\n  \"dev\": ");
        cli_json_array(o.f, dev, ntau);
        fprintf(o.f, ",\n  \"lo\": ");
        cli_json_array(o.f, lo, ntau);
        fprintf(o.f, ",\n  \"hi\": ");
        cli_json_array(o.f, hi, ntau);
        fprintf(o.f, ",\n  \"edf\": ");
        cli_json_array(o.f, edf, ntau);
        fprintf(o.f, ",\n  \"count\": ");
        cli_json_iarray(o.f, cnt, ntau);
        fprintf(o.f, ",\n  \"noise\": {");
        for (int k = 0; k < 4; k++) {
            fprintf(o.f, "%s\"%s\": ", k ? ", " : "", nn[k]);
            cli_json_num(o.f, have_nid ? nid[ni[k]] : NAN);
        }
        fprintf(o.f, "}\n}\n");
    } else {
        fprintf(o.f, "%s: %d samples at %g Hz (%.6g s)\n", a.file, n, a.fs, n / a.fs);
        if (have_block)
            fprintf(o.f, "%g-s blocks: 3 sigma = %.6e (sigma %.6e of %d block means; mean "
                         "%.12g; Allan deviation at %g s %.6e)\n",
                    blk[IGEA_STABILITY_BLOCK_NSAMP] / a.fs, blk[IGEA_STABILITY_BLOCK_3SIGMA], blk[IGEA_STABILITY_BLOCK_SIGMA],
                    (int)blk[IGEA_STABILITY_BLOCK_NBLOCK], blk[IGEA_STABILITY_BLOCK_MEAN],
                    blk[IGEA_STABILITY_BLOCK_NSAMP] / a.fs, blk[IGEA_STABILITY_BLOCK_ADEV]);
        else
            fprintf(o.f, "%g-s blocks: the record holds fewer than 2 blocks\n", a.block);
        fprintf(o.f, "\n%s Allan deviation, %.1f %% intervals\n", a.kind, 100 * a.conf);
        fprintf(o.f, "%12s %14s %14s %14s %9s %10s\n", "tau (s)", "deviation", "low", "high",
                "edf", "terms");
        for (int j = 0; j < ntau; j++)
            fprintf(o.f, "%12.6g %14.6e %14.6e %14.6e %9.1f %10d\n", tau[j], dev[j], lo[j],
                    hi[j], edf[j], cnt[j]);
        if (have_nid) {
            fprintf(o.f, "\nnoise terms (units of the data; '-': no such slope)\n");
            static const char *label[4] = {"random walk N (at 1 s)", "bias instability B",
                                           "rate random walk K (at 3 s)", "quantisation Q"};
            for (int k = 0; k < 4; k++) {
                fprintf(o.f, "  %-28s", label[k]);
                num_or_dash(o.f, nid[ni[k]]);
                fprintf(o.f, "\n");
            }
        }
    }
    ec = cli_out_commit(&o);
done:
    cli_matrix_free(&m);
    cli_matrix_free(&tm);
    free(y);
    free(tau);
    free(dev);
    free(cnt);
    return ec;
}
