/*
 * aocs_direct_loop_kernel: whole lockstep periods of the in-process transport compiled (issue 24, docs/spec.md
 * 5.13.2).
 *
 * plant_node's lockstep loop over the in-process node (sil/aocs_runner/plant_node.py, _Loop.run_lockstep with
 * aocs_loop.direct_adapter.DirectBus) spends a period in a dozen Python calls around two C calls (the node's step and
 * the plant's compiled period). For the plants whose period is all of the following, DirectLoop.run flies a run of
 * periods in C instead, the same statements in the same order:
 *   - the rigid body alone (Plant._segment_body with its compiled period, rigid_body_core.h), at most one gravity
 *     gradient about a fixed direction, the constant torques;
 *   - the body actuator held over the period with its axis and norm limits and scale factor (effectors/actuator.py,
 *     hold; no slew-rate limit, lag or delay);
 *   - ideal attitude and rate sensors without latency or faults (sensors/attitude.py: q as it is; sensors/rate.py:
 *     w + 0.0), a fixed target;
 *   - no wheels, thrusters or magnetorquers.
 * Per period k (tick = tick0 + k, t_s = tick dt), as the Python loop:
 *   1. sensors_t of the sample packed (frame = tick, utime = round(t_s 1e6), the valid bits) and recorded;
 *   2. the node's step on it (aocs_direct_sensors, through the pointer the ctypes library gives); its
 *      actuator_cmd_t recorded, then the event_t payloads the step raised (aocs_direct_event), each recorded;
 *   3. truth_t of tick recorded: q, w, the actuator output of the last period, the disturbance c + u_gg(q), the
 *      pointing error 2 asin(min(1, |qe_vec|)) and |qe_i| in arcsec, qe = q (x) qd^-1 (SPEC 1);
 *   4. the reply checked as plant_node's on_cmd (size, fingerprint, tick) and read as LcmCodec.command; Plant.apply:
 *      a non-finite torque refused (counted), else held through the limits;
 *   5. the integration check (integration_error.StepDoubling): due when k_plant % every == 0 or the last local
 *      error exceeds its threshold; the period from the same state at 2n substeps of dt / (2n), the difference
 *      x 16/15 in arcsec (pointing) and rad/s (rate);
 *   6. the period: T = c_torque + held, n RK4 substeps of dt / n, applied = 0.0 + held.
 * The log records are the EventLogWriter's (aocs_wire/recorder.py: sync, event number, receive time in us since the
 * epoch, channel and payload lengths, channel, payload; big-endian), returned as one bytes block. The message
 * layouts (offset and struct code of each field) come from aocs_wire.wire's codecs, so this file never spells an
 * LCM layout. Whatever else a period meets (no reply, a reply for another tick, a command for wheels or thrusters
 * the plant does not have, a node error) ends the run there with a status, and the Python loop takes over from the
 * same point with the same messages recorded. tests/python/aocs_runner/test_direct_loop_kernel.py checks the log
 * and the state against the Python loop bit for bit.
 *
 * Python API (sil/aocs_runner/compiled_loop.py):
 *     d = DirectLoop(J, Ji, gg, config)     config: the tuple of compiled_loop.config (its order is CONFIG below)
 *     status, done, state, log, rt, extra = d.run(state, tick0, count)
 */
#include "rigid_body_core.h"

#include <stdint.h>
#include <string.h>
#include <time.h>

/* the statuses of run() (compiled_loop.py names them) */
enum { RUN_DONE = 0, RUN_NO_REPLY = 1, RUN_MISMATCH = 2, RUN_NODE_ERROR = 3 };

typedef int32_t (*sensors_fn)(int32_t handle, const char *data, uint32_t len, void *out, uint32_t cap);
typedef int32_t (*event_fn)(int32_t handle, void *out, uint32_t cap);

#define REPLY_CAP 2048      /* direct_adapter.REPLY_CAP */
#define MSG_CAP 4096        /* the largest template accepted */
#define LOG_SYNC 0xEDA1DA01u
#define LOG_HEAD 28         /* recorder._HEAD, ">IqqII" */

/* one field of a message: its byte offset and struct code ('d', 'q', 'i', 'h', 'b') */
typedef struct {
    Py_ssize_t off;
    char code;
} Field;

enum { S_FRAME, S_UTIME, S_TICK, S_T, S_VALID, S_Q, S_W, S_N };
enum { T_FRAME, T_UTIME, T_TICK, T_T, T_Q, T_W, T_APPLIED, T_DIST, T_ANGLE, T_QE, T_N };
enum { A_TICK, A_U, A_NWHEELS, A_POLICY, A_NTHRUSTERS, A_N };

