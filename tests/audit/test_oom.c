/* Out-of-memory loop over every exported function (SQLite's): with the
 * baseline call of the generated tables, fail the 1st, 2nd, ... allocation
 * made inside the call until the call succeeds. Every failure must return
 * IGEA_ENOMEM, leave the outputs and handles as they were and print
 * nothing; the final success must equal the unconstrained call bit for
 * bit. malloc is tests/oom.h's hook; calloc, realloc and pthread_create
 * are hooked here on the same counter. Each function runs in its own child process, so a
 * crash is reported as that function's failure.
 *     test_oom KNOWN_DEFECTS_FILE */
#define _GNU_SOURCE 1 /* RTLD_NEXT */
#include <dlfcn.h>
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "audit_gen.c"
#include "oom.h"

#ifndef OOM_DISABLED
extern void *__libc_calloc(size_t, size_t);
extern void *__libc_realloc(void *, size_t);
void *calloc(size_t n, size_t size)
{
    if (oom_fail_at >= 0 && oom_calls++ == oom_fail_at)
        return NULL;
    return __libc_calloc(n, size);
}
void *realloc(void *p, size_t n)
{
    if (oom_fail_at >= 0 && oom_calls++ == oom_fail_at)
        return NULL;
    return __libc_realloc(p, n);
}

/* A thread that cannot be created is a resource failure like an
 * allocation: it fails on the same counter (EAGAIN). */
typedef int (*pthread_create_fn)(pthread_t *, const pthread_attr_t *, void *(*)(void *), void *);
int pthread_create(pthread_t *t, const pthread_attr_t *attr, void *(*fn)(void *), void *arg)
{
    static pthread_create_fn real;
    if (oom_fail_at >= 0 && oom_calls++ == oom_fail_at)
        return EAGAIN;
    if (!real) {
        void *p = dlsym(RTLD_NEXT, "pthread_create");
        if (!p)
            return EAGAIN;
        memcpy(&real, &p, sizeof real);
    }
    return real(t, attr, fn, arg);
}

enum { K_MAX = 20000 };

/* One call with the k-th allocation failed (k < 0: none); *printed: bytes
 * written to stdout or stderr during the call. */
static FILE *cap;

/* The start of what the last call printed, on one line. */
static void audit_captured(char *text, size_t n)
{
    size_t got;
    lseek(fileno(cap), 0, SEEK_SET);
    got = (size_t)read(fileno(cap), text, n - 1);
    if (got >= n)
        got = 0;
    text[got] = 0;
    for (size_t i = 0; i < got; i++)
        if ((unsigned char)text[i] < 32)
            text[i] = ' ';
}

static int call_armed(const audit_fn *f, audit_call *c, long k, long *nalloc, long *printed)
{
    if (!cap && !(cap = tmpfile()))
        _exit(3);
    if (ftruncate(fileno(cap), 0) != 0)
        _exit(3);
    lseek(fileno(cap), 0, SEEK_SET);
    fflush(stdout);
    fflush(stderr);
    int so = dup(1), se = dup(2);
    dup2(fileno(cap), 1);
    dup2(fileno(cap), 2);
    oom_calls = 0;
    oom_fail_at = k >= 0 ? k : LONG_MAX;
    int st = f->call(c);
    oom_fail_at = -1;
    *nalloc = oom_calls;
    fflush(stdout);
    fflush(stderr);
    dup2(so, 1);
    dup2(se, 2);
    close(so);
    close(se);
    *printed = lseek(fileno(cap), 0, SEEK_END);
    return st;
}

