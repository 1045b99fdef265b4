/* Parameters shared by the friction models (LS and LuGre) and the Stribeck curve
 * g(v) = Fc + (Fs - Fc) exp(-(v/vs)^2). Equations and units: docs/model.md. */
#ifndef SS_FRICTION_H
#define SS_FRICTION_H

#include "ss_status.h"

typedef struct {
    float fs_n;            /* static (break-away) friction Fs = mu_s * N, (0, 1e4] */
    float fc_n;            /* Coulomb friction Fc = mu_d * N, (0, Fs] */
    float vs_m_per_s;      /* Stribeck velocity, [1e-9, 10] */
    float sigma0_n_per_m;  /* initial contact stiffness, [1, 1e12] */
    float sigma1_ns_per_m; /* micro-damping, [0, 1e6] */
    float sigma2_ns_per_m; /* viscous friction, [0, 1e6] */
    float asymmetry;       /* contact force times 1 + asymmetry sgn(load): direction-dependent, [-0.9, 0.9] */
    float gms_decay;       /* GMS only: exponent of its presliding stiffness decay (ss_gms_friction.h),
                            * [0.05, 20]; 1, ss_friction_config_from_mu_f32's, a parabolic virgin curve */
    float gms_stiffness_ratio; /* GMS only: stiffness of each element over the one before it, [0.05, 20];
                                * 1, ss_friction_config_from_mu_f32's, equal stiffnesses */
} ss_friction_config_f32_t;

/* The friction of Table I of the LS paper as the dataset (stick-slip-dataset/1) names it:
 * coefficients and clamping force, from which ss_friction_config_from_mu_f32 makes the config. */
typedef struct {
    float mu_s;            /* static friction coefficient */
    float mu_d;            /* dynamic (Coulomb) friction coefficient */
    float normal_force_n;  /* clamping force N */
    float vs_m_per_s;      /* Stribeck velocity */
    float sigma0_n_per_m;  /* initial contact stiffness */
    float sigma1_ns_per_m; /* micro-damping */
    float sigma2_ns_per_m; /* viscous friction */
} ss_friction_mu_f32_t;

/* Table I of the LS paper: mu_s 0.36, mu_d 0.30, N 10 N, vs 0.4 mm/s, sigma 1e7/80/8 (the one home
 * of these values in C; the node's parameter defaults and ss_friction_config_table1_f32 use it). */
ss_friction_mu_f32_t ss_friction_mu_table1_f32(void);

/* ss_friction_config_from_mu_f32 of ss_friction_mu_table1_f32(). */
ss_friction_config_f32_t ss_friction_config_table1_f32(void);

/* Config from friction coefficients and clamping (normal) force; symmetric (asymmetry 0). */
ss_friction_config_f32_t ss_friction_config_from_mu_f32(float mu_s, float mu_d, float normal_force_n,
                                                        float vs_m_per_s, float sigma0_n_per_m,
                                                        float sigma1_ns_per_m, float sigma2_ns_per_m);

/* SS_OK, SS_ERR_NULL, SS_ERR_NONFINITE or SS_ERR_RANGE (ranges above). On error, *bad_field
 * (when bad_field is not NULL) names the offending field, e.g. "fc_n"; on success it is "". */
ss_status_t ss_friction_config_check_f32(const ss_friction_config_f32_t *cfg, const char **bad_field);

/* As ss_friction_config_check_f32, with names prefixed "friction." when prefixed != 0 (used by
 * the actuator's check); bad_field must not be NULL. */
ss_status_t ss_friction_config_check_named_f32(const ss_friction_config_f32_t *cfg, int prefixed,
                                               const char **bad_field);

/* A force law's slopes at its state, for the actuator's implicit step (docs/model.md, "The
 * integrator"): dF/dv, the damping the closing kick feeds back; dF/dx, the contact's tangent
 * stiffness (0 in gross sliding), through which the rod's sampled compliance is corrected. */
typedef struct {
    float dfdv_ns_per_m;
    float dfdx_n_per_m;
} ss_friction_slopes_f32_t;

/* Stribeck curve g(v) in N: Fs at rest, Fc in fast sliding. */
float ss_stribeck_f32(const ss_friction_config_f32_t *cfg, float v_m_per_s);

/* Asymmetric friction: the contact's elastic and micro-damping force is 1 + asymmetry times as
 * strong when loaded in +x (load > 0) as nominal, 1 - asymmetry in -x. Continuous, since the
 * force vanishes where the load changes sign; 1 exactly for symmetric friction. */
float ss_asymmetry_factor_f32(const ss_friction_config_f32_t *cfg, float load);

/* Slope dg/dv of the Stribeck curve, N s/m. */
float ss_stribeck_slope_f32(const ss_friction_config_f32_t *cfg, float v_m_per_s);

/* g(v) as ss_stribeck_f32 and its slope into *slope_ns_per_m, from one exponential (the force
 * laws' implicit step needs both at the same velocity). */
float ss_stribeck_with_slope_f32(const ss_friction_config_f32_t *cfg, float v_m_per_s, float *slope_ns_per_m);

#endif /* SS_FRICTION_H */
