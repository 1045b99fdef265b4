#include "ss_actuator.h"

#include <float.h>
#include <math.h>
#include <stddef.h>

#include "ss_check.h"
#include "ss_effects_inline_f32.h"
#include "ss_exp_f32.h"
#include "ss_friction_inline_f32.h"
#include "ss_friction_parts_f32.h"
#include "ss_inline.h"
#include "ss_trig_f32.h"

ss_actuator_config_f32_t ss_actuator_config_table1_f32(void)
{
    ss_actuator_config_f32_t cfg;
    cfg.piezo_stiffness_n_per_m = 2.08e8f;
    cfg.piezo_damping_kg_per_s = 6.2f;
    cfg.rod_mass_kg = 1.1e-3f;
    cfg.slider_mass_kg = 1.38e-2f;
    cfg.piezo_gain_m_per_v = 4.4e-8f;
    cfg.dt_s = 1.0e-6f;
    cfg.friction_model = SS_FRICTION_LS;
    cfg.friction = ss_friction_config_table1_f32();
    cfg.effects = ss_effects_config_none_f32();
    return cfg;
}

float ss_position_value_f32(ss_position_f32_t p)
{
    return p.hi_m + p.lo_m;
}

/* Fast2Sum-style compensated add: keeps what hi cannot hold in lo. */
static void position_add(ss_position_f32_t *p, float dx)
{
    const float y = dx + p->lo_m;
    const float t = p->hi_m + y;
    p->lo_m = y - (t - p->hi_m);
    p->hi_m = t;
}

ss_status_t ss_actuator_config_check_f32(const ss_actuator_config_f32_t *cfg, const char **bad_field)
{
    const char *dummy = "";
    const char **bad = (bad_field != NULL) ? bad_field : &dummy;
    *bad = "";
    if (cfg == NULL) {
        *bad = "config";
        return SS_ERR_NULL;
    }
    const ss_range_f32_t ranges[] = {
        {"piezo_stiffness_n_per_m", cfg->piezo_stiffness_n_per_m, 1.0f, 1e12f},
        {"piezo_damping_kg_per_s", cfg->piezo_damping_kg_per_s, 0.0f, 1e6f},
        {"rod_mass_kg", cfg->rod_mass_kg, 1e-9f, 1e3f},
        {"slider_mass_kg", cfg->slider_mass_kg, 1e-9f, 1e3f},
        {"piezo_gain_m_per_v", cfg->piezo_gain_m_per_v, -1e-3f, 1e-3f},
        {"dt_s", cfg->dt_s, 1e-9f, 1e-3f},
    };
    ss_status_t st = ss_check_ranges_f32(ranges, sizeof ranges / sizeof ranges[0], bad);
    if (st != SS_OK) {
        return st;
    }
    if (cfg->piezo_gain_m_per_v == 0.0f) {
        *bad = "piezo_gain_m_per_v";
        return SS_ERR_RANGE;
    }
    if (cfg->friction_model != SS_FRICTION_LS && cfg->friction_model != SS_FRICTION_LUGRE &&
        cfg->friction_model != SS_FRICTION_GMS) {
        *bad = "friction_model";
        return SS_ERR_RANGE;
    }
    /* friction fields carry a prefix so the caller can tell them apart */
    st = ss_friction_config_check_named_f32(&cfg->friction, 1, bad);
    if (st == SS_OK) {
        st = ss_effects_config_check_f32(&cfg->effects, bad);
    }
    return st;
}

/* Exact flow of M e'' + c e' + k e = 0 over dt, as a 2x2 matrix on (e, e'). Under-, critically
 * and over-damped cases share one form with s(t) = sin(w t)/w, sinh(w t)/w or t. Init takes it over
 * the step, a step that a drive's corner splits over each piece: the library's own exponential and
 * sine (ss_exp_f32.h, ss_trig_f32.h), a few dozen instructions where newlib's take several hundred,
 * and the same bits on every target. */
static void rod_flow(const ss_actuator_config_f32_t *cfg, float dt, float phi[4])
{
    const float k = cfg->piezo_stiffness_n_per_m;
    const float m = cfg->rod_mass_kg;
    const float wn2 = k / m;
    const float sigma = 0.5f * cfg->piezo_damping_kg_per_s / m;
    const float wd2 = wn2 - sigma * sigma;
    float co;
    float si; /* s(dt) as above */
    if (wd2 > 0.0f) {
        const float wd = sqrtf(wd2);
        float sn;
        if (wd * dt < SS_TRIG_MAX_ARG) {
            ss_sincos_f32(wd * dt, &sn, &co);
        } else { /* a rod that rings more than 650 times a step: libm's reduction */
            co = cosf(wd * dt);
            sn = sinf(wd * dt);
        }
        si = sn / wd;
    } else if (wd2 < 0.0f) {
        /* over-damped: e^(-sigma t) cosh and sinh from the two real roots -sigma -+ w, never
         * cosh(w dt) itself (it overflows when a light, stiff, damped rod makes w dt > 89, and
         * then inf x e^(-sigma dt) = inf x 0 is NaN). The slow root in a form without cancellation,
         * and e_fast (e^(2 w dt) - 1) as -e_slow expm1(-2 w dt), which has none either. */
        const float w = sqrtf(-wd2);
        const float e_slow = ss_exp_neg_f32(wn2 / (sigma + w) * dt);
        const float e_fast = ss_exp_neg_f32((sigma + w) * dt);
        float e_2w;
        const float s = -e_slow * ss_expm1_neg_f32(2.0f * w * dt, &e_2w) / (2.0f * w);
        const float c = 0.5f * (e_slow + e_fast);
        phi[0] = c + sigma * s;
        phi[1] = s;
        phi[2] = -wn2 * s;
        phi[3] = c - sigma * s;
        return;
    } else {
        co = 1.0f;
        si = dt;
    }
    const float e = ss_exp_neg_f32(sigma * dt);
    phi[0] = e * (co + sigma * si);
    phi[1] = e * si;
    phi[2] = -e * wn2 * si;
    phi[3] = e * (co - sigma * si);
}

/* What a step carries from one phase to the next: step() runs the phases in turn, a batch
 * (ss_actuator_run_many_f32) runs each phase for several simulations before the next. */
typedef struct {
    float dt;              /* the step: cfg's dt, or a coarse step's n dt */
    float inv_mr;          /* 1 / rod mass */
    float inv_mc;          /* 1 / slider mass */
    float dx_rel;          /* the drift's relative displacement, rod minus slider */
    float v_free;          /* relative velocity before the closing kick */
    float kick_per_n;      /* relative dv per newton of the closing kick */
    float rod_lag_m_per_n; /* dt^2 / 12 M_R: the rod's compliance the kicks leave out (step_finish) */
    float f0;              /* the friction the step began with */
    float turn_m;          /* LS, GMS: the drift's relative excursion before its motion turned, else 0 */
    float turn_frac;       /* ... and when it turned, a fraction of dt */
    float v_start;         /* GMS: the relative velocity the step started from (its force's) */
} carry_t;

/* What a batch's step carries besides (its address is taken: kept apart from carry_t, which a
 * single step then holds in registers). */
typedef struct {
    const ss_friction_config_f32_t *fr; /* the step's friction: cfg's, or scaled */
    ss_friction_config_f32_t scaled;    /* Fs and Fc under a position or thermal scale */
    ss_lugre_slip_f32_t lugre_slip;     /* the friction law's parts in flight */
    ss_lugre_level_f32_t lugre_level;
    ss_ls_branch_f32_t ls_branch;
} parts_t;

/* The step's friction config: position-dependent and thermal effects scale Fs and Fc (the normal
 * force) for the step. */
SS_FORCE_INLINE const ss_friction_config_f32_t *friction_config(const ss_actuator_config_f32_t *cfg,
                                                                const ss_actuator_state_f32_t *st,
                                                                ss_friction_config_f32_t *scaled)
{
    const int scales =
        cfg->effects.friction_gradient_per_m != 0.0f || cfg->effects.thermal_coeff_per_j != 0.0f;
    const float scale =
        scales ? ss_effects_friction_scale_f32(&cfg->effects, &st->fx, ss_position_value_f32(st->x_slider))
               : 1.0f;
    if (scale == 1.0f) {
        return &cfg->friction;
    }
    *scaled = cfg->friction;
    scaled->fs_n *= scale;
    scaled->fc_n *= scale;
    return scaled;
}

/* GMS's advance over the drift's relative displacement: to the turning point first, where the
 * motion turned inside the step (its elements keep LS's memory), then the rest. */
SS_FORCE_INLINE void gms_advance(ss_actuator_state_f32_t *st, const ss_friction_config_f32_t *fr,
                                 const carry_t *c)
{
    ss_gms_begin_step_f32(&st->fr.gms, c->v_start);
    if (c->turn_m != 0.0f) {
        ss_gms_advance_piece_f32(fr, &st->fr.gms, c->turn_m, c->turn_frac * c->dt);
    }
    ss_gms_advance_piece_f32(fr, &st->fr.gms, c->dx_rel - c->turn_m, (1.0f - c->turn_frac) * c->dt);
}

/* LS's advance to the turning point, where the motion turned inside the step; the rest of the
 * step follows whole (friction_advance) or in parts (friction_begin, friction_end). */
SS_FORCE_INLINE void ls_advance_to_turn(ss_actuator_state_f32_t *st, const ss_friction_config_f32_t *fr,
                                        const carry_t *c)
{
    if (c->turn_m != 0.0f) {
        ss_ls_advance_f32(fr, &st->fr.ls, c->turn_m, c->turn_frac * c->dt);
    }
}

