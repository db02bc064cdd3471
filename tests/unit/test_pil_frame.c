/*
 * PIL frame codec (aocs/pil_frame.h) and instruction budget table
 * (aocs/budget.h), on the host in both precisions.
 *
 * Expected bytes are written down from the protocol description (header
 * fields, little-endian integers, IEEE-754 binary64 patterns) and the CRCs
 * come from zlib.crc32 (an implementation independent of the codec);
 * tests/sil/test_pil_frame.py checks the Python codec against the same
 * vectors, so the two ends of the link agree byte for byte.
 */
#include <string.h>

#include "test_support.h"
#include "aocs/budget.h"
#include "aocs/executive.h"
#include "aocs/pil_frame.h"
#include "gains/aocs_gains.h"

/* BYE, seq 7, empty payload: "APIL", version 5, type 8, length 0, seq 7, CRC (zlib) */
static const uint8_t golden_bye[16] = {0x41, 0x50, 0x49, 0x4C, 0x05, 0x08, 0x00, 0x00,
                                       0x07, 0x00, 0x00, 0x00, 0x17, 0x44, 0x7C, 0x14};

/* HELLO seq 0 of target 2, 8-byte reals, shift 7, calib ok 2000/2000, overhead 47 */
static const uint8_t golden_hello[44] = {
    0x41, 0x50, 0x49, 0x4C, 0x05, 0x01, 0x1C, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00,
    0x00, 0x08, 0x00, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0xD0, 0x07,
    0x00, 0x00, 0xD0, 0x07, 0x00, 0x00, 0x2F, 0x00, 0x00, 0x00, 0xE6, 0x9F, 0x3A, 0x44};

/* bit-at-a-time CRC-32/ISO-HDLC, the textbook definition (independent of the table) */
static uint32_t crc_bitwise(const uint8_t *p, size_t n)
{
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; ++i) {
        c ^= p[i];
        for (int k = 0; k < 8; ++k) {
            c = (c & 1u) ? (c >> 1) ^ 0xEDB88320u : (c >> 1);
        }
    }
    return c ^ 0xFFFFFFFFu;
}

/* bit-for-bit equality of two reals (the codec must not change a single bit) */
#define assert_same_real(a, b)                                  \
    do {                                                        \
        const real_t a_ = (a);                                  \
        const real_t b_ = (b);                                  \
        assert_memory_equal(&a_, &b_, sizeof(real_t));          \
    } while (0)

static uint32_t le32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

static uint64_t le64(const uint8_t *p)
{
    uint64_t v = 0;
    for (int i = 7; i >= 0; --i) {
        v = (v << 8) | p[i];
    }
    return v;
}

static void test_crc_known_values(void **state)
{
    (void)state;
    const uint8_t check[] = "123456789";
    uint8_t buf[300];
    assert_int_equal(aocs_pil_crc32(check, 9), 0xCBF43926u); /* the CRC catalogue's check value */
    assert_int_equal(aocs_pil_crc32(check, 0), 0u);
    assert_int_equal(aocs_pil_crc32(NULL, 5), 0u);
    for (size_t i = 0; i < sizeof(buf); ++i) {
        buf[i] = (uint8_t)(i * 37u + 11u);
    }
    for (size_t n = 0; n <= sizeof(buf); n += 7) {
        assert_int_equal(aocs_pil_crc32(buf, (uint32_t)n), crc_bitwise(buf, n));
    }
}

static void test_frame_golden_bytes(void **state)
{
    (void)state;
    uint8_t out[AOCS_PIL_FRAME_MAX];
    uint8_t payload[AOCS_PIL_HELLO_BYTES];
    uint32_t len = 0;
    aocs_pil_hello_t h = {2u, 8u, 7u, 1u, 2000u, 2000u, 47u};
    assert_int_equal(aocs_pil_frame_encode(AOCS_PIL_T_BYE, 7u, NULL, 0u, out, sizeof(out), &len), AOCS_PIL_OK);
    assert_int_equal(len, sizeof(golden_bye));
    assert_memory_equal(out, golden_bye, sizeof(golden_bye));

    assert_int_equal(aocs_pil_hello_encode(&h, payload, sizeof(payload)), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_frame_encode(AOCS_PIL_T_HELLO, 0u, payload, sizeof(payload), out, sizeof(out), &len),
                     AOCS_PIL_OK);
    assert_int_equal(len, sizeof(golden_hello));
    assert_memory_equal(out, golden_hello, sizeof(golden_hello));
}

static void test_frame_check_accepts_and_decodes(void **state)
{
    (void)state;
    aocs_pil_header_t h;
    aocs_pil_hello_t back;
    assert_int_equal(aocs_pil_frame_check(golden_hello, sizeof(golden_hello), &h), AOCS_PIL_OK);
    assert_int_equal(h.version, AOCS_PIL_VERSION);
    assert_int_equal(h.type, AOCS_PIL_T_HELLO);
    assert_int_equal(h.length, AOCS_PIL_HELLO_BYTES);
    assert_int_equal(h.seq, 0);
    assert_int_equal(aocs_pil_hello_decode(&golden_hello[AOCS_PIL_HEADER_BYTES], h.length, &back), AOCS_PIL_OK);
    assert_int_equal(back.target, 2);
    assert_int_equal(back.real_bytes, 8);
    assert_int_equal(back.icount_shift, 7);
    assert_int_equal(back.calib_ok, 1);
    assert_int_equal(back.calib_measured, 2000);
    assert_int_equal(back.calib_expected, 2000);
    assert_int_equal(back.overhead, 47);
}

/* Every single-bit error anywhere in a frame is caught (CRC-32 detects all of them). */
static void test_every_bit_flip_is_rejected(void **state)
{
    (void)state;
    uint8_t f[sizeof(golden_hello)];
    aocs_pil_header_t h;
    for (size_t byte = 0; byte < sizeof(f); ++byte) {
        for (int bit = 0; bit < 8; ++bit) {
            memcpy(f, golden_hello, sizeof(f));
            f[byte] ^= (uint8_t)(1u << bit);
            assert_int_not_equal(aocs_pil_frame_check(f, sizeof(f), &h), AOCS_PIL_OK);
        }
    }
}

