/* sim_model.h - the simulation model and the flight generator's parts
 * (sim.c), shared with the batched Monte Carlo (sim_batch.c). */
#ifndef IGEA_SIM_MODEL_H
#define IGEA_SIM_MODEL_H

#include <math.h>
#include <pthread.h>

#include <gsl/gsl_rng.h>

#include "igea/sim.h"

/* The Monte Carlo's set-up of a model (sim.c mc_setup): Sw = K^-1/2 S D
 * (m x N, K the stated sigmas squared, D the specs), A = Sw^T Sw (N x N),
 * A = V diag(lam0) V^T (V N x N, lam0 N descending), Q = Sw V (m x N), L =
 * V diag(lam0) (N x N): one allocation of (2 m + 3 N + 1) N doubles. */
typedef struct {
    double *Sw, *A, *V, *lam0, *Q, *L;
} igea__sim_setup;

/* The set-up kept by the first Monte Carlo run of a model that completed,
 * for the later runs (data NULL until then; read and published under
 * lock, never changed once published, dropped by the setters of sigma and
 * specs, which no run may overlap). */
typedef struct {
    pthread_mutex_t lock;
    double *data;
} igea__sim_cache;

struct igea_sim_model {
    int m, N;
    double *S;     /* m x N, ld m */
    double *sigma; /* m stated sigmas, growth applied */
    double *spec;  /* N specs (1 where none) */
    int has_spec;
    double *x_value; /* N, with x_fixed: the fixed terms */
    int *x_fixed;
    int has_truth;
    double opts[IGEA_SIM_OPT_LEN];
    /* trajectory models: the nonlinear truth */
    int system, nsamp, nepochs, has_axes, axes[6], nonlinear;
    double *traj, *epochs; /* nsamp x 11 (ld nsamp), nepochs */
    int *terms;            /* N codes */
    igea__sim_cache *mc;   /* the Monte Carlo's set-up (above) */
};

/* Point s at the set-up of a model of m x N held in data. */
void igea__sim_setup_map(igea__sim_setup *s, double *data, int m, int N);

/* The 32-bit GSL seed of flight `flight` of stream `seed` (SplitMix64). */
unsigned long igea__sim_flight_seed(int seed, int flight);
/* The model's generator type (IGEA_SIM_OPT_GENERATOR). */
const gsl_rng_type *igea__sim_rng_type(const igea_sim_model *c);
/* Seed r for the flight and draw its truth: x (N, fixed terms kept) and
 * xs = x * spec (N). The first draws of the flight's stream. */
void igea__sim_draw_truth(const igea_sim_model *c, gsl_rng *r, int seed, int flight,
                          double *x, double *xs);
/* Add the flight's tracking noise to dw (m): the draws after the truth. */
void igea__sim_draw_noise(const igea_sim_model *c, gsl_rng *r, double *dw);

/* The draws on igea's keyed streams (IGEA_SIM_XOSHIRO, sim_batch.c): the
 * truth as igea__sim_draw_truth, st keyed by (seed, flight); the plain
 * noise (white, AR(1), growth, outliers) added to dw: one normal per row,
 * then a uniform and a normal per row only when outlier_prob > 0. The
 * state is a gsl_rng's of type igea__xoshiro_type (void * here). */
void igea__sim_truth_xoshiro(const igea_sim_model *c, void *st, int seed, int flight,
                             double *x, double *xs);
void igea__sim_noise_xoshiro(const igea_sim_model *c, void *st, double *dw);

/* The flights of a Monte Carlo run shared out among its threads: each
 * takes the next consecutive flights when it is free (so a thread slowed
 * by others' load takes fewer), in portions that shrink towards the end
 * (about remaining / (2 nthreads), a multiple of unit, at most max) so
 * that the threads finish together. A flight's result depends on (seed,
 * flight) only, never on the thread or portion that ran it. A failure
 * stops the taking; the status returned is the one of the lowest failing
 * flight, which every thread count finds (the portions are taken in
 * flight order and each is run up to its own first failure). */
typedef struct {
    pthread_mutex_t lock;
    int next, nflights, nthreads, stop;
    int fail_flight, fail; /* the lowest failing flight and its status */
} igea__sim_queue;

/* Returns 0 or IGEA_ENOMEM (the mutex). */
int igea__sim_queue_init(igea__sim_queue *q, int nflights, int nthreads);
void igea__sim_queue_destroy(igea__sim_queue *q);
/* The next portion: its first flight in *f0 and its length (0: none left,
 * or a failure). */
int igea__sim_queue_take(igea__sim_queue *q, int max, int unit, int *f0);
/* Flight f failed with status st (< 0). */
void igea__sim_queue_fail(igea__sim_queue *q, int f, int st);

/* The largest |z_i| over the tested components (reject[i] >= 0) of a
 * judged flight: IGEA_SIM_MC_TABLE_ZMAX. */
static inline double igea__sim_zmax(int N, const double *z, const int *reject)
{
    double zm = 0.0;
    for (int i = 0; i < N; i++)
        if (reject[i] >= 0 && fabs(z[i]) > zm)
            zm = fabs(z[i]);
    return zm;
}

/* Q = Sw V of a set-up by the calls of sim_batch.c (row segments of
 * MB_ROWS), on the calling thread. */
void igea__sim_setup_q(const igea__sim_setup *s, int m, int N);

/* The set-up of s but Q (sim.c's mc_setup), zeros its scratch. */
typedef int (*igea__sim_setup_fn)(const igea_sim_model *c, const igea__sim_setup *s,
                                  double *zeros);

/* The batched Monte Carlo (sim_batch.c): flights first .. first + nflights
 * - 1 judged on the stated K common to them, in blocks of at most `block`
 * flights (rounded up to a multiple of 32), on nthreads threads, with the
 * set-up s: when setup is not NULL, the calling thread runs setup(c, s,
 * zeros) first while the other threads draw their first block (a failure
 * of it is the result); then its Q is computed on the threads unless
 * have_q. The per-flight outputs chi2, scale, zmax, fsize (the overall
 * size), dof, nrej, status (nflights each, as mc_judge writes them) and
 * the component counts cnt (tested then rejected, N each, added to).
 * Returns 0 or a failure as mc_judge's or setup's. */
int igea__sim_mc_batch(const igea_sim_model *c, const igea__sim_setup *s,
                       igea__sim_setup_fn setup, double *zeros, int have_q,
                       const double *eqo, int seed, int first, int nflights,
                       int nthreads, int block, double *chi2, double *scale, double *zmax,
                       double *fsize, int *dof, int *nrej, int *status, int *cnt);

#endif
