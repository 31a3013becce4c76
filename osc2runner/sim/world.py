"""The simulated world: one MuJoCo model of a road network and its actors.

A :class:`World` is built from a road network (a built-in map or an OpenDRIVE
file: :class:`~osc2check.world.network.RoadNetwork`) and a list of
:class:`ActorSpec` (sedans, HGVs, pedestrians, obstacles with their initial
pose and speed). It advances in fixed control steps (50 ms by default), each
made of a whole number of physics steps (2 ms by default):

1. the inputs of this tick go through the actuator layer (rate limits, ABS,
   TCS, Ackermann) and are written into the model; trailers brake with their
   tow vehicles (``sim/trailer_bank.py``);
2. pedestrians move along their commanded velocity (kinematic);
3. ``mj_step`` runs the physics sub-steps;
4. the state of every actor is read out, with its road coordinates (road,
   lane, ``s``, ``t``: :class:`~osc2check.world.tracking.RoadLocator`, which
   prefers the path the actor's driver follows), and collision and road-departure
   events are detected. A vehicle leaves the road when its reference point is on
   no driving lane of any road (a shoulder, a sidewalk, off the map); a
   pedestrian when it is on no lane of any type.

Nothing here reads the wall clock or draws random numbers: the same
construction and the same inputs give bit-identical states (within one MuJoCo
version and platform; see :func:`osc2runner.sim.versions`).

The physics can diverge (a force too large for the time step): MuJoCo then
finds NaN, infinite or huge values, warns and resets its state to the initial
one. :meth:`World.diverged` reports that, or a non-finite read-out, after a
step, naming the actor, so that the runner ends the run as an error instead of
carrying on from a teleported or NaN state.

Trailers are bodies of their own, hitched to a tow vehicle by a ball joint
(:meth:`World.connect`, :meth:`World.disconnect`); a hitched pair is not a
collision.

The world orchestrates; each body kind is a bank that owns its model indices,
inputs and read-out (``vehicle_bank.py``, ``trailer_bank.py``, ``walker_bank.py``,
``obstacle_bank.py``; ``kinematic_bank.py`` for the vehicles a run moves by the
kinematic model, which have no body in the MuJoCo model); the model's MJCF is
assembled in ``assembly.py``, road positions kept in ``locating.py``, MuJoCo's
divergence warnings in ``divergence.py``, and the specs, inputs and states are in
``state.py``.

Friction is a property of the tires (they override the road's geom friction
by priority): :meth:`World.set_road_friction` writes every tire,
:meth:`World.set_wheel_friction` one vehicle or one wheel. Weather is recorded;
rain sets a default friction unless friction was set explicitly.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace

import mujoco
import numpy as np

from osc2check.world.network import RoadNetwork
from osc2check.world.paths import LanePath
from osc2check.world.tracking import RoadPosition
from osc2runner.sim.assembly import model_xml, prefix
from osc2runner.sim.divergence import DivergenceWatch
from osc2runner.sim.events import Event, EventDetector
from osc2runner.sim.kinematic_bank import KinematicBank
from osc2runner.sim.locating import ActorLocators
from osc2runner.sim.obstacle_bank import ObstacleBank
from osc2runner.sim.state import (
    ActorParams,
    ActorSpec,
    ActorState,
    PedestrianInput,
    VehicleInput,
    Weather,
    weather_friction,
)
from osc2runner.sim.trailer import TrailerParams, articulation
from osc2runner.sim.trailer_bank import TrailerBank
from osc2runner.sim.vehicle import WHEELS, VehicleParams
from osc2runner.sim.vehicle_bank import VehicleBank, four
from osc2runner.sim.walker_bank import WalkerBank

__all__ = [
    "ActorSpec",
    "ActorState",
    "Event",
    "PedestrianInput",
    "VehicleInput",
    "Weather",
    "World",
    "weather_friction",
]


class World:
    """A road network with its actors in one MuJoCo model, stepped at a fixed control rate.

    Parameters:
        network: the map the actors are placed on.
        actors: the actors, each with a unique name.
        dt_control: control period in seconds (inputs are held over it).
        dt_physics: physics step in seconds; ``dt_control`` must be a whole
            multiple of it.
        friction: initial road friction; None means "from the weather".
        weather: initial weather (recorded; rain sets the default friction).
        physical_collisions: give chassis and obstacles physical contacts.
            Off by default: collisions are then events only and bodies pass
            through each other, which is what a scenario verdict needs.
        settle_time: seconds of physics run at rest before the start, so that
            suspensions start in equilibrium. Not counted in ``time``.
    """

    def __init__(
        self,
        network: RoadNetwork,
        actors: Sequence[ActorSpec],
        *,
        dt_control: float = 0.05,
        dt_physics: float = 0.002,
        friction: float | None = None,
        weather: Weather | None = None,
        physical_collisions: bool = False,
        settle_time: float = 1.0,
    ) -> None:
        substeps = round(dt_control / dt_physics)
        if substeps < 1 or abs(substeps * dt_physics - dt_control) > 1e-9 * dt_control:
            raise ValueError(
                f"dt_control ({dt_control}) must be a whole multiple of dt_physics ({dt_physics})"
            )
        names = [a.name for a in actors]
        if len(set(names)) != len(names):
            raise ValueError(f"actor names must be unique: {names}")
        self.network = network
        self.specs: tuple[ActorSpec, ...] = tuple(actors)
        self.dt_control = float(dt_control)
        self.dt_physics = float(dt_physics)
        self.substeps = substeps
        self.physical_collisions = physical_collisions
        self.settle_time = float(settle_time)
        self._initial_friction = friction
        self._initial_weather = weather or Weather()
        self._names = tuple(names)
        self._kinds = tuple(a.kind for a in self.specs)
        self._index = {name: i for i, name in enumerate(names)}
        # each actor's initial world (x, y, yaw): its spec's pose on the map, found once
        self._initial = [a.pose(network) for a in self.specs]
        self._check_hitches()

        def of(kind: str) -> list[int]:
            return [i for i, k in enumerate(self._kinds) if k == kind]

        driven, trailers, walkers, obstacles = (
            of(k) for k in ("vehicle", "trailer", "pedestrian", "obstacle")
        )
        vehicles = [i for i in driven if not self.specs[i].kinematic]
        kinematic = [i for i in driven if self.specs[i].kinematic]
        if kinematic and physical_collisions:
            raise ValueError("kinematic vehicles have no body for physical collisions")
        # every (tow vehicle, trailer) pair that may hitch, by world index
        pairs = [(v, t) for t in trailers for v in vehicles if self.can_tow(names[v])]
        body_poses = list(self._initial)
        for t in trailers:  # a trailer that starts towed starts on its hitch
            tow = self.specs[t].towed_by
            if tow is not None:
                body_poses[t] = self._hitch_pose(names[t], tow, initial=True)
        self.xml = model_xml(
            self.specs,
            body_poses,
            [(v, t, self.specs[t].towed_by == names[v]) for v, t in pairs],
            network.bounds(),
            self.dt_physics,
            physical_collisions,
        )
        self.model = m = mujoco.MjModel.from_xml_string(self.xml)
        self.data = d = mujoco.MjData(self.model)

        def bank_args(rows: list[int]) -> tuple[list[ActorSpec], list[str], list[int]]:
            return [self.specs[i] for i in rows], [prefix(i) for i in rows], rows

        self.vehicles = VehicleBank(m, d, *bank_args(vehicles), self.dt_control)
        self.kinematic = KinematicBank([self.specs[i] for i in kinematic], kinematic, dt_control)
        self.trailers = TrailerBank(m, d, *bank_args(trailers), self.dt_control)
        self.walkers = WalkerBank(m, d, *bank_args(walkers), self.dt_control)
        self.obstacles = ObstacleBank(
            [self.specs[i] for i in obstacles], [self._initial[i] for i in obstacles], obstacles
        )
        self._hitch_eq = {
            (names[v], names[t]): mujoco.mj_name2id(
                m, mujoco.mjtObj.mjOBJ_EQUALITY, f"{prefix(v)}_tows_{prefix(t)}"
            )
            for v, t in pairs
        }
        is_static = np.array([k == "obstacle" for k in self._kinds])
        self._events = EventDetector(
            self._names,
            np.array([(0.5 * a.params.length, 0.5 * a.params.width) for a in self.specs]),
            is_static,
            margin=0.1 if physical_collisions else 0.0,
        )
        self._locators = ActorLocators(network, self._initial)
        n = len(self.specs)
        self._moving_rows = [i for i in range(n) if not is_static[i]]
        # per moving row: a walker (off the map when outside every road, not off drivable lanes)
        self._moving_walker = tuple(self._kinds[i] == "pedestrian" for i in self._moving_rows)
        self._centre = np.zeros((n, 2))
        self._yaw_all = np.zeros(n)
        self._divergence = DivergenceWatch(m, d, [(a, prefix(i)) for i, a in enumerate(names)])
        self.reset()

    def _check_hitches(self) -> None:
        towing: set[str] = set()
        for spec in self.specs:
            tow = spec.towed_by
            if spec.kind != "trailer" or tow is None:
                continue
            if not self.can_tow(tow):
                raise ValueError(f"`{spec.name}` is towed by `{tow}`, which {self._no_hitch(tow)}")
            if tow in towing:
                raise ValueError(f"`{tow}` tows two trailers")
            towing.add(tow)

    def can_tow(self, name: str) -> bool:
        """Whether actor ``name`` is a vehicle with a hitch receiver (and a body: a
        kinematic vehicle tows nothing)."""
        i = self._index.get(name)
        spec = self.specs[i] if i is not None else None
        return (
            spec is not None
            and isinstance(spec.params, VehicleParams)
            and spec.params.can_tow
            and not spec.kinematic
        )

    def _no_hitch(self, name: str) -> str:
        """Why vehicle ``name`` cannot tow (:meth:`can_tow` is false)."""
        i = self._index.get(name)
        if i is not None and self.specs[i].kinematic:
            return "is a kinematic vehicle (only the multibody model tows)"
        return "has no hitch receiver"

    def model_of(self, name: str) -> str:
        """What moves actor ``name``: ``kinematic`` for a kinematic vehicle, else
        ``multibody`` for a vehicle or a trailer, ``kinematic`` for a pedestrian (moved
        along its commanded velocity), ``static`` for an obstacle."""
        i = self._index[name]
        kind = self._kinds[i]
        if kind in ("vehicle", "trailer"):
            return "kinematic" if self.specs[i].kinematic else "multibody"
        return "kinematic" if kind == "pedestrian" else "static"

    def _driven(self, name: str) -> tuple[VehicleBank | KinematicBank, int]:
        """The bank of vehicle ``name`` (multibody or kinematic) and its row there."""
        bank: VehicleBank | KinematicBank = self.vehicles
        row = bank.rows.get(name)
        if row is None:
            bank = self.kinematic
            row = bank.rows[name]
        return bank, row

    # ------------------------------------------------------------------ reset

    def reset(self) -> None:
        """Back to the initial state: settle the suspensions, then place every actor."""
        m, d = self.model, self.data
        mujoco.mj_resetData(m, d)
        self.vehicles.reset()
        self.kinematic.reset()
        self.tick = 0
        self.events: list[Event] = []
        self._events.reset()
        self.weather = self._initial_weather
        self.friction_explicit = self._initial_friction is not None
        if self._initial_friction is not None:
            self._apply_road_friction(self._initial_friction)
        else:
            self._apply_road_friction(weather_friction(self.weather))
        self.trailers.reset()
        self.hitched: dict[str, str] = {}  # trailer -> its tow vehicle
        for spec in self.trailers.specs:
            if spec.towed_by is not None:
                self._hitch(spec.towed_by, spec.name)
        # settle at rest with the brakes on and the steering centred
        if (self.vehicles.count or self.trailers.count) and self.settle_time > 0.0:
            self.vehicles.hold_still()
            self.trailers.hold_still()
            d.ctrl[:] = 0.0
            mujoco.mj_step(m, d, nstep=max(1, round(self.settle_time / self.dt_physics)))
            d.qvel[:] = 0.0
            d.time = 0.0
            d.qacc_warmstart[:] = 0.0
        mujoco.mj_forward(m, d)
        self.walkers.reset()
        self._moving_now = list(self._moving_rows)  # the moving rows, still walkers left out
        self._locators.forget()
        self.vehicles.read()
        self.trailers.read()
        for spec, (x, y, yaw) in zip(self.specs, self._initial, strict=True):
            if spec.kind != "obstacle" and spec.name not in self.hitched:
                # obstacles stay where the model put them; hitched trailers come with their tow
                self.place(spec.name, x, y, yaw, spec.speed)
        mujoco.mj_forward(m, d)
        self.vehicles.read()
        self.trailers.read()
        self._locate()
        self._divergence.reset()

    def place(self, name: str, x: float, y: float, yaw: float, speed: float = 0.0) -> None:
        """Move an actor to ``(x, y)`` with heading ``yaw`` and ``speed`` along it.

        For vehicles the suspension state and the chassis pitch/roll are kept;
        the wheels get the matching spin. Call before the first tick (the
        scenario initializer does); mid-run it is a teleport.
        """
        i = self._index[name]
        kind = self._kinds[i]
        self._locators.forget(i)
        if kind == "vehicle":
            bank, row = self._driven(name)
            bank.place(row, x, y, yaw, speed)
            trailer = self.towing(name)
            if trailer is not None:  # the trailer comes along, on the hitch
                self._place_trailer(trailer, *self._hitch_pose(trailer, name), speed)
        elif kind == "trailer":
            self._place_trailer(name, x, y, yaw, speed)
        elif kind == "pedestrian":
            row = self.walkers.rows[name]
            self._walker_changed(row, self.walkers.place(row, x, y, yaw, speed))
        else:
            raise ValueError(f"obstacle `{name}` is static and cannot be placed after start")
        self._locate()

    def _place_trailer(self, name: str, x: float, y: float, yaw: float, speed: float) -> None:
        self._locators.forget(self._index[name])
        self.trailers.place(self.trailers.rows[name], x, y, yaw, speed)

    # ------------------------------------------------------------------ hitches

    def _hitch_pose(
        self, trailer: str, tow: str, initial: bool = False
    ) -> tuple[float, float, float]:
        """Where ``trailer`` stands on ``tow``'s hitch, aligned with it: its world
        ``(x, y, yaw)`` from the tow vehicle's current pose (``initial``: its spec's)."""
        tp, vp = self.params(trailer), self.params(tow)
        assert isinstance(tp, TrailerParams) and isinstance(vp, VehicleParams)
        assert vp.receiver_x is not None
        if initial:
            x, y, yaw = self._initial[self._index[tow]]
        else:
            bank, row = self.vehicles, self.vehicles.rows[tow]
            x, y, yaw = float(bank.pos[row, 0]), float(bank.pos[row, 1]), float(bank.yaw[row])
        back = -vp.receiver_x + tp.coupler  # tow centre to trailer centre, along the heading
        return (x - back * math.cos(yaw), y - back * math.sin(yaw), yaw)

    def _hitch(self, tow: str, trailer: str, on: bool = True) -> None:
        if on:
            self.hitched[trailer] = tow
        else:
            del self.hitched[trailer]
        self.trailers.tow_row[self.trailers.rows[trailer]] = self.vehicles.rows[tow] if on else None
        self.data.eq_active[self._hitch_eq[(tow, trailer)]] = int(on)
        self._events.ignore(self._index[tow], self._index[trailer], on)

    def towing(self, name: str) -> str | None:
        """The trailer vehicle ``name`` tows, or None."""
        return next((t for t, tow in self.hitched.items() if tow == name), None)

    def connect(self, tow: str, trailer: str) -> float:
        """Hitch ``trailer`` to ``tow``'s receiver; returns how far the trailer was moved (m).

        A trailer whose coupler is not on the receiver (within 5 cm, its heading within
        0.01 rad of the tow vehicle's) is first put there, aligned, at the tow vehicle's
        speed. Raises ValueError when the pair cannot be hitched.
        """
        if not self.can_tow(tow):
            raise ValueError(f"`{tow}` {self._no_hitch(tow)}")
        if self.kind(trailer) != "trailer":
            raise ValueError(f"`{trailer}` is not a trailer")
        if trailer in self.hitched:
            raise ValueError(f"`{trailer}` is already towed by `{self.hitched[trailer]}`")
        if self.towing(tow) is not None:
            raise ValueError(f"`{tow}` already tows `{self.towing(tow)}`")
        x, y, yaw = self._hitch_pose(trailer, tow)
        row = self.trailers.rows[trailer]
        here = self.trailers.pos[row].tolist()
        moved = math.hypot(x - here[0], y - here[1])
        turned = abs(articulation(yaw, float(self.trailers.yaw[row])))
        if moved > 0.05 or turned > 0.01:
            speed = float(self.vehicles.speed[self.vehicles.rows[tow]])
            self._place_trailer(trailer, x, y, yaw, speed)
        else:
            moved = 0.0
        self._hitch(tow, trailer)
        mujoco.mj_forward(self.model, self.data)
        self._locate()
        return moved

    def disconnect(self, tow: str) -> str:
        """Unhitch the trailer ``tow`` tows; returns its name. Raises ValueError when it
        tows none. The trailer stays where it is, its brakes applied when it has any."""
        trailer = self.towing(tow)
        if trailer is None:
            raise ValueError(f"`{tow}` tows no trailer")
        self._hitch(tow, trailer, on=False)
        return trailer

    def articulation(self, trailer: str) -> float:
        """A hitched trailer's articulation angle (rad; NaN when it is not hitched)."""
        return self.trailers.articulation(self.trailers.rows[trailer], self.vehicles.yaw)

    # ------------------------------------------------------------------ time

    @property
    def time(self) -> float:
        """Simulated time in seconds since the start (ticks times the control period)."""
        return self.tick * self.dt_control

    @property
    def names(self) -> tuple[str, ...]:
        """Actor names in creation order."""
        return self._names

    def kind(self, name: str) -> str:
        """``vehicle``, ``trailer``, ``pedestrian`` or ``obstacle``."""
        return self._kinds[self._index[name]]

    def params(self, name: str) -> ActorParams:
        """The parameters an actor was built from."""
        return self.specs[self._index[name]].params

    # ------------------------------------------------------------------ stepping

    def set_input(self, name: str, value: VehicleInput | PedestrianInput) -> None:
        """Set the input an actor holds from the next control step on."""
        if name not in self._index:
            raise KeyError(f"no actor named `{name}`; actors: {', '.join(self._names)}")
        kind = self._kinds[self._index[name]]
        if kind == "vehicle" and isinstance(value, VehicleInput):
            bank, row = self._driven(name)
            bank.set_input(row, value.throttle, value.brake, value.steer)
        elif kind == "pedestrian" and isinstance(value, PedestrianInput):
            row = self.walkers.rows[name]
            self._walker_changed(row, self.walkers.set_input(row, value))
        else:
            raise TypeError(f"{type(value).__name__} is not an input for {kind} `{name}`")

    def _walker_changed(self, row: int, changed: bool) -> None:
        """Walker ``row`` started or stopped moving (``changed``): only the moving ones are
        located and checked for events (a walker that stands still costs nothing per tick)."""
        if changed:
            walkers = self.walkers
            self._events.hold(int(walkers.index[row]), walkers.still[row])
            still = walkers.still_index()
            self._moving_now = [i for i in self._moving_rows if i not in still]

    def step_control(
        self, inputs: Mapping[str, VehicleInput | PedestrianInput] | None = None
    ) -> list[Event]:
        """Advance one control step; actors not in ``inputs`` keep their last input.

        Returns the events detected at the end of the step.
        """
        if inputs:
            for name, value in inputs.items():
                self.set_input(name, value)
        vehicles, trailers, walkers = self.vehicles, self.trailers, self.walkers
        if vehicles.count:
            vehicles.apply()
        if trailers.count:
            trailers.apply(vehicles.actuators.brake)
        walkers.move()
        self.kinematic.step()
        if self.model.nv:
            mujoco.mj_step(self.model, self.data, nstep=self.substeps)
        else:  # nothing for the physics to move (kinematic vehicles, walkers, obstacles)
            self.data.time += self.dt_control
        self.tick += 1
        vehicles.read_step()
        if trailers.count:
            trailers.read_step()
        walkers.read_step()
        centre, yaw = self._poses()
        self._locate(centre, yaw)
        positions = self._locators.positions
        off = [
            not (positions[i].inside if walker else positions[i].drivable)
            for i, walker in zip(self._moving_rows, self._moving_walker, strict=True)
        ]
        events = self._events.detect(self.tick, self.time, centre, yaw, off)
        self.events.extend(events)
        return events

    def _locate(self, centre: np.ndarray | None = None, yaw: np.ndarray | None = None) -> None:
        """The road coordinates of every moving actor, from their new poses (a step's
        ``centre`` and ``yaw`` given: of those that may have moved, not the walkers that
        stand still)."""
        rows = self._moving_rows
        if centre is None or yaw is None:
            centre, yaw = self._poses()
        elif self.walkers.moving < self.walkers.count:
            rows = self._moving_now
        self._locators.locate(rows, centre, yaw)

    def follow(self, name: str, path: LanePath | None) -> None:
        """Tell the world the lanes actor ``name`` drives (its driver's path): where roads
        overlap, its road coordinates are taken on them."""
        self._locators.follow(self._index[name], path)

    def position(self, name: str) -> RoadPosition:
        """Where actor ``name`` is on the map now."""
        return self._locators.positions[self._index[name]]

    def run(self, seconds: float, inputs: Mapping[str, VehicleInput | PedestrianInput]) -> None:
        """Hold ``inputs`` for ``seconds`` (rounded to whole control steps)."""
        for _ in range(round(seconds / self.dt_control)):
            self.step_control(inputs)

    # ------------------------------------------------------------------ read-out

    def _poses(self) -> tuple[np.ndarray, np.ndarray]:
        """Centre (n, 2) and yaw (n,) of every actor's bounding box."""
        centre, yaw = self._centre, self._yaw_all
        for bank in (self.vehicles, self.kinematic, self.trailers):
            if bank.count:
                centre[bank.index] = bank.pos
                yaw[bank.index] = bank.yaw
        self.walkers.poses(centre, yaw)
        self.obstacles.poses(centre, yaw)
        return centre, yaw

    def state(self, name: str) -> ActorState:
        """The state of actor ``name`` at the current tick."""
        i = self._index[name]
        kind = self._kinds[i]
        where = self._locators.positions[i]
        tick, time = self.tick, self.time
        if kind == "vehicle":
            bank, row = self._driven(name)
            return bank.state(row, tick, time, where)
        if kind == "trailer":
            row = self.trailers.rows[name]
            return self.trailers.state(row, tick, time, where, self.vehicles.yaw)
        if kind == "pedestrian":
            return self.walkers.state(self.walkers.rows[name], tick, time, where)
        return self.obstacles.state(self.obstacles.rows[name], tick, time, where)

    def states(self) -> dict[str, ActorState]:
        """The state of every actor, by name."""
        return {name: self.state(name) for name in self._names}

    def read_states(self, out: dict[str, ActorState], static: bool = True) -> None:
        """Write the state of every actor into ``out`` (the same values as :meth:`state`).

        Each kind is read in one pass over its bank's arrays, which is what a runner
        needs every tick; ``static=False`` leaves obstacles (which never move) as they
        are in ``out``.
        """
        tick, time, positions = self.tick, self.time, self._locators.positions
        self.vehicles.read_states(out, tick, time, positions)
        self.kinematic.read_states(out, tick, time, positions)
        self.trailers.read_states(out, tick, time, positions, self.vehicles.yaw)
        self.walkers.read_states(out, tick, time, positions)
        if static or any(name not in out for name in self.obstacles.names):
            self.obstacles.read_states(out, tick, time, positions)

    # ------------------------------------------------------------------ divergence

    def diverged(self) -> tuple[str, str] | None:
        """``(actor, what)`` when the state is no longer physical, else None.

        Either MuJoCo found a NaN, infinite or huge value since the last call (it
        then resets the simulation, so the state would look finite but be
        teleported), or an actor's position or speed is not finite. ``actor`` is
        the actor concerned (``""`` when MuJoCo's report names none).
        """
        if self._divergence.warned():
            return self._divergence.report()
        return (
            self.vehicles.non_finite()
            or self.kinematic.non_finite()
            or self.trailers.non_finite()
            or self.walkers.non_finite()
        )

    def wheel_loads(self, name: str) -> tuple[float, float, float, float]:
        """Normal load (N) of each tire (fl, fr, rl, rr) of a vehicle: measured from the
        contacts, or the actuator layer's estimate for a kinematic vehicle."""
        bank, row = self._driven(name)
        return bank.wheel_loads(row)

    def wheel_speeds(self, name: str) -> tuple[float, float, float, float]:
        """Spin rate times radius (m/s) of each wheel of a vehicle (a kinematic vehicle's
        speed)."""
        bank, row = self._driven(name)
        return bank.wheel_speeds(row)

    def state_array(self) -> np.ndarray:
        """Every number that determines the future, as one array (for replay checks)."""
        d = self.data
        bank = self.vehicles.actuators
        return np.concatenate(
            [
                [d.time],
                d.qpos,
                d.qvel,
                d.act,
                d.qacc_warmstart,
                d.mocap_pos.ravel(),
                d.mocap_quat.ravel(),
                bank.throttle,
                bank.brake,
                bank.delta,
                self.model.geom_friction[:, 0],
                self.kinematic.state_array(),
            ]
        )

    # ------------------------------------------------------------------ friction and weather

    def _apply_road_friction(self, mu: float) -> None:
        if mu <= 0.0:
            raise ValueError(f"friction must be > 0, got {mu}")
        self.road_friction = float(mu)
        self.vehicles.set_friction(mu)
        self.kinematic.set_friction(mu)
        self.trailers.mu[:] = mu
        self._write_friction()

    def _write_friction(self) -> None:
        self.vehicles.write_friction()
        self.kinematic.write_friction()
        self.trailers.write_friction()

    def set_road_friction(self, mu: float) -> None:
        """Set the friction coefficient of the whole road (every tire contact) from now on."""
        self._apply_road_friction(mu)
        self.friction_explicit = True

    def set_wheel_friction(self, name: str, mu: float, wheel: int | str | None = None) -> None:
        """Set the friction under one vehicle, or under one of its wheels (index or fl/fr/rl/rr)."""
        if mu <= 0.0:
            raise ValueError(f"friction must be > 0, got {mu}")
        bank, row = self._driven(name)
        w = WHEELS.index(wheel) if isinstance(wheel, str) else wheel
        bank.set_friction(mu, row, None if w is None else int(w))
        self._write_friction()

    def wheel_friction(self, name: str) -> tuple[float, float, float, float]:
        """Current friction coefficient of each tire (fl, fr, rl, rr) of a vehicle."""
        bank, row = self._driven(name)
        return four(bank.mu[row])

    def set_weather(self, rain: float | None = None, fog: float | None = None) -> None:
        """Record the weather; rain also sets the road friction unless it was set explicitly."""
        changes: dict[str, float] = {}
        if rain is not None:
            changes["rain"] = float(rain)
        if fog is not None:
            changes["fog"] = float(fog)
        self.weather = replace(self.weather, **changes)
        if not self.friction_explicit:
            self._apply_road_friction(weather_friction(self.weather))

    # ------------------------------------------------------------------ events

    @property
    def collisions(self) -> frozenset[tuple[str, str]]:
        """Pairs of actors whose bounding boxes overlap now."""
        return self._events.collisions
