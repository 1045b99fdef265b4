/* Private integer helpers of the _q family (not public API): rounding shifts and divisions that
 * never shift a negative value and never divide by a value <= 0, so every target computes the same
 * bits (C99 leaves right shifts of negative values implementation-defined). */
#ifndef SS_FIXED_OPS_H
#define SS_FIXED_OPS_H

#include <stdint.h>

#include "ss_fixed.h"

/* v / 2^s rounded to nearest (ties toward +infinity), 0 < s < 63. */
static inline int64_t ss_shr_round(int64_t v, int s)
{
    const int64_t half = (int64_t)1 << (s - 1);
    if (v >= -half) {
        return (v + half) >> s;
    }
    /* floor((v + half) / 2^s) for negative v + half, without shifting a negative value */
    return -((-(v + half) + (((int64_t)1 << s) - 1)) >> s);
}

/* n / d rounded to nearest (ties away from zero), d > 0, |n| < 2^62. */
static inline int64_t ss_div_round(int64_t n, int64_t d)
{
    return (n >= 0) ? (n + d / 2) / d : -((-n + d / 2) / d);
}

static inline int64_t ss_abs64(int64_t v)
{
    return (v < 0) ? -v : v;
}

static inline int32_t ss_sign32(int64_t v)
{
    return (v > 0) ? 1 : ((v < 0) ? -1 : 0);
}

/* Clamp into [lo, hi]. */
static inline int64_t ss_clamp64(int64_t v, int64_t lo, int64_t hi)
{
    return (v < lo) ? lo : ((v > hi) ? hi : v);
}

/* num / den with 16 more fraction bits than num/den has, rounded, den > 0, saturated at 2^63
 * (far beyond where exp(-x) is zero). The friction models use it for sigma0 |dx| / F: N/m times
 * 2^-40 m over N at 2^-24 is a pure number at 2^-16, so the result is the Q32 exponent. */
static inline uint64_t ss_ratio_x65536(uint64_t num, uint64_t den)
{
    const uint64_t q = num / den;
    if (q >= ((uint64_t)1 << 47)) {
        return (uint64_t)1 << 63;
    }
    return (q << 16) + (((num % den) << 16) + den / 2) / den;
}

#endif /* SS_FIXED_OPS_H */
