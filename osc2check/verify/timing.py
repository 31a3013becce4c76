"""The timing of behaviour: when each phase of a scenario's ``do`` tree starts and ends.

Every phase of the root scenario's ``do`` (and of the scenarios it invokes, under
their instance paths) gets a start and an end, linear terms over exact rationals
in the constraint IR, so the solver decides the timing with the scenario's other
constraints and names the lines of a conflict (B608). The rules are the runner's
(``docs/runner.md``, "Language semantics as run"; ``osc2runner.compile``):

* ``serial``: each member starts when the one before ends.
* ``parallel``: members start together. ``start``, ``any``, ``full`` end when
  every member has ended, or earlier when one has and every other is open-ended
  (an endless action without ``duration``/``until``, which the others end).
  ``equal``, ``end``, ``final``, ``initial``, ``inside`` end with the first
  member (``phases.ENDS_WITH_FIRST``); every other member must have ended then
  or be endless then (stopping it is its planned end).
* ``one_of``: one acting member runs (some choice must work), with the members
  that only wait; the first of them to end ends it, and stops the others.
* ``duration: d`` or ``[a..b]``: the phase ends at ``b`` and holds an earlier end
  until ``a``; what still runs at ``b`` must be endless then. Its phase lasts
  ``[a, b]``; a phase that completes exactly at ``b`` ends on time.
* ``until e``: the phase ends when ``e`` occurs, also before a duration's lower
  bound; ``elapsed(d)`` occurs ``d`` after the start, any other event at an unknown
  time. What runs under it only has to keep its timing until then.
* Actions (``phases``): instant ones take no time; endless ones
  (``phases.ENDLESS_ACTIONS``) never end on their own, unless a modifier that ends
  the phase is reached; any other action ends when its goal is reached, after an
  unknown time (zero or more: the goal may hold already). ``wait`` ends when its
  event occurs (``elapsed(d)``: after ``d``); ``emit`` and ``call`` take no time.

"Endless at time t" follows the runner's ``running_endless`` (a phase bounded by a
duration is endless only once its lower bound has passed, one with ``until``
never), "open" its ``running_open``. What is stopped before a check is due (by a
duration, by the first member of its ``parallel``, by a ``one_of`` or ``until``)
owes nothing after that.

What the model cannot know stays free, so a conflict is reported only when no
trace satisfies the rules: the time an event occurs, the time a goal takes (the
physics may need more: that is the runner's to find), which ``one_of`` member is
chosen. Members' start offsets (``start_to_start``, ``end_to_end``) are not
modelled: such a ``parallel`` is free, and the offsets are reported as not
verified (C411), as is a duration that cannot be solved for.

Cost: with constant durations the model usually folds to constants while it is
built; what is left is checked under a canonical choice of the unknowns (zero
times, the first choice). Only when that fails, or when a duration names a
parameter (the witness must then give it a value that keeps the timing), is the
model added to the problem, with each duration's written value a constraint of
its own line so that a conflict names the lines (kind ``timing``); the rules that
only define a start or an end are added as ``definition`` constraints, which
never take part in a conflict. The model's variables and constraints are kept in a
``verify.timing_model.TimingModel``; this module builds the phases and what they require.
"""

from __future__ import annotations

from fractions import Fraction

