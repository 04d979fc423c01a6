/* igea triad - turntable-free calibration of an IMU's accelerometer and
 * gyroscope triads from a raw record of static attitudes and the rotations
 * between them (docs/calibration.md). */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

typedef struct {
    const char *acc, *gyro, *out, *calibrated;
    double acc_scale, gyro_scale;
    double opts[IGEA_TRIAD_OPT_LEN];
    int json, lat_given, rate_given;
} tr_args;

static tr_args A;

static const cli_opt options[] = {
    {"--acc", CLI_OPT_STR, &A.acc, NULL, "FILE", "the accelerometer record: rows t ax ay az", NULL},
    {"--gyro", CLI_OPT_STR, &A.gyro, NULL, "FILE", "the gyro record: rows t gx gy gz at the same\n"
     "instants (omit it for the accelerometer alone)", NULL},
    {"--acc-scale", CLI_OPT_NUM, &A.acc_scale, "1", "K", "nominal accelerometer scale factor: the outputs\n"
     "are multiplied by K (m/s^2 per count) first", NULL},
    {"--gyro-scale", CLI_OPT_NUM, &A.gyro_scale, "1", "K", "nominal gyro scale factor (rad/s per count; for\n"
     "deg/s 0.017453292519943295)", NULL},
    {"--g", CLI_OPT_NUM, &A.opts[IGEA_TRIAD_OPT_G], CLI_DEF_LIB, "G", "local gravity, in the calibrated unit", NULL},
    {"--window", CLI_OPT_NUM, &A.opts[IGEA_TRIAD_OPT_WINDOW], CLI_DEF_LIB, "S", "variance window (s)", NULL},
    {"--init", CLI_OPT_NUM, &A.opts[IGEA_TRIAD_OPT_INIT], CLI_DEF_LIB, "S", "the first static period (s): the noise level", NULL},
    {"--min-static", CLI_OPT_NUM, &A.opts[IGEA_TRIAD_OPT_MIN_STATIC], CLI_DEF_LIB, "S", "shortest static interval used (s)", NULL},
    {"--threshold", CLI_OPT_NUM, &A.opts[IGEA_TRIAD_OPT_THRESHOLD], CLI_DEF_LIB, "K", "static below K x the initial variance (0: scan\n"
     "K = 1..10)", NULL},
    {"--max-iter", CLI_OPT_NUM, &A.opts[IGEA_TRIAD_OPT_MAX_ITER], CLI_DEF_LIB, "N", "Levenberg-Marquardt iterations", NULL},
    {"--lat", CLI_OPT_NUM, &A.opts[IGEA_TRIAD_OPT_LAT], CLI_DEF_LIB, "DEG", "latitude: model the Earth's rate in the gyro fit\n"
     "(its vertical part known, the horizontal part and the\n"
     "heading estimated; for gyros that resolve it)", &A.lat_given},
    {"--earth-rate", CLI_OPT_NUM, &A.opts[IGEA_TRIAD_OPT_EARTH_RATE], CLI_DEF_LIB, "W", "--lat: the Earth's rate in the gyro's unit\n"
     "(default 7.292115e-5 rad/s)", &A.rate_given},
    {"--calibrated", CLI_OPT_STR, &A.calibrated, NULL, "FILE", "also write the compensated record there: rows t\n"
     "ax ay az [gx gy gz] (.npy or text)", NULL},
    CLI_JSON_OPT(&A.json),
    CLI_OUT_OPT(&A.out),
    CLI_END};

static const cli_command command = {"triad",
"usage: igea triad --acc FILE [--gyro FILE] [options]\n"
"\n"
"Calibrates an IMU without a turntable (Tedaldi et al., ICRA 2014): the unit\n"
"is left still for --init seconds, then put in 12 or more (better 20-30)\n"
"different attitudes held a few seconds each, turned by hand between them.\n"
"Static intervals are found by a windowed-variance threshold (scanned, or\n"
"--threshold); the accelerometer's 9 parameters (biases, scale factors,\n"
"non-orthogonality) make |a| = g in every one; the gyro's biases are its\n"
"static mean, its scale factors and 6 misalignments make the rotation\n"
"integrated between consecutive intervals carry one gravity direction onto\n"
"the next. Each with its covariance.\n"
"\n"
"The records: text or .npy, rows t ax ay az and t gx gy gz, sampled\n"
"uniformly at the same instants; raw counts with --acc-scale/--gyro-scale,\n"
"or physical units. The parameters refer to the scaled outputs.\n"
"\n"
"options:\n",
options,
"\n"
"examples:\n"
"  igea triad --acc imu_acc.txt --gyro imu_gyro.txt\n"
"  igea triad --acc acc.npy --gyro gyro.npy --acc-scale 0.000598 --gyro-scale 0.000266 --json --out cal.json\n"
"  igea triad --acc acc.txt --gyro gyro.txt --calibrated compensated.npy\n"
"  igea triad --acc nav_acc.txt --gyro nav_gyro.txt --lat 45.2   # Earth's rate\n"
"\n"
"exit status: 0 ok, 64 usage, 65 bad input (also fewer than 12 static\n"
"intervals, or attitudes or rotations that do not determine the parameters),\n"
"66 missing input, 70 numerical failure (no convergence), 74 output error. A\n"
"misfit above 3 is a warning in the text report, not a failure.\n"};

