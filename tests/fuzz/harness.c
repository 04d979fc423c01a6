/* tests/fuzz/harness.c - see harness.h. */
#include "harness.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"

/* The driver's entry (dispatch and the check of standard output) when it
 * has one; else the command functions are called directly. */
int cli_run(int argc, char **argv);
#pragma weak cli_run

/* The two-pass reader, compared with the one-pass reads when present. */
int cli_reader_open_twice(const char *path, cli_reader **out);
int cli_reader_rewind(cli_reader *r);
#pragma weak cli_reader_open_twice
#pragma weak cli_reader_rewind

/* The sanitizer runtime's report descriptor (present under -fsanitize). */
void __sanitizer_set_report_fd(void *fd);

static char root[4096];     /* private directory of this process */
static char work[4200];     /* root/w: the commands' working directory */
static int work_fd = -1;
static int home_fd = -1;    /* the working directory to return to */
static int err_fd = -1;     /* the original stderr, for the harness's reports */
static int out_fd = -1;     /* capture file of stdout */
static int errcap_fd = -1;  /* capture file of stderr (once libFuzzer closed it) */
static int full_fd = -1;    /* /dev/full */
static int null_rdev_ok;
static dev_t null_rdev;
static const fz_run *current;

static int is_input(const fz_run *r, const char *name);

static void rm_tree_at(int dfd)
{
    int fd = dup(dfd);
    DIR *d = fd >= 0 ? fdopendir(fd) : NULL;
    if (!d) {
        if (fd >= 0)
            close(fd);
        return;
    }
    rewinddir(d);
    struct dirent *e;
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        struct stat st;
        if (fstatat(dfd, e->d_name, &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISDIR(st.st_mode)) {
            int sub = openat(dfd, e->d_name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW);
            if (sub >= 0) {
                rm_tree_at(sub);
                close(sub);
            }
            unlinkat(dfd, e->d_name, AT_REMOVEDIR);
        } else
            unlinkat(dfd, e->d_name, 0);
    }
    closedir(d);
}

static void remove_root(void)
{
    if (!root[0])
        return;
    int fd = open(root, O_RDONLY | O_DIRECTORY);
    if (fd >= 0) {
        rm_tree_at(fd);
        close(fd);
    }
    rmdir(root);
    root[0] = '\0';
}

void fz_clean(void)
{
    if (work_fd >= 0)
        rm_tree_at(work_fd);
}

const char *fz_dir(void) { return work; }