from osc2check.semantics.bindings import BoundArgument
from osc2check.semantics.builtins import EVENT_FUNCTIONS, OVERLAP_KINDS
from osc2check.semantics.constants import NotConstant, evaluate, si_number
from osc2check.semantics.members import scenario_do
from osc2check.semantics.phases import (
    ENDLESS_ACTIONS,
    ENDS_WITH_FIRST,
    INSTANT_ACTIONS,
    NOT_BEFORE_FIRST,
    PHASE_ENDING_MODIFIERS,
    STARTS_PLANNED,
    enum_word,
    is_acting,
    modifier_timing,
)
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.verify import ir
from osc2check.verify.parameters import Lowerer
from osc2check.verify.schedule import Resolver, TimingPlan
from osc2check.verify.terms import (
    MAX_DEPTH,
    InstanceScope,
    NotEncodable,
    join_path,
    one_of_variable,
)
from osc2check.verify.timeline import (
    NEVER,
    TRUE,
    ZERO,
    Bounded,
    Choice,
    Leaf,
    Phase,
    Sequence,
    Time,
    Together,
    UntilEvent,
    after,
    all_of,
    any_of,
    at_time,
    before,
    compare,
    earliest,
    earliest_of,
    either,
    endless,
    holds_as,
    if_then,
    implies,
    latest,
    latest_of,
    no_later,
    open_from,
    open_now,
    plus,
    same_time,
)
from osc2check.verify.timing_model import TIMING_PREFIX, TimingModel, is_timing_variable

__all__ = ["TIMING_PREFIX", "is_timing_variable", "lower_timing", "timing_plan"]

# ---- building the model ------------------------------------------------------------


class _NotConstant(Exception):
    """A duration names a parameter: the model must go to the solver with the problem."""


