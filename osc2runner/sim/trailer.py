"""Trailers: a towed body, its hitch to a tow vehicle, and what the world does with them.

A trailer is a body of its own (a chassis on a free joint, its catalogue row's
box and mass) with one axle (group) of two wheels: knuckles on suspension slide
joints and wheels on spin hinges with sphere tires, as the vehicles' rear
wheels (``sim/vehicle.py``), but neither driven nor steered. Its coupler is a
site at the front (on a drawbar ahead of the box for a central-axle trailer);
below it a front support (the jockey wheel) stands a few centimetres above the
ground while the trailer is hitched and carries its nose when it is not.

Hitching is a MuJoCo ``connect`` equality (a ball joint) between the tow
vehicle's receiver site and the trailer's coupler site: every (vehicle,
trailer) pair has one, inactive until :meth:`World.connect
<osc2runner.sim.world.World.connect>` switches it on. The ball carries the
trailer's nose load into the tow vehicle's rear suspension and its inertia
into the tow vehicle's acceleration, braking and cornering: the tow vehicle
feels its load through the physics, not through a model of it.

Brakes: a braked trailer (heavier than the catalogue's unbraked limit) brakes
with its tow vehicle's applied brake, as air and overrun brakes do, each wheel
capped by ABS at ``0.9 * mu * N * r`` like the vehicles'; once disconnected its
brakes are applied (the parking/breakaway brake). An unbraked trailer only has
rolling resistance. Aerodynamic drag acts on its chassis.

:class:`~osc2runner.sim.trailer_bank.TrailerBank` keeps the trailers' model
indices and does, vectorised over the trailers, what the world does each tick:
brakes, drag, read-out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from osc2runner.sim.mjcf import GRAVITY, corner_xml, num, vec, yaw_quat

__all__ = [
    "TRAILER_WHEELS",
    "TrailerParams",
    "articulation",
    "hitch_equality_xml",
    "trailer_body_xml",
]

#: the trailer's wheels, left and right of its axle (group)
TRAILER_WHEELS: tuple[str, str] = ("l", "r")

#: the front support's (jockey wheel's) gap above the ground while hitched (m), its radius,
#: and its friction (a caster wheel rolls in any direction)
SUPPORT_CLEARANCE = 0.06
SUPPORT_RADIUS = 0.1
SUPPORT_FRICTION = 0.05

#: the hitch constraint's time constant (s): stiff, at the 2 ms physics step's safe limit
HITCH_TIMECONST = 0.004


@dataclass(frozen=True, slots=True)
class TrailerParams:
    """A central-axle trailer (lengths in m from the centre of its box, + forward; kg).

    ``coupler`` is the coupler's position along the trailer, ``coupler_height`` its
    height; ``axle`` the axle's position; ``cog`` the centre of gravity's, ahead of the
    axle so that the coupler carries a share of the weight (the nose load).
    """

    model: str = "trailer.caravan"
    category: str = "trailer"
    length: float = 6.5
    width: float = 2.3
    height: float = 2.6
    ground_clearance: float = 0.3
    coupler: float = 4.45
    coupler_height: float = 0.45
    axle: float = -0.75
    cog: float = -0.49
    h_cog: float = 1.0
    mass: float = 1400.0  # total, wheels and knuckles included
    wheel_mass: float = 15.0
    knuckle_mass: float = 5.0
    inertia: tuple[float, float, float] = (1000.0, 4500.0, 4800.0)  # chassis, about its CoG
    track: float = 2.0
    wheel_radius: float = 0.33
    max_brake_torque: float = 0.0  # all wheels together; 0: unbraked
    abs_margin: float = 0.9
    rolling_resistance: float = 0.010
    drag_area: float = 1.8  # Cd * A in m^2
    air_density: float = 1.2
    susp_frequency: float = 1.6
    susp_damping_ratio: float = 0.35
    susp_travel: float = 0.2
    spin_damping: float = 0.02
    max_speed: float = 100.0 / 3.6

    def __post_init__(self) -> None:
        if not self.axle < self.cog < self.coupler:
            raise ValueError(
                "a central-axle trailer has its centre of gravity between its axle and its "
                f"coupler (axle {self.axle}, CoG {self.cog}, coupler {self.coupler})"
            )

    @property
    def wheelbase(self) -> float:
        """Coupler to axle (m)."""
        return self.coupler - self.axle

    @property
    def braked(self) -> bool:
        return self.max_brake_torque > 0.0

    @property
    def chassis_mass(self) -> float:
        return self.mass - 2.0 * (self.wheel_mass + self.knuckle_mass)

    @property
    def nose_load(self) -> float:
        """Vertical load on the coupler at rest, level (N)."""
        return self.mass * GRAVITY * (self.cog - self.axle) / self.wheelbase

    @property
    def static_wheel_load(self) -> float:
        """Normal load per wheel at rest, hitched and level (N)."""
        return 0.5 * (self.mass * GRAVITY - self.nose_load)

    def resistance_force(self, speed: float) -> float:
        """Rolling plus aerodynamic resistance (N, opposing motion) at ``speed``."""
        v = abs(speed)
        return (
            self.rolling_resistance * self.mass * GRAVITY
            + 0.5 * self.air_density * self.drag_area * v * v
        )


def trailer_body_xml(
    prefix: str, p: TrailerParams, x: float, y: float, yaw: float, collide: bool = False
) -> str:
    """The ``<body>`` subtree of one trailer, its chassis frame at (x, y, h_cog)."""
    bits = 2 if collide else 0
    chassis_half = (0.5 * p.length, 0.5 * p.width, 0.5 * (p.height - p.ground_clearance))
    chassis_z = 0.5 * (p.height + p.ground_clearance) - p.h_cog
    load = p.static_wheel_load
    support_z = SUPPORT_CLEARANCE + SUPPORT_RADIUS - p.h_cog
    lines = [
        f'<body name="{prefix}" pos="{vec(x, y, p.h_cog)}" quat="{vec(*yaw_quat(yaw))}">',
        f'  <freejoint name="{prefix}_root"/>',
        f'  <inertial pos="{vec(p.cog, 0, 0)}" mass="{num(p.chassis_mass)}" '
        f'diaginertia="{vec(*p.inertia)}"/>',
        f'  <geom name="{prefix}_chassis" type="box" size="{vec(*chassis_half)}" '
        f'pos="{vec(0, 0, chassis_z)}" contype="{bits}" conaffinity="{bits}" condim="3" '
        f'group="1" mass="0"/>',
        f'  <site name="{prefix}_coupler" pos="{vec(p.coupler, 0, p.coupler_height - p.h_cog)}"/>',
        f'  <geom name="{prefix}_support" type="sphere" size="{num(SUPPORT_RADIUS)}" '
        f'pos="{vec(p.coupler - 0.3, 0, support_z)}" condim="3" priority="1" contype="1" '
        f'conaffinity="0" friction="{num(SUPPORT_FRICTION)} 0.005 0.0001" group="2" mass="0"/>',
    ]
    for wheel, side in zip(TRAILER_WHEELS, (1.0, -1.0), strict=True):
        lines += corner_xml(f"{prefix}_{wheel}", p, p.axle, side * 0.5 * p.track, load)
    lines.append("</body>")
    return "\n".join(lines)


def hitch_equality_xml(tow: str, trailer: str, active: bool) -> str:
    """The ball joint between a tow vehicle's receiver and a trailer's coupler (by prefix)."""
    return (
        f'<connect name="{tow}_tows_{trailer}" site1="{tow}_receiver" '
        f'site2="{trailer}_coupler" active="{str(active).lower()}" '
        f'solref="{num(HITCH_TIMECONST)} 1"/>'
    )


def articulation(tow_yaw: float, trailer_yaw: float) -> float:
    """The articulation angle: the tow vehicle's heading less the trailer's, in (-pi, pi]."""
    angle = math.remainder(tow_yaw - trailer_yaw, 2.0 * math.pi)
    return math.pi if angle == -math.pi else angle
