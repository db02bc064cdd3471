/*
 * node_udpm: LCM's udpm transport in the caller's thread (node_udpm.h).
 */
#define _DEFAULT_SOURCE 1 /* struct ip_mreq and SO_REUSEPORT, beyond the POSIX the build asks for */

#include "node_udpm.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <sched.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#define MAGIC_SHORT 0x4c433032u /* "LC02" */
#define MAGIC_LONG 0x4c433033u  /* "LC03": a fragment */
#define HEAD_BYTES 8u
#define URL_PREFIX "udpm://"
#define RECV_BUF_BYTES (2 * 1024 * 1024)

static uint32_t get_u32(const uint8_t *p)
{
    return ((uint32_t)p[0] << 24) | ((uint32_t)p[1] << 16) | ((uint32_t)p[2] << 8) | (uint32_t)p[3];
}

static void put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

/* group, port and ttl of udpm://A.B.C.D:PORT[?k=v&...] (ttl=N the only option read, default 0); 0 or -1 */
static int parse_url(const char *url, struct in_addr *group, uint16_t *port, int *ttl)
{
    char host[64];
    const char *p;
    const char *colon;
    char *end;
    unsigned long v;
    size_t len;
    *ttl = 0;
    if ((url == NULL) || (strncmp(url, URL_PREFIX, strlen(URL_PREFIX)) != 0)) {
        return -1;
    }
    p = url + strlen(URL_PREFIX);
    colon = strchr(p, ':');
    if (colon == NULL) {
        return -1;
    }
    len = (size_t)(colon - p);
    if ((len == 0u) || (len >= sizeof(host))) {
        return -1;
    }
    memcpy(host, p, len);
    host[len] = '\0';
    if (inet_pton(AF_INET, host, group) != 1) {
        return -1;
    }
    errno = 0;
    v = strtoul(colon + 1, &end, 10);
    if ((errno != 0) || (end == colon + 1) || (v == 0u) || (v > 65535u) || ((*end != '\0') && (*end != '?'))) {
        return -1;
    }
    *port = (uint16_t)v;
    if (*end == '?') {
        const char *t = strstr(end, "ttl=");
        if ((t != NULL) && ((t[-1] == '?') || (t[-1] == '&'))) {
            unsigned long n = strtoul(t + 4, &end, 10);
            if ((end == t + 4) || (n > 255u) || ((*end != '\0') && (*end != '&'))) {
                return -1;
            }
            *ttl = (int)n;
        }
    }
    return 0;
}

int node_udpm_url_ok(const char *url)
{
    struct in_addr group;
    uint16_t port;
    int ttl;
    return (parse_url(url, &group, &port, &ttl) == 0) ? 1 : 0;
}

int node_udpm_open(node_udpm_t *u, const char *url)
{
    struct in_addr group;
    uint16_t port;
    int ttl;
    int one = 1;
    int rcvbuf = RECV_BUF_BYTES;
    unsigned char ttl_c;
    unsigned char loop = 1u;
    struct sockaddr_in addr;
    struct ip_mreq mreq;
    memset(u, 0, sizeof(*u));
    u->fd = -1;
    if (parse_url(url, &group, &port, &ttl) != 0) {
        errno = EINVAL;
        return -1;
    }
    ttl_c = (unsigned char)ttl;
    u->fd = socket(AF_INET, SOCK_DGRAM, IPPROTO_UDP);
    if (u->fd < 0) {
        return -1;
    }
    memset(&addr, 0, sizeof(addr));
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port);
    addr.sin_addr.s_addr = htonl(INADDR_ANY);
    mreq.imr_multiaddr = group;
    mreq.imr_interface.s_addr = htonl(INADDR_ANY);
    /* as the LCM library and aocs_wire.udpm: every process of the host on the same port, the group joined,
     * the datagrams looped back to the host's other members */
    if ((setsockopt(u->fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one)) != 0) ||
#ifdef SO_REUSEPORT
        (setsockopt(u->fd, SOL_SOCKET, SO_REUSEPORT, &one, sizeof(one)) != 0) ||
#endif
        (setsockopt(u->fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof(rcvbuf)) != 0) ||
        (bind(u->fd, (const struct sockaddr *)&addr, sizeof(addr)) != 0) ||
        (setsockopt(u->fd, IPPROTO_IP, IP_ADD_MEMBERSHIP, &mreq, sizeof(mreq)) != 0) ||
        (setsockopt(u->fd, IPPROTO_IP, IP_MULTICAST_TTL, &ttl_c, sizeof(ttl_c)) != 0) ||
        (setsockopt(u->fd, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, sizeof(loop)) != 0)) {
        const int e = errno;
        (void)close(u->fd);
        u->fd = -1;
        errno = e;
        return -1;
    }
    u->group_be = group.s_addr;
    u->port = port;
    return 0;
}

