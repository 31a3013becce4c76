"""Parameter values of one scenario instance: where the runner gets every number it runs with.

The design's data flow has the checker's solver produce a *witness* (concrete
values for every parameter, seeded); the runner executes exactly that witness.
Until the solver lands, :class:`ConstantValues` folds what the source pins
down as constants:

* ``keep(x == c)`` and ``keep(c == x)`` (hard), in the scenario or in the
  field's own ``with:`` block (``keep(it == c)``);
* ``keep(default x == c)`` and the field's ``= c`` (default strength; a later
  default overrides an earlier one, a hard constraint overrides both);
* ``var`` initialisers;
* actor attributes: ``hero: vehicle with: keep(it.model == "...")``.

Values are exact: numbers are ints or :class:`~fractions.Fraction`, physical
values are :class:`Quantity` (SI value as a fraction and its dimension), so
``35kph + 12.42mph`` is folded without rounding. :func:`to_runtime` turns them
into the floats (SI units) the simulation runs with — the only place where
exactness is given up.

:class:`ParameterValues` is the interface; the solver's witness will be a
second implementation of it.
"""

from __future__ import annotations

import operator
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from fractions import Fraction

from osc2check.semantics import types as T
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast

__all__ = [
    "ConstantValues",
    "EnumValue",
    "NoValue",
    "ParameterValues",
    "Quantity",
    "RangeValue",
    "fold",
    "scenario_fields",
    "to_json",
    "to_runtime",
]


# ---------------------------------------------------------------------- exact values


@dataclass(frozen=True, slots=True)
class Quantity:
    """An exact physical value: ``value`` in SI units and its dimension."""

    value: Fraction
    dimension: T.Dimension

    def __str__(self) -> str:
        return f"{float(self.value):g} {T.dimension_text(self.dimension)}"


@dataclass(frozen=True, slots=True)
class EnumValue:
    """An enum member, by its enum's and its own name."""

    enum: str
    member: str

    def __str__(self) -> str:
        return self.member


@dataclass(frozen=True, slots=True)
class RangeValue:
    """``[low..high]``: both bounds folded."""

    low: object
    high: object


class NoValue(Exception):
    """A value the constants do not determine (the solver will)."""

    def __init__(self, message: str, node: ast.Node | None = None) -> None:
        super().__init__(message)
        self.node = node


Exact = int | Fraction | Quantity | bool | str | EnumValue | RangeValue | tuple


def to_runtime(value: object) -> object:
    """The runtime form of an exact value: SI floats for physical values and fractions."""
    if isinstance(value, Quantity):
        return float(value.value)
    if isinstance(value, Fraction):
        return float(value)
    if isinstance(value, EnumValue):
        return value.member
    if isinstance(value, RangeValue):
        return (to_runtime(value.low), to_runtime(value.high))
    if isinstance(value, tuple):
        return tuple(to_runtime(v) for v in value)
    return value


def to_json(value: object) -> object:
    """A JSON-friendly form of an exact value (physical values with their SI unit)."""
    if isinstance(value, Quantity):
        return {
            "si": float(value.value),
            "unit": T.dimension_text(value.dimension),
            "exact": str(value.value),
        }
    if isinstance(value, Fraction):
        return float(value)
    if isinstance(value, EnumValue):
        return value.member
    if isinstance(value, RangeValue):
        return [to_json(value.low), to_json(value.high)]
    if isinstance(value, tuple):
        return [to_json(v) for v in value]
    return value


# ---------------------------------------------------------------------- the interface


class ParameterValues(ABC):
    """The values of one scenario instance's parameters, variables and actor attributes.

    ``value`` and ``attribute`` return exact values (see the module docstring)
    and raise :class:`NoValue` when the source of values does not determine
    one. A solver witness implements the same interface.
    """

    @abstractmethod
    def value(self, field: Symbol) -> object:
        """The value of a scenario parameter or the initial value of a variable."""

    @abstractmethod
    def attribute(self, actor: Symbol, member: str) -> object | None:
        """A constant attribute of an actor field (``keep(it.model == "...")``), or None."""

    @abstractmethod
    def table(self) -> dict[str, object]:
        """Every determined value by name, JSON-friendly, for the run metadata."""

    @property
    def source(self) -> str:
        """Where the values come from, for the run metadata."""
        return type(self).__name__


