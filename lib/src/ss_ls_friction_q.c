#include "ss_ls_friction_q.h"

#include <stddef.h>

#include "ss_fixed_ops.h"
#include "ss_friction_inline_q.h"

/* sigma0 |dx| / (2^halves Fs) as the Q32 exponent of ss_exp_neg_q32_q30: N/m times m at 2^-40
 * times 1/N at 2^-24 is a pure number at 2^-64. A branch spans at most two saturation lengths
 * (2^29); |dx| held below 2^31 keeps sigma0 |dx| below 2^62, as the wide product needs. */
static uint64_t exponent_fs_q32(const ss_friction_config_q_t *cfg, int64_t dx_q40, int halves)
{
    const int64_t num =
        ss_mul_s32_s64(cfg->sigma0_n_per_m, (int32_t)ss_clamp64(ss_abs64(dx_q40), 0, INT32_MAX));
    return (uint64_t)ss_mul_shr_round_wide(num, cfg->inv_fs_q48, 32 + halves);
}

/* sigma0 |dx| / g (g a Stribeck level at 2^-24 N, > 0) as the Q32 exponent of ss_exp_neg_q32_q30,
 * by g's reciprocal (no division while sigma0 |dx| < 2^49; Fc's from the config in gross slip). */
static uint64_t exponent_q32(const ss_friction_config_q_t *cfg, int64_t dx_q40, int64_t den_q24)
{
    /* |dx| < 2^32 and sigma0 < 2^31: the product fits */
    const uint64_t num = ss_mul_u64_u32((uint64_t)ss_abs64(dx_q40), (uint32_t)cfg->sigma0_n_per_m);
    int sh = 0;
    const int32_t m = ss_stribeck_recip_q(cfg, den_q24, &sh);
    return ss_ratio_x65536_recip(num, (uint64_t)den_q24, m, sh);
}

/* Smooth step from 0 (|F_M| <= 0.9 Fs) to 1 (at Fs) in Q30: only gross slip drives the LuGre part.
 * The threshold is compared exactly (10 |F_M| <= 9 Fs), so presliding below it is bit-exact
 * rate independent. */
static int64_t breakaway_gate_q30(const ss_friction_config_q_t *cfg, int32_t fm_q24)
{
    const int64_t over = 10 * ss_abs64(fm_q24) - 9 * (int64_t)cfg->fs_q24;
    if (over <= 0) {
        return 0;
    }
    if (over >= cfg->fs_q24) {
        return SS_Q30_ONE;
    }
    /* 0 < over < Fs < 2^31, so t in (0, 2^30]: every product below is of 32-bit values */
    const int64_t t =
        ss_shr_round(ss_mul_s32_s64((int32_t)over, cfg->inv_fs_q48), 48 - 30); /* over / Fs, Q30 */
    const int64_t t2 = ss_shr_round(ss_mul_s32_s64((int32_t)t, (int32_t)t), 30);
    /* t2 (3 - 2t) below 3 x 2^60: within int64 */
    return ss_shr_round((int64_t)ss_mul_u32_u64((uint32_t)t2, (uint32_t)(3 * (int64_t)SS_Q30_ONE - 2 * t)),
                        30);
}

/* The gate of fm_q24, kept in the state (made again where the config's Fs is not the one it was
 * taken at) */
static int64_t gate_of_fm_q30(const ss_friction_config_q_t *cfg, ss_ls_state_q_t *st)
{
    if (st->gate_fs_q24 != cfg->fs_q24) {
        st->gate_q30 = (int32_t)breakaway_gate_q30(cfg, st->fm_q24);
        st->gate_fs_q24 = cfg->fs_q24;
    }
    return st->gate_q30;
}

