/* Fixed-point kernels against double precision. */
#include "ss_test.h"

#include "ss_fixed.h"
#include "ss_fixed_ops.h"
#include "ss_actuator_q.h"
#include "ss_friction_q.h"

static void test_sat32(void **unused)
{
    (void)unused;
    assert_int_equal(ss_sat32((int64_t)INT32_MAX + 5), INT32_MAX);
    assert_int_equal(ss_sat32((int64_t)INT32_MIN - 5), INT32_MIN);
    assert_int_equal(ss_sat32(-42), -42);
}

/* The rounding shift's two forms (ARMv6-M takes one, the other targets the other) against
 * floor((v + 2^(s-1)) / 2^s) in 128-bit arithmetic, for every shift (1 to 62): around 0 and the
 * ties, the ends of the domain (|v| <= 2^63 - 2^s), and random words of every length. */
static int64_t shr_round_exact(int64_t v, int s)
{
    const __int128 p = (__int128)v + ((__int128)1 << (s - 1));
    return (int64_t)((p >= 0) ? p >> s : -((-p + (((__int128)1 << s) - 1)) >> s));
}

static void test_shr_round(void **unused)
{
    (void)unused;
    uint64_t r = 88172645463325252ull;
    for (int s = 1; s < 63; ++s) {
        const int64_t half = (int64_t)1 << (s - 1);
        const int64_t top = INT64_MAX - ((int64_t)1 << s) + 1; /* 2^63 - 2^s */
        const int64_t three = (s < 62) ? 3 * half : half;      /* 3 x 2^61 is beyond int64 */
        const int64_t edges[] = {-top, -top + 1, -three - 1, -three, -half - 1, -half, -half + 1,       -1,
                                 0,    1,        half - 1,   half,   half + 1,  three, INT64_MAX - half};
        for (size_t i = 0; i < sizeof edges / sizeof edges[0]; ++i) {
            const int64_t want = shr_round_exact(edges[i], s);
            if (ss_shr_round_by_sign(edges[i], s) != want || ss_shr_round_by_offset(edges[i], s) != want) {
                fail_msg("s = %d, v = %lld: %lld and %lld, exact %lld", s, (long long)edges[i],
                         (long long)ss_shr_round_by_sign(edges[i], s),
                         (long long)ss_shr_round_by_offset(edges[i], s), (long long)want);
            }
        }
        for (int i = 0; i < 20000; ++i) {
            const uint64_t w = ss_test_xorshift(&r) >> (ss_test_xorshift(&r) % 64);
            const int64_t v = (int64_t)(w >> 1) * ((i & 1) ? 1 : -1);
            if (v <= top && v >= -top) {
                const int64_t want = shr_round_exact(v, s);
                assert_true(ss_shr_round_by_sign(v, s) == want && ss_shr_round_by_offset(v, s) == want);
            }
        }
    }
}

/* round(a b / 2^s) in two 32 x 32 products, against 128-bit arithmetic: at most 1 off (its one
 * inner rounding), over the stated operand ranges. */
static void test_mul_shr_round_wide(void **unused)
{
    (void)unused;
    uint64_t r = 88172645463325252ull;
    int64_t worst = 0;
    for (int i = 0; i < 200000; ++i) {
        const int64_t a =
            (int64_t)(ss_test_xorshift(&r) >> 2) * ((i & 1) ? 1 : -1) >> (ss_test_xorshift(&r) % 40);
        const int32_t b = (int32_t)((int64_t)(ss_test_xorshift(&r) >> 33) * ((i & 2) ? 1 : -1) >>
                                    (ss_test_xorshift(&r) % 20));
        const int s = 32 + (int)(ss_test_xorshift(&r) % 31);
        const __int128 p = (__int128)a * b + ((__int128)1 << (s - 1));
        const __int128 q = (p >= 0) ? p >> s : -((-p + (((__int128)1 << s) - 1)) >> s); /* floor */
        const int64_t d = ss_mul_shr_round_wide(a, b, s) - (int64_t)q;
        worst = (d < 0 ? -d : d) > worst ? (d < 0 ? -d : d) : worst;
    }
    assert_true(worst <= 1);
}

/* |m - 2^shift / d| in units of m, exactly, from 128-bit arithmetic (m d - 2^shift over d). */
static double reciprocal_error(uint32_t d)
{
    int sh = 0;
    const int32_t m = ss_reciprocal_mantissa_q(d, &sh);
    const __int128 r = (__int128)m * (__int128)d - ((__int128)1 << sh);
    return fabs((double)r / (double)d);
}

