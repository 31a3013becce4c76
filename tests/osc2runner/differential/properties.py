"""What each modifier's effect looks like in the telemetry: one property per modifier.

A property reads the subject's telemetry over its phase (the ticks between the
action's ``start`` and ``end`` in the event log) and the witness (the value the
solver chose from a range) and raises :class:`PropertyFailed` when the effect is not
there. The timing follows docs/runner.md: ``at: start`` holds at the phase's first
tick, ``at: end`` at its last, ``at: all`` (the default) throughout once reached —
for a phase that starts the scenario the witness placed the actor so at tick 0.
Tolerances are the runner's own verdict tolerances (``execution.tolerances``),
widened by what one control period of motion can add.

A property applies only when nothing else in the case commands the same quantity
(an action that sets the speed itself, ``remain_stationary`` and ``speed``); then
only the differential's other checks hold (the checker's verdict, no internal error,
no argument left unread). :data:`PROPERTIES` is the hand list; a modifier without an
entry fails ``test_every_modifier_has_a_property``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from functools import cache
from typing import Any

import numpy as np

from osc2check.world.builtin import builtin_network
from osc2check.world.network import LaneRef
from osc2runner.execution.tolerances import Tolerances
from tests.osc2runner.differential.cases import Call, Case

__all__ = ["PROPERTIES", "Observed", "PropertyFailed", "check", "phase_time"]

KPH = 1 / 3.6
#: the runner's verdict tolerances at the control period the harness runs with (50 ms)
TOLERANCES = Tolerances.for_period(0.05)
#: what a speed may be off by where the property reads it: the verdict's tolerance,
#: and what a control period at the comfort acceleration adds
SPEED = TOLERANCES.speed + 0.15
LATERAL = TOLERANCES.lateral
YAW = TOLERANCES.heading
GAP = TOLERANCES.position + 0.1


class PropertyFailed(AssertionError):
    """A modifier's effect is not in the telemetry."""


# actions that command a quantity themselves: a modifier of that quantity is the
# action's business then, and its property is not read
ACTION_COMMANDS: dict[str, frozenset[str]] = {
    "remain_stationary": frozenset({"speed", "lane", "lateral", "heading", "position"}),
    "assign_speed": frozenset({"speed"}),
    "assign_acceleration": frozenset({"speed"}),
    "change_speed": frozenset({"speed"}),
    "keep_speed": frozenset({"speed"}),
    "change_acceleration": frozenset({"speed"}),
    "keep_acceleration": frozenset({"speed"}),
    "change_lane": frozenset({"lane", "lateral"}),
    "follow_lane": frozenset({"lane", "lateral"}),
    "assign_position": frozenset({"lane", "lateral", "position", "speed"}),
    "assign_orientation": frozenset({"heading"}),
    "change_position": frozenset({"lane", "lateral", "position", "speed", "heading"}),
    "follow_path": frozenset({"lane", "lateral", "heading"}),
    "follow_trajectory": frozenset({"lane", "lateral", "heading", "speed"}),
    "replay_path": frozenset({"lane", "lateral", "heading", "position"}),
    "replay_trajectory": frozenset({"lane", "lateral", "heading", "speed", "position"}),
    "change_time_gap": frozenset({"speed", "position"}),
    "keep_time_gap": frozenset({"speed", "position"}),
    "change_space_gap": frozenset({"speed", "position"}),
    "keep_space_gap": frozenset({"speed", "position"}),
    "change_time_headway": frozenset({"speed", "position"}),
    "keep_time_headway": frozenset({"speed", "position"}),
    "change_space_headway": frozenset({"speed", "position"}),
    "keep_space_headway": frozenset({"speed", "position"}),
}


