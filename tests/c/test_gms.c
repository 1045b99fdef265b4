/* GMS friction (docs/model.md, "GMS (third law)"): the element shares and the piecewise-linear
 * virgin curve they make, stiffness sigma0, saturation, wiping-out, rate independence without
 * micro-damping and the damping of the sticking elements with it, the Stribeck curve in steady
 * sliding, and the actuator driven through it (steps, convergence, effects). Tests of the elastic
 * part set sigma1 = 0: the damping force is sigma1 / N v a sticking element. */
#include "ss_test.h"

#include <float.h>

#include "ss_abi.h"
#include "ss_actuator.h"
#include "ss_convert_q.h"
#include "ss_gms_friction.h"

static ss_friction_config_f32_t table1(void)
{
    return ss_friction_config_table1_f32();
}

/* Table I without micro-damping: the rate-independent elastic-plastic contact. */
static ss_friction_config_f32_t undamped(void)
{
    ss_friction_config_f32_t c = table1();
    c.sigma1_ns_per_m = 0.0f;
    return c;
}

/* Move a GMS contact from its current position to x_to in steps of at most |h|, at speed v. */
static float gms_move(const ss_friction_config_f32_t *c, ss_gms_state_f32_t *st, double *x, double x_to,
                      double h, double v)
{
    float f = st->force_n;
    while (fabs(x_to - *x) > 1e-15) {
        double dx = x_to - *x;
        if (fabs(dx) > h) {
            dx = (dx > 0) ? h : -h;
        }
        f = ss_gms_step_f32(c, st, (float)dx, (float)(fabs(dx) / v));
        *x += dx;
    }
    return f;
}

/* The element distribution of docs/model.md in double: stiffnesses k_i / sigma0 proportional to
 * rho^(i-1) and summing to 1, shares alpha_i proportional to k_i (1 - c_i^(1/d)),
 * c_i = 1 - (2i-1)/2N. */
static void distribution(double decay, double rho, double alpha[SS_GMS_ELEMENTS], double k[SS_GMS_ELEMENTS])
{
    double sum = 0.0, ksum = 0.0;
    for (int i = 1; i <= SS_GMS_ELEMENTS; ++i) {
        k[i - 1] = pow(rho, i - 1.0);
        ksum += k[i - 1];
    }
    for (int i = 1; i <= SS_GMS_ELEMENTS; ++i) {
        k[i - 1] /= ksum;
        alpha[i - 1] = k[i - 1] * (1.0 - pow(1.0 - (2.0 * i - 1.0) / (2.0 * SS_GMS_ELEMENTS), 1.0 / decay));
        sum += alpha[i - 1];
    }
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        alpha[i] /= sum;
    }
}

static void shares(double decay, double out[SS_GMS_ELEMENTS])
{
    double k[SS_GMS_ELEMENTS];
    distribution(decay, 1.0, out, k);
}

/* The virgin curve of docs/model.md: sum over i of min(k_i u, alpha_i Fs); for the default decay 1
 * and stiffness ratio 1, k_i = sigma0 / N and alpha_i = (2i-1)/N^2. */
static double virgin_curve(const ss_friction_config_f32_t *c, double u)
{
    double alpha[SS_GMS_ELEMENTS], k[SS_GMS_ELEMENTS];
    distribution((double)c->gms_decay, (double)c->gms_stiffness_ratio, alpha, k);
    double f = 0.0;
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        f += fmin((double)c->sigma0_n_per_m * k[i] * fabs(u), alpha[i] * (double)c->fs_n);
    }
    return (u < 0.0) ? -f : f;
}

/* The shares: (1, 3, 5, 7) / 16 exactly at the default decay; at every decay in its range they sum
 * to 1 and rise with the element, as the double formula has them; near 0 they are nearly equal
 * (one break-away), at 20 near the exponential limit, proportional to -ln c_i. */
static void test_gms_shares(void **unused)
{
    (void)unused;
    float s[SS_GMS_ELEMENTS], ks[SS_GMS_ELEMENTS];
    ss_gms_shares_f32(1.0f, 1.0f, s, ks);
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        assert_true(s[i] == (float)(2 * i + 1) / 16.0f);
        assert_true(ks[i] == 1.0f);
    }
    const float decays[] = {0.05f, 0.125f, 0.5f, 1.0f, 2.0f, 4.0f, 8.0f, 20.0f};
    for (size_t k = 0; k < sizeof decays / sizeof decays[0]; ++k) {
        double want[SS_GMS_ELEMENTS];
        shares((double)decays[k], want);
        ss_gms_shares_f32(decays[k], 1.0f, s, ks);
        double sum = 0.0;
        for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
            assert_close(s[i], want[i], 4.0 * FLT_EPSILON);
            assert_true(i == 0 || s[i] >= s[i - 1]); /* equal in float at the smallest decays */
            sum += (double)s[i];
        }
        assert_close(sum, 1.0, 4.0 * FLT_EPSILON);
    }
    ss_gms_shares_f32(0.05f, 1.0f, s, ks);
    assert_true(s[3] / s[0] < 1.08f); /* c_0^20 = 0.875^20 = 0.069: 1 against 1 - 0.069 */
    ss_gms_shares_f32(20.0f, 1.0f, s, ks);
    double lim = 0.0, sum_ln = 0.0;
    for (int i = 1; i <= SS_GMS_ELEMENTS; ++i) {
        sum_ln += -log(1.0 - (2.0 * i - 1.0) / (2.0 * SS_GMS_ELEMENTS));
    }
    for (int i = 1; i <= SS_GMS_ELEMENTS; ++i) {
        lim = fmax(lim, fabs(s[i - 1] + log(1.0 - (2.0 * i - 1.0) / (2.0 * SS_GMS_ELEMENTS)) / sum_ln));
    }
    print_message("shares at decay 20: %.4f %.4f %.4f %.4f, %.3g off the exponential limit\n", s[0], s[1],
                  s[2], s[3], lim);
    assert_true(lim < 0.03);
}