/* One simulation's step (step()): the law's advance over the drift's relative displacement (LS
 * and GMS in two pieces where the motion turned inside the step) under the step's friction fr, ... */
SS_FORCE_INLINE void friction_advance(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                      const ss_friction_config_f32_t *fr, const carry_t *c)
{
    if (cfg->friction_model == SS_FRICTION_LUGRE) {
        ss_lugre_advance_f32(fr, &st->fr.lugre, c->dx_rel, c->dt);
    } else if (cfg->friction_model == SS_FRICTION_GMS) {
        gms_advance(st, fr, c);
    } else {
        ls_advance_to_turn(st, fr, c);
        ss_ls_advance_f32(fr, &st->fr.ls, c->dx_rel - c->turn_m, (1.0f - c->turn_frac) * c->dt);
    }
}

/* ... then its force at the velocity the step ends with, with the slope. */
SS_FORCE_INLINE float friction_force(const ss_actuator_config_f32_t *cfg, const ss_actuator_state_f32_t *st,
                                     const ss_friction_config_f32_t *fr, const carry_t *c,
                                     ss_friction_slopes_f32_t *slopes)
{
    if (cfg->friction_model == SS_FRICTION_LUGRE) {
        return ss_lugre_force_at_f32(fr, &st->fr.lugre, c->v_free, slopes);
    }
    if (cfg->friction_model == SS_FRICTION_GMS) {
        return ss_gms_force_at_f32(fr, &st->fr.gms, c->v_free, slopes);
    }
    return ss_ls_force_at_f32(fr, &st->fr.ls, c->v_free, slopes);
}

/* A batch's step (ss_actuator_run_many_f32) in parts, the same operations: the step's friction and
 * the law's advance begun (LuGre: with the Stribeck level of the force at the step's end, which
 * does not depend on the state), ... */
SS_FORCE_INLINE void friction_begin(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                    const carry_t *c, parts_t *p)
{
    p->fr = friction_config(cfg, st, &p->scaled);
    if (cfg->friction_model == SS_FRICTION_LUGRE) {
        ss_lugre_advance_begin_f32(p->fr, c->dx_rel, c->dt, &p->lugre_slip);
        ss_lugre_force_begin_f32(p->fr, c->v_free, 1, &p->lugre_level);
    } else if (cfg->friction_model == SS_FRICTION_GMS) {
        gms_advance(st, p->fr, c); /* whole here: GMS has no parts */
    } else {
        ls_advance_to_turn(st, p->fr, c);
        ss_ls_advance_begin_f32(p->fr, &st->fr.ls, c->dx_rel - c->turn_m, (1.0f - c->turn_frac) * c->dt,
                                &p->ls_branch);
    }
}

/* ... the rest of the advance, ... */
SS_FORCE_INLINE void friction_end(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                  const carry_t *c, const parts_t *p)
{
    if (cfg->friction_model == SS_FRICTION_LUGRE) {
        ss_lugre_advance_end_f32(p->fr, &st->fr.lugre, c->dx_rel, &p->lugre_slip);
    } else if (cfg->friction_model != SS_FRICTION_GMS) { /* LS, as friction_begin */
        ss_ls_advance_end_f32(p->fr, &st->fr.ls, c->dx_rel - c->turn_m, (1.0f - c->turn_frac) * c->dt,
                              &p->ls_branch);
    }
}

/* ... and the force: LuGre's with the part of it begun there, the others' whole. */
SS_FORCE_INLINE float friction_force_parts(const ss_actuator_config_f32_t *cfg,
                                           const ss_actuator_state_f32_t *st, const carry_t *c,
                                           const parts_t *p, ss_friction_slopes_f32_t *slopes)
{
    if (cfg->friction_model == SS_FRICTION_LUGRE) {
        return ss_lugre_force_end_f32(p->fr, &st->fr.lugre, c->v_free, &p->lugre_level, slopes);
    }
    return friction_force(cfg, st, p->fr, c, slopes);
}

/* Force of the base spring-damper and of the piezo's reaction on the base (0 without a base). */
static float base_force(const ss_actuator_config_f32_t *cfg, const ss_actuator_state_f32_t *st)
{
    const ss_effects_config_f32_t *e = &cfg->effects;
    if (e->base_mass_kg == 0.0f) {
        return 0.0f;
    }
    const float w = 6.2831853f * e->base_freq_hz;
    const float k_b = e->base_mass_kg * w * w;
    const float c_b = 2.0f * e->base_damping_ratio * e->base_mass_kg * w;
    const float x_b = st->fx.x_base_m;
    const float v_b = st->fx.v_base_m_per_s;
    /* the stack between base and rod pushes the rod with F_p and the base with -F_p: its spring on
     * the stack's elastic length, its damper on the stack's length rate, as on the rod (rod_drift) */
    const float f_piezo = cfg->piezo_stiffness_n_per_m * (st->x_p_m + x_b - st->x_rod_m) +
                          cfg->piezo_damping_kg_per_s * (v_b - st->v_rod_m_per_s);
    return -k_b * x_b - c_b * v_b - f_piezo;
}

/* Half a step of friction (and load, and base forces) on every body. */
SS_FORCE_INLINE void half_kick(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st, float inv_mr,
                               float inv_mc, float dt)
{
    const float half = 0.5f * dt;
    st->v_rod_m_per_s -= st->force_n * inv_mr * half;
    st->v_slider_m_per_s += (st->force_n + cfg->effects.load_n) * inv_mc * half;
    if (cfg->effects.base_mass_kg != 0.0f) {
        st->fx.v_base_m_per_s += base_force(cfg, st) / cfg->effects.base_mass_kg * half;
    }
}

ss_status_t ss_actuator_init_f32(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                 float drive0_v)
{
    if (cfg == NULL || st == NULL) {
        return SS_ERR_NULL;
    }
    ss_status_t status = ss_actuator_config_check_f32(cfg, NULL);
    if (status == SS_OK) {
        status = ss_check_range_f32(drive0_v, -1e5f, 1e5f);
    }
    if (status != SS_OK) {
        return status;
    }
    if (cfg->friction_model == SS_FRICTION_LUGRE) {
        status = ss_lugre_init_f32(&cfg->friction, &st->fr.lugre);
    } else if (cfg->friction_model == SS_FRICTION_GMS) {
        status = ss_gms_init_f32(&cfg->friction, &st->fr.gms);
    } else {
        status = ss_ls_init_f32(&cfg->friction, &st->fr.ls);
    }
    if (status != SS_OK) {
        return status;
    }
    st->drive_v = drive0_v;
    ss_effects_init_f32(&cfg->effects, &st->fx, cfg->piezo_gain_m_per_v, drive0_v);
    st->x_p_m = st->fx.strain_m;
    st->x_rod_m = st->x_p_m; /* static equilibrium: no friction at the virgin state */
    st->v_rod_m_per_s = 0.0f;
    st->x_slider.hi_m = 0.0f;
    st->x_slider.lo_m = 0.0f;
    st->v_slider_m_per_s = 0.0f;
    st->force_n = 0.0f;
    st->steps = 0u;
    rod_flow(cfg, cfg->dt_s, st->phi);
    return SS_OK;
}

/* The rod's exact flow over s under a piezo anchor (strain plus base) ramping linearly from a0 to a1,
 * the base moving at v_b (phi: the free flow over s). The stack's damper acts on its length rate,
 * the rod's velocity relative to the base: M x'' = k (a - x) - c (x' - v_b). Its forced response is
 * y(t) = a(t) - c (b - v_b) / k with b the ramp rate; the rest is free. */
static void rod_drift(const ss_actuator_config_f32_t *cfg, const float phi[4], float s, float a0, float a1,
                      float v_b, float *x, float *v)
{
    const float b = (a1 - a0) / s;
    const float lag = cfg->piezo_damping_kg_per_s * (b - v_b) / cfg->piezo_stiffness_n_per_m;
    const float e0 = *x - (a0 - lag);
    const float ed0 = *v - b;
    const float e1 = phi[0] * e0 + phi[1] * ed0;
    const float ed1 = phi[2] * e0 + phi[3] * ed0;
    *x = (a1 - lag) + e1;
    *v = b + ed1;
}

/* The drift of a step whose drive bends at corner_frac dt: the anchor's two straight pieces, each
 * with the rod's exact flow over its own length (two flow matrices by the own functions), and the
 * effects' drive advanced in the same two pieces. Returns the strain at the step's end. */
static float drift_with_corner(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st, float dt,
                               float drive_v, float corner_frac, float corner_v)
{
    const float t1 = corner_frac * dt;
    const float t2 = dt - t1;
    const float x_b0 = st->fx.x_base_m;
    const float a0 = st->x_p_m + x_b0;
    const float x_pc =
        ss_effects_drive_inline_f32(&cfg->effects, &st->fx, cfg->piezo_gain_m_per_v, corner_v, t1);
    const float x_p1 =
        ss_effects_drive_inline_f32(&cfg->effects, &st->fx, cfg->piezo_gain_m_per_v, drive_v, t2);
    const float ac = x_pc + (x_b0 + st->fx.v_base_m_per_s * t1);
    const float a1 = x_p1 + (x_b0 + st->fx.v_base_m_per_s * dt);
    float phi[4];
    rod_flow(cfg, t1, phi);
    rod_drift(cfg, phi, t1, a0, ac, st->fx.v_base_m_per_s, &st->x_rod_m, &st->v_rod_m_per_s);
    rod_flow(cfg, t2, phi);
    rod_drift(cfg, phi, t2, ac, a1, st->fx.v_base_m_per_s, &st->x_rod_m, &st->v_rod_m_per_s);
    return x_p1;
}

