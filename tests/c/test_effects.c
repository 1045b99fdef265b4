/* The optional effects of the diagnosis catalog: each one does what its physics says, and off
 * (zero) it changes nothing. */
#include "ss_test.h"

#include <string.h>

#include "ss_actuator.h"

#define PI 3.14159265358979323846

static double slider_x(const ss_actuator_state_f32_t *st)
{
    return (double)st->x_slider.hi_m + (double)st->x_slider.lo_m;
}

/* Play n periods of a 100 V sawtooth at f_hz from the actuator's present state; returns the
 * slider travel over the last n - 1. */
static double play_steps(const ss_actuator_config_f32_t *c, ss_actuator_state_f32_t *st, float f_hz, int dir,
                         uint32_t n)
{
    ss_waveform_config_f32_t w = ss_waveform_sawtooth_f32(f_hz, 100.0f, 0.0f, 0.95f, dir, n);
    ss_waveform_state_f32_t ws;
    assert_int_equal(ss_waveform_init_f32(&w, c->dt_s, &ws), SS_OK);
    double x1 = 0.0;
    while (ws.index < n) {
        ss_waveform_advance_f32(&ws);
        assert_int_equal(ss_actuator_step_f32(c, st, ss_waveform_value_f32(&w, &ws)), SS_OK);
        if (ws.index == 1u && ws.j == 0u) {
            x1 = slider_x(st);
        }
    }
    return slider_x(st) - x1;
}

/* The same from rest. */
static double run_steps(const ss_actuator_config_f32_t *c, ss_actuator_state_f32_t *st, float f_hz, int dir,
                        uint32_t n)
{
    assert_int_equal(ss_actuator_init_f32(c, st, 0.0f), SS_OK);
    return play_steps(c, st, f_hz, dir, n);
}

