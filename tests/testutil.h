/* tests/testutil.h - helpers shared by the cmocka suites. */
#ifndef IGEA_TESTUTIL_H
#define IGEA_TESTUTIL_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

/* cmocka 1.1.5's assert_float_equal casts to float: this one does not.
 * Passes when |got - want| <= rtol * max(|want|, tiny) (+ atol floor). */
#define assert_close(got, want, rtol) \
    assert_close_at((got), (want), (rtol), 0.0, __FILE__, __LINE__)
#define assert_close_abs(got, want, rtol, atol) \
    assert_close_at((got), (want), (rtol), (atol), __FILE__, __LINE__)

static inline void assert_close_at(double got, double want, double rtol,
                                   double atol, const char *file, int line)
{
    double tol = rtol * fabs(want) + atol;
    if (!(fabs(got - want) <= tol) &&
        !(isinf(want) && got == want)) {
        char msg[256];
        snprintf(msg, sizeof msg,
                 "got %.17g, want %.17g (rel err %.3g, rtol %.3g, atol %.3g)",
                 got, want, fabs(got - want) / (fabs(want) > 0 ? fabs(want) : 1.0),
                 rtol, atol);
        print_error("%s\n", msg);
        _fail(file, line);
    }
}

/* Fill n doubles with NaN (to detect reads of leading-dimension padding). */
static inline void fill_nan(double *x, size_t n)
{
    for (size_t i = 0; i < n; i++)
        x[i] = NAN;
}

/* Fill with a recognisable sentinel, to check outputs stay untouched. */
#define SENTINEL 12345.678
static inline void fill_sentinel(double *x, size_t n)
{
    for (size_t i = 0; i < n; i++)
        x[i] = SENTINEL;
}
static inline int all_sentinel(const double *x, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (x[i] != SENTINEL)
            return 0;
    return 1;
}

#endif
