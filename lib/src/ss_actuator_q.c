#include "ss_actuator_q.h"

#include <stddef.h>

#include "ss_fixed_ops.h"
#include "ss_inline.h"

/* 0.1 in Q30, the float family's floor on the implicit-damping denominator. */
#define SS_ACT_Q_DENOM_MIN_Q30 107374182

ss_actuator_config_q_t ss_actuator_config_table1_q(void)
{
    /* ss_actuator_config_to_q(ss_actuator_config_table1_f32()), rounded in double on the host */
    ss_actuator_config_q_t cfg;
    cfg.dt_q40 = 1099512;          /* 1 us (1.00000034 us) */
    cfg.inv_dt_q47 = 127999957;    /* 2^47 / 1099512 */
    cfg.piezo_gain_q48 = 12384899; /* 44 nm/V */
    cfg.friction_model = SS_FRICTION_Q_LS;
    cfg.lag_q24 = 500090;           /* 6.2 / (2.08e8 x 1 us) = 0.0298 */
    cfg.kick_rod_q40 = 499778185;   /* 1 us / (2 x 1.1 g) */
    cfg.kick_slider_q40 = 39837392; /* 1 us / (2 x 13.8 g) */
    cfg.phi_q28[0] = 243500213;     /* 69.2 kHz rod mode, damping ratio 0.0065, over 1 us */
    cfg.phi_q28[1] = 259323787;
    cfg.phi_q28[2] = -49035804;
    cfg.phi_q28[3] = 242038569;
    cfg.friction = ss_friction_config_table1_q();
    cfg.effects = ss_effects_config_none_q();
    cfg.contact_lag_q30 = 813441; /* 1e7 N/m x (1 us)^2 / (12 x 1.1 g) = 7.6e-4 */
    cfg.rod_w2dt2_q28 = 50758739; /* 2.08e8 N/m x (1 us)^2 / 1.1 g = 0.189 */
    return cfg;
}

int32_t ss_actuator_inv_dt_q47(int32_t dt_q40)
{
    return ss_inv_dt_q47(dt_q40);
}

ss_status_t ss_actuator_config_check_q(const ss_actuator_config_q_t *cfg, const char **bad_field)
{
    const char *dummy = "";
    const char **bad = (bad_field != NULL) ? bad_field : &dummy;
    *bad = "";
    if (cfg == NULL) {
        *bad = "config";
        return SS_ERR_NULL;
    }
    if (cfg->dt_q40 <= SS_Q_DT_MIN_Q40) {
        *bad = "dt_q40";
    } else if (cfg->inv_dt_q47 != ss_actuator_inv_dt_q47(cfg->dt_q40)) {
        *bad = "inv_dt_q47"; /* not 2^47 / dt_q40 */
    } else if (cfg->piezo_gain_q48 == 0) {
        *bad = "piezo_gain_q48";
    } else if (cfg->friction_model != SS_FRICTION_Q_LS && cfg->friction_model != SS_FRICTION_Q_LUGRE) {
        *bad = "friction_model";
    } else if (cfg->lag_q24 < 0) {
        *bad = "lag_q24";
    } else if (cfg->kick_rod_q40 == 0u) {
        *bad = "kick_rod_q40";
    } else if (cfg->kick_slider_q40 <= 0) {
        *bad = "kick_slider_q40";
    } else if (cfg->contact_lag_q30 < 0) {
        *bad = "contact_lag_q30";
    } else if (cfg->rod_w2dt2_q28 < 0 || cfg->rod_w2dt2_q28 > ((int32_t)1 << SS_QF_FLOW)) {
        *bad = "rod_w2dt2_q28"; /* beyond 1 the corner's series does not hold */
    } else if (cfg->effects.load_q24 < -SS_Q_LOAD_MAX_Q24 || cfg->effects.load_q24 > SS_Q_LOAD_MAX_Q24) {
        *bad = "effects.load_q24";
    } else if (cfg->effects.slew_q24 < 0 || cfg->effects.slew_q24 > SS_Q_SLEW_MAX_Q24) {
        *bad = "effects.slew_q24";
    } else if (cfg->effects.sensor_scale_q30 < -(SS_Q30_ONE / 2) ||
               cfg->effects.sensor_scale_q30 > SS_Q30_ONE / 2) {
        *bad = "effects.sensor_scale_q30";
    } else if (cfg->effects.hysteresis_alpha_q30 < 0 ||
               cfg->effects.hysteresis_alpha_q30 > SS_Q_HYSTERESIS_ALPHA_MAX_Q30) {
        *bad = "effects.hysteresis_alpha_q30";
    } else if (cfg->effects.hysteresis_alpha_q30 != 0 &&
               cfg->effects.hysteresis_width_q40 < SS_Q_HYSTERESIS_WIDTH_MIN_Q40) {
        *bad = "effects.hysteresis_width_q40";
    } else if (cfg->effects.hysteresis_alpha_q30 != 0 &&
               ss_abs64(cfg->effects.hysteresis_inv_width_q48 * cfg->effects.hysteresis_width_q40 -
                        ((int64_t)1 << 48)) > cfg->effects.hysteresis_width_q40) {
        *bad = "effects.hysteresis_inv_width_q48"; /* not 2^48 / width */
    } else if (cfg->effects.base_kick_q40 < 0) {
        *bad = "effects.base_kick_q40";
    } else if (cfg->effects.base_kick_q40 != 0 &&
               (cfg->effects.base_stiffness_n_per_m < 0 || cfg->effects.base_damping_q16 < 0 ||
                cfg->effects.piezo_stiffness_n_per_m <= 0 || cfg->effects.piezo_damping_q16 < 0)) {
        *bad = "effects.base_stiffness_n_per_m"; /* a base needs its spring and the piezo's */
    } else {
        return ss_friction_config_check_named_q(&cfg->friction, 1, bad);
    }
    return SS_ERR_RANGE;
}

/* Ideal strain of a drive voltage: m/V at 2^-48 times V at 2^-16 is m at 2^-64. */
static int32_t strain_q40(const ss_actuator_config_q_t *cfg, int32_t drive_q16)
{
    return ss_sat32(ss_shr_round(ss_mul_s32_s64(cfg->piezo_gain_q48, drive_q16), 24));
}

ss_status_t ss_actuator_init_q(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                               int32_t drive0_q16)
{
    if (cfg == NULL || st == NULL) {
        return SS_ERR_NULL;
    }
    ss_status_t status = ss_actuator_config_check_q(cfg, NULL);
    if (status != SS_OK) {
        return status;
    }
    if (cfg->friction_model == SS_FRICTION_Q_LUGRE) {
        status = ss_lugre_init_q(&cfg->friction, &st->fr.lugre);
    } else {
        status = ss_ls_init_q(&cfg->friction, &st->fr.ls);
    }
    if (status != SS_OK) {
        return status;
    }
    st->drive_q16 = drive0_q16;
    st->amp_q24 = (int64_t)drive0_q16 * 256;
    st->x_p_q40 = strain_q40(cfg, drive0_q16);
    st->strain_q40 = st->x_p_q40; /* virgin hysteresis: h = 0 */
    st->hysteresis_q40 = 0;
    st->x_rod_q40 = st->x_p_q40; /* static equilibrium: no friction at the virgin state */
    st->v_rod_q28 = 0;
    st->x_slider_q40 = 0;
    st->v_slider_q28 = 0;
    st->force_q24 = 0;
    st->steps = 0u;
    st->pad = 0u;
    st->x_base_q40 = 0;
    st->v_base_q28 = 0;
    return SS_OK;
}

/* The slider's velocity after half a step of force_q24 and the load on it: N at 2^-24 times
 * (m/s)/N at 2^-40 is m/s at 2^-64. */
SS_FORCE_INLINE int64_t slider_dv_q28(const ss_actuator_config_q_t *cfg, int64_t force_q24)
{
    return ss_shr_round(ss_mul_i64_i32(force_q24, cfg->kick_slider_q40), 36);
}

SS_FORCE_INLINE int32_t slider_kicked_q28(const ss_actuator_config_q_t *cfg, const ss_actuator_state_q_t *st,
                                          int32_t force_q24)
{
    return ss_sat32(st->v_slider_q28 + slider_dv_q28(cfg, (int64_t)force_q24 + cfg->effects.load_q24));
}

/* The rod's velocity after half a step of force_q24 on it, the other way (a coarse step's kick_rod
 * reaches past int32: ss_mul_s32_u32_s64). */