typedef struct {
    char name[32];
    uint32_t len;
} Channel;

typedef struct {
    PyObject_HEAD
    Body body;
    double dt;
    long substeps;
    double const_torque[3];   /* Plant._const: the CONSTANT effectors' sum */
    double const_dist[3];     /* Plant._const_dist */
    int dist_gg;              /* the gravity gradient is a disturbance (Plant.disturbance adds it) */
    int has_axis, has_norm;
    double axis_limit, norm_limit, scale;
    double qd_inv[4];         /* the fixed target's inverse */
    double arcsec_per_rad, richardson;
    long check_every;
    double check_threshold;
    sensors_fn sensors;
    event_fn event;
    int32_t handle;
    long valid_bits;
    unsigned char s_tpl[MSG_CAP], t_tpl[MSG_CAP];
    Py_ssize_t s_len, t_len;
    Field s_f[S_N], t_f[T_N], a_f[A_N];
    Py_ssize_t a_len;
    unsigned char a_fp[8];
    long max_wheels, max_thrusters, policy_thrusters, policy_magnetorquers;
    Channel ch_sensors, ch_actuator, ch_truth, ch_events;
} DirectLoop;

/* the run's state, what the Python objects hold between runs (compiled_loop.CompiledLoop._state: its order) */
typedef struct {
    double y[7];                      /* q, w */
    long long k;                      /* Plant.k */
    double held[3], limited[3];       /* Actuator.held, _limited */
    long long saturated, commands, bad_commands;
    long long taken_valid;            /* Plant.taken is not None (0 / 1) */
    double taken[3];
    double applied[3];                /* Plant._applied */
    double last[2], local_max[2], local_sum[2], worst_t;   /* StepDoubling */
    long long periods, checked;
    long long log_count, frame_truth, bad_replies, stale_replies;
} State;

#define STATE_SIZE 37

/* ---- big-endian fields ---- */

static void put_u64(unsigned char *p, uint64_t v)
{
    for (int i = 7; i >= 0; i--) {
        p[i] = (unsigned char)(v & 0xffu);
        v >>= 8;
    }
}

static uint64_t get_u64(const unsigned char *p)
{
    uint64_t v = 0;
    for (int i = 0; i < 8; i++) {
        v = (v << 8) | p[i];
    }
    return v;
}

static void put_double(unsigned char *msg, const Field *f, double v)
{
    uint64_t bits;
    memcpy(&bits, &v, sizeof bits);
    put_u64(msg + f->off, bits);
}

/* n doubles from an array field's first element on */
static void put_doubles(unsigned char *msg, const Field *f, const double *v, int n)
{
    for (int i = 0; i < n; i++) {
        const Field e = {f->off + 8 * i, 'd'};
        put_double(msg, &e, v[i]);
    }
}

static double get_double(const unsigned char *msg, Py_ssize_t off)
{
    uint64_t bits = get_u64(msg + off);
    double v;
    memcpy(&v, &bits, sizeof v);
    return v;
}

static void put_int(unsigned char *msg, const Field *f, long long v)
{
    unsigned char *p = msg + f->off;
    uint64_t u = (uint64_t)v;
    int n = f->code == 'q' ? 8 : f->code == 'i' ? 4 : f->code == 'h' ? 2 : 1;
    for (int i = n - 1; i >= 0; i--) {
        p[i] = (unsigned char)(u & 0xffu);
        u >>= 8;
    }
}

static long long get_int(const unsigned char *msg, const Field *f)
{
    const unsigned char *p = msg + f->off;
    int n = f->code == 'q' ? 8 : f->code == 'i' ? 4 : f->code == 'h' ? 2 : 1;
    uint64_t u = 0;
    for (int i = 0; i < n; i++) {
        u = (u << 8) | p[i];
    }
    if (n < 8 && (u >> (8 * n - 1)) & 1u) {   /* sign-extend */
        u |= ~(uint64_t)0 << (8 * n);
    }
    return (long long)u;
}

/* ---- the log block ---- */

typedef struct {
    unsigned char *data;
    size_t len, cap;
    long long count;   /* the next event number */
} Block;

