"""Generated scenarios: the cells the generator covers, and a hypothesis strategy per cell.

A **cell** is what must be covered: an actor type, one of its actions, and one of the
modifiers the library associates with that action (or none), optionally with the form
of the modifier's call fixed: which reference parameter it names (``behind``,
``side_of``, ...), its ``at:`` (written or not) and whether a scalar is given a range.
:func:`cells` lists them from the library (:mod:`.library`): every action of every
actor type with every one of its modifiers, and every form of every modifier on the
open actions of each kind of actor (a vehicle that drives or stands, a person who
walks, an animal that moves). Hypothesis draws the rest of a case from the cell:
the values (:mod:`.values`), which optional parameters are given, positional or
named, a phase duration, and the context that makes the effect observable (the
subject's start lane and speed, a reference actor beside it).

A **case** renders as one scenario ``top``: the subject ``sub`` doing the action with
its modifiers, and, when a reference is named, ``ref`` moving beside it in
``parallel``.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, replace
from functools import cache
from typing import Any

from hypothesis import strategies as st

from tests.osc2runner.differential.library import Library, Parameter, Signature, library
from tests.osc2runner.differential.values import Value, rotated, value_of

__all__ = ["Arg", "Call", "Case", "Cell", "case_strategy", "cells"]

#: the open actions (no parameters, no end of their own) that carry every form of every
#: modifier, by actor kind: a vehicle that drives and one that stands, a person who
#: walks, an animal that moves
CARRIERS: dict[str, tuple[str, ...]] = {
    "vehicle": ("drive", "remain_stationary"),
    "person": ("walk",),
    "animal": ("move",),
}
#: the reference actor beside the subject, by the subject's kind: its type and action
REFERENCE: dict[str, tuple[str, str]] = {
    "vehicle": ("vehicle", "drive"),
    "person": ("person", "walk"),
    "animal": ("animal", "move"),
}
#: parameters every movement modifier has (the library's "common" ones), drawn seldom
COMMON = ("movement_mode", "track", "shape")
AT_FORMS = ("", "start", "end", "all")  # "" leaves `at` out (the default, all)


@dataclass(frozen=True)
class Arg:
    name: str
    text: str
    positional: bool = False
    value: Any = None  # SI number, (low, high) for a range, enum member, bool, actor name
    range: bool = False

    def render(self) -> str:
        return self.text if self.positional else f"{self.name}: {self.text}"


@dataclass(frozen=True)
class Call:
    name: str
    args: tuple[Arg, ...] = ()

    def arg(self, name: str) -> Arg | None:
        for a in self.args:
            if a.name == name:
                return a
        return None

    def has(self, name: str) -> bool:
        return self.arg(name) is not None

    @property
    def at(self) -> str:
        a = self.arg("at")
        return str(a.value) if a is not None else "all"

    def render(self, extra: str = "") -> str:
        parts = [a.render() for a in self.args]
        if extra:
            parts.append(extra)
        return f"{self.name}({', '.join(parts)})"


@dataclass(frozen=True)
class Cell:
    """What one generated test covers (see the module docstring)."""

    subject: str  # actor type
    action: str  # the action's label (``vehicle.drive``)
    modifier: str | None = None  # the modifier's label, or None
    reference: str | None = None  # the form's reference parameter; "-" none; None drawn
    at: str | None = None  # "" (left out), start, end, all; None: drawn
    ranged: bool | None = None  # a range given for a scalar; None: drawn
    index: int = 0  # its place in :func:`cells` (rotates the first choices)

    @property
    def id(self) -> str:
        parts = [self.subject, self.action.split(".")[-1]]
        if self.modifier is not None:
            parts.append(self.modifier.split(".")[-1])
        if self.reference is not None:
            parts.append(self.reference if self.reference != "-" else "plain")
        if self.at is not None:
            parts.append(f"at_{self.at or 'omitted'}")
        if self.ranged is not None:
            parts.append("range" if self.ranged else "scalar")
        return "-".join(parts)


@dataclass(frozen=True)
class Case:
    """One generated scenario (see the module docstring)."""

    cell: Cell
    subject: str  # the subject's actor type
    kind: str  # its catalogue kind (vehicle, person, ...) or its type for other actors
    action: Call
    tested: Call | None = None
    context: tuple[Call, ...] = ()  # the subject's other modifiers (its start)
    duration: float | None = None  # the subject's phase
    reference: str | None = None  # the reference actor's type, when one is named
    reference_action: str = "drive"
    reference_calls: tuple[Call, ...] = ()
    fields: tuple[str, ...] = ()  # more field declarations (structs, trailers)
    members: tuple[str, ...] = ()  # scenario members (``box.location(...)``)
    limit: float = 6.0  # the run's time limit (simulated seconds)
    instant: bool = False  # the action takes effect at once: wait a little after it

    @property
    def modifiers(self) -> tuple[Call, ...]:
        return (*self.context, *((self.tested,) if self.tested is not None else ()))

    def text(self) -> str:
        lines = ["import osc.standard", "", "scenario top:", f"    sub: {self.subject}"]
        if self.reference is not None:
            lines.append(f"    ref: {self.reference}")
        lines += [f"    {f}" for f in self.fields]
        lines += [f"    {m}" for m in self.members]
        extra = f"duration: {_seconds(self.duration)}" if self.duration is not None else ""
        invocation = f"sub.{self.action.render(extra)}" + (" with:" if self.modifiers else "")
        body: list[str] = [invocation, *(f"    {c.render()}" for c in self.modifiers)]
        if self.instant:
            body = ["serial:", *(f"    {line}" for line in body), "    wait elapsed(0.5s)"]
        if self.reference is not None:
            lines.append("    do parallel:")
            with_ = " with:" if self.reference_calls else ""
            lines.append(f"        ref.{self.reference_action}(){with_}")
            lines += [f"            {c.render()}" for c in self.reference_calls]
            lines += [f"        {line}" for line in body]
        else:
            lines.append(f"    do {body[0]}")
            lines += [f"    {line}" for line in body[1:]]
        return "\n".join(lines) + "\n"

    @property
    def tested_line(self) -> int:
        """The line of the tested modifier in :meth:`text` (1-based)."""
        lines = self.text().splitlines()
        if self.tested is None:
            return 0
        wanted = self.tested.render()
        return max(i for i, line in enumerate(lines, 1) if line.strip() == wanted)


def _seconds(x: float) -> str:
    return f"{x:g}s"


# ---------------------------------------------------------------------- cells


def _has_at(sig: Signature) -> bool:
    return sig.parameter("at") is not None


def _references(sig: Signature) -> list[str]:
    return [p.name for p in sig.parameters if p.actor]


def _scalars(sig: Signature) -> list[Parameter]:
    """The parameters a range may be given to (numbers and quantities)."""
    return [
        p for p in sig.parameters if p.kind in ("physical", "int", "uint") and p.name not in ("at",)
    ]


def movable_kinds(lib: Library) -> dict[str, str]:
    return dict(lib.actor_kinds)


def cells(lib: Library | None = None) -> list[Cell]:
    """Every cell the differential test covers, in a fixed order."""
    lib = lib or library()
    found: list[Cell] = []
    for subject, actions in lib.actions.items():
        for action in actions:
            found.append(Cell(subject, action.label))
            for mod in lib.modifiers.get(action.label, ()):
                found.append(Cell(subject, action.label, mod.label))
    for subject, kind in lib.actor_kinds.items():
        if subject != kind:  # one actor type per kind carries the forms (trailer: vehicle)
            continue
        for carrier in CARRIERS.get(kind, ()):
            action = next((a for a in lib.actions.get(subject, ()) if a.name == carrier), None)
            if action is None:
                continue
            for mod in lib.modifiers.get(action.label, ()):
                for form in _forms(mod):
                    found.append(Cell(subject, action.label, mod.label, *form))
    return [replace(c, index=i) for i, c in enumerate(found)]


def _forms(mod: Signature) -> Iterator[tuple[str, str | None, bool | None]]:
    references = ["-", *_references(mod)]
    ats: tuple[str | None, ...] = AT_FORMS if _has_at(mod) else (None,)
    ranges: tuple[bool | None, ...] = (False, True) if _scalars(mod) else (None,)
    for ref in references:
        for at in ats:
            for ranged in ranges:
                yield ref, at, ranged


# ---------------------------------------------------------------------- cases


@dataclass
class _Draft:
    """What drawing a case's calls found they need (a reference actor)."""

    kind: str
    reference: bool = False


