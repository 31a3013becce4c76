"""Methods with arguments (§7.3.7): ``is expression`` inline, ``is external`` in Python.

The external functions are in ``demo_externals.py``, registered with
``@external`` as docs/runner.md describes; the tests put this folder on
``sys.path`` so that ``is external demo_externals.faster_than(...)`` imports it.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from osc2runner import run
from osc2runner.errors import ScenarioError
from osc2runner.external import ExternalLoadError, ExternalRegistry, external

HERE = Path(__file__).parent
SCENARIOS = HERE / "scenarios"


@pytest.fixture
def externals(monkeypatch: pytest.MonkeyPatch):
    monkeypatch.syspath_prepend(str(HERE))
    import demo_externals

    demo_externals.CALLS.clear()
    yield demo_externals
    demo_externals.CALLS.clear()


def test_expression_and_external_methods_take_their_arguments(externals):
    result = run(SCENARIOS / "methods.osc")
    assert result.outcome.status == "success", result.outcome.reason
    speed = result.telemetry["hero"]["speed"]
    # wait above(margin(10kph)): hero.speed > 10kph + 2kph (the default `extra`)
    crossed = int(np.flatnonzero(speed > 12.0 / 3.6)[0])
    assert result.event_ticks("emit", "crossed") == [crossed]
    # wait faster(hero.speed, 25kph): the Python function gets SI values
    fast = int(np.flatnonzero(speed > 25.0 / 3.6)[0])
    assert result.event_ticks("emit", "fast") == [fast]
    # call note(c.at) in `on @crossed as c`, then call note(hero.speed) in the `do`
    assert externals.CALLS == [(speed[crossed], "seen"), (speed[fast], "seen")]


def test_an_unknown_external_is_an_input_error_at_its_declaration(externals):
    with pytest.raises(ScenarioError) as caught:
        run(SCENARIOS / "methods_unknown.osc")
    [problem] = caught.value.problems
    assert "demo_externals.no_such_function" in problem.message
    assert problem.span is not None and problem.span.line == 6


def test_an_external_that_raises_fails_the_run_at_the_call(externals):
    result = run(SCENARIOS / "methods_raising.osc")
    assert result.outcome.status == "failure"
    assert result.outcome.reason.startswith(f"{SCENARIOS / 'methods_raising.osc'}:13:")
    assert "raised ValueError" in result.outcome.reason


def test_registry_finds_marked_functions_by_name_and_imports_their_module(externals):
    registry = ExternalRegistry()
    found = registry.find("demo_externals.note")  # @external without a name
    assert found is not None and found.function is externals.note
    assert registry.find("demo_externals.not_marked") is None
    assert registry.find("no_such_package_xyz.fn") is None
    assert "demo_externals.faster_than" in registry.names()


def test_registry_refuses_two_functions_under_one_name():
    @external("twice.fn")
    def one() -> int:
        return 1

    @external("twice.fn")
    def two() -> int:
        return 2

    registry = ExternalRegistry()
    registry.add("twice.fn", one)
    registry.add("twice.fn", one)  # the same function again is fine
    with pytest.raises(ExternalLoadError):
        registry.add("twice.fn", two)


def test_registry_reports_a_module_that_fails_to_import(tmp_path, monkeypatch):
    (tmp_path / "failing_externals.py").write_text("raise RuntimeError('boom')\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(ExternalLoadError, match="boom"):
        ExternalRegistry().find("failing_externals.fn")
    sys.modules.pop("failing_externals", None)
