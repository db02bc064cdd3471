"""aocs_core.modes: the executive's mode values by name, as the build's registry gives them.

Expected values come from an independent source: the wire contract's constants
(sil/lcmtypes/actuator_cmd_t.lcm and command_t.lcm, through the generated bindings).
"""
from __future__ import annotations

import pytest

from aocs_core import paths
from aocs_core.modes import mode_value, mode_values


@pytest.fixture(scope="module")
def lcm_types():
    return paths.import_bindings()


def test_mode_values_are_the_wire_contracts(lcm_types):
    for msg in (lcm_types.actuator_cmd_t, lcm_types.command_t):
        assert mode_value("standby") == msg.MODE_STANDBY
        assert mode_value("nominal") == msg.MODE_NOMINAL
        assert mode_value("safe") == msg.MODE_SAFE


def test_every_mode_in_value_order():
    assert list(mode_values()) == ["standby", "nominal", "safe"]
    assert list(mode_values().values()) == sorted(mode_values().values())


def test_an_unknown_mode_names_the_known_ones():
    with pytest.raises(KeyError, match="'cruise'.*standby, nominal, safe"):
        mode_value("cruise")