static void test_header_errors_are_named(void **state)
{
    (void)state;
    uint8_t f[sizeof(golden_bye)];
    aocs_pil_header_t h;
    memcpy(f, golden_bye, sizeof(f));
    f[0] = 'X';
    assert_int_equal(aocs_pil_header_decode(f, sizeof(f), &h), AOCS_PIL_ERR_MAGIC);
    memcpy(f, golden_bye, sizeof(f));
    f[4] = 4; /* version: the one before the latch valves */
    assert_int_equal(aocs_pil_header_decode(f, sizeof(f), &h), AOCS_PIL_ERR_VERSION);
    memcpy(f, golden_bye, sizeof(f));
    f[6] = 0x01; /* length 1025 */
    f[7] = 0x04;
    assert_int_equal(aocs_pil_header_decode(f, sizeof(f), &h), AOCS_PIL_ERR_LENGTH);
    memcpy(f, golden_bye, sizeof(f));
    assert_int_equal(aocs_pil_header_decode(f, AOCS_PIL_HEADER_BYTES - 1u, &h), AOCS_PIL_ERR_LENGTH);
    /* a whole frame shorter or longer than its header says */
    assert_int_equal(aocs_pil_frame_check(golden_bye, sizeof(golden_bye) - 1u, &h), AOCS_PIL_ERR_LENGTH);
    assert_int_equal(aocs_pil_frame_check(golden_hello, sizeof(golden_hello) + 0u, NULL), AOCS_PIL_ERR_NULL_ARG);
    /* the CRC itself corrupted: CRC error, not a header error */
    memcpy(f, golden_bye, sizeof(f));
    f[15] ^= 0x80;
    assert_int_equal(aocs_pil_frame_check(f, sizeof(f), &h), AOCS_PIL_ERR_CRC);
    assert_string_equal(aocs_pil_err_name(AOCS_PIL_ERR_CRC), "AOCS_PIL_ERR_CRC");
    assert_string_equal(aocs_pil_err_name(AOCS_PIL_ERR_COUNT), "AOCS_PIL_ERR_UNKNOWN");
}

static void test_encode_limits(void **state)
{
    (void)state;
    static uint8_t big[AOCS_PIL_PAYLOAD_MAX + 1u];
    uint8_t out[AOCS_PIL_FRAME_MAX + 8u];
    uint32_t len = 0;
    assert_int_equal(aocs_pil_frame_encode(AOCS_PIL_T_CONFIG, 1u, big, AOCS_PIL_PAYLOAD_MAX + 1u, out, sizeof(out),
                                           &len),
                     AOCS_PIL_ERR_LENGTH);
    assert_int_equal(aocs_pil_frame_encode(AOCS_PIL_T_CONFIG, 1u, big, AOCS_PIL_PAYLOAD_MAX, out, sizeof(out), &len),
                     AOCS_PIL_OK);
    assert_int_equal(len, AOCS_PIL_FRAME_MAX);
    assert_int_equal(aocs_pil_frame_encode(AOCS_PIL_T_CONFIG, 1u, big, 10u, out, 25u, &len), AOCS_PIL_ERR_BUFFER);
    assert_int_equal(aocs_pil_frame_encode(AOCS_PIL_T_CONFIG, 1u, NULL, 10u, out, sizeof(out), &len),
                     AOCS_PIL_ERR_NULL_ARG);
}

static aocs_exec_input_t sample_input(void)
{
    aocs_exec_input_t in;
    memset(&in, 0, sizeof(in));
    in.tick = 0x01020304u;
    in.t_sensor_ns = 0x1122334455667788ull;
    in.valid = 3u;
    in.q_BN = aocs_quat_make(AOCS_R(1.0), AOCS_R(-2.0), AOCS_R(0.5), AOCS_R(0.0));
    in.w_BN_B = aocs_vec3_make(AOCS_R(0.25), AOCS_R(-0.125), AOCS_R(4.0));
    in.pos_m = aocs_vec3_make(AOCS_R(1.0), AOCS_R(2.0), AOCS_R(3.0));
    in.vel_mps = aocs_vec3_make(AOCS_R(-1.0), AOCS_R(-2.0), AOCS_R(-3.0));
    return in;
}

/* Byte positions of the STEP payload, from the layout of pil_frame.h. */
static void test_step_layout(void **state)
{
    (void)state;
    uint8_t p[AOCS_PIL_STEP_BYTES];
    aocs_exec_input_t in = sample_input();
    assert_int_equal(aocs_pil_step_encode(&in, p, sizeof(p)), AOCS_PIL_OK);
    assert_int_equal(p[0], 0x04); /* tick, little-endian */
    assert_int_equal(p[3], 0x01);
    assert_int_equal(le64(&p[4]), 0x1122334455667788ull);
    assert_int_equal(p[12], 3);
    assert_int_equal(le64(&p[16]), 0x3FF0000000000000ull);  /* q1 = 1.0 */
    assert_int_equal(le64(&p[24]), 0xC000000000000000ull);  /* q2 = -2.0 */
    assert_int_equal(le64(&p[32]), 0x3FE0000000000000ull);  /* q3 = 0.5 */
    assert_int_equal(le64(&p[40]), 0x0000000000000000ull);  /* q4 = 0 */
    assert_int_equal(le64(&p[48]), 0x3FD0000000000000ull);  /* w1 = 0.25 */
    assert_int_equal(le64(&p[112]), 0xC008000000000000ull); /* vel3 = -3.0 (last field) */
    assert_int_equal(aocs_pil_step_encode(&in, p, sizeof(p) - 1u), AOCS_PIL_ERR_BUFFER);
}

static void test_step_round_trip_and_sizes(void **state)
{
    (void)state;
    uint8_t p[AOCS_PIL_STEP_BYTES + 1u];
    aocs_exec_input_t in = sample_input();
    aocs_exec_input_t back;
    in.w_BN_B.v[1] = (real_t)NAN; /* passed through unchecked, as the SIL node does */
    in.pos_m.v[2] = (real_t)INFINITY;
    assert_int_equal(aocs_pil_step_encode(&in, p, sizeof(p)), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_step_decode(p, AOCS_PIL_STEP_BYTES, &back), AOCS_PIL_OK);
    assert_int_equal(back.tick, in.tick);
    assert_true(back.t_sensor_ns == in.t_sensor_ns);
    assert_int_equal(back.valid, in.valid);
    assert_memory_equal(&back.q_BN, &in.q_BN, sizeof(in.q_BN));
    assert_true(isnan(back.w_BN_B.v[1]));
    assert_same_real(back.w_BN_B.v[0], in.w_BN_B.v[0]);
    assert_true(isinf(back.pos_m.v[2]) && (back.pos_m.v[2] > 0));
    assert_memory_equal(&back.vel_mps, &in.vel_mps, sizeof(in.vel_mps));
    /* one byte missing or one too many: refused, output untouched */
    memset(&back, 0, sizeof(back));
    assert_int_equal(aocs_pil_step_decode(p, AOCS_PIL_STEP_BYTES - 1u, &back), AOCS_PIL_ERR_PAYLOAD);
    assert_int_equal(aocs_pil_step_decode(p, AOCS_PIL_STEP_BYTES + 1u, &back), AOCS_PIL_ERR_PAYLOAD);
    assert_int_equal(back.tick, 0);
}

/* A binary64 on the wire becomes real_t exactly as (real_t) of the double (the node's conversion). */
static void test_decode_rounds_like_a_cast(void **state)
{
    (void)state;
    uint8_t p[AOCS_PIL_STEP_BYTES];
    aocs_exec_input_t in;
    const double third = 1.0 / 3.0;
    uint64_t bits;
    memset(p, 0, sizeof(p));
    memcpy(&bits, &third, sizeof(bits));
    for (int i = 0; i < 8; ++i) {
        p[16 + i] = (uint8_t)(bits >> (8 * i));
    }
    assert_int_equal(aocs_pil_step_decode(p, sizeof(p), &in), AOCS_PIL_OK);
    assert_same_real(in.q_BN.q[0], (real_t)third);
}

