"""The multisine held at the plant input ([disturbances.input_injection], issue 22) against its formula
evaluated here: the value held over each period is the sum at the period's start, along the direction;
Schroeder's phases; the section's errors."""
from __future__ import annotations

import math

import pytest

from aocs_plant import Plant, ScenarioError, load

SECTION = "disturbances.input_injection"


def _scenario(**extra):
    ov = {"disturbances.constant_torque.enabled": False, "disturbances.gravity_gradient_l2.enabled": False,
          f"{SECTION}.enabled": True, f"{SECTION}.amplitude_nm": 0.2, f"{SECTION}.frequency_rad_s": [1.0, 3.0, 7.0],
          f"{SECTION}.direction": [0.0, 0.6, 0.8], "plant.euler321_deg": [0.0, 0.0, 0.0]}
    ov.update(extra)
    return load("irassi_large", ov)


def test_the_held_torque_is_the_multisine_at_each_period_start():
    sc = _scenario()
    cfg = sc.effectors["input_injection"]
    phases = [-math.pi * i * (i - 1) / 3 for i in (1, 2, 3)]       # Schroeder 1970
    assert cfg.phase_rad == pytest.approx(phases)
    p = Plant(sc)
    inj = next(e for e in p.effectors if e.kind == "input_injection")
    for k in range(5):
        t = k * sc.dt
        s = 0.2 * sum(math.sin(w * t + ph) for w, ph in zip((1.0, 3.0, 7.0), phases))
        p.apply({"u_body": (0.0, 0.0, 0.0)})
        p.advance()
        assert inj.value() == pytest.approx((0.0, 0.6 * s, 0.8 * s), abs=1e-15)


@pytest.mark.parametrize("extra,says", [
    ({f"{SECTION}.frequency_rad_s": [1.0, 31.5]}, "Nyquist"),
    ({f"{SECTION}.phase_rad": [0.0]}, "1 phases for 3 frequencies"),
    ({f"{SECTION}.direction": [1.0, 1.0, 0.0]}, "unit vector"),
    ({f"{SECTION}.frequency_rad_s": []}, "1 to 64"),
])
def test_section_errors_name_the_key(extra, says):
    with pytest.raises(ScenarioError, match=says):
        _scenario(**extra)
