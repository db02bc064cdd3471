/* Instruction counting of the PIL image (pil_icount.h, docs/pil.md). */
#include "aocs/pil_frame.h"
#include "aocs_cm.h"
#include "pil_icount.h"

/* SysTick current value register (ARMv7-M ARM B3.3.4) */
#define PIL_SYST_CVR (*(volatile uint32_t *)0xE000E018UL)

/* a SysTick tick is a whole number of ns (40 ns at the MPS2's 25 MHz SYSCLK) */
#if ((1000000000UL % AOCS_CM_CORE_HZ) != 0UL)
#error "AOCS_CM_CORE_HZ must divide 1 GHz for exact tick to instruction conversion"
#endif

/* a SysTick period is AOCS_CM_CORE_HZ / AOCS_CM_TICK_HZ ticks */
#define PIL_PERIOD_TICKS (AOCS_CM_CORE_HZ / AOCS_CM_TICK_HZ)
/* instructions left to the reload when the delay loop stops: the poll does the rest */
#define PIL_SYNC_MARGIN_INSTR 48U
/* the poll never reads the counter more often than a whole period's worth of ticks */
#define PIL_SYNC_READS_MAX PIL_PERIOD_TICKS

#if (AOCS_PIL_ICOUNT_WINDOW_LONG_TICKS >= PIL_PERIOD_TICKS)
#error "AOCS_PIL_ICOUNT_WINDOW_LONG_TICKS must be shorter than a SysTick period"
#endif

uint32_t aocs_pil_icount_sync(void)
{
    return aocs_pil_icount_sync_window(AOCS_PIL_ICOUNT_WINDOW_TICKS);
}

uint32_t aocs_pil_icount_sync_window(uint32_t window_ticks)
{
    uint32_t window = window_ticks;
    uint32_t left = PIL_SYST_CVR; /* ticks to the next reload (the counter runs down to 0) */
    /* never less than the default window, never more than a period holds */
    if (window < AOCS_PIL_ICOUNT_WINDOW_TICKS) {
        window = AOCS_PIL_ICOUNT_WINDOW_TICKS;
    }
    if (window > AOCS_PIL_ICOUNT_WINDOW_LONG_TICKS) {
        window = AOCS_PIL_ICOUNT_WINDOW_LONG_TICKS;
    }
    if (left < window) {
        /* too little of this period left for a window: run it out, mostly without touching the counter */
        const uint32_t instr = aocs_pil_icount_from_ticks(left);
        uint32_t prev;
        uint32_t reads = 0U;
        int reloaded = 0;
        if (instr > (PIL_SYNC_MARGIN_INSTR + 2U)) {
            aocs_pil_calib_loop((instr - PIL_SYNC_MARGIN_INSTR) / 2U);
        }
        prev = PIL_SYST_CVR;
        /* a reading above the previous one is the reload */
        while ((reloaded == 0) && (reads < PIL_SYNC_READS_MAX)) {
            const uint32_t now = PIL_SYST_CVR;
            if (now > prev) {
                reloaded = 1;
            }
            prev = now;
            reads++;
        }
        left = prev;
    }
    return left;
}

uint32_t aocs_pil_icount_from_ticks(uint32_t ticks)
{
    /* instructions = ticks * (ns per tick) / 2^shift, rounded to nearest (virtual ns = instructions 2^shift) */
    const uint64_t ns_per_tick = 1000000000ULL / (uint64_t)AOCS_CM_CORE_HZ;
    const uint64_t ns = (uint64_t)ticks * ns_per_tick;
    const uint64_t half = 1ULL << (AOCS_PIL_ICOUNT_SHIFT - 1U);
    const uint64_t instr = (ns + half) >> AOCS_PIL_ICOUNT_SHIFT;
    return (uint32_t)instr;
}
