/* tests/audit/audit.h - run-time support of the generated audit suites.
 *
 * gen_invalid.py reads the public headers and writes, for every exported
 * function, a descriptor (audit_fn): a set-up that builds one valid call
 * (its "baseline") in an audit_call, a wrapper that makes the call from it,
 * and the list of invalid mutations of that call. The suites
 * (test_invalid.c, test_oom.c, test_threads.c) only interpret those tables.
 *
 * Every pointer argument gets its own heap buffer of AUDIT_NB elements,
 * larger than any baseline needs: an output is filled with a byte pattern
 * (AUDIT_FILL) and compared whole, so no output size has to be known. */
#ifndef IGEA_AUDIT_H
#define IGEA_AUDIT_H

#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <pthread.h>
#include <unistd.h>

#include "igea.h"

#define AUDIT_MAXARG 24
#define AUDIT_NB 4096
#define AUDIT_FILL 0xA5
#define AUDIT_PI 3.14159265358979323846
/* A handle output's initial content: not a valid handle, not NULL. */
#define AUDIT_BAD_HANDLE ((igea_rls *)(uintptr_t)0x5a5a5a50u)

/* Handle kinds. */
enum { AUDIT_HK_RLS, AUDIT_HK_SIM, AUDIT_HK_IO, AUDIT_HK_WHITEN, AUDIT_HK_STREAM };
/* Argument types. */
enum { AT_INT, AT_DBL, AT_PD, AT_PI, AT_H, AT_HO };
/* Mutation kinds. */
enum { MK_INT, MK_IADD, MK_DBL, MK_NULL, MK_ELEM, MK_IELEM };
/* What a mutated call must do. */
enum { EX_FAIL, EX_OK, EX_ANY };

typedef struct {
    int arg;       /* 0-based argument index */
    int kind;      /* MK_* */
    long ival;     /* MK_INT: the new value; MK_IADD: added to the baseline;
                      MK_ELEM: the index of the element; MK_IELEM: the value */
    double dval;   /* MK_DBL, MK_ELEM: the new value */
    int expect;    /* EX_* */
    const char *label; /* "lda=m-1", "A=NULL", "A[0]=NaN", ... */
} audit_mut;

typedef struct {
    int nargs;
    int type[AUDIT_MAXARG];
    int isconst[AUDIT_MAXARG];
    long iv[AUDIT_MAXARG];
    double dv[AUDIT_MAXARG];
    void *pv[AUDIT_MAXARG];  /* what is passed */
    void *buf[AUDIT_MAXARG]; /* what is owned (freed by audit_teardown) */
    size_t nbytes[AUDIT_MAXARG];
    unsigned char *snap[AUDIT_MAXARG]; /* content before the call */
    double hstate[AUDIT_MAXARG][64];   /* a handle's state before the call */
    int consumed[AUDIT_MAXARG];        /* the call released this handle */
    int hkind[AUDIT_MAXARG];           /* a handle's kind: AUDIT_HK_* */
} audit_call;

typedef struct {
    const char *name;
    int nargs;
    const char *const *argnames;
    void (*setup)(audit_call *);
    int (*call)(audit_call *);
    const audit_mut *muts;
    int nmut;
    int threads; /* 0: process-wide set-up, not for the threads suite */
    int consumes; /* index of a handle argument the call releases, or -1 */
    unsigned long nan_out; /* bit a: output argument a may hold NaN on success */
    int base_any; /* the baseline may fail (extreme data): then untouched, no mutations */
    unsigned long progress; /* bit a: argument a reports progress and may be written
                               when a call fails with an IGEA_E* status (not -i) */
} audit_fn;

/* ---- deterministic values -------------------------------------------- */

/* Uniform in [0, 1) from an index (SplitMix64 finaliser). */
static inline double audit_u01(long i)
{
    uint64_t z = (uint64_t)i * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}
/* Uniform in [-1, 1). */
static inline double au(long i) { return 2.0 * audit_u01(i) - 1.0; }
/* Uniform in [0.5, 1.5): scales, sigmas. */
static inline double apos(long i) { return 0.5 + audit_u01(i + 7777); }
static inline double asind(double deg) { return sin(deg * AUDIT_PI / 180.0); }
static inline double acosd(double deg) { return cos(deg * AUDIT_PI / 180.0); }

