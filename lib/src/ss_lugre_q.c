#include "ss_lugre_q.h"

#include <stddef.h>

#include "ss_fixed_ops.h"
#include "ss_friction_inline_q.h"

/* |sigma0 z| (N at 2^-40) is at most about Fs; clamping it at 256 N keeps every product below
 * 2^63 whatever the state holds. */
#define SS_LUGRE_Q_SZ_MAX ((int64_t)1 << 48)

ss_status_t ss_lugre_init_q(const ss_friction_config_q_t *cfg, ss_lugre_state_q_t *st)
{
    if (st == NULL) {
        return SS_ERR_NULL;
    }
    const ss_status_t status = ss_friction_config_check_q(cfg, NULL);
    if (status != SS_OK) {
        return status;
    }
    st->z_q40 = 0;
    st->zdot_q28 = 0;
    st->force_q24 = 0;
    return SS_OK;
}

/* sigma0 z / g in Q30 from sz = sigma0 z (N at 2^-40) and g's reciprocal m 2^-sh
 * (ss_reciprocal_mantissa_q; sh in [42, 60] for g in (2^11, 2^29]): |sz| 2^14 m / 2^sh with
 * |sz| < 2^49 in two products (ss_mul_shr_round_u49: sh - 14 >= 28). */
static int64_t bristle_ratio_q30(int64_t sz, int32_t m, int sh)
{
    const int64_t k = (int64_t)ss_mul_shr_round_u49((uint64_t)ss_abs64(sz), m, sh - 14);
    return (sz < 0) ? -k : k;
}

/* The force at slip velocity v (and its slopes when slopes is not NULL), and dz/dt there: one
 * Stribeck level, one reciprocal of it, one bristle force for all of them. */
static int32_t force_at(const ss_friction_config_q_t *cfg, const ss_lugre_state_q_t *st, int32_t v_q28,
                        ss_friction_slopes_q_t *slopes, int64_t *zdot_q28)
{
    int32_t *dfdv_q16 = (slopes != NULL) ? &slopes->dfdv_q16 : NULL;
    const int64_t v = v_q28;
    int32_t slope = 0;
    const int64_t g =
        (dfdv_q16 != NULL) ? ss_stribeck_with_slope_q(cfg, v_q28, &slope) : ss_stribeck_q(cfg, v_q28);
    /* 1/g = m 2^-sh, once for both quotients by g */
    int sh = 0;
    const int32_t m = ss_stribeck_recip_q(cfg, g, &sh);
    /* the bristle force sigma0 z, N at 2^-40 */
    const int64_t sz =
        ss_clamp64(ss_mul_s32_s64(cfg->sigma0_n_per_m, st->z_q40), -SS_LUGRE_Q_SZ_MAX, SS_LUGRE_Q_SZ_MAX);
    const int64_t k = bristle_ratio_q30(sz, m, sh);
    const int64_t zdot = v - ss_shr_round(ss_mul_i64(ss_abs64(v), k), 30);
    if (dfdv_q16 != NULL) {
        /* d(dz/dt)/dv = 1 - sgn(v) sigma0 z / g + |v| (sigma0 z / g) g' / g; |v| g'/g at 2^-20, from
         * |v| g' rounded to 2^-24 N (as in the LS element) */
        const int64_t vg =
            ss_mul_recip_q(ss_sat32(ss_shr_round(ss_mul_i64_i32(ss_abs64(v), slope), 20)), m, sh - 20);
        const int64_t dzdv = SS_Q30_ONE - ss_times_sign_of(k, v) + ss_shr_round(ss_mul_i64(k, vg), 20);
        *dfdv_q16 = ss_sat32(
            ss_asymmetric_inline_q(cfg, ss_shr_round(ss_mul_i64_i32(dzdv, cfg->sigma1_q16), 30), st->z_q40) +
            cfg->sigma2_q16);
        /* the relaxation's dz/dx = 1 - sgn(v) sigma0 z / g, Q30, none below 0 */
        const int64_t dzdx = SS_Q30_ONE - ss_times_sign_of(k, v);
        slopes->dfdx_q30 = (dzdx > 0) ? ss_sat32(ss_asymmetric_inline_q(cfg, dzdx, st->z_q40)) : 0;
    }
    *zdot_q28 = zdot;
    const int64_t contact = ss_shr_round(sz, 16) + ss_shr_round(ss_mul_i64_i32(zdot, cfg->sigma1_q16), 20);
    return ss_sat32(ss_asymmetric_inline_q(cfg, contact, st->z_q40) +
                    ss_shr_round(ss_mul_s32_s64(cfg->sigma2_q16, v_q28), 20));
}

