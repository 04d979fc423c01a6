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

/* Strict option values: the whole string must be a finite number (the
 * library's syntax, igea_io_parse_number: D exponents too) / an int.
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

/* Read a whole text or .npy file through the library's reader (igea/io.h
 * says what it accepts: blanks, tabs or commas, '#' comments, D exponents,
 * a header row or '# names' line of column names, BOM and CRLF; decimal
 * commas and repeat counts refused; .npy float64 in C or Fortran order).
 * "-" is standard input; pipes, FIFOs and devices are read as they come.
 * Returns an exit code; messages name file:line:column (65 bad data, 66
 * unreadable, 74 temporary copy, 70 "out of memory reading FILE"). An empty
 * file is an error (65). */
#define CLI_LINE_MAX IGEA_IO_LINE_MAX
int cli_read_matrix(const char *path, cli_matrix *out);
void cli_matrix_free(cli_matrix *m);

/* The numbers of a file in any layout, malloc'd into *out: exactly n of them
 * (n >= 0; otherwise a message "PATH: K values, but WHAT needs N" and
 * CLI_DATAERR) or, for n < 0, as many as it holds; *count (may be NULL) gets
 * how many. */
int cli_read_vector(const char *path, long n, const char *what, double **out, long *count);
/* FILE|NUMBER: a number (> 0) gives n copies of it (n >= 1), a file
 * cli_read_vector(arg, n, ...). */
int cli_read_values(const char *arg, long n, const char *what, double **out, long *count);

/* Streaming reader: row blocks of a text or .npy file in O(block) memory. */
typedef struct cli_reader cli_reader;
int cli_reader_open(const char *path, cli_reader **out);
/* The same, reading the token NaN (and a .npy NaN) as a gap (IGEA_IO_NAN). */
int cli_reader_open_gaps(const char *path, cli_reader **out);
/* The same, for two passes: cli_reader_rewind starts the file again (a
 * non-seekable input is copied to an anonymous temporary file as it is read
 * and the second pass reads the copy); cli_reader_view may map a .npy file
 * (a SIGBUS handler then turns a file shortened meanwhile into exit 66). */
int cli_reader_open_twice(const char *path, cli_reader **out);
/* cli_reader_open_twice whose .npy views are not checked for NaN and Inf
 * (IGEA_IO_UNCHECKED): the caller checks each view's values, and before it
 * reports any failure met after the view, calls cli_reader_view_check, so
 * that a NaN or Inf is reported first, as a checked view would have. */
int cli_reader_open_unchecked(const char *path, cli_reader **out);
int cli_reader_rewind(cli_reader *r);
/* Columns of the file (known after open for .npy, after the first data row
 * for text: cli_reader_open reads ahead one row). */
int cli_reader_cols(const cli_reader *r);
/* The rows of the input when known before reading them (a .npy file whose
 * header was checked against its size), else -1. */
long cli_reader_rows_known(const cli_reader *r);
/* Where a .npy input's values are, read where they are in a regular file:
 * *data the byte offset of the first value, *fortran 1 for Fortran order
 * with more than one column. Returns 1, or 0 (text, a pipe, a copy). */
int cli_reader_npy_data(const cli_reader *r, double *data, int *fortran);
/* Read up to maxrows rows into buf (row-major, maxrows * cols doubles);
 * *nread = rows read, 0 at end of file. Returns an exit code. */
int cli_reader_next(cli_reader *r, long maxrows, double *buf, long *nread);
/* The next up to maxrows rows without a copy where the input allows it
 * (igea_io_reader_view: a .npy file opened by cli_reader_open_twice is
 * viewed through a memory map): *rows valid until the next call on r,
 * *nread rows, 0 at the end. Returns an exit code. */
int cli_reader_view(cli_reader *r, long maxrows, const double **rows, long *nread);
/* The same; when it fails, the current view of `unchecked` (opened by
 * cli_reader_open_unchecked, its block read before this one's; NULL: none)
 * is checked first. */
int cli_reader_view_after(cli_reader *r, long maxrows, const double **rows, long *nread,
                          cli_reader *unchecked);
/* The current view's values checked (igea_io_reader_view_check): CLI_OK,
 * or the message "PATH: row R, column C: NaN or Inf" and its exit code. */
