"""MJCF assembly: the world's one MuJoCo model from its road and its actors' bodies.

The road is a plane (tires collide with it, nothing else does); each actor is the
body its parameters make (``sim/vehicle.py``, ``sim/trailer.py``), named by its
prefix (``a0``, ``a1``, ... in world order; a kinematic vehicle has none); vehicles
add their actuators; every (tow vehicle, trailer) pair has a hitch equality, active
when the trailer starts towed by that vehicle.
"""

from __future__ import annotations

from collections.abc import Sequence

from osc2runner.sim.state import ActorSpec
from osc2runner.sim.trailer import TrailerParams, hitch_equality_xml, trailer_body_xml
from osc2runner.sim.vehicle import (
    PedestrianParams,
    VehicleParams,
    obstacle_xml,
    pedestrian_xml,
    vehicle_actuator_xml,
    vehicle_body_xml,
)

__all__ = ["model_xml", "prefix"]


def prefix(index: int) -> str:
    """The name of the body of the actor at ``index`` in world order (and of its parts'
    prefix)."""
    return f"a{index}"


def model_xml(
    specs: Sequence[ActorSpec],
    poses: Sequence[tuple[float, float, float]],
    hitches: Sequence[tuple[int, int, bool]],
    bounds: tuple[float, float, float, float],
    dt_physics: float,
    collide: bool,
) -> str:
    """The MJCF of a world.

    Parameters:
        specs: the actors, in world order.
        poses: each actor's body's initial world ``(x, y, yaw)``.
        hitches: ``(tow, trailer, active)`` by world index, one per pair that may hitch.
        bounds: the road network's ``(x0, x1, y0, y1)`` (the road plane is centred on it).
        dt_physics: the physics step (s).
        collide: give chassis and obstacles physical contacts.
    """
    bodies: list[str] = []
    actuators: list[str] = []
    for i, (spec, (x, y, yaw)) in enumerate(zip(specs, poses, strict=True)):
        name = prefix(i)
        p = spec.params
        if isinstance(p, VehicleParams):
            if spec.kinematic:  # no body: the kinematic model moves it
                continue
            bodies.append(vehicle_body_xml(name, p, x, y, yaw, collide=collide))
            actuators.append(vehicle_actuator_xml(name, p))
        elif isinstance(p, TrailerParams):
            bodies.append(trailer_body_xml(name, p, x, y, yaw, collide=collide))
        elif isinstance(p, PedestrianParams):
            bodies.append(pedestrian_xml(name, p, x, y, yaw))
        else:
            bodies.append(obstacle_xml(name, p, x, y, yaw, collide=collide))
    equalities = [
        hitch_equality_xml(prefix(tow), prefix(trailer), active=active)
        for tow, trailer, active in hitches
    ]
    x0, x1, y0, y1 = bounds
    return "\n".join(
        [
            '<mujoco model="osc2run">',
            '  <compiler angle="radian" autolimits="true"/>',
            f'  <option timestep="{dt_physics!r}" integrator="implicitfast" cone="elliptic">',
            # one Newton iteration per step: islands cost more bookkeeping than they save
            '    <flag island="disable"/>',
            "  </option>",
            "  <worldbody>",
            '    <geom name="road" type="plane" size="0 0 1" contype="0" conaffinity="1" '
            f'pos="{0.5 * (x0 + x1)!r} {0.5 * (y0 + y1)!r} 0" condim="3"/>',
            *bodies,
            "  </worldbody>",
            "  <actuator>",
            *actuators,
            "  </actuator>",
            "  <equality>",
            *equalities,
            "  </equality>",
            "</mujoco>",
        ]
    )