static void test_reply_select_ack_bye_error_round_trip(void **state)
{
    (void)state;
    uint8_t p[AOCS_PIL_STEP_REPLY_BYTES];
    aocs_pil_step_reply_t r;
    aocs_pil_step_reply_t rb;
    aocs_pil_select_t s;
    aocs_pil_select_t sb;
    aocs_pil_ack_t a;
    aocs_pil_ack_t ab;
    aocs_pil_bye_t b = {1800u, 600u, 1925u, 2u};
    aocs_pil_bye_t bb;
    aocs_pil_error_t e = {AOCS_PIL_ERR_CRC, 4u, 99u, 120u};
    aocs_pil_error_t eb;

    memset(&r, 0, sizeof(r));
    r.tick = 42u;
    r.step_status = AOCS_OK;
    r.law = AOCS_LAW_MRP_SAT_LINEAR;
    r.mode = AOCS_EXEC_MODE_SAFE;
    r.law_status = AOCS_ERR_CRP_SINGULAR;
    r.input_status = AOCS_ERR_INPUT_NOT_FINITE;
    r.u_cmd = aocs_vec3_make(AOCS_R(0.5), AOCS_R(-0.25), AOCS_R(0.125));
    r.u_unsat = aocs_vec3_make(AOCS_R(8.0), AOCS_R(-16.0), AOCS_R(0.0));
    r.saturated = 1u;
    r.overrun = 1u;
    r.exact = 1u;
    r.instructions = 1916u;
    r.law_instructions = 1244u;
    r.budget = 3000u;
    r.counters.steps = 1u;
    r.counters.invalid = 2u;
    r.counters.stale = 3u;
    r.counters.missing = 4u;
    r.counters.law_error = 5u;
    r.counters.overrun = 6u;
    r.counters.mode_transitions = 7u;
    r.counters.saturated = 8u;
    r.counters.select_accepted = 9u;
    r.counters.select_rejected = 10u;
    r.pil_overruns = 11u;
    r.exec_law = AOCS_LAW_ORBIT_LQR;
    r.exec_mode = AOCS_EXEC_MODE_NOMINAL;
    assert_int_equal(aocs_pil_step_reply_encode(&r, p, sizeof(p)), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_step_reply_decode(p, sizeof(p), &rb), AOCS_PIL_OK);
    assert_int_equal(rb.tick, 42);
    assert_int_equal(rb.step_status, AOCS_OK);
    assert_int_equal(rb.law, AOCS_LAW_MRP_SAT_LINEAR);
    assert_int_equal(rb.mode, AOCS_EXEC_MODE_SAFE);
    assert_int_equal(rb.law_status, AOCS_ERR_CRP_SINGULAR);
    assert_int_equal(rb.input_status, AOCS_ERR_INPUT_NOT_FINITE);
    assert_memory_equal(&rb.u_cmd, &r.u_cmd, sizeof(r.u_cmd));
    assert_memory_equal(&rb.u_unsat, &r.u_unsat, sizeof(r.u_unsat));
    assert_int_equal(rb.saturated, 1);
    assert_int_equal(rb.overrun, 1);
    assert_int_equal(rb.exact, 1);
    assert_int_equal(rb.instructions, 1916);
    assert_int_equal(rb.law_instructions, 1244);
    assert_int_equal(rb.budget, 3000);
    assert_int_equal(rb.counters.steps, 1);
    assert_int_equal(rb.counters.invalid, 2);
    assert_int_equal(rb.counters.stale, 3);
    assert_int_equal(rb.counters.missing, 4);
    assert_int_equal(rb.counters.law_error, 5);
    assert_int_equal(rb.counters.overrun, 6);
    assert_int_equal(rb.counters.mode_transitions, 7);
    assert_int_equal(rb.counters.saturated, 8);
    assert_int_equal(rb.counters.select_accepted, 9);
    assert_int_equal(rb.counters.select_rejected, 10);
    assert_true(rb.counters.step_time_max_ns == 0u); /* not on the wire */
    assert_int_equal(rb.pil_overruns, 11);
    assert_int_equal(rb.exec_law, AOCS_LAW_ORBIT_LQR);
    assert_int_equal(rb.exec_mode, AOCS_EXEC_MODE_NOMINAL);
    assert_int_equal(aocs_pil_step_reply_decode(p, sizeof(p) - 4u, &rb), AOCS_PIL_ERR_PAYLOAD);

    memset(&s, 0, sizeof(s));
    s.law = AOCS_LAW_QUAT_PD;
    s.has_target = 1u;
    s.target.qd_DN = aocs_quat_make(AOCS_R(0.5), AOCS_R(0.5), AOCS_R(0.5), AOCS_R(0.5));
    s.target.wd_B = aocs_vec3_make(AOCS_R(0.0), AOCS_R(-0.001), AOCS_R(0.0));
    assert_int_equal(aocs_pil_select_encode(&s, p, AOCS_PIL_SELECT_BYTES), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_select_decode(p, AOCS_PIL_SELECT_BYTES, &sb), AOCS_PIL_OK);
    assert_memory_equal(&sb, &s, sizeof(s));

    memset(&a, 0, sizeof(a));
    a.pil_err = AOCS_PIL_ERR_FIELD;
    a.status = AOCS_ERR_GAIN_TABLE_WRONG_LAW;
    a.field = 26u;
    a.exec_law = AOCS_LAW_NONE;
    a.exec_mode = AOCS_EXEC_MODE_STANDBY;
    a.select_accepted = 3u;
    a.select_rejected = 0xFFFFFFFFu;
    a.budget = 4000u;
    assert_int_equal(aocs_pil_ack_encode(&a, p, AOCS_PIL_ACK_BYTES), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_ack_decode(p, AOCS_PIL_ACK_BYTES, &ab), AOCS_PIL_OK);
    assert_memory_equal(&ab, &a, sizeof(a));

    assert_int_equal(aocs_pil_bye_encode(&b, p, AOCS_PIL_BYE_REPLY_BYTES), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_bye_decode(p, AOCS_PIL_BYE_REPLY_BYTES, &bb), AOCS_PIL_OK);
    assert_memory_equal(&bb, &b, sizeof(b));

    assert_int_equal(aocs_pil_error_encode(&e, p, AOCS_PIL_ERROR_BYTES), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_error_decode(p, AOCS_PIL_ERROR_BYTES, &eb), AOCS_PIL_OK);
    assert_memory_equal(&eb, &e, sizeof(e));
    assert_int_equal(aocs_pil_error_decode(p, AOCS_PIL_ERROR_BYTES + 1u, &eb), AOCS_PIL_ERR_PAYLOAD);
}

