/*
 * The executive with a reaction wheel array (executive.h "Reaction wheels",
 * src/actuation/actuation.c): the saturated body torque goes to the wheels, the
 * delivered torque (checked here as -Gs u_s, multiplied out in double) keeps
 * the law's direction, no wheel command exceeds its limit, a failed wheel gets
 * nothing, bad tachometer speeds give a zero command, the array's status codes
 * reach aocs_exec_init, and without an array nothing changes.
 */
#include "test_support.h"
#include "wheel_test_support.h"

#include <string.h>

#include "aocs/executive.h"

#define UMAX TEST_WHEEL_U_MAX_NM

static void pyramid(aocs_wheels_config_t *w)
{
    test_wheels_pyramid(w);
}

static void config(aocs_exec_config_t *cfg, int wheels)
{
    aocs_exec_config_default(cfg);
    cfg->law = AOCS_LAW_QUAT_PD;
    cfg->laws.quat_pd.kp = AOCS_R(4000.0);
    cfg->laws.quat_pd.kd = AOCS_R(8000.0);
    cfg->u_max_axis = aocs_vec3_make(AOCS_R(1e9), AOCS_R(1e9), AOCS_R(1e9));
    /* 1 deg about a skew axis: the law asks for ~ 50 N m, far beyond the wheels */
    cfg->target.qd_DN = aocs_quat_make(AOCS_R(0.005), AOCS_R(-0.006), AOCS_R(0.003),
                                       AOCS_SQRT(AOCS_R(1.0) - AOCS_R(0.000070)));
    if (wheels != 0) {
        pyramid(&cfg->wheels);
    }
}

static aocs_exec_input_t sample(uint32_t tick)
{
    aocs_exec_input_t in;
    (void)memset(&in, 0, sizeof(in));
    in.tick = tick;
    in.t_sensor_ns = 100000000u * (uint64_t)(tick + 1u);
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
    in.q_BN = aocs_quat_identity();
    in.w_BN_B = aocs_vec3_make(AOCS_R(1e-4), AOCS_R(-2e-4), AOCS_R(5e-5));
    return in;
}

static void delivered_d(const aocs_wheels_config_t *w, const aocs_exec_output_t *out, double body[3])
{
    for (int r = 0; r < 3; ++r) {
        body[r] = 0.0;
        for (uint32_t i = 0u; i < w->n; ++i) {
            body[r] -= (double)w->axis_B[i].v[r] * (double)out->wheels.u_s_nm[i];
        }
    }
}

static void test_the_law_torque_is_allocated_and_keeps_its_direction(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t plain;
    aocs_exec_output_t out;
    aocs_exec_input_t in = sample(0u);
    config(&cfg, 0);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    assert_int_equal(aocs_exec_step(&exec, &in, &plain), AOCS_OK);
    config(&cfg, 1);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.wheels_status, AOCS_OK);
    /* the same law output; the wheels scale it down */
    assert_vec3_close(out.u_unsat, plain.u_unsat, 0.0);
    assert_true(out.wheels.scale > AOCS_R(0.0) && out.wheels.scale < AOCS_R(0.1));
    assert_int_equal(out.saturated, 1);
    double body[3];
    delivered_d(&cfg.wheels, &out, body);
    double mx = 0.0;
    for (int r = 0; r < 3; ++r) {
        assert_close(out.u_cmd.v[r], body[r], TOL_TIGHT);
        assert_close(out.u_cmd.v[r], (double)out.wheels.scale * (double)plain.u_cmd.v[r], TOL_TIGHT);
    }
    for (int i = 0; i < 4; ++i) {
        mx = fmax(mx, fabs((double)out.wheels.u_s_nm[i]));
    }
    assert_close(mx, UMAX, TOL_TIGHT);
    /* momentum reported: H = J w at rest wheels */
    assert_close(out.momentum.h_total_B_Nms.v[0], 2059.5 * 1e-4, TOL_LOOSE);
    assert_close(out.momentum.speed_margin, 1.0, 0.0);
}

