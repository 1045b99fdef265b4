/* GMS friction: the Generalized Maxwell-Slip model (Al-Bender, Lampaert, Swevers 2005) with slip
 * at once (its attraction rate taken to infinity): SS_GMS_ELEMENTS Maxwell-slip (Iwan) elements in
 * parallel whose slip levels scale with a Stribeck-driven level s, micro-damping on the elements
 * that stick, plus viscous friction. Equations, the element distribution and the slip-level law:
 * docs/model.md, "GMS (third law)". Float family only. */
#ifndef SS_GMS_FRICTION_H
#define SS_GMS_FRICTION_H

#include <stdint.h>

#include "ss_friction.h"

/* Elements in parallel. Element i = 1..N has slip level alpha_i s (the alpha_i sum to 1) and, with
 * equal stiffnesses (cfg->gms_stiffness_ratio rho = 1, the default), stiffness sigma0 / N. They then
 * discretise a virgin curve whose tangent stiffness decays as sigma0 (1 - u / u_s)^d,
 * d = cfg->gms_decay, u_s = (d + 1) Fs / sigma0: element i breaks away where that stiffness falls to
 * c_i = 1 - (2i - 1) / (2N) of sigma0, so alpha_i is proportional to 1 - c_i^(1/d). d = 1 (the
 * default): alpha_i = (2i - 1) / N^2 (1/16, 3/16, 5/16, 7/16), the piecewise-linear form of the
 * parabola F = sigma0 u - sigma0^2 u^2 / (4 Fs), saturated from u = 1.75 Fs / sigma0 on; d -> 0 one
 * elastic-plastic break-away at Fs / sigma0; large d LS's exponential. With rho != 1 the stiffnesses
 * run in a geometric progression, k_{i+1} = rho k_i, summing to sigma0, and each element keeps the
 * break-away displacement's place in that order (proportional to 1 - c_i^(1/d)), so alpha_i is
 * proportional to k_i (1 - c_i^(1/d)): rho < 1 puts the stiffness in the elements that break first
 * (a steeper initial fall of the tangent stiffness and a softer tail). docs/model.md, "GMS". */
#define SS_GMS_ELEMENTS 4

/* Parameters: the shared ss_friction_config_f32_t, gms_decay and gms_stiffness_ratio its own. sigma1
 * damps the elements that stick (sigma1 k_i / sigma0 each, original GMS's sigma_i; sigma1 / N for
 * equal stiffnesses): sigma1 = 0 makes presliding exactly rate independent. An element's damping
 * switches on and off inside steps; the step's account of it (the stuck displacement) keeps its
 * impulse exact over the steps around the switch (docs/model.md, "Micro-damping"). */
typedef struct {
    float f_n[SS_GMS_ELEMENTS];     /* element forces F_i = k_i (x - a_i), N; |F_i| <= alpha_i s. Kept
                                     * instead of the anchors a_i: bounded, so long travel loses nothing */
    float share[SS_GMS_ELEMENTS];   /* alpha_i, from gms_decay and gms_stiffness_ratio at init */
    float kscale[SS_GMS_ELEMENTS];  /* k_i / (sigma0 / N): 1 each for equal stiffnesses, at init */
    float stuck_m[SS_GMS_ELEMENTS]; /* the step so far: relative displacement while element i stuck, m */
    float level_n;         /* slip level s, N: Fs at init, -> g(v) in gross sliding, held otherwise */
    float elastic_n;       /* sum of the element forces, N */
    float force_n;         /* total friction after the last step, N */
    float v_start_m_per_s; /* relative velocity the step started from (the last force's), m/s */
    float step_s;          /* the step so far, s */
    uint8_t damped_start;  /* bit i: element i was damped at the step's start */
    int8_t sliding;        /* +1 / -1: every element slipped in the last step (gross sliding) */
} ss_gms_state_f32_t;

ss_status_t ss_gms_init_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st);

/* Advance by a relative displacement dx_m taken in dt_s, return the force in N.
 * Presliding depends on the path of x only; dt_s enters through the sliding velocity of the level
 * and the viscous term. dt_s must be > 0; non-finite input leaves the state unchanged and returns
 * the last force. */
float ss_gms_step_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st, float dx_m, float dt_s);

/* The element shares alpha_i and stiffnesses k_i / (sigma0 / N) (kscale) for a decay exponent d and
 * a stiffness ratio rho, both in [0.05, 20] (as init computes them). */
void ss_gms_shares_f32(float decay, float stiffness_ratio, float share[SS_GMS_ELEMENTS],
                       float kscale[SS_GMS_ELEMENTS]);

/* Advance the elements (and in gross sliding the level) over dx_m taken in dt_s without computing a
 * force: one step, begun from the velocity dx_m / dt_s. Non-finite input changes nothing. */
void ss_gms_advance_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st, float dx_m, float dt_s);

/* A step in pieces (the actuator's, split where the motion turned): begin it from the relative
 * velocity the last force was taken at, then advance piece by piece. */
void ss_gms_begin_step_f32(ss_gms_state_f32_t *st, float v_start_m_per_s);
void ss_gms_advance_piece_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st, float dx_m,
                              float dt_s);

/* Force at the current state for a relative velocity v (N) at the end of the step, and when slopes is
 * not NULL its slopes dF/dv (N s/m: sigma2 and the micro-damping of the elements that stick at v)
 * and dF/dx (the sticking elements' stiffness, N/m). An element sticks unless it sits at its slip
 * level and v carries it further. step() ends with
 * force_at(dx/dt); the actuator asks for the velocity at the end of its step. */
float ss_gms_force_at_f32(const ss_friction_config_f32_t *cfg, const ss_gms_state_f32_t *st, float v_m_per_s,
                          ss_friction_slopes_f32_t *slopes);

/* Apply n displacement increments dx_m[i] (each taken in dt_s) and write each force to force_n[i]. */
ss_status_t ss_gms_run_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st, const float *dx_m,
                           uint32_t n, float dt_s, float *force_n);

#endif /* SS_GMS_FRICTION_H */
