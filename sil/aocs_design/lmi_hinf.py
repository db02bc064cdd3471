"""H-infinity state feedback through LMIs (SPEC 2.6, Duan and Yu), cvxpy + Clarabel / SCS.

Selection rule (the minimum gamma is reached by many K, SPEC 2.6):

1. gamma* = min gamma subject to X > 0, the bounded-real LMI of SPEC 2.6 and,
   when the design has a pole region, the decay-rate LMI
   (A X + B1 W) + (A X + B1 W)^T + 2 alpha X < 0   (all poles Re < -alpha).
2. gamma_fix = (1 + delta) gamma*; among all (X, W) feasible at gamma_fix with
   the decay-rate LMI at alpha_sel, take the one of minimum control effort
   trace(K X K^T) = min trace(Z) with [[Z, W], [W^T, X]] >= 0.
   Without a decay floor that minimum is not attained (the effort goes to zero
   as poles approach the imaginary axis), so every design states alpha_sel.
   The bounded form (Duan and Yu's second form, -I < [...] < 0) adds, in
   steps 1 and 2, the lower bound: the bounded-real LMI matrix in SI units
   must exceed -I. That bounds X and A X + B1 W, hence the gain: the plain
   minimum-effort solution has LMI eigenvalues near -9 and is excluded.
3. K = W X^-1; entries below K_ZERO_RTOL * max|K| are set to 0 (solver noise
   in structurally zero couplings) and K is rounded to K_SIG_DIGITS
   significant digits, so solver noise below that cannot change the table.
   Every check is then repeated on the rounded K.

Numerics: the LMIs are solved in scaled units (input and disturbance in kN m,
sigma = 1000, so D1 = D2 = I and gamma ~ 1; angles scaled by alpha_sel so X is
well conditioned). The strict inequalities are imposed with a margin
LMI_MARGIN * I in those units. trace(K X K^T), gamma and K are invariant under
this scaling, so the rule does not depend on it; only conditioning does.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from .checks import (
    DesignError,
    InfeasibleLMIError,
    SolverDisagreementError,
    hinf_norm,
    require_controllable,
    require_stable,
)
from .models import HinfPlant

SIGMA = 1000.0          # N m per scaled input unit
LMI_MARGIN = 1e-6       # strictness margin of every LMI, scaled units
K_SIG_DIGITS = 9
K_ZERO_RTOL = 1e-10
SCS_OPTS = {"eps_abs": 1e-8, "eps_rel": 1e-8, "max_iters": 200000}
GOOD = ("optimal",)


@dataclass
class HinfResult:
    name: str
    plant: HinfPlant
    k: np.ndarray                 # u = +K x, rounded as emitted
    k_raw: np.ndarray             # Clarabel, before rounding
    k_scs: np.ndarray
    x: np.ndarray                 # X in SI units (with W = K_raw X)
    w: np.ndarray
    gamma_star: float             # step 1 minimum (Clarabel)
    gamma_star_scs: float
    gamma: float                  # gamma_fix: the LMI's gamma for the emitted K
    hinf_norm: float              # independent closed-loop norm of the emitted K
    hinf_sweep: float
    hinf_peak_rad_s: float
    lmi_max_eig: float            # max eigenvalue of the assembled LMI at (X, K X, gamma)
    decay_max_eig: float
    poles: np.ndarray
    alpha: float | None           # pole-region decay rate used in step 1 (None: plain SPEC LMI)
    bounded: bool                 # the LMI is also bounded below by -I (SI units), steps 1 and 2
    gamma_min: float              # minimum gamma of the plain SPEC LMI (no region, no bound), Clarabel
    lmi_min_eig: float            # min eigenvalue of the assembled LMI at the emitted K (bounded: > -1)
    alpha_sel: float
    delta: float
    k_rel_diff: float             # ||K_clarabel - K_scs||_F / ||K_clarabel||_F
    k_rtol: float
    solver: str
    status: str
    inputs: dict = field(default_factory=dict)

    @property
    def slowest_pole_re(self) -> float:
        return float(np.max(self.poles.real))

    @property
    def form(self) -> str:
        """Which LMI step 1 minimised: "plain" (SPEC 2.6), "decay_rate" (+ pole region), "bounded" (-I < . < 0)."""
        if self.bounded:
            return "bounded"
        return "plain" if self.alpha is None else "decay_rate"


def closed_loop(plant: HinfPlant, k: np.ndarray):
    """d -> z of xdot = (A + B1 K) x + B2 d, z = (C1 + D1 K) x + D2 d."""
    return plant.a + plant.b1 @ k, plant.b2, plant.c1 + plant.d1 @ k, plant.d2


def assemble_lmi(plant: HinfPlant, x: np.ndarray, w: np.ndarray, gamma: float) -> np.ndarray:
    """The bounded-real LMI matrix of SPEC 2.6 in SI units (numpy, for checking)."""
    axbw = plant.a @ x + plant.b1 @ w
    cxdw = plant.c1 @ x + plant.d1 @ w
    nz, nd = plant.c1.shape[0], plant.b2.shape[1]
    m = np.block([[axbw + axbw.T, plant.b2, cxdw.T],
                  [plant.b2.T, -gamma * np.eye(nd), plant.d2.T],
                  [cxdw, plant.d2, -gamma * np.eye(nz)]])
    return 0.5 * (m + m.T)


def assemble_decay(plant: HinfPlant, x: np.ndarray, w: np.ndarray, alpha: float) -> np.ndarray:
    axbw = plant.a @ x + plant.b1 @ w
    m = axbw + axbw.T + 2.0 * alpha * x
    return 0.5 * (m + m.T)


def _scaled(plant: HinfPlant, angle_scale: float):
    n = plant.a.shape[0]
    t = np.eye(n)
    t[: n // 2, : n // 2] /= angle_scale
    ti = np.linalg.inv(t)
    return {"a": ti @ plant.a @ t, "b1": ti @ plant.b1 * SIGMA, "b2": ti @ plant.b2 * SIGMA,
            "c1": plant.c1 @ t, "d1": plant.d1 * SIGMA, "d2": plant.d2 * SIGMA, "t": t}


def _problem(s, gamma, alpha, min_effort: bool, bounded: bool = False):
    import cvxpy as cp  # deferred: ~1 s to import, only the H-infinity designs need it

    n, m = s["b1"].shape
    nd, nz = s["b2"].shape[1], s["c1"].shape[0]
    x = cp.Variable((n, n), symmetric=True)
    w = cp.Variable((m, n))
    g = cp.Variable() if gamma is None else float(gamma)
    axbw = s["a"] @ x + s["b1"] @ w
    cxdw = s["c1"] @ x + s["d1"] @ w
    lmi = cp.bmat([[axbw + axbw.T, s["b2"], cxdw.T],
                   [s["b2"].T, -g * np.eye(nd), s["d2"].T],
                   [cxdw, s["d2"], -g * np.eye(nz)]])
    size = n + nd + nz
    cons = [0.5 * (lmi + lmi.T) << -LMI_MARGIN * np.eye(size), x >> LMI_MARGIN * np.eye(n)]
    if bounded:
        # M_s = SIGMA P M_si P^T with P = diag(T^-1, I, I) (the scaling of _scaled), so
        # M_si > -I  <=>  M_s + SIGMA P P^T > 0
        pdiag = np.concatenate([np.diag(np.linalg.inv(s["t"])) ** 2, np.ones(nd + nz)])
        cons.append(0.5 * (lmi + lmi.T) + SIGMA * np.diag(pdiag) >> LMI_MARGIN * np.eye(size))
    if alpha is not None:
        dec = axbw + axbw.T + 2.0 * alpha * x
        cons.append(0.5 * (dec + dec.T) << -LMI_MARGIN * np.eye(n))
    if min_effort:
        z = cp.Variable((m, m), symmetric=True)
        sch = cp.bmat([[z, w], [w.T, x]])
        cons.append(0.5 * (sch + sch.T) >> 0)
        obj = cp.Minimize(cp.trace(z))
    else:
        obj = cp.Minimize(g)
    return cp.Problem(obj, cons), x, w, g


def _solve(name, prob, solver):
    import cvxpy as cp  # deferred: ~1 s to import, only the H-infinity designs need it

    opts = SCS_OPTS if solver == "SCS" else {}
    try:
        with warnings.catch_warnings():
            # the status is checked below; cvxpy's "may be inaccurate" warning adds nothing
            warnings.simplefilter("ignore", UserWarning)
            prob.solve(solver=getattr(cp, solver), **opts)
    except cp.error.SolverError as exc:
        raise InfeasibleLMIError(f"{name}: {solver} failed on the LMI: {exc}; no table written") from exc
    if prob.status in ("infeasible", "infeasible_inaccurate"):
        raise InfeasibleLMIError(f"{name}: LMI infeasible ({solver} status '{prob.status}'); "
                                 "no table written")
    if prob.status not in GOOD:
        raise InfeasibleLMIError(f"{name}: {solver} did not solve the LMI (status '{prob.status}'); "
                                 "no table written")
    return prob.status


def min_gamma(name: str, plant: HinfPlant, alpha: float | None, angle_scale: float,
              solver: str = "CLARABEL", bounded: bool = False) -> float:
    """Step 1: minimum gamma (SI units) of the bounded-real LMI (+ decay rate, + lower bound -I)."""
    s = _scaled(plant, angle_scale)
    prob, _, _, g = _problem(s, None, None if alpha is None else alpha, False, bounded)
    _solve(name, prob, solver)
    return float(g.value) / SIGMA


def min_effort_gain(name: str, plant: HinfPlant, gamma: float, alpha_sel: float,
                    solver: str = "CLARABEL", bounded: bool = False):
    """Step 2 at a fixed gamma (SI units): returns K (+K x), X, W in SI units and the status."""
    s = _scaled(plant, alpha_sel)
    prob, x, w, _ = _problem(s, gamma * SIGMA, alpha_sel, True, bounded)
    status = _solve(name, prob, solver)
    xs, ws, t = np.asarray(x.value), np.asarray(w.value), s["t"]
    k = SIGMA * ws @ np.linalg.inv(xs) @ np.linalg.inv(t)
    x_si = t @ xs @ t.T / SIGMA
    w_si = ws @ t.T
    return k, 0.5 * (x_si + x_si.T), w_si, status


def round_sig(k: np.ndarray, digits: int = K_SIG_DIGITS, zero_rtol: float = K_ZERO_RTOL) -> np.ndarray:
    kmax = float(np.max(np.abs(k)))
    out = np.zeros_like(k)
    for idx, v in np.ndenumerate(k):
        if abs(v) > zero_rtol * kmax:
            out[idx] = float(f"{v:.{digits - 1}e}")
    return out


def design(name: str, plant: HinfPlant, *, alpha: float | None, alpha_sel: float, delta: float,
           k_rtol: float, inputs: dict | None = None, bounded: bool = False) -> HinfResult:
    import clarabel  # deferred: solver versions for the provenance, with cvxpy
    import cvxpy as cp  # deferred: ~1 s to import, only the H-infinity designs need it
    import scs  # deferred: as clarabel

    require_controllable(name, plant.a, plant.b1)
    if alpha is not None and not math.isclose(alpha, alpha_sel):
        raise DesignError(f"{name}: pole-region alpha {alpha} must equal the selection alpha_sel {alpha_sel}")
    # step 1 without a pole region is the plain SPEC LMI: left unscaled in the angles
    scale1 = alpha_sel if alpha is not None else 1.0
    gstar = min_gamma(name, plant, alpha, scale1, "CLARABEL", bounded)
    gstar_scs = min_gamma(name, plant, alpha, scale1, "SCS", bounded)
    if abs(gstar_scs - gstar) > 1e-4 * gstar:
        raise SolverDisagreementError(f"{name}: minimum gamma differs: Clarabel {gstar:.9g}, SCS {gstar_scs:.9g}")
    plain = alpha is None and not bounded
    gmin = gstar if plain else min_gamma(name, plant, None, 1.0, "CLARABEL")
    gfix = (1.0 + delta) * gstar
    k_raw, x, w, status = min_effort_gain(name, plant, gfix, alpha_sel, "CLARABEL", bounded)
    k_scs, _, _, _ = min_effort_gain(name, plant, gfix, alpha_sel, "SCS", bounded)
    rel = float(np.linalg.norm(k_raw - k_scs) / np.linalg.norm(k_raw))
    if not rel <= k_rtol:
        raise SolverDisagreementError(
            f"{name}: Clarabel and SCS gains differ by {rel:.3e} (relative Frobenius) > {k_rtol:.1e}; "
            "no table written")
    k = round_sig(k_raw)
    # every check on the emitted (rounded) K, with X from the solver and W = K X
    w_emit = k @ x
    lmi_eigs = np.linalg.eigvalsh(assemble_lmi(plant, x, w_emit, gfix))
    lmi_eig, lmi_min = float(np.max(lmi_eigs)), float(np.min(lmi_eigs))
    dec_eig = float(np.max(np.linalg.eigvalsh(assemble_decay(plant, x, w_emit, alpha_sel))))
    if not (lmi_eig < 0.0 and dec_eig < 0.0 and np.min(np.linalg.eigvalsh(x)) > 0.0):
        raise DesignError(f"{name}: LMI not satisfied at the emitted K (max eig {lmi_eig:.3e}, "
                          f"decay {dec_eig:.3e}); no table written")
    if bounded and not lmi_min > -1.0:
        raise DesignError(f"{name}: LMI not bounded below by -I at the emitted K (min eig {lmi_min:.6g}); "
                          "no table written")
    a_cl, b_cl, c_cl, d_cl = closed_loop(plant, k)
    poles = np.linalg.eigvals(a_cl)
    require_stable(name, poles)
    if not np.max(poles.real) < -alpha_sel * (1.0 - 1e-6):
        raise DesignError(f"{name}: slowest pole {np.max(poles.real):.6g} not left of -alpha_sel")
    # independent norm in kN m input units (well scaled), back to SI
    hn = hinf_norm(a_cl, b_cl * SIGMA, c_cl, d_cl * SIGMA)
    norm = hn["norm"] / SIGMA
    if not norm <= gfix * (1.0 + 1e-9):
        raise DesignError(f"{name}: closed-loop H-infinity norm {norm:.9g} exceeds the LMI gamma {gfix:.9g}")
    return HinfResult(
        name=name, plant=plant, k=k, k_raw=k_raw, k_scs=k_scs, x=x, w=w_emit, gamma_star=gstar,
        gamma_star_scs=gstar_scs, gamma=gfix, hinf_norm=norm, hinf_sweep=hn["sweep"] / SIGMA,
        hinf_peak_rad_s=hn["peak_rad_s"], lmi_max_eig=lmi_eig, decay_max_eig=dec_eig, poles=poles,
        alpha=alpha, bounded=bounded, gamma_min=gmin, lmi_min_eig=lmi_min, alpha_sel=alpha_sel,
        delta=delta, k_rel_diff=rel, k_rtol=k_rtol,
        solver=(f"cvxpy {cp.__version__} + Clarabel {clarabel.__version__} "
                f"(cross-check SCS {scs.__version__})"),
        status=status, inputs=dict(inputs or {}))
