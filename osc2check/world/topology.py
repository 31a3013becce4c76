"""Lanes beside a lane: left and right neighbours in its direction of travel.

Successors and predecessors (the lane graph across sections, road links and
junctions) are built once by :mod:`osc2check.world.layout` and stored on the
network; this module answers the lateral question. Lane ids count outwards from
the centre lane, so the lane on the ``+t`` side of lane ``k`` is ``k + 1`` (or
``1`` after ``-1``: the centre lane 0 has no width). Left in the direction of
travel is the ``+t`` side for a lane driving along ``s`` and the ``-t`` side for
one driving against it.
"""

from __future__ import annotations

from dataclasses import dataclass

from osc2check.world.network import LaneRef, RoadNetwork

__all__ = ["Neighbours", "neighbour_n", "neighbours", "side_neighbour"]


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
