"""``sample(expression, event[, default])``: a value taken when an event occurs.

§7.3.6.6 (variables) and the built-in ``sample`` (§7.4): the value of a
``sample`` is the value its expression had at the last occurrence of its event
so far; before the first occurrence it is the default, and reading it then
without a default is an error of the run (a :class:`RunFault` naming the
``sample`` in the source: the run fails). Its event context is the enclosing
scenario: occurrences count from the scenario's start.

* ``@e`` (an event, a label's ``@l.end``, ``@start``/``@end``): the expression is
  evaluated at the moment ``e`` occurs, through the run context's listeners,
  so it reads the state of the occurrence's tick (and an ``emit`` earlier in
  the same tick is seen by the ``sample`` at once).
* an event function (``rise``, ``fall``, ``elapsed``, ``every``) or a boolean
  condition: watched from the scenario's start and polled at the start of
  every tick, before the tree.

:func:`on_occurrence` is the one way both ``sample`` and the coverage items
(:mod:`osc2runner.compile.coverage`) wait for their event.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from osc2check.semantics.builtins import VALUE_FUNCTIONS
from osc2check.syntax import ast
from osc2runner.compile.conditions import NamedEventWatch, Watch, compile_watch
from osc2runner.compile.expressions import Bindings, Closure, Environment
from osc2runner.errors import CompileProblem
from osc2runner.execution.context import RunContext, RunFault

if TYPE_CHECKING:
    from osc2check.semantics.model import Model

__all__ = ["Sampler", "compile_sample", "is_sample", "on_occurrence", "sample_arguments"]

_UNSET: Any = object()


class Sampler:
    """One ``sample(...)`` of the scenario: the value at the last occurrence so far."""

    __slots__ = ("text", "node", "expression", "default", "value", "tick", "event")

    def __init__(
        self,
        text: str,
        node: ast.Node,
        expression: Closure,
        default: Closure | None,
        event: str,
    ) -> None:
        self.text = text
        self.node = node
        self.expression = expression
        self.default = default
        self.event = event
        self.value: Any = _UNSET
        self.tick: int | None = None

    def take(self, ctx: RunContext) -> None:
        """The event occurs: hold the expression's value now."""
        self.value = self.expression()
        self.tick = ctx.tick

    def read(self) -> Any:
        """The held value, or the default before the first occurrence."""
        value = self.value
        if value is not _UNSET:
            return value
        if self.default is None:
            raise RunFault(
                f"`{self.text}` was read before `{self.event}` occurred, and it has no default",
                self.node,
            )
        return self.default()


def is_sample(node: ast.Node) -> bool:
    """Whether ``node`` is a call of the built-in ``sample``."""
    return (
        isinstance(node, ast.Call)
        and isinstance(node.callee, ast.NameRef)
        and node.callee.name.namespace is None
        and node.callee.name.name.text == "sample"
    )


def sample_arguments(model: Model, call: ast.Call) -> dict[str, ast.Node]:
    """The arguments of a ``sample`` call by parameter name (expression, event, default),
    as the checker bound them (an ``@e`` argument is the event)."""
    binding = model.binding(call)
    if binding is None:
        raise CompileProblem("this `sample` was not bound by the checker", call)
    given: dict[str, ast.Node] = dict(binding.values())
    if binding.events and "event" not in given:
        given["event"] = binding.events[0]
    for p in VALUE_FUNCTIONS["sample"].parameters:
        if not p.optional and p.name not in given:
            raise CompileProblem(f"`sample` needs its argument `{p.name}`", call)
    return given


def compile_sample(
    env: Environment, call: ast.Call, scope: Bindings, text: str
) -> tuple[Closure, Sampler]:
    """The closure reading ``sample(...)`` and its sampler (registered with the run)."""
    args = sample_arguments(env.model, call)
    expression_node, event_node = args["expression"], args["event"]
    default_node = args.get("default")
    expression = env.compile(expression_node, scope)
    default = env.compile(default_node, scope) if default_node is not None else None
    watch = compile_watch(env, event_node, Bindings())
    name = _event_text(watch, event_node)
    sampler = Sampler(text, call, expression, default, name)
    ctx = env.run
    on_occurrence(ctx, watch, lambda: sampler.take(ctx))
    return sampler.read, sampler


def on_occurrence(ctx: RunContext, watch: Watch, callback: Callable[[], None]) -> None:
    """Call ``callback()`` at every occurrence of the watched event from the scenario's
    start: at the occurrence of a named event (the watch's condition, if any, decided on
    it), else when the polled watch reports one."""
    if isinstance(watch, NamedEventWatch) and watch.condition is None:
        ctx.listen(watch.name, lambda occurrence: callback())
        return
    started = [False]

    def poll() -> None:
        if not started[0]:
            started[0] = True
            watch.start()
        watch.drain(callback)

    ctx.poll(poll)


def _event_text(watch: Watch, node: ast.Node) -> str:
    if isinstance(watch, NamedEventWatch):
        return watch.name
    return "its event"
