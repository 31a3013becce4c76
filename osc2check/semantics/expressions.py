"""Type every expression: names, members, calls, operators, units.

``ExpressionChecker.check(expr, scope, expected)`` returns the expression's
``Type``, records it in ``model.expr_types``, binds names in
``model.references`` and reports problems. An expected type, when given,
decides bare enum literals (``at: start``) and is checked at the end.
"""

from __future__ import annotations

from collections.abc import Callable

from osc2check import messages
from osc2check.diagnostics import Diagnostic
from osc2check.semantics import types as T
from osc2check.semantics.bindings import Binding, argument_values
from osc2check.semantics.builtins import (
    EVENT_FUNCTIONS,
    LIST_METHODS,
    TYPE_TESTS,
    VALUE_FUNCTIONS,
    Builtin,
)
from osc2check.semantics.calls import bind_builtin, builtin_problems
from osc2check.semantics.declare import TOOLKIT_NAMESPACES
from osc2check.semantics.model import Model
from osc2check.semantics.scope import Scope
from osc2check.semantics.suggest import closest
from osc2check.semantics.symbols import IMPLICIT_NAMES, Symbol, SymbolKind
from osc2check.syntax import ast

# Checks a method call's arguments: (method, parameters, arguments, scope, span of the call).
CallCheck = Callable[[Symbol, list[Symbol], tuple[ast.Argument, ...], Scope, ast.Node], None]

_ARITH = {"+", "-"}
_SCALE = {"*", "/", "%"}
_ORDER = {"<", "<=", ">", ">="}
_EQUALITY = {"==", "!="}
_LOGIC = {"and", "or", "=>"}
_VALUE_KINDS = {
    SymbolKind.FIELD,
    SymbolKind.VARIABLE,
    SymbolKind.GLOBAL,
    SymbolKind.ARGUMENT,
    SymbolKind.IMPLICIT,
    SymbolKind.LABEL,
    SymbolKind.ENUM_MEMBER,
}


def _is_plain_literal(expr: ast.Node) -> bool:
    if isinstance(expr, ast.Unary) and expr.op in ("-", "+"):
        return _is_plain_literal(expr.operand)
    return isinstance(expr, (ast.IntLiteral, ast.FloatLiteral))


