/* igea accel --model ieee and igea accel --design: the IEEE Std 1293 model
 * fitted to tumble readings in the IA-PA and IA-OA planes, and the
 * D-criterion of a position list (called from cmd_accel.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

typedef struct {
    int n, ieee, np;
    double *ang, *e, *th, *me; /* n each */
    int *pl, *mpl, *cnt;       /* n each */
} ai_data;

static void ai_free(ai_data *d)
{
    free(d->ang);
    free(d->pl);
}

/* Rows: angle[, plane][, output]. ncol_need: columns needed. */
static int ai_read(const cli_accel_args *a, int ncol_need, ai_data *d)
{
    cli_matrix in = {0};
    int ec = cli_read_matrix(a->data, &in);
    if (ec)
        return ec;
    if (in.cols < ncol_need) {
        cli_error("%s: %d column(s); expected angle (deg)%s%s per row", a->data, in.cols,
                  ncol_need > 1 && d->ieee ? ", plane (0 IA-PA, 1 IA-OA)" : "",
                  ncol_need > 2 ? ", output" : "");
        ec = CLI_DATAERR;
    } else if (in.rows > 10000000L) {
        cli_error("%s: too many rows", a->data);
        ec = CLI_DATAERR;
    } else if (!(d->ang = malloc((size_t)in.rows * 4 * sizeof(double) + 1)) ||
               !(d->pl = malloc((size_t)in.rows * 3 * sizeof(int) + 1))) {
        ec = cli_oom("the readings");
    }
    int n = d->n = (int)in.rows;
    for (int i = 0; !ec && i < n; i++) {
        const double *row = in.v + (size_t)i * in.cols;
        d->ang[i] = row[0];
        d->pl[i] = 0;
        if (d->ieee) {
            if (!(row[1] == 0.0 || row[1] == 1.0)) {
                cli_error("%s: row %d column 2: the plane must be 0 (IA-PA) or 1 (IA-OA), "
                          "not %g", a->data, i + 1, row[1]);
                ec = CLI_DATAERR;
            }
            d->pl[i] = (int)row[1];
        }
    }
    if (!ec) {
        d->e = d->ang + n, d->th = d->e + n, d->me = d->th + n;
        d->mpl = d->pl + n, d->cnt = d->mpl + n;
        for (int i = 0; ncol_need > 2 && i < n; i++)
            d->e[i] = in.v[(size_t)i * in.cols + 2];
    }
    cli_matrix_free(&in);
    return ec;
}

/* Merge the readings of each plane into positions (CW/CCW, 0/360). */
static int ai_merge(const cli_accel_args *a, ai_data *d, int *npos)
{
    int n = d->n, tot = 0;
    double *ang = malloc((size_t)n * 2 * sizeof(double) + 1);
    if (!ang)
        return cli_oom("the readings");
    double *e = ang + n;
    for (int p = 0; p < 2; p++) {
        int k = 0, m = 0;
        for (int i = 0; i < n; i++)
            if (d->pl[i] == p)
                ang[k] = d->ang[i], e[k++] = d->e[i];
        if (!k)
            continue;
        int st = igea_accel_merge(k, ang, e, NULL, a->tol, d->th + tot, d->me + tot, NULL,
                                  d->cnt + tot, &m);
        if (st) {
            free(ang);
            return cli_status(st, "accel --ieee");
        }
        for (int i = 0; i < m; i++)
            d->mpl[tot + i] = p;
        tot += m;
    }
    free(ang);
    *npos = tot;
    return CLI_OK;
}

static void names_of(int model, int method, int axis, const char **nm, int *np)
{
    *np = model == IGEA_ACCEL_SINGLE ? IGEA_ACCEL_NP_SINGLE
          : model == IGEA_ACCEL_IEEE ? IGEA_ACCEL_NP_IEEE
          : method == IGEA_ACCEL_JOINT ? IGEA_ACCEL_NP_JOINT : IGEA_ACCEL_NP_DUAL;
    for (int j = 0; j < *np; j++)
        nm[j] = j == IGEA_ACCEL_SIM_DELTA0 && model == IGEA_ACCEL_DUAL
                    ? igea_accel_coef_name(IGEA_ACCEL_SINGLE, axis, IGEA_ACCEL_DELTA0)
                    : igea_accel_coef_name(model, axis, j);
}

