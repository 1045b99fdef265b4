/* The two-mass stick-slip actuator of the LS paper, eqs. (7)-(9): a piezo spring k and damper c
 * drive the rod M_R, friction couples the rod to the slider M_c. Integrated at a fixed step by a
 * kick-drift-kick splitting whose drift is the exact flow of the linear rod: docs/model.md. */
#ifndef SS_ACTUATOR_H
#define SS_ACTUATOR_H

#include <stdint.h>
#include "ss_effects.h"
#include "ss_friction.h"
#include "ss_gms_friction.h"
#include "ss_ls_friction.h"
#include "ss_lugre.h"
#include "ss_waveform.h"

typedef enum { SS_FRICTION_LS = 0, SS_FRICTION_LUGRE = 1, SS_FRICTION_GMS = 2 } ss_friction_kind_t;

typedef struct {
    float piezo_stiffness_n_per_m; /* k, [1, 1e12] */
    float piezo_damping_kg_per_s;  /* c, [0, 1e6] */
    float rod_mass_kg;             /* M_R, [1e-9, 1e3] */
    float slider_mass_kg;          /* M_c, [1e-9, 1e3] */
    float piezo_gain_m_per_v;      /* ideal strain per volt, 0 < |gain| <= 1e-3 */
    float dt_s;                    /* fixed step, [1e-9, 1e-3] */
    int32_t friction_model;        /* ss_friction_kind_t */
    ss_friction_config_f32_t friction;
    ss_effects_config_f32_t effects; /* optional extensions, all off in a zeroed struct */
} ss_actuator_config_f32_t;

/* Position as an unevaluated sum hi + lo: micrometre steps over centimetres of travel stay exact
 * to well below a picometre in float arithmetic (compensated summation). */
typedef struct {
    float hi_m;
    float lo_m;
} ss_position_f32_t;

typedef struct {
    float x_rod_m, v_rod_m_per_s; /* rod position and velocity */
    ss_position_f32_t x_slider;   /* slider position */
    float v_slider_m_per_s;
    float x_p_m;    /* piezo strain at the current time (ideal gain * drive unless effects shape it) */
    float drive_v;  /* commanded drive voltage at the current time */
    float force_n;  /* friction on the slider (on the rod: -force_n) */
    uint32_t steps; /* steps taken since init */
    float phi[4];   /* rod flow over dt: [e, de/dt] -> phi * [e, de/dt] */
    ss_effects_state_f32_t fx; /* states of the optional effects */
    union {
        ss_ls_state_f32_t ls;
        ss_lugre_state_f32_t lugre;
        ss_gms_state_f32_t gms; /* float family only: the q converter refuses friction_model 2 */
    } fr;
} ss_actuator_state_f32_t;

/* Table I of the LS paper (LS friction, gain 44 nm/V so 100 V is the paper's 4.4 um), dt 1 us,
 * no effects. */
ss_actuator_config_f32_t ss_actuator_config_table1_f32(void);

/* SS_OK or the first problem with cfg; *bad_field (when not NULL) names the field, e.g.
 * "rod_mass_kg" or "friction.fc_n". */
ss_status_t ss_actuator_config_check_f32(const ss_actuator_config_f32_t *cfg, const char **bad_field);

/* Validate cfg and put the actuator at rest under drive0_v (rod at its static equilibrium). */
ss_status_t ss_actuator_init_f32(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                 float drive0_v);

/* One step of dt_s, the drive going linearly from its current value to drive_v.
 * A non-finite drive returns SS_ERR_NONFINITE and leaves the state unchanged. */
ss_status_t ss_actuator_step_f32(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                 float drive_v);

/* One step whose drive bends inside it: linear from its current value to corner_v at
 * corner_frac x dt (0 < corner_frac < 1), then linear to drive_v. The rod's flow is taken in the
 * two pieces (each exact), so a sawtooth's edge inside a step is not cut to the chord: with the
 * corner on the chord instead, a 15 us fall at a 2 us step put 0.5-0.9 % into a cycle's step
 * (docs/model.md). Costs two evaluations of the flow (cos, sin, exp), so on a target it is a
 * step that takes longer than the others. Bad corner_frac: SS_ERR_RANGE, state unchanged. */
