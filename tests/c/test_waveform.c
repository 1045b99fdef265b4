/* The sawtooth of stick-slip-dataset/1 and the sampled drive. */
#include "ss_test.h"

#include "ss_waveform.h"

static void test_sawtooth_forward_shape(void **unused)
{
    (void)unused;
    /* 1 kHz, rise 0.8: 0 -> 10 V over 800 us, back to 0 over 200 us; offset 1 V */
    ss_waveform_config_f32_t w = ss_waveform_sawtooth_f32(1000.0f, 10.0f, 1.0f, 0.8f, 1, 2);
    ss_waveform_state_f32_t st;
    assert_int_equal(ss_waveform_init_f32(&w, 1e-6f, &st), SS_OK);
    float v[2501];
    for (int k = 0; k <= 2500; ++k) {
        v[k] = ss_waveform_value_f32(&w, &st);
        ss_waveform_advance_f32(&st);
    }
    assert_close(v[0], 1.0f, 1e-6f);
    assert_close(v[400], 6.0f, 1e-4f);
    assert_close(v[800], 11.0f, 1e-3f);
    assert_close(v[900], 6.0f, 1e-3f);
    assert_close(v[1000], 1.0f, 1e-3f);
    assert_close(v[1400], 6.0f, 1e-3f);
    assert_close(v[2000], 1.0f, 1e-3f); /* after the last cycle: held at offset */
    assert_close(v[2300], 1.0f, 0.0f);
}

static void test_sawtooth_reverse_is_time_reversed(void **unused)
{
    (void)unused;
    ss_waveform_config_f32_t f = ss_waveform_sawtooth_f32(1000.0f, 10.0f, 0.0f, 0.8f, 1, 1);
    ss_waveform_config_f32_t r = ss_waveform_sawtooth_f32(1000.0f, 10.0f, 0.0f, 0.8f, -1, 1);
    for (int k = 1; k < 1000; ++k) {
        const float p = (float)k / 1000.0f;
        assert_close(ss_sawtooth_at_phase_f32(&r, p), ss_sawtooth_at_phase_f32(&f, 1.0f - p), 1e-4f);
    }
    /* the reversed period rises fast: at 10 % it is at half amplitude */
    assert_close(ss_sawtooth_at_phase_f32(&r, 0.1f), 5.0f, 1e-4f);
}

/* Edges stay on time over many periods: no accumulated float drift. */
static void test_long_run_keeps_phase(void **unused)
{
    (void)unused;
    ss_waveform_config_f32_t w = ss_waveform_sawtooth_f32(300.0f, 1.0f, 0.0f, 0.5f, 1, 100000);
    ss_waveform_state_f32_t st;
    ss_waveform_init_f32(&w, 1e-6f, &st);
    const uint32_t n = 100000000u; /* 100 s, 30000 periods */
    for (uint32_t k = 0; k < n; ++k) {
        ss_waveform_advance_f32(&st);
    }
    /* the player's clock (periods + time into the period) against n * dt in double */
    const double elapsed =
        (double)st.index * (double)st.period_s + (double)st.tau0_s + (double)st.j * (double)st.dt_s;
    const double expect = (double)n * (double)st.dt_s;
    print_message("after %u steps: clock error %.3g s\n", n, elapsed - expect);
    assert_true(fabs(elapsed - expect) < 0.5e-6); /* edges within half a step after 1e8 steps */
}

static void test_sampled_interpolates_and_holds(void **unused)
{
    (void)unused;
    const float s[3] = {0.0f, 10.0f, -10.0f};
    ss_waveform_config_f32_t w = ss_waveform_sawtooth_f32(1.0f, 0.0f, 0.0f, 0.5f, 1, 0);
    w.kind = SS_WAVE_SAMPLED;
    w.samples_v = s;
    w.n_samples = 3;
    w.sample_interval_s = 1e-3f;
    ss_waveform_state_f32_t st;
    assert_int_equal(ss_waveform_init_f32(&w, 1e-4f, &st), SS_OK);
    float v[40];
    for (int k = 0; k < 40; ++k) {
        v[k] = ss_waveform_value_f32(&w, &st);
        ss_waveform_advance_f32(&st);
    }
    assert_close(v[5], 5.0f, 1e-3f);
    assert_close(v[10], 10.0f, 1e-3f);
    assert_close(v[15], 0.0f, 1e-3f);
    assert_close(v[30], -10.0f, 0.0f);
}

