"""Movement modifiers: constraints on the speed and lateral controllers of an action's actor.

The timing rule is the base class's (``behaviours.base.Modifier``): ``at: start``
is realised by the witness at time 0 and checked at a later phase's start;
``at: end`` is planned to arrive when the phase ends (and checked then); ``at:
all`` is reached and held. The reference-relative forms (``faster_than``,
``side_of``, ``behind``, ...) obey the same rule and track the reference every
tick while they drive. Each class documents its own forms; the tolerances the
checks allow are the module's constants.
"""

from __future__ import annotations

import math

from osc2check.world.network import LaneRef
from osc2check.world.numbering import LANE_REFERENCES, lane_side
from osc2runner.behaviours.base import (
    ActionBehaviour,
    ActionError,
    AssignedPose,
    Modifier,
    number,
    whole,
)
from osc2runner.behaviours.driving import (
    SPEED_PROFILE,
    gap_between,
    lane_change_duration,
    lane_heading,
    lane_of,
    lane_width,
    offset_for_t,
    offset_in,
    profile_for,
    retarget,
    set_speed,
    side_of,
)
from osc2runner.compile.registry import modifier
from osc2runner.execution.context import RunContext
from osc2runner.execution.controls import LateralControl, is_walker
from osc2runner.execution.tolerances import MAX_CLOSING_SPEED, Tolerances
from osc2runner.instance.actors import Actor
from osc2runner.sim import ActorState, RateProfile, SpeedController

__all__ = [
    "Acceleration",
    "AvoidCollisions",
    "ChangeLaneModifier",
    "ChangeSpeedModifier",
    "Distance",
    "KeepLane",
    "KeepPosition",
    "KeepSpeedModifier",
    "Lane",
    "Lateral",
    "Orientation",
    "PhysicalMovement",
    "Position",
    "Speed",
    "Yaw",
]

#: gain of the longitudinal position tracking (1/s)
POSITION_GAIN = 0.5


def _lateral(action: ActionBehaviour) -> LateralControl:
    ctrl = action.controller
    if ctrl is None:
        raise ActionError("this actor has no lateral control (only vehicles change lanes)")
    if is_walker(ctrl):  # a walker: heads for the lateral target
        ctrl.yaw = None
    return ctrl.lateral


def _kph(speed: float) -> str:
    return f"{speed * 3.6:.2f} kph"


def _tolerances(action: ActionBehaviour) -> Tolerances:
    return action.ctx.tolerances


def _speed_problem(action: ActionBehaviour, speed: float, want: float) -> str | None:
    """None when ``speed`` is ``want`` within the tolerance, else both and the tolerance."""
    tol = _tolerances(action)
    if abs(speed - want) <= tol.speed:
        return None
    return f"the speed is {_kph(speed)}, not {_kph(want)} (tolerance {tol.kph()})"


# ---------------------------------------------------------------------- speed


_RELATIVE_SPEED = ("faster_than", "slower_than", "same_as")


@modifier("speed")
class Speed(Modifier):
    """``speed(v)``; ``faster_than``/``slower_than``/``same_as: ref`` make it
    ``ref.speed * factor ± v``.

    ``all``: reached with the ``smooth`` profile (2.5 m/s², 10 m/s³) and held; a
    reference is tracked every tick. ``end``: with a planned duration the speed
    changes at the one constant rate that arrives when the phase ends; without
    one the phase ends when the speed is reached. ``start``: the speed when the
    phase starts.
    """

    longitudinal = True

    def target(self, action: ActionBehaviour) -> float:
        args = self.args
        v = number(args.get("speed", 0.0))
        factor = number(args.get("factor", 1.0))
        for key, sign in (("faster_than", 1.0), ("slower_than", -1.0), ("same_as", 1.0)):
            ref = args.get(key)
            if isinstance(ref, Actor):
                return action.ctx.states[ref.name].speed * factor + sign * v
        return v

    def realise(self, action: ActionBehaviour) -> None:
        ctrl = action.controller
        v = self.target(action)
        self.relative = any(k in self.args for k in _RELATIVE_SPEED)
        self.planned = self.at == "end" and bool(action.remaining())
        if self.planned:
            change = v - action.state.speed
            set_speed(ctrl, v, profile_for("constant", change=change, duration=action.plan_time()))
        else:
            set_speed(ctrl, v, SPEED_PROFILE)

    def step(self, action: ActionBehaviour) -> None:
        if self.relative:
            retarget(action.driver, self.target(action))

    def finished(self, action: ActionBehaviour) -> bool:
        if self.at != "end" or self.planned:
            return False
        return _speed_problem(action, action.state.speed, self.target(action)) is None

    def holds(self, action: ActionBehaviour) -> str | None:
        return _speed_problem(action, action.state.speed, self.target(action))

    def assign(self, pose: AssignedPose, action: ActionBehaviour) -> None:
        pose.speed = self.target(action)


