/* The node's model adapter for the fixed-point family (ss_node_model.h, SS_NODE_MODEL_Q). The q
 * node may use float at its edges (protocol fields are float32, a config goes through the host
 * converter ss_convert_q): the no-float check applies to the q library and the q-only images, not
 * to this application. Every conversion below gives the same bits on every target. */
#include "ss_node_model.h"

#include <math.h>
#include <string.h>

#include "ss_convert_q.h" /* float32 and SI at the node's edges */

/* float32 volts to Q16.16: floor(v 2^16 + 1/2) in double, saturated (ss_volts_to_q16, the
 * converter's rule for amplitude and offset). v 2^16 and the + 1/2 are exact in double for every
 * float32 v, and floor is exact, so the host and a soft-float target agree. */
ss_node_drive_t ss_node_model_drive_from_v(float v)
{
    return ss_volts_to_q16((double)v);
}

float ss_node_model_dt_s(const ss_node_config_t *cfg)
{
    return (float)cfg->dt_q40 * 0x1p-40f;
}

/* dt_q40 x 10^15 / 2^40 = dt_q40 x 5^15 / 2^25, rounded; split so that no product overflows. */
uint64_t ss_node_model_dt_fs(const ss_node_config_t *cfg)
{
    const uint64_t five15 = 30517578125u; /* 5^15 */
    const uint64_t dt = (uint64_t)cfg->dt_q40;
    return (dt >> 25) * five15 + (((dt & 0x1FFFFFFu) * five15 + 0x1000000u) >> 25);
}

ss_node_config_t ss_node_model_default_config(void)
{
    return ss_actuator_config_table1_q(); /* integer constants: the same on every target */
}

/* The converter refuses an effect the q family does not model by its field name; say why (it
 * models the load, the slew limit and the sensor scale: ss_effects_q.h). */
#define SS_NO_Q(field)                                                                                       \
    {                                                                                                        \
        field, field ": the fixed-point node does not model this effect"                                     \
    }
static const char *no_effects_reason(const char *field)
{
    static const char *const table[][2] = {

        SS_NO_Q("effects.creep_ratio"),
        SS_NO_Q("effects.friction_gradient_per_m"),
        SS_NO_Q("effects.thermal_coeff_per_j"),
        SS_NO_Q("effects.amp_bandwidth_hz"),

    };
    for (size_t i = 0; i < sizeof table / sizeof table[0]; ++i) {
        if (strcmp(field, table[i][0]) == 0) {
            return table[i][1];
        }
    }
    return field;
}
#undef SS_NO_Q

/* Through the host converter (double and libm), so a target matches the host to the bit only where
 * both round the same (docs/fixed-point.md). */
ss_status_t ss_node_model_config(const ss_actuator_config_f32_t *f, ss_node_config_t *out, const char **why)
{
    ss_status_t st = ss_actuator_config_check_f32(f, why); /* out of range: the float family's words */
    if (st == SS_OK) {
        st = ss_actuator_config_to_q(f, out, why);
        if (st != SS_OK) {
            *why = no_effects_reason(*why);
        }
    }
    return st;
}

void ss_node_model_init(const ss_node_config_t *cfg, ss_node_state_t *st, ss_node_drive_t d)
{
    (void)ss_actuator_init_q(cfg, st, d);
}

/* x 2^40 and the + 1/2 are exact in double for the node's |x| <= 1 m, and floor is exact: the
 * same integer on every target. */
void ss_node_model_place_slider(ss_node_state_t *st, float x_m)
{
    ss_actuator_place_slider_q(st, (int64_t)floor((double)x_m * 1099511627776.0 + 0.5));
}

void ss_node_model_step(const ss_node_config_t *cfg, ss_node_state_t *st, ss_node_drive_t d)
{
    (void)ss_actuator_step_q(cfg, st, d);
}

/* Integer to float32 (round to nearest, ties to even: one rounding), then times a power of two
 * (exact): the same bits on the host's SSE and a target's soft float. The slider is split into
 * hi = float32(x) and lo = float32(x - hi), both times 2^-40, so hi + lo in double is x exactly
 * while |x| < 2^48 (256 m). */
ss_node_row_t ss_node_model_row(const ss_node_state_t *st)
{
    const float hi = (float)st->x_slider_q40;
    int64_t rest = 0;
    const float two62 = 4611686018427387904.0f; /* 2^62 */
    if (hi > -two62 && hi < two62) {            /* always, in practice; keeps the cast defined */
        rest = st->x_slider_q40 - (int64_t)hi;
    }
    const ss_node_row_t r = {st->steps,     (float)st->drive_q16 * 0x1p-16f, (float)st->x_rod_q40 * 0x1p-40f,
                             hi * 0x1p-40f, (float)rest * 0x1p-40f,          (float)st->force_q24 * 0x1p-24f};
    return r;
}

ss_status_t ss_node_model_wave_convert(const ss_waveform_config_f32_t *w, ss_node_wave_t *out,
                                       const char **why)
{
    return ss_waveform_config_to_q(w, out, why);
}

ss_status_t ss_node_model_wave_init(const ss_node_config_t *cfg, const ss_node_wave_t *w,
                                    ss_node_wave_state_t *ws)
{
    return ss_waveform_init_q(w, cfg->dt_q40, ws);
}

ss_node_drive_t ss_node_model_wave_value(const ss_node_wave_t *w, const ss_node_wave_state_t *ws)
{
    return ss_waveform_value_q(w, ws);
}

void ss_node_model_wave_step(const ss_node_config_t *cfg, ss_node_state_t *st, const ss_node_wave_t *w,
                             ss_node_wave_state_t *ws)
{
    (void)ss_actuator_wave_step_q(cfg, st, w, ws);
}
