/* The in-process flight computer's C ABI over node_core (aocs_node_direct.h). */
#include "aocs_node_direct.h"

#include <stdio.h>
#include <string.h>

#include "node_core.h"

#define ABI_VERSION 2 /* 2: aocs_direct_event */

typedef struct {
    int used;
    aocs_node_core_t core;
} slot_t;

static slot_t g_slots[AOCS_DIRECT_SLOTS];   /* static: a node holds the stats ring (no allocation) */

static aocs_node_core_t *core_of(int32_t h)
{
    if ((h < 0) || (h >= (int32_t)AOCS_DIRECT_SLOTS) || (g_slots[h].used == 0)) {
        return NULL;
    }
    return &g_slots[h].core;
}

int32_t aocs_direct_abi_version(void)
{
    return ABI_VERSION;
}

static void set_err(char *err, uint32_t err_size, const char *msg)
{
    if ((err != NULL) && (err_size > 0u)) {
        (void)snprintf(err, err_size, "%s", msg);
    }
}

int32_t aocs_direct_open(const char *config_text, const char *name, char *err, uint32_t err_size)
{
    char msg[AOCS_NODE_ERR_MAX];
    int32_t h;
    FILE *f;
    int rc;
    aocs_node_core_t *c;
    const char *nm = (name != NULL) ? name : "configuration";
    if (config_text == NULL) {
        set_err(err, err_size, "no configuration text");
        return -1;
    }
    for (h = 0; h < (int32_t)AOCS_DIRECT_SLOTS; ++h) {
        if (g_slots[h].used == 0) {
            break;
        }
    }
    if (h == (int32_t)AOCS_DIRECT_SLOTS) {
        (void)snprintf(msg, sizeof(msg), "all %d in-process node slots are open (close one first)",
                       AOCS_DIRECT_SLOTS);
        set_err(err, err_size, msg);
        return -1;
    }
    c = &g_slots[h].core;
    aocs_node_core_reset(c);
    /* the text read as fsw_node reads its file: the same parser, line numbers and messages */
    f = fmemopen((void *)(uintptr_t)config_text, strlen(config_text), "r");
    if (f == NULL) {
        set_err(err, err_size, "cannot read the configuration text");
        return -1;
    }
    rc = aocs_node_config_read(f, nm, &c->cfg, msg, sizeof(msg));
    (void)fclose(f);
    if (rc == 0) {
        rc = aocs_node_core_configure(c, nm, msg, sizeof(msg));
    }
    if ((rc == 0) && (c->cfg.run_mode != AOCS_NODE_RUN_LOCKSTEP)) {
        (void)snprintf(msg, sizeof(msg), "%s: mode = realtime: the in-process node is lockstep only", nm);
        rc = 1;
    }
    if (rc != 0) {
        set_err(err, err_size, msg);
        return -1;
    }
    g_slots[h].used = 1;
    return h;
}

int32_t aocs_direct_sensors(int32_t h, const uint8_t *data, uint32_t size, uint8_t *out, uint32_t cap)
{
    aocs_lcm_actuator_cmd_t m;
    aocs_node_core_t *c = core_of(h);
    int len;
    if ((c == NULL) || (data == NULL) || (out == NULL)) {
        return -1;
    }
    if (aocs_node_core_lockstep(c, data, size, &m) == 0) {
        return 0;
    }
    /* the bytes aocs_lcm_actuator_cmd_t_publish would send */
    len = aocs_lcm_actuator_cmd_t_encoded_size(&m);
    if ((len <= 0) || ((uint32_t)len > cap) || (cap > (uint32_t)INT32_MAX)) {
        return -2;
    }
    return (aocs_lcm_actuator_cmd_t_encode(out, 0, (int)cap, &m) == len) ? (int32_t)len : -2;
}

static int32_t encode_status(aocs_node_core_t *c, int32_t exiting, int64_t utime_us, uint8_t *out, uint32_t cap)
{
    aocs_lcm_status_t m;
    int len;
    aocs_node_core_status(c, exiting, utime_us, &m);
    len = aocs_lcm_status_t_encoded_size(&m);
    if ((len <= 0) || ((uint32_t)len > cap) || (cap > (uint32_t)INT32_MAX)) {
        return -2;
    }
    return (aocs_lcm_status_t_encode(out, 0, (int)cap, &m) == len) ? (int32_t)len : -2;
}

int32_t aocs_direct_command(int32_t h, const uint8_t *data, uint32_t size, int64_t utime_us, uint8_t *out,
                            uint32_t cap)
{
    aocs_node_core_t *c = core_of(h);
    if ((c == NULL) || (data == NULL) || (out == NULL)) {
        return -1;
    }
    if (aocs_node_core_command(c, data, size) == 0) {
        return 0;
    }
    return encode_status(c, 0, utime_us, out, cap);
}

int32_t aocs_direct_event(int32_t h, uint8_t *out, uint32_t cap)
{
    aocs_node_core_t *c = core_of(h);
    aocs_lcm_event_t m;
    int len;
    if ((c == NULL) || (out == NULL)) {
        return -1;
    }
    if (aocs_node_core_event(c, &m) == 0) {
        return 0;
    }
    len = aocs_lcm_event_t_encoded_size(&m);
    if ((len <= 0) || ((uint32_t)len > cap) || (cap > (uint32_t)INT32_MAX)) {
        return -2;
    }
    return (aocs_lcm_event_t_encode(out, 0, (int)cap, &m) == len) ? (int32_t)len : -2;
}

int32_t aocs_direct_status(int32_t h, int32_t exiting, int64_t utime_us, uint8_t *out, uint32_t cap)
{
    aocs_node_core_t *c = core_of(h);
    if ((c == NULL) || (out == NULL)) {
        return -1;
    }
    return encode_status(c, exiting, utime_us, out, cap);
}

int32_t aocs_direct_report(int32_t h, const char *reason, char *out, uint32_t cap)
{
    aocs_node_core_t *c = core_of(h);
    int len;
    if ((c == NULL) || (out == NULL) || (reason == NULL)) {
        return -1;
    }
    len = aocs_node_core_report_json(c, reason, out, (size_t)cap);
    return ((len < 0) || ((uint32_t)len >= cap)) ? -2 : (int32_t)len;
}

int32_t aocs_direct_last_request(int32_t h, int64_t *request, int32_t *status)
{
    aocs_node_core_t *c = core_of(h);
    if ((c == NULL) || (request == NULL) || (status == NULL)) {
        return -1;
    }
    *request = c->last_request;
    *status = c->last_request_status;
    return 0;
}

int32_t aocs_direct_close(int32_t h)
{
    if (core_of(h) == NULL) {
        return -1;
    }
    g_slots[h].used = 0;
    return 0;
}
