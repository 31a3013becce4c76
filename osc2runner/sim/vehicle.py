"""Actor parameters and their MuJoCo bodies (parameters -> MJCF).

A vehicle is a multibody car (reference/vehicle-model.md, prototype A): a
chassis on a free joint, four knuckles on suspension slide joints, steer
hinges on the front knuckles and four wheels on spin hinges with sphere tires.

* Tires collide only with the road (``contype=1 conaffinity=0``, the road has
  ``contype=0 conaffinity=1``) and carry ``priority=1``, so the contact
  friction is the tire's own value, which the world writes at runtime.
* Chassis boxes collide only with other chassis and obstacles (bit 2), and
  only when physical collisions are enabled.
* All angles are radians (``<compiler angle="radian">`` is set by the world;
  orientations are written as quaternions anyway).
* Drive is one ``motor`` per driven wheel (equal torque: an open
  differential); brakes are runtime ``dof_frictionloss`` on the spin joints;
  steering is a ``position`` actuator per front knuckle (Ackermann split in
  the actuator layer).

The chassis body frame sits at the centre of the actor's bounding box at the
height of the centre of gravity, so the reported ``(x, y)`` of a vehicle is
its bounding-box centre, the reference point the checker places.

A pedestrian is a kinematic ``mocap`` capsule; an obstacle a static box.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from osc2runner.sim.mjcf import GRAVITY, SteerHinge, corner_xml, num, vec, yaw_quat

__all__ = [
    "GRAVITY",
    "WHEELS",
    "ObstacleParams",
    "PedestrianParams",
    "VehicleParams",
    "hgv",
    "obstacle_xml",
    "pedestrian_xml",
    "sedan",
    "yaw_quat",
    "vehicle_actuator_xml",
    "vehicle_body_xml",
]

#: Wheel order used by every per-wheel array: front-left, front-right, rear-left, rear-right.
WHEELS: tuple[str, str, str, str] = ("fl", "fr", "rl", "rr")


@dataclass(frozen=True, slots=True)
class VehicleParams:
    """Physical and actuator parameters of a four-wheeled road vehicle.

    Lengths in metres, masses in kg, forces in N, torques in N·m, angles in
    radians, rates per second. The defaults are the measured sedan of
    reference/vehicle-model.md §5.
    """

    model: str = "sedan"
    category: str = "car"
    # bounding box
    length: float = 4.5
    width: float = 1.8
    height: float = 1.45
    ground_clearance: float = 0.15
    front_overhang: float = 0.85  # front bumper to front axle
    # masses and inertia
    mass: float = 1600.0  # total, wheels and knuckles included
    wheel_mass: float = 20.0
    knuckle_mass: float = 5.0
    inertia: tuple[float, float, float] = (600.0, 2500.0, 2800.0)  # chassis, about its CoG
    # geometry
    lf: float = 1.2  # CoG to front axle
    lr: float = 1.5  # CoG to rear axle
    track: float = 1.55
    wheel_radius: float = 0.33
    h_cog: float = 0.55
    # powertrain
    drive: str = "rwd"  # "rwd", "fwd" or "awd"
    max_drive_force: float = 5000.0
    max_power: float = 100e3
    # brakes
    max_brake_torque: float = 6000.0  # all four wheels together
    brake_front_share: float = 0.65
    # steering
    max_steer: float = 0.55  # road-wheel angle
    steer_rate: float = 0.8  # road-wheel angle rate limit
    steer_kp: float = 5000.0  # position actuator gain on the steer hinge
    steer_damping: float = 50.0
    steer_armature: float = 2.0
    spin_damping: float = 0.02  # wheel bearing viscous friction, N·m·s/rad
    # pedal rate limits (0 -> 1 in 1/rate seconds)
    throttle_rate: float = 4.0
    brake_rate: float = 6.0
    # suspension (per corner)
    susp_frequency: float = 1.4
    susp_damping_ratio: float = 0.35
    susp_travel: float = 0.25
    # resistances
    rolling_resistance: float = 0.012
    drag_area: float = 0.66  # Cd * A in m^2
    air_density: float = 1.2
    # ECU
    abs_enabled: bool = True
    tcs_enabled: bool = True
    abs_margin: float = 0.9  # brake torque cap = margin * mu * N * r
    tcs_margin: float = 0.9
    max_speed: float = 250.0 / 3.6
    # hitch receiver: how far behind the rear of the box (None: tows nothing), how high
    hitch_reach: float | None = 0.1
    hitch_height: float = 0.45

    def __post_init__(self) -> None:
        if self.drive not in ("rwd", "fwd", "awd"):
            raise ValueError(f"drive must be rwd, fwd or awd, got {self.drive!r}")
        if self.front_overhang + self.lf + self.lr > self.length:
            raise ValueError("wheelbase plus front overhang exceeds the vehicle length")

    # ------------------------------------------------------------ derived values

    @property
    def wheelbase(self) -> float:
        return self.lf + self.lr

    @property
    def chassis_mass(self) -> float:
        return self.mass - 4.0 * (self.wheel_mass + self.knuckle_mass)

    @property
    def cog_x(self) -> float:
        """Longitudinal position of the CoG relative to the bounding-box centre."""
        return 0.5 * self.length - self.front_overhang - self.lf

    @property
    def front_axle_x(self) -> float:
        """Front axle relative to the bounding-box centre."""
        return self.cog_x + self.lf

    @property
    def rear_axle_x(self) -> float:
        """Rear axle relative to the bounding-box centre."""
        return self.cog_x - self.lr

    @property
    def receiver_x(self) -> float | None:
        """The hitch receiver relative to the bounding-box centre (None: tows nothing)."""
        return None if self.hitch_reach is None else -0.5 * self.length - self.hitch_reach

    def front_axle(self, x: float, y: float, yaw: float) -> tuple[float, float]:
        """The world point of the front axle's centre of a vehicle centred at ``(x, y)``
        heading ``yaw`` (where the Stanley law measures its errors)."""
        d = self.front_axle_x
        return x + d * math.cos(yaw), y + d * math.sin(yaw)

    @property
    def can_tow(self) -> bool:
        """Whether it has a hitch receiver."""
        return self.hitch_reach is not None

    @property
    def driven(self) -> tuple[bool, bool, bool, bool]:
        """Which wheels (fl, fr, rl, rr) are driven."""
        front = self.drive in ("fwd", "awd")
        rear = self.drive in ("rwd", "awd")
        return (front, front, rear, rear)

    @property
    def static_wheel_loads(self) -> tuple[float, float, float, float]:
        """Normal load per wheel (N) at rest on flat ground."""
        front = 0.5 * self.mass * GRAVITY * self.lr / self.wheelbase
        rear = 0.5 * self.mass * GRAVITY * self.lf / self.wheelbase
        return (front, front, rear, rear)

    @property
    def brake_torque_per_wheel(self) -> tuple[float, float, float, float]:
        """Maximum brake torque of each wheel (fl, fr, rl, rr)."""
        front = 0.5 * self.max_brake_torque * self.brake_front_share
        rear = 0.5 * self.max_brake_torque * (1.0 - self.brake_front_share)
        return (front, front, rear, rear)

    def drive_force_available(self, speed: float) -> float:
        """Maximum total tractive force (N) at ``speed`` (force then power limited)."""
        return min(self.max_drive_force, self.max_power / max(abs(speed), 1.0))

    def resistance_force(self, speed: float) -> float:
        """Rolling plus aerodynamic resistance (N, opposing motion) at ``speed``."""
        v = abs(speed)
        return (
            self.rolling_resistance * self.mass * GRAVITY
            + 0.5 * self.air_density * self.drag_area * v * v
        )


def sedan(**changes: object) -> VehicleParams:
    """The measured passenger car: 1600 kg, RWD 5 kN / 100 kW, 6 kN·m brakes."""
    return VehicleParams(**changes)  # type: ignore[arg-type]


def hgv(**changes: object) -> VehicleParams:
    """A rigid heavy goods vehicle: 12 t, RWD 20 kN / 250 kW, 60 kN·m brakes (50/50)."""
    base: dict[str, object] = dict(
        model="hgv",
        category="truck",
        length=12.0,
        width=2.5,
        height=3.6,
        ground_clearance=0.3,
        front_overhang=1.5,
        mass=12000.0,
        wheel_mass=100.0,
        knuckle_mass=25.0,
        inertia=(10000.0, 60000.0, 60000.0),
        lf=1.8,
        lr=3.7,
        track=2.0,
        wheel_radius=0.5,
        h_cog=1.2,
        max_drive_force=20000.0,
        max_power=250e3,
        max_brake_torque=60000.0,
        brake_front_share=0.5,
        max_steer=0.55,
        steer_rate=0.6,
        steer_kp=40000.0,
        steer_damping=400.0,
        steer_armature=16.0,
        drag_area=6.0,
        rolling_resistance=0.008,
        max_speed=90.0 / 3.6,
        hitch_reach=0.25,
        hitch_height=0.9,
    )
    base.update(changes)
    return VehicleParams(**base)  # type: ignore[arg-type]


@dataclass(frozen=True, slots=True)
class PedestrianParams:
    """A kinematic pedestrian: a capsule moved along its commanded velocity."""

    model: str = "pedestrian"
    category: str = "person"
    length: float = 0.6  # bounding box (x, y), as the checker assumes
    width: float = 0.6
    height: float = 1.8
    radius: float = 0.25  # capsule radius
    max_speed: float = 3.0


@dataclass(frozen=True, slots=True)
class ObstacleParams:
    """A static box on the road (a stopped object, a barrier, debris)."""

    model: str = "obstacle"
    category: str = "obstacle"
    length: float = 1.0
    width: float = 1.0
    height: float = 1.0


# ---------------------------------------------------------------------- MJCF


def vehicle_body_xml(
    prefix: str, p: VehicleParams, x: float, y: float, yaw: float, collide: bool = False
) -> str:
    """The ``<body>`` subtree of one vehicle, its chassis frame at (x, y, h_cog).

    ``collide`` gives the chassis box physical contacts with other chassis and
    obstacles; without it the box is only used for collision events.
    """
    bits = 2 if collide else 0
    chassis_half = (0.5 * p.length, 0.5 * p.width, 0.5 * (p.height - p.ground_clearance))
    chassis_z = 0.5 * (p.height + p.ground_clearance) - p.h_cog
    loads = p.static_wheel_loads
    steered = (True, True, False, False)
    corners = (
        (p.front_axle_x, 0.5 * p.track),
        (p.front_axle_x, -0.5 * p.track),
        (p.rear_axle_x, 0.5 * p.track),
        (p.rear_axle_x, -0.5 * p.track),
    )
    lines = [
        f'<body name="{prefix}" pos="{vec(x, y, p.h_cog)}" quat="{vec(*yaw_quat(yaw))}">',
        f'  <freejoint name="{prefix}_root"/>',
        f'  <inertial pos="{vec(p.cog_x, 0, 0)}" mass="{num(p.chassis_mass)}" '
        f'diaginertia="{vec(*p.inertia)}"/>',
        f'  <geom name="{prefix}_chassis" type="box" size="{vec(*chassis_half)}" '
        f'pos="{vec(0, 0, chassis_z)}" contype="{bits}" conaffinity="{bits}" condim="3" '
        f'group="1" mass="0"/>',
    ]
    if p.receiver_x is not None:
        lines.append(
            f'  <site name="{prefix}_receiver" '
            f'pos="{vec(p.receiver_x, 0, p.hitch_height - p.h_cog)}"/>'
        )
    for wheel, (cx, cy), steer, load in zip(WHEELS, corners, steered, loads, strict=True):
        hinge = SteerHinge(p.max_steer, p.steer_damping, p.steer_armature) if steer else None
        lines += corner_xml(f"{prefix}_{wheel}", p, cx, cy, load, hinge)
    lines.append("</body>")
    return "\n".join(lines)


def vehicle_actuator_xml(prefix: str, p: VehicleParams) -> str:
    """The ``<actuator>`` entries of one vehicle: steer positions, wheel motors."""
    lines = []
    for wheel in WHEELS[:2]:
        name = f"{prefix}_{wheel}"
        lines.append(
            f'<position name="{name}_steer" joint="{name}_steer" kp="{num(p.steer_kp)}" '
            f'ctrlrange="{vec(-p.max_steer, p.max_steer)}"/>'
        )
    limit = p.max_drive_force * p.wheel_radius
    for wheel, driven in zip(WHEELS, p.driven, strict=True):
        if driven:
            name = f"{prefix}_{wheel}"
            lines.append(
                f'<motor name="{name}_drive" joint="{name}_spin" gear="1" '
                f'ctrlrange="{vec(-limit, limit)}"/>'
            )
    return "\n".join(lines)


def pedestrian_xml(prefix: str, p: PedestrianParams, x: float, y: float, yaw: float) -> str:
    """A mocap body with a capsule that collides with nothing (events only)."""
    half = max(0.5 * p.height - p.radius, 0.01)
    return (
        f'<body name="{prefix}" mocap="true" pos="{vec(x, y, 0.5 * p.height)}" '
        f'quat="{vec(*yaw_quat(yaw))}">\n'
        f'  <geom name="{prefix}_body" type="capsule" size="{vec(p.radius, half)}" '
        f'contype="0" conaffinity="0" group="1"/>\n'
        "</body>"
    )


def obstacle_xml(
    prefix: str, p: ObstacleParams, x: float, y: float, yaw: float, collide: bool = False
) -> str:
    """A static box; with ``collide`` it has physical contacts with chassis."""
    bits = 2 if collide else 0
    return (
        f'<body name="{prefix}" pos="{vec(x, y, 0.5 * p.height)}" '
        f'quat="{vec(*yaw_quat(yaw))}">\n'
        f'  <geom name="{prefix}_box" type="box" '
        f'size="{vec(0.5 * p.length, 0.5 * p.width, 0.5 * p.height)}" '
        f'contype="{bits}" conaffinity="{bits}" group="1"/>\n'
        "</body>"
    )
