/*
 * Cortex-M startup for the AOCS image (ARMv7-M: Cortex-M4F and Cortex-M7).
 *
 * Written in assembly so that no compiler-generated code (which may use FPU
 * registers under -mfloat-abi=hard) runs before the FPU is enabled:
 *   1. enable CP10/CP11 (FPU) in CPACR bits 20-23 (ARMv7-M ARM B3.2.20),
 *      then DSB/ISB so the next instruction sees it;
 *   2. copy .data from its load address in code memory to RAM;
 *   3. zero .bss;
 *   4. paint the main stack below the current SP with AOCS_CM_STACK_PAINT
 *      (the image reports the high-water mark from it);
 *   5. call main() and hand its return value to aocs_cm_exit()
 *      (semihosting exit, the value becomes QEMU's exit status).
 * Every fault ends the run through semihosting with a distinct exit code
 * instead of hanging the emulator.
 */
    .syntax unified
    .thumb

    .equ CPACR,             0xE000ED88
    .equ CPACR_CP10_CP11,   (0xF << 20)
    .equ STACK_PAINT,       0xA5A5A5A5
    .equ SYS_EXIT_EXTENDED, 0x20
    .equ ADP_APP_EXIT,      0x20026

/* ---- vector table (ARMv7-M ARM B1.5.3) ---- */
    .section .isr_vector, "a", %progbits
    .align 2
    .global aocs_cm_vectors
aocs_cm_vectors:
    .word __stack_top
    .word Reset_Handler
    .word NMI_Handler
    .word HardFault_Handler
    .word MemManage_Handler
    .word BusFault_Handler
    .word UsageFault_Handler
    .word 0
    .word 0
    .word 0
    .word 0
    .word SVC_Handler
    .word DebugMon_Handler
    .word 0
    .word PendSV_Handler
    .word SysTick_Handler
    .size aocs_cm_vectors, . - aocs_cm_vectors

    .text

/* ---- reset ---- */
    .thumb_func
    .global Reset_Handler
    .type Reset_Handler, %function
Reset_Handler:
    ldr   r0, =CPACR
    ldr   r1, [r0]
    orr   r1, r1, #CPACR_CP10_CP11
    str   r1, [r0]
    dsb
    isb

    ldr   r0, =__data_load
    ldr   r1, =__data_start
    ldr   r2, =__data_end
1:  cmp   r1, r2
    bhs   2f
    ldr   r3, [r0], #4
    str   r3, [r1], #4
    b     1b

2:  ldr   r1, =__bss_start
    ldr   r2, =__bss_end
    movs  r3, #0
3:  cmp   r1, r2
    bhs   4f
    str   r3, [r1], #4
    b     3b

4:  ldr   r1, =__stack_limit
    mov   r2, sp
    ldr   r3, =STACK_PAINT
5:  cmp   r1, r2
    bhs   6f
    str   r3, [r1], #4
    b     5b

6:  bl    main
    bl    aocs_cm_exit
7:  b     7b
    .size Reset_Handler, . - Reset_Handler

/*
 * Semihosting call (ARM DUI 0471, "BKPT 0xAB" on M-profile):
 * uint32_t aocs_cm_semihost_call(uint32_t op, const void *arg).
 * Operation in r0, parameter block in r1, result in r0: the AAPCS already
 * puts the arguments there.
 */
    .thumb_func
    .global aocs_cm_semihost_call
    .type aocs_cm_semihost_call, %function
aocs_cm_semihost_call:
    bkpt  0xAB
    bx    lr
    .size aocs_cm_semihost_call, . - aocs_cm_semihost_call

/* void aocs_cm_wfi(void): sleep until the next interrupt. */
    .thumb_func
    .global aocs_cm_wfi
    .type aocs_cm_wfi, %function
aocs_cm_wfi:
    dsb
    wfi
    bx    lr
    .size aocs_cm_wfi, . - aocs_cm_wfi

/* uint32_t aocs_cm_sp(void): current main stack pointer. */
    .thumb_func
    .global aocs_cm_sp
    .type aocs_cm_sp, %function
aocs_cm_sp:
    mov   r0, sp
    bx    lr
    .size aocs_cm_sp, . - aocs_cm_sp

/*
 * Faults: exit through semihosting with the code in r2 so a crash in the
 * emulator is a failed run, never a hang. Codes: 10 NMI, 11 HardFault,
 * 12 MemManage, 13 BusFault, 14 UsageFault, 15 any other exception.
 */
    .macro FAULT name, code
    .thumb_func
    .weak \name
    .type \name, %function
\name:
    movs  r2, #\code
    b     aocs_cm_fault_exit
    .size \name, . - \name
    .endm

    FAULT NMI_Handler, 10
    FAULT HardFault_Handler, 11
    FAULT MemManage_Handler, 12
    FAULT BusFault_Handler, 13
    FAULT UsageFault_Handler, 14
    FAULT SVC_Handler, 15
    FAULT DebugMon_Handler, 15
    FAULT PendSV_Handler, 15
    FAULT SysTick_Handler, 15

    .thumb_func
    .type aocs_cm_fault_exit, %function
aocs_cm_fault_exit:
    ldr   r1, =ADP_APP_EXIT
    ldr   r0, =aocs_cm_fault_block
    str   r1, [r0]
    str   r2, [r0, #4]
    mov   r1, r0
    movs  r0, #SYS_EXIT_EXTENDED
    bkpt  0xAB
8:  b     8b
    .size aocs_cm_fault_exit, . - aocs_cm_fault_exit

    .bss
    .align 2
aocs_cm_fault_block:
    .space 8
