"""Margins of a loop broken at the plant input (docs/spec.md, "Stability margins"), with python-control.

One axis (SISO l, negative feedback, S = 1 / (1 + l)):
    gain margin      1 / |l| at the phase crossovers (arg l = -180 deg): the smallest above 1 (gain_margin_db,
                     an increase) and the largest below 1 (gain_margin_low_db, a decrease that destabilises:
                     the conditionally stable integral laws), control.stability_margins;
    phase margin     180 deg + arg l at the gain crossovers |l| = 1 (the smallest), at crossover_rad_s;
    delay margin     min over the gain crossovers of (phase margin, rad) / w_c: the extra delay at the plant
                     input that makes the loop marginally stable (seconds; sampled loops: any delay, not only
                     whole periods);
    modulus margin   min_w |1 + l| = 1 / ||S||_inf;
    bandwidth        the lowest w where |T| = |l / (1 + l)| falls 3 dB below |T| at the lowest w;
    disk margin      alpha_max of the balanced (skew 0) disk margin, Seiler, Packard, Gahinet 2020
                     (control.disk_margins), with its gain (dB) and phase (deg) ranges.
Multivariable (L 3 x 3, mimo):
    gain margin      the largest uniform gain k > 1 (all channels at once) keeping the closed loop stable,
                     from the closed-loop poles (bisection);
    phase margin     uniform phase: 180 deg + arg lambda_i(L) where an eigenvalue of L crosses |lambda| = 1;
    delay margin     the same crossings, (phase, rad) / w: a delay in all channels at once;
    modulus margin   1 / max_w sigma_max(S), S = (I + L)^-1;
    disk margin      the multiloop balanced disk margin (simultaneous, independent perturbations of every
                     channel; Seiler, Packard, Gahinet 2020, section "Multiloop disk margins"):
                     alpha = 1 / max_w mu_Delta(S - I/2), Delta diagonal complex. python-control computes it only
                     through SLICOT (slycot), whose LQR solver also replaces scipy's in control.lqr; here mu is
                     the D-scaled bound inf_D sigma_max(D M D^-1) over positive diagonal D, which equals mu for
                     three or fewer complex scalar blocks (Doyle 1982; Packard and Doyle 1993), minimised in
                     log D (a convex problem).
"""
from __future__ import annotations

import math
import warnings

import control
import numpy as np
from scipy.optimize import minimize
from scipy.signal import BadCoefficients

from .loop_model import AXES, closed_loop_poles, is_stable, loop_at, response

W_MIN = 1e-4   # rad/s, the lowest frequency of the grids


def grid(dt: float | None, w_max: float = 100.0, n: int = 3000) -> np.ndarray:
    """Frequencies, rad/s: 1e-4 up to just below the Nyquist frequency (sampled) or w_max (continuous)."""
    top = 0.999 * math.pi / dt if dt else w_max
    return np.logspace(math.log10(W_MIN), math.log10(top), n)


def _db(x: float) -> float | None:
    return None if x is None or not math.isfinite(x) or x <= 0 else 20.0 * math.log10(x)


def _finite(x):
    return None if x is None or not math.isfinite(x) else float(x)


def _at(l, f: float) -> complex:
    return complex(response(l, [f])[0, 0, 0])


def crossings(l, w, h, f, where=lambda r: True) -> list[float]:
    """Frequencies where f(l(jw)) changes sign between grid points (and `where` holds), refined by bisection."""
    v = np.array([f(r) for r in h])
    out = []
    for k in np.nonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0)[0]:
        if not (where(h[k]) or where(h[k + 1])):
            continue
        lo, hi, flo = w[k], w[k + 1], v[k]
        for _ in range(60):
            mid = math.sqrt(lo * hi)
            fm = f(_at(l, mid))
            lo, hi, flo = (mid, hi, fm) if np.sign(fm) == np.sign(flo) else (lo, mid, flo)
        r = _at(l, math.sqrt(lo * hi))
        if where(r):
            out.append(math.sqrt(lo * hi))
    return out