int cli_reader_view_check(cli_reader *r);
const char *cli_reader_path(const cli_reader *r);
/* The column names of the input, '\n'-separated, or "" (igea/io.h). */
const char *cli_reader_names(const cli_reader *r);
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

/* ---- JSON --------------------------------------------------------------- */
/* The writer: cli_json_begin opens the top-level object, every value is
 * written with its key (NULL inside an array), containers are opened and
 * closed, cli_json_end closes whatever is open. Separators, indentation and
 * string escapes are the writer's; numbers are %.17g, NaN and Inf null. */
#define CLI_JSON_DEPTH 8
typedef struct {
    FILE *f;
    int depth;
    int count[CLI_JSON_DEPTH];
    int lines[CLI_JSON_DEPTH];
    char close[CLI_JSON_DEPTH];
} cli_json;
void cli_json_begin(cli_json *j, FILE *f);
void cli_json_end(cli_json *j);
void cli_json_open(cli_json *j, const char *key, char bracket); /* '{' or '[' */
void cli_json_close(cli_json *j);
void cli_jnum(cli_json *j, const char *key, double x);
void cli_jint(cli_json *j, const char *key, long x);
void cli_jbool(cli_json *j, const char *key, int x);
void cli_jstr(cli_json *j, const char *key, const char *s); /* NULL: null */
void cli_jnums(cli_json *j, const char *key, const double *x, long n);
void cli_jints(cli_json *j, const char *key, const int *x, long n);
void cli_jbools(cli_json *j, const char *key, const int *x, long n);

/* ---- options -------------------------------------------------------------- */
/* One table per command: name, kind, target, default (as text: set before
 * parsing and shown in --help), argument name (for CHOICE either
 * CLI_CHOICES(IGEA_CHOICE_...), a library enumeration whose names --help
 * lists and whose code the target receives, or the driver's own words
 * "a|b|c", whose index it receives), help text ('\n' continues on an
 * indented line), and an optional int set to 1 when the option is given.
 * FLAG sets its int to 1 (default 0), CLEAR sets it to 0 (a --no-x flag,
 * default 1). DSET and DCLEAR set a double (a slot of a library options
 * array) to 1 or 0 and leave it alone otherwise. HEAD is a heading line of
 * the help (help text only); END closes the table. A default of CLI_DEF_LIB
 * leaves the target as the command set it (from the library's defaults) and
 * shows that value in the help. --help and -h print the help. */
enum { CLI_OPT_END, CLI_OPT_FLAG, CLI_OPT_CLEAR, CLI_OPT_INT, CLI_OPT_NUM, CLI_OPT_STR,
       CLI_OPT_CHOICE, CLI_OPT_DSET, CLI_OPT_DCLEAR, CLI_OPT_HEAD };
#define CLI_DEF_LIB "\001"
#define CLI_CHOICE_MARK "\002"
#define CLI_CHOICE_STR_(k) #k
#define CLI_CHOICE_STR(k) CLI_CHOICE_STR_(k)
#define CLI_CHOICES(kind) CLI_CHOICE_MARK CLI_CHOICE_STR(kind)
typedef struct {
    const char *name;
    int kind;
    void *target;
    const char *def;
    const char *arg;
    const char *help;
    int *given;
} cli_opt;
#define CLI_HEAD(text) {NULL, CLI_OPT_HEAD, NULL, NULL, NULL, text, NULL}
#define CLI_JSON_OPT(t) {"--json", CLI_OPT_FLAG, t, NULL, NULL, "machine-readable output", NULL}
#define CLI_OUT_OPT(t)                                                                       \
    {"--out", CLI_OPT_STR, t, NULL, "FILE", "write the report there (atomically; '-' is\n"  \
                                           "standard output) instead of standard output", NULL}
#define CLI_END {NULL, CLI_OPT_END, NULL, NULL, NULL, NULL, NULL}

typedef struct {
    const char *name;  /* the command, for messages */
    const char *intro; /* help text before the option list */
    const cli_opt *opts;
    const char *outro; /* help text after it */
} cli_command;

/* Returned by cli_parse when --help was printed (the command returns CLI_OK). */
#define CLI_HELP (-1)
/* Defaults, then argv[1..]: CLI_OK, CLI_HELP or CLI_USAGE (with a message).
 * Every argument is an option: a bare word is refused; at most one input
 * may be '-' (cli_one_stdin). */
