"""Types of OSC2 values, physical dimensions and the rules that relate them.

A physical dimension is a vector of exponents over the SI base units plus
`rad`; unit factors and offsets are exact fractions. Two physical values are
compatible when their dimensions are equal, whatever their named types.
"""

from __future__ import annotations

import weakref
from enum import Enum
from fractions import Fraction
from typing import TYPE_CHECKING

from osc2check.semantics.builtins import PRIMITIVE_TYPES

if TYPE_CHECKING:
    from osc2check.semantics.symbols import Symbol

BASE_UNITS = ("m", "kg", "s", "A", "K", "mol", "cd", "rad")
Dimension = tuple[int, int, int, int, int, int, int, int]
DIMENSIONLESS: Dimension = (0,) * 8


def dimension_text(dim: Dimension) -> str:
    """``m*s^-1`` style text for a dimension."""
    parts = []
    for base, exp in zip(BASE_UNITS, dim, strict=True):
        if exp == 1:
            parts.append(base)
        elif exp:
            parts.append(f"{base}^{exp}")
    return "*".join(parts) or "1"


def add_dims(a: Dimension, b: Dimension, sign: int = 1) -> Dimension:
    return tuple(x + sign * y for x, y in zip(a, b, strict=True))  # type: ignore[return-value]


def snap_factor(value: Fraction) -> Fraction:
    """An exact small-denominator fraction when the decimal is a rounding of one (5/18)."""
    if value == 0:
        return value
    snapped = value.limit_denominator(3600)
    if abs(snapped - value) <= abs(value) * Fraction(1, 10**9):
        return snapped
    return value


class Kind(Enum):
    BOOL = "bool"
    INT = "int"
    UINT = "uint"
    FLOAT = "float"
    STRING = "string"
    PHYSICAL = "physical"
    ENUM = "enum"
    COMPOUND = "compound"  # struct, actor, scenario, action
    LIST = "list"
    RANGE = "range"
    UNKNOWN = "unknown"  # after an error: compatible with everything
    NONE = "none"  # methods without a return type


class Type:
    """The type of a value: its kind, the declaration it names (enums, physical types,
    structs, actors, scenarios, actions), its dimension, its element (lists, ranges).

    Immutable. The declaration is held weakly: a declaration's symbol holds its own
    type (``Symbol.type``), and a strong reference back would make every analysis a
    cycle that only the cyclic collector frees (about 13 MB for a 10,000-line file,
    held until a full collection). The model that declared the symbol keeps it
    alive; a type used after its analysis was dropped raises ``ReferenceError``
    rather than lose its declaration silently.
    """

    __slots__ = ("kind", "_symbol", "dimension", "element")

    kind: Kind
    _symbol: weakref.ref[Symbol] | None
    dimension: Dimension | None
    element: Type | None

    def __init__(
        self,
        kind: Kind,
        symbol: Symbol | None = None,
        dimension: Dimension | None = None,
        element: Type | None = None,
    ) -> None:
        object.__setattr__(self, "kind", kind)
        object.__setattr__(self, "_symbol", weakref.ref(symbol) if symbol is not None else None)
        object.__setattr__(self, "dimension", dimension)
        object.__setattr__(self, "element", element)

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError(f"Type is immutable: cannot set {name!r}")

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"Type is immutable: cannot delete {name!r}")

    @property
    def symbol(self) -> Symbol | None:
        """The declaration this type names (None for primitives, lists, ranges...)."""
        ref = self._symbol
        if ref is None:
            return None
        symbol = ref()
        if symbol is None:
            raise ReferenceError("the declaration of this type was freed with its analysis")
        return symbol

    def __reduce__(self) -> tuple[type[Type], tuple[object, ...]]:
        # the declaration is held weakly, which pickle cannot store: store the symbol
        return Type, (self.kind, self.symbol, self.dimension, self.element)

    def __repr__(self) -> str:
        return (
            f"Type(kind={self.kind!r}, symbol={self.symbol!r}, "
            f"dimension={self.dimension!r}, element={self.element!r})"
        )

    def __str__(self) -> str:
        if self.kind in (Kind.LIST, Kind.RANGE):
            return f"{self.kind.value} of {self.element}"
        symbol = self.symbol
        if symbol is not None:
            return symbol.name
        if self.kind is Kind.PHYSICAL:
            return f"physical ({dimension_text(self.dimension or DIMENSIONLESS)})"
        return str(self.kind.value)  # mypy loses `value`'s type after the `in` narrowing

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Type) or other.kind is not self.kind:
            return False
        if self.kind is Kind.PHYSICAL:
            return self.dimension == other.dimension
        if self.kind in (Kind.LIST, Kind.RANGE):
            return self.element == other.element
        return self.symbol is other.symbol

    def __hash__(self) -> int:
        return hash((self.kind, self.dimension, id(self.symbol)))

    @property
    def is_numeric(self) -> bool:
        return self.kind in NUMERIC

    @property
    def is_unknown(self) -> bool:
        return self.kind is Kind.UNKNOWN


