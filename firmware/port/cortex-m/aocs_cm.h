/*
 * Cortex-M port internals shared by the HAL, the semihosting helpers and the
 * image main (not part of the portable firmware API).
 */
#ifndef AOCS_CM_H
#define AOCS_CM_H

#include <stdint.h>

/*
 * Core clock of the MPS2 FPGA images that QEMU models (AN386, AN500:
 * 25 MHz SYSCLK); SysTick counts it (CLKSOURCE = processor clock).
 * Override with -DAOCS_CM_CORE_HZ=... for another board.
 */
#ifndef AOCS_CM_CORE_HZ
#define AOCS_CM_CORE_HZ 25000000UL
#endif

/* SysTick interrupt rate: the extension of the 24-bit counter to 64 bits. 100 Hz: a period of 250000
 * ticks (78125 instructions under the PIL's -icount), so the PIL image can measure a whole wheel-array
 * step with its slew planning (about 10000 instructions) between two interrupts (pil_icount.h). */
#define AOCS_CM_TICK_HZ 100UL

/* Value startup.S writes over the free main stack (high-water mark). */
#define AOCS_CM_STACK_PAINT 0xA5A5A5A5UL

/* ---- startup.S ---- */
/* Semihosting request: operation op, parameter block arg; returns r0. */
uint32_t aocs_cm_semihost_call(uint32_t op, const void *arg);
/* Wait for interrupt. */
void aocs_cm_wfi(void);
/* Current main stack pointer. */
uint32_t aocs_cm_sp(void);
/* SysTick exception (hal_cortex_m.c overrides the weak fault stub). */
void SysTick_Handler(void);

/* ---- semihost.c ---- */
/* Write a NUL-terminated string to the host console (SYS_WRITE0). */
void aocs_cm_write(const char *text);
/* Append the decimal text of value to buf at *pos (bounded by cap, NUL kept). */
void aocs_cm_fmt_int(char *buf, uint32_t cap, uint32_t *pos, int64_t value);
/* Append text to buf at *pos (bounded by cap, NUL kept). */
void aocs_cm_fmt_str(char *buf, uint32_t cap, uint32_t *pos, const char *text);
/*
 * End the program: semihosting SYS_EXIT_EXTENDED with
 * ADP_Stopped_ApplicationExit and the status as subcode, so QEMU exits with
 * that status. Called by startup.S with main's return value.
 */
void aocs_cm_exit(int32_t status);

/* ---- hal_cortex_m.c ---- */
/* 1 when the DWT cycle counter runs, 0 when the SysTick fallback is used. */
uint32_t aocs_cm_cycles_from_dwt(void);
/* Bytes of the main stack ever used since reset (painted region scan). */
uint32_t aocs_cm_stack_high_water(void);

#endif /* AOCS_CM_H */
