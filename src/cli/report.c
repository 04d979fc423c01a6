/* report.c - steps the commands share around their library call: a matrix
 * file read column-major, column-major results as row-major tables, JSON
 * matrices and name lists, and the usage message of a failed check. */
#include <stdlib.h>

#include "cli.h"

int cli_read_colmajor(const char *path, double **v, int *rows, int *cols)
{
    cli_matrix m = {0};
    int ec = cli_read_matrix(path, &m);
    if (ec)
        return ec;
    if (m.rows > 2147483647L) {
        cli_error("%s: too many rows", path);
        cli_matrix_free(&m);
        return CLI_DATAERR;
    }
    *rows = (int)m.rows, *cols = m.cols;
    if (!(*v = malloc(sizeof(double) * (size_t)m.rows * m.cols))) {
        cli_matrix_free(&m);
        return cli_oom(path);
    }
    for (long i = 0; i < m.rows; i++)
        for (int c = 0; c < m.cols; c++)
            (*v)[i + (size_t)c * m.rows] = m.v[(size_t)i * m.cols + c];
    cli_matrix_free(&m);
    return CLI_OK;
}

double *cli_rowmajor(const double *v, long rows, int cols)
{
    double *r = malloc(sizeof(double) * (size_t)rows * cols + 1);
    for (long i = 0; r && i < rows; i++)
        for (int c = 0; c < cols; c++)
            r[(size_t)i * cols + c] = v[i + (size_t)c * rows];
    return r;
}

void cli_jmatrix(cli_json *j, const char *key, const double *v, const int *iv, int rows,
                 int cols, long rs, long cs)
{
    cli_json_open(j, key, '[');
    for (int i = 0; i < rows; i++) {
        cli_json_open(j, NULL, '[');
        for (int k = 0; k < cols; k++)
            if (v)
                cli_jnum(j, NULL, v[i * rs + k * cs]);
            else
                cli_jint(j, NULL, iv[i * rs + k * cs]);
        cli_json_close(j);
    }
    cli_json_close(j);
}

void cli_jrows(cli_json *j, const char *key, const double *v, int rows, int cols)
{
    cli_json_open(j, key, '[');
    for (int i = 0; i < rows; i++)
        cli_jnums(j, NULL, v + (size_t)i * cols, cols);
    cli_json_close(j);
}

void cli_jstrs(cli_json *j, const char *key, const char *const *s, int n)
{
    cli_json_open(j, key, '[');
    for (int i = 0; i < n; i++)
        cli_jstr(j, NULL, s[i]);
    cli_json_close(j);
}

void cli_jterms(cli_json *j, const char *key, const int *codes, int n)
{
    cli_json_open(j, key, '[');
    for (int k = 0; k < n; k++)
        cli_jstr(j, NULL, igea_envfun_term_name(codes[k]));
    cli_json_close(j);
}

int cli_usage(const char *msg)
{
    if (!msg)
        return CLI_OK;
    cli_error("%s", msg);
    return CLI_USAGE;
}
