"""Paths and trajectories in world coordinates: ``follow_*``, ``replay_*``, ``change_position``,
the ``along`` and ``along_trajectory`` modifiers.

A ``path`` value has ``points`` (``pose_3d``, or ``position_3d``) and an
``interpolation`` (``straight_line`` or ``smooth``: a spline through every
point); a ``trajectory`` also has ``time_stamps``, one per point. Values come
from struct parameters (the witness) or from ``map.create_path`` /
``map.create_trajectory`` (``behaviours/methods.py``). ``z``, roll and pitch are
not used: the world is flat.

* ``follow_path`` (physical): the actor is steered along the path (vehicles: the
  Stanley law on the front axle; walkers: towards a point 1 m ahead) at the
  speed its modifiers give (else its own); it ends when the front axle reaches
  the end (less ``end_offset``). ``start_offset`` skips the path's first metres.
* ``follow_trajectory`` (physical): as ``follow_path``, and the speed is the
  trajectory's plus a correction of the distance error, so that the actor is
  where the trajectory says when it says; ends at the last time stamp.
  Time stamps count from the action's start (the first stamp is the start).
* ``replay_path`` / ``replay_trajectory`` (exact): the same, and the actor is put
  on the path every tick (at its place in time for a trajectory, its
  progress along the path for a path).
* ``relative`` forms (``relative_path_pose_3d``, ``relative_trajectory_pose_3d``):
  the points are in the frame of ``reference`` (the actor by default) when the
  action starts: ``object_relative`` its position and heading, ``world_relative``
  its position and the world axes, ``road_relative``/``lane_relative`` its position
  and the road's heading.
* ``change_position`` (physical): a straight (or smooth) path from the actor to
  ``target_xyz`` / ``target_position``, followed as ``follow_path``.
* ``along(route)`` / ``along_trajectory(trajectory)``: the action's actor follows
  the path or trajectory while the action runs (``route`` must be a ``path`` here;
  road routes come with maps).
"""

from __future__ import annotations

import math
from typing import Any

from py_trees.common import Status

from osc2runner.behaviours.base import ActionBehaviour, ActionError, Modifier, number
from osc2runner.behaviours.driving import retarget, set_speed
from osc2runner.behaviours.maps import map_point_xy
from osc2runner.behaviours.road_paths import (
    interpolation_of,
    resolve_points,
    road_line,
    time_stamps_of,
)
from osc2runner.compile.registry import action, method, modifier
from osc2runner.execution.context import RunContext
from osc2runner.execution.controls import is_vehicle, is_walker
from osc2runner.instance.actors import Actor
from osc2runner.sim.tracking import PathTracker, Polyline, Trajectory
from osc2runner.structs import Path, Pose3d, Position3d, XyzPoint

__all__ = [
    "Along",
    "AlongTrajectory",
    "ChangePosition",
    "FollowPath",
    "FollowTrajectory",
    "PathMotion",
    "ReplayPath",
    "ReplayTrajectory",
    "path_points",
]

#: gain of the trajectory's distance error in the speed command (1/s)
TRAJECTORY_GAIN = 1.0
#: a walker reaches a target position within this (m)
WALKER_ARRIVED = 0.1


def path_points(ctx: RunContext, value: object) -> list[tuple[float, float]]:
    """The world points of a path or trajectory value (poses, or points of the map)."""
    points = getattr(value, "points", None)
    if not points:
        raise ActionError("the path has no points")
    return [map_point_xy(ctx, p) for p in points]


