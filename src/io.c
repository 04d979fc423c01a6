/* src/io.c - the matrix reader (igea/io.h): text rows, column names,
 * numbers in C and Fortran syntax, the public API. The byte source is
 * io_src.c, the .npy format io_npy.c. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io_src.h"

/* ---- numbers -------------------------------------------------------------- */
static int is_digit(char c) { return c >= '0' && c <= '9'; }
static int is_sep(char c)
{
    return c == ' ' || c == '\t' || c == ',' || c == '\r' || c == '\n';
}
static int ends_token(char c) { return c == '\0' || c == '#' || is_sep(c); }

/* A number at p (leading blanks skipped by strtod): *end past it, *v its
 * value, *erange strtod's range error. A Fortran D or d exponent
 * (1.5D+03) is read as e; a hexadecimal number has no exponent letter D.
 * Returns 0 when a number was read (end > p), 1 when none. */
static int scan_number(const char *p, const char **end, double *v, int *erange)
{
    char *e;
    errno = 0;
    double x = strtod(p, &e);
    *erange = errno == ERANGE;
    if (e == p)
        return 1;
    const char *q = e + 1;
    if ((*e == 'D' || *e == 'd') && (is_digit(e[-1]) || e[-1] == '.')) {
        const char *h = p;
        while (*h == ' ' || *h == '\t')
            h++;
        if (*h == '+' || *h == '-')
            h++;
        if (*q == '+' || *q == '-')
            q++;
        if (!(h[0] == '0' && (h[1] == 'x' || h[1] == 'X')) && is_digit(*q)) {
            while (is_digit(*q))
                q++;
            char buf[128];
            size_t n = (size_t)(q - p);
            if (n < sizeof buf) {
                memcpy(buf, p, n);
                buf[n] = '\0';
                buf[e - p] = 'e';
                char *e2;
                errno = 0;
                x = strtod(buf, &e2);
                *erange = errno == ERANGE;
                if (e2 == buf + n)
                    e = (char *)q;
            }
        }
    }
    *end = e;
    *v = x;
    return 0;
}

int igea_io_parse_number(const char *s, double *x)
{
    if (!s)
        return -1;
    if (!x)
        return -2;
    const char *end;
    double v;
    int erange;
    if (scan_number(s, &end, &v, &erange) || *end != '\0')
        return IGEA_EFORMAT;
    if (!isfinite(v) && !erange)
        return IGEA_ENONFINITE;
    if (erange || !isfinite(v))
        return IGEA_EOVERFLOW;
    *x = v;
    return 0;
}

/* ---- names ------------------------------------------------------------------ */
/* The names of a header line (p up to '\0' or '#'), joined by '\n' into
 * a malloc'd *out, their count in *n. Returns 1 when every field is a name
 * (at least one), 0 when some field is not (nothing allocated), < 0 a
 * status. */
static int names_of(igea_io_reader *r, const char *p, char **out, int *n)
{
    size_t len = strlen(p);
    char *buf = malloc(len + 1), *w = buf;
    int count = 0;
    if (!buf)
        return io_fail(r, IGEA_ENOMEM, 0, 0, 0, "out of memory (column names)");
    for (;;) {
        while (is_sep(*p))
            p++;
        if (*p == '\0' || *p == '#')
            break;
        if (count > 0)
            *w++ = '\n';
        if (*p == '"') {
            const char *q = strchr(p + 1, '"');
            if (!q || q == p + 1 || !ends_token(q[1]))
                goto not_names;
            memcpy(w, p + 1, (size_t)(q - p - 1));
            w += q - p - 1;
            p = q + 1;
        } else {
            const char *q = p, *e;
            double v;
            int er;
            if (!((*p >= 'A' && *p <= 'Z') || (*p >= 'a' && *p <= 'z') || *p == '_'))
                goto not_names;
            while (!ends_token(*q) && *q != '"')
                q++;
            if (!scan_number(p, &e, &v, &er) && e == q)
                goto not_names; /* nan, inf */
            memcpy(w, p, (size_t)(q - p));
            w += q - p;
            p = q;
        }
        count++;
    }
    if (count == 0)
        goto not_names;
    *w = '\0';
    *out = buf;
    *n = count;
    return 1;
not_names:
    free(buf);
    return 0;
}

/* A line before the first data row: a header row of names (1), a comment
 * line (its names kept as candidates) or blank (0), or data (2). < 0 a
 * status. */