ss_status_t ss_ls_init_q(const ss_friction_config_q_t *cfg, ss_ls_state_q_t *st)
{
    if (st == NULL) {
        return SS_ERR_NULL;
    }
    const ss_status_t status = ss_friction_config_check_q(cfg, NULL);
    if (status != SS_OK) {
        return status;
    }
    st->x_q40 = 0;
    st->x0_q40 = 0;
    st->fm_q24 = 0;
    st->kt_q30 = SS_Q30_ONE;
    st->level_q24 = cfg->fs_q24;
    st->force_q24 = 0;
    st->gate_q30 = 0; /* F_M = 0: no gross slip */
    st->gate_fs_q24 = cfg->fs_q24;
    st->dir = 0;
    st->depth = 0;
    for (int i = 0; i < SS_LS_Q_MEMORY_DEPTH; ++i) {
        st->rev[i].x_q40 = 0;
        st->rev[i].f_q24 = 0;
    }
    return SS_OK;
}

static void push_reversal(ss_ls_state_q_t *st)
{
    if (st->depth >= SS_LS_Q_MEMORY_DEPTH) {
        st->depth = (uint8_t)(st->depth - 2u); /* forget the innermost minor loop */
    }
    st->rev[st->depth].x_q40 = st->x_q40;
    st->rev[st->depth].f_q24 = st->fm_q24;
    st->depth++;
}

/* Has a branch moving up (else down) reached a point d below (above) it: d dir >= 0, by compares
 * (a product by +-1 is a library call on ARMv6-M) */
static inline int reached(int up, int64_t d)
{
    return up ? d >= 0 : d <= 0;
}

/* Wiping-out, as in the float family: a branch that reaches the reversal point where the opposite
 * branch began closes that minor loop. */
static void close_loops(ss_ls_state_q_t *st)
{
    const int up = st->dir > 0; /* dir is +-1 here: set by the step that called us */
    for (;;) {
        if (st->depth >= 2u && reached(up, (int64_t)st->x_q40 - st->rev[st->depth - 2u].x_q40)) {
            st->depth = (uint8_t)(st->depth - 2u);
        } else if (st->depth == 1u &&
                   reached(up, (int64_t)st->x_q40 - (2 * (int64_t)st->x0_q40 - st->rev[0].x_q40))) {
            st->depth = 0u;
        } else {
            return;
        }
    }
}

/* Masing branches of phi(u) = Fs (1 - exp(-sigma0 u / Fs)); 1 - e in [0, 2^30] (Q30), a 32-bit
 * factor. */
static void eval_branch(const ss_friction_config_q_t *cfg, ss_ls_state_q_t *st)
{
    const int64_t fs = cfg->fs_q24;
    if (st->depth == 0u) {
        const int64_t u = (int64_t)st->x_q40 - st->x0_q40;
        const int64_t e = ss_exp_neg_q32_q30(exponent_fs_q32(cfg, u, 0));
        st->fm_q24 =
            (int32_t)ss_times_sign_of(ss_shr_round(ss_mul_i64_i32(fs, (int32_t)(SS_Q30_ONE - e)), 30), u);
        st->kt_q30 = (int32_t)e;
    } else {
        const ss_ls_reversal_q_t *r = &st->rev[st->depth - 1u];
        const int64_t e = ss_exp_neg_q32_q30(exponent_fs_q32(cfg, (int64_t)st->x_q40 - r->x_q40, 1));
        const int64_t swing = ss_shr_round(ss_mul_i64_i32(2 * fs, (int32_t)(SS_Q30_ONE - e)), 30);
        const int64_t fm = r->f_q24 + ((st->dir > 0) ? swing : -swing);
        st->fm_q24 = (int32_t)ss_clamp64(fm, -fs, fs); /* rounding must not push |F_M| past Fs */
        st->kt_q30 = (int32_t)e;
    }
}

static void rebase(const ss_friction_config_q_t *cfg, ss_ls_state_q_t *st)
{
    if (st->depth != 0u) {
        return; /* reversal points bound the excursion */
    }
    const int64_t u = (int64_t)st->x_q40 - st->x0_q40;
    const int64_t l_sat = cfg->sat_length_q40; /* SS_LS_Q_SATURATION_LENGTHS Fs / sigma0 */
    if (ss_abs64(u) > l_sat) {
        st->x0_q40 = (int32_t)ss_times_sign_of(-l_sat, u);
        st->x_q40 = 0;
    }
}

