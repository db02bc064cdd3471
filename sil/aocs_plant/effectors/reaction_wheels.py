"""Reaction wheel array (SPEC 5.3; docs/spec.md 5.3): `[wheels]`, N wheels exchanging momentum with the body.

State: the wheels' axial momenta h_i = Js_i (g_i . w + Omega_i) (N m s), integrated by the same RK4
as the body (a GENERAL effector). With J the scenario's inertia (it includes the wheels) the body
equation uses J_b = J - sum Js_i g_i g_i^T (inertia_offset), and this effector adds

    -w x (Gs h) - Gs tau        to the body torque,     hdot_i = tau_i = u_i - f_i(Omega_i)

so that J_b wdot = -w x (J_b w + Gs h) - Gs tau + L (Schaub & Junkins, ch. 4, reaction wheels;
docs/spec.md 5.3). The total momentum H = J_b w + Gs h = J w + sum Js_i g_i Omega_i changes only by
the external torque L: friction and the motors are internal.

Command fields (Plant.apply): `u_wheels`, the flight software's motor torque commands (N m, one per
wheel), and `u_body`, the body torque it asked for (recorded as `commanded`, not applied). Motor
torque u_i, held over the control period (zero-order hold) from the wheel torque command: clipped to |u_i| <= torque_limit_nm, plus an optional white torque noise (one draw
per wheel and period, seeded channel "wheel_torque"); a failed wheel's motor gives no torque (the
wheel coasts down under friction). Speed limit: at every RK4 stage a motor torque that would drive
|Omega_i| beyond speed_limit_rad_s (|Omega_i| >= limit and u_i Omega_i > 0) is cut to zero.
Friction, smooth through zero speed (the sign of the Coulomb term replaced by tanh with width
coulomb_width_rad_s, SPEC 5.3 "smooth near 0"):

    f_i(Omega) = b Omega + c tanh(Omega / Omega_eps)

The array is either a pyramid (spin axes cant_deg from one body axis, equally spaced around it,
the first at azimuth 0 from the next body axis in cyclic order) or explicit unit axes. The same
description gives the flight software's wheel configuration (aocs_flightcfg.fsw_config), so the two
cannot disagree; geometry() is that one derivation.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..rng import NormalStream
from .actuator import U_BODY
from .base import ATTITUDE, ZERO3, Effector, Form, register

#: the command field of the motor torques (N m, one per wheel)
U_WHEELS = "u_wheels"
MAX_WHEELS = 6                        # the flight software's fixed array size (wheel_array.h)
PYRAMID_CANT_DEG = math.degrees(math.acos(1.0 / math.sqrt(3.0)))   # 54.7356 deg (SPEC 5.3)
_AXES = {"x": 0, "y": 1, "z": 2}


@dataclass(frozen=True)
class WheelsConfig:
    """The [wheels] figures, built only by ReactionWheels.read (every field passed; the keys' defaults there)."""
    axes: tuple                   # N unit spin axes g_i in B (rows)
    spin_inertia_kg_m2: tuple     # Js_i
    torque_limit_nm: tuple        # u_s,max per wheel
    speed_limit_rad_s: tuple      # Omega_max per wheel
    viscous_nms: float            # b, N m s (per rad/s)
    coulomb_nm: float             # c, N m
    coulomb_width_rad_s: float    # Omega_eps of the tanh
    torque_noise_nm: float        # std of the motor torque noise per period (0 = none)
    speed0_rad_s: tuple           # initial Omega_i relative to the body
    failed: tuple                 # indices (0-based) of the wheels declared failed at t = 0
    tach_noise_rad_s: float       # tachometer white noise std (0 = none)
    tach_quantum_rad_s: float     # tachometer quantisation step (0 = none)
    array: str                    # "pyramid" | "explicit" (how the axes were given)
    # flight software only (the plant has no use for them): the null-space wheel speed management
    null_gain_per_s: float        # k_n, 1/s (0 = none)
    null_speed_rad_s: tuple       # Omega*_i, target speeds (their null-space part is what counts)
    fsw_friction_scale: float     # the flight software's friction model = this x (b, c): 1 = the plant's
                                  # own, 0 = no feedforward, else a model error (campaign dispersions)

    @property
    def n(self) -> int:
        return len(self.axes)

    def momentum_capacity_nms(self) -> tuple:
        """Js_i Omega_max,i: the most momentum each wheel holds (N m s)."""
        return tuple(j * w for j, w in zip(self.spin_inertia_kg_m2, self.speed_limit_rad_s))


def pyramid_axes(n: int, axis: int, cant_deg: float, azimuth0_deg: float = 0.0) -> tuple:
    """n spin axes cant_deg from body axis `axis`, 360/n deg apart around it (SPEC 5.3 reference array):
    g_i = cos(beta) a + sin(beta) (cos(az_i) b + sin(az_i) c), (a, b, c) cyclic body axes."""
    b_ax, c_ax = (axis + 1) % 3, (axis + 2) % 3
    beta = math.radians(cant_deg)
    out = []
    for i in range(n):
        az = math.radians(azimuth0_deg + 360.0 * i / n)
        g = [0.0, 0.0, 0.0]
        g[axis] = math.cos(beta)
        g[b_ax] = math.sin(beta) * math.cos(az)
        g[c_ax] = math.sin(beta) * math.sin(az)
        out.append(tuple(0.0 if abs(x) < 1e-15 else x for x in g))   # exact zeros, not cos(90 deg) = 6e-17
    return tuple(out)


def _per_wheel(sec, k, n, positive=True, required=True, default=None):
    v = sec.scalar_or_vector(k, n=n, required=required, default=default, positive=positive)
    return None if v is None else tuple(v)


def _check_registry_ranges(sec, values: dict) -> None:
    """Each value inside its registry row's range (what fsw_node would refuse is refused here, by key)."""
    from aocs_core import registry  # deferred: the registry JSON of the build, only for a [wheels] section

    rows = {f.key: f for f in registry.load().config_fields}
    for key, vals in values.items():
        f = rows[registry.WHEEL_REGISTRY_ROWS[key]]
        for i, v in enumerate(vals):
            if not f.holds(v):
                where = f"wheel {i}: " if len(vals) > 1 else ""
                sec.fail(sec.key(key), f"{where}{v!r} must be {f.rule_text} (the flight software's range, "
                                       f"configuration registry row {f.key})")


def _check_plant_inertia(sec, ctx, axes, js) -> None:
    """The body inertia less the wheels' spin inertia about their axes, J - sum Js_i g_i g_i^T, must stay
    positive definite (the plant integrates with it, RigidBody); else the loader refuses, by key."""
    J = getattr(ctx.plant, "inertia", None)
    if J is None:
        return
    import numpy as np  # deferred: only with a [wheels] section

    less = np.array(J, float) - sum(j * np.outer(g, g) for j, g in zip(js, axes))
    if not np.all(np.linalg.eigvalsh(less) > 0.0):
        sec.fail(sec.key("spin_inertia_kg_m2"), f"{max(js)!r} kg m^2: the body inertia less the wheels' spin "
                 "inertia (J - sum Js g g^T) is not positive definite: the wheels are heavier than the spacecraft")


def _rank3(axes) -> bool:
    """The axes span 3 dimensions: det(Gs Gs^T) well away from 0 (relative to its scale)."""
    m = [[sum(g[i] * g[j] for g in axes) for j in range(3)] for i in range(3)]
    det = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
           + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    return det > 1e-9 * (len(axes) / 3.0) ** 3


@register
class ReactionWheels(Effector):
    kind = "wheels"
    group = None                      # a top-level section [wheels]
    applies_to = (ATTITUDE,)
    role = "actuator"
    replaces = ("actuator",)          # the array stands in for the plain body-torque actuator
    form = Form.GENERAL
    period_hooks = True

    @classmethod
    def read(cls, sec, ctx) -> WheelsConfig:
        sec.only(("array", "count", "pyramid_axis", "cant_deg", "azimuth0_deg", "axes", "spin_inertia_kg_m2",
                  "torque_limit_nm", "speed_limit_rad_s", "viscous_nms", "coulomb_nm", "coulomb_width_rad_s",
                  "torque_noise_nm", "speed0_rad_s", "failed", "tach_noise_rad_s", "tach_quantum_rad_s",
                  "null_gain_per_s", "null_speed_rad_s", "fsw_friction_scale"))
        array = sec.string("array", choices=("pyramid", "explicit"))
        if array == "pyramid":
            for k in ("axes",):
                if sec.has(k):
                    sec.fail(sec.key(k), 'only with array = "explicit"')
            n = sec.integer("count", required=False, default=4, minimum=3)
            if n > MAX_WHEELS:
                sec.fail(sec.key("count"), f"{n} wheels: the flight software holds at most {MAX_WHEELS}")
            ax = sec.string("pyramid_axis", required=False, default="z", choices=tuple(_AXES))
            cant = sec.number("cant_deg", required=False, default=PYRAMID_CANT_DEG, positive=True)
            if not cant < 90.0:
                sec.fail(sec.key("cant_deg"), f"must be < 90 deg (a pyramid), got {cant}")
            az0 = sec.number("azimuth0_deg", required=False, default=0.0)
            axes = pyramid_axes(n, _AXES[ax], cant, az0)
        else:
            for k in ("count", "pyramid_axis", "cant_deg", "azimuth0_deg"):
                if sec.has(k):
                    sec.fail(sec.key(k), 'only with array = "pyramid"')
            raw, _ = sec._pop("axes", True, None)
            if not isinstance(raw, list) or not 3 <= len(raw) <= MAX_WHEELS:
                sec.fail(sec.key("axes"), f"expected 3 to {MAX_WHEELS} spin axes (arrays of 3 numbers)")
            axes = tuple(sec._check_vector(f"{sec.key('axes')}[{i}]", g, 3) for i, g in enumerate(raw))
            for i, g in enumerate(axes):
                nrm = math.sqrt(sum(x * x for x in g))
                if abs(nrm - 1.0) > 1e-9:
                    sec.fail(f"{sec.key('axes')}[{i}]", f"must be a unit vector (norm {nrm!r})")
            n = len(axes)
        if not _rank3(axes):
            sec.fail(sec.key("axes" if array == "explicit" else "array"),
                     "the spin axes do not span the three body axes")
        js = _per_wheel(sec, "spin_inertia_kg_m2", n)
        umax = _per_wheel(sec, "torque_limit_nm", n)
        wmax = _per_wheel(sec, "speed_limit_rad_s", n)
        b = sec.number("viscous_nms", required=False, default=0.0, nonneg=True)
        c = sec.number("coulomb_nm", required=False, default=0.0, nonneg=True)
        eps = sec.number("coulomb_width_rad_s", required=False, default=0.1, positive=True)
        # each value in the flight software's range before the checks across values name another key
        _check_registry_ranges(sec, {"spin_inertia_kg_m2": js, "torque_limit_nm": umax, "speed_limit_rad_s": wmax,
                                     "viscous_nms": (b,), "coulomb_nm": (c,), "coulomb_width_rad_s": (eps,)})
        noise = sec.number("torque_noise_nm", required=False, default=0.0, nonneg=True)
        s0 = sec.scalar_or_vector("speed0_rad_s", n=n, required=False, default=(0.0,) * n)
        for i, (s, m) in enumerate(zip(s0, wmax)):
            if abs(s) > m:
                sec.fail(sec.key("speed0_rad_s"), f"wheel {i}: |{s}| rad/s is beyond its speed limit {m}")
        raw, present = sec._pop("failed", False, [])
        if not isinstance(raw, list) or any(isinstance(i, bool) or not isinstance(i, int) for i in raw):
            sec.fail(sec.key("failed"), "expected an array of wheel indices (integers, 0-based)")
        failed = tuple(sorted(set(raw)))
        for i in failed:
            if not 0 <= i < n:
                sec.fail(sec.key("failed"), f"wheel {i} does not exist (wheels 0 to {n - 1})")
        healthy = [g for i, g in enumerate(axes) if i not in failed]
        if len(healthy) < 3 or not _rank3(healthy):
            sec.fail(sec.key("failed"), "the healthy wheels left do not span the three body axes")
        tn = sec.number("tach_noise_rad_s", required=False, default=0.0, nonneg=True)
        tq = sec.number("tach_quantum_rad_s", required=False, default=0.0, nonneg=True)
        fs = sec.number("fsw_friction_scale", required=False, default=1.0, nonneg=True)
        for i, (m, jm) in enumerate(zip(wmax, umax)):
            if not fs * (b * m + c) < jm:
                sec.fail(sec.key("coulomb_nm"), f"wheel {i}: the flight software's friction model at the speed "
                         f"limit, {fs!r} x (b Omega_max + c) = {fs * (b * m + c)!r} N m, is not below the torque "
                         f"limit {jm} (the friction feedforward needs motor torque left)")
        kn = sec.number("null_gain_per_s", required=False, default=0.0, nonneg=True)
        ns = sec.scalar_or_vector("null_speed_rad_s", n=n, required=False, default=(0.0,) * n)
        _check_registry_ranges(sec, {"null_gain_per_s": (kn,), "null_speed_rad_s": ns})
        if kn * ctx.dt > 1.0:
            sec.fail(sec.key("null_gain_per_s"), f"{kn} 1/s times the control period {ctx.dt} s is above 1")
        for i, (v, m) in enumerate(zip(ns, wmax)):
            if not abs(v) < m:
                sec.fail(sec.key("null_speed_rad_s"), f"wheel {i}: |{v}| rad/s is not below its speed limit {m}")
        _check_plant_inertia(sec, ctx, axes, js)
        return WheelsConfig(axes, js, umax, wmax, b, c, eps, noise, tuple(s0), failed, tn, tq, array,
                            kn, tuple(float(v) for v in ns), fs)

    def __init__(self, config: WheelsConfig, body):
        super().__init__(config, body)
        self.n = n = config.n
        self.state_size = n
        self.g = config.axes
        self.js = config.spin_inertia_kg_m2
        self.umax = config.torque_limit_nm
        self.wmax = config.speed_limit_rad_s
        self.b, self.c, self.eps = config.viscous_nms, config.coulomb_nm, config.coulomb_width_rad_s
        self.failed = frozenset(config.failed)
        g = self.g
        #: per wheel (axis in B, spin inertia, speed limit): derivative()'s loop
        self._wheel_rows = tuple((gi[0], gi[1], gi[2], j, m) for gi, j, m in zip(g, self.js, self.wmax))
        #: per wheel (torque limit, failed at t = 0): command_wheels()'s loop
        self._limits = tuple((m, i in self.failed) for i, m in enumerate(self.umax))
        self.inertia_offset = tuple(sum(self.js[k] * g[k][i] * g[k][j] for k in range(n))
                                    for i in range(3) for j in range(3))
        self.J = tuple(float(v) for v in body.inertia)   # total inertia (with the wheels), row-major
        self.dt = float(body.dt)
        self.w0 = tuple(body.w0) if body.w0 is not None else ZERO3
        self.noise = NormalStream(body.seed, "wheel_torque", config.torque_noise_nm, width=n) \
            if config.torque_noise_nm > 0.0 else None
        self.c_body = ZERO3              # the body torque the flight software commanded (truth)
        self.u_cmd = (0.0,) * n          # wheel torque command of the period, N m
        self.u = (0.0,) * n              # motor torque held over the period (after limit, noise, failure)
        self.at_torque_limit = (False,) * n
        self.at_speed_limit = [False] * n   # set when a stage of the last period cut the motor
        self._h0 = (0.0,) * n
        self._applied = ZERO3
        self.command_fields = {U_BODY: 3, U_WHEELS: n}
        self.fault_model = None          # injected faults (aocs_plant.faults.wheels), set by faults.attach
        self.u_motor = self.u            # the motor torques before the injected faults

    def initial_state(self) -> tuple:
        """h_i = Js_i (g_i . w0 + Omega_i(0)): the wheel speeds are given relative to the body."""
        w = self.w0
        return tuple(self.js[i] * (self.g[i][0] * w[0] + self.g[i][1] * w[1] + self.g[i][2] * w[2]
                                   + self.config.speed0_rad_s[i]) for i in range(self.n))

    # ---------------------------------------------------------------- command (zero-order hold)
    def command(self, cmd) -> None:
        u_s = cmd.get(U_WHEELS)
        if u_s is not None:
            self.command_wheels(u_s)
        c = cmd.get(U_BODY)
        if c is not None:
            self.c_body = (float(c[0]), float(c[1]), float(c[2]))

    def command_wheels(self, u_s) -> None:
        """The flight software's wheel torque commands (N m, one per wheel) for this period."""
        u_s = tuple(float(v) for v in u_s)
        if len(u_s) != self.n:
            raise ValueError(f"{len(u_s)} wheel torques for {self.n} wheels")
        self.u_cmd = u_s
        # v clipped to [-m, m] (min(m, max(-m, v)) for the finite values Plant.apply lets through), plus the noise;
        # a failed wheel's motor gives nothing: per wheel (m, failed) built once (_limits)
        nz = self.noise.next() if self.noise is not None else None
        out = []
        for i, (v, (m, dead)) in enumerate(zip(u_s, self._limits)):
            lim = m if v > m else (-m if v < -m else v)
            if nz is not None:
                lim += nz[i]
            out.append(0.0 if dead else lim)
        self.u = self.u_motor = tuple(out)
        self.at_torque_limit = tuple([abs(v) >= m for v, (m, _) in zip(u_s, self._limits)])

    # ---------------------------------------------------------------- dynamics
    def speeds(self, body, h) -> tuple:
        """Omega_i = h_i / Js_i - g_i . w (rad/s, relative to the body)."""
        w1, w2, w3 = body[4], body[5], body[6]
        return tuple([hi / js - (g0 * w1 + g1 * w2 + g2 * w3) for hi, (g0, g1, g2, js, _) in zip(h, self._wheel_rows)])

    def axial_torques(self, om) -> tuple:
        """tau_i = u_i - f_i(Omega_i), the motor cut when it would drive |Omega_i| beyond the limit."""
        if self.fault_model is not None:
            return self.fault_model.axial_torques(self, om)
        tanh = math.tanh
        b, c, eps = self.b, self.c, self.eps
        out = []
        for i in range(self.n):
            u = self.u[i]
            o = om[i]
            if u * o > 0.0 and abs(o) >= self.wmax[i]:
                u = 0.0
                self.at_speed_limit[i] = True
            out.append(u - (b * o + c * tanh(o / eps)))
        return tuple(out)

    def derivative(self, t, body, x):
        """(-(w x Gs h) - Gs tau, tau): the wheels' reaction on the body and dh/dt = tau, with tau =
        axial_torques(speeds(body, h)). The two fused into one loop (the same expressions in the same order,
        bit for bit; no intermediate tuples): four times per RK4 substep, the plant's hot path with wheels.
        With injected faults the axial torques are the fault model's (aocs_plant.faults.wheels)."""
        if self.fault_model is not None:
            return self._derivative_composed(body, x)
        w1, w2, w3 = body[4], body[5], body[6]
        b, c, eps, tanh = self.b, self.c, self.eps, math.tanh
        u_held, at_limit = self.u, self.at_speed_limit
        hx = hy = hz = 0.0
        gx = gy = gz = 0.0
        tau = []
        for i, (g0, g1, g2, js, wmax) in enumerate(self._wheel_rows):
            h = x[i]
            o = h / js - (g0 * w1 + g1 * w2 + g2 * w3)          # speeds()
            u = u_held[i]
            if u * o > 0.0 and abs(o) >= wmax:                    # axial_torques()
                u = 0.0
                at_limit[i] = True
            ti = u - (b * o + c * tanh(o / eps))
            tau.append(ti)
            hx += g0 * h
            hy += g1 * h
            hz += g2 * h
            gx += g0 * ti
            gy += g1 * ti
            gz += g2 * ti
        return (-(w2 * hz - w3 * hy) - gx, -(w3 * hx - w1 * hz) - gy, -(w1 * hy - w2 * hx) - gz), tuple(tau)

    def compiled_general(self):
        """("wheels", rows (g0, g1, g2, Js, Omega_max), b, c, Omega_eps): derivative() compiled (kernels.py)."""
        return ("wheels", self._wheel_rows, self.b, self.c, self.eps)

    def compiled_input(self):
        """The motor torques held over the period; None under an injected fault model (its own axial torques)."""
        return self.u if self.fault_model is None else None

    def speed_limit_cut(self, bits: int) -> None:
        """The compiled kernel's report: wheel i's motor was cut at its speed limit in a stage (bit i)."""
        for i in range(self.n):
            if bits >> i & 1:
                self.at_speed_limit[i] = True

    def _derivative_composed(self, body, x):
        """derivative() through speeds() and axial_torques() (which hands the torques to a fault model)."""
        tau = self.axial_torques(self.speeds(body, x))
        w1, w2, w3 = body[4], body[5], body[6]
        hx = hy = hz = 0.0
        gx = gy = gz = 0.0
        for i, (g0, g1, g2, _js, _wmax) in enumerate(self._wheel_rows):
            hx += g0 * x[i]
            hy += g1 * x[i]
            hz += g2 * x[i]
            gx += g0 * tau[i]
            gy += g1 * tau[i]
            gz += g2 * tau[i]
        return (-(w2 * hz - w3 * hy) - gx, -(w3 * hx - w1 * hz) - gy, -(w1 * hy - w2 * hx) - gz), tau

    def begin_period(self, t, x) -> None:
        self._h0 = x
        self.at_speed_limit = [False] * self.n
        fm = self.fault_model
        if fm is not None:
            fm.begin(t)
            self.u = fm.motor(self.u_motor)

    def end_period(self, t, x) -> None:
        """The mean axial torque over the period is exactly (h(t+dt) - h(t)) / dt (RK4 sums its stages
        linearly); its reaction -Gs tau_mean is what the wheels applied to the body."""
        g, dt, h0 = self.g, self.dt, self._h0
        ax = ay = az = 0.0
        for i in range(self.n):
            m = (x[i] - h0[i]) / dt
            ax -= g[i][0] * m
            ay -= g[i][1] * m
            az -= g[i][2] * m
        self._applied = (ax, ay, az)

    # ---------------------------------------------------------------- truth
    def total_momentum(self, body, x, speeds=None) -> tuple:
        """H = J w + sum Js_i g_i Omega_i = J_b w + Gs h, B components (N m s); speeds: speeds(body, x) when the
        caller has them."""
        J = self.J
        w1, w2, w3 = body[4], body[5], body[6]
        om = self.speeds(body, x) if speeds is None else speeds
        H0 = J[0] * w1 + J[1] * w2 + J[2] * w3
        H1 = J[3] * w1 + J[4] * w2 + J[5] * w3
        H2 = J[6] * w1 + J[7] * w2 + J[8] * w3
        for (g0, g1, g2, js, _), o in zip(self._wheel_rows, om):
            H0 += js * g0 * o
            H1 += js * g1 * o
            H2 += js * g2 * o
        return (H0, H1, H2)

    @property
    def commanded(self) -> tuple:
        return self.c_body

    @property
    def applied(self) -> tuple:
        return self._applied

    #: the fields of truth_fields(), in order
    TRUTH_FIELDS = ("speed_rad_s", "momentum_nms", "motor_torque_nm", "torque_cmd_nm", "at_torque_limit",
                    "at_speed_limit", "momentum_total_nms")

    def truth_fields(self, body, x) -> tuple:
        """The values of TRUTH_FIELDS now, as a tuple (truth_t's wheel fields are packed from it at every tick)."""
        om = self.speeds(body, x)
        return (om, tuple(x), self.u, self.u_cmd, self.at_torque_limit, tuple(self.at_speed_limit),
                self.total_momentum(body, x, om))

    def truth(self, t, body, x) -> dict:
        return dict(zip(self.TRUTH_FIELDS, self.truth_fields(body, x)))