void fz_fail(const char *fmt, ...)
{
    char msg[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    int fd = err_fd >= 0 ? err_fd : 2;
    dprintf(fd, "igea-fuzz: %s\n", msg);
    if (current) {
        dprintf(fd, "igea-fuzz: command line:");
        for (int i = 0; i < current->argc; i++)
            dprintf(fd, " %s", current->argv[i]);
        dprintf(fd, "\n");
        for (int k = 0; k < current->nfiles; k++)
            dprintf(fd, "igea-fuzz: file %s: %zu bytes\n", current->name[k], current->len[k]);
    }
    abort();
}

void fz_init(void)
{
    static int done;
    if (done)
        return;
    done = 1;
    err_fd = fcntl(2, F_DUPFD_CLOEXEC, 10);
    __sanitizer_set_report_fd((void *)(intptr_t)(err_fd >= 0 ? err_fd : 2));
    const char *tmp = getenv("TMPDIR");
    snprintf(root, sizeof root, "%s/igea-fuzz-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(root)) {
        root[0] = '\0';
        fz_fail("mkdtemp under %s: %s", tmp && *tmp ? tmp : "/tmp", strerror(errno));
    }
    atexit(remove_root);
    snprintf(work, sizeof work, "%s/w", root);
    if (mkdir(work, 0700) != 0 || (work_fd = open(work, O_RDONLY | O_DIRECTORY)) < 0)
        fz_fail("%s: %s", work, strerror(errno));
    home_fd = open(".", O_RDONLY | O_DIRECTORY);
    int devnull = open("/dev/null", O_RDWR);
    if (devnull < 0 || dup2(devnull, 0) < 0)
        fz_fail("/dev/null: %s", strerror(errno));
    struct stat st;
    if (fstat(devnull, &st) == 0) {
        null_rdev = st.st_rdev;
        null_rdev_ok = 1;
    }
    close(devnull);
    /* /dev/full only when it really is the full device (a test elsewhere
     * that replaced it with a file would make every write succeed) */
    full_fd = open("/dev/full", O_WRONLY | O_CLOEXEC);
    if (full_fd >= 0 && (fstat(full_fd, &st) != 0 || !S_ISCHR(st.st_mode) ||
                         write(full_fd, "x", 1) != -1 || errno != ENOSPC)) {
        dprintf(err_fd, "igea-fuzz: /dev/full is not the full device: the check of exit 74 "
                        "on a failed write is skipped\n");
        close(full_fd);
        full_fd = -1;
    }
    char p[4300];
    snprintf(p, sizeof p, "%s/stdout", root);
    fflush(stdout);
    if ((out_fd = open(p, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600)) < 0 ||
        dup2(out_fd, 1) < 0)
        fz_fail("%s: %s", p, strerror(errno));
}

/* stderr is captured only when libFuzzer has already sent it to /dev/null
 * (-close_fd_mask=2): its own output and the sanitizers' reports then go to
 * a copy of the original. */
static void capture_stderr(void)
{
    static int tried;
    if (tried)
        return;
    tried = 1;
    struct stat st;
    if (!null_rdev_ok || fstat(2, &st) != 0 || !S_ISCHR(st.st_mode) || st.st_rdev != null_rdev)
        return;
    char p[4300];
    snprintf(p, sizeof p, "%s/stderr", root);
    errcap_fd = open(p, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (errcap_fd >= 0 && dup2(errcap_fd, 2) < 0) {
        close(errcap_fd);
        errcap_fd = -1;
    }
}

int fz_write(const char *name, const void *p, size_t n)
{
    int fd = openat(work_fd, name, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
        return -1;
    const char *c = p;
    while (n > 0) {
        ssize_t w = write(fd, c, n);
        if (w <= 0) {
            close(fd);
            return -1;
        }
        c += w;
        n -= (size_t)w;
    }
    return close(fd);
}

double fz_opt_num(const fz_run *r, const char *opt, double dflt)
{
    double v = dflt;
    for (int i = 0; i + 1 < r->argc; i++)
        if (!strcmp(r->argv[i], opt)) {
            char *end;
            double x = strtod(r->argv[i + 1], &end);
            v = end != r->argv[i + 1] && *end == '\0' ? x : dflt;
        }
    return v;
}

int fz_has(const fz_run *r, const char *token)
{
    for (int i = 0; i < r->argc; i++)
        if (!strcmp(r->argv[i], token))
            return 1;
    return 0;
}

const char *fz_opt_str(const fz_run *r, const char *opt)
{
    const char *v = NULL;
    for (int i = 0; i + 1 < r->argc; i++)
        if (!strcmp(r->argv[i], opt))
            v = r->argv[i + 1];
    return v;
}

long fz_values(const fz_run *r, const char *name)
{
    if (name && !strcmp(name, "-"))
        name = "stdin";
    if (!name || is_input(r, name) < 0)
        return 0;
    if (fchdir(work_fd) != 0)
        fz_fail("chdir %s: %s", work, strerror(errno));
    cli_matrix m;
    long rows = 0;
    if (cli_read_matrix(name, &m) == CLI_OK) {
        rows = m.rows * m.cols;
        cli_matrix_free(&m);
    }
    if (home_fd >= 0 && fchdir(home_fd) != 0)
        fz_fail("chdir back: %s", strerror(errno));
    return rows;
}

double fz_max_abs(const fz_run *r)
{
    double mx = 0.0;
    if (fchdir(work_fd) != 0)
        fz_fail("chdir %s: %s", work, strerror(errno));
    for (int k = 0; k < r->nfiles; k++) {
        cli_matrix m;
        if (cli_read_matrix(r->name[k], &m) != CLI_OK)
            continue;
        for (long i = 0; i < m.rows * m.cols; i++)
            if (fabs(m.v[i]) > mx)
                mx = fabs(m.v[i]);
        cli_matrix_free(&m);
    }
    if (home_fd >= 0 && fchdir(home_fd) != 0)
        fz_fail("chdir back: %s", strerror(errno));
    return mx;
}

/* ---- parsing the input ----------------------------------------------- */
static char tokbuf[8192];

static int valid_name(const char *s, size_t n)
{
    if (n < 1 || n > FZ_NAME_MAX || s[0] == '.')
        return 0;
    for (size_t i = 0; i + 5 <= n; i++)
        if (!memcmp(s + i, ".tmp.", 5))
            return 0; /* the name of a command's temporary file */
    for (size_t i = 0; i < n; i++) {
        char c = s[i];
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
              c == '.' || c == '_' || c == '-'))
            return 0;
    }
    return 1;
}

/* Offset of the next section header ("%% " at a line start) at or after
 * pos, or size. */
static size_t next_header(const uint8_t *d, size_t size, size_t pos)
{
    for (size_t i = pos; i + 3 <= size; i++)
        if ((i == 0 || d[i - 1] == '\n') && d[i] == '%' && d[i + 1] == '%' && d[i + 2] == ' ')
            return i;
    return size;
}

static int parse(fz_run *r, const char *name, const char *const *prefix, const uint8_t *d,
                 size_t size)
{
    size_t tb = 0;
    r->argc = 0;
    r->nfiles = 0;
#define ADD_TOKEN(s, n)                                                                 \
    do {                                                                                \
        if (r->argc >= FZ_MAX_ARGS || tb + (n) + 1 > sizeof tokbuf)                     \
            return -1;                                                                  \
        memcpy(tokbuf + tb, (s), (n));                                                  \
        tokbuf[tb + (n)] = '\0';                                                        \
        r->argv[r->argc++] = tokbuf + tb;                                               \
        tb += (n) + 1;                                                                  \
    } while (0)
    ADD_TOKEN(name, strlen(name));
    for (int i = 0; prefix && prefix[i]; i++)
        ADD_TOKEN(prefix[i], strlen(prefix[i]));
    size_t end = next_header(d, size, 0);
    for (size_t i = 0; i < end;) {
        while (i < end && (d[i] == ' ' || d[i] == '\t' || d[i] == '\n' || d[i] == '\r' ||
                           d[i] == '\0'))
            i++;
        size_t j = i;
        while (j < end && !(d[j] == ' ' || d[j] == '\t' || d[j] == '\n' || d[j] == '\r' ||
                            d[j] == '\0'))
            j++;
        if (j > i) {
            if (j - i > 64 || memchr(d + i, '/', j - i))
                return -1; /* every path stays inside the private directory */
            ADD_TOKEN((const char *)d + i, j - i);
        }
        i = j;
    }
#undef ADD_TOKEN
    r->argv[r->argc] = NULL;
    size_t pos = end;
    while (pos < size) {
        size_t nl = pos + 3;
        while (nl < size && d[nl] != '\n')
            nl++;
        size_t ns = pos + 3, ne = nl;
        while (ne > ns && (d[ne - 1] == ' ' || d[ne - 1] == '\r'))
            ne--;
        if (r->nfiles >= FZ_MAX_FILES || !valid_name((const char *)d + ns, ne - ns))
            return -1;
        int k = r->nfiles;
        memcpy(r->name[k], d + ns, ne - ns);
        r->name[k][ne - ns] = '\0';
        for (int q = 0; q < k; q++)
            if (!strcmp(r->name[q], r->name[k]))
                return -1;
        size_t cs = nl < size ? nl + 1 : size;
        size_t ce = next_header(d, size, cs);
        r->data[k] = d + cs;
        r->len[k] = ce - cs;
        r->nfiles++;
        pos = ce;
    }
    return 0;
}

/* ---- checking a run --------------------------------------------------- */
static int is_input(const fz_run *r, const char *name)
{
    for (int k = 0; k < r->nfiles; k++)
        if (!strcmp(r->name[k], name))
            return k;
    return -1;
}

static int same_content(int dfd, const char *name, const uint8_t *p, size_t n)
{
    int fd = openat(dfd, name, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return 0;
    uint8_t buf[4096];
    size_t at = 0;
    int same = 1;
    for (;;) {
        ssize_t got = read(fd, buf, sizeof buf);
        if (got < 0) {
            same = 0;
            break;
        }
        if (got == 0)
            break;
        if (at + (size_t)got > n || memcmp(buf, p + at, (size_t)got) != 0) {
            same = 0;
            break;
        }
        at += (size_t)got;
    }
    close(fd);
    return same && at == n;
}

/* Walk the directory: a *.tmp.* file is always an error; after a failed run
 * (failed = 1) so is any file that is not an input, and any changed input. */
static void check_dir(const fz_run *r, int dfd, const char *rel, int failed, int rc)
{
    int fd = dup(dfd);
    DIR *d = fd >= 0 ? fdopendir(fd) : NULL;
    if (!d)
        fz_fail("opendir %s: %s", rel, strerror(errno));
    rewinddir(d);
    struct dirent *e;
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        struct stat st;
        if (fstatat(dfd, e->d_name, &st, AT_SYMLINK_NOFOLLOW) != 0)
            continue;
        if (S_ISDIR(st.st_mode)) {
            int sub = openat(dfd, e->d_name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW);
            if (sub >= 0) {
                char p[512];
                snprintf(p, sizeof p, "%s%s/", rel, e->d_name);
                check_dir(r, sub, p, failed, rc);
                close(sub);
            }
            continue;
        }
        if (strstr(e->d_name, ".tmp.") && !fz_has(r, e->d_name))
            fz_fail("exit %d left the temporary file %s%s", rc, rel, e->d_name);
        if (!failed)
            continue;
        int k = rel[0] ? -1 : is_input(r, e->d_name);
        if (k < 0)
            fz_fail("exit %d (a failure) left the file %s%s", rc, rel, e->d_name);
        if (!same_content(dfd, e->d_name, r->data[k], r->len[k]))
            fz_fail("exit %d (a failure) changed the input file %s", rc, e->d_name);
    }
    closedir(d);
}

/* Temporary files the driver makes outside the working directory (the
 * spool of a non-seekable input) are unlinked at once: none may remain in
 * TMPDIR. Checked only when TMPDIR is a private directory (run.sh). */
static void check_tmpdir(void)
{
    static int use = -1;
    static const char *dir;
    if (use < 0) {
        dir = getenv("TMPDIR");
        use = dir && *dir && strcmp(dir, "/tmp") != 0 && strcmp(dir, "/tmp/") != 0;
    }
    if (!use)
        return;
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir(d)))
        if (!strncmp(e->d_name, "igea-spool.", 11)) {
            char name[256];
            snprintf(name, sizeof name, "%s", e->d_name);
            closedir(d);
            fz_fail("the temporary file %s/%s was left", dir, name);
        }
    closedir(d);
}

