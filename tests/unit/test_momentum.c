/*
 * Momentum-management stage alone (firmware/src/momentum/momentum.c,
 * aocs/momentum/momentum.h): every row of momentum.def has a distinct name
 * and steps; NONE commands nothing; a policy out of range, a stage not
 * initialised and NULL arguments give an error and a zero output.
 */
#include "test_support.h"

#include <string.h>

#include "aocs/executive.h"

static void assert_zero_output(const aocs_mom_output_t *out)
{
    assert_vec3_close(out->dipole_Am2, aocs_vec3_zero(), 0.0);
    assert_vec3_close(out->u_unload_B_Nm, aocs_vec3_zero(), 0.0);
}

static void test_rows_and_none(void **state)
{
    (void)state;
    aocs_wheels_momentum_t h;
    (void)memset(&h, 0, sizeof(h));
    h.h_total_B_Nms = aocs_vec3_make(AOCS_R(5.0), AOCS_R(-3.0), AOCS_R(1.0));
    for (int i = 0; i < (int)AOCS_MOM_COUNT; ++i) {
        const char *name = aocs_mom_name((aocs_mom_id_t)i);
        assert_true(strlen(name) > 0u);
        assert_string_not_equal(name, "unknown");
        for (int j = 0; j < i; ++j) {
            assert_string_not_equal(name, aocs_mom_name((aocs_mom_id_t)j));
        }
    }
    assert_string_equal(aocs_mom_name(AOCS_MOM_NONE), "none");
    assert_string_equal(aocs_mom_name(AOCS_MOM_COUNT), "unknown");
    aocs_mom_t m;
    aocs_mom_config_t cfg = {(uint32_t)AOCS_MOM_NONE};
    aocs_mom_output_t out;
    (void)memset(&m, 0x7f, sizeof(m));
    assert_int_equal(aocs_mom_init(&m, &cfg), AOCS_OK);
    assert_int_equal(aocs_mom_step(&m, &h), AOCS_OK);
    out = aocs_mom_output(&m);
    assert_zero_output(&out);
    assert_int_equal(aocs_mom_step(&m, NULL), AOCS_OK); /* no array: nothing either */
    out = aocs_mom_output(&m);
    assert_zero_output(&out);
    /* the default configuration is NONE */
    aocs_exec_config_t ecfg;
    aocs_exec_config_default(&ecfg);
    assert_int_equal(ecfg.momentum.policy, (uint32_t)AOCS_MOM_NONE);
}

static void test_errors_give_zero(void **state)
{
    (void)state;
    aocs_mom_t m;
    aocs_mom_config_t bad = {(uint32_t)AOCS_MOM_COUNT};
    aocs_mom_output_t out;
    (void)memset(&m, 0x7f, sizeof(m));
    assert_int_equal(aocs_mom_init(&m, &bad), AOCS_ERR_MOMENTUM_POLICY_UNKNOWN);
    assert_int_equal(aocs_mom_step(&m, NULL), AOCS_ERR_NOT_INITIALISED);
    out = aocs_mom_output(&m);
    assert_zero_output(&out);
    assert_int_equal(aocs_mom_init(NULL, &bad), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_mom_init(&m, NULL), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_mom_step(NULL, NULL), AOCS_ERR_NULL_ARG);
    out = aocs_mom_output(NULL);
    assert_zero_output(&out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rows_and_none),
        cmocka_unit_test(test_errors_give_zero),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