ss_status_t ss_actuator_step_corner_f32(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                        float drive_v, float corner_frac, float corner_v);

/* Advance the waveform player one step and take that step, with the drive's corner if one lies
 * inside it (ss_waveform_corner_f32): what ss_actuator_run_f32 and the node's free run do. */
ss_status_t ss_actuator_wave_step_f32(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                      const ss_waveform_config_f32_t *wave, ss_waveform_state_f32_t *wst);

/* Coarse steps (issue 17, docs/model.md "Coarse steps while the contact sticks"): up to n steps of
 * dt taken as one step where that step is as accurate as the fine ones. That is where the contact
 * sticks and the rod's 69 kHz ring has died down and the drive is straight. A coarse step takes
 * the friction into the rod's exact flow, ramping from the force it starts with to the one the
 * contact's stiffness predicts, and kicks only the rest, so that it does not ring the rod (the fine
 * step's kicks, taken at 8 us, put 0.2-0.7 % into a cycle's step; held, 0.07 %). LuGre and LS (with
 * its turning point inside the step); not GMS. The bounds: the relative velocity (3.75 x Table I's
 * Stribeck velocity), and the rod's velocity off the piezo's ideal rate (0.11 nm of 69 kHz ring). */
#define SS_COARSE_V_REL_MAX_M_PER_S 1.5e-3f
#define SS_COARSE_V_RING_MAX_M_PER_S 5e-5f
/* Between a stick and a slip the contact rings at its 4 kHz mode (LuGre: on its bristles; LS: on
 * its presliding stiffness, through the whole slow edge): there a step of 2 dt, in the coarse
 * step's form, holds as well (the ring's 120 points a period at 1 us; the rod's 69 kHz mode turns
 * 0.87 rad in it). Its bounds: the relative velocity (below the slip after a fall, -21 mm/s on
 * the paper's drive) and the rod's ring (LuGre 0.46 nm, LS 1.15 nm: 0.5 mm/s, chosen with LS's
 * split steps of 8, docs/model.md "The split step"); each law's chosen on a grid inside the region
 * that holds 0.1 % over issue 17's drive matrix (docs/model.md). LS's own
 * coarse bounds: its slider rings on the contact through the slow edge (|v_rel| 1-4 mm/s), which
 * its coarse step takes in an exact flow (ss_actuator_f32.c, slider_flow), so that it needs no
 * stick, only a contact that rings within 3 mm/s, and a rod ring of 0.69 nm (0.3 mm/s). */
#define SS_COARSE_V_REL_MID_MAX_M_PER_S 5e-3f
#define SS_COARSE_V_RING_MID_MAX_M_PER_S 2e-4f
#define SS_COARSE_LS_V_REL_MID_MAX_M_PER_S 1e-2f
#define SS_COARSE_LS_V_RING_MID_MAX_M_PER_S 5e-4f
#define SS_COARSE_LS_V_RING_MAX_M_PER_S 3e-4f
#define SS_COARSE_LS_V_REL_MAX_M_PER_S 3e-3f
/* The bounds above lean on the coarse step's flows: the rod's force ramp (both laws) and LS's
 * slider flow. A coarse step that cannot take them (with a base it takes the fine step's form; an
 * LS contact as stiff as x = (1 + |asymmetry|) sigma0 (n dt)^2 / M_C >= 0.1, its stiffest, takes
 * the slider's kick-drift-kick; in the q family, a stack too soft for the held form) keeps the
 * bounds they were chosen with before
 * the flows: 1 mm/s and 0.05 mm/s, and 2 dt's LS 10 and 0.5 mm/s, LuGre's as above
 * (ss_actuator_coarse_kicked_bounds_f32). */
#define SS_COARSE_KICKED_V_REL_MAX_M_PER_S 1e-3f
#define SS_COARSE_KICKED_V_RING_MAX_M_PER_S 5e-5f
#define SS_COARSE_KICKED_LS_V_RING_MID_MAX_M_PER_S 5e-4f
/* The x = sigma0 (n dt)^2 / M_C below which LS's slider flow holds (its series to x^2); the q
 * family's is the same in Q30 (ss_actuator_q.c) */
