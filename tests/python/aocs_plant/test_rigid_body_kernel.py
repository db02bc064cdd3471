"""The compiled rigid-body kernel (sil/plant_kernels/rigid_body_kernel.c) against the Python stepper it replaces.

The Python stepper (rigid_body.rk4_stepper over body_derivative, with gravity_gradient.gg_term) is the
independent model here: the kernel must give the same doubles, bit for bit, for any inertia (diagonal or
not), gravity gradient (none, diagonal or full inertia), substep count and state, and a whole plant must fly
the same period for period whichever stepper runs. The build of the tests (AOCS_BUILD_DIR) must hold the
kernel: a missing one fails here instead of silently slowing every run.
"""
import math
import random

import numpy as np
import pytest

from aocs_core import compiled
from aocs_plant import kernels
from aocs_plant.effectors.gravity_gradient import gg_term, l2_gg_coefficient
from aocs_plant.plant import Plant
from aocs_plant.rigid_body import _mat9, body_derivative, rk4_stepper
from aocs_plant.scenario import load


@pytest.fixture(scope="module")
def kernel(aocs_build_dir):  # noqa: ARG001 - the build the module is loaded from
    mod = kernels.module()
    assert mod is not None, (f"{kernels.RIGID_BODY} not built in {aocs_build_dir}/lib (cmake --build --preset host), "
                             f"or {kernels.ENV}=python is set")
    return mod


def _inertia(rng, diagonal):
    if diagonal:
        return np.diag(rng.uniform(10.0, 6000.0, 3))
    a = rng.normal(size=(3, 3))
    return a @ a.T * rng.uniform(10.0, 1000.0) + np.eye(3) * 5.0


def _unit(rng, n):
    v = rng.normal(size=n)
    return tuple(float(x) for x in v / np.linalg.norm(v))


def _python_period(J9, Ji9, gg, q, w, h, n, torque):
    term = None if gg is None else gg_term(gg[2], gg[0], gg[1])[0]
    step = rk4_stepper(body_derivative(J9, Ji9, term))
    for _ in range(n):
        q, w = step(q, w, h, torque)
    return q, w


@pytest.mark.parametrize("diagonal", [True, False])
@pytest.mark.parametrize("gg_kind", [None, "diagonal", "full"])
def test_kernel_period_is_the_python_period_bit_for_bit(kernel, diagonal, gg_kind):
    rng = np.random.default_rng(2024 + 7 * diagonal + len(gg_kind or ""))
    for case in range(60):
        J = _inertia(rng, diagonal)
        J9, Ji9 = _mat9(J), tuple(np.linalg.inv(J).ravel().tolist())
        gg = None
        if gg_kind is not None:
            Jg = _mat9(_inertia(rng, gg_kind == "diagonal"))
            # coefficients from the L2 value up to a fast LEO orbit's 3 n^2, so that the term shows in the result
            gg = (float(rng.choice([l2_gg_coefficient(), 3.0 * 1.1e-3 ** 2, 1e-2])), _unit(rng, 3), Jg)
        q, w = _unit(rng, 4), tuple(float(x) for x in rng.normal(scale=0.05, size=3))
        torque = tuple(float(x) for x in rng.normal(scale=2.0, size=3))
        h, n = float(rng.uniform(1e-3, 0.5)), int(rng.integers(1, 6))
        want = _python_period(J9, Ji9, gg, q, w, h, n, torque)
        got = kernel.Stepper(J9, Ji9, gg).period(q, w, h, n, torque)
        assert [v.hex() for v in got[0] + got[1]] == [v.hex() for v in want[0] + want[1]], (case, J9, gg)


def test_kernel_keeps_non_finite_values_as_python_does(kernel):
    J9, Ji9 = _mat9(np.diag([2.0, 3.0, 4.0])), _mat9(np.diag([0.5, 1 / 3, 0.25]))
    q, w = (0.0, 0.0, 0.0, 1.0), (math.nan, 0.0, 0.0)
    want = _python_period(J9, Ji9, None, q, w, 0.1, 2, (0.0, 0.0, 0.0))
    got = kernel.Stepper(J9, Ji9).period(q, w, 0.1, 2, (0.0, 0.0, 0.0))
    assert all(math.isnan(v) for v in want[0] + want[1])
    assert all(math.isnan(v) for v in got[0] + got[1])
    huge = kernel.Stepper(J9, Ji9).period(q, (1e300, 1e300, 1e300), 0.1, 1, (1e308, 0.0, 0.0))
    assert [repr(v) for v in huge[0] + huge[1]] == \
        [repr(v) for v in sum(_python_period(J9, Ji9, None, q, (1e300,) * 3, 0.1, 1, (1e308, 0.0, 0.0)), ())]


