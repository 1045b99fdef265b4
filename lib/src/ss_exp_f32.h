/* Private float32 exponential of the _f32 family (not public API): exp(-a) and exp(-a) - 1 for
 * a >= 0, the only forms the models' steps need (Masing branches, Stribeck curve, relaxations).
 *
 * Why not libm's expf: it costs 100+ instructions on a Cortex-M (newlib, soft range checks) and
 * differs between C libraries in the last bit, so host and firmware agreed bit for bit only by
 * luck. This one is C99 arithmetic in a fixed order (the library builds with -std=c99, which
 * turns off FMA contraction), so every target computes the same bits, and it is short.
 *
 * Method: a = n ln2 + r with n = round(a / ln2) and |r| <= ln2 / 2 (Cody-Waite: ln2 split in a
 * high part exact for n < 512 and a low part), exp(-r) - 1 by its Taylor polynomial to r^7
 * (truncation below r^8 / 8! = 5e-9 at |r| = ln2 / 2), scaled by 2^-n through the exponent bits.
 * Relative error against float64: <= 2.5e-7 for exp(-a) and for exp(-a) - 1 (both), over
 * a in [0, 87.3], tested in tests/c/test_exp.c. Beyond 87.3 the
 * result is below FLT_MIN and returned as 0 (-1). Needs IEEE-754 binary32 floats.
 * Domain: a >= 0; a NaN gives NaN; -ln2/2 < a < 0 is still accurate (rounding near 0). */
#ifndef SS_EXP_F32_H
#define SS_EXP_F32_H

#include <stdint.h>
#include <string.h>

#define SS_EXP_MAX_ARG 87.3f /* exp(-87.3) = 1.2e-38: FLT_MIN */

/* exp(-a) - 1 and (through *e) exp(-a), a >= 0. */
static inline float ss_expm1_neg_f32(float a, float *e)
{
    if (!(a < SS_EXP_MAX_ARG)) {
        if (a != a) { /* NaN */
            *e = a;
            return a;
        }
        *e = 0.0f;
        return -1.0f;
    }
    const float log2e = 1.44269504f;
    const float ln2_hi = 0.693145751953125f; /* 15 significant bits: n * ln2_hi is exact */
    const float ln2_lo = 1.42860677e-6f;
    const int32_t n = (int32_t)(a * log2e + 0.5f); /* a >= 0: truncation rounds to nearest */
    const float nf = (float)n;
    const float r = (a - nf * ln2_hi) - nf * ln2_lo;
    /* exp(-r) - 1 = -r + r^2/2 - r^3/6 + ... - r^7/7!, Horner */
    const float p =
        r *
        (-1.0f + r * (0.5f + r * (-1.66666667e-1f +
                                  r * (4.16666667e-2f +
                                       r * (-8.33333333e-3f + r * (1.38888889e-3f + r * -1.98412698e-4f))))));
    if (n == 0) {
        *e = 1.0f + p;
        return p; /* keeps its digits for small a, where 1 + p would round them away */
    }
    const uint32_t bits = (uint32_t)(127 - n) << 23; /* 2^-n, 1 <= n <= 126 */
    float scale;
    memcpy(&scale, &bits, sizeof scale);
    *e = (1.0f + p) * scale;
    return *e - 1.0f;
}

/* exp(-a), a >= 0. */
static inline float ss_exp_neg_f32(float a)
{
    float e;
    (void)ss_expm1_neg_f32(a, &e);
    return e;
}

#endif /* SS_EXP_F32_H */
