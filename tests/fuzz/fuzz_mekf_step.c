/*
 * libFuzzer target: the attitude-determination stage with the MEKF row
 * (estimation/determination.h, src/estimation/mekf_stage.c, mekf.c) on a
 * configuration and a sequence of samples and acceptance verdicts taken
 * from the fuzz bytes, without the executive (which would refuse most of
 * them first). Invariants after every step (fuzz_support.h,
 * fuzz_check_estimate): every real of the estimate finite; a usable estimate
 * is a unit q with the attitude and rate flags, an unusable one has no
 * attitude flag; P's diagonal not negative; the filter's counters never go
 * back (but on a reset); the step's return is the estimate's status.
 *
 * Input layout (reads past the end give zeros):
 *   u8  config mode (fuzz_mekf_config: bit0 tuning magnitudes, bit1 mounting, bit2 configured start, bit3 the
 *       gyroless model) and its bytes
 *   then ops until the end, each one u8 op then its fields:
 *     0-6  step: u8 verdict (OK mostly; STALE, MISSING, INVALID), u8 time mode (+ raw u64 when asked),
 *          u8 valid (bits 0-4: the AOCS_EXEC_VALID_* flags; bit5 raw gyro f64s, else 3 x u16 within
 *          +-4 rad/s; bit6 raw q f64s, else a unit q from 3 bytes; bit7 raw t_meas u64, else u8 age
 *          in tenths of a period, 255 = from the future)
 *     7    reset (aocs_det_reset)
 *     8    the gyro excluded (aocs_det_set_gyroless): u8 inertia mode (< 200: a diagonal of 10^(u8 / 64) kg m^2
 *          per axis with u8 / 1024 of it off the diagonal, else 9 raw f64s)
 *     9    the torque held (aocs_det_set_torque): u8 raw (>= 200: 6 raw f64s, else 6 x u16 within +-1 N m
 *          and +-50 N m s)
 * Gyroless (spec 5.6.12), besides the invariants above: a usable estimate has every rate 1-sigma at or
 * below mekf.gyroless_rate_sigma_radps; AOCS_ERR_MEKF_GYROLESS_CONVERGING carries the rate flag only.
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

#define FUZZ_PERIOD_NS 100000000ull

static aocs_quat_t fuzz_unit_quat(fuzz_reader_t *r)
{
    const double a = ((double)fuzz_u8(r) - 128.0) / 40.0;
    const double b = ((double)fuzz_u8(r) - 128.0) / 40.0;
    const double c = ((double)fuzz_u8(r) - 128.0) / 40.0;
    const double n = sqrt(1.0 + (a * a) + (b * b) + (c * c));
    return aocs_quat_make((real_t)(a / n), (real_t)(b / n), (real_t)(c / n), (real_t)(1.0 / n));
}

/* the gyroless stage's rules (spec 5.6.12) on one output */
static void fuzz_check_gyroless(const aocs_det_t *det, const aocs_det_output_t *out)
{
    if (aocs_det_is_gyroless(det) != 0u) {
        static const int diag[3] = {15, 18, 20}; /* (3,3), (4,4), (5,5) of the upper triangle */
        const real_t s = det->states.mekf.cfg.gyroless_rate_sigma_radps;
        if (out->status == AOCS_OK) {
            for (int i = 0; i < 3; ++i) {
                if (!((double)out->p_upper[diag[i]] <= (double)s * (double)s * (1.0 + 1e-5))) {
                    (void)fprintf(stderr, "fuzz invariant violated: a gyroless estimate used with its rate unknown\n");
                    abort();
                }
            }
        }
        if ((out->status == AOCS_ERR_MEKF_GYROLESS_CONVERGING) &&
            ((out->valid != AOCS_EXEC_VALID_RATE) || (aocs_vec3_is_finite(out->w_BN_B) == 0))) {
            (void)fprintf(stderr, "fuzz invariant violated: a converging gyroless estimate without its rate\n");
            abort();
        }
    }
}

static void fuzz_gyroless(fuzz_reader_t *r, aocs_det_t *det)
{
    aocs_mat3_t j;
    const uint8_t m = fuzz_u8(r);
    aocs_status_t st;
    if (m < 200u) {
        for (int a = 0; a < 3; ++a) {
            j.m[a][a] = (real_t)pow(10.0, (double)fuzz_u8(r) / 64.0);
        }
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3;
            const double off = ((double)fuzz_u8(r) / 1024.0) * sqrt((double)j.m[a][a] * (double)j.m[b][b]);
            j.m[a][b] = (real_t)off;
            j.m[b][a] = (real_t)off;
        }
    } else {
        for (int a = 0; a < 9; ++a) {
            j.m[a / 3][a % 3] = (real_t)fuzz_f64(r);
        }
    }
    st = aocs_det_set_gyroless(det, &j);
    if ((st == AOCS_OK) && (aocs_det_is_gyroless(det) == 0u)) {
        (void)fprintf(stderr, "fuzz invariant violated: set_gyroless OK but the filter is not gyroless\n");
        abort();
    }
}