static int before_data(igea_io_reader *r, const char *p)
{
    while (is_sep(*p))
        p++;
    if (*p == '\0')
        return 0;
    char *nm = NULL;
    int n = 0, got = names_of(r, *p == '#' ? p + 1 : p, &nm, &n);
    if (got < 0)
        return got;
    if (*p == '#') {
        if (got && !r->header_row && r->cols == 0) {
            free(r->cnames);
            r->cnames = nm, r->ncnames = n;
        } else if (got)
            free(nm);
        return 0;
    }
    if (!got || r->header_row) { /* data, or a second header row: refused as data */
        free(got ? nm : NULL);
        return 2;
    }
    if (r->cols == 0) {
        free(r->names);
        r->names = nm, r->nnames = n;
    } else
        free(nm);
    r->header_row = 1;
    return 1;
}

/* ---- text rows ---------------------------------------------------------------- */
/* A comma between two digits ("0,1234") in a file whose other values are
 * separated by blanks is a decimal comma, not a separator. */
static int decimal_comma(igea_io_reader *r)
{
    if (!r->comma_line || !r->blank_gap_line)
        return 0;
    return io_fail(r, IGEA_EFORMAT, r->comma_line, r->comma_col, 0,
                   "a comma between digits in a file whose values are separated by blanks "
                   "(line %ld): decimal comma? write 0.5, not 0,5", r->blank_gap_line);
}

static int bad_number(igea_io_reader *r, const char *p)
{
    char tok[40];
    size_t k = 0;
    while (p[k] && !strchr(" \t,\r\n#", p[k]) && k < sizeof tok - 1) {
        tok[k] = p[k];
        k++;
    }
    tok[k] = '\0';
    long col = (long)(p - r->line) + 1;
    const char *q = p;
    while (is_digit(*q))
        q++;
    if (q > p && *q == '*')
        return io_fail(r, IGEA_EFORMAT, r->lineno, col, 0,
                       "'%s' is a Fortran repeat count (r*value), which igea does not "
                       "expand: write the values out", tok);
    const char *e;
    double v;
    int er;
    if (!scan_number(p, &e, &v, &er) && (*e == '+' || *e == '-') && is_digit(e[-1]) &&
        is_digit(e[1]))
        return io_fail(r, IGEA_EFORMAT, r->lineno, col, 0,
                       "'%s' is not a finite number (an exponent without its letter, as "
                       "Fortran writes exponents beyond 99? write 1.5E-100 or 1.5D-100)", tok);
    return io_fail(r, IGEA_EFORMAT, r->lineno, col, 0, "'%s' is not a finite number", tok);
}

/* Note the separator before value n of the line (decimal-comma rule). */
static int gap(igea_io_reader *r, const char *g, const char *p, int comma, int blank)
{
    if (blank && !comma && !r->blank_gap_line)
        r->blank_gap_line = r->lineno;
    if (comma == 1 && !blank && is_digit(g[-1]) && is_digit(*p) && !r->comma_line) {
        r->comma_line = r->lineno;
        r->comma_col = (long)(g - r->line) + 1;
    }
    return decimal_comma(r);
}

static int push(igea_io_reader *r, int n, double v)
{
    if (n == r->vcap) {
        int nc = r->vcap ? 2 * r->vcap : 16;
        double *nv = realloc(r->vals, (size_t)nc * sizeof(double));
        if (!nv)
            return io_fail(r, IGEA_ENOMEM, r->lineno, 0, 0, "out of memory (line %ld)",
                           r->lineno);
        r->vals = nv;
        r->vcap = nc;
    }
    r->vals[n] = v;
    return 0;
}

/* The values of the line from p into r->vals: their number (0 for a blank
 * or comment line) or < 0 a status. */
static int parse_values(igea_io_reader *r, const char *p)
{
    int n = 0, st;
    for (;;) {
        const char *g = p;
        int comma = 0, blank = 0;
        for (; is_sep(*p); p++)
            if (*p == ',')
                comma++;
            else
                blank = 1;
        if (*p == '\0' || *p == '#')
            break;
        if (n > 0 && (st = gap(r, g, p, comma, blank)))
            return st;
        const char *end;
        double v;
        int erange;
        if (r->nan_ok && p[0] == 'N' && p[1] == 'a' && p[2] == 'N' && ends_token(p[3])) {
            v = NAN; /* a gap (IGEA_IO_NAN) */
            end = p + 3;
        } else if (scan_number(p, &end, &v, &erange) || !ends_token(*end) || !isfinite(v) ||
                   (erange && fabs(v) > 1.0)) {
            return bad_number(r, p);
        }
        if ((st = push(r, n, v)))
            return st;
        n++;
        p = end;
    }
    return n;
}

