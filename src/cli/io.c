/* io.c - the driver's input, output and message helpers (see cli.h). */
#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"

void cli_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("igea: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

int cli_status(int status, const char *context)
{
    if (status == 0)
        return CLI_OK;
    cli_error("%s: %s (status %d)", context, igea_strerror(status), status);
    switch (status) {
    case IGEA_ENONFINITE:
    case IGEA_ENONPOSITIVE:
    case IGEA_EEMPTY:
    case IGEA_EDEPENDENT:
        return CLI_DATAERR;
    default:
        return CLI_SOFTWARE;
    }
}

int cli_parse_double(const char *opt, const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE || !isfinite(v)) {
        cli_error("option %s: '%s' is not a finite number", opt, s);
        return CLI_USAGE;
    }
    *out = v;
    return CLI_OK;
}

int cli_parse_int(const char *opt, const char *s, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s || *end != '\0' || errno == ERANGE || v < INT_MIN || v > INT_MAX) {
        cli_error("option %s: '%s' is not a whole number", opt, s);
        return CLI_USAGE;
    }
    *out = (int)v;
    return CLI_OK;
}

int cli_file_or_positive(const char *opt, const char *v, int *is_number, double *value)
{
    char *end;
    errno = 0;
    double x = strtod(v, &end);
    if (end == v || *end != '\0')
        return CLI_OK; /* a file name */
    if (!(x > 0) || !isfinite(x)) {
        cli_error("%s %s: must be a positive number or a file", opt, v);
        return CLI_USAGE;
    }
    *is_number = 1;
    *value = x;
    return CLI_OK;
}

const char *cli_optarg(int argc, char **argv, int *i)
{
    if (*i + 1 >= argc) {
        cli_error("option %s needs a value", argv[*i]);
        return NULL;
    }
    return argv[++*i];
}

/* ---- readers ------------------------------------------------------------ */
struct cli_reader {
    FILE *f;
    char *path;
    int npy;
    int cols;
    /* text */
    char *line;
    size_t cap;
    long lineno;
    double *vals; /* the last text row parsed */
    int vcap;
    int have_ahead; /* vals holds a row not yet handed out */
    int eof;
    /* npy */
    long rows, next_row;
    int fortran;
    off_t data_off;
    int oned;
};

static int ends_with(const char *s, const char *suf)
{
    size_t n = strlen(s), k = strlen(suf);
    return n >= k && strcmp(s + n - k, suf) == 0;
}

/* Parse one text line into vals (capacity *cap, grown); returns the number
 * of values, 0 for a blank/comment line, -1 after printing an error. */
static int parse_line(cli_reader *r, double **vals, int *cap)
{
    char *p = r->line;
    int n = 0;
    for (;;) {
        while (*p == ' ' || *p == '\t' || *p == ',' || *p == '\r' || *p == '\n')
            p++;
        if (*p == '\0' || *p == '#')
            break;
        char *end;
        errno = 0;
        double v = strtod(p, &end);
        /* A number must end at a separator, a comment or the end. */
        int okend = (*end == '\0' || *end == ' ' || *end == '\t' || *end == ',' ||
                     *end == '\r' || *end == '\n' || *end == '#');
        if (end == p || !okend || !isfinite(v) || (errno == ERANGE && fabs(v) > 1.0)) {
            char tok[40];
            size_t k = 0;
            while (p[k] && !strchr(" \t,\r\n#", p[k]) && k < sizeof tok - 1) {
                tok[k] = p[k];
                k++;
            }
            tok[k] = '\0';
            cli_error("%s:%ld:%ld: '%s' is not a finite number", r->path,
                      r->lineno, (long)(p - r->line) + 1, tok);
            return -1;
        }
        if (n == *cap) {
            int nc = *cap ? 2 * *cap : 16;
            double *nv = realloc(*vals, (size_t)nc * sizeof(double));
            if (!nv) {
                cli_error("out of memory reading %s", r->path);
                return -1;
            }
            *vals = nv;
            *cap = nc;
        }
        (*vals)[n++] = v;
        p = end;
    }
    return n;
}

/* Next data row of a text file into row (r->cols values, or discover the
 * column count when r->cols == 0). Returns 1 row read, 0 EOF, -1 error
 * (exit code in *ec). */
