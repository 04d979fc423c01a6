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

#endif