#define SS_COARSE_FLOW_X_MAX 0.1f
/* ... and below which its series with one more term holds (the split steps' reach, 12 us on Table I
 * at x = 0.0996; the next term at most 6.3e-7) */
#define SS_COARSE_FLOW_X_LONG_MAX 0.4f
/* LS's coarse steps of this many dt or more take the split form (ss_actuator_f32.c, split_step_over:
 * the rod's ring split from its quasi-static part); 2 dt the held form */
#define SS_COARSE_SPLIT_MIN_N 3u
/* ... whose ring takes the rod's own flow: with a contact stiffer than this share of the stack the
 * coarse steps keep the kicked form's bounds (Table I: 0.048) */
#define SS_COARSE_SPLIT_RHO_MAX 0.1f

/* Made by ss_actuator_coarse_init_f32 from the actuator's config: init it again after a change of
 * the config's dt, piezo or rod (its flow is theirs). */
typedef struct {
    float phi[4];                 /* the rod's flow over n dt */
    float phi_mid[4];             /* ... and over 2 dt */
    float dt_s;                   /* n dt */
    uint32_t n;                   /* steps of dt in a coarse step, [2, 64] */
    float v_rel_max_m_per_s;      /* the contact sticks: |v_rod - v_slider| below this */
    float v_ring_max_m_per_s;     /* the rod is quiet: |v_rod - the piezo's ideal rate| below this */
    float v_rel_mid_max_m_per_s;  /* a step of 2 dt: the contact rings, |v_rod - v_slider| below this */
    float v_ring_mid_max_m_per_s; /* ... and the rod's ring below this */
    uint32_t stick_n;             /* steps of dt in a stick step, 0: none (ss_actuator_coarse_stick_f32) */
    float stick_dt_s;             /* stick_n dt */
    float stick_omega_per_s;      /* the rod's rate on the stack, sqrt(k / M_R) */
    uint32_t edge_parts;          /* with stick steps: a fine step on a fast edge in this many parts */
    float stick_phi[16];          /* the stuck contact's linear flow over stick_n dt, row-major, on the
                                   * deviation from the ramp's steady state of (e, v_rod / omega, z,
                                   * v_slider / omega): e the rod off the piezo's strain, z the bristle */
    uint32_t split_min_n;         /* LS: coarse steps of this many dt or more take the split form
                                   * (SS_COARSE_SPLIT_MIN_N), 0: none (a contact stiffer than
                                   * SS_COARSE_SPLIT_RHO_MAX of the stack, or LuGre) */
} ss_actuator_coarse_f32_t;

/* The coarse steps for n steps of cfg's dt, with the bounds above (chosen on Table I: LuGre at
 * dt = 1 us, n = 8, worst per-cycle error over issue 17's drive matrix 0.067 %, 0.275 model steps a
 * microsecond on the paper's drive; LS at 1.5 us, n = 8 in split steps, 0.071 %, 0.243 read before
 * each fast edge; bench/step_study.py --coarse N [--edge]). SS_ERR_RANGE with bad_field "friction_model" for
 * GMS, "coarse_n" for n outside [2, 64] or n dt past the config's range of dt; the config's own errors as
 * ss_actuator_config_check_f32. */
ss_status_t ss_actuator_coarse_init_f32(const ss_actuator_config_f32_t *cfg, uint32_t n,
                                        ss_actuator_coarse_f32_t *co, const char **bad_field);

/* Set co's bounds to the kicked form's (SS_COARSE_KICKED_*) for the friction model (ss_friction_kind_t):
 * what ss_actuator_coarse_init_f32 does where the flows cannot be taken, and the q converter for a
 * stack too soft for the held form. */
void ss_actuator_coarse_kicked_bounds_f32(ss_actuator_coarse_f32_t *co, int32_t friction_model);

