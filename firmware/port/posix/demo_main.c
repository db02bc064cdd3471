/*
 * aocs_demo: the placeholder main job until the SIL lands (`make sil`).
 * Runs the executive with quat_pd (kp 4000, kd 8000, IRASSI inertia, SPEC 4)
 * in lockstep with an in-process rigid body, J wdot = -w x (J w) + u
 * (SPEC 1), integrated by RK4 with the command held over each period
 * (zero-order hold, SPEC 3). 100 s at 10 Hz from a 10 deg error about
 * [1 1 1]/sqrt 3 to the identity target. Prints a short table and the final
 * true pointing error; exit 0 when it is below DEMO_CONVERGED_ARCSEC.
 */
#include <stdio.h>
#include <stdlib.h>

#include "aocs/executive.h"

#define DEMO_DT_S AOCS_R(0.1)
#define DEMO_STEPS 1000u       /* 100 s at 10 Hz */
#define DEMO_SUBSTEPS 10u      /* RK4 steps per control period */
#define DEMO_PRINT_EVERY 100u  /* one table row every 10 s */
#define DEMO_RAD_TO_ARCSEC AOCS_R(206264.806)
#define DEMO_PI AOCS_R(3.14159265358979323846)
/* well inside the IRASSI settle criterion (10 arcsec, SPEC 4) */
#define DEMO_CONVERGED_ARCSEC AOCS_R(1.0)

typedef struct {
    aocs_quat_t q;
    aocs_vec3_t w;
} demo_state_t;

typedef struct {
    aocs_mat3_t j;
    aocs_mat3_t j_inv;
} demo_body_t;

/* SPEC 1: qdot = 0.5 Xi(q) w, J wdot = -w x (J w) + u */
static demo_state_t demo_derivative(const demo_body_t *b, demo_state_t x, aocs_vec3_t u)
{
    demo_state_t d;
    aocs_vec3_t h = aocs_mat3_mul_vec(b->j, x.w);
    d.q = aocs_quat_derivative(x.q, x.w);
    d.w = aocs_mat3_mul_vec(b->j_inv, aocs_vec3_add(aocs_vec3_neg(aocs_vec3_cross(x.w, h)), u));
    return d;
}

static demo_state_t demo_axpy(demo_state_t x, demo_state_t d, real_t h)
{
    demo_state_t y;
    int i;
    for (i = 0; i < 4; ++i) {
        y.q.q[i] = x.q.q[i] + (h * d.q.q[i]);
    }
    y.w = aocs_vec3_add(x.w, aocs_vec3_scale(d.w, h));
    return y;
}

static demo_state_t demo_rk4(const demo_body_t *b, demo_state_t x, aocs_vec3_t u, real_t h)
{
    demo_state_t k1 = demo_derivative(b, x, u);
    demo_state_t k2 = demo_derivative(b, demo_axpy(x, k1, AOCS_R(0.5) * h), u);
    demo_state_t k3 = demo_derivative(b, demo_axpy(x, k2, AOCS_R(0.5) * h), u);
    demo_state_t k4 = demo_derivative(b, demo_axpy(x, k3, h), u);
    demo_state_t y = x;
    aocs_quat_t qn;
    int i;
    for (i = 0; i < 4; ++i) {
        y.q.q[i] += (h / AOCS_R(6.0)) *
                    (k1.q.q[i] + (AOCS_R(2.0) * k2.q.q[i]) + (AOCS_R(2.0) * k3.q.q[i]) + k4.q.q[i]);
    }
    for (i = 0; i < 3; ++i) {
        y.w.v[i] += (h / AOCS_R(6.0)) *
                    (k1.w.v[i] + (AOCS_R(2.0) * k2.w.v[i]) + (AOCS_R(2.0) * k3.w.v[i]) + k4.w.v[i]);
    }
    /* SPEC 3: renormalised RK4 */
    if (aocs_quat_normalize(y.q, &qn) == AOCS_OK) {
        y.q = qn;
    }
    return y;
}

