"""Keeping clear of what is ahead where the scenario leaves a vehicle's speed open.

The standard's ``avoid_collisions`` says that actors avoid collisions unless told
otherwise (its ``avoid`` is true by default). The runner reads it for the speed a
scenario leaves open: a vehicle in a ``drive()`` or ``follow_lane()`` whose modifiers
set no speed, acceleration, position or gap, keeps at least a safe gap behind the
nearest actor ahead in its path (``SAFE_GAP + SAFE_TIME`` x its speed, bumper to
bumper), slowing by the law the gap actions use (``motion.GapAction``), and takes
its own speed up again once the path is clear. Its own speed is the one it had when
the action began, or the one an earlier action left it (``_hold``); when the action
ends, it is the vehicle's target again, for the next action to hold.

What the runner does not do:

* a speed the scenario commands (a modifier, ``change_speed``, a gap action, an
  acceleration) is driven as commanded: when it leads into another actor, the
  collision fails the run (docs/runner.md, Outcomes);
* another action that commands the vehicle's speed during the phase takes it over:
  the following stops for the rest of the action;
* ``avoid_collisions(false)`` on the vehicle turns the following off while it is
  active, and a system under test (``--sut``) drives its vehicle itself;
* nothing is steered around: the vehicle slows in its path, down to a stop.
"""

from __future__ import annotations

import math

from osc2runner.behaviours.base import ActionBehaviour
from osc2runner.behaviours.driving import GAP_GAIN, GAP_LAG, retarget
from osc2runner.sim import ActorState
from osc2runner.sim.controllers import SpeedController, VehicleController

__all__ = ["SAFE_GAP", "SAFE_TIME", "Follower", "gap_ahead"]

#: the gap kept at a standstill (m) and the time gap added at speed (s)
SAFE_GAP = 2.0
SAFE_TIME = 1.5
#: how far ahead is looked (m, and s at the vehicle's speed)
LOOK_AHEAD = 20.0
LOOK_AHEAD_TIME = 4.0
#: lateral clearance below which an actor is in the path (m, besides half the widths)
PATH_MARGIN = 0.3


def gap_ahead(me: ActorState, other: ActorState) -> tuple[float, float] | None:
    """The bumper-to-bumper gap to ``other`` and its speed along ``me``'s direction of
    travel, when ``other`` is ahead in ``me``'s path and within the look-ahead: along
    the road (``s`` and ``t``) when both are on one road, else along ``me``'s heading."""
    if me.road is not None and me.road == other.road and me.direction:
        ahead = (other.s - me.s) * me.direction
        aside = other.t - me.t
    else:
        dx, dy = other.x - me.x, other.y - me.y
        cos, sin = math.cos(me.yaw), math.sin(me.yaw)
        ahead = dx * cos + dy * sin
        aside = dy * cos - dx * sin
    if ahead <= 0.0 or abs(aside) >= 0.5 * (me.width + other.width) + PATH_MARGIN:
        return None
    gap = ahead - 0.5 * (me.length + other.length)
    if gap > LOOK_AHEAD + LOOK_AHEAD_TIME * me.speed:
        return None
    along = other.speed * math.cos(other.yaw - me.yaw)
    return gap, max(along, 0.0)


class Follower:
    """The following of one ``drive()``: made when the action starts, stepped every tick
    (see the module docstring)."""

    def __init__(self, action: ActionBehaviour, speed: SpeedController) -> None:
        self.action = action
        self.speed = speed
        self.own = float(speed.target or 0.0)  # the vehicle's own speed, when clear
        self.written = speed.target

    @classmethod
    def of(cls, action: ActionBehaviour) -> Follower | None:
        """The following of ``action``; None where its speed is the scenario's."""
        controller = action.controller
        # a system under test drives its vehicle itself (the scenario's targets are its
        # intent); a person walks (``PedestrianController``)
        if not isinstance(controller, VehicleController) or action.drives("longitudinal"):
            return None
        speed = controller.speed
        if speed.target is None or speed.accel_goal is not None:
            return None  # released, or accelerating as an earlier action said
        return cls(action, speed)

    def step(self) -> bool:
        """One tick; False once another action commands the speed (the following ends)."""
        speed = self.speed
        if speed.target != self.written or speed.accel_goal is not None:
            return False
        action = self.action
        name = action.actor.name
        wanted = self.own
        if action.ctx.collisions_allowed.get(name, 0) <= 0:
            wanted = min(wanted, self._clear_speed())
        if wanted != speed.target:
            retarget(action.driver, wanted)
        self.written = speed.target
        return True

    def stop(self) -> None:
        """The action ends: the vehicle's own speed is its target again, for the next
        action to hold (unless another action commands the speed by now)."""
        speed = self.speed
        if speed.target == self.written and speed.accel_goal is None:
            retarget(self.action.driver, self.own)

    def _clear_speed(self) -> float:
        """The highest speed that keeps the safe gap to everything ahead in the path."""
        states = self.action.ctx.states
        name = self.action.actor.name
        me = states[name]
        lowest = math.inf
        for other_name, other in states.items():
            if other_name == name:
                continue
            found = gap_ahead(me, other)
            if found is None:
                continue
            gap, along = found
            error = gap - (SAFE_GAP + SAFE_TIME * me.speed)
            ahead = error + GAP_LAG * (along - me.speed)
            lowest = min(lowest, max(along + GAP_GAIN * ahead, 0.0))
        return lowest
