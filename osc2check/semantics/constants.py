"""The one exact evaluator of constant expressions.

``evaluate(expr, model, lookup)`` folds an expression to an exact value:

* numbers are ``int`` or ``Fraction`` (``int / int`` is exact: the type checker
  gives ``/`` a float result, and a float is exact here until the runner turns it
  into a machine float);
* physical values are :class:`Quantity`: the value in SI base units as a fraction
  and its dimension, plus the unit it was written in (for display only; two
  quantities are equal when their SI values and dimensions are), so
  ``35kph + 12.42mph`` folds without rounding and shows in ``kph``;
* enum members are :class:`EnumValue`, ranges :class:`RangeValue`, lists tuples,
  strings and booleans themselves.

Names are values only through ``lookup(symbol, node)``: the language server
looks up a field's initialiser, the runner the witness's value, the flow checks
nothing at all (they fold literals). Anything else (actor state, method calls,
events) raises :class:`NotConstant` with the node that is not constant.

Hover, inlay hints, the flow checks (B604, B609), lowering (physical literals
to SI) and the runner's parameter values all use this module.
"""

from __future__ import annotations

import operator
from collections.abc import Callable
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from osc2check.numbers import NumberOutOfRange, exact_number, representable
from osc2check.semantics import types as T
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast

__all__ = [
    "EnumValue",
    "Lookup",
    "NotConstant",
    "Quantity",
    "RangeValue",
    "Value",
    "evaluate",
    "initial_value",
    "literal_number",
    "physical_literal",
    "si_number",
    "to_json",
    "to_runtime",
]


@dataclass(frozen=True, slots=True)
class Quantity:
    """An exact physical value: ``si`` in SI base units, its dimension, its display unit."""

    si: Fraction
    dimension: T.Dimension
    unit: Symbol | None = field(default=None, compare=False)

    @property
    def physical(self) -> bool:
        """Whether it has a dimension or was written with a unit (not a plain number)."""
        return self.dimension != T.DIMENSIONLESS or self.unit is not None

    def __str__(self) -> str:
        return f"{float(self.si):g} {T.dimension_text(self.dimension)}"


@dataclass(frozen=True, slots=True)
class EnumValue:
    """An enum member: its enum's name, its own name and its number."""

    enum: str
    member: str
    value: int = 0

    def __str__(self) -> str:
        return self.member


@dataclass(frozen=True, slots=True)
class RangeValue:
    """``[low..high]`` with both bounds folded (in the order written)."""

    low: Value
    high: Value


Value = bool | int | Fraction | Quantity | str | EnumValue | RangeValue | tuple["Value", ...]
Lookup = Callable[[Symbol, ast.Node], Value]


class NotConstant(Exception):
    """The expression has no constant value; ``node`` is the part that is not constant."""

    def __init__(self, message: str, node: ast.Node | None = None) -> None:
        super().__init__(message)
        self.node = node


def literal_number(node: ast.IntLiteral | ast.FloatLiteral) -> int | Fraction:
    """The exact number a numeric literal writes (``1.5`` is 3/2); NotConstant beyond
    the budget of ``osc2check.numbers`` (reported as T209 by the parser)."""
    try:
        return exact_number(node.text or "0")
    except NumberOutOfRange:
        raise NotConstant(f"`{node.text}` is out of range", node) from None
    except ValueError:
        raise NotConstant(f"`{node.text}` has no exact value", node) from None


def physical_literal(node: ast.PhysicalLiteral, model: Model) -> Quantity:
    """``20kph`` as an exact SI quantity, through its unit's factor and offset."""
    unit = model.reference(node.unit) or model.unit(node.unit.text)
    if unit is None or unit.kind is not SymbolKind.UNIT or unit.dimension is None:
        raise NotConstant(f"unknown unit `{node.unit.text}`", node)
    number = node.number  # exact as written (a float only for what has no exact value)
    if isinstance(number, float):
        raise NotConstant(f"`{node.number_text}` has no exact value", node)
    return Quantity(number * unit.factor + unit.offset, unit.dimension, unit)


def evaluate(
    expr: ast.Node,
    model: Model,
    lookup: Lookup | None = None,
    it: Callable[[ast.Node], Value] | None = None,
) -> Value:
    """The exact value of ``expr`` (see the module docstring); raises NotConstant."""
    return _Evaluator(model, lookup, it).value(expr)


