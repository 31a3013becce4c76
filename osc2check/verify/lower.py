"""Lower one scenario of the model to a constraint ``ConstraintProblem``.

The instance tree: the scenario's parameters, its actors' parameters (one
level, more when a constraint reaches deeper), every behaviour and modifier
invocation of its ``do`` tree (with its arguments as constraints), and the
scenarios it invokes, recursively. Variables are named by their path
(``npc.vehicle_category``, ``hero.drive@31.duration``) and created when first
mentioned; field values (``x: speed = 50kph``) are attached at the end to the
variables that exist.

The override rule reads the order of the constraint list: a type's members come
before those of its subtypes, and an actor type's before the `with:` block of
the field that instantiates it, so of two defaults of one parameter the later
is the more specific (see ``z3_backend.active_constraints``). A hard constraint
with the parameter alone on the left of `==` or `in` (an argument is one)
records the parameter as its ``subject`` and replaces the parameter's defaults.

Values are exact: physical literals become SI rationals through the unit's
factor and offset; strings and enum members become integers. A constant given
to an integer parameter loses its fraction (``lane(1.5)`` is lane 1, with the
T204 warning), and a range's bounds may come in either order.

Everything written is encoded or recorded in ``ConstraintProblem.skipped``
(reported as C411, listed with the witness), never dropped: quotients and
remainders (``ir.guarded`` keeps divisors off 0), calls of `is expression`
methods (inlined), conversions that keep the value, the condition of a
conditional inheritance (a hard constraint on every instance of the type). A
`var` is its initialiser at the start when that can be encoded, and otherwise
has no value here (``Lowerer._variable``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Literal

from osc2check.semantics import types as T
from osc2check.semantics.builtins import TYPE_TESTS, Builtin
from osc2check.semantics.constants import NotConstant, literal_number, physical_literal
from osc2check.semantics.members import actor_alias, declaration_bodies
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.verify import ir
from osc2check.verify.structs import is_scalar, is_struct, struct_leaves
from osc2check.world.limits import ARGUMENT_LIMITS

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


class Lowerer:
    def __init__(
        self,
        model: Model,
        problem: ir.ConstraintProblem,
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

    # ---- instances -----------------------------------------------------------------

    def scenario(self, sym: Symbol) -> None:
        scope = InstanceScope("", sym, "", sym, actor="actor" if sym.actor else None)
        self.instances[""] = sym
        aliased = set()
        for param in self.model.all_members(sym):
            target = actor_alias(self.model, param)
            if target is not None:  # `other: vehicle = npc` names npc: the same actor
                self.aliases[param.name] = target.name
                aliased.add(param)
        self._instance(sym, scope)
        for param in self.model.all_members(sym):
            if param.kind not in (SymbolKind.FIELD, SymbolKind.VARIABLE) or param in aliased:
                continue
            t = param.type
            if (
                t is not None
                and t.kind is T.Kind.COMPOUND
                and t.symbol is not None
                and t.symbol.kind is SymbolKind.ACTOR
            ):
                self._compound(param.name, t.symbol)
                for sub in self.model.parameters(t.symbol):
                    self._scalar_var(join_path(param.name, sub.name), sub)
            elif param.kind is SymbolKind.FIELD:
                self._scalar_var(param.name, param)
            elif is_scalar(param.type):
                try:  # a `var` has a value here only when its initialiser gives one
                    self._variable(param.name, param)
                except NotEncodable:
                    pass  # known only at run time: not a constraint, nothing dropped

    def _compound(self, path: str, type_symbol: Symbol) -> None:
        if path in self.instances:
            return
        self.instances[path] = type_symbol
        actor = path if type_symbol.kind is SymbolKind.ACTOR else None
        self._instance(
            type_symbol, InstanceScope(path, type_symbol, path, type_symbol, actor=actor)
        )

    def _instance(self, sym: Symbol, scope: InstanceScope) -> None:
        """Constraints of ``sym``'s declaration (and supertypes and extensions)."""
        if sym in self.active:
            return  # a recursive scenario (B611) or type: its members are being lowered
        if self.depth > MAX_DEPTH:
            self._too_deep(sym, scope)
            return
        self.active.append(sym)
        self.depth += 1
        outer = self.body
        try:
            for ancestor in reversed(list(self.model.ancestors(sym))):
                self.body = ancestor.name
                self._inheritance_condition(ancestor, scope)
                for decl in self.member_decls.get(ancestor, ()):
                    self._members(decl, scope)
        finally:
            self.body = outer
            self.depth -= 1
            self.active.pop()

    def _too_deep(self, sym: Symbol, scope: InstanceScope) -> None:
        """Record that the constraints of an instance nested too deeply are not lowered."""
        span = sym.name_span or self.problem.span
        self.problem.skip(
            span,
            f"the members of `{scope.prefix or sym.name}`",
            f"instances nested more than {MAX_DEPTH} deep are not lowered",
        )

    def _inheritance_condition(self, sym: Symbol, scope: InstanceScope) -> None:
        """``actor truck inherits vehicle(vehicle_category == truck)``: every instance of
        ``truck`` has that value, a hard constraint on the instance (its subject is the
        field, so it replaces the field's defaults)."""
        decl = sym.decl
        if (
            sym.condition is None
            or not isinstance(decl, ast.StructuredDecl)
            or decl.inherits is None
        ):
            return
        condition = sym.condition
        written = self.text_of(decl.inherits.span)
        try:
            term = self.term(condition, scope)
        except NotEncodable as reason:
            self.problem.skip(condition.span, written, str(reason))
            return
        self.problem.add(
            ir.Constraint(
                term,
                condition.span,
                "condition",
                written,
                "hard",
                self._subject(condition, scope),
                origin=self._origin(scope),
            )
        )

    def _members(self, members: tuple[ast.Member, ...], scope: InstanceScope) -> None:
        for member in members:
            match member:
                case ast.FieldDecl():
                    self._field(member, scope)
                case ast.KeepConstraint():
                    self._keep(member, scope, "keep")
                case ast.RemoveDefault():
                    path = self.path(member.target, scope)
                    if path is not None:
                        self.problem.removed_defaults.add(path)
                case ast.DoDirective():
                    self._do_member(member.member, scope)

    def _field(self, decl: ast.FieldDecl, scope: InstanceScope) -> None:
        for name in decl.names:
            sym = self.model.references.get(name)
            if sym is None:
                continue
            path = join_path(scope.prefix, name.text)
            type_symbol = _type_symbol(sym)
            if (
                decl.with_members
                and type_symbol is not None
                and type_symbol.kind is SymbolKind.ACTOR
            ):
                # the type's own constraints come first: the instance's `with:` block is
                # more specific, so its defaults override the type's (see attach_defaults)
                self._compound(path, type_symbol)
            if scope.owner is not None and scope.owner.kind is SymbolKind.SCENARIO:
                self.struct_variables(path, sym)
            if decl.default is not None:
                self.pending_defaults.append(
                    (path, sym, decl, scope, len(self.problem.constraints), self._origin(scope))
                )
            if decl.with_members:
                inner = InstanceScope(
                    scope.prefix,
                    scope.owner,
                    path,
                    _type_symbol(sym),
                    scope.actor,
                    dict(scope.locals),
                    it_field=sym,
                )
                for item in decl.with_members:
                    if isinstance(item, ast.KeepConstraint):
                        self._keep(item, inner, "keep")
                    elif isinstance(item, ast.RemoveDefault):
                        target = self.path(item.target, inner)
                        if target is not None:
                            self.problem.removed_defaults.add(target)

    def attach_defaults(self) -> None:
        """Add field defaults for every variable created so far (a `var` has none: it is
        not a parameter, and its initialiser is its value when the run starts).

        Each goes where its declaration was lowered, so the order of the constraint
        list stays the order of specificity that the override rule reads: a type's
        field default (`x: speed = 50kph`) comes before the type's later
        `keep(default x == ...)`, before a subtype's, and before the instance's.
        """
        placed: list[tuple[int, ir.Constraint]] = []
        for path, _sym, decl, scope, at, origin in self.pending_defaults:
            var = self.problem.variables.get(path)
            if var is None or decl.is_var:
                continue  # a `var`'s initialiser is its value when the run starts
            assert decl.default is not None  # only fields with a value are pending
            span = _up_to(decl.span, decl.default.span)
            try:
                value = coerce(var, self.term(decl.default, scope))
            except NotEncodable as reason:
                self.problem.skip(span, self.text_of(span), str(reason))
                continue
            placed.append(
                (
                    at,
                    ir.Constraint(
                        ir.guarded(ir.op("==", ir.Ref(var), value)),
                        span,
                        "declaration",
                        self.text_of(span),
                        "default",
                        var,
                        origin=origin,
                    ),
                )
            )
        for at, constraint in sorted(placed, key=lambda p: p[0], reverse=True):
            self.problem.constraints.insert(at, constraint)

    # ---- constraints ------------------------------------------------------------------

    def _origin(self, scope: InstanceScope) -> str:
        """The declaration body a constraint is written in, for one instance; the
        `with:` blocks of its fields and invocations belong to that body."""
        return f"{scope.prefix}|{self.body}"

    def _keep(self, keep: ast.KeepConstraint, scope: InstanceScope, kind: str) -> None:
        if keep.strength != "default" and self._list_binding(keep.expr, scope):
            return
        try:
            term = self.term(keep.expr, scope)
        except NotEncodable as reason:
            self.problem.skip(keep.span, self.text_of(keep.span), str(reason))
            return
        subject = self._subject(keep.expr, scope)
        strength = "default" if keep.strength == "default" else "hard"
        kind = "default" if strength == "default" else kind
        self.problem.add(
            ir.Constraint(
                term,
                keep.span,
                kind,
                self.text_of(keep.span),
                strength,
                subject,
                origin=self._origin(scope),
            )
        )

    def _subject(self, expr: ast.Node, scope: InstanceScope) -> ir.Var | None:
        """The parameter alone on the left of `==` or `in` (the override rule's form)."""
        if isinstance(expr, ast.Binary) and expr.op in ("==", "in"):
            path = self.path(expr.left, scope)
            if path is not None:
                return self.problem.variables.get(path)
        return None

    # ---- behaviour ----------------------------------------------------------------------

    def _do_member(self, member: ast.DoMember, scope: InstanceScope) -> None:
        body = member.body
        match body:
            case ast.Composition():
                for sub in body.members:
                    self._do_member(sub, scope)
                for item in body.with_members:
                    if isinstance(item, ast.KeepConstraint):
                        self._keep(item, scope, "keep")
            case ast.Invocation():
                self._invocation(body, scope, member.label)

    def instance_scope(
        self, inv: ast.Invocation, scope: InstanceScope, label: ast.Name | None
    ) -> tuple[Symbol, InstanceScope] | None:
        """The behaviour an invocation invokes and the scope of its own members (its
        instance's path: ``invocation_path``); None when it invokes nothing known."""
        behaviour = self.model.references.get(inv.name)
        if behaviour is None or not behaviour.kind.is_behaviour:
            return None
        actor_path = self.path(inv.actor, scope) if inv.actor is not None else scope.actor
        path = invocation_path(scope.prefix, actor_path, label, behaviour.name, inv)
        return behaviour, InstanceScope(path, behaviour, path, behaviour, actor_path)

    def _invocation(
        self, inv: ast.Invocation, scope: InstanceScope, label: ast.Name | None
    ) -> None:
        found = self.instance_scope(inv, scope, label)
        if found is None:
            return
        behaviour, body = found
        path = body.prefix
        inner = InstanceScope(
            scope.prefix, scope.owner, path, behaviour, scope.actor, dict(scope.locals)
        )  # its `with:` block: `it` is the behaviour
        self._arguments(inv, path, scope, "argument")
        if behaviour.kind is SymbolKind.SCENARIO:
            self._bind_actors(inv, path, scope)
        if self.depth <= MAX_DEPTH and not behaviour.library:
            self.instances[path] = behaviour
            self._instance(behaviour, body)
        for item in inv.with_members:
            match item:
                case ast.KeepConstraint():
                    self._keep(item, inner, "keep")
                case ast.Invocation():
                    modifier = self.model.references.get(item.name)
                    if modifier is not None and modifier.kind is SymbolKind.MODIFIER:
                        mod_path = join_path(path, f"{modifier.name}@{item.span.line}")
                        self._arguments(item, mod_path, scope, "modifier")

    def _bind_actors(self, inv: ast.Invocation, path: str, scope: InstanceScope) -> None:
        """An invoked scenario's actor parameters given as arguments (``cut_in(car1: npc)``)
        are the actors passed: their paths are aliases of the actors' own."""
        binding = self.model.binding(inv)
        for bound in binding.arguments if binding is not None else ():
            param = bound.parameter
            target = _type_symbol(param) if param is not None and not bound.is_default else None
            if target is None or target.kind is not SymbolKind.ACTOR:
                continue
            actual = self.path(bound.value, scope)
            if actual is not None:
                self.aliases[join_path(path, bound.name)] = actual

    def _arguments(self, call: ast.Invocation, path: str, scope: InstanceScope, kind: str) -> None:
        """Each argument given to a behaviour or modifier as a rule on its parameter's
        variable: ``p == v``, or ``p in [a..b]`` for a range given where a scalar is
        expected (one value chosen from it)."""
        binding = self.model.binding(call)
        if binding is None or isinstance(binding.callee, Builtin):
            return
        callee = binding.callee
        for bound in binding.arguments:
            param, arg = bound.parameter, bound.written
            if param is None or arg is None:
                continue
            if not is_scalar(param.type):
                continue
            var = self._scalar_var(join_path(path, param.name), param)
            if var is None:
                continue
            self.argument_vars[(scope.prefix, id(bound.value))] = var
            if callee.library or callee.toolkit:
                self._argument_limit(callee, param, var, arg)
            written = self.text_of(arg.span)
            if bound.positional:
                written = f"{param.name}: {written}"
            try:
                term = self._membership(var, arg.value, scope)
            except NotEncodable as reason:
                self.problem.skip(arg.span, f"{callee.name}({written})", str(reason))
                continue
            self.problem.add(
                ir.Constraint(term, arg.span, kind, f"{callee.name}({written})", "hard", var)
            )

    def chosen(self, node: ast.Node, scope: InstanceScope) -> ir.Var | None:
        """The variable of the argument ``node`` lowered in instance ``scope``: the value
        the solver chooses (from the range, for a range given where a scalar is
        expected); None when ``node`` is no such argument."""
        return self.argument_vars.get((scope.prefix, id(node)))

    def _argument_limit(
        self, callee: Symbol, param: Symbol, var: ir.Var, arg: ast.Argument
    ) -> None:
        """The values the world takes for a library action's argument (``world.limits``:
        a road friction in (0, 2]), as a rule on the argument's variable."""
        limit = ARGUMENT_LIMITS.get((callee.qualified_name, param.name))
        if limit is None:
            return
        ref = ir.Ref(var)
        term: ir.Term = ir.op(">" if limit.low_open else ">=", ref, ir.const(limit.low))
        if limit.high is not None:
            term = ir.op("and", term, ir.op("<=", ref, ir.const(limit.high)))
        self.problem.add(
            ir.Constraint(term, arg.span, "domain", limit.text, "hard", explanation=limit.text)
        )

    def _membership(self, var: ir.Var, value: ast.Node, scope: InstanceScope) -> ir.Term:
        """``var == value`` (an argument is a constraint), or ``var in value`` for a range."""
        if isinstance(value, ast.RangeLiteral):
            return self._in_range(ir.Ref(var), value, scope)
        return ir.op("==", ir.Ref(var), coerce(var, self.term(value, scope)))

    # ---- paths and variables ------------------------------------------------------------

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
                        span = _up_to(decl.span, default.span)
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

    def _list_binding(self, expr: ast.Node, scope: InstanceScope) -> bool:
        """``keep(s.points == [p1, p2])`` on a list member of a struct parameter: the
        list's items recorded in ``problem.lists`` (each item's own constraints are its
        leaves'); False when ``expr`` is not of that form."""
        if not (
            isinstance(expr, ast.Binary)
            and expr.op == "=="
            and isinstance(expr.left, ast.MemberAccess)
            and isinstance(expr.right, ast.ListLiteral)
        ):
            return False
        member = self.model.references.get(expr.left.member)
        if member is None or member.type is None or member.type.kind is not T.Kind.LIST:
            return False
        path = self.path(expr.left, scope)
        if path is None:
            return False
        element = member.type.element
        items: list[ir.ListItem] = []
        for item in expr.right.items:
            if is_struct(element):
                ref = self.path(item, scope)
                if ref is None:
                    return False
                items.append(("ref", ref))
                continue
            if element is not None and element.kind is T.Kind.ENUM:
                name = item.member.text if isinstance(item, ast.EnumRef) else None
                if isinstance(item, ast.NameRef):
                    name = item.name.name.text
                if name is None:
                    return False
                items.append(("value", name))
                continue
            try:
                term = self.term(item, scope)
            except NotEncodable:
                return False
            if not isinstance(term, ir.Const):
                return False
            items.append(("value", term.value))
        self.problem.lists[path] = tuple(items)
        return True

    def struct_variables(self, path: str, sym: Symbol) -> None:
        """A variable for every scalar leaf of a struct-typed scenario parameter
        (:mod:`osc2check.verify.structs`), so the witness gives the whole struct a value."""
        if sym.kind is not SymbolKind.FIELD or not is_struct(sym.type):
            return
        struct = _type_symbol(sym)
        assert struct is not None
        self._compound(path, struct)
        for leaf, leaf_sym in struct_leaves(self.model, struct):
            var = self._scalar_var(join_path(path, leaf), leaf_sym)
            if var is not None and (var.unit == "deg" or leaf == "z" or leaf.endswith(".z")):
                # left open, an angle or a height is 0 (level, on the road), not a draw
                self.problem.preferred.setdefault(var.name, (Fraction(0), Fraction(0)))

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

    # ---- expressions ---------------------------------------------------------------------

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


def _up_to(decl: Span, default: Span) -> Span:
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


def _type_symbol(sym: Symbol) -> Symbol | None:
    return sym.type.symbol if sym.type is not None and sym.type.kind is T.Kind.COMPOUND else None


class Declarations(dict[Symbol, list[tuple[ast.Member, ...]]]):
    """Each type's member lists (symbol -> lists), and how each parameter symbol becomes
    a variable (``kinds``): what the scenarios of one model share."""

    def __init__(self) -> None:
        super().__init__()
        self.kinds: dict[Symbol, VarKind] = {}


def member_declarations(model: Model) -> Declarations:
    """Each type's member lists (``semantics.members``), with room for the variable kinds."""
    result = Declarations()
    result.update(declaration_bodies(model))
    return result
