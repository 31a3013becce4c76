"""Paths and trajectories through points of the map, and relative ones (ASAM OpenSCENARIO
DSL 2.1 §8.12.2.1: ``create_path_*``, ``create_trajectory_*``, ``resolve_relative_*``;
§8.8: ``relative_path_st``, ``relative_path_odr`` and their trajectories).

A path's points may be world poses, route points (``s`` along a route, ``t`` left of
its reference line) or OpenDRIVE points (road, lane, ``s``, ``t``); every kind becomes
a world point on the map (``behaviours.maps``). How the points are joined:

* ``on_road_network: false`` (and world poses): straight lines, or a smooth curve
  through every point, in world coordinates (:class:`~osc2runner.sim.tracking.Polyline`);
* ``on_road_network: true``: **along the road** (:class:`~osc2runner.sim.tracking.RoadLine`):
  points on one road follow its reference line (in either direction of ``s``), points
  on several roads the lane the first point is in, through the lanes it leads into
  towards the later points' roads; between two points the offset from that line
  changes as the interpolation says. So a path through two points in one lane of a
  curved road follows the lane's curve, where a straight line would cut it.

Relative points (``relative_path_st``, ``relative_path_odr`` and the trajectories)
are offsets from the ``reference`` object where it is when the path is resolved (the
action's start, or the call of ``resolve_relative_*``): their ``s`` and ``t`` (an
OpenDRIVE point's road and lane are not read) are

* ``road_relative``: along and across its road: ``s`` more in its direction of
  travel, ``t`` more to the left, joined along the road;
* ``lane_relative``: the same, ``t`` measured from the centre of its lane;
* ``object_relative``: ``s`` ahead of it and ``t`` to its left, in its own axes;
* ``world_relative``: ``s`` along the world's x and ``t`` along its y, from it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import numpy as np

from osc2check.world.network import LaneRef, RoadNetwork
from osc2check.world.projection import lane_centre
from osc2check.world.tracking import PathCursor
from osc2runner.behaviours.base import ActionError, items, number
from osc2runner.behaviours.maps import OdrPoint, RoutePoint, map_point_xy
from osc2runner.compile.registry import method
from osc2runner.execution.context import RunContext, RunFault
from osc2runner.instance.actors import Actor
from osc2runner.sim.tracking import RoadLine
from osc2runner.structs import Orientation3d, Path, Pose3d, Position3d, member_number

__all__ = [
    "interpolation_of",
    "relative_points",
    "resolve_points",
    "road_line",
    "time_stamps_of",
]


def road_line(
    network: RoadNetwork, points: Sequence[tuple[float, float]], interpolation: str
) -> RoadLine:
    """The path through world ``points`` along the road (see the module docstring).

    Raises:
        ActionError: a point near no road, or points that do not follow one another along
            the road.
    """
    found = [network.to_road(x, y) for x, y in points]
    if any(p is None for p in found):
        k = next(i for i, p in enumerate(found) if p is None)
        raise ActionError(
            f"point {k + 1} of the path, ({points[k][0]:g}, {points[k][1]:g}), is "
            "near no road of the map"
        )
    roads = [p.road for p in found if p is not None]
    s = np.array([p.s for p in found if p is not None])
    t = np.array([p.t for p in found if p is not None])
    try:
        if len(set(roads)) == 1 and (np.all(np.diff(s) > 0) or np.all(np.diff(s) < 0)):
            return _along_reference_line(network, roads[0], s, t, interpolation)
        first = found[0]
        assert first is not None
        return _along_lanes(network, first.lane, points, roads, interpolation)
    except ValueError as exc:
        raise ActionError(str(exc)) from None


def _along_reference_line(
    network: RoadNetwork, road: str, s: np.ndarray, t: np.ndarray, interpolation: str
) -> RoadLine:
    """Points on one road, joined along its reference line in the direction of their ``s``."""
    direction = 1.0 if s[-1] > s[0] else -1.0
    along = np.union1d(np.arange(0.0, abs(s[-1] - s[0]), 0.5), [abs(s[-1] - s[0])])
    road_s = s[0] + direction * along
    index = np.full(len(road_s), network.road_ids.index(road))
    x, y, heading = network.road_to_world(index, road_s, np.zeros(len(road_s)))
    if direction < 0:
        heading = heading + math.pi
    heading = np.unwrap(heading)
    return RoadLine((along, x, y, heading), direction * (s - s[0]), direction * t, interpolation)


def _along_lanes(
    network: RoadNetwork,
    lane: LaneRef,
    points: Sequence[tuple[float, float]],
    roads: Sequence[str],
    interpolation: str,
) -> RoadLine:
    """Points on several roads, joined along the first point's lane and the lanes it leads
    into towards the later points' roads."""
    towards: list[str] = []
    for road in roads[1:]:
        if network.roads[road].junction is not None:
            continue  # inside a junction roads overlap: the roads after it decide the way
        if road != lane.road and (not towards or towards[-1] != road):
            towards.append(road)
    reach = sum(math.dist(a, b) for a, b in zip(points, points[1:], strict=False))
    route = network.route(
        lane, towards=towards, max_length=network.lane_path(lane).length + 2.0 * reach + 100.0
    )
    path = route.path
    cursor = PathCursor(path)
    located = [cursor.locate(x, y) for x, y in points]
    d = [p.distance for p in located]
    if any(b <= a for a, b in zip(d, d[1:], strict=False)):
        raise ValueError(
            "the points of the path do not follow one another along the road network "
            f"(the lane of the first point, {lane}, leads away from them)"
        )
    heading = np.unwrap(path.heading)
    return RoadLine(
        (path.distance, path.x, path.y, heading), d, [p.offset for p in located], interpolation
    )


