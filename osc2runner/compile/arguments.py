"""What an invocation gives its behaviour: its arguments as the checker bound them.

The arguments of an action or a modifier become closures by parameter name; a range
given where a scalar is expected, and a parameter a ``keep`` of the call's ``with:``
gives, are the values the checker's witness chose under the call's instance path (as
``osc2check.verify.terms`` names it). The fields of an invoked scenario's instance are
the witness's values, the actors its arguments pass, and its ``var``s (initialised when
the instance starts, or live when they hold a ``sample``).
"""

from __future__ import annotations

from collections.abc import Callable

from osc2check.semantics import types as T
from osc2check.semantics.bindings import Binding, note_read
from osc2check.semantics.builtins import OVERLAP_KINDS
from osc2check.semantics.constants import NotConstant, to_runtime
from osc2check.semantics.phases import enum_word
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast
from osc2check.syntax.walk import walk
from osc2runner.compile.expressions import (
    Bindings,
    Closure,
    Environment,
    Frame,
    constant,
    read_variable,
)
from osc2runner.compile.sampling import is_sample
from osc2runner.errors import CompileProblem
from osc2runner.instance.actors import Actor

__all__ = [
    "call_arguments",
    "checked_binding",
    "instance_field",
    "overlap_kind",
    "scenario_arguments",
]


def checked_binding(env: Environment, call: ast.Node) -> Binding:
    """The checker's binding of ``call``'s arguments (every checked call has one)."""
    binding = env.model.binding(call)
    if binding is None:
        raise CompileProblem("the checker bound no arguments here", call)
    return binding


def call_arguments(
    env: Environment, call: ast.Invocation, scope: Bindings, path: str, *, defaults: bool = False
) -> tuple[dict[str, Closure], ast.Node | None]:
    """The closures of the arguments given to an action or modifier by parameter name
    (as the checker bound them; with ``defaults``, the declared defaults of those not
    given too), and its duration. A range given where a scalar is expected is one
    value the solver chose from it (``keep(p in r)``): the witness's, under the
    call's instance ``path`` (as ``verify.terms`` names it)."""
    binding = checked_binding(env, call)
    if binding.events:
        raise CompileProblem("event arguments are not supported here", binding.events[0])
    result: dict[str, Closure] = {}
    declared: dict[str, Closure] = {}
    for bound in binding.arguments:
        if bound.is_default:
            if defaults:
                declared[bound.name] = env.compile(bound.value, Bindings())
            continue
        if bound.range and bound.parameter is not None:
            result[bound.name] = _chosen(env, path, bound.parameter, bound.value)
        else:
            result[bound.name] = env.compile(bound.value, scope)
    callee = binding.callee
    if isinstance(callee, Symbol) and callee.kind is SymbolKind.ACTION:
        # a parameter that a `keep` of the call's `with:` gives: the witness's value
        for param in env.model.parameters(callee):
            if param.name in result or binding.given(param.name) is not None:
                continue
            kept = env.values.kept(path, param)
            if kept is not None:
                result[param.name] = constant(to_runtime(kept))
    if defaults and isinstance(callee, Symbol):
        _kept(env, callee, path, result)
        result = {**declared, **result}
    duration = binding.extra("duration")
    if duration is not None:  # the phase's bound (``_wrap``) and the plans' (ActionUse)
        note_read(call, "duration")
    return result, duration.value if duration is not None else None


def _kept(env: Environment, callee: Symbol, path: str, result: dict[str, Closure]) -> None:
    """The parameters of a plug-in's behaviour given no argument whose value the
    witness chose (a ``keep`` of the invocation's ``with:``; else their defaults)."""
    for param in env.model.all_members(callee):
        if param.kind is not SymbolKind.FIELD or param.name in result:
            continue
        try:
            value = to_runtime(env.values.value_at(path, param))
        except NotConstant:
            continue  # its default, or none: the checker required what has none
        result[param.name] = constant(value)


def _chosen(env: Environment, path: str, param: Symbol, where: ast.Node) -> Closure:
    """The witness's value of parameter ``param`` of the call at ``path``."""
    try:
        return constant(to_runtime(env.values.value_at(path, param)))
    except NotConstant:
        raise CompileProblem(
            f"`{param.name}` is given a range and the checker's witness chose no value from it",
            where,
        ) from None


def scenario_arguments(
    env: Environment, inv: ast.Invocation
) -> tuple[dict[str, ast.Node], ast.Node | None]:
    """The arguments of a scenario invocation by parameter name, and its duration."""
    binding = checked_binding(env, inv)
    duration = binding.extra("duration")
    return dict(binding.values(defaults=False)), duration.value if duration else None


def instance_field(
    env: Environment,
    param: Symbol,
    frame: Frame,
    given: dict[str, ast.Node],
    inv: ast.Invocation,
    scope: Bindings,
    inner: Bindings,
    initialisers: list[Callable[[], None]],
) -> Closure:
    """The closure of one field of an invoked scenario's instance (``frame``): its
    arguments ``given`` are compiled in the invoking ``scope``, its ``var``s' initialisers
    in the instance's ``inner`` one. A ``var`` with an initialiser adds its
    initialisation to ``initialisers`` (run when the instance starts), unless it holds a
    ``sample`` (then it is live)."""
    t = param.type
    if t is not None and t.kind is T.Kind.COMPOUND and t.symbol is not None:
        if t.symbol.kind is SymbolKind.ACTOR:
            if param.name not in given:
                raise CompileProblem(
                    f"the runner needs the actor parameter `{param.name}` of "
                    f"`{param.owner.name if param.owner else ''}` passed as an argument "
                    f"(`{param.name}: <an actor>`)",
                    inv,
                )
            value = env.compiler.constant_value(given[param.name], scope)
            if not isinstance(value, Actor):
                raise CompileProblem(f"`{param.name}` must be given an actor", inv)
            return constant(value)
    if param.kind is SymbolKind.VARIABLE:
        default = param.default
        if default is not None and any(is_sample(node) for node in walk(default)):
            return env.compile(default, inner)
        store, key = env.run.variables, frame.qualified(param.name)
        if default is not None:
            init = env.compile(default, inner)

            def initialise(init: Closure = init, key: str = key) -> None:
                store[key] = init()

            initialisers.append(initialise)
        where: ast.Node = param.decl or inv
        return lambda: read_variable(store, key, where)
    try:
        return constant(to_runtime(env.values.value_at(frame.path, param)))
    except NotConstant:
        if param.name in given:
            return env.compile(given[param.name], scope)
        raise CompileProblem(
            f"`{param.name}` of the invoked scenario has no value in the checker's witness",
            inv,
        ) from None


def overlap_kind(node: ast.Node) -> str:
    """The overlap kind a ``parallel(overlap: ...)`` names (the checker validated it)."""
    word = enum_word(node)
    if word is None:
        raise CompileProblem("`overlap` takes one of the overlap kinds", node)
    if word not in OVERLAP_KINDS:
        raise CompileProblem(f"`{word}` is not an overlap kind ({', '.join(OVERLAP_KINDS)})", node)
    return word
