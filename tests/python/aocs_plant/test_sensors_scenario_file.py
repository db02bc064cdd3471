"""A whole scenario file with a star tracker and a gyro (tests/python/aocs_plant/data/sensors_st_gyro.toml: the
examples of docs/scenarios.md verbatim), and no reference scenario with either (the ideal sensors stay the
default of every reference scenario until the realistic suite is added)."""
import math
from pathlib import Path

from aocs_plant import Plant, list_scenarios, load

HERE = Path(__file__).resolve().parent
FILE = HERE / "data" / "sensors_st_gyro.toml"
DOC = HERE.parents[2] / "docs" / "scenarios.md"


def test_the_file_holds_the_documented_examples_verbatim():
    doc = DOC.read_text()
    blocks = [b.split("```", 1)[0] for b in doc.split("```toml\n")[1:]]
    mine = [b for b in blocks if b.startswith(("[sensors.star_tracker]", "[sensors.gyro]"))]
    assert len(mine) == 2
    text = FILE.read_text()
    assert all(b in text for b in mine)


def test_the_file_loads_and_flies():
    sc = load(FILE)
    st, g = sc.sensors["star_tracker"], sc.sensors["gyro"]
    assert (st.rate_hz, st.latency_s, st.noise_cross_arcsec, st.noise_about_arcsec) == (5.0, 0.1, 1.0, 8.0)
    assert st.low_frequency == "gauss_markov" and st.outages == ((200.0, 260.0),)
    assert g.mode == "rate" and g.arw == 5.8e-7 and g.quantum == 1e-8
    assert abs(g.misalignment[0][1] - 2e-5) < 1e-20           # -[d x] with d = (1e-4, -5e-5, 2e-5)
    p = Plant(sc)
    assert [s.name for s in p.sensors] == ["attitude", "gyro", "rate", "star_tracker"]
    news = 0
    for _ in range(20):
        s = p.sense()
        news += s["st_new"]
        assert all(math.isfinite(x) for x in s["gyro_w"])
        p.advance()
    assert news == 10 - 1     # 5 Hz over 2 s, less the first (t_meas = -0.1 s)


def test_no_reference_scenario_has_them():
    """The ideal attitude and rate sensors stay the default of every reference scenario: only the MEKF hold
    (irassi_hold_mekf, the realistic suite) and the realistic-suite copies of the slews and wheel scenarios
    (*_mekf, and irassi_rw_wheel_dies, irassi_rw_mekf with a fault) have a star tracker and a gyro."""
    with_them = {sid for sid in list_scenarios() if set(load(sid).sensors.sensors) & {"star_tracker", "gyro"}}
    assert with_them == {"irassi_hold_mekf", "irassi_small_mekf", "irassi_large_mekf", "irassi_rw_mekf",
                         "irassi_rw_failed_mekf", "irassi_day_mekf", "irassi_rw_wheel_dies"}
