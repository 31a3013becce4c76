"""Movement modifiers: constraints on the speed and lateral controllers of an action's actor.

Each class documents what its ``at: start`` / ``end`` / ``all`` forms do. The
reference-relative forms (``faster_than``, ``side_of``, ``behind``, ...) track
the reference every tick while ``at: all`` holds.
"""

from __future__ import annotations

from typing import Any

from osc2runner.behaviours.base import ActionBehaviour, ActionError, AssignedPose, Modifier
from osc2runner.behaviours.driving import (
    SPEED_PROFILE,
    gap_between,
    lane_change_duration,
    lane_of,
    profile_for,
    retarget,
    set_speed,
    side_of,
)
from osc2runner.compile.registry import modifier
from osc2runner.instance.actors import Actor
from osc2runner.sim import RateProfile

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


def _lateral(action: ActionBehaviour) -> Any:
    ctrl = action.controller
    if ctrl is None or getattr(ctrl, "lateral", None) is None:
        raise ActionError("this actor has no lateral control (only vehicles change lanes)")
    return ctrl.lateral


def _skip_start(modifier: Modifier, action: ActionBehaviour) -> bool:
    """``at: start`` constraints of phases that start the scenario were realised before tick 0."""
    return modifier.at == "start" and action.at_scenario_start


# ---------------------------------------------------------------------- speed


@modifier("speed")
class Speed(Modifier):
    """``speed(v)``: reach ``v`` (``smooth`` profile: 2.5 m/s², 10 m/s³) and hold it.

    ``faster_than``/``slower_than``/``same_as: ref`` make the target
    ``ref.speed * factor ± v``, tracked every tick. ``at: start`` sets the
    start speed (or the target when the phase starts later); ``at: end``
    reaches ``v`` by the end of the phase at a constant rate.
    """

    longitudinal = True

    def target(self, action: ActionBehaviour) -> float:
        args = self.args
        v = float(args.get("speed", 0.0))
        factor = float(args.get("factor", 1.0))
        for key, sign in (("faster_than", 1.0), ("slower_than", -1.0), ("same_as", 1.0)):
            ref = args.get(key)
            if isinstance(ref, Actor):
                return action.ctx.states[ref.name].speed * factor + sign * v
        return v

    def begin(self, action: ActionBehaviour) -> None:
        self.evaluate()
        self.tracking = self.at == "all" and any(
            k in self.args for k in ("faster_than", "slower_than", "same_as")
        )
        if _skip_start(self, action):
            return
        ctrl = action.controller
        v = self.target(action)
        if self.at == "end":
            remaining = action.remaining()
            profile = (
                profile_for("constant", change=v - action.state.speed, duration=remaining)
                if remaining
                else RateProfile(SPEED_PROFILE)
            )
            set_speed(ctrl, v, profile)
        else:
            set_speed(ctrl, v, SPEED_PROFILE)

    def step(self, action: ActionBehaviour) -> None:
        if self.tracking:
            retarget(action.controller, self.target(action))

    def assign(self, pose: AssignedPose, action: ActionBehaviour) -> None:
        pose.speed = self.target(action)


@modifier("change_speed")
class ChangeSpeedModifier(Modifier):
    """``change_speed(dv)``: the speed changes by ``dv`` from its value when the phase starts."""

    longitudinal = True

    def begin(self, action: ActionBehaviour) -> None:
        self.evaluate()
        v0 = action.state.speed
        dv = float(self.args.get("speed", 0.0))
        remaining = action.remaining()
        profile = (
            profile_for("constant", change=dv, duration=remaining)
            if remaining
            else RateProfile(SPEED_PROFILE)
        )
        set_speed(action.controller, v0 + dv, profile)


@modifier("keep_speed")
class KeepSpeedModifier(Modifier):
    """``keep_speed()``: hold the speed the actor has when the phase starts."""

    longitudinal = True

    def begin(self, action: ActionBehaviour) -> None:
        self.evaluate()
        set_speed(action.controller, action.state.speed, "none")