SS_FORCE_INLINE int32_t rod_kicked_q28(const ss_actuator_config_q_t *cfg, const ss_actuator_state_q_t *st,
                                       int32_t force_q24)
{
    return ss_sat32(st->v_rod_q28 - ss_shr_round(ss_mul_s32_u32_s64(force_q24, cfg->kick_rod_q40), 36));
}

/* Half a step of the friction force on both bodies and of the load on the slider. */
static void kick(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st)
{
    st->v_rod_q28 = rod_kicked_q28(cfg, st, st->force_q24);
    st->v_slider_q28 = slider_kicked_q28(cfg, st, st->force_q24);
    const ss_effects_config_q_t *e = &cfg->effects;
    if (e->base_kick_q40 != 0) {
        /* the base's spring-damper, and the stack pushing it with -F_p (it pushes the rod with F_p):
         * its spring on the stack's elastic length, its damper on the stack's length rate, as on the
         * rod (the drift's lag). N/m times m at 2^-40 is N at 2^-40, Q16 N s/m times m/s at 2^-28
         * is N at 2^-44 */
        const int64_t f_piezo =
            ss_shr_round((int64_t)e->piezo_stiffness_n_per_m *
                             ((int64_t)st->x_p_q40 + st->x_base_q40 - st->x_rod_q40),
                         16) +
            ss_shr_round((int64_t)e->piezo_damping_q16 * ((int64_t)st->v_base_q28 - st->v_rod_q28), 20);
        const int64_t f_base = -ss_shr_round((int64_t)e->base_stiffness_n_per_m * st->x_base_q40, 16) -
                               ss_shr_round((int64_t)e->base_damping_q16 * st->v_base_q28, 20) - f_piezo;
        st->v_base_q28 = ss_sat32(
            st->v_base_q28 + ss_shr_round(ss_clamp64(f_base, -INT32_MAX, INT32_MAX) * e->base_kick_q40, 36));
    }
}

/* The amplifier: the piezo voltage follows the drive at most slew_q24 per step (slew: what is left
 * of it after a corner inside the step). The strain is taken from it rounded to Q16.16, the drive's
 * own grid (0.7 fm at 44 nm/V). Without a limit the voltage is the drive and the strain the base
 * model's, bit for bit. */
SS_FORCE_INLINE int32_t ideal_strain_q40(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                                         int32_t drive_q16, int64_t slew)
{
    const int64_t target = (int64_t)drive_q16 * 256;
    if (cfg->effects.slew_q24 == 0) {
        st->amp_q24 = target;
        return strain_q40(cfg, drive_q16);
    }
    st->amp_q24 += ss_clamp64(target - st->amp_q24, -slew, slew);
    return strain_q40(cfg, ss_sat32(ss_shr_round(st->amp_q24, 8)));
}

/* The piezo strain at ideal strain u: u less the Bouc-Wen hysteresis h, which relaxes over a
 * monotone du to sgn(du) alpha width over the strain distance width (the float family's exact
 * solution, h_inf + (h - h_inf) exp(-|du| / width)). */
static int32_t hysteresis_strain_q40(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st, int32_t u)
{
    const ss_effects_config_q_t *e = &cfg->effects;
    const int64_t du = (int64_t)u - st->strain_q40;
    const int64_t adu = ss_abs64(du);
    const int64_t width = e->hysteresis_width_q40;
    const int64_t h_inf = ss_times_sign_of(ss_shr_round((int64_t)e->hysteresis_alpha_q30 * width, 30), du);
    /* |du| / width in Q32 from the reciprocal; beyond 24 widths exp(-x) is below 2^-34: 0 */
    const int64_t decay =
        (adu >= 24 * width)
            ? 0
            : ss_exp_neg_q32_q30((uint64_t)ss_shr_round(adu * e->hysteresis_inv_width_q48, 16));
    st->hysteresis_q40 = ss_sat32(h_inf + ss_shr_round(((int64_t)st->hysteresis_q40 - h_inf) * decay, 30));
    st->strain_q40 = u;
    return ss_sat32((int64_t)u - st->hysteresis_q40);
}

/* The piezo strain at ideal strain u, with or without the hysteresis (h stays 0 without) */
SS_FORCE_INLINE int32_t piezo_at_q40(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st, int32_t u)
{
    if (cfg->effects.hysteresis_alpha_q30 == 0) {
        st->strain_q40 = u;
        return u;
    }
    return hysteresis_strain_q40(cfg, st, u);
}

/* The piezo strain at the end of the step (slew: the amplifier's allowance for it) */
SS_FORCE_INLINE int32_t piezo_strain_q40(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                                         int32_t drive_q16, int64_t slew)
{
    return piezo_at_q40(cfg, st, ideal_strain_q40(cfg, st, drive_q16, slew));
}

/* num / den in Q30, 0 <= num <= den < 2^31, den > 0: by den's reciprocal, no division */
SS_FORCE_INLINE int64_t share_q30(int64_t num, int64_t den)
{
    int sh = 0;
    const int32_t m = ss_reciprocal_mantissa_q((uint32_t)den, &sh);
    return ss_mul_recip_q((int32_t)num, m, sh - 30);
}

/* LS's advance over a step whose relative motion turned inside it, from v0 (the step's start) to
 * v1 (its end, the closing kick estimated), signs opposite: up to the turning point, then back,
 * each piece over its own time (as the float step, ss_actuator_f32.c: the velocity linear in
 * between). The turning time's fraction and the pieces' 1/dt by reciprocals
 * (ss_reciprocal_mantissa_q): no division. Out of line: a minority of steps take it, and inline it
 * grew the step by 1 KB on the Cortex-M3. Where float and q differ: |v0| + |v1| from 8 m/s (no
 * turn taken), and a piece shorter than 0.06 us, the format's shortest step, whose 1/dt saturates
 * (its slip's velocity understated; it slips at most its own excursion). */
SS_NOINLINE void ls_advance_turning(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                                    int32_t dx_rel, int64_t v0, int64_t v1)
{
    const int64_t dv = ss_abs64(v0 - v1); /* |v0| + |v1| */
    /* |v0| / (|v0| + |v1|) in Q30 */
    const int64_t frac = (dv > 0 && dv < INT32_MAX) ? share_q30(ss_abs64(v0), dv) : 0;
    if (frac <= 0 || frac >= SS_Q30_ONE) {
        ss_ls_advance_q(&cfg->friction, &st->fr.ls, dx_rel, cfg->inv_dt_q47);
        return;
    }
    /* the excursion to the turn: v0 frac dt / 2; v0 dt in m at 2^-40 saturates at 2^31 (2 mm: 2 m/s
     * over the longest step), so the product with frac stays within 64 bits */
    const int32_t v0_dt = ss_sat32(ss_shr_round(ss_mul_i64_i32(v0, cfg->dt_q40), 28));
    const int32_t turn = ss_sat32(ss_shr_round(ss_mul_s32_s64(v0_dt, (int32_t)frac), 31));
    int sh1 = 0;
    int sh2 = 0;
    const int32_t m1 = ss_reciprocal_mantissa_q((uint32_t)frac, &sh1);
    const int32_t m2 = ss_reciprocal_mantissa_q((uint32_t)(SS_Q30_ONE - frac), &sh2);
    /* 1 / (frac dt) and 1 / ((1 - frac) dt): inv_dt 2^30 / frac */
    if (turn != 0) {
        ss_ls_advance_q(&cfg->friction, &st->fr.ls, turn,
                        ss_sat32(ss_mul_recip_q(cfg->inv_dt_q47, m1, sh1 - 30)));
    }
    ss_ls_advance_q(&cfg->friction, &st->fr.ls, ss_sat32((int64_t)dx_rel - turn),
                    ss_sat32(ss_mul_recip_q(cfg->inv_dt_q47, m2, sh2 - 30)));
}

/* 1/6, 1/24 and 1/120 in Q30, rounded: the corner's series multiplies by them */
#define SS_ACT_Q_SIXTH_Q30 178956971
#define SS_ACT_Q_24TH_Q30 44739243
#define SS_ACT_Q_120TH_Q30 8947849

/* The rod's response at the step's end to a drive that bends inside it: the anchor less its chord
 * is a triangle of height h at the corner, f of the step in (f' = 1 - f). By the rod's impulse
 * response to second order in W = (w dt)^2, M x'' = k (d - x) from rest, the triangle's moments:
 *   dx = W h [(1 + f') / 6 - W (1 + f' + f'^2 + f'^3) / 120],
 *   dv = (W h / dt) [1 / 2 - W (1 + f' + f'^2) / 24],
 * within 0.3 % of the exact damped flow for Table I's rod up to 2 us (the damping's share; the
 * float family takes the flow over each piece, ss_actuator_f32.c). h is the piezo strain's, slew
 * limit and hysteresis taken in the step's two pieces. W <= 1 (the config check), so |W h| <= |h|. */
