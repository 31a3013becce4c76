"""Lexical scopes for the resolution pass: what `it`, `actor` and local names mean."""

from __future__ import annotations

from dataclasses import dataclass, field

from osc2check.semantics.model import Context
from osc2check.semantics.symbols import Symbol
from osc2check.semantics.types import Type


@dataclass
class Scope:
    context: Context
    owner: Symbol | None = None  # the type whose members are visible unqualified
    it: Type | None = None  # the type of `it`, when it means something here
    actor: Symbol | None = None  # the associated actor (`actor`)
    behavior: Symbol | None = None  # the invoked behaviour of a `with:` block
    locals: dict[str, Symbol] = field(default_factory=dict)
    parent: Scope | None = None
    in_argument: bool = False  # inside an invocation's arguments (dialect D805)

    def child(self, **changes) -> Scope:
        values = dict(
            context=self.context,
            owner=self.owner,
            it=self.it,
            actor=self.actor,
            behavior=self.behavior,
            parent=self,
        )
        values.update(changes)
        return Scope(**values)

    def local(self, name: str) -> Symbol | None:
        scope: Scope | None = self
        while scope is not None:
            if name in scope.locals:
                return scope.locals[name]
            scope = scope.parent
        return None