static void flags_json(cli_json *j, const int *flag, int np)
{
    cli_json_open(j, "flags", '[');
    for (int i = 0; i < np; i++)
        cli_jstr(j, NULL, flag[i] ? "prior" : "data");
    cli_json_close(j);
}

/* The fit's report. */
static void ieee_report(FILE *f, const cli_accel_args *a, const ai_data *d, int npos,
                        const double *coef, const double *sd, const double *cov,
                        const int *flag, const double *info)
{
    const char *nm[IGEA_ACCEL_NP_IEEE], *un[IGEA_ACCEL_NP_IEEE];
    for (int j = 0; j < IGEA_ACCEL_NP_IEEE; j++)
        nm[j] = igea_accel_coef_name(IGEA_ACCEL_IEEE, IGEA_ACCEL_AXIS_PA, j),
        un[j] = igea_accel_coef_unit(IGEA_ACCEL_IEEE, j);
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, f);
        cli_jstr(&j, "model", "ieee");
        cli_jstr(&j, "method", igea_choice_name(IGEA_CHOICE_ACCEL_IEEE_METHOD, a->method));
        cli_jint(&j, "positions", npos);
        cli_jint(&j, "readings", d->n);
        cli_jnums(&j, "theta_deg", d->th, npos);
        cli_jints(&j, "plane", d->mpl, npos);
        cli_jstrs(&j, "names", nm, IGEA_ACCEL_NP_IEEE);
        cli_jstrs(&j, "units", un, IGEA_ACCEL_NP_IEEE);
        cli_jnums(&j, "coef", coef, IGEA_ACCEL_NP_IEEE);
        cli_jnums(&j, "sd", sd, IGEA_ACCEL_NP_IEEE);
        cli_jrows(&j, "cov", cov, IGEA_ACCEL_NP_IEEE, IGEA_ACCEL_NP_IEEE);
        flags_json(&j, flag, IGEA_ACCEL_NP_IEEE);
        cli_jint(&j, "rank", (long)info[IGEA_ACCEL_INFO_RANK]);
        cli_jint(&j, "dof", (long)info[IGEA_ACCEL_INFO_DOF]);
        cli_jnum(&j, "sigma", info[IGEA_ACCEL_INFO_SIGMA]);
        cli_jnum(&j, "rms", info[IGEA_ACCEL_INFO_RMS]);
        cli_json_end(&j);
        return;
    }
    fprintf(f, "igea accel: IEEE Std 1293 model, %s; %d readings -> %d positions; rank %d "
               "of 8, dof %d\nresidual sd %.3e, rms %.3e (output units)\n\n%-8s %-6s %15s "
               "%12s  %s\n", a->method == IGEA_ACCEL_HARMONIC ? "harmonic method"
                                                              : "least squares",
            d->n, npos, (int)info[IGEA_ACCEL_INFO_RANK], (int)info[IGEA_ACCEL_INFO_DOF],
            info[IGEA_ACCEL_INFO_SIGMA], info[IGEA_ACCEL_INFO_RMS], "coef", "unit",
            "estimate", "sd", "determined by");
    for (int j = 0; j < IGEA_ACCEL_NP_IEEE; j++)
        fprintf(f, "%-8s %-6s %15.6e %12.3e  %s\n", nm[j], un[j], coef[j], sd[j],
                flag[j] ? "NOT DETERMINED (no readings in its plane, or confounded)"
                        : "data");
}

