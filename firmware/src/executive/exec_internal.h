/*
 * Private interface between the executive's source files (law_table.c,
 * mode.c, gain_tables.c, timing.c, executive.c). Not part of the public API.
 */
#ifndef AOCS_EXEC_INTERNAL_H
#define AOCS_EXEC_INTERNAL_H

#include "aocs/executive.h"

/* 1 when law is a real law id (not NONE, not out of range). */
int aocs_exec_law_is_valid(aocs_law_id_t law);

/* Target check: finite, unit qd (AOCS_ERR_TARGET_INVALID). */
aocs_status_t aocs_exec_target_check(const aocs_exec_target_t *target);

/* SAFE-mode gain check: AOCS_ERR_PARAM_NOT_FINITE (not finite), AOCS_ERR_GAIN_NOT_POSITIVE (<= 0). */
aocs_status_t aocs_exec_safe_config_check(const aocs_exec_config_t *cfg);

/* Safe-mode command before saturation: rate damping of the estimate (attitude, RATE flag, finite), else zero. */
aocs_vec3_t aocs_exec_safe_command(const aocs_exec_config_t *cfg, aocs_law_id_t law,
                                   const aocs_det_output_t *est);

/* Counter increment that sticks at the maximum instead of wrapping. */
void aocs_exec_count(uint32_t *counter, uint32_t n);

#endif /* AOCS_EXEC_INTERNAL_H */
