"""Property-based tests (hypothesis) of `aocs run`'s options before anything starts: any duration,
limit, reply timeout, seed, law, event or --set text is accepted or refused with ValueError,
ScenarioError or EventError (one line, exit 2 in the CLI); never another exception (issue 11)."""
from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from aocs_plant.scenario import ScenarioError
from aocs_runner import events as evmod
from aocs_runner.run import RunOptions, prepare

FLOATS = st.one_of(st.none(), st.floats(allow_nan=True, allow_infinity=True),
                   st.sampled_from([1e-300, 5e-324, 1e308, -1.0, 0.0, 0.1, 1e9]))
REFUSED = (ValueError, ScenarioError, evmod.EventError)


@settings(max_examples=300, deadline=None)
@given(duration=FLOATS, limit=FLOATS, reply=FLOATS, seed=st.one_of(st.none(), st.integers(-2 ** 70, 2 ** 70)),
       law=st.one_of(st.none(), st.text(max_size=12), st.sampled_from(["quat_pd", "smc", "", " ", "none"])),
       sets=st.lists(st.text(max_size=30), max_size=2), scenario=st.sampled_from(["irassi_small", "gao_mrp"]))
def test_options_are_accepted_or_refused_cleanly(tmp_path_factory, duration, limit, reply, seed, law, sets, scenario):
    opts = RunOptions(scenario=scenario, law=law, duration=duration, limit=limit, reply_timeout=reply, seed=seed,
                      sets=sets, out=str(tmp_path_factory.mktemp("o")))
    try:
        sc, _, chosen, _ = prepare(opts)
    except REFUSED as exc:
        assert "\n" not in str(exc).strip(), str(exc)
        return
    assert sc.n_steps >= 1 and chosen in sc.control.laws


@settings(max_examples=300, deadline=None)
@given(specs=st.lists(st.text(max_size=24), max_size=3))
def test_any_event_text_parses_or_is_an_event_error(specs):
    try:
        evs = evmod.parse_all(specs)
        evmod.schedule(evs, 0.1, 5000)
    except evmod.EventError:
        pass