static int block_add(Block *b, const Channel *ch, const unsigned char *payload, size_t n)
{
    const size_t need = LOG_HEAD + ch->len + n;
    if (b->len + need > b->cap) {
        size_t cap = b->cap ? b->cap : 65536;
        while (b->len + need > cap) {
            cap *= 2;
        }
        unsigned char *p = PyMem_RawRealloc(b->data, cap);
        if (p == NULL) {
            return -1;
        }
        b->data = p;
        b->cap = cap;
    }
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);   /* time.time_ns() // 1000 */
    const long long utime = (long long)ts.tv_sec * 1000000LL + ts.tv_nsec / 1000;
    unsigned char *p = b->data + b->len;
    p[0] = (unsigned char)(LOG_SYNC >> 24);
    p[1] = (unsigned char)(LOG_SYNC >> 16);
    p[2] = (unsigned char)(LOG_SYNC >> 8);
    p[3] = (unsigned char)LOG_SYNC;
    put_u64(p + 4, (uint64_t)b->count);
    put_u64(p + 12, (uint64_t)utime);
    for (int i = 0; i < 4; i++) {
        p[20 + i] = (unsigned char)(ch->len >> (24 - 8 * i));
        p[24 + i] = (unsigned char)((uint32_t)n >> (24 - 8 * i));
    }
    memcpy(p + LOG_HEAD, ch->name, ch->len);
    memcpy(p + LOG_HEAD + ch->len, payload, n);
    b->len += need;
    b->count++;
    return 0;
}

static long long now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);   /* time.perf_counter_ns */
    return (long long)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

/* ---- the period's expressions (the Python twins named) ---- */

/* conventions.quat_mul: q (x) p */
static void quat_mul(const double q[4], const double p[4], double out[4])
{
    const double q1 = q[0], q2 = q[1], q3 = q[2], q4 = q[3], p1 = p[0], p2 = p[1], p3 = p[2], p4 = p[3];
    out[0] = q4 * p1 + p4 * q1 - (q2 * p3 - q3 * p2);
    out[1] = q4 * p2 + p4 * q2 - (q3 * p1 - q1 * p3);
    out[2] = q4 * p3 + p4 * q3 - (q1 * p2 - q2 * p1);
    out[3] = q4 * p4 - (q1 * p1 + q2 * p2 + q3 * p3);
}

/* 2 asin(min(1, |e_vec|)): Python's min(1.0, n) is 1.0 unless n < 1.0 */
static double angle_of(const double e[4])
{
    const double n = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    return 2.0 * asin(n < 1.0 ? n : 1.0);
}

/* Actuator.hold without the slew-rate limit: per-axis clip, norm clip, scale; the saturated count */
static void hold(const DirectLoop *d, State *s, const double u[3])
{
    double c[3] = {u[0], u[1], u[2]};
    int clipped = 0;
    if (d->has_axis) {
        const double lim = d->axis_limit;
        for (int i = 0; i < 3; i++) {
            const double m = c[i] > -lim ? c[i] : -lim;   /* max(-lim, c): -lim unless c > -lim */
            const double v = m < lim ? m : lim;           /* min(lim, m): lim unless m < lim */
            if (v != c[i]) {
                clipped = 1;
            }
            c[i] = v;
        }
    }
    if (d->has_norm) {
        const double n = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        if (n > d->norm_limit) {
            const double k = d->norm_limit / n;
            for (int i = 0; i < 3; i++) {
                c[i] = c[i] * k;
            }
            clipped = 1;
        }
    }
    if (clipped) {
        s->saturated++;
    }
    memcpy(s->limited, c, sizeof c);
    if (d->scale != 1.0) {
        for (int i = 0; i < 3; i++) {
            c[i] = d->scale * c[i];
        }
    }
    memcpy(s->held, c, sizeof c);
}

/* Plant._segment_body's compiled period: n substeps of dt / n */
static void body_period(const DirectLoop *d, double y[7], long n, const double t[3])
{
    const double h = d->dt / (double)n;
    for (long i = 0; i < n; i++) {
        rk4_substep(&d->body, y, h, t);
    }
}

/* StepDoubling.end of a checked period: main at its end, y0 its start, t its torque */
static void check_period(const DirectLoop *d, State *s, const double y0[7], const double t[3])
{
    double sh[7];
    memcpy(sh, y0, sizeof sh);
    body_period(d, sh, 2 * d->substeps, t);
    const double conj[4] = {-sh[0], -sh[1], -sh[2], sh[3]};
    double e[4];
    quat_mul(s->y, conj, e);
    double a = angle_of(e) * d->arcsec_per_rad;
    double b = sqrt(pow(s->y[4] - sh[4], 2.0) + pow(s->y[5] - sh[5], 2.0) + pow(s->y[6] - sh[6], 2.0));
    a = a * d->richardson;
    b = b * d->richardson;
    s->checked++;
    if (a > s->local_max[0]) {
        s->local_max[0] = a;
        s->worst_t = (double)s->k * d->dt;
    }
    if (b > s->local_max[1]) {   /* max(m, b): m unless b > m */
        s->local_max[1] = b;
    }
    s->local_sum[0] = s->local_sum[0] + a;
    s->local_sum[1] = s->local_sum[1] + b;
    s->last[0] = a;
    s->last[1] = b;
}