/* The step's reciprocal (no division) against exact 128-bit arithmetic: m in [2^30, 2^31), within
 * 0.55 of 2^shift / d (every normalised divisor in (2^30, 2^31) was checked once, off line: worst
 * 0.533, i.e. m is the rounded quotient but next to a tie), 2^31 - 1 at powers of two. The step gives it g in
 * (2^11, 2^29] and the implicit-damping denominator in (0.1 x 2^30, 2^31). */
static void test_reciprocal_mantissa(void **unused)
{
    (void)unused;
    double worst = 0.0;
    for (uint32_t dn = ((uint32_t)1 << 30) + 1u; dn < ((uint32_t)1 << 31) - 4099u; dn += 4099u) {
        worst = fmax(worst, reciprocal_error(dn));
    }
    for (uint32_t i = 1; i < 2048u; ++i) { /* the seed's parts (2^22), and steps of 2^19 */
        const uint32_t edge = ((uint32_t)1 << 30) + (i << 19);
        worst = fmax(worst, fmax(reciprocal_error(edge), reciprocal_error(edge + 1u)));
        worst = fmax(worst, reciprocal_error(edge - 1u));
    }
    worst = fmax(worst, reciprocal_error(INT32_MAX));
    uint64_t r = 1181783497276652981ull;
    for (int i = 0; i < 200000; ++i) {
        const uint32_t d =
            (uint32_t)(ss_test_xorshift(&r) >> (33 + ss_test_xorshift(&r) % 31)) + 1u; /* [1, 2^31) */
        int sh = 0;
        assert_true(ss_reciprocal_mantissa_q(d, &sh) >= ((int32_t)1 << 30));
        if ((d & (d - 1u)) != 0u) {
            worst = fmax(worst, reciprocal_error(d));
        }
    }
    print_message("reciprocal: worst |m - 2^shift / d| %.3f\n", worst);
    assert_true(worst < 0.55);
    int sh = 0;
    for (int k = 0; k < 31; ++k) { /* powers of two: 2^31 - 1 */
        assert_int_equal(ss_reciprocal_mantissa_q((uint32_t)1 << k, &sh), INT32_MAX);
        assert_int_equal(sh, 31 + k);
    }
    assert_int_equal(ss_reciprocal_mantissa_q(3u, &sh), 1431655765); /* 2^32 / 3, rounded */
    assert_int_equal(sh, 32);
    assert_int_equal(ss_reciprocal_mantissa_q(0u, &sh), 0);
    assert_int_equal(ss_reciprocal_mantissa_q((uint32_t)1 << 31, &sh), 0);
}

/* ss_mul_recip_q: round(a m / 2^s), ties away from zero, exactly (128-bit arithmetic). */
static void test_mul_recip(void **unused)
{
    (void)unused;
    uint64_t r = 2463534242ull;
    for (int i = 0; i < 200000; ++i) {
        const int32_t a = (int32_t)(ss_test_xorshift(&r) >> 32);
        const int32_t m = (int32_t)(ss_test_xorshift(&r) >> 33);
        const int s = 1 + (int)(ss_test_xorshift(&r) % 62);
        const __int128 p = (__int128)a * m;
        const __int128 mag = ((p < 0 ? -p : p) + ((__int128)1 << (s - 1))) >> s;
        assert_true(ss_mul_recip_q(a, m, s) == (int64_t)(p < 0 ? -mag : mag));
    }
}

/* round(a m / 2^s) for a 49-bit a in two products, against 128-bit arithmetic: at most 1 off. */
static void test_mul_shr_round_u49(void **unused)
{
    (void)unused;
    uint64_t r = 88172645463325252ull;
    int64_t worst = 0;
    for (int i = 0; i < 200000; ++i) {
        const uint64_t a = ss_test_xorshift(&r) >> (15 + ss_test_xorshift(&r) % 49); /* below 2^49 */
        const int32_t m = (int32_t)(ss_test_xorshift(&r) >> 33);
        const int s = 18 + (int)(ss_test_xorshift(&r) % 45);
        const unsigned __int128 q =
            ((unsigned __int128)a * (uint64_t)m + ((unsigned __int128)1 << (s - 1))) >> s;
        const int64_t d = (int64_t)(ss_mul_shr_round_u49(a, m, s) - (uint64_t)q);
        worst = (d < 0 ? -d : d) > worst ? (d < 0 ? -d : d) : worst;
    }
    assert_true(worst <= 1);
}

