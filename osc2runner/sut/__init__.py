"""The system under test (SUT): a Python controller that drives one actor of a scenario.

A scenario marks one vehicle as the system under test: the field named ``sut``
or ``ego`` (or the one ``--sut-actor NAME`` names). With ``--sut module:Class``
(or ``sut = "module:Class"`` under ``[tool.osc2run]`` in ``pyproject.toml``)
that actor's controller is replaced by an instance of ``Class``; the scenario's
behaviour for the actor does not drive it any more, it becomes its **intent**:
the set speed and the lateral path (lane, offset) the scenario asks for, and
what the runner's own driver model would do to follow them this tick
(``Observation.driver``), which a driver-assistance function can pass through
and override (an AEB brakes, an ACC sets the pedals, both leave the steering to
the driver).

Each control tick (20 Hz by default) the runner calls ``step(observation)`` with

* ``ego``: the SUT actor's own state (:class:`ActorView`, world frame);
* ``others``: every other actor's state, world frame and seen from the SUT
  (``rel_x`` forward, ``rel_y`` left, relative velocities, bumper gaps);
* ``road``: the road around it (:class:`RoadAhead`: where the actor is, the
  lane's width and speed limit, the intended path ahead, its curvature);
* ``intent``: the scenario's set speed and lateral target (:class:`Intent`);
* ``driver``: the runner's driver model's :class:`Command` for the intent,

and applies what it returns: a :class:`Command` (throttle, brake, steer in
[0, 1], [0, 1], [-1, 1]) or a :class:`Demand` (target acceleration in m/s² and
path curvature in 1/m, turned into pedals by the vehicle's inverse model and
into a steering angle by the bicycle model). The vehicle's actuator layer
(pedal and steering rate limits, ABS, traction control) applies to both.

A fresh instance is made for every run and ``reset(info)`` is called before the
first tick (:class:`SutInfo`: the actor, its vehicle's size and limits, the
control period, the run's seed), so runs do not share state and the same seed
gives the same run. The controller must not read the wall clock or draw
unseeded random numbers if runs are to replay exactly.

docs/campaigns.md has a complete example; ``examples/controllers/`` ships an
AEB (time-to-collision braking) and an ACC.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

__all__ = [
    "ActorView",
    "Command",
    "Demand",
    "Intent",
    "Observation",
    "RoadAhead",
    "SutInfo",
    "SystemUnderTest",
]


@dataclass(frozen=True, slots=True)
class ActorView:
    """An actor as the SUT sees it at one tick (SI units).

    World frame: ``x``, ``y`` (bounding-box centre), ``yaw`` (rad), ``speed``
    (signed, along the heading), ``accel``, ``vx``, ``vy`` (world velocity).
    Road frame: ``lane`` (1 = rightmost lane in the driving direction, None off
    the road), ``s`` along the road, ``t`` to the left of the road's reference
    line. Seen from the SUT (its centre and heading; zero for the SUT itself):
    ``rel_x`` forward, ``rel_y`` to the left, ``rel_vx``, ``rel_vy`` the relative
    velocity (the other's minus the SUT's, in the SUT's axes: ``rel_vx < 0`` is
    closing in on an actor ahead), ``gap`` the bumper-to-bumper distance along
    the SUT's heading (``rel_x`` less both half lengths; negative when the boxes
    overlap lengthwise) and ``lateral_gap`` the side-to-side distance (``|rel_y|``
    less both half widths; negative when they overlap sideways, that is when the
    other is in the SUT's path).
    """

    name: str
    kind: str
    x: float
    y: float
    yaw: float
    speed: float
    accel: float
    vx: float
    vy: float
    length: float
    width: float
    lane: int | None
    s: float
    t: float
    rel_x: float = 0.0
    rel_y: float = 0.0
    rel_vx: float = 0.0
    rel_vy: float = 0.0
    gap: float = 0.0
    lateral_gap: float = 0.0

    @property
    def in_path(self) -> bool:
        """Whether the actor is ahead of the SUT and overlaps its width."""
        return self.rel_x > 0.0 and self.lateral_gap < 0.0

    @property
    def time_to_collision(self) -> float:
        """``gap / closing speed`` for an actor in the SUT's path that it is closing in
        on; infinity otherwise (and 0 once the boxes touch)."""
        if not self.in_path or self.rel_vx >= 0.0:
            return float("inf")
        return max(self.gap, 0.0) / -self.rel_vx


@dataclass(frozen=True, slots=True)
class RoadAhead:
    """The road around the SUT, on the lanes its driver model follows.

    ``road`` (the road's id, None off every road), ``lane`` (1 = rightmost lane in
    the driving direction), ``s`` and ``t`` of the SUT on that road; ``lane_width``
    there (m; NaN off the roads); ``speed_limit`` (m/s, None when the map has none);
    ``heading`` and ``curvature`` (1/m, positive turns left) of the followed centre
    line where the SUT is; ``path``: the intended path ahead as world points
    ``(x, y)`` every 5 m over 50 m (the lane centre line the scenario asks for, moved
    by its lateral offset, through a lane change in progress); ``distance_to_end``:
    how far that path goes on before the road ends (m; it is planned 1.5 km ahead).
    """

    road: str | None
    lane: int | None
    s: float
    t: float
    lane_width: float
    speed_limit: float | None
    heading: float
    curvature: float
    path: tuple[tuple[float, float], ...]
    distance_to_end: float


@dataclass(frozen=True, slots=True)
class Intent:
    """What the scenario asks of the SUT actor now: ``speed`` (m/s; None when no
    behaviour has set one) and ``offset``: where its lateral path ends, in m left of
    the centre line it follows (0: the lane centre; None without a lateral target);
    ``changing_lane`` while a lane change or lateral move is under way."""

    speed: float | None
    offset: float | None
    changing_lane: bool


@dataclass(frozen=True, slots=True)
class Command:
    """Driver inputs: ``throttle`` and ``brake`` in [0, 1], ``steer`` in [-1, 1]
    (+1 full left). Values outside are clipped."""

    throttle: float = 0.0
    brake: float = 0.0
    steer: float = 0.0


@dataclass(frozen=True, slots=True)
class Demand:
    """A motion demand: ``acceleration`` along the heading (m/s², negative brakes)
    and ``curvature`` of the path (1/m, positive turns left; None keeps the
    driver model's steering)."""

    acceleration: float
    curvature: float | None = None


@dataclass(frozen=True, slots=True)
class SutInfo:
    """What a SUT is told before a run: the ``actor`` it drives, its vehicle
    (``length``, ``width``, ``wheelbase``, ``mass``, ``max_steer`` road-wheel angle
    in rad, ``max_accel`` and ``max_decel`` in m/s², ``max_speed`` in m/s), the
    control period ``dt`` (s), the run's ``seed`` and the ``scenario``'s name."""

    actor: str
    length: float
    width: float
    wheelbase: float
    mass: float
    max_steer: float
    max_accel: float
    max_decel: float
    max_speed: float
    dt: float
    seed: int
    scenario: str


@dataclass(frozen=True, slots=True)
class Observation:
    """What the SUT receives each tick (see the module docstring)."""

    tick: int
    time: float
    ego: ActorView
    others: tuple[ActorView, ...]
    road: RoadAhead
    intent: Intent
    driver: Command

    def ahead(self) -> ActorView | None:
        """The nearest actor in the SUT's path ahead (smallest gap), or None."""
        found = [o for o in self.others if o.in_path]
        return min(found, key=lambda o: o.gap) if found else None


@runtime_checkable
class SystemUnderTest(Protocol):
    """The interface of a SUT class: made with no arguments, ``reset`` before each run,
    ``step`` every tick."""

    def reset(self, info: SutInfo) -> None: ...

    def step(self, observation: Observation) -> Command | Demand: ...