int cli_parse(const cli_command *c, int argc, char **argv);
void cli_help(FILE *f, const cli_command *c);
/* value, a name of the library's enumeration kind (IGEA_CHOICE_*): *code =
 * its code, or a message listing the library's names and CLI_USAGE. */
int cli_choice(const char *opt, int kind, const char *value, int *code);
/* The names of enumeration kind as "a|b|c" in buf (size bytes). */
#define CLI_CHOICE_MAX 32
#define CLI_CHOICE_TEXT 256
const char *cli_choice_names(int kind, char *buf, size_t size);
/* value among the driver's own words "a|b|c" (a command's sub-command or
 * method, not a library code): *index = its position, or a message and
 * CLI_USAGE. */
int cli_pick(const char *opt, const char *value, const char *words, int *index);
/* The status of a library options check (igea_eqerr_check_opts, ...): 0 is
 * CLI_OK; 1 + slot names the slot's option (the slot name with '-' for '_')
 * in a usage message. */
int cli_check_opts(const char *cmd, int module, int status);
/* Set OpenBLAS to n threads (n >= 1) and return the count it had (0, and
 * nothing done, without OpenBLAS or for n < 1): a command that runs its own
 * threads calls cli_blas_threads(1) for their duration, then restores the
 * count. Process state: the driver's to change, never the library's. */
int cli_blas_threads(int n);
/* A comma-separated list: *items (one malloc'd block, free(*items)) points to
 * *n non-empty items. */
int cli_split_list(const char *list, char ***items, int *n);

/* ---- progress on stderr (progress.c) ------------------------------------ */
/* The long commands (montecarlo, stability, eqerr) put CLI_PROGRESS_OPTIONS in
 * their table and report their chunks of work: a line updated in place when
 * stderr is a terminal, one line per 10 % (percentage, elapsed time, ETA)
 * with --progress, nothing with --quiet. Only stderr is written: results
 * never depend on it. */
extern int cli_progress_opt, cli_quiet_opt;
#define CLI_PROGRESS_OPTIONS                                                                   \
    {"--progress", CLI_OPT_FLAG, &cli_progress_opt, NULL, NULL, "progress and ETA on stderr, a line per 10 %\n"  \
     "(automatic, updated in place, when stderr is a\nterminal)", NULL},                        \
    {"--quiet", CLI_OPT_FLAG, &cli_quiet_opt, NULL, NULL, "no progress on stderr", NULL}
typedef struct {
    const char *cmd, *unit;
    double total, t0;
    int mode; /* 0 silent, 1 terminal (in place), 2 a line per 10 % */
    int decile, shown;
    double last; /* cli_progress_count's last count shown */
} cli_progress;
/* The total of a count not known in advance (cli_progress_count). */
#define CLI_PROGRESS_UNKNOWN (-1.0)
/* Start counting total units (flights, taus) of command cmd: CLI_OK, or a
 * message and CLI_USAGE for --progress with --quiet. */
int cli_progress_start(cli_progress *p, const char *cmd, const char *unit, double total);
/* done units of the total are finished. */
void cli_progress_update(cli_progress *p, double done);
/* done units so far of a total not known (started with
 * CLI_PROGRESS_UNKNOWN): the count and the elapsed time, in place on a
 * terminal, with --progress a line each time the count has doubled. */
void cli_progress_count(cli_progress *p, double done);
void cli_progress_end(cli_progress *p);

/* ---- flights (flight.c) ------------------------------------------------ */
/* --terms LIST ('default', 'all' or names) into term codes (malloc'd). */
int cli_parse_terms(int system, const char *list, int **codes, int *n);
/* A trajectory file (rows t f3 w3 q4) into a column-major array. */
int cli_read_traj(const char *path, double **traj, int *nsamp);
/* "name name ..." of the terms (malloc'd; NULL when out of memory). */
char *cli_term_header(const int *codes, int n);
/* Epochs every step seconds from t0 + step to t1, or those of a file. */
int cli_epochs(const char *file, double step, double t0, double t1, double **ep, int *n);
/* --spec default|FILE: the specs of the terms (malloc'd). */
int cli_term_specs(int system, const int *codes, int n, const char *arg, double **spec);