# ---------------------------------------------------------------------- folding


def scenario_fields(model: Model, scenario: Symbol) -> list[Symbol]:
    """The fields (parameters, variables, events excluded) of a scenario, inherited first."""
    return [
        m for m in model.all_members(scenario) if m.kind in (SymbolKind.FIELD, SymbolKind.VARIABLE)
    ]


_ARITH: dict[str, Callable[[object, object], object]] = {
    "+": operator.add,
    "-": operator.sub,
    "*": operator.mul,
    "/": operator.truediv,
    "%": operator.mod,
}
_COMPARE: dict[str, Callable[[object, object], bool]] = {
    "==": operator.eq,
    "!=": operator.ne,
    "<": operator.lt,
    "<=": operator.le,
    ">": operator.gt,
    ">=": operator.ge,
}


def _number(value: object) -> Fraction | int | None:
    if isinstance(value, bool):
        return None
    if isinstance(value, (int, Fraction)):
        return value
    return None


def _arith(op: str, left: object, right: object, node: ast.Node) -> object:
    fn = _ARITH[op]
    ln, rn = _number(left), _number(right)
    if ln is not None and rn is not None:
        if op == "/" and isinstance(ln, int) and isinstance(rn, int):
            return Fraction(ln, rn) if rn else _fail("division by zero", node)
        return fn(Fraction(ln), Fraction(rn)) if op in "/%" else fn(ln, rn)
    if isinstance(left, Quantity) and isinstance(right, Quantity):
        if op in "+-%":
            if left.dimension != right.dimension:
                _fail("dimensions differ", node)
            return Quantity(fn(left.value, right.value), left.dimension)
        if op == "*":
            return _quantity(left.value * right.value, T.add_dims(left.dimension, right.dimension))
        if right.value == 0:
            _fail("division by zero", node)
        return _quantity(left.value / right.value, T.add_dims(left.dimension, right.dimension, -1))
    if isinstance(left, Quantity) and rn is not None and op in "*/":
        if op == "/" and rn == 0:
            _fail("division by zero", node)
        return Quantity(fn(left.value, Fraction(rn)), left.dimension)
    if ln is not None and isinstance(right, Quantity) and op in "*/":
        if op == "*":
            return Quantity(Fraction(ln) * right.value, right.dimension)
        return _quantity(
            Fraction(ln) / right.value, T.add_dims(T.DIMENSIONLESS, right.dimension, -1)
        )
    if op == "+" and isinstance(left, str) and isinstance(right, str):
        return left + right
    _fail(f"cannot fold `{op}` on these operands", node)
    return None  # unreachable


def _quantity(value: Fraction, dim: T.Dimension) -> object:
    return value if dim == T.DIMENSIONLESS else Quantity(value, dim)


def _comparable(value: object) -> object:
    if isinstance(value, Quantity):
        return value.value
    return value


def _fail(message: str, node: ast.Node | None) -> None:
    raise NoValue(message, node)


