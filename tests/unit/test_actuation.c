/*
 * Actuation stage alone (firmware/src/actuation/actuation.c, saturation.c;
 * aocs/actuation/actuation.h):
 *  - the rows of actuation.def have distinct names; no array selects BODY,
 *    an array WHEELS (a bad array: the array's status);
 *  - BODY: the saturated body torque (within the limits untouched, beyond
 *    them limited, NaN zero), nothing on the wheels;
 *  - WHEELS: u_cmd is what the wheels deliver (sum of -g_i u_s,i), STANDBY
 *    commands no motor torque, the held step reuses the last sample's speeds;
 *  - the limit check's codes.
 */
#include "test_support.h"
#include "wheel_test_support.h"

#include <string.h>

#include "aocs/executive.h"

static void pyramid(aocs_wheels_config_t *w)
{
    test_wheels_pyramid(w);
}

static aocs_exec_config_t config(int wheels)
{
    aocs_exec_config_t cfg;
    aocs_exec_config_default(&cfg);
    cfg.u_max_axis = aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0));
    cfg.u_max_norm = AOCS_R(1.5);
    if (wheels != 0) {
        pyramid(&cfg.wheels);
    }
    return cfg;
}

static void test_rows_and_selection(void **state)
{
    (void)state;
    for (int i = 0; i < (int)AOCS_ACT_COUNT; ++i) {
        const char *name = aocs_act_name((aocs_act_id_t)i);
        assert_true(strlen(name) > 0u);
        assert_string_not_equal(name, "unknown");
        for (int j = 0; j < i; ++j) {
            assert_string_not_equal(name, aocs_act_name((aocs_act_id_t)j));
        }
    }
    assert_string_equal(aocs_act_name(AOCS_ACT_COUNT), "unknown");
    aocs_act_t act;
    aocs_exec_config_t cfg = config(0);
    (void)memset(&act, 0, sizeof(act));
    assert_int_equal(aocs_act_init(&act, &cfg), AOCS_OK);
    assert_int_equal(act.id, AOCS_ACT_BODY);
    assert_int_equal(aocs_act_has_wheels(&act), 0);
    assert_null(aocs_act_wheels(&act));
    cfg = config(1);
    assert_int_equal(aocs_act_init(&act, &cfg), AOCS_OK);
    assert_int_equal(act.id, AOCS_ACT_WHEELS);
    assert_int_equal(aocs_act_has_wheels(&act), 1);
    assert_ptr_equal(aocs_act_wheels(&act), &act.wheels);
    /* the array's horizon is the control period */
    assert_close(act.wheels.cfg.period_s, cfg.period_s, 0.0);
    cfg.wheels.js_kgm2[2] = AOCS_R(-1.0);
    (void)memset(&act, 0, sizeof(act));
    assert_int_equal(aocs_act_init(&act, &cfg), AOCS_ERR_WHEEL_INERTIA_NOT_POSITIVE);
    assert_int_equal(aocs_act_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_act_init(&act, NULL), AOCS_ERR_NULL_ARG);
}

static void test_body_path(void **state)
{
    (void)state;
    aocs_act_t act;
    aocs_exec_config_t cfg = config(0);
    aocs_exec_output_t out;
    real_t omega[AOCS_WHEELS_MAX] = {AOCS_R(0.0)};
    int sat = 0;
    (void)memset(&act, 0, sizeof(act));
    assert_int_equal(aocs_act_init(&act, &cfg), AOCS_OK);
    (void)memset(&out, 0, sizeof(out));
    const aocs_vec3_t small = aocs_vec3_make(AOCS_R(0.1), AOCS_R(-0.2), AOCS_R(0.3));
    aocs_act_step(&act, 0, small, omega, aocs_vec3_zero(), &out, &sat);
    assert_memory_equal(&out.u_cmd, &small, sizeof(small));
    assert_int_equal(sat, 0);
    aocs_act_step(&act, 0, aocs_vec3_make(AOCS_R(5.0), AOCS_R(-0.2), AOCS_R(0.3)), omega, aocs_vec3_zero(), &out,
                  &sat);
    assert_int_equal(sat, 1);
    assert_true(out.u_cmd.v[0] <= AOCS_R(1.0));
    assert_true(aocs_vec3_norm(out.u_cmd) <= AOCS_R(1.5));
    aocs_act_step(&act, 0, aocs_vec3_make((real_t)NAN, AOCS_R(0.0), AOCS_R(0.0)), omega, aocs_vec3_zero(), &out,
                  &sat);
    assert_int_equal(sat, 1);
    assert_vec3_close(out.u_cmd, aocs_vec3_zero(), 0.0);
    for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
        assert_close(out.wheels.u_s_nm[i], 0.0, 0.0);
    }
    /* NULL limits: zero */
    assert_vec3_close(aocs_act_saturate(NULL, small, &sat), aocs_vec3_zero(), 0.0);
}