static void test_gms_api(void **unused)
{
    (void)unused;
    ss_friction_config_f32_t c = table1();
    ss_gms_state_f32_t st;
    assert_int_equal(ss_gms_init_f32(&c, NULL), SS_ERR_NULL);
    assert_int_equal(ss_gms_init_f32(NULL, &st), SS_ERR_NULL);
    c.fc_n = 1.01f * c.fs_n;
    assert_int_equal(ss_gms_init_f32(&c, &st), SS_ERR_RANGE);
    c = table1();
    assert_int_equal(ss_gms_init_f32(&c, &st), SS_OK);
    assert_true(st.level_n == c.fs_n);
    /* non-finite input changes nothing */
    ss_gms_step_f32(&c, &st, 1e-8f, 1e-6f);
    const ss_gms_state_f32_t keep = st;
    assert_true(ss_gms_step_f32(&c, &st, NAN, 1e-6f) == keep.force_n);
    assert_true(ss_gms_step_f32(&c, &st, 1e-9f, 0.0f) == keep.force_n);
    ss_gms_advance_f32(&c, &st, INFINITY, 1e-6f);
    assert_memory_equal(&st, &keep, sizeof st);
    /* run = the same steps one by one */
    const float dx[4] = {1e-8f, 2e-8f, -5e-9f, 3e-8f};
    float f_run[4];
    ss_gms_state_f32_t a, b;
    ss_gms_init_f32(&c, &a);
    ss_gms_init_f32(&c, &b);
    assert_int_equal(ss_gms_run_f32(&c, &a, dx, 4, 1e-6f, f_run), SS_OK);
    for (int i = 0; i < 4; ++i) {
        assert_true(f_run[i] == ss_gms_step_f32(&c, &b, dx[i], 1e-6f));
    }
    assert_int_equal(ss_gms_run_f32(&c, &a, NULL, 4, 1e-6f, f_run), SS_ERR_NULL);
    assert_int_equal(ss_gms_run_f32(&c, &a, dx, 4, 0.0f, f_run), SS_ERR_RANGE);
    const float bad[1] = {NAN};
    assert_int_equal(ss_gms_run_f32(&c, &a, bad, 1, 1e-6f, f_run), SS_ERR_NONFINITE);
    assert_int_equal(ss_abi_sizeof(SS_ABI_GMS_STATE_F32), sizeof(ss_gms_state_f32_t));
    /* gms_decay is checked with the rest of the config, by name */
    c.gms_decay = 0.04f;
    const char *bad_field = "";
    assert_int_equal(ss_friction_config_check_f32(&c, &bad_field), SS_ERR_RANGE);
    assert_string_equal(bad_field, "gms_decay");
    assert_int_equal(ss_gms_init_f32(&c, &st), SS_ERR_RANGE);
    c.gms_decay = 21.0f;
    assert_int_equal(ss_gms_init_f32(&c, &st), SS_ERR_RANGE);
    c = table1();
    /* the slopes for the actuator's implicit step: dF/dv is sigma2 and the damping of the sticking
     * elements (here all four, sigma1); dF/dx the sticking elements' stiffness: sigma0 at rest
     * and after a reversal, 0 once every element slips */
    ss_friction_slopes_f32_t slopes;
    ss_gms_force_at_f32(&c, &a, 1e-3f, &slopes);
    assert_true(slopes.dfdv_ns_per_m == c.sigma2_ns_per_m + c.sigma1_ns_per_m);
    ss_gms_state_f32_t s;
    assert_int_equal(ss_gms_init_f32(&c, &s), SS_OK);
    ss_gms_force_at_f32(&c, &s, 0.0f, &slopes);
    assert_true(slopes.dfdx_n_per_m == c.sigma0_n_per_m);
    ss_gms_step_f32(&c, &s, 2e-6f, 1e-6f); /* 2 um: past the last element's 0.25 um */
    ss_gms_step_f32(&c, &s, 1e-9f, 1e-6f); /* on: every element slips the whole step */
    ss_gms_force_at_f32(&c, &s, 1.0f, &slopes);
    assert_true(slopes.dfdx_n_per_m == 0.0f);
    assert_true(slopes.dfdv_ns_per_m == c.sigma2_ns_per_m);
    ss_gms_step_f32(&c, &s, -1e-9f, 1e-6f); /* reversed: every element sticks again */
    ss_gms_force_at_f32(&c, &s, -1e-3f, &slopes);
    assert_true(slopes.dfdx_n_per_m == c.sigma0_n_per_m);
}

/* First loading follows the piecewise-linear curve to float32 rounding, at any step size: the
 * Maxwell-slip elements are exact in displacement. Steps of 2^-27 m keep every element force an
 * exact float (k dx = 78125 * 2^-22 N), so the only rounding is the sum over the elements. */
