"""The map at run time: `along`, the map modifiers, and the map methods.

The checker chose every road, route, lane and junction field among the map's
elements (``osc2check.verify.map_modifiers``); the witness gives each one
(:class:`~osc2check.verify.map_modifiers.ElementValue`), so the map modifiers
(``number_of_lanes``, ``roads_follow_in_junction``, ...) are realised before the
run starts and have nothing left to do in it.

Values the map methods make (ASAM OpenSCENARIO DSL 2.1 §8.12.2):

* :class:`RoutePoint` ``(route, s, t)``: a point on a route, which here is a road
  driven one way (``route.road``, ``route.direction``); ``s`` runs along the
  direction of travel from the route's start, ``t`` to the left of the road's
  reference line as seen in that direction (a route driven along the road's ``s``
  has the road's coordinates; one driven against it ``length - s`` and ``-t``);
* :class:`OdrPoint` ``(road_id, lane_id, s, t)``: OpenDRIVE road coordinates; with a
  lane id, ``t`` is measured from that lane's centre, else from the reference line;
* :class:`XyzPoint` ``(position)``: world coordinates (``position.x``, ``.y``, ``.z``);
* :class:`CompoundRoute` ``(route_elements)``: routes one after the other.

``along(route: r)`` with a map route makes the actor's lane following pass the
roads of ``r`` (its route through the forks ahead is re-planned when the phase
starts; at time 0 the witness placed the actor on ``r`` already): the `along`
modifier (``behaviours.paths``) calls :func:`follow_route` for such a route.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from osc2check.verify.map_modifiers import ElementValue
from osc2check.world.crossings import crossing_points
from osc2check.world.network import LaneRef
from osc2check.world.projection import lane_centre
from osc2runner.behaviours.base import ActionBehaviour, ActionError, Modifier, number
from osc2runner.compile.registry import method, modifier
from osc2runner.execution.context import RunContext, RunFault
from osc2runner.execution.controls import is_vehicle
from osc2runner.instance.actors import Actor
from osc2runner.sim.tracking import Polyline
from osc2runner.structs import Position3d, XyzPoint, member_number

__all__ = [
    "CompoundRoute",
    "OdrPoint",
    "RoutePoint",
    "XyzPoint",
    "crossing_path",
    "follow_route",
    "is_map_route",
    "map_point_xy",
    "odr_coordinates",
    "route_coordinates",
    "route_holds",
]


@dataclass(frozen=True, slots=True)
class RoutePoint:
    """A point on a route: ``s`` along it from its start, ``t`` left of the reference line
    in its direction of travel."""

    route: ElementValue
    s: float
    t: float


@dataclass(frozen=True, slots=True)
class OdrPoint:
    """OpenDRIVE road coordinates (``t`` from the lane centre when ``lane_id`` is given)."""

    road_id: str
    lane_id: str
    s: float
    t: float


@dataclass(frozen=True, slots=True)
class CompoundRoute:
    """Routes one after the other."""

    route_elements: tuple[object, ...]

    @property
    def roads(self) -> tuple[str, ...]:
        found: list[str] = []
        for element in self.route_elements:
            found.extend(roads_of(element))
        return tuple(found)


def roads_of(value: object) -> tuple[str, ...]:
    """The roads a route value runs over, in order."""
    if isinstance(value, CompoundRoute):
        return value.roads
    if isinstance(value, RoutePoint):
        return roads_of(value.route)
    if isinstance(value, ElementValue) and value.road:
        return (value.road,)
    if isinstance(value, OdrPoint):
        return (value.road_id,)
    return ()


def _route_length(ctx: RunContext, route: ElementValue) -> float:
    return ctx.network.roads[route.road].length


def route_coordinates(ctx: RunContext, point: RoutePoint) -> tuple[str, float, float]:
    """``(road, s, t)`` of a route point (a fault when its route is not a road of the map)."""
    route = point.route
    if not route.road:
        raise RunFault(f"{route.label} is not a route")
    if route.direction >= 0:
        return route.road, point.s, point.t
    return route.road, _route_length(ctx, route) - point.s, -point.t


def _on_route(ctx: RunContext, road: str, s: float, t: float, direction: int) -> RoutePoint:
    route = ElementValue("route", road=road, direction=direction or 1)
    if direction >= 0:
        return RoutePoint(route, s, t)
    return RoutePoint(route, ctx.network.roads[road].length - s, -t)


def odr_coordinates(ctx: RunContext, point: OdrPoint) -> tuple[str, float, float]:
    """``(road, s, t)`` of an OpenDRIVE point (a fault for a road or lane the map lacks)."""
    road = point.road_id
    if road not in ctx.network.roads:
        raise RunFault(f"the map has no road `{road}`")
    t = point.t
    if point.lane_id not in ("", None):
        try:
            ref = ctx.network.lane_at(road, point.s, int(point.lane_id))
        except (KeyError, ValueError):
            raise RunFault(
                f"road `{road}` has no lane `{point.lane_id}` at s = {point.s:g} m"
            ) from None
        centre, _ = lane_centre(ctx.network, ref, np.array([point.s]))
        t = float(centre[0]) + t
    return road, point.s, t


def map_point_xy(ctx: RunContext, point: object) -> tuple[float, float]:
    """World x, y of a route point, an OpenDRIVE point, an ``xyz_point``, a ``pose_3d`` or a
    ``position_3d``."""
    if isinstance(point, RoutePoint):
        pose = ctx.network.to_world(*route_coordinates(ctx, point))
        return pose.x, pose.y
    if not isinstance(point, OdrPoint) and hasattr(point, "road_id"):  # a struct parameter
        point = OdrPoint(
            str(point.road_id),
            str(getattr(point, "lane_id", "") or ""),
            float(getattr(point, "s", 0.0)),
            float(getattr(point, "t", 0.0)),
        )
    if isinstance(point, OdrPoint):
        pose = ctx.network.to_world(*odr_coordinates(ctx, point))
        return pose.x, pose.y
    if hasattr(point, "position") and not hasattr(point, "x"):
        point = point.position
    try:
        return member_number(point, "x"), member_number(point, "y")
    except TypeError:
        raise ActionError(f"`{point!r}` is not a position (it has no x and y)") from None


def _xyz(ctx: RunContext, road: str, s: float, t: float) -> XyzPoint:
    pose = ctx.network.to_world(road, s, t)
    return XyzPoint(Position3d(x=pose.x, y=pose.y, z=0.0))


# ---------------------------------------------------------------------- along


def crossing_path(ctx: RunContext, value: object, x: float, y: float) -> Polyline | None:
    """``along(route: c)`` of a crossing the witness chose, from ``(x, y)``: to the end of
    the crossing nearer to it, then straight across to the other end (**choice**: a
    person crosses from the kerb it stands at, either way); None for another value."""
    if not isinstance(value, ElementValue) or value.kind != "crossing":
        return None
    crossing = next(c for c in ctx.network.crossings if c.id == value.crossing)
    a, b = crossing_points(ctx.network, crossing)
    if math.hypot(b[0] - x, b[1] - y) < math.hypot(a[0] - x, a[1] - y):
        a, b = b, a
    approach = [(x, y)] if math.hypot(a[0] - x, a[1] - y) > 0.1 else []
    return Polyline([*approach, a, b], "straight_line")


def is_map_route(value: object) -> bool:
    """Whether an `along` route is the map's (a road, route, lane, compound route or route
    point) rather than a world path."""
    if isinstance(value, ElementValue) and value.kind == "crossing":
        return False  # walked across (crossing_path)
    return bool(roads_of(value)) and not hasattr(value, "points")


def follow_route(modifier: Modifier, action: ActionBehaviour) -> None:
    """``along(route: r)`` with a map route: the actor's lane following passes the roads of
    ``r`` (the route through the forks ahead is re-planned when the phase starts).
    ``end_offset`` is not supported."""
    if number(modifier.args.get("end_offset", 0.0) or 0.0) != 0.0:
        raise ActionError("along(end_offset: ...) on a map route is not supported")
    roads = roads_of(modifier.args.get("route"))
    ctrl = action.controller
    if not is_vehicle(ctrl):
        return  # a walker: along is checked, not steered
    lateral = ctrl.lateral
    lateral.set_route(roads)
    state = action.state
    ref = state.lane_ref
    if ref is not None and action.ctx.network.lane(ref).drivable and state.road not in roads[1:]:
        offset = lateral.path.at(0.0)[0] if lateral.path is not None else state.offset
        lateral.keep_lane(ref, offset if math.isfinite(offset) else 0.0)


def route_holds(modifier: Modifier, action: ActionBehaviour) -> str | None:
    """Whether the actor is on one of the roads of an `along` map route now."""
    roads = roads_of(modifier.args.get("route"))
    road = action.state.road
    if road in roads:
        return None
    return f"it is on road `{road}`, not on {', '.join(f'`{r}`' for r in roads)}"


# ---------------------------------------------------------------------- map modifiers

_REALISED = "scenario member: the checker chose the map elements"


def realised(name: str, note: str = _REALISED, module: str = __name__) -> type[Modifier]:
    """The runner's entry of ``map.name(...)`` that the witness realises: nothing to do
    during the run (``module`` is where the entry is registered from)."""
    cls = type(
        "".join(part.title() for part in name.split("_")),
        (Modifier,),
        {
            "__doc__": f"``map.{name}(...)``: realised by the witness (the checker chose "
            "where it holds); nothing to do during the run.",
            "__module__": module,
        },
    )
    return modifier(name, actor="map", note=note)(cls)


NumberOfLanes = realised("number_of_lanes")
RoutesAreInSequence = realised("routes_are_in_sequence")
RoadsFollowInJunction = realised("roads_follow_in_junction")
RoutesOverlap = realised("routes_overlap")
RoutesAreOpposite = realised("routes_are_opposite")
LaneSide = realised("lane_side")
CompoundLaneSide = realised("compound_lane_side")
StartLane = realised("start_lane")
EndLane = realised("end_lane")
CrossingConnects = realised("crossing_connects")


# ---------------------------------------------------------------------- map methods


@method("map", "get_map_file")
def get_map_file(ctx: RunContext, subject: object) -> str:
    """The map in use: the OpenDRIVE file read, or the built-in map's name."""
    return ctx.network.source or ctx.network.name


