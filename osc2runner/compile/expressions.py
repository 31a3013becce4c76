"""Expressions compiled once to closures, evaluated every tick against live state.

``compile(expr)`` walks the AST of an expression one time and returns a
zero-argument function; evaluating it reads only the execution context's
per-tick state (actor states, variables). Numbers are SI floats at run time
(units are folded into literals at compile time, exactly, then converted);
enum values are their member names; actors are :class:`~osc2runner.instance.actors.Actor`
objects. Sub-expressions without live inputs are folded at compile time.

Methods of the domain model that are ``is undefined`` (``object_distance``,
``position.ahead_of``, ...) are looked up in the method registry; methods
``is expression`` are compiled inline with their parameters bound.
"""

from __future__ import annotations

import operator
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol

from osc2check.semantics import types as T
from osc2check.semantics.bindings import python_arguments
from osc2check.semantics.builtins import EVENT_FUNCTIONS, PREDEFINED_EVENTS, VALUE_FUNCTIONS
from osc2check.semantics.constants import NotConstant, physical_literal, to_runtime
from osc2check.semantics.members import actor_alias
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast
from osc2runner.compile.text import unparse
from osc2runner.errors import CompileProblem
from osc2runner.execution.context import RunFault
from osc2runner.external import ExternalLoadError, ExternalRegistry
from osc2runner.instance.actors import Actor

if TYPE_CHECKING:
    from osc2check.semantics.model import Model
    from osc2runner.compile.registry import MethodRegistry
    from osc2runner.execution.context import RunContext
    from osc2runner.instance.values import ScenarioValues

__all__ = [
    "Bindings",
    "Closure",
    "Environment",
    "ExpressionCompiler",
    "Frame",
    "PositionOf",
    "constant",
    "read_variable",
]

Closure = Callable[[], Any]


@dataclass
class Frame:
    """One scenario instance being compiled: the root scenario, or one that it invokes.

    ``path`` names the instance as the checker's witness does (``""`` for the root,
    ``hero.cut_in@12`` for an invocation: ``osc2check.verify.terms.invocation_path``);
    ``fields`` are the closures of the instance's own parameters, actor parameters
    and variables; ``at_start`` the invocations of its behaviour that begin at time 0
    (the witness realised their ``at: start`` modifiers).
    """

    path: str
    scenario: Symbol
    fields: dict[Symbol, Closure] = field(default_factory=dict)
    actor: Closure | None = None
    at_start: frozenset[ast.Node] = frozenset()
    parent: Frame | None = None
    events: frozenset[str] = frozenset()  # the events the scenario declares
    labels: frozenset[str] = frozenset()  # the labels of its behaviour's members

    def qualified(self, name: str) -> str:
        """A name of this instance (a variable's, an event's) unique among instances."""
        return f"{self.path}.{name}" if self.path else name

    def event(self, path: tuple[str, ...]) -> str:
        """The run's name of the event ``path`` written in this instance: its own events
        (its ``start``/``end``/``fail``, the events it declares, its labels' events) are
        qualified by the instance's path; others (an actor's, the root's) are not."""
        name = ".".join(path)
        own = (len(path) == 1 and (path[0] in PREDEFINED_EVENTS or path[0] in self.events)) or (
            len(path) == 2 and path[0] in self.labels and path[1] in PREDEFINED_EVENTS
        )
        return self.qualified(name) if own else name


class Bindings:
    """Names bound while compiling: ``it``, ``actor``, event ``as`` aliases, method
    parameters, and the scenario instance (``frame``) being compiled."""

    def __init__(
        self,
        parent: Bindings | None = None,
        frame: Frame | None = None,
        bindings: Mapping[str, Closure] | None = None,
    ) -> None:
        self.parent = parent
        self.bindings: dict[str, Closure] = dict(bindings or {})
        self.frame: Frame | None = (
            frame if frame is not None else (parent.frame if parent else None)
        )

    def lookup(self, name: str) -> Closure | None:
        scope: Bindings | None = self
        while scope is not None:
            if name in scope.bindings:
                return scope.bindings[name]
            scope = scope.parent
        return None

    def child(self, **bindings: Closure) -> Bindings:
        return Bindings(self, bindings=bindings)

    def event(self, path: tuple[str, ...]) -> str:
        """The run's name of the event ``path`` written here (:meth:`Frame.event`)."""
        return self.frame.event(path) if self.frame is not None else ".".join(path)


