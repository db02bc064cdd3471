"""One gain design from its configuration: a `[designs.<name>]` row of tools/gains.toml and the
plant it names. `aocs gains` runs it for every row (the compiled tables); the runner runs it for a
scenario's own plant and weights at run start (aocs_runner.scenario_gains). One function, so a
table designed at run start passes exactly the checks of a compiled one.

Weights `q` and `r` are a number (times the identity, as in tools/gains.toml) or the diagonal
(6 and 3 numbers, as a scenario may give them). The `lqr_quat` plant takes `inertia_diag` or a
full 3x3 `inertia` (B = [0; J^-1], SPEC 2.5).
"""
from __future__ import annotations

import numpy as np

from . import models
from .errors import DesignError

#: the design kinds with LQR weights q (one per state: 6, or 9 for lqr_quat_i) and r (3): the
#: weights a scenario may set
LQR_KINDS = ("lqr_quat", "orbit_lqr", "lqr_quat_i")


def state_count(kind: str) -> int:
    """Length of the state an LQR kind weighs (the columns of its gain): 9 for lqr_quat_i, else 6."""
    return 9 if kind == "lqr_quat_i" else 6


def weight_matrix(v, n: int) -> np.ndarray:
    """q or r as the n x n weight: a number times I, or a diagonal of n numbers."""
    a = np.asarray(v, dtype=float)
    if a.ndim == 0:
        return float(a) * np.eye(n)
    if a.shape != (n,):
        raise ValueError(f"weight {v!r}: a number or {n} numbers")
    return np.diag(a)


def weight_text(v, n: int) -> str:
    """'200 I6' for a number (the text of the compiled tables' provenance), 'diag(...)' otherwise."""
    a = np.asarray(v, dtype=float)
    if a.ndim == 0:
        return f"{float(a):g} I{n}"
    return f"diag({', '.join(f'{x:g}' for x in a)})"


def inertia_of(plant: dict) -> np.ndarray:
    """The lqr_quat / hinf plant's inertia as a 3x3 matrix (kg m^2)."""
    if "inertia" in plant:
        return np.asarray(plant["inertia"], dtype=float).reshape(3, 3)
    return np.diag(np.asarray(plant["inertia_diag"], dtype=float))


def _inertia_text(j: np.ndarray) -> str:
    if np.count_nonzero(j - np.diag(np.diag(j))) == 0:
        return f"diag({', '.join(f'{v:g}' for v in np.diag(j))}) kg m^2"
    return "[" + "; ".join(" ".join(f"{v:g}" for v in row) for row in j) + "] kg m^2"


def design_one(name: str, d: dict, p: dict, hinf: dict):
    """The design `d` ([designs.<name>]) on plant `p` ([plants.<d.plant>]); hinf: the [hinf] table.
    Raises DesignError when a check fails, KeyError / TypeError / ValueError on a bad configuration."""
    # riccati and lmi_hinf import scipy and cvxpy (~0.5 s); every `aocs run` imports this module for the light
    # helpers above, and only a scenario whose gain is designed at run start calls this
    from . import lmi_hinf, riccati  # deferred: scipy and cvxpy only when a gain is designed

    kind = d["kind"]
    if kind == "lqr_quat":
        j = inertia_of(p)
        a, b = models.lqr_quat_model(j)
        inputs = {"law": "SPEC 2.5 lqr_quat, u = -K [sign(qe4) qe_vec; we]", "kind": kind,
                  "J": _inertia_text(j), "Q": weight_text(d["q"], 6), "R": weight_text(d["r"], 3)}
        return riccati.lqr(name, kind, a, b, weight_matrix(d["q"], 6), weight_matrix(d["r"], 3), inputs)
    if kind == "lqr_quat_i":
        j = inertia_of(p)
        a, b = models.lqr_quat_i_model(j)
        inputs = {"law": "SPEC 5.2 lqr_quat_i, u = -K [z; sign(qe4) qe_vec; we], z' = sign(qe4) qe_vec",
                  "kind": kind, "J": _inertia_text(j), "Q": weight_text(d["q"], 9), "R": weight_text(d["r"], 3)}
        return riccati.lqr(name, kind, a, b, weight_matrix(d["q"], 9), weight_matrix(d["r"], 3), inputs)
    if kind == "orbit_lqr":
        a, b = models.orbit_model(p["mass"], p["radius"], p["mu"])
        n = models.mean_motion(p["mu"], p["radius"])
        inputs = {"law": "SPEC 2.8 orbit_lqr, F = -K x, x = [du dv dw dx dy dz]", "kind": kind,
                  "m": f"{p['mass']:g} kg", "R": f"{p['radius']:g} m", "mu": f"{p['mu']:.10g} m^3/s^2",
                  "n": f"{n:.12e} rad/s", "Q": weight_text(d["q"], 6), "R_weight": weight_text(d["r"], 3)}
        return riccati.lqr(name, kind, a, b, weight_matrix(d["q"], 6), weight_matrix(d["r"], 3), inputs)
    if kind == "hinf":
        j = inertia_of(p)
        if np.count_nonzero(j - np.diag(np.diag(j))) != 0:
            raise DesignError(f"{name}: the SPEC 2.6 model needs principal axes (a diagonal inertia), got {j.tolist()}")
        ix, iy, iz = (float(v) for v in np.diag(j))
        plant = models.hinf_model(ix, iy, iz, p["w0"], p["z_scale"])
        alpha = d.get("alpha")
        alpha_sel = d.get("alpha_sel", alpha)
        bounded = d.get("bounded", False)
        if not isinstance(bounded, bool):
            raise TypeError(f"designs.{name}.bounded: must be true or false, not {bounded!r}")
        inputs = {"law": "SPEC 2.6 hinf, u = +K x, x = [phi theta psi phidot thetadot psidot]",
                  "kind": kind, "I": f"({ix:g}, {iy:g}, {iz:g}) kg m^2", "w0": f"{p['w0']:g} rad/s",
                  "z": f"{p['z_scale']:g} M q'', D1 = D2 = {p['z_scale']:g} I3",
                  "pole region": "none (plain SPEC LMI)" if alpha is None else f"Re < -{alpha:g} 1/s"}
        if bounded:
            inputs["lower bound"] = "-I < LMI (SI units), steps 1 and 2"
        return lmi_hinf.design(name, plant, alpha=alpha, alpha_sel=alpha_sel, delta=hinf["delta"],
                               k_rtol=hinf["k_rtol"], inputs=inputs, bounded=bounded)
    raise DesignError(f"{name}: unknown design kind '{kind}'")
