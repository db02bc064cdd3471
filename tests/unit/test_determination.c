/*
 * Attitude-determination stage alone (firmware/src/estimation/determination.c,
 * passthrough.c; aocs/estimation/determination.h):
 *  - every row of determination.def has a distinct non-empty name, inits from
 *    its configuration fields' defaults and resets; an estimator out of range
 *    is AOCS_ERR_ESTIMATOR_UNKNOWN;
 *  - PASSTHROUGH gives the measured q and w bit for bit, the attitude and rate
 *    flags of the sample, and the acceptance's verdict as its status (the
 *    measured values stay: SAFE damps with the rate of a stale sample);
 *  - not initialised / NULL arguments: an error and an unusable output.
 */
#include "test_support.h"

#include <string.h>

#include "aocs/executive.h"

static aocs_exec_input_t sample(void)
{
    aocs_exec_input_t in;
    (void)memset(&in, 0, sizeof(in));
    in.tick = 7u;
    in.t_sensor_ns = 800000000u;
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE | AOCS_EXEC_VALID_ORBIT;
    in.q_BN = aocs_quat_make(AOCS_R(0.1), AOCS_R(-0.2), AOCS_R(0.3), AOCS_SQRT(AOCS_R(1.0) - AOCS_R(0.14)));
    in.w_BN_B = aocs_vec3_make(AOCS_R(1.0e-3), AOCS_R(-2.5e-4), AOCS_R(7.0e-5));
    return in;
}

/* The stage's configuration with every field at its DEFAULT (config_fields.def) and the given estimator. */
static aocs_det_config_t default_config(uint32_t estimator)
{
    aocs_exec_config_t ecfg;
    aocs_exec_config_default(&ecfg);
    ecfg.determination.estimator = estimator;
    return ecfg.determination;
}

static void test_every_row_has_a_name_and_inits(void **state)
{
    (void)state;
    for (int i = 0; i < (int)AOCS_DET_COUNT; ++i) {
        aocs_det_t det;
        /* every estimator inits from its configuration fields' defaults */
        aocs_det_config_t cfg = default_config((uint32_t)i);
        const char *name = aocs_det_name((aocs_det_id_t)i);
        assert_true(strlen(name) > 0u);
        assert_string_not_equal(name, "unknown");
        for (int j = 0; j < i; ++j) {
            assert_string_not_equal(name, aocs_det_name((aocs_det_id_t)j));
        }
        assert_int_equal(aocs_det_init(&det, &cfg), AOCS_OK);
        assert_int_equal((int)det.id, i);
        assert_int_equal(aocs_det_reset(&det), AOCS_OK);
    }
    assert_string_equal(aocs_det_name(AOCS_DET_PASSTHROUGH), "passthrough");
    assert_string_equal(aocs_det_name(AOCS_DET_COUNT), "unknown");
}

static void test_unknown_estimator_is_refused(void **state)
{
    (void)state;
    aocs_det_t det;
    aocs_det_config_t cfg = default_config((uint32_t)AOCS_DET_COUNT);
    aocs_det_output_t out;
    aocs_exec_input_t in = sample();
    assert_int_equal(aocs_det_init(&det, &cfg), AOCS_ERR_ESTIMATOR_UNKNOWN);
    assert_int_equal(det.initialised, 0);
    assert_int_equal(aocs_det_step(&det, &in, AOCS_OK, AOCS_R(0.1), &out), AOCS_ERR_NOT_INITIALISED);
    assert_int_equal(out.status, AOCS_ERR_NOT_INITIALISED);
    assert_int_equal(out.valid, 0u);
    assert_int_equal(aocs_det_reset(&det), AOCS_ERR_NOT_INITIALISED);
    /* the default configuration is the pass-through */
    aocs_exec_config_t ecfg;
    aocs_exec_config_default(&ecfg);
    assert_int_equal(ecfg.determination.estimator, (uint32_t)AOCS_DET_PASSTHROUGH);
}

static void test_passthrough_gives_the_measurement_bit_for_bit(void **state)
{
    (void)state;
    aocs_det_t det;
    aocs_det_config_t cfg = default_config((uint32_t)AOCS_DET_PASSTHROUGH);
    aocs_det_output_t out;
    aocs_exec_input_t in = sample();
    assert_int_equal(aocs_det_init(&det, &cfg), AOCS_OK);
    assert_int_equal(aocs_det_step(&det, &in, AOCS_OK, AOCS_R(0.1), &out), AOCS_OK);
    assert_memory_equal(&out.q_BN, &in.q_BN, sizeof(in.q_BN));
    assert_memory_equal(&out.w_BN_B, &in.w_BN_B, sizeof(in.w_BN_B));
    assert_int_equal(out.valid, AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE); /* no orbit flag: not its estimate */
    assert_int_equal(out.status, AOCS_OK);
    /* a rejected sample: its verdict, the measured values kept */
    in.valid = AOCS_EXEC_VALID_RATE;
    assert_int_equal(aocs_det_step(&det, &in, AOCS_ERR_INPUT_STALE, AOCS_R(0.1), &out), AOCS_ERR_INPUT_STALE);
    assert_int_equal(out.status, AOCS_ERR_INPUT_STALE);
    assert_int_equal(out.valid, AOCS_EXEC_VALID_RATE);
    assert_memory_equal(&out.w_BN_B, &in.w_BN_B, sizeof(in.w_BN_B));
    assert_int_equal(det.states.passthrough.steps, 2u);
    assert_int_equal(aocs_det_reset(&det), AOCS_OK);
    assert_int_equal(det.states.passthrough.steps, 0u);
}

static void test_null_arguments(void **state)
{
    (void)state;
    aocs_det_t det;
    aocs_det_config_t cfg = default_config(0u);
    aocs_det_output_t out;
    aocs_exec_input_t in = sample();
    assert_int_equal(aocs_det_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_det_init(&det, NULL), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_det_init(&det, &cfg), AOCS_OK);
    assert_int_equal(aocs_det_step(&det, NULL, AOCS_OK, AOCS_R(0.1), &out), AOCS_ERR_NULL_ARG);
    assert_int_equal(out.status, AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_det_step(NULL, &in, AOCS_OK, AOCS_R(0.1), &out), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_det_step(&det, &in, AOCS_OK, AOCS_R(0.1), NULL), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_det_reset(NULL), AOCS_ERR_NULL_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_row_has_a_name_and_inits),
        cmocka_unit_test(test_unknown_estimator_is_refused),
        cmocka_unit_test(test_passthrough_gives_the_measurement_bit_for_bit),
        cmocka_unit_test(test_null_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