/* Where the relative motion turned inside the step (the rod's 69 kHz ringing after the fall turns
 * it some 70 times a cycle), into c->turn_m and c->turn_frac (0: no turn): the relative velocity
 * linear from its value at the step's start (c->v_start, before the opening kick) to p1, its end
 * before the closing kick's change of force (a kicked step: the drift's end less the same kick as
 * the opening one, the two averaging to the drift's; LS's coarse step: its slider flow's). LS's Masing memory
 * keeps that turning point; taken at the step's end, the loop it closes was up to (w dt)^2 / 8 of
 * the ring short, and LS's per-cycle error over the drive matrix was 0.087 % at 1 us and 0.31 % at
 * 1.5 us (docs/model.md). The drift's own velocities turn in most steps of a stick phase, where the
 * kicks alone flip the sign. GMS's elements keep the same memory (its position error at 1 us
 * against 0.125 us, 6.6 -> 0.6 nm RMS on the diagnosis' drives). LuGre keeps no turning point, and
 * the split made its error grow (0.056 % -> 0.127 % at 1 us). */
SS_FORCE_INLINE void turn_between(const ss_actuator_config_f32_t *cfg, float p1, carry_t *c)
{
    c->turn_m = 0.0f;
    c->turn_frac = 0.0f;
    if (cfg->friction_model != SS_FRICTION_LUGRE) {
        const float frac = c->v_start / (c->v_start - p1);
        if (c->v_start * p1 < 0.0f && frac < 1.0f) { /* frac rounds to 1 where p1 is tiny: no turn */
            c->turn_frac = frac;
            c->turn_m = 0.5f * c->v_start * frac * c->dt;
        }
    }
}

/* turn_between's end velocity for a kicked step: the drift's less the closing kick, taken as the
 * opening one (kick_dv) */
SS_FORCE_INLINE void turn_inside(const ss_actuator_config_f32_t *cfg, const ss_actuator_state_f32_t *st,
                                 float kick_dv, carry_t *c)
{
    turn_between(cfg, (st->v_rod_m_per_s - st->v_slider_m_per_s) - kick_dv, c);
}

/* A step's first phase, a step of dt with the rod's flow phi over it (cfg's dt and the state's
 * flow, or a coarse step's): the drive is linear from its current value to drive_v, or (corner_frac >
 * 0) linear to corner_v at corner_frac dt and then linear to drive_v. The opening kick and the
 * drift; the friction is advanced over the drift next (friction_advance, or in a batch
 * friction_begin and friction_end), then step_finish. */
SS_FORCE_INLINE ss_status_t step_start(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                       const float phi[4], float dt, float drive_v, float corner_frac,
                                       float corner_v, carry_t *c)
{
    /* cfg and st: checked by every caller (step, the coarse entry points, lane_start) */
    if (!isfinite(drive_v)) {
        return SS_ERR_NONFINITE;
    }
    const float half = 0.5f * dt;
    c->dt = dt;
    c->inv_mr = 1.0f / cfg->rod_mass_kg;
    c->inv_mc = 1.0f / cfg->slider_mass_kg;

    /* kick: half a step of friction on both bodies */
    const float v_rel_start = st->v_rod_m_per_s - st->v_slider_m_per_s;
    c->v_start = v_rel_start;
    half_kick(cfg, st, c->inv_mr, c->inv_mc, dt);
    const float kick_dv = v_rel_start - (st->v_rod_m_per_s - st->v_slider_m_per_s);

    /* drift: the rod's exact flow under the piezo anchor (strain plus base), in two pieces when the
     * drive bends inside the step (each with the flow over its own length) */
    const float x_b0 = st->fx.x_base_m;
    const float a0 = st->x_p_m + x_b0;
    const float x_rod0 = st->x_rod_m;
    float x_p1;
    if (corner_frac > 0.0f) {
        x_p1 = drift_with_corner(cfg, st, dt, drive_v, corner_frac, corner_v);
    } else {
        /* one straight piece, with the flow over dt from init (or the coarse step's) */
        x_p1 = ss_effects_drive_inline_f32(&cfg->effects, &st->fx, cfg->piezo_gain_m_per_v, drive_v, dt);
        const float a1 = x_p1 + (x_b0 + st->fx.v_base_m_per_s * dt);
        rod_drift(cfg, phi, dt, a0, a1, st->fx.v_base_m_per_s, &st->x_rod_m, &st->v_rod_m_per_s);
    }
    const float x_b1 = x_b0 + st->fx.v_base_m_per_s * dt;
    const float dx_slider = st->v_slider_m_per_s * dt;
    c->dx_rel = (st->x_rod_m - x_rod0) - dx_slider;
    turn_inside(cfg, st, kick_dv, c);
    st->fx.x_base_m = x_b1;
    position_add(&st->x_slider, dx_slider);
    st->x_p_m = x_p1;
    st->drive_v = drive_v;

    /* Friction at the new state and at the velocity the step ends with. That velocity depends on
     * the closing kick, i.e. on the force: solve the linearised relation (implicit in the
     * damping terms, so a stiff sigma1 costs no stability). */
    c->v_free = st->v_rod_m_per_s - st->v_slider_m_per_s -
                cfg->effects.load_n * c->inv_mc * half; /* before the closing kick */
    c->kick_per_n = half * (c->inv_mr + c->inv_mc);     /* relative dv per newton */
    c->rod_lag_m_per_n = (dt * dt * (1.0f / 12.0f)) * c->inv_mr;
    c->f0 = st->force_n;
    return SS_OK;
}

/* A step's last phase, from the friction f_free at the velocity the step ends with before the
 * closing kick, and its slopes (dF/dv, dF/dx): the force after the kick, the heat, the closing
 * kick. */
SS_FORCE_INLINE void step_finish(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                 const carry_t *c, float f_free, const ss_friction_slopes_f32_t *slopes)
{
    /* The rod's response to the friction comes as kicks at the step's ends, which its exact flow
     * between them turns into a sampled deflection (dt^2 / 12 M_R) / F short of the static F / k
     * (1.6 % of it at 1 us: the 69 kHz rod mode is 0.43 rad a step). The contact sees the rod
     * that much too stiff, and the slider's 4.2 kHz mode on it ran 3.9e-4 fast, 0.1 % a cycle of
     * the paper's drive under LS, whose mode rings through the stick phase. Taking the force at
     * the position the rod would have reached, x - F dt^2 / 12 M_R, and linearising in the
     * contact's stiffness dF/dx, is the denominator's last term (docs/model.md). */
    const float denom =
        1.0f + slopes->dfdv_ns_per_m * c->kick_per_n + slopes->dfdx_n_per_m * c->rod_lag_m_per_n;
    st->force_n = (denom > 0.1f) ? f_free / denom : f_free;
    if (cfg->effects.thermal_coeff_per_j != 0.0f) {
        /* heat: the work friction does on the relative motion, signed. The contact's elastic
         * energy (at most Fs^2 / 2 sigma0, ~1e-6 J) goes in and comes back within a cycle, so
         * over cycles this is the dissipation. Taking F^2 / 2 sigma0 off each step and counting
         * a negative step as 0 stored 12-15 % more heat under LuGre, whose force holds
         * sigma1 zdot + sigma2 v beside the spring (docs/effects.md). */
        ss_effects_heat_f32(&cfg->effects, &st->fx, 0.5f * (c->f0 + st->force_n) * c->dx_rel, c->dt);
    }

    /* kick */
    half_kick(cfg, st, c->inv_mr, c->inv_mc, c->dt);
    st->steps++;
}

/* One step of dt with the rod's flow phi over it: its phases in turn, the friction law's advance
 * and force whole. */
SS_FORCE_INLINE ss_status_t step_over(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                      const float phi[4], float dt, float drive_v, float corner_frac,
                                      float corner_v)
{
    carry_t c;
    const ss_status_t status = step_start(cfg, st, phi, dt, drive_v, corner_frac, corner_v, &c);
    if (status != SS_OK) {
        return status;
    }
    ss_friction_config_f32_t scaled;
    const ss_friction_config_f32_t *fr = friction_config(cfg, st, &scaled);
    friction_advance(cfg, st, fr, &c);
    ss_friction_slopes_f32_t slopes;
    const float f_free = friction_force(cfg, st, fr, &c, &slopes);
    step_finish(cfg, st, &c, f_free, &slopes);
    return SS_OK;
}

/* GMS's micro-damped elements lose accuracy while the contact slips fast: at 1 us the slider
 * drifts 2.6-3.8 nm a cycle on 15 us falls against the same run at 1/8 us, and the step's
 * error is made on the fast edge (bench/gms_edge_substeps.c). A step whose commanded piezo
 * velocity exceeds SS_GMS_EDGE_V_M_PER_S is taken in SS_GMS_EDGE_SUBSTEPS sub-steps (1: every
 * step whole, as before; bench/gms_edge_cost.c builds it so to time what the sub-steps cost). */
#ifndef SS_GMS_EDGE_SUBSTEPS
#define SS_GMS_EDGE_SUBSTEPS 4
#endif
#define SS_GMS_EDGE_V_M_PER_S 0.1f

/* Does the step's drive (to drive_v, bending at corner_frac to corner_v) move the piezo faster
 * than SS_GMS_EDGE_V_M_PER_S? */
