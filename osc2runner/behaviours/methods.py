"""Methods of the domain model that the runner implements (``is undefined`` in the library).

Each is ``fn(ctx, subject, *arguments)`` with arguments in declaration order
(defaults filled in by the compiler); distances in metres, times in seconds.
Reference points are the bounding-box centres the world reports; ``bounding_boxes``
mode measures between the boxes along the asked axis.
"""

from __future__ import annotations

import datetime
import math

from osc2runner.behaviours.driving import gap_between
from osc2runner.compile.expressions import PositionOf
from osc2runner.compile.registry import method
from osc2runner.execution.context import RunContext, RunFault
from osc2runner.instance.actors import Actor
from osc2runner.structs import member_number

__all__ = [
    "ahead_of",
    "norm",
    "get_s_coord",
    "get_t_coord",
    "object_distance",
    "road_distance",
    "space_gap",
    "space_headway",
    "time_gap",
    "time_headway",
    "time_to_collision",
]


def _shrink(distance: float, extent: float) -> float:
    """A centre distance made a box distance: ``extent`` less, never past zero."""
    if distance >= 0.0:
        return max(distance - extent, 0.0)
    return min(distance + extent, 0.0)


@method("physical_object", "object_distance")
def object_distance(
    ctx: RunContext,
    subject: Actor,
    reference: Actor,
    direction: str,
    mode: str = "reference_points",
) -> float:
    """Distance to ``reference`` in the subject's frame (positive: reference in front / left)."""
    me, other = ctx.states[subject.name], ctx.states[reference.name]
    dx, dy = other.x - me.x, other.y - me.y
    c, s = math.cos(me.yaw), math.sin(me.yaw)
    lon, lat = dx * c + dy * s, -dx * s + dy * c
    boxes = mode == "bounding_boxes"
    if direction == "longitudinal":
        return _shrink(lon, 0.5 * (me.length + other.length)) if boxes else lon
    if direction == "lateral":
        return _shrink(lat, 0.5 * (me.width + other.width)) if boxes else lat
    if direction == "vertical":
        return 0.0
    if boxes:
        return math.hypot(
            _shrink(lon, 0.5 * (me.length + other.length)),
            _shrink(lat, 0.5 * (me.width + other.width)),
        )
    return math.hypot(lon, lat)


@method("physical_object", "road_distance")
def road_distance(
    ctx: RunContext,
    subject: Actor,
    reference: Actor,
    direction: str,
    mode: str = "reference_points",
    route_type: str = "on_road",
) -> float:
    """Distance to ``reference`` in road coordinates: along ``s`` (longitudinal,
    positive ahead in the subject's direction of travel) or ``t`` (lateral, positive to
    the subject's left) when both are on one road; along and across the subject's
    heading when they are on different roads (through a junction)."""
    me, other = ctx.states[subject.name], ctx.states[reference.name]
    boxes = mode == "bounding_boxes"
    same = me.road is not None and me.road == other.road and me.direction != 0
    if direction == "lateral":
        if same:
            d = (other.t - me.t) * me.direction
        else:
            d = -(other.x - me.x) * math.sin(me.yaw) + (other.y - me.y) * math.cos(me.yaw)
        return _shrink(d, 0.5 * (me.width + other.width)) if boxes else d
    d = gap_between(me, other, bumpers=False)
    return _shrink(d, 0.5 * (me.length + other.length)) if boxes else d


@method("physical_object", "get_s_coord")
def get_s_coord(ctx: RunContext, subject: Actor, route_type: str = "on_road") -> float:
    """The ``s`` of the subject on the road it is on (NaN off the roads)."""
    return ctx.states[subject.name].s


@method("physical_object", "get_t_coord")
def get_t_coord(ctx: RunContext, subject: Actor, route_type: str = "on_road") -> float:
    """The ``t`` of the subject on the road it is on, left of its reference line (NaN
    off the roads)."""
    return ctx.states[subject.name].t


@method("actor_position", "ahead_of")
def ahead_of(ctx: RunContext, subject: PositionOf, reference: Actor) -> float:
    """(Toolkit) the subject's position projected on the reference's heading, from the reference."""
    me = ctx.states[subject.actor.name]  # type: ignore[attr-defined]
    ref = ctx.states[reference.name]
    return (me.x - ref.x) * math.cos(ref.yaw) + (me.y - ref.y) * math.sin(ref.yaw)


@method("position_3d", "norm")
@method("translational_velocity_3d", "norm")
@method("translational_acceleration_3d", "norm")
def norm(ctx: RunContext, subject: object) -> float:
    """Euclidean length of a 3-D vector struct (``hero.velocity.translational.norm()``)."""
    return math.sqrt(sum(member_number(subject, k) ** 2 for k in ("x", "y", "z")))


@method("traffic_participant", "space_gap")
def space_gap(
    ctx: RunContext, subject: Actor, reference: Actor, direction: str = "longitudinal"
) -> float:
    """Bumper-to-bumper gap along the road (positive: the reference ahead / left)."""
    return road_distance(ctx, subject, reference, direction, "bounding_boxes")


