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


def test_the_lockstep_spin_is_bounded_by_the_nodes_own_limit(capsys):
    """--wait-spin-us takes what fsw_node's wait_spin_us takes: [0, AOCS_NODE_WAIT_SPIN_MAX_US] (node_checks.h)."""
    from aocs_core import paths

    top = paths.header_number(plant_node.SPIN_HEADER, "AOCS_NODE_WAIT_SPIN_MAX_US")
    assert top == 10000.0
    for bad in ("-1", "nan", "inf", repr(top * 1.000001)):
        assert plant_node.main(["irassi_small", "--wait-spin-us", bad]) == plant_node.EXIT_ARGS
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and f"--wait-spin-us {float(bad):g}: must be in [0, 10000] us" in err[0]
