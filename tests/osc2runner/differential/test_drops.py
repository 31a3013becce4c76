"""Silent drops are found (issue 19): every argument the checker binds for a call the
run starts is read by the start placement or the runner's behaviours, or the file is
refused before tick 0 (A308). ``drops.dropped`` lists the rest, from the checker's
binding table; these tests show it finds a dropped argument and none in a full run."""

from __future__ import annotations

from osc2check.analysis import SourceInput, analyze
from osc2check.semantics.bindings import recording_reads
from osc2runner.behaviours import modifiers
from osc2runner.runner import check_analysis, execute, prepare_checked
from tests.osc2runner.differential.drops import dropped, reading

URI = "drops.osc"
SCENARIO = """\
import osc.standard

scenario top:
    sub: vehicle
    ref: vehicle
    do parallel(duration: 3s):
        ref.drive() with:
            lane(2, at: start)
            speed(20kph)
            position(20m, ahead_of: sub, at: start)
        sub.drive() with:
            lane(1, at: start)
            speed([15kph..25kph], at: start)
            lateral(distance: 0.4m, side: right, at: end)
            keep_lane()
"""


def _dropped(text: str) -> list[str]:
    with reading() as reads:
        analysis = analyze([SourceInput(URI, text)])
        prepared = prepare_checked(check_analysis(analysis, URI))
    with recording_reads(reads):
        result = execute(prepared, duration=3.0)
    assert result.outcome.status == "success", result.outcome.reason
    return dropped(analysis, reads)


def test_a_run_reads_every_argument_it_was_given():
    assert _dropped(SCENARIO) == []


def test_an_argument_the_runner_ignores_is_a_silent_drop(monkeypatch):
    # a lateral that reads its distance but not its side (the bug this catches: a
    # form of a modifier dropped in silence, the run still reporting success)
    monkeypatch.setattr(
        modifiers.Lateral, "_offset", lambda self: float(self.args.get("distance", 0.0))
    )
    lost = _dropped(SCENARIO.replace("side: right", "side: left"))
    assert [w.split(" ", 1)[1] for w in lost] == ["lateral(side)"]
