"""Events and conditions: ``wait``, ``emit``, ``until``, ``on``, ``call``; watches over event specs.

An event spec compiles to a *watch*, which a behaviour starts when it
becomes active and asks once per tick whether the event occurred since:

* ``@e [as x] [if cond]`` (:class:`NamedEventWatch`): an occurrence of ``e``
  on the blackboard at or after the tick the watch started. An emit in a
  branch ticked earlier in the same tick is seen in that tick; one in a
  branch ticked later is seen on the next tick.
* ``rise(b)`` / ``fall(b)`` (:class:`EdgeWatch`): the edge detectors are
  evaluated at the start of every tick by the execution context, whether a
  behaviour waits on them or not, so an edge is never missed.
* ``every(d[, offset: o])`` (:class:`EdgeWatch` on a periodic detector).
* ``elapsed(d)`` (:class:`ElapsedWatch`): ``d`` of simulated time since the
  watch started.
* a boolean expression (:class:`LevelWatch`): true when evaluated.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from types import SimpleNamespace
from typing import Any

import py_trees
from py_trees.common import Access, Status

from osc2runner.behaviours.base import FastLeaf
from osc2runner.compile.composites import tick_child
from osc2runner.compile.expressions import Closure
from osc2runner.execution.context import (
    EdgeDetector,
    Occurrence,
    PeriodicDetector,
    RunContext,
    event_key,
)

__all__ = [
    "CallDirective",
    "Emit",
    "EdgeWatch",
    "ElapsedWatch",
    "LevelWatch",
    "NamedEventWatch",
    "OnHandler",
    "Until",
    "Wait",
    "Watch",
]


class Watch:
    """A compiled event spec: ``start()`` when the waiting begins, ``occurred()`` each tick."""

    key: str | None = None
    consumes = False  # True when each call consumes one occurrence

    def start(self) -> None:
        pass

    def occurred(self) -> bool:  # pragma: no cover - abstract
        raise NotImplementedError


class NamedEventWatch(Watch):
    """``@name [as alias] [if condition]``."""

    consumes = True

    def __init__(
        self,
        ctx: RunContext,
        name: str,
        condition: Closure | None = None,
        cell: list[Any] | None = None,
    ) -> None:
        self.ctx = ctx
        self.name = name
        self.key = ctx.declare_event(name)
        self.condition = condition
        self.cell = cell  # where the `as` alias reads the occurrence from
        self.cursor = 0

    def start(self) -> None:
        occurrences = py_trees.blackboard.Blackboard.storage.get(self.key, ())
        tick = self.ctx.tick
        cursor = len(occurrences)
        while cursor > 0 and occurrences[cursor - 1].tick >= tick:
            cursor -= 1
        self.cursor = cursor

    def occurred(self) -> bool:
        occurrences: tuple[Occurrence, ...] = py_trees.blackboard.Blackboard.storage.get(
            self.key, ()
        )
        while self.cursor < len(occurrences):
            occurrence = occurrences[self.cursor]
            self.cursor += 1
            if self.condition is None:
                return True
            if self.cell is not None:
                self.cell[0] = SimpleNamespace(**occurrence.args)
            if self.condition():
                return True
        return False


class EdgeWatch(Watch):
    """An edge detector's value at this tick (``rise``, ``fall``, ``every``)."""

    def __init__(self, detector: EdgeDetector | PeriodicDetector) -> None:
        self.detector = detector

    def occurred(self) -> bool:
        return self.detector.edge


class ElapsedWatch(Watch):
    """``elapsed(d)``: ``d`` seconds of simulated time since the watch started."""

    def __init__(self, ctx: RunContext, duration: Closure) -> None:
        self.ctx = ctx
        self.duration = duration
        self.start_tick = 0
        self.seconds = 0.0

    def start(self) -> None:
        self.start_tick = self.ctx.tick
        self.seconds = float(self.duration())

    def occurred(self) -> bool:
        return (self.ctx.tick - self.start_tick) * self.ctx.dt >= self.seconds - 1e-9


class LevelWatch(Watch):
    """A boolean condition, true whenever it evaluates true."""

    def __init__(self, condition: Closure) -> None:
        self.condition = condition

    def occurred(self) -> bool:
        return bool(self.condition())


# ---------------------------------------------------------------------- behaviours


class _ContextBehaviour(FastLeaf, py_trees.behaviour.Behaviour):
    """A leaf that takes the execution context from ``tree.setup(context=ctx)``."""

    ctx: RunContext

    def setup(self, **kwargs: Any) -> None:
        ctx = kwargs.get("context")
        if ctx is not None:
            self.ctx = ctx