def case_strategy(cell: Cell) -> st.SearchStrategy[Case]:
    """The cases of ``cell``."""
    return _case(cell)


@st.composite
def _case(draw: Any, cell: Cell) -> Case:
    lib = library()
    action = next(a for a in lib.actions[cell.subject] if a.label == cell.action)
    modifier = lib.everything[cell.modifier] if cell.modifier is not None else None
    kind = lib.actor_kinds.get(cell.subject, cell.subject)
    draft = _Draft(kind)
    action_call = draw(_call(action, cell, draft, False))
    tested = draw(_call(modifier, cell, draft, True)) if modifier is not None else None
    context = _context(kind, action, tested)
    if tested is not None and tested.name == "change_lane" and draw(st.booleans()):
        context = tuple(c for c in context if c.name != "lane")  # its start lane left free
    duration = draw(_duration(action, tested, cell.index))
    ref_type, ref_action = REFERENCE.get(kind, ("vehicle", "drive"))
    reference_calls = _reference_context(kind, tested) if draft.reference else ()
    return Case(
        cell,
        cell.subject,
        kind,
        action_call,
        tested,
        context,
        duration,
        ref_type if draft.reference else None,
        ref_action,
        reference_calls,
        limit=(duration or 6.0) + 1.0,
        instant=_instant(cell.subject, action.name),
    )


