"""Each attitude law linearised about its hold, as the controller of the loop (docs/spec.md, "Stability margins").

At the hold the error quaternion is the identity and the rate error zero. With the small rotation vector
theta of the body from the target (qe_vec = theta / 2 to first order) and the rate error we, the plant
output the law reads is y = [theta; we] (6), and every law's first-order expansion about y = 0 is a
linear controller

    z(k+1) = z(k) + dt Bc y(k)         (forward Euler, exactly the firmware's integrator, integral.c)
    u(k)   = Cc z(k) + Dc y(k)

with no state for the laws without integral action. The continuous-time controller with the same
matrices (z' = Bc y) is what "continuous" means in the sampled-versus-continuous comparison. The
expansions, from the C source of each law (firmware/src/control/):

    crp_linear             u = -k1 we - k2 rho, rho = qe_vec / qe4     -> Dc = [-k2/2 I, -k1 I]
    quat_pd, quat_nlpd_*   u = -kp qe_vec - kd (1 -+ |qe_vec|^2) we   -> Dc = [-kp/2 I, -kd I]
    smc                    u = J (-Lambda qe_vec' - G sat(s / eps)) + w x J w,  s = we + Lambda qe_vec,
                           inside the boundary layer: Dc = [-J G Lambda / (2 eps), -J (Lambda / 2 + G / eps)]
    lqr_quat               u = -K [qe_vec; we]                        -> Dc = -K diag(I/2, I)
    quat_pid               u = -kp qe_vec - kd we - ki z, z' = qe_vec  -> Bc = [I/2, 0], Cc = -ki I
    lqr_quat_i             u = -K [z; qe_vec; we], z' = qe_vec        -> Cc = -K_z, Dc = -[K_q / 2, K_w]
    hinf                   u = +K x, x = [roll pitch yaw, Euler rates] (its plant state, aocs_design.models)

The integrators are linear only inside their clamp |z| <= z_max and with no saturated command; the
boundary layer of smc only for |s_i| <= eps_i: the analysis states these as the operating region.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aocs_analysis.gain_tables import gain_matrix


class LawModelError(ValueError):
    """The law has no linear model here (an orbit law, an unknown law, a missing gain)."""


@dataclass(frozen=True)
class LinearLaw:
    """u = Cc z + Dc y, z' = Bc y (continuous) or z(k+1) = z(k) + dt Bc y(k) (the firmware)."""

    law: str
    table: str | None
    bc: np.ndarray          # (nz, 6)
    cc: np.ndarray          # (3, nz)
    dc: np.ndarray          # (3, 6)
    output: str             # "rotation" (y = [theta; we]) or "euler" (y = the H-infinity model state)
    region: str             # where the expansion holds

    @property
    def states(self) -> int:
        return self.bc.shape[0]

    def scaled(self, k: float) -> "LinearLaw":
        """The same law with every gain times k (a loop gain k at the plant input)."""
        return LinearLaw(self.law, self.table, self.bc, k * self.cc, k * self.dc, self.output, self.region)


HALF = np.diag([0.5, 0.5, 0.5])
I3 = np.eye(3)
Z3 = np.zeros((3, 3))


def _static(law, table, dc, output="rotation", region="any small error about the hold") -> LinearLaw:
    return LinearLaw(law, table, np.zeros((0, 6)), np.zeros((3, 0)), np.asarray(dc, float), output, region)


def _inertia(sc) -> np.ndarray:
    return np.asarray(sc.attitude.inertia, float)


def linear_law(sc, law: str, table: str | None = None) -> LinearLaw:
    """The law's first-order expansion about the hold with the scenario's gains (table: a gain table)."""
    if sc.kind != "attitude":
        raise LawModelError(f"scenario {sc.id} is an orbit scenario: the margins are of the attitude laws")
    lc = sc.control.laws.get(law)
    if lc is None:
        raise LawModelError(f"scenario {sc.id} has no gains for law {law!r} (it has: {', '.join(sc.control.laws)})")
    p = dict(lc.params)
    table = table or lc.table
    if law == "crp_linear":
        return _static(law, None, np.hstack([-0.5 * p["k2"] * I3, -p["k1"] * I3]))
    if law in ("quat_pd", "quat_nlpd_neg", "quat_nlpd_pos"):
        return _static(law, None, np.hstack([-0.5 * p["kp"] * I3, -p["kd"] * I3]))
    if law == "smc":
        j = _inertia(sc)
        lam, g, eps = (np.diag(np.asarray(p[k], float)) for k in ("lambda", "g", "eps"))
        ge = g @ np.linalg.inv(eps)
        return _static(law, None, np.hstack([-0.5 * j @ ge @ lam, -j @ (0.5 * lam + ge)]),
                       region="inside the boundary layer |we_i + lambda_i qe_i| <= eps_i")
    if law == "lqr_quat":
        k = gain_matrix(table)
        return _static(law, table, -k @ np.block([[HALF, Z3], [Z3, I3]]))
    if law == "hinf":
        return _static(law, table, gain_matrix(table), output="euler")
    if law == "quat_pid":
        return LinearLaw(law, None, np.hstack([HALF, Z3]), -p["ki"] * I3,
                         np.hstack([-0.5 * p["kp"] * I3, -p["kd"] * I3]), "rotation",
                         f"integrator inside its clamp |z_i| <= {p['z_max']:g} s, command not saturated")
    if law == "lqr_quat_i":
        k = gain_matrix(table, cols=9)
        return LinearLaw(law, table, np.hstack([HALF, Z3]), -k[:, 0:3],
                         np.hstack([-0.5 * k[:, 3:6], -k[:, 6:9]]), "rotation",
                         f"integrator inside its clamp |z_i| <= {p['z_max']:g} s, command not saturated")
    raise LawModelError(f"law {law!r} has no linear model about the hold in the margin analysis "
                        "(analysed: crp_linear, quat_pd, quat_nlpd_neg, quat_nlpd_pos, smc, lqr_quat, hinf, quat_pid, lqr_quat_i)")


ANALYSED = ("crp_linear", "quat_pd", "quat_nlpd_neg", "quat_nlpd_pos", "smc", "lqr_quat", "hinf", "quat_pid", "lqr_quat_i")


def law_rows(sc, laws: str = "all") -> list[tuple[str, str | None]]:
    """(law, table) for every analysed law of the scenario (every table of a table law), or the
    comma list `laws` (law or law:table)."""
    rows = []
    for law, lc in sc.control.laws.items():
        if law in ANALYSED:
            rows += [(law, t) for t in lc.tables] if lc.tables else [(law, None)]
    if laws in ("", "all", None):
        return rows
    out = []
    for item in laws.split(","):
        law, _, table = item.strip().partition(":")
        match = [r for r in rows if r[0] == law and (not table or r[1] == table)]
        if not match:
            linear_law(sc, law, table or None)   # raises with the reason
            raise LawModelError(f"--law {item.strip()}: scenario {sc.id} has no gain table {table!r} for {law}")
        out.append((law, table or sc.control.laws[law].table))
    return out
