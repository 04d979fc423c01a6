/* src/io_npy.c - the .npy part of the matrix reader (io_src.h): the header
 * checked against the bytes present, C and Fortran order. */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "internal.h"
#include "io_src.h"

static int truncated(igea_io_reader *r, long long have)
{
    return io_fail(r, IGEA_EFORMAT, 0, 0, 0,
                   "truncated: the header promises %ld x %d values, the input holds %lld "
                   "bytes of data", r->rows, r->cols, have < 0 ? 0LL : have);
}

/* The header dictionary (malloc'd, NUL-terminated). */
static int header_text(igea_io_reader *r, char **text)
{
    unsigned char magic[10], more[2];
    long long k = io_src_read(r, magic, 10);
    if (k < 0)
        return (int)k;
    if (k != 10 || memcmp(magic, "\x93NUMPY", 6) != 0)
        return io_fail(r, IGEA_EFORMAT, 0, 0, 0, "not a .npy file (bad magic)");
    int major = magic[6];
    size_t hlen = magic[8] | ((size_t)magic[9] << 8);
    if (major == 2 || major == 3) {
        if ((k = io_src_read(r, more, 2)) < 0)
            return (int)k;
        if (k != 2)
            return io_fail(r, IGEA_EFORMAT, 0, 0, 0, "truncated .npy header");
        hlen |= ((size_t)more[0] << 16) | ((size_t)more[1] << 24);
    } else if (major != 1) {
        return io_fail(r, IGEA_EFORMAT, 0, 0, 0, "unsupported .npy version %d", major);
    }
    if (hlen > 1 << 20)
        return io_fail(r, IGEA_EFORMAT, 0, 0, 0, ".npy header too long");
    char *h = malloc(hlen + 1);
    if (!h)
        return io_fail(r, IGEA_ENOMEM, 0, 0, 0, "out of memory (.npy header)");
    if ((k = io_src_read(r, h, hlen)) < 0 || (size_t)k != hlen) {
        free(h);
        return k < 0 ? (int)k : io_fail(r, IGEA_EFORMAT, 0, 0, 0, "truncated .npy header");
    }
    h[hlen] = '\0';
    *text = h;
    return 0;
}

/* The 'shape' tuple: rows and columns of a 1-D or 2-D array. */
static int shape(igea_io_reader *r, const char *sh)
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
    if (dims[0] < 0 || dims[1] < 0)
        return io_fail(r, IGEA_EFORMAT, 0, 0, 0, "malformed .npy shape");
    if (nd == 1 && !big) {
        r->rows = dims[0], r->cols = 1, r->oned = 1;
        return 0;
    }
    if (nd == 2 && !big && dims[1] <= INT_MAX) {
        r->rows = dims[0], r->cols = (int)dims[1];
        return 0;
    }
    if (big || nd == 2)
        return io_fail(r, IGEA_EFORMAT, 0, 0, 0, ".npy shape too large");
    return io_fail(r, IGEA_EFORMAT, 0, 0, 0, ".npy array must be 1-D or 2-D");
}

/* descr, fortran_order and shape of the header. */
static int dict(igea_io_reader *r, const char *h)
{
    const char *d = strstr(h, "'descr'"), *fo = strstr(h, "'fortran_order'");
    const char *sh = strstr(h, "'shape'");
    if (!d || !fo || !sh)
        return io_fail(r, IGEA_EFORMAT, 0, 0, 0, "malformed .npy header");
    if (!strstr(d, "'<f8'") || strstr(d, "'<f8'") > strchr(d + 7, ','))
        return io_fail(r, IGEA_EFORMAT, 0, 0, 0,
                       ".npy data must be little-endian float64 ('<f8'); convert with "
                       "numpy: np.save(path, a.astype('<f8'))");
    const char *v = strchr(fo + 15, ':');
    while (v && (*v == ':' || *v == ' '))
        v++;
    r->fortran = v && strncmp(v, "True", 4) == 0;
    return shape(r, sh);
}

