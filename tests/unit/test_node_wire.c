/*
 * fsw_node's wire rules (sil/fsw_node/node_wire.h, node_checks.h;
 * docs/wire-contract.md "Frame acceptance"): the frame sequence dedupe (no
 * signed overflow, no latch on one far frame, replays still duplicates,
 * resynchronisation after K consistent frames), the seconds-to-ns
 * conversion over the whole double range, the real-time epoch, payload
 * decoding, the sensors_t -> executive input mapping (the star tracker's
 * time of measurement included), the estimate -> actuator_cmd_t fields
 * and the timeout ranges. Built with the SIL node (host preset),
 * registered from sil/CMakeLists.txt.
 */
#include "test_support.h"

#include <string.h>

#include "node_checks.h"
#include "node_wire.h"

/* bit-for-bit equality of two reals, of two doubles */
#define assert_same_real(a, b)                         \
    do {                                               \
        const real_t a_ = (a);                         \
        const real_t b_ = (b);                         \
        assert_memory_equal(&a_, &b_, sizeof(real_t)); \
    } while (0)
#define assert_same_double(a, b)                       \
    do {                                               \
        const double a_ = (a);                         \
        const double b_ = (b);                         \
        assert_memory_equal(&a_, &b_, sizeof(double)); \
    } while (0)

#define K AOCS_NODE_SEQ_RESYNC_FRAMES
#define W AOCS_NODE_SEQ_WINDOW

static void test_seq_in_order_gaps_duplicates(void **state)
{
    (void)state;
    aocs_node_seq_t s;
    aocs_node_seq_reset(&s);
    assert_int_equal(aocs_node_seq_check(&s, 10), AOCS_NODE_SEQ_OK);
    assert_int_equal(aocs_node_seq_check(&s, 11), AOCS_NODE_SEQ_OK);
    assert_int_equal(aocs_node_seq_check(&s, 11), AOCS_NODE_SEQ_DUPLICATE);
    assert_int_equal(aocs_node_seq_check(&s, 9), AOCS_NODE_SEQ_DUPLICATE);
    assert_int_equal(aocs_node_seq_check(&s, 14), AOCS_NODE_SEQ_GAP);
    assert_int_equal(s.lost, 2u);
    assert_int_equal(s.duplicate, 2u);
    /* the largest accepted step, and one beyond it */
    assert_int_equal(aocs_node_seq_check(&s, 14 + (int64_t)W), AOCS_NODE_SEQ_GAP);
    assert_int_equal(s.lost, 2u + W - 1u);
    assert_int_equal(aocs_node_seq_check(&s, 14 + 2 * (int64_t)W + 1), AOCS_NODE_SEQ_JUMP);
    assert_int_equal(s.jump, 1u);
    assert_int_equal(aocs_node_seq_accepted(AOCS_NODE_SEQ_GAP), 1);
    assert_int_equal(aocs_node_seq_accepted(AOCS_NODE_SEQ_RESYNC), 1);
    assert_int_equal(aocs_node_seq_accepted(AOCS_NODE_SEQ_DUPLICATE), 0);
    assert_int_equal(aocs_node_seq_accepted(AOCS_NODE_SEQ_JUMP), 0);
}

/* issue 11 item 2: one frame INT64_MAX made every later frame a duplicate */
static void test_seq_int64_max_does_not_silence(void **state)
{
    (void)state;
    aocs_node_seq_t s;
    aocs_node_seq_reset(&s);
    for (int64_t f = 0; f < 5; ++f) {
        assert_int_equal(aocs_node_seq_check(&s, f), AOCS_NODE_SEQ_OK);
    }
    assert_int_equal(aocs_node_seq_check(&s, INT64_MAX), AOCS_NODE_SEQ_JUMP);
    assert_int_equal(aocs_node_seq_check(&s, 5), AOCS_NODE_SEQ_OK); /* answered at once */
    assert_int_equal(aocs_node_seq_check(&s, INT64_MIN), AOCS_NODE_SEQ_JUMP);
    assert_int_equal(aocs_node_seq_check(&s, 6), AOCS_NODE_SEQ_OK);
    assert_int_equal(s.lost, 0u);
    /* a replayed old frame is still a duplicate */
    assert_int_equal(aocs_node_seq_check(&s, 2), AOCS_NODE_SEQ_DUPLICATE);
    assert_int_equal(aocs_node_seq_check(&s, 7), AOCS_NODE_SEQ_OK);
}

