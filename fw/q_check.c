/* The q-only image: calls every entry point of the fixed-point family, so that the build's symbol
 * check (cmake/check_no_float.cmake) sees everything the q family can link. Under QEMU it also
 * plays two cycles of the paper's drive and exits (semihosting) with 0 only if the slider lands on
 * the very bits the host computes (tests/c/test_fixed_model.c, test_q_bit_exact_reference). */
#include <stddef.h>
#include <stdint.h>

#include "ss_actuator_q.h"
#include "ss_fixed.h"

/* Slider position after two cycles at 2000 Hz, 100 V, rise 0.95, Table I q config (m at 2^-40);
 * the same under LuGre, and under LuGre with the effects below (test_q_bit_exact_reference). */
#define SS_Q_CHECK_X_SLIDER 9385943LL
#define SS_Q_CHECK_X_SLIDER_LUGRE 9146832LL
#define SS_Q_CHECK_X_SLIDER_EFFECTS 7279943LL

/* The slider's position after the two cycles of `w` from rest under cfg; -1 if a call fails. */
static int64_t two_cycles(const ss_actuator_config_q_t *cfg, const ss_waveform_config_q_t *w)
{
    ss_waveform_state_q_t ws;
    static ss_actuator_state_q_t st;
    uint32_t rows = 0;
    if (ss_waveform_init_q(w, cfg->dt_q40, &ws) != SS_OK ||
        ss_actuator_init_q(cfg, &st, ss_waveform_value_q(w, &ws)) != SS_OK ||
        ss_actuator_run_q(cfg, &st, w, &ws, 1000u, 250u, NULL, &rows) != SS_OK) {
        return -1;
    }
    return st.x_slider_q40;
}

void SysTick_Handler(void);
void SysTick_Handler(void)
{
}

static void semihost_exit(int code)
{
    volatile uint32_t block[2] = {0x20026u, (uint32_t)code}; /* ADP_Stopped_ApplicationExit */
    register uint32_t r0 __asm("r0") = 0x20u;                /* SYS_EXIT_EXTENDED */
    register volatile uint32_t *r1 __asm("r1") = block;
    __asm volatile("bkpt 0xab" : : "r"(r0), "r"(r1) : "memory");
}

static volatile int32_t sink; /* keeps every result alive */

