#include "ss_friction_q.h"

#include <stddef.h>

#include "ss_fixed_ops.h"

/* Beyond r = v/vs = 256 (r^2 = 65536) exp(-r^2) is zero in Q30; the clamp also bounds r^2. */
#define SS_Q_STRIBECK_R_MAX_Q16 ((int64_t)256 << 16)
/* r = |v| / vs (Q16.16) from which exp(-r^2) is 0 in Q30 whatever r's fraction: r^2 at 2^-32 then
 * has a top (Q16) part hi >= 1 408 209, where ss_exp_neg_q16_q30's power of two, hi log2(e) (its
 * 1 549 082 005 at 2^-30), reaches 31: below 2^-31, 0 (303 791^2 >= 1 408 209 x 2^16 > 303 790^2).
 * The Stribeck level there is Fc and its slope 0, the bits the exponential gives, without its two
 * products (gross sliding, |v| >= 4.64 vs) */
#define SS_Q_STRIBECK_R_ZERO_Q16 303791

/* Fc's reciprocal as ss_reciprocal_mantissa_q gives it (0 and 0 for Fc <= 0) */
static void fc_reciprocal(ss_friction_config_q_t *cfg)
{
    int sh = 0;
    cfg->fc_recip_mantissa = (cfg->fc_q24 > 0) ? ss_reciprocal_mantissa_q((uint32_t)cfg->fc_q24, &sh) : 0;
    cfg->fc_recip_shift = sh;
}

ss_friction_config_q_t ss_friction_config_table1_q(void)
{
    /* round(x * 2^k) of the float Table I values (0.36 * 10 N, 0.30 * 10 N, 0.4 mm/s, ...) */
    ss_friction_config_q_t cfg;
    cfg.fs_q24 = 60397980; /* 3.6000001 N (float 0.36f * 10.0f) */
    cfg.fc_q24 = 50331648; /* 3.0 N */
    cfg.vs_q28 = 107374;   /* 0.4e-3 m/s */
    cfg.sigma0_n_per_m = 10000000;
    cfg.sigma1_q16 = 5242880; /* 80 N s/m */
    cfg.sigma2_q16 = 524288;  /* 8 N s/m */
    cfg.asymmetry_q30 = 0;
    cfg.inv_vs_q45 = 327680557;    /* 2^45 / 107374 */
    cfg.inv_sigma0_q47 = 14073749; /* 2^47 / 1e7 */
    cfg.inv_fs_q48 = 4660338;      /* 2^48 / 60397980 */
    cfg.sat_length_q40 = 9499780;  /* 24 x 3.6 N / 1e7 N/m = 8.64 um */
    fc_reciprocal(&cfg);           /* integer arithmetic: the same on every target */
    return cfg;
}

/* SS_LS_Q_SATURATION_LENGTHS Fs / sigma0 in m at 2^-40, truncated; 0 unless both are > 0 */
static int32_t sat_length_q40(const ss_friction_config_q_t *cfg)
{
    if (cfg->sigma0_n_per_m <= 0 || cfg->fs_q24 <= 0) {
        return 0;
    }
    const int64_t l = SS_LS_Q_SATURATION_LENGTHS * (int64_t)cfg->fs_q24 * ((int64_t)1 << SS_QF_F_OVER_K) /
                      cfg->sigma0_n_per_m;
    return (int32_t)ss_clamp64(l, 0, INT32_MAX);
}

void ss_friction_config_reciprocals_q(ss_friction_config_q_t *cfg)
{
    cfg->inv_vs_q45 = ss_reciprocal_q(cfg->vs_q28, SS_Q_VS_MIN_Q28, 45);
    cfg->inv_sigma0_q47 = ss_reciprocal_q(cfg->sigma0_n_per_m, SS_Q_SIGMA0_MIN_N_PER_M, 47);
    cfg->inv_fs_q48 = ss_reciprocal_q(cfg->fs_q24, SS_Q_FS_MIN_Q24, 48);
    cfg->sat_length_q40 = sat_length_q40(cfg);
    fc_reciprocal(cfg);
}

