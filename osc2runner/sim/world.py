"""The simulated world: one MuJoCo model of a road network and its actors.

A :class:`World` is built from a road network (a built-in map or an OpenDRIVE
file: :class:`~osc2check.world.network.RoadNetwork`) and a list of
:class:`ActorSpec` (sedans, HGVs, pedestrians, obstacles with their initial
pose and speed). It advances in fixed control steps (50 ms by default), each
made of a whole number of physics steps (2 ms by default):

1. the inputs of this tick go through the actuator layer (rate limits, ABS,
   TCS, Ackermann) and are written into the model; trailers brake with their
   tow vehicles (``sim/trailer.py``);
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

Friction is a property of the tires (they override the road's geom friction
by priority): :meth:`World.set_road_friction` writes every tire,
:meth:`World.set_wheel_friction` one vehicle or one wheel. Weather is recorded;
rain sets a default friction unless friction was set explicitly.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import mujoco
import numpy as np

from osc2check.world.carriageways import carriageways, start_pose
from osc2check.world.network import LaneRef, RoadNetwork
from osc2check.world.paths import LanePath
from osc2check.world.tracking import RoadLocator, RoadPosition
from osc2runner.sim.actuators import ActuatorBank
from osc2runner.sim.events import Event, EventDetector
from osc2runner.sim.trailer import (
    TrailerBank,
    TrailerParams,
    articulation,
    hitch_equality_xml,
    trailer_body_xml,
)
from osc2runner.sim.vehicle import (
    WHEELS,
    ObstacleParams,
    PedestrianParams,
    VehicleParams,
    drag_forces,
    free_body_state,
    obstacle_xml,
    pedestrian_xml,
    vehicle_actuator_xml,
    vehicle_body_xml,
)

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

ActorParams = VehicleParams | PedestrianParams | ObstacleParams | TrailerParams

DRY_FRICTION = 1.0

#: MuJoCo's warnings of a diverged simulation (NaN, inf or > 1e10 in qpos, qvel, qacc)
_BAD_STATE = (
    (mujoco.mjtWarning.mjWARN_BADQPOS, "position"),
    (mujoco.mjtWarning.mjWARN_BADQVEL, "velocity"),
    (mujoco.mjtWarning.mjWARN_BADQACC, "acceleration"),
)


# ---------------------------------------------------------------------- data


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
    position, heading and speed are not used).
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


# ---------------------------------------------------------------------- world


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

        self._index = {a.name: i for i, a in enumerate(self.specs)}
        # each actor's initial world (x, y, yaw): its spec's pose on the map, found once
        self._initial = [a.pose(network) for a in self.specs]
        self._vehicles = [a for a in self.specs if a.kind == "vehicle"]
        self._pedestrians = [a for a in self.specs if a.kind == "pedestrian"]
        self._trailers = [a for a in self.specs if a.kind == "trailer"]
        self._vparams = [a.params for a in self._vehicles if isinstance(a.params, VehicleParams)]
        self._vrow = {a.name: i for i, a in enumerate(self._vehicles)}
        self._prow = {a.name: i for i, a in enumerate(self._pedestrians)}
        self._trow = {a.name: i for i, a in enumerate(self._trailers)}
        self._check_hitches()
        self.xml = self._build_xml()
        self.model = mujoco.MjModel.from_xml_string(self.xml)
        self.data = mujoco.MjData(self.model)
        self._build_indices()
        self.actuators = ActuatorBank(self._vparams, self.dt_control)
        self.reset()

    # ------------------------------------------------------------------ build

    def _prefix(self, name: str) -> str:
        return f"a{self._index[name]}"

    def _check_hitches(self) -> None:
        towing: set[str] = set()
        for spec in self._trailers:
            tow = spec.towed_by
            if tow is None:
                continue
            if not self.can_tow(tow):
                raise ValueError(f"`{spec.name}` is towed by `{tow}`, which has no hitch receiver")
            if tow in towing:
                raise ValueError(f"`{tow}` tows two trailers")
            towing.add(tow)

    def can_tow(self, name: str) -> bool:
        """Whether actor ``name`` is a vehicle with a hitch receiver."""
        i = self._index.get(name)
        params = self.specs[i].params if i is not None else None
        return isinstance(params, VehicleParams) and params.can_tow

    def _build_xml(self) -> str:
        bodies: list[str] = []
        actuators: list[str] = []
        collide = self.physical_collisions
        for spec, (x, y, yaw) in zip(self.specs, self._initial, strict=True):
            prefix = self._prefix(spec.name)
            p = spec.params
            if isinstance(p, VehicleParams):
                bodies.append(vehicle_body_xml(prefix, p, x, y, yaw, collide=collide))
                actuators.append(vehicle_actuator_xml(prefix, p))
            elif isinstance(p, TrailerParams):
                if spec.towed_by is not None:
                    x, y, yaw = self._hitch_pose(spec.name, spec.towed_by, initial=True)
                bodies.append(trailer_body_xml(prefix, p, x, y, yaw, collide=collide))
            elif isinstance(p, PedestrianParams):
                bodies.append(pedestrian_xml(prefix, p, x, y, yaw))
            else:
                bodies.append(obstacle_xml(prefix, p, x, y, yaw, collide=collide))
        hitches = [
            hitch_equality_xml(
                self._prefix(tow.name), self._prefix(t.name), active=t.towed_by == tow.name
            )
            for t in self._trailers
            for tow in self._vehicles
            if self.can_tow(tow.name)
        ]
        x0, x1, y0, y1 = self.network.bounds()
        return "\n".join(
            [
                '<mujoco model="osc2run">',
                '  <compiler angle="radian" autolimits="true"/>',
                f'  <option timestep="{self.dt_physics!r}" integrator="implicitfast" '
                'cone="elliptic"/>',
                "  <worldbody>",
                '    <geom name="road" type="plane" size="0 0 1" contype="0" conaffinity="1" '
                f'pos="{0.5 * (x0 + x1)!r} {0.5 * (y0 + y1)!r} 0" condim="3"/>',
                *bodies,
                "  </worldbody>",
                "  <actuator>",
                *actuators,
                "  </actuator>",
                "  <equality>",
                *hitches,
                "  </equality>",
                "</mujoco>",
            ]
        )

    def _build_indices(self) -> None:
        m = self.model

        def jid(name: str) -> int:
            return mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, name)

        def aid(name: str) -> int:
            return mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_ACTUATOR, name)

        def gid(name: str) -> int:
            return mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, name)

        def bid(name: str) -> int:
            return mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, name)

        nv = len(self._vehicles)
        self._body = np.zeros(nv, dtype=int)
        self._qadr = np.zeros(nv, dtype=int)
        self._vadr = np.zeros(nv, dtype=int)
        self._spin_dof = np.zeros((nv, 4), dtype=int)
        self._wheel_body = np.zeros((nv, 4), dtype=int)
        self._tire = np.zeros((nv, 4), dtype=int)
        self._steer_act = np.zeros((nv, 2), dtype=int)
        drive_act: list[int] = []
        self._geom_wheel = np.full(m.ngeom, -1, dtype=int)
        for row, spec in enumerate(self._vehicles):
            prefix = self._prefix(spec.name)
            root = jid(f"{prefix}_root")
            self._body[row] = bid(prefix)
            self._qadr[row] = m.jnt_qposadr[root]
            self._vadr[row] = m.jnt_dofadr[root]
            for w, wheel in enumerate(WHEELS):
                name = f"{prefix}_{wheel}"
                self._spin_dof[row, w] = m.jnt_dofadr[jid(f"{name}_spin")]
                self._wheel_body[row, w] = bid(f"{name}_wheel")
                self._tire[row, w] = gid(f"{name}_tire")
                self._geom_wheel[self._tire[row, w]] = 4 * row + w
                if self._vparams[row].driven[w]:
                    drive_act.append(aid(f"{name}_drive"))
            self._steer_act[row] = (aid(f"{prefix}_fl_steer"), aid(f"{prefix}_fr_steer"))
        self._drive_act = np.asarray(drive_act, dtype=int)
        driven = [p.driven for p in self._vparams]
        self._driven_mask = np.array(driven, dtype=bool).reshape(nv, 4)
        self._mocap = np.array(
            [m.body_mocapid[bid(self._prefix(a.name))] for a in self._pedestrians], dtype=int
        )
        self._mu = np.ones((nv, 4))
        self._mu_mean = [1.0] * nv
        self.trailers = TrailerBank(
            m,
            [self._prefix(a.name) for a in self._trailers],
            [a.params for a in self._trailers if isinstance(a.params, TrailerParams)],
        )
        self._tmu = np.ones((len(self._trailers), 2))
        self._hitch_eq = {
            (tow.name, t.name): mujoco.mj_name2id(
                m,
                mujoco.mjtObj.mjOBJ_EQUALITY,
                f"{self._prefix(tow.name)}_tows_{self._prefix(t.name)}",
            )
            for t in self._trailers
            for tow in self._vehicles
            if self.can_tow(tow.name)
        }
        self._q7 = self._qadr[:, None] + np.arange(7)
        self._v6 = self._vadr[:, None] + np.arange(6)

        # bounding boxes of every actor, for events
        n = len(self.specs)
        self._is_static = np.array([a.kind == "obstacle" for a in self.specs])
        self._kinds = tuple(a.kind for a in self.specs)
        self._names = tuple(a.name for a in self.specs)
        self._veh_pos = np.array([self._index[a.name] for a in self._vehicles], dtype=int)
        self._trl_pos = np.array([self._index[a.name] for a in self._trailers], dtype=int)
        self._ped_pos = np.array([self._index[a.name] for a in self._pedestrians], dtype=int)
        self._obs_pos = np.flatnonzero(self._is_static)
        self._obs_names = tuple(self._names[i] for i in self._obs_pos)
        self._obs_pose = np.array([self._initial[i] for i in self._obs_pos], dtype=float).reshape(
            -1, 3
        )
        self._events = EventDetector(
            self._names,
            np.array([(0.5 * a.params.length, 0.5 * a.params.width) for a in self.specs]),
            self._is_static,
            margin=0.1 if self.physical_collisions else 0.0,
        )
        self._locators = [RoadLocator(self.network) for _ in self.specs]
        self._positions: list[RoadPosition] = [
            loc.locate(*pose) for loc, pose in zip(self._locators, self._initial, strict=True)
        ]
        self._moving_rows = [i for i in range(n) if not self._is_static[i]]
        self._located: list[tuple[float, float] | None] = [None] * n
        walkers = set(self._ped_pos.tolist())
        # per moving row: a walker (off the map when outside every road, not off drivable lanes)
        self._moving_walker = tuple(i in walkers for i in self._moving_rows)
        self._centre = np.zeros((n, 2))
        self._yaw_all = np.zeros(n)
        self._bad_stats = tuple(self.data.warning[int(w)] for w, _ in _BAD_STATE)

    # ------------------------------------------------------------------ reset

    def reset(self) -> None:
        """Back to the initial state: settle the suspensions, then place every actor."""
        m, d = self.model, self.data
        mujoco.mj_resetData(m, d)
        self.actuators.reset()
        self.tick = 0
        self.events: list[Event] = []
        self._events.reset()
        self.weather = self._initial_weather
        self.friction_explicit = self._initial_friction is not None
        if self._initial_friction is not None:
            self._apply_road_friction(self._initial_friction)
        else:
            self._apply_road_friction(weather_friction(self.weather))

        nv = len(self._vehicles)
        self.trailers.reset()
        self.hitched: dict[str, str] = {}  # trailer -> its tow vehicle
        for spec in self._trailers:
            if spec.towed_by is not None:
                self._hitch(spec.towed_by, spec.name)
        # settle at rest with the brakes on and the steering centred
        if (nv or self._trailers) and self.settle_time > 0.0:
            m.dof_frictionloss[self._spin_dof.ravel()] = self.actuators.brake_max.ravel()
            m.dof_frictionloss[self.trailers.spin_dof.ravel()] = np.repeat(
                [p.mass * p.wheel_radius * 5.0 for p in self.trailers.params], 2
            )
            d.ctrl[:] = 0.0
            mujoco.mj_step(m, d, nstep=max(1, round(self.settle_time / self.dt_physics)))
            d.qvel[:] = 0.0
            d.time = 0.0
            d.qacc_warmstart[:] = 0.0
        mujoco.mj_forward(m, d)
        self._ped_vel = np.zeros((len(self._pedestrians), 3))
        self._ped_speed = np.zeros(len(self._pedestrians))
        self._ped_yaw = np.zeros(len(self._pedestrians))
        self._ped_accel = np.zeros(len(self._pedestrians))
        self._ped_input: list[PedestrianInput | None] = [None] * len(self._pedestrians)
        n_ped = len(self._pedestrians)
        # walkers that stand still (no speed, no acceleration) keep their pose and their
        # state: nothing is moved, read, or checked for them until they move again
        self._ped_still = [False] * n_ped
        self._ped_moving = n_ped
        self._moving_now = list(self._moving_rows)  # the moving rows, still walkers left out
        self._ped_state: list[ActorState | None] = [None] * n_ped
        self._ped_all_kept = False  # every walker stands still and has its state kept
        self._ped_dirty = True  # a walker's pose changed: its row of the pose arrays too
        self._ped_unchecked = True  # ... and its position is not known to be finite
        self._located = [None] * len(self.specs)
        self._accel = np.zeros(nv)
        self._distance = np.zeros(len(self.specs))
        self._read()
        self.trailers.read(d)
        for spec, (x, y, yaw) in zip(self.specs, self._initial, strict=True):
            if spec.kind != "obstacle" and spec.name not in self.hitched:
                # obstacles stay where the model put them; hitched trailers come with their tow
                self.place(spec.name, x, y, yaw, spec.speed)
        mujoco.mj_forward(m, d)
        self._read()
        self.trailers.read(d)
        self._locate()
        self._bad_seen = self._bad_counts()
        self._bad_total = sum(self._bad_seen)

    def place(self, name: str, x: float, y: float, yaw: float, speed: float = 0.0) -> None:
        """Move an actor to ``(x, y)`` with heading ``yaw`` and ``speed`` along it.

        For vehicles the suspension state and the chassis pitch/roll are kept;
        the wheels get the matching spin. Call before the first tick (the
        scenario initializer does); mid-run it is a teleport.
        """
        kind = self._kinds[self._index[name]]
        m, d = self.model, self.data
        self._locators[self._index[name]].reset()
        self._located[self._index[name]] = None
        if kind == "vehicle":
            row = self._vrow[name]
            _set_free_body(
                m, d, self._qadr[row], self._vadr[row], self._spin_dof[row],
                self._wheel_body[row], x, y, yaw, speed,
            )  # fmt: skip
            self._read()
            self._accel[row] = 0.0
            trailer = self.towing(name)
            if trailer is not None:  # the trailer comes along, on the hitch
                self._place_trailer(trailer, *self._hitch_pose(trailer, name), speed)
        elif kind == "trailer":
            self._place_trailer(name, x, y, yaw, speed)
        elif kind == "pedestrian":
            row = self._prow[name]
            mid = self._mocap[row]
            d.mocap_pos[mid, :2] = (x, y)
            d.mocap_quat[mid] = _yaw_quat(yaw)
            self._ped_speed[row] = speed
            self._ped_yaw[row] = yaw
            self._ped_vel[row] = (speed * math.cos(yaw), speed * math.sin(yaw), 0.0)
            self._ped_input[row] = None
            self._walker_moves(row, speed != 0.0 or self._ped_accel[row] != 0.0)
        else:
            raise ValueError(f"obstacle `{name}` is static and cannot be placed after start")
        self._locate()

    def _place_trailer(self, name: str, x: float, y: float, yaw: float, speed: float) -> None:
        m, d = self.model, self.data
        bank = self.trailers
        row = self._trow[name]
        self._locators[self._index[name]].reset()
        self._located[self._index[name]] = None
        _set_free_body(
            m, d, bank.qadr[row], bank.vadr[row], bank.spin_dof[row], bank.wheel_body[row],
            x, y, yaw, speed,
        )  # fmt: skip
        bank.read(d)
        bank.accel[row] = 0.0

    # ------------------------------------------------------------------ hitches

    def _hitch_pose(
        self, trailer: str, tow: str, initial: bool = False
    ) -> tuple[float, float, float]:
        """Where ``trailer`` stands on ``tow``'s hitch, aligned with it: its world
        ``(x, y, yaw)`` from the tow vehicle's current pose (``initial``: its spec's)."""
        tow_spec = self.specs[self._index[tow]]
        tp, vp = self.specs[self._index[trailer]].params, tow_spec.params
        assert isinstance(tp, TrailerParams) and isinstance(vp, VehicleParams)
        assert vp.receiver_x is not None
        if initial:
            x, y, yaw = self._initial[self._index[tow]]
        else:
            row = self._vrow[tow]
            x, y, yaw = float(self._pos[row, 0]), float(self._pos[row, 1]), float(self._yaw[row])
        back = -vp.receiver_x + tp.coupler  # tow centre to trailer centre, along the heading
        return (x - back * math.cos(yaw), y - back * math.sin(yaw), yaw)

    def _hitch(self, tow: str, trailer: str) -> None:
        self.hitched[trailer] = tow
        self.data.eq_active[self._hitch_eq[(tow, trailer)]] = 1
        self._events.ignore(self._index[tow], self._index[trailer])

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
            raise ValueError(f"`{tow}` has no hitch receiver")
        if self.kind(trailer) != "trailer":
            raise ValueError(f"`{trailer}` is not a trailer")
        if trailer in self.hitched:
            raise ValueError(f"`{trailer}` is already towed by `{self.hitched[trailer]}`")
        if self.towing(tow) is not None:
            raise ValueError(f"`{tow}` already tows `{self.towing(tow)}`")
        x, y, yaw = self._hitch_pose(trailer, tow)
        row = self._trow[trailer]
        bank = self.trailers
        here = bank.pos[row].tolist()
        moved = math.hypot(x - here[0], y - here[1])
        turned = abs(articulation(yaw, float(bank.yaw[row])))
        if moved > 0.05 or turned > 0.01:
            self._place_trailer(trailer, x, y, yaw, float(self._speed[self._vrow[tow]]))
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
        del self.hitched[trailer]
        self.data.eq_active[self._hitch_eq[(tow, trailer)]] = 0
        self._events.ignore(self._index[tow], self._index[trailer], False)
        return trailer

    def articulation(self, trailer: str) -> float:
        """A hitched trailer's articulation angle (rad; NaN when it is not hitched)."""
        tow = self.hitched.get(trailer)
        if tow is None:
            return math.nan
        return articulation(
            float(self._yaw[self._vrow[tow]]), float(self.trailers.yaw[self._trow[trailer]])
        )

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
            self.actuators.set_command(self._vrow[name], value.throttle, value.brake, value.steer)
        elif kind == "pedestrian" and isinstance(value, PedestrianInput):
            row = self._prow[name]
            held = self._ped_input[row]
            if (held is value or held == value) and self._ped_accel[row] == 0.0:
                return  # the same input as held: nothing changes (idle walkers cost nothing)
            self._ped_input[row] = value
            yaw = value.yaw
            speed = value.speed
            self._ped_vel[row] = (speed * math.cos(yaw), speed * math.sin(yaw), 0.0)
            self._ped_yaw[row] = yaw
            self._ped_accel[row] = (speed - self._ped_speed[row]) / self.dt_control
            self._ped_speed[row] = speed
            self.data.mocap_quat[self._mocap[row]] = _yaw_quat(yaw)
            self._walker_moves(row, speed != 0.0 or self._ped_accel[row] != 0.0)
        else:
            raise TypeError(f"{type(value).__name__} is not an input for {kind} `{name}`")

    def _walker_moves(self, row: int, moves: bool) -> None:
        """Walker ``row``'s input or pose changed: whether it moves now (a walker that
        stands still costs nothing per tick until it moves again)."""
        self._ped_state[row] = None
        self._ped_all_kept = False
        self._ped_dirty = self._ped_unchecked = True
        if self._ped_still[row] == moves:
            self._ped_still[row] = not moves
            self._ped_moving += 1 if moves else -1
            self._events.hold(int(self._ped_pos[row]), not moves)
            still = {int(self._ped_pos[r]) for r, s in enumerate(self._ped_still) if s}
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
        m, d = self.model, self.data
        if len(self._vehicles):
            bank = self.actuators
            bank.update(self._speed, self._mu, self._accel, self._speed * self._yaw_rate)
            d.ctrl[self._drive_act] = bank.drive_torque[self._driven_mask]
            m.dof_frictionloss[self._spin_dof] = bank.brake_torque
            d.ctrl[self._steer_act] = bank.steer_angles
            d.xfrc_applied[self._body, :2] = drag_forces(bank.drag_coefficient, self._vel)
        if self._trailers:
            self._brake_trailers()
        if self._ped_moving:
            d.mocap_pos[self._mocap] += self._ped_vel * self.dt_control
        mujoco.mj_step(m, d, nstep=self.substeps)
        self.tick += 1
        prev = self._vel
        self._read()
        if len(self._vehicles):
            c, s = self._cos, self._sin  # of the new yaw, from _read
            dv = (self._vel - prev) / self.dt_control
            self._accel = dv[:, 0] * c + dv[:, 1] * s
            self._distance[self._veh_pos] += np.abs(self._speed) * self.dt_control
        if self._trailers:
            self.trailers.read(d, self.dt_control)
            self._distance[self._trl_pos] += np.abs(self.trailers.speed) * self.dt_control
        if self._ped_moving:
            self._distance[self._ped_pos] += np.abs(self._ped_speed) * self.dt_control
        centre, yaw = self._poses()
        self._locate(centre, yaw)
        positions = self._positions
        off = [
            not (positions[i].inside if walker else positions[i].drivable)
            for i, walker in zip(self._moving_rows, self._moving_walker, strict=True)
        ]
        events = self._events.detect(self.tick, self.time, centre, yaw, off)
        self.events.extend(events)
        return events

    def _brake_trailers(self) -> None:
        """A hitched trailer brakes as its tow vehicle does; an unhitched one is parked."""
        bank = self.trailers
        applied = self.actuators.brake
        for row, spec in enumerate(self._trailers):
            tow = self.hitched.get(spec.name)
            bank.brake[row] = applied[self._vrow[tow]] if tow is not None else 1.0
        bank.apply(self.model, self.data, self._tmu)

    def _locate(self, centre: np.ndarray | None = None, yaw: np.ndarray | None = None) -> None:
        """The road coordinates of every moving actor, from their new poses (a step's
        ``centre`` and ``yaw`` given: of those that may have moved, not the walkers that
        stand still)."""
        rows = self._moving_rows
        if centre is None or yaw is None:
            centre, yaw = self._poses()
        elif self._ped_moving < len(self._pedestrians):
            rows = self._moving_now
        points = centre.tolist()
        angles = yaw.tolist()
        positions, locators, last = self._positions, self._locators, self._located
        for i in rows:
            x, y = points[i]
            if last[i] == (x, y):
                continue  # a walker standing still: where it was
            last[i] = (x, y)
            positions[i] = locators[i].locate(x, y, angles[i])

    def follow(self, name: str, path: LanePath | None) -> None:
        """Tell the world the lanes actor ``name`` drives (its driver's path): where roads
        overlap, its road coordinates are taken on them."""
        self._locators[self._index[name]].follow(path)

    def position(self, name: str) -> RoadPosition:
        """Where actor ``name`` is on the map now."""
        return self._positions[self._index[name]]

    def run(self, seconds: float, inputs: Mapping[str, VehicleInput | PedestrianInput]) -> None:
        """Hold ``inputs`` for ``seconds`` (rounded to whole control steps)."""
        for _ in range(round(seconds / self.dt_control)):
            self.step_control(inputs)

    # ------------------------------------------------------------------ read-out

    def _read(self) -> None:
        d = self.data
        if len(self._vehicles):
            (
                self._pos,
                self._yaw,
                self._vel,
                self._yaw_rate,
                self._cos,
                self._sin,
                self._speed,
                self._lat_speed,
            ) = free_body_state(d.qpos[self._q7], d.qvel[self._v6])
        else:
            self._pos = np.zeros((0, 2))
            self._yaw = self._speed = self._lat_speed = self._yaw_rate = np.zeros(0)
            self._vel = np.zeros((0, 3))

    def _measure_loads(self) -> np.ndarray:
        """Normal force per tire from the contacts of the last physics step, shape (n, 4)."""
        d = self.data
        nv = len(self._vehicles)
        if d.ncon == 0:
            return np.zeros((nv, 4))
        contact = d.contact
        wheel = self._geom_wheel[contact.geom].max(axis=1)
        adr = contact.efc_address
        ok = (wheel >= 0) & (adr >= 0)
        force = d.efc_force[adr[ok]]  # elliptic cones: the first row is the normal force
        return np.bincount(wheel[ok], weights=force, minlength=4 * nv).reshape(nv, 4)

    def _poses(self) -> tuple[np.ndarray, np.ndarray]:
        """Centre (n, 2) and yaw (n,) of every actor's bounding box."""
        centre = self._centre
        yaw = self._yaw_all
        if len(self._vehicles):
            centre[self._veh_pos] = self._pos
            yaw[self._veh_pos] = self._yaw
        if self._trailers:
            centre[self._trl_pos] = self.trailers.pos
            yaw[self._trl_pos] = self.trailers.yaw
        if self._ped_moving or self._ped_dirty:
            centre[self._ped_pos] = self.data.mocap_pos[self._mocap, :2]
            yaw[self._ped_pos] = self._ped_yaw
            self._ped_dirty = False
        if len(self._obs_pos):
            centre[self._obs_pos] = self._obs_pose[:, :2]
            yaw[self._obs_pos] = self._obs_pose[:, 2]
        return centre, yaw

    def state(self, name: str) -> ActorState:
        """The state of actor ``name`` at the current tick."""
        i = self._index[name]
        kind = self._kinds[i]
        spec = self.specs[i]
        nan = math.nan
        if kind == "vehicle":
            r = self._vrow[name]
            bank = self.actuators
            x, y = float(self._pos[r, 0]), float(self._pos[r, 1])
            yaw = float(self._yaw[r])
            speed, lat = float(self._speed[r]), float(self._lat_speed[r])
            yaw_rate, accel = float(self._yaw_rate[r]), float(self._accel[r])
            friction = self._mu_mean[r]
            throttle, brake = float(bank.throttle[r]), float(bank.brake[r])
            steer = float(bank.delta[r] / bank.max_steer[r])
        elif kind == "trailer":
            return self._trailer_state(name, self.tick, self.time)
        elif kind == "pedestrian":
            r = self._prow[name]
            pos = self.data.mocap_pos[self._mocap[r]]
            x, y = float(pos[0]), float(pos[1])
            yaw = float(self._ped_yaw[r])
            speed, lat, yaw_rate = float(self._ped_speed[r]), 0.0, 0.0
            accel = float(self._ped_accel[r])
            friction = throttle = brake = steer = nan
        else:
            x, y, yaw = self._initial[i]
            speed = lat = yaw_rate = accel = 0.0
            friction = throttle = brake = steer = nan
        p = self._positions[i]
        return ActorState(
            name,
            kind,
            self.tick,
            self.time,
            x,
            y,
            yaw,
            speed,
            lat,
            yaw_rate,
            accel,
            p.number if p.inside else None,
            p.s,
            p.t,
            friction,
            throttle,
            brake,
            steer,
            spec.params.length,
            spec.params.width,
            p.road,
            p.section,
            p.lane,
            p.offset,
            p.direction,
            p.drivable,
            float(self._distance[i]),
        )

    def _trailer_state(self, name: str, tick: int, time: float) -> ActorState:
        r = self._trow[name]
        i = self._index[name]
        bank = self.trailers
        x, y = (float(v) for v in bank.pos[r])
        params = bank.params[r]
        p = self._positions[i]
        return ActorState(
            name,
            "trailer",
            tick,
            time,
            x,
            y,
            float(bank.yaw[r]),
            float(bank.speed[r]),
            float(bank.lat_speed[r]),
            float(bank.yaw_rate[r]),
            float(bank.accel[r]),
            p.number if p.inside else None,
            p.s,
            p.t,
            float(self._tmu[r].mean()),
            math.nan,
            float(bank.brake[r]) if params.braked else 0.0,
            math.nan,
            params.length,
            params.width,
            p.road,
            p.section,
            p.lane,
            p.offset,
            p.direction,
            p.drivable,
            float(self._distance[i]),
            self.articulation(name),
        )

    def states(self) -> dict[str, ActorState]:
        """The state of every actor, by name."""
        return {name: self.state(name) for name in self._names}

    def read_states(self, out: dict[str, ActorState], static: bool = True) -> None:
        """Write the state of every actor into ``out`` (the same values as :meth:`state`).

        Vehicles are read in one pass over the model's arrays, which is what
        a runner needs every tick; ``static=False`` leaves obstacles (which
        never move) as they are in ``out``.
        """
        tick, time = self.tick, self.time
        if len(self._vehicles):
            bank = self.actuators
            pos = self._pos.tolist()
            yaw = self._yaw.tolist()
            speed = self._speed.tolist()
            lat = self._lat_speed.tolist()
            yaw_rate = self._yaw_rate.tolist()
            accel = self._accel.tolist()
            throttle = bank.throttle.tolist()
            brake = bank.brake.tolist()
            steer = (bank.delta / bank.max_steer).tolist()
            distance = self._distance.tolist()
            mu = self._mu_mean
            positions = self._positions
            rows = self._veh_pos.tolist()
            for row, spec in enumerate(self._vehicles):
                x, y = pos[row]
                params = spec.params
                i = rows[row]
                p = positions[i]
                out[spec.name] = ActorState(
                    spec.name,
                    "vehicle",
                    tick,
                    time,
                    x,
                    y,
                    yaw[row],
                    speed[row],
                    lat[row],
                    yaw_rate[row],
                    accel[row],
                    p.number if p.inside else None,
                    p.s,
                    p.t,
                    mu[row],
                    throttle[row],
                    brake[row],
                    steer[row],
                    params.length,
                    params.width,
                    p.road,
                    p.section,
                    p.lane,
                    p.offset,
                    p.direction,
                    p.drivable,
                    distance[i],
                )
        for spec in self._trailers:
            out[spec.name] = self._trailer_state(spec.name, tick, time)
        if len(self._pedestrians):
            self._read_pedestrians(out, tick, time)
        if static or any(name not in out for name in self._obs_names):
            for i in self._obs_pos:
                name = self._names[i]
                out[name] = self.state(name)

    def _read_pedestrians(self, out: dict[str, ActorState], tick: int, time: float) -> None:
        """The walkers' states, as :meth:`state` gives them (their road coordinates are
        located again only when they moved: :meth:`_locate`); a walker that stands still
        keeps its state (whose ``tick`` and ``time`` are those of when it stopped, as an
        obstacle's are those of the start)."""
        still, kept = self._ped_still, self._ped_state
        if self._ped_all_kept:
            for spec, state in zip(self._pedestrians, kept, strict=True):
                out[spec.name] = state  # type: ignore[assignment]
            return
        pos = self.data.mocap_pos[self._mocap, :2].tolist()
        speed = self._ped_speed.tolist()
        yaw = self._ped_yaw.tolist()
        accel = self._ped_accel.tolist()
        rows = self._ped_pos.tolist()
        positions = self._positions
        distance = self._distance
        nan = math.nan
        for row, spec in enumerate(self._pedestrians):
            if still[row] and kept[row] is not None:
                out[spec.name] = kept[row]  # type: ignore[assignment]
                continue
            x, y = pos[row]
            i = rows[row]
            p = positions[i]
            params = spec.params
            state = out[spec.name] = ActorState(
                spec.name,
                "pedestrian",
                tick,
                time,
                x,
                y,
                yaw[row],
                speed[row],
                0.0,
                0.0,
                accel[row],
                p.number if p.inside else None,
                p.s,
                p.t,
                nan,
                nan,
                nan,
                nan,
                params.length,
                params.width,
                p.road,
                p.section,
                p.lane,
                p.offset,
                p.direction,
                p.drivable,
                float(distance[i]),
            )
            if still[row]:
                kept[row] = state
        self._ped_all_kept = not self._ped_moving

    # ------------------------------------------------------------------ divergence

    def _bad_counts(self) -> tuple[int, ...]:
        return tuple(stat.number for stat in self._bad_stats)

    def diverged(self) -> tuple[str, str] | None:
        """``(actor, what)`` when the state is no longer physical, else None.

        Either MuJoCo found a NaN, infinite or huge value since the last call (it
        then resets the simulation, so the state would look finite but be
        teleported), or an actor's position or speed is not finite. ``actor`` is
        the actor concerned (``""`` when MuJoCo's report names none).
        """
        a, b, c = self._bad_stats
        if a.number + b.number + c.number != self._bad_total:
            return self._mujoco_divergence()
        if len(self._vehicles) and not math.isfinite(
            float(self._speed.dot(self._speed)) + float(np.vdot(self._pos, self._pos))
        ):
            for row, spec in enumerate(self._vehicles):
                (x, y), speed = self._pos[row].tolist(), float(self._speed[row])
                if not all(math.isfinite(v) for v in (x, y, speed)):
                    return spec.name, f"non-finite state: x {x}, y {y}, speed {speed}"
        for row, spec in enumerate(self._trailers):
            (x, y), speed = self.trailers.pos[row].tolist(), float(self.trailers.speed[row])
            if not all(math.isfinite(v) for v in (x, y, speed)):
                return spec.name, f"non-finite state: x {x}, y {y}, speed {speed}"
        if (self._ped_moving or self._ped_unchecked) and not np.isfinite(
            self.data.mocap_pos[self._mocap]
        ).all():
            for row, spec in enumerate(self._pedestrians):
                x, y = self.data.mocap_pos[self._mocap[row], :2].tolist()
                speed = float(self._ped_speed[row])
                if not all(math.isfinite(v) for v in (x, y, speed)):
                    return spec.name, f"non-finite state: x {x}, y {y}, speed {speed}"
        self._ped_unchecked = False
        return None

    def _mujoco_divergence(self) -> tuple[str, str]:
        m = self.model
        counts = self._bad_counts()
        found: tuple[str, str] | None = None
        for (warning, what), stat, now, seen in zip(
            _BAD_STATE, self._bad_stats, counts, self._bad_seen, strict=True
        ):
            if now == seen or found is not None:
                continue
            index = int(stat.lastinfo)
            if warning == mujoco.mjtWarning.mjWARN_BADQPOS:
                joints = np.flatnonzero(m.jnt_qposadr <= index)
                body = int(m.jnt_bodyid[joints[-1]]) if len(joints) else -1
            else:
                body = int(m.dof_bodyid[index]) if 0 <= index < m.nv else -1
            found = (
                self._actor_of_body(body),
                f"NaN, infinite or huge {what} in the physics (MuJoCo reset the simulation)",
            )
        self._bad_seen = counts
        self._bad_total = sum(counts)
        return found or ("", "MuJoCo reported an unstable simulation")

    def _actor_of_body(self, body: int) -> str:
        if body < 0:
            return ""
        root = int(self.model.body_rootid[body])
        for spec in self.specs:
            bid = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, self._prefix(spec.name))
            if bid == root:
                return spec.name
        return ""

    def wheel_loads(self, name: str) -> tuple[float, float, float, float]:
        """Measured normal load (N) of each tire (fl, fr, rl, rr) of a vehicle."""
        return _four(self._measure_loads()[self._vrow[name]])

    def wheel_speeds(self, name: str) -> tuple[float, float, float, float]:
        """Spin rate times radius (m/s) of each wheel of a vehicle."""
        row = self._vrow[name]
        r = self.actuators.radius[row]
        return _four(self.data.qvel[self._spin_dof[row]] * r)

    def state_array(self) -> np.ndarray:
        """Every number that determines the future, as one array (for replay checks)."""
        d = self.data
        bank = self.actuators
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
            ]
        )

    # ------------------------------------------------------------------ friction and weather

    def _apply_road_friction(self, mu: float) -> None:
        if mu <= 0.0:
            raise ValueError(f"friction must be > 0, got {mu}")
        self.road_friction = float(mu)
        self._mu[:] = mu
        self._tmu[:] = mu
        self._write_friction()

    def _write_friction(self) -> None:
        """Copy the per-wheel friction table into the model (effective at the next step)."""
        self.model.geom_friction[self._tire, 0] = self._mu
        self.model.geom_friction[self.trailers.tire, 0] = self._tmu
        self._mu_mean = [float(v) for v in self._mu.mean(axis=1)]

    def set_road_friction(self, mu: float) -> None:
        """Set the friction coefficient of the whole road (every tire contact) from now on."""
        self._apply_road_friction(mu)
        self.friction_explicit = True

    def set_wheel_friction(self, name: str, mu: float, wheel: int | str | None = None) -> None:
        """Set the friction under one vehicle, or under one of its wheels (index or fl/fr/rl/rr)."""
        if mu <= 0.0:
            raise ValueError(f"friction must be > 0, got {mu}")
        row = self._vrow[name]
        if wheel is None:
            self._mu[row] = mu
        else:
            w = WHEELS.index(wheel) if isinstance(wheel, str) else int(wheel)
            self._mu[row, w] = mu
        self._write_friction()

    def wheel_friction(self, name: str) -> tuple[float, float, float, float]:
        """Current friction coefficient of each tire (fl, fr, rl, rr) of a vehicle."""
        row = self._vrow[name]
        return _four(self._mu[row])

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