static int parse(int argc, char **argv, tr_args *a)
{
    igea_triad_defaults(A.opts);
    int ec = cli_parse(&command, argc, argv);
    *a = A;
    if (ec)
        return ec;
    if ((ec = cli_usage(!a->acc ? "triad: --acc FILE is required (see igea triad --help)"
                        : !(a->acc_scale > 0) ? "triad: --acc-scale must be positive"
                        : !(a->gyro_scale > 0) ? "triad: --gyro-scale must be positive"
                        : a->rate_given && !a->lat_given ? "triad: --earth-rate needs --lat"
                        : a->lat_given && !a->gyro ? "triad: --lat needs --gyro" : NULL)))
        return ec;
    if (a->lat_given && !a->rate_given)
        a->opts[IGEA_TRIAD_OPT_EARTH_RATE] = 7.292115e-5; /* rad/s, WGS 84 */
    return cli_check_opts("triad", IGEA_MODULE_TRIAD, igea_triad_check_opts(a->opts));
}

typedef struct {
    int n, nint, has_gyro;
    double fs, *t, *acc, *gyro; /* n; n x 3 row-major each */
    int *start, *end;
    double theta_a[IGEA_TRIAD_NP], cov_a[IGEA_TRIAD_NP * IGEA_TRIAD_NP];
    double info_a[IGEA_TRIAD_INFO_LEN];
    double theta_g[IGEA_TRIAD_GYRO_NP], cov_g[IGEA_TRIAD_GYRO_NP * IGEA_TRIAD_GYRO_NP];
    double info_g[IGEA_TRIAD_GYRO_INFO_LEN];
} tr_run;

/* One record of rows t x y z: the first (the accelerometer's) sets n and
 * t, a second must have the same instants; the outputs times scale. */
static int read_record(const char *path, double scale, tr_run *r, int first)
{
    cli_matrix in = {0};
    int ec = cli_read_matrix(path, &in);
    if (ec)
        return ec;
    if (in.cols != 4)
        cli_error("%s: %d column(s); expected t x y z per row", path, in.cols), ec = CLI_DATAERR;
    else if (in.rows < 3 || in.rows > 100000000L)
        cli_error("%s: %ld rows; expected 3 to 1e8", path, in.rows), ec = CLI_DATAERR;
    else if (!first && in.rows != r->n)
        cli_error("%s: %ld rows, but the accelerometer record has %d", path, in.rows, r->n),
            ec = CLI_DATAERR;
    else if (first && !(r->t = malloc((size_t)in.rows * 7 * sizeof(double))))
        ec = cli_oom("the records");
    if (!ec && first) {
        r->n = (int)in.rows;
        r->acc = r->t + r->n, r->gyro = r->acc + 3 * (size_t)r->n;
    }
    double *out = first ? r->acc : r->gyro;
    for (long i = 0; !ec && i < in.rows; i++) {
        const double *row = in.v + (size_t)i * 4;
        if (first)
            r->t[i] = row[0];
        else if (row[0] != r->t[i]) {
            cli_error("%s: row %ld: t = %.17g, but the accelerometer's is %.17g (the records "
                      "must share their instants)", path, i + 1, row[0], r->t[i]);
            ec = CLI_DATAERR;
        }
        for (int j = 0; j < 3; j++)
            out[3 * i + j] = scale * row[1 + j];
    }
    cli_matrix_free(&in);
    return ec;
}