def initial_value(model: Model, sym: Symbol | None, _seen: tuple[Symbol, ...] = ()) -> Value:
    """The value of a field, variable, global or argument from its declared initialiser
    (``x: speed = 50kph``), following names to their own initialisers."""
    if sym is None or sym.default is None:
        raise NotConstant("no initial value")
    if any(s is sym for s in _seen) or len(_seen) > 32:
        raise NotConstant(f"the value of `{sym.name}` depends on itself", sym.decl)
    seen = (*_seen, sym)

    def lookup(target: Symbol, node: ast.Node) -> Value:
        return initial_value(model, target, seen)

    return evaluate(sym.default, model, lookup)


_VALUE_KINDS = (SymbolKind.FIELD, SymbolKind.VARIABLE, SymbolKind.GLOBAL, SymbolKind.ARGUMENT)
# Ordering raises TypeError for operands of kinds that have no order (a string and a number).
_COMPARE: dict[str, Callable[[Any, Any], bool]] = {
    "==": operator.eq,
    "!=": operator.ne,
    "<": operator.lt,
    "<=": operator.le,
    ">": operator.gt,
    ">=": operator.ge,
}


class _Evaluator:
    def __init__(
        self, model: Model, lookup: Lookup | None, it: Callable[[ast.Node], Value] | None
    ) -> None:
        self.model = model
        self.lookup = lookup
        self.it = it

    def value(self, e: ast.Node) -> Value:
        match e:
            case ast.IntLiteral() | ast.FloatLiteral():
                return literal_number(e)
            case ast.PhysicalLiteral():
                return physical_literal(e, self.model)
            case ast.StringLiteral():
                return e.value
            case ast.BoolLiteral():
                return e.value
            case ast.EnumRef():
                member = self.model.reference(e.member)
                if member is None or member.kind is not SymbolKind.ENUM_MEMBER:
                    raise NotConstant(f"unknown enum member `{e.member.text}`", e)
                return _enum(member)
            case ast.NameRef():
                return self._name(e)
            case ast.Unary():
                return self._unary(e)
            case ast.Binary():
                return self._binary(e)
            case ast.Ternary():
                condition = self.value(e.condition)
                if not isinstance(condition, bool):
                    raise NotConstant("the condition of `?:` is not a boolean", e.condition)
                return self.value(e.then if condition else e.otherwise)
            case ast.RangeLiteral():
                return RangeValue(self.value(e.low), self.value(e.high))
            case ast.ListLiteral():
                return tuple(self.value(item) for item in e.items)
        raise NotConstant("not a constant", e)

    def _name(self, e: ast.NameRef) -> Value:
        name = e.name.name
        if e.name.namespace is None and name.text == "it" and self.it is not None:
            return self.it(e)
        sym = self.model.reference(name)
        if sym is None:
            raise NotConstant(f"`{name.text}` is not a constant", e)
        if sym.kind is SymbolKind.ENUM_MEMBER:
            return _enum(sym)
        if sym.kind in _VALUE_KINDS and self.lookup is not None:
            return self.lookup(sym, e)
        raise NotConstant(f"`{name.text}` is not a constant", e)

    def _unary(self, e: ast.Unary) -> Value:
        value = self.value(e.operand)
        if e.op == "not":
            if not isinstance(value, bool):
                raise NotConstant("`not` needs a boolean", e)
            return not value
        if e.op == "+":
            return value
        if isinstance(value, Quantity):
            return Quantity(-value.si, value.dimension, value.unit)
        number = _number(value)
        if number is None:
            raise NotConstant("`-` needs a number", e)
        return -number

    def _binary(self, e: ast.Binary) -> Value:
        op = e.op
        left: Value
        right: Value
        if op in ("and", "or", "=>"):
            left, right = self._bool(e.left), self._bool(e.right)
            if op == "and":
                return left and right
            if op == "or":
                return left or right
            return (not left) or right
        left, right = self.value(e.left), self.value(e.right)
        if op in _COMPARE:
            try:
                return _COMPARE[op](_comparable(left, right, e), _comparable(right, left, e))
            except TypeError:
                raise NotConstant(f"`{op}` cannot compare these operands", e) from None
        if op == "in":
            if isinstance(right, RangeValue):
                low, high = _comparable(right.low, left, e), _comparable(right.high, left, e)
                item = _comparable(left, right.low, e)
                le = _COMPARE["<="]
                try:
                    lo, hi = (low, high) if le(low, high) else (high, low)
                    return le(lo, item) and le(item, hi)
                except TypeError:
                    raise NotConstant("`in` cannot compare these operands", e) from None
            if isinstance(right, tuple):
                return left in right
            raise NotConstant("`in` needs a range or a list", e)
        return arithmetic(op, left, right, e)

    def _bool(self, e: ast.Node) -> bool:
        value = self.value(e)
        if not isinstance(value, bool):
            raise NotConstant("a logical operator needs booleans", e)
        return value