/* The flight-model options of simulate and montecarlo (CLI_FLIGHT_OPTIONS
 * in their tables; cli_flight_defaults before parsing). */
typedef struct {
    const char *traj, *terms, *epochs, *spec, *x, *sigma;
    double duration, rate, step, sigma_growth;
    int system, seed, generator;
    double opts[IGEA_SIM_OPT_LEN];
} cli_flight_args;
extern cli_flight_args cli_flight_opts;
void cli_flight_defaults(void);
#define CLI_FLIGHT_MODEL_OPTIONS                                                               \
    CLI_HEAD("flight model:"),                                                                 \
    {"--traj", CLI_OPT_STR, &cli_flight_opts.traj, NULL, "FILE", "trajectory (t f3 w3 q4 rows, see igea envfun\n"   \
     "--help), or the reference boost:", NULL},                                                \
    {"--duration", CLI_OPT_NUM, &cli_flight_opts.duration, "120", "S", "the reference boost (METHODS 5.6) of S seconds", NULL}, \
    {"--rate", CLI_OPT_NUM, &cli_flight_opts.rate, "50", "HZ", "sampled at HZ", NULL},          \
    {"--system", CLI_OPT_CHOICE, &cli_flight_opts.system, "strapdown", CLI_CHOICES(IGEA_CHOICE_ENVFUN_SYSTEM), "the inertial system", NULL}, \
    {"--terms", CLI_OPT_STR, &cli_flight_opts.terms, "default", "LIST", "term names, 'default' (21-term model) or 'all'", NULL}, \
    {"--epoch-step", CLI_OPT_NUM, &cli_flight_opts.step, "1", "DT", "tracking epochs every DT s", NULL}, \
    {"--epochs", CLI_OPT_STR, &cli_flight_opts.epochs, NULL, "FILE", "or the tracking epochs of a file", NULL}, \
    {"--spec", CLI_OPT_STR, &cli_flight_opts.spec, NULL, "FILE", "1-sigma specs of the terms (default: igea envfun\n--list)", NULL}, \
    {"--sigma", CLI_OPT_STR, &cli_flight_opts.sigma, "0.01", "FILE|NUM", "stated tracking 1-sigma (m/s), one per row or one\nnumber", NULL}, \
    {"--sigma-growth", CLI_OPT_NUM, &cli_flight_opts.sigma_growth, "0", "G", "stated (and true) sigma grows by 1 + G e/(M-1)\n" \
     "along the epochs, as with range", NULL}
#define CLI_FLIGHT_TRUTH_OPTIONS                                                               \
    CLI_HEAD("true errors:"),                                                                  \
    {"--x", CLI_OPT_STR, &cli_flight_opts.x, NULL, "NAME=K,...", "these terms at K x spec; the others drawn N(0, 1)", NULL}, \
    {"--sigma-w", CLI_OPT_NUM, &cli_flight_opts.opts[IGEA_SIM_OPT_SIGMA_W], CLI_DEF_LIB, "W", "true tracking noise = W x stated", NULL}, \
    {"--ar1", CLI_OPT_NUM, &cli_flight_opts.opts[IGEA_SIM_OPT_AR1], CLI_DEF_LIB, "PHI", "AR(1) correlation of the noise along epochs", NULL}, \
    {"--growth", CLI_OPT_NUM, &cli_flight_opts.opts[IGEA_SIM_OPT_GROWTH], CLI_DEF_LIB, "G", "unstated noise growth: true sd x (1 + G e/(M-1))", NULL}, \
    {"--outlier-prob", CLI_OPT_NUM, &cli_flight_opts.opts[IGEA_SIM_OPT_OUTLIER_PROB], CLI_DEF_LIB, "P", "probability of an outlier per row", NULL}, \
    {"--outlier-scale", CLI_OPT_NUM, &cli_flight_opts.opts[IGEA_SIM_OPT_OUTLIER_SCALE], CLI_DEF_LIB, "K", "outlier sd in row sds", NULL}, \
    {"--seed", CLI_OPT_INT, &cli_flight_opts.seed, "0", "N", "random seed", NULL},          \
    {"--generator", CLI_OPT_CHOICE, &cli_flight_opts.generator, "mt19937", CLI_CHOICES(IGEA_CHOICE_SIM_GENERATOR), "random number generator", NULL}

