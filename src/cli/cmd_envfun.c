/* igea envfun - environment-function matrix S of a trajectory file and a
 * list of error terms (METHODS 5). Also holds the term-name table that the
 * simulate and montecarlo commands share (the library speaks int codes). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

/* ---- term names (docs/envfun.md) ---------------------------------------- */
static const char *const TERM_NAMES[IGEA_ENVFUN_TERM_COUNT] = {
    "acc_bias_x",   "acc_bias_y",   "acc_bias_z",   "acc_scale_x", "acc_scale_y",
    "acc_scale_z",  "acc_sq_x",     "acc_sq_y",     "acc_sq_z",    "acc_mis_xy",
    "acc_mis_xz",   "acc_mis_yx",   "acc_mis_yz",   "acc_mis_zx",  "acc_mis_zy",
    "gyro_bias_x",  "gyro_bias_y",  "gyro_bias_z",  "gyro_g_x",    "gyro_g_y",
    "gyro_g_z",     "gyro_scale_x", "gyro_scale_y", "gyro_scale_z", "att0_x",
    "att0_y",       "att0_z",       "gyro_gi_x",    "gyro_gi_y",   "gyro_gi_z",
    "gyro_gs_x",    "gyro_gs_y",    "gyro_gs_z",    "align0_x",    "align0_y",
    "align0_z"};

#define G0 9.80665
#define DEG_H (3.14159265358979323846 / 180.0 / 3600.0)

/* Default 1-sigma spec of a term code (SI units; docs/envfun.md). */
double envfun_default_spec(int code)
{
    if (code < IGEA_ENVFUN_TERM_ACC_SCALE_X) return 1e-3 * G0;          /* 1 mg */
    if (code < IGEA_ENVFUN_TERM_ACC_SQ_X) return 1e-4;
    if (code < IGEA_ENVFUN_TERM_ACC_MIS_XY) return 1e-5 / G0;           /* 10 ug/g^2 */
    if (code < IGEA_ENVFUN_TERM_GYRO_BIAS_X) return 1e-4;
    if (code < IGEA_ENVFUN_TERM_GYRO_G_X) return 0.5 * DEG_H;           /* 0.5 deg/h */
    if (code < IGEA_ENVFUN_TERM_GYRO_SCALE_X) return 0.5 * DEG_H / G0;  /* 0.5 deg/h/g */
    if (code < IGEA_ENVFUN_TERM_ATT0_X) return 1e-4;
    if (code < IGEA_ENVFUN_TERM_GYRO_GI_X) return 1e-4;                 /* rad */
    if (code < IGEA_ENVFUN_TERM_ALIGN0_X) return 0.5 * DEG_H / G0;
    return 1e-4;
}

const char *envfun_term_name(int code)
{
    return (code >= 0 && code < IGEA_ENVFUN_TERM_COUNT) ? TERM_NAMES[code] : "?";
}

static const char *const SD21[21] = {
    "acc_bias_x", "acc_bias_y", "acc_bias_z", "acc_scale_x", "acc_scale_y", "acc_scale_z",
    "acc_mis_xy", "acc_mis_xz", "acc_mis_yx", "acc_mis_yz", "acc_mis_zx", "acc_mis_zy",
    "gyro_bias_x", "gyro_bias_y", "gyro_bias_z", "gyro_g_x", "gyro_g_y", "gyro_g_z",
    "att0_x", "att0_y", "att0_z"};
static const char *const PF21[21] = {
    "acc_bias_x", "acc_bias_y", "acc_bias_z", "acc_scale_x", "acc_scale_y", "acc_scale_z",
    "gyro_bias_x", "gyro_bias_y", "gyro_bias_z", "gyro_gi_x", "gyro_gi_y", "gyro_gi_z",
    "gyro_gs_x", "gyro_gs_y", "gyro_gs_z", "align0_x", "align0_y", "align0_z",
    "acc_sq_x", "acc_sq_y", "acc_sq_z"};

static int lookup(int system, const char *name, size_t len)
{
    for (int k = 0; k < IGEA_ENVFUN_TERM_COUNT; k++)
        if (strlen(TERM_NAMES[k]) == len && !strncmp(TERM_NAMES[k], name, len) &&
            igea_envfun_term_valid(system, k))
            return k;
    return -1;
}

