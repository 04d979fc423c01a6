/* Thread safety: the baseline call of every exported function (the
 * generated tables), from 8 threads at once, many times, each thread in
 * its own order; every call's status and results (every writable buffer,
 * every handle's state) must be bitwise equal to a single-threaded run.
 * Run with OPENBLAS_NUM_THREADS=1, and under ThreadSanitizer by make tsan.
 *     test_threads KNOWN_DEFECTS_FILE [REPETITIONS] */
#include <pthread.h>

#include "audit_gen.c"

enum { NTHREADS = 8, MAX_FNS = 1024 };

static int reps = 20;
static int ref_status[MAX_FNS];
static unsigned char *ref_res[MAX_FNS];
static size_t ref_len[MAX_FNS];

typedef struct {
    int t;
    long calls;
    int bad[MAX_FNS];     /* calls of function fi that differed */
    int first_rep[MAX_FNS];
} job_t;

static void *worker(void *arg)
{
    job_t *j = arg;
    for (int r = 0; r < reps; r++)
        for (int i = 0; i < audit_nfns; i++) {
            /* each thread walks the functions from its own start, so
             * different modules run side by side */
            int fi = (i + 11 * j->t + r) % audit_nfns;
            const audit_fn *f = &audit_fns[fi];
            if (!f->threads)
                continue;
            audit_call c;
            size_t len;
            f->setup(&c);
            int st = f->call(&c);
            unsigned char *res = audit_results(&c, &len);
            audit_teardown(&c);
            j->calls++;
            if (st != ref_status[fi] || len != ref_len[fi] || memcmp(res, ref_res[fi], len) != 0) {
                if (!j->bad[fi]++)
                    j->first_rep[fi] = r;
            }
            free(res);
        }
    return NULL;
}

int main(int argc, char **argv)
{
    static audit_known known[512];
    static job_t jobs[NTHREADS];
    pthread_t tid[NTHREADS];
    int nknown = argc > 1 ? audit_read_known(argv[1], known, 512) : 0;
    int passed = 0, failed = 0, nhit = 0, nfn = 0;
    long calls = 0;
    setvbuf(stdout, NULL, _IOLBF, 0);
    if (argc > 2)
        reps = atoi(argv[2]);
    if (audit_nfns > MAX_FNS || reps < 1) {
        printf("test_threads: %d baselines (at most %d) or repetitions %d < 1\n", audit_nfns,
               MAX_FNS, reps);
        return 2;
    }
    for (int fi = 0; fi < audit_nfns; fi++) {
        audit_call c;
        if (!audit_fns[fi].threads)
            continue;
        audit_fns[fi].setup(&c);
        ref_status[fi] = audit_fns[fi].call(&c);
        ref_res[fi] = audit_results(&c, &ref_len[fi]);
        audit_teardown(&c);
    }
    for (int t = 0; t < NTHREADS; t++) {
        jobs[t].t = t;
        if (pthread_create(&tid[t], NULL, worker, &jobs[t]) != 0) {
            printf("test_threads: pthread_create failed\n");
            return 2;
        }
    }
    for (int t = 0; t < NTHREADS; t++) {
        pthread_join(tid[t], NULL);
        calls += jobs[t].calls;
    }
    for (int fi = 0; fi < audit_nfns; fi++) {
        const audit_fn *f = &audit_fns[fi];
        char id[200], msg[300];
        int bad = 0, tfirst = -1;
        if (!f->threads)
            continue;
        nfn++;
        for (int t = 0; t < NTHREADS; t++)
            if (jobs[t].bad[fi]) {
                bad += jobs[t].bad[fi];
                if (tfirst < 0)
                    tfirst = t;
            }
        if (!bad) {
            passed++;
            continue;
        }
        snprintf(id, sizeof id, "threads %s", f->name);
        snprintf(msg, sizeof msg, "%d of %d calls differ from the single-threaded run "
                 "(first: thread %d, repetition %d)", bad, NTHREADS * reps, tfirst,
                 jobs[tfirst].first_rep[fi]);
        audit_fail(known, nknown, id, msg, &nhit, &failed);
    }
    audit_unseen(known, nknown, "threads ");
    printf("test_threads: %d threads x %d repetitions x %d functions: %ld calls compared bit for "
           "bit with a single-threaded run\n", NTHREADS, reps, nfn, calls);
    if (nhit)
        printf("%d checks failed as listed in tests/audit/known_defects.txt\n", nhit);
    printf("%d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}
