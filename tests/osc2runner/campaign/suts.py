"""Systems under test for the campaign tests (loaded by path: ``suts.py:Class``)."""

from __future__ import annotations

import os
import time
from pathlib import Path

from osc2runner.sut import Command, Demand, Observation, SutInfo


class PassThrough:
    """Applies what the scenario's driver model would: the run is the run without a SUT."""

    def reset(self, info: SutInfo) -> None:
        self.info = info

    def step(self, obs: Observation) -> Command:
        return obs.driver


class Decelerate:
    """Brakes at 3 m/s² (a Demand) from the first tick, steering as the driver."""

    decel = 3.0

    def reset(self, info: SutInfo) -> None:
        pass

    def step(self, obs: Observation) -> Demand:
        return Demand(-self.decel if obs.ego.speed > 0.5 else 0.0)


class Raises:
    """Raises at tick 5."""

    def reset(self, info: SutInfo) -> None:
        pass

    def step(self, obs: Observation) -> Command:
        if obs.tick >= 5:
            raise ValueError("sensor failure")
        return obs.driver


class CrashOnSeed:
    """Kills its process outright at the start of seed 2's run (a crash in native code)."""

    def reset(self, info: SutInfo) -> None:
        self.crash = info.seed == 2

    def step(self, obs: Observation) -> Command:
        if self.crash:
            os._exit(3)
        return obs.driver


class StuckOnSeed:
    """Seed 1's run: from its first tick on, touches ``stuck`` beside this file and takes
    0.5 s of wall clock per tick (a SUT too slow for any limit; 30 s for a 3 s scenario if
    nothing stops it). The other seeds' runs are the driver's."""

    def reset(self, info: SutInfo) -> None:
        self.stuck = info.seed == 1

    def step(self, obs: Observation) -> Command:
        if self.stuck:
            Path(__file__).with_name("stuck").touch()
            time.sleep(0.5)
        return obs.driver


class Slow:
    """0.02 s of wall clock per tick in every run (a campaign long enough to interrupt)."""

    def reset(self, info: SutInfo) -> None:
        pass

    def step(self, obs: Observation) -> Command:
        time.sleep(0.02)
        return obs.driver
