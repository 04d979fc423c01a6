/* sim_noise.h - the simulator's noise models (sim_noise.c), for sim.c. */
#ifndef IGEA_SIM_NOISE_H
#define IGEA_SIM_NOISE_H

#include <gsl/gsl_rng.h>

/* 0 or 1 + the first invalid slot among IGEA_SIM_OPT_AR2 .. JUDGE_NOISE. */
int igea__sim_noise_check(const double *o);
/* 1 when those slots leave the seed's white noise (the old generator). */
int igea__sim_noise_plain(const double *o);
/* Group (0 or 1) of epoch e of M. */
int igea__sim_group_of(const double *o, int M, int e);
/* Cholesky factor (row-major, lower) of epoch e's 3 x 3 correlation. */
void igea__sim_corr_chol(const double *o, int M, int e, double L[9]);
/* The noise of a flight added to dw (m rows), sigma the stated row sigmas. */
void igea__sim_noise_rows(const double *o, const double *sigma, int m, gsl_rng *r,
                          double *dw);
/* 1 when the Monte Carlo judges with igea_noise_eqerr. */
int igea__sim_noise_judged(const double *so, const double *eqo);
/* What the judge is told: cov (6 per epoch, when the return is 1), group
 * labels (M), the number of groups, phi (3 p, the true one, used when the
 * eqerr options give phi). */
int igea__sim_judge_stated(const double *so, const double *eqo, int m, const double *sigma,
                           double *cov, int *group, int *ngroups, double *phi);

#endif
