"""Physical values for hover and inlay hints: the checker's exact constants, shown.

Folding is ``osc2check.semantics.constants`` (one evaluator for the checker, the
runner and the editor); this module only turns its quantities into text:
``v_hero + 12.42mph`` with ``v_hero = 35kph`` folds to 15.274... m/s, shown as
≈ 55.0 kph (the unit it was written in, carried through sums and through
products with plain numbers).
"""

from __future__ import annotations

from fractions import Fraction

from osc2check.semantics.constants import NotConstant, Quantity, Value, initial_value
from osc2check.semantics.constants import evaluate as fold
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol
from osc2check.semantics.types import BASE_UNITS, DIMENSIONLESS, Dimension
from osc2check.syntax import ast

__all__ = ["Quantity", "describe", "evaluate", "format_number", "in_unit", "short", "value_of"]


def _numeric(value: object) -> Quantity | None:
    if isinstance(value, Quantity):
        return value
    if isinstance(value, (int, Fraction)) and not isinstance(value, bool):
        return Quantity(Fraction(value), DIMENSIONLESS)
    return None


def evaluate(model: Model, expr: ast.Node | None) -> Quantity | None:
    """The constant numeric value of ``expr`` (names through their initialisers), or None."""
    if expr is None:
        return None

    def lookup(sym: Symbol, node: ast.Node) -> Value:
        return initial_value(model, sym)

    try:
        return _numeric(fold(expr, model, lookup))
    except (NotConstant, RecursionError):
        return None


def value_of(model: Model, sym: Symbol | None) -> Quantity | None:
    """The constant numeric value of a field, variable or global parameter's initialiser."""
    try:
        return _numeric(initial_value(model, sym))
    except (NotConstant, RecursionError):
        return None


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

    def part(items: list[tuple[str, int]]) -> str:
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
