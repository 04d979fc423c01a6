/* src/sim_batch.c - the Monte Carlo in blocks of flights when S and the
 * stated K are common to them (igea_sim_montecarlo judging with the seed's
 * diagonal K): the normal matrix is decomposed once, A = V diag(lam0) V^T,
 * Q = Sw V; a block of b flights draws its truths X and noises E from the
 * flights' own streams (those of igea_sim_flight), forms
 * W = diag(sigma)^-1 (E + S D X) and the projections Q^T W with two dgemm,
 * then each flight's sigma_w loop and tests run on its column
 * (igea__eqerr_solve_projected, with the verdict rule's cache and the
 * per-thread table of what depends on lam0 alone). Every dgemm has
 * MB_CHUNK columns (a short block padded with zero columns), so that a
 * flight's result does not depend on the block it falls in, nor on the
 * thread that runs it. On a model's first call the other threads draw
 * their first block while the calling thread runs the set-up. */
#include <pthread.h>

#include <cblas.h>

#include "igea/eqerr.h"
#include "igea/stats.h"
#include "internal.h"
#include "sim_model.h"
#include "rng.h"
#include "sim_noise.h"

/* The width of every dgemm: a BLAS may treat the columns of a product
 * differently by their number (its kernels' tails), never by their values;
 * one shape for every call keeps a flight's result independent of the
 * block size, the thread and first_flight. A multiple of the column
 * unrolls of the common kernels (4, 8). */
#define MB_CHUNK 32

/* The rows of Q = Sw V in segments of MB_ROWS, taken by the threads in
 * turn: the same dgemm calls for every thread count (a row of a product
 * does not depend on the rows beside it in the call: OpenBLAS gives the
 * same bits as one call over all rows, checked with OpenBLAS 0.3.21 on its
 * Haswell and Cooperlake kernels). */
#define MB_ROWS 512

/* ---- the flights shared out among the threads (sim_model.h) ------------ */

int igea__sim_queue_init(igea__sim_queue *q, int nflights, int nthreads)
{
    q->next = 0;
    q->nflights = nflights;
    q->nthreads = nthreads;
    q->stop = 0;
    q->fail_flight = nflights;
    q->fail = 0;
    return pthread_mutex_init(&q->lock, NULL) ? IGEA_ENOMEM : 0;
}

void igea__sim_queue_destroy(igea__sim_queue *q)
{
    pthread_mutex_destroy(&q->lock);
}

int igea__sim_queue_take(igea__sim_queue *q, int max, int unit, int *f0)
{
    pthread_mutex_lock(&q->lock);
    int left = q->stop ? 0 : q->nflights - q->next, n = 0;
    if (left > 0) {
        n = (left + 2 * q->nthreads - 1) / (2 * q->nthreads);
        n = (n + unit - 1) / unit * unit;
        n = IGEA_MIN(IGEA_MIN(IGEA_MAX(n, unit), max), left);
        *f0 = q->next;
        q->next += n;
    }
    pthread_mutex_unlock(&q->lock);
    return n;
}

void igea__sim_queue_fail(igea__sim_queue *q, int f, int st)
{
    pthread_mutex_lock(&q->lock);
    q->stop = 1;
    if (f < q->fail_flight || !q->fail) {
        q->fail_flight = f;
        q->fail = st;
    }
    pthread_mutex_unlock(&q->lock);
}

/* What the threads share (read only but for the queue and each flight's
 * own outputs); each thread's own state is on its stack and in its own
 * allocation (mb_worker): nothing it writes per flight shares a cache line
 * with another thread's. */
typedef struct {
    const igea_sim_model *c;
    const double *Q, *lam0, *eqo, *L; /* L = V diag(lam0), N x N */
    /* Q = Sw V (m x N) in row segments before the flights (mb_rows) */
    const igea__sim_setup *s;
    igea__sim_setup_fn setup; /* NULL, or run by the calling thread (mb_run) */
    double *zeros;
    igea__sim_queue *qrow;
    int *rows_done;
    int *setup_state;         /* 0 running, 1 done, -1 failed (under qrow's lock) */
    pthread_cond_t *rows_cv;
    int seed, first, block;
    double *chi2, *scale, *zmax, *fsize;
    int *dof, *nrej, *status;
    int *cnt; /* tested, rejected (N each): the threads' counts added at their end */
    pthread_mutex_t *cnt_lock;
    igea__sim_queue *q;
} mb_job;

/* ---- igea's keyed streams (IGEA_SIM_XOSHIRO) --------------------------- */

