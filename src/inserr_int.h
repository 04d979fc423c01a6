/* src/inserr_int.h - checks shared by inserr.c and inserr_li.c (private:
 * not installed). */
#ifndef IGEA_INSERR_INT_H
#define IGEA_INSERR_INT_H

/* A 15 x 15 initial covariance: 0, IGEA_ENONFINITE, IGEA_ENONPOSITIVE (a
 * negative diagonal) or IGEA_EDOMAIN (not symmetric to 1e-12 relative). */
int igea__inserr_check_p0(const double *P0);

#endif
