/* Fixed-point (_q) parameters of the friction models and the Stribeck curve
 * g(v) = Fc + (Fs - Fc) exp(-(v/vs)^2). Integer arithmetic only; formats: docs/fixed-point.md.
 * Units of the q family: length 2^-40 m (_q40), time 2^-40 s (_q40), velocity 2^-28 m/s (_q28),
 * force 2^-24 N (_q24), damping Q16.16 N s/m (_q16), ratios Q1.30 (_q30); the shifts: ss_qformat.h. */
#ifndef SS_FRICTION_Q_H
#define SS_FRICTION_Q_H

#include <stdint.h>

#include "ss_qformat.h"
#include "ss_status.h"

/* Largest static friction the q family takes: forces are int32 at 2^-24 N (+-128 N), and the
 * total friction adds damping terms to the presliding force, so Fs keeps a factor 4 headroom. */
#define SS_Q_FS_MAX_Q24 ((int32_t)32 << 24)

/* Longest presliding length the element may need before it re-bases its frame (24 Fs/sigma0):
 * 2^28 x 2^-40 m = 0.24 mm keeps the local frame far inside int32 (+-1.95 mm). */
#define SS_Q_SAT_LENGTH_MAX_Q40 ((int64_t)1 << 28)

/* Presliding lengths Fs/sigma0 after which the LS virgin curve is Fs exactly in Q30 (exp(-24) is
 * 0.04 LSB), so its frame re-bases without changing any force (the float family's constant). */
#define SS_LS_Q_SATURATION_LENGTHS 24

/* |asymmetry| at most 0.9 (the float range), in Q2.30: ceil(0.9 x 2^30). */
#define SS_Q_ASYMMETRY_MAX_Q30 966367642

/* Fs/Fc at most this: the ratio s/g (<= Fs/Fc) times a velocity must fit 64-bit intermediates. */
#define SS_Q_FS_OVER_FC_MAX 64

/* Shortest Stribeck velocity and softest contact, exclusive, for which the config's reciprocals
 * (2^45 / vs_q28, 2^47 / sigma0) fit 31 bits: 2^14 at 2^-28 m/s is 61 um/s, 2^16 N/m 65.5 kN/m. */
#define SS_Q_VS_MIN_Q28 ((int32_t)1 << 14)
/* ... and the smallest static friction, exclusive, for 2^48 / fs_q24: 2^17 at 2^-24 N is 7.8 mN. */
#define SS_Q_FS_MIN_Q24 ((int32_t)1 << 17)
#define SS_Q_SIGMA0_MIN_N_PER_M ((int32_t)1 << 16)

typedef struct {
    int32_t fs_q24;         /* static friction Fs, N at 2^-24: (2^17 (7.8 mN), 32 N] */
    int32_t fc_q24;         /* Coulomb friction Fc, N at 2^-24: [Fs/64, Fs] */
    int32_t vs_q28;         /* Stribeck velocity, m/s at 2^-28: (2^14 (61 um/s), 2^31 (8 m/s)) */
    int32_t sigma0_n_per_m; /* initial contact stiffness, whole N/m: (2^16, 2^31), 24 Fs/sigma0 <= 0.24 mm */
    int32_t sigma1_q16;     /* micro-damping, N s/m in Q16.16: [0, 32768) */
    int32_t sigma2_q16;     /* viscous friction, N s/m in Q16.16: [0, 32768) */
    int32_t asymmetry_q30;  /* asymmetric_friction a, Q2.30 in [-0.9, 0.9]: the contact's elastic and
                               micro-damping force times 1 + a sgn(load) (ss_friction.h); 0 = symmetric */
    /* Reciprocals, so that the step multiplies where it divided (ss_friction_config_reciprocals_q
     * fills them; the check refuses a config whose reciprocals are not its own): */
    int32_t inv_vs_q45;        /* 2^45 / vs_q28 rounded: 1/vs in s/m at 2^-17 */
    int32_t inv_sigma0_q47;    /* 2^47 / sigma0_n_per_m rounded: 1/sigma0 in m/N at 2^-47 */
    int32_t inv_fs_q48;        /* 2^48 / fs_q24 rounded: 1/Fs in 1/N at 2^-24 */
    int32_t sat_length_q40;    /* 24 Fs / sigma0 (truncated), m at 2^-40: where the LS element re-bases */
    int32_t fc_recip_mantissa; /* 1/Fc = fc_recip_mantissa 2^-fc_recip_shift as ss_reciprocal_mantissa_q */
    int32_t fc_recip_shift;    /* gives it: the Stribeck level in gross sliding is Fc exactly, and the
                                * laws take its reciprocal from here, not anew each step */
} ss_friction_config_q_t;

/* Fill cfg's reciprocals and saturation length from its fs_q24, vs_q28 and sigma0_n_per_m (0 where
 * these are out of range). */
void ss_friction_config_reciprocals_q(ss_friction_config_q_t *cfg);

/* Table I of the LS paper as integer constants (no float anywhere): what ss_friction_config_to_q
 * makes of ss_friction_config_table1_f32() (tests/c/test_fixed_model.c checks it bit for bit). */
ss_friction_config_q_t ss_friction_config_table1_q(void);

/* SS_OK, SS_ERR_NULL or SS_ERR_RANGE; *bad_field (when not NULL) names the field, e.g. "fc_q24". */
ss_status_t ss_friction_config_check_q(const ss_friction_config_q_t *cfg, const char **bad_field);

/* As ss_friction_config_check_q, names prefixed "friction." when prefixed != 0; bad_field not NULL. */
ss_status_t ss_friction_config_check_named_q(const ss_friction_config_q_t *cfg, int prefixed,
                                             const char **bad_field);

/* A force law's slopes at its state for the actuator's implicit step (ss_friction_slopes_f32_t):
 * dF/dv in N s/m, Q16.16; dF/dx as a share of sigma0, Q2.30 in [0, 2^30 (1 + asymmetry)]. */
typedef struct {
    int32_t dfdv_q16;
    int32_t dfdx_q30;
} ss_friction_slopes_q_t;

/* Stribeck curve g(v), N at 2^-24, for v in m/s at 2^-28. */
int32_t ss_stribeck_q(const ss_friction_config_q_t *cfg, int32_t v_q28);

/* The contact force (N at 2^-24) times 1 + asymmetry sgn(load): unchanged when the contact is
 * symmetric or unloaded (load 0). */
int64_t ss_asymmetric_q(const ss_friction_config_q_t *cfg, int64_t force_q24, int64_t load);

/* ss_asymmetric_q with its common case inline (a symmetric contact or no load: the value as it is),
 * for the step, which asks three times per force. */
static inline int64_t ss_asymmetric_inline_q(const ss_friction_config_q_t *cfg, int64_t force_q24,
                                             int64_t load)
{
    return (cfg->asymmetry_q30 == 0 || load == 0) ? force_q24 : ss_asymmetric_q(cfg, force_q24, load);
}

/* Slope dg/dv, N s/m in Q16.16 (saturated). */
int32_t ss_stribeck_slope_q(const ss_friction_config_q_t *cfg, int32_t v_q28);

/* ss_stribeck_q, and its slope as ss_stribeck_slope_q into *slope_q16, from one ratio and one
 * exponential (the same bits as the two calls). */
int32_t ss_stribeck_with_slope_q(const ss_friction_config_q_t *cfg, int32_t v_q28, int32_t *slope_q16);

#endif /* SS_FRICTION_Q_H */