# ---------------------------------------------------------------------- helpers


def _set_free_body(
    m: mujoco.MjModel,
    d: mujoco.MjData,
    q: int,
    v: int,
    spin_dof: np.ndarray,
    wheel_body: np.ndarray,
    x: float,
    y: float,
    yaw: float,
    speed: float,
) -> None:
    """Move a vehicle's or trailer's free body (``qpos`` at ``q``, ``qvel`` at ``v``) to
    ``(x, y)`` heading ``yaw``, keeping its height, pitch and roll, at ``speed`` along the
    heading; its wheels (``spin_dof``, ``wheel_body``) get the matching spin."""
    old = d.qpos[q + 3 : q + 7].copy()
    tilt = _quat_mul(_yaw_quat(-_quat_yaw(old)), old)
    d.qpos[q : q + 2] = (x, y)
    d.qpos[q + 3 : q + 7] = _quat_mul(_yaw_quat(yaw), tilt)
    d.qvel[v : v + 6] = (speed * math.cos(yaw), speed * math.sin(yaw), 0.0, 0.0, 0.0, 0.0)
    mujoco.mj_kinematics(m, d)
    d.qvel[spin_dof] = speed / d.xpos[wheel_body, 2]  # rolling radius = wheel centre height


def _four(values: np.ndarray) -> tuple[float, float, float, float]:
    a, b, c, d = (float(v) for v in values)
    return (a, b, c, d)


def _yaw_quat(yaw: float) -> np.ndarray:
    return np.array([math.cos(0.5 * yaw), 0.0, 0.0, math.sin(0.5 * yaw)])


def _quat_yaw(q: np.ndarray) -> float:
    w, x, y, z = (float(v) for v in q)
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def _quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    out = np.empty(4)
    mujoco.mju_mulQuat(out, np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    return out
