#include "ss_friction.h"

#include <math.h>
#include <stddef.h>

#include "ss_check.h"

ss_friction_config_f32_t ss_friction_config_from_mu_f32(float mu_s, float mu_d, float normal_force_n,
                                                        float vs_m_per_s, float sigma0_n_per_m,
                                                        float sigma1_ns_per_m, float sigma2_ns_per_m)
{
    ss_friction_config_f32_t cfg;
    cfg.fs_n = mu_s * normal_force_n;
    cfg.fc_n = mu_d * normal_force_n;
    cfg.vs_m_per_s = vs_m_per_s;
    cfg.sigma0_n_per_m = sigma0_n_per_m;
    cfg.sigma1_ns_per_m = sigma1_ns_per_m;
    cfg.sigma2_ns_per_m = sigma2_ns_per_m;
    return cfg;
}

ss_friction_config_f32_t ss_friction_config_table1_f32(void)
{
    return ss_friction_config_from_mu_f32(0.36f, 0.30f, 10.0f, 0.4e-3f, 1.0e7f, 80.0f, 8.0f);
}

ss_status_t ss_friction_config_check_f32(const ss_friction_config_f32_t *cfg, const char **bad_field)
{
    const char *dummy = "";
    const char **bad = (bad_field != NULL) ? bad_field : &dummy;
    *bad = "";
    if (cfg == NULL) {
        *bad = "config";
        return SS_ERR_NULL;
    }
    const ss_range_f32_t ranges[] = {
        {"fs_n", cfg->fs_n, 1e-6f, 1e4f},
        {"fc_n", cfg->fc_n, 1e-6f, 1e4f},
        {"vs_m_per_s", cfg->vs_m_per_s, 1e-9f, 10.0f},
        {"sigma0_n_per_m", cfg->sigma0_n_per_m, 1.0f, 1e12f},
        {"sigma1_ns_per_m", cfg->sigma1_ns_per_m, 0.0f, 1e6f},
        {"sigma2_ns_per_m", cfg->sigma2_ns_per_m, 0.0f, 1e6f},
    };
    ss_status_t st = ss_check_ranges_f32(ranges, sizeof ranges / sizeof ranges[0], bad);
    if (st == SS_OK && cfg->fc_n > cfg->fs_n) {
        /* Fc above Fs would make the Stribeck curve rise: not the physics either model describes. */
        *bad = "fc_n";
        st = SS_ERR_RANGE;
    }
    return st;
}

float ss_stribeck_f32(const ss_friction_config_f32_t *cfg, float v_m_per_s)
{
    const float r = v_m_per_s / cfg->vs_m_per_s;
    return cfg->fc_n + (cfg->fs_n - cfg->fc_n) * expf(-r * r);
}

float ss_stribeck_slope_f32(const ss_friction_config_f32_t *cfg, float v_m_per_s)
{
    const float r = v_m_per_s / cfg->vs_m_per_s;
    return -2.0f * (cfg->fs_n - cfg->fc_n) * r / cfg->vs_m_per_s * expf(-r * r);
}