static off_t fd_size(int fd)
{
    struct stat st;
    return fstat(fd, &st) == 0 ? st.st_size : -1;
}

static void reset_capture(void)
{
    fflush(stdout);
    if (ftruncate(out_fd, 0) != 0)
        fz_fail("truncating the stdout capture: %s", strerror(errno));
    rewind(stdout);
    if (errcap_fd >= 0) {
        if (ftruncate(errcap_fd, 0) != 0)
            fz_fail("truncating the stderr capture: %s", strerror(errno));
        rewind(stderr);
    }
}

static int write_inputs(const fz_run *r)
{
    fz_clean();
    for (int k = 0; k < r->nfiles; k++)
        if (fz_write(r->name[k], r->data[k], r->len[k]) != 0)
            fz_fail("writing %s/%s: %s", work, r->name[k], strerror(errno));
    return 0;
}

static int stdin_pipe(const void *p, size_t n);
static void stdin_null(void);

static int call(int (*cmd)(int, char **), const fz_run *r)
{
    static char igea[] = "igea";
    static char *argv[FZ_MAX_ARGS + 2];
    argv[0] = igea;
    for (int i = 0; i <= r->argc; i++)
        argv[i + 1] = r->argv[i];
    if (fchdir(work_fd) != 0)
        fz_fail("chdir %s: %s", work, strerror(errno));
    int k = is_input(r, "stdin");
    if (k >= 0 && stdin_pipe(r->data[k], r->len[k]) != 0)
        fz_fail("a pipe as standard input: %s", strerror(errno));
    clearerr(stdin);
    int rc = cli_run ? cli_run(r->argc + 1, argv) : cmd(r->argc, argv + 1);
    fflush(stdout);
    fflush(stderr);
    if (k >= 0)
        stdin_null();
    if (home_fd >= 0 && fchdir(home_fd) != 0)
        fz_fail("chdir back: %s", strerror(errno));
    return rc;
}

