#include "ss_ls_friction.h"

#include <math.h>
#include <stddef.h>

#include "ss_check.h"
#include "ss_exp_f32.h"
#include "ss_friction_inline_f32.h"
#include "ss_friction_parts_f32.h"
#include "ss_inline.h"

/* Beyond this many presliding lengths Fs/sigma0 the virgin curve equals Fs to float precision
 * (exp(-24) ~ 4e-11), so the frame can be re-based without changing any force. */
#define SS_LS_SATURATION_LENGTHS 24.0f

/* Smooth step from 0 (presliding force below SS_LS_BREAKAWAY_RATIO of Fs) to 1 (at Fs): only
 * gross slip drives the LuGre part, as the elasto-plastic model's alpha(z) does. */
static float breakaway_gate(float fm_over_fs)
{
    const float over = fm_over_fs - SS_LS_BREAKAWAY_RATIO;
    if (over <= 0.0f) {
        return 0.0f; /* the quotient below has over's sign: the same test, without the division */
    }
    const float t = over / (1.0f - SS_LS_BREAKAWAY_RATIO);
    if (t >= 1.0f) {
        return 1.0f;
    }
    return t * t * (3.0f - 2.0f * t);
}

/* The gate of the state's F_M under cfg's Fs: the one the last step kept when it was taken at
 * that Fs (the same bits), else computed. */
static float gate_of(const ss_friction_config_f32_t *cfg, const ss_ls_state_f32_t *st)
{
    return (st->gate_fs_n == cfg->fs_n) ? st->gate : breakaway_gate(fabsf(st->fm_n) / cfg->fs_n);
}

ss_status_t ss_ls_init_f32(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st)
{
    if (st == NULL) {
        return SS_ERR_NULL;
    }
    ss_status_t status = ss_friction_config_check_f32(cfg, NULL);
    if (status != SS_OK) {
        return status;
    }
    st->x_m = 0.0f;
    st->x0_m = 0.0f;
    st->fm_n = 0.0f;
    st->kt_n_per_m = cfg->sigma0_n_per_m;
    st->level_n = cfg->fs_n;
    st->force_n = 0.0f;
    st->gate = 0.0f; /* F_M = 0 lies below the break-away at any Fs */
    st->gate_fs_n = cfg->fs_n;
    st->dir = 0;
    st->depth = 0;
    for (int i = 0; i < SS_LS_MEMORY_DEPTH; ++i) {
        st->rev[i].x_m = 0.0f;
        st->rev[i].f_n = 0.0f;
    }
    return SS_OK;
}

static void push_reversal(ss_ls_state_f32_t *st)
{
    if (st->depth >= SS_LS_MEMORY_DEPTH) {
        /* Forget the innermost (smallest, most recent) minor loop; parity of the stack holds. */
        st->depth = (uint8_t)(st->depth - 2u);
    }
    st->rev[st->depth].x_m = st->x_m;
    st->rev[st->depth].f_n = st->fm_n;
    st->depth++;
}

/* Wiping-out: a branch that reaches the reversal point where the opposite branch began closes
 * that minor loop, and motion resumes on the branch that was active before it. */
SS_FORCE_INLINE void close_loops(ss_ls_state_f32_t *st)
{
    const float d = (float)st->dir;
    for (;;) {
        if (st->depth >= 2u && d * (st->x_m - st->rev[st->depth - 2u].x_m) >= 0.0f) {
            st->depth = (uint8_t)(st->depth - 2u);
        } else if (st->depth == 1u && d * (st->x_m - (2.0f * st->x0_m - st->rev[0].x_m)) >= 0.0f) {
            st->depth = 0u; /* back on the virgin curve, at the mirror of the first reversal */
        } else {
            return;
        }
    }
}

/* Masing branches of the exponential virgin curve phi(u) = Fs (1 - exp(-sigma0 u / Fs)). */
SS_FORCE_INLINE void eval_branch(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st)
{
    const float fs = cfg->fs_n;
    const float k0 = cfg->sigma0_n_per_m;
    if (st->depth == 0u) {
        const float u = st->x_m - st->x0_m;
        float e;
        const float em1 = ss_expm1_neg_f32(k0 * fabsf(u) / fs, &e);
        st->fm_n = -ss_sign_f32(u) * fs * em1;
        st->kt_n_per_m = k0 * e;
    } else {
        const ss_ls_reversal_f32_t *r = &st->rev[st->depth - 1u];
        float e;
        const float em1 = ss_expm1_neg_f32(k0 * fabsf(st->x_m - r->x_m) / (2.0f * fs), &e);
        st->fm_n = r->f_n - (float)st->dir * 2.0f * fs * em1;
        st->kt_n_per_m = k0 * e;
    }
}

static void rebase(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st)
{
    if (st->depth != 0u) {
        return; /* reversal points bound the excursion: nothing grows */
    }
    const float u = st->x_m - st->x0_m;
    const float l_sat = SS_LS_SATURATION_LENGTHS * cfg->fs_n / cfg->sigma0_n_per_m;
    if (fabsf(u) > l_sat) {
        st->x0_m = -ss_sign_f32(u) * l_sat;
        st->x_m = 0.0f;
    }
}

/* The advance's parts (ss_friction_parts_f32.h), inline here as for LuGre. */
SS_FORCE_INLINE void advance_begin(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st, float dx_m,
                                   float dt_s, ss_ls_branch_f32_t *b)
{
    b->moves = !(!isfinite(dx_m) || !isfinite(dt_s) || !(dt_s > 0.0f));
    if (!b->moves) {
        return;
    }
    b->fm_old_n = st->fm_n;
    const float gate_old = gate_of(cfg, st);
    b->gate_old = gate_old;
    if (dx_m != 0.0f) {
        const int8_t d = (dx_m > 0.0f) ? (int8_t)1 : (int8_t)-1;
        if (st->dir != 0 && d != st->dir) {
            push_reversal(st);
        }
        st->dir = d;
        st->x_m += dx_m;
        close_loops(st);
        eval_branch(cfg, st);
        rebase(cfg, st);
        st->gate = breakaway_gate(fabsf(st->fm_n) / cfg->fs_n);
    } else {
        st->gate = gate_old;
    }
    st->gate_fs_n = cfg->fs_n;
}

