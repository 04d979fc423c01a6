/*
 * igea/common.h - status codes, version, library-wide conventions.
 *
 * What is not declared in the igea headers is not part of the API.
 *
 * Conventions (every module):
 *  - Matrices are column-major with an explicit leading dimension, sizes
 *    are int, vectors are contiguous: a Fortran caller passes its arrays
 *    as they are.
 *  - Every routine returns an int status like LAPACK's INFO: 0 success;
 *    -i argument i (1-based) is invalid; IGEA_E* (-1010 and below) a
 *    library-wide failure; > 0 a routine's own documented outcome.
 *    Outputs are untouched when a call fails (status < 0).
 *  - The library never prints, never exits or aborts, keeps no global
 *    mutable state and never changes process-wide state: every function is
 *    reentrant and may be called from many threads at once; a handle
 *    belongs to one thread at a time.
 */
#ifndef IGEA_COMMON_H
#define IGEA_COMMON_H

#ifdef __cplusplus
extern "C" {
#endif

#if defined(IGEA_BUILDING) && defined(__GNUC__)
#define IGEA_API __attribute__((visibility("default")))
#else
#define IGEA_API
#endif

/* The version, written here only: the Makefile (library file name,
 * igea.pc) and the Python package (python/igea/_capi.py) read these three
 * lines. The soname is libigea.so.IGEA_VERSION_MAJOR. */
#define IGEA_VERSION_MAJOR 1
#define IGEA_VERSION_MINOR 1
#define IGEA_VERSION_PATCH 0
#define IGEA_VERSION_NUMBER                                                  \
    (IGEA_VERSION_MAJOR * 10000 + IGEA_VERSION_MINOR * 100 + IGEA_VERSION_PATCH)
#define IGEA_VERSION_STR_(a, b, c) #a "." #b "." #c
#define IGEA_VERSION_XSTR_(a, b, c) IGEA_VERSION_STR_(a, b, c)
#define IGEA_VERSION_STRING                                                  \
    IGEA_VERSION_XSTR_(IGEA_VERSION_MAJOR, IGEA_VERSION_MINOR, IGEA_VERSION_PATCH)

/* Layout of a matrix argument, for every function that takes one:
 * IGEA_COLMAJOR, the m x n matrix column-major with ld >= max(1, m)
 * (Fortran, LAPACK); IGEA_ROWMAJOR, the array holds its transpose, i.e. the
 * matrix stored row by row with ld >= max(1, n) (C, numpy, .npy files). */
#define IGEA_COLMAJOR 0
#define IGEA_ROWMAJOR 1

/* Status codes. 0 is success, -i names the invalid argument i. */
#define IGEA_OK 0
#define IGEA_ENOMEM (-1010)       /* out of memory */
#define IGEA_ENONFINITE (-1011)   /* an input holds NaN or Inf */
#define IGEA_ENONPOSITIVE (-1012) /* a variance or sigma is zero or negative */
#define IGEA_ESINGULAR (-1013)    /* a matrix is singular or not positive definite */
#define IGEA_ERANK (-1014)        /* rank-deficient where full rank is needed */
#define IGEA_ENOCONV (-1015)      /* an iteration did not converge */
#define IGEA_ELAPACK (-1016)      /* LAPACK reported a failure */
#define IGEA_EDOMAIN (-1017)      /* a value is outside its mathematical domain */
#define IGEA_ENOTESTABLE (-1018)  /* no component is precise enough to test */
#define IGEA_EDEPENDENT (-1019)   /* pooled flights are not independent */
#define IGEA_EEMPTY (-1020)       /* no data (zero rows or zero terms) */
#define IGEA_ERANGE (-1021)       /* a sigma is below IGEA_SIGMA_MIN (1/sigma^2 overflows) */
#define IGEA_EOVERFLOW (-1022)    /* a result overflowed or underflowed: rescale */
#define IGEA_EFORMAT (-1023)      /* an input file is not what its format says (igea/io.h) */
#define IGEA_EREAD (-1024)        /* an input file cannot be opened or read (igea/io.h) */
#define IGEA_ETEMPFILE (-1025)    /* a temporary copy of an input cannot be written */
#define IGEA_EVERDICT (-1027)     /* the verdict rule cannot be evaluated for this many
                                   * tested components (> IGEA_STATS_UNION_N_MAX) */
#define IGEA_DW_ESPAN (-1031)     /* a tracking epoch is outside the telemetry span */
#define IGEA_DW_ETRACK (-1032)    /* tracking epochs are not strictly increasing */
#define IGEA_DW_ETELEMETRY (-1033) /* telemetry times are not strictly increasing */

/* Smallest standard deviation (a sigma whose inverse square weights the
 * data) accepted: 2^-511, about 1.5e-154, where 1/sigma^2 = 2^1022 is still
 * finite. A positive sigma below it (a denormal one, say) gives IGEA_ERANGE
 * where the weight would be Inf. A large sigma is accepted: its weight
 * 1/sigma^2 may round to 0, which removes the row. */
#define IGEA_SIGMA_MIN 1.4916681462400413e-154 /* 2^-511 */

/* Static English text for a status code; never NULL. */
IGEA_API const char *igea_strerror(int status);

/* What kind of failure a status is, for a front end that maps statuses to
 * its own terms (the driver's exit codes, Python's exception classes):
 *   IGEA_STATUS_OK        status >= 0 (a success; positive codes are results)
 *   IGEA_STATUS_ARGUMENT  -999 .. -1: argument -status is invalid
 *   IGEA_STATUS_DATA      the values passed cannot be used for the job: NaN
 *                         or Inf, a sigma <= 0 or too small, a singular or
 *                         rank-deficient design, nothing testable, empty or
 *                         dependent data, a value outside its domain, a
 *                         malformed input file, records out of order
 *   IGEA_STATUS_INPUT     an input file cannot be opened or read
 *   IGEA_STATUS_FAILURE   the computation failed on valid data: no
 *                         convergence, LAPACK, a size the method cannot
 *                         evaluate, or an unknown status
 *   IGEA_STATUS_RESOURCE  memory or temporary storage ran out */
#define IGEA_STATUS_OK 0
#define IGEA_STATUS_ARGUMENT 1
#define IGEA_STATUS_DATA 2
#define IGEA_STATUS_INPUT 3
#define IGEA_STATUS_FAILURE 4
#define IGEA_STATUS_RESOURCE 5
IGEA_API int igea_status_class(int status);

/* Modules that take an options array (opts[IGEA_<MODULE>_OPT_LEN]), for
 * igea_opt_name. */
#define IGEA_MODULE_EQERR 1 /* igea/eqerr.h, IGEA_EQERR_OPT_* */
#define IGEA_MODULE_SIM 2   /* igea/sim.h, IGEA_SIM_OPT_* */
#define IGEA_MODULE_IMPACT 10 /* igea/impact.h, IGEA_IMPACT_OPT_* */
#define IGEA_MODULE_TRIAD 11  /* igea/triad.h, IGEA_TRIAD_OPT_* */
#define IGEA_MODULE_INSERR 15 /* igea/inserr.h, IGEA_INSERR_OPT_* */

/*
 * Static name of slot `slot` of module `module`'s options array, as the
 * index macro spells it in lower case ("alpha" for IGEA_EQERR_OPT_ALPHA,
 * "sigma_w" for IGEA_SIM_OPT_SIGMA_W): the name to print for the slot that
 * igea_eqerr_check_opts or igea_sim_check_opts reports (their status minus
 * 1). "reserved" for a slot of the array that has no meaning yet (it must
 * hold a finite value), "" for an unknown module or a slot outside the
 * array. Never NULL.
 */
IGEA_API const char *igea_opt_name(int module, int slot);

/* Enumerations whose codes the library takes or returns as int, for
 * igea_choice_name / igea_choice_code / igea_choice_codes. A name is the
 * code's macro suffix in lower case; the codes are listed in increasing
 * order (bit values for IGEA_CHOICE_RLS_FLAG). */
#define IGEA_CHOICE_EQERR_ROUTE 1        /* igea/eqerr.h IGEA_EQERR_ROUTE_*: eig svd */
#define IGEA_CHOICE_REGRESS_RIDGE_RULE 2 /* igea/regress.h IGEA_REGRESS_RIDGE_*: fixed hkb lw
                                          * gcv loo */
#define IGEA_CHOICE_REGRESS_EBR_RULE 3   /* igea/regress.h IGEA_REGRESS_EBR_*: sc mm ml2 */
#define IGEA_CHOICE_ACCEL_MODEL 4        /* igea/accel.h IGEA_ACCEL_SINGLE, _DUAL: single dual */
#define IGEA_CHOICE_ACCEL_METHOD 5       /* igea/accel.h IGEA_ACCEL_LS, _EBR, _JOINT: ls ebr
                                          * joint */
#define IGEA_CHOICE_REGRESS_METHOD 60    /* igea/regress.h IGEA_REGRESS_METHOD_*: ls ridge pce
                                          * bayes ebr */
#define IGEA_CHOICE_ACCEL_AXIS 41        /* igea/accel.h IGEA_ACCEL_AXIS_*: pa oa */
#define IGEA_CHOICE_IMPACT_MODEL 42      /* igea/impact.h IGEA_IMPACT_KEPLER, _J2: kepler j2 */
#define IGEA_CHOICE_IMPACT_CEP 43        /* igea/impact.h IGEA_IMPACT_CEP_*: sum rms */
#define IGEA_CHOICE_ENVFUN_SYSTEM 6      /* igea/envfun.h IGEA_ENVFUN_STRAPDOWN, _PLATFORM:
                                          * strapdown platform */
#define IGEA_CHOICE_ENVFUN_OUTPUT 7      /* igea/envfun.h IGEA_ENVFUN_VELOCITY, _POSITION,
                                          * _VELOCITY_G, _POSITION_G: velocity position
                                          * velocity_g position_g */
#define IGEA_CHOICE_SIM_GENERATOR 8      /* igea/sim.h IGEA_SIM_MT19937, _RANLXD2, _XOSHIRO:
                                          * mt19937 ranlxd2 xoshiro */
#define IGEA_CHOICE_RLS_VARIANT 9        /* igea/rls.h IGEA_RLS_STANDARD, _ITERATED,
                                          * _POLYNOMIAL: standard iterated polynomial */
#define IGEA_CHOICE_RLS_ANOMALY 10       /* igea/rls.h IGEA_RLS_ANOMALY_*: none replace skip
                                          * isolate */
#define IGEA_CHOICE_RLS_ACTION 11        /* igea/rls.h IGEA_RLS_UPDATED, _FLAGGED, _REPLACED,
                                          * _SKIPPED, _ISOLATED: updated flagged replaced
                                          * skipped isolated */
#define IGEA_CHOICE_RLS_FLAG 12          /* igea/rls.h IGEA_RLS_FLAG_* (bits 1 2 4 8):
                                          * innovation jump missing unused */
#define IGEA_CHOICE_STABILITY_KIND 13    /* igea/stability.h IGEA_STABILITY_ALLAN_*:
                                          * overlapping modified nonoverlapping adev oadev
                                          * mdev tdev hdev ohdev totdev mtotdev ttotdev
                                          * htotdev theo1 mtie tierms theobr theoh */
#define IGEA_CHOICE_STABILITY_NOISE 14   /* igea/stability.h IGEA_STABILITY_NOISE_* (-2 .. 2,
                                          * 99): rwfm ffm wfm fpm wpm auto */