@method("map", "outer_side")
def outer_side(ctx: RunContext, subject: object) -> str:
    """The side of the road away from opposing traffic: right under right-hand traffic."""
    rules = {road.rule for road in ctx.network.roads.values()}
    return "left" if rules == {"LHT"} else "right"


@method("map", "inner_side")
def inner_side(ctx: RunContext, subject: object) -> str:
    """The side of the road towards opposing traffic."""
    return "right" if outer_side(ctx, subject) == "left" else "left"


@method("map", "create_route_point")
def create_route_point(
    ctx: RunContext, subject: object, route: object, s: float, t: float
) -> RoutePoint:
    if isinstance(route, ElementValue) and route.kind in ("road", "lane"):
        direction = route.direction or 1
        if route.kind == "lane":
            ref = LaneRef(route.road, route.section, route.lane)
            direction = ctx.network.lane(ref).direction
        route = ElementValue("route", road=route.road, direction=direction)
    if not isinstance(route, ElementValue) or not route.road:
        raise RunFault("create_route_point needs a road, route or lane of the map")
    return RoutePoint(route, float(s), float(t))


@method("map", "create_odr_point")
def create_odr_point(
    ctx: RunContext, subject: object, road_id: str, lane_id: str, s: float, t: float
) -> OdrPoint:
    point = OdrPoint(str(road_id), str(lane_id), float(s), float(t))
    odr_coordinates(ctx, point)  # a road or lane the map lacks is a fault here
    return point