/* negative values survive the int32 round trip (two's complement on the wire) */
static void test_negative_int32(void **state)
{
    (void)state;
    uint8_t p[AOCS_PIL_ACK_BYTES];
    aocs_pil_ack_t a;
    aocs_pil_ack_t ab;
    memset(&a, 0, sizeof(a));
    a.exec_law = (aocs_law_id_t)-1;
    a.status = (aocs_status_t)INT32_MIN;
    assert_int_equal(aocs_pil_ack_encode(&a, p, sizeof(p)), AOCS_PIL_OK);
    assert_int_equal(p[12], 0xFF);
    assert_int_equal(p[15], 0xFF);
    assert_int_equal(p[7], 0x80);
    assert_int_equal(aocs_pil_ack_decode(p, sizeof(p), &ab), AOCS_PIL_OK);
    assert_int_equal((int)ab.exec_law, -1);
    assert_int_equal((int32_t)ab.status, INT32_MIN);
}

/*
 * The rows' wire description (AOCS_PIL_WIRE_<KIND>: what the registry JSON tells the Python codec) adds up to
 * the size each payload's encoder writes and its decoder takes (AOCS_PIL_<NAME>_BYTES, checked by the round
 * trips above); tests/python/aocs_pil/test_frame.py checks each row's place against the C decoder.
 */
static uint32_t wire_bytes(const char *wire, uint32_t count)
{
    return count * (((strcmp(wire, "u64") == 0) || (strcmp(wire, "f64") == 0)) ? 8u : 4u);
}

#define ROW_BYTES(NAME, KIND, MEMBER) +wire_bytes(AOCS_PIL_WIRE_##KIND)
#define CHECK_PAYLOAD_BYTES(NAME, FN, TYPE, ROWS, BYTES) assert_int_equal(0u ROWS(ROW_BYTES), BYTES);

static void test_rows_add_up_to_the_payload_sizes(void **state)
{
    (void)state;
    assert_int_equal(0u AOCS_PIL_COUNTER_ROWS(ROW_BYTES), 4u * AOCS_PIL_COUNTERS);
    AOCS_PIL_PAYLOAD_ROWS(CHECK_PAYLOAD_BYTES)
    assert_int_equal(AOCS_PIL_HELLO_BYTES, 28u); /* the wire: a size changes only with AOCS_PIL_VERSION */
    assert_int_equal(AOCS_PIL_STEP_BYTES, 256u);
    assert_int_equal(AOCS_PIL_STEP_REPLY_BYTES, 736u);
    assert_int_equal(AOCS_PIL_SELECT_BYTES, 64u);
    assert_int_equal(AOCS_PIL_ACK_BYTES, 36u);
    assert_int_equal(AOCS_PIL_BYE_REPLY_BYTES, 16u);
    assert_int_equal(AOCS_PIL_ERROR_BYTES, 16u);
}

/* ---- CONFIG field list ---- */
static void test_config_fields_apply(void **state)
{
    (void)state;
    uint8_t p[AOCS_PIL_PAYLOAD_MAX];
    uint32_t pos = 0;
    aocs_exec_config_t cfg;
    aocs_exec_config_t def;
    uint64_t budget = 0;
    uint32_t field = 99;
    aocs_status_t st = AOCS_ERR_NULL_ARG;
    const real_t period = AOCS_R(0.01);
    const real_t q[4] = {AOCS_R(0.0), AOCS_R(0.6), AOCS_R(0.0), AOCS_R(0.8)};
    const real_t lim[3] = {AOCS_R(0.5), AOCS_R(0.6), AOCS_R(0.7)};
    const real_t j[9] = {AOCS_R(42.0), AOCS_R(1.8), AOCS_R(-1.5), AOCS_R(1.8), AOCS_R(25.0),
                         AOCS_R(-1.2), AOCS_R(-1.5), AOCS_R(-1.2), AOCS_R(61.8)};
    const real_t kp = AOCS_R(4000.0);
    const real_t rate[3] = {AOCS_R(0.0), AOCS_R(-7.292115e-5), AOCS_R(0.0)};
    assert_int_equal(aocs_pil_config_put_u64(p, sizeof(p), &pos, AOCS_PIL_CFG_LAW, (uint64_t)AOCS_LAW_SMC),
                     AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &pos, AOCS_PIL_CFG_PERIOD_S, &period, 1u), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &pos, AOCS_PIL_CFG_TARGET_Q, q, 4u), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &pos, AOCS_PIL_CFG_U_MAX_AXIS, lim, 3u), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &pos, AOCS_PIL_CFG_INERTIA, j, 9u), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &pos, AOCS_PIL_CFG_QUAT_PD_KP, &kp, 1u), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &pos, AOCS_PIL_CFG_TARGET_ROTATION_RATE, rate, 3u),
                     AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_put_u64(p, sizeof(p), &pos, AOCS_PIL_CFG_RECOVER_GOOD_SAMPLES, 7u),
                     AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_put_u64(p, sizeof(p), &pos, AOCS_PIL_CFG_BUDGET_INSTR, 12345u), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_put_name(p, sizeof(p), &pos, AOCS_PIL_CFG_LQR_QUAT_TABLE, "lqr_quat_strong"),
                     AOCS_PIL_OK);
    /* entry sizes: 2 + 8 per value, 2 + length for a name */
    assert_int_equal(pos, 10u + 10u + 34u + 26u + 74u + 10u + 26u + 10u + 10u + 17u);

    aocs_exec_config_default(&cfg);
    aocs_exec_config_default(&def);
    assert_int_equal(aocs_pil_config_decode(p, pos, &cfg, &budget, &field, &st), AOCS_PIL_OK);
    assert_int_equal(field, 0);
    assert_int_equal(st, AOCS_OK);
    assert_int_equal(cfg.law, AOCS_LAW_SMC);
    assert_same_real(cfg.period_s, period);
    assert_memory_equal(&cfg.target.qd_DN, q, sizeof(q));
    assert_memory_equal(&cfg.u_max_axis, lim, sizeof(lim));
    assert_same_real(cfg.laws.smc.inertia.m[0][1], AOCS_R(1.8));
    assert_same_real(cfg.laws.smc.inertia.m[2][2], AOCS_R(61.8));
    assert_same_real(cfg.laws.smc.inertia.m[1][2], AOCS_R(-1.2));
    assert_same_real(cfg.laws.quat_pd.kp, kp);
    assert_same_real(cfg.target_rotation_rate_D.v[1], rate[1]);
    assert_int_equal(cfg.recover_good_samples, 7);
    assert_true(budget == 12345u);
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 6; ++c) {
            assert_same_real(cfg.laws.lqr_quat.k[r][c], aocs_gains_lqr_quat_strong_K[r][c]);
        }
    }
    /* untouched fields keep their defaults */
    assert_same_real(cfg.k_safe, def.k_safe);
    assert_int_equal(cfg.missing_max_periods, def.missing_max_periods);
    assert_memory_equal(&cfg.laws.mrp_sat, &def.laws.mrp_sat, sizeof(def.laws.mrp_sat));
    /* and the executive accepts the result (smc needs its gains too) */
    cfg.laws.smc.lambda = aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0));
    cfg.laws.smc.g = aocs_vec3_make(AOCS_R(0.05), AOCS_R(0.05), AOCS_R(0.05));
    cfg.laws.smc.eps = aocs_vec3_make(AOCS_R(0.02), AOCS_R(0.02), AOCS_R(0.02));
    {
        static aocs_exec_t exec;
        assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    }
}

