"""Crossings of a road network: where an OpenDRIVE crosswalk starts and ends, and in which
lanes (ASAM OpenSCENARIO DSL 2.1 ``crossing``, ``map.crossing_connects``).

A crossing (:class:`~osc2check.world.network.Crossing`) runs along its object's length,
at ``hdg`` from the road's direction, from ``u = -length/2`` to ``u = +length/2`` about
its ``(s, t)``: its ends are at road coordinates ``(s + u cos hdg, t + u sin hdg)``. The
checker chooses a crossing for a ``crossing`` field (``verify.map_modifiers``); the runner
walks a person across it (``along(route: c)``).
"""

from __future__ import annotations

import math

import numpy as np

from osc2check.world.network import Crossing, LaneRef, RoadNetwork

__all__ = [
    "ANGLE_TOLERANCE",
    "crossing_angle",
    "crossing_ends",
    "crossing_lanes",
    "crossing_points",
]

#: how far (radians) a crossing's angle may be from a ``start_angle`` that names it: 1 degree
ANGLE_TOLERANCE = math.radians(1.0)


def crossing_angle(crossing: Crossing) -> float:
    """The angle (radians, 0 to pi) between the road's direction and the crossing
    (``map.crossing_connects``'s ``start_angle``: 90 degrees across the road)."""
    return abs(math.atan2(math.sin(crossing.hdg), math.cos(crossing.hdg)))


def crossing_ends(crossing: Crossing) -> tuple[tuple[float, float], tuple[float, float]]:
    """Road ``(s, t)`` of the crossing's start and end."""
    half = 0.5 * crossing.length
    ds, dt = half * math.cos(crossing.hdg), half * math.sin(crossing.hdg)
    return (crossing.s - ds, crossing.t - dt), (crossing.s + ds, crossing.t + dt)


def crossing_points(
    network: RoadNetwork, crossing: Crossing
) -> tuple[tuple[float, float], tuple[float, float]]:
    """World ``(x, y)`` of the crossing's start and end."""
    ends = []
    for s, t in crossing_ends(crossing):
        pose = network.to_world(crossing.road, s, t)
        ends.append((pose.x, pose.y))
    return ends[0], ends[1]


def crossing_lanes(network: RoadNetwork, crossing: Crossing) -> tuple[LaneRef, LaneRef]:
    """The lanes the crossing starts and ends in (of any type: sidewalks too; an end
    beyond the road's outer lane is in that lane)."""
    start, end = crossing_ends(crossing)
    return _lane_at(network, crossing.road, *start), _lane_at(network, crossing.road, *end)


def _lane_at(network: RoadNetwork, road_id: str, s: float, t: float) -> LaneRef:
    """The lane of road ``road_id`` that contains ``(s, t)``, counting out from the centre
    lane (its ``t`` the lane offset) on the side of ``t``."""
    road = network.roads[road_id]
    section = road.section_at(s)
    edge = float(np.interp(s, road.s, road.offset))
    side = 1 if t >= edge else -1
    ids = sorted((lane.id for lane in section.lanes if lane.id * side > 0), key=abs)
    if not ids:
        raise ValueError(f"road `{road_id}` has no lane on that side at s {s:.1f} m")
    for lane_id in ids:
        ref = LaneRef(road_id, section.index, lane_id)
        edge += side * float(network.width(ref, s))
        if side * (t - edge) <= 0.0:
            return ref
    return LaneRef(road_id, section.index, ids[-1])