@method("map", "odr_to_route_point")
def odr_to_route_point(
    ctx: RunContext, subject: object, road_id: str, lane_id: str, s: float, t: float
) -> RoutePoint:
    """The route point of OpenDRIVE coordinates: on the road, in the direction of travel
    of the lane (of the lane at ``t`` when no lane is given)."""
    road, s_road, t_road = odr_coordinates(ctx, OdrPoint(str(road_id), str(lane_id), s, t))
    pose = ctx.network.to_world(road, s_road, t_road)
    found = ctx.network.to_road(pose.x, pose.y)
    direction = ctx.network.lane(found.lane).direction if found is not None else 1
    return _on_route(ctx, road, s_road, t_road, direction)


@method("map", "xyz_to_route_point")
def xyz_to_route_point(
    ctx: RunContext, subject: object, x: float, y: float, z: float
) -> RoutePoint:
    """The route point of a world point: the road and lane it is on (the nearest within
    the search margin); a point near no road is a fault."""
    found = ctx.network.to_road(float(x), float(y))
    if found is None:
        raise RunFault(f"({x:g}, {y:g}) is near no road of the map")
    direction = ctx.network.lane(found.lane).direction
    return _on_route(ctx, found.road, found.s, found.t, direction)


@method("map", "route_point_to_xyz")
def route_point_to_xyz(ctx: RunContext, subject: object, route_point: RoutePoint) -> XyzPoint:
    return _xyz(ctx, *route_coordinates(ctx, route_point))


