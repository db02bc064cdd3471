/*
 * Shared pieces of the libFuzzer targets (tests/fuzz/README.md): a reader of
 * the fuzz bytes, a valid configuration of every law, and the invariant of
 * every executive output (finite command within every enabled limit, the
 * norm checked exactly in long double). A violated invariant aborts, which
 * libFuzzer reports as a crash with the input that caused it.
 */
#ifndef AOCS_FUZZ_SUPPORT_H
#define AOCS_FUZZ_SUPPORT_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aocs/executive.h"
#include "aocs_registry.h"
#include "../unit/exact_norm.h"

/* ---- byte reader: past the end every read gives zeros ---- */
typedef struct {
    const uint8_t *p;
    size_t n;
    size_t pos;
} fuzz_reader_t;

static inline void fuzz_bytes(fuzz_reader_t *r, void *out, size_t k)
{
    uint8_t *o = (uint8_t *)out;
    for (size_t i = 0; i < k; ++i) {
        o[i] = (r->pos < r->n) ? r->p[r->pos++] : 0u;
    }
}

static inline int fuzz_more(const fuzz_reader_t *r)
{
    return (r->pos < r->n) ? 1 : 0;
}

static inline uint8_t fuzz_u8(fuzz_reader_t *r)
{
    uint8_t v;
    fuzz_bytes(r, &v, 1u);
    return v;
}

static inline uint16_t fuzz_u16(fuzz_reader_t *r)
{
    uint16_t v;
    fuzz_bytes(r, &v, sizeof(v));
    return v;
}

/* The next payload: a u16 little-endian length and that many bytes (fewer at the end of the input), copied
 * into buf (room for 65535 bytes); returns its length. */
static inline uint16_t fuzz_chunk(fuzz_reader_t *r, uint8_t *buf)
{
    uint16_t len = fuzz_u16(r);
    const size_t avail = r->n - r->pos;
    if ((size_t)len > avail) {
        len = (uint16_t)avail;
    }
    memcpy(buf, r->p + r->pos, len);
    r->pos += len;
    return len;
}

static inline uint32_t fuzz_u32(fuzz_reader_t *r)
{
    uint32_t v;
    fuzz_bytes(r, &v, sizeof(v));
    return v;
}

static inline uint64_t fuzz_u64(fuzz_reader_t *r)
{
    uint64_t v;
    fuzz_bytes(r, &v, sizeof(v));
    return v;
}

/* any double, NaN and Inf included (raw bits) */
static inline double fuzz_f64(fuzz_reader_t *r)
{
    double v;
    fuzz_bytes(r, &v, sizeof(v));
    return v;
}

/* 10^e with e from a u16 spread over [lo, hi]: a plausible magnitude */
/* A real: raw f64 (raw != 0), or a u16 mapped onto [lo, hi). */
static inline real_t fuzz_scaled(fuzz_reader_t *r, int raw, double lo, double hi)
{
    double v;
    if (raw != 0) {
        v = fuzz_f64(r);
    } else {
        v = lo + ((hi - lo) * (double)fuzz_u16(r) / 65536.0);
    }
    return (real_t)v;
}

static inline double fuzz_mag(fuzz_reader_t *r, double lo, double hi)
{
    return pow(10.0, lo + (hi - lo) * ((double)fuzz_u16(r) / 65535.0));
}

/*
 * ---- a valid configuration of every law: the registry's reference configuration ----
 * (the REF column of every law field row of laws.def, tools/registry), so a new law is fuzzed
 * with its own reference values and no list here can miss it. A row whose REF does not parse
 * aborts with its key.
 */
static inline void fuzz_all_law_configs(aocs_exec_law_configs_t *laws)
{
    static aocs_exec_law_configs_t reference; /* parsed once: every input starts from the same values */
    static int parsed = 0;
    if (parsed == 0) {
        char err[256];
        if (aocs_registry_reference_configs(&reference, err, sizeof(err)) != 0) {
            (void)fprintf(stderr, "fuzz: the registry's reference configuration is not valid: %s\n", err);
            abort();
        }
        parsed = 1;
    }
    *laws = reference;
}

/* ---- the MEKF (estimation/mekf.h, the mekf row of determination.def) ---- */