int main(void)
{
    const ss_actuator_config_q_t cfg = ss_actuator_config_table1_q();
    const char *bad = "";
    int ok = (ss_actuator_config_check_q(&cfg, &bad) == SS_OK);
    ok = ok && (ss_friction_config_check_q(&cfg.friction, &bad) == SS_OK);
    ok = ok && (ss_friction_config_check_named_q(&cfg.friction, 1, &bad) == SS_OK);
    sink = ss_stribeck_q(&cfg.friction, 1000) + ss_stribeck_slope_q(&cfg.friction, 1000);
    sink =
        ss_sat32((int64_t)sink * 3) + ss_exp_neg_q16_q30(sink & 0xFFFF) + ss_exp_neg_q32_q30((uint32_t)sink);
    sink = (int32_t)ss_status_str(SS_ERR_RANGE)[0];

    ss_friction_config_q_t fr = ss_friction_config_table1_q();
    ss_ls_state_q_t ls;
    ss_lugre_state_q_t lg;
    int32_t dx[4] = {1000, 2000, -500, 100};
    int32_t f[4];
    ok = ok && ss_ls_init_q(&fr, &ls) == SS_OK && ss_lugre_init_q(&fr, &lg) == SS_OK;
    ok = ok && ss_ls_run_q(&fr, &ls, dx, 4u, cfg.dt_q40, f) == SS_OK;
    ok = ok && ss_lugre_run_q(&fr, &lg, dx, 4u, cfg.dt_q40, f) == SS_OK;
    ss_ls_advance_q(&fr, &ls, 10, cfg.inv_dt_q47);
    ss_lugre_advance_q(&fr, &lg, 10, cfg.inv_dt_q47);
    sink = ss_ls_step_q(&fr, &ls, 5, cfg.dt_q40) + ss_lugre_step_q(&fr, &lg, 5, cfg.dt_q40) +
           ss_ls_force_at_q(&fr, &ls, 7, NULL) + ss_lugre_force_at_q(&fr, &lg, 7, NULL);

    /* two cycles at 2000 Hz, 100 V, rise 0.95 (0.95 x 2^32 = 4080218931) */
    const ss_waveform_config_q_t w = ss_waveform_sawtooth_q(2000000u, 100 << 16, 0, 4080218931u, 1, 2u);
    ss_waveform_state_q_t ws;
    static ss_actuator_state_q_t st;
    int32_t drive[2];
    ok = ok && ss_waveform_init_q(&w, cfg.dt_q40, &ws) == SS_OK;
    ok = ok && ss_actuator_init_q(&cfg, &st, ss_waveform_value_q(&w, &ws)) == SS_OK;
    /* written through the trace's pointers */
    /* cppcheck-suppress unassignedVariable */
    static uint32_t step[4];
    /* cppcheck-suppress unassignedVariable */
    static int64_t xs[4];
    ss_actuator_trace_q_t tr = {step, NULL, NULL, NULL, xs, NULL, NULL, NULL, NULL, NULL, NULL, 4u};
    uint32_t rows = 0;
    ok = ok && ss_actuator_run_q(&cfg, &st, &w, &ws, 1000u, 250u, &tr, &rows) == SS_OK && rows == 4u;
    ok = ok && st.x_slider_q40 == SS_Q_CHECK_X_SLIDER && xs[3] == st.x_slider_q40 && step[3] == 1000u;
    ss_actuator_record_q(&cfg, &st, &tr, 0u);
    ok = ok && ss_waveform_fill_q(&w, &ws, drive, 2u) == SS_OK;
    ss_waveform_advance_q(&ws);
    ok = ok && ss_actuator_step_q(&cfg, &st, ss_sawtooth_at_phase_q(&w, 12345u)) == SS_OK;
    /* the effects: 0.25 N of load, 1 V a step of slew, a sensor reading 1/32 long */
    ss_actuator_config_q_t fx = cfg;
    fx.effects.load_q24 = 1 << 22;
    fx.effects.slew_q24 = 1 << 24;
    fx.effects.sensor_scale_q30 = 1 << 25;
    fx.effects.hysteresis_alpha_q30 = 1 << 28; /* 0.25 over 2^20 x 2^-40 m (0.95 um) */
    fx.effects.hysteresis_width_q40 = 1 << 20;
    fx.effects.hysteresis_inv_width_q48 = (int64_t)1 << 28;
    fx.effects.base_kick_q40 = 27487791; /* 20 g at 1 us */
    fx.effects.base_stiffness_n_per_m = 12633094;
    fx.effects.base_damping_q16 = 3292990;
    fx.effects.piezo_stiffness_n_per_m = 208000000;
    fx.effects.piezo_damping_q16 = 406323;
    static ss_actuator_state_q_t sf;
    ok = ok && ss_actuator_init_q(&fx, &sf, 0) == SS_OK;
    ss_actuator_place_slider_q(&sf, 1000);
    ok = ok && ss_actuator_step_q(&fx, &sf, 100 << 16) == SS_OK && sf.amp_q24 == ((int64_t)1 << 24);
    /* 1 V of 44 nm/V rises the hysteresis toward alpha width = 2^18, and the strain is u - h */
    ok = ok && sf.hysteresis_q40 > 0 && sf.hysteresis_q40 < (1 << 18) &&
         sf.x_p_q40 == sf.strain_q40 - sf.hysteresis_q40;
    /* the piezo's extension pushed the base back (the rod forward) */
    ok = ok && sf.v_base_q28 < 0;
    ok = ok && ss_actuator_sensor_q(&fx, (int64_t)1 << 40) == ((int64_t)1 << 40) + ((int64_t)1 << 35);
    /* a contact a quarter stronger under a positive load, as strong unloaded */
    fr.asymmetry_q30 = 1 << 28;
    ok = ok && ss_asymmetric_q(&fr, 4 << 24, 1) == 5 << 24 && ss_asymmetric_q(&fr, 4 << 24, 0) == 4 << 24;
    /* LuGre, then LuGre with the effects (the sensor's scale aside): the host's bits */
    ss_actuator_config_q_t lugre = cfg;
    lugre.friction_model = SS_FRICTION_Q_LUGRE;
    ok = ok && two_cycles(&lugre, &w) == SS_Q_CHECK_X_SLIDER_LUGRE;
    ss_actuator_config_q_t lfx = fx;
    lfx.friction_model = SS_FRICTION_Q_LUGRE;
    lfx.effects.sensor_scale_q30 = 0;
    ok = ok && two_cycles(&lfx, &w) == SS_Q_CHECK_X_SLIDER_EFFECTS;
    semihost_exit(ok ? 0 : 1);
    return 0;
}