static void test_a_failed_wheel_gets_nothing_and_a_bad_array_is_refused(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_exec_input_t in = sample(0u);
    config(&cfg, 1);
    cfg.wheels.failed_mask = 1u << 3;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_close(out.wheels.u_s_nm[3], 0.0, 0.0);
    double body[3];
    delivered_d(&cfg.wheels, &out, body);
    for (int r = 0; r < 3; ++r) {
        assert_close(out.u_cmd.v[r], body[r], TOL_TIGHT);
    }
    cfg.wheels.failed_mask = 0x3u;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_WHEELS_NOT_SPANNING);
    config(&cfg, 1);
    cfg.wheels.js_kgm2[0] = AOCS_R(-1.0);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_WHEEL_INERTIA_NOT_POSITIVE);
}

static void test_bad_tachometer_speeds_give_a_zero_command(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_exec_input_t in = sample(0u);
    config(&cfg, 1);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    in.wheel_speed_radps[2] = NAN;
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    /* rejected like every invalid input (issue 25: "rejected like other invalid inputs") */
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_NOT_FINITE);
    assert_int_equal(out.counters.invalid, 1u);
    assert_int_equal(out.wheels_status, AOCS_ERR_INPUT_NOT_FINITE);
    assert_vec3_close(out.u_cmd, aocs_vec3_zero(), 0.0);
    for (int i = 0; i < 6; ++i) {
        assert_close(out.wheels.u_s_nm[i], 0.0, 0.0);
    }
}

/* issue 25 item 1: Js = 10, the null-space management on and one frame with a tachometer reading of 1e308
 * gave NaN wheel commands with every status OK */
static void test_a_tachometer_of_1e308_gives_finite_commands_and_says_so(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_exec_input_t in = sample(0u);
    config(&cfg, 1);
    for (int i = 0; i < 4; ++i) {
        cfg.wheels.js_kgm2[i] = AOCS_R(10.0);
    }
    cfg.wheels.null_gain_per_s = AOCS_R(1.0);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    in.wheel_speed_radps[1] = TEST_WHEEL_TACH_HUGE;
    (void)aocs_exec_step(&exec, &in, &out);
    assert_int_equal(out.input_status, AOCS_ERR_WHEEL_SPEED_RANGE);
    assert_int_equal(out.counters.invalid, 1u);
    assert_int_equal(out.law_status, AOCS_OK); /* the law did not run on it */
    assert_int_equal(out.wheels_status, AOCS_ERR_WHEEL_SPEED_RANGE);
    assert_true(aocs_vec3_is_finite(out.u_cmd) != 0);
    for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
        assert_true(isfinite((double)out.wheels.u_s_nm[i]));
        assert_true(AOCS_FABS(out.wheels.u_s_nm[i]) <= ((i < 4u) ? cfg.wheels.u_max_nm[i] : AOCS_R(0.0)));
    }
    assert_true(aocs_vec3_is_finite(out.momentum.h_total_B_Nms) != 0);
}

/* a reading just inside the physical range is a reading: the range is AOCS_WHEEL_SPEED_RANGE_FACTOR Omega_max */
static void test_a_tachometer_at_the_edge_of_its_range_is_accepted(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_exec_input_t in = sample(0u);
    config(&cfg, 1);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    in.wheel_speed_radps[3] = -AOCS_WHEEL_SPEED_RANGE_FACTOR * cfg.wheels.omega_max_radps[3];
    (void)aocs_exec_step(&exec, &in, &out);
    assert_int_equal(out.input_status, AOCS_OK);
    assert_int_equal(out.counters.invalid, 0u);
    in = sample(1u);
    in.wheel_speed_radps[3] = -AOCS_WHEEL_SPEED_RANGE_FACTOR * cfg.wheels.omega_max_radps[3] * AOCS_R(1.001);
    (void)aocs_exec_step(&exec, &in, &out);
    assert_int_equal(out.input_status, AOCS_ERR_WHEEL_SPEED_RANGE);
    assert_int_equal(out.counters.invalid, 1u);
}

