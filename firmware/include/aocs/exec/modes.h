/*
 * The executive's modes and clock (part of aocs/executive.h; mode rules in
 * aocs/exec/pipeline.h).
 */
#ifndef AOCS_EXEC_MODES_H
#define AOCS_EXEC_MODES_H

#include "aocs/types.h"

/* ---- modes ---- */
typedef enum {
    AOCS_EXEC_MODE_STANDBY = 0, /* zero command */
    AOCS_EXEC_MODE_NOMINAL,     /* selected law */
    AOCS_EXEC_MODE_SAFE,        /* rate damping (attitude) / zero force (orbit) */
    AOCS_EXEC_MODE_COUNT
} aocs_exec_mode_t;

/* "standby", "nominal", "safe"; "unknown" when out of range. Total. */
const char *aocs_exec_mode_name(aocs_exec_mode_t mode);

/* Where time comes from (ARCHITECTURE.md): the sensor message (lockstep) or the HAL clock. */
typedef enum {
    AOCS_EXEC_CLOCK_LOCKSTEP = 0, /* the sensor sample is the tick; HAL clock only times the step */
    AOCS_EXEC_CLOCK_REALTIME      /* sample age is also checked against aocs_hal_time_ns() */
} aocs_exec_clock_t;

#endif /* AOCS_EXEC_MODES_H */