SS_NOINLINE void corner_response(const ss_actuator_config_q_t *cfg, int32_t h_q40, int32_t frac_q30,
                                 int64_t *dx_q40, int64_t *dv_q28)
{
    const int64_t w2 = cfg->rod_w2dt2_q28;
    const int64_t g = SS_Q30_ONE - (int64_t)frac_q30; /* f' in Q30 */
    const int64_t g2 = ss_shr_round(g * g, 30);
    const int64_t g3 = ss_shr_round(g2 * g, 30);
    const int64_t s2 = SS_Q30_ONE + g + g2; /* Q30, < 3 x 2^30: times W within 2^60 */
    const int64_t p1 = ss_shr_round((SS_Q30_ONE + g) * SS_ACT_Q_SIXTH_Q30, 30) -
                       ss_shr_round(ss_shr_round(w2 * (s2 + g3), 28) * SS_ACT_Q_120TH_Q30, 30);
    const int64_t p0 = SS_Q30_ONE / 2 - ss_shr_round(ss_shr_round(w2 * s2, 28) * SS_ACT_Q_24TH_Q30, 30);
    const int64_t hw = ss_shr_round((int64_t)h_q40 * w2, 28); /* m at 2^-40, |hw| <= |h| */
    *dx_q40 = ss_shr_round(hw * p1, 30);
    /* m at 2^-40 times 1/s at 2^-7 is m/s at 2^-47 */
    *dv_q28 =
        ss_shr_round(ss_mul_s32_s64((int32_t)ss_shr_round(hw * p0, 30), cfg->inv_dt_q47), 47 - SS_QF_DXDT);
}

/* The slider flow's series holds below x = 0.1 (SS_COARSE_FLOW_X_MAX of the float family), in Q30,
 * and with one more term below 0.4 (SS_COARSE_FLOW_X_LONG_MAX) */
#define SS_ACT_Q_FLOW_X_MAX_Q30 (SS_Q30_ONE / 10)
#define SS_ACT_Q_FLOW_X_LONG_MAX_Q30 429496730

/* 1/42 and 1/56 in Q30, rounded: the longer series' last factors */
#define SS_ACT_Q_42ND_Q30 25565282
#define SS_ACT_Q_56TH_Q30 19173962

/* 1/12, 1/20 and 1/30 in Q30, rounded: the slider flow's series (with SS_ACT_Q_SIXTH_Q30) */
#define SS_ACT_Q_12TH_Q30 89478485
#define SS_ACT_Q_20TH_Q30 53687091
#define SS_ACT_Q_30TH_Q30 35791394

/* LS's contact stiffness for a coarse step, N/m: sigma0 times its dF/dx over sigma0 as
 * ss_ls_force_at_q gives it (the Masing branch's tangent kt_q30 times the level's share of Fs, and
 * the asymmetry: at most 1.9 sigma0) */
SS_FORCE_INLINE int32_t ls_stiffness(const ss_actuator_config_q_t *cfg, const ss_actuator_state_q_t *st)
{
    const ss_friction_config_q_t *f = &cfg->friction;
    const int32_t level_share = (int32_t)ss_shr_round(ss_mul_s32_s64(st->fr.ls.level_q24, f->inv_fs_q48), 18);
    const int64_t k30 = ss_asymmetric_inline_q(
        f, ss_shr_round(ss_mul_s32_s64(level_share, st->fr.ls.kt_q30), 30), st->fr.ls.fm_q24);
    return ss_sat32(ss_shr_round(ss_mul_s32_s64(f->sigma0_n_per_m, ss_sat32(k30)), 30));
}

/* The force of stiffness kt (N/m) over dx (m at 2^-40): N at 2^-24 */
SS_FORCE_INLINE int64_t contact_q24(int32_t kt, int32_t dx_q40)
{
    return ss_shr_round(ss_mul_s32_s64(dx_q40, kt), 16);
}

/* 1 - a (1 - b) in Q30 for a, b in [0, 2^30]: the series' nested form */
SS_FORCE_INLINE int64_t one_less_q30(int64_t a, int64_t b)
{
    return SS_Q30_ONE - ss_shr_round(ss_mul_s32_s64((int32_t)a, (int32_t)(SS_Q30_ONE - b)), 30);
}

/* x * c in Q30, x and c in Q30 */
SS_FORCE_INLINE int64_t times_q30(int64_t x, int64_t c)
{
    return ss_shr_round(ss_mul_s32_s64((int32_t)x, (int32_t)c), 30);
}

/* The slider flow's three series with one more term, for 0.1 <= x < 0.4 (a split step's longer
 * reach; the float family's slider_flow): cos = 1 - x/2 (1 - x/12 (1 - x/30)), sin / (om dt) = 1 -
 * x/6 (1 - x/20 (1 - x/42)), 2 (1 - cos) / (om dt)^2 = 1 - x/12 (1 - x/30 (1 - x/56)), in Q30. Out
 * of line: Table I's steps stay below 0.1. */
SS_NOINLINE void long_series_q30(int32_t x, int64_t *cos_x, int64_t *sin_over, int64_t *one_less)
{
    const int64_t x12 = times_q30(x, SS_ACT_Q_12TH_Q30);
    const int64_t x30 = times_q30(x, SS_ACT_Q_30TH_Q30);
    *cos_x = one_less_q30(x / 2, times_q30(x12, SS_Q30_ONE - x30));
    *sin_over = one_less_q30(
        times_q30(x, SS_ACT_Q_SIXTH_Q30),
        times_q30(times_q30(x, SS_ACT_Q_20TH_Q30), SS_Q30_ONE - times_q30(x, SS_ACT_Q_42ND_Q30)));
    *one_less = one_less_q30(x12, times_q30(x30, SS_Q30_ONE - times_q30(x, SS_ACT_Q_56TH_Q30)));
}

/* LS's slider in a coarse step, as the float family's slider_flow (ss_actuator_f32.c): its exact
 * flow on the contact's stiffness kt (N/m), whose other end rides on the rod (dx_rod over dt),
 * under the force F0 + load (dv_half: its half kick, m/s at 2^-28), from v_s0 (m/s at 2^-28): the
 * slider's travel u (m at 2^-40) and end velocity ud (m/s at 2^-28). x = kt dt^2 / M_C in Q30: kt
 * dt rounded to N s/m at 2^-16 (saturated: past 32 768 N s/m x is far beyond the series' 0.1), times
 * 2 dt / (2 M_C) (kick_slider_q40); past x = 0.1 (and at 0) the kick-drift-kick's: the series' terms
 * at x = 0, and the closing kick of the linear contact's force at u. */
SS_FORCE_INLINE void slider_flow_q(const ss_actuator_config_q_t *cfg, int32_t kt, int32_t dx_rod,
                                   int64_t dv_half, int64_t v_s0, int32_t *u_q40, int32_t *ud_q28)
{
    const int32_t kt_dt = ss_sat32(ss_shr_round(ss_mul_s32_s64(kt, cfg->dt_q40), 24));
    const int64_t x = ss_shr_round(ss_mul_s32_s64(kt_dt, cfg->kick_slider_q40), 25);
    int64_t cos_x = SS_Q30_ONE;    /* cos(om dt), om^2 = kt / M_C */
    int64_t sin_over = SS_Q30_ONE; /* sin(om dt) / (om dt) */
    int64_t one_less = SS_Q30_ONE; /* 2 (1 - cos(om dt)) / (om dt)^2 */
    const int series = x > 0 && x < SS_ACT_Q_FLOW_X_LONG_MAX_Q30;
    if (series && x < SS_ACT_Q_FLOW_X_MAX_Q30) { /* x and every factor below 2^31: 32 x 32 -> 64 products */
        const int32_t x32 = (int32_t)x;
        const int64_t x12 = ss_shr_round(ss_mul_s32_s64(x32, SS_ACT_Q_12TH_Q30), 30);
        cos_x = one_less_q30(x / 2, x12);
        sin_over = one_less_q30(ss_shr_round(ss_mul_s32_s64(x32, SS_ACT_Q_SIXTH_Q30), 30),
                                ss_shr_round(ss_mul_s32_s64(x32, SS_ACT_Q_20TH_Q30), 30));
        one_less = one_less_q30(x12, ss_shr_round(ss_mul_s32_s64(x32, SS_ACT_Q_30TH_Q30), 30));
    } else if (series) { /* a split step's longer reach */
        long_series_q30((int32_t)x, &cos_x, &sin_over, &one_less);
    }
    const int64_t w = ss_velocity_q28(dx_rod, cfg->inv_dt_q47);
    const int32_t dv = (int32_t)ss_clamp64(v_s0 - w, -INT32_MAX, INT32_MAX);
    const int32_t h = (int32_t)ss_clamp64(dv_half, -INT32_MAX / 2, INT32_MAX / 2);
    /* m/s at 2^-28 times s at 2^-40 is m at 2^-68 */
    const int32_t dv_dt = ss_sat32(ss_shr_round(ss_mul_s32_s64(dv, cfg->dt_q40), 28));
    const int32_t h_dt = ss_sat32(ss_shr_round(ss_mul_s32_s64(h, cfg->dt_q40), 28));
    *u_q40 = ss_sat32(ss_shr_round(ss_mul_s32_s64(h_dt, (int32_t)one_less), 30) + dx_rod +
                      ss_shr_round(ss_mul_s32_s64(dv_dt, (int32_t)sin_over), 30));
    int64_t ud = ss_shr_round(ss_mul_s32_s64(2 * h, (int32_t)sin_over), 30) + w +
                 ss_shr_round(ss_mul_s32_s64(dv, (int32_t)cos_x), 30);
    if (!series) { /* the kick-drift-kick: the closing kick's linear contact */
        const int32_t f = ss_sat32(contact_q24(kt, ss_sat32((int64_t)dx_rod - *u_q40)));
        ud += slider_dv_q28(cfg, f);
    }
    *ud_q28 = ss_sat32(ud);
}

