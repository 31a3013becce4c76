"""Movement actions of vehicles and persons: drive, speed changes, lanes, gaps.

Open-ended actions (``drive``, ``move``, ``walk``, ``keep_speed``,
``follow_lane``, ``remain_stationary``, ``keep_*_gap``) run until their
phase is ended by ``duration``, ``until``, a race, or by the end of the other
members of their ``parallel``. The others end on their own when their goal is
reached (``change_speed``: the target speed; ``change_lane``: the front axle
at the end of the lateral path; ``change_*_gap``: the gap held).
"""

from __future__ import annotations

import math

from py_trees.common import Status

from osc2runner.behaviours.base import ActionBehaviour, ActionError, InstantAction, number, whole
from osc2runner.behaviours.driving import (
    GAP_GAIN,
    GAP_LAG,
    gap_between,
    lane_change_duration,
    lane_of,
    lane_width,
    profile_for,
    retarget,
    set_speed,
    side_of,
)
from osc2runner.behaviours.following import Follower
from osc2runner.compile.registry import action
from osc2runner.instance.actors import Actor
from osc2runner.sim import ActorState

__all__ = [
    "AssignAcceleration",
    "ChangeAcceleration",
    "KeepAcceleration",
    "acceleration_limits",
    "command_acceleration",
    "ChangeLane",
    "ChangeSpeed",
    "Drive",
    "FollowLane",
    "GapAction",
    "KeepSpeed",
    "RemainStationary",
]


def _hold(action: ActionBehaviour) -> None:
    """Keep what the actor does now where the action's modifiers say nothing."""
    ctrl = action.controller
    if ctrl is None:
        raise ActionError("this actor has no driver (it cannot move)")
    if not action.drives("longitudinal") and ctrl.speed.target is None:
        set_speed(ctrl, action.state.speed, "none")
    if not action.drives("lateral") and ctrl.lateral.path is None:
        ctrl.lateral.hold(action.state)


class _KeepsClear(ActionBehaviour):
    """An open-ended action that keeps the speed the scenario leaves open clear of what
    is ahead (:mod:`osc2runner.behaviours.following`); ``start`` makes ``follower``."""

    follower: Follower | None = None

    def step(self) -> Status:
        if self.follower is not None and not self.follower.step():
            self.follower = None
        return Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        if self.follower is not None:  # the next action holds the vehicle's own speed
            self.follower.stop()
            self.follower = None
        super().terminate(new_status)


@action("vehicle", "drive")
class Drive(_KeepsClear):
    """``drive()``: what happens comes from the modifiers; otherwise keep speed and lane,
    and a safe gap behind what is ahead."""

    own_motions = frozenset[str]()
    finite = False

    def start(self) -> None:
        _hold(self)
        self.follower = Follower.of(self)


@action("movable_object", "move")
class Move(Drive):
    """``move()``: as ``drive`` for any movable object."""


@action("person", "walk")
class Walk(Drive):
    """``walk()``: as ``drive`` for persons (kinematic pedestrian)."""


@action("movable_object", "keep_speed")
class KeepSpeed(ActionBehaviour):
    """``keep_speed()``: hold the speed the actor has when the phase starts."""

    own_motions = frozenset({"longitudinal"})
    finite = False

    def start(self) -> None:
        _hold(self)
        set_speed(self.controller, self.state.speed, "none")


@action("movable_object", "remain_stationary")
class RemainStationary(ActionBehaviour):
    """``remain_stationary()``: come to a stop (comfortably) and stay stopped."""

    finite = False

    def start(self) -> None:
        _hold(self)
        set_speed(self.controller, 0.0, "smooth")


