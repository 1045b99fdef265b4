/* LuGre friction in fixed point: the same model as ss_lugre.h (bristle update exact for a
 * velocity frozen over the step), in integer arithmetic. Formats: docs/fixed-point.md. */
#ifndef SS_LUGRE_Q_H
#define SS_LUGRE_Q_H

#include <stdint.h>

#include "ss_friction_q.h"

typedef struct {
    int32_t z_q40;     /* mean bristle deflection, m at 2^-40 (|z| <= Fs/sigma0) */
    int32_t zdot_q28;  /* dz/dt at the end of the last step, m/s at 2^-28 */
    int32_t force_q24; /* friction after the last step, N at 2^-24 */
} ss_lugre_state_q_t;

ss_status_t ss_lugre_init_q(const ss_friction_config_q_t *cfg, ss_lugre_state_q_t *st);

/* Advance by dx (m at 2^-40) taken in dt (s at 2^-40, in (2^16, 2^31): 0.06 us to 1.95 ms), return
 * the force (N at 2^-24); a step outside that range changes nothing. */
int32_t ss_lugre_step_q(const ss_friction_config_q_t *cfg, ss_lugre_state_q_t *st, int32_t dx_q40,
                        int32_t dt_q40);

/* Advance the bristle without computing a force, the step given by its reciprocal 2^47 / dt_q40
 * (1/s at 2^-7: the actuator config's inv_dt_q47); inv_dt_q47 <= 0 or dx_q40 == 0 changes nothing. */
void ss_lugre_advance_q(const ss_friction_config_q_t *cfg, ss_lugre_state_q_t *st, int32_t dx_q40,
                        int32_t inv_dt_q47);

/* Force at the current state for relative velocity v (m/s at 2^-28), N at 2^-24, and when slopes
 * is not NULL its slopes: dF/dv, and dF/dx = dz/dx of the relaxation at v, over sigma0
 * (ss_lugre_force_at_f32). */
int32_t ss_lugre_force_at_q(const ss_friction_config_q_t *cfg, const ss_lugre_state_q_t *st, int32_t v_q28,
                            ss_friction_slopes_q_t *slopes);

/* Set st's force and dz/dt at relative velocity v (m/s at 2^-28) from its z, and return the force
 * (ss_lugre_settle_f32). */
int32_t ss_lugre_settle_q(const ss_friction_config_q_t *cfg, ss_lugre_state_q_t *st, int32_t v_q28);

/* n increments dx_q40[i], each in dt_q40; forces into force_q24[i]. */
ss_status_t ss_lugre_run_q(const ss_friction_config_q_t *cfg, ss_lugre_state_q_t *st, const int32_t *dx_q40,
                           uint32_t n, int32_t dt_q40, int32_t *force_q24);

#endif /* SS_LUGRE_Q_H */