/* Symmetric positive definite n x n (ld) matrix: d I + a small symmetric
 * perturbation. */
static inline void audit_spd(double *p, int n, int ld, double d)
{
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            int lo = i < j ? i : j, hi = i < j ? j : i;
            p[i + (size_t)j * ld] = (i == j ? d : 0.0) + 0.1 * au(lo * 31 + hi);
        }
}
/* Upper-triangular n x n (ld) with diagonal d and small entries above. */
static inline void audit_upper(double *p, int n, int ld, double d)
{
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            p[i + (size_t)j * ld] = i == j ? d * (1.0 + 0.1 * j) : i < j ? au(i + 17 * j) : 0.0;
}

/* A handle of m coefficients, k rows, with the given variant (order p)
 * and anomaly policy, after nup updates. NULL on failure. */
static inline igea_rls *audit_rls_new_ex(int m, int k, int nup, int variant, int p, int policy)
{
    double g[64], c[64], y[16];
    igea_rls *h = NULL;
    audit_spd(g, m, m, 4.0);
    if (igea_rls_create(m, k, NULL, g, m, &h) != 0)
        return NULL;
    if (igea_rls_set_variant(h, variant, p) != 0 ||
        igea_rls_set_anomaly(h, policy, 4.0, NULL) != 0) {
        igea_rls_free(h);
        return NULL;
    }
    for (int e = 0; e < nup; e++) {
        for (int i = 0; i < k * m; i++)
            c[i] = au(100 * e + i);
        for (int i = 0; i < k; i++)
            y[i] = 0.3 * au(1000 + 10 * e + i);
        if (igea_rls_update(h, c, k, y, NULL, NULL) < 0) {
            igea_rls_free(h);
            return NULL;
        }
    }
    return h;
}

static inline igea_rls *audit_rls_new(int m, int k, int nup)
{
    return audit_rls_new_ex(m, k, nup, IGEA_RLS_STANDARD, 1, IGEA_RLS_ANOMALY_NONE);
}

/* The observable state of a handle, for "untouched" and "bitwise equal"
 * checks: sizes, x, Gamma, P (or a marker), Q, counters. */
static inline void audit_rls_state(const igea_rls *h, double st[64])
{
    int m = 0, k = 0, counts[IGEA_RLS_COUNT_LEN] = {0};
    for (int i = 0; i < 64; i++)
        st[i] = 0;
    if (!h || igea_rls_get_size(h, &m, &k) != 0 || m > 4)
        return;
    st[0] = m;
    st[1] = k;
    igea_rls_get_x(h, st + 2);
    igea_rls_get_gamma(h, st + 6, m);
    if (igea_rls_get_covariance(h, st + 22, m) != 0)
        st[22] = -1;
    igea_rls_get_q(h, st + 38);
    igea_rls_get_counts(h, counts);
    for (int i = 0; i < IGEA_RLS_COUNT_LEN; i++)
        st[40 + i] = counts[i];
}

/* A simulation model of a 6 x 3 geometry (traj 0) or of the 10 s reference
 * trajectory, 3 terms, 5 epochs (traj 1; traj 2 with the nonlinear truth);
 * stated sigma 0.05, specs, one fixed term. NULL on failure. */
static inline igea_sim_model *audit_sim_model_new(int traj)
{
    double S[18], sig = 0.05, spec[3] = {0.5, 1.0, 2.0}, xv[3] = {1.5, 0, 0};
    double tr[101 * IGEA_ENVFUN_TRAJ_COLS], ep[5] = {1, 3, 5, 7, 9};
    int xf[3] = {1, 0, 0}, terms[3] = {0, 3, 15};
    igea_sim_model *h = NULL;
    for (int i = 0; i < 18; i++)
        S[i] = au(i + 300);
    if (traj ? igea_sim_trajectory(IGEA_ENVFUN_STRAPDOWN, 10.0, 10.0, 101, tr, 101) != 0 ||
                   igea_sim_model_create_trajectory(IGEA_ENVFUN_STRAPDOWN, 101, tr, 101, 3,
                                                    terms, NULL, 5, ep, &h) != 0
             : igea_sim_model_create(6, 3, S, 6, &h) != 0)
        return NULL;
    if (igea_sim_model_set_sigma(h, &sig, 0, 0.5) != 0 ||
        (!traj && igea_sim_model_set_spec(h, spec) != 0) ||
        igea_sim_model_set_truth(h, xv, xf) != 0 ||
        (traj == 2 && igea_sim_model_set_nonlinear(h, 1) != 0)) {
        igea_sim_model_free(h);
        return NULL;
    }
    return h;
}

