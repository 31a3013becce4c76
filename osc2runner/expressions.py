"""Expressions compiled once to closures, evaluated every tick against live state.

``compile(expr)`` walks the AST of an expression one time and returns a
zero-argument function; evaluating it reads only the execution context's
per-tick state (actor states, variables). Numbers are SI floats at run time
(units are folded into literals at compile time, exactly, then converted);
enum values are their member names; actors are :class:`~osc2runner.actors.Actor`
objects. Sub-expressions without live inputs are folded at compile time.

Methods of the domain model that are ``is undefined`` (``object_distance``,
``position.ahead_of``, ...) are looked up in the method registry; methods
``is expression`` are compiled inline with their parameters bound.
"""

from __future__ import annotations

import operator
from collections.abc import Callable
from types import SimpleNamespace
from typing import TYPE_CHECKING, Any

from osc2check.semantics import types as T
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast
from osc2runner.errors import CompileProblem
from osc2runner.values import NoValue, to_runtime

if TYPE_CHECKING:
    from osc2runner.context import ExecutionContext

__all__ = ["Closure", "ExpressionCompiler", "Scope", "PositionOf", "constant"]

Closure = Callable[[], Any]

EVENT_FUNCTIONS = frozenset({"rise", "fall", "elapsed", "every"})


class Scope:
    """Names bound while compiling: ``it``, ``actor``, event ``as`` aliases, method parameters."""

    def __init__(self, parent: Scope | None = None, **bindings: Closure) -> None:
        self.parent = parent
        self.bindings = dict(bindings)

    def lookup(self, name: str) -> Closure | None:
        scope: Scope | None = self
        while scope is not None:
            if name in scope.bindings:
                return scope.bindings[name]
            scope = scope.parent
        return None

    def child(self, **bindings: Closure) -> Scope:
        return Scope(self, **bindings)


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


