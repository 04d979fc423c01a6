/* src/envfun_terms.h - the term catalogue's instrument-error model, shared
 * by envfun.c (the environment functions) and sim.c (the nonlinear truth
 * model). Private; nothing here is API. */
#ifndef IGEA_ENVFUN_TERMS_H
#define IGEA_ENVFUN_TERMS_H

/* Term families. ACC: accelerometer error u per unit coefficient; GYRO:
 * gyro (strapdown) or platform drift u; ATT: initial attitude or
 * alignment e_j; POS0: launch-point error (a rotation of the launch frame);
 * LEVER: lever arm to the tracked point; SIZE: accelerometer displacement
 * (size effect); NONE: not a term. */
enum {
    IGEA__FAM_ACC = 0,
    IGEA__FAM_GYRO,
    IGEA__FAM_ATT,
    IGEA__FAM_POS0,
    IGEA__FAM_LEVER,
    IGEA__FAM_SIZE,
    IGEA__FAM_NONE
};

/* Family of code `term` (IGEA__FAM_NONE for an unknown code). */
int igea__term_family(int term);

/* The axis j of code `term` (0..2; for SIZE the accelerometer j and
 * *k the displacement axis, else *k = -1). */
int igea__term_axis(int term, int *k);

/* 1 if code `term` reads gyro j's output axis O(j). */
int igea__term_uses_out(int term);

/* The nonzero entries of err[nerr] (by term code) sorted into the lists the
 * error simulations apply: acc (ACC and SIZE codes), size (SIZE), gyro
 * (GYRO), each of room IGEA_ENVFUN_TERM_END; *lever 1 if a LEVER code is
 * set; *uses_out 1 if a set code reads a gyro's output axis. Returns 0, or
 * -1 for a set code not valid for system (the lists are then partial). */
int igea__term_lists(int system, int nerr, const double *err, int *acc, int *nacc, int *size,
                     int *nsize, int *gyro, int *ngyro, int *lever, int *uses_out);

/* Unit instrument error u (3) of an ACC or GYRO code from f, w in
 * instrument axes; in/spin/out the gyro axes I(j), S(j), O(j). For SIZE
 * the centripetal part e_j (w x (w x e_k))_j. */
void igea__term_unit(int term, const double *f, const double *w,
                     const int *in, const int *spin, const int *out, double *u);

/* Output axes O(j) of a gyro axis mapping: 0, or -1 where I(j) == S(j)
 * (out[j] is then set to (I(j) + 2) mod 3). */
int igea__out_axes(const int *in, const int *spin, int *out);

/* Launch-frame rotation theta (3) of unit launch-point errors: pos0_x
 * (downrange) -> -e_z / R, pos0_z (cross-range) -> +e_x / R, R = 6371 km;
 * the tracking is read in the assumed frame, v' = exp(-[theta x]) v. */
void igea__pos0_rotation(int term, double *theta);

#endif
