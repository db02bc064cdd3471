/*
 * POSIX HAL (host builds, SIL): CLOCK_MONOTONIC for time, absolute
 * clock_nanosleep for deadlines (no drift), the x86 TSC as cycle counter
 * where the compiler exposes it, else 0 (hal.h allows "0 where none").
 * _POSIX_C_SOURCE comes from CMakeLists.txt (clock_* under -std=c99).
 */
#include <errno.h>
#include <stddef.h>
#include <time.h>

#include "aocs/hal.h"

#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

#define NS_PER_S 1000000000ULL

uint64_t aocs_hal_time_ns(void)
{
    struct timespec ts;
    uint64_t t = 0u;
    if (clock_gettime(CLOCK_MONOTONIC, &ts) == 0) {
        uint64_t sec = (uint64_t)ts.tv_sec;
        uint64_t nsec = (uint64_t)ts.tv_nsec;
        t = (sec * NS_PER_S) + nsec;
    }
    return t;
}

uint32_t aocs_hal_cycles(void)
{
    uint32_t c = 0u;
#if defined(__x86_64__) || defined(__i386__)
    uint64_t tsc = (uint64_t)__rdtsc();
    c = (uint32_t)tsc; /* wraps modulo 2^32 as hal.h states */
#endif
    return c;
}

void aocs_hal_sleep_until_ns(uint64_t t_ns)
{
    struct timespec ts;
    uint64_t sec = t_ns / NS_PER_S;
    uint64_t nsec = t_ns % NS_PER_S;
    int rc;
    ts.tv_sec = (time_t)sec;
    ts.tv_nsec = (long)nsec;
    /* a signal interrupts the sleep: resume to the same absolute deadline */
    do {
        rc = clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
    } while (rc == EINTR);
}