@action("movable_object", "change_speed")
class ChangeSpeed(ActionBehaviour):
    """``change_speed(target, rate_profile, rate_peak)``: ends when the target speed is reached.

    With a ``duration`` and no profile the change is spread evenly over it.
    """

    own_motions = frozenset({"longitudinal"})

    def start(self) -> None:
        _hold(self)
        target = number(self.args["target"])
        kind = str(self.args.get("rate_profile", "none"))
        peak = self.args.get("rate_peak")
        profile = profile_for(
            kind,
            number(peak) if peak is not None else None,
            change=target - self.state.speed,
            duration=self.plan_time(),
        )
        set_speed(self.controller, target, profile)
        self.target = target

    def step(self) -> Status:
        if self.driver.speed.reached(self.state, self.ctx.tolerances.speed):
            return Status.SUCCESS
        return Status.RUNNING

    def progress(self) -> str:
        tol = self.ctx.tolerances
        return (
            f"the speed is {self.state.speed * 3.6:.2f} kph, not {self.target * 3.6:.2f} kph "
            f"(tolerance {tol.kph()})"
        )


@action("vehicle", "change_lane")
class ChangeLane(ActionBehaviour):
    """``change_lane(num_of_lanes, side, reference, offset, rate_profile, rate_peak)``.

    The target lane is ``num_of_lanes`` lanes to ``side`` of the reference's
    lane (the actor's own by default), by number on the road the actor is on;
    ``same`` is the reference's lane.
    The path is a minimum-jerk lateral blend over the phase duration, over
    the time a ``rate_peak`` lateral speed gives, or over 4 s (2.5 s for
    ``asap``); it ends when the front axle reaches the end of the blend.
    """

    own_motions = frozenset({"lateral"})

    def start(self) -> None:
        ctx = self.ctx
        args = self.args
        if "target" in args:
            raise ActionError(
                "change_lane(target: lane) needs a road network; use num_of_lanes and side"
            )
        _hold(self)
        reference = args.get("reference")
        ref = reference if isinstance(reference, Actor) else self.actor
        n = whole(args.get("num_of_lanes", 1))
        side = str(args.get("side", "left"))
        here = lane_of(ctx, self.actor)
        start_lane = lane_of(ctx, ref)
        found = start_lane if side == "same" else ctx.lanes.beside(start_lane, side_of(side), n)
        target = (
            ctx.lanes.lane(here, ctx.lanes.number(found, "right"), "right")
            if found is not None
            else None
        )
        if target is None:
            raise ActionError(
                f"there is no lane {n} lane(s) to the {side} of lane "
                f"{ctx.lanes.number(start_lane)} on road `{start_lane.road}`"
            )
        peak = args.get("rate_peak")
        lanes = abs(ctx.lanes.number(target, "right") - ctx.lanes.number(here, "right")) or 1
        duration = lane_change_duration(
            lanes,
            lane_width(ctx, self.state),
            phase=self.plan_time(),
            rate_peak=number(peak) if peak is not None else None,
            profile=str(args.get("rate_profile", "none")),
        )
        lateral = self.driver.lateral
        self.offset = number(args.get("offset", 0.0))
        lateral.change_lane(self.state, target, offset=self.offset, duration=duration)
        self.target_lane = target
        self.planned = duration

    def step(self) -> Status:
        # done when the blend is over (the front axle passed its end) or its planned time
        # is up, and the actor is at the new lane's centre within the tolerance: a blend
        # passed with the car still in the old lane (a change too quick for the physics)
        # is not a lane change
        over = self.driver.lateral.done(self.state) or self.elapsed >= self.planned - 1e-9
        distance = self._from_centre()
        if over and distance is not None and abs(distance) <= self.ctx.tolerances.lateral:
            return Status.SUCCESS
        return Status.RUNNING

    def _from_centre(self) -> float | None:
        """How far the actor is from where it is going in the new lane (None while it
        is in another lane)."""
        state = self.state
        here = state.lane_ref
        if here is None or (here.road, here.lane) != (self.target_lane.road, self.target_lane.lane):
            return None
        return state.offset - self.offset

    def progress(self) -> str:
        distance = self._from_centre()
        tol = self.ctx.tolerances.lateral
        lane = self.ctx.lanes.number(self.target_lane)
        if distance is None:
            return f"it is not in lane {lane} yet"
        return f"it is {abs(distance):.2f} m from the centre of lane {lane} (tolerance {tol:.2f} m)"


