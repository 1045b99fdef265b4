/* LS friction in fixed point: the same model as ss_ls_friction.h (Masing presliding element with
 * a reversal stack, LuGre sliding part driven by the gross slip), in integer arithmetic. The
 * exponentials go through ss_exp_neg_q32_q30; formats and error bounds: docs/fixed-point.md. */
#ifndef SS_LS_FRICTION_Q_H
#define SS_LS_FRICTION_Q_H

#include <stdint.h>

#include "ss_friction_q.h"

/* Same depth as the float family (SS_LS_MEMORY_DEPTH), kept apart so this header sees no float. */
#define SS_LS_Q_MEMORY_DEPTH 32

typedef struct {
    int32_t x_q40; /* reversal position in the local frame, m at 2^-40 */
    int32_t f_q24; /* presliding force F_M there, N at 2^-24 */
} ss_ls_reversal_q_t;

typedef struct {
    int32_t x_q40;     /* relative displacement in the local frame (re-based in gross sliding), m at 2^-40 */
    int32_t x0_q40;    /* origin of the virgin curve in the local frame, m at 2^-40 */
    int32_t fm_q24;    /* Masing presliding force F_M, N at 2^-24, |F_M| <= Fs */
    int32_t kt_q30;    /* tangent stiffness over sigma0, dF_M/dx / sigma0 in Q1.30, [0, 1] */
    int32_t level_q24; /* break-away level s: Fs at rest, -> g(v) in gross sliding, N at 2^-24 */
    int32_t force_q24; /* total friction after the last step, N at 2^-24 */
    /* the break-away gate of fm_q24 in Q30 and the Fs (N at 2^-24) it was taken at: kept, for the
     * next step and the force need it again (a config whose Fs moved makes it again) */
    int32_t gate_q30;
    int32_t gate_fs_q24;
    int8_t dir;    /* direction of the last motion: +1, -1, 0 before any motion */
    uint8_t depth; /* reversal points on the stack */
    ss_ls_reversal_q_t rev[SS_LS_Q_MEMORY_DEPTH];
} ss_ls_state_q_t;

ss_status_t ss_ls_init_q(const ss_friction_config_q_t *cfg, ss_ls_state_q_t *st);

/* Advance by dx (m at 2^-40) taken in dt (s at 2^-40, in (2^16, 2^31): 0.06 us to 1.95 ms), return
 * the force (N at 2^-24); a step outside that range changes nothing. */
int32_t ss_ls_step_q(const ss_friction_config_q_t *cfg, ss_ls_state_q_t *st, int32_t dx_q40, int32_t dt_q40);

/* Advance the state without computing a force, the step given by its reciprocal 2^47 / dt_q40
 * (1/s at 2^-7: the actuator config's inv_dt_q47), so that no division by dt is left in the step;
 * inv_dt_q47 <= 0 changes nothing. */
void ss_ls_advance_q(const ss_friction_config_q_t *cfg, ss_ls_state_q_t *st, int32_t dx_q40,
                     int32_t inv_dt_q47);

/* Force at the current state for relative velocity v (m/s at 2^-28), N at 2^-24, and when slopes
 * is not NULL its slopes: dF/dv, and dF/dx = (level / Fs) kt over sigma0 (ss_ls_force_at_f32). */
int32_t ss_ls_force_at_q(const ss_friction_config_q_t *cfg, const ss_ls_state_q_t *st, int32_t v_q28,
                         ss_friction_slopes_q_t *slopes);

/* n increments dx_q40[i], each in dt_q40; forces into force_q24[i]. */
ss_status_t ss_ls_run_q(const ss_friction_config_q_t *cfg, ss_ls_state_q_t *st, const int32_t *dx_q40,
                        uint32_t n, int32_t dt_q40, int32_t *force_q24);

#endif /* SS_LS_FRICTION_Q_H */
