"""The RunContext: everything a behaviour reads while the tree is ticked.

One context per run. Behaviours receive it through ``tree.setup(context=ctx)``
and read only it: the simulated time and tick, each actor's state at this tick
(read once per tick, shared by every expression), the actors' controllers,
the world, and the edge detectors (``rise``, ``fall``, ``every``) that are
evaluated every tick whether or not a behaviour is currently waiting on them.
What the compiler needs (the model, the parameter values, the registry) is in
``compile.environment.CompileEnvironment``, not here.

State shared *between* behaviours lives on the py_trees blackboard only:
event occurrences under ``/osc2/events/<name>`` and scenario variables under
``/osc2/vars``. The blackboard is cleared for every run (:func:`fresh_blackboard`).

Nothing here reads the wall clock: time is ``tick * dt``.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import py_trees

from osc2check.road import Road
from osc2check.syntax import ast
from osc2runner.instance.actors import Actor
from osc2runner.instance.roads import LaneNumbers

if TYPE_CHECKING:
    from osc2runner.sim import ActorState, World

__all__ = [
    "EVENT_ROOT",
    "EdgeDetector",
    "LogRecord",
    "Occurrence",
    "PeriodicDetector",
    "RunContext",
    "event_key",
    "fresh_blackboard",
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


@dataclass(frozen=True, slots=True)
class LogRecord:
    """One line of the run's event log."""

    tick: int
    time: float
    kind: str  # emit, start, end, fail, collision, off_road, environment, lights, outcome, ...
    name: str
    detail: str = ""
    actors: tuple[str, ...] = ()


class EdgeDetector:
    """``rise(b)`` / ``fall(b)``: true on the tick where ``b`` changes, evaluated every tick.

    The first evaluation only records the value (there is no edge without a
    previous tick).
    """

    __slots__ = ("fn", "rising", "previous", "edge", "node")

    def __init__(self, fn: Callable[[], Any], rising: bool, node: ast.Node | None = None) -> None:
        self.fn = fn
        self.rising = rising
        self.previous: bool | None = None
        self.edge = False
        self.node = node

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
    """``every(period, offset: o)``: at ``o, o + period, ...`` (``o`` defaults to ``period``)."""

    __slots__ = ("period", "offset", "dt", "edge", "_next")

    def __init__(self, period: float, offset: float | None, dt: float) -> None:
        if period <= 0.0:
            raise ValueError("every() needs a positive period")
        self.period = period
        self.offset = period if offset is None else offset
        self.dt = dt
        self.edge = False
        self._next = self.offset

    def update_at(self, time: float) -> None:
        self.edge = False
        if time + 1e-9 * self.dt >= self._next - 1e-9:
            self.edge = True
            while self._next <= time + 1e-9:
                self._next += self.period


class RunContext:
    """Live state and services for one run (see the module docstring).

    Parameters:
        road: the road the scenario runs on.
        actors: the scenario's actors.
        dt: control period in seconds.
        seed: the run's seed (random choices the scenario leaves open).
    """

    def __init__(
        self,
        road: Road,
        actors: list[Actor],
        *,
        dt: float = 0.05,
        seed: int = 0,
    ) -> None:
        self.road = road
        self.lanes = LaneNumbers(road)
        self.actors: dict[str, Actor] = {a.name: a for a in actors}
        self.dt = float(dt)
        self.seed = seed
        self.rng = np.random.default_rng(seed)
        self.tick = 0
        self.time = 0.0
        self.world: World | None = None
        self.controllers: dict[str, Any] = {}
        self.states: dict[str, ActorState] = {}
        self.variables: dict[str, Any] = {}
        self.detectors: list[EdgeDetector] = []
        self.periodic: list[PeriodicDetector] = []
        self.records: list[LogRecord] = []
        self.lights: dict[str, str] = {}
        self.collisions_allowed: dict[str, int] = {}
        self.failed: str | None = None
        self.event_names: set[str] = set()
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
        """A rise/fall detector on ``fn``, updated at the start of every tick."""
        detector = EdgeDetector(fn, rising, node)
        self.detectors.append(detector)
        return detector

    def every(self, period: float, offset: float | None) -> PeriodicDetector:
        detector = PeriodicDetector(period, offset, self.dt)
        self.periodic.append(detector)
        return detector

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

    def attach(self, world: World, controllers: dict[str, Any]) -> None:
        """Connect the world and the controllers built by the initializer."""
        self.world = world
        self.controllers = controllers
        world.read_states(self.states)
        self.refresh()

    def begin_tick(self) -> None:
        """Evaluate every edge detector against this tick's state (before the tree tick)."""
        for detector in self.detectors:
            detector.update()
        time = self.time
        for periodic in self.periodic:
            periodic.update_at(time)

    # ---- events

    def occurrences(self, name: str) -> tuple[Occurrence, ...]:
        return py_trees.blackboard.Blackboard.storage.get(event_key(name), ())

    def emit(self, name: str, args: dict[str, Any] | None = None, *, kind: str = "emit") -> None:
        """Record an occurrence of event ``name`` now (runner-level events: start, end, ...)."""
        key = self.declare_event(name)
        occurrence = Occurrence(self.tick, self.time, dict(args or {}))
        self._client.set(key, self._client.get(key) + (occurrence,))
        self.record(kind, name, _args_text(args))

    def record(self, kind: str, name: str, detail: str = "", actors: tuple[str, ...] = ()) -> None:
        """Add a line to the event log at the current tick."""
        self.records.append(LogRecord(self.tick, self.time, kind, name, detail, actors))

    def fail(self, reason: str) -> None:
        """Mark the run as failed (the scenario's `fail` event, an impossible action, ...)."""
        if self.failed is None:
            self.failed = reason


def _args_text(args: dict[str, Any] | None) -> str:
    if not args:
        return ""
    return ", ".join(f"{k}: {_short(v)}" for k, v in args.items())


def _short(value: object) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, Actor):
        return value.name
    return str(value)