static void test_gms_virgin_curve_is_piecewise_linear(void **unused)
{
    (void)unused;
    ss_friction_config_f32_t c = undamped();
    c.sigma2_ns_per_m = 0.0f;
    const double h = ldexp(1.0, -27);
    for (int dir = -1; dir <= 1; dir += 2) {
        ss_gms_state_f32_t st;
        ss_gms_init_f32(&c, &st);
        double worst = 0.0;
        for (int n = 1; n <= 134; ++n) { /* to 1.0 um, past full slip at 1.75 Fs / sigma0 = 0.63 um */
            const float f = ss_gms_step_f32(&c, &st, (float)(dir * h), 1.0f); /* 7.5 nm/s: g(v) = Fs */
            worst = fmax(worst, fabs(f - virgin_curve(&c, dir * n * h)));
        }
        print_message("virgin curve, direction %+d: worst difference %.3g N (%.2g Fs)\n", dir, worst,
                      worst / (double)c.fs_n);
        assert_true(worst <= 4.0 * FLT_EPSILON * (double)c.fs_n);
    }
    /* one step of 0.5 um lands on the same curve as 67 small ones */
    ss_gms_state_f32_t st;
    ss_gms_init_f32(&c, &st);
    const float f = ss_gms_step_f32(&c, &st, 0.5e-6f, 1.0f);
    assert_close(f, virgin_curve(&c, (double)0.5e-6f), 4.0 * FLT_EPSILON * (double)c.fs_n);
    /* another decay, another curve: its shares' (to their float rounding), and within Fs / 16 of
     * the continuum Fs (1 - (1 - u / u_s)^(d + 1)), u_s = (d + 1) Fs / sigma0, that they discretise */
    c.gms_decay = 3.0f;
    ss_gms_init_f32(&c, &st);
    const double us = 4.0 * (double)c.fs_n / (double)c.sigma0_n_per_m;
    double worst = 0.0, off = 0.0;
    for (int n = 1; n <= 268; ++n) { /* to 2 um: past full slip at 0.96 Fs / sigma0 ... 5.4 */
        const double u = n * h;
        const float fd = ss_gms_step_f32(&c, &st, (float)h, 1.0f);
        worst = fmax(worst, fabs(fd - virgin_curve(&c, u)));
        const double cont = (double)c.fs_n * ((u < us) ? 1.0 - pow(1.0 - u / us, 4.0) : 1.0);
        off = fmax(off, fabs(fd - cont));
    }
    print_message("decay 3: %.3g N off its shares' curve, %.3g Fs off the continuum\n", worst,
                  off / (double)c.fs_n);
    assert_true(worst <= 8.0 * FLT_EPSILON * (double)c.fs_n);
    assert_true(off < (double)c.fs_n / 16.0);
}

/* One step of dx_m in dt_s begun from the velocity of the force before it (v_prev), as the
 * actuator takes it (ss_gms_step_f32 begins each step from its own velocity). */
static float gms_step_from(const ss_friction_config_f32_t *c, ss_gms_state_f32_t *st, float dx_m, float dt_s,
                           float v_prev)
{
    ss_gms_begin_step_f32(st, v_prev);
    ss_gms_advance_piece_f32(c, st, dx_m, dt_s);
    return ss_gms_force_at_f32(c, st, dx_m / dt_s, NULL);
}

/* Unequal stiffnesses (gms_stiffness_ratio rho): the virgin curve is sum_i min(k_i u, alpha_i Fs)
 * with k_i in a geometric progression summing to sigma0; it starts at slope sigma0, reaches Fs, and
 * its break-away displacements alpha_i Fs / k_i stand in the same ratios as with equal stiffnesses
 * (only the stiffness of each element changes). A sticking element is damped by sigma1 k_i / sigma0. */