/* The noise models beyond white (IGEA_SIM_OPT_AR2 .. JUDGE_NOISE), for
 * igea simulate and igea montecarlo. */
#define CLI_FLIGHT_NOISE_OPTIONS                                                               \
    CLI_HEAD("noise models:"),                                                                 \
    {"--ar2", CLI_OPT_NUM, &cli_flight_opts.opts[IGEA_SIM_OPT_AR2], CLI_DEF_LIB, "PHI", "AR lag-2 coefficient (with --ar1: AR(2))", NULL}, \
    {"--ar3", CLI_OPT_NUM, &cli_flight_opts.opts[IGEA_SIM_OPT_AR3], CLI_DEF_LIB, "PHI", "AR lag-3 coefficient", NULL}, \
    {"--corr", CLI_OPT_NUM, &cli_flight_opts.opts[IGEA_SIM_OPT_CORR], CLI_DEF_LIB, "R", "per-epoch x-y-z correlation [[1 r r^2][r 1 r][r^2 r 1]],\n" \
     "r ramping 0 .. R along the epochs", NULL},                                                \
    {"--group-split", CLI_OPT_NUM, &cli_flight_opts.opts[IGEA_SIM_OPT_GROUP_SPLIT], CLI_DEF_LIB, "F", "two stations: epochs before F M are group 0", NULL}, \
    {"--sigma-w2", CLI_OPT_NUM, &cli_flight_opts.opts[IGEA_SIM_OPT_SIGMA_W2], CLI_DEF_LIB, "W", "true sigma_w of group 1 (0: --sigma-w)", NULL}, \
    {"--bias0", CLI_OPT_NUM, &cli_flight_opts.opts[IGEA_SIM_OPT_BIAS0], CLI_DEF_LIB, "B", "bias of group 0 rows, in stated sigmas", NULL}, \
    {"--bias1", CLI_OPT_NUM, &cli_flight_opts.opts[IGEA_SIM_OPT_BIAS1], CLI_DEF_LIB, "B", "bias of group 1 rows, in stated sigmas", NULL}

/* A flight model built from the options: trajectory, terms, epochs, specs,
 * true X settings and the library's model. */
typedef struct {
    double *traj, *ep, *spec, *xval;
    int *codes, *xfix, nsamp, nep, m, N;
    igea_sim_model *model;
} cli_flight;
int cli_flight_build(const cli_flight_args *a, cli_flight *f, const char *cmd);
/* The model's stated sigma, specs (f->spec or none), truth and noise. */
int cli_flight_set(const cli_flight_args *a, cli_flight *f, const char *cmd);
/* The noise options (opts with the generator set). */
void cli_flight_noise(const cli_flight_args *a, double *opts);
void cli_flight_free(cli_flight *f);

/* ---- shared steps of the commands (report.c) ----------------------------- */
/* A matrix file into a column-major array (malloc'd); *rows, *cols. */
int cli_read_colmajor(const char *path, double **v, int *rows, int *cols);
/* A row-major copy of a column-major rows x cols array (malloc'd; NULL when
 * out of memory). */
double *cli_rowmajor(const double *v, long rows, int cols);
/* A rows x cols matrix as an array of row arrays, each row on its own line;
 * element (i, k) is v[i rs + k cs] (row-major: rs = cols, cs = 1;
 * column-major: rs = 1, cs = rows), or iv[...] when v is NULL. */
void cli_jmatrix(cli_json *j, const char *key, const double *v, const int *iv, int rows,
                 int cols, long rs, long cs);
/* A row-major rows x cols matrix as an array of row arrays, inline. */
void cli_jrows(cli_json *j, const char *key, const double *v, int rows, int cols);
/* An array of n strings; of the names of n term codes. */
void cli_jstrs(cli_json *j, const char *key, const char *const *s, int n);
void cli_jterms(cli_json *j, const char *key, const int *codes, int n);
/* A failed option check: msg (not NULL) as the usage message and CLI_USAGE;
 * CLI_OK for NULL. */
