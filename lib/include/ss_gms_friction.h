/* GMS friction: the Generalized Maxwell-Slip model (Al-Bender, Lampaert, Swevers 2005) in its
 * rate-independent limit: SS_GMS_ELEMENTS Maxwell-slip (Iwan) elements in parallel whose slip
 * levels scale with a Stribeck-driven level s, plus viscous friction. Equations, the element
 * distribution and the slip-level law: docs/model.md, "GMS (third law)". Float family only. */
#ifndef SS_GMS_FRICTION_H
#define SS_GMS_FRICTION_H

#include <stdint.h>

#include "ss_friction.h"

/* Elements in parallel. Element i = 1..N has stiffness sigma0 / N and slip level
 * alpha_i s with alpha_i = (2i - 1) / N^2 (1/16, 3/16, 5/16, 7/16 for N = 4; they sum to 1), so
 * the break-away displacements alpha_i s N / sigma0 are the midpoints of N equal intervals of
 * [0, 2 s / sigma0]. The virgin curve (s = Fs) is the N-segment piecewise-linear form of the parabola
 * F = sigma0 u - sigma0^2 u^2 / (4 Fs): it meets the parabola at u = 2j Fs / (N sigma0), lies at
 * most Fs / (4 N^2) above it in between, and saturates at Fs from u = (2N - 1) Fs / (N sigma0) on. */
#define SS_GMS_ELEMENTS 4

/* Parameters: the shared ss_friction_config_f32_t. sigma1 is not used by GMS: its presliding is
 * purely elastic-plastic (rate independent) and its sliding force is the Stribeck curve itself. */
typedef struct {
    float f_n[SS_GMS_ELEMENTS]; /* element forces F_i = k_i (x - a_i), N; |F_i| <= alpha_i s. Kept
                                 * instead of the anchors a_i: bounded, so long travel loses nothing */
    float level_n;              /* slip level s, N: Fs at init, -> g(v) in gross sliding, held otherwise */
    float elastic_n;            /* sum of the element forces, N */
    float force_n;              /* total friction after the last step, N */
    int8_t sliding;             /* +1 / -1: every element slipped in the last step (gross sliding) */
} ss_gms_state_f32_t;

ss_status_t ss_gms_init_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st);

/* Advance by a relative displacement dx_m taken in dt_s, return the force in N.
 * Presliding depends on the path of x only; dt_s enters through the sliding velocity of the level
 * and the viscous term. dt_s must be > 0; non-finite input leaves the state unchanged and returns
 * the last force. */
float ss_gms_step_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st, float dx_m, float dt_s);

/* Advance the elements (and in gross sliding the level) over dx_m taken in dt_s without computing a
 * force. Non-finite input changes nothing. */
void ss_gms_advance_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st, float dx_m, float dt_s);

/* Force at the current state for a relative velocity v (N), and when slopes is not NULL its
 * slopes dF/dv (N s/m, sigma2: the elements do not depend on v) and dF/dx (the sticking
 * elements' stiffness, N/m). step() ends with
 * force_at(dx/dt); the actuator asks for the velocity at the end of its step. */
float ss_gms_force_at_f32(const ss_friction_config_f32_t *cfg, const ss_gms_state_f32_t *st, float v_m_per_s,
                          ss_friction_slopes_f32_t *slopes);

/* Apply n displacement increments dx_m[i] (each taken in dt_s) and write each force to force_n[i]. */
ss_status_t ss_gms_run_f32(const ss_friction_config_f32_t *cfg, ss_gms_state_f32_t *st, const float *dx_m,
                           uint32_t n, float dt_s, float *force_n);

#endif /* SS_GMS_FRICTION_H */
