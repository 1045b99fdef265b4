#include "ss_convert_q.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

/* round(x) as an integer if it lies in [lo, hi], else not ok (NaN fails the comparisons). */
static int to_int(double x, double lo, double hi, int64_t *out)
{
    const double r = floor(x + 0.5);
    if (!(r >= lo && r <= hi)) {
        return 0;
    }
    *out = (int64_t)r;
    return 1;
}

static const char *const FRICTION_NAMES[2][6] = {
    {"fs_n", "fc_n", "vs_m_per_s", "sigma0_n_per_m", "sigma1_ns_per_m", "sigma2_ns_per_m"},
    {"friction.fs_n", "friction.fc_n", "friction.vs_m_per_s", "friction.sigma0_n_per_m",
     "friction.sigma1_ns_per_m", "friction.sigma2_ns_per_m"},
};

static ss_status_t friction_to_q(const ss_friction_config_f32_t *in, int prefixed,
                                 ss_friction_config_q_t *out, const char **bad)
{
    ss_status_t st = ss_friction_config_check_named_f32(in, prefixed, bad);
    if (st != SS_OK) {
        return st;
    }
    const char *const *names = FRICTION_NAMES[prefixed ? 1 : 0];
    const double i32max = 2147483647.0;
    int64_t v[6] = {0, 0, 0, 0, 0, 0};
    const int ok[6] = {
        to_int((double)in->fs_n * SS_QF_ONE(SS_QF_FORCE), SS_Q_FS_MIN_Q24 + 1.0, (double)SS_Q_FS_MAX_Q24,
               &v[0]),
        to_int((double)in->fc_n * SS_QF_ONE(SS_QF_FORCE), 1.0, i32max, &v[1]),
        to_int((double)in->vs_m_per_s * SS_QF_ONE(SS_QF_VELOCITY), SS_Q_VS_MIN_Q28 + 1.0, i32max, &v[2]),
        to_int((double)in->sigma0_n_per_m, SS_Q_SIGMA0_MIN_N_PER_M + 1.0, i32max, &v[3]),
        to_int((double)in->sigma1_ns_per_m * SS_QF_ONE(SS_QF_DAMPING), 0.0, i32max, &v[4]),
        to_int((double)in->sigma2_ns_per_m * SS_QF_ONE(SS_QF_DAMPING), 0.0, i32max, &v[5]),
    };
    for (int i = 0; i < 6; ++i) {
        if (!ok[i]) {
            *bad = names[i];
            return SS_ERR_RANGE;
        }
    }
    /* the float check held |asymmetry| <= 0.9, which rounds to at most SS_Q_ASYMMETRY_MAX_Q30 */
    out->asymmetry_q30 = (int32_t)floor((double)in->asymmetry * SS_QF_ONE(30) + 0.5);
    out->fs_q24 = (int32_t)v[0];
    out->fc_q24 = (int32_t)v[1];
    out->vs_q28 = (int32_t)v[2];
    out->sigma0_n_per_m = (int32_t)v[3];
    out->sigma1_q16 = (int32_t)v[4];
    out->sigma2_q16 = (int32_t)v[5];
    ss_friction_config_reciprocals_q(out);
    /* the q family's own limits (ss_friction_q.h), named by the float field */
    if ((int64_t)out->fc_q24 * SS_Q_FS_OVER_FC_MAX < out->fs_q24) {
        *bad = names[1];
        return SS_ERR_RANGE;
    }
    if ((int64_t)SS_LS_Q_SATURATION_LENGTHS * out->fs_q24 * ((int64_t)1 << SS_QF_F_OVER_K) >
        SS_Q_SAT_LENGTH_MAX_Q40 * out->sigma0_n_per_m) {
        *bad = names[3];
        return SS_ERR_RANGE;
    }
    return ss_friction_config_check_q(out, NULL); /* SS_OK: the checks above are the q check's */
}

