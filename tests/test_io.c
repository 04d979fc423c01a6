/* Tests of the matrix reader (igea/io.h): every value is checked against
 * the number the test itself wrote into the file (text literals, or the
 * doubles of a .npy written here byte by byte). */
#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "testutil.h"

#include "igea.h"

static char dir[] = "/tmp/igea-test-io.XXXXXX";
static char path[256];

static const char *put(const char *name, const void *data, size_t n)
{
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, n, f), n);
    fclose(f);
    return path;
}
static const char *puts_(const char *name, const char *text)
{
    return put(name, text, strlen(text));
}

/* Open, load everything; returns the status and fills v (row-major). */
static int load(const char *p, double *v, long *rows, int *cols, igea_io_reader **out)
{
    igea_io_reader *r;
    assert_int_equal(igea_io_reader_create(&r), 0);
    int st = igea_io_reader_open(r, p, 0, NULL);
    if (!st)
        st = igea_io_reader_load(r);
    if (!st) {
        double info[IGEA_IO_INFO_LEN];
        assert_int_equal(igea_io_reader_info(r, info), 0);
        *rows = (long)info[IGEA_IO_INFO_ROWS];
        *cols = (int)info[IGEA_IO_INFO_COLS];
        assert_int_equal(igea_io_reader_copy(r, v, IGEA_ROWMAJOR), 0);
    }
    *out = r;
    return st;
}

static void expect_error(igea_io_reader *r, int st, long line, long col, const char *text)
{
    double info[IGEA_IO_INFO_LEN];
    igea_io_reader_info(r, info);
    assert_int_equal((int)info[IGEA_IO_INFO_STATUS], st);
    assert_int_equal((long)info[IGEA_IO_INFO_LINE], line);
    assert_int_equal((long)info[IGEA_IO_INFO_COLUMN], col);
    if (!strstr(igea_io_reader_message(r), text)) {
        print_error("message '%s' lacks '%s'\n", igea_io_reader_message(r), text);
        fail();
    }
}

static void test_text_layouts(void **state)
{
    (void)state;
    double v[16];
    long rows;
    int cols;
    igea_io_reader *r;
    const char *p = puts_("a.txt", "# a comment\n1.5 -2\t3e2\n\n4, 5 ,6 # trailing\n");
    assert_int_equal(load(p, v, &rows, &cols, &r), 0);
    assert_int_equal(rows, 2);
    assert_int_equal(cols, 3);
    const double want[] = {1.5, -2, 300, 4, 5, 6};
    for (int k = 0; k < 6; k++)
        assert_close(v[k], want[k], 0);
    double c[6];
    assert_int_equal(igea_io_reader_copy(r, c, IGEA_COLMAJOR), 0);
    assert_close(c[1], 4, 0); /* row 1, column 0 */
    assert_close(c[4], 3e2, 0);
    assert_string_equal(igea_io_reader_names(r), "");
    igea_io_reader_free(r);
}

static void test_ragged_rows(void **state)
{
    (void)state;
    double v[16];
    long rows;
    int cols;
    igea_io_reader *r;
    assert_int_equal(load(puts_("r.txt", "1 2\n3 4\n5\n"), v, &rows, &cols, &r), IGEA_EFORMAT);
    expect_error(r, IGEA_EFORMAT, 3, 0, "1 values, but the rows before have 2");
    igea_io_reader_free(r);
}

static void test_decimal_comma(void **state)
{
    (void)state;
    double v[16];
    long rows;
    int cols;
    igea_io_reader *r;
    assert_int_equal(load(puts_("c.txt", "1,5 2,5\n"), v, &rows, &cols, &r), IGEA_EFORMAT);
    expect_error(r, IGEA_EFORMAT, 1, 2, "decimal comma");
    igea_io_reader_free(r);
    /* a genuine CSV of integers is not a decimal comma */
    assert_int_equal(load(puts_("c2.txt", "1,5\n2,6\n"), v, &rows, &cols, &r), 0);
    assert_int_equal(cols, 2);
    assert_close(v[3], 6, 0);
    igea_io_reader_free(r);
}