class PathMotion:
    """An actor moving along a polyline, physically or exactly (one per phase)."""

    def __init__(
        self,
        action: ActionBehaviour,
        path: Polyline,
        *,
        trajectory: Trajectory | None = None,
        exact: bool = False,
        start_offset: float = 0.0,
        end_offset: float = 0.0,
    ) -> None:
        self.action = action
        self.path = path
        self.trajectory = trajectory
        self.exact = exact
        self.begin = max(0.0, start_offset)
        self.end = path.length - max(0.0, end_offset)
        if self.end <= self.begin:
            raise ActionError(f"the offsets leave nothing of the path ({path.length:.2f} m long)")
        ctrl = action.controller
        if ctrl is None:
            raise ActionError("this actor has no driver (it cannot move)")
        self.ctrl = ctrl
        #: a walker walks along the path itself; a vehicle steers along it with a tracker
        self.walker = ctrl if is_walker(ctrl) else None
        self.vehicle = ctrl if self.walker is None and is_vehicle(ctrl) else None
        self.progress = self.begin
        state = action.state
        if self.vehicle is not None:
            corners = trajectory.corner_speeds() if trajectory is not None else None
            self.vehicle.path = PathTracker(
                self.vehicle.params, path, end=self.end, corner_speeds=corners
            )
        elif self.walker is not None:
            self.walker.path = path
        if exact:  # an exact motion starts on the path
            x, y, yaw = path.at(self.begin)
            self._place(x, y, yaw, state.speed)

    def _place(self, x: float, y: float, yaw: float, speed: float) -> None:
        self.action.ctx.place(self.action.actor.name, x, y, yaw, speed)

    def step(self) -> Status:
        action = self.action
        state = action.state
        if self.trajectory is not None:
            traj = self.trajectory
            t = traj.times[0] + action.elapsed
            s_want, v_want = traj.s_at(t)
            if self.exact:
                s_next, _ = traj.s_at(t + action.ctx.dt)
                x, y, yaw = self.path.at(s_want)
                self._place(x, y, yaw, (s_next - s_want) / action.ctx.dt)
                retarget(self.ctrl, max((s_next - s_want) / action.ctx.dt, 0.0))
            else:
                s_now = self.path.project(state.x, state.y)[0]
                retarget(self.ctrl, max(v_want + TRAJECTORY_GAIN * (s_want - s_now), 0.0))
            if t >= traj.times[-1]:
                return Status.SUCCESS
            return Status.RUNNING
        if self.exact:
            speed = self.ctrl.speed.target if self.ctrl.speed.target is not None else state.speed
            self.progress = min(self.progress + max(speed, 0.0) * action.ctx.dt, self.end)
            x, y, yaw = self.path.at(self.progress)
            self._place(x, y, yaw, speed)
            return Status.SUCCESS if self.progress >= self.end else Status.RUNNING
        return Status.SUCCESS if self.arrived() else Status.RUNNING

    def arrived(self) -> bool:
        state = self.action.state
        if self.vehicle is not None:
            tracker = self.vehicle.path
            return tracker is not None and tracker.done(state.x, state.y, state.yaw)
        s, _, _ = self.path.project(state.x, state.y)
        return s >= self.end - WALKER_ARRIVED

    def stop(self) -> None:
        """The phase ended: the actor drives on along the road (its lateral position)."""
        state = self.action.state
        if self.vehicle is not None:
            self.vehicle.path = None
            self.vehicle.lateral.hold(state)  # the lane it is in, at its offset from the centre
        elif self.walker is not None:
            self.walker.path = None
            self.walker.yaw = state.yaw


def _motion_path(
    value: object,
    timed: bool,
    points: list[tuple[float, float]] | None = None,
    ctx: Any = None,  # (None where the points need no map)
) -> tuple[Polyline, Trajectory | None]:
    """The polyline of a path or trajectory value (through ``points`` when given: its
    points in world coordinates; the value's own line when it runs along the road) and,
    ``timed``, its trajectory over its time stamps."""
    try:
        line = value.line if isinstance(value, Path) and points is None else None
        if line is not None:
            path = line.follower()
        else:
            path = Polyline(
                path_points(ctx, value) if points is None else points, interpolation_of(value)
            )
        if not timed:
            return path, None
        stamps = time_stamps_of(value)
        if stamps is None:
            raise ActionError("the trajectory has no time stamps")
        return path, Trajectory(path, stamps)
    except ValueError as exc:
        raise ActionError(str(exc)) from None


