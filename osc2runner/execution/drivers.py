"""The driver of each actor: the controller that turns behaviour targets into world inputs.

Vehicles get a :class:`~osc2runner.sim.VehicleController` (speed PID with rate
profiles, Stanley lateral control along their lane's route: the roads of the
witness's route for the actor, the other forks chosen with the run's seed); a
vehicle that starts with a trailer hitched knows its load. Pedestrians get a
:class:`PedestrianController`: a speed with an acceleration limit along a
heading, no dynamics. Trailers, obstacles and the environment have no driver.

Behaviours set targets (``ctrl.speed.set_target``, ``ctrl.lateral.change_lane``);
targets persist when the behaviour that set them ends, so an actor keeps
driving as it was told until another behaviour changes it.
"""

from __future__ import annotations

import math
import zlib
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from osc2check.world.network import LaneRef, RoadNetwork
from osc2check.world.projection import lane_centre
from osc2runner.execution.controls import Controller
from osc2runner.sim import ActorState, PedestrianInput, RateProfile, VehicleController, World
from osc2runner.sim.controllers import resolve_lane

if TYPE_CHECKING:
    from osc2runner.sut.driver import Log
from osc2runner.sim.tracking import Polyline, walker_heading
from osc2runner.sim.trailer import TrailerParams
from osc2runner.sim.vehicle import PedestrianParams, VehicleParams

__all__ = [
    "PedestrianController",
    "PedestrianSpeed",
    "WalkerLateral",
    "controllers_for",
    "drive_with_sut",
]


class PedestrianSpeed:
    """Target speed of a pedestrian, approached at a fixed acceleration; or, in the
    acceleration mode (:meth:`set_acceleration`), a commanded acceleration."""

    def __init__(self, dt: float, accel: float = 1.5, top: float = math.inf) -> None:
        self.dt = dt
        self.accel = accel
        self.top = top
        self.target: float | None = None
        self.command = 0.0
        self.profile = RateProfile()
        self.accel_goal: float | None = None
        self.accel_jerk = math.inf
        self.a_ref = 0.0
        self.speed_bounds = (0.0, top)

    def set_target(self, speed: float, profile: RateProfile | str = "none") -> None:
        self.target = min(max(0.0, float(speed)), self.top)
        self.profile = RateProfile(profile) if isinstance(profile, str) else profile
        self.accel_goal = None

    def set_acceleration(
        self, accel: float, jerk: float = math.inf, bounds: tuple[float, float] = (0.0, math.inf)
    ) -> None:
        """Accelerate at ``accel`` (reached at ``jerk``) within the speed ``bounds``."""
        self.accel_goal = float(accel)
        self.accel_jerk = float(jerk)
        self.speed_bounds = (bounds[0], min(bounds[1], self.top))
        self.target = self.speed_bounds[1] if accel > 0.0 else self.speed_bounds[0]

    def accel_reached(self, tolerance: float = 1e-6) -> bool:
        if self.accel_goal is None:
            return False
        return abs(self.a_ref - self.accel_goal) <= tolerance

    def next_speed(self, speed: float) -> float:
        """The speed at the end of this tick."""
        if self.accel_goal is not None:
            step = self.accel_jerk * self.dt
            self.a_ref += min(max(self.accel_goal - self.a_ref, -step), step)
            low, high = self.speed_bounds
            v = speed + self.a_ref * self.dt
            if v <= low or v >= high:
                v, self.a_ref = min(max(v, low), high), 0.0
            return v
        assert self.target is not None
        limit = self.accel * self.dt
        if self.profile.kind == "asap":
            limit *= 2.0
        return speed + max(-limit, min(limit, self.target - speed))

    def reached(self, state: ActorState, tolerance: float = 0.1) -> bool:
        return self.target is not None and abs(state.speed - self.target) <= tolerance

    def release(self) -> None:
        self.target = None
        self.accel_goal = None


