"""Road room: how far an actor can drive during the scenario, where that is a constant.

The witness must leave each actor enough road ahead of its start for what the
scenario makes it do. Where the scenario fixes how long everything lasts (every
phase has a constant ``duration``; no phase waits for an event or a goal) and
how fast an actor goes (constant ``speed(v)`` modifiers, ``change_speed``
targets, ``assign_speed``; ``remain_stationary`` is 0), the distance the actor
covers is at most its largest speed (or its start speed, if larger) times the
scenario's duration; placement then requires that much road ahead of the
actor's start (L514 when no start allows it). Where it does not, nothing is
required; placement prefers starts near the road's entry instead
(``placement.PREFERRED_START_SHARE``), which leaves room for most scenarios.

Durations and speeds are folded with the one evaluator
(``semantics.constants``), parameters through the constants that hard
``==`` constraints give them.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction

from osc2check.semantics.builtins import EVENT_FUNCTIONS
from osc2check.semantics.constants import (
    NotConstant,
    RangeValue,
    Value,
    evaluate,
    si_number,
)
from osc2check.semantics.model import Model
from osc2check.semantics.phases import (
    ENDLESS_ACTIONS,
    ENDS_WITH_FIRST,
    PHASE_ENDING_MODIFIERS,
    enum_word,
    invocations,
    is_instant,
)
from osc2check.semantics.symbols import Symbol
from osc2check.syntax import ast

__all__ = ["Motion", "motion_bounds", "wait_time"]

Lookup = Callable[[Symbol, ast.Node], Value]

_STOPPING = frozenset({"remain_stationary"})
_RELATIVE = ("faster_than", "slower_than", "same_as")


@dataclass
class Motion:
    """A bound on what the scenario makes its actors do: its total duration (None when
    not a constant) and each actor's largest constant speed (absent when unknown)."""

    duration: Fraction | None
    top_speed: dict[str, Fraction] = field(default_factory=dict)  # m/s, by actor name
    unknown_speed: set[str] = field(default_factory=set)  # actors whose speed is not constant


def motion_bounds(model: Model, bodies: Sequence[ast.Node], lookup: Lookup) -> Motion:
    """The bounds of the ``do`` bodies of a scenario (see the module docstring)."""
    motion = Motion(Fraction(0))
    for body in bodies:
        length = _duration(model, body, lookup)
        if length is None or motion.duration is None:
            motion.duration = None
        else:
            motion.duration = max(motion.duration, length)
        for inv in invocations(body):
            _speeds(model, inv, lookup, motion)
    return motion


def _number(
    model: Model, node: ast.Node, lookup: Lookup, upper: bool = True, ranges: bool = True
) -> Fraction | None:
    """A constant SI number (a range's upper, else lower, bound; None for one without
    ``ranges``), or None."""
    try:
        value = evaluate(node, model, lookup)
    except NotConstant:
        return None
    if isinstance(value, RangeValue):
        if not ranges:
            return None
        bounds = [si_number(value.low), si_number(value.high)]
        if None in bounds:
            return None
        known = [b for b in bounds if b is not None]
        return max(known) if upper else min(known)
    return si_number(value)


def _given(model: Model, call: ast.Node, name: str) -> ast.Node | None:
    """The argument given for parameter or extra ``name`` of ``call`` (no default)."""
    binding = model.binding(call)
    bound = binding.given(name) if binding is not None else None
    return bound.value if bound is not None else None


def _duration(model: Model, body: ast.Node, lookup: Lookup) -> Fraction | None:
    """The constant length of ``body`` in seconds, or None when it is not one."""
    match body:
        case ast.Composition():
            given = _given(model, body, "duration")
            if given is not None:
                return _number(model, given, lookup)
            if body.op == "parallel":
                return _parallel(model, body, lookup)
            lengths = [_duration(model, m.body, lookup) for m in body.members]
            if any(length is None for length in lengths):
                return None
            known = [length for length in lengths if length is not None]
            if body.op == "serial":
                return sum(known, Fraction(0))
            return max(known, default=Fraction(0))
        case ast.Invocation():
            given = _given(model, body, "duration")
            if given is not None:
                return _number(model, given, lookup)
            return Fraction(0) if is_instant(body) else None
        case ast.Wait():
            return _elapsed(model, body.event, lookup)
        case ast.Emit() | ast.CallDirective():
            return Fraction(0)
    return None


