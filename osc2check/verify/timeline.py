"""Points in time and phases: when a phase runs, and when it may be stopped.

The timing model (``verify.timing``) gives every phase of a scenario's behaviour a
start and an end on its own (``Phase.end``: before anything around it stops it).
Times are ``Time`` values, linear terms of the constraint IR with a flag for
"never" (an endless action never ends on its own); the combinators fold what does
not depend on the unknowns as they build, so constant durations give constants.

What the runner does at a given time (``osc2runner.compile.composites``):

* ``endless``: the phase runs and everything running under it is an action that
  never ends on its own, so stopping it is its planned end (``running_endless``): a
  phase bounded by a duration is endless only once its lower bound has passed, one
  ended by ``until`` never, a ``one_of`` with waiting members never.
* ``open_now``: everything running under it is open-ended (an endless action
  without ``duration`` or ``until``; ``running_open``), so a ``parallel`` that joins
  on its members may end without it.

A check at time ``t`` sees a phase as it is before the tick at ``t`` (one ending in
that tick still runs) or after it (one starting in it runs); ``pre`` chooses.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from fractions import Fraction

from osc2check.source import Span
from osc2check.verify import ir, propagate

TRUE, FALSE = ir.const(True), ir.const(False)
ZERO = ir.const(0)


# ---- terms, folded while they are built ----------------------------------------------


def holds_as(term: ir.Term, value: bool) -> bool:
    return isinstance(term, ir.Const) and term.value is value


def all_of(*args: ir.Term) -> ir.Term:
    kept: list[ir.Term] = []
    for a in args:
        if holds_as(a, False):
            return FALSE
        if holds_as(a, True):
            continue
        if isinstance(a, ir.Op) and a.op == "and":
            kept.extend(a.args)
        else:
            kept.append(a)
    if not kept:
        return TRUE
    return kept[0] if len(kept) == 1 else ir.Op("and", tuple(kept))


def any_of(*args: ir.Term) -> ir.Term:
    kept: list[ir.Term] = []
    for a in args:
        if holds_as(a, True):
            return TRUE
        if holds_as(a, False):
            continue
        if isinstance(a, ir.Op) and a.op == "or":
            kept.extend(a.args)
        else:
            kept.append(a)
    if not kept:
        return FALSE
    return kept[0] if len(kept) == 1 else ir.Op("or", tuple(kept))


def negation(a: ir.Term) -> ir.Term:
    if isinstance(a, ir.Const):
        return ir.const(not a.value)
    if isinstance(a, ir.Op) and a.op == "not":
        return a.args[0]
    return ir.Op("not", (a,))


def implies(a: ir.Term, b: ir.Term) -> ir.Term:
    return any_of(negation(a), b)


def if_then(condition: ir.Term, a: ir.Term, b: ir.Term) -> ir.Term:
    if isinstance(condition, ir.Const):
        return a if condition.value else b
    if a is b or (isinstance(a, ir.Const) and isinstance(b, ir.Const) and a == b):
        return a
    return ir.Op("ite", (condition, a, b))


def plus(a: ir.Term, b: ir.Term) -> ir.Term:
    if isinstance(a, ir.Const) and isinstance(b, ir.Const):
        return ir.const(Fraction(a.value) + Fraction(b.value))
    if isinstance(b, ir.Const) and b.value == 0:
        return a
    if isinstance(a, ir.Const) and a.value == 0:
        return b
    return ir.Op("+", (a, b))


def compare(op: str, a: ir.Term, b: ir.Term) -> ir.Term:
    """``a op b``, computed when it does not depend on the unknowns (``s < s + 3``)."""
    if a is b:
        return ir.const(op in ("<=", ">=", "=="))
    left, right = propagate.linear(a), propagate.linear(b)
    if left is not None and right is not None:
        difference = dict(left[0])
        for name, c in right[0].items():
            difference[name] = difference.get(name, Fraction(0)) - c
        if not any(difference.values()):
            value = propagate.evaluate(ir.Op(op, (ir.const(left[1]), ir.const(right[1]))), {})
            return ir.const(bool(value))
    return ir.Op(op, (a, b))


# ---- points in time -------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Time:
    """A point in time: ``at`` seconds when ``finite`` holds, else never."""

    finite: ir.Term
    at: ir.Term

    @property
    def never(self) -> bool:
        """Never, whatever the unknowns."""
        return holds_as(self.finite, False)


NEVER = Time(FALSE, ZERO)


def at_time(term: ir.Term) -> Time:
    return Time(TRUE, term)


def no_later(a: Time, b: Time) -> ir.Term:
    return any_of(negation(b.finite), all_of(a.finite, compare("<=", a.at, b.at)))


def before(a: Time, b: Time) -> ir.Term:
    return all_of(a.finite, any_of(negation(b.finite), compare("<", a.at, b.at)))


def same_time(a: Time, b: Time) -> ir.Term:
    both = all_of(a.finite, b.finite, compare("==", a.at, b.at))
    return any_of(all_of(negation(a.finite), negation(b.finite)), both)


def after(a: Time, duration: ir.Term) -> Time:
    return NEVER if a.never else Time(a.finite, plus(a.at, duration))


def earliest(a: Time, b: Time) -> Time:
    if a.never:
        return b
    if b.never:
        return a
    first = all_of(a.finite, any_of(negation(b.finite), compare("<=", a.at, b.at)))
    return Time(any_of(a.finite, b.finite), if_then(first, a.at, b.at))


def latest(a: Time, b: Time) -> Time:
    if a.never or b.never:
        return NEVER
    return Time(all_of(a.finite, b.finite), if_then(compare(">=", a.at, b.at), a.at, b.at))


def earliest_of(times: Iterable[Time]) -> Time:
    result = NEVER
    for t in times:
        result = earliest(result, t)
    return result


def latest_of(times: list[Time]) -> Time:
    if not times:
        return NEVER
    result = times[0]
    for t in times[1:]:
        result = latest(result, t)
    return result


def either(condition: ir.Term, a: Time, b: Time) -> Time:
    return Time(if_then(condition, a.finite, b.finite), if_then(condition, a.at, b.at))


# ---- phases ---------------------------------------------------------------------------


#: a phase as the runner knows it: the path of the scenario instance it is written in
#: ("" for the root scenario) and the span of its invocation, composition or directive
PhaseKey = tuple[str, Span]


@dataclass(eq=False, kw_only=True)
class Phase:
    """One phase of the behaviour: where it is written, when it starts, and when it ends
    on its own (``end``: before anything around it stops it); ``keys``: the runner's
    names of it (an invocation without duration or ``until`` of a scenario is the same
    phase as the scenario's ``do``)."""

    name: str
    span: Span
    start: Time
    end: Time
    keys: list[PhaseKey] = field(default_factory=list)


@dataclass(eq=False, kw_only=True)
class Leaf(Phase):
    """An action, a `wait`, an `emit` or a `call`; ``endless``: stopping it at any time
    is its planned end; ``opens``: the runner's open-ended (no duration, no until)."""

    endless: bool = False
    opens: bool = False


@dataclass(eq=False, kw_only=True)
class Bounded(Phase):
    """``duration: [low..high]`` around ``child``; ``values``: what its written duration
    says of ``low`` and ``high`` (its line in a conflict is ``where``, ``text``)."""

    child: Phase
    low: ir.Term
    high: ir.Term
    values: ir.Term
    where: Span
    text: str


@dataclass(eq=False, kw_only=True)
class UntilEvent(Phase):
    """``with: until e`` around ``child``: ``event`` is when ``e`` occurs."""

    child: Phase
    event: Time


@dataclass(eq=False, kw_only=True)
class Sequence(Phase):
    members: list[Phase]


@dataclass(eq=False, kw_only=True)
class Together(Phase):
    """A ``parallel``; ``joined``: when every member has ended or is open-ended;
    ``delays``: how long after the composition each member starts (``overlap: end``,
    ``final``: a member of known length starts so that it ends with the others)."""

    members: list[Phase]
    first_ends: bool
    joined: Time
    where: Span
    text: str
    delays: list[ir.Term] = field(default_factory=list)
    kind: str = "start"  # the overlap kind
    lengths: list[ir.Term | None] = field(default_factory=list)  # each member's, when known


@dataclass(eq=False, kw_only=True)
class Choice(Phase):
    """A ``one_of``: acting member ``j`` runs when ``chosen[j]`` holds; waiting members
    run alongside; ``chosen_end`` is when the chosen member ends."""

    acting: list[Phase]
    waiting: list[Phase]
    chosen: list[ir.Term]
    chosen_end: Time


def running(phase: Phase, t: Time, pre: bool) -> ir.Term:
    """Whether ``phase`` runs at ``t``: seen before the tick at ``t`` (it may end in that
    tick) or after it (it may have started in that tick)."""
    if pre:
        return all_of(before(phase.start, t), no_later(t, phase.end))
    return all_of(no_later(phase.start, t), before(t, phase.end))


def endless(phase: Phase, t: Time, pre: bool) -> ir.Term:
    """Whether ``phase`` runs at ``t`` and everything running under it is endless: it
    may be stopped then as planned (the runner's ``running_endless``)."""
    match phase:
        case Leaf():
            return running(phase, t, pre) if phase.endless else FALSE
        case Bounded():  # its child may run on after the bound ends the phase: both run
            return all_of(
                running(phase, t, pre),
                no_later(after(phase.start, phase.low), t),
                endless(phase.child, t, pre),
            )
        case UntilEvent():
            return FALSE
        case Sequence():
            return any_of(*(endless(m, t, pre) for m in phase.members))
        case Together():
            each = [endless(m, t, pre) for m in phase.members]
            return all_of(
                running(phase, t, pre),
                any_of(*each),
                *(implies(running(m, t, pre), e) for m, e in zip(phase.members, each, strict=True)),
            )
        case Choice():
            if phase.waiting:
                return FALSE
            return all_of(
                running(phase, t, pre),
                any_of(
                    *(
                        all_of(c, endless(a, t, pre))
                        for c, a in zip(phase.chosen, phase.acting, strict=True)
                    )
                ),
            )
    return FALSE


def open_now(phase: Phase, t: Time) -> ir.Term:
    """Whether ``phase`` runs at ``t`` and everything running under it is open-ended
    (the runner's ``running_open``, after the tick at ``t``)."""
    match phase:
        case Leaf():
            return running(phase, t, False) if phase.opens else FALSE
        case Sequence():
            return any_of(*(open_now(m, t) for m in phase.members))
        case Together():
            each = [open_now(m, t) for m in phase.members]
            return all_of(
                running(phase, t, False),
                any_of(*each),
                *(
                    implies(running(m, t, False), o)
                    for m, o in zip(phase.members, each, strict=True)
                ),
            )
        case Choice():
            if phase.waiting:
                return FALSE
            return all_of(
                running(phase, t, False),
                any_of(
                    *(
                        all_of(c, open_now(a, t))
                        for c, a in zip(phase.chosen, phase.acting, strict=True)
                    )
                ),
            )
    return FALSE


def open_from(phase: Phase) -> Time | None:
    """When ``phase`` becomes open-ended, if it then stays so until it ends (``NEVER``:
    it never is); None when it may be open for a while and then go on."""
    match phase:
        case Leaf():
            return phase.start if phase.opens else NEVER
        case Bounded() | UntilEvent():
            return NEVER
        case Sequence():
            froms = [open_from(m) for m in phase.members]
            capable = [i for i, f in enumerate(froms) if f is None or not f.never]
            if not capable:
                return NEVER
            i = capable[0]
            last = i == len(phase.members) - 1 or phase.members[i].end.never
            return froms[i] if len(capable) == 1 and last else None
        case Together():
            together = [open_from(m) for m in phase.members]
            if any(f is None for f in together):
                return None
            return latest_of([f for f in together if f is not None])
        case Choice():
            if phase.waiting:
                return NEVER
            acting = [open_from(a) for a in phase.acting]
            if any(f is None for f in acting):
                return None
            found = NEVER
            for c, f in zip(reversed(phase.chosen), reversed(acting), strict=True):
                assert f is not None  # checked above
                found = either(c, f, found)
            return found
    return NEVER