/* The wheel array's CONFIG fields: the array-wide ones and the per-wheel ones (id 100 + 8 i + field) reach
 * their members, wheel by wheel, and the executive accepts the array they describe. */
static void test_config_wheel_fields_apply(void **state)
{
    (void)state;
    uint8_t p[AOCS_PIL_PAYLOAD_MAX];
    uint32_t pos = 0;
    aocs_exec_config_t cfg;
    uint64_t budget = 0;
    uint32_t field = 99;
    aocs_status_t st = AOCS_ERR_NULL_ARG;
    const real_t gain = AOCS_R(0.02);
    const double beta = acos(1.0 / sqrt(3.0));
    assert_int_equal(aocs_pil_config_put_u64(p, sizeof(p), &pos, AOCS_PIL_CFG_LAW, (uint64_t)AOCS_LAW_QUAT_PD),
                     AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_put_u64(p, sizeof(p), &pos, AOCS_PIL_CFG_WHEELS_COUNT, 4u), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_put_u64(p, sizeof(p), &pos, AOCS_PIL_CFG_WHEELS_FAILED_MASK, 2u), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &pos, AOCS_PIL_CFG_WHEELS_NULL_GAIN, &gain, 1u),
                     AOCS_PIL_OK);
    for (uint32_t i = 0u; i < 4u; ++i) {
        const double az = 0.5 * 3.14159265358979323846 * (double)i;
        const real_t axis[3] = {(real_t)cos(beta), (real_t)(sin(beta) * cos(az)), (real_t)(sin(beta) * sin(az))};
        /* every per-wheel value distinct: wheel i, field f is 1 + 10 i + f (inside every rule) */
        const uint32_t id0 = AOCS_PIL_CFG_WHEEL_BASE + (i * AOCS_PIL_WHEEL_STRIDE);
        assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &pos, (aocs_pil_cfg_field_t)id0, axis, 3u),
                         AOCS_PIL_OK);
        for (uint32_t f = 1u; f < AOCS_PIL_WHEEL_STRIDE; ++f) {
            real_t v = (real_t)(1.0 + 10.0 * (double)i + (double)f);
            if (f == 4u || f == 5u) {
                v = (real_t)(1e-5 * (double)v); /* viscous, Coulomb: small against the motor limit */
            }
            if (f == 1u) {
                v = (real_t)(1e-2 * (double)v); /* spin inertia: inside its range [1e-7, 10] kg m^2 */
            }
            if (f == 2u) {
                v = AOCS_R(0.25);
            }
            if (f == 3u) {
                v = AOCS_R(600.0);
            }
            assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &pos, (aocs_pil_cfg_field_t)(id0 + f), &v, 1u),
                             AOCS_PIL_OK);
        }
    }
    aocs_exec_config_default(&cfg);
    assert_int_equal(aocs_pil_config_decode(p, pos, &cfg, &budget, &field, &st), AOCS_PIL_OK);
    assert_int_equal(field, 0);
    assert_int_equal(cfg.wheels.n, 4);
    assert_int_equal(cfg.wheels.failed_mask, 2);
    assert_same_real(cfg.wheels.null_gain_per_s, gain);
    for (uint32_t i = 0u; i < 4u; ++i) {
        assert_same_real(cfg.wheels.axis_B[i].v[0], (real_t)cos(beta));
        assert_same_real(cfg.wheels.js_kgm2[i], (real_t)(1e-2 * (double)(real_t)(2.0 + 10.0 * (double)i)));
        assert_same_real(cfg.wheels.u_max_nm[i], AOCS_R(0.25));
        assert_same_real(cfg.wheels.omega_max_radps[i], AOCS_R(600.0));
        assert_same_real(cfg.wheels.viscous_nms[i], (real_t)(1e-5 * (5.0 + 10.0 * (double)i)));
        assert_same_real(cfg.wheels.coulomb_nm[i], (real_t)(1e-5 * (6.0 + 10.0 * (double)i)));
        assert_same_real(cfg.wheels.coulomb_width_radps[i], (real_t)(7.0 + 10.0 * (double)i));
        assert_same_real(cfg.wheels.null_speed_radps[i], (real_t)(8.0 + 10.0 * (double)i));
    }
    /* wheels 4 and 5 untouched (defaults) */
    assert_same_real(cfg.wheels.js_kgm2[4], AOCS_R(0.0));
    assert_same_real(cfg.wheels.coulomb_width_radps[5], AOCS_R(0.1));
    /* the inertia (field 15) also gives the array's momentum, as in fsw_node */
    assert_memory_equal(&cfg.wheels.inertia_B_kgm2, &cfg.laws.smc.inertia, sizeof(cfg.wheels.inertia_B_kgm2));
    /* the executive accepts the array (quat_pd gains and a limit added) */
    cfg.laws.quat_pd.kp = AOCS_R(4000.0);
    cfg.laws.quat_pd.kd = AOCS_R(8000.0);
    cfg.u_max_axis = aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0));
    cfg.laws.smc.inertia = aocs_mat3_diag(aocs_vec3_make(AOCS_R(2059.5), AOCS_R(5954.2), AOCS_R(5974.3)));
    cfg.wheels.inertia_B_kgm2 = cfg.laws.smc.inertia;
    {
        static aocs_exec_t exec;
        assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
        assert_int_equal(exec.act.wheels.n_healthy, 3);
    }
    /* a per-wheel field with the wrong count, beyond the last wheel, or between the families: refused */
    {
        const real_t two[2] = {AOCS_R(1.0), AOCS_R(2.0)};
        const real_t one = AOCS_R(1.0);
        uint32_t q = 0;
        assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &q, (aocs_pil_cfg_field_t)(AOCS_PIL_CFG_WHEEL_BASE + 9u),
                                                   two, 2u), AOCS_PIL_OK); /* wheel 1's js takes one value */
        assert_int_equal(aocs_pil_config_decode(p, q, &cfg, &budget, &field, &st), AOCS_PIL_ERR_FIELD);
        assert_int_equal(field, AOCS_PIL_CFG_WHEEL_BASE + 9u);
        q = 0;
        assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &q, (aocs_pil_cfg_field_t)148u, &one, 1u),
                         AOCS_PIL_OK);
        assert_int_equal(aocs_pil_config_decode(p, q, &cfg, &budget, &field, &st), AOCS_PIL_ERR_FIELD);
        assert_int_equal(field, 148);
        q = 0;
        assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &q, (aocs_pil_cfg_field_t)99u, &one, 1u),
                         AOCS_PIL_OK);
        assert_int_equal(aocs_pil_config_decode(p, q, &cfg, &budget, &field, &st), AOCS_PIL_ERR_FIELD);
        q = 0;
        assert_int_equal(aocs_pil_config_put_u64(p, sizeof(p), &q, AOCS_PIL_CFG_WHEELS_COUNT, 1ull << 33), AOCS_PIL_OK);
        assert_int_equal(aocs_pil_config_decode(p, q, &cfg, &budget, &field, &st), AOCS_PIL_ERR_FIELD);
    }
}

