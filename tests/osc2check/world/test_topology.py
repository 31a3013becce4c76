"""Lanes beside a lane, several lanes over."""

from __future__ import annotations

from pathlib import Path

from osc2check.world.network import LaneRef
from osc2check.world.opendrive import load_opendrive
from osc2check.world.topology import neighbour_n, side_neighbour
from osc2runner.instance.roads import LaneNumbers

FOUR_WAY = Path(__file__).resolve().parents[3] / "examples" / "maps" / "four_way_junction.xodr"


def test_neighbour_n_steps_over_the_centre_lane_and_stops_at_the_section_edge() -> None:
    network = load_opendrive(FOUR_WAY)  # lanes 2 1 | -1 -2 on the arms
    ref = LaneRef("1", 0, -2)
    assert neighbour_n(network, ref, 1, 0) == ref
    assert neighbour_n(network, ref, 1, 1) == LaneRef("1", 0, -1)
    assert neighbour_n(network, ref, 1, 2) == LaneRef("1", 0, 1)
    assert neighbour_n(network, ref, 1, 3) == LaneRef("1", 0, 2)
    assert neighbour_n(network, ref, 1, 4) is None
    assert neighbour_n(network, ref, -1, 1) is None
    assert neighbour_n(network, LaneRef("1", 0, 2), -1, 3) == ref
    assert neighbour_n(network, ref, 1, 1) == side_neighbour(network, ref, 1)


def test_lane_numbers_beside_is_a_driving_lane_the_same_way_or_none() -> None:
    network = load_opendrive(FOUR_WAY)
    lanes = LaneNumbers(network)
    ref = LaneRef("1", 0, -1)
    assert lanes.number(ref) == 1 and lanes.number(ref, "left") == 1
    assert lanes.beside(ref, "left") is None  # lane 1 travels the other way
    assert lanes.beside(ref, "right") is None  # the sidewalk
    assert lanes.beside(ref, "left", 0) == ref
