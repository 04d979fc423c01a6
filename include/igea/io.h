/*
 * igea/io.h - reading matrices from text and .npy files.
 *
 * One reader for every front end (the driver, Python, Fortran, C hosts), so
 * that a file that reads in one reads the same way in the others.
 *
 * Text: one row per line; values separated by blanks, tabs or commas; '#'
 * starts a comment; blank and comment lines are skipped; every row has the
 * same number of values. Numbers are C decimal numbers or Fortran ones, with
 * a D or d exponent (0.1000000000000000D+01). Refused, naming line and
 * column: anything that is not a finite number, a Fortran list-directed
 * repeat count (3*1.0), a NUL byte, a line longer than IGEA_IO_LINE_MAX
 * bytes, a decimal comma (a comma between two digits in a file whose values
 * are otherwise separated by blanks), a row with another number of values
 * than the rows before. A UTF-8 byte order mark at the start and CR before
 * the line feed (CRLF) are ignored.
 *
 * Column names [D]: a header row (the first line that is not blank or a
 * comment, when every field on it is a name: a word that starts with a
 * letter or '_' and is not a number, or a "quoted" text), or a '#' comment
 * line of names before the first data row (igea's own '# name name ...'
 * header; the last such line counts, and only when it names as many
 * columns as the rows have). A header row must name every column.
 *
 * .npy: version 1, 2 or 3, little-endian float64 ('<f8'), C or Fortran
 * order, 1-D (one column) or 2-D; recognised by a name ending in ".npy" or
 * by its magic bytes. The header is checked against the data really present
 * before anything is sized from it; NaN and Inf are refused.
 *
 * Inputs: a path, or a descriptor the caller opened (standard input, a
 * pipe, a FIFO, a socket, a device, a regular file at its current offset).
 * A non-seekable input is read as it comes; opened with IGEA_IO_TWICE it is
 * copied as it is read to an anonymous temporary file (created in tmpdir,
 * unlinked at once) which serves the second pass; a Fortran-order or wide
 * (more than 512 columns) .npy from a non-seekable input is copied first.
 *
 * Errors: a failed call returns its status and keeps, in the reader, the
 * line and column (1-based, 0 when not known), the errno of a system error
 * and a message text without the path (igea_io_reader_info,
 * igea_io_reader_message): the caller writes "PATH:LINE:COL: message" in its
 * own words. The library prints nothing.
 *   IGEA_EFORMAT   the input is not what the format says
 *   IGEA_EREAD     the input cannot be opened or read (errno kept)
 *   IGEA_ETEMPFILE the temporary copy for a second pass cannot be made or
 *                  written (errno kept)
 *   IGEA_ENOMEM    out of memory
 *
 * Memory: the caller allocates every array it receives (row blocks, the
 * copy of a whole matrix); the reader's own memory is freed by
 * igea_io_reader_free. No memory crosses to the caller to be freed, so a
 * host with its own allocator (Python, Fortran) needs no release function.
 *
 * Thread safety: reentrant; a reader belongs to one thread at a time.
 */
#ifndef IGEA_IO_H
#define IGEA_IO_H

#include "igea/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Longest text line, bytes (without the line feed). */
#define IGEA_IO_LINE_MAX 1048576

/* Flags of igea_io_reader_open. */
#define IGEA_IO_TWICE 1 /* igea_io_reader_rewind will be called */
#define IGEA_IO_MAP 2   /* igea_io_reader_view may hand out the rows of a .npy
                           file in place, through a memory map */
#define IGEA_IO_NAN 4   /* a gap: the text token NaN (exactly these three
                           letters) and a .npy NaN are read as NaN; any other
                           spelling (nan, NAN, an empty field) and Inf stay
                           refused */
#define IGEA_IO_UNCHECKED 8 /* igea_io_reader_view hands out a .npy's rows
                               without checking them for NaN and Inf: the
                               caller does (igea_io_reader_view_check) */

/* Slots of igea_io_reader_info (integers stored as exact doubles). */
#define IGEA_IO_INFO_STATUS 0 /* status of the last failed call, 0 none */
#define IGEA_IO_INFO_LINE 1   /* its line, 1-based, 0 when not known */
#define IGEA_IO_INFO_COLUMN 2 /* its column (bytes from the line's start,
                                 after a byte order mark), 1-based, 0 */