static const char *const FIELD_NAMES_Q[2][13] = {
    {"fs_q24", "fc_q24", "vs_q28", "sigma0_n_per_m", "sigma1_q16", "sigma2_q16", "asymmetry_q30",
     "inv_vs_q45", "inv_sigma0_q47", "inv_fs_q48", "sat_length_q40", "fc_recip_mantissa", "fc_recip_shift"},
    {"friction.fs_q24", "friction.fc_q24", "friction.vs_q28", "friction.sigma0_n_per_m",
     "friction.sigma1_q16", "friction.sigma2_q16", "friction.asymmetry_q30", "friction.inv_vs_q45",
     "friction.inv_sigma0_q47", "friction.inv_fs_q48", "friction.sat_length_q40",
     "friction.fc_recip_mantissa", "friction.fc_recip_shift"},
};

ss_status_t ss_friction_config_check_named_q(const ss_friction_config_q_t *cfg, int prefixed,
                                             const char **bad_field)
{
    *bad_field = "";
    if (cfg == NULL) {
        *bad_field = "config";
        return SS_ERR_NULL;
    }
    const char *const *names = FIELD_NAMES_Q[prefixed ? 1 : 0];
    int bad = -1;
    if (cfg->fs_q24 <= SS_Q_FS_MIN_Q24 || cfg->fs_q24 > SS_Q_FS_MAX_Q24) {
        bad = 0;
    } else if (cfg->fc_q24 > cfg->fs_q24 || (int64_t)cfg->fc_q24 * SS_Q_FS_OVER_FC_MAX < cfg->fs_q24) {
        bad = 1; /* Fc above Fs would make the Stribeck curve rise; s/g <= Fs/Fc must fit */
    } else if (cfg->vs_q28 <= SS_Q_VS_MIN_Q28) {
        bad = 2;
    } else if (cfg->sigma0_n_per_m <= SS_Q_SIGMA0_MIN_N_PER_M ||
               (int64_t)SS_LS_Q_SATURATION_LENGTHS * cfg->fs_q24 * ((int64_t)1 << SS_QF_F_OVER_K) >
                   SS_Q_SAT_LENGTH_MAX_Q40 * cfg->sigma0_n_per_m) {
        bad = 3; /* the presliding length must fit the element's local frame */
    } else if (cfg->sigma1_q16 < 0) {
        bad = 4;
    } else if (cfg->sigma2_q16 < 0) {
        bad = 5;
    } else if (cfg->asymmetry_q30 < -SS_Q_ASYMMETRY_MAX_Q30 || cfg->asymmetry_q30 > SS_Q_ASYMMETRY_MAX_Q30) {
        bad = 6;
    } else if (cfg->inv_vs_q45 != ss_reciprocal_q(cfg->vs_q28, SS_Q_VS_MIN_Q28, 45)) {
        bad = 7;
    } else if (cfg->inv_sigma0_q47 != ss_reciprocal_q(cfg->sigma0_n_per_m, SS_Q_SIGMA0_MIN_N_PER_M, 47)) {
        bad = 8;
    } else if (cfg->inv_fs_q48 != ss_reciprocal_q(cfg->fs_q24, SS_Q_FS_MIN_Q24, 48)) {
        bad = 9;
    } else if (cfg->sat_length_q40 != sat_length_q40(cfg)) {
        bad = 10;
    } else {
        ss_friction_config_q_t own = *cfg;
        fc_reciprocal(&own);
        if (cfg->fc_recip_mantissa != own.fc_recip_mantissa) {
            bad = 11;
        } else if (cfg->fc_recip_shift != own.fc_recip_shift) {
            bad = 12;
        }
    }
    if (bad >= 0) {
        *bad_field = names[bad];
        return SS_ERR_RANGE;
    }
    return SS_OK;
}

ss_status_t ss_friction_config_check_q(const ss_friction_config_q_t *cfg, const char **bad_field)
{
    const char *dummy = "";
    return ss_friction_config_check_named_q(cfg, 0, (bad_field != NULL) ? bad_field : &dummy);
}

