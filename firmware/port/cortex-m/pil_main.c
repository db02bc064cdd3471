/*
 * aocs_pil: the processor-in-the-loop image. The same executive as the SIL
 * node (sil/fsw_node), driven by frames from the host bridge
 * (sil/pil/aocs_pil/bridge.py) over semihosting (pil_link.c), one STEP frame
 * per sensor sample (lockstep). docs/pil.md has the protocol and figures.
 *
 *   boot:  start the HAL time base, calibrate the instruction counter,
 *          open the link, send HELLO
 *   loop:  CONFIG -> aocs_exec_init            -> CONFIG_ACK
 *          STEP   -> aocs_exec_step (counted)  -> STEP_REPLY
 *          SELECT -> aocs_exec_select          -> SELECT_ACK
 *          BYE    -> BYE reply, exit 0
 *          a frame that fails its checks       -> ERROR, then the next frame
 *
 * Entry point: aocs_pil_main (pil_main.h), which the link of aocs_pil maps
 * onto the `main` that startup.S calls (-Wl,--defsym=main=aocs_pil_main in
 * CMakeLists.txt): aocs_image's image_main.c defines `main` in the same
 * port directory, and both are analysed together (MISRA 8.6: one external
 * definition per identifier).
 *
 * Exit status (QEMU's): 0 after BYE, PIL_EXIT_EOF when the host closed the
 * link, PIL_EXIT_LINK when a semihosting call failed, 10..15 on a fault
 * (startup.S). The image never writes anything but frames to stdout;
 * diagnostics go to stderr (SYS_WRITE0).
 *
 * Timing: the executive's own step-time check compares HAL nanoseconds with
 * the host budgets (AOCS_<LAW>_BUDGET_NS); under QEMU those are virtual
 * nanoseconds (2^7 per instruction), meaningless against host budgets, so the
 * image sets the executive's budget_ns out of reach and judges every step
 * against the instruction budget of aocs/budget.h instead.
 */
#include <stddef.h>
#include <stdint.h>

#include "aocs/types.h"
#include "aocs/executive.h"
#include "aocs/budget.h"
#include "aocs/pil_frame.h"
#include "aocs/hal.h"
#include "aocs_cm.h"
#include "pil_icount.h"
#include "pil_link.h"
#include "pil_main.h"

#if defined(AOCS_PIL_CORTEX_M7)
#define PIL_TARGET AOCS_PIL_TARGET_CORTEX_M7
#define PIL_BUDGET_TARGET AOCS_BUDGET_TARGET_CORTEX_M7
#else
#define PIL_TARGET AOCS_PIL_TARGET_CORTEX_M4F
#define PIL_BUDGET_TARGET AOCS_BUDGET_TARGET_CORTEX_M4F
#endif

#define PIL_EXIT_EOF 3
#define PIL_EXIT_LINK 4

/* SysTick ticks between the sync's last counter reading and the first cycle reading (~20 instructions) */
#define PIL_SYNC_SLACK_TICKS 400U

/* calibration: two loop lengths, difference 2 (N2 - N1) instructions */
#define PIL_CALIB_N1 ((uint32_t)100U)
#define PIL_CALIB_N2 ((uint32_t)1100U)
#define PIL_YES ((uint32_t)1U)
#define PIL_NO ((uint32_t)0U)

typedef struct {
    int configured;             /* a CONFIG was accepted by aocs_exec_init */
    uint64_t budget_override;   /* instructions; 0 = aocs_budget_instructions */
    uint32_t overhead;          /* instructions of an empty measurement */
    uint32_t steps;
    uint32_t overruns;
    uint32_t instructions_max;
    uint32_t window_ticks;      /* SysTick ticks left before a measured step (pil_icount.h) */
    uint32_t frame_errors;
    int link_failed;            /* 0, PIL_EXIT_EOF or PIL_EXIT_LINK */
} pil_state_t;

static aocs_exec_t pil_exec;
static pil_state_t pil;
static uint8_t pil_rx[AOCS_PIL_FRAME_MAX];
static uint8_t pil_payload[AOCS_PIL_PAYLOAD_MAX];

