/*
 * HAL of firmware/include/aocs/hal.h for ARMv7-M (Cortex-M4F, Cortex-M7).
 *
 * Time base: SysTick counting the core clock (CLKSOURCE = 1) with a
 * AOCS_CM_TICK_HZ interrupt that extends the 24-bit down-counter to a 64-bit
 * tick count. Under QEMU this follows QEMU's virtual clock, which is
 * deterministic with -icount shift=N (one instruction = 2^N ns, so
 * 2^N * 25 MHz / 1 GHz ticks per instruction: shift=5 gives 0.8).
 *
 * Cycle counter: DWT CYCCNT (ARMv7-M ARM C1.8) when it runs. QEMU models the
 * DWT registers but CYCCNT stays 0, so the first call checks that it
 * advances and otherwise falls back to the low 32 bits of the SysTick tick
 * count, which is the same unit (core clock cycles).
 *
 * Both services start themselves on first use (hal.h has no init call).
 * Registers are reached through fixed addresses (MISRA 11.4 deviation in
 * firmware/MISRA-DEVIATIONS.md).
 */
#include "aocs/hal.h"
#include "aocs_cm.h"

/* System Control Space registers (ARMv7-M ARM B3.2.4 ICSR, B3.3 SysTick, C1.6 DEMCR, C1.8 DWT) */
#define CM_SYST_CSR (*(volatile uint32_t *)0xE000E010UL)
#define CM_SYST_RVR (*(volatile uint32_t *)0xE000E014UL)
#define CM_SYST_CVR (*(volatile uint32_t *)0xE000E018UL)
#define CM_ICSR (*(volatile uint32_t *)0xE000ED04UL)
#define CM_DEMCR (*(volatile uint32_t *)0xE000EDFCUL)
#define CM_DWT_CTRL (*(volatile uint32_t *)0xE0001000UL)
#define CM_DWT_CYCCNT (*(volatile uint32_t *)0xE0001004UL)

#define CM_SYST_CSR_ENABLE 0x1UL
#define CM_SYST_CSR_TICKINT 0x2UL
#define CM_SYST_CSR_CLKSOURCE 0x4UL
#define CM_ICSR_PENDSTSET 0x04000000UL
#define CM_DEMCR_TRCENA 0x01000000UL
#define CM_DWT_CTRL_CYCCNTENA 0x1UL
#define CM_DWT_CTRL_NOCYCCNT 0x02000000UL

/* core clock ticks per SysTick interrupt; RVR holds this minus one */
#define CM_TICK_PERIOD ((uint64_t)AOCS_CM_CORE_HZ / (uint64_t)AOCS_CM_TICK_HZ)
#define CM_NS_PER_S 1000000000ULL

/* SysTick wraps since start, written only by SysTick_Handler. */
static volatile uint64_t cm_systick_wraps;
/* 1 when DWT CYCCNT counts (set once by cm_cycles_dwt_runs). */
static uint32_t cm_cycles_dwt;

/* Stack bounds from mps2.ld */
extern uint32_t __stack_limit;
extern uint32_t __stack_top;

void SysTick_Handler(void)
{
    cm_systick_wraps = cm_systick_wraps + 1U;
}

static void cm_timebase_start(void)
{
    static uint32_t cm_timebase_started = 0U;
    if (cm_timebase_started == 0U) {
        cm_systick_wraps = 0U;
        CM_SYST_RVR = (uint32_t)(CM_TICK_PERIOD - 1U);
        CM_SYST_CVR = 0U; /* any write clears the counter */
        CM_SYST_CSR = CM_SYST_CSR_CLKSOURCE | CM_SYST_CSR_TICKINT | CM_SYST_CSR_ENABLE;
        cm_timebase_started = 1U;
    }
}

/*
 * Core clock ticks since the time base started. The counter can reload
 * before SysTick_Handler has counted the wrap (exception entry latency on
 * silicon; QEMU only takes interrupts between translation blocks), so a
 * pending SysTick (ICSR.PENDSTSET) means one more wrap, and the counter is
 * read again after it. QEMU without -icount can still show a reloaded
 * counter with neither the wrap counted nor PENDSTSET set (its SysTick
 * follows host time, its interrupts arrive later); a reading below the
 * previous one by less than a period is that wrap, and the result is never
 * allowed to go back (hal.h: monotonic).
 */
