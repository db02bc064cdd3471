/*
 * Multiplicative EKF of attitude and gyro bias: see aocs/estimation/mekf.h;
 * every equation is in docs/spec.md section 5.6 (Lefferts, Markley, Shuster
 * 1982; Markley & Crassidis 2014, ch. 6-7).
 */
#include <stddef.h>
#include <string.h>

#include "aocs/estimation/mekf.h"

/* marks a successful init; a zeroed or garbage struct is very unlikely to hold it */
#define MEKF_INIT_MAGIC 0x4D454B46

#define MEKF_NS_TO_S AOCS_R(1.0e-9)

/* the diagonal floors of spec 5.6.9, as fractions of the configured figures */
#define MEKF_FLOOR_ATT_FRAC AOCS_R(1.0e-3)
#define MEKF_FLOOR_BIAS_FRAC AOCS_R(1.0e-6)

/*
 * Below this rotation angle per step the coefficient functions of spec 5.6.3
 * are evaluated by their Taylor series (five terms: truncation below 1e-19
 * relative in double at 0.1 rad, below 1e-12 in float at 0.5 rad); above it
 * the closed forms, whose cancellation is then harmless.
 */
#if defined(AOCS_REAL_IS_FLOAT)
#define MEKF_SERIES_THETA AOCS_R(0.5)
#else
#define MEKF_SERIES_THETA AOCS_R(0.1)
#endif

/* the five functions of theta of spec 5.6.3 */
typedef struct {
    real_t s0; /* sin(th)/th */
    real_t f1; /* (1 - cos th)/th^2 */
    real_t f2; /* (th - sin th)/th^3 */
    real_t f3; /* (th^2/2 - 1 + cos th)/th^4 */
    real_t f4; /* (th^3/3 - 2 th + 2 sin th)/th^5 */
} mekf_coeffs_t;

typedef struct {
    real_t m[3][3];
} mekf_sym3_t;

/* ---- small helpers ---- */

static mekf_coeffs_t mekf_coeffs(real_t th)
{
    mekf_coeffs_t c;
    const real_t t2 = th * th;
    if (th < MEKF_SERIES_THETA) {
        /* spec 5.6.3: Taylor series, Horner form */
        c.s0 = AOCS_R(1.0) - ((t2 / AOCS_R(6.0)) *
                              (AOCS_R(1.0) - ((t2 / AOCS_R(20.0)) *
                                              (AOCS_R(1.0) - ((t2 / AOCS_R(42.0)) * (AOCS_R(1.0) - (t2 / AOCS_R(72.0))))))));
        c.f1 = AOCS_R(0.5) *
               (AOCS_R(1.0) - ((t2 / AOCS_R(12.0)) *
                               (AOCS_R(1.0) - ((t2 / AOCS_R(30.0)) *
                                               (AOCS_R(1.0) - ((t2 / AOCS_R(56.0)) * (AOCS_R(1.0) - (t2 / AOCS_R(90.0)))))))));
        c.f2 = (AOCS_R(1.0) / AOCS_R(6.0)) *
               (AOCS_R(1.0) - ((t2 / AOCS_R(20.0)) *
                               (AOCS_R(1.0) - ((t2 / AOCS_R(42.0)) *
                                               (AOCS_R(1.0) - ((t2 / AOCS_R(72.0)) * (AOCS_R(1.0) - (t2 / AOCS_R(110.0)))))))));
        c.f3 = (AOCS_R(1.0) / AOCS_R(24.0)) *
               (AOCS_R(1.0) - ((t2 / AOCS_R(30.0)) *
                               (AOCS_R(1.0) - ((t2 / AOCS_R(56.0)) *
                                               (AOCS_R(1.0) - ((t2 / AOCS_R(90.0)) * (AOCS_R(1.0) - (t2 / AOCS_R(132.0)))))))));
        c.f4 = (AOCS_R(1.0) / AOCS_R(60.0)) *
               (AOCS_R(1.0) - ((t2 / AOCS_R(42.0)) *
                               (AOCS_R(1.0) - ((t2 / AOCS_R(72.0)) *
                                               (AOCS_R(1.0) - ((t2 / AOCS_R(110.0)) * (AOCS_R(1.0) - (t2 / AOCS_R(156.0)))))))));
    } else {
        const real_t s = AOCS_SIN(th);
        const real_t sh = AOCS_SIN(AOCS_R(0.5) * th);
        const real_t omc = AOCS_R(2.0) * sh * sh; /* 1 - cos th without cancellation */
        c.s0 = s / th;
        c.f1 = omc / t2;
        c.f2 = (th - s) / (th * t2);
        c.f3 = ((AOCS_R(0.5) * t2) - omc) / (t2 * t2);
        c.f4 = (((th * t2) / AOCS_R(3.0)) - (AOCS_R(2.0) * th) + (AOCS_R(2.0) * s)) / (t2 * t2 * th);
    }
    return c;
}

/* the rotation of rotation vector r: [sin(|r|/2) r/|r|; cos(|r|/2)] (spec 5.6.2), total */
static aocs_quat_t mekf_rotvec_to_quat(aocs_vec3_t r)
{
    const real_t th = aocs_vec3_norm(r);
    const real_t half = AOCS_R(0.5) * th;
    /* sin(th/2)/th = 0.5 sinc(th/2) */
    const real_t k = AOCS_R(0.5) * mekf_coeffs(half).s0;
    return aocs_quat_make(k * r.v[0], k * r.v[1], k * r.v[2], AOCS_COS(half));
}

/* ---- the reference attitude in double (spec 5.6.9): same algebra as aocs_quat_mul (Shuster product) ---- */
static aocs_mekf_quatd_t qd_of(aocs_quat_t q)
{
    aocs_mekf_quatd_t r;
    for (int i = 0; i < 4; ++i) {
        r.q[i] = (double)q.q[i];
    }
    return r;
}

static aocs_quat_t qd_to_real(aocs_mekf_quatd_t q)
{
    return aocs_quat_make((real_t)q.q[0], (real_t)q.q[1], (real_t)q.q[2], (real_t)q.q[3]);
}

static aocs_mekf_quatd_t qd_identity(void)
{
    aocs_mekf_quatd_t r = {{0.0, 0.0, 0.0, 1.0}};
    return r;
}

static aocs_mekf_quatd_t qd_conj(aocs_mekf_quatd_t a)
{
    aocs_mekf_quatd_t r = {{-a.q[0], -a.q[1], -a.q[2], a.q[3]}};
    return r;
}

/* a (x) b = [a4 b_v + b4 a_v - a_v x b_v ; a4 b4 - a_v . b_v] */
static aocs_mekf_quatd_t qd_mul(aocs_mekf_quatd_t a, aocs_mekf_quatd_t b)
{
    aocs_mekf_quatd_t r;
    r.q[0] = ((a.q[3] * b.q[0]) + (b.q[3] * a.q[0])) - ((a.q[1] * b.q[2]) - (a.q[2] * b.q[1]));
    r.q[1] = ((a.q[3] * b.q[1]) + (b.q[3] * a.q[1])) - ((a.q[2] * b.q[0]) - (a.q[0] * b.q[2]));
    r.q[2] = ((a.q[3] * b.q[2]) + (b.q[3] * a.q[2])) - ((a.q[0] * b.q[1]) - (a.q[1] * b.q[0]));
    r.q[3] = (a.q[3] * b.q[3]) - ((a.q[0] * b.q[0]) + (a.q[1] * b.q[1]) + (a.q[2] * b.q[2]));
    return r;
}