ss_status_t ss_friction_config_to_q(const ss_friction_config_f32_t *in, ss_friction_config_q_t *out,
                                    const char **bad_field)
{
    const char *dummy = "";
    const char **bad = (bad_field != NULL) ? bad_field : &dummy;
    *bad = "";
    if (out == NULL) {
        *bad = "out";
        return SS_ERR_NULL;
    }
    return friction_to_q(in, 0, out, bad);
}

/* Exact flow of M e'' + c e' + k e = 0 over dt on (e, e'), in double: the float family's
 * rod_flow, with s(t) = sin(w t)/w, sinh(w t)/w or t. */
static void rod_flow(double k, double c, double m, double dt, double phi[4])
{
    const double wn2 = k / m;
    const double sigma = 0.5 * c / m;
    const double wd2 = wn2 - sigma * sigma;
    double co = 1.0;
    double si = dt;
    if (wd2 > 0.0) {
        const double wd = sqrt(wd2);
        co = cos(wd * dt);
        si = sin(wd * dt) / wd;
    } else if (wd2 < 0.0) { /* over-damped: from the real roots, as the float family's */
        const double w = sqrt(-wd2);
        const double e_slow = exp(-wn2 / (sigma + w) * dt);
        const double e_fast = exp(-(sigma + w) * dt);
        const double s =
            (w * dt < 0.5) ? e_fast * expm1(2.0 * w * dt) / (2.0 * w) : (e_slow - e_fast) / (2.0 * w);
        const double cc = 0.5 * (e_slow + e_fast);
        phi[0] = cc + sigma * s;
        phi[1] = s;
        phi[2] = -wn2 * s;
        phi[3] = cc - sigma * s;
        return;
    }
    const double e = exp(-sigma * dt);
    phi[0] = e * (co + sigma * si);
    phi[1] = e * si;
    phi[2] = -e * wn2 * si;
    phi[3] = e * (co - sigma * si);
}

/* ss_actuator_config_to_q; with split, for the config of LS's split steps, which never kick the rod:
 * a kick_rod_q40 past its format saturates there, not an error (LS's 12 us steps on Table I's rod) */