/* The sampling rate: every step t_{i+1} - t_i within 1 % of the mean step. */
static int sample_rate(const char *path, tr_run *r)
{
    double dt = (r->t[r->n - 1] - r->t[0]) / (r->n - 1);
    if (!(dt > 0 && isfinite(dt))) {
        cli_error("%s: t must increase", path);
        return CLI_DATAERR;
    }
    for (int i = 0; i + 1 < r->n; i++) {
        double d = r->t[i + 1] - r->t[i];
        if (!(fabs(d - dt) <= 0.01 * dt)) {
            cli_error("%s: row %d: the step t = %.17g -> %.17g is not the mean step %.6g s "
                      "(within 1 %%): the record must be sampled uniformly", path, i + 2,
                      r->t[i], r->t[i + 1], dt);
            return CLI_DATAERR;
        }
    }
    r->fs = 1.0 / dt;
    return CLI_OK;
}

static int compute(const tr_args *a, tr_run *r)
{
    int st;
    if (r->has_gyro)
        st = igea_triad_calibrate_imu(IGEA_ROWMAJOR, r->n, r->acc, 3, r->gyro, 3, r->fs, a->opts,
                                      r->theta_a, r->cov_a, IGEA_TRIAD_NP, r->theta_g, r->cov_g,
                                      IGEA_TRIAD_GYRO_NP, r->info_a, r->info_g);
    else
        st = igea_triad_calibrate(IGEA_ROWMAJOR, r->n, r->acc, 3, r->fs, a->opts, r->theta_a,
                                  r->cov_a, IGEA_TRIAD_NP, r->info_a);
    if (st == IGEA_EEMPTY)
        cli_error("triad: fewer than 12 static intervals at %s (or the record is shorter "
                  "than --init, or intervals of one sample): see --threshold, --window, "
                  "--min-static", a->opts[IGEA_TRIAD_OPT_THRESHOLD] > 0 ? "this --threshold"
                                                                : "every threshold 1..10");
    if (st)
        return st == IGEA_EEMPTY ? CLI_DATAERR : cli_status(st, "triad");
    /* the static intervals at the threshold chosen, for the report */
    double thr = r->info_a[IGEA_TRIAD_INFO_THRESHOLD], win = a->opts[IGEA_TRIAD_OPT_WINDOW];
    double ms = a->opts[IGEA_TRIAD_OPT_MIN_STATIC];
    int nint = (int)r->info_a[IGEA_TRIAD_INFO_INTERVALS];
    if (!(r->start = malloc(2 * (size_t)nint * sizeof(int))))
        return cli_oom("the static intervals");
    r->end = r->start + nint;
    st = igea_triad_static(IGEA_ROWMAJOR, r->n, r->acc, 3, r->fs, win, thr, ms, nint, &r->nint,
                           r->start, r->end, NULL);
    r->nint = r->nint < nint ? r->nint : nint;
    return cli_status(st, "triad");
}

/* The compensated record: t, calibrated acc [and gyro] per row. */
static int write_calibrated(const tr_args *a, tr_run *r)
{
    int cols = r->has_gyro ? 7 : 4, st;
    double *c = malloc((size_t)r->n * (size_t)cols * sizeof(double));
    if (!c)
        return cli_oom("the compensated record");
    for (int i = 0; i < r->n; i++)
        c[(size_t)i * cols] = r->t[i];
    st = igea_triad_apply(IGEA_ROWMAJOR, r->n, r->acc, 3, r->theta_a, c + 1, cols);
    if (!st && r->has_gyro)
        st = igea_triad_gyro_apply(IGEA_ROWMAJOR, r->n, r->gyro, 3, r->theta_g, c + 4, cols);
    int ec = cli_status(st, "triad --calibrated");
    if (!ec)
        ec = cli_write_matrix(a->calibrated, c, r->n, cols,
                              r->has_gyro ? "t ax ay az gx gy gz" : "t ax ay az");
    free(c);
    return ec;
}

static const char *const acc_names[IGEA_TRIAD_NP] = {"b_x", "b_y", "b_z", "k_x", "k_y",
                                                     "k_z", "t_yx", "t_zx", "t_zy"};
static const char *const gyro_names[IGEA_TRIAD_GYRO_NP] = {
    "b_x", "b_y", "b_z", "k_x", "k_y", "k_z", "m_xy", "m_xz", "m_yx", "m_yz", "m_zx", "m_zy"};

static void json_params(cli_json *j, int np, const double *theta, const double *cov)
{
    double sd[IGEA_TRIAD_GYRO_NP];
    for (int i = 0; i < np; i++)
        sd[i] = sqrt(cov[i + (size_t)np * i]);
    cli_jnums(j, "theta", theta, np);
    cli_jmatrix(j, "covariance", cov, NULL, np, np, 1, np);
    cli_jnums(j, "sd", sd, np);
}

