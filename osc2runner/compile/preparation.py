"""Bringing about an ``at: start`` of a phase that begins after time 0 (§8.9), and the
choice of the member a ``one_of`` runs (§7.6.2).

A phase's ``at: start`` constraint holds when the phase starts. At time 0 the
checker's witness places the actors so; for a later phase the runner plans the
phase before it so that the actor gets there (docs/runner.md, "Modifier
timing"):

* In a ``serial``, when a member starts actions with ``speed``, ``lane`` or
  ``position(..., ahead_of|behind: ...)`` modifiers ``at: start`` (directly, or
  as the first invocations of a ``parallel``/``serial``/``one_of`` member), and
  the member before it ends with an action of the same actor (itself, the last of
  a ``serial``, one of a ``parallel``, the chosen ``one_of`` member's) that can
  carry the target (a vehicle's, whose ``ActionBehaviour.own_motions`` is set:
  ``drive()``, ``change_speed``, ``change_lane``, ...) and does not drive that
  motion itself (neither by its own nature nor by a modifier of its own acting
  there), that action takes the constraint as a target for its end: planned
  against its deadline (the schedule's, less the margin) like an ``at: end``, or
  reached at the usual rate when the deadline is not known, an action that
  reaches its own goal first then running on until it holds
  (:data:`PREPARATION_WAIT` at most). It is not checked there: the next phase
  checks it when it starts, with the tolerances, and fails saying by how much
  when physics did not allow it.
* When the member before is a ``wait``, nothing of the scenario commands the
  vehicles while it runs: the wait runs a ``drive()`` of each vehicle whose
  action starts next with such targets (:class:`Preparing`, planned against the
  wait's end when the schedule knows it, else reached at the usual rate and held),
  stopped when the wait ends.
* A previous action that drives the same motion itself (``change_speed`` before
  ``speed(v, at: start)``) has the scenario's end state for it: the start is
  checked only, and fails with the measured value when the two differ.
* A ``one_of`` whose members start there is chosen first (:class:`Choices`):
  drawn with the run's seed among the members whose every ``at: start`` the
  previous phase brings about (all of them when none is), and the chosen
  member's starts are brought about as a serial member's.
"""

from __future__ import annotations

import zlib
from collections.abc import Mapping
from typing import Any

import numpy as np

from osc2check.semantics.constants import NotConstant, evaluate
from osc2check.semantics.model import Model
from osc2check.semantics.phases import TimeZero, acting_members, enum_word, time_zero
from osc2check.syntax import ast
from osc2check.syntax.walk import walk
from osc2runner.behaviours.base import ActionBehaviour, ActionUse, Modifier
from osc2runner.behaviours.motion import Drive
from osc2runner.compile.composites import OneOf
from osc2runner.compile.conditions import Wait

__all__ = [
    "PREPARATION_WAIT",
    "PREPARED_MODIFIERS",
    "Choices",
    "Preparing",
    "drop_concurrent_preparations",
    "prepare_starts",
]

#: the ``at: start`` modifiers a previous phase brings about
PREPARED_MODIFIERS = frozenset({"speed", "lane", "position"})
_MOTIONS = ("longitudinal", "lateral")
#: how long (s) an action that reached its own goal runs on for the next start at most:
#: the longest change a start asks at the usual rates (0 to 130 kph at 2.5 m/s², 14.4 s)
PREPARATION_WAIT = 15.0

Uses = Mapping[ast.Invocation, tuple[ActionUse, type]]


