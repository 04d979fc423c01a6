/* parallel.c - the library's own threads: work items 0..n-1 shared out
 * to threads that take the next one free (internal.h). */
#include <pthread.h>

#include "internal.h"

typedef struct {
    pthread_mutex_t lock;
    int next, n;
    void (*work)(void *, int);
    void *arg;
} pf_ctx;

static void *pf_worker(void *p)
{
    pf_ctx *c = p;
    for (;;) {
        pthread_mutex_lock(&c->lock);
        int k = c->next < c->n ? c->next++ : -1;
        pthread_mutex_unlock(&c->lock);
        if (k < 0)
            return NULL;
        c->work(c->arg, k);
    }
}

void igea__parallel_for(int n, int nthreads, void (*work)(void *arg, int k), void *arg)
{
    pf_ctx c;
    c.next = 0, c.n = n, c.work = work, c.arg = arg;
    if (nthreads > n)
        nthreads = n;
    if (nthreads > IGEA__THREADS_MAX)
        nthreads = IGEA__THREADS_MAX;
    if (nthreads < 2 || pthread_mutex_init(&c.lock, NULL) != 0) {
        for (int k = 0; k < n; k++)
            work(arg, k);
        return;
    }
    pthread_t tid[IGEA__THREADS_MAX];
    int started = 0;
    while (started < nthreads - 1 && pthread_create(&tid[started], NULL, pf_worker, &c) == 0)
        started++;
    pf_worker(&c); /* the calling thread too; a thread that did not start
                      leaves its items to the others */
    for (int t = 0; t < started; t++)
        pthread_join(tid[t], NULL);
    pthread_mutex_destroy(&c.lock);
}
