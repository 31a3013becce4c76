"""The solver checks at most ``MAX_SCENARIOS`` scenarios of a file: a file of a thousand
conflicting scenarios (200 KB) took more than a minute; each one past the budget is C408
and is checked alone with ``--scenario``."""

from __future__ import annotations

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.verify import check
from tests.osc2lsp.lsp_helpers import CONFLICT

_BODY = CONFLICT.split("\n", 1)[1]  # one scenario whose two `keep`s conflict (C401)
TEXT = (
    CONFLICT.split("\n", 1)[0]
    + "\n"
    + "".join(_BODY.replace("cruise_band", f"band_{i}") for i in range(4))
)


def test_scenarios_past_the_files_budget_are_c408_and_checked_alone(monkeypatch):
    monkeypatch.setattr(check, "MAX_SCENARIOS", 2)
    found = analyze([SourceInput("many.osc", TEXT)]).diagnostics
    assert [d.code.code for d in found] == ["C401", "C401", "C408", "C408"]
    assert "check it alone with `--scenario band_3`" in found[-1].message
    alone = analyze([SourceInput("many.osc", TEXT)], AnalysisOptions(scenario="band_3"))
    assert [d.code.code for d in alone.diagnostics] == ["C401"]


def test_a_value_nested_deep_in_brackets_is_quoted_whole():
    """A field's span ends inside its default's brackets; the closers are taken from
    the source one at a time (slicing the rest of the file for each made a megabyte
    of brackets take minutes)."""
    depth = 3_000
    default = "(" * depth + "1" + ") " * depth
    text = (
        "import osc.standard\nscenario s:\n    hero: vehicle\n"
        f"    x: float = {default} # a comment\n    keep(x == 2)\n"
        "    do hero.drive(duration: 3s) with:\n        speed(30kph)\n"
    )
    found = analyze([SourceInput("deep.osc", text)]).diagnostics
    replaced = [d for d in found if d.code.code == "C403"]
    assert len(replaced) == 1
    assert f"`x: float = {default.rstrip()}` is replaced by `keep(x == 2)`" in replaced[0].message
