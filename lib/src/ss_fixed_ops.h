/* Private integer helpers of the _q family (not public API): exact widening products (ARMv6-M has no
 * 32 x 32 -> 64 multiply), and rounding shifts and divisions that never shift a negative value and
 * never divide by a value <= 0, so every target computes the same bits (C99 leaves right shifts of
 * negative values implementation-defined). */
#ifndef SS_FIXED_OPS_H
#define SS_FIXED_OPS_H

#include <stdint.h>

#include "ss_fixed.h"
#include "ss_inline.h"
#include "ss_qformat.h"

/* a b, exact, from four 16 x 16 -> 32 products and their carries: how ARMv6-M (the M0+, no widening
 * multiply) gets a 32 x 32 -> 64 product in about 25 instructions, inline. Its compiler calls
 * __aeabi_lmul instead, a full 64 x 64 product of about 45. Compiled everywhere, so that the host
 * tests it against the plain product. */
static inline uint64_t ss_mul_u32_u64_halves(uint32_t a, uint32_t b)
{
    const uint32_t al = a & 0xFFFFu;
    const uint32_t ah = a >> 16;
    const uint32_t bl = b & 0xFFFFu;
    const uint32_t bh = b >> 16;
    const uint32_t lh = al * bh;
    const uint32_t mid = lh + ah * bl; /* each below 2^32, their sum may carry out */
    const uint32_t ll = al * bl;
    const uint32_t lo = ll + (mid << 16);
    const uint32_t hi = ah * bh + (mid >> 16) + ((mid < lh) ? 0x10000u : 0u) + ((lo < ll) ? 1u : 0u);
    return ((uint64_t)hi << 32) | lo;
}

/* a b, exact: one UMULL on ARMv7-M and on the host, the halves on ARMv6-M. */
static inline uint64_t ss_mul_u32_u64(uint32_t a, uint32_t b)
{
#if defined(__ARM_ARCH_6M__)
    return ss_mul_u32_u64_halves(a, b);
#else
    return (uint64_t)a * b;
#endif
}

/* a b, exact, for int32 a and b, from the halves of the magnitudes (|a b| <= 2^62). */
static inline int64_t ss_mul_s32_s64_halves(int32_t a, int32_t b)
{
    const uint32_t ma = (a < 0) ? 0u - (uint32_t)a : (uint32_t)a;
    const uint32_t mb = (b < 0) ? 0u - (uint32_t)b : (uint32_t)b;
    const int64_t p = (int64_t)ss_mul_u32_u64_halves(ma, mb);
    return ((a < 0) != (b < 0)) ? -p : p;
}

/* a b, exact: one SMULL on ARMv7-M and on the host, the halves on ARMv6-M. */
static inline int64_t ss_mul_s32_s64(int32_t a, int32_t b)
{
#if defined(__ARM_ARCH_6M__)
    return ss_mul_s32_s64_halves(a, b);
#else
    return (int64_t)a * b;
#endif
}

/* a b, exact, for int32 a and uint32 b (|a b| < 2^63), from the halves of a's magnitude. */
static inline int64_t ss_mul_s32_u32_s64_halves(int32_t a, uint32_t b)
{
    const uint32_t ma = (a < 0) ? 0u - (uint32_t)a : (uint32_t)a;
    const int64_t p = (int64_t)ss_mul_u32_u64_halves(ma, b);
    return (a < 0) ? -p : p;
}

/* a b, exact, for int32 a and uint32 b: on ARMv7-M and the host one SMULL where b fits int32
 * (every fine step's kick), and a 2^32 carried into the high word where it does not (a coarse
 * step's kick, dt / 2 M_R past 2^31 at 2^-40); the halves on ARMv6-M. */
static inline int64_t ss_mul_s32_u32_s64(int32_t a, uint32_t b)
{
#if defined(__ARM_ARCH_6M__)
    return ss_mul_s32_u32_s64_halves(a, b);
#else
    int64_t p = (int64_t)a * (int32_t)b; /* b's bits read as int32: b - 2^32 where b >= 2^31 */
    if ((int32_t)b < 0) {
        p += (int64_t)a * 4294967296; /* a 2^32, within 64 bits for |a| <= 2^31 */
    }
    return p;
#endif
}

/* a b for an int64 a (the product within 64 bits): where a fits 32 bits, as ss_mul_s32_s64 on
 * ARMv6-M (a compare, then the halves); the plain product elsewhere. Many of the step's 64-bit
 * values are 32-bit ones kept wide for the arithmetic around them. */
static inline int64_t ss_mul_i64_i32(int64_t a, int32_t b)
{
#if defined(__ARM_ARCH_6M__)
    if (a >= INT32_MIN && a <= INT32_MAX) {
        return ss_mul_s32_s64_halves((int32_t)a, b);
    }
#endif
    return a * b;
}

/* a b for int64 a and b (the product within 64 bits): the halves on ARMv6-M where both fit 32
 * bits, the plain product elsewhere. */
