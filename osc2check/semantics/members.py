"""The member lists of every declared type: its declaration's body and each ``extend`` of it.

A scenario, actor or struct is written once and may be extended (``extend
cut_in: ...``) in the same file or another; what it is, is all of those member
lists together, the declaration's first. Lowering (the solver's view) and the
runner's compiler both read it from here.
"""

from __future__ import annotations

from osc2check.semantics import types as T
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast

__all__ = [
    "actor_alias",
    "declaration_bodies",
    "do_labels",
    "last_do",
    "scenario_do",
    "scenario_members",
]

MemberList = tuple[ast.Member, ...]


def declaration_bodies(model: Model) -> dict[Symbol, list[MemberList]]:
    """Each type's member lists (the library's types too): its declaration's body first,
    then every ``extend`` of it in declaration order."""
    result: dict[Symbol, list[MemberList]] = {}
    chain: list[Model] = []
    current: Model | None = model
    while current is not None:
        chain.append(current)
        current = current.base
    for m in reversed(chain):
        for node, sym in m.declarations.items():
            if isinstance(node, ast.StructuredDecl) and m.declarations.get(node) is sym:
                result.setdefault(sym, []).insert(0, node.members)
            elif isinstance(node, ast.ExtendDecl):
                result.setdefault(sym, []).append(node.members)
    return result


def scenario_members(
    model: Model, bodies: dict[Symbol, list[MemberList]], scenario: Symbol
) -> list[ast.Member]:
    """The members ``scenario`` runs with, as the runner compiles them: its ancestors'
    first, each type's declaration then its ``extend``s."""
    return [
        member
        for sym in reversed(list(model.ancestors(scenario)))
        for members in bodies.get(sym, ())
        for member in members
    ]


def scenario_do(
    model: Model, bodies: dict[Symbol, list[MemberList]], scenario: Symbol
) -> ast.DoDirective | None:
    """The ``do`` that ``scenario`` runs: the last one written in its ancestors' member
    lists and its own, in that order (a subtype's or an extension's replaces an earlier
    one, as the runner compiles it); None when it has none."""
    return last_do(scenario_members(model, bodies, scenario))


def last_do(members: list[ast.Member]) -> ast.DoDirective | None:
    """The last ``do`` of ``members`` (see ``scenario_do``)."""
    found = None
    for member in members:
        if isinstance(member, ast.DoDirective):
            found = member
    return found


def _actor_field(sym: Symbol | None) -> bool:
    t = sym.type if sym is not None else None
    return (
        sym is not None
        and sym.kind is SymbolKind.FIELD
        and t is not None
        and t.kind is T.Kind.COMPOUND
        and t.symbol is not None
        and t.symbol.kind is SymbolKind.ACTOR
    )


def actor_alias(model: Model, field: Symbol) -> Symbol | None:
    """The actor field that the actor field ``field`` names (``other: vehicle = npc``): the
    same actor, not a new one; None when ``field`` is no such alias. Chains are followed
    (``a = b``, ``b = npc``: ``npc``); a cycle is no alias. Placement, the witness and the
    runner read aliases here."""
    seen: set[int] = set()
    target: Symbol | None = None
    current = field
    while _actor_field(current) and isinstance(current.default, ast.NameRef):
        if id(current) in seen:
            return None
        seen.add(id(current))
        named = model.reference(current.default.name.name)
        if not _actor_field(named) or named is None:
            break
        target = current = named
    return target


def do_labels(do: ast.DoDirective | None) -> frozenset[str]:
    """The labels of the members of a ``do`` tree."""
    if do is None:
        return frozenset()
    found: set[str] = set()
    stack = [do.member]
    while stack:
        member = stack.pop()
        if member.label is not None and not member.label.missing:
            found.add(member.label.text)
        if isinstance(member.body, ast.Composition):
            stack.extend(member.body.members)
    return frozenset(found)
