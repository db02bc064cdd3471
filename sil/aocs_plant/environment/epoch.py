"""The scenario's epoch: the calendar instant of t = 0, as a Julian date (Meeus, Astronomical Algorithms,
2nd ed., ch. 7: JD 2451545.0 is 2000-01-01 12:00).

The epoch is UTC and used as if it were TT (the ephemeris' time scale): the difference, 69.2 s in 2026,
moves the Sun by 0.0008 deg, a tenth of the solar formula's own precision (sun.py).
"""
from __future__ import annotations

from datetime import datetime, timezone

J2000_JD = 2451545.0
J2000 = datetime(2000, 1, 1, 12, 0, 0, tzinfo=timezone.utc)
SECONDS_PER_DAY = 86400.0
#: the range of the low-precision solar formula (The Astronomical Almanac, section C: 1950 to 2050)
EPOCH_MIN = datetime(1950, 1, 1, tzinfo=timezone.utc)
EPOCH_MAX = datetime(2050, 1, 1, tzinfo=timezone.utc)


def parse(value) -> datetime:
    """A TOML datetime or an ISO 8601 string ("2026-03-20T14:46:00Z"); no offset means UTC.
    ValueError with what is wrong."""
    if isinstance(value, str):
        try:
            value = datetime.fromisoformat(value)
        except ValueError:
            raise ValueError(f"{value!r} is not an ISO 8601 date and time (e.g. \"2026-03-20T14:46:00Z\")") from None
    elif not isinstance(value, datetime):
        raise ValueError(f"expected a date and time (TOML datetime or ISO 8601 string), got {type(value).__name__}")
    if value.tzinfo is None:
        value = value.replace(tzinfo=timezone.utc)
    value = value.astimezone(timezone.utc)
    if not EPOCH_MIN <= value < EPOCH_MAX:
        raise ValueError(f"{value.isoformat()} is outside 1950 to 2050 (the solar ephemeris' range)")
    return value


def julian_date(epoch: datetime) -> float:
    """JD of an aware datetime: J2000.0 plus the days since it."""
    return J2000_JD + (epoch - J2000).total_seconds() / SECONDS_PER_DAY
