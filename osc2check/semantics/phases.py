"""Phases: when behaviour happens, for the checker's placement and the runner's compiler.

* **Instant actions** set a state and take no time (``assign_position``,
  ``assign_speed``, the weather and light actions, ...), unless given a
  ``duration``.
* **Time 0**: an invocation begins at time 0 when it is the first member of the
  scenario's ``do`` (after instant members and ``emit``/``call``), any member of
  a ``parallel`` that begins at time 0, or the first member of a ``serial`` that
  does. The members of a ``one_of`` are alternatives: none of them is known to
  run at time 0 (:attr:`TimeZero.alternatives` lists them; :attr:`TimeZero.options`
  says which acting member of which ``one_of`` each belongs to, so the placement
  can place the actors for the member the run chooses).
* **Modifier timing** (§8.9, the ``at`` argument of movement modifiers):
  ``start`` constrains the start of the phase only, ``end`` its end (reached
  when the phase ends), ``all`` (the default) the whole phase.
* **Endless actions** never end on their own (``drive``, ``keep_speed``, ...):
  a ``duration``, an ``until`` or the composition around them ends them, and
  ending them then is their planned end. A modifier may still end their phase
  when it is reached (an ``at: end`` modifier, ``distance``, ``along``). Every
  other action that is not instant ends when its goal is reached.
* **Ending with the first member**: ``parallel(overlap: equal|end|final|initial|
  inside)`` ends when its first member ends (the others end no later);
  ``start``, ``any`` and ``full`` end when every member has. With ``end`` and
  ``final`` a member of known length starts so that it ends with the others
  (``STARTS_PLANNED``); with ``equal`` and ``full`` one that is shorter than the first
  member cannot keep the overlap (``NOT_BEFORE_FIRST``).
* **Acting and waiting members** of a ``one_of``: a member acts when it invokes
  an action or a scenario; one that only waits (``wait``, ``emit``, ``call``)
  runs alongside the chosen one and may end the composition.

The checker's timing model (``verify.timing``) and the runner's compiler read
these from here.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field

from osc2check.semantics.bindings import named_given
from osc2check.syntax import ast

__all__ = [
    "ENDLESS_ACTIONS",
    "acting_members",
    "ENDS_WITH_FIRST",
    "INSTANT_ACTIONS",
    "NOT_BEFORE_FIRST",
    "STARTS_PLANNED",
    "PHASE_ENDING_MODIFIERS",
    "MODIFIER_TIMINGS",
    "Guard",
    "TimeZero",
    "enum_word",
    "invocations",
    "is_acting",
    "is_instant",
    "modifier_timing",
    "time_zero",
    "after_waits",
    "leading_parallel",
    "tree_members",
]

INSTANT_ACTIONS = frozenset(
    {
        "assign_position", "assign_speed", "assign_orientation", "assign_acceleration",
        "set_lights", "set_road_friction",
        "air", "rain", "snow", "wind", "fog", "clouds", "assign_celestial_position",
        "set_bulb_state", "set_state", "set_semantic_state", "set_group_bulb_state",
        "set_group_state", "set_group_semantic_state",
        "connect_trailer", "disconnect_trailer",
    }
)  # fmt: skip
ENDLESS_ACTIONS = frozenset(
    {
        "drive", "move", "walk", "keep_speed", "remain_stationary", "follow_lane",
        "keep_acceleration", "keep_space_gap", "keep_time_gap", "keep_space_headway",
        "keep_time_headway", "play_cycles",
    }
)  # fmt: skip
#: modifiers that end an action's phase when they are reached, whatever their ``at``
#: (an ``at: end`` modifier does too)
PHASE_ENDING_MODIFIERS = frozenset({"distance", "along", "along_trajectory"})
#: ``parallel(overlap: ...)`` kinds whose other members end no later than the first one
#: (§7.6.2: ``equal``, ``end``, ``final`` end together with it; ``initial`` and
#: ``inside`` within it): the composition ends when its first member ends.
ENDS_WITH_FIRST = frozenset({"equal", "end", "final", "initial", "inside"})
#: kinds whose members of known length start late so that they end together (§7.3.9.3.3:
#: ``end``, all members end at the same time, the longest starting first; ``final``, the
#: others end with the first member and start no earlier than it)
STARTS_PLANNED = frozenset({"end", "final"})
#: kinds whose other members end no earlier than the first (``equal``: all start and end
#: at the same time; ``full``: the others cover the first member): a member of known length
#: that is shorter than the first cannot keep them
NOT_BEFORE_FIRST = frozenset({"equal", "full"})
MODIFIER_TIMINGS = ("start", "end", "all")


def _has_duration(arguments: tuple[ast.Argument, ...]) -> bool:
    return named_given(arguments, "duration")


def is_instant(inv: ast.Invocation) -> bool:
    """Whether the invocation takes no time: an instant action without a ``duration``."""
    return inv.name.text in INSTANT_ACTIONS and not _has_duration(inv.arguments)


def invocations(node: ast.Node) -> Iterator[ast.Invocation]:
    """The invocations of a ``do`` or ``on`` tree (a directive, a ``do`` member or a body),
    in source order: the members only, not their modifiers."""
    return (member for member in tree_members(node) if isinstance(member, ast.Invocation))


def tree_members(node: ast.Node) -> Iterator[ast.Node]:
    """Every member of a ``do`` or ``on`` tree (a directive, a ``do`` member or a body),
    in source order: the compositions, invocations, waits, emits and calls, not their
    arguments or modifiers. Compositions and emits are found nowhere else, so a search
    for them needs to walk no expression."""
    match node:
        case ast.DoDirective():
            yield from tree_members(node.member.body)
        case ast.OnDirective():
            for action in node.members:
                yield from tree_members(action)
        case ast.DoMember():
            yield from tree_members(node.body)
        case ast.Composition():
            yield node
            for member in node.members:
                yield from tree_members(member.body)
        case _:
            yield node


def is_acting(body: ast.Node) -> bool:
    """Whether a ``one_of`` member acts (invokes an action or a scenario) rather than
    only waiting (``wait``, ``emit``, ``call``)."""
    match body:
        case ast.Composition():
            return any(is_acting(m.body) for m in body.members)
        case ast.Invocation():
            return True
    return False


def enum_word(node: ast.Node | None) -> str | None:
    """The enum member an argument names (``start``, ``at.start``), else None."""
    match node:
        case ast.NameRef():
            return node.name.name.text
        case ast.EnumRef():
            return node.member.text
    return None


def modifier_timing(arguments: Mapping[str, ast.Node]) -> str:
    """``start``, ``end`` or ``all``: when a modifier with these bound arguments applies."""
    word = enum_word(arguments.get("at"))
    return word if word in MODIFIER_TIMINGS else "all"


#: the ``one_of`` choices an alternative depends on: (``one_of``, index of the acting
#: member) from the outermost in
Guard = tuple[tuple[ast.Composition, int], ...]


@dataclass
class TimeZero:
    """The invocations of a ``do`` tree that begin at time 0, in source order."""

    starts: list[ast.Invocation] = field(default_factory=list)
    alternatives: list[ast.Invocation] = field(default_factory=list)  # inside a one_of
    #: each alternative with the choices under which it begins at time 0
    options: list[tuple[Guard, ast.Invocation]] = field(default_factory=list)


def time_zero(body: ast.Node) -> TimeZero:
    """What of ``body`` (a ``do`` member's body) begins at time 0 (see the module docs)."""
    found = TimeZero()
    _collect(body, found.starts, found, ())
    return found


def _takes_no_time(body: ast.Node) -> bool:
    """Whether a ``do`` body ends when it begins (instant actions, emits, calls)."""
    return _collect(body, [], TimeZero(), ())


def after_waits(body: ast.Node) -> tuple[list[ast.Wait], TimeZero] | None:
    """What begins when the scenario first waits: for a ``serial`` body whose members
    before the first one that acts are ``wait``s (at least one) and members that take no
    time, those waits and what begins when they end (as :func:`time_zero` says of time
    0); None for any other body."""
    if not (isinstance(body, ast.Composition) and body.op == "serial"):
        return None
    waits: list[ast.Wait] = []
    found = TimeZero()
    for member in body.members:
        if isinstance(member.body, ast.Wait) and not (found.starts or found.alternatives):
            waits.append(member.body)
            continue
        if not waits:
            if not _takes_no_time(member.body):
                return None  # it acts or takes time before any wait
            continue
        if not _collect(member.body, found.starts, found, ()):
            break
    return (waits, found) if waits and (found.starts or found.alternatives) else None


def leading_parallel(body: ast.Node) -> ast.Composition | None:
    """The ``parallel`` a ``do`` body begins with at time 0: the body itself, or the
    first member of a ``serial`` when the members before it take no time (and so on
    inward); None when it begins otherwise."""
    while isinstance(body, ast.Composition) and body.op == "serial":
        first = next((m.body for m in body.members if not _takes_no_time(m.body)), None)
        if first is None:
            return None
        body = first
    return body if isinstance(body, ast.Composition) and body.op == "parallel" else None


def acting_members(comp: ast.Composition) -> list[ast.DoMember]:
    """The members of a ``one_of`` that act (:func:`is_acting`), the ones chosen from."""
    return [m for m in comp.members if is_acting(m.body)]


def _collect(body: ast.Node, starts: list[ast.Invocation], found: TimeZero, guard: Guard) -> bool:
    """Add the time-0 invocations of ``body`` (under the choices ``guard``); True when
    ``body`` takes no time."""
    match body:
        case ast.Composition(op="serial"):
            for member in body.members:
                if not _collect(member.body, starts, found, guard):
                    return False
            return not _has_duration(body.arguments)
        case ast.Composition(op="one_of"):
            for index, member in enumerate(acting_members(body)):
                _collect(member.body, found.alternatives, found, (*guard, (body, index)))
            return False
        case ast.Composition():
            instant = True
            for member in body.members:
                instant = _collect(member.body, starts, found, guard) and instant
            return instant and not _has_duration(body.arguments)
        case ast.Invocation():
            starts.append(body)
            if guard:
                found.options.append((guard, body))
            return is_instant(body)
        case ast.Emit() | ast.CallDirective():
            return True
    return False