/* The tachometers ride in the STEP frame, the allocation in the reply, bit for bit. */
static void test_step_and_reply_carry_the_wheels(void **state)
{
    (void)state;
    uint8_t p[AOCS_PIL_STEP_REPLY_BYTES];
    aocs_exec_input_t in = sample_input();
    aocs_exec_input_t back;
    aocs_pil_step_reply_t r;
    aocs_pil_step_reply_t rb;
    for (int i = 0; i < 6; ++i) {
        in.wheel_speed_radps[i] = (real_t)(-300.5 + 111.25 * (double)i);
    }
    in.wheel_speed_radps[5] = (real_t)NAN; /* an unmeasured wheel stays NaN */
    assert_int_equal(aocs_pil_step_encode(&in, p, AOCS_PIL_STEP_BYTES), AOCS_PIL_OK);
    assert_int_equal(le64(&p[120]), 0xC072C80000000000ull); /* -300.5: the first tachometer after vel */
    assert_int_equal(aocs_pil_step_decode(p, AOCS_PIL_STEP_BYTES, &back), AOCS_PIL_OK);
    assert_memory_equal(back.wheel_speed_radps, in.wheel_speed_radps, 5u * sizeof(real_t));
    assert_true(isnan(back.wheel_speed_radps[5]));

    memset(&r, 0, sizeof(r));
    for (int i = 0; i < 6; ++i) {
        r.u_wheels_nm[i] = (real_t)(0.015625 * (double)(i + 1) * ((i % 2 == 0) ? 1.0 : -1.0));
    }
    r.wheel_scale = AOCS_R(0.75);
    r.wheel_limited = 0x0201u;
    r.wheels_status = AOCS_ERR_INPUT_NOT_FINITE;
    r.h_total_B_Nms = aocs_vec3_make(AOCS_R(1.5), AOCS_R(-2.5), AOCS_R(0.125));
    r.speed_margin = AOCS_R(0.5);
    assert_int_equal(aocs_pil_step_reply_encode(&r, p, sizeof(p)), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_step_reply_decode(p, sizeof(p), &rb), AOCS_PIL_OK);
    assert_memory_equal(rb.u_wheels_nm, r.u_wheels_nm, sizeof(r.u_wheels_nm));
    assert_same_real(rb.wheel_scale, r.wheel_scale);
    assert_int_equal(rb.wheel_limited, 0x0201u);
    assert_int_equal(rb.wheels_status, AOCS_ERR_INPUT_NOT_FINITE);
    assert_memory_equal(&rb.h_total_B_Nms, &r.h_total_B_Nms, sizeof(r.h_total_B_Nms));
    assert_same_real(rb.speed_margin, r.speed_margin);
    /* the wheel part follows the 148 bytes of the version 1 reply */
    assert_int_equal(le64(&p[148]), 0x3F90000000000000ull); /* u_wheels[0] = 0.015625 */
}

/* Version 3: the star tracker and the gyro ride in the STEP frame after the tachometers, the estimate in the
 * reply after the wheel array, bit for bit. */
static void test_step_and_reply_carry_the_star_tracker_gyro_and_estimate(void **state)
{
    (void)state;
    uint8_t p[AOCS_PIL_STEP_REPLY_BYTES];
    aocs_exec_input_t in = sample_input();
    aocs_exec_input_t back;
    aocs_pil_step_reply_t r;
    aocs_pil_step_reply_t rb;
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE | AOCS_EXEC_VALID_ST | AOCS_EXEC_VALID_GYRO;
    in.st_q_SN = aocs_quat_make(AOCS_R(0.5), AOCS_R(-0.5), AOCS_R(0.5), AOCS_R(-0.5));
    in.st_t_meas_ns = 0x8877665544332211ull;
    in.gyro_w_B = aocs_vec3_make(AOCS_R(0.0078125), AOCS_R(-0.25), (real_t)NAN);
    assert_int_equal(aocs_pil_step_encode(&in, p, AOCS_PIL_STEP_BYTES), AOCS_PIL_OK);
    assert_int_equal(p[12], 0x1B);                          /* ATT | RATE | ST | GYRO */
    assert_int_equal(le64(&p[168]), 0x3FE0000000000000ull); /* st_q[0] = 0.5: after the 168 bytes of version 2 */
    assert_int_equal(le64(&p[192]), 0xBFE0000000000000ull); /* st_q[3] = -0.5 */
    assert_int_equal(le64(&p[200]), 0x8877665544332211ull); /* st_t_meas_ns */
    assert_int_equal(le64(&p[208]), 0x3F80000000000000ull); /* gyro_w[0] = 2^-7 */
    assert_int_equal(aocs_pil_step_decode(p, AOCS_PIL_STEP_BYTES, &back), AOCS_PIL_OK);
    assert_int_equal(back.valid, in.valid);
    assert_memory_equal(&back.st_q_SN, &in.st_q_SN, sizeof(in.st_q_SN));
    assert_true(back.st_t_meas_ns == in.st_t_meas_ns);
    assert_same_real(back.gyro_w_B.v[1], in.gyro_w_B.v[1]);
    assert_true(isnan(back.gyro_w_B.v[2])); /* passed through unchecked, as the SIL node does */

    memset(&r, 0, sizeof(r));
    r.estimator = 1u;
    r.estimate.status = AOCS_ERR_INPUT_NOT_FINITE;
    r.estimate.q_BN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(-0.75), AOCS_R(0.5));
    r.estimate.w_BN_B = aocs_vec3_make(AOCS_R(0.001953125), AOCS_R(-0.5), AOCS_R(3.0));
    r.estimate.bias_B_radps = aocs_vec3_make(AOCS_R(-0.0009765625), AOCS_R(0.0), AOCS_R(0.25));
    for (uint32_t i = 0u; i < AOCS_EST_P_UPPER_COUNT; ++i) {
        r.estimate.p_upper[i] = (real_t)(0.0625 * (double)(i + 1u));
    }
    r.estimate.valid = AOCS_EXEC_VALID_ATT; /* not on the wire */
    r.estimate.st_status = AOCS_ERR_QUAT_NOT_UNIT;
    r.estimate.n_st_used = 0x80000001u;
    r.estimate.n_st_gated = 2u;
    r.estimate.n_st_hostile = 3u;
    r.estimate.n_restarts = 4u;
    assert_int_equal(aocs_pil_step_reply_encode(&r, p, sizeof(p)), AOCS_PIL_OK);
    assert_int_equal(le32(&p[244]), 1u);                    /* estimator: after the 244 bytes of version 2 */
    assert_int_equal(le32(&p[248]), (uint32_t)AOCS_ERR_INPUT_NOT_FINITE);
    assert_int_equal(le64(&p[268]), 0xBFE8000000000000ull); /* q_est[2] = -0.75 */
    assert_int_equal(le64(&p[332]), 0x3FB0000000000000ull); /* est_p[0] = 0.0625 */
    assert_int_equal(le32(&p[500]), (uint32_t)AOCS_ERR_QUAT_NOT_UNIT);
    assert_int_equal(le32(&p[504]), 0x80000001u);
    assert_int_equal(le32(&p[516]), 4u);                    /* n_est_restarts: the last field */
    assert_int_equal(aocs_pil_step_reply_decode(p, sizeof(p), &rb), AOCS_PIL_OK);
    assert_int_equal(rb.estimator, 1u);
    assert_int_equal(rb.estimate.status, AOCS_ERR_INPUT_NOT_FINITE);
    assert_memory_equal(&rb.estimate.q_BN, &r.estimate.q_BN, sizeof(r.estimate.q_BN));
    assert_memory_equal(&rb.estimate.w_BN_B, &r.estimate.w_BN_B, sizeof(r.estimate.w_BN_B));
    assert_memory_equal(&rb.estimate.bias_B_radps, &r.estimate.bias_B_radps, sizeof(r.estimate.bias_B_radps));
    assert_memory_equal(rb.estimate.p_upper, r.estimate.p_upper, sizeof(r.estimate.p_upper));
    assert_int_equal(rb.estimate.valid, 0u);                /* a member not on the wire decodes as 0 */
    assert_int_equal(rb.estimate.st_status, AOCS_ERR_QUAT_NOT_UNIT);
    assert_int_equal(rb.estimate.n_st_used, 0x80000001u);
    assert_int_equal(rb.estimate.n_st_gated, 2u);
    assert_int_equal(rb.estimate.n_st_hostile, 3u);
    assert_int_equal(rb.estimate.n_restarts, 4u);
}