int cli_accel_ieee(const cli_accel_args *a)
{
    ai_data d = {0};
    d.ieee = 1;
    int ec = ai_read(a, 3, &d), npos = 0;
    if (!ec)
        ec = ai_merge(a, &d, &npos);
    double coef[8], sd[8], cov[64], info[IGEA_ACCEL_INFO_LEN];
    int flag[8];
    if (!ec) {
        int st = igea_accel_ieee_fit(a->method, npos, d.th, d.mpl, d.me, coef, sd, cov, 8,
                                     flag, info);
        if (st == IGEA_EDOMAIN && a->method == IGEA_ACCEL_HARMONIC)
            cli_error("accel --ieee harmonic: each plane needs N >= 7 equispaced positions "
                      "(use --ieee ls otherwise)");
        ec = cli_status(st, "accel --ieee");
    }
    cli_out o;
    if (!ec && !(ec = cli_out_open(&o, a->out))) {
        ieee_report(o.f, a, &d, npos, coef, sd, cov, flag, info);
        ec = cli_out_commit(&o);
    }
    ai_free(&d);
    return ec;
}

static void design_report(FILE *f, const cli_accel_args *a, int n, double ld,
                          const double *vf, const int *flag, int rank)
{
    const char *nm[10];
    int np;
    names_of(a->model, a->method, a->axis, nm, &np);
    double det = rank == np ? exp(np * ld) : 0.0;
    if (a->json) {
        cli_json j;
        cli_json_begin(&j, f);
        cli_jstr(&j, "model", igea_choice_name(IGEA_CHOICE_ACCEL_CRIT_MODEL, a->model));
        cli_jstr(&j, "method", igea_choice_name(a->model == IGEA_ACCEL_IEEE
                                                    ? IGEA_CHOICE_ACCEL_IEEE_METHOD
                                                    : IGEA_CHOICE_ACCEL_METHOD, a->method));
        cli_jint(&j, "readings", n);
        cli_jnum(&j, "head_ratio", a->head_ratio);
        cli_jstrs(&j, "names", nm, np);
        cli_jnum(&j, "logdet", ld);
        cli_jnum(&j, "det", det);
        cli_jnums(&j, "varfac", vf, np);
        flags_json(&j, flag, np);
        cli_jint(&j, "rank", rank);
        cli_json_end(&j);
        return;
    }
    fprintf(f, "igea accel --design: %s model%s, %d readings; rank %d of %d\n"
               "D-criterion (1/%d) log det(M/n) = %.6f, det(M/n) = %.6g%s\n\n%-9s %12s %12s  %s\n",
            igea_choice_name(IGEA_CHOICE_ACCEL_CRIT_MODEL, a->model),
            a->method == IGEA_ACCEL_JOINT ? " (joint)" : "", n, rank, np, rank, ld, det,
            rank < np ? " (rank-deficient: logdet of the estimable part)" : "", "coef",
            "varfac", "sd/sigma", "determined");
    for (int j = 0; j < np; j++)
        fprintf(f, "%-9s %12.6g %12.6g  %s\n", nm[j], vf[j], sqrt(vf[j] / n),
                flag[j] ? "NO (confounded or absent)" : "yes");
}

int cli_accel_design(const cli_accel_args *a)
{
    ai_data d = {0};
    d.ieee = a->model == IGEA_ACCEL_IEEE;
    int ec = ai_read(a, d.ieee ? 2 : 1, &d), rank = 0, flag[10];
    double ld = 0.0, vf[10];
    if (!ec)
        ec = cli_status(igea_accel_criterion(a->model, a->method, d.n, d.ang,
                                             d.ieee ? d.pl : NULL, a->head_ratio, &ld, vf,
                                             flag, &rank), "accel --design");
    cli_out o;
    if (!ec && !(ec = cli_out_open(&o, a->out))) {
        design_report(o.f, a, d.n, ld, vf, flag, rank);
        ec = cli_out_commit(&o);
    }
    ai_free(&d);
    return ec;
}

/* ---- --history: earlier 'igea accel --json' results --------------------- */