void ss_lugre_advance_q(const ss_friction_config_q_t *cfg, ss_lugre_state_q_t *st, int32_t dx_q40,
                        int32_t inv_dt_q47)
{
    if (inv_dt_q47 <= 0 || dx_q40 == 0) {
        return;
    }
    /* z relaxes to sgn(v) g / sigma0 over the distance g / sigma0: exact for v frozen over the step */
    const int32_t v = ss_velocity_q28(dx_q40, inv_dt_q47);
    const int64_t g = ss_stribeck_q(cfg, v);
    /* g / sigma0 in m at 2^-40: N at 2^-24 times m/N at 2^-47 is m at 2^-71 */
    const int64_t z_ss =
        ss_times_sign_of(ss_shr_round(ss_mul_i64_i32(g, cfg->inv_sigma0_q47), 47 - SS_QF_F_OVER_K), dx_q40);
    /* exponent sigma0 |dx| / g with 32 fraction bits, as in the LS element */
    const uint64_t num = ss_mul_u64_u32((uint64_t)ss_abs64(dx_q40), (uint32_t)cfg->sigma0_n_per_m);
    int sh = 0;
    const int32_t m = ss_stribeck_recip_q(cfg, g, &sh);
    const int64_t decay = ss_exp_neg_q32_q30(ss_ratio_x65536_recip(num, (uint64_t)g, m, sh)); /* [0, 2^30] */
    st->z_q40 = ss_sat32(z_ss + ss_shr_round(ss_mul_i64_i32((int64_t)st->z_q40 - z_ss, (int32_t)decay), 30));
}

int32_t ss_lugre_step_q(const ss_friction_config_q_t *cfg, ss_lugre_state_q_t *st, int32_t dx_q40,
                        int32_t dt_q40)
{
    const int32_t inv_dt = ss_inv_dt_q47(dt_q40);
    if (inv_dt == 0) {
        return st->force_q24;
    }
    ss_lugre_advance_q(cfg, st, dx_q40, inv_dt);
    int64_t zdot = 0;
    st->force_q24 = force_at(cfg, st, ss_velocity_q28(dx_q40, inv_dt), NULL, &zdot);
    st->zdot_q28 = ss_sat32(zdot);
    return st->force_q24;
}

int32_t ss_lugre_force_at_q(const ss_friction_config_q_t *cfg, const ss_lugre_state_q_t *st, int32_t v_q28,
                            ss_friction_slopes_q_t *slopes)
{
    int64_t zdot = 0;
    return force_at(cfg, st, v_q28, slopes, &zdot);
}

int32_t ss_lugre_settle_q(const ss_friction_config_q_t *cfg, ss_lugre_state_q_t *st, int32_t v_q28)
{
    int64_t zdot = 0;
    st->force_q24 = force_at(cfg, st, v_q28, NULL, &zdot);
    st->zdot_q28 = ss_sat32(zdot);
    return st->force_q24;
}

ss_status_t ss_lugre_run_q(const ss_friction_config_q_t *cfg, ss_lugre_state_q_t *st, const int32_t *dx_q40,
                           uint32_t n, int32_t dt_q40, int32_t *force_q24)
{
    if (cfg == NULL || st == NULL || (n > 0u && (dx_q40 == NULL || force_q24 == NULL))) {
        return SS_ERR_NULL;
    }
    if (ss_inv_dt_q47(dt_q40) == 0) {
        return SS_ERR_RANGE;
    }
    for (uint32_t i = 0; i < n; ++i) {
        force_q24[i] = ss_lugre_step_q(cfg, st, dx_q40[i], dt_q40);
    }
    return SS_OK;
}