/* Version 4: the magnetometer rides in the STEP frame after the gyro, the momentum stage in the reply after the
 * estimate, bit for bit. */
static void test_step_and_reply_carry_the_magnetometer_and_momentum(void **state)
{
    (void)state;
    uint8_t p[AOCS_PIL_STEP_REPLY_BYTES];
    aocs_exec_input_t in = sample_input();
    aocs_exec_input_t back;
    aocs_pil_step_reply_t r;
    aocs_pil_step_reply_t rb;
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_MAG;
    in.mag_B_T = aocs_vec3_make(AOCS_R(0.0009765625), AOCS_R(-0.5), (real_t)NAN);
    assert_int_equal(aocs_pil_step_encode(&in, p, AOCS_PIL_STEP_BYTES), AOCS_PIL_OK);
    assert_int_equal(p[12], 0x21);                          /* ATT | MAG */
    assert_int_equal(le64(&p[232]), 0x3F50000000000000ull); /* mag_b_t[0] = 2^-10: after the 232 bytes of version 3 */
    assert_int_equal(le64(&p[240]), 0xBFE0000000000000ull); /* mag_b_t[1] = -0.5 */
    assert_int_equal(aocs_pil_step_decode(p, AOCS_PIL_STEP_BYTES, &back), AOCS_PIL_OK);
    assert_int_equal(back.valid, in.valid);
    assert_same_real(back.mag_B_T.v[0], in.mag_B_T.v[0]);
    assert_true(isnan(back.mag_B_T.v[2])); /* passed through unchecked, as the SIL node does */

    memset(&r, 0, sizeof(r));
    r.mom_policy = 2u;
    r.n_thrusters = 12u;
    r.unloading = 1u;
    r.mom.status = AOCS_ERR_INPUT_MISSING;
    for (uint32_t i = 0u; i < AOCS_MOM_THRUSTERS_MAX; ++i) {
        r.mom.thruster_on_s[i] = (real_t)(0.0078125 * (double)(i + 1u));
    }
    r.mom.dipole_Am2 = aocs_vec3_make(AOCS_R(1.5), AOCS_R(-2.5), AOCS_R(0.25));
    r.mom.u_unload_B_Nm = aocs_vec3_make(AOCS_R(-0.125), AOCS_R(0.0), AOCS_R(0.5));
    r.mom.h_wheels_B_Nms = aocs_vec3_make(AOCS_R(10.0), AOCS_R(-2.0), AOCS_R(0.5));
    r.mom.dh_B_Nms = aocs_vec3_make(AOCS_R(9.0), AOCS_R(-2.0), AOCS_R(0.5));
    r.mom.unloading = 1;
    r.mom.n_events = 0x80000003u;
    r.mom.latch_closed_mask = 2u;
    assert_int_equal(aocs_pil_step_reply_encode(&r, p, sizeof(p)), AOCS_PIL_OK);
    assert_int_equal(le32(&p[520]), 2u);                    /* mom_policy: after the 520 bytes of version 3 */
    assert_int_equal(le32(&p[524]), (uint32_t)AOCS_ERR_INPUT_MISSING);
    assert_int_equal(le32(&p[528]), 12u);
    assert_int_equal(le64(&p[532]), 0x3F80000000000000ull); /* thruster_on_s[0] = 2^-7 */
    assert_int_equal(le64(&p[628]), 0x3FF8000000000000ull); /* dipole_am2[0] = 1.5, after 12 on-times */
    assert_int_equal(le64(&p[652]), 0xBFC0000000000000ull); /* u_unload[0] = -0.125 */
    assert_int_equal(le64(&p[676]), 0x4024000000000000ull); /* h_wheels[0] = 10 */
    assert_int_equal(le64(&p[700]), 0x4022000000000000ull); /* dh[0] = 9 */
    assert_int_equal(le32(&p[724]), 1u);                    /* unloading */
    assert_int_equal(le32(&p[728]), 0x80000003u);           /* n_unload_events: the last of version 4 */
    assert_int_equal(le32(&p[732]), 2u);                    /* thruster_latch_closed (version 5): the last field */
    assert_int_equal(aocs_pil_step_reply_decode(p, sizeof(p), &rb), AOCS_PIL_OK);
    assert_int_equal(rb.mom_policy, 2u);
    assert_int_equal(rb.n_thrusters, 12u);
    assert_int_equal(rb.unloading, 1u);
    assert_int_equal(rb.mom.status, AOCS_ERR_INPUT_MISSING);
    assert_memory_equal(rb.mom.thruster_on_s, r.mom.thruster_on_s, sizeof(r.mom.thruster_on_s));
    assert_memory_equal(&rb.mom.dipole_Am2, &r.mom.dipole_Am2, sizeof(r.mom.dipole_Am2));
    assert_memory_equal(&rb.mom.u_unload_B_Nm, &r.mom.u_unload_B_Nm, sizeof(r.mom.u_unload_B_Nm));
    assert_memory_equal(&rb.mom.dh_B_Nms, &r.mom.dh_B_Nms, sizeof(r.mom.dh_B_Nms));
    assert_int_equal(rb.mom.unloading, 0);                  /* a member not on the wire decodes as 0 */
    assert_int_equal(rb.mom.n_events, 0x80000003u);
    assert_int_equal(rb.mom.latch_closed_mask, 2u);
}

