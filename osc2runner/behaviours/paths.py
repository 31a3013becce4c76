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
from types import SimpleNamespace
from typing import Any

from py_trees.common import Status

from osc2runner.behaviours.base import ActionBehaviour, ActionError, Modifier
from osc2runner.behaviours.driving import retarget, set_speed
from osc2runner.compile.registry import action, method, modifier
from osc2runner.execution.context import RunContext
from osc2runner.instance.actors import Actor
from osc2runner.sim.tracking import PathTracker, Polyline, Trajectory

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


def _xy(point: Any) -> tuple[float, float]:
    """World x, y of a ``pose_3d``, ``position_3d`` or ``xyz_point`` value."""
    if hasattr(point, "position") and not hasattr(point, "x"):
        point = point.position
    try:
        return float(point.x), float(point.y)
    except AttributeError:
        raise ActionError(f"`{point!r}` is not a position (it has no x and y)") from None


def path_points(value: Any) -> list[tuple[float, float]]:
    """The world points of a path or trajectory value."""
    points = getattr(value, "points", None)
    if not points:
        raise ActionError("the path has no points")
    return [_xy(p) for p in points]


def _frame(action: ActionBehaviour, reference: Any, transform: str) -> tuple[float, float, float]:
    """Origin and heading of the frame relative points are given in."""
    ref = reference if isinstance(reference, Actor) else action.actor
    st = action.ctx.states[ref.name]
    if transform == "world_relative":
        return st.x, st.y, 0.0
    if transform in ("road_relative", "lane_relative"):
        from osc2runner.behaviours.driving import lane_heading

        return st.x, st.y, lane_heading(action.ctx, st)
    return st.x, st.y, st.yaw


def _to_world(points: list[tuple[float, float]], frame: tuple[float, float, float]) -> list:
    x0, y0, yaw = frame
    c, s = math.cos(yaw), math.sin(yaw)
    return [(x0 + c * x - s * y, y0 + s * x + c * y) for x, y in points]


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
        self.vehicle = hasattr(ctrl, "lateral") and not hasattr(ctrl, "yaw")
        self.progress = self.begin
        state = action.state
        if self.vehicle:
            corners = trajectory.corner_speeds() if trajectory is not None else None
            ctrl.path = PathTracker(ctrl.params, path, end=self.end, corner_speeds=corners)
        else:
            ctrl.path = path
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
        if self.vehicle:
            tracker = self.ctrl.path
            return bool(tracker is not None and tracker.done(state.x, state.y, state.yaw))
        s, _, _ = self.path.project(state.x, state.y)
        return s >= self.end - WALKER_ARRIVED

    def stop(self) -> None:
        """The phase ended: the actor drives on along the road (its lateral position)."""
        ctrl = self.ctrl
        ctrl.path = None
        state = self.action.state
        if self.vehicle:
            ctrl.lateral.keep_offset(state.t)
        else:
            ctrl.yaw = state.yaw


def _motion_path(
    value: Any, timed: bool, points: list[tuple[float, float]] | None = None
) -> tuple[Polyline, Trajectory | None]:
    """The polyline of a path or trajectory value (through ``points`` when given: its
    points in world coordinates) and, ``timed``, its trajectory over its time stamps."""
    try:
        path = Polyline(
            path_points(value) if points is None else points,
            str(getattr(value, "interpolation", "straight_line")),
        )
        if not timed:
            return path, None
        stamps = getattr(value, "time_stamps", None)
        if stamps is None:
            raise ActionError("the trajectory has no time stamps")
        return path, Trajectory(path, tuple(float(t) for t in stamps))
    except ValueError as exc:
        raise ActionError(str(exc)) from None