def arithmetic(op: str, left: Value, right: Value, node: ast.Node | None = None) -> Value:
    """``left op right`` for ``+ - * / %`` over exact numbers and quantities; NotConstant
    for a result beyond the budget (``numbers.representable``)."""
    result = _arithmetic(op, left, right, node)
    number = result.si if isinstance(result, Quantity) else _number(result)
    if number is not None and not representable(number):
        raise NotConstant("the value is out of the range of numbers", node)
    return result


def _arithmetic(op: str, left: Value, right: Value, node: ast.Node | None) -> Value:
    ln, rn = _number(left), _number(right)
    if ln is not None and rn is not None:
        if op in ("/", "%") and rn == 0:
            raise NotConstant("division by zero", node)
        if op == "/":
            return Fraction(ln) / Fraction(rn)
        return _ARITH[op](ln, rn)
    if isinstance(left, str) and isinstance(right, str) and op == "+":
        return left + right
    lq, rq = _as_quantity(left), _as_quantity(right)
    if lq is None or rq is None:
        raise NotConstant(f"`{op}` cannot fold these operands", node)
    if op in ("+", "-", "%"):
        if lq.dimension != rq.dimension:
            raise NotConstant("the dimensions differ", node)
        if op == "%" and rq.si == 0:
            raise NotConstant("division by zero", node)
        return Quantity(Fraction(_ARITH[op](lq.si, rq.si)), lq.dimension, lq.unit or rq.unit)
    if op == "*":
        dim = T.add_dims(lq.dimension, rq.dimension)
        unit = lq.unit if rn is not None else rq.unit if ln is not None else None
        return _quantity(lq.si * rq.si, dim, unit)
    if op == "/":
        if rq.si == 0:
            raise NotConstant("division by zero", node)
        dim = T.add_dims(lq.dimension, rq.dimension, -1)
        return _quantity(lq.si / rq.si, dim, lq.unit if rn is not None else None)
    raise NotConstant(f"unknown operator `{op}`", node)


_ARITH: dict[str, Callable[[Fraction | int, Fraction | int], Fraction | int]] = {
    "+": operator.add,
    "-": operator.sub,
    "*": operator.mul,
    "%": operator.mod,
}


def si_number(value: object) -> Fraction | None:
    """The SI number of a constant value (a quantity's ``si``, a number as it is), or None
    for anything else (a bool, an enum member, a string, a range, ...)."""
    if isinstance(value, Quantity):
        return value.si
    number = _number(value)
    return Fraction(number) if number is not None else None


def _number(value: object) -> int | Fraction | None:
    if isinstance(value, bool):
        return None
    if isinstance(value, (int, Fraction)):
        return value
    return None


def _as_quantity(value: object) -> Quantity | None:
    if isinstance(value, Quantity):
        return value
    number = _number(value)
    return Quantity(Fraction(number), T.DIMENSIONLESS) if number is not None else None


def _quantity(si: Fraction, dim: T.Dimension, unit: Symbol | None) -> Value:
    if dim == T.DIMENSIONLESS and unit is None:
        return si
    return Quantity(si, dim, unit)


def _comparable(value: Value, other: Value, node: ast.Node) -> object:
    """The part of ``value`` that comparisons read (SI numbers for quantities)."""
    if isinstance(value, Quantity):
        if isinstance(other, Quantity) and other.dimension != value.dimension:
            raise NotConstant("the dimensions differ", node)
        return value.si
    if isinstance(value, EnumValue):
        return (value.enum, value.value)
    return value


def _enum(member: Symbol) -> EnumValue:
    owner = member.owner.name if member.owner is not None else ""
    return EnumValue(owner, member.name, member.value)


def to_runtime(value: object) -> object:
    """The run-time form of a value: SI floats for numbers that are not whole, enum
    members by name, ranges as ``(low, high)``; the only place exactness is given up."""
    if isinstance(value, Quantity):
        return float(value.si)
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
    """A JSON-ready form of a value (physical values with their SI unit and exact text)."""
    if isinstance(value, Quantity):
        return {
            "si": float(value.si),
            "unit": T.dimension_text(value.dimension),
            "exact": str(value.si),
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
