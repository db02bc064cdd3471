"""aocs_compare.results_notes: the per-scenario prose of docs/results.md comes from
results_notes.toml, with the figures measured from the runs filled in; a missing entry or an
unknown figure name is an error naming the file and the key."""
from __future__ import annotations

import pytest

from aocs_compare import results_notes as notes
from aocs_compare.compare import Row
from aocs_report import markdown
from aocs_report.document import Document

#: every entry results_doc.build asks for
USED = {"sections": ("rtc", "landsat8_q", "landsat8_dist", "geo_hinf", "gao_mrp"),
        "discussion": ("geo_hinf", "gao_mrp")}


def test_every_entry_the_page_uses_is_in_the_file():
    data = notes.load()
    for table, keys in USED.items():
        for key in keys:
            assert data[table][key]["title"], (table, key)


def test_section_heading_and_note():
    text = markdown.render(Document("t").add(notes.section("rtc").add()))
    assert text == ("# t\n\n## rtc_ex1a ... rtc_ex3b: crp_linear (Rotea, Tsiotras, Corless)\n\n"
                    "J = I3, no disturbance, 100 Hz; settled when |rho| < 1e-3 and |w| < 1e-3 rad/s.\n")
    assert notes.section("geo_hinf").blocks == []   # a heading without a note


def test_discussion_fills_in_the_measured_figures_and_needs_a_run_with_metrics():
    rows = [Row("mrp_sat", "mrp_sat", None, metrics={"max_torque_norm_nm": 0.0499999}),
            Row("mrp_sat_tanh", "mrp_sat_tanh", None, error="boom")]
    sec = notes.discussion("gao_mrp", rows)
    assert sec.title == "gao_mrp"
    assert "(measured max norms: mrp_sat 0.05 N m)" in sec.blocks[0].text
    assert notes.discussion("gao_mrp", rows[1:]) is None


def test_missing_entry_and_unknown_figure_are_named(tmp_path):
    bad = tmp_path / "notes.toml"
    bad.write_text('[discussion.x]\ntitle = "x"\ntext = "{no_such_figure}"\n')
    with pytest.raises(KeyError, match=r"no \[sections.rtc\]"):
        notes.section("rtc", bad)
    with pytest.raises(KeyError, match=r"discussion.x names \{no_such_figure\}.*max_torque_norms"):
        notes.discussion("x", [Row("a", "a", None, metrics={"max_torque_norm_nm": 1.0})], bad)