void igea__sim_truth_xoshiro(const igea_sim_model *c, void *st, int seed, int flight,
                             double *x, double *xs)
{
    igea__xoshiro_key(st, seed, flight);
    igea__xoshiro_normals(st, c->N, x); /* drawn for the fixed terms too */
    for (int j = 0; j < c->N; j++) {
        if (c->x_fixed[j])
            x[j] = c->x_value[j];
        xs[j] = x[j] * c->spec[j];
    }
}

/* The plain noise on the keyed stream: dw[i] += sd_i eps_i, or with
 * whiten dw[i] = (sd_i / sigma_i) eps_i (the same draws, in stated
 * sigmas: the batched path's rows), sd_i = sigma_w sigma_i (1 + g e/(M-1)). */
static void noise_xoshiro(const igea_sim_model *c, igea__xoshiro *st, int whiten, double *dw)
{
    int M = c->m / 3;
    double sw = c->opts[IGEA_SIM_OPT_SIGMA_W], phi = c->opts[IGEA_SIM_OPT_AR1];
    double growth = c->opts[IGEA_SIM_OPT_GROWTH], p_out = c->opts[IGEA_SIM_OPT_OUTLIER_PROB];
    double out_scale = c->opts[IGEA_SIM_OPT_OUTLIER_SCALE];
    double innov = sqrt(1.0 - phi * phi), prev[3] = {0, 0, 0};
    if (whiten && phi == 0.0 && growth == 0.0 && p_out == 0.0) { /* white: the same values */
        int m = c->m;
        igea__xoshiro_normals(st, m, dw);
        for (int i = 0; i < m; i++)
            dw[i] *= sw;
        return;
    }
    for (int e = 0; e < M; e++) {
        double ge = sw * (1.0 + (M > 1 ? growth * e / (double)(M - 1) : 0.0));
        for (int a = 0; a < 3; a++) {
            int i = 3 * e + a;
            double g = igea__xoshiro_normal(st);
            double eps = (e == 0) ? g : phi * prev[a] + innov * g;
            double sd = whiten ? ge : ge * c->sigma[i], v = sd * eps;
            prev[a] = eps;
            if (p_out > 0.0 && igea__xoshiro_uniform(st) < p_out)
                v += out_scale * sd * igea__xoshiro_normal(st);
            dw[i] = whiten ? v : dw[i] + v;
        }
    }
}

void igea__sim_noise_xoshiro(const igea_sim_model *c, void *st, double *dw)
{
    noise_xoshiro(c, st, 0, dw);
}

/* A block on the keyed streams: the truths X (N x b, unscaled) and the
 * whitened noises E (m x b; the noise models of sim_noise.c drawn as
 * igea__sim_draw_noise draws them, then divided by sigma); mb_products_xoshiro
 * then forms PB = L^T X + Q^T E with L = V diag(lam0) (Q^T Sw = V^T A =
 * diag(lam0) V^T: the product with S is not formed). The draws need no
 * set-up. */
static void mb_draw_xoshiro(const mb_job *jb, gsl_rng *r, int f0, int nb, double *X,
                            double *E, double *xs)
{
    const igea_sim_model *c = jb->c;
    int m = c->m, N = c->N, b = (nb + MB_CHUNK - 1) / MB_CHUNK * MB_CHUNK;
    for (int j = 0; j < b; j++) {
        double *x = X + (size_t)j * N, *e = E + (size_t)j * m;
        if (j >= nb) {
            memset(x, 0, (size_t)N * sizeof(double));
            memset(e, 0, (size_t)m * sizeof(double));
            continue;
        }
        igea__sim_truth_xoshiro(c, r->state, jb->seed, jb->first + f0 + j, x, xs);
        if (igea__sim_noise_plain(c->opts)) {
            noise_xoshiro(c, r->state, 1, e);
            continue;
        }
        memset(e, 0, (size_t)m * sizeof(double)); /* AR(p), correlation, groups */
        igea__sim_draw_noise(c, r, e);
        for (int i = 0; i < m; i++)
            e[i] /= c->sigma[i];
    }
}

static void mb_products_xoshiro(const mb_job *jb, int nb, const double *X, const double *E,
                                double *PB)
{
    int m = jb->c->m, N = jb->c->N, b = (nb + MB_CHUNK - 1) / MB_CHUNK * MB_CHUNK;
    for (int j0 = 0; j0 < b; j0 += MB_CHUNK) {
        double *pb = PB + (size_t)j0 * N;
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, N, MB_CHUNK, N, 1.0, jb->L, N,
                    X + (size_t)j0 * N, N, 0.0, pb, N);
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, N, MB_CHUNK, m, 1.0, jb->Q, m,
                    E + (size_t)j0 * m, m, 1.0, pb, N);
    }
}