@pytest.mark.parametrize("args, error, words", [
    (((0.0, 0.0, 1.0), (0.0,) * 3, 0.1, 1, (0.0,) * 3), ValueError, "q: 3 values, expected 4"),
    (((0.0, 0.0, 0.0, 1.0), (0.0,) * 4, 0.1, 1, (0.0,) * 3), ValueError, "w: 4 values, expected 3"),
    (((0.0, 0.0, 0.0, 1.0), (0.0,) * 3, 0.1, 1, None), TypeError, "torque"),
    (((0.0, 0.0, 0.0, "1"), (0.0,) * 3, 0.1, 1, (0.0,) * 3), TypeError, "q[3]: not a number"),
    (((0.0, 0.0, 0.0, 1.0), (0.0,) * 3, "0.1", 1, (0.0,) * 3), TypeError, "h: not a number"),
    (((0.0, 0.0, 0.0, 1.0), (0.0,) * 3, 0.1, 0, (0.0,) * 3), ValueError, "n: 0 substeps"),
    (((0.0, 0.0, 0.0, 1.0), (0.0,) * 3, 0.1, 1.5, (0.0,) * 3), TypeError, "n: not an integer"),
    (((0.0, 0.0, 0.0, 1.0), (0.0,) * 3, 0.1), TypeError, "5 arguments"),
])
def test_kernel_refuses_bad_arguments_by_name(kernel, args, error, words):
    s = kernel.Stepper((1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0), (1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0))
    with pytest.raises(error, match=words.replace("[", r"\[").replace("]", r"\]")):
        s.period(*args)


def test_kernel_refuses_a_bad_configuration(kernel):
    with pytest.raises(ValueError, match="J: 8 values, expected 9"):
        kernel.Stepper((1.0,) * 8, (1.0,) * 9)
    with pytest.raises(TypeError, match=r"gg: None or a tuple"):
        kernel.Stepper((1.0,) * 9, (1.0,) * 9, [1.0, (0.0, 0.0, 1.0), (1.0,) * 9])
    with pytest.raises(ValueError, match="gg d: 2 values"):
        kernel.Stepper((1.0,) * 9, (1.0,) * 9, (1.0, (0.0, 1.0), (1.0,) * 9))


def test_only_what_the_kernel_computes_the_same_is_compiled(kernel):  # noqa: ARG001
    J9 = (1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0)
    gg = ("gravity_gradient", 1e-6, (0.0, 0.0, 1.0), J9)
    assert kernels.rigid_body_period(J9, J9, ()) is not None
    assert kernels.rigid_body_period(J9, J9, (gg,)) is not None
    assert kernels.rigid_body_period(J9, J9, (gg, gg)) is None     # two terms: sum_terms' 0.0 + a + b
    assert kernels.rigid_body_period(J9, J9, (None,)) is None      # a term without a compiled form


def _fly(name, monkeypatch, mode, periods=1500):
    monkeypatch.setenv(kernels.ENV, mode)
    monkeypatch.setattr(compiled, "_loaded", {})
    plant = Plant(load(name))
    rng = random.Random(5)
    fields = {f: n for f, n in plant.command_fields.items() if isinstance(n, int)}
    for _ in range(periods):
        u = tuple(rng.uniform(-0.5, 0.5) for _ in range(3))
        plant.apply({f: (u if n == 3 else (0.0,) * n) for f, n in fields.items()})
        plant.advance()
    return plant


