"""CARLA's world (``osc2toolkit.carla``, :mod:`osc2check.dialects.carla`) in the runner.

CARLA's path conditions are conditions on where the actors start: the checker's
placement met them (``osc2check.verify.placement``), so they have nothing left to
do in the run. ``set_position`` and ``follow_trajectory(input_file:)`` need
CARLA's world frame of its maps, which the built-in stand-ins do not have: the
capability table says so (``osc2check.capabilities``, A308), the runner refuses
them with that finding, and they are registered nowhere here.
"""

from __future__ import annotations

from osc2runner.behaviours.maps import realised

PathMinDrivingLanes = realised(
    "path_min_driving_lanes",
    "CARLA's; scenario member: the checker placed the actors on such a road",
    __name__,
)
PathOverJunction = realised(
    "path_over_junction",
    "CARLA's; scenario member: the checker placed the actors before a junction",
    __name__,
)
