"""The one tick loop: behaviour tree, controllers and world advanced together.

Each control tick (50 ms by default):

1. the active edge detectors (``rise``, ``fall``) read this tick's state, then
   the background polls (event functions of ``sample``, coverage, declared
   events);
2. the behaviour tree is ticked once (behaviours set controller targets); a
   :class:`~osc2runner.execution.context.RunFault` raised by the scenario in
   1 or 2 fails the run at this tick;
3. every controller turns its targets and its actor's state into inputs (a
   system under test that fails here ends the run as ``error``);
4. the world advances one control step (its physics sub-steps);
5. every actor's state is read once, and recorded; collisions and road
   departures come back as world events.

A state that is no longer physical after step 4 (NaN or infinite values, or
MuJoCo resetting a diverged simulation: :meth:`World.diverged`) ends the run
with outcome ``error`` naming the actor and the tick; that tick is not
recorded (the telemetry ends with the last physical state).

Nothing reads the wall clock except to report the real-time factor: the same
inputs give the same ticks. :meth:`TickLoop.run` returns how the run ended with
what it recorded, also when it is interrupted (a signal noted by
:class:`~osc2runner.execution.signals.Interrupts`, read between ticks, or a
``KeyboardInterrupt``) or a bug stops it, so that the caller can write the
files before re-raising.
"""

from __future__ import annotations

import time as wallclock
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import py_trees
from py_trees.common import Status

from osc2runner.behaviours.base import FastLeaf
from osc2runner.compile.composites import running_open, tick_child
from osc2runner.execution.context import RunContext, RunFault
from osc2runner.execution.controls import Controller
from osc2runner.execution.outcome import RunOutcome
from osc2runner.execution.signals import Interrupts, SignalInterrupt, signal_name
from osc2runner.output.telemetry import Recorder
from osc2runner.sim import World
from osc2runner.sut.driver import SutFault

__all__ = ["RunOutcome", "TickLoop", "Ticked"]


@dataclass
class Ticked:
    """What the loop did: its outcome, the telemetry, the wall time, an exception that
    stopped it (KeyboardInterrupt or a bug), to re-raise once the files are written,
    and the signal that interrupted it."""

    outcome: RunOutcome
    recorder: Recorder
    wall_seconds: float
    error: BaseException | None = None
    signum: int | None = None


class TickLoop:
    """The tick loop of one run (see the module docstring).

    ``step()`` does one control tick and returns the outcome once the run has
    ended; ``run(limit)`` steps to the end. :meth:`without_scenario` drives
    controllers and a world with no behaviour tree (physics measurements).
    """

    def __init__(
        self,
        root: py_trees.behaviour.Behaviour,
        ctx: RunContext,
        world: World,
        *,
        limit: float = float("inf"),
        record: bool = True,
    ) -> None:
        self.root = root
        self.ctx = ctx
        self.world = world
        self.limit = limit
        self.max_ticks = max(0, round(limit / world.dt_control)) if limit != float("inf") else -1
        py_trees.trees.BehaviourTree(root).setup(context=ctx)
        self.recorder = Recorder(world.names if record else (), world.dt_control)
        self.recorder.record(ctx.states, world.tick, world.time, ctx.controllers)

    @classmethod
    def without_scenario(
        cls, world: World, controllers: dict[str, Controller], *, record: bool = False
    ) -> TickLoop:
        """A loop that steps ``controllers`` and ``world`` under a tree that never ends
        (physics measurements; it records no telemetry unless asked)."""
        ctx = RunContext(world.network, [], dt=world.dt_control)
        ctx.attach(world, controllers)
        return cls(_Forever("no scenario"), ctx, world, record=record)

    def step(self) -> RunOutcome | None:
        """One control tick; the outcome when the run ends with it, else None."""
        ctx, world, root = self.ctx, self.world, self.root
        try:
            ctx.begin_tick()
            tick_child(root)
        except RunFault as fault:  # the scenario went wrong at run time: a failed run
            ctx.fail(str(fault))
        outcome = _tree_outcome(root, ctx, world, self.max_ticks, self.limit)
        if outcome is not None:
            return outcome
        states, controllers = ctx.states, ctx.controllers
        try:
            inputs = {name: c.step(states[name]) for name, c in controllers.items()}
        except SutFault as fault:  # the system under test failed: its outcome, not a bug
            return RunOutcome("error", str(fault), ctx.tick, ctx.time)
        events = world.step_control(inputs)
        if (bad := world.diverged()) is not None:
            return _diverged(world, *bad)
        ctx.refresh()
        self.recorder.record(states, world.tick, world.time, controllers)
        return _world_events(ctx, events) if events else None

    def run(
        self,
        progress: Callable[[float, float, float], None] | None = None,
        interrupts: Interrupts | None = None,
        fault: str | None = None,
    ) -> Ticked:
        """Step until the run ends; also when it is interrupted or a bug stops it.

        ``interrupts.first`` is read before every tick: once a signal has arrived
        the run ends as ``interrupted`` (at a tick boundary, or where the signal was
        raised, in the system under test's code). ``fault`` (a system under test
        that could not start) ends the run as ``error`` before its first tick.
        """
        ctx, world = self.ctx, self.world
        progress_every = max(1, round(1.0 / world.dt_control))
        start_wall = wallclock.perf_counter()
        outcome: RunOutcome | None = None
        error: BaseException | None = None
        signum: int | None = None
        try:
            if fault is not None:
                outcome = RunOutcome("error", fault, ctx.tick, ctx.time)
            elif (bad := world.diverged()) is not None:  # a start that is not physical
                outcome = _diverged(world, *bad)
            while outcome is None:
                if interrupts is not None and interrupts.first is not None:
                    signum = interrupts.consume()
                    outcome = _interrupted(ctx, signum)
                    break
                outcome = self.step()
                if progress is not None and world.tick % progress_every == 0:
                    progress(world.time, self.limit, wallclock.perf_counter() - start_wall)
        except SignalInterrupt as exc:  # raised where the run was (foreign code, a 2nd signal)
            if interrupts is not None:
                interrupts.consume()
            signum = exc.signum
            outcome, error = _interrupted(ctx, signum), exc
        except KeyboardInterrupt as exc:
            outcome = RunOutcome("interrupted", "interrupted", ctx.tick, ctx.time)
            error = exc
        except BaseException as exc:  # a bug: recorded, reported, re-raised by the caller
            outcome = RunOutcome(
                "error", f"internal error: {type(exc).__name__}: {exc}", ctx.tick, ctx.time
            )
            error = exc
        wall = wallclock.perf_counter() - start_wall
        ctx.record("outcome", outcome.status, outcome.reason)
        return Ticked(outcome, self.recorder, wall, error, signum)


