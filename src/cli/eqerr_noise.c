/* igea eqerr with the noise models (--cov, --xcov, --ar, --ar-phi,
 * --groups, --robust, --group-bias): the flight read into memory, one call
 * of igea_noise_eqerr_resid (igea_noise_eqerr_xcov with --xcov); the
 * report is cmd_eqerr.c's, with the noise route's own lines and fields
 * from here. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

typedef struct {
    cli_matrix S, dw, cov, xcov, grp;
    double *Sc, *sig, *spec, *phi;
    int *group, G, m, N;
} noise_in;

static void in_free(noise_in *d)
{
    cli_matrix_free(&d->S);
    cli_matrix_free(&d->dw);
    cli_matrix_free(&d->cov);
    cli_matrix_free(&d->xcov);
    cli_matrix_free(&d->grp);
    free(d->Sc);
    free(d->sig);
    free(d->spec);
    free(d->group);
}

/* The position of a covariance entry named c_ab or ab (a, b of x y z) in
 * the lower-triangle order xx yx yy zx zy zz, or -1 for another name. */
static int cov_entry(const char *name, size_t len)
{
    if (len == 4 && (name[0] == 'c' || name[0] == 'C') && name[1] == '_') {
        name += 2;
        len = 2;
    }
    if (len != 2 || !strchr("xyz", name[0]) || !strchr("xyz", name[1]))
        return -1;
    int a = name[0] - 'x', b = name[1] - 'x';
    int r = a > b ? a : b, c = a > b ? b : a;
    return r * (r + 1) / 2 + c;
}

/* The positions of the six entries named on a '#' line ('# names c_xx ...'
 * as igea writes it, or the names alone); 1 when the line names six
 * covariance entries, else 0. */
static int cov_line(const char *line, int out[6])
{
    int k = 0, pos[6];
    const char *p = line + strspn(line, "# \t");
    if (!strncmp(p, "names", 5) && (p[5] == ' ' || p[5] == '\t'))
        p += 5;
    for (;;) {
        p += strspn(p, " \t,");
        size_t len = strcspn(p, " \t,\r\n");
        if (!len)
            break;
        if (k == 6 || (pos[k++] = cov_entry(p, len)) < 0)
            return 0;
        p += len;
    }
    if (k == 6)
        memcpy(out, pos, sizeof pos);
    return k == 6;
}

/* A --cov file whose header names its columns as covariance entries in
 * another order (igea dw --cov-out writes xx xy xz yy yz zz) is refused:
 * read by position it would swap entries silently. Other names pass. */
static int check_cov_names(const char *path)
{
    size_t lp = strlen(path);
    if (!strcmp(path, "-") || (lp >= 4 && !strcmp(path + lp - 4, ".npy")))
        return CLI_OK; /* stdin is consumed; .npy has no names */
    FILE *f = fopen(path, "r");
    if (!f)
        return CLI_OK; /* a pipe already consumed */
    char *line = NULL;
    size_t cap = 0;
    int pos[6], named = 0;
    while (getline(&line, &cap, f) > 0 && line[strspn(line, " \t")] == '#')
        if (cov_line(line, pos))
            named = 1;
    free(line);
    fclose(f);
    int ok = 1;
    for (int i = 0; i < 6 && named; i++)
        ok = ok && pos[i] == i;
    if (named && !ok) {
        cli_error("%s: its columns are named in another order than --cov reads (c_xx c_yx "
                  "c_yy c_zx c_zy c_zz, the lower triangle by rows)%s", path,
                  pos[1] == 1 && pos[2] == 3 ? ": igea dw --cov-out's file? give --cov the "
                  "file of igea dw --k-out" : "");
        return CLI_DATAERR;
    }
    return CLI_OK;
}

/* The position of a cross-block entry named x_ab (a, b of x y z: row a,
 * column b of X_e) in the row-major order x_xx x_xy .. x_zz, or -1. */
static int xcov_entry(const char *name, size_t len)
{
    if (len != 4 || (name[0] != 'x' && name[0] != 'X') || name[1] != '_' ||
        !strchr("xyz", name[2]) || !strchr("xyz", name[3]))
        return -1;
    return 3 * (name[2] - 'x') + (name[3] - 'x');
}

