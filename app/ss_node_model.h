/* The node's model adapter: the one place that knows which family the node runs. Built once per
 * family (CMake picks ss_node_model_f32.c for stickslip_app, ss_node_model_q.c for stickslip_app_q,
 * which also defines SS_NODE_MODEL_Q so that users see the q types); the rest of the application
 * speaks float32 volts and SI telemetry, as the protocol does (docs/protocol.md, the fixed-point
 * node, for the q family's conversions). */
#ifndef SS_NODE_MODEL_H
#define SS_NODE_MODEL_H

#include <stdint.h>

#include "ss_actuator.h"
#include "ss_actuator_q.h"

/* HELLO reports SS_NODE_VARIANT (0 float32, 1 fixed point). */
#ifdef SS_NODE_MODEL_Q
#define SS_NODE_VARIANT 1u
typedef ss_actuator_config_q_t ss_node_config_t;
typedef ss_actuator_state_q_t ss_node_state_t;
typedef ss_waveform_config_q_t ss_node_wave_t;
typedef ss_waveform_state_q_t ss_node_wave_state_t;
typedef int32_t ss_node_drive_t; /* V in Q16.16 */
#else
#define SS_NODE_VARIANT 0u
typedef ss_actuator_config_f32_t ss_node_config_t;
typedef ss_actuator_state_f32_t ss_node_state_t;
typedef ss_waveform_config_f32_t ss_node_wave_t;
typedef ss_waveform_state_f32_t ss_node_wave_state_t;
typedef float ss_node_drive_t; /* V */
#endif

/* The state as a telemetry row or a CAN state sends it: float32, SI. */
typedef struct {
    uint32_t steps;
    float drive_v, x_rod_m, x_slider_hi_m, x_slider_lo_m, force_n;
} ss_node_row_t;

/* A float32 drive in volts as the model takes it (q: Q16.16, ss_volts_to_q16's rounding). */
ss_node_drive_t ss_node_model_drive_from_v(float v);

/* The step the model runs, in seconds (HELLO), and in femtoseconds (the paced run's clock:
 * integer from here on; f32: dt_s x 1e15 rounded in float32, 0.06 ppm; q: dt_q40 x 10^15 / 2^40,
 * exact to 1 fs). */
float ss_node_model_dt_s(const ss_node_config_t *cfg);
uint64_t ss_node_model_dt_fs(const ss_node_config_t *cfg);

/* Table I in the family's form (q: integer constants, the same on every target). */
ss_node_config_t ss_node_model_default_config(void);

/* The family's config for a float config, checked (q: through the host converter); on refusal
 * *why names the field. */
ss_status_t ss_node_model_config(const ss_actuator_config_f32_t *f, ss_node_config_t *out, const char **why);

void ss_node_model_init(const ss_node_config_t *cfg, ss_node_state_t *st, ss_node_drive_t d);
void ss_node_model_step(const ss_node_config_t *cfg, ss_node_state_t *st, ss_node_drive_t d);
ss_node_row_t ss_node_model_row(const ss_node_state_t *st);
/* Put the slider at x_m (where a measured run starts; q: rounded to 2^-40 m in double). */
void ss_node_model_place_slider(ss_node_state_t *st, float x_m);

/* The sawtooth player in the family's form. */
ss_status_t ss_node_model_wave_convert(const ss_waveform_config_f32_t *w, ss_node_wave_t *out,
                                       const char **why);
ss_status_t ss_node_model_wave_init(const ss_node_config_t *cfg, const ss_node_wave_t *w,
                                    ss_node_wave_state_t *ws);
ss_node_drive_t ss_node_model_wave_value(const ss_node_wave_t *w, const ss_node_wave_state_t *ws);
/* Advance the player a step and step the model to its drive (f32: with the drive's corner when
 * one falls inside the step, as the batch simulator's run does; q: to the step's end value). */
void ss_node_model_wave_step(const ss_node_config_t *cfg, ss_node_state_t *st, const ss_node_wave_t *w,
                             ss_node_wave_state_t *ws);

#endif /* SS_NODE_MODEL_H */