/* truth_t of this tick (the plant at t_k), recorded */
static int record_truth(const DirectLoop *d, State *s, Block *log, long long tick)
{
    unsigned char msg[MSG_CAP];
    memcpy(msg, d->t_tpl, (size_t)d->t_len);
    const double t_s = (double)tick * d->dt;
    put_int(msg, &d->t_f[T_FRAME], s->frame_truth);
    put_int(msg, &d->t_f[T_UTIME], (long long)nearbyint(t_s * 1e6));
    put_int(msg, &d->t_f[T_TICK], tick);
    put_double(msg, &d->t_f[T_T], t_s);
    put_doubles(msg, &d->t_f[T_Q], s->y, 4);
    put_doubles(msg, &d->t_f[T_W], s->y + 4, 3);
    put_doubles(msg, &d->t_f[T_APPLIED], s->applied, 3);
    double dist[3] = {d->const_dist[0], d->const_dist[1], d->const_dist[2]};
    if (d->dist_gg) {
        double g[3];
        gg_torque(&d->body, s->y, g);
        for (int i = 0; i < 3; i++) {
            dist[i] = dist[i] + g[i];
        }
    }
    put_doubles(msg, &d->t_f[T_DIST], dist, 3);
    double e[4];
    quat_mul(s->y, d->qd_inv, e);
    put_double(msg, &d->t_f[T_ANGLE], angle_of(e) * d->arcsec_per_rad);
    const double qe[3] = {fabs(e[0]) * d->arcsec_per_rad, fabs(e[1]) * d->arcsec_per_rad,
                          fabs(e[2]) * d->arcsec_per_rad};
    put_doubles(msg, &d->t_f[T_QE], qe, 3);
    s->frame_truth++;
    return block_add(log, &d->ch_truth, msg, (size_t)d->t_len);
}

/* sensors_t of this tick's sample (ideal sensors: q, w + 0.0) */
static void pack_sensors(const DirectLoop *d, const State *s, long long tick, unsigned char *msg)
{
    memcpy(msg, d->s_tpl, (size_t)d->s_len);
    const double t_s = (double)tick * d->dt;
    put_int(msg, &d->s_f[S_FRAME], tick);
    put_int(msg, &d->s_f[S_UTIME], (long long)nearbyint(t_s * 1e6));
    put_int(msg, &d->s_f[S_TICK], tick);
    put_double(msg, &d->s_f[S_T], t_s);
    put_int(msg, &d->s_f[S_VALID], d->valid_bits);
    const double w[3] = {s->y[4] + 0.0, s->y[5] + 0.0, s->y[6] + 0.0};   /* the rate sensor's y = w + 0.0 */
    put_doubles(msg, &d->s_f[S_Q], s->y, 4);
    put_doubles(msg, &d->s_f[S_W], w, 3);
}

/* LcmCodec.command + PlantPort.apply's checks: 0 and the torque, or 1 when the command names wheels, thrusters or
 * magnetorquers this plant has not (the Python loop raises WheelMismatch / ActuatorMismatch on it) */
static int read_command(const DirectLoop *d, const unsigned char *reply, double u[3])
{
    for (int i = 0; i < 3; i++) {
        u[i] = get_double(reply, d->a_f[A_U].off + 8 * i);
    }
    long long nw = get_int(reply, &d->a_f[A_NWHEELS]);
    nw = nw < 0 ? 0 : nw > d->max_wheels ? d->max_wheels : nw;
    const long long policy = get_int(reply, &d->a_f[A_POLICY]);
    long long nt = get_int(reply, &d->a_f[A_NTHRUSTERS]);
    nt = nt < 0 ? 0 : nt > d->max_thrusters ? d->max_thrusters : nt;
    return nw != 0 || (policy == d->policy_thrusters && nt != 0) || policy == d->policy_magnetorquers;
}

/* ---- state in and out ---- */

