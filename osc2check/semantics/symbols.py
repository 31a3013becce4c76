"""Symbols: what a declared name stands for.

A ``Symbol`` is plain data about one declaration. Which names a type has as
members, which behaviours an actor has and which units exist are kept in the
``Model`` (``model.py``), not on the symbol, so that a program can extend
standard-library types without touching the cached library.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from fractions import Fraction
from typing import TYPE_CHECKING, TypedDict

from osc2check.semantics.types import Dimension, Type
from osc2check.source import Span
from osc2check.syntax import ast

if TYPE_CHECKING:
    from osc2check.semantics.model import Context


# Names the language gives in a scope (the subject of a `with:` block, the actor of a
# behaviour): a declaration of either would be read as the implicit one.
IMPLICIT_NAMES = ("it", "actor")


class SymbolKind(Enum):
    PRIMITIVE = "primitive type"
    PHYSICAL_TYPE = "physical type"
    UNIT = "unit"
    ENUM = "enum"
    ENUM_MEMBER = "enum member"
    STRUCT = "struct"
    ACTOR = "actor"
    SCENARIO = "scenario"
    ACTION = "action"
    MODIFIER = "modifier"
    FIELD = "parameter"  # a field that is a parameter (not `var`)
    VARIABLE = "variable"
    EVENT = "event"
    METHOD = "method"
    ARGUMENT = "argument"  # a parameter of a method or event
    GLOBAL = "global parameter"
    LABEL = "label"
    IMPLICIT = "implicit name"  # `it`, `actor`, event `as` bindings

    @property
    def is_type(self) -> bool:
        return self in TYPE_KINDS

    @property
    def is_behaviour(self) -> bool:
        return self in (SymbolKind.SCENARIO, SymbolKind.ACTION)


TYPE_KINDS = frozenset(
    {
        SymbolKind.PRIMITIVE,
        SymbolKind.PHYSICAL_TYPE,
        SymbolKind.ENUM,
        SymbolKind.STRUCT,
        SymbolKind.ACTOR,
        SymbolKind.SCENARIO,
        SymbolKind.ACTION,
    }
)
COMPOUND_KINDS = frozenset(
    {
        SymbolKind.STRUCT,
        SymbolKind.ACTOR,
        SymbolKind.SCENARIO,
        SymbolKind.ACTION,
        SymbolKind.MODIFIER,
    }
)


class SymbolExtra(TypedDict, total=False):
    """What only some symbols carry."""

    alias: ast.NameRef | ast.EnumRef  # an enum member whose value names another member
    implicit: bool  # an event that is emitted without a declaration
    event: Symbol | None  # an `@e as x` binding: the event it binds


@dataclass(eq=False)
class Symbol:
    kind: SymbolKind
    name: str
    namespace: str = ""  # "" is the null namespace
    uri: str = ""
    decl: ast.Node | None = None
    name_span: Span | None = None
    type: Type | None = None  # the value type of a field, argument or method result
    owner: Symbol | None = None  # the type, behaviour, method or enum a member belongs to
    parent: Symbol | None = None  # inheritance
    condition: ast.Expr | None = None  # conditional inheritance
    actor: Symbol | None = None  # associated actor of a scenario, action or modifier
    of: Symbol | None = None  # the behaviour a scenario-associated modifier belongs to
    dimension: Dimension | None = None  # physical types and units
    factor: Fraction = Fraction(1)
    offset: Fraction = Fraction(0)
    value: int = 0  # enum members
    default: ast.Expr | None = None
    has_default: bool = False
    parameters: tuple[Symbol, ...] = ()  # methods and events
    library: bool = False  # declared in the bundled library
    toolkit: bool = False  # declared in the toolkit's own extension library
    doc: str | None = None
    context: Context | None = None  # the lookup context of the declaration
    extra: SymbolExtra = field(default_factory=SymbolExtra)

    @property
    def qualified_name(self) -> str:
        prefix = f"{self.namespace}::" if self.namespace else ""
        if self.actor is not None and self.kind in (
            SymbolKind.SCENARIO,
            SymbolKind.ACTION,
            SymbolKind.MODIFIER,
        ):
            return f"{self.actor.name}.{self.name}"
        return prefix + self.name

    def __repr__(self) -> str:
        return f"<{self.kind.value} {self.qualified_name}>"


@dataclass(eq=False)
class Namespace:
    name: str
    symbols: dict[str, list[Symbol]] = field(default_factory=dict)
    exports_all: bool = False
    exports: set[str] = field(default_factory=set)
    reexports: list[tuple[str, str | None]] = field(default_factory=list)  # (ns, name|None=all)

    def add(self, symbol: Symbol) -> list[Symbol]:
        """Add a symbol; returns the symbols of that name declared before it."""
        existing = self.symbols.setdefault(symbol.name, [])
        before = list(existing)
        existing.append(symbol)
        return before
