#include "ss_fixed.h"

/* v / 2^s rounded toward minus infinity, as an arithmetic shift would, without shifting a
 * negative value (implementation-defined in C99): bit-exact on every target. */
static int64_t shr_floor(int64_t v, int s)
{
    if (v >= 0) {
        return v >> s;
    }
    return -((-v + (((int64_t)1 << s) - 1)) >> s);
}

/* x / n truncated toward zero, exactly as C's `/`, for |x| < 2^31 and n in [2, 7]: a multiply by
 * m = ceil(2^34 / n). With e = m n - 2^34 <= n - 1, x m / 2^34 = x / n + x e / (n 2^34) and
 * x e < 2^31 x 8 = 2^34 keeps the floor (Granlund & Montgomery 1994). Why: the M0+ has no divide
 * instruction, and each 64-bit `/` is a call to __aeabi_ldivmod; the exponential did seven. */
static int64_t div_small(int64_t x, int n)
{
    static const uint64_t m[8] = {0u,          0u,          8589934592u, 5726623062u,
                                  4294967296u, 3435973837u, 2863311531u, 2454267027u};
    const uint64_t a = (x < 0) ? (uint64_t)(-x) : (uint64_t)x;
    const int64_t q = (int64_t)((a * m[n]) >> 34);
    return (x < 0) ? -q : q;
}

/* exp(-x) = 2^-(x log2 e) = 2^-k * 2^-f with k whole and f in [0, 1); 2^-f = 2^-1/2 * e^(-u ln2)
 * with u = f - 1/2 in [-1/2, 1/2), |u ln2| <= 0.347: a Taylor polynomial of degree 7 there has a
 * remainder below 0.347^8 / 8! = 5.6e-9 (2^-27.4). All in Q30 with 64-bit products. */
int32_t ss_exp_neg_q16_q30(int32_t x_q16)
{
    if (x_q16 <= 0) {
        return SS_Q30_ONE;
    }
    /* y = x * log2(e) with 46 fraction bits (Q16 x Q30), so the fraction keeps 30 of them */
    const int64_t y = (int64_t)x_q16 * 1549082005LL; /* log2(e) in Q30; < 2^62 for x < 2^31 */
    const int64_t k = y >> 46;
    if (k >= 31) {
        return 0; /* below 2^-31: zero in Q30 */
    }
    const int64_t f_q30 = (y >> 16) & (SS_Q30_ONE - 1);
    /* w = -u ln2 in Q30, u = f - 1/2; ln2 in Q30 = 744261118 */
    const int64_t u_q30 = f_q30 - ((int64_t)1 << 29);
    const int64_t w = -shr_floor(u_q30 * 744261118LL, 30);
    /* e^w by Horner: 1 + w(1 + w/2(1 + w/3(1 + ... w/7))); |w p| / 2^30 < 0.35 x 1.42 x 2^30, so
     * div_small's |x| < 2^31 holds */
    int64_t p = SS_Q30_ONE;
    for (int n = 7; n >= 2; --n) {
        p = SS_Q30_ONE + div_small(shr_floor(w * p, 30), n);
    }
    p = SS_Q30_ONE + shr_floor(w * p, 30);
    /* times 2^-1/2 (Q30: 759250125) and 2^-k, rounded */
    const int64_t r = (p * 759250125LL) >> 30;
    return (int32_t)((r + (k > 0 ? ((int64_t)1 << (k - 1)) : 0)) >> k);
}

int32_t ss_exp_neg_q32_q30(uint64_t x_q32)
{
    const uint64_t hi = x_q32 >> 16;
    if (hi > (uint64_t)INT32_MAX) {
        return 0;
    }
    const int64_t e_hi = ss_exp_neg_q16_q30((int32_t)hi);
    const int64_t lo = (int64_t)(x_q32 & 0xFFFFu); /* units of 2^-32, below 2^-16 */
    /* e_hi * (1 - lo): e_hi * lo < 2^30 * 2^16, no overflow; rounded to nearest */
    return (int32_t)(e_hi - ((e_hi * lo + ((int64_t)1 << 31)) >> 32));
}