def siso(l: control.StateSpace, w: np.ndarray | None = None) -> dict:
    """The margins of one SISO loop (module docstring); None where a margin does not exist (no crossover)."""
    dt = l.dt if l.dt else None
    w = grid(dt) if w is None else w
    with warnings.catch_warnings():
        # its own notes (falling back to the frd method, the polynomial's conditioning, an evaluation at the
        # Nyquist frequency) are about the precision of its answer, which is checked on the response below
        warnings.simplefilter("ignore", UserWarning)
        warnings.simplefilter("ignore", BadCoefficients)
        gm, pm, sm, wpc, wgc, wms = (np.atleast_1d(np.asarray(v, float))
                                     for v in control.stability_margins(l, returnall=True))
    # its crossings checked on the response itself (the polynomial roots of a loop with poles at z = 1 can
    # be off): a gain crossover has |l| = 1, a phase crossover l real and negative, to 1e-6
    # (a sampled loop's response above the Nyquist frequency repeats the one below: a crossing reported there
    # is an alias of one the grid finds below, so only 0 < w <= pi / dt is taken)
    top = math.pi / dt if dt else math.inf

    def inside(f: float) -> bool:
        return math.isfinite(f) and 0.0 < f <= top

    ok_g = [k for k, f in enumerate(wgc) if inside(f) and abs(abs(_at(l, f)) - 1.0) < 1e-6]
    ok_p = [k for k, f in enumerate(wpc) if inside(f) and abs(np.angle(-_at(l, f))) < 1e-6]
    ok_s = [k for k, f in enumerate(wms) if inside(f) and math.isfinite(sm[k])
            and abs(abs(1.0 + _at(l, f)) - sm[k]) <= 1e-6 * max(sm[k], 1e-12)]
    pm, wgc, gm, wpc, sm = pm[ok_g], wgc[ok_g], gm[ok_p], wpc[ok_p], sm[ok_s]
    h = response(l, w)[0, 0]
    # stability_margins works on the transfer function's polynomials and can miss a crossing of these
    # high-order loops with poles at z = 1; the crossings of the frequency response on the grid, refined
    # by bisection, are added (and duplicates do no harm: the extreme of each margin is kept)
    g_w = crossings(l, w, h, lambda r: abs(r) - 1.0)
    p_w = crossings(l, w, h, lambda r: r.imag, where=lambda r: r.real < 0.0)
    if dt is not None:   # a sampled loop is real at the Nyquist frequency: a phase crossover when negative
        r = _at(l, math.pi / dt)
        if r.real < 0.0 and abs(r.imag) <= 1e-9 * abs(r):
            p_w.append(math.pi / dt)
    gm = np.concatenate([gm, [1.0 / abs(_at(l, f)) for f in p_w]])
    wpc = np.concatenate([wpc, p_w])
    pm = np.concatenate([pm, [math.degrees(np.angle(-_at(l, f))) for f in g_w]])
    wgc = np.concatenate([wgc, g_w])
    # a double integrator sits at -180 deg at w -> 0: crossings below the grid are that, not a margin
    up = [(g, f) for g, f in zip(gm, wpc) if math.isfinite(g) and g > 1.0 and f >= W_MIN]
    low = [(g, f) for g, f in zip(gm, wpc) if math.isfinite(g) and 0.0 < g < 1.0 and f >= W_MIN]
    gm_up = min(up) if up else (math.inf, None)
    gm_low = max(low) if low else (0.0, None)
    s_abs = np.abs(1.0 + h)
    modulus = float(min([float(np.min(s_abs))] + [float(x) for x in sm if math.isfinite(x)]))
    pm_deg, w_c, delay = None, None, None
    for p, f in zip(pm, wgc):
        if not (math.isfinite(p) and math.isfinite(f) and f >= W_MIN):
            continue
        p = (p + 180.0) % 360.0 - 180.0
        d = math.radians(p) / f if p > 0 else 0.0
        if pm_deg is None or p < pm_deg:
            pm_deg, w_c = p, float(f)
        delay = d if delay is None else min(delay, d)
    t = h / (1.0 + h)
    below = np.nonzero(np.abs(t) < abs(t[0]) / math.sqrt(2.0))[0]
    dm, dgm, dpm = control.disk_margins(l, w, skew=0.0)
    return {
        "gain_margin_db": _db(gm_up[0]) if math.isfinite(gm_up[0]) else None,
        "phase_crossover_rad_s": _finite(gm_up[1]) if gm_up[1] is not None else None,
        "gain_margin_low_db": _db(gm_low[0]) if gm_low[1] is not None else None,
        "phase_margin_deg": _finite(pm_deg),
        "delay_margin_s": _finite(delay),
        "crossover_rad_s": _finite(w_c),
        "modulus_margin": modulus,
        "bandwidth_rad_s": float(w[below[0]]) if below.size else None,
        "disk_margin": float(dm),
        "disk_gain_margin_db": float(dgm),   # control.disk_margins gives dB already
        "disk_phase_margin_deg": float(dpm),
        "closed_loop_stable": None,      # filled by the caller, which has the MIMO loop
    }


