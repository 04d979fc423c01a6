/* opt.c - the driver's one option parser: every command describes its
 * options in a table (name, kind, default, help, target); the same table
 * sets the defaults, parses the command line (--name value or
 * --name=value; an option given twice is refused) and prints the option
 * list of the command's --help. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

int cli_pick(const char *opt, const char *value, const char *words, int *index)
{
    size_t len = strlen(value);
    int k = 0;
    for (const char *p = words;; k++) {
        const char *bar = strchr(p, '|');
        size_t n = bar ? (size_t)(bar - p) : strlen(p);
        if (n == len && !strncmp(p, value, n)) {
            *index = k;
            return CLI_OK;
        }
        if (!bar)
            break;
        p = bar + 1;
    }
    cli_error("option %s: '%s' is not one of %s", opt, value, words);
    return CLI_USAGE;
}

const char *cli_choice_names(int kind, char *buf, size_t size)
{
    int codes[CLI_CHOICE_MAX], n = igea_choice_codes(kind, codes, CLI_CHOICE_MAX);
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < n && i < CLI_CHOICE_MAX; i++) {
        int w = snprintf(buf + used, size - used, "%s%s", i ? "|" : "",
                         igea_choice_name(kind, codes[i]));
        if (w < 0 || (size_t)w >= size - used)
            break;
        used += (size_t)w;
    }
    return buf;
}

int cli_choice(const char *opt, int kind, const char *value, int *code)
{
    char names[CLI_CHOICE_TEXT];
    if (igea_choice_code(kind, value, code) == 0)
        return CLI_OK;
    cli_error("option %s: '%s' is not one of %s", opt, value,
              cli_choice_names(kind, names, sizeof names));
    return CLI_USAGE;
}

/* The library enumeration of a CHOICE option (CLI_CHOICES(kind)), or 0 for
 * a list of words. */
static int choice_kind(const cli_opt *o)
{
    return o->arg[0] == CLI_CHOICE_MARK[0] ? atoi(o->arg + 1) : 0;
}

/* Store the text v into o's target. */
static int set_value(const cli_opt *o, const char *v)
{
    switch (o->kind) {
    case CLI_OPT_INT:
        return cli_parse_int(o->name, v, (int *)o->target);
    case CLI_OPT_NUM:
        return cli_parse_double(o->name, v, (double *)o->target);
    case CLI_OPT_STR:
        *(const char **)o->target = v;
        return CLI_OK;
    case CLI_OPT_CHOICE:
        if (choice_kind(o))
            return cli_choice(o->name, choice_kind(o), v, (int *)o->target);
        return cli_pick(o->name, v, o->arg, (int *)o->target);
    default:
        return CLI_OK;
    }
}

static int takes_value(const cli_opt *o)
{
    return o->kind == CLI_OPT_INT || o->kind == CLI_OPT_NUM || o->kind == CLI_OPT_STR ||
           o->kind == CLI_OPT_CHOICE;
}

/* "  --name ARG" padded to the help column, then the help text (its '\n'
 * continue on indented lines) and the default. */
#define HELP_COL 22
static void print_option(FILE *f, const cli_opt *o)
{
    char head[CLI_CHOICE_TEXT + 96], names[CLI_CHOICE_TEXT];
    const char *arg = o->arg;
    if (o->kind == CLI_OPT_CHOICE && choice_kind(o))
        arg = cli_choice_names(choice_kind(o), names, sizeof names);
    if (o->kind == CLI_OPT_FLAG || o->kind == CLI_OPT_CLEAR || o->kind == CLI_OPT_DSET ||
        o->kind == CLI_OPT_DCLEAR)
        arg = NULL;
    snprintf(head, sizeof head, "  %s%s%s", o->name, arg ? " " : "", arg ? arg : "");
    int w = (int)strlen(head);
    if (w >= HELP_COL) {
        fprintf(f, "%s\n%*s", head, HELP_COL, "");
    } else {
        fprintf(f, "%-*s", HELP_COL, head);
    }
    for (const char *p = o->help; *p; p++) {
        fputc(*p, f);
        if (*p == '\n')
            fprintf(f, "%*s", HELP_COL, "");
    }
    if (o->def && !strcmp(o->def, CLI_DEF_LIB)) {
        if (o->kind == CLI_OPT_NUM)
            fprintf(f, " (default %g)", *(const double *)o->target);
        else if (o->kind == CLI_OPT_INT)
            fprintf(f, " (default %d)", *(const int *)o->target);
    } else if (o->def) {
        fprintf(f, " (default %s)", o->def);
    }
    fputc('\n', f);
}

void cli_help(FILE *f, const cli_command *c)
{
    fputs(c->intro, f);
    for (const cli_opt *o = c->opts; o->kind != CLI_OPT_END; o++) {
        if (o->kind == CLI_OPT_HEAD)
            fprintf(f, "%s\n", o->help);
        else
            print_option(f, o);
    }
    fputs(c->outro, f);
}

/* The option of c's table named by a ("--name", or "--name=value": then
 * *value points after the '='), or NULL. */