/* The exponent sigma0 |dx| / g through g's reciprocal against the exact division: off by at most
 * the reciprocal's relative error (0.55 of m >= 2^30: below 2^-30.8) of the result plus 1.5 (the
 * two products' roundings), for num below 2^49 and g in (2^11, 2^31). */
static void test_ratio_x65536_by_reciprocal(void **unused)
{
    (void)unused;
    uint64_t r = 5489ull;
    for (int i = 0; i < 200000; ++i) {
        const uint64_t num = ss_test_xorshift(&r) >> (15 + ss_test_xorshift(&r) % 49);
        const uint32_t den = (uint32_t)(ss_test_xorshift(&r) >> (33 + ss_test_xorshift(&r) % 20)) + 2049u;
        int sh = 0;
        const int32_t m = ss_reciprocal_mantissa_q(den, &sh);
        const double exact = ldexp((double)num, 16) / den;
        const double got = (double)ss_ratio_x65536_recip(num, den, m, sh);
        assert_true(fabs(got - exact) <= exact * ldexp(0.55, -30) + 1.5);
    }
}

/* The one-division path of ss_ratio_x65536 (num below 2^47) gives the bits of the exact two-step
 * form (quotient, then the remainder's 16 more bits) on every num and den drawn. */
static void test_ratio_x65536_one_division(void **unused)
{
    (void)unused;
    uint64_t r = 2463534242ull;
    for (int i = 0; i < 200000; ++i) {
        const uint64_t num = ss_test_xorshift(&r) >> (17 + ss_test_xorshift(&r) % 40);
        const uint64_t den = (ss_test_xorshift(&r) >> (33 + ss_test_xorshift(&r) % 30)) + 1u;
        const uint64_t q = num / den;
        const uint64_t two_step = (q << 16) + (((num % den) << 16) + den / 2) / den;
        assert_true(ss_ratio_x65536(num, den) == two_step);
    }
    assert_true(ss_ratio_x65536(((uint64_t)1 << 47) - 1, 1) == (((uint64_t)1 << 47) - 1) << 16);
    assert_true(ss_ratio_x65536((uint64_t)1 << 62, 1) == (uint64_t)1 << 63); /* saturated */
}

/* dx / dt through the step's reciprocal: off the rounded quotient by at most one quantum plus the
 * reciprocal's own relative error (half a unit of 2^47 / dt: 3.9e-9 at 1 us, 9 quanta at the 8 m/s
 * end of the format), and that error at most 2^-17 over the whole range of steps. */
static void test_velocity_by_reciprocal(void **unused)
{
    (void)unused;
    const int32_t dt = 1099512; /* 1 us */
    const int32_t inv = ss_inv_dt_q47(dt);
    for (int64_t dx = -2000000000; dx <= 2000000000; dx += 999983) {
        const int64_t exact = ss_div_round(dx * 268435456, dt); /* m/s at 2^-28 */
        const int64_t v = ss_velocity_q28(dx, inv);
        if (exact > INT32_MAX || exact < -INT32_MAX) {
            assert_true(v == INT32_MAX || v == -INT32_MAX);
        } else {
            const double bound = 1.0 + fabs((double)exact) * 0.5 / (double)inv;
            assert_true(fabs((double)(v - exact)) <= bound);
        }
    }
    for (int64_t t = 65537; t <= INT32_MAX; t = t * 3 / 2 + 1) {
        const double rel = fabs((double)ss_inv_dt_q47((int32_t)t) * (double)t / 140737488355328.0 - 1.0);
        assert_true(rel <= 1.0 / 131072.0);
    }
    assert_int_equal(ss_inv_dt_q47(0), 0);
    assert_int_equal(ss_inv_dt_q47(-5), 0);
}

/* Every x on a 2^-12 grid over [0, 32): error < 2^-26, monotone, exact at 0. */
static void test_exp_neg_error_bound(void **unused)
{
    (void)unused;
    assert_int_equal(ss_exp_neg_q16_q30(0), SS_Q30_ONE);
    assert_int_equal(ss_exp_neg_q16_q30(-5 * SS_Q16_ONE), SS_Q30_ONE);
    double worst = 0.0;
    int32_t prev = SS_Q30_ONE;
    for (int32_t x = 0; x < 32 * SS_Q16_ONE; x += 16) {
        const int32_t q = ss_exp_neg_q16_q30(x);
        const double err = fabs((double)q / (double)SS_Q30_ONE - exp(-(double)x / SS_Q16_ONE));
        worst = err > worst ? err : worst;
        if (q > prev) {
            fail_msg("not monotone at x = %d: %d after %d", x, q, prev);
        }
        prev = q;
    }
    print_message("exp(-x), Q16.16 -> Q1.30: worst absolute error %.3g (2^%.1f)\n", worst, log2(worst));
    assert_true(worst < ldexp(1.0, -26));
    assert_int_equal(ss_exp_neg_q16_q30(INT32_MAX), 0);
}

