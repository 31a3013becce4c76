"""Small driving helpers shared by actions and modifiers: speed targets, lanes, gaps."""

from __future__ import annotations

from typing import Any

from osc2runner.behaviours.base import ActionError
from osc2runner.execution.context import RunContext
from osc2runner.instance.actors import Actor
from osc2runner.sim import ActorState, RateProfile

__all__ = [
    "LANE_CHANGE_ACCEL",
    "gap_between",
    "lane_change_duration",
    "lane_of",
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


def set_speed(ctrl: Any, speed: float, profile: RateProfile | str = "none") -> None:
    """Give a controller a new target speed (>= 0) with a rate profile."""
    if ctrl is None:
        raise ActionError("the actor has no driver (it cannot move)")
    ctrl.speed.set_target(max(0.0, float(speed)), profile)


def retarget(ctrl: Any, speed: float) -> None:
    """Move the current target speed without restarting its profile (tracking a reference)."""
    if ctrl.speed.target is None:
        ctrl.speed.set_target(max(0.0, float(speed)), "none")
    else:
        ctrl.speed.target = max(0.0, float(speed))


def lane_of(ctx: RunContext, actor: Actor | Any) -> int:
    """The road lane an actor is in now; an action on an actor off the road fails."""
    state: ActorState = ctx.states[actor.name]
    if state.lane is None:
        raise ActionError(f"`{actor.name}` is not on the road")
    return state.lane


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
    return (_QUINTIC_PEAK * distance / accel) ** 0.5


def gap_between(me: ActorState, other: ActorState, *, bumpers: bool) -> float:
    """Longitudinal distance along the road from ``me`` to ``other`` (positive: other ahead).

    With ``bumpers`` the half lengths of both are taken off (a space gap).
    """
    d = other.s - me.s
    if bumpers:
        half = 0.5 * (me.length + other.length)
        d = d - half if d >= 0.0 else d + half
    return d
