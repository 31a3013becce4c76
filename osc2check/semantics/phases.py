"""Phases: when behaviour happens, for the checker's placement and the runner's compiler.

* **Instant actions** set a state and take no time (``assign_position``,
  ``assign_speed``, the weather and light actions, ...), unless given a
  ``duration``.
* **Time 0**: an invocation begins at time 0 when it is the first member of the
  scenario's ``do`` (after instant members and ``emit``/``call``), any member of
  a ``parallel`` that begins at time 0, or the first member of a ``serial`` that
  does. The members of a ``one_of`` are alternatives: none of them is known to
  run at time 0 (:attr:`TimeZero.alternatives` lists them).
* **Modifier timing** (§8.9, the ``at`` argument of movement modifiers):
  ``start`` constrains the start of the phase only, ``end`` its end (reached
  when the phase ends), ``all`` (the default) the whole phase.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from osc2check.syntax import ast

__all__ = [
    "INSTANT_ACTIONS",
    "MODIFIER_TIMINGS",
    "TimeZero",
    "is_instant",
    "modifier_timing",
    "time_zero",
]

INSTANT_ACTIONS = frozenset(
    {
        "assign_position", "assign_speed", "assign_orientation", "assign_acceleration",
        "set_lights", "set_road_friction",
        "air", "rain", "snow", "wind", "fog", "clouds", "assign_celestial_position",
        "set_bulb_state", "set_state", "set_semantic_state", "set_group_bulb_state",
        "set_group_state", "set_group_semantic_state",
    }
)  # fmt: skip
MODIFIER_TIMINGS = ("start", "end", "all")


def _has_duration(arguments: tuple[ast.Argument, ...]) -> bool:
    return any(isinstance(a, ast.NamedArgument) and a.name.text == "duration" for a in arguments)


def is_instant(inv: ast.Invocation) -> bool:
    """Whether the invocation takes no time: an instant action without a ``duration``."""
    return inv.name.text in INSTANT_ACTIONS and not _has_duration(inv.arguments)


def modifier_timing(arguments: Mapping[str, ast.Node]) -> str:
    """``start``, ``end`` or ``all``: when a modifier with these bound arguments applies."""
    node = arguments.get("at")
    match node:
        case ast.NameRef():
            word = node.name.name.text
        case ast.EnumRef():
            word = node.member.text
        case _:
            return "all"
    return word if word in MODIFIER_TIMINGS else "all"


@dataclass
class TimeZero:
    """The invocations of a ``do`` tree that begin at time 0, in source order."""

    starts: list[ast.Invocation] = field(default_factory=list)
    alternatives: list[ast.Invocation] = field(default_factory=list)  # inside a one_of


def time_zero(body: ast.Node) -> TimeZero:
    """What of ``body`` (a ``do`` member's body) begins at time 0 (see the module docs)."""
    found = TimeZero()
    _collect(body, found.starts, found)
    return found


def _collect(body: ast.Node, starts: list[ast.Invocation], found: TimeZero) -> bool:
    """Add the time-0 invocations of ``body``; True when ``body`` takes no time."""
    match body:
        case ast.Composition(op="serial"):
            for member in body.members:
                if not _collect(member.body, starts, found):
                    return False
            return not _has_duration(body.arguments)
        case ast.Composition(op="one_of"):
            for member in body.members:
                _collect(member.body, found.alternatives, found)
            return False
        case ast.Composition():
            instant = True
            for member in body.members:
                instant = _collect(member.body, starts, found) and instant
            return instant and not _has_duration(body.arguments)
        case ast.Invocation():
            starts.append(body)
            return is_instant(body)
        case ast.Emit() | ast.CallDirective():
            return True
    return False
