/*
 * aocs_image: the flight executive on the target core, closed loop in the
 * image (no host, no I/O other than one semihosting line per run).
 *
 * A rigid body (SPEC 1: J wdot = -w x (J w) + u, qdot = 0.5 Xi(q) w;
 * explicit Euler substeps, renormalised: a smoke plant, not the SIL plant)
 * starts 40 deg off target and is driven by aocs_exec_step for IMG_STEPS
 * periods, once per law of img_runs. Checks of every step: the executive
 * returns AOCS_OK, the command is finite and within the per-axis limit, and
 * the mode is NOMINAL, except at IMG_FAULT_STEP where one sample carries a
 * NaN attitude and the executive must answer in SAFE mode with a finite,
 * limited command. At the end the pointing error must be below
 * IMG_FINAL_FRACTION of the initial one. A HAL self-check (img_hal_ok)
 * runs first. The exit status (0 = every check passed) becomes QEMU's.
 *
 * Then the run "mekf": quat_pd flown on the MEKF's estimate (estimator
 * mekf, estimation/determination.def) from a gyro (the body rate) and a
 * star tracker (the body attitude, identity mounting) every
 * IMG_ST_EVERY periods; at IMG_FAULT_STEP the tracker sample is NaN and
 * the executive must stay NOMINAL (the filter rejects and counts it). Its
 * attitude-determination step is measured on a shadow stage fed the same
 * samples: instructions = SysTick ticks x (1e9 / AOCS_CM_CORE_HZ) ns per tick
 * / 2^AOCS_IMAGE_ICOUNT_SHIFT ns per instruction (QEMU -icount, the
 * command of CMakeLists.txt), the worst step reported (det_instr_max) and
 * checked against the row's INSTR_M4F / INSTR_M7 (aocs/budget.h): the
 * measurement behind those columns. The worst step is also sought on an
 * open-loop stream whose tracker samples are IMG_ST_AGE periods old (a
 * delayed sample walks back the whole gyro history, spec 5.6.8: in double,
 * software floating point on the M4F).
 */
#include <math.h>
#include <stdint.h>

#include "aocs/types.h"
#include "aocs/math3.h"
#include "aocs/attitude.h"
#include "aocs/executive.h"
#include "aocs/hal.h"
#include "aocs/budget.h"
#include "aocs_cm.h"

/* the -icount shift of the QEMU command: CMakeLists.txt passes its AOCS_IMAGE_ICOUNT_SHIFT (5 there too) */
#ifndef AOCS_IMAGE_ICOUNT_SHIFT
#define AOCS_IMAGE_ICOUNT_SHIFT 5U
#endif

#if defined(AOCS_IMAGE_CORTEX_M7)
#define IMG_BUDGET_TARGET AOCS_BUDGET_TARGET_CORTEX_M7
#else
#define IMG_BUDGET_TARGET AOCS_BUDGET_TARGET_CORTEX_M4F
#endif

#ifndef AOCS_IMAGE_TARGET
#define AOCS_IMAGE_TARGET "cortex-m"
#endif

#if defined(AOCS_REAL_IS_FLOAT)
#define IMG_REAL_NAME "float"
#else
#define IMG_REAL_NAME "double"
#endif

#define IMG_STEPS 200U
#define IMG_FAULT_STEP 50U
#define IMG_SUBSTEPS 10U
#define IMG_PERIOD_NS 100000000ULL       /* 0.1 s */
#define IMG_DT_S AOCS_R(0.1)
#define IMG_U_MAX AOCS_R(1.0)            /* N m per axis */
#define IMG_FINAL_FRACTION AOCS_R(0.05)  /* final / initial pointing error */
#define IMG_RAD_TO_MDEG AOCS_R(57295.7795)
#define IMG_LINE_CAP 256U
#define IMG_RUN_COUNT 3U
#define IMG_HAL_READS 20000U
#define IMG_HAL_SLEEP_NS 2500000ULL      /* 2.5 ms: several SysTick periods */
#define IMG_ST_EVERY 5U                  /* a tracker sample every 5 periods (2 Hz) */
#define IMG_DET_STEPS 160U               /* the worst-case stream of the determination step */
#define IMG_ST_AGE 31U                   /* its tracker samples' age, periods: the whole history */
#if (AOCS_MEKF_HISTORY_LEN - 1U) != IMG_ST_AGE
#error "IMG_ST_AGE: the MEKF's history length less one (estimation/mekf.h)"
#endif

