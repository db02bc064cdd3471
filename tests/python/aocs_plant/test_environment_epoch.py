"""The scenario epoch (environment/epoch.py): parsing and Julian dates against Meeus' examples."""
from datetime import datetime, timedelta, timezone

import pytest

from aocs_plant.environment import epoch


def test_julian_dates():
    assert epoch.julian_date(epoch.J2000) == 2451545.0
    # Meeus, Astronomical Algorithms, example 7.a: 1957 October 4.81 = JD 2436116.31 (Sputnik 1)
    assert epoch.julian_date(datetime(1957, 10, 4, tzinfo=timezone.utc) + timedelta(days=0.81)) == \
        pytest.approx(2436116.31, abs=1e-9)
    # example 7.b's neighbour: 1987 January 27.0 = JD 2446822.5
    assert epoch.julian_date(epoch.parse("1987-01-27T00:00:00")) == 2446822.5


def test_parse_accepts_toml_datetimes_and_iso_strings_and_means_utc():
    a = epoch.parse("2026-03-20T14:46:00Z")
    assert a == epoch.parse("2026-03-20T14:46:00") == epoch.parse(datetime(2026, 3, 20, 14, 46))
    assert a == epoch.parse("2026-03-20T16:46:00+02:00")


@pytest.mark.parametrize("value,what", [("20 March 2026", "is not an ISO 8601 date and time"),
                                        (2026, "expected a date and time"),
                                        ("1949-12-31T23:59:59Z", "outside 1950 to 2050"),
                                        ("2050-01-01T00:00:00Z", "outside 1950 to 2050")])
def test_parse_refuses(value, what):
    with pytest.raises(ValueError, match=what):
        epoch.parse(value)