SS_FORCE_INLINE int fast_edge(const ss_actuator_config_f32_t *cfg, const ss_actuator_state_f32_t *st,
                              float drive_v, float corner_frac, float corner_v)
{
    const float limit_v = SS_GMS_EDGE_V_M_PER_S * cfg->dt_s / fabsf(cfg->piezo_gain_m_per_v);
    if (corner_frac > 0.0f) {
        return fabsf(corner_v - st->drive_v) > limit_v * corner_frac ||
               fabsf(drive_v - corner_v) > limit_v * (1.0f - corner_frac);
    }
    return fabsf(drive_v - st->drive_v) > limit_v;
}

/* ... for a GMS contact with micro-damping, whose fine step takes such steps in sub-steps */
SS_FORCE_INLINE int gms_fast_edge(const ss_actuator_config_f32_t *cfg, const ss_actuator_state_f32_t *st,
                                  float drive_v, float corner_frac, float corner_v)
{
    return SS_GMS_EDGE_SUBSTEPS >= 2 && cfg->friction_model == SS_FRICTION_GMS &&
           cfg->friction.sigma1_ns_per_m != 0.0f && fast_edge(cfg, st, drive_v, corner_frac, corner_v);
}

/* A step of cfg's dt in SS_GMS_EDGE_SUBSTEPS sub-steps along the same drive (its corner in the
 * sub-step it falls in); counted as one step. */
static ss_status_t step_in_parts(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                 float drive_v, float corner_frac, float corner_v, int parts)
{
    const float n = (float)parts;
    const float sub_dt = cfg->dt_s / n;
    float phi[4];
    rod_flow(cfg, sub_dt, phi);
    const float u0 = st->drive_v;
    for (int j = 0; j < parts; ++j) {
        const float a = (float)j / n;
        const float b = (float)(j + 1) / n;
        /* the drive at fraction b of the step, and the corner if it lies inside (a, b) */
        float u_b;
        float frac = 0.0f;
        if (corner_frac <= 0.0f) {
            u_b = u0 + (drive_v - u0) * b;
        } else if (b <= corner_frac) {
            u_b = u0 + (corner_v - u0) * (b / corner_frac);
        } else {
            u_b = corner_v + (drive_v - corner_v) * ((b - corner_frac) / (1.0f - corner_frac));
            if (corner_frac > a) {
                frac = (corner_frac - a) * n;
            }
        }
        if (j == parts - 1) {
            u_b = drive_v; /* exactly the step's end */
        }
        const ss_status_t status =
            step_over(cfg, st, phi, sub_dt, u_b, (frac > 0.0f && frac < 1.0f) ? frac : 0.0f, corner_v);
        if (status != SS_OK) {
            return status;
        }
    }
    st->steps -= (uint32_t)(parts - 1);
    return SS_OK;
}

/* One step of cfg's dt. */
static ss_status_t step(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st, float drive_v,
                        float corner_frac, float corner_v)
{
    if (cfg == NULL || st == NULL) {
        return SS_ERR_NULL;
    }
    if (gms_fast_edge(cfg, st, drive_v, corner_frac, corner_v)) {
        return step_in_parts(cfg, st, drive_v, corner_frac, corner_v, SS_GMS_EDGE_SUBSTEPS);
    }
    return step_over(cfg, st, st->phi, cfg->dt_s, drive_v, corner_frac, corner_v);
}

ss_status_t ss_actuator_step_f32(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                 float drive_v)
{
    return step(cfg, st, drive_v, 0.0f, 0.0f);
}

ss_status_t ss_actuator_step_corner_f32(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                        float drive_v, float corner_frac, float corner_v)
{
    if (!(corner_frac > 0.0f && corner_frac < 1.0f) || !isfinite(corner_v)) {
        return isfinite(corner_frac) && isfinite(corner_v) ? SS_ERR_RANGE : SS_ERR_NONFINITE;
    }
    return step(cfg, st, drive_v, corner_frac, corner_v);
}

/* The player's next step: the drive at its end, and where the drive bends inside it (*frac 0: it
 * does not). */
SS_FORCE_INLINE float wave_next(const ss_waveform_config_f32_t *wave, ss_waveform_state_f32_t *wst,
                                float *frac, float *corner_v)
{
    *frac = 0.0f;
    *corner_v = 0.0f;
    if (!ss_waveform_corner_f32(wave, wst, frac, corner_v)) {
        *frac = 0.0f;
    }
    ss_waveform_advance_f32(wst);
    return ss_waveform_value_f32(wave, wst);
}

/* ss_actuator_wave_step_f32's body, inlined into the run's loop */
static inline ss_status_t wave_step(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                    const ss_waveform_config_f32_t *wave, ss_waveform_state_f32_t *wst)
{
    float frac;
    float corner_v;
    const float drive_v = wave_next(wave, wst, &frac, &corner_v);
    return step(cfg, st, drive_v, frac, corner_v);
}

ss_status_t ss_actuator_wave_step_f32(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                      const ss_waveform_config_f32_t *wave, ss_waveform_state_f32_t *wst)
{
    return wave_step(cfg, st, wave, wst);
}

/* A fine step of a run with stick steps: on a fast edge in co->edge_parts sub-steps (LuGre,
 * ss_actuator.h), else wave_step's. Out of line: the stick run's own loop. */
static ss_status_t wave_step_edges(const ss_actuator_config_f32_t *cfg, const ss_actuator_coarse_f32_t *co,
                                   ss_actuator_state_f32_t *st, const ss_waveform_config_f32_t *wave,
                                   ss_waveform_state_f32_t *wst)
{
    float frac;
    float corner_v;
    const float drive_v = wave_next(wave, wst, &frac, &corner_v);
    if (co->edge_parts >= 2u && fast_edge(cfg, st, drive_v, frac, corner_v)) {
        return step_in_parts(cfg, st, drive_v, frac, corner_v, (int)co->edge_parts);
    }
    return step(cfg, st, drive_v, frac, corner_v);
}

/* Do LS's slider flows hold at its stiffest contact kt_max over coarse steps of up to n dt: with
 * split steps, theirs (3 dt to n dt, the contact in series with the stack) within the longer series
 * and the held step's of 2 dt within the short one; without, the held steps' of up to n dt? */
static int ls_flows_hold(const ss_actuator_config_f32_t *cfg, uint32_t n, float kt_max, int split)
{
    const float dt2 = 2.0f * cfg->dt_s;
    const float dt = (float)n * cfg->dt_s;
    if (!split) {
        return kt_max * dt * dt / cfg->slider_mass_kg < SS_COARSE_FLOW_X_MAX;
    }
    const float ks_max = kt_max / (1.0f + kt_max / cfg->piezo_stiffness_n_per_m);
    return kt_max * dt2 * dt2 / cfg->slider_mass_kg < SS_COARSE_FLOW_X_MAX &&
           ks_max * dt * dt / cfg->slider_mass_kg < SS_COARSE_FLOW_X_LONG_MAX;
}

ss_status_t ss_actuator_coarse_init_f32(const ss_actuator_config_f32_t *cfg, uint32_t n,
                                        ss_actuator_coarse_f32_t *co, const char **bad_field)
{
    const char *dummy = "";
    const char **bad = (bad_field != NULL) ? bad_field : &dummy;
    if (co == NULL) {
        *bad = "coarse";
        return SS_ERR_NULL;
    }
    const ss_status_t status = ss_actuator_config_check_f32(cfg, bad);
    if (status != SS_OK) {
        return status;
    }
    if (cfg->friction_model == SS_FRICTION_GMS) {
        *bad = "friction_model";
        return SS_ERR_RANGE;
    }
    const float dt = (float)n * cfg->dt_s;
    if (n < 2u || n > 64u || !(dt <= 1e-3f)) { /* the config's range of dt */
        *bad = "coarse_n";
        return SS_ERR_RANGE;
    }
    co->n = n;
    co->dt_s = dt;
    const int ls = cfg->friction_model == SS_FRICTION_LS;
    co->v_rel_max_m_per_s = ls ? SS_COARSE_LS_V_REL_MAX_M_PER_S : SS_COARSE_V_REL_MAX_M_PER_S;
    co->v_ring_max_m_per_s = ls ? SS_COARSE_LS_V_RING_MAX_M_PER_S : SS_COARSE_V_RING_MAX_M_PER_S;
    co->v_rel_mid_max_m_per_s = ls ? SS_COARSE_LS_V_REL_MID_MAX_M_PER_S : SS_COARSE_V_REL_MID_MAX_M_PER_S;
    co->v_ring_mid_max_m_per_s = ls ? SS_COARSE_LS_V_RING_MID_MAX_M_PER_S : SS_COARSE_V_RING_MID_MAX_M_PER_S;
    /* LS's contact is at most (1 + |asymmetry|) sigma0 stiff (ls_stiffness' dF/dx): the flow must
     * hold at that */
    const float kt_max = (1.0f + fabsf(cfg->friction.asymmetry)) * cfg->friction.sigma0_n_per_m;
    /* the split form takes the ring on the rod's own flow: a contact much softer than the stack */
    const int split =
        ls && n >= SS_COARSE_SPLIT_MIN_N && kt_max <= SS_COARSE_SPLIT_RHO_MAX * cfg->piezo_stiffness_n_per_m;
    co->split_min_n = split ? SS_COARSE_SPLIT_MIN_N : 0u;
    if (cfg->effects.base_mass_kg != 0.0f || (ls && !ls_flows_hold(cfg, n, kt_max, split))) {
        ss_actuator_coarse_kicked_bounds_f32(co, cfg->friction_model);
    }
    rod_flow(cfg, dt, co->phi);
    rod_flow(cfg, 2.0f * cfg->dt_s, co->phi_mid);
    co->stick_n = 0u; /* off until ss_actuator_coarse_stick_f32 */
    co->stick_dt_s = 0.0f;
    co->stick_omega_per_s = 0.0f;
    co->edge_parts = 0u;
    for (int i = 0; i < 16; ++i) {
        co->stick_phi[i] = 0.0f;
    }
    return SS_OK;
}