/* Closed loop of DEMO_STEPS periods; the final true pointing error in *err_arcsec. */
static aocs_status_t demo_run(aocs_exec_t *exec, const demo_body_t *body, uint64_t period_ns, real_t *err_arcsec)
{
    aocs_status_t st = AOCS_OK;
    aocs_exec_output_t out;
    aocs_exec_input_t in;
    demo_state_t x;
    real_t half = AOCS_R(5.0) * DEMO_PI / AOCS_R(180.0);
    real_t s = AOCS_SIN(half) / AOCS_SQRT(AOCS_R(3.0));

    x.q = aocs_quat_make(s, s, s, AOCS_COS(half));
    x.w = aocs_vec3_zero();
    (void)printf("%8s %16s %12s %12s %12s %8s\n", "t [s]", "error [arcsec]", "ux [N m]", "uy [N m]", "uz [N m]",
                 "mode");
    for (uint32_t k = 0u; (k <= DEMO_STEPS) && (st == AOCS_OK); ++k) {
        in.tick = k;
        in.t_sensor_ns = (uint64_t)k * period_ns;
        in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
        in.q_BN = x.q;
        in.w_BN_B = x.w;
        in.pos_m = aocs_vec3_zero();
        in.vel_mps = aocs_vec3_zero();
        st = aocs_exec_step(exec, &in, &out);
        /* SPEC 1: true pointing angle 2 asin(|qe_vec|), target = identity */
        *err_arcsec = aocs_quat_angle(x.q) * DEMO_RAD_TO_ARCSEC;
        if ((st == AOCS_OK) && ((k % DEMO_PRINT_EVERY) == 0u)) {
            (void)printf("%8.1f %16.6g %12.5g %12.5g %12.5g %8s\n", (double)k * (double)DEMO_DT_S,
                         (double)*err_arcsec, (double)out.u_cmd.v[0], (double)out.u_cmd.v[1],
                         (double)out.u_cmd.v[2], aocs_exec_mode_name(out.mode));
        }
        if ((st == AOCS_OK) && (k < DEMO_STEPS)) {
            for (uint32_t n = 0u; n < DEMO_SUBSTEPS; ++n) {
                x = demo_rk4(body, x, out.u_cmd, DEMO_DT_S / (real_t)DEMO_SUBSTEPS);
            }
        }
    }
    if (st == AOCS_OK) {
        (void)printf("steps %u, max step time %llu ns, overruns %u, mode transitions %u, saturated steps %u\n",
                     (unsigned)out.counters.steps, (unsigned long long)out.counters.step_time_max_ns,
                     (unsigned)out.counters.overrun, (unsigned)out.counters.mode_transitions,
                     (unsigned)out.counters.saturated);
    }
    return st;
}

int main(void)
{
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    demo_body_t body;
    aocs_status_t st;
    uint64_t period_ns = 0u;
    real_t err_arcsec = AOCS_REAL_MAX;
    int rc = EXIT_FAILURE;

    body.j = aocs_mat3_diag(aocs_vec3_make(AOCS_R(2059.5), AOCS_R(5954.2), AOCS_R(5974.3)));
    aocs_exec_config_default(&cfg);
    cfg.period_s = DEMO_DT_S;
    cfg.law = AOCS_LAW_QUAT_PD;
    cfg.laws.quat_pd.kp = AOCS_R(4000.0);
    cfg.laws.quat_pd.kd = AOCS_R(8000.0);
    /* IRASSI reference torques are hundreds of N m (SPEC 4); this limit does not bind here */
    cfg.u_max_axis = aocs_vec3_make(AOCS_R(1000.0), AOCS_R(1000.0), AOCS_R(1000.0));

    st = aocs_mat3_inverse(body.j, &body.j_inv);
    if (st == AOCS_OK) {
        st = aocs_exec_init(&exec, &cfg);
    }
    if (st == AOCS_OK) {
        st = aocs_exec_period_to_ns(cfg.period_s, &period_ns);
    }
    if (st == AOCS_OK) {
        (void)printf("aocs_demo: executive + %s, IRASSI inertia, 10 deg initial error, %u steps at %.0f Hz\n",
                     aocs_law_name(cfg.law), (unsigned)DEMO_STEPS, 1.0 / (double)DEMO_DT_S);
        st = demo_run(&exec, &body, period_ns, &err_arcsec);
    }
    if (st != AOCS_OK) {
        (void)fprintf(stderr, "aocs_demo: failed: %s\n", aocs_status_name(st));
    } else {
        const char *verdict = "no";
        if (err_arcsec < DEMO_CONVERGED_ARCSEC) {
            verdict = "yes";
            rc = EXIT_SUCCESS;
        }
        (void)printf("final pointing error: %.6g arcsec (converged below %.3g arcsec: %s)\n", (double)err_arcsec,
                     (double)DEMO_CONVERGED_ARCSEC, verdict);
    }
    return rc;
}