class Preparing(Modifier):
    """The next phase's ``at: start`` modifier, realised in this phase as an ``at: end``
    target and never checked here (the next phase checks it when it starts)."""

    def __init__(self, inner: Modifier) -> None:
        super().__init__(inner.use)
        self.inner = inner
        self.longitudinal = inner.longitudinal
        self.lateral = inner.lateral

    def evaluate(self) -> dict[str, Any]:
        self.args = self.inner.evaluate()
        self.inner.at = "end"
        self.at = "prepare"  # neither checked at this phase's start nor at its end
        return self.args

    def begin(self, action: ActionBehaviour) -> None:
        self.waiting_since: float | None = None
        self.inner.realise(action)

    def step(self, action: ActionBehaviour) -> None:
        self.inner.step(action)

    def pending(self, action: ActionBehaviour) -> bool:
        # without a deadline an action that reached its own goal (a change_speed at its
        # speed) runs on until the next phase's start holds, for PREPARATION_WAIT at
        # most (then the next phase says what does not hold); with a deadline, the plan
        # arrives by then and the next phase checks it
        if action.remaining() is not None or self.inner.holds(action) is None:
            return False
        if self.waiting_since is None:
            self.waiting_since = action.elapsed
        return action.elapsed - self.waiting_since < PREPARATION_WAIT

    def end(self, action: ActionBehaviour) -> None:
        self.inner.end(action)


class Choices:
    """Which acting member each ``one_of`` runs: the compiled plan's one record of it.

    The witness's choice when it made one (it placed the actors for it at time 0),
    else drawn with the run's seed (one generator per ``one_of``, named by its
    instance path, so that one choice never shifts another): by :func:`prepare_starts`
    for a ``one_of`` that starts after a previous phase, preferring the members
    that phase can prepare; by :meth:`finish` for the others. The ``OneOf``
    behaviour runs the member recorded here."""

    def __init__(self, seed: int) -> None:
        self.seed = seed
        self.made: dict[str, int] = {}  # the record: one_of name -> acting member index
        self._nodes: list[tuple[str, OneOf]] = []
        self._latest: dict[ast.Composition, tuple[str, OneOf]] = {}

    def add(self, comp: ast.Composition, name: str, node: OneOf, witness: int | None) -> None:
        """A compiled ``one_of`` (``name``: its instance's variable name)."""
        self._nodes.append((name, node))
        self._latest[comp] = (name, node)
        if witness is not None:
            self._set(name, node, witness)

    def __contains__(self, comp: object) -> bool:
        return comp in self._latest

    def get(self, comp: ast.Composition) -> int | None:
        """The member chosen for the last compiled instance of ``comp``, if chosen yet."""
        found = self._latest.get(comp)
        return self.made.get(found[0]) if found is not None else None

    def choose(self, comp: ast.Composition, ready: list[bool]) -> int:
        """Draw the member of ``comp`` among the ``ready`` ones (all when none is)."""
        name, node = self._latest[comp]
        pool = [i for i, ok in enumerate(ready) if ok] or list(range(len(ready)))
        index = pool[self._draw(name, len(pool))]
        self._set(name, node, index)
        return index

    def finish(self) -> dict[str, int]:
        """Draw every choice not made yet; returns the record."""
        for name, node in self._nodes:
            if name not in self.made and any(node.acting):
                self._set(name, node, self._draw(name, sum(node.acting)))
        return self.made

    def _draw(self, name: str, count: int) -> int:
        entropy = [self.seed % 2**63, zlib.crc32(name.encode())]
        return int(np.random.default_rng(entropy).integers(count))

    def _set(self, name: str, node: OneOf, index: int) -> None:
        self.made[name] = index
        node.choice = index


def _at(modifier: Modifier) -> str:
    node = modifier.use.given("at")
    return (enum_word(node) or "all") if node is not None else "all"


def _last_invocations(body: ast.Node, choices: Choices) -> list[ast.Invocation]:
    """The invocations running when ``body`` ends: itself, a ``serial``'s last member's,
    each ``parallel`` member's, the chosen ``one_of`` member's."""
    match body:
        case ast.Invocation():
            return [body]
        case ast.Composition(op="serial") if body.members:
            return _last_invocations(body.members[-1].body, choices)
        case ast.Composition(op="parallel"):
            return [inv for m in body.members for inv in _last_invocations(m.body, choices)]
        case ast.Composition(op="one_of") if body in choices:
            members = acting_members(body)
            index = choices.get(body)
            if index is None:  # not chosen yet: the same draw as Choices.finish
                index = choices.choose(body, [True] * len(members))
            return _last_invocations(members[index].body, choices)
    return []


