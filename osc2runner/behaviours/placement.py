"""Instant assignments: ``assign_position``, ``assign_speed``, ``assign_orientation``.

At the start of the scenario the checker's witness has realised them (the
world is built with every actor in place). Later in a run they teleport the
actor: the pose comes from the action's ``lane``/``position``/``lateral``
modifiers (their ``assign`` hooks), resolved against the actors' current positions.
"""

from __future__ import annotations

import numpy as np

from osc2check.world.projection import lane_centre
from osc2runner.behaviours.base import ActionError, AssignedPose, InstantAction, number
from osc2runner.behaviours.driving import lane_heading, set_speed
from osc2runner.behaviours.maps import map_point_xy
from osc2runner.compile.registry import action
from osc2runner.execution.controls import is_walker
from osc2runner.structs import member_number

__all__ = ["AssignOrientation", "AssignPosition", "AssignSpeed"]


def _movable(action: InstantAction, why: str) -> None:
    """A stationary object stays where its ``location`` put it (ActionError ``why``)."""
    if action.ctx.attached_world.kind(action.actor.name) == "obstacle":
        raise ActionError(why)


def _teleport(
    action: InstantAction, *, speed: float | None = None, yaw: float | None = None
) -> None:
    state = action.state
    _movable(action, "a stationary object cannot be moved after the start")
    action.ctx.place(
        action.actor.name,
        state.x,
        state.y,
        state.yaw if yaw is None else yaw,
        state.speed if speed is None else speed,
    )


def _not_hitched(action: InstantAction) -> None:
    """A hitched trailer moves with its tow vehicle: it cannot be put elsewhere."""
    tow = action.ctx.attached_world.hitched.get(action.actor.name)
    if tow is not None:
        raise ActionError(
            f"`{action.actor.name}` is hitched to `{tow}` and moves with it "
            f"(`{tow}.disconnect_trailer()` first)"
        )


@action("movable_object", "assign_position")
class AssignPosition(InstantAction):
    """``assign_position() with: lane(...); position(...); lateral(...)``: put the actor there;
    ``assign_position(position: p | route_point: r | odr_point: o)``: at that point of the
    world or the map (at time 0 too: the checker places actors by their modifiers)."""

    modifiers_realised = True

    def start(self) -> None:
        given = [k for k in ("position", "route_point", "odr_point") if k in self.args]
        if len(given) > 1:
            raise ActionError(f"give one of {', '.join(given)}, not several")
        if given == ["position"]:
            position = self.args["position"]
            try:
                x, y = member_number(position, "x"), member_number(position, "y")
            except TypeError:
                raise ActionError("`position` is not a position_3d") from None
            self._world_position(x, y)
            return
        for key in given:  # a route or OpenDRIVE point (at time 0 too): its world position
            x, y = map_point_xy(self.ctx, self.args[key])
            self._world_position(x, y, on_map=True)
            return
        if self.at_scenario_start:
            return
        _not_hitched(self)
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
        ctx.place(name, target.x, target.y, yaw, speed)
        ctrl = self.controller
        if ctrl is not None:
            set_speed(ctrl, speed, "none")
            ctrl.lateral.keep_lane(ref, offset)

    def _world_position(self, x: float, y: float, on_map: bool = False) -> None:
        """``assign_position(position: p)``: the actor's centre at world ``(x, y)``
        (``z`` is not used: the world is flat); heading and speed are kept, or come from
        the ``yaw``/``orientation`` and ``speed`` modifiers (a yaw from the road's
        direction there). A point of the map (``on_map``: a route or OpenDRIVE point)
        also gives the heading: the direction of travel of the lane there. At time 0
        too: the checker places actors by road coordinates only."""
        _not_hitched(self)
        state = self.state
        _movable(self, "a stationary object is placed with its `location` modifier")
        pose = AssignedPose()
        for modifier in self.use.modifiers:
            if modifier.use.name in ("speed", "yaw", "orientation"):
                modifier.evaluate()
                modifier.assign(pose, self)
        there = self.ctx.network.to_road(x, y)
        road_yaw = (
            self.ctx.network.lane_to_world(there.lane, there.s).yaw
            if there is not None
            else lane_heading(self.ctx, state)
        )
        if pose.yaw is not None:
            yaw = road_yaw + pose.yaw
        else:
            yaw = road_yaw if on_map else state.yaw
        speed = state.speed if pose.speed is None else pose.speed
        self.ctx.place(self.actor.name, x, y, yaw, speed)
        ctrl = self.controller
        if ctrl is not None:
            set_speed(ctrl, speed, "none")
            if hasattr(ctrl, "yaw"):
                ctrl.yaw = yaw
            elif ctrl.lateral is not None:
                ctrl.lateral.hold(self.ctx.states[self.actor.name])


@action("movable_object", "assign_speed")
class AssignSpeed(InstantAction):
    """``assign_speed(speed)``: the actor has that speed at once (along its heading)."""

    def start(self) -> None:
        speed = number(self.args["speed"])
        if not self.at_scenario_start:
            _teleport(self, speed=speed)
        if self.controller is not None:
            set_speed(self.controller, speed, "none")


@action("movable_object", "assign_orientation", note="yaw (the world is flat: roll, pitch 0)")
class AssignOrientation(InstantAction):
    """``assign_orientation(orientation)``: the heading at once, the world yaw of the
    ``orientation_3d`` (roll and pitch are not used: the world is flat). Walkers walk on
    in the new heading; vehicles keep their lateral position on the road."""

    def start(self) -> None:
        _not_hitched(self)
        orientation = self.args.get("orientation")
        yaw = getattr(orientation, "yaw", None)
        if yaw is None:
            raise ActionError("assign_orientation needs an orientation_3d with a yaw")
        _teleport(self, yaw=float(yaw))
        ctrl = self.controller
        if is_walker(ctrl):
            ctrl.yaw = float(yaw)