class _Constant:
    """Marks a closure whose value is known at compile time."""

    __slots__ = ("value",)

    def __init__(self, value: object) -> None:
        self.value = value

    def __call__(self) -> object:
        return self.value


def constant(value: object) -> Closure:
    """A closure returning ``value``, recognised as constant by the compiler."""
    return _Constant(value)


def is_constant(fn: Closure) -> bool:
    return isinstance(fn, _Constant)


class PositionOf:
    """``actor.position`` (toolkit ``actor_position``): the actor whose position it is."""

    __slots__ = ("actor",)

    def __init__(self, actor: object) -> None:
        self.actor = actor


# Names a scope binds: `it`, `actor`, `as` aliases; a method's parameters while its body is
# compiled inline.
_BOUND_KINDS = (SymbolKind.IMPLICIT, SymbolKind.ARGUMENT)

_BINARY: dict[str, Callable[[Any, Any], Any]] = {
    "+": operator.add,
    "-": operator.sub,
    "*": operator.mul,
    "/": operator.truediv,
    "%": operator.mod,
    "==": operator.eq,
    "!=": operator.ne,
    "<": operator.lt,
    "<=": operator.le,
    ">": operator.gt,
    ">=": operator.ge,
}


class Environment(Protocol):
    """What compiling reads from its environment (the program's model, the instance's
    values, the method registry, the run context) and the compilers it offers.

    :class:`~osc2runner.compile.environment.CompileEnvironment` is the one there is; the
    compilers of expressions, conditions, samples and coverage take this Protocol so that
    none of them imports the module that builds them all.
    """

    @property
    def model(self) -> Model: ...
    @property
    def values(self) -> ScenarioValues: ...
    @property
    def registry(self) -> MethodRegistry: ...
    @property
    def run(self) -> RunContext: ...
    @property
    def actors(self) -> dict[str, Actor]: ...
    @property
    def variable_symbols(self) -> set[Symbol]: ...
    @property
    def compiler(self) -> ExpressionCompiler: ...

    def compile(self, expr: ast.Node, scope: Bindings | None = None) -> Closure: ...

    def actor_member(
        self, actor: Actor, member: str, sym: Symbol | None, node: ast.Node
    ) -> Closure: ...

    def sample(self, call: ast.Call, scope: Bindings, text: str) -> tuple[Closure, Any]:
        """The closure reading ``sample(...)`` and its sampler (registered with the run)."""
        ...


