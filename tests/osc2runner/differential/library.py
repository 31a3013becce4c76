"""The library's own signatures, read from the checker's model of the bundled library.

Nothing here lists an action, a modifier or a parameter by hand: the actor types are
the library's actors that the world catalogue builds (``placement.actor_kind``), their
actions are the library's actions of those types (base actions left out, as
docs/coverage.md leaves them out), the modifiers of an action are those the model
associates with it, and every parameter comes with its type, its default, the members
of its enum and the units of its physical type. The checker's own tables of arguments
that exclude or need each other, and of parameters that the standard's examples use
beyond the library (``calls.EXCLUSIVE``, ``REQUIRES``, ``SPEC_EXAMPLE_PARAMETERS``),
are read too, so that the generator writes mostly calls the checker accepts.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from functools import cache

from osc2check.semantics import types as T
from osc2check.semantics.calls import EXCLUSIVE, REQUIRES, SPEC_EXAMPLE_PARAMETERS
from osc2check.semantics.model import Model
from osc2check.semantics.stdlib import standard_library
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.verify.placement import actor_kind

__all__ = [
    "Library",
    "Parameter",
    "Signature",
    "Unit",
    "library",
]


@dataclass(frozen=True)
class Unit:
    name: str
    factor: Fraction  # SI value of one unit
    offset: Fraction


@dataclass(frozen=True)
class Parameter:
    """One parameter of a library action or modifier, as plain data."""

    name: str
    type_name: str  # the declared type's name (``speed``, ``side_left_right``, ``uint``)
    kind: str  # T.Kind's value: physical, enum, bool, int, uint, float, string, compound, list
    default: bool  # it has a default
    members: tuple[str, ...] = ()  # an enum's members
    units: tuple[Unit, ...] = ()  # a physical type's units
    actor: bool = False  # a compound of an actor type (a reference to another actor)
    fields: tuple[Parameter, ...] = ()  # a struct's parameters (its leaves are generated)
    #: not declared by the library: a parameter the standard's examples use (D807)
    example_only: bool = False

    @property
    def si_unit(self) -> Unit | None:
        """The unit of factor 1 and offset 0 (``mps``, ``m``, ``rad``)."""
        for unit in self.units:
            if unit.factor == 1 and unit.offset == 0:
                return unit
        return None


@dataclass(frozen=True)
class Signature:
    """A library action or modifier: its name, owner and parameters in declaration order."""

    kind: str  # action | modifier
    name: str
    owner: str  # an action's actor type; a modifier's associated actor or behaviour
    parameters: tuple[Parameter, ...]
    exclusive: tuple[frozenset[str], ...] = ()
    requires: tuple[tuple[str, str], ...] = ()  # (argument, the argument it needs)

    @property
    def label(self) -> str:
        return f"{self.owner}.{self.name}"

    def parameter(self, name: str) -> Parameter | None:
        for p in self.parameters:
            if p.name == name:
                return p
        return None


@dataclass(frozen=True)
class Library:
    """What the generator reads of the bundled library."""

    #: actor types the world builds, by name: their catalogue kind
    actor_kinds: dict[str, str]
    #: the actions each actor type takes (inherited ones included), by actor type; every
    #: library actor type that takes an action or a modifier
    actions: dict[str, tuple[Signature, ...]]
    #: the modifiers of each action (by the action's label)
    modifiers: dict[str, tuple[Signature, ...]]
    #: the modifiers associated with an actor type, applied as scenario members
    member_modifiers: dict[str, tuple[Signature, ...]]
    #: every library action and modifier by label (what the generator must cover)
    everything: dict[str, Signature]


def _library_symbol(sym: Symbol) -> bool:
    return sym.library or sym.toolkit


def _is_base_action(model: Model, sym: Symbol) -> bool:
    """An action other actions inherit (``action_for_vehicle``): not invoked itself."""
    return any(c.kind is SymbolKind.ACTION for c in model.children.get(sym, ()))


def _units(model: Model, physical: Symbol) -> tuple[Unit, ...]:
    found = [
        Unit(u.name, u.factor, u.offset)
        for u in model.all_units().values()
        if u.dimension == physical.dimension and u.owner is physical
    ]
    if not found:  # units declared for the dimension, whichever type names it
        found = [
            Unit(u.name, u.factor, u.offset)
            for u in model.all_units().values()
            if u.dimension == physical.dimension
        ]
    return tuple(sorted(found, key=lambda u: u.name))


def _parameter(model: Model, sym: Symbol, depth: int = 0) -> Parameter:
    t = sym.type
    kind = t.kind.value if t is not None else "unknown"
    type_name = str(t) if t is not None else "?"
    members: tuple[str, ...] = ()
    units: tuple[Unit, ...] = ()
    fields: tuple[Parameter, ...] = ()
    actor = False
    target = t.symbol if t is not None and t.kind is not T.Kind.LIST else None
    if t is not None and t.kind is T.Kind.ENUM and target is not None:
        members = tuple(m.name for m in model.enum_values(target))
    elif t is not None and t.kind is T.Kind.PHYSICAL and target is not None:
        units = _units(model, target)
    elif t is not None and t.kind is T.Kind.COMPOUND and target is not None:
        actor = target.kind is SymbolKind.ACTOR
        if target.kind is SymbolKind.STRUCT and depth < 3:
            fields = tuple(_parameter(model, f, depth + 1) for f in model.parameters(target))
    return Parameter(
        sym.name,
        type_name,
        kind,
        sym.has_default or sym.default is not None,
        members,
        units,
        actor,
        fields,
    )


def _signature(model: Model, sym: Symbol, kind: str, owner: str) -> Signature:
    params = [_parameter(model, p) for p in model.parameters(sym)]
    extra = SPEC_EXAMPLE_PARAMETERS.get(sym.name, set())
    if extra:
        like = next((p for p in params if p.actor), None)
        for name in sorted(extra):
            if like is not None and all(p.name != name for p in params):
                params.append(
                    Parameter(name, like.type_name, like.kind, False, actor=True, example_only=True)
                )
    return Signature(
        kind,
        sym.name,
        owner,
        tuple(params),
        tuple(EXCLUSIVE.get(sym.name, ())),
        tuple((arg, needed) for (name, arg), needed in REQUIRES.items() if name == sym.name),
    )


@cache
def library() -> Library:
    """The bundled library's signatures (once per process)."""
    model = standard_library().model
    actor_kinds: dict[str, str] = {}
    actions: dict[str, tuple[Signature, ...]] = {}
    modifiers: dict[str, tuple[Signature, ...]] = {}
    member_modifiers: dict[str, tuple[Signature, ...]] = {}
    everything: dict[str, Signature] = {}
    for sym in model.symbols:
        if sym.kind is SymbolKind.ACTOR and _library_symbol(sym):
            kind = actor_kind(model, sym)
            if kind is not None:
                actor_kinds[sym.name] = kind
    for sym in model.symbols:
        if not _library_symbol(sym):
            continue
        if sym.kind is SymbolKind.ACTION and not _is_base_action(model, sym):
            owner = sym.actor.name if sym.actor is not None else ""
            everything[f"{owner}.{sym.name}"] = _signature(model, sym, "action", owner)
        elif sym.kind is SymbolKind.MODIFIER:
            owner = (sym.actor or sym.of).name if (sym.actor or sym.of) is not None else ""
            everything[f"{owner}.{sym.name}"] = _signature(model, sym, "modifier", owner)
    actor_syms = {s.name: s for s in model.symbols if s.kind is SymbolKind.ACTOR and s.library}
    for name, actor in actor_syms.items():
        found = [
            s
            for s in model.behaviours_of(actor)
            if s.kind is SymbolKind.ACTION and _library_symbol(s) and not _is_base_action(model, s)
        ]
        if not found and not model.modifiers_of(actor):
            continue
        actions[name] = tuple(
            everything[f"{s.actor.name if s.actor else ''}.{s.name}"] for s in found
        )
        for s in found:
            label = f"{s.actor.name if s.actor else ''}.{s.name}"
            if label not in modifiers:
                modifiers[label] = tuple(
                    everything[f"{(m.actor or m.of).name}.{m.name}"]
                    for m in model.modifiers_of(s)
                    if _library_symbol(m) and (m.actor or m.of) is not None
                )
        member_modifiers[name] = tuple(
            everything[f"{m.actor.name}.{m.name}"]
            for m in model.modifiers_of(actor)
            if _library_symbol(m) and m.actor is not None
        )
    return Library(actor_kinds, actions, modifiers, member_modifiers, everything)
