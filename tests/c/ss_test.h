/* Shared includes for the cmocka tests (cmocka needs these before its header). */
#ifndef SS_TEST_H
#define SS_TEST_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>

/* assert |a - b| <= tol, printing the numbers on failure */
#define assert_close(a, b, tol)                                                                              \
    do {                                                                                                     \
        double a_ = (double)(a), b_ = (double)(b), t_ = (double)(tol);                                       \
        if (!(fabs(a_ - b_) <= t_)) {                                                                        \
            fail_msg("%s = %.9g, %s = %.9g, |diff| %.3g > %.3g", #a, a_, #b, b_, fabs(a_ - b_), t_);         \
        }                                                                                                    \
    } while (0)

/* A reproducible 64-bit xorshift stream for the randomised checks (x != 0 in, never 0 out) */
static inline uint64_t ss_test_xorshift(uint64_t *x)
{
    *x ^= *x << 13;
    *x ^= *x >> 7;
    *x ^= *x << 17;
    return *x;
}

#endif