#: start quantities a modifier constrains: the context leaves them to it
CONSTRAINS: dict[str, tuple[str, ...]] = {
    "speed": ("speed",),
    "keep_position": ("speed",),
    "acceleration": ("speed",),
    "lane": ("lane",),
    "lateral": ("lane",),
    "position": ("s",),
}
#: actions that give the start speed themselves (the context leaves it to them)
SETS_SPEED = ("remain_stationary", "assign_speed")


def _context(kind: str, action: Signature, tested: Call | None) -> tuple[Call, ...]:
    """The subject's start: lane 1 and a steady speed, unless the tested modifier or the
    action gives them."""
    taken = CONSTRAINS.get(tested.name, ()) if tested is not None else ()
    calls = []
    if kind in ("vehicle", "person", "animal") and "lane" not in taken:
        calls.append(Call("lane", (Arg("lane", "1", True, 1), Arg("at", "start", value="start"))))
    if (
        kind in ("vehicle", "person", "animal")
        and "speed" not in taken
        and action.name not in SETS_SPEED
    ):
        v = "20kph" if kind == "vehicle" else "4kph"
        si = 20 / 3.6 if kind == "vehicle" else 4 / 3.6
        calls.append(Call("speed", (Arg("speed", v, True, si), Arg("at", "start", value="start"))))
    return tuple(calls)


def _reference_context(kind: str, tested: Call | None) -> tuple[Call, ...]:
    """The reference actor: in lane 2 at a steady speed, 30 m ahead of the subject unless
    the tested modifier places the subject relative to it."""
    v = "20kph" if kind == "vehicle" else "4kph"
    si = 20 / 3.6 if kind == "vehicle" else 4 / 3.6
    calls = [
        Call("lane", (Arg("lane", "2", True, 2), Arg("at", "start", value="start"))),
        Call("speed", (Arg("speed", v, True, si),)),
    ]
    if tested is None or "s" not in CONSTRAINS.get(tested.name, ()):
        calls.append(
            Call(
                "position",
                (
                    Arg("distance", "30m", True, 30.0),
                    Arg("ahead_of", "sub", value="sub"),
                    Arg("at", "start", value="start"),
                ),
            )
        )
    return tuple(calls)


def _duration(
    action: Signature, tested: Call | None, rotation: int
) -> st.SearchStrategy[float | None]:
    from tests.osc2runner.differential.properties import phase_time

    base = phase_time(action.name, tested)
    choices: list[float | None] = [base, base + 1.0]
    return st.sampled_from(rotated(choices, rotation))