/* aocs_act_check_sample: the tachometers against the array's range on the wheel path, nothing to check on the
 * body path; a missing stage or a missing sample is AOCS_ERR_NULL_ARG on either path. */
static void test_check_sample(void **state)
{
    (void)state;
    real_t omega[AOCS_WHEELS_MAX] = {AOCS_R(10.0), AOCS_R(-20.0), AOCS_R(5.0), AOCS_R(0.0), AOCS_R(0.0),
                                     AOCS_R(0.0)};
    for (int wheels = 0; wheels < 2; ++wheels) {
        aocs_act_t act;
        aocs_exec_config_t cfg = config(wheels);
        (void)memset(&act, 0, sizeof(act));
        assert_int_equal(aocs_act_init(&act, &cfg), AOCS_OK);
        assert_int_equal(aocs_act_check_sample(&act, omega), AOCS_OK);
        assert_int_equal(aocs_act_check_sample(&act, NULL), AOCS_ERR_NULL_ARG);
        assert_int_equal(aocs_act_check_sample(NULL, omega), AOCS_ERR_NULL_ARG);
    }
    {
        aocs_act_t act;
        aocs_exec_config_t cfg = config(1);
        (void)memset(&act, 0, sizeof(act));
        assert_int_equal(aocs_act_init(&act, &cfg), AOCS_OK);
        /* far past its speed limit, beyond the range a tachometer can read */
        omega[1] = AOCS_R(1.01) * AOCS_WHEEL_SPEED_RANGE_FACTOR * cfg.wheels.omega_max_radps[1];
        assert_int_equal(aocs_act_check_sample(&act, omega), AOCS_ERR_WHEEL_SPEED_RANGE);
    }
}

static void test_wheel_path(void **state)
{
    (void)state;
    aocs_act_t act;
    aocs_exec_config_t cfg = config(1);
    aocs_exec_output_t out;
    real_t omega[AOCS_WHEELS_MAX] = {AOCS_R(10.0), AOCS_R(-20.0), AOCS_R(5.0), AOCS_R(0.0), AOCS_R(0.0),
                                     AOCS_R(0.0)};
    int sat = 0;
    (void)memset(&act, 0, sizeof(act));
    assert_int_equal(aocs_act_init(&act, &cfg), AOCS_OK);
    (void)memset(&out, 0, sizeof(out));
    aocs_act_step(&act, 0, aocs_vec3_make(AOCS_R(0.05), AOCS_R(-0.02), AOCS_R(0.01)), omega,
                  aocs_vec3_make(AOCS_R(1e-3), AOCS_R(0.0), AOCS_R(0.0)), &out, &sat);
    assert_int_equal(out.wheels_status, AOCS_OK);
    {
        /* u_cmd is what the wheels deliver: -sum g_i (u_s,i - friction_i) ... as the array reports it */
        assert_memory_equal(&out.u_cmd, &out.wheels.u_body_B_nm, sizeof(out.u_cmd));
        assert_vec3_close(out.u_cmd, aocs_vec3_make(AOCS_R(0.05), AOCS_R(-0.02), AOCS_R(0.01)), TOL_LOOSE);
    }
    assert_true(aocs_vec3_norm(out.momentum.h_total_B_Nms) > AOCS_R(0.0));
    for (uint32_t i = 0u; i < 4u; ++i) {
        assert_close(act.wheel_speed_last[i], omega[i], 0.0);
    }
    /* STANDBY: no motor torque at all */
    aocs_act_step(&act, 1, aocs_vec3_zero(), omega, aocs_vec3_zero(), &out, &sat);
    for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
        assert_close(out.wheels.u_s_nm[i], 0.0, 0.0);
    }
    /* held: the last sample's speeds */
    {
        aocs_exec_output_t held;
        (void)memset(&held, 0, sizeof(held));
        aocs_act_step_held(&act, 0, aocs_vec3_make(AOCS_R(0.05), AOCS_R(-0.02), AOCS_R(0.01)), &held, &sat);
        aocs_act_step(&act, 0, aocs_vec3_make(AOCS_R(0.05), AOCS_R(-0.02), AOCS_R(0.01)), omega, aocs_vec3_zero(),
                      &out, &sat);
        assert_memory_equal(&held.wheels, &out.wheels, sizeof(out.wheels));
    }
    /* a torque beyond the wheels: scaled, flagged */
    aocs_act_step(&act, 0, aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(0.0)), omega, aocs_vec3_zero(), &out,
                  &sat);
    assert_int_equal(sat, 1);
    /* non-finite tachometer: zero wheel command and a status */
    omega[1] = (real_t)NAN;
    aocs_act_step(&act, 0, aocs_vec3_make(AOCS_R(0.05), AOCS_R(0.0), AOCS_R(0.0)), omega, aocs_vec3_zero(), &out,
                  &sat);
    assert_int_not_equal(out.wheels_status, AOCS_OK);
    assert_vec3_close(out.u_cmd, aocs_vec3_zero(), 0.0);
}