@modifier("acceleration")
class Acceleration(Modifier):
    """``acceleration(a)``: change speed at a constant ``a`` (to standstill when negative).

    Positive: towards the vehicle's top speed. Relative forms (``faster_than``
    ...) are not supported and fail the phase.
    """

    longitudinal = True

    def begin(self, action: ActionBehaviour) -> None:
        self.evaluate()
        if any(k in self.args for k in ("faster_than", "slower_than", "same_as")):
            raise ActionError("acceleration relative to another actor is not supported")
        a = float(self.args.get("acceleration", 0.0))
        ctrl = action.controller
        if abs(a) < 1e-9:
            set_speed(ctrl, action.state.speed, "none")
            return
        top = float(getattr(action.actor.params, "max_speed", 70.0))
        set_speed(ctrl, top if a > 0.0 else 0.0, RateProfile("constant", peak=abs(a)))


@modifier("keep_position")
class KeepPosition(Modifier):
    """``keep_position()``: stand still."""

    longitudinal = True

    def begin(self, action: ActionBehaviour) -> None:
        self.evaluate()
        set_speed(action.controller, 0.0, SPEED_PROFILE)


@modifier("distance")
class Distance(Modifier):
    """``distance(d)``: the phase ends when the actor has travelled ``d`` along the road."""

    def begin(self, action: ActionBehaviour) -> None:
        self.evaluate()
        self.s0 = action.state.s
        self.goal = float(self.args.get("distance", 0.0))

    def finished(self, action: ActionBehaviour) -> bool:
        return abs(action.state.s - self.s0) >= self.goal - 1e-9


@modifier("position")
class Position(Modifier):
    """``position(distance: d, behind:|ahead_of: ref)``: a bumper-to-bumper gap ``d``.

    The checker's convention (its witness says "bumper to bumper"). ``at:
    start`` places the actor; ``at: all`` / ``end`` track the gap with the
    speed (gain :data:`POSITION_GAIN`). ``time:`` is a headway at the actor's
    speed. Without a reference only ``at: start`` is supported (the actor's
    centre ``d`` from the start of the road).
    """

    longitudinal = True

    def _reference(self) -> tuple[Actor | None, float]:
        args = self.args
        if isinstance(args.get("ahead_of"), Actor):
            return args["ahead_of"], 1.0
        if isinstance(args.get("behind"), Actor):
            return args["behind"], -1.0
        return None, 1.0

    def _distance(self, speed: float) -> float:
        if "distance" in self.args:
            return float(self.args["distance"])
        if "time" in self.args:
            return float(self.args["time"]) * speed
        raise ActionError("position() needs `distance` or `time`")

    def begin(self, action: ActionBehaviour) -> None:
        self.evaluate()
        ref, _ = self._reference()
        if _skip_start(self, action):
            return
        if ref is None:
            raise ActionError(
                "position() without `ahead_of` or `behind` can only place an "
                "actor at the start of the scenario"
            )
        self.step(action)

    def step(self, action: ActionBehaviour) -> None:
        if self.at == "start" and action.elapsed > 0.0:
            return
        ref, sign = self._reference()
        if ref is None:
            return
        me = action.state
        other = action.ctx.states[ref.name]
        want = self._distance(max(me.speed, 0.0))
        gap = sign * gap_between(other, me, bumpers=True)  # my bumper gap on the asked side
        error = gap - want  # >0: farther from the reference than asked
        retarget(action.controller, other.speed - sign * POSITION_GAIN * error)

    def assign(self, pose: AssignedPose, action: ActionBehaviour) -> None:
        ref, sign = self._reference()
        speed = pose.speed if pose.speed is not None else action.state.speed
        d = self._distance(max(speed, 0.0))
        if ref is None:
            pose.s = d
            return
        half = 0.5 * (
            float(getattr(action.actor.params, "length", 0.0))
            + float(getattr(ref.params, "length", 0.0))
        )
        pose.s = action.ctx.states[ref.name].s + sign * (d + half)