/* The observable state of a model: sizes, S, stated sigma, specs. */
static inline void audit_sim_model_state(const igea_sim_model *h, double st[64])
{
    int m = 0, N = 0;
    for (int i = 0; i < 64; i++)
        st[i] = 0;
    if (!h || igea_sim_model_get_size(h, &m, &N) != 0 || m * N > 30 || m > 15)
        return;
    st[0] = m;
    st[1] = N;
    igea_sim_model_get_s(h, st + 2, m);
    igea_sim_model_get_sigma(h, st + 32);
    igea_sim_model_get_spec(h, st + 47);
}

/* The matrix file of the reader's baselines: a header row and 3 x 2 values,
 * written once (atomically, by whichever process or thread comes first). */
#define AUDIT_IO_TEXT "t,x\n1.5,2D0\n-3,4e1\n5,6\n"
static inline const char *audit_io_path(void)
{
    static const char path[] = "/tmp/igea-audit-io.txt";
    char tmp[64];
    FILE *f;
    if ((f = fopen(path, "rb")) != NULL) {
        char b[64] = {0};
        size_t n = fread(b, 1, sizeof b - 1, f);
        fclose(f);
        if (n == strlen(AUDIT_IO_TEXT) && !strcmp(b, AUDIT_IO_TEXT))
            return path;
    }
    snprintf(tmp, sizeof tmp, "%s.%ld.%lu", path, (long)getpid(),
             (unsigned long)(uintptr_t)&tmp);
    if (!(f = fopen(tmp, "wb")) || fputs(AUDIT_IO_TEXT, f) < 0 || fclose(f) != 0 ||
        rename(tmp, path) != 0) {
        fprintf(stderr, "audit: cannot write %s\n", path);
        exit(2);
    }
    return path;
}

/* Its path into b_ (an argument buffer). */
static inline void audit_io_file(char *b) { strcpy(b, audit_io_path()); }

/* A descriptor of it, opened once per process (the reader uses pread on a
 * regular file, so threads may share it). */
static int audit_io_fd_v = -1;
static void audit_io_fd_init(void)
{
    FILE *f = fopen(audit_io_path(), "rb");
    if (!f)
        exit(2);
    audit_io_fd_v = fileno(f); /* kept open for the process */
}
static inline int audit_io_fd(void)
{
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, audit_io_fd_init);
    return audit_io_fd_v;
}

/* A reader: created only (how 0), opened on the file (1), opened for two
 * passes (2), opened and loaded (3). NULL on failure. */
static inline igea_io_reader *audit_io_new(int how)
{
    igea_io_reader *r = NULL;
    if (igea_io_reader_create(&r) != 0)
        return NULL;
    if (how > 0 && igea_io_reader_open(r, audit_io_path(), how == 2 ? IGEA_IO_TWICE : 0,
                                       NULL) != 0) {
        igea_io_reader_free(r);
        return NULL;
    }
    if (how == 3 && igea_io_reader_load(r) != 0) {
        igea_io_reader_free(r);
        return NULL;
    }
    return r;
}

/* The observable state of a reader: columns, rows loaded, names, kind. */
static inline void audit_io_state(const igea_io_reader *h, double st[64])
{
    double info[IGEA_IO_INFO_LEN];
    for (int i = 0; i < 64; i++)
        st[i] = 0;
    if (!h || igea_io_reader_info(h, info) != 0)
        return;
    st[0] = info[IGEA_IO_INFO_COLS];
    st[1] = info[IGEA_IO_INFO_ROWS];
    st[2] = info[IGEA_IO_INFO_NAMES];
    st[3] = info[IGEA_IO_INFO_NPY];
}

