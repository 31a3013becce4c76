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
    """Seed 1's run: from its sixth tick on, touches ``stuck`` beside this file and takes
    0.5 s of wall clock per tick (a SUT too slow for any limit; 30 s for a 3 s scenario if
    nothing stops it), so its run has ticks to write when it is stopped. The other seeds'
    runs are the driver's."""

    def reset(self, info: SutInfo) -> None:
        self.stuck = info.seed == 1
        self.ticks = 0

    def step(self, obs: Observation) -> Command:
        self.ticks += 1
        if self.stuck and self.ticks > 5:
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


# ---- systems under test that misbehave (tests/osc2runner/sut/test_sut_misbehaviour.py) ----------


def _marker(text: str) -> None:
    """A line on stderr a test waits for (the SUT is where the test wants it)."""
    import sys

    sys.stderr.write(f"sut: {text}\n")
    sys.stderr.flush()


class ExitsZero:
    """Calls ``sys.exit(0)`` in its first step: it must not make the command succeed."""

    def step(self, obs: Observation) -> Command:
        raise SystemExit(0)


class RaisesKeyboardInterrupt:
    """Raises KeyboardInterrupt in its first step: no signal came, the run was not stopped."""

    def step(self, obs: Observation) -> Command:
        raise KeyboardInterrupt


class OwnBaseException(BaseException):
    """An exception outside ``Exception``."""


class RaisesBaseException:
    def step(self, obs: Observation) -> Command:
        raise OwnBaseException("out of band")


class FakesASignal:
    """Raises the runner's own signal exception, though no signal came."""

    def step(self, obs: Observation) -> Command:
        from osc2runner.execution.signals import SignalInterrupt

        raise SignalInterrupt(2)


class FailsInInit:
    def __init__(self) -> None:
        raise RuntimeError("no licence")

    def step(self, obs: Observation) -> Command:
        return obs.driver


class FailsInReset:
    def reset(self, info: SutInfo) -> None:
        raise RuntimeError("calibration missing")

    def step(self, obs: Observation) -> Command:
        return obs.driver


class SleepsAtTick5:
    """Drives as the driver model, then sleeps for an hour in its step of tick 5."""

    def step(self, obs: Observation) -> Command:
        if obs.tick == 5:
            _marker("sleeping")
            time.sleep(3600)
        return obs.driver


class LoopsAtTick5:
    """Drives as the driver model, then spins forever in its step of tick 5."""

    def step(self, obs: Observation) -> Command:
        if obs.tick == 5:
            _marker("looping")
            while True:
                pass
        return obs.driver


class SwallowsAtTick5:
    """At tick 5, sleeps forever and swallows whatever is raised into it."""

    def step(self, obs: Observation) -> Command:
        if obs.tick == 5:
            _marker("swallowing")
            while True:
                try:
                    time.sleep(3600)
                except BaseException as exc:  # noqa: BLE001 - what a SUT must not be able to do
                    _marker(f"swallowed {type(exc).__name__}")
        return obs.driver


class CatchesTheTimeout:
    """Sleeps past its budget in its first step, catches what stops it, and answers late."""

    def step(self, obs: Observation) -> Command:
        try:
            time.sleep(3600)
        except BaseException:  # noqa: BLE001
            pass
        return obs.driver


class Chaotic:
    """A SUT whose every step is drawn from its seed (``PLAN``): it drives well, or it
    answers NaN, the wrong type, raises one thing or another, or sleeps past its budget.
    ``plan(seed)`` tells what it does at each tick, for the test to predict the outcome."""

    KINDS = ("drive", "drive", "drive", "drive", "demand", "nan", "type", "value_error",
             "system_exit", "keyboard", "base", "late")  # fmt: skip

    @staticmethod
    def plan(seed: int, ticks: int = 200) -> list[str]:
        import random

        rng = random.Random(seed)
        return [rng.choice(Chaotic.KINDS) for _ in range(ticks)]

    def reset(self, info: SutInfo) -> None:
        self.steps = Chaotic.plan(info.seed)

    def step(self, obs: Observation) -> Command | Demand:
        kind = self.steps[obs.tick]
        if kind == "demand":
            return Demand(0.5)
        if kind == "nan":
            return Command(float("nan"), 0.0, 0.0)
        if kind == "type":
            return "full throttle"  # type: ignore[return-value]
        if kind == "value_error":
            raise ValueError("sensor failure")
        if kind == "system_exit":
            raise SystemExit(0)
        if kind == "keyboard":
            raise KeyboardInterrupt
        if kind == "base":
            raise OwnBaseException("out of band")
        if kind == "late":
            time.sleep(3600)
        return obs.driver
