/* src/io_src.c - the matrix reader's byte source: buffered reads of a
 * descriptor, pread on seekable inputs, the spool that makes a
 * non-seekable input readable twice (io_src.h). */
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io_src.h"

int io_fail(igea_io_reader *r, int status, long line, long col, int err, const char *fmt, ...)
{
    va_list ap;
    r->st = status;
    r->eline = line;
    r->ecol = col;
    r->eerrno = err;
    va_start(ap, fmt);
    vsnprintf(r->emsg, sizeof r->emsg, fmt, ap);
    va_end(ap);
    return status;
}

int io_sysfail(igea_io_reader *r, int status, int err, const char *what)
{
    if (err == ENOMEM)
        return io_fail(r, IGEA_ENOMEM, 0, 0, 0, "out of memory (%s)", what);
    return io_fail(r, status, 0, 0, err, "%s", what);
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

int igea__pread_full(int fd, void *p, size_t n, long long off)
{
    for (size_t got = 0; got < n;) {
        ssize_t k = pread_retry(fd, (char *)p + got, n - got, (off_t)off + (off_t)got);
        if (k <= 0)
            return IGEA_EREAD;
        got += (size_t)k;
    }
    return 0;
}

int io_spool_new(igea_io_reader *r)
{
    const char *dir = r->tmpdir && *r->tmpdir ? r->tmpdir : "/tmp";
    size_t n = strlen(dir) + sizeof "/igea-spool.XXXXXX";
    char *name = malloc(n);
    if (!name)
        return io_fail(r, IGEA_ENOMEM, 0, 0, 0, "out of memory (a temporary copy)");
    snprintf(name, n, "%s/igea-spool.XXXXXX", dir);
    int fd = mkstemp(name);
    if (fd < 0) {
        int e = errno;
        free(name);
        if (e == ENOMEM)
            return io_fail(r, IGEA_ENOMEM, 0, 0, 0, "out of memory (a temporary copy)");
        return io_fail(r, IGEA_ETEMPFILE, 0, 0, e,
                       "cannot create a temporary copy of the input in %s", dir);
    }
    unlink(name);
    free(name);
    return fd;
}

static int tee_failed(igea_io_reader *r, const char *what)
{
    int e = errno;
    if (e == ENOMEM)
        return io_fail(r, IGEA_ENOMEM, 0, 0, 0, "out of memory (a temporary copy)");
    return io_fail(r, IGEA_ETEMPFILE, 0, 0, e, "%s", what);
}

int io_src_more(igea_io_reader *r)
{
    io_src *s = &r->s;
    if (s->eof)
        return 0;
    if (s->bpos > 0) {
        memmove(s->buf, s->buf + s->bpos, s->blen - s->bpos);
        s->blen -= s->bpos;
        s->bpos = 0;
    }
    if (s->blen == IO_BUF)
        return 1;
    ssize_t k;
    if (s->seekable) {
        off_t at = s->pos + (off_t)s->blen;
        k = pread_retry(s->fd, s->buf + s->blen, IO_BUF - s->blen, at + s->delta);
    } else
        k = read_retry(s->fd, s->buf + s->blen, IO_BUF - s->blen);
    if (k < 0)
        return io_sysfail(r, IGEA_EREAD, errno, "read error");
    if (k == 0) {
        s->eof = 1;
        return 0;
    }
    if (s->tee >= 0 && write_all(s->tee, s->buf + s->blen, (size_t)k) != 0)
        return tee_failed(r, "cannot keep a copy of the input for the second pass");
    s->blen += (size_t)k;
    return 1;
}

/* A large read of a seekable input that bypasses the buffer: bytes read,
 * 0 at the end, < 0 a status. */
static long long direct_read(igea_io_reader *r, unsigned char *d, size_t want)
{
    io_src *s = &r->s;
    off_t avail = s->size - s->pos;
    if (avail <= 0)
        return 0;
    if ((off_t)want > avail)
        want = (size_t)avail;
    ssize_t k = pread_retry(s->fd, d, want, s->pos + s->delta);
    if (k < 0)
        return io_sysfail(r, IGEA_EREAD, errno, "read error");
    s->pos += k;
    return k;
}

long long io_src_read(igea_io_reader *r, void *dst, size_t n)
{
    io_src *s = &r->s;
    unsigned char *d = dst;
    size_t got = 0;
    while (got < n) {
        if (s->bpos == s->blen) {
            if (s->seekable && n - got >= IO_BUF) {
                long long k = direct_read(r, d + got, n - got);
                if (k < 0)
                    return k;
                if (k == 0)
                    break;
                got += (size_t)k;
                continue;
            }
            s->bpos = s->blen = 0;
            int m = io_src_more(r);
            if (m < 0)
                return m;
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

/* Copy the rest of a non-seekable input to sp. 0 or a status. */
static int spool_rest(igea_io_reader *r, int sp)
{
    io_src *s = &r->s;
    while (!s->eof) {
        ssize_t k = read_retry(s->fd, s->buf, IO_BUF);
        if (k < 0)
            return io_sysfail(r, IGEA_EREAD, errno, "read error");
        if (k == 0)
            break;
        if (write_all(sp, s->buf, (size_t)k) != 0)
            return tee_failed(r, "cannot keep a temporary copy of the input");
    }
    return 0;
}

int io_src_spool(igea_io_reader *r)
{
    io_src *s = &r->s;
    if (s->seekable)
        return 0;
    off_t start;
    int sp, st;
    if (s->tee >= 0) {
        sp = s->tee;
        s->tee = -1;
        start = 0;
    } else {
        if ((sp = io_spool_new(r)) < 0)
            return sp;
        start = s->pos;
        if (write_all(sp, s->buf + s->bpos, s->blen - s->bpos) != 0) {
            st = tee_failed(r, "cannot keep a temporary copy of the input");
            close(sp);
            return st;
        }
    }
    if ((st = spool_rest(r, sp)) != 0) {
        close(sp);
        return st;
    }
    off_t end = lseek(sp, 0, SEEK_END);
    if (end < 0) {
        st = tee_failed(r, "cannot keep a temporary copy of the input");
        close(sp);
        return st;
    }
    if (s->own)
        close(s->fd);
    s->fd = sp;
    s->own = 1;
    s->seekable = 1;
    s->inplace = 0;
    s->delta = -start;
    s->size = start + end;
    s->bpos = s->blen = 0;
    s->eof = 0;
    return 0;
}

void io_src_close(io_src *s)
{
    if (s->own && s->fd >= 0)
        close(s->fd);
    if (s->tee >= 0)
        close(s->tee);
    s->fd = s->tee = -1;
    s->own = 0;
}
