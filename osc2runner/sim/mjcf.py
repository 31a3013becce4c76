"""MJCF text shared by the bodies: numbers, quaternions and the wheel corner.

Vehicles (``sim/vehicle.py``) and trailers (``sim/trailer.py``) both write
their wheels with :func:`corner_xml`; it reads only the fields of
:class:`CornerParams`, which both parameter classes have, so neither body
module imports the other.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

__all__ = ["GRAVITY", "CornerParams", "SteerHinge", "corner_xml", "num", "vec", "yaw_quat"]

GRAVITY = 9.81


def num(value: float) -> str:
    """A float as MJCF text, round-trippable."""
    return repr(float(value))


def vec(*values: float) -> str:
    """Floats as one space-separated MJCF attribute."""
    return " ".join(num(v) for v in values)


def yaw_quat(yaw: float) -> tuple[float, float, float, float]:
    """Unit quaternion (w, x, y, z) of a rotation by ``yaw`` about z."""
    return (math.cos(0.5 * yaw), 0.0, 0.0, math.sin(0.5 * yaw))


class CornerParams(Protocol):
    """What a wheel corner is built from (vehicles and trailers have these fields)."""

    @property
    def wheel_radius(self) -> float: ...
    @property
    def wheel_mass(self) -> float: ...
    @property
    def knuckle_mass(self) -> float: ...
    @property
    def h_cog(self) -> float: ...
    @property
    def susp_frequency(self) -> float: ...
    @property
    def susp_damping_ratio(self) -> float: ...
    @property
    def susp_travel(self) -> float: ...
    @property
    def spin_damping(self) -> float: ...


@dataclass(frozen=True, slots=True)
class SteerHinge:
    """A steered corner's hinge: its range (+- ``max_angle``, rad), damping and armature."""

    max_angle: float
    damping: float
    armature: float


def corner_xml(
    name: str,
    p: CornerParams,
    x: float,
    y: float,
    load: float,
    steer: SteerHinge | None = None,
) -> list[str]:
    """The MJCF lines of one wheel corner of a vehicle or trailer body (indented for it):
    a knuckle body on a suspension slide sprung for the corner's static ``load`` (N) at
    ``(x, y)`` of the chassis frame, a steering hinge when ``steer`` is given, and
    the wheel with its spin hinge and sphere tire."""
    r = p.wheel_radius
    i_spin = 0.5 * p.wheel_mass * r * r
    i_side = 0.25 * p.wheel_mass * r * r
    # sprung load of this corner: the wheel's static load minus unsprung masses
    sprung = load - (p.wheel_mass + p.knuckle_mass) * GRAVITY
    corner_mass = sprung / GRAVITY
    k = corner_mass * (2.0 * math.pi * p.susp_frequency) ** 2
    c = 2.0 * p.susp_damping_ratio * math.sqrt(k * corner_mass)
    lines = [
        f'  <body name="{name}_knuckle" pos="{vec(x, y, r - p.h_cog)}">',
        f'    <inertial pos="0 0 0" mass="{num(p.knuckle_mass)}" '
        f'diaginertia="{vec(0.05, 0.05, 0.05)}"/>',
        f'    <joint name="{name}_susp" type="slide" axis="0 0 1" stiffness="{num(k)}" '
        f'springref="{num(-sprung / k)}" damping="{num(c)}" armature="1" '
        f'range="{vec(-p.susp_travel, p.susp_travel)}"/>',
    ]
    if steer is not None:
        lines.append(
            f'    <joint name="{name}_steer" type="hinge" axis="0 0 1" '
            f'damping="{num(steer.damping)}" armature="{num(steer.armature)}" '
            f'range="{vec(-steer.max_angle, steer.max_angle)}"/>'
        )
    return lines + [
        f'    <body name="{name}_wheel">',
        f'      <inertial pos="0 0 0" mass="{num(p.wheel_mass)}" '
        f'diaginertia="{vec(i_side, i_spin, i_side)}"/>',
        f'      <joint name="{name}_spin" type="hinge" axis="0 1 0" '
        f'damping="{num(p.spin_damping)}"/>',
        f'      <geom name="{name}_tire" type="sphere" size="{num(r)}" condim="3" '
        f'priority="1" contype="1" conaffinity="0" friction="1 0.005 0.0001" '
        f'group="2" mass="0"/>',
        "    </body>",
        "  </body>",
    ]
