#include "ss_lugre.h"

#include <math.h>
#include <stddef.h>

#include "ss_check.h"

ss_status_t ss_lugre_init_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st)
{
    if (st == NULL) {
        return SS_ERR_NULL;
    }
    ss_status_t status = ss_friction_config_check_f32(cfg);
    if (status != SS_OK) {
        return status;
    }
    st->z_m = 0.0f;
    st->zdot_m_per_s = 0.0f;
    st->force_n = 0.0f;
    return SS_OK;
}

float ss_lugre_step_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st, float dx_m,
                        float dt_s)
{
    if (!isfinite(dx_m) || !isfinite(dt_s) || !(dt_s > 0.0f)) {
        return st->force_n;
    }
    const float v = dx_m / dt_s;
    const float z_old = st->z_m;
    if (dx_m != 0.0f) {
        /* dz/dx = sgn(v) - sigma0 z / g relaxes z to sgn(v) g / sigma0 over the distance
         * g / sigma0: exact for v frozen over the step, stable for any step. */
        const float g = ss_stribeck_f32(cfg, v);
        const float z_ss = ss_sign_f32(v) * g / cfg->sigma0_n_per_m;
        st->z_m = z_ss + (z_old - z_ss) * expf(-cfg->sigma0_n_per_m * fabsf(dx_m) / g);
    }
    st->zdot_m_per_s = (st->z_m - z_old) / dt_s;
    st->force_n = cfg->sigma0_n_per_m * st->z_m + cfg->sigma1_ns_per_m * st->zdot_m_per_s +
                  cfg->sigma2_ns_per_m * v;
    return st->force_n;
}

ss_status_t ss_lugre_run_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st,
                          const float *dx_m, uint32_t n, float dt_s, float *force_n)
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