int io_npy_header(igea_io_reader *r)
{
    char *h = NULL;
    int st = header_text(r, &h);
    if (st)
        return st;
    st = dict(r, h);
    free(h);
    if (st)
        return st;
    r->data_off = r->s.pos;
    if (r->rows == 0 || r->cols == 0)
        return io_fail(r, IGEA_EFORMAT, 0, 0, 0, "empty array");
    /* rows * cols * 8 bytes must be addressable and representable as a file
     * offset before anything is sized from it. */
    uintmax_t lim = (uintmax_t)SIZE_MAX < (uintmax_t)INT64_MAX ? (uintmax_t)SIZE_MAX
                                                               : (uintmax_t)INT64_MAX;
    if ((uintmax_t)r->rows > (lim - (uintmax_t)r->data_off) / 8u / (uintmax_t)r->cols)
        return io_fail(r, IGEA_EFORMAT, 0, 0, 0, ".npy shape (%ld, %d) too large", r->rows,
                       r->cols);
    /* A non-seekable input is copied to a temporary file first when it
     * must be read out of order (Fortran order) or when its rows are wide:
     * then the header is checked against the bytes really there before
     * anything is sized from the column count. */
    if (((r->fortran && !r->oned && r->cols > 1) || r->cols > 512) && (st = io_src_spool(r)))
        return st;
    if (r->s.seekable) {
        off_t need = (off_t)r->rows * r->cols * 8;
        if (r->s.size - r->data_off < need)
            return truncated(r, (long long)(r->s.size - r->data_off));
    }
    return 0;
}

/* n bytes at logical offset off (seekable, or sequential at the current
 * position). */
static int read_at(igea_io_reader *r, off_t off, void *dst, size_t n)
{
    if (r->s.seekable) {
        r->s.pos = off;
        r->s.bpos = r->s.blen = 0;
        r->s.eof = 0;
    } else if (off != r->s.pos) {
        return io_fail(r, -1, 0, 0, 0, ".npy data out of order on a non-seekable input");
    }
    long long k = io_src_read(r, dst, n);
    if (k < 0)
        return (int)k;
    if ((size_t)k != n)
        return truncated(r, (long long)(off - r->data_off) + k);
    return 0;
}

/* Fortran order: column j of the block, then scatter. */
static int fortran_block(igea_io_reader *r, long want, double *buf)
{
    double *col = malloc((size_t)want * sizeof(double));
    if (!col)
        return io_fail(r, IGEA_ENOMEM, 0, 0, 0, "out of memory (a .npy block)");
    for (int j = 0; j < r->cols; j++) {
        off_t off = r->data_off + ((off_t)j * r->rows + r->next_row) * 8;
        int st = read_at(r, off, col, (size_t)want * 8);
        if (st) {
            free(col);
            return st;
        }
        for (long i = 0; i < want; i++)
            buf[i * r->cols + j] = col[i];
    }
    free(col);
    return 0;
}

/* Rows row0 .. row0 + n - 1 at v finite (or NaN, a gap, under IGEA_IO_NAN),
 * else IGEA_EFORMAT naming the first value that is not (row and column
 * from 1). */
int io_npy_check_rows(igea_io_reader *r, long row0, long n, const double *v)
{
    size_t k = (size_t)n * (size_t)r->cols;
    if (igea__finite_run(k, v))
        return 0;
    size_t i = 0; /* the first entry that is not finite, nor a gap (IGEA_IO_NAN) */
    while (i < k && (isfinite(v[i]) || (r->nan_ok && isnan(v[i]))))
        i++;
    if (i == k)
        return 0;
    return io_fail(r, IGEA_EFORMAT, 0, 0, 0, "row %ld, column %ld: NaN or Inf",
                   row0 + (long)(i / (size_t)r->cols) + 1, (long)(i % (size_t)r->cols) + 1);
}