/* Every Q16.16 input up to where the result is 0 (x = 21.5): non-increasing (the header's promise:
 * the table's steps and the polynomial must meet without a rise at the 256 joins), within the
 * grid test's bound; and the M0+'s products from 16-bit halves (unsigned, signed) against the plain ones. */
static void test_exp_neg_every_input(void **unused)
{
    (void)unused;
    int32_t prev = SS_Q30_ONE;
    double worst = 0.0;
    for (int32_t x = 0; x < 22 * SS_Q16_ONE; ++x) {
        const int32_t q = ss_exp_neg_q16_q30(x);
        if (q > prev) {
            fail_msg("not monotone at x = %d: %d after %d", x, q, prev);
        }
        prev = q;
        worst = fmax(worst, fabs((double)q / (double)SS_Q30_ONE - exp(-(double)x / SS_Q16_ONE)));
    }
    print_message("exp(-x), every Q16.16 input: worst absolute error %.3g (2^%.1f)\n", worst, log2(worst));
    assert_true(worst < ldexp(1.0, -26));
    assert_int_equal(prev, 0);
    static const uint32_t edge[] = {0u,          1u,          0xFFFFu,     0x10000u,
                                    0x7FFFFFFFu, 0x80000000u, 0xFFFF0000u, 0xFFFFFFFFu};
    for (size_t i = 0; i < sizeof edge / sizeof edge[0]; ++i) {
        for (size_t j = 0; j < sizeof edge / sizeof edge[0]; ++j) {
            assert_true(ss_mul_u32_u64_halves(edge[i], edge[j]) == (uint64_t)edge[i] * edge[j]);
        }
    }
    static const int32_t sedge[] = {0, 1, -1, 0xFFFF, -0x10000, INT32_MAX, INT32_MIN, INT32_MIN + 1};
    for (size_t i = 0; i < sizeof sedge / sizeof sedge[0]; ++i) {
        for (size_t j = 0; j < sizeof sedge / sizeof sedge[0]; ++j) {
            assert_true(ss_mul_s32_s64_halves(sedge[i], sedge[j]) == (int64_t)sedge[i] * sedge[j]);
        }
    }
    uint32_t a = 12345u;
    uint32_t b = 678910u;
    for (int i = 0; i < 1000000; ++i) {
        a = a * 1664525u + 1013904223u; /* two linear congruential streams */
        b = b * 22695477u + 1u;
        if (ss_mul_u32_u64_halves(a, b) != (uint64_t)a * b) {
            fail_msg("%u x %u: halves give a different product", a, b);
        }
        const int32_t sa = (int32_t)(a ^ 0x80000000u);
        const int32_t sb = (int32_t)b;
        if (ss_mul_s32_s64_halves(sa, sb) != (int64_t)sa * sb) {
            fail_msg("%d x %d: signed halves give a different product", sa, sb);
        }
    }
}

/* int32 times uint32 (the rod's kick, past 2^31 in a coarse step): the step's form and the M0+'s
 * halves against the plain 64-bit product, at the edges and on a million pairs. */
static void test_mul_signed_unsigned(void **unused)
{
    (void)unused;
    static const int32_t sedge[] = {0, 1, -1, 0xFFFF, -0x10000, INT32_MAX, INT32_MIN, INT32_MIN + 1};
    static const uint32_t edge[] = {0u,          1u,          0xFFFFu,     0x10000u,
                                    0x7FFFFFFFu, 0x80000000u, 0xFFFF0000u, 0xFFFFFFFFu};
    for (size_t i = 0; i < sizeof sedge / sizeof sedge[0]; ++i) {
        for (size_t j = 0; j < sizeof edge / sizeof edge[0]; ++j) {
            const int64_t p = (int64_t)sedge[i] * (int64_t)edge[j];
            assert_true(ss_mul_s32_u32_s64(sedge[i], edge[j]) == p);
            assert_true(ss_mul_s32_u32_s64_halves(sedge[i], edge[j]) == p);
        }
    }
    uint32_t a = 2891336453u;
    uint32_t b = 362436069u;
    for (int i = 0; i < 1000000; ++i) {
        a = a * 1664525u + 1013904223u;
        b = b * 22695477u + 1u;
        const int32_t sa = (int32_t)(a ^ 0x80000000u);
        const int64_t p = (int64_t)sa * (int64_t)b;
        if (ss_mul_s32_u32_s64(sa, b) != p || ss_mul_s32_u32_s64_halves(sa, b) != p) {
            fail_msg("%d x %u: a different product", sa, b);
        }
    }
}

