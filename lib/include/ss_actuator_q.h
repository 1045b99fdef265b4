/* The two-mass stick-slip actuator in fixed point: the same equations and the same kick-drift-kick
 * integrator (exact rod flow, implicit friction damping) as ss_actuator.h, in integer arithmetic.
 * The config holds the step's coefficients (rod flow matrix, kicks), computed on the host by
 * ss_actuator_config_to_q (ss_convert_q.h) or taken from ss_actuator_config_table1_q.
 * Formats, ranges and errors: docs/fixed-point.md. */
#ifndef SS_ACTUATOR_Q_H
#define SS_ACTUATOR_Q_H

#include <stdint.h>

#include "ss_effects_q.h"
#include "ss_friction_q.h"
#include "ss_ls_friction_q.h"
#include "ss_lugre_q.h"
#include "ss_waveform_q.h"

/* Values of friction_model, as ss_friction_kind_t of the float family (0 LS, 1 LuGre). */
#define SS_FRICTION_Q_LS 0
#define SS_FRICTION_Q_LUGRE 1

typedef struct {
    int32_t dt_q40;         /* fixed step, s at 2^-40: (2^16 (0.06 us), 2^31 (1.95 ms)) */
    int32_t piezo_gain_q48; /* ideal strain per volt, m/V at 2^-48: nonzero, |gain| < 7.6 um/V */
    int32_t friction_model; /* SS_FRICTION_Q_LS or SS_FRICTION_Q_LUGRE */
    int32_t lag_q24; /* c / (k dt): forced-response lag of the rod per strain increment, Q8.24 [0, 128) */
    uint32_t kick_rod_q40;   /* dt / (2 M_R): rod velocity per newton per half step, (m/s)/N at 2^-40, > 0 */
    int32_t kick_slider_q40; /* dt / (2 M_c): the same for the slider, > 0 */
    /* Exact rod flow over dt on (e, e' dt), e the rod's deviation from its forced response:
     * {phi00, phi01 / dt, phi10 dt, phi11} of the float family's phi, dimensionless, Q4.28 */
    int32_t phi_q28[4];
    ss_friction_config_q_t friction;
    /* 2^47 / dt_q40 rounded: 1/dt in 1/s at 2^-7, so the step multiplies where it divided by dt;
     * [2^16, 2^31). Where it sits, the effects (with an int64) start 8-byte aligned on every target */
    int32_t inv_dt_q47;
    ss_effects_config_q_t effects; /* load, slew limit, sensor scale; zeroed = off */
    /* sigma0 dt^2 / (12 M_R), Q2.30 in [0, 2^31): the rod's compliance the kicks leave out, times
     * the contact's largest stiffness (docs/model.md, "The rod seen through kicks") */
    int32_t contact_lag_q30;
    /* (w dt)^2 = k dt^2 / M_R, Q4.28 in [0, 2^28]: the rod mode over a step, with which a step takes
     * a drive that bends inside it (ss_actuator_step_corner_q); 0 takes the bend on the chord (steps
     * beyond (w dt)^2 = 1, 2.3 us for Table I, where the series the step uses no longer holds) */
    int32_t rod_w2dt2_q28;
} ss_actuator_config_q_t;

typedef struct {
    int64_t x_slider_q40;   /* slider position, m at 2^-40 (+-8.4e6 m; 0.91 pm resolution) */
    int32_t x_rod_q40;      /* rod position, m at 2^-40 (+-1.95 mm) */
    int32_t v_rod_q28;      /* rod velocity, m/s at 2^-28 (+-8 m/s) */
    int32_t v_slider_q28;   /* slider velocity, m/s at 2^-28 */
    int32_t x_p_q40;        /* piezo strain at the current time (after the hysteresis), m at 2^-40 */
    int32_t drive_q16;      /* drive at the current time, V in Q16.16 */
    int32_t force_q24;      /* friction on the slider (on the rod: minus it), N at 2^-24 */
    int64_t amp_q24;        /* voltage on the piezo (the slew-limited drive), V at 2^-24 */
    int32_t strain_q40;     /* ideal strain u before the hysteresis, m at 2^-40 */
    int32_t hysteresis_q40; /* Bouc-Wen hysteretic strain h (x_p = u - h), m at 2^-40 */
    int32_t x_base_q40;     /* base displacement (effects.base_kick_q40), m at 2^-40 */
    int32_t v_base_q28;     /* base velocity, m/s at 2^-28 */
    uint32_t steps;         /* steps taken since init */
    uint32_t pad;           /* zero; keeps the union 8-byte aligned on every target */
    union {
        ss_ls_state_q_t ls;
        ss_lugre_state_q_t lugre;
    } fr;
} ss_actuator_state_q_t;