static int documented(int rc, int flags)
{
    return rc == CLI_OK || (rc == CLI_REJECT && (flags & FZ_VERDICT)) || rc == CLI_USAGE ||
           rc == CLI_DATAERR || rc == CLI_NOINPUT || rc == CLI_SOFTWARE || rc == CLI_IOERR;
}

int fz_command(const char *name, int (*cmd)(int, char **), const char *const *prefix,
               int flags, int (*guard)(const fz_run *), const uint8_t *data, size_t size)
{
    static fz_run r;
    fz_init();
    capture_stderr();
    if (parse(&r, name, prefix, data, size) != 0)
        return 0;
    current = &r;
    write_inputs(&r);
    if (guard && guard(&r)) {
        fz_clean();
        current = NULL;
        return 0;
    }
    reset_capture();
    int rc = call(cmd, &r);
    static int trace = -1;
    if (trace < 0)
        trace = getenv("IGEA_FUZZ_TRACE") != NULL;
    if (trace) {
        dprintf(err_fd, "igea-fuzz: exit %d:", rc);
        for (int i = 0; i < r.argc; i++)
            dprintf(err_fd, " %s", r.argv[i]);
        dprintf(err_fd, "\n");
    }
    if (!documented(rc, flags))
        fz_fail("undocumented exit status %d", rc);
    int failed = rc != CLI_OK && rc != CLI_REJECT;
    check_dir(&r, work_fd, "", failed, rc);
    check_tmpdir();
    off_t nout = fd_size(out_fd);
    if (failed && nout > 0 && !(flags & FZ_STREAMS))
        fz_fail("exit %d (a failure) after writing %lld bytes to standard output", rc,
                (long long)nout);
    if (failed && errcap_fd >= 0 && fd_size(errcap_fd) == 0)
        fz_fail("exit %d (a failure) without a message on standard error", rc);
    if (!failed && nout > 0 && full_fd >= 0) {
        /* The same run with its result going to a full device. */
        write_inputs(&r);
        reset_capture();
        if (dup2(full_fd, 1) < 0)
            fz_fail("dup2 /dev/full: %s", strerror(errno));
        int rc2 = call(cmd, &r);
        clearerr(stdout);
        if (dup2(out_fd, 1) < 0)
            fz_fail("dup2 stdout capture: %s", strerror(errno));
        rewind(stdout);
        if (rc2 != CLI_IOERR)
            fz_fail("exit %d with standard output on /dev/full (a write error must give 74; "
                    "the run to a file gave %d)", rc2, rc);
        check_dir(&r, work_fd, "", 0, rc2);
        if (errcap_fd >= 0 && fd_size(errcap_fd) == 0)
            fz_fail("exit 74 without a message on standard error");
    }
    fz_clean();
    current = NULL;
    return 0;
}

