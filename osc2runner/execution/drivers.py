"""The driver of each actor: the controller that turns behaviour targets into world inputs.

Vehicles get a :class:`~osc2runner.sim.VehicleController` (speed PID with rate
profiles, Stanley lateral control). Pedestrians get a
:class:`PedestrianController`: a speed with an acceleration limit along a
heading, no dynamics. Obstacles and the environment have no driver.

Behaviours set targets (``ctrl.speed.set_target``, ``ctrl.lateral.change_lane``);
targets persist when the behaviour that set them ends, so an actor keeps
driving as it was told until another behaviour changes it.
"""

from __future__ import annotations

import math
from typing import Any

from osc2check.road import Road
from osc2runner.sim import ActorState, PedestrianInput, RateProfile, VehicleController, World
from osc2runner.sim.vehicle import VehicleParams

__all__ = ["PedestrianController", "PedestrianSpeed", "controllers_for", "drive_with_sut"]


class PedestrianSpeed:
    """Target speed of a pedestrian, approached at a fixed acceleration."""

    def __init__(self, dt: float, accel: float = 1.5) -> None:
        self.dt = dt
        self.accel = accel
        self.target: float | None = None
        self.command = 0.0
        self.profile = RateProfile()

    def set_target(self, speed: float, profile: RateProfile | str = "none") -> None:
        self.target = max(0.0, float(speed))
        self.profile = RateProfile(profile) if isinstance(profile, str) else profile

    def reached(self, state: ActorState, tolerance: float = 0.1) -> bool:
        return self.target is not None and abs(state.speed - self.target) <= tolerance

    def release(self) -> None:
        self.target = None


class PedestrianController:
    """Speed along the road heading for a kinematic pedestrian."""

    def __init__(self, road: Road, dt: float) -> None:
        self.road = road
        self.speed = PedestrianSpeed(dt)
        self.lateral = None
        self.yaw: float | None = None

    def step(self, state: ActorState) -> PedestrianInput:
        s = self.speed
        if s.target is None:
            return PedestrianInput(state.speed, state.yaw if self.yaw is None else self.yaw)
        limit = s.accel * s.dt
        if s.profile.kind == "asap":
            limit *= 2.0
        v = state.speed + max(-limit, min(limit, s.target - state.speed))
        yaw = self.road.heading if self.yaw is None else self.yaw
        return PedestrianInput(v, yaw)


def controllers_for(world: World, road: Road) -> dict[str, Any]:
    """One controller per vehicle and pedestrian, holding the initial speed and lane."""
    controllers: dict[str, Any] = {}
    for name in world.names:
        kind = world.kind(name)
        state = world.state(name)
        if kind == "vehicle":
            params = world.params(name)
            assert isinstance(params, VehicleParams)
            ctrl = VehicleController(params, road, world.dt_control)
            ctrl.speed.set_target(max(0.0, state.speed), "none")
            ctrl.lateral.keep_offset(state.t)
            controllers[name] = ctrl
        elif kind == "pedestrian":
            ped = PedestrianController(road, world.dt_control)
            ped.speed.set_target(max(0.0, state.speed))
            ped.yaw = state.yaw if not math.isnan(state.yaw) else None
            controllers[name] = ped
    return controllers


def drive_with_sut(
    controllers: dict[str, Any], world: World, states: Any, name: str, sut: Any
) -> None:
    """Put the system under test ``sut`` in the seat of actor ``name``: its controller
    becomes the driver model of a :class:`~osc2runner.sut.driver.SutDriver` (the
    scenario's behaviours set its targets: the SUT's intent), which ``states`` (the
    run's states of each tick) feed."""
    from osc2runner.sut.driver import SutDriver

    inner = controllers[name]
    assert isinstance(inner, VehicleController)
    controllers[name] = SutDriver(name, sut, inner, world.road, states)
