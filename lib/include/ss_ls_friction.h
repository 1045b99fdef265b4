/* LS friction (Liang et al.): a rate-independent Modified Maxwell-Slip presliding element
 * (Masing branches with a stack of reversal points: nonlocal memory, wiping-out) joined to a
 * LuGre sliding part driven by the gross-slip velocity (Stribeck curve in steady sliding).
 * The consistent form and every deviation from the printed equations: docs/model.md. */
#ifndef SS_LS_FRICTION_H
#define SS_LS_FRICTION_H

#include <stdint.h>
#include "ss_friction.h"

/* Presliding force (share of Fs) where gross slip, and with it the LuGre part, sets in. */
#define SS_LS_BREAKAWAY_RATIO 0.9f

/* Reversal points remembered; nested minor loops deeper than this lose their innermost loop. */
#define SS_LS_MEMORY_DEPTH 32

typedef struct {
    float x_m; /* reversal position in the element's local frame */
    float f_n; /* presliding force F_M at that point */
} ss_ls_reversal_f32_t;

typedef struct {
    float x_m;        /* relative displacement in the local frame (re-based in gross sliding) */
    float x0_m;       /* origin of the virgin curve in the local frame */
    float fm_n;       /* Masing presliding force F_M (level Fs), N */
    float kt_n_per_m; /* tangent stiffness dF_M/dx, N/m */
    float level_n;    /* break-away level s: Fs at rest, -> g(v) in gross sliding, N */
    float force_n;    /* total friction after the last step, N */
    float gate;       /* break-away gate of fm_n over gate_fs_n (kept: the next step and the force */
    float gate_fs_n;  /* ... need it again; Fs moves only under a position or thermal scale) */
    int8_t dir;       /* direction of the last motion: +1, -1, 0 before any motion */
    uint8_t depth;    /* reversal points on the stack */
    ss_ls_reversal_f32_t rev[SS_LS_MEMORY_DEPTH];
} ss_ls_state_f32_t;

ss_status_t ss_ls_init_f32(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st);

/* Advance by a relative displacement dx_m taken in dt_s, return the force in N.
 * The presliding part depends on the path of x only (rate independent); dt_s enters through
 * the slip velocity of the LuGre part and the viscous term. dt_s must be > 0. */
float ss_ls_step_f32(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st, float dx_m, float dt_s);

/* Advance the state over dx_m taken in dt_s without computing a force (the actuator asks for the
 * force at its own velocity with ss_ls_force_at_f32). Non-finite input changes nothing. */
void ss_ls_advance_f32(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st, float dx_m, float dt_s);

/* Force at the current state for a relative velocity v (N), and when slopes is not NULL its
 * slopes dF/dv (N s/m) and dF/dx ((level / Fs) times the Masing tangent stiffness, N/m). step() ends with
 * force_at(dx/dt); the actuator asks for the velocity at the end of its step instead (docs/model.md,
 * integrator). */
float ss_ls_force_at_f32(const ss_friction_config_f32_t *cfg, const ss_ls_state_f32_t *st, float v_m_per_s,
                         ss_friction_slopes_f32_t *slopes);

/* Apply n displacement increments dx_m[i] (each taken in dt_s) and write each force to force_n[i]. */
ss_status_t ss_ls_run_f32(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st, const float *dx_m,
                          uint32_t n, float dt_s, float *force_n);

#endif /* SS_LS_FRICTION_H */