static void test_gms_unequal_stiffnesses(void **unused)
{
    (void)unused;
    ss_friction_config_f32_t c = undamped();
    c.sigma2_ns_per_m = 0.0f;
    c.gms_decay = 2.0f;
    const double h = ldexp(1.0, -27);
    const float rhos[] = {0.05f, 0.4f, 2.5f, 20.0f};
    for (size_t r = 0; r < sizeof rhos / sizeof rhos[0]; ++r) {
        c.gms_stiffness_ratio = rhos[r];
        ss_gms_state_f32_t st, eq;
        ss_gms_init_f32(&c, &st);
        ss_friction_config_f32_t e = c;
        e.gms_stiffness_ratio = 1.0f;
        ss_gms_init_f32(&e, &eq);
        double ksum = 0.0, ratio_off = 0.0;
        for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
            ksum += (double)st.kscale[i] / SS_GMS_ELEMENTS;
            const double gap = (double)st.share[i] / (double)st.kscale[i];
            const double gap_eq = (double)eq.share[i] / (double)eq.kscale[i];
            ratio_off = fmax(ratio_off, fabs(gap / ((double)st.share[0] / (double)st.kscale[0]) -
                                             gap_eq / ((double)eq.share[0] / (double)eq.kscale[0])) /
                                            (gap_eq / ((double)eq.share[0] / (double)eq.kscale[0])));
            assert_true(i == 0 || fabs(st.kscale[i] / st.kscale[i - 1] - rhos[r]) < 1e-5 * rhos[r]);
        }
        assert_close(ksum, 1.0, 4.0 * FLT_EPSILON);
        assert_true(ratio_off < 1e-5);
        double worst = 0.0, slope_off = 0.0;
        float f = 0.0f;
        for (int n = 1; n <= 1340; ++n) { /* to 10 um: past full slip for every rho here */
            f = ss_gms_step_f32(&c, &st, (float)h, 1.0f);
            worst = fmax(worst, fabs(f - virgin_curve(&c, n * h)));
            /* the slope dF/dx: the stiffness of the elements that still stick, sum of their k_i */
            ss_friction_slopes_f32_t sl;
            (void)ss_gms_force_at_f32(&c, &st, (float)h, &sl);
            double k_stuck = 0.0;
            for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
                const int sticks = fabsf(st.f_n[i]) < st.share[i] * st.level_n;
                k_stuck += sticks ? (double)c.sigma0_n_per_m * (double)st.kscale[i] / SS_GMS_ELEMENTS : 0.0;
            }
            slope_off = fmax(slope_off, fabs((double)sl.dfdx_n_per_m - k_stuck));
        }
        assert_true(slope_off <= 1e-6 * (double)c.sigma0_n_per_m);
        ss_gms_init_f32(&c, &st);
        const float f1 = ss_gms_step_f32(&c, &st, 1e-12f, 1.0f);
        print_message(
            "stiffness ratio %.2f: %.3g N off the curve, initial slope %.6g sigma0, %.6g Fs at 10 um\n",
            (double)rhos[r], worst, (double)f1 / 1e-12 / (double)c.sigma0_n_per_m,
            (double)f / (double)c.fs_n);
        assert_true(worst <= 16.0 * FLT_EPSILON * (double)c.fs_n);
        assert_close((double)f1 / 1e-12, (double)c.sigma0_n_per_m, 1e-4 * (double)c.sigma0_n_per_m);
        assert_close(f, (double)c.fs_n, 4.0 * FLT_EPSILON * (double)c.fs_n);
    }
    /* the damping of the sticking elements: sigma1 times their stiffness over sigma0 */
    c = table1();
    c.sigma2_ns_per_m = 0.0f;
    c.gms_stiffness_ratio = 0.4f;
    ss_friction_config_f32_t u = c;
    u.sigma1_ns_per_m = 0.0f;
    ss_gms_state_f32_t d, e;
    ss_gms_init_f32(&c, &d);
    ss_gms_init_f32(&u, &e);
    int seen = 0;
    double impulse = 0.0, last = 0.0; /* the damping force at rest before the ramp: 0 */
    for (int i = 0; i < 400; ++i) {   /* 0.8 um forward in 2 nm steps at 2 mm/s: elements break one by one */
        const ss_gms_state_f32_t before = e;
        const float v_prev = (i == 0) ? 0.0f : 2e-3f;
        const float fd = gms_step_from(&c, &d, 2e-9f, 1e-6f, v_prev);
        const float fe = gms_step_from(&u, &e, 2e-9f, 1e-6f, v_prev);
        /* a step's end force acts for half of it and half of the next: the trapezoid */
        impulse += 0.5 * (last + ((double)fd - (double)fe)) * 1e-6;
        last = (double)fd - (double)fe;
        double k_stuck = 0.0;
        int broke = 0;
        for (int k = 0; k < SS_GMS_ELEMENTS; ++k) {
            const float w = e.share[k] * e.level_n;
            k_stuck += (fabsf(e.f_n[k]) < w) ? (double)e.kscale[k] / SS_GMS_ELEMENTS : 0.0;
            broke += (fabsf(before.f_n[k]) < w && fabsf(e.f_n[k]) >= w) ? 1 : 0;
        }
        if (broke == 0 && k_stuck > 0.0) {
            assert_close((double)fd - (double)fe, (double)c.sigma1_ns_per_m * k_stuck * 2e-3,
                         1e-6 * (double)c.fs_n);
            seen++;
        }
    }
    assert_true(seen > 100);
    double k_turn = 0.0; /* the elements that stick through the turn, their share of sigma0 */
    for (int k = 0; k < SS_GMS_ELEMENTS; ++k) {
        k_turn += (fabsf(e.f_n[k]) < e.share[k] * e.level_n) ? (double)e.kscale[k] / SS_GMS_ELEMENTS : 0.0;
    }
    for (int i = 0; i < 100; ++i) { /* then 0.2 um back: every element sticks again at the turn */
        const float v_prev = (i == 0) ? 2e-3f : -2e-3f;
        const float fd = gms_step_from(&c, &d, -2e-9f, 1e-6f, v_prev);
        const float fe = gms_step_from(&u, &e, -2e-9f, 1e-6f, v_prev);
        impulse += 0.5 * (last + ((double)fd - (double)fe)) * 1e-6;
        last = (double)fd - (double)fe;
    }
    /* ... and through the break-aways and the turn, where elements' damping switches inside a
     * step: the damping's impulse is sigma1 k_i / sigma0 times the displacement element i stuck
     * for (forward min(0.8 um, its break-away alpha_i Fs / k_i), then all of the 0.2 um back: none
     * breaks away again within 2 alpha_i Fs / k_i), less the half of the first step the force at
     * rest stands for (sigma1 v dt / 2: the ramp starts at v at once), and plus the half step the
     * force before the turn stands for in the turn's step for the elements that stuck through it
     * (the velocity jumps from v to -v there, the trapezoid takes the mean). Exact in the scheme,
     * so to float rounding (measured 2.4e-6; tolerance 1e-5); the switch terms weighted by 1 in
     * place of k_i / (sigma0 / N) move it by 1.5e-3 (break-away) and 2.6e-3 (turn) */
    const double sv_dt = (double)c.sigma1_ns_per_m * 2e-3 * 1e-6;
    double want = -0.5 * sv_dt + k_turn * sv_dt - (double)c.sigma1_ns_per_m * 100 * 2e-9;
    for (int k = 0; k < SS_GMS_ELEMENTS; ++k) {
        const double k_i = (double)c.sigma0_n_per_m * (double)d.kscale[k] / SS_GMS_ELEMENTS;
        const double gap = (double)d.share[k] * (double)c.fs_n / k_i;
        want += (double)c.sigma1_ns_per_m * k_i / (double)c.sigma0_n_per_m * fmin(400 * 2e-9, gap);
    }
    print_message(
        "damping impulse over 0.8 um and back 0.2 at stiffness ratio 0.4: %.6g N s, want %.6g (%.2g)\n",
        impulse, want, impulse / want - 1.0);
    assert_close(impulse, want, 1e-5 * want);
}

/* sigma0 is the initial stiffness, from rest and right after any reversal. */
static void test_gms_initial_stiffness(void **unused)
{
    (void)unused;
    const ss_friction_config_f32_t c = undamped();
    ss_gms_state_f32_t st;
    ss_gms_init_f32(&c, &st);
    double x = 0.0;
    const double viscous = 1e-6 * c.sigma2_ns_per_m; /* at 1 um/s */
    const float f1 = gms_move(&c, &st, &x, 1e-10, 1e-10, 1e-6);
    assert_close((f1 - viscous) / 1e-10, c.sigma0_n_per_m, 1e-3 * c.sigma0_n_per_m);
    /* at 0.5 um three of the four elements have slipped; back off 0.1 nm: all stick again */
    const float fa = gms_move(&c, &st, &x, 0.5e-6, 1e-9, 1e-6);
    const float fb = gms_move(&c, &st, &x, 0.5e-6 - 1e-10, 1e-10, 1e-6);
    assert_close((fa - fb - 2.0 * viscous) / 1e-10, c.sigma0_n_per_m, 2e-3 * c.sigma0_n_per_m);
}

