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

/* The drive after each of the next n steps (advance, then value), into out[0..n-1]: what
 * ss_actuator_run_f32 feeds the actuator, for a lock-step peer or a controller to send. */
ss_status_t ss_waveform_fill_f32(const ss_waveform_config_f32_t *cfg, ss_waveform_state_f32_t *st, float *out,
                                 uint32_t n);

/* Sawtooth shape alone: voltage at phase p in [0, 1) of a period. */
float ss_sawtooth_at_phase_f32(const ss_waveform_config_f32_t *cfg, float phase);

#endif /* SS_WAVEFORM_H */
