/* The friction laws' shared pieces of the _f32 family, inline (not public API): the Stribeck curve
 * (once or twice a step in every law) and the asymmetry factor (once), where a call cost more than
 * the body's common path. ss_stribeck_f32, ss_stribeck_with_slope_f32 and ss_asymmetry_factor_f32
 * are these bodies, so every caller gets the same bits. */
#ifndef SS_FRICTION_INLINE_F32_H
#define SS_FRICTION_INLINE_F32_H

#include "ss_check.h"
#include "ss_exp_f32.h"
#include "ss_friction.h"
#include "ss_inline.h"

/* g(v) = Fc + (Fs - Fc) exp(-(v / vs)^2), N */
SS_FORCE_INLINE float ss_stribeck_inline_f32(const ss_friction_config_f32_t *cfg, float v_m_per_s)
{
    if (v_m_per_s == 0.0f) {
        return cfg->fc_n + (cfg->fs_n - cfg->fc_n); /* exp(0) = 1: the same sum, no exp (sticking) */
    }
    const float r = v_m_per_s / cfg->vs_m_per_s;
    return cfg->fc_n + (cfg->fs_n - cfg->fc_n) * ss_exp_neg_f32(r * r);
}

/* g(v) and dg/dv (N s/m) from one exponential */
SS_FORCE_INLINE float ss_stribeck_with_slope_inline_f32(const ss_friction_config_f32_t *cfg, float v_m_per_s,
                                                        float *slope_ns_per_m)
{
    if (v_m_per_s == 0.0f) {
        *slope_ns_per_m = 0.0f;
        return cfg->fc_n + (cfg->fs_n - cfg->fc_n);
    }
    const float r = v_m_per_s / cfg->vs_m_per_s;
    const float e = ss_exp_neg_f32(r * r);
    *slope_ns_per_m = -2.0f * (cfg->fs_n - cfg->fc_n) * r / cfg->vs_m_per_s * e;
    return cfg->fc_n + (cfg->fs_n - cfg->fc_n) * e;
}

/* 1 + asymmetry sgn(load); 1 exactly for a symmetric contact */
SS_FORCE_INLINE float ss_asymmetry_inline_f32(const ss_friction_config_f32_t *cfg, float load)
{
    return (cfg->asymmetry == 0.0f) ? 1.0f : 1.0f + cfg->asymmetry * ss_sign_f32(load);
}

#endif /* SS_FRICTION_INLINE_F32_H */
