/*
 * libFuzzer target: the fault-management stage (fdir/fdir.h, src/fdir/) on a configuration and a sequence of
 * steps taken from the fuzz bytes, without the executive, over the reference pyramid of four wheels (or three
 * healthy: wheel 3 declared failed). A configuration the stage refuses must leave it not initialised (steps do
 * nothing). Invariants after every step (a violation aborts):
 *   - every event of the log finite (value, threshold), its id a row of events.def, severity and unit kind the
 *     row's, a wheel event's unit a configured wheel;
 *   - the event sequence monotonic: seq_last never goes back, and the events read after the last seen come
 *     in order with seq + 1 each (none lost at 32 per step at most);
 *   - a wheel's friction model rescaled only with a wheel_friction_high event of that wheel (then or before),
 *     and the array still initialised (checked with the isolation below);
 *   - isolation only of a configured, healthy wheel: the failed mask only grows, by bits below n; the array
 *     stays initialised with at least 3 healthy wheels (never fewer than 3 used): a refused isolation
 *     latches SAFE, and an isolation-refused event comes with it;
 *   - disabled: no event at all;
 *   - the bias re-inflation asked on a step only with a gyro_st_inconsistent event of that step;
 *   - the tracker's noise scale finite, within [1, fdir.st_noise_scale_max] (1 when that is 0), changed only on
 *     a step with a st_noise_rescaled event (and then st_rescaled set);
 *   - the switch to the gyroless estimator (go_gyroless) asked only when the estimator can, on the step of an
 *     estimator_gyroless event and of a gyro_excluded one (docs/spec.md 5.6.12);
 *   - the momentum test (a thruster momentum stage, irassi_day's twelve thrusters, dumping on a 20 / 3 N m s
 *     hysteresis, stepped before the stage on the wheels' momentum): a thruster event names a configured
 *     thruster; the excluded thrusters only grow, each new one with an unload_actuator_switched event naming
 *     it in that step, at least one thruster left per signed axis (the stage stays initialised and its next
 *     step never fires an excluded thruster);
 *   - the latch valves (the couples' two thrusters on branches A and B, mom.thr_latch_b_mask 0xAAA): a valve
 *     closes only on a step with a thruster_branch_closed event naming that branch (its value) and opens only
 *     with a thruster_branch_reopened one, never both closed, and no thruster on a closed branch has an
 *     on-time after fault management nor in the next step.
 *
 * Input layout (reads past the end give zeros):
 *   u8 setup (bit0 three healthy wheels, bit1 disabled, bit2 raw f64 parameters, bit3 an estimator that can
 *   fly without the gyro), the parameters
 *   (wheel_residual_frac, st_chi2, st_frozen_rate, gyro_sat as u16 scaled or raw f64; wheel_persist, st_persist,
 *   st_restore, st_frozen_samples, gyro_stuck_samples, link_lost_periods as u8; gyro_bias_chi2 scaled or raw,
 *   gyro_bias_persist u8, mom_residual_nm scaled or raw, mom_window u8, mom_persist u8, wheel_friction_window
 *   u8, wheel_friction_excess scaled or raw), then steps until the end:
 *   u8 flags (bit0 have sample, bit1 input ok, bit2 st valid, bit3 gyro valid, bit4 raw f64 values, bit5-6 mode,
 *   bit7 an innovation was tested), u8 missing, 4 x (speed, command), chi2, gyro[3], q[4] (u16 scaled or raw),
 *   u8 filter flags (bit0 the sample applied, bit1 a restart), bias[3], P bias diagonal[3], sigma_u, the
 *   whitened innovation z[3] (u16 scaled within +-30, or raw).
 */
#include "fuzz_support.h"

#include "aocs/fdir/fdir.h"

static void fuzz_fdir_fail(const char *what)
{
    (void)fprintf(stderr, "fuzz_fdir_step invariant: %s\n", what);
    abort();
}

