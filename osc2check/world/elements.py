"""The map as OSC2's map modifiers see it: roads, routes, lanes, junctions and their relations.

ASAM OpenSCENARIO DSL's ``map`` modifiers (``number_of_lanes``,
``roads_follow_in_junction``, ``lane_side``, ...) constrain fields of the types
``road``, ``route``, ``lane`` and ``junction``; the checker lets the solver
choose each such field among a map's elements, and the modifiers become tables
of the element combinations that satisfy them. This module makes those tables,
once per network:

* **roads**: every road id, connecting roads included;
* **routes**: every road together with a direction of travel that has driving
  lanes (``road 3`` along its ``s``, ``road 3 (against s)``): a route here is one
  road driven one way, the route element every longer route is made of;
* **lanes**: every driving lane (:class:`~osc2check.world.network.LaneRef`);
* **junctions**: every junction id;
* **turns** (:class:`JunctionTurn`): each way through a junction, from a lane of
  an incoming road over one connecting road to a lane of an outgoing road, with
  its direction (``straight``, ``left``, ``right``, ``u_turn``: the change of
  heading along the connecting lane, as :func:`.routes.turn_of` measures it), the
  number of roads the junction joins, and how many of them the outgoing road is
  from the incoming one counting clockwise.

How OpenDRIVE lane types map onto OSC2's ``lane_type`` and ``lane_use`` is
:data:`LANE_KINDS`; an OpenDRIVE type that is not there is ``other``/``other``.
"""

from __future__ import annotations

import math
from collections import defaultdict
from dataclasses import dataclass

from osc2check.world.network import LaneRef, RoadNetwork
from osc2check.world.paths import join_paths
from osc2check.world.routes import turn_along
from osc2check.world.topology import end_lanes, linked_ways, side_neighbour, travel_ways, way_label

__all__ = [
    "LANE_KINDS",
    "JunctionTurn",
    "MapElements",
    "lane_kind",
    "map_elements",
]

#: OpenDRIVE lane type -> (OSC2 lane_type, OSC2 lane_use)
LANE_KINDS: dict[str, tuple[str, str]] = {
    "driving": ("driving", "normal"),
    "bidirectional": ("driving", "normal"),
    "entry": ("driving", "entry"),
    "mwyEntry": ("driving", "entry"),
    "exit": ("driving", "exit"),
    "mwyExit": ("driving", "exit"),
    "onRamp": ("driving", "on_ramp"),
    "offRamp": ("driving", "off_ramp"),
    "connectingRamp": ("driving", "connecting_ramp"),
    "HOV": ("driving", "hov"),
    "bus": ("driving", "bus"),
    "taxi": ("driving", "other"),
    "slipLane": ("driving", "other"),
    "parking": ("non_driving", "parking"),
    "stop": ("non_driving", "stop"),
    "restricted": ("non_driving", "restricted"),
    "border": ("non_driving", "border"),
    "shoulder": ("non_driving", "shoulder"),
    "curb": ("non_driving", "curb"),
    "median": ("non_driving", "median"),
    "none": ("non_driving", "none"),
    "biking": ("vru_vehicles", "bicycle"),
    "sidewalk": ("pedestrian", "sidewalk"),
    "walking": ("pedestrian", "sidewalk"),
}

_TURN_WORDS = {"straight": "straight", "left": "left", "right": "right", "u-turn": "u_turn"}


def lane_kind(opendrive_type: str) -> tuple[str, str]:
    """OSC2 ``(lane_type, lane_use)`` of an OpenDRIVE lane type."""
    return LANE_KINDS.get(opendrive_type, ("other", "other"))


@dataclass(frozen=True, slots=True)
class JunctionTurn:
    """One way through a junction: ``in_lane`` over ``connecting`` into ``out_lane``."""

    junction: str
    in_road: str
    out_road: str
    connecting: tuple[str, int]  # the connecting road and the direction it is driven
    direction: str  # OSC2 junction_direction: straight, left, right, u_turn
    clockwise_count: int
    number_of_roads: int
    in_lane: LaneRef
    out_lane: LaneRef
    in_route: tuple[str, int]
    out_route: tuple[str, int]


