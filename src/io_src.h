/* src/io_src.h - private: the byte source of the matrix reader (io_src.c)
 * and the reader's state, shared by io.c (text, API) and io_npy.c. */
#ifndef IGEA_IO_SRC_H
#define IGEA_IO_SRC_H

#include <stddef.h>
#include <sys/types.h>

#include "igea/io.h"

/* Every input is read through a file descriptor with the reader's own
 * buffer: a regular file by pread at logical offsets, anything else
 * sequentially. A non-seekable input that must be read twice is copied as
 * it is read into an anonymous temporary file (the spool), which then
 * serves the second pass. */
#define IO_BUF 65536
#define IO_MSG 256
/* A .npy viewed through a map (IGEA_IO_MAP) whose data take at most this
 * many bytes is mapped whole once and kept over a rewind; a larger one
 * block by block. */
#define IO_MAP_WHOLE ((size_t)256 << 20)

typedef struct {
    int fd;       /* -1: none */
    int own;      /* close fd at the end (not a caller's descriptor) */
    int seekable; /* pread(fd, logical + delta) */
    off_t delta;
    off_t size;   /* seekable: logical size */
    off_t pos;    /* logical offset of buf[bpos] */
    unsigned char *buf;
    size_t bpos, blen;
    int eof;
    int tee;      /* spool receiving a copy of every byte read, -1 none */
    int inplace;  /* a regular file read where it is (not a spool) */
} io_src;

struct igea_io_reader {
    io_src s;
    int open, npy, cols, twice;
    int nan_ok; /* IGEA_IO_NAN: the token NaN (text) and NaN (.npy) are gaps */
    char *tmpdir;
    /* text */
    char *line;
    size_t cap;
    long lineno;
    double *vals; /* the last text row parsed */
    int vcap;
    int have_ahead; /* vals holds a row not yet handed out */
    int eof;
    long blank_gap_line, comma_line, comma_col; /* decimal-comma detection */
    long data_rows;                             /* data rows of this pass */
    int header_row;                             /* this pass met a header row */
    char *names, *cnames; /* the header's names; a comment line's */
    int nnames, ncnames;
    /* npy */
    long rows, next_row;
    int fortran, oned;
    off_t data_off;
    /* load */
    double *data;
    long nloaded;
    /* view (igea_io_reader_view) */
    int map, nomap;       /* IGEA_IO_MAP asked; the system refused a map */
    int unchecked;        /* IGEA_IO_UNCHECKED: a .npy's views not checked */
    void *mbase;          /* the pages mapped for the views, NULL */
    size_t mlen;
    int mwhole;           /* 1: mbase maps all the data (mdata), for every pass */
    const char *mdata;
    const double *vrows;  /* the current view, NULL */
    long vrow0, vn;       /* its first row (from 0) and its rows */
    double *vbuf;         /* rows of an input that is not mapped */
    long vrcap;           /* rows vbuf holds */
    long checked;         /* mapped .npy: rows checked finite (kept by rewind) */
    /* the last failure */
    int st, eerrno;
    long eline, ecol;
    char emsg[IO_MSG];
};

/* Record a failure in r and return status. */
int io_fail(igea_io_reader *r, int status, long line, long col, int err, const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 6, 7)))
#endif
    ;
/* A failed system call (errno err): IGEA_ENOMEM for ENOMEM, else status
 * with the errno kept. */
int io_sysfail(igea_io_reader *r, int status, int err, const char *what);

/* Append bytes to the buffer: 1 added, 0 end of input, < 0 a status. */
int io_src_more(igea_io_reader *r);
/* Sequential read of n bytes: the count (< n at the end) or < 0 a status. */
long long io_src_read(igea_io_reader *r, void *dst, size_t n);
/* Make the rest of the input seekable (a spool); 0 or a status. */
int io_src_spool(igea_io_reader *r);
/* A new spool for r (fd, or < 0 a status). */
int io_spool_new(igea_io_reader *r);
void io_src_close(io_src *s);

/* .npy (io_npy.c): the header (0 or a status), the next rows (checked
 * for NaN and Inf when check is 1). */
int io_npy_header(igea_io_reader *r);
int io_npy_next(igea_io_reader *r, long want, double *buf, int check);
/* Rows row0 .. row0 + n - 1 of a .npy at v finite: 0, else IGEA_EFORMAT
 * naming the first value that is not (row and column from 1). */
int io_npy_check_rows(igea_io_reader *r, long row0, long n, const double *v);
/* 1 when the rows of r may be viewed in place (IGEA_IO_MAP, a seekable
 * .npy in C order or with one column, data aligned for doubles). */
int io_npy_mappable(const igea_io_reader *r);
/* The next want rows mapped in place (the previous map released) into
 * r->vrows: 0, 1 when the system refused the map (nothing changed: read
 * them instead), or a status < 0. */
int io_npy_view(igea_io_reader *r, long want);
/* Release the current map, if any: a block's, or (all) also the whole
 * data's. */
void io_npy_unmap(igea_io_reader *r, int all);

#endif