/* Instructions of the window between two aocs_hal_cycles() readings. */
static uint32_t pil_window(uint32_t c0, uint32_t c1)
{
    return aocs_pil_icount_from_ticks(c1 - c0);
}

/* Instructions of aocs_pil_calib_loop(n) plus the measurement itself. */
static uint32_t pil_measure_loop(uint32_t n)
{
    uint32_t c0;
    uint32_t c1;
    (void)aocs_pil_icount_sync();
    c0 = aocs_hal_cycles();
    aocs_pil_calib_loop(n);
    c1 = aocs_hal_cycles();
    return pil_window(c0, c1);
}

static void pil_calibrate(aocs_pil_hello_t *hello)
{
    uint32_t c0;
    uint32_t c1;
    uint32_t m1;
    uint32_t m2;
    (void)aocs_hal_time_ns(); /* starts the SysTick time base */
    (void)aocs_hal_cycles();  /* settles the DWT probe (first call only) */
    (void)aocs_pil_icount_sync();
    c0 = aocs_hal_cycles();
    c1 = aocs_hal_cycles();
    pil.overhead = pil_window(c0, c1);
    m1 = pil_measure_loop(PIL_CALIB_N1);
    m2 = pil_measure_loop(PIL_CALIB_N2);
    hello->target = PIL_TARGET;
    hello->real_bytes = (uint32_t)sizeof(real_t);
    hello->icount_shift = AOCS_PIL_ICOUNT_SHIFT;
    hello->calib_measured = m2 - m1;
    hello->calib_expected = 2U * (PIL_CALIB_N2 - PIL_CALIB_N1);
    hello->calib_ok = (hello->calib_measured == hello->calib_expected) ? PIL_YES : PIL_NO;
    hello->overhead = pil.overhead;
}

static void pil_note_link(aocs_pil_link_status_t st)
{
    if ((st == AOCS_PIL_LINK_EOF) && (pil.link_failed == 0)) {
        pil.link_failed = PIL_EXIT_EOF;
    } else if ((st != AOCS_PIL_LINK_OK) && (pil.link_failed == 0)) {
        pil.link_failed = PIL_EXIT_LINK;
    } else {
        /* no new failure, or the first one is kept */
    }
}

/* Frames pil_payload[0 .. len) as `type` with `seq` and writes it to the host. */
static void pil_send(aocs_pil_type_t type, uint32_t seq, uint32_t len)
{
    static uint8_t pil_tx[AOCS_PIL_FRAME_MAX];
    uint32_t frame_len = 0U;
    if (aocs_pil_frame_encode(type, seq, pil_payload, len, pil_tx, AOCS_PIL_FRAME_MAX, &frame_len) == AOCS_PIL_OK) {
        pil_note_link(aocs_pil_link_write(pil_tx, frame_len));
    }
}

static void pil_send_error(aocs_pil_err_t err, uint32_t type, uint32_t seq, uint32_t detail)
{
    aocs_pil_error_t e;
    e.pil_err = err;
    e.type = type;
    e.seq = seq;
    e.detail = detail;
    pil.frame_errors++;
    if (aocs_pil_error_encode(&e, pil_payload, AOCS_PIL_PAYLOAD_MAX) == AOCS_PIL_OK) {
        pil_send(AOCS_PIL_T_ERROR, seq, AOCS_PIL_ERROR_BYTES);
    }
}

static uint32_t pil_budget(aocs_law_id_t law)
{
    uint32_t budget = aocs_budget_instructions(law, PIL_BUDGET_TARGET);
    if ((law != AOCS_LAW_NONE) && (aocs_law_is_orbit(law) == 0)) {
        /* the guidance mode's own work, e.g. the slew reference (guidance_modes.def, aocs/budget.h) */
        budget += aocs_budget_guidance_instructions(pil_exec.guidance.id, PIL_BUDGET_TARGET);
    }
    budget += aocs_budget_estimator_instructions(pil_exec.det.id, PIL_BUDGET_TARGET); /* determination.def */
    budget += aocs_budget_momentum_instructions(pil_exec.momentum.id, PIL_BUDGET_TARGET); /* momentum.def */
    if (pil_exec.cfg.wheels.n != 0U) {
        budget += aocs_budget_wheels_instructions(PIL_BUDGET_TARGET); /* the wheel allocation (aocs/budget.h) */
    }
    if (pil_exec.fdir.cfg.enabled != 0U) {
        budget += aocs_budget_fdir_instructions(PIL_BUDGET_TARGET); /* fault management (aocs/budget.h) */
    }
    if (pil.budget_override > 0U) {
        budget = (uint32_t)pil.budget_override;
    }
    return budget;
}