static void fuzz_torque(fuzz_reader_t *r, aocs_det_t *det)
{
    real_t v[6];
    const uint8_t raw = fuzz_u8(r);
    for (int i = 0; i < 6; ++i) {
        v[i] = (raw >= 200u) ? (real_t)fuzz_f64(r)
                             : (real_t)(((double)fuzz_u16(r) - 32768.0) / 32768.0 * ((i < 3) ? 1.0 : 50.0));
    }
    aocs_det_set_torque(det, aocs_vec3_make(v[0], v[1], v[2]), aocs_vec3_make(v[3], v[4], v[5]));
}

static void fuzz_counters_forward(const aocs_det_output_t *prev, const aocs_det_output_t *now)
{
    if ((now->n_st_used < prev->n_st_used) || (now->n_st_gated < prev->n_st_gated) ||
        (now->n_st_hostile < prev->n_st_hostile) || (now->n_restarts < prev->n_restarts)) {
        (void)fprintf(stderr, "fuzz invariant violated: an MEKF counter went back\n");
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const aocs_status_t verdicts[8] = {AOCS_OK, AOCS_OK, AOCS_OK, AOCS_OK, AOCS_OK,
                                              AOCS_ERR_INPUT_STALE, AOCS_ERR_INPUT_MISSING, AOCS_ERR_INPUT_INVALID};
    fuzz_reader_t r = {data, size, 0u};
    aocs_exec_config_t ecfg;
    aocs_det_t det;
    aocs_det_output_t out;
    aocs_det_output_t prev;
    uint64_t t_ns = 0u;
    int ops = 0;
    const uint8_t mode = fuzz_u8(&r);

    aocs_exec_config_default(&ecfg);
    ecfg.determination.estimator = (uint32_t)AOCS_DET_MEKF;
    fuzz_mekf_config(&r, mode, &ecfg.determination.mekf);
    if (aocs_det_init(&det, &ecfg.determination) != AOCS_OK) {
        abort(); /* fuzz_mekf_config gives only configurations the filter accepts */
    }
    memset(&prev, 0, sizeof(prev));
    while ((fuzz_more(&r) != 0) && (ops < 4096)) {
        const uint8_t op = (uint8_t)(fuzz_u8(&r) % 10u);
        ++ops;
        if (op <= 6u) {
            aocs_exec_input_t in;
            const aocs_status_t verdict = verdicts[fuzz_u8(&r) & 7u];
            const uint8_t tm = fuzz_u8(&r);
            uint8_t valid;
            aocs_status_t st;
            memset(&in, 0, sizeof(in));
            /* time: mostly a period on; a gap, a repeat, a step back, or any value */
            if (tm < 200u) {
                t_ns += FUZZ_PERIOD_NS;
            } else if (tm < 230u) {
                t_ns += (uint64_t)(tm - 198u) * FUZZ_PERIOD_NS * 10u;
            } else if (tm < 240u) {
                /* repeat */
            } else if (tm < 250u) {
                t_ns -= (t_ns > FUZZ_PERIOD_NS) ? FUZZ_PERIOD_NS : 0u;
            } else {
                t_ns = fuzz_u64(&r);
            }
            in.t_sensor_ns = t_ns;
            valid = fuzz_u8(&r);
            in.valid = (uint32_t)(valid & 0x1Fu);
            for (int i = 0; i < 3; ++i) {
                in.gyro_w_B.v[i] = ((valid & 0x20u) != 0u) ? (real_t)fuzz_f64(&r)
                                                          : (real_t)(((double)fuzz_u16(&r) - 32768.0) / 8192.0);
            }
            if ((valid & 0x40u) != 0u) {
                for (int i = 0; i < 4; ++i) {
                    in.st_q_SN.q[i] = (real_t)fuzz_f64(&r);
                }
            } else {
                in.st_q_SN = fuzz_unit_quat(&r);
            }
            if ((valid & 0x80u) != 0u) {
                in.st_t_meas_ns = fuzz_u64(&r);
            } else {
                const uint8_t age = fuzz_u8(&r);
                const uint64_t back = (uint64_t)age * (FUZZ_PERIOD_NS / 10u);
                in.st_t_meas_ns = (age == 255u) ? (t_ns + FUZZ_PERIOD_NS) : ((t_ns > back) ? (t_ns - back) : 0u);
            }
            in.q_BN = in.st_q_SN;
            in.w_BN_B = in.gyro_w_B;
            st = aocs_det_step(&det, &in, verdict, AOCS_R(0.1), &out);
            if (st != out.status) {
                abort();
            }
            fuzz_check_estimate(&out);
            fuzz_check_gyroless(&det, &out);
            fuzz_counters_forward(&prev, &out);
            prev = out;
        } else if (op == 8u) {
            fuzz_gyroless(&r, &det);
        } else if (op == 9u) {
            fuzz_torque(&r, &det);
        } else {
            if (aocs_det_reset(&det) != AOCS_OK) {
                abort();
            }
            memset(&prev, 0, sizeof(prev));
        }
    }
    return 0;
}