int io_npy_next(igea_io_reader *r, long want, double *buf, int check)
{
    int st;
    if (!r->fortran || r->oned || r->cols == 1) {
        off_t off = r->data_off + (off_t)r->next_row * r->cols * 8;
        st = read_at(r, off, buf, (size_t)want * r->cols * 8);
    } else {
        st = fortran_block(r, want, buf);
    }
    if (st || (check && (st = io_npy_check_rows(r, r->next_row, want, buf))))
        return st;
    r->next_row += want;
    return 0;
}

int io_npy_mappable(const igea_io_reader *r)
{
    return r->map && !r->nomap && r->npy && r->s.seekable &&
           (!r->fortran || r->oned || r->cols == 1) &&
           (r->s.delta + r->data_off) % (off_t)sizeof(double) == 0;
}

void io_npy_unmap(igea_io_reader *r, int all)
{
    if (r->mbase && (all || !r->mwhole))
        munmap(r->mbase, r->mlen);
    if (all || !r->mwhole) {
        r->mbase = NULL;
        r->mlen = 0;
        r->mwhole = 0;
    }
}

/* Map len bytes of the file from offset start (page-aligned down) into
 * r->mbase, r->mlen; the address of start, or NULL when the system refuses. */
static const char *map_range(igea_io_reader *r, off_t start, size_t len)
{
    long pg = sysconf(_SC_PAGESIZE);
    off_t base = pg > 0 ? start - start % pg : start;
    size_t mlen = len + (size_t)(start - base);
    void *m = mmap(NULL, mlen, PROT_READ, MAP_PRIVATE, r->s.fd, base);
    if (m == MAP_FAILED)
        return NULL;
    posix_madvise(m, mlen, POSIX_MADV_SEQUENTIAL);
    r->mbase = m;
    r->mlen = mlen;
    return (const char *)m + (start - base);
}

int io_npy_view(igea_io_reader *r, long want)
{
    io_npy_unmap(r, 0);
    r->vrows = NULL;
    off_t first = r->s.delta + r->data_off; /* the data's offset in the file */
    size_t row = (size_t)r->cols * 8, total = (size_t)r->rows * row;
    off_t start = first + (off_t)r->next_row * (off_t)row;
    size_t len = (size_t)want * row;
    /* a file shortened since it was opened is refused, not mapped past its
     * end (reading such pages would raise SIGBUS) */
    struct stat sb;
    if (fstat(r->s.fd, &sb) != 0)
        return io_sysfail(r, IGEA_EREAD, errno, "read error");
    if (sb.st_size - start < (off_t)len)
        return truncated(r, (long long)(sb.st_size - first));
    const double *v;
    if (r->mwhole) {
        v = (const double *)(r->mdata + (size_t)r->next_row * row);
    } else if (total <= IO_MAP_WHOLE) { /* mapped once, kept for every pass */
        const char *d = map_range(r, first, total);
        if (!d)
            return 1;
        r->mwhole = 1;
        r->mdata = d;
        v = (const double *)(d + (size_t)r->next_row * row);
    } else {
        const char *d = map_range(r, start, len);
        if (!d)
            return 1;
        v = (const double *)d;
    }
    /* rows a pass before this one checked are not checked again; with
     * IGEA_IO_UNCHECKED the caller checks them */
    long from = r->checked > r->next_row ? r->checked : r->next_row;
    if (!r->unchecked && from < r->next_row + want) {
        int st = io_npy_check_rows(r, from, r->next_row + want - from,
                            v + (size_t)(from - r->next_row) * (size_t)r->cols);
        if (st) {
            io_npy_unmap(r, 0);
            return st;
        }
        r->checked = r->next_row + want;
    }
    r->vrows = v;
    r->vrow0 = r->next_row;
    r->vn = want;
    r->next_row += want;
    return 0;
}
