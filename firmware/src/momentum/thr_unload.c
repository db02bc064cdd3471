/*
 * Momentum policy THRUSTERS (row of aocs/momentum/momentum.def; docs/spec.md
 * 5.9.3): a dumping torque opposing the wheel momentum error dh,
 *
 *     tau_d = -(dh / |dh|) min(dump_torque_nm, |dh| / dt)      (never more than dh in one period),
 *
 * allocated to thruster on-times by pulse-width modulation over the control
 * period. Thruster i at full thrust F applies the torque t_i = F (r_i x d_i)
 * (the rows mom.thr_arm_*_m hold r_i x d_i). At init, for each signed body
 * axis s e_k the least-propellant non-negative duty vector c with
 * sum_i c_i t_i = s e_k (per N m) is found among the basic solutions of that
 * linear programme: every invertible triple of thruster torques (the torque
 * mapping of Basilisk's thrForceMapping, non-negative by construction). A step's duties are
 * f = sum_k |tau_k| c_(sign tau_k, k), scaled down together when one exceeds 1
 * (the direction of tau kept), on-times t_i = f_i dt quantised to
 * thr_quantum_s and dropped below thr_min_on_s (the minimum impulse bit); what
 * was requested and not fired is added to the next period's request while
 * the unload lasts (error feedback: over many periods the impulse delivered
 * follows the impulse requested to within one minimum pulse per thruster).
 * The torque of the quantised on-times, sum_i (t_i / dt) t_i, is fed forward
 * to the wheels.
 */
#include <stddef.h>

#include "aocs/executive.h"

/* Torque of thruster i at full thrust, N m. */
static aocs_vec3_t thr_torque(const aocs_mom_config_t *c, uint32_t i)
{
    const aocs_vec3_t arm = {{c->thr_arm_x_m[i], c->thr_arm_y_m[i], c->thr_arm_z_m[i]}};
    return aocs_vec3_scale(arm, c->thr_thrust_N);
}

static aocs_status_t thr_check(const aocs_mom_config_t *c)
{
    aocs_status_t st = AOCS_OK;
    if ((c->thr_count < 3u) || (c->thr_count > AOCS_MOM_THRUSTERS_MAX) ||
        !(AOCS_IS_FINITE(c->thr_thrust_N) && (c->thr_thrust_N > AOCS_R(0.0))) ||
        !(AOCS_IS_FINITE(c->dump_torque_Nm) && (c->dump_torque_Nm > AOCS_R(0.0))) ||
        !(AOCS_IS_FINITE(c->thr_min_on_s) && (c->thr_min_on_s >= AOCS_R(0.0))) ||
        !(AOCS_IS_FINITE(c->thr_quantum_s) && (c->thr_quantum_s >= AOCS_R(0.0)))) {
        st = AOCS_ERR_MOMENTUM_CONFIG_INVALID;
    } else {
        for (uint32_t i = 0u; i < c->thr_count; ++i) {
            if (aocs_vec3_is_finite(thr_torque(c, i)) == 0) {
                st = AOCS_ERR_MOMENTUM_CONFIG_INVALID;
            }
        }
    }
    return st;
}

/* The cheapest duty vector giving the unit torque e among the invertible triples; 1 when one exists. */
static int thr_axis_alloc(const aocs_mom_config_t *c, aocs_vec3_t e, real_t tmax, real_t *duty)
{
    const uint32_t n = c->thr_count;
    const real_t det_min = AOCS_R(1.0e-6) * tmax * tmax * tmax;
    real_t best = AOCS_REAL_MAX;
    int found = 0;
    for (uint32_t i = 0u; i < n; ++i) {
        for (uint32_t j = i + 1u; j < n; ++j) {
            for (uint32_t l = j + 1u; l < n; ++l) {
                const aocs_vec3_t ti = thr_torque(c, i);
                const aocs_vec3_t tj = thr_torque(c, j);
                const aocs_vec3_t tl = thr_torque(c, l);
                /* columns ti tj tl; Cramer's rule */
                const real_t det = aocs_vec3_dot(ti, aocs_vec3_cross(tj, tl));
                if (AOCS_FABS(det) > det_min) {
                    const real_t ci = aocs_vec3_dot(e, aocs_vec3_cross(tj, tl)) / det;
                    const real_t cj = aocs_vec3_dot(ti, aocs_vec3_cross(e, tl)) / det;
                    const real_t cl = aocs_vec3_dot(ti, aocs_vec3_cross(tj, e)) / det;
                    const real_t tol = AOCS_R(-1.0e-6) / tmax;
                    const real_t cost = ci + cj + cl;
                    if ((ci >= tol) && (cj >= tol) && (cl >= tol) && (cost < best)) {
                        best = cost;
                        for (uint32_t k = 0u; k < AOCS_MOM_THRUSTERS_MAX; ++k) {
                            duty[k] = AOCS_R(0.0);
                        }
                        duty[i] = (ci > AOCS_R(0.0)) ? ci : AOCS_R(0.0);
                        duty[j] = (cj > AOCS_R(0.0)) ? cj : AOCS_R(0.0);
                        duty[l] = (cl > AOCS_R(0.0)) ? cl : AOCS_R(0.0);
                        found = 1;
                    }
                }
            }
        }
    }
    return found;
}