typedef struct {
    aocs_quat_t q_BN;
    aocs_vec3_t w_BN_B;
} img_body_t;

typedef struct {
    uint32_t steps_ok;      /* steps that passed every per-step check */
    uint32_t cycles_max;    /* largest out.step_cycles */
    uint32_t det_instr_max; /* the mekf run: largest attitude-determination step, instructions */
    real_t angle0_rad;
    real_t angle_rad;
    aocs_status_t status;   /* first error of the run, AOCS_OK if none */
} img_result_t;

/* Principal inertia of the smoke plant, kg m^2. */
static aocs_vec3_t img_inertia(void)
{
    return aocs_vec3_make(AOCS_R(10.0), AOCS_R(12.0), AOCS_R(8.0));
}

/* SPEC 1 rigid body, diagonal J, torque u held over dt. */
static aocs_status_t img_plant_step(img_body_t *body, aocs_vec3_t u, real_t dt)
{
    const aocs_vec3_t j_diag = img_inertia();
    const real_t h = dt / (real_t)IMG_SUBSTEPS;
    aocs_status_t status = AOCS_OK;
    uint32_t k;
    for (k = 0U; (k < IMG_SUBSTEPS) && (status == AOCS_OK); k++) {
        const aocs_vec3_t jw = aocs_vec3_hadamard(j_diag, body->w_BN_B);
        const aocs_vec3_t torque = aocs_vec3_sub(u, aocs_vec3_cross(body->w_BN_B, jw));
        const aocs_vec3_t wdot = aocs_vec3_make(torque.v[0] / j_diag.v[0],
                                                torque.v[1] / j_diag.v[1],
                                                torque.v[2] / j_diag.v[2]);
        const aocs_quat_t qdot = aocs_quat_derivative(body->q_BN, body->w_BN_B);
        aocs_quat_t q_next;
        uint32_t i;
        for (i = 0U; i < 4U; i++) {
            q_next.q[i] = body->q_BN.q[i] + (h * qdot.q[i]);
        }
        body->w_BN_B = aocs_vec3_add(body->w_BN_B, aocs_vec3_scale(wdot, h));
        status = aocs_quat_normalize(q_next, &body->q_BN);
    }
    return status;
}

static aocs_status_t img_exec_init(aocs_exec_t *exec, aocs_law_id_t law, aocs_det_id_t estimator)
{
    aocs_exec_config_t cfg;
    aocs_exec_config_default(&cfg);
    cfg.determination.estimator = (uint32_t)estimator;
    cfg.period_s = IMG_DT_S;
    cfg.law = law;
    cfg.u_max_axis = aocs_vec3_make(IMG_U_MAX, IMG_U_MAX, IMG_U_MAX);
    cfg.laws.quat_pd.kp = AOCS_R(20.0);
    cfg.laws.quat_pd.kd = AOCS_R(25.0);
    cfg.laws.quat_nlpd.kp = AOCS_R(20.0);
    cfg.laws.quat_nlpd.kd = AOCS_R(25.0);
    cfg.laws.crp_linear.k1 = AOCS_R(25.0);
    cfg.laws.crp_linear.k2 = AOCS_R(10.0);
    return aocs_exec_init(exec, &cfg);
}

/* 1 when every component is finite and within the per-axis limit. */
static int img_command_ok(aocs_vec3_t u)
{
    int ok = 0;
    if ((aocs_vec3_is_finite(u) != 0) && (aocs_vec3_norm_inf(u) <= IMG_U_MAX)) {
        ok = 1;
    }
    return ok;
}

