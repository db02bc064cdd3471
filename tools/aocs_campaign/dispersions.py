"""Dispersions of a Monte Carlo campaign (SPEC 5.4): what varies from run to run.

A dispersion is `KEY=DIST`, KEY being any scenario key that `aocs run --set`
takes (aocs_runner.scenario_opts: one source of truth for what a key is),
optionally one element of a vector or matrix, DIST one of

    normal:MEAN:SIGMA     Gaussian, standard deviation SIGMA >= 0
    uniform:LO:HI         uniform on [LO, HI], LO <= HI
    integer:LO:HI         a uniform integer in [LO, HI] (both integers): the
                          scenario's noise `seed`, so that each run draws
                          its own sensor noise and disturbance realisation
    rotation:SIGMA_DEG    a rotation of uniformly random axis and angle
                          N(0, SIGMA_DEG) degrees, applied to an attitude
                          (plant.euler321_deg, plant.quaternion, plant.rho,
                          plant.sigma) or to a 3-vector (a disturbance
                          direction: the magnitude is kept)

    plant.w0=normal:0:1e-4             every element, each drawn on its own
    plant.w0[1]=normal:0:1e-4          one element (0-based)
    plant.inertia[0][0]=normal:2059.5:20
    plant.inertia[0][1]=normal:0:5     a cross product: J[0][1] and J[1][0] together
    disturbances.constant_torque.scale=uniform:0.5:1.5
    plant.euler321_deg=rotation:1.0
    seed=integer:0:4294967295          each run its own noise realisation

Values are a pure function of (campaign seed, run index, key): each
dispersion draws from its own numpy Generator seeded by
SeedSequence(seed, spawn_key=(index, crc32(key))), so adding or removing a
dispersion does not change the values of the others.

Inertia: the dispersed matrix must stay symmetric positive definite and
physically valid (each principal moment below the sum of the other two). A
draw that is not is RESAMPLED (the next draw of the same run's stream, up to
MAX_INERTIA_DRAWS), so the inertia distribution is the given one truncated
to the physical set; when no valid draw comes within the bound the campaign
refuses to start, naming the key.
"""
from __future__ import annotations

import copy
import math
import re
import zlib
from dataclasses import dataclass

import numpy as np

from aocs_core.conventions import (
    crp_to_quat,
    euler321_deg_to_quat,
    mrp_to_quat,
    quat_from_axis_angle,
    quat_mul,
    quat_rotate,
    quat_to_crp,
    quat_to_euler321,
    quat_to_mrp,
)
from aocs_runner import scenario_opts

KINDS = ("normal", "uniform", "integer", "rotation")
#: draws of one run's inertia stream before the campaign refuses (docs/campaigns.md)
MAX_INERTIA_DRAWS = 100
#: attitude representations of a scenario (aocs_plant.scenario ATTITUDE_INPUTS)
ATTITUDE_KEYS = ("euler321_deg", "quaternion", "rho", "sigma")
INERTIA_KEY = "plant.inertia"

_KEY_RE = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*)((?:\[\d+\])*)$")


class DispersionError(ValueError):
    """A dispersion that cannot be honoured; the message names the key."""


@dataclass(frozen=True)
class Dispersion:
    text: str            # as given: KEY=DIST
    key: str             # dotted scenario key
    index: tuple         # element indices ((), (i,), (i, j))
    kind: str            # normal | uniform | integer | rotation
    params: tuple        # (mean, sigma) | (lo, hi) | (lo, hi) integers | (sigma_deg,)

    @property
    def name(self) -> str:
        """Key with its element, e.g. plant.w0[1] (a column of the results)."""
        return self.key + "".join(f"[{i}]" for i in self.index)


