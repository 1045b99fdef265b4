/* Stick steps' flow (ss_actuator.h, ss_actuator_coarse_stick_f32): the stuck contact's linear
 * system and its exact flow over a stick step, made once. */
#include <math.h>
#include <stddef.h>

#include "ss_actuator.h"

/* Scaled so that ||A h / 2^s||_1 <= 1/2: the Taylor series to x^12 then errs by less than
 * (1/2)^13 / 13! = 2e-14, below double's rounding. */
#define STICK_TAYLOR_TERMS 12

static void mat4_mul(const double a[16], const double b[16], double out[16])
{
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
            double acc = 0.0;
            for (int k = 0; k < 4; ++k) {
                acc += a[4 * i + k] * b[4 * k + j];
            }
            out[4 * i + j] = acc;
        }
    }
}

/* exp(a) by scaling and squaring, in double: it is made once, and over the configs' range the norm
 * of a reaches 1e12 (a light, stiff, damped rod: 41 squarings), where float's rounding grew to 1e-3
 * of the largest entry and put the flow's eigenvalues past 1 (tests/python/test_model_api.py). */
static void mat4_exp(const double a[16], double out[16])
{
    double norm = 0.0;
    for (int j = 0; j < 4; ++j) {
        double col = 0.0;
        for (int i = 0; i < 4; ++i) {
            col += fabs(a[4 * i + j]);
        }
        norm = fmax(norm, col);
    }
    int squarings = 0;
    double scale = 1.0;
    while (norm * scale > 0.5 && squarings < 80) {
        scale *= 0.5;
        ++squarings;
    }
    double m[16];
    double term[16];
    double sum[16];
    for (int i = 0; i < 16; ++i) {
        m[i] = a[i] * scale;
        term[i] = (i % 5 == 0) ? 1.0 : 0.0; /* the identity */
        sum[i] = term[i];
    }
    for (int k = 1; k <= STICK_TAYLOR_TERMS; ++k) {
        double next[16];
        mat4_mul(term, m, next);
        for (int i = 0; i < 16; ++i) {
            term[i] = next[i] / (double)k;
            sum[i] += term[i];
        }
    }
    for (int q = 0; q < squarings; ++q) {
        double sq[16];
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
        co->edge_parts = 0u;
        return SS_OK;
    }
    if (cfg->friction_model != SS_FRICTION_LUGRE) {
        *bad = "friction_model";
        return SS_ERR_RANGE;
    }
    const float h = (float)stick_n * cfg->dt_s;
    /* longer than a coarse step (a stick step is taken where a whole one may be: a shorter one
     * would take more steps than the coarse ones, not fewer) */
    if (stick_n <= co->n || stick_n > 256u || !(h <= 1e-3f)) {
        *bad = "coarse_stick_n";
        return SS_ERR_RANGE;
    }
    const char *effect = stick_refused_effect(cfg);
    if (effect != NULL) {
        *bad = effect;
        return SS_ERR_RANGE;
    }
    /* a load holds the bristle at -L / sigma0, and the relaxation the flow leaves out, sigma0 |v|
     * z / g, then creeps with every swing of the contact's ring (0.08 % a cycle at 0.1 N on Table
     * I's 3 N Fc) */
    if (!(fabsf(cfg->effects.load_n) <= SS_COARSE_STICK_LOAD_SHARE * cfg->friction.fc_n)) {
        *bad = "effects.load_n";
        return SS_ERR_RANGE;
    }
    /* u = (e, v_rod / w, z, v_slider / w) about the ramp's steady state, w = sqrt(k / M_R) the
     * rod's rate, in the step's own time t / h (a velocity over w is a length, and the rod's two
     * terms alike, -(w h) e and (w h) v / w: a balanced matrix, fewer squarings; its flow, rounded
     * to float, against scipy's expm: tests/python/test_model_api.py):
     *   e' = wh v_r,  v_r' = -wh e - (c h / M_R) v_r - (s0 h / (M_R w)) z - (s h / M_R) (v_r - v_s),
     *   z' = wh (v_r - v_s),  v_s' = (s0 h / (M_C w)) z + (s h / M_C) (v_r - v_s),
     * with s0 = sigma0 and s = sigma1 + sigma2 (the bristle's damping and the viscous term, both on
     * the relative velocity while dz/dt = v) */
    const double mr = (double)cfg->rod_mass_kg;
    const double mc = (double)cfg->slider_mass_kg;
    const double s0 = (double)cfg->friction.sigma0_n_per_m;
    const double s = (double)cfg->friction.sigma1_ns_per_m + (double)cfg->friction.sigma2_ns_per_m;
    const double w = sqrt((double)cfg->piezo_stiffness_n_per_m / mr);
    const double hd = (double)h;
    const double wh = w * hd;
    const double c = (double)cfg->piezo_damping_kg_per_s;
    /* clang-format off */
    const double a[16] = {
        0.0, wh, 0.0, 0.0,
        -wh, -(c + s) * hd / mr, -s0 * hd / (mr * w), s * hd / mr,
        0.0, wh, 0.0, -wh,
        0.0, s * hd / mc, s0 * hd / (mc * w), -s * hd / mc,
    };
    /* clang-format on */
    double flow[16];
    mat4_exp(a, flow);
    float phi[16];
    for (int i = 0; i < 16; ++i) {
        phi[i] = (float)flow[i];
    }
    for (int i = 0; i < 16; ++i) {
        if (!isfinite(phi[i])) {
            *bad = "coarse_stick_n";
            return SS_ERR_RANGE;
        }
    }
    for (int i = 0; i < 16; ++i) {
        co->stick_phi[i] = phi[i];
    }
    co->stick_omega_per_s = (float)w;
    co->edge_parts = SS_COARSE_STICK_EDGE_PARTS;
    co->stick_n = stick_n;
    co->stick_dt_s = h;
    return SS_OK;
}