@dataclass
class Observed:
    """A finished run of a case, read for its properties."""

    case: Case
    result: Any  # osc2runner.RunResult
    line: int  # the tested modifier's line in the scenario text

    @property
    def telemetry(self) -> dict[str, np.ndarray]:
        return self.result.telemetry["sub"]

    @property
    def reference(self) -> dict[str, np.ndarray]:
        return self.result.telemetry["ref"]

    def phase(self) -> tuple[int, int]:
        """The first and last tick (rows) of the subject's action."""
        label = f"sub.{self.case.action.name}"
        start = end = None
        for r in self.result.events:
            if r.name == label and r.kind == "start" and start is None:
                start = r.tick
            elif r.name == label and r.kind in ("end", "stop", "fail") and start is not None:
                end = r.tick
        rows = len(self.telemetry["tick"])
        start = 0 if start is None else min(start, rows - 1)
        end = rows - 1 if end is None else min(end, rows - 1)
        return start, end

    def value(self, call: Call, name: str, default: float | None = None) -> float:
        """An argument's SI value: as written, or the witness's choice from its range."""
        arg = call.arg(name)
        if arg is None:
            if default is None:
                raise KeyError(name)
            return default
        if not arg.range:
            return float(arg.value)
        suffix = f".{call.name}@{self.line}.{name}"
        for p in self.result.metadata["witness"]["parameters"]:
            if p["name"].endswith(suffix):
                return float(Fraction(p["si"]))
        raise PropertyFailed(f"the witness has no value for the range given to `{name}`")

    def at(self, call: Call) -> str:
        return call.at


def phase_time(action: str, tested: Call | None) -> float:
    """A phase long enough for the tested modifier's effect to show (simulated seconds)."""
    name = tested.name if tested is not None else ""
    if name in ("lane", "change_lane", "lateral", "keep_lane") or action in (
        "change_lane",
        "follow_lane",
    ):
        return 4.0
    if name in ("distance", "position") or action.startswith(("change_", "keep_")):
        return 3.0
    return 1.5


def _ticks(obs: Observed, call: Call, settle: float = 0.0) -> np.ndarray:
    """The rows where an ``at`` of ``call`` says the constraint holds."""
    start, end = obs.phase()
    at = obs.at(call)
    if at == "start":
        return np.array([start])
    if at == "end":
        return np.array([end])
    dt = float(obs.result.metadata["dt_control"])
    first = min(end, start + int(round(settle / dt)))
    return np.arange(first, end + 1)


def _within(what: str, got: np.ndarray, want: np.ndarray | float, tol: float) -> None:
    error = np.abs(np.asarray(got, dtype=float) - want)
    if error.size and float(np.max(error)) > tol:
        i = int(np.argmax(error))
        raise PropertyFailed(
            f"{what}: {float(np.asarray(got).flat[i]):.3f}, wanted "
            f"{float(np.broadcast_to(want, np.shape(got)).flat[i]):.3f} (tolerance {tol})"
        )


# ---------------------------------------------------------------------- per modifier


def _speed(obs: Observed, call: Call) -> None:
    tel = obs.telemetry
    factor = obs.value(call, "factor", 1.0)
    v = obs.value(call, "speed", 0.0)
    rows = _ticks(obs, call)
    want: np.ndarray | float = v
    for key, sign in (("faster_than", 1.0), ("slower_than", -1.0), ("same_as", 1.0)):
        if call.has(key):
            want = obs.reference["speed"][rows] * factor + sign * v
    _within("speed (m/s)", tel["speed"][rows], want, SPEED)


def _change_speed(obs: Observed, call: Call) -> None:
    start, end = obs.phase()
    if obs.at(call) == "start":
        return  # a change that holds at the start is no change
    tel = obs.telemetry
    dv = obs.value(call, "speed")
    _within("change of speed (m/s)", tel["speed"][end] - tel["speed"][start], dv, SPEED)


def _keep_speed(obs: Observed, call: Call) -> None:
    start, end = obs.phase()
    tel = obs.telemetry
    _within("speed kept (m/s)", tel["speed"][_ticks(obs, call)], tel["speed"][start], SPEED)


