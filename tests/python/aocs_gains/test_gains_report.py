"""aocs_gains.report: docs/gains/report.md as a Document, from design results (stand-ins here with
the attributes a Riccati and an LMI design carry; the numbers are chosen here)."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from aocs_gains import report
from aocs_report import markdown

POLES = np.array([-0.5 + 0.5j, -0.5 - 0.5j, -2.0 + 0j])


def _lqr():
    return SimpleNamespace(name="lqr_quat_ref", inputs={"law": "lqr_quat", "kind": "lqr_quat"}, poles=POLES,
                           residual_abs=1e-12, residual_rel=1e-15, slowest_pole_re=-0.5)


def _hinf():
    return SimpleNamespace(name="hinf_min", inputs={"law": "hinf", "kind": "hinf"}, poles=POLES, gamma=1.0e-3,
                           hinf_norm=0.99e-3, slowest_pole_re=-0.5, form="plain", alpha=None, bounded=False,
                           gamma_min=1e-3, gamma_star=1e-3, gamma_star_scs=1.000001e-3, alpha_sel=0.01, delta=0.01,
                           lmi_min_eig=-1.0, lmi_max_eig=-1e-9, k=np.full((3, 6), -2.5), k_rel_diff=1e-7,
                           k_rtol=1e-4, hinf_sweep=0.98e-3, hinf_peak_rad_s=0.1)


def test_report_sections_tables_and_figures():
    text = markdown.render(report.document([_lqr(), _hinf()]))
    headings = [ln for ln in text.splitlines() if ln.startswith("#")]
    assert headings == ["# Gain designs", "## H-infinity designs side by side", "## H-infinity selection rule",
                        "### hinf_min", "## Closed-loop poles", "### lqr_quat_ref", "### hinf_min", "## Figures"]
    assert "| `lqr_quat_ref` | lqr_quat | ARE residual 1.00e-12 (rel 1.00e-15) | -5.0000e-01 | 0.707 | 2 |" in text
    assert "| | `hinf_min` |\n|---|---|\n| form | plain |" in text               # only the LMI designs side by side
    assert "| max abs K (N m/rad, N m s/rad) | 2.5 |" in text
    assert "- pole region" not in text and "alpha_sel = 0.01 1/s; pole region: none (plain SPEC LMI)" in text
    assert text.endswith("![closed-loop poles](poles.png)\n\n"
                         "![H-infinity closed loop singular values](hinf_sv.png)\n")
