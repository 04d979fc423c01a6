/* stability_internal.h - what the stability sources share (not exported). */
#ifndef IGEA_STABILITY_INTERNAL_H
#define IGEA_STABILITY_INTERNAL_H

/* Greenhall and Riley's EDF (PTTI 2003) of a difference variance: noise
 * exponent a (-2 .. 2), difference order d (2 Allan, 3 Hadamard), averaging
 * factor m, N phase points, overlapping (stride m) or not, modified (F = 1)
 * or not (F = m). stability_dev.c. */
double igea__stability_edf_greenhall(int a, int d, double m, double N, int overlapping,
                                     int modified);

#endif
