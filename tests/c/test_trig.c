/* The float family's own sine and cosine (lib/src/ss_trig_f32.h): their stated error bounds against
 * float64 over the domain, relative near 0 (a corner just after a step's start, where sin(w t)/w
 * must keep its digits), and the domain's edges. */
#include "ss_test.h"

#include "ss_trig_f32.h"

/* The header's bounds: 1.2e-7 absolute over the domain (two half units of a float at 1), 1.5e-7
 * relative for the sine below pi/4 (no reduction there). Measured: 8.6e-8 and 6.6e-8. */
#define TRIG_ABS_BOUND 1.2e-7
#define SIN_REL_BOUND 1.5e-7

typedef struct {
    double abs_s, abs_c, rel_s;
} worst_t;

static void check_at(float x, worst_t *w)
{
    float s;
    float c;
    ss_sincos_f32(x, &s, &c);
    const double es = fabs((double)s - sin((double)x));
    const double ec = fabs((double)c - cos((double)x));
    w->abs_s = fmax(w->abs_s, es);
    w->abs_c = fmax(w->abs_c, ec);
    if (!(es <= TRIG_ABS_BOUND) || !(ec <= TRIG_ABS_BOUND)) {
        fail_msg("x = %.9g: sin error %.3g, cos error %.3g (bound %.3g)", (double)x, es, ec, TRIG_ABS_BOUND);
    }
    if (x > 0.0f && x < 0.78f) {
        const double rs = es / sin((double)x);
        w->rel_s = fmax(w->rel_s, rs);
        if (!(rs <= SIN_REL_BOUND)) {
            fail_msg("x = %.9g: sin relative error %.3g (bound %.3g)", (double)x, rs, SIN_REL_BOUND);
        }
    }
}

/* Dense sweeps, linear over the domain and logarithmic from 1e-9, and every float around the
 * reduction's seams (n + 1/2) pi/2, where the quadrant changes. */
static void test_sincos_accuracy(void **unused)
{
    (void)unused;
    worst_t w = {0.0, 0.0, 0.0};
    const int n = 2000000;
    for (int i = 0; i < n; ++i) {
        check_at((float)(4095.99 * (double)i / n), &w);
        check_at((float)(1e-9 * pow(4095.99e9, (double)i / n)), &w);
    }
    for (int k = 0; k < 2607; k += (k < 64) ? 1 : 37) {
        float x = (float)((k + 0.5) * 1.5707963267948966);
        for (int j = 0; j < 64; ++j) {
            x = nextafterf(x, 0.0f);
        }
        for (int j = 0; j < 128; ++j) {
            check_at(x, &w);
            x = nextafterf(x, 5000.0f);
        }
    }
    print_message("worst error: sin %.3g, cos %.3g absolute; sin %.3g relative below pi/4\n", w.abs_s,
                  w.abs_c, w.rel_s);
}

static void test_sincos_edges(void **unused)
{
    (void)unused;
    float s;
    float c;
    /* exactly 0 and 1 at 0: a corner on the step's start leaves the flow the identity */
    ss_sincos_f32(0.0f, &s, &c);
    assert_true(s == 0.0f && c == 1.0f);
    /* |sin|, |cos| never above 1 (the flow matrix must not grow from rounding alone) */
    for (float x = 0.0f; x < 40.0f; x += 1e-4f) {
        ss_sincos_f32(x, &s, &c);
        assert_true(fabsf(s) <= 1.0f && fabsf(c) <= 1.0f);
    }
    /* outside the domain: NaN, which the callers' checks see */
    ss_sincos_f32(-1e-30f, &s, &c);
    assert_true(isnan(s) && isnan(c));
    ss_sincos_f32(SS_TRIG_MAX_ARG, &s, &c);
    assert_true(isnan(s) && isnan(c));
    ss_sincos_f32(NAN, &s, &c);
    assert_true(isnan(s) && isnan(c));
    ss_sincos_f32(INFINITY, &s, &c);
    assert_true(isnan(s) && isnan(c));
    /* just inside the top: finite */
    ss_sincos_f32(nextafterf(SS_TRIG_MAX_ARG, 0.0f), &s, &c);
    assert_true(isfinite(s) && isfinite(c));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sincos_accuracy),
        cmocka_unit_test(test_sincos_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
