"""The SUT's seat in the loop: :class:`SutDriver` stands where the actor's controller was.

The scenario's behaviours keep talking to the actor's own
:class:`~osc2runner.sim.VehicleController` (they set its speed target and
lateral path, and ask whether they are reached): that controller is the
*driver model* that turns the scenario's intent into inputs. Each tick the
:class:`SutDriver` steps it (so its state follows the car), builds the
:class:`~osc2runner.sut.Observation` from the tick's states, asks the SUT, and
returns the SUT's inputs instead of the driver model's. ``speed`` and
``lateral`` are the driver model's, so behaviours and telemetry see no
difference. When the SUT's inputs depart from the driver model's (by more than
:data:`INTERVENTION` in a pedal or the steering) it *intervenes*, and when they
agree again it hands back: both go to the event log (kind ``sut``), so plots and
reports can show when the system acted.

What the SUT does wrong is its own outcome, not a bug of the runner: whatever
its construction, ``reset`` or ``step`` raises (``SystemExit`` and
``KeyboardInterrupt`` included: a SUT does not end the run, let alone the
command), a call that runs past its wall-clock budget, or an answer that is not
a finite :class:`Command` or :class:`Demand` raises :class:`SutFault`, which
becomes the outcome ``error`` naming the SUT and where (:func:`call_sut`). Only
a genuine signal passes through it (it stops the run).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any

from osc2check.world.network import RoadNetwork
from osc2check.world.tracking import PathCursor
from osc2runner.execution.signals import SignalInterrupt, StepTimeout, foreign_code, genuine
from osc2runner.sim import ActorState, VehicleController, VehicleInput
from osc2runner.sim.vehicle import GRAVITY, VehicleParams
from osc2runner.sut import (
    ActorView,
    Command,
    Demand,
    Intent,
    Observation,
    RoadAhead,
    SutInfo,
    SystemUnderTest,
)

if TYPE_CHECKING:
    from osc2runner.execution.context import EventKind

__all__ = [
    "INTERVENTION",
    "PATH_SPACING",
    "PATH_POINTS",
    "SutDriver",
    "SutFault",
    "call_sut",
    "sut_info",
]

PATH_SPACING = 5.0  # m between the points of RoadAhead.path
PATH_POINTS = 11  # 0 to 50 m ahead
INTERVENTION = 0.02  # a pedal or steering difference from the driver model that intervenes

#: what the event log is told: ``log(kind, name, detail, actors)``
Log = Callable[["EventKind", str, str, tuple[str, ...]], None]


class SutFault(Exception):
    """The system under test failed (raised, ran past its budget, or answered something
    that is not an input)."""


def call_sut(who: str, what: str, budget: float | None, fn: Callable[..., Any], *args: Any) -> Any:
    """``fn(*args)``, code of the SUT called ``who`` doing ``what`` (``step at tick 5``),
    as foreign code with ``budget`` wall-clock seconds (``signals.foreign_code``); any
    way it fails is a :class:`SutFault` saying so."""
    seat = f"the system under test ({who})"
    late = SutFault(f"{seat} did not return from {what} within {budget:g} s")
    try:
        with foreign_code(budget, f"{seat} in {what}") as expired:
            answer = fn(*args)
    except SignalInterrupt as exc:
        if genuine(exc):
            raise
        raise SutFault(f"{seat} raised KeyboardInterrupt in {what}") from None
    except StepTimeout:
        raise late from None
    except BaseException as exc:
        detail = f": {exc}" if str(exc) else ""
        raise SutFault(f"{seat} raised {type(exc).__name__}{detail} in {what}") from exc
    if expired[0]:  # it caught the timeout and came back late all the same
        raise late
    return answer


def sut_info(name: str, params: VehicleParams, dt: float, seed: int, scenario: str) -> SutInfo:
    """What the SUT is told about its vehicle before a run."""
    return SutInfo(
        actor=name,
        length=params.length,
        width=params.width,
        wheelbase=params.wheelbase,
        mass=params.mass,
        max_steer=params.max_steer,
        max_accel=params.max_drive_force / params.mass,
        max_decel=min(params.max_brake_torque / params.wheel_radius / params.mass, GRAVITY),
        max_speed=params.max_speed,
        dt=dt,
        seed=seed,
        scenario=scenario,
    )


def _view(state: ActorState, ego: ActorView | None = None) -> ActorView:
    """``state`` in the world frame and, when ``ego`` (the SUT's own view) is given, seen
    from the SUT."""
    c, s = math.cos(state.yaw), math.sin(state.yaw)
    vx = state.speed * c - state.lateral_speed * s
    vy = state.speed * s + state.lateral_speed * c
    if ego is None:
        return ActorView(
            state.name, state.kind, state.x, state.y, state.yaw, state.speed, state.accel,
            vx, vy, state.length, state.width, state.lane, state.s, state.t,
        )  # fmt: skip
    ec, es = math.cos(ego.yaw), math.sin(ego.yaw)
    dx, dy = state.x - ego.x, state.y - ego.y
    rel_x, rel_y = dx * ec + dy * es, -dx * es + dy * ec
    dvx, dvy = vx - ego.vx, vy - ego.vy
    # the other's box projected on the SUT's axes (its half extents along them)
    rc, rs = abs(math.cos(state.yaw - ego.yaw)), abs(math.sin(state.yaw - ego.yaw))
    half_long = 0.5 * (state.length * rc + state.width * rs)
    half_lat = 0.5 * (state.length * rs + state.width * rc)
    return ActorView(
        state.name, state.kind, state.x, state.y, state.yaw, state.speed, state.accel,
        vx, vy, state.length, state.width, state.lane, state.s, state.t,
        rel_x=rel_x,
        rel_y=rel_y,
        rel_vx=dvx * ec + dvy * es,
        rel_vy=-dvx * es + dvy * ec,
        gap=abs(rel_x) - 0.5 * ego.length - half_long,
        lateral_gap=abs(rel_y) - 0.5 * ego.width - half_lat,
    )  # fmt: skip


def _pedals(inputs: VehicleInput) -> str:
    return f"throttle {inputs.throttle:.2f} brake {inputs.brake:.2f} steer {inputs.steer:.2f}"


def _finite(*values: float) -> bool:
    return all(isinstance(v, (int, float)) and math.isfinite(v) for v in values)


class SutDriver:
    """The controller of the SUT actor (see the module docstring).

    Parameters:
        name: the SUT actor.
        sut: the SUT instance (already ``reset``).
        inner: the actor's driver model; behaviours set its targets.
        network: the map.
        states: the run's states of this tick, by actor (read when stepping).
        log: where interventions are logged (the run context's ``record``).
    """

    def __init__(
        self,
        name: str,
        sut: SystemUnderTest,
        inner: VehicleController,
        network: RoadNetwork,
        states: Mapping[str, ActorState],
        log: Log | None = None,
        budget: float | None = None,
    ) -> None:
        self.name = name
        self.log = log
        self.intervening = False
        self.budget = budget
        self.sut = sut
        self.inner = inner
        self.network = network
        self.states = states
        self._cursor: PathCursor | None = None
        self._cursor_route: Any = None
        self.speed = inner.speed
        self.lateral = inner.lateral
        params = inner.speed.params
        self.params = params

    @property
    def path(self) -> Any:
        """The world path the driver model follows (``follow_path``...), set by behaviours."""
        return self.inner.path

    @path.setter
    def path(self, value: Any) -> None:
        self.inner.path = value

    def __getattr__(self, name: str) -> Any:
        # everything else behaviours ask of the actor's controller is the driver model's
        return getattr(self.inner, name)

    def observe(self, state: ActorState, driver: VehicleInput) -> Observation:
        """The observation of this tick."""
        ego = _view(state)
        others = tuple(_view(s, ego) for n, s in self.states.items() if n != self.name)
        return Observation(
            tick=state.tick,
            time=state.time,
            ego=ego,
            others=others,
            road=self._road(state),
            intent=self._intent(state),
            driver=Command(driver.throttle, driver.brake, driver.steer),
        )

    def _road(self, state: ActorState) -> RoadAhead:
        lateral = self.inner.lateral
        route, path = lateral.route, lateral.path
        points: list[tuple[float, float]] = []
        heading, curvature, to_end = state.yaw, 0.0, 0.0
        if route is not None:
            if self._cursor is None or self._cursor_route is not route:
                self._cursor, self._cursor_route = PathCursor(route), route
            here = self._cursor.locate(state.x, state.y)
            heading, curvature = here.heading, here.curvature
            to_end = max(route.length - here.distance, 0.0)
            for i in range(PATH_POINTS):
                d = here.distance + i * PATH_SPACING
                pose = route.pose_at(d)
                offset = path.at(d)[0] if path is not None else 0.0
                points.append(
                    (pose.x - offset * math.sin(pose.yaw), pose.y + offset * math.cos(pose.yaw))
                )
        ref = state.lane_ref
        width = math.nan
        if ref is not None:
            width = float(self.network.width(ref, state.s))
        return RoadAhead(
            road=state.road,
            lane=state.lane,
            s=state.s,
            t=state.t,
            lane_width=width,
            speed_limit=self.network.speed_limit,
            heading=heading,
            curvature=curvature,
            path=tuple(points),
            distance_to_end=to_end,
        )

    def _intent(self, state: ActorState) -> Intent:
        lateral = self.inner.lateral
        path = lateral.path
        if path is None:
            return Intent(self.inner.speed.target, None, False)
        changing = lateral.route is not None and not lateral.done(state) and path.d1 > path.d0
        return Intent(self.inner.speed.target, path.goal(path.d1)[0], changing)

    def step(self, state: ActorState) -> VehicleInput:
        """One tick: the driver model's inputs, the observation, the SUT's answer."""
        driver = self.inner.step(state)
        observation = self.observe(state, driver)
        who, what = type(self.sut).__name__, f"step at tick {state.tick}"
        answer = call_sut(who, what, self.budget, self.sut.step, observation)
        inputs = self.inputs(answer, state, driver)
        self._note(inputs, driver)
        return inputs

    def _note(self, inputs: VehicleInput, driver: VehicleInput) -> None:
        """Log when the SUT starts overriding the driver model, and when it hands back."""
        differs = (
            max(
                abs(inputs.throttle - driver.throttle),
                abs(inputs.brake - driver.brake),
                abs(inputs.steer - driver.steer),
            )
            > INTERVENTION
        )
        if differs == self.intervening:
            return
        self.intervening = differs
        if self.log is not None:
            name = "intervenes" if differs else "hands back"
            detail = f"{_pedals(inputs)} (driver model: {_pedals(driver)})"
            self.log("sut", name, detail, (self.name,))

    def inputs(
        self, answer: Command | Demand, state: ActorState, driver: VehicleInput
    ) -> VehicleInput:
        """The vehicle inputs for the SUT's answer (SutFault when it is not one)."""
        who = f"the system under test ({type(self.sut).__name__})"
        if isinstance(answer, Command):
            if not _finite(answer.throttle, answer.brake, answer.steer):
                raise SutFault(f"{who} returned a non-finite command at tick {state.tick}")
            return VehicleInput(
                min(max(answer.throttle, 0.0), 1.0),
                min(max(answer.brake, 0.0), 1.0),
                min(max(answer.steer, -1.0), 1.0),
            )
        if isinstance(answer, Demand):
            curvature = answer.curvature
            if not _finite(answer.acceleration) or (
                curvature is not None and not _finite(curvature)
            ):
                raise SutFault(f"{who} returned a non-finite demand at tick {state.tick}")
            throttle, brake = self.inner.speed.pedals_for(answer.acceleration, state.speed)
            if curvature is None:
                steer = driver.steer
            else:
                delta = math.atan(self.params.wheelbase * curvature)
                steer = min(max(delta / self.params.max_steer, -1.0), 1.0)
            return VehicleInput(throttle, brake, steer)
        raise SutFault(
            f"{who} returned {type(answer).__name__} from step at tick {state.tick}, "
            "not a Command or a Demand"
        )