/* one value of the state tuple: a double or an integer member of State */
typedef struct {
    double *d;
    long long *i;
} Slot;

/* the state tuple's order (compiled_loop.CompiledLoop._state), the one place it is written in C */
static void state_slots(State *s, Slot sl[STATE_SIZE])
{
    int n = 0;
#define D(x) (sl[n++] = (Slot){&(x), NULL})
#define I(x) (sl[n++] = (Slot){NULL, &(x)})
    for (int i = 0; i < 7; i++) {
        D(s->y[i]);
    }
    I(s->k);
    for (int i = 0; i < 3; i++) {
        D(s->held[i]);
    }
    for (int i = 0; i < 3; i++) {
        D(s->limited[i]);
    }
    I(s->saturated);
    I(s->commands);
    I(s->bad_commands);
    I(s->taken_valid);
    for (int i = 0; i < 3; i++) {
        D(s->taken[i]);
    }
    for (int i = 0; i < 3; i++) {
        D(s->applied[i]);
    }
    D(s->last[0]);
    D(s->last[1]);
    D(s->local_max[0]);
    D(s->local_max[1]);
    D(s->local_sum[0]);
    D(s->local_sum[1]);
    D(s->worst_t);
    I(s->periods);
    I(s->checked);
    I(s->log_count);
    I(s->frame_truth);
    I(s->bad_replies);
    I(s->stale_replies);
#undef D
#undef I
}

static int read_state(PyObject *obj, State *s)
{
    PyObject *fast = PySequence_Fast(obj, "state");
    if (fast == NULL) {
        return -1;
    }
    if (PySequence_Fast_GET_SIZE(fast) != STATE_SIZE) {
        PyErr_Format(PyExc_ValueError, "state: %zd values, expected %d", PySequence_Fast_GET_SIZE(fast), STATE_SIZE);
        Py_DECREF(fast);
        return -1;
    }
    PyObject **it = PySequence_Fast_ITEMS(fast);
    Slot sl[STATE_SIZE];
    state_slots(s, sl);
    for (int i = 0; i < STATE_SIZE; i++) {
        if (sl[i].d != NULL) {
            *sl[i].d = PyFloat_AsDouble(it[i]);
        } else {
            *sl[i].i = PyLong_AsLongLong(it[i]);   /* True / False are 1 / 0 */
        }
        if (PyErr_Occurred()) {
            PyErr_Format(PyExc_TypeError, "state[%d]: not %s", i, sl[i].d != NULL ? "a number" : "an integer");
            Py_DECREF(fast);
            return -1;
        }
    }
    Py_DECREF(fast);
    return 0;
}

static PyObject *state_tuple(State *s)
{
    Slot sl[STATE_SIZE];
    state_slots(s, sl);
    PyObject *t = PyTuple_New(STATE_SIZE);
    for (int i = 0; t != NULL && i < STATE_SIZE; i++) {
        PyObject *v = sl[i].d != NULL ? PyFloat_FromDouble(*sl[i].d) : PyLong_FromLongLong(*sl[i].i);
        if (v == NULL) {
            Py_CLEAR(t);
        } else {
            PyTuple_SET_ITEM(t, i, v);
        }
    }
    return t;
}

/* ---- run ---- */

