/*
 * Hardware abstraction: the only platform services the firmware uses.
 * Implemented by port/posix (host, SIL) and port/cortex-m (target).
 */
#ifndef AOCS_HAL_H
#define AOCS_HAL_H

#include <stdint.h>
#include "aocs/types.h"

/* Monotonic time since an arbitrary origin, ns. */
uint64_t aocs_hal_time_ns(void);

/*
 * Free-running cycle counter of the core (DWT CYCCNT on Cortex-M, TSC-like or
 * 0 where the platform has none); wraps modulo 2^32.
 */
uint32_t aocs_hal_cycles(void);

/*
 * Sleep until the absolute monotonic time t_ns (no-op when already past).
 * Returns AOCS_OK, or AOCS_ERR_NULL_ARG-style codes never; total.
 */
void aocs_hal_sleep_until_ns(uint64_t t_ns);

#endif /* AOCS_HAL_H */