#define IGEA_IO_INFO_ERRNO 3  /* errno of a system error, 0 */
#define IGEA_IO_INFO_COLS 4   /* columns of the open input, 0 */
#define IGEA_IO_INFO_ROWS 5   /* rows held after igea_io_reader_load, 0 */
#define IGEA_IO_INFO_NAMES 6  /* 1 when the input names its columns */
#define IGEA_IO_INFO_NPY 7    /* 1 for a .npy input, 0 for text */
#define IGEA_IO_INFO_NPY_ROWS 8 /* rows its .npy header states, 0 */
#define IGEA_IO_INFO_CHECKED 9  /* 1 when those rows were checked against the
                                   bytes present (a seekable input) */
#define IGEA_IO_INFO_NPY_DATA 10 /* a .npy read where it is in a regular file
                                    (not a temporary copy): the byte offset of
                                    its first value in that file; -1 */
#define IGEA_IO_INFO_NPY_FORTRAN 11 /* 1 for a .npy in Fortran order with more
                                       than one column (a column's values
                                       then follow each other), 0 */
#define IGEA_IO_INFO_LEN 16

typedef struct igea_io_reader igea_io_reader;

/* A new reader, not yet open, into *out (the handle; igea_io_reader_free
 * releases it). Returns 0, -1 (out NULL) or IGEA_ENOMEM (*out = NULL). */
IGEA_API int igea_io_reader_create(igea_io_reader **out);
/* Release a reader and close what it opened (a descriptor given to
 * igea_io_reader_open_fd stays open). r may be NULL. */
IGEA_API void igea_io_reader_free(igea_io_reader *r);

/* Open the file at path (NUL-terminated) for reading, check a .npy header
 * or read the first text row ahead (the columns are known after it).
 * flags: 0 or any of IGEA_IO_TWICE, IGEA_IO_MAP, IGEA_IO_NAN, IGEA_IO_UNCHECKED (|).
 * tmpdir: directory of a temporary copy
 * (may be NULL: "/tmp"). A reader that is already open is closed first.
 * Returns 0, -1..-4 for an invalid argument (r NULL, path NULL, flags
 * unknown), IGEA_EREAD, IGEA_EFORMAT (an empty input: no data),
 * IGEA_ETEMPFILE or IGEA_ENOMEM, the error kept in r. */
IGEA_API int igea_io_reader_open(igea_io_reader *r, const char *path, int flags,
                                 const char *tmpdir);
/* The same for descriptor fd (>= 0, open for reading; not closed by the
 * reader), known as name (may be NULL: ""; a name ending in ".npy" says
 * .npy, any other is recognised by the bytes). A regular file is read from
 * its current offset. Returns as igea_io_reader_open (-2: fd < 0). */
IGEA_API int igea_io_reader_open_fd(igea_io_reader *r, int fd, const char *name, int flags,
                                    const char *tmpdir);

/* Columns of the open input (>= 1), or 0 when r is NULL or not open. */
IGEA_API int igea_io_reader_cols(const igea_io_reader *r);
/* The column names of the open input, separated by '\n' (valid until the
 * reader is opened again or freed), or "" when it has none (or r is NULL). */
IGEA_API const char *igea_io_reader_names(const igea_io_reader *r);

/* Read up to maxrows (>= 1) rows into buf (row-major, maxrows * cols
 * doubles); *nread = rows read (0 at the end of the input). Returns 0, -1..-4
 * for an invalid argument (r NULL or not open), IGEA_EFORMAT, IGEA_EREAD,
 * IGEA_ETEMPFILE or IGEA_ENOMEM. On a failure *nread is untouched and buf
 * may hold part of the rows read. */
