"""The schedule of a run: when each phase must end and when each member starts, as the
timing model (``verify.timing``) works it out, for the runner to plan against.

The timing model gives every phase a start and an end, terms over exact rationals
(``verify.timeline``). Some of those times are known before the phase starts, once
the witness has given every duration its value: a ``drive()`` inside
``parallel(duration: 25s)`` is stopped 25 s after the ``parallel`` starts, a
``change_lane(duration: 3s)`` must be done 3 s after it starts, a member of
``parallel(overlap: end)`` that lasts 2 s starts 2 s before the others end. Others
depend on what only the run knows (when a goal is reached, when an event occurs):
those are not in the schedule, and a plan without a deadline is the runner's own.

* A phase's **deadline** is the earliest time something ends or stops it that is
  known: its own end (a fixed length), its ``duration``'s upper bound, an
  ``until elapsed(d)``, the end of the ``parallel`` or ``serial`` duration around
  it, the first member of a ``parallel(overlap: equal|end|...)`` it belongs to, the
  other members of a ``parallel`` that ends an open-ended member with them.
  It is given relative to the start of a phase that has started by then (the phase
  itself or one around it), because the run knows when phases start: ``(anchor,
  seconds after the anchor starts)``.
* A member's **delay**: how long after its ``parallel`` starts it starts
  (``overlap: end``, ``final``).
* A phase's **length**, when it is fixed before it starts (a ``duration`` that is
  one value, ``wait elapsed(d)``, a ``serial`` of such).

:class:`Resolver` holds what the model knows of its variables: which are durations
written in the scenario (their values come with the witness) and which are defined
by others; :func:`schedule` evaluates the plan for one witness.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from fractions import Fraction

from osc2check.verify import ir, propagate
from osc2check.verify.timeline import (
    Bounded,
    Choice,
    Leaf,
    Phase,
    PhaseKey,
    Sequence,
    Time,
    Together,
    UntilEvent,
    after,
    holds_as,
)

__all__ = ["PhasePlan", "Resolver", "Schedule", "TimingPlan", "schedule"]

#: how many nodes an expanded term may have before it counts as unknown
_BUDGET = 4000


class Resolver:
    """What the timing model knows of its variables: ``defined`` (a variable and the term
    it stands for) and ``written`` (a duration or event time the scenario writes, and the
    term of its value: a constant, or a parameter the witness values)."""

    def __init__(self, defined: Mapping[str, ir.Term], written: Mapping[str, ir.Term]) -> None:
        self.defined = defined
        self.written = written
        self._memo: dict[str, ir.Term | None] = {}

    def forget(self) -> None:
        """Forget the expansions worked out so far (definitions were taken back)."""
        self._memo.clear()

    def expand(self, term: ir.Term) -> ir.Term | None:
        """``term`` with every defined variable replaced by what it stands for; None when
        that grows beyond a bound (then it is treated as unknown)."""
        budget = [_BUDGET]
        try:
            return self._expand(term, budget)
        except _TooBig:
            return None

    def _expand(self, term: ir.Term, budget: list[int]) -> ir.Term:
        budget[0] -= 1
        if budget[0] < 0:
            raise _TooBig
        if isinstance(term, ir.Ref):
            name = term.var.name
            if name not in self.defined:
                return term
            if name not in self._memo:
                self._memo[name] = None  # a cycle cannot happen; guard anyway
                self._memo[name] = self._expand(self.defined[name], budget)
            found = self._memo[name]
            if found is None:
                raise _TooBig
            return found
        if isinstance(term, ir.Op):
            return ir.Op(term.op, tuple(self._expand(a, budget) for a in term.args))
        return term

    def known(self, term: ir.Term) -> bool:
        """Whether ``term`` (expanded) depends on written values only."""
        return all(n in self.written for n in ir.names(term))

    def difference(self, later: ir.Term, earlier: ir.Term) -> ir.Term | None:
        """``later - earlier`` as a term of written values only, or None when it depends on
        what only the run knows."""
        linear = propagate.linear(ir.minus(later, earlier))
        if linear is not None and not linear[0]:
            return ir.const(linear[1])
        expanded = self.expand(ir.minus(later, earlier))
        if expanded is None:
            return None
        linear = propagate.linear(expanded)
        if linear is not None and not linear[0]:
            return ir.const(linear[1])
        folded = propagate.fold(expanded, {})
        return folded if self.known(folded) else None

    def always(self, flag: ir.Term, given: ir.Term) -> bool:
        """Whether ``flag`` holds whenever ``given`` does (both expanded and compared as
        written: a time that is finite whenever its phase starts)."""
        if holds_as(flag, True):
            return True
        a, b = self.expand(flag), self.expand(given)
        return a is not None and (holds_as(a, True) or a == b)

    def length(self, phase: Phase) -> ir.Term | None:
        """How long ``phase`` lasts, when that is fixed before it starts."""
        if phase.end.never or not self.always(phase.end.finite, phase.start.finite):
            return None
        return self.difference(phase.end.at, phase.start.at)


class _TooBig(Exception):
    pass


@dataclass(frozen=True, slots=True)
class PhasePlan:
    """What the schedule says of one phase (see the module docstring); times in s."""

    #: ``(anchor, seconds)``: the phase must be done that long after ``anchor`` starts;
    #: the earliest of them counts
    deadlines: tuple[tuple[PhaseKey, float], ...] = ()
    delay: float = 0.0  # after its ``parallel`` starts
    length: float | None = None


@dataclass(frozen=True)
class Schedule:
    """The plan of every phase of one run, by the runner's name of it (``PhaseKey``)."""

    phases: Mapping[PhaseKey, PhasePlan] = field(default_factory=dict)

    def get(self, key: PhaseKey) -> PhasePlan | None:
        return self.phases.get(key)

    def __len__(self) -> int:
        return len(self.phases)