int cli_usage(const char *msg);

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
int cmd_triad(int argc, char **argv);
/* igea accel --model ieee and --design (cmd_accel_ieee.c). */
typedef struct {
    const char *data, *out;
    int model, method, axis, json;
    double tol, head_ratio;
} cli_accel_args;
int cli_accel_ieee(const cli_accel_args *a);
int cli_accel_design(const cli_accel_args *a);
/* --history LIST: earlier 'igea accel --method joint --json' results (coef,
 * cov, flags): b (np x m) and V (m blocks np x np) in one allocation at *b
 * (free(*b)); *m files. */
int cli_accel_history_read(const char *list, int np, double **b, double **V, int *m);
int cmd_regress(int argc, char **argv);
int cmd_envfun(int argc, char **argv);
int cmd_simulate(int argc, char **argv);
int cmd_montecarlo(int argc, char **argv);
int cmd_rls(int argc, char **argv);
int cmd_redund(int argc, char **argv);
int cmd_stability(int argc, char **argv);
int cmd_impact(int argc, char **argv);
int cmd_nav(int argc, char **argv);
int cmd_dw(int argc, char **argv);

/* igea eqerr with the noise models (eqerr_noise.c): --cov, --xcov, --ar,
 * --ar-phi, --groups, --robust, --group-bias read the whole flight and call
 * igea_noise_eqerr (igea_noise_eqerr_xcov with --xcov). */
typedef struct {
    const char *S, *dw, *sigma, *spec, *cov, *groups;
    int json, p_given;
    double phi[9];
    const double *opts;
    const char *xcov; /* --xcov: the cross blocks X_e of igea dw --xcov-out */
} cli_noise_args;
int cli_noise_parse_phi(const char *arg, double *phi, int *p);
/* The results of igea_noise_eqerr_resid (lambda's block holds P, xhat, z,
 * the group table, the row w-statistics and the whitened residuals). */
typedef struct {
    int m, N, G;
    double *lambda, *P, *xhat, *z, *gout, *row_w, *resid, *spec;
    double info[IGEA_STATS_INFO_LEN], ar[IGEA_NOISE_AR_OUT_LEN];
    int *reject;
    int ar_method; /* IGEA_NOISE_AR_* that estimated phi; -1: phi given or p = 0 */
} cli_noise_result;
int cli_eqerr_noise(const cli_noise_args *a, cli_noise_result *r);
void cli_noise_result_free(cli_noise_result *r);
/* The noise route's own lines (phi, group scales, rejected rows, the
 * outer iteration) and JSON fields. */
void cli_noise_text(FILE *f, const cli_noise_args *a, const cli_noise_result *r);
void cli_noise_json(cli_json *j, const cli_noise_result *r);

/* ---- SVG pictures (svg.c) ------------------------------------------------ */
/* A self-contained SVG writer for --plot FILE.svg: panels with linear or
 * log10 axes (ticks, labels with units), series as polylines, markers,
 * error bars, bands, marker lines and a legend. Text is escaped for XML
 * (control characters and invalid UTF-8 become '?'); a NaN or Inf (and, on
 * a log axis, a value <= 0) is never written: the point is left out.
 * Series carry class="series", markers class="marker", bands
 * class="band", error bars class="errbar", marker lines class="hline" or
 * "vline", the legend class="legend", the axes class="axes". Colours are
 * indices into a fixed palette. */
#define CLI_SVG_LEGEND_MAX 12
typedef struct {
    double lo, hi;     /* data range (cli_svg_range; empty: lo > hi) */
    int log;           /* 1: log10 axis */
    const char *label; /* the quantity and its unit, "tau (s)" */
    int integer;       /* 1: ticks at integers only (indices) */
    int noticks;       /* 1: no ticks, tick labels or grid (the caller labels it) */
} cli_svg_axis;
typedef struct {
    FILE *f;
    int panel;                    /* panels drawn so far */
    double px, py, pw, ph;        /* the current panel's plot area (pixels) */
    double x0, x1, y0, y1;        /* its data range (log10 on a log axis) */
    int xlog, ylog;
    int xint, yint;               /* integer ticks */
    int xnoticks, ynoticks;       /* no ticks */
    int legrow;                   /* 1: the legend's entries side by side, in rows */
    int legbottom;                /* 1: the legend in the bottom right corner */
    int nleg;                     /* legend entries of the current panel */
    const char *leg[CLI_SVG_LEGEND_MAX];
    int legcolor[CLI_SVG_LEGEND_MAX], legkind[CLI_SVG_LEGEND_MAX];
} cli_svg;
#define CLI_SVG_AXIS_EMPTY(log, label) {HUGE_VAL, -HUGE_VAL, log, label, 0, 0}
/* After cli_svg_panel (which resets both to 0, the top right corner and
 * one entry a line), s->legrow = 1 lays the panel's legend out in rows
 * and s->legbottom = 1 puts it in the bottom right corner. */
