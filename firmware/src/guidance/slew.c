/*
 * Rest-to-rest eigenaxis slew guidance (aocs/guidance/slew.h; docs/spec.md
 * "Slew guidance"). All evaluation is closed form in the time since the
 * command, so the reference has no accumulated drift.
 */
#include <stddef.h>

#include "aocs/control/law_io.h"
#include "aocs/guidance/slew.h"

/* Below this |dq_vec| the slew has no usable axis: a zero-length slew (angle ~ 2e-12 rad double, 2e-6 float). */
#if defined(AOCS_REAL_IS_FLOAT)
#define SLEW_AXIS_MIN AOCS_R(1.0e-6)
#else
#define SLEW_AXIS_MIN AOCS_R(1.0e-12)
#endif

static real_t max_r(real_t a, real_t b)
{
    return ((a > b) ? a : b);
}

static real_t min_r(real_t a, real_t b)
{
    return ((a < b) ? a : b);
}

aocs_status_t aocs_slew_config_check(const aocs_slew_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (cfg == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (((int)cfg->profile < 0) || (cfg->profile >= AOCS_SLEW_PROFILE_COUNT)) {
        st = AOCS_ERR_GUIDANCE_PROFILE_INVALID;
    } else if (!AOCS_IS_FINITE(cfg->margin) || !(cfg->margin > AOCS_R(0.0)) || (cfg->margin > AOCS_R(1.0))) {
        st = AOCS_ERR_GUIDANCE_MARGIN_INVALID;
    } else if (!AOCS_IS_FINITE(cfg->rate_limit_radps) || (cfg->rate_limit_radps < AOCS_R(0.0))) {
        st = AOCS_ERR_GUIDANCE_RATE_LIMIT_INVALID;
    } else if (!AOCS_IS_FINITE(cfg->jerk_time_s) || (cfg->jerk_time_s < AOCS_R(0.0)) ||
               (cfg->jerk_time_s > (real_t)AOCS_SLEW_JERK_TIME_MAX_S) ||
               ((cfg->profile == AOCS_SLEW_PROFILE_JERK_LIMITED) && !(cfg->jerk_time_s > AOCS_R(0.0))) ||
               ((cfg->profile == AOCS_SLEW_PROFILE_BANG_COAST_BANG) && (cfg->jerk_time_s > AOCS_R(0.0)))) {
        st = AOCS_ERR_GUIDANCE_JERK_TIME_INVALID;
    } else {
        st = aocs_mat3_check_inertia(cfg->inertia_kgm2);
    }
    return st;
}

real_t aocs_slew_alpha_box(aocs_vec3_t u_max_axis_Nm, aocs_vec3_t a, aocs_vec3_t b)
{
    real_t alpha = AOCS_REAL_MAX;
    int bad = 0;
    for (int i = 0; i < 3; ++i) {
        /* |alpha (+-a_i + s b_i)| <= alpha (|a_i| + |b_i|) for s in [0, 1], equality at a vertex */
        const real_t need = AOCS_FABS(a.v[i]) + AOCS_FABS(b.v[i]);
        if (!AOCS_IS_FINITE(need) || !AOCS_IS_FINITE(u_max_axis_Nm.v[i])) {
            bad = 1;
        } else if (need > AOCS_R(0.0)) {
            alpha = min_r(alpha, u_max_axis_Nm.v[i] / need);
        } else {
            /* this axis carries no reference torque */
        }
    }
    return ((bad != 0) ? AOCS_R(0.0) : alpha);
}

real_t aocs_slew_alpha_norm(real_t u_max_norm_Nm, aocs_vec3_t a, aocs_vec3_t b)
{
    /* |.| is convex: over conv{+-a, +-a + b} its maximum is at a vertex, |a + b| or |a - b| (>= |a|) */
    const real_t need = max_r(aocs_vec3_norm(aocs_vec3_add(a, b)), aocs_vec3_norm(aocs_vec3_sub(a, b)));
    real_t alpha = AOCS_R(0.0);
    if ((AOCS_IS_FINITE(need)) && (AOCS_IS_FINITE(u_max_norm_Nm))) {
        if (need > AOCS_R(0.0)) {
            alpha = u_max_norm_Nm / need;
        } else {
            alpha = AOCS_REAL_MAX; /* no reference torque: the ball does not bound alpha */
        }
    }
    return alpha;
}

real_t aocs_slew_alpha_max(const aocs_slew_envelope_t *env, aocs_mat3_t inertia_kgm2, aocs_vec3_t e,
                           real_t theta_f_rad)
{
    real_t alpha = AOCS_REAL_MAX;
    int any = 0;
    if (env != NULL) {
        const aocs_vec3_t a = aocs_mat3_mul_vec(inertia_kgm2, e);
        const aocs_vec3_t b = aocs_vec3_scale(aocs_vec3_cross(e, a), theta_f_rad);
        if (aocs_vec3_norm_inf(env->u_max_axis_Nm) > AOCS_R(0.0)) {
            alpha = min_r(alpha, aocs_slew_alpha_box(env->u_max_axis_Nm, a, b));
            any = 1;
        }
        if (env->u_max_norm_Nm > AOCS_R(0.0)) {
            alpha = min_r(alpha, aocs_slew_alpha_norm(env->u_max_norm_Nm, a, b));
            any = 1;
        }
        if ((env->wheels != NULL) && (env->wheels->initialised != 0)) {
            /* the wheel kind (docs/spec.md 5.3.1): the allocation must deliver the reference unscaled */
            alpha = min_r(alpha, aocs_wheels_alpha_envelope(env->wheels, a, b));
            any = 1;
        }
    }
    if ((any == 0) || !AOCS_IS_FINITE(alpha)) {
        alpha = AOCS_R(0.0);
    }
    return alpha;
}

/* A slew of zero length at qf (the reference is the target itself). */
static void slew_zero(aocs_slew_t *slew, aocs_quat_t q0, aocs_quat_t qf)
{
    slew->q0_BN = q0;
    slew->qf_DN = qf;
    slew->e = aocs_vec3_make(AOCS_R(1.0), AOCS_R(0.0), AOCS_R(0.0));
    slew->theta_f_rad = AOCS_R(0.0);
    slew->accel_radps2 = AOCS_R(0.0);
    slew->jerk_time_s = AOCS_R(0.0);
    slew->hold_s = AOCS_R(0.0);
    slew->pulse_s = AOCS_R(0.0);
    slew->coast_s = AOCS_R(0.0);
    slew->rate_radps = AOCS_R(0.0);
    slew->t_end_s = AOCS_R(0.0);
}

/*
 * Timing of the profile for angle th, acceleration bound alpha, ramp time tj,
 * rate limit w (0 = none). Each acceleration pulse (ramp up over tj, hold,
 * ramp down over tj) takes the rate from 0 to v; its rate curve is
 * antisymmetric about v/2, so it covers v * pulse / 2, and the two pulses
 * together cover v * pulse; the coast covers the rest at v.
 *   No coast, peak acceleration reached (th >= 2 alpha tj^2):
 *       v (v / alpha + tj) = th  ->  v = alpha (sqrt(tj^2 + 4 th / alpha) - tj) / 2
 *       (tj = 0: v = sqrt(alpha th), the bang-bang peak rate);
 *   a short slew (th < 2 alpha tj^2) keeps the ramp time and lowers the peak
 *   acceleration to th / (2 tj^2) (triangular pulses, v = th / (2 tj)), so the
 *   jerk stays at most alpha / tj.
 * The rate limit caps v; the peak acceleration is then min(alpha, v / tj).
 */
static void slew_timing(aocs_slew_t *slew, real_t th, real_t alpha, real_t tj, real_t w)
{
    real_t v;
    real_t ap;
    if (th >= (AOCS_R(2.0) * alpha * tj * tj)) {
        v = AOCS_R(0.5) * alpha * (AOCS_SQRT((tj * tj) + ((AOCS_R(4.0) * th) / alpha)) - tj);
    } else {
        v = th / (AOCS_R(2.0) * tj); /* th < 2 alpha tj^2 implies tj > 0 */
    }
    if ((w > AOCS_R(0.0)) && (w < v)) {
        v = w;
    }
    ap = alpha;
    if ((tj > AOCS_R(0.0)) && ((v / tj) < alpha)) {
        ap = v / tj;
    }
    slew->accel_radps2 = ap;
    slew->jerk_time_s = tj;
    slew->rate_radps = v;
    slew->hold_s = max_r((v / ap) - tj, AOCS_R(0.0));
    slew->pulse_s = slew->hold_s + (AOCS_R(2.0) * tj);
    slew->coast_s = max_r((th / v) - slew->pulse_s, AOCS_R(0.0));
    slew->t_end_s = (AOCS_R(2.0) * slew->pulse_s) + slew->coast_s;
}

aocs_status_t aocs_slew_plan(aocs_slew_t *slew, const aocs_slew_config_t *cfg, const aocs_slew_envelope_t *env,
                             aocs_quat_t q0_BN, aocs_quat_t qf_DN)
{
    aocs_status_t st = AOCS_OK;
    aocs_quat_t q0 = aocs_quat_identity();
    aocs_quat_t qf = aocs_quat_identity();
    if ((slew == NULL) || (cfg == NULL) || (env == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        int q0_ok = 0;
        int qf_ok = 0;
        if ((aocs_quat_is_finite(q0_BN) != 0) && (AOCS_FABS(aocs_quat_norm(q0_BN) - AOCS_R(1.0)) <= AOCS_QUAT_UNIT_TOL)) {
            q0_ok = 1;
        }
        if ((aocs_quat_is_finite(qf_DN) != 0) && (AOCS_FABS(aocs_quat_norm(qf_DN) - AOCS_R(1.0)) <= AOCS_QUAT_UNIT_TOL)) {
            qf_ok = 1;
        }
        if ((q0_ok == 0) || (qf_ok == 0) || (aocs_quat_normalize(q0_BN, &q0) != AOCS_OK) ||
            (aocs_quat_normalize(qf_DN, &qf) != AOCS_OK)) {
            st = AOCS_ERR_QUAT_NOT_UNIT;
        } else {
            st = aocs_slew_config_check(cfg);
        }
        /* the end of the slew is the target exactly as commanded (bit for bit the step-mode target) */
        slew_zero(slew, q0, (qf_ok != 0) ? qf_DN : qf);
    }
    if (st == AOCS_OK) {
        /* SPEC 5.1: dq = qd_f (x) q0^-1, short way */
        aocs_quat_t dq = aocs_quat_mul(qf, aocs_quat_conj(q0));
        aocs_vec3_t dv;
        real_t s;
        if (dq.q[3] < AOCS_R(0.0)) {
            dq = aocs_quat_make(-dq.q[0], -dq.q[1], -dq.q[2], -dq.q[3]);
        }
        dv = aocs_quat_vec(dq);
        s = aocs_vec3_norm(dv);
        if (s > SLEW_AXIS_MIN) {
            const real_t th = AOCS_R(2.0) * AOCS_ATAN2(s, dq.q[3]);
            const aocs_vec3_t e = aocs_vec3_scale(dv, AOCS_R(1.0) / s);
            const real_t alpha = cfg->margin * aocs_slew_alpha_max(env, cfg->inertia_kgm2, e, th);
            if (!AOCS_IS_FINITE(alpha) || !(alpha > AOCS_R(0.0))) {
                st = AOCS_ERR_GUIDANCE_ENVELOPE_INVALID;
            } else {
                slew->e = e;
                slew->theta_f_rad = th;
                slew_timing(slew, th, alpha, cfg->jerk_time_s, cfg->rate_limit_radps);
                if (!AOCS_IS_FINITE(slew->t_end_s)) {
                    st = AOCS_ERR_GUIDANCE_ENVELOPE_INVALID;
                    slew_zero(slew, q0, qf_DN);
                }
            }
        }
    }
    return st;
}

/*
 * One acceleration pulse from rest, at tau in [0, pulse]: acceleration,
 * rate and angle. Ramp up (jerk j = ap / tj), hold at ap, ramp down; the
 * ramp down is written from the pulse end (r = pulse - tau) by the pulse's
 * symmetry, so the end values are exact: rate v, angle v pulse / 2.
 */
static void pulse_eval(const aocs_slew_t *s, real_t tau, real_t *acc, real_t *rate, real_t *ang)
{
    const real_t tj = s->jerk_time_s;
    const real_t ap = s->accel_radps2;
    const real_t v = s->rate_radps;
    real_t j = AOCS_R(0.0);
    if (tj > AOCS_R(0.0)) {
        j = ap / tj;
    }
    if (tau < tj) {
        *acc = j * tau;
        *rate = AOCS_R(0.5) * j * tau * tau;
        *ang = (j * tau * tau * tau) / AOCS_R(6.0);
    } else if (tau < (tj + s->hold_s)) {
        const real_t h = tau - tj;
        const real_t v1 = AOCS_R(0.5) * ap * tj;
        *acc = ap;
        *rate = v1 + (ap * h);
        *ang = ((ap * tj * tj) / AOCS_R(6.0)) + (v1 * h) + (AOCS_R(0.5) * ap * h * h);
    } else {
        const real_t r = max_r(s->pulse_s - tau, AOCS_R(0.0));
        if (tj > AOCS_R(0.0)) {
            *acc = j * r;
            *rate = v - (AOCS_R(0.5) * j * r * r);
            *ang = (AOCS_R(0.5) * v * s->pulse_s) - ((v * r) - ((j * r * r * r) / AOCS_R(6.0)));
        } else {
            /* bang-coast-bang: the hold ends the pulse exactly */
            *acc = ap;
            *rate = v;
            *ang = AOCS_R(0.5) * v * s->pulse_s;
        }
    }
}

void aocs_slew_eval(const aocs_slew_t *slew, real_t t_s, aocs_slew_ref_t *ref)
{
    if ((slew != NULL) && (ref != NULL)) {
        real_t acc = AOCS_R(0.0);
        real_t rate = AOCS_R(0.0);
        real_t ang = AOCS_R(0.0);
        const real_t t_dec = slew->pulse_s + slew->coast_s; /* start of the deceleration pulse */
        if (t_s >= slew->t_end_s) {
            ref->qd_DN = slew->qf_DN;
            ref->wd_D = aocs_vec3_zero();
            ref->wd_dot_D = aocs_vec3_zero();
            ref->theta_rad = slew->theta_f_rad;
            ref->theta_dot_radps = AOCS_R(0.0);
            ref->theta_ddot_radps2 = AOCS_R(0.0);
        } else {
            if (!(t_s >= AOCS_R(0.0))) {
                /* before the command (or NaN): at rest at the start */
            } else if (t_s < slew->pulse_s) {
                pulse_eval(slew, t_s, &acc, &rate, &ang);
            } else if (t_s < t_dec) {
                rate = slew->rate_radps;
                ang = (AOCS_R(0.5) * slew->rate_radps * slew->pulse_s) + (slew->rate_radps * (t_s - slew->pulse_s));
            } else {
                /* the deceleration mirrors the acceleration in time from the end */
                pulse_eval(slew, slew->t_end_s - t_s, &acc, &rate, &ang);
                acc = -acc;
                ang = slew->theta_f_rad - ang;
            }
            ang = min_r(max_r(ang, AOCS_R(0.0)), slew->theta_f_rad);
            {
                const real_t h = AOCS_R(0.5) * ang;
                const real_t sh = AOCS_SIN(h);
                const aocs_quat_t dq =
                    aocs_quat_make(sh * slew->e.v[0], sh * slew->e.v[1], sh * slew->e.v[2], AOCS_COS(h));
                /* qd(t) = dq_e(theta) (x) q0 (SPEC 5.1) */
                ref->qd_DN = aocs_quat_mul(dq, slew->q0_BN);
            }
            ref->wd_D = aocs_vec3_scale(slew->e, rate);
            ref->wd_dot_D = aocs_vec3_scale(slew->e, acc);
            ref->theta_rad = ang;
            ref->theta_dot_radps = rate;
            ref->theta_ddot_radps2 = acc;
        }
    }
}

aocs_vec3_t aocs_slew_feedforward(aocs_mat3_t inertia_kgm2, aocs_vec3_t wd, aocs_vec3_t wd_dot,
                                  aocs_vec3_t h_wheels_Nms)
{
    const aocs_vec3_t h = aocs_vec3_add(aocs_mat3_mul_vec(inertia_kgm2, wd), h_wheels_Nms);
    return aocs_vec3_add(aocs_mat3_mul_vec(inertia_kgm2, wd_dot), aocs_vec3_cross(wd, h));
}