/* A whitener of N = 3 columns, AR(1) with phi 0.5, 0.3, -0.2, two groups,
 * after one block of two epochs (so that it carries rows). NULL on failure. */
static inline igea_whiten *audit_whiten_new(void)
{
    double phi[3] = {0.5, 0.3, -0.2}, S[18], dw[6], sg = 0.5, A[18] = {0}, b[6] = {0};
    double wtw[4] = {0};
    igea_whiten *h = NULL;
    for (int i = 0; i < 18; i++)
        S[i] = au(i + 700);
    for (int i = 0; i < 6; i++)
        dw[i] = au(i + 720);
    if (igea_whiten_create(3, 1, phi, 2, &h) != 0)
        return NULL;
    if (igea_whiten_accumulate(h, IGEA_COLMAJOR, 6, S, 6, dw, &sg, 0, NULL, NULL, NULL, NULL,
                               A, 3, b, wtw, NULL, NULL) != 0) {
        igea_whiten_free(h);
        return NULL;
    }
    return h;
}

/* The whole K of the audit's xcov baselines (igea_whiten_accumulate_xcov,
 * igea_noise_eqerr_xcov): epoch e's K_ee = s (C + 0.1 e I) and X_e = 0.1 e s I
 * (a white C per epoch and a random walk of steps 0.1 s I), C = [1 .2 .1;
 * .2 1 .3; .1 .3 1], for epochs e0 .. e0 + n - 1 into k6 (6 n) and x9 (9 n). */
static inline void audit_whole_k(int e0, int n, double s, double *k6, double *x9)
{
    for (int q = 0; q < n; q++) {
        double r = 0.1 * (e0 + q), c6[6] = {1.0 + r, 0.2, 1.0 + r, 0.1, 0.3, 1.0 + r};
        for (int k = 0; k < 6; k++)
            k6[6 * q + k] = s * c6[k];
        for (int k = 0; k < 9; k++)
            x9[9 * q + k] = k % 4 == 0 ? s * r : 0.0;
    }
}

/* A whitener of N = 3 columns for the whole K (p = 0, one group) after one
 * block of two epochs of igea_whiten_accumulate_xcov. NULL on failure. */
static inline igea_whiten *audit_whiten_xcov_new(void)
{
    double S[18], dw[6], k6[12], x9[18], A[9] = {0}, b[3] = {0}, wtw[2] = {0};
    igea_whiten *h = NULL;
    for (int i = 0; i < 18; i++)
        S[i] = au(i + 740);
    for (int i = 0; i < 6; i++)
        dw[i] = au(i + 760);
    audit_whole_k(0, 2, 1.0, k6, x9);
    if (igea_whiten_create(3, 0, NULL, 1, &h) != 0)
        return NULL;
    if (igea_whiten_accumulate_xcov(h, IGEA_COLMAJOR, 6, S, 6, dw, k6, x9, NULL, NULL, A, 3, b,
                                    wtw, NULL, NULL) != 0) {
        igea_whiten_free(h);
        return NULL;
    }
    return h;
}

/* The observable state of a whitener: epochs carried and current group. */
static inline void audit_whiten_state(const igea_whiten *h, double st[64])
{
    int g = 0;
    for (int i = 0; i < 64; i++)
        st[i] = 0;
    if (h && igea_whiten_get_state(h, st, &g) == 0)
        st[1] = g;
}

/* A stability stream (overlapping Allan deviation, octave taus, noise
 * identified, 100-sample blocks) fed 300 samples. NULL on failure. */
static inline igea_stability_stream *audit_stream_new(void)
{
    double y[300];
    igea_stability_stream *h = NULL;
    for (int i = 0; i < 300; i++)
        y[i] = au(i + 900);
    if (igea_stability_stream_create(10.0, IGEA_STABILITY_DATA_FREQ, IGEA_STABILITY_ALLAN_OVERLAPPING,
                                     IGEA_STABILITY_NOISE_AUTO, 0.683, 0, NULL,
                                     IGEA_STABILITY_TAUS_OCTAVE, 10.0, &h) != 0)
        return NULL;
    if (igea_stability_stream_feed(h, 300, y) != 0) {
        igea_stability_stream_free(h);
        return NULL;
    }
    return h;
}

