/* The float friction laws' advance and force in parts (not public API). Each public
 * ss_*_advance_f32 / ss_*_force_at_f32 is its parts called in turn, so the actuator's batch
 * (ss_actuator_run_many_f32), which runs one part for several simulations before the next, computes
 * each simulation's bits exactly: a part is a chain of dependent operations, and the same part of
 * another simulation, independent of it, is what the core overlaps it with. */
#ifndef SS_FRICTION_PARTS_F32_H
#define SS_FRICTION_PARTS_F32_H

#include "ss_friction.h"
#include "ss_ls_friction.h"
#include "ss_lugre.h"

/* LuGre's advance: the slip velocity and its Stribeck level, then the bristle's relaxation. */
typedef struct {
    float v_m_per_s;
    float g_n;
    int moves; /* 0: nothing to advance (no motion, or input the advance ignores) */
} ss_lugre_slip_f32_t;

void ss_lugre_advance_begin_f32(const ss_friction_config_f32_t *cfg, float dx_m, float dt_s,
                                ss_lugre_slip_f32_t *s);
void ss_lugre_advance_end_f32(const ss_friction_config_f32_t *cfg, ss_lugre_state_f32_t *st, float dx_m,
                              const ss_lugre_slip_f32_t *s);

/* LuGre's force: the Stribeck level at v (and its slope when asked: with_slope), which does not
 * depend on the state, then the force at the state. */
typedef struct {
    float g_n;
    float slope_ns_per_m;
} ss_lugre_level_f32_t;

void ss_lugre_force_begin_f32(const ss_friction_config_f32_t *cfg, float v_m_per_s, int with_slope,
                              ss_lugre_level_f32_t *l);
float ss_lugre_force_end_f32(const ss_friction_config_f32_t *cfg, const ss_lugre_state_f32_t *st,
                             float v_m_per_s, const ss_lugre_level_f32_t *l,
                             ss_friction_slopes_f32_t *slopes);

/* LS's advance: the presliding element (reversals, Masing branch, break-away gate), then the
 * LuGre part's level in the gross slip. */
typedef struct {
    float fm_old_n;
    float gate_old;
    int moves; /* 0: input the advance ignores */
} ss_ls_branch_f32_t;

void ss_ls_advance_begin_f32(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st, float dx_m,
                             float dt_s, ss_ls_branch_f32_t *b);
void ss_ls_advance_end_f32(const ss_friction_config_f32_t *cfg, ss_ls_state_f32_t *st, float dx_m, float dt_s,
                           const ss_ls_branch_f32_t *b);

#endif /* SS_FRICTION_PARTS_F32_H */