#define IGEA_CHOICE_STATS_SIGMAW_FLAG 15 /* igea/stats.h IGEA_STATS_SIGMAW_*: converged
                                          * not_estimable no_convergence off */
#define IGEA_CHOICE_REDUND_RBD 16        /* igea/redund.h IGEA_REDUND_RBD_*: series parallel
                                          * kofn */
#define IGEA_CHOICE_STATS_VERDICT 17     /* igea/stats.h IGEA_STATS_VERDICT_*: seed chi2
                                          * exact sidak */
#define IGEA_CHOICE_NOISE_AR_METHOD 18   /* igea/noise.h IGEA_NOISE_AR_*: reml ls */
#define IGEA_CHOICE_STABILITY_DATA 35    /* igea/stability.h IGEA_STABILITY_DATA_*: freq phase */
#define IGEA_CHOICE_STABILITY_TAUS 36    /* igea/stability.h IGEA_STABILITY_TAUS_*: octave
                                          * decade all */
#define IGEA_CHOICE_NAV_FRAME 26         /* igea/nav.h IGEA_NAV_ECEF, _LE, _LI: ecef le li */
#define IGEA_CHOICE_NAV_GRAVITY 27       /* igea/nav.h IGEA_NAV_GRAVITY_*: point_mass j2 */
#define IGEA_CHOICE_DW_KIND 28           /* igea/dw.h IGEA_DW_APPARENT, _NAVIGATED: apparent
                                          * navigated */
