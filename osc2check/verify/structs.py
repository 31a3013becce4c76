"""Structured values: the scalar fields of a struct-typed scenario parameter as solver variables.

A ``position_3d``, ``orientation_3d``, ``pose_3d``, a velocity or an acceleration
(any struct, in fact) has no value of its own: its value is the values of its
scalar fields, reached through struct members that are not lists
(``p.position.x``, ``p.orientation.yaw``). Every such leaf of a scenario's
struct parameter is a variable of the constraint problem, whether or not a
constraint mentions it, so that

* ``keep(it.x == 30m)``, ``keep(p.position.y in [1m..2m])`` are verified like any
  scalar constraint (not dropped as "not encodable"), and
* the witness gives every leaf a value, from which the runner builds the struct
  (``osc2runner.instance.values``): the witness stays the only source of values.

Members that are lists (``path.points``) and members typed by an actor are not
leaves: their values come from expressions evaluated at run time
(``map.create_path(...)``). Nesting is followed to :data:`MAX_STRUCT_DEPTH`.
"""

from __future__ import annotations

from osc2check.semantics import types as T
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind

__all__ = ["MAX_STRUCT_DEPTH", "is_scalar", "is_struct", "struct_leaves"]

#: struct members inside struct members followed at most this deep
MAX_STRUCT_DEPTH = 4

_SCALARS = (
    T.Kind.PHYSICAL,
    T.Kind.FLOAT,
    T.Kind.INT,
    T.Kind.UINT,
    T.Kind.BOOL,
    T.Kind.ENUM,
    T.Kind.STRING,
)


def is_scalar(t: T.Type | None) -> bool:
    """Whether ``t`` is a number, boolean, enum or string type: one solver variable."""
    return t is not None and t.kind in _SCALARS


def is_struct(t: T.Type | None) -> bool:
    """Whether ``t`` is a struct type (not an actor, not a list)."""
    return (
        t is not None
        and t.kind is T.Kind.COMPOUND
        and t.symbol is not None
        and t.symbol.kind is SymbolKind.STRUCT
    )


def struct_leaves(model: Model, struct: Symbol, depth: int = 0) -> list[tuple[str, Symbol]]:
    """The scalar fields of ``struct``, as (dotted path below it, field symbol), in order."""
    leaves: list[tuple[str, Symbol]] = []
    for member in model.parameters(struct):
        t = member.type
        if t is None:
            continue
        if is_scalar(t):
            leaves.append((member.name, member))
        elif is_struct(t) and depth < MAX_STRUCT_DEPTH and t.symbol is not struct:
            assert t.symbol is not None
            for sub, sym in struct_leaves(model, t.symbol, depth + 1):
                leaves.append((f"{member.name}.{sub}", sym))
    return leaves
