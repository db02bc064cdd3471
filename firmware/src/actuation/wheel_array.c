/*
 * Reaction wheel array (wheel_array.h; docs/spec.md 5.3). Gs^+ is computed
 * once at init; every step is a 6 x 3 product, one scale and a few compares.
 */
#include <stddef.h>

#include "aocs/actuation/wheel_array.h"

/* | |g| - 1 | above this is not a unit axis (the scenario loader writes axes unit to 1e-9) */
#define WHEEL_AXIS_UNIT_TOL AOCS_R(1.0e-4)
/* det(Gs Gs^T) of unit axes below this: the healthy axes are (nearly) coplanar. For three orthogonal
 * axes det = 1, for the SPEC 5.3 pyramid 16/27 (four) and about 0.15 (three); 1e-6 means a pseudo-inverse
 * gain above ~1e3 per N m, which no real array has. */
#define WHEEL_SPAN_DET_MIN AOCS_R(1.0e-6)

/* The share of the torque room left by the body torque that the null-space management may use (spec 5.3.2):
 * half, so it never takes a wheel to its bound on its own and the body torque keeps the other half of any
 * transient margin. */
#define WHEEL_NULL_ROOM_SHARE AOCS_R(0.5)

static uint32_t wheel_bit(uint32_t i)
{
    return (uint32_t)1u << i;
}

static int wheel_healthy(const aocs_wheels_config_t *cfg, uint32_t i)
{
    return ((cfg->failed_mask & wheel_bit(i)) == 0u) ? 1 : 0;
}

void aocs_wheels_config_default(aocs_wheels_config_t *cfg)
{
    if (cfg != NULL) {
        cfg->n = 0u;
        for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
            cfg->axis_B[i] = aocs_vec3_zero();
            cfg->js_kgm2[i] = AOCS_R(0.0);
            cfg->u_max_nm[i] = AOCS_R(0.0);
            cfg->omega_max_radps[i] = AOCS_R(0.0);
            cfg->viscous_nms[i] = AOCS_R(0.0);
            cfg->coulomb_nm[i] = AOCS_R(0.0);
            cfg->coulomb_width_radps[i] = AOCS_R(0.1);
            cfg->null_speed_radps[i] = AOCS_R(0.0);
        }
        cfg->null_gain_per_s = AOCS_R(0.0);
        cfg->failed_mask = 0u;
        cfg->period_s = AOCS_R(0.1);
        cfg->inertia_B_kgm2 = aocs_mat3_identity();
    }
}

static aocs_status_t wheels_check_wheel(const aocs_wheels_config_t *cfg, uint32_t i)
{
    aocs_status_t st = AOCS_OK;
    aocs_vec3_t g = cfg->axis_B[i];
    if ((aocs_vec3_is_finite(g) == 0) || (AOCS_FABS(aocs_vec3_norm(g) - AOCS_R(1.0)) > WHEEL_AXIS_UNIT_TOL)) {
        st = AOCS_ERR_WHEEL_AXIS_NOT_UNIT;
    } else if (!(AOCS_IS_FINITE(cfg->js_kgm2[i]) && (cfg->js_kgm2[i] > AOCS_R(0.0)))) {
        st = AOCS_ERR_WHEEL_INERTIA_NOT_POSITIVE;
    } else if (!(AOCS_IS_FINITE(cfg->u_max_nm[i]) && (cfg->u_max_nm[i] > AOCS_R(0.0)) &&
                 AOCS_IS_FINITE(cfg->omega_max_radps[i]) && (cfg->omega_max_radps[i] > AOCS_R(0.0)))) {
        st = AOCS_ERR_WHEEL_LIMIT_NOT_POSITIVE;
    } else {
        st = AOCS_OK;
    }
    return st;
}