/* fill gives, sample for sample, the advance-then-value sequence the actuator's run loop uses */
static void test_fill_matches_player(void **unused)
{
    (void)unused;
    ss_waveform_config_f32_t w = ss_waveform_sawtooth_f32(700.0f, 80.0f, 2.0f, 0.9f, -1, 3);
    ss_waveform_state_f32_t a, b;
    ss_waveform_init_f32(&w, 1e-6f, &a);
    ss_waveform_init_f32(&w, 1e-6f, &b);
    static float out[5000];
    assert_int_equal(ss_waveform_fill_f32(&w, &a, out, 5000), SS_OK);
    for (int k = 0; k < 5000; ++k) {
        ss_waveform_advance_f32(&b);
        assert_true(out[k] == ss_waveform_value_f32(&w, &b));
    }
    assert_memory_equal(&a, &b, sizeof a);
    assert_int_equal(ss_waveform_fill_f32(&w, &a, NULL, 1), SS_ERR_NULL);
    assert_int_equal(ss_waveform_fill_f32(&w, &a, NULL, 0), SS_OK);
}

/* Every corner the player reports over n steps: count, and the largest error of the time and
 * drive it gives against the analytic corners of a sawtooth (forward and reverse) or samples. */
typedef struct {
    int count;
    double worst_t_s, worst_v;
} corners_t;

static corners_t corners_over(const ss_waveform_config_f32_t *w, float dt, uint32_t n, const double *t_true,
                              const double *v_true, int n_true)
{
    ss_waveform_state_f32_t st;
    assert_int_equal(ss_waveform_init_f32(w, dt, &st), SS_OK);
    corners_t c = {0, 0.0, 0.0};
    for (uint32_t k = 0; k < n; ++k) {
        float frac = -1.0f;
        float v = 0.0f;
        if (ss_waveform_corner_f32(w, &st, &frac, &v)) {
            assert_true(frac > 0.0f && frac < 1.0f);
            assert_true(c.count < n_true);
            const double t = ((double)k + (double)frac) * (double)dt;
            c.worst_t_s = fmax(c.worst_t_s, fabs(t - t_true[c.count]));
            c.worst_v = fmax(c.worst_v, fabs((double)v - v_true[c.count]));
            c.count++;
        }
        ss_waveform_advance_f32(&st);
    }
    return c;
}

/* Corners inside steps: a 300 Hz sawtooth at 1 us has its corners off the grid but for the second
 * peak (1.95 periods = 6500 us; reversed, 1.05 periods = 3500 us): 3 corners in two periods, the
 * last where the drive starts to hold. A 500 Hz one at 1 us has them on it (none reported), and a
 * drive sampled every 2.5 us bends inside a 1 us step at 2.5 and 7.5 us. */