/* A --xcov file whose header names its nine columns as cross-block
 * entries in another order than igea dw --xcov-out writes (x_xx x_xy x_xz
 * x_yx .. x_zz: X_e row-major, row the axis of dW_e, column that of the
 * later epoch's) is refused: read by position, a transposed X_e would be
 * taken silently. Other names pass (as --cov's). */
static int check_xcov_names(const char *path)
{
    size_t lp = strlen(path);
    if (!strcmp(path, "-") || (lp >= 4 && !strcmp(path + lp - 4, ".npy")))
        return CLI_OK;
    FILE *f = fopen(path, "r");
    if (!f)
        return CLI_OK;
    char *line = NULL;
    size_t cap = 0;
    int pos[9], named = 0, ok = 1;
    while (getline(&line, &cap, f) > 0 && line[strspn(line, " \t")] == '#') {
        const char *p = line + strspn(line, "# \t");
        if (strncmp(p, "names", 5) || (p[5] != ' ' && p[5] != '\t'))
            continue;
        int k = 0, q[9], bad = 0;
        for (p += 5;;) {
            p += strspn(p, " \t,");
            size_t len = strcspn(p, " \t,\r\n");
            if (!len)
                break;
            if (k == 9 || (q[k++] = xcov_entry(p, len)) < 0)
                bad = 1;
            p += len;
        }
        if (!bad && k == 9)
            named = 1, memcpy(pos, q, sizeof q);
    }
    free(line);
    fclose(f);
    for (int i = 0; i < 9 && named; i++)
        ok = ok && pos[i] == i;
    if (!ok) {
        cli_error("%s: its columns are named in another order than --xcov reads (x_xx x_xy x_xz "
                  "x_yx x_yy x_yz x_zx x_zy x_zz: X_e row-major, as igea dw --xcov-out writes)%s",
                  path, pos[1] == 3 ? ": the blocks transposed?" : "");
        return CLI_DATAERR;
    }
    return CLI_OK;
}

/* --ar-phi a,b,c: p = the count, the same lags for every axis. */
int cli_noise_parse_phi(const char *arg, double *phi, int *p)
{
    char *end;
    const char *s = arg;
    int n = 0;
    while (*s && n < 3) {
        double v = strtod(s, &end);
        if (end == s || !isfinite(v))
            break;
        phi[n++] = v;
        s = end;
        if (*s == ',')
            s++;
        else
            break;
    }
    if (n == 0 || *s) {
        cli_error("--ar-phi: expected 1 to 3 comma-separated numbers, got '%s'", arg);
        return CLI_USAGE;
    }
    for (int a = 2; a >= 0; a--)
        for (int k = 0; k < n; k++)
            phi[a * n + k] = phi[k];
    *p = n;
    return CLI_OK;
}

static int read_groups(const char *path, noise_in *d)
{
    int M = d->m / 3, ec = cli_read_matrix(path, &d->grp);
    if (ec)
        return ec;
    if (d->grp.rows * d->grp.cols != M) {
        cli_error("%s: %ld labels, but the flight has %d epochs (one label per epoch)", path,
                  d->grp.rows * d->grp.cols, M);
        return CLI_DATAERR;
    }
    d->group = malloc((size_t)M * sizeof(int));
    if (!d->group)
        return cli_oom("the group labels");
    d->G = 0;
    for (int e = 0; e < M; e++) {
        double v = d->grp.v[e];
        if (!(v >= 0 && v < 64 && v == floor(v))) {
            cli_error("%s: epoch %d: group label %g must be an integer 0..63", path, e, v);
            return CLI_DATAERR;
        }
        d->group[e] = (int)v;
        d->G = d->group[e] + 1 > d->G ? d->group[e] + 1 : d->G;
    }
    for (int g = 0; g < d->G; g++) {
        int n = 0;
        for (int e = 0; e < M && !n; e++)
            n = d->group[e] == g;
        if (!n) {
            cli_error("%s: group %d has no epoch (labels are 0 .. G-1, each used)", path, g);
            return CLI_DATAERR;
        }
    }
    return CLI_OK;
}