/* Stick steps (LuGre; docs/model.md "Stick steps: the stuck contact's linear flow"): once the
 * contact has stopped ringing, a longer step than the coarse one. There the bristle deflects as the
 * relative displacement does (dz/dt = v - sigma0 |v| z / g(v) ~ v while sigma0 |z| << g: the
 * force is far below Fc), so rod, bristle and slider are a linear system: the rod on the stack's
 * spring and damper, the slider on the bristle's spring (sigma0) and damping (sigma1 + sigma2), the
 * anchor ramping with the straight drive and the load constant. Its exact flow over stick_n dt is
 * one 4 x 4 matrix, made once (ss_actuator_coarse_stick_f32); the step is that flow about the
 * ramp's steady state, then LuGre's force at the state it ends in. It is taken where stick_n steps
 * fit before the run's next row (rows every stick_n steps or a multiple), the drive is straight
 * over them, |v_rel| and the rod's ring are within the bounds below and |F| < 0.1 Fc. With them
 * LuGre's step can be LS's 1.5 us (n = 4, stick_n = 40; its fine steps on a fast edge in parts,
 * below): 0.154 model steps a microsecond on the paper's drive against the coarse steps' 0.275 at
 * 1 us, worst cycle over issue 17's drive matrix 0.056 % (bench/step_study.py --steps-us 1.5
 * --coarse 4 --stick 40; at 1 us with n = 8, 0.221 and 0.091 %). */
#define SS_COARSE_STICK_V_REL_MAX_M_PER_S 5e-4f
#define SS_COARSE_STICK_V_RING_MAX_M_PER_S 5e-5f
#define SS_COARSE_STICK_FORCE_SHARE 0.1f
/* A load at most this share of Fc (it holds the bristle off 0 all through the stick) */
#define SS_COARSE_STICK_LOAD_SHARE 0.01f
/* A run with stick steps takes a fine step that moves the piezo faster than 0.1 m/s (a 15 us fall,
 * not the paper's 100 us one) in this many parts, as GMS's fine step does: what lets LuGre's step
 * be 1.5 us there (bench/step_study.py --steps-us 1.5 --coarse 4 --stick 40: 0.056 % worst over
 * the drive matrix, 0.154 model steps a microsecond on the paper's drive). */
#define SS_COARSE_STICK_EDGE_PARTS 4u

/* Turn co's stick steps on with stick_n steps of dt each ((co->n, 256], stick_n dt <= 1 ms), or off
 * with stick_n 0, for cfg (the config co was made for). SS_ERR_RANGE with bad_field
 * "friction_model" for a law other than LuGre, "coarse_stick_n" for stick_n out of range, the first
 * effect the linear flow does not hold (every one but the sensor's scale and a load within
 * SS_COARSE_STICK_LOAD_SHARE Fc, and an asymmetry): e.g. "effects.slew_v_per_s" or
 * "effects.load_n"; co unchanged on an error. */
ss_status_t ss_actuator_coarse_stick_f32(const ss_actuator_config_f32_t *cfg, uint32_t stick_n,
                                         ss_actuator_coarse_f32_t *co, const char **bad_field);

/* Advance by one step of cfg's dt, or by m = min(co->n, max_steps) >= 2 of them in one coarse step
 * where the drive is straight over them (ss_waveform_straight_f32), the contact sticks and the rod
 * is quiet (max_steps: so that a run can end, or record a row, on its grid; a step shorter than
 * co->n and 2 makes its rod flow on the way), or by 2 of them where the contact rings within the
 * middle bounds. *taken gets the steps of dt taken (st->steps counts them too). co may be NULL:
 * always one step. */
ss_status_t ss_actuator_coarse_step_f32(const ss_actuator_config_f32_t *cfg,
                                        const ss_actuator_coarse_f32_t *co, ss_actuator_state_f32_t *st,
                                        const ss_waveform_config_f32_t *wave, ss_waveform_state_f32_t *wst,
                                        uint32_t max_steps, uint32_t *taken);

/* Put the slider at x_m (e.g. where a measured run starts; position-dependent friction sees it). */
void ss_actuator_place_slider_f32(ss_actuator_state_f32_t *st, float x_m);

/* The stored frictional heat of thermal_drift, J (ss_effects_state_f32_t.heat_j): read at the end
 * of a run and given to the next, so that runs recorded one after another carry their heat over
 * (init starts cold). A negative or non-finite heat_j is taken as 0. */
