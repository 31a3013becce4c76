"""The simulation world under the runner: road, vehicles, actuators, controllers.

Modules, each one idea:

* ``vehicle``, ``trailer``: actor parameters (sedan, HGV, pedestrian, obstacle,
  trailer) -> MJCF, with ``mjcf`` the MJCF text they share;
* ``state``: actor specs, inputs, weather and the actors' states;
* ``assembly``: the world's MJCF from its actors;
* ``actuators``: the ECU layer (rate limits, ABS, TCS, Ackermann);
* ``vehicle_bank``, ``trailer_bank``, ``walker_bank``, ``obstacle_bank``: one bank
  per body kind, owning its model indices, inputs and read-out (``bank``: what they
  all have);
* ``free_body``, ``locating``, ``divergence``: free-body read-out and placing, road
  positions, MuJoCo's divergence warnings;
* ``world``: the MuJoCo world, stepped in fixed control steps, orchestrating the banks;
* ``events``: collisions and road departures from the actors' bounding boxes;
* ``controllers``, ``tracking``: speed PID with rate profiles, Stanley lateral control;
* ``sky``: sun and moon positions.

The one loop that ticks them with a scenario is ``osc2runner.execution.loop``.

The road networks (built-in straight roads and OpenDRIVE maps) live in
:mod:`osc2check.world`, shared with the checker.
"""

from __future__ import annotations

import platform

import mujoco
import numpy as np

from osc2runner.sim.controllers import (
    LateralPath,
    RateProfile,
    SpeedController,
    StanleyController,
    VehicleController,
)
from osc2runner.sim.events import Event
from osc2runner.sim.vehicle import ObstacleParams, PedestrianParams, VehicleParams, hgv, sedan
from osc2runner.sim.world import (
    ActorSpec,
    ActorState,
    PedestrianInput,
    VehicleInput,
    Weather,
    World,
)

__all__ = [
    "ActorSpec",
    "ActorState",
    "Event",
    "LateralPath",
    "ObstacleParams",
    "PedestrianInput",
    "PedestrianParams",
    "RateProfile",
    "SpeedController",
    "StanleyController",
    "VehicleController",
    "VehicleInput",
    "VehicleParams",
    "Weather",
    "World",
    "hgv",
    "sedan",
    "versions",
]


def versions() -> dict[str, str]:
    """Versions that determine simulation results, for run metadata.

    Bit-identical replays are only promised for the same MuJoCo version on the
    same platform (MuJoCo's own reproducibility guarantee).
    """
    return {
        "mujoco": mujoco.__version__,
        "numpy": np.__version__,
        "python": platform.python_version(),
        "platform": f"{platform.system()}-{platform.machine()}",
    }