class _MotionAction(ActionBehaviour):
    """An action whose actor moves along a path (``start`` sets its :class:`PathMotion`)."""

    motion: PathMotion

    def step(self) -> Status:
        return self.motion.step()

    def terminate(self, new_status: Status) -> None:
        motion = getattr(self, "motion", None)
        if motion is not None and self.status == Status.RUNNING:
            motion.stop()
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
        value = absolute if absolute is not None else relative
        points = path_points(value)
        if relative is not None:
            frame = _frame(
                self, args.get("reference"), str(args.get("transform", "object_relative"))
            )
            points = _to_world(points, frame)
        path, trajectory = _motion_path(value, self.timed, points)
        if not self.drives("longitudinal") and not self.timed:
            ctrl = self.controller
            if ctrl is not None and ctrl.speed.target is None:
                set_speed(ctrl, self.state.speed, "none")
        self.motion = PathMotion(
            self,
            path,
            trajectory=trajectory,
            exact=self.exact,
            start_offset=float(args.get("start_offset", 0.0)),
            end_offset=float(args.get("end_offset", 0.0)),
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


@action("movable_object", "change_position")
class ChangePosition(_MotionAction):
    """``change_position(target_xyz | target_position, interpolation)``: move to the point
    along a straight line (or a smooth curve leaving along the heading); ends there."""

    def start(self) -> None:
        args = self.args
        target = args.get("target_position", args.get("target_xyz"))
        for key in ("target_st", "target_odr"):
            if key in args:
                raise ActionError(f"change_position({key}: ...) needs a road network (maps)")
        if target is None:
            raise ActionError("give `target_position` or `target_xyz`")
        state = self.state
        end = _xy(target)
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
        try:
            path = Polyline(points, "smooth" if smooth else "straight_line")
        except ValueError as exc:
            raise ActionError(str(exc)) from None
        self.motion = PathMotion(self, path)


class _AlongModifier(Modifier):
    """The action's actor follows a path or trajectory while the phase lasts."""

    lateral = True
    timed = False

    def realise(self, action: ActionBehaviour) -> None:
        value = self.args.get("trajectory" if self.timed else "route")
        if value is None or not hasattr(value, "points"):
            raise ActionError(
                f"{self.use.name}() needs a {'trajectory' if self.timed else 'path'} with "
                "points (road routes come with maps)"
            )
        path, trajectory = _motion_path(value, self.timed)
        self.motion: PathMotion | None = PathMotion(
            action,
            path,
            trajectory=trajectory,
            start_offset=float(self.args.get("start_offset", 0.0)),
            end_offset=float(self.args.get("end_offset", 0.0)),
        )

    def step(self, action: ActionBehaviour) -> None:
        if self.motion is not None:
            self.done = self.motion.step() == Status.SUCCESS

    def finished(self, action: ActionBehaviour) -> bool:
        return bool(getattr(self, "done", False))

    def end(self, action: ActionBehaviour) -> None:
        motion = getattr(self, "motion", None)
        if motion is not None:
            motion.stop()
            self.motion = None


@modifier("along")
class Along(_AlongModifier):
    """``along(route: a_path)``: the actor follows the path; the phase ends at its end.
    ``along(route: r)`` with a route of the map (a road, route or lane field, a compound
    route): the actor's lane following passes its roads (``behaviours.maps``)."""

    def realise(self, action: ActionBehaviour) -> None:
        from osc2runner.behaviours.maps import follow_route, is_map_route

        self.motion = None
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
def create_xyz_point(ctx: RunContext, subject: object, x: float, y: float, z: float) -> Any:
    """An ``xyz_point`` at world ``(x, y, z)``."""
    return SimpleNamespace(position=SimpleNamespace(x=x, y=y, z=z))


@method("map", "create_path")
def create_path(ctx: RunContext, subject: object, points: Any, interpolation: str) -> Any:
    """A ``path`` through world poses (``list of pose_3d``)."""
    return SimpleNamespace(points=tuple(points), interpolation=interpolation)


@method("map", "create_trajectory")
def create_trajectory(
    ctx: RunContext, subject: object, points: Any, time_stamps: Any, interpolation: str
) -> Any:
    """A ``trajectory``: world poses with a time stamp each."""
    return SimpleNamespace(
        points=tuple(points), time_stamps=tuple(time_stamps), interpolation=interpolation
    )