static int fuzz_fdir_raised(const aocs_evlog_t *log, uint32_t since, aocs_evt_id_t id, uint64_t t_ns);

/* the tracker's noise scale (5.15.3): finite, within [1, max], changed only with its event of the step */
static void fuzz_fdir_check_noise(const aocs_fdir_t *f, real_t scale_before, uint32_t events_before, uint64_t t_ns)
{
    if (f->initialised != 0) {
        const real_t s = f->st.noise_scale;
        const real_t hi = (f->cfg.st_noise_scale_max > AOCS_R(1.0)) ? f->cfg.st_noise_scale_max : AOCS_R(1.0);
        if (!AOCS_IS_FINITE(s) || (s < AOCS_R(1.0)) || (s > hi)) {
            fuzz_fdir_fail("the tracker's noise scale out of [1, fdir.st_noise_scale_max]");
        }
        if ((aocs_fdir_same(s, scale_before) == 0) &&
            ((f->st_rescaled == 0) ||
             (fuzz_fdir_raised(&f->log, events_before, AOCS_EVT_ST_NOISE_RESCALED, t_ns) == 0))) {
            fuzz_fdir_fail("the tracker's noise scale changed without st_noise_rescaled");
        }
    }
}

/* 1 when an event id at t_ns was raised after sequence number since */
static int fuzz_fdir_raised(const aocs_evlog_t *log, uint32_t since, aocs_evt_id_t id, uint64_t t_ns)
{
    aocs_event_t e;
    uint32_t seq = since;
    int found = 0;
    while (aocs_evlog_next(log, seq, &e, NULL) == AOCS_OK) {
        if ((e.id == id) && (e.t_ns == t_ns)) {
            found = 1;
        }
        seq = e.seq;
    }
    return found;
}

static void fuzz_fdir_config(fuzz_reader_t *r, uint8_t setup, aocs_fdir_config_t *c)
{
    const int raw = (int)((setup >> 2) & 1u);
    aocs_fdir_config_default(c);
    c->enabled = ((setup & 2u) != 0u) ? 0u : 1u;
    c->wheel_residual_frac = fuzz_scaled(r, raw, 0.0, 1.2);
    c->st_chi2 = fuzz_scaled(r, raw, 0.0, 100.0);
    c->st_frozen_rate_radps = fuzz_scaled(r, raw, 0.0, 1.0e-2);
    c->gyro_sat_radps = fuzz_scaled(r, raw, -0.1, 1.0);
    c->wheel_persist = fuzz_u8(r) % 8u;
    c->st_persist = fuzz_u8(r) % 8u;
    c->st_restore = fuzz_u8(r) % 8u;
    c->st_frozen_samples = fuzz_u8(r) % 8u;
    c->gyro_stuck_samples = fuzz_u8(r) % 8u;
    c->link_lost_periods = fuzz_u8(r) % 8u;
    c->gyro_bias_chi2 = fuzz_scaled(r, raw, -1.0, 50.0);
    c->gyro_bias_persist = fuzz_u8(r) % 8u;
    c->mom_residual_nm = fuzz_scaled(r, raw, 0.0, 5.0e-2);
    c->mom_window = fuzz_u8(r) % 40u;
    c->mom_persist = fuzz_u8(r) % 4u;
    c->wheel_friction_window = fuzz_u8(r) % 16u;
    c->wheel_friction_excess = fuzz_scaled(r, raw, 0.0, 3.0);
}

