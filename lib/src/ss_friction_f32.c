#include "ss_friction.h"

#include <math.h>
#include <stddef.h>

#include "ss_check.h"
#include "ss_friction_inline_f32.h"

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
    cfg.asymmetry = 0.0f;
    cfg.gms_decay = 1.0f;
    cfg.gms_stiffness_ratio = 1.0f;
    return cfg;
}

ss_friction_mu_f32_t ss_friction_mu_table1_f32(void)
{
    const ss_friction_mu_f32_t m = {0.36f, 0.30f, 10.0f, 0.4e-3f, 1.0e7f, 80.0f, 8.0f};
    return m;
}

ss_friction_config_f32_t ss_friction_config_table1_f32(void)
{
    const ss_friction_mu_f32_t m = ss_friction_mu_table1_f32();
    return ss_friction_config_from_mu_f32(m.mu_s, m.mu_d, m.normal_force_n, m.vs_m_per_s, m.sigma0_n_per_m,
                                          m.sigma1_ns_per_m, m.sigma2_ns_per_m);
}

/* Field names, bare and as seen from the actuator config (no string functions in lib/). */
static const char *const FIELD_NAMES[2][SS_FRICTION_N_FIELDS] = {
    {"fs_n", "fc_n", "vs_m_per_s", "sigma0_n_per_m", "sigma1_ns_per_m", "sigma2_ns_per_m", "asymmetry",
     "gms_decay", "gms_stiffness_ratio"},
    {"friction.fs_n", "friction.fc_n", "friction.vs_m_per_s", "friction.sigma0_n_per_m",
     "friction.sigma1_ns_per_m", "friction.sigma2_ns_per_m", "friction.asymmetry", "friction.gms_decay",
     "friction.gms_stiffness_ratio"},
};

ss_status_t ss_friction_config_check_named_f32(const ss_friction_config_f32_t *cfg, int prefixed,
                                               const char **bad_field)
{
    *bad_field = "";
    if (cfg == NULL) {
        *bad_field = "config";
        return SS_ERR_NULL;
    }
    const char *const *names = FIELD_NAMES[prefixed ? 1 : 0];
    const ss_range_f32_t ranges[SS_FRICTION_N_FIELDS] = {
        {names[0], cfg->fs_n, 1e-6f, 1e4f},
        {names[1], cfg->fc_n, 1e-6f, 1e4f},
        {names[2], cfg->vs_m_per_s, 1e-9f, 10.0f},
        {names[3], cfg->sigma0_n_per_m, 1.0f, 1e12f},
        {names[4], cfg->sigma1_ns_per_m, 0.0f, 1e6f},
        {names[5], cfg->sigma2_ns_per_m, 0.0f, 1e6f},
        {names[6], cfg->asymmetry, -0.9f, 0.9f},
        {names[7], cfg->gms_decay, 0.05f, 20.0f},
        {names[8], cfg->gms_stiffness_ratio, 0.05f, 20.0f},
    };
    ss_status_t st = ss_check_ranges_f32(ranges, SS_FRICTION_N_FIELDS, bad_field);
    if (st == SS_OK && cfg->fc_n > cfg->fs_n) {
        /* Fc above Fs would make the Stribeck curve rise: not the physics either model describes. */
        *bad_field = names[1];
        st = SS_ERR_RANGE;
    }
    return st;
}

ss_status_t ss_friction_config_check_f32(const ss_friction_config_f32_t *cfg, const char **bad_field)
{
    const char *dummy = "";
    return ss_friction_config_check_named_f32(cfg, 0, (bad_field != NULL) ? bad_field : &dummy);
}

float ss_stribeck_f32(const ss_friction_config_f32_t *cfg, float v_m_per_s)
{
    return ss_stribeck_inline_f32(cfg, v_m_per_s);
}

float ss_asymmetry_factor_f32(const ss_friction_config_f32_t *cfg, float load)
{
    return ss_asymmetry_inline_f32(cfg, load);
}

float ss_stribeck_slope_f32(const ss_friction_config_f32_t *cfg, float v_m_per_s)
{
    float slope;
    (void)ss_stribeck_with_slope_f32(cfg, v_m_per_s, &slope);
    return slope;
}

float ss_stribeck_with_slope_f32(const ss_friction_config_f32_t *cfg, float v_m_per_s, float *slope_ns_per_m)
{
    return ss_stribeck_with_slope_inline_f32(cfg, v_m_per_s, slope_ns_per_m);
}