class ExpressionCompiler:
    """Compiles expression nodes of one program; the closures read the run context."""

    def __init__(self, env: Environment) -> None:
        self.env = env
        self.model = env.model
        self._references = [m.references for m in _chain(env.model)]
        #: ``var`` fields whose value is live (a ``sample``): the closure that reads them
        self.live_variables: dict[Symbol, Closure] = {}
        #: the ``sample`` calls compiled, in order (each has a sampler in the run)
        self.samplers: list[Any] = []
        #: Python functions of ``is external`` methods (:mod:`osc2runner.external`)
        self.externals = ExternalRegistry()
        self._inlining: list[Symbol] = []  # `is expression` methods being compiled inline

    def ref(self, name: ast.Name) -> Symbol | None:
        """What ``name`` refers to, in the program or in the library it builds on."""
        for table in self._references:
            sym: Symbol | None = table.get(name)
            if sym is not None:
                return sym
        return None

    # ---- entry

    def compile(self, expr: ast.Node, scope: Bindings | None = None) -> Closure:
        """A closure evaluating ``expr``; raises CompileProblem for what cannot run."""
        return self._c(expr, scope or Bindings())

    def constant_value(self, expr: ast.Node, scope: Bindings | None = None) -> object:
        """The value of an expression that must not depend on live state."""
        fn = self.compile(expr, scope)
        if not is_constant(fn):
            raise CompileProblem("this value must be known before the run starts", expr)
        return fn()

    # ---- dispatch

    def _c(self, e: ast.Node, scope: Bindings) -> Closure:
        match e:
            case ast.IntLiteral() | ast.StringLiteral() | ast.BoolLiteral():
                return constant(e.value)
            case ast.FloatLiteral():
                return constant(float(e.value))
            case ast.PhysicalLiteral():
                try:
                    return constant(float(physical_literal(e, self.model).si))
                except NotConstant as exc:
                    raise CompileProblem(str(exc), e) from None
            case ast.EnumRef():
                return constant(e.member.text)
            case ast.ListLiteral():
                items = [self._c(i, scope) for i in e.items]
                if all(is_constant(i) for i in items):
                    return constant(tuple(i() for i in items))
                return lambda: tuple(i() for i in items)
            case ast.RangeLiteral():
                lo, hi = self._c(e.low, scope), self._c(e.high, scope)
                if is_constant(lo) and is_constant(hi):
                    return constant((lo(), hi()))
                return lambda: (lo(), hi())
            case ast.NameRef():
                return self._name(e, scope)
            case ast.Unary():
                return self._unary(e, scope)
            case ast.Binary():
                return self._binary(e, scope)
            case ast.Ternary():
                return self._ternary(e, scope)
            case ast.Index():
                target, index = self._c(e.target, scope), self._c(e.index, scope)
                return lambda: target()[index()]
            case ast.MemberAccess():
                return self._member(e, scope)
            case ast.Call():
                return self._call(e, scope)
            case ast.Missing():
                raise CompileProblem("incomplete expression", e)
        raise CompileProblem(f"the runner cannot evaluate {type(e).__name__} expressions", e)

    # ---- names

    def _name(self, e: ast.NameRef, scope: Bindings) -> Closure:
        name = e.name.name
        bound = scope.lookup(name.text) if e.name.namespace is None else None
        sym = self.ref(name)
        if bound is not None and (sym is None or sym.kind in _BOUND_KINDS):
            return bound
        if sym is None:
            raise CompileProblem(f"`{name.text}` has no meaning here for the runner", e)
        frame = scope.frame
        while frame is not None:  # an instance's own fields, then its invoker's
            if sym in frame.fields:
                return frame.fields[sym]
            frame = frame.parent
        if name.text == "actor" and scope.frame is not None and scope.frame.actor is not None:
            return scope.frame.actor
        return self.symbol_value(sym, e)

    def symbol_value(self, sym: Symbol, node: ast.Node) -> Closure:
        """The closure for a referenced symbol (field, variable, enum member, ...)."""
        env = self.env
        if sym.kind is SymbolKind.ENUM_MEMBER:
            return constant(sym.name)
        if sym.kind is SymbolKind.GLOBAL:  # `global min_gap: length = 10m`: the witness's
            try:
                return constant(to_runtime(env.values.value(sym)))
            except NotConstant as exc:
                raise CompileProblem(str(exc), node) from None
        if sym.kind in (SymbolKind.FIELD, SymbolKind.VARIABLE):
            named = actor_alias(self.model, sym) or sym  # `other: vehicle = npc` is npc
            actor = env.actors.get(named.name)
            if actor is not None and actor.symbol is named:
                return constant(actor)
            live = self.live_variables.get(sym)
            if live is not None:
                return live
            if sym in env.variable_symbols:
                store = env.run.variables
                key = sym.name
                if key in store:
                    return (
                        constant(store[key])
                        if sym.kind is SymbolKind.FIELD
                        else (lambda: store[key])
                    )
                return lambda: read_variable(store, key, node)
            if sym.kind is SymbolKind.VARIABLE:  # never from the witness: not a parameter
                raise CompileProblem(f"the variable `{sym.name}` has no value here", node)
            try:
                return constant(to_runtime(env.values.value(sym)))
            except NotConstant as exc:
                raise CompileProblem(str(exc), node) from None
        if sym.kind is SymbolKind.IMPLICIT:
            raise CompileProblem(f"`{sym.name}` is not bound here", node)
        raise CompileProblem(f"the {sym.kind.value} `{sym.name}` is not a value", node)

    # ---- operators

    def _unary(self, e: ast.Unary, scope: Bindings) -> Closure:
        operand = self._c(e.operand, scope)
        fn: Callable[[Any], Any]
        if e.op == "not":
            fn = operator.not_
        elif e.op == "-":
            fn = operator.neg
        else:
            return operand
        if is_constant(operand):
            return constant(fn(operand()))
        return lambda: fn(operand())

    def _binary(self, e: ast.Binary, scope: Bindings) -> Closure:
        left, right = self._c(e.left, scope), self._c(e.right, scope)
        op = e.op
        if op == "and":
            fn: Callable[[], Any] = lambda: bool(left()) and bool(right())  # noqa: E731
        elif op == "or":
            fn = lambda: bool(left()) or bool(right())  # noqa: E731
        elif op == "=>":
            fn = lambda: (not left()) or bool(right())  # noqa: E731
        elif op == "in":
            fn = lambda: _contains(right(), left())  # noqa: E731
        else:
            binary = _BINARY.get(op)
            if binary is None:
                raise CompileProblem(f"the runner cannot evaluate `{op}`", e)
            if op in ("==", "!="):
                binary = _equality(op)
            fn = lambda: binary(left(), right())  # noqa: E731
        if is_constant(left) and is_constant(right):
            try:
                return constant(fn())
            except ZeroDivisionError:
                raise CompileProblem("division by zero", e) from None
        return fn

    def _ternary(self, e: ast.Ternary, scope: Bindings) -> Closure:
        cond = self._c(e.condition, scope)
        then, other = self._c(e.then, scope), self._c(e.otherwise, scope)
        if is_constant(cond):
            return then if cond() else other
        return lambda: then() if cond() else other()

    # ---- members and calls

    def _member(self, e: ast.MemberAccess, scope: Bindings) -> Closure:
        target = self._c(e.target, scope)
        member = e.member.text
        sym = self.ref(e.member)
        if is_constant(target):
            value = target()
            if isinstance(value, Actor):
                return self.env.actor_member(value, member, sym, e)
        env = self.env

        def access() -> object:
            value = target()
            if isinstance(value, Actor):
                return env.actor_member(value, member, sym, e)()
            if isinstance(value, dict):
                return value[member]
            return getattr(value, member)

        return access

    def _call(self, e: ast.Call, scope: Bindings) -> Closure:
        callee = e.callee
        if isinstance(callee, ast.NameRef) and self.ref(callee.name.name) is None:
            fname = callee.name.name.text
            if fname in EVENT_FUNCTIONS:
                raise CompileProblem(
                    f"`{fname}(...)` is an event; use it in `wait`, `until` or `on`", e
                )
            if fname in VALUE_FUNCTIONS:
                return self._value_function(fname, e, scope)
        if isinstance(callee, ast.MemberAccess):
            method = self.ref(callee.member)
            if method is None or method.kind is not SymbolKind.METHOD:
                raise CompileProblem(f"`{callee.member.text}` is not a method the runner knows", e)
            target = self._c(callee.target, scope)
            return self._method_call(method, target, e, scope)
        if isinstance(callee, ast.NameRef):
            method = self.ref(callee.name.name)
            if method is not None and method.kind is SymbolKind.METHOD:
                owner = scope.lookup("actor")
                return self._method_call(method, owner or constant(None), e, scope)
        raise CompileProblem("the runner cannot call this", e)

    def _value_function(self, fname: str, e: ast.Call, scope: Bindings) -> Closure:
        """``sample(expression, event[, default])`` and ``range(low, high)``."""
        if fname == "sample":
            read, sampler = self.env.sample(e, scope, unparse(e))
            self.samplers.append(sampler)
            return read
        binding = self.model.binding(e)
        low, high = (binding.value(n) if binding else None for n in ("low", "high"))
        if low is None or high is None:
            raise CompileProblem("`range` needs two bounds", e)
        return self._c(ast.RangeLiteral(e.span, low, high), scope)

    def _arguments(self, method: Symbol, call: ast.Call, scope: Bindings) -> list[Closure]:
        """The closures of a method call's arguments in parameter order, as the checker
        bound them (a default is compiled in no scope of the call's)."""
        binding = self.model.binding(call)
        if binding is None:
            raise CompileProblem(f"the call of `{method.name}` was not bound by the checker", call)
        result = []
        for p in method.parameters:
            bound = binding.argument(p.name)
            if bound is None:
                raise CompileProblem(f"`{method.name}` needs its argument `{p.name}`", call)
            result.append(self._c(bound.value, Bindings() if bound.is_default else scope))
        return result

    def _method_call(
        self, method: Symbol, target: Closure, call: ast.Call, scope: Bindings
    ) -> Closure:
        """A method call: ``is expression`` bodies compiled inline with the parameters
        bound to the argument closures; ``is external`` through the external registry;
        ``is undefined`` through the method registry (the runner's implementations)."""
        args = self._arguments(method, call, scope)
        decl = method.decl
        if isinstance(decl, ast.MethodDecl) and decl.kind == "expression" and decl.body is not None:
            if any(m is method for m in self._inlining):
                raise CompileProblem(
                    f"`{method.name}` calls itself: recursive methods are not supported", call
                )
            bindings = {p.name: a for p, a in zip(method.parameters, args, strict=True)}
            self._inlining.append(method)
            try:
                return self._c(decl.body, Bindings(None, bindings={"actor": target, **bindings}))
            finally:
                self._inlining.pop()
        if isinstance(decl, ast.MethodDecl) and decl.kind == "external":
            return self._external_call(method, decl, target, args, call)
        entry = self.env.registry.find_method(self.model, method)
        if entry is None:
            owner = method.owner.name if method.owner is not None else ""
            raise CompileProblem(
                f"method `{owner}.{method.name}` has no runner implementation", call
            )
        fn = entry.target
        ctx = self.env.run
        if len(args) == 1:
            a0 = args[0]
            return lambda: fn(ctx, target(), a0())
        if len(args) == 2:
            a0, a1 = args
            return lambda: fn(ctx, target(), a0(), a1())
        return lambda: fn(ctx, target(), *(a() for a in args))

    def _external_call(
        self,
        method: Symbol,
        decl: ast.MethodDecl,
        target: Closure,
        args: list[Closure],
        call: ast.Call,
    ) -> Closure:
        """``def m(x: speed) -> bool is external pkg.mod.fn(x, limit: 3kph)``: the external
        arguments are evaluated with the parameters bound (SI values) and passed to the
        registered Python function, positional then by keyword; an empty argument list
        passes the method's parameters in order."""
        name = ".".join(n.text for n in decl.external)
        try:
            found = self.externals.find(name)
        except ExternalLoadError as exc:
            raise CompileProblem(str(exc), decl) from None
        if found is None:
            raise CompileProblem(
                f"no external function `{name}` is registered: mark a Python function "
                f'with @external("{name}") in an importable module (docs/runner.md)',
                decl,
            )
        bindings = {p.name: a for p, a in zip(method.parameters, args, strict=True)}
        inner = Bindings(None, bindings={"actor": target, **bindings})
        written, named, events = python_arguments(decl.external_arguments)
        if events:
            raise CompileProblem("an event is not an argument of an external method", events[0])
        positional = [self._c(value, inner) for value in written]
        keywords = {key: self._c(value, inner) for key, value in named.items()}
        if not decl.external_arguments:
            positional = list(args)
        convert = _result_conversion(method)
        return found.closure(positional, keywords, convert, call)


