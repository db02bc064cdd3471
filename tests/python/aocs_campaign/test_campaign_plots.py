"""The campaign plots' axis scaling (aocs_campaign.plots)."""
from __future__ import annotations

import numpy as np

from aocs_campaign.plots import _exponent


def test_small_and_large_inputs_get_a_power_of_ten_in_the_label_and_the_rest_none():
    # initial rates of 1e-4 rad/s would otherwise carry matplotlib's offset text onto the axis label
    assert _exponent(np.array([-3.3e-4, 4.5e-4])) == -4
    assert _exponent(np.array([2.1e5, 1.0])) == 5
    for plain in ([0.4, 1.7], [1841.0, 6522.0], [-67.9, 68.5], [1e-3], [9999.0], [0.0], []):
        assert _exponent(np.array(plain, dtype=float)) == 0, plain
