/* noise_job.h - the state of igea_noise_eqerr shared by noise_job.c (the
 * job, its outer iteration, the robust route) and noise_reml.c (phi and
 * the group scales by restricted maximum likelihood). Not installed. */
#ifndef IGEA_NOISE_JOB_H
#define IGEA_NOISE_JOB_H

#include "igea/noise.h"

typedef struct {
    int m, N, Nt, G, p, nb, M;
    const int *group;
    double *U, *V;       /* m x (Nt + 1): stage 1 and stage 2 whitened rows */
    double *A, *b, *wtw; /* G x Nt^2, G x Nt, 2 G */
    double *c, *red, *x; /* G, G, Nt */
    double *work;        /* scratch of the snooping and VCE: 2 Nt^2 + 4 Nt + G */
    double *T, *q;       /* m x Nt and m: snooping */
    double phi[9], se[9];
    int *mask;
    double *row_w;
    int nrej, maxrej;
    double kcrit;
    double *reml_se; /* G: se of c_g from the joint information (REML), or NULL */
    /* the REML iteration's curvature (3p x 3p, BFGS from the expected
     * information) and the previous point and profile score */
    int reml_have;
    double reml_H[81], reml_z[9], reml_s[9]; /* in z = atanh(partial autocorrelations) */
} igea__njob;

/* Stage 2 (the AR filter at phi, 3 p values) of the job's stage-1 rows U
 * with its mask into V (m x (Nt + 1)) and the group sums A, b, wtw.
 * Returns 0, IGEA_EDOMAIN (phi not stationary) or a failure. */
int igea__noise_stage2(const igea__njob *j, const double *phi, double *V, double *A,
                       double *b, double *wtw);

/* The pseudo-inverse factor of N = sum A_g / c_g (noise.c): F (N x r) with
 * N^+ = F F'; Nt (N x N) and lam (N) scratch. Returns the rank r or a
 * failure < 0. */
int igea__noise_pinv_factor(int N, int G, const double *A, int lda, const double *c,
                            double *Nt, double *lam, double *F);

/* One quasi-Newton step of the REML of phi at the job's group scales
 * (after the Helmert scales of the current sums, so that the score is
 * the profile's): phi += H^-1 score with H the expected information of the
 * profile, then BFGS-updated from the previous step's score (reml_have
 * 0 restarts from the expected information); *d the largest change.
 * Returns 0 or a failure. */
int igea__noise_reml_step(igea__njob *j, double *d);

/* Standard errors of phi (into j->se) and of the scales (into
 * j->reml_se) from the inverse of the observed REML information of phi and
 * the scales together, at the job's final phi and scales. Returns 0 or a
 * failure. */
int igea__noise_reml_se(igea__njob *j);

#endif
