/*
 * libFuzzer target: the executive step (executive.h) on a configuration and a
 * sequence of inputs taken from the fuzz bytes. Invariant after every step:
 * the command is finite and within every enabled limit (fuzz_support.h); the
 * sanitizers catch everything else (overflow, out-of-bounds, UB).
 *
 * Input layout (reads past the end give zeros):
 *   u8  law (mod AOCS_LAW_COUNT)      u8 flags: bit0 real time, bits1-2 limit kind
 *                                     (axis / norm / both), bit3 raw limit doubles,
 *                                     bit4 rotating target, bit5 reaction wheels (the SPEC 5.3
 *                                     pyramid with friction feedforward and null-space
 *                                     management, wheel 3 failed when bit6), bit7 the MEKF as
 *                                     the estimator (its defaults; a step's valid byte then
 *                                     gives VALID_ST (bit3) and VALID_GYRO (bit4), the gyro is
 *                                     the step's w, the tracker sample its q measured now or,
 *                                     bit5, a period earlier)
 *   u8  period choice                 3 x u16 axis limit magnitudes, u16 norm magnitude
 *   (bit3: 4 x f64 raw limits)        u8 M, u8 N, u16 stale timeout (periods / 16)
 *   then ops until the end, each one u8 op then its fields:
 *     0-5  step: u8 tick mode, u8 time mode (+ raw u32 / u64 when asked), u8 valid,
 *          4 x f64 q (or a unit q from 3 bytes when bit7 of valid), 3 x f64 w,
 *          3 x f64 pos, 3 x f64 vel, and with wheels 4 x u16 tachometer speeds (+-1000 rad/s, or
 *          a raw f64 each when bit6 of valid)
 *     6    step_no_input            7  select: u8 law, u8 with target, 4 x f64 qd
 *     8    HAL clock jump: u64      9  set_target_epoch: u64
 *
 * Configurations init refuses end the input: the target is what init accepts.
 */
#include "fuzz_support.h"

#include "aocs/hal.h"

/* ---- scripted HAL clock ---- */
static uint64_t g_now_ns;

uint64_t aocs_hal_time_ns(void)
{
    g_now_ns += 100u; /* every read a little later: step times are non-zero */
    return g_now_ns;
}

uint32_t aocs_hal_cycles(void)
{
    return 0u;
}

void aocs_hal_sleep_until_ns(uint64_t t_ns)
{
    if (t_ns > g_now_ns) {
        g_now_ns = t_ns;
    }
}

static const double PERIODS[8] = {0.1, 0.01, 1.0, 1.0e-6, 1000.0, 0.02, 0.5, 0.1};

static int build_config(fuzz_reader_t *r, aocs_exec_config_t *cfg)
{
    uint8_t law = fuzz_u8(r);
    uint8_t flags = fuzz_u8(r);
    uint8_t kind = (uint8_t)((flags >> 1) & 3u);
    aocs_exec_config_default(cfg);
    fuzz_all_law_configs(&cfg->laws);
    cfg->law = (aocs_law_id_t)(law % (uint8_t)AOCS_LAW_COUNT);
    cfg->clock = ((flags & 1u) != 0u) ? AOCS_EXEC_CLOCK_REALTIME : AOCS_EXEC_CLOCK_LOCKSTEP;
    cfg->period_s = (real_t)PERIODS[fuzz_u8(r) & 7u];
    cfg->u_max_axis = aocs_vec3_zero();
    cfg->u_max_norm = AOCS_R(0.0);
    for (int i = 0; i < 3; ++i) {
        real_t a = (real_t)fuzz_mag(r, -9.0, 9.0);
        if ((kind == 0u) || (kind == 2u) || (kind == 3u)) {
            cfg->u_max_axis.v[i] = a;
        }
    }
    {
        real_t nlim = (real_t)fuzz_mag(r, -9.0, 9.0);
        if ((kind == 1u) || (kind == 2u)) {
            cfg->u_max_norm = nlim;
        }
    }
    if ((flags & 8u) != 0u) {
        for (int i = 0; i < 3; ++i) {
            cfg->u_max_axis.v[i] = (real_t)fuzz_f64(r);
        }
        cfg->u_max_norm = (real_t)fuzz_f64(r);
    }
    if ((flags & 16u) != 0u) {
        cfg->target_rotation_rate_D = aocs_vec3_make(AOCS_R(0.01), AOCS_R(-0.02), AOCS_R(0.005));
    }
    if ((flags & 32u) != 0u) {
        fuzz_wheels(&cfg->wheels, (flags & 64u) != 0u);
        if ((flags & 16u) != 0u) {
            /* heavy wheels: Js Omega of a wild tachometer reading overflows unless it is rejected (issue 25) */
            for (uint32_t i = 0u; i < 4u; ++i) {
                cfg->wheels.js_kgm2[i] = AOCS_R(10.0);
            }
        }
    }
    if ((flags & 128u) != 0u) {
        cfg->determination.estimator = (uint32_t)AOCS_DET_MEKF;
        fuzz_mekf_config(r, 0u, &cfg->determination.mekf);
    }
    cfg->recover_good_samples = 1u + (uint32_t)(fuzz_u8(r) % 16u);
    cfg->missing_max_periods = 1u + (uint32_t)(fuzz_u8(r) % 16u);
    cfg->stale_timeout_ns = 1u + (uint64_t)fuzz_u16(r) * 6250000u; /* up to ~410 s */
    return 0;
}

