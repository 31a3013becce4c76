"""Events and conditions: ``wait``, ``emit``, ``until``, ``on``, ``call``; watches over event specs.

An event spec compiles to a *watch*. A behaviour starts the watch when its
event context starts (§7.3.10.3: a ``wait`` starts it when the wait starts,
``until`` when the invocation starts, ``on`` when the scenario starts), asks
it once per tick whether the event occurred since, and stops it when it
ends:

* ``@e [as x] [if cond]`` (:class:`NamedEventWatch`): each occurrence of ``e``
  on the blackboard at or after the tick the watch started, one per call;
  ``x`` reads the occurrence's arguments (SI values) and ``cond`` is
  evaluated on it. An emit in a branch ticked earlier in the same tick is
  seen in that tick; one in a branch ticked later is seen on the next tick.
* ``rise(b)`` / ``fall(b)`` (:class:`EdgeWatch`): the value of ``b`` when the
  context starts is its first evaluation (no edge there); from then on the
  execution context evaluates ``b`` at the start of every tick, so an edge
  between two ticks is seen at the second.
* ``every(d[, offset: o])`` (:class:`EveryWatch`): at the start of the
  context plus ``o`` (default 0), then every ``d``.
* ``elapsed(d)`` (:class:`ElapsedWatch`): once, ``d`` after the context started.
* a boolean expression (:class:`LevelWatch`): at every evaluation (tick) where
  it is true.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from typing import Any

import py_trees
from py_trees.common import Access, Status

from osc2check.semantics.builtins import EVENT_FUNCTIONS, PREDEFINED_EVENTS
from osc2check.semantics.symbols import SymbolKind
from osc2check.syntax import ast
from osc2runner.behaviours.base import FastLeaf
from osc2runner.compile.composites import end_instances, tick_child
from osc2runner.compile.expressions import Bindings, Closure, Environment, is_constant
from osc2runner.errors import CompileProblem
from osc2runner.execution.context import (
    EdgeDetector,
    Occurrence,
    PeriodicDetector,
    RunContext,
    RunFault,
    event_key,
)
from osc2runner.structs import StructValue

__all__ = [
    "CallDirective",
    "Emit",
    "EdgeWatch",
    "ElapsedWatch",
    "EveryWatch",
    "LevelWatch",
    "NamedEventWatch",
    "OnHandler",
    "Until",
    "Wait",
    "Watch",
    "calls",
    "compile_watch",
    "emits",
    "emits_now",
    "event_path",
]


class Watch:
    """A compiled event spec: ``start()`` when its context starts, ``occurred()`` once per
    tick while it runs, ``stop()`` when the context ends."""

    key: str | None = None
    consumes = False  # True when each call consumes one occurrence

    def start(self) -> None:
        pass

    def stop(self) -> None:
        pass

    def occurred(self) -> bool:  # pragma: no cover - abstract
        raise NotImplementedError

    def drain(self, callback: Callable[[], None]) -> None:
        """Call ``callback()`` once per occurrence since the last call (this tick's
        evaluation: every pending one of a consuming watch, at most one otherwise)."""
        if self.consumes:
            while self.occurred():
                callback()
        elif self.occurred():
            callback()


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
        self.key: str = ctx.declare_event(name)
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
            if self.cell is not None:
                self.cell[0] = StructValue(self.name, dict(occurrence.args))
            if self.condition is None or self.condition():
                return True
        return False


class EdgeWatch(Watch):
    """``rise(b)`` / ``fall(b)``: the detector's edge at this tick, within the context."""

    def __init__(self, detector: EdgeDetector) -> None:
        self.detector = detector
        self.running = False

    def start(self) -> None:
        if self.running:
            self.detector.deactivate()
        self.running = True
        self.detector.activate()

    def stop(self) -> None:
        if self.running:
            self.running = False
            self.detector.deactivate()

    def occurred(self) -> bool:
        return self.detector.edge


class EveryWatch(Watch):
    """``every(period[, offset: o])``: at the context's start + ``o``, then every period.

    The durations are evaluated when the context starts (a parameter's value, or the
    live value of an expression at that tick).
    """

    def __init__(
        self, ctx: RunContext, period: Closure, offset: Closure | None, node: ast.Node
    ) -> None:
        self.ctx = ctx
        self.period = period
        self.offset = offset
        self.node = node
        self.detector: PeriodicDetector | None = None

    def start(self) -> None:
        offset = float(self.offset()) if self.offset is not None else 0.0
        try:
            self.detector = PeriodicDetector(float(self.period()), offset)
        except ValueError as exc:
            raise RunFault(str(exc), self.node) from None
        self.detector.start(self.ctx.time)

    def stop(self) -> None:
        self.detector = None

    def occurred(self) -> bool:
        return self.detector is not None and self.detector.occurred(self.ctx.time)