aocs_status_t aocs_mom_thr_init(aocs_mom_t *m)
{
    aocs_status_t st = thr_check(&m->cfg);
    if (st == AOCS_OK) {
        real_t tmax = AOCS_R(0.0);
        for (uint32_t i = 0u; i < m->cfg.thr_count; ++i) {
            const real_t t = aocs_vec3_norm(thr_torque(&m->cfg, i));
            tmax = (t > tmax) ? t : tmax;
        }
        if (!(tmax > AOCS_R(0.0))) {
            st = AOCS_ERR_MOMENTUM_CONFIG_INVALID;
        }
        for (uint32_t s = 0u; (st == AOCS_OK) && (s < AOCS_MOM_AXES_SIGNED); ++s) {
            aocs_vec3_t e = aocs_vec3_zero();
            e.v[s / 2u] = ((s % 2u) == 0u) ? AOCS_R(1.0) : AOCS_R(-1.0);
            if (thr_axis_alloc(&m->cfg, e, tmax, m->thr_alloc[s]) == 0) {
                st = AOCS_ERR_MOMENTUM_THRUSTERS_NOT_SPANNING;
            }
        }
    }
    return st;
}

/* On-time of a requested on-time t over dt: quantised to q (0 = none), below t_min dropped, within [0, dt]. */
static real_t thr_on_time(real_t t_req, real_t dt, real_t q, real_t t_min)
{
    real_t t = t_req;
    if ((q > AOCS_R(0.0)) && ((t / q) < AOCS_R(4.0e9))) {
        const uint32_t k = (uint32_t)((t / q) + AOCS_R(0.5));
        t = (real_t)k * q;
    }
    if (t > dt) {
        t = dt;
    }
    if ((t < t_min) || !(t > AOCS_R(0.0))) {
        t = AOCS_R(0.0);
    }
    return t;
}

aocs_status_t aocs_mom_thr_step(aocs_mom_t *m, const aocs_mom_input_t *in)
{
    aocs_status_t st = AOCS_OK;
    aocs_mom_output_t *out = &m->out;
    const aocs_mom_config_t *c = &m->cfg;
    const real_t dh_norm = aocs_vec3_norm(out->dh_B_Nms);
    if (!AOCS_IS_FINITE(dh_norm)) {
        st = AOCS_ERR_INPUT_NOT_FINITE;
    } else if (dh_norm > AOCS_R(0.0)) {
        const real_t dt = in->dt_s;
        const real_t mag = (c->dump_torque_Nm < (dh_norm / dt)) ? c->dump_torque_Nm : (dh_norm / dt);
        const aocs_vec3_t tau = aocs_vec3_scale(out->dh_B_Nms, -mag / dh_norm);
        real_t duty[AOCS_MOM_THRUSTERS_MAX];
        real_t fmax = AOCS_R(0.0);
        aocs_vec3_t u = aocs_vec3_zero();
        for (uint32_t i = 0u; i < AOCS_MOM_THRUSTERS_MAX; ++i) {
            duty[i] = AOCS_R(0.0);
        }
        for (uint32_t k = 0u; k < 3u; ++k) {
            const uint32_t s = (2u * k) + ((tau.v[k] < AOCS_R(0.0)) ? 1u : 0u);
            const real_t a = AOCS_FABS(tau.v[k]);
            for (uint32_t i = 0u; i < c->thr_count; ++i) {
                duty[i] += a * m->thr_alloc[s][i];
            }
        }
        for (uint32_t i = 0u; i < c->thr_count; ++i) {
            fmax = (duty[i] > fmax) ? duty[i] : fmax;
        }
        for (uint32_t i = 0u; i < c->thr_count; ++i) {
            const real_t f = (fmax > AOCS_R(1.0)) ? (duty[i] / fmax) : duty[i];
            const real_t t_req = (f * dt) + m->thr_residual_s[i];
            const real_t t_on = thr_on_time(t_req, dt, c->thr_quantum_s, c->thr_min_on_s);
            real_t rest = t_req - t_on;
            rest = (rest > dt) ? dt : rest;
            m->thr_residual_s[i] = (rest < -dt) ? -dt : rest;
            out->thruster_on_s[i] = t_on;
            u = aocs_vec3_add(u, aocs_vec3_scale(thr_torque(c, i), t_on / dt));
        }
        out->u_unload_B_Nm = u;
    } else {
        st = AOCS_OK; /* nothing to dump */
    }
    return st;
}