def read_variable(store: dict[str, Any], key: str, node: ast.Node) -> Any:
    """The value of the variable ``key``; reading one that has none fails the run."""
    try:
        return store[key]
    except KeyError:
        raise RunFault(f"the variable `{key}` has no value (it has no initialiser)", node) from None


def _result_conversion(method: Symbol) -> Callable[[Any], Any]:
    """How an external function's result becomes a run-time value of the method's type."""
    t = method.type
    if t is None or t.kind is T.Kind.NONE:
        return lambda value: None
    if t.kind is T.Kind.BOOL:
        return bool
    if t.kind in (T.Kind.INT, T.Kind.UINT):
        return int
    if t.kind in (T.Kind.FLOAT, T.Kind.PHYSICAL):
        return float
    return lambda value: value


def _chain(model: Any) -> list[Any]:
    models = []
    while model is not None:
        models.append(model)
        model = model.base
    return models


def _contains(container: object, value: object) -> bool:
    if (
        isinstance(container, tuple)
        and len(container) == 2
        and all(isinstance(v, (int, float)) for v in container)
    ):
        lo, hi = container
        inside: bool = min(lo, hi) <= value <= max(lo, hi)
        return inside
    return value in container  # type: ignore[operator]


def _equality(op: str) -> Callable[[Any, Any], bool]:
    tolerance = 1e-9

    def eq(a: Any, b: Any) -> bool:
        if isinstance(a, float) or isinstance(b, float):
            try:
                close: bool = abs(a - b) <= tolerance * max(1.0, abs(a), abs(b))
                return close
            except TypeError:
                return bool(a == b)
        return bool(a == b)

    if op == "==":
        return eq
    return lambda a, b: not eq(a, b)