/* Grow r->line to hold need bytes. */
static int line_room(igea_io_reader *r, size_t need)
{
    if (need <= r->cap)
        return 0;
    size_t nc = r->cap ? r->cap : 256;
    while (nc < need)
        nc *= 2;
    if (nc > (size_t)IGEA_IO_LINE_MAX + 1)
        nc = (size_t)IGEA_IO_LINE_MAX + 1;
    char *nl = realloc(r->line, nc);
    if (!nl)
        return io_fail(r, IGEA_ENOMEM, r->lineno + 1, 0, 0, "out of memory (line %ld)",
                       r->lineno + 1);
    r->line = nl;
    r->cap = nc;
    return 0;
}

/* Next line into r->line, bounded and refused at the first NUL byte.
 * 1 a line, 0 end of input, < 0 a status. */
static int read_line(igea_io_reader *r)
{
    io_src *s = &r->s;
    size_t n = 0;
    int st;
    for (;;) {
        if (s->bpos == s->blen) {
            s->bpos = s->blen = 0;
            int m = io_src_more(r);
            if (m < 0)
                return m;
            if (m == 0) {
                if (n == 0)
                    return 0;
                break;
            }
        }
        unsigned char *b = s->buf + s->bpos;
        size_t avail = s->blen - s->bpos;
        unsigned char *nl = memchr(b, '\n', avail);
        size_t take = nl ? (size_t)(nl - b) : avail;
        unsigned char *z = memchr(b, '\0', take);
        if (z)
            return io_fail(r, IGEA_EFORMAT, r->lineno + 1, (long)(n + (size_t)(z - b)) + 1, 0,
                           "a NUL byte in a text file (binary data?)");
        if (n + take > IGEA_IO_LINE_MAX)
            return io_fail(r, IGEA_EFORMAT, r->lineno + 1, 0, 0,
                           "line longer than %ld bytes (binary data?)", (long)IGEA_IO_LINE_MAX);
        if ((st = line_room(r, n + take + 1)))
            return st;
        memcpy(r->line + n, b, take);
        n += take;
        s->bpos += take + (nl ? 1 : 0);
        s->pos += (off_t)(take + (nl ? 1 : 0));
        if (nl)
            break;
    }
    r->line[n] = '\0';
    r->lineno++;
    /* A UTF-8 byte order mark: columns count from after it. */
    if (r->lineno == 1 && n >= 3 && !memcmp(r->line, "\xef\xbb\xbf", 3))
        memmove(r->line, r->line + 3, n - 2);
    return 1;
}

/* The first data row of a pass fixes the columns and settles the names. */
static int first_row(igea_io_reader *r, int n)
{
    if (r->cols == 0) {
        r->cols = n;
        if (r->header_row && r->nnames != n)
            return io_fail(r, IGEA_EFORMAT, r->lineno, 0, 0,
                           "%d values, but the header row names %d columns", n, r->nnames);
        if (!r->header_row && r->cnames && r->ncnames == n) {
            r->names = r->cnames, r->nnames = n;
            r->cnames = NULL;
        }
        free(r->cnames);
        r->cnames = NULL;
    }
    return 0;
}

/* Next data row into r->vals (r->cols values, or discover them). 1 a row,
 * 0 end of input, < 0 a status. */
static int text_row(igea_io_reader *r)
{
    for (;;) {
        int got = read_line(r), st;
        if (got <= 0)
            return got;
        if (r->data_rows == 0) {
            int kind = before_data(r, r->line);
            if (kind < 0)
                return kind;
            if (kind != 2)
                continue;
        }
        int n = parse_values(r, r->line);
        if (n < 0)
            return n;
        if (n == 0)
            continue;
        if (r->data_rows == 0 && (st = first_row(r, n)))
            return st;
        if (n != r->cols)
            return io_fail(r, IGEA_EFORMAT, r->lineno, 0, 0,
                           "%d values, but the rows before have %d", n, r->cols);
        r->data_rows++;
        return 1;
    }
}

/* ---- the reader ----------------------------------------------------------------- */
static void reset(igea_io_reader *r)
{
    io_npy_unmap(r, 1);
    free(r->vbuf);
    io_src_close(&r->s);
    free(r->tmpdir);
    free(r->line);
    free(r->vals);
    free(r->names);
    free(r->cnames);
    free(r->data);
    unsigned char *buf = r->s.buf;
    memset(r, 0, sizeof *r);
    r->s.buf = buf;
    r->s.fd = r->s.tee = -1;
}

