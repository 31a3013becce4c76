"""What the checker accepts, the runner does (issue 19): each form that the runner once
crashed on, dropped in silence or refused without the checker saying so, run and
checked in the telemetry."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2runner import run

HEADER = "import osc.standard\n\nscenario top:\n"
KPH = 1 / 3.6


def _run(tmp_path, body: str):  # type: ignore[no-untyped-def]
    source = tmp_path / "s.osc"
    source.write_text(HEADER + body)
    analysis = analyze([SourceInput(str(source), HEADER + body)], AnalysisOptions())
    problems = [  # a dialect form (D code) is a warning the checker accepts
        d.message
        for d in analysis.diagnostics
        if d.severity.name == "ERROR"
        or (d.severity.name == "WARNING" and not d.code.code.startswith("D"))
    ]
    assert not problems
    result = run(source, duration=20)
    assert result.outcome.status == "success", result.outcome.reason
    return result


def _chosen(result, call: str, suffix: str) -> float:  # type: ignore[no-untyped-def]
    """The witness's value (SI) of parameter ``suffix`` of the modifier ``call``."""
    found = [
        p
        for p in result.metadata["witness"]["parameters"]
        if f".{call}@" in p["name"] and p["name"].endswith(suffix)
    ]
    assert len(found) == 1, [p["name"] for p in result.metadata["witness"]["parameters"]]
    return float(Fraction(found[0]["si"]))


def test_a_speed_range_runs_at_the_speed_the_solver_chose(tmp_path):
    result = _run(
        tmp_path,
        """\
    ego: vehicle
    do ego.drive(duration: 4s) with:
        lane(1, at: start)
        speed([30kph..31kph])
""",
    )
    chosen = _chosen(result, "speed", ".speed")
    assert 30 * KPH <= chosen <= 31 * KPH
    assert result.telemetry["ego"]["speed"][-1] == pytest.approx(chosen, abs=0.5 * KPH)


def test_a_lane_count_range_changes_by_the_chosen_count(tmp_path):
    result = _run(
        tmp_path,
        """\
    npc: vehicle
    do npc.drive(duration: 8s) with:
        lane(1, at: start)
        speed(40kph)
        change_lane(lane: [1..2], side: left, at: end)
""",
    )
    chosen = _chosen(result, "change_lane", ".lane")
    assert chosen in (1, 2)
    lanes = result.telemetry["npc"]["lane"]
    assert lanes[0] == 1 and lanes[-1] == 1 + chosen


@pytest.mark.parametrize("side", ["", ", side: left", ", side: right"])
def test_a_lane_change_from_a_free_start_lane_starts_where_the_change_exists(tmp_path, side):
    """The start lane is the witness's: one from which the chosen count of lanes exists
    to the side (either side without one), so the runner never finds no such lane."""
    result = _run(
        tmp_path,
        f"""\
    npc: vehicle
    do npc.drive(duration: 8s) with:
        speed(40kph)
        change_lane(lane: [1..2]{side})
""",
    )
    chosen = _chosen(result, "change_lane", ".lane")
    lanes = result.telemetry["npc"]["lane"]
    assert result.outcome.status == "success", result.outcome.reason
    assert abs(lanes[-1] - lanes[0]) == chosen
    if side:
        assert np.sign(lanes[-1] - lanes[0]) == (1 if "left" in side else -1)


def test_a_start_gap_range_places_the_follower_behind(tmp_path):
    result = _run(
        tmp_path,
        """\
    ego: vehicle
    npc: vehicle
    do parallel(duration: 2s):
        npc.drive() with:
            lane(2, at: start)
            speed(40kph)
        ego.drive() with:
            lane(2, at: start)
            speed(40kph)
            position([10m..20m], behind: npc, at: start)
""",
    )
    gap = _chosen(result, "position", ".distance")
    assert 10 <= gap <= 20
    ego, npc = result.telemetry["ego"], result.telemetry["npc"]
    starts = {a["name"]: a for a in result.metadata["witness"]["actors"]}
    half = (float(starts["ego"]["length_m"]) + float(starts["npc"]["length_m"])) / 2
    assert npc["x"][0] - ego["x"][0] == pytest.approx(gap + half, abs=0.01)