/* The rod's free flow over the config's step (phi_q28): e1 = phi00 e0 + (phi01 / dt) (e0' dt), e1' =
 * (phi10 dt) e0 / dt + phi11 e0', for e0 (m at 2^-40) and e0' (m/s at 2^-28) within 32 bits: every
 * product of two 32-bit values (w, e0' dt's velocity, saturated to 32 bits too) */
SS_FORCE_INLINE void rod_free_flow_q(const ss_actuator_config_q_t *cfg, int64_t e0, int64_t ed0, int64_t *e1,
                                     int64_t *ed1)
{
    const int32_t *phi = cfg->phi_q28;
    const int64_t w = ss_sat32(ss_shr_round(ss_mul_i64_i32(ed0, phi[1]), 28)); /* m/s at 2^-28 */
    *e1 = ss_shr_round(ss_mul_i64_i32(e0, phi[0]), 28) + ss_shr_round(ss_mul_i64_i32(w, cfg->dt_q40), 28);
    *ed1 = ss_mul_shr_round_wide(ss_mul_i64_i32(e0, phi[2]), cfg->inv_dt_q47, 47) +
           ss_shr_round(ss_mul_i64_i32(ed0, phi[3]), 28);
}

/* The step's force F_free / denom (denom in Q30, the implicit damping's 1 + g): by denom's reciprocal
 * m 2^-sh where denom is in (0.1 x 2^30, 2^31) (sh in [57, 61], F_free m / 2^(sh - 30) one product),
 * by a division above (damping past the masses' dt/2: g >= 1), and F_free itself below the bound
 * (as the float takes it) */
SS_FORCE_INLINE int32_t over_denom_q24(int32_t f_free, int64_t denom)
{
    if (denom > SS_ACT_Q_DENOM_MIN_Q30 && denom <= INT32_MAX) {
        int sh = 0;
        const int32_t m = ss_reciprocal_mantissa_q((uint32_t)denom, &sh);
        return ss_sat32(ss_mul_recip_q(f_free, m, sh - 30));
    }
    if (denom > SS_ACT_Q_DENOM_MIN_Q30) {
        return ss_sat32(ss_div_round((int64_t)f_free * SS_Q30_ONE, denom));
    }
    return f_free;
}

/* A step (ss_actuator_step_q), with the drive bending at corner_frac_q30 of it to corner_q16 when
 * corner_frac_q30 > 0 (ss_actuator_step_corner_q). compliance_q56 0: the fine step, which kicks the
 * rod with the friction at both ends. Else a coarse step (no corner, no base) in the float family's
 * held form (ss_actuator_f32.c, coarse_step_over): the force it starts with held in the rod's flow,
 * its anchor shifted by the static deflection F0 / k (1 / k, the stack's compliance, m/N at 2^-56),
 * only the force's change kicked onto the rod at the end; with ls_model, LS's form of it (the
 * anchor ramping to f_rod's deflection, the slider's flow on the contact, F1 about f_ref). */