int igea_io_reader_create(igea_io_reader **out)
{
    if (!out)
        return -1;
    *out = NULL;
    igea_io_reader *r = calloc(1, sizeof *r);
    if (r && !(r->s.buf = malloc(IO_BUF))) {
        free(r);
        r = NULL;
    }
    if (!r)
        return IGEA_ENOMEM;
    r->s.fd = r->s.tee = -1;
    *out = r;
    return 0;
}

void igea_io_reader_free(igea_io_reader *r)
{
    if (!r)
        return;
    reset(r);
    free(r->s.buf);
    free(r);
}

static int ends_with(const char *s, const char *suf)
{
    size_t n = strlen(s), k = strlen(suf);
    return n >= k && strcmp(s + n - k, suf) == 0;
}

/* Kind and size of the open descriptor. */
static int fd_kind(igea_io_reader *r, int from_offset)
{
    struct stat st;
    if (fstat(r->s.fd, &st) != 0)
        return io_sysfail(r, IGEA_EREAD, errno, "");
    if (S_ISDIR(st.st_mode))
        return io_fail(r, IGEA_EREAD, 0, 0, 0, "is a directory");
    if (S_ISREG(st.st_mode)) {
        off_t at = from_offset ? lseek(r->s.fd, 0, SEEK_CUR) : 0;
        if (at >= 0 && at <= st.st_size) {
            r->s.seekable = 1;
            r->s.inplace = 1;
            r->s.delta = at;
            r->s.size = st.st_size - at;
        }
    }
    return 0;
}

/* .npy by name, or by its magic bytes; then its header, or the first text
 * row read ahead. */
static int start(igea_io_reader *r, const char *name)
{
    int more = 1;
    r->npy = ends_with(name, ".npy");
    if (!r->npy) {
        while (r->s.blen < 6 && (more = io_src_more(r)) > 0)
            ;
        if (more < 0)
            return more;
        r->npy = r->s.blen >= 6 && memcmp(r->s.buf, "\x93NUMPY", 6) == 0;
    }
    if (r->npy)
        return io_npy_header(r);
    int got = text_row(r);
    if (got == 0)
        return io_fail(r, IGEA_EFORMAT, 0, 0, 0,
                       "no data (the file is empty or holds only comments)");
    if (got == 1)
        r->have_ahead = 1;
    return got < 0 ? got : 0;
}

/* Open fd (own: the reader closes it) known as name. */
static int open_common(igea_io_reader *r, int fd, int own, const char *name, int flags,
                       const char *tmpdir)
{
    reset(r);
    r->s.fd = fd;
    r->s.own = own;
    r->twice = flags & IGEA_IO_TWICE;
    r->map = (flags & IGEA_IO_MAP) != 0;
    r->nan_ok = (flags & IGEA_IO_NAN) != 0;
    r->unchecked = (flags & IGEA_IO_UNCHECKED) != 0;
    int st = 0;
    if (tmpdir && !(r->tmpdir = strdup(tmpdir)))
        st = io_fail(r, IGEA_ENOMEM, 0, 0, 0, "out of memory (opening)");
    if (!st)
        st = fd_kind(r, !own);
    if (!st && r->twice && !r->s.seekable) {
        int sp = io_spool_new(r);
        if (sp < 0)
            st = sp;
        else
            r->s.tee = sp;
    }
    if (!st)
        st = start(r, name ? name : "");
    if (st) {
        int e = r->st;
        long line = r->eline, col = r->ecol;
        int err = r->eerrno;
        char msg[IO_MSG];
        memcpy(msg, r->emsg, IO_MSG);
        reset(r);
        r->st = e, r->eline = line, r->ecol = col, r->eerrno = err;
        memcpy(r->emsg, msg, IO_MSG);
        return st;
    }
    r->open = 1;
    return 0;
}

int igea_io_reader_open(igea_io_reader *r, const char *path, int flags, const char *tmpdir)
{
    if (!r)
        return -1;
    if (!path)
        return -2;
    if (flags & ~(IGEA_IO_TWICE | IGEA_IO_MAP | IGEA_IO_NAN | IGEA_IO_UNCHECKED))
        return -3;
    int fd;
    do
        fd = open(path, O_RDONLY);
    while (fd < 0 && errno == EINTR);
    if (fd < 0) {
        reset(r);
        return io_sysfail(r, IGEA_EREAD, errno, "");
    }
    return open_common(r, fd, 1, path, flags, tmpdir);
}

