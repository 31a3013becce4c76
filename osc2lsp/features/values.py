"""Constant folding of physical values, with the exact unit factors of the library.

``evaluate(model, expr)`` folds literals, unary and binary arithmetic and names
of fields, variables and global parameters whose initialiser folds, into a
``Quantity``: an exact value in SI base units, its dimension, and the unit it
is best shown in (the unit it was written in, carried through sums and
through products with plain numbers). ``v_hero + 12.42mph`` with
``v_hero = 35kph`` folds to 15.274... m/s, shown as ≈ 55.0 kph.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.semantics.types import BASE_UNITS, DIMENSIONLESS, Dimension, add_dims
from osc2check.syntax import ast

_VALUE_KINDS = (SymbolKind.FIELD, SymbolKind.VARIABLE, SymbolKind.GLOBAL, SymbolKind.ARGUMENT)
_MAX_DEPTH = 32


@dataclass(frozen=True, slots=True)
class Quantity:
    si: Fraction  # the value in SI base units
    dimension: Dimension
    unit: Symbol | None = None  # the unit to show it in

    @property
    def physical(self) -> bool:
        return self.dimension != DIMENSIONLESS or self.unit is not None


def evaluate(model: Model, expr: ast.Node | None, _seen: tuple = ()) -> Quantity | None:
    """The constant value of ``expr``, or None when it is not a constant."""
    if expr is None or len(_seen) > _MAX_DEPTH:
        return None
    match expr:
        case ast.IntLiteral():
            return Quantity(Fraction(expr.value), DIMENSIONLESS)
        case ast.FloatLiteral():
            try:
                return Quantity(Fraction(expr.text), DIMENSIONLESS)
            except (ValueError, ZeroDivisionError):
                return None
        case ast.PhysicalLiteral():
            unit = model.references.get(expr.unit) or model.unit(expr.unit.text)
            if unit is None or unit.kind is not SymbolKind.UNIT or unit.dimension is None:
                return None
            try:
                number = Fraction(expr.number_text)
            except (ValueError, ZeroDivisionError):
                return None
            return Quantity(number * unit.factor + unit.offset, unit.dimension, unit)
        case ast.NameRef():
            sym = model.references.get(expr.name.name)
            return value_of(model, sym, _seen)
        case ast.Unary(op="-"):
            inner = evaluate(model, expr.operand, _seen)
            return Quantity(-inner.si, inner.dimension, inner.unit) if inner else None
        case ast.Unary(op="+"):
            return evaluate(model, expr.operand, _seen)
        case ast.Binary(op="+" | "-"):
            left = evaluate(model, expr.left, _seen)
            right = evaluate(model, expr.right, _seen)
            if left is None or right is None or left.dimension != right.dimension:
                return None
            value = left.si + right.si if expr.op == "+" else left.si - right.si
            return Quantity(value, left.dimension, left.unit or right.unit)
        case ast.Binary(op="*" | "/"):
            left = evaluate(model, expr.left, _seen)
            right = evaluate(model, expr.right, _seen)
            if left is None or right is None:
                return None
            if expr.op == "*":
                value, dim = left.si * right.si, add_dims(left.dimension, right.dimension)
            else:
                if right.si == 0:
                    return None
                value, dim = left.si / right.si, add_dims(left.dimension, right.dimension, -1)
            unit = None
            if right.dimension == DIMENSIONLESS and right.unit is None:
                unit = left.unit
            elif left.dimension == DIMENSIONLESS and left.unit is None and expr.op == "*":
                unit = right.unit
            return Quantity(value, dim, unit)
    return None


def value_of(model: Model, sym: Symbol | None, _seen: tuple = ()) -> Quantity | None:
    """The constant value of a field, variable or global parameter (its initialiser)."""
    if sym is None or sym.kind not in _VALUE_KINDS or sym.default is None:
        return None
    if any(s is sym for s in _seen):
        return None
    return evaluate(model, sym.default, (*_seen, sym))


# ---- text ---------------------------------------------------------------------


def in_unit(q: Quantity, unit: Symbol) -> Fraction:
    return (q.si - unit.offset) / unit.factor if unit.factor else q.si


def format_number(x: Fraction) -> str:
    """Exact decimals as written (``12.42``); others to about three significant
    digits, at least one decimal, marked with ``≈`` (``≈ 55.0``)."""
    scaled = x * 10**6
    if scaled.denominator == 1:
        text = (
            f"{x.numerator // x.denominator}"
            if x.denominator == 1
            else f"{float(x):.6f}".rstrip("0").rstrip(".")
        )
        return text
    value = float(x)
    magnitude = len(str(int(abs(value)))) if abs(value) >= 1 else 0
    if magnitude == 0:
        return f"≈ {value:.3g}"
    return f"≈ {value:.{max(1, 3 - magnitude)}f}"


def dimension_units(dim: Dimension) -> str:
    """``m/s^2`` style text for the SI base units of a dimension."""
    top = [(b, e) for b, e in zip(BASE_UNITS, dim, strict=True) if e > 0]
    bottom = [(b, -e) for b, e in zip(BASE_UNITS, dim, strict=True) if e < 0]

    def part(items):
        return "*".join(b if e == 1 else f"{b}^{e}" for b, e in items)

    if not top and not bottom:
        return ""
    if not bottom:
        return part(top)
    return f"{part(top) or '1'}/{part(bottom)}"


def describe(q: Quantity) -> str:
    """``≈ 55.0 kph (≈ 15.3 m/s)``; SI only when there is no unit to show it in."""
    si_units = dimension_units(q.dimension)
    si = f"{format_number(q.si)} {si_units}".rstrip()
    if q.unit is None:
        return si
    written = f"{format_number(in_unit(q, q.unit))} {q.unit.name}"
    if q.unit.factor == 1 and q.unit.offset == 0 and q.unit.name == si_units:
        return written
    return f"{written} ({si})"


def short(q: Quantity) -> str:
    """The value in its written unit only (``≈ 55.0 kph``)."""
    if q.unit is None:
        return f"{format_number(q.si)} {dimension_units(q.dimension)}".rstrip()
    return f"{format_number(in_unit(q, q.unit))} {q.unit.name}"
