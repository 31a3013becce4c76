"""What an export reads of a finished run: one plain record, built once from the run.

:func:`run_recording` gathers from a prepared run and its result what every
export format needs — the map, every actor's category, box and axles, its
pose at every control tick, the traffic lights' states, the environment
changes and the emitted events — so the writers (:mod:`.xosc`, :mod:`.osi`)
read one typed value and never the runner's live objects.

**Reference points.** Telemetry gives each actor's bounding-box centre. An
OpenSCENARIO vehicle's reference point is the centre of its rear axle (the
standard's vehicle coordinate system); :attr:`ActorTrack.rear_axle` is how far
that axle lies ahead of the box centre (negative: behind it), and
:meth:`ActorTrack.reference_xy` moves the centre there. Persons, animals and
obstacles keep the box centre as their reference point.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from osc2check.world.builtin import BuiltinMap, builtin_map
from osc2check.world.errors import UnknownMapError
from osc2check.world.network import RoadNetwork
from osc2runner.execution.context import EnvironmentChange
from osc2runner.sim.trailer import TrailerParams
from osc2runner.sim.vehicle import PedestrianParams, VehicleParams

if TYPE_CHECKING:
    from osc2runner.runner import Prepared, RunResult

__all__ = [
    "ActorTrack",
    "Axle",
    "EmittedEvent",
    "LightTrack",
    "RunRecording",
    "run_recording",
]


@dataclass(frozen=True, slots=True)
class Axle:
    """An axle: its position ahead of the reference point (m), the road wheels'
    diameter, the track width and the largest steering angle (rad)."""

    x: float
    wheel_diameter: float
    track_width: float
    max_steer: float


@dataclass(frozen=True)
class ActorTrack:
    """One actor and where it was at every recorded tick.

    ``kind`` is the world's (``vehicle``, ``trailer``, ``pedestrian``, ``obstacle``),
    ``category`` the catalogue's (``car``, ``truck``, ``vru_vehicle``, ``person``, ...),
    ``model`` the catalogue row's key. ``x``, ``y`` are the box centre, ``yaw`` the
    heading as recorded (rad), ``speed`` the signed speed along it (m/s).
    """

    name: str
    kind: str
    category: str
    model: str
    length: float
    width: float
    height: float
    mass: float
    max_speed: float
    x: np.ndarray
    y: np.ndarray
    yaw: np.ndarray
    speed: np.ndarray
    rear_axle: float = 0.0  # the reference point's place ahead of the box centre (m)
    axles: tuple[Axle, ...] = ()  # front first; x from the reference point
    max_acceleration: float = 0.0
    max_deceleration: float = 0.0
    towed_by: str | None = None

    @property
    def moves(self) -> bool:
        """Whether it is an actor that can move (obstacles never do)."""
        return self.kind != "obstacle"

    def reference_xy(self) -> tuple[np.ndarray, np.ndarray]:
        """The reference point at every tick (the rear axle's centre for vehicles)."""
        return (
            self.x + self.rear_axle * np.cos(self.yaw),
            self.y + self.rear_axle * np.sin(self.yaw),
        )


@dataclass(frozen=True)
class LightTrack:
    """A traffic light: its name, the map signal it is (``signal``, the ``map_id``;
    empty for a light placed by its pose), its pose and every change of its bulbs:
    ``(tick, time, semantic state, ((colour, icon, state), ...))``."""

    name: str
    signal: str
    x: float
    y: float
    yaw: float
    changes: tuple[tuple[int, float, str, tuple[tuple[str, str, str], ...]], ...]


@dataclass(frozen=True, slots=True)
class EmittedEvent:
    """An ``emit`` of the scenario: the event's name, tick and time."""

    name: str
    tick: int
    time: float


@dataclass(frozen=True)
class RunRecording:
    """A finished run as the exports see it (see the module docstring).

    ``ticks`` and ``times`` are the recorded ticks, shared by every actor;
    ``map_file`` is the OpenDRIVE file the run used (None on a built-in map, which
    ``builtin`` then names); ``host`` is the actor an OSI trace calls the host
    vehicle (the system under test's, else the field named ``sut`` or ``ego``,
    else the first vehicle; None without vehicles).
    """

    scenario: str
    source: str
    seed: int
    dt: float
    ticks: np.ndarray
    times: np.ndarray
    network: RoadNetwork
    map_name: str
    map_file: Path | None
    builtin: BuiltinMap | None
    actors: tuple[ActorTrack, ...]
    lights: tuple[LightTrack, ...]
    environment: tuple[EnvironmentChange, ...]
    events: tuple[EmittedEvent, ...]
    outcome: str
    end_time: float
    host: str | None = None


def _axles(p: VehicleParams | TrailerParams) -> tuple[float, tuple[Axle, ...]]:
    """The rear (only) axle's place ahead of the box centre, and the axles from it."""
    diameter = 2.0 * p.wheel_radius
    if isinstance(p, TrailerParams):
        return p.axle, (Axle(0.0, diameter, p.track, 0.0),)
    front = 0.5 * p.length - p.front_overhang
    wheelbase = p.lf + p.lr
    rear = front - wheelbase
    return rear, (
        Axle(wheelbase, diameter, p.track, p.max_steer),
        Axle(0.0, diameter, p.track, 0.0),
    )


def _track(prepared: Prepared, result: RunResult, name: str) -> ActorTrack:
    world = prepared.world
    spec = world.specs[world.names.index(name)]
    p = spec.params
    actor = prepared.ctx.actors.get(name)
    row = actor.row if actor is not None else None
    channels = result.telemetry[name]
    category = row.category if row is not None else p.category
    model = row.key if row is not None else p.model
    rear, axles = 0.0, tuple[Axle, ...]()
    mass, max_speed = 0.0, 0.0  # an obstacle's
    if isinstance(p, (VehicleParams, TrailerParams)):
        rear, axles = _axles(p)
        mass, max_speed = float(p.mass), float(p.max_speed)
    elif isinstance(p, PedestrianParams):
        mass = float(row.mass) if row is not None else 75.0
        max_speed = float(p.max_speed)
    return ActorTrack(
        name=name,
        kind=spec.kind,
        category=category,
        model=model,
        length=float(p.length),
        width=float(p.width),
        height=float(p.height),
        mass=mass if mass > 0 else (float(row.mass) if row is not None else 0.0),
        max_speed=max_speed,
        x=np.asarray(channels["x"], dtype=float),
        y=np.asarray(channels["y"], dtype=float),
        yaw=np.asarray(channels["yaw"], dtype=float),
        speed=np.asarray(channels["speed"], dtype=float),
        rear_axle=rear,
        axles=axles,
        max_acceleration=float(row.max_acceleration) if row is not None else 0.0,
        max_deceleration=float(row.max_deceleration) if row is not None else 0.0,
        towed_by=spec.towed_by,
    )


def _builtin(name: str, network: RoadNetwork) -> BuiltinMap | None:
    if network.source is not None:
        return None
    try:
        return builtin_map(name)
    except UnknownMapError:
        return None


def _host(actors: tuple[ActorTrack, ...], sut: dict[str, str] | None) -> str | None:
    if sut is not None:
        return sut["actor"]
    vehicles = [a.name for a in actors if a.kind == "vehicle"]
    named = [n for n in ("sut", "ego") if n in vehicles]
    return named[0] if named else (vehicles[0] if vehicles else None)


def run_recording(prepared: Prepared, result: RunResult) -> RunRecording:
    """The record of a finished run that the exports read (see the module docstring)."""
    world, ctx = prepared.world, prepared.ctx
    network = world.network
    names = [n for n in world.names if n in result.telemetry]
    actors = tuple(_track(prepared, result, n) for n in names)
    first = result.telemetry[names[0]] if names else None
    ticks = np.asarray(first["tick"], dtype=np.int64) if first is not None else np.zeros(0, int)
    times = np.asarray(first["time"], dtype=float) if first is not None else np.zeros(0)
    dt = world.dt_control
    lights = tuple(
        LightTrack(
            light.name,
            str(getattr(light.value, "map_id", "") or "") if light.placed == "signal" else "",
            float(light.x),
            float(light.y),
            float(light.yaw),
            tuple((h.tick, h.tick * dt, h.semantic, h.bulbs) for h in light.history),
        )
        for light in ctx.traffic_lights.values()
    )
    events = tuple(EmittedEvent(r.name, r.tick, r.time) for r in result.events if r.kind == "emit")
    map_name = prepared.instance.witness.map or network.name
    source = Path(network.source) if network.source else None
    return RunRecording(
        scenario=prepared.scenario.name,
        source=prepared.uri,
        seed=ctx.seed,
        dt=dt,
        ticks=ticks,
        times=times,
        network=network,
        map_name=map_name,
        map_file=source,
        builtin=_builtin(map_name, network) if source is None else None,
        actors=actors,
        lights=lights,
        environment=tuple(ctx.environment_changes),
        events=events,
        outcome=result.outcome.status,
        end_time=float(times[-1]) if len(times) else 0.0,
        host=_host(actors, prepared.sut),
    )