/* a / |a|; a is within rounding of unit here (products of unit quaternions) */
static aocs_mekf_quatd_t qd_unit(aocs_mekf_quatd_t a)
{
    const double n = sqrt((a.q[0] * a.q[0]) + (a.q[1] * a.q[1]) + (a.q[2] * a.q[2]) + (a.q[3] * a.q[3]));
    aocs_mekf_quatd_t r = a;
    if (n > 0.5) {
        for (int i = 0; i < 4; ++i) {
            r.q[i] = a.q[i] / n;
        }
    }
    return r;
}

/* q / |q|; total for the unit-ish quaternions of this file (their norm is within rounding of 1) */
static aocs_quat_t mekf_unit(aocs_quat_t q)
{
    aocs_quat_t out = q;
    (void)aocs_quat_normalize(q, &out);
    return out;
}

static int mekf_mat6_is_finite(const aocs_mekf_mat6_t *p)
{
    int ok = 1;
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) {
            if (!AOCS_IS_FINITE(p->m[i][j])) {
                ok = 0;
            }
        }
    }
    return ok;
}

/*
 * spec 5.6.9: P <- (P + P^T)/2, diag P >= floor, then a Cholesky
 * factorisation must find every pivot > 0 (P positive definite). 0 when it
 * does not (or P is not finite).
 */
static int mekf_cov_condition(aocs_mekf_mat6_t *p, const real_t floor_diag[6])
{
    real_t l[6][6];
    int ok = mekf_mat6_is_finite(p);
    (void)memset(l, 0, sizeof(l));
    for (int i = 0; i < 6; ++i) {
        for (int j = i + 1; j < 6; ++j) {
            const real_t s = AOCS_R(0.5) * (p->m[i][j] + p->m[j][i]);
            p->m[i][j] = s;
            p->m[j][i] = s;
        }
        if (p->m[i][i] < floor_diag[i]) {
            p->m[i][i] = floor_diag[i];
        }
    }
    for (int j = 0; (j < 6) && (ok != 0); ++j) {
        real_t d = p->m[j][j];
        for (int k = 0; k < j; ++k) {
            d -= l[j][k] * l[j][k];
        }
        if (!(d > AOCS_R(0.0)) || !AOCS_IS_FINITE(d)) {
            ok = 0;
        } else {
            l[j][j] = AOCS_SQRT(d);
            for (int i = j + 1; i < 6; ++i) {
                real_t s = p->m[i][j];
                for (int k = 0; k < j; ++k) {
                    s -= l[i][k] * l[j][k];
                }
                l[i][j] = s / l[j][j];
            }
        }
    }
    return ok;
}

/* Cholesky S = L L^T of a 3x3; 0 unless every pivot is > 0 and finite */
static int mekf_chol3(const mekf_sym3_t *s, mekf_sym3_t *l)
{
    int ok = 1;
    (void)memset(l, 0, sizeof(*l));
    for (int j = 0; (j < 3) && (ok != 0); ++j) {
        real_t d = s->m[j][j];
        for (int k = 0; k < j; ++k) {
            d -= l->m[j][k] * l->m[j][k];
        }
        if (!(d > AOCS_R(0.0)) || !AOCS_IS_FINITE(d)) {
            ok = 0;
        } else {
            l->m[j][j] = AOCS_SQRT(d);
            for (int i = j + 1; i < 3; ++i) {
                real_t v = s->m[i][j];
                for (int k = 0; k < j; ++k) {
                    v -= l->m[i][k] * l->m[j][k];
                }
                l->m[i][j] = v / l->m[j][j];
            }
        }
    }
    return ok;
}

/* L^-1 b (forward substitution) */
static aocs_vec3_t mekf_lsolve(const mekf_sym3_t *l, aocs_vec3_t b)
{
    aocs_vec3_t z;
    z.v[0] = b.v[0] / l->m[0][0];
    z.v[1] = (b.v[1] - (l->m[1][0] * z.v[0])) / l->m[1][1];
    z.v[2] = (b.v[2] - (l->m[2][0] * z.v[0]) - (l->m[2][1] * z.v[1])) / l->m[2][2];
    return z;
}

/* L^-T z (back substitution) */
static aocs_vec3_t mekf_ltsolve(const mekf_sym3_t *l, aocs_vec3_t z)
{
    aocs_vec3_t x;
    x.v[2] = z.v[2] / l->m[2][2];
    x.v[1] = (z.v[1] - (l->m[2][1] * x.v[2])) / l->m[1][1];
    x.v[0] = (z.v[0] - (l->m[1][0] * x.v[1]) - (l->m[2][0] * x.v[2])) / l->m[0][0];
    return x;
}

/* A P B^T for 6x6 */
static aocs_mekf_mat6_t mekf_mat6_abt(const aocs_mekf_mat6_t *a, const aocs_mekf_mat6_t *p, const aocs_mekf_mat6_t *b)
{
    aocs_mekf_mat6_t ap;
    aocs_mekf_mat6_t out;
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) {
            real_t s = AOCS_R(0.0);
            for (int k = 0; k < 6; ++k) {
                s += a->m[i][k] * p->m[k][j];
            }
            ap.m[i][j] = s;
        }
    }
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) {
            real_t s = AOCS_R(0.0);
            for (int k = 0; k < 6; ++k) {
                s += ap.m[i][k] * b->m[j][k];
            }
            out.m[i][j] = s;
        }
    }
    return out;
}

static void mekf_set_block(aocs_mekf_mat6_t *p, int r0, int c0, aocs_mat3_t b)
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            p->m[r0 + i][c0 + j] = b.m[i][j];
        }
    }
}

/* a I + b V + c V2 */
static aocs_mat3_t mekf_poly3(real_t a, real_t b, aocs_mat3_t v, real_t c, aocs_mat3_t v2)
{
    return aocs_mat3_add(aocs_mat3_add(aocs_mat3_scale(aocs_mat3_identity(), a), aocs_mat3_scale(v, b)),
                         aocs_mat3_scale(v2, c));
}

static void mekf_clear_history(aocs_mekf_t *f)
{
    (void)memset(f->hist, 0, sizeof(f->hist));
    f->hist_count = 0u;
    f->hist_head = 0u;
}

/* back to waiting for a star-tracker sample (spec 5.6.10); counters kept */
static void mekf_restart(aocs_mekf_t *f)
{
    f->started = 0u;
    f->configured_start = 0u; /* only the first start after init is from q0_BN */
    f->have_meas = 0u;
    f->q_BN_hat = qd_identity();
    f->bias_B_hat = aocs_vec3_zero();
    f->w_meas_B_radps = aocs_vec3_zero();
    f->w_hat_B_radps = aocs_vec3_zero();
    (void)memset(&f->P, 0, sizeof(f->P));
    mekf_clear_history(f);
    if (f->n_restarts < UINT32_MAX) {
        f->n_restarts += 1u;
    }
}

