/* The fixed-point (_q) model against the float core: converter, friction properties, actuator
 * accuracy over the paper's drives (tests/vectors/fixed_model_drives.csv), long travel. */
#include "ss_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ss_abi.h"
#include "ss_convert_q.h"
#include "ss_fixed.h"

#define Q40 1099511627776.0 /* 2^40 */
#define Q24 16777216.0      /* 2^24 */

static const ss_friction_config_q_t *fq_table1(void)
{
    static ss_friction_config_q_t c;
    c = ss_friction_config_table1_q();
    return &c;
}

/* ---- converter and constants ---------------------------------------------------------------- */

/* table1_q is pure integer constants; they must be exactly what the converter makes of the float
 * Table I, or the two families would simulate different actuators. */
static void test_table1_constants_match_converter(void **unused)
{
    (void)unused;
    const ss_actuator_config_f32_t f = ss_actuator_config_table1_f32();
    ss_actuator_config_q_t conv;
    memset(&conv, 0, sizeof conv);
    const char *bad = NULL;
    assert_int_equal(ss_actuator_config_to_q(&f, &conv, &bad), SS_OK);
    assert_string_equal(bad, "");
    ss_actuator_config_q_t tab = ss_actuator_config_table1_q();
    assert_memory_equal(&conv, &tab, sizeof conv);
    ss_friction_config_q_t fr;
    assert_int_equal(ss_friction_config_to_q(&f.friction, &fr, NULL), SS_OK);
    assert_memory_equal(&fr, fq_table1(), sizeof fr);
    assert_int_equal(ss_actuator_config_check_q(&tab, &bad), SS_OK);
}

/* The paper's drive in q is what the converter makes of the float one, field by field. */
static void test_paper_drive_constants_match_converter(void **unused)
{
    (void)unused;
    const ss_waveform_config_f32_t f = ss_waveform_paper_f32();
    ss_waveform_config_q_t conv;
    memset(&conv, 0, sizeof conv);
    const char *bad = NULL;
    assert_int_equal(ss_waveform_config_to_q(&f, &conv, &bad), SS_OK);
    const ss_waveform_config_q_t tab = ss_waveform_paper_q();
    assert_memory_equal(&conv, &tab, sizeof conv);
    assert_int_equal(tab.rise_q32, 4080218880u);
}

