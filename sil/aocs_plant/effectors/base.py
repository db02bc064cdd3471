"""The effector interface: one disturbance or actuator acting on the plant (docs/extending.md).

An effector is one module in this package. It owns

- its scenario section (`[disturbances.<kind>]`, or a top-level table such as
  `[actuator]`): `read(sec, ctx)` parses and validates it and returns a frozen
  config; errors go through `sec.fail(key, what)`, so they name file and key;
- its contribution to the body equation (a torque on the attitude plant, a
  force on the orbit plant), evaluated in one of the `Form`s below, the
  cheapest that fits: the integrator folds constants once, calls attitude-only
  closures at every RK4 stage, and integrates GENERAL effectors (the only ones
  with state) together with the body in one RK4 over the concatenated state;
- its own state vector where it has one (`state_size`, `initial_state()`,
  the derivative returned by `derivative()`);
- its truth fields (`truth()`: names and values for Plant.truth()).

The plant never names an effector: it builds them from the scenario through
the registry (`register`, `REGISTRY`) and composes them by form.
"""
from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Callable, ClassVar, Mapping

ATTITUDE = "attitude"
ORBIT = "orbit"
ZERO3 = (0.0, 0.0, 0.0)


class Form:
    """How the integrator evaluates an effector's contribution (cheapest first)."""

    CONSTANT = "constant"  # value() once, at construction: folded into one constant torque / force
    HELD = "held"          # value() once per control period, after the command (zero-order hold)
    ATTITUDE = "attitude"  # term(): closure (q1, q2, q3, q4) -> torque, at every RK4 stage (attitude plant)
    GENERAL = "general"    # derivative(t, body, x) -> (torque or force, xdot) at every RK4 stage
    DISCRETE = "discrete"  # no continuous contribution, only jumps at event_times()


FORMS = (Form.CONSTANT, Form.HELD, Form.ATTITUDE, Form.GENERAL, Form.DISCRETE)


@dataclass(frozen=True)
class ReadContext:
    """What a section reader may check its keys against."""

    file: str
    kind: str            # "attitude" | "orbit"
    duration_s: float
    dt: float            # control period, s
    substeps: int        # RK4 steps per control period
    plant: Any           # the validated [plant] config (AttitudePlantConfig | OrbitPlantConfig)


@dataclass(frozen=True)
class BodyContext:
    """What an effector is built with."""

    kind: str                    # "attitude" | "orbit"
    dt: float
    substeps: int
    seed: int
    inertia: tuple | None = None  # row-major 9-tuple of the scenario's (total) inertia, kg m^2 (attitude)
    mass_kg: float | None = None  # orbit
    w0: tuple | None = None       # initial body rate w_BN_B, rad/s (attitude: effector states relative to it)
    environment: Any = None       # aocs_plant.environment.Environment: orbit, Sun, Earth, magnetic field at t