@method("map", "create_route")
def create_route(
    ctx: RunContext,
    subject: object,
    routes: object,
    connect_points_by: str = "road",
    legal_route: bool = True,
) -> CompoundRoute:
    """Routes one after the other; with ``legal_route``, each road must be reachable from
    the one before in the direction of travel (else a fault)."""
    elements = tuple(routes) if isinstance(routes, (list, tuple)) else (routes,)
    compound = CompoundRoute(elements)
    roads = compound.roads
    if legal_route:
        for a, b in zip(roads, roads[1:], strict=False):
            if not _leads(ctx, a, b):
                raise RunFault(f"no lane leads from road `{a}` to road `{b}`")
    return compound


def _leads(ctx: RunContext, a: str, b: str) -> bool:
    """Whether a driving lane of road ``a`` leads to road ``b`` (through junctions)."""
    from osc2check.world.routes import reachable_lanes

    network = ctx.network
    for lane in network.roads[a].lanes():
        if not lane.drivable:
            continue
        for span in reachable_lanes(
            network, lane.ref, 0.0 if lane.direction > 0 else network.roads[a].length, 1000.0
        ):
            if span.lane.road == b:
                return True
    return False


@method("route", "start_point")
def start_point(ctx: RunContext, subject: object) -> RoutePoint:
    route = _as_route(ctx, subject)
    return RoutePoint(route, 0.0, 0.0)


@method("route", "end_point")
def end_point(ctx: RunContext, subject: object) -> RoutePoint:
    route = _as_route(ctx, subject)
    return RoutePoint(route, _route_length(ctx, route), 0.0)


def _as_route(ctx: RunContext, value: object) -> ElementValue:
    if isinstance(value, ElementValue) and value.road:
        if value.kind == "route":
            return value
        direction = 1
        if value.kind == "lane":
            direction = ctx.network.lane(LaneRef(value.road, value.section, value.lane)).direction
        return ElementValue("route", road=value.road, direction=direction)
    raise RunFault("this is not a route of the map")


@method("physical_object", "get_route_point")
def get_route_point(ctx: RunContext, subject: Actor, route_type: str = "on_road") -> RoutePoint:
    """Where the subject is, as a point on the road it is on, in its lane's direction."""
    state = ctx.states[subject.name]
    if state.road is None:
        raise RunFault(f"`{subject.name}` is on no road")
    return _on_route(ctx, state.road, state.s, state.t, state.direction)


@method("physical_object", "distance_to_route_point")
def distance_to_route_point(
    ctx: RunContext,
    subject: Actor,
    point: RoutePoint,
    direction: str = "longitudinal",
    mode: str = "reference_points",
    route_type: str = "on_road",
) -> float:
    return _distance_to(ctx, subject, *route_coordinates(ctx, point), direction)


@method("physical_object", "distance_to_odr_point")
def distance_to_odr_point(
    ctx: RunContext,
    subject: Actor,
    point: OdrPoint,
    direction: str = "longitudinal",
    mode: str = "reference_points",
    route_type: str = "on_road",
) -> float:
    return _distance_to(ctx, subject, *odr_coordinates(ctx, point), direction)


def _distance_to(
    ctx: RunContext, subject: Actor, road: str, s: float, t: float, direction: str
) -> float:
    """Along ``s`` (or across, ``t``) in the subject's direction of travel on one road;
    along (across) its heading to a point on another road."""
    me = ctx.states[subject.name]
    if me.road == road and me.direction:
        return (t - me.t) * me.direction if direction == "lateral" else (s - me.s) * me.direction
    pose = ctx.network.to_world(road, s, t)
    dx, dy = pose.x - me.x, pose.y - me.y
    c, sn = math.cos(me.yaw), math.sin(me.yaw)
    return -dx * sn + dy * c if direction == "lateral" else dx * c + dy * sn


@method("movable_object", "distance_along_route")
def distance_along_route(
    ctx: RunContext, subject: Actor, route: object, from_: str = "from_start"
) -> float:
    """How far along ``route`` the subject is (from its start, or to its end with
    ``from_end``); a subject on none of the route's roads is a fault."""
    state = ctx.states[subject.name]
    roads = roads_of(route)
    if state.road not in roads:
        raise RunFault(f"`{subject.name}` is not on the route (roads {', '.join(roads)})")
    network = ctx.network
    direction = (
        route.direction
        if isinstance(route, ElementValue) and route.direction
        else (state.direction or 1)
    )
    before = 0.0
    for road in roads:
        length = network.roads[road].length
        if road == state.road:
            along = state.s if direction > 0 else length - state.s
            total = before + along
            if from_ == "from_end":
                rest = sum(network.roads[r].length for r in roads[roads.index(road) + 1 :])
                return length - along + rest
            return total
        before += length
    return before
