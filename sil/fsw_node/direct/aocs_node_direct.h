/*
 * The in-process flight computer: fsw_node's node logic (node_core.h) behind
 * a small C ABI, loaded into the plant's process (aocs_loop.direct_adapter,
 * `--transport direct`, docs/sil.md "Transports"). Lockstep only.
 *
 * The messages in and out are the wire contract's bytes (sil/lcmtypes): a
 * sensors_t payload in, the actuator_cmd_t payload fsw_node would publish
 * out, encoded by the same generated code. Node slots are static storage
 * (no allocation): at most AOCS_DIRECT_SLOTS nodes open in one process.
 * Host code (SIL only).
 */
#ifndef AOCS_NODE_DIRECT_H
#define AOCS_NODE_DIRECT_H

#include <stddef.h>
#include <stdint.h>

#define AOCS_DIRECT_SLOTS 2

/* The library is built with hidden visibility: only these functions are its ABI. */
#if defined(__GNUC__)
#define AOCS_DIRECT_API __attribute__((visibility("default")))
#else
#define AOCS_DIRECT_API
#endif

/* Version of this ABI (the Python adapter checks it). */
AOCS_DIRECT_API int32_t aocs_direct_abi_version(void);

/*
 * Opens a node on `config_text` (fsw_node's configuration file's text, docs/wire-contract.md), which
 * `name` names in messages. Returns the handle (>= 0), or -1 with one line in err: a configuration error,
 * a real-time configuration (the in-process node is lockstep only), or no free slot.
 */
AOCS_DIRECT_API int32_t aocs_direct_open(const char *config_text, const char *name, char *err, uint32_t err_size);

/*
 * One AOCS_SENSORS payload: the actuator_cmd_t payload of its step into out. Returns its length (> 0),
 * 0 when the payload got no reply (dropped, malformed, foreign: counted as fsw_node counts them), -1 for
 * a bad handle, -2 when cap is too small.
 */
AOCS_DIRECT_API int32_t aocs_direct_sensors(int32_t h, const uint8_t *data, uint32_t size, uint8_t *out, uint32_t cap);

/*
 * One AOCS_COMMAND payload applied: the status_t acknowledgement payload into out (utime_us: its time).
 * Returns its length, 0 when the payload was malformed or foreign (counted), -1 / -2 as above.
 */
AOCS_DIRECT_API int32_t aocs_direct_command(int32_t h, const uint8_t *data, uint32_t size, int64_t utime_us, uint8_t *out,
                            uint32_t cap);

/* The next event_t payload of the events the last steps raised, not yet returned (call after each
 * aocs_direct_sensors until it returns 0: fsw_node publishes the same messages on AOCS_EVENTS). Returns its
 * length, 0 when there is none, -1 / -2 as above. ABI version 2. */
AOCS_DIRECT_API int32_t aocs_direct_event(int32_t h, uint8_t *out, uint32_t cap);

/* The node's status_t payload now (exiting: the last one). Returns its length, -1 / -2 as above. */
AOCS_DIRECT_API int32_t aocs_direct_status(int32_t h, int32_t exiting, int64_t utime_us, uint8_t *out, uint32_t cap);

/*
 * fsw_node's exit summary {"fsw_node": {...}} (NUL-terminated) into out. Returns its length, -1 for a
 * bad handle, -2 when cap is too small.
 */
AOCS_DIRECT_API int32_t aocs_direct_report(int32_t h, const char *reason, char *out, uint32_t cap);

/* The last command's request id and status (AOCS_OK = 0), for the caller's messages. -1 for a bad handle. */
AOCS_DIRECT_API int32_t aocs_direct_last_request(int32_t h, int64_t *request, int32_t *status);

/* Frees the slot. 0, or -1 for a bad handle. */
AOCS_DIRECT_API int32_t aocs_direct_close(int32_t h);

#endif /* AOCS_NODE_DIRECT_H */