/* The block's truths (XS, N x b) and noises (DW, m x b), zero columns past
 * nb flights up to b = nb rounded up to MB_CHUNK (no set-up needed);
 * mb_products then forms DW = diag(sigma)^-1 (DW + S XS) and PB = Q^T DW,
 * by dgemm calls of MB_CHUNK columns each. */
static void mb_draw(const mb_job *jb, gsl_rng *r, int f0, int nb, double *XS, double *DW,
                    double *x)
{
    const igea_sim_model *c = jb->c;
    int m = c->m, N = c->N, b = (nb + MB_CHUNK - 1) / MB_CHUNK * MB_CHUNK;
    for (int j = 0; j < b; j++) {
        double *xs = XS + (size_t)j * N, *dw = DW + (size_t)j * m;
        memset(dw, 0, (size_t)m * sizeof(double));
        if (j >= nb) {
            memset(xs, 0, (size_t)N * sizeof(double));
            continue;
        }
        igea__sim_draw_truth(c, r, jb->seed, jb->first + f0 + j, x, xs);
        igea__sim_draw_noise(c, r, dw);
    }
}

static void mb_products(const mb_job *jb, int nb, double *XS, double *DW, double *PB)
{
    const igea_sim_model *c = jb->c;
    int m = c->m, N = c->N, b = (nb + MB_CHUNK - 1) / MB_CHUNK * MB_CHUNK;
    for (int j0 = 0; j0 < b; j0 += MB_CHUNK) {
        double *xs = XS + (size_t)j0 * N, *dw = DW + (size_t)j0 * m;
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, MB_CHUNK, N, 1.0, c->S, m,
                    xs, N, 1.0, dw, m);
        for (int j = 0; j < MB_CHUNK; j++)
            for (int i = 0; i < m; i++)
                dw[(size_t)j * m + i] /= c->sigma[i];
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, N, MB_CHUNK, m, 1.0, jb->Q, m,
                    dw, m, 0.0, PB + (size_t)j0 * N, N);
    }
}

/* Flight f's verdict from its projections pb, recorded as mc_judge does
 * (sim.c), its components counted in cnt (the thread's own, 2 N); pre the
 * model's sqrt(lam0) and sqrt(1 + 1 / lam0) (mb_pre), scratch w (4 N +
 * IGEA_STATS_INFO_LEN), vc the caches (6 N). The p-value is not computed:
 * no output of the study holds it. */
static int mb_judge(const mb_job *jb, int f, const double *pb, const double *pre, double *w,
                    double *vc, int *rej, int *cnt)
{
    int N = jb->c->N;
    double *z = w + 3 * (size_t)N, *info = z + N;
    int st = igea__eqerr_solve_projected(N, jb->lam0, pre, 0, pb, jb->eqo, vc, w, z, rej, info);
    jb->status[f] = st;
    jb->fsize[f] = 0.0;
    jb->zmax[f] = 0.0;
    if (st == IGEA_ENOTESTABLE) {
        jb->chi2[f] = 0.0;
        jb->dof[f] = 0;
        jb->nrej[f] = 0;
        jb->scale[f] = NAN;
        return 0;
    }
    if (st < 0)
        return (st > -1000) ? -2 : st;
    jb->chi2[f] = info[IGEA_STATS_INFO_CHI2];
    jb->dof[f] = (int)info[IGEA_STATS_INFO_DOF];
    jb->nrej[f] = (int)info[IGEA_STATS_INFO_N_REJECT];
    jb->scale[f] = info[IGEA_STATS_INFO_SCALE];
    jb->status[f] = info[IGEA_STATS_INFO_CHI2] >= info[IGEA_STATS_INFO_VERDICT_CHI2_CRIT];
    jb->fsize[f] = info[IGEA_STATS_INFO_OVERALL_SIZE];
    jb->zmax[f] = igea__sim_zmax(N, z, rej);
    for (int i = 0; i < N; i++) {
        cnt[i] += rej[i] >= 0;
        cnt[N + i] += rej[i] == 1;
    }
    return 0;
}

void igea__sim_setup_map(igea__sim_setup *s, double *data, int m, int N)
{
    size_t mn = (size_t)m * N, nn = (size_t)N * N;
    s->Sw = data;
    s->A = s->Sw + mn;
    s->V = s->A + nn;
    s->lam0 = s->V + nn;
    s->Q = s->lam0 + N;
    s->L = s->Q + mn;
}