static PyObject *DirectLoop_run(DirectLoop *self, PyObject *const *args, Py_ssize_t nargs)
{
    if (nargs != 3) {
        PyErr_Format(PyExc_TypeError, "run(state, tick0, count): 3 arguments, got %zd", nargs);
        return NULL;
    }
    State s;
    if (read_state(args[0], &s) < 0) {
        return NULL;
    }
    const long long tick0 = PyLong_AsLongLong(args[1]);
    const long long count = PyLong_AsLongLong(args[2]);
    if (PyErr_Occurred() || count < 0 || tick0 < 0) {
        PyErr_Clear();
        PyErr_SetString(PyExc_ValueError, "run: tick0 and count must be integers >= 0");
        return NULL;
    }
    const DirectLoop *d = self;
    Block log = {NULL, 0, 0, s.log_count};
    long long *rt = PyMem_Malloc((size_t)(count > 0 ? count : 1) * sizeof *rt);
    if (rt == NULL) {
        return PyErr_NoMemory();
    }
    unsigned char msg[MSG_CAP], reply[REPLY_CAP], ev[REPLY_CAP];
    int status = RUN_DONE, nomem = 0;
    long long done = 0, n_rt = 0;
    int32_t node_rc = 0;
    const char *node_call = "";
    Py_ssize_t reply_len = 0;

    Py_BEGIN_ALLOW_THREADS
    for (; done < count; done++) {
        const long long tick = tick0 + done;
        pack_sensors(d, &s, tick, msg);
        if (block_add(&log, &d->ch_sensors, msg, (size_t)d->s_len) < 0) {
            nomem = 1;
            break;
        }
        const long long t0 = now_ns();
        const int32_t n = d->sensors(d->handle, (const char *)msg, (uint32_t)d->s_len, reply, REPLY_CAP);
        if (n < 0) {
            status = RUN_NODE_ERROR;
            node_rc = n;
            node_call = "aocs_direct_sensors";
            break;
        }
        int answered = 0;
        if (n > 0) {
            reply_len = n;
            if (block_add(&log, &d->ch_actuator, reply, (size_t)n) < 0) {
                nomem = 1;
                break;
            }
            /* on_cmd: a payload of another type, or for another tick, is no answer */
            if (n != d->a_len || memcmp(reply, d->a_fp, 8) != 0) {
                s.bad_replies++;
            } else if (get_int(reply, &d->a_f[A_TICK]) != tick) {
                s.stale_replies++;
            } else {
                answered = 1;
            }
            int32_t m;
            while ((m = d->event(d->handle, ev, REPLY_CAP)) > 0) {
                if (block_add(&log, &d->ch_events, ev, (size_t)m) < 0) {
                    nomem = 1;
                    break;
                }
            }
            if (nomem) {
                break;
            }
            if (m < 0) {
                status = RUN_NODE_ERROR;
                node_rc = m;
                node_call = "aocs_direct_event";
                break;
            }
        }
        if (record_truth(d, &s, &log, tick) < 0) {
            nomem = 1;
            break;
        }
        if (!answered) {
            status = RUN_NO_REPLY;
            break;
        }
        rt[n_rt++] = now_ns() - t0;
        double u[3];
        if (read_command(d, reply, u)) {
            status = RUN_MISMATCH;
            break;
        }
        /* Plant.apply: every value finite, or the whole command refused */
        s.commands++;
        if (isfinite(u[0]) && isfinite(u[1]) && isfinite(u[2])) {
            hold(d, &s, u);
            s.taken_valid = 1;
            memcpy(s.taken, u, sizeof u);
        } else {
            s.bad_commands++;
            s.taken_valid = 0;
        }
        /* StepDoubling.begin, Plant.advance, StepDoubling.end */
        const int due = s.k % d->check_every == 0 || s.last[0] > d->check_threshold;
        double y0[7], t[3];
        memcpy(y0, s.y, sizeof y0);
        for (int i = 0; i < 3; i++) {
            t[i] = d->const_torque[i] + s.held[i];
            s.applied[i] = 0.0 + s.held[i];
        }
        body_period(d, s.y, d->substeps, t);
        s.k++;
        s.periods++;
        if (due) {
            check_period(d, &s, y0, t);
        } else {
            s.local_sum[0] = s.local_sum[0] + s.last[0];
            s.local_sum[1] = s.local_sum[1] + s.last[1];
        }
    }
    Py_END_ALLOW_THREADS

    if (nomem) {
        PyMem_RawFree(log.data);
        PyMem_Free(rt);
        return PyErr_NoMemory();
    }
    s.log_count = log.count;
    PyObject *extra;
    if (status == RUN_MISMATCH) {
        extra = PyBytes_FromStringAndSize((const char *)reply, reply_len);
    } else if (status == RUN_NODE_ERROR) {
        extra = PyUnicode_FromFormat("%s failed (%d)", node_call, (int)node_rc);
    } else {
        extra = Py_NewRef(Py_None);
    }
    PyObject *blob = PyBytes_FromStringAndSize((const char *)log.data, (Py_ssize_t)log.len);
    PyObject *rts = PyBytes_FromStringAndSize((const char *)rt, (Py_ssize_t)(n_rt * (long long)sizeof *rt));
    PyMem_RawFree(log.data);
    PyMem_Free(rt);
    PyObject *st = state_tuple(&s);
    if (extra == NULL || blob == NULL || rts == NULL || st == NULL) {
        Py_XDECREF(extra);
        Py_XDECREF(blob);
        Py_XDECREF(rts);
        Py_XDECREF(st);
        return NULL;
    }
    return Py_BuildValue("(iLNNNN)", status, done, st, blob, rts, extra);
}

/* ---- construction ---- */