/* issue 11 item 2: INT64_MIN then INT64_MAX overflowed frame - last - 1 (UB under UBSan) */
static void test_seq_extremes_no_overflow(void **state)
{
    (void)state;
    aocs_node_seq_t s;
    aocs_node_seq_reset(&s);
    assert_int_equal(aocs_node_seq_check(&s, INT64_MIN), AOCS_NODE_SEQ_OK); /* first frame: taken */
    assert_int_equal(aocs_node_seq_check(&s, INT64_MAX), AOCS_NODE_SEQ_DUPLICATE); /* one behind, modulo 2^64 */
    assert_int_equal(aocs_node_seq_check(&s, INT64_MIN + 1), AOCS_NODE_SEQ_OK);
    assert_int_equal(s.lost, 0u);
    /* the counter wraps from INT64_MAX to INT64_MIN: one step */
    aocs_node_seq_reset(&s);
    assert_int_equal(aocs_node_seq_check(&s, INT64_MAX - 1), AOCS_NODE_SEQ_OK);
    assert_int_equal(aocs_node_seq_check(&s, INT64_MAX), AOCS_NODE_SEQ_OK);
    assert_int_equal(aocs_node_seq_check(&s, INT64_MIN), AOCS_NODE_SEQ_OK);
    assert_int_equal(aocs_node_seq_check(&s, INT64_MIN + 3), AOCS_NODE_SEQ_GAP);
    assert_int_equal(s.lost, 2u);
    /* lost saturates instead of wrapping */
    s.lost = UINT64_MAX - 1u;
    assert_int_equal(aocs_node_seq_check(&s, INT64_MIN + 3 + (int64_t)W), AOCS_NODE_SEQ_GAP);
    assert_int_equal(s.lost, UINT64_MAX);
    assert_int_equal(aocs_node_add_sat(UINT64_MAX, 1u), UINT64_MAX);
    assert_int_equal(aocs_node_add_sat(1u, 2u), 3u);
}

/* a bad FIRST frame: the plant's own frames resynchronise after K of them */
static void test_seq_bad_first_frame_resyncs(void **state)
{
    (void)state;
    aocs_node_seq_t s;
    aocs_node_seq_reset(&s);
    assert_int_equal(aocs_node_seq_check(&s, INT64_MAX), AOCS_NODE_SEQ_OK);
    for (int64_t f = 0; f + 1 < (int64_t)K; ++f) {
        assert_int_equal(aocs_node_seq_check(&s, f), AOCS_NODE_SEQ_DUPLICATE);
    }
    assert_int_equal(aocs_node_seq_check(&s, (int64_t)K - 1), AOCS_NODE_SEQ_RESYNC);
    assert_int_equal(s.resyncs, 1u);
    assert_int_equal(aocs_node_seq_check(&s, (int64_t)K), AOCS_NODE_SEQ_OK);
    assert_int_equal(s.lost, 0u);
    /* a first frame slightly ahead (within W): the same, not W frames of silence */
    aocs_node_seq_reset(&s);
    assert_int_equal(aocs_node_seq_check(&s, 500), AOCS_NODE_SEQ_OK);
    assert_int_equal(aocs_node_seq_check(&s, 0), AOCS_NODE_SEQ_DUPLICATE);
    assert_int_equal(aocs_node_seq_check(&s, 1), AOCS_NODE_SEQ_DUPLICATE);
    assert_int_equal(aocs_node_seq_check(&s, 2), AOCS_NODE_SEQ_RESYNC);
}

static void test_seq_resync_rules(void **state)
{
    (void)state;
    aocs_node_seq_t s;
    /* a plant that restarts far ahead: K consistent frames, then followed */
    aocs_node_seq_reset(&s);
    assert_int_equal(aocs_node_seq_check(&s, 100), AOCS_NODE_SEQ_OK);
    assert_int_equal(aocs_node_seq_check(&s, 1000000), AOCS_NODE_SEQ_JUMP);
    assert_int_equal(aocs_node_seq_check(&s, 1000001), AOCS_NODE_SEQ_JUMP);
    assert_int_equal(aocs_node_seq_check(&s, 1000003), AOCS_NODE_SEQ_RESYNC); /* gaps inside W are consistent */
    assert_int_equal(aocs_node_seq_check(&s, 1000004), AOCS_NODE_SEQ_OK);
    assert_int_equal(s.lost, 0u);
    /* the same forged frame repeated never resynchronises */
    aocs_node_seq_reset(&s);
    assert_int_equal(aocs_node_seq_check(&s, 100), AOCS_NODE_SEQ_OK);
    for (int i = 0; i < 10; ++i) {
        assert_int_equal(aocs_node_seq_check(&s, INT64_MAX), AOCS_NODE_SEQ_JUMP);
    }
    assert_int_equal(s.resyncs, 0u);
    /* forged frames interleaved with the plant's: each accepted frame drops the candidates */
    for (int64_t i = 0; i < 10; ++i) {
        assert_int_equal(aocs_node_seq_check(&s, 5000000 + i), AOCS_NODE_SEQ_JUMP);
        assert_int_equal(aocs_node_seq_check(&s, 101 + i), AOCS_NODE_SEQ_OK);
    }
    assert_int_equal(s.resyncs, 0u);
    /* K - 1 consistent forged frames: the next plant frame is still in sequence */
    assert_int_equal(aocs_node_seq_check(&s, 7000000), AOCS_NODE_SEQ_JUMP);
    assert_int_equal(aocs_node_seq_check(&s, 7000001), AOCS_NODE_SEQ_JUMP);
    assert_int_equal(aocs_node_seq_check(&s, 111), AOCS_NODE_SEQ_OK);
}