static int text_row(cli_reader *r, int *ec)
{
    for (;;) {
        errno = 0;
        ssize_t len = getline(&r->line, &r->cap, r->f);
        if (len < 0) {
            if (ferror(r->f)) {
                cli_error("%s: read error: %s", r->path, strerror(errno));
                *ec = CLI_NOINPUT;
                return -1;
            }
            return 0;
        }
        r->lineno++;
        if ((size_t)len != strlen(r->line)) {
            cli_error("%s:%ld: a NUL byte in a text file (binary data?)", r->path, r->lineno);
            *ec = CLI_DATAERR;
            return -1;
        }
        int n = parse_line(r, &r->vals, &r->vcap);
        if (n < 0) {
            *ec = CLI_DATAERR;
            return -1;
        }
        if (n == 0)
            continue;
        if (r->cols == 0)
            r->cols = n;
        else if (n != r->cols) {
            cli_error("%s:%ld: %d values, but the rows before have %d", r->path,
                      r->lineno, n, r->cols);
            *ec = CLI_DATAERR;
            return -1;
        }
        return 1;
    }
}

static int npy_header(cli_reader *r)
{
    unsigned char magic[10];
    if (fread(magic, 1, 10, r->f) != 10 || memcmp(magic, "\x93NUMPY", 6) != 0) {
        cli_error("%s: not a .npy file (bad magic)", r->path);
        return CLI_DATAERR;
    }
    int major = magic[6];
    size_t hlen;
    if (major == 1)
        hlen = magic[8] | (magic[9] << 8);
    else if (major == 2 || major == 3) {
        unsigned char more[2];
        if (fread(more, 1, 2, r->f) != 2) {
            cli_error("%s: truncated .npy header", r->path);
            return CLI_DATAERR;
        }
        hlen = (size_t)magic[8] | ((size_t)magic[9] << 8) | ((size_t)more[0] << 16) |
               ((size_t)more[1] << 24);
    } else {
        cli_error("%s: unsupported .npy version %d", r->path, major);
        return CLI_DATAERR;
    }
    if (hlen > 1 << 20) {
        cli_error("%s: .npy header too long", r->path);
        return CLI_DATAERR;
    }
    char *h = malloc(hlen + 1);
    if (!h || fread(h, 1, hlen, r->f) != hlen) {
        free(h);
        cli_error("%s: truncated .npy header", r->path);
        return CLI_DATAERR;
    }
    h[hlen] = '\0';
    int ec = CLI_OK;
    char *d = strstr(h, "'descr'");
    char *fo = strstr(h, "'fortran_order'");
    char *sh = strstr(h, "'shape'");
    if (!d || !fo || !sh) {
        cli_error("%s: malformed .npy header", r->path);
        ec = CLI_DATAERR;
    } else if (!strstr(d, "'<f8'") || strstr(d, "'<f8'") > strchr(d + 7, ',')) {
        cli_error("%s: .npy data must be little-endian float64 ('<f8'); convert with "
                  "numpy: np.save(path, a.astype('<f8'))", r->path);
        ec = CLI_DATAERR;
    } else {
        char *v = strchr(fo + 15, ':');
        while (v && (*v == ':' || *v == ' '))
            v++;
        r->fortran = v && strncmp(v, "True", 4) == 0;
        char *p = strchr(sh, '(');
        long dims[3] = {0, 0, 0};
        int nd = 0;
        if (p) {
            p++;
            while (nd < 3) {
                while (*p == ' ')
                    p++;
                if (*p == ')')
                    break;
                char *end;
                long x = strtol(p, &end, 10);
                if (end == p)
                    break;
                dims[nd++] = x;
                p = end;
                while (*p == ' ' || *p == 'L')
                    p++;
                if (*p == ',')
                    p++;
            }
        }
        if (dims[0] < 0 || dims[1] < 0) {
            cli_error("%s: malformed .npy shape", r->path);
            ec = CLI_DATAERR;
        } else if (nd == 1) {
            r->rows = dims[0];
            r->cols = 1;
            r->oned = 1;
        } else if (nd == 2 && dims[1] <= INT_MAX) {
            r->rows = dims[0];
            r->cols = (int)dims[1];
        } else {
            cli_error("%s: .npy array must be 1-D or 2-D", r->path);
            ec = CLI_DATAERR;
        }
    }
    free(h);
    if (ec)
        return ec;
    r->data_off = ftello(r->f);
    /* Check the file really holds rows * cols doubles. */
    struct stat st;
    if (fstat(fileno(r->f), &st) == 0 && S_ISREG(st.st_mode)) {
        double need = (double)r->rows * r->cols * 8.0 + (double)r->data_off;
        if ((double)st.st_size < need) {
            cli_error("%s: truncated: the header promises %ld x %d values, the file "
                      "holds %lld bytes of data", r->path, r->rows, r->cols,
                      (long long)(st.st_size - r->data_off));
            return CLI_DATAERR;
        }
    }
    if (r->rows == 0 || r->cols == 0) {
        cli_error("%s: empty array", r->path);
        return CLI_DATAERR;
    }
    return CLI_OK;
}

