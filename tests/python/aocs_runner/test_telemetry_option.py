"""RunOptions.telemetry: "failed" writes OUT/telemetry.parquet only for a run whose verdict failed (a campaign
deletes a passed run's folder), "always" (the default) for every run; anything else is refused before the run."""
from __future__ import annotations

import pytest

from aocs_runner.run import TELEMETRY_FILE, RunOptions, execute


def _run(tmp_path, name, **kw):
    out = tmp_path / name
    r = execute(RunOptions(scenario="irassi_large", law="quat_pd", out=str(out), plots=False, quiet=True,
                           transport="direct", **kw))
    return r, out / TELEMETRY_FILE


def test_failed_only_writes_the_table_of_a_failed_run(aocs_build_dir, tmp_path):
    passed, table = _run(tmp_path, "passed", telemetry="failed")
    assert passed.metrics["verdict"]["passed"] and not table.exists() and passed.telemetry is None
    # an integration tolerance no RK4 step meets: the verdict fails (integration-error)
    failed, table = _run(tmp_path, "failed", telemetry="failed", sets=["integrator.tolerance_arcsec=1e-12"])
    assert not failed.metrics["verdict"]["passed"] and table.is_file() and failed.telemetry == table
    always, table = _run(tmp_path, "always", duration=3.0)
    assert table.is_file()


def test_another_value_is_refused_before_the_run(aocs_build_dir, tmp_path):
    with pytest.raises(ValueError, match="telemetry 'sometimes'"):
        _run(tmp_path, "bad", telemetry="sometimes")
    assert not (tmp_path / "bad").exists()
