/* progress.c - progress and ETA of the long commands on stderr (the
 * driver's, never the library's): a line updated in place when stderr is a
 * terminal, one line per 10 % with --progress, nothing with --quiet. The
 * commands split their work into the chunks the library already supports
 * (flights by first index, averaging times one by one); the reporter only
 * counts them, so the results do not depend on it. */
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"

int cli_progress_opt, cli_quiet_opt;

static double now(void)
{
    struct timespec t;
    if (clock_gettime(CLOCK_MONOTONIC, &t) != 0)
        return 0;
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* "4.2 s", "3 min 07 s", "2 h 05 min" into buf. */
static const char *duration(double s, char *buf, size_t size)
{
    if (!(s >= 0) || s > 1e9)
        snprintf(buf, size, "?");
    else if (s < 60)
        snprintf(buf, size, "%.1f s", s);
    else if (s < 3600)
        snprintf(buf, size, "%d min %02d s", (int)(s / 60), (int)s % 60);
    else
        snprintf(buf, size, "%d h %02d min", (int)(s / 3600), (int)(s / 60) % 60);
    return buf;
}

int cli_progress_start(cli_progress *p, const char *cmd, const char *unit, double total)
{
    memset(p, 0, sizeof *p);
    p->cmd = cmd, p->unit = unit, p->total = total;
    if (cli_progress_opt && cli_quiet_opt) {
        cli_error("%s: --progress and --quiet exclude each other", cmd);
        return CLI_USAGE;
    }
    p->mode = cli_quiet_opt ? 0 : cli_progress_opt ? 2 : isatty(2) ? 1 : 0;
    if (!(total > 0) && total != CLI_PROGRESS_UNKNOWN)
        p->mode = 0;
    p->t0 = now();
    return CLI_OK;
}

void cli_progress_update(cli_progress *p, double done)
{
    if (!p->mode || !(done >= 0))
        return;
    int pct = done >= p->total ? 100 : (int)(100 * done / p->total);
    if (p->mode == 2 && pct / 10 <= p->decile)
        return; /* batch: only when a new 10 % is passed */
    p->decile = pct / 10;
    char el[32], eta[32];
    double t = now() - p->t0;
    duration(t, el, sizeof el);
    if (done >= p->total)
        snprintf(eta, sizeof eta, "done");
    else if (done > 0)
        duration(t * (p->total - done) / done, eta + 4, sizeof eta - 4), memcpy(eta, "ETA ", 4);
    else
        snprintf(eta, sizeof eta, "ETA ?");
    fprintf(stderr, "%sigea %s: %3d %% (%.0f of %.0f %s), %s elapsed, %s%s",
            p->mode == 1 ? "\r" : "", p->cmd, pct, done, p->total, p->unit, el, eta,
            p->mode == 1 ? "    " : "\n");
    p->shown = 1;
    fflush(stderr);
}

void cli_progress_count(cli_progress *p, double done)
{
    if (!p->mode || !(done > 0))
        return;
    if (p->mode == 2 && done < 2 * p->last)
        return; /* batch: when the count has doubled */
    p->last = done;
    char el[32];
    fprintf(stderr, "%sigea %s: %.0f %s, %s elapsed%s", p->mode == 1 ? "\r" : "", p->cmd,
            done, p->unit, duration(now() - p->t0, el, sizeof el), p->mode == 1 ? "    " : "\n");
    p->shown = 1;
    fflush(stderr);
}

void cli_progress_end(cli_progress *p)
{
    if (p->mode == 1 && p->shown)
        fputc('\n', stderr);
    p->mode = 0;
}