/* Slow sliding saturates at Fs in either direction, with every element at its slip level. */
static void test_gms_saturation(void **unused)
{
    (void)unused;
    ss_friction_config_f32_t c = table1();
    c.sigma2_ns_per_m = 0.0f;
    for (int dir = -1; dir <= 1; dir += 2) {
        ss_gms_state_f32_t st;
        ss_gms_init_f32(&c, &st);
        double x = 0.0;
        const float f = gms_move(&c, &st, &x, dir * 3e-6, 1e-9, 1e-8);
        assert_close(f, dir * c.fs_n, 1e-6 * c.fs_n);
        assert_int_equal(st.sliding, dir);
        for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
            assert_close(fabsf(st.f_n[i]), (2.0 * i + 1.0) / 16.0 * c.fs_n, 1e-6 * c.fs_n);
        }
        assert_true(fabsf(st.force_n) <= c.fs_n * (1.0f + FLT_EPSILON));
    }
}

/* Wiping-out: a closed minor loop returns to its start force, and the path goes on as if the
 * loop had not been. */
static void test_gms_wiping_out(void **unused)
{
    (void)unused;
    const ss_friction_config_f32_t c = undamped();
    ss_gms_state_f32_t a, b;
    ss_gms_init_f32(&c, &a);
    ss_gms_init_f32(&c, &b);
    double xa = 0.0, xb = 0.0;
    const double v = 1e-6, h = 1e-9;
    /* a: -0.4 um, then up to 0.3 um; b: the same with a minor loop 0.1 -> -0.2 -> 0.1 um, deep
     * enough that the softest element slips both ways (break-away after 2 x 0.09 um) */
    gms_move(&c, &a, &xa, -0.4e-6, h, v);
    gms_move(&c, &b, &xb, -0.4e-6, h, v);
    const float f_start = gms_move(&c, &b, &xb, 0.1e-6, h, v);
    const float f_low = gms_move(&c, &b, &xb, -0.2e-6, h, v);
    const float f_back = gms_move(&c, &b, &xb, 0.1e-6, h, v);
    const float fa = gms_move(&c, &a, &xa, 0.3e-6, h, v);
    const float fb = gms_move(&c, &b, &xb, 0.3e-6, h, v);
    print_message("minor loop: start %.6g N, turn %.6g N, back %.6g N; at 0.3 um %.6g vs %.6g N\n",
                  (double)f_start, (double)f_low, (double)f_back, (double)fa, (double)fb);
    assert_true(f_low < f_start - 0.5f); /* a real loop */
    assert_close(f_back, f_start, 1e-5 * c.fs_n);
    assert_close(fb, fa, 1e-5 * c.fs_n);
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        assert_close(b.f_n[i], a.f_n[i], 1e-5 * c.fs_n);
    }
}

/* Presliding depends on the path only: the same loop, partly slipping (two of the four elements)
 * but never sliding as a whole, at 10 Hz and at 1 kHz gives the same forces. The displacement
 * samples are the same; only the time per sample differs (100 us and 1 us). sigma1 and sigma2 off,
 * since their forces are rate dependent by definition. */
static void test_gms_rate_independent(void **unused)
{
    (void)unused;
    ss_friction_config_f32_t c = undamped();
    c.sigma2_ns_per_m = 0.0f;
    const double amp = 0.36e-6; /* Fs / sigma0: elements 1 and 2 slip, 3 and 4 do not */
    const double hz[2] = {10.0, 1000.0};
    enum { PER_CYCLE = 1000 };
    static float f[2][3 * PER_CYCLE];
    for (int k = 0; k < 2; ++k) {
        ss_gms_state_f32_t st;
        ss_gms_init_f32(&c, &st);
        const double dt = 1.0 / (hz[k] * PER_CYCLE);
        double x = 0.0;
        for (int i = 0; i < 3 * PER_CYCLE; ++i) { /* triangle 0 -> amp -> -amp -> 0, three cycles */
            const double ph = (double)((i + 1) % PER_CYCLE) / PER_CYCLE;
            const double x1 = amp * ((ph < 0.25) ? 4.0 * ph : (ph < 0.75) ? 2.0 - 4.0 * ph : 4.0 * ph - 4.0);
            f[k][i] = ss_gms_step_f32(&c, &st, (float)(x1 - x), (float)dt);
            x = x1;
            assert_int_equal(st.sliding, 0);
        }
        assert_true(st.level_n == c.fs_n);
    }
    double worst = 0.0;
    for (int i = 0; i < 3 * PER_CYCLE; ++i) {
        worst = fmax(worst, fabs((double)f[1][i] - (double)f[0][i]));
    }
    /* hysteresis: at x = 0 the rising and the falling branch differ */
    const double gap = (double)f[0][2 * PER_CYCLE - 1] - (double)f[0][2 * PER_CYCLE + PER_CYCLE / 2 - 1];
    print_message("10 Hz vs 1 kHz: worst difference %.3g N; branch gap at x = 0: %.4g N\n", worst, gap);
    assert_true(worst <= 1e-5 * c.fs_n);
    assert_true(fabs(gap) > 0.1 * c.fs_n);
}

/* Micro-damping: on the same loop at 1 kHz, sigma1 adds sigma1 / N v for every element that
 * sticks (below its level, or at it and turned back), and nothing for one that slips on; the
 * elements themselves do not depend on it. Steps in which an element breaks away are counted by
 * their part (test_gms_step_convergence covers them), so they are left out here. */
