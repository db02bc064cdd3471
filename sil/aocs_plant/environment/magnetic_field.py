"""The slot of a geomagnetic field model (`[environment.magnetic_field] model`).

A model is a class with field_n_t(jd, r_n_m) -> the field (tesla, Earth-centred inertial frame) at
the spacecraft, registered in MODELS under its scenario name. Today there is only "none": no field
(None), which is what a magnetometer or a magnetorquer must treat as "no model". A later issue adds
IGRF (the ppigrf package) as one more class here.
"""
from __future__ import annotations


class NoField:
    """No magnetic field model: every query answers None."""

    name = "none"

    def field_n_t(self, jd: float, r_n_m):
        return None


MODELS = {NoField.name: NoField}