/* Values that pass the float check but do not fit a Q format are rejected, and named. */
static void test_converter_names_bad_fields(void **unused)
{
    (void)unused;
    const ss_actuator_config_f32_t ok = ss_actuator_config_table1_f32();
    ss_actuator_config_q_t q;
    const char *bad = NULL;
    struct {
        float *field;
        float value;
        const char *name;
        ss_status_t status;
    } cases[7];
    ss_actuator_config_f32_t c = ok;
    cases[0].field = &c.friction.fs_n, cases[0].value = 100.0f, cases[0].name = "friction.fs_n";
    cases[1].field = &c.friction.vs_m_per_s, cases[1].value = 1e-9f, cases[1].name = "friction.vs_m_per_s";
    cases[2].field = &c.rod_mass_kg, cases[2].value = 1e-6f, cases[2].name = "rod_mass_kg";
    cases[3].field = &c.dt_s, cases[3].value = 5e-3f, cases[3].name = "dt_s"; /* float check: > 1e-3 */
    cases[4].field = &c.piezo_gain_m_per_v, cases[4].value = 1e-4f, cases[4].name = "piezo_gain_m_per_v";
    cases[5].field = &c.friction.sigma0_n_per_m, cases[5].value = 1e3f,
    cases[5].name = "friction.sigma0_n_per_m";
    cases[6].field = &c.friction.fc_n, cases[6].value = 0.01f, cases[6].name = "friction.fc_n";
    for (int i = 0; i < 7; ++i) {
        c = ok;
        *cases[i].field = cases[i].value;
        assert_int_not_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_OK);
        assert_string_equal(bad, cases[i].name);
    }
    /* effects the q family does not model are refused by name, never silently dropped */
    c = ok;
    c.effects.creep_ratio = 0.1f;
    c.effects.creep_tau_s = 1e-2f;
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "effects.creep_ratio");
    c = ok; /* an amplifier's bandwidth is a float-family effect */
    c.effects.slew_v_per_s = 1e6f;
    c.effects.amp_bandwidth_hz = 160e3f;
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "effects.amp_bandwidth_hz");
    c = ok; /* a hysteresis narrower than the q family's 0.93 nm */
    c.effects.hysteresis_alpha = 0.1f;
    c.effects.hysteresis_width_m = 1e-10f;
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "effects.hysteresis_width_m");
    /* the effects it models: converted, or refused by name beyond what their formats hold */
    c = ok;
    c.effects.load_n = 0.2f;
    c.effects.slew_v_per_s = 1e6f; /* 1 V/us: 1 V a step */
    c.effects.sensor_scale_error = -0.03f;
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_OK);
    assert_int_equal(q.effects.load_q24, 3355443);           /* 0.2 x 2^24, rounded */
    assert_int_equal(q.effects.slew_q24, 16777222);          /* 1e6 V/s x 1.00000034 us x 2^24 */
    assert_int_equal(q.effects.sensor_scale_q30, -32212254); /* float32(-0.03) x 2^30, rounded */
    c.friction.asymmetry = -0.9f;                            /* the float range's end fits the q check's */
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_OK);
    assert_int_equal(q.friction.asymmetry_q30, -966367616); /* float32(-0.9) x 2^30 */
    c.friction.asymmetry = 0.0f;
    c.effects.load_n = 40.0f; /* within the float range, beyond the q forces' 32 N */
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "effects.load_n");
    c.effects.load_n = 0.0f;
    c.effects.slew_v_per_s = 1e12f; /* 1e6 V a step: beyond 127 V */
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "effects.slew_v_per_s");
    c = ok;
    c.friction_model = SS_FRICTION_GMS; /* a float-family law: refused, never run as LS */
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "friction_model");
    c = ok;
    c.friction.sigma1_ns_per_m = NAN;
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_ERR_NONFINITE);
    assert_string_equal(bad, "friction.sigma1_ns_per_m");
    /* the q check names q fields */
    ss_actuator_config_q_t t = ss_actuator_config_table1_q();
    t.friction.fc_q24 = t.friction.fs_q24 + 1;
    assert_int_equal(ss_actuator_config_check_q(&t, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "friction.fc_q24");
    t = ss_actuator_config_table1_q();
    t.kick_slider_q40 = 0;
    ss_actuator_state_q_t st;
    assert_int_equal(ss_actuator_init_q(&t, &st, 0), SS_ERR_RANGE);
    assert_int_equal(ss_actuator_config_check_q(&t, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "kick_slider_q40");
    assert_int_equal(ss_actuator_config_check_q(NULL, &bad), SS_ERR_NULL);
    /* the corner's series holds to (w dt)^2 = 1; the converter writes 0 (the chord) past it */
    t = ss_actuator_config_table1_q();
    t.rod_w2dt2_q28 = (1 << 28) + 1;
    assert_int_equal(ss_actuator_config_check_q(&t, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "rod_w2dt2_q28");
    c = ok;
    c.dt_s = 3e-6f; /* (w dt)^2 = 1.7 for Table I's rod */
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_OK);
    assert_int_equal(q.rod_w2dt2_q28, 0);
    /* the step's reciprocal must be the step's, and the step long enough for it to fit 31 bits */
    t = ss_actuator_config_table1_q();
    t.inv_dt_q47 += 1;
    assert_int_equal(ss_actuator_init_q(&t, &st, 0), SS_ERR_RANGE);
    assert_int_equal(ss_actuator_config_check_q(&t, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "inv_dt_q47");
    t.dt_q40 = 65536; /* 0.0596 us: 2^47 / dt_q40 would be 2^31 */
    assert_int_equal(ss_actuator_config_check_q(&t, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "dt_q40");
    assert_int_equal(ss_actuator_inv_dt_q47(65536), 0);
    assert_int_equal(ss_actuator_inv_dt_q47(65537), 2147450880); /* 2^47 / 65537, rounded */
    assert_int_equal(ss_actuator_inv_dt_q47(INT32_MAX), 65536);  /* 17 bits at 1.95 ms */
    c = ok;
    c.dt_s = 5e-8f; /* within the float range, shorter than the q family's 0.06 us */
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "dt_s");
    /* the friction's reciprocals must be its own, and vs and sigma0 large enough for them to fit */
    t = ss_actuator_config_table1_q();
    t.friction.inv_vs_q45 -= 1;
    assert_int_equal(ss_actuator_config_check_q(&t, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "friction.inv_vs_q45");
    t = ss_actuator_config_table1_q();
    t.friction.inv_sigma0_q47 = 0;
    assert_int_equal(ss_actuator_init_q(&t, &st, 0), SS_ERR_RANGE);
    assert_int_equal(ss_actuator_config_check_q(&t, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "friction.inv_sigma0_q47");
    t = ss_actuator_config_table1_q();
    t.friction.vs_q28 = SS_Q_VS_MIN_Q28;
    ss_friction_config_reciprocals_q(&t.friction);
    assert_int_equal(t.friction.inv_vs_q45, 0);
    assert_int_equal(ss_actuator_config_check_q(&t, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "friction.vs_q28");
    t.friction.vs_q28 = SS_Q_VS_MIN_Q28 + 1;
    ss_friction_config_reciprocals_q(&t.friction);
    assert_int_equal(t.friction.inv_vs_q45, 2147352584); /* 2^45 / (2^14 + 1), rounded: 31 bits */
    assert_int_equal(ss_actuator_config_check_q(&t, &bad), SS_OK);
    c = ok;
    c.friction.vs_m_per_s = 5e-5f; /* 50 um/s: below the q family's 61 um/s */
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "friction.vs_m_per_s");
    c = ok;
    c.friction.sigma0_n_per_m = 6e4f; /* below the q family's 65.5 kN/m */
    c.friction.fs_n = 0.01f;          /* (a presliding length the element's frame holds) */
    c.friction.fc_n = 0.008f;
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "friction.sigma0_n_per_m");
    t = ss_actuator_config_table1_q();
    t.friction.inv_fs_q48 += 1;
    assert_int_equal(ss_actuator_config_check_q(&t, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "friction.inv_fs_q48");
    t = ss_actuator_config_table1_q();
    t.friction.sat_length_q40 -= 1;
    assert_int_equal(ss_actuator_config_check_q(&t, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "friction.sat_length_q40");
    c = ok;
    c.friction.fs_n = 0.005f; /* 5 mN: below the q family's 7.8 mN */
    c.friction.fc_n = 0.004f;
    assert_int_equal(ss_actuator_config_to_q(&c, &q, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "friction.fs_n");
    /* waveform */
    ss_waveform_config_f32_t w = ss_waveform_sawtooth_f32(500.0f, 100.0f, 0.0f, 0.95f, 1, 3);
    ss_waveform_config_q_t wq;
    assert_int_equal(ss_waveform_config_to_q(&w, &wq, &bad), SS_OK);
    assert_int_equal(wq.frequency_mhz, 500000u);
    assert_int_equal(wq.amplitude_q16, 100 << 16);
    w.amplitude_v = 40000.0f;
    assert_int_equal(ss_waveform_config_to_q(&w, &wq, &bad), SS_ERR_RANGE);
    assert_string_equal(bad, "amplitude_v");
}

/* ---- friction element: float and q side by side -------------------------------------------- */

typedef struct {
    ss_friction_config_f32_t cf;
    ss_friction_config_q_t cq;
    ss_ls_state_f32_t sf;
    ss_ls_state_q_t sq;
    double x;     /* exact path position, m */
    int64_t x_q;  /* round(x 2^40), so the q increments sum to the path without drift */
    float f_f32;  /* last forces */
    double f_q_n; /* in N */
} pair_t;

static void pair_init(pair_t *p, double sigma2)
{
    p->cf = ss_friction_config_table1_f32();
    p->cf.sigma2_ns_per_m = (float)sigma2;
    assert_int_equal(ss_friction_config_to_q(&p->cf, &p->cq, NULL), SS_OK);
    assert_int_equal(ss_ls_init_f32(&p->cf, &p->sf), SS_OK);
    assert_int_equal(ss_ls_init_q(&p->cq, &p->sq), SS_OK);
    p->x = 0.0;
    p->x_q = 0;
    p->f_f32 = 0.0f;
    p->f_q_n = 0.0;
}

/* Move both to x_to in increments of at most h at speed v; returns the worst |F_q - F_f32| (N). */
static double pair_move(pair_t *p, double x_to, double h, double v)
{
    double worst = 0.0;
    const int32_t dt_q = (int32_t)floor(h / v * Q40 + 0.5);
    while (fabs(x_to - p->x) > 1e-15) {
        double dx = x_to - p->x;
        if (fabs(dx) > h) {
            dx = (dx > 0) ? h : -h;
        }
        p->x += dx;
        const int64_t xq = (int64_t)floor(p->x * Q40 + 0.5);
        /* a last, shorter increment takes a whole step too (the q step is at least 0.06 us) */
        p->f_f32 = ss_ls_step_f32(&p->cf, &p->sf, (float)dx, (float)(h / v));
        p->f_q_n = ss_ls_step_q(&p->cq, &p->sq, (int32_t)(xq - p->x_q), dt_q) / Q24;
        p->x_q = xq;
        const double d = fabs(p->f_q_n - (double)p->f_f32);
        worst = d > worst ? d : worst;
    }
    return worst;
}

/* Read a one-column CSV of numbers (comment lines start with '#', one header line). */
static int read_column(const char *name, double *out, int cap)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", SS_VECTORS_DIR, name);
    FILE *fp = fopen(path, "r");
    assert_non_null(fp);
    char line[256];
    int n = 0, header = 1;
    while (fgets(line, sizeof line, fp) != NULL && n < cap) {
        if (line[0] == '#' || line[0] == '\n') {
            continue;
        }
        if (header) {
            header = 0;
            continue;
        }
        out[n++] = atof(line);
    }
    fclose(fp);
    return n;
}

/* Presliding hysteresis with nested minor loops (tests/vectors/presliding_path.csv): the q force
 * follows the float force within 2 % of Fs at every step (the bound). Measured: ~1e-6 Fs,
 * the 0.9 pm position quantum times sigma0. */
static void test_q_presliding_loops_follow_float(void **unused)
{
    (void)unused;
    double turns[64];
    const int n = read_column("presliding_path.csv", turns, 64);
    assert_true(n >= 4);
    pair_t p;
    pair_init(&p, 8.0);
    double worst = 0.0, fmax = 0.0;
    for (int i = 0; i < n; ++i) {
        const double w = pair_move(&p, turns[i] * 1e-6, 1e-9, 1e-3);
        worst = w > worst ? w : worst;
        fmax = fabs(p.f_q_n) > fmax ? fabs(p.f_q_n) : fmax;
    }
    print_message("presliding loops: worst |F_q - F_f32| = %.3g N = %.3g %% of Fs (peak %.3g Fs)\n", worst,
                  100.0 * worst / (double)p.cf.fs_n, fmax / (double)p.cf.fs_n);
    assert_true(fmax < 0.9 * (double)p.cf.fs_n); /* the path stays in presliding */
    assert_true(fmax > 0.5 * (double)p.cf.fs_n); /* and spans most of it */
    assert_true(worst < 0.02 * (double)p.cf.fs_n);
    /* the stack is back to empty after the last outer reversal's mirror is passed? it holds the
     * outer loop; both families agree on its depth */
    assert_int_equal(p.sq.depth, p.sf.depth);
}

/* sigma0 is the initial stiffness, from rest and right after a reversal (the q exponent keeps
 * 2^-32 resolution, so a 0.1 nm move is resolved to 1e-3). */
static void test_q_initial_stiffness(void **unused)
{
    (void)unused;
    pair_t p;
    pair_init(&p, 8.0);
    const double viscous = 1e-6 * 8.0;
    pair_move(&p, 1e-10, 1e-10, 1e-6);
    assert_close((p.f_q_n - viscous) / 1e-10, 1e7, 1e-3 * 1e7);
    pair_move(&p, 0.2e-6, 1e-9, 1e-6);
    const double fa = p.f_q_n;
    pair_move(&p, 0.2e-6 - 1e-10, 1e-10, 1e-6);
    assert_close((fa - p.f_q_n - 2.0 * viscous) / 1e-10, 1e7, 2e-3 * 1e7);
}

/* Steady sliding: the q force is the Stribeck curve g(v) + sigma2 v, as the float one (same
 * 2e-4 tolerance as the float test; the q error is the exp bound 2^-26 of 0.6 N, ~1e-8 N). */
static void test_q_steady_sliding_is_stribeck(void **unused)
{
    (void)unused;
    const double speeds[] = {1e-6, 1e-4, 4e-4, 1e-3, 1e-2};
    for (size_t i = 0; i < 5; ++i) {
        pair_t p;
        pair_init(&p, 8.0);
        pair_move(&p, 20e-6, 1e-9, speeds[i]);
        const double expect = (double)ss_stribeck_f32(&p.cf, (float)speeds[i]) + 8.0 * speeds[i];
        print_message("v %.0e m/s: q %.7f N, f32 %.7f N, g + sigma2 v %.7f N\n", speeds[i], p.f_q_n,
                      (double)p.f_f32, expect);
        assert_close(p.f_q_n, expect, 2e-4 * expect);
    }
    /* the curve itself, over four decades of speed */
    const ss_friction_config_f32_t cf = ss_friction_config_table1_f32();
    double worst = 0.0;
    for (double v = 1e-6; v < 1e-1; v *= 1.1) {
        const double gq = ss_stribeck_q(fq_table1(), (int32_t)floor(v * 268435456.0 + 0.5)) / Q24;
        const double r = v / (double)cf.vs_m_per_s;
        const double gd = 3.0 + 0.6000001 * exp(-r * r);
        worst = fmax(worst, fabs(gq - gd));
    }
    print_message("Stribeck curve: worst |g_q - g| = %.3g N\n", worst);
    assert_true(worst < 1e-5); /* v quantised to 2^-28 m/s: dg = 2 r g' dv < 1e-6 N */
}

/* Wiping-out: after a minor loop closes, the force is that of the path without the loop. The q
 * branches are recomputed from the same reversal point, so the forces agree to the bit. */
static void test_q_wiping_out(void **unused)
{
    (void)unused;
    pair_t a, b;
    pair_init(&a, 8.0);
    pair_init(&b, 8.0);
    pair_move(&a, -0.4e-6, 1e-10, 1e-6);
    pair_move(&b, -0.4e-6, 1e-10, 1e-6);
    pair_move(&b, 0.1e-6, 1e-10, 1e-6);
    const uint8_t depth = b.sq.depth;
    pair_move(&b, -0.05e-6, 1e-10, 1e-6);
    assert_int_equal(b.sq.depth, depth + 1);
    pair_move(&a, 0.3e-6, 1e-10, 1e-6);
    pair_move(&b, 0.3e-6, 1e-10, 1e-6);
    assert_int_equal(b.sq.depth, depth);
    assert_int_equal(b.sq.fm_q24, a.sq.fm_q24);
    assert_int_equal(b.sq.force_q24, a.sq.force_q24);
}

/* LS keeps the break-away gate of F_M in its state (gate_q30): along a path through presliding, the
 * gate's ramp and gross slip, a state made to take the gate again at every step (a wrong gate at a
 * forgotten Fs) steps to the same bits; and a config whose Fs moved is not read through the kept
 * gate. */
static void test_q_ls_gate_kept(void **unused)
{
    (void)unused;
    const ss_friction_config_q_t cfg = ss_friction_config_table1_q();
    ss_ls_state_q_t a;
    ss_ls_state_q_t b;
    memset(&a, 0, sizeof a); /* the padding too: the states are compared byte for byte */
    memset(&b, 0, sizeof b);
    assert_int_equal(ss_ls_init_q(&cfg, &a), SS_OK);
    assert_int_equal(ss_ls_init_q(&cfg, &b), SS_OK);
    const double amp_m = 12.0 * (cfg.fs_q24 / 16777216.0) / cfg.sigma0_n_per_m; /* into gross slip */
    const int32_t dt_q40 = 1099512;                                             /* 1 us */
    int64_t x_prev = 0;
    int ramp = 0;
    int slip = 0;
    for (int k = 1; k <= 20000; ++k) {
        const double x =
            amp_m * sin(6.283185307179586 * k / 4000.0) * (1.0 + 0.3 * sin(6.283185307179586 * k / 700.0));
        const int64_t x_q40 = (int64_t)llround(x * 1099511627776.0);
        const int32_t dx = (int32_t)(x_q40 - x_prev);
        x_prev = x_q40;
        b.gate_q30 = SS_Q30_ONE / 3; /* a wrong gate at a forgotten Fs: b takes the gate again */
        b.gate_fs_q24 = 0;
        assert_int_equal(ss_ls_step_q(&cfg, &a, dx, dt_q40), ss_ls_step_q(&cfg, &b, dx, dt_q40));
        assert_memory_equal(&a, &b, sizeof a);
        ramp += a.gate_q30 > 0 && a.gate_q30 < SS_Q30_ONE / 2;
        slip += a.gate_q30 > SS_Q30_ONE / 10 * 9 && a.level_q24 != cfg.fs_q24; /* the level moved */
    }
    print_message("LS gate kept: %d steps low on its ramp, %d at 0.9 or more in gross slip\n", ramp, slip);
    assert_true(ramp > 100 && slip > 1000); /* the path crossed the ramp and slid */
    /* Fs and Fc 20 % lower (a lighter normal force): the kept gate, taken at Table I's Fs, is not
     * read */
    ss_friction_config_f32_t f = ss_friction_config_table1_f32();
    f.fs_n *= 0.8f;
    f.fc_n *= 0.8f;
    ss_friction_config_q_t low;
    const char *bad = NULL;
    assert_int_equal(ss_friction_config_to_q(&f, &low, &bad), SS_OK);
    assert_true(low.fs_q24 != cfg.fs_q24);
    /* F_M at 0.85 of Table I's Fs on the virgin curve: gate 0 there, 1 under the lower Fs */
    assert_int_equal(ss_ls_init_q(&cfg, &a), SS_OK);
    const double u_m = -log(0.15) * (cfg.fs_q24 / 16777216.0) / cfg.sigma0_n_per_m;
    (void)ss_ls_step_q(&cfg, &a, (int32_t)llround(u_m * 1099511627776.0), dt_q40);
    assert_int_equal(a.gate_q30, 0);
    b = a;
    ss_ls_advance_q(&low, &b, 0, 1); /* no motion: b only takes its gate at the lower Fs */
    assert_int_equal(b.gate_q30, SS_Q30_ONE);
    ss_friction_slopes_q_t sa;
    ss_friction_slopes_q_t sb;
    assert_int_equal(ss_ls_force_at_q(&low, &a, 1 << 20, &sa), ss_ls_force_at_q(&low, &b, 1 << 20, &sb));
    assert_memory_equal(&sa, &sb, sizeof sa);
    assert_int_equal(ss_ls_step_q(&low, &a, 1000, dt_q40), ss_ls_step_q(&low, &b, 1000, dt_q40));
    assert_memory_equal(&a, &b, sizeof a);
}

/* Presliding below 0.9 Fs depends on the path only: in q the same path at 1000x the speed gives the
 * same force to the bit (viscous term off); LuGre q does not. */
static void test_q_rate_independent_lugre_not(void **unused)
{
    (void)unused;
    int32_t ls_f[2], lg_f[2];
    const double speeds[2] = {1e-6, 1e-3};
    for (int k = 0; k < 2; ++k) {
        pair_t p;
        pair_init(&p, 0.0);
        pair_move(&p, 0.25e-6, 1e-9, speeds[k]);
        pair_move(&p, -0.25e-6, 1e-9, speeds[k]);
        ls_f[k] = p.sq.force_q24;
        ss_lugre_state_q_t lg;
        ss_lugre_init_q(&p.cq, &lg);
        const int32_t dx = (int32_t)floor(1e-9 * Q40 + 0.5);
        const int32_t dt = (int32_t)floor(1e-9 / speeds[k] * Q40 + 0.5);
        for (int i = 0; i < 250; ++i) {
            ss_lugre_step_q(&p.cq, &lg, dx, dt);
        }
        for (int i = 0; i < 500; ++i) {
            lg_f[k] = ss_lugre_step_q(&p.cq, &lg, -dx, dt);
        }
    }
    print_message("q force at -0.25 um, 1 um/s vs 1 mm/s: LS %.6g vs %.6g N, LuGre %.5g vs %.5g N\n",
                  ls_f[0] / Q24, ls_f[1] / Q24, lg_f[0] / Q24, lg_f[1] / Q24);
    assert_int_equal(ls_f[1], ls_f[0]);
    assert_true(fabs((double)lg_f[1] - (double)lg_f[0]) / Q24 > 1e-2 * 3.6);
}

/* Dupont's biased-force drift test with the q elements: a 13.8 g mass under 0..0.8 Fs at 50 Hz,
 * integrated in double; the position is quantised to 2^-40 m without accumulating rounding. */
static double drift_per_period_q(int lugre)
{
    const ss_friction_config_q_t *c = fq_table1();
    ss_ls_state_q_t ls;
    ss_lugre_state_q_t lg;
    ss_ls_init_q(c, &ls);
    ss_lugre_init_q(c, &lg);
    const double m = 1.38e-2, f_hz = 50.0, dt = 1e-6, fs = 3.6;
    const int32_t dt_q = (int32_t)floor(dt * Q40 + 0.5);
    const int per = (int)(1.0 / (f_hz * dt) + 0.5);
    double x = 0.0, v = 0.0, f = 0.0, x_prev = 0.0, drift = 0.0;
    int64_t xq_prev = 0;
    for (int k = 0; k < 20 * per; ++k) {
        const double fext = fs * (0.4 + 0.4 * sin(6.283185307179586 * f_hz * k * dt));
        v += (fext - f) / m * dt;
        x += v * dt;
        const int64_t xq = (int64_t)floor(x * Q40 + 0.5);
        const int32_t dxq = (int32_t)(xq - xq_prev);
        xq_prev = xq;
        f = (lugre ? ss_lugre_step_q(c, &lg, dxq, dt_q) : ss_ls_step_q(c, &ls, dxq, dt_q)) / Q24;
        if ((k + 1) % per == 0) {
            drift = x - x_prev;
            x_prev = x;
        }
    }
    return drift;
}

static void test_q_no_drift_ls_drift_lugre(void **unused)
{
    (void)unused;
    const double d_ls = drift_per_period_q(0);
    const double d_lg = drift_per_period_q(1);
    print_message("q drift per period: LS %.3g m, LuGre %.3g m\n", d_ls, d_lg);
    /* one position quantum (0.9 pm) of dither per period at most; LuGre creeps 1e5 x more */
    assert_true(fabs(d_ls) < 2e-12);
    assert_true(d_lg > 1e-7);
}

static void test_q_memory_depth_bounded(void **unused)
{
    (void)unused;
    pair_t p;
    pair_init(&p, 8.0);
    double amp = 0.3e-6;
    for (int i = 0; i < 3 * SS_LS_Q_MEMORY_DEPTH; ++i) {
        pair_move(&p, (i % 2) ? amp : -amp, 1e-10, 1e-3);
        amp *= 0.9;
        assert_true(p.sq.depth <= SS_LS_Q_MEMORY_DEPTH);
        assert_true(abs(p.sq.fm_q24) <= p.cq.fs_q24);
        assert_int_equal(p.sq.depth, p.sf.depth);
    }
}

/* ---- actuator ------------------------------------------------------------------------------- */

enum { MAX_CYCLES = 16 };

/* Slider position at the period boundaries (x[0] at t = 0 .. x[cycles]) for both families, taken
 * at the same step numbers round(k / (f dt)): the float player and the q phase accumulator may
 * put a boundary one step apart, and the slider can be sliding there (20 nm in a step at 300 Hz). */
static void run_both(ss_actuator_config_f32_t cf, double f_hz, double amp_v, double rise, uint32_t cycles,
                     double *x_f, double *x_q, int64_t x0_q)
{
    ss_actuator_config_q_t cq;
    assert_int_equal(ss_actuator_config_to_q(&cf, &cq, NULL), SS_OK);
    ss_waveform_config_f32_t wf =
        ss_waveform_sawtooth_f32((float)f_hz, (float)amp_v, 0.0f, (float)rise, 1, cycles);
    ss_waveform_config_q_t wq;
    assert_int_equal(ss_waveform_config_to_q(&wf, &wq, NULL), SS_OK);
    ss_waveform_state_f32_t swf;
    ss_waveform_state_q_t swq;
    ss_actuator_state_f32_t sf;
    ss_actuator_state_q_t sq;
    assert_int_equal(ss_waveform_init_f32(&wf, cf.dt_s, &swf), SS_OK);
    assert_int_equal(ss_waveform_init_q(&wq, cq.dt_q40, &swq), SS_OK);
    assert_int_equal(ss_actuator_init_f32(&cf, &sf, 0.0f), SS_OK);
    assert_int_equal(ss_actuator_init_q(&cq, &sq, 0), SS_OK);
    sq.x_slider_q40 = x0_q;
    x_f[0] = 0.0;
    x_q[0] = 0.0;
    const double per = 1.0 / (f_hz * (double)cf.dt_s);
    uint32_t n = 0;
    for (uint32_t k = 1; k <= cycles; ++k) {
        for (const uint32_t n_k = (uint32_t)floor(k * per + 0.5); n < n_k; ++n) {
            ss_actuator_wave_step_f32(&cf, &sf, &wf, &swf); /* both with the drive's corners */
            ss_actuator_wave_step_q(&cq, &sq, &wq, &swq);
        }
        x_f[k] = ss_position_value_f32(sf.x_slider);
        x_q[k] = (double)(sq.x_slider_q40 - x0_q) / Q40;
    }
}

/* Per-cycle steps over the drives of tests/vectors/fixed_model_drives.csv, every cycle from the
 * virgin start on: |q - f32| within the file's share (the 1 %) of the float step, or of
 * 0.1 % of the stroke where the slider hardly steps (100 Hz: the 500 us fall lets it follow the
 * rod back, steps < 1 nm, below the float core's own discretisation error of 0.08 % of a 2 um
 * step, docs/model.md). */
static void test_q_actuator_steps_match_float(void **unused)
{
    (void)unused;
    char path[512];
    snprintf(path, sizeof path, "%s/fixed_model_drives.csv", SS_VECTORS_DIR);
    FILE *fp = fopen(path, "r");
    assert_non_null(fp);
    char line[256];
    int header = 1, cases = 0;
    double worst_all = 0.0;
    while (fgets(line, sizeof line, fp) != NULL) {
        if (line[0] == '#' || line[0] == '\n') {
            continue;
        }
        if (header) {
            header = 0;
            continue;
        }
        double f_hz, amp, rise, tol;
        unsigned cycles;
        char model[16];
        assert_int_equal(
            sscanf(line, "%lf,%lf,%lf,%u,%15[a-z],%lf", &f_hz, &amp, &rise, &cycles, model, &tol), 6);
        assert_true(cycles <= MAX_CYCLES);
        ss_actuator_config_f32_t cf = ss_actuator_config_table1_f32();
        cf.friction_model = (strcmp(model, "lugre") == 0) ? SS_FRICTION_LUGRE : SS_FRICTION_LS;
        double xf[MAX_CYCLES + 1], xq[MAX_CYCLES + 1];
        run_both(cf, f_hz, amp, rise, cycles, xf, xq, 0);
        const double floor_m = 1e-3 * amp * (double)cf.piezo_gain_m_per_v;
        double worst = 0.0, worst_abs = 0.0, settled = 0.0;
        for (unsigned k = 1; k <= cycles; ++k) {
            const double sf = xf[k] - xf[k - 1], sq = xq[k] - xq[k - 1];
            const double err = fabs(sq - sf) / fmax(fabs(sf), floor_m / tol);
            worst = err > worst ? err : worst;
            worst_abs = fmax(worst_abs, fabs(sq - sf));
            settled = sf;
        }
        print_message(
            "%6.0f Hz %5.1f V rise %.2f %-5s: last step %8.4f um, worst |q - f32| %.4f %% (%.3g nm)\n", f_hz,
            amp, rise, model, settled * 1e6, 100.0 * worst, worst_abs * 1e9);
        assert_true(worst < tol);
        worst_all = worst > worst_all ? worst : worst_all;
        ++cases;
    }
    fclose(fp);
    print_message("%d drives, worst per-cycle step error %.4f %% of the tolerance's base\n", cases,
                  100.0 * worst_all);
    assert_true(cases >= 15);
}

/* The effects the q family models (load, slew limit, asymmetric friction) against float, per
 * cycle, as the drives above: |q - f32| within 1 % of the float step (the bound) or 1e-3 of
 * the stroke where the slider hardly steps. A load of 0.2 N (Fc is 3 N), slews of 1 and 3 V/us,
 * which stretch the 15 us fall of 95 V to 95 and 32 us, and a contact 20 % stronger one way. */
static void test_q_effects_steps_match_float(void **unused)
{
    (void)unused;
    const float loads[] = {0.2f, -0.2f, 0.0f, 0.0f, 0.2f, 0.0f, 0.0f,
                           0.2f, 0.0f,  0.0f, 0.2f, 0.0f, 0.0f, 0.2f};
    const float slews[] = {0.0f, 0.0f, 1e6f, 3e6f, 3e6f, 0.0f, 0.0f,
                           0.0f, 0.0f, 0.0f, 3e6f, 0.0f, 0.0f, 0.0f};
    const float asyms[] = {0.0f,  0.0f, 0.0f, 0.0f, 0.0f, 0.2f, -0.2f,
                           -0.2f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
    const float hyst_alpha[] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f,
                                0.0f, 0.1f, 0.3f, 0.3f, 0.0f, 0.0f, 0.1f};
    const float hyst_width_m[] = {0, 0, 0, 0, 0, 0, 0, 0, 1e-6f, 2e-7f, 2e-7f, 0, 0, 1e-6f};
    /* base: mass (kg), its resonance (Hz) and damping ratio */
    const float base_kg[] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.02f, 0.01f, 0.05f};
    const float base_hz[] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 4000.0f, 2000.0f, 8000.0f};
    const float base_zeta[] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.05f, 0.1f, 0.02f};
    const double freqs[] = {300.0, 500.0, 1000.0, 2000.0};
    double worst_all = 0.0;
    for (int model = 0; model < 2; ++model) {
        for (size_t e = 0; e < sizeof loads / sizeof loads[0]; ++e) {
            double worst = 0.0;
            for (size_t i = 0; i < sizeof freqs / sizeof freqs[0]; ++i) {
                ss_actuator_config_f32_t cf = ss_actuator_config_table1_f32();
                cf.friction_model = model ? SS_FRICTION_LUGRE : SS_FRICTION_LS;
                cf.effects.load_n = loads[e];
                cf.effects.slew_v_per_s = slews[e];
                cf.friction.asymmetry = asyms[e];
                cf.effects.hysteresis_alpha = hyst_alpha[e];
                cf.effects.hysteresis_width_m = hyst_width_m[e];
                cf.effects.base_mass_kg = base_kg[e];
                cf.effects.base_freq_hz = base_hz[e];
                cf.effects.base_damping_ratio = base_zeta[e];
                double xf[9], xq[9];
                run_both(cf, freqs[i], 100.0, 0.95, 8, xf, xq, 0);
                const double floor_m = 1e-3 * 100.0 * (double)cf.piezo_gain_m_per_v;
                for (int k = 1; k <= 8; ++k) {
                    const double sf = xf[k] - xf[k - 1], sq = xq[k] - xq[k - 1];
                    const double err = fabs(sq - sf) / fmax(fabs(sf), floor_m / 0.01);
                    worst = fmax(worst, err);
                    assert_true(err < 0.01);
                }
            }
            print_message("%-5s load %+.1f N, slew %.0f V/us, asymmetry %+.1f, hysteresis %.1f over %.1f um, "
                          "base %.2f kg at %.0f Hz: worst per-cycle step error %.4f %%\n",
                          model ? "lugre" : "ls", (double)loads[e], (double)slews[e] * 1e-6, (double)asyms[e],
                          (double)hyst_alpha[e], (double)hyst_width_m[e] * 1e6, (double)base_kg[e],
                          (double)base_hz[e], 100.0 * worst);
            worst_all = fmax(worst_all, worst);
        }
    }
    print_message(
        "q effects (load, slew, asymmetry, hysteresis, base): worst per-cycle step error %.4f %% of the "
        "float step\n",
        100.0 * worst_all);
}

/* The sensor's scale error: x + e x in integers equals the exact product to the rounding of the
 * low part (1 LSB), over the whole int64 travel's practical range and both signs. */
static void test_q_sensor_scale(void **unused)
{
    (void)unused;
    ss_actuator_config_q_t c = ss_actuator_config_table1_q();
    const int32_t es[] = {-(SS_Q30_ONE / 2), -32212254, 1, 5368709, SS_Q30_ONE / 2};
    const int64_t xs[] = {0, 1, -1, 123456789, -987654321012LL, (int64_t)1 << 50, -((int64_t)1 << 52)};
    for (size_t i = 0; i < sizeof es / sizeof es[0]; ++i) {
        c.effects.sensor_scale_q30 = es[i];
        for (size_t j = 0; j < sizeof xs / sizeof xs[0]; ++j) {
            const long double exact = (long double)xs[j] * (1.0L + (long double)es[i] / 1073741824.0L);
            const int64_t got = ss_actuator_sensor_q(&c, xs[j]);
            assert_true(fabsl((long double)got - exact) <= 1.0L);
        }
    }
    c.effects.sensor_scale_q30 = 0;
    assert_true(ss_actuator_sensor_q(&c, -((int64_t)1 << 52)) == -((int64_t)1 << 52));
}

/* Travel of +-25 mm at 2^-40 m: nothing in the q model depends on where the slider is, so a run
 * that starts at -25 mm or +25 mm steps exactly (to the bit) as one that starts at 0. */
static void test_q_long_travel_is_exact(void **unused)
{
    (void)unused;
    const ss_actuator_config_f32_t cf = ss_actuator_config_table1_f32();
    double xf[5], x0[5], xm[5], xp[5];
    const int64_t mm25 = (int64_t)floor(25e-3 * Q40 + 0.5);
    run_both(cf, 2000.0, 100.0, 0.95, 4, xf, x0, 0);
    run_both(cf, 2000.0, 100.0, 0.95, 4, xf, xm, -mm25);
    run_both(cf, 2000.0, 100.0, 0.95, 4, xf, xp, mm25);
    for (int k = 0; k < 5; ++k) {
        assert_true(xm[k] == x0[k] && xp[k] == x0[k]);
    }
    assert_true(x0[4] > 4e-6);
}

static void test_q_rest_stays_at_rest(void **unused)
{
    (void)unused;
    const ss_actuator_config_q_t c = ss_actuator_config_table1_q();
    ss_actuator_state_q_t st;
    assert_int_equal(ss_actuator_init_q(&c, &st, 30 << 16), SS_OK);
    for (int k = 0; k < 10000; ++k) {
        assert_int_equal(ss_actuator_step_q(&c, &st, 30 << 16), SS_OK);
    }
    assert_true(st.x_slider_q40 == 0);
    assert_int_equal(st.force_q24, 0);
    /* 30 V x 44 nm/V = 1.32 um, to the position quantum */
    assert_close(st.x_rod_q40 / Q40, 1.32e-6, 2.0 / Q40);
}

/* The run loop records exactly what stepping by hand produces; the trace columns are the state. */
static void test_q_run_matches_manual_steps(void **unused)
{
    (void)unused;
    const ss_actuator_config_q_t c = ss_actuator_config_table1_q();
    const ss_waveform_config_q_t w = ss_waveform_sawtooth_q(500000u, 100 << 16, 0, 4080218931u, 1, 2);
    ss_waveform_state_q_t wa, wb;
    ss_actuator_state_q_t a, b;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    ss_waveform_init_q(&w, c.dt_q40, &wa);
    ss_waveform_init_q(&w, c.dt_q40, &wb);
    ss_actuator_init_q(&c, &a, 0);
    ss_actuator_init_q(&c, &b, 0);
    enum { N = 4000, DEC = 7, ROWS = N / DEC };
    static uint32_t step[ROWS];
    static int32_t col[8][ROWS];
    static int64_t xs[ROWS], xm[ROWS];
    ss_actuator_trace_q_t tr = {step,   col[0], col[1], col[2], xs, col[3],
                                col[4], col[5], col[6], col[7], xm, ROWS};
    uint32_t rows = 0;
    assert_int_equal(ss_actuator_run_q(&c, &a, &w, &wa, N, DEC, &tr, &rows), SS_OK);
    assert_int_equal(rows, ROWS);
    for (uint32_t k = 1; k <= N; ++k) {
        ss_actuator_wave_step_q(&c, &b, &w, &wb);
        if (k % DEC == 0) {
            const uint32_t r = k / DEC - 1;
            assert_int_equal(step[r], k);
            assert_true(xs[r] == b.x_slider_q40);
            assert_true(xm[r] == b.x_slider_q40); /* no sensor scale error */
            assert_int_equal(col[5][r], b.force_q24);
            assert_int_equal(col[6][r], b.fr.ls.level_q24);
            assert_int_equal(col[7][r], b.fr.ls.fm_q24);
        }
    }
    assert_memory_equal(&a, &b, sizeof a);
    ss_actuator_si_t si;
    ss_actuator_state_q_to_si(&c, &b, &si);
    assert_close(si.x_slider_m, (double)b.x_slider_q40 / Q40, 0.0);
    assert_close(si.force_n, b.force_q24 / Q24, 0.0);
    tr.capacity = ROWS - 1;
    assert_int_equal(ss_actuator_run_q(&c, &a, &w, &wa, N, DEC, &tr, &rows), SS_ERR_RANGE);
    assert_int_equal(ss_actuator_run_q(&c, &a, &w, &wa, N, 0, NULL, &rows), SS_ERR_RANGE);
    assert_int_equal(ss_actuator_run_q(&c, &a, &w, &wa, N, 1, NULL, NULL), SS_ERR_NULL);
}

/* The q player's corners are the float player's: the same steps, the same drive there, the same
 * place within 5e-4 of a step, the two steps' difference aside (the float player's time into a
 * period is float32: 2.3e-10 s, 2.3e-4 of a step, its last bit at 3 ms; measured up to 3.3e-4), both
 * directions, a 300 Hz sawtooth whose corners fall at a third and two thirds of a step; and a
 * corner share outside (0, 1) is refused with the state unchanged. */
static void test_q_waveform_corners(void **unused)
{
    (void)unused;
    for (int dir = -1; dir <= 1; dir += 2) {
        ss_waveform_config_f32_t wf = ss_waveform_sawtooth_f32(300.0f, 100.0f, 2.0f, 0.95f, dir, 3);
        ss_waveform_config_q_t wq;
        assert_int_equal(ss_waveform_config_to_q(&wf, &wq, NULL), SS_OK);
        ss_actuator_config_f32_t cf = ss_actuator_config_table1_f32();
        ss_actuator_config_q_t cq;
        assert_int_equal(ss_actuator_config_to_q(&cf, &cq, NULL), SS_OK);
        ss_waveform_state_q_t sq;
        ss_waveform_state_f32_t sf;
        assert_int_equal(ss_waveform_init_q(&wq, cq.dt_q40, &sq), SS_OK);
        assert_int_equal(ss_waveform_init_f32(&wf, cf.dt_s, &sf), SS_OK);
        int corners = 0;
        for (int k = 0; k < 10500; ++k) {
            float frac_f = 0.0f, v_f = 0.0f;
            int32_t frac_q = 0, v_q = 0;
            const int has_f = ss_waveform_corner_f32(&wf, &sf, &frac_f, &v_f);
            const int has_q = ss_waveform_corner_q(&wq, &sq, &frac_q, &v_q);
            if (has_q && !has_f) {
                /* on the grid for the float player, 3.5e-3 of a step inside for q's longer step */
                const double fq = frac_q / 1073741824.0;
                assert_true(fmin(fq, 1.0 - fq) < 5e-3);
            }
            assert_true(has_q || !has_f);
            if (has_f) {
                /* the q step is 3.4e-7 of itself longer than the float one: k steps in, the q
                 * corner lies k x 3.4e-7 of a step earlier within its step */
                const double drift = (double)k * ((double)cq.dt_q40 * 0x1p-40 / (double)cf.dt_s - 1.0);
                assert_true(fabs(frac_q / 1073741824.0 + drift - (double)frac_f) < 5e-4);
                assert_int_equal(v_q, ss_volts_to_q16((double)v_f));
                ++corners;
            }
            ss_waveform_advance_q(&sq);
            ss_waveform_advance_f32(&sf);
        }
        assert_int_equal(corners, 4); /* of 6: the period boundaries at 10 ms lie on the grid */
    }
    ss_actuator_config_q_t c = ss_actuator_config_table1_q();
    ss_actuator_state_q_t st;
    assert_int_equal(ss_actuator_init_q(&c, &st, 0), SS_OK);
    const ss_actuator_state_q_t before = st;
    assert_int_equal(ss_actuator_step_corner_q(&c, &st, 1 << 16, 0, 1 << 16), SS_ERR_RANGE);
    assert_int_equal(ss_actuator_step_corner_q(&c, &st, 1 << 16, SS_Q30_ONE, 1 << 16), SS_ERR_RANGE);
    assert_memory_equal(&st, &before, sizeof st);
    assert_int_equal(ss_actuator_step_corner_q(&c, &st, 1 << 16, SS_Q30_ONE / 2, 2 << 16), SS_OK);
}

/* The sawtooth's value by 64-bit division, as the player computed it before its division became a
 * reciprocal and a remainder: the player must give these bits exactly, from the reciprocal the
 * shape computes (ss_sawtooth_at_phase_q) and from the one init cached in the player's state. */
static int32_t sawtooth_by_division(const ss_waveform_config_q_t *cfg, uint32_t phase_q32)
{
    const uint64_t one = (uint64_t)1 << 32;
    const uint64_t r = cfg->rise_q32;
    const uint64_t p = (cfg->direction < 0) ? one - phase_q32 : phase_q32;
    const uint64_t a = (cfg->amplitude_q16 < 0) ? (uint64_t)0 - (uint64_t)(int64_t)cfg->amplitude_q16
                                                : (uint64_t)cfg->amplitude_q16;
    const uint64_t num = (p < r) ? a * p : a * (one - p);
    const uint64_t den = (p < r) ? r : one - r;
    const int64_t mag = (int64_t)((num + den / 2u) / den);
    const int64_t v = (int64_t)cfg->offset_q16 + ((cfg->amplitude_q16 < 0) ? -mag : mag);
    return (v > INT32_MAX) ? INT32_MAX : (v < INT32_MIN) ? INT32_MIN : (int32_t)v;
}

static int32_t player_at(const ss_waveform_config_q_t *w, uint32_t phase_q32)
{
    ss_waveform_state_q_t st;
    assert_int_equal(ss_waveform_init_q(w, 1 << 20, &st), SS_OK);
    st.phase_q64 = ((uint64_t)phase_q32 << 32) | 0x9e3779b9u; /* the low word is not read */
    const int32_t v = ss_waveform_value_q(w, &st);
    assert_int_equal(v, ss_sawtooth_at_phase_q(w, phase_q32));
    return v;
}

static void test_q_sawtooth_without_division_is_exact(void **unused)
{
    (void)unused;
    /* the divisor's extremes (a rise of 1, of 2^32 - 1, a divisor either side of 2^31, where the
     * reciprocal takes it halved), the amplitude's (0, +-1, INT32_MIN, INT32_MAX), the phase's */
    const uint32_t rises[] = {1u,          2u,          3u,          0x7fffffffu, 0x80000000u,
                              0x80000001u, 0xfffffffeu, 0xffffffffu, 4080218880u};
    const int32_t amps[] = {0, 1, -1, INT32_MIN, INT32_MAX, 100 * 65536, -37 * 65536};
    const uint32_t phases[] = {0u,          1u,          2u,          0x7fffffffu, 0x80000000u,
                               0xfffffffeu, 0xffffffffu, 4080218879u, 4080218880u, 4080218881u};
    long checked = 0;
    for (size_t i = 0; i < sizeof rises / sizeof rises[0]; ++i) {
        for (size_t j = 0; j < sizeof amps / sizeof amps[0]; ++j) {
            for (int dir = -1; dir <= 1; dir += 2) {
                ss_waveform_config_q_t w = ss_waveform_sawtooth_q(1000000u, amps[j], 0, rises[i], dir, 1u);
                for (size_t k = 0; k < sizeof phases / sizeof phases[0]; ++k) {
                    assert_int_equal(player_at(&w, phases[k]), sawtooth_by_division(&w, phases[k]));
                    ++checked;
                }
                /* the phase just either side of the corner */
                for (int64_t dp = -2; dp <= 2; ++dp) {
                    const uint32_t ph = (uint32_t)((int64_t)rises[i] + dp);
                    assert_int_equal(player_at(&w, ph), sawtooth_by_division(&w, ph));
                    ++checked;
                }
            }
        }
    }
    /* and random configurations and phases, the offset included */
    uint64_t seed = 0x2545f4914f6cdd1dull;
    for (int n = 0; n < 200000; ++n) {
        const uint32_t rise = (uint32_t)(ss_test_xorshift(&seed) >> 32) | 1u;
        const int32_t amp = (int32_t)(ss_test_xorshift(&seed) >> 32) >> (ss_test_xorshift(&seed) % 24u);
        const int32_t off = (int32_t)(ss_test_xorshift(&seed) >> 32) >> 8;
        const int32_t dir = (ss_test_xorshift(&seed) & 1u) ? 1 : -1;
        ss_waveform_config_q_t w = ss_waveform_sawtooth_q(1000000u, amp, off, rise, dir, 1u);
        const uint32_t ph = (uint32_t)(ss_test_xorshift(&seed) >> 32);
        assert_int_equal(player_at(&w, ph), sawtooth_by_division(&w, ph));
        ++checked;
    }
    print_message("sawtooth by reciprocal and remainder: %ld values, each the division's\n", checked);
}

/* n steps at once: the phase and period index of n single steps, across a period's end, for short
 * and long skips, and with the index saturated. */
static void test_q_waveform_advance_by(void **unused)
{
    (void)unused;
    const ss_waveform_config_q_t w = ss_waveform_sawtooth_q(2000000u, 100 << 16, 0, 4080218880u, 1, 3u);
    uint64_t seed = 0x9e3779b97f4a7c15ull;
    long wraps = 0;
    for (int k = 0; k < 2000; ++k) {
        ss_waveform_state_q_t a;
        assert_int_equal(ss_waveform_init_q(&w, (int32_t)(1 + ss_test_xorshift(&seed) % 700000u), &a), SS_OK);
        a.phase_q64 = ss_test_xorshift(&seed);
        a.index = (k % 7 == 0) ? UINT32_MAX - 1u : (uint32_t)(k % 5);
        ss_waveform_state_q_t b = a;
        const uint32_t n = (uint32_t)(ss_test_xorshift(&seed) % 300u);
        ss_waveform_advance_by_q(&a, n);
        for (uint32_t i = 0; i < n; ++i) {
            ss_waveform_advance_q(&b);
        }
        assert_memory_equal(&a, &b, sizeof a);
        wraps += a.index != (uint32_t)(k % 5) && k % 7 != 0;
    }
    assert_true(wraps > 100); /* the period's end is crossed often */
}

/* The phase accumulator: period boundaries at the exact step, shape as the float sawtooth. */
static void test_q_waveform(void **unused)
{
    (void)unused;
    ss_waveform_config_f32_t wf = ss_waveform_sawtooth_f32(1000.0f, 10.0f, 1.0f, 0.8f, 1, 2);
    ss_waveform_config_q_t wq;
    assert_int_equal(ss_waveform_config_to_q(&wf, &wq, NULL), SS_OK);
    const int32_t dt_q = 1099512;
    ss_waveform_state_q_t st;
    ss_waveform_state_f32_t sf;
    assert_int_equal(ss_waveform_init_q(&wq, dt_q, &st), SS_OK);
    assert_int_equal(ss_waveform_init_f32(&wf, 1e-6f, &sf), SS_OK);
    double worst = 0.0;
    for (int k = 0; k < 2500; ++k) {
        /* dt_q is 1.00000034 us: 1000 steps are 0.34 ns more than a period, a 3.4 uV shift */
        worst = fmax(worst,
                     fabs(ss_waveform_value_q(&wq, &st) / 65536.0 - (double)ss_waveform_value_f32(&wf, &sf)));
        if (k == 999 || k == 1999) {
            assert_int_equal(st.index, (uint32_t)(k / 1000));
        }
        ss_waveform_advance_q(&st);
        ss_waveform_advance_f32(&sf);
    }
    print_message("sawtooth: worst |V_q - V_f32| = %.3g V\n", worst);
    assert_true(worst < 1e-3); /* float32 tau/period rounding dominates */
    assert_int_equal(ss_waveform_value_q(&wq, &st), 1 << 16);
    /* reversed direction is the period played backwards */
    ss_waveform_config_q_t r = wq;
    r.direction = -1;
    for (uint32_t i = 0; i < 63u; ++i) {
        const uint32_t p = (1u << 20) + i * (1u << 26);
        assert_int_equal(ss_sawtooth_at_phase_q(&r, p), ss_sawtooth_at_phase_q(&wq, (uint32_t)(0u - p)));
    }
    int32_t out[3];
    assert_int_equal(ss_waveform_fill_q(&wq, &st, out, 3), SS_OK);
    assert_int_equal(ss_waveform_init_q(&wq, 0, &st), SS_ERR_RANGE);
    wq.frequency_mhz = 2000000000u; /* 2 MHz: a period shorter than the 1 us step */
    assert_int_equal(ss_waveform_init_q(&wq, dt_q, &st), SS_ERR_RANGE);
}

/* q_check.c's effects: 0.25 N of load, 1 V a step of slew, a hysteresis of 0.25 over 0.95 um, a
 * 20 g base, and the stack's stiffness and damping it needs. */
static void q_check_effects(ss_actuator_config_q_t *fx)
{
    fx->effects.load_q24 = 1 << 22;
    fx->effects.slew_q24 = 1 << 24;
    fx->effects.hysteresis_alpha_q30 = 1 << 28;
    fx->effects.hysteresis_width_q40 = 1 << 20;
    fx->effects.hysteresis_inv_width_q48 = (int64_t)1 << 28;
    fx->effects.base_kick_q40 = 27487791;
    fx->effects.base_stiffness_n_per_m = 12633094;
    fx->effects.base_damping_q16 = 3292990;
    fx->effects.piezo_stiffness_n_per_m = 208000000;
    fx->effects.piezo_damping_q16 = 406323;
}

/* The q arithmetic is bit-identical on every target: fw/q_check.c runs this same drive (under LS,
 * LuGre, and LuGre with effects) on the Cortex-M0+ build, whose 32 x 32 -> 64 products are made
 * from 16-bit halves, and exits non-zero unless it lands on the same 2^-40 m each time. */
static void test_q_bit_exact_reference(void **unused)
{
    (void)unused;
    const ss_actuator_config_q_t cfg = ss_actuator_config_table1_q();
    const ss_waveform_config_q_t w = ss_waveform_sawtooth_q(2000000u, 100 << 16, 0, 4080218931u, 1, 2u);
    ss_waveform_state_q_t ws;
    ss_actuator_state_q_t st;
    uint32_t rows = 0;
    assert_int_equal(ss_waveform_init_q(&w, cfg.dt_q40, &ws), SS_OK);
    assert_int_equal(ss_actuator_init_q(&cfg, &st, ss_waveform_value_q(&w, &ws)), SS_OK);
    assert_int_equal(ss_actuator_run_q(&cfg, &st, &w, &ws, 1000u, 250u, NULL, &rows), SS_OK);
    /* SS_Q_CHECK_X_SLIDER in q_check.c: 8.54 um (9386164 while the step divided by Fs: 7 fm;
     * 9386156 before the rod's compliance was taken up in the contact's force, 9387071 before LS
     * kept the turning point inside a step) */
    assert_true(st.x_slider_q40 == 9385943);
    /* the same drive under LuGre, and under LuGre with a load, a slew limit, a hysteresis and a base
     * (q_check.c's effects): SS_Q_CHECK_X_SLIDER_LUGRE and SS_Q_CHECK_X_SLIDER_EFFECTS */
    ss_actuator_config_q_t lg = cfg;
    lg.friction_model = SS_FRICTION_Q_LUGRE;
    assert_int_equal(ss_waveform_init_q(&w, lg.dt_q40, &ws), SS_OK);
    assert_int_equal(ss_actuator_init_q(&lg, &st, ss_waveform_value_q(&w, &ws)), SS_OK);
    assert_int_equal(ss_actuator_run_q(&lg, &st, &w, &ws, 1000u, 250u, NULL, &rows), SS_OK);
    assert_true(st.x_slider_q40 == 9146832); /* 8.32 um (9146861 before the rod's compliance) */
    ss_actuator_config_q_t fx = lg;
    q_check_effects(&fx);
    assert_int_equal(ss_waveform_init_q(&w, fx.dt_q40, &ws), SS_OK);
    assert_int_equal(ss_actuator_init_q(&fx, &st, ss_waveform_value_q(&w, &ws)), SS_OK);
    assert_int_equal(ss_actuator_run_q(&fx, &st, &w, &ws, 1000u, 250u, NULL, &rows), SS_OK);
    assert_true(st.x_slider_q40 == 7279943); /* 6.62 um (7279828 before the rod's compliance) */
}

static void test_q_abi_sizes(void **unused)
{
    (void)unused;
    assert_int_equal(ss_abi_sizeof(SS_ABI_ACTUATOR_CONFIG_Q), sizeof(ss_actuator_config_q_t));
    assert_int_equal(ss_abi_sizeof(SS_ABI_ACTUATOR_STATE_Q), sizeof(ss_actuator_state_q_t));
    assert_int_equal(ss_abi_sizeof(SS_ABI_ACTUATOR_TRACE_Q), sizeof(ss_actuator_trace_q_t));
    assert_int_equal(ss_abi_sizeof(SS_ABI_ACTUATOR_SI), sizeof(ss_actuator_si_t));
    for (int32_t id = 0; id <= SS_ABI_ACTUATOR_SI; ++id) {
        assert_true(ss_abi_sizeof(id) > 0u);
    }
    print_message("sizeof q state: actuator %zu, LS %zu, LuGre %zu bytes (f32: %zu)\n",
                  sizeof(ss_actuator_state_q_t), sizeof(ss_ls_state_q_t), sizeof(ss_lugre_state_q_t),
                  sizeof(ss_actuator_state_f32_t));
    assert_true(sizeof(ss_actuator_state_q_t) <= sizeof(ss_actuator_state_f32_t));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table1_constants_match_converter),
        cmocka_unit_test(test_paper_drive_constants_match_converter),
        cmocka_unit_test(test_converter_names_bad_fields),
        cmocka_unit_test(test_q_presliding_loops_follow_float),
        cmocka_unit_test(test_q_initial_stiffness),
        cmocka_unit_test(test_q_steady_sliding_is_stribeck),
        cmocka_unit_test(test_q_wiping_out),
        cmocka_unit_test(test_q_ls_gate_kept),
        cmocka_unit_test(test_q_rate_independent_lugre_not),
        cmocka_unit_test(test_q_no_drift_ls_drift_lugre),
        cmocka_unit_test(test_q_memory_depth_bounded),
        cmocka_unit_test(test_q_rest_stays_at_rest),
        cmocka_unit_test(test_q_run_matches_manual_steps),
        cmocka_unit_test(test_q_waveform),
        cmocka_unit_test(test_q_sawtooth_without_division_is_exact),
        cmocka_unit_test(test_q_waveform_advance_by),
        cmocka_unit_test(test_q_waveform_corners),
        cmocka_unit_test(test_q_actuator_steps_match_float),
        cmocka_unit_test(test_q_effects_steps_match_float),
        cmocka_unit_test(test_q_sensor_scale),
        cmocka_unit_test(test_q_long_travel_is_exact),
        cmocka_unit_test(test_q_bit_exact_reference),
        cmocka_unit_test(test_q_abi_sizes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
