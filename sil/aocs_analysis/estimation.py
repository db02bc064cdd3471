"""How well the attitude filter knows the attitude and the gyro bias, from a run's log (issue 20; SPEC 5.7).

Pure functions over numpy arrays, one row per control step. The flight software's multiplicative EKF has
the 6-state error x = [dth; db]: dth (rad) the small rotation from the estimated to the true body frame,
db (rad/s) the bias error, and logs its covariance P (6 x 6) as the 21 values of the upper triangle,
row-major (P00 P01 .. P05 P11 .. P55). Conventions (SPEC 1, docs/conventions.md; quaternions scalar last,
Shuster product, A(q) maps N to B):

- knowledge error: dth = the rotation vector of q_BN (x) q_est^-1, so that q_BN = dq(dth) (x) q_est and
  A(q_BN) = A(dq(dth)) A(q_est) ~ (I - [dth x]) A(q_est): dth has components in B (those of the true
  frame and of the estimated one are the same for the rotation's own axis), and dth_x > 0 when the truth
  is the estimate turned by a positive angle about x. This is the MEKF's error state
  (Markley & Crassidis 2014, ch. 6), the one firmware/src/estimation/mekf.c resets with
  q_hat <- dq(dth) (x) q_hat, b_hat <- b_hat + db;
- db = bias_true - bias_est, the same sign as dth (truth minus estimate: the filter's error state, used in
  the NEES); the reported bias error is the estimate minus the truth, bias_est - bias_true;
- control error: the estimate against the reference, pointing error: the truth against the reference, both
  from metrics.pointing_errors_arcsec (the true angle 2 asin|qe_vec| of SPEC 1.7, and 2 qe_i per axis).

Consistency (Bar-Shalom, Li & Kirubarajan 2001, "Estimation with Applications to Tracking and Navigation",
ch. 5.4): NEES eps_k = e_k^T P_k^-1 e_k, chi-square with n degrees of freedom for a consistent filter
(n = 6 for e = [dth; db], 3 for the attitude block). The samples of one run are correlated in time
(the filter's error decays with the filter's time constants, seconds for the attitude and up to
sigma_v / sigma_u for the bias), so consecutive samples are not independent draws and the usual
"N eps_bar ~ chi2(N n)" band would be far too narrow. `nees_window_test` therefore

1. estimates tau, the integrated autocorrelation time of the NEES series itself (mean removed, over the
   tested samples; Sokal's self-consistent window: the smallest lag K with K >= 5 tau(K),
   tau(K) = 1 + 2 sum_{k=1..K} rho(k); Sokal 1997, "Monte Carlo methods in statistical mechanics", the
   estimator emcee uses), unless the caller gives the spacing (e.g. from the filter's time constant); and,
   given the error's components normalised by their sigma (analyse does), the same tau of each component's
   square, keeping the largest: the NEES sums parts of different time constants (the hold's attitude
   error decorrelates in about 1 s across the boresight and 9 s about it) and the tau of the sum is their
   mean, too short a spacing for the slow part (its windows then scatter more than the band allows:
   0.93 instead of 0.95 on the hold, 0.90 on the test's synthetic run of such errors);
2. keeps samples a spacing s = ceil(2 tau) apart: for an exponential correlation the NEES samples left
   are then correlated by e^-4 ~ 0.02 at most, and are treated as independent;
3. groups M consecutive kept samples (default 10) into a window and tests the window's mean NEES against
   the two-sided 95 % band [chi2.ppf(0.025, M n), chi2.ppf(0.975, M n)] / M;
4. repeats this for every phase 0 .. s-1 of the subsampling grid (each phase gives disjoint windows;
   windows of different phases overlap in time, which does not change the expected fraction, only its
   scatter) and returns the fraction of windows in the band.

A consistent filter gives about 0.95; P too small by 4 (the mean NEES 4 n) or too large by 4 gives
nearly 0. The estimate of tau needs a run much longer than tau: when the tested samples span fewer than
50 tau (the usual rule for this estimator) or Sokal's window is not found, the test is not `reliable` and
the fraction is None (the counts stay in the result); with fewer than M samples a spacing apart there is
no window and the fraction is None too. The bias error decorrelates slowly (with a time constant near
sigma_v / sigma_u when sigma_v^2 >> 2 sigma_u sigma_n dt^0.5, an overdamped filter: e.g. 1000 s for
sigma_v = 3e-7 rad/s^0.5, sigma_u = 3e-10 rad/s^1.5), so the 6-dof test needs long runs; the attitude-only
test decorrelates much faster.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from aocs_core.conventions import ARCSEC_PER_RAD, quat_to_dcm

from . import estimation_transients as T
from . import metrics as M
from .estimation_bounds import between_updates, farrenkopf, steady_state_per_axis

DEG_H_PER_RAD_S = 180.0 / math.pi * 3600.0        # 1 rad/s in deg/h
STATE_DIM = 6                                     # [dth (rad, B); db (rad/s, B)]
P_UPPER_LEN = STATE_DIM * (STATE_DIM + 1) // 2    # 21: the logged upper triangle
_IU = np.triu_indices(STATE_DIM)                  # row-major upper triangle: (0,0) (0,1) .. (0,5) (1,1) ..


# --------------------------------------------------------------------------- covariance
def covariance_from_upper(est_p) -> np.ndarray:
    """(n, 21) upper triangle, row-major (P00 P01 .. P05 P11 .. P55) -> (n, 6, 6) symmetric P.
    A (n, 6, 6) array is returned as it is (as float)."""
    p = np.asarray(est_p, float)
    if p.ndim == 3 and p.shape[1:] == (STATE_DIM, STATE_DIM):
        return p
    if p.ndim != 2 or p.shape[1] != P_UPPER_LEN:
        raise ValueError(f"est_p must be (n, {P_UPPER_LEN}) or (n, 6, 6), got {p.shape}")
    out = np.empty((p.shape[0], STATE_DIM, STATE_DIM))
    out[:, _IU[0], _IU[1]] = p
    out[:, _IU[1], _IU[0]] = p
    return out


def sigma_from_covariance(p) -> np.ndarray:
    """sqrt of the diagonal (n, k); NaN where a variance is negative or not finite."""
    d = np.diagonal(np.asarray(p, float), axis1=-2, axis2=-1)
    with np.errstate(invalid="ignore"):
        return np.where(d >= 0.0, np.sqrt(np.abs(d)), np.nan)


# --------------------------------------------------------------------------- errors
def rotation_vector_rad(q) -> np.ndarray:
    """The rotation vector (n, 3) of quaternion rows (scalar last): angle 2 atan2(|qv|, |q4|) in [0, pi]
    about qv / |qv| of the short representative (q4 >= 0). Any norm (the ratio is scale-free); zero for the
    identity."""
    q = np.asarray(q, float)
    q = np.where(q[..., 3:4] < 0.0, -q, q)
    v = q[..., :3]
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    ang = 2.0 * np.arctan2(n, q[..., 3:4])
    with np.errstate(invalid="ignore", divide="ignore"):
        k = np.where(n > 0.0, ang / n, 0.0)          # the identity's 0 / 0 is left out
    return v * k


def knowledge_error_rad(q_true, q_est) -> np.ndarray:
    """dth (n, 3), rad, components in B: the rotation vector of q_true (x) q_est^-1 (module docstring)."""
    return rotation_vector_rad(M.error_quaternion(np.asarray(q_true, float), np.asarray(q_est, float)))


def angle_rad(rotvec) -> np.ndarray:
    """|dth| (n,), the error angle (equal to 2 asin|qe_vec| of SPEC 1.7)."""
    return np.linalg.norm(np.asarray(rotvec, float), axis=-1)


def control_error_arcsec(q_est, qd) -> dict:
    """The estimate against the reference: metrics.pointing_errors_arcsec(q_est, qd) (true_angle,
    per_axis 2 qe_i, qe_arcsec), what the control law acts on."""
    return M.pointing_errors_arcsec(np.asarray(q_est, float), np.asarray(qd, float))


def pointing_error_arcsec(q_true, qd) -> dict:
    """The truth against the reference: metrics.pointing_errors_arcsec(q_true, qd), what the mission gets."""
    return M.pointing_errors_arcsec(np.asarray(q_true, float), np.asarray(qd, float))


def bias_error_radps(bias_est_radps, bias_true_radps) -> np.ndarray:
    """bias_est - bias_true (n, 3), rad/s, components in B."""
    return np.asarray(bias_est_radps, float) - np.asarray(bias_true_radps, float)


def bias_error_deg_h(bias_est_radps, bias_true_radps) -> np.ndarray:
    """bias_est - bias_true (n, 3) in deg/h."""
    return bias_error_radps(bias_est_radps, bias_true_radps) * DEG_H_PER_RAD_S


def error_state(dth_rad, bias_est_radps, bias_true_radps) -> np.ndarray:
    """The filter's error state e = [dth; bias_true - bias_est] (n, 6), truth minus estimate in both
    parts, so that it pairs with the logged P (including its attitude-bias cross terms)."""
    return np.concatenate([np.asarray(dth_rad, float),
                           -bias_error_radps(bias_est_radps, bias_true_radps)], axis=-1)


def rms_per_axis(x, mask=None) -> np.ndarray:
    """sqrt(mean x_i^2) per column over the masked rows (NaN when none)."""
    x = np.asarray(x, float)
    if mask is not None:
        x = x[np.asarray(mask, bool)]
    if x.shape[0] == 0:
        return np.full(x.shape[1:], np.nan)
    return np.sqrt(np.mean(x * x, axis=0))


# --------------------------------------------------------------------------- consistency
def three_sigma_fraction(dth_rad, p, valid=None, *, axes=(0, 1, 2)) -> float | None:
    """Fraction of (sample, axis) pairs with |dth_i| <= 3 sqrt(P_ii), i in `axes` (default the attitude).

    Counted over the samples where `valid` (the estimate is valid; all when None) and dth is finite; a
    negative or non-finite P_ii at such a sample counts as outside. None when no pair is counted.
    0.9973 for a consistent filter with Gaussian errors."""
    e = np.asarray(dth_rad, float)[:, list(axes)]
    sig = sigma_from_covariance(p)[:, list(axes)]
    rows = np.all(np.isfinite(e), axis=1)
    if valid is not None:
        rows &= np.asarray(valid, bool)
    if not np.any(rows):
        return None
    with np.errstate(invalid="ignore"):
        inside = np.abs(e[rows]) <= 3.0 * sig[rows]
    return float(np.mean(inside))


def nees(e, p) -> np.ndarray:
    """eps_k = e_k^T P_k^-1 e_k (n,) for e (n, k) and P (n, k, k); NaN where e or P is not finite or P is
    not positive definite (Cholesky fails)."""
    e = np.asarray(e, float)
    p = np.asarray(p, float)
    p = 0.5 * (p + np.swapaxes(p, -1, -2))
    out = np.full(e.shape[0], np.nan)
    ok = np.flatnonzero(np.all(np.isfinite(e), axis=1) & np.all(np.isfinite(p), axis=(1, 2)))
    if ok.size == 0:
        return out
    try:
        chol = np.linalg.cholesky(p[ok])
    except np.linalg.LinAlgError:     # some P not positive definite: find them one by one
        good = []
        for i in ok:
            try:
                np.linalg.cholesky(p[i])
                good.append(i)
            except np.linalg.LinAlgError:
                pass
        ok = np.asarray(good, int)
        if ok.size == 0:
            return out
        chol = np.linalg.cholesky(p[ok])
    y = np.linalg.solve(chol, e[ok][..., None])[..., 0]
    out[ok] = np.sum(y * y, axis=1)
    return out


def nees_full(dth_rad, bias_est_radps, bias_true_radps, p) -> np.ndarray:
    """6-dof NEES of e = [dth; bias_true - bias_est] with the whole P (n, 6, 6)."""
    return nees(error_state(dth_rad, bias_est_radps, bias_true_radps), p)


def nees_attitude(dth_rad, p) -> np.ndarray:
    """3-dof NEES of dth with the attitude block P[:3, :3]."""
    return nees(np.asarray(dth_rad, float), np.asarray(p, float)[:, :3, :3])


def autocorrelation(x, mask=None) -> np.ndarray:
    """Normalised autocorrelation rho(k), k = 0 .. n-1, of x about its mean over the masked samples (NaN
    samples are left out too); each lag uses the pairs present, rho(k) is NaN where fewer than half of the
    lag-0 pairs are."""
    x = np.asarray(x, float)
    m = np.isfinite(x) if mask is None else (np.asarray(mask, bool) & np.isfinite(x))
    n = x.size
    if np.count_nonzero(m) < 2:
        return np.full(n, np.nan)
    xc = np.where(m, x - np.mean(x[m]), 0.0)
    nfft = 1 << (2 * n - 1).bit_length()
    fx = np.fft.rfft(xc, nfft)
    fm = np.fft.rfft(m.astype(float), nfft)
    num = np.fft.irfft(fx * np.conj(fx), nfft)[:n]
    cnt = np.rint(np.fft.irfft(fm * np.conj(fm), nfft)[:n])
    if not num[0] > 0.0:
        return np.full(n, np.nan)
    with np.errstate(invalid="ignore", divide="ignore"):
        rho = (num / cnt) / (num[0] / cnt[0])
    rho[cnt < 0.5 * cnt[0]] = np.nan
    return rho


def integrated_autocorrelation_time(x, mask=None, c: float = 5.0) -> tuple[float, bool]:
    """(tau, reliable): tau = 1 + 2 sum_{k=1..K} rho(k) in samples, with Sokal's window, the smallest K with
    K >= c tau(K). reliable: such a K exists and the series holds at least 50 tau samples."""
    rho = autocorrelation(x, mask)
    nvalid = int(np.count_nonzero(np.isfinite(np.asarray(x, float)) if mask is None
                                  else np.asarray(mask, bool) & np.isfinite(np.asarray(x, float))))
    r = rho[1:]
    finite = np.isfinite(r)
    if not np.any(finite):
        return math.nan, False
    r = r[: np.argmin(finite) if not np.all(finite) else r.size]
    if r.size == 0:
        return 1.0, False
    taus = 1.0 + 2.0 * np.cumsum(r)
    lags = np.arange(1, r.size + 1)
    hit = np.flatnonzero(lags >= c * taus)
    if hit.size == 0:
        return float(taus[-1]), False
    tau = float(taus[hit[0]])
    return tau, bool(nvalid >= 50.0 * max(tau, 1.0))


def nees_band(dof: int, samples_per_window: int, confidence: float = 0.95) -> tuple[float, float]:
    """Two-sided band of the mean of M independent chi2(dof) samples: chi2.ppf((1 -+ c)/2, M dof) / M."""
    a = 0.5 * (1.0 - confidence)
    k = samples_per_window * dof
    from scipy.stats import chi2  # deferred: scipy.stats costs ~1 s of every `aocs run` start, filter runs only
    return (float(chi2.ppf(a, k) / samples_per_window), float(chi2.ppf(1.0 - a, k) / samples_per_window))


@dataclass(frozen=True)
class NeesWindowTest:
    """The windowed NEES test of one run (module docstring). Times in s."""

    dof: int
    in_band_fraction: float | None     # over every window of every phase; None: no window, or not reliable
    reason: str | None                 # why in_band_fraction is None
    windows: int                       # windows tested, all phases
    windows_in_band: int
    independent_windows: int           # windows of phase 0 (disjoint in time)
    samples_per_window: int            # M
    spacing_samples: int               # s
    spacing_s: float
    tau_samples: float                 # integrated autocorrelation time of the NEES (nan when given)
    tau_s: float
    reliable: bool                     # the run holds >= 50 tau (always True when the spacing is given)
    band: tuple                        # (low, high) of a window's mean NEES
    mean: float                        # mean NEES over the tested samples
    samples: int                       # samples tested (finite NEES in the mask)
    window_t_s: np.ndarray             # phase-0 windows: the mid time ...
    window_mean: np.ndarray            # ... and the mean NEES

    def as_dict(self) -> dict:
        return {"dof": self.dof, "in_band_fraction": _f(self.in_band_fraction), "none_because": self.reason,
                "mean": _f(self.mean),
                "band_of_window_mean": [_f(self.band[0]), _f(self.band[1])],
                "samples_per_window": self.samples_per_window, "spacing_s": _f(self.spacing_s),
                "spacing_samples": self.spacing_samples, "autocorrelation_time_s": _f(self.tau_s),
                "autocorrelation_reliable": self.reliable, "windows": self.windows,
                "windows_in_band": self.windows_in_band, "independent_windows": self.independent_windows,
                "samples": self.samples}


def sample_period_s(t_s) -> float:
    """The (uniform) sample period of t_s; ValueError when t_s is not uniform to 1e-6 of a period."""
    t = np.asarray(t_s, float)
    if t.size < 2:
        raise ValueError("need at least two samples")
    d = np.diff(t)
    dt = float(np.median(d))
    if not dt > 0.0 or np.max(np.abs(d - dt)) > 1e-6 * dt:
        raise ValueError("the samples must be uniform in time (one per control step)")
    return dt


def slowest_component_tau(z, mask=None) -> tuple[float, bool]:
    """(tau, reliable) of the slowest column of z (n, k): the largest integrated autocorrelation time of the
    squares z_i^2 (integrated_autocorrelation_time), reliable only when every column's is. For z the error
    normalised per component (e_i / sigma_i) these are the parts the NEES sums: its own tau is their
    variance-weighted mean and underestimates the slowest part (module docstring, step 1)."""
    z = np.asarray(z, float)
    taus, rel = [], True
    for i in range(z.shape[1]):
        tau_i, r_i = integrated_autocorrelation_time(z[:, i] ** 2, mask)
        taus.append(tau_i)
        rel &= r_i
    if not taus or not all(math.isfinite(x) for x in taus):
        return math.nan, False
    return float(max(taus)), bool(rel)


def nees_window_test(t_s, eps, dof: int, mask=None, *, samples_per_window: int = 10,
                     spacing_s: float | None = None, confidence: float = 0.95, components=None) -> NeesWindowTest:
    """Windowed consistency test of a NEES series eps (n,) of `dof` degrees of freedom, over the samples in
    mask (all when None; NaN samples are left out): the fraction of windows of M = samples_per_window
    samples, spaced by spacing_s (default: 2 tau of the data, rounded up to whole samples; tau the largest of
    the NEES's own and, when `components` (n, dof) is given, of each component's square), whose mean lies
    in the two-sided `confidence` chi-square band (module docstring)."""
    t = np.asarray(t_s, float)
    dt = sample_period_s(t)
    x = np.asarray(eps, float).copy()
    if mask is not None:
        x[~np.asarray(mask, bool)] = np.nan
    fin = np.isfinite(x)
    n_test = int(np.count_nonzero(fin))
    if spacing_s is None:
        tau, reliable = integrated_autocorrelation_time(x)
        if components is not None:   # the slowest component, when slower than the sum (step 1)
            zc = np.asarray(components, float).copy()
            zc[~np.isfinite(x)] = np.nan
            tau_c, rel_c = slowest_component_tau(zc)
            if not math.isfinite(tau_c):
                tau, reliable = math.nan, False
            elif tau_c > tau:
                tau, reliable = tau_c, rel_c
        s = max(1, int(math.ceil(2.0 * tau))) if math.isfinite(tau) else x.size + 1
    else:
        tau, reliable = math.nan, True
        s = max(1, int(round(spacing_s / dt)))
    band = nees_band(dof, samples_per_window, confidence)
    means = []
    indep_t, indep_m = [], []
    first = int(np.argmax(fin)) if n_test else x.size       # the grid starts at the first tested sample
    xs, ts = x[first:], t[first:]
    if s * (samples_per_window - 1) < xs.size:
        for phase in range(min(s, xs.size)):
            sub = xs[phase::s]
            k = sub.size // samples_per_window
            if k == 0:
                break
            blocks = sub[: k * samples_per_window].reshape(k, samples_per_window)
            full = np.all(np.isfinite(blocks), axis=1)
            bm = np.mean(blocks[full], axis=1)
            means.append(bm)
            if phase == 0:
                idx = np.arange(k * samples_per_window).reshape(k, samples_per_window)[full] * s
                indep_t, indep_m = ts[idx].mean(axis=1), bm
    means = np.concatenate(means) if means else np.zeros(0)
    inside = int(np.count_nonzero((means >= band[0]) & (means <= band[1])))
    if not reliable:
        fraction, reason = None, "the tested samples span fewer than 50 autocorrelation times (or no Sokal window)"
    elif not means.size:
        fraction, reason = None, f"fewer than {samples_per_window} samples {s * dt:g} s apart"
    else:
        fraction, reason = inside / means.size, None
    return NeesWindowTest(
        dof=dof, in_band_fraction=fraction, reason=reason, windows=int(means.size),
        windows_in_band=inside, independent_windows=int(np.size(indep_m)), samples_per_window=samples_per_window,
        spacing_samples=s, spacing_s=s * dt, tau_samples=tau, tau_s=tau * dt, reliable=reliable, band=band,
        mean=float(np.mean(x[fin])) if n_test else math.nan, samples=n_test,
        window_t_s=np.asarray(indep_t, float), window_mean=np.asarray(indep_m, float))


def nees_ensemble_test(eps_runs, dof: int, confidence: float = 0.95) -> dict:
    """Bar-Shalom, Li & Kirubarajan 2001, ch. 5.4.2: R independent runs (Monte Carlo, other seeds) of the same
    case, eps_runs (R, n) their NEES at the same n instants: the ensemble mean eps_bar_k = sum_r eps_k^r / R
    of a consistent filter has R eps_bar_k ~ chi2(R dof) at every k, whatever the correlation in time, so
    the fraction of instants with eps_bar_k in [chi2.ppf((1 - c)/2, R dof), chi2.ppf((1 + c)/2, R dof)] / R
    is about c. Instants where a run has no NEES are left out. {"in_band_fraction" (None without an
    instant), "band", "runs", "instants", "mean"}."""
    e = np.asarray(eps_runs, float)
    if e.ndim != 2 or e.shape[0] < 1:
        raise ValueError(f"eps_runs must be (runs, n), got {e.shape}")
    r = e.shape[0]
    ok = np.all(np.isfinite(e), axis=0)
    m = np.mean(e[:, ok], axis=0)
    band = nees_band(dof, r, confidence)
    inside = (m >= band[0]) & (m <= band[1])
    return {"in_band_fraction": float(np.mean(inside)) if m.size else None, "band": [band[0], band[1]],
            "runs": r, "instants": int(m.size), "mean": float(np.mean(m)) if m.size else math.nan}


# --------------------------------------------------------------------------- windows in time
def steady_state_mask(t_s, valid=None, *, window_s: float | None = None, fraction: float = 0.5,
                      start_s: float | None = None) -> np.ndarray:
    """The steady-state part of a run: the last window_s seconds (metrics.window_mask), or when window_s is
    None the last `fraction` of the run; only samples at or after start_s (e.g. the convergence time) and
    where valid."""
    t = np.asarray(t_s, float)
    if t.size == 0:
        return np.zeros(0, bool)
    if window_s is not None:
        m = M.window_mask(t, window_s)
    else:
        if not 0.0 < fraction <= 1.0:
            raise ValueError(f"fraction must be in (0, 1], got {fraction}")
        m = t >= t[-1] - fraction * (t[-1] - t[0])
    if start_s is not None:
        m &= t >= start_s
    if valid is not None:
        m &= np.asarray(valid, bool)
    return m


def convergence_time_s(t_s, angle_rad, value_rad: float, k: float = 1.0, valid=None) -> float | None:
    """First time after which the knowledge error angle stays <= k value_rad (and the estimate valid) to the
    end of the run (metrics.settle_time's rule); None when the last sample is outside."""
    inside = np.asarray(angle_rad, float) <= k * value_rad
    if valid is not None:
        inside &= np.asarray(valid, bool)
    return M.settle_time(np.asarray(t_s, float), inside)


# --------------------------------------------------------------------------- sensors and bounds
@dataclass(frozen=True)
class SensorSet:
    """The sensor figures the bound needs, named as the scenario's [sensors.star_tracker] and
    [sensors.gyro] keys (docs/scenarios.md)."""

    noise_cross_arcsec: float          # star tracker, 1-sigma about x_S, y_S
    noise_about_arcsec: float          # about z_S (the boresight)
    rate_hz: float                     # star tracker sample rate
    arw_rad_sqrt_s: float              # gyro angle random walk sigma_v
    rrw_rad_s_sqrt_s: float            # gyro rate random walk sigma_u
    mounting_q: tuple = (0.0, 0.0, 0.0, 1.0)   # q_SB

    @classmethod
    def from_configs(cls, star_tracker, gyro) -> SensorSet:
        """From the plant's StarTrackerConfig and GyroConfig (aocs_plant.sensors: the gyro's arw, rrw are
        the scenario's arw_rad_sqrt_s, rrw_rad_s_sqrt_s)."""
        return cls(float(star_tracker.noise_cross_arcsec), float(star_tracker.noise_about_arcsec),
                   float(star_tracker.rate_hz), float(gyro.arw), float(gyro.rrw),
                   tuple(float(v) for v in getattr(star_tracker, "mounting_q", (0.0, 0.0, 0.0, 1.0))))

    def as_dict(self) -> dict:
        return {"star_tracker": {"noise_cross_arcsec": self.noise_cross_arcsec,
                                 "noise_about_arcsec": self.noise_about_arcsec, "rate_hz": self.rate_hz,
                                 "mounting_q": list(self.mounting_q)},
                "gyro": {"arw_rad_sqrt_s": self.arw_rad_sqrt_s, "rrw_rad_s_sqrt_s": self.rrw_rad_s_sqrt_s}}


def _to_body(per_s_axis, mounting_q) -> np.ndarray:
    """1-sigma per axis of S -> per axis of B: sqrt(diag(A^T diag(s^2) A)), A = A(q_SB) (B to S)."""
    a = np.asarray(quat_to_dcm(tuple(mounting_q)), float)
    s2 = np.asarray(per_s_axis, float) ** 2
    return np.sqrt(np.einsum("ji,j,ji->i", a, s2, a))


def steady_state_bounds(sensors: SensorSet, control_rate_hz: float | None = None) -> dict | None:
    """Farrenkopf's 1-sigma steady state per axis of B (estimation_bounds; S axes rotated to B by the
    mounting, exact for an isotropic gyro): attitude after an update (`post_arcsec`, what
    steady_state_per_axis gives), before it (`pre_arcsec`), the rms over the control periods of an update
    interval (`log_rms_arcsec`: what the knowledge error's rms over a log at the control rate is to be
    compared with; the post figure without a control rate) and the bias after an update (`bias_deg_h`).
    None when a star-tracker noise is 0 (no steady state)."""
    s = sensors
    if not (s.noise_cross_arcsec > 0.0 and s.noise_about_arcsec > 0.0 and s.rate_hz > 0.0):
        return None
    args = (s.noise_cross_arcsec, s.noise_about_arcsec, s.rate_hz, s.arw_rad_sqrt_s, s.rrw_rad_s_sqrt_s)
    post = steady_state_per_axis(*args, when="post")
    pre = steady_state_per_axis(*args, when="pre")
    dt = 1.0 / s.rate_hz
    per = [x / ARCSEC_PER_RAD for x in (s.noise_cross_arcsec, s.noise_cross_arcsec, s.noise_about_arcsec)]
    n = T.control_steps_per_update(s, control_rate_hz) if control_rate_hz else 1
    log_rms = [between_updates(sn, s.arw_rad_sqrt_s, s.rrw_rad_s_sqrt_s, dt, n) * ARCSEC_PER_RAD for sn in per]
    bias = [farrenkopf(sn, s.arw_rad_sqrt_s, s.rrw_rad_s_sqrt_s, dt).bias_post * DEG_H_PER_RAD_S for sn in per]
    q = s.mounting_q
    return {"post_arcsec": _to_body(post, q), "pre_arcsec": _to_body(pre, q),
            "log_rms_arcsec": _to_body(log_rms, q), "bias_deg_h": _to_body(bias, q),
            "updates_every_control_periods": n}


# --------------------------------------------------------------------------- the run's section
def _f(x):
    """JSON-safe float (None for None, NaN, inf)."""
    if x is None:
        return None
    x = float(x)
    return x if math.isfinite(x) else None


def _fl(a):
    return None if a is None else [_f(v) for v in np.asarray(a, float).ravel()]


def _max(a):
    a = np.asarray(a, float)
    return float(np.max(a)) if a.size else math.nan


def analyse(t_s, q_true, q_est, bias_est_radps, bias_true_radps, est_p, qd=None, valid=None, *,
            sensors: SensorSet | None = None, control_rate_hz: float | None = None,
            window_s: float | None = None, steady_fraction: float = 0.5, convergence_k: float = 5.0,
            samples_per_window: int = 10, nees_spacing_s: float | None = None, outages=(),
            start: dict | None = None) -> tuple[dict, dict]:
    """(the run JSON's `estimation` section, the series for estimation_plots).

    Inputs, one row per control step: t_s (n,), q_true = q_BN and q_est (n, 4) scalar last, bias_est and
    bias_true (n, 3) rad/s in B, est_p (n, 21) upper triangle or (n, 6, 6), qd (n, 4) the reference
    (None: no control / pointing error), valid (n,) the estimate's validity, e.g. est_status == 0 of
    actuator_cmd_t (None: all valid).

    Steady-state window: the last window_s seconds, or the last steady_fraction of the run, from the
    convergence time on when the run converged; convergence: the knowledge angle stays within
    convergence_k x the analytic rms angle sqrt(sum pre_i^2) (before an update, the largest) to the end
    (needs sensors). Every statistic except the convergence time is over the valid samples of that window.

    With sensors, `transients` (estimation_transients): the convergence of the trailing rms per axis into
    3 times the steady state, measured, and predicted from the filter's own equations when `start` gives
    the filter's start {"p0_att_rad", "p0_bias_radps", "e0_att_B_rad" (3), "e0_bias_B_radps" (3)}; and one
    entry per star-tracker outage [start_s, end_s) of `outages` inside the run."""
    t = np.asarray(t_s, float)
    n = t.size
    valid = np.ones(n, bool) if valid is None else np.asarray(valid, bool).copy()
    p = covariance_from_upper(est_p)
    dth = knowledge_error_rad(q_true, q_est)
    valid &= np.all(np.isfinite(dth), axis=1)
    ang = angle_rad(dth)
    bounds = steady_state_bounds(sensors, control_rate_hz) if sensors is not None else None
    conv_thr = conv = None
    if bounds is not None:
        conv_thr = convergence_k * float(np.linalg.norm(bounds["pre_arcsec"])) / ARCSEC_PER_RAD
        conv = convergence_time_s(t, ang, conv_thr, 1.0, valid)
    steady = steady_state_mask(t, valid, window_s=window_s, fraction=steady_fraction, start_s=conv)
    ns = int(np.count_nonzero(steady))

    eps6 = nees_full(dth, bias_est_radps, bias_true_radps, p)
    eps3 = nees_attitude(dth, p)
    eps6[~valid] = np.nan
    eps3[~valid] = np.nan
    e6 = error_state(dth, bias_est_radps, bias_true_radps)
    with np.errstate(invalid="ignore", divide="ignore"):
        z6 = e6 / sigma_from_covariance(p)          # each component over its own sigma (its square: step 1)
    test6 = nees_window_test(t, eps6, 6, steady, samples_per_window=samples_per_window, spacing_s=nees_spacing_s,
                             components=z6)
    test3 = nees_window_test(t, eps3, 3, steady, samples_per_window=samples_per_window, spacing_s=nees_spacing_s,
                             components=z6[:, :3])

    sig = sigma_from_covariance(p)
    be_deg_h = bias_error_deg_h(bias_est_radps, bias_true_radps)
    ke_as = dth * ARCSEC_PER_RAD
    rms_ke = rms_per_axis(ke_as, steady)
    frac3 = three_sigma_fraction(dth, p, steady)
    frac3_run = three_sigma_fraction(dth, p, valid)
    frac3_axes = [three_sigma_fraction(dth, p, steady, axes=(i,)) for i in range(3)]
    frac3_bias = three_sigma_fraction(-bias_error_radps(bias_est_radps, bias_true_radps), p[:, 3:, 3:], steady)
    not_pd = int(np.count_nonzero(steady & ~np.isfinite(eps6)))

    out = {
        "knowledge_error_arcsec": {
            "rms_per_axis": _fl(rms_ke), "frame": "B", "max": _f(_max(ang[steady]) * ARCSEC_PER_RAD),
            "rms": _f(math.sqrt(np.mean(ang[steady] ** 2)) * ARCSEC_PER_RAD if ns else math.nan),
            "max_abs_per_axis": _fl(np.max(np.abs(ke_as[steady]), axis=0) if ns else np.full(3, np.nan)),
            "mean_per_axis": _fl(np.mean(ke_as[steady], axis=0) if ns else np.full(3, np.nan)),
            "filter_sigma_rms_per_axis": _fl(rms_per_axis(sig[:, :3] * ARCSEC_PER_RAD, steady)),
            "definition": "rotation vector of q_true (x) q_est^-1",
        },
        "steady_state_bound_arcsec": _fl(bounds["post_arcsec"]) if bounds else None,
        "steady_state_bound_pre_arcsec": _fl(bounds["pre_arcsec"]) if bounds else None,
        "steady_state_bound_log_rms_arcsec": _fl(bounds["log_rms_arcsec"]) if bounds else None,
        "knowledge_rms_over_bound": _fl(rms_ke / bounds["log_rms_arcsec"]) if bounds else None,
        "nees_in_band_fraction": _f(test6.in_band_fraction),
        "nees_attitude_in_band_fraction": _f(test3.in_band_fraction),
        "three_sigma_fraction": _f(frac3),
        "three_sigma_fraction_per_axis": [_f(v) for v in frac3_axes],
        "three_sigma_fraction_whole_run": _f(frac3_run),
        "three_sigma_fraction_bias": _f(frac3_bias),
        "nees": test6.as_dict(),
        "nees_attitude": test3.as_dict(),
        "convergence_time_s": _f(conv),
        "convergence_threshold_arcsec": _f(conv_thr * ARCSEC_PER_RAD) if conv_thr is not None else None,
        "bias_error_deg_h": {
            "rms_per_axis": _fl(rms_per_axis(be_deg_h, steady)),
            "max_abs_per_axis": _fl(np.max(np.abs(be_deg_h[steady]), axis=0) if ns else np.full(3, np.nan)),
            "final": _fl(be_deg_h[-1]), "frame": "B", "definition": "bias_est - bias_true",
            "filter_sigma_rms_per_axis": _fl(rms_per_axis(sig[:, 3:] * DEG_H_PER_RAD_S, steady)),
            "steady_state_bound": _fl(bounds["bias_deg_h"]) if bounds else None,
        },
        "window": {"start_s": _f(t[steady][0]) if ns else None, "end_s": _f(t[steady][-1]) if ns else None,
                   "rule": (f"last {window_s:g} s" if window_s is not None else f"last {steady_fraction:g} of the run")
                   + " from the convergence time, valid samples"},
        "samples": {"total": n, "valid": int(np.count_nonzero(valid)), "in_window": ns,
                    "covariance_not_positive_definite": not_pd},
        "sensors": sensors.as_dict() if sensors is not None else None,
        "transients": _transients(t, dth, p, valid, sensors, control_rate_hz, outages, start),
    }
    series = {"t": t, "valid": valid, "steady": steady, "knowledge_arcsec": ke_as,
              "sigma_arcsec": sig[:, :3] * ARCSEC_PER_RAD, "bias_est_deg_h": np.asarray(bias_est_radps, float)
              * DEG_H_PER_RAD_S, "bias_true_deg_h": np.asarray(bias_true_radps, float) * DEG_H_PER_RAD_S,
              "sigma_bias_deg_h": sig[:, 3:] * DEG_H_PER_RAD_S, "nees": eps6, "nees_attitude": eps3,
              "nees_test": test6, "nees_attitude_test": test3, "convergence_time_s": conv,
              "bound_post_arcsec": None if bounds is None else bounds["post_arcsec"]}
    if qd is not None:
        ce = control_error_arcsec(q_est, qd)["true_angle"]
        pe = pointing_error_arcsec(q_true, qd)["true_angle"]
        for key, a in (("control_error_arcsec", ce), ("pointing_error_arcsec", pe)):
            out[key] = {"rms": _f(math.sqrt(np.mean(a[steady] ** 2)) if ns else math.nan),
                        "max": _f(_max(a[steady])), "definition": "2 asin|qe_vec| (SPEC 1.7)"}
        out["control_error_arcsec"]["of"] = "q_est against qd"
        out["pointing_error_arcsec"]["of"] = "q_true against qd"
        series.update(control_error_arcsec=ce, pointing_error_arcsec=pe)
    else:
        out["control_error_arcsec"] = out["pointing_error_arcsec"] = None
    return out, series


def _transients(t, dth, p, valid, sensors, control_rate_hz, outages, start) -> dict | None:
    """The `transients` subsection (analyse); None without sensors or a control rate."""
    if sensors is None or not control_rate_hz or steady_state_bounds(sensors) is None:
        return None
    conv = T.convergence(t, dth, sensors, control_rate_hz, valid=valid)
    pred = None
    if start is not None:
        pc = T.predicted_convergence(sensors, control_rate_hz, start["p0_att_rad"], start["p0_bias_radps"],
                                    start["e0_att_B_rad"], start["e0_bias_B_radps"], t[-1] - t[0] + 1.0 / control_rate_hz,
                                    k=T.PREDICTION_K)
        pred = _f(pc["time_s"])
    conv["time_s"] = _f(conv["time_s"] - t[0]) if conv["time_s"] is not None else None
    return {"convergence": {**conv, "predicted_time_s": pred, "predicted_k": T.PREDICTION_K, "measured_from_s": _f(t[0]),
                            "start": None if start is None else {k: (_fl(v) if np.ndim(v) else _f(v))
                                                                 for k, v in start.items()}},
            "outages": T.outage_report(t, dth, p[:, :3, :3], outages, sensors, control_rate_hz, valid=valid)}


def summary(*args, **kwargs) -> dict:
    """The run JSON's `estimation` section (analyse's first value; the same arguments)."""
    return analyse(*args, **kwargs)[0]


def window_errors(t_s, q_true, q_est, qd, valid=None, *, window_s: float) -> dict:
    """Knowledge, control and pointing error (true angles 2 asin|qe_vec|, arcsec) over the last window_s
    seconds (metrics.window_mask, the window of the run's pointing figures), valid samples only: rms and max
    of each. Knowledge: q_true against q_est; control: q_est against qd (what the law acts on); pointing:
    q_true against qd (what the mission gets). `aocs compare` and docs/results.md report these."""
    t = np.asarray(t_s, float)
    mask = steady_state_mask(t, valid, window_s=window_s)
    ns = int(np.count_nonzero(mask))
    series = {"knowledge_arcsec": angle_rad(knowledge_error_rad(q_true, q_est)) * ARCSEC_PER_RAD,
              "control_arcsec": control_error_arcsec(q_est, qd)["true_angle"],
              "pointing_arcsec": pointing_error_arcsec(q_true, qd)["true_angle"]}
    out = {"window_s": _f(window_s), "samples": ns,
           "start_s": _f(t[mask][0]) if ns else None, "end_s": _f(t[mask][-1]) if ns else None}
    for key, a in series.items():
        a = np.asarray(a, float)[mask]
        out[key] = {"rms": _f(math.sqrt(float(np.mean(a ** 2)))) if ns else None, "max": _f(_max(a))}
    return out
