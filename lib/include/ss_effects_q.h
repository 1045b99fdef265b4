/* The effects of the cause catalog (ss_effects.h) that the fixed-point family models, in integer
 * form: zero is off, so a zeroed struct is the base model. The host converter
 * (ss_actuator_config_to_q) fills them from the float config and refuses, by field name, any
 * effect not listed here. Formats and error bounds: docs/fixed-point.md. */
#ifndef SS_EFFECTS_Q_H
#define SS_EFFECTS_Q_H

#include <stdint.h>

/* Largest |load| (N at 2^-24) the q family takes: the friction's own headroom (SS_Q_FS_MAX_Q24). */
#define SS_Q_LOAD_MAX_Q24 ((int32_t)32 << 24)
/* Largest hysteresis alpha, Q2.30: ceil(0.9 x 2^30), the float range's 0.9. */
#define SS_Q_HYSTERESIS_ALPHA_MAX_Q30 966367642
/* Narrowest hysteresis width, m at 2^-40 (0.93 nm): keeps |du| / width in 64 bits (docs/fixed-point.md). */
#define SS_Q_HYSTERESIS_WIDTH_MIN_Q40 1024

/* Largest slew per step (V at 2^-24): 127 V; a slower amplifier than that is refused by name. */
#define SS_Q_SLEW_MAX_Q24 ((int32_t)127 << 24)

typedef struct {
    int32_t load_q24;         /* external_load: constant force on the slider, N at 2^-24, |.| <= 32 N */
    int32_t slew_q24;         /* amplifier_slew_limit: largest change of the piezo voltage in one step,
                                 V at 2^-24 (slew rate x dt): 0 = off, else (0, 127 V] */
    int32_t sensor_scale_q30; /* sensor_scale_error e, Q2.30 in [-0.5, 0.5]: the sensor reports (1 + e) x */
    /* piezo_hysteresis (Bouc-Wen on the ideal strain, ss_effects.h): alpha in Q2.30, [0, 0.9], 0 = off;
     * width in m at 2^-40, [1024 (0.93 nm), 2^31) when alpha > 0; inv_width = round(2^48 / width),
     * from the host converter (the step divides by nothing) */
    int32_t hysteresis_alpha_q30;
    int32_t hysteresis_width_q40;
    int32_t pad; /* zero: no implicit padding, so configs compare byte for byte on every target */
    int64_t hysteresis_inv_width_q48;
    /* base_compliance: the piezo pushes against a base mass on a spring-damper to ground. 0 = off, else
     * base_kick = dt / (2 m_b), (m/s)/N at 2^-40, in (0, 2^31); k_b whole N/m; c_b N s/m in Q16.16; and the
     * piezo's own k (whole N/m) and c (Q16.16), which the base feels (the rod's flow takes them as lag_q24)
     */
    int32_t base_kick_q40;
    int32_t base_stiffness_n_per_m;
    int32_t base_damping_q16;
    int32_t piezo_stiffness_n_per_m;
    int32_t piezo_damping_q16;
    int32_t pad2; /* zero */
} ss_effects_config_q_t;

/* All off (pads zero): the base model. */
static inline ss_effects_config_q_t ss_effects_config_none_q(void)
{
    const ss_effects_config_q_t none = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    return none;
}

#endif /* SS_EFFECTS_Q_H */
