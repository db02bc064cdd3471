"""aocs.bench_breakdown (`python -m aocs.bench_sil --breakdown`) measures what docs/benchmarks.md says: one figure per
part of the lockstep loop, per whole period, and the loop's methods as they were afterwards. Nothing about speed."""
from __future__ import annotations

from aocs import bench_breakdown as B
from aocs_loop.frames import PlantPort
from aocs_plant.plant import Plant
from aocs_runner import plant_node


def test_a_direct_run_is_broken_down_period_by_period_and_the_methods_are_restored():
    before = (plant_node._Loop.sensors, plant_node._Loop.truth, PlantPort.apply, Plant.advance)
    res = B.breakdown("irassi_large", 2.0, "direct")
    assert (plant_node._Loop.sensors, plant_node._Loop.truth, PlantPort.apply, Plant.advance) == before
    assert res["transport"] == "direct" and res["dt"] == 0.1
    assert res["steps"] == 19                     # 20 periods flown, 19 whole ones between 20 sensors calls
    names = [p[0] for p in res["parts"]]
    # every part the direct loop calls, once; no socket in process
    for part in ("sensors", "publish", "truth", "_check_end", "command", "apply", "begin", "advance", "loop"):
        assert names.count(part) == 1, (part, names)
    assert "handle_timeout" not in names and "flush" not in names
    med, mean = res["period"]
    assert 0.0 < med and 0.0 < mean
    for name, what, m, a in res["parts"]:
        assert what and a >= 0.0 and (m >= 0.0 or name == "loop"), (name, m, a)
    # the parts and the rest are the period, on average
    total = sum(a for _, _, _, a in res["parts"])
    assert abs(total - mean) <= 1e-6 * mean
    assert res["fsw_step_ns_median"] > 0          # the in-process node's exit summary (its executive step)