SS_FORCE_INLINE ss_status_t step_held(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                                      int32_t drive_q16, int32_t corner_frac_q30, int32_t corner_q16,
                                      int32_t compliance_q56, int ls_model)
{
    if (cfg == NULL || st == NULL) {
        return SS_ERR_NULL;
    }
    if (cfg->inv_dt_q47 <= 0) {
        return SS_ERR_RANGE; /* cfg did not pass init */
    }
    const int64_t dt = cfg->dt_q40;
    /* a corner inside the step: the piezo voltage there (through the slew limit, which then has the
     * rest of the step for the rest of the way), and the strain, the hysteresis taken to it: the
     * drive turns there, and over the chord the hysteresis would miss the turn */
    const int corner = corner_frac_q30 > 0 && cfg->rod_w2dt2_q28 != 0;
    const int32_t x_p0 = st->x_p_q40;
    int32_t x_pc = 0;
    int64_t slew = cfg->effects.slew_q24;
    if (corner) {
        const int64_t slew_1 = ss_shr_round(slew * corner_frac_q30, 30); /* 0 without a limit */
        x_pc = piezo_strain_q40(cfg, st, corner_q16, slew_1);
        slew -= slew_1;
    }
    const int64_t v_rel_start = (int64_t)st->v_rod_q28 - st->v_slider_q28;
    const int32_t f0 = st->force_q24;
    /* a coarse step (the float's coarse_step_over): the force ramps in the rod's flow to f_rod =
     * F0 + kt v_rel dt (kt: LS's tangent stiffness, LuGre's bristles); LS's slider takes its exact
     * flow on the contact (slider_flow_q) */
    const int ls_flow = ls_model && compliance_q56 != 0;
    int32_t f_rod = f0;
    int32_t kt = 0;
    if (compliance_q56 != 0) {
        kt = ls_model ? ls_stiffness(cfg, st) : cfg->friction.sigma0_n_per_m;
        const int64_t v_dt = ss_shr_round(ss_mul_s32_s64(ss_sat32(v_rel_start), cfg->dt_q40), 28);
        f_rod = ss_sat32(f0 + contact_q24(kt, ss_sat32(v_dt)));
    }
    if (compliance_q56 == 0) {
        kick(cfg, st);
    } else if (!ls_flow) {
        st->v_slider_q28 = slider_kicked_q28(cfg, st, f0);
    }
    const int64_t kick_dv = v_rel_start - ((int64_t)st->v_rod_q28 - st->v_slider_q28);
    /* the held force's static deflection of the rod, m at 2^-40: N at 2^-24 times m/N at 2^-56; at
     * the step's end, f_rod's */
    const int64_t held = (compliance_q56 == 0) ? 0 : ss_shr_round(ss_mul_s32_s64(f0, compliance_q56), 40);
    const int64_t held1 = (compliance_q56 == 0) ? 0 : ss_shr_round(ss_mul_s32_s64(f_rod, compliance_q56), 40);

    /* drift: exact flow of the rod under an anchor (strain plus base) ramping linearly over the step
     * (rate b); the stack's damper acts on the rod's velocity relative to the base, so its forced
     * response is a(t) - c (b - v_b) / k = a(t) - c x_p' / k, the rest e is free. Intermediates
     * saturate at the formats' ranges (a drive jump beyond 8 m/s of strain rate is not a physical
     * drive). */
    const int32_t x_p1 = piezo_strain_q40(cfg, st, drive_q16, slew);
    /* the anchor a = strain + base (the base drifts at its velocity; 0 without one) */
    const int32_t x_b1 =
        (cfg->effects.base_kick_q40 == 0)
            ? 0
            : ss_sat32((int64_t)st->x_base_q40 + ss_shr_round((int64_t)st->v_base_q28 * dt, 28));
    const int64_t a0 = (int64_t)st->x_p_q40 + st->x_base_q40;
    const int64_t a1 = (int64_t)x_p1 + x_b1;
    const int64_t dxp = ss_sat32((a1 - held1) - (a0 - held));
    /* b = dxp / dt, m/s at 2^-28: m at 2^-40 times 1/s at 2^-7 is m/s at 2^-47 */
    const int64_t b = ss_sat32(ss_shr_round(ss_mul_i64_i32(dxp, cfg->inv_dt_q47), 47 - SS_QF_DXDT));
    /* c (b - v_b) / k, m at 2^-40: from the strain's change (the anchor's, without a base) */
    const int64_t lag = ss_shr_round(
        ss_mul_s32_s64(cfg->lag_q24, ss_sat32((int64_t)x_p1 - st->x_p_q40 - (held1 - held))), SS_QF_LAG);
    const int64_t e0 = ss_sat32((int64_t)st->x_rod_q40 - (a0 - held - lag));
    const int64_t ed0 = ss_sat32((int64_t)st->v_rod_q28 - b);
    int64_t e1 = 0;
    int64_t ed1 = 0;
    rod_free_flow_q(cfg, e0, ed0, &e1, &ed1);
    int64_t dx_corner = 0;
    int64_t dv_corner = 0;
    if (corner) {
        /* the corner's height over the strain's chord */
        const int64_t chord = x_p0 + ss_shr_round(((int64_t)x_p1 - x_p0) * corner_frac_q30, 30);
        corner_response(cfg, ss_sat32(x_pc - chord), corner_frac_q30, &dx_corner, &dv_corner);
    }
    const int32_t x_rod1 = ss_sat32(a1 - held1 - lag + e1 + dx_corner);
    int32_t dx_slider;
    int32_t v_slider_end = st->v_slider_q28; /* after the drift, before the closing kick */
    if (ls_flow) {
        slider_flow_q(cfg, kt, ss_sat32((int64_t)x_rod1 - st->x_rod_q40),
                      slider_dv_q28(cfg, (int64_t)cfg->effects.load_q24 + f0), st->v_slider_q28, &dx_slider,
                      &v_slider_end);
    } else {
        dx_slider = ss_sat32(ss_shr_round(ss_mul_s32_s64(st->v_slider_q28, cfg->dt_q40), 28));
    }
    const int32_t dx_rel = ss_sat32((int64_t)x_rod1 - st->x_rod_q40 - dx_slider);
    st->x_rod_q40 = x_rod1;
    st->v_rod_q28 = ss_sat32(b + ed1 + dv_corner);
    st->x_slider_q40 += dx_slider; /* the same increment the friction sees: no drift between them */
    st->v_slider_q28 = v_slider_end;
    st->x_base_q40 = x_b1;
    st->x_p_q40 = x_p1;
    st->drive_q16 = drive_q16;

    /* friction at the new state and the velocity the step ends with, solved for the closing kick
     * (implicit in the damping terms): F = F_free / (1 + dF/dv dt/2 (1/M_R + 1/M_c)); what the
     * closing kicks would be with F1 at its reference (the load's; in a coarse step F1 - f_rod on
     * the rod, and the held slider's F0 + load) is known and taken out of the relative velocity */
    int64_t known_kick = 0;
    /* LS's coarse step: the force its linearised contact ends with, about which F1 is linearised */
    const int32_t f_ref = ls_flow ? ss_sat32(f0 + contact_q24(kt, dx_rel)) : f0;
    if (compliance_q56 != 0) { /* the rod's closing kick were the force to end at f_ref */
        known_kick =
            ss_shr_round(ss_mul_s32_u32_s64(ss_sat32((int64_t)f_ref - f_rod), cfg->kick_rod_q40), 36);
        if (!ls_flow) { /* and the slider's, F0 + load's */
            known_kick += slider_dv_q28(cfg, (int64_t)cfg->effects.load_q24 + f0);
        }
    } else if (cfg->effects.load_q24 != 0) {
        known_kick = ss_shr_round(ss_mul_s32_s64(cfg->effects.load_q24, cfg->kick_slider_q40), 36);
    }
    const int32_t v_free = ss_sat32((int64_t)st->v_rod_q28 - st->v_slider_q28 - known_kick);
    ss_friction_slopes_q_t slopes;
    int32_t f_free;
    if (cfg->friction_model == SS_FRICTION_Q_LUGRE) {
        ss_lugre_advance_q(&cfg->friction, &st->fr.lugre, dx_rel, cfg->inv_dt_q47);
        f_free = ss_lugre_force_at_q(&cfg->friction, &st->fr.lugre, v_free, &slopes);
    } else {
        /* where the relative motion turned inside the drift: LS's Masing memory keeps that point
         * (the float step, ss_actuator_f32.c, says why) */
        const int64_t p1 = (int64_t)st->v_rod_q28 - st->v_slider_q28 - kick_dv; /* LS's flow: 0 */
        if ((v_rel_start > 0 && p1 < 0) || (v_rel_start < 0 && p1 > 0)) {
            ls_advance_turning(cfg, st, dx_rel, v_rel_start, p1);
        } else {
            ss_ls_advance_q(&cfg->friction, &st->fr.ls, dx_rel, cfg->inv_dt_q47);
        }
        f_free = ss_ls_force_at_q(&cfg->friction, &st->fr.ls, v_free, &slopes);
    }
    /* N s/m in Q16 times (m/s)/N at 2^-40 is 2^-56: to Q30; and the rod's compliance the kicks
     * leave out, the contact's stiffness over sigma0 (Q30) times contact_lag_q30 (as the float) */
    const int64_t kicks = (int64_t)cfg->kick_rod_q40 + cfg->kick_slider_q40;
    const int64_t g = ss_shr_round(ss_mul_i64_i32(kicks, slopes.dfdv_q16), 26);
    const int64_t denom =
        SS_Q30_ONE + g +
        ((compliance_q56 == 0) ? ss_shr_round(ss_mul_s32_s64(slopes.dfdx_q30, cfg->contact_lag_q30), 30) : 0);
    if (compliance_q56 != 0 && denom > SS_ACT_Q_DENOM_MIN_Q30) {
        /* a coarse step: F1 = (F_free + g f_ref) / (1 + g), the change linearised about f_ref (F0,
         * or LS's linearised contact's); below the bound, F_free as the float takes it */
        f_free = ss_sat32((int64_t)f_free + ss_shr_round(ss_mul_i64_i32(g, f_ref), 30));
    }
    st->force_q24 = over_denom_q24(f_free, denom);

    if (compliance_q56 == 0) {
        kick(cfg, st);
    } else {
        st->v_rod_q28 = rod_kicked_q28(cfg, st, ss_sat32((int64_t)st->force_q24 - f_rod));
        st->v_slider_q28 =
            ls_flow ? ss_sat32(st->v_slider_q28 + slider_dv_q28(cfg, (int64_t)st->force_q24 - f_ref))
                    : slider_kicked_q28(cfg, st, st->force_q24);
    }
    st->steps++;
    return SS_OK;
}

/* x / (1 + rho) for the split step, by (1 + rho)'s reciprocal m 2^-sh (rho in Q30) */
SS_FORCE_INLINE int64_t in_series_q(int64_t x, int32_t m, int sh)
{
    return ss_mul_recip_q(ss_sat32(x), m, sh - 30);
}

/* The viscous force sigma2 v: N s/m in Q16 times m/s at 2^-28 is N at 2^-44 */
SS_FORCE_INLINE int64_t viscous_q24(const ss_actuator_config_q_t *cfg, int64_t v_q28)
{
    return ss_shr_round(ss_mul_s32_s64(cfg->friction.sigma2_q16, ss_sat32(v_q28)), 20);
}

/* LS's split step (the float family's split_step_over, ss_actuator_f32.c): the rod split into its
 * quasi-static part (x_p - c b / k - F / k) and its free ring about it, which takes the rod's flow
 * (phi_q28); the slider's flow on the contact in series with the stack (kt / (1 + rho), rho = kt /
 * k), from the force less the ring's share; the law over the contact's whole travel. The rod is not
 * kicked, so that a split config's kick_rod_q40 may be past its format (saturated by
 * ss_actuator_coarse_to_q: LS's 12 us at 1.5 us on Table I's rod). compliance_q56: 1 / k, m/N at
 * 2^-56. */
