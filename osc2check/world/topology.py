"""Lanes beside a lane, and the ways of travel a road's ends lead to.

Successors and predecessors (the lane graph across sections, road links and
junctions) are built once by :mod:`osc2check.world.layout` and stored on the
network; this module answers the lateral question, and which roads, driven
which way, the driving lanes at a road's ends link to (a *way* is a road and a
direction of travel on it, ``(road id, +1 or -1)``). Lane ids count outwards from
the centre lane, so the lane on the ``+t`` side of lane ``k`` is ``k + 1`` (or
``1`` after ``-1``: the centre lane 0 has no width). Left in the direction of
travel is the ``+t`` side for a lane driving along ``s`` and the ``-t`` side for
one driving against it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from osc2check.world.network import LaneRef, RoadNetwork

__all__ = [
    "Neighbours",
    "Way",
    "end_lanes",
    "linked_ways",
    "neighbour_n",
    "neighbours",
    "side_neighbour",
    "travel_ways",
    "way_label",
]

#: a road and a direction of travel on it (+1 along its ``s``, -1 against)
Way = tuple[str, int]


@dataclass(frozen=True, slots=True)
class Neighbours:
    """The lanes left and right of a lane, in its direction of travel.

    ``*_drivable`` is True when that neighbour's type is a driving type;
    ``*_same_direction`` when its traffic travels the same way (a lane change
    into it is not a move into oncoming traffic).
    """

    left: LaneRef | None
    right: LaneRef | None
    left_drivable: bool
    right_drivable: bool
    left_same_direction: bool
    right_same_direction: bool


def side_neighbour(network: RoadNetwork, ref: LaneRef, side: int) -> LaneRef | None:
    """The lane next to ``ref`` on the ``+t`` side (``side=+1``) or ``-t`` side (``-1``)."""
    other = ref.lane + side
    if other == 0:
        other = side
    section = network.section(ref)
    if section.lane(other) is None:
        return None
    return LaneRef(ref.road, ref.section, other)


def neighbour_n(network: RoadNetwork, ref: LaneRef, side: int, count: int) -> LaneRef | None:
    """The lane ``count`` lanes from ``ref`` on the ``+t`` (``side=+1``) or ``-t`` side
    (``-1``) in its section (``ref`` itself for 0; None when the section ends first)."""
    other = ref
    for _ in range(count):
        found = side_neighbour(network, other, side)
        if found is None:
            return None
        other = found
    return other


def neighbours(network: RoadNetwork, ref: LaneRef) -> Neighbours:
    """Left and right neighbours of ``ref`` in its direction of travel."""
    lane = network.lane(ref)
    left = side_neighbour(network, ref, lane.direction)
    right = side_neighbour(network, ref, -lane.direction)

    def drivable(other: LaneRef | None) -> bool:
        return other is not None and network.lane(other).drivable

    def same(other: LaneRef | None) -> bool:
        return other is not None and network.lane(other).direction == lane.direction

    return Neighbours(left, right, drivable(left), drivable(right), same(left), same(right))


def way_label(way: Way) -> str:
    """``road 3`` driven along its ``s``, ``road 3 (against s)`` the other way."""
    road, direction = way
    return f"road {road}" + ("" if direction > 0 else " (against s)")


def travel_ways(network: RoadNetwork) -> tuple[Way, ...]:
    """Every way with a driving lane, in road order, along ``s`` before against."""
    return tuple(
        (road.id, direction)
        for road in network.roads.values()
        for direction in (1, -1)
        if any(lane.drivable and lane.direction == direction for lane in road.lanes())
    )


def end_lanes(
    network: RoadNetwork, road_id: str, direction: int, end: Literal["entry", "exit"] = "exit"
) -> list[LaneRef]:
    """The driving lanes travelling ``direction`` in the lane section where traffic enters
    (``entry``) or leaves (``exit``) road ``road_id``, left to right as seen along ``s``."""
    sections = network.roads[road_id].sections
    section = sections[-1] if (direction > 0) == (end == "exit") else sections[0]
    return [lane.ref for lane in section.lanes if lane.drivable and lane.direction == direction]


def linked_ways(
    network: RoadNetwork, way: Way, towards: Literal["next", "previous"] = "next"
) -> set[Way]:
    """The ways on other roads that the driving lanes leaving ``way`` lead to (``next``),
    or that those entering it come from (``previous``)."""
    road, direction = way
    if towards == "next":
        lanes, links = end_lanes(network, road, direction, "exit"), network.next_lanes
    else:
        lanes, links = end_lanes(network, road, direction, "entry"), network.previous_lanes
    return {
        (other.road, network.lane(other).direction)
        for ref in lanes
        for other in links(ref)
        if other.road != road
    }