@modifier("change_speed")
class ChangeSpeedModifier(Modifier):
    """``change_speed(dv)``: the speed changes by ``dv`` from its value when the phase starts.

    Spread evenly over a planned duration, else with the ``smooth`` profile; ``end``
    and ``all`` both mean the change is complete when the phase ends.
    """

    longitudinal = True

    def realise(self, action: ActionBehaviour) -> None:
        self.goal = action.state.speed + number(self.args.get("speed", 0.0))
        profile = (
            profile_for(
                "constant", change=self.goal - action.state.speed, duration=action.plan_time()
            )
            if action.remaining()
            else RateProfile(SPEED_PROFILE)
        )
        set_speed(action.controller, self.goal, profile)

    def holds(self, action: ActionBehaviour) -> str | None:
        return _speed_problem(action, action.state.speed, self.goal)


@modifier("keep_speed")
class KeepSpeedModifier(Modifier):
    """``keep_speed()``: hold the speed the actor has when the phase starts."""

    longitudinal = True

    def realise(self, action: ActionBehaviour) -> None:
        set_speed(action.controller, action.state.speed, "none")


@modifier("acceleration")
class Acceleration(Modifier):
    """``acceleration(a)``: change speed at a constant ``a`` (to standstill when negative).

    Positive: towards the vehicle's top speed. Relative forms (``faster_than``
    ...) are not supported and fail the phase.
    """

    longitudinal = True

    def realise(self, action: ActionBehaviour) -> None:
        if any(k in self.args for k in _RELATIVE_SPEED):
            raise ActionError("acceleration relative to another actor is not supported")
        a = number(self.args.get("acceleration", 0.0))
        ctrl = action.controller
        if abs(a) < 1e-9:
            set_speed(ctrl, action.state.speed, "none")
            return
        set_speed(
            ctrl, action.actor.top_speed if a > 0.0 else 0.0, RateProfile("constant", peak=abs(a))
        )


@modifier("keep_position")
class KeepPosition(Modifier):
    """``keep_position()``: stand still."""

    longitudinal = True

    def realise(self, action: ActionBehaviour) -> None:
        set_speed(action.controller, 0.0, SPEED_PROFILE)

    def holds(self, action: ActionBehaviour) -> str | None:
        return _speed_problem(action, action.state.speed, 0.0)


@modifier("distance")
class Distance(Modifier):
    """``distance(d)``: the phase ends when the actor has travelled ``d`` (along its path,
    across roads)."""

    def realise(self, action: ActionBehaviour) -> None:
        self.start = action.state.distance
        self.goal = number(self.args.get("distance", 0.0))

    def finished(self, action: ActionBehaviour) -> bool:
        return action.state.distance - self.start >= self.goal - 1e-9


