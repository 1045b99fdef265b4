#include "ss_lugre.h"

#include <math.h>
#include <stddef.h>

#include "ss_check.h"
#include "ss_exp_f32.h"

ss_status_t ss_lugre_init_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st)
{
    if (st == NULL) {
        return SS_ERR_NULL;
    }
    ss_status_t status = ss_friction_config_check_f32(cfg, NULL);
    if (status != SS_OK) {
        return status;
    }
    st->z_m = 0.0f;
    st->zdot_m_per_s = 0.0f;
    st->force_n = 0.0f;
    return SS_OK;
}

void ss_lugre_advance_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st, float dx_m,
                          float dt_s)
{
    if (!isfinite(dx_m) || !isfinite(dt_s) || !(dt_s > 0.0f) || dx_m == 0.0f) {
        return;
    }
    /* dz/dx = sgn(v) - sigma0 z / g relaxes z to sgn(v) g / sigma0 over the distance g / sigma0:
     * exact for v frozen over the step, stable for any step. */
    const float v = dx_m / dt_s;
    const float g = ss_stribeck_f32(cfg, v);
    const float z_ss = ss_sign_f32(v) * g / cfg->sigma0_n_per_m;
    st->z_m = z_ss + (st->z_m - z_ss) * ss_exp_neg_f32(cfg->sigma0_n_per_m * fabsf(dx_m) / g);
}

float ss_lugre_step_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st, float dx_m, float dt_s)
{
    if (!isfinite(dx_m) || !isfinite(dt_s) || !(dt_s > 0.0f)) {
        return st->force_n;
    }
    ss_lugre_advance_f32(cfg, st, dx_m, dt_s);
    const float v = dx_m / dt_s;
    st->zdot_m_per_s = v - cfg->sigma0_n_per_m * fabsf(v) * st->z_m / ss_stribeck_f32(cfg, v);
    st->force_n = ss_lugre_force_at_f32(cfg, st, v, NULL);
    return st->force_n;
}

float ss_lugre_force_at_f32(const ss_friction_config_f32_t *cfg, const ss_lugre_state_f32_t *st,
                            float v_m_per_s, float *dfdv_ns_per_m)
{
    const float v = v_m_per_s;
    float slope = 0.0f;
    const float g =
        (dfdv_ns_per_m != NULL) ? ss_stribeck_with_slope_f32(cfg, v, &slope) : ss_stribeck_f32(cfg, v);
    const float k = cfg->sigma0_n_per_m * st->z_m / g; /* sigma0 z / g */
    const float zdot = v - fabsf(v) * k;
    const float asym = ss_asymmetry_factor_f32(cfg, st->z_m);
    if (dfdv_ns_per_m != NULL) {
        /* d(dz/dt)/dv = 1 - sgn(v) sigma0 z / g + |v| sigma0 z g' / g^2 */
        const float dzdv = 1.0f - ss_sign_f32(v) * k + fabsf(v) * k * slope / g;
        *dfdv_ns_per_m = asym * cfg->sigma1_ns_per_m * dzdv + cfg->sigma2_ns_per_m;
    }
    return asym * (cfg->sigma0_n_per_m * st->z_m + cfg->sigma1_ns_per_m * zdot) + cfg->sigma2_ns_per_m * v;
}

ss_status_t ss_lugre_run_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st, const float *dx_m,
                             uint32_t n, float dt_s, float *force_n)
{
    if (cfg == NULL || st == NULL || (n > 0u && (dx_m == NULL || force_n == NULL))) {
        return SS_ERR_NULL;
    }
    ss_status_t status = ss_check_range_f32(dt_s, 1e-12f, 1e3f);
    for (uint32_t i = 0; status == SS_OK && i < n; ++i) {
        if (!isfinite(dx_m[i])) {
            return SS_ERR_NONFINITE;
        }
        force_n[i] = ss_lugre_step_f32(cfg, st, dx_m[i], dt_s);
    }
    return status;
}