/* The per-step checks of the file comment. */
static int img_step_ok(uint32_t step, const aocs_exec_output_t *out)
{
    int ok = img_command_ok(out->u_cmd);
    if (step == IMG_FAULT_STEP) {
        if ((out->mode != AOCS_EXEC_MODE_SAFE) || (out->input_status == AOCS_OK)) {
            ok = 0;
        }
    } else if (step < IMG_FAULT_STEP) {
        if ((out->mode != AOCS_EXEC_MODE_NOMINAL) || (out->law_status != AOCS_OK)) {
            ok = 0;
        }
    } else {
        /* after the fault: SAFE until the recovery rule, then NOMINAL again */
        if (out->mode == AOCS_EXEC_MODE_STANDBY) {
            ok = 0;
        }
    }
    return ok;
}

static img_result_t img_run(aocs_exec_t *exec, aocs_law_id_t law)
{
    img_result_t res;
    img_body_t body;
    aocs_exec_input_t in;
    aocs_exec_output_t out;
    uint32_t step;
    const real_t nan_value = (real_t)NAN;

    /* 40 deg about the unit axis (1, 2, -2)/3, small initial tumble */
    body.q_BN = aocs_quat_make(AOCS_R(0.342020143) / AOCS_R(3.0),
                               (AOCS_R(0.342020143) * AOCS_R(2.0)) / AOCS_R(3.0),
                               (AOCS_R(-0.342020143) * AOCS_R(2.0)) / AOCS_R(3.0),
                               AOCS_R(0.939692621));
    body.w_BN_B = aocs_vec3_make(AOCS_R(0.01), AOCS_R(-0.02), AOCS_R(0.015));
    res.steps_ok = 0U;
    res.cycles_max = 0U;
    res.angle0_rad = aocs_quat_angle(body.q_BN);
    res.det_instr_max = 0U;
    res.status = img_exec_init(exec, law, AOCS_DET_PASSTHROUGH);

    in.pos_m = aocs_vec3_zero();
    in.vel_mps = aocs_vec3_zero();
    for (step = 0U; (step < IMG_STEPS) && (res.status == AOCS_OK); step++) {
        in.tick = step;
        in.t_sensor_ns = (uint64_t)step * IMG_PERIOD_NS;
        in.q_BN = body.q_BN;
        in.w_BN_B = body.w_BN_B;
        in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
        if (step == IMG_FAULT_STEP) {
            in.q_BN.q[0] = nan_value;
        }
        res.status = aocs_exec_step(exec, &in, &out);
        if (res.status == AOCS_OK) {
            if (out.step_cycles > res.cycles_max) {
                res.cycles_max = out.step_cycles;
            }
            if (img_step_ok(step, &out) != 0) {
                res.steps_ok++;
            }
            res.status = img_plant_step(&body, out.u_cmd, IMG_DT_S);
        }
    }
    res.angle_rad = aocs_quat_angle(body.q_BN);
    return res;
}

/* SysTick ticks -> instructions under QEMU -icount shift N (1e9 / AOCS_CM_CORE_HZ ns per tick, 2^N ns each). */
static uint32_t img_instructions(uint32_t ticks)
{
    const uint64_t ns = ((uint64_t)ticks * 1000000000ULL) / (uint64_t)AOCS_CM_CORE_HZ;
    return (uint32_t)(ns >> AOCS_IMAGE_ICOUNT_SHIFT);
}

/* The checks of one step of the mekf run: NOMINAL throughout (a NaN tracker sample is the filter's business). */
static int img_mekf_step_ok(uint32_t step, const aocs_exec_output_t *out)
{
    int ok = img_command_ok(out->u_cmd);
    if ((out->mode != AOCS_EXEC_MODE_NOMINAL) || (out->law_status != AOCS_OK) || (out->input_status != AOCS_OK) ||
        (out->estimate.status != AOCS_OK)) {
        ok = 0;
    }
    if ((step == IMG_FAULT_STEP) && ((out->estimate.st_status == AOCS_OK) || (out->estimate.n_st_hostile != 1U))) {
        ok = 0;
    }
    return ok;
}