IGEA_API int igea_io_reader_next(igea_io_reader *r, int maxrows, double *buf, int *nread);
/*
 * The next rows without a copy where the input allows it: up to maxrows
 * (>= 1) rows, row-major (cols values each), are made available at
 * igea_io_reader_view_rows(r); *nread = their number (0 at the end of the
 * input). With IGEA_IO_MAP, a regular .npy file in C order (or with one
 * column) whose data start at a multiple of 8 bytes is viewed where it
 * lies, through a read-only memory map: data of up to 256 MiB mapped whole
 * at the first view and kept until the reader is closed (both passes read
 * the same pages; they count in the process's resident set once read),
 * larger data block by block (each view's pages replace the last's). Any
 * other input, or a map the system refuses, is read as
 * igea_io_reader_next reads it into a buffer the reader owns. The rows are
 * checked as igea_io_reader_next checks them (NaN and Inf refused with the
 * row and column); on a mapped file the rows of a second pass that the
 * first pass checked are not checked again, and the file's size is
 * checked before each view. A mapped file that another process truncates
 * while it is read raises SIGBUS in the reading process, as any memory map
 * of a file does: a host that cannot accept that opens without
 * IGEA_IO_MAP. Returns as igea_io_reader_next (-3: nread NULL); on a
 * failure the view is empty.
 */
IGEA_API int igea_io_reader_view(igea_io_reader *r, int maxrows, int *nread);
/* The rows of the last igea_io_reader_view (maxrows * cols doubles at
 * most, *nread rows of them), valid until the next call on r; NULL when
 * none (r NULL or not open, before a view, after a failure, a rewind or
 * the end of the input). */
IGEA_API const double *igea_io_reader_view_rows(const igea_io_reader *r);
/*
 * Opened with IGEA_IO_UNCHECKED, the views of a .npy are not checked for
 * NaN and Inf (the check reads every value once more: a caller that
 * passes the rows to a function which reads them all anyway and refuses
 * non-finite data, e.g. igea_eqerr_accumulate with its IGEA_ENONFINITE,
 * saves that pass). The caller then checks each view before it relies on
 * its values, and on such a refusal calls igea_io_reader_view_check:
 * the rows of the current view are checked as igea_io_reader_view would
 * have checked them. Returns 0 (every value finite; also for text, whose
 * non-finite numbers are refused as they are read, and when there is no
 * view), -1 (r NULL or not open) or IGEA_EFORMAT with the row and column
 * of the first non-finite value in the message, as the view's own check
 * words it.
 */
IGEA_API int igea_io_reader_view_check(igea_io_reader *r);
/* Start the input again (opened with IGEA_IO_TWICE): the next row is the
 * first. Returns 0, -1 (r NULL, not open or not opened for two passes),
 * IGEA_EREAD, IGEA_ETEMPFILE or IGEA_ENOMEM. */
IGEA_API int igea_io_reader_rewind(igea_io_reader *r);

/* Read every remaining row into the reader; their number is then
 * info[IGEA_IO_INFO_ROWS] and igea_io_reader_copy writes them. Returns as
 * igea_io_reader_next (-1: r NULL or not open). */
IGEA_API int igea_io_reader_load(igea_io_reader *r);
/* The rows held by igea_io_reader_load into v (rows * cols doubles): layout
 * IGEA_ROWMAJOR (row i, column j at v[i * cols + j]) or IGEA_COLMAJOR
 * (v[j * rows + i]). Returns 0, -1 (r NULL or nothing loaded), -2 (v NULL),
 * -3 (layout unknown). */
IGEA_API int igea_io_reader_copy(const igea_io_reader *r, double *v, int layout);

/* The state of r into info (IGEA_IO_INFO_LEN doubles, slots
 * IGEA_IO_INFO_*). Returns 0, -1 (r NULL), -2 (info NULL). */
IGEA_API int igea_io_reader_info(const igea_io_reader *r, double *info);
/* The message of the last failure (without the path; "" when none, or r
 * NULL); valid until the next call on r. */
IGEA_API const char *igea_io_reader_message(const igea_io_reader *r);

/* One number in the reader's syntax: s (NUL-terminated) wholly a decimal
 * number, exponent e, E, d or D (leading blanks allowed). Returns 0 (*x
 * set), IGEA_EFORMAT (not a number, *x untouched), IGEA_ENONFINITE (NaN or
 * Inf written out, *x untouched) or IGEA_EOVERFLOW (out of the range of a
 * double, overflow or underflow; *x untouched). */
IGEA_API int igea_io_parse_number(const char *s, double *x);

#ifdef __cplusplus
}
#endif

#endif