static int read_fields(PyObject *seq, Field *out, int n, const char *codes[], const char *what)
{
    PyObject *fast = PySequence_Fast(seq, what);
    if (fast == NULL) {
        return -1;
    }
    if (PySequence_Fast_GET_SIZE(fast) != n) {
        PyErr_Format(PyExc_ValueError, "%s: %zd fields, expected %d", what, PySequence_Fast_GET_SIZE(fast), n);
        Py_DECREF(fast);
        return -1;
    }
    for (int i = 0; i < n; i++) {
        Py_ssize_t off;
        const char *code;
        if (!PyArg_ParseTuple(PySequence_Fast_GET_ITEM(fast, i), "ns", &off, &code) || off < 0
            || strlen(code) != 1 || strchr(codes[i], code[0]) == NULL) {
            PyErr_Clear();
            PyErr_Format(PyExc_ValueError, "%s[%d]: (offset >= 0, one of the codes '%s')", what, i, codes[i]);
            Py_DECREF(fast);
            return -1;
        }
        out[i].off = off;
        out[i].code = code[0];
    }
    Py_DECREF(fast);
    return 0;
}

static int read_template(PyObject *obj, unsigned char *out, Py_ssize_t *len, const Field *f, int n, const char *what)
{
    char *p;
    Py_ssize_t sz;
    if (PyBytes_AsStringAndSize(obj, &p, &sz) < 0 || sz > MSG_CAP) {
        PyErr_Clear();
        PyErr_Format(PyExc_ValueError, "%s: bytes of at most %d", what, MSG_CAP);
        return -1;
    }
    for (int i = 0; i < n; i++) {   /* every field inside the message, with the widest read (4 doubles) */
        if (f[i].off + 32 > sz) {
            PyErr_Format(PyExc_ValueError, "%s: field %d at %zd is outside the %zd bytes", what, i, f[i].off, sz);
            return -1;
        }
    }
    memcpy(out, p, (size_t)sz);
    *len = sz;
    return 0;
}

static int read_channel(PyObject *obj, Channel *ch)
{
    char *p;
    Py_ssize_t n;
    if (PyBytes_AsStringAndSize(obj, &p, &n) < 0 || n <= 0 || n >= (Py_ssize_t)sizeof ch->name) {
        PyErr_Clear();
        PyErr_SetString(PyExc_ValueError, "channel: bytes of 1 to 31");
        return -1;
    }
    memcpy(ch->name, p, (size_t)n);
    ch->len = (uint32_t)n;
    return 0;
}

static int read_limit(PyObject *obj, int *has, double *v, const char *what)
{
    *has = obj != Py_None;
    if (*has) {
        *v = PyFloat_AsDouble(obj);
        if (*v == -1.0 && PyErr_Occurred()) {
            PyErr_Format(PyExc_TypeError, "%s: None or a number", what);
            return -1;
        }
    }
    return 0;
}