class WalkerLateral:
    """Lateral position of a walker on the map: an offset from a lane's centre that it
    heads for (the lane it is in, unless a lane is given).

    The heading is the road's (its reference line's, or the opposite, whichever is
    nearer the walker's) turned towards the target, ``atan2(k (t* - t), v)`` (``k`` =
    :data:`WALKER_LATERAL_GAIN`), at most 90 degrees: a walker moves across the road as
    fast as it walks. Same calls as the vehicles' lateral controller (``keep_lane``,
    ``keep_offset``, ``move_to``, ``change_lane``, ``hold``, ``done``).
    """

    def __init__(self, network: RoadNetwork) -> None:
        self.network = network
        #: the target: a lane (None: the one it is in) and the offset from its centre
        self.path: tuple[LaneRef | None, float] | None = None
        self.error = 0.0  # last lateral error (m, positive: left of the target)
        self.route = None  # walkers follow no route of lanes

    def keep_lane(
        self, lane: LaneRef | int, offset: float = 0.0, state: ActorState | None = None
    ) -> None:
        self.path = (resolve_lane(self.network, lane, state), offset)

    def hold(self, state: ActorState) -> None:
        if math.isfinite(state.offset):
            self.path = (None, state.offset)

    def keep_offset(self, offset: float) -> None:
        self.path = (None, offset)

    def move_to(
        self,
        state: ActorState,
        offset: float,
        *,
        distance: float | None = None,
        duration: float | None = None,
        shape: str = "smooth",
    ) -> float:
        self.path = (None, offset)
        return offset

    def change_lane(self, state: ActorState, lane: LaneRef | int, **kwargs: Any) -> float:
        offset = float(kwargs.get("offset", 0.0))
        self.keep_lane(lane, offset, state)
        return offset

    def wanted_t(self, state: ActorState) -> float | None:
        """The road ``t`` the walker heads for on the road it is on (None: off the map)."""
        if self.path is None or state.road is None:
            return None
        ref, offset = self.path
        ref = ref if ref is not None and ref.road == state.road else state.lane_ref
        if ref is None:
            return None
        centre, _ = lane_centre(self.network, ref, np.array([state.s]))
        return float(centre[0]) + offset * self.network.lane(ref).direction

    def done(self, state: ActorState) -> bool:
        wanted = self.wanted_t(state)
        return wanted is None or abs(state.t - wanted) <= WALKER_LATERAL_DONE

    def release(self) -> None:
        self.path = None

    def heading(self, state: ActorState, speed: float) -> float:
        wanted = self.wanted_t(state)
        if wanted is None or state.road is None:
            return state.yaw
        self.error = state.t - wanted
        base = self.network.to_world(state.road, state.s).yaw
        along = math.cos(state.yaw - base) >= 0.0
        if not along:
            base += math.pi
        turn = math.atan2(WALKER_LATERAL_GAIN * (wanted - state.t), max(speed, 0.1))
        return base + (turn if along else -turn)


#: how fast a walker's lateral error closes relative to its speed (1/s per m/s)
WALKER_LATERAL_GAIN = 1.0
#: a walker is at its lateral target within this (m)
WALKER_LATERAL_DONE = 0.05


class PedestrianController:
    """A kinematic walker: a speed (or an acceleration) along a heading.

    The heading is, in this order: a world path's (``follow_path``), an explicit
    heading (``yaw``: set by ``orientation``/``yaw`` modifiers and at the start),
    the heading towards a lateral target (``lateral``), its own.
    """

    def __init__(self, network: RoadNetwork, dt: float, top: float = math.inf) -> None:
        self.network = network
        self.speed = PedestrianSpeed(dt, top=top)
        self.lateral = WalkerLateral(network)
        self.yaw: float | None = None
        self.path: Polyline | None = None
        self.heading_for: Callable[[ActorState], float] | None = None
        self._last: PedestrianInput | None = None

    def step(self, state: ActorState) -> PedestrianInput:
        s = self.speed
        last = self._last
        if (
            last is not None
            and s.accel_goal is None
            and s.target == state.speed == last.speed
            and self.heading_for is None
            and self.path is None
            and self.lateral.path is None
            and self.yaw == last.yaw
        ):
            return last  # standing or walking straight on as told: the same input
        if s.target is None:
            v = state.speed
        else:
            v = s.next_speed(state.speed)
        if self.heading_for is not None:
            yaw = self.heading_for(state)
        elif self.path is not None:
            yaw = walker_heading(self.path, state.x, state.y)
        elif self.lateral.path is not None and self.yaw is None:
            yaw = self.lateral.heading(state, v)
        else:
            yaw = state.yaw if self.yaw is None else self.yaw
        self._last = PedestrianInput(v, yaw)
        return self._last


def controllers_for(
    world: World, routes: Mapping[str, Sequence[str]] | None = None, seed: int = 0
) -> dict[str, Controller]:
    """One controller per vehicle and pedestrian, holding the initial speed and lane.

    ``routes`` gives a vehicle the roads its lane following passes (the witness's
    route); ``seed`` (with the actor's name) picks the forks nothing decides.
    """
    controllers: dict[str, Controller] = {}
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
            trailer = world.towing(name)
            if trailer is not None:
                towed = world.params(trailer)
                ctrl.speed.towed = towed if isinstance(towed, TrailerParams) else None
            controllers[name] = ctrl
        elif kind == "pedestrian":
            walker = world.params(name)
            top = walker.max_speed if isinstance(walker, PedestrianParams) else math.inf
            ped = PedestrianController(world.network, world.dt_control, top=top)
            ped.speed.set_target(max(0.0, state.speed))
            ped.yaw = state.yaw if not math.isnan(state.yaw) else None
            controllers[name] = ped
    return controllers


def drive_with_sut(
    controllers: dict[str, Controller],
    world: World,
    states: Any,
    name: str,
    sut: Any,
    log: Log | None = None,
    budget: float | None = None,
) -> None:
    """Put the system under test ``sut`` in the seat of actor ``name``: its controller
    becomes the driver model of a :class:`~osc2runner.sut.driver.SutDriver` (the
    scenario's behaviours set its targets: the SUT's intent), which ``states`` (the
    run's states of each tick) feed; its interventions go to ``log``; each of its steps
    has ``budget`` wall-clock seconds."""
    from osc2runner.sut.driver import SutDriver

    inner = controllers[name]
    assert isinstance(inner, VehicleController)
    controllers[name] = SutDriver(name, sut, inner, world.network, states, log, budget)
