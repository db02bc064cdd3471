/*
 * law_io.c: common input validation of the control laws.
 * Proves: a valid input passes; every field of the attitude and orbit inputs
 * is checked for NaN, +Inf and -Inf; dt <= 0 (and non-finite dt) gives
 * AOCS_ERR_DT_INVALID; quaternions off unit norm by more than
 * AOCS_QUAT_UNIT_TOL are rejected while small rounding passes; the documented
 * order of the checks (dt first, then finiteness, then norm) holds; the
 * shared two-gain check rejects NaN/Inf before a gain <= 0; the shared output
 * rule passes u through on success, turns a non-finite u into
 * AOCS_ERR_OUTPUT_NOT_FINITE, keeps an earlier error, and zeroes the output
 * on every error.
 */
#include "law_test_support.h"

static aocs_att_input_t valid_att_input(void)
{
    aocs_att_input_t in;
    /* 0.6^2 + 0.8^2 = 1 exactly in decimal; rounding stays far inside the tolerance */
    in.q_BN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.6), AOCS_R(0.0), AOCS_R(0.8));
    in.w_BN_B = aocs_vec3_make(AOCS_R(0.01), AOCS_R(-0.02), AOCS_R(0.03));
    in.qd_DN = aocs_quat_make(AOCS_R(0.5), AOCS_R(0.5), AOCS_R(0.5), AOCS_R(0.5));
    in.wd_B = aocs_vec3_make(AOCS_R(0.0), AOCS_R(0.001), AOCS_R(0.0));
    in.wd_dot_B = aocs_vec3_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(1e-4));
    in.dt_s = AOCS_R(0.1);
    in.u_max_axis = aocs_vec3_zero();
    in.u_max_norm = AOCS_R(0.0);
    return in;
}

/* field accessors input_field / orbit_input_field: law_test_support.h */

static aocs_orbit_input_t valid_orbit_input(void)
{
    aocs_orbit_input_t in;
    in.vel_mps = aocs_vec3_make(AOCS_R(1.0), AOCS_R(-1.0), AOCS_R(-6.0));
    in.pos_m = aocs_vec3_make(AOCS_R(50.0), AOCS_R(-100.0), AOCS_R(350.0));
    in.dt_s = AOCS_R(0.1);
    return in;
}

static void test_att_valid_passes(void **state)
{
    (void)state;
    aocs_att_input_t in = valid_att_input();
    assert_int_equal(aocs_att_input_check(&in), AOCS_OK);
    /* zero rates and a tiny positive dt are legal */
    in.w_BN_B = aocs_vec3_zero();
    in.wd_B = aocs_vec3_zero();
    in.dt_s = AOCS_R(1e-6);
    assert_int_equal(aocs_att_input_check(&in), AOCS_OK);
}

static void test_att_null(void **state)
{
    (void)state;
    assert_int_equal(aocs_att_input_check(NULL), AOCS_ERR_NULL_ARG);
}

static void test_att_every_field_non_finite(void **state)
{
    (void)state;
    const real_t bad[3] = {(real_t)NAN, (real_t)INFINITY, -(real_t)INFINITY};
    for (int k = 0; k < N_INPUT_FIELDS; ++k) {
        for (int b = 0; b < 3; ++b) {
            aocs_att_input_t in = valid_att_input();
            *input_field(&in, k) = bad[b];
            aocs_status_t expected = (k == N_INPUT_FIELDS - 1) ? AOCS_ERR_DT_INVALID : AOCS_ERR_INPUT_NOT_FINITE;
            if (aocs_att_input_check(&in) != expected) {
                print_error("field %d, bad value %d\n", k, b);
            }
            assert_int_equal(aocs_att_input_check(&in), expected);
        }
    }
}

static void test_att_dt_not_positive(void **state)
{
    (void)state;
    const real_t dts[3] = {AOCS_R(0.0), -AOCS_R(0.0), AOCS_R(-0.1)};
    for (int i = 0; i < 3; ++i) {
        aocs_att_input_t in = valid_att_input();
        in.dt_s = dts[i];
        assert_int_equal(aocs_att_input_check(&in), AOCS_ERR_DT_INVALID);
    }
}

static void test_att_quat_norm(void **state)
{
    (void)state;
    /* scale each quaternion: inside the tolerance passes, outside fails */
    const real_t ok_scale[2] = {AOCS_R(1.0005), AOCS_R(0.9995)};
    const real_t bad_scale[4] = {AOCS_R(1.002), AOCS_R(0.998), AOCS_R(0.0), AOCS_R(2.0)};
    for (int which = 0; which < 2; ++which) {
        for (int i = 0; i < 2; ++i) {
            aocs_att_input_t in = valid_att_input();
            aocs_quat_t *q = (which == 0) ? &in.q_BN : &in.qd_DN;
            for (int j = 0; j < 4; ++j) {
                q->q[j] *= ok_scale[i];
            }
            assert_int_equal(aocs_att_input_check(&in), AOCS_OK);
        }
        for (int i = 0; i < 4; ++i) {
            aocs_att_input_t in = valid_att_input();
            aocs_quat_t *q = (which == 0) ? &in.q_BN : &in.qd_DN;
            for (int j = 0; j < 4; ++j) {
                q->q[j] *= bad_scale[i];
            }
            assert_int_equal(aocs_att_input_check(&in), AOCS_ERR_QUAT_NOT_UNIT);
        }
    }
    /* finite but overflowing norm: still rejected, not accepted as unit */
    aocs_att_input_t in = valid_att_input();
    in.q_BN = aocs_quat_make(AOCS_REAL_MAX, AOCS_REAL_MAX, AOCS_R(0.0), AOCS_R(0.0));
    assert_int_equal(aocs_att_input_check(&in), AOCS_ERR_QUAT_NOT_UNIT);
}

