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

from typing import TYPE_CHECKING, Protocol, TypeGuard, runtime_checkable

if TYPE_CHECKING:
    from collections.abc import Sequence

    from osc2check.world.network import LaneRef
    from osc2check.world.paths import LanePath
    from osc2runner.sim import ActorState, PedestrianInput, RateProfile, VehicleInput
    from osc2runner.sim.controllers import LateralPath
    from osc2runner.sim.tracking import PathTracker, Polyline
    from osc2runner.sim.vehicle import VehicleParams

__all__ = [
    "Controller",
    "LateralControl",
    "LongitudinalControl",
    "VehicleControl",
    "VehicleLateralControl",
    "WalkerControl",
    "WalkerLateralControl",
    "is_vehicle",
    "is_walker",
]


class LongitudinalControl(Protocol):
    """An actor's speed: a target reached along a rate profile, or released; or an
    acceleration held within speed bounds."""

    #: the speed it drives towards, m/s (None: released); a behaviour that tracks a
    #: moving goal writes it each tick
    target: float | None

    @property
    def a_ref(self) -> float:
        """The acceleration of its reference now, m/s²."""

    def set_acceleration(
        self, accel: float, jerk: float = ..., bounds: tuple[float, float] = ...
    ) -> None:
        """Accelerate at ``accel`` (m/s², reached at ``jerk``) within the speed ``bounds``."""

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

    @property
    def route(self) -> LanePath | None:
        """The lane centre lines it follows (None: none, as a walker's)."""

    def hold(self, state: ActorState) -> None:
        """Keep the lane and offset ``state`` is at."""

    def keep_offset(self, offset: float) -> None:
        """Keep ``offset`` (m) from the centre of the lane followed."""

    def done(self, state: ActorState) -> bool:
        """Whether the lateral move asked for is complete at ``state``."""

    def keep_lane(
        self, lane: LaneRef | int, offset: float = 0.0, state: ActorState | None = None
    ) -> None:
        """Follow ``lane`` (a number counts from the right where ``state`` is) at
        ``offset`` m left of its centre."""

    def change_lane(
        self,
        state: ActorState,
        lane: LaneRef | int,
        *,
        offset: float = 0.0,
        duration: float | None = None,
    ) -> object:
        """Move from where ``state`` is to ``lane`` (plus ``offset``) in ``duration`` s."""

    def move_to(self, state: ActorState, offset: float, *, duration: float | None = None) -> object:
        """Move from where ``state`` is to ``offset`` m left of its lane's centre in
        ``duration`` s."""


class VehicleLateralControl(LateralControl, Protocol):
    """A vehicle's place across the road: along a route of lanes it can be given."""

    @property
    def path(self) -> LateralPath | None:
        """The offset from the lane centre it follows along the route (None: none)."""

    def set_route(self, towards: Sequence[str]) -> None:
        """Follow lanes through the roads ``towards`` (in order) from where it is."""


class WalkerLateralControl(LateralControl, Protocol):
    """A walker's place across the road: it heads for it, and can be let go of it."""

    def release(self) -> None:
        """No lateral target: the walker walks on in its heading."""


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


@runtime_checkable
class VehicleControl(Controller, Protocol):
    """The controller of a vehicle (or the SUT's seat around one): ``path`` is the tracker
    of a world path it steers along instead of its lane (``follow_path``...)."""

    params: VehicleParams
    path: PathTracker | None

    @property
    def lateral(self) -> VehicleLateralControl: ...


@runtime_checkable
class WalkerControl(Controller, Protocol):
    """The controller of a walker: a heading of its own (``yaw``; None: it heads for its
    lateral target) and a world ``path`` it walks along."""

    yaw: float | None
    path: Polyline | None

    @property
    def lateral(self) -> WalkerLateralControl: ...


# ``isinstance`` against a runtime-checkable Protocol looks up every member on each call
# (tens of µs); a controller's kind is its class's, so each class is tested once.
_kinds: dict[type, tuple[bool, bool]] = {}


def _kind(ctrl: object) -> tuple[bool, bool]:
    """Whether ``ctrl`` is a walker's controller, and whether a vehicle's."""
    found = _kinds.get(type(ctrl))
    if found is None:
        walker = isinstance(ctrl, WalkerControl)
        found = _kinds[type(ctrl)] = (walker, not walker and isinstance(ctrl, VehicleControl))
    return found


def is_walker(ctrl: object) -> TypeGuard[WalkerControl]:
    """Whether ``ctrl`` is a walker's controller (:class:`WalkerControl`)."""
    return _kind(ctrl)[0]


def is_vehicle(ctrl: object) -> TypeGuard[VehicleControl]:
    """Whether ``ctrl`` is a vehicle's controller (:class:`VehicleControl`), not a walker's."""
    return _kind(ctrl)[1]


if TYPE_CHECKING:
    from osc2runner.execution.drivers import PedestrianController
    from osc2runner.sim import VehicleController
    from osc2runner.sut.driver import SutDriver

    def _honoured(
        vehicle: VehicleController, seat: SutDriver, walker: PedestrianController
    ) -> tuple[VehicleControl, VehicleControl, WalkerControl]:
        """(mypy checks here that each kind of controller honours its Protocol.)"""
        return vehicle, seat, walker
