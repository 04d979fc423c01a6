/* accel_internal.h - helpers shared by the accel_*.c files (not exported). */
#ifndef IGEA_ACCEL_INTERNAL_H
#define IGEA_ACCEL_INTERNAL_H

/* sin and cos of an angle in degrees, exact at multiples of 90. */
void igea__accel_sincosd(double deg, double *s, double *c);
/* Design row at one angle: IGEA_ACCEL_SINGLE (5), IGEA_ACCEL_DUAL (9), or
 * IGEA_ACCEL_JOINT: the joint model's tangential row (10). */
void igea__accel_row(int model, double deg, double *row);
/* Singular values s[N], right singular vectors V (N x N) and rank of the
 * m x N matrix A (N <= 10). Returns 0, IGEA_ENOMEM, IGEA_ELAPACK. */
int igea__accel_svd(int m, int N, const double *A, int lda, double *s, double *V, int *rank);
/* Canonical orthonormal null basis of V[:, r:] into nb (N x N). */
void igea__accel_null(int N, int r, const double *V, double *nb);
/* Norm of the projection of c[N] on the null space V[:, r:]. */
double igea__accel_loading(int N, int r, const double *V, const double *c);

#endif