# ---------------------------------------------------------------------- lanes


@modifier("lane")
class Lane(Modifier):
    """``lane(n)``, ``lane(same_as: ref)``, ``lane(side_of: ref, side: s)``.

    ``n`` counts from the ``from:`` side (default: the map's, see
    :mod:`osc2runner.instance.roads`). ``at: start`` places the actor; ``all``
    changes into the lane if needed and keeps it (following the reference
    when it changes lanes); ``end`` arrives by the end of the phase.
    """

    lateral = True

    def _target(self, ctx: Any, reference_lane: Any) -> int:
        args = self.args
        n = args.get("lane", 1)
        if isinstance(n, tuple):
            raise ActionError("a lane range needs the solver's choice; give one lane")
        n = int(n)
        if isinstance(args.get("same_as"), Actor):
            return reference_lane(args["same_as"])
        if isinstance(args.get("side_of"), Actor):
            side = side_of(str(args.get("side", "left")))
            return ctx.lanes.beside(reference_lane(args["side_of"]), side, n)
        side = args.get("from")
        return ctx.lanes.to_road(n, str(side) if side is not None else None)

    def begin(self, action: ActionBehaviour) -> None:
        self.evaluate()
        self.changing_to: int | None = None
        if _skip_start(self, action):
            return
        self._apply(action, first=True)

    def step(self, action: ActionBehaviour) -> None:
        if self.at == "all" and ("same_as" in self.args or "side_of" in self.args):
            self._apply(action, first=False)

    def _apply(self, action: ActionBehaviour, first: bool) -> None:
        ctx = action.ctx
        target = self._target(ctx, lambda a: lane_of(ctx, a))
        if not ctx.road.has_lane(target):
            raise ActionError(
                f"lane {ctx.lanes.to_scenario(target)} does not exist on map `{ctx.road.name}`"
            )
        lateral = _lateral(action)
        if not first and target == self.changing_to:
            return
        state = action.state
        if state.lane == target and self.changing_to is None:
            lateral.keep_lane(target)
        else:
            duration = action.remaining() if self.at == "end" else None
            lateral.change_lane(
                state,
                target,
                duration=lane_change_duration(
                    1, ctx.road.lane_width, phase=duration, rate_peak=None, profile=None
                ),
            )
        self.changing_to = target

    def assign(self, pose: AssignedPose, action: ActionBehaviour) -> None:
        ctx = action.ctx
        pose.lane = self._target(ctx, lambda a: lane_of(ctx, a))


@modifier("change_lane")
class ChangeLaneModifier(Modifier):
    """``change_lane(n, side)``: end the phase ``n`` lanes to the side of the start lane.

    Without ``side`` one is drawn with the run's seed among the sides that exist.
    """

    lateral = True

    def begin(self, action: ActionBehaviour) -> None:
        self.evaluate()
        ctx = action.ctx
        n = int(self.args.get("lane", 1))
        start = lane_of(ctx, action.actor)
        side = self.args.get("side")
        if side is None:
            sides = [
                s for s in ("left", "right") if ctx.road.has_lane(ctx.lanes.beside(start, s, n))
            ]
            if not sides:
                raise ActionError(f"no lane {n} lanes away on either side")
            side = sides[int(ctx.rng.integers(len(sides)))]
        target = ctx.lanes.beside(start, side_of(str(side)), n)
        if not ctx.road.has_lane(target):
            raise ActionError(
                f"there is no lane {n} lane(s) to the {side} of lane {ctx.lanes.to_scenario(start)}"
            )
        duration = lane_change_duration(
            n, ctx.road.lane_width, phase=action.remaining(), rate_peak=None, profile=None
        )
        _lateral(action).change_lane(action.state, target, duration=duration)