class ExpressionCompiler:
    """Compiles expression nodes of one program against an execution context."""

    def __init__(self, ctx: ExecutionContext) -> None:
        self.ctx = ctx
        self.model = ctx.model
        self._references = [m.references for m in _chain(ctx.model)]
        self._types = [m.expr_types for m in _chain(ctx.model)]

    def ref(self, name: ast.Name) -> Symbol | None:
        """What ``name`` refers to, in the program or in the library it builds on."""
        for table in self._references:
            sym = table.get(name)
            if sym is not None:
                return sym
        return None

    def type_of(self, node: ast.Node) -> T.Type | None:
        for table in self._types:
            t = table.get(node)
            if t is not None:
                return t
        return None

    # ---- entry

    def compile(self, expr: ast.Node, scope: Scope | None = None) -> Closure:
        """A closure evaluating ``expr``; raises CompileProblem for what cannot run."""
        return self._c(expr, scope or Scope())

    def constant_value(self, expr: ast.Node, scope: Scope | None = None) -> object:
        """The value of an expression that must not depend on live state."""
        fn = self.compile(expr, scope)
        if not is_constant(fn):
            raise CompileProblem("this value must be known before the run starts", expr)
        return fn()

    # ---- dispatch

    def _c(self, e: ast.Node, scope: Scope) -> Closure:
        method = getattr(self, f"_{type(e).__name__}", None)
        if method is None:
            raise CompileProblem(f"the runner cannot evaluate {type(e).__name__} expressions", e)
        return method(e, scope)

    # ---- literals

    def _IntLiteral(self, e: ast.IntLiteral, scope: Scope) -> Closure:
        return constant(e.value)

    def _FloatLiteral(self, e: ast.FloatLiteral, scope: Scope) -> Closure:
        return constant(float(e.value))

    def _StringLiteral(self, e: ast.StringLiteral, scope: Scope) -> Closure:
        return constant(e.value)

    def _BoolLiteral(self, e: ast.BoolLiteral, scope: Scope) -> Closure:
        return constant(e.value)

    def _PhysicalLiteral(self, e: ast.PhysicalLiteral, scope: Scope) -> Closure:
        unit = self.ref(e.unit) or self.model.unit(e.unit.text)
        if unit is None:
            raise CompileProblem(f"unknown unit `{e.unit.text}`", e)
        from fractions import Fraction

        number = e.number if isinstance(e.number, Fraction) else Fraction(e.number)
        return constant(float(number * unit.factor + unit.offset))

    def _EnumRef(self, e: ast.EnumRef, scope: Scope) -> Closure:
        return constant(e.member.text)

    def _Missing(self, e: ast.Missing, scope: Scope) -> Closure:
        raise CompileProblem("incomplete expression", e)

    def _ListLiteral(self, e: ast.ListLiteral, scope: Scope) -> Closure:
        items = [self._c(i, scope) for i in e.items]
        if all(is_constant(i) for i in items):
            return constant(tuple(i() for i in items))
        return lambda: tuple(i() for i in items)

    def _RangeLiteral(self, e: ast.RangeLiteral, scope: Scope) -> Closure:
        lo, hi = self._c(e.low, scope), self._c(e.high, scope)
        if is_constant(lo) and is_constant(hi):
            return constant((lo(), hi()))
        return lambda: (lo(), hi())

    # ---- names

    def _NameRef(self, e: ast.NameRef, scope: Scope) -> Closure:
        name = e.name.name
        bound = scope.lookup(name.text) if e.name.namespace is None else None
        sym = self.ref(name)
        if bound is not None and (sym is None or sym.kind is SymbolKind.IMPLICIT):
            return bound
        if sym is None:
            raise CompileProblem(f"`{name.text}` has no meaning here for the runner", e)
        return self.symbol_value(sym, e)

    def symbol_value(self, sym: Symbol, node: ast.Node) -> Closure:
        """The closure for a referenced symbol (field, variable, enum member, ...)."""
        ctx = self.ctx
        if sym.kind is SymbolKind.ENUM_MEMBER:
            return constant(sym.name)
        if sym.kind in (SymbolKind.FIELD, SymbolKind.VARIABLE):
            actor = ctx.actors.get(sym.name)
            if actor is not None and actor.symbol is sym:
                return constant(actor)
            if sym in ctx.variable_symbols:
                store = ctx.variables
                key = sym.name
                if key in store:
                    return (
                        constant(store[key])
                        if sym.kind is SymbolKind.FIELD
                        else (lambda: store[key])
                    )
                return lambda: store[key]
            try:
                return constant(to_runtime(ctx.values.value(sym)))
            except NoValue as exc:
                raise CompileProblem(str(exc), node) from None
        if sym.kind is SymbolKind.IMPLICIT:
            raise CompileProblem(f"`{sym.name}` is not bound here", node)
        raise CompileProblem(f"the {sym.kind.value} `{sym.name}` is not a value", node)

    # ---- operators

    def _Unary(self, e: ast.Unary, scope: Scope) -> Closure:
        operand = self._c(e.operand, scope)
        if e.op == "not":
            fn = operator.not_
        elif e.op == "-":
            fn = operator.neg
        else:
            return operand
        if is_constant(operand):
            return constant(fn(operand()))
        return lambda: fn(operand())

    def _Binary(self, e: ast.Binary, scope: Scope) -> Closure:
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
        elif op == "/" and self._integral(e.left) and self._integral(e.right):
            fn = lambda: left() // right()  # noqa: E731
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

    def _integral(self, e: ast.Node) -> bool:
        t = self.type_of(e)
        return t is not None and t.kind in (T.Kind.INT, T.Kind.UINT)

    def _Ternary(self, e: ast.Ternary, scope: Scope) -> Closure:
        cond = self._c(e.condition, scope)
        then, other = self._c(e.then, scope), self._c(e.otherwise, scope)
        if is_constant(cond):
            return then if cond() else other
        return lambda: then() if cond() else other()

    def _Index(self, e: ast.Index, scope: Scope) -> Closure:
        target, index = self._c(e.target, scope), self._c(e.index, scope)
        return lambda: target()[index()]

    # ---- members and calls

    def _MemberAccess(self, e: ast.MemberAccess, scope: Scope) -> Closure:
        target = self._c(e.target, scope)
        member = e.member.text
        sym = self.ref(e.member)
        if is_constant(target):
            value = target()
            from osc2runner.actors import Actor

            if isinstance(value, Actor):
                return self.ctx.actor_member(value, member, sym, e)
        ctx = self.ctx

        def access() -> object:
            value = target()
            from osc2runner.actors import Actor

            if isinstance(value, Actor):
                return ctx.actor_member(value, member, sym, e)()
            if isinstance(value, dict):
                return value[member]
            return getattr(value, member)

        return access

    def _Call(self, e: ast.Call, scope: Scope) -> Closure:
        callee = e.callee
        if (
            isinstance(callee, ast.NameRef)
            and callee.name.name.text in EVENT_FUNCTIONS
            and self.ref(callee.name.name) is None
        ):
            raise CompileProblem(
                f"`{callee.name.name.text}(...)` is an event; use it in `wait`, `until` or `on`", e
            )
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

    def _arguments(self, method: Symbol, call: ast.Call, scope: Scope) -> list[Closure]:
        params = list(method.parameters)
        given: dict[str, Closure] = {}
        position = 0
        for arg in call.arguments:
            if isinstance(arg, ast.PositionalArgument):
                if position >= len(params):
                    raise CompileProblem(f"too many arguments for `{method.name}`", arg)
                given[params[position].name] = self._c(arg.value, scope)
                position += 1
            elif isinstance(arg, ast.NamedArgument):
                given[arg.name.text] = self._c(arg.value, scope)
            else:
                raise CompileProblem("event arguments are not supported in calls", arg)
        result = []
        for p in params:
            if p.name in given:
                result.append(given[p.name])
            elif p.default is not None:
                result.append(self._c(p.default, scope))
            else:
                raise CompileProblem(f"`{method.name}` needs its argument `{p.name}`", call)
        return result

    def _method_call(
        self, method: Symbol, target: Closure, call: ast.Call, scope: Scope
    ) -> Closure:
        args = self._arguments(method, call, scope)
        decl = method.decl
        if isinstance(decl, ast.MethodDecl) and decl.kind == "expression" and decl.body is not None:
            bindings = {p.name: a for p, a in zip(method.parameters, args, strict=True)}
            inner = Scope(None, actor=target, **bindings)
            return self._c(decl.body, inner)
        entry = self.ctx.registry.find_method(self.model, method)
        if entry is None:
            owner = method.owner.name if method.owner is not None else ""
            raise CompileProblem(
                f"method `{owner}.{method.name}` has no runner implementation", call
            )
        fn = entry.target
        ctx = self.ctx
        if len(args) == 1:
            a0 = args[0]
            return lambda: fn(ctx, target(), a0())
        if len(args) == 2:
            a0, a1 = args
            return lambda: fn(ctx, target(), a0(), a1())
        return lambda: fn(ctx, target(), *(a() for a in args))


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
        return min(lo, hi) <= value <= max(lo, hi)  # type: ignore[operator]
    return value in container  # type: ignore[operator]


def _equality(op: str) -> Callable[[Any, Any], bool]:
    tolerance = 1e-9

    def eq(a: Any, b: Any) -> bool:
        if isinstance(a, float) or isinstance(b, float):
            try:
                return abs(a - b) <= tolerance * max(1.0, abs(a), abs(b))
            except TypeError:
                return a == b
        return a == b

    if op == "==":
        return eq
    return lambda a, b: not eq(a, b)


def namespace(**values: object) -> SimpleNamespace:
    """A struct value (``velocity.translational.x``)."""
    return SimpleNamespace(**values)