@action("vehicle", "follow_lane")
class FollowLane(_KeepsClear):
    """``follow_lane(offset)``: keep the lane of the start at ``offset`` from its centre."""

    own_motions = frozenset({"lateral"})
    finite = False

    def start(self) -> None:
        if "target" in self.args:
            raise ActionError(
                "follow_lane(target: lane) needs a road network; drive in a lane "
                "with the lane() modifier instead"
            )
        _hold(self)
        self.driver.lateral.keep_lane(
            lane_of(self.ctx, self.actor), offset=number(self.args.get("offset", 0.0))
        )
        self.follower = Follower.of(self)


# ---------------------------------------------------------------------- gaps


class GapAction(ActionBehaviour):
    """Gap and headway actions: the speed tracks the reference to hold a longitudinal gap.

    ``space`` gaps are between bounding boxes (bumper to bumper), headways
    between reference points; ``time`` forms divide by the actor's speed.
    ``change_*`` actions end once the gap is within tolerance and the speeds
    match; ``keep_*`` actions hold the gap they start with.
    """

    own_motions = frozenset({"longitudinal"})
    finite = True
    bumpers = True  # space gap (bounding boxes) vs headway (reference points)
    timed = False  # time gap/headway vs distance
    error = 0.0  # the last step's gap error, m (>0: too far apart)
    keep = False

    def start(self) -> None:
        _hold(self)
        args = self.args
        ref = args.get("reference")
        if not isinstance(ref, Actor):
            raise ActionError("needs a `reference` actor")
        self.reference = ref
        direction = str(args.get("direction", "longitudinal"))
        if direction in ("left", "right", "inside", "outside", "lateral"):
            raise ActionError(f"lateral gaps (direction `{direction}`) are not supported")
        me, other = self.state, self.ctx.states[ref.name]
        gap = gap_between(me, other, bumpers=self.bumpers)
        if direction in ("ahead", "behind"):
            self.sign = 1.0 if direction == "behind" else -1.0
        else:
            self.sign = 1.0 if gap >= 0.0 else -1.0
        if self.keep:
            self.goal = self._measure(me, other)
        else:
            self.goal = number(args["target"])

    def _measure(self, me: ActorState, other: ActorState) -> float:
        gap: float = self.sign * gap_between(me, other, bumpers=self.bumpers)
        if self.timed:
            headway: float = gap / max(me.speed, 0.1)
            return headway
        return gap

    def step(self) -> Status:
        me, other = self.state, self.ctx.states[self.reference.name]
        distance = self.sign * gap_between(me, other, bumpers=self.bumpers)
        wanted = self.goal * max(me.speed, 0.1) if self.timed else self.goal
        error = distance - wanted  # >0: too far apart
        self.error = error
        # the error GAP_LAG from now at today's speeds: the speed follows its target that
        # much late, and a gap to a standing reference overshot cannot be taken back
        ahead = error + GAP_LAG * self.sign * (other.speed - me.speed)
        retarget(self.driver, other.speed + self.sign * GAP_GAIN * ahead)
        tol = self.ctx.tolerances
        if (
            not self.keep
            and abs(error) <= tol.position
            and abs(me.speed - other.speed) <= tol.speed
        ):
            return Status.SUCCESS
        return Status.RUNNING

    def progress(self) -> str:
        tol = self.ctx.tolerances.position
        return f"the gap is {self.error:+.2f} m from the one asked (tolerance {tol:.2f} m)"


def _gap(name: str, *, bumpers: bool, timed: bool, keep: bool) -> type[GapAction]:
    cls = type(
        f"{''.join(p.title() for p in name.split('_'))}",
        (GapAction,),
        {
            "bumpers": bumpers,
            "timed": timed,
            "keep": keep,
            "finite": not keep,
            "__doc__": f"``{name}``: see :class:`GapAction`.",
            "__module__": __name__,
        },
    )
    return action("vehicle", name)(cls)