class _MotionAction(ActionBehaviour):
    """An action whose actor moves along a path (``start`` sets its :class:`PathMotion`)."""

    motion: PathMotion | None = None  # (none before the action starts)

    def step(self) -> Status:
        assert self.motion is not None  # (start set it)
        return self.motion.step()

    def terminate(self, new_status: Status) -> None:
        if self.motion is not None and self.status == Status.RUNNING:
            self.motion.stop()
        super().terminate(new_status)


class _PathAction(_MotionAction):
    """``follow_path`` and its kin: ``absolute`` or ``relative`` path (see the module)."""

    exact = False
    timed = False

    def start(self) -> None:
        args = self.args
        absolute, relative = args.get("absolute"), args.get("relative")
        if (absolute is None) == (relative is None):
            raise ActionError("give exactly one of `absolute` and `relative`")
        if relative is None:
            path, trajectory = _motion_path(absolute, self.timed, ctx=self.ctx)
        else:
            reference = args.get("reference")
            ref = reference if isinstance(reference, Actor) else self.actor
            transform = str(args.get("transform", "object_relative"))
            points, on_road = resolve_points(self.ctx, relative, ref, transform)
            value = relative
            if on_road:
                interpolation = interpolation_of(relative)
                stamps = time_stamps_of(relative)
                line = road_line(self.ctx.network, points, interpolation)
                value = Path((), interpolation, stamps, line)
            path, trajectory = _motion_path(value, self.timed, None if on_road else points)
        if not self.drives("longitudinal") and not self.timed:
            ctrl = self.controller
            if ctrl is not None and ctrl.speed.target is None:
                set_speed(ctrl, self.state.speed, "none")
        self.motion = PathMotion(
            self,
            path,
            trajectory=trajectory,
            exact=self.exact,
            start_offset=number(args.get("start_offset", 0.0)),
            end_offset=number(args.get("end_offset", 0.0)),
        )


@action("movable_object", "follow_path")
class FollowPath(_PathAction):
    """``follow_path(absolute | relative, ...)``: steered along the path (see the module)."""


@action("movable_object", "replay_path")
class ReplayPath(_PathAction):
    """``replay_path(...)``: put on the path every tick, moving at its speed (exact)."""

    exact = True


@action("movable_object", "follow_trajectory")
class FollowTrajectory(_PathAction):
    """``follow_trajectory(...)``: steered along, at the trajectory's pace (see the module)."""

    timed = True


@action("movable_object", "replay_trajectory")
class ReplayTrajectory(_PathAction):
    """``replay_trajectory(...)``: where the trajectory says, when it says, every tick."""

    exact = True
    timed = True


#: the targets of ``change_position``, exactly one of which is given
_TARGETS = ("target_position", "target_st", "target_odr", "target_xyz")


@action("movable_object", "change_position")
class ChangePosition(_MotionAction):
    """``change_position(target_position | target_st | target_odr | target_xyz,
    interpolation, on_road_network)``: move to the point along a straight line (or a
    smooth curve leaving along the heading), or along the road; ends there."""

    def start(self) -> None:
        args = self.args
        given = [k for k in _TARGETS if args.get(k) is not None]
        if len(given) != 1:
            raise ActionError("give exactly one of " + ", ".join(f"`{k}`" for k in _TARGETS))
        state = self.state
        end = map_point_xy(self.ctx, args[given[0]])
        smooth = str(args.get("interpolation", "straight_line")) == "smooth"
        points = [(state.x, state.y)]
        if smooth:
            lead = 0.25 * math.hypot(end[0] - state.x, end[1] - state.y)
            points.append(
                (state.x + lead * math.cos(state.yaw), state.y + lead * math.sin(state.yaw))
            )
        points.append(end)
        if not self.drives("longitudinal"):
            set_speed(self.controller, state.speed, "none")
        if state.speed <= 0.01 and not self.drives("longitudinal"):
            raise ActionError("the actor stands still: give a speed() to move it")
        if bool(args.get("on_road_network", False)):
            interpolation = "smooth" if smooth else "straight_line"
            path: Polyline = road_line(self.ctx.network, [points[0], end], interpolation)
        else:
            try:
                path = Polyline(points, "smooth" if smooth else "straight_line")
            except ValueError as exc:
                raise ActionError(str(exc)) from None
        self.motion = PathMotion(self, path)