static void test_a_wheel_at_its_speed_limit_is_not_driven_further(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_exec_input_t in = sample(0u);
    config(&cfg, 1);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    /* put every wheel at its limit in the direction the command drives it */
    for (uint32_t i = 0u; i < 4u; ++i) {
        in.wheel_speed_radps[i] = (out.wheels.u_s_nm[i] > AOCS_R(0.0)) ? AOCS_R(600.0) : AOCS_R(-600.0);
    }
    in = (aocs_exec_input_t){.tick = 1u, .t_sensor_ns = 200000000u, .valid = in.valid, .q_BN = in.q_BN,
                             .w_BN_B = in.w_BN_B, .wheel_speed_radps = {in.wheel_speed_radps[0],
                             in.wheel_speed_radps[1], in.wheel_speed_radps[2], in.wheel_speed_radps[3], 0, 0}};
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    for (uint32_t i = 0u; i < 4u; ++i) {
        /* u Omega <= 0: only braking torques */
        assert_true(out.wheels.u_s_nm[i] * in.wheel_speed_radps[i] <= AOCS_R(0.0));
    }
    assert_close(out.momentum.speed_margin, 0.0, 0.0);
}

static void test_no_input_holds_through_the_wheels(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_exec_output_t held;
    aocs_exec_input_t in = sample(0u);
    config(&cfg, 1);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(aocs_exec_step_no_input(&exec, &held), AOCS_OK);
    assert_vec3_close(held.u_cmd, out.u_cmd, TOL_TIGHT);
    for (int i = 0; i < 4; ++i) {
        assert_close(held.wheels.u_s_nm[i], out.wheels.u_s_nm[i], TOL_TIGHT);
    }
}

static void test_standby_commands_no_motor_torque_even_with_the_friction_model(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_exec_input_t in = sample(0u);
    config(&cfg, 1);
    for (uint32_t i = 0u; i < 4u; ++i) {
        cfg.wheels.viscous_nms[i] = AOCS_R(1e-5);
        cfg.wheels.coulomb_nm[i] = AOCS_R(2e-3);
        cfg.wheels.coulomb_width_radps[i] = AOCS_R(0.5);
        cfg.wheels.null_speed_radps[i] = AOCS_R(((i % 2u) == 0u) ? 50.0 : -50.0);
        in.wheel_speed_radps[i] = AOCS_R(10.0);
    }
    cfg.wheels.null_gain_per_s = AOCS_R(0.02);
    cfg.target.qd_DN = aocs_quat_identity(); /* a small command (rate damping only): room for the null space */
    /* NOMINAL: the motors get the friction feedforward and the null-space torque on top of the law's */
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
    double fsum = 0.0;
    double nsum = 0.0;
    for (int i = 0; i < 4; ++i) {
        fsum += fabs((double)out.wheels.friction_nm[i]);
        nsum += fabs((double)out.wheels.null_nm[i]);
    }
    assert_true(fsum > 4.0 * 2e-3 * 0.99 && nsum > 0.0);
    /* STANDBY: nothing at all reaches the motors */
    cfg.law = AOCS_LAW_NONE;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_STANDBY);
    assert_int_equal(out.wheels_status, AOCS_OK);
    for (int i = 0; i < 6; ++i) {
        assert_close(out.wheels.u_s_nm[i], 0.0, 0.0);
    }
    /* the model's own codes reach aocs_exec_init */
    config(&cfg, 1);
    cfg.wheels.coulomb_width_radps[2] = AOCS_R(0.0);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_WHEEL_FRICTION_WIDTH_NOT_POSITIVE);
    config(&cfg, 1);
    cfg.wheels.null_gain_per_s = AOCS_R(20.0); /* k_n T = 2 at 0.1 s */
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_WHEEL_NULL_GAIN_INVALID);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_law_torque_is_allocated_and_keeps_its_direction),
        cmocka_unit_test(test_a_failed_wheel_gets_nothing_and_a_bad_array_is_refused),
        cmocka_unit_test(test_bad_tachometer_speeds_give_a_zero_command),
        cmocka_unit_test(test_a_tachometer_of_1e308_gives_finite_commands_and_says_so),
        cmocka_unit_test(test_a_tachometer_at_the_edge_of_its_range_is_accepted),
        cmocka_unit_test(test_a_wheel_at_its_speed_limit_is_not_driven_further),
        cmocka_unit_test(test_no_input_holds_through_the_wheels),
        cmocka_unit_test(test_standby_commands_no_motor_torque_even_with_the_friction_model),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