/* issue 11 item 2: llround overflowed for t_s near 1e10 s */
static void test_seconds_to_ns(void **state)
{
    (void)state;
    assert_int_equal(aocs_node_seconds_to_ns(0.1), 100000000u);
    assert_int_equal(aocs_node_seconds_to_ns(1.0), 1000000000u);
    assert_int_equal(aocs_node_seconds_to_ns(1.5e-9), 2u);  /* half away from zero */
    assert_int_equal(aocs_node_seconds_to_ns(1.4e-9), 1u);
    assert_int_equal(aocs_node_seconds_to_ns(0.0), 0u);
    assert_int_equal(aocs_node_seconds_to_ns(-1.0), 0u);
    assert_int_equal(aocs_node_seconds_to_ns((double)NAN), 0u);
    assert_int_equal(aocs_node_seconds_to_ns((double)INFINITY), 0u);
    /* above INT64_MAX ns (9.22e9 s), where llround overflowed: exact */
    assert_int_equal(aocs_node_seconds_to_ns(1.0e10), 10000000000000000000ull);
    assert_int_equal(aocs_node_seconds_to_ns(9.5e9), 9500000000000000000ull);
    assert_int_equal(aocs_node_seconds_to_ns(1.7999999e10), 17999999000000000000ull);
    /* out of range: 0 ("no time") */
    assert_int_equal(aocs_node_seconds_to_ns(1.8e10), 0u);
    assert_int_equal(aocs_node_seconds_to_ns(1.0e300), 0u);
    /* monotone over the range */
    uint64_t prev = 0u;
    for (double t = 1e-9; t < 1.8e10; t *= 1.37) {
        uint64_t ns = aocs_node_seconds_to_ns(t);
        assert_true(ns >= prev);
        prev = ns;
    }
}

static void test_epoch_update(void **state)
{
    (void)state;
    const uint64_t tol = 200000000u; /* 0.2 s */
    const uint64_t s = 1000000000u;
    aocs_node_epoch_t ep;
    memset(&ep, 0, sizeof(ep));
    assert_int_equal(aocs_node_epoch_update(&ep, 100u * s, 5u * s, tol), 1); /* first: sim 0 at HAL 95 s */
    assert_int_equal(ep.t0_ns, 95u * s);
    assert_int_equal(aocs_node_epoch_update(&ep, 101u * s + 1000u, 6u * s, tol), 0); /* agrees */
    /* one forged t_s: ignored */
    assert_int_equal(aocs_node_epoch_update(&ep, 102u * s, 1000000u * s, tol), 0);
    assert_int_equal(ep.t0_ns, 95u * s);
    assert_int_equal(aocs_node_epoch_update(&ep, 103u * s, 8u * s, tol), 0);
    /* K consistent samples of a re-based plant: followed */
    assert_int_equal(aocs_node_epoch_update(&ep, 104u * s, 0u, tol), 0);
    assert_int_equal(aocs_node_epoch_update(&ep, 105u * s, 1u * s, tol), 0);
    assert_int_equal(aocs_node_epoch_update(&ep, 106u * s, 2u * s, tol), 1);
    assert_int_equal(ep.t0_ns, 104u * s);
    /* sim time ahead of the HAL clock maps to 0; NULL is a no-op */
    memset(&ep, 0, sizeof(ep));
    assert_int_equal(aocs_node_epoch_update(&ep, 1u, 5u * s, tol), 1);
    assert_int_equal(ep.t0_ns, 0u);
    assert_int_equal(aocs_node_epoch_update(NULL, 1u, 1u, tol), 0);
}

