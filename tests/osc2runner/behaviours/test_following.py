"""A vehicle whose speed the scenario leaves open keeps a safe gap behind what is ahead
(``osc2runner.behaviours.following``); a commanded speed is driven as commanded."""

from __future__ import annotations

import numpy as np
import pytest

from osc2runner import run
from osc2runner.behaviours.following import SAFE_GAP, SAFE_TIME

KPH = 1 / 3.6

HEADER = """\
import osc.standard

scenario s:
    ego: vehicle
    npc: vehicle
    do parallel(duration: {duration}):
"""
# an ego at 60 kph whose speed is left open after its start, 60 m behind an npc
EGO = (
    HEADER
    + """\
        ego.drive() with:
            lane(1, at: start)
            position(distance: 20m, at: start)
            speed(60kph, at: start){ego}
"""
)
BEHIND_A_SLOWER_CAR = (
    EGO
    + """\
        npc.drive() with:
            lane(1, at: start)
            position(distance: 80m, at: start)
            speed(20kph)
"""
)
# the npc at 20 kph ahead of the ego, then in the lane to the left
NPC_LEAVES = """\
        serial:
            npc.drive(duration: {leave}) with:
                lane(1, at: start)
                position(distance: 80m, at: start)
                speed(20kph)
            npc.change_lane(num_of_lanes: 1, side: left)
            npc.drive()
"""


def _run(tmp_path, ego: str = "", text: str = BEHIND_A_SLOWER_CAR, **times: str):
    source = tmp_path / "s.osc"
    source.write_text(text.format(ego=ego, **{"duration": "30s", "leave": "", **times}))
    return run(source)


def _gaps(result) -> np.ndarray:
    """Bumper-to-bumper gap from the ego to the npc, every tick (both in one lane)."""
    ego, npc = result.telemetry["ego"], result.telemetry["npc"]
    sizes = result.metadata["actors"]
    half = 0.5 * (sizes["ego"]["size"]["length"] + sizes["npc"]["size"]["length"])
    return np.asarray(npc["x"]) - np.asarray(ego["x"]) - half


def test_a_speed_left_open_slows_behind_a_slower_car_and_keeps_a_safe_gap(tmp_path):
    result = _run(tmp_path)
    assert result.outcome.status == "success", result.outcome.reason
    ego = result.telemetry["ego"]
    assert ego["speed"][0] == pytest.approx(60 * KPH, abs=0.3)
    assert ego["speed"][-1] == pytest.approx(20 * KPH, abs=0.3)  # the npc's speed
    gaps = _gaps(result)
    wanted = SAFE_GAP + SAFE_TIME * 20 * KPH
    assert gaps[-1] == pytest.approx(wanted, abs=1.0)
    assert gaps.min() > 0.7 * wanted  # never much closer than the safe gap
    assert not [r for r in result.events if r.kind == "collision"]


def test_a_commanded_speed_is_driven_into_the_slower_car(tmp_path):
    result = _run(tmp_path, ego="\n            speed(60kph)")
    assert result.outcome.status == "failure"
    assert result.outcome.reason == "collision: ego and npc"
    speed = result.telemetry["ego"]["speed"]
    assert min(speed) == pytest.approx(60 * KPH, abs=0.3)  # it never slowed


def test_avoid_collisions_false_turns_the_following_off(tmp_path):
    result = _run(tmp_path, ego="\n            avoid_collisions(false)")
    hits = [r for r in result.events if r.kind == "collision"]
    assert hits and hits[0].actors == ("ego", "npc")
    assert result.outcome.status == "success", result.outcome.reason  # it was allowed
    first = hits[0].tick
    assert min(result.telemetry["ego"]["speed"][: first - 2]) == pytest.approx(60 * KPH, abs=0.3)


def test_its_own_speed_comes_back_when_the_car_ahead_leaves_the_lane(tmp_path):
    result = _run(tmp_path, text=EGO + NPC_LEAVES, duration="40s", leave="15s")
    assert result.outcome.status == "success", result.outcome.reason
    ego = result.telemetry["ego"]
    slowest = int(np.argmin(ego["speed"]))
    assert ego["speed"][slowest] < 25 * KPH  # it followed the npc
    assert ego["speed"][-1] == pytest.approx(60 * KPH, abs=0.5)  # and took its speed up again


def test_its_own_speed_outlasts_the_phase_it_followed_in(tmp_path):
    """A phase that ends while the vehicle follows leaves it its own speed, not the one it
    slowed to: the next phase that leaves the speed open takes it up once clear."""
    text = (
        HEADER
        + """\
        serial:
            ego.drive(duration: 20s) with:
                lane(1, at: start)
                position(distance: 20m, at: start)
                speed(60kph, at: start)
            ego.drive()
"""
        + NPC_LEAVES
    )
    result = _run(tmp_path, text=text, duration="45s", leave="25s")
    assert result.outcome.status == "success", result.outcome.reason
    ego = result.telemetry["ego"]
    second = result.event_ticks("start", "ego.drive")[1]
    assert ego["speed"][second] < 25 * KPH  # still behind the npc when the phase changed
    assert ego["speed"][-1] == pytest.approx(60 * KPH, abs=0.5)
