"""The MethodRegistry: OSC2 actions, modifiers and methods -> their runner implementations.

Implementations register themselves with decorators::

    @registry.action("vehicle", "change_speed")
    class ChangeSpeed(ActionBehaviour): ...

    @registry.modifier("speed")
    class Speed(Modifier): ...

    @registry.method("physical_object", "object_distance")
    def object_distance(ctx, subject, reference, direction, mode): ...

An action is registered for an actor type; an invocation on an actor finds
the registration of the actor's type or of its nearest supertype (a
``vehicle.change_speed`` entry serves every vehicle; a
``movable_object.change_speed`` entry would also serve persons). Modifiers
are registered by name; methods by their declaring type and name.

Anything the compiler cannot find here is an error before the run starts,
with the invocation's location: nothing is silently skipped.
``docs/coverage.md`` is generated from this table (:mod:`osc2runner.coverage`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any, TypeVar

from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol

__all__ = ["Entry", "MethodRegistry", "registry"]

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
        self._actions: dict[tuple[str, str], Entry] = {}
        self._modifiers: dict[tuple[str | None, str], Entry] = {}
        self._methods: dict[tuple[str, str], Entry] = {}

    # ---- registration

    def action(self, actor: str, name: str, *, note: str = "") -> Callable[[_T], _T]:
        """Register the decorated behaviour class for ``actor.name`` invocations."""

        def register(cls: _T) -> _T:
            self._add(self._actions, (actor, name), Entry("action", actor, name, cls, note))
            return cls

        return register

    def modifier(
        self, name: str, *, actor: str | None = None, note: str = ""
    ) -> Callable[[_T], _T]:
        """Register the decorated modifier class for ``name(...)``.

        Movement modifiers (``speed``, ``lane``, ...) have no actor; an
        actor-associated modifier such as ``map.set_map_file`` names its actor.
        """

        def register(cls: _T) -> _T:
            self._add(self._modifiers, (actor, name), Entry("modifier", actor, name, cls, note))
            return cls

        return register

    def method(self, owner: str, name: str, *, note: str = "") -> Callable[[_T], _T]:
        """Register the decorated function ``fn(ctx, subject, *args)`` for ``owner.name()``."""

        def register(fn: _T) -> _T:
            self._add(self._methods, (owner, name), Entry("method", owner, name, fn, note))
            return fn

        return register

    @staticmethod
    def _add(table: dict, key: object, entry: Entry) -> None:
        if key in table:
            raise ValueError(f"{entry.kind} `{entry.label}` is registered twice")
        table[key] = entry

    # ---- lookup

    def find_action(self, model: Model, actor_type: Symbol | None, action: Symbol) -> Entry | None:
        """The entry for invoking ``action`` on an actor of type ``actor_type``."""
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


registry = MethodRegistry()
"""The runner's registry; ``osc2runner.behaviours`` fills it on import."""
