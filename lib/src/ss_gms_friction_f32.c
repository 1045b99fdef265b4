#include "ss_gms_friction.h"

#include <math.h>
#include <stddef.h>

#include "ss_check.h"
#include "ss_exp_f32.h"
#include "ss_friction_inline_f32.h"

/* Share alpha_i of the slip level carried by element i (0-based): (2i + 1) / N^2, exact in float
 * for N a power of two. */
static float share(int i)
{
    return (float)(2 * i + 1) / (float)(SS_GMS_ELEMENTS * SS_GMS_ELEMENTS);
}

ss_status_t ss_gms_init_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st)
{
    if (st == NULL) {
        return SS_ERR_NULL;
    }
    ss_status_t status = ss_friction_config_check_f32(cfg, NULL);
    if (status != SS_OK) {
        return status;
    }
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        st->f_n[i] = 0.0f;
    }
    st->level_n = cfg->fs_n;
    st->elastic_n = 0.0f;
    st->force_n = 0.0f;
    st->sliding = 0;
    return SS_OK;
}

void ss_gms_advance_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st, float dx_m, float dt_s)
{
    if (!isfinite(dx_m) || !isfinite(dt_s) || !(dt_s > 0.0f)) {
        return;
    }
    if (dx_m == 0.0f) {
        st->sliding = 0; /* no motion, nothing slips */
        return;
    }
    const int8_t dir = (dx_m > 0.0f) ? (int8_t)1 : (int8_t)-1;
    const float d = (float)dir;
    const float kdx = cfg->sigma0_n_per_m / (float)SS_GMS_ELEMENTS * dx_m;
    float trial[SS_GMS_ELEMENTS];
    int all_slip = 1;
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        trial[i] = st->f_n[i] + kdx;
        if (d * trial[i] < share(i) * st->level_n) {
            all_slip = 0;
        }
    }
    if (all_slip) {
        /* Gross sliding: the level relaxes to g(v) over the distance g / sigma0, as LS's sliding
         * part does (exact for v frozen over the step, stable at any step). In presliding some
         * element sticks and the level stays put, so presliding is exactly rate independent. */
        const float g = ss_stribeck_inline_f32(cfg, dx_m / dt_s);
        st->level_n = g + (st->level_n - g) * ss_exp_neg_f32(cfg->sigma0_n_per_m * fabsf(dx_m) / g);
    }
    float sum = 0.0f;
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        const float w = share(i) * st->level_n;
        /* an element past its slip level slips; compares, not libm's fminf / fmaxf calls (the same
         * result for a slip level w > 0, a NaN trial included: -w) */
        st->f_n[i] = (trial[i] > w) ? w : ((trial[i] >= -w) ? trial[i] : -w);
        sum += st->f_n[i];
    }
    st->elastic_n = sum;
    st->sliding = 0;
    if (all_slip) {
        st->sliding = dir;
    }
}

float ss_gms_step_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st, float dx_m, float dt_s)
{
    if (!isfinite(dx_m) || !isfinite(dt_s) || !(dt_s > 0.0f)) {
        return st->force_n;
    }
    ss_gms_advance_f32(cfg, st, dx_m, dt_s);
    st->force_n = ss_gms_force_at_f32(cfg, st, dx_m / dt_s, NULL);
    return st->force_n;
}

float ss_gms_force_at_f32(const ss_friction_config_f32_t *cfg, const ss_gms_state_f32_t *st, float v_m_per_s,
                          ss_friction_slopes_f32_t *slopes)
{
    /* asymmetric friction scales the contact's elastic force, as in LS */
    const float asym = ss_asymmetry_inline_f32(cfg, st->elastic_n);
    if (slopes != NULL) {
        slopes->dfdv_ns_per_m = cfg->sigma2_ns_per_m;
        /* an element at its slip level takes no more load in the direction it slipped: the last
         * motion's (none yet: every element sticks) */
        int sticking = 0;
        for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
            sticking += (fabsf(st->f_n[i]) < share(i) * st->level_n) ? 1 : 0;
        }
        slopes->dfdx_n_per_m = asym * cfg->sigma0_n_per_m * ((float)sticking / (float)SS_GMS_ELEMENTS);
    }
    return asym * st->elastic_n + cfg->sigma2_ns_per_m * v_m_per_s;
}

ss_status_t ss_gms_run_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st, const float *dx_m,
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
        force_n[i] = ss_gms_step_f32(cfg, st, dx_m[i], dt_s);
    }
    return status;
}
