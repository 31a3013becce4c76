"""Catalogue rows -> the parameters of the bodies the world builds.

The checker placed each actor with a row of ``osc2check.world.catalogue`` and a
length and width (the row's, or the scenario's declared ``bounding_box``); the
witness records both. :func:`body_params` turns them into the simulation's
parameters, so the MuJoCo body has exactly the footprint the checker placed:

* vehicles (``car``, ``truck``, ``bus``, ``trailer``, ``two_wheeler``): the
  multibody car of ``sim/vehicle.py`` with the row's box, wheelbase, front
  overhang and mass; drive force from the row's acceleration limit, power from
  the template's power to weight (at least what its top speed takes), brake
  torque from its deceleration limit, the rest from the
  measured sedan (cars, two-wheelers) or heavy goods vehicle (the others).
  A two-wheeler is built as a narrow four-wheeled body with its centre of
  gravity kept low enough not to roll over (its footprint, mass and limits are
  the two-wheeler's; lean dynamics are not modelled);
* persons and animals: kinematic walkers with the row's box and top speed;
* stationary objects: static boxes.
"""

from __future__ import annotations

from dataclasses import replace

from osc2check.world.catalogue import ActorRow
from osc2runner.sim.vehicle import GRAVITY, ObstacleParams, PedestrianParams, VehicleParams, hgv

__all__ = ["ActorParams", "body_params"]

ActorParams = VehicleParams | PedestrianParams | ObstacleParams

_HEAVY = ("truck", "bus", "trailer")


def body_params(row: ActorRow, length: float, width: float) -> ActorParams:
    """The world parameters of an actor of ``row`` with this box (m)."""
    if row.body in ("person", "animal"):
        return PedestrianParams(
            model=row.key,
            category=row.category,
            length=length,
            width=width,
            height=float(row.height),
            radius=0.5 * min(length, width),
            max_speed=float(row.max_speed),
        )
    if row.body == "box":
        return ObstacleParams(
            model=row.key,
            category=row.category,
            length=length,
            width=width,
            height=float(row.height),
        )
    return vehicle_params(row, length, width)


def vehicle_params(row: ActorRow, length: float, width: float) -> VehicleParams:
    """A four-wheeled body with the row's proportions, scaled to ``length`` x ``width``."""
    template = hgv() if row.body in _HEAVY else VehicleParams()
    scale = length / float(row.length)
    height = float(row.height)
    wheelbase = float(row.wheelbase) * scale
    overhang = float(row.front_overhang) * scale
    front_share = template.lf / template.wheelbase  # CoG to front axle, share of the wheelbase
    mass = float(row.mass)
    track = max(0.4 * width, width - (template.width - template.track))
    h_cog = template.h_cog * height / template.height
    if row.body == "two_wheeler":
        h_cog = min(h_cog, track / 1.6)  # rolls over only beyond about 0.8 g
    radius = min(template.wheel_radius, 0.45 * h_cog + 0.2, 0.25 * wheelbase)
    drag_area = template.drag_area * (width * height) / (template.width * template.height)
    top = float(row.max_speed)
    resistance = template.rolling_resistance * mass * GRAVITY
    drive_force = mass * float(row.max_acceleration) + resistance
    # the template's power to weight (a governed top speed is reached with power to spare),
    # and at least what holding the top speed takes
    cruise = (resistance + 0.5 * template.air_density * drag_area * top * top) * top * 1.05
    power = max(template.max_power * mass / template.mass, cruise)
    inertia = _box_inertia(mass, length, width, height, template)
    unsprung = 4.0 * (template.wheel_mass + template.knuckle_mass)
    wheel_mass, knuckle_mass = template.wheel_mass, template.knuckle_mass
    if unsprung > 0.3 * mass:  # light vehicles: keep the chassis the heaviest part
        shrink = 0.3 * mass / unsprung
        wheel_mass, knuckle_mass = wheel_mass * shrink, knuckle_mass * shrink
    return replace(
        template,
        model=row.key,
        category=row.category,
        length=length,
        width=width,
        height=height,
        ground_clearance=min(template.ground_clearance, 0.5 * h_cog),
        front_overhang=overhang,
        mass=mass,
        wheel_mass=wheel_mass,
        knuckle_mass=knuckle_mass,
        inertia=inertia,
        lf=front_share * wheelbase,
        lr=(1.0 - front_share) * wheelbase,
        track=track,
        wheel_radius=radius,
        h_cog=h_cog,
        max_drive_force=drive_force,
        max_power=power,
        max_brake_torque=mass * float(row.max_deceleration) * radius * 1.15,
        drag_area=drag_area,
        max_speed=top,
    )


def _box_inertia(
    mass: float, length: float, width: float, height: float, template: VehicleParams
) -> tuple[float, float, float]:
    """Roll, pitch and yaw inertia: the template's, scaled as a box of this size and mass."""

    def box(m: float, l_: float, w: float, h: float) -> tuple[float, float, float]:
        return (m * (w * w + h * h) / 12, m * (l_ * l_ + h * h) / 12, m * (l_ * l_ + w * w) / 12)

    ours = box(mass, length, width, height)
    theirs = box(template.mass, template.length, template.width, template.height)
    return tuple(  # type: ignore[return-value]
        t * o / b for t, o, b in zip(template.inertia, ours, theirs, strict=True)
    )