static void mekf_count(uint32_t *n)
{
    if (*n < UINT32_MAX) {
        *n += 1u;
    }
}

static int mekf_all_positive(const real_t *v, int n)
{
    int ok = 1;
    for (int i = 0; i < n; ++i) {
        if (!(v[i] > AOCS_R(0.0))) {
            ok = 0;
        }
    }
    return ok;
}

static int mekf_all_finite(const real_t *v, int n)
{
    int ok = 1;
    for (int i = 0; i < n; ++i) {
        if (!AOCS_IS_FINITE(v[i])) {
            ok = 0;
        }
    }
    return ok;
}

static uint64_t mekf_max_gap_ns(const aocs_mekf_t *f)
{
    /* validated at init: 0 < max_gap_s <= AOCS_MEKF_MAX_GAP_LIMIT_S, so the product fits */
    const real_t max_gap_ns = f->cfg.max_gap_s * AOCS_R(1.0e9);
    return (uint64_t)max_gap_ns;
}

/* ---- configuration ---- */

void aocs_mekf_config_default(aocs_mekf_config_t *cfg)
{
    if (cfg != NULL) {
        const real_t arcsec = AOCS_R(4.84813681109536e-6);
        (void)memset(cfg, 0, sizeof(*cfg));
        cfg->q_SB = aocs_quat_identity();
        cfg->st_sigma_cross_rad = AOCS_R(1.0) * arcsec;
        cfg->st_sigma_about_rad = AOCS_R(8.0) * arcsec;
        cfg->gyro_arw_radpsqrts = AOCS_R(1.0e-6);
        cfg->gyro_rrw_radps1p5 = AOCS_R(1.0e-9);
        cfg->bias0_B_radps = aocs_vec3_zero();
        cfg->p0_att_sigma_rad = AOCS_R(0.017453292519943295);          /* 1 deg */
        cfg->p0_bias_sigma_radps = AOCS_R(1.0) * arcsec; /* 1 deg/h = 1 arcsec/s */
        cfg->gate_chi2 = AOCS_MEKF_GATE_CHI2_3DOF_999;
        cfg->max_gap_s = AOCS_R(10.0);
        cfg->init_mode = AOCS_MEKF_INIT_FIRST_ST;
        cfg->q0_BN = aocs_quat_identity();
        cfg->gyroless_torque_sigma_nm = AOCS_R(1.0e-2);
        cfg->gyroless_p0_rate_sigma_radps = AOCS_R(1.0e-2);
        cfg->gyroless_rate_sigma_radps = AOCS_R(1.0e-5);
    }
}

static aocs_status_t mekf_check_config(const aocs_mekf_config_t *c)
{
    aocs_status_t st = AOCS_OK;
    const real_t sig[6] = {c->st_sigma_cross_rad, c->st_sigma_about_rad, c->gyro_arw_radpsqrts,
                           c->gyro_rrw_radps1p5,  c->p0_att_sigma_rad,   c->p0_bias_sigma_radps};
    const real_t other[5] = {c->gate_chi2, c->max_gap_s, c->gyroless_torque_sigma_nm,
                             c->gyroless_p0_rate_sigma_radps, c->gyroless_rate_sigma_radps};
    if ((mekf_all_finite(sig, 6) == 0) || (mekf_all_finite(other, 5) == 0) || (aocs_quat_is_finite(c->q_SB) == 0) ||
        (aocs_vec3_is_finite(c->bias0_B_radps) == 0) || (aocs_quat_is_finite(c->q0_BN) == 0)) {
        st = AOCS_ERR_PARAM_NOT_FINITE;
    } else if (!(AOCS_FABS(aocs_quat_norm(c->q_SB) - AOCS_R(1.0)) <= AOCS_MEKF_QUAT_UNIT_TOL) ||
               !(AOCS_FABS(aocs_quat_norm(c->q0_BN) - AOCS_R(1.0)) <= AOCS_MEKF_QUAT_UNIT_TOL)) {
        st = AOCS_ERR_QUAT_NOT_UNIT;
    } else if ((mekf_all_positive(sig, 6) == 0) || !(c->gyroless_torque_sigma_nm >= AOCS_R(0.0)) ||
               (mekf_all_positive(&other[3], 2) == 0)) {
        st = AOCS_ERR_MEKF_NOISE_NOT_POSITIVE;
    } else if (!(c->gate_chi2 > AOCS_R(0.0))) {
        st = AOCS_ERR_MEKF_GATE_INVALID;
    } else if (!(c->max_gap_s > AOCS_R(0.0)) || (c->max_gap_s > AOCS_MEKF_MAX_GAP_LIMIT_S)) {
        st = AOCS_ERR_DT_INVALID;
    } else if (c->init_mode >= AOCS_MEKF_INIT_COUNT) {
        st = AOCS_ERR_MEKF_INIT_MODE_INVALID;
    } else {
        st = AOCS_OK;
    }
    return st;
}

aocs_status_t aocs_mekf_init(aocs_mekf_t *f, const aocs_mekf_config_t *cfg)
{
    aocs_status_t st = AOCS_ERR_NULL_ARG;
    if ((f != NULL) && (cfg != NULL)) {
        st = mekf_check_config(cfg);
    }
    if (f != NULL) {
        (void)memset(f, 0, sizeof(*f));
        f->q_BN_hat = qd_identity();
        if (st == AOCS_OK) {
            const real_t sc = cfg->st_sigma_cross_rad;
            const real_t sa = cfg->st_sigma_about_rad;
            const real_t smin = (sc < sa) ? sc : sa;
            const real_t fa = MEKF_FLOOR_ATT_FRAC * smin;
            const real_t fb = MEKF_FLOOR_BIAS_FRAC * cfg->p0_bias_sigma_radps;
            f->cfg = *cfg;
            (void)aocs_quat_normalize(cfg->q_SB, &f->cfg.q_SB);
            (void)aocs_quat_normalize(cfg->q0_BN, &f->cfg.q0_BN);
            f->configured_start = 0u;
            if (cfg->init_mode == AOCS_MEKF_INIT_CONFIGURED) {
                f->configured_start = 1u;
            }
            f->r_S[0] = sc * sc;
            f->r_S[1] = sc * sc;
            f->r_S[2] = sa * sa;
            f->st_noise_scale = AOCS_R(1.0);
            for (int i = 0; i < 3; ++i) {
                f->p_floor[i] = fa * fa;
                f->p_floor[i + 3] = fb * fb;
            }
            f->initialised = MEKF_INIT_MAGIC;
        }
    }
    return st;
}