@modifier("position")
class Position(Modifier):
    """``position(distance: d | time: t, behind:|ahead_of: ref)``: a bumper-to-bumper gap.

    The checker's convention (its witness says "bumper to bumper"); ``time:`` is a
    headway at the follower's speed. ``all``: the gap is tracked with the speed
    (gain :data:`POSITION_GAIN`) from the phase start. ``end``: with a planned
    duration the gap error is closed evenly over the time left (at most
    :data:`MAX_CLOSING_SPEED` relative to the reference), so that it holds when
    the phase ends; without one the phase ends when it holds. ``start``: the
    gap when the phase starts. Without a reference, ``distance`` is the centre's
    distance along the road (``start`` only; the checker measures it along the
    actor's carriageway, the runner checks it on a one-road carriageway).
    """

    longitudinal = True

    def _reference(self) -> tuple[Actor | None, float]:
        args = self.args
        ahead, behind = args.get("ahead_of"), args.get("behind")
        if isinstance(ahead, Actor):
            return ahead, 1.0
        if isinstance(behind, Actor):
            return behind, -1.0
        return None, 1.0

    def _distance(self, follower_speed: float) -> float:
        """The bumper gap asked: ``distance``, or ``time`` at the follower's speed."""
        if "distance" in self.args:
            return number(self.args["distance"])
        if "time" in self.args:
            return number(self.args["time"]) * max(follower_speed, 0.0)
        raise ActionError("position() needs `distance` or `time`")

    def _error(self, action: ActionBehaviour) -> tuple[float, ActorState, float]:
        """(gap error: > 0 farther from the reference than asked, the reference's state, sign)."""
        ref, sign = self._reference()
        assert ref is not None
        me, other = action.state, action.ctx.states[ref.name]
        gap = sign * gap_between(other, me, bumpers=True)  # my bumper gap on the asked side
        follower = me if sign < 0 else other
        return gap - self._distance(follower.speed), other, sign

    def realise(self, action: ActionBehaviour) -> None:
        ref, _ = self._reference()
        if ref is None:
            raise ActionError(
                "position() without `ahead_of` or `behind` can only place an actor at the "
                "start of the scenario"
            )
        self.step(action)

    def step(self, action: ActionBehaviour) -> None:
        error, other, sign = self._error(action)
        left = action.remaining()
        if self.at == "end" and left:
            closing = _closing_speed(
                action, error, -sign * (action.state.speed - other.speed), left
            )
            retarget(action.driver, other.speed - sign * closing)
        else:
            retarget(action.driver, other.speed - sign * POSITION_GAIN * error)

    def finished(self, action: ActionBehaviour) -> bool:
        if self.at != "end" or action.remaining():
            return False
        error, other, _ = self._error(action)
        tol = _tolerances(action)
        return abs(error) <= tol.position and abs(action.state.speed - other.speed) <= tol.speed

    def holds(self, action: ActionBehaviour) -> str | None:
        ref, sign = self._reference()
        state = action.state
        tol = _tolerances(action).position
        if ref is None:
            want = number(self.args.get("distance", 0.0))
            along = state.s if state.direction >= 0 else _road_length(action, state) - state.s
            if abs(along - want) <= tol:
                return None
            return (
                f"it is at {along:.2f} m along the road, not {want:.2f} m (tolerance {tol:.2f} m)"
            )
        error, _, _ = self._error(action)
        if abs(error) <= tol:
            return None
        asked = self._distance(
            action.state.speed if sign < 0 else action.ctx.states[ref.name].speed
        )
        return f"the gap is {asked + error:.2f} m, not {asked:.2f} m (tolerance {tol:.2f} m)"

    def assign(self, pose: AssignedPose, action: ActionBehaviour) -> None:
        ref, sign = self._reference()
        speed = pose.speed if pose.speed is not None else action.state.speed
        if ref is None:
            state = action.state
            d = number(self.args.get("distance", 0.0))
            pose.s = d if state.direction >= 0 else _road_length(action, state) - d
            return
        other = action.ctx.states[ref.name]
        d = self._distance(speed if sign < 0 else other.speed)
        half = 0.5 * (action.actor.length + ref.length)
        pose.s = other.s + sign * (d + half) * (other.direction or 1)
        pose.reference = other


