"""Composites and decorators for OSC2 compositions: serial, parallel, one_of, duration, labels.

* :class:`Serial` is a py_trees ``Sequence`` with memory: members run one
  after the other; a member that finishes hands over to the next in the same
  tick.
* :class:`Parallel` starts all members together and ends as its ``overlap``
  says: when all have ended (``start``, ``any``, ``full``), or with its first
  member (``equal``, ``end``, ``final``, ``initial``, ``inside``).
* :class:`OneOf`: exactly one acting member runs (the witness's choice, else
  one drawn with the run's seed; recorded); members that only wait run
  alongside and may end it.
* :class:`DurationBound` bounds its child in simulated time: it succeeds at
  the upper bound (stopping the child), and holds an early success until the
  lower bound.
* :class:`Labelled` emits ``<label>.start`` and ``<label>.end`` events.
* :class:`ScenarioRoot` runs the scenario's ``do`` and its ``on`` handlers;
  its status is that of the ``do``.

None of them read a clock: time comes from the execution context.

Ticking: every node of the runner implements ``tick_status()`` (one tick, the
py_trees lifecycle, returns the new status) and its ``tick()`` generator
delegates to it, so ``tick_once()`` and ``BehaviourTree.tick()`` work as for
any py_trees tree. Composites tick their children through :func:`tick_child`,
which takes the fast path when the child has one and py_trees' generator
otherwise (scripted test children). The generators yield only the node
ticked, not its descendants: the runner attaches no tick visitors.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from typing import Any

import py_trees
from py_trees.common import ParallelPolicy, Status

from osc2check.semantics.phases import ENDS_WITH_FIRST, NOT_BEFORE_FIRST
from osc2check.verify.schedule import PhasePlan

__all__ = [
    "DurationBound",
    "InvokedScenario",
    "Labelled",
    "OneOf",
    "Parallel",
    "ScenarioRoot",
    "Serial",
    "end_instances",
    "running_endless",
    "running_open",
    "tick_child",
]

RUNNING, SUCCESS, FAILURE, INVALID = Status.RUNNING, Status.SUCCESS, Status.FAILURE, Status.INVALID
Behaviour = py_trees.behaviour.Behaviour


def tick_child(child: Behaviour) -> Status:
    """Tick ``child`` once and return its status."""
    fast = getattr(child, "tick_status", None)
    if fast is not None:
        status: Status = fast()
        return status
    for _ in child.tick():
        pass
    return child.status


def _reset(children: Sequence[Behaviour]) -> None:
    for child in children:
        if child.status != INVALID:
            child.stop(INVALID)


class _Fast:
    """``tick()`` as a generator over ``tick_status()``; the execution context from
    ``tree.setup(context=ctx)``; ``phase_key``: the schedule's name of the phase it runs
    (``osc2check.verify.schedule``), whose start it records."""

    ctx: Any = None
    phase_key: Any = None

    def _started(self) -> None:
        started = getattr(self.ctx, "phase_started", None)  # (scripted tests' contexts)
        if started is not None:
            started(self.phase_key)

    def setup(self, **kwargs: Any) -> None:
        self.ctx = kwargs.get("context", self.ctx)

    def tick(self) -> Iterator[Behaviour]:
        self.tick_status()  # type: ignore[attr-defined]
        yield self  # type: ignore[misc]


class Serial(_Fast, py_trees.composites.Sequence):
    """``serial``: members one after the other."""

    def __init__(self, name: str, children: Sequence[Behaviour] = ()) -> None:
        super().__init__(name, memory=True, children=list(children))
        self._index = 0

    def tick_status(self) -> Status:
        children = self.children
        if self.status != RUNNING:
            self.current_child = children[0] if children else None
            _reset(children)
            self.initialise()
            self._index = 0
            self._started()
        for index in range(self._index, len(children)):
            child = children[index]
            self.current_child = child
            self._index = index
            status = tick_child(child)
            if status == RUNNING:
                self.status = RUNNING
                return RUNNING
            if status != SUCCESS:
                self.stop(status)
                return status
        self.stop(SUCCESS)
        return SUCCESS


class Parallel(_Fast, py_trees.composites.Parallel):
    """``parallel``: members start together; the end depends on ``overlap``.

    * ``start`` (the default), ``any``, ``full``: success when every member has
      ended. Members that cannot end on their own (open-ended actions such as
      ``drive()`` without ``duration`` or ``until``) end with the others.
    * ``equal``, ``end``, ``final``, ``initial``, ``inside``: the first member is
      primary and the composition ends with it: a member that is done earlier is
      held (its phase lasts until then), one still running then is stopped — its
      planned end if it is open-ended, a failure if it had a goal it had not
      reached. An open-ended first member ends when the others have ended.

    Members start together, except with ``end`` and ``final``: a member whose length
    is known before it starts (the schedule's, ``osc2check.verify.schedule``) starts
    so that it ends with the others (``end``: the longest first) or with the first
    member (``final``). With ``equal`` and ``full`` a member of known length that ends
    before a first member of known length fails the composition (its phase cannot be
    held: the members end together, or the others cover the first). The first
    failure stops the others and fails the composition.
    """

    def __init__(
        self,
        name: str,
        children: Sequence[Behaviour] = (),
        overlap: str = "start",
        where: str = "",
        plans: Sequence[PhasePlan | None] = (),
    ) -> None:
        super().__init__(
            name, policy=ParallelPolicy.SuccessOnAll(synchronise=True), children=list(children)
        )
        self._open = [may_be_open(c) for c in self.children]
        self.overlap = overlap
        self.where = where
        found = list(plans) or [None] * len(self.children)
        self._delays = [p.delay if p is not None else 0.0 for p in found]
        self._lengths = [p.length if p is not None else None for p in found]
        self._delayed = any(d > 0.0 for d in self._delays)
        self._not_before_first = overlap in NOT_BEFORE_FIRST and self._lengths[:1] != [None]
        self._begun = 0.0

    def tick_status(self) -> Status:
        children = self.children
        if self.status != RUNNING:
            _reset(children)
            self.current_child = None
            self.initialise()
            self._started()
            self._begun = self.ctx.time if self._delayed else 0.0
        if not children:
            self.stop(SUCCESS)
            return SUCCESS
        done = 0
        for k, child in enumerate(children):
            if child.status == SUCCESS:
                done += 1
                continue
            if self._delayed and child.status != RUNNING and not self._due(k):
                continue  # it starts later, to end with the others
            status = tick_child(child)
            if status == FAILURE:
                self.current_child = child
                self.stop(FAILURE)
                return FAILURE
            if status == SUCCESS:
                done += 1
                if (
                    k
                    and self._not_before_first
                    and self._lengths[k] is not None
                    and children[0].status == RUNNING
                ):
                    return self._ended_before_first(k)
        if done == len(children):
            self.stop(SUCCESS)
            return SUCCESS
        if self.overlap in ENDS_WITH_FIRST and children[0].status == SUCCESS:
            return self._end_with_first()
        if done and all(
            c.status == SUCCESS or (o and running_open(c))
            for c, o in zip(children, self._open, strict=True)
        ):
            self.feedback_message = "open-ended members ended with the others"
            for child in children:
                if child.status == RUNNING:
                    mark_ended_on_time(child)
            self.stop(SUCCESS)
            return SUCCESS
        self.current_child = next((c for c in children if c.status == RUNNING), None)
        self.status = RUNNING
        return RUNNING

    def _due(self, k: int) -> bool:
        """Whether member ``k`` starts in this tick or has started."""
        due: bool = self.ctx.time - self._begun >= self._delays[k] - 1e-9
        return due

    def _ended_before_first(self, k: int) -> Status:
        child = self.children[k]
        reason = (
            f"{self.where}: `{child.name}` ended before the first member of "
            f"`parallel(overlap: {self.overlap})` (it lasts {self._lengths[k]:g} s, the first "
            f"member {self._lengths[0]:g} s)"
        )
        return self._fail(reason)

    def _fail(self, reason: str) -> Status:
        if self.ctx is not None:
            self.ctx.fail(reason)
        self.feedback_message = reason
        self.stop(FAILURE)
        return FAILURE

    def _end_with_first(self) -> Status:
        for child in self.children[1:]:
            if child.status != RUNNING:
                continue
            if not running_endless(child):
                reason = (
                    f"{self.where}: `{child.name}` had not completed when the first member "
                    f"of `parallel(overlap: {self.overlap})` ended"
                )
                return self._fail(reason)
            mark_ended_on_time(child)
        self.feedback_message = f"ended with its first member (overlap: {self.overlap})"
        self.stop(SUCCESS)
        return SUCCESS


class OneOf(_Fast, py_trees.composites.Parallel):
    """``one_of``: exactly one member's behaviour happens (§7.6.2).

    Members that only wait (they invoke no action or scenario: ``wait``, ``emit``,
    ``call``) command nothing and run alongside; among the members that act, one
    runs, recorded in the event log (``choice``) when the composition starts: the
    compiled plan's choice (``chosen``, an index among the acting members, from
    ``compile.preparation.Choices``: the witness's, else drawn with the seed before
    the phase before it was planned), else, for a ``one_of`` built by hand, one
    drawn with the run's seed when it starts; the others never start. The first of the running
    members to succeed ends the composition (a waiting member ends the chosen
    behaviour: the design paper's ``one_of: drive() / wait fall(...)``). With no
    acting member, the waiting members race. A failing chosen member fails it.
    """

    def __init__(
        self,
        name: str,
        children: Sequence[Behaviour] = (),
        acting: Sequence[bool] | None = None,
        chosen: int | None = None,
    ) -> None:
        super().__init__(name, policy=ParallelPolicy.SuccessOnOne(), children=list(children))
        self.acting = list(acting) if acting is not None else [True] * len(self.children)
        self.choice = chosen  # the witness's choice among the acting members
        self.winner: Behaviour | None = None
        self.chosen: Behaviour | None = None
        self.running: list[Behaviour] = []

    def _choose(self) -> None:
        acting = [c for c, a in zip(self.children, self.acting, strict=True) if a]
        waiting = [c for c, a in zip(self.children, self.acting, strict=True) if not a]
        self.chosen = None
        if acting:
            rng = getattr(self.ctx, "rng", None)
            if self.choice is not None and 0 <= self.choice < len(acting):
                index = self.choice
            else:
                index = int(rng.integers(len(acting))) if rng is not None else 0
            self.chosen = acting[index]
            if self.ctx is not None:
                position = self.children.index(self.chosen) + 1
                self.ctx.record(
                    "choice",
                    self.name,
                    f"member {position} of {len(self.children)}: {self.chosen.name}",
                )
        self.running = ([self.chosen] if self.chosen is not None else []) + waiting

    def tick_status(self) -> Status:
        children = self.children
        if self.status != RUNNING:
            _reset(children)
            self.current_child = None
            self.winner = None
            self.initialise()
            self._started()
            self._choose()
        if not children:
            self.stop(SUCCESS)
            return SUCCESS
        alive = False
        for child in self.running:
            if child.status == FAILURE:
                continue
            status = tick_child(child)
            if status == SUCCESS:
                self.winner = child
                self.current_child = child
                self.stop(SUCCESS)
                return SUCCESS
            if status == FAILURE and child is self.chosen:
                self.current_child = child
                self.stop(FAILURE)
                return FAILURE
            if status == RUNNING:
                alive = True
        if alive:
            self.current_child = next((c for c in self.running if c.status == RUNNING), None)
            self.status = RUNNING
            return RUNNING
        self.stop(FAILURE)
        return FAILURE

    def stop(self, new_status: Status = INVALID) -> None:
        for child in self.children:
            if child.status == RUNNING:
                child.stop(INVALID)
        py_trees.composites.Composite.stop(self, new_status)


def _behaviour_of(node: Behaviour) -> list[Behaviour]:
    """The children that make ``node``'s behaviour (a scenario's ``do``, not its handlers)."""
    do = getattr(node, "do", None)
    return [do] if do is not None else list(node.children)


def may_be_open(node: Behaviour) -> bool:
    """Whether ``node`` has open-ended leaves outside bounds (see :func:`running_open`)."""
    if getattr(node, "open_ended", False):
        return True
    if isinstance(node, py_trees.decorators.Decorator) and not isinstance(node, Labelled):
        return False
    return any(may_be_open(c) for c in _behaviour_of(node))


def running_open(node: Behaviour) -> bool:
    """True when ``node`` runs and everything running under it is open-ended.

    Open-ended leaves carry ``open_ended = True`` (set by the compiler on
    actions that never end on their own and have no ``duration``/``until``).
    """
    if node.status != RUNNING:
        return False
    if getattr(node, "open_ended", False):
        return True
    if isinstance(node, py_trees.decorators.Decorator) and not isinstance(node, Labelled):
        return False
    running = [c for c in _behaviour_of(node) if c.status == RUNNING]
    return bool(running) and all(running_open(c) for c in running)


class DurationBound(_Fast, py_trees.decorators.Decorator):
    """Bounds the child's phase to ``[low, high]`` seconds of simulated time (``duration:``).

    ``bounds()`` is evaluated when the phase starts and returns ``(low, high)``
    (either may be None). A child that succeeds before ``low`` is held (not
    re-ticked) until ``low``. At ``high`` the phase ends: a child that completes in
    that tick ends on time (§7.6.2: a phase of duration ``d`` may end at ``d``); one
    still running after it is stopped — the end it was planned for when everything
    still running is open-ended (``drive()``; an action's ``at: end`` modifiers are
    then checked), a failure otherwise (a goal not reached in time: the phase
    "exceeds its duration bound"). A failing child fails the phase.
    """

    def __init__(
        self,
        name: str,
        child: Behaviour,
        bounds: Callable[[], tuple[float | None, float | None]],
        where: str = "",
    ) -> None:
        super().__init__(name=name, child=child)
        self.bounds = bounds
        self.where = where  # "file:line:column" of the invocation or composition
        self.low: float | None = None
        self.high: float | None = None
        self.start_tick = 0

    def initialise(self) -> None:
        self.low, self.high = self.bounds()
        self.start_tick = self.ctx.tick

    def elapsed(self) -> float:
        elapsed: float = (self.ctx.tick - self.start_tick) * self.ctx.dt
        return elapsed

    def may_end_now(self) -> bool:
        """Whether ending the phase now keeps its duration: its lower bound has passed
        and what runs under it cannot end on its own."""
        if self.status != RUNNING or self.low is None:
            return False
        return self.elapsed() >= self.low - 1e-9 and running_endless(self.decorated)

    def tick_status(self) -> Status:
        if self.status != RUNNING:
            self.initialise()
        elapsed = self.elapsed()
        eps = 1e-9
        child = self.decorated
        if self.high is not None and elapsed >= self.high - eps:
            if child.status == RUNNING and not running_endless(child):
                # the child gets this tick: a phase that completes in it (one planned to
                # end with the bound, a `wait elapsed(...)` as long) ends on time
                status = tick_child(child)
                if status == FAILURE:
                    self.stop(FAILURE)
                    return FAILURE
            if child.status == RUNNING and not running_endless(child):
                reason = (
                    f"{self.where}: `{child.name}` did not complete within its duration "
                    f"({self.high:g} s)" + progress_of(child)
                )
                self.ctx.fail(reason)
                self.feedback_message = reason
                child.stop(INVALID)
                self.stop(FAILURE)
                return FAILURE
            if child.status == RUNNING:
                mark_ended_on_time(child)
                end_instances(child)
                child.stop(INVALID)
            self.feedback_message = f"ended at {elapsed:.3f} s"
            self.stop(SUCCESS)
            return SUCCESS
        if child.status != SUCCESS or self.status != RUNNING:
            status = tick_child(child)
        else:
            status = SUCCESS  # held: done early, waiting for the lower bound
        if status == FAILURE:
            self.stop(FAILURE)
            return FAILURE
        if status == SUCCESS and (self.low is None or elapsed >= self.low - eps):
            self.stop(SUCCESS)
            return SUCCESS
        self.status = RUNNING
        return RUNNING

    def update(self) -> Status:  # pragma: no cover - tick_status() decides
        return self.status


def running_endless(node: Behaviour) -> bool:
    """True when ``node`` runs and everything running under it is an action that cannot
    end on its own (``drive()``, ``keep_speed()``: their ``endless`` is set), so that
    a duration bound ending them is their planned end, not a goal missed. A phase with
    its own ``duration`` is endless only once its lower bound has passed; one with an
    ``until`` ends on its event, never before."""
    if node.status != RUNNING:
        return False
    if getattr(node, "endless", False):
        return True
    if isinstance(node, DurationBound):
        return node.may_end_now()
    if getattr(node, "ends_on_event", False):
        return False
    running = [c for c in _behaviour_of(node) if c.status == RUNNING]
    return bool(running) and all(running_endless(c) for c in running)


def progress_of(node: Behaviour) -> str:
    """``: <how far>`` from the running action under ``node`` that can say how far it is
    from its goal (its ``progress()``: the measured value and the tolerance), else ""."""
    stack = [node]
    while stack:
        current = stack.pop()
        if current.status != RUNNING:
            continue
        progress = getattr(current, "progress", None)
        if callable(progress):
            return f": {progress()}"
        stack.extend(reversed(_behaviour_of(current)))
    return ""


def mark_ended_on_time(node: Behaviour) -> None:
    """Tell the running endless actions under ``node`` that their phase ends as planned
    (their ``at: end`` modifiers are then checked), not that they are pre-empted."""
    if getattr(node, "endless", False) and node.status == RUNNING:
        node.ended_on_time = True  # type: ignore[attr-defined]
    for child in node.children:
        if child.status == RUNNING:
            mark_ended_on_time(child)


class Labelled(_Fast, py_trees.decorators.Decorator):
    """A labelled member: emits ``<label>.start`` when it starts and ``<label>.end`` on success."""

    def __init__(self, name: str, child: Behaviour, label: str) -> None:
        super().__init__(name=name, child=child)
        self.label = label

    def tick_status(self) -> Status:
        if self.status != RUNNING:
            self.ctx.emit(f"{self.label}.start", kind="start")
        status = tick_child(self.decorated)
        if status == SUCCESS:
            self.ctx.emit(f"{self.label}.end", kind="end")
        elif status == FAILURE:
            self.ctx.emit(f"{self.label}.fail", kind="fail")
        if status != RUNNING:
            self.stop(status)
        self.status = status
        return status

    def update(self) -> Status:  # pragma: no cover - tick_status() decides
        return self.decorated.status


class ScenarioRoot(_Fast, py_trees.composites.Parallel):
    """The scenario: its ``do`` (first child) and its ``on`` handlers (the rest).

    Handlers run for as long as the ``do`` runs and are ticked first, so they
    see this tick's edges; the root's status is the ``do``'s. The scenario's
    predefined events ``start`` and ``end`` (or ``fail``) are emitted here; the
    handlers are ticked once more after ``end``/``fail``, so ``on @end:`` runs.
    """

    def __init__(
        self,
        name: str,
        do: Behaviour,
        handlers: Sequence[Behaviour] = (),
        path: str = "",
        initialisers: Sequence[Callable[[], None]] = (),
        emits_events: bool = True,
    ) -> None:
        super().__init__(
            name, policy=ParallelPolicy.SuccessOnSelected(children=[do]), children=[do, *handlers]
        )
        self.do = do
        self.path = path  # the instance's path: its events are `<path>.start` ...
        self.initialisers = list(initialisers)  # run when the instance starts (its `var`s)
        self.emits_events = emits_events  # False when a label of the same name emits them

    def _event(self, name: str) -> str:
        return f"{self.path}.{name}" if self.path else name

    def _emit(self, name: str) -> None:
        if self.ctx is not None and self.emits_events:
            self.ctx.emit(self._event(name), kind=name)

    def tick_status(self) -> Status:
        if self.status != RUNNING:
            _reset(self.children)
            self._started()
            for initialise in self.initialisers:
                initialise()
            self._emit("start")
        for child in self.children[1:]:
            tick_child(child)
        status = tick_child(self.do)
        if status == RUNNING:
            self.status = RUNNING
            return RUNNING
        self._end("end" if status == SUCCESS else "fail")
        self.stop(status)
        return status

    def _end(self, event: str) -> None:
        """Emit ``end`` (or ``fail``) and let the handlers see it."""
        self._emit(event)
        for child in self.children[1:]:
            tick_child(child)

    def end_now(self) -> None:
        """The instance is ended from outside as planned (its invocation's ``until``
        occurred, or its ``duration`` is up): its ``end`` occurs now."""
        if self.status == RUNNING:
            end_instances(self.do)
            self._end("end")


def end_instances(node: Behaviour) -> None:
    """Emit ``end`` for every running scenario instance under ``node``, which is ended as
    planned (by ``until`` or ``duration``), innermost last to first."""
    if isinstance(node, ScenarioRoot):
        node.end_now()
        return
    for child in _behaviour_of(node):
        if child.status == RUNNING:
            end_instances(child)


class InvokedScenario(ScenarioRoot):
    """A scenario invoked by another: its instance's ``do`` and ``on`` handlers, with its
    events ``<path>.start``, ``<path>.end`` (or ``.fail``); it ends with its ``do``."""