/* The same stream before any sample is fed (igea_stability_stream_source
 * is called then). NULL on failure. */
static inline igea_stability_stream *audit_stream_new0(void)
{
    igea_stability_stream *h = NULL;
    if (igea_stability_stream_create(10.0, IGEA_STABILITY_DATA_FREQ, IGEA_STABILITY_ALLAN_OVERLAPPING,
                                     IGEA_STABILITY_NOISE_AUTO, 0.683, 0, NULL,
                                     IGEA_STABILITY_TAUS_OCTAVE, 10.0, &h) != 0)
        return NULL;
    return h;
}

/* The observable state of a stream: the samples fed. */
static inline void audit_stream_state(const igea_stability_stream *h, double st[64])
{
    for (int i = 0; i < 64; i++)
        st[i] = 0;
    if (h)
        igea_stability_stream_samples(h, st);
}

static inline void audit_hfree(int kind, void *h)
{
    if (kind == AUDIT_HK_STREAM)
        igea_stability_stream_free((igea_stability_stream *)h);
    else if (kind == AUDIT_HK_IO)
        igea_io_reader_free((igea_io_reader *)h);
    else if (kind == AUDIT_HK_WHITEN)
        igea_whiten_free((igea_whiten *)h);
    else if (kind == AUDIT_HK_SIM)
        igea_sim_model_free((igea_sim_model *)h);
    else
        igea_rls_free((igea_rls *)h);
}

static inline void audit_hstate(int kind, const void *h, double st[64])
{
    if (kind == AUDIT_HK_STREAM)
        audit_stream_state((const igea_stability_stream *)h, st);
    else if (kind == AUDIT_HK_IO)
        audit_io_state((const igea_io_reader *)h, st);
    else if (kind == AUDIT_HK_WHITEN)
        audit_whiten_state((const igea_whiten *)h, st);
    else if (kind == AUDIT_HK_SIM)
        audit_sim_model_state((const igea_sim_model *)h, st);
    else
        audit_rls_state((const igea_rls *)h, st);
}

/* ---- buffers ---------------------------------------------------------- */

static inline void *audit_buf(audit_call *c, int a, int type, int isconst, size_t elsize)
{
    c->type[a] = type;
    c->isconst[a] = isconst;
    c->nbytes[a] = (size_t)AUDIT_NB * elsize;
    c->buf[a] = malloc(c->nbytes[a]);
    if (!c->buf[a]) {
        fprintf(stderr, "audit: out of memory in the set-up\n");
        exit(2);
    }
    memset(c->buf[a], AUDIT_FILL, c->nbytes[a]);
    c->pv[a] = c->buf[a];
    return c->buf[a];
}

static inline void audit_teardown(audit_call *c)
{
    for (int a = 0; a < c->nargs; a++) {
        if (c->type[a] == AT_H && c->buf[a] && !c->consumed[a])
            audit_hfree(c->hkind[a], c->buf[a]);
        else if (c->type[a] == AT_HO && c->buf[a]) {
            igea_rls *h = *(igea_rls **)c->buf[a];
            if (h != AUDIT_BAD_HANDLE)
                audit_hfree(c->hkind[a], h);
            free(c->buf[a]);
        } else if (c->type[a] != AT_H)
            free(c->buf[a]);
        free(c->snap[a]);
        c->buf[a] = c->snap[a] = NULL;
    }
}

static inline void audit_apply(audit_call *c, const audit_mut *m)
{
    switch (m->kind) {
    case MK_INT: c->iv[m->arg] = m->ival; break;
    case MK_IADD: c->iv[m->arg] += m->ival; break;
    case MK_DBL: c->dv[m->arg] = m->dval; break;
    case MK_NULL: c->pv[m->arg] = NULL; break;
    case MK_ELEM: ((double *)c->buf[m->arg])[m->ival] = m->dval; break;
    case MK_IELEM: ((int *)c->buf[m->arg])[0] = (int)m->ival; break;
    }
}

