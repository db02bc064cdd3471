/*
 * node_udpm: LCM's UDP multicast transport (udpm) read and written in the caller's thread, for fsw_node.
 *
 * The same datagrams as the LCM library (docs/wire-contract.md; the Python side is sil/aocs_wire/udpm.py): a short
 * message is one datagram to the group, big-endian
 *
 *     uint32 magic 0x4c433032 ("LC02") | uint32 sequence number | channel | NUL | payload
 *
 * Every aocs_lcm type is far below the 64 kB datagram limit, so the fragmented form ("LC03") is never sent;
 * received fragments are counted and dropped (no aocs type arrives fragmented).
 *
 * Why: the LCM library receives on a thread of its own and hands each message to the caller's thread through
 * a pipe: two thread wake-ups per message where one does, in the lockstep round trip of every control period
 * (docs/benchmarks.md, "SIL loop speed"). fsw_node uses it for udpm:// URLs and the library for any other.
 *
 * A wait may poll the socket for a while before it sleeps (spin_ns, the node's `wait_spin_us`): in lockstep the
 * plant's next sensors_t comes some 20 us after the reply, and a sleeping process on an idle virtual CPU takes
 * longer than that to wake (docs/benchmarks.md, "Waiting without sleeping"). The poll gives the CPU up between
 * tries (sched_yield), so a process that has work takes the core at once.
 *
 * Host code only (POSIX sockets); the firmware rules apply to firmware/.
 */
#ifndef AOCS_NODE_UDPM_H
#define AOCS_NODE_UDPM_H

#include <stddef.h>
#include <stdint.h>

#define NODE_UDPM_MAX_SUBS 4
#define NODE_UDPM_CHANNEL_MAX 63            /* LCM_MAX_CHANNEL_NAME_LENGTH */
#define NODE_UDPM_DATAGRAM_MAX 65536

/* a subscriber: the payload (after the channel's NUL) of every message on its channel */
typedef void (*node_udpm_handler_t)(const void *data, size_t size, void *user);

typedef struct {
    char channel[NODE_UDPM_CHANNEL_MAX + 1];
    node_udpm_handler_t fn;
    void *user;
} node_udpm_sub_t;

typedef struct {
    int fd;                                   /* joined to the group, bound to its port; also sends */
    uint32_t group_be;                        /* the group's address, network order */
    uint16_t port;
    uint32_t seq;                             /* sequence number of the next message sent */
    node_udpm_sub_t subs[NODE_UDPM_MAX_SUBS];
    size_t n_subs;
    uint64_t fragments;                       /* LC03 datagrams received and dropped */
    uint64_t garbage;                         /* datagrams that are not LCM messages */
    uint64_t spin_ns;                         /* a wait polls this long before it sleeps (0: sleeps at once) */
    uint8_t rx[NODE_UDPM_DATAGRAM_MAX];
    uint8_t tx[NODE_UDPM_DATAGRAM_MAX];
} node_udpm_t;

/* 1 when url is a udpm:// URL this reader serves (udpm://A.B.C.D:PORT[?ttl=N...]), else 0 */
int node_udpm_url_ok(const char *url);

/* opens the group of url (udpm://A.B.C.D:PORT?ttl=N); 0 on success, -1 (errno set) otherwise */
int node_udpm_open(node_udpm_t *u, const char *url);

/* handler for every message on channel (exact name); 0, or -1 when the table is full or the name too long */
int node_udpm_subscribe(node_udpm_t *u, const char *channel, node_udpm_handler_t fn, void *user);

/* one message on channel; 0, or -1 (errno set) when it does not fit one datagram or sendto failed */
int node_udpm_publish(node_udpm_t *u, const char *channel, const void *data, size_t size);

/* dispatches every datagram already queued, waiting at most timeout_ms for the first: the messages handled
 * (subscribed ones), 0 on timeout, -1 on an error of poll or recv (errno set; EINTR included) */
int node_udpm_handle_timeout(node_udpm_t *u, int timeout_ms);

void node_udpm_close(node_udpm_t *u);

#endif /* AOCS_NODE_UDPM_H */