/*
 * A configuration of the MEKF from the fuzz bytes: its defaults (aocs_mekf_config_default, the mekf.* rows'
 * DEFAULT) with, when `mode` asks, plausible magnitudes of every noise and tuning figure (bit0) and a tracker
 * mounting from 3 bytes (bit1), a configured start (mekf.init_mode configured) at an initial estimate from
 * 3 bytes (bit2). Always one the init accepts (an init failure would end the input early).
 *   reads (bit0): 6 x u16 magnitudes (cross, about, ARW, RRW, P0 att, P0 bias), u16 gate, u16 max gap;
 *         (bit1): 3 x u8 mounting; (bit2): 3 x u8 initial estimate q0_BN
 */
static inline void fuzz_mekf_config(fuzz_reader_t *r, uint8_t mode, aocs_mekf_config_t *c)
{
    aocs_mekf_config_default(c);
    if ((mode & 1u) != 0u) {
        c->st_sigma_cross_rad = (real_t)fuzz_mag(r, -9.0, -1.0);
        c->st_sigma_about_rad = (real_t)fuzz_mag(r, -9.0, -1.0);
        c->gyro_arw_radpsqrts = (real_t)fuzz_mag(r, -10.0, -2.0);
        c->gyro_rrw_radps1p5 = (real_t)fuzz_mag(r, -14.0, -4.0);
        c->p0_att_sigma_rad = (real_t)fuzz_mag(r, -6.0, 0.5);
        c->p0_bias_sigma_radps = (real_t)fuzz_mag(r, -9.0, -1.0);
        c->gate_chi2 = (real_t)fuzz_mag(r, -1.0, 4.0);
        c->max_gap_s = (real_t)fuzz_mag(r, -3.0, 3.5);
    }
    if ((mode & 2u) != 0u) {
        const double a = (double)fuzz_u8(r) / 40.0;
        const double b = (double)fuzz_u8(r) / 40.0;
        const double d = (double)fuzz_u8(r) / 40.0;
        const double n = sqrt(1.0 + (a * a) + (b * b) + (d * d));
        c->q_SB = aocs_quat_make((real_t)(a / n), (real_t)(b / n), (real_t)(d / n), (real_t)(1.0 / n));
    }
    if ((mode & 4u) != 0u) {
        const double a = ((double)fuzz_u8(r) - 128.0) / 40.0;
        const double b = ((double)fuzz_u8(r) - 128.0) / 40.0;
        const double d = ((double)fuzz_u8(r) - 128.0) / 40.0;
        const double n = sqrt(1.0 + (a * a) + (b * b) + (d * d));
        c->init_mode = AOCS_MEKF_INIT_CONFIGURED;
        c->q0_BN = aocs_quat_make((real_t)(a / n), (real_t)(b / n), (real_t)(d / n), (real_t)(1.0 / n));
    }
    if ((mode & 8u) != 0u) {
        /* the gyroless model (spec 5.6.12): none (0), or torque noise, rate prior and usable rate */
        const uint8_t none = fuzz_u8(r);
        c->gyroless_torque_sigma_nm = (none == 0u) ? (real_t)0.0 : (real_t)fuzz_mag(r, -6.0, 1.0);
        c->gyroless_p0_rate_sigma_radps = (real_t)fuzz_mag(r, -5.0, 0.0);
        c->gyroless_rate_sigma_radps = (real_t)fuzz_mag(r, -8.0, -2.0);
    }
}

/* An estimate of the determination stage: every real finite; a usable one is a unit q with both flags, an
 * unusable one has no attitude flag; the covariance's diagonal (p_upper 0, 6, 11, 15, 18, 20) not negative. */
static inline void fuzz_check_estimate(const aocs_det_output_t *e)
{
    static const uint32_t diag[6] = {0u, 6u, 11u, 15u, 18u, 20u};
    int ok = (aocs_quat_is_finite(e->q_BN) != 0) && (aocs_vec3_is_finite(e->w_BN_B) != 0) &&
             (aocs_vec3_is_finite(e->bias_B_radps) != 0);
    for (uint32_t i = 0u; i < AOCS_EST_P_UPPER_COUNT; ++i) {
        ok = ok && AOCS_IS_FINITE(e->p_upper[i]);
    }
    for (uint32_t i = 0u; i < 6u; ++i) {
        ok = ok && !(e->p_upper[diag[i]] < AOCS_R(0.0));
    }
    if (e->status == AOCS_OK) {
        ok = ok && (e->valid == (AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE)) &&
             (AOCS_FABS(aocs_quat_norm(e->q_BN) - AOCS_R(1.0)) <= AOCS_R(1.0e-3));
    } else {
        ok = ok && ((e->valid & AOCS_EXEC_VALID_ATT) == 0u);
    }
    if (ok == 0) {
        (void)fprintf(stderr, "fuzz invariant violated: estimate (status %d, valid %u) not finite or inconsistent\n",
                      (int)e->status, (unsigned)e->valid);
        abort();
    }
}