def fold(
    expr: ast.Node,
    model: Model,
    lookup: Callable[[Symbol, ast.Node], object],
    it: Callable[[ast.Node], object] | None = None,
) -> object:
    """The exact value of a constant expression.

    ``lookup(symbol, node)`` gives the value of a referenced field; ``it``
    the value of ``it`` (or raises). Raises :class:`NoValue` for anything that
    is not a constant (actor state, methods, unknown parameters).
    """

    def go(e: ast.Node) -> object:
        match e:
            case ast.IntLiteral():
                return e.value
            case ast.FloatLiteral():
                try:
                    return Fraction(e.text.replace("_", ""))
                except (ValueError, ZeroDivisionError):
                    return Fraction(e.value)
            case ast.PhysicalLiteral():
                unit = model.references.get(e.unit) or model.unit(e.unit.text)
                if unit is None or unit.dimension is None:
                    _fail(f"unknown unit `{e.unit.text}`", e)
                number = e.number if isinstance(e.number, Fraction) else Fraction(e.number)
                return Quantity(number * unit.factor + unit.offset, unit.dimension)
            case ast.StringLiteral():
                return e.value
            case ast.BoolLiteral():
                return e.value
            case ast.EnumRef():
                sym = model.references.get(e.member)
                enum = (
                    sym.owner.name
                    if sym is not None and sym.owner is not None
                    else e.enum.name.text
                )
                return EnumValue(enum, e.member.text)
            case ast.NameRef():
                name = e.name.name
                sym = model.references.get(name)
                if sym is None:
                    if name.text == "it" and it is not None:
                        return it(e)
                    _fail(f"`{name.text}` is not a constant", e)
                if sym.kind is SymbolKind.ENUM_MEMBER:
                    return EnumValue(sym.owner.name if sym.owner is not None else "", sym.name)
                if sym.kind in (SymbolKind.FIELD, SymbolKind.VARIABLE, SymbolKind.GLOBAL):
                    return lookup(sym, e)
                _fail(f"`{name.text}` is not a constant", e)
            case ast.Unary():
                value = go(e.operand)
                if e.op == "not":
                    if not isinstance(value, bool):
                        _fail("`not` needs a boolean", e)
                    return not value
                if e.op == "+":
                    return value
                if isinstance(value, Quantity):
                    return Quantity(-value.value, value.dimension)
                number = _number(value)
                if number is None:
                    _fail("`-` needs a number", e)
                return -number
            case ast.Binary():
                if e.op in ("and", "or", "=>"):
                    left = go(e.left)
                    right = go(e.right)
                    if e.op == "and":
                        return bool(left) and bool(right)
                    if e.op == "or":
                        return bool(left) or bool(right)
                    return (not left) or bool(right)
                left, right = go(e.left), go(e.right)
                if e.op in _COMPARE:
                    return _COMPARE[e.op](_comparable(left), _comparable(right))
                if e.op == "in":
                    if isinstance(right, RangeValue):
                        lo, hi = _comparable(right.low), _comparable(right.high)
                        v = _comparable(left)
                        return min(lo, hi) <= v <= max(lo, hi)  # type: ignore[operator]
                    if isinstance(right, tuple):
                        return left in right
                    _fail("`in` needs a range or a list", e)
                return _arith(e.op, left, right, e)
            case ast.Ternary():
                return go(e.then) if go(e.condition) else go(e.otherwise)
            case ast.RangeLiteral():
                return RangeValue(go(e.low), go(e.high))
            case ast.ListLiteral():
                return tuple(go(item) for item in e.items)
            case ast.MemberAccess():
                _fail(f"`.{e.member.text}` is not a constant", e)
        _fail(f"`{type(e).__name__}` is not a constant", e)
        return None  # unreachable

    return go(expr)


# ---------------------------------------------------------------------- constants


@dataclass
class _Source:
    """One candidate value of a field: its expression, strength and order."""

    expr: ast.Node
    hard: bool
    order: int
    it_field: Symbol | None = None  # `it` stands for this field (with-block constraints)