@pytest.mark.parametrize("name", ["irassi_large", "gao_mrp", "rtc_ex1a"])
def test_a_plant_flies_the_same_with_and_without_the_kernel(kernel, monkeypatch, name):  # noqa: ARG001
    compiled = _fly(name, monkeypatch, "")
    python = _fly(name, monkeypatch, "python")
    assert compiled._compiled_period is not None and python._compiled_period is None
    assert compiled.body.q == python.body.q and compiled.body.w == python.body.w
    assert compiled.truth()["pointing_arcsec"] == python.truth()["pointing_arcsec"]


# ---- the coupled period: the body with reaction wheels and thrusters (rk4_coupled_stepper) ------------------------
def _coupled_pair(name, monkeypatch):
    monkeypatch.setenv(kernels.ENV, "")
    monkeypatch.setattr(compiled, "_loaded", {})
    plant = Plant(load(name))
    assert plant._coupled_kernel is not None, name
    return plant


@pytest.mark.parametrize("name", ["irassi_rw", "irassi_day"])   # wheels alone; wheels and thrusters
def test_coupled_kernel_period_is_the_python_period_bit_for_bit(kernel, monkeypatch, name):  # noqa: ARG001
    plant = _coupled_pair(name, monkeypatch)
    wheels = plant.wheel_array
    thr = next((e for e, _, _ in plant._general if e.kind == "thrusters"), None)
    rng = np.random.default_rng(11)
    cuts = 0
    for case in range(200):
        q, w = _unit(rng, 4), tuple(float(v) for v in rng.normal(scale=0.02, size=3))
        # wheel momenta up to beyond their speed limit, motor torques up to twice their limit of either sign:
        # the stages that cut a motor at the speed limit are exercised
        x = list(plant._x)
        for i, (g0, g1, g2, js, wmax) in enumerate(wheels._wheel_rows):
            x[i] = float(js * wmax * rng.uniform(-1.2, 1.2))
        wheels.u = tuple(float(v) for v in rng.uniform(-2.0, 2.0, wheels.n) * np.array(wheels.umax))
        if thr is not None:
            on = rng.random() < 0.5
            thr.mdot = float(rng.uniform(1e-6, 1e-3)) if on else 0.0
            thr.force_b = tuple(float(v) for v in rng.normal(scale=1.0, size=3)) if on else (0.0, 0.0, 0.0)
            thr.torque_b = tuple(float(v) for v in rng.normal(scale=1.0, size=3)) if on else (0.0, 0.0, 0.0)
        x = tuple(x)
        torque = tuple(float(v) for v in rng.normal(scale=1e-3, size=3))
        h, n = float(rng.uniform(0.01, 1.0)), int(rng.integers(1, 5))
        wheels.at_speed_limit = [False] * wheels.n
        pq, pw, px = q, w, x
        for i in range(n):
            pq, pw, px = plant._coupled(pq, pw, px, i * h, h, torque)
        want_cut = list(wheels.at_speed_limit)
        wheels.at_speed_limit = [False] * wheels.n
        kq, kw, kx = plant._coupled_kernel.period(q, w, x, h, n, torque)
        assert [v.hex() for v in kq + kw + kx] == [v.hex() for v in pq + pw + px], (name, case)
        assert wheels.at_speed_limit == want_cut, (name, case)
        cuts += any(want_cut)
    assert cuts > 20   # the speed-limit branch was taken in many of the cases


