"""The effector registry (aocs_plant/effectors/__init__.py): every module registers its kinds,
the loader accepts exactly the registered sections (one-line errors naming file and key), the
plant builds its effectors from the scenario, and no source is generated anywhere in the plant."""
import re
from pathlib import Path

import pytest

import aocs_plant
from aocs_plant import Plant, ScenarioError, load
from aocs_plant import effectors as eff

PLANT_DIR = Path(aocs_plant.__file__).resolve().parent

KINDS = {"constant_torque": "disturbances", "gravity_gradient_l2": "disturbances",
         "gravity_gradient_earth": "disturbances", "srp_torque": "disturbances", "srp_force": "disturbances",
         "impulse": "disturbances", "actuator": None}


def test_every_module_registers_its_kinds():
    assert {k: c.group for k, c in eff.REGISTRY.items()} == KINDS
    modules = {p.stem for p in (PLANT_DIR / "effectors").glob("*.py")} - {"__init__", "base"}
    assert modules == {c.__module__.rsplit(".", 1)[1] for c in eff.REGISTRY.values()}
    for kind, cls in eff.REGISTRY.items():
        assert cls.kind == kind and set(cls.applies_to) <= {"attitude", "orbit"} and cls.applies_to
        assert cls.role in ("disturbance", "actuator")
        assert cls.section() == (f"disturbances.{kind}" if cls.group else kind)


def test_register_refuses_a_kind_twice():
    class Other(eff.Effector):
        kind = "constant_torque"
    with pytest.raises(ValueError, match="registered twice"):
        eff.register(Other)


def _error(overrides) -> str:
    with pytest.raises(ScenarioError) as err:
        load("irassi_large", overrides)
    return str(err.value)


def test_an_unknown_effector_section_is_one_line_naming_file_and_key():
    file = str(load("irassi_large").path)
    msg = _error({"disturbances.magnetic_dipole": {"enabled": True}})
    assert "\n" not in msg
    assert msg.startswith(f"{file}: disturbances.magnetic_dipole: unknown key (known disturbances: constant_torque, ")
    assert "gravity_gradient_l2" in msg and "actuator" not in msg
    # a top-level table nobody registered is an unknown key of the file, as before
    assert _error({"reaction_wheels": {"count": 4}}) == f"{file}: reaction_wheels: unknown key"
    # and a key an effector does not know, inside its own section
    assert _error({"disturbances.constant_torque.colour": 1}) == f"{file}: disturbances.constant_torque.colour: unknown key"


def test_the_plant_builds_the_effectors_from_the_scenario_in_order():
    assert [e.kind for e in Plant(load("irassi_large")).effectors] == ["constant_torque", "gravity_gradient_l2",
                                                                        "actuator"]
    assert [e.kind for e in Plant(load("landsat8_debris")).effectors] == ["impulse", "actuator"]
    assert [e.kind for e in Plant(load("rtc_ex1a")).effectors] == ["actuator"]
    sc = load("irassi_large", {"disturbances.gravity_gradient_l2.enabled": False})
    assert list(sc.effectors) == ["constant_torque", "gravity_gradient_l2", "actuator"]
    assert [e.kind for e in Plant(sc).effectors] == ["constant_torque", "actuator"]


def test_disturbances_view_of_the_scenario():
    d = load("irassi_large").disturbances
    assert list(d) == ["constant_torque", "gravity_gradient_l2"] and d.srp_torque is None
    assert d.active("constant_torque") is d.constant_torque and d["gravity_gradient_l2"].enabled
    with pytest.raises(AttributeError):
        d.magnetic_dipole  # noqa: B018
    with pytest.raises(AttributeError):
        d.constant_torque = None


def test_no_generated_source_in_the_plant():
    """The RK4 step is plain closures: no exec, eval or compile of source text anywhere in the package."""
    call = re.compile(r"(?<![\w.])(exec|eval|compile)\s*\(")
    for path in sorted(PLANT_DIR.rglob("*.py")):
        for i, line in enumerate(path.read_text().splitlines(), 1):
            code = line.split("#", 1)[0]
            assert not call.search(code), f"{path.relative_to(PLANT_DIR)}:{i}: {line.strip()}"
    assert not call.search("re.compile(x)") and call.search("exec(src)")  # the pattern itself