class ElapsedWatch(Watch):
    """``elapsed(d)``: once, ``d`` seconds of simulated time after the context started."""

    def __init__(self, ctx: RunContext, duration: Closure) -> None:
        self.ctx = ctx
        self.duration = duration
        self.start_tick = 0
        self.seconds = 0.0
        self.fired = True  # nothing before start()

    def start(self) -> None:
        self.start_tick = self.ctx.tick
        self.seconds = float(self.duration())
        self.fired = False

    def occurred(self) -> bool:
        if self.fired:
            return False
        if (self.ctx.tick - self.start_tick) * self.ctx.dt >= self.seconds - 1e-9:
            self.fired = True
            return True
        return False


class LevelWatch(Watch):
    """A boolean condition: occurs at every evaluation where it is true."""

    def __init__(self, condition: Closure) -> None:
        self.condition = condition

    def occurred(self) -> bool:
        return bool(self.condition())


# ---------------------------------------------------------------------- compiling


def compile_watch(env: Environment, spec: ast.Node, scope: Bindings) -> Watch:
    """The watch of an event spec (``@e as x if c``, an event function, a condition), of
    an event argument (``@e`` in ``sample``) or of an event named by a path (``event: e``
    of a coverage item). Raises CompileProblem for what the runner cannot watch."""
    run = env.run
    match spec:
        case ast.EventReference():
            name = scope.event(tuple(p.text for p in spec.path))
            condition = None
            cell: list[Any] | None = None
            inner = scope
            if spec.alias is not None:
                cell = [None]
                inner = scope.child(**{spec.alias.text: lambda c=cell: c[0]})
            if spec.condition is not None:
                condition = env.compile(spec.condition, inner)
            return NamedEventWatch(run, name, condition, cell)
        case ast.EventArgument():
            return NamedEventWatch(run, scope.event(tuple(p.text for p in spec.path)))
        case ast.EventCondition():
            return compile_watch(env, spec.expr, scope)
    path = event_path(env, spec)
    if path is not None:
        return NamedEventWatch(run, scope.event(tuple(path.split("."))))
    if (
        isinstance(spec, ast.Call)
        and isinstance(spec.callee, ast.NameRef)
        and spec.callee.name.name.text in EVENT_FUNCTIONS
        and env.compiler.ref(spec.callee.name.name) is None
    ):
        return _event_function(env, spec.callee.name.name.text, spec, scope)
    if isinstance(spec, ast.Expr):
        return LevelWatch(env.compile(spec, scope))
    raise CompileProblem("the runner cannot watch this event", spec)


def event_path(env: Environment, node: ast.Node) -> str | None:
    """``e`` or ``lbl.end`` written as an expression, when it names an event: its name."""
    names: list[str] = []
    current = node
    while isinstance(current, ast.MemberAccess):
        names.append(current.member.text)
        current = current.target
    if not isinstance(current, ast.NameRef) or current.name.namespace is not None:
        return None
    names.append(current.name.name.text)
    names.reverse()
    if len(names) == 1:
        sym = env.compiler.ref(current.name.name)
        if names[0] in PREDEFINED_EVENTS or (sym is not None and sym.kind is SymbolKind.EVENT):
            return names[0]
        return None
    if names[-1] in PREDEFINED_EVENTS:  # `lbl.end`
        return event_name(tuple(names))
    return None


def _arguments(env: Environment, builtin: str, call: ast.Call) -> dict[str, ast.Node]:
    """The arguments of a built-in call by parameter name, as the checker bound them."""
    binding = env.model.binding(call)
    if binding is None:
        raise CompileProblem(f"this `{builtin}` was not bound by the checker", call)
    given: dict[str, ast.Node] = dict(binding.values())
    for p in EVENT_FUNCTIONS[builtin].parameters:
        if not p.optional and p.name not in given:
            raise CompileProblem(f"`{builtin}` needs its argument `{p.name}`", call)
    return given