static void test_decode(void **state)
{
    (void)state;
    aocs_lcm_sensors_t m;
    memset(&m, 0, sizeof(m));
    m.protocol_version = AOCS_LCM_SENSORS_T_PROTOCOL_VERSION;
    m.frame = 7;
    m.tick = 3;
    m.t_s = 0.3;
    m.q[3] = 1.0;
    uint8_t buf[512];
    int n = aocs_lcm_sensors_t_encode(buf, 0, (int)sizeof(buf), &m);
    assert_true(n > 0);
    aocs_lcm_sensors_t d;
    assert_int_equal(aocs_node_decode_sensors(buf, (uint32_t)n, &d), AOCS_NODE_DECODE_OK);
    assert_int_equal(d.frame, 7);
    (void)aocs_lcm_sensors_t_decode_cleanup(&d);
    assert_int_equal(aocs_node_decode_sensors(buf, (uint32_t)n - 1u, &d), AOCS_NODE_DECODE_MALFORMED);
    buf[n] = 0u;
    assert_int_equal(aocs_node_decode_sensors(buf, (uint32_t)n + 1u, &d), AOCS_NODE_DECODE_MALFORMED);
    assert_int_equal(aocs_node_decode_sensors(buf, 0u, &d), AOCS_NODE_DECODE_MALFORMED);
    assert_int_equal(aocs_node_decode_sensors(NULL, 10u, &d), AOCS_NODE_DECODE_MALFORMED);
    assert_int_equal(aocs_node_decode_sensors(buf, 0x80000000u, &d), AOCS_NODE_DECODE_MALFORMED);
    m.protocol_version = 99;
    n = aocs_lcm_sensors_t_encode(buf, 0, (int)sizeof(buf), &m);
    assert_int_equal(aocs_node_decode_sensors(buf, (uint32_t)n, &d), AOCS_NODE_DECODE_FOREIGN);
    /* a command payload on the sensors decoder: fingerprint mismatch */
    aocs_lcm_command_t c;
    memset(&c, 0, sizeof(c));
    c.protocol_version = AOCS_LCM_COMMAND_T_PROTOCOL_VERSION;
    c.law_id = AOCS_LCM_COMMAND_T_LAW_KEEP;
    c.mode = AOCS_LCM_COMMAND_T_MODE_KEEP;
    n = aocs_lcm_command_t_encode(buf, 0, (int)sizeof(buf), &c);
    assert_int_equal(aocs_node_decode_sensors(buf, (uint32_t)n, &d), AOCS_NODE_DECODE_MALFORMED);
    aocs_lcm_command_t dc;
    assert_int_equal(aocs_node_decode_command(buf, (uint32_t)n, &dc), AOCS_NODE_DECODE_OK);
    (void)aocs_lcm_command_t_decode_cleanup(&dc);
    assert_int_equal(aocs_node_decode_command(buf, (uint32_t)n - 3u, &dc), AOCS_NODE_DECODE_MALFORMED);
}

static void test_command_apply(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_config_default(&cfg);
    cfg.law = AOCS_LAW_QUAT_PD;
    cfg.laws.quat_pd.kp = AOCS_R(1.0);
    cfg.laws.quat_pd.kd = AOCS_R(1.0);
    cfg.u_max_axis = aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0));
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    aocs_law_id_t nominal = AOCS_LAW_QUAT_PD;
    aocs_lcm_command_t c;
    memset(&c, 0, sizeof(c));
    c.law_id = AOCS_LCM_COMMAND_T_LAW_KEEP;
    c.mode = AOCS_LCM_COMMAND_T_MODE_KEEP;
    assert_int_equal(aocs_node_command_apply(&exec, &nominal, &c), AOCS_OK); /* nothing asked */
    c.mode = AOCS_LCM_COMMAND_T_MODE_SAFE;
    assert_int_equal(aocs_node_command_apply(&exec, &nominal, &c), AOCS_ERR_MODE_INVALID);
    c.mode = AOCS_LCM_COMMAND_T_MODE_STANDBY;
    assert_int_equal(aocs_node_command_apply(&exec, &nominal, &c), AOCS_OK);
    assert_int_equal(exec.law, AOCS_LAW_NONE);
    c.mode = AOCS_LCM_COMMAND_T_MODE_NOMINAL;
    assert_int_equal(aocs_node_command_apply(&exec, &nominal, &c), AOCS_OK);
    assert_int_equal(exec.law, AOCS_LAW_QUAT_PD);
    c.law_id = 99;
    assert_int_equal(aocs_node_command_apply(&exec, &nominal, &c), AOCS_ERR_UNKNOWN_LAW);
    c.law_id = AOCS_LCM_COMMAND_T_LAW_KEEP;
    c.mode = AOCS_LCM_COMMAND_T_MODE_KEEP;
    c.set_target = 1;
    c.qd[3] = 1e300; /* non-unit: refused by the executive, not a crash */
    assert_int_equal(aocs_node_command_apply(&exec, &nominal, &c), AOCS_ERR_TARGET_INVALID);
    assert_int_equal(aocs_node_command_apply(NULL, &nominal, &c), AOCS_ERR_NULL_ARG);
}

/* Lockstep: the measurement time converted exactly as t_s is; real time: shifted onto the reception clock by its
 * age; every absurd time is 0 ("no time"), never a wrap. */
