/* Private float32 sine and cosine of the _f32 family (not public API): sin(x) and cos(x) together,
 * for 0 <= x < SS_TRIG_MAX_ARG. The caller is the rod's flow (ss_actuator_f32.c), x = w t: over the
 * step at init, and over each piece of a step that a drive's corner splits, a new t each time.
 *
 * Why not libm's sinf and cosf: the reasons of ss_exp_f32.h. On a Cortex-M newlib's pair and its
 * expf made a corner step cost about 1 590 instructions, twice a plain step, and their last bits
 * differ between C libraries, so a free run whose corners fall inside steps left the host's bits.
 * This one is C99 arithmetic in a fixed order (the library builds without FMA contraction), so
 * every target computes the same bits.
 *
 * Method: x = n pi/2 + r with n = round(x 2/pi) and |r| <= pi/4 (Cody-Waite: pi/2 split in a high
 * part of 12 significant bits, so n pi/2_hi is exact for n < 4096, and a low part), sin r and cos r
 * by their Taylor polynomials to r^9 and r^10 (truncation below r^11 / 11! = 1.8e-9 and r^12 / 12!
 * = 1.1e-10 at |r| = pi/4), the quadrant n mod 4 choosing signs and roles. Error against float64,
 * tested in tests/c/test_trig.c: <= 1.2e-7 absolute over the domain (measured 8.6e-8), and for the
 * sine below pi/4 <= 1.5e-7 relative (measured 6.6e-8). Outside the domain (x < 0, x >=
 * SS_TRIG_MAX_ARG, NaN) both results are NaN; the rod's flow takes libm's there. Needs IEEE-754
 * binary32 floats. */
#ifndef SS_TRIG_F32_H
#define SS_TRIG_F32_H

#include <math.h>
#include <stdint.h>

#define SS_TRIG_MAX_ARG 4096.0f /* n <= 2608: n pi/2_hi exact */

/* sin(x) and cos(x), 0 <= x < SS_TRIG_MAX_ARG. */
static inline void ss_sincos_f32(float x, float *s, float *c)
{
    if (!(x >= 0.0f && x < SS_TRIG_MAX_ARG)) {
        *s = *c = (float)NAN;
        return;
    }
    const float two_over_pi = 6.36619747e-1f;
    const float pio2_hi = 1.57080078125f; /* 3217 / 2048 */
    const float pio2_lo = -4.45445494e-6f;
    const int32_t n = (int32_t)(x * two_over_pi + 0.5f); /* x >= 0: truncation rounds to nearest */
    const float nf = (float)n;
    const float r = (x - nf * pio2_hi) - nf * pio2_lo;
    const float r2 = r * r;
    const float sr =
        r + r * r2 * (-1.66666672e-1f + r2 * (8.33333377e-3f + r2 * (-1.98412701e-4f + r2 * 2.75573188e-6f)));
    const float cr =
        1.0f + r2 * (-0.5f + r2 * (4.16666679e-2f +
                                   r2 * (-1.38888892e-3f + r2 * (2.48015876e-5f + r2 * -2.75573200e-7f))));
    switch (n & 3) {
    case 0:
        *s = sr;
        *c = cr;
        break;
    case 1:
        *s = cr;
        *c = -sr;
        break;
    case 2:
        *s = -sr;
        *c = -cr;
        break;
    default:
        *s = -cr;
        *c = sr;
        break;
    }
}

#endif /* SS_TRIG_F32_H */