def _closing_speed(action: ActionBehaviour, error: float, closing: float, left: float) -> float:
    """The closing speed to ask for now so that a gap ``error`` m too wide is closed in
    ``left`` s, when the actor closes at ``closing`` m/s now and its speed follows what it
    is asked with the lag of its speed controller (a first-order lag of ``1 / kp``): it
    passes through the gap at its deadline (no margin: it arrives moving), at most
    :data:`MAX_CLOSING_SPEED` relative to the reference."""
    speed = action.controller.speed if action.controller is not None else None
    gains = speed.gains if isinstance(speed, SpeedController) else None
    lag = 1.0 / gains.kp if gains is not None and gains.kp > 0.0 else 1.0
    # what the closing speed now still covers while it turns into the one asked
    covered = lag * (1.0 - math.exp(-left / lag))
    wanted = (error - closing * covered) / max(left - covered, action.ctx.dt)
    return max(-MAX_CLOSING_SPEED, min(MAX_CLOSING_SPEED, wanted))


# ---------------------------------------------------------------------- lanes


@modifier("lane")
class Lane(Modifier):
    """``lane(n)``, ``lane(same_as: ref)``, ``lane(side_of: ref, side: s)``,
    ``lane(n, left_of: ref)``, ``lane(n, right_of: ref)``.

    Lanes are those of the road the actor is on, travelling its way. ``n`` counts from
    the ``from:`` side (default: the map's, see :mod:`osc2runner.instance.roads`);
    ``same_as`` is the lane with the reference's number, ``side_of`` the one ``n``
    lanes to a side of it, ``left_of``/``right_of`` to that side (``numbering.lane_side``,
    as the checker places them). ``all``: changes into the lane at once if needed and keeps
    it (following a reference when it changes lanes). ``end``: with a planned duration
    the lane change is timed to end when the phase ends (it starts a change's length
    before; a shorter phase spreads it over all of it); without one the change starts
    at once and the phase ends in the lane. ``start``: the lane when the phase starts.
    """

    lateral = True

    def _number(self, action: ActionBehaviour) -> int:
        """The lane asked for, counted from the right where the actor is."""
        ctx = action.ctx
        args = self.args
        here = lane_of(ctx, action.actor)
        n = args.get("lane", 1)
        if isinstance(n, tuple):
            raise ActionError("a lane range needs the solver's choice; give one lane")
        n = whole(n)
        lanes = ctx.lanes
        for key in LANE_REFERENCES:
            reference = args.get(key)
            if isinstance(reference, Actor):
                side = side_of(str(args["side"])) if "side" in args else None
                other = lanes.number(lane_of(ctx, reference), "right")
                return other + lane_side(key, side) * n
        counted_from = args.get("from")
        count = lanes.count(here)
        side_text = str(counted_from) if counted_from is not None else lanes.default_side
        return n if side_text == "right" else count + 1 - n

    def _lane(self, action: ActionBehaviour, number: int) -> LaneRef:
        """The lane numbered ``number`` from the right on the actor's road, its way."""
        ctx = action.ctx
        here = lane_of(ctx, action.actor)
        target = ctx.lanes.lane(here, number, "right")
        if target is None:
            count = ctx.lanes.count(here)
            raise ActionError(
                f"there is no lane {_scenario(ctx, here, number)} on road `{here.road}` "
                f"here ({count} driving lane(s) this way)"
            )
        return target

    def realise(self, action: ActionBehaviour) -> None:
        self.changing_to: LaneRef | None = None
        self.change_at: float | None = None
        self.relative = any(key in self.args for key in LANE_REFERENCES)
        if self.at == "end" and action.remaining():
            target = self._lane(action, self._number(action))
            if action.state.lane_ref == target:
                _lateral(action).keep_lane(target)
                self.changing_to = target
                return
            length = lane_change_duration(
                1, lane_width(action.ctx, action.state), phase=None, rate_peak=None, profile=None
            )
            left = action.plan_time() or 0.0
            self.change_at = action.elapsed + max(0.0, left - length)
            self.step(action)
            return
        self._apply(action, first=True)

    def step(self, action: ActionBehaviour) -> None:
        if self.change_at is not None:
            if action.elapsed + 1e-9 >= self.change_at:
                self.change_at = None
                target = self._lane(action, self._number(action))
                duration = action.plan_time() or action.ctx.dt
                _lateral(action).change_lane(action.state, target, duration=duration)
                self.changing_to = target
            return
        if self.at == "all" and self.relative:
            self._apply(action, first=False)

    def _apply(self, action: ActionBehaviour, first: bool) -> None:
        ctx = action.ctx
        state = action.state
        number = self._number(action)
        lateral = _lateral(action)
        if not first and self.changing_to is not None:
            if ctx.lanes.number(self.changing_to, "right") == number:
                return  # on its way into (or in) that lane already
        target = self._lane(action, number)
        if state.lane_ref == target and self.changing_to is None:
            lateral.keep_lane(target)
        else:
            lateral.change_lane(
                state,
                target,
                duration=lane_change_duration(
                    1, lane_width(ctx, state), phase=None, rate_peak=None, profile=None
                ),
            )
        self.changing_to = target

    def finished(self, action: ActionBehaviour) -> bool:
        if self.at != "end" or action.remaining():
            return False
        return self.holds(action) is None and _lateral(action).done(action.state)

    def holds(self, action: ActionBehaviour) -> str | None:
        state = action.state
        if state.lane_ref is None or state.lane is None:
            return "it is off the road"  # (the lane asked for is counted from where it is)
        return _lane_problem(action, self._number(action))

    def assign(self, pose: AssignedPose, action: ActionBehaviour) -> None:
        pose.lane = self._number(action)


