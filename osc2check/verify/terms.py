"""The term encoder: a scenario's expressions as solver terms in one instance, the
variables of the parameters they name, and the names every lowering step shares.

A parameter is named by its instance path (``npc.vehicle_category``,
``hero.drive@31.duration``: ``invocation_path``) and becomes a variable when first
mentioned; naming a member of an instance not lowered yet lowers that instance (the
instance tree's, ``parameters.Lowerer``). Values are exact: physical literals become SI
rationals through the unit's factor and offset; strings and enum members become
integers. What the solver cannot take raises ``NotEncodable``; the caller records it
(C411), never drops it. A `var` is its initialiser at the start when that can be
encoded, and otherwise has no value here (``TermEncoder._variable``). Quotients and
remainders are exact (``ir.guarded`` keeps divisors off 0), calls of `is expression`
methods are inlined, and conversions that keep the value are the value.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal

from osc2check.semantics import types as T
from osc2check.semantics.builtins import TYPE_TESTS
from osc2check.semantics.constants import NotConstant, literal_number, physical_literal
from osc2check.semantics.members import declaration_bodies
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.verify import ir
from osc2check.verify.problem import ConstraintProblem
from osc2check.verify.structs import is_scalar

MAX_DEPTH = 8  # scenario invocations nested deeper than this are not lowered
_DISPLAY_UNITS: dict[tuple[int, ...], str] = {  # dimension -> unit the witness shows
    (1, 0, -1, 0, 0, 0, 0, 0): "kph",
    (1, 0, -2, 0, 0, 0, 0, 0): "mpsps",
    (1, 0, 0, 0, 0, 0, 0, 0): "m",
    (0, 0, 1, 0, 0, 0, 0, 0): "s",
    (0, 0, 0, 0, 0, 0, 0, 1): "deg",
}
_CMP = {"==", "!=", "<", "<=", ">", ">="}

# The source text of a span.
TextOf = Callable[[Span], str]
# A parameter's implicit domain: lowest and highest value, or the values it may take.
_Domain = tuple[ir.Const | None, ir.Const | None, tuple[ir.Const, ...] | None]
# How a parameter becomes a variable: its sort, the Var's details, its domain and the
# domain's text; False for a parameter that is not a scalar.
VarKind = tuple[str, ir.VarDetails, _Domain | None, str] | Literal[False]


class NotEncodable(Exception):
    """An expression the solver cannot take (a method call, a list, ...)."""


@dataclass
class InstanceScope:
    prefix: str  # path of the instance whose members are in scope ("" = top scenario)
    owner: Symbol | None
    it: str | None  # path `it` stands for
    it_symbol: Symbol | None = None
    actor: str | None = None  # path of `actor`
    locals: dict[str, str] = field(default_factory=dict)
    it_field: Symbol | None = None  # the field `it` stands for in a field's `with:` block


def join_path(prefix: str, name: str) -> str:
    """``name`` under the instance path ``prefix`` (the root's path is empty)."""
    return f"{prefix}.{name}" if prefix else name


def one_of_choice(prefix: str, comp: ast.Composition) -> str:
    """The witness's variable of which acting member the ``one_of`` ``comp`` of the
    instance at ``prefix`` runs (0 for the first): the placement places the actors for
    that member, and the runner's ``OneOf`` runs it."""
    return join_path(prefix, f"one_of@{comp.span.line}:{comp.span.column}{_CHOICE}")


_CHOICE = ".member"


def one_of_variable(prefix: str, comp: ast.Composition) -> ir.Var:
    """The variable :func:`one_of_choice` names: one per ``one_of``, which the placement
    (the members' starts) and the timing (their durations) share."""
    return ir.Var(one_of_choice(prefix, comp), "int", span=comp.span)


def is_one_of_choice(name: str) -> bool:
    """Whether ``name`` is a variable :func:`one_of_choice` names."""
    last = name.rsplit(".", 2)[-2:]
    return name.endswith(_CHOICE) and len(last) == 2 and last[0].startswith("one_of@")


def invocation_path(
    prefix: str, actor_path: str | None, label: ast.Name | None, name: str, inv: ast.Invocation
) -> str:
    """The instance path of an invocation: under the enclosing instance, its label (a
    label is unique in its scenario: ``tight``, ``tight.passing``), else its actor and
    ``name@line`` (``hero.cut_in@12``; inside that instance, ``hero.cut_in@12.npc.drive@8``).
    The witness names an invoked scenario's parameters under it; the runner reads them
    there, and names the instance's events after it."""
    if label is not None:
        return join_path(prefix, label.text)
    own = f"{name}@{inv.span.line}"
    return join_path(join_path(prefix, actor_path) if actor_path else prefix, own)


class TermEncoder(ABC):
    """Expressions as terms, and the variables they name, into ``problem``; the state
    the lowering steps share (string constants, instances, aliases, defaults to attach)."""

    def __init__(
        self,
        model: Model,
        problem: ConstraintProblem,
        text_of: TextOf,
        member_decls: Declarations | None = None,
    ):
        self.model = model
        self.problem = problem
        self.text_of = text_of
        self.strings: dict[str, int] = {}
        self.string_spans: dict[str, list[Span]] = {}  # where each string constant is written
        self.instances: dict[str, Symbol] = {}  # path -> type of the compound instance there
        # (path, field, declaration, scope, where its default goes in the constraint list,
        # the body it is written in)
        self.pending_defaults: list[tuple[str, Symbol, ast.FieldDecl, InstanceScope, int, str]] = []
        self.member_decls = member_decls if member_decls is not None else member_declarations(model)
        self.kinds = self.member_decls.kinds  # shared by the scenarios of a model
        self.depth = 0
        self.active: list[Symbol] = []
        self.body = ""  # the declaration whose members are being lowered (C404 compares)
        self.aliases: dict[str, str] = {}  # an invoked scenario's actor parameter -> the actor
        #: the variable of each argument, by (instance, value node): a range given where a
        #: scalar is expected is the one value the solver chose from it
        self.argument_vars: dict[tuple[str, int], ir.Var] = {}
        self.runtime: dict[str, str] = {}  # `var`s with no value before the run: why
        self.opening: set[str] = set()  # `var`s whose initialisers are being lowered
        self.bound: dict[Symbol, ir.Term] = {}  # parameters of the methods being inlined
        self.inlining: list[Symbol] = []

    @abstractmethod
    def _compound(self, path: str, type_symbol: Symbol) -> None:
        """Lower the members of the compound instance at ``path`` of type ``type_symbol``
        once: a path through an instance not lowered yet opens it (the instance tree's)."""

    def _origin(self, scope: InstanceScope) -> str:
        """The declaration body a constraint is written in, for one instance; the
        `with:` blocks of its fields and invocations belong to that body."""
        return f"{scope.prefix}|{self.body}"

    def _variable(self, path: str, sym: Symbol) -> ir.Var:
        """The variable of a `var` at time 0, fixed to its initialiser.

        A `var` is not a parameter: it changes at run time (``sample``) and the solver
        never chooses its value. At the start it is its initialiser, which the start
        state may use (``position(distance: lag, ...)`` with ``var lag: length =
        5m``); a `var` without an initialiser, or one whose initialiser is known only at
        run time (``sample(...)``, actor state, a method), has no value here, and what
        uses it raises NotEncodable. Its initialiser is never a dropped constraint.
        """
        existing = self.problem.variables.get(path)
        if existing is not None:
            return existing
        why = self.runtime.get(path)
        if why is None:
            decl = sym.decl
            default = sym.default
            if default is None or not isinstance(decl, ast.FieldDecl) or path in self.opening:
                why = "it has no value before the run"
            else:
                owner = _owner(path)
                owner_type = self.instances.get(owner, sym.owner)
                actor = (
                    owner
                    if owner_type is not None and owner_type.kind is SymbolKind.ACTOR
                    else None
                )
                scope = InstanceScope(owner, owner_type, owner, owner_type, actor=actor)
                self.opening.add(path)
                try:
                    value = self.term(default, scope)
                except NotEncodable:
                    why = "its value is known only at run time"
                finally:
                    self.opening.discard(path)
                if why is None:
                    var = self._scalar_var(path, sym)
                    if var is None:
                        why = "it is not a number, boolean, enum or string"
                    else:
                        span = up_to(decl.span, default.span)
                        self.problem.add(
                            ir.Constraint(
                                ir.op("==", ir.Ref(var), coerce(var, value)),
                                span,
                                "declaration",
                                self.text_of(span),
                                "hard",
                                var,
                                origin=self._origin(scope),
                            )
                        )
                        return var
            self.runtime[path] = why
        raise NotEncodable(f"`{path}` is a run-time variable (`var`): {why}")

    def _scalar_var(self, path: str, sym: Symbol) -> ir.Var | None:
        existing = self.problem.variables.get(path)
        if existing is not None:
            return existing
        kind = self.kinds.get(sym)
        if kind is None:
            kind = self.kinds[sym] = self._kind(sym)
        if kind is False:
            return None
        sort, kw, domain, text = kind
        var = self.problem.var(path, sort, span=sym.name_span, **kw)
        if domain is not None:
            lo, hi, values = domain
            ref = ir.Ref(var)
            if values is None:
                assert lo is not None  # a domain is a lowest value or a list of values
                term = (
                    ir.op(">=", ref, lo)
                    if hi is None
                    else ir.op("and", ir.op(">=", ref, lo), ir.op("<=", ref, hi))
                )
            else:
                term = ir.op("or", *(ir.op("==", ref, v) for v in values))
            self.problem.add(
                ir.Constraint(
                    term,
                    sym.name_span or self.problem.span,
                    "domain",
                    text,
                    "hard",
                    explanation=text,
                )
            )
        return var

    def _kind(self, sym: Symbol) -> VarKind:
        """(sort, var keywords, domain, its text) of a parameter's variables, or False."""
        t = sym.type
        if t is None or not is_scalar(t):
            return False
        kw: ir.VarDetails = {}
        domain: _Domain | None = None
        text = ""
        if t.kind is T.Kind.PHYSICAL:
            sort = "real"
            unit_name = _DISPLAY_UNITS.get(t.dimension or ())
            unit = self.model.unit(unit_name) if unit_name else None
            if unit is not None:
                kw.update(
                    {"unit": unit.name, "unit_factor": unit.factor, "unit_offset": unit.offset}
                )
        elif t.kind is T.Kind.FLOAT:
            sort = "real"
        elif t.kind is T.Kind.BOOL:
            sort = "bool"
        elif t.kind is T.Kind.ENUM and t.symbol is not None:
            sort = "int"
            kw["enum"] = tuple((m.name, m.value) for m in self.model.enum_values(t.symbol))
            values = sorted({v for _, v in kw["enum"]})
            if values:
                text = f"`{sym.name}` is one of its enum's members"
                if values == list(range(values[0], values[-1] + 1)):  # the usual 0..n-1
                    domain = (ir.const(values[0]), ir.const(values[-1]), None)
                else:
                    domain = (None, None, tuple(ir.const(v) for v in values))
        else:
            sort = "int"
            kw["is_string"] = t.kind is T.Kind.STRING
            if t.kind is T.Kind.UINT:
                domain = (ir.const(0), None, None)
                text = f"`{sym.name}` is a uint"
        return sort, kw, domain, text

    def path(self, expr: ast.Node | None, scope: InstanceScope) -> str | None:
        """The instance path an expression names, or None if it names no parameter."""
        match expr:
            case ast.NameRef():
                name = expr.name.name.text
                if expr.name.namespace is None and name == "it":
                    return scope.it
                if expr.name.namespace is None and name == "actor":
                    return scope.actor
                if name in scope.locals:
                    return scope.locals[name]
                sym = self.model.reference(expr.name.name)
                if sym is None:
                    return None
                if sym.kind is SymbolKind.GLOBAL:
                    return f"::{sym.name}"
                if sym.kind in (SymbolKind.FIELD, SymbolKind.VARIABLE):
                    return self._aliased(self._member_path(scope, sym))
                return None
            case ast.MemberAccess():
                base = self.path(expr.target, scope)
                sym = self.model.reference(expr.member)
                if (
                    base is None
                    or sym is None
                    or sym.kind not in (SymbolKind.FIELD, SymbolKind.VARIABLE)
                ):
                    return None
                if base not in self.instances:
                    target_type = self.model.expr_types.get(expr.target)
                    if target_type is not None and target_type.symbol is not None:
                        self._compound(base, target_type.symbol)
                return self._aliased(join_path(base, sym.name))
        return None

    def _aliased(self, path: str) -> str:
        """``path`` with an aliased prefix replaced (an actor passed to a scenario)."""
        if not self.aliases:
            return path
        head = path
        while True:
            if head in self.aliases:
                return self.aliases[head] + path[len(head) :]
            if "." not in head:
                return path
            head = head.rsplit(".", 1)[0]

    def _member_path(self, scope: InstanceScope, sym: Symbol) -> str:
        """Path of field ``sym`` seen from ``scope``: a member of `it`'s type or of the owner."""
        if (
            scope.it is not None
            and scope.it_symbol is not None
            and any(a is sym.owner for a in self.model.ancestors(scope.it_symbol))
        ):
            return join_path(scope.it, sym.name)
        return join_path(scope.prefix, sym.name)

    def _var_at(self, path: str, expr: ast.Node, scope: InstanceScope) -> ir.Var:
        var = self.problem.variables.get(path)
        if var is not None:
            return var
        sym = None
        if isinstance(expr, ast.NameRef) and expr.name.name.text == "it" and path == scope.it:
            sym = scope.it_field
        elif isinstance(expr, ast.NameRef):
            sym = self.model.reference(expr.name.name)
        elif isinstance(expr, ast.MemberAccess):
            sym = self.model.reference(expr.member)
        if sym is not None and sym.kind is SymbolKind.VARIABLE and is_scalar(sym.type):
            return self._variable(path, sym)
        if sym is None or not is_scalar(sym.type):
            raise NotEncodable(f"`{path}` is not a number, boolean, enum or string")
        created = self._scalar_var(path, sym)
        if created is None:
            raise NotEncodable(f"`{path}` cannot be encoded")
        if sym.kind is SymbolKind.GLOBAL and isinstance(sym.decl, ast.FieldDecl):
            if sym.decl.default is not None:  # `global min_lane: int = 2`: its default holds
                root = InstanceScope("", None, None)
                self.pending_defaults.append(
                    (path, sym, sym.decl, root, len(self.problem.constraints), self._origin(root))
                )
        owner = path.rsplit(".", 1)[0] if "." in path else ""
        owner_type = self.instances.get(owner)
        if owner_type is None and sym.owner is not None and owner:
            self._compound(owner, sym.owner)
        return created

    def term(self, expr: ast.Node, scope: InstanceScope) -> ir.Term:
        """``expr`` as a solver term in the instance ``scope`` (parameters become the
        variables of their paths; NotEncodable when the solver cannot take it)."""
        match expr:
            case ast.IntLiteral() | ast.FloatLiteral() | ast.PhysicalLiteral():
                try:
                    value = (
                        physical_literal(expr, self.model).si
                        if isinstance(expr, ast.PhysicalLiteral)
                        else literal_number(expr)
                    )
                except NotConstant as reason:
                    raise NotEncodable(str(reason)) from None
                return ir.const(value)
            case ast.BoolLiteral():
                return ir.const(expr.value)
            case ast.StringLiteral():
                self.string_spans.setdefault(expr.value, []).append(expr.span)
                return ir.const(self.strings.setdefault(expr.value, len(self.strings)))
            case ast.EnumRef():
                member = self.model.reference(expr.member)
                if member is None:
                    raise NotEncodable("unknown enum member")
                return ir.const(member.value)
            case ast.NameRef() | ast.MemberAccess():
                target = self.model.reference(
                    expr.name.name if isinstance(expr, ast.NameRef) else expr.member
                )
                if target is not None and target.kind is SymbolKind.ENUM_MEMBER:
                    return ir.const(target.value)
                if target is not None and target in self.bound:
                    return self.bound[target]  # a parameter of a method being inlined
                path = self.path(expr, scope)
                if path is None:
                    raise NotEncodable(f"`{self.text_of(expr.span)}` is not a parameter")
                return ir.Ref(self._var_at(path, expr, scope))
            case ast.Unary():
                inner = self.term(expr.operand, scope)
                if expr.op == "not":
                    return ir.op("not", inner)
                if (
                    expr.op == "-"
                    and isinstance(inner, ir.Const)
                    and not isinstance(inner.value, bool)
                ):
                    return ir.const(-inner.value)  # `-75` is a constant (a set's member)
                return ir.op("neg", inner) if expr.op == "-" else inner
            case ast.Binary():
                return self._binary(expr, scope)
            case ast.Call():
                return self._method_call(expr, scope)
            case ast.Ternary():
                return ir.op(
                    "ite",
                    self.term(expr.condition, scope),
                    self.term(expr.then, scope),
                    self.term(expr.otherwise, scope),
                )
        raise NotEncodable(f"`{self.text_of(expr.span)}` cannot be solved for")

    def _method_call(self, call: ast.Call, scope: InstanceScope) -> ir.Term:
        """A call of an `is expression` method: its body with its parameters bound to the
        arguments' terms (defaults where an argument is left out), lowered in the scope
        of the instance the method belongs to."""
        callee = call.callee
        name = callee.name.name if isinstance(callee, ast.NameRef) else None
        if isinstance(callee, ast.MemberAccess):
            name = callee.member
        if isinstance(callee, ast.MemberAccess) and callee.member.text in TYPE_TESTS:
            return self._conversion(call, callee, scope)
        method = self.model.references.get(name) if name is not None else None
        decl = method.decl if method is not None else None
        if (
            method is None
            or method.kind is not SymbolKind.METHOD
            or not isinstance(decl, ast.MethodDecl)
            or decl.kind != "expression"
            or decl.body is None
        ):
            raise NotEncodable(f"`{self.text_of(call.span)}` is known only at run time")
        if len(self.inlining) >= MAX_DEPTH:
            raise NotEncodable(f"`{self.text_of(call.span)}` calls methods too deeply")
        if isinstance(callee, ast.MemberAccess):
            owner = self.path(callee.target, scope)
            if owner is None:
                raise NotEncodable(f"`{self.text_of(callee.target.span)}` is not an instance")
        else:
            owner = _owner(self._member_path(scope, method))
        owner_type = self.instances.get(owner, method.owner)
        inner = InstanceScope(owner, owner_type, owner, owner_type, actor=scope.actor)
        binding = self.model.binding(call)
        given: dict[Symbol, ir.Term] = {}
        for bound in binding.arguments if binding is not None else ():
            if bound.parameter is not None:  # a default is read in the method's instance
                given[bound.parameter] = self.term(
                    bound.value, inner if bound.is_default else scope
                )
        for param in method.parameters:
            if param not in given:
                raise NotEncodable(f"`{param.name}` of `{method.name}` has no value")
        saved = dict(self.bound)
        self.bound.update(given)
        self.inlining.append(method)
        try:
            return self.term(decl.body, inner)
        finally:
            self.inlining.pop()
            self.bound = saved

    def _conversion(
        self, call: ast.Call, callee: ast.MemberAccess, scope: InstanceScope
    ) -> ir.Term:
        """``x.as(T)`` where it keeps the value: an enum member as its number
        (``signal_state!red.as(uint)``), an integer as a float, a value as its own type."""
        target = self.model.expr_types.get(callee.target)
        result = self.model.expr_types.get(call)
        if callee.member.text == "as" and target is not None and result is not None:
            same = target.kind is result.kind and (
                target.kind is not T.Kind.PHYSICAL or target.dimension == result.dimension
            )
            numbered = target.kind is T.Kind.ENUM and result.kind in (T.Kind.INT, T.Kind.UINT)
            widened = target.kind in (T.Kind.INT, T.Kind.UINT) and result.kind is T.Kind.FLOAT
            if same or numbered or widened:
                return self.term(callee.target, scope)
        raise NotEncodable(
            f"`{self.text_of(call.span)}`: only conversions that keep the value are encoded"
        )

    def _binary(self, expr: ast.Binary, scope: InstanceScope) -> ir.Term:
        if expr.op == "in":
            left = self.term(expr.left, scope)
            if isinstance(expr.right, ast.RangeLiteral):
                return self._in_range(left, expr.right, scope)
            if isinstance(expr.right, ast.ListLiteral):
                return ir.op(
                    "or", *(ir.op("==", left, self.term(i, scope)) for i in expr.right.items)
                )
            raise NotEncodable("`in` needs a range or a list written in place")
        left = self.term(expr.left, scope)
        right = self.term(expr.right, scope)
        if expr.op in ("and", "or", "=>"):
            return ir.op(expr.op, left, right)
        if expr.op in _CMP or expr.op in ("+", "-"):
            return ir.op(expr.op, left, right)
        if expr.op == "*":
            return ir.op("*", left, right)
        if expr.op == "/":
            if (
                isinstance(right, ir.Const)
                and not isinstance(right.value, bool)
                and right.value != 0
            ):
                return ir.op("*", left, ir.const(1 / right.value))
            return ir.op("/", left, right)  # exact; `guarded` keeps the divisor off 0
        if expr.op == "%":
            return ir.op("%", left, right)
        raise NotEncodable(f"operator `{expr.op}`")

    def _in_range(self, target: ir.Term, rng: ast.RangeLiteral, scope: InstanceScope) -> ir.Term:
        """``target in [low..high]``; the bounds of a range may come in either order."""
        low, high = self.term(rng.low, scope), self.term(rng.high, scope)
        return in_range(target, low, high)


def in_range(target: ir.Term, low: ir.Term, high: ir.Term) -> ir.Term:
    """``target`` lies between ``low`` and ``high``, whichever of them is the larger."""
    if isinstance(low, ir.Const) and isinstance(high, ir.Const):
        if low.value > high.value:
            low, high = high, low
        return ir.op("and", ir.op(">=", target, low), ir.op("<=", target, high))
    return ir.op(
        "or",
        ir.op("and", ir.op(">=", target, low), ir.op("<=", target, high)),
        ir.op("and", ir.op(">=", target, high), ir.op("<=", target, low)),
    )


def coerce(var: ir.Var, value: ir.Term) -> ir.Term:
    """A value given to an integer parameter loses its fraction (T204 says so), as in
    the runner: ``lane(1.5)`` is lane 1. Only constants are converted."""
    if (
        var.sort == "int"
        and isinstance(value, ir.Const)
        and not isinstance(value.value, bool)
        and value.value.denominator != 1
    ):
        return ir.const(math.trunc(value.value))
    return value


def call_span(inv: ast.Invocation) -> Span:
    """The span of an invocation's name and arguments (not its `with:` block)."""
    span = inv.name.span if inv.actor is None else inv.span
    last = inv.arguments[-1].span if inv.arguments else inv.name.span
    if last.uri != span.uri or last.end < span.start:
        return span
    return Span(
        span.uri, span.line, span.column, last.end_line, last.end_column, span.start, last.end
    )


def _owner(path: str) -> str:
    """The path of the instance that ``path`` is a member of."""
    return path.rsplit(".", 1)[0] if "." in path else ""


def up_to(decl: Span, default: Span) -> Span:
    """The span of a field declaration up to the end of its default value (not its
    `with:` block)."""
    if decl.uri != default.uri:
        return decl
    return Span(
        decl.uri,
        decl.line,
        decl.column,
        default.end_line,
        default.end_column,
        decl.start,
        default.end,
    )


class Declarations(dict[Symbol, list[tuple[ast.Member, ...]]]):
    """Each type's member lists (symbol -> lists), and how each parameter symbol becomes
    a variable (``kinds``): what the scenarios of one model share."""

    def __init__(self) -> None:
        super().__init__()
        self.kinds: dict[Symbol, VarKind] = {}
        #: the ids of the invocations inside a ``one_of`` of any scenario of the model
        #: (``start_modifiers``: worked out once per model, not once per scenario)
        self.one_of_invocations: set[int] | None = None


def member_declarations(model: Model) -> Declarations:
    """Each type's member lists (``semantics.members``), with room for the variable kinds."""
    result = Declarations()
    result.update(declaration_bodies(model))
    return result