/* Instructions of one attitude-determination step of det on in (SysTick ticks around it). */
static uint32_t img_det_step_instructions(aocs_det_t *det, const aocs_exec_input_t *in, aocs_status_t *st)
{
    aocs_det_output_t est;
    const uint32_t c0 = aocs_hal_cycles();
    *st = aocs_det_step(det, in, AOCS_OK, IMG_DT_S, &est);
    return img_instructions(aocs_hal_cycles() - c0);
}

/*
 * The worst-case stream: a body turning at a constant rate, the gyro exact,
 * a tracker sample every IMG_ST_EVERY periods measured IMG_ST_AGE periods
 * earlier (the first one, at t = 0, starts the filter). Every step must give
 * an estimate and every tracker sample be used. The largest step, instructions.
 */
static uint32_t img_det_worst(const aocs_det_config_t *cfg, aocs_status_t *status)
{
    static aocs_det_t det;
    static aocs_quat_t ring[AOCS_MEKF_HISTORY_LEN];
    const aocs_vec3_t w = aocs_vec3_make(AOCS_R(0.01), AOCS_R(-0.02), AOCS_R(0.015));
    const real_t th = aocs_vec3_norm(w) * IMG_DT_S;
    const real_t k = AOCS_SIN(AOCS_R(0.5) * th) / aocs_vec3_norm(w);
    const aocs_quat_t dq = aocs_quat_make(k * w.v[0], k * w.v[1], k * w.v[2], AOCS_COS(AOCS_R(0.5) * th));
    aocs_quat_t q = aocs_quat_make(AOCS_R(0.6), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.8));
    aocs_exec_input_t in;
    uint32_t worst = 0U;
    uint32_t step;
    *status = aocs_det_init(&det, cfg);
    in.q_BN = aocs_quat_identity();
    in.w_BN_B = aocs_vec3_zero();
    in.pos_m = aocs_vec3_zero();
    in.vel_mps = aocs_vec3_zero();
    in.gyro_w_B = w;
    for (step = 0U; (step < IMG_DET_STEPS) && (*status == AOCS_OK); step++) {
        aocs_status_t st = AOCS_OK;
        uint32_t n;
        ring[step % AOCS_MEKF_HISTORY_LEN] = q;
        in.tick = step;
        in.t_sensor_ns = (uint64_t)step * IMG_PERIOD_NS;
        in.valid = AOCS_EXEC_VALID_GYRO;
        if (step == 0U) {
            in.valid |= AOCS_EXEC_VALID_ST;
            in.st_q_SN = q;
            in.st_t_meas_ns = 0U;
        } else if ((step >= IMG_ST_AGE) && ((step % IMG_ST_EVERY) == 0U)) {
            const uint64_t meas_step = (uint64_t)step - (uint64_t)IMG_ST_AGE;
            in.valid |= AOCS_EXEC_VALID_ST;
            in.st_q_SN = ring[(step - IMG_ST_AGE) % AOCS_MEKF_HISTORY_LEN];
            in.st_t_meas_ns = meas_step * IMG_PERIOD_NS;
        } else {
            /* no tracker sample this period */
        }
        n = img_det_step_instructions(&det, &in, &st);
        if (n > worst) {
            worst = n;
        }
        if ((st != AOCS_OK) ||
            (((in.valid & AOCS_EXEC_VALID_ST) != 0U) && (det.states.mekf.t_last_meas_ns != in.st_t_meas_ns))) {
            *status = (st != AOCS_OK) ? st : AOCS_ERR_MEKF_GATED;
        }
        q = aocs_quat_mul(dq, q);
    }
    return worst;
}

