"""Parameter values of one scenario instance: the checker's witness, and nothing else.

The checker's solver draws a witness for the seed (``osc2check.solve``): an exact
value for every parameter that a constraint, a default or an argument decides,
and every actor's category, size and start. The runner executes exactly that.
:class:`ScenarioValues` reads it as exact values of
``osc2check.semantics.constants`` (a speed is a ``Quantity`` in SI units);
``constants.to_runtime`` turns them into the floats the simulation runs with.

A field of type road, route, lane or junction stands for the map element the
witness chose (``osc2check.verify.map_modifiers.ElementValue``: kind, road,
direction, lane, junction), which the runner's map methods and `along` take.

``var`` fields are not parameters: their initialisers are evaluated when the
run starts (constant ones exactly, here; the others by the compiler, over the
live state).
"""

from __future__ import annotations

from fractions import Fraction

from osc2check.semantics import types as T
from osc2check.semantics.constants import (
    EnumValue,
    NotConstant,
    Quantity,
    Value,
    to_json,
    to_runtime,
)
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.verify.ir import ListItem
from osc2check.verify.structs import MAX_STRUCT_DEPTH, is_struct, struct_leaves
from osc2check.verify.witness import Witness
from osc2runner.structs import StructValue, struct_json

__all__ = ["ScenarioValues", "scenario_fields", "struct_json"]


def scenario_fields(model: Model, scenario: Symbol) -> list[Symbol]:
    """The fields (parameters and variables, not events) of a scenario, inherited first."""
    return [
        m for m in model.all_members(scenario) if m.kind in (SymbolKind.FIELD, SymbolKind.VARIABLE)
    ]


def exact(value: Fraction | bool | str, type_: T.Type | None, model: Model) -> Value:
    """A witness value as the exact value of its type (a speed becomes a Quantity)."""
    if isinstance(value, bool) or type_ is None:
        return value
    if type_.kind is T.Kind.PHYSICAL and isinstance(value, Fraction):
        return Quantity(value, type_.dimension or T.DIMENSIONLESS)
    if type_.kind in (T.Kind.INT, T.Kind.UINT) and isinstance(value, Fraction):
        return int(value)
    if type_.kind is T.Kind.ENUM and isinstance(value, str):
        enum = type_.symbol
        members = model.enum_values(enum) if enum is not None else []
        number = next((m.value for m in members if m.name == value), 0)
        return EnumValue(enum.name if enum is not None else "", value, number)
    return value