ChangeSpaceGap = _gap("change_space_gap", bumpers=True, timed=False, keep=False)
KeepSpaceGap = _gap("keep_space_gap", bumpers=True, timed=False, keep=True)
ChangeTimeGap = _gap("change_time_gap", bumpers=True, timed=True, keep=False)
KeepTimeGap = _gap("keep_time_gap", bumpers=True, timed=True, keep=True)
ChangeSpaceHeadway = _gap("change_space_headway", bumpers=False, timed=False, keep=False)
KeepSpaceHeadway = _gap("keep_space_headway", bumpers=False, timed=False, keep=True)
ChangeTimeHeadway = _gap("change_time_headway", bumpers=False, timed=True, keep=False)
KeepTimeHeadway = _gap("keep_time_headway", bumpers=False, timed=True, keep=True)


# ---------------------------------------------------------------------- acceleration


def acceleration_limits(actor: Actor) -> tuple[float, float]:
    """``(max acceleration, max deceleration)`` of an actor's catalogue row (m/s², both > 0)."""
    row = actor.row
    if row is None:
        return (math.inf, math.inf)
    return (float(row.max_acceleration), float(row.max_deceleration))


def command_acceleration(action: ActionBehaviour, accel: float, jerk: float = math.inf) -> float:
    """Command ``accel`` (clamped to the actor's limits; the clamp is logged) from now on;
    returns the acceleration commanded."""
    ctrl = action.controller
    if ctrl is None:
        raise ActionError("this actor has no driver (it cannot move)")
    up, down = acceleration_limits(action.actor)
    commanded = min(max(accel, -down), up)
    if commanded != accel:
        action.ctx.record(
            "limit",
            action.use.label,
            f"acceleration {accel:.3g} m/s² limited to {commanded:.3g} m/s² "
            f"(the {action.actor.blueprint}'s limits: +{up:.3g} / -{down:.3g} m/s²)",
            actors=(action.actor.name,),
        )
    ctrl.speed.set_acceleration(commanded, jerk, (0.0, action.actor.top_speed))
    return commanded


@action("movable_object", "assign_acceleration")
class AssignAcceleration(InstantAction):
    """``assign_acceleration(acceleration)``: accelerate at that rate from now on (at once),
    until standstill or the top speed, or until another action sets the speed."""

    def start(self) -> None:
        command_acceleration(self, number(self.args["acceleration"]))


@action("movable_object", "change_acceleration")
class ChangeAcceleration(ActionBehaviour):
    """``change_acceleration(target, rate_profile, rate_peak)``: the acceleration moves to
    ``target`` at the jerk ``rate_peak`` (``none``: at once; ``smooth``/``constant``
    without a peak: 10 m/s³; ``asap``: 50 m/s³); ends when the commanded acceleration has
    reached it (or the speed a bound); the acceleration then persists."""

    own_motions = frozenset({"longitudinal"})

    def start(self) -> None:
        peak = self.args.get("rate_peak")
        kind = str(self.args.get("rate_profile", "none"))
        if peak is not None:
            jerk = number(peak)
        else:
            jerk = JERK_BY_PROFILE.get(kind, math.inf)
        plan = self.plan_time()
        if plan and kind in ("none", "constant") and peak is None:
            # spread over the phase: the change takes the planned duration
            change = number(self.args["target"]) - self.driver.speed.a_ref
            jerk = max(abs(change) / plan, 1e-3) if abs(change) > 1e-9 else math.inf
        self.target = command_acceleration(self, number(self.args["target"]), jerk)

    def step(self) -> Status:
        if self.driver.speed.accel_reached():
            return Status.SUCCESS
        return Status.RUNNING


@action("movable_object", "keep_acceleration")
class KeepAcceleration(ActionBehaviour):
    """``keep_acceleration()``: hold the acceleration the actor has when the phase starts."""

    own_motions = frozenset({"longitudinal"})
    finite = False

    def start(self) -> None:
        command_acceleration(self, self.state.accel)


#: jerk of change_acceleration by rate profile when no rate_peak is given (m/s³)
JERK_BY_PROFILE = {"none": math.inf, "constant": 10.0, "smooth": 10.0, "asap": 50.0}
