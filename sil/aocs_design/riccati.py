"""LQR designs through the continuous algebraic Riccati equation (scipy)."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy
import scipy.linalg as sla

from .checks import DesignError, are_residual, assert_symmetric_psd, require_controllable, require_stable

# relative residual of the ARE accepted for a table (double precision, small model)
ARE_RTOL = 1e-10


@dataclass
class LqrResult:
    name: str
    kind: str            # "lqr_quat" or "orbit_lqr"
    a: np.ndarray
    b: np.ndarray
    q: np.ndarray
    r: np.ndarray
    k: np.ndarray        # u = -K x
    s: np.ndarray
    poles: np.ndarray
    residual_abs: float
    residual_rel: float
    solver: str
    inputs: dict = field(default_factory=dict)

    @property
    def slowest_pole_re(self) -> float:
        return float(np.max(self.poles.real))


def lqr(name: str, kind: str, a, b, q, r, inputs: dict | None = None) -> LqrResult:
    """K = R^-1 B^T S with S the stabilising solution of the CARE (SPEC 2.5, 2.8).

    The 0.5 factor in front of the cost integral does not change S or K.
    Raises UncontrollableError before calling the solver, DesignError when a check fails.
    """
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    q = np.asarray(q, float)
    r = np.asarray(r, float)
    require_controllable(name, a, b)
    if np.min(np.linalg.eigvalsh(r)) <= 0.0:
        raise DesignError(f"{name}: R is not positive definite")
    if np.min(np.linalg.eigvalsh(q)) < 0.0:
        raise DesignError(f"{name}: Q is not positive semidefinite")
    try:
        s = sla.solve_continuous_are(a, b, q, r)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise DesignError(f"{name}: Riccati solver failed: {exc}") from exc
    assert_symmetric_psd(name, s)
    res_abs, res_rel = are_residual(a, b, q, r, s)
    if not res_rel < ARE_RTOL:
        raise DesignError(f"{name}: ARE relative residual {res_rel:.3e} above tolerance {ARE_RTOL:.0e}; "
                          "no table written")
    k = np.linalg.solve(r, b.T @ s)
    poles = np.linalg.eigvals(a - b @ k)
    require_stable(name, poles)
    return LqrResult(name=name, kind=kind, a=a, b=b, q=q, r=r, k=k, s=s, poles=poles,
                     residual_abs=res_abs, residual_rel=res_rel,
                     solver=f"scipy.linalg.solve_continuous_are (scipy {scipy.__version__})",
                     inputs=dict(inputs or {}))