void ss_ls_advance_q(const ss_friction_config_q_t *cfg, ss_ls_state_q_t *st, int32_t dx_q40,
                     int32_t inv_dt_q47)
{
    if (inv_dt_q47 <= 0) {
        return;
    }
    const int32_t fm_old = st->fm_q24;
    const int64_t gate_old = gate_of_fm_q30(cfg, st);
    if (dx_q40 != 0) {
        const int8_t d = (dx_q40 > 0) ? (int8_t)1 : (int8_t)-1;
        if (st->dir != 0 && d != st->dir) {
            push_reversal(st);
        }
        st->dir = d;
        st->x_q40 = ss_sat32((int64_t)st->x_q40 + dx_q40);
        close_loops(st);
        eval_branch(cfg, st);
        rebase(cfg, st);
        st->gate_q30 = (int32_t)breakaway_gate_q30(cfg, st->fm_q24);
    }
    /* elastic-plastic split: dF_M / sigma0 in m at 2^-40 is dF_M [2^-24 N] times 1/sigma0 [m/N at
     * 2^-47], to 2^-40; |dF_M| <= 2 Fs < 2^30: the product fits */
    int64_t slip = dx_q40 - ss_shr_round(ss_mul_i64_i32((int64_t)st->fm_q24 - fm_old, cfg->inv_sigma0_q47),
                                         47 - SS_QF_F_OVER_K);
    if ((slip > 0 && dx_q40 < 0) || (slip < 0 && dx_q40 > 0)) {
        slip = 0; /* rounding only: the tangent stiffness never exceeds sigma0 */
    }
    /* the gate's mean over the step, as the float step (ss_ls_friction_f32.c) */
    const int64_t gate = ss_shr_round(gate_old + st->gate_q30, 1);
    slip = ss_shr_round(ss_mul_i64_i32(slip, (int32_t)gate), 30); /* gate in [0, 2^30] */
    if (slip == 0) {
        return; /* no gross slip: the level keeps its value (exp(0) = 1) */
    }
    /* LuGre in the slip, exact for a slip velocity frozen over the step (decay in [0, 2^30]) */
    const int32_t v_slip = ss_velocity_q28(slip, inv_dt_q47);
    const int64_t g = ss_stribeck_q(cfg, v_slip);
    const int64_t decay = ss_exp_neg_q32_q30(exponent_q32(cfg, slip, g));
    st->level_q24 =
        (int32_t)(g + ss_shr_round(ss_mul_i64_i32((int64_t)st->level_q24 - g, (int32_t)decay), 30));
}

int32_t ss_ls_step_q(const ss_friction_config_q_t *cfg, ss_ls_state_q_t *st, int32_t dx_q40, int32_t dt_q40)
{
    const int32_t inv_dt = ss_inv_dt_q47(dt_q40);
    if (inv_dt == 0) {
        return st->force_q24;
    }
    ss_ls_advance_q(cfg, st, dx_q40, inv_dt);
    const int32_t v = ss_velocity_q28(dx_q40, inv_dt);
    st->force_q24 = ss_ls_force_at_q(cfg, st, v, NULL);
    return st->force_q24;
}

