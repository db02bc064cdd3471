"""Checks every design must pass, and the independent H-infinity norm."""
from __future__ import annotations

import numpy as np
import scipy.linalg as sla
from scipy.optimize import minimize_scalar

from .errors import DesignError


class UncontrollableError(DesignError):
    """(A, B) is not controllable: no stabilising gain for every mode."""


class InfeasibleLMIError(DesignError):
    """The LMI has no solution (solver reports infeasible or inaccurate)."""


class SolverDisagreementError(DesignError):
    """Clarabel and SCS give gains further apart than the stated tolerance."""


def controllability_rank(a: np.ndarray, b: np.ndarray) -> int:
    """Rank of [B AB ... A^(n-1) B], with columns scaled block by block."""
    n = a.shape[0]
    blocks = []
    blk = b
    for _ in range(n):
        scale = np.linalg.norm(blk)
        blocks.append(blk / scale if scale > 0.0 else blk)
        blk = a @ blk
    ctrb = np.hstack(blocks)
    s = np.linalg.svd(ctrb, compute_uv=False)
    tol = max(ctrb.shape) * np.finfo(float).eps * (s[0] if s.size else 0.0) * 1e3
    return int(np.sum(s > tol))


def require_controllable(name: str, a: np.ndarray, b: np.ndarray) -> None:
    n = a.shape[0]
    rank = controllability_rank(a, b)
    if rank < n:
        raise UncontrollableError(
            f"{name}: (A, B) is not controllable: controllability matrix rank {rank} < {n}; "
            "no table written")
    # PBH test per eigenvalue: catches what the Krylov rank may hide on badly scaled models
    for lam in np.linalg.eigvals(a):
        m = np.hstack([a - lam * np.eye(n), b])
        s = np.linalg.svd(m, compute_uv=False)
        if s[-1] <= 1e-12 * max(1.0, s[0]):
            raise UncontrollableError(
                f"{name}: (A, B) is not controllable: PBH rank test fails at eigenvalue {lam:.6g}; "
                "no table written")


def pole_stats(poles: np.ndarray) -> list[dict]:
    """Per pole: real, imag, natural frequency, damping, time constant."""
    out = []
    for p in sorted(poles, key=lambda z: (z.real, z.imag)):
        wn = abs(p)
        out.append({
            "re": float(p.real), "im": float(p.imag), "wn": float(wn),
            "zeta": float(-p.real / wn) if wn > 0.0 else 1.0,
            "tau": float(-1.0 / p.real) if p.real < 0.0 else float("inf"),
        })
    return out


def require_stable(name: str, poles: np.ndarray) -> None:
    worst = float(np.max(poles.real))
    if not worst < 0.0:
        raise DesignError(f"{name}: closed-loop pole with Re = {worst:.6g} >= 0 (not in the open LHP); "
                          "no table written")


def _freq_gain(a, b, c, d, w: float) -> float:
    n = a.shape[0]
    g = c @ np.linalg.solve(1j * w * np.eye(n) - a, b) + d
    return float(np.linalg.svd(g, compute_uv=False)[0])


def hinf_norm_sweep(a, b, c, d, wmin=1e-8, wmax=1e4, npts=3000) -> tuple[float, float]:
    """Lower bound: max singular value over a dense log grid refined around the peak.

    Returns (peak gain, frequency); includes the limit w -> inf (sigma_max(D)).
    """
    ws = np.logspace(np.log10(wmin), np.log10(wmax), npts)
    gains = np.array([_freq_gain(a, b, c, d, w) for w in ws])
    k = int(np.argmax(gains))
    best, wbest = float(gains[k]), float(ws[k])
    lo = np.log10(ws[max(k - 1, 0)])
    hi = np.log10(ws[min(k + 1, npts - 1)])
    if hi > lo:
        r = minimize_scalar(lambda lw: -_freq_gain(a, b, c, d, 10.0**lw), bounds=(lo, hi),
                            method="bounded", options={"xatol": 1e-10})
        if -r.fun > best:
            best, wbest = float(-r.fun), float(10.0**r.x)
    dinf = float(np.linalg.svd(d, compute_uv=False)[0])
    if dinf > best:
        best, wbest = dinf, float("inf")
    return best, wbest


def _has_imag_axis_eig(a, b, c, d, gamma: float) -> bool:
    """Hamiltonian test (Boyd, Balakrishnan, Kabamba 1989): gamma > ||G||inf iff no
    eigenvalue on the imaginary axis (A stable, sigma_max(D) < gamma)."""
    r = gamma**2 * np.eye(d.shape[1]) - d.T @ d
    ri = np.linalg.inv(r)
    ah = a + b @ ri @ d.T @ c
    h = np.block([[ah, b @ ri @ b.T],
                  [-c.T @ (np.eye(d.shape[0]) + d @ ri @ d.T) @ c, -ah.T]])
    ev = np.linalg.eigvals(h)
    scale = max(1.0, float(np.max(np.abs(ev))))
    return bool(np.any(np.abs(ev.real) < 1e-8 * scale))


def hinf_norm(a, b, c, d, rtol=1e-9) -> dict:
    """H-infinity norm of C (sI - A)^-1 B + D, independent of any LMI:
    frequency sweep for a lower bound, then Hamiltonian bisection for the value."""
    if np.max(np.linalg.eigvals(a).real) >= 0.0:
        return {"norm": float("inf"), "sweep": float("inf"), "peak_rad_s": 0.0}
    low, wpk = hinf_norm_sweep(a, b, c, d)
    dmax = float(np.linalg.svd(d, compute_uv=False)[0])
    lo = max(low, dmax * (1.0 + 1e-15))
    hi = lo * (1.0 + 1e-6)
    # grow the upper bracket until the Hamiltonian has no imaginary-axis eigenvalue
    while _has_imag_axis_eig(a, b, c, d, hi):
        lo = hi
        hi *= 2.0
        if hi > 1e12 * max(low, 1e-300):
            raise DesignError("H-infinity norm bisection did not bracket")
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        if _has_imag_axis_eig(a, b, c, d, mid):
            lo = mid
        else:
            hi = mid
    return {"norm": hi, "sweep": low, "peak_rad_s": wpk}


def are_residual(a, b, q, r, s) -> tuple[float, float]:
    """Absolute and relative residual of A^T S + S A - S B R^-1 B^T S + Q = 0."""
    res = a.T @ s + s @ a - s @ b @ np.linalg.solve(r, b.T @ s) + q
    absr = float(np.linalg.norm(res, 2))
    scale = (np.linalg.norm(a.T @ s, 2) * 2.0 + np.linalg.norm(s @ b @ np.linalg.solve(r, b.T @ s), 2)
             + np.linalg.norm(q, 2))
    return absr, absr / scale


def assert_symmetric_psd(name: str, s: np.ndarray) -> None:
    if not np.allclose(s, s.T, rtol=1e-10, atol=0.0):
        raise DesignError(f"{name}: Riccati solution not symmetric")
    if np.min(sla.eigvalsh(0.5 * (s + s.T))) <= 0.0:
        raise DesignError(f"{name}: Riccati solution not positive definite")
