/* The float family's own exponential (lib/src/ss_exp_f32.h): its stated error bound against
 * float64, exactness at 0, and its edges (underflow, infinity, NaN). */
#include "ss_test.h"

#include "ss_exp_f32.h"

/* The header's bound: 2.5e-7 relative, about 2 units in the last place of a float. The measured
 * worst case is 1.0e-7 (exp) and 1.7e-7 (expm1, at the reduction's edge |r| = ln2 / 2). */
#define EXP_REL_BOUND 2.5e-7

static void check_at(float a, double *worst_e, double *worst_m)
{
    float e;
    const float m = ss_expm1_neg_f32(a, &e);
    const double te = exp(-(double)a);
    const double tm = expm1(-(double)a);
    const double re = fabs((double)e - te) / te;
    const double rm = fabs((double)m - tm) / fabs(tm);
    if (re > *worst_e) {
        *worst_e = re;
    }
    if (a > 0.0f && rm > *worst_m) {
        *worst_m = rm;
    }
    if (!(re <= EXP_REL_BOUND) || !(a == 0.0f || rm <= EXP_REL_BOUND)) {
        fail_msg("a = %.9g: exp rel error %.3g, expm1 rel error %.3g (bound %.3g)", (double)a, re, rm,
                 EXP_REL_BOUND);
    }
}

/* Dense sweeps, linear over the whole domain and logarithmic from 1e-9 (the small arguments of a
 * Masing branch right after a reversal, where expm1 must keep its digits), and every float
 * around the reduction's seams n ln2 +- ln2/2. */
static void test_exp_neg_accuracy(void **unused)
{
    (void)unused;
    double we = 0.0;
    double wm = 0.0;
    const int n = 2000000;
    for (int i = 0; i <= n; ++i) {
        check_at((float)(87.29 * (double)i / n), &we, &wm);
        check_at((float)(1e-9 * pow(87.29e9, (double)i / n)), &we, &wm);
    }
    for (int k = 0; k < 126; ++k) {
        float a = (float)((k + 0.5) * 0.69314718055994531);
        for (int j = 0; j < 64; ++j) {
            a = nextafterf(a, 0.0f);
        }
        for (int j = 0; j < 128; ++j) {
            check_at(a, &we, &wm);
            a = nextafterf(a, 100.0f);
        }
    }
    print_message("worst relative error: exp %.3g, expm1 %.3g\n", we, wm);
}

static void test_exp_neg_edges(void **unused)
{
    (void)unused;
    float e;
    /* exactly 1 and 0 at 0: a sticking contact, where the step's relaxations must be the identity */
    assert_true(ss_expm1_neg_f32(0.0f, &e) == 0.0f);
    assert_true(e == 1.0f);
    /* below FLT_MIN: 0 and -1, no denormals */
    assert_true(ss_expm1_neg_f32(87.3f, &e) == -1.0f);
    assert_true(e == 0.0f);
    assert_true(ss_expm1_neg_f32(INFINITY, &e) == -1.0f);
    assert_true(e == 0.0f);
    /* just above the cut: a normal float */
    assert_true(ss_exp_neg_f32(87.29f) >= 1.17549435e-38f);
    /* NaN in, NaN out (the callers' checks see it) */
    assert_true(isnan(ss_expm1_neg_f32(NAN, &e)));
    assert_true(isnan(e));
    /* monotone: a larger argument never gives a larger exponential */
    float prev = 1.0f;
    for (float a = 0.0f; a < 20.0f; a += 1e-3f) {
        const float x = ss_exp_neg_f32(a);
        assert_true(x <= prev);
        prev = x;
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exp_neg_accuracy),
        cmocka_unit_test(test_exp_neg_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
