/*
 * Estimator PASSTHROUGH (row of aocs/estimation/determination.def;
 * src/estimation/passthrough.c): the measured attitude and rate as they are,
 * the input acceptance's verdict as the status. No configuration.
 */
#ifndef AOCS_ESTIMATION_PASSTHROUGH_H
#define AOCS_ESTIMATION_PASSTHROUGH_H

#include <stdint.h>

/* It keeps no estimate: its state counts steps (a C99 struct needs a member). */
typedef struct {
    uint32_t steps;
} aocs_det_passthrough_state_t;

#endif /* AOCS_ESTIMATION_PASSTHROUGH_H */
