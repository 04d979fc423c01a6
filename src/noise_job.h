/* noise_job.h - the state of igea_noise_eqerr shared by noise_job.c (the
 * job, its outer iteration, the robust route) and noise_reml.c (phi and
 * the group scales by restricted maximum likelihood). Not installed. */
#ifndef IGEA_NOISE_JOB_H
#define IGEA_NOISE_JOB_H

#include "igea/noise.h"

/* The rows the robust route rejected, as additive outliers (docs/eqerr.md,
 * "Robust route"): rejected raw row i is a nuisance column of the model, its
 * indicator e_i, whose whitened image d_i = T L^-1 e_i lives on the rows of
 * its epoch (the axes where L_e^-1 e_a is not 0) and of the next p epochs of
 * its segment (the structural support, whatever the value there). Images
 * sharing a whitened row form a block; each block's images are
 * orthonormalised, D_b = Q_b R_b, and projected out of the whitened rows and
 * the sums: the same fit as the epoch left out of the AR model. */
typedef struct {
    int k, nblk;   /* dummies, blocks */
    int *dblk;     /* k: the dummies (indices into the job's rej) block by block */
    int *boff;     /* nblk + 1: block b's dummies are dblk[boff[b] .. boff[b + 1]) */
    int *roff;     /* nblk + 1: block b's whitened rows are rows[roff[b] .. roff[b + 1]) */
    int *rows;     /* ascending within a block */
    int *rblk;     /* m: the block of each whitened row, -1 outside every block */
    int *rpos;     /* m: its position in the block's rows */
    size_t *qoff;  /* nblk + 1: block b's Q_b (nr x kb, ld nr) at Q + qoff[b] */
    size_t *roff2; /* nblk + 1: its R_b (kb x kb upper, ld kb) at R + roff2[b] */
    double *Q, *R;
    double *Z;     /* block b: kb x (Nt + 1) (ld kb) at Z + boff[b] (Nt + 1): Q_b' V0 */
    double *V0;    /* block b: nr x (Nt + 1) (ld nr) at V0 + roff[b] (Nt + 1): the rows
                      before the projection */
    double logdet; /* sum_b log det R_b (R_b's diagonal > 0) */
} igea__ndum;

/* The whitened rows and sums at one phi. */
typedef struct {
    double *V;              /* m x (Nt + 1): stage 2, the dummies projected out */
    double *A, *b, *wtw;    /* G x Nt^2, G x Nt, 2 G: their group sums */
    double *A0, *b0, *wtw0; /* the sums before the projection */
    igea__ndum d;
    double phi[9];          /* the phi of the whitening */
    int valid;
} igea__nstate;

typedef struct {
    int m, N, Nt, G, p, nb, M;
    const int *group;
    const double *cov;   /* the epochs' 3 x 3 covariances or NULL (sigmas) */
    double *U, *V;       /* m x (Nt + 1): stage 1 and stage 2 whitened rows (V: the
                            current state's) */
    double *A, *b, *wtw; /* G x Nt^2, G x Nt, 2 G: the current state's sums */
    double *c, *red, *x; /* G, G, Nt */
    double *work;        /* scratch of the snooping and VCE: 2 Nt^2 + 4 Nt + G */
    double *T, *q;       /* m x Nt and m: snooping */
    double phi[9], se[9];
    int *mask;           /* m: 1 for a rejected raw row */
    int *mask1;          /* m: 1 for a stage-1 row a rejected raw row touches */
    int *rej;            /* the rejected raw rows, ascending (nrej) */
    int *segpos;         /* M: the epoch's position in its segment */
    double *W1;          /* m x 3: L_e^-1 e_a (column a) per epoch, or NULL (sigmas:
                            the stage-1 image of e_i is e_i up to a scale) */
    igea__nstate st[2];  /* the current state (cur) and a trial one */
    int cur;
    double *row_w;
    int nrej, maxrej;
    double kcrit;
    double *reml_se; /* G: se of c_g from the joint information (REML), or NULL */
    /* the REML iteration's curvature (3p x 3p, BFGS from the expected
     * information) and the previous point and profile score */
    int reml_have;
    double reml_H[81], reml_z[9], reml_s[9]; /* in z = atanh(partial autocorrelations) */
} igea__njob;

/* The coefficients of one axis's whitening (or of its derivative by one
 * phi): row t < p of a segment is sum_s head[t][s] u_s, a later row t is
 * diag u_t + sum_l lag[l] u_(t-l) (l = 1..p). */
typedef struct {
    double head[IGEA_NOISE_AR_MAX][IGEA_NOISE_AR_MAX];
    double diag, lag[IGEA_NOISE_AR_MAX + 1];
} igea__arrow;

/* The whitening coefficients of the three axes at phi (3 p; p = 0: the
 * identity). Returns 0 or 1 (an axis not stationary). */
int igea__noise_arrows(int p, const double *phi, igea__arrow co[3]);

/* The whitened image of the indicator of raw row i under the coefficients
 * co: its structural support (rows ascending, at most 3 (p + 1)) into
 * rows[] and the values into val[]. Returns the count. */
int igea__noise_ao_image(const igea__njob *j, const igea__arrow co[3], int i, int *rows,
                         double *val);

/* Project the job's dummies (j->rej) at the state's phi out of s->V and
 * the sums: restores the rows the previous projection changed, rebuilds
 * the blocks (noise.c). Returns 0 or a failure. */
int igea__noise_dummies(const igea__njob *j, igea__nstate *s);
void igea__ndum_free(igea__ndum *d);

/* The state at phi: stage 2 of the job's stage-1 rows U (all rows) into
 * s->V and s->A0, b0, wtw0, then the dummies projected out. Returns 0,
 * IGEA_EDOMAIN (phi not stationary) or a failure. */
int igea__noise_state(const igea__njob *j, const double *phi, igea__nstate *s);

/* Make state k the job's current one (j->V, A, b, wtw). */
void igea__noise_use(igea__njob *j, int k);

/* The pseudo-inverse factor of N = sum A_g / c_g (noise.c): F (N x r) with
 * N^+ = F F'; Nt (N x N) and lam (N) scratch. Returns the rank r or a
 * failure < 0. */
int igea__noise_pinv_factor(int N, int G, const double *A, int lda, const double *c,
                            double *Nt, double *lam, double *F);

/* One quasi-Newton step of the REML of phi at the job's group scales
 * (after the Helmert scales of the current sums, so that the score is
 * the profile's): the step H^-1 score in z (partial autocorrelations), H
 * the expected information of the profile, then BFGS-updated from the
 * previous step's score (reml_have 0 restarts from the expected
 * information), at most 1 in z, halved until the profile restricted
 * likelihood rises (Armijo) or the change of phi is below tol / 100 (no
 * move); the accepted point's state becomes the job's. *d the largest
 * change of phi. Returns 0 or a failure. */
int igea__noise_reml_step(igea__njob *j, double tol, double *d);

/* Standard errors of phi (into j->se) and of the scales (into
 * j->reml_se) from the inverse of the observed REML information of phi and
 * the scales together, at the job's final phi and scales. Returns 0 or a
 * failure. */
int igea__noise_reml_se(igea__njob *j);

#endif
