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
    switch (igea_status_class(status)) {
    case IGEA_STATUS_DATA: return CLI_DATAERR;
    case IGEA_STATUS_INPUT: return CLI_NOINPUT;
    default: return CLI_SOFTWARE; /* an argument the driver passed, a failure, memory */
    }
}

int cli_parse_double(const char *opt, const char *s, double *out)
{
    if (igea_io_parse_number(s, out) != 0) {
        cli_error("option %s: '%s' is not a finite number", opt, s);
        return CLI_USAGE;
    }
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
    double x = 0;
    int st = igea_io_parse_number(v, &x);
    if (st == IGEA_EFORMAT)
        return CLI_OK; /* a file name */
    if (st || !(x > 0)) {
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

/* ---- input: the library's reader (igea/io.h) -------------------------------
 * The driver opens "-" as standard input, keeps the name it shows in
 * messages, creates temporary copies in $TMPDIR and turns the reader's
 * errors into "PATH:LINE:COL: message" and an exit code. */
struct cli_reader {
    igea_io_reader *r;
    char *path; /* as given, or "<stdin>" */
};

/* The reader's failure st as a message naming path, and its exit code. */
static int reader_failed(const char *path, const igea_io_reader *r, int st)
{
    double info[IGEA_IO_INFO_LEN];
    igea_io_reader_info(r, info);
    long line = (long)info[IGEA_IO_INFO_LINE], col = (long)info[IGEA_IO_INFO_COLUMN];
    int e = (int)info[IGEA_IO_INFO_ERRNO];
    const char *msg = igea_io_reader_message(r);
    if (st == IGEA_ENOMEM) {
        cli_error("out of memory reading %s", path);
        return CLI_SOFTWARE;
    }
    if (line > 0 && col > 0)
        cli_error("%s:%ld:%ld: %s", path, line, col, msg);
    else if (line > 0)
        cli_error("%s:%ld: %s", path, line, msg);
    else if (e && *msg)
        cli_error("%s: %s: %s", path, msg, strerror(e));
    else if (e)
        cli_error("%s: %s", path, strerror(e));
    else
        cli_error("%s: %s%s", path, st == IGEA_EFORMAT || st == IGEA_EREAD ||
                  st == IGEA_ETEMPFILE ? "" : "internal error: ", msg);
    switch (st) {
    case IGEA_EFORMAT: return CLI_DATAERR;
    case IGEA_EREAD: return CLI_NOINPUT;
    case IGEA_ETEMPFILE: return CLI_IOERR;
    default: return CLI_SOFTWARE;
    }
}

static int reader_open(const char *path, int flags, cli_reader **out)
{
    int is_stdin = !strcmp(path, "-");
    cli_reader *c = calloc(1, sizeof *c);
    if (c && !(c->path = strdup(is_stdin ? "<stdin>" : path))) {
        free(c);
        c = NULL;
    }
    if (!c || igea_io_reader_create(&c->r) != 0) {
        cli_error("out of memory opening %s", path);
        cli_reader_close(c);
        return CLI_SOFTWARE;
    }
    const char *tmp = getenv("TMPDIR");
    int st = is_stdin ? igea_io_reader_open_fd(c->r, 0, c->path, flags, tmp)
                      : igea_io_reader_open(c->r, path, flags, tmp);
    if (st) {
        int ec = reader_failed(c->path, c->r, st);
        cli_reader_close(c);
        return ec;
    }
    *out = c;
    return CLI_OK;
}

static void install_sigbus(void);

int cli_reader_open(const char *path, cli_reader **out) { return reader_open(path, 0, out); }
int cli_reader_open_gaps(const char *path, cli_reader **out)
{
    return reader_open(path, IGEA_IO_NAN, out);
}
int cli_reader_open_twice(const char *path, cli_reader **out)
{
    install_sigbus(); /* a .npy viewed through a map (cli_reader_view) */
    return reader_open(path, IGEA_IO_TWICE | IGEA_IO_MAP, out);
}

int cli_reader_open_unchecked(const char *path, cli_reader **out)
{
    install_sigbus();
    return reader_open(path, IGEA_IO_TWICE | IGEA_IO_MAP | IGEA_IO_UNCHECKED, out);
}

int cli_reader_rewind(cli_reader *r)
{
    int st = igea_io_reader_rewind(r->r);
    return st ? reader_failed(r->path, r->r, st) : CLI_OK;
}

int cli_reader_cols(const cli_reader *r) { return igea_io_reader_cols(r->r); }
long cli_reader_rows_known(const cli_reader *r)
{
    double info[IGEA_IO_INFO_LEN];
    igea_io_reader_info(r->r, info);
    return info[IGEA_IO_INFO_NPY] != 0 && info[IGEA_IO_INFO_CHECKED] != 0
               ? (long)info[IGEA_IO_INFO_NPY_ROWS] : -1;
}
int cli_reader_npy_data(const cli_reader *r, double *data, int *fortran)
{
    double info[IGEA_IO_INFO_LEN];
    igea_io_reader_info(r->r, info);
    if (info[IGEA_IO_INFO_NPY_DATA] < 0)
        return 0;
    *data = info[IGEA_IO_INFO_NPY_DATA];
    *fortran = info[IGEA_IO_INFO_NPY_FORTRAN] != 0;
    return 1;
}
const char *cli_reader_path(const cli_reader *r) { return r->path; }
const char *cli_reader_names(const cli_reader *r) { return igea_io_reader_names(r->r); }

int cli_reader_next(cli_reader *r, long maxrows, double *buf, long *nread)
{
    int got = 0;
    int st = igea_io_reader_next(r->r, maxrows > INT_MAX ? INT_MAX : (int)maxrows, buf, &got);
    if (st)
        return reader_failed(r->path, r->r, st);
    *nread = got;
    return CLI_OK;
}

int cli_reader_view_check(cli_reader *r)
{
    int st = r ? igea_io_reader_view_check(r->r) : 0;
    return st ? reader_failed(r->path, r->r, st) : CLI_OK;
}

int cli_reader_view_after(cli_reader *r, long maxrows, const double **rows, long *nread,
                          cli_reader *unchecked)
{
    int got = 0;
    int st = igea_io_reader_view(r->r, maxrows > INT_MAX ? INT_MAX : (int)maxrows, &got);
    if (st) {
        int ec = cli_reader_view_check(unchecked);
        return ec ? ec : reader_failed(r->path, r->r, st);
    }
    *rows = igea_io_reader_view_rows(r->r);
    *nread = got;
    return CLI_OK;
}

int cli_reader_view(cli_reader *r, long maxrows, const double **rows, long *nread)
{
    return cli_reader_view_after(r, maxrows, rows, nread, NULL);
}

void cli_reader_close(cli_reader *r)
{
    if (!r)
        return;
    igea_io_reader_free(r->r);
    free(r->path);
    free(r);
}

/* Grow *v (cap rows of cols) to hold need rows: CLI_OK or a message. */
static int matrix_room(const cli_reader *r, double **v, long *cap, long need, long most)
{
    int cols = cli_reader_cols(r);
    if (need <= *cap)
        return CLI_OK;
    long nc = *cap > LONG_MAX / 2 ? LONG_MAX : *cap * 2;
    if (nc < need)
        nc = need;
    if (most > 0 && nc > most)
        nc = most;
    double *nv = NULL;
    if ((size_t)nc <= SIZE_MAX / sizeof(double) / (size_t)cols)
        nv = realloc(*v, (size_t)nc * cols * sizeof(double));
    if (!nv) {
        cli_error("out of memory reading %s (%ld x %d values)", r->path, nc, cols);
        return CLI_SOFTWARE;
    }
    *v = nv;
    *cap = nc;
    return CLI_OK;
}

/* The driver's whole read grows its own malloc'd array as the rows arrive
 * (the commands free it), so a large record is held once, not copied out of
 * the reader (igea_io_reader_load is for hosts that copy into their own
 * arrays). A .npy states its rows: the array is sized from them once the
 * reader has checked them against the bytes present. */
int cli_read_matrix(const char *path, cli_matrix *out)
{
    cli_reader *r;
    int ec = cli_reader_open(path, &r);
    if (ec)
        return ec;
    double info[IGEA_IO_INFO_LEN];
    igea_io_reader_info(r->r, info);
    int cols = cli_reader_cols(r);
    long rows = 0, cap = 0, most = 0, first = 1024;
    double *v = NULL;
    if (info[IGEA_IO_INFO_NPY] != 0) {
        most = (long)info[IGEA_IO_INFO_NPY_ROWS];
        first = info[IGEA_IO_INFO_CHECKED] != 0 ? most : (1L << 17) / cols; /* 1 MB */
        if (first < 1)
            first = 1;
        if (first > most)
            first = most;
    }
    ec = matrix_room(r, &v, &cap, first, most);
    while (!ec) {
        if (rows == cap && most > 0 && rows >= most)
            break; /* a .npy's stated rows, all read */
        if (rows == cap && (ec = matrix_room(r, &v, &cap, rows + 1, most)))
            break;
        long got = 0;
        if ((ec = cli_reader_next(r, cap - rows, v + rows * cols, &got)) || got == 0)
            break;
        rows += got;
    }
    cli_reader_close(r);
    if (ec) {
        free(v);
        return ec;
    }
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

/* A file mapped by the reader (IGEA_IO_MAP) that another process shortens
 * while a block of it is read raises SIGBUS: the temporary outputs are
 * removed and the driver exits 66 with a message instead of a core dump. */
static void on_sigbus(int sig)
{
    static const char msg[] = "igea: an input file was shortened while it was being read "
                              "(SIGBUS)\n";
    (void)sig;
    for (int i = 0; i < TMP_SLOTS; i++)
        if (tmp_used[i])
            unlink(tmp_paths[i]);
    if (write(2, msg, sizeof msg - 1) < 0) {
        /* nothing more can be done in a signal handler */
    }
    _exit(CLI_NOINPUT);
}

static void install_sigbus(void)
{
    struct sigaction old, sa;
    if (sigaction(SIGBUS, NULL, &old) != 0 || old.sa_handler != SIG_DFL)
        return; /* a host program's own handler, or an inherited 'ignore' */
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_sigbus;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGBUS, &sa, NULL);
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

static int ends_with(const char *s, const char *suf)
{
    size_t n = strlen(s), k = strlen(suf);
    return n >= k && strcmp(s + n - k, suf) == 0;
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
    double x = 0;
    int st = igea_io_parse_number(arg, &x);
    if (st == IGEA_EFORMAT)
        return cli_read_vector(arg, n, what, out, count);
    if (st || !(x > 0)) {
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
