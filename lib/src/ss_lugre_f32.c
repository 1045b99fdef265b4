#include "ss_lugre.h"

#include <math.h>
#include <stddef.h>

#include "ss_check.h"
#include "ss_exp_f32.h"
#include "ss_friction_inline_f32.h"
#include "ss_friction_parts_f32.h"
#include "ss_inline.h"

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

/* The parts of the advance and the force (ss_friction_parts_f32.h): inline here, so that the
 * public functions, which are their parts in turn, cost no more than before they were parts. */
SS_FORCE_INLINE void advance_begin(const ss_friction_config_f32_t *cfg, float dx_m, float dt_s,
                                   ss_lugre_slip_f32_t *s)
{
    s->moves = !(!isfinite(dx_m) || !isfinite(dt_s) || !(dt_s > 0.0f) || dx_m == 0.0f);
    if (s->moves) {
        s->v_m_per_s = dx_m / dt_s;
        s->g_n = ss_stribeck_inline_f32(cfg, s->v_m_per_s);
    }
}

SS_FORCE_INLINE void advance_end(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st, float dx_m,
                                 const ss_lugre_slip_f32_t *s)
{
    if (!s->moves) {
        return;
    }
    /* dz/dx = sgn(v) - sigma0 z / g relaxes z to sgn(v) g / sigma0 over the distance g / sigma0:
     * exact for v frozen over the step, stable for any step. */
    const float g = s->g_n;
    const float z_ss = ss_sign_f32(s->v_m_per_s) * g / cfg->sigma0_n_per_m;
    st->z_m = z_ss + (st->z_m - z_ss) * ss_exp_neg_f32(cfg->sigma0_n_per_m * fabsf(dx_m) / g);
}

SS_FORCE_INLINE void force_begin(const ss_friction_config_f32_t *cfg, float v_m_per_s, int with_slope,
                                 ss_lugre_level_f32_t *l)
{
    l->slope_ns_per_m = 0.0f;
    l->g_n = with_slope ? ss_stribeck_with_slope_inline_f32(cfg, v_m_per_s, &l->slope_ns_per_m)
                        : ss_stribeck_inline_f32(cfg, v_m_per_s);
}

SS_FORCE_INLINE float force_end(const ss_friction_config_f32_t *cfg, const ss_lugre_state_f32_t *st,
                                float v_m_per_s, const ss_lugre_level_f32_t *l,
                                ss_friction_slopes_f32_t *slopes)
{
    const float v = v_m_per_s;
    const float slope = l->slope_ns_per_m;
    const float g = l->g_n;
    const float k = cfg->sigma0_n_per_m * st->z_m / g; /* sigma0 z / g */
    const float zdot = v - fabsf(v) * k;
    const float asym = ss_asymmetry_inline_f32(cfg, st->z_m);
    if (slopes != NULL) {
        /* d(dz/dt)/dv = 1 - sgn(v) sigma0 z / g + |v| sigma0 z g' / g^2 */
        const float dzdv = 1.0f - ss_sign_f32(v) * k + fabsf(v) * k * slope / g;
        slopes->dfdv_ns_per_m = asym * cfg->sigma1_ns_per_m * dzdv + cfg->sigma2_ns_per_m;
        /* the relaxation's dz/dx = 1 - sgn(v) sigma0 z / g: sigma0 at rest, 0 in steady sliding
         * (and below 0 nowhere but in rounding) */
        const float dzdx = 1.0f - ss_sign_f32(v) * k;
        slopes->dfdx_n_per_m = (dzdx > 0.0f) ? asym * cfg->sigma0_n_per_m * dzdx : 0.0f; /* no libm fmaxf */
    }
    return asym * (cfg->sigma0_n_per_m * st->z_m + cfg->sigma1_ns_per_m * zdot) + cfg->sigma2_ns_per_m * v;
}

void ss_lugre_advance_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st, float dx_m,
                          float dt_s)
{
    ss_lugre_slip_f32_t s;
    advance_begin(cfg, dx_m, dt_s, &s);
    advance_end(cfg, st, dx_m, &s);
}

float ss_lugre_step_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st, float dx_m, float dt_s)
{
    if (!isfinite(dx_m) || !isfinite(dt_s) || !(dt_s > 0.0f)) {
        return st->force_n;
    }
    ss_lugre_slip_f32_t s;
    advance_begin(cfg, dx_m, dt_s, &s);
    advance_end(cfg, st, dx_m, &s);
    const float v = dx_m / dt_s;
    /* the force's Stribeck level is the advance's, at the same velocity (once a step, not thrice) */
    ss_lugre_level_f32_t l;
    l.slope_ns_per_m = 0.0f;
    l.g_n = s.moves ? s.g_n : ss_stribeck_inline_f32(cfg, v);
    st->zdot_m_per_s = v - cfg->sigma0_n_per_m * fabsf(v) * st->z_m / l.g_n;
    st->force_n = force_end(cfg, st, v, &l, NULL);
    return st->force_n;
}

float ss_lugre_force_at_f32(const ss_friction_config_f32_t *cfg, const ss_lugre_state_f32_t *st,
                            float v_m_per_s, ss_friction_slopes_f32_t *slopes)
{
    ss_lugre_level_f32_t l;
    force_begin(cfg, v_m_per_s, slopes != NULL, &l);
    return force_end(cfg, st, v_m_per_s, &l, slopes);
}

float ss_lugre_settle_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st, float v_m_per_s)
{
    ss_lugre_level_f32_t l;
    force_begin(cfg, v_m_per_s, 0, &l);
    st->zdot_m_per_s = v_m_per_s - cfg->sigma0_n_per_m * fabsf(v_m_per_s) * st->z_m / l.g_n;
    st->force_n = force_end(cfg, st, v_m_per_s, &l, NULL);
    return st->force_n;
}

void ss_lugre_advance_begin_f32(const ss_friction_config_f32_t *cfg, float dx_m, float dt_s,
                                ss_lugre_slip_f32_t *s)
{
    advance_begin(cfg, dx_m, dt_s, s);
}

void ss_lugre_advance_end_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st, float dx_m,
                              const ss_lugre_slip_f32_t *s)
{
    advance_end(cfg, st, dx_m, s);
}

void ss_lugre_force_begin_f32(const ss_friction_config_f32_t *cfg, float v_m_per_s, int with_slope,
                              ss_lugre_level_f32_t *l)
{
    force_begin(cfg, v_m_per_s, with_slope, l);
}

float ss_lugre_force_end_f32(const ss_friction_config_f32_t *cfg, const ss_lugre_state_f32_t *st,
                             float v_m_per_s, const ss_lugre_level_f32_t *l, ss_friction_slopes_f32_t *slopes)
{
    return force_end(cfg, st, v_m_per_s, l, slopes);
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