/* Parse a comma-separated term list ("default" = the 21-term model of the
 * system, "all" = the whole catalogue) into codes (malloc'ed). Returns an
 * exit code; names the unknown term. */
int envfun_parse_terms(int system, const char *list, int **codes, int *n)
{
    int cap = IGEA_ENVFUN_TERM_COUNT + 64, cnt = 0;
    int *c = malloc(sizeof(int) * (size_t)cap);
    if (!c) {
        cli_error("out of memory");
        return CLI_SOFTWARE;
    }
    if (!strcmp(list, "default")) {
        for (int j = 0; j < 21; j++)
            c[cnt++] = lookup(system, system == IGEA_ENVFUN_STRAPDOWN ? SD21[j] : PF21[j],
                              strlen(system == IGEA_ENVFUN_STRAPDOWN ? SD21[j] : PF21[j]));
    } else if (!strcmp(list, "all")) {
        for (int k = 0; k < IGEA_ENVFUN_TERM_COUNT; k++)
            if (igea_envfun_term_valid(system, k))
                c[cnt++] = k;
    } else {
        const char *p = list;
        while (*p) {
            const char *e = strchr(p, ',');
            size_t len = e ? (size_t)(e - p) : strlen(p);
            int k = lookup(system, p, len);
            if (k < 0 || cnt >= cap) {
                cli_error("--terms: '%.*s' is not a %s term (see igea envfun --list)",
                          (int)len, p,
                          system == IGEA_ENVFUN_STRAPDOWN ? "strapdown" : "platform");
                free(c);
                return CLI_USAGE;
            }
            c[cnt++] = k;
            p = e ? e + 1 : p + len;
        }
        if (cnt == 0) {
            cli_error("--terms: empty list");
            free(c);
            return CLI_USAGE;
        }
    }
    *codes = c;
    *n = cnt;
    return CLI_OK;
}

int envfun_parse_system(const char *s, int *system)
{
    if (!strcmp(s, "strapdown")) *system = IGEA_ENVFUN_STRAPDOWN;
    else if (!strcmp(s, "platform")) *system = IGEA_ENVFUN_PLATFORM;
    else {
        cli_error("--system: 'strapdown' or 'platform', not '%s'", s);
        return CLI_USAGE;
    }
    return CLI_OK;
}

/* Read a trajectory file (rows t f3 w3 q4) into a column-major array. */
int envfun_read_traj(const char *path, double **traj, int *nsamp)
{
    cli_matrix m;
    int ec = cli_read_matrix(path, &m);
    if (ec)
        return ec;
    if (m.cols != IGEA_ENVFUN_TRAJ_COLS || m.rows < 2 || m.rows > 100000000L) {
        cli_error("%s: a trajectory has 11 columns (t f_x f_y f_z w_x w_y w_z q0 q1 q2 q3) "
                  "and at least 2 rows; found %ld x %d", path, m.rows, m.cols);
        cli_matrix_free(&m);
        return CLI_DATAERR;
    }
    double *t = malloc(sizeof(double) * (size_t)m.rows * IGEA_ENVFUN_TRAJ_COLS);
    if (!t) {
        cli_matrix_free(&m);
        cli_error("out of memory");
        return CLI_SOFTWARE;
    }
    for (long k = 0; k < m.rows; k++)
        for (int c = 0; c < IGEA_ENVFUN_TRAJ_COLS; c++)
            t[k + (size_t)c * (size_t)m.rows] = m.v[k * IGEA_ENVFUN_TRAJ_COLS + c];
    *nsamp = (int)m.rows;
    *traj = t;
    cli_matrix_free(&m);
    return CLI_OK;
}

/* Header line "# name name ..." of S files. */
char *envfun_header(const int *codes, int n)
{
    size_t len = 2;
    for (int j = 0; j < n; j++)
        len += strlen(envfun_term_name(codes[j])) + 1;
    char *h = malloc(len + 1);
    if (!h)
        return NULL;
    strcpy(h, "");
    for (int j = 0; j < n; j++) {
        if (j)
            strcat(h, " ");
        strcat(h, envfun_term_name(codes[j]));
    }
    return h;
}

/* Epochs every step seconds from t0 + step to the end (inclusive within
 * 1e-9 step), or from a file. */