def _parallel(model: Model, body: ast.Composition, lookup: Lookup) -> Fraction | None:
    """A ``parallel`` without a duration, as the runner runs it (docs/runner.md,
    Composition): a member that cannot end on its own (an endless action without
    ``duration``, ``until`` or a modifier that ends its phase) ends when the others have;
    ``equal``, ``end``, ``final``, ``initial``, ``inside`` end with their first member."""
    members = [m.body for m in body.members]
    ending = [m for m in members if not _open_ended(model, m)]
    if not ending:
        return None  # nothing ends it
    overlap = enum_word(_given(model, body, "overlap")) or "start"
    if overlap in ENDS_WITH_FIRST and members[0] in ending:
        return _duration(model, members[0], lookup)
    lengths = [_duration(model, m, lookup) for m in ending]
    if any(length is None for length in lengths):
        return None
    return max((length for length in lengths if length is not None), default=Fraction(0))


def _open_ended(model: Model, body: ast.Node) -> bool:
    """An invocation of an endless action that nothing ends: no ``duration``, no ``until``,
    no modifier that ends its phase (``phases``)."""
    if not isinstance(body, ast.Invocation) or body.name.text not in ENDLESS_ACTIONS:
        return False
    if _given(model, body, "duration") is not None:
        return False
    for item in body.with_members:
        if isinstance(item, ast.Until):
            return False
        if isinstance(item, ast.Invocation) and (
            item.name.text in PHASE_ENDING_MODIFIERS
            or enum_word(_given(model, item, "at")) == "end"
        ):
            return False
    return True


def wait_time(model: Model, wait: ast.Wait, lookup: Lookup) -> Fraction | None:
    """The time a ``wait elapsed(d)`` takes when ``d`` is one constant (not a range the
    run draws from), else None."""
    return _elapsed(model, wait.event, lookup, exact=True)


def _elapsed(model: Model, event: ast.Node, lookup: Lookup, exact: bool = False) -> Fraction | None:
    """The time a ``wait`` takes when its event is ``elapsed(d)`` with a constant ``d``
    (a range's upper bound, unless ``exact``)."""
    if not (
        isinstance(event, ast.EventCondition)
        and isinstance(event.expr, ast.Call)
        and isinstance(event.expr.callee, ast.NameRef)
        and event.expr.callee.name.namespace is None
        and event.expr.callee.name.name.text == "elapsed"
    ):
        return None
    given = _given(model, event.expr, EVENT_FUNCTIONS["elapsed"].parameters[0].name)
    if given is None:
        return None
    found = _number(model, given, lookup, ranges=not exact)
    return None if found is None else max(found, Fraction(0))


def _speeds(model: Model, inv: ast.Invocation, lookup: Lookup, motion: Motion) -> None:
    """Record the speeds an invocation gives its actor (or that they are not constant)."""
    if not isinstance(inv.actor, ast.NameRef):
        return
    actor = inv.actor.name.name.text
    found: list[Fraction | None] = []
    if inv.name.text in _STOPPING:
        found.append(Fraction(0))
    for key in ("target", "speed"):
        given = _given(model, inv, key)
        if given is not None and inv.name.text in ("change_speed", "assign_speed"):
            found.append(_number(model, given, lookup))
    if inv.name.text == "assign_speed" and not inv.arguments:
        found.append(None)
    for item in inv.with_members:
        if not isinstance(item, ast.Invocation):
            continue
        name = item.name.text
        if name in ("speed", "change_speed", "acceleration", "keep_speed"):
            if name != "speed" or any(_given(model, item, k) is not None for k in _RELATIVE):
                found.append(None)
                continue
            given = _given(model, item, "speed")
            found.append(_number(model, given, lookup) if given is not None else None)
    for speed in found:
        if speed is None:
            motion.unknown_speed.add(actor)
        else:
            motion.top_speed[actor] = max(motion.top_speed.get(actor, Fraction(0)), abs(speed))