/* Rows r0 .. r0 + MB_ROWS - 1 (or to m) of Q = Sw V. */
static void q_rows(const igea__sim_setup *s, int m, int N, int r0)
{
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, IGEA_MIN(MB_ROWS, m - r0), N, N,
                1.0, s->Sw + r0, m, s->V, N, 0.0, s->Q + r0, m);
}

void igea__sim_setup_q(const igea__sim_setup *s, int m, int N)
{
    for (int r0 = 0; r0 < m; r0 += MB_ROWS)
        q_rows(s, m, N, r0);
}

/* The thread's share of Q = Sw V by segments of MB_ROWS rows, then the
 * wait for the others' (rows_done counts the segments, under qrow's lock). */
static void mb_rows(const mb_job *jb)
{
    int m = jb->c->m, N = jb->c->N, nseg = (m + MB_ROWS - 1) / MB_ROWS, s0;
    while (igea__sim_queue_take(jb->qrow, 1, 1, &s0) > 0) {
        q_rows(jb->s, m, N, s0 * MB_ROWS);
        pthread_mutex_lock(&jb->qrow->lock);
        if (++*jb->rows_done == nseg)
            pthread_cond_broadcast(jb->rows_cv);
        pthread_mutex_unlock(&jb->qrow->lock);
    }
    pthread_mutex_lock(&jb->qrow->lock);
    while (*jb->rows_done < nseg)
        pthread_cond_wait(jb->rows_cv, &jb->qrow->lock);
    pthread_mutex_unlock(&jb->qrow->lock);
}

/* What the judgement of every flight takes from lam0 alone, computed once
 * per thread: pre[i] = sqrt(lam0[i]), pre[N + i] = sqrt(1 + 1 / lam0[i])
 * (the expressions of igea__eqerr_solve_projected and the accuracy test,
 * hence their bits; zero where lam0[i] <= 0, below the rank, not read). */
static void mb_pre(int N, const double *lam0, double *pre)
{
    for (int i = 0; i < N; i++) {
        int pos = lam0[i] > 0.0;
        pre[i] = pos ? sqrt(lam0[i]) : 0.0;
        pre[N + i] = pos ? sqrt(1.0 + 1.0 / lam0[i]) : 0.0;
    }
}

static void *mb_worker(void *arg)
{
    const mb_job *jb = arg;
    const igea_sim_model *c = jb->c;
    size_t m = (size_t)c->m, N = (size_t)c->N, b = (size_t)jb->block;
    double *w = igea__dalloc(b * (N + m + N) + 13 * N + IGEA_STATS_INFO_LEN);
    int *rej = igea__ialloc(3 * N);
    gsl_rng *r = (w && rej) ? igea__rng_new(igea__sim_rng_type(c), 0) : NULL;
    if (!r) {
        free(w);
        free(rej);
        igea__sim_queue_fail(jb->q, -1, IGEA_ENOMEM); /* before every flight */
        return NULL;
    }
    double *XS = w, *DW = XS + b * N, *PB = DW + b * m, *x = PB + b * N;
    int xo = r->type == igea__xoshiro_type, f0 = 0, nb = 0, drawn = 0;
    /* the first block's draws while the calling thread runs the set-up */
    pthread_mutex_lock(&jb->qrow->lock);
    int waiting = *jb->setup_state == 0;
    pthread_mutex_unlock(&jb->qrow->lock);
    if (waiting && (nb = igea__sim_queue_take(jb->q, jb->block, MB_CHUNK, &f0)) > 0) {
        if (xo)
            mb_draw_xoshiro(jb, r, f0, nb, XS, DW, x);
        else
            mb_draw(jb, r, f0, nb, XS, DW, x);
        drawn = 1;
    }
    pthread_mutex_lock(&jb->qrow->lock);
    while (*jb->setup_state == 0)
        pthread_cond_wait(jb->rows_cv, &jb->qrow->lock);
    int setup_ok = *jb->setup_state == 1;
    pthread_mutex_unlock(&jb->qrow->lock);
    if (!setup_ok) {
        igea__rng_free(r);
        free(w);
        free(rej);
        return NULL;
    }
    mb_rows(jb);
    double *vc = x + N, *pre = vc + 6 * N, *judge = pre + 2 * N;
    int *cnt = rej + N;
    memset(vc, 0, 6 * N * sizeof(double));
    mb_pre((int)N, jb->lam0, pre);
    memset(cnt, 0, 2 * N * sizeof(int));
    for (;;) {
        if (!drawn) {
            if ((nb = igea__sim_queue_take(jb->q, jb->block, MB_CHUNK, &f0)) <= 0)
                break;
            if (xo)
                mb_draw_xoshiro(jb, r, f0, nb, XS, DW, x);
            else
                mb_draw(jb, r, f0, nb, XS, DW, x);
        }
        drawn = 0;
        if (xo)
            mb_products_xoshiro(jb, nb, XS, DW, PB);
        else
            mb_products(jb, nb, XS, DW, PB);
        for (int j = 0; j < nb; j++) {
            int st = mb_judge(jb, f0 + j, PB + (size_t)j * N, pre, judge, vc, rej, cnt);
            if (st) {
                igea__sim_queue_fail(jb->q, f0 + j, st);
                break;
            }
        }
    }
    pthread_mutex_lock(jb->cnt_lock);
    for (size_t i = 0; i < 2 * N; i++)
        jb->cnt[i] += cnt[i];
    pthread_mutex_unlock(jb->cnt_lock);
    igea__rng_free(r);
    free(w);
    free(rej);
    return NULL;
}

