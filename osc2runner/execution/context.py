"""The RunContext: everything a behaviour reads while the tree is ticked.

One context per run. Behaviours receive it through ``tree.setup(context=ctx)``
and read only it: the simulated time and tick, each actor's state at this tick
(read once per tick, shared by every expression), the actors' controllers,
the world, the edge detectors (``rise``, ``fall``) that are evaluated at the
start of every tick while their context is active, whether or not a behaviour
asks in that tick, and the listeners of event occurrences (``sample``,
coverage), called at the moment an event occurs. What the compiler needs (the
model, the parameter values, the registry) is in
``compile.environment.CompileEnvironment``, not here.

State shared *between* behaviours lives on the py_trees blackboard only:
event occurrences under ``/osc2/events/<name>`` and scenario variables under
``/osc2/vars``. The blackboard is cleared for every run (:func:`fresh_blackboard`).

Nothing here reads the wall clock: time is ``tick * dt``.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import py_trees

from osc2check.syntax import ast
from osc2check.verify.schedule import PhasePlan, Schedule
from osc2check.verify.timeline import PhaseKey
from osc2check.world.network import RoadNetwork
from osc2runner.execution.controls import Controller
from osc2runner.execution.coverage import RunCoverage
from osc2runner.execution.tolerances import Tolerances
from osc2runner.instance.actors import Actor
from osc2runner.instance.roads import LaneNumbers
from osc2runner.options import DT_CONTROL
from osc2runner.sim.sky import Sky
from osc2runner.structs import Air, Clouds, Fog, Precipitation, Weather, Wind

if TYPE_CHECKING:
    from osc2runner.sim import ActorState, World

__all__ = [
    "EVENT_ROOT",
    "EdgeDetector",
    "EnvironmentChange",
    "EventKind",
    "ended_kind",
    "LogRecord",
    "Occurrence",
    "PeriodicDetector",
    "RunContext",
    "RunFault",
    "event_key",
    "fresh_blackboard",
    "initial_weather",
]

log = logging.getLogger(__name__)

EVENT_ROOT = "/osc2/events/"
VARIABLES_KEY = "/osc2/vars"


def event_key(name: str) -> str:
    """The blackboard key of an event's occurrences (dots are not allowed in keys)."""
    return EVENT_ROOT + name.replace(".", "__")


def fresh_blackboard() -> None:
    """Forget every key, value and client: each run (and each test) starts empty."""
    py_trees.blackboard.Blackboard.clear()


@dataclass(frozen=True, slots=True)
class Occurrence:
    """One occurrence of an event: when, and the arguments it was emitted with."""

    tick: int
    time: float
    args: dict[str, Any]


#: what a line of the event log (``events.csv``) records: the scenario's events
#: (``emit``; ``event``: a declared event that occurred; ``start``, ``end``, ``fail``:
#: a phase's, ``stop``: a phase stopped), what the world detected (``collision``,
#: ``off_road``), what the runner did (``choice``: a ``one_of``'s member; ``limit``:
#: a bound an action was held to; ``environment``, ``lights``, ``traffic_light``,
#: ``trailer``, ``sut``, ``coverage``, ``log``) and the ``outcome``
EventKind = Literal[
    "emit",
    "event",
    "start",
    "end",
    "fail",
    "stop",
    "choice",
    "collision",
    "off_road",
    "limit",
    "environment",
    "lights",
    "traffic_light",
    "trailer",
    "sut",
    "coverage",
    "log",
    "outcome",
]


def ended_kind(status: py_trees.common.Status) -> EventKind:
    """How a behaviour that terminates with ``status`` is logged: ``end`` (it succeeded),
    ``fail`` (it failed) or ``stop`` (it was stopped)."""
    if status == py_trees.common.Status.SUCCESS:
        return "end"
    if status == py_trees.common.Status.FAILURE:
        return "fail"
    return "stop"


@dataclass(frozen=True, slots=True)
class LogRecord:
    """One line of the run's event log."""

    tick: int
    time: float
    kind: EventKind
    name: str
    detail: str = ""
    actors: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class EnvironmentChange:
    """An environment action as it took effect: its tick and time, the action's name
    (``rain``, ``set_road_friction``, ...), the arguments it was given (SI values, enum
    members by name) and the road friction after it (what exports replay)."""

    tick: int
    time: float
    action: str
    values: dict[str, float | str]
    road_friction: float


