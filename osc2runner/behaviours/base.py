"""Base classes of the registered leaves: actions and the modifiers that constrain them.

An :class:`ActionBehaviour` is one action invocation (``hero.drive() with:
...``). The compiler hands it an :class:`ActionUse`: the actor, the argument
closures (evaluated when the action starts), the modifier objects of its
``with:`` block and the phase duration. Lifecycle:

* ``initialise`` (the phase starts): arguments are evaluated, then
  :meth:`ActionBehaviour.start` sets the actor's controller targets, then
  each modifier's :meth:`Modifier.begin` constrains them;
* ``update`` (every tick): each modifier's :meth:`Modifier.step`, then
  :meth:`ActionBehaviour.step` decides the status;
* ``terminate``: the action's end is logged; controller targets persist.

A :class:`Modifier` is a constraint on the controllers of its action's actor.
``at`` says when it applies: ``start`` (realised by the scenario initializer
for phases that start the scenario, else applied when the phase starts),
``end`` (reached by the end of the phase), ``all`` (held throughout).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, SupportsFloat, SupportsInt

import py_trees
from py_trees.common import Status

from osc2check.semantics.bindings import Binding, ReadArguments, note_started
from osc2check.semantics.symbols import Symbol
from osc2check.syntax import ast
from osc2check.verify.schedule import PhasePlan
from osc2check.verify.timeline import PhaseKey
from osc2runner.compile.expressions import Closure
from osc2runner.execution.context import RunContext, ended_kind
from osc2runner.execution.controls import Controller
from osc2runner.instance.actors import Actor

if TYPE_CHECKING:
    from osc2runner.sim import ActorState

__all__ = [
    "FastLeaf",
    "ActionBehaviour",
    "ActionUse",
    "AssignedPose",
    "InstantAction",
    "Modifier",
    "ModifierUse",
    "ScenarioBehaviour",
    "items",
    "number",
    "whole",
]

#: A behaviour's arguments by parameter name. A value is whatever its expression
#: gives at run time (a number, an enum member's name, an Actor, a struct value of
#: ``osc2runner.structs``, a map element, a list as a tuple, or what a plug-in's method
#: returns), so a behaviour reads it through a test of its kind (``isinstance``, or
#: :func:`number` and :func:`whole`, which ask for the ``SupportsFloat`` and
#: ``SupportsInt`` protocols).
Arguments = dict[str, object]


def number(value: object) -> float:
    """An argument that is a number, as a float (TypeError for another value, as ``float``)."""
    if isinstance(value, float):
        return value
    if isinstance(value, SupportsFloat):
        return float(value)
    raise TypeError(f"`{value!r}` is not a number")


def items(value: object) -> tuple[object, ...]:
    """An argument that is a list, as a tuple (none: empty; TypeError for another value)."""
    if isinstance(value, tuple):
        return value
    if value is None or isinstance(value, list):
        return tuple(value or ())
    raise TypeError(f"`{value!r}` is not a list")


def whole(value: object) -> int:
    """An argument that is a whole number, as an int (TypeError for another value, as
    ``int``)."""
    if isinstance(value, SupportsInt):
        return int(value)
    raise TypeError(f"`{value!r}` is not a whole number")


class FastLeaf:
    """The py_trees leaf lifecycle as ``tick_status()`` (see :mod:`osc2runner.compile.composites`).

    Same order as ``Behaviour.tick``: ``initialise`` when not running,
    ``update``, ``stop`` (hence ``terminate``) on leaving RUNNING; without
    py_trees' per-tick debug formatting, which is most of a leaf's cost at 20 Hz.
    """

    status: Status  # the py_trees behaviour's it is mixed into

    def tick_status(self) -> Status:
        if self.status != Status.RUNNING:
            self.initialise()  # type: ignore[attr-defined]
        new_status: Status = self.update()  # type: ignore[attr-defined]
        if new_status != Status.RUNNING:
            self.stop(new_status)  # type: ignore[attr-defined]
        self.status = new_status
        return new_status

    def tick(self) -> Iterator[py_trees.behaviour.Behaviour]:
        self.tick_status()
        yield self  # type: ignore[misc]


@dataclass
class AssignedPose:
    """Where ``assign_position`` puts an actor: on the road of ``reference`` (an actor's
    state; the actor's own road by default), lane number (1 = rightmost in the direction
    of travel), road ``s`` of its centre, offset from the lane centre or road ``t``, yaw
    relative to the lane, speed."""

    lane: int | None = None
    s: float | None = None
    offset: float | None = None
    t: float | None = None
    yaw: float | None = None
    speed: float | None = None
    reference: ActorState | None = None  # the state the pose is taken from


@dataclass
class ModifierUse:
    """One modifier application in a ``with:`` block, compiled."""

    node: ast.Invocation
    symbol: Symbol
    arguments: dict[str, Closure]
    actor: Actor | None = None
    binding: Binding | None = None  # the checker's reading of its arguments

    @property
    def name(self) -> str:
        return self.symbol.name

    def given(self, name: str) -> ast.Node | None:
        """The expression written for parameter ``name``; None when it was not given."""
        return _given(self.binding, name)


@dataclass
class ActionUse:
    """One action invocation, compiled."""

    node: ast.Invocation
    symbol: Symbol
    actor: Actor
    arguments: dict[str, Closure]
    modifiers: list[Modifier] = field(default_factory=list)
    duration: Callable[[], tuple[float | None, float | None]] | None = None
    behaviour: type[ActionBehaviour] | None = None  # the registered class
    starts_scenario: bool = False  # begins at time 0: the witness realised its `at: start`
    binding: Binding | None = None  # the checker's reading of its arguments
    key: PhaseKey | None = None  # the schedule's name of its phase
    plan: PhasePlan | None = None  # what the schedule says of it (its deadline)

    def given(self, name: str) -> ast.Node | None:
        """The expression written for parameter ``name``; None when it was not given."""
        return _given(self.binding, name)

    @property
    def label(self) -> str:
        return f"{self.actor.name}.{self.symbol.name}"


def _given(binding: Binding | None, name: str) -> ast.Node | None:
    bound = binding.given(name) if binding is not None else None
    return bound.value if bound is not None else None


class ScenarioBehaviour(FastLeaf, py_trees.behaviour.Behaviour):
    """A leaf that takes the execution context from ``tree.setup(context=ctx)``."""

    ctx: RunContext

    def setup(self, **kwargs: Any) -> None:
        ctx = kwargs.get("context")
        if ctx is not None:
            self.ctx = ctx


class Modifier:
    """A constraint of one modifier application on its action's actor (see the module docs).

    The standard's timing (``at``, §8.9 "movement modifiers"):

    * ``start``: the constraint holds when the phase starts. For a phase that
      begins at time 0 the checker's witness placed the actor so; for a later
      phase the runner checks it then (:meth:`holds`) and fails the phase when it
      does not hold — nothing can change the past.
    * ``end``: the constraint holds when the phase ends. With a planned duration
      the modifier plans its motion to arrive then (:meth:`realise`); without
      one, reaching the constraint ends the phase (:meth:`finished`). When the
      phase ends on its own or on its duration, :meth:`holds` is checked.
    * ``all`` (the default): the constraint is reached and held throughout.

    Subclasses set ``longitudinal`` / ``lateral`` when they drive the speed or the
    lateral position, so that an action does not override them, and implement
    :meth:`realise` (``end`` and ``all``), :meth:`step` and :meth:`holds`.
    """

    longitudinal = False
    lateral = False

    def __init__(self, use: ModifierUse) -> None:
        self.use = use
        self.args: Arguments = {}
        self.at = "all"
        self.movement_mode = "other"
        self.track = "actual"

    # ---- helpers

    def evaluate(self) -> Arguments:
        self.args = ReadArguments(self.node, {k: fn() for k, fn in self.use.arguments.items()})
        self.at = str(self.args.get("at", "all"))
        # every motion the runner makes is physical and rate-limited, so `monotonous`
        # holds as `other` does; a reference's motion is followed as it is (`track:
        # projected` is the checker's A308)
        self.movement_mode = str(self.args.get("movement_mode", "other"))
        self.track = str(self.args.get("track", "actual"))
        return self.args

    @property
    def drives(self) -> bool:
        """Whether it acts on the motion in this phase (``at: start`` only checks)."""
        return self.at != "start"

    # ---- hooks

    def begin(self, action: ActionBehaviour) -> None:
        """The phase starts (arguments were evaluated): ``at: start`` is checked (or was
        realised by the witness), ``end`` and ``all`` are realised."""
        if self.at == "start":
            if not action.at_scenario_start:
                problem = self.holds(action)
                if problem is not None:
                    raise ActionError(
                        f"`{self.text}` does not hold when the phase starts: {problem}"
                    )
            return
        self.realise(action)

    def realise(self, action: ActionBehaviour) -> None:
        """Start driving the actor towards the constraint (``at: end`` or ``all``)."""

    def step(self, action: ActionBehaviour) -> None:
        """Every tick of the phase."""

    def finished(self, action: ActionBehaviour) -> bool:
        """True when the modifier ends the phase (``distance``; ``at: end`` reached)."""
        return False

    def pending(self, action: ActionBehaviour) -> bool:
        """True while the modifier keeps an action that reached its own goal from ending
        (the next phase's start it brings about, :mod:`osc2runner.compile.preparation`)."""
        return False

    def holds(self, action: ActionBehaviour) -> str | None:
        """None when the constraint holds now, else what is wrong (``speed 76.3 kph``)."""
        return None

    def end(self, action: ActionBehaviour) -> None:
        """The phase ended (or was stopped)."""

    def assign(self, pose: AssignedPose, action: ActionBehaviour) -> None:
        """Contribute to the pose an ``assign_position`` puts the actor in during a run
        (at time 0 the checker's witness has placed every actor already)."""

    @property
    def node(self) -> ast.Invocation:
        return self.use.node

    @property
    def text(self) -> str:
        return f"{self.use.name}(...) [{self.node.span.line}]"


class ActionBehaviour(ScenarioBehaviour):
    """One action invocation (see the module docstring)."""

    #: the phase ends on its own (True) or only by duration/until/race (False)
    finite = True
    #: the action realises its modifiers itself (assign_position): they are not begun
    modifiers_realised = False
    #: the motions (``longitudinal``, ``lateral``) the action drives itself, when it can
    #: bring about the next phase's ``at: start`` in the others while it runs
    #: (:mod:`osc2runner.compile.preparation`); None when it cannot
    own_motions: frozenset[str] | None = None

    def __init__(self, name: str, use: ActionUse) -> None:
        super().__init__(name)
        self.use = use
        self.actor = use.actor
        self.args: Arguments = {}
        self.start_tick = 0
        #: how long the phase lasts at most (until its deadline in the schedule: its own
        #: duration, a composition's around it, an `until elapsed`), when known
        self.phase: float | None = None
        self.at_scenario_start = False
        self.ended_on_time = False  # stopped by its own duration bound, not pre-empted

    # ---- conveniences

    @property
    def state(self) -> ActorState:
        return self.ctx.states[self.actor.name]

    @property
    def controller(self) -> Controller | None:
        """The actor's controller (None for an actor nothing drives: an obstacle)."""
        return self.ctx.controllers.get(self.actor.name)

    @property
    def driver(self) -> Controller:
        """The actor's controller; an ActionError for an actor nothing drives."""
        ctrl = self.ctx.controllers.get(self.actor.name)
        if ctrl is None:
            raise ActionError("this actor has no driver (it cannot move)")
        return ctrl

    @property
    def elapsed(self) -> float:
        return (self.ctx.tick - self.start_tick) * self.ctx.dt

    def remaining(self) -> float | None:
        """Seconds until the phase must be done (its deadline), when known."""
        if self.phase is None:
            return None
        return max(self.phase - self.elapsed, 0.0)

    def plan_time(self) -> float | None:
        """Seconds a plan made now has to arrive: until the deadline less the margin
        (``ctx.tolerances``), at least one control period; None without a deadline."""
        left = self.remaining()
        if left is None:
            return None
        ctx = self.ctx
        return max(left - ctx.tolerances.margin, ctx.dt)

    def drives(self, channel: str) -> bool:
        """True when a modifier acting in this phase controls ``longitudinal`` or
        ``lateral`` motion (an ``at: start`` one only checks the start)."""
        return any(getattr(m, channel) and m.drives for m in self.use.modifiers)

    def fail(self, message: str) -> Status:
        """Fail the phase (and the run) with a message naming the invocation."""
        node = self.use.node
        where = f"{node.span.uri}:{node.span.line}:{node.span.column}"
        self.ctx.fail(f"{where}: {self.use.label}: {message}")
        self.feedback_message = message
        return Status.FAILURE

    # ---- lifecycle

    def initialise(self) -> None:
        ctx = self.ctx
        self.start_tick = ctx.tick
        note_started(self.use.node)
        ctx.phase_started(self.use.key)
        self.args = ReadArguments(self.use.node, {k: fn() for k, fn in self.use.arguments.items()})
        self.phase = None
        deadline = ctx.deadline(self.use.plan)  # the end of the phase it belongs to
        if deadline is not None:
            self.phase = max(deadline - ctx.time, 0.0)
        elif self.use.duration is not None:
            low, high = self.use.duration()
            self.phase = high if high is not None else low
        self.at_scenario_start = ctx.tick == 0 and self.use.starts_scenario
        self.ended_on_time = False
        ctx.record("start", self.use.label, actors=(self.actor.name,))
        self._failure: str | None = None
        modifiers = [] if self.modifiers_realised else self.use.modifiers
        try:
            for modifier in modifiers:
                modifier.evaluate()  # before the action starts: it reads their timing
            self.start()
            for modifier in modifiers:
                modifier.begin(self)
        except ActionError as exc:
            self._failure = str(exc)
        # only the modifiers that act every tick are called every tick
        acting = [m for m in modifiers if m.drives]
        self._stepping = [m for m in acting if type(m).step is not Modifier.step]
        self._finishing = [m for m in acting if type(m).finished is not Modifier.finished]
        self._pending = [m for m in acting if type(m).pending is not Modifier.pending]

    def update(self) -> Status:
        if self._failure is not None:
            return self.fail(self._failure)
        try:
            for modifier in self._stepping:
                modifier.step(self)
            status = self.step()
            if status == Status.SUCCESS and any(m.pending(self) for m in self._pending):
                status = Status.RUNNING
        except ActionError as exc:
            return self.fail(str(exc))
        if status == Status.RUNNING:
            for modifier in self._finishing:
                if modifier.finished(self):
                    return Status.SUCCESS
        return status

    def terminate(self, new_status: Status) -> None:
        if new_status == Status.INVALID and self.status != Status.RUNNING:
            return
        how = ended_kind(new_status)
        if new_status == Status.INVALID and self.ended_on_time:
            how = "end"
        self.ctx.record(how, self.use.label, actors=(self.actor.name,))
        if self.modifiers_realised:
            return
        for modifier in self.use.modifiers:
            modifier.end(self)
        if how == "end":  # the phase ended as planned: its `at: end` constraints must hold
            for modifier in self.use.modifiers:
                problem = modifier.holds(self) if modifier.at == "end" else None
                if problem is not None:
                    self.fail(f"`{modifier.text}` does not hold when the phase ends: {problem}")

    # ---- hooks

    def start(self) -> None:
        """Set the controller targets when the phase starts."""

    def step(self) -> Status:
        """The status at this tick (after the modifiers' step)."""
        return Status.RUNNING


class InstantAction(ActionBehaviour):
    """An action that takes effect at once and succeeds in the tick it starts."""

    def step(self) -> Status:
        return Status.SUCCESS


class ActionError(Exception):
    """An action cannot do what it was asked (fails the run with this message)."""


def finite(value: object) -> bool:
    return isinstance(value, (int, float)) and math.isfinite(value)


__all__ += ["ActionError", "finite"]
