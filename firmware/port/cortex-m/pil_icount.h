/*
 * Exact instruction counts in the PIL image (docs/pil.md, "Counting
 * instructions"). QEMU runs with -icount shift=AOCS_PIL_ICOUNT_SHIFT: its
 * virtual clock advances 2^shift ns per executed guest instruction, and the
 * SysTick of the MPS2 board counts that clock at 25 MHz. The HAL's cycle
 * counter (aocs_hal_cycles: DWT CYCCNT on silicon, the SysTick fallback under
 * QEMU, where CYCCNT stays 0) therefore counts 40/2^shift instructions per
 * tick; with shift 7 that is exactly 3.2 ticks per instruction, so a tick
 * difference rounds to the exact instruction count (the +-1 tick of reading
 * the counter is 0.31 instruction).
 *
 * Repeatability: the HAL extends SysTick with a 100 Hz interrupt. A step that
 * contained such an interrupt (and the HAL's wrap handling) would count a
 * few instructions more than the same step without, depending on when the
 * step started. aocs_pil_icount_sync() makes sure that at least
 * AOCS_PIL_ICOUNT_WINDOW_TICKS (22500 instructions; with the MEKF
 * AOCS_PIL_ICOUNT_WINDOW_LONG_TICKS, 77500) of the current SysTick
 * period are left before a window starts, waiting for the next reload when
 * they are not; a window shorter than that contains no wrap, so the count of
 * a step depends only on what the step executes. Whether that held is
 * checked after the fact (window ticks < ticks that were left): the
 * `exact` flag of the reply. Cortex-M port only.
 */
#ifndef AOCS_PIL_ICOUNT_H
#define AOCS_PIL_ICOUNT_H

#include <stdint.h>

/* SysTick ticks a measured window may take (72000 ticks = 22500 instructions, of a 250000-tick period:
 * the image waits for the reload before less than a third of the steps). */
#define AOCS_PIL_ICOUNT_WINDOW_TICKS 72000UL

/* The longest window a SysTick period holds: 248000 ticks = 77500 instructions of the 250000-tick
 * (78125-instruction) period, less the sync's slack. The PIL image asks for it when the MEKF flies (an
 * MEKF step takes 20000 to 40000 instructions with fresh tracker samples), so it waits for the reload
 * before every step: a step up to 77500 instructions is counted exactly. A longer one (a tracker sample
 * many periods old, walked back along the gyro history) cannot be: it contains a SysTick interrupt, and
 * the reply says so (exact = 0). */
#define AOCS_PIL_ICOUNT_WINDOW_LONG_TICKS 248000UL

/*
 * Returns when at least AOCS_PIL_ICOUNT_WINDOW_TICKS are left before the next
 * SysTick reload (waiting for the reload if needed); returns the ticks left.
 */
uint32_t aocs_pil_icount_sync(void);

/*
 * The same for a window of window_ticks, taken within [AOCS_PIL_ICOUNT_WINDOW_TICKS,
 * AOCS_PIL_ICOUNT_WINDOW_LONG_TICKS].
 */
uint32_t aocs_pil_icount_sync_window(uint32_t window_ticks);

/* Instructions in a window of `ticks` SysTick ticks (rounded to nearest). */
uint32_t aocs_pil_icount_from_ticks(uint32_t ticks);

/* Executes exactly 2 n + 1 instructions after the call (n >= 1): pil_calib.S. */
void aocs_pil_calib_loop(uint32_t n);

#endif /* AOCS_PIL_ICOUNT_H */