/* the output guard of the wheel path (docs/spec.md 5.3.3), the independent check after the allocation: a
   motor command beyond its limit (here the limit of wheel 0 corrupted to NaN after init, which the allocation
   cannot meet) replaces the WHOLE allocation by zero, the null-space and friction torques too, and says so */
static void test_the_wheel_output_guard_zeroes_the_whole_allocation(void **state)
{
    (void)state;
    aocs_act_t act;
    aocs_exec_config_t cfg = config(1);
    aocs_exec_output_t out;
    real_t omega[AOCS_WHEELS_MAX] = {AOCS_R(30.0), AOCS_R(-20.0), AOCS_R(5.0), AOCS_R(-10.0), AOCS_R(0.0),
                                     AOCS_R(0.0)};
    int sat = 0;
    for (uint32_t i = 0u; i < 4u; ++i) {
        cfg.wheels.viscous_nms[i] = AOCS_R(1e-5);
        cfg.wheels.coulomb_nm[i] = AOCS_R(1e-3);
    }
    cfg.wheels.null_gain_per_s = AOCS_R(0.005);
    (void)memset(&act, 0, sizeof(act));
    assert_int_equal(aocs_act_init(&act, &cfg), AOCS_OK);
    (void)memset(&out, 0, sizeof(out));
    const aocs_vec3_t uc = aocs_vec3_make(AOCS_R(0.05), AOCS_R(-0.02), AOCS_R(0.01));
    /* healthy: friction and null-space torques on every wheel */
    aocs_act_step(&act, 0, uc, omega, aocs_vec3_zero(), &out, &sat);
    assert_int_equal(out.wheels_status, AOCS_OK);
    for (uint32_t i = 0u; i < 4u; ++i) {
        assert_true(fabs((double)out.wheels.null_nm[i]) > 1e-4);
        assert_true(fabs((double)out.wheels.friction_nm[i]) > 1e-4);
    }
    /* corrupted: the guard trips */
    act.wheels.cfg.u_max_nm[0] = (real_t)NAN;
    sat = 0;
    aocs_act_step(&act, 0, uc, omega, aocs_vec3_zero(), &out, &sat);
    assert_int_equal(out.wheels_status, AOCS_ERR_WHEEL_CMD_INVALID);
    assert_int_equal(sat, 1);
    for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
        assert_close(out.wheels.u_s_nm[i], 0.0, 0.0);
        assert_close(out.wheels.friction_nm[i], 0.0, 0.0);
        assert_close(out.wheels.null_nm[i], 0.0, 0.0);
    }
    assert_vec3_close(out.wheels.u_body_B_nm, aocs_vec3_zero(), 0.0);
    assert_vec3_close(out.u_cmd, aocs_vec3_zero(), 0.0);
    assert_close(out.wheels.scale, 0.0, 0.0);
    assert_close(out.wheels.null_scale, 0.0, 0.0);
}

static void test_limit_check(void **state)
{
    (void)state;
    aocs_act_limits_t lim = {aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0)), AOCS_R(0.0)};
    assert_int_equal(aocs_act_limits_check(&lim), AOCS_OK);
    lim.u_max_axis.v[1] = AOCS_R(0.0);
    assert_int_equal(aocs_act_limits_check(&lim), AOCS_ERR_SAT_LIMIT_NOT_POSITIVE); /* mixed */
    lim.u_max_axis = aocs_vec3_zero();
    assert_int_equal(aocs_act_limits_check(&lim), AOCS_ERR_SAT_LIMIT_NOT_POSITIVE); /* none set */
    lim.u_max_norm = AOCS_R(2.0);
    assert_int_equal(aocs_act_limits_check(&lim), AOCS_OK);
    lim.u_max_norm = (real_t)NAN;
    assert_int_equal(aocs_act_limits_check(&lim), AOCS_ERR_PARAM_NOT_FINITE);
    lim.u_max_norm = AOCS_R(2.0e9);
    assert_int_equal(aocs_act_limits_check(&lim), AOCS_ERR_SAT_LIMIT_NOT_POSITIVE); /* beyond the range */
    assert_int_equal(aocs_act_limits_check(NULL), AOCS_ERR_NULL_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rows_and_selection),
        cmocka_unit_test(test_body_path),
        cmocka_unit_test(test_check_sample),
        cmocka_unit_test(test_wheel_path),
        cmocka_unit_test(test_limit_check),
        cmocka_unit_test(test_the_wheel_output_guard_zeroes_the_whole_allocation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