@method("traffic_participant", "time_gap")
def time_gap(
    ctx: RunContext, subject: Actor, reference: Actor, direction: str = "longitudinal"
) -> float:
    """The space gap divided by the subject's speed (infinite at standstill)."""
    speed = ctx.states[subject.name].speed
    gap = space_gap(ctx, subject, reference, direction)
    return gap / speed if speed > 1e-6 else math.copysign(math.inf, gap)


@method("traffic_participant", "space_headway")
def space_headway(ctx: RunContext, subject: Actor, reference: Actor) -> float:
    """Distance between reference points along the road (positive: the reference ahead)."""
    return road_distance(ctx, subject, reference, "longitudinal")


@method("traffic_participant", "time_headway")
def time_headway(ctx: RunContext, subject: Actor, reference: Actor) -> float:
    speed = ctx.states[subject.name].speed
    d = space_headway(ctx, subject, reference)
    return d / speed if speed > 1e-6 else math.copysign(math.inf, d)


@method("traffic_participant", "time_to_collision")
def time_to_collision(ctx: RunContext, subject: Actor, reference: Actor) -> float:
    """Space gap over closing speed along the road; infinite when not closing."""
    me, other = ctx.states[subject.name], ctx.states[reference.name]
    gap = road_distance(ctx, subject, reference, "longitudinal", "bounding_boxes")
    closing = (me.speed - other.speed) if gap >= 0.0 else (other.speed - me.speed)
    if closing <= 1e-9:
        return math.inf
    return abs(gap) / closing


@method("physical_object", "distance_to_xyz_point")
def distance_to_xyz_point(
    ctx: RunContext,
    subject: Actor,
    point: object,
    direction: str,
    mode: str = "reference_points",
) -> float:
    """Distance from the subject to a world point, in the subject's frame as
    ``object_distance`` (``bounding_boxes``: from the subject's box)."""
    me = ctx.states[subject.name]
    position = getattr(point, "position", point)
    dx = float(position.x) - me.x  # type: ignore[attr-defined]
    dy = float(position.y) - me.y  # type: ignore[attr-defined]
    c, s = math.cos(me.yaw), math.sin(me.yaw)
    lon, lat = dx * c + dy * s, -dx * s + dy * c
    boxes = mode == "bounding_boxes"
    if direction == "longitudinal":
        return _shrink(lon, 0.5 * me.length) if boxes else lon
    if direction == "lateral":
        return _shrink(lat, 0.5 * me.width) if boxes else lat
    if direction == "vertical":
        return 0.0
    if boxes:
        return math.hypot(_shrink(lon, 0.5 * me.length), _shrink(lat, 0.5 * me.width))
    return math.hypot(lon, lat)


@method("environment", "local_to_unix_time")
def local_to_unix_time(
    ctx: RunContext,
    subject: object,
    year: int,
    month: int,
    day: int,
    hour: int,
    minute: int,
    second: int,
    time_zone: float,
) -> float:
    """Seconds since 1970-01-01 00:00 UTC of a local date and time ``time_zone`` hours
    ahead of UTC (proleptic Gregorian calendar, no leap seconds)."""
    try:
        local = datetime.datetime(
            int(year), int(month), int(day), int(hour), int(minute), int(second)
        )
    except ValueError as exc:
        raise RunFault(f"local_to_unix_time: {exc}") from None
    epoch = datetime.datetime(1970, 1, 1)
    return (local - epoch).total_seconds() - float(time_zone) * 3600.0


# ---------------------------------------------------------------------- shapes


def _shape_args(subject: object) -> tuple[str, float | None, float]:
    profile = str(getattr(subject, "rate_profile", "none"))
    peak = getattr(subject, "rate_peak", None)
    return profile, (float(peak) if peak is not None else None), float(subject.target)  # type: ignore[attr-defined]


@method("any_shape", "duration")
def shape_duration(ctx: RunContext, subject: object) -> float:
    """Time a ``common_*_shape`` takes from 0 to its ``target`` at its ``rate_peak``
    (``constant``, ``none``: at the peak throughout; ``smooth``: a half-sine rate, whose
    mean is 2/pi of the peak); infinite without a peak."""
    profile, peak, target = _shape_args(subject)
    if peak is None or peak <= 0.0:
        return math.inf
    base = abs(target) / peak
    return base * (math.pi / 2.0) if profile == "smooth" else base


@method("any_acceleration_shape", "compute")
@method("any_speed_shape", "compute")
@method("any_position_shape", "compute")
@method("any_lateral_shape", "compute")
def shape_compute(ctx: RunContext, subject: object, time: float) -> float:
    """The shape's value ``time`` after the phase start, from 0 towards ``target`` (see
    :func:`shape_duration`); the target once its duration has passed."""
    profile, _peak, target = _shape_args(subject)
    duration = shape_duration(ctx, subject)
    if not math.isfinite(duration) or duration <= 0.0 or time >= duration:
        return target
    u = max(time, 0.0) / duration
    if profile == "smooth":
        return target * 0.5 * (1.0 - math.cos(math.pi * u))
    return target * u