@st.composite
def _call(draw: Any, sig: Signature, cell: Cell, draft: _Draft, tested: bool) -> Call:
    """A call of ``sig``: the cell's form for the tested modifier, the rest drawn."""
    rotation = cell.index
    params = list(sig.parameters)
    given: dict[str, Arg] = {}
    reference = cell.reference if tested else None
    if tested and reference is None:
        reference = draw(st.sampled_from(rotated(["-", *_references(sig)], rotation)))
    at = cell.at if tested else None
    if tested and at is None and _has_at(sig):
        at = draw(st.sampled_from(rotated(list(AT_FORMS), rotation)))
    ranged = cell.ranged if tested else False
    if tested and ranged is None:
        ranged = draw(st.booleans()) if _scalars(sig) else False
    # one member of each group of arguments that exclude each other may be given
    allowed: set[str] = set()
    for group in sig.exclusive:
        if any(sig.parameter(n) is not None and sig.parameter(n).actor for n in group):  # type: ignore[union-attr]
            continue  # references: the form chose
        allowed.add(draw(st.sampled_from(rotated(sorted(group), rotation))))
    excluded = {n for g in sig.exclusive for n in g if n not in allowed}
    mains = [p for p in params if _is_main(p) and p.name not in excluded]
    first_main = draw(st.sampled_from(rotated(mains, rotation))) if mains else None
    range_target = None
    if ranged:
        candidates = [p for p in _scalars(sig) if p.name not in excluded]
        range_target = (
            draw(st.sampled_from(rotated(candidates, rotation))).name if candidates else None
        )
    for param in params:
        if param.name == "at":
            if at:
                given["at"] = Arg("at", at, value=at)
            continue
        if param.actor:
            if tested and param.name == reference:
                given[param.name] = Arg(param.name, "ref", value="ref")
                draft.reference = True
            elif not tested and param.name == "reference" and draw(st.booleans()):
                given[param.name] = Arg(param.name, "ref", value="ref")
                draft.reference = True
            continue
        if param.name in excluded or param.kind in ("compound", "list"):
            continue  # structs and map elements: not written by this generator
        if param.name in COMMON:
            if draw(st.integers(0, 9)) != 9:  # seldom (hypothesis tries 0 first)
                continue
        elif param.name == range_target:
            pass
        elif param is not first_main and not draw(st.booleans()):
            continue
        strategy = value_of(sig.name, param, draft.kind, rotation, param.name == range_target)
        if strategy is None:
            continue
        value: Value = draw(strategy)
        given[param.name] = Arg(param.name, value.text, value=value.value, range=value.range)
    for arg, needed in sig.requires:
        if arg in given and needed not in given:
            p = sig.parameter(needed)
            if p is not None and p.actor:
                given[needed] = Arg(needed, "ref", value="ref")
                draft.reference = True
            elif p is not None:
                strategy = value_of(sig.name, p, draft.kind, rotation, False)
                if strategy is not None:
                    v = draw(strategy)
                    given[needed] = Arg(needed, v.text, value=v.value)
    declared = [p.name for p in params]
    ordered = sorted(given.values(), key=lambda a: declared.index(a.name))
    # positional: a prefix of the parameters in declaration order, each of them given
    prefix = 0
    for p in params:
        if p.name not in given or p.example_only:
            break
        prefix += 1
    k = draw(st.integers(0, prefix)) if prefix else 0
    return Call(sig.name, tuple(replace(a, positional=i < k) for i, a in enumerate(ordered)))


def _is_main(param: Parameter) -> bool:
    """A parameter the call is about (no default: ``speed`` of ``speed``, ``target`` of
    ``change_speed``): one of them is always given."""
    return not param.default and not param.actor and param.name not in COMMON


@cache
def _instant(subject: str, action: str) -> bool:
    """Whether the runner's implementation of the action takes effect at once (the case
    then waits a little after it, for the telemetry to show it)."""
    from osc2check.semantics.stdlib import standard_library
    from osc2runner.behaviours.base import InstantAction
    from osc2runner.compile.registry import standard_registry

    model = standard_library().model
    actor = next(s for s in model.symbols if s.name == subject and s.library)
    found = model.behaviour(actor, action)
    entry = standard_registry().find_action(model, actor, found[0]) if found else None
    return (
        entry is not None
        and isinstance(entry.target, type)
        and issubclass(entry.target, InstantAction)
    )