def _reader(behaviour: py_trees.behaviour.Behaviour, watch: Watch) -> None:
    if watch.key is not None:
        client = behaviour.attach_blackboard_client(name=behaviour.name)
        client.register_key(watch.key, access=Access.READ)


class Wait(_ContextBehaviour):
    """``wait <event>``: running until the event occurs, then success."""

    def __init__(self, name: str, watch: Watch) -> None:
        super().__init__(name)
        self.watch = watch
        _reader(self, watch)

    def initialise(self) -> None:
        self.watch.start()

    def update(self) -> Status:
        if self.watch.occurred():
            self.feedback_message = f"occurred at tick {self.ctx.tick}"
            return Status.SUCCESS
        return Status.RUNNING


class Emit(_ContextBehaviour):
    """``emit e(args)``: one occurrence of ``e`` on the blackboard, then success."""

    def __init__(
        self, name: str, event: str, key: str, arguments: dict[str, Closure] | None = None
    ) -> None:
        super().__init__(name)
        self.event = event
        self.key = key
        self.arguments = dict(arguments or {})
        self.blackboard = self.attach_blackboard_client(name=name)
        self.blackboard.register_key(key, access=Access.WRITE)

    def update(self) -> Status:
        emit_now(self.ctx, self.blackboard, self.event, self.key, self.arguments)
        return Status.SUCCESS


def emit_now(
    ctx: RunContext, client: Any, event: str, key: str, arguments: dict[str, Closure]
) -> None:
    """Append an occurrence of ``event`` through ``client`` and log it."""
    args = {k: fn() for k, fn in arguments.items()}
    occurrence = Occurrence(ctx.tick, ctx.time, args)
    client.set(key, client.get(key) + (occurrence,))
    ctx.record("emit", event, ", ".join(f"{k}: {_text(v)}" for k, v in args.items()))
    if event == "fail":
        ctx.fail("the scenario emitted `fail`")


def _text(value: object) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(getattr(value, "name", value))


class CallDirective(_ContextBehaviour):
    """``call method(args)``: evaluate the call once, then success."""

    def __init__(self, name: str, call: Closure) -> None:
        super().__init__(name)
        self.call = call

    def update(self) -> Status:
        self.call()
        return Status.SUCCESS


class Until(py_trees.decorators.Decorator):
    """``with: until <event>``: the child's phase ends (success) when the event occurs.

    The event is checked before the child is ticked, so an event seen at a
    tick ends the phase at that tick and the next member starts at once.
    """

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, watch: Watch) -> None:
        super().__init__(name=name, child=child)
        self.watch = watch
        _reader(self, watch)

    def initialise(self) -> None:
        self.watch.start()

    def tick_status(self) -> Status:
        if self.status != Status.RUNNING:
            self.initialise()
        if self.watch.occurred():
            self.feedback_message = "until: event occurred"
            self.stop(Status.SUCCESS)
            return Status.SUCCESS
        status = tick_child(self.decorated)
        if status != Status.RUNNING:
            self.stop(status)
        self.status = status
        return status

    def tick(self) -> Iterator[py_trees.behaviour.Behaviour]:
        self.tick_status()
        yield self

    def update(self) -> Status:  # pragma: no cover - tick() decides
        return self.status


class OnHandler(_ContextBehaviour):
    """``on <event>: ...``: runs for the whole scenario; each occurrence runs the members."""

    def __init__(
        self, name: str, watch: Watch, members: list[Callable[[Any], None]], keys: list[str] = ()
    ) -> None:  # type: ignore[assignment]
        super().__init__(name)
        self.watch = watch
        self.members = members
        _reader(self, watch)
        self.blackboard = self.attach_blackboard_client(name=f"{name} (emits)")
        for key in keys:
            self.blackboard.register_key(key, access=Access.WRITE)

    def initialise(self) -> None:
        self.watch.start()

    def update(self) -> Status:
        if self.watch.consumes:
            while self.watch.occurred():
                self._run()
        elif self.watch.occurred():
            self._run()
        return Status.RUNNING

    def _run(self) -> None:
        for member in self.members:
            member(self)


def event_name(path: tuple[str, ...]) -> str:
    """``@a.b`` -> ``a.b``."""
    return ".".join(path)


__all__ += ["emit_now", "event_name", "event_key"]
