/* src/cli/cli.h - the igea driver's shared pieces: exit codes, strict
 * number parsing with file:line:column messages, text and .npy input
 * (whole or streamed in row blocks), atomic output files, JSON helpers.
 * The driver calls only the public library API besides these. */
#ifndef IGEA_CLI_H
#define IGEA_CLI_H

#include <math.h>
#include <stdio.h>

#include "igea.h"

/* Exit codes (sysexits-style, DESIGN.md). */
#define CLI_OK 0
#define CLI_REJECT 1    /* an accuracy test rejected: a verdict */
#define CLI_USAGE 64    /* bad command line */
#define CLI_DATAERR 65  /* malformed or invalid input data */
#define CLI_NOINPUT 66  /* an input file is missing or unreadable */
#define CLI_SOFTWARE 70 /* numerical or internal failure */
#define CLI_IOERR 74    /* writing output failed */

/* "igea: <message>\n" on stderr. */
void cli_error(const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 1, 2)))
#endif
    ;

/* "igea: out of memory (<what>)" and CLI_SOFTWARE. */
int cli_oom(const char *what);

/* Map a library status to an exit code, printing igea_strerror() with the
 * given context ("eqerr: ..."). Returns CLI_OK for 0. */
int cli_status(int status, const char *context);

/* Strict option values: the whole string must be a finite number / an int.
 * On failure print "option --name: 'text' is not a number" and return
 * CLI_USAGE. */
int cli_parse_double(const char *opt, const char *s, double *out);
int cli_parse_int(const char *opt, const char *s, int *out);
/* An option that takes a file or one positive number (--sigma FILE|NUM):
 * when v is a number, sets *is_number = 1 and *value; a number <= 0 prints
 * a message and returns CLI_USAGE. */
int cli_file_or_positive(const char *opt, const char *v, int *is_number, double *value);
/* Value of an option that takes one: argv[*i + 1] (advancing *i), or NULL
 * with a usage message when it is missing. */
const char *cli_optarg(int argc, char **argv, int *i);

/* ---- input ------------------------------------------------------------- */
/* A dense matrix, row-major (row r, column c at v[r * cols + c]). */
typedef struct {
    double *v;
    long rows;
    int cols;
} cli_matrix;

/* Read a whole text (whitespace or commas, '#' comments, blank lines
 * skipped; every row the same number of columns) or .npy (float64, any
 * order, 1-D or 2-D; 1-D gives one column; recognised by the name or, for
 * any other name, by its magic bytes) file. "-" is standard input; pipes,
 * FIFOs and devices are read as they come. A text line is at most
 * CLI_LINE_MAX bytes and holds no NUL byte; a comma between two digits in a
 * file whose values are otherwise separated by blanks is refused as a
 * decimal comma. Returns an exit code; messages name file:line:column (out
 * of memory: 70 "out of memory reading FILE"). An empty file is an error
 * (65). */
#define CLI_LINE_MAX (1L << 20)
int cli_read_matrix(const char *path, cli_matrix *out);
void cli_matrix_free(cli_matrix *m);

/* Streaming reader: row blocks of a text or .npy file in O(block) memory. */
typedef struct cli_reader cli_reader;
int cli_reader_open(const char *path, cli_reader **out);
/* The same, for two passes: cli_reader_rewind starts the file again (a
 * non-seekable input is copied to an anonymous temporary file as it is read
 * and the second pass reads the copy). */
int cli_reader_open_twice(const char *path, cli_reader **out);
int cli_reader_rewind(cli_reader *r);
/* Columns of the file (known after open for .npy, after the first data row
 * for text: cli_reader_open reads ahead one row). */
int cli_reader_cols(const cli_reader *r);
/* Read up to maxrows rows into buf (row-major, maxrows * cols doubles);
 * *nread = rows read, 0 at end of file. Returns an exit code. */
int cli_reader_next(cli_reader *r, long maxrows, double *buf, long *nread);
const char *cli_reader_path(const cli_reader *r);
void cli_reader_close(cli_reader *r);

/* At most one input of a command line may be "-" (an argument "-" that is
 * not the value of --out or --residuals): otherwise a message and
 * CLI_USAGE. argv[0] is the command name. */
int cli_one_stdin(int argc, char **argv);

/* ---- output ------------------------------------------------------------ */
/* An output stream that is either stdout (path NULL or "-") or a temporary
 * file in the target's directory renamed onto the target by cli_out_commit:
 * a failed run never leaves a half-written file. Symbolic links are
 * followed (the link's target is replaced); the replaced file keeps its
 * mode, a new one gets 0666 & ~umask; a target that is not a regular file (a
 * device, a FIFO) is written in place. The temporary file is removed if the
 * process is killed by SIGINT, SIGTERM, SIGHUP or SIGPIPE. */
typedef struct {
    FILE *f;
    char *tmp;
    char *path;
    int direct; /* writing the target itself (not a regular file) */
    int slot;   /* the temporary's entry in the signal clean-up table, + 1 */
} cli_out;
#define CLI_OUT_INIT {NULL, NULL, NULL, 0, 0}
int cli_out_open(cli_out *o, const char *path);
int cli_out_commit(cli_out *o); /* returns CLI_OK or CLI_IOERR */
/* Commit n outputs together: all are flushed and closed first, and renamed
 * only when every one is complete; on any failure all are removed. */
int cli_out_commit_all(cli_out *o, int n);
void cli_out_abort(cli_out *o);

/* Flush standard output: CLI_OK, or a message and CLI_IOERR when it cannot
 * be written (a command that also writes files calls it before committing
 * them, so that a lost summary is not a success). */
int cli_stdout_check(void);

/* Write a row-major matrix to path atomically: .npy (float64, C order) when
 * the name ends in ".npy", else text with %.17g and an optional '#' header
 * line (may be NULL). */
int cli_write_matrix(const char *path, const double *v, long rows, int cols,
                     const char *header);
/* The same contents to an open stream (errors show at the commit). */
void cli_write_matrix_body(FILE *f, int npy, const double *v, long rows, int cols,
                           const char *header);

/* JSON: a number (NaN/Inf become null), %.17g. */
void cli_json_num(FILE *f, double x);
/* JSON array of n doubles / ints. */
void cli_json_array(FILE *f, const double *x, long n);
void cli_json_iarray(FILE *f, const int *x, long n);
/* JSON string with escapes. */
void cli_json_str(FILE *f, const char *s);

/* ---- commands: int cmd_<name>(int argc, char **argv), argv[0] = name -- */
/* The driver: argv[1] names the command (or --help, --version); runs it,
 * then checks that standard output was written: a failed write or flush is
 * exit 74 with a message, whatever the command returned (unless that was
 * already a failure). main() is cli_run plus closing stdout. */
int cli_run(int argc, char **argv);

int cmd_eqerr(int argc, char **argv);
int cmd_test(int argc, char **argv);
int cmd_version(int argc, char **argv);
int cmd_accel(int argc, char **argv);
int cmd_regress(int argc, char **argv);
int cmd_envfun(int argc, char **argv);
int cmd_simulate(int argc, char **argv);
int cmd_montecarlo(int argc, char **argv);
int cmd_rls(int argc, char **argv);
int cmd_redund(int argc, char **argv);
int cmd_stability(int argc, char **argv);

#endif
