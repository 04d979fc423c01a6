/* src/inserr_int.h - checks and the RK4 step shared by inserr.c and inserr_li.c (private:
 * not installed). */
#ifndef IGEA_INSERR_INT_H
#define IGEA_INSERR_INT_H

/* A 15 x 15 initial covariance: 0, IGEA_ENONFINITE, IGEA_ENONPOSITIVE (a
 * negative diagonal) or IGEA_EDOMAIN (not symmetric to 1e-12 relative). */
int igea__inserr_check_p0(const double *P0);

/* One classical RK4 step over h of the 15-state error model y' = F y
 * (m = 15) or of its covariance P' = F P + P F^T + Q (m = 225, Q 15 x 15
 * symmetric), F and Q row-major; y updated in place. */
void igea__inserr_rk4(const double *F, const double *Q, int m, double h, double *y);

/* The stationary standard deviation s = GM_OF_B B of the Gauss-Markov bias
 * whose Allan deviation peaks at the flicker floor of bias instability B
 * [D]: sqrt(2 ln 2 / pi) over the peak of a unit-variance GM's Allan
 * deviation, max over x = tau / T of sqrt((2 / x^2)(x - (3 - 4 e^-x +
 * e^-2x) / 2)) = 0.6173642831 at x = 1.8926 (scipy's bounded Brent
 * minimisation). */
#define IGEA__INSERR_GM_OF_B (0.6642824702679601 / 0.6173642831444414)

/* The longest Runge-Kutta step that the Gauss-Markov bias states of
 * correlation times tc[2] (0: none) allow: a quarter of the shortest
 * positive one, HUGE_VAL without any [D]. RK4 on d(b)/dt = -b / T diverges
 * for steps beyond 2.785 T and keeps e^(-h / T) to (h / T)^5 / 120 of it
 * (8e-6 at T / 4); the steps of igea_inserr_* (opts' STEP) and of the
 * telemetry intervals of igea_inserr_li_* are cut to it. */
double igea__inserr_gm_step(const double *tc);

/* The coefficient arrays acc, gyro (IGEA_INSERR_NOISE_LEN each): 0,
 * IGEA_ENONFINITE or IGEA_ENONPOSITIVE. */
int igea__inserr_noise_args(const double *acc, const double *gyro);

/* The split of IEEE Std 952 coefficients into the two runs of the noise
 * covariance: qw (IGEA_INSERR_NQ) the white and random-walk densities N^2,
 * K^2; qg the Gauss-Markov driving densities 2 s^2 / T in the bias slots
 * and P0g (15 x 15, zeroed by the caller) its stationary diag(s^2) on the
 * bias states; *any = 1 when some B > 0. tc[2] the accelerometer and gyro
 * correlation times; IGEA_EDOMAIN for a B > 0 whose tc is 0. */
int igea__inserr_noise_split(const double *tc, const double *acc, const double *gyro,
                             double *qw, double *qg, double *P0g, int *any);

#endif
