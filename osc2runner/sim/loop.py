"""A fixed-step driver: controllers and world advanced together, one control tick at a time.

The scenario runner's own loop ticks a behaviour tree between the controller
updates; this one is the minimal version used by tests and benchmarks.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

from osc2runner.sim.controllers import VehicleController
from osc2runner.sim.world import Event, World

__all__ = ["ControlLoop"]


class ControlLoop:
    """Steps every controller with its actor's state, then the world.

    Parameters:
        world: the world to drive.
        controllers: one controller per controlled vehicle, by actor name.
    """

    def __init__(self, world: World, controllers: Mapping[str, VehicleController]) -> None:
        self.world = world
        self.controllers = dict(controllers)

    def tick(self) -> list[Event]:
        """One control step; returns the events it produced."""
        world = self.world
        inputs = {name: c.step(world.state(name)) for name, c in self.controllers.items()}
        return world.step_control(inputs)

    def run(self, seconds: float, until: Callable[[World], bool] | None = None) -> int:
        """Tick for ``seconds`` of simulated time, or until ``until(world)`` holds.

        Returns the number of ticks done.
        """
        ticks = round(seconds / self.world.dt_control)
        for n in range(ticks):
            self.tick()
            if until is not None and until(self.world):
                return n + 1
        return ticks
