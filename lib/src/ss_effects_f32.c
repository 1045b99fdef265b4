#include "ss_effects.h"

#include <math.h>
#include <stddef.h>

#include "ss_check.h"
#include "ss_effects_inline_f32.h"
#include "ss_exp_f32.h"

/* Friction never scales below this share of its nominal value: a scaled Fs stays positive. */
#define SS_EFFECTS_MIN_FRICTION_SCALE 0.1f

ss_effects_config_f32_t ss_effects_config_none_f32(void)
{
    ss_effects_config_f32_t c;
    c.hysteresis_alpha = 0.0f;
    c.hysteresis_width_m = 0.0f;
    c.creep_ratio = 0.0f;
    c.creep_tau_s = 0.0f;
    c.load_n = 0.0f;
    c.friction_gradient_per_m = 0.0f;
    c.slew_v_per_s = 0.0f;
    c.amp_bandwidth_hz = 0.0f;
    c.thermal_coeff_per_j = 0.0f;
    c.thermal_tau_s = 0.0f;
    c.base_mass_kg = 0.0f;
    c.base_freq_hz = 0.0f;
    c.base_damping_ratio = 0.0f;
    c.sensor_scale_error = 0.0f;
    return c;
}

ss_status_t ss_effects_config_check_f32(const ss_effects_config_f32_t *c, const char **bad_field)
{
    *bad_field = "";
    if (c == NULL) {
        *bad_field = "effects";
        return SS_ERR_NULL;
    }
    /* The companion of a switched-off effect is not used and may be anything finite (0 included). */
    const float big = 3.0e38f;
    const int hyst = c->hysteresis_alpha != 0.0f;
    const int creep = c->creep_ratio != 0.0f;
    const int slew = c->slew_v_per_s != 0.0f;
    const int bw = c->amp_bandwidth_hz != 0.0f;
    const int thermal = c->thermal_coeff_per_j != 0.0f;
    const int base = c->base_mass_kg != 0.0f;
    const ss_range_f32_t ranges[] = {
        {"effects.hysteresis_alpha", c->hysteresis_alpha, 0.0f, 0.9f},
        {"effects.hysteresis_width_m", c->hysteresis_width_m, hyst ? 1e-12f : -big, hyst ? 1e-3f : big},
        {"effects.creep_ratio", c->creep_ratio, 0.0f, 1.0f},
        {"effects.creep_tau_s", c->creep_tau_s, creep ? 1e-5f : -big, creep ? 1e4f : big},
        {"effects.load_n", c->load_n, -1e3f, 1e3f},
        {"effects.friction_gradient_per_m", c->friction_gradient_per_m, -1e5f, 1e5f},
        {"effects.slew_v_per_s", c->slew_v_per_s, slew ? 1e2f : 0.0f, slew ? 1e12f : 0.0f},
        /* a bandwidth belongs to the amplifier's slew limit: on only beside one (an unlimited
         * amplifier with a bandwidth is a slew of 1e12 V/s) */
        {"effects.amp_bandwidth_hz", c->amp_bandwidth_hz, bw ? 1e3f : 0.0f,
         bw ? (slew ? 1e10f : 0.0f) : 0.0f},
        {"effects.thermal_coeff_per_j", c->thermal_coeff_per_j, -1e6f, 1e6f},
        {"effects.thermal_tau_s", c->thermal_tau_s, thermal ? 1e-4f : -big, thermal ? 1e6f : big},
        {"effects.base_mass_kg", c->base_mass_kg, base ? 1e-4f : 0.0f, base ? 1e3f : 0.0f},
        {"effects.base_freq_hz", c->base_freq_hz, base ? 10.0f : -big, base ? 1e5f : big},
        {"effects.base_damping_ratio", c->base_damping_ratio, base ? 0.0f : -big, base ? 2.0f : big},
        {"effects.sensor_scale_error", c->sensor_scale_error, -0.5f, 0.5f},
    };
    return ss_check_ranges_f32(ranges, sizeof ranges / sizeof ranges[0], bad_field);
}

void ss_effects_init_f32(const ss_effects_config_f32_t *cfg, ss_effects_state_f32_t *st, float gain_m_per_v,
                         float v0_v)
{
    st->amp_v = v0_v;
    st->amp_cmd_v = v0_v;
    st->creep_v = v0_v;
    st->strain_m = gain_m_per_v * (v0_v + cfg->creep_ratio * v0_v);
    st->hysteresis_m = 0.0f;
    st->heat_j = 0.0f;
    st->x_base_m = 0.0f;
    st->v_base_m_per_s = 0.0f;
}

float ss_effects_drive_f32(const ss_effects_config_f32_t *cfg, ss_effects_state_f32_t *st, float gain_m_per_v,
                           float command_v, float dt_s)
{
    return ss_effects_drive_inline_f32(cfg, st, gain_m_per_v, command_v, dt_s);
}

/* The amplifier's output at the end of a piece of dt_s along which the command runs straight from
 * the last one (st->amp_cmd_v) to command_v: the exact solution of
 * dV/dt = clamp((V_cmd - V) / tau, -slew, +slew) (docs/effects.md). In the lag e = V_cmd - V, with
 * r the command's rate: outside the band |e| <= slew tau the voltage runs at the slew rate s and e
 * changes at r - s; inside it e relaxes to r tau as exp(-t / tau). A piece enters the band at most
 * once and leaves it at most once (where r tau lies outside it, a ramp steeper than the slew). */