static uint64_t cm_ticks(void)
{
    static uint64_t cm_last_ticks = 0U;
    uint64_t ticks;
    uint64_t wraps_before;
    uint64_t wraps_after;
    uint32_t count;
    uint32_t pending;
    cm_timebase_start();
    /* A counted wrap between the two reads of the wrap count makes them differ. */
    do {
        wraps_before = cm_systick_wraps;
        count = CM_SYST_CVR;
        pending = CM_ICSR & CM_ICSR_PENDSTSET;
        wraps_after = cm_systick_wraps;
    } while (wraps_before != wraps_after);
    if (pending != 0U) {
        wraps_after = wraps_after + 1U;
        count = CM_SYST_CVR;
    }
    /* the counter runs down from RVR to 0 */
    ticks = (wraps_after * CM_TICK_PERIOD) + ((CM_TICK_PERIOD - 1U) - (uint64_t)count);
    if ((ticks < cm_last_ticks) && ((cm_last_ticks - ticks) < CM_TICK_PERIOD)) {
        ticks = ticks + CM_TICK_PERIOD;
    }
    if (ticks < cm_last_ticks) {
        ticks = cm_last_ticks;
    }
    cm_last_ticks = ticks;
    return ticks;
}

uint64_t aocs_hal_time_ns(void)
{
    const uint64_t ticks = cm_ticks();
    const uint64_t sec = ticks / (uint64_t)AOCS_CM_CORE_HZ;
    const uint64_t rem = ticks % (uint64_t)AOCS_CM_CORE_HZ;
    return (sec * CM_NS_PER_S) + ((rem * CM_NS_PER_S) / (uint64_t)AOCS_CM_CORE_HZ);
}

static void cm_cycles_check(void)
{
    static uint32_t cm_cycles_checked = 0U;
    if (cm_cycles_checked == 0U) {
        cm_cycles_dwt = 0U;
        CM_DEMCR = CM_DEMCR | CM_DEMCR_TRCENA;
        if ((CM_DWT_CTRL & CM_DWT_CTRL_NOCYCCNT) == 0U) {
            uint32_t first;
            uint32_t spin;
            CM_DWT_CYCCNT = 0U;
            CM_DWT_CTRL = CM_DWT_CTRL | CM_DWT_CTRL_CYCCNTENA;
            first = CM_DWT_CYCCNT;
            for (spin = 0U; spin < 64U; spin++) {
                (void)CM_DWT_CTRL; /* volatile reads: the loop cannot vanish */
            }
            if (CM_DWT_CYCCNT != first) {
                cm_cycles_dwt = 1U;
            }
        }
        cm_cycles_checked = 1U;
    }
}

uint32_t aocs_hal_cycles(void)
{
    uint32_t cycles;
    cm_cycles_check();
    if (cm_cycles_dwt != 0U) {
        cycles = CM_DWT_CYCCNT;
    } else {
        cycles = (uint32_t)(cm_ticks() & 0xFFFFFFFFULL);
    }
    return cycles;
}

uint32_t aocs_cm_cycles_from_dwt(void)
{
    cm_cycles_check();
    return cm_cycles_dwt;
}

void aocs_hal_sleep_until_ns(uint64_t t_ns)
{
    const uint64_t tick_period_ns = CM_NS_PER_S / (uint64_t)AOCS_CM_TICK_HZ;
    uint64_t now = aocs_hal_time_ns();
    while (now < t_ns) {
        /* sleep through whole SysTick periods, busy-wait the remainder */
        if ((t_ns - now) > tick_period_ns) {
            aocs_cm_wfi();
        }
        now = aocs_hal_time_ns();
    }
}

uint32_t aocs_cm_stack_high_water(void)
{
    /* the stack region is a bare address range from mps2.ld, not a C object */
    const uintptr_t limit = (uintptr_t)&__stack_limit;
    const uintptr_t top = (uintptr_t)&__stack_top;
    const volatile uint32_t *const words = (const volatile uint32_t *)limit;
    const uint32_t n_words = (uint32_t)((top - limit) / sizeof(uint32_t));
    uint32_t unused = 0U;
    while ((unused < n_words) && (words[unused] == (uint32_t)AOCS_CM_STACK_PAINT)) {
        unused++;
    }
    return (n_words - unused) * (uint32_t)sizeof(uint32_t);
}
