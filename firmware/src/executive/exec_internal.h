/*
 * Private interface between the executive's source files (law_table.c,
 * mode.c, guidance.c, gain_tables.c, executive.c). Not part of the public API.
 */
#ifndef AOCS_EXEC_INTERNAL_H
#define AOCS_EXEC_INTERNAL_H

#include "aocs/executive.h"

/* 1 when law is a real law id (not NONE, not out of range). */
int aocs_exec_law_is_valid(aocs_law_id_t law);

/* Input check for the selected law: AOCS_OK or the reason (flags, NaN, non-unit q). */
aocs_status_t aocs_exec_input_check(aocs_law_id_t law, const aocs_exec_input_t *in);

/* Target check: finite, unit qd (AOCS_ERR_TARGET_INVALID). */
aocs_status_t aocs_exec_target_check(const aocs_exec_target_t *target);

/* Safe-mode command before saturation: the rate damping of mode.c (attitude, valid rate), else zero. */
aocs_vec3_t aocs_exec_safe_command(const aocs_exec_config_t *cfg, aocs_law_id_t law,
                                   const aocs_exec_input_t *in);

/*
 * Apply the actuator limits of cfg; the result is finite and within every
 * enabled limit, also when u is NaN/Inf. *saturated = 1 when changed.
 */
aocs_vec3_t aocs_exec_saturate(const aocs_exec_config_t *cfg, aocs_vec3_t u, int *saturated);

/* Limit-config check (see aocs_exec_init). */
aocs_status_t aocs_exec_limits_check(const aocs_exec_config_t *cfg);

/* Rotating-target attitude qd(t) = dq(w dt) (x) qd0 (guidance.c). Total. */
aocs_quat_t aocs_exec_guidance_attitude(aocs_quat_t qd0_DN, aocs_vec3_t w_DN_D, real_t dt_s);

/*
 * wd_B = A(qe) w, wd_dot_B = wd_B x w_BN_B for a target rotating at w (in D),
 * qe = q (x) qd^-1 normalised (guidance.c); zero when qe cannot be
 * normalised. NULL outputs are skipped. Total.
 */
void aocs_exec_guidance_rates(aocs_quat_t q_BN, aocs_quat_t qd_DN, aocs_vec3_t w_DN_D, aocs_vec3_t w_BN_B,
                              aocs_vec3_t *wd_B, aocs_vec3_t *wd_dot_B);

/*
 * Slew reference rates in B (guidance mode SLEW): with qe = q (x) qd^-1
 * normalised and A = A(qe) = A_BD,
 *     wd_B = A wd_D,  wd_dot_B = A wd_dot_D + wd_B x w_BN_B
 * (d/dt of the B components: dA/dt = -[(w - wd_B) x] A, as in guidance.c
 * for the rotating target, plus the profile's own acceleration). Zero when
 * qe cannot be normalised. NULL outputs are skipped. Total.
 */
void aocs_exec_slew_rates(aocs_quat_t q_BN, aocs_quat_t qd_DN, aocs_vec3_t wd_D, aocs_vec3_t wd_dot_D,
                          aocs_vec3_t w_BN_B, aocs_vec3_t *wd_B, aocs_vec3_t *wd_dot_B);

/* t - t0 in seconds, negative when t < t0, without forming a huge real ns count. Total. */
real_t aocs_exec_elapsed_s(uint64_t t_ns, uint64_t t0_ns);

/*
 * Wheel array (wheels.c): aocs_exec_wheels_init validates and initialises it
 * when cfg.wheels.n != 0 (AOCS_OK without an array); aocs_exec_wheels_apply
 * allocates out->u_cmd to the wheels (omega: tachometer speeds, w: body rate
 * for the momentum), replaces u_cmd by what they deliver and sets *saturated
 * when the allocation scaled it. Without an array it does nothing. Total.
 */
aocs_status_t aocs_exec_wheels_init(aocs_exec_t *exec, const aocs_exec_config_t *cfg);
void aocs_exec_wheels_apply(aocs_exec_t *exec, const real_t *omega_radps, aocs_vec3_t w_BN_B,
                            aocs_exec_output_t *out, int *saturated);

/* Counter increment that sticks at the maximum instead of wrapping. */
void aocs_exec_count(uint32_t *counter, uint32_t n);

#endif /* AOCS_EXEC_INTERNAL_H */
