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
* trailers (rows of ``trailer`` construction): a towed body
  (``sim/trailer.py``) with the row's box, mass, coupler and axle; its centre of
  gravity ahead of the axle by :data:`NOSE_LOAD_SHARE` of the wheelbase (the
  coupler carries that share of its weight), its height
  :data:`TRAILER_COG_HEIGHT` of the box's; brakes when it is heavier than the
  catalogue's unbraked limit;
* persons and animals: kinematic walkers with the row's box and top speed;
* stationary objects: static boxes.
"""

from __future__ import annotations

from dataclasses import replace
from fractions import Fraction

from osc2check.world.catalogue import UNBRAKED_TRAILER_MASS, ActorRow, receiver
from osc2runner.sim.trailer import TrailerParams
from osc2runner.sim.vehicle import GRAVITY, ObstacleParams, PedestrianParams, VehicleParams, hgv

__all__ = ["ActorParams", "body_params", "trailer_params", "vehicle_params"]

ActorParams = VehicleParams | PedestrianParams | ObstacleParams | TrailerParams

_HEAVY = ("truck", "bus", "trailer")
#: a trailer's nose load: the share of its weight its coupler carries (caravan makers ask
#: for 4-7 %; central-axle truck trailers up to 10 %)
NOSE_LOAD_SHARE = 0.05
#: a trailer's centre of gravity, as a share of its height
TRAILER_COG_HEIGHT = 0.4
#: a trailer's drag area per square metre of its front (it runs in its tow vehicle's wake)
TRAILER_DRAG = 0.3


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
    if row.is_trailer:
        return trailer_params(row, length, width)
    return vehicle_params(row, length, width)


def trailer_params(row: ActorRow, length: float, width: float) -> TrailerParams:
    """A central-axle trailer with the row's box, mass, coupler and axle (scaled to
    ``length``), braked when it is heavier than the unbraked limit."""
    scale = length / float(row.length)
    height = float(row.height)
    mass = float(row.mass)
    front = 0.5 * length
    coupler = front - float(row.hitch) * scale
    axle = front - float(row.front_overhang) * scale
    heavy = mass > 3500.0
    radius = 0.5 if heavy else 0.33
    wheel_mass = 100.0 if heavy else 15.0
    h_cog = TRAILER_COG_HEIGHT * height
    inertia = tuple(
        mass * (a * a + b * b) / 12.0
        for a, b in ((width, height), (length, height), (length, width))
    )
    braked = mass > float(UNBRAKED_TRAILER_MASS)
    return TrailerParams(
        model=row.key,
        category=row.category,
        length=length,
        width=width,
        height=height,
        ground_clearance=min(0.3, 0.5 * h_cog),
        coupler=coupler,
        coupler_height=float(row.hitch_height),
        axle=axle,
        cog=axle + NOSE_LOAD_SHARE * (coupler - axle),
        h_cog=h_cog,
        mass=mass,
        wheel_mass=wheel_mass,
        knuckle_mass=wheel_mass / 4.0,
        inertia=(inertia[0], inertia[1], inertia[2]),
        track=max(0.4 * width, width - 0.3),
        wheel_radius=radius,
        max_brake_torque=mass * float(row.max_deceleration) * radius * 1.15 if braked else 0.0,
        drag_area=TRAILER_DRAG * width * height,
        max_speed=float(row.max_speed),
    )


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
    hitch = receiver(row, Fraction(length))
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
        hitch_reach=None if hitch is None else float(hitch.behind_front) - length,
        hitch_height=template.hitch_height if hitch is None else float(hitch.height),
    )


def _box_inertia(
    mass: float, length: float, width: float, height: float, template: VehicleParams
) -> tuple[float, float, float]:
    """Roll, pitch and yaw inertia: the template's, scaled as a box of this size and mass."""

    def box(m: float, l_: float, w: float, h: float) -> tuple[float, float, float]:
        return (m * (w * w + h * h) / 12, m * (l_ * l_ + h * h) / 12, m * (l_ * l_ + w * w) / 12)

    ours = box(mass, length, width, height)
    theirs = box(template.mass, template.length, template.width, template.height)
    roll, pitch, yaw = (t * o / b for t, o, b in zip(template.inertia, ours, theirs, strict=True))
    # every rigid body's principal moments meet the triangle inequality; the template's
    # ratios scaled to a much longer body (a 30 m tram from a 12 m bus) can miss it
    yaw = min(yaw, roll + pitch)
    pitch = min(pitch, roll + yaw)
    return roll, pitch, yaw
