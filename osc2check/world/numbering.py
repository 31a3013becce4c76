"""OSC2 lane numbers: counting the driving lanes of one travel direction.

ASAM OpenSCENARIO DSL counts lanes from the right by default (``lane(1)`` is
the rightmost lane) or from the left, among the lanes a vehicle could drive in
its direction of travel. Here that means: in one lane section, take the lanes
whose type is a driving type and whose direction of travel is the same,
ordered from right to left *as seen in that direction*; number them from 1.
Opposing lanes, shoulders, borders and sidewalks are not counted; the
rightmost driving lane of a side is 1 whatever its OpenDRIVE id, and the same
rule holds under left-hand traffic, where the right lanes of a road travel
against ``s``.
"""

from __future__ import annotations

from typing import Literal

from osc2check.world.network import LaneRef, RoadNetwork

__all__ = [
    "LANE_REFERENCES",
    "driving_lanes_right_to_left",
    "lane_from_osc2_index",
    "lane_side",
    "osc2_lane_index",
]

#: The arguments of ``lane(...)`` that name another actor whose lane the actor's is
#: counted from; ``left_of``/``right_of`` are the standard's own examples' forms.
LANE_REFERENCES = ("same_as", "side_of", "left_of", "right_of")


def lane_side(reference: str, side: str | None) -> int:
    """Which way ``lane(<reference>: b, lane: n)`` counts from ``b``'s lane: +1 for ``n``
    lanes to the left, -1 to the right, 0 for ``b``'s own lane (``same_as``, where ``n``
    is not used). ``side_of`` goes to its ``side:`` (which the checker requires; left
    when absent); checker and runner both read it here."""
    if reference == "same_as":
        return 0
    if reference == "left_of":
        return 1
    if reference == "right_of":
        return -1
    return -1 if side in ("right", "outside") else 1  # right-hand traffic: outside is right


def driving_lanes_right_to_left(
    network: RoadNetwork, road_id: str, section: int, direction: int
) -> list[LaneRef]:
    """The driving lanes of a section travelling ``direction``, rightmost first."""
    lanes = [
        lane
        for lane in network.roads[road_id].sections[section].lanes
        if lane.drivable and lane.direction == direction
    ]
    # ``lanes`` runs left to right as seen along +s; travelling along +s the
    # rightmost is last, travelling against +s it is first.
    ordered = lanes[::-1] if direction > 0 else lanes
    return [lane.ref for lane in ordered]


def osc2_lane_index(
    network: RoadNetwork, ref: LaneRef, from_side: Literal["right", "left"] = "right"
) -> int:
    """The 1-based OSC2 number of driving lane ``ref`` counted from ``from_side``.

    Raises:
        ValueError: when ``ref`` is not a driving lane.
    """
    lane = network.lane(ref)
    if not lane.drivable:
        raise ValueError(f"{ref} is a `{lane.type}` lane, not a driving lane")
    order = driving_lanes_right_to_left(network, ref.road, ref.section, lane.direction)
    index = order.index(ref)
    return index + 1 if from_side == "right" else len(order) - index


def lane_from_osc2_index(
    network: RoadNetwork,
    road_id: str,
    s: float,
    index: int,
    direction: int = 1,
    from_side: Literal["right", "left"] = "right",
) -> LaneRef:
    """The driving lane numbered ``index`` (from ``from_side``) at ``s``, travelling ``direction``.

    ``direction`` is +1 for the lanes driving along the reference line, -1 for
    those driving against it.

    Raises:
        ValueError: when there is no such lane; the message says how many there are.
    """
    section = network.roads[road_id].section_at(s)
    order = driving_lanes_right_to_left(network, road_id, section.index, direction)
    if not 1 <= index <= len(order):
        way = "along" if direction > 0 else "against"
        raise ValueError(
            f"road `{road_id}` at s={s:g} has {len(order)} driving lane(s) {way} its "
            f"reference line, so lane {index} from the {from_side} does not exist"
        )
    return order[index - 1] if from_side == "right" else order[len(order) - index]