/* The document of width x height pixels with a title (may be NULL). */
void cli_svg_begin(cli_svg *s, FILE *f, double width, double height, const char *title);
/* The legend of the last panel, its group's and the closing tag. */
void cli_svg_end(cli_svg *s);
/* Widen ax's range to the finite values v[0], v[stride], ... (n of them;
 * on a log axis the positive ones). */
void cli_svg_range(cli_svg_axis *ax, const double *v, long n, long stride);
/* A panel at (left, top), width x height pixels (the axes inside it): the
 * frame, ticks, tick labels, axis labels and the title (may be NULL); an
 * empty range becomes [0, 1] ([1, 10] on a log axis), a single value is
 * widened. Draws the previous panel's legend first. */
void cli_svg_panel(cli_svg *s, double left, double top, double width, double height,
                   const cli_svg_axis *x, const cli_svg_axis *y, const char *title);
/* A polyline through (x[i xs], y[i ys]), i < n (x NULL: x = i). label (may
 * be NULL) goes into the legend. Nothing is drawn for no valid point. */
void cli_svg_line(cli_svg *s, const double *x, long xs, const double *y, long ys, long n,
                  int color, const char *label);
/* Circles at the points. */
void cli_svg_points(cli_svg *s, const double *x, long xs, const double *y, long ys, long n,
                    int color, const char *label);
/* Vertical bars from lo[i] to hi[i] at x[i] (x NULL: i). */
void cli_svg_errbars(cli_svg *s, const double *x, const double *lo, const double *hi, long n,
                     int color);
/* A filled band between lo and hi along x (x NULL: i); one polygon per run
 * of valid points. */
void cli_svg_band(cli_svg *s, const double *x, long xs, const double *lo, const double *hi,
                  long bs, long n, int color, const char *label);
/* A dashed line across the panel at y (hline) or x (vline). */
void cli_svg_hline(cli_svg *s, double y, int color, const char *label);
void cli_svg_vline(cli_svg *s, double x, int color, const char *label);
/* XML-escaped text at (x, y) pixels; anchor "start", "middle" or "end". */
void cli_svg_text(cli_svg *s, double x, double y, const char *anchor, const char *text);
/* The plots of the commands (each opens, writes and commits path through
 * cli_out; returns an exit code). */
int cli_svg_stability(const char *path, const char *file, const char *kind, int ntau, const double *tau,
                      const double *dev, const double *lo, const double *hi,
                      const double *fit, const int *fit_sup);
/* The residuals (one number a line, epoch-major rows x y z) read back
 * from res, an output being written (its temporary, or a temporary file of
 * the driver's own: f set, path NULL; nothing drawn for standard output, a
 * device or f NULL), and the N eigenvalues with lambda_test and
 * lambda_small. */
int cli_svg_eqerr(const char *path, const cli_out *res, int N, const double *lambda,
                  double lambda_test, double lambda_small);
/* The rejection rate of each component over the flights that tested it
 * (tested[N], rejected[N]) with its 99 % interval (igea_sim_interval), and
 * the level alpha; a component never tested is not drawn. */
int cli_svg_montecarlo(const char *path, int flights, int N, const int *tested,
                       const int *rejected, double alpha);
/* redund fuse: the fused output of nwin windows of step seconds with its
 * +- sigma band, and the niv exclusion intervals (sensor[k] from t0[k] to
 * t1[k] s, igea_redund_monitor_intervals) of the nc sensors. */
int cli_svg_fuse(const char *path, int nwin, double step, const double *fused,
                 const double *fsig, int nc, int niv, const int *sensor, const double *t0,
                 const double *t1);
/* rls: the estimates and their honest sd, epoch by epoch (rows of 2 m:
 * x then sd, appended by cli_svg_rls_add after each update; free(v)), and
 * the picture of the first CLI_SVG_RLS_PANELS coefficients, each with its
 * 3 sigma band (none at epochs where igea_rls_get_sd has no honest P). */
