"""Small driving helpers shared by actions and modifiers: speed targets, lanes, gaps.

On a map, an actor's lane is a lane of the road it is on
(:class:`~osc2check.world.network.LaneRef`); lane numbers are counted on that road
and in that direction (:class:`~osc2runner.instance.roads.LaneNumbers`). Gaps
between two actors on one road are taken along its ``s``; between actors on
different roads (through a junction) along the follower's heading.
"""

from __future__ import annotations

import math

import numpy as np

from osc2check.world.network import LaneRef
from osc2check.world.projection import lane_centre
from osc2runner.behaviours.base import ActionError
from osc2runner.execution.context import RunContext
from osc2runner.execution.controls import Controller
from osc2runner.instance.actors import Actor
from osc2runner.sim import ActorState, RateProfile

__all__ = [
    "GAP_GAIN",
    "GAP_LAG",
    "LANE_CHANGE_ACCEL",
    "gap_between",
    "lane_change_duration",
    "lane_heading",
    "lane_of",
    "lane_width",
    "offset_for_t",
    "offset_in",
    "profile_for",
    "retarget",
    "set_speed",
    "side_of",
]

#: peak lateral acceleration of a lane change by rate profile (m/s²); the duration
#: follows from the lateral distance: the minimum-jerk blend peaks at 5.77·d/T²
LANE_CHANGE_ACCEL = {"none": 4.0, "asap": 5.0, "constant": 1.3, "smooth": 1.3}
_QUINTIC_PEAK = 10.0 / 3.0**0.5
#: the profile a speed modifier approaches its target with
SPEED_PROFILE = "smooth"
#: gain of gap tracking: speed change per metre of gap error (1/s), and the lag (s)
#: the gap error is looked ahead by (the speed follows its target that much late)
GAP_GAIN = 0.4
GAP_LAG = 1.0


def profile_for(
    kind: str | None,
    peak: float | None = None,
    change: float | None = None,
    duration: float | None = None,
) -> RateProfile:
    """A rate profile from an OSC2 ``dynamic_profile``, a peak rate, or a phase duration."""
    kind = kind or "none"
    if (
        duration is not None
        and duration > 0.0
        and change is not None
        and kind in ("none", "constant")
    ):
        return RateProfile("constant", peak=max(abs(change) / duration, 0.05))
    if peak is not None and peak > 0.0:
        if kind in ("constant", "smooth"):
            return RateProfile(kind, peak=peak)
        if kind == "asap":
            return RateProfile("asap")
        return RateProfile("rate_peak", peak=peak)
    return RateProfile(kind)


def set_speed(ctrl: Controller | None, speed: float, profile: RateProfile | str = "none") -> None:
    """Give a controller a new target speed (>= 0) with a rate profile."""
    if ctrl is None:
        raise ActionError("the actor has no driver (it cannot move)")
    ctrl.speed.set_target(max(0.0, float(speed)), profile)


def retarget(ctrl: Controller, speed: float) -> None:
    """Move the current target speed without restarting its profile (tracking a reference)."""
    if ctrl.speed.target is None:
        ctrl.speed.set_target(max(0.0, float(speed)), "none")
    else:
        ctrl.speed.target = max(0.0, float(speed))


def lane_of(ctx: RunContext, actor: Actor, beside: bool = False) -> LaneRef:
    """The driving lane an actor is in now; ``beside``: for one on another lane of its
    road (a person on a sidewalk), the driving lane next to it on its side (its lane
    1). An action on an actor off the lanes fails."""
    state: ActorState = ctx.states[actor.name]
    ref = state.lane_ref
    if ref is not None and state.lane is not None:
        return ref
    if beside and state.road is not None and state.direction:
        try:
            return ctx.network.lane_from_osc2_index(state.road, state.s, 1, state.direction)
        except (KeyError, ValueError):
            pass
    raise ActionError(f"`{actor.name}` is not in a driving lane")


def offset_in(ctx: RunContext, state: ActorState, ref: LaneRef, t: float | None = None) -> float:
    """The offset left of lane ``ref``'s centre, in its direction of travel, of the road
    coordinate ``t`` (the actor's own by default) where the actor is."""
    t = state.t if t is None else t
    if ref == state.lane_ref:
        return state.offset + (t - state.t) * state.direction
    centre, _ = lane_centre(ctx.network, ref, np.array([state.s]))
    return (t - float(centre[0])) * ctx.network.lane(ref).direction


def lane_width(ctx: RunContext, state: ActorState) -> float:
    """The width of the lane an actor is in (3.5 m off the lanes)."""
    ref = state.lane_ref
    if ref is None:
        return 3.5
    return float(ctx.network.width(ref, state.s))


def lane_heading(ctx: RunContext, state: ActorState) -> float:
    """The direction of travel of the lane an actor is in (its own yaw off the lanes)."""
    ref = state.lane_ref
    if ref is None:
        return state.yaw
    return ctx.network.lane_to_world(ref, state.s).yaw


def offset_for_t(state: ActorState, t: float) -> float:
    """The offset from the centre of the actor's lane (left, in its direction of travel)
    of the road coordinate ``t`` on the actor's road."""
    return state.offset + (t - state.t) * state.direction


def side_of(side: str) -> str:
    """``left``/``right`` of an OSC2 side (right-hand traffic: inside left, outside right)."""
    if side in ("left", "inside"):
        return "left"
    if side in ("right", "outside"):
        return "right"
    raise ActionError(f"side `{side}` is not left or right")


def lane_change_duration(
    lanes: int,
    lane_width: float,
    *,
    phase: float | None,
    rate_peak: float | None,
    profile: str | None,
) -> float:
    """How long a lane change takes: the phase, a peak lateral speed, or the profile.

    Without a phase duration or a ``rate_peak`` the profile bounds the peak
    lateral acceleration (:data:`LANE_CHANGE_ACCEL`): one 3.5 m lane takes
    2.5 s with ``none`` (the library default), 2.0 s ``asap``, 3.9 s ``smooth``.
    """
    distance = abs(lanes) * lane_width
    if phase is not None and phase > 0.0:
        return phase
    if rate_peak is not None and rate_peak > 0.0:
        # the quintic blend's peak lateral speed is 15/8 of the mean
        return 1.875 * distance / rate_peak
    accel = LANE_CHANGE_ACCEL.get(profile or "none", LANE_CHANGE_ACCEL["none"])
    seconds: float = (_QUINTIC_PEAK * distance / accel) ** 0.5
    return seconds


def gap_between(me: ActorState, other: ActorState, *, bumpers: bool) -> float:
    """Longitudinal distance from ``me`` to ``other`` (positive: other ahead): along the
    road's ``s`` in ``me``'s direction of travel when both are on one road, else along
    ``me``'s heading.

    With ``bumpers`` the half lengths of both are taken off (a space gap).
    """
    if me.road is not None and me.road == other.road and me.direction:
        d = (other.s - me.s) * me.direction
    else:
        d = (other.x - me.x) * math.cos(me.yaw) + (other.y - me.y) * math.sin(me.yaw)
    if bumpers:
        half = 0.5 * (me.length + other.length)
        d = d - half if d >= 0.0 else d + half
    return d
