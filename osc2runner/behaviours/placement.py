"""Instant assignments: ``assign_position``, ``assign_speed``, ``assign_orientation``.

At the start of the scenario the initializer has already realised them (the
world is built with every actor in place). Later in a run they teleport the
actor: the pose comes from the action's ``lane``/``position``/``lateral``
modifiers, resolved against the actors' current positions.
"""

from __future__ import annotations

from typing import Any

from osc2runner.actors import Actor
from osc2runner.behaviours.base import ActionError, InstantAction
from osc2runner.behaviours.driving import set_speed
from osc2runner.compile.registry import registry
from osc2runner.initializer import StartPlan, _Rel

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


@registry.action("movable_object", "assign_position")
class AssignPosition(InstantAction):
    """``assign_position() with: lane(...); position(...); lateral(...)``: put the actor there."""

    modifiers_realised = True

    def start(self) -> None:
        if self.at_scenario_start:
            return
        for key in ("position", "route_point", "odr_point"):
            if key in self.args:
                raise ActionError(
                    f"assign_position({key}: ...) needs a road network; place the "
                    "actor with the lane() and position() modifiers"
                )
        ctx = self.ctx
        plan = StartPlan(list(ctx.actors.values()), ctx.lanes)
        name = self.actor.name
        for modifier in self.use.modifiers:
            args = modifier.evaluate()
            modifier.place(plan, self.actor, {**args, "at": "start"})
        pose = plan.poses[name]
        state = self.state
        lane = pose.lane
        if isinstance(lane, _Rel):
            lane = ctx.states[lane.ref].lane + int(lane.delta)
        if lane is None:
            lane = state.lane
        s = pose.s
        if isinstance(s, _Rel):
            s = ctx.states[s.ref].s + s.delta
        if s is None:
            s = state.s
        if lane is None or not ctx.road.has_lane(lane):
            raise ActionError("the assigned lane does not exist")
        x, y = ctx.road.lane_to_xy(s, lane, pose.offset or 0.0)
        yaw = ctx.road.heading + (pose.yaw or 0.0)
        speed = pose.speed if pose.speed is not None else state.speed
        ctx.world.place(name, x, y, yaw, speed)  # type: ignore[union-attr]
        ctx.refresh()
        ctrl = self.controller
        if ctrl is not None:
            set_speed(ctrl, speed, "none")
            if getattr(ctrl, "lateral", None) is not None:
                ctrl.lateral.keep_offset(ctx.states[name].t)

    @staticmethod
    def place_arguments(plan: StartPlan, actor: Actor, args: dict[str, Any]) -> None:
        """Nothing beyond the modifiers: position structs need a road network."""


@registry.action("movable_object", "assign_speed")
class AssignSpeed(InstantAction):
    """``assign_speed(speed)``: the actor has that speed at once (along its heading)."""

    def start(self) -> None:
        speed = float(self.args["speed"])
        if not self.at_scenario_start:
            _teleport(self, speed=speed)
        if self.controller is not None:
            set_speed(self.controller, speed, "none")

    @staticmethod
    def place_arguments(plan: StartPlan, actor: Actor, args: dict[str, Any]) -> None:
        if "speed" in args:
            plan.speed(actor.name, float(args["speed"]), None)


@registry.action("movable_object", "assign_orientation", note="yaw only")
class AssignOrientation(InstantAction):
    """``assign_orientation(orientation)``: the heading at once (yaw relative to the road)."""

    def start(self) -> None:
        orientation = self.args.get("orientation")
        yaw = getattr(orientation, "yaw", None)
        if yaw is None:
            raise ActionError("assign_orientation needs an orientation with a yaw")
        if not self.at_scenario_start:
            _teleport(self, yaw=self.ctx.road.heading + float(yaw))

    @staticmethod
    def place_arguments(plan: StartPlan, actor: Actor, args: dict[str, Any]) -> None:
        yaw = getattr(args.get("orientation"), "yaw", None)
        if yaw is not None:
            plan.yaw(actor.name, float(yaw), None)
