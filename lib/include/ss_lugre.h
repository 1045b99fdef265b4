/* LuGre friction (Canudas de Wit et al. 1995), the baseline the LS paper compares with.
 * dz/dt = v - sigma0 |v| z / g(v),  F = sigma0 z + sigma1 dz/dt + sigma2 v.
 * The bristle update is exact for a velocity frozen over the step: docs/model.md. */
#ifndef SS_LUGRE_H
#define SS_LUGRE_H

#include <stdint.h>

#include "ss_friction.h"

typedef struct {
    float z_m;          /* mean bristle deflection */
    float zdot_m_per_s; /* dz/dt at the end of the last step */
    float force_n;      /* friction force after the last step */
} ss_lugre_state_f32_t;

ss_status_t ss_lugre_init_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st);

/* Advance by a relative displacement dx_m taken in dt_s (velocity dx/dt), return the force in N.
 * dt_s must be > 0; non-finite input leaves the state unchanged and returns the last force. */
float ss_lugre_step_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st, float dx_m,
                        float dt_s);

/* Advance the bristle over dx_m taken in dt_s without computing a force. Non-finite input changes
 * nothing. */
void ss_lugre_advance_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st, float dx_m,
                          float dt_s);

/* Force at the current state for a relative velocity v (N), and when slopes is not NULL its
 * slopes dF/dv (N s/m) and dF/dx (sigma0 dz/dx of the bristle's relaxation at v, N/m). step() ends with
 * force_at(dx/dt); the actuator asks for the velocity at the end of its step instead (docs/model.md,
 * integrator). */
float ss_lugre_force_at_f32(const ss_friction_config_f32_t *cfg, const ss_lugre_state_f32_t *st,
                            float v_m_per_s, ss_friction_slopes_f32_t *slopes);

/* Set st's force and dz/dt at relative velocity v_m_per_s from its z, and return the force: what a
 * step ends with, for a z the caller set (the actuator's stick step, ss_actuator.h). */
float ss_lugre_settle_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st, float v_m_per_s);

/* Apply n displacement increments dx_m[i] (each taken in dt_s) and write each force to force_n[i]. */
ss_status_t ss_lugre_run_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st, const float *dx_m,
                             uint32_t n, float dt_s, float *force_n);

#endif /* SS_LUGRE_H */
