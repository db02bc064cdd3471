"""Thrusters (docs/spec.md 5.8.1): `[thrusters]`, command fields `thruster_on_s`, `thruster_latch_closed`.

N thrusters at positions r_i (m, B, from the centre of mass) firing along unit directions d_i (B): the
thrust F_i acts on the body along d_i (the exhaust leaves along -d_i). The command is the on-time of each
thruster within the control period (s). Once per command:

    tau_i = min(dt, max(0, c_i))                       clipped to the period
    tau_i = q round(tau_i / q)                         on_time_quantum_s q (none when 0), at most dt
    tau_i = 0 if tau_i < min_on_time_s                 the minimum impulse bit F_i min_on_time_s

Each control period, after the injected faults (aocs_plant.faults.thrusters: a stuck-open thruster flies
tau_i = dt) and before the thrust:

    tau_i = 0 if bit b_i of the latch mask is set      b_i = latch_branch[i], 0 (branch A) or 1 (B)

Every thruster is fed through the latch valve of its branch, upstream of its own valve: closing a branch's
latch valve stops every thruster on it, a stuck-open one too (fault isolation, docs/spec.md 5.15.8). The
command field `thruster_latch_closed` is that mask (bit 0: branch A's valve closed, bit 1: B's), an integer
in [0, 3] (Plant.apply refuses anything else); the valves keep their state until a command carries the
field again (all open at the start). `latch_branch` defaults to every thruster on branch A.

Over each control period (the pulse is spread over the period: its impulse is exact, its timing within
the period is not resolved), with the actual thrust of the period and the actual directions:

    F_i = thrust_i (1 + sigma_F n_i), n_i ~ N(0, 1)    thrust_noise_frac sigma_F, drawn every period
    d_i' = Rot(phi_i) d_i,  phi_i = s (n_a e1 + n_b e2)  misalignment_deg s, drawn once per run; e1, e2
                                                         unit, perpendicular to d_i and to each other
    force_B  = sum_i F_i d_i' tau_i / dt               (N, held over the period)
    torque_B = sum_i F_i (r_i x d_i') tau_i / dt       (N m, held over the period)
    mdot     = sum_i F_i tau_i / (dt Isp g0)           (kg/s; g0 = 9.80665 m/s^2)

On the attitude plant the torque acts on the body; the force is recorded: the effector's state is the
impulse in N, I_N = integral of A(q)^T force_B dt (N s), and the propellant used (kg), integrated by the
same RK4 as the body. With `mass_kg` the truth also gives the velocity change I_N / mass_kg (m/s).
Truth: on-times commanded and applied, thrust, force, torque, impulse, propellant, delta-v, the pulses
fired and the on-time flown per thruster, the latch mask. Seeded streams "thrust_noise" (9, one draw of N
per period) and "thruster_misalignment" (10, 2 N draws at construction), only when their sigma is set.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .. import rng
from ..rng import NormalStream
from .base import ATTITUDE, ZERO3, Effector, Form, Mask, register
from .magnetorquers import cross

THRUSTER_ON = "thruster_on_s"
THRUSTER_LATCH = "thruster_latch_closed"
LATCH_BRANCHES = 2               # latch valves A (bit 0 of the mask) and B (bit 1)
ZERO4 = (0.0, 0.0, 0.0, 0.0)
G0 = 9.80665                     # standard gravity, m/s^2 (the definition of Isp)
MAX_THRUSTERS = 24
NOISE_CHANNEL, MISALIGNMENT_CHANNEL = "thrust_noise", "thruster_misalignment"
rng.claim(NOISE_CHANNEL, 9)
rng.claim(MISALIGNMENT_CHANNEL, 10)
KEYS = ("thrust_n", "positions_m", "directions", "min_on_time_s", "on_time_quantum_s", "thrust_noise_frac",
        "misalignment_deg", "isp_s", "mass_kg", "latch_branch")


@dataclass(frozen=True)
class ThrustersConfig:
    """The [thrusters] figures, built only by Thrusters.read (every field passed; the keys' defaults there)."""
    thrust_n: tuple              # per thruster, N
    positions_m: tuple           # r_i, B, from the centre of mass
    directions: tuple            # d_i, unit, B
    min_on_time_s: float
    on_time_quantum_s: float
    thrust_noise_frac: float
    misalignment_deg: float
    isp_s: float
    mass_kg: float | None        # for the delta-v in the truth only
    latch_branch: tuple          # the latch valve's branch of each thruster, 0 (A) or 1 (B); (): all A

    @property
    def n(self) -> int:
        return len(self.positions_m)


def _flat3(sec, key: str) -> tuple:
    raw = sec.data.get(key)
    if not isinstance(raw, list) or not raw or len(raw) % 3:
        sec.fail(sec.key(key), "expected a flat array of 3 N numbers (x, y, z of each thruster)")
    flat = sec.vector(key, n=len(raw))
    return tuple(flat[i:i + 3] for i in range(0, len(flat), 3))


def _what(v) -> str:
    """A TOML value's kind, as the loader names it."""
    for t, name in ((bool, "a boolean"), (int, "an integer"), (float, "a number"), (str, "a string"),
                    (list, "an array"), (dict, "a table")):
        if isinstance(v, t):
            return name
    return type(v).__name__


def _latch_branch(sec, n: int) -> tuple:
    """`latch_branch`: n integers, 0 (branch A) or 1 (branch B); absent: all 0."""
    if not sec.has("latch_branch"):
        return (0,) * n
    raw = sec.data.pop("latch_branch")
    key = sec.key("latch_branch")
    if not isinstance(raw, list) or len(raw) != n:
        got = f"{len(raw)} values" if isinstance(raw, list) else _what(raw)
        sec.fail(key, f"expected an array of {n} integers (one per thruster), 0 (branch A) or 1 (branch B), "
                      f"got {got}")
    for i, b in enumerate(raw):
        if isinstance(b, bool) or not isinstance(b, int) or b not in (0, 1):
            got = repr(b) if isinstance(b, (int, float)) and not isinstance(b, bool) else _what(b)
            sec.fail(f"{key}[{i}]", f"expected 0 (branch A) or 1 (branch B), got {got}")
    return tuple(raw)


def quantise_on_time(c: float, dt: float, quantum: float, min_on: float) -> float:
    """The on-time flown for a commanded c (module docstring)."""
    t = min(dt, max(0.0, c))
    if quantum > 0.0:
        t = min(dt, quantum * math.floor(t / quantum + 0.5))
    return 0.0 if t < min_on else t


def misaligned(d, tilt) -> tuple:
    """Rot(phi) d with phi = tilt[0] e1 + tilt[1] e2 perpendicular to d (Rodrigues; phi . d = 0)."""
    ref = (1.0, 0.0, 0.0) if abs(d[0]) < 0.9 else (0.0, 1.0, 0.0)
    e1 = cross(d, ref)
    n1 = math.sqrt(sum(v * v for v in e1))
    e1 = tuple(v / n1 for v in e1)
    e2 = cross(d, e1)
    phi = tuple(tilt[0] * e1[k] + tilt[1] * e2[k] for k in range(3))
    a = math.sqrt(sum(v * v for v in phi))
    if a == 0.0:
        return tuple(d)
    u = tuple(v / a for v in phi)
    ud = cross(u, d)
    return tuple(d[k] * math.cos(a) + ud[k] * math.sin(a) for k in range(3))


@register
class Thrusters(Effector):
    kind = "thrusters"
    group = None                     # a top-level section [thrusters]
    applies_to = (ATTITUDE,)
    role = "actuator"
    form = Form.GENERAL              # state: the impulse in N (3) and the propellant used (1)
    state_size = 4
    period_hooks = True

    @classmethod
    def read(cls, sec, ctx) -> ThrustersConfig:
        sec.only(KEYS)
        pos = _flat3(sec, "positions_m")
        dirs = _flat3(sec, "directions")
        n = len(pos)
        if len(dirs) != n:
            sec.fail(sec.key("directions"), f"{len(dirs)} directions for {n} thrusters (positions_m)")
        if n > MAX_THRUSTERS:
            sec.fail(sec.key("positions_m"), f"{n} thrusters, at most {MAX_THRUSTERS}")
        for i, d in enumerate(dirs):
            norm = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            if abs(norm - 1.0) > 1e-9:
                sec.fail(sec.key("directions"), f"thruster {i}: not a unit vector (norm {norm!r})")
        thrust = sec.scalar_or_vector("thrust_n", n=n, positive=True)
        dt = ctx.dt
        min_on = sec.number("min_on_time_s", required=False, default=0.0, nonneg=True)
        quantum = sec.number("on_time_quantum_s", required=False, default=0.0, nonneg=True)
        for k, v in (("min_on_time_s", min_on), ("on_time_quantum_s", quantum)):
            if v > dt:
                sec.fail(sec.key(k), f"{v:g} s is longer than the control period ({dt:g} s)")
        noise = sec.number("thrust_noise_frac", required=False, default=0.0, nonneg=True)
        if noise > 0.5:
            sec.fail(sec.key("thrust_noise_frac"), f"{noise:g} is above 0.5 (a 1-sigma fraction of the thrust)")
        mis = sec.number("misalignment_deg", required=False, default=0.0, nonneg=True)
        if mis > 10.0:
            sec.fail(sec.key("misalignment_deg"), f"{mis:g} deg is above 10 deg (a small misalignment)")
        isp = sec.number("isp_s", required=False, default=220.0, positive=True)
        mass = sec.number("mass_kg", required=False, default=None, positive=True)
        return ThrustersConfig(tuple(thrust), pos, dirs, min_on, quantum, noise, mis, isp, mass,
                               _latch_branch(sec, n))

    def __init__(self, config: ThrustersConfig, body):
        super().__init__(config, body)
        n = config.n
        self.n = n
        self.dt = float(body.dt)
        self.command_fields = {THRUSTER_ON: n, THRUSTER_LATCH: Mask(LATCH_BRANCHES)}
        branch = config.latch_branch or (0,) * n
        # for each latch mask, the thrusters its closed valves stop (None: none of them), built once
        self._stopped = tuple(
            tuple(bool(m >> b & 1) for b in branch) if any(m >> b & 1 for b in branch) else None
            for m in range(1 << LATCH_BRANCHES))
        self.latch_closed = 0                        # the mask: every valve open at the start
        self._stop = None
        dirs = config.directions
        if config.misalignment_deg > 0.0:
            s = NormalStream(body.seed, MISALIGNMENT_CHANNEL, math.radians(config.misalignment_deg), width=2)
            dirs = tuple(misaligned(d, s.next()) for d in dirs)
        self.directions = dirs                       # the actual d_i'
        self.arms = tuple(cross(r, d) for r, d in zip(config.positions_m, dirs))   # r_i x d_i'
        self.noise = NormalStream(body.seed, NOISE_CHANNEL, config.thrust_noise_frac, width=n) \
            if config.thrust_noise_frac > 0.0 else None
        self.on_cmd = (0.0,) * n
        self._off = (0.0,) * n
        self.on = self._off                          # on-times flown this period
        self.on_nominal = self._off                  # on-times commanded (quantised), before injected faults
        self.fault_model = None                      # injected faults (aocs_plant.faults.thrusters)
        self.thrust = tuple(config.thrust_n)         # actual thrust of the period
        self.force_b = ZERO3
        self.torque_b = ZERO3
        self.mdot = 0.0
        self.pulses = [0] * n
        self.on_total = [0.0] * n

    def initial_state(self) -> tuple:
        return ZERO4

    def command(self, cmd) -> None:
        m = cmd.get(THRUSTER_LATCH)
        if m is not None:                   # absent: the valves keep their state
            self.latch_closed = m           # Plant.apply hands an int in [0, 3]
            self._stop = self._stopped[m]
        c = cmd.get(THRUSTER_ON)
        if c is None:
            return
        self.on_cmd = c = tuple(c)          # Plant.apply hands finite floats
        if not any(c):
            self.on = self.on_nominal = self._off
            return
        cfg = self.config
        self.on = self.on_nominal = tuple(quantise_on_time(v, self.dt, cfg.on_time_quantum_s, cfg.min_on_time_s)
                                          for v in c)

    def begin_period(self, t, x) -> None:
        """The on-times flown (faults, then the latch valves), the thrust of the period (noise drawn in every
        period) and the held force and torque."""
        on = self.on_nominal
        if self.fault_model is not None:   # injected faults (aocs_plant.faults.thrusters) on the on-times
            on = self.fault_model.on_times(t, on)
        stop = self._stop
        if stop is not None and any(on):   # a closed latch valve, upstream: stops a stuck-open thruster too
            on = tuple(0.0 if s else v for v, s in zip(on, stop))
        self.on = on
        nom = self.config.thrust_n
        if self.noise is not None:
            z = self.noise.next()
            self.thrust = tuple(max(0.0, f * (1.0 + z[i])) for i, f in enumerate(nom))
        if not any(self.on):
            self.force_b = self.torque_b = ZERO3
            self.mdot = 0.0
            return
        fx = fy = fz = tx = ty = tz = 0.0
        flow = 0.0
        inv = 1.0 / self.dt
        for i in range(self.n):
            tau = self.on[i]
            if tau == 0.0:
                continue
            f = self.thrust[i] * tau * inv
            d, a = self.directions[i], self.arms[i]
            fx += f * d[0]
            fy += f * d[1]
            fz += f * d[2]
            tx += f * a[0]
            ty += f * a[1]
            tz += f * a[2]
            flow += f
        self.force_b = (fx, fy, fz)
        self.torque_b = (tx, ty, tz)
        self.mdot = flow / (self.config.isp_s * G0)

    def end_period(self, t, x) -> None:
        for i in range(self.n):
            if self.on[i] > 0.0:
                self.pulses[i] += 1
                self.on_total[i] += self.on[i]

    def derivative(self, t, body, x):
        if self.mdot == 0.0:             # no thruster fires this period (most periods)
            return ZERO3, ZERO4
        q1, q2, q3, q4 = body[0], body[1], body[2], body[3]
        f1, f2, f3 = self.force_b
        # A(q)^T f: the force in N (the transpose of quat_rotate's A(q))
        s = q4 * q4 - (q1 * q1 + q2 * q2 + q3 * q3)
        vd = 2.0 * (q1 * f1 + q2 * f2 + q3 * f3)
        k = 2.0 * q4
        fn = (s * f1 + vd * q1 + k * (q2 * f3 - q3 * f2),
              s * f2 + vd * q2 + k * (q3 * f1 - q1 * f3),
              s * f3 + vd * q3 + k * (q1 * f2 - q2 * f1))
        return self.torque_b, (fn[0], fn[1], fn[2], self.mdot)

    def compiled_general(self):
        return ("thrusters",)

    def compiled_input(self):
        """(mdot, force_b, torque_b) of the period: derivative()'s held values (kernels.py)."""
        return (self.mdot, *self.force_b, *self.torque_b)

    @property
    def applied(self) -> tuple:
        return self.torque_b

    def truth(self, t, body, x) -> dict:
        out = {"on_time_cmd_s": self.on_cmd, "on_time_s": self.on, "thrust_n": self.thrust,
               "force_b_n": self.force_b, "torque_nm": self.torque_b, "impulse_n_ns": tuple(x[0:3]),
               "propellant_kg": x[3], "pulses": tuple(self.pulses), "on_time_total_s": tuple(self.on_total),
               "latch_closed": self.latch_closed}
        if self.config.mass_kg is not None:
            out["delta_v_n_m_s"] = tuple(v / self.config.mass_kg for v in x[0:3])
        return out