def _lane_problem(action: ActionBehaviour, number: int) -> str | None:
    """None when the actor is in the lane numbered ``number`` from the right, else where
    it is instead."""
    state = action.state
    here = state.lane_ref
    if here is None or state.lane is None:
        return "it is off the road"
    lanes = action.ctx.lanes
    if lanes.number(here, "right") == number:
        return None
    return f"it is in lane {lanes.number(here)}, not lane {_scenario(action.ctx, here, number)}"


def _scenario(ctx: RunContext, here: LaneRef, number: int) -> int:
    """The scenario's number (the map's side) of the lane numbered ``number`` from the right."""
    if ctx.lanes.default_side == "right":
        return number
    lane: int = ctx.lanes.count(here) + 1 - number
    return lane


def _road_length(action: ActionBehaviour, state: ActorState) -> float:
    return action.ctx.network.roads[state.road].length if state.road is not None else 0.0


@modifier("change_lane")
class ChangeLaneModifier(Modifier):
    """``change_lane(n, side)``: end the phase ``n`` lanes to the side of the start lane.

    The change takes the phase's planned duration, else the default lane-change
    time. Without ``side`` one is drawn with the run's seed among the sides that exist.
    """

    lateral = True

    def realise(self, action: ActionBehaviour) -> None:
        ctx = action.ctx
        n = whole(self.args.get("lane", 1))
        start = lane_of(ctx, action.actor)
        side = self.args.get("side")
        if side is None:
            sides = [s for s in ("left", "right") if ctx.lanes.beside(start, s, n) is not None]
            if not sides:
                raise ActionError(f"no lane {n} lanes away on either side")
            side = sides[int(ctx.rng.integers(len(sides)))]
        target = ctx.lanes.beside(start, side_of(str(side)), n)
        if target is None:
            raise ActionError(
                f"there is no lane {n} lane(s) to the {side} of lane {ctx.lanes.number(start)}"
            )
        self.target = ctx.lanes.number(target, "right")
        duration = lane_change_duration(
            n,
            lane_width(ctx, action.state),
            phase=action.plan_time(),
            rate_peak=None,
            profile=None,
        )
        _lateral(action).change_lane(action.state, target, duration=duration)

    def holds(self, action: ActionBehaviour) -> str | None:
        return _lane_problem(action, self.target)