def _number(text: str, what: str, spec: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise DispersionError(f"--disperse {spec}: {what} {text!r} is not a number") from None
    if not math.isfinite(v):
        raise DispersionError(f"--disperse {spec}: {what} {text!r} is not finite")
    return v


#: the range of an integer draw (numpy's integers on int64)
INTEGER_RANGE = (-2 ** 63, 2 ** 63 - 2)


def _integer(text: str, what: str, spec: str) -> int:
    try:
        v = int(text, 10)
    except ValueError:
        raise DispersionError(f"--disperse {spec}: {what} {text!r} is not an integer") from None
    if not INTEGER_RANGE[0] <= v <= INTEGER_RANGE[1]:
        raise DispersionError(f"--disperse {spec}: {what} {text} is beyond a 64-bit integer")
    return v


def parse(spec: str) -> Dispersion:
    """KEY=DIST -> Dispersion; DispersionError (naming the key) on anything malformed."""
    if "=" not in spec:
        raise DispersionError(f"--disperse {spec!r}: expected KEY=DIST (DIST normal:MEAN:SIGMA, uniform:LO:HI, "
                              "integer:LO:HI or rotation:SIGMA_DEG)")
    key_text, dist = (s.strip() for s in spec.split("=", 1))
    m = _KEY_RE.match(key_text)
    if not m:
        raise DispersionError(f"--disperse {spec}: {key_text!r} is not a scenario key (dotted name, optional "
                              "[i] or [i][j])")
    key = m.group(1)
    index = tuple(int(i) for i in re.findall(r"\[(\d+)\]", m.group(2)))
    parts = dist.split(":")
    kind = parts[0]
    if kind not in KINDS:
        raise DispersionError(f"--disperse {spec}: unknown distribution {kind!r} (one of {', '.join(KINDS)})")
    want = {"normal": 2, "uniform": 2, "integer": 2, "rotation": 1}[kind]
    if len(parts) != want + 1:
        form = {"normal": "normal:MEAN:SIGMA", "uniform": "uniform:LO:HI", "integer": "integer:LO:HI",
                "rotation": "rotation:SIGMA_DEG"}[kind]
        raise DispersionError(f"--disperse {spec}: expected {form}")
    names = {"normal": ("mean", "sigma"), "uniform": ("lo", "hi"), "integer": ("lo", "hi"),
             "rotation": ("sigma_deg",)}[kind]
    if kind == "integer":
        params = tuple(_integer(p, n, spec) for p, n in zip(parts[1:], names))
        if params[0] > params[1]:
            raise DispersionError(f"--disperse {spec}: lo {params[0]} is above hi {params[1]}")
        return Dispersion(spec, key, index, kind, params)
    params = tuple(_number(p, n, spec) for p, n in zip(parts[1:], names))
    if kind == "normal" and params[1] < 0:
        raise DispersionError(f"--disperse {spec}: sigma {params[1]!r} is negative")
    if kind == "uniform" and params[0] > params[1]:
        raise DispersionError(f"--disperse {spec}: lo {params[0]!r} is above hi {params[1]!r}")
    if kind == "uniform" and not math.isfinite(params[1] - params[0]):
        raise DispersionError(f"--disperse {spec}: hi - lo is not finite (the range overflows a double)")
    if kind == "normal" and not (math.isfinite(params[0] + 10.0 * params[1])
                                 and math.isfinite(params[0] - 10.0 * params[1])):
        raise DispersionError(f"--disperse {spec}: draws beyond 10 sigma are not finite (they overflow a double)")
    if kind == "rotation":
        if params[0] < 0:
            raise DispersionError(f"--disperse {spec}: sigma_deg {params[0]!r} is negative")
        if index:
            raise DispersionError(f"--disperse {spec}: a rotation applies to a whole attitude or 3-vector, "
                                  "not to one element")
    return Dispersion(spec, key, index, kind, params)


def parse_all(specs) -> list[Dispersion]:
    out = [parse(s) for s in specs or ()]
    seen = {}
    for d in out:
        if d.name in seen:
            raise DispersionError(f"--disperse {d.text}: {d.name} is dispersed twice (also {seen[d.name]})")
        seen[d.name] = d.text
    for d in out:
        # a whole-vector dispersion and one of its elements would overwrite each other
        if d.index and d.key in seen:
            raise DispersionError(f"--disperse {d.text}: {d.key} is also dispersed as a whole ({seen[d.key]})")
    return out


# --------------------------------------------------------------------------- nominal values
def _get(doc: dict, key: str):
    node = doc
    for p in key.split("."):
        if not isinstance(node, dict) or p not in node:
            return None
        node = node[p]
    return node


def _is_number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def check_against(disps: list[Dispersion], doc: dict, scenario_id: str) -> None:
    """Each dispersion's key exists in the scenario document (with the campaign's --set) and has the shape
    its distribution needs; DispersionError naming the key otherwise. A scalar key the file leaves at its
    default (actuator.axis_limit) may be dispersed whole; the loader then validates the value."""
    for d in disps:
        v = _get(doc, d.key)
        where = f"--disperse {d.text}"
        if d.kind == "rotation":
            if v is None:
                raise DispersionError(f"{where}: scenario {scenario_id} has no {d.key} to rotate")
            if not (isinstance(v, list) and all(_is_number(x) for x in v)):
                raise DispersionError(f"{where}: {d.key} is not a vector")
            leaf = d.key.rsplit(".", 1)[-1]
            attitude = d.key.startswith(("plant.", "target.")) and leaf in ATTITUDE_KEYS
            if not attitude and len(v) != 3:
                raise DispersionError(f"{where}: a rotation applies to an attitude ({', '.join(ATTITUDE_KEYS)}) "
                                      f"or a 3-vector; {d.key} has {len(v)} elements")
            continue
        if v is None:
            if d.index:
                raise DispersionError(f"{where}: scenario {scenario_id} has no {d.key} (give it with --set)")
            continue  # a scalar at its default: validated by the loader
        node = v
        for depth, i in enumerate(d.index):
            if not isinstance(node, list) or i >= len(node):
                raise DispersionError(f"{where}: {d.key}{''.join(f'[{j}]' for j in d.index[:depth + 1])} "
                                      "does not exist")
            node = node[i]
        if _is_number(node):
            continue
        if isinstance(node, list) and node and all(_is_number(x) for x in node):
            continue
        raise DispersionError(f"{where}: {d.name} is not a number or a vector of numbers")
    inertia = [d for d in disps if d.key == INERTIA_KEY]
    for d in inertia:
        if len(d.index) not in (0, 2):
            raise DispersionError(f"--disperse {d.text}: disperse the inertia per element, plant.inertia[i][j]")


# --------------------------------------------------------------------------- draws
def generator(seed: int, index: int, name: str) -> np.random.Generator:
    """The stream of one dispersion in one run: a pure function of (seed, index, key)."""
    return np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=(int(index), zlib.crc32(name.encode()))))