class _AlongModifier(Modifier):
    """The action's actor follows a path or trajectory while the phase lasts."""

    lateral = True
    timed = False
    motion: PathMotion | None = None  # (none before the phase, and after it)
    done = False  # whether the motion reached the path's end

    def realise(self, action: ActionBehaviour) -> None:
        value = self.args.get("trajectory" if self.timed else "route")
        if value is None or not hasattr(value, "points"):
            raise ActionError(
                f"{self.use.name}() needs a {'trajectory' if self.timed else 'path'} with "
                "points (road routes come with maps)"
            )
        path, trajectory = _motion_path(value, self.timed, ctx=action.ctx)
        self.motion = PathMotion(
            action,
            path,
            trajectory=trajectory,
            start_offset=number(self.args.get("start_offset", 0.0)),
            end_offset=number(self.args.get("end_offset", 0.0)),
        )

    def step(self, action: ActionBehaviour) -> None:
        if self.motion is not None:
            self.done = self.motion.step() == Status.SUCCESS

    def finished(self, action: ActionBehaviour) -> bool:
        return self.done

    def end(self, action: ActionBehaviour) -> None:
        if self.motion is not None:
            self.motion.stop()
            self.motion = None


@modifier("along")
class Along(_AlongModifier):
    """``along(route: a_path)``: the actor follows the path; the phase ends at its end.
    ``along(route: r)`` with a route of the map (a road, route or lane field, a compound
    route): the actor's lane following passes its roads (``behaviours.maps``)."""

    def realise(self, action: ActionBehaviour) -> None:
        from osc2runner.behaviours.maps import crossing_path, follow_route, is_map_route

        self.motion = None
        state = action.state
        across = crossing_path(action.ctx, self.args.get("route"), state.x, state.y)
        if across is not None:
            self.motion = PathMotion(action, across)
            return
        if is_map_route(self.args.get("route")):
            follow_route(self, action)
            return
        super().realise(action)

    def holds(self, action: ActionBehaviour) -> str | None:
        from osc2runner.behaviours.maps import is_map_route, route_holds

        if is_map_route(self.args.get("route")):
            return route_holds(self, action)
        return super().holds(action)


@modifier("along_trajectory")
class AlongTrajectory(_AlongModifier):
    """``along_trajectory(trajectory)``: the actor follows the trajectory at its pace."""

    timed = True
    longitudinal = True


# ---------------------------------------------------------------------- constructors


@method("map", "create_xyz_point")
def create_xyz_point(ctx: RunContext, subject: object, x: float, y: float, z: float) -> XyzPoint:
    """An ``xyz_point`` at world ``(x, y, z)``."""
    return XyzPoint(Position3d(x=x, y=y, z=z))


@method("map", "create_path")
def create_path(
    ctx: RunContext, subject: object, points: tuple[Pose3d, ...], interpolation: str
) -> Path:
    """A ``path`` through world poses (``list of pose_3d``)."""
    return Path(tuple(points), interpolation)


@method("map", "create_trajectory")
def create_trajectory(
    ctx: RunContext,
    subject: object,
    points: tuple[Pose3d, ...],
    time_stamps: tuple[float, ...],
    interpolation: str,
) -> Path:
    """A ``trajectory``: world poses with a time stamp each."""
    return Path(tuple(points), interpolation, tuple(time_stamps))