/* Record what a failed call must leave untouched. */
static inline void audit_snapshot(audit_call *c)
{
    for (int a = 0; a < c->nargs; a++) {
        if ((c->type[a] == AT_PD || c->type[a] == AT_PI) && !c->isconst[a] && c->buf[a]) {
            free(c->snap[a]);
            c->snap[a] = malloc(c->nbytes[a]);
            if (!c->snap[a])
                exit(2);
            memcpy(c->snap[a], c->buf[a], c->nbytes[a]);
        } else if (c->type[a] == AT_H && !c->isconst[a] && c->buf[a])
            audit_hstate(c->hkind[a], c->buf[a], c->hstate[a]);
    }
}

/* The first argument changed since audit_snapshot (its index), or -1,
 * skipping the arguments whose bit is set in except. A handle output must
 * be NULL after a failure. */
static inline int audit_changed_but(const audit_call *c, int failed, unsigned long except)
{
    for (int a = 0; a < c->nargs; a++) {
        if (except >> a & 1)
            continue;
        if (c->snap[a] && memcmp(c->snap[a], c->buf[a], c->nbytes[a]) != 0)
            return a;
        if (c->type[a] == AT_H && !c->isconst[a] && c->buf[a] && !c->consumed[a]) {
            double st[64];
            audit_hstate(c->hkind[a], c->buf[a], st);
            if (memcmp(st, c->hstate[a], sizeof st) != 0)
                return a;
        }
        if (failed && c->type[a] == AT_HO && c->pv[a] && *(igea_rls **)c->buf[a] != NULL)
            return a;
    }
    return -1;
}

static inline int audit_changed(const audit_call *c, int failed)
{
    return audit_changed_but(c, failed, 0);
}

/* The same for a call of f that returned st < 0: a progress output may
 * tell how far a call got when it failed on the data (st <= -1000). */
static inline int audit_changed_after(const audit_fn *f, const audit_call *c, int st)
{
    return audit_changed_but(c, 1, st <= -1000 ? f->progress : 0);
}

/* The first writable double array holding a NaN after a successful call
 * (its index), or -1; arguments whose nan_ok bit is set may hold NaN. */
static inline int audit_nan_output(const audit_call *c, unsigned long nan_ok)
{
    for (int a = 0; a < c->nargs; a++) {
        if (c->type[a] != AT_PD || c->isconst[a] || !c->buf[a] || (nan_ok >> a & 1))
            continue;
        const double *x = (const double *)c->buf[a];
        for (size_t i = 0; i < c->nbytes[a] / sizeof(double); i++)
            if (isnan(x[i]))
                return a;
    }
    return -1;
}

/* Results of a successful call, for bitwise comparison: the content of
 * every writable buffer and the state of every handle (an output handle's
 * state, not its address). Returns a malloc'ed block of *len bytes. */
static inline unsigned char *audit_results(const audit_call *c, size_t *len)
{
    size_t n = 0;
    for (int a = 0; a < c->nargs; a++)
        if ((c->type[a] == AT_PD || c->type[a] == AT_PI) && !c->isconst[a] && c->buf[a])
            n += c->nbytes[a];
        else if (c->type[a] == AT_H || c->type[a] == AT_HO)
            n += 64 * sizeof(double);
    unsigned char *r = malloc(n ? n : 1), *p = r;
    if (!r)
        exit(2);
    for (int a = 0; a < c->nargs; a++)
        if ((c->type[a] == AT_PD || c->type[a] == AT_PI) && !c->isconst[a] && c->buf[a]) {
            memcpy(p, c->buf[a], c->nbytes[a]);
            p += c->nbytes[a];
        } else if (c->type[a] == AT_H || c->type[a] == AT_HO) {
            double st[64];
            const igea_rls *h = NULL;
            if (c->type[a] == AT_H && !c->consumed[a])
                h = (const igea_rls *)c->buf[a];
            else if (c->type[a] == AT_HO && c->buf[a] && *(igea_rls **)c->buf[a] != AUDIT_BAD_HANDLE)
                h = *(igea_rls **)c->buf[a];
            audit_hstate(c->hkind[a], h, st);
            memcpy(p, st, sizeof st);
            p += sizeof st;
        }
    *len = n;
    return r;
}