/* Table I (LS friction, gain 44 nm/V, dt 1 us) as integer constants: exactly what
 * ss_actuator_config_to_q makes of ss_actuator_config_table1_f32() (checked by a test). */
ss_actuator_config_q_t ss_actuator_config_table1_q(void);

/* 2^47 / dt_q40 rounded (inv_dt_q47 of the config), 0 for a step outside dt_q40's range. */
int32_t ss_actuator_inv_dt_q47(int32_t dt_q40);

/* SS_OK or the first problem with cfg; *bad_field (when not NULL) names the field, e.g. "dt_q40"
 * or "friction.fc_q24". The rod flow matrix is not checked (it can only be computed on the host). */
ss_status_t ss_actuator_config_check_q(const ss_actuator_config_q_t *cfg, const char **bad_field);

/* Validate cfg and put the actuator at rest under drive0 (V in Q16.16). */
ss_status_t ss_actuator_init_q(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                               int32_t drive0_q16);

/* One step of dt, the drive going linearly from its current value to drive (V in Q16.16). */
ss_status_t ss_actuator_step_q(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                               int32_t drive_q16);

/* One step whose drive bends inside it, as ss_actuator_step_corner_f32: linear from its current
 * value to corner_q16 at corner_frac_q30 x dt (a share in (0, 2^30)), then linear to drive_q16. The
 * rod takes the bend by its response to the anchor's deviation from the chord, to second order in
 * (w dt)^2 (rod_w2dt2_q28; docs/fixed-point.md); the slew limit and the hysteresis take the step in
 * its two pieces. Taken on the chord, a corner inside a step put 0.08 % into a cycle's step at 1 us
 * (300 Hz, 15 us fall) and 0.27 % at 1.5 us. Bad corner_frac_q30: SS_ERR_RANGE, state unchanged. */
ss_status_t ss_actuator_step_corner_q(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                                      int32_t drive_q16, int32_t corner_frac_q30, int32_t corner_q16);

/* Coarse steps while the contact sticks, as ss_actuator_coarse_f32_t (docs/model.md), LuGre's and
 * LS's: the actuator's configs at n dt and at 2 dt, made with the bounds by ss_actuator_coarse_to_q
 * (ss_convert_q.h). As the float family's, a coarse step holds the friction in the rod's flow (LS's
 * split form: splits the rod's ring from it); a q config holds dt / 2 M_R within 32 bits up to 8.6
 * us for Table I's rod (n dt at most that, but for LS's split steps, which never kick the rod), and
 * a coarse step cut by a row is taken as 2 dt or not at all. */
typedef struct {
    ss_actuator_config_q_t cfg;     /* the actuator's config with dt_q40 the coarse step's */
    ss_actuator_config_q_t cfg_mid; /* ... and with dt_q40 2 dt: the middle step, and a coarse
                                     * step cut to 2 by a row */
    uint32_t n;                     /* steps of dt in a coarse step, [2, 64] */
    int32_t v_rel_max_q28;          /* the contact sticks: |v_rod - v_slider| below this, m/s at 2^-28 */
    int32_t ring_max_q40;           /* the rod is quiet: its travel at v_rod over n dt off the ideal strain's
                                     * change by less than this, m at 2^-40 (the ring bound times n dt) */
    int32_t ring_max_2_q40;         /* the same bound over 2 dt */
    int32_t v_rel_mid_max_q28;      /* a step of 2 dt: the contact rings, |v_rod - v_slider| below this */
    int32_t ring_mid_max_q40;       /* ... and the rod's travel off the strain's over 2 dt below this */
    int32_t compliance_q56;         /* 1 / k, the stack's compliance, m/N at 2^-56: the coarse step holds
                                     * the friction in the rod's flow; 0 (a stack softer than 33.6
                                     * MN/m): it kicks the rod as the fine step does (so with a base) */
    int32_t split;                  /* 1: LS's whole coarse steps take the split form (the float's
                                     * split_min_n, where the stack's compliance fits and no base asks
                                     * for the kicked form), else 0 */
    /* Stick steps (LuGre), as the float family's (ss_actuator_coarse_stick_f32): made by
     * ss_actuator_coarse_stick_to_q (ss_convert_q.h), all 0 when off */
    uint32_t stick_n;                /* steps of dt in a stick step, 0: none */
    int32_t stick_h_q40;             /* stick_n dt, s at 2^-40 */
    int32_t stick_inv_h_q47;         /* 1 / (stick_n dt), 1/s at 2^-7 */
    int32_t stick_omega_q47;         /* the rod's rate w = sqrt(k / M_R), 1/s at 2^-7 */
    int32_t stick_inv_omega_q40;     /* 1 / w, s at 2^-40: a velocity over w is a length */
    int32_t stick_lag_q30;           /* c / (k stick_n dt), Q1.30: the rod's lag behind the ramp */
    int32_t stick_v_rel_max_q28;     /* the contact is quiet: |v_rod - v_slider| below this */
    int32_t stick_ring_max_q40;      /* ... the rod too: its travel off the strain's over stick_n dt */
    int32_t stick_force_max_q24;     /* ... and |F| below this (SS_COARSE_STICK_FORCE_SHARE Fc) */
    int32_t stick_phi_shift;         /* stick_phi_q's fraction bits: |entries| <= 2^30 */
    int32_t stick_phi_q[16];         /* the float family's stick_phi, row-major, at 2^-stick_phi_shift */
    uint32_t edge_parts;             /* with stick steps: a fine step on a fast edge in this many parts, */
    int32_t edge_limit_q16;          /* ... one whose drive changes by more than this in dt (0.1 m/s) */
    int32_t edge_part_q30;           /* ... 1 / edge_parts in Q30: each part's share of the step */
    int32_t edge_pad;                /* zero */
    ss_actuator_config_q_t cfg_edge; /* ... each part's config: dt / edge_parts */
} ss_actuator_coarse_q_t;