def uniform_gain_margin(big_l: control.StateSpace, k_max: float = 1e4) -> float | None:
    """The largest k > 1 with the loop closed through k I stable (None if stable up to k_max)."""
    if not is_stable(big_l, 1.0):
        return 0.0
    if is_stable(big_l, k_max):
        return None
    lo, hi = 1.0, k_max
    for _ in range(80):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if is_stable(big_l, mid) else (lo, mid)
        if hi / lo < 1.0 + 1e-9:
            break
    return lo


def _eig_sorted(big_l, w):
    fr = response(big_l, w)
    return [np.linalg.eigvals(fr[:, :, k]) for k in range(len(w))]


def eigen_crossings(big_l: control.StateSpace, w: np.ndarray) -> list[tuple[float, complex]]:
    """(w, lambda) where an eigenvalue of L(jw) crosses |lambda| = 1 (bisection on the sorted magnitudes)."""
    eigs = _eig_sorted(big_l, w)
    mags = np.array([np.sort(np.abs(e)) for e in eigs])
    out = []
    for j in range(mags.shape[1]):
        f = mags[:, j] - 1.0
        for k in np.nonzero(np.sign(f[:-1]) * np.sign(f[1:]) < 0)[0]:
            lo, hi = w[k], w[k + 1]
            flo = f[k]
            for _ in range(50):
                mid = math.sqrt(lo * hi)
                fm = np.sort(np.abs(_eig_sorted(big_l, [mid])[0]))[j] - 1.0
                lo, hi, flo = (mid, hi, fm) if np.sign(fm) == np.sign(flo) else (lo, mid, flo)
            wc = math.sqrt(lo * hi)
            e = _eig_sorted(big_l, [wc])[0]
            out.append((wc, complex(e[np.argmin(np.abs(np.abs(e) - 1.0))])))
    return sorted(out, key=lambda p: p[0])


def mu_diagonal(m: np.ndarray) -> float:
    """mu of m (n x n, n <= 3) for a diagonal complex perturbation: inf over D = diag(e^x, 1) of
    sigma_max(D m D^-1) (exact for n <= 3 complex scalar blocks)."""
    n = m.shape[0]

    def f(x):
        d = np.exp(np.append(x, 0.0))
        return np.linalg.svd((d[:, None] * m) / d[None, :], compute_uv=False)[0]

    r = minimize(f, np.zeros(n - 1), method="Nelder-Mead", options={"xatol": 1e-9, "fatol": 1e-12, "maxiter": 4000})
    return float(min(r.fun, f(np.zeros(n - 1))))