static void test_meas_time_ns(void **state)
{
    (void)state;
    const uint64_t s = 1000000000u;
    const double bad[] = {(double)NAN, (double)INFINITY, -(double)INFINITY, -1.0, 0.0, 1.8e10, 1e300, -1e-300};
    /* lockstep: t_sensor_ns = ns(t_s), the result is ns(t_meas_s) whatever the two times are */
    assert_true(aocs_node_meas_time_ns(aocs_node_seconds_to_ns(12.5), 12.5, 12.4) == aocs_node_seconds_to_ns(12.4));
    assert_true(aocs_node_meas_time_ns(aocs_node_seconds_to_ns(0.3), 0.3, 0.2) == 200000000u);
    assert_true(aocs_node_meas_time_ns(aocs_node_seconds_to_ns(0.3), 0.3, 0.7) == 700000000u); /* future: kept */
    assert_true(aocs_node_meas_time_ns(0u, (double)NAN, 0.2) == 200000000u);   /* t_s no time: still ns(t_meas) */
    assert_true(aocs_node_meas_time_ns(aocs_node_seconds_to_ns(1.7e10), 1.7e10, 1.7999999e10) ==
                aocs_node_seconds_to_ns(1.7999999e10));
    for (double t = 1e-9; t < 1.8e10; t *= 3.7) {
        assert_true(aocs_node_meas_time_ns(aocs_node_seconds_to_ns(t), t, t * 0.5) == aocs_node_seconds_to_ns(t * 0.5));
        assert_true(aocs_node_meas_time_ns(aocs_node_seconds_to_ns(t), t, t) == aocs_node_seconds_to_ns(t));
    }
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); ++i) {
        assert_true(aocs_node_meas_time_ns(aocs_node_seconds_to_ns(5.0), 5.0, bad[i]) == 0u);
        assert_true(aocs_node_meas_time_ns(UINT64_MAX, 5.0, bad[i]) == 0u);
        /* real time: a sample whose own t_s is no time has no age */
        assert_true(aocs_node_meas_time_ns(100u * s, bad[i], 4.0) == 0u);
    }
    /* real time: the reception time minus the age (t_s - t_meas_s) */
    assert_true(aocs_node_meas_time_ns(100u * s, 5.0, 4.75) == 100u * s - 250000000u);
    assert_true(aocs_node_meas_time_ns(100u * s, 5.0, 5.0) == 100u * s);
    assert_true(aocs_node_meas_time_ns(100u * s, 5.0, 5.5) == 100u * s + 500000000u);      /* future: kept */
    assert_true(aocs_node_meas_time_ns(1u * s, 1.0e9, 1.0) == 0u);                        /* before the clock */
    assert_true(aocs_node_meas_time_ns(UINT64_MAX - 1u, 1.0, 1.7e10) == UINT64_MAX);     /* saturates */
}

static void test_sensors_to_input_star_tracker_and_gyro(void **state)
{
    (void)state;
    aocs_lcm_sensors_t m;
    aocs_exec_input_t in;
    memset(&m, 0, sizeof(m));
    m.tick = 42;
    m.t_s = 4.2;
    m.valid = AOCS_LCM_SENSORS_T_VALID_ATTITUDE | AOCS_LCM_SENSORS_T_VALID_RATE;
    m.q[3] = 1.0;
    m.st_q[0] = 0.5;
    m.st_q[1] = -0.5;
    m.st_q[2] = 0.5;
    m.st_q[3] = -0.5;
    m.st_t_meas_s = 4.1;
    m.gyro_w[0] = 0.0078125;
    m.gyro_w[1] = -0.25;
    m.gyro_w[2] = (double)NAN;
    /* the flags off: the values are there all the same (the last sample), the executive is told it is not new */
    aocs_node_sensors_to_input(&m, aocs_node_seconds_to_ns(m.t_s), &in);
    assert_int_equal(in.valid, AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE);
    assert_same_real(in.st_q_SN.q[1], AOCS_R(-0.5));
    assert_true(in.st_t_meas_ns == aocs_node_seconds_to_ns(4.1));
    m.valid |= AOCS_LCM_SENSORS_T_VALID_STAR_TRACKER;
    aocs_node_sensors_to_input(&m, aocs_node_seconds_to_ns(m.t_s), &in);
    assert_int_equal(in.valid, AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE | AOCS_EXEC_VALID_ST);
    m.valid = AOCS_LCM_SENSORS_T_VALID_GYRO;
    aocs_node_sensors_to_input(&m, aocs_node_seconds_to_ns(m.t_s), &in);
    assert_int_equal(in.valid, AOCS_EXEC_VALID_GYRO);
    for (int i = 0; i < 4; ++i) {
        assert_same_real(in.st_q_SN.q[i], (real_t)m.st_q[i]);
    }
    assert_same_real(in.gyro_w_B.v[0], AOCS_R(0.0078125));
    assert_same_real(in.gyro_w_B.v[1], AOCS_R(-0.25));
    assert_true(isnan(in.gyro_w_B.v[2])); /* unchecked: the executive decides */
    /* real time: the tracker's time on the reception clock, 0.1 s before it */
    aocs_node_sensors_to_input(&m, 1000000000000u, &in);
    assert_true(in.t_sensor_ns == 1000000000000u);
    assert_true(in.st_t_meas_ns == 1000000000000u - (aocs_node_seconds_to_ns(4.2) - aocs_node_seconds_to_ns(4.1)));
    /* an absurd time of measurement: no time, whatever the mode */
    m.st_t_meas_s = -1e300;
    aocs_node_sensors_to_input(&m, aocs_node_seconds_to_ns(m.t_s), &in);
    assert_true(in.st_t_meas_ns == 0u);
}