static inline int64_t ss_mul_i64(int64_t a, int64_t b)
{
#if defined(__ARM_ARCH_6M__)
    if (a >= INT32_MIN && a <= INT32_MAX && b >= INT32_MIN && b <= INT32_MAX) {
        return ss_mul_s32_s64_halves((int32_t)a, (int32_t)b);
    }
#endif
    return a * b;
}

/* a b's low 64 bits (all of it for a below 2^64 / b) from the halves of a's low word and one 32-bit
 * product of its high word: on ARMv6-M instead of __aeabi_lmul. Compiled everywhere (tested). */
static inline uint64_t ss_mul_u64_u32_halves(uint64_t a, uint32_t b)
{
    return ((uint64_t)((uint32_t)(a >> 32) * b) << 32) + ss_mul_u32_u64_halves((uint32_t)a, b);
}

/* a b for uint64 a below 2^64 / b: the halves on ARMv6-M (of a's low word alone where that is a),
 * the plain product elsewhere. */
static inline uint64_t ss_mul_u64_u32(uint64_t a, uint32_t b)
{
#if defined(__ARM_ARCH_6M__)
    return ((a >> 32) == 0u) ? ss_mul_u32_u64_halves((uint32_t)a, b) : ss_mul_u64_u32_halves(a, b);
#else
    return a * b;
#endif
}

/* Does a b pass 2^64 (a b > UINT64_MAX, as a > UINT64_MAX / b for b > 0)? If not, *p = a b. Two
 * 32 x 32 -> 64 products, no division. */
static inline int ss_mul_u64_u32_overflows(uint64_t a, uint32_t b, uint64_t *p)
{
    const uint64_t lo = ss_mul_u32_u64((uint32_t)a, b);
    const uint64_t top = ss_mul_u32_u64((uint32_t)(a >> 32), b) + (lo >> 32); /* < 2^64 */
    *p = (top << 32) | (uint32_t)lo;
    return (top >> 32) != 0u;
}

/* v / 2^s rounded to nearest (ties toward +infinity), 0 < s < 63, |v| <= 2^63 - 2^s, in two
 * forms with the same results (tests/c/test_fixed.c, test_shr_round). Neither shifts a negative
 * value (implementation-defined in C99). */

/* By the sign: a compare and a branch, then one 64-bit add and shift on the common path. */
static inline int64_t ss_shr_round_by_sign(int64_t v, int s)
{
    const int64_t half = (int64_t)1 << (s - 1);
    if (v >= -half) {
        return (v + half) >> s;
    }
    /* floor((v + half) / 2^s) for negative v + half */
    return -((-(v + half) + (((int64_t)1 << s) - 1)) >> s);
}

/* By an offset, without a branch: v + 2^63 (the two's-complement word read as unsigned, which C
 * defines) is never negative, and the shift takes the offset down to 2^(63-s), subtracted again. */
static inline int64_t ss_shr_round_by_offset(int64_t v, int s)
{
    const uint64_t u = (uint64_t)v + ((uint64_t)1 << 63) + ((uint64_t)1 << (s - 1));
    return (int64_t)(u >> s) - ((int64_t)1 << (63 - s));
}

/* The q step's rounding shift (some 70 sites). The offset form is 8 % fewer instructions of the
 * M3's q LS step (792 -> 728 a microsecond, bench/firmware_bench.sh); on ARMv6-M, where a 64-bit
 * add and shift are several Thumb-1 instructions each, it was 4 % more (2 203 -> 2 293). */
static inline int64_t ss_shr_round(int64_t v, int s)
{
#if defined(__ARM_ARCH_6M__)
    return ss_shr_round_by_sign(v, s);
#else
    return ss_shr_round_by_offset(v, s);
#endif
}

/* round(a b / 2^s) for |a| < 2^62, |b| < 2^31, 32 <= s < 63, in two 32 x 32 products (a b needs 93
 * bits): a's low 31 bits times b are rounded to 2^-31 first, so the result can be 1 off the exact
 * rounding. The q step's divisions by a constant go through it with a reciprocal. Forced inline:
 * with a fourth step form beside it GCC made it a call from the fine q step on the M0+ (0.5-1.2 %
 * dearer). */
SS_FORCE_INLINE int64_t ss_mul_shr_round_wide(int64_t a, int32_t b, int s)
{
    const int64_t hi = a >> 31; /* floor: hi 2^31 + lo == a, lo in [0, 2^31), hi within int32 */
    const int64_t lo = a - hi * ((int64_t)1 << 31);
    return ss_shr_round(ss_mul_s32_s64((int32_t)hi, b) + ss_shr_round(ss_mul_s32_s64((int32_t)lo, b), 31),
                        s - 31);
}

/* A reciprocal made in the step, for a divisor that is not a config constant (the Stribeck level
 * g, the implicit-damping denominator): 1/d ~ m 2^-shift for d in [1, 2^31), m in [2^30, 2^31)
 * within 0.55 of 2^shift / d (relative error below 2^-30.8; every normalised d checked once, off
 * line; 2^31 - 1 where that is 2^31, d a power of two), shift = 61 less the left shift that brings d
 * into [2^30, 2^31). No division: a 256-entry seed, a Newton step in 32-bit products and one in
 * two 32 x 32 -> 64 products (tests/c/test_fixed.c, test_reciprocal_mantissa). d = 0 or d >= 2^31
 * gives m = 0. Defined in ss_fixed.c, so that its table is once in the image. */