void ss_actuator_coarse_kicked_bounds_f32(ss_actuator_coarse_f32_t *co, int32_t friction_model)
{
    if (co == NULL) {
        return;
    }
    const int ls = friction_model == SS_FRICTION_LS;
    co->v_rel_max_m_per_s = SS_COARSE_KICKED_V_REL_MAX_M_PER_S;
    co->v_ring_max_m_per_s = SS_COARSE_KICKED_V_RING_MAX_M_PER_S;
    co->v_rel_mid_max_m_per_s = ls ? SS_COARSE_LS_V_REL_MID_MAX_M_PER_S : SS_COARSE_V_REL_MID_MAX_M_PER_S;
    co->v_ring_mid_max_m_per_s =
        ls ? SS_COARSE_KICKED_LS_V_RING_MID_MAX_M_PER_S : SS_COARSE_V_RING_MID_MAX_M_PER_S;
}

/* The rod's ring: its velocity off the piezo's ideal rate (which the slider follows in a stick) */
SS_FORCE_INLINE float rod_ring(const ss_actuator_config_f32_t *cfg, const ss_actuator_state_f32_t *st,
                               const ss_waveform_config_f32_t *wave, const ss_waveform_state_f32_t *wst)
{
    return fabsf(st->v_rod_m_per_s - cfg->piezo_gain_m_per_v * ss_waveform_slope_f32(wave, wst));
}

/* The player m steps on (*w, from *wst) and the drive there */
SS_FORCE_INLINE float drive_after(const ss_waveform_config_f32_t *wave, const ss_waveform_state_f32_t *wst,
                                  uint32_t m, ss_waveform_state_f32_t *w)
{
    *w = *wst;
    for (uint32_t k = 0; k < m; ++k) {
        ss_waveform_advance_f32(w);
    }
    return ss_waveform_value_f32(wave, w);
}

/* The coarse step that may be taken, in steps of dt, or 0: m = min(co->n, max_steps) >= 2 where the
 * contact sticks (|v_rel| within v_rel_max), the rod is quiet (its velocity off the piezo's ideal
 * rate, which the slider follows in stick, within v_ring_max) and the drive is straight over the m
 * steps; else 2 where the contact rings within the middle bounds and the drive is straight over
 * them. The cheap test first: most steps of a slip stop at it. */
SS_FORCE_INLINE uint32_t coarse_allowed(const ss_actuator_config_f32_t *cfg,
                                        const ss_actuator_coarse_f32_t *co, const ss_actuator_state_f32_t *st,
                                        const ss_waveform_config_f32_t *wave,
                                        const ss_waveform_state_f32_t *wst, uint32_t max_steps)
{
    if (co == NULL || max_steps < 2u) {
        return 0u;
    }
    const float v_rel = fabsf(st->v_rod_m_per_s - st->v_slider_m_per_s);
    if (!(v_rel < co->v_rel_max_m_per_s || v_rel < co->v_rel_mid_max_m_per_s)) {
        return 0u;
    }
    const float ring = rod_ring(cfg, st, wave, wst);
    if (v_rel < co->v_rel_max_m_per_s && ring < co->v_ring_max_m_per_s) {
        const uint32_t m = (co->n < max_steps) ? co->n : max_steps;
        return ss_waveform_straight_f32(wave, wst, m) ? m : 0u;
    }
    return (v_rel < co->v_rel_mid_max_m_per_s && ring < co->v_ring_mid_max_m_per_s &&
            ss_waveform_straight_f32(wave, wst, 2u))
               ? 2u
               : 0u;
}

/* LS's slider in a coarse step: on the contact's stiffness kt (N/m), whose other end rides on the
 * rod at w (m/s, its mean over the step), under the force it starts with (a_s = (F0 + load) / M_C):
 * M_C u'' = F0 + load + kt (w t - u), u(0) = 0, u'(0) = v_s0, solved exactly over dt. With om^2 =
 * kt / M_C: u = a_s (1 - cos om dt) / om^2 + w dt + (v_s0 - w) sin(om dt) / om, and u' = a_s sin(om
 * dt) / om + w + (v_s0 - w) cos(om dt); the three functions in series in x = (om dt)^2 to x^2 (the
 * next term at most x^3 / 720 = 1.4e-6 at x = 0.1, 2.4e-8 at Table I's 6 us), and from 0.1 to
 * SS_COARSE_FLOW_X_LONG_MAX to x^3 (the next at most x^4 / 40320 = 6.3e-7 at 0.4; a split step of 12
 * us reaches 0.1 on Table I). Past that (and at x <= 0) the kick-drift-kick's: u = v_s0 dt + a_s dt^2 / 2, u'
 * its two kicks, the closing one with the linear contact's force at u. The kick-drift-kick is this flow to
 * first order in x, its ring's frequency x / 24 high: on LS's slider, which rings at 4.3 kHz through a stick
 * (x = 0.026 in 6 us), that put 0.1-0.2 % into a cycle's step over the slow edge's eight periods
 * (docs/model.md). */
SS_FORCE_INLINE void slider_flow(float kt, float inv_mc, float dt, float a_s, float v_s0, float w, float *u,
                                 float *ud)
{
    const float x = kt * dt * dt * inv_mc;
    if (x >= SS_COARSE_FLOW_X_MAX && x < SS_COARSE_FLOW_X_LONG_MAX) { /* a split step's longer reach */
        const float cos_x = 1.0f - 0.5f * x * (1.0f - x / 12.0f * (1.0f - x / 30.0f));
        const float sin_over = dt * (1.0f - x / 6.0f * (1.0f - x / 20.0f * (1.0f - x / 42.0f)));
        const float one_less = dt * dt * (0.5f - x / 24.0f * (1.0f - x / 30.0f * (1.0f - x / 56.0f)));
        *u = a_s * one_less + w * dt + (v_s0 - w) * sin_over;
        *ud = a_s * sin_over + w + (v_s0 - w) * cos_x;
        return;
    }
    if (!(x > 0.0f && x < SS_COARSE_FLOW_X_MAX)) {
        *u = (v_s0 + 0.5f * a_s * dt) * dt;
        *ud = v_s0 + a_s * dt + 0.5f * x * (w * dt - *u) / dt;
        return;
    }
    const float cos_x = 1.0f - 0.5f * x * (1.0f - x / 12.0f);                 /* cos(om dt) */
    const float sin_over = dt * (1.0f - x / 6.0f * (1.0f - x / 20.0f));       /* sin(om dt) / om */
    const float one_less = dt * dt * (0.5f - x / 24.0f * (1.0f - x / 30.0f)); /* (1 - cos) / om^2 */
    *u = a_s * one_less + w * dt + (v_s0 - w) * sin_over;
    *ud = a_s * sin_over + w + (v_s0 - w) * cos_x;
}

/* LS's contact stiffness, N/m: its Masing branch's tangent times the level's share of Fs and the
 * asymmetry (ss_ls_force_at_f32's dF/dx, at the unscaled Fs) */
SS_FORCE_INLINE float ls_contact_stiffness(const ss_actuator_config_f32_t *cfg,
                                           const ss_actuator_state_f32_t *st)
{
    const ss_friction_config_f32_t *f = &cfg->friction;
    return ss_asymmetry_inline_f32(f, st->fr.ls.fm_n) * (st->fr.ls.level_n / f->fs_n) * st->fr.ls.kt_n_per_m;
}

/* LS's split step, a coarse step of 3 dt or more (docs/model.md, "The split step"): the rod is split
 * into its quasi-static response to the strain and the contact's force, x_q = x_p - c b / k - F / k
 * (its velocity v_q = (b + rho v_s) / (1 + rho) with rho = kt / k), and its free 69 kHz ring about
 * it, r = x_rod - x_q, which takes the rod's own flow phi. The slider sees the contact without the
 * ring: its flow on the contact in series with the stack (kt / (1 + rho)), from the force less the
 * ring's share (kt r + sigma2 r'), its other end riding on the strain's ramp b. In the held form
 * the ring's travel over the step went into the slider's flow and the rod was kicked by the force's
 * change, which rang it: the 69 kHz mode turns 5.2 rad in 12 us, and held steps of 9 us were 0.3 %
 * off where split ones of 12 us hold 0.07 %. The law advances over the contact's whole travel, the
 * ring's included (its memory sees the rod as it is), and F1 is linearised about the flow's force
 * plus the ring's. */