@dataclass
class _Entry:
    """One phase as the walk meets it: the phases around it and what stops it."""

    phase: Phase
    anchors: list[Phase]  # itself, then the phases around it, innermost first
    stops: list[Time]  # when something around it ends it (with or without a check)
    delay: ir.Term | None = None


@dataclass
class TimingPlan:
    """The timing model of one scenario, kept for the schedule of its runs."""

    root: Phase
    resolver: Resolver
    entries: list[_Entry] = field(default_factory=list)

    @classmethod
    def of(cls, root: Phase, resolver: Resolver) -> TimingPlan:
        plan = cls(root, resolver)
        plan.entries = list(_walk(root, [], []))
        return plan


def _walk(phase: Phase, around: list[Phase], stops: list[Time]) -> Iterator[_Entry]:
    """Every phase under ``phase`` (included), with the phases around it and the times at
    which something around it stops it (as ``verify.timing``'s ``require`` passes them)."""
    anchors = [phase, *around]
    yield _Entry(phase, anchors, list(stops))
    match phase:
        case Bounded():
            last = after(phase.start, phase.high)
            yield from _walk(phase.child, anchors, [*stops, last])
        case UntilEvent():
            yield from _walk(phase.child, anchors, [*stops, phase.event])
        case Sequence():
            for member in phase.members:
                yield from _walk(member, anchors, stops)
        case Together():
            inner = [*stops, phase.end]
            for k, member in enumerate(phase.members):
                entries = list(_walk(member, anchors, inner))
                if phase.delays:
                    entries[0].delay = phase.delays[k]
                yield from entries
        case Choice():
            for member in (*phase.acting, *phase.waiting):
                yield from _walk(member, anchors, [*stops, phase.end])
        case Leaf():
            pass


def schedule(plan: TimingPlan | None, values: Mapping[str, Fraction | bool]) -> Schedule:
    """The schedule of one run: ``plan`` evaluated with the witness's ``values`` (the
    parameters that written durations name)."""
    if plan is None:
        return Schedule()
    resolver = plan.resolver
    known: dict[str, Fraction | bool] = {}
    for name, term in resolver.written.items():
        try:
            value = propagate.evaluate(term, values)
        except (KeyError, TypeError, ZeroDivisionError):
            continue
        known[name] = value if isinstance(value, bool) else Fraction(value)

    def seconds(term: ir.Term | None) -> float | None:
        if term is None:
            return None
        folded = propagate.fold(term, known)
        if isinstance(folded, ir.Const) and not isinstance(folded.value, bool):
            return float(folded.value)
        return None

    phases: dict[PhaseKey, PhasePlan] = {}
    for entry in plan.entries:
        phase = entry.phase
        if not phase.keys or all(k in phases for k in phase.keys):
            continue  # a phase wrapped by another of the same keys: the outer one counts
        candidates = [phase.end, *entry.stops]
        if isinstance(phase, Bounded):
            candidates.append(after(phase.start, phase.high))
        elif isinstance(phase, UntilEvent):
            candidates.append(phase.event)  # (an `until elapsed(d)`: known)
        deadlines: dict[PhaseKey, float] = {}
        for time in candidates:
            found = _relative(resolver, time, entry.anchors, seconds)
            if found is not None:
                key, offset = found
                deadlines[key] = min(offset, deadlines.get(key, offset))
        delay = seconds(entry.delay) if entry.delay is not None else 0.0
        length = seconds(resolver.length(phase))
        found_plan = PhasePlan(tuple(deadlines.items()), max(delay or 0.0, 0.0), length)
        for key in phase.keys:
            phases.setdefault(key, found_plan)
    return Schedule(phases)


def _relative(
    resolver: Resolver,
    time: Time,
    anchors: list[Phase],
    seconds: Callable[[ir.Term | None], float | None],
) -> tuple[PhaseKey, float] | None:
    """``time`` as seconds after the start of the innermost anchor it is known from."""
    if time.never:
        return None
    for anchor in anchors:
        if not anchor.keys or anchor.start.never:
            continue
        if not resolver.always(time.finite, anchor.start.finite):
            continue
        offset = seconds(resolver.difference(time.at, anchor.start.at))
        if offset is not None:
            return anchor.keys[0], offset
    return None
