"""The driver of each actor: the controller that turns behaviour targets into world inputs.

Vehicles get a :class:`~osc2runner.sim.VehicleController` (speed PID with rate
profiles, Stanley lateral control along their lane's route: the roads of the
witness's route for the actor, the other forks chosen with the run's seed).
Pedestrians get a
:class:`PedestrianController`: a speed with an acceleration limit along a
heading, no dynamics. Obstacles and the environment have no driver.

Behaviours set targets (``ctrl.speed.set_target``, ``ctrl.lateral.change_lane``);
targets persist when the behaviour that set them ends, so an actor keeps
driving as it was told until another behaviour changes it.
"""

from __future__ import annotations

import math
import zlib
from collections.abc import Mapping, Sequence
from typing import Any

from osc2runner.sim import ActorState, PedestrianInput, RateProfile, VehicleController, World
from osc2runner.sim.vehicle import VehicleParams

__all__ = ["PedestrianController", "PedestrianSpeed", "controllers_for"]


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
    """Speed along a heading (its start heading unless told otherwise) for a kinematic
    pedestrian."""

    def __init__(self, dt: float) -> None:
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
        yaw = state.yaw if self.yaw is None else self.yaw
        return PedestrianInput(v, yaw)


def controllers_for(
    world: World, routes: Mapping[str, Sequence[str]] | None = None, seed: int = 0
) -> dict[str, Any]:
    """One controller per vehicle and pedestrian, holding the initial speed and lane.

    ``routes`` gives a vehicle the roads its lane following passes (the witness's
    route); ``seed`` (with the actor's name) picks the forks nothing decides.
    """
    controllers: dict[str, Any] = {}
    routes = routes or {}
    for name in world.names:
        kind = world.kind(name)
        state = world.state(name)
        if kind == "vehicle":
            params = world.params(name)
            assert isinstance(params, VehicleParams)
            picked = zlib.crc32(f"{seed}/{name}".encode())
            ctrl = VehicleController(params, world.network, world.dt_control, seed=picked)
            ctrl.lateral.on_route = lambda path, n=name: world.follow(n, path)
            ctrl.lateral.set_route(routes.get(name, ()))
            ctrl.speed.set_target(max(0.0, state.speed), "none")
            ctrl.lateral.hold(state)
            controllers[name] = ctrl
        elif kind == "pedestrian":
            ped = PedestrianController(world.dt_control)
            ped.speed.set_target(max(0.0, state.speed))
            ped.yaw = state.yaw if not math.isnan(state.yaw) else None
            controllers[name] = ped
    return controllers