def _acceleration(obs: Observed, call: Call) -> None:
    if obs.at(call) != "all":
        return  # an acceleration at one instant: the controller's, not a speed to read
    start, end = obs.phase()
    tel = obs.telemetry
    a = obs.value(call, "acceleration")
    dt = float(obs.result.metadata["dt_control"])
    seconds = (end - start) * dt
    if seconds <= 0:
        return
    speeds = tel["speed"][start : end + 1]
    if a < 0 and float(np.min(speeds)) < 0.2:
        return  # stopped: the speed cannot fall further
    mean = (tel["speed"][end] - tel["speed"][start]) / seconds
    _within("mean acceleration (m/s^2)", mean, a, 0.35)


def _keep_position(obs: Observed, call: Call) -> None:
    _within("speed (m/s)", obs.telemetry["speed"][_ticks(obs, call, settle=2.0)], 0.0, SPEED)


def _distance(obs: Observed, call: Call) -> None:
    start, end = obs.phase()
    d = obs.value(call, "distance")
    travelled = obs.telemetry["distance"][end] - obs.telemetry["distance"][start]
    if obs.case.duration is not None and travelled < d - 0.5:
        return  # the phase's duration ended it first
    _within("distance travelled (m)", travelled, d, 0.5 + obs.telemetry["speed"][end] * 0.05)


def _position(obs: Observed, call: Call) -> None:
    tel = obs.telemetry
    rows = _ticks(obs, call, settle=0.0 if obs.at(call) != "all" else 0.0)
    if not call.has("behind") and not call.has("ahead_of"):
        if obs.at(call) == "start":
            _within("s at the start (m)", tel["s"][rows], obs.value(call, "distance"), GAP)
        return
    ref = obs.reference
    sign = 1.0 if call.has("ahead_of") else -1.0
    half = 0.5 * (_length(obs, "sub") + _length(obs, "ref"))
    gap = sign * (tel["s"][rows] - ref["s"][rows]) - half
    if call.has("distance"):
        want: np.ndarray | float = obs.value(call, "distance")
    else:
        follower = tel if sign < 0 else ref
        want = obs.value(call, "time") * follower["speed"][rows]
    _within("bumper-to-bumper gap (m)", gap, want, GAP)


def _length(obs: Observed, name: str) -> float:
    for actor in obs.result.metadata["witness"]["actors"]:
        if actor["name"] == name:
            return float(actor["length_m"])
    return 0.0


def _lane(obs: Observed, call: Call) -> None:
    tel = obs.telemetry
    rows = _ticks(obs, call, settle=obs.case.duration or 0.0 if obs.at(call) == "all" else 0.0)
    if obs.at(call) == "all":
        rows = rows[-1:]  # reached (a change takes time) and then held: the phase's end
    n = int(round(obs.value(call, "lane", 1)))
    for key, side in (("same_as", 0), ("left_of", 1), ("right_of", -1), ("side_of", None)):
        if call.has(key):
            if side is None:
                side = 1 if call.arg("side") and call.arg("side").value == "left" else -1  # type: ignore[union-attr]
            want = obs.reference["lane"][rows] + side * n
            _within("lane (from the right)", tel["lane"][rows], want, 0)
            return
    counted = call.arg("from")
    want_lane = n if counted is None or counted.value == "right" else 4 - n  # 3 lanes
    _within("lane (from the right)", tel["lane"][rows], want_lane, 0)


def _change_lane(obs: Observed, call: Call) -> None:
    if obs.at(call) == "start":
        return
    start, end = obs.phase()
    tel = obs.telemetry
    n = int(round(obs.value(call, "lane", 1)))
    moved = int(tel["lane"][end]) - int(tel["lane"][start])
    side = call.arg("side")
    if side is None:
        _within("lanes changed", abs(moved), n, 0)
    else:
        _within("lanes changed (left +)", moved, n if side.value == "left" else -n, 0)


