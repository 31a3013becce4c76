"""Persons on sidewalks (issue 20, item 5): a person may use every lane of the road,
sidewalks and shoulders included (ASAM OpenSCENARIO DSL 2.1 §8.7: a ``person`` is a
``traffic_participant``, not a vehicle; OpenDRIVE 1.8 §9.5.3 lane type ``sidewalk``:
"a lane that is used by pedestrians"), so "off the road" for a person means off every
lane. The checker places a person there and the runner lets it walk there; a vehicle
still stays on the driving lanes.

The bundled four-way junction's arms have one 3.5 m lane each way and 2 m sidewalks:
the right lane's centre is 1.75 m right of the reference line, its sidewalk spans
3.5 m to 5.5 m right of it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from osc2check.analysis import SourceInput, analyze
from osc2check.verify.api import solve
from osc2check.verify.witness import Witness
from osc2runner import run

JUNCTION = Path(__file__).resolve().parents[3] / "examples" / "maps" / "four_way_junction.xodr"


def _scenario(actor: str, lateral: float, action: str = "walk", seconds: float = 4.0) -> str:
    yaw = "        orientation(yaw: 90deg)\n" if action == "walk" else ""
    return f"""\
import osc.standard

scenario s:
    town: map with:
        keep(it.map_file == "{JUNCTION.as_posix()}")
    who: {actor}
    do who.{action}(duration: {seconds}s) with:
        lane(1, at: start)
        position(distance: 50m, at: start)
        lateral(distance: {lateral}m, at: start)
        speed(4kph)
{yaw}"""


def _errors(text: str):
    analysis = analyze([SourceInput("s.osc", text)])
    return analysis, [d for d in analysis.diagnostics if d.severity.name == "ERROR"]


def test_a_person_starts_on_the_sidewalk():
    analysis, errors = _errors(_scenario("person", -3.0))
    assert not errors, [d.message for d in errors]
    witness = solve(analysis, seed=0)
    assert isinstance(witness, Witness)
    who = witness.actor("who")
    assert who is not None and who.t == pytest.approx(-3.0)


@pytest.mark.parametrize(
    ("actor", "lateral", "code"),
    [("vehicle", -3.0, "L503"), ("person", -5.4, "L503")],
    ids=["a vehicle keeps to the driving lanes", "a person stays on the sidewalk"],
)
def test_off_every_lane_it_may_use_is_refused(actor, lateral, code):
    _, errors = _errors(_scenario(actor, lateral, "drive" if actor == "vehicle" else "walk"))
    assert [d.code.code for d in errors] == [code]


def test_a_person_crosses_from_the_kerb(tmp_path):
    source = tmp_path / "s.osc"
    source.write_text(_scenario("person", -3.0))
    result = run(source)
    assert result.outcome.status == "success", result.outcome.reason
    who = result.telemetry["who"]
    lanes = list(dict.fromkeys(int(x) for x in who["lane_id"]))
    assert lanes[:2] == [-2, -1]  # the sidewalk, then the driving lane beside it
    # from 4.75 m right of the reference line, across at 4 kph (its start speed: the
    # phase's, docs/runner.md) for 4 s
    assert who["t"][-1] == pytest.approx(-4.75 + 4.0 / 3.6 * 4.0, abs=0.01)


def test_a_person_walks_along_the_sidewalk(tmp_path):
    source = tmp_path / "s.osc"
    source.write_text(
        _scenario("person", -3.0, seconds=20.0).replace("        orientation(yaw: 90deg)\n", "")
        + "        lateral(distance: -3m)\n"
    )
    result = run(source)
    assert result.outcome.status == "success", result.outcome.reason
    who = result.telemetry["who"]
    assert set(int(x) for x in who["lane_id"]) == {-2}
    assert np.abs(np.asarray(who["t"]) + 4.75).max() < 0.05
    assert abs(who["s"][-1] - who["s"][0]) == pytest.approx(4.0 / 3.6 * 20.0, abs=0.1)