/* irassi_day's twelve 1 N thrusters in six couples on 1.2 m arms: r_i x d_i, m */
static void fuzz_fdir_thrusters(aocs_mom_config_t *mc)
{
    static const real_t arm[12][3] = {{1.2, 0, 0},  {1.2, 0, 0},  {-1.2, 0, 0}, {-1.2, 0, 0},
                                      {0, 1.2, 0},  {0, 1.2, 0},  {0, -1.2, 0}, {0, -1.2, 0},
                                      {0, 0, 1.2},  {0, 0, 1.2},  {0, 0, -1.2}, {0, 0, -1.2}};
    (void)memset(mc, 0, sizeof(*mc));
    mc->policy = (uint32_t)AOCS_MOM_THRUSTERS;
    mc->trigger = AOCS_MOM_TRIGGER_THRESHOLD;
    mc->h_start_Nms = AOCS_R(20.0);
    mc->h_stop_Nms = AOCS_R(3.0);
    mc->dump_torque_Nm = AOCS_R(0.02);
    mc->thr_count = 12u;
    mc->thr_thrust_N = AOCS_R(1.0);
    mc->thr_min_on_s = AOCS_R(0.01);
    mc->thr_quantum_s = AOCS_R(0.001);
    mc->thr_latch_b_mask = 0xAAAu; /* each couple's second thruster behind valve B */
    for (uint32_t i = 0u; i < 12u; ++i) {
        mc->thr_arm_x_m[i] = arm[i][0];
        mc->thr_arm_y_m[i] = arm[i][1];
        mc->thr_arm_z_m[i] = arm[i][2];
    }
}

/* 1 when a thruster on a closed latch branch has an on-time */
static int fuzz_fdir_latched_fires(const aocs_mom_t *mom)
{
    int fires = 0;
    for (uint32_t i = 0u; i < 12u; ++i) {
        const uint32_t b = (mom->cfg.thr_latch_b_mask >> i) & 1u;
        if ((((mom->out.latch_closed_mask >> b) & 1u) != 0u) && (mom->out.thruster_on_s[i] > AOCS_R(0.0))) {
            fires = 1;
        }
    }
    return fires;
}

/* the thruster invariants of one step: events, exclusions and their events, the latch valves (see the header) */
static void fuzz_fdir_check_thrusters(const aocs_fdir_t *f, const aocs_mom_t *mom, uint32_t excluded_before,
                                      uint32_t latch_before, uint32_t since, uint64_t t_ns)
{
    aocs_event_t e;
    uint32_t seq = since;
    uint32_t switched = 0u;
    uint32_t closed = 0u;
    uint32_t reopened = 0u;
    while (aocs_evlog_next(&f->log, seq, &e, NULL) == AOCS_OK) {
        if ((e.unit_kind == AOCS_UNIT_THRUSTER) && ((e.unit < 0) || ((uint32_t)e.unit >= mom->cfg.thr_count))) {
            fuzz_fdir_fail("thruster event names no configured thruster");
        }
        if ((e.id == AOCS_EVT_UNLOAD_ACTUATOR_SWITCHED) && (e.t_ns == t_ns) && (e.unit >= 0) && (e.unit < 12)) {
            switched |= (uint32_t)1u << (uint32_t)e.unit;
        }
        if ((e.t_ns == t_ns) &&
            ((e.id == AOCS_EVT_THRUSTER_BRANCH_CLOSED) || (e.id == AOCS_EVT_THRUSTER_BRANCH_REOPENED))) {
            if ((aocs_fdir_same(e.value, AOCS_R(0.0)) == 0) && (aocs_fdir_same(e.value, AOCS_R(1.0)) == 0)) {
                fuzz_fdir_fail("a latch event names no branch");
            }
            if (e.id == AOCS_EVT_THRUSTER_BRANCH_CLOSED) {
                closed |= (e.value > AOCS_R(0.5)) ? 2u : 1u;
            } else {
                reopened |= (e.value > AOCS_R(0.5)) ? 2u : 1u;
            }
        }
        seq = e.seq;
    }
    if (((mom->out.latch_closed_mask & ~latch_before) & ~closed) != 0u) {
        fuzz_fdir_fail("a latch valve closed without its thruster_branch_closed event");
    }
    if (((latch_before & ~mom->out.latch_closed_mask) & ~reopened) != 0u) {
        fuzz_fdir_fail("a latch valve opened without its thruster_branch_reopened event");
    }
    if ((mom->out.latch_closed_mask & 3u) == 3u) {
        fuzz_fdir_fail("both latch valves closed");
    }
    if (fuzz_fdir_latched_fires(mom) != 0) {
        fuzz_fdir_fail("a thruster on a closed latch branch commanded after fault management");
    }
    if ((mom->thr_excluded_mask & excluded_before) != excluded_before) {
        fuzz_fdir_fail("an excluded thruster came back");
    }
    if ((mom->thr_excluded_mask & ~excluded_before) != switched) {
        fuzz_fdir_fail("a thruster excluded without its unload_actuator_switched event");
    }
    if (mom->initialised == 0) {
        fuzz_fdir_fail("the momentum stage lost its initialisation");
    }
}

