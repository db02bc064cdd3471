/* orbit_lqr: SPEC 2.8, see orbit_lqr.h. */
#include <stddef.h>

#include "aocs/control/orbit_lqr.h"

aocs_status_t aocs_orbit_lqr_init(aocs_orbit_lqr_t *law, const aocs_orbit_lqr_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (law != NULL) {
        law->initialised = 0;
    }
    if ((law == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 6; ++j) {
                if (!AOCS_IS_FINITE(cfg->k[i][j])) {
                    st = AOCS_ERR_PARAM_NOT_FINITE;
                }
            }
        }
        if (st == AOCS_OK) {
            for (int i = 0; i < 3; ++i) {
                if (!(cfg->k[i][i] > AOCS_R(0.0))) {
                    st = AOCS_ERR_GAIN_TABLE_INVALID;
                }
            }
        }
        if (st == AOCS_OK) {
            law->cfg = *cfg;
            law->initialised = 1;
        }
    }
    return st;
}

aocs_status_t aocs_orbit_lqr_step(aocs_orbit_lqr_t *law, const aocs_orbit_input_t *in, aocs_vec3_t *f_out)
{
    aocs_status_t st = AOCS_OK;
    aocs_vec3_t f = aocs_vec3_zero();

    if ((law == NULL) || (f_out == NULL) || (in == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (law->initialised == 0) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        st = aocs_orbit_input_check(in);
    }
    if (st == AOCS_OK) {
        real_t x[6];
        /* SPEC 2.8 state order: velocities first, then positions */
        for (int i = 0; i < 3; ++i) {
            x[i] = in->vel_mps.v[i];
            x[3 + i] = in->pos_m.v[i];
        }
        for (int i = 0; i < 3; ++i) {
            real_t acc = AOCS_R(0.0);
            for (int j = 0; j < 6; ++j) {
                acc += law->cfg.k[i][j] * x[j];
            }
            f.v[i] = -acc;
        }
        if (aocs_vec3_is_finite(f) == 0) {
            st = AOCS_ERR_OUTPUT_NOT_FINITE; /* finite inputs, overflowing result */
        }
    }
    if (f_out != NULL) {
        *f_out = (st == AOCS_OK) ? f : aocs_vec3_zero();
    }
    return st;
}
