/*
 * Guidance mode ROTATING (aocs/guidance/guidance.h, guidance_modes.def), and
 * the rate and time helpers the SLEW mode shares.
 *
 * The target frame D turns at a constant rate w (rad/s, components in D)
 * relative to N. Its attitude obeys qd' = 0.5 Xi(qd) w (SPEC 1), whose exact
 * solution for constant w is (docs/conventions.md, kinematics)
 *     qd(t) = dq(w (t - t0)) (x) qd0,
 *     dq(theta) = [sin(|theta|/2) theta/|theta|; cos(|theta|/2)],
 * the same closed form as the plant's Plant.target(t) (sil/plant/plant.py,
 * sim time from 0). It is evaluated from the sensor time at every step, so
 * there is no accumulated drift.
 *
 * Rates seen by the laws, with qe = q (x) qd^-1 and A(qe) = A_BD:
 *     wd_B = A(qe) w                     (the rate of D in B components, so
 *                                         we = w_BN_B - wd_B is the rate of B
 *                                         relative to D: SPEC 1 we = w - wd)
 *     wd_dot_B = d/dt (A(qe) w) = dA/dt w            (w constant in D)
 *              = -(we x) A(qe) w = -we x wd_B          (dA_BD/dt = -[w_BD x] A_BD)
 *              = -(w_BN_B - wd_B) x wd_B = wd_B x w_BN_B.
 * That is the derivative of the B components the error dynamics use
 * (we' = w' - wd_dot_B, e.g. the smc law's feed-forward). With a small
 * pointing error and rate error it is ~ wd x wd = 0 (geo_hinf: |wd_dot| ~
 * |w0| |we|).
 */
#include <stddef.h>

#include "aocs/executive.h"

/*
 * Below this |theta| (rad) sin(|theta|/2)/|theta| is evaluated by its series
 * 0.5 (1 - |theta|^2/24): the next term, |theta|^4/3840 relative, is
 * < 3e-20 there, far below the rounding of either precision, and there is
 * no division by a tiny |theta|.
 */
#define GUIDANCE_SMALL_ANGLE AOCS_R(1.0e-4)

aocs_quat_t aocs_guidance_rotating_attitude(aocs_quat_t qd0_DN, aocs_vec3_t w_DN_D, real_t dt_s)
{
    const aocs_vec3_t theta = aocs_vec3_scale(w_DN_D, dt_s);
    const real_t a = aocs_vec3_norm(theta);
    real_t s;
    aocs_quat_t dq;
    if (a < GUIDANCE_SMALL_ANGLE) {
        s = AOCS_R(0.5) * (AOCS_R(1.0) - ((a * a) / AOCS_R(24.0)));
    } else {
        s = AOCS_SIN(AOCS_R(0.5) * a) / a;
    }
    dq = aocs_quat_make(s * theta.v[0], s * theta.v[1], s * theta.v[2], AOCS_COS(AOCS_R(0.5) * a));
    /* qd(t) = dq (x) qd0: dq acts on the D side (Xi(qd) w, w in D) */
    return aocs_quat_mul(dq, qd0_DN);
}

void aocs_guidance_rotating_rates(aocs_quat_t q_BN, aocs_quat_t qd_DN, aocs_vec3_t w_DN_D, aocs_vec3_t w_BN_B,
                              aocs_vec3_t *wd_B, aocs_vec3_t *wd_dot_B)
{
    aocs_quat_t qe;
    aocs_vec3_t wd = aocs_vec3_zero();
    aocs_vec3_t wd_dot = aocs_vec3_zero();
    /* A(q) of a non-unit q is |q|^2 times a rotation: normalise qe first */
    if (aocs_quat_normalize(aocs_quat_error(q_BN, qd_DN), &qe) == AOCS_OK) {
        wd = aocs_mat3_mul_vec(aocs_quat_to_dcm(qe), w_DN_D);
        wd_dot = aocs_vec3_cross(wd, w_BN_B);
    }
    if (wd_B != NULL) {
        *wd_B = wd;
    }
    if (wd_dot_B != NULL) {
        *wd_dot_B = wd_dot;
    }
}

void aocs_guidance_slew_rates(aocs_quat_t q_BN, aocs_quat_t qd_DN, aocs_vec3_t wd_D, aocs_vec3_t wd_dot_D,
                          aocs_vec3_t w_BN_B, aocs_vec3_t *wd_B, aocs_vec3_t *wd_dot_B)
{
    aocs_quat_t qe;
    aocs_vec3_t wd = aocs_vec3_zero();
    aocs_vec3_t wd_dot = aocs_vec3_zero();
    if (aocs_quat_normalize(aocs_quat_error(q_BN, qd_DN), &qe) == AOCS_OK) {
        const aocs_mat3_t a = aocs_quat_to_dcm(qe);
        wd = aocs_mat3_mul_vec(a, wd_D);
        wd_dot = aocs_vec3_add(aocs_mat3_mul_vec(a, wd_dot_D), aocs_vec3_cross(wd, w_BN_B));
    }
    if (wd_B != NULL) {
        *wd_B = wd;
    }
    if (wd_dot_B != NULL) {
        *wd_dot_B = wd_dot;
    }
}

real_t aocs_guidance_elapsed_s(uint64_t t_ns, uint64_t t0_ns)
{
    uint64_t d;
    uint64_t whole_s;
    uint64_t frac_ns;
    real_t sign;
    if (t_ns >= t0_ns) {
        d = t_ns - t0_ns;
        sign = AOCS_R(1.0);
    } else {
        d = t0_ns - t_ns;
        sign = AOCS_R(-1.0);
    }
    /* whole seconds and the ns remainder apart: each converts exactly in double
     * (and the float rounding is that of the result, not of a 1e18 ns count) */
    whole_s = d / 1000000000u;
    frac_ns = d % 1000000000u;
    return sign * ((real_t)whole_s + ((real_t)frac_ns * AOCS_R(1.0e-9)));
}

aocs_status_t aocs_guidance_rotating_check(const aocs_exec_guidance_config_t *gcfg,
                                           const aocs_exec_target_t *target, aocs_vec3_t rate_D)
{
    /* the target's own checks (a rotating target with a fixed wd/wd_dot) are the executive's
     * (AOCS_ERR_TARGET_INVALID, before this): nothing more here */
    (void)gcfg;
    (void)target;
    (void)rate_D;
    return AOCS_OK;
}

void aocs_guidance_rotating_step(aocs_guidance_t *g, const aocs_guidance_input_t *in, aocs_exec_target_t *target)
{
    const aocs_vec3_t w_D = g->rate_D;
    target->qd_DN =
        aocs_guidance_rotating_attitude(g->target.qd_DN, w_D, aocs_guidance_elapsed_s(in->t_ns, g->target_t0_ns));
    target->wd_B = aocs_vec3_zero();
    target->wd_dot_B = aocs_vec3_zero();
    if (in->usable != 0) {
        aocs_guidance_rotating_rates(in->est->q_BN, target->qd_DN, w_D, in->est->w_BN_B, &target->wd_B,
                                     &target->wd_dot_B);
    }
}