def disk_of(alpha: float) -> tuple[float, float, float]:
    """(alpha, gain margin as a ratio, phase margin deg) of a balanced disk of size alpha (skew 0)."""
    gain = (1.0 + alpha / 2.0) / (1.0 - alpha / 2.0) if alpha < 2.0 else math.inf
    return alpha, gain, math.degrees(2.0 * math.atan(alpha / 2.0))


def multiloop_disk_margin(big_l: control.StateSpace, w: np.ndarray) -> tuple[float, float, float]:
    """The multiloop balanced disk margin (module docstring): mu on a grid, refined around its peak."""
    fr = response(big_l, w)
    n = fr.shape[0]
    ms = [np.linalg.inv(np.eye(n) + fr[:, :, k]) - 0.5 * np.eye(n) for k in range(len(w))]
    # mu <= sigma_max: mu is needed only where sigma_max is above the largest mu found so far
    bound = np.array([np.linalg.svd(m, compute_uv=False)[0] for m in ms])
    peak, k_peak = 0.0, 0
    for k in np.argsort(-bound):
        if bound[k] <= peak:
            break
        mu = mu_diagonal(ms[k])
        if mu > peak:
            peak, k_peak = mu, k
    fine = np.geomspace(w[max(k_peak - 1, 0)], w[min(k_peak + 1, len(w) - 1)], 21)
    fr2 = response(big_l, fine)
    for j in range(len(fine)):
        peak = max(peak, mu_diagonal(np.linalg.inv(np.eye(n) + fr2[:, :, j]) - 0.5 * np.eye(n)))
    return disk_of(1.0 / peak)


def mimo(big_l: control.StateSpace, w: np.ndarray | None = None, disk: bool = True) -> dict:
    """The multivariable margins (module docstring)."""
    dt = big_l.dt if big_l.dt else None
    w = grid(dt, n=1500) if w is None else w
    fr = response(big_l, w)
    eye = np.eye(fr.shape[0])
    s_peak = max(np.linalg.svd(np.linalg.inv(eye + fr[:, :, k]), compute_uv=False)[0] for k in range(len(w)))
    pm_deg, w_c, delay = None, None, None
    for wc, lam in eigen_crossings(big_l, w):
        p = math.degrees(math.atan2(lam.imag, lam.real)) + 180.0
        p = (p + 180.0) % 360.0 - 180.0
        d = math.radians(p) / wc if p > 0 else 0.0
        if pm_deg is None or p < pm_deg:
            pm_deg, w_c = p, wc
        delay = d if delay is None else min(delay, d)
    k = uniform_gain_margin(big_l)
    dm, dgm, dpm = multiloop_disk_margin(big_l, w) if disk else (math.nan, math.nan, math.nan)
    return {
        "gain_margin_db": None if k is None else _db(k),
        "phase_margin_deg": _finite(pm_deg),
        "delay_margin_s": _finite(delay),
        "crossover_rad_s": _finite(w_c),
        "modulus_margin": float(1.0 / s_peak),
        "disk_margin": float(dm),
        "disk_gain_margin_db": _db(float(dgm)),
        "disk_phase_margin_deg": float(dpm),
        "closed_loop_stable": is_stable(big_l),
        "closed_loop_spectral_radius": float(np.max(np.abs(closed_loop_poles(big_l)))) if dt else None,
    }


def loops(big_l: control.StateSpace, w: np.ndarray | None = None, disk: bool = True) -> dict:
    """{"x", "y", "z", "mimo"}: the margins of every axis loop (the others closed) and of the MIMO loop."""
    out = {}
    stable = is_stable(big_l)
    for i, ax in enumerate(AXES):
        m = siso(loop_at(big_l, i), w)
        m["closed_loop_stable"] = stable
        out[ax] = m
    out["mimo"] = mimo(big_l, w, disk)
    return out