/* The child's work: "ALLOC n LOOPS k" on success, or what went wrong. */
static void oom_function(const audit_fn *f, char *out, size_t cap)
{
    audit_call c;
    long nalloc, printed;
    size_t len0, len;
    f->setup(&c);
    int st0 = call_armed(f, &c, -1, &nalloc, &printed);
    unsigned char *ref = audit_results(&c, &len0);
    audit_teardown(&c);
    if (st0 < 0 && f->base_any) {
        snprintf(out, cap, "ALLOC 0 LOOPS 0 ABSORBED 0"); /* extreme data refused */
        return;
    }
    if (st0 < 0) {
        snprintf(out, cap, "baseline failed with status %d", st0);
        return;
    }
    if (nalloc == 0) {
        snprintf(out, cap, "ALLOC 0 LOOPS 0 ABSORBED 0");
        return;
    }
    long absorbed = 0;
    for (long k = 0; k < K_MAX; k++) {
        long n;
        f->setup(&c);
        audit_snapshot(&c);
        int st = call_armed(f, &c, k, &n, &printed);
        if (printed > 0) {
            char text[80] = "";
            audit_captured(text, sizeof text);
            snprintf(out, cap, "allocation %ld failed: status %d and %ld bytes printed \"%s\"", k,
                     st, printed, text);
            audit_teardown(&c);
            return;
        }
        if (st >= 0) {
            unsigned char *res = audit_results(&c, &len);
            int same = len == len0 && memcmp(res, ref, len) == 0;
            free(res);
            audit_teardown(&c);
            if (!same) {
                snprintf(out, cap, "the success with allocation %ld failed differs from the "
                         "unconstrained call", k);
                return;
            }
            if (n > k) { /* the failure was absorbed (a fallback): go on */
                absorbed++;
                continue;
            }
            snprintf(out, cap, "ALLOC %ld LOOPS %ld ABSORBED %ld", nalloc, k, absorbed);
            free(ref);
            return;
        }
        int a = audit_changed_after(f, &c, st);
        audit_teardown(&c);
        if (st != IGEA_ENOMEM) {
            snprintf(out, cap, "allocation %ld failed: status %d (%s), want IGEA_ENOMEM", k, st,
                     igea_strerror(st));
            return;
        }
        if (a >= 0) {
            snprintf(out, cap, "allocation %ld failed: IGEA_ENOMEM but %s changed", k,
                     f->argnames[a]);
            return;
        }
    }
    snprintf(out, cap, "still failing after %d failed allocations", K_MAX);
}

int main(int argc, char **argv)
{
    static audit_known known[512];
    int nknown = argc > 1 ? audit_read_known(argv[1], known, 512) : 0;
    int passed = 0, failed = 0, nhit = 0, nalloc_fns = 0;
    long loops = 0;
    setvbuf(stdout, NULL, _IOLBF, 0);
    for (int fi = 0; fi < audit_nfns; fi++) {
        const audit_fn *f = &audit_fns[fi];
        char msg[600] = "", id[200];
        int pfd[2];
        if (pipe(pfd) != 0)
            return 2;
        pid_t pid = fork();
        if (pid == 0) {
            close(pfd[0]);
            alarm(60);
            oom_function(f, msg, sizeof msg);
            if (write(pfd[1], msg, strlen(msg)) < 0)
                _exit(3);
            _exit(0);
        }
        close(pfd[1]);
        size_t got = 0;
        ssize_t r;
        while (got + 1 < sizeof msg && (r = read(pfd[0], msg + got, sizeof msg - 1 - got)) > 0)
            got += (size_t)r;
        msg[got] = 0;
        close(pfd[0]);
        int ws = 0;
        waitpid(pid, &ws, 0);
        if (WIFSIGNALED(ws))
            snprintf(msg + strlen(msg), sizeof msg - strlen(msg), "%scrashed (signal %d%s)",
                     msg[0] ? "; " : "", WTERMSIG(ws), WTERMSIG(ws) == SIGALRM ? ", hung" : "");
        snprintf(id, sizeof id, "oom %s", f->name);
        long na, nl, nabs;
        if (sscanf(msg, "ALLOC %ld LOOPS %ld ABSORBED %ld", &na, &nl, &nabs) == 3 &&
            !WIFSIGNALED(ws)) {
            passed++;
            if (na > 0) {
                nalloc_fns++;
                loops += nl + 1;
                printf("ok: %s: %ld allocations; each failed in turn gave IGEA_ENOMEM with "
                       "outputs untouched", f->name, na);
                if (nabs)
                    printf(" (%ld absorbed by a fallback, with the same result)", nabs);
                printf("\n");
            }
            continue;
        }
        audit_fail(known, nknown, id, msg, &nhit, &failed);
    }
    audit_unseen(known, nknown, "oom ");
    printf("test_oom: %d baseline calls, %d allocate; %ld out-of-memory calls\n", audit_nfns,
           nalloc_fns, loops);
    if (nhit)
        printf("%d checks failed as listed in tests/audit/known_defects.txt\n", nhit);
    printf("%d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}
#else
int main(void)
{
    printf("test_oom: skipped under AddressSanitizer (it replaces malloc itself)\n");
    printf("0 passed, 0 failed\n");
    return 0;
}
#endif