def initial_weather() -> Weather:
    """The weather before any environment action: dry, clear, calm, no fog; the ISA
    standard atmosphere at sea level (15 °C, 1013.25 hPa), 50 % relative humidity."""
    return Weather(
        air=Air(temperature=288.15, pressure=101325.0, relative_humidity=0.5),
        rain=Precipitation(intensity=0.0),
        snow=Precipitation(intensity=0.0),
        wind=Wind(speed=0.0, direction=0.0),
        fog=Fog(visual_range=math.inf),
        clouds=Clouds(cloudiness=0),
    )


class RunFault(Exception):
    """The scenario itself went wrong while running (not a bug, not bad input seen before
    the run): a ``sample`` read before its event with no default, an external method that
    raised. The loop ends the run as a ``failure`` whose reason is the message, which
    names the place in the source."""

    def __init__(self, message: str, node: ast.Node | None = None) -> None:
        where = ""
        if node is not None:
            s = node.span
            where = f"{s.uri}:{s.line}:{s.column}: "
        super().__init__(where + message)
        self.node = node


class EdgeDetector:
    """``rise(b)`` / ``fall(b)``: true on the tick where ``b`` changes.

    A detector is evaluated only while its context is active (a watch on it has
    started and not stopped): at :meth:`activate`, which only records the value
    (there is no edge without a previous evaluation in the context), and then at
    the start of every tick, before the tree, by :meth:`RunContext.begin_tick`, so
    an edge is never missed whether or not a behaviour asks in that tick.
    """

    __slots__ = ("fn", "rising", "previous", "edge", "node", "active")

    def __init__(self, fn: Callable[[], Any], rising: bool, node: ast.Node | None = None) -> None:
        self.fn = fn
        self.rising = rising
        self.previous: bool | None = None
        self.edge = False
        self.node = node
        self.active = 0

    def activate(self) -> None:
        """The context starts: the value now is the first evaluation (no edge)."""
        self.active += 1
        self.previous = bool(self.fn())
        self.edge = False

    def deactivate(self) -> None:
        self.active = max(0, self.active - 1)
        if not self.active:
            self.edge = False
            self.previous = None

    def update(self) -> None:
        value = bool(self.fn())
        previous = self.previous
        if previous is None:
            self.edge = False
        elif self.rising:
            self.edge = value and not previous
        else:
            self.edge = previous and not value
        self.previous = value


class PeriodicDetector:
    """``every(period, offset: o)``: at ``c + o, c + o + period, ...`` where ``c`` is the
    time its context started (``o`` defaults to 0: the first occurrence is the start of
    the context). Occurrences are on the control grid: the first tick at or after each
    due time (a period that is not a multiple of the tick keeps its phase; it does not
    drift)."""

    __slots__ = ("period", "offset", "_next")

    def __init__(self, period: float, offset: float = 0.0) -> None:
        if not period > 0.0:
            raise ValueError("every() needs a positive period")
        if offset < 0.0:
            raise ValueError("every() needs an offset of zero or more")
        self.period = period
        self.offset = offset
        self._next = math.inf

    def start(self, time: float) -> None:
        """The context starts at ``time``."""
        self._next = time + self.offset

    def occurred(self, time: float) -> bool:
        """Whether an occurrence is due at ``time`` (each occurrence is reported once)."""
        if time < self._next - _TIME_EPS:
            return False
        while self._next <= time + _TIME_EPS:
            self._next += self.period
        return True


_TIME_EPS = 1e-9  # s: tick times are multiples of dt computed in floating point