int32_t ss_ls_force_at_q(const ss_friction_config_q_t *cfg, const ss_ls_state_q_t *st, int32_t v_q28,
                         ss_friction_slopes_q_t *slopes)
{
    int32_t *dfdv_q16 = (slopes != NULL) ? &slopes->dfdv_q16 : NULL;
    /* gross-slip share of v: (1 - kt/sigma0) alpha, Q30 */
    const int64_t share = ss_shr_round(
        ss_mul_i64_i32(SS_Q30_ONE - (int64_t)st->kt_q30, (st->gate_fs_q24 == cfg->fs_q24)
                                                             ? st->gate_q30
                                                             : (int32_t)breakaway_gate_q30(cfg, st->fm_q24)),
        30);
    /* dz/dt and the micro-damping's part of dF/dv; both 0 without gross slip (share 0: presliding
     * and sticking, most steps), where the Stribeck level and its reciprocal are then not needed:
     * the same bits without them */
    int64_t zdot = 0;
    int64_t damping = 0;
    if (share != 0) {
        const int32_t vp =
            (int32_t)ss_shr_round(ss_mul_s32_s64(v_q28, (int32_t)share), 30); /* share in [0, 2^30] */
        int32_t slope = 0;
        const int64_t g =
            (dfdv_q16 != NULL) ? ss_stribeck_with_slope_q(cfg, vp, &slope) : ss_stribeck_q(cfg, vp);
        /* 1/g = m 2^-sh, once for both quotients by g: g in [Fc, Fs] within (2^11, 2^29], so sh in
         * [42, 60] */
        int sh = 0;
        const int32_t m = ss_stribeck_recip_q(cfg, g, &sh);
        const int64_t ratio = ss_mul_recip_q(st->level_q24, m, sh - 30); /* s / g, Q30 */
        const int64_t one_m = SS_Q30_ONE - ratio;
        zdot = ss_shr_round(ss_mul_i64_i32(one_m, vp), 30); /* m/s at 2^-28 */
        if (dfdv_q16 != NULL) {
            /* d(dz/dt)/dvp = (1 - s/g) + vp s g' / g^2; vp g' / g is a pure number at 2^-20, from vp
             * g' rounded to 2^-24 N (|vp g'| <= 0.74 (Fs - Fc) < 2^29 there: the product with m
             * fits) */
            const int64_t vg =
                ss_mul_recip_q(ss_sat32(ss_shr_round(ss_mul_s32_s64(vp, slope), 20)), m, sh - 20);
            const int64_t dzdvp = one_m + ss_shr_round(ss_mul_i64(ratio, vg), 20);
            const int64_t s1 = ss_shr_round(ss_mul_s32_s64(cfg->sigma1_q16, (int32_t)share), 30);
            damping = ss_shr_round(ss_mul_i64(s1, dzdvp), 30);
        }
    }
    /* s / Fs in Q30 (level <= Fs: at most 2^30), once for the force and the stiffness */
    const int32_t level_share = (int32_t)ss_shr_round(ss_mul_s32_s64(st->level_q24, cfg->inv_fs_q48), 18);
    if (slopes != NULL) {
        slopes->dfdv_q16 = ss_sat32(ss_asymmetric_inline_q(cfg, damping, st->fm_q24) + cfg->sigma2_q16);
        /* the contact's stiffness over sigma0: (s / Fs) kt / sigma0, Q30 */
        slopes->dfdx_q30 = ss_sat32(ss_asymmetric_inline_q(
            cfg, ss_shr_round(ss_mul_s32_s64(level_share, st->kt_q30), 30), st->fm_q24));
    }
    /* (s / Fs) F_M + sigma1 dz/dt (the contact, asymmetric by the sign of F_M) + sigma2 v; Q16 N s/m
     * times 2^-28 m/s is N at 2^-44 */
    const int64_t contact = ss_shr_round(ss_mul_s32_s64(level_share, st->fm_q24), 30) +
                            ss_shr_round(ss_mul_i64_i32(zdot, cfg->sigma1_q16), 20);
    return ss_sat32(ss_asymmetric_inline_q(cfg, contact, st->fm_q24) +
                    ss_shr_round(ss_mul_s32_s64(cfg->sigma2_q16, v_q28), 20));
}

ss_status_t ss_ls_run_q(const ss_friction_config_q_t *cfg, ss_ls_state_q_t *st, const int32_t *dx_q40,
                        uint32_t n, int32_t dt_q40, int32_t *force_q24)
{
    if (cfg == NULL || st == NULL || (n > 0u && (dx_q40 == NULL || force_q24 == NULL))) {
        return SS_ERR_NULL;
    }
    if (ss_inv_dt_q47(dt_q40) == 0) {
        return SS_ERR_RANGE;
    }
    for (uint32_t i = 0; i < n; ++i) {
        force_q24[i] = ss_ls_step_q(cfg, st, dx_q40[i], dt_q40);
    }
    return SS_OK;
}