def _keep_lane(obs: Observed, call: Call) -> None:
    start, end = obs.phase()
    tel = obs.telemetry
    _within("lane kept", tel["lane"][_ticks(obs, call)], tel["lane"][start], 0)


@cache
def _centre_t(road: str, lane_id: int, s: float) -> float:
    network = builtin_network("default")
    pose = network.lane_to_world(LaneRef(road, 0, lane_id), s, 0.0)
    point = network.to_road(pose.x, pose.y)
    return float(point.t) if point is not None else 0.0


def _offset(tel: dict[str, np.ndarray], row: int) -> float:
    return float(tel["t"][row]) - _centre_t(str(tel["road"][row]), int(tel["lane_id"][row]), 0.0)


def _lateral(obs: Observed, call: Call) -> None:
    tel = obs.telemetry
    rows = _ticks(obs, call)
    if obs.at(call) == "all":
        rows = rows[-1:]
    d = obs.value(call, "distance", 0.0) if call.has("distance") else None
    for key, sign in (("left_of", 1.0), ("right_of", -1.0), ("same_as", 0.0), ("side_of", None)):
        if call.has(key):
            if sign is None:
                side = call.arg("side")
                sign = 1.0 if side is None or side.value == "left" else -1.0
            if d is None:
                return  # some value within 10 cm of the reference line: any
            want = obs.reference["t"][rows] + sign * d
            _within("lateral position t (m)", tel["t"][rows], want, LATERAL)
            return
    if d is None:
        return
    offsets = np.array([_offset(tel, int(r)) for r in rows])
    _within("offset from the lane centre (m)", offsets, d, LATERAL)


def _heading(name: str) -> Callable[[Observed, Call], None]:
    def check(obs: Observed, call: Call) -> None:
        angle = obs.value(call, name, 0.0) if call.has(name) else None
        if angle is None:
            return
        tel = obs.telemetry
        rows = _ticks(obs, call)
        if obs.at(call) == "all":
            rows = rows[-1:]
        diff = (tel["yaw"][rows] - angle + math.pi) % (2 * math.pi) - math.pi
        _within("heading relative to the road (rad)", diff, 0.0, YAW)

    return check


def _none(obs: Observed, call: Call) -> None:
    """A modifier whose effect no telemetry channel shows in a run without its trigger:
    ``physical_movement`` (every movement is physical), ``avoid_collisions`` (only a
    collision shows it)."""


def _along(obs: Observed, call: Call) -> None:
    """``along``/``along_trajectory`` take paths the generator does not write."""


#: the property of each modifier, and which quantity it commands (None: no property
#: reads it, for the reason its function gives)
PROPERTIES: dict[str, tuple[Callable[[Observed, Call], None], str | None]] = {
    "speed": (_speed, "speed"),
    "change_speed": (_change_speed, "speed"),
    "keep_speed": (_keep_speed, "speed"),
    "acceleration": (_acceleration, "speed"),
    "keep_position": (_keep_position, "speed"),
    "distance": (_distance, "position"),
    "position": (_position, "position"),
    "lane": (_lane, "lane"),
    "change_lane": (_change_lane, "lane"),
    "keep_lane": (_keep_lane, "lane"),
    "lateral": (_lateral, "lateral"),
    "yaw": (_heading("angle"), "heading"),
    "orientation": (_heading("yaw"), "heading"),
    "physical_movement": (_none, None),
    "avoid_collisions": (_none, None),
    "along": (_along, None),
    "along_trajectory": (_along, None),
}


def check(obs: Observed) -> str | None:
    """Check the tested modifier's property on a successful run; the reason it is not
    read (another command of the same quantity), or None when it was checked."""
    call = obs.case.tested
    if call is None:
        return "no modifier"
    prop, quantity = PROPERTIES[call.name]
    if quantity is not None and quantity in ACTION_COMMANDS.get(obs.case.action.name, ()):
        return f"`{obs.case.action.name}` commands the {quantity} itself"
    prop(obs, call)
    return None