/* The friction model and the null-space target of wheel i (docs/spec.md 5.3.2), after its limits passed. */
static aocs_status_t wheels_check_model(const aocs_wheels_config_t *cfg, uint32_t i)
{
    aocs_status_t st = AOCS_OK;
    const real_t b = cfg->viscous_nms[i];
    const real_t c = cfg->coulomb_nm[i];
    const real_t eps = cfg->coulomb_width_radps[i];
    const real_t target = cfg->null_speed_radps[i];
    if (!(AOCS_IS_FINITE(b) && (b >= AOCS_R(0.0)) && AOCS_IS_FINITE(c) && (c >= AOCS_R(0.0)))) {
        st = AOCS_ERR_WHEEL_FRICTION_NEGATIVE;
    } else if (!(AOCS_IS_FINITE(eps) && (eps > AOCS_R(0.0)))) {
        st = AOCS_ERR_WHEEL_FRICTION_WIDTH_NOT_POSITIVE;
    } else if (!(((b * cfg->omega_max_radps[i]) + c) < cfg->u_max_nm[i])) {
        /* |f^| <= b Omega_max + c (the model's speed is clamped): below u_s,max there is always motor torque
         * left for the attitude loop after the compensation (and a finite product: b, Omega_max finite) */
        st = AOCS_ERR_WHEEL_FRICTION_EXCEEDS_LIMIT;
    } else if (!(AOCS_IS_FINITE(target) && (AOCS_FABS(target) < cfg->omega_max_radps[i]))) {
        st = AOCS_ERR_WHEEL_NULL_SPEED_INVALID;
    } else {
        st = AOCS_OK;
    }
    return st;
}

static aocs_status_t wheels_check(const aocs_wheels_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if ((cfg->n < AOCS_WHEELS_MIN) || (cfg->n > AOCS_WHEELS_MAX)) {
        st = AOCS_ERR_WHEEL_COUNT;
    } else if ((cfg->failed_mask >> cfg->n) != 0u) {
        st = AOCS_ERR_WHEEL_FAILED_MASK;
    } else {
        for (uint32_t i = 0u; (i < cfg->n) && (st == AOCS_OK); ++i) {
            st = wheels_check_wheel(cfg, i);
        }
    }
    if (st == AOCS_OK) {
        if (!(AOCS_IS_FINITE(cfg->period_s) && (cfg->period_s > AOCS_R(0.0)))) {
            st = AOCS_ERR_DT_INVALID;
        } else {
            st = aocs_mat3_check_inertia(cfg->inertia_B_kgm2);
        }
    }
    return st;
}

/* The feedforward's model and the null-space management (checked after the array spans the three axes). */
static aocs_status_t wheels_check_compensation(const aocs_wheels_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    for (uint32_t i = 0u; (i < cfg->n) && (st == AOCS_OK); ++i) {
        st = wheels_check_model(cfg, i);
    }
    if (st == AOCS_OK) {
        const real_t k = cfg->null_gain_per_s;
        /* k_n T <= 1: the discrete null-space momentum error e+ = (1 - k_n T) e decays without overshoot */
        if (!(AOCS_IS_FINITE(k) && (k >= AOCS_R(0.0)) && ((k * cfg->period_s) <= AOCS_R(1.0)))) {
            st = AOCS_ERR_WHEEL_NULL_GAIN_INVALID;
        }
    }
    return st;
}

aocs_status_t aocs_wheels_set_friction(aocs_wheels_t *wa, uint32_t i, real_t viscous_nms, real_t coulomb_nm)
{
    aocs_status_t st = AOCS_OK;
    if (wa == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if ((wa->initialised == 0) || (i >= wa->cfg.n)) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        aocs_wheels_config_t cfg = wa->cfg;
        cfg.viscous_nms[i] = viscous_nms;
        cfg.coulomb_nm[i] = coulomb_nm;
        st = wheels_check_model(&cfg, i);
        if (st == AOCS_OK) {
            /* the friction model enters neither Gs^+ nor the null-space projector: nothing to recompute */
            wa->cfg.viscous_nms[i] = viscous_nms;
            wa->cfg.coulomb_nm[i] = coulomb_nm;
        }
    }
    return st;
}