/* uint64 times uint32 (the player's n steps): the M0+'s form against the plain product's low 64
 * bits, and the overflow test against a > UINT64_MAX / b, at the edges and on a million pairs; the
 * product by a sign against the plain one. */
static void test_mul_u64_u32(void **unused)
{
    (void)unused;
    static const uint64_t aedge[] = {
        0u,        1u, 0xFFFFFFFFu, 0x100000000u, 0x20000000000000u, UINT64_MAX / 64u, UINT64_MAX / 64u + 1u,
        UINT64_MAX};
    static const uint32_t edge[] = {0u, 1u, 2u, 64u, 0xFFFFu, 0x10000u, 0x80000000u, 0xFFFFFFFFu};
    for (size_t i = 0; i < sizeof aedge / sizeof aedge[0]; ++i) {
        for (size_t j = 0; j < sizeof edge / sizeof edge[0]; ++j) {
            const uint64_t a = aedge[i];
            const uint32_t b = edge[j];
            uint64_t p = 0u;
            assert_true(ss_mul_u64_u32_halves(a, b) == a * b);
            const int over = ss_mul_u64_u32_overflows(a, b, &p);
            assert_int_equal(over, b != 0u && a > UINT64_MAX / b);
            assert_true(over || p == a * b);
        }
    }
    uint64_t a = 88172645463325252ull;
    uint32_t b = 362436069u;
    for (int i = 0; i < 1000000; ++i) {
        a ^= a << 13; /* xorshift64 */
        a ^= a >> 7;
        a ^= a << 17;
        b = b * 22695477u + 1u;
        const uint32_t n = (i & 1) ? b : (b >> 26); /* small n, as the player's, and any */
        const uint64_t x = (i & 2) ? a : (a >> 8);
        uint64_t p = 0u;
        if (ss_mul_u64_u32_halves(x, n) != x * n) {
            fail_msg("%llu x %u: halves give a different product", (unsigned long long)x, n);
        }
        const int over = n != 0u && x > UINT64_MAX / n;
        if (ss_mul_u64_u32_overflows(x, n, &p) != over || (!over && p != x * n)) {
            fail_msg("%llu x %u: a wrong overflow test", (unsigned long long)x, n);
        }
    }
    static const int64_t v[] = {0, 1, -1, INT64_MAX, -INT64_MAX};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; ++i) {
        for (size_t j = 0; j < sizeof v / sizeof v[0]; ++j) {
            const int64_t sign = (v[j] > 0) ? 1 : ((v[j] < 0) ? -1 : 0);
            assert_true(ss_times_sign_of(v[i], v[j]) == sign * v[i]);
        }
    }
}

/* The Q32 argument: same bound plus the linearised tail (2^-33) and rounding (2^-31), and
 * 1 - exp(-x) resolved for x far below the Q16 quantum (the Masing branch after a reversal). */
static void test_exp_neg_q32_error_bound(void **unused)
{
    (void)unused;
    const double bound = ldexp(1.0, -26) + ldexp(1.0, -31);
    double worst = 0.0;
    for (uint64_t x = 0; x < ((uint64_t)24 << 32); x += 0x1234567ull) {
        const double err = fabs(ss_exp_neg_q32_q30(x) / (double)SS_Q30_ONE - exp(-ldexp((double)x, -32)));
        worst = err > worst ? err : worst;
    }
    print_message("exp(-x), Q32 -> Q1.30: worst absolute error %.3g (2^%.1f)\n", worst, log2(worst));
    assert_true(worst < bound);
    /* x = 1000 x 2^-32 (2.3e-7) lies inside one Q16 quantum: 1 - e must still be x to 1 % */
    const double one_minus = 1.0 - ss_exp_neg_q32_q30(1000u) / (double)SS_Q30_ONE;
    assert_close(one_minus, ldexp(1000.0, -32), 0.01 * ldexp(1000.0, -32));
    assert_int_equal(ss_exp_neg_q32_q30(0u), SS_Q30_ONE);
    assert_int_equal(ss_exp_neg_q32_q30(UINT64_MAX), 0);
}