static void json_report(FILE *f, const tr_args *a, const tr_run *r)
{
    cli_json j;
    const double *ia = r->info_a, *ig = r->info_g;
    cli_json_begin(&j, f);
    json_params(&j, IGEA_TRIAD_NP, r->theta_a, r->cov_a);
    cli_jnum(&j, "k", ia[IGEA_TRIAD_INFO_K]);
    cli_jnum(&j, "threshold", ia[IGEA_TRIAD_INFO_THRESHOLD]);
    cli_jint(&j, "intervals", (long)ia[IGEA_TRIAD_INFO_INTERVALS]);
    cli_jnum(&j, "rms_before", ia[IGEA_TRIAD_INFO_RMS_BEFORE]);
    cli_jnum(&j, "rms_after", ia[IGEA_TRIAD_INFO_RMS_AFTER]);
    cli_jnum(&j, "sigma", ia[IGEA_TRIAD_INFO_SIGMA]);
    cli_jint(&j, "iterations", (long)ia[IGEA_TRIAD_INFO_ITERATIONS]);
    cli_jnum(&j, "misfit", ia[IGEA_TRIAD_INFO_MISFIT]);
    cli_json_open(&j, "static_intervals", '[');
    for (int k = 0; k < r->nint; k++) {
        int se[2] = {r->start[k], r->end[k]};
        cli_jints(&j, NULL, se, 2);
    }
    cli_json_close(&j);
    if (r->has_gyro) {
        cli_json_open(&j, "gyro", '{');
        json_params(&j, IGEA_TRIAD_GYRO_NP, r->theta_g, r->cov_g);
        cli_jint(&j, "pairs", (long)ig[IGEA_TRIAD_GYRO_INFO_PAIRS]);
        cli_jnum(&j, "rms_before", ig[IGEA_TRIAD_GYRO_INFO_RMS_BEFORE]);
        cli_jnum(&j, "rms_after", ig[IGEA_TRIAD_GYRO_INFO_RMS_AFTER]);
        cli_jnum(&j, "sigma", ig[IGEA_TRIAD_GYRO_INFO_SIGMA]);
        cli_jint(&j, "iterations", (long)ig[IGEA_TRIAD_GYRO_INFO_ITERATIONS]);
        cli_jint(&j, "static_samples", (long)ig[IGEA_TRIAD_GYRO_INFO_STATIC_SAMPLES]);
        cli_jnums(&j, "noise", ig + IGEA_TRIAD_GYRO_INFO_NOISE_X, 3);
        cli_jnum(&j, "misfit", ig[IGEA_TRIAD_GYRO_INFO_MISFIT]);
        if (a->opts[IGEA_TRIAD_OPT_EARTH_RATE] > 0) {
            cli_jnum(&j, "lat", a->opts[IGEA_TRIAD_OPT_LAT]);
            cli_jnum(&j, "earth_rate", a->opts[IGEA_TRIAD_OPT_EARTH_RATE]);
            cli_jnum(&j, "earth_h", ig[IGEA_TRIAD_GYRO_INFO_EARTH_H]);
            cli_jnum(&j, "earth_h_sd", ig[IGEA_TRIAD_GYRO_INFO_EARTH_H_SD]);
            cli_jnum(&j, "heading", ig[IGEA_TRIAD_GYRO_INFO_HEADING]);
            cli_jnum(&j, "heading_sd", ig[IGEA_TRIAD_GYRO_INFO_HEADING_SD]);
        } else {
            static const char *const keys[] = {"lat", "earth_rate", "earth_h", "earth_h_sd",
                                               "heading", "heading_sd"};
            for (int k = 0; k < 6; k++)
                cli_jstr(&j, keys[k], NULL);
        }
        cli_json_close(&j);
    } else {
        cli_jstr(&j, "gyro", NULL);
    }
    cli_json_end(&j);
}

static void text_params(FILE *f, int np, const char *const *names, const double *theta,
                        const double *cov)
{
    fprintf(f, "%-6s %18s %12s\n", "param", "estimate", "sd");
    for (int i = 0; i < np; i++)
        fprintf(f, "%-6s %18.10g %12.3e\n", names[i], theta[i], sqrt(cov[i + (size_t)np * i]));
}

/* A misfit well above 1 (3: the residual variance 9 times the noise's). */
static void text_misfit(FILE *f, const char *what, double misfit)
{
    fprintf(f, "%s residual sd / noise-predicted sd: %.3g%s\n", what, misfit,
            misfit > 3.0 ? "  WARNING: the residuals are well above the noise: the static "
                           "intervals\nmay hold motion (see the threshold), or the model does "
                           "not hold; the sds do not cover the errors" : "");
}