class Effector:
    """Base class: override what the effector's form needs; the defaults contribute nothing.

    body, everywhere below, is the body state as one tuple: (q1, q2, q3, q4, w1, w2, w3) on the
    attitude plant (SPEC 1.2, 1.6), (u, v, w, x, y, z) on the orbit plant (SPEC 2.8); x is the
    effector's own state (a tuple of state_size floats, () when it has none).
    """

    kind: ClassVar[str] = ""                   # registry key and name of the scenario section
    group: ClassVar[str | None] = "disturbances"  # parent table of the section; None: a top-level table
    applies_to: ClassVar[tuple] = (ATTITUDE,)  # plant kinds the section is valid for
    role: ClassVar[str] = "disturbance"        # "disturbance": sums into truth()["disturbance"];
    #                                            "actuator": receives the command (command())
    command_fields: Mapping[str, Any] = MappingProxyType({})   # actuators: the command fields it reads,
    #                                            {name: number of floats} (may be set per instance: the wheel
    #                                            array's "u_wheels" has one value per wheel), or {name: Mask(bits)}
    #                                            for a field that is one integer bitmask (the thrusters' latch
    #                                            valves, "thruster_latch_closed")
    conflicts: ClassVar[tuple] = ()            # kinds that must not be enabled together with this one
    replaces: ClassVar[tuple] = ()             # kinds not built when this one is (a wheel array stands in
    #                                            for the plain body-torque actuator)

    form: str = Form.CONSTANT                  # may be set per instance (e.g. the actuator with a lag)
    state_size: int = 0
    inertia_offset: tuple | None = None        # 9-tuple taken out of the scenario's inertia for the body
    #                                            equation: rotating parts whose momentum is this effector's
    #                                            state (wheels, SPEC 5.3: J_b = J - sum Js g g^T)
    time_varying: bool = False                 # ATTITUDE form: at_time(t) is called before every substep
    period_hooks: bool | None = None           # begin/end_period called? None: when the class overrides them

    # ---------------------------------------------------------------- scenario section
    @classmethod
    def section(cls) -> str:
        return f"{cls.group}.{cls.kind}" if cls.group else cls.kind

    @classmethod
    def read(cls, sec, ctx: ReadContext):
        """Parse and validate the section (the registry rejects the keys left over)."""
        raise NotImplementedError

    @classmethod
    def default(cls, ctx: ReadContext):
        """Config when the section is absent; None means the effector is not built."""
        return None

    @staticmethod
    def active(config) -> bool:
        return bool(getattr(config, "enabled", True))

    def __init__(self, config, body: BodyContext):
        self.config = config
        self.plant_kind = body.kind

    # ---------------------------------------------------------------- contribution, by form
    def value(self) -> tuple:
        """CONSTANT (read once) and HELD (read at every period start): the torque or force."""
        return ZERO3

    def term(self) -> Callable:
        """ATTITUDE: closure (q1, q2, q3, q4) -> (tx, ty, tz), built once."""
        raise NotImplementedError

    def at_time(self, t: float) -> None:
        """ATTITUDE with time_varying: freeze the time dependence at t (the substep midpoint)."""

    def compiled_term(self) -> tuple | None:
        """ATTITUDE: the term as the compiled rigid-body kernel takes it, or None when it has no compiled form
        (then the plant integrates with its Python stepper). Today one kind: a gravity gradient about a fixed
        direction, ("gravity_gradient", c, (d1, d2, d3), J): the term() closure c (R x J R), R = A(q) d."""
        return None

    def compiled_general(self) -> tuple | None:
        """GENERAL: the effector as the compiled coupled kernel takes it (kernels.CoupledKernel), or None when it
        has no compiled form (the plant then integrates with rk4_coupled_stepper)."""
        return None

    def compiled_input(self) -> tuple | None:
        """GENERAL with a compiled form: what its derivative holds over this period (read after begin_period),
        or None when this period cannot be compiled (the Python stepper runs it)."""
        return None

    def initial_state(self) -> tuple:
        return ()

    def derivative(self, t: float, body: tuple, x: tuple) -> tuple:
        """GENERAL: ((torque or force on the body), xdot) at time t and the full state."""
        raise NotImplementedError

    # ---------------------------------------------------------------- control period, events
    def command(self, cmd: Mapping[str, tuple]) -> None:
        """Actuators: the command of the period (Plant.apply), held over it. cmd maps field names to
        tuples of finite floats (a Mask field: to one int in its range), checked against every actuator's
        command_fields; an actuator reads its own fields and keeps its held value for a field the command
        does not carry."""

    def begin_period(self, t: float, x: tuple) -> None:
        """Before a control period is integrated (called only when overridden)."""

    def end_period(self, t: float, x: tuple) -> None:
        """After a control period is integrated (called only when overridden)."""

    def event_times(self) -> tuple:
        """DISCRETE: times (s) at which jump() applies."""
        return ()

    def jump(self, t: float, body: tuple) -> tuple:
        """The body state just after the event at t."""
        return body

    # ---------------------------------------------------------------- truth
    def contribution(self, t: float, body: tuple, x: tuple) -> tuple:
        """The torque (or force) it exerts now, whatever its form."""
        f = self.form
        if f == Form.CONSTANT or f == Form.HELD:
            return self.value()
        if f == Form.ATTITUDE:
            if self.time_varying:
                self.at_time(t)
            return self.term()(body[0], body[1], body[2], body[3])
        if f == Form.GENERAL:
            return self.derivative(t, body, x)[0]
        return ZERO3

    def truth(self, t: float, body: tuple, x: tuple) -> dict:
        """Truth fields {name: value}; Plant.truth() reports them as "<kind>.<name>"."""
        return {"torque_nm" if self.plant_kind == ATTITUDE else "force_n": self.contribution(t, body, x)}

    # actuators: what Plant.truth() reports as "commanded" and "applied"
    @property
    def commanded(self) -> tuple:
        return ZERO3

    @property
    def applied(self) -> tuple:
        """GENERAL actuators: their mean output over the last control period (read after
        end_period). A HELD actuator's is the value() the plant held, reported by the plant."""
        return ZERO3


@dataclass(frozen=True)
class Mask:
    """A command field that is one integer, a bitmask of `bits` bits (0 .. 2**bits - 1), declared in
    command_fields as Mask(bits) where a field of floats gives its size. Plant.apply takes an int, or a float
    with an integral value, in range; anything else (2.5, -1, 2**bits, nan, a string, a sequence, a bool)
    refuses the whole command like a non-finite float (counters["bad_commands"])."""

    bits: int

    def value(self, v) -> int | None:
        """v as the mask, or None when it is not one."""
        top = (1 << self.bits) - 1
        if type(v) is int:                   # the common case: an int off the wire
            return v if 0 <= v <= top else None
        if isinstance(v, bool):
            return None
        if isinstance(v, numbers.Integral):  # numpy's integers
            m = int(v)
        elif isinstance(v, numbers.Real):
            f = float(v)
            if not f.is_integer():           # 2.5, nan, inf
                return None
            m = int(f)
        else:
            return None
        return m if 0 <= m <= top else None


REGISTRY: dict[str, type[Effector]] = {}


def register(cls: type[Effector]) -> type[Effector]:
    """Class decorator: make an effector kind known to the scenario loader and the plant."""
    if not cls.kind or cls.kind in REGISTRY and REGISTRY[cls.kind] is not cls:
        raise ValueError(f"effector kind {cls.kind!r} is empty or registered twice")
    REGISTRY[cls.kind] = cls
    return cls


# ---------------------------------------------------------------- section helpers


def onoff(sec) -> tuple[bool, float]:
    """`enabled` (required) and `scale` (>= 0, default 1): every disturbance has both (SPEC 3.3)."""
    return sec.boolean("enabled"), sec.number("scale", required=False, default=1.0, nonneg=True)


def unit_vector(sec, k: str) -> tuple:
    v = sec.vector(k)
    n = math.sqrt(sum(x * x for x in v))
    if abs(n - 1.0) > 1e-9:
        sec.fail(sec.key(k), f"must be a unit vector (norm {n!r})")
    return v