/* libFuzzer calls this once before the first input. */
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    igea_init();
    fz_init();
    return 0;
}

/* ---- readers ------------------------------------------------------------ */
static int reader_code(int ec)
{
    return ec == CLI_OK || ec == CLI_DATAERR || ec == CLI_NOINPUT || ec == CLI_SOFTWARE;
}

typedef struct {
    long rows;
    int cols;
    double *v;
} fz_mat;

/* One pass of an open reader in random blocks into m (appended). */
static int stream_pass(cli_reader *rd, uint32_t *seed, fz_mat *m)
{
    m->cols = cli_reader_cols(rd);
    if (m->cols < 1)
        fz_fail("cli_reader_open: success with %d columns", m->cols);
    for (;;) {
        uint32_t u = fz_rand(seed);
        long block = (u & 3) == 0 ? 1 + (long)(u >> 8) % 1000 : 1 + (long)(u >> 8) % 5;
        /* exactly block rows: an overrun is seen by the address sanitizer */
        double *buf = malloc((size_t)block * (size_t)m->cols * sizeof(double));
        if (!buf)
            fz_fail("out of memory in the harness");
        long got = -1;
        int ec = cli_reader_next(rd, block, buf, &got);
        if (ec != CLI_OK) {
            free(buf);
            return ec;
        }
        if (got < 0 || got > block)
            fz_fail("cli_reader_next: %ld rows for a block of %ld", got, block);
        if (got == 0) {
            free(buf);
            return CLI_OK;
        }
        double *na = realloc(m->v, (size_t)(m->rows + got) * (size_t)m->cols * sizeof(double));
        if (!na)
            fz_fail("out of memory in the harness");
        m->v = na;
        memcpy(m->v + m->rows * m->cols, buf, (size_t)got * (size_t)m->cols * sizeof(double));
        m->rows += got;
        free(buf);
    }
}