/* CONFIG: the config tuple's order (compiled_loop.config builds it) */
static int DirectLoop_init(DirectLoop *self, PyObject *args, PyObject *kwds)
{
    static char *names[] = {"J", "Ji", "gg", "config", NULL};
    PyObject *j, *ji, *gg, *cfg;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OOOO!", names, &j, &ji, &gg, &PyTuple_Type, &cfg)) {
        return -1;
    }
    if (read_body(&self->body, j, ji, gg) < 0) {
        return -1;
    }
    PyObject *ctorque, *cdist, *axis, *norm, *qd0, *s_tpl, *s_f, *t_tpl, *t_f, *a_f, *a_fp, *chs;
    unsigned long long sensors_addr, event_addr;
    int handle, dist_gg;
    if (!PyArg_ParseTuple(cfg, "dlOOpOOdOddldKKilOOOOOnOllllO", &self->dt, &self->substeps, &ctorque, &cdist,
                          &dist_gg, &axis, &norm, &self->scale, &qd0, &self->arcsec_per_rad, &self->richardson,
                          &self->check_every, &self->check_threshold, &sensors_addr, &event_addr, &handle,
                          &self->valid_bits, &s_tpl, &s_f, &t_tpl, &t_f, &a_f, &self->a_len, &a_fp,
                          &self->max_wheels, &self->max_thrusters, &self->policy_thrusters,
                          &self->policy_magnetorquers, &chs)) {
        return -1;
    }
    self->dist_gg = dist_gg;
    self->handle = handle;
    if (self->substeps < 1 || self->check_every < 1 || !(self->dt > 0.0)) {
        PyErr_SetString(PyExc_ValueError, "config: substeps and check_every >= 1, dt > 0");
        return -1;
    }
    if (sensors_addr == 0 || event_addr == 0) {
        PyErr_SetString(PyExc_ValueError, "config: the node's functions are null");
        return -1;
    }
    self->sensors = (sensors_fn)(uintptr_t)sensors_addr;
    self->event = (event_fn)(uintptr_t)event_addr;
    double q[4];
    if (read_doubles(ctorque, 3, self->const_torque, "const_torque") < 0
        || read_doubles(cdist, 3, self->const_dist, "const_dist") < 0 || read_doubles(qd0, 4, q, "qd0") < 0
        || read_limit(axis, &self->has_axis, &self->axis_limit, "axis_limit") < 0
        || read_limit(norm, &self->has_norm, &self->norm_limit, "norm_limit") < 0) {
        return -1;
    }
    self->qd_inv[0] = -q[0];
    self->qd_inv[1] = -q[1];
    self->qd_inv[2] = -q[2];
    self->qd_inv[3] = q[3];
    static const char *s_codes[S_N] = {"qihb", "qihb", "qihb", "d", "qihb", "d", "d"};
    static const char *t_codes[T_N] = {"qihb", "qihb", "qihb", "d", "d", "d", "d", "d", "d", "d"};
    static const char *a_codes[A_N] = {"qihb", "d", "qihb", "qihb", "qihb"};
    if (read_fields(s_f, self->s_f, S_N, s_codes, "sensors_t fields") < 0
        || read_fields(t_f, self->t_f, T_N, t_codes, "truth_t fields") < 0
        || read_fields(a_f, self->a_f, A_N, a_codes, "actuator_cmd_t fields") < 0
        || read_template(s_tpl, self->s_tpl, &self->s_len, self->s_f, S_N, "sensors_t template") < 0
        || read_template(t_tpl, self->t_tpl, &self->t_len, self->t_f, T_N, "truth_t template") < 0) {
        return -1;
    }
    for (int i = 0; i < A_N; i++) {
        if (self->a_f[i].off + 24 > self->a_len || self->a_len > REPLY_CAP) {
            PyErr_SetString(PyExc_ValueError, "actuator_cmd_t fields: outside its size");
            return -1;
        }
    }
    char *fp;
    Py_ssize_t fpn;
    if (PyBytes_AsStringAndSize(a_fp, &fp, &fpn) < 0 || fpn != 8) {
        PyErr_Clear();
        PyErr_SetString(PyExc_ValueError, "actuator_cmd_t fingerprint: 8 bytes");
        return -1;
    }
    memcpy(self->a_fp, fp, 8);
    PyObject *c0, *c1, *c2, *c3;
    if (!PyArg_ParseTuple(chs, "OOOO", &c0, &c1, &c2, &c3) || read_channel(c0, &self->ch_sensors) < 0
        || read_channel(c1, &self->ch_actuator) < 0 || read_channel(c2, &self->ch_truth) < 0
        || read_channel(c3, &self->ch_events) < 0) {
        return -1;
    }
    return 0;
}

static PyMethodDef DirectLoop_methods[] = {
    {"run", (PyCFunction)(void (*)(void))DirectLoop_run, METH_FASTCALL,
     "run(state, tick0, count) -> (status, done, state, log, rt, extra): count lockstep periods from tick0"},
    {NULL, NULL, 0, NULL}
};

static PyTypeObject DirectLoopType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "aocs_direct_loop_kernel.DirectLoop",
    .tp_basicsize = sizeof(DirectLoop),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "DirectLoop(J, Ji, gg, config): lockstep periods of the in-process transport compiled",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)DirectLoop_init,
    .tp_methods = DirectLoop_methods,
};

static struct PyModuleDef direct_loop_module = {
    PyModuleDef_HEAD_INIT, "aocs_direct_loop_kernel",
    "Whole lockstep periods of the in-process transport, compiled (docs/spec.md 5.13.2)", -1, NULL,
    NULL, NULL, NULL, NULL
};

PyMODINIT_FUNC PyInit_aocs_direct_loop_kernel(void)
{
    if (PyType_Ready(&DirectLoopType) < 0) {
        return NULL;
    }
    PyObject *m = PyModule_Create(&direct_loop_module);
    if (m == NULL) {
        return NULL;
    }
    Py_INCREF(&DirectLoopType);
    if (PyModule_AddObject(m, "DirectLoop", (PyObject *)&DirectLoopType) < 0) {
        Py_DECREF(&DirectLoopType);
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