aocs_status_t aocs_wheels_init(aocs_wheels_t *wa, const aocs_wheels_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if ((wa == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        wa->initialised = 0;
        st = wheels_check(cfg);
    }
    if (st == AOCS_OK) {
        /* M = Gs Gs^T = sum over the healthy wheels of g g^T (docs/spec.md 5.3) */
        aocs_mat3_t m = aocs_mat3_zero();
        aocs_mat3_t m_inv = aocs_mat3_identity();
        uint32_t healthy = 0u;
        for (uint32_t i = 0u; i < cfg->n; ++i) {
            if (wheel_healthy(cfg, i) != 0) {
                m = aocs_mat3_add(m, aocs_mat3_outer(cfg->axis_B[i], cfg->axis_B[i]));
                ++healthy;
            }
        }
        if ((healthy < AOCS_WHEELS_MIN) || (aocs_mat3_det(m) < WHEEL_SPAN_DET_MIN)) {
            st = AOCS_ERR_WHEELS_NOT_SPANNING;
        } else if (aocs_mat3_inverse(m, &m_inv) != AOCS_OK) {
            st = AOCS_ERR_WHEELS_NOT_SPANNING;
        } else {
            st = wheels_check_compensation(cfg);
        }
        if (st == AOCS_OK) {
            wa->cfg = *cfg;
            wa->n_healthy = healthy;
            for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
                /* row i of Gs^+ = g_i^T M^-1 (M symmetric), zero for a failed or absent wheel */
                aocs_vec3_t row = aocs_vec3_zero();
                if ((i < cfg->n) && (wheel_healthy(cfg, i) != 0)) {
                    row = aocs_mat3_tmul_vec(m_inv, cfg->axis_B[i]);
                }
                for (uint32_t k = 0u; k < 3u; ++k) {
                    wa->pinv[i][k] = row.v[k];
                }
            }
            /* P_N = D_h - Gs^+ Gs_h (docs/spec.md 5.3.2): D_h the identity on the healthy wheels, Gs_h the
             * healthy columns; P_N[i][j] = d_ij - g_j . (row i of Gs^+) for healthy i, j, else 0. Symmetric
             * and idempotent; Gs P_N = 0, so no torque through it reaches the body. */
            for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
                for (uint32_t j = 0u; j < AOCS_WHEELS_MAX; ++j) {
                    real_t p = AOCS_R(0.0);
                    /* three healthy wheels spanning three axes have no null space: P_N = 0 exactly, not the
                     * rounding residue of I - Gs^+ Gs (which k_n would amplify in the float build) */
                    if ((healthy > AOCS_WHEELS_MIN) && (i < cfg->n) && (j < cfg->n) && (wheel_healthy(cfg, i) != 0) &&
                        (wheel_healthy(cfg, j) != 0)) {
                        const aocs_vec3_t g = cfg->axis_B[j];
                        p = ((i == j) ? AOCS_R(1.0) : AOCS_R(0.0)) -
                            ((wa->pinv[i][0] * g.v[0]) + (wa->pinv[i][1] * g.v[1]) + (wa->pinv[i][2] * g.v[2]));
                    }
                    wa->null_proj[i][j] = p;
                }
            }
            wa->initialised = 1;
        }
    }
    return st;
}

static void wheels_zero_alloc(aocs_wheels_alloc_t *out)
{
    for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
        out->u_s_nm[i] = AOCS_R(0.0);
        out->friction_nm[i] = AOCS_R(0.0);
        out->null_nm[i] = AOCS_R(0.0);
    }
    out->u_body_B_nm = aocs_vec3_zero();
    out->scale = AOCS_R(0.0);
    out->null_scale = AOCS_R(0.0);
    out->torque_limited_mask = 0u;
    out->speed_limited_mask = 0u;
}

static int wheels_speeds_finite(const aocs_wheels_t *wa, const real_t *omega_radps)
{
    int ok = 1;
    for (uint32_t i = 0u; i < wa->cfg.n; ++i) {
        if (!AOCS_IS_FINITE(omega_radps[i])) {
            ok = 0;
        }
    }
    return ok;
}

