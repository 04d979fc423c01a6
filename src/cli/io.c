/* io.c - the driver's input, output and message helpers (see cli.h). */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
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

int cli_oom(const char *what)
{
    cli_error("out of memory (%s)", what);
    return CLI_SOFTWARE;
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

/* ---- byte sources --------------------------------------------------------
 * Every input is read through a file descriptor with the driver's own
 * buffer: a regular file by pread at logical offsets, anything else (a pipe,
 * a FIFO, a terminal, a device, standard input) sequentially. A
 * non-seekable input that must be read twice is copied as it is read into an
 * anonymous temporary file (the spool), which then serves the second pass;
 * a Fortran-order .npy from a non-seekable input is spooled whole first. */
#define SRC_BUF 65536

typedef struct {
    int fd;         /* -1: none */
    int own;        /* close fd at the end (not standard input) */
    int seekable;   /* pread(fd, logical + delta) */
    off_t delta;
    off_t size;     /* seekable: logical size */
    off_t pos;      /* logical offset of buf[bpos] */
    unsigned char *buf;
    size_t bpos, blen;
    int eof;
    int tee;        /* spool receiving a copy of every byte read, -1 none */
} src;

/* A read failure: out of memory is 70 ("out of memory"), anything else 66. */
static int read_failed(const char *path, int err)
{
    if (err == ENOMEM) {
        cli_error("out of memory reading %s", path);
        return CLI_SOFTWARE;
    }
    cli_error("%s: read error: %s", path, strerror(err));
    return CLI_NOINPUT;
}

static int write_all(int fd, const unsigned char *p, size_t n)
{
    while (n > 0) {
        ssize_t k = write(fd, p, n);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            return -1;
        p += k;
        n -= (size_t)k;
    }
    return 0;
}

/* An anonymous temporary file (unlinked at once), or -1 after a message. */
static int spool_new(const char *path, int *ec)
{
    const char *dir = getenv("TMPDIR");
    char name[4096];
    if (!dir || !*dir)
        dir = "/tmp";
    if (snprintf(name, sizeof name, "%s/igea-spool.XXXXXX", dir) >= (int)sizeof name)
        snprintf(name, sizeof name, "/tmp/igea-spool.XXXXXX");
    int fd = mkstemp(name);
    if (fd < 0) {
        int e = errno;
        cli_error("%s: cannot create a temporary copy of the input in %s: %s", path, dir,
                  strerror(e));
        *ec = e == ENOMEM ? CLI_SOFTWARE : CLI_IOERR;
        return -1;
    }
    unlink(name);
    return fd;
}

static ssize_t read_retry(int fd, void *p, size_t n)
{
    ssize_t k;
    do
        k = read(fd, p, n);
    while (k < 0 && errno == EINTR);
    return k;
}

static ssize_t pread_retry(int fd, void *p, size_t n, off_t off)
{
    ssize_t k;
    do
        k = pread(fd, p, n, off);
    while (k < 0 && errno == EINTR);
    return k;
}

/* Append more bytes to the buffer (compacting it first). Returns 1 when
 * bytes were added, 0 at end of input, -1 after a message (*ec set). */
static int src_more(src *s, const char *path, int *ec)
{
    if (s->eof)
        return 0;
    if (s->bpos > 0) {
        memmove(s->buf, s->buf + s->bpos, s->blen - s->bpos);
        s->blen -= s->bpos;
        s->bpos = 0;
    }
    if (s->blen == SRC_BUF)
        return 1;
    ssize_t k;
    if (s->seekable) {
        off_t at = s->pos + (off_t)s->blen;
        k = pread_retry(s->fd, s->buf + s->blen, SRC_BUF - s->blen, at + s->delta);
    } else
        k = read_retry(s->fd, s->buf + s->blen, SRC_BUF - s->blen);
    if (k < 0) {
        *ec = read_failed(path, errno);
        return -1;
    }
    if (k == 0) {
        s->eof = 1;
        return 0;
    }
    if (s->tee >= 0 && write_all(s->tee, s->buf + s->blen, (size_t)k) != 0) {
        int e = errno;
        cli_error("%s: cannot keep a copy of the input for the second pass: %s", path,
                  strerror(e));
        *ec = e == ENOMEM ? CLI_SOFTWARE : CLI_IOERR;
        return -1;
    }
    s->blen += (size_t)k;
    return 1;
}

/* Sequential read of n bytes; returns the bytes read (< n at end of input)
 * or -1 after a message. */
static long long src_read(src *s, void *dst, size_t n, const char *path, int *ec)
{
    unsigned char *d = dst;
    size_t got = 0;
    while (got < n) {
        if (s->bpos == s->blen) {
            /* Large reads of a seekable input bypass the buffer. */
            if (s->seekable && n - got >= SRC_BUF) {
                off_t avail = s->size - s->pos;
                size_t want = n - got;
                if (avail <= 0)
                    break;
                if ((off_t)want > avail)
                    want = (size_t)avail;
                ssize_t k = pread_retry(s->fd, d + got, want, s->pos + s->delta);
                if (k < 0) {
                    *ec = read_failed(path, errno);
                    return -1;
                }
                if (k == 0)
                    break;
                got += (size_t)k;
                s->pos += k;
                continue;
            }
            s->bpos = s->blen = 0;
            int m = src_more(s, path, ec);
            if (m < 0)
                return -1;
            if (m == 0)
                break;
        }
        size_t take = s->blen - s->bpos;
        if (take > n - got)
            take = n - got;
        memcpy(d + got, s->buf + s->bpos, take);
        s->bpos += take;
        s->pos += (off_t)take;
        got += take;
    }
    return (long long)got;
}

/* Make the rest of the input seekable: copy it to a spool (or finish the
 * spool that the tee has filled from offset 0). */
static int src_spool(src *s, const char *path)
{
    int ec = CLI_OK;
    if (s->seekable)
        return CLI_OK;
    off_t start;
    int sp;
    if (s->tee >= 0) {
        sp = s->tee;
        s->tee = -1;
        start = 0;
    } else {
        if ((sp = spool_new(path, &ec)) < 0)
            return ec;
        start = s->pos;
        if (write_all(sp, s->buf + s->bpos, s->blen - s->bpos) != 0)
            goto write_error;
    }
    while (!s->eof) {
        ssize_t k = read_retry(s->fd, s->buf, SRC_BUF);
        if (k < 0) {
            ec = read_failed(path, errno);
            close(sp);
            return ec;
        }
        if (k == 0)
            break;
        if (write_all(sp, s->buf, (size_t)k) != 0)
            goto write_error;
    }
    off_t end = lseek(sp, 0, SEEK_END);
    if (end < 0)
        goto write_error;
    if (s->own)
        close(s->fd);
    s->fd = sp;
    s->own = 1;
    s->seekable = 1;
    s->delta = -start;
    s->size = start + end;
    s->bpos = s->blen = 0;
    s->eof = 0;
    return CLI_OK;
write_error:;
    int e = errno;
    cli_error("%s: cannot keep a temporary copy of the input: %s", path, strerror(e));
    close(sp);
    return e == ENOMEM ? CLI_SOFTWARE : CLI_IOERR;
}

/* ---- readers ------------------------------------------------------------ */
struct cli_reader {
    src s;
    char *path;     /* as given, or "<stdin>" */
    int npy;
    int cols;
    int twice;      /* cli_reader_rewind allowed */
    /* text */
    char *line;
    size_t cap;
    long lineno;
    double *vals;   /* the last text row parsed */
    int vcap;
    int have_ahead; /* vals holds a row not yet handed out */
    int eof;
    long blank_gap_line, comma_line; /* decimal-comma detection: first line with */
    long comma_col;                  /* a blank separator / a digit,digit comma */
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

static int is_digit(char c) { return c >= '0' && c <= '9'; }

/* A comma written between two digits ("0,1234") in a file whose other values
 * are separated by blanks is a decimal comma, not a separator: a genuine
 * comma-separated file never separates values by blanks alone. */
static int decimal_comma(cli_reader *r)
{
    if (!r->comma_line || !r->blank_gap_line)
        return 0;
    cli_error("%s:%ld:%ld: a comma between digits in a file whose values are separated by "
              "blanks (line %ld): decimal comma? write 0.5, not 0,5",
              r->path, r->comma_line, r->comma_col, r->blank_gap_line);
    return 1;
}

/* Parse one text line into vals (capacity *cap, grown); returns the number
 * of values, 0 for a blank/comment line, -1 after printing an error (exit
 * code in *ec). */
static int parse_line(cli_reader *r, double **vals, int *cap, int *ec)
{
    char *p = r->line;
    int n = 0;
    *ec = CLI_DATAERR;
    for (;;) {
        char *gap = p;
        int comma = 0, blank = 0;
        while (*p == ' ' || *p == '\t' || *p == ',' || *p == '\r' || *p == '\n') {
            if (*p == ',')
                comma++;
            else
                blank = 1;
            p++;
        }
        if (*p == '\0' || *p == '#')
            break;
        if (n > 0) {
            if (blank && !comma && !r->blank_gap_line)
                r->blank_gap_line = r->lineno;
            if (comma == 1 && !blank && is_digit(gap[-1]) && is_digit(*p) && !r->comma_line) {
                r->comma_line = r->lineno;
                r->comma_col = (long)(gap - r->line) + 1;
            }
            if (decimal_comma(r))
                return -1;
        }
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
                cli_error("out of memory reading %s (line %ld)", r->path, r->lineno);
                *ec = CLI_SOFTWARE;
                return -1;
            }
            *vals = nv;
            *cap = nc;
        }
        (*vals)[n++] = v;
        p = end;
    }
    *ec = CLI_OK;
    return n;
}

