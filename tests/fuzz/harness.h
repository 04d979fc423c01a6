/* tests/fuzz/harness.h - shared pieces of the libFuzzer targets.
 *
 * A command target's input is text: the first section holds the command
 * line (whitespace-separated tokens after the command name), then each
 * section "%% NAME\n" followed by bytes is a file NAME written to a private
 * directory, which is the working directory while the command runs:
 *
 *     --S S.txt --dw dw.txt --sigma 0.01 --json --out r.json
 *     %% S.txt
 *     1 2
 *     3 4
 *     %% dw.txt
 *     0.5
 *     0.25
 *
 * A file named "stdin" is also what the command reads on standard input
 * (a pipe), so "-" in the command line reads it.
 * After every run the harness checks that the exit status is a documented
 * one, that a failed run left no new file (nor a *.tmp.* file on any run),
 * did not change an input file, wrote nothing to standard output (unless
 * the command streams its report) and said why on standard error; and that a run which printed its result exits 74
 * when standard output is /dev/full. A violation prints the reason and
 * aborts, so libFuzzer saves the input as a crash. */
#ifndef IGEA_FUZZ_HARNESS_H
#define IGEA_FUZZ_HARNESS_H

#include <stddef.h>
#include <stdint.h>

#define FZ_MAX_ARGS 48
#define FZ_MAX_FILES 6
#define FZ_NAME_MAX 40

typedef struct {
    int argc;
    char *argv[FZ_MAX_ARGS + 1];
    int nfiles;
    char name[FZ_MAX_FILES][FZ_NAME_MAX + 1];
    const uint8_t *data[FZ_MAX_FILES];
    size_t len[FZ_MAX_FILES];
} fz_run;

/* Flags of fz_command. */
#define FZ_VERDICT 1 /* exit 1 (an accuracy test rejected) is documented */
#define FZ_STREAMS 2 /* prints as it reads: a failure may follow printed lines */

/* Once per process: private directory, stdin from /dev/null, stdout to a
 * capture file, a copy of the original stderr for the harness's reports. */
void fz_init(void);
/* Print "igea-fuzz: <reason>" with the command line and abort. */
void fz_fail(const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 1, 2), noreturn))
#endif
    ;
/* The private directory (absolute path), emptied by fz_clean. */
const char *fz_dir(void);
void fz_clean(void);
/* Write bytes to fz_dir()/name; 0 on success. */
int fz_write(const char *name, const void *p, size_t n);

/* Guards (per-input limits that keep a run short). The value of the last
 * occurrence of option opt as a number, or dflt when absent or not a
 * number. */
double fz_opt_num(const fz_run *r, const char *opt, double dflt);
int fz_has(const fz_run *r, const char *token);
/* The value of the last occurrence of option opt, or NULL. */
const char *fz_opt_str(const fz_run *r, const char *opt);
/* The largest |value| in the input files that read as matrices (0 if none). */
double fz_max_abs(const fz_run *r);
/* Values in the input file name read as a matrix ("-": the file named
 * stdin; 0 if it does not read). */
long fz_values(const fz_run *r, const char *name);

/* Parse data, write its files, run cmd with argv = {name, prefix...,
 * tokens...}, check the run as described above. guard returns nonzero to
 * skip an input (too slow). Returns 0 (libFuzzer's convention). */
int fz_command(const char *name, int (*cmd)(int, char **), const char *const *prefix,
               int flags, int (*guard)(const fz_run *), const uint8_t *data, size_t size);

/* Reader targets: data[0] seeds the block sizes, the rest is the file
 * fz_dir()/fname. Reads it whole (cli_read_matrix), streamed (cli_reader_next
 * in random blocks) and in two passes (cli_reader_rewind), then the same
 * bytes from a pipe on standard input ("-") the three ways: the exit codes,
 * shapes and bits must agree, a failure must leave the output untouched and
 * say why, and a success holds only finite values. */
int fz_reader(const char *fname, const uint8_t *data, size_t size);

/* A small deterministic generator for the readers' block sizes. */
static inline uint32_t fz_rand(uint32_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return *s;
}

#endif
