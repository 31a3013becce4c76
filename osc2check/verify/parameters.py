"""The instance tree of one scenario: its parameters and their constraints.

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

Expressions become terms through ``terms.TermEncoder``. A constant given
to an integer parameter loses its fraction (``lane(1.5)`` is lane 1, with the
T204 warning), and a range's bounds may come in either order.

Everything written is encoded or recorded in ``ConstraintProblem.skipped``
(reported as C411, listed with the witness), never dropped: quotients and
remainders (``ir.guarded`` keeps divisors off 0), calls of `is expression`
methods (inlined), conversions that keep the value, the condition of a
conditional inheritance (a hard constraint on every instance of the type). A
`var` is its initialiser at the start when that can be encoded, and otherwise
has no value here (``TermEncoder._variable``).
"""

from __future__ import annotations

from fractions import Fraction

from osc2check.semantics import types as T
from osc2check.semantics.builtins import Builtin
from osc2check.semantics.members import actor_alias
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast
from osc2check.verify import ir
from osc2check.verify.problem import ConstraintProblem
from osc2check.verify.structs import is_scalar, is_struct, struct_leaves
from osc2check.verify.terms import (
    MAX_DEPTH,
    Declarations,
    InstanceScope,
    NotEncodable,
    TermEncoder,
    TextOf,
    coerce,
    invocation_path,
    join_path,
    up_to,
)
from osc2check.world.limits import ARGUMENT_LIMITS


class Lowerer(TermEncoder):
    """The instance tree of a scenario into ``problem``: its instances' members, keeps,
    invocations and arguments (``lower_parameters``)."""

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
            span = up_to(decl.span, decl.default.span)
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


def _type_symbol(sym: Symbol) -> Symbol | None:
    return sym.type.symbol if sym.type is not None and sym.type.kind is T.Kind.COMPOUND else None


def lower_parameters(
    model: Model,
    scenario: Symbol,
    problem: ConstraintProblem,
    text_of: TextOf,
    member_decls: Declarations | None = None,
) -> Lowerer:
    """Lower ``scenario`` as a top-level instance into ``problem``: its parameters, its
    actors', its behaviour's invocations and arguments, the scenarios it invokes; the
    fields' defaults are attached by ``Lowerer.attach_defaults`` once the other steps
    created their variables. ``member_decls`` (``terms.member_declarations``) can be
    shared by the scenarios of one model."""
    lowerer = Lowerer(model, problem, text_of, member_decls)
    lowerer.scenario(scenario)
    return lowerer