static ss_status_t config_to_q(const ss_actuator_config_f32_t *in, ss_actuator_config_q_t *out,
                               const char **bad_field, int split)
{
    const char *dummy = "";
    const char **bad = (bad_field != NULL) ? bad_field : &dummy;
    ss_status_t st = ss_actuator_config_check_f32(in, bad);
    if (st != SS_OK) {
        return st;
    }
    if (out == NULL) {
        *bad = "out";
        return SS_ERR_NULL;
    }
    if (in->friction_model != SS_FRICTION_LS && in->friction_model != SS_FRICTION_LUGRE) {
        /* the q family has LS and LuGre only; GMS is a float-family law. Refused, never swapped. */
        *bad = "friction_model";
        return SS_ERR_RANGE;
    }
    /* the q family models the load, the slew limit and the sensor scale (ss_effects_q.h); a config
     * that asks for another effect is refused by its field name, never run without it. */
    static const char *const effect_names[] = {"effects.creep_ratio", "effects.friction_gradient_per_m",
                                               "effects.thermal_coeff_per_j", "effects.amp_bandwidth_hz"};
    const float switches[] = {in->effects.creep_ratio, in->effects.friction_gradient_per_m,
                              in->effects.thermal_coeff_per_j, in->effects.amp_bandwidth_hz};
    for (size_t i = 0; i < sizeof switches / sizeof switches[0]; ++i) {
        if (switches[i] != 0.0f) {
            *bad = effect_names[i];
            return SS_ERR_RANGE;
        }
    }
    const double i32max = 2147483647.0;
    int64_t v = 0;
    /* everything below uses the step the q family actually takes, dt_q40 2^-40 s */
    if (!to_int((double)in->dt_s * SS_QF_ONE(SS_QF_TIME), 65537.0, i32max, &v)) {
        *bad = "dt_s";
        return SS_ERR_RANGE;
    }
    out->dt_q40 = (int32_t)v;
    out->inv_dt_q47 = ss_actuator_inv_dt_q47(out->dt_q40);
    const double dt = (double)v * SS_Q40_M;
    if (!to_int((double)in->piezo_gain_m_per_v * SS_QF_ONE(SS_QF_GAIN), -i32max, i32max, &v) || v == 0) {
        *bad = "piezo_gain_m_per_v";
        return SS_ERR_RANGE;
    }
    out->piezo_gain_q48 = (int32_t)v;
    const double k = (double)in->piezo_stiffness_n_per_m;
    const double c = (double)in->piezo_damping_kg_per_s;
    if (!to_int(c / (k * dt) * SS_QF_ONE(SS_QF_LAG), 0.0, i32max, &v)) {
        *bad = "piezo_damping_kg_per_s";
        return SS_ERR_RANGE;
    }
    out->lag_q24 = (int32_t)v;
    const double kick_rod = dt / (2.0 * (double)in->rod_mass_kg) * SS_QF_ONE(SS_QF_KICK);
    if (split && kick_rod >= 4294967295.0) {
        v = (int64_t)UINT32_MAX; /* never used: the split step does not kick the rod */
    } else if (!to_int(kick_rod, 1.0, 4294967295.0, &v)) {
        *bad = "rod_mass_kg";
        return SS_ERR_RANGE;
    }
    out->kick_rod_q40 = (uint32_t)v;
    if (!to_int(dt / (2.0 * (double)in->slider_mass_kg) * SS_QF_ONE(SS_QF_KICK), 1.0, i32max, &v)) {
        *bad = "slider_mass_kg";
        return SS_ERR_RANGE;
    }
    out->kick_slider_q40 = (int32_t)v;
    /* beyond 2 the contact's mode on the rod is not resolved by the step at all */
    if (!to_int((double)in->friction.sigma0_n_per_m * dt * dt / (12.0 * (double)in->rod_mass_kg) *
                    SS_QF_ONE(SS_QF_RATIO),
                0.0, i32max, &v)) {
        *bad = "rod_mass_kg";
        return SS_ERR_RANGE;
    }
    out->contact_lag_q30 = (int32_t)v;
    /* (w dt)^2, with which a step takes a drive's corner inside it; 0 (the corner on the chord)
     * past 1, where the step's series in it no longer holds */
    const double w2dt2 = k * dt * dt / (double)in->rod_mass_kg;
    out->rod_w2dt2_q28 = (w2dt2 <= 1.0) ? (int32_t)floor(w2dt2 * SS_QF_ONE(SS_QF_FLOW) + 0.5) : 0;
    double phi[4];
    rod_flow(k, c, (double)in->rod_mass_kg, dt, phi);
    const double scaled[4] = {phi[0], phi[1] / dt, phi[2] * dt, phi[3]};
    for (int i = 0; i < 4; ++i) {
        if (!to_int(scaled[i] * SS_QF_ONE(SS_QF_FLOW), -i32max, i32max, &v)) {
            *bad = "piezo_stiffness_n_per_m"; /* the rod mode is too fast for the step */
            return SS_ERR_RANGE;
        }
        out->phi_q28[i] = (int32_t)v;
    }
    out->friction_model = in->friction_model;
    out->effects = ss_effects_config_none_q(); /* filled below where the float config asks */
    /* effects: the load in N at 2^-24, the slew as volts per step at 2^-24 (of the step taken),
     * the sensor's scale error in Q2.30; 0 stays 0 (off) */
    const double lmax = (double)SS_Q_LOAD_MAX_Q24;
    if (!to_int((double)in->effects.load_n * SS_QF_ONE(SS_QF_FORCE), -lmax, lmax, &v)) {
        *bad = "effects.load_n";
        return SS_ERR_RANGE;
    }
    out->effects.load_q24 = (int32_t)v;
    v = 0;
    if (in->effects.slew_v_per_s != 0.0f &&
        !to_int((double)in->effects.slew_v_per_s * dt * SS_QF_ONE(24), 1.0, (double)SS_Q_SLEW_MAX_Q24, &v)) {
        *bad = "effects.slew_v_per_s";
        return SS_ERR_RANGE;
    }
    out->effects.slew_q24 = (int32_t)v;
    if (!to_int((double)in->effects.sensor_scale_error * SS_QF_ONE(30), -SS_QF_ONE(29), SS_QF_ONE(29), &v)) {
        *bad = "effects.sensor_scale_error";
        return SS_ERR_RANGE;
    }
    out->effects.sensor_scale_q30 = (int32_t)v;
    /* the hysteresis: alpha (the float check held it in [0, 0.9]), the width and its reciprocal */
    out->effects.hysteresis_alpha_q30 =
        (int32_t)floor((double)in->effects.hysteresis_alpha * SS_QF_ONE(30) + 0.5);
    if (in->effects.base_mass_kg != 0.0f) {
        /* the base on its spring: k_b = m w^2, c_b = 2 zeta m w (the float step's, in double) */
        const double m_b = (double)in->effects.base_mass_kg;
        const double w = 6.283185307179586 * (double)in->effects.base_freq_hz;
        int64_t q[5] = {0, 0, 0, 0, 0};
        const int fits[5] = {
            to_int(dt / (2.0 * m_b) * SS_QF_ONE(SS_QF_KICK), 1.0, i32max, &q[0]),
            to_int(m_b * w * w, 0.0, i32max, &q[1]),
            to_int(2.0 * (double)in->effects.base_damping_ratio * m_b * w * SS_QF_ONE(SS_QF_DAMPING), 0.0,
                   i32max, &q[2]),
            to_int(k, 1.0, i32max, &q[3]),
            to_int(c * SS_QF_ONE(SS_QF_DAMPING), 0.0, i32max, &q[4]),
        };
        static const char *const names[5] = {"effects.base_mass_kg", "effects.base_freq_hz",
                                             "effects.base_damping_ratio", "piezo_stiffness_n_per_m",
                                             "piezo_damping_kg_per_s"};
        for (int i = 0; i < 5; ++i) {
            if (!fits[i]) {
                *bad = names[i];
                return SS_ERR_RANGE;
            }
        }
        out->effects.base_kick_q40 = (int32_t)q[0];
        out->effects.base_stiffness_n_per_m = (int32_t)q[1];
        out->effects.base_damping_q16 = (int32_t)q[2];
        out->effects.piezo_stiffness_n_per_m = (int32_t)q[3];
        out->effects.piezo_damping_q16 = (int32_t)q[4];
    }
    if (out->effects.hysteresis_alpha_q30 != 0) {
        if (!to_int((double)in->effects.hysteresis_width_m * SS_QF_ONE(SS_QF_LENGTH),
                    (double)SS_Q_HYSTERESIS_WIDTH_MIN_Q40, i32max, &v)) {
            *bad = "effects.hysteresis_width_m";
            return SS_ERR_RANGE;
        }
        out->effects.hysteresis_width_q40 = (int32_t)v;
        out->effects.hysteresis_inv_width_q48 = (int64_t)floor(SS_QF_ONE(48) / (double)v + 0.5);
    }
    st = friction_to_q(&in->friction, 1, &out->friction, bad);
    if (st == SS_OK) {
        st = ss_actuator_config_check_q(out, NULL);
    }
    return st;
}