SS_FORCE_INLINE ss_status_t split_step_over(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                            const float phi[4], float dt, float drive_v, float kt)
{
    carry_t c;
    const float half = 0.5f * dt;
    const float f0 = st->force_n;
    const float load = cfg->effects.load_n;
    const float s2 = cfg->friction.sigma2_ns_per_m;
    const float inv_k = 1.0f / cfg->piezo_stiffness_n_per_m;
    const float inv_mc = 1.0f / cfg->slider_mass_kg;
    c.dt = dt;
    const float x_p0 = st->x_p_m;
    const float x_p1 =
        ss_effects_drive_inline_f32(&cfg->effects, &st->fx, cfg->piezo_gain_m_per_v, drive_v, dt);
    const float b = (x_p1 - x_p0) / dt;
    const float lag = cfg->piezo_damping_kg_per_s * b * inv_k;
    const float rho = kt * inv_k;
    const float in_series = 1.0f / (1.0f + rho);
    const float v_s0 = st->v_slider_m_per_s;
    /* the ring at the start: x_rod - x_q with the force less the ring's own share, kt r */
    const float r0 = (st->x_rod_m - x_p0 + lag + f0 * inv_k) * in_series;
    const float rd0 = st->v_rod_m_per_s - (b + rho * v_s0) * in_series;
    const float f0s = f0 - kt * r0 - s2 * rd0;
    const float ks = kt * in_series;
    float u;
    float ud;
    slider_flow(ks, inv_mc, dt, (f0s + load) * inv_mc, v_s0, b, &u, &ud);
    const float f_ref = f0s + ks * (b * dt - u);
    const float r1 = phi[0] * r0 + phi[1] * rd0;
    const float rd1 = phi[2] * r0 + phi[3] * rd0;
    const float vq1 = (b + rho * ud) * in_series;
    /* the contact's travel: the quasi-static rod's (the strain's less the force's change over k) and
     * the ring's, less the slider's */
    c.dx_rel = b * dt - (f_ref - f0s) * inv_k + (r1 - r0) - u;
    c.v_start = st->v_rod_m_per_s - v_s0;
    turn_between(cfg, vq1 + rd1 - ud, &c);
    position_add(&st->x_slider, u);
    st->x_p_m = x_p1;
    st->drive_v = drive_v;
    c.v_free = vq1 + rd1 - ud;

    ss_friction_config_f32_t scaled;
    const ss_friction_config_f32_t *fr = friction_config(cfg, st, &scaled);
    friction_advance(cfg, st, fr, &c);
    ss_friction_slopes_f32_t slopes;
    const float f_free = friction_force(cfg, st, fr, &c, &slopes);
    /* F1 = f_free - dF/dv (F1 - f_ref) dt / 2 M_C: the slider's closing kick alone (the rod is not
     * kicked: its quasi-static part follows F1) */
    const float f_ring = f_ref + kt * r1 + s2 * rd1;
    const float g = slopes.dfdv_ns_per_m * half * inv_mc;
    st->force_n = (1.0f + g > 0.1f) ? (f_free + g * f_ring) / (1.0f + g) : f_free;
    if (cfg->effects.thermal_coeff_per_j != 0.0f) {
        ss_effects_heat_f32(&cfg->effects, &st->fx, 0.5f * (f0 + st->force_n) * c.dx_rel, dt);
    }
    st->v_slider_m_per_s = ud + (st->force_n - f_ring) * inv_mc * half;
    /* the rod: quasi-static under F1 less the ring's share, and the ring */
    const float f1s = st->force_n - kt * r1 - s2 * rd1;
    st->x_rod_m = x_p1 - lag - f1s * inv_k + r1;
    st->v_rod_m_per_s = (b + rho * st->v_slider_m_per_s) * in_series + rd1;
    st->steps++;
    return SS_OK;
}

/* A coarse step over dt (the rod's flow phi over it): the friction reaches the rod through its
 * flow, not as kicks. The rod's 69 kHz mode turns 1.7 rad in 4 us and 3.5 rad in 8 us, where
 * kicks F dt / 2 at the ends ring it (the fine step's kicks, taken coarse, held 0.1 % at 4 us
 * but 0.2-0.7 % at 8 us: docs/model.md). Here the rod's anchor carries the static deflection the
 * force makes, -F / k, ramping over the step from F0's to that of f_rod = F0 + kt v_rel dt, the
 * force the contact's stiffness kt predicts for the step's end (held at F0, the change came as a
 * jump at the end and rang the rod: LS's at 0.1-0.19 mm/s through the slow edge, the fine steps'
 * 0.05-0.1), and only F1's departure from f_rod is kicked onto the rod at the end. LuGre's slider
 * is kicked as in a fine step (F0 dt / 2, drift, F1 dt / 2), F1 linearised in dF/dv about the
 * velocity the step ends with if the force stays F0. LS's contact rings through a stick: its
 * slider takes its exact flow on the contact (slider_flow), F1 is linearised about f_ref, the
 * force that flow ends with, and the slider is kicked by F1 - f_ref. A base (whose kicks this
 * step does not make) takes the fine step's form over dt. */
SS_FORCE_INLINE ss_status_t coarse_step_over(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                             const float phi[4], float dt, float drive_v, int split)
{
    if (cfg->effects.base_mass_kg != 0.0f) {
        return step_over(cfg, st, phi, dt, drive_v, 0.0f, 0.0f);
    }
    if (!isfinite(drive_v)) {
        return SS_ERR_NONFINITE;
    }
    const int ls = cfg->friction_model == SS_FRICTION_LS;
    if (ls && split) {
        return split_step_over(cfg, st, phi, dt, drive_v, ls_contact_stiffness(cfg, st));
    }
    carry_t c;
    const float half = 0.5f * dt;
    const float f0 = st->force_n;
    const float load = cfg->effects.load_n;
    c.dt = dt;
    c.inv_mr = 1.0f / cfg->rod_mass_kg;
    c.inv_mc = 1.0f / cfg->slider_mass_kg;
    c.v_start = st->v_rod_m_per_s - st->v_slider_m_per_s;
    c.f0 = f0;

    c.kick_per_n = half * (c.inv_mr + c.inv_mc);
    const float a0 = st->x_p_m - f0 / cfg->piezo_stiffness_n_per_m; /* no base: its position stays 0 */
    const float x_rod0 = st->x_rod_m;
    const float x_p1 =
        ss_effects_drive_inline_f32(&cfg->effects, &st->fx, cfg->piezo_gain_m_per_v, drive_v, dt);
    /* the contact's stiffness: LS's (its Masing branch's tangent times the level's share of Fs and
     * the asymmetry: ss_ls_force_at_f32's dF/dx, at the unscaled Fs), LuGre's bristles (at rest in a
     * stick) */
    const float kt = ls ? ls_contact_stiffness(cfg, st) : cfg->friction.sigma0_n_per_m;
    const float f_rod = f0 + kt * c.v_start * dt; /* the rod's closing kick is F1 - f_rod, */
    float f_ref = f0;                             /* F1 is linearised about f_ref, */
    float f_slider = -load; /* the slider's closing kick F1 - f_slider (kicked: F1 + load) */
    rod_drift(cfg, phi, dt, a0, x_p1 - f_rod / cfg->piezo_stiffness_n_per_m, 0.0f, &st->x_rod_m,
              &st->v_rod_m_per_s);
    if (ls) {
        const float dx_rod = st->x_rod_m - x_rod0;
        float u;
        float ud;
        slider_flow(kt, c.inv_mc, dt, (f0 + load) * c.inv_mc, st->v_slider_m_per_s, dx_rod / dt, &u, &ud);
        c.dx_rel = dx_rod - u;
        f_ref = f0 + kt * c.dx_rel;
        f_slider = f_ref; /* the flow's force ends at f_ref + load: the kick is F1's departure */
        turn_between(cfg, st->v_rod_m_per_s - ud, &c);
        position_add(&st->x_slider, u);
        st->v_slider_m_per_s = ud;
        c.v_free = st->v_rod_m_per_s - ud - (f_ref - f_rod) * c.inv_mr * half;
    } else {
        const float kick_dv = (f0 + load) * c.inv_mc * half; /* the opening kick's relative dv */
        st->v_slider_m_per_s += kick_dv;
        const float dx_slider = st->v_slider_m_per_s * dt;
        c.dx_rel = (st->x_rod_m - x_rod0) - dx_slider;
        turn_inside(cfg, st, kick_dv, &c);
        position_add(&st->x_slider, dx_slider);
        c.v_free = st->v_rod_m_per_s - st->v_slider_m_per_s - (f0 + load) * c.inv_mc * half -
                   (f0 - f_rod) * c.inv_mr * half;
    }
    st->x_p_m = x_p1;
    st->drive_v = drive_v;

    ss_friction_config_f32_t scaled;
    const ss_friction_config_f32_t *fr = friction_config(cfg, st, &scaled);
    friction_advance(cfg, st, fr, &c);
    ss_friction_slopes_f32_t slopes;
    const float f_free = friction_force(cfg, st, fr, &c, &slopes);
    /* F1 = f_free - dF/dv (F1 - f_ref) (dt / 2 M_R + dt / 2 M_C) */
    const float g = slopes.dfdv_ns_per_m * c.kick_per_n;
    st->force_n = (1.0f + g > 0.1f) ? (f_free + g * f_ref) / (1.0f + g) : f_free;
    if (cfg->effects.thermal_coeff_per_j != 0.0f) {
        ss_effects_heat_f32(&cfg->effects, &st->fx, 0.5f * (f0 + st->force_n) * c.dx_rel, dt);
    }
    st->v_rod_m_per_s -= (st->force_n - f_rod) * c.inv_mr * half;
    st->v_slider_m_per_s += (st->force_n - f_slider) * c.inv_mc * half;
    st->steps++;
    return SS_OK;
}

/* May a stick step be taken (ss_actuator.h, SS_COARSE_STICK_*)? co's stick steps on, they fit
 * before the row, the contact and the rod are quiet, the force is far below Fc (the bristle's
 * relaxation, sigma0 |v| z / g, is then negligible against v) and the drive is straight. */
