/* tests/fuzz/fuzz_io.c - libFuzzer target: the library's matrix reader
 * (igea/io.h) alone. data[0]: bit 0 names the input "m.npy" (else
 * "m.txt"), the other bits seed the block sizes; the rest is the file. The
 * same bytes are read whole (igea_io_reader_load), streamed in random
 * blocks, in two passes (rewind), and from a pipe in two passes (spooled):
 * the outcome (the first failing status, or the rows and their bits) must
 * agree, a failure must say why (message, status kept in the reader), a
 * success must hold only finite values and as many names as columns (or
 * none). A violation aborts, so libFuzzer keeps the input. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "igea.h"

#define MAXV (1L << 20)

typedef struct {
    int st;      /* 0 or the first failing status */
    long rows;
    int cols;
    double *v;   /* rows * cols values (malloc'd) */
} outcome;

static void die(const char *what)
{
    fprintf(stderr, "fuzz_io: %s\n", what);
    abort();
}

static char dir[512];
static char path[600];

/* A failure: a status < 0 kept in the reader with a message. */
static int failed(igea_io_reader *r, int st, outcome *o)
{
    double info[IGEA_IO_INFO_LEN];
    if (st >= 0)
        die("a positive status");
    if (igea_io_reader_info(r, info) != 0 || (int)info[IGEA_IO_INFO_STATUS] != st)
        die("the failure is not kept in the reader");
    if (st != IGEA_ENOMEM && !*igea_io_reader_message(r))
        die("a failure without a message");
    if (info[IGEA_IO_INFO_LINE] < 0 || info[IGEA_IO_INFO_COLUMN] < 0)
        die("a negative line or column");
    o->st = st;
    return st;
}

/* Rows in blocks (block 0: load whole), appended to o. */
static int drain(igea_io_reader *r, uint32_t *seed, int whole, outcome *o)
{
    int cols = igea_io_reader_cols(r), st;
    if (whole) {
        double info[IGEA_IO_INFO_LEN];
        if ((st = igea_io_reader_load(r)))
            return failed(r, st, o);
        igea_io_reader_info(r, info);
        long n = (long)info[IGEA_IO_INFO_ROWS];
        if (n * cols > MAXV || !(o->v = realloc(o->v, sizeof(double) * (size_t)(n * cols + 1))))
            die("too large");
        if (igea_io_reader_copy(r, o->v, IGEA_ROWMAJOR) != 0)
            die("copy failed after a load");
        o->rows = n;
        return 0;
    }
    for (;;) {
        *seed = *seed * 1103515245u + 12345u;
        int block = 1 + (int)((*seed >> 16) % 7), got = -1;
        if ((o->rows + block) * cols > MAXV)
            die("too large");
        o->v = realloc(o->v, sizeof(double) * (size_t)((o->rows + block) * cols));
        if (!o->v)
            die("out of memory");
        if ((st = igea_io_reader_next(r, block, o->v + o->rows * cols, &got)))
            return failed(r, st, o);
        if (got < 0 || got > block)
            die("a row count out of range");
        if (got == 0)
            return 0;
        o->rows += got;
    }
}

/* One way of reading: how 0 whole, 1 streamed, 2 two passes, 3 a pipe. */
static void read_once(int how, const uint8_t *data, size_t size, const char *name,
                      uint32_t seed, outcome *o)
{
    igea_io_reader *r;
    int fd[2] = {-1, -1}, st;
    memset(o, 0, sizeof *o);
    if (igea_io_reader_create(&r) != 0)
        die("create failed");
    if (how == 3) {
        if (pipe(fd) != 0 || (size && write(fd[1], data, size) != (ssize_t)size))
            die("pipe");
        close(fd[1]);
        st = igea_io_reader_open_fd(r, fd[0], name, IGEA_IO_TWICE, dir);
    } else
        st = igea_io_reader_open(r, path, how == 2 ? IGEA_IO_TWICE : 0, dir);
    if (st)
        failed(r, st, o);
    else {
        o->cols = igea_io_reader_cols(r);
        const char *nm = igea_io_reader_names(r);
        int n = *nm ? 1 : 0;
        for (; *nm; nm++)
            n += *nm == '\n';
        if (o->cols < 1 || (n && n != o->cols))
            die("columns and names disagree");
        if (!drain(r, &seed, how == 0, o) && how >= 2) {
            outcome again = {0, 0, 0, NULL};
            if ((st = igea_io_reader_rewind(r)))
                failed(r, st, &again);
            else
                drain(r, &seed, 0, &again);
            if (again.st || again.rows != o->rows ||
                memcmp(again.v, o->v, sizeof(double) * (size_t)(o->rows * o->cols)))
                die("the second pass differs from the first");
            free(again.v);
        }
    }
    igea_io_reader_free(r);
    if (fd[0] >= 0)
        close(fd[0]);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static int ready;
    if (!ready) {
        const char *t = getenv("TMPDIR");
        snprintf(dir, sizeof dir, "%s/igea-fuzz-io.XXXXXX", t && *t ? t : "/tmp");
        if (!mkdtemp(dir))
            die("mkdtemp");
        ready = 1;
    }
    if (size < 1)
        return 0;
    const char *name = data[0] & 1 ? "m.npy" : "m.txt";
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f || (size > 1 && fwrite(data + 1, 1, size - 1, f) != size - 1) || fclose(f) != 0)
        die("cannot write the input");
    outcome o[4];
    for (int how = 0; how < 4; how++)
        read_once(how, data + 1, size - 1, name, data[0] >> 1, &o[how]);
    for (int how = 0; how < 4; how++) {
        if (o[how].st != o[0].st || (!o[0].st && (o[how].rows != o[0].rows ||
                                                  o[how].cols != o[0].cols)))
            die("the ways of reading disagree");
        if (!o[0].st && memcmp(o[how].v, o[0].v, sizeof(double) * (size_t)(o[0].rows * o[0].cols)))
            die("the values differ between the ways of reading");
    }
    for (long k = 0; !o[0].st && k < o[0].rows * o[0].cols; k++)
        if (!isfinite(o[0].v[k]))
            die("a success holds NaN or Inf");
    for (int how = 0; how < 4; how++)
        free(o[how].v);
    unlink(path);
    return 0;
}