def _draw(d: Dispersion, rng: np.random.Generator) -> float | int:
    if d.kind == "normal":
        return float(d.params[0] + d.params[1] * rng.standard_normal())
    if d.kind == "integer":   # inclusive of hi; an int, so that the repeat command's --set reads back an integer
        return int(rng.integers(d.params[0], d.params[1], endpoint=True))
    return float(rng.uniform(d.params[0], d.params[1]))


def random_rotation(rng: np.random.Generator, sigma_deg: float):
    """dq of uniformly random axis (normalised Gaussian 3-vector) and angle N(0, sigma_deg) deg."""
    a = rng.standard_normal(3)
    n = float(np.linalg.norm(a))
    axis = (1.0, 0.0, 0.0) if n == 0.0 else tuple(float(x) / n for x in a)
    angle = math.radians(float(sigma_deg) * float(rng.standard_normal()))
    return quat_from_axis_angle(axis, angle)


_TO_Q = {"euler321_deg": euler321_deg_to_quat, "rho": crp_to_quat, "sigma": mrp_to_quat,
         "quaternion": lambda v: tuple(float(x) for x in v)}


def _from_q(leaf: str, q):
    if q[3] < 0.0:
        q = tuple(-x for x in q)   # same attitude, the short representation (|sigma| <= 1, finite rho)
    if leaf == "euler321_deg":
        return [math.degrees(a) for a in quat_to_euler321(q)]
    if leaf == "rho":
        return list(quat_to_crp(q))
    if leaf == "sigma":
        return list(quat_to_mrp(q))
    return list(q)