@pytest.mark.parametrize(("key", "theirs", "ours"), [("left_of", 2, 3), ("right_of", 3, 2)])
def test_lane_left_of_and_right_of_another_actor(tmp_path, key, theirs, ours):
    result = _run(
        tmp_path,
        f"""\
    ego: vehicle
    npc: vehicle
    do parallel(duration: 3s):
        npc.drive() with:
            lane({theirs}, at: start)
            speed(30kph)
        ego.drive() with:
            lane({key}: npc)
            speed(30kph)
""",
    )
    assert result.telemetry["ego"]["lane"][-1] == ours
    assert result.telemetry["npc"]["lane"][-1] == theirs


def test_a_person_faces_and_walks_across_the_road(tmp_path):
    result = _run(
        tmp_path,
        """\
    p: person
    do p.walk(duration: 2s) with:
        lane(1, at: start)
        speed(1.5mps)
        orientation(yaw: 90deg, measured_by: relative_to_road, at: start)
""",
    )
    walker = result.telemetry["p"]
    assert walker["yaw"][0] == pytest.approx(np.pi / 2, abs=0.01)
    moved_x = walker["x"][-1] - walker["x"][0]
    moved_y = walker["y"][-1] - walker["y"][0]
    assert moved_y > 2.0 and abs(moved_x) < 0.1  # across the road, not along it


def test_a_standing_car_keeps_its_start_yaw(tmp_path):
    result = _run(
        tmp_path,
        """\
    car: vehicle
    do car.remain_stationary(duration: 2s) with:
        lane(1, at: start)
        yaw(angle: 20deg, at: start)
""",
    )
    yaw = result.telemetry["car"]["yaw"]
    assert yaw[0] == pytest.approx(np.radians(20), abs=0.01)
    assert yaw[-1] == pytest.approx(np.radians(20), abs=0.01)


def test_an_actor_field_initialised_with_another_actor_names_it(tmp_path):
    result = _run(
        tmp_path,
        """\
    ego: vehicle
    npc: vehicle
    other: vehicle = npc
    do parallel(duration: 2s):
        ego.drive() with:
            lane(1, at: start)
            speed(30kph)
        other.drive() with:
            lane(2, at: start)
            speed(40kph)
""",
    )
    assert sorted(result.telemetry) == ["ego", "npc"]
    assert [a["name"] for a in result.metadata["witness"]["actors"]] == ["ego", "npc"]
    assert result.telemetry["npc"]["speed"][-1] == pytest.approx(40 * KPH, abs=0.5 * KPH)
    assert result.telemetry["npc"]["lane"][0] == 2


def test_a_files_own_vehicle_type_without_the_library_is_an_actor_without_a_body(tmp_path):
    """Only the standard library's `vehicle`, `person`, ... are bodies the checker places
    (Scena's DSL 2.2 cases declare their own `actor vehicle`): the runner makes no body for
    a type of the same name, where it used to refuse to start (no witness start)."""
    text = """\
actor vehicle:
    length: float
actor car inherits vehicle
scenario host:
    v: list of vehicle
    c: car
"""
    source = tmp_path / "own.osc"
    source.write_text(text)
    analysis = analyze([SourceInput(str(source), text)], AnalysisOptions())
    assert not [d.message for d in analysis.diagnostics if d.severity.name == "ERROR"]
    result = run(source, duration=5)
    assert result.outcome.status == "success", result.outcome.reason
    assert result.telemetry == {}
    assert result.metadata["witness"]["actors"] == []


GLOBALS = """\
import osc.standard

global cruise: speed = 40kph
global slow: bool = false
global lanes: int = 2
global pause: time = 1s

scenario top:
    car: vehicle
    do serial:
        car.drive(duration: 3s) with:
            speed(slow ? 20kph : cruise)
            lane(lanes, at: start)
        wait elapsed(pause)
"""


def test_global_parameters_have_the_witness_values(tmp_path):
    """A `global` parameter used in an argument or an expression: the runner refused
    each use (`the global parameter ... is not a value`) of a file the checker passed;
    the witness has their values (`::cruise`)."""
    source = tmp_path / "g.osc"
    source.write_text(GLOBALS)
    analysis = analyze([SourceInput(str(source), GLOBALS)], AnalysisOptions())
    assert analysis.diagnostics == []
    result = run(source, duration=10)
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    assert car["lane"][0] == 2
    assert car["speed"][59] == pytest.approx(40 * KPH, abs=0.5 * KPH)
    assert result.outcome.time == pytest.approx(4.0)  # the drive, then the pause
