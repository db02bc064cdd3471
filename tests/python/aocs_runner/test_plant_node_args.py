"""plant_node's own argument checks (aocs_runner.plant_node), before any LCM handle exists."""
from __future__ import annotations

from aocs_runner import plant_node


def test_truth_to_the_log_needs_a_log_and_the_log_needs_the_plants_own_udpm_reader(capsys):
    assert plant_node.main(["irassi_small", "--truth", "log"]) == plant_node.EXIT_ARGS
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--truth log needs --log" in err[0]
    assert plant_node.main(["irassi_small", "--log", "/nonexistent/x.lcmlog", "--lcm-lib"]) == plant_node.EXIT_ARGS
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--log records the udpm socket" in err[0]