def prepare_starts(
    comp: ast.Composition,
    uses: Uses,
    waits: Mapping[ast.Wait, Wait],
    choices: Choices,
    model: Model,
) -> None:
    """Choose the ``one_of`` members that start after each member of ``comp`` (a
    ``serial``), and give the actions that end each member the ``at: start`` targets
    of the next, or a ``wait`` member a drive of the vehicles that need them (see the
    module docstring)."""
    bodies = [m.body for m in comp.members]
    for before, after in zip(bodies, bodies[1:], strict=False):
        zero = time_zero(after)
        if isinstance(before, ast.Wait) and before in waits:
            _choose(zero, [], uses, choices, model)  # (any member: the wait commands none)
            _prepare_during(waits[before], _started(zero, choices), uses)
            continue
        previous = [
            found[0]
            for inv in _last_invocations(before, choices)
            if (found := uses.get(inv)) is not None and _carries(found[0])
        ]
        _choose(zero, previous, uses, choices, model)
        for inv in _started(zero, choices):
            following = uses.get(inv)
            if following is None or _realised(following[0]):
                continue
            for modifier in following[0].modifiers:
                use = _preparer(modifier, following[0], previous)
                if use is not None:
                    use.modifiers.append(Preparing(type(modifier)(modifier.use)))


class _PreparingUse(ActionUse):
    """The drive the runner gives a vehicle during a ``wait``, logged as the actor's
    ``preparing@line`` (the line of the action whose start it brings about)."""

    @property
    def label(self) -> str:
        return f"{self.actor.name}.preparing@{self.node.span.line}"


def _prepare_during(wait: Wait, started: list[ast.Invocation], uses: Uses) -> None:
    """Give ``wait`` a ``drive()`` of each vehicle whose action starts after it with
    ``at: start`` targets: nothing of the scenario commands it while the wait runs, so
    it is driven there as a ``drive()`` with those targets would be (planned against
    the wait's end when the schedule knows it)."""
    drives: dict[str, ActionUse] = {}
    for inv in started:
        found = uses.get(inv)
        if found is None or _realised(found[0]) or found[0].actor.kind != "vehicle":
            continue
        following = found[0]
        for modifier in following.modifiers:
            if not _preparable(modifier):
                continue
            use = drives.get(following.actor.name)
            if use is None:
                use = _PreparingUse(
                    following.node, following.symbol, following.actor, {}, plan=wait.plan
                )
                use.behaviour = Drive
                drives[following.actor.name] = use
            use.modifiers.append(Preparing(type(modifier)(modifier.use)))
    wait.companions.extend(Drive(f"{name}.drive() (preparing)", u) for name, u in drives.items())


def drop_concurrent_preparations(
    comp: ast.Composition, uses: Uses, waits: Mapping[ast.Wait, Wait]
) -> None:
    """Take back the drives a ``wait`` inside a member of ``comp`` (a ``parallel``) was
    given for a vehicle that an action in another member commands meanwhile: the
    scenario commands it there, and the two would compete (its end state is that
    action's to say, and the start is checked only)."""
    actors = [_acting_actors(m.body, uses) for m in comp.members]
    for k, member in enumerate(comp.members):
        others = set().union(*(a for j, a in enumerate(actors) if j != k))
        if not others:
            continue
        for node in walk(member.body):
            wait = waits.get(node) if isinstance(node, ast.Wait) else None
            if wait is not None:
                wait.companions[:] = [
                    c
                    for c in wait.companions
                    if not (isinstance(c, ActionBehaviour) and c.use.actor.name in others)
                ]


def _acting_actors(body: ast.Node, uses: Uses) -> set[str]:
    """The names of the actors of the actions invoked in ``body``."""
    return {
        found[0].actor.name
        for node in walk(body)
        if isinstance(node, ast.Invocation) and (found := uses.get(node)) is not None
    }


def _carries(use: ActionUse) -> bool:
    """Whether ``use`` can bring about a next start (a vehicle's: persons' and objects'
    controllers carry no such target yet)."""
    return use.actor.kind == "vehicle" and _own_motions(use) is not None