SS_FORCE_INLINE void advance_end(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st, float dx_m,
                                 float dt_s, const ss_ls_branch_f32_t *b)
{
    if (!b->moves) {
        return;
    }
    const float fm_old = b->fm_old_n;
    const float gate_old = b->gate_old;
    /* Elastic-plastic split of the increment: what the presliding element does not take up
     * elastically has slipped (zero right after a reversal). It counts as gross slip only once the
     * presliding force nears its saturation, so presliding stays rate independent. The gate is
     * taken as its mean over the step (its two ends): at the end alone, a step in which the contact
     * saturates counted all its slip as gross, and the level fell too fast at the break-away (the
     * first-order error of the LS step, docs/model.md). */
    float slip = 0.0f; /* both gates 0 (presliding, most steps): a finite slip times 0, signs aside */
    if (gate_old != 0.0f || st->gate != 0.0f) {
        slip = dx_m - (st->fm_n - fm_old) / cfg->sigma0_n_per_m;
        if (slip * dx_m < 0.0f) {
            slip = 0.0f; /* rounding only: the tangent stiffness never exceeds sigma0 */
        }
        slip *= 0.5f * (gate_old + st->gate);
    }
    /* LuGre in the slip: the break-away level s relaxes to g(v_slip) over the distance g/sigma0,
     * exact for a slip velocity frozen over the step. */
    const float g = ss_stribeck_inline_f32(cfg, slip / dt_s);
    /* no gross slip (presliding, sticking): exp(0) = 1, the same arithmetic without the exp */
    const float decay = (slip == 0.0f) ? 1.0f : ss_exp_neg_f32(cfg->sigma0_n_per_m * fabsf(slip) / g);
    st->level_n = g + (st->level_n - g) * decay;
}

void ss_ls_advance_f32(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st, float dx_m, float dt_s)
{
    ss_ls_branch_f32_t b;
    advance_begin(cfg, st, dx_m, dt_s, &b);
    advance_end(cfg, st, dx_m, dt_s, &b);
}

void ss_ls_advance_begin_f32(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st, float dx_m,
                             float dt_s, ss_ls_branch_f32_t *b)
{
    advance_begin(cfg, st, dx_m, dt_s, b);
}

void ss_ls_advance_end_f32(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st, float dx_m, float dt_s,
                           const ss_ls_branch_f32_t *b)
{
    advance_end(cfg, st, dx_m, dt_s, b);
}

float ss_ls_step_f32(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st, float dx_m, float dt_s)
{
    if (!isfinite(dx_m) || !isfinite(dt_s) || !(dt_s > 0.0f)) {
        return st->force_n;
    }
    ss_ls_advance_f32(cfg, st, dx_m, dt_s);
    st->force_n = ss_ls_force_at_f32(cfg, st, dx_m / dt_s, NULL);
    return st->force_n;
}

float ss_ls_force_at_f32(const ss_friction_config_f32_t *cfg, const ss_ls_state_f32_t *st, float v_m_per_s,
                         ss_friction_slopes_f32_t *slopes)
{
    /* gross-slip velocity: the share of v the presliding element does not take up elastically */
    const float gate = gate_of(cfg, st);
    /* kt <= sigma0 (kt is sigma0 times exp(-a) <= 1), so the first factor is >= 0 and a gate of 0
     * gives +0 either way */
    const float share = (gate == 0.0f) ? 0.0f : (1.0f - st->kt_n_per_m / cfg->sigma0_n_per_m) * gate;
    const float vp = v_m_per_s * share;
    float slope = 0.0f;
    const float g = (slopes != NULL) ? ss_stribeck_with_slope_inline_f32(cfg, vp, &slope)
                                     : ss_stribeck_inline_f32(cfg, vp);
    const float zdot = vp * (1.0f - st->level_n / g); /* LuGre's dz/dt once sliding, sigma0 z = s */
    const float asym = ss_asymmetry_inline_f32(cfg, st->fm_n);
    const float level_share = st->level_n / cfg->fs_n;
    if (slopes != NULL) {
        const float dzdvp = (1.0f - st->level_n / g) + vp * st->level_n * slope / (g * g);
        slopes->dfdv_ns_per_m = asym * cfg->sigma1_ns_per_m * share * dzdvp + cfg->sigma2_ns_per_m;
        slopes->dfdx_n_per_m = asym * level_share * st->kt_n_per_m; /* the Masing branch's */
    }
    return asym * (level_share * st->fm_n + cfg->sigma1_ns_per_m * zdot) + cfg->sigma2_ns_per_m * v_m_per_s;
}

ss_status_t ss_ls_run_f32(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st, const float *dx_m,
                          uint32_t n, float dt_s, float *force_n)
{
    if (cfg == NULL || st == NULL || (n > 0u && (dx_m == NULL || force_n == NULL))) {
        return SS_ERR_NULL;
    }
    ss_status_t status = ss_check_range_f32(dt_s, 1e-12f, 1e3f);
    for (uint32_t i = 0; status == SS_OK && i < n; ++i) {
        if (!isfinite(dx_m[i])) {
            return SS_ERR_NONFINITE;
        }
        force_n[i] = ss_ls_step_f32(cfg, st, dx_m[i], dt_s);
    }
    return status;
}