int32_t ss_reciprocal_mantissa_q(uint32_t d, int *shift);

/* round(a m / 2^s), ties away from zero, for int32 a, m from ss_reciprocal_mantissa_q and
 * 1 <= s < 63: a / d at 2^-(s - shift), exact but for m's rounding. One 32 x 32 -> 64 product. */
static inline int64_t ss_mul_recip_q(int32_t a, int32_t m, int s)
{
    const uint32_t mag = (a < 0) ? (uint32_t)0 - (uint32_t)a : (uint32_t)a;
    const int64_t q = (int64_t)(((ss_mul_u32_u64(mag, (uint32_t)m) >> (s - 1)) + 1u) >> 1);
    return (a < 0) ? -q : q;
}

/* round(a m / 2^s) for a < 2^49, 0 <= m < 2^31, 18 <= s < 63, in two 32 x 32 -> 64 products (a m
 * needs 80 bits): a = hi 2^17 + lo, lo m rounded to 2^-17 first, so the result can be 1 off the
 * exact rounding. A quotient by a reciprocal of ss_reciprocal_mantissa_q with a 49-bit dividend. */
static inline uint64_t ss_mul_shr_round_u49(uint64_t a, int32_t m, int s)
{
    const uint32_t hi = (uint32_t)(a >> 17);
    const uint32_t lo = (uint32_t)a & (((uint32_t)1 << 17) - 1u);
    const uint64_t sum =
        ss_mul_u32_u64(hi, (uint32_t)m) + ((ss_mul_u32_u64(lo, (uint32_t)m) + ((uint64_t)1 << 16)) >> 17);
    return ((sum >> (s - 18)) + 1u) >> 1;
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

/* v times the sign of s (1, 0 or -1), by compares: a product by the sign would be a library call
 * on ARMv6-M */
static inline int64_t ss_times_sign_of(int64_t v, int64_t s)
{
    return (s > 0) ? v : ((s < 0) ? -v : 0);
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
    if (num < ((uint64_t)1 << 47)) {
        /* num 2^16 fits: one division, the same rounding as the two below (a step's sigma0 |dx|
         * is this small: 1 um at 10 MN/m is 2^43) */
        return ((num << 16) + den / 2) / den;
    }
    const uint64_t q = num / den;
    if (q >= ((uint64_t)1 << 47)) {
        return (uint64_t)1 << 63;
    }
    return (q << 16) + (((num % den) << 16) + den / 2) / den;
}

/* ss_ratio_x65536(num, den) from den's reciprocal m 2^-sh (ss_reciprocal_mantissa_q, sh >= 34):
 * num below 2^49 (a step's sigma0 |dx| is: 1 um at 10 MN/m is 2^43) in two products, at most 1 off
 * num 2^16 m / 2^sh; a larger num by the division. */
static inline uint64_t ss_ratio_x65536_recip(uint64_t num, uint64_t den, int32_t m, int sh)
{
    if (num < ((uint64_t)1 << 49)) {
        return ss_mul_shr_round_u49(num, m, sh - 16);
    }
    return ss_ratio_x65536(num, den);
}

/* The shortest step the q family takes, exclusive: 2^47 / dt_q40 then fits 31 bits (the longest,
 * 2^31 = 1.95 ms, leaves 17). */
#define SS_Q_DT_MIN_Q40 65536

/* round(2^s / d) for d > lo, else 0: a config value's reciprocal, made once (at init or by the
 * converter), so that the step multiplies where it divided; lo is where it would no longer fit
 * 31 bits. */
static inline int32_t ss_reciprocal_q(int32_t d, int32_t lo, int s)
{
    if (d <= lo) {
        return 0;
    }
    return (int32_t)((((int64_t)1 << s) + d / 2) / d);
}

/* 2^47 / dt_q40 rounded: 1/dt in 1/s at 2^-7, the step's reciprocal; 0 for dt_q40 outside
 * (SS_Q_DT_MIN_Q40, 2^31). */
static inline int32_t ss_inv_dt_q47(int32_t dt_q40)
{
    return ss_reciprocal_q(dt_q40, SS_Q_DT_MIN_Q40, 47);
}

/* dx / dt in m/s at 2^-28 (saturated) from dx in m at 2^-40 and 1/dt in 1/s at 2^-7. */
static inline int32_t ss_velocity_q28(int64_t dx_q40, int32_t inv_dt_q47)
{
    const int64_t v = ss_shr_round(
        ss_mul_s32_s64((int32_t)ss_clamp64(dx_q40, -INT32_MAX, INT32_MAX), inv_dt_q47), 47 - SS_QF_DXDT);
    return (int32_t)ss_clamp64(v, -INT32_MAX, INT32_MAX);
}

#endif /* SS_FIXED_OPS_H */