/* Open path (twice: for two passes, the second compared with the first) and
 * read it streamed. */
static int stream_read(const char *path, int twice, uint32_t *seed, fz_mat *m)
{
    cli_reader *rd = (cli_reader *)&rd, *sentinel = rd;
    int ec = twice ? cli_reader_open_twice(path, &rd) : cli_reader_open(path, &rd);
    if (ec != CLI_OK) {
        if (rd != sentinel)
            fz_fail("cli_reader_open%s failed (%d) but changed its output", twice ? "_twice" : "",
                    ec);
        return ec;
    }
    ec = stream_pass(rd, seed, m);
    if (ec == CLI_OK && twice) {
        fz_mat again = {0, 0, NULL};
        ec = cli_reader_rewind(rd);
        if (ec == CLI_OK)
            ec = stream_pass(rd, seed, &again);
        if (ec == CLI_OK &&
            (again.rows != m->rows || again.cols != m->cols ||
             memcmp(again.v, m->v, (size_t)m->rows * (size_t)m->cols * sizeof(double)) != 0))
            fz_fail("%s: the second pass (cli_reader_rewind) differs from the first", path);
        free(again.v);
    }
    cli_reader_close(rd);
    return ec;
}

static void compare(const char *what, int ec1, const cli_matrix *m, int ec2, const fz_mat *s)
{
    if (!reader_code(ec2))
        fz_fail("%s: exit code %d", what, ec2);
    if (ec1 != ec2)
        fz_fail("whole read gives %d, %s gives %d", ec1, what, ec2);
    if (ec1 != CLI_OK)
        return;
    if (s->rows != m->rows || s->cols != m->cols)
        fz_fail("whole read %ld x %d, %s %ld x %d", m->rows, m->cols, what, s->rows, s->cols);
    if (memcmp(s->v, m->v, (size_t)s->rows * (size_t)s->cols * sizeof(double)) != 0)
        fz_fail("whole read and %s differ in their bits", what);
}

/* Standard input becomes a pipe holding p[0..n) (n fits the pipe buffer);
 * returns 0, or -1 when it could not be set up. */
static int stdin_pipe(const void *p, size_t n)
{
    int fd[2];
    if (pipe(fd) != 0)
        return -1;
    const char *c = p;
    while (n > 0) {
        ssize_t w = write(fd[1], c, n > 4096 ? 4096 : n);
        if (w <= 0) {
            close(fd[0]);
            close(fd[1]);
            return -1;
        }
        c += w;
        n -= (size_t)w;
    }
    close(fd[1]);
    int ok = dup2(fd[0], 0) >= 0;
    close(fd[0]);
    rewind(stdin);
    return ok ? 0 : -1;
}

