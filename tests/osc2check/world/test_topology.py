"""Lanes beside a lane, several lanes over; the ways a road's ends link to."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from osc2check.world.network import LaneRef
from osc2check.world.opendrive import load_opendrive
from osc2check.world.topology import (
    end_lanes,
    linked_ways,
    neighbour_n,
    side_neighbour,
    travel_ways,
    way_label,
)
from osc2runner.instance.roads import LaneNumbers
from tests.osc2check.world.maptext import WIDTH, road_xml, xodr

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


def test_ways_into_and_out_of_a_junction() -> None:
    network = load_opendrive(FOUR_WAY)  # arm lane -1 drives along s into the junction
    ways = travel_ways(network)
    assert ways[:2] == (("1", 1), ("1", -1))
    assert [w for w in ways if w[0] == "101"] == [("101", 1)]  # one-way connecting road
    assert linked_ways(network, ("1", 1)) == {("101", 1), ("102", 1), ("103", 1)}
    assert linked_ways(network, ("1", -1), "previous") == {("106", 1), ("107", 1), ("111", 1)}
    assert linked_ways(network, ("1", 1), "previous") == set()  # the arm's far end
    assert linked_ways(network, ("1", -1)) == set()
    assert [way_label(w) for w in ways[:2]] == ["road 1", "road 1 (against s)"]


def test_end_lanes_are_taken_in_the_section_traffic_enters_or_leaves(
    write_map: Callable[..., Path],
) -> None:
    one = f'<lane id="-1" type="driving">{WIDTH}</lane>'
    two = one + f'<lane id="-2" type="driving">{WIDTH}</lane>'
    left = f'<left><lane id="1" type="driving">{WIDTH}</lane></left>'
    centre = '<center><lane id="0" type="none"/></center>'
    lanes = (
        f'<laneSection s="0">{left}{centre}<right>{one}</right></laneSection>'
        f'<laneSection s="50">{left}{centre}<right>{two}</right></laneSection>'
    )
    network = load_opendrive(write_map(xodr(road_xml(lanes=lanes))))
    assert end_lanes(network, "1", 1) == [LaneRef("1", 1, -1), LaneRef("1", 1, -2)]
    assert end_lanes(network, "1", 1, "entry") == [LaneRef("1", 0, -1)]
    assert end_lanes(network, "1", -1) == [LaneRef("1", 0, 1)]
    assert end_lanes(network, "1", -1, "entry") == [LaneRef("1", 1, 1)]