/* The whole file (malloc'd, NUL-terminated) or NULL with a message. */
static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        cli_error("%s: cannot be read", path);
        return NULL;
    }
    size_t cap = 4096, len = 0;
    char *buf = malloc(cap);
    while (buf) {
        size_t got = fread(buf + len, 1, cap - 1 - len, f);
        len += got;
        if (len < cap - 1)
            break;
        char *nb = cap < ((size_t)64 << 20) ? realloc(buf, cap * 2) : NULL;
        if (!nb) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = nb, cap *= 2;
    }
    fclose(f);
    if (!buf)
        cli_error("%s: out of memory or larger than 64 MB", path);
    else
        buf[len] = 0;
    return buf;
}

/* n numbers of the top-level array "key": [..] (nested brackets skipped
 * over), into x. Returns the count read, -1 when the key is absent or a
 * value is not a number. */
static int json_numbers(const char *text, const char *key, double *x, int n)
{
    char pat[32];
    snprintf(pat, sizeof pat, "\n  \"%s\": [", key);
    const char *p = strstr(text, pat);
    if (!p)
        return -1;
    p += strlen(pat);
    int k = 0;
    while (*p && k < n) {
        while (*p == ' ' || *p == '[' || *p == ',' || *p == '\n' || *p == ']')
            p++;
        char *end;
        double v = strtod(p, &end);
        if (end == p || !isfinite(v))
            return -1;
        x[k++] = v;
        p = end;
    }
    return k;
}

/* One history file: coef[np] and cov (np x np of the file's nf x nf). */
static int history_file(const char *path, int np, double *coef, double *cov)
{
    char *t = slurp(path);
    if (!t)
        return CLI_NOINPUT;
    int ec = CLI_OK, nf = strstr(t, "\"method\": \"joint\"") ? IGEA_ACCEL_NP_JOINT : np;
    double c[IGEA_ACCEL_NP_JOINT], v[IGEA_ACCEL_NP_JOINT * IGEA_ACCEL_NP_JOINT];
    const char *fl = strstr(t, "\n  \"flags\": [");
    const char *fe = fl ? strchr(fl, ']') : NULL;
    const char *pr = fl ? strstr(fl, "\"prior\"") : NULL;
    if (!fl || !fe || (pr && pr < fe)) {
        cli_error("%s: %s", path, fl ? "a coefficient is flagged prior (a minimum-norm or prior "
                                       "value, not an estimate): use joint fits"
                                     : "no \"flags\" (not an 'igea accel --json' result)");
        ec = CLI_DATAERR;
    } else if (json_numbers(t, "coef", c, nf) != nf || json_numbers(t, "cov", v, nf * nf) != nf * nf) {
        cli_error("%s: needs \"coef\" (%d numbers) and \"cov\" (%d x %d), as 'igea accel "
                  "--method joint --json' writes", path, nf, nf, nf);
        ec = CLI_DATAERR;
    }
    for (int i = 0; !ec && i < np; i++) {
        coef[i] = c[i];
        for (int j = 0; j < np; j++) /* the rows of the file, column-major here */
            cov[i + j * np] = v[i * nf + j];
    }
    free(t);
    return ec;
}

int cli_accel_history_read(const char *list, int np, double **b, double **V, int *m)
{
    char **items;
    int n = 0, ec = cli_split_list(list, &items, &n);
    if (ec)
        return ec;
    double *w = malloc(sizeof(double) * (size_t)(n * np + n * np * np + 1));
    if (!w) {
        free(items);
        return cli_oom("the history");
    }
    for (int i = 0; !ec && i < n; i++)
        ec = history_file(items[i], np, w + (size_t)i * np,
                          w + (size_t)n * np + (size_t)i * np * np);
    if (!ec && n < 2)
        ec = cli_usage("accel: --history needs at least two result files");
    free(items);
    if (ec) {
        free(w);
        return ec;
    }
    *b = w, *V = w + (size_t)n * np, *m = n;
    return CLI_OK;
}