def relative_points(
    ctx: RunContext, points: Sequence[object], reference: Actor, transform: str
) -> tuple[list[tuple[float, float]], bool]:
    """World points of relative route or OpenDRIVE points (``s``, ``t`` offsets) from where
    ``reference`` is now, and whether they are joined along the road (the road and lane
    frames)."""
    state = ctx.states[reference.name]
    offsets = [(member_number(p, "s"), member_number(p, "t")) for p in points]
    if transform in ("road_relative", "lane_relative"):
        if state.road is None or not state.direction:
            raise ActionError(
                f"`{reference.name}` is on no road: its road frame ({transform}) is not defined"
            )
        network = ctx.network
        direction = state.direction
        t0 = state.t
        if transform == "lane_relative" and state.lane_ref is not None:
            centre, _ = lane_centre(network, state.lane_ref, np.array([state.s]))
            t0 = float(centre[0])
        world = []
        for ds, dt in offsets:
            pose = network.to_world(state.road, state.s + direction * ds, t0 + direction * dt)
            world.append((pose.x, pose.y))
        return world, True
    if transform == "world_relative":
        return [(state.x + ds, state.y + dt) for ds, dt in offsets], False
    c, s = math.cos(state.yaw), math.sin(state.yaw)
    return [(state.x + c * ds - s * dt, state.y + s * ds + c * dt) for ds, dt in offsets], False


def _path_value(
    ctx: RunContext,
    points: Sequence[tuple[float, float]],
    interpolation: str,
    on_road: bool,
    time_stamps: Sequence[float] | None = None,
) -> Path:
    """A ``path`` (or, with time stamps, a ``trajectory``) through world ``points``: its
    points as world poses, and along the road its line (read by the path actions)."""
    poses = tuple(
        Pose3d(Position3d(x=x, y=y, z=0.0), Orientation3d(roll=0.0, pitch=0.0, yaw=0.0))
        for x, y in points
    )
    line = None
    if on_road:
        try:
            line = road_line(ctx.network, points, interpolation)
        except ActionError as exc:
            raise RunFault(str(exc)) from None
    stamps = tuple(float(t) for t in time_stamps) if time_stamps is not None else None
    return Path(poses, interpolation, stamps, line)