class ScenarioValues:
    """The witness's values of one scenario instance (see the module docstring)."""

    def __init__(self, model: Model, scenario: Symbol, witness: Witness) -> None:
        self.model = model
        self.scenario = scenario
        self.witness = witness
        self.fields = scenario_fields(model, scenario)
        self._by_name = {p.name: p for p in witness.parameters}
        #: struct values by path, built once: a struct read twice is the same object
        self._structs: dict[str, StructValue] = {}

    def value(self, field: Symbol) -> Value:
        """The value of a scenario parameter, or of a global parameter (the witness's
        ``::name``); NotConstant when the witness has none.

        A road, route, lane or junction parameter is the map element the witness
        chose. A struct parameter (``position_3d``, ``pose_3d``, ...) is built from the
        witness's values of its scalar leaves (``p.position.x``): a
        :class:`~osc2runner.structs.StructValue` of run-time values (:meth:`struct`)."""
        path = f"::{field.name}" if field.kind is SymbolKind.GLOBAL else field.name
        element = self.witness.element(path)
        if element is not None:
            return element  # type: ignore[return-value]
        if is_struct(field.type):
            return self.struct(path, field)  # type: ignore[return-value]
        p = self._by_name.get(path)
        if p is None:
            raise NotConstant(
                f"the checker's witness gives `{field.name}` no value (the solver cannot "
                "encode its type)",
                field.decl,
            )
        return exact(p.value, field.type, self.model)

    def value_at(self, path: str, field: Symbol) -> Value:
        """The value of a parameter of an invoked scenario's instance (``hero.cut_in@12.gap``)."""
        if is_struct(field.type):
            where = f"{path}.{field.name}" if path else field.name
            return self.struct(where, field)  # type: ignore[return-value]
        p = self._by_name.get(f"{path}.{field.name}" if path else field.name)
        if p is None:
            raise NotConstant(
                f"the checker's witness gives `{field.name}` of `{path}` no value", field.decl
            )
        return exact(p.value, field.type, self.model)

    def kept(self, path: str, field: Symbol) -> Value | None:
        """The value a ``keep`` gave parameter ``field`` of the call at ``path``
        (``car.assign_speed@9`` with ``keep(it.speed == 30kph)``), or None when no
        constraint mentions it. A struct has the leaves the constraints mention; the
        others are 0 (the world is flat and the standard leaves them open)."""
        where = f"{path}.{field.name}"
        if not is_struct(field.type):
            p = self._by_name.get(where)
            if p is None or not p.constrained:
                return None
            return exact(p.value, field.type, self.model)
        struct = field.type.symbol if field.type is not None else None
        assert struct is not None
        leaves = struct_leaves(self.model, struct)
        if not any(f"{where}.{leaf}" in self._by_name for leaf, _ in leaves):
            return None
        root = StructValue(struct.name)
        for leaf, sym in leaves:
            p = self._by_name.get(f"{where}.{leaf}")
            value = to_runtime(exact(p.value, sym.type, self.model)) if p is not None else 0.0
            _put(self.model, root, struct, leaf, value)
        return root  # type: ignore[return-value]

    def struct(self, path: str, field: Symbol) -> StructValue:
        """The struct value of the parameter at ``path``: nested struct values of
        run-time values (SI floats, enum members by name), one per struct member."""
        struct = field.type.symbol if field.type is not None else None
        assert struct is not None
        return self._struct(path, struct, field, 0)

    def _struct(self, path: str, struct: Symbol, field: Symbol, depth: int) -> StructValue:
        cached = self._structs.get(path)
        if cached is not None:
            return cached
        root = StructValue(struct.name)
        for member in self.model.parameters(struct):
            t = member.type
            if t is None or t.kind is not T.Kind.LIST:
                continue
            items = self.witness.lists.get(f"{path}.{member.name}")
            if items is not None and depth < MAX_STRUCT_DEPTH:
                setattr(root, member.name, self._items(items, t.element, field, depth))
        for leaf, sym in struct_leaves(self.model, struct):
            p = self._by_name.get(f"{path}.{leaf}")
            if p is None:
                raise NotConstant(
                    f"the checker's witness gives `{path}.{leaf}` no value", field.decl
                )
            _put(self.model, root, struct, leaf, to_runtime(exact(p.value, sym.type, self.model)))
        self._structs[path] = root
        return root

    def _items(
        self, items: tuple[ListItem, ...], element: T.Type | None, field: Symbol, depth: int
    ) -> tuple[object, ...]:
        values: list[object] = []
        for kind, item in items:
            if kind == "ref" and is_struct(element):
                assert element is not None and element.symbol is not None
                values.append(self._struct(str(item), element.symbol, field, depth + 1))
            elif element is not None and element.kind is T.Kind.ENUM:
                values.append(item)
            else:
                values.append(to_runtime(exact(item, element, self.model)))
        return tuple(values)

    def constrained_si(self, name: str) -> float | None:
        """The SI value of the witness's parameter ``name`` (``env.datetime``,
        ``env.geodetic_position.latitude``) when a constraint decides it, else None."""
        p = self._by_name.get(name)
        if p is None or not p.constrained or isinstance(p.value, (bool, str)):
            return None
        return float(p.value)

    def attribute(self, actor: Symbol, member: str) -> Value | None:
        """An actor field's attribute that a constraint decides (``keep(it.model ==
        ...)``), or None: attributes nothing constrains are not chosen by the solver."""
        p = self._by_name.get(f"{actor.name}.{member}")
        if p is None or not p.constrained:
            return None
        owner = actor.type.symbol if actor.type is not None else None
        found = self.model.member(owner, member) if owner is not None else []
        return exact(p.value, found[0].type if found else None, self.model)

    def attributes(self, actor: Symbol) -> dict[str, Value]:
        """Every attribute of an actor field that a constraint decides."""
        result: dict[str, Value] = {}
        prefix = f"{actor.name}."
        for name in self._by_name:
            rest = name[len(prefix) :] if name.startswith(prefix) else ""
            if rest and "@" not in rest and "." not in rest:
                value = self.attribute(actor, rest)
                if value is not None:
                    result[rest] = value
        return result

    def table(self) -> dict[str, object]:
        """The scenario's own parameters by name (JSON-ready), for the run metadata."""
        result: dict[str, object] = {}
        for field in self.fields:
            if field.kind is not SymbolKind.FIELD:
                continue
            if is_struct(field.type):
                result[field.name] = struct_json(self.struct(field.name, field))
                continue
            if field.type is not None and field.type.kind is T.Kind.COMPOUND:
                attrs = self.attributes(field)
                if attrs:
                    result[field.name] = {k: to_json(v) for k, v in attrs.items()}
                continue
            try:
                result[field.name] = to_json(self.value(field))
            except NotConstant:
                continue
        return result

    @property
    def source(self) -> str:
        return f"witness (seed {self.witness.seed})"


def _put(model: Model, root: StructValue, struct: Symbol, leaf: str, value: object) -> None:
    """Set the leaf ``leaf`` (``position.x``) of ``root``, a value of ``struct``, making the
    struct values on the way (named after their members' types)."""
    *parents, name = leaf.split(".")
    node, owner = root, struct
    for part in parents:
        member = model.member(owner, part)
        t = member[0].type if member else None
        owner = t.symbol if t is not None and t.symbol is not None else owner
        child = node.fields.get(part)
        if not isinstance(child, StructValue):
            child = StructValue(owner.name)
            node.fields[part] = child
        node = child
    node.fields[name] = value
