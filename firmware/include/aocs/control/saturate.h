/*
 * Shared saturation helpers: actuator limits (per axis, on the vector norm)
 * and the scalar saturation functions used inside the control laws.
 *
 * Every function is total. Non-finite inputs never produce a value outside
 * the bound:
 *   - a NaN signal gives 0 (the safe command), with *saturated = 1;
 *   - +-Inf gives the bound with the sign of the input;
 *   - a limit / level that is NaN or <= 0 gives 0 (nothing may be commanded);
 *   - a limit of +Inf means "no limit" (the input passes unchanged).
 */
#ifndef AOCS_CONTROL_SATURATE_H
#define AOCS_CONTROL_SATURATE_H

#include "aocs/math3.h"

/*
 * Clamp each axis to [-limit_i, +limit_i] (actuator limit per axis, SPEC 3).
 * *saturated (may be NULL) is set to 1 when any axis was changed, else 0.
 */
aocs_vec3_t aocs_sat_clamp_per_axis(aocs_vec3_t u, aocs_vec3_t limit, int *saturated);

/*
 * Scale the whole vector down to |u|_2 = max_norm when |u|_2 > max_norm,
 * keeping its direction (SPEC 3, limit on the vector norm). Scale-aware: the
 * norm is computed as amax sqrt(sum (u_i / amax)^2) (amax = max |u_i|) and the
 * result as (u / amax) (max_norm / root), so nothing overflows or underflows
 * for any finite u and any normal max_norm. Exact bound: the computed norm of
 * the result is at most max_norm (1 - 8 eps) (pulled back when rounding lands
 * above), and that computation is within 3 eps of the exact norm, so the
 * exact |out|_2 < max_norm; a scaled result is above max_norm (1 - 24 eps)
 * (normal max_norm).
 * A u within 8 eps below max_norm may be scaled too (the margin). If some
 * components are +-Inf (and none NaN) the direction of the infinite
 * components is kept. *saturated (may be NULL) is 1 when u was scaled (or
 * zeroed), else 0.
 */
aocs_vec3_t aocs_sat_scale_to_norm(aocs_vec3_t u, real_t max_norm, int *saturated);

/*
 * 1 when |v|_2, computed scale-aware as above, is above limit (no overflow
 * or underflow of the norm itself); 1 as well for a non-finite v or a NaN
 * limit (nothing can be said), 0 for limit = +Inf. A result of
 * aocs_sat_scale_to_norm(u, limit) always gives 0 here. Total.
 */
int aocs_sat_norm_above(aocs_vec3_t v, real_t limit);

/*
 * Linear saturation function of Gao, Lu, Wang 2010 (SPEC 2.7): phi(x) = x for
 * |x| <= l, |phi| <= m, odd, increasing, continuous and C1, locally
 * Lipschitz. Above l:
 *     phi(x) = sign(x) (l + (m - l) tanh((|x| - l) / (m - l)))
 * so the slope is 1 at |x| = l (tanh'(0) = 1) and phi -> m as |x| -> Inf.
 * With l >= m (in particular l = m) it is the plain clamp to [-m, m].
 * Parameters: m NaN or <= 0 -> 0; l NaN or < 0 -> taken as 0 (then
 * phi = m tanh(x / m)); m = +Inf -> identity. Result clamped to [-m, m].
 */
real_t aocs_sat_linear(real_t x, real_t l, real_t m);

/*
 * Generalised saturation phi(x) = m tanh(x / m) (SPEC 2.7, tanh variant):
 * unit slope at 0, |phi| <= m. m NaN or <= 0 -> 0; m = +Inf -> x; x NaN -> 0.
 */
real_t aocs_sat_tanh(real_t x, real_t m);

/*
 * Boundary-layer saturation of the sliding surface (SPEC 2.4, CVM 2000):
 * s / eps inside |s| <= eps, sign(s) outside (the reference's |s|/eps is a
 * typo). eps NaN or <= 0 -> sign(s) (the eps -> 0 limit, sign(0) = 0);
 * eps = +Inf -> 0; s NaN -> 0. Result in [-1, 1].
 */
real_t aocs_sat_boundary_layer(real_t s, real_t eps);

#endif /* AOCS_CONTROL_SATURATE_H */