aocs_status_t aocs_mekf_reset(aocs_mekf_t *f)
{
    aocs_status_t st = AOCS_OK;
    if (f == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (f->initialised != MEKF_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        mekf_restart(f);
        f->n_updates = 0u;
        f->n_gated = 0u;
        f->n_hostile = 0u;
        f->n_restarts = 0u;
        f->innovation_B_rad = aocs_vec3_zero();
        f->innovation_chi2 = AOCS_R(0.0);
        f->innovation_white = aocs_vec3_zero();
        f->t_ns = 0u;
        f->t_last_meas_ns = 0u;
    }
    return st;
}

/* ---- propagation (spec 5.6.2 - 5.6.4) ---- */

static aocs_status_t mekf_check_rate(aocs_vec3_t w)
{
    aocs_status_t st = AOCS_OK;
    if (aocs_vec3_is_finite(w) == 0) {
        st = AOCS_ERR_INPUT_NOT_FINITE;
    } else if (aocs_vec3_norm_inf(w) > AOCS_MEKF_RATE_MAX_RADPS) {
        st = AOCS_ERR_MEKF_RATE_RANGE;
    } else {
        st = AOCS_OK;
    }
    return st;
}

/* The end of a propagation step: P <- p once conditioned (else the restart, AOCS_ERR_MEKF_COV_INVALID), the
 * attitude turned by the rotation vector r = w dt, the step into the history ring, the time to t_ns. */
static aocs_status_t mekf_commit_step(aocs_mekf_t *f, aocs_mekf_mat6_t *p, aocs_vec3_t w, aocs_vec3_t r, uint64_t t_ns)
{
    aocs_status_t st = AOCS_OK;
    if (mekf_cov_condition(p, f->p_floor) == 0) {
        st = AOCS_ERR_MEKF_COV_INVALID;
        mekf_restart(f);
    } else {
        /* spec 5.6.2: q_hat(t) = [sin(th/2) r/th; cos(th/2)] (x) q_hat(t_prev) */
        const aocs_quat_t dq = mekf_rotvec_to_quat(r);
        f->q_BN_hat = qd_unit(qd_mul(qd_of(dq), f->q_BN_hat));
        f->P = *p;
        /* spec 5.6.8: the step's rotation into the history ring */
        f->hist_head = (f->hist_count == 0u) ? 0u : ((f->hist_head + 1u) % AOCS_MEKF_HISTORY_LEN);
        if (f->hist_count < AOCS_MEKF_HISTORY_LEN) {
            f->hist_count += 1u;
        }
        f->hist[f->hist_head].t0_ns = f->t_ns;
        f->hist[f->hist_head].t1_ns = t_ns;
        f->hist[f->hist_head].dq = dq;
        f->hist[f->hist_head].w_B_radps = w;
        f->hist[f->hist_head].w_corr_B_radps = f->w_corr_B_radps;
        f->t_ns = t_ns;
    }
    return st;
}

/* spec 5.6.12: dw/dt = J^-1 (tau - w x (J w + h_w)) with the held torque and wheel momentum */
static aocs_vec3_t mekf_rate_dot(const aocs_mekf_t *f, aocs_vec3_t w)
{
    const aocs_vec3_t h = aocs_vec3_add(aocs_mat3_mul_vec(f->inertia_B_kgm2, w), f->h_wheels_B_Nms);
    return aocs_mat3_mul_vec(f->inertia_inv_B, aocs_vec3_sub(f->tau_B_Nm, aocs_vec3_cross(w, h)));
}

/* a + b + c (3x3) */
static aocs_mat3_t mekf_mat3_sum3(aocs_mat3_t a, aocs_mat3_t b, aocs_mat3_t c)
{
    return aocs_mat3_add(aocs_mat3_add(a, b), c);
}

/*
 * The gyroless step from f->t_ns to t_ns (spec 5.6.12): the rate by Heun's rule on the dynamics, the attitude
 * turned by the step's mean rate; Phi = I + F dt + F^2 dt^2 / 2 of F = [-[w x]  I; 0  F22],
 * F22 = J^-1 ([(J w + h_w) x] - [w x] J) at the mean rate (Phi11 the exact rotation of the error), and
 * Q = Qc [dt^3/3  dt^2/2; dt^2/2  dt] of the torque's white noise, Qc = sigma_tau^2 J^-1 J^-T.
 */
static aocs_status_t mekf_propagate_dynamics(aocs_mekf_t *f, uint64_t t_ns)
{
    aocs_status_t st = AOCS_OK;
    const uint64_t dt_ns = t_ns - f->t_ns;
    const real_t dt = (real_t)dt_ns * MEKF_NS_TO_S;
    const aocs_vec3_t w0 = f->w_hat_B_radps;
    const aocs_vec3_t k1 = mekf_rate_dot(f, w0);
    const aocs_vec3_t k2 = mekf_rate_dot(f, aocs_vec3_add(w0, aocs_vec3_scale(k1, dt)));
    const aocs_vec3_t w1 = aocs_vec3_add(w0, aocs_vec3_scale(aocs_vec3_add(k1, k2), AOCS_R(0.5) * dt));
    const aocs_vec3_t wm = aocs_vec3_scale(aocs_vec3_add(w0, w1), AOCS_R(0.5));
    if (mekf_check_rate(w1) != AOCS_OK) {
        st = AOCS_ERR_MEKF_RATE_RANGE; /* the model left every physical rate: start again from the tracker */
        mekf_restart(f);
    } else {
        const aocs_vec3_t r = aocs_vec3_scale(wm, dt);
        const mekf_coeffs_t c = mekf_coeffs(aocs_vec3_norm(r));
        const aocs_mat3_t v = aocs_mat3_skew(r);
        const aocs_mat3_t v2 = aocs_mat3_mul(v, v);
        const aocs_mat3_t jinv = f->inertia_inv_B;
        const aocs_vec3_t hm = aocs_vec3_add(aocs_mat3_mul_vec(f->inertia_B_kgm2, wm), f->h_wheels_B_Nms);
        const aocs_mat3_t f22 = aocs_mat3_mul(
            jinv, aocs_mat3_add(aocs_mat3_skew(hm),
                                aocs_mat3_scale(aocs_mat3_mul(aocs_mat3_skew(wm), f->inertia_B_kgm2), -AOCS_R(1.0))));
        const aocs_mat3_t a = aocs_mat3_scale(f22, dt);
        const real_t s2 = f->cfg.gyroless_torque_sigma_nm * f->cfg.gyroless_torque_sigma_nm;
        const aocs_mat3_t qc = aocs_mat3_scale(aocs_mat3_mul(jinv, aocs_mat3_transpose(jinv)), s2);
        aocs_mekf_mat6_t phi;
        aocs_mekf_mat6_t p;
        (void)memset(&phi, 0, sizeof(phi));
        mekf_set_block(&phi, 0, 0, mekf_poly3(AOCS_R(1.0), -c.s0, v, c.f1, v2));
        /* Phi12 = dt I + (dt/2) (-[w x] + F22) dt = dt I - (dt/2) V + (dt/2) A */
        mekf_set_block(&phi, 0, 3,
                       aocs_mat3_add(mekf_poly3(dt, -AOCS_R(0.5) * dt, v, AOCS_R(0.0), v2),
                                     aocs_mat3_scale(a, AOCS_R(0.5) * dt)));
        mekf_set_block(&phi, 3, 3, mekf_mat3_sum3(aocs_mat3_identity(), a,
                                                  aocs_mat3_scale(aocs_mat3_mul(a, a), AOCS_R(0.5))));
        p = mekf_mat6_abt(&phi, &f->P, &phi);
        {
            const real_t dt2 = dt * dt;
            for (int i = 0; i < 3; ++i) {
                for (int j = 0; j < 3; ++j) {
                    const real_t q = qc.m[i][j];
                    p.m[i][j] += q * dt2 * dt / AOCS_R(3.0);
                    p.m[i][j + 3] += q * AOCS_R(0.5) * dt2;
                    p.m[i + 3][j] += q * AOCS_R(0.5) * dt2;
                    p.m[i + 3][j + 3] += q * dt;
                }
            }
        }
        st = mekf_commit_step(f, &p, wm, r, t_ns);
        if (st == AOCS_OK) {
            f->w_hat_B_radps = w1;
        }
    }
    return st;
}

/* the step from f->t_ns to t_ns, already checked (t_ns > f->t_ns, within max_gap) */
static aocs_status_t mekf_propagate_gyro(aocs_mekf_t *f, aocs_vec3_t w_meas, uint64_t t_ns)
{
    aocs_status_t st = AOCS_OK;
    const uint64_t dt_ns = t_ns - f->t_ns;
    const real_t dt = (real_t)dt_ns * MEKF_NS_TO_S;
    const real_t sv2 = f->cfg.gyro_arw_radpsqrts * f->cfg.gyro_arw_radpsqrts;
    const real_t su2 = f->cfg.gyro_rrw_radps1p5 * f->cfg.gyro_rrw_radps1p5;
    /* spec 5.6.2: omega_hat = omega_m - b_hat, held over the step; r = omega_hat dt */
    const aocs_vec3_t w = aocs_vec3_sub(w_meas, f->bias_B_hat);
    const aocs_vec3_t r = aocs_vec3_scale(w, dt);
    const mekf_coeffs_t c = mekf_coeffs(aocs_vec3_norm(r));
    const aocs_mat3_t v = aocs_mat3_skew(r);
    const aocs_mat3_t v2 = aocs_mat3_mul(v, v);
    aocs_mekf_mat6_t phi;
    aocs_mekf_mat6_t p;

    /* spec 5.6.3: Phi11 = I - s0 V + f1 V^2, Phi12 = dt (-I + f1 V - f2 V^2), Phi21 = 0, Phi22 = I */
    (void)memset(&phi, 0, sizeof(phi));
    mekf_set_block(&phi, 0, 0, mekf_poly3(AOCS_R(1.0), -c.s0, v, c.f1, v2));
    mekf_set_block(&phi, 0, 3, mekf_poly3(-dt, dt * c.f1, v, -dt * c.f2, v2));
    mekf_set_block(&phi, 3, 3, aocs_mat3_identity());
    p = mekf_mat6_abt(&phi, &f->P, &phi);
    /* spec 5.6.4: Q11 = sv^2 dt I + su^2 dt^3 (I/3 + f4 V^2), Q12 = -su^2 dt^2 (I/2 - f2 V + f3 V^2),
     * Q22 = su^2 dt I; Q21 = Q12^T */
    {
        const real_t dt2 = dt * dt;
        const aocs_mat3_t q11 =
            mekf_poly3((sv2 * dt) + ((su2 * dt * dt2) / AOCS_R(3.0)), AOCS_R(0.0), v, su2 * dt * dt2 * c.f4, v2);
        const aocs_mat3_t q12 = mekf_poly3(-AOCS_R(0.5) * su2 * dt2, su2 * dt2 * c.f2, v, -su2 * dt2 * c.f3, v2);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                p.m[i][j] += q11.m[i][j];
                p.m[i][j + 3] += q12.m[i][j];
                p.m[j + 3][i] += q12.m[i][j];
            }
            p.m[i + 3][i + 3] += su2 * dt;
        }
    }
    st = mekf_commit_step(f, &p, w, r, t_ns);
    if (st == AOCS_OK) {
        f->w_meas_B_radps = w_meas;
    }
    return st;
}