static void fuzz_fdir_check(const aocs_fdir_t *f, const aocs_wheels_t *wa, uint32_t mask_before, uint32_t *seq_seen,
                            uint32_t refused_before)
{
    aocs_event_t e;
    uint32_t lost = 0u;
    uint32_t refused = refused_before;
    const uint32_t n = wa->cfg.n;
    if (f->log.seq_last < *seq_seen) {
        fuzz_fdir_fail("event seq went back");
    }
    while (aocs_evlog_next(&f->log, *seq_seen, &e, &lost) == AOCS_OK) {
        if ((lost != 0u) || (e.seq != (*seq_seen + 1u))) {
            fuzz_fdir_fail("events not read in sequence");
        }
        if (!AOCS_IS_FINITE(e.value) || !AOCS_IS_FINITE(e.threshold)) {
            fuzz_fdir_fail("non-finite event value");
        }
        if ((aocs_evt_name(e.id) == NULL) || (e.severity != aocs_evt_severity(e.id)) ||
            (e.unit_kind != aocs_evt_unit_kind(e.id))) {
            fuzz_fdir_fail("event not a row of the table");
        }
        if ((e.unit_kind == AOCS_UNIT_WHEEL) && ((e.unit < 0) || ((uint32_t)e.unit >= n))) {
            fuzz_fdir_fail("wheel event names no configured wheel");
        }
        if (e.id == AOCS_EVT_WHEEL_ISOLATION_REFUSED) {
            refused += 1u;
        }
        if (f->cfg.enabled == 0u) {
            fuzz_fdir_fail("disabled stage raised an event");
        }
        *seq_seen = e.seq;
    }
    if ((wa->cfg.failed_mask & mask_before) != mask_before) {
        fuzz_fdir_fail("a failed wheel came back");
    }
    if ((wa->cfg.failed_mask >> n) != 0u) {
        fuzz_fdir_fail("isolated a wheel that is not configured");
    }
    if ((wa->initialised == 0) || (wa->n_healthy < AOCS_WHEELS_MIN)) {
        fuzz_fdir_fail("fewer than three wheels used");
    }
    if ((refused != 0u) && (f->safe_latched == 0)) {
        fuzz_fdir_fail("refused isolation without SAFE");
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_reader_t r = {data, size, 0u};
    const uint8_t setup = fuzz_u8(&r);
    aocs_wheels_config_t wc;
    aocs_wheels_t wa;
    aocs_fdir_config_t c;
    aocs_fdir_t f;
    aocs_mom_config_t mc;
    aocs_mom_t mom;
    uint32_t seq_seen = 0u;
    uint32_t refused = 0u;
    uint64_t t_ns = 0u;
    uint32_t restarts = 0u;
    fuzz_wheels(&wc, (int)(setup & 1u));
    wc.period_s = AOCS_R(0.1);
    if (aocs_wheels_init(&wa, &wc) != AOCS_OK) {
        fuzz_fdir_fail("the reference array refused");
    }
    fuzz_fdir_thrusters(&mc);
    if (aocs_mom_init(&mom, &mc) != AOCS_OK) {
        fuzz_fdir_fail("the reference thrusters refused");
    }
    fuzz_fdir_config(&r, setup, &c);
    if (aocs_fdir_init(&f, &c) != AOCS_OK) {
        aocs_fdir_input_t in;
        (void)memset(&in, 0, sizeof(in));
        in.have_sample = 1;
        aocs_fdir_step(&f, &in, &wa);
        if ((f.initialised != 0) || (aocs_evlog_count(&f.log) != 0u) || (wa.cfg.failed_mask != wc.failed_mask)) {
            fuzz_fdir_fail("a refused configuration did something");
        }
        return 0;
    }
    uint32_t friction_flagged = 0u; /* wheels with a wheel_friction_high event so far */
    for (int k = 0; (k < 4096) && (fuzz_more(&r) != 0); ++k) {
        const uint8_t flags = fuzz_u8(&r);
        real_t coulomb_before[AOCS_WHEELS_MAX];
        const uint32_t seq_before_step = f.log.seq_last;
        const int raw = (int)((flags >> 4) & 1u);
        aocs_fdir_input_t in;
        aocs_wheels_alloc_t alloc;
        aocs_det_output_t est;
        real_t speeds[AOCS_WHEELS_MAX] = {0};
        const uint32_t mask_before = wa.cfg.failed_mask;
        for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
            coulomb_before[i] = wa.cfg.coulomb_nm[i];
        }
        (void)memset(&in, 0, sizeof(in));
        (void)memset(&alloc, 0, sizeof(alloc));
        (void)memset(&est, 0, sizeof(est));
        t_ns += 100000000u;
        in.t_ns = t_ns;
        in.period_s = AOCS_R(0.1);
        in.have_sample = (int)(flags & 1u);
        in.missing = (uint32_t)fuzz_u8(&r) % 5u;
        in.input_status = ((flags & 2u) != 0u) ? AOCS_OK : AOCS_ERR_INPUT_STALE;
        in.mode = (aocs_exec_mode_t)((flags >> 5) % 3u);
        for (uint32_t i = 0u; i < 4u; ++i) {
            speeds[i] = fuzz_scaled(&r, raw, -700.0, 700.0);
            alloc.u_s_nm[i] = fuzz_scaled(&r, raw, -0.3, 0.3);
        }
        in.wheel_speed_radps = speeds;
        in.alloc = &alloc;
        est.status = AOCS_OK;
        est.st_status = ((flags & 128u) != 0u) ? AOCS_ERR_MEKF_GATED : AOCS_ERR_INPUT_MISSING;
        est.innovation_chi2 = fuzz_scaled(&r, raw, 0.0, 50.0);
        in.est = &est;
        in.gyro_valid = (int)((flags >> 3) & 1u);
        in.gyroless_capable = (int)((setup >> 3) & 1u);
        in.gyro_w_B = aocs_vec3_make(fuzz_scaled(&r, raw, -1.0, 1.0), fuzz_scaled(&r, raw, -1.0, 1.0),
                                     fuzz_scaled(&r, raw, -1.0, 1.0));
        in.st_valid = (int)((flags >> 2) & 1u);
        in.st_q_SN = aocs_quat_make(fuzz_scaled(&r, raw, -1.0, 1.0), fuzz_scaled(&r, raw, -1.0, 1.0),
                                    fuzz_scaled(&r, raw, -1.0, 1.0), fuzz_scaled(&r, raw, -1.0, 1.0));
        {
            const uint8_t ff = fuzz_u8(&r);
            const uint32_t events_before = f.log.seq_last;
            if ((ff & 1u) != 0u) {
                est.st_status = AOCS_OK;
            }
            restarts += (uint32_t)((ff >> 1) & 1u);
            est.n_restarts = restarts;
            for (uint32_t i = 0u; i < 3u; ++i) {
                est.bias_B_radps.v[i] = fuzz_scaled(&r, raw, -1.0e-4, 1.0e-4);
            }
            est.p_upper[15] = fuzz_scaled(&r, raw, 0.0, 1.0e-10);
            est.p_upper[18] = fuzz_scaled(&r, raw, 0.0, 1.0e-10);
            est.p_upper[20] = fuzz_scaled(&r, raw, 0.0, 1.0e-10);
            in.gyro_rrw_radps1p5 = fuzz_scaled(&r, raw, 0.0, 1.0e-8);
            est.innovation_white = aocs_vec3_make(fuzz_scaled(&r, raw, -30.0, 30.0), fuzz_scaled(&r, raw, -30.0, 30.0),
                                                  fuzz_scaled(&r, raw, -30.0, 30.0));
            /* the momentum stage on this sample's wheels, then fault management (the executive's order) */
            {
                aocs_mom_input_t mi;
                (void)memset(&mi, 0, sizeof(mi));
                mi.h_wheels_B_Nms = aocs_wheels_h_B(&wa, speeds);
                mi.h_valid = aocs_vec3_is_finite(mi.h_wheels_B_Nms);
                mi.enabled = (in.mode == AOCS_EXEC_MODE_NOMINAL) ? 1 : 0;
                mi.dt_s = in.period_s;
                (void)aocs_mom_step(&mom, &mi);
                for (uint32_t i = 0u; i < 12u; ++i) {
                    if ((((mom.thr_excluded_mask >> i) & 1u) != 0u) && (mom.out.thruster_on_s[i] > AOCS_R(0.0))) {
                        fuzz_fdir_fail("an excluded thruster fired");
                    }
                }
                if (fuzz_fdir_latched_fires(&mom) != 0) {
                    fuzz_fdir_fail("a thruster on a closed latch branch fired");
                }
            }
            est.q_BN = in.st_q_SN;
            est.w_BN_B = in.gyro_w_B;
            in.mom = &mom;
            {
                const uint32_t excluded_before = mom.thr_excluded_mask;
                const uint32_t latch_before = mom.out.latch_closed_mask;
                const real_t scale_before = f.st.noise_scale;
                aocs_fdir_step(&f, &in, &wa);
                fuzz_fdir_check_thrusters(&f, &mom, excluded_before, latch_before, events_before, t_ns);
                fuzz_fdir_check_noise(&f, scale_before, events_before, t_ns);
            }
            if ((f.reinflate_bias != 0) && (fuzz_fdir_raised(&f.log, events_before, AOCS_EVT_GYRO_ST_INCONSISTENT,
                                                             t_ns) == 0)) {
                fuzz_fdir_fail("bias re-inflation without a gyro_st_inconsistent event of the step");
            }
            if ((f.go_gyroless != 0) &&
                ((in.gyroless_capable == 0) ||
                 (fuzz_fdir_raised(&f.log, events_before, AOCS_EVT_ESTIMATOR_GYROLESS, t_ns) == 0) ||
                 (fuzz_fdir_raised(&f.log, events_before, AOCS_EVT_GYRO_EXCLUDED, t_ns) == 0))) {
                fuzz_fdir_fail("the gyroless switch asked without an estimator that can, or without its events");
            }
        }
        {
            aocs_event_t e;
            uint32_t seq = seq_before_step;
            while (aocs_evlog_next(&f.log, seq, &e, NULL) == AOCS_OK) {
                if ((e.id == AOCS_EVT_WHEEL_FRICTION_HIGH) && (e.unit >= 0) && (e.unit < (int32_t)AOCS_WHEELS_MAX)) {
                    friction_flagged |= (uint32_t)1u << (uint32_t)e.unit;
                }
                seq = e.seq;
            }
            for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
                if ((aocs_fdir_same(coulomb_before[i], wa.cfg.coulomb_nm[i]) == 0) &&
                    (((friction_flagged >> i) & 1u) == 0u)) {
                    fuzz_fdir_fail("a wheel's friction model rescaled without its wheel_friction_high event");
                }
            }
        }
        fuzz_fdir_check(&f, &wa, mask_before, &seq_seen, refused);
        refused = (f.safe_latched != 0) ? 1u : refused;
    }
    return 0;
}
