/* src/rotation.h - quaternion, direction-cosine and rotation-vector
 * kernels, and the trajectory checks, shared by envfun.c and sim.c
 * (private: not installed).
 * Matrices are row-major 3x3; quaternions scalar first, body -> frame. */
#ifndef IGEA_ROTATION_H
#define IGEA_ROTATION_H

/* c = a x b (c may not alias a or b). */
void igea__cross(const double *a, const double *b, double *c);

/* Direction cosine matrix C (v_a = C v_b) of the unit quaternion q. */
void igea__quat_dcm(const double *q, double *C);

/* The same of q / |q| (|q| > 0). */
void igea__quat_dcm_unit(const double *q, double *C);

/* q <- q * exp(rotation vector v / 2), normalised. */
void igea__quat_rotate(double *q, const double *v);

/* c = a b (c may alias a or b). */
void igea__m3_mul(const double *a, const double *b, double *c);

/* y = a x (trans 0) or a^T x (trans 1); y may alias x. */
void igea__m3_vec(const double *a, const double *x, double *y, int trans);

/* R = exp([v x]) (Rodrigues). */
void igea__m3_exp(const double *v, double *R);

/* Arguments 1-4 of a trajectory call (system, nsamp >= 2, traj, ldt >=
 * nsamp): 0 or -i. */
int igea__traj_args(int system, int nsamp, const double *traj, int ldt);

/* Times of a trajectory (nsamp x 11, ld ldt, finite) and its epochs: 0, 1
 * (t not strictly increasing), 2 (epochs decreasing or outside [t_0,
 * t_last]). */
int igea__traj_times(int nsamp, const double *traj, int ldt, int nepochs,
                     const double *epochs);

/* Squared norm of the quaternion of sample k. */
double igea__traj_qnorm2(const double *traj, int ldt, int k);

#endif