NUMERIC = frozenset({Kind.INT, Kind.UINT, Kind.FLOAT, Kind.PHYSICAL})
PLAIN_NUMBERS = frozenset({Kind.INT, Kind.UINT, Kind.FLOAT})

BOOL = Type(Kind.BOOL)
INT = Type(Kind.INT)
UINT = Type(Kind.UINT)
FLOAT = Type(Kind.FLOAT)
STRING = Type(Kind.STRING)
UNKNOWN = Type(Kind.UNKNOWN)
NONE = Type(Kind.NONE)
PRIMITIVES = dict(zip(PRIMITIVE_TYPES, (BOOL, INT, UINT, FLOAT, STRING), strict=True))


def list_of(element: Type) -> Type:
    return Type(Kind.LIST, element=element)


def range_of(element: Type) -> Type:
    return Type(Kind.RANGE, element=element)


class Compat(Enum):
    """How a value of one type fits a place that expects another."""

    OK = "ok"
    NARROWING = "narrowing"  # float into int: T204
    MISSING_UNIT = "missing-unit"  # plain number into a physical type: T202
    DIMENSION = "dimension"  # physical of another dimension: T201
    MISMATCH = "mismatch"  # anything else: T203


def is_subtype(sub: Symbol | None, sup: Symbol | None) -> bool:
    seen = set()
    while sub is not None and id(sub) not in seen:
        if sub is sup:
            return True
        seen.add(id(sub))
        sub = sub.parent
    return False


def compatible(expected: Type, actual: Type, *, allow_range: bool = False) -> Compat:
    """Whether ``actual`` may stand where ``expected`` is required."""
    if expected.is_unknown or actual.is_unknown:
        return Compat.OK
    if expected.kind is Kind.RANGE:
        if actual.kind is Kind.RANGE:
            return compatible(expected.element, actual.element)  # type: ignore[arg-type]
        return compatible(expected.element, actual)  # type: ignore[arg-type]
    if actual.kind is Kind.RANGE and allow_range:
        return compatible(expected, actual.element)  # type: ignore[arg-type]
    if expected.kind is Kind.PHYSICAL:
        if actual.kind is Kind.PHYSICAL:
            return Compat.OK if actual.dimension == expected.dimension else Compat.DIMENSION
        if actual.kind in PLAIN_NUMBERS:
            return Compat.MISSING_UNIT
        return Compat.MISMATCH
    if expected.kind is Kind.FLOAT:
        return Compat.OK if actual.kind in PLAIN_NUMBERS else Compat.MISMATCH
    if expected.kind in (Kind.INT, Kind.UINT):
        if actual.kind in (Kind.INT, Kind.UINT):
            return Compat.OK
        if actual.kind is Kind.FLOAT:
            return Compat.NARROWING
        return Compat.MISMATCH
    if expected.kind is Kind.LIST:
        if actual.kind is Kind.LIST:
            if actual.element is None or actual.element.is_unknown:
                return Compat.OK
            return compatible(expected.element, actual.element)  # type: ignore[arg-type]
        return Compat.MISMATCH
    if expected.kind is Kind.COMPOUND:
        if actual.kind is Kind.COMPOUND and is_subtype(actual.symbol, expected.symbol):
            return Compat.OK
        return Compat.MISMATCH
    if expected.kind is Kind.ENUM:
        return (
            Compat.OK
            if actual.kind is Kind.ENUM and actual.symbol is expected.symbol
            else Compat.MISMATCH
        )
    return Compat.OK if expected.kind is actual.kind else Compat.MISMATCH