def _event_function(env: Environment, fname: str, call: ast.Call, scope: Bindings) -> Watch:
    run = env.run
    args = _arguments(env, fname, call)
    first = args[EVENT_FUNCTIONS[fname].parameters[0].name]
    if fname in ("rise", "fall"):
        return EdgeWatch(run.edge(env.compile(first, scope), fname == "rise", call))
    if fname == "elapsed":
        return ElapsedWatch(run, env.compile(first, scope))
    period = env.compile(first, scope)
    offset_node = args.get(EVENT_FUNCTIONS[fname].parameters[1].name)
    offset = env.compile(offset_node, scope) if offset_node is not None else None
    if is_constant(period) and (offset is None or is_constant(offset)):
        try:  # known before the run: check it now
            PeriodicDetector(float(period()), float(offset()) if offset is not None else 0.0)
        except ValueError as exc:
            raise CompileProblem(str(exc), call) from None
    return EveryWatch(run, period, offset, call)


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
    """``wait <event>``: running until the event occurs, then success.

    Its ``companions`` (actions the runner adds: the next phase's ``at: start``
    brought about while the wait runs, :mod:`osc2runner.compile.preparation`) run
    with it and are stopped when it ends."""

    phase_key: Any = None  # the schedule's name of its phase
    plan: Any = None  # what the schedule says of it (its deadline)

    def __init__(self, name: str, watch: Watch) -> None:
        super().__init__(name)
        self.watch = watch
        self.companions: list[FastLeaf] = []
        _reader(self, watch)

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        for companion in self.companions:
            companion.setup(**kwargs)  # type: ignore[attr-defined]

    def initialise(self) -> None:
        self.ctx.phase_started(self.phase_key)
        self.watch.start()

    def update(self) -> Status:
        if self.watch.occurred():
            self.feedback_message = f"occurred at tick {self.ctx.tick}"
            return Status.SUCCESS
        for companion in self.companions:
            if companion.tick_status() == Status.FAILURE:
                return Status.FAILURE
        return Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        self.watch.stop()
        for companion in self.companions:
            if companion.status == Status.RUNNING:
                companion.stop(Status.INVALID)  # type: ignore[attr-defined]


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
        args = {k: fn() for k, fn in self.arguments.items()}  # SI values, evaluated now
        self.ctx.emit(self.event, args, client=self.blackboard, key=self.key)
        return Status.SUCCESS


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

    The event context is the invocation (§7.3.10.3): the watch starts when the
    invocation starts and stops when it ends. The event is checked before the
    child is ticked, so an event seen at a tick ends the phase at that tick and
    the next member starts at once.
    """

    #: its phase ends when its event occurs: stopping it earlier is not its planned end
    ends_on_event = True

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, watch: Watch) -> None:
        super().__init__(name=name, child=child)
        self.watch = watch
        _reader(self, watch)

    def initialise(self) -> None:
        self.watch.start()

    def terminate(self, new_status: Status) -> None:
        self.watch.stop()

    def tick_status(self) -> Status:
        if self.status != Status.RUNNING:
            self.initialise()
        if self.watch.occurred():
            self.feedback_message = "until: event occurred"
            end_instances(self.decorated)
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
    """``on <event>: ...``: runs for the whole scenario (its event context); each
    occurrence runs the members, in order, with the ``as`` alias bound to it."""

    def __init__(
        self,
        name: str,
        watch: Watch,
        members: list[Callable[[Any], None]],
        keys: Sequence[str] = (),
    ) -> None:
        super().__init__(name)
        self.watch = watch
        self.members = members
        _reader(self, watch)
        self.blackboard = self.attach_blackboard_client(name=f"{name} (emits)")
        for key in keys:
            self.blackboard.register_key(key, access=Access.WRITE)

    def initialise(self) -> None:
        self.watch.start()

    def terminate(self, new_status: Status) -> None:
        self.watch.stop()

    def update(self) -> Status:
        self.watch.drain(self._run)
        return Status.RUNNING

    def _run(self) -> None:
        for member in self.members:
            member(self)


# the members of an `on` handler: each called with the handler when it fires


def emits(run: RunContext, name: str) -> Callable[[Any], None]:
    """An ``on`` handler's member that emits ``name`` (an ``event e is <spec>``)."""

    def fire(handler: Any) -> None:
        run.emit(name, kind="event")

    return fire


def emits_now(
    run: RunContext, name: str, key: str, args: dict[str, Closure]
) -> Callable[[Any], None]:
    """An ``on`` handler's ``emit name(args)``: the arguments evaluated when it fires."""

    def fire(handler: Any) -> None:
        values = {k: fn() for k, fn in args.items()}  # SI values, evaluated now
        run.emit(name, values, client=handler.blackboard, key=key)

    return fire


def calls(call: Callable[[], Any]) -> Callable[[Any], None]:
    """An ``on`` handler's ``call m(args)``."""

    def fire(handler: Any) -> None:
        call()

    return fire


def event_name(path: tuple[str, ...]) -> str:
    """``@a.b`` -> ``a.b``."""
    return ".".join(path)


__all__ += ["event_name", "event_key"]
