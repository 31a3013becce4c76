"""Which scenarios invoke which (``semantics.roots``): the root the runner runs, and the
scenarios the checker verifies as invoked (no witness, no placement of their own)."""

from __future__ import annotations

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.semantics.roots import file_scenarios, invokers, root_scenario

HEADER = "import osc.standard\n\n"
INNER = """scenario inner:
    car: vehicle
    do car.drive(duration: 5s)

"""


def _analysis(text: str):
    return analyze([SourceInput("t.osc", HEADER + INNER + text)], AnalysisOptions())


def _scenarios(text: str):
    program = _analysis(text).programs["t.osc"]
    return program.model, file_scenarios(program.model, program.files["t.osc"].ast.declarations)


def _invokers(text: str) -> dict[str, list[str]]:
    model, scenarios = _scenarios(text)
    return {t.name: [s.name for s in by] for t, by in invokers(model, scenarios).items()}


def _root(text: str) -> str:
    return root_scenario(*_scenarios(text)).name


def test_an_invocation_in_the_scenarios_own_do():
    text = """scenario outer:
    hero: vehicle
    do inner()
"""
    assert _invokers(text) == {"inner": ["outer"]}
    assert _root(text) == "outer"


def test_an_invocation_in_an_extend_is_one_the_scenario_makes():
    # the runner compiles `outer` with the `do` of its `extend`: it runs `inner`
    text = """scenario outer:
    hero: vehicle

extend outer:
    do inner()
"""
    assert _invokers(text) == {"inner": ["outer"]}
    assert _root(text) == "outer"


def test_an_inherited_do_invokes_and_an_own_do_replaces_it():
    text = """scenario base:
    hero: vehicle
    do inner()

scenario same inherits base:
    x: int = 1

scenario other inherits base:
    do hero.drive(duration: 3s)
"""
    assert _invokers(text) == {"inner": ["base", "same"]}


def test_the_checker_verifies_a_scenario_invoked_from_an_extend_as_invoked():
    analysis = _analysis(
        """scenario outer:
    hero: vehicle

extend outer:
    do inner()
"""
    )
    results = {r.scenario.name: r for r in analysis.verified["t.osc"].scenarios}
    assert results["inner"].invoked_by == ("outer",)
    assert results["inner"].witness is None
    assert results["outer"].invoked_by == ()
    assert results["outer"].witness is not None
    # `inner`'s car is placed by the scenario that invokes it: no L506 of its own (the
    # runner builds the actors of the root scenario only: A308, as `car` is not passed)
    assert [d.code.code for d in analysis.diagnostics] == ["A308"]