int64_t ss_asymmetric_q(const ss_friction_config_q_t *cfg, int64_t force_q24, int64_t load)
{
    if (cfg->asymmetry_q30 == 0 || load == 0) {
        return force_q24;
    }
    /* |force| < 2^32 (the int32 sum of two saturated terms) times < 2^31: within 64 bits */
    const int64_t factor = SS_Q30_ONE + ((load > 0) ? cfg->asymmetry_q30 : -(int64_t)cfg->asymmetry_q30);
    return ss_shr_round(ss_mul_i64_i32(force_q24, (int32_t)factor), 30); /* factor in (0.1, 1.9) x 2^30 */
}

/* r = |v| / vs in Q16.16, clamped where exp(-r^2) is zero anyway: m/s at 2^-28 times s/m at 2^-17
 * is a pure number at 2^-45. */
static int64_t stribeck_ratio_q16(const ss_friction_config_q_t *cfg, int32_t v_q28)
{
    const int64_t r = ss_shr_round(ss_mul_i64_i32(ss_abs64(v_q28), cfg->inv_vs_q45), 29);
    return (r > SS_Q_STRIBECK_R_MAX_Q16) ? SS_Q_STRIBECK_R_MAX_Q16 : r;
}

int32_t ss_stribeck_q(const ss_friction_config_q_t *cfg, int32_t v_q28)
{
    if (v_q28 == 0) {
        return cfg->fs_q24;
    }
    /* r in [0, 2^24] (clamped), e in [0, 2^30], Fs - Fc in [0, Fs]: 32-bit products */
    const int64_t r = stribeck_ratio_q16(cfg, v_q28);
    if (r >= SS_Q_STRIBECK_R_ZERO_Q16) {
        return cfg->fc_q24;
    }
    const int64_t e = ss_exp_neg_q32_q30(ss_mul_u32_u64((uint32_t)r, (uint32_t)r)); /* r^2 in Q32, exact */
    return (int32_t)(cfg->fc_q24 + ss_shr_round(ss_mul_s32_s64(cfg->fs_q24 - cfg->fc_q24, (int32_t)e), 30));
}

int32_t ss_stribeck_slope_q(const ss_friction_config_q_t *cfg, int32_t v_q28)
{
    int32_t slope;
    (void)ss_stribeck_with_slope_q(cfg, v_q28, &slope);
    return slope;
}

int32_t ss_stribeck_with_slope_q(const ss_friction_config_q_t *cfg, int32_t v_q28, int32_t *slope_q16)
{
    if (v_q28 == 0) {
        *slope_q16 = 0;
        return cfg->fs_q24;
    }
    const int64_t r = stribeck_ratio_q16(cfg, v_q28); /* as in ss_stribeck_q: 32-bit products */
    if (r >= SS_Q_STRIBECK_R_ZERO_Q16) {
        *slope_q16 = 0;
        return cfg->fc_q24;
    }
    const int64_t e = ss_exp_neg_q32_q30(ss_mul_u32_u64((uint32_t)r, (uint32_t)r)); /* r^2 in Q32, exact */
    const int64_t excess =
        ss_shr_round(ss_mul_s32_s64(cfg->fs_q24 - cfg->fc_q24, (int32_t)e), 30); /* N at 2^-24 */
    /* slope: (Fs - Fc) r e, then 2 x that / vs: N at 2^-24 times s/m at 2^-17, x 2 is N s/m at
     * 2^-40, to 2^-16. fre <= 0.43 (Fs - Fc) < 2^28 (the largest r e^-r^2): the product fits */
    const int64_t fre = ss_shr_round(ss_mul_i64_i32(excess, (int32_t)r), 16);
    const int64_t slope = ss_shr_round(ss_mul_i64_i32(fre, cfg->inv_vs_q45), 24);
    *slope_q16 = ss_sat32((v_q28 > 0) ? -slope : slope);
    return (int32_t)(cfg->fc_q24 + excess);
}