/* ---- the expected-failure list ---------------------------------------- */

/* known_defects.txt: one entry per line, "ID | what happens"; '#' starts a
 * comment line. ID is the suite's name of a check, e.g.
 * "invalid igea_regress_ls lda=m-1" or "oom igea_regress_ridge". */
typedef struct {
    char id[160];
    char what[400];
    int seen;
} audit_known;

static inline int audit_read_known(const char *path, audit_known *k, int cap)
{
    FILE *f = fopen(path, "r");
    int n = 0;
    char line[600];
    if (!f)
        return 0;
    while (n < cap && fgets(line, sizeof line, f)) {
        char *bar, *e;
        if (line[0] == '#' || line[0] == '\n')
            continue;
        line[strcspn(line, "\n")] = 0;
        bar = strchr(line, '|');
        if (bar)
            *bar = 0;
        for (e = line + strlen(line); e > line && e[-1] == ' '; e--)
            e[-1] = 0;
        memcpy(k[n].id, line, strlen(line) < sizeof k[n].id ? strlen(line) + 1 : sizeof k[n].id);
        k[n].id[sizeof k[n].id - 1] = 0;
        if (bar) {
            const char *w = bar + 1 + (bar[1] == ' ');
            size_t l = strlen(w) < sizeof k[n].what - 1 ? strlen(w) : sizeof k[n].what - 1;
            memcpy(k[n].what, w, l);
            k[n].what[l] = 0;
        } else
            k[n].what[0] = 0;
        k[n].seen = 0;
        n++;
    }
    fclose(f);
    return n;
}

/* Glob match where only '*' is special (any run of characters). */
static inline int audit_glob(const char *pat, const char *s)
{
    if (!*pat)
        return !*s;
    if (*pat == '*')
        return audit_glob(pat + 1, s) || (*s && audit_glob(pat, s + 1));
    return *s == *pat && audit_glob(pat + 1, s + 1);
}

/* The entry for check id that failed with message msg. An ID may hold '*'
 * (any characters); a "[msg: TEXT]" in the description restricts the
 * entry to failures whose message contains TEXT. */
static inline audit_known *audit_find_known(audit_known *k, int n, const char *id,
                                            const char *msg)
{
    for (int i = 0; i < n; i++) {
        if (!audit_glob(k[i].id, id))
            continue;
        const char *want = strstr(k[i].what, "[msg: ");
        if (msg && want) {
            char t[200];
            const char *e = strchr(want + 6, ']');
            size_t tl = e ? (size_t)(e - want - 6) : strlen(want + 6);
            if (tl >= sizeof t)
                tl = sizeof t - 1;
            memcpy(t, want + 6, tl);
            t[tl] = 0;
            if (!strstr(msg, t))
                continue;
        }
        return &k[i];
    }
    return NULL;
}

/* Print the entries of the list that no check matched (a stale entry,
 * or one of a suite that did not run: filtered by the id's prefix). */
/* A failed check: "KNOWN DEFECT" (counted in *hit) when the list has it,
 * else "FAIL" (counted in *failed). */
static inline void audit_fail(audit_known *k, int n, const char *id, const char *msg, int *hit,
                              int *failed)
{
    audit_known *e = audit_find_known(k, n, id, msg);
    if (e) {
        e->seen = 1;
        (*hit)++;
        printf("KNOWN DEFECT: %s: %s\n", id, msg);
    } else {
        (*failed)++;
        printf("FAIL: %s: %s\n", id, msg);
    }
}

static inline void audit_unseen(const audit_known *k, int n, const char *prefix)
{
    for (int i = 0; i < n; i++)
        if (!k[i].seen && strncmp(k[i].id, prefix, strlen(prefix)) == 0)
            printf("NOW PASSES (drop it from known_defects.txt): %s\n", k[i].id);
}

#endif