int32_t ss_volts_to_q16(double v)
{
    const double r = floor(v * SS_QF_ONE(SS_QF_VOLTAGE) + 0.5);
    if (!(r == r)) {
        return 0;
    }
    if (r >= 2147483647.0) {
        return INT32_MAX;
    }
    if (r <= -2147483648.0) {
        return INT32_MIN;
    }
    return (int32_t)r;
}

ss_status_t ss_actuator_config_to_q(const ss_actuator_config_f32_t *in, ss_actuator_config_q_t *out,
                                    const char **bad_field)
{
    return config_to_q(in, out, bad_field, 0);
}

ss_status_t ss_actuator_coarse_to_q(const ss_actuator_config_f32_t *in, uint32_t n,
                                    ss_actuator_coarse_q_t *out, const char **bad_field)
{
    const char *dummy = "";
    const char **bad = (bad_field != NULL) ? bad_field : &dummy;
    ss_actuator_coarse_f32_t co;
    if (out == NULL) {
        *bad = "out";
        return SS_ERR_NULL;
    }
    ss_status_t status = ss_actuator_coarse_init_f32(in, n, &co, bad); /* its rules and bounds */
    if (status != SS_OK) {
        return status;
    }
    ss_actuator_config_f32_t at_n = *in;
    at_n.dt_s = co.dt_s;
    const double compliance = ldexp(1.0, 56) / (double)in->piezo_stiffness_n_per_m;
    /* LS's whole coarse steps of 3 dt or more take the split form where the stack's compliance fits
     * and no base asks for the kicked form (ss_actuator_q.c, step_split_ls) */
    const int split = co.split_min_n != 0u && n >= co.split_min_n && compliance < 2147483647.0 &&
                      in->effects.base_mass_kg == 0.0f;
    status = config_to_q(&at_n, &out->cfg, bad, split);
    if (status != SS_OK) {
        return status;
    }
    at_n.dt_s = 2.0f * in->dt_s;
    status = ss_actuator_config_to_q(&at_n, &out->cfg_mid, bad);
    if (status != SS_OK) {
        return status;
    }
    out->compliance_q56 = (compliance < 2147483647.0) ? (int32_t)floor(compliance + 0.5) : 0;
    if (out->compliance_q56 == 0) { /* a stack too soft for the held form: the kicked form's bounds */
        ss_actuator_coarse_kicked_bounds_f32(&co, in->friction_model);
    }
    const double length = SS_QF_ONE(SS_QF_LENGTH);
    out->n = n;
    out->v_rel_max_q28 = (int32_t)floor((double)co.v_rel_max_m_per_s * SS_QF_ONE(SS_QF_VELOCITY) + 0.5);
    out->ring_max_q40 = (int32_t)floor((double)co.v_ring_max_m_per_s * (double)co.dt_s * length + 0.5);
    out->ring_max_2_q40 = (int32_t)floor((double)co.v_ring_max_m_per_s * (double)at_n.dt_s * length + 0.5);
    out->v_rel_mid_max_q28 =
        (int32_t)floor((double)co.v_rel_mid_max_m_per_s * SS_QF_ONE(SS_QF_VELOCITY) + 0.5);
    out->ring_mid_max_q40 =
        (int32_t)floor((double)co.v_ring_mid_max_m_per_s * (double)at_n.dt_s * length + 0.5);
    out->split = split;
    return ss_actuator_coarse_stick_to_q(in, 0u, out, bad);
}