class ConstantValues(ParameterValues):
    """Values folded from constants (see the module docstring).

    Parameters:
        model: the program's model.
        scenario: the scenario symbol whose instance is run.
    """

    def __init__(self, model: Model, scenario: Symbol) -> None:
        self.model = model
        self.scenario = scenario
        self.fields = scenario_fields(model, scenario)
        self._sources: dict[Symbol, list[_Source]] = {f: [] for f in self.fields}
        self._attributes: dict[Symbol, dict[str, list[_Source]]] = {}
        self._cache: dict[Symbol, object] = {}
        self._active: list[Symbol] = []
        self._order = 0
        self._collect()

    # ---- collection

    def _next(self) -> int:
        self._order += 1
        return self._order

    def _collect(self) -> None:
        for decl in self._scenario_decls():
            for member in decl.members:
                match member:
                    case ast.FieldDecl():
                        self._field_decl(member)
                    case ast.KeepConstraint():
                        self._keep(member, None)

    def _scenario_decls(self) -> Iterator[ast.StructuredDecl]:
        chain = list(self.model.ancestors(self.scenario))
        for sym in reversed(chain):
            if isinstance(sym.decl, ast.StructuredDecl):
                yield sym.decl

    def _field_symbols(self, decl: ast.FieldDecl) -> list[Symbol]:
        found = []
        for name in decl.names:
            sym = self.model.references.get(name)
            if sym is not None and sym in self._sources:
                found.append(sym)
        return found

    def _field_decl(self, decl: ast.FieldDecl) -> None:
        symbols = self._field_symbols(decl)
        for sym in symbols:
            if decl.default is not None:
                # a `var` initialiser is an assignment; a parameter's `= v` has default strength
                self._sources[sym].append(_Source(decl.default, decl.is_var, self._next()))
        for member in decl.with_members:
            if isinstance(member, ast.KeepConstraint):
                for sym in symbols:
                    self._keep(member, sym)

    def _keep(self, keep: ast.KeepConstraint, it_field: Symbol | None) -> None:
        expr = keep.expr
        if not isinstance(expr, ast.Binary):
            return
        hard = keep.strength != "default"
        if expr.op == "==":
            for target, value in ((expr.left, expr.right), (expr.right, expr.left)):
                if self._bind(target, value, hard, it_field):
                    return
        elif expr.op == "and":
            self._keep(ast.KeepConstraint(keep.span, keep.strength, expr.left), it_field)
            self._keep(ast.KeepConstraint(keep.span, keep.strength, expr.right), it_field)

    def _bind(self, target: ast.Node, value: ast.Node, hard: bool, it_field: Symbol | None) -> bool:
        if isinstance(target, ast.NameRef):
            name = target.name.name
            sym = self.model.references.get(name)
            if sym is None and name.text == "it" and it_field is not None:
                sym = it_field
            if sym in self._sources:
                self._sources[sym].append(_Source(value, hard, self._next(), it_field))
                return True
            return False
        if isinstance(target, ast.MemberAccess) and isinstance(target.target, ast.NameRef):
            name = target.target.name.name
            owner = self.model.references.get(name)
            if owner is None and name.text == "it":
                owner = it_field
            if owner is not None and owner in self._sources and _is_compound(owner):
                table = self._attributes.setdefault(owner, {})
                table.setdefault(target.member.text, []).append(
                    _Source(value, hard, self._next(), it_field)
                )
                return True
        return False

    # ---- values

    @staticmethod
    def _chosen(sources: list[_Source]) -> _Source | None:
        hard = [s for s in sources if s.hard]
        if hard:
            return hard[-1]
        return sources[-1] if sources else None

    def _lookup(self, sym: Symbol, node: ast.Node) -> object:
        if sym not in self._sources:
            raise NoValue(f"`{sym.name}` is not a parameter of this scenario", node)
        return self.value(sym)

    def value(self, field: Symbol) -> object:
        if field in self._cache:
            return self._cache[field]
        if field in self._active:
            cycle = " -> ".join(s.name for s in [*self._active, field])
            raise NoValue(f"the value of `{field.name}` depends on itself ({cycle})", field.decl)
        source = self._chosen(self._sources.get(field, []))
        if source is None:
            raise NoValue(
                f"`{field.name}` has no constant value; only constants are folded until the "
                "solver's witness is available",
                field.decl,
            )
        self._active.append(field)
        try:
            result = fold(source.expr, self.model, self._lookup, it=self._it(source.it_field))
        finally:
            self._active.pop()
        self._cache[field] = result
        return result

    def _it(self, field: Symbol | None) -> Callable[[ast.Node], object] | None:
        if field is None:
            return None
        return lambda node: self.value(field)

    def attribute(self, actor: Symbol, member: str) -> object | None:
        source = self._chosen(self._attributes.get(actor, {}).get(member, []))
        if source is None:
            return None
        return fold(source.expr, self.model, self._lookup)

    def attributes(self, actor: Symbol) -> dict[str, object]:
        """Every constant attribute of an actor field."""
        result: dict[str, object] = {}
        for member in self._attributes.get(actor, {}):
            try:
                value = self.attribute(actor, member)
            except NoValue:
                continue
            if value is not None:
                result[member] = value
        return result

    def table(self) -> dict[str, object]:
        result: dict[str, object] = {}
        for field in self.fields:
            if _is_compound(field):
                attrs = self.attributes(field)
                if attrs:
                    result[field.name] = {k: to_json(v) for k, v in attrs.items()}
                continue
            try:
                result[field.name] = to_json(self.value(field))
            except NoValue:
                continue
        return result

    @property
    def source(self) -> str:
        return "constants"


def _is_compound(sym: Symbol) -> bool:
    return sym.type is not None and sym.type.kind is T.Kind.COMPOUND
