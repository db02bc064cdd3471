/*
 * Byte link of the PIL image to the host bridge: semihosting SYS_READ and
 * SYS_WRITE on the console (":tt"), which QEMU maps to its own stdin and
 * stdout when no chardev is given for semihosting (the bridge's pipes).
 * Cortex-M port only (not part of the portable firmware API).
 */
#ifndef AOCS_PIL_LINK_H
#define AOCS_PIL_LINK_H

#include <stdint.h>

typedef enum {
    AOCS_PIL_LINK_OK = 0,
    AOCS_PIL_LINK_EOF,        /* the host closed the link (reads return nothing) */
    AOCS_PIL_LINK_IO_ERROR    /* an open, read or write call failed */
} aocs_pil_link_status_t;

/* Opens ":tt" for reading (QEMU's stdin) and for writing (QEMU's stdout). */
aocs_pil_link_status_t aocs_pil_link_open(void);

/*
 * Reads exactly n bytes into buf, retrying short reads. A read that returns
 * nothing AOCS_PIL_LINK_EMPTY_READS_MAX times in a row is the end of the
 * link: QEMU's stdin is a blocking pipe, so an empty read means EOF.
 */
aocs_pil_link_status_t aocs_pil_link_read(uint8_t *buf, uint32_t n);

/* Writes exactly n bytes of buf, retrying short writes. */
aocs_pil_link_status_t aocs_pil_link_write(const uint8_t *buf, uint32_t n);

#define AOCS_PIL_LINK_EMPTY_READS_MAX 1000U

#endif /* AOCS_PIL_LINK_H */