class RunContext:
    """Live state and services for one run (see the module docstring).

    Parameters:
        network: the map the scenario runs on.
        actors: the scenario's actors.
        dt: control period in seconds.
        seed: the run's seed (random choices the scenario leaves open).
    """

    def __init__(
        self,
        network: RoadNetwork,
        actors: list[Actor],
        *,
        dt: float = DT_CONTROL,
        seed: int = 0,
    ) -> None:
        self.network = network
        self.lanes = LaneNumbers(network)
        self.actors: dict[str, Actor] = {a.name: a for a in actors}
        self.dt = float(dt)
        self.seed = seed
        self.rng = np.random.default_rng(seed)
        self.tick = 0
        self.time = 0.0
        self.world: World | None = None
        self.controllers: dict[str, Controller] = {}
        self.states: dict[str, ActorState] = {}
        self.variables: dict[str, Any] = {}
        self.detectors: list[EdgeDetector] = []
        self.background: list[Callable[[], None]] = []  # polled every tick, before the tree
        self.listeners: dict[str, list[Callable[[Occurrence], None]]] = {}
        self.coverage = RunCoverage(seed=seed)  # the cover/record items and their samples
        self.records: list[LogRecord] = []
        self.lights: dict[str, str] = {}
        #: the scenario's traffic lights by parameter name (``instance.lights``)
        self.traffic_lights: dict[str, Any] = {}
        #: ``env.weather`` as the environment actions set it
        self.weather: Any = initial_weather()
        #: ``env.sun`` and ``env.moon`` (``runner`` gives it the environment's observer)
        self.sky = Sky(clock=lambda: self.time)
        #: every environment action, in order (what it set, when)
        self.environment_changes: list[EnvironmentChange] = []
        self.collisions_allowed: dict[str, int] = {}
        self.failed: str | None = None
        self.event_names: set[str] = set()
        #: what a check at a phase boundary allows, and the margin plans keep
        self.tolerances = Tolerances.for_period(self.dt)
        #: when each phase must end and each member starts (the checker's, for the witness)
        self.schedule = Schedule()
        #: when each phase started last (s), by the schedule's name of it
        self.phase_starts: dict[PhaseKey, float] = {}
        self._client = py_trees.blackboard.Client(name="osc2runner")
        self._client.register_key(VARIABLES_KEY, access=py_trees.common.Access.WRITE)
        self._client.set(VARIABLES_KEY, self.variables)

    # ---- events and detectors, declared while compiling

    def declare_event(self, name: str) -> str:
        """Make an event known (its blackboard key exists, empty); returns the key."""
        key = event_key(name)
        if name not in self.event_names:
            self.event_names.add(name)
            self._client.register_key(key, access=py_trees.common.Access.WRITE)
            self._client.set(key, ())
        return key

    def edge(
        self, fn: Callable[[], Any], rising: bool, node: ast.Node | None = None
    ) -> EdgeDetector:
        """A rise/fall detector on ``fn``, updated at the start of every tick while active."""
        detector = EdgeDetector(fn, rising, node)
        self.detectors.append(detector)
        return detector

    def listen(self, name: str, callback: Callable[[Occurrence], None]) -> None:
        """Call ``callback(occurrence)`` at every occurrence of event ``name``, when it
        occurs (``sample`` and coverage read the state of the occurrence's tick)."""
        self.declare_event(name)
        self.listeners.setdefault(name, []).append(callback)

    def poll(self, callback: Callable[[], None]) -> None:
        """Call ``callback()`` at the start of every tick, after the edge detectors (the
        event functions that ``sample`` and coverage items wait for)."""
        self.background.append(callback)

    # ---- phases

    def phase_started(self, key: PhaseKey | None) -> None:
        """A phase starts now (the anchors of the schedule's deadlines)."""
        if key is not None:
            self.phase_starts[key] = self.time

    def deadline(self, plan: PhasePlan | None) -> float | None:
        """When a phase with ``plan`` must be done (s of simulated time), from the phases
        that have started; None when the schedule does not know."""
        if plan is None:
            return None
        found: float | None = None
        starts = self.phase_starts
        for anchor, offset in plan.deadlines:
            begun = starts.get(anchor)
            if begun is not None and (found is None or begun + offset < found):
                found = begun + offset
        return found

    # ---- actors

    def state(self, name: str) -> ActorState:
        """The state of actor ``name`` at this tick."""
        return self.states[name]

    def refresh(self) -> None:
        """Read every actor's state after a world step (once per tick).

        Obstacles never move: their states are read once, at ``attach``
        (their ``tick`` and ``time`` fields stay those of the start).
        """
        world = self.world
        assert world is not None
        world.read_states(self.states, static=False)
        self.tick = world.tick
        self.time = world.time

    def place(self, name: str, x: float, y: float, yaw: float, speed: float) -> None:
        """Teleport actor ``name`` mid-run (:meth:`World.place`) and read its new state,
        and that of the trailer it tows (which the world moves along); the other actors'
        states are unchanged."""
        world = self.attached_world
        world.place(name, x, y, yaw, speed)
        states = self.states
        states[name] = world.state(name)
        trailer = world.towing(name)
        if trailer is not None:
            states[trailer] = world.state(trailer)

    @property
    def attached_world(self) -> World:
        """The world, once attached (behaviours tick only after :meth:`attach`)."""
        if self.world is None:
            raise RuntimeError("the run context has no world attached yet")
        return self.world

    def attach(self, world: World, controllers: dict[str, Controller]) -> None:
        """Connect the world and the controllers built by the initializer."""
        self.world = world
        self.controllers = controllers
        world.read_states(self.states)
        self.refresh()

    def begin_tick(self) -> None:
        """Evaluate the active edge detectors against this tick's state (before the tree
        tick), then the background polls."""
        for detector in self.detectors:
            if detector.active:
                detector.update()
        for callback in self.background:
            callback()

    # ---- events

    def occurrences(self, name: str) -> tuple[Occurrence, ...]:
        found: tuple[Occurrence, ...] = py_trees.blackboard.Blackboard.storage.get(
            event_key(name), ()
        )
        return found

    def emit(
        self,
        name: str,
        args: dict[str, Any] | None = None,
        *,
        kind: EventKind = "emit",
        client: py_trees.blackboard.Client | None = None,
        key: str | None = None,
    ) -> None:
        """Record an occurrence of event ``name`` now, with ``args`` (values, in the event's
        parameter order): appended to its blackboard key through ``client`` (the emitting
        behaviour's, registered to write ``key``; else the context's own), written to the
        event log as ``kind`` and told to its listeners. The scenario's ``emit fail`` (kind
        ``emit``) fails the run; runner-level events (start, end, ...) have kinds of their
        own."""
        if client is None or key is None:
            client, key = self._client, self.declare_event(name)
        occurrence = Occurrence(self.tick, self.time, dict(args or {}))
        client.set(key, client.get(key) + (occurrence,))
        self.record(kind, name, _args_text(args))
        self.occurred(name, occurrence)
        if kind == "emit" and name == "fail":
            self.fail("the scenario emitted `fail`")

    def occurred(self, name: str, occurrence: Occurrence) -> None:
        """Tell the listeners of ``name`` (see :meth:`listen`) that it occurred now; every
        path that appends an occurrence calls this once."""
        for callback in self.listeners.get(name, ()):
            callback(occurrence)

    def record(
        self, kind: EventKind, name: str, detail: str = "", actors: tuple[str, ...] = ()
    ) -> None:
        """Add a line to the event log at the current tick."""
        self.records.append(LogRecord(self.tick, self.time, kind, name, detail, actors))

    def environment_changed(self, action: str, values: dict[str, Any], detail: str) -> None:
        """Log an environment action that took effect now (``detail`` for the event log)
        and keep what it set (:attr:`environment_changes`)."""
        plain = {k: v if isinstance(v, (int, float)) else str(v) for k, v in values.items()}
        friction = self.attached_world.road_friction
        self.environment_changes.append(
            EnvironmentChange(self.tick, self.time, action, plain, float(friction))
        )
        self.record("environment", action, detail)

    def fail(self, reason: str) -> None:
        """Mark the run as failed (the scenario's `fail` event, an impossible action, ...)."""
        if self.failed is None:
            self.failed = reason


def _args_text(args: dict[str, Any] | None) -> str:
    if not args:
        return ""
    return ", ".join(f"{k}: {_short(v)}" for k, v in args.items())


def _short(value: object) -> str:
    """An argument in the event log: a float to 6 digits, an actor or enum value by name."""
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(getattr(value, "name", value))