/*
 * Reads one frame whose header passed its checks into pil_rx. A header that
 * fails (magic, version, length) is reported once, then the stream is
 * scanned byte by byte for the next header that passes. Returns 0 with
 * *hdr filled, or 1 when the link failed.
 */
static int pil_receive(aocs_pil_header_t *hdr)
{
    aocs_pil_link_status_t st = aocs_pil_link_read(pil_rx, AOCS_PIL_HEADER_BYTES);
    aocs_pil_err_t err = AOCS_PIL_ERR_MAGIC;
    int reported = 0;
    while ((st == AOCS_PIL_LINK_OK) && (err != AOCS_PIL_OK)) {
        err = aocs_pil_header_decode(pil_rx, AOCS_PIL_HEADER_BYTES, hdr);
        if (err != AOCS_PIL_OK) {
            uint32_t i;
            if (reported == 0) {
                const uint32_t length = (uint32_t)pil_rx[6] | ((uint32_t)pil_rx[7] << 8U);
                pil_send_error(err, (uint32_t)pil_rx[5], 0U, length);
                reported = 1;
            }
            for (i = 0U; i < (AOCS_PIL_HEADER_BYTES - 1U); i++) {
                pil_rx[i] = pil_rx[i + 1U];
            }
            st = aocs_pil_link_read(&pil_rx[AOCS_PIL_HEADER_BYTES - 1U], 1U);
        }
    }
    if (st == AOCS_PIL_LINK_OK) {
        st = aocs_pil_link_read(&pil_rx[AOCS_PIL_HEADER_BYTES], (uint32_t)hdr->length + AOCS_PIL_CRC_BYTES);
    }
    pil_note_link(st);
    return (st == AOCS_PIL_LINK_OK) ? 0 : 1;
}

static void pil_ack(aocs_pil_type_t type, uint32_t seq, aocs_pil_err_t pil_err, aocs_status_t status,
                    uint32_t field)
{
    aocs_pil_ack_t a;
    const aocs_exec_counters_t c = aocs_exec_counters(&pil_exec);
    a.pil_err = pil_err;
    a.status = status;
    a.field = field;
    a.exec_law = pil_exec.law;
    a.exec_mode = pil_exec.mode;
    a.select_accepted = c.select_accepted;
    a.select_rejected = c.select_rejected;
    a.budget = pil_budget(pil_exec.law);
    a.reserved = 0U;
    if (aocs_pil_ack_encode(&a, pil_payload, AOCS_PIL_PAYLOAD_MAX) == AOCS_PIL_OK) {
        pil_send(type, seq, AOCS_PIL_ACK_BYTES);
    }
}

static void pil_on_config(const aocs_pil_header_t *hdr)
{
    aocs_exec_config_t cfg;
    uint64_t budget = 0U;
    uint32_t field = 0U;
    aocs_status_t st = AOCS_OK;
    aocs_pil_err_t err;
    aocs_exec_config_default(&cfg);
    err = aocs_pil_config_decode(&pil_rx[AOCS_PIL_HEADER_BYTES], (uint32_t)hdr->length, &cfg, &budget, &field,
                                 &st);
    pil.configured = 0;
    if (err == AOCS_PIL_OK) {
        /* the executive's ns check is replaced by the instruction budget (file comment) */
        cfg.budget_ns = UINT64_MAX;
        pil.budget_override = budget;
        /* an MEKF step is longer than the default window: the longest one a SysTick period holds */
        pil.window_ticks = (cfg.determination.estimator == (uint32_t)AOCS_DET_MEKF)
                               ? AOCS_PIL_ICOUNT_WINDOW_LONG_TICKS
                               : AOCS_PIL_ICOUNT_WINDOW_TICKS;
        st = aocs_exec_init(&pil_exec, &cfg);
        if (st == AOCS_OK) {
            pil.configured = 1;
        }
    }
    pil_ack(AOCS_PIL_T_CONFIG_ACK, hdr->seq, err, st, field);
}

