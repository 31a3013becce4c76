"""Lexical scopes: what `it`, `actor` and local names mean at a point.

The resolution pass (``bodies.py``) builds them as it walks declarations;
``visibility.scope_at`` rebuilds the one at a position (for the language
server), from the same rule for a declaration's own body (``declaration_scope``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TypedDict, Unpack

from osc2check.semantics.model import Context
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.semantics.types import Type


class ScopeChanges(TypedDict, total=False):
    """What a child scope may set differently from its parent."""

    owner: Symbol | None
    it: Type | None
    actor: Symbol | None
    behaviour: Symbol | None
    locals: dict[str, Symbol]
    in_argument: bool
    modifier_block: bool


@dataclass
class Scope:
    context: Context
    owner: Symbol | None = None  # the type whose members are visible unqualified
    it: Type | None = None  # the type of `it`, when it means something here
    actor: Symbol | None = None  # the associated actor (`actor`)
    behaviour: Symbol | None = None  # the invoked behaviour of a `with:` block
    locals: dict[str, Symbol] = field(default_factory=dict)
    parent: Scope | None = None
    in_argument: bool = False  # inside an invocation's arguments (dialect D805)
    modifier_block: bool = False  # inside the `with:` block of an invocation or composition

    def child(self, **changes: Unpack[ScopeChanges]) -> Scope:
        values: ScopeChanges = dict(
            owner=self.owner,
            it=self.it,
            actor=self.actor,
            behaviour=self.behaviour,
        )
        values.update(changes)
        return Scope(self.context, parent=self, **values)

    def local(self, name: str) -> Symbol | None:
        scope: Scope | None = self
        while scope is not None:
            if name in scope.locals:
                return scope.locals[name]
            scope = scope.parent
        return None


BEHAVIOUR_KINDS = frozenset({SymbolKind.SCENARIO, SymbolKind.ACTION, SymbolKind.MODIFIER})


def declaration_scope(sym: Symbol, ctx: Context) -> Scope:
    """The scope of a declaration's own body: its members unqualified, `it` the instance
    being declared (a modifier's: the behaviour it modifies), `actor` a behaviour's actor."""
    it = sym.type
    if sym.kind is SymbolKind.MODIFIER:
        it = sym.of.type if sym.of is not None else None
    actor = sym.actor if sym.kind in BEHAVIOUR_KINDS else None
    return Scope(ctx, owner=sym, it=it, actor=actor)