/* Every tachometer speed finite and |Omega_i| <= AOCS_WHEEL_SPEED_RANGE_FACTOR Omega_max,i (docs/spec.md
 * 5.3.3): beyond it the reading is not physical, and Js Omega could overflow (issue 25 item 1). */
static int wheels_speeds_in_range(const aocs_wheels_t *wa, const real_t *omega_radps)
{
    int ok = 1;
    for (uint32_t i = 0u; i < wa->cfg.n; ++i) {
        if (!(AOCS_FABS(omega_radps[i]) <= (AOCS_WHEEL_SPEED_RANGE_FACTOR * wa->cfg.omega_max_radps[i]))) {
            ok = 0; /* also a NaN */
        }
    }
    return ok;
}

aocs_status_t aocs_wheels_check_speeds(const aocs_wheels_t *wa, const real_t *omega_radps)
{
    aocs_status_t st = AOCS_OK;
    if ((wa == NULL) || (omega_radps == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (wa->initialised == 0) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else if (wheels_speeds_finite(wa, omega_radps) == 0) {
        st = AOCS_ERR_INPUT_NOT_FINITE;
    } else if (wheels_speeds_in_range(wa, omega_radps) == 0) {
        st = AOCS_ERR_WHEEL_SPEED_RANGE;
    } else {
        st = AOCS_OK;
    }
    return st;
}

/* The friction model (docs/spec.md 5.3.2, the plant's f of 5.3.1): b w + c tanh(w / Omega_eps), the speed
 * clamped to the limit so |f^| <= b Omega_max + c < u_s,max (checked at init). */
static real_t wheels_friction(const aocs_wheels_config_t *cfg, uint32_t i, real_t omega)
{
    real_t w = omega;
    if (w > cfg->omega_max_radps[i]) {
        w = cfg->omega_max_radps[i];
    } else if (w < -cfg->omega_max_radps[i]) {
        w = -cfg->omega_max_radps[i];
    } else {
        /* within the limits: the speed as measured */
    }
    return (cfg->viscous_nms[i] * w) + (cfg->coulomb_nm[i] * AOCS_TANH(w / cfg->coulomb_width_radps[i]));
}

real_t aocs_wheels_friction(const aocs_wheels_t *wa, uint32_t i, real_t omega_radps)
{
    real_t f = AOCS_R(0.0);
    if ((wa != NULL) && (wa->initialised != 0) && (i < wa->cfg.n) && AOCS_IS_FINITE(omega_radps)) {
        f = wheels_friction(&wa->cfg, i, omega_radps);
    }
    return f;
}

/* The interval [lo, hi] of wheel i's net axial torque this step (docs/spec.md 5.3.2): the motor command
 * n + f^ within +-u_s,max, and a net torque that speeds the wheel up (n Omega > 0, and from rest either way)
 * at most the headroom Js (Omega_max - |Omega|) / T (clamped at 0). lo <= 0 <= hi since |f^| < u_s,max. */
typedef struct {
    real_t lo;
    real_t hi;
    int lo_by_speed;
    int hi_by_speed;
} wheel_room_t;

static wheel_room_t wheels_room(const aocs_wheels_config_t *cfg, uint32_t i, real_t omega, real_t f)
{
    wheel_room_t room;
    real_t head = cfg->js_kgm2[i] * (cfg->omega_max_radps[i] - AOCS_FABS(omega)) / cfg->period_s;
    if (head < AOCS_R(0.0)) {
        head = AOCS_R(0.0);
    }
    room.lo = -cfg->u_max_nm[i] - f;
    room.hi = cfg->u_max_nm[i] - f;
    room.lo_by_speed = 0;
    room.hi_by_speed = 0;
    if ((omega >= AOCS_R(0.0)) && (head < room.hi)) {
        room.hi = head;
        room.hi_by_speed = 1;
    }
    if ((omega <= AOCS_R(0.0)) && (-head > room.lo)) {
        room.lo = -head;
        room.lo_by_speed = 1;
    }
    return room;
}

/* The largest r in [0, r_in] with base + r d inside [room.lo, room.hi] (base is inside: r = 0 is always
 * feasible); *bound_by_speed tells which side's reason bounded it. Written without dividing by a tiny d. */
static real_t wheels_fit(wheel_room_t room, real_t base, real_t d, real_t r_in, int *bound_by_speed)
{
    real_t r = r_in;
    if ((d > AOCS_R(0.0)) && ((base + (r * d)) > room.hi)) {
        r = (room.hi - base) / d;
        *bound_by_speed = room.hi_by_speed;
    } else if ((d < AOCS_R(0.0)) && ((base + (r * d)) < room.lo)) {
        r = (room.lo - base) / d;
        *bound_by_speed = room.lo_by_speed;
    } else {
        /* fits as it is */
    }
    if (r < AOCS_R(0.0)) {
        r = AOCS_R(0.0); /* rounding of a base exactly at the bound */
    }
    return r;
}

real_t aocs_wheels_clamp_cmd(real_t u_nm, real_t u_max_nm)
{
    /* the scaling keeps u_s within +-u_s,max only to rounding (n + f^ can be 1 ulp over, issue 25 item 6):
     * the command is clamped to exactly +-u_max; a NaN gives 0 (the actuation stage's guard reports it) */
    real_t u = AOCS_R(0.0);
    if (u_nm > u_max_nm) {
        u = u_max_nm;
    } else if (u_nm < -u_max_nm) {
        u = -u_max_nm;
    } else if (AOCS_IS_FINITE(u_nm)) {
        u = u_nm;
    } else {
        u = AOCS_R(0.0);
    }
    return u;
}

aocs_status_t aocs_wheels_allocate(const aocs_wheels_t *wa, aocs_vec3_t u_c_B, const real_t *omega_radps,
                                   aocs_wheels_alloc_t *out)
{
    aocs_status_t st = AOCS_OK;
    if ((wa == NULL) || (omega_radps == NULL) || (out == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (aocs_vec3_is_finite(u_c_B) == 0) {
        st = AOCS_ERR_INPUT_NOT_FINITE;
    } else {
        st = aocs_wheels_check_speeds(wa, omega_radps);
    }
    if (out != NULL) {
        wheels_zero_alloc(out);
    }
    if (st == AOCS_OK) {
        const aocs_wheels_config_t *cfg = &wa->cfg;
        real_t tau[AOCS_WHEELS_MAX];
        real_t un[AOCS_WHEELS_MAX];
        wheel_room_t room[AOCS_WHEELS_MAX];
        real_t s = AOCS_R(1.0);
        real_t r = AOCS_R(1.0);
        uint32_t limiter = AOCS_WHEELS_MAX;
        int limiter_by_speed = 0;
        int invalid = 0;
        for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
            /* tau = -Gs^+ u_c: the net axial torques whose reaction -Gs tau on the body is Gs Gs^+ u_c = u_c */
            tau[i] = -((wa->pinv[i][0] * u_c_B.v[0]) + (wa->pinv[i][1] * u_c_B.v[1]) + (wa->pinv[i][2] * u_c_B.v[2]));
            un[i] = AOCS_R(0.0);
        }
        for (uint32_t i = 0u; i < cfg->n; ++i) {
            /* the motor must also overcome the bearing: u_s = tau + f^(Omega) delivers tau (spec 5.3.2) */
            if (wheel_healthy(cfg, i) != 0) {
                out->friction_nm[i] = wheels_friction(cfg, i, omega_radps[i]);
            }
            room[i] = wheels_room(cfg, i, omega_radps[i], out->friction_nm[i]);
            int by_speed = 0;
            const real_t s_i = wheels_fit(room[i], AOCS_R(0.0), tau[i], s, &by_speed);
            if (s_i < s) {
                s = s_i;
                limiter = i;
                limiter_by_speed = by_speed;
            }
        }
        if (cfg->null_gain_per_s > AOCS_R(0.0)) {
            /* u_n = k_n P_N Js (Omega* - Omega): the null-space part of the wheel momenta Js Omega relaxes to
             * that of Js Omega* at the rate k_n, and -Gs u_n = 0 (spec 5.3.2) */
            real_t e[AOCS_WHEELS_MAX];
            for (uint32_t j = 0u; j < AOCS_WHEELS_MAX; ++j) {
                e[j] = (j < cfg->n) ? (cfg->js_kgm2[j] * (cfg->null_speed_radps[j] - omega_radps[j])) : AOCS_R(0.0);
            }
            for (uint32_t i = 0u; i < cfg->n; ++i) {
                real_t acc = AOCS_R(0.0);
                for (uint32_t j = 0u; j < cfg->n; ++j) {
                    acc += wa->null_proj[i][j] * e[j];
                }
                un[i] = cfg->null_gain_per_s * acc;
            }
            /* one scale r for every wheel (a multiple of a null vector is one) within a share of the room
             * s tau leaves: the momentum management never takes a wheel to its torque or speed bound */
            for (uint32_t i = 0u; i < cfg->n; ++i) {
                int unused = 0;
                const real_t base = s * tau[i];
                wheel_room_t share = room[i];
                share.lo = base + (WHEEL_NULL_ROOM_SHARE * (room[i].lo - base));
                share.hi = base + (WHEEL_NULL_ROOM_SHARE * (room[i].hi - base));
                r = wheels_fit(share, base, un[i], r, &unused);
            }
        }
        /* one scale for every wheel: the delivered torque keeps u_c's direction (docs/spec.md 5.3) */
        for (uint32_t i = 0u; i < cfg->n; ++i) {
            if (wheel_healthy(cfg, i) != 0) {
                const real_t net = (s * tau[i]) + (r * un[i]);
                const real_t u = net + out->friction_nm[i];
                if (!AOCS_IS_FINITE(u)) {
                    invalid = 1;
                }
                out->null_nm[i] = r * un[i];
                out->u_s_nm[i] = aocs_wheels_clamp_cmd(u, cfg->u_max_nm[i]);
            }
        }
        /* -Gs (u_s - f^) = -Gs (s tau + r u_n) = s Gs Gs^+ u_c = s u_c, reported as s u_c itself: the sum over
         * the wheels equals it only to rounding, which could put a saturated command an ulp beyond its limit
         * (found by fuzz_exec_step); with 0 <= s <= 1 each component of s u_c is within |u_c| exactly */
        out->u_body_B_nm = aocs_vec3_scale(u_c_B, s);
        out->scale = s;
        out->null_scale = r;
        if (limiter < AOCS_WHEELS_MAX) {
            if (limiter_by_speed != 0) {
                out->speed_limited_mask = wheel_bit(limiter);
            } else {
                out->torque_limited_mask = wheel_bit(limiter);
            }
        }
        if (invalid != 0) {
            /* not reachable with accepted speeds; a non-finite command is no command: zero, reported */
            wheels_zero_alloc(out);
            st = AOCS_ERR_WHEEL_CMD_INVALID;
        }
    }
    return st;
}

aocs_status_t aocs_wheels_momentum(const aocs_wheels_t *wa, aocs_vec3_t w_BN_B, const real_t *omega_radps,
                                   aocs_wheels_momentum_t *out)
{
    aocs_status_t st = AOCS_OK;
    if ((wa == NULL) || (omega_radps == NULL) || (out == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (aocs_vec3_is_finite(w_BN_B) == 0) {
        st = AOCS_ERR_INPUT_NOT_FINITE;
    } else {
        st = aocs_wheels_check_speeds(wa, omega_radps);
    }
    if (out != NULL) {
        out->h_total_B_Nms = aocs_vec3_zero();
        out->h_wheels_norm_Nms = AOCS_R(0.0);
        out->speed_margin = AOCS_R(0.0);
        out->worst_wheel = 0u;
    }
    if (st == AOCS_OK) {
        const aocs_wheels_config_t *cfg = &wa->cfg;
        /* H = J w + sum Js_i g_i Omega_i = J_b w + Gs h (docs/spec.md 5.3) */
        aocs_vec3_t hw = aocs_vec3_zero();
        real_t margin = AOCS_R(1.0);
        uint32_t worst = 0u;
        int first = 1;
        for (uint32_t i = 0u; i < cfg->n; ++i) {
            hw = aocs_vec3_add(hw, aocs_vec3_scale(cfg->axis_B[i], cfg->js_kgm2[i] * omega_radps[i]));
            if (wheel_healthy(cfg, i) != 0) {
                real_t m = AOCS_R(1.0) - (AOCS_FABS(omega_radps[i]) / cfg->omega_max_radps[i]);
                if ((first != 0) || (m < margin)) {
                    margin = m;
                    worst = i;
                    first = 0;
                }
            }
        }
        out->h_total_B_Nms = aocs_vec3_add(aocs_mat3_mul_vec(cfg->inertia_B_kgm2, w_BN_B), hw);
        out->h_wheels_norm_Nms = aocs_vec3_norm(hw);
        out->speed_margin = margin;
        out->worst_wheel = worst;
    }
    return st;
}

real_t aocs_wheels_alpha_envelope(const aocs_wheels_t *wa, aocs_vec3_t a, aocs_vec3_t b)
{
    real_t alpha = AOCS_R(0.0);
    if ((wa != NULL) && (wa->initialised != 0) && (aocs_vec3_is_finite(a) != 0) && (aocs_vec3_is_finite(b) != 0)) {
        /* the torque per unit acceleration is a (+ b); its wheel torques are -Gs^+ (a + b); the first wheel to
         * reach its limit bounds alpha (the uniform scale of the allocation at s = 1) */
        real_t best = AOCS_REAL_MAX;
        for (uint32_t i = 0u; i < wa->cfg.n; ++i) {
            const real_t pa = (wa->pinv[i][0] * a.v[0]) + (wa->pinv[i][1] * a.v[1]) + (wa->pinv[i][2] * a.v[2]);
            const real_t pb = (wa->pinv[i][0] * b.v[0]) + (wa->pinv[i][1] * b.v[1]) + (wa->pinv[i][2] * b.v[2]);
            const real_t d = AOCS_FABS(pa) + AOCS_FABS(pb);
            if ((wheel_healthy(&wa->cfg, i) != 0) && (d > AOCS_R(0.0))) {
                /* u_max / d < best, without dividing by a tiny d */
                if (wa->cfg.u_max_nm[i] < (best * d)) {
                    best = wa->cfg.u_max_nm[i] / d;
                }
            }
        }
        alpha = best;
    }
    return alpha;
}

real_t aocs_wheels_alpha_max(const aocs_wheels_t *wa, aocs_mat3_t j_B_kgm2, aocs_vec3_t e_B)
{
    real_t alpha = AOCS_R(0.0);
    if ((aocs_mat3_is_finite(j_B_kgm2) != 0) && (aocs_vec3_is_finite(e_B) != 0)) {
        alpha = aocs_wheels_alpha_envelope(wa, aocs_mat3_mul_vec(j_B_kgm2, e_B), aocs_vec3_zero());
        if (!(alpha < AOCS_REAL_MAX)) {
            alpha = AOCS_R(0.0); /* J e = 0: nothing to accelerate */
        }
    }
    return alpha;
}

aocs_vec3_t aocs_wheels_h_B(const aocs_wheels_t *wa, const real_t *omega_radps)
{
    aocs_vec3_t h = aocs_vec3_zero();
    if ((wa != NULL) && (omega_radps != NULL) && (wa->initialised != 0) && (wheels_speeds_finite(wa, omega_radps) != 0)) {
        for (uint32_t i = 0u; i < wa->cfg.n; ++i) {
            h = aocs_vec3_add(h, aocs_vec3_scale(wa->cfg.axis_B[i], wa->cfg.js_kgm2[i] * omega_radps[i]));
        }
    }
    return h;
}