static void test_estimate_to_cmd(void **state)
{
    (void)state;
    aocs_det_output_t e;
    aocs_lcm_actuator_cmd_t m;
    memset(&e, 0, sizeof(e));
    memset(&m, 0, sizeof(m));
    m.tick = 9;
    e.q_BN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(-0.75), AOCS_R(0.5));
    e.w_BN_B = aocs_vec3_make(AOCS_R(0.125), AOCS_R(-0.5), AOCS_R(3.0));
    e.valid = AOCS_EXEC_VALID_ATT;
    e.status = AOCS_ERR_INPUT_NOT_FINITE;
    e.bias_B_radps = aocs_vec3_make(AOCS_R(-0.0009765625), AOCS_R(0.0), AOCS_R(0.25));
    for (uint32_t i = 0u; i < AOCS_EST_P_UPPER_COUNT; ++i) {
        e.p_upper[i] = (real_t)(0.0625 * (double)(i + 1u));
    }
    e.st_status = AOCS_ERR_QUAT_NOT_UNIT;
    e.n_st_used = UINT32_MAX;
    e.n_st_gated = 2u;
    e.n_st_hostile = 3u;
    e.n_restarts = 4u;
    aocs_node_estimate_to_cmd(&e, 1u, &m);
    assert_int_equal(m.tick, 9); /* the other fields as they were */
    assert_int_equal(m.estimator, 1);
    assert_int_equal(m.est_status, (int32_t)AOCS_ERR_INPUT_NOT_FINITE);
    assert_same_double(m.q_est[0], 0.0);
    assert_same_double(m.q_est[2], -0.75);
    assert_same_double(m.q_est[3], 0.5);
    assert_same_double(m.w_est[0], 0.125);
    assert_same_double(m.w_est[1], -0.5);
    assert_same_double(m.w_est[2], 3.0);
    assert_same_double(m.bias_est[0], -0.0009765625);
    assert_same_double(m.bias_est[2], 0.25);
    for (uint32_t i = 0u; i < AOCS_EST_P_UPPER_COUNT; ++i) {
        assert_same_double(m.est_p[i], 0.0625 * (double)(i + 1u));
    }
    assert_int_equal(m.st_status, (int32_t)AOCS_ERR_QUAT_NOT_UNIT);
    assert_true(m.n_st_used == (int64_t)UINT32_MAX);
    assert_true((m.n_st_gated == 2) && (m.n_st_hostile == 3) && (m.n_est_restarts == 4));
    aocs_node_estimate_to_cmd(&e, 1000u, &m);
    assert_int_equal(m.estimator, INT8_MAX);
    aocs_node_estimate_to_cmd(NULL, 0u, &m); /* total */
    aocs_node_estimate_to_cmd(&e, 0u, NULL);
    assert_int_equal(m.estimator, INT8_MAX);
}

/* protocol version 4: the magnetometer reaches the executive with its flag, values unchecked */
static void test_sensors_to_input_magnetometer(void **state)
{
    (void)state;
    aocs_lcm_sensors_t m;
    aocs_exec_input_t in;
    memset(&m, 0, sizeof(m));
    m.t_s = 1.0;
    m.valid = AOCS_LCM_SENSORS_T_VALID_ATTITUDE;
    m.mag_b_t[0] = 2.5e-5;
    m.mag_b_t[1] = -1.25e-5;
    m.mag_b_t[2] = (double)NAN;
    aocs_node_sensors_to_input(&m, aocs_node_seconds_to_ns(m.t_s), &in);
    assert_int_equal(in.valid, AOCS_EXEC_VALID_ATT); /* flag off: not a reading */
    m.valid |= AOCS_LCM_SENSORS_T_VALID_MAGNETOMETER;
    aocs_node_sensors_to_input(&m, aocs_node_seconds_to_ns(m.t_s), &in);
    assert_int_equal(in.valid, AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_MAG);
    assert_same_real(in.mag_B_T.v[0], (real_t)2.5e-5);
    assert_same_real(in.mag_B_T.v[1], (real_t)-1.25e-5);
    assert_true(isnan(in.mag_B_T.v[2]));
    assert_int_equal(AOCS_LCM_SENSORS_T_VALID_MAGNETOMETER, 128);
}