static int read_inputs(const cli_noise_args *a, noise_in *d)
{
    int ec = cli_read_matrix(a->S, &d->S);
    if (!ec)
        ec = cli_read_matrix(a->dw, &d->dw);
    if (ec)
        return ec;
    d->m = (int)d->S.rows;
    d->N = d->S.cols;
    if (d->dw.rows * d->dw.cols != d->m || d->m % 3) {
        cli_error("%s: %ld values for the %d rows of %s (epoch-major x, y, z: a multiple of 3)",
                  a->dw, d->dw.rows * d->dw.cols, d->m, a->S);
        return CLI_DATAERR;
    }
    d->Sc = malloc((size_t)d->m * d->N * sizeof(double));
    if (!d->Sc)
        return cli_oom("the environment functions");
    for (int i = 0; i < d->m; i++)
        for (int c = 0; c < d->N; c++)
            d->Sc[i + (size_t)c * d->m] = d->S.v[(size_t)i * d->N + c];
    if (a->cov) {
        if ((ec = cli_read_matrix(a->cov, &d->cov)))
            return ec;
        if (d->cov.cols != 6 || d->cov.rows != d->m / 3) {
            cli_error("%s: %ld rows x %d columns, but --cov needs one line of 6 lower-triangle "
                      "entries (c_xx c_yx c_yy c_zx c_zy c_zz) per epoch (%d epochs)",
                      a->cov, d->cov.rows, d->cov.cols, d->m / 3);
            return CLI_DATAERR;
        }
        if ((ec = check_cov_names(a->cov)))
            return ec;
        if (a->xcov) {
            if ((ec = cli_read_matrix(a->xcov, &d->xcov)))
                return ec;
            if (d->xcov.cols != 9 || d->xcov.rows != d->m / 3) {
                cli_error("%s: %ld rows x %d columns, but --xcov needs one line of the 9 "
                          "entries of X_e (x_xx x_xy .. x_zz, row-major) per epoch (%d epochs)",
                          a->xcov, d->xcov.rows, d->xcov.cols, d->m / 3);
                return CLI_DATAERR;
            }
            if ((ec = check_xcov_names(a->xcov)))
                return ec;
        }
    } else if ((ec = cli_read_values(a->sigma, d->m, "--sigma (one per row)", &d->sig, NULL)))
        return ec;
    if (a->spec && (ec = cli_read_vector(a->spec, d->N, "--spec (one per column of S)",
                                         &d->spec, NULL)))
        return ec;
    d->G = 1;
    return a->groups ? read_groups(a->groups, d) : CLI_OK;
}

/* The epoch of a covariance that is not positive definite, for the message. */
static void name_bad_epoch(const cli_noise_args *a, const noise_in *d)
{
    igea_whiten *w = NULL;
    int bad = -1, N = d->N;
    double *A = calloc((size_t)N * N + N + 2, sizeof(double));
    if (!A || igea_whiten_create(N, 0, NULL, 1, &w) != 0) {
        free(A);
        return;
    }
    double *b = A + (size_t)N * N, *wtw = b + N;
    if (a->xcov) {
        if (igea_whiten_accumulate_xcov(w, IGEA_COLMAJOR, d->m, d->Sc, d->m, d->dw.v, d->cov.v,
                                        d->xcov.v, NULL, NULL, A, N, b, wtw, NULL,
                                        &bad) == IGEA_ESINGULAR)
            cli_error("%s:%d, %s: the covariance of epoch %d given the earlier epochs (K_ee "
                      "with the cross blocks X_e) is not positive definite, or nearly not "
                      "(its conditional variance below %g of the variances it is computed "
                      "from)", a->cov, bad + 1, a->xcov, bad, IGEA_WHITEN_XCOV_RTOL);
    } else if (igea_whiten_accumulate(w, IGEA_COLMAJOR, d->m, d->Sc, d->m, d->dw.v, NULL, 1,
                                      d->cov.v, NULL, NULL, NULL, A, N, b, wtw, NULL,
                                      &bad) == IGEA_ESINGULAR)
        cli_error("%s:%d: the covariance of epoch %d is not positive definite", a->cov,
                  bad + 1, bad);
    igea_whiten_free(w);
    free(A);
}