def _fly_wheels(name, monkeypatch, mode, periods=900):
    monkeypatch.setenv(kernels.ENV, mode)
    monkeypatch.setattr(compiled, "_loaded", {})
    # the wheels start at 97 % of their speed limit: the pushes below reach it within seconds
    top = min(Plant(load(name)).wheel_array.wmax)
    plant = Plant(load(name, {"wheels.speed0_rad_s": 0.97 * top}))
    rng = random.Random(9)
    limits, cuts = [], 0
    for k in range(periods):
        cmd = {}
        for f, n in plant.command_fields.items():
            if f == "u_wheels":   # pushes of one sign for 100 periods, then the other: at and off the limit
                cmd[f] = tuple((0.5 if (k // 100) % 2 == 0 else -0.5) * (1 + 0.1 * rng.random()) for _ in range(n))
            elif f == "thruster_on_s":
                cmd[f] = tuple(rng.choice((0.0, 0.0, 0.0, 0.05, 0.3)) for _ in range(n))
            elif isinstance(n, int):
                cmd[f] = tuple(rng.uniform(-0.1, 0.1) for _ in range(n))
        assert plant.apply(cmd)
        plant.advance()
        limits.append(tuple(plant.wheel_array.at_speed_limit))
        cuts += any(limits[-1])
    return plant, limits, cuts


@pytest.mark.parametrize("name", ["irassi_rw", "irassi_day", "irassi_rw_failed"])
def test_a_wheel_plant_flies_the_same_with_and_without_the_coupled_kernel(kernel, monkeypatch, name):  # noqa: ARG001
    compiled, c_limits, cuts = _fly_wheels(name, monkeypatch, "")
    python, p_limits, _ = _fly_wheels(name, monkeypatch, "python")
    assert compiled._coupled_kernel is not None and python._coupled_kernel is None
    assert (compiled.body.q, compiled.body.w, compiled._x) == (python.body.q, python.body.w, python._x)
    assert c_limits == p_limits and cuts > 0
    assert compiled.effector_truth() == python.effector_truth()
    assert compiled.applied == python.applied


def test_a_wheel_fault_model_runs_the_python_period(kernel, monkeypatch):  # noqa: ARG001
    """An injected wheel fault computes its own axial torques: that period is not compiled (compiled_input None)."""
    plant = _coupled_pair("irassi_rw_wheel_dies", monkeypatch)
    assert plant.wheel_array.fault_model is not None
    assert plant._coupled_kernel.period(plant.body.q, plant.body.w, plant._x, 0.1, 1, (0.0, 0.0, 0.0)) is None


def test_the_coupled_kernel_refuses_bad_specs_and_inputs(kernel):
    J9 = (1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0)
    row = (1.0, 0.0, 0.0, 0.01, 600.0)
    with pytest.raises(ValueError, match="1 to 4 effector specs"):
        kernel.CoupledStepper(J9, J9, None, ())
    with pytest.raises(ValueError, match="7 wheels, 1 to 6"):
        kernel.CoupledStepper(J9, J9, None, (("wheels", (row,) * 7, 0.0, 0.0, 0.1),))
    with pytest.raises(ValueError, match="one wheel array at most"):
        kernel.CoupledStepper(J9, J9, None, (("wheels", (row,) * 3, 0.0, 0.0, 0.1),) * 2)
    with pytest.raises(ValueError, match=r'\("wheels", rows, b, c, eps\) or \("thrusters",\)'):
        kernel.CoupledStepper(J9, J9, None, (("magnetorquers",),))
    s = kernel.CoupledStepper(J9, J9, None, (("wheels", (row,) * 3, 0.0, 0.0, 0.1), ("thrusters",)))
    q, w = (0.0, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="x: 6 values, expected 7"):
        s.period(q, w, (0.0,) * 6, 0.1, 1, (0.0,) * 3, ((0.0,) * 3, (0.0,) * 7))
    with pytest.raises(ValueError, match=r"inputs: 1, one per effector \(2\)"):
        s.period(q, w, (0.0,) * 7, 0.1, 1, (0.0,) * 3, ((0.0,) * 3,))
    with pytest.raises(ValueError, match="thrusters .* 6 values, expected 7"):
        s.period(q, w, (0.0,) * 7, 0.1, 1, (0.0,) * 3, ((0.0,) * 3, (0.0,) * 6))


def test_a_time_varying_term_is_never_compiled(kernel, monkeypatch):  # noqa: ARG001
    """The kernel freezes its terms; geo_hinf's Earth gravity gradient moves with time (at_time before every
    substep). Even were it to offer a compiled form, the plant keeps such a period in Python."""
    from aocs_plant.effectors.gravity_gradient import GravityGradientEarth

    monkeypatch.setattr(GravityGradientEarth, "compiled_term",
                        lambda self: ("gravity_gradient", 1e-6, (0.0, 0.0, 1.0), (1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0)))
    monkeypatch.setenv(kernels.ENV, "")
    monkeypatch.setattr(compiled, "_loaded", {})
    plant = Plant(load("geo_hinf"))
    assert plant._time_varying and not plant._general
    assert plant._compiled_period is None and plant._coupled_kernel is None
