"""Bringing about an ``at: start`` of a phase that begins after time 0 (§8.9).

A phase's ``at: start`` constraint holds when the phase starts. At time 0 the
checker's witness places the actors so; for a later phase the runner plans the
phase before it so that the actor gets there (docs/runner.md, "Modifier
timing"):

* In a ``serial``, when a member starts actions with ``speed``, ``lane`` or
  ``position(..., ahead_of|behind: ...)`` modifiers ``at: start`` (directly, or
  as the first invocations of a ``parallel``/``serial`` member), and the member
  before it is a ``drive()`` of the same actor that does not itself drive that
  motion (no ``speed``/``lane``/... modifier of its own acting there), that
  ``drive()`` takes the constraint as a target for its end: planned against its
  deadline (the schedule's, less the margin) like an ``at: end``, or reached at
  the usual rate and held when the deadline is not known. It is not checked
  there: the next phase checks it when it starts, with the tolerances, and
  fails saying by how much when physics did not allow it.
* Anything else (a previous phase that drives the same motion itself, another
  action, a ``one_of`` member) is checked only, as before; an action that
  realises its modifiers itself (``assign_position``) puts the actor there.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from osc2check.semantics.phases import enum_word, time_zero
from osc2check.syntax import ast
from osc2runner.behaviours.base import ActionBehaviour, ActionUse, Modifier

__all__ = ["PREPARED_MODIFIERS", "Preparing", "prepare_starts"]

#: the ``at: start`` modifiers a previous phase brings about
PREPARED_MODIFIERS = frozenset({"speed", "lane", "position"})
#: the actions that may bring them about: they drive the actor as modifiers say
_PREPARING_ACTIONS = frozenset({"drive"})


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
        self.inner.realise(action)

    def step(self, action: ActionBehaviour) -> None:
        self.inner.step(action)

    def end(self, action: ActionBehaviour) -> None:
        self.inner.end(action)


def _at(modifier: Modifier) -> str:
    node = modifier.use.given("at")
    return (enum_word(node) or "all") if node is not None else "all"


def _last_invocations(body: ast.Node) -> list[ast.Invocation]:
    """The invocations running when ``body`` ends (itself, or a ``parallel``'s)."""
    if isinstance(body, ast.Invocation):
        return [body]
    if isinstance(body, ast.Composition) and body.op == "parallel":
        return [m.body for m in body.members if isinstance(m.body, ast.Invocation)]
    return []


def prepare_starts(
    comp: ast.Composition, uses: Mapping[ast.Invocation, tuple[ActionUse, type]]
) -> None:
    """Give each ``drive()`` of ``comp`` (a ``serial``) the ``at: start`` targets of the
    member after it (see the module docstring)."""
    bodies = [m.body for m in comp.members]
    for before, after in zip(bodies, bodies[1:], strict=False):
        nexts = [uses[inv][0] for inv in time_zero(after).starts if inv in uses]
        for inv in _last_invocations(before):
            found = uses.get(inv)
            if found is None or found[0].symbol.name not in _PREPARING_ACTIONS:
                continue
            use = found[0]
            for following in nexts:
                # an action that realises its modifiers itself (assign_position) puts the
                # actor there; nothing before it need bring it about
                realised = getattr(following.behaviour, "modifiers_realised", False)
                if following.actor is use.actor and not realised:
                    _prepare(use, following)


def _prepare(use: ActionUse, following: ActionUse) -> None:
    for modifier in following.modifiers:
        if modifier.use.name not in PREPARED_MODIFIERS or _at(modifier) != "start":
            continue
        relative = any(modifier.use.given(k) is not None for k in ("ahead_of", "behind"))
        if modifier.use.name == "position" and not relative:
            continue  # a place on the road, not a gap: only a start can put the actor there
        busy = any(
            (m.longitudinal and modifier.longitudinal) or (m.lateral and modifier.lateral)
            for m in use.modifiers
            if isinstance(m, Preparing) or _at(m) != "start"
        )
        if not busy:
            use.modifiers.append(Preparing(type(modifier)(modifier.use)))
