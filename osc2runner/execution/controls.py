"""What an actor's controller is to the rest of the runner: the seams behaviours, the
tick loop and the telemetry use, as Protocols (py_trees' ``Behaviour`` is to leaves what
these are to controllers).

Three kinds honour them: a vehicle's (:class:`osc2runner.sim.VehicleController`: a
speed PID and a Stanley lateral controller), a walker's
(:class:`~osc2runner.execution.drivers.PedestrianController`) and the system under
test's seat (:class:`~osc2runner.sut.driver.SutDriver`, around a vehicle's). mypy checks
each against them where the controllers are made (``drivers.controllers_for``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    from osc2runner.sim import ActorState, PedestrianInput, RateProfile, VehicleInput

__all__ = ["Controller", "LateralControl", "LongitudinalControl"]


class LongitudinalControl(Protocol):
    """An actor's speed: a target reached along a rate profile, or released."""

    def set_target(self, speed: float, profile: RateProfile | str = "none") -> None:
        """Drive towards ``speed`` (m/s), changing it as ``profile`` says."""

    def accel_reached(self, tolerance: float = 1e-6) -> bool:
        """Whether the acceleration asked for is reached."""

    def reached(self, state: ActorState, tolerance: float = ...) -> bool:
        """Whether ``state``'s speed is the target's, to ``tolerance``."""

    def release(self) -> None:
        """No target: the actor is let go (coasts, or stands)."""


class LateralControl(Protocol):
    """An actor's place across the road: a lane and an offset it holds or moves to."""

    @property
    def error(self) -> float:
        """The last lateral error, m (positive: left of the target)."""

    @property
    def path(self) -> object:
        """What it steers along (None: nothing, it is not controlled across the road)."""

    def hold(self, state: ActorState) -> None:
        """Keep the lane and offset ``state`` is at."""

    def keep_offset(self, offset: float) -> None:
        """Keep ``offset`` (m) from the centre of the lane followed."""

    def done(self, state: ActorState) -> bool:
        """Whether the lateral move asked for is complete at ``state``."""


class Controller(Protocol):
    """One actor's controller: stepped once per control tick for the world's inputs."""

    @property
    def speed(self) -> LongitudinalControl: ...

    @property
    def lateral(self) -> LateralControl: ...

    @property
    def path(self) -> object:
        """A world path followed (``follow_path``...), which steers instead of
        ``lateral``; None when there is none."""

    def step(self, state: ActorState) -> VehicleInput | PedestrianInput:
        """This tick's inputs from the actor's ``state``."""