SS_FORCE_INLINE int stick_allowed(const ss_actuator_config_f32_t *cfg, const ss_actuator_coarse_f32_t *co,
                                  const ss_actuator_state_f32_t *st, const ss_waveform_config_f32_t *wave,
                                  const ss_waveform_state_f32_t *wst, uint32_t max_steps)
{
    if (max_steps < co->stick_n ||
        !(fabsf(st->v_rod_m_per_s - st->v_slider_m_per_s) < SS_COARSE_STICK_V_REL_MAX_M_PER_S) ||
        !(fabsf(st->force_n) < SS_COARSE_STICK_FORCE_SHARE * cfg->friction.fc_n)) {
        return 0;
    }
    return rod_ring(cfg, st, wave, wst) < SS_COARSE_STICK_V_RING_MAX_M_PER_S &&
           ss_waveform_straight_f32(wave, wst, co->stick_n);
}

/* A stick step to drive_v at its end: the linear flow (co->stick_phi) of the deviation from the
 * steady state that the ramp b and the load L hold (rod at (L - c b) / k off the strain, bristle
 * at -L / sigma0, both bodies at b), the slider's travel that of the rod less the bristle's, and
 * LuGre's force and dz/dt at the state it ends in. */
SS_FORCE_INLINE ss_status_t stick_step(const ss_actuator_config_f32_t *cfg,
                                       const ss_actuator_coarse_f32_t *co, ss_actuator_state_f32_t *st,
                                       float drive_v)
{
    if (!isfinite(drive_v)) {
        return SS_ERR_NONFINITE;
    }
    const float inv_h = 1.0f / co->stick_dt_s;
    const float w = co->stick_omega_per_s;
    const float inv_w = 1.0f / w;
    const ss_friction_config_f32_t *f = &cfg->friction;
    const float load = cfg->effects.load_n;
    const float x_p0 = st->x_p_m;
    const float x_rod0 = st->x_rod_m;
    const float z0 = st->fr.lugre.z_m;
    const float x_p1 =
        ss_effects_drive_inline_f32(&cfg->effects, &st->fx, cfg->piezo_gain_m_per_v, drive_v, co->stick_dt_s);
    const float b = (x_p1 - x_p0) * inv_h;
    const float e_ss = (load - cfg->piezo_damping_kg_per_s * b) / cfg->piezo_stiffness_n_per_m;
    const float z_ss = -load / f->sigma0_n_per_m;
    const float u0[4] = {x_rod0 - x_p0 - e_ss, (st->v_rod_m_per_s - b) * inv_w, z0 - z_ss,
                         (st->v_slider_m_per_s - b) * inv_w};
    float u1[4];
    for (size_t i = 0; i < 4u; ++i) {
        const float *row = &co->stick_phi[4u * i];
        u1[i] = row[0] * u0[0] + row[1] * u0[1] + row[2] * u0[2] + row[3] * u0[3];
    }
    st->x_rod_m = x_p1 + e_ss + u1[0];
    st->v_rod_m_per_s = b + u1[1] * w;
    const float z1 = z_ss + u1[2];
    position_add(&st->x_slider, (st->x_rod_m - x_rod0) - (z1 - z0));
    st->v_slider_m_per_s = b + u1[3] * w;
    st->x_p_m = x_p1;
    st->drive_v = drive_v;
    st->fr.lugre.z_m = z1;
    st->force_n = ss_lugre_settle_f32(f, &st->fr.lugre, st->v_rod_m_per_s - st->v_slider_m_per_s);
    st->steps++;
    return SS_OK;
}

/* A stick step where one may be taken: the steps of dt it took (0: none, or an error in *status).
 * Out of line: a few steps in a period take it, and inline it slowed LS's coarse loop on the M4F
 * (166 -> 168 instructions a microsecond). */
SS_NOINLINE uint32_t stick_try(const ss_actuator_config_f32_t *cfg, const ss_actuator_coarse_f32_t *co,
                               ss_actuator_state_f32_t *st, const ss_waveform_config_f32_t *wave,
                               ss_waveform_state_f32_t *wst, uint32_t max_steps, ss_status_t *status)
{
    if (!stick_allowed(cfg, co, st, wave, wst, max_steps)) {
        return 0u;
    }
    ss_waveform_state_f32_t w; /* committed with the step */
    *status = stick_step(cfg, co, st, drive_after(wave, wst, co->stick_n, &w));
    if (*status != SS_OK) {
        return 0u;
    }
    *wst = w;
    st->steps += co->stick_n - 1u; /* the step counted one */
    return co->stick_n;
}

/* ss_actuator_coarse_step_f32's body, inlined into the coarse run's loop. A coarse step shorter
 * than co->n (up to a row, or the run's end) and than 2 makes its flow here: such steps come once
 * after each stretch of finer steps, so that the next coarse step starts on the grid of rows
 * again (rows every co->n steps; the flow costs about 1 instruction a microsecond on the M4F). */
SS_FORCE_INLINE ss_status_t coarse_step(const ss_actuator_config_f32_t *cfg,
                                        const ss_actuator_coarse_f32_t *co, ss_actuator_state_f32_t *st,
                                        const ss_waveform_config_f32_t *wave, ss_waveform_state_f32_t *wst,
                                        uint32_t max_steps, uint32_t *taken, int sticks)
{
    const uint32_t m = coarse_allowed(cfg, co, st, wave, wst, max_steps);
    if (m == 0u) {
        const ss_status_t status =
            sticks ? wave_step_edges(cfg, co, st, wave, wst) : wave_step(cfg, st, wave, wst);
        *taken = (status == SS_OK) ? 1u : 0u;
        return status;
    }
    /* a stick step only where a whole coarse step may be taken: its bounds are within those */
    if (sticks && m == co->n) {
        ss_status_t status = SS_OK;
        *taken = stick_try(cfg, co, st, wave, wst, max_steps, &status);
        if (*taken != 0u || status != SS_OK) {
            return status;
        }
    }
    ss_waveform_state_f32_t w; /* committed with the step */
    const float drive_end = drive_after(wave, wst, m, &w);
    float phi_m[4];
    const float *phi = co->phi;
    float dt = co->dt_s;
    if (m != co->n) {
        dt = (float)m * cfg->dt_s;
        if (m == 2u) {
            phi = co->phi_mid;
        } else {
            rod_flow(cfg, dt, phi_m);
            phi = phi_m;
        }
    }
    const ss_status_t status =
        coarse_step_over(cfg, st, phi, dt, drive_end, co->split_min_n != 0u && m >= co->split_min_n);
    *taken = 0u;
    if (status == SS_OK) {
        *wst = w;
        st->steps += m - 1u; /* the step counted one */
        *taken = m;
    }
    return status;
}

ss_status_t ss_actuator_coarse_step_f32(const ss_actuator_config_f32_t *cfg,
                                        const ss_actuator_coarse_f32_t *co, ss_actuator_state_f32_t *st,
                                        const ss_waveform_config_f32_t *wave, ss_waveform_state_f32_t *wst,
                                        uint32_t max_steps, uint32_t *taken)
{
    if (cfg == NULL || st == NULL || wave == NULL || wst == NULL || taken == NULL) {
        return SS_ERR_NULL;
    }
    *taken = 0u;
    return (max_steps == 0u)
               ? SS_OK
               : coarse_step(cfg, co, st, wave, wst, max_steps, taken, co != NULL && co->stick_n != 0u);
}

void ss_actuator_place_slider_f32(ss_actuator_state_f32_t *st, float x_m)
{
    st->x_slider.hi_m = x_m;
    st->x_slider.lo_m = 0.0f;
}

float ss_actuator_heat_f32(const ss_actuator_state_f32_t *st)
{
    return st->fx.heat_j;
}

void ss_actuator_set_heat_f32(ss_actuator_state_f32_t *st, float heat_j)
{
    st->fx.heat_j = (heat_j > 0.0f && heat_j <= FLT_MAX) ? heat_j : 0.0f; /* NaN fails both */
}

/* The friction model's two recorded states (ss_actuator_trace_f32_t: state_a, state_b). */
static void friction_columns(const ss_actuator_config_f32_t *cfg, const ss_actuator_state_f32_t *st, float *a,
                             float *b)
{
    if (cfg->friction_model == SS_FRICTION_LUGRE) {
        *a = st->fr.lugre.z_m;
        *b = st->fr.lugre.zdot_m_per_s;
    } else if (cfg->friction_model == SS_FRICTION_GMS) {
        *a = st->fr.gms.level_n;
        *b = st->fr.gms.elastic_n;
    } else {
        *a = st->fr.ls.level_n;
        *b = st->fr.ls.fm_n;
    }
}

void ss_actuator_record_f32(const ss_actuator_config_f32_t *cfg, const ss_actuator_state_f32_t *st,
                            ss_actuator_trace_f32_t *tr, uint32_t row)
{
    if (tr->step != NULL) {
        tr->step[row] = st->steps;
    }
    if (tr->drive_v != NULL) {
        tr->drive_v[row] = st->drive_v;
    }
    if (tr->x_p_m != NULL) {
        tr->x_p_m[row] = st->x_p_m;
    }
    if (tr->x_rod_m != NULL) {
        tr->x_rod_m[row] = st->x_rod_m;
    }
    if (tr->x_slider_m != NULL) {
        tr->x_slider_m[row] = ss_position_value_f32(st->x_slider);
    }
    if (tr->v_rod_m_per_s != NULL) {
        tr->v_rod_m_per_s[row] = st->v_rod_m_per_s;
    }
    if (tr->v_slider_m_per_s != NULL) {
        tr->v_slider_m_per_s[row] = st->v_slider_m_per_s;
    }
    if (tr->force_n != NULL) {
        tr->force_n[row] = st->force_n;
    }
    float state_a;
    float state_b;
    friction_columns(cfg, st, &state_a, &state_b);
    if (tr->state_a != NULL) {
        tr->state_a[row] = state_a;
    }
    if (tr->state_b != NULL) {
        tr->state_b[row] = state_b;
    }
    if (tr->x_meas_m != NULL) {
        tr->x_meas_m[row] = ss_effects_sensor_f32(&cfg->effects, ss_position_value_f32(st->x_slider));
    }
}

