/* json.c - the driver's JSON writer: keys, separators and nesting tracked
 * by the writer, strings escaped, non-finite numbers written as null.
 * Members of the top-level object, and containers inside a top-level
 * member, start on their own lines; everything else is inline. */
#include <math.h>
#include <stdio.h>

#include "cli.h"

static void json_num(FILE *f, double x)
{
    if (isfinite(x))
        fprintf(f, "%.17g", x);
    else
        fputs("null", f);
}

static void json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c == '\n')
            fputs("\\n", f);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
    fputc('"', f);
}

void cli_json_begin(cli_json *j, FILE *f)
{
    j->f = f;
    j->depth = 1;
    j->count[1] = 0;
    j->lines[1] = 1;
    fputc('{', f);
}

/* The separator and key of the next member; container: the value opens one. */
static void member(cli_json *j, const char *key, int container)
{
    int d = j->depth;
    if (j->count[d]++)
        fputc(',', j->f);
    if (j->lines[d] || (d == 2 && container)) {
        j->lines[d] = 1;
        fprintf(j->f, "\n%*s", 2 * d, "");
    } else if (j->count[d] > 1) {
        fputc(' ', j->f);
    }
    if (key) {
        json_str(j->f, key);
        fputs(": ", j->f);
    }
}

void cli_json_open(cli_json *j, const char *key, char bracket)
{
    member(j, key, 1);
    fputc(bracket, j->f);
    if (j->depth + 1 < CLI_JSON_DEPTH) {
        j->depth++;
        j->count[j->depth] = 0;
        j->lines[j->depth] = 0;
        j->close[j->depth] = bracket == '{' ? '}' : ']';
    }
}

void cli_json_close(cli_json *j)
{
    int d = j->depth;
    if (d <= 1)
        return;
    if (j->lines[d])
        fprintf(j->f, "\n%*s", 2 * (d - 1), "");
    fputc(j->close[d], j->f);
    j->depth--;
}

void cli_json_end(cli_json *j)
{
    while (j->depth > 1)
        cli_json_close(j);
    fputs("\n}\n", j->f);
}

void cli_jnum(cli_json *j, const char *key, double x)
{
    member(j, key, 0);
    json_num(j->f, x);
}

void cli_jint(cli_json *j, const char *key, long x)
{
    member(j, key, 0);
    fprintf(j->f, "%ld", x);
}

void cli_jbool(cli_json *j, const char *key, int x)
{
    member(j, key, 0);
    fputs(x ? "true" : "false", j->f);
}

void cli_jstr(cli_json *j, const char *key, const char *s)
{
    member(j, key, 0);
    if (s)
        json_str(j->f, s);
    else
        fputs("null", j->f);
}

void cli_jnums(cli_json *j, const char *key, const double *x, long n)
{
    member(j, key, 0);
    fputc('[', j->f);
    for (long i = 0; i < n; i++) {
        if (i)
            fputs(", ", j->f);
        json_num(j->f, x[i]);
    }
    fputc(']', j->f);
}

void cli_jints(cli_json *j, const char *key, const int *x, long n)
{
    member(j, key, 0);
    fputc('[', j->f);
    for (long i = 0; i < n; i++)
        fprintf(j->f, "%s%d", i ? ", " : "", x[i]);
    fputc(']', j->f);
}

void cli_jbools(cli_json *j, const char *key, const int *x, long n)
{
    member(j, key, 0);
    fputc('[', j->f);
    for (long i = 0; i < n; i++)
        fprintf(j->f, "%s%s", i ? ", " : "", x[i] ? "true" : "false");
    fputc(']', j->f);
}

