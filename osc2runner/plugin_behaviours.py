"""The runner's side of the plug-in API (:mod:`osc2check.plugins`): what a plug-in's
implementation is given, and how it becomes a behaviour of the tree.

An **action** implemented by a function is instant: the function is called once
when the action starts, as ``fn(run, actor, **arguments)`` (without ``actor`` for
an action declared without one) and the action ends in that tick. An action
implemented by a class is lasting: one object per invocation, made without
arguments; ``start(run, actor, **arguments)`` when the phase starts, then
``step(run, actor)`` every tick until it returns True (the action's goal is
reached) or the phase's ``duration`` ends it.

A **modifier** class is made per application: ``start(run, actor, **arguments)``
when its action's phase starts, ``step(run, actor)`` every tick of the phase.
A **method** function is called as ``fn(run, subject, *arguments)`` and returns
its value (SI units for physical types).

``run`` is a :class:`PluginRun`: the simulated time, the event log, every
actor's state, and the commands an implementation may give an actor (a target
speed). ``actor`` is an :class:`ActorView`. Arguments arrive by parameter name:
physical values in SI units (``10kph`` as 2.777... m/s), booleans, numbers and
strings as themselves, enum members by name, actors as :class:`ActorView`,
lists as tuples. A plug-in that raises fails the run with the invocation's place.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from py_trees.common import Status

from osc2check.plugins import Implementation, PluginError, PluginRegistry
from osc2check.syntax import ast
from osc2runner.behaviours.base import (
    ActionBehaviour,
    ActionError,
    Modifier,
    ModifierUse,
    ScenarioBehaviour,
)
from osc2runner.behaviours.driving import SPEED_PROFILE, profile_for, set_speed
from osc2runner.compile.expressions import Closure
from osc2runner.compile.registry import Entry, MethodRegistry, load_registry, standard_registry
from osc2runner.execution.context import RunContext, ended_kind
from osc2runner.instance.actors import Actor

__all__ = ["ActorView", "PluginRun", "add_plugins", "runner_registry"]


@dataclass(frozen=True)
class ActorView:
    """One actor as a plug-in sees it, read at the moment it asks."""

    name: str
    _ctx: RunContext

    @property
    def speed(self) -> float:
        """Speed (m/s)."""
        return float(self._ctx.states[self.name].speed)

    @property
    def position(self) -> tuple[float, float]:
        """World ``x``, ``y`` of its reference point (m)."""
        state = self._ctx.states[self.name]
        return float(state.x), float(state.y)

    @property
    def lane(self) -> int | None:
        """Lane number, 1 = the rightmost in its direction of travel (None off the road)."""
        state = self._ctx.states[self.name]
        return None if state.lane is None else int(state.lane)


class PluginRun:
    """What a plug-in may read and do during the run (see the module docstring)."""

    def __init__(self, ctx: RunContext, source: str) -> None:
        self._ctx = ctx
        self._source = source  # the invocation, in the event log

    @property
    def time(self) -> float:
        """Simulated time (s)."""
        return float(self._ctx.time)

    def actor(self, name: str) -> ActorView:
        if name not in self._ctx.states:
            raise ActionError(f"there is no actor `{name}`")
        return ActorView(name, self._ctx)

    def log(self, message: str) -> None:
        """A line of the event log (``events.csv``, kind ``log``)."""
        self._ctx.record("log", self._source, str(message))

    def set_speed(self, actor: ActorView, target: float, acceleration: float | None = None) -> None:
        """Drive ``actor`` towards ``target`` m/s, at ``acceleration`` m/s² at most (the
        runner's smooth profile when None); the target persists after the action."""
        if not math.isfinite(target) or target < 0:
            raise ActionError(f"a target speed must be finite and not negative, got {target}")
        profile = profile_for("none", peak=acceleration) if acceleration else SPEED_PROFILE
        set_speed(self._ctx.controllers.get(actor.name), target, profile)


def _plain(value: Any, ctx: RunContext) -> Any:
    if isinstance(value, Actor):
        return ActorView(value.name, ctx)
    if isinstance(value, (list, tuple)):
        return tuple(_plain(v, ctx) for v in value)
    return value


def _call(fn: Any, *args: Any, **kwargs: Any) -> Any:
    try:
        return fn(*args, **kwargs)
    except ActionError:
        raise
    except Exception as exc:  # the user's code: said with the invocation
        raise ActionError(f"the plug-in raised {type(exc).__name__}: {exc}") from exc


class _Performance:
    """One invocation's implementation at work: started once, stepped until done."""

    def __init__(self, impl: Implementation, run: PluginRun, actor: tuple[ActorView, ...]):
        self._impl = impl
        self._run = run
        self._actor = actor
        self._object: Any = None
        self.done = False

    def start(self, args: dict[str, Any]) -> None:
        if self._impl.lasting:
            self._object = self._impl.target()
            _call(self._object.start, self._run, *self._actor, **args)
        else:
            _call(self._impl.target, self._run, *self._actor, **args)
            self.done = True

    def step(self) -> None:
        if not self.done:
            self.done = bool(_call(self._object.step, self._run, *self._actor))


class PluginAction(ActionBehaviour):
    """An action of an actor that a plug-in implements (see the module docstring)."""

    implementation: Implementation  # set on each subclass made by add_plugins
    with_defaults = True  # compiled with the declared defaults of its parameters

    def start(self) -> None:
        run = PluginRun(self.ctx, self.use.label)
        self._performance = _Performance(
            self.implementation, run, (ActorView(self.actor.name, self.ctx),)
        )
        self._performance.start(_arguments(self.args, self.ctx))

    def step(self) -> Status:
        self._performance.step()
        return Status.SUCCESS if self._performance.done else Status.RUNNING


class UnboundPluginAction(ScenarioBehaviour):
    """An action declared without an actor (``action log:``) that a plug-in implements:
    its log records name the action alone; a plug-in's exception fails the run with the
    invocation's place."""

    implementation: Implementation
    finite = True

    def __init__(self, name: str, node: ast.Invocation, arguments: dict[str, Closure]) -> None:
        super().__init__(name)
        self.node = node
        self.arguments = arguments
        self.label = self.implementation.name

    def initialise(self) -> None:
        self.ctx.record("start", self.label)
        self._failure: str | None = None
        self._performance = _Performance(self.implementation, PluginRun(self.ctx, self.label), ())
        try:
            args = {k: fn() for k, fn in self.arguments.items()}
            self._performance.start(_arguments(args, self.ctx))
        except ActionError as exc:
            self._failure = str(exc)

    def update(self) -> Status:
        try:
            if self._failure is None:
                self._performance.step()
        except ActionError as exc:
            self._failure = str(exc)
        if self._failure is not None:
            span = self.node.span
            self.ctx.fail(f"{span.uri}:{span.line}:{span.column}: {self.label}: {self._failure}")
            return Status.FAILURE
        return Status.SUCCESS if self._performance.done else Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        if new_status == Status.INVALID and self.status != Status.RUNNING:
            return
        self.ctx.record(ended_kind(new_status), self.label)


def _arguments(args: dict[str, Any], ctx: RunContext) -> dict[str, Any]:
    """An invocation's argument values as a plug-in gets them (not its ``duration``)."""
    return {k: _plain(v, ctx) for k, v in args.items() if k != "duration"}


class PluginModifier(Modifier):
    """A modifier a plug-in implements (see the module docstring)."""

    implementation: Implementation
    with_defaults = True

    def __init__(self, use: ModifierUse) -> None:
        super().__init__(use)
        self._object = self.implementation.target()

    def realise(self, action: ActionBehaviour) -> None:
        self._run = PluginRun(action.ctx, f"{action.use.label} {self.use.name}")
        args = {k: _plain(v, action.ctx) for k, v in self.args.items() if k != "at"}
        _call(self._object.start, self._run, ActorView(action.actor.name, action.ctx), **args)

    def step(self, action: ActionBehaviour) -> None:
        step = getattr(self._object, "step", None)
        if step is not None:
            _call(step, self._run, ActorView(action.actor.name, action.ctx))


def _method(impl: Implementation) -> Any:
    fn = impl.target

    def call(ctx: RunContext, subject: Any, *args: Any) -> Any:
        run = PluginRun(ctx, impl.label)
        plain = [_plain(a, ctx) for a in args]
        try:
            return fn(run, _plain(subject, ctx), *plain)
        except Exception as exc:  # the user's code
            raise ActionError(
                f"the plug-in method `{impl.label}` raised {type(exc).__name__}: {exc}"
            ) from exc

    return call


_with_plugins: dict[int, tuple[PluginRegistry, MethodRegistry]] = {}


def runner_registry(plugins: PluginRegistry) -> MethodRegistry:
    """The runner's registry with ``plugins`` added (the runner's own without any);
    made once per plug-in registry. A plug-in that implements one of the runner's own
    behaviours is a :class:`~osc2check.plugins.PluginError`."""
    if not len(plugins):
        return standard_registry()
    made = _with_plugins.get(id(plugins))
    if made is None or made[0] is not plugins:
        made = (plugins, add_plugins(load_registry(), plugins))
        _with_plugins[id(plugins)] = made
    return made[1]


def add_plugins(registry: MethodRegistry, plugins: PluginRegistry) -> MethodRegistry:
    """``registry`` with the plug-ins' implementations added (a registration of the same
    behaviour as the runner's own is an error, as two plug-ins' are)."""
    for impl in plugins:
        if impl.kind == "action":
            base = PluginAction if impl.owner is not None else UnboundPluginAction
            target: Any = type(f"Plugin_{impl.name}", (base,), {"implementation": impl})
        elif impl.kind == "modifier":
            target = type(f"Plugin_{impl.name}", (PluginModifier,), {"implementation": impl})
        else:
            target = _method(impl)
        try:
            registry.add(
                Entry(impl.kind, impl.owner, impl.name, target, f"plug-in `{impl.module}`")
            )
        except ValueError:
            raise PluginError(
                f"plug-in `{impl.module}` implements {impl.kind} `{impl.label}`, which the "
                "runner implements already"
            ) from None
    return registry