static void test_fortran_numbers(void **state)
{
    (void)state;
    double v[16], x = 0;
    long rows;
    int cols;
    igea_io_reader *r;
    const char *p = puts_("d.txt", " 0.1000000000000000D+01  2.5d-3 -4D2 1.D0\n");
    assert_int_equal(load(p, v, &rows, &cols, &r), 0);
    assert_int_equal(cols, 4);
    assert_close(v[0], 1.0, 0);
    assert_close(v[1], 2.5e-3, 0);
    assert_close(v[2], -400, 0);
    assert_close(v[3], 1, 0);
    igea_io_reader_free(r);
    assert_int_equal(load(puts_("rep.txt", "1 2\n4 3*1.0\n"), v, &rows, &cols, &r),
                     IGEA_EFORMAT);
    expect_error(r, IGEA_EFORMAT, 2, 3, "repeat count");
    igea_io_reader_free(r);
    /* Fortran's E format drops the letter of a 3-digit exponent */
    assert_int_equal(load(puts_("e3.txt", "0.1500000000000000-100\n"), v, &rows, &cols, &r),
                     IGEA_EFORMAT);
    expect_error(r, IGEA_EFORMAT, 1, 1, "exponent without its letter");
    igea_io_reader_free(r);
    assert_int_equal(igea_io_parse_number("1.0D-02", &x), 0);
    assert_close(x, 0.01, 0);
    assert_int_equal(igea_io_parse_number("0x1D", &x), 0); /* hexadecimal 29 */
    assert_close(x, 29, 0);
    assert_int_equal(igea_io_parse_number("1D", &x), IGEA_EFORMAT);
    assert_int_equal(igea_io_parse_number("nan", &x), IGEA_ENONFINITE);
    assert_int_equal(igea_io_parse_number("1D400", &x), IGEA_EOVERFLOW);
    assert_int_equal(igea_io_parse_number("1.5 ", &x), IGEA_EFORMAT);
    assert_close(x, 29, 0); /* untouched by the failures */
}

static void test_bom_crlf_tabs(void **state)
{
    (void)state;
    double v[16];
    long rows;
    int cols;
    igea_io_reader *r;
    const char *p = puts_("b.txt", "\xef\xbb\xbf" "1\t2\r\n3\t4\r\n");
    assert_int_equal(load(p, v, &rows, &cols, &r), 0);
    assert_int_equal(rows, 2);
    assert_close(v[0], 1, 0);
    assert_close(v[3], 4, 0);
    igea_io_reader_free(r);
    /* columns count from after the byte order mark */
    assert_int_equal(load(puts_("b2.txt", "\xef\xbb\xbf" "1 x\n"), v, &rows, &cols, &r),
                     IGEA_EFORMAT);
    expect_error(r, IGEA_EFORMAT, 1, 3, "'x' is not a finite number");
    igea_io_reader_free(r);
}

static void test_header_names(void **state)
{
    (void)state;
    double v[16];
    long rows;
    int cols;
    igea_io_reader *r;
    assert_int_equal(load(puts_("h.csv", "\xef\xbb\xbf" "t,x_1,\"y z\"\r\n1,2,3\r\n"), v, &rows,
                          &cols, &r), 0);
    assert_string_equal(igea_io_reader_names(r), "t\nx_1\ny z");
    assert_int_equal(rows, 1);
    assert_close(v[2], 3, 0);
    igea_io_reader_free(r);
    /* igea's own '# names' header: the same names */
    assert_int_equal(load(puts_("h.txt", "# generated\n# t x_1 y\n1 2 3\n"), v, &rows, &cols,
                          &r), 0);
    assert_string_equal(igea_io_reader_names(r), "t\nx_1\ny");
    igea_io_reader_free(r);
    /* a comment of another number of words names nothing */
    assert_int_equal(load(puts_("h2.txt", "# two words\n1 2 3\n"), v, &rows, &cols, &r), 0);
    assert_string_equal(igea_io_reader_names(r), "");
    igea_io_reader_free(r);
    /* a header row must name every column; nan is a number, not a name */
    assert_int_equal(load(puts_("h3.txt", "a b c\n1 2\n"), v, &rows, &cols, &r),
                     IGEA_EFORMAT);
    expect_error(r, IGEA_EFORMAT, 2, 0, "header row names 3");
    igea_io_reader_free(r);
    assert_int_equal(load(puts_("h4.txt", "a nan\n1 2\n"), v, &rows, &cols, &r),
                     IGEA_EFORMAT);
    expect_error(r, IGEA_EFORMAT, 1, 1, "'a' is not a finite number");
    igea_io_reader_free(r);
    assert_int_equal(load(puts_("h5.txt", "a b\nc d\n1 2\n"), v, &rows, &cols, &r),
                     IGEA_EFORMAT);
    expect_error(r, IGEA_EFORMAT, 2, 1, "'c'");
    igea_io_reader_free(r);
}