/* A job in progress: steps left, and steps until its next recorded row. */
typedef struct {
    ss_actuator_run_job_f32_t *job;
    uint32_t left;
    uint32_t to_row;
} lane_t;

/* Check a job as ss_actuator_run_f32 checks its arguments and put it in the lane; 1 if it has
 * steps to run. */
SS_FORCE_INLINE int lane_start(lane_t *lane, ss_actuator_run_job_f32_t *j)
{
    j->rows = 0u;
    if (j->cfg == NULL || j->st == NULL || j->wave == NULL || j->wst == NULL) {
        j->status = SS_ERR_NULL;
        return 0;
    }
    if (j->decimation == 0u || (j->trace != NULL && j->trace->capacity < j->n_steps / j->decimation)) {
        j->status = SS_ERR_RANGE;
        return 0;
    }
    j->status = SS_OK;
    lane->job = j;
    lane->left = j->n_steps;
    lane->to_row = j->decimation;
    return j->n_steps > 0u;
}

/* After a lane's step of `taken` steps of dt (1; a coarse step's n, which never passes a row or the
 * end): its row when it ends on a decimation-th step; 1 while steps are left. */
SS_FORCE_INLINE int lane_after_steps(lane_t *lane, uint32_t taken)
{
    ss_actuator_run_job_f32_t *j = lane->job;
    lane->to_row -= taken;
    if (lane->to_row == 0u) {
        lane->to_row = j->decimation;
        if (j->trace != NULL) {
            ss_actuator_record_f32(j->cfg, j->st, j->trace, j->rows++);
        }
    }
    lane->left -= taken;
    return lane->left != 0u;
}

/* One step of the lane's job, and its row; 1 while steps are left and it has not failed. */
SS_FORCE_INLINE int lane_step(lane_t *lane)
{
    ss_actuator_run_job_f32_t *j = lane->job;
    j->status = wave_step(j->cfg, j->st, j->wave, j->wst);
    if (j->status != SS_OK) {
        return 0;
    }
    return lane_after_steps(lane, 1u);
}

/* The drive of the lane's next step from its player (wave_step's first half), then the step's
 * first phase. */
SS_FORCE_INLINE ss_status_t lane_start_step(lane_t *lane, carry_t *c, int *whole)
{
    ss_actuator_run_job_f32_t *j = lane->job;
    float frac;
    float corner_v;
    const float drive_v = wave_next(j->wave, j->wst, &frac, &corner_v);
    if (gms_fast_edge(j->cfg, j->st, drive_v, frac, corner_v)) {
        *whole = 1; /* taken here whole, in sub-steps (a non-finite drive fails in the first) */
        return step_in_parts(j->cfg, j->st, drive_v, frac, corner_v, SS_GMS_EDGE_SUBSTEPS);
    }
    return step_start(j->cfg, j->st, j->st->phi, j->cfg->dt_s, drive_v, frac, corner_v, c);
}

ss_status_t ss_actuator_run_f32(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                const ss_waveform_config_f32_t *wave, ss_waveform_state_f32_t *wst,
                                uint32_t n_steps, uint32_t decimation, ss_actuator_trace_f32_t *trace,
                                uint32_t *rows_out)
{
    if (cfg == NULL || st == NULL || wave == NULL || wst == NULL || rows_out == NULL) {
        return SS_ERR_NULL;
    }
    ss_actuator_run_job_f32_t job = {cfg, st, wave, wst, n_steps, decimation, trace, 0u, SS_OK};
    lane_t lane;
    if (lane_start(&lane, &job)) {
        while (lane_step(&lane)) {
        }
    }
    *rows_out = job.rows;
    return job.status;
}

/* ss_actuator_run_coarse_f32's loop, made twice: with stick steps (sticks 1) and without, so that
 * a run without them keeps the loop it had (the test in it cost 2 instructions a microsecond on
 * the M4F, LS 166 -> 168) */
SS_FORCE_INLINE ss_status_t coarse_loop(const ss_actuator_config_f32_t *cfg,
                                        const ss_actuator_coarse_f32_t *co, ss_actuator_state_f32_t *st,
                                        const ss_waveform_config_f32_t *wave, ss_waveform_state_f32_t *wst,
                                        ss_actuator_run_job_f32_t *job, uint32_t *steps_out, int sticks)
{
    lane_t lane;
    uint32_t model_steps = 0u;
    if (lane_start(&lane, job)) {
        uint32_t taken;
        do {
            job->status = coarse_step(cfg, co, st, wave, wst,
                                      (lane.to_row < lane.left) ? lane.to_row : lane.left, &taken, sticks);
            if (job->status != SS_OK) {
                break;
            }
            ++model_steps;
        } while (lane_after_steps(&lane, taken));
    }
    if (steps_out != NULL) {
        *steps_out = model_steps;
    }
    return job->status;
}

ss_status_t ss_actuator_run_coarse_f32(const ss_actuator_config_f32_t *cfg,
                                       const ss_actuator_coarse_f32_t *co, ss_actuator_state_f32_t *st,
                                       const ss_waveform_config_f32_t *wave, ss_waveform_state_f32_t *wst,
                                       uint32_t n_steps, uint32_t decimation, ss_actuator_trace_f32_t *trace,
                                       uint32_t *rows_out, uint32_t *steps_out)
{
    if (rows_out == NULL) {
        return SS_ERR_NULL;
    }
    /* ss_actuator_run_f32's lane: its checks and rows */
    ss_actuator_run_job_f32_t job = {cfg, st, wave, wst, n_steps, decimation, trace, 0u, SS_OK};
    const ss_status_t status = (co != NULL && co->stick_n != 0u)
                                   ? coarse_loop(cfg, co, st, wave, wst, &job, steps_out, 1)
                                   : coarse_loop(cfg, co, st, wave, wst, &job, steps_out, 0);
    *rows_out = job.rows;
    return status;
}

/* Simulations a batch steps side by side (ss_actuator_run_many_f32). */
#define SS_RUN_LANES 4

ss_status_t ss_actuator_run_many_f32(ss_actuator_run_job_f32_t *jobs, uint32_t n)
{
    if (jobs == NULL && n > 0u) {
        return SS_ERR_NULL;
    }
    ss_status_t out = SS_OK;
    lane_t lane[SS_RUN_LANES];
    carry_t carry[SS_RUN_LANES];
    parts_t parts[SS_RUN_LANES];
    int busy[SS_RUN_LANES] = {0};
    uint32_t next = 0u;
    for (;;) {
        int active = 0;
        for (int k = 0; k < SS_RUN_LANES; ++k) {
            while (!busy[k] && next < n) {
                busy[k] = lane_start(&lane[k], &jobs[next]);
                if (jobs[next++].status == SS_ERR_NULL) {
                    out = SS_ERR_NULL;
                }
            }
            active += busy[k];
        }
        if (active == 0) {
            return out;
        }
        /* Every busy lane's step, phase by phase: each phase of one simulation is a chain of
         * dependent operations, and the same phase of the others, independent of it, sits beside
         * it in the instruction stream for the core to overlap. Each lane's own operations are
         * those of lane_step, in its order. Until a lane ends, then it takes the next job. */
        int all = 1;
        while (all) {
            ss_status_t status[SS_RUN_LANES];
            int whole[SS_RUN_LANES] = {0};
            for (int k = 0; k < SS_RUN_LANES; ++k) {
                status[k] = busy[k] ? lane_start_step(&lane[k], &carry[k], &whole[k]) : SS_ERR_RANGE;
            }
            for (int k = 0; k < SS_RUN_LANES; ++k) {
                if (status[k] == SS_OK && !whole[k]) {
                    friction_begin(lane[k].job->cfg, lane[k].job->st, &carry[k], &parts[k]);
                }
            }
            for (int k = 0; k < SS_RUN_LANES; ++k) {
                if (status[k] == SS_OK && !whole[k]) {
                    friction_end(lane[k].job->cfg, lane[k].job->st, &carry[k], &parts[k]);
                }
            }
            for (int k = 0; k < SS_RUN_LANES; ++k) {
                if (!busy[k]) {
                    continue;
                }
                lane[k].job->status = status[k];
                if (status[k] != SS_OK) {
                    busy[k] = 0;
                } else if (whole[k]) {
                    busy[k] = lane_after_steps(&lane[k], 1u);
                } else {
                    const ss_actuator_config_f32_t *cfg = lane[k].job->cfg;
                    ss_friction_slopes_f32_t slopes;
                    const float f_free =
                        friction_force_parts(cfg, lane[k].job->st, &carry[k], &parts[k], &slopes);
                    step_finish(cfg, lane[k].job->st, &carry[k], f_free, &slopes);
                    busy[k] = lane_after_steps(&lane[k], 1u);
                }
                all = all && busy[k];
            }
        }
    }
}