class _Builder:
    """Builds the phases of a scenario (see the module docstring). With ``symbolic``
    false every duration must be a constant (else ``_NotConstant``) and is folded in;
    with it true every written duration and event time is a variable whose value is a
    constraint of its own line."""

    def __init__(self, lowerer: Lowerer, scenario: Symbol, symbolic: bool) -> None:
        self.lw = lowerer
        self.model = lowerer.model
        self.scenario = scenario
        self.symbolic = symbolic
        self.out = TimingModel(symbolic)
        self.expanding: list[Symbol] = []
        self.resolver = Resolver(self.out.defined, self.out.written)
        self.root: Phase | None = None

    # ---- values written in the scenario

    def _constant(self, node: ast.Node) -> Fraction | None:
        try:
            return si_number(evaluate(node, self.model))
        except NotConstant:
            return None

    def _value(
        self, node: ast.Node, scope: InstanceScope, name: str, where: Span, text: str
    ) -> tuple[ir.Term, ir.Term] | None:
        """A written time as a term, and what its line says of that term (``TRUE`` when
        folded in); None when it cannot be solved for (reported as not verified)."""
        constant = self._constant(node)
        if constant is not None and not self.symbolic:
            return ir.const(constant), TRUE
        if constant is None and not self.symbolic:
            raise _NotConstant
        if constant is not None:
            value: ir.Term = ir.const(constant)
        else:
            try:
                value = self.lw.term(node, scope)
            except NotEncodable as reason:
                self.lw.problem.skip(where, text, f"{reason}: its timing is not verified")
                return None
        var = ir.Ref(self.out.var(name, "real"))
        self.out.written[var.var.name] = value
        return var, ir.op("==", var, value)

    def _duration(
        self, arg: BoundArgument, scope: InstanceScope, callee: str, name: str
    ) -> tuple[ir.Term, ir.Term, ir.Term, str] | None:
        """The bounds of a ``duration`` argument, what its line says of them, and its
        text; None when a bound is a negative constant (B604 reports it)."""
        value = arg.value
        written = self.lw.text_of(arg.span)
        if arg.positional:
            written = f"duration: {written}"
        text = f"{callee}({written})"
        nodes = [value.low, value.high] if isinstance(value, ast.RangeLiteral) else [value]
        if any((c := self._constant(n)) is not None and c < 0 for n in nodes):
            return None
        terms: list[ir.Term] = []
        says: list[ir.Term] = []
        for i, node in enumerate(nodes):
            found = self._value(node, scope, f"{name}.duration{'.' + str(i) if i else ''}",
                                arg.span, text)  # fmt: skip
            if found is None:
                found = (self.out.unknown(f"{name}.duration.{i}", "real", arg.span, ZERO), TRUE)
            terms.append(found[0])
            says.append(found[1])
            if not isinstance(found[0], ir.Const):
                says.append(compare(">=", found[0], ZERO))  # a phase lasts no negative time
        if len(terms) == 1:
            return terms[0], terms[0], all_of(*says), text
        a, b = terms
        in_order = compare("<=", a, b)  # a range's bounds may come in either order
        return if_then(in_order, a, b), if_then(in_order, b, a), all_of(*says), text

    def _delay(
        self, spec: ast.Node, scope: InstanceScope, name: str, where: Span, text: str
    ) -> ir.Term | None:
        """How long after its context starts an event occurs: ``elapsed(d)`` after ``d``,
        ``every(p, offset: o)`` first after ``o``; None for any other event."""
        if not (
            isinstance(spec, ast.EventCondition)
            and isinstance(spec.expr, ast.Call)
            and isinstance(spec.expr.callee, ast.NameRef)
            and spec.expr.callee.name.namespace is None
        ):
            return None
        function = spec.expr.callee.name.name.text
        if function not in ("elapsed", "every"):
            return None
        wanted = 0 if function == "elapsed" else 1
        parameter = EVENT_FUNCTIONS[function].parameters[wanted].name
        binding = self.model.binding(spec.expr)
        node = binding.value(parameter) if binding is not None else None
        if node is None:
            return ZERO if function == "every" else None
        found = self._value(node, scope, f"{name}.delay", where, text)
        if found is None:
            return None
        delay, says = found
        self.out.track(says, where, text)
        return if_then(compare(">=", delay, ZERO), delay, ZERO)  # a negative one occurs at once

    # ---- phases

    def build(self) -> Phase | None:
        """The phases of the scenario's ``do`` (None when it has none)."""
        do = scenario_do(self.model, self.lw.member_decls, self.scenario)
        if do is None:
            return None
        actor = "actor" if self.scenario.actor else None
        scope = InstanceScope("", self.scenario, "", self.scenario, actor=actor)
        self.expanding.append(self.scenario)
        return self._member(do.member, scope, at_time(ZERO), 0)

    def _member(self, member: ast.DoMember, scope: InstanceScope, start: Time, depth: int) -> Phase:
        body = member.body
        phase: Phase
        match body:
            case ast.Composition():
                phase = self._composition(body, scope, start, depth)
            case ast.Invocation():
                phase = self._invocation(body, member.label, scope, start, depth)
            case ast.Wait():
                phase = self._wait(body, scope, start)
            case _:
                name = join_path(scope.prefix, f"{type(body).__name__.lower()}@{_where(body.span)}")
                phase = Leaf(name=name, span=body.span, start=start, end=start)  # emit, call
        phase.keys.append((scope.prefix, body.span))  # the runner's name of the phase
        return phase

    def _wait(self, wait: ast.Wait, scope: InstanceScope, start: Time) -> Leaf:
        name = join_path(scope.prefix, f"wait@{_where(wait.span)}")
        text = self.lw.text_of(wait.span)
        delay = self._delay(wait.event, scope, name, wait.span, text)
        end = after(start, delay) if delay is not None else self.out.after(start, name, wait.span)
        return Leaf(name=name, span=wait.span, start=start, end=end)

    def _unmodelled(self, name: str, span: Span, start: Time) -> Leaf:
        """A phase whose timing is not modelled: it may end at any time, or never, and
        be stopped at any time."""
        end = self.out.after(start, name, span, may_never=True)
        return Leaf(name=name, span=span, start=start, end=end, endless=True, opens=True)

    def _composition(
        self, comp: ast.Composition, scope: InstanceScope, start: Time, depth: int
    ) -> Phase:
        name = join_path(scope.prefix, f"{comp.op}@{_where(comp.span)}")
        binding = self.model.binding(comp)
        duration = binding.extra("duration") if binding is not None else None
        overlap = binding.extra("overlap") if binding is not None else None
        offsets = [
            b
            for b in (binding.extras if binding is not None else ())
            if b.name in ("start_to_start", "end_to_end")
        ]
        kind = _overlap_kind(overlap.value) if overlap is not None else "start"
        untils = [w for w in comp.with_members if isinstance(w, ast.Until)]
        core: Phase
        if offsets or kind is None:
            for arg in offsets:
                self.lw.problem.skip(
                    arg.span,
                    f"parallel({self.lw.text_of(arg.span)})",
                    "offsets between the members' starts or ends are not in the timing model",
                )
            core = self._unmodelled(name, comp.span, start)
        elif comp.op == "serial":
            members: list[Phase] = []
            at = start
            for m in comp.members:
                phase = self._member(m, scope, at, depth)
                members.append(phase)
                at = phase.end
            core = Sequence(name=name, span=comp.span, start=start, end=at, members=members)
        elif comp.op == "parallel":
            core = self._together(comp, kind, overlap, scope, start, depth, name)
        else:
            core = self._choice(comp, scope, start, depth, name)
        return self._wrap(core, comp.span, duration, untils, scope, comp.op, name)

    def _together(
        self,
        comp: ast.Composition,
        kind: str,
        overlap: BoundArgument | None,
        scope: InstanceScope,
        start: Time,
        depth: int,
        name: str,
    ) -> Together:
        mark = self.out.mark()
        members = [self._member(m, scope, start, depth) for m in comp.members]
        delays = self._delays(kind, members)
        if any(not holds_as(compare("==", d, ZERO), True) for d in delays):
            self.out.undo(mark)  # built again, each member at its own start
            self.resolver.forget()
            members = [
                self._member(m, scope, Time(start.finite, plus(start.at, d)), depth)
                for m, d in zip(comp.members, delays, strict=True)
            ]
        first_ends = kind in ENDS_WITH_FIRST
        joined = self._joined(members, name, comp.span) if members else start
        end = joined
        if first_ends and members:
            end = earliest(members[0].end, joined)
        where = overlap.span if overlap is not None else comp.span
        text = f"parallel({self.lw.text_of(overlap.span)})" if overlap is not None else "parallel"
        return Together(
            name=name,
            span=comp.span,
            start=start,
            end=self.out.bind(end, name, comp.span),
            members=members,
            first_ends=first_ends,
            joined=joined,
            where=where,
            text=text,
            delays=delays,
            kind=kind,
            lengths=[self.resolver.length(m) for m in members],
        )

    def _delays(self, kind: str, members: list[Phase]) -> list[ir.Term]:
        """How long after the composition each member starts: with ``overlap: end`` the
        members of known length end together (the longest starts first), with ``final``
        they end with the first member (which starts first); otherwise all at once."""
        zero: list[ir.Term] = [ZERO] * len(members)
        if kind not in STARTS_PLANNED or len(members) < 2:
            return zero
        lengths = [self.resolver.length(m) for m in members]
        first = lengths[0]
        if first is None:
            return zero  # the first member's end is not known before it comes
        end = first
        if kind == "end":
            for length in lengths[1:]:
                if length is not None:
                    end = if_then(compare(">=", end, length), end, length)
        delays: list[ir.Term] = []
        for length in lengths:
            if length is None:
                delays.append(ZERO)
                continue
            delay = ir.minus(end, length)
            delays.append(if_then(compare(">=", delay, ZERO), delay, ZERO))
        return delays

    def _joined(self, members: list[Phase], name: str, span: Span) -> Time:
        """When a ``parallel`` ends by joining: the first time at which one member has
        ended and each other has ended or is open-ended."""
        froms = [open_from(m) for m in members]
        ends = [m.end for m in members]
        if all(f is not None for f in froms):
            ready = latest_of(
                [earliest(m.end, f) for m, f in zip(members, froms, strict=True) if f is not None]
            )
            return self.out.bind(latest(earliest_of(ends), ready), f"{name}.joined", span)
        # an open-ended member may go on after it: the end is one of the times that qualify
        last = latest_of(ends)
        t = Time(
            self.out.unknown(f"{name}.joined.ends", "bool", span, last.finite),
            self.out.unknown(f"{name}.joined.at", "real", span, last.at),
        )
        qualifies = all_of(
            no_later(earliest_of(ends), t),
            no_later(t, last),
            *(any_of(no_later(m.end, t), open_now(m, t)) for m in members),
        )
        self.out.rule(qualifies, span, f"{name} joins")
        return t

    def _choice(
        self, comp: ast.Composition, scope: InstanceScope, start: Time, depth: int, name: str
    ) -> Choice:
        acting: list[Phase] = []
        waiting: list[Phase] = []
        for m in comp.members:
            (acting if is_acting(m.body) else waiting).append(self._member(m, scope, start, depth))
        chosen: list[ir.Term] = [TRUE] * len(acting)
        if len(acting) > 1:
            shared = one_of_variable(scope.prefix, comp)  # the placement's too
            self.out.variables[shared.name] = shared
            self.out.canonical[shared.name] = ZERO
            choice: ir.Term = ir.Ref(shared)
            self.out.rule(
                all_of(compare(">=", choice, ZERO), compare("<", choice, ir.const(len(acting)))),
                comp.span,
                f"{name} chooses one member",
            )
            chosen = [compare("==", choice, ir.const(j)) for j in range(len(acting))]
        chosen_end = acting[-1].end if acting else NEVER
        for c, a in zip(reversed(chosen[:-1]), reversed(acting[:-1]), strict=True):
            chosen_end = either(c, a.end, chosen_end)
        if acting:
            chosen_end = self.out.bind(chosen_end, f"{name}.chosen_end", comp.span)
        ends = ([chosen_end] if acting else []) + [w.end for w in waiting]
        end = earliest_of(ends) if ends else start
        return Choice(
            name=name,
            span=comp.span,
            start=start,
            end=self.out.bind(end, name, comp.span),
            acting=acting,
            waiting=waiting,
            chosen=chosen,
            chosen_end=chosen_end,
        )

    def _invocation(
        self,
        inv: ast.Invocation,
        label: ast.Name | None,
        scope: InstanceScope,
        start: Time,
        depth: int,
    ) -> Phase:
        found = self.lw.instance_scope(inv, scope, label)
        name = join_path(scope.prefix, f"{inv.name.text}@{_where(inv.span)}")
        if found is None:
            return self._unmodelled(name, inv.span, start)
        behaviour, inner = found
        name = inner.prefix
        binding = self.model.binding(inv)
        duration = binding.extra("duration") if binding is not None else None
        untils = [w for w in inv.with_members if isinstance(w, ast.Until)]
        core: Phase
        if behaviour.kind is SymbolKind.SCENARIO:
            do = scenario_do(self.model, self.lw.member_decls, behaviour)
            if behaviour in self.expanding or depth >= MAX_DEPTH or behaviour.library:
                core = self._unmodelled(name, inv.span, start)
            elif do is None:
                core = Leaf(name=name, span=inv.span, start=start, end=start)
            else:
                self.expanding.append(behaviour)
                try:
                    core = self._member(do.member, inner, start, depth + 1)
                finally:
                    self.expanding.pop()
        elif behaviour.kind is SymbolKind.ACTION:
            core = self._action(inv, behaviour, start, name, duration is not None, bool(untils))
        else:
            core = self._unmodelled(name, inv.span, start)
        callee = inv.name.text
        if inv.actor is not None:
            callee = f"{self.lw.text_of(inv.actor.span)}.{callee}"
        return self._wrap(core, inv.span, duration, untils, scope, callee, name)

    def _given(self, call: ast.Node) -> dict[str, ast.Expr]:
        """The arguments given to ``call`` by parameter, as the checker bound them."""
        binding = self.model.binding(call)
        return binding.values(defaults=False) if binding is not None else {}

    def _action(
        self,
        inv: ast.Invocation,
        action: Symbol,
        start: Time,
        name: str,
        bounded: bool,
        until: bool,
    ) -> Leaf:
        if action.name in INSTANT_ACTIONS:
            return Leaf(name=name, span=inv.span, start=start, end=start)
        if action.name not in ENDLESS_ACTIONS:  # it ends when its goal is reached
            end = self.out.after(start, name, inv.span)
            return Leaf(name=name, span=inv.span, start=start, end=end)
        ends_phase = any(
            isinstance(m, ast.Invocation)
            and (m.name.text in PHASE_ENDING_MODIFIERS or modifier_timing(self._given(m)) == "end")
            for m in inv.with_members
        )
        end = self.out.after(start, name, inv.span, may_never=True) if ends_phase else NEVER
        opens = not bounded and not until
        return Leaf(name=name, span=inv.span, start=start, end=end, endless=True, opens=opens)

    def _wrap(
        self,
        core: Phase,
        span: Span,
        duration: BoundArgument | None,
        untils: list[ast.Until],
        scope: InstanceScope,
        callee: str,
        name: str,
    ) -> Phase:
        """``core`` bounded by its ``duration`` (innermost) and ended by its ``until``s, as
        the runner wraps it."""
        phase = core
        start = core.start
        bounds = self._duration(duration, scope, callee, name) if duration is not None else None
        if bounds is not None and duration is not None:
            low, high, values, text = bounds
            last = after(start, high)
            if low is high:  # one value: the phase ends then, on time or stopped
                end = Time(start.finite, last.at)
            else:
                within = no_later(core.end, last)
                held = latest(core.end, after(start, low))
                end = Time(start.finite, if_then(within, held.at, last.at))
            phase = Bounded(
                name=name,
                span=span,
                start=start,
                end=self.out.bind(end, f"{name}.bounded", span),
                child=core,
                low=low,
                high=high,
                values=values,
                where=duration.span,
                text=text,
            )
        for until in untils:
            text = self.lw.text_of(until.span)
            delay = self._delay(until.event, scope, f"{name}.until", until.span, text)
            event = (
                after(start, delay)
                if delay is not None
                else self.out.after(start, f"{name}.until", until.span)
            )
            phase = UntilEvent(
                name=name,
                span=span,
                start=start,
                end=self.out.bind(earliest(phase.end, event), f"{name}.until", until.span),
                child=phase,
                event=event,
            )
        return phase

    # ---- what must hold

    def require(self, phase: Phase, active: ir.Term, free: Time, checked: Time) -> None:
        """Add what ``phase`` needs to run without failing: ``active`` when it runs at all;
        ``free`` and ``checked``: when something around it stops it, without a check
        (``one_of``, ``until``) or with one (a duration, a ``parallel``)."""
        match phase:
            case Bounded():
                last = after(phase.start, phase.high)
                child = phase.child
                stoppable = any_of(
                    no_later(child.end, last),
                    endless(child, last, True),
                    endless(child, last, False),
                )
                due = _guard(last, phase.start, active, free, checked)
                self.out.track(
                    all_of(phase.values, implies(due, stoppable)), phase.where, phase.text
                )
                self.require(child, active, free, earliest(checked, last))
            case UntilEvent():
                self.require(phase.child, active, earliest(free, phase.event), checked)
            case Sequence():
                for m in phase.members:
                    self.require(m, active, free, checked)
            case Together():
                inner = earliest(checked, phase.end)
                for m in phase.members:
                    self.require(m, active, free, inner)
                if phase.first_ends and len(phase.members) > 1:
                    first = phase.members[0].end
                    others = phase.members[1:]
                    ended = all_of(
                        *(any_of(no_later(m.end, first), endless(m, first, False)) for m in others)
                    )
                    due = all_of(
                        _guard(first, phase.start, active, free, checked),
                        no_later(first, phase.joined),
                    )
                    self.out.track(implies(due, ended), phase.where, phase.text)
                self._not_before_first(phase, active, free, checked)
            case Choice():
                waiting_ends = [w.end for w in phase.waiting]
                for c, a in zip(phase.chosen, phase.acting, strict=True):
                    self.require(
                        a, all_of(active, c), earliest(free, earliest_of(waiting_ends)), checked
                    )
                for k, w in enumerate(phase.waiting):
                    rivals = waiting_ends[:k] + waiting_ends[k + 1 :]
                    if phase.acting:
                        rivals.append(phase.chosen_end)
                    self.require(w, active, earliest(free, earliest_of(rivals)), checked)

    def _not_before_first(
        self, phase: Together, active: ir.Term, free: Time, checked: Time
    ) -> None:
        """``equal`` and ``full``: a member of known length ends no earlier than the first
        member (of known length) ends; a shorter one cannot (a fixed length cannot be
        held, unlike a goal reached early)."""
        first = phase.lengths[0] if phase.lengths else None
        if phase.kind not in NOT_BEFORE_FIRST or first is None:
            return
        for member, length in zip(phase.members[1:], phase.lengths[1:], strict=True):
            if length is None:
                continue
            due = _guard(member.end, phase.start, active, free, checked)
            self.out.track(implies(due, compare(">=", length, first)), phase.where, phase.text)