static void test_config_field_errors(void **state)
{
    (void)state;
    uint8_t p[64];
    uint32_t pos;
    aocs_exec_config_t cfg;
    uint64_t budget = 0;
    uint32_t field = 0;
    aocs_status_t st = AOCS_OK;
    const real_t two[2] = {AOCS_R(1.0), AOCS_R(2.0)};

    /* unknown field id */
    aocs_exec_config_default(&cfg);
    p[0] = 200u;
    p[1] = 1u;
    memset(&p[2], 0, 8);
    assert_int_equal(aocs_pil_config_decode(p, 10u, &cfg, &budget, &field, &st), AOCS_PIL_ERR_FIELD);
    assert_int_equal(field, 200);
    /* a known field with the wrong count */
    pos = 0;
    assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &pos, AOCS_PIL_CFG_U_MAX_AXIS, two, 2u), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_decode(p, pos, &cfg, &budget, &field, &st), AOCS_PIL_ERR_FIELD);
    assert_int_equal(field, AOCS_PIL_CFG_U_MAX_AXIS);
    /* truncated entry */
    pos = 0;
    assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &pos, AOCS_PIL_CFG_K_SAFE, two, 1u), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_decode(p, pos - 1u, &cfg, &budget, &field, &st), AOCS_PIL_ERR_PAYLOAD);
    assert_int_equal(aocs_pil_config_decode(p, 1u, &cfg, &budget, &field, &st), AOCS_PIL_ERR_PAYLOAD);
    /* law id out of range */
    pos = 0;
    assert_int_equal(aocs_pil_config_put_u64(p, sizeof(p), &pos, AOCS_PIL_CFG_LAW, (uint64_t)AOCS_LAW_COUNT),
                     AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_decode(p, pos, &cfg, &budget, &field, &st), AOCS_PIL_ERR_FIELD);
    assert_int_equal(field, AOCS_PIL_CFG_LAW);
    /* a count beyond uint32 */
    pos = 0;
    assert_int_equal(aocs_pil_config_put_u64(p, sizeof(p), &pos, AOCS_PIL_CFG_MISSING_MAX_PERIODS, 0x100000000ull),
                     AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_decode(p, pos, &cfg, &budget, &field, &st), AOCS_PIL_ERR_FIELD);
    /* gain tables: unknown name, and a table of another law */
    pos = 0;
    assert_int_equal(aocs_pil_config_put_name(p, sizeof(p), &pos, AOCS_PIL_CFG_HINF_TABLE, "hinf_nope"), AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_decode(p, pos, &cfg, &budget, &field, &st), AOCS_PIL_ERR_FIELD);
    assert_int_equal(field, AOCS_PIL_CFG_HINF_TABLE);
    assert_int_equal(st, AOCS_ERR_GAIN_TABLE_UNKNOWN);
    pos = 0;
    assert_int_equal(aocs_pil_config_put_name(p, sizeof(p), &pos, AOCS_PIL_CFG_ORBIT_TABLE, "lqr_quat_ref"),
                     AOCS_PIL_OK);
    assert_int_equal(aocs_pil_config_decode(p, pos, &cfg, &budget, &field, &st), AOCS_PIL_ERR_FIELD);
    assert_int_equal(st, AOCS_ERR_GAIN_TABLE_WRONG_LAW);
    /* writer limits */
    pos = 0;
    assert_int_equal(aocs_pil_config_put_name(p, sizeof(p), &pos, AOCS_PIL_CFG_HINF_TABLE,
                                              "a_name_of_thirty_two_characters_"),
                     AOCS_PIL_ERR_FIELD);
    assert_int_equal(aocs_pil_config_put_name(p, sizeof(p), &pos, AOCS_PIL_CFG_HINF_TABLE, ""), AOCS_PIL_ERR_FIELD);
    assert_int_equal(aocs_pil_config_put_reals(p, sizeof(p), &pos, AOCS_PIL_CFG_K_SAFE, two, 0u), AOCS_PIL_ERR_FIELD);
    assert_int_equal(aocs_pil_config_put_reals(p, 9u, &pos, AOCS_PIL_CFG_K_SAFE, two, 1u), AOCS_PIL_ERR_BUFFER);
    assert_int_equal(pos, 0);
    /* an empty list is valid: defaults only */
    assert_int_equal(aocs_pil_config_decode(p, 0u, &cfg, &budget, &field, &st), AOCS_PIL_OK);
}

/* ---- instruction budgets ---- */
static void test_budget_table(void **state)
{
    (void)state;
    for (int law = 0; law < (int)AOCS_LAW_COUNT; ++law) {
        for (int t = 0; t < (int)AOCS_BUDGET_TARGET_COUNT; ++t) {
            const uint32_t b = aocs_budget_instructions((aocs_law_id_t)law, (aocs_budget_target_t)t);
            /* a budget exists and fits a 1 kHz loop on the slower core with room to spare */
            assert_true(b > 0u);
            assert_true(b < 168000u / 10u);
        }
    }
    assert_int_equal(aocs_budget_instructions(AOCS_LAW_COUNT, AOCS_BUDGET_TARGET_CORTEX_M7), 0);
    assert_int_equal(aocs_budget_instructions((aocs_law_id_t)-1, AOCS_BUDGET_TARGET_CORTEX_M7), 0);
    assert_int_equal(aocs_budget_instructions(AOCS_LAW_QUAT_PD, AOCS_BUDGET_TARGET_COUNT), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_crc_known_values),
        cmocka_unit_test(test_frame_golden_bytes),
        cmocka_unit_test(test_frame_check_accepts_and_decodes),
        cmocka_unit_test(test_every_bit_flip_is_rejected),
        cmocka_unit_test(test_header_errors_are_named),
        cmocka_unit_test(test_encode_limits),
        cmocka_unit_test(test_step_layout),
        cmocka_unit_test(test_step_round_trip_and_sizes),
        cmocka_unit_test(test_decode_rounds_like_a_cast),
        cmocka_unit_test(test_reply_select_ack_bye_error_round_trip),
        cmocka_unit_test(test_negative_int32),
        cmocka_unit_test(test_rows_add_up_to_the_payload_sizes),
        cmocka_unit_test(test_config_fields_apply),
        cmocka_unit_test(test_config_field_errors),
        cmocka_unit_test(test_config_wheel_fields_apply),
        cmocka_unit_test(test_step_and_reply_carry_the_wheels),
        cmocka_unit_test(test_step_and_reply_carry_the_star_tracker_gyro_and_estimate),
        cmocka_unit_test(test_step_and_reply_carry_the_magnetometer_and_momentum),
        cmocka_unit_test(test_budget_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
