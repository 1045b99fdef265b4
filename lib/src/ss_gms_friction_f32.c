#include "ss_gms_friction.h"

#include <math.h>
#include <stddef.h>

#include "ss_check.h"
#include "ss_exp_f32.h"
#include "ss_friction_inline_f32.h"

void ss_gms_shares_f32(float decay, float stiffness_ratio, float share[SS_GMS_ELEMENTS],
                       float kscale[SS_GMS_ELEMENTS])
{
    /* stiffnesses rho^i, scaled to sum to N (each 1 for rho = 1, exactly) */
    float k = 1.0f;
    float ksum = 0.0f;
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        kscale[i] = k;
        ksum += k;
        k *= stiffness_ratio;
    }
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        kscale[i] *= (float)SS_GMS_ELEMENTS / ksum;
    }
    /* element i (0-based) breaks away at a displacement proportional to 1 - c_i^(1/d),
     * c_i = 1 - (2i + 1) / 2N; its share is its stiffness times that. For d = 1 and rho = 1 every term
     * is exact in float: 1 - c_i = (2i + 1) / 8, shares (2i + 1) / 16. */
    const float inv_d = 1.0f / decay;
    float raw[SS_GMS_ELEMENTS];
    float sum = 0.0f;
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        const float c = 1.0f - (float)(2 * i + 1) / (float)(2 * SS_GMS_ELEMENTS);
        raw[i] = kscale[i] * (1.0f - powf(c, inv_d));
        sum += raw[i];
    }
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        share[i] = raw[i] / sum;
    }
}

/* An element is damped while it sticks: below its level, or at it with v turning it back (at
 * v = 0 its damping force is 0 either way). */
static int damped_at(const ss_gms_state_f32_t *st, int i, float v)
{
    return fabsf(st->f_n[i]) < st->share[i] * st->level_n || st->f_n[i] * v <= 0.0f;
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
    ss_gms_shares_f32(cfg->gms_decay, cfg->gms_stiffness_ratio, st->share, st->kscale);
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        st->f_n[i] = 0.0f;
    }
    st->level_n = cfg->fs_n;
    st->elastic_n = 0.0f;
    st->force_n = 0.0f;
    st->sliding = 0;
    ss_gms_begin_step_f32(st, 0.0f);
    return SS_OK;
}

void ss_gms_begin_step_f32(ss_gms_state_f32_t *st, float v_start_m_per_s)
{
    uint8_t bits = 0u;
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        bits |= (uint8_t)(damped_at(st, i, v_start_m_per_s) ? (1u << i) : 0u);
        st->stuck_m[i] = 0.0f;
    }
    st->damped_start = bits;
    st->v_start_m_per_s = v_start_m_per_s;
    st->step_s = 0.0f;
}

void ss_gms_advance_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st, float dx_m, float dt_s)
{
    if (!isfinite(dx_m) || !isfinite(dt_s) || !(dt_s > 0.0f)) {
        return;
    }
    ss_gms_begin_step_f32(st, dx_m / dt_s);
    ss_gms_advance_piece_f32(cfg, st, dx_m, dt_s);
}

void ss_gms_advance_piece_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st, float dx_m,
                              float dt_s)
{
    if (!isfinite(dx_m) || !isfinite(dt_s) || !(dt_s > 0.0f)) {
        return;
    }
    st->step_s += dt_s;
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
        trial[i] = st->f_n[i] + kdx * st->kscale[i];
        if (d * trial[i] < st->share[i] * st->level_n) {
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
    const float inv_kdx = 1.0f / fabsf(kdx);
    float sum = 0.0f;
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        const float w = st->share[i] * st->level_n;
        if (d * st->f_n[i] < w) {
            /* stuck at the piece's start: for all of it, or to where it reaches its level */
            /* (the reciprocal of its stiffness here, where an element breaks away, not kept) */
            const float part =
                (d * trial[i] > w) ? (w - d * st->f_n[i]) * inv_kdx * (1.0f / st->kscale[i]) : 1.0f;
            st->stuck_m[i] += part * dx_m;
        }
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
    /* asymmetric friction scales the contact's elastic and micro-damping force, as in LS */
    const float asym = ss_asymmetry_inline_f32(cfg, st->elastic_n);
    /* An element damped at both ends of the step adds sigma_i v (sigma_i = sigma1 k_i / sigma0), the
     * step's trapezoid with the force it began with. One whose damping switched inside the step adds
     * what makes its impulse over this step and the next sigma_i times its stuck displacement: this
     * force acts for half of this step and half of the next, the start force (at v_start) for half
     * of this one. Broke away: stuck / dt - v_start / 2; stuck again after a turn: stuck / dt + v / 2. */
    float below = 0.0f; /* stiffness of the elements below their level, in units of sigma0 / N */
    float per_v = 0.0f; /* damped elements, by their stiffness and their weight on v */
    float owed = 0.0f;  /* the switched elements' part that does not depend on v, m/s */
    const float inv_step = (st->step_s > 0.0f) ? 1.0f / st->step_s : 0.0f;
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        const float ks = st->kscale[i];
        below += (fabsf(st->f_n[i]) < st->share[i] * st->level_n) ? ks : 0.0f;
        const int end = damped_at(st, i, v_m_per_s);
        const int start = (int)((st->damped_start >> i) & 1u);
        if (start == end) {
            per_v += (float)end * ks;
        } else if (start) {
            owed += ks * (st->stuck_m[i] * inv_step - 0.5f * st->v_start_m_per_s);
        } else {
            owed += ks * (st->stuck_m[i] * inv_step);
            per_v += 0.5f * ks;
        }
    }
    const float c_i = asym * cfg->sigma1_ns_per_m / (float)SS_GMS_ELEMENTS;
    if (slopes != NULL) {
        slopes->dfdv_ns_per_m = cfg->sigma2_ns_per_m + c_i * per_v;
        /* an element at its slip level takes no more load in the direction it slipped: the last
         * motion's (none yet: every element sticks) */
        slopes->dfdx_n_per_m = asym * cfg->sigma0_n_per_m * (below / (float)SS_GMS_ELEMENTS);
    }
    return asym * st->elastic_n + (cfg->sigma2_ns_per_m + c_i * per_v) * v_m_per_s + c_i * owed;
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