SS_NOINLINE ss_status_t step_split_ls(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                                      int32_t drive_q16, int32_t compliance_q56)
{
    if (cfg->inv_dt_q47 <= 0) {
        return SS_ERR_RANGE; /* cfg did not pass init */
    }
    const int32_t kt = ls_stiffness(cfg, st);
    const int32_t f0 = st->force_q24;
    const int32_t x_p0 = st->x_p_q40;
    const int32_t x_p1 = piezo_strain_q40(cfg, st, drive_q16, cfg->effects.slew_q24);
    const int32_t dxp = ss_sat32((int64_t)x_p1 - x_p0);
    const int64_t b = ss_velocity_q28(dxp, cfg->inv_dt_q47);
    /* c b / k over the step, m at 2^-40 */
    const int64_t lag = ss_shr_round(ss_mul_s32_s64(cfg->lag_q24, dxp), SS_QF_LAG);
    /* rho = kt / k in Q30: N/m times m/N at 2^-56; then 1 / (1 + rho) as m 2^-sh */
    const int64_t rho = ss_shr_round(ss_mul_s32_s64(kt, compliance_q56), 26);
    int sh = 0;
    const int32_t m = ss_reciprocal_mantissa_q((uint32_t)ss_clamp64(SS_Q30_ONE + rho, 1, INT32_MAX), &sh);
    const int32_t rho32 = ss_sat32(rho);
    const int32_t v_s0 = st->v_slider_q28;
    /* the ring at the start: x_rod - x_q, the force less the ring's share */
    const int64_t f0_k = ss_shr_round(ss_mul_s32_s64(f0, compliance_q56), 40); /* F0 / k, m at 2^-40 */
    const int32_t r0 = ss_sat32(in_series_q((int64_t)st->x_rod_q40 - x_p0 + lag + f0_k, m, sh));
    const int64_t vq0 = in_series_q(b + ss_shr_round(ss_mul_s32_s64(rho32, v_s0), 30), m, sh);
    const int32_t rd0 = ss_sat32((int64_t)st->v_rod_q28 - vq0);
    const int64_t f0s = (int64_t)f0 - contact_q24(kt, r0) - viscous_q24(cfg, rd0);
    const int32_t ks = ss_sat32(in_series_q(kt, m, sh));
    int32_t u = 0;
    int32_t ud = 0;
    slider_flow_q(cfg, ks, dxp, slider_dv_q28(cfg, (int64_t)cfg->effects.load_q24 + f0s), v_s0, &u, &ud);
    const int64_t f_ref = f0s + contact_q24(ks, ss_sat32((int64_t)dxp - u));
    /* the ring's free flow */
    int64_t e1 = 0;
    int64_t ed1 = 0;
    rod_free_flow_q(cfg, r0, rd0, &e1, &ed1);
    const int32_t r1 = ss_sat32(e1);
    const int32_t rd1 = ss_sat32(ed1);
    const int64_t vq1 = in_series_q(b + ss_shr_round(ss_mul_s32_s64(rho32, ud), 30), m, sh);
    /* the contact's travel: the quasi-static rod's, the ring's, less the slider's */
    const int64_t df_k = ss_shr_round(ss_mul_s32_s64(ss_sat32(f_ref - f0s), compliance_q56), 40);
    const int32_t dx_rel = ss_sat32((int64_t)dxp - df_k + ((int64_t)r1 - r0) - u);
    const int64_t v_rel_start = (int64_t)st->v_rod_q28 - v_s0;
    const int64_t p1 = vq1 + rd1 - ud;
    st->x_slider_q40 += u;
    st->x_p_q40 = x_p1;
    st->drive_q16 = drive_q16;
    if ((v_rel_start > 0 && p1 < 0) || (v_rel_start < 0 && p1 > 0)) {
        ls_advance_turning(cfg, st, dx_rel, v_rel_start, p1);
    } else {
        ss_ls_advance_q(&cfg->friction, &st->fr.ls, dx_rel, cfg->inv_dt_q47);
    }
    ss_friction_slopes_q_t slopes;
    int32_t f_free = ss_ls_force_at_q(&cfg->friction, &st->fr.ls, ss_sat32(p1), &slopes);
    /* F1 = (F_free + g f_ring) / (1 + g), g = dF/dv dt / 2 M_C: the slider's closing kick alone */
    const int32_t ring_f = ss_sat32(contact_q24(kt, r1) + viscous_q24(cfg, rd1));
    const int32_t f_ring = ss_sat32(f_ref + ring_f);
    const int64_t g = ss_shr_round(ss_mul_s32_s64(slopes.dfdv_q16, cfg->kick_slider_q40), 26);
    const int64_t denom = SS_Q30_ONE + g;
    if (denom > SS_ACT_Q_DENOM_MIN_Q30) {
        f_free = ss_sat32((int64_t)f_free + ss_shr_round(ss_mul_i64_i32(g, f_ring), 30));
    }
    st->force_q24 = over_denom_q24(f_free, denom);
    st->v_slider_q28 = ss_sat32(ud + slider_dv_q28(cfg, (int64_t)st->force_q24 - f_ring));
    /* the rod: quasi-static under F1 less the ring's share, and the ring */
    const int64_t f1s = (int64_t)st->force_q24 - ring_f;
    const int64_t f1_k = ss_shr_round(ss_mul_s32_s64(ss_sat32(f1s), compliance_q56), 40);
    st->x_rod_q40 = ss_sat32((int64_t)x_p1 - lag - f1_k + r1);
    st->v_rod_q28 =
        ss_sat32(in_series_q(b + ss_shr_round(ss_mul_s32_s64(rho32, st->v_slider_q28), 30), m, sh) + rd1);
    st->steps++;
    return SS_OK;
}

/* LS's coarse step, out of line: the run's loop inlines LuGre's, which then carries none of LS's
 * slider flow (inlined both, the M0+'s loop spilled more: q LuGre 1 541 -> 1 593 instructions a
 * microsecond) */
SS_NOINLINE ss_status_t step_held_ls(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                                     int32_t drive_q16, int32_t compliance_q56)
{
    return step_held(cfg, st, drive_q16, 0, 0, compliance_q56, 1);
}

/* The fine step */
SS_FORCE_INLINE ss_status_t step(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                                 int32_t drive_q16, int32_t corner_frac_q30, int32_t corner_q16)
{
    return step_held(cfg, st, drive_q16, corner_frac_q30, corner_q16, 0, 0);
}

ss_status_t ss_actuator_step_q(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                               int32_t drive_q16)
{
    return step(cfg, st, drive_q16, 0, 0);
}

ss_status_t ss_actuator_step_corner_q(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                                      int32_t drive_q16, int32_t corner_frac_q30, int32_t corner_q16)
{
    if (corner_frac_q30 <= 0 || corner_frac_q30 >= SS_Q30_ONE) {
        return SS_ERR_RANGE;
    }
    return step(cfg, st, drive_q16, corner_frac_q30, corner_q16);
}

/* The player's next step: the drive's corner inside it if one lies there (its fraction of the step
 * in Q30, 0 for none, and its value), then the drive at its end */
SS_FORCE_INLINE int32_t wave_next_q(const ss_waveform_config_q_t *wave, ss_waveform_state_q_t *wst,
                                    int32_t *frac, int32_t *corner)
{
    *frac = 0;
    *corner = 0;
    if (!ss_waveform_corner_q(wave, wst, frac, corner)) {
        *frac = 0;
    }
    ss_waveform_advance_q(wst);
    return ss_waveform_value_q(wave, wst);
}

ss_status_t ss_actuator_wave_step_q(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                                    const ss_waveform_config_q_t *wave, ss_waveform_state_q_t *wst)
{
    if (wave == NULL || wst == NULL) {
        return SS_ERR_NULL;
    }
    int32_t frac;
    int32_t corner;
    const int32_t drive = wave_next_q(wave, wst, &frac, &corner);
    return step(cfg, st, drive, frac, corner);
}

void ss_actuator_place_slider_q(ss_actuator_state_q_t *st, int64_t x_q40)
{
    st->x_slider_q40 = x_q40;
}

/* x + e x with e in Q2.30, x split at bit 30 so that no product leaves 64 bits (|x| < 2^63). */
int64_t ss_actuator_sensor_q(const ss_actuator_config_q_t *cfg, int64_t x_slider_q40)
{
    const int64_t e = cfg->effects.sensor_scale_q30;
    if (e == 0) {
        return x_slider_q40;
    }
    const int64_t hi = x_slider_q40 >> 30; /* floor: hi 2^30 + lo == x, lo in [0, 2^30) */
    const int64_t lo = x_slider_q40 - hi * ((int64_t)1 << 30);
    return x_slider_q40 + hi * e + ss_shr_round(lo * e, 30);
}

