/*
 * The executive's modes and clock (part of aocs/executive.h; mode rules in
 * aocs/exec/pipeline.h, the clock's time rules in aocs/exec/acceptance.def).
 */
#ifndef AOCS_EXEC_MODES_H
#define AOCS_EXEC_MODES_H

#include "aocs/types.h"
#include "aocs/exec/acceptance.def"

/* ---- modes ---- */
typedef enum {
    AOCS_EXEC_MODE_STANDBY = 0, /* zero command */
    AOCS_EXEC_MODE_NOMINAL,     /* selected law */
    AOCS_EXEC_MODE_SAFE,        /* rate damping (attitude) / zero force (orbit) */
    AOCS_EXEC_MODE_COUNT
} aocs_exec_mode_t;

/* "standby", "nominal", "safe"; "unknown" when out of range. Total. */
const char *aocs_exec_mode_name(aocs_exec_mode_t mode);

/*
 * Where time comes from (ARCHITECTURE.md): the sensor message (LOCKSTEP: the
 * sensor sample is the tick; the HAL clock only times the step) or the HAL
 * clock (REALTIME: the sample's age is also checked against
 * aocs_hal_time_ns()). One value per time rule of the input acceptance
 * (aocs/exec/acceptance.def, in row order).
 */
#define AOCS_EXEC_CLOCK_ENUM_ROW(ID, ...) AOCS_EXEC_CLOCK_##ID,
typedef enum {
    AOCS_ACCEPTANCE_ROWS(AOCS_EXEC_CLOCK_ENUM_ROW)
    AOCS_EXEC_CLOCK_COUNT
} aocs_exec_clock_t;

#endif /* AOCS_EXEC_MODES_H */