/* The noise route's own lines: phi per axis, the group scales, the rows
 * the robust route rejected, the outer iteration. */
void cli_noise_text(FILE *f, const cli_noise_args *a, const cli_noise_result *r)
{
    const double *info = r->info;
    int p = (int)info[IGEA_STATS_INFO_AR_ORDER];
    if (a->xcov)
        fprintf(f, "the whole K: cross blocks between epochs from %s (rows differenced between "
                   "epochs, block-tridiagonal Cholesky; the whitened rows are each epoch's "
                   "innovations)\n", a->xcov);
    for (int ax = 0; ax < 3 && p > 0; ax++) {
        fprintf(f, "AR(%d) axis %c%s: phi", p, "xyz"[ax],
                r->ar_method == IGEA_NOISE_AR_REML ? " (REML)" : "");
        for (int k = 0; k < p; k++)
            fprintf(f, " %.5f (se %.5f)", r->ar[3 * ax + k], r->ar[9 + 3 * ax + k]);
        fprintf(f, "\n");
    }
    for (int g = 0; g < r->G; g++) {
        const double *o = r->gout + (size_t)g * IGEA_NOISE_GROUP_COLS;
        fprintf(f, "group %d: c = %.6g (se %.3g, REML se %.3g, sigma_w = %.4f), redundancy "
                   "%.1f, %g rows, bias %.4g %.4g %.4g\n", g, o[IGEA_NOISE_GROUP_SCALE],
                o[IGEA_NOISE_GROUP_SE], o[IGEA_NOISE_GROUP_SE_REML],
                sqrt(o[IGEA_NOISE_GROUP_SCALE]), o[IGEA_NOISE_GROUP_REDUND],
                o[IGEA_NOISE_GROUP_ROWS], o[IGEA_NOISE_GROUP_BIAS], o[IGEA_NOISE_GROUP_BIAS + 1],
                o[IGEA_NOISE_GROUP_BIAS + 2]);
    }
    if (a->opts[IGEA_EQERR_OPT_ROBUST] == 1) {
        fprintf(f, "robust: %d row(s) rejected by data snooping, |w| > %.4f:",
                (int)info[IGEA_STATS_INFO_N_OUTLIERS], info[IGEA_STATS_INFO_ROBUST_CRIT]);
        for (int i = 0; i < r->m; i++)
            if (r->row_w[i] != 0)
                fprintf(f, " row %d (w = %.2f)", i, r->row_w[i]);
        fprintf(f, "\n");
    }
    fprintf(f, "noise iterations %d, %s\n", (int)info[IGEA_STATS_INFO_NOISE_ITERATIONS],
            info[IGEA_STATS_INFO_NOISE_CONVERGED] == 1 ? "settled" : "NOT settled");
}