static void test_gms_damps_sticking_elements(void **unused)
{
    (void)unused;
    ss_friction_config_f32_t c = table1();
    c.sigma2_ns_per_m = 0.0f;
    ss_friction_config_f32_t u = c;
    u.sigma1_ns_per_m = 0.0f;
    const double amp = 0.36e-6, dt = 1e-6;
    enum { PER_CYCLE = 1000 };
    ss_gms_state_f32_t d, e;
    ss_gms_init_f32(&c, &d);
    ss_gms_init_f32(&u, &e);
    double x = 0.0;
    int seen[SS_GMS_ELEMENTS + 1] = {0};
    for (int i = 0; i < 2 * PER_CYCLE; ++i) {
        const double ph = (double)((i + 1) % PER_CYCLE) / PER_CYCLE;
        const double x1 = amp * ((ph < 0.25) ? 4.0 * ph : (ph < 0.75) ? 2.0 - 4.0 * ph : 4.0 * ph - 4.0);
        const float dx = (float)(x1 - x);
        x = x1;
        const ss_gms_state_f32_t before = e;
        const float fd = ss_gms_step_f32(&c, &d, dx, (float)dt);
        const float fe = ss_gms_step_f32(&u, &e, dx, (float)dt);
        assert_memory_equal(d.f_n, e.f_n, sizeof d.f_n);
        int sticking = 0, broke = 0;
        for (int k = 0; k < SS_GMS_ELEMENTS; ++k) {
            const float w = e.share[k] * e.level_n;
            sticking += (fabsf(e.f_n[k]) < w || e.f_n[k] * dx <= 0.0f) ? 1 : 0;
            broke += (fabsf(before.f_n[k]) < w && fabsf(e.f_n[k]) >= w) ? 1 : 0;
        }
        if (broke == 0) {
            const double want = (double)c.sigma1_ns_per_m * sticking / SS_GMS_ELEMENTS * (double)dx / dt;
            assert_close((double)fd - (double)fe, want, 1e-6 * (double)c.fs_n);
            seen[sticking]++;
        }
    }
    print_message("damped steps with 4 / 3 / 2 elements sticking: %d / %d / %d\n", seen[4], seen[3], seen[2]);
    assert_true(seen[4] > 0 && seen[3] > 0 && seen[2] > 0);
}

/* Steady sliding follows the Stribeck curve plus viscous friction. */
static void test_gms_steady_sliding_is_stribeck(void **unused)
{
    (void)unused;
    const ss_friction_config_f32_t c = table1();
    const double speeds[] = {1e-6, 1e-4, 4e-4, 1e-3, 1e-2};
    for (size_t i = 0; i < sizeof speeds / sizeof speeds[0]; ++i) {
        for (int dir = -1; dir <= 1; dir += 2) {
            ss_gms_state_f32_t st;
            ss_gms_init_f32(&c, &st);
            double x = 0.0;
            const float f = gms_move(&c, &st, &x, dir * 20e-6, 1e-9, speeds[i]);
            const double v = dir * speeds[i];
            const double expect = dir * (double)ss_stribeck_f32(&c, (float)v) + c.sigma2_ns_per_m * v;
            assert_int_equal(st.sliding, dir);
            assert_close(f, expect, 1e-4 * fabs(expect));
        }
    }
}

/* Asymmetric friction scales the contact force by 1 + a sgn(load), as in LS. */
static void test_gms_asymmetric_sliding(void **unused)
{
    (void)unused;
    ss_friction_config_f32_t c = table1();
    c.asymmetry = 0.2f;
    for (int dir = -1; dir <= 1; dir += 2) {
        ss_gms_state_f32_t st;
        ss_gms_init_f32(&c, &st);
        double x = 0.0;
        const float f = gms_move(&c, &st, &x, dir * 20e-6, 1e-9, 1e-3);
        const double expect = dir * (1.0 + dir * 0.2) * (double)ss_stribeck_f32(&c, 1e-3f) + dir * 1e-3 * 8.0;
        assert_close(f, expect, 1e-4 * fabs(expect));
    }
}

/* Mean step per cycle over cycles [skip, cycles) of a 100 V sawtooth run with the slider starting
 * at x0_m, in metres. */
static double steady_step_at(ss_actuator_config_f32_t cfg, float x0_m, float f_hz, float rise, int dir,
                             uint32_t cycles, uint32_t skip)
{
    ss_waveform_config_f32_t w = ss_waveform_sawtooth_f32(f_hz, 100.0f, 0.0f, rise, dir, cycles);
    ss_waveform_state_f32_t ws;
    ss_actuator_state_f32_t st;
    assert_int_equal(ss_waveform_init_f32(&w, cfg.dt_s, &ws), SS_OK);
    assert_int_equal(ss_actuator_init_f32(&cfg, &st, ss_waveform_value_f32(&w, &ws)), SS_OK);
    ss_actuator_place_slider_f32(&st, x0_m);
    double x_skip = 0.0;
    uint32_t idx = 0;
    while (ws.index < cycles) {
        ss_waveform_advance_f32(&ws);
        assert_int_equal(ss_actuator_step_f32(&cfg, &st, ss_waveform_value_f32(&w, &ws)), SS_OK);
        if (ws.index != idx) {
            idx = ws.index;
            if (idx == skip) {
                x_skip = (double)st.x_slider.hi_m + (double)st.x_slider.lo_m;
            }
        }
    }
    const double x_end = (double)st.x_slider.hi_m + (double)st.x_slider.lo_m;
    return (x_end - x_skip) / (double)(cycles - skip);
}

static double steady_step(ss_actuator_config_f32_t cfg, float f_hz, float rise, int dir, uint32_t cycles,
                          uint32_t skip)
{
    return steady_step_at(cfg, 0.0f, f_hz, rise, dir, cycles, skip);
}

/* The paper's drive, forward, from x0_m. */
static double steady_step_from(ss_actuator_config_f32_t cfg, float x0_m, uint32_t cycles, uint32_t skip)
{
    return steady_step_at(cfg, x0_m, 500.0f, 0.95f, 1, cycles, skip);
}

static ss_actuator_config_f32_t gms_actuator(void)
{
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    c.friction_model = SS_FRICTION_GMS;
    return c;
}

/* The paper's drive (Table I, 500 Hz, 100 V, rise fraction 0.95) steps the slider forward a few
 * um per cycle; the reversed drive steps it back. */