/* the step from f->t_ns to t_ns (checked): on the gyro, or on the dynamics once gyroless */
static aocs_status_t mekf_propagate_checked(aocs_mekf_t *f, aocs_vec3_t w_meas, uint64_t t_ns)
{
    return (f->gyroless != 0u) ? mekf_propagate_dynamics(f, t_ns) : mekf_propagate_gyro(f, w_meas, t_ns);
}

aocs_status_t aocs_mekf_propagate(aocs_mekf_t *f, aocs_vec3_t w_meas_B_radps, uint64_t t_ns)
{
    aocs_status_t st = AOCS_OK;
    if (f == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (f->initialised != MEKF_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else if (f->started == 0u) {
        st = AOCS_ERR_MEKF_NO_ATTITUDE;
    } else if (f->gyroless != 0u) {
        st = AOCS_OK; /* no gyro rate used */
    } else {
        st = mekf_check_rate(w_meas_B_radps);
    }
    if (st == AOCS_OK) {
        if (t_ns <= f->t_ns) {
            st = AOCS_ERR_INPUT_STALE;
        } else if ((t_ns - f->t_ns) > mekf_max_gap_ns(f)) {
            st = AOCS_ERR_MEKF_GAP;
            mekf_restart(f);
        } else {
            st = mekf_propagate_checked(f, w_meas_B_radps, t_ns);
        }
    }
    return st;
}

/* ---- update (spec 5.6.5 - 5.6.8) ---- */

/* checks of a sample against the current time; the unit quaternion q_SN in *q_unit */
static aocs_status_t mekf_check_sample(const aocs_mekf_t *f, const aocs_mekf_st_sample_t *s, uint64_t t_now_ns,
                                       aocs_quat_t *q_unit)
{
    aocs_status_t st = AOCS_OK;
    if (aocs_quat_is_finite(s->q_SN) == 0) {
        st = AOCS_ERR_INPUT_NOT_FINITE;
    } else if (!(AOCS_FABS(aocs_quat_norm(s->q_SN) - AOCS_R(1.0)) <= AOCS_MEKF_QUAT_UNIT_TOL)) {
        st = AOCS_ERR_QUAT_NOT_UNIT;
    } else if (s->t_meas_ns > t_now_ns) {
        st = AOCS_ERR_MEKF_MEAS_FUTURE;
    } else if ((f->have_meas != 0u) && (s->t_meas_ns <= f->t_last_meas_ns)) {
        st = AOCS_ERR_INPUT_STALE;
    } else {
        *q_unit = mekf_unit(s->q_SN);
    }
    return st;
}

/*
 * spec 5.6.8: M, the rotation from t_meas to now along the history
 * (q_hat(now) = M (x) q_hat(t_meas)). 0 when t_meas is older than the history.
 */
static int mekf_history_rotation(const aocs_mekf_t *f, uint64_t t_meas_ns, aocs_mekf_quatd_t *m)
{
    int found = 0;
    uint32_t idx = f->hist_head;
    aocs_mekf_quatd_t acc = qd_identity();
    if (t_meas_ns >= f->t_ns) {
        found = 1; /* at or after the estimate: nothing to undo */
    }
    for (uint32_t k = 0u; (k < f->hist_count) && (found == 0); ++k) {
        const aocs_mekf_hist_t *e = &f->hist[idx];
        /* spec 5.6.12: gyroless, the step's rate with the corrections the updates made since (its error is
         * then the current rate error, the h term of H); the gyro's rate is a measurement: used as it was */
        const aocs_vec3_t w = (f->gyroless != 0u)
                                  ? aocs_vec3_add(e->w_B_radps, aocs_vec3_sub(f->w_corr_B_radps, e->w_corr_B_radps))
                                  : e->w_B_radps;
        if (e->t0_ns <= t_meas_ns) {
            /* t_meas inside (t0, t1]: the part of the step after it, with the step's rate */
            const uint64_t tau_ns = e->t1_ns - t_meas_ns;
            const real_t tau = (real_t)tau_ns * MEKF_NS_TO_S;
            acc = qd_mul(acc, qd_of(mekf_rotvec_to_quat(aocs_vec3_scale(w, tau))));
            found = 1;
        } else {
            aocs_quat_t dq = e->dq;
            if (f->gyroless != 0u) {
                const uint64_t step_ns = e->t1_ns - e->t0_ns;
                dq = mekf_rotvec_to_quat(aocs_vec3_scale(w, (real_t)step_ns * MEKF_NS_TO_S));
            }
            acc = qd_mul(acc, qd_of(dq));
            idx = (idx + AOCS_MEKF_HISTORY_LEN - 1u) % AOCS_MEKF_HISTORY_LEN;
        }
    }
    *m = qd_unit(acc);
    return found;
}

/* the update with a checked sample (q_SN unit) */
static aocs_status_t mekf_update_checked(aocs_mekf_t *f, aocs_quat_t q_SN, uint64_t t_meas_ns)
{
    aocs_status_t st = AOCS_OK;
    aocs_mekf_quatd_t m;
    if (mekf_history_rotation(f, t_meas_ns, &m) == 0) {
        st = AOCS_ERR_MEKF_MEAS_TOO_OLD;
        mekf_count(&f->n_hostile);
    } else {
        const aocs_mekf_mat6_t *p = &f->P;
        /* spec 5.6.5: the measured body attitude carried to now, q_m = M (x) q_SB^-1 (x) q_SN */
        const aocs_mekf_quatd_t m_sb = qd_mul(m, qd_conj(qd_of(f->cfg.q_SB)));
        const aocs_mekf_quatd_t dqd = qd_mul(qd_mul(m_sb, qd_of(q_SN)), qd_conj(f->q_BN_hat));
        aocs_quat_t dq = qd_to_real(dqd);
        /* spec 5.6.6: R = C diag(r_S) C^T, C = A(M (x) q_SB^-1) (S to B now) */
        const aocs_mat3_t cmat = aocs_quat_to_dcm(qd_to_real(m_sb));
        const uint64_t h_ns = f->t_ns - t_meas_ns;
        /* spec 5.6.5: H = [I  h I] against the bias error; spec 5.6.12: H = [I  -h I] against the rate error */
        const real_t h = ((f->gyroless != 0u) ? -AOCS_R(1.0) : AOCS_R(1.0)) * ((real_t)h_ns * MEKF_NS_TO_S);
        mekf_sym3_t s;
        mekf_sym3_t l;
        mekf_sym3_t rmat;
        aocs_vec3_t y;
        if (dq.q[3] < AOCS_R(0.0)) {
            dq = aocs_quat_make(-dq.q[0], -dq.q[1], -dq.q[2], -dq.q[3]);
        }
        /* spec 5.6.5: y = 2 vec(dq), H = [I  h I] */
        y = aocs_vec3_scale(aocs_quat_vec(dq), AOCS_R(2.0));
        /* spec 5.6.6: R_ij = sum_k C_ik r_S,k C_jk; spec 5.6.7: S = H P H^T + R */
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                real_t r = AOCS_R(0.0);
                for (int k = 0; k < 3; ++k) {
                    r += cmat.m[i][k] * f->r_S[k] * cmat.m[j][k];
                }
                rmat.m[i][j] = r;
                s.m[i][j] = p->m[i][j] + (h * (p->m[i][j + 3] + p->m[i + 3][j])) + (h * h * p->m[i + 3][j + 3]) + r;
            }
        }
        if (mekf_chol3(&s, &l) == 0) {
            st = AOCS_ERR_MEKF_COV_INVALID;
            mekf_restart(f);
        } else {
            /* spec 5.6.7: d^2 = y^T S^-1 y = |L^-1 y|^2 */
            const aocs_vec3_t z = mekf_lsolve(&l, y);
            const real_t d2 = aocs_vec3_norm_sq(z);
            f->innovation_B_rad = y;
            f->innovation_chi2 = d2;
            f->innovation_white = z;
            if (!(d2 <= f->cfg.gate_chi2)) {
                st = AOCS_ERR_MEKF_GATED;
                mekf_count(&f->n_gated);
            } else if (f->st_excluded != 0u) {
                st = AOCS_ERR_MEKF_ST_EXCLUDED; /* tested, not applied (fault management, spec 5.15.3) */
            } else {
                /* applied below */
            }
        }
        if (st == AOCS_OK) {
            real_t k[6][3];
            real_t dx[6];
            aocs_mekf_mat6_t a;
            aocs_mekf_mat6_t pj;
            /* spec 5.6.7: K = P H^T S^-1, row by row: K_i = S^-1 (P H^T)_i */
            for (int i = 0; i < 6; ++i) {
                aocs_vec3_t b;
                aocs_vec3_t x;
                for (int j = 0; j < 3; ++j) {
                    b.v[j] = p->m[i][j] + (h * p->m[i][j + 3]);
                }
                x = mekf_ltsolve(&l, mekf_lsolve(&l, b));
                for (int j = 0; j < 3; ++j) {
                    k[i][j] = x.v[j];
                }
                dx[i] = (k[i][0] * y.v[0]) + (k[i][1] * y.v[1]) + (k[i][2] * y.v[2]);
            }
            /* spec 5.6.7 (Joseph): P+ = (I - K H) P (I - K H)^T + K R K^T, K H = [K  h K] */
            for (int i = 0; i < 6; ++i) {
                for (int j = 0; j < 3; ++j) {
                    a.m[i][j] = ((i == j) ? AOCS_R(1.0) : AOCS_R(0.0)) - k[i][j];
                    a.m[i][j + 3] = ((i == (j + 3)) ? AOCS_R(1.0) : AOCS_R(0.0)) - (h * k[i][j]);
                }
            }
            pj = mekf_mat6_abt(&a, p, &a);
            for (int i = 0; i < 6; ++i) {
                real_t kr[3]; /* (K R)_i */
                for (int j = 0; j < 3; ++j) {
                    kr[j] = (k[i][0] * rmat.m[0][j]) + (k[i][1] * rmat.m[1][j]) + (k[i][2] * rmat.m[2][j]);
                }
                for (int j = 0; j < 6; ++j) {
                    pj.m[i][j] += (kr[0] * k[j][0]) + (kr[1] * k[j][1]) + (kr[2] * k[j][2]);
                }
            }
            if (mekf_cov_condition(&pj, f->p_floor) == 0) {
                st = AOCS_ERR_MEKF_COV_INVALID;
                mekf_restart(f);
            } else {
                /* spec 5.6.6 reset: q_hat <- dq(dth) (x) q_hat, b_hat <- b_hat + db, error back to 0 */
                const aocs_vec3_t dth = aocs_vec3_make(dx[0], dx[1], dx[2]);
                f->q_BN_hat = qd_unit(qd_mul(qd_of(mekf_rotvec_to_quat(dth)), f->q_BN_hat));
                if (f->gyroless != 0u) {
                    f->w_hat_B_radps = aocs_vec3_add(f->w_hat_B_radps, aocs_vec3_make(dx[3], dx[4], dx[5]));
                    f->w_corr_B_radps = aocs_vec3_add(f->w_corr_B_radps, aocs_vec3_make(dx[3], dx[4], dx[5]));
                } else {
                    f->bias_B_hat = aocs_vec3_add(f->bias_B_hat, aocs_vec3_make(dx[3], dx[4], dx[5]));
                }
                f->P = pj;
                f->t_last_meas_ns = t_meas_ns;
                f->have_meas = 1u;
                mekf_count(&f->n_updates);
            }
        }
    }
    return st;
}

