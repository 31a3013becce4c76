"""The MethodRegistry: OSC2 actions, modifiers and methods -> their runner implementations.

Implementations are marked with decorators where they are written::

    @action("vehicle", "change_speed")
    class ChangeSpeed(ActionBehaviour): ...

    @modifier("speed")
    class Speed(Modifier): ...

    @method("physical_object", "object_distance")
    def object_distance(ctx, subject, reference, direction, mode): ...

Marking changes nothing global: :func:`load_registry` builds a registry from the
modules it is given (by default :data:`BEHAVIOUR_MODULES`), so a test can build
one of its own and importing a module never registers anything.

An action is registered for an actor type; an invocation on an actor finds
the registration of the actor's type or of its nearest supertype (a
``vehicle.change_speed`` entry serves every vehicle; a
``movable_object.change_speed`` entry would also serve persons). Modifiers
are registered by name; methods by their declaring type and name.

Anything the compiler cannot find here is an error before the run starts,
with the invocation's location: nothing is silently skipped.
``docs/coverage.md`` is generated from this table (:mod:`osc2runner.output.support`).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from types import ModuleType
from typing import Any, TypeVar

from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol

__all__ = [
    "BEHAVIOUR_MODULES",
    "Entry",
    "MethodRegistry",
    "action",
    "load_registry",
    "method",
    "modifier",
    "standard_registry",
]

#: The modules whose marked implementations make the runner's registry.
BEHAVIOUR_MODULES = (
    "osc2runner.behaviours.motion",
    "osc2runner.behaviours.modifiers",
    "osc2runner.behaviours.placement",
    "osc2runner.behaviours.paths",
    "osc2runner.behaviours.road_paths",
    "osc2runner.behaviours.environment",
    "osc2runner.behaviours.lights",
    "osc2runner.behaviours.traffic",
    "osc2runner.behaviours.towing",
    "osc2runner.behaviours.methods",
    "osc2runner.behaviours.maps",
    "osc2runner.behaviours.carla",
)
_MARK = "__osc2_entries__"

_T = TypeVar("_T")


@dataclass(frozen=True, slots=True)
class Entry:
    """One registration: what it implements and the implementing class or function."""

    kind: str  # "action" | "modifier" | "method"
    owner: str | None  # actor type of an action, declaring type of a method; None for modifiers
    name: str
    target: Any
    note: str = ""

    @property
    def label(self) -> str:
        return f"{self.owner}.{self.name}" if self.owner else self.name


class MethodRegistry:
    """Actions by (actor type, name), modifiers by name, methods by (type, name)."""

    def __init__(self) -> None:
        self._actions: dict[tuple[str | None, str], Entry] = {}
        self._modifiers: dict[tuple[str | None, str], Entry] = {}
        self._methods: dict[tuple[str, str], Entry] = {}

    # ---- registration

    def add(self, entry: Entry) -> None:
        """Register one implementation (an error when its key is registered already)."""
        table: dict[Any, Entry]
        if entry.kind == "action":
            table, key = self._actions, (entry.owner, entry.name)
        elif entry.kind == "modifier":
            table, key = self._modifiers, (entry.owner, entry.name)
        else:
            table, key = self._methods, (entry.owner, entry.name)
        self._add(table, key, entry)

    def collect(self, module: ModuleType) -> None:
        """Register every implementation marked in ``module`` (in definition order)."""
        for value in vars(module).values():
            if getattr(value, "__module__", None) != module.__name__:
                continue  # imported from elsewhere: registered with its own module
            for entry in getattr(value, _MARK, ()):
                if entry.target is value:
                    self.add(entry)

    @staticmethod
    def _add(table: dict[Any, Any], key: object, entry: Entry) -> None:
        if key in table:
            raise ValueError(f"{entry.kind} `{entry.label}` is registered twice")
        table[key] = entry

    # ---- lookup

    def find_action(self, model: Model, actor_type: Symbol | None, action: Symbol) -> Entry | None:
        """The entry for invoking ``action`` on an actor of type ``actor_type`` (of an action
        declared without an actor: its registration without one)."""
        if action.actor is None and actor_type is None:
            return self._actions.get((None, action.name))
        chains = []
        if actor_type is not None:
            chains.append(model.ancestors(actor_type))
        if action.actor is not None:
            chains.append(model.ancestors(action.actor))
        for chain in chains:
            for sym in chain:
                entry = self._actions.get((sym.name, action.name))
                if entry is not None:
                    return entry
        return None

    def find_modifier(self, model: Model, modifier: Symbol) -> Entry | None:
        """The entry of a modifier: by its associated actor (or its supertypes) and name."""
        if modifier.actor is None:
            return self._modifiers.get((None, modifier.name))
        for sym in model.ancestors(modifier.actor):
            entry = self._modifiers.get((sym.name, modifier.name))
            if entry is not None:
                return entry
        return None

    def find_method(self, model: Model, method: Symbol) -> Entry | None:
        owner = method.owner
        for sym in model.ancestors(owner) if owner is not None else []:
            entry = self._methods.get((sym.name, method.name))
            if entry is not None:
                return entry
        return None

    def action_entry(self, actor: str, name: str) -> Entry | None:
        return self._actions.get((actor, name))

    def modifier_entry(self, name: str, actor: str | None = None) -> Entry | None:
        return self._modifiers.get((actor, name))

    # ---- listing

    def actions(self) -> Iterator[Entry]:
        return iter(self._actions.values())

    def modifiers(self) -> Iterator[Entry]:
        return iter(self._modifiers.values())

    def methods(self) -> Iterator[Entry]:
        return iter(self._methods.values())


def _mark(entry_of: Callable[[Any], Entry]) -> Callable[[_T], _T]:
    def mark(target: _T) -> _T:
        entries = list(getattr(target, _MARK, ()))
        entries = [e for e in entries if e.target is target]  # not a base class's marks
        entries.append(entry_of(target))
        setattr(target, _MARK, tuple(entries))
        return target

    return mark


def action(actor: str, name: str, *, note: str = "") -> Callable[[_T], _T]:
    """Mark the decorated behaviour class as the implementation of ``actor.name()``."""
    return _mark(lambda cls: Entry("action", actor, name, cls, note))


def modifier(name: str, *, actor: str | None = None, note: str = "") -> Callable[[_T], _T]:
    """Mark the decorated modifier class as the implementation of ``name(...)``.

    Movement modifiers (``speed``, ``lane``, ...) have no actor; an
    actor-associated modifier such as ``map.set_map_file`` names its actor.
    """
    return _mark(lambda cls: Entry("modifier", actor, name, cls, note))


def method(owner: str, name: str, *, note: str = "") -> Callable[[_T], _T]:
    """Mark the decorated function ``fn(ctx, subject, *args)`` as ``owner.name()``."""
    return _mark(lambda fn: Entry("method", owner, name, fn, note))


def load_registry(modules: Iterable[str] = BEHAVIOUR_MODULES) -> MethodRegistry:
    """A registry of the implementations marked in ``modules`` (imported by name)."""
    registry = MethodRegistry()
    for name in modules:
        registry.collect(importlib.import_module(name))
    return registry


_standard: MethodRegistry | None = None


def standard_registry() -> MethodRegistry:
    """The runner's registry (:data:`BEHAVIOUR_MODULES`), loaded once."""
    global _standard
    if _standard is None:
        _standard = load_registry()
    return _standard
