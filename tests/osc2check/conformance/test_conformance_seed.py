"""The design paper's two scenarios (``seed``): accepted, each dialect form a warning.

The paper's dialect is accepted without an error; every non-standard form gets
its own D8xx warning, and these lists are exactly what osc2check reports.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.diagnostics import Severity

FOLDER = Path(__file__).resolve().parents[3].parent / "shared" / "conformance" / "seed"
if not (FOLDER / "cut_in_and_stop.osc").is_file():
    pytest.skip(f"no conformance data at {FOLDER}", allow_module_level=True)

D801, D802, D803, D804, D805, D806 = "D801", "D802", "D803", "D804", "D805", "D806"

EXPECTED = {
    "cut_in_and_stop.osc": [
        (1, D804),  # import "domain.osc" for the standard library
        (2, D801),  # use std.stdtypes as a statement
        (10, D803),
        (11, D803),
        (13, D803),
        (14, D803),  # the toolkit's `model` and `name`
        (34, D802),  # emit go_signal, never declared
        (42, D803),
        (42, D803),  # the toolkit's `position` and its `ahead_of()`
        (42, D806),  # one_of with a `wait` member: a race
        (47, D802),  # emit CRASH_AVOIDED
        (49, D803),
        (51, D803),  # set_lights
        (63, D803),
        (63, D803),
        (63, D806),
        (69, D806),
        (72, D802),  # emit OBSTACLE_DETECTED
    ],
    "braking_friction.osc": [
        (10, D804),
        (11, D801),
        (18, D803),
        (19, D803),
        (32, D802),
        (39, D802),
        (45, D805),  # rain intensity 100.0 without a unit
        (46, D803),  # set_road_friction
        (51, D802),
    ],
}


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_the_paper_scenario_has_exactly_its_dialect_warnings(name):
    path = FOLDER / name
    config = AnalysisOptions(implicit_imports=(), modules={})
    analysis = analyze([SourceInput(str(path), path.read_text(encoding="utf-8"))], config)
    assert [d for d in analysis.diagnostics if d.severity is Severity.ERROR] == []
    found = sorted((d.span.line, d.code.code) for d in analysis.diagnostics)
    assert found == sorted(EXPECTED[name])


def test_every_dialect_form_of_the_paper_is_reported():
    codes = {code for findings in EXPECTED.values() for _, code in findings}
    assert codes == {D801, D802, D803, D804, D805, D806}


@pytest.mark.parametrize("name", ["cut_in_and_stop.osc", "braking_friction.osc"])
def test_the_vendored_copies_are_the_shared_scenarios(name):
    vendored = Path(__file__).resolve().parents[2] / "data" / "seed" / name
    assert vendored.read_bytes() == (FOLDER / name).read_bytes()