aocs_status_t aocs_mekf_update(aocs_mekf_t *f, const aocs_mekf_st_sample_t *st_sample)
{
    aocs_status_t st = AOCS_OK;
    aocs_quat_t q_SN = aocs_quat_identity();
    if ((f == NULL) || (st_sample == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (f->initialised != MEKF_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else if (f->started == 0u) {
        st = AOCS_ERR_MEKF_NO_ATTITUDE;
    } else {
        st = mekf_check_sample(f, st_sample, f->t_ns, &q_SN);
        if (st != AOCS_OK) {
            mekf_count(&f->n_hostile);
        } else {
            st = mekf_update_checked(f, q_SN, st_sample->t_meas_ns);
        }
    }
    return st;
}

/* ---- initialisation from a sample (spec 5.6.10) and the step ---- */

/* the start of spec 5.6.10 at q_hat, time t_ns: b_hat = bias0, P = diag(p0_att^2 I, p0_bias^2 I), no sample yet
 * (gyroless, spec 5.6.12: w_hat = 0 and gyroless_p0_rate^2 I in place of the bias block) */
static void mekf_start_at(aocs_mekf_t *f, aocs_mekf_quatd_t q_hat, uint64_t t_ns)
{
    const real_t pa = f->cfg.p0_att_sigma_rad * f->cfg.p0_att_sigma_rad;
    const real_t sb = (f->gyroless != 0u) ? f->cfg.gyroless_p0_rate_sigma_radps : f->cfg.p0_bias_sigma_radps;
    const real_t pb = sb * sb; /* spec 5.6.12: gyroless, the rate's prior (the rate estimate from zero) */
    f->w_hat_B_radps = aocs_vec3_zero();
    f->q_BN_hat = q_hat;
    f->bias_B_hat = f->cfg.bias0_B_radps;
    (void)memset(&f->P, 0, sizeof(f->P));
    for (int i = 0; i < 3; ++i) {
        f->P.m[i][i] = pa;
        f->P.m[i + 3][i + 3] = pb;
    }
    mekf_clear_history(f);
    f->t_ns = t_ns;
    f->have_meas = 0u;
    f->started = 1u;
    f->configured_start = 0u;
}

static aocs_status_t mekf_start(aocs_mekf_t *f, const aocs_mekf_st_sample_t *s, uint64_t t_now_ns)
{
    aocs_quat_t q_SN = aocs_quat_identity();
    aocs_status_t st = mekf_check_sample(f, s, t_now_ns, &q_SN);
    if ((st == AOCS_OK) && ((t_now_ns - s->t_meas_ns) > mekf_max_gap_ns(f))) {
        st = AOCS_ERR_MEKF_MEAS_TOO_OLD;
    }
    if (st != AOCS_OK) {
        mekf_count(&f->n_hostile);
    } else {
        /* q_BN = q_SB^-1 (x) q_SN (A(q_SN) = A(q_SB) A(q_BN)) */
        mekf_start_at(f, qd_unit(qd_mul(qd_conj(qd_of(f->cfg.q_SB)), qd_of(q_SN))), s->t_meas_ns);
        f->t_last_meas_ns = s->t_meas_ns;
        f->have_meas = 1u;
    }
    return st;
}

static void mekf_fill_output(const aocs_mekf_t *f, aocs_status_t st, aocs_status_t st_status, aocs_mekf_output_t *out)
{
    (void)memset(out, 0, sizeof(*out));
    if (st == AOCS_OK) {
        const double sgn = (f->q_BN_hat.q[3] < 0.0) ? -1.0 : 1.0;
        out->q_BN_hat = aocs_quat_make((real_t)(sgn * f->q_BN_hat.q[0]), (real_t)(sgn * f->q_BN_hat.q[1]),
                                       (real_t)(sgn * f->q_BN_hat.q[2]), (real_t)(sgn * f->q_BN_hat.q[3]));
        out->bias_B_hat = f->bias_B_hat;
        out->w_BN_B_hat = (f->gyroless != 0u) ? f->w_hat_B_radps : aocs_vec3_sub(f->w_meas_B_radps, f->bias_B_hat);
        out->P = f->P;
        for (int i = 0; i < 6; ++i) {
            out->sigma[i] = AOCS_SQRT(f->P.m[i][i]);
        }
        out->valid = 1u;
        out->innovation_B_rad = f->innovation_B_rad;
        out->innovation_chi2 = f->innovation_chi2;
        out->innovation_white = f->innovation_white;
        out->t_ns = f->t_ns;
    }
    out->st_status = st_status;
    out->n_updates = f->n_updates;
    out->n_gated = f->n_gated;
    out->n_hostile = f->n_hostile;
    out->n_restarts = f->n_restarts;
}

aocs_status_t aocs_mekf_get_output(const aocs_mekf_t *f, aocs_mekf_output_t *out)
{
    aocs_status_t st = AOCS_OK;
    if ((f == NULL) || (out == NULL)) {
        st = AOCS_ERR_NULL_ARG;
        if (out != NULL) {
            (void)memset(out, 0, sizeof(*out));
        }
    } else if (f->initialised != MEKF_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
        (void)memset(out, 0, sizeof(*out));
    } else {
        st = (f->started != 0u) ? AOCS_OK : AOCS_ERR_MEKF_NO_ATTITUDE;
        mekf_fill_output(f, st, AOCS_ERR_INPUT_MISSING, out);
    }
    return st;
}

aocs_status_t aocs_mekf_step(aocs_mekf_t *f, const aocs_mekf_input_t *in, aocs_mekf_output_t *out)
{
    aocs_status_t st = AOCS_OK;
    aocs_status_t st_status = AOCS_ERR_INPUT_MISSING;
    if ((f == NULL) || (in == NULL) || (out == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (f->initialised != MEKF_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else if (f->gyroless != 0u) {
        st = AOCS_OK; /* spec 5.6.12: the gyro's reading is not used */
    } else {
        st = mekf_check_rate(in->w_meas_B_radps);
    }
    if ((st == AOCS_OK) && (f->started != 0u)) {
        st = aocs_mekf_propagate(f, in->w_meas_B_radps, in->t_ns);
        if ((st == AOCS_OK) && (in->st.valid != 0u)) {
            st_status = aocs_mekf_update(f, &in->st);
            if (st_status == AOCS_ERR_MEKF_COV_INVALID) {
                st = st_status;
            }
        } else if (st == AOCS_ERR_MEKF_GAP) {
            st = AOCS_OK; /* restarted: this step's sample may start it again below */
        } else {
            /* the propagation's error stands; the sample, if any, is not looked at */
        }
    }
    if ((st == AOCS_OK) && (f->started == 0u) && (f->configured_start != 0u)) {
        /* spec 5.6.10, init_mode configured: start at q0_BN now, then take this step's sample as any other */
        mekf_start_at(f, qd_of(f->cfg.q0_BN), in->t_ns);
        f->w_meas_B_radps = in->w_meas_B_radps;
        if (in->st.valid != 0u) {
            st_status = aocs_mekf_update(f, &in->st);
            if (st_status == AOCS_ERR_MEKF_COV_INVALID) {
                st = st_status;
            }
        }
    } else if ((st == AOCS_OK) && (f->started == 0u)) {
        if (in->st.valid == 0u) {
            st = AOCS_ERR_MEKF_NO_ATTITUDE;
        } else {
            st_status = mekf_start(f, &in->st, in->t_ns);
            if (st_status != AOCS_OK) {
                st = AOCS_ERR_MEKF_NO_ATTITUDE;
            } else if (in->t_ns > f->t_ns) {
                /* spec 5.6.10: from the sample's time of measurement to now with this step's rate */
                st = mekf_propagate_checked(f, in->w_meas_B_radps, in->t_ns);
            } else {
                /* measured now: nothing to propagate, but the output rate is this step's gyro less b_hat */
                f->w_meas_B_radps = in->w_meas_B_radps;
                st = AOCS_OK;
            }
        }
    } else {
        /* started already, or the step failed: nothing to start */
    }
    if (out != NULL) {
        if ((f == NULL) || (f->initialised != MEKF_INIT_MAGIC)) {
            (void)memset(out, 0, sizeof(*out));
        } else {
            mekf_fill_output(f, st, st_status, out);
        }
    }
    return st;
}

void aocs_mekf_reinflate_bias(aocs_mekf_t *f)
{
    if ((f != NULL) && (f->initialised == MEKF_INIT_MAGIC) && (f->started != 0u) && (f->gyroless == 0u)) {
        const real_t pb = f->cfg.p0_bias_sigma_radps * f->cfg.p0_bias_sigma_radps;
        for (int i = 3; i < 6; ++i) {
            for (int j = 0; j < 6; ++j) {
                f->P.m[i][j] = AOCS_R(0.0);
                f->P.m[j][i] = AOCS_R(0.0);
            }
            f->P.m[i][i] = pb;
        }
    }
}

void aocs_mekf_set_st_excluded(aocs_mekf_t *f, uint32_t excluded)
{
    if (f != NULL) {
        f->st_excluded = 0u;
        if (excluded != 0u) {
            f->st_excluded = 1u;
        }
    }
}

aocs_status_t aocs_mekf_set_gyroless(aocs_mekf_t *f, const aocs_mat3_t *inertia_B_kgm2, aocs_vec3_t w_hat_B_radps)
{
    aocs_status_t st = AOCS_OK;
    aocs_mat3_t jinv = aocs_mat3_identity();
    if ((f == NULL) || (inertia_B_kgm2 == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (f->initialised != MEKF_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else if (!(f->cfg.gyroless_torque_sigma_nm > AOCS_R(0.0))) {
        st = AOCS_ERR_MEKF_NOISE_NOT_POSITIVE; /* no gyroless model configured */
    } else {
        st = aocs_mat3_check_inertia(*inertia_B_kgm2);
        if (st == AOCS_OK) {
            st = aocs_mat3_inverse(*inertia_B_kgm2, &jinv);
        }
    }
    if (st == AOCS_OK) {
        const real_t pa = f->cfg.p0_att_sigma_rad * f->cfg.p0_att_sigma_rad;
        const real_t s0 = f->cfg.gyroless_p0_rate_sigma_radps;
        const real_t fl = MEKF_FLOOR_BIAS_FRAC * s0;
        f->inertia_B_kgm2 = *inertia_B_kgm2;
        f->inertia_inv_B = jinv;
        f->gyroless = 1u;
        f->w_hat_B_radps = aocs_vec3_zero();
        if ((aocs_vec3_is_finite(w_hat_B_radps) != 0) && (mekf_check_rate(w_hat_B_radps) == AOCS_OK)) {
            f->w_hat_B_radps = w_hat_B_radps;
        }
        /* spec 5.6.12: the switch: P = diag(p0_att^2 I, p0_rate^2 I), the rate block's floor from its prior */
        (void)memset(&f->P, 0, sizeof(f->P));
        for (int i = 0; i < 3; ++i) {
            f->P.m[i][i] = pa;
            f->P.m[i + 3][i + 3] = s0 * s0;
            f->p_floor[i + 3] = fl * fl;
        }
    }
    return st;
}

void aocs_mekf_set_torque(aocs_mekf_t *f, aocs_vec3_t tau_B_Nm, aocs_vec3_t h_wheels_B_Nms)
{
    if (f != NULL) {
        f->tau_B_Nm = (aocs_vec3_is_finite(tau_B_Nm) != 0) ? tau_B_Nm : aocs_vec3_zero();
        f->h_wheels_B_Nms = (aocs_vec3_is_finite(h_wheels_B_Nms) != 0) ? h_wheels_B_Nms : aocs_vec3_zero();
    }
}

uint32_t aocs_mekf_is_gyroless(const aocs_mekf_t *f)
{
    return ((f != NULL) && (f->gyroless != 0u)) ? 1u : 0u;
}

void aocs_mekf_set_st_noise_scale(aocs_mekf_t *f, real_t scale)
{
    if ((f != NULL) && (f->initialised == MEKF_INIT_MAGIC)) {
        const real_t sc = f->cfg.st_sigma_cross_rad;
        const real_t sa = f->cfg.st_sigma_about_rad;
        real_t k = AOCS_R(1.0);
        if (AOCS_IS_FINITE(scale) && (scale > AOCS_R(1.0))) {
            k = scale;
        }
        /* spec 5.15.3: R_S = diag(sc^2, sc^2, sa^2) times the scale */
        f->st_noise_scale = k;
        f->r_S[0] = k * sc * sc;
        f->r_S[1] = k * sc * sc;
        f->r_S[2] = k * sa * sa;
    }
}