static void test_corners_inside_steps(void **unused)
{
    (void)unused;
    const double p = 1.0 / 300.0;
    ss_waveform_config_f32_t w = ss_waveform_sawtooth_f32(300.0f, 100.0f, 5.0f, 0.95f, 1, 2);
    const double t_fwd[3] = {0.95 * p, p, 2.0 * p};
    const double v_fwd[3] = {105.0, 5.0, 5.0};
    corners_t c = corners_over(&w, 1e-6f, 8000u, t_fwd, v_fwd, 3);
    print_message("300 Hz: %d corners, time within %.3g s, drive within %.3g V\n", c.count, c.worst_t_s,
                  c.worst_v);
    assert_int_equal(c.count, 3);
    assert_true(c.worst_t_s < 2e-9); /* float32 time into a 3.3 ms period: a few ulp of 2.4e-10 s */
    assert_true(c.worst_v == 0.0);
    w.direction = -1; /* the peak at 0.05 of the period */
    const double t_rev[3] = {0.05 * p, p, 2.0 * p};
    c = corners_over(&w, 1e-6f, 8000u, t_rev, v_fwd, 3);
    assert_int_equal(c.count, 3);
    assert_true(c.worst_t_s < 2e-9);
    /* on the grid */
    ss_waveform_config_f32_t paper = ss_waveform_paper_f32();
    c = corners_over(&paper, 1e-6f, 20000u, t_fwd, v_fwd, 0);
    assert_int_equal(c.count, 0);
    /* sampled: 0, 1, 0, 1 V every 2.5 us; corners at 2.5 and 7.5 us fall inside 1 us steps (5 us is
     * on the grid), and the last sample (10 us) too */
    static const float samples[5] = {0.0f, 1.0f, 0.0f, 1.0f, 0.0f};
    ss_waveform_config_f32_t sw = ss_waveform_sawtooth_f32(1.0f, 1.0f, 0.0f, 0.5f, 1, 1);
    sw.kind = SS_WAVE_SAMPLED;
    sw.samples_v = samples;
    sw.n_samples = 5u;
    sw.sample_interval_s = 2.5e-6f;
    const double t_s[2] = {2.5e-6, 7.5e-6};
    const double v_s[2] = {1.0, 1.0};
    c = corners_over(&sw, 1e-6f, 12u, t_s, v_s, 2);
    assert_int_equal(c.count, 2);
    assert_true(c.worst_t_s < 1e-12);
}

static void test_waveform_validation(void **unused)
{
    (void)unused;
    ss_waveform_state_f32_t st;
    ss_waveform_config_f32_t w = ss_waveform_sawtooth_f32(500.0f, 100.0f, 0.0f, 0.95f, 1, 1);
    assert_int_equal(ss_waveform_init_f32(&w, 1e-6f, &st), SS_OK);
    assert_int_equal(ss_waveform_init_f32(NULL, 1e-6f, &st), SS_ERR_NULL);
    assert_int_equal(ss_waveform_init_f32(&w, NAN, &st), SS_ERR_NONFINITE);
    w.rise_fraction = 1.0f;
    assert_int_equal(ss_waveform_init_f32(&w, 1e-6f, &st), SS_ERR_RANGE);
    w.rise_fraction = 0.5f;
    w.direction = 0;
    assert_int_equal(ss_waveform_init_f32(&w, 1e-6f, &st), SS_ERR_RANGE);
    w.direction = 1;
    w.frequency_hz = NAN;
    assert_int_equal(ss_waveform_init_f32(&w, 1e-6f, &st), SS_ERR_NONFINITE);
    w.frequency_hz = -5.0f;
    assert_int_equal(ss_waveform_init_f32(&w, 1e-6f, &st), SS_ERR_RANGE);
    const float bad[2] = {0.0f, NAN};
    w = ss_waveform_sawtooth_f32(1.0f, 0.0f, 0.0f, 0.5f, 1, 0);
    w.kind = SS_WAVE_SAMPLED;
    w.samples_v = bad;
    w.n_samples = 2;
    w.sample_interval_s = 1e-3f;
    assert_int_equal(ss_waveform_init_f32(&w, 1e-6f, &st), SS_ERR_NONFINITE);
    w.samples_v = NULL;
    assert_int_equal(ss_waveform_init_f32(&w, 1e-6f, &st), SS_ERR_NULL);
    w.kind = 7;
    assert_int_equal(ss_waveform_init_f32(&w, 1e-6f, &st), SS_ERR_RANGE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sawtooth_forward_shape),
        cmocka_unit_test(test_sawtooth_reverse_is_time_reversed),
        cmocka_unit_test(test_long_run_keeps_phase),
        cmocka_unit_test(test_sampled_interpolates_and_holds),
        cmocka_unit_test(test_fill_matches_player),
        cmocka_unit_test(test_corners_inside_steps),
        cmocka_unit_test(test_waveform_validation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