void ss_actuator_record_q(const ss_actuator_config_q_t *cfg, const ss_actuator_state_q_t *st,
                          ss_actuator_trace_q_t *tr, uint32_t row)
{
    const int lugre = (cfg->friction_model == SS_FRICTION_Q_LUGRE);
    if (tr->step != NULL) {
        tr->step[row] = st->steps;
    }
    if (tr->drive_q16 != NULL) {
        tr->drive_q16[row] = st->drive_q16;
    }
    if (tr->x_p_q40 != NULL) {
        tr->x_p_q40[row] = st->x_p_q40;
    }
    if (tr->x_rod_q40 != NULL) {
        tr->x_rod_q40[row] = st->x_rod_q40;
    }
    if (tr->x_slider_q40 != NULL) {
        tr->x_slider_q40[row] = st->x_slider_q40;
    }
    if (tr->v_rod_q28 != NULL) {
        tr->v_rod_q28[row] = st->v_rod_q28;
    }
    if (tr->v_slider_q28 != NULL) {
        tr->v_slider_q28[row] = st->v_slider_q28;
    }
    if (tr->force_q24 != NULL) {
        tr->force_q24[row] = st->force_q24;
    }
    if (tr->state_a != NULL) {
        tr->state_a[row] = lugre ? st->fr.lugre.z_q40 : st->fr.ls.level_q24;
    }
    if (tr->state_b != NULL) {
        tr->state_b[row] = lugre ? st->fr.lugre.zdot_q28 : st->fr.ls.fm_q24;
    }
    if (tr->x_meas_q40 != NULL) {
        tr->x_meas_q40[row] = ss_actuator_sensor_q(cfg, st->x_slider_q40);
    }
}

/* The player's position (its phase and period) from src into dst, a player of the same waveform
 * (the rest of it src's already): the player's fields that its steps change, without a copy of the
 * whole (a call to memcpy on ARMv6-M). */
SS_FORCE_INLINE void player_to(ss_waveform_state_q_t *dst, const ss_waveform_state_q_t *src)
{
    dst->phase_q64 = src->phase_q64;
    dst->index = src->index;
}

/* The drive after m steps (*w_end, a player of the same waveform: advanced m steps from *wst), and
 * whether the rod's ring over them is within ring_max_q40 (its travel at v_rod against the ideal
 * strain's change). */
SS_FORCE_INLINE int quiet_over(const ss_actuator_config_q_t *cfg, const ss_actuator_state_q_t *st,
                               const ss_waveform_config_q_t *wave, const ss_waveform_state_q_t *wst,
                               uint32_t m, int32_t dt_q40, int32_t ring_max_q40, ss_waveform_state_q_t *w_end,
                               int32_t *drive_end)
{
    player_to(w_end, wst);
    ss_waveform_advance_by_q(w_end, m);
    *drive_end = ss_waveform_value_q(wave, w_end);
    /* m/s at 2^-28 times s at 2^-40, and m/V at 2^-48 times V at 2^-16: both m at 2^-40 */
    const int64_t rod = ss_shr_round(ss_mul_s32_s64(st->v_rod_q28, dt_q40), 28);
    const int64_t strain =
        ss_shr_round(ss_mul_s32_s64(cfg->piezo_gain_q48, ss_sat32((int64_t)*drive_end - st->drive_q16)), 24);
    return ss_abs64(rod - strain) < ring_max_q40;
}

/* The coarse step that may be taken (as coarse_allowed of ss_actuator_f32.c), in steps of dt, or 0:
 * where the contact sticks and the rod is quiet, co->n where they fit before the row, else 2; where
 * the contact rings within the middle bounds, 2. The drive is straight over them; *w_end and
 * *drive_end get the player and the drive at the step's end. */
SS_FORCE_INLINE uint32_t coarse_allowed(const ss_actuator_config_q_t *cfg, const ss_actuator_coarse_q_t *co,
                                        const ss_actuator_state_q_t *st, const ss_waveform_config_q_t *wave,
                                        const ss_waveform_state_q_t *wst, uint32_t max_steps,
                                        ss_waveform_state_q_t *w_end, int32_t *drive_end)
{
    if (co == NULL || max_steps < 2u) {
        return 0u;
    }
    const int64_t v_rel = ss_abs64((int64_t)st->v_rod_q28 - st->v_slider_q28);
    if (v_rel < co->v_rel_max_q28) {
        const int whole = co->n <= max_steps;
        const uint32_t m = whole ? co->n : 2u;
        if (ss_waveform_straight_q(wave, wst, m) &&
            quiet_over(cfg, st, wave, wst, m, whole ? co->cfg.dt_q40 : co->cfg_mid.dt_q40,
                       whole ? co->ring_max_q40 : co->ring_max_2_q40, w_end, drive_end)) {
            return m;
        }
    }
    return (v_rel < co->v_rel_mid_max_q28 && ss_waveform_straight_q(wave, wst, 2u) &&
            quiet_over(cfg, st, wave, wst, 2u, co->cfg_mid.dt_q40, co->ring_mid_max_q40, w_end, drive_end))
               ? 2u
               : 0u;
}

/* May a stick step be taken (as stick_allowed of ss_actuator_f32.c)? co's stick steps on and fit
 * before the row, the contact quiet and its force far below Fc, the drive straight and the rod
 * quiet over them; *w_end and *drive_end get the player and the drive at the step's end. */
SS_FORCE_INLINE int stick_allowed_q(const ss_actuator_config_q_t *cfg, const ss_actuator_coarse_q_t *co,
                                    const ss_actuator_state_q_t *st, const ss_waveform_config_q_t *wave,
                                    const ss_waveform_state_q_t *wst, uint32_t max_steps,
                                    ss_waveform_state_q_t *w_end, int32_t *drive_end)
{
    return max_steps >= co->stick_n &&
           ss_abs64((int64_t)st->v_rod_q28 - st->v_slider_q28) < co->stick_v_rel_max_q28 &&
           ss_abs64(st->force_q24) < co->stick_force_max_q24 &&
           ss_waveform_straight_q(wave, wst, co->stick_n) &&
           quiet_over(cfg, st, wave, wst, co->stick_n, co->stick_h_q40, co->stick_ring_max_q40, w_end,
                      drive_end);
}

/* A stick step to drive_q16 at its end, as stick_step of ss_actuator_f32.c: the linear flow of the
 * deviation from the ramp's steady state (rod (L - c b) / k off the strain, bristle -L / sigma0,
 * both bodies at b), velocities over the rod's rate w as lengths (m at 2^-40, as the flow's
 * entries), and LuGre's force and dz/dt at the end. */
SS_FORCE_INLINE void stick_step_q(const ss_actuator_config_q_t *cfg, const ss_actuator_coarse_q_t *co,
                                  ss_actuator_state_q_t *st, int32_t drive_q16)
{
    const int32_t x_p0 = st->x_p_q40;
    const int32_t x_rod0 = st->x_rod_q40;
    const int32_t z0 = st->fr.lugre.z_q40;
    const int32_t x_p1 = piezo_strain_q40(cfg, st, drive_q16, cfg->effects.slew_q24);
    const int32_t dxp = ss_sat32((int64_t)x_p1 - x_p0);
    const int64_t b = ss_velocity_q28(dxp, co->stick_inv_h_q47); /* m/s at 2^-28 */
    const int64_t load = cfg->effects.load_q24;
    /* (L - c b) / k: N at 2^-24 times m/N at 2^-56 is m at 2^-80; c b / k = (c / (k h)) dxp */
    const int64_t e_ss = ss_shr_round(ss_mul_s32_s64((int32_t)load, co->compliance_q56), 40) -
                         ss_shr_round(ss_mul_s32_s64(dxp, co->stick_lag_q30), 30);
    /* -L / sigma0: N at 2^-24 times m/N at 2^-47 is m at 2^-71 */
    const int64_t z_ss = -ss_shr_round(ss_mul_s32_s64((int32_t)load, cfg->friction.inv_sigma0_q47), 31);
    /* (v - b) / w: m/s at 2^-28 times s at 2^-40, to m at 2^-40 */
    const int32_t u0[4] = {
        ss_sat32((int64_t)x_rod0 - x_p0 - e_ss),
        ss_sat32(ss_shr_round(ss_mul_s32_s64(ss_sat32(st->v_rod_q28 - b), co->stick_inv_omega_q40), 28)),
        ss_sat32((int64_t)z0 - z_ss),
        ss_sat32(ss_shr_round(ss_mul_s32_s64(ss_sat32(st->v_slider_q28 - b), co->stick_inv_omega_q40), 28)),
    };
    int32_t u1[4];
    for (size_t i = 0; i < 4u; ++i) {
        const int32_t *row = &co->stick_phi_q[4u * i];
        /* |entries| <= 2^30: each product below 2^61, their sum below 2^63 */
        const int64_t acc = ss_mul_s32_s64(row[0], u0[0]) + ss_mul_s32_s64(row[1], u0[1]) +
                            ss_mul_s32_s64(row[2], u0[2]) + ss_mul_s32_s64(row[3], u0[3]);
        u1[i] = ss_sat32(ss_shr_round(acc, co->stick_phi_shift));
    }
    const int32_t x_rod1 = ss_sat32((int64_t)x_p1 + e_ss + u1[0]);
    const int32_t z1 = ss_sat32(z_ss + u1[2]);
    st->x_rod_q40 = x_rod1;
    st->v_rod_q28 = ss_sat32(b + ss_velocity_q28(u1[1], co->stick_omega_q47));
    st->x_slider_q40 += ((int64_t)x_rod1 - x_rod0) - ((int64_t)z1 - z0);
    st->v_slider_q28 = ss_sat32(b + ss_velocity_q28(u1[3], co->stick_omega_q47));
    st->x_p_q40 = x_p1;
    st->drive_q16 = drive_q16;
    st->fr.lugre.z_q40 = z1;
    st->force_q24 =
        ss_lugre_settle_q(&cfg->friction, &st->fr.lugre, ss_sat32((int64_t)st->v_rod_q28 - st->v_slider_q28));
    st->steps++;
}