static aocs_quat_t unit_quat(fuzz_reader_t *r)
{
    double a = (double)fuzz_u8(r) / 40.0;
    double b = (double)fuzz_u8(r) / 40.0;
    double c = (double)fuzz_u8(r) / 40.0;
    double n = sqrt(1.0 + a * a + b * b + c * c);
    return aocs_quat_make((real_t)(a / n), (real_t)(b / n), (real_t)(c / n), (real_t)(1.0 / n));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_reader_t r = {data, size, 0u};
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    uint32_t tick = 0u;
    uint64_t t_ns = 0u;
    uint64_t period_ns = 0u;
    int ops = 0;

    g_now_ns = 1000000000u;
    (void)build_config(&r, &cfg);
    if (aocs_exec_init(&exec, &cfg) != AOCS_OK) {
        return 0;
    }
    period_ns = exec.period_ns;
    t_ns = g_now_ns;
    while ((fuzz_more(&r) != 0) && (ops < 4096)) {
        uint8_t op = (uint8_t)(fuzz_u8(&r) % 10u);
        ++ops;
        if (op <= 5u) {
            aocs_exec_input_t in;
            uint8_t tm = fuzz_u8(&r);
            uint8_t mm = fuzz_u8(&r);
            uint8_t valid;
            memset(&in, 0, sizeof(in));
            /* mostly the next tick; sometimes a small gap, a repeat, or any value */
            if (tm < 200u) {
                tick += 1u;
            } else if (tm < 240u) {
                tick += (uint32_t)(tm - 198u);
            } else if (tm < 250u) {
                /* repeat */
            } else {
                tick = fuzz_u32(&r);
            }
            in.tick = tick;
            /* time: the plant's period, a jitter inside or outside the tolerance, or any value */
            if (mm < 200u) {
                t_ns += period_ns;
            } else if (mm < 230u) {
                t_ns += period_ns + ((uint64_t)(mm - 200u) * period_ns) / 64u;
            } else if (mm < 250u) {
                t_ns += (uint64_t)fuzz_u32(&r);
            } else {
                t_ns = fuzz_u64(&r);
            }
            in.t_sensor_ns = t_ns;
            if (cfg.clock == AOCS_EXEC_CLOCK_REALTIME) {
                g_now_ns = t_ns + (uint64_t)(fuzz_u8(&r)) * 1000000u;
            }
            valid = fuzz_u8(&r);
            in.valid = (uint32_t)(valid & 7u);
            if ((valid & 0x80u) != 0u) {
                in.q_BN = unit_quat(&r);
            } else {
                for (int i = 0; i < 4; ++i) {
                    in.q_BN.q[i] = (real_t)fuzz_f64(&r);
                }
            }
            for (int i = 0; i < 3; ++i) {
                in.w_BN_B.v[i] = (real_t)fuzz_f64(&r);
            }
            for (int i = 0; i < 3; ++i) {
                in.pos_m.v[i] = (real_t)fuzz_f64(&r);
                in.vel_mps.v[i] = (real_t)fuzz_f64(&r);
            }
            if (cfg.wheels.n != 0u) {
                for (uint32_t i = 0u; i < cfg.wheels.n; ++i) {
                    in.wheel_speed_radps[i] = ((valid & 0x40u) != 0u) ? (real_t)fuzz_f64(&r)
                                                                      : (real_t)((double)fuzz_u16(&r) / 32.768 - 1000.0);
                }
            }
            if (cfg.determination.estimator == (uint32_t)AOCS_DET_MEKF) {
                in.valid = (uint32_t)(valid & 0x1Fu);
                in.gyro_w_B = in.w_BN_B;
                in.st_q_SN = in.q_BN;
                in.st_t_meas_ns = ((valid & 0x20u) != 0u) ? (t_ns - period_ns) : t_ns;
            }
            if (aocs_exec_step(&exec, &in, &out) != AOCS_OK) {
                abort(); /* an initialised executive always produces a command */
            }
            fuzz_check_output(&cfg, &out);
            if (cfg.determination.estimator == (uint32_t)AOCS_DET_MEKF) {
                fuzz_check_estimate(&out.estimate);
            }
            fuzz_check_wheels(&cfg, &out);
        } else if (op == 6u) {
            g_now_ns += period_ns;
            if (aocs_exec_step_no_input(&exec, &out) != AOCS_OK) {
                abort();
            }
            fuzz_check_output(&cfg, &out);
            fuzz_check_wheels(&cfg, &out);
        } else if (op == 7u) {
            aocs_exec_target_t tgt;
            uint8_t law = fuzz_u8(&r);
            uint8_t with = fuzz_u8(&r);
            memset(&tgt, 0, sizeof(tgt));
            for (int i = 0; i < 4; ++i) {
                tgt.qd_DN.q[i] = (real_t)fuzz_f64(&r);
            }
            if ((with & 2u) != 0u) {
                tgt.qd_DN = unit_quat(&r);
            }
            (void)aocs_exec_select(&exec, (aocs_law_id_t)(law % (uint8_t)AOCS_LAW_COUNT), ((with & 1u) != 0u) ? &tgt : NULL);
        } else if (op == 8u) {
            g_now_ns += fuzz_u64(&r);
        } else {
            (void)aocs_exec_set_target_epoch(&exec, fuzz_u64(&r));
        }
    }
    return 0;
}
