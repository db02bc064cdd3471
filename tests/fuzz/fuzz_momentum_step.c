/*
 * libFuzzer target: the momentum-management stage (momentum/momentum.h, src/momentum/) on a configuration
 * and a sequence of inputs taken from the fuzz bytes, without the executive. A configuration the stage
 * refuses must leave it not initialised (steps refused, output zero). Invariants after every step of an
 * initialised stage (a violation aborts):
 *   - every real of the output finite;
 *   - the step's return is the output's status; not unloading, or an error: every command zero;
 *   - thruster on-times in [0, dt], zero beyond thr_count, none below thr_min_on_s but zero;
 *   - each rod's dipole within its limit (a rounding of the limit allowed);
 *   - magnetorquers: the dipole in B perpendicular to the field (to the precision's rounding);
 *   - the event counter never goes back, and rises only where unloading turns on.
 *
 * Input layout (reads past the end give zeros):
 *   u8 policy (bit0: 0 magnetorquers, 1 thrusters), u8 trigger (bit0), u8 raw (bit0: raw f64 parameters),
 *   then the parameters (fuzz_mom_config), then steps until the end: u8 flags (bit0 enabled, bit1 h valid,
 *   bit2 b valid, bit3 raw f64 values), h[3], b[3] (u16 scaled or raw f64).
 */
#include "fuzz_support.h"

#include "aocs/hal.h"

uint64_t aocs_hal_time_ns(void)
{
    return 0u;
}

uint32_t aocs_hal_cycles(void)
{
    return 0u;
}

void aocs_hal_sleep_until_ns(uint64_t t_ns)
{
    (void)t_ns;
}

#if defined(AOCS_REAL_IS_FLOAT)
#define FUZZ_MOM_TOL 1.0e-3
#else
#define FUZZ_MOM_TOL 1.0e-9
#endif

static void fuzz_mom_config(fuzz_reader_t *r, aocs_mom_config_t *c)
{
    const uint8_t policy = fuzz_u8(r);
    const uint8_t trigger = fuzz_u8(r);
    const int raw = (int)(fuzz_u8(r) & 1u);
    aocs_exec_config_t e;
    aocs_exec_config_default(&e);
    *c = e.momentum;
    c->policy = ((policy & 1u) != 0u) ? (uint32_t)AOCS_MOM_THRUSTERS : (uint32_t)AOCS_MOM_MAGNETORQUERS;
    c->trigger = (uint32_t)(trigger & 1u);
    for (int i = 0; i < 3; ++i) {
        c->h_target_B_Nms.v[i] = fuzz_scaled(r, raw, -5.0, 5.0);
        c->mtq_max_dipole_Am2.v[i] = fuzz_scaled(r, raw, 0.0, 400.0);
        for (int j = 0; j < 3; ++j) {
            c->mtq_axes.m[i][j] = AOCS_R((i == j) ? 1.0 : 0.0) + fuzz_scaled(r, raw, -0.0005, 0.0005);
        }
    }
    c->h_start_Nms = fuzz_scaled(r, raw, 0.0, 20.0);
    c->h_stop_Nms = fuzz_scaled(r, raw, 0.0, 20.0);
    c->k_mtq_per_s = fuzz_scaled(r, raw, 0.0, 1.0);
    c->dump_torque_Nm = fuzz_scaled(r, raw, 0.0, 5.0);
    c->thr_count = (uint32_t)(fuzz_u8(r) % 14u);
    c->thr_thrust_N = fuzz_scaled(r, raw, 0.0, 20.0);
    c->thr_min_on_s = fuzz_scaled(r, raw, 0.0, 0.05);
    c->thr_quantum_s = fuzz_scaled(r, raw, 0.0, 0.01);
    for (uint32_t i = 0u; i < AOCS_MOM_THRUSTERS_MAX; ++i) {
        c->thr_arm_x_m[i] = fuzz_scaled(r, raw, -2.0, 2.0);
        c->thr_arm_y_m[i] = fuzz_scaled(r, raw, -2.0, 2.0);
        c->thr_arm_z_m[i] = fuzz_scaled(r, raw, -2.0, 2.0);
    }
}

static void mom_fail(const char *what)
{
    (void)fprintf(stderr, "fuzz invariant violated: %s\n", what);
    abort();
}