static void test_gms_actuator_steps(void **unused)
{
    (void)unused;
    const ss_actuator_config_f32_t c = gms_actuator();
    assert_int_equal(ss_actuator_config_check_f32(&c, NULL), SS_OK);
    const double fwd = steady_step(c, 500.0f, 0.95f, 1, 6, 2);
    const double rev = steady_step(c, 500.0f, 0.95f, -1, 6, 2);
    print_message("GMS: forward %.5g um, reverse %.5g um per cycle\n", fwd * 1e6, rev * 1e6);
    assert_true(fwd > 1e-6 && fwd < 4.4e-6);
    assert_true(rev < -1e-6 && rev > -4.4e-6);
    /* the recorded states are the level and the elastic force */
    ss_actuator_state_f32_t st;
    assert_int_equal(ss_actuator_init_f32(&c, &st, 0.0f), SS_OK);
    for (int k = 0; k < 500; ++k) {
        ss_actuator_step_f32(&c, &st, 0.1f * (float)k);
    }
    float a = 0.0f, b = 0.0f;
    ss_actuator_trace_f32_t tr = {NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, &a, &b, NULL, 1};
    ss_actuator_record_f32(&c, &st, &tr, 0);
    assert_true(a == st.fr.gms.level_n);
    assert_true(b == st.fr.gms.elastic_n);
    assert_true(b != 0.0f);
}

/* Halving the 1 us step changes the settled step of the paper's run by less than 0.2 %. */
static void test_gms_step_convergence(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = gms_actuator();
    const double s1 = steady_step(c, 500.0f, 0.95f, 1, 10, 2);
    c.dt_s = 0.5e-6f;
    const double s2 = steady_step(c, 500.0f, 0.95f, 1, 10, 2);
    print_message("GMS: dt 1 us %.7g m, 0.5 us %.7g m, change %.3g %%\n", s1, s2,
                  100.0 * fabs(s1 / s2 - 1.0));
    assert_true(fabs(s1 / s2 - 1.0) < 2e-3);
}

/* The settled step of a sawtooth taken with the drive's corners inside steps, as the runners do. */
static double wave_step_mean(ss_actuator_config_f32_t cfg, float f_hz, float fall_s, uint32_t cycles,
                             uint32_t skip)
{
    ss_waveform_config_f32_t w =
        ss_waveform_sawtooth_f32(f_hz, 100.0f, 0.0f, 1.0f - fall_s * f_hz, 1, cycles);
    ss_waveform_state_f32_t ws;
    ss_actuator_state_f32_t st;
    assert_int_equal(ss_waveform_init_f32(&w, cfg.dt_s, &ws), SS_OK);
    assert_int_equal(ss_actuator_init_f32(&cfg, &st, ss_waveform_value_f32(&w, &ws)), SS_OK);
    double x_skip = 0.0;
    while (ws.index < cycles) {
        const uint32_t idx = ws.index;
        assert_int_equal(ss_actuator_wave_step_f32(&cfg, &st, &w, &ws), SS_OK);
        if (ws.index != idx && ws.index == skip) {
            x_skip = (double)st.x_slider.hi_m + (double)st.x_slider.lo_m;
        }
    }
    return ((double)st.x_slider.hi_m + (double)st.x_slider.lo_m - x_skip) / (double)(cycles - skip);
}

/* Micro-damping in a 15 us fall: the contact breaks away within a step or two at 0.1-0.5 m/s, and
 * each element's damping (5-30 N there) switches off inside a step. With the fast edge's steps
 * taken in sub-steps, the settled step at 1 us is within 0.03 % of 1/8 us (measured 0.002 and
 * 0.007 %); in whole steps it was 0.07 and 0.11 % off (0.16 and 0.21 % with each element's
 * damping switched with the state at the step's end). */
static void test_gms_damped_fast_edge_convergence(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = gms_actuator();
    c.friction.gms_decay = 4.0f;
    const float hz[2] = {300.0f, 2000.0f};
    const float rho[2] = {1.0f, 0.4f}; /* equal stiffnesses, and unequal: damping by k_i */
    for (int r = 0; r < 2; ++r) {
        c.friction.gms_stiffness_ratio = rho[r];
        for (int k = 0; k < 2; ++k) {
            c.dt_s = 1e-6f;
            const double s1 = wave_step_mean(c, hz[k], 15e-6f, 8, 2);
            c.dt_s = 0.125e-6f;
            const double s8 = wave_step_mean(c, hz[k], 15e-6f, 8, 2);
            print_message(
                "GMS, decay 4, stiffness ratio %.1f, %g Hz, 15 us fall: 1 us %.7g m, 1/8 us %.7g m, "
                "%.3f %%\n",
                (double)rho[r], (double)hz[k], s1, s8, 100.0 * fabs(s1 / s8 - 1.0));
            assert_true(fabs(s1 / s8 - 1.0) < 3e-4);
        }
    }
}

/* A fast edge's sub-steps count as the one step they make up: a run's rows stay on its steps. */
static void test_gms_fast_edge_substeps_are_one_step(void **unused)
{
    (void)unused;
    const ss_actuator_config_f32_t c = gms_actuator();
    ss_waveform_config_f32_t w = ss_waveform_sawtooth_f32(2000.0f, 100.0f, 0.0f, 0.97f, 1, 2);
    ss_waveform_state_f32_t ws;
    ss_actuator_state_f32_t st;
    assert_int_equal(ss_waveform_init_f32(&w, c.dt_s, &ws), SS_OK);
    assert_int_equal(ss_actuator_init_f32(&c, &st, 0.0f), SS_OK);
    for (int k = 0; k < 1000; ++k) {
        assert_int_equal(ss_actuator_wave_step_f32(&c, &st, &w, &ws), SS_OK);
    }
    assert_int_equal(st.steps, 1000);
}

/* Over 2000 cycles (8 mm of travel) the settled step stays what it was after 50 cycles: the state
 * holds bounded element forces, not anchors that would grow with the travel. */