static void test_momentum_to_cmd(void **state)
{
    (void)state;
    aocs_mom_output_t o;
    aocs_mom_config_t c;
    aocs_lcm_actuator_cmd_t m;
    memset(&o, 0, sizeof(o));
    memset(&c, 0, sizeof(c));
    memset(&m, 0, sizeof(m));
    m.tick = 7;
    c.policy = (uint32_t)AOCS_MOM_THRUSTERS;
    c.thr_count = 12u;
    for (uint32_t i = 0u; i < AOCS_MOM_THRUSTERS_MAX; ++i) {
        o.thruster_on_s[i] = (real_t)(0.001 * (double)(i + 1u));
    }
    o.dipole_Am2 = aocs_vec3_make(AOCS_R(0.5), AOCS_R(-0.25), AOCS_R(0.125));
    o.u_unload_B_Nm = aocs_vec3_make(AOCS_R(-0.5), AOCS_R(0.0), AOCS_R(0.75));
    o.h_wheels_B_Nms = aocs_vec3_make(AOCS_R(10.0), AOCS_R(-2.0), AOCS_R(0.5));
    o.dh_B_Nms = aocs_vec3_make(AOCS_R(9.0), AOCS_R(-2.0), AOCS_R(0.5));
    o.unloading = 1;
    o.n_events = UINT32_MAX;
    o.latch_closed_mask = 2u; /* valve B closed */
    o.status = AOCS_ERR_INPUT_MISSING;
    aocs_node_momentum_to_cmd(&o, &c, &m);
    assert_int_equal(m.tick, 7); /* the other fields as they were */
    assert_int_equal(m.mom_policy, (int)AOCS_MOM_THRUSTERS);
    assert_int_equal(m.mom_status, (int32_t)AOCS_ERR_INPUT_MISSING);
    assert_int_equal(m.n_thrusters, 12);
    for (uint32_t i = 0u; i < AOCS_MOM_THRUSTERS_MAX; ++i) {
        assert_same_double(m.thruster_on_s[i], (double)(real_t)(0.001 * (double)(i + 1u)));
    }
    assert_same_double(m.dipole_am2[1], -0.25);
    assert_same_double(m.u_unload[2], 0.75);
    assert_same_double(m.h_wheels[0], 10.0);
    assert_same_double(m.dh[0], 9.0);
    assert_int_equal(m.unloading, 1);
    assert_true(m.n_unload_events == (int64_t)UINT32_MAX);
    assert_int_equal(m.thruster_latch_closed, 2);
    o.latch_closed_mask = 0xFFFFFFFFu; /* only the two branches' bits reach the wire */
    aocs_node_momentum_to_cmd(&o, &c, &m);
    assert_int_equal(m.thruster_latch_closed, 3);
    o.latch_closed_mask = 2u;
    /* magnetorquers: no thrusters reported whatever thr_count holds */
    c.policy = (uint32_t)AOCS_MOM_MAGNETORQUERS;
    aocs_node_momentum_to_cmd(&o, &c, &m);
    assert_int_equal(m.n_thrusters, 0);
    assert_int_equal(m.mom_policy, 1);
    aocs_node_momentum_to_cmd(NULL, &c, &m); /* total */
    aocs_node_momentum_to_cmd(&o, &c, NULL);
}