static img_result_t img_run_mekf(aocs_exec_t *exec, aocs_law_id_t law)
{
    static aocs_det_t shadow;
    img_result_t res;
    img_body_t body;
    aocs_exec_input_t in;
    aocs_exec_output_t out;
    aocs_vec3_t w_prev = aocs_vec3_zero();
    uint32_t step;
    const real_t nan_value = (real_t)NAN;

    body.q_BN = aocs_quat_make(AOCS_R(0.342020143) / AOCS_R(3.0),
                               (AOCS_R(0.342020143) * AOCS_R(2.0)) / AOCS_R(3.0),
                               (AOCS_R(-0.342020143) * AOCS_R(2.0)) / AOCS_R(3.0),
                               AOCS_R(0.939692621));
    body.w_BN_B = aocs_vec3_make(AOCS_R(0.01), AOCS_R(-0.02), AOCS_R(0.015));
    res.steps_ok = 0U;
    res.cycles_max = 0U;
    res.det_instr_max = 0U;
    res.angle0_rad = aocs_quat_angle(body.q_BN);
    res.status = img_exec_init(exec, law, AOCS_DET_MEKF);
    if (res.status == AOCS_OK) {
        res.status = aocs_det_init(&shadow, &exec->cfg.determination);
    }

    in.q_BN = aocs_quat_identity();
    in.w_BN_B = aocs_vec3_zero();
    in.pos_m = aocs_vec3_zero();
    in.vel_mps = aocs_vec3_zero();
    for (step = 0U; (step < IMG_STEPS) && (res.status == AOCS_OK); step++) {
        in.tick = step;
        in.t_sensor_ns = (uint64_t)step * IMG_PERIOD_NS;
        in.valid = AOCS_EXEC_VALID_GYRO;
        /* a gyro gives the mean rate over the period that ended (torque held: the mean of its end rates) */
        in.gyro_w_B = (step == 0U) ? body.w_BN_B : aocs_vec3_scale(aocs_vec3_add(w_prev, body.w_BN_B), AOCS_R(0.5));
        w_prev = body.w_BN_B;
        in.st_q_SN = body.q_BN;
        in.st_t_meas_ns = in.t_sensor_ns;
        if ((step % IMG_ST_EVERY) == 0U) {
            in.valid |= AOCS_EXEC_VALID_ST;
        }
        if (step == IMG_FAULT_STEP) {
            in.valid |= AOCS_EXEC_VALID_ST;
            in.st_q_SN.q[0] = nan_value;
        }
        /* the determination step alone, on a shadow stage fed the same samples */
        {
            aocs_status_t st_shadow = AOCS_OK;
            const uint32_t n = img_det_step_instructions(&shadow, &in, &st_shadow);
            if (n > res.det_instr_max) {
                res.det_instr_max = n;
            }
        }
        res.status = aocs_exec_step(exec, &in, &out);
        if (res.status == AOCS_OK) {
            if (out.step_cycles > res.cycles_max) {
                res.cycles_max = out.step_cycles;
            }
            if (img_mekf_step_ok(step, &out) != 0) {
                res.steps_ok++;
            }
            res.status = img_plant_step(&body, out.u_cmd, IMG_DT_S);
        }
    }
    res.angle_rad = aocs_quat_angle(body.q_BN);
    if (res.status == AOCS_OK) {
        const uint32_t worst = img_det_worst(&exec->cfg.determination, &res.status);
        if (worst > res.det_instr_max) {
            res.det_instr_max = worst;
        }
    }
    return res;
}