@modifier("keep_lane")
class KeepLane(Modifier):
    """``keep_lane()``: stay in the lane the phase starts in (at its centre, or at the
    offset a ``lateral`` of the phase asks for)."""

    lateral = True

    def realise(self, action: ActionBehaviour) -> None:
        if any(isinstance(m, Lateral) and m.at != "start" for m in action.use.modifiers):
            return  # a `lateral` of the phase keeps the lane, at its offset from the centre
        _lateral(action).keep_lane(lane_of(action.ctx, action.actor))


@modifier("lateral")
class Lateral(Modifier):
    """``lateral(distance: d)``: ``d`` to the left of the lane centre (to the right with
    ``side: right``); with a reference,
    ``d`` to its ``left_of``/``right_of``/``side_of`` side (``same_as``: aligned), on the
    road the actor is on.

    ``all``: reached and tracked; ``end``: reached over the planned duration (else
    the phase ends when reached); ``start``: the offset when the phase starts.
    """

    lateral = True

    def _target_t(self, action: ActionBehaviour) -> float | None:
        """The road ``t`` a reference form asks for (None without a reference)."""
        args = self.args
        d = number(args.get("distance", 0.0))
        for key, sign in (("left_of", 1.0), ("right_of", -1.0), ("same_as", 0.0)):
            ref = args.get(key)
            if isinstance(ref, Actor):
                other = action.ctx.states[ref.name]
                return other.t + sign * d * (other.direction or 1)
        ref = args.get("side_of")
        if isinstance(ref, Actor):
            other = action.ctx.states[ref.name]
            sign = 1.0 if side_of(str(args.get("side", "left"))) == "left" else -1.0
            return other.t + sign * d * (other.direction or 1)
        return None

    def _offset(self) -> float:
        """The offset from the lane centre asked for without a reference: ``distance`` to
        the left, or to the right with ``side: right`` (as the checker places it)."""
        d = number(self.args.get("distance", 0.0))
        return -d if str(self.args.get("side", "left")) == "right" else d

    def _wanted(self, action: ActionBehaviour, ref: LaneRef | None = None) -> float:
        """The offset from the centre of the actor's lane (or of ``ref``) asked for."""
        t = self._target_t(action)
        if t is not None:
            if ref is None:
                return offset_for_t(action.state, t)
            return offset_in(action.ctx, action.state, ref, t)
        return self._offset()

    def realise(self, action: ActionBehaviour) -> None:
        if self.at == "end" and action.remaining():
            lateral = _lateral(action)
            lateral.move_to(action.state, self._wanted(action), duration=action.plan_time())
            return
        self.step(action)

    def step(self, action: ActionBehaviour) -> None:
        if self.at == "end" and action.remaining():
            return  # the planned path arrives when the phase ends
        lateral = _lateral(action)
        state = action.state
        if lateral.route is None or state.lane_ref not in (lateral.route.lanes or ()):
            # a person on a sidewalk: from the driving lane beside it, as it was placed
            ref = lane_of(action.ctx, action.actor, beside=True)
            lateral.keep_lane(ref, self._wanted(action, ref))
        else:
            lateral.keep_offset(self._wanted(action))

    def finished(self, action: ActionBehaviour) -> bool:
        if self.at != "end" or action.remaining():
            return False
        return self.holds(action) is None

    def holds(self, action: ActionBehaviour) -> str | None:
        ref = lane_of(action.ctx, action.actor, beside=True)
        want = self._wanted(action, ref)
        offset = offset_in(action.ctx, action.state, ref)
        tol = _tolerances(action).lateral
        if abs(offset - want) <= tol:
            return None
        return (
            f"it is {offset - want:+.2f} m from the lateral position asked (tolerance {tol:.2f} m)"
        )

    def assign(self, pose: AssignedPose, action: ActionBehaviour) -> None:
        t = self._target_t(action)
        if t is None:
            pose.offset = self._offset()
        else:
            pose.t = t


