/* Fixed-point kernels for the _q family: integer arithmetic only, 32-bit values with 64-bit
 * intermediates, saturation instead of wrap-around. Q formats are named in each signature;
 * docs/fixed-point.md tabulates the model's signals and the error bound of each kernel. */
#ifndef SS_FIXED_H
#define SS_FIXED_H

#include <stdint.h>

#define SS_Q16_ONE (1 << 16)          /* 1.0 in Q16.16 */
#define SS_Q30_ONE ((int32_t)1 << 30) /* 1.0 in Q1.30 */

/* Clamp a 64-bit value into int32 (saturation, never wrap). Inline: the q step calls it a dozen
 * times, and a call costs more than the test. v is in range iff v + 2^31, taken unsigned, is below
 * 2^32: one 64-bit add and a look at its high word, where two signed 64-bit compares cost about
 * twice that on the M0+ (181 instructions of its actuator step, bench/fw_profile.py --lines). */
static inline int32_t ss_sat32(int64_t v)
{
    if ((((uint64_t)v + 0x80000000u) >> 32) == 0u) {
        return (int32_t)v;
    }
    return (v < 0) ? INT32_MIN : INT32_MAX;
}

/* exp(-x) for x >= 0 given in Q16.16 (x < 32768), as Q1.30 in [0, 2^30]. exp(0) is exactly
 * 2^30; results are non-increasing in x; the absolute error is below 2^-26 (tests/c/test_fixed.c
 * checks every input against double precision: 2^-28.6). A table of 2^(-i/256) and a cubic, no
 * division (docs/fixed-point.md). Negative x saturates to 1.0. */
int32_t ss_exp_neg_q16_q30(int32_t x_q16);

/* exp(-x) for x >= 0 given with 32 fraction bits (unsigned, x < 2^32), as Q1.30. The part below
 * 2^-16 is applied as exp(-l) ~ 1 - l (error l^2/2 < 2^-33), so the argument keeps 2^-32
 * resolution where the Q16.16 kernel would quantise it: 1 - exp(-x) is then accurate for small x
 * (the Masing branch right after a reversal). Absolute error < 2^-26 + 2^-31. */
int32_t ss_exp_neg_q32_q30(uint64_t x_q32);

#endif /* SS_FIXED_H */