static void test_gms_long_travel_keeps_resolution(void **unused)
{
    (void)unused;
    const ss_actuator_config_f32_t c = gms_actuator();
    const double early = steady_step(c, 500.0f, 0.99f, 1, 60, 50);
    const double late = steady_step(c, 500.0f, 0.99f, 1, 2000, 1990);
    print_message("GMS: step early %.7g m, after 2000 cycles %.7g m\n", early, late);
    assert_close(late, early, 1e-5 * early);
}

/* The effects act on GMS as on LS: asymmetric friction parts forward and reverse steps, softer
 * (warm) friction and a nearly sliding load do what they do with LS. */
static void test_gms_actuator_effects(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t c = gms_actuator();
    const double fwd0 = steady_step(c, 500.0f, 0.95f, 1, 5, 1);
    const double rev0 = steady_step(c, 500.0f, 0.95f, -1, 5, 1);
    c.friction.asymmetry = 0.1f;
    const double fwd = steady_step(c, 500.0f, 0.95f, 1, 5, 1);
    const double rev = steady_step(c, 500.0f, 0.95f, -1, 5, 1);
    print_message("asymmetry 0.1: forward %.4g -> %.4g um, reverse %.4g -> %.4g um\n", fwd0 * 1e6, fwd * 1e6,
                  rev0 * 1e6, rev * 1e6);
    assert_true(fwd > 1.05 * fwd0);
    assert_true(-rev < 0.95 * -rev0);

    /* more friction further out drags the slider back more on the fast edge: smaller steps */
    c = gms_actuator();
    c.effects.friction_gradient_per_m = 2000.0f; /* +20 % over 100 um */
    const double near = steady_step(c, 500.0f, 0.95f, 1, 5, 1);
    const double far = steady_step_from(c, 1e-4f, 5, 1);
    print_message("friction gradient: step at 0 %.4g um, at 100 um %.4g um\n", near * 1e6, far * 1e6);
    assert_true(far < 0.9 * near);

    c = gms_actuator();
    c.effects.thermal_coeff_per_j = 500.0f;
    c.effects.thermal_tau_s = 1.0f;
    const double warm = steady_step(c, 500.0f, 0.95f, 1, 11, 1);
    const double cold = steady_step(gms_actuator(), 500.0f, 0.95f, 1, 11, 1);
    print_message("thermal: cold %.5g um, warm %.5g um per cycle\n", cold * 1e6, warm * 1e6);
    assert_true(warm > cold + 1e-9);

    /* a load above Fs slides the slider off at the velocity where viscous friction takes the
     * rest: (load - Fc) / sigma2 */
    c = gms_actuator();
    c.effects.load_n = 4.0f;
    ss_actuator_state_f32_t st;
    assert_int_equal(ss_actuator_init_f32(&c, &st, 0.0f), SS_OK);
    for (int i = 0; i < 50000; ++i) {
        assert_int_equal(ss_actuator_step_f32(&c, &st, 0.0f), SS_OK);
    }
    assert_close(st.v_slider_m_per_s, (4.0 - 3.0) / 8.0, 1e-3 * 0.125);
    /* below Fs it is held: the slider rings about a rest point and stops */
    c.effects.load_n = 1.0f;
    assert_int_equal(ss_actuator_init_f32(&c, &st, 0.0f), SS_OK);
    for (int i = 0; i < 40000; ++i) {
        assert_int_equal(ss_actuator_step_f32(&c, &st, 0.0f), SS_OK);
    }
    assert_true(fabsf(st.v_slider_m_per_s) < 1e-4f);
    assert_true(fabs((double)st.x_slider.hi_m - (double)st.x_rod_m) <
                2.0 * c.friction.fs_n / c.friction.sigma0_n_per_m);
}

/* The fixed-point family has no GMS: the converter refuses it by name. */
static void test_gms_refused_by_q_converter(void **unused)
{
    (void)unused;
    const ss_actuator_config_f32_t c = gms_actuator();
    ss_actuator_config_q_t q;
    const char *bad = NULL;
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "friction_model");
}

/* The GMS state keeps the actuator's friction union no larger than LS alone makes it. */
static void test_gms_state_size(void **unused)
{
    (void)unused;
    const ss_actuator_state_f32_t *st = NULL;
    print_message("sizeof: GMS state %zu, LS state %zu, actuator state %zu bytes\n",
                  sizeof(ss_gms_state_f32_t), sizeof(ss_ls_state_f32_t), sizeof(ss_actuator_state_f32_t));
    assert_true(sizeof(ss_gms_state_f32_t) <= sizeof(ss_ls_state_f32_t));
    assert_int_equal(sizeof st->fr, sizeof(ss_ls_state_f32_t));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gms_api),
        cmocka_unit_test(test_gms_shares),
        cmocka_unit_test(test_gms_virgin_curve_is_piecewise_linear),
        cmocka_unit_test(test_gms_unequal_stiffnesses),
        cmocka_unit_test(test_gms_initial_stiffness),
        cmocka_unit_test(test_gms_saturation),
        cmocka_unit_test(test_gms_wiping_out),
        cmocka_unit_test(test_gms_rate_independent),
        cmocka_unit_test(test_gms_damps_sticking_elements),
        cmocka_unit_test(test_gms_steady_sliding_is_stribeck),
        cmocka_unit_test(test_gms_asymmetric_sliding),
        cmocka_unit_test(test_gms_actuator_steps),
        cmocka_unit_test(test_gms_step_convergence),
        cmocka_unit_test(test_gms_damped_fast_edge_convergence),
        cmocka_unit_test(test_gms_fast_edge_substeps_are_one_step),
        cmocka_unit_test(test_gms_long_travel_keeps_resolution),
        cmocka_unit_test(test_gms_actuator_effects),
        cmocka_unit_test(test_gms_refused_by_q_converter),
        cmocka_unit_test(test_gms_state_size),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