/* A version 1.0 .npy of the doubles a (shape rows x cols, or 1-D). */
static size_t npy(unsigned char *out, const double *a, int rows, int cols, int fortran,
                  int oned)
{
    char h[128];
    int hl;
    if (oned)
        hl = snprintf(h, sizeof h, "{'descr': '<f8', 'fortran_order': False, 'shape': (%d,), }",
                      rows);
    else
        hl = snprintf(h, sizeof h, "{'descr': '<f8', 'fortran_order': %s, 'shape': (%d, %d), }",
                      fortran ? "True" : "False", rows, cols);
    int pad = (64 - (10 + hl + 1) % 64) % 64, hlen = hl + pad + 1;
    memcpy(out, "\x93NUMPY\x01\x00", 8);
    out[8] = (unsigned char)(hlen & 0xff);
    out[9] = (unsigned char)(hlen >> 8);
    memcpy(out + 10, h, (size_t)hl);
    memset(out + 10 + hl, ' ', (size_t)pad);
    out[10 + hl + pad] = '\n';
    memcpy(out + 10 + hlen, a, sizeof(double) * (size_t)rows * (size_t)cols);
    return 10 + (size_t)hlen + sizeof(double) * (size_t)rows * (size_t)cols;
}

static void test_npy_orders(void **state)
{
    (void)state;
    /* the matrix [[1, 2, 3], [4, 5, 6]] in C order, and the same in
     * Fortran order (columns stored one after the other) */
    const double c[] = {1, 2, 3, 4, 5, 6}, f[] = {1, 4, 2, 5, 3, 6};
    unsigned char buf[512];
    double v[16];
    long rows;
    int cols;
    igea_io_reader *r;
    for (int fo = 0; fo < 2; fo++) {
        size_t n = npy(buf, fo ? f : c, 2, 3, fo, 0);
        assert_int_equal(load(put(fo ? "f.npy" : "c.npy", buf, n), v, &rows, &cols, &r), 0);
        assert_int_equal(rows, 2);
        assert_int_equal(cols, 3);
        for (int k = 0; k < 6; k++)
            assert_close(v[k], c[k], 0);
        igea_io_reader_free(r);
        /* by its magic bytes under another name */
        assert_int_equal(load(put(fo ? "f.bin" : "c.bin", buf, n), v, &rows, &cols, &r), 0);
        assert_close(v[5], 6, 0);
        igea_io_reader_free(r);
        /* truncated: the header promises 6 values */
        assert_int_equal(load(put("t.npy", buf, n - 12), v, &rows, &cols, &r), IGEA_EFORMAT);
        expect_error(r, IGEA_EFORMAT, 0, 0, "truncated");
        igea_io_reader_free(r);
    }
    size_t n = npy(buf, c, 6, 1, 0, 1);
    assert_int_equal(load(put("one.npy", buf, n), v, &rows, &cols, &r), 0);
    assert_int_equal(rows, 6);
    assert_int_equal(cols, 1);
    assert_close(v[4], 5, 0);
    igea_io_reader_free(r);
}

/* Read r to the end in blocks of 2 rows: the values into v, their count. */
static long drain(igea_io_reader *r, double *v)
{
    long k = 0;
    int got, cols = igea_io_reader_cols(r);
    do {
        assert_int_equal(igea_io_reader_next(r, 2, v + k * cols, &got), 0);
        k += got;
    } while (got > 0);
    return k;
}

