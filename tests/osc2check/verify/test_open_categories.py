"""A vehicle whose category the scenario leaves open (issue 20, item 7): ASAM OpenSCENARIO
DSL 2.1 §8.7 makes ``vehicle_category`` a parameter with no default, so a scenario that
says nothing of it allows every category. The checker places such a vehicle as a car
where a car fits, and with the footprint of any category that fits where none does;
a placement no category allows is still a conflict."""

from __future__ import annotations

import pytest

from osc2check.analysis import SourceInput, analyze
from osc2check.verify.api import solve
from osc2check.verify.witness import Witness
from osc2check.world.catalogue import CATEGORIES

URI = "open.osc"


def _scenario(lateral: str, extra: str = "") -> str:
    # lane 3 of the built-in 3 x 3.5 m road: its centre is 8.75 m from the right edge;
    # the vehicle's left side stays within 10.5 m
    return f"""\
import osc.standard

scenario s:
    v: vehicle{extra}
    do v.drive(duration: 2s) with:
        lane(3, at: start)
        position(distance: 50m, at: start)
        lateral(distance: {lateral}, at: start)
"""


def _check(text: str):
    analysis = analyze([SourceInput(URI, text)])
    errors = [d for d in analysis.diagnostics if d.severity.name == "ERROR"]
    return analysis, errors


def _fits(row, lateral: float) -> bool:
    return 8.75 + lateral + float(row.width) / 2 <= 10.5


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_vehicle_no_car_fits_is_placed_with_a_category_that_does(seed):
    analysis, errors = _check(_scenario("1.2m"))
    assert not errors, [d.message for d in errors]
    witness = solve(analysis, seed=seed)
    assert isinstance(witness, Witness)
    v = witness.actor("v")
    assert v is not None and v.category != "car"
    row = CATEGORIES[v.category]
    assert not _fits(CATEGORIES["car"], 1.2) and _fits(row, 1.2)
    assert (v.length, v.width) == (row.length, row.width)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_vehicle_a_car_fits_is_a_car(seed):
    analysis, errors = _check(_scenario("0.5m"))
    assert not errors
    witness = solve(analysis, seed=seed)
    assert isinstance(witness, Witness)
    assert witness.actor("v").category == "car"  # type: ignore[union-attr]


def test_a_placement_no_category_allows_is_a_conflict():
    assert not any(_fits(row, 2.0) for row in CATEGORIES.values())
    _, errors = _check(_scenario("2.0m"))
    assert [d.code.code for d in errors] == ["L507"]
    assert "`v` (1.8 m wide) stays on the road's 3 lanes of 3.5 m" in errors[0].message


def test_a_category_the_scenario_chooses_is_kept():
    _, errors = _check(_scenario("1.2m", " with:\n        keep(it.vehicle_category == car)"))
    assert [d.code.code for d in errors] == ["L507"]


def test_the_runner_builds_the_category_the_witness_chose(tmp_path):
    from osc2runner import run

    source = tmp_path / "open.osc"
    source.write_text(_scenario("1.2m"))
    result = run(source)
    assert result.outcome.status == "success", result.outcome.reason
    actor = result.metadata["actors"]["v"]
    row = CATEGORIES[actor["category"]]
    assert actor["category"] != "car"
    assert actor["size"]["width"] == pytest.approx(float(row.width))
    # it starts where the witness put it, its left side on the road
    assert result.telemetry["v"]["y"][0] + float(row.width) / 2 <= 10.5