static void stdin_null(void)
{
    int fd = open("/dev/null", O_RDONLY);
    if (fd < 0 || dup2(fd, 0) < 0)
        fz_fail("/dev/null as stdin: %s", strerror(errno));
    close(fd);
    rewind(stdin);
}

int fz_reader(const char *fname, const uint8_t *data, size_t size)
{
    fz_init();
    capture_stderr();
    if (size < 1)
        return 0;
    uint32_t seed = 0x9e3779b9u ^ data[0];
    const uint8_t *body = data + 1;
    size_t n = size - 1;
    fz_clean();
    if (fz_write(fname, body, n) != 0)
        fz_fail("writing %s/%s: %s", work, fname, strerror(errno));
    if (fchdir(work_fd) != 0)
        fz_fail("chdir %s: %s", work, strerror(errno));

    double sentinel_v;
    cli_matrix m = {&sentinel_v, -7, -7};
    reset_capture();
    int ec1 = cli_read_matrix(fname, &m);
    if (!reader_code(ec1))
        fz_fail("cli_read_matrix: exit code %d", ec1);
    if (ec1 != CLI_OK && errcap_fd >= 0 && fd_size(errcap_fd) == 0)
        fz_fail("cli_read_matrix failed (%d) without a message", ec1);
    if (ec1 != CLI_OK && (m.v != &sentinel_v || m.rows != -7 || m.cols != -7))
        fz_fail("cli_read_matrix failed (%d) but changed its output", ec1);
    if (ec1 == CLI_OK) {
        if (m.rows < 1 || m.cols < 1 || !m.v)
            fz_fail("cli_read_matrix: success with %ld x %d values", m.rows, m.cols);
        for (long i = 0; i < m.rows * m.cols; i++)
            if (!isfinite(m.v[i]))
                fz_fail("cli_read_matrix: success with a non-finite value at %ld", i);
    }

    /* the same file streamed in random blocks, then in two passes */
    fz_mat s = {0, 0, NULL};
    int ec2 = stream_read(fname, 0, &seed, &s);
    compare("the streamed read", ec1, &m, ec2, &s);
    free(s.v);
    s.rows = 0;
    s.v = NULL;
    if (cli_reader_open_twice && cli_reader_rewind) {
        ec2 = stream_read(fname, 1, &seed, &s);
        compare("the two-pass read", ec1, &m, ec2, &s);
        free(s.v);
    }

    /* the same bytes from a pipe on standard input ("-"), whole, streamed
     * and in two passes (spooled); a pipe is told .npy by its magic bytes,
     * so only inputs whose kind does not depend on the name are compared */
    int is_npy = n >= 6 && memcmp(body, "\x93NUMPY", 6) == 0;
    int by_name = strlen(fname) > 4 && !strcmp(fname + strlen(fname) - 4, ".npy");
    if (is_npy == by_name) {
        for (int pass = 0; pass < 3; pass++) {
            static const char *what[3] = {"the whole read of a pipe", "the streamed read of a pipe",
                                          "the two-pass read of a pipe"};
            if (stdin_pipe(body, n) != 0)
                break;
            if (pass == 0) {
                cli_matrix p = {&sentinel_v, -7, -7};
                ec2 = cli_read_matrix("-", &p);
                fz_mat q = {p.rows, p.cols, p.v};
                compare(what[0], ec1, &m, ec2, &q);
                if (ec2 == CLI_OK)
                    cli_matrix_free(&p);
            } else {
                s.rows = 0;
                s.cols = 0;
                s.v = NULL;
                if (pass == 2 && !(cli_reader_open_twice && cli_reader_rewind))
                    break;
                ec2 = stream_read("-", pass == 2, &seed, &s);
                compare(what[pass], ec1, &m, ec2, &s);
                free(s.v);
            }
            stdin_null();
        }
    }
    if (ec1 == CLI_OK)
        cli_matrix_free(&m);
    if (home_fd >= 0 && fchdir(home_fd) != 0)
        fz_fail("chdir back: %s", strerror(errno));
    if (fd_size(out_fd) > 0)
        fz_fail("a reader wrote to standard output");
    check_tmpdir();
    fz_clean();
    return 0;
}