int cli_reader_open(const char *path, cli_reader **out)
{
    cli_reader *r = calloc(1, sizeof *r);
    if (!r) {
        cli_error("out of memory");
        return CLI_SOFTWARE;
    }
    r->path = strdup(path);
    r->f = fopen(path, "rb");
    if (!r->f) {
        cli_error("%s: %s", path, strerror(errno));
        cli_reader_close(r);
        return CLI_NOINPUT;
    }
    struct stat st;
    if (fstat(fileno(r->f), &st) == 0 && S_ISDIR(st.st_mode)) {
        cli_error("%s: is a directory", path);
        cli_reader_close(r);
        return CLI_NOINPUT;
    }
    int ec = CLI_OK;
    if (ends_with(path, ".npy")) {
        r->npy = 1;
        ec = npy_header(r);
    } else {
        int got = text_row(r, &ec);
        if (got == 0) {
            cli_error("%s: no data (the file is empty or holds only comments)", path);
            ec = CLI_DATAERR;
        } else if (got == 1)
            r->have_ahead = 1;
    }
    if (ec) {
        cli_reader_close(r);
        return ec;
    }
    *out = r;
    return CLI_OK;
}

int cli_reader_cols(const cli_reader *r) { return r->cols; }
const char *cli_reader_path(const cli_reader *r) { return r->path; }

int cli_reader_next(cli_reader *r, long maxrows, double *buf, long *nread)
{
    long n = 0;
    int ec = CLI_OK;
    if (r->npy) {
        long want = r->rows - r->next_row;
        if (want > maxrows)
            want = maxrows;
        if (want > 0) {
            if (!r->fortran || r->oned) {
                off_t off = r->data_off + (off_t)r->next_row * r->cols * 8;
                if (fseeko(r->f, off, SEEK_SET) != 0 ||
                    fread(buf, 8, (size_t)want * r->cols, r->f) != (size_t)want * r->cols) {
                    cli_error("%s: truncated .npy data", r->path);
                    return CLI_DATAERR;
                }
            } else {
                /* Fortran order: column j of the block, then scatter. */
                double *col = malloc((size_t)want * sizeof(double));
                if (!col) {
                    cli_error("out of memory");
                    return CLI_SOFTWARE;
                }
                for (int j = 0; j < r->cols; j++) {
                    off_t off = r->data_off + ((off_t)j * r->rows + r->next_row) * 8;
                    if (fseeko(r->f, off, SEEK_SET) != 0 ||
                        fread(col, 8, (size_t)want, r->f) != (size_t)want) {
                        free(col);
                        cli_error("%s: truncated .npy data", r->path);
                        return CLI_DATAERR;
                    }
                    for (long i = 0; i < want; i++)
                        buf[i * r->cols + j] = col[i];
                }
                free(col);
            }
            for (long k = 0; k < want * r->cols; k++)
                if (!isfinite(buf[k])) {
                    long row = r->next_row + k / r->cols;
                    cli_error("%s: row %ld, column %ld: NaN or Inf", r->path, row + 1,
                              (long)(k % r->cols) + 1);
                    return CLI_DATAERR;
                }
            r->next_row += want;
            n = want;
        }
        *nread = n;
        return CLI_OK;
    }
    while (n < maxrows) {
        if (!r->have_ahead) {
            if (r->eof)
                break;
            int got = text_row(r, &ec);
            if (got < 0)
                return ec;
            if (got == 0) {
                r->eof = 1;
                break;
            }
        }
        memcpy(buf + n * r->cols, r->vals, (size_t)r->cols * sizeof(double));
        r->have_ahead = 0;
        n++;
    }
    *nread = n;
    return CLI_OK;
}

void cli_reader_close(cli_reader *r)
{
    if (!r)
        return;
    if (r->f)
        fclose(r->f);
    free(r->path);
    free(r->line);
    free(r->vals);
    free(r);
}

int cli_read_matrix(const char *path, cli_matrix *out)
{
    cli_reader *r;
    int ec = cli_reader_open(path, &r);
    if (ec)
        return ec;
    long cap = r->npy ? r->rows : 1024, rows = 0;
    int cols = r->cols;
    double *v = malloc((size_t)cap * cols * sizeof(double));
    if (!v) {
        cli_reader_close(r);
        cli_error("%s: out of memory", path);
        return CLI_SOFTWARE;
    }
    for (;;) {
        if (rows == cap) {
            long nc = cap * 2;
            double *nv = realloc(v, (size_t)nc * cols * sizeof(double));
            if (!nv) {
                free(v);
                cli_reader_close(r);
                cli_error("%s: out of memory", path);
                return CLI_SOFTWARE;
            }
            v = nv;
            cap = nc;
        }
        long got;
        ec = cli_reader_next(r, cap - rows, v + rows * cols, &got);
        if (ec) {
            free(v);
            cli_reader_close(r);
            return ec;
        }
        if (got == 0)
            break;
        rows += got;
    }
    cli_reader_close(r);
    out->v = v;
    out->rows = rows;
    out->cols = cols;
    return CLI_OK;
}