def _xy_all(ctx: RunContext, points: Iterable[object]) -> list[tuple[float, float]]:
    try:
        return [map_point_xy(ctx, p) for p in points]
    except ActionError as exc:
        raise RunFault(str(exc)) from None


@method("map", "create_path_odr_points")
@method("map", "create_path_route_points")
def create_path_through(
    ctx: RunContext, subject: object, points: object, interpolation: str, on_road_network: bool
) -> Path:
    """A ``path`` through OpenDRIVE or route points, along the road with
    ``on_road_network``."""
    return _path_value(ctx, _xy_all(ctx, items(points)), str(interpolation), bool(on_road_network))


@method("map", "create_trajectory_odr_points")
@method("map", "create_trajectory_route_points")
def create_trajectory_through(
    ctx: RunContext,
    subject: object,
    points: object,
    time_stamps: object,
    interpolation: str,
    on_road_network: bool,
) -> Path:
    """A ``trajectory`` through OpenDRIVE or route points with a time stamp each."""
    stamps = None if time_stamps is None else [number(t) for t in items(time_stamps)]
    return _path_value(
        ctx, _xy_all(ctx, items(points)), str(interpolation), bool(on_road_network), stamps
    )


def interpolation_of(value: object) -> str:
    """How a path or trajectory value's points are joined (a relative one's too)."""
    if isinstance(value, Path):
        return value.interpolation
    return str(getattr(value, "interpolation", "straight_line"))


def time_stamps_of(value: object) -> tuple[float, ...] | None:
    """A trajectory value's time stamps, s (a relative one's too); None for a path."""
    if isinstance(value, Path):
        return value.time_stamps
    stamps = getattr(value, "time_stamps", None)
    return None if stamps is None else tuple(float(t) for t in stamps)


def resolve_points(
    ctx: RunContext, value: object, reference: Actor, transform: str
) -> tuple[list[tuple[float, float]], bool]:
    """The world points of a relative path or trajectory from where ``reference`` is now,
    and whether they are joined along the road."""
    points = getattr(value, "points", None)
    if not points:
        raise ActionError("the path has no points")
    if isinstance(points[0], (RoutePoint, OdrPoint)) or _has_st(points[0]):
        return relative_points(ctx, points, reference, transform)
    state = ctx.states[reference.name]
    if transform == "world_relative":
        heading = 0.0
    elif transform in ("road_relative", "lane_relative"):
        from osc2runner.behaviours.driving import lane_heading

        heading = lane_heading(ctx, state)
    else:
        heading = state.yaw
    c, s = math.cos(heading), math.sin(heading)
    world = []
    for p in points:
        x, y = map_point_xy(ctx, p)
        world.append((state.x + c * x - s * y, state.y + s * x + c * y))
    return world, False


def _has_st(point: object) -> bool:
    return hasattr(point, "s") and hasattr(point, "t") and not hasattr(point, "position")


@method("map", "resolve_relative_path")
def resolve_relative_path(
    ctx: RunContext, subject: object, relative_path: object, reference: Actor, transform: str
) -> Path:
    """The absolute ``path`` of a relative one, from where ``reference`` is now."""
    return _resolved(ctx, relative_path, reference, transform, timed=False)


@method("map", "resolve_relative_trajectory")
def resolve_relative_trajectory(
    ctx: RunContext, subject: object, relative_trajectory: object, reference: Actor, transform: str
) -> Path:
    """The absolute ``trajectory`` of a relative one, from where ``reference`` is now."""
    return _resolved(ctx, relative_trajectory, reference, transform, timed=True)


def _resolved(
    ctx: RunContext, value: object, reference: Actor, transform: str, timed: bool
) -> Path:
    try:
        points, on_road = resolve_points(ctx, value, reference, str(transform))
    except ActionError as exc:
        raise RunFault(str(exc)) from None
    interpolation = interpolation_of(value)
    stamps = time_stamps_of(value) if timed else None
    if timed and stamps is None:
        raise RunFault("the relative trajectory has no time stamps")
    return _path_value(ctx, points, interpolation, on_road, stamps)
