/* The sawtooth drive in fixed point: a 64-bit phase accumulator (bit-exact period boundaries on
 * every target) and voltages in Q16.16. The float family's sampled drive has no q counterpart:
 * a sampled drive is fed to ss_actuator_step_q sample by sample. Formats: docs/fixed-point.md. */
#ifndef SS_WAVEFORM_Q_H
#define SS_WAVEFORM_Q_H

#include <stdint.h>

#include "ss_status.h"

typedef struct {
    uint32_t frequency_mhz; /* mHz: (0, 2^32), i.e. up to 4.29 MHz; a period must be longer than dt */
    int32_t amplitude_q16;  /* V in Q16.16 (+-32768 V) */
    int32_t offset_q16;     /* V in Q16.16 */
    uint32_t rise_q32;      /* slow-edge share of the period, fraction at 2^-32: (0, 2^32) */
    int32_t direction;      /* +1 slow rise then fast fall; -1 the period reversed in time */
    uint32_t cycles;        /* periods played; afterwards the drive holds offset */
} ss_waveform_config_q_t;

typedef struct {
    uint64_t phase_q64; /* time into the current period, fraction of the period at 2^-64 */
    uint64_t step_q64;  /* phase increment per step: f dt 2^64, rounded */
    uint32_t index;     /* period index */
    /* the rise's and the fall's shares of the period (at 2^-32) as reciprocal mantissas with their
     * shifts (ss_reciprocal_mantissa_q; 0 for a share of 2^-32), made by init from the config's
     * rise_q32: the drive's value without a division. Init again after a change of rise_q32. */
    uint32_t rise_recip;
    uint32_t fall_recip;
    uint8_t rise_shift;
    uint8_t fall_shift;
    uint16_t pad; /* zero; keeps the size a multiple of 8 on every target */
} ss_waveform_state_q_t;

ss_waveform_config_q_t ss_waveform_sawtooth_q(uint32_t frequency_mhz, int32_t amplitude_q16,
                                              int32_t offset_q16, uint32_t rise_q32, int32_t direction,
                                              uint32_t cycles);

/* The paper's drive (ss_waveform_paper_f32) in integer constants, what ss_waveform_config_to_q
 * makes of it (checked by tests/c/test_fixed_model.c): 500000 mHz, 100 V in Q16.16, offset 0, rise
 * 4080218880 (the float32 0.95f is 15938355 x 2^-24, exact at 2^-32; round(0.95 x 2^32) would
 * move the fall edge), forward, 20 cycles. */
ss_waveform_config_q_t ss_waveform_paper_q(void);

/* Validate cfg (SS_ERR_RANGE also when a period is not longer than the step) and start the player
 * at t = 0 with step dt (s at 2^-40, > 0). */
ss_status_t ss_waveform_init_q(const ss_waveform_config_q_t *cfg, int32_t dt_q40, ss_waveform_state_q_t *st);

/* Drive voltage at the player's current time, V in Q16.16 (saturated). */
int32_t ss_waveform_value_q(const ss_waveform_config_q_t *cfg, const ss_waveform_state_q_t *st);

/* Advance the player by one step. */
void ss_waveform_advance_q(ss_waveform_state_q_t *st);

/* Advance the player by n steps: the phase and period index of n calls of ss_waveform_advance_q,
 * in one product where n steps are less than a period. */
void ss_waveform_advance_by_q(ss_waveform_state_q_t *st, uint32_t n);

/* Where the drive bends inside the next step (the one ss_waveform_advance_q would take), as
 * ss_waveform_corner_f32: 1 with *frac_q30 in (0, 2^30), the corner's time as a share of the step,
 * and *v_q16 the drive there; 0 when the drive is one straight segment over the step, bends within
 * 2^-10 of a step of its ends (the float family's 1e-3: an edge on the grid stays on it), or holds.
 * A sawtooth bends at its peak and at each period's start. */
int ss_waveform_corner_q(const ss_waveform_config_q_t *cfg, const ss_waveform_state_q_t *st,
                         int32_t *frac_q30, int32_t *v_q16);

/* 1 when the drive is one straight piece over the next n steps (its next corner at or beyond their
 * end, within 2^-10 of a step, or the drive holding), as ss_waveform_straight_f32; else 0. */
int ss_waveform_straight_q(const ss_waveform_config_q_t *cfg, const ss_waveform_state_q_t *st, uint32_t n);

/* The drive after each of the next n steps (advance, then value), into out_q16[0..n-1]. */
ss_status_t ss_waveform_fill_q(const ss_waveform_config_q_t *cfg, ss_waveform_state_q_t *st, int32_t *out_q16,
                               uint32_t n);

/* Sawtooth shape alone: voltage (Q16.16) at phase p (fraction of a period at 2^-32). */
int32_t ss_sawtooth_at_phase_q(const ss_waveform_config_q_t *cfg, uint32_t phase_q32);

#endif /* SS_WAVEFORM_Q_H */
