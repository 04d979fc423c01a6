/* Invalid-argument suite, generated from the public headers: every exported
 * function is called with its valid baseline and then with each mutation
 * of gen_invalid.py (a pointer NULL, a size 0 or negative, a leading
 * dimension one too small, an enumeration out of range, NaN or Inf in a
 * double). An invalid call must return a status < 0, leave every output
 * and handle as it was, print nothing, and not crash; an allowed one (a
 * NULL the header permits, a documented zero size) must succeed. Each call
 * runs in its own child process, so a crash is reported as that call's
 * failure and the suite goes on.
 *     test_invalid KNOWN_DEFECTS_FILE */
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "audit_gen.c"

/* Run one call (mutation m, or the baseline when m is NULL) and describe
 * what went wrong in msg (empty when nothing did). */
static void run_one(const audit_fn *f, const audit_mut *m, char *msg, size_t cap)
{
    int pfd[2];
    msg[0] = 0;
    fflush(stdout);
    fflush(stderr);
    if (pipe(pfd) != 0) {
        snprintf(msg, cap, "pipe failed");
        return;
    }
    FILE *cap_f = tmpfile();
    if (!cap_f) {
        snprintf(msg, cap, "tmpfile failed");
        return;
    }
    pid_t pid = fork();
    if (pid < 0) {
        snprintf(msg, cap, "fork failed");
        return;
    }
    if (pid == 0) {
        char out[600] = "";
        size_t len = 0;
        close(pfd[0]);
        alarm(20);
        audit_call c;
        f->setup(&c);
        if (m)
            audit_apply(&c, m);
        audit_snapshot(&c);
        int so = dup(1), se = dup(2);
        if (so < 0 || se < 0)
            _exit(3);
        dup2(fileno(cap_f), 1);
        dup2(fileno(cap_f), 2);
        int st = f->call(&c);
        fflush(stdout);
        fflush(stderr);
        dup2(so, 1);
        dup2(se, 2);
        long printed = lseek(fileno(cap_f), 0, SEEK_END);
        int expect = m ? m->expect : f->base_any ? EX_ANY : EX_OK;
        if (expect == EX_FAIL && st >= 0)
            len += (size_t)snprintf(out + len, sizeof out - len, "status %d (want < 0); ", st);
        if (expect == EX_OK && st < 0)
            len += (size_t)snprintf(out + len, sizeof out - len, "status %d (%s) (want >= 0); ",
                                    st, igea_strerror(st));
        if (st >= 0) {
            int a = audit_nan_output(&c, f->nan_out);
            if (a >= 0)
                len += (size_t)snprintf(out + len, sizeof out - len,
                                        "status %d but %s holds NaN; ", st, f->argnames[a]);
        }
        if (st < 0) {
            int a = audit_changed_after(f, &c, st);
            if (a >= 0)
                len += (size_t)snprintf(out + len, sizeof out - len,
                                        "failed with status %d but changed %s; ", st,
                                        f->argnames[a]);
        }
        if (printed > 0) {
            char text[80] = "";
            lseek(fileno(cap_f), 0, SEEK_SET);
            size_t got = fread(text, 1, sizeof text - 1, cap_f);
            text[got] = 0;
            for (size_t i = 0; i < got; i++)
                if (text[i] == '\n' || text[i] == '\r' || (unsigned char)text[i] < 32)
                    text[i] = ' ';
            len += (size_t)snprintf(out + len, sizeof out - len, "printed %ld bytes \"%s\"; ",
                                    printed, text);
        }
        if (len >= 2 && len < sizeof out)
            out[len - 2] = 0;
        if (write(pfd[1], out, strlen(out)) < 0)
            _exit(3);
        close(pfd[1]);
        audit_teardown(&c);
        _exit(0);
    }
    close(pfd[1]);
    size_t got = 0;
    ssize_t r;
    while (got + 1 < cap && (r = read(pfd[0], msg + got, cap - 1 - got)) > 0)
        got += (size_t)r;
    msg[got] = 0;
    close(pfd[0]);
    int ws = 0;
    waitpid(pid, &ws, 0);
    if (WIFSIGNALED(ws))
        snprintf(msg + strlen(msg), cap - strlen(msg), "%scrashed (signal %d%s)",
                 msg[0] ? "; " : "", WTERMSIG(ws), WTERMSIG(ws) == SIGALRM ? ", hung" : "");
    else if (!WIFEXITED(ws) || WEXITSTATUS(ws) != 0)
        snprintf(msg + strlen(msg), cap - strlen(msg), "%sthe call did not return (exit %d)",
                 msg[0] ? "; " : "", WIFEXITED(ws) ? WEXITSTATUS(ws) : -1);
    if (!WIFEXITED(ws) || WEXITSTATUS(ws) != 0) {
        /* what the call printed before it died: a sanitizer's summary */
        char line[300], last[300] = "";
        rewind(cap_f);
        while (fgets(line, sizeof line, cap_f))
            if (strstr(line, "SUMMARY:") || strstr(line, "ERROR:") || !last[0]) {
                line[strcspn(line, "\n")] = 0;
                snprintf(last, sizeof last, "%s", line);
                if (strstr(line, "SUMMARY:"))
                    break;
            }
        if (last[0])
            snprintf(msg + strlen(msg), cap - strlen(msg), ": %s", last);
    }
    fclose(cap_f);
}

static audit_known known[512];
static int nknown;
static int passed, failed, nknown_hit;

static void report(const char *id, const char *msg)
{
    if (!msg[0]) {
        passed++;
        return;
    }
    audit_fail(known, nknown, id, msg, &nknown_hit, &failed);
}

int main(int argc, char **argv)
{
    long ninvalid = 0, nallowed = 0;
    char msg[1024], id[200];
    setvbuf(stdout, NULL, _IOLBF, 0);
    if (argc > 1)
        nknown = audit_read_known(argv[1], known, 512);
    for (int fi = 0; fi < audit_nfns; fi++) {
        const audit_fn *f = &audit_fns[fi];
        snprintf(id, sizeof id, "invalid %s baseline", f->name);
        run_one(f, NULL, msg, sizeof msg);
        report(id, msg);
        if (msg[0])
            continue; /* nothing to mutate from */
        for (int j = 0; j < f->nmut; j++) {
            const audit_mut *m = &f->muts[j];
            if (!m->label)
                continue;
            snprintf(id, sizeof id, "invalid %s %s", f->name, m->label);
            run_one(f, m, msg, sizeof msg);
            report(id, msg);
            if (m->expect == EX_FAIL)
                ninvalid++;
            else
                nallowed++;
        }
    }
    audit_unseen(known, nknown, "invalid ");
    printf("test_invalid: %d baseline calls of the exported functions\n", audit_nfns);
    printf("invalid-argument calls: %ld (and %ld allowed variants: documented NULLs, zero sizes, "
           "infinities)\n", ninvalid, nallowed);
    if (nknown_hit)
        printf("%d checks failed as listed in tests/audit/known_defects.txt\n", nknown_hit);
    printf("%d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}