int node_udpm_subscribe(node_udpm_t *u, const char *channel, node_udpm_handler_t fn, void *user)
{
    node_udpm_sub_t *s;
    if ((u->n_subs >= NODE_UDPM_MAX_SUBS) || (fn == NULL) || (strlen(channel) > NODE_UDPM_CHANNEL_MAX)) {
        return -1;
    }
    s = &u->subs[u->n_subs];
    (void)strcpy(s->channel, channel);
    s->fn = fn;
    s->user = user;
    u->n_subs++;
    return 0;
}

int node_udpm_publish(node_udpm_t *u, const char *channel, const void *data, size_t size)
{
    struct sockaddr_in dest;
    const size_t ch = strlen(channel);
    const size_t total = HEAD_BYTES + ch + 1u + size;
    ssize_t sent;
    if ((ch > NODE_UDPM_CHANNEL_MAX) || (total > sizeof(u->tx))) {
        errno = EMSGSIZE;
        return -1;
    }
    put_u32(u->tx, MAGIC_SHORT);
    put_u32(u->tx + 4, u->seq);
    memcpy(u->tx + HEAD_BYTES, channel, ch + 1u);   /* the name and its NUL */
    if (size > 0u) {
        memcpy(u->tx + HEAD_BYTES + ch + 1u, data, size);
    }
    memset(&dest, 0, sizeof(dest));
    dest.sin_family = AF_INET;
    dest.sin_port = htons(u->port);
    dest.sin_addr.s_addr = u->group_be;
    sent = sendto(u->fd, u->tx, total, 0, (const struct sockaddr *)&dest, sizeof(dest));
    u->seq++;
    return (sent == (ssize_t)total) ? 0 : -1;
}

/* one datagram to its subscriber; 1 when one handled it */
static int dispatch(node_udpm_t *u, size_t len)
{
    const uint8_t *d = u->rx;
    const uint8_t *nul;
    size_t i;
    uint32_t magic;
    if (len < HEAD_BYTES + 1u) {
        u->garbage++;
        return 0;
    }
    magic = get_u32(d);
    if (magic != MAGIC_SHORT) {
        if (magic == MAGIC_LONG) {
            u->fragments++;
        } else {
            u->garbage++;
        }
        return 0;
    }
    nul = memchr(d + HEAD_BYTES, 0, len - HEAD_BYTES);
    if (nul == NULL) {
        u->garbage++;
        return 0;
    }
    for (i = 0u; i < u->n_subs; i++) {
        if (strcmp((const char *)(d + HEAD_BYTES), u->subs[i].channel) == 0) {
            const size_t off = (size_t)(nul - d) + 1u;
            u->subs[i].fn(d + off, len - off, u->subs[i].user);
            return 1;
        }
    }
    return 0;
}

static uint64_t now_ns(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return ((uint64_t)ts.tv_sec * 1000000000u) + (uint64_t)ts.tv_nsec;
}

/* polls without sleeping for at most u->spin_ns, yielding the CPU between tries: poll's result (0: nothing came) */
static int spin(const node_udpm_t *u, struct pollfd *pfd)
{
    uint64_t t0;
    int r = 0;
    if (u->spin_ns == 0u) {
        return 0;
    }
    t0 = now_ns();
    do {
        (void)sched_yield();
        pfd->revents = 0;
        r = poll(pfd, 1, 0);
    } while ((r == 0) && ((now_ns() - t0) < u->spin_ns));
    return r;
}

int node_udpm_handle_timeout(node_udpm_t *u, int timeout_ms)
{
    struct pollfd pfd;
    int handled = 0;
    int waited = 0;
    pfd.fd = u->fd;
    pfd.events = POLLIN;
    for (;;) {
        ssize_t n;
        int r;
        /* asked before each read: every call ends on an empty queue, found by a poll (aocs_wire.udpm) */
        pfd.revents = 0;
        r = poll(&pfd, 1, 0);
        if (r < 0) {
            return -1;
        }
        if (r == 0) {
            if ((handled > 0) || (waited != 0)) {
                return handled;
            }
            r = spin(u, &pfd);
            if (r == 0) {
                r = poll(&pfd, 1, (timeout_ms < 0) ? 0 : timeout_ms);
            }
            if (r < 0) {
                return -1;
            }
            if (r == 0) {
                return 0;
            }
            waited = 1;
        }
        n = recv(u->fd, u->rx, sizeof(u->rx), MSG_DONTWAIT);
        if (n < 0) {
            if ((errno == EAGAIN) || (errno == EWOULDBLOCK)) {
                continue;   /* readiness without a datagram: ask again */
            }
            return -1;
        }
        handled += dispatch(u, (size_t)n);
    }
}

void node_udpm_close(node_udpm_t *u)
{
    if (u->fd >= 0) {
        (void)close(u->fd);
        u->fd = -1;
    }
}