int igea_io_reader_open_fd(igea_io_reader *r, int fd, const char *name, int flags,
                           const char *tmpdir)
{
    if (!r)
        return -1;
    if (fd < 0)
        return -2;
    if (flags & ~(IGEA_IO_TWICE | IGEA_IO_MAP | IGEA_IO_NAN | IGEA_IO_UNCHECKED))
        return -4;
    return open_common(r, fd, 0, name, flags, tmpdir);
}

int igea_io_reader_cols(const igea_io_reader *r) { return r && r->open ? r->cols : 0; }

const char *igea_io_reader_names(const igea_io_reader *r)
{
    return r && r->open && r->names ? r->names : "";
}

const char *igea_io_reader_message(const igea_io_reader *r) { return r ? r->emsg : ""; }

int igea_io_reader_info(const igea_io_reader *r, double *info)
{
    if (!r)
        return -1;
    if (!info)
        return -2;
    for (int k = 0; k < IGEA_IO_INFO_LEN; k++)
        info[k] = 0.0;
    info[IGEA_IO_INFO_STATUS] = r->st;
    info[IGEA_IO_INFO_LINE] = (double)r->eline;
    info[IGEA_IO_INFO_COLUMN] = (double)r->ecol;
    info[IGEA_IO_INFO_ERRNO] = r->eerrno;
    info[IGEA_IO_INFO_COLS] = r->open ? r->cols : 0;
    info[IGEA_IO_INFO_ROWS] = r->open ? (double)r->nloaded : 0.0;
    info[IGEA_IO_INFO_NAMES] = r->open && r->names ? 1.0 : 0.0;
    info[IGEA_IO_INFO_NPY] = r->open ? r->npy : 0;
    info[IGEA_IO_INFO_NPY_ROWS] = r->open && r->npy ? (double)r->rows : 0.0;
    info[IGEA_IO_INFO_CHECKED] = r->open && r->npy && r->s.seekable ? 1.0 : 0.0;
    info[IGEA_IO_INFO_NPY_DATA] =
        r->open && r->npy && r->s.inplace ? (double)(r->s.delta + r->data_off) : -1.0;
    info[IGEA_IO_INFO_NPY_FORTRAN] = r->open && r->npy && r->fortran && !r->oned && r->cols > 1;
    return 0;
}

/* Up to maxrows text rows into buf: the count or < 0 a status. */
static long text_next(igea_io_reader *r, long maxrows, double *buf)
{
    long n = 0;
    while (n < maxrows) {
        if (!r->have_ahead) {
            if (r->eof)
                break;
            int got = text_row(r);
            if (got < 0)
                return got;
            if (got == 0) {
                r->eof = 1;
                break;
            }
        }
        memcpy(buf + n * r->cols, r->vals, (size_t)r->cols * sizeof(double));
        r->have_ahead = 0;
        n++;
    }
    return n;
}

/* Up to maxrows rows of either format (a .npy's checked for NaN and Inf
 * when check is 1): the count or < 0 a status. */
static long next_rows(igea_io_reader *r, long maxrows, double *buf, int check)
{
    if (!r->npy)
        return text_next(r, maxrows, buf);
    long want = r->rows - r->next_row;
    if (want > maxrows)
        want = maxrows;
    if (want > 0) {
        int st = io_npy_next(r, want, buf, check);
        if (st)
            return st;
    }
    return want;
}

int igea_io_reader_next(igea_io_reader *r, int maxrows, double *buf, int *nread)
{
    if (!r || !r->open)
        return -1;
    if (maxrows < 1)
        return -2;
    if (!buf)
        return -3;
    if (!nread)
        return -4;
    long n = next_rows(r, maxrows, buf, 1);
    if (n < 0)
        return (int)n;
    *nread = (int)n;
    return 0;
}

