"""A308: the capability table's forms, found by the checker where they are written."""

from __future__ import annotations

import pytest

from osc2check.analysis import SourceInput, analyze
from osc2check.capabilities import FORMS, NOT_EXECUTED

HEADER = "import osc.standard\n\nscenario s:\n    car: vehicle\n    p: person\n    m: map\n"

CASES = {
    "start_to_start": """\
    do parallel(start_to_start: 1s):
        car.drive(duration: 2s)
        p.walk(duration: 2s)
""",
    "orientation_relative_to": """\
    do p.walk(duration: 2s) with:
        orientation(yaw: 10deg, relative_to: car, at: start)
""",
    "heading_frame": """\
    do p.walk(duration: 2s) with:
        orientation(yaw: 10deg, measured_by: absolute, at: start)
""",
    "pitch_roll": """\
    do p.walk(duration: 2s) with:
        orientation(yaw: 10deg, pitch: 5deg, at: start)
""",
    "vehicle_heading": """\
    do car.drive(duration: 2s) with:
        yaw(angle: 10deg, at: end)
""",
}


def _a308(body: str) -> list[str]:
    analysis = analyze([SourceInput("s.osc", HEADER + body)])
    return [d.message for d in analysis.diagnostics if d.code.code == "A308"]


@pytest.mark.parametrize("key", sorted(CASES))
def test_each_form_is_reported_once_with_its_reason(key: str) -> None:
    form = FORMS[key]
    assert _a308(CASES[key]) == [
        f"{form.written} is not executed by osc2run: {form.reason} (docs/coverage.md)"
    ]


def test_a_library_method_the_runner_lacks_is_reported() -> None:
    found = _a308(
        "    bm: behavioral_model\n    event go\n    on @go:\n        call car.set_bm(bm)\n"
    )
    assert found == [
        "`physical_object.set_bm` is not executed by osc2run: "
        f"{NOT_EXECUTED['physical_object.set_bm']} (docs/coverage.md)"
    ]


def test_forms_the_runner_executes_are_not_reported() -> None:
    assert not _a308("""\
    do parallel:
        car.drive(duration: 2s) with:
            yaw(angle: 10deg, at: start)
        p.walk(duration: 2s) with:
            orientation(yaw: 90deg, measured_by: relative_to_road, at: start)
""")
