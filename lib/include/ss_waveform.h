/* Drive waveforms: the sawtooth of stick-slip-dataset/1 (docs/data-format in ../shared) and an
 * arbitrary sampled drive, played at a fixed step. Time is kept as (period index, time within the
 * period) so a long run does not lose the edges to float rounding. */
#ifndef SS_WAVEFORM_H
#define SS_WAVEFORM_H

#include <stdint.h>
#include "ss_status.h"

typedef enum { SS_WAVE_SAWTOOTH = 0, SS_WAVE_SAMPLED = 1 } ss_waveform_kind_t;

typedef struct {
    int32_t kind; /* ss_waveform_kind_t */
    /* sawtooth */
    float frequency_hz;  /* (0, 1e6] */
    float amplitude_v;   /* finite, |A| <= 1e5 */
    float offset_v;      /* finite, |offset| <= 1e5 */
    float rise_fraction; /* (0, 1): slow edge share of the period */
    int32_t direction;   /* +1 slow rise then fast fall; -1 the period reversed in time */
    uint32_t cycles;     /* periods played; afterwards the drive holds offset_v */
    /* sampled: linear interpolation, held at the last sample after the end */
    const float *samples_v; /* caller-owned, n_samples >= 1 */
    uint32_t n_samples;
    float sample_interval_s; /* (0, 1e3] */
} ss_waveform_config_f32_t;

typedef struct {
    float period_s; /* sawtooth period or sample interval */
    float dt_s;     /* player step */
    float tau0_s;   /* time into the current period at j = 0 */
    uint32_t index; /* period (sawtooth) or sample (sampled) index */
    uint32_t j;     /* steps since tau0 */
    float peak_s;   /* time into a period of its inner corner (sawtooth: the peak; sampled: none, period_s) */
    float corner_s; /* time into the period of the next corner not yet passed (peak_s or period_s) */
} ss_waveform_state_f32_t;

ss_waveform_config_f32_t ss_waveform_sawtooth_f32(float frequency_hz, float amplitude_v, float offset_v,
                                                  float rise_fraction, int32_t direction, uint32_t cycles);

/* The paper's drive (LS paper, Fig. 13): 500 Hz, 100 V (4.4 um at 44 nm/V), offset 0, rise 0.95
 * (a 100 us fall), forward, 20 cycles. The q family's is ss_waveform_paper_q (ss_waveform_q.h). */
ss_waveform_config_f32_t ss_waveform_paper_f32(void);

/* Validate cfg and start the player at t = 0 with step dt_s. */
ss_status_t ss_waveform_init_f32(const ss_waveform_config_f32_t *cfg, float dt_s,
                                 ss_waveform_state_f32_t *st);

/* Drive voltage at the player's current time. */
float ss_waveform_value_f32(const ss_waveform_config_f32_t *cfg, const ss_waveform_state_f32_t *st);

/* Advance the player by one step. */
void ss_waveform_advance_f32(ss_waveform_state_f32_t *st);

/* Steps closer than this share of a step to a corner take it as on the step's end: the drive's
 * deviation from the chord is at most frac (1 - frac) of the step's slope change, and 0.1 % of a
 * step also hides the float rounding of where the corner is (an edge on the grid stays on it). */
#define SS_WAVEFORM_CORNER_MIN_FRAC 1e-3f

/* Where the drive bends inside the next step (the step ss_waveform_advance_f32 would take): 1 with
 * *frac_out in (0, 1), the corner's time as a share of the step, and *v_out the drive there; 0 when
 * the drive is one straight segment over the step (or bends within SS_WAVEFORM_CORNER_MIN_FRAC of
 * its ends). A sawtooth bends at its peak and at each period's start (and once more where the
 * last period ends and the drive holds), a sampled drive at each sample; a step is taken to hold at
 * most one corner (steps shorter than either edge and than the sample interval). */
int ss_waveform_corner_f32(const ss_waveform_config_f32_t *cfg, const ss_waveform_state_f32_t *st,
                           float *frac_out, float *v_out);

/* 1 when the drive is one straight segment over the next n steps (its next corner at or beyond
 * their end, within SS_WAVEFORM_CORNER_MIN_FRAC of a step, or the drive holding), else 0: where a
 * coarse step of n steps may be taken (ss_actuator_coarse_step_f32). n = 0 gives 1. */
int ss_waveform_straight_f32(const ss_waveform_config_f32_t *cfg, const ss_waveform_state_f32_t *st,
                             uint32_t n);

/* The drive's slope over the next step, V/s (the straight piece it lies on; 0 while holding). */
float ss_waveform_slope_f32(const ss_waveform_config_f32_t *cfg, const ss_waveform_state_f32_t *st);

/* The drive after each of the next n steps (advance, then value), into out[0..n-1]: what
 * ss_actuator_run_f32 feeds the actuator, for a lock-step peer or a controller to send. */
ss_status_t ss_waveform_fill_f32(const ss_waveform_config_f32_t *cfg, ss_waveform_state_f32_t *st, float *out,
                                 uint32_t n);

/* Sawtooth shape alone: voltage at phase p in [0, 1) of a period. */
float ss_sawtooth_at_phase_f32(const ss_waveform_config_f32_t *cfg, float phase);

#endif /* SS_WAVEFORM_H */