/* Gross sliding's shortcuts, the bits the long way gives: from r = |v| / vs = 303 791 / 2^16
 * (4.64) exp(-r^2) is 0 in Q30, so g is Fc and its slope 0 without the exponential; just below,
 * the exponential's own rounding decides; and 1/g there is the config's Fc reciprocal,
 * ss_reciprocal_mantissa_q's of Fc. */
static void test_q_stribeck_in_gross_sliding(void **unused)
{
    (void)unused;
    /* a contact with Fs - Fc of 29 N, so that an exponential of 1 (2^-30) still moves g by one
     * unit: Table I's 0.6 N rounds e <= 53 away, and would not tell */
    ss_friction_config_q_t wide = ss_friction_config_table1_q();
    wide.fs_q24 = 30 << 24;
    wide.fc_q24 = 1 << 24;
    ss_friction_config_reciprocals_q(&wide);
    assert_int_equal(ss_friction_config_check_q(&wide, NULL), SS_OK);
    const ss_friction_config_q_t *f = &wide;
    assert_int_equal(ss_exp_neg_q32_q30((uint64_t)303791 * 303791), 0);
    /* r = v_q28 inv_vs_q45 / 2^29: the speeds around the threshold, a 2^-28 m/s apart */
    const double v_zero = 303791.0 * 0x1p29 / (double)f->inv_vs_q45;
    int32_t prev = INT32_MAX;
    for (int32_t v = (int32_t)(0.95 * v_zero); v < (int32_t)v_zero + 3000; ++v) {
        int32_t slope = 1;
        const int32_t g = ss_stribeck_with_slope_q(f, v, &slope);
        assert_int_equal(ss_stribeck_q(f, v), g);
        assert_int_equal(ss_stribeck_q(f, -v), g);
        assert_true(g <= prev && g >= f->fc_q24); /* falling to Fc, never below */
        const int64_t r = ((int64_t)v * f->inv_vs_q45 + ((int64_t)1 << 28)) >> 29;
        /* the long way: Fc + (Fs - Fc) exp(-r^2), rounded as the library does */
        const int64_t e = ss_exp_neg_q32_q30((uint64_t)r * (uint64_t)r);
        assert_int_equal(g, f->fc_q24 + (((int64_t)(f->fs_q24 - f->fc_q24) * e + (1 << 29)) >> 30));
        if (r >= 303791) {
            assert_int_equal(g, f->fc_q24);
            assert_int_equal(slope, 0);
        }
        prev = g;
    }
    int sh = 0;
    assert_int_equal(ss_reciprocal_mantissa_q((uint32_t)f->fc_q24, &sh), f->fc_recip_mantissa);
    assert_int_equal(sh, f->fc_recip_shift);
    const ss_friction_config_q_t table1 = ss_friction_config_table1_q();
    assert_int_equal(ss_reciprocal_mantissa_q((uint32_t)table1.fc_q24, &sh), table1.fc_recip_mantissa);
    assert_int_equal(sh, table1.fc_recip_shift);
    ss_actuator_config_q_t t = ss_actuator_config_table1_q();
    const char *bad = NULL;
    t.friction.fc_recip_mantissa += 1; /* a config whose reciprocal is not its own */
    assert_int_equal(ss_actuator_config_check_q(&t, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "friction.fc_recip_mantissa");
    t = ss_actuator_config_table1_q();
    t.friction.fc_recip_shift -= 1;
    assert_int_equal(ss_actuator_config_check_q(&t, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "friction.fc_recip_shift");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_q_stribeck_in_gross_sliding),
        cmocka_unit_test(test_sat32),
        cmocka_unit_test(test_shr_round),
        cmocka_unit_test(test_mul_shr_round_wide),
        cmocka_unit_test(test_velocity_by_reciprocal),
        cmocka_unit_test(test_ratio_x65536_one_division),
        cmocka_unit_test(test_reciprocal_mantissa),
        cmocka_unit_test(test_mul_recip),
        cmocka_unit_test(test_mul_shr_round_u49),
        cmocka_unit_test(test_ratio_x65536_by_reciprocal),
        cmocka_unit_test(test_exp_neg_error_bound),
        cmocka_unit_test(test_exp_neg_every_input),
        cmocka_unit_test(test_mul_signed_unsigned),
        cmocka_unit_test(test_mul_u64_u32),
        cmocka_unit_test(test_exp_neg_q32_error_bound),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
