"""Instant assignments: ``assign_position``, ``assign_speed``, ``assign_orientation``.

At the start of the scenario the checker's witness has realised them (the
world is built with every actor in place). Later in a run they teleport the
actor: the pose comes from the action's ``lane``/``position``/``lateral``
modifiers (their ``assign`` hooks), resolved against the actors' current positions.
"""

from __future__ import annotations

import numpy as np

from osc2check.world.projection import lane_centre
from osc2runner.behaviours.base import ActionError, AssignedPose, InstantAction
from osc2runner.behaviours.driving import lane_heading, set_speed
from osc2runner.compile.registry import action

__all__ = ["AssignOrientation", "AssignPosition", "AssignSpeed"]


def _teleport(
    action: InstantAction, *, speed: float | None = None, yaw: float | None = None
) -> None:
    ctx = action.ctx
    world = ctx.world
    assert world is not None
    state = action.state
    if world.kind(action.actor.name) == "obstacle":
        raise ActionError("a stationary object cannot be moved after the start")
    x, y = state.x, state.y
    world.place(
        action.actor.name,
        x,
        y,
        state.yaw if yaw is None else yaw,
        state.speed if speed is None else speed,
    )
    ctx.refresh()


@action("movable_object", "assign_position")
class AssignPosition(InstantAction):
    """``assign_position() with: lane(...); position(...); lateral(...)``: put the actor there."""

    modifiers_realised = True

    def start(self) -> None:
        if self.at_scenario_start:
            return
        for key in ("position", "route_point", "odr_point"):
            if key in self.args:
                raise ActionError(
                    f"assign_position({key}: ...) is not supported; place the actor with "
                    "the lane() and position() modifiers"
                )
        ctx = self.ctx
        name = self.actor.name
        state = self.state
        pose = AssignedPose()
        for modifier in sorted(self.use.modifiers, key=lambda m: m.use.name != "speed"):
            modifier.evaluate()  # the speed first: a time gap needs it
            modifier.assign(pose, self)
        where = pose.reference if pose.reference is not None else state
        if where.road is None or not where.direction:
            raise ActionError("the actor is not on a road to place it on")
        network = ctx.network
        road = network.roads[where.road]
        s = pose.s if pose.s is not None else where.s
        if not 0.0 <= s <= road.length:
            raise ActionError(
                f"s = {s:.2f} m is off road `{where.road}` (0 .. {road.length:.2f} m)"
            )
        section = road.section_at(s).index
        number = pose.lane if pose.lane is not None else (state.lane or 1)
        lanes = ctx.lanes.lanes(where.road, section, where.direction)
        if not 1 <= number <= len(lanes):
            raise ActionError(f"the assigned lane {number} does not exist on road `{where.road}`")
        ref = lanes[number - 1]
        if pose.t is not None:
            centre, _ = lane_centre(network, ref, np.array([s]))
            offset = (pose.t - float(centre[0])) * where.direction
        else:
            offset = pose.offset or 0.0
        target = network.lane_to_world(ref, s, offset)
        yaw = target.yaw + (pose.yaw or 0.0)
        speed = pose.speed if pose.speed is not None else state.speed
        ctx.world.place(name, target.x, target.y, yaw, speed)  # type: ignore[union-attr]
        ctx.refresh()
        ctrl = self.controller
        if ctrl is not None:
            set_speed(ctrl, speed, "none")
            if getattr(ctrl, "lateral", None) is not None:
                ctrl.lateral.keep_lane(ref, offset)


@action("movable_object", "assign_speed")
class AssignSpeed(InstantAction):
    """``assign_speed(speed)``: the actor has that speed at once (along its heading)."""

    def start(self) -> None:
        speed = float(self.args["speed"])
        if not self.at_scenario_start:
            _teleport(self, speed=speed)
        if self.controller is not None:
            set_speed(self.controller, speed, "none")


@action("movable_object", "assign_orientation", note="yaw only")
class AssignOrientation(InstantAction):
    """``assign_orientation(orientation)``: the heading at once (yaw relative to the road)."""

    def start(self) -> None:
        orientation = self.args.get("orientation")
        yaw = getattr(orientation, "yaw", None)
        if yaw is None:
            raise ActionError("assign_orientation needs an orientation with a yaw")
        if not self.at_scenario_start:
            _teleport(self, yaw=lane_heading(self.ctx, self.state) + float(yaw))