#define CLI_SVG_RLS_PANELS 8
typedef struct {
    double *v;
    long n, cap;
} cli_svg_rows;
int cli_svg_rls_add(cli_svg_rows *r, const igea_rls *h, int m);
int cli_svg_rls(const char *path, const cli_svg_rows *r, int m);
/* nav: the position, velocity and attitude errors (rows of IGEA_INSERR_N
 * values, x[k IGEA_INSERR_N + i]) at the n epochs t (t NULL: k dt), one
 * panel each, north east down (li 0) or launch-inertial x y z (li 1), and
 * with P (n blocks of IGEA_INSERR_N^2, or NULL) the +-1 sigma band of each;
 * what (may be NULL) goes into the first panel's title. At most
 * CLI_SVG_NAV_POINTS epochs are drawn (every k-th and the last). */
#define CLI_SVG_NAV_POINTS 2000
int cli_svg_nav(const char *path, const char *what, int li, int n, const double *t, double dt,
                const double *x, const double *P);
/* impact: the impact plane (crossrange right, downrange up) with the 1 and
 * 3 sigma ellipses of cov (2 x 2, downrange first) and the circle of
 * radius holding prob, and the n terms' shares (share[n], split into the
 * downrange and crossrange parts of miss, rows of 2) as bars, largest
 * first, the first CLI_SVG_IMPACT_BARS and the rest summed; names NULL:
 * term_0, ... */
#define CLI_SVG_IMPACT_BARS 15
int cli_svg_impact(const char *path, int n, char *const *names, const double *miss,
                   const double *share, const double *cov, double prob, double radius);

/* ---- the burnout from a trajectory (burnout.c): igea eqerr and impact --- */
/* --burnout-time T with --traj FILE, the launch point --lat --lon
 * [--height] --azimuth (degrees, m; as igea envfun's), --system and the
 * platform gyro --axes: igea_impact_burnout. */
typedef struct {
    const char *traj, *axes;
    double time, lat, lon, height, azimuth;
    int system, given_time, given_lat, given_lon, given_az, given_height, given_system;
} cli_burnout_args;
#define CLI_BURNOUT_OPTIONS(b, what)                                                           \
    {"--burnout-time", CLI_OPT_NUM, &(b).time, NULL, "T", "the burnout at T s of the trajectory --traj flown\n" \
     "from the launch point by the nav core, and\n" what, &(b).given_time},                   \
    {"--traj", CLI_OPT_STR, &(b).traj, NULL, "FILE", "the trajectory (t f3 w3 q4 rows, as igea envfun\n"      \
     "reads it; t_0 the lift-off)", NULL},                                                     \
    {"--lat", CLI_OPT_NUM, &(b).lat, NULL, "DEG", "the launch point: latitude", &(b).given_lat}, \
    {"--lon", CLI_OPT_NUM, &(b).lon, NULL, "DEG", "its longitude", &(b).given_lon},          \
    {"--height", CLI_OPT_NUM, &(b).height, "0", "M", "its ellipsoidal height", &(b).given_height}, \
    {"--azimuth", CLI_OPT_NUM, &(b).azimuth, NULL, "DEG", "the firing azimuth, from north toward east", &(b).given_az}, \
    {"--system", CLI_OPT_CHOICE, &(b).system, "strapdown", CLI_CHOICES(IGEA_CHOICE_ENVFUN_SYSTEM), "the inertial system of the terms", &(b).given_system}, \
    {"--axes", CLI_OPT_STR, &(b).axes, NULL, "I,I,I,S,S,S", "platform gyro input and spin axes (0..2; default\n0,1,2,1,2,0)", NULL}
/* CLI_OK when --burnout-time was given with --traj, --lat, --lon and
 * --azimuth (else a message naming the missing one and CLI_USAGE), or
 * when none of these options (nor --height, --system, --axes) was. */
int cli_burnout_check(const char *cmd, const cli_burnout_args *b);
/* The burnout state (6) and E (6 x n, column-major) of the n terms
 * codes[] at spec (may be NULL) from the trajectory file: CLI_OK or a
 * message (the time outside the trajectory, a bad file) and its code. */
int cli_burnout_compute(const cli_burnout_args *b, int n, const int *codes, const double *spec,
                        double *state, double *E);

#endif