static void test_check_names_fields(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    const char *bad = NULL;
    assert_int_equal(ss_actuator_config_check_f32(&c, &bad), SS_OK);
    c.effects.hysteresis_alpha = 0.2f; /* on, but no width */
    assert_int_equal(ss_actuator_config_check_f32(&c, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "effects.hysteresis_width_m");
    c = ss_actuator_config_table1_f32();
    c.effects.creep_tau_s = NAN;
    assert_int_equal(ss_actuator_config_check_f32(&c, &bad), SS_ERR_NONFINITE);
    assert_string_equal(bad, "effects.creep_tau_s");
    c = ss_actuator_config_table1_f32();
    c.effects.slew_v_per_s = -5.0f;
    assert_int_equal(ss_actuator_config_check_f32(&c, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "effects.slew_v_per_s");
    c = ss_actuator_config_table1_f32();
    c.effects.base_mass_kg = 0.01f; /* on, base_freq_hz 0 */
    assert_int_equal(ss_actuator_config_check_f32(&c, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "effects.base_freq_hz");
    c = ss_actuator_config_table1_f32();
    c.friction.asymmetry = 1.5f;
    assert_int_equal(ss_actuator_config_check_f32(&c, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "friction.asymmetry");
}

/* Off is off: companions of a disabled effect change nothing, to the bit. */
static void test_off_is_bit_identical(void **unused)
{
    (void)unused;
    const ss_actuator_config_f32_t a = ss_actuator_config_table1_f32();
    ss_actuator_config_f32_t b = a;
    b.effects.hysteresis_width_m = 1e-6f;
    b.effects.creep_tau_s = 0.1f;
    b.effects.thermal_tau_s = 1.0f;
    b.effects.base_freq_hz = 2000.0f;
    ss_actuator_state_f32_t sa;
    ss_actuator_state_f32_t sb;
    const double da = run_steps(&a, &sa, 500.0f, 1, 4);
    const double db = run_steps(&b, &sb, 500.0f, 1, 4);
    assert_true(da == db);
    assert_true(memcmp(&sa.x_slider, &sb.x_slider, sizeof sa.x_slider) == 0);
}

/* A load below break-away is held in presliding: the slider rings about a rest point but does
 * not creep away. Above Fs it slides off at the velocity where viscous friction takes the rest. */
static void test_external_load(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    ss_actuator_state_f32_t st;
    c.effects.load_n = 1.0f; /* Fs 3.6 N */
    assert_int_equal(ss_actuator_init_f32(&c, &st, 0.0f), SS_OK);
    double mean[2] = {0.0, 0.0};
    double peak = 0.0;
    for (int i = 0; i < 40000; ++i) {
        assert_int_equal(ss_actuator_step_f32(&c, &st, 0.0f), SS_OK);
        const double rel = slider_x(&st) - (double)st.x_rod_m;
        mean[i / 20000] += rel / 20000.0;
        peak = fmax(peak, fabs(rel));
    }
    /* Static deflection u on the virgin curve phi(x) = Fs (1 - exp(-sigma0 x / Fs)) = load. A
     * suddenly applied load overshoots to where its work equals the stored energy,
     * load x = Fs x - Fs^2 / sigma0 (1 - exp(-sigma0 x / Fs)); damping only lowers the peak. */
    const double fs = 3.6;
    const double s0 = 1e7;
    const double u = -(fs / s0) * log(1.0 - 1.0 / fs);
    double lo = u;
    double hi = 10.0 * u;
    for (int k = 0; k < 60; ++k) {
        const double x = 0.5 * (lo + hi);
        const double excess = fs * x - fs * fs / s0 * (1.0 - exp(-s0 * x / fs)) - 1.0 * x;
        if (excess < 0.0) {
            lo = x;
        } else {
            hi = x;
        }
    }
    const double x_peak = lo;
    assert_true(mean[0] > u && mean[0] < x_peak);
    assert_true(peak < 1.05 * x_peak);        /* 5 %: the rod's own 5 nm deflection on the piezo */
    assert_close(mean[1], mean[0], 0.01 * u); /* no creep: the two 20 ms means agree */

    c.effects.load_n = 4.0f; /* above Fs: slides off to the terminal velocity (load - Fc) / sigma2 */
    assert_int_equal(ss_actuator_init_f32(&c, &st, 0.0f), SS_OK);
    for (int i = 0; i < 50000; ++i) { /* 50 ms: time constant m / sigma2 = 1.7 ms */
        assert_int_equal(ss_actuator_step_f32(&c, &st, 0.0f), SS_OK);
    }
    assert_close(st.v_slider_m_per_s, (4.0 - 3.0) / 8.0, 1e-3 * 0.125);
}

/* g(v) scales by 1 + a sgn(v); forward and reverse steps part ways accordingly. */
static void test_asymmetric_friction(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    c.friction.asymmetry = 0.1f;
    assert_close(ss_asymmetry_factor_f32(&c.friction, 1e-3f), 1.1, 1e-7);
    assert_close(ss_asymmetry_factor_f32(&c.friction, -1e-3f), 0.9, 1e-7);
    assert_close(ss_asymmetry_factor_f32(&c.friction, 0.0f), 1.0, 0.0);
    ss_actuator_state_f32_t st;
    const double fwd = run_steps(&c, &st, 500.0f, 1, 5);
    const double rev = run_steps(&c, &st, 500.0f, -1, 5);
    c.friction.asymmetry = 0.0f;
    const double fwd0 = run_steps(&c, &st, 500.0f, 1, 5);
    const double rev0 = run_steps(&c, &st, 500.0f, -1, 5);
    /* forward slip (rod retracting under the slider) loads the contact in -x: weaker friction
     * there drags the slider back less, so forward steps grow; reverse steps shrink */
    assert_true(fwd > 1.05 * fwd0);
    assert_true(-rev < 0.95 * -rev0);
}

/* The amplifier output follows the command at the slew limit and catches up after the edge. */
static void test_slew_limit(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    c.effects.slew_v_per_s = 2e5f; /* 100 V in 500 us */
    ss_actuator_state_f32_t st;
    assert_int_equal(ss_actuator_init_f32(&c, &st, 0.0f), SS_OK);
    for (int i = 1; i <= 1000; ++i) {
        assert_int_equal(ss_actuator_step_f32(&c, &st, 100.0f), SS_OK);
        if (i == 250) {
            assert_close(st.fx.amp_v, 50.0, 1e-3);
            /* float32 sums 250 increments of 0.2 V: a relative error of a few 1e-6 */
            assert_close(st.x_p_m, 50.0 * 4.4e-8, 1e-5 * 2.2e-6);
        }
    }
    assert_close(st.fx.amp_v, 100.0, 0.0);
}

/* The amplifier's voltage behind a slew limit and a bandwidth, dV/dt = clamp((V_cmd - V) / tau,
 * -slew, +slew), in double by explicit Euler at 0.1 ns (tau is 1 us: the Euler error is 1e-4 of a
 * volt's lag at most, below the float tolerance below). cmd(t) is linear between the ends of
 * steps of dt, as the library's piecewise-exact solution takes it. */
static void amp_reference(double v, const float *cmd, int n, double dt, double tau, double slew, double *out)
{
    const int sub = (int)(dt / 1e-10 + 0.5);
    const double h = dt / sub;
    for (int k = 1; k < n; ++k) {
        for (int j = 0; j < sub; ++j) {
            const double c = cmd[k - 1] + (cmd[k] - cmd[k - 1]) * ((j + 0.5) / sub);
            double rate = (c - v) / tau;
            rate = (rate > slew) ? slew : ((rate < -slew) ? -slew : rate);
            v += rate * h;
        }
        out[k] = v;
    }
}

/* With a bandwidth the amplifier lags the command by rate x tau on a slow ramp, slews at the limit
 * on a fast edge and catches up along exp(-t / tau): every step's end against the reference, over
 * a rise, a 15 us fall at 6.7 V/us against a 1.44 V/us limit (in the band, out of it, a ramp that
 * outruns the slew from inside the band), the rise after it, and a turn while still slewing. */
static void test_amplifier_bandwidth(void **unused)
{
    (void)unused;
    ss_effects_config_f32_t e = ss_effects_config_none_f32();
    e.slew_v_per_s = 1.44e6f;
    e.amp_bandwidth_hz = 160e3f;
    const char *bad = NULL;
    assert_int_equal(ss_effects_config_check_f32(&e, &bad), SS_OK);
    const double tau = 1.0 / (2.0 * PI * 160e3);
    enum { N = 200 };
    float cmd[N];
    const float dt = 1e-6f;
    for (int k = 0; k < N; ++k) { /* 0.2 V/us up to 100 V, 15 us down, up again, steeper from 120 */
        double c = (k <= 50) ? 90.0 + 0.2 * k : (k <= 65) ? 100.0 - 100.0 * (k - 50) / 15.0 : 0.2 * (k - 65);
        if (k > 120) {
            c = 0.2 * 55 + 3.0 * (k - 120); /* a 3 V/us rise that outruns the slew */
        }
        cmd[k] = (float)c;
    }
    ss_effects_state_f32_t st;
    ss_effects_init_f32(&e, &st, 4.4e-8f, cmd[0]);
    double ref[N];
    amp_reference(cmd[0], cmd, N, dt, tau, 1.44e6, ref);
    double worst = 0.0;
    for (int k = 1; k < N; ++k) {
        const float x = ss_effects_drive_f32(&e, &st, 4.4e-8f, cmd[k], dt);
        assert_close(x, st.amp_v * 4.4e-8, 1e-6 * 4.4e-6);
        const double err = fabs((double)st.amp_v - ref[k]);
        worst = (err > worst) ? err : worst;
    }
    /* float32 over 100 V: a few 1e-5 V; the lag itself is up to 21 V on the fall */
    assert_true(worst < 2e-4);
    /* the settled lag on the first ramp is rate x tau (0.2 V/us x 0.995 us), to the reference */
    ss_effects_init_f32(&e, &st, 4.4e-8f, 0.0f);
    for (int k = 1; k <= 40; ++k) {
        (void)ss_effects_drive_f32(&e, &st, 4.4e-8f, 0.2f * (float)k, dt);
    }
    assert_close(8.0 - st.amp_v, 0.2e6 * tau, 1e-5);
    /* a slew limit too fast to act (1e12 V/s): the plain first-order lag of a held step */
    e.slew_v_per_s = 1e12f;
    ss_effects_init_f32(&e, &st, 4.4e-8f, 0.0f);
    (void)ss_effects_drive_f32(&e, &st, 4.4e-8f, 10.0f, 1e-9f); /* the step, in 1 ns */
    for (int k = 1; k <= 5; ++k) {
        (void)ss_effects_drive_f32(&e, &st, 4.4e-8f, 10.0f, dt);
        assert_close(st.amp_v, 10.0 * (1.0 - exp(-(k * 1e-6 + 0.5e-9) / tau)), 2e-5);
    }
    /* its range: 0 (unlimited) or at least 1 kHz, and only beside a slew limit */
    e.amp_bandwidth_hz = 500.0f;
    assert_int_equal(ss_effects_config_check_f32(&e, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "effects.amp_bandwidth_hz");
    e.amp_bandwidth_hz = 160e3f;
    e.slew_v_per_s = 0.0f;
    assert_int_equal(ss_effects_config_check_f32(&e, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "effects.amp_bandwidth_hz");
}

/* After a voltage step the strain creeps by ratio x gain x V with time constant tau. */
static void test_creep(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    c.effects.creep_ratio = 0.1f;
    c.effects.creep_tau_s = 2e-3f;
    ss_actuator_state_f32_t st;
    assert_int_equal(ss_actuator_init_f32(&c, &st, 0.0f), SS_OK);
    for (int i = 1; i <= 2000; ++i) { /* one tau */
        assert_int_equal(ss_actuator_step_f32(&c, &st, 100.0f), SS_OK);
    }
    const double expect = 4.4e-6 * (1.0 + 0.1 * (1.0 - exp(-1.0)));
    assert_close(st.x_p_m, expect, 1e-4 * expect);
}

/* Bouc-Wen: a slow and a fast voltage triangle trace the same loop (rate independence); the loop
 * opens by 2 alpha width (1 - exp(-stroke / width)) in the middle, about, and closes on return. */
static void test_hysteresis(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    c.effects.hysteresis_alpha = 0.15f;
    c.effects.hysteresis_width_m = 1e-6f;
    double mid_up[2];
    double mid_down[2];
    double end[2];
    for (int r = 0; r < 2; ++r) {
        const int n = (r == 0) ? 2000 : 20000; /* steps per edge: 10 x slower */
        ss_actuator_state_f32_t st;
        assert_int_equal(ss_actuator_init_f32(&c, &st, 0.0f), SS_OK);
        for (int i = 1; i <= 2 * n; ++i) {
            const float v = (i <= n) ? 100.0f * (float)i / (float)n : 100.0f * (float)(2 * n - i) / (float)n;
            assert_int_equal(ss_actuator_step_f32(&c, &st, v), SS_OK);
            if (i == n / 2) {
                mid_up[r] = st.x_p_m;
            }
            if (i == 3 * n / 2) {
                mid_down[r] = st.x_p_m;
            }
        }
        end[r] = st.x_p_m;
    }
    /* equal to float32 rounding of the strain summed over 2000 vs 20000 steps (1e-5 relative) */
    assert_close(mid_up[0], mid_up[1], 2e-11);
    assert_close(mid_down[0], mid_down[1], 2e-11);
    /* the loop is open in the middle by more than alpha width (h swings from -sat to +sat) */
    assert_true(mid_down[0] - mid_up[0] > 0.15 * 1e-6);
    assert_true(mid_down[0] - mid_up[0] < 2.0 * 0.15 * 1e-6);
    /* back at 0 V the hysteretic strain is near -alpha width: the strain undershoots */
    assert_close(end[0], 0.15 * 1e-6 * (1.0 - 2.0 * exp(-4.4)), 0.02e-6);
}

/* Heat stored from sliding lowers (coeff > 0) friction; it decays with tau at rest. */
static void test_thermal(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    ss_actuator_state_f32_t st;
    const double cold = run_steps(&c, &st, 500.0f, 1, 11);
    c.effects.thermal_coeff_per_j = 500.0f;
    c.effects.thermal_tau_s = 1.0f;
    const double warm = run_steps(&c, &st, 500.0f, 1, 11);
    /* per slip phase Fc x slip distance ~ 3 N x 4 um = 1.2e-5 J; ten periods store ~1e-4 J */
    assert_true(st.fx.heat_j > 0.5e-4f && st.fx.heat_j < 3e-4f);
    /* softer friction (coeff > 0) drags the slider back less: larger steps */
    assert_true(warm > cold + 1e-9);
    /* with no new dissipation the heat decays with tau: 10 ms of tau 1 s is exp(-0.01) */
    ss_effects_state_f32_t fx = st.fx;
    const float q = fx.heat_j;
    for (int i = 0; i < 10; ++i) {
        ss_effects_heat_f32(&c.effects, &fx, 0.0f, 1e-3f);
    }
    assert_close(fx.heat_j, (double)q * exp(-0.01), 1e-5 * (double)q);
}

/* Runs recorded one after another: the heat one run leaves is where the next starts. Given the
 * same heat, a run from a fresh init matches the continued one; garbage is taken as no heat. */
static void test_heat_carried(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    c.effects.thermal_coeff_per_j = 500.0f;
    c.effects.thermal_tau_s = 1.0f;
    ss_actuator_state_f32_t st;
    (void)run_steps(&c, &st, 500.0f, 1, 11);
    const float q = ss_actuator_heat_f32(&st);
    assert_true(q == st.fx.heat_j && q > 0.0f);
    const double cold = run_steps(&c, &st, 500.0f, 1, 11);
    assert_int_equal(ss_actuator_init_f32(&c, &st, 0.0f), SS_OK);
    assert_true(ss_actuator_heat_f32(&st) == 0.0f);
    ss_actuator_set_heat_f32(&st, q);
    /* warmer from the start: softer friction, longer steps than the cold run's */
    const double warm = play_steps(&c, &st, 500.0f, 1, 11);
    print_message("heat carried: cold %.5g um, warm start %.5g um over 10 periods\n", cold * 1e6, warm * 1e6);
    assert_true(warm > cold * 1.001);
    ss_actuator_set_heat_f32(&st, NAN);
    assert_true(ss_actuator_heat_f32(&st) == 0.0f);
    ss_actuator_set_heat_f32(&st, -1.0f);
    assert_true(ss_actuator_heat_f32(&st) == 0.0f);
    ss_actuator_set_heat_f32(&st, INFINITY);
    assert_true(ss_actuator_heat_f32(&st) == 0.0f);
}

/* The stack between base and rod pushes both alike: the base's kicks take -F_p, the rod's exact
 * flow F_p, with the damper on the stack's length rate in both. So rod, base and slider (friction is
 * internal) change their momentum only by the base's spring-damper to ground. A base on a soft
 * spring (10 Hz) under a 100 V ramp over 500 us, at a 0.5 us step: what is left is the splitting's
 * second-order error (the rod's force integrated exactly, the base's by its values at the step
 * ends): 2.2e-6 N s at 1 us, 5.0e-7 at 0.5 us, 9.7e-8 at 0.25 us. A damper on the strain rate on
 * the base's side only (the model before 2026-11-25) left 1.8e-5 N s at every step size. */
static void test_base_momentum_balance(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    c.dt_s = 0.5e-6f;
    c.effects.base_mass_kg = 0.03f;
    c.effects.base_freq_hz = 10.0f;
    c.effects.base_damping_ratio = 0.0f;
    ss_actuator_state_f32_t st;
    assert_int_equal(ss_actuator_init_f32(&c, &st, 0.0f), SS_OK);
    const double k_b = 0.03 * (2.0 * PI * 10.0) * (2.0 * PI * 10.0);
    double ground = 0.0; /* impulse of the base's spring to ground (trapezoid), N s */
    double worst = 0.0;
    for (int i = 1; i <= 1400; ++i) {
        const float v = (i < 1000) ? 0.1f * (float)i : 100.0f;
        ground -= k_b * (double)st.fx.x_base_m * 0.25e-6;
        assert_int_equal(ss_actuator_step_f32(&c, &st, v), SS_OK);
        ground -= k_b * (double)st.fx.x_base_m * 0.25e-6;
        const double p = (double)c.rod_mass_kg * (double)st.v_rod_m_per_s +
                         (double)c.effects.base_mass_kg * (double)st.fx.v_base_m_per_s +
                         (double)c.slider_mass_kg * (double)st.v_slider_m_per_s;
        worst = fmax(worst, fabs(p - ground));
    }
    print_message("base momentum balance: worst %.3g N s (a one-sided damper: 1.8e-5)\n", worst);
    assert_true(worst < 2e-6); /* 4 x the splitting's error, 9 x under a one-sided damper's */
}

/* A base on a spring: plucked together with rod and slider it rings at the lower mode of base+rod
 * (M1, the piezo is rigid at these frequencies) on k_b, coupled to the slider (M2) through the
 * presliding stiffness sigma0: M1 M2 w^4 - (M1 s0 + M2 (k_b + s0)) w^2 + k_b s0 = 0. */
static void test_base_compliance(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    c.effects.base_mass_kg = 0.05f;
    c.effects.base_freq_hz = 1500.0f;
    c.effects.base_damping_ratio = 0.0f;
    ss_actuator_state_f32_t st;
    assert_int_equal(ss_actuator_init_f32(&c, &st, 0.0f), SS_OK);
    /* 5 nm: presliding stays near its initial stiffness (sigma0 u / 2 Fs < 1 %) */
    st.fx.x_base_m = 5e-9f;
    st.x_rod_m = 5e-9f;
    ss_actuator_place_slider_f32(&st, 5e-9f);
    int crossings = 0;
    int first = -1;
    int last = -1;
    float prev = st.fx.x_base_m;
    for (int i = 1; i <= 20000; ++i) {
        assert_int_equal(ss_actuator_step_f32(&c, &st, 0.0f), SS_OK);
        if ((prev > 0.0f) != (st.fx.x_base_m > 0.0f)) {
            first = (first < 0) ? i : first;
            last = i;
            crossings++;
        }
        prev = st.fx.x_base_m;
    }
    assert_true(crossings > 10);
    const double period_s = 2.0 * (double)(last - first) * 1e-6 / (double)(crossings - 1);
    const double w_b = 2.0 * PI * 1500.0;
    const double kb = 0.05 * w_b * w_b;
    const double s0 = 1e7;
    const double m1 = 0.05 + 1.1e-3;
    const double m2 = 1.38e-2;
    const double bq = m1 * s0 + m2 * (kb + s0);
    const double w2 = (bq - sqrt(bq * bq - 4.0 * m1 * m2 * kb * s0)) / (2.0 * m1 * m2);
    const double expect = 2.0 * PI / sqrt(w2);
    /* 1 %: the upper mode's share of the pluck shifts zero crossings a little */
    assert_close(period_s, expect, 0.01 * expect);
}

/* The sensor scales what it reports; the slider itself is untouched. */
static void test_sensor_scale(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    c.effects.sensor_scale_error = 0.02f;
    ss_actuator_state_f32_t st;
    ss_actuator_state_f32_t st0;
    const ss_actuator_config_f32_t c0 = ss_actuator_config_table1_f32();
    assert_true(run_steps(&c, &st, 500.0f, 1, 3) == run_steps(&c0, &st0, 500.0f, 1, 3));
    float meas = 0.0f;
    ss_actuator_trace_f32_t tr;
    memset(&tr, 0, sizeof tr);
    tr.x_meas_m = &meas;
    tr.capacity = 1u;
    ss_actuator_record_f32(&c, &st, &tr, 0);
    assert_close(meas, 1.02 * slider_x(&st), 1e-6 * slider_x(&st));
}

/* Friction grows with position (gradient > 0): the same drive steps less further along. */
static void test_position_dependent_friction(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    c.effects.friction_gradient_per_m = 2000.0f; /* +20 % over 100 um */
    ss_effects_state_f32_t fx;
    ss_effects_init_f32(&c.effects, &fx, c.piezo_gain_m_per_v, 0.0f);
    assert_close(ss_effects_friction_scale_f32(&c.effects, &fx, 1e-4f), 1.2, 1e-6);
    assert_close(ss_effects_friction_scale_f32(&c.effects, &fx, -1e-3f), 0.1, 1e-6); /* clamped */
    ss_actuator_state_f32_t st;
    const double near = run_steps(&c, &st, 500.0f, 1, 5);
    assert_int_equal(ss_actuator_init_f32(&c, &st, 0.0f), SS_OK);
    ss_actuator_place_slider_f32(&st, 1e-4f);
    const double far = play_steps(&c, &st, 500.0f, 1, 5);
    /* more friction drags the slider further back on the fast edge: a smaller net step */
    assert_true(far < 0.9 * near);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_check_names_fields),
        cmocka_unit_test(test_off_is_bit_identical),
        cmocka_unit_test(test_external_load),
        cmocka_unit_test(test_asymmetric_friction),
        cmocka_unit_test(test_slew_limit),
        cmocka_unit_test(test_amplifier_bandwidth),
        cmocka_unit_test(test_creep),
        cmocka_unit_test(test_hysteresis),
        cmocka_unit_test(test_thermal),
        cmocka_unit_test(test_heat_carried),
        cmocka_unit_test(test_base_compliance),
        cmocka_unit_test(test_base_momentum_balance),
        cmocka_unit_test(test_sensor_scale),
        cmocka_unit_test(test_position_dependent_friction),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