def _realised(use: ActionUse) -> bool:
    # an action that realises its modifiers itself (assign_position) puts the actor
    # there; nothing before it need bring it about
    return use.behaviour is not None and use.behaviour.modifiers_realised


def _own_motions(use: ActionUse) -> frozenset[str] | None:
    """The motions the action drives itself while it can bring about a next start."""
    return use.behaviour.own_motions if use.behaviour is not None else None


def _started(zero: TimeZero, choices: Choices) -> list[ast.Invocation]:
    """The invocations that start with the phase: its own, and the chosen members'."""
    chosen = [inv for guard, inv in zero.options if all(choices.get(c) == i for c, i in guard)]
    return [*zero.starts, *chosen]


def _choose(
    zero: TimeZero, previous: list[ActionUse], uses: Uses, choices: Choices, model: Model
) -> None:
    """Choose each ``one_of`` starting with the phase (outer ones first), preferring the
    members whose every ``at: start`` the ``previous`` actions bring about or hold."""
    for guard, _ in zero.options:
        for comp, _ in guard:
            if comp not in choices or choices.get(comp) is not None:
                continue  # (a one_of the runner refused is not chosen)
            ready = []
            for index in range(len(acting_members(comp))):
                invs = [
                    inv
                    for g, inv in zero.options
                    if (comp, index) in g
                    and all(choices.get(c) in (None, i) for c, i in g if c is not comp)
                ]
                ready.append(all(_ready(uses.get(inv), previous, model) for inv in invs))
            choices.choose(comp, ready)


def _ready(found: tuple[ActionUse, type] | None, previous: list[ActionUse], model: Model) -> bool:
    """Whether every ``at: start`` of an invocation holds by the ``previous`` actions'
    doing (or is the action's own to realise)."""
    if found is None or _realised(found[0]):
        return True
    use = found[0]
    return all(
        _preparer(m, use, previous) is not None or _held(m, use, previous, model)
        for m in use.modifiers
        if _at(m) == "start"
    )


def _held(
    modifier: Modifier, following: ActionUse, previous: list[ActionUse], model: Model
) -> bool:
    """Whether a ``previous`` action of the same actor ends holding ``modifier`` (``at:
    start`` of ``following``) already: it has a modifier of the same name, ``at: all`` or
    ``at: end``, whose other arguments are the same constants (``lane(1)`` then
    ``lane(1, at: start)``)."""
    wanted = _constant_arguments(modifier, model)
    if wanted is None:
        return False
    return any(
        use.actor is following.actor
        and m.use.name == modifier.use.name
        and _at(m) in ("all", "end")
        and _constant_arguments(m, model) == wanted
        for use in previous
        for m in use.modifiers
    )


def _constant_arguments(modifier: Modifier, model: Model) -> dict[str, object] | None:
    """The exact values of a modifier's arguments other than ``at`` (defaults included);
    None when one is not a constant."""
    binding = modifier.use.binding
    if binding is None:
        return None
    try:
        return {
            name: evaluate(expr, model) for name, expr in binding.values().items() if name != "at"
        }
    except NotConstant:
        return None


def _preparable(modifier: Modifier) -> bool:
    """Whether ``modifier`` is an ``at: start`` a previous phase can bring about."""
    if modifier.use.name not in PREPARED_MODIFIERS or _at(modifier) != "start":
        return False
    relative = any(modifier.use.given(k) is not None for k in ("ahead_of", "behind"))
    # a place on the road, not a gap: only a start can put the actor there
    return modifier.use.name != "position" or relative


def _preparer(
    modifier: Modifier, following: ActionUse, previous: list[ActionUse]
) -> ActionUse | None:
    """The previous action that brings about ``modifier`` (``at: start`` of
    ``following``), or None when none can (it is checked only)."""
    if not _preparable(modifier):
        return None
    channels = {c for c in _MOTIONS if getattr(modifier, c)}
    for use in previous:
        if use.actor is not following.actor:
            continue
        own = set(_own_motions(use) or ())
        busy = own & channels or any(
            getattr(m, c) and (isinstance(m, Preparing) or _at(m) != "start")
            for m in use.modifiers
            for c in channels
        )
        return None if busy else use
    return None