def _rotate(d: Dispersion, nominal, rng):
    dq = random_rotation(rng, d.params[0])
    leaf = d.key.rsplit(".", 1)[-1]
    if leaf in ATTITUDE_KEYS and d.key.startswith(("plant.", "target.")):
        return _from_q(leaf, quat_mul(dq, _TO_Q[leaf](nominal)))   # q' = dq (x) q0 (SPEC 1 product)
    return [float(x) for x in quat_rotate(dq, nominal)]            # a direction: same magnitude


def inertia_problem(J) -> str | None:
    """Why a 3x3 matrix is not a physical inertia, or None (symmetric, positive definite, triangle rule)."""
    a = np.asarray(J, float)
    if a.shape != (3, 3) or not np.all(np.isfinite(a)):
        return "not a finite 3x3 matrix"
    if not np.array_equal(a, a.T):
        return "not symmetric"
    eig = np.linalg.eigvalsh(a)
    if eig[0] <= 0.0:
        return f"not positive definite (principal moments {eig.tolist()})"
    s = float(np.sum(eig))
    for e in eig:
        if not e < s - e:
            return f"principal moment {float(e)!r} is not below the sum of the other two {eig.tolist()}"
    return None


def sample(disps: list[Dispersion], doc: dict, seed: int, index: int) -> tuple[dict, dict]:
    """(overrides, inputs) of run `index`: overrides {dotted key: whole value} for the loader (and the
    repeat command), inputs {name: drawn value} for the results table (one column per scalar)."""
    overrides: dict = {}
    inputs: dict = {}
    work = {}  # key -> value being built (a deep copy of the nominal)
    for d in disps:
        if d.key == INERTIA_KEY:
            continue
        rng = generator(seed, index, d.name)
        nominal = _get(doc, d.key)
        if d.kind == "rotation":
            value = _rotate(d, nominal, rng)
            overrides[d.key] = value
            for i, x in enumerate(value):
                inputs[f"{d.key}[{i}]"] = x
            continue
        if not d.index and isinstance(nominal, list):
            value = [_draw(d, rng) for _ in nominal]
            overrides[d.key] = value
            for i, x in enumerate(value):
                inputs[f"{d.key}[{i}]"] = x
            continue
        x = _draw(d, rng)
        inputs[d.name] = x
        if not d.index:
            overrides[d.key] = x
            continue
        v = work.setdefault(d.key, copy.deepcopy(nominal))
        node = v
        for i in d.index[:-1]:
            node = node[i]
        node[d.index[-1]] = x
        overrides[d.key] = v
    inertia = [d for d in disps if d.key == INERTIA_KEY]
    if inertia:
        J, drawn = _inertia(inertia, _get(doc, INERTIA_KEY), seed, index)
        overrides[INERTIA_KEY] = J
        inputs.update(drawn)
    return overrides, inputs


def _inertia(disps: list[Dispersion], nominal, seed: int, index: int):
    """The dispersed inertia: J[i][j] and J[j][i] from one draw, resampled until physical."""
    rngs = [generator(seed, index, d.name) for d in disps]
    why = None
    for _ in range(MAX_INERTIA_DRAWS):
        J = [[float(x) for x in row] for row in nominal]
        drawn = {}
        for d, rng in zip(disps, rngs):
            i, j = d.index
            x = _draw(d, rng)
            J[i][j] = x
            J[j][i] = x
            drawn[d.name] = x
        why = inertia_problem(J)
        if why is None:
            return J, drawn
    names = ", ".join(d.name for d in disps)
    raise DispersionError(f"--disperse {names}: run {index}: no physical inertia in {MAX_INERTIA_DRAWS} draws "
                          f"(last: {why}); narrow the dispersion")


def set_args(overrides: dict) -> list[str]:
    """The overrides as `--set KEY=VALUE` words, numbers written with repr (they read back bit-identical)."""
    return scenario_opts.to_args(overrides)
