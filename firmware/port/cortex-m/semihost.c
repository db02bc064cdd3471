/*
 * Semihosting output and exit (ARM DUI 0471, "Semihosting operations"),
 * without newlib stdio: printf would pull in malloc through its buffers.
 */
#include "aocs_cm.h"

#define SH_SYS_WRITE0 0x04UL
#define SH_SYS_EXIT_EXTENDED 0x20UL
#define SH_ADP_STOPPED_APPLICATION_EXIT 0x20026UL

void aocs_cm_write(const char *text)
{
    (void)aocs_cm_semihost_call(SH_SYS_WRITE0, text);
}

void aocs_cm_fmt_str(char *buf, uint32_t cap, uint32_t *pos, const char *text)
{
    uint32_t i = 0U;
    while ((text[i] != '\0') && ((*pos + 1U) < cap)) {
        buf[*pos] = text[i];
        *pos += 1U;
        i++;
    }
    buf[*pos] = '\0';
}

void aocs_cm_fmt_int(char *buf, uint32_t cap, uint32_t *pos, int64_t value)
{
    static const char decimal[] = "0123456789";
    char digits[21];
    uint32_t n = 0U;
    uint64_t mag;
    if (value < 0) {
        aocs_cm_fmt_str(buf, cap, pos, "-");
        mag = (uint64_t)(-(value + 1)) + 1U; /* no overflow at INT64_MIN */
    } else {
        mag = (uint64_t)value;
    }
    do {
        digits[n] = decimal[mag % 10U];
        mag /= 10U;
        n++;
    } while ((mag > 0U) && (n < 20U));
    while ((n > 0U) && ((*pos + 1U) < cap)) {
        n--;
        buf[*pos] = digits[n];
        *pos += 1U;
    }
    buf[*pos] = '\0';
}

void aocs_cm_exit(int32_t status)
{
    /* SYS_EXIT_EXTENDED block: reason, subcode (QEMU returns the subcode) */
    uint32_t block[2];
    block[0] = SH_ADP_STOPPED_APPLICATION_EXIT;
    block[1] = (uint32_t)status;
    (void)aocs_cm_semihost_call(SH_SYS_EXIT_EXTENDED, block);
    for (;;) {
        aocs_cm_wfi(); /* not reached when a debugger/QEMU serves the call */
    }
}