static float amplifier_with_bandwidth(const ss_effects_config_f32_t *cfg, const ss_effects_state_f32_t *st,
                                      float command_v, float dt_s)
{
    const float tau = 1.0f / (6.28318531f * cfg->amp_bandwidth_hz);
    const float slew = cfg->slew_v_per_s; /* > 0: the config's check */
    const float band = slew * tau;        /* the lag past which the slew limit holds */
    if (!(dt_s > 0.0f)) {
        return st->amp_v;
    }
    const float r = (command_v - st->amp_cmd_v) / dt_s;
    const float target = r * tau; /* the lag a ramp of rate r settles to inside the band */
    float e = st->amp_cmd_v - st->amp_v;
    float left = dt_s;
    if (e > band || e < -band) {
        const float s = (e > 0.0f) ? slew : -slew;
        const float edge = (e > 0.0f) ? band : -band;
        const float t_in = (edge - e) / (r - s); /* > 0: moving in */
        if (!(t_in > 0.0f) || t_in >= left) {
            return command_v - (e + (r - s) * left);
        }
        e = edge;
        left -= t_in;
    }
    if (target > band || target < -band) {
        const float s = (target > 0.0f) ? slew : -slew;
        const float edge = (target > 0.0f) ? band : -band;
        /* ln((e - target) / (edge - target)), with its digits where the two are close */
        const float t_out = tau * log1pf((e - edge) / (edge - target));
        if (t_out < left) {
            return command_v - (edge + (r - s) * (left - t_out));
        }
    }
    /* target + (e - target) exp(-x) without the difference of the two: a short piece of a steep
     * ramp has a target far above the lag it ends with */
    float decay;
    const float grown = -ss_expm1_neg_f32(left / tau, &decay); /* 1 - exp(-x), to its last digits */
    return command_v - (e * decay + target * grown);
}

float ss_effects_drive_shaped_f32(const ss_effects_config_f32_t *cfg, ss_effects_state_f32_t *st,
                                  float gain_m_per_v, float command_v, float dt_s)
{
    /* amplifier: a slew-rate limit on the output voltage, and its bandwidth */
    float amp = command_v;
    if (cfg->amp_bandwidth_hz > 0.0f) {
        amp = amplifier_with_bandwidth(cfg, st, command_v, dt_s);
    } else if (cfg->slew_v_per_s > 0.0f) {
        const float max_dv = cfg->slew_v_per_s * dt_s;
        const float dv = command_v - st->amp_v;
        amp = st->amp_v + ((dv > max_dv) ? max_dv : ((dv < -max_dv) ? -max_dv : dv));
    }
    st->amp_v = amp;
    st->amp_cmd_v = command_v;
    /* creep: w follows the voltage with time constant tau (exact for a voltage held over dt) */
    float u = amp;
    if (cfg->creep_ratio > 0.0f) {
        /* -expm1: the share relaxed in one step (~dt / tau, 1e-5 and below) keeps its digits,
         * where 1 - exp would round it to a few float steps and lose tau's gradient */
        float e;
        st->creep_v += (amp - st->creep_v) * -ss_expm1_neg_f32(dt_s / cfg->creep_tau_s, &e);
        u += cfg->creep_ratio * st->creep_v;
    }
    u *= gain_m_per_v;
    /* Bouc-Wen, rate independent: over a monotone du, h relaxes to sgn(du) alpha width over the
     * strain distance width (exact solution of dh/du = alpha - sgn(du) h / width) */
    if (cfg->hysteresis_alpha > 0.0f) {
        const float du = u - st->strain_m;
        const float h_inf = ss_sign_f32(du) * cfg->hysteresis_alpha * cfg->hysteresis_width_m;
        st->hysteresis_m =
            h_inf + (st->hysteresis_m - h_inf) * ss_exp_neg_f32(fabsf(du) / cfg->hysteresis_width_m);
    }
    st->strain_m = u;
    return u - st->hysteresis_m;
}

float ss_effects_friction_scale_f32(const ss_effects_config_f32_t *cfg, const ss_effects_state_f32_t *st,
                                    float x_slider_m)
{
    const float s =
        (1.0f + cfg->friction_gradient_per_m * x_slider_m) * (1.0f - cfg->thermal_coeff_per_j * st->heat_j);
    return (s > SS_EFFECTS_MIN_FRICTION_SCALE) ? s : SS_EFFECTS_MIN_FRICTION_SCALE;
}

void ss_effects_heat_f32(const ss_effects_config_f32_t *cfg, ss_effects_state_f32_t *st, float energy_j,
                         float dt_s)
{
    if (cfg->thermal_coeff_per_j == 0.0f) {
        return;
    }
    float e;
    const float loss = st->heat_j * -ss_expm1_neg_f32(dt_s / cfg->thermal_tau_s, &e); /* as in creep */
    const float q = st->heat_j + energy_j - loss;
    st->heat_j = (q > 0.0f) ? q : 0.0f; /* elastic energy given back from a cold contact */
}

float ss_effects_sensor_f32(const ss_effects_config_f32_t *cfg, float x_slider_m)
{
    return (1.0f + cfg->sensor_scale_error) * x_slider_m;
}