class ExpressionChecker:
    def __init__(
        self,
        model: Model,
        report: Callable[[Diagnostic], None],
        check_call: CallCheck | None = None,
    ):
        self.model = model
        self.report = report
        self.check_call = check_call
        # dimension -> named physical type
        self._physical_types: dict[T.Dimension | None, T.Type] | None = None

    # ---- entry points ------------------------------------------------------------

    def check(
        self, expr: ast.Node, scope: Scope, expected: T.Type | None = None, what: str = "value"
    ) -> T.Type:
        actual = self._type(expr, scope, expected)
        self.model.expr_types[expr] = actual
        if expected is not None:
            self.expect(expr, actual, expected, scope, what)
        return actual

    def infer(self, expr: ast.Node, scope: Scope, hint: T.Type | None) -> T.Type:
        """The type of ``expr``, using ``hint`` only to decide enum literals."""
        actual = self._type(expr, scope, hint)
        self.model.expr_types[expr] = actual
        return actual

    def expect(
        self,
        expr: ast.Node,
        actual: T.Type,
        expected: T.Type,
        scope: Scope,
        what: str = "value",
        allow_range: bool = False,
    ) -> bool:
        compat = T.compatible(expected, actual, allow_range=allow_range)
        if compat is T.Compat.OK:
            return True
        if compat is T.Compat.MISSING_UNIT:
            if scope.in_argument and _is_plain_literal(expr):
                self.report(messages.unitless_literal(expr.span, expected))
                return True
            self.report(messages.missing_unit(expr.span, expected, what))
        elif compat is T.Compat.DIMENSION:
            self.report(messages.dimension_mismatch(expr.span, actual, expected, what))
        elif compat is T.Compat.NARROWING:
            self.report(messages.float_to_int(expr.span, expected))
        else:
            self.report(messages.type_mismatch(expr.span, actual, expected, what))
        return False

    def condition(self, expr: ast.Node, scope: Scope, what: str) -> T.Type:
        actual = self.check(expr, scope)
        if not actual.is_unknown and actual.kind is not T.Kind.BOOL:
            self.report(messages.non_boolean(expr.span, actual, what))
        return actual

    # ---- dispatch --------------------------------------------------------------------

    def _type(self, expr: ast.Node, scope: Scope, expected: T.Type | None) -> T.Type:
        match expr:
            case ast.IntLiteral():
                return T.UINT if expr.value >= 0 else T.INT
            case ast.FloatLiteral():
                return T.FLOAT
            case ast.StringLiteral():
                return T.STRING
            case ast.BoolLiteral():
                return T.BOOL
            case ast.PhysicalLiteral():
                return self._physical(expr)
            case ast.NameRef():
                return self._name(expr.name, scope, expected)
            case ast.EnumRef():
                return self._enum_ref(expr, scope)
            case ast.MemberAccess():
                return self._member(expr, scope)
            case ast.Call():
                return self._call(expr, scope, expected)
            case ast.Index():
                target = self.check(expr.target, scope)
                self.check(expr.index, scope, T.INT, "index")
                if target.kind is T.Kind.LIST and target.element is not None:
                    return target.element
                if not target.is_unknown:
                    self.report(
                        messages.type_mismatch(expr.target.span, target, None, "indexed value")
                    )
                return T.UNKNOWN
            case ast.Unary():
                return self._unary(expr, scope, expected)
            case ast.Binary():
                return self._binary(expr, scope, expected)
            case ast.Ternary():
                self.condition(expr.condition, scope, "condition of `?:`")
                a = self.check(expr.then, scope, None)
                b = self.check(expr.otherwise, scope, None)
                if T.compatible(a, b) is not T.Compat.OK and T.compatible(b, a) is not T.Compat.OK:
                    self.report(messages.type_mismatch(expr.otherwise.span, b, a, "branch"))
                return a if not a.is_unknown else b
            case ast.ListLiteral():
                element_expected = (
                    expected.element
                    if expected is not None and expected.kind is T.Kind.LIST
                    else None
                )
                element = T.UNKNOWN
                for item in expr.items:
                    t = self.check(item, scope, element_expected)
                    if t.kind is T.Kind.LIST and t.element is not None:
                        t = t.element  # nested list literals flatten
                    if element.is_unknown:
                        element = t
                return T.list_of(element)
            case ast.RangeLiteral():
                bound = (
                    expected.element
                    if expected is not None and expected.kind is T.Kind.RANGE
                    else expected
                )
                low = self.check(expr.low, scope, None)
                high = self.check(expr.high, scope, None)
                if (
                    not low.is_unknown
                    and not high.is_unknown
                    and (
                        T.compatible(low, high) is not T.Compat.OK
                        and T.compatible(high, low) is not T.Compat.OK
                    )
                ):
                    self.report(messages.range_bounds(expr.span, low, high))
                element = low if not low.is_unknown else high
                if bound is not None and bound.kind in T.PLAIN_NUMBERS | {T.Kind.PHYSICAL}:
                    if element.kind in T.PLAIN_NUMBERS and bound.kind is T.Kind.FLOAT:
                        element = bound
                return T.range_of(element)
            case ast.Missing():
                return T.UNKNOWN
        return T.UNKNOWN

    # ---- literals and names ----------------------------------------------------

    def _physical(self, expr: ast.PhysicalLiteral) -> T.Type:
        unit = self.model.unit(expr.unit.text)
        if unit is None:
            self.report(
                messages.unknown_unit(
                    expr.unit.span, expr.unit.text, closest(expr.unit.text, self.model.all_units())
                )
            )
            return T.UNKNOWN
        self.model.references[expr.unit] = unit
        if unit.type is not None:
            return unit.type
        return T.Type(T.Kind.PHYSICAL, None, unit.dimension)

    def value_symbol(self, qname: ast.QualifiedName, scope: Scope) -> Symbol | None:
        """The symbol a value name stands for, without reporting."""
        name = qname.name.text
        if qname.namespace is None:
            local = scope.local(name)
            if local is not None:
                return local
        current: Scope | None = scope
        while current is not None:
            if current.owner is not None:
                found = self._members(current.owner, name, qname.namespace)
                if found:
                    return found[0]
            current = current.parent
        found = self._globals(qname, scope)
        return found[0] if found else None

    def _globals(self, qname: ast.QualifiedName, scope: Scope) -> list[Symbol]:
        """Global parameters and types that ``qname`` may name."""
        return self.model.lookup(
            qname.name.text,
            scope.context,
            qname.namespace,
            lambda s: s.kind is SymbolKind.GLOBAL or s.kind.is_type,
        )

    def _members(self, owner: Symbol, name: str, namespace: str | None) -> list[Symbol]:
        found = self.model.member(owner, name)
        if namespace is not None:
            found = [s for s in found if s.namespace == namespace]
        return found

    def _name(self, qname: ast.QualifiedName, scope: Scope, expected: T.Type | None) -> T.Type:
        name = qname.name.text
        if qname.name.missing:
            return T.UNKNOWN
        if qname.namespace is None and name == "it":
            if scope.it is None:
                self.report(messages.invalid_implicit(qname.span, "it"))
                return T.UNKNOWN
            return scope.it
        if qname.namespace is None and name == "actor" and scope.local("actor") is None:
            if scope.actor is None:
                self.report(messages.invalid_implicit(qname.span, "actor"))
                return T.UNKNOWN
            return scope.actor.type or T.UNKNOWN
        if expected is not None and expected.kind is T.Kind.ENUM and qname.namespace is None:
            member = self._enum_member(expected.symbol, name)
            shadow = self.value_symbol(qname, scope)
            if member is not None and (shadow is None or not self._fits(shadow, expected)):
                # where an enum is expected its member wins over an event, a string global,
                # ... of that name (CARLA's `event start` beside `at: start`), with N115
                if shadow is not None and not shadow.kind.is_type and expected.symbol:
                    self.report(
                        messages.shadowed_enum_literal(qname.span, name, expected.symbol, shadow)
                    )
                self.model.references[qname.name] = member
                return expected
        sym = self.value_symbol(qname, scope)
        if sym is not None and (sym.kind is SymbolKind.GLOBAL or sym.kind.is_type):
            candidates = self._globals(qname, scope)
            if self.model.ambiguous(candidates):
                self.report(messages.ambiguous_name(qname.span, name, candidates))
                return T.UNKNOWN
        if sym is not None:
            self.model.references[qname.name] = sym
            if sym.toolkit and scope.context.namespace not in TOOLKIT_NAMESPACES:
                self.report(messages.toolkit_extension(qname.name.span, sym))
            if sym.kind.is_type:
                return sym.type or T.UNKNOWN
            if sym.kind is SymbolKind.METHOD:
                return sym.type or T.UNKNOWN
            if sym.kind is SymbolKind.EVENT:
                return T.UNKNOWN
            return sym.type or T.UNKNOWN
        # a bare enum member: unique among the visible enums?
        owners = [
            e
            for e in self.model.visible_enums(scope.context)
            if self._enum_member(e, name) is not None
        ]
        if len(owners) == 1:
            member = self._enum_member(owners[0], name)
            assert member is not None  # as `owners` was chosen
            self.model.references[qname.name] = member
            return owners[0].type or T.UNKNOWN
        if len(owners) > 1:
            if expected is not None and expected.kind is T.Kind.ENUM:
                self.report(messages.unknown_enum_member(qname.span, name, expected.symbol, None))
            else:
                self.report(messages.ambiguous_enum_literal(qname.span, name, owners))
            return T.UNKNOWN
        if expected is not None and expected.kind is T.Kind.ENUM:
            assert expected.symbol is not None  # an enum type is its declaration's
            members = [m.name for m in self.model.enum_values(expected.symbol)]
            self.report(
                messages.unknown_enum_member(
                    qname.span, name, expected.symbol, closest(name, members)
                )
            )
            return T.UNKNOWN
        self.report(
            messages.undefined_name(
                qname.span, str(qname), closest(name, self._visible_values(scope))
            )
        )
        return T.UNKNOWN

    @staticmethod
    def _fits(sym: Symbol, expected: T.Type) -> bool:
        """Whether the value ``sym`` names is of the ``expected`` type (an event is none)."""
        if sym.kind is SymbolKind.EVENT or sym.kind.is_type or sym.type is None:
            return False
        return T.compatible(expected, sym.type) is T.Compat.OK

    def _overloaded_literal(self, expr: ast.Node, scope: Scope) -> bool:
        """Whether ``expr`` is a bare name that only enum members of several enums bear."""
        if not isinstance(expr, ast.NameRef) or expr.name.namespace is not None:
            return False
        name = expr.name.name.text
        if name in IMPLICIT_NAMES or self.value_symbol(expr.name, scope) is not None:
            return False
        owners = [
            e
            for e in self.model.visible_enums(scope.context)
            if self._enum_member(e, name) is not None
        ]
        return len(owners) > 1

    def _visible_values(self, scope: Scope) -> list[str]:
        names: list[str] = []
        current: Scope | None = scope
        while current is not None:
            names.extend(current.locals)
            if current.owner is not None:
                names.extend(m.name for m in self.model.all_members(current.owner))
            current = current.parent
        return names

    def _enum_member(self, enum: Symbol | None, name: str) -> Symbol | None:
        if enum is None:
            return None
        for member in self.model.enum_values(enum):
            if member.name == name:
                return member
        return None

    def _enum_ref(self, expr: ast.EnumRef, scope: Scope) -> T.Type:
        enums = self.model.lookup(
            expr.enum.name.text,
            scope.context,
            expr.enum.namespace,
            lambda s: s.kind is SymbolKind.ENUM,
        )
        if self.model.ambiguous(enums):
            self.report(messages.ambiguous_name(expr.enum.span, expr.enum.name.text, enums))
            return T.UNKNOWN
        if not enums:
            self.report(messages.undefined_type(expr.enum.span, str(expr.enum), None))
            return T.UNKNOWN
        enum = enums[0]
        self.model.references[expr.enum.name] = enum
        member = self._enum_member(enum, expr.member.text)
        if member is None:
            names = [m.name for m in self.model.enum_values(enum)]
            self.report(
                messages.unknown_enum_member(
                    expr.member.span, expr.member.text, enum, closest(expr.member.text, names)
                )
            )
            return T.UNKNOWN
        self.model.references[expr.member] = member
        return enum.type or T.UNKNOWN

    # ---- members and calls -----------------------------------------------------

    def _member(self, expr: ast.MemberAccess, scope: Scope) -> T.Type:
        target = self.check(expr.target, scope)
        name = expr.member.text
        if target.is_unknown or expr.member.missing:
            return T.UNKNOWN
        if target.kind is T.Kind.COMPOUND and target.symbol is not None:
            found = self.model.member(target.symbol, name)
            if found:
                sym = found[0]
                self.model.references[expr.member] = sym
                if sym.toolkit and scope.context.namespace not in TOOLKIT_NAMESPACES:
                    self.report(messages.toolkit_extension(expr.member.span, sym))
                if sym.kind is SymbolKind.EVENT:
                    return T.UNKNOWN
                return sym.type or T.UNKNOWN
            candidates = [m.name for m in self.model.all_members(target.symbol)]
            self.report(
                messages.unknown_member(expr.member.span, name, target, closest(name, candidates))
            )
            return T.UNKNOWN
        self.report(messages.unknown_member(expr.member.span, name, target, None))
        return T.UNKNOWN

    def _call(self, expr: ast.Call, scope: Scope, expected: T.Type | None) -> T.Type:
        callee = expr.callee
        if isinstance(callee, ast.NameRef) and callee.name.namespace is None:
            name = callee.name.name.text
            builtin = self._builtin(name, expr, scope, expected)
            if builtin is not None:
                return builtin
        if isinstance(callee, ast.MemberAccess):
            target = self.check(callee.target, scope)
            self.model.expr_types[callee] = T.UNKNOWN
            special = self._method_on_value(callee, target, expr, scope)
            if special is not None:
                return special
            if target.is_unknown:
                self._check_arguments_loosely(expr, scope)
                return T.UNKNOWN
            if target.kind is T.Kind.COMPOUND and target.symbol is not None:
                found = [
                    s
                    for s in self.model.member(target.symbol, callee.member.text)
                    if s.kind is SymbolKind.METHOD
                ]
                if found:
                    return self._invoke_method(found[0], callee.member, expr, scope)
            self._check_arguments_loosely(expr, scope)
            members = self.model.all_members(target.symbol) if target.symbol else []
            self.report(
                messages.unknown_method(
                    callee.member.span,
                    callee.member.text,
                    target,
                    closest(callee.member.text, [m.name for m in members]),
                )
            )
            return T.UNKNOWN
        if isinstance(callee, ast.NameRef):
            sym = self.value_symbol(callee.name, scope)
            if sym is not None and sym.kind is SymbolKind.METHOD:
                return self._invoke_method(sym, callee.name.name, expr, scope)
            if sym is not None and sym.kind is SymbolKind.STRUCT:
                return self._construct(sym, callee.name.name, expr, scope)
            if sym is not None:
                self.model.references[callee.name.name] = sym
                self.report(messages.not_callable(callee.span, sym))
                self._check_arguments_loosely(expr, scope)
                return T.UNKNOWN
            self._check_arguments_loosely(expr, scope)
            self.report(
                messages.undefined_name(
                    callee.span,
                    str(callee.name),
                    closest(callee.name.name.text, self._visible_values(scope)),
                )
            )
            return T.UNKNOWN
        self.check(callee, scope)
        self._check_arguments_loosely(expr, scope)
        self.report(messages.not_callable(callee.span, None))
        return T.UNKNOWN

    def _invoke_method(
        self, method: Symbol, name: ast.Name, expr: ast.Call, scope: Scope
    ) -> T.Type:
        self.model.references[name] = method
        if method.toolkit and scope.context.namespace not in TOOLKIT_NAMESPACES:
            self.report(messages.toolkit_extension(name.span, method))
        if self.check_call is not None:
            self.check_call(method, list(method.parameters), expr.arguments, scope, expr)
        return method.type or T.UNKNOWN

    def _construct(self, struct: Symbol, name: ast.Name, expr: ast.Call, scope: Scope) -> T.Type:
        """``pose_3d(position_3d(x: 1m))``: a struct value whose fields the arguments give,
        positional ones in declaration order (inherited first); a dialect form (D809)."""
        self.model.references[name] = struct
        self.report(messages.struct_constructor_call(expr.span, struct))
        if self.check_call is not None:
            fields = self.model.parameters(struct)
            self.check_call(struct, fields, expr.arguments, scope, expr)
        return struct.type or T.UNKNOWN

    def _check_arguments_loosely(self, expr: ast.Call, scope: Scope) -> None:
        for value in argument_values(expr.arguments):
            self.check(value, scope)

    def _method_on_value(
        self, callee: ast.MemberAccess, target: T.Type, expr: ast.Call, scope: Scope
    ) -> T.Type | None:
        name = callee.member.text
        args = argument_values(expr.arguments)
        if name in TYPE_TESTS and len(args) == 1 and isinstance(args[0], ast.NameRef):
            qname = args[0].name
            if qname.namespace is None and qname.name.text in T.PRIMITIVES:
                t = T.PRIMITIVES[qname.name.text]
            else:
                found = [
                    s
                    for s in self.model.lookup(qname.name.text, scope.context, qname.namespace)
                    if s.kind.is_type
                ]
                if not found:
                    self.report(messages.undefined_type(qname.span, str(qname), None))
                    return T.UNKNOWN
                self.model.references[qname.name] = found[0]
                t = found[0].type or T.UNKNOWN
            return t if name == "as" else T.BOOL
        if target.kind is T.Kind.LIST and name in LIST_METHODS:
            element = target.element or T.UNKNOWN
            inner = scope.child(it=element)
            for a in args:
                self.check(a, inner)
            result = LIST_METHODS[name].result
            if result == "list":
                return target if name == "filter" else T.list_of(T.UNKNOWN)
            return T.PRIMITIVES[result]
        if target.kind is T.Kind.RANGE and name in ("lower", "upper"):
            return target.element or T.UNKNOWN
        return None

    def _builtin(
        self, name: str, expr: ast.Call, scope: Scope, expected: T.Type | None
    ) -> T.Type | None:
        if (
            self.value_symbol(ast.QualifiedName(expr.span, None, ast.Name(expr.span, name)), scope)
            is not None
        ):
            return None
        builtin = EVENT_FUNCTIONS.get(name) or VALUE_FUNCTIONS.get(name)
        if builtin is None:
            return None
        binding = bind_builtin(builtin, expr.arguments, expr)
        self.model.bindings[expr] = binding
        self._builtin_arguments(builtin, binding, scope)
        values = [b.value for b in binding.arguments]
        if name in EVENT_FUNCTIONS:
            for bound in binding.arguments:
                param = next(p for p in builtin.parameters if p.name == bound.name)
                if param.type == "bool":
                    self.condition(bound.value, scope, f"argument of `{name}`")
                else:
                    physical = self._physical_named(param.type, scope)
                    self.check(bound.value, scope, physical, "duration")
            return T.BOOL
        if name == "range" and len(values) == 2:
            low = self.check(values[0], scope)
            self.check(values[1], scope, low if not low.is_unknown else None, "range bound")
            return T.range_of(low)
        if name == "sample" and values:
            t = self.check(values[0], scope)
            for v in values[1:]:
                self.check(v, scope, t)
            return t
        return None

    def _builtin_arguments(self, builtin: Builtin, binding: Binding, scope: Scope) -> None:
        """Report what a built-in call's binding left out (``calls.builtin_problems``)."""
        for problem in builtin_problems(builtin, binding):
            self.report(problem)
        for value in argument_values(binding.rejected):
            self.check(value, scope)

    def _physical_named(self, name: str, scope: Scope) -> T.Type | None:
        found = [
            s for s in self.model.lookup(name, scope.context) if s.kind is SymbolKind.PHYSICAL_TYPE
        ]
        if not found:
            for ns in ("stdtypes",):
                found = [
                    s
                    for s in self.model.lookup(name, scope.context, ns)
                    if s.kind is SymbolKind.PHYSICAL_TYPE
                ]
        if found:
            return found[0].type
        time_dim = (0, 0, 1, 0, 0, 0, 0, 0) if name == "time" else None
        return T.Type(T.Kind.PHYSICAL, None, time_dim) if time_dim else None

    # ---- operators -------------------------------------------------------------

    def _unary(self, expr: ast.Unary, scope: Scope, expected: T.Type | None) -> T.Type:
        if expr.op == "not":
            self.condition(expr.operand, scope, "operand of `not`")
            return T.BOOL
        t = self.check(expr.operand, scope, None)
        if not t.is_unknown and not t.is_numeric:
            self.report(
                messages.type_mismatch(expr.operand.span, t, None, f"operand of `{expr.op}`")
            )
            return T.UNKNOWN
        if expr.op == "-" and t.kind is T.Kind.UINT:
            return T.INT
        return t

    def _binary(self, expr: ast.Binary, scope: Scope, expected: T.Type | None) -> T.Type:
        op = expr.op
        if op in _LOGIC:
            self.condition(expr.left, scope, f"operand of `{op}`")
            self.condition(expr.right, scope, f"operand of `{op}`")
            return T.BOOL
        if op == "in":
            left = self.check(expr.left, scope)
            hint = (
                T.range_of(left)
                if isinstance(expr.right, ast.RangeLiteral)
                else T.list_of(left)
                if isinstance(expr.right, ast.ListLiteral)
                else None
            )
            right = (
                self.check(expr.right, scope, None)
                if hint is None
                else self.infer(expr.right, scope, hint)
            )
            if right.kind in (T.Kind.RANGE, T.Kind.LIST) and right.element is not None:
                self._comparable(expr, left, right.element)
            elif not right.is_unknown:
                self.report(
                    messages.type_mismatch(
                        expr.right.span, right, None, "right operand of `in` (a range or a list)"
                    )
                )
            return T.BOOL
        if op in _EQUALITY and self._overloaded_literal(expr.left, scope):
            # `ahead == where`: the other operand decides the literal (§7.3.3)
            right = self.check(expr.right, scope)
            self.infer(expr.left, scope, right if right.kind is T.Kind.ENUM else None)
            return T.BOOL
        left = self.check(expr.left, scope)
        right_expected = left if (left.kind is T.Kind.ENUM and op in _EQUALITY) else None
        right = (
            self.check(expr.right, scope, None)
            if right_expected is None
            else self.infer(expr.right, scope, right_expected)
        )
        if left.kind is T.Kind.UNKNOWN and right.kind is T.Kind.ENUM and op in _EQUALITY:
            pass
        if op in _EQUALITY:
            self._comparable(expr, left, right)
            return T.BOOL
        if op in _ORDER:
            if self._numeric(expr, left, right):
                self._comparable(expr, left, right)
            return T.BOOL
        if op in _ARITH:
            if left.kind is T.Kind.STRING and right.kind is T.Kind.STRING and op == "+":
                return T.STRING
            if not self._numeric(expr, left, right):
                return T.UNKNOWN
            return self._sum_type(expr, left, right)
        if op in _SCALE:
            if not self._numeric(expr, left, right):
                return T.UNKNOWN
            return self._product_type(op, left, right)
        return T.UNKNOWN

    def _numeric(self, expr: ast.Binary, left: T.Type, right: T.Type) -> bool:
        for side, t in ((expr.left, left), (expr.right, right)):
            if not t.is_unknown and not t.is_numeric:
                self.report(
                    messages.type_mismatch(side.span, t, None, f"operand of `{expr.op}` (a number)")
                )
                return False
        return not (left.is_unknown or right.is_unknown)

    def _comparable(self, expr: ast.Binary, left: T.Type, right: T.Type) -> None:
        if left.is_unknown or right.is_unknown:
            return
        if left.kind is T.Kind.PHYSICAL or right.kind is T.Kind.PHYSICAL:
            if left.kind is T.Kind.PHYSICAL and right.kind is T.Kind.PHYSICAL:
                if left.dimension != right.dimension:
                    self.report(
                        messages.dimension_mismatch(
                            expr.span, right, left, f"comparison `{expr.op}`"
                        )
                    )
            else:
                plain = expr.right if right.kind is not T.Kind.PHYSICAL else expr.left
                physical = left if left.kind is T.Kind.PHYSICAL else right
                self.report(messages.missing_unit(plain.span, physical, "comparison"))
            return
        if left.is_numeric and right.is_numeric:
            return
        if T.compatible(left, right) is T.Compat.OK or T.compatible(right, left) is T.Compat.OK:
            return
        self.report(messages.type_mismatch(expr.right.span, right, left, f"operand of `{expr.op}`"))

    def _sum_type(self, expr: ast.Binary, left: T.Type, right: T.Type) -> T.Type:
        if left.kind is T.Kind.PHYSICAL and right.kind is T.Kind.PHYSICAL:
            if left.dimension != right.dimension:
                self.report(messages.dimension_mismatch(expr.span, right, left, f"`{expr.op}`"))
                return T.UNKNOWN
            return left
        if left.kind is T.Kind.PHYSICAL or right.kind is T.Kind.PHYSICAL:
            plain = expr.right if right.kind is not T.Kind.PHYSICAL else expr.left
            physical = left if left.kind is T.Kind.PHYSICAL else right
            self.report(messages.missing_unit(plain.span, physical, f"operand of `{expr.op}`"))
            return physical
        return _plain_result(left, right)

    def _product_type(self, op: str, left: T.Type, right: T.Type) -> T.Type:
        ldim = left.dimension if left.kind is T.Kind.PHYSICAL else T.DIMENSIONLESS
        rdim = right.dimension if right.kind is T.Kind.PHYSICAL else T.DIMENSIONLESS
        if op == "%":
            return left if left.kind is T.Kind.PHYSICAL else _plain_result(left, right)
        sign = 1 if op == "*" else -1
        dim = T.add_dims(ldim or T.DIMENSIONLESS, rdim or T.DIMENSIONLESS, sign)
        if dim == T.DIMENSIONLESS:
            if left.kind is T.Kind.PHYSICAL or right.kind is T.Kind.PHYSICAL or op == "/":
                return T.FLOAT
            return _plain_result(left, right)
        return self.physical_type(dim)

    def physical_type(self, dim: T.Dimension) -> T.Type:
        """The named physical type of a dimension (``length`` for m), or an anonymous one."""
        if self._physical_types is None:
            table: dict[T.Dimension | None, T.Type] = {}
            for model in (self.model, self.model.base):  # the first declared wins
                if model is None:
                    continue
                for sym in model.symbols:
                    if sym.kind is SymbolKind.PHYSICAL_TYPE and sym.type is not None:
                        table.setdefault(sym.dimension, sym.type)
            self._physical_types = table
        return self._physical_types.get(dim) or T.Type(T.Kind.PHYSICAL, None, dim)


def _plain_result(left: T.Type, right: T.Type) -> T.Type:
    if T.Kind.FLOAT in (left.kind, right.kind):
        return T.FLOAT
    if T.Kind.INT in (left.kind, right.kind):
        return T.INT
    return T.UINT