@dataclass(frozen=True, eq=False)
class MapElements:
    """The element lists and relations of one network (see the module docstring)."""

    roads: tuple[str, ...]
    routes: tuple[tuple[str, int], ...]
    lanes: tuple[LaneRef, ...]
    junctions: tuple[str, ...]
    turns: tuple[JunctionTurn, ...]

    def route_label(self, route: tuple[str, int]) -> str:
        return way_label(route)

    @staticmethod
    def lane_label(ref: LaneRef) -> str:
        section = f" (section {ref.section})" if ref.section else ""
        return f"road {ref.road} lane {ref.lane}{section}"

    def lane_counts(
        self,
        network: RoadNetwork,
        lane_type: str,
        lane_use: str | None,
        both_directions: bool,
    ) -> dict[tuple[str, int], int]:
        """Routes whose lanes of ``lane_type`` (and ``lane_use``, unless None) number the
        same in every lane section, and that number; lanes travelling the route's way,
        or either way with ``both_directions``. Routes whose count changes are left out."""
        counts: dict[tuple[str, int], int] = {}
        for road_id, direction in self.routes:
            found: set[int] = set()
            for section in network.roads[road_id].sections:
                n = 0
                for lane in section.lanes:
                    kind, use = lane_kind(lane.type)
                    if kind != lane_type or (lane_use is not None and use != lane_use):
                        continue
                    if both_directions or lane.direction == direction:
                        n += 1
                found.add(n)
            if len(found) == 1:
                counts[(road_id, direction)] = found.pop()
        return counts

    def sequences(self, network: RoadNetwork) -> set[tuple[tuple[str, int], tuple[str, int]]]:
        """Pairs of routes where a lane leaving the first enters the second directly."""
        return {(route, after) for route in self.routes for after in linked_ways(network, route)}

    def lane_sides(self, network: RoadNetwork) -> set[tuple[LaneRef, str, LaneRef, int]]:
        """``(lane1, side, lane2, count)``: ``lane1`` is ``count`` lanes to ``side`` of
        ``lane2`` in ``lane2``'s direction of travel, in one lane section."""
        known = set(self.lanes)
        found: set[tuple[LaneRef, str, LaneRef, int]] = set()
        for ref in self.lanes:
            direction = network.lane(ref).direction
            for side, step in (("left", direction), ("right", -direction)):
                other: LaneRef | None = ref
                count = 0
                while other is not None:
                    other = side_neighbour(network, other, step)
                    count += 1
                    if other is not None and other in known:
                        found.add((other, side, ref, count))
        return found

    def lane_ends(self, network: RoadNetwork, end: str) -> set[LaneRef]:
        """Driving lanes that start (``end="start"``) or end (``"end"``) while the lanes
        beside them go on: no predecessor (successor) where another lane of their section
        travelling their way has one."""
        found: set[LaneRef] = set()
        for ref in self.lanes:
            links = network.previous_lanes if end == "start" else network.next_lanes
            if links(ref):
                continue
            lane = network.lane(ref)
            section = network.section(ref)
            if any(
                other.drivable and other.direction == lane.direction and links(other.ref)
                for other in section.lanes
                if other.ref != ref
            ):
                found.add(ref)
        return found


def map_elements(network: RoadNetwork) -> MapElements:
    """The :class:`MapElements` of ``network`` (built on first use, then cached on it)."""
    cached = network.cache.get("elements")
    if not isinstance(cached, MapElements):
        cached = network.cache["elements"] = _build(network)
    return cached


def _build(network: RoadNetwork) -> MapElements:
    return MapElements(
        roads=network.road_ids,
        routes=travel_ways(network),
        lanes=tuple(lane.ref for lane in network.driving_lanes()),
        junctions=tuple(network.junctions),
        turns=tuple(_turns(network)),
    )


def _junction_roads(network: RoadNetwork) -> dict[str, list[tuple[str, float]]]:
    """Per junction: the roads that link to it and their bearing from its centre."""
    ends: dict[str, list[tuple[str, float, float]]] = defaultdict(list)
    for road in network.roads.values():
        if road.junction is not None:
            continue
        for link, index in ((road.predecessor, 0), (road.successor, -1)):
            if link is not None and link.element_type == "junction":
                ends[link.element_id].append((road.id, float(road.x[index]), float(road.y[index])))
    result: dict[str, list[tuple[str, float]]] = {}
    for junction, found in ends.items():
        cx = sum(x for _, x, _ in found) / len(found)
        cy = sum(y for _, _, y in found) / len(found)
        result[junction] = [(road, math.atan2(y - cy, x - cx)) for road, x, y in found]
    return result


def _turns(network: RoadNetwork) -> list[JunctionTurn]:
    around = _junction_roads(network)
    turns: list[JunctionTurn] = []
    for road in network.roads.values():
        if road.junction is not None:
            continue
        for direction in (1, -1):
            for in_lane in end_lanes(network, road.id, direction):
                for first in network.next_lanes(in_lane):
                    junction = network.roads[first.road].junction
                    if junction is None:
                        continue
                    # follow the connecting road's lanes (its sections) to the road after it
                    inside = [first]
                    while True:
                        after = [r for r in network.next_lanes(inside[-1]) if r.road == first.road]
                        if not after or after[0] in inside:
                            break
                        inside.append(after[0])
                    for out_lane in network.next_lanes(inside[-1]):
                        out_road = network.roads[out_lane.road]
                        if out_road.junction is not None:
                            continue
                        roads = around.get(junction, [])
                        turns.append(_turn(network, roads, junction, in_lane, inside, out_lane))
    return turns


def _turn(
    network: RoadNetwork,
    around: list[tuple[str, float]],
    junction: str,
    in_lane: LaneRef,
    inside: list[LaneRef],
    out_lane: LaneRef,
) -> JunctionTurn:
    connecting = inside[0]
    word = turn_along(join_paths([network.lane_path(ref) for ref in inside]))
    clockwise = sorted((road for road in around), key=lambda rb: -rb[1])
    names = [road for road, _ in clockwise]
    count = 0
    if in_lane.road in names and out_lane.road in names:
        count = (names.index(out_lane.road) - names.index(in_lane.road)) % len(names)
    return JunctionTurn(
        junction=junction,
        in_road=in_lane.road,
        out_road=out_lane.road,
        connecting=(connecting.road, network.lane(connecting).direction),
        direction=_TURN_WORDS[word],
        clockwise_count=count,
        number_of_roads=len(names),
        in_lane=in_lane,
        out_lane=out_lane,
        in_route=(in_lane.road, network.lane(in_lane).direction),
        out_route=(out_lane.road, network.lane(out_lane).direction),
    )
