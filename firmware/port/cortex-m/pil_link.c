/*
 * PIL byte link over semihosting (ARM DUI 0471, "Semihosting operations"):
 * SYS_OPEN of ":tt" gives console handles (mode 0: read, mode 4: write);
 * SYS_READ / SYS_WRITE return the number of bytes NOT transferred. QEMU
 * (without -semihosting-config chardev=...) serves the console reads with a
 * read(2) of its own stdin and the writes with a write(2) to its stdout. A
 * chardev on stdin would race with those reads for the bytes (measured: one
 * byte in ~500 exchanges lost), so the bridge never gives QEMU one.
 */
#include <stddef.h>

#include "aocs_cm.h"
#include "pil_link.h"

#define SH_SYS_OPEN 0x01UL
#define SH_SYS_WRITE 0x05UL
#define SH_SYS_READ 0x06UL
#define SH_MODE_READ 0UL   /* "r" */
#define SH_MODE_WRITE 4UL  /* "w" */
#define SH_OPEN_FAILED 0xFFFFFFFFUL

static uint32_t pil_in = SH_OPEN_FAILED;
static uint32_t pil_out = SH_OPEN_FAILED;

/* Semihosting parameter blocks hold 32-bit words: addresses become words (ILP32). */
static uint32_t pil_addr(const uint8_t *p)
{
    return (uint32_t)(uintptr_t)p;
}

static uint32_t pil_open(uint32_t mode)
{
    static const char console_name[] = ":tt";
    uint32_t block[3];
    block[0] = (uint32_t)(uintptr_t)console_name;
    block[1] = mode;
    block[2] = (uint32_t)(sizeof(console_name) - 1U);
    return aocs_cm_semihost_call(SH_SYS_OPEN, block);
}

aocs_pil_link_status_t aocs_pil_link_open(void)
{
    aocs_pil_link_status_t st = AOCS_PIL_LINK_OK;
    pil_in = pil_open(SH_MODE_READ);
    pil_out = pil_open(SH_MODE_WRITE);
    if ((pil_in == SH_OPEN_FAILED) || (pil_out == SH_OPEN_FAILED)) {
        st = AOCS_PIL_LINK_IO_ERROR;
    }
    return st;
}

aocs_pil_link_status_t aocs_pil_link_read(uint8_t *buf, uint32_t n)
{
    aocs_pil_link_status_t st = AOCS_PIL_LINK_OK;
    uint32_t got = 0U;
    uint32_t empty = 0U;
    while ((st == AOCS_PIL_LINK_OK) && (got < n)) {
        uint32_t block[3];
        uint32_t not_read;
        block[0] = pil_in;
        block[1] = pil_addr(&buf[got]);
        block[2] = n - got;
        not_read = aocs_cm_semihost_call(SH_SYS_READ, block);
        if (not_read > (n - got)) {
            st = AOCS_PIL_LINK_IO_ERROR; /* -1: the host call failed */
        } else if (not_read == (n - got)) {
            empty++;
            if (empty >= AOCS_PIL_LINK_EMPTY_READS_MAX) {
                st = AOCS_PIL_LINK_EOF;
            }
        } else {
            got += (n - got) - not_read;
            empty = 0U;
        }
    }
    return st;
}

aocs_pil_link_status_t aocs_pil_link_write(const uint8_t *buf, uint32_t n)
{
    aocs_pil_link_status_t st = AOCS_PIL_LINK_OK;
    uint32_t put = 0U;
    uint32_t stuck = 0U;
    while ((st == AOCS_PIL_LINK_OK) && (put < n)) {
        uint32_t block[3];
        uint32_t not_written;
        block[0] = pil_out;
        block[1] = pil_addr(&buf[put]);
        block[2] = n - put;
        not_written = aocs_cm_semihost_call(SH_SYS_WRITE, block);
        if (not_written > (n - put)) {
            st = AOCS_PIL_LINK_IO_ERROR;
        } else if (not_written == (n - put)) {
            stuck++;
            if (stuck >= AOCS_PIL_LINK_EMPTY_READS_MAX) {
                st = AOCS_PIL_LINK_IO_ERROR; /* the host takes nothing: closed */
            }
        } else {
            put += (n - put) - not_written;
            stuck = 0U;
        }
    }
    return st;
}