/* Columns a run may record (any pointer may be NULL); formats as in the state. */
typedef struct {
    uint32_t *step;
    int32_t *drive_q16;
    int32_t *x_p_q40;
    int32_t *x_rod_q40;
    int64_t *x_slider_q40;
    int32_t *v_rod_q28;
    int32_t *v_slider_q28;
    int32_t *force_q24;
    int32_t *state_a;    /* LS: break-away level s (N at 2^-24);  LuGre: bristle z (m at 2^-40) */
    int32_t *state_b;    /* LS: presliding force F_M (N at 2^-24); LuGre: dz/dt (m/s at 2^-28) */
    int64_t *x_meas_q40; /* slider position as the sensor reports it (effects.sensor_scale_q30), m at 2^-40 */
    uint32_t capacity;   /* rows the buffers hold */
} ss_actuator_trace_q_t;

/* Put the slider at x (m at 2^-40; e.g. where a measured run starts). */
void ss_actuator_place_slider_q(ss_actuator_state_q_t *st, int64_t x_q40);

/* What the position sensor reports for a slider position (effects.sensor_scale_q30), m at 2^-40. */
int64_t ss_actuator_sensor_q(const ss_actuator_config_q_t *cfg, int64_t x_slider_q40);

/* Write the current state into row `row` of the trace (row < capacity is the caller's duty). */
void ss_actuator_record_q(const ss_actuator_config_q_t *cfg, const ss_actuator_state_q_t *st,
                          ss_actuator_trace_q_t *trace, uint32_t row);

/* Advance the waveform player one step and take that step, with the drive's corner if one lies
 * inside it (ss_waveform_corner_q): what ss_actuator_run_q and the node's free run do. */
ss_status_t ss_actuator_wave_step_q(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                                    const ss_waveform_config_q_t *wave, ss_waveform_state_q_t *wst);

/* Play a waveform through the actuator for n_steps, recording after every decimation-th step, as
 * ss_actuator_run_f32. rows_out gets the rows written. */
ss_status_t ss_actuator_run_q(const ss_actuator_config_q_t *cfg, ss_actuator_state_q_t *st,
                              const ss_waveform_config_q_t *wave, ss_waveform_state_q_t *wst,
                              uint32_t n_steps, uint32_t decimation, ss_actuator_trace_q_t *trace,
                              uint32_t *rows_out);

/* ss_actuator_run_q with coarse steps, as ss_actuator_run_coarse_f32: co may be NULL (none); a
 * coarse step never crosses a row; *steps_out (may be NULL) gets the model's steps. */
ss_status_t ss_actuator_run_coarse_q(const ss_actuator_config_q_t *cfg, const ss_actuator_coarse_q_t *co,
                                     ss_actuator_state_q_t *st, const ss_waveform_config_q_t *wave,
                                     ss_waveform_state_q_t *wst, uint32_t n_steps, uint32_t decimation,
                                     ss_actuator_trace_q_t *trace, uint32_t *rows_out, uint32_t *steps_out);

#endif /* SS_ACTUATOR_Q_H */