/* A fine step of a run with stick steps, as wave_step_edges of ss_actuator_f32.c: one whose drive
 * changes by more than edge_limit_q16 (0.1 m/s of strain; on the corner's pieces in proportion)
 * in co->edge_parts steps of cfg_edge, the drive linear in between (and the corner in the part it
 * falls in), else the fine step. */
SS_NOINLINE ss_status_t wave_step_edges_q(const ss_actuator_config_q_t *cfg, const ss_actuator_coarse_q_t *co,
                                          ss_actuator_state_q_t *st, const ss_waveform_config_q_t *wave,
                                          ss_waveform_state_q_t *wst)
{
    int32_t frac;
    int32_t corner;
    const int32_t drive = wave_next_q(wave, wst, &frac, &corner);
    const int64_t u0 = st->drive_q16;
    /* the drive's change over the step, or over each piece of a corner against its share of the
     * limit (changes below 2^32, the limit below 2^31, shares within 2^30: within 64 bits) */
    const int64_t limit = co->edge_limit_q16;
    const int fast = (frac > 0)
                         ? (ss_abs64((int64_t)corner - u0) * SS_Q30_ONE > limit * frac ||
                            ss_abs64((int64_t)drive - corner) * SS_Q30_ONE > limit * (SS_Q30_ONE - frac))
                         : ss_abs64((int64_t)drive - u0) > limit;
    if (co->edge_parts < 2u || !fast) {
        return step(cfg, st, drive, frac, corner);
    }
    const int64_t part = co->edge_part_q30;
    const int64_t n = co->edge_parts;
    for (int64_t j = 0; j < n; ++j) {
        /* the part's ends a, b (Q30 of the step) and the drive at b, linear on each piece */
        const int64_t a = j * part;
        const int64_t b = a + part;
        int64_t u_b;
        int32_t part_frac = 0;
        if (j == n - 1) {
            u_b = drive; /* exactly the step's end */
        } else if (frac <= 0) {
            u_b = u0 + ss_shr_round(((int64_t)drive - u0) * b, 30);
        } else if (b <= frac) {
            u_b = u0 + ss_shr_round(((int64_t)corner - u0) * share_q30(b, frac), 30);
        } else {
            u_b =
                corner + ss_shr_round(((int64_t)drive - corner) * share_q30(b - frac, SS_Q30_ONE - frac), 30);
        }
        if (frac > a && frac < b) {
            part_frac = (int32_t)((frac - a) * n); /* the corner's place in the part, Q30 */
        }
        /* the public steps, out of line: one inlined copy of the step here (the fast path's) */
        const ss_status_t status =
            (part_frac != 0) ? ss_actuator_step_corner_q(&co->cfg_edge, st, ss_sat32(u_b), part_frac, corner)
                             : ss_actuator_step_q(&co->cfg_edge, st, ss_sat32(u_b));
        if (status != SS_OK) {
            return status;
        }
    }
    st->steps -= (uint32_t)(n - 1);
    return SS_OK;
}

/* A stick step where one may be taken (the player then at its end): whether it was. Out of line: a
 * few steps in a period take it, and inline it slowed the coarse loop of both laws. */
SS_NOINLINE int stick_try_q(const ss_actuator_config_q_t *cfg, const ss_actuator_coarse_q_t *co,
                            ss_actuator_state_q_t *st, const ss_waveform_config_q_t *wave,
                            ss_waveform_state_q_t *wst, uint32_t max_steps)
{
    ss_waveform_state_q_t w_end = *wst;
    int32_t drive_end = 0;
    if (!stick_allowed_q(cfg, co, st, wave, wst, max_steps, &w_end, &drive_end)) {
        return 0;
    }
    stick_step_q(cfg, co, st, drive_end);
    player_to(wst, &w_end);
    st->steps += co->stick_n - 1u; /* the step counted one */
    return 1;
}

ss_status_t ss_actuator_run_coarse_q(const ss_actuator_config_q_t *cfg, const ss_actuator_coarse_q_t *co,
                                     ss_actuator_state_q_t *st, const ss_waveform_config_q_t *wave,
                                     ss_waveform_state_q_t *wst, uint32_t n_steps, uint32_t decimation,
                                     ss_actuator_trace_q_t *trace, uint32_t *rows_out, uint32_t *steps_out)
{
    if (cfg == NULL || st == NULL || wave == NULL || wst == NULL || rows_out == NULL) {
        return SS_ERR_NULL;
    }
    *rows_out = 0u;
    if (decimation == 0u || (trace != NULL && trace->capacity < n_steps / decimation)) {
        return SS_ERR_RANGE;
    }
    uint32_t model_steps = 0u;
    uint32_t left = n_steps;
    uint32_t to_row = decimation;
    ss_status_t status = SS_OK;
    ss_waveform_state_q_t w_end = *wst; /* the player at a coarse step's end: its position alone moves */
    while (left > 0u && status == SS_OK) {
        int32_t drive_end = 0;
        uint32_t taken = 1u;
        const uint32_t max_steps = (to_row < left) ? to_row : left;
        const uint32_t m = coarse_allowed(cfg, co, st, wave, wst, max_steps, &w_end, &drive_end);
        if (m != 0u) {
            /* a stick step only where a whole coarse step may be taken: its bounds are within those */
            if (m == co->n && co->stick_n != 0u && stick_try_q(cfg, co, st, wave, wst, max_steps)) {
                taken = co->stick_n;
            } else {
                const ss_actuator_config_q_t *c = (m == co->n) ? &co->cfg : &co->cfg_mid;
                const int32_t compliance = (cfg->effects.base_kick_q40 == 0) ? co->compliance_q56 : 0;
                if (cfg->friction_model == SS_FRICTION_Q_LUGRE) {
                    status = step_held(c, st, drive_end, 0, 0, compliance, 0);
                } else if (m == co->n && co->split != 0 && compliance != 0) {
                    status = step_split_ls(c, st, drive_end, compliance);
                } else {
                    status = step_held_ls(c, st, drive_end, compliance);
                }
                if (status == SS_OK) {
                    player_to(wst, &w_end);
                    st->steps += m - 1u; /* step counted one */
                    taken = m;
                }
            }
        } else {
            status = (co != NULL && co->stick_n != 0u) ? wave_step_edges_q(cfg, co, st, wave, wst)
                                                       : ss_actuator_wave_step_q(cfg, st, wave, wst);
        }
        if (status != SS_OK) {
            break;
        }
        ++model_steps;
        left -= taken;
        to_row -= taken;
        if (to_row == 0u) {
            to_row = decimation;
            if (trace != NULL) {
                ss_actuator_record_q(cfg, st, trace, (*rows_out)++);
            }
        }
    }
    if (steps_out != NULL) {
        *steps_out = model_steps;
    }
    return status;
}

ss_status_t ss_actuator_run_q(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                              const ss_waveform_config_q_t *wave, ss_waveform_state_q_t *wst,
                              uint32_t n_steps, uint32_t decimation, ss_actuator_trace_q_t *trace,
                              uint32_t *rows_out)
{
    if (cfg == NULL || st == NULL || wave == NULL || wst == NULL || rows_out == NULL) {
        return SS_ERR_NULL;
    }
    *rows_out = 0u;
    if (decimation == 0u || (trace != NULL && trace->capacity < n_steps / decimation)) {
        return SS_ERR_RANGE;
    }
    uint32_t rows = 0u;
    ss_status_t status = SS_OK;
    for (uint32_t i = 1u; i <= n_steps && status == SS_OK; ++i) {
        status = ss_actuator_wave_step_q(cfg, st, wave, wst);
        if (status == SS_OK && trace != NULL && i % decimation == 0u) {
            ss_actuator_record_q(cfg, st, trace, rows++);
        }
    }
    *rows_out = rows;
    return status;
}