/* Run the job on nthreads threads, the calling thread one of them (a
 * thread that cannot start leaves its share to the others); the calling
 * thread runs the set-up (if any) once the others are started: they draw
 * their first block meanwhile (the draws need no set-up) and wait for it
 * (a failed set-up is the result, at flight -2: before every other). */
static void mb_run(mb_job *jb, int nthreads)
{
    pthread_t *tid = calloc((size_t)nthreads, sizeof *tid);
    int nstarted = 0;
    for (int t = 1; tid && t < nthreads; t++) {
        if (pthread_create(&tid[t], NULL, mb_worker, jb) != 0)
            break;
        nstarted = t;
    }
    if (jb->setup) {
        int st = jb->setup(jb->c, jb->s, jb->zeros);
        if (st)
            igea__sim_queue_fail(jb->q, -2, st);
        pthread_mutex_lock(&jb->qrow->lock);
        *jb->setup_state = st ? -1 : 1;
        pthread_cond_broadcast(jb->rows_cv);
        pthread_mutex_unlock(&jb->qrow->lock);
    }
    mb_worker(jb);
    for (int t = 1; t <= nstarted; t++)
        pthread_join(tid[t], NULL);
    free(tid);
}

int igea__sim_mc_batch(const igea_sim_model *c, const igea__sim_setup *s,
                       igea__sim_setup_fn setup, double *zeros, int have_q,
                       const double *eqo, int seed, int first, int nflights,
                       int nthreads, int block, double *chi2, double *scale, double *zmax,
                       double *fsize, int *dof, int *nrej, int *status, int *cnt)
{
    int m = c->m, nseg = (m + MB_ROWS - 1) / MB_ROWS, ok = 0;
    int rows_done = have_q ? nseg : 0; /* a kept Q: nothing to do */
    int setup_state = setup ? 0 : 1;
    igea__sim_queue q, qrow;
    pthread_mutex_t cnt_lock;
    pthread_cond_t rows_cv;
    /* ok counts what is initialised: the queues, the lock, the condition */
    if (igea__sim_queue_init(&q, nflights, nthreads) == 0 && ++ok &&
        igea__sim_queue_init(&qrow, have_q ? 0 : nseg, nthreads) == 0 && ++ok &&
        pthread_mutex_init(&cnt_lock, NULL) == 0 && ++ok && pthread_cond_init(&rows_cv, NULL) == 0)
        ++ok;
    int st = ok == 4 ? 0 : IGEA_ENOMEM;
    block = (block + MB_CHUNK - 1) / MB_CHUNK * MB_CHUNK;
    if (st == 0) {
        mb_job jb = {c,     s->Q,  s->lam0, eqo,  s->L,   s,    setup, zeros, &qrow,
                     &rows_done, &setup_state, &rows_cv, seed, first, block, chi2, scale,
                     zmax,  fsize, dof,     nrej, status, cnt, &cnt_lock, &q};
        mb_run(&jb, nthreads);
        st = q.fail;
    }
    if (ok >= 4)
        pthread_cond_destroy(&rows_cv);
    if (ok >= 3)
        pthread_mutex_destroy(&cnt_lock);
    if (ok >= 2)
        igea__sim_queue_destroy(&qrow);
    if (ok >= 1)
        igea__sim_queue_destroy(&q);
    return st;
}