int envfun_epochs(const char *file, double step, double t0, double t1, double **ep, int *n)
{
    if (file) {
        cli_matrix m;
        int ec = cli_read_matrix(file, &m);
        if (ec)
            return ec;
        *ep = m.v;
        *n = (int)(m.rows * m.cols);
        return CLI_OK;
    }
    if (!(step > 0)) {
        cli_error("--epoch-step must be > 0");
        return CLI_USAGE;
    }
    long cnt = (long)floor((t1 - t0) / step + 1e-9);
    if (cnt < 1 || cnt > 10000000L) {
        cli_error("--epoch-step %g gives %ld epochs in [%g, %g]", step, cnt, t0, t1);
        return CLI_USAGE;
    }
    double *e = malloc(sizeof(double) * (size_t)cnt);
    if (!e) {
        cli_error("out of memory");
        return CLI_SOFTWARE;
    }
    for (long i = 0; i < cnt; i++)
        e[i] = fmin(t0 + (double)(i + 1) * step, t1);
    *ep = e;
    *n = (int)cnt;
    return CLI_OK;
}

/* ---------------------------------------------------------------------- */
static void envfun_help(void)
{
    printf(
"usage: igea envfun TRAJECTORY --terms LIST [options]\n"
"\n"
"Environment-function matrix S of a flight (METHODS 5): column j holds the\n"
"change of the apparent velocity (launch-inertial frame) per unit of error\n"
"coefficient j, at each tracking epoch, rows epoch-major (x, y, z of epoch 1,\n"
"then epoch 2, ...). This is the S that 'igea eqerr' reads.\n"
"\n"
"TRAJECTORY: text or .npy, one row per telemetry sample:\n"
"  t f_x f_y f_z w_x w_y w_z q0 q1 q2 q3\n"
"  (s, m/s^2, rad/s; specific force and rate in body axes for strapdown, force\n"
"  in launch-inertial axes for a platform, whose rate columns are ignored;\n"
"  q the attitude body -> launch-inertial, scalar first).\n"
"Integration is by the trapezoid rule at the telemetry rate (>= 10 Hz\n"
"recommended), then linear interpolation to the epochs.\n"
"\n"
"options:\n"
"  --terms LIST        comma-separated term names, 'default' (the 21-term model)\n"
"                      or 'all'; --list prints the catalogue with default specs\n"
"  --system KIND       strapdown (default) or platform\n"
"  --epochs FILE       epoch times (s), non-decreasing, inside the trajectory\n"
"  --epoch-step DT     or one epoch every DT s after the first sample (default 1)\n"
"  --spec default|FILE multiply the columns by 1-sigma specs (default: raw S)\n"
"  --axes I,I,I,S,S,S  platform gyro input and spin axes (0..2; default\n"
"                      0,1,2,1,2,0)\n"
"  --output KIND       velocity (default), position, velocity_g, position_g\n"
"                      (_g: with the point-mass gravity-gradient coupling)\n"
"  --out FILE          write S there (text with a '# names' header, or .npy)\n"
"  --json              machine-readable summary (with --out) or S as JSON\n"
"\n"
"example:\n"
"  igea simulate --dir flight --save-traj        # writes flight/traj.txt, ...\n"
"  igea envfun flight/traj.txt --terms acc_bias_x,gyro_bias_y,att0_z \\\n"
"      --epoch-step 1 --out S3.txt\n"
"  igea envfun flight/traj.txt --terms default --out S.txt\n");
}

static void list_terms(void)
{
    printf("%-14s %-10s %-12s %s\n", "term", "systems", "default spec", "unit");
    for (int k = 0; k < IGEA_ENVFUN_TERM_COUNT; k++) {
        int sd = igea_envfun_term_valid(IGEA_ENVFUN_STRAPDOWN, k);
        int pf = igea_envfun_term_valid(IGEA_ENVFUN_PLATFORM, k);
        const char *unit = k < IGEA_ENVFUN_TERM_ACC_SCALE_X ? "m/s^2"
                         : k < IGEA_ENVFUN_TERM_ACC_SQ_X ? "-"
                         : k < IGEA_ENVFUN_TERM_ACC_MIS_XY ? "1/(m/s^2)"
                         : k < IGEA_ENVFUN_TERM_GYRO_BIAS_X ? "-"
                         : k < IGEA_ENVFUN_TERM_GYRO_G_X ? "rad/s"
                         : k < IGEA_ENVFUN_TERM_GYRO_SCALE_X ? "rad/s/(m/s^2)"
                         : k < IGEA_ENVFUN_TERM_ATT0_X ? "-"
                         : k < IGEA_ENVFUN_TERM_GYRO_GI_X ? "rad"
                         : k < IGEA_ENVFUN_TERM_ALIGN0_X ? "rad/s/(m/s^2)" : "rad";
        printf("%-14s %-10s %-12.5g %s\n", TERM_NAMES[k],
               sd && pf ? "both" : sd ? "strapdown" : "platform", envfun_default_spec(k), unit);
    }
}

