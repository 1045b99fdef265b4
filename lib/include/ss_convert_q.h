/* Host-side bridge between the float (_f32) and fixed-point (_q) families: SI configs to q
 * configs (derived coefficients such as the rod flow matrix computed in double and rounded, every
 * value range-checked against its Q format), and q signals back to SI. Uses float and double, so
 * it is built into the host library only, never into the q-only firmware library. */
#ifndef SS_CONVERT_Q_H
#define SS_CONVERT_Q_H

#include <stdint.h>

#include "ss_actuator.h"
#include "ss_actuator_q.h"
#include "ss_qformat.h"

/* 2^n as a double, exact (n < 63): the scale of a Q format of ss_qformat.h. */
#define SS_QF_ONE(n) ((double)((int64_t)1 << (n)))

/* Scale factors of the q family (value in SI = integer * scale). */
#define SS_Q40_M (1.0 / SS_QF_ONE(SS_QF_LENGTH))         /* 2^-40: length (m) and time (s) */
#define SS_Q28_M_PER_S (1.0 / SS_QF_ONE(SS_QF_VELOCITY)) /* 2^-28: velocity (m/s) */
#define SS_Q24_N (1.0 / SS_QF_ONE(SS_QF_FORCE))          /* 2^-24: force (N) */
#define SS_Q16 (1.0 / SS_QF_ONE(SS_QF_VOLTAGE))          /* 2^-16: voltage (V), damping (N s/m) */
#define SS_Q48_M_PER_V (1.0 / SS_QF_ONE(SS_QF_GAIN))

/* The conversions below return SS_OK, SS_ERR_NULL, SS_ERR_NONFINITE or SS_ERR_RANGE. On error
 * *bad_field (when not NULL) names the float field whose value does not pass the float check or
 * does not fit its Q format, e.g. "friction.vs_m_per_s" or "rod_mass_kg" (kick_rod_q40 too big).
 * The q family has LS and LuGre only: friction_model SS_FRICTION_GMS is refused as "friction_model". */
ss_status_t ss_friction_config_to_q(const ss_friction_config_f32_t *in, ss_friction_config_q_t *out,
                                    const char **bad_field);
ss_status_t ss_actuator_config_to_q(const ss_actuator_config_f32_t *in, ss_actuator_config_q_t *out,
                                    const char **bad_field);
/* The q family's coarse steps for n steps of in's dt (ss_actuator_coarse_init_f32's rules and
 * bounds): out->cfg is ss_actuator_config_to_q of in at n dt. SS_ERR_RANGE with bad_field
 * "friction_model" (not LuGre) or "coarse_n", or the converter's own. */
ss_status_t ss_actuator_coarse_to_q(const ss_actuator_config_f32_t *in, uint32_t n,
                                    ss_actuator_coarse_q_t *out, const char **bad_field);
/* Turn out's stick steps on with stick_n steps of in's dt (out made by ss_actuator_coarse_to_q
 * from in), or off with stick_n 0: ss_actuator_coarse_stick_f32's flow and rules, converted. Its
 * errors, SS_ERR_RANGE "piezo_stiffness_n_per_m" for a stack too soft for the held form
 * (compliance_q56 0), and "coarse_stick_n" where a stick step's constants do not fit their
 * formats; out unchanged on an error. */
ss_status_t ss_actuator_coarse_stick_to_q(const ss_actuator_config_f32_t *in, uint32_t stick_n,
                                          ss_actuator_coarse_q_t *out, const char **bad_field);
/* A sawtooth (kind SS_WAVE_SAWTOOTH) only; frequency to whole mHz, volts to Q16.16. */
ss_status_t ss_waveform_config_to_q(const ss_waveform_config_f32_t *in, ss_waveform_config_q_t *out,
                                    const char **bad_field);

/* Volts to Q16.16, rounded and saturated (NaN gives 0). */
int32_t ss_volts_to_q16(double v);

/* The actuator's q state in SI units (double). */
typedef struct {
    double x_rod_m, v_rod_m_per_s;
    double x_slider_m, v_slider_m_per_s;
    double x_p_m, drive_v, force_n;
    double state_a; /* LS: level s (N); LuGre: z (m) */
    double state_b; /* LS: F_M (N); LuGre: dz/dt (m/s) */
    uint32_t steps;
} ss_actuator_si_t;

void ss_actuator_state_q_to_si(const ss_actuator_config_q_t *cfg, const ss_actuator_state_q_t *st,
                               ss_actuator_si_t *out);

#endif /* SS_CONVERT_Q_H */
