/* The piezo's drive through the effects of the _f32 family, inline (not public API): with no
 * effect of the drive on (the base model, most simulations) the strain is one product, and the
 * actuator's step pays no call for it. ss_effects_drive_f32 is this function, so every caller
 * gets the same bits. */
#ifndef SS_EFFECTS_INLINE_F32_H
#define SS_EFFECTS_INLINE_F32_H

#include "ss_effects.h"
#include "ss_inline.h"

/* The drive with a slew limit (and its bandwidth), creep or hysteresis on (ss_effects_f32.c). */
float ss_effects_drive_shaped_f32(const ss_effects_config_f32_t *cfg, ss_effects_state_f32_t *st,
                                  float gain_m_per_v, float command_v, float dt_s);

/* ss_effects_drive_f32 (ss_effects.h) */
SS_FORCE_INLINE float ss_effects_drive_inline_f32(const ss_effects_config_f32_t *cfg,
                                                  ss_effects_state_f32_t *st, float gain_m_per_v,
                                                  float command_v, float dt_s)
{
    /* a bandwidth needs a slew limit (ss_effects_config_check_f32): one test covers the amplifier */
    if (cfg->slew_v_per_s == 0.0f && cfg->creep_ratio == 0.0f && cfg->hysteresis_alpha == 0.0f) {
        st->amp_v = command_v; /* the base model's ideal strain, the same product */
        st->amp_cmd_v = command_v;
        st->strain_m = command_v * gain_m_per_v;
        return st->strain_m;
    }
    return ss_effects_drive_shaped_f32(cfg, st, gain_m_per_v, command_v, dt_s);
}

#endif /* SS_EFFECTS_INLINE_F32_H */
