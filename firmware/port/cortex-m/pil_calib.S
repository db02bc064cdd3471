/*
 * Calibration loop of the PIL instruction counter (pil_icount.h):
 * void aocs_pil_calib_loop(uint32_t n), n >= 1, executes exactly 2 n + 1
 * instructions after the call (n times SUBS + BNE, then BX LR). Two calls
 * with different n differ by exactly 2 (n2 - n1) instructions, which the
 * image measures at boot to prove that its tick-to-instruction conversion
 * matches QEMU's -icount shift. Assembly so that the count is known by
 * construction, whatever the compiler does.
 */
    .syntax unified
    .thumb
    .text

    .thumb_func
    .global aocs_pil_calib_loop
    .type aocs_pil_calib_loop, %function
aocs_pil_calib_loop:
1:  subs  r0, r0, #1
    bne   1b
    bx    lr
    .size aocs_pil_calib_loop, . - aocs_pil_calib_loop