/* issue 11 item 3: idle_timeout_s = 2e10, 1e300 or 1e-10 made fsw_node exit at once */
static void test_timeouts_check(void **state)
{
    (void)state;
    aocs_node_config_t cfg;
    char err[256];
    memset(&cfg, 0, sizeof(cfg));
    cfg.idle_timeout_s = 5.0;
    cfg.run_timeout_s = 0.0;
    cfg.status_period_s = 1.0;
    assert_int_equal(aocs_node_timeouts_check(&cfg, err, sizeof(err)), 0);
    const double bad_idle[] = {2e10, 1e300, 1e-10, 0.0, -1.0, (double)NAN, 86400.1, 0.009};
    for (size_t i = 0; i < sizeof(bad_idle) / sizeof(bad_idle[0]); ++i) {
        cfg.idle_timeout_s = bad_idle[i];
        err[0] = '\0';
        assert_int_equal(aocs_node_timeouts_check(&cfg, err, sizeof(err)), 1);
        assert_non_null(strstr(err, "idle_timeout_s"));
        assert_null(strchr(err, '\n'));
    }
    cfg.idle_timeout_s = 0.01;
    assert_int_equal(aocs_node_timeouts_check(&cfg, err, sizeof(err)), 0);
    cfg.run_timeout_s = 1e300;
    assert_int_equal(aocs_node_timeouts_check(&cfg, err, sizeof(err)), 1);
    assert_non_null(strstr(err, "run_timeout_s"));
    cfg.run_timeout_s = 1e-10;
    assert_int_equal(aocs_node_timeouts_check(&cfg, err, sizeof(err)), 1);
    cfg.run_timeout_s = 1e7;
    assert_int_equal(aocs_node_timeouts_check(&cfg, err, sizeof(err)), 0);
    cfg.status_period_s = 2e10;
    assert_int_equal(aocs_node_timeouts_check(&cfg, err, sizeof(err)), 1);
    assert_non_null(strstr(err, "status_period_s"));
    cfg.status_period_s = 1e-10;
    assert_int_equal(aocs_node_timeouts_check(&cfg, err, sizeof(err)), 1);
    cfg.status_period_s = 0.05;
    assert_int_equal(aocs_node_timeouts_check(&cfg, NULL, 0u), 0);
    assert_int_equal(aocs_node_timeouts_check(NULL, err, sizeof(err)), 1);
    /* wait_spin_us: [0, AOCS_NODE_WAIT_SPIN_MAX_US] us, named with its unit */
    const double bad_spin[] = {-1.0, (double)NAN, (double)INFINITY, AOCS_NODE_WAIT_SPIN_MAX_US * 1.000001, 1e300};
    for (size_t i = 0; i < sizeof(bad_spin) / sizeof(bad_spin[0]); ++i) {
        cfg.wait_spin_us = bad_spin[i];
        err[0] = '\0';
        assert_int_equal(aocs_node_timeouts_check(&cfg, err, sizeof(err)), 1);
        assert_non_null(strstr(err, "key 'wait_spin_us'"));
        assert_non_null(strstr(err, "us is outside [0, 10000] us"));
    }
    cfg.wait_spin_us = AOCS_NODE_WAIT_SPIN_MAX_US;
    assert_int_equal(aocs_node_timeouts_check(&cfg, err, sizeof(err)), 0);
    cfg.wait_spin_us = 0.0;
    assert_int_equal(aocs_node_timeouts_check(&cfg, err, sizeof(err)), 0);
}

/* an event of the log into event_t: every field, t_s from ns, the unit clamped to int16, version 6 */
static void test_event_to_msg(void **state)
{
    (void)state;
    aocs_evlog_t log;
    aocs_event_t e;
    aocs_lcm_event_t m;
    aocs_evlog_init(&log);
    assert_int_equal(aocs_evlog_raise(&log, AOCS_EVT_WHEEL_ISOLATED, 60500000000ull, 1, AOCS_R(0.1875), AOCS_R(0.025)),
                     1u);
    assert_int_equal(aocs_evlog_raise(&log, AOCS_EVT_LINK_LOST, 3u, 70000, AOCS_R(3.0), AOCS_R(3.0)), 2u);
    assert_int_equal(aocs_evlog_next(&log, 0u, &e, NULL), AOCS_OK);
    aocs_node_event_to_msg(&e, 4u, &m);
    assert_int_equal(m.protocol_version, 6);
    assert_int_equal(m.seq, 1);
    assert_close(m.t_s, 60.5, 1e-12);
    assert_int_equal(m.id, 10);
    assert_int_equal(m.severity, 2);  /* error */
    assert_int_equal(m.unit_kind, 3); /* wheel */
    assert_int_equal(m.unit, 1);
    assert_close(m.value, 0.1875, 0.0);
    assert_close(m.threshold, (double)AOCS_R(0.025), 0.0);
    assert_int_equal(m.n_lost, 4);
    assert_int_equal(aocs_evlog_next(&log, 1u, &e, NULL), AOCS_OK);
    aocs_node_event_to_msg(&e, 0u, &m);
    assert_int_equal(m.unit, INT16_MAX);
    assert_int_equal(m.severity, 1);
    assert_int_equal(m.unit_kind, 6); /* link */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_seq_in_order_gaps_duplicates),
        cmocka_unit_test(test_seq_int64_max_does_not_silence),
        cmocka_unit_test(test_seq_extremes_no_overflow),
        cmocka_unit_test(test_seq_bad_first_frame_resyncs),
        cmocka_unit_test(test_seq_resync_rules),
        cmocka_unit_test(test_seconds_to_ns),
        cmocka_unit_test(test_meas_time_ns),
        cmocka_unit_test(test_sensors_to_input_star_tracker_and_gyro),
        cmocka_unit_test(test_estimate_to_cmd),
        cmocka_unit_test(test_sensors_to_input_magnetometer),
        cmocka_unit_test(test_momentum_to_cmd),
        cmocka_unit_test(test_event_to_msg),
        cmocka_unit_test(test_epoch_update),
        cmocka_unit_test(test_decode),
        cmocka_unit_test(test_command_apply),
        cmocka_unit_test(test_timeouts_check),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