static void test_att_check_order(void **state)
{
    (void)state;
    /* dt first, then finiteness, then norm (law_io.c header) */
    aocs_att_input_t in = valid_att_input();
    in.dt_s = AOCS_R(0.0);
    in.w_BN_B.v[1] = (real_t)NAN;
    in.qd_DN.q[3] = AOCS_R(3.0);
    assert_int_equal(aocs_att_input_check(&in), AOCS_ERR_DT_INVALID);
    in.dt_s = AOCS_R(0.1);
    assert_int_equal(aocs_att_input_check(&in), AOCS_ERR_INPUT_NOT_FINITE);
    in.w_BN_B.v[1] = AOCS_R(0.0);
    assert_int_equal(aocs_att_input_check(&in), AOCS_ERR_QUAT_NOT_UNIT);
}

static void test_orbit(void **state)
{
    (void)state;
    aocs_orbit_input_t in = valid_orbit_input();
    assert_int_equal(aocs_orbit_input_check(&in), AOCS_OK);
    assert_int_equal(aocs_orbit_input_check(NULL), AOCS_ERR_NULL_ARG);
    const real_t bad[3] = {(real_t)NAN, (real_t)INFINITY, -(real_t)INFINITY};
    for (int k = 0; k < N_ORBIT_INPUT_FIELDS; ++k) {
        for (int b = 0; b < 3; ++b) {
            in = valid_orbit_input();
            *orbit_input_field(&in, k) = bad[b];
            aocs_status_t expected = (k == N_ORBIT_INPUT_FIELDS - 1) ? AOCS_ERR_DT_INVALID : AOCS_ERR_INPUT_NOT_FINITE;
            assert_int_equal(aocs_orbit_input_check(&in), expected);
        }
    }
    in = valid_orbit_input();
    in.dt_s = AOCS_R(0.0);
    assert_int_equal(aocs_orbit_input_check(&in), AOCS_ERR_DT_INVALID);
    in.dt_s = AOCS_R(-1.0);
    assert_int_equal(aocs_orbit_input_check(&in), AOCS_ERR_DT_INVALID);
}

/* the gain check and the output rule the laws share (law_io.h) */
static void test_law_check_gains(void **state)
{
    (void)state;
    assert_int_equal(aocs_law_check_gains(AOCS_R(1e-30), AOCS_R(4000.0)), AOCS_OK);
    const real_t not_finite[3] = {(real_t)NAN, (real_t)INFINITY, -(real_t)INFINITY};
    const real_t not_positive[3] = {AOCS_R(0.0), -AOCS_R(0.0), AOCS_R(-2.0)};
    for (int b = 0; b < 3; ++b) {
        assert_int_equal(aocs_law_check_gains(not_finite[b], AOCS_R(1.0)), AOCS_ERR_PARAM_NOT_FINITE);
        assert_int_equal(aocs_law_check_gains(AOCS_R(1.0), not_finite[b]), AOCS_ERR_PARAM_NOT_FINITE);
        assert_int_equal(aocs_law_check_gains(not_positive[b], AOCS_R(1.0)), AOCS_ERR_GAIN_NOT_POSITIVE);
        assert_int_equal(aocs_law_check_gains(AOCS_R(1.0), not_positive[b]), AOCS_ERR_GAIN_NOT_POSITIVE);
        /* finiteness is checked before the sign */
        assert_int_equal(aocs_law_check_gains(not_positive[b], not_finite[b]), AOCS_ERR_PARAM_NOT_FINITE);
    }
}

static void test_law_set_output(void **state)
{
    (void)state;
    const aocs_vec3_t u = aocs_vec3_make(AOCS_R(1.5), AOCS_R(-2.0), AOCS_R(0.25));
    const aocs_vec3_t u_inf = aocs_vec3_make(AOCS_R(1.0), (real_t)INFINITY, AOCS_R(0.0));
    aocs_vec3_t out = aocs_vec3_make(AOCS_R(7.0), AOCS_R(7.0), AOCS_R(7.0));
    /* success: u passed through unchanged */
    assert_int_equal(aocs_law_set_output(AOCS_OK, u, &out), AOCS_OK);
    assert_memory_equal(&out, &u, sizeof u);
    /* a non-finite result under AOCS_OK: its own status and a zero output */
    assert_int_equal(aocs_law_set_output(AOCS_OK, u_inf, &out), AOCS_ERR_OUTPUT_NOT_FINITE);
    assert_vec3_is_zero(out);
    /* an earlier error wins and zeroes the output, whatever u holds */
    out = u;
    assert_int_equal(aocs_law_set_output(AOCS_ERR_QUAT_NOT_UNIT, u, &out), AOCS_ERR_QUAT_NOT_UNIT);
    assert_vec3_is_zero(out);
    out = u;
    assert_int_equal(aocs_law_set_output(AOCS_ERR_DT_INVALID, u_inf, &out), AOCS_ERR_DT_INVALID);
    assert_vec3_is_zero(out);
    /* no output pointer: the status alone */
    assert_int_equal(aocs_law_set_output(AOCS_OK, u, NULL), AOCS_OK);
    assert_int_equal(aocs_law_set_output(AOCS_OK, u_inf, NULL), AOCS_ERR_OUTPUT_NOT_FINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_att_valid_passes),
        cmocka_unit_test(test_att_null),
        cmocka_unit_test(test_att_every_field_non_finite),
        cmocka_unit_test(test_att_dt_not_positive),
        cmocka_unit_test(test_att_quat_norm),
        cmocka_unit_test(test_att_check_order),
        cmocka_unit_test(test_orbit),
        cmocka_unit_test(test_law_check_gains),
        cmocka_unit_test(test_law_set_output),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