/* The noise route's own JSON fields. */
void cli_noise_json(cli_json *j, const cli_noise_result *r)
{
    const double *info = r->info;
    int p = (int)info[IGEA_STATS_INFO_AR_ORDER];
    cli_jint(j, "ar_order", p);
    cli_jstr(j, "ar_method", r->ar_method < 0 ? NULL
                             : igea_choice_name(IGEA_CHOICE_NOISE_AR_METHOD, r->ar_method));
    cli_json_open(j, "ar_phi", '[');
    for (int ax = 0; ax < 3 && p > 0; ax++)
        cli_jnums(j, NULL, r->ar + 3 * ax, p);
    cli_json_close(j);
    cli_json_open(j, "ar_se", '[');
    for (int ax = 0; ax < 3 && p > 0; ax++)
        cli_jnums(j, NULL, r->ar + 9 + 3 * ax, p);
    cli_json_close(j);
    cli_json_open(j, "groups", '[');
    for (int g = 0; g < r->G; g++) {
        const double *o = r->gout + (size_t)g * IGEA_NOISE_GROUP_COLS;
        cli_json_open(j, NULL, '{');
        cli_jnum(j, "scale", o[IGEA_NOISE_GROUP_SCALE]);
        cli_jnum(j, "scale_se", o[IGEA_NOISE_GROUP_SE]);
        cli_jnum(j, "scale_se_reml", o[IGEA_NOISE_GROUP_SE_REML]);
        cli_jnum(j, "redundancy", o[IGEA_NOISE_GROUP_REDUND]);
        cli_jint(j, "rows", (long)o[IGEA_NOISE_GROUP_ROWS]);
        cli_jnums(j, "bias", o + IGEA_NOISE_GROUP_BIAS, 3);
        cli_json_close(j);
    }
    cli_json_close(j);
    cli_jnum(j, "robust_crit", info[IGEA_STATS_INFO_ROBUST_CRIT]);
    cli_json_open(j, "rejected_rows", '[');
    for (int i = 0; i < r->m; i++)
        if (r->row_w[i] != 0) {
            cli_json_open(j, NULL, '{');
            cli_jint(j, "row", i);
            cli_jnum(j, "w", r->row_w[i]);
            cli_json_close(j);
        }
    cli_json_close(j);
    cli_jint(j, "noise_iterations", (long)info[IGEA_STATS_INFO_NOISE_ITERATIONS]);
    cli_jbool(j, "noise_converged", info[IGEA_STATS_INFO_NOISE_CONVERGED] == 1);
}

void cli_noise_result_free(cli_noise_result *r)
{
    free(r->lambda);
    free(r->reject);
    free(r->spec);
    memset(r, 0, sizeof *r);
}

/* Read the flight and run igea_noise_eqerr_resid; the report is the
 * caller's (cmd_eqerr.c, the same as the plain route's). */
int cli_eqerr_noise(const cli_noise_args *a, cli_noise_result *r)
{
    noise_in d;
    memset(&d, 0, sizeof d);
    memset(r, 0, sizeof *r);
    int ec = read_inputs(a, &d);
    size_t N = (size_t)d.N, m = (size_t)d.m;
    if (!ec) {
        r->lambda = malloc((N * N + 3 * N + (size_t)d.G * IGEA_NOISE_GROUP_COLS + 2 * m) *
                           sizeof(double));
        r->reject = malloc(N * sizeof(int));
        if (!r->lambda || !r->reject)
            ec = cli_oom("the results");
    }
    if (!ec) {
        r->m = d.m, r->N = d.N, r->G = d.G;
        r->P = r->lambda + N;
        r->xhat = r->P + N * N;
        r->z = r->xhat + N;
        r->gout = r->z + N;
        r->row_w = r->gout + (size_t)d.G * IGEA_NOISE_GROUP_COLS;
        r->resid = r->row_w + m;
        int st;
        if (a->xcov) {
            st = igea_noise_eqerr_xcov(d.m, d.N, d.Sc, d.m, d.dw.v, d.cov.v, d.xcov.v, d.spec,
                                       a->opts, r->lambda, r->P, d.N, r->xhat, r->z, r->reject,
                                       r->info, r->gout, r->row_w, r->resid);
            memset(r->ar, 0, sizeof r->ar);
        } else
            st = igea_noise_eqerr_resid(d.m, d.N, d.Sc, d.m, d.dw.v, a->cov ? NULL : d.sig, 1,
                                        a->cov ? d.cov.v : NULL, d.group, d.G, d.spec,
                                        a->p_given ? a->phi : NULL, a->opts, r->lambda, r->P,
                                        d.N, r->xhat, r->z, r->reject, r->info, r->ar, r->gout,
                                        r->row_w, r->resid);
        if (st == IGEA_ESINGULAR && a->cov)
            name_bad_epoch(a, &d);
        ec = cli_status(st, "eqerr");
    }
    if (!ec) {
        r->ar_method = r->info[IGEA_STATS_INFO_AR_ORDER] > 0 && !a->p_given
                           ? (int)a->opts[IGEA_EQERR_OPT_AR_METHOD] : -1;
        r->spec = d.spec; /* handed over */
        d.spec = NULL;
    } else {
        cli_noise_result_free(r);
    }
    in_free(&d);
    return ec;
}
