#include "ss_fixed.h"
#include "ss_fixed_ops.h"

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

/* Seeds of ss_reciprocal_mantissa_q: 2^24 / (256.5 + i) rounded, 1 / the middle of the i-th of 256
 * equal parts of [1, 2) at 2^-15, within (1/256) / (2 + 1/256) < 2^-9 of 1/x over its part,
 * relative (2^-17 more for the rounding). */
static const uint16_t RECIP_SEED[256] = {
    65408u, 65154u, 64902u, 64652u, 64404u, 64158u, 63913u, 63671u, 63430u, 63191u, 62954u, 62719u, 62485u,
    62253u, 62023u, 61795u, 61568u, 61343u, 61119u, 60897u, 60677u, 60458u, 60241u, 60026u, 59812u, 59599u,
    59388u, 59179u, 58971u, 58764u, 58559u, 58356u, 58153u, 57952u, 57753u, 57555u, 57358u, 57163u, 56968u,
    56776u, 56584u, 56394u, 56205u, 56017u, 55831u, 55646u, 55462u, 55279u, 55098u, 54917u, 54738u, 54560u,
    54383u, 54207u, 54033u, 53859u, 53687u, 53516u, 53346u, 53177u, 53009u, 52842u, 52676u, 52511u, 52347u,
    52184u, 52022u, 51862u, 51702u, 51543u, 51385u, 51228u, 51072u, 50917u, 50763u, 50610u, 50458u, 50306u,
    50156u, 50007u, 49858u, 49710u, 49563u, 49417u, 49272u, 49128u, 48985u, 48842u, 48700u, 48559u, 48419u,
    48280u, 48141u, 48003u, 47867u, 47730u, 47595u, 47460u, 47326u, 47193u, 47061u, 46929u, 46798u, 46668u,
    46539u, 46410u, 46282u, 46155u, 46028u, 45902u, 45777u, 45652u, 45528u, 45405u, 45283u, 45161u, 45040u,
    44919u, 44799u, 44680u, 44561u, 44443u, 44326u, 44209u, 44093u, 43977u, 43862u, 43748u, 43634u, 43521u,
    43408u, 43296u, 43185u, 43074u, 42963u, 42854u, 42744u, 42636u, 42528u, 42420u, 42313u, 42207u, 42101u,
    41996u, 41891u, 41786u, 41683u, 41579u, 41476u, 41374u, 41272u, 41171u, 41070u, 40970u, 40870u, 40771u,
    40672u, 40574u, 40476u, 40378u, 40281u, 40185u, 40089u, 39993u, 39898u, 39804u, 39709u, 39616u, 39522u,
    39429u, 39337u, 39245u, 39153u, 39062u, 38971u, 38881u, 38791u, 38702u, 38613u, 38524u, 38436u, 38348u,
    38260u, 38173u, 38087u, 38000u, 37915u, 37829u, 37744u, 37659u, 37575u, 37491u, 37407u, 37324u, 37241u,
    37159u, 37077u, 36995u, 36914u, 36833u, 36752u, 36672u, 36592u, 36512u, 36433u, 36354u, 36275u, 36197u,
    36119u, 36041u, 35964u, 35887u, 35810u, 35734u, 35658u, 35583u, 35507u, 35432u, 35358u, 35283u, 35209u,
    35136u, 35062u, 34989u, 34916u, 34844u, 34771u, 34700u, 34628u, 34557u, 34486u, 34415u, 34344u, 34274u,
    34204u, 34135u, 34065u, 33996u, 33928u, 33859u, 33791u, 33723u, 33655u, 33588u, 33521u, 33454u, 33387u,
    33321u, 33255u, 33189u, 33124u, 33059u, 32994u, 32929u, 32864u, 32800u};

int32_t ss_reciprocal_mantissa_q(uint32_t d, int *shift)
{
    if (d == 0u || d > (uint32_t)INT32_MAX) {
        *shift = 0;
        return 0;
    }
    /* dn = d 2^n in [2^30, 2^31). Where the core has CLZ (ARMv7-M: the ACLE's feature macro) it is
     * one instruction; elsewhere (the host, ARMv6-M, where __builtin_clz is a libgcc call) a
     * compare tree. The same n either way (the M3 and M0+ images print the same bits) */
#if defined(__ARM_FEATURE_CLZ)
    const int n = __builtin_clz(d) - 1;
    const uint32_t dn = d << n;
#else
    int n = 0;
    uint32_t dn = d;
    if (dn < ((uint32_t)1 << 15)) {
        dn <<= 16;
        n += 16;
    }
    if (dn < ((uint32_t)1 << 23)) {
        dn <<= 8;
        n += 8;
    }
    if (dn < ((uint32_t)1 << 27)) {
        dn <<= 4;
        n += 4;
    }
    if (dn < ((uint32_t)1 << 29)) {
        dn <<= 2;
        n += 2;
    }
    if (dn < ((uint32_t)1 << 30)) {
        dn <<= 1;
        n += 1;
    }
#endif
    /* y0 ~ 2^60 / dn in (2^29, 2^30], in 32-bit products (one instruction on every target): the
     * seed s ~ 2^46 / dn, and a Newton step s + s e / 2^38 on dn's top 23 bits, e = 2^38 - (dn /
     * 2^8) s within 2^29: it is the product's low word (mod 2^32; unsigned wrap-around is defined)
     * taken with an offset 2^31, so that no negative value is shifted. Relative error (2^-9)^2
     * plus the truncations, within 2^-17.7. */
    const uint32_t s = RECIP_SEED[(dn >> 22) - 256u];
    const uint32_t res = ((uint32_t)1 << 31) - (dn >> 8) * s; /* 2^31 + e */
    const uint32_t y0 = (s << 14) + ((s * (res >> 16)) >> 8) - (s << 7);
    /* a Newton step in 32 x 32 -> 64 products, y0 + y0 (1 - dn y0 / 2^60), at the scale 2^61: its
     * residual e = 2^60 - dn y0 is within 2^42.3, u = e / 2^15 + 2^31 fits 32 bits, and y0 e /
     * 2^59 is (y0 u - y0 2^31) / 2^44, rounded, unsigned and below 2^63. What is left: the
     * rounding and (2^-17.7)^2 of y, within 0.6 of 2^61 / dn over every dn */
    const uint32_t u = (uint32_t)((((uint64_t)1 << 60) + ((uint64_t)1 << 46) - (uint64_t)dn * y0) >> 15);
    const uint64_t c = (uint64_t)y0 * u + (((uint64_t)1 << 61) + ((uint64_t)1 << 43)) - ((uint64_t)y0 << 31);
    const uint64_t y = 2 * (uint64_t)y0 + (c >> 44) - ((uint64_t)1 << 17);
    *shift = 61 - n;
    return (int32_t)((y > (uint64_t)INT32_MAX) ? INT32_MAX : y);
}