@modifier("keep_lane")
class KeepLane(Modifier):
    """``keep_lane()``: stay in the lane the phase starts in (at its centre)."""

    lateral = True

    def begin(self, action: ActionBehaviour) -> None:
        self.evaluate()
        _lateral(action).keep_lane(lane_of(action.ctx, action.actor))


@modifier("lateral")
class Lateral(Modifier):
    """``lateral(distance: d)``: ``d`` to the left of the lane centre; with a reference,
    ``d`` to its ``left_of``/``right_of``/``side_of`` side (``same_as``: aligned), tracked."""

    lateral = True

    def _target_t(self, action: ActionBehaviour) -> float | None:
        args = self.args
        d = float(args.get("distance", 0.0))
        for key, sign in (("left_of", 1.0), ("right_of", -1.0), ("same_as", 0.0)):
            ref = args.get(key)
            if isinstance(ref, Actor):
                return action.ctx.states[ref.name].t + sign * d
        ref = args.get("side_of")
        if isinstance(ref, Actor):
            sign = 1.0 if side_of(str(args.get("side", "left"))) == "left" else -1.0
            return action.ctx.states[ref.name].t + sign * d
        return None

    def begin(self, action: ActionBehaviour) -> None:
        self.evaluate()
        if _skip_start(self, action):
            return
        self.step(action)

    def step(self, action: ActionBehaviour) -> None:
        lateral = _lateral(action)
        t = self._target_t(action)
        if t is None:
            lateral.keep_lane(
                lane_of(action.ctx, action.actor), offset=float(self.args.get("distance", 0.0))
            )
        else:
            lateral.keep_offset(t)

    def assign(self, pose: AssignedPose, action: ActionBehaviour) -> None:
        t = self._target_t(action)
        if t is None:
            pose.offset = float(self.args.get("distance", 0.0))
        else:
            pose.t = t


# ---------------------------------------------------------------------- orientation


class _StartOnly(Modifier):
    def begin(self, action: ActionBehaviour) -> None:
        self.evaluate()
        if _skip_start(self, action):
            return
        raise ActionError(
            f"{self.use.name}() is only supported with `at: start` on a phase "
            "that starts the scenario"
        )


@modifier("yaw", note="at: start only")
class Yaw(_StartOnly):
    """``yaw(angle, at: start)``: the start heading relative to the road."""

    def assign(self, pose: AssignedPose, action: ActionBehaviour) -> None:
        if self.args.get("relative_to") is not None:
            raise ActionError("yaw relative to another actor is not supported")
        pose.yaw = float(self.args.get("angle", 0.0))


@modifier("orientation", note="at: start only (yaw)")
class Orientation(_StartOnly):
    """``orientation(yaw: a, at: start)``: the start heading relative to the road."""

    def assign(self, pose: AssignedPose, action: ActionBehaviour) -> None:
        if "yaw" in self.args:
            pose.yaw = float(self.args["yaw"])


# ---------------------------------------------------------------------- behaviour options


@modifier("avoid_collisions")
class AvoidCollisions(Modifier):
    """``avoid_collisions(false)``: this actor's collisions in the phase do not fail the run."""

    def begin(self, action: ActionBehaviour) -> None:
        self.evaluate()
        self.allowing = not bool(self.args.get("avoid", True))
        if self.allowing:
            allowed = action.ctx.collisions_allowed
            allowed[action.actor.name] = allowed.get(action.actor.name, 0) + 1

    def end(self, action: ActionBehaviour) -> None:
        if getattr(self, "allowing", False):
            action.ctx.collisions_allowed[action.actor.name] -= 1
            self.allowing = False


@modifier("physical_movement", note="always physical; accepted, no effect")
class PhysicalMovement(Modifier):
    """``physical_movement(...)``: every movement in this runner is physical; nothing to do."""


@modifier(
    "set_map_file", actor="map", note="scenario member: chooses the built-in road before the run"
)
class SetMapFile(Modifier):
    """``the_map.set_map_file(file)``: the road is chosen from it before compiling (runner)."""