static const cli_opt *find_option(const cli_command *c, const char *a, const char **value)
{
    const char *eq = a[0] == '-' && a[1] == '-' ? strchr(a, '=') : NULL;
    size_t len = eq ? (size_t)(eq - a) : strlen(a);
    *value = eq ? eq + 1 : NULL;
    for (const cli_opt *o = c->opts; o->kind != CLI_OPT_END; o++)
        if (o->name && strlen(o->name) == len && !strncmp(o->name, a, len))
            return o;
    return NULL;
}

/* Refuse an option given twice (its first value would be lost silently). */
#define CLI_OPTS_MAX 256
static int seen_once(const cli_command *c, const cli_opt *o, unsigned char *seen)
{
    long k = o - c->opts;
    if (k >= CLI_OPTS_MAX) {
        cli_error("%s: option table too long", c->name);
        return CLI_SOFTWARE;
    }
    if (seen[k]) {
        cli_error("%s: option %s given twice", c->name, o->name);
        return CLI_USAGE;
    }
    seen[k] = 1;
    return CLI_OK;
}

int cli_parse(const cli_command *c, int argc, char **argv)
{
    const cli_opt *o;
    unsigned char seen[CLI_OPTS_MAX] = {0};
    if (cli_one_stdin(argc, argv))
        return CLI_USAGE;
    for (o = c->opts; o->kind != CLI_OPT_END; o++) {
        if (o->given)
            *o->given = 0;
        if (o->kind == CLI_OPT_FLAG)
            *(int *)o->target = 0;
        else if (o->kind == CLI_OPT_CLEAR)
            *(int *)o->target = 1;
        else if (takes_value(o) && o->def && strcmp(o->def, CLI_DEF_LIB) &&
                 set_value(o, o->def) != CLI_OK)
            return CLI_SOFTWARE; /* a default that does not parse: a table error */
        else if (o->kind == CLI_OPT_STR && !o->def)
            *(const char **)o->target = NULL;
    }
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            cli_help(stdout, c);
            return CLI_HELP;
        }
        const char *v;
        if (!(o = find_option(c, a, &v))) {
            if (a[0] == '-' && a[1] != '\0')
                cli_error("%s: unknown option '%s' (see igea %s --help)", c->name, a, c->name);
            else
                cli_error("%s: unexpected argument '%s': inputs are options (see igea %s --help)",
                          c->name, a, c->name);
            return CLI_USAGE;
        }
        int ec = seen_once(c, o, seen);
        if (ec)
            return ec;
        if (o->given)
            *o->given = 1;
        if (!takes_value(o) && v) {
            cli_error("%s: option %s takes no value ('%s')", c->name, o->name, a);
            return CLI_USAGE;
        }
        if (o->kind == CLI_OPT_FLAG || o->kind == CLI_OPT_CLEAR) {
            *(int *)o->target = o->kind == CLI_OPT_FLAG;
            continue;
        }
        if (o->kind == CLI_OPT_DSET || o->kind == CLI_OPT_DCLEAR) {
            *(double *)o->target = o->kind == CLI_OPT_DSET;
            continue;
        }
        if (!v && !(v = cli_optarg(argc, argv, &i)))
            return CLI_USAGE;
        ec = set_value(o, v);
        if (ec)
            return ec;
    }
    return CLI_OK;
}

int cli_check_opts(const char *cmd, int module, int status)
{
    if (status == 0)
        return CLI_OK;
    char name[64];
    snprintf(name, sizeof name, "%s", status > 0 ? igea_opt_name(module, status - 1) : "");
    for (char *p = name; *p; p++)
        if (*p == '_')
            *p = '-';
    cli_error("%s: --%s is out of range (see igea %s --help)", cmd, name, cmd);
    return CLI_USAGE;
}

int cli_split_list(const char *list, char ***items, int *n)
{
    size_t len = strlen(list);
    int k = 1;
    for (const char *p = list; *p; p++)
        k += *p == ',';
    /* the pointers, then a copy of the text cut at the commas */
    char **v = malloc(sizeof(char *) * (size_t)k + len + 1);
    if (!v)
        return cli_oom("a list");
    char *text = (char *)(v + k);
    memcpy(text, list, len + 1);
    k = 0;
    for (char *p = text;; p++) {
        char *c = strchr(p, ',');
        v[k++] = p;
        if (!c)
            break;
        *c = '\0';
        p = c;
    }
    for (int i = 0; i < k; i++)
        if (!*v[i]) {
            cli_error("list '%s': an empty item", list);
            free(v);
            return CLI_USAGE;
        }
    *items = v;
    *n = k;
    return CLI_OK;
}

/* OpenBLAS's thread count, where the program is linked with OpenBLAS
 * (weak: another BLAS has no such functions and this does nothing). */
#ifdef __GNUC__
extern void openblas_set_num_threads(int) __attribute__((weak));
extern int openblas_get_num_threads(void) __attribute__((weak));
#else
static void (*openblas_set_num_threads)(int) = NULL;
static int (*openblas_get_num_threads)(void) = NULL;
#endif

int cli_blas_threads(int n)
{
    if (!openblas_set_num_threads || !openblas_get_num_threads || n < 1)
        return 0;
    int old = openblas_get_num_threads();
    openblas_set_num_threads(n);
    return old;
}