int cmd_envfun(int argc, char **argv)
{
    if (cli_one_stdin(argc, argv))
        return CLI_USAGE;
    const char *traj_path = NULL, *terms = NULL, *epochs_file = NULL, *spec_arg = NULL;
    const char *out = NULL, *v;
    int system = IGEA_ENVFUN_STRAPDOWN, output = IGEA_ENVFUN_VELOCITY, json = 0;
    int axes[6], have_axes = 0, ec;
    double step = 1.0;

    for (int i = 1; i < argc; i++) {
        const char *o = argv[i];
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) { envfun_help(); return CLI_OK; }
        else if (!strcmp(o, "--list")) { list_terms(); return CLI_OK; }
        else if (!strcmp(o, "--json")) json = 1;
        else if (!strcmp(o, "--terms")) { if (!(terms = cli_optarg(argc, argv, &i))) return CLI_USAGE; }
        else if (!strcmp(o, "--epochs")) { if (!(epochs_file = cli_optarg(argc, argv, &i))) return CLI_USAGE; }
        else if (!strcmp(o, "--spec")) { if (!(spec_arg = cli_optarg(argc, argv, &i))) return CLI_USAGE; }
        else if (!strcmp(o, "--out")) { if (!(out = cli_optarg(argc, argv, &i))) return CLI_USAGE; }
        else if (!strcmp(o, "--epoch-step")) {
            if (!(v = cli_optarg(argc, argv, &i))) return CLI_USAGE;
            if ((ec = cli_parse_double("epoch-step", v, &step))) return ec;
        } else if (!strcmp(o, "--system")) {
            if (!(v = cli_optarg(argc, argv, &i))) return CLI_USAGE;
            if ((ec = envfun_parse_system(v, &system))) return ec;
        } else if (!strcmp(o, "--output")) {
            if (!(v = cli_optarg(argc, argv, &i))) return CLI_USAGE;
            if (!strcmp(v, "velocity")) output = IGEA_ENVFUN_VELOCITY;
            else if (!strcmp(v, "position")) output = IGEA_ENVFUN_POSITION;
            else if (!strcmp(v, "velocity_g")) output = IGEA_ENVFUN_VELOCITY_G;
            else if (!strcmp(v, "position_g")) output = IGEA_ENVFUN_POSITION_G;
            else { cli_error("--output: velocity, position, velocity_g or position_g"); return CLI_USAGE; }
        } else if (!strcmp(o, "--axes")) {
            if (!(v = cli_optarg(argc, argv, &i))) return CLI_USAGE;
            if (sscanf(v, "%d,%d,%d,%d,%d,%d", &axes[0], &axes[1], &axes[2], &axes[3],
                       &axes[4], &axes[5]) != 6) {
                cli_error("--axes: six comma-separated axis numbers 0..2");
                return CLI_USAGE;
            }
            have_axes = 1;
        } else if (o[0] == '-' && o[1]) { cli_error("envfun: unknown option %s (see --help)", o); return CLI_USAGE; }
        else if (!traj_path) traj_path = o;
        else { cli_error("envfun: one trajectory file only ('%s')", o); return CLI_USAGE; }
    }
    if (!traj_path || !terms) {
        cli_error("envfun: a trajectory file and --terms are required (see --help)");
        return CLI_USAGE;
    }
    int *codes = NULL, nt = 0, nsamp = 0, nep = 0;
    double *traj = NULL, *ep = NULL, *spec = NULL, *S = NULL, *Srow = NULL;
    char *header = NULL;
    if ((ec = envfun_parse_terms(system, terms, &codes, &nt)))
        return ec;
    if ((ec = envfun_read_traj(traj_path, &traj, &nsamp)))
        goto done;
    if ((ec = envfun_epochs(epochs_file, step, traj[0], traj[nsamp - 1], &ep, &nep)))
        goto done;
    if (spec_arg) {
        spec = malloc(sizeof(double) * (size_t)nt);
        if (!spec) { ec = cli_oom("the term specs"); goto done; }
        if (!strcmp(spec_arg, "default")) {
            for (int j = 0; j < nt; j++)
                spec[j] = envfun_default_spec(codes[j]);
        } else {
            cli_matrix sm;
            if ((ec = cli_read_matrix(spec_arg, &sm)))
                goto done;
            if (sm.rows * sm.cols != nt) {
                cli_error("%s: %ld specs for %d terms", spec_arg, sm.rows * sm.cols, nt);
                cli_matrix_free(&sm);
                ec = CLI_DATAERR;
                goto done;
            }
            memcpy(spec, sm.v, sizeof(double) * (size_t)nt);
            cli_matrix_free(&sm);
        }
    }
    int m = 3 * nep;
    S = malloc(sizeof(double) * (size_t)m * nt);
    Srow = malloc(sizeof(double) * (size_t)m * nt);
    header = envfun_header(codes, nt);
    if (!S || !Srow || !header) { cli_error("out of memory"); ec = CLI_SOFTWARE; goto done; }
    int st = igea_envfun_compute(system, nsamp, traj, nsamp, nt, codes,
                                 have_axes ? axes : NULL, nep, ep, spec, output, S, m);
    if (st == -9) {
        cli_error("envfun: the epochs must be non-decreasing and inside [%g, %g] s",
                  traj[0], traj[nsamp - 1]);
        ec = CLI_DATAERR;
        goto done;
    }
    if (st == -3) {
        cli_error("%s: the time column must be strictly increasing", traj_path);
        ec = CLI_DATAERR;
        goto done;
    }
    if (st == -7) {
        cli_error("--axes: axis numbers are 0, 1, 2");
        ec = CLI_USAGE;
        goto done;
    }
    if ((ec = cli_status(st, "envfun")))
        goto done;
    for (int i = 0; i < m; i++)
        for (int j = 0; j < nt; j++)
            Srow[(size_t)i * nt + j] = S[i + (size_t)j * m];
    if (out) {
        cli_out o;
        if ((ec = cli_out_open(&o, out)))
            goto done;
        cli_write_matrix_body(o.f, o.f != stdout && strlen(out) >= 4 &&
                                       !strcmp(out + strlen(out) - 4, ".npy"),
                              Srow, m, nt, header);
        if (json) {
            printf("{\n  \"rows\": %d,\n  \"terms\": [", m);
            for (int j = 0; j < nt; j++) {
                if (j) fputs(", ", stdout);
                cli_json_str(stdout, envfun_term_name(codes[j]));
            }
            printf("],\n  \"out\": ");
            cli_json_str(stdout, out);
            printf("\n}\n");
        }
        /* the summary first: a run whose summary is lost keeps the old file */
        if (json && (ec = cli_stdout_check())) {
            cli_out_abort(&o);
            goto done;
        }
        if ((ec = cli_out_commit(&o)))
            goto done;
        if (!json)
            fprintf(stderr, "igea envfun: %d epochs x 3 axes, %d terms -> %s\n", nep, nt, out);
    } else if (json) {
        printf("{\n  \"terms\": [");
        for (int j = 0; j < nt; j++) {
            if (j) fputs(", ", stdout);
            cli_json_str(stdout, envfun_term_name(codes[j]));
        }
        printf("],\n  \"S\": [\n");
        for (int i = 0; i < m; i++) {
            fputs("    ", stdout);
            cli_json_array(stdout, Srow + (size_t)i * nt, nt);
            fputs(i + 1 < m ? ",\n" : "\n", stdout);
        }
        printf("  ]\n}\n");
    } else {
        printf("# %s\n", header);
        for (int i = 0; i < m; i++) {
            for (int j = 0; j < nt; j++)
                printf(j ? " %.17g" : "%.17g", Srow[(size_t)i * nt + j]);
            putchar('\n');
        }
    }
done:
    free(codes);
    free(traj);
    free(ep);
    free(spec);
    free(S);
    free(Srow);
    free(header);
    return ec;
}