/* round(v), or 0 where it does not fit an int32 (a NaN neither) */
static int fits_i32(double v, int32_t *out)
{
    const double r = floor(v + 0.5);
    if (!(r > -2147483648.0 && r < 2147483647.0)) {
        return 0;
    }
    *out = (int32_t)r;
    return 1;
}

ss_status_t ss_actuator_coarse_stick_to_q(const ss_actuator_config_f32_t *in, uint32_t stick_n,
                                          ss_actuator_coarse_q_t *out, const char **bad_field)
{
    const char *dummy = "";
    const char **bad = (bad_field != NULL) ? bad_field : &dummy;
    if (out == NULL) {
        *bad = "out";
        return SS_ERR_NULL;
    }
    ss_actuator_coarse_f32_t co;
    ss_status_t status = ss_actuator_coarse_init_f32(in, (out->n >= 2u) ? out->n : 2u, &co, bad);
    if (status == SS_OK) {
        status = ss_actuator_coarse_stick_f32(in, stick_n, &co, bad);
    }
    if (status != SS_OK) {
        return status;
    }
    ss_actuator_coarse_q_t q = *out;
    q.stick_n = 0u;
    q.stick_h_q40 = q.stick_inv_h_q47 = q.stick_omega_q47 = q.stick_inv_omega_q40 = 0;
    q.stick_lag_q30 = q.stick_v_rel_max_q28 = q.stick_ring_max_q40 = q.stick_force_max_q24 = 0;
    q.stick_phi_shift = 0;
    for (int i = 0; i < 16; ++i) {
        q.stick_phi_q[i] = 0;
    }
    q.edge_parts = 0u;
    q.edge_limit_q16 = 0;
    q.edge_part_q30 = 0;
    q.edge_pad = 0;
    memset(&q.cfg_edge, 0, sizeof q.cfg_edge);
    if (stick_n != 0u) {
        const double h = (double)stick_n * (double)in->dt_s;
        const double w = (double)co.stick_omega_per_s;
        double phi_max = 0.0;
        for (int i = 0; i < 16; ++i) {
            phi_max = fmax(phi_max, fabs((double)co.stick_phi[i]));
        }
        int shift = 30; /* |entries| <= 2^30: four products of 32-bit lengths sum within 2^63 */
        while (shift > 0 && phi_max * ldexp(1.0, shift) > ldexp(1.0, 30)) {
            --shift;
        }
        if (out->compliance_q56 == 0) { /* the steady state's rod offset is load / k */
            *bad = "piezo_stiffness_n_per_m";
            return SS_ERR_RANGE;
        }
        /* stick_n of the q config's own dt (rounded as ss_actuator_config_to_q rounds it), as the
         * player takes them */
        const double dt_q40 = floor((double)in->dt_s * SS_QF_ONE(SS_QF_TIME) + 0.5);
        int ok = fits_i32((double)stick_n * dt_q40, &q.stick_h_q40);
        /* 1/s at 2^-7, as the config's inv_dt_q47: a length at 2^-40 times it is a velocity at 2^-47 */
        ok = ok && fits_i32(ldexp(1.0, 7) / h, &q.stick_inv_h_q47);
        ok = ok && fits_i32(w * ldexp(1.0, 7), &q.stick_omega_q47);
        ok = ok && fits_i32(SS_QF_ONE(SS_QF_TIME) / w, &q.stick_inv_omega_q40);
        ok = ok && fits_i32((double)in->piezo_damping_kg_per_s / ((double)in->piezo_stiffness_n_per_m * h) *
                                SS_QF_ONE(SS_QF_RATIO),
                            &q.stick_lag_q30);
        ok = ok && fits_i32((double)SS_COARSE_STICK_V_REL_MAX_M_PER_S * SS_QF_ONE(SS_QF_VELOCITY),
                            &q.stick_v_rel_max_q28);
        ok = ok && fits_i32((double)SS_COARSE_STICK_V_RING_MAX_M_PER_S * h * SS_QF_ONE(SS_QF_LENGTH),
                            &q.stick_ring_max_q40);
        ok = ok && fits_i32((double)SS_COARSE_STICK_FORCE_SHARE * (double)in->friction.fc_n *
                                SS_QF_ONE(SS_QF_FORCE),
                            &q.stick_force_max_q24);
        for (int i = 0; ok && i < 16; ++i) {
            ok = fits_i32((double)co.stick_phi[i] * ldexp(1.0, shift), &q.stick_phi_q[i]);
        }
        /* the fine steps on a fast edge, in co.edge_parts parts of their own config (the float
         * family's speed, 0.1 m/s of strain, as a drive change in a step of dt) */
        if (!ok || shift < 16) {
            *bad = "coarse_stick_n";
            return SS_ERR_RANGE;
        }
        /* ... where the part's config fits the q formats (dt / 4 >= 60 ns, c / (k dt / 4) < 128)
         * and the limit its own; else the fast edges whole, as before the parts (the float family
         * still takes them in parts: 0.075 % against 0.056 % on Table I at 1.5 us) */
        ss_actuator_config_f32_t part = *in;
        part.dt_s = in->dt_s / (float)co.edge_parts;
        const char *part_bad = "";
        if (ss_actuator_config_to_q(&part, &q.cfg_edge, &part_bad) == SS_OK &&
            fits_i32(0.1 * (double)in->dt_s / fabs((double)in->piezo_gain_m_per_v) * SS_QF_ONE(SS_QF_VOLTAGE),
                     &q.edge_limit_q16)) {
            q.edge_parts = co.edge_parts;
            q.edge_part_q30 = (int32_t)(((int32_t)1 << SS_QF_RATIO) / (int32_t)co.edge_parts);
        } else {
            q.edge_limit_q16 = 0;
            memset(&q.cfg_edge, 0, sizeof q.cfg_edge);
        }
        q.stick_phi_shift = shift;
        q.stick_n = stick_n;
    }
    *out = q;
    return SS_OK;
}