static int img_report(aocs_law_id_t law, const img_result_t *res)
{
    char line[IMG_LINE_CAP];
    uint32_t pos = 0U;
    int pass = 0;
    const real_t angle0_mdeg = res->angle0_rad * IMG_RAD_TO_MDEG;
    const real_t angle_mdeg = res->angle_rad * IMG_RAD_TO_MDEG;
    if ((res->status == AOCS_OK) && (res->steps_ok == IMG_STEPS)
        && (res->angle_rad < (IMG_FINAL_FRACTION * res->angle0_rad))) {
        pass = 1;
    }
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, "aocs_image " AOCS_IMAGE_TARGET " " IMG_REAL_NAME " law=");
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, aocs_law_name(law));
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, " steps_ok=");
    aocs_cm_fmt_int(line, IMG_LINE_CAP, &pos, (int64_t)res->steps_ok);
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, "/");
    aocs_cm_fmt_int(line, IMG_LINE_CAP, &pos, (int64_t)IMG_STEPS);
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, " angle_mdeg=");
    aocs_cm_fmt_int(line, IMG_LINE_CAP, &pos, (int64_t)angle0_mdeg);
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, "->");
    aocs_cm_fmt_int(line, IMG_LINE_CAP, &pos, (int64_t)angle_mdeg);
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, " step_cycles_max=");
    aocs_cm_fmt_int(line, IMG_LINE_CAP, &pos, (int64_t)res->cycles_max);
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos,
                    (aocs_cm_cycles_from_dwt() != 0U) ? "(dwt)" : "(systick)");
    if (res->det_instr_max > 0U) {
        const uint32_t budget = aocs_budget_estimator_instructions(AOCS_DET_MEKF, IMG_BUDGET_TARGET);
        aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, " estimator=mekf det_instr_max=");
        aocs_cm_fmt_int(line, IMG_LINE_CAP, &pos, (int64_t)res->det_instr_max);
        aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, " budget=");
        aocs_cm_fmt_int(line, IMG_LINE_CAP, &pos, (int64_t)budget);
        if (res->det_instr_max > budget) {
            pass = 0;
        }
    }
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, " status=");
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, aocs_status_name(res->status));
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, (pass != 0) ? " PASS\n" : " FAIL\n");
    aocs_cm_write(line);
    return pass;
}

/*
 * HAL self-check on the target: aocs_hal_time_ns never goes back over
 * IMG_HAL_READS reads (SysTick wraps included), and aocs_hal_sleep_until_ns
 * returns no earlier than its deadline (WFI on SysTick, then busy-wait).
 */
static int img_hal_ok(void)
{
    int ok = 1;
    uint32_t i;
    uint64_t prev = aocs_hal_time_ns();
    uint64_t deadline;
    for (i = 0U; i < IMG_HAL_READS; i++) {
        const uint64_t now = aocs_hal_time_ns();
        if (now < prev) {
            ok = 0;
        }
        prev = now;
    }
    deadline = prev + IMG_HAL_SLEEP_NS;
    aocs_hal_sleep_until_ns(deadline);
    if (aocs_hal_time_ns() < deadline) {
        ok = 0;
    }
    return ok;
}

int main(void)
{
    static const aocs_law_id_t img_runs[IMG_RUN_COUNT] = {
        AOCS_LAW_QUAT_PD, AOCS_LAW_QUAT_NLPD_NEG, AOCS_LAW_CRP_LINEAR
    };
    static aocs_exec_t exec;
    char line[IMG_LINE_CAP];
    uint32_t pos = 0U;
    uint32_t passed = 0U;
    uint32_t run;
    int exit_status = 1;
    const int hal_ok = img_hal_ok();

    for (run = 0U; run < IMG_RUN_COUNT; run++) {
        const img_result_t res = img_run(&exec, img_runs[run]);
        if (img_report(img_runs[run], &res) != 0) {
            passed++;
        }
    }
    {
        const img_result_t res = img_run_mekf(&exec, AOCS_LAW_QUAT_PD);
        if (img_report(AOCS_LAW_QUAT_PD, &res) != 0) {
            passed++;
        }
    }
    if ((passed == (IMG_RUN_COUNT + 1U)) && (hal_ok != 0)) {
        exit_status = 0;
    }
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, "aocs_image " AOCS_IMAGE_TARGET ": runs_passed=");
    aocs_cm_fmt_int(line, IMG_LINE_CAP, &pos, (int64_t)passed);
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, "/");
    aocs_cm_fmt_int(line, IMG_LINE_CAP, &pos, (int64_t)IMG_RUN_COUNT + 1);
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, (hal_ok != 0) ? " hal=ok" : " hal=FAIL");
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, " stack_high_water_bytes=");
    aocs_cm_fmt_int(line, IMG_LINE_CAP, &pos, (int64_t)aocs_cm_stack_high_water());
    aocs_cm_fmt_str(line, IMG_LINE_CAP, &pos, (exit_status == 0) ? " PASS\n" : " FAIL\n");
    aocs_cm_write(line);
    return exit_status;
}