static void pil_on_step(const aocs_pil_header_t *hdr)
{
    aocs_exec_input_t in;
    aocs_exec_output_t out;
    aocs_pil_step_reply_t rp;
    aocs_pil_err_t err = aocs_pil_step_decode(&pil_rx[AOCS_PIL_HEADER_BYTES], (uint32_t)hdr->length, &in);
    if (pil.configured == 0) {
        pil_send_error(AOCS_PIL_ERR_STATE, (uint32_t)hdr->type, hdr->seq, 0U);
    } else if (err != AOCS_PIL_OK) {
        pil_send_error(err, (uint32_t)hdr->type, hdr->seq, (uint32_t)hdr->length);
    } else {
        uint32_t c0;
        uint32_t c1;
        uint32_t window;
        const uint32_t left = aocs_pil_icount_sync_window(pil.window_ticks);
        c0 = aocs_hal_cycles();
        rp.step_status = aocs_exec_step(&pil_exec, &in, &out);
        c1 = aocs_hal_cycles();
        window = pil_window(c0, c1);
        rp.instructions = (window > pil.overhead) ? (window - pil.overhead) : 0U;
        /* no SysTick reload inside the window (PIL_SYNC_SLACK_TICKS: from the sync's last reading to c0) */
        rp.exact = (((c1 - c0) + PIL_SYNC_SLACK_TICKS) < left) ? PIL_YES : PIL_NO;
        rp.law_instructions = aocs_pil_icount_from_ticks(out.step_cycles);
        rp.budget = pil_budget(out.law);
        rp.overrun = (rp.instructions > rp.budget) ? PIL_YES : PIL_NO;
        pil.steps++;
        if (rp.overrun != 0U) {
            pil.overruns++;
        }
        if (rp.instructions > pil.instructions_max) {
            pil.instructions_max = rp.instructions;
        }
        rp.tick = in.tick;
        rp.law = out.law;
        rp.mode = out.mode;
        rp.law_status = out.law_status;
        rp.input_status = out.input_status;
        rp.u_cmd = out.u_cmd;
        rp.u_unsat = out.u_unsat;
        rp.saturated = (out.saturated != 0) ? PIL_YES : PIL_NO;
        rp.counters = out.counters;
        rp.pil_overruns = pil.overruns;
        rp.exec_law = pil_exec.law;
        rp.exec_mode = pil_exec.mode;
        for (uint32_t i = 0U; i < AOCS_WHEELS_MAX; i++) {
            rp.u_wheels_nm[i] = out.wheels.u_s_nm[i];
        }
        rp.wheel_scale = out.wheels.scale;
        rp.wheel_limited = out.wheels.torque_limited_mask | (out.wheels.speed_limited_mask << 8U);
        rp.wheels_status = out.wheels_status;
        rp.h_total_B_Nms = out.momentum.h_total_B_Nms;
        rp.speed_margin = out.momentum.speed_margin;
        rp.estimator = pil_exec.cfg.determination.estimator;
        rp.estimate = out.estimate;
        rp.mom_policy = pil_exec.cfg.momentum.policy;
        rp.n_thrusters = (pil_exec.cfg.momentum.policy == (uint32_t)AOCS_MOM_THRUSTERS) ? pil_exec.cfg.momentum.thr_count
                                                                                         : 0U;
        rp.mom = aocs_exec_momentum(&pil_exec);
        rp.unloading = (rp.mom.unloading != 0) ? PIL_YES : PIL_NO;
        if (aocs_pil_step_reply_encode(&rp, pil_payload, AOCS_PIL_PAYLOAD_MAX) == AOCS_PIL_OK) {
            pil_send(AOCS_PIL_T_STEP_REPLY, hdr->seq, AOCS_PIL_STEP_REPLY_BYTES);
        }
    }
}