class _Forever(FastLeaf, py_trees.behaviour.Behaviour):
    """A tree that never ends (``TickLoop.without_scenario``)."""

    def update(self) -> Status:
        return Status.RUNNING


def _interrupted(ctx: RunContext, signum: int | None) -> RunOutcome:
    name = signal_name(signum or 0)
    return RunOutcome("interrupted", f"interrupted by {name}", ctx.tick, ctx.time, signal=name)


def _tree_outcome(
    root: py_trees.behaviour.Behaviour, ctx: RunContext, world: World, max_ticks: int, limit: float
) -> RunOutcome | None:
    if ctx.failed is not None:
        return RunOutcome("failure", ctx.failed, ctx.tick, ctx.time)
    status = root.status
    if status == Status.SUCCESS:
        return RunOutcome("success", "the scenario's behaviour ended", ctx.tick, ctx.time)
    if status == Status.FAILURE:
        return RunOutcome("failure", _failure_reason(root), ctx.tick, ctx.time)
    if 0 <= max_ticks <= world.tick:
        if running_open(getattr(root, "do", root)):
            return RunOutcome(
                "success",
                f"time limit {limit:g} s reached with only open-ended actions running",
                ctx.tick,
                ctx.time,
            )
        return RunOutcome("timeout", f"time limit {limit:g} s reached", ctx.tick, ctx.time)
    return None


def _failure_reason(root: py_trees.behaviour.Behaviour) -> str:
    failed = [n for n in root.iterate() if n.status == Status.FAILURE and not n.children]
    if failed:
        node = failed[0]
        why = f": {node.feedback_message}" if node.feedback_message else ""
        return f"`{node.name}` failed{why}"
    return "the scenario's behaviour failed"


def _diverged(world: World, actor: str, what: str) -> RunOutcome:
    who = f"`{actor}`" if actor else "an actor"
    return RunOutcome(
        "error",
        f"the physics diverged at tick {world.tick} ({world.time:g} s): {who}: {what}",
        world.tick,
        world.time,
    )


def _world_events(ctx: RunContext, events: list[Any]) -> RunOutcome | None:
    """Log the world's events; a collision no ``avoid_collisions(false)`` allows, or an
    actor off the drivable road (past its end included), fails the run."""
    outcome = None
    for event in events:
        ctx.record(event.kind, "-".join(event.actors), event.detail, tuple(event.actors))
        if outcome is not None:
            continue
        if event.kind == "collision":
            if not any(ctx.collisions_allowed.get(a, 0) > 0 for a in event.actors):
                outcome = RunOutcome(
                    "failure", f"collision: {' and '.join(event.actors)}", event.tick, event.time
                )
        elif event.kind == "off_road":
            (name,) = event.actors
            outcome = RunOutcome("failure", _off_road(ctx, name), event.tick, event.time)
    return outcome


def _off_road(ctx: RunContext, name: str) -> str:
    state = ctx.states[name]
    network = ctx.network
    x, y = state.x, state.y
    if bool(network.past_end(np.array([x]), np.array([y]))[0]):
        return f"`{name}` drove past the end of the road (at x = {x:.1f} m, y = {y:.1f} m)"
    if state.road is None:
        return f"`{name}` left the roads of the map (at x = {x:.1f} m, y = {y:.1f} m)"
    kind = network.lane(state.lane_ref).type if state.lane_ref is not None else "no"
    return (
        f"`{name}` left the drivable road: it is on a `{kind}` lane of road `{state.road}` "
        f"(s = {state.s:.1f} m, t = {state.t:.2f} m)"
    )