static void mom_check_output(const aocs_mom_t *m, const aocs_mom_output_t *o, aocs_status_t st, real_t dt,
                              aocs_vec3_t b, int b_used)
{
    const aocs_mom_config_t *c = &m->cfg;
    int any = 0;
    if (st != o->status) {
        mom_fail("step return is not the output status");
    }
    if ((aocs_vec3_is_finite(o->dipole_Am2) == 0) || (aocs_vec3_is_finite(o->u_unload_B_Nm) == 0) ||
        (aocs_vec3_is_finite(o->h_wheels_B_Nms) == 0) || (aocs_vec3_is_finite(o->dh_B_Nms) == 0)) {
        mom_fail("a real of the output not finite");
    }
    for (uint32_t i = 0u; i < AOCS_MOM_THRUSTERS_MAX; ++i) {
        const real_t t = o->thruster_on_s[i];
        if (!AOCS_IS_FINITE(t) || (t < AOCS_R(0.0)) || (t > dt) || ((i >= c->thr_count) && (t > AOCS_R(0.0))) ||
            ((t > AOCS_R(0.0)) && (t < c->thr_min_on_s))) {
            mom_fail("a thruster on-time outside [0, dt], beyond thr_count or below the minimum pulse");
        }
        any |= (t > AOCS_R(0.0)) ? 1 : 0;
    }
    for (int i = 0; i < 3; ++i) {
        const double lim = (double)c->mtq_max_dipole_Am2.v[i];
        if (fabs((double)o->dipole_Am2.v[i]) > lim * (1.0 + FUZZ_MOM_TOL)) {
            mom_fail("a rod's dipole beyond its limit");
        }
        /* exact zero is the contract: anything of either sign counts */
        any |= ((o->dipole_Am2.v[i] > AOCS_R(0.0)) || (o->dipole_Am2.v[i] < AOCS_R(0.0))) ? 1 : 0;
        any |= ((o->u_unload_B_Nm.v[i] > AOCS_R(0.0)) || (o->u_unload_B_Nm.v[i] < AOCS_R(0.0))) ? 1 : 0;
    }
    if (((o->unloading == 0) || (st != AOCS_OK)) && (any != 0)) {
        mom_fail("a command while not unloading or after an error");
    }
    if ((c->policy == (uint32_t)AOCS_MOM_MAGNETORQUERS) && (b_used != 0)) {
        /* the angle between the dipole in B and the field, each scaled by its largest component first (the
         * fuzzer gives values from 1e-300 to 1e300: their squares would underflow or overflow) */
        double mb[3] = {0.0, 0.0, 0.0};
        double bs[3];
        double mmax = 0.0;
        double bmax = 0.0;
        double dot = 0.0;
        double nm = 0.0;
        double nb = 0.0;
        for (int rod = 0; rod < 3; ++rod) {
            for (int j = 0; j < 3; ++j) {
                mb[j] += (double)o->dipole_Am2.v[rod] * (double)c->mtq_axes.m[rod][j];
            }
        }
        for (int j = 0; j < 3; ++j) {
            mmax = (fabs(mb[j]) > mmax) ? fabs(mb[j]) : mmax;
            bmax = (fabs((double)b.v[j]) > bmax) ? fabs((double)b.v[j]) : bmax;
        }
        if ((mmax > 0.0) && (bmax > 0.0)) {
            for (int j = 0; j < 3; ++j) {
                mb[j] /= mmax;
                bs[j] = (double)b.v[j] / bmax;
                dot += mb[j] * bs[j];
                nm += mb[j] * mb[j];
                nb += bs[j] * bs[j];
            }
            if (fabs(dot) > (FUZZ_MOM_TOL * sqrt(nm * nb))) {
                mom_fail("the magnetorquer dipole is not perpendicular to the field");
            }
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_reader_t r = {data, size, 0u};
    aocs_mom_config_t cfg;
    aocs_mom_t m;
    uint32_t events = 0u;
    int was = 0;
    int ops = 0;
    const real_t dt = AOCS_R(0.1);
    fuzz_mom_config(&r, &cfg);
    if (aocs_mom_init(&m, &cfg) != AOCS_OK) {
        aocs_mom_input_t in;
        memset(&in, 0, sizeof(in));
        const aocs_mom_output_t o = aocs_mom_output(&m);
        if ((aocs_mom_step(&m, &in) != AOCS_ERR_NOT_INITIALISED) || (o.unloading != 0) ||
            (aocs_vec3_norm_inf(o.u_unload_B_Nm) > AOCS_R(0.0))) {
            mom_fail("a refused configuration left the stage usable");
        }
        return 0;
    }
    while ((fuzz_more(&r) != 0) && (ops < 4096)) {
        aocs_mom_input_t in;
        const uint8_t flags = fuzz_u8(&r);
        const int raw = (int)((flags >> 3) & 1u);
        aocs_status_t st;
        ++ops;
        memset(&in, 0, sizeof(in));
        in.enabled = (int)(flags & 1u);
        in.h_valid = (int)((flags >> 1) & 1u);
        in.b_valid = (int)((flags >> 2) & 1u);
        in.dt_s = dt;
        for (int i = 0; i < 3; ++i) {
            in.h_wheels_B_Nms.v[i] = fuzz_scaled(&r, raw, -60.0, 60.0);
            in.b_B_T.v[i] = fuzz_scaled(&r, raw, -6e-5, 6e-5);
        }
        st = aocs_mom_step(&m, &in);
        {
            const aocs_mom_output_t o = aocs_mom_output(&m);
            mom_check_output(&m, &o, st, dt, in.b_B_T, (st == AOCS_OK) ? in.b_valid : 0);
            if ((o.n_events < events) || ((o.n_events > events) && !((o.unloading != 0) && (was == 0)))) {
                mom_fail("the event counter went back or rose without an unload starting");
            }
            events = o.n_events;
            was = o.unloading;
        }
    }
    return 0;
}