/* The bytes through a pipe (small: they fit in the pipe's buffer). */
static int piped(const void *data, size_t n)
{
    int fd[2];
    assert_int_equal(pipe(fd), 0);
    assert_int_equal(write(fd[1], data, n), (ssize_t)n);
    close(fd[1]);
    return fd[0];
}

static void test_pipe_rewind(void **state)
{
    (void)state;
    const char *text = "# x y\n1 2\n3 4\n5 6\n";
    const double c[] = {1, 2, 3, 4, 5, 6}, f[] = {1, 3, 5, 2, 4, 6};
    unsigned char buf[512];
    size_t nb = npy(buf, f, 3, 2, 1, 0);
    for (int kind = 0; kind < 2; kind++) {
        int fd = kind ? piped(buf, nb) : piped(text, strlen(text));
        igea_io_reader *r;
        double v[16], w[16];
        assert_int_equal(igea_io_reader_create(&r), 0);
        assert_int_equal(igea_io_reader_open_fd(r, fd, "<pipe>", IGEA_IO_TWICE, dir), 0);
        assert_int_equal(igea_io_reader_cols(r), 2);
        assert_int_equal(drain(r, v), 3);
        assert_int_equal(igea_io_reader_rewind(r), 0);
        assert_int_equal(drain(r, w), 3);
        for (int k = 0; k < 6; k++) {
            assert_close(v[k], c[k], 0);
            assert_close(w[k], c[k], 0);
        }
        assert_string_equal(igea_io_reader_names(r), kind ? "" : "x\ny");
        igea_io_reader_free(r);
        close(fd);
    }
    /* one pass only: rewind refused */
    int fd = piped(text, strlen(text));
    igea_io_reader *r;
    assert_int_equal(igea_io_reader_create(&r), 0);
    assert_int_equal(igea_io_reader_open_fd(r, fd, NULL, 0, NULL), 0);
    assert_int_equal(igea_io_reader_rewind(r), -1);
    igea_io_reader_free(r);
    close(fd);
}

static void test_fifo(void **state)
{
    (void)state;
    char fifo[300];
    snprintf(fifo, sizeof fifo, "%s/fifo", dir);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        int w = open(fifo, O_WRONLY);
        const char *t = "7 8\n9 10\n";
        _exit(w >= 0 && write(w, t, strlen(t)) == (ssize_t)strlen(t) ? 0 : 1);
    }
    igea_io_reader *r;
    double v[8];
    assert_int_equal(igea_io_reader_create(&r), 0);
    assert_int_equal(igea_io_reader_open(r, fifo, IGEA_IO_TWICE, dir), 0);
    assert_int_equal(drain(r, v), 2);
    assert_int_equal(igea_io_reader_rewind(r), 0);
    assert_int_equal(drain(r, v), 2);
    assert_close(v[3], 10, 0);
    igea_io_reader_free(r);
    int status;
    waitpid(pid, &status, 0);
    unlink(fifo);
}

static void test_system_errors(void **state)
{
    (void)state;
    igea_io_reader *r;
    double info[IGEA_IO_INFO_LEN], v[4];
    char p[300];
    snprintf(p, sizeof p, "%s/absent.txt", dir);
    assert_int_equal(igea_io_reader_create(&r), 0);
    assert_int_equal(igea_io_reader_open(r, p, 0, NULL), IGEA_EREAD);
    igea_io_reader_info(r, info);
    assert_int_equal((int)info[IGEA_IO_INFO_ERRNO], ENOENT);
    assert_int_equal(igea_io_reader_cols(r), 0);
    assert_int_equal(igea_io_reader_open(r, dir, 0, NULL), IGEA_EREAD);
    assert_string_equal(igea_io_reader_message(r), "is a directory");
    assert_int_equal(igea_io_reader_open(r, puts_("e.txt", "# only a comment\n"), 0, NULL),
                     IGEA_EFORMAT);
    assert_int_equal(igea_io_reader_open(r, put("z.txt", "1 2\n3\0 4\n", 9), 0, NULL), 0);
    int got = -7;
    assert_int_equal(igea_io_reader_next(r, 4, v, &got), IGEA_EFORMAT);
    assert_int_equal(got, -7);
    expect_error(r, IGEA_EFORMAT, 2, 2, "NUL byte");
    /* invalid arguments */
    assert_int_equal(igea_io_reader_next(NULL, 1, v, &got), -1);
    assert_int_equal(igea_io_reader_open(r, NULL, 0, NULL), -2);
    assert_int_equal(igea_io_reader_open(r, p, 16, NULL), -3);
    assert_int_equal(igea_io_reader_open_fd(r, -1, NULL, 0, NULL), -2);
    assert_int_equal(igea_io_reader_copy(r, v, IGEA_ROWMAJOR), -1);
    igea_io_reader_free(r);
}