# ---------------------------------------------------------------------- orientation


class _Heading(Modifier):
    """Heading modifiers: the start heading (the witness's, at time 0); checked later."""

    def wanted(self, action: ActionBehaviour) -> float:  # pragma: no cover - abstract
        raise NotImplementedError

    def realise(self, action: ActionBehaviour) -> None:
        ctrl = action.controller
        if is_walker(ctrl):  # a walker turns at once
            ctrl.yaw = lane_heading(action.ctx, action.state) + self.wanted(action)
            ctrl.lateral.release()
            return
        raise ActionError(
            f"{self.use.name}() with `at: {self.at}` is not supported for vehicles: the "
            "runner steers them along the lanes or a path; give the heading `at: start`"
        )

    def holds(self, action: ActionBehaviour) -> str | None:
        want = lane_heading(action.ctx, action.state) + self.wanted(action)
        diff = (action.state.yaw - want + math.pi) % (2 * math.pi) - math.pi
        tol = _tolerances(action).heading
        if abs(diff) <= tol:
            return None
        return (
            f"the heading differs by {math.degrees(diff):+.1f} deg "
            f"(tolerance {math.degrees(tol):.1f} deg)"
        )


@modifier("yaw", note="vehicles: at: start (the witness's heading), else checked; walkers turn")
class Yaw(_Heading):
    """``yaw(angle, at: start)``: the heading relative to the road when the phase starts."""

    def wanted(self, action: ActionBehaviour) -> float:
        if self.args.get("relative_to") is not None:
            raise ActionError("yaw relative to another actor is not supported")
        return number(self.args.get("angle", 0.0))

    def assign(self, pose: AssignedPose, action: ActionBehaviour) -> None:
        pose.yaw = self.wanted(action)


@modifier("orientation", note="yaw; vehicles: at: start, else checked; walkers turn")
class Orientation(_Heading):
    """``orientation(yaw: a, at: start)``: the heading relative to the road at the phase start."""

    def wanted(self, action: ActionBehaviour) -> float:
        return number(self.args.get("yaw", 0.0))

    def assign(self, pose: AssignedPose, action: ActionBehaviour) -> None:
        if "yaw" in self.args:
            pose.yaw = number(self.args["yaw"])


# ---------------------------------------------------------------------- behaviour options


@modifier("avoid_collisions")
class AvoidCollisions(Modifier):
    """``avoid_collisions(false)``: this actor's collisions in the phase do not fail the run."""

    allowing = False  # whether the phase allows them now

    def begin(self, action: ActionBehaviour) -> None:
        self.allowing = not bool(self.args.get("avoid", True))
        if self.allowing:
            allowed = action.ctx.collisions_allowed
            allowed[action.actor.name] = allowed.get(action.actor.name, 0) + 1

    def end(self, action: ActionBehaviour) -> None:
        if self.allowing:
            action.ctx.collisions_allowed[action.actor.name] -= 1
            self.allowing = False


@modifier("physical_movement", note="always physical; accepted, no effect")
class PhysicalMovement(Modifier):
    """``physical_movement(option)``: every movement in this runner is physical, which
    each option allows (``prefer_non_physical`` asks for exact motion only where the
    implementation has it): nothing to change."""

    def begin(self, action: ActionBehaviour) -> None:
        self.option = str(self.args.get("option", "prefer_physical"))


@modifier(
    "location",
    actor="stationary_object",
    note="scenario member: the object's world pose (instance.locations)",
)
class Location(Modifier):
    """``box.location(pose: p)``: the object is built at ``p`` (before compiling)."""


@modifier("set_map_file", actor="map", note="scenario member: the checker reads the map")
class SetMapFile(Modifier):
    """``the_map.set_map_file(file)``: the checker read the map (a built-in name or an
    OpenDRIVE file relative to the scenario) and placed the scenario on it; the runner
    loads the same map before compiling."""