#define IGEA_CHOICE_DW_FRAME 29          /* igea/nav.h IGEA_NAV_ECEF, _LE: ecef le (the
                                          * frames a tracking record may be in) */
#define IGEA_CHOICE_ACCEL_IEEE_METHOD 70 /* igea/accel.h IGEA_ACCEL_LS, _HARMONIC: ls harmonic
                                          * (igea_accel_ieee_fit) */
#define IGEA_CHOICE_ACCEL_CRIT_MODEL 71  /* igea/accel.h IGEA_ACCEL_SINGLE, _DUAL, _IEEE: single
                                          * dual ieee (igea_accel_criterion) */

/* Static name of code `code` of enumeration `kind` (IGEA_CHOICE_*): "svd"
 * for (IGEA_CHOICE_EQERR_ROUTE, IGEA_EQERR_ROUTE_SVD). "" for an unknown
 * kind or a code outside the enumeration; never NULL. */
IGEA_API const char *igea_choice_name(int kind, int code);

/*
 * The code of the name `name` (as igea_choice_name spells it, exact and
 * case-sensitive) in enumeration `kind`, into *code. Returns 0, or -1 for
 * an unknown kind, -2 for a NULL or unknown name, -3 for a NULL code (*code
 * untouched). The code is an out-argument because some codes are negative
 * (IGEA_STABILITY_NOISE_FFM).
 */
IGEA_API int igea_choice_code(int kind, const char *name, int *code);

/*
 * The codes of enumeration `kind` in their listing order: returns how many
 * there are and writes the first min(count, len) of them to codes (NULL
 * when len is 0). -1 for an unknown kind, -2 for a NULL codes with len > 0,
 * -3 for len < 0.
 */
IGEA_API int igea_choice_codes(int kind, int *codes, int len);

/* IGEA_VERSION_STRING ("1.1.0") and IGEA_VERSION_NUMBER of the library
 * actually linked. */
IGEA_API const char *igea_version(void);
IGEA_API int igea_version_number(void);

/*
 * Optional process-wide set-up for programs that own their process (the
 * driver, the Python package): switches GSL's abort-on-error handler off.
 * The library validates every argument before GSL sees it and does not
 * need this; it exists for hosts that also call GSL themselves. Returns 0.
 */
IGEA_API int igea_init(void);

#ifdef __cplusplus
}
#endif
#endif
