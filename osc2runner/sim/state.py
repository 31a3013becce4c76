"""What the world is made of and what it gives back: actor specs, inputs, states, weather.

:class:`ActorSpec` is an actor to create, :class:`VehicleInput` and
:class:`PedestrianInput` what a driver or a walker commands each control tick,
:class:`ActorState` an actor's read-out at a tick. :func:`actor_state` is the one
place an :class:`ActorState` is made from a body's read-out and its road position;
every bank (``sim/vehicle_bank.py``, ``trailer_bank.py``, ``walker_bank.py``,
``obstacle_bank.py``) calls it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from osc2check.world.carriageways import carriageways, start_pose
from osc2check.world.network import LaneRef, RoadNetwork
from osc2check.world.tracking import RoadPosition
from osc2runner.sim.trailer import TrailerParams
from osc2runner.sim.vehicle import ObstacleParams, PedestrianParams, VehicleParams

__all__ = [
    "DRY_FRICTION",
    "ActorParams",
    "ActorSpec",
    "ActorState",
    "PedestrianInput",
    "VehicleInput",
    "Weather",
    "actor_state",
    "weather_friction",
]

ActorParams = VehicleParams | PedestrianParams | ObstacleParams | TrailerParams

DRY_FRICTION = 1.0


@dataclass(frozen=True, slots=True)
class ActorSpec:
    """An actor to create and its initial state.

    The position is given in road coordinates or in world coordinates (``x`` and
    ``y``, which win when given). In road coordinates, ``lane`` is a
    :class:`~osc2check.world.network.LaneRef` with ``s`` its road's ``s``, or a lane
    number counted from the right (1 = rightmost) on the map's first carriageway
    (the road of a built-in map) with ``s`` along it; ``offset`` is to the left of the
    lane centre; ``lane=None`` takes ``offset`` as the ``t`` of that carriageway's first
    road. ``yaw`` is the world heading in radians (default: the lane's direction of
    travel) and ``speed`` the initial speed along it in m/s. A trailer ``towed_by`` a
    vehicle starts hitched to it: on its hitch, with its heading and speed (its own
    position, heading and speed are not used). A ``kinematic`` vehicle has no body in
    the physics model: the kinematic model moves it (``sim/kinematic_bank.py``).
    """

    name: str
    params: ActorParams
    s: float = 0.0
    lane: int | LaneRef | None = 1
    offset: float = 0.0
    x: float | None = None
    y: float | None = None
    yaw: float | None = None
    speed: float = 0.0
    towed_by: str | None = None
    kinematic: bool = False  # a vehicle moved by the kinematic model (sim/kinematic_bank.py)

    @property
    def kind(self) -> str:
        """``vehicle``, ``trailer``, ``pedestrian`` or ``obstacle``."""
        if isinstance(self.params, VehicleParams):
            return "vehicle"
        if isinstance(self.params, TrailerParams):
            return "trailer"
        if isinstance(self.params, PedestrianParams):
            return "pedestrian"
        return "obstacle"

    def pose(self, network: RoadNetwork) -> tuple[float, float, float]:
        """Initial world ``(x, y, yaw)``."""
        first = carriageways(network)[0]
        if isinstance(self.lane, LaneRef):
            pose = network.lane_to_world(self.lane, self.s, self.offset)
        elif self.lane is not None:
            pose = start_pose(network, first, self.s, self.lane, self.offset)[2]
        else:
            leg = first.leg_at(self.s)
            pose = network.to_world(leg.road, leg.road_s(self.s), self.offset)
            if leg.direction < 0:
                pose = replace(pose, yaw=pose.yaw + math.pi)
        x, y = (self.x, self.y) if self.x is not None and self.y is not None else (pose.x, pose.y)
        yaw = pose.yaw if self.yaw is None else self.yaw
        return (x, y, yaw)


@dataclass(frozen=True, slots=True)
class VehicleInput:
    """Driver inputs of a vehicle for one control tick."""

    throttle: float = 0.0
    brake: float = 0.0
    steer: float = 0.0  # +1 = full left


@dataclass(frozen=True, slots=True)
class PedestrianInput:
    """Commanded velocity of a pedestrian: speed (m/s) along yaw (rad)."""

    speed: float = 0.0
    yaw: float = 0.0


@dataclass(frozen=True, slots=True)
class Weather:
    """Recorded weather. ``rain`` and ``fog`` are intensities in [0, 1]."""

    rain: float = 0.0
    fog: float = 0.0


def weather_friction(weather: Weather) -> float:
    """The default road friction for ``weather``: 1.0 dry, 0.7 (light) to 0.4 (heavy rain)."""
    if weather.rain <= 0.0:
        return DRY_FRICTION
    return 0.7 - 0.3 * min(weather.rain, 1.0)


@dataclass(slots=True)  # read-only by convention: made per actor per tick (frozen costs 4x)
class ActorState:
    """Read-out of one actor at a control tick (SI units, world frame).

    ``x``/``y`` are the bounding-box centre, ``speed`` the signed speed along
    the heading, ``accel`` its change over the last control step,
    ``friction`` the mean tire friction (NaN for actors without tires),
    ``throttle``/``brake``/``steer`` the applied (rate-limited) inputs, and
    ``articulation`` a hitched trailer's articulation angle (its tow vehicle's
    heading less its own; NaN otherwise).

    Road coordinates of the centre: ``road`` (None off every road), ``s`` and ``t``
    on it, ``section`` and ``lane_id`` (OpenDRIVE) of the lane it is in, ``offset``
    left of that lane's centre in its direction of travel, ``lane`` the OSC2 number
    of that lane counted from the right (None outside driving lanes), ``on_road``
    whether it stands on the drivable surface; ``distance`` is the distance
    travelled since the start (m).
    """

    name: str
    kind: str
    tick: int
    time: float
    x: float
    y: float
    yaw: float
    speed: float
    lateral_speed: float
    yaw_rate: float
    accel: float
    lane: int | None
    s: float
    t: float
    friction: float
    throttle: float
    brake: float
    steer: float
    length: float
    width: float
    road: str | None = None
    section: int = -1
    lane_id: int = 0
    offset: float = math.nan
    direction: int = 0
    on_road: bool = False
    distance: float = 0.0
    articulation: float = math.nan

    @property
    def lane_ref(self) -> LaneRef | None:
        """The lane it is in, or None off the roads."""
        return LaneRef(self.road, self.section, self.lane_id) if self.road is not None else None


def actor_state(
    name: str,
    kind: str,
    tick: int,
    time: float,
    x: float,
    y: float,
    yaw: float,
    speed: float,
    lateral_speed: float,
    yaw_rate: float,
    accel: float,
    friction: float,
    throttle: float,
    brake: float,
    steer: float,
    length: float,
    width: float,
    where: RoadPosition,
    distance: float,
    articulation: float = math.nan,
) -> ActorState:
    """The state of an actor from its body's read-out and ``where`` it is on the map
    (its road coordinates; ``lane`` only inside a driving lane)."""
    return ActorState(
        name,
        kind,
        tick,
        time,
        x,
        y,
        yaw,
        speed,
        lateral_speed,
        yaw_rate,
        accel,
        where.number if where.inside else None,
        where.s,
        where.t,
        friction,
        throttle,
        brake,
        steer,
        length,
        width,
        where.road,
        where.section,
        where.lane,
        where.offset,
        where.direction,
        where.drivable,
        distance,
        articulation,
    )