ss_status_t ss_waveform_config_to_q(const ss_waveform_config_f32_t *in, ss_waveform_config_q_t *out,
                                    const char **bad_field)
{
    const char *dummy = "";
    const char **bad = (bad_field != NULL) ? bad_field : &dummy;
    *bad = "";
    if (in == NULL || out == NULL) {
        *bad = (in == NULL) ? "config" : "out";
        return SS_ERR_NULL;
    }
    const double i32max = 2147483647.0;
    int64_t v[4] = {0, 0, 0, 0};
    if (in->kind != SS_WAVE_SAWTOOTH) {
        *bad = "kind";
        return SS_ERR_RANGE;
    }
    const float vals[4] = {in->frequency_hz, in->amplitude_v, in->offset_v, in->rise_fraction};
    static const char *const names[4] = {"frequency_hz", "amplitude_v", "offset_v", "rise_fraction"};
    const int ok[4] = {
        to_int((double)in->frequency_hz * 1000.0, 1.0, 4294967295.0, &v[0]),
        to_int((double)in->amplitude_v * SS_QF_ONE(SS_QF_VOLTAGE), -i32max, i32max, &v[1]),
        to_int((double)in->offset_v * SS_QF_ONE(SS_QF_VOLTAGE), -i32max, i32max, &v[2]),
        to_int((double)in->rise_fraction * SS_QF_ONE(SS_QF_FRACTION), 1.0, 4294967295.0, &v[3]),
    };
    for (int i = 0; i < 4; ++i) {
        if (!isfinite(vals[i])) {
            *bad = names[i];
            return SS_ERR_NONFINITE;
        }
        if (!ok[i]) {
            *bad = names[i];
            return SS_ERR_RANGE;
        }
    }
    if (in->direction != 1 && in->direction != -1) {
        *bad = "direction";
        return SS_ERR_RANGE;
    }
    *out = ss_waveform_sawtooth_q((uint32_t)v[0], (int32_t)v[1], (int32_t)v[2], (uint32_t)v[3], in->direction,
                                  in->cycles);
    return SS_OK;
}

void ss_actuator_state_q_to_si(const ss_actuator_config_q_t *cfg, const ss_actuator_state_q_t *st,
                               ss_actuator_si_t *out)
{
    const int lugre = (cfg->friction_model == SS_FRICTION_Q_LUGRE);
    out->x_rod_m = st->x_rod_q40 * SS_Q40_M;
    out->v_rod_m_per_s = st->v_rod_q28 * SS_Q28_M_PER_S;
    out->x_slider_m = (double)st->x_slider_q40 * SS_Q40_M;
    out->v_slider_m_per_s = st->v_slider_q28 * SS_Q28_M_PER_S;
    out->x_p_m = st->x_p_q40 * SS_Q40_M;
    out->drive_v = st->drive_q16 * SS_Q16;
    out->force_n = st->force_q24 * SS_Q24_N;
    out->state_a = lugre ? st->fr.lugre.z_q40 * SS_Q40_M : st->fr.ls.level_q24 * SS_Q24_N;
    out->state_b = lugre ? st->fr.lugre.zdot_q28 * SS_Q28_M_PER_S : st->fr.ls.fm_q24 * SS_Q24_N;
    out->steps = st->steps;
}
