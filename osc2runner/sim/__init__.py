"""The simulation world under the runner: road, vehicles, actuators, controllers.

Modules, each one idea:

* ``vehicle``: actor parameters (sedan, HGV, pedestrian, obstacle) -> MJCF;
* ``actuators``: the ECU layer (rate limits, ABS, TCS, Ackermann);
* ``world``: the MuJoCo world, stepped in fixed control steps;
* ``events``: collisions and road departures from the actors' bounding boxes;
* ``controllers``: speed PID with rate profiles, Stanley lateral control.

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