/* IGEA_IO_NAN: the token NaN (and a .npy NaN) is a gap; other spellings
 * and Inf stay refused, with the line and column. */
static void test_nan_gaps(void **state)
{
    (void)state;
    igea_io_reader *r;
    double v[8], info[IGEA_IO_INFO_LEN];
    int got = 0;
    const char *p = puts_("gap.txt", "1 NaN\nNaN 4\n");
    assert_int_equal(igea_io_reader_create(&r), 0);
    int st = igea_io_reader_open(r, p, 0, NULL);
    if (st == 0)
        st = igea_io_reader_next(r, 4, v, &got);
    assert_int_equal(st, IGEA_EFORMAT);
    igea_io_reader_info(r, info);
    assert_int_equal((int)info[IGEA_IO_INFO_LINE], 1);
    assert_int_equal((int)info[IGEA_IO_INFO_COLUMN], 3);
    assert_int_equal(igea_io_reader_open(r, p, IGEA_IO_NAN | IGEA_IO_TWICE, NULL), 0);
    assert_int_equal(igea_io_reader_next(r, 4, v, &got), 0);
    assert_int_equal(got, 2);
    assert_true(v[0] == 1 && isnan(v[1]) && isnan(v[2]) && v[3] == 4);
    static const char *const bad[] = {"1 nan\n", "1 NAN\n", "1 NaNa\n", "1 Inf\n", "1 -NaN\n"};
    for (int i = 0; i < 5; i++) {
        st = igea_io_reader_open(r, puts_("gap2.txt", bad[i]), IGEA_IO_NAN, NULL);
        if (st == 0)
            st = igea_io_reader_next(r, 4, v, &got);
        assert_int_equal(st, IGEA_EFORMAT);
        igea_io_reader_info(r, info);
        assert_int_equal((int)info[IGEA_IO_INFO_LINE], 1);
    }
    assert_int_equal(igea_io_reader_open(r, p, 16, NULL), -3); /* an unknown flag */
    igea_io_reader_free(r);
}

static void test_offsets_tempfile_partial_load(void **state)
{
    (void)state;
    igea_io_reader *r;
    double info[IGEA_IO_INFO_LEN], v[8];
    int got;
    assert_int_equal(igea_io_reader_create(&r), 0);
    /* a descriptor at an offset: the reader starts there (past "9 9\n") */
    int fd = open(puts_("o.txt", "9 9\n1 2\n3 4\n5 6\n"), O_RDONLY);
    assert_true(fd >= 0);
    assert_int_equal(lseek(fd, 4, SEEK_SET), 4);
    assert_int_equal(igea_io_reader_open_fd(r, fd, "o.txt", 0, NULL), 0);
    assert_int_equal(igea_io_reader_next(r, 1, v, &got), 0);
    assert_int_equal(got, 1);
    assert_close(v[0], 1, 0);
    /* the rest loaded whole: rows 2 and 3 */
    assert_int_equal(igea_io_reader_load(r), 0);
    igea_io_reader_info(r, info);
    assert_int_equal((long)info[IGEA_IO_INFO_ROWS], 2);
    assert_int_equal(igea_io_reader_copy(r, v, IGEA_ROWMAJOR), 0);
    assert_close(v[0], 3, 0);
    assert_close(v[3], 6, 0);
    close(fd);
    /* two passes of a pipe need a temporary copy: a missing directory */
    char nodir[300];
    snprintf(nodir, sizeof nodir, "%s/no/such/dir", dir);
    fd = piped("1\n", 2);
    assert_int_equal(igea_io_reader_open_fd(r, fd, NULL, IGEA_IO_TWICE, nodir), IGEA_ETEMPFILE);
    igea_io_reader_info(r, info);
    assert_int_equal((int)info[IGEA_IO_INFO_ERRNO], ENOENT);
    assert_non_null(strstr(igea_io_reader_message(r), "temporary copy"));
    close(fd);
    igea_io_reader_free(r);
}