def _guard(t: Time, owner_start: Time, active: ir.Term, free: Time, checked: Time) -> ir.Term:
    """Whether a check due at ``t`` happens: its phase runs and is not stopped before
    ``t`` (by a stop without a check, or strictly before ``t`` by one with a check; a
    stop with a check at ``t`` itself leaves checks of phases begun at ``t`` undone)."""
    return all_of(
        active,
        t.finite,
        before(t, free),
        any_of(before(t, checked), all_of(same_time(t, checked), before(owner_start, t))),
    )


def _overlap_kind(node: ast.Node) -> str | None:
    word = enum_word(node)
    return word if word in OVERLAP_KINDS else None


def _where(span: Span) -> str:
    return f"{span.line}:{span.column}"


def _model(lowerer: Lowerer, scenario: Symbol, symbolic: bool) -> _Builder | None:
    builder = _Builder(lowerer, scenario, symbolic)
    root = builder.build()
    if root is None:
        return None
    builder.require(root, TRUE, NEVER, NEVER)
    builder.root = root
    return builder


def _plan(builder: _Builder | None) -> TimingPlan | None:
    if builder is None or builder.root is None:
        return None
    return TimingPlan.of(builder.root, builder.resolver)


def timing_plan(lowerer: Lowerer, scenario: Symbol) -> TimingPlan | None:
    """The timing model of ``scenario`` kept for the schedule of its runs
    (``verify.schedule``): with constant durations folded in when they are all constant."""
    try:
        return _plan(_model(lowerer, scenario, symbolic=False))
    except _NotConstant:
        return _plan(_model(lowerer, scenario, symbolic=True))


def lower_timing(lowerer: Lowerer, scenario: Symbol) -> None:
    """Add the timing of ``scenario``'s behaviour to the lowerer's problem, where it can
    matter: when a duration names a parameter, or when the timing cannot obviously be
    kept (see the module docstring)."""
    problem = lowerer.problem
    try:
        folded = _model(lowerer, scenario, symbolic=False)
    except _NotConstant:
        folded = None
    else:
        problem.timing = _plan(folded)
        if folded is None or not folded.out.tracked or folded.out.holds_canonically():
            return
    built = _model(lowerer, scenario, symbolic=True)
    if problem.timing is None:
        problem.timing = _plan(built)
    if built is None or not built.out.tracked:
        return
    for var in built.out.variables.values():
        problem.variables[var.name] = var
    for c in (*built.out.definitions, *built.out.tracked):
        problem.add(c)