int igea_io_reader_view(igea_io_reader *r, int maxrows, int *nread)
{
    if (!r || !r->open)
        return -1;
    if (maxrows < 1)
        return -2;
    if (!nread)
        return -3;
    io_npy_unmap(r, 0);
    r->vrows = NULL;
    long want = maxrows;
    if (r->npy) {
        want = r->rows - r->next_row < want ? r->rows - r->next_row : want;
        if (want <= 0) {
            *nread = 0;
            return 0;
        }
        if (io_npy_mappable(r)) {
            int st = io_npy_view(r, want);
            if (st <= 0) {
                if (st == 0)
                    *nread = (int)want;
                return st;
            }
            r->nomap = 1; /* the system refused: read from now on */
        }
    }
    if (want > r->vrcap) {
        double *nv = NULL;
        if ((size_t)want <= SIZE_MAX / sizeof(double) / (size_t)r->cols) {
            free(r->vbuf);
            r->vbuf = NULL, r->vrcap = 0;
            nv = malloc((size_t)want * (size_t)r->cols * sizeof(double));
        }
        if (!nv)
            return io_fail(r, IGEA_ENOMEM, 0, 0, 0, "out of memory (%ld x %d values)", want,
                           r->cols);
        r->vbuf = nv, r->vrcap = want;
    }
    long row0 = r->next_row;
    long n = next_rows(r, want, r->vbuf, !r->unchecked);
    if (n < 0)
        return (int)n;
    r->vrows = n > 0 ? r->vbuf : NULL;
    r->vrow0 = row0;
    r->vn = n;
    *nread = (int)n;
    return 0;
}

const double *igea_io_reader_view_rows(const igea_io_reader *r)
{
    return r && r->open ? r->vrows : NULL;
}

int igea_io_reader_view_check(igea_io_reader *r)
{
    if (!r || !r->open)
        return -1;
    if (!r->npy || !r->vrows)
        return 0; /* text rows are refused at a non-finite number */
    return io_npy_check_rows(r, r->vrow0, r->vn, r->vrows);
}

int igea_io_reader_rewind(igea_io_reader *r)
{
    if (!r || !r->open || !r->twice)
        return -1;
    io_npy_unmap(r, 0);
    r->vrows = NULL;
    int st = io_src_spool(r);
    if (st)
        return st;
    r->s.pos = 0;
    r->s.bpos = r->s.blen = 0;
    r->s.eof = 0;
    r->next_row = 0;
    r->lineno = 0;
    r->have_ahead = 0;
    r->eof = 0;
    r->data_rows = 0;
    r->header_row = 0;
    if (r->npy)
        r->s.pos = r->data_off;
    return 0;
}

/* Grow the loaded rows to hold cap rows. */
static int load_room(igea_io_reader *r, double **v, long *cap, long need)
{
    if (need <= *cap)
        return 0;
    long nc = *cap > LONG_MAX / 2 ? LONG_MAX : *cap * 2;
    if (nc < need)
        nc = need;
    if (r->npy && nc > r->rows)
        nc = r->rows;
    double *nv = NULL;
    if ((size_t)nc <= SIZE_MAX / sizeof(double) / (size_t)r->cols)
        nv = realloc(*v, (size_t)nc * r->cols * sizeof(double));
    if (!nv)
        return io_fail(r, IGEA_ENOMEM, 0, 0, 0, "out of memory (%ld x %d values)", nc,
                       r->cols);
    *v = nv;
    *cap = nc;
    return 0;
}

int igea_io_reader_load(igea_io_reader *r)
{
    if (!r || !r->open)
        return -1;
    long cap = 0, rows = 0, first = 1024;
    if (r->npy) /* a seekable .npy has been checked to hold its rows */
        first = r->s.seekable ? r->rows - r->next_row : (1L << 17) / r->cols;
    if (first < 1)
        first = 1;
    double *v = NULL;
    int st = load_room(r, &v, &cap, first);
    while (!st) {
        if (rows == cap) {
            if (r->npy ? r->next_row == r->rows : r->eof && !r->have_ahead)
                break;
            if ((st = load_room(r, &v, &cap, rows + 1)))
                break;
        }
        long got = next_rows(r, cap - rows, v + rows * r->cols, 1);
        if (got < 0)
            st = (int)got;
        else if (got == 0)
            break;
        rows += got > 0 ? got : 0;
    }
    if (st) {
        free(v);
        return st;
    }
    free(r->data);
    r->data = v;
    r->nloaded = rows;
    return 0;
}

int igea_io_reader_copy(const igea_io_reader *r, double *v, int layout)
{
    if (!r || !r->open || !r->data)
        return -1;
    if (!v)
        return -2;
    if (layout != IGEA_ROWMAJOR && layout != IGEA_COLMAJOR)
        return -3;
    long m = r->nloaded;
    int n = r->cols;
    if (layout == IGEA_ROWMAJOR)
        memcpy(v, r->data, (size_t)m * n * sizeof(double));
    else
        for (long i = 0; i < m; i++)
            for (int j = 0; j < n; j++)
                v[(size_t)j * m + i] = r->data[(size_t)i * n + j];
    return 0;
}