/* Views (igea_io_reader_view): a C-order .npy opened with IGEA_IO_MAP is
 * handed out in place (the views of one pass lie one after the other in
 * the map, and the second pass sees the same addresses); Fortran order,
 * text and a reader without the flag are read into the reader's buffer;
 * NaN is refused with its row and column; a file shortened after it was
 * opened is refused, not read past its end. */
static void test_views(void **state)
{
    (void)state;
    double a[21], fo[21];
    for (int i = 0; i < 7; i++)
        for (int j = 0; j < 3; j++)
            a[i * 3 + j] = fo[j * 7 + i] = 10.0 * i + j;
    unsigned char buf[1024];
    size_t n = npy(buf, a, 7, 3, 0, 0);
    const char *p = put("v.npy", buf, n);
    igea_io_reader *r;
    const double *v, *first[3];
    int got;
    assert_int_equal(igea_io_reader_create(&r), 0);
    assert_int_equal(igea_io_reader_open(r, p, IGEA_IO_TWICE | IGEA_IO_MAP, NULL), 0);
    assert_null(igea_io_reader_view_rows(r));
    for (int pass = 0; pass < 2; pass++) {
        for (int b = 0; b < 3; b++) {
            assert_int_equal(igea_io_reader_view(r, 3, &got), 0);
            assert_int_equal(got, b < 2 ? 3 : 1);
            v = igea_io_reader_view_rows(r);
            assert_non_null(v);
            for (int k = 0; k < got * 3; k++)
                assert_close(v[k], a[b * 9 + k], 0);
            if (pass == 0)
                first[b] = v;
            else
                assert_ptr_equal(v, first[b]); /* the same pages both passes */
            if (b > 0)
                assert_ptr_equal(v, first[b - 1] + 9); /* in place, not copied */
        }
        assert_int_equal(igea_io_reader_view(r, 3, &got), 0);
        assert_int_equal(got, 0);
        assert_null(igea_io_reader_view_rows(r));
        assert_int_equal(igea_io_reader_rewind(r), 0);
        assert_null(igea_io_reader_view_rows(r));
    }
    /* arguments */
    assert_int_equal(igea_io_reader_view(NULL, 3, &got), -1);
    assert_int_equal(igea_io_reader_view(r, 0, &got), -2);
    assert_int_equal(igea_io_reader_view(r, 3, NULL), -3);
    assert_null(igea_io_reader_view_rows(NULL));
    assert_int_equal(igea_io_reader_open(r, p, 16, NULL), -3); /* an unknown flag */
    assert_int_equal(igea_io_reader_open_fd(r, 0, "x.npy", 16, NULL), -4);
    /* without IGEA_IO_MAP, in Fortran order and as text: the same rows
     * from the reader's own buffer */
    const char *other[3] = {p, put("vf.npy", buf, npy(buf, fo, 7, 3, 1, 0)),
                            puts_("v.txt", "0 1 2\n10 11 12\n20 21 22\n30 31 32\n40 41 42\n"
                                           "50 51 52\n60 61 62\n")};
    for (int k = 0; k < 3; k++) {
        assert_int_equal(igea_io_reader_open(r, other[k], k ? IGEA_IO_MAP : 0, NULL), 0);
        assert_int_equal(igea_io_reader_view(r, 4, &got), 0);
        const double *v0 = igea_io_reader_view_rows(r);
        assert_int_equal(got, 4);
        for (int i = 0; i < 12; i++)
            assert_close(v0[i], a[i], 0);
        assert_int_equal(igea_io_reader_view(r, 4, &got), 0);
        assert_int_equal(got, 3);
        assert_ptr_equal(igea_io_reader_view_rows(r), v0); /* one buffer */
        assert_close(igea_io_reader_view_rows(r)[8], a[20], 0);
    }
    /* NaN in row 5, column 2 (from 1): the view holding it is refused */
    a[4 * 3 + 1] = NAN;
    p = put("vn.npy", buf, npy(buf, a, 7, 3, 0, 0));
    assert_int_equal(igea_io_reader_open(r, p, IGEA_IO_MAP, NULL), 0);
    assert_int_equal(igea_io_reader_view(r, 3, &got), 0);
    assert_int_equal(igea_io_reader_view(r, 3, &got), IGEA_EFORMAT);
    expect_error(r, IGEA_EFORMAT, 0, 0, "row 5, column 2: NaN or Inf");
    assert_null(igea_io_reader_view_rows(r));
    /* IGEA_IO_UNCHECKED: the same views, handed out unchecked, mapped or
     * read (Fortran order); igea_io_reader_view_check names the value as
     * the checked view did, and only for the view that holds it */
    fo[1 * 7 + 4] = NAN;
    const char *un[2] = {p, put("vnf.npy", buf, npy(buf, fo, 7, 3, 1, 0))};
    for (int k = 0; k < 2; k++) {
        assert_int_equal(igea_io_reader_open(r, un[k], IGEA_IO_TWICE | IGEA_IO_MAP |
                                             IGEA_IO_UNCHECKED, NULL), 0);
        assert_int_equal(igea_io_reader_view_check(r), 0); /* no view yet */
        assert_int_equal(igea_io_reader_view(r, 3, &got), 0);
        assert_int_equal(igea_io_reader_view_check(r), 0);
        assert_int_equal(igea_io_reader_view(r, 3, &got), 0);
        assert_int_equal(got, 3);
        v = igea_io_reader_view_rows(r);
        assert_true(isnan(v[1 * 3 + 1])); /* row 5 is the view's second */
        assert_int_equal(igea_io_reader_view_check(r), IGEA_EFORMAT);
        expect_error(r, IGEA_EFORMAT, 0, 0, "row 5, column 2: NaN or Inf");
        assert_ptr_equal(igea_io_reader_view_rows(r), v); /* the view stays */
        assert_int_equal(igea_io_reader_view(r, 3, &got), 0);
        assert_int_equal(igea_io_reader_view_check(r), 0);
        assert_int_equal(igea_io_reader_rewind(r), 0);
        assert_int_equal(igea_io_reader_view_check(r), 0); /* no view after a rewind */
        /* igea_io_reader_next and _load check whatever the flag */
        double rows[21];
        assert_int_equal(igea_io_reader_next(r, 7, rows, &got), IGEA_EFORMAT);
        expect_error(r, IGEA_EFORMAT, 0, 0, "row 5, column 2: NaN or Inf");
    }
    fo[1 * 7 + 4] = 41;
    assert_int_equal(igea_io_reader_view_check(NULL), -1);
    /* shortened to 4 rows after the first view: the next view is refused */
    a[4 * 3 + 1] = 41;
    p = put("vt.npy", buf, n = npy(buf, a, 7, 3, 0, 0));
    assert_int_equal(igea_io_reader_open(r, p, IGEA_IO_MAP, NULL), 0);
    assert_int_equal(igea_io_reader_view(r, 3, &got), 0);
    assert_int_equal(truncate(p, (off_t)(n - 3 * 3 * sizeof(double))), 0);
    assert_int_equal(igea_io_reader_view(r, 3, &got), IGEA_EFORMAT);
    expect_error(r, IGEA_EFORMAT, 0, 0, "truncated");
    igea_io_reader_free(r);
}

static int setup(void **state)
{
    (void)state;
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_text_layouts),  cmocka_unit_test(test_ragged_rows),
        cmocka_unit_test(test_decimal_comma), cmocka_unit_test(test_fortran_numbers),
        cmocka_unit_test(test_bom_crlf_tabs), cmocka_unit_test(test_header_names),
        cmocka_unit_test(test_npy_orders),    cmocka_unit_test(test_pipe_rewind),
        cmocka_unit_test(test_fifo),          cmocka_unit_test(test_system_errors),
        cmocka_unit_test(test_offsets_tempfile_partial_load),
        cmocka_unit_test(test_views), cmocka_unit_test(test_nan_gaps),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