static void text_report(FILE *f, const tr_args *a, const tr_run *r)
{
    const double *ia = r->info_a, *ig = r->info_g;
    fprintf(f, "igea triad: %d samples at %.6g Hz; %d static intervals at threshold %g x "
               "zeta_init = %.6g\n", r->n, r->fs, (int)ia[IGEA_TRIAD_INFO_INTERVALS],
            ia[IGEA_TRIAD_INFO_K], ia[IGEA_TRIAD_INFO_THRESHOLD]);
    fprintf(f, "static intervals (samples, from 0):");
    for (int k = 0; k < r->nint; k++)
        fprintf(f, "%s [%d, %d)", k % 6 ? "" : "\n ", r->start[k], r->end[k]);
    fprintf(f, "\n\naccelerometer: a = T K (m - b); rms |a| - g %.3e -> %.3e, sigma %.3e, "
               "%d iterations\n", ia[IGEA_TRIAD_INFO_RMS_BEFORE], ia[IGEA_TRIAD_INFO_RMS_AFTER],
            ia[IGEA_TRIAD_INFO_SIGMA], (int)ia[IGEA_TRIAD_INFO_ITERATIONS]);
    text_params(f, IGEA_TRIAD_NP, acc_names, r->theta_a, r->cov_a);
    text_misfit(f, "accelerometer", ia[IGEA_TRIAD_INFO_MISFIT]);
    if (!r->has_gyro)
        return;
    fprintf(f, "\ngyro: w = M K (r - b); %d rotations, rms gravity-direction mismatch %.3e -> "
               "%.3e rad, sigma %.3e, %d iterations;\nbiases from %d static samples, noise sd "
               "%.3e %.3e %.3e\n", (int)ig[IGEA_TRIAD_GYRO_INFO_PAIRS],
            ig[IGEA_TRIAD_GYRO_INFO_RMS_BEFORE], ig[IGEA_TRIAD_GYRO_INFO_RMS_AFTER],
            ig[IGEA_TRIAD_GYRO_INFO_SIGMA], (int)ig[IGEA_TRIAD_GYRO_INFO_ITERATIONS],
            (int)ig[IGEA_TRIAD_GYRO_INFO_STATIC_SAMPLES], ig[IGEA_TRIAD_GYRO_INFO_NOISE_X],
            ig[IGEA_TRIAD_GYRO_INFO_NOISE_Y], ig[IGEA_TRIAD_GYRO_INFO_NOISE_Z]);
    text_params(f, IGEA_TRIAD_GYRO_NP, gyro_names, r->theta_g, r->cov_g);
    text_misfit(f, "gyro", ig[IGEA_TRIAD_GYRO_INFO_MISFIT]);
    double w = a->opts[IGEA_TRIAD_OPT_EARTH_RATE], lat = a->opts[IGEA_TRIAD_OPT_LAT];
    if (w > 0)
        fprintf(f, "Earth's rate %.6g at latitude %g deg: horizontal part seen %.4e +- %.2e "
                   "(expected %.4e);\nheading of the x axis in the first interval %.3f +- %.3f "
                   "deg\n", w, lat, ig[IGEA_TRIAD_GYRO_INFO_EARTH_H],
                ig[IGEA_TRIAD_GYRO_INFO_EARTH_H_SD], w * cos(lat * 3.14159265358979323846 / 180.0),
                ig[IGEA_TRIAD_GYRO_INFO_HEADING], ig[IGEA_TRIAD_GYRO_INFO_HEADING_SD]);
}

int cmd_triad(int argc, char **argv)
{
    tr_args a;
    int ec = parse(argc, argv, &a);
    if (ec)
        return ec == CLI_HELP ? CLI_OK : ec;
    tr_run r = {0};
    r.has_gyro = a.gyro != NULL;
    cli_out o;
    if (!(ec = read_record(a.acc, a.acc_scale, &r, 1)) &&
        !(ec = r.has_gyro ? read_record(a.gyro, a.gyro_scale, &r, 0) : CLI_OK) &&
        !(ec = sample_rate(a.acc, &r)) && !(ec = compute(&a, &r)) &&
        !(ec = a.calibrated ? write_calibrated(&a, &r) : CLI_OK) &&
        !(ec = cli_out_open(&o, a.out))) {
        (a.json ? json_report : text_report)(o.f, &a, &r);
        ec = cli_out_commit(&o);
    }
    free(r.t);
    free(r.start);
    return ec;
}