/* ---- the invariant ---- */

static inline void fuzz_fail(const char *what, const aocs_exec_config_t *cfg, aocs_vec3_t u)
{
    (void)fprintf(stderr, "fuzz invariant violated: %s: u_cmd = (%.17g %.17g %.17g), axis (%.17g %.17g %.17g), norm %.17g\n",
                  what, (double)u.v[0], (double)u.v[1], (double)u.v[2], (double)cfg->u_max_axis.v[0],
                  (double)cfg->u_max_axis.v[1], (double)cfg->u_max_axis.v[2], (double)cfg->u_max_norm);
    abort();
}

/* every output of the executive: finite, within every enabled limit (exact norm) */
static inline void fuzz_check_output(const aocs_exec_config_t *cfg, const aocs_exec_output_t *out)
{
    const aocs_vec3_t u = out->u_cmd;
    if (aocs_vec3_is_finite(u) == 0) {
        fuzz_fail("command not finite", cfg, u);
    }
    if ((cfg->u_max_axis.v[0] > AOCS_R(0.0)) && (cfg->u_max_axis.v[1] > AOCS_R(0.0)) &&
        (cfg->u_max_axis.v[2] > AOCS_R(0.0))) {
        for (int i = 0; i < 3; ++i) {
            if (!(fabsl((long double)u.v[i]) <= (long double)cfg->u_max_axis.v[i])) {
                fuzz_fail("per-axis limit exceeded", cfg, u);
            }
        }
    }
    if ((cfg->u_max_norm > AOCS_R(0.0)) && !(exact_norm(u) <= (long double)cfg->u_max_norm)) {
        fuzz_fail("norm limit exceeded", cfg, u);
    }
}

/* ---- the reaction wheel array (wheel_array.h, docs/spec.md 5.3) ---- */

/* The SPEC 5.3 reference pyramid about x with the irassi_rw friction model and null-space management
 * (docs/spec.md 5.3.2); wheel 3 failed when asked. A configuration aocs_wheels_init accepts. */
static inline void fuzz_wheels(aocs_wheels_config_t *w, int failed)
{
    const double beta = acos(1.0 / sqrt(3.0));
    aocs_wheels_config_default(w);
    w->n = 4u;
    for (uint32_t i = 0u; i < 4u; ++i) {
        const double az = 1.5707963267948966 * (double)i;
        w->axis_B[i] = aocs_vec3_make((real_t)cos(beta), (real_t)(sin(beta) * cos(az)), (real_t)(sin(beta) * sin(az)));
        w->js_kgm2[i] = AOCS_R(0.08);
        w->u_max_nm[i] = AOCS_R(0.25);
        w->omega_max_radps[i] = AOCS_R(600.0);
        w->viscous_nms[i] = AOCS_R(1.0e-5);
        w->coulomb_nm[i] = AOCS_R(2.0e-3);
        w->coulomb_width_radps[i] = AOCS_R(0.5);
        w->null_speed_radps[i] = AOCS_R(((i % 2u) == 0u) ? 50.0 : -50.0);
    }
    w->null_gain_per_s = AOCS_R(0.02);
    w->failed_mask = (failed != 0) ? 8u : 0u;
    w->inertia_B_kgm2 = aocs_mat3_diag(aocs_vec3_make(AOCS_R(2059.5), AOCS_R(5954.2), AOCS_R(5974.3)));
}

/* every wheel command finite and within its motor limit exactly (the compensation included; not even 1 ulp
 * over, issue 25 item 6; docs/spec.md 5.3.3), zero for an absent wheel, none to a failed wheel */
static inline void fuzz_check_wheels(const aocs_exec_config_t *cfg, const aocs_exec_output_t *out)
{
    for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
        const real_t u = out->wheels.u_s_nm[i];
        const real_t lim = (i < cfg->wheels.n) ? cfg->wheels.u_max_nm[i] : AOCS_R(0.0);
        if (!AOCS_IS_FINITE(u) || !(AOCS_FABS(u) <= lim)) {
            fuzz_fail("wheel command not finite or beyond its motor limit", cfg, out->u_cmd);
        }
        if (((cfg->wheels.failed_mask >> i) & 1u) != 0u) {
            if (u > AOCS_R(0.0) || u < AOCS_R(0.0)) {
                fuzz_fail("a failed wheel was commanded", cfg, out->u_cmd);
            }
        }
    }
}

#endif /* AOCS_FUZZ_SUPPORT_H */