float ss_actuator_heat_f32(const ss_actuator_state_f32_t *st);
void ss_actuator_set_heat_f32(ss_actuator_state_f32_t *st, float heat_j);

float ss_position_value_f32(ss_position_f32_t p);

/* Columns a run may record; any pointer may be NULL. */
typedef struct {
    uint32_t *step;
    float *drive_v;
    float *x_p_m;
    float *x_rod_m;
    float *x_slider_m;
    float *v_rod_m_per_s;
    float *v_slider_m_per_s;
    float *force_n;
    float *state_a;    /* LS: break-away level s (N);    LuGre: bristle z (m);    GMS: slip level s (N) */
    float *state_b;    /* LS: presliding force F_M (N); LuGre: dz/dt (m/s); GMS: elastic force sum F_i (N) */
    float *x_meas_m;   /* slider position as the sensor reports it (effects.sensor_scale_error) */
    uint32_t capacity; /* rows the buffers hold */
} ss_actuator_trace_f32_t;

/* Write the current state into row `row` of the trace (row < capacity is the caller's duty). */
void ss_actuator_record_f32(const ss_actuator_config_f32_t *cfg, const ss_actuator_state_f32_t *st,
                            ss_actuator_trace_f32_t *trace, uint32_t row);

/* Play a waveform through the actuator for n_steps, recording the state after every
 * decimation-th step (rows 0.. n_steps/decimation - 1; the state before the run is not recorded).
 * rows_out gets the rows written. Stops at the first error (rows so far are kept). */
ss_status_t ss_actuator_run_f32(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st,
                                const ss_waveform_config_f32_t *wave, ss_waveform_state_f32_t *wst,
                                uint32_t n_steps, uint32_t decimation, ss_actuator_trace_f32_t *trace,
                                uint32_t *rows_out);

/* ss_actuator_run_f32 with coarse steps (co: ss_actuator_coarse_init_f32): the same rows on the
 * same grid of dt (a coarse step never crosses a row); the steps of the model are fewer. *steps_out
 * (may be NULL) gets the steps the model took, fine and coarse. */
ss_status_t ss_actuator_run_coarse_f32(const ss_actuator_config_f32_t *cfg,
                                       const ss_actuator_coarse_f32_t *co, ss_actuator_state_f32_t *st,
                                       const ss_waveform_config_f32_t *wave, ss_waveform_state_f32_t *wst,
                                       uint32_t n_steps, uint32_t decimation, ss_actuator_trace_f32_t *trace,
                                       uint32_t *rows_out, uint32_t *steps_out);

/* One simulation of a batch (ss_actuator_run_many_f32): the arguments of ss_actuator_run_f32,
 * and its results. trace may be NULL. */
typedef struct {
    const ss_actuator_config_f32_t *cfg;
    ss_actuator_state_f32_t *st;
    const ss_waveform_config_f32_t *wave;
    ss_waveform_state_f32_t *wst;
    uint32_t n_steps;
    uint32_t decimation;
    ss_actuator_trace_f32_t *trace;
    uint32_t rows;      /* out: rows written */
    ss_status_t status; /* out: what ss_actuator_run_f32 would have returned */
} ss_actuator_run_job_f32_t;

/* Run n independent simulations, each with exactly the arithmetic of ss_actuator_run_f32 (the
 * same bits), four at a time, their steps interleaved phase by phase (the kick and drift, the
 * friction law's advance in two parts, its force and the closing kick). A phase is a chain of
 * dependent float operations and data-dependent branches; the same phase of three independent
 * simulations beside it keeps the core's execution units busy while it waits: on an x86-64 host
 * a dataset's 13 runs take 0.53 (LuGre) to 0.94 (GMS) x the time they take one after the other
 * (BENCHMARKS.md). A finished
 * simulation's slot takes the next job. Returns SS_OK,
 * or SS_ERR_NULL for a NULL jobs (n > 0) or a job missing cfg, st, wave or wst (that job's status
 * says so; the others still run); each job's own outcome is in its status. */
ss_status_t ss_actuator_run_many_f32(ss_actuator_run_job_f32_t *jobs, uint32_t n);

#endif /* SS_ACTUATOR_H */
