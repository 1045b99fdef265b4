/* Stick steps' flow (ss_actuator.h, ss_actuator_coarse_stick_f32): the stuck contact's linear
 * system and its exact flow over a stick step, made once. */
#include <math.h>
#include <stddef.h>

#include "ss_actuator.h"

/* Scaled so that ||A h / 2^s||_1 <= 1/2: the Taylor series to x^9 then errs by less than
 * (1/2)^10 / 10! = 3e-10, below float's rounding. */
#define STICK_TAYLOR_TERMS 9

static void mat4_mul(const float a[16], const float b[16], float out[16])
{
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
            float acc = 0.0f;
            for (int k = 0; k < 4; ++k) {
                acc += a[4 * i + k] * b[4 * k + j];
            }
            out[4 * i + j] = acc;
        }
    }
}

/* exp(a) by scaling and squaring. a is dimensionless (the flow's time is 1): its norm is at most a
 * few thousand for the configs' range of stick steps, so at most a dozen squarings. */
static void mat4_exp(const float a[16], float out[16])
{
    float norm = 0.0f;
    for (int j = 0; j < 4; ++j) {
        float col = 0.0f;
        for (int i = 0; i < 4; ++i) {
            col += fabsf(a[4 * i + j]);
        }
        norm = fmaxf(norm, col);
    }
    int squarings = 0;
    float scale = 1.0f;
    while (norm * scale > 0.5f && squarings < 60) {
        scale *= 0.5f;
        ++squarings;
    }
    float m[16];
    float term[16];
    float sum[16];
    for (int i = 0; i < 16; ++i) {
        m[i] = a[i] * scale;
        term[i] = (i % 5 == 0) ? 1.0f : 0.0f; /* the identity */
        sum[i] = term[i];
    }
    for (int k = 1; k <= STICK_TAYLOR_TERMS; ++k) {
        float next[16];
        mat4_mul(term, m, next);
        for (int i = 0; i < 16; ++i) {
            term[i] = next[i] / (float)k;
            sum[i] += term[i];
        }
    }
    for (int q = 0; q < squarings; ++q) {
        float sq[16];
        mat4_mul(sum, sum, sq);
        for (int i = 0; i < 16; ++i) {
            sum[i] = sq[i];
        }
    }
    for (int i = 0; i < 16; ++i) {
        out[i] = sum[i];
    }
}

/* The effect that the linear flow does not hold, or NULL: the load is a constant force and the
 * sensor's scale acts on the record only; everything else shapes the strain, the friction's level
 * or the contact's force over the step. */
static const char *stick_refused_effect(const ss_actuator_config_f32_t *cfg)
{
    const ss_effects_config_f32_t *e = &cfg->effects;
    if (e->hysteresis_alpha != 0.0f) {
        return "effects.hysteresis_alpha";
    }
    if (e->creep_ratio != 0.0f) {
        return "effects.creep_ratio";
    }
    if (e->friction_gradient_per_m != 0.0f) {
        return "effects.friction_gradient_per_m";
    }
    if (e->slew_v_per_s != 0.0f) {
        return "effects.slew_v_per_s";
    }
    if (e->thermal_coeff_per_j != 0.0f) {
        return "effects.thermal_coeff_per_j";
    }
    if (e->base_mass_kg != 0.0f) {
        return "effects.base_mass_kg";
    }
    if (cfg->friction.asymmetry != 0.0f) {
        return "friction.asymmetry";
    }
    return NULL;
}

ss_status_t ss_actuator_coarse_stick_f32(const ss_actuator_config_f32_t *cfg, uint32_t stick_n,
                                         ss_actuator_coarse_f32_t *co, const char **bad_field)
{
    const char *dummy = "";
    const char **bad = (bad_field != NULL) ? bad_field : &dummy;
    if (co == NULL) {
        *bad = "coarse";
        return SS_ERR_NULL;
    }
    const ss_status_t status = ss_actuator_config_check_f32(cfg, bad);
    if (status != SS_OK) {
        return status;
    }
    if (stick_n == 0u) {
        co->stick_n = 0u;
        co->stick_dt_s = 0.0f;
        co->stick_omega_per_s = 0.0f;
        return SS_OK;
    }
    if (cfg->friction_model != SS_FRICTION_LUGRE) {
        *bad = "friction_model";
        return SS_ERR_RANGE;
    }
    const float h = (float)stick_n * cfg->dt_s;
    if (stick_n < 2u || stick_n > 256u || !(h <= 1e-3f)) {
        *bad = "coarse_stick_n";
        return SS_ERR_RANGE;
    }
    const char *effect = stick_refused_effect(cfg);
    if (effect != NULL) {
        *bad = effect;
        return SS_ERR_RANGE;
    }
    /* u = (e, v_rod / w, z, v_slider / w) about the ramp's steady state, w = sqrt(k / M_R) the
     * rod's rate, in the step's own time t / h (a velocity over w is a length, and the rod's two
     * terms alike, -(w h) e and (w h) v / w: a balanced matrix, fewer squarings; against scipy's
     * expm on Table I within 2.8e-6 of the largest entry at 40 us, where velocities times h gave
     * five times that, tests/python/test_model_api.py):
     *   e' = wh v_r,  v_r' = -wh e - (c h / M_R) v_r - (s0 h / (M_R w)) z - (s h / M_R) (v_r - v_s),
     *   z' = wh (v_r - v_s),  v_s' = (s0 h / (M_C w)) z + (s h / M_C) (v_r - v_s),
     * with s0 = sigma0 and s = sigma1 + sigma2 (the bristle's damping and the viscous term, both on
     * the relative velocity while dz/dt = v) */
    const float mr = cfg->rod_mass_kg;
    const float mc = cfg->slider_mass_kg;
    const float s0 = cfg->friction.sigma0_n_per_m;
    const float s = cfg->friction.sigma1_ns_per_m + cfg->friction.sigma2_ns_per_m;
    const float w = sqrtf(cfg->piezo_stiffness_n_per_m / mr);
    const float wh = w * h;
    /* clang-format off */
    const float a[16] = {
        0.0f, wh, 0.0f, 0.0f,
        -wh, -(cfg->piezo_damping_kg_per_s + s) * h / mr, -s0 * h / (mr * w), s * h / mr,
        0.0f, wh, 0.0f, -wh,
        0.0f, s * h / mc, s0 * h / (mc * w), -s * h / mc,
    };
    /* clang-format on */
    float phi[16];
    mat4_exp(a, phi);
    for (int i = 0; i < 16; ++i) {
        if (!isfinite(phi[i])) {
            *bad = "coarse_stick_n";
            return SS_ERR_RANGE;
        }
    }
    for (int i = 0; i < 16; ++i) {
        co->stick_phi[i] = phi[i];
    }
    co->stick_omega_per_s = w;
    co->stick_n = stick_n;
    co->stick_dt_s = h;
    return SS_OK;
}