static void pil_on_select(const aocs_pil_header_t *hdr)
{
    aocs_pil_select_t s;
    aocs_pil_err_t err = aocs_pil_select_decode(&pil_rx[AOCS_PIL_HEADER_BYTES], (uint32_t)hdr->length, &s);
    if (pil.configured == 0) {
        pil_send_error(AOCS_PIL_ERR_STATE, (uint32_t)hdr->type, hdr->seq, 0U);
    } else if (err != AOCS_PIL_OK) {
        pil_send_error(err, (uint32_t)hdr->type, hdr->seq, (uint32_t)hdr->length);
    } else {
        const aocs_exec_target_t *target = (s.has_target != 0U) ? &s.target : NULL;
        const aocs_status_t st = aocs_exec_select(&pil_exec, s.law, target);
        pil_ack(AOCS_PIL_T_SELECT_ACK, hdr->seq, AOCS_PIL_OK, st, 0U);
    }
}

static void pil_on_bye(const aocs_pil_header_t *hdr)
{
    aocs_pil_bye_t b;
    b.stack_bytes = aocs_cm_stack_high_water();
    b.steps = pil.steps;
    b.instructions_max = pil.instructions_max;
    b.frame_errors = pil.frame_errors;
    if (aocs_pil_bye_encode(&b, pil_payload, AOCS_PIL_PAYLOAD_MAX) == AOCS_PIL_OK) {
        pil_send(AOCS_PIL_T_BYE, hdr->seq, AOCS_PIL_BYE_REPLY_BYTES);
    }
}

/* One received frame; returns 1 after BYE. */
static int pil_dispatch(void)
{
    aocs_pil_header_t hdr;
    int done = 0;
    if (pil_receive(&hdr) == 0) {
        const uint32_t total = AOCS_PIL_HEADER_BYTES + (uint32_t)hdr.length + AOCS_PIL_CRC_BYTES;
        const aocs_pil_err_t err = aocs_pil_frame_check(pil_rx, total, &hdr);
        if (err != AOCS_PIL_OK) {
            pil_send_error(err, (uint32_t)hdr.type, hdr.seq, (uint32_t)hdr.length);
        } else if (hdr.type == (uint8_t)AOCS_PIL_T_CONFIG) {
            pil_on_config(&hdr);
        } else if (hdr.type == (uint8_t)AOCS_PIL_T_STEP) {
            pil_on_step(&hdr);
        } else if (hdr.type == (uint8_t)AOCS_PIL_T_SELECT) {
            pil_on_select(&hdr);
        } else if ((hdr.type == (uint8_t)AOCS_PIL_T_BYE) && (hdr.length == 0U)) {
            pil_on_bye(&hdr);
            done = 1;
        } else {
            pil_send_error(AOCS_PIL_ERR_TYPE, (uint32_t)hdr.type, hdr.seq, (uint32_t)hdr.length);
        }
    }
    return done;
}

int aocs_pil_main(void)
{
    aocs_pil_hello_t hello;
    int done = 0;
    int exit_status = 0;
    pil.configured = 0;
    pil.budget_override = 0U;
    pil.steps = 0U;
    pil.overruns = 0U;
    pil.instructions_max = 0U;
    pil.frame_errors = 0U;
    pil.link_failed = 0;
    pil_calibrate(&hello);
    pil_note_link(aocs_pil_link_open());
    if ((pil.link_failed == 0) && (aocs_pil_hello_encode(&hello, pil_payload, AOCS_PIL_PAYLOAD_MAX) == AOCS_PIL_OK)) {
        pil_send(AOCS_PIL_T_HELLO, 0U, AOCS_PIL_HELLO_BYTES);
    }
    while ((done == 0) && (pil.link_failed == 0)) {
        done = pil_dispatch();
    }
    if (pil.link_failed == PIL_EXIT_EOF) {
        aocs_cm_write("aocs_pil: the host closed the link (EOF on stdin), exiting\n");
        exit_status = PIL_EXIT_EOF;
    } else if (pil.link_failed != 0) {
        aocs_cm_write("aocs_pil: a semihosting read/write failed, exiting\n");
        exit_status = PIL_EXIT_LINK;
    } else {
        exit_status = 0;
    }
    return exit_status;
}