/* Next line of a text input into r->line, bounded by CLI_LINE_MAX bytes and
 * refused at the first NUL byte. Returns 1, 0 at end of input, -1 after a
 * message (*ec set). */
static int read_line(cli_reader *r, int *ec)
{
    src *s = &r->s;
    size_t n = 0;
    for (;;) {
        if (s->bpos == s->blen) {
            s->bpos = s->blen = 0;
            int m = src_more(s, r->path, ec);
            if (m < 0)
                return -1;
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
        if (z) {
            cli_error("%s:%ld:%ld: a NUL byte in a text file (binary data?)", r->path,
                      r->lineno + 1, (long)(n + (size_t)(z - b)) + 1);
            *ec = CLI_DATAERR;
            return -1;
        }
        if (n + take > CLI_LINE_MAX) {
            cli_error("%s:%ld: line longer than %ld bytes (binary data?)", r->path,
                      r->lineno + 1, (long)CLI_LINE_MAX);
            *ec = CLI_DATAERR;
            return -1;
        }
        if (n + take + 1 > r->cap) {
            size_t nc = r->cap ? r->cap : 256;
            while (nc < n + take + 1)
                nc *= 2;
            if (nc > (size_t)CLI_LINE_MAX + 1)
                nc = (size_t)CLI_LINE_MAX + 1;
            char *nl2 = realloc(r->line, nc);
            if (!nl2) {
                cli_error("out of memory reading %s (line %ld)", r->path, r->lineno + 1);
                *ec = CLI_SOFTWARE;
                return -1;
            }
            r->line = nl2;
            r->cap = nc;
        }
        memcpy(r->line + n, b, take);
        n += take;
        s->bpos += take + (nl ? 1 : 0);
        s->pos += (off_t)(take + (nl ? 1 : 0));
        if (nl)
            break;
    }
    r->line[n] = '\0';
    r->lineno++;
    return 1;
}

/* Next data row of a text file into r->vals (r->cols values, or discover the
 * column count when r->cols == 0). Returns 1 row read, 0 EOF, -1 error
 * (exit code in *ec). */
static int text_row(cli_reader *r, int *ec)
{
    for (;;) {
        int got = read_line(r, ec);
        if (got <= 0)
            return got;
        int n = parse_line(r, &r->vals, &r->vcap, ec);
        if (n < 0)
            return -1;
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

static int npy_truncated(cli_reader *r, long long have)
{
    cli_error("%s: truncated: the header promises %ld x %d values, the input holds %lld "
              "bytes of data", r->path, r->rows, r->cols, have < 0 ? 0LL : have);
    return CLI_DATAERR;
}

/* The header dictionary of a .npy file (malloc'd, NUL-terminated). */
static int npy_header_text(cli_reader *r, char **text)
{
    unsigned char magic[10], more[2];
    int ec = CLI_OK;
    long long k = src_read(&r->s, magic, 10, r->path, &ec);
    if (k < 0)
        return ec;
    if (k != 10 || memcmp(magic, "\x93NUMPY", 6) != 0) {
        cli_error("%s: not a .npy file (bad magic)", r->path);
        return CLI_DATAERR;
    }
    int major = magic[6];
    size_t hlen = magic[8] | ((size_t)magic[9] << 8);
    if (major == 2 || major == 3) {
        if ((k = src_read(&r->s, more, 2, r->path, &ec)) < 0)
            return ec;
        if (k != 2) {
            cli_error("%s: truncated .npy header", r->path);
            return CLI_DATAERR;
        }
        hlen |= ((size_t)more[0] << 16) | ((size_t)more[1] << 24);
    } else if (major != 1) {
        cli_error("%s: unsupported .npy version %d", r->path, major);
        return CLI_DATAERR;
    }
    if (hlen > 1 << 20) {
        cli_error("%s: .npy header too long", r->path);
        return CLI_DATAERR;
    }
    char *h = malloc(hlen + 1);
    if (!h) {
        cli_error("out of memory reading %s (.npy header)", r->path);
        return CLI_SOFTWARE;
    }
    if ((k = src_read(&r->s, h, hlen, r->path, &ec)) < 0 || (size_t)k != hlen) {
        free(h);
        if (k >= 0)
            cli_error("%s: truncated .npy header", r->path);
        return k < 0 ? ec : CLI_DATAERR;
    }
    h[hlen] = '\0';
    *text = h;
    return CLI_OK;
}

/* The 'shape' tuple: rows and columns of a 1-D or 2-D array. */
static int npy_shape(cli_reader *r, const char *sh)
{
    const char *p = strchr(sh, '(');
    long dims[3] = {0, 0, 0};
    int nd = 0, big = 0;
    for (p = p ? p + 1 : NULL; p && nd < 3;) {
        while (*p == ' ')
            p++;
        if (*p == ')')
            break;
        char *end;
        errno = 0;
        long x = strtol(p, &end, 10);
        if (end == p)
            break;
        big |= errno == ERANGE;
        dims[nd++] = x;
        for (p = end; *p == ' ' || *p == 'L'; p++)
            ;
        if (*p == ',')
            p++;
    }
    if (dims[0] < 0 || dims[1] < 0) {
        cli_error("%s: malformed .npy shape", r->path);
    } else if (nd == 1 && !big) {
        r->rows = dims[0], r->cols = 1, r->oned = 1;
        return CLI_OK;
    } else if (nd == 2 && !big && dims[1] <= INT_MAX) {
        r->rows = dims[0], r->cols = (int)dims[1];
        return CLI_OK;
    } else if (big || nd == 2) {
        cli_error("%s: .npy shape too large", r->path);
    } else {
        cli_error("%s: .npy array must be 1-D or 2-D", r->path);
    }
    return CLI_DATAERR;
}

/* descr, fortran_order and shape of the header. */
static int npy_dict(cli_reader *r, const char *h)
{
    const char *d = strstr(h, "'descr'"), *fo = strstr(h, "'fortran_order'");
    const char *sh = strstr(h, "'shape'");
    if (!d || !fo || !sh) {
        cli_error("%s: malformed .npy header", r->path);
        return CLI_DATAERR;
    }
    if (!strstr(d, "'<f8'") || strstr(d, "'<f8'") > strchr(d + 7, ',')) {
        cli_error("%s: .npy data must be little-endian float64 ('<f8'); convert with "
                  "numpy: np.save(path, a.astype('<f8'))", r->path);
        return CLI_DATAERR;
    }
    const char *v = strchr(fo + 15, ':');
    while (v && (*v == ':' || *v == ' '))
        v++;
    r->fortran = v && strncmp(v, "True", 4) == 0;
    return npy_shape(r, sh);
}

static int npy_header(cli_reader *r)
{
    char *h = NULL;
    int ec = npy_header_text(r, &h);
    if (ec)
        return ec;
    ec = npy_dict(r, h);
    free(h);
    if (ec)
        return ec;
    r->data_off = r->s.pos;
    if (r->rows == 0 || r->cols == 0) {
        cli_error("%s: empty array", r->path);
        return CLI_DATAERR;
    }
    /* rows * cols * 8 bytes must be addressable and representable as a file
     * offset before anything is sized from it. */
    uintmax_t lim = (uintmax_t)SIZE_MAX < (uintmax_t)INT64_MAX ? (uintmax_t)SIZE_MAX
                                                               : (uintmax_t)INT64_MAX;
    if ((uintmax_t)r->rows > (lim - (uintmax_t)r->data_off) / 8u / (uintmax_t)r->cols) {
        cli_error("%s: .npy shape (%ld, %d) too large", r->path, r->rows, r->cols);
        return CLI_DATAERR;
    }
    /* A non-seekable input is copied to a temporary file first when it
     * must be read out of order (Fortran order) or when its rows are wide
     * (more than 512 values): then the header is checked against the bytes
     * really there before anything is sized from the column count. */
    if (((r->fortran && !r->oned && r->cols > 1) || r->cols > 512) &&
        (ec = src_spool(&r->s, r->path)))
        return ec;
    if (r->s.seekable) {
        off_t need = (off_t)r->rows * r->cols * 8;
        if (r->s.size - r->data_off < need)
            return npy_truncated(r, (long long)(r->s.size - r->data_off));
    }
    return CLI_OK;
}

/* Read n bytes at logical offset off (seekable, or sequential at the
 * current position). */
static int npy_read_at(cli_reader *r, off_t off, void *dst, size_t n)
{
    int ec = CLI_OK;
    if (r->s.seekable) {
        r->s.pos = off;
        r->s.bpos = r->s.blen = 0;
        r->s.eof = 0;
    } else if (off != r->s.pos) {
        cli_error("%s: .npy data out of order on a non-seekable input", r->path);
        return CLI_SOFTWARE;
    }
    long long k = src_read(&r->s, dst, n, r->path, &ec);
    if (k < 0)
        return ec;
    if ((size_t)k != n)
        return npy_truncated(r, (long long)(off - r->data_off) + k);
    return CLI_OK;
}

/* The descriptor of path ("-": standard input), its kind and size. */
static int reader_fd(cli_reader *r, const char *path, int is_stdin)
{
    if (is_stdin) {
        r->s.fd = 0;
    } else {
        do
            r->s.fd = open(path, O_RDONLY);
        while (r->s.fd < 0 && errno == EINTR);
        if (r->s.fd < 0) {
            int e = errno;
            if (e == ENOMEM)
                cli_error("out of memory opening %s", path);
            else
                cli_error("%s: %s", path, strerror(e));
            return e == ENOMEM ? CLI_SOFTWARE : CLI_NOINPUT;
        }
        r->s.own = 1;
    }
    struct stat st;
    if (fstat(r->s.fd, &st) != 0) {
        int e = errno;
        cli_error("%s: %s", r->path, strerror(e));
        return e == ENOMEM ? CLI_SOFTWARE : CLI_NOINPUT;
    }
    if (S_ISDIR(st.st_mode)) {
        cli_error("%s: is a directory", path);
        return CLI_NOINPUT;
    }
    if (S_ISREG(st.st_mode)) {
        off_t at = is_stdin ? lseek(0, 0, SEEK_CUR) : 0;
        if (at >= 0 && at <= st.st_size) {
            r->s.seekable = 1;
            r->s.delta = at;
            r->s.size = st.st_size - at;
        }
    }
    return CLI_OK;
}

/* .npy by name, or by its magic bytes for any other name; then its header,
 * or the first text row read ahead. */
static int reader_start(cli_reader *r, const char *path)
{
    int ec = CLI_OK;
    r->npy = ends_with(path, ".npy");
    if (!r->npy) {
        int more = 1;
        while (r->s.blen < 6 && (more = src_more(&r->s, r->path, &ec)) > 0)
            ;
        if (more < 0)
            return ec;
        r->npy = r->s.blen >= 6 && memcmp(r->s.buf, "\x93NUMPY", 6) == 0;
    }
    if (r->npy)
        return npy_header(r);
    int got = text_row(r, &ec);
    if (got == 0) {
        cli_error("%s: no data (the file is empty or holds only comments)", r->path);
        ec = CLI_DATAERR;
    } else if (got == 1) {
        r->have_ahead = 1;
    }
    return ec;
}

static int reader_open(const char *path, int twice, cli_reader **out)
{
    cli_reader *r = calloc(1, sizeof *r);
    int is_stdin = !strcmp(path, "-");
    if (r) {
        r->s.fd = -1;
        r->s.tee = -1;
        r->path = strdup(is_stdin ? "<stdin>" : path);
        r->s.buf = malloc(SRC_BUF);
    }
    if (!r || !r->path || !r->s.buf) {
        cli_error("out of memory opening %s", path);
        cli_reader_close(r);
        return CLI_SOFTWARE;
    }
    r->twice = twice;
    int ec = reader_fd(r, path, is_stdin);
    if (!ec && twice && !r->s.seekable)
        r->s.tee = spool_new(r->path, &ec);
    if (!ec)
        ec = reader_start(r, path);
    if (ec) {
        cli_reader_close(r);
        return ec;
    }
    *out = r;
    return CLI_OK;
}

int cli_reader_open(const char *path, cli_reader **out) { return reader_open(path, 0, out); }
int cli_reader_open_twice(const char *path, cli_reader **out) { return reader_open(path, 1, out); }

int cli_reader_rewind(cli_reader *r)
{
    if (!r->twice) {
        cli_error("%s: internal error: the reader was not opened for two passes", r->path);
        return CLI_SOFTWARE;
    }
    int ec = src_spool(&r->s, r->path);
    if (ec)
        return ec;
    r->s.pos = 0;
    r->s.bpos = r->s.blen = 0;
    r->s.eof = 0;
    r->next_row = 0;
    r->lineno = 0;
    r->have_ahead = 0;
    r->eof = 0;
    if (r->npy)
        r->s.pos = r->data_off;
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
            if (!r->fortran || r->oned || r->cols == 1) {
                off_t off = r->data_off + (off_t)r->next_row * r->cols * 8;
                if ((ec = npy_read_at(r, off, buf, (size_t)want * r->cols * 8)))
                    return ec;
            } else {
                /* Fortran order: column j of the block, then scatter. */
                double *col = malloc((size_t)want * sizeof(double));
                if (!col) {
                    cli_error("out of memory reading %s", r->path);
                    return CLI_SOFTWARE;
                }
                for (int j = 0; j < r->cols; j++) {
                    off_t off = r->data_off + ((off_t)j * r->rows + r->next_row) * 8;
                    if ((ec = npy_read_at(r, off, col, (size_t)want * 8))) {
                        free(col);
                        return ec;
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
    if (r->s.own && r->s.fd >= 0)
        close(r->s.fd);
    if (r->s.tee >= 0)
        close(r->s.tee);
    free(r->s.buf);
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
    int cols = r->cols;
    /* A seekable .npy has been checked to hold its rows; anything else
     * grows as the data arrives. */
    long cap = r->npy && r->s.seekable ? r->rows : 1024, rows = 0;
    if (r->npy && !r->s.seekable) {
        cap = (1L << 17) / cols; /* 1 MB to start with */
        if (cap < 1)
            cap = 1;
        if (cap > r->rows)
            cap = r->rows;
    }
    double *v = NULL;
    if ((size_t)cap > SIZE_MAX / sizeof(double) / (size_t)cols ||
        !(v = malloc((size_t)cap * cols * sizeof(double)))) {
        cli_error("out of memory reading %s (%ld x %d values)", r->path, cap, cols);
        cli_reader_close(r);
        return CLI_SOFTWARE;
    }
    for (;;) {
        if (rows == cap) {
            if (r->npy && rows == r->rows)
                break;
            long nc = cap > LONG_MAX / 2 ? LONG_MAX : cap * 2;
            if (r->npy && nc > r->rows)
                nc = r->rows;
            double *nv = NULL;
            if ((size_t)nc <= SIZE_MAX / sizeof(double) / (size_t)cols)
                nv = realloc(v, (size_t)nc * cols * sizeof(double));
            if (!nv) {
                cli_error("out of memory reading %s (%ld x %d values)", r->path, nc, cols);
                free(v);
                cli_reader_close(r);
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

int cli_one_stdin(int argc, char **argv)
{
    int n = 0;
    for (int i = 1; i < argc; i++)
        if (!strcmp(argv[i], "-") &&
            !(i > 1 && (!strcmp(argv[i - 1], "--out") || !strcmp(argv[i - 1], "--residuals"))))
            n++;
    if (n > 1) {
        cli_error("%s: only one input can be '-' (standard input)", argv[0]);
        return CLI_USAGE;
    }
    return CLI_OK;
}

/* ---- temporary output files, removed on SIGINT/SIGTERM/SIGHUP/SIGPIPE --- */
#define TMP_SLOTS 32
#define TMP_PATH 4096
static char tmp_paths[TMP_SLOTS][TMP_PATH];
static volatile sig_atomic_t tmp_used[TMP_SLOTS];
static int handlers_installed;

static void on_fatal_signal(int sig)
{
    int e = errno;
    for (int i = 0; i < TMP_SLOTS; i++)
        if (tmp_used[i])
            unlink(tmp_paths[i]);
    errno = e;
    raise(sig); /* SA_RESETHAND: the default action now */
}

static void install_handlers(void)
{
    static const int sigs[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};
    if (handlers_installed)
        return;
    handlers_installed = 1;
    for (size_t k = 0; k < sizeof sigs / sizeof sigs[0]; k++) {
        struct sigaction old, sa;
        if (sigaction(sigs[k], NULL, &old) != 0 || old.sa_handler == SIG_IGN)
            continue; /* keep an inherited 'ignore' (nohup) */
        if (old.sa_handler != SIG_DFL)
            continue; /* a host program's own handler */
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_fatal_signal;
        sigemptyset(&sa.sa_mask);
        sa.sa_flags = SA_RESETHAND;
        sigaction(sigs[k], &sa, NULL);
    }
}

/* Slot + 1 of a registered path, 0 when the table is full. */
static int tmp_register(const char *path)
{
    install_handlers();
    if (strlen(path) >= TMP_PATH)
        return 0;
    for (int i = 0; i < TMP_SLOTS; i++)
        if (!tmp_used[i]) {
            memcpy(tmp_paths[i], path, strlen(path) + 1);
            tmp_used[i] = 1;
            return i + 1;
        }
    return 0;
}

static void tmp_unregister(int slot)
{
    if (slot > 0)
        tmp_used[slot - 1] = 0;
}

/* ---- output ------------------------------------------------------------- */
/* The file a path names after following symbolic links (a dangling link
 * names its target), or NULL when out of memory. */
static char *resolve_target(const char *path)
{
    char *cur = strdup(path);
    for (int hop = 0; cur && hop < 40; hop++) {
        struct stat st;
        if (lstat(cur, &st) != 0 || !S_ISLNK(st.st_mode))
            break;
        size_t sz = st.st_size > 0 ? (size_t)st.st_size + 1 : TMP_PATH;
        char *t = malloc(sz + 1);
        if (!t) {
            free(cur);
            return NULL;
        }
        ssize_t k = readlink(cur, t, sz);
        if (k < 0 || (size_t)k >= sz) {
            free(t);
            break;
        }
        t[k] = '\0';
        char *next;
        const char *slash = strrchr(cur, '/');
        if (t[0] == '/' || !slash)
            next = t;
        else {
            size_t dl = (size_t)(slash - cur) + 1;
            next = malloc(dl + (size_t)k + 1);
            if (next) {
                memcpy(next, cur, dl);
                memcpy(next + dl, t, (size_t)k + 1);
            }
            free(t);
            if (!next) {
                free(cur);
                return NULL;
            }
        }
        free(cur);
        cur = next;
    }
    return cur;
}

static int out_oom(cli_out *o, const char *path)
{
    cli_error("out of memory opening %s for writing", path);
    cli_out_abort(o);
    return CLI_SOFTWARE;
}

/* Create the temporary o->tmp ("<path>.tmp." + 6 characters), registered
 * for the signal clean-up before it exists: a fatal signal, delivered to
 * any thread (the numerical libraries run their own), can never leave it
 * behind unregistered. Returns the descriptor or -1 (errno set). */
static int out_mkstemp(cli_out *o)
{
    static const char digits[] = "0123456789abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ";
    static unsigned long counter;
    char *x = o->tmp + strlen(o->tmp) - 6;
    install_handlers();
    for (int tries = 0; tries < 1000; tries++) {
        unsigned long v = (unsigned long)getpid() * 2654435761u ^ (unsigned long)time(NULL) ^
                          (unsigned long)clock() * 40503u ^ ++counter * 0x9e3779b9u;
        for (int k = 0; k < 6; k++, v /= 62)
            x[k] = digits[v % 62];
        o->slot = tmp_register(o->tmp);
        int fd = open(o->tmp, O_RDWR | O_CREAT | O_EXCL, 0600);
        if (fd >= 0)
            return fd;
        int e = errno;
        tmp_unregister(o->slot);
        o->slot = 0;
        errno = e;
        if (e != EEXIST)
            return -1;
    }
    errno = EEXIST;
    return -1;
}

/* A failed open or create: out of memory, or "cannot <what>" and 74. */
static int out_fail(cli_out *o, const char *path, const char *what, int e)
{
    if (e == ENOMEM)
        return out_oom(o, path);
    cli_error("%s: cannot %s: %s", path, what, strerror(e));
    cli_out_abort(o);
    return CLI_IOERR;
}

/* The temporary that will replace o->path; st: the replaced file's (exists). */
static int out_temporary(cli_out *o, const char *path, int exists, const struct stat *st)
{
    size_t n = strlen(o->path);
    if (!(o->tmp = malloc(n + 16)))
        return out_oom(o, path);
    snprintf(o->tmp, n + 16, "%s.tmp.XXXXXX", o->path);
    mode_t um = umask(0);
    umask(um);
    int fd = out_mkstemp(o);
    if (fd < 0) {
        int e = errno;
        free(o->tmp);
        o->tmp = NULL;
        return out_fail(o, path, "create", e);
    }
    /* The replaced file keeps its mode (and owner, when allowed); a new one
     * gets 0666 less the umask, as with a plain open(). */
    if (exists) {
        fchmod(fd, st->st_mode & 07777);
        if (st->st_uid != geteuid() || st->st_gid != getegid())
            if (fchown(fd, st->st_uid, st->st_gid) != 0) {
                /* not allowed: the file becomes ours, with the same mode */
            }
    } else {
        fchmod(fd, 0666 & ~um);
    }
    if (!(o->f = fdopen(fd, "wb"))) {
        int e = errno;
        close(fd);
        return out_fail(o, path, "create", e);
    }
    return CLI_OK;
}

int cli_out_open(cli_out *o, const char *path)
{
    o->f = NULL;
    o->tmp = NULL;
    o->path = NULL;
    o->direct = 0;
    o->slot = 0;
    if (!path || !strcmp(path, "-")) {
        o->f = stdout;
        return CLI_OK;
    }
    /* What the path names, following every link (the kernel's view: also
     * right for /dev/stdout and /proc/self/fd/N); then the file to replace. */
    struct stat st;
    int exists = stat(path, &st) == 0;
    if (!(o->path = exists && !S_ISREG(st.st_mode) ? strdup(path) : resolve_target(path)))
        return out_oom(o, path);
    if (exists && S_ISREG(st.st_mode))
        exists = stat(o->path, &st) == 0;
    if (exists && S_ISDIR(st.st_mode)) {
        cli_error("%s: is a directory", path);
        cli_out_abort(o);
        return CLI_IOERR;
    }
    if (!exists || S_ISREG(st.st_mode))
        return out_temporary(o, path, exists, &st);
    /* A device or a FIFO: written in place, never replaced. */
    if (!(o->f = fopen(o->path, "wb")))
        return out_fail(o, path, "open", errno);
    o->direct = 1;
    return CLI_OK;
}

int cli_stdout_check(void)
{
    errno = 0;
    if (fflush(stdout) != 0 || ferror(stdout)) {
        cli_error("writing standard output: %s", errno ? strerror(errno) : "I/O error");
        return CLI_IOERR;
    }
    return CLI_OK;
}

/* Flush and close; the temporary stays until out_rename. */
static int out_finish(cli_out *o)
{
    if (o->f == stdout)
        return cli_stdout_check();
    errno = 0;
    int bad = fflush(o->f) != 0 || ferror(o->f);
    int e = errno;
    /* The temporary's data reach the disk before it replaces the target, so
     * a crash after the rename never leaves an empty or partial file. */
    if (!bad && o->tmp && !o->direct && fsync(fileno(o->f)) != 0 && errno != EINVAL) {
        bad = 1;
        e = errno;
    }
    if (fclose(o->f) != 0 && !bad) {
        bad = 1;
        e = errno;
    }
    o->f = NULL;
    if (bad) {
        cli_error("%s: write failed: %s", o->path, e ? strerror(e) : "I/O error");
        return CLI_IOERR;
    }
    return CLI_OK;
}

static int out_rename(cli_out *o)
{
    if (o->f == stdout || o->direct || !o->tmp)
        return CLI_OK;
    if (rename(o->tmp, o->path) != 0) {
        cli_error("%s: cannot replace: %s", o->path, strerror(errno));
        return CLI_IOERR;
    }
    tmp_unregister(o->slot);
    o->slot = 0;
    free(o->tmp);
    o->tmp = NULL;
    return CLI_OK;
}

int cli_out_commit(cli_out *o)
{
    return cli_out_commit_all(o, 1);
}

int cli_out_commit_all(cli_out *o, int n)
{
    int ec = CLI_OK;
    for (int i = 0; i < n; i++) {
        int e = out_finish(&o[i]);
        if (e && !ec)
            ec = e;
    }
    for (int i = 0; !ec && i < n; i++)
        ec = out_rename(&o[i]);
    for (int i = 0; i < n; i++) {
        if (ec)
            cli_out_abort(&o[i]);
        else if (o[i].f != stdout) {
            free(o[i].path);
            o[i].path = NULL;
        }
    }
    return ec;
}

void cli_out_abort(cli_out *o)
{
    if (o->f && o->f != stdout)
        fclose(o->f);
    o->f = NULL;
    if (o->tmp)
        unlink(o->tmp);
    tmp_unregister(o->slot);
    o->slot = 0;
    free(o->tmp);
    free(o->path);
    o->tmp = o->path = NULL;
}

void cli_write_matrix_body(FILE *f, int npy, const double *v, long rows, int cols,
                           const char *header)
{
    if (npy) {
        char h[128];
        int hl = snprintf(h, sizeof h,
                          "{'descr': '<f8', 'fortran_order': False, 'shape': (%ld, %d), }",
                          rows, cols);
        int total = 10 + hl + 1;
        int pad = (64 - total % 64) % 64;
        unsigned short hlen = (unsigned short)(hl + pad + 1);
        fwrite("\x93NUMPY\x01\x00", 1, 8, f);
        unsigned char le[2] = {(unsigned char)(hlen & 0xff), (unsigned char)(hlen >> 8)};
        fwrite(le, 1, 2, f);
        fwrite(h, 1, (size_t)hl, f);
        for (int i = 0; i < pad; i++)
            fputc(' ', f);
        fputc('\n', f);
        fwrite(v, sizeof(double), (size_t)rows * cols, f);
    } else {
        if (header)
            fprintf(f, "# %s\n", header);
        for (long i = 0; i < rows; i++)
            for (int j = 0; j < cols; j++)
                fprintf(f, "%.17g%c", v[i * cols + j], j + 1 < cols ? ' ' : '\n');
    }
}

int cli_write_matrix(const char *path, const double *v, long rows, int cols,
                     const char *header)
{
    cli_out o;
    int ec = cli_out_open(&o, path);
    if (ec)
        return ec;
    cli_write_matrix_body(o.f, path && ends_with(path, ".npy"), v, rows, cols, header);
    return cli_out_commit(&o);
}


int cli_read_vector(const char *path, long n, const char *what, double **out, long *count)
{
    cli_matrix m = {0};
    int ec = cli_read_matrix(path, &m);
    if (ec)
        return ec;
    long got = m.rows * m.cols;
    if (n >= 0 && got != n) {
        cli_error("%s: %ld values, but %s needs %ld", path, got, what, n);
        cli_matrix_free(&m);
        return CLI_DATAERR;
    }
    if (count)
        *count = got;
    *out = m.v;
    return CLI_OK;
}

int cli_read_values(const char *arg, long n, const char *what, double **out, long *count)
{
    char *end;
    errno = 0;
    double x = strtod(arg, &end);
    if (end == arg || *end != '\0')
        return cli_read_vector(arg, n, what, out, count);
    if (!(x > 0) || !isfinite(x)) {
        cli_error("%s %s: must be a positive number or a file", what, arg);
        return CLI_USAGE;
    }
    if (n < 1) {
        cli_error("%s must be a file here", what);
        return CLI_USAGE;
    }
    if (!(*out = malloc(sizeof(double) * (size_t)n)))
        return cli_oom(what);
    for (long i = 0; i < n; i++)
        (*out)[i] = x;
    if (count)
        *count = n;
    return CLI_OK;
}
