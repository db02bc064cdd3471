/*
 * fsw_node's wire rules (sil/fsw_node/node_wire.h, node_checks.h;
 * docs/wire-contract.md "Frame acceptance"): the frame sequence dedupe (no
 * signed overflow, no latch on one far frame, replays still duplicates,
 * resynchronisation after K consistent frames), the seconds-to-ns
 * conversion over the whole double range, the real-time epoch, payload
 * decoding and the timeout ranges. Built with the SIL node (host preset),
 * registered from sil/CMakeLists.txt.
 */
#include "test_support.h"

#include <string.h>

#include "node_checks.h"
#include "node_wire.h"

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
        cmocka_unit_test(test_epoch_update),
        cmocka_unit_test(test_decode),
        cmocka_unit_test(test_command_apply),
        cmocka_unit_test(test_timeouts_check),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