void cli_matrix_free(cli_matrix *m)
{
    if (m) {
        free(m->v);
        m->v = NULL;
        m->rows = 0;
        m->cols = 0;
    }
}

/* ---- output ------------------------------------------------------------- */
int cli_out_open(cli_out *o, const char *path)
{
    o->f = NULL;
    o->tmp = NULL;
    o->path = NULL;
    if (!path || !strcmp(path, "-")) {
        o->f = stdout;
        return CLI_OK;
    }
    size_t n = strlen(path);
    o->tmp = malloc(n + 16);
    o->path = strdup(path);
    if (!o->tmp || !o->path) {
        cli_out_abort(o);
        cli_error("out of memory");
        return CLI_SOFTWARE;
    }
    snprintf(o->tmp, n + 16, "%s.tmp.XXXXXX", path);
    int fd = mkstemp(o->tmp);
    if (fd < 0) {
        cli_error("%s: cannot create: %s", path, strerror(errno));
        free(o->tmp);
        o->tmp = NULL;
        cli_out_abort(o);
        return CLI_IOERR;
    }
    fchmod(fd, 0644);
    o->f = fdopen(fd, "wb");
    if (!o->f) {
        close(fd);
        cli_out_abort(o);
        return CLI_IOERR;
    }
    return CLI_OK;
}

int cli_out_commit(cli_out *o)
{
    if (o->f == stdout) {
        if (fflush(stdout) != 0 || ferror(stdout)) {
            cli_error("writing standard output: %s", strerror(errno));
            return CLI_IOERR;
        }
        return CLI_OK;
    }
    int bad = fflush(o->f) != 0 || ferror(o->f);
    bad |= fclose(o->f) != 0;
    o->f = NULL;
    if (!bad && rename(o->tmp, o->path) != 0)
        bad = 1;
    if (bad) {
        cli_error("%s: write failed: %s", o->path, strerror(errno));
        cli_out_abort(o);
        return CLI_IOERR;
    }
    free(o->tmp);
    free(o->path);
    o->tmp = o->path = NULL;
    return CLI_OK;
}

void cli_out_abort(cli_out *o)
{
    if (o->f && o->f != stdout)
        fclose(o->f);
    o->f = NULL;
    if (o->tmp)
        unlink(o->tmp);
    free(o->tmp);
    free(o->path);
    o->tmp = o->path = NULL;
}

int cli_write_matrix(const char *path, const double *v, long rows, int cols,
                     const char *header)
{
    cli_out o;
    int ec = cli_out_open(&o, path);
    if (ec)
        return ec;
    if (path && ends_with(path, ".npy")) {
        char h[128];
        int hl = snprintf(h, sizeof h,
                          "{'descr': '<f8', 'fortran_order': False, 'shape': (%ld, %d), }",
                          rows, cols);
        int total = 10 + hl + 1;
        int pad = (64 - total % 64) % 64;
        unsigned short hlen = (unsigned short)(hl + pad + 1);
        fwrite("\x93NUMPY\x01\x00", 1, 8, o.f);
        unsigned char le[2] = {(unsigned char)(hlen & 0xff), (unsigned char)(hlen >> 8)};
        fwrite(le, 1, 2, o.f);
        fwrite(h, 1, (size_t)hl, o.f);
        for (int i = 0; i < pad; i++)
            fputc(' ', o.f);
        fputc('\n', o.f);
        fwrite(v, sizeof(double), (size_t)rows * cols, o.f);
    } else {
        if (header)
            fprintf(o.f, "# %s\n", header);
        for (long i = 0; i < rows; i++)
            for (int j = 0; j < cols; j++)
                fprintf(o.f, "%.17g%c", v[i * cols + j], j + 1 < cols ? ' ' : '\n');
    }
    return cli_out_commit(&o);
}

void cli_json_num(FILE *f, double x)
{
    if (isfinite(x))
        fprintf(f, "%.17g", x);
    else
        fputs("null", f);
}

void cli_json_array(FILE *f, const double *x, long n)
{
    fputc('[', f);
    for (long i = 0; i < n; i++) {
        if (i)
            fputs(", ", f);
        cli_json_num(f, x[i]);
    }
    fputc(']', f);
}

void cli_json_iarray(FILE *f, const int *x, long n)
{
    fputc('[', f);
    for (long i = 0; i < n; i++)
        fprintf(f, "%s%d", i ? ", " : "", x[i]);
    fputc(']', f);
}

void cli_json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c == '\n')
            fputs("\\n", f);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
    fputc('"', f);
}
