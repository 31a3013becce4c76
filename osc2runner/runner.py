"""``run(path)``: check, compile, place, tick — and write what happened.

The stages, in order (each one function or class elsewhere):

1. ``osc2check.analysis.analyze``: error diagnostics stop here
   (:class:`~osc2runner.errors.ScenarioError`, exit status 2);
2. the scenario instance: :class:`~osc2runner.values.ParameterValues`
   (constants until the solver's witness lands), actors, road;
3. :func:`~osc2runner.compile.tree.compile_scenario`: the behaviour tree;
4. :class:`~osc2runner.initializer.StartPlan`: every actor's start pose;
5. the fixed-step loop: edge detectors, one tree tick, controllers, one
   world step, telemetry — nothing reads the wall clock;
6. :func:`~osc2runner.telemetry.write` (and plots), also when the run fails
   or is interrupted.

Outcomes: ``success`` (the scenario's behaviour succeeded, or only open-ended
actions were still running at the time limit), ``failure`` (a failed phase, the
``fail`` event, a collision no ``avoid_collisions(false)`` allowed),
``timeout`` (the time limit with bounded phases still running),
``interrupted``, ``error`` (a bug: the exception propagates after writing).
"""

from __future__ import annotations

import logging
import time as wallclock
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import py_trees
from py_trees.common import Status

from osc2check.analysis import Analysis, SourceInput, analyze
from osc2check.diagnostics import Severity
from osc2check.road import UnknownMapError
from osc2check.semantics.symbols import Symbol
from osc2check.source import decode_source
from osc2check.syntax import ast
from osc2runner.actors import Actor, scenario_actors
from osc2runner.compile.composites import running_open
from osc2runner.compile.registry import registry
from osc2runner.compile.tree import CompiledScenario, compile_scenario
from osc2runner.context import ExecutionContext, LogRecord, fresh_blackboard
from osc2runner.drivers import controllers_for
from osc2runner.errors import CompileProblem, Problem, ScenarioError, problem
from osc2runner.initializer import Placement, StartPlan
from osc2runner.roads import LaneNumbers, road_for
from osc2runner.sim import World, versions
from osc2runner.telemetry import Recorder, write
from osc2runner.values import NoValue, ParameterValues, fold, to_runtime

__all__ = [
    "Compiled",
    "Outcome",
    "Prepared",
    "RunInterrupted",
    "RunResult",
    "compile_file",
    "execute",
    "prepare",
    "run",
]

log = logging.getLogger(__name__)

DEFAULT_TIME_LIMIT = 600.0  # s of simulated time
ValuesFactory = Callable[[Analysis, str, Any, Symbol], ParameterValues]


@dataclass(frozen=True, slots=True)
class Outcome:
    """How a run ended."""

    status: str  # success | failure | timeout | interrupted | error
    reason: str
    tick: int
    time: float

    @property
    def ok(self) -> bool:
        return self.status == "success"


@dataclass
class RunResult:
    """A finished (or stopped) run.

    ``telemetry[actor][channel]`` is a numpy array over the ticks (channels:
    :data:`osc2runner.telemetry.CHANNELS`); ``events`` the event log;
    ``outputs`` the files written.
    """

    outcome: Outcome
    telemetry: dict[str, dict[str, np.ndarray]]
    events: list[LogRecord]
    metadata: dict[str, Any]
    outputs: list[Path] = field(default_factory=list)

    @property
    def success(self) -> bool:
        return self.outcome.ok

    def event_ticks(self, kind: str, name: str) -> list[int]:
        """Ticks of the log records of ``kind`` named ``name``."""
        return [r.tick for r in self.events if r.kind == kind and r.name == name]


class RunInterrupted(KeyboardInterrupt):
    """The run was interrupted (Ctrl-C); ``result`` holds what was recorded and written."""

    def __init__(self, result: RunResult) -> None:
        super().__init__("interrupted")
        self.result = result


@dataclass
class Prepared:
    """A scenario compiled and placed, ready to tick (``prepare``)."""

    uri: str
    analysis: Analysis
    scenario: Symbol
    ctx: ExecutionContext
    compiled: CompiledScenario
    world: World
    plan_notes: list[str]

    @property
    def root(self) -> py_trees.behaviour.Behaviour:
        return self.compiled.root


# ---------------------------------------------------------------------- preparation


def _read(path: str | Path, source: str | None) -> tuple[str, str]:
    uri = str(path)
    if source is not None:
        return uri, source
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise ScenarioError([Problem(f"{uri}: cannot read: {exc.strerror or exc}")]) from None
    text, _ = decode_source(data)
    return uri, text


def _choose_scenario(analysis: Analysis, uri: str, name: str | None) -> Symbol:
    program = analysis.programs[uri]
    model = program.model
    result = program.files.get(uri)
    decls = [
        d for d in (result.ast.declarations if result else ()) if isinstance(d, ast.ScenarioDecl)
    ]
    symbols = [model.declarations[d] for d in decls if d in model.declarations]
    if name is not None:
        for sym in symbols:
            if sym.name == name or sym.qualified_name == name:
                return sym
        known = ", ".join(s.name for s in symbols) or "none"
        raise ScenarioError([Problem(f"{uri}: no scenario `{name}` (scenarios: {known})")])
    if not symbols:
        raise ScenarioError([Problem(f"{uri}: declares no scenario to run")])
    if len(symbols) > 1:
        names = ", ".join(s.name for s in symbols)
        raise ScenarioError(
            [Problem(f"{uri}: declares several scenarios ({names}); choose one with --scenario")]
        )
    return symbols[0]


def _map_file(model: Any, scenario: Symbol, actors: list[Actor]) -> tuple[str | None, Any]:
    """The map name from the map actor's ``map_file`` or a ``set_map_file`` modifier."""
    for actor in actors:
        if actor.kind == "map" and "map_file" in actor.attributes:
            return str(to_runtime(actor.attributes["map_file"])), actor.symbol.decl
    for sym in model.ancestors(scenario):
        decl = sym.decl
        for member in getattr(decl, "members", ()):
            if isinstance(member, ast.Invocation) and member.name.text == "set_map_file":
                for arg in member.arguments:
                    value = getattr(arg, "value", None)
                    if value is not None:
                        try:
                            return str(fold(value, model, lambda s, n: None)), member
                        except NoValue:
                            pass
    return None, None


@dataclass
class Compiled:
    """A scenario compiled against its execution context, before placement (``compile_file``)."""

    uri: str
    analysis: Analysis
    scenario: Symbol
    ctx: ExecutionContext
    compiled: CompiledScenario
    actors: list[Actor]

    @property
    def root(self) -> py_trees.behaviour.Behaviour:
        return self.compiled.root


def compile_file(
    path: str | Path,
    *,
    scenario: str | None = None,
    seed: int = 0,
    dt_control: float = 0.05,
    values: ValuesFactory | None = None,
    source: str | None = None,
) -> Compiled:
    """Check a file and compile one of its scenarios; raises ScenarioError for input errors.

    The blackboard is cleared first: a compiled tree belongs to one run.
    """
    uri, text = _read(path, source)
    analysis = analyze([SourceInput(uri, text)])
    errors = [d for d in analysis.diagnostics if d.severity is Severity.ERROR]
    if errors:
        raise ScenarioError([], diagnostics=errors, texts=analysis.texts)
    sym = _choose_scenario(analysis, uri, scenario)
    model = analysis.programs[uri].model
    if values is None:  # the witness the checker reports, picked by the seed
        from osc2runner.witness import witness_values

        values = witness_values(seed=seed)
    parameter_values = values(analysis, uri, model, sym)
    actors = scenario_actors(model, sym, parameter_values)
    map_name, map_node = _map_file(model, sym, actors)
    try:
        road = road_for(map_name)
    except UnknownMapError as exc:
        raise ScenarioError([problem(str(exc), map_node)]) from None
    fresh_blackboard()
    ctx = ExecutionContext(
        model, parameter_values, registry, road, actors, dt=dt_control, seed=seed
    )
    compiled = compile_scenario(ctx, sym, analysis.texts)
    if compiled.problems:
        raise ScenarioError(compiled.problems, texts=analysis.texts)
    return Compiled(uri, analysis, sym, ctx, compiled, actors)


def prepare(
    path: str | Path,
    *,
    scenario: str | None = None,
    seed: int = 0,
    dt_control: float = 0.05,
    dt_physics: float = 0.002,
    values: ValuesFactory | None = None,
    source: str | None = None,
) -> Prepared:
    """Check, compile and place a scenario; raises ScenarioError for input errors."""
    c = compile_file(
        path, scenario=scenario, seed=seed, dt_control=dt_control, values=values, source=source
    )
    uri, analysis, sym, ctx, compiled, actors = (
        c.uri,
        c.analysis,
        c.scenario,
        c.ctx,
        c.compiled,
        c.actors,
    )
    parameter_values, road = ctx.values, ctx.road
    plan = StartPlan(actors, ctx.lanes)
    problems: list[Problem] = []
    for use in compiled.start_uses:
        ctx.placed.add(use.node)
        hook = getattr(use.behaviour, "place_arguments", None)
        if hook is not None:
            try:
                hook(plan, use.actor, {k: fn() for k, fn in use.arguments.items()})
            except (KeyError, CompileProblem, NoValue):
                pass
        for modifier in use.modifiers:
            try:
                args = {k: fn() for k, fn in modifier.use.arguments.items()}
            except KeyError:
                problems.append(
                    problem(
                        f"`{modifier.use.name}(...)` at the start needs values known before the "
                        "first tick",
                        modifier.node,
                    )
                )
                continue
            if args.get("at", "all") in ("start", "all"):
                modifier.place(plan, use.actor, args)
    placements = plan.resolve()
    problems.extend(plan.problems)
    if problems:
        raise ScenarioError(problems, texts=analysis.texts)
    start = getattr(parameter_values, "start", None)
    if callable(start):  # the witness places every actor itself
        for name in list(placements):
            given = start(name)
            if given is not None:
                placements[name] = Placement(
                    s=given.s,
                    lane=ctx.lanes.to_road(given.lane),
                    offset=given.t,
                    yaw=given.heading,
                    speed=given.speed,
                )
    world = World(road, plan.specs(placements), dt_control=dt_control, dt_physics=dt_physics)
    ctx.attach(world, controllers_for(world, road))
    for name, fn in ctx.variable_inits:
        ctx.variables[name] = fn()
    return Prepared(uri, analysis, sym, ctx, compiled, world, plan.notes)


# ---------------------------------------------------------------------- running


def run(
    path: str | Path,
    *,
    scenario: str | None = None,
    seed: int = 0,
    out: str | Path | None = None,
    duration: float | None = None,
    dt_control: float = 0.05,
    dt_physics: float = 0.002,
    plot: bool = False,
    progress: Callable[[float, float, float], None] | None = None,
    values: ValuesFactory | None = None,
    source: str | None = None,
) -> RunResult:
    """Run one scenario of the file at ``path`` (see the module docstring).

    Parameters:
        path: the ``.osc`` file.
        scenario: which scenario (needed when the file declares several).
        seed: seed of the run (random choices left open; recorded).
        out: folder for telemetry, events, metadata (and plots); None writes nothing.
        duration: time limit in simulated seconds (default 600).
        dt_control: control period (tree tick) in seconds.
        dt_physics: physics step in seconds; ``dt_control`` must be a whole multiple.
        plot: also write PNG plots into ``out``.
        progress: called as ``progress(sim_time, limit, wall_seconds)`` every simulated second.
        values: a factory ``(analysis, uri, model, scenario) -> ParameterValues``
            (default: folded constants; :func:`osc2runner.witness.witness_values` solves).
        source: the file's text, instead of reading ``path``.

    Raises:
        ScenarioError: the input has errors (nothing ran).
        RunInterrupted: Ctrl-C; its ``result`` has what was recorded (and written).
    """
    prepared = prepare(
        path,
        scenario=scenario,
        seed=seed,
        dt_control=dt_control,
        dt_physics=dt_physics,
        values=values,
        source=source,
    )
    return execute(prepared, out=out, duration=duration, plot=plot, progress=progress)


def execute(
    prepared: Prepared,
    *,
    out: str | Path | None = None,
    duration: float | None = None,
    plot: bool = False,
    progress: Callable[[float, float, float], None] | None = None,
) -> RunResult:
    """Tick a prepared scenario to its end (see :func:`run`)."""
    ctx, world = prepared.ctx, prepared.world
    limit = DEFAULT_TIME_LIMIT if duration is None else float(duration)
    max_ticks = max(0, round(limit / world.dt_control))
    root = prepared.root
    tree = py_trees.trees.BehaviourTree(root)
    tree.setup(context=ctx)
    recorder = Recorder(world.names, world.dt_control)
    controllers = ctx.controllers
    states = ctx.states
    progress_every = max(1, round(1.0 / world.dt_control))
    start_wall = wallclock.perf_counter()
    outcome: Outcome | None = None
    error: BaseException | None = None
    try:
        recorder.record(states, world.tick, world.time, controllers)
        while True:
            ctx.begin_tick()
            for _ in root.tick():
                pass
            if ctx.failed is not None:
                outcome = Outcome("failure", ctx.failed, ctx.tick, ctx.time)
                break
            status = root.status
            if status == Status.SUCCESS:
                outcome = Outcome("success", "the scenario's behaviour ended", ctx.tick, ctx.time)
                break
            if status == Status.FAILURE:
                outcome = Outcome("failure", _failure_reason(root), ctx.tick, ctx.time)
                break
            if world.tick >= max_ticks:
                if running_open(root.do if hasattr(root, "do") else root):
                    outcome = Outcome(
                        "success",
                        f"time limit {limit:g} s reached with only open-ended actions running",
                        ctx.tick,
                        ctx.time,
                    )
                else:
                    outcome = Outcome(
                        "timeout", f"time limit {limit:g} s reached", ctx.tick, ctx.time
                    )
                break
            inputs = {name: c.step(states[name]) for name, c in controllers.items()}
            events = world.step_control(inputs)
            ctx.refresh()
            recorder.record(states, world.tick, world.time, controllers)
            if events:
                outcome = _world_events(ctx, events)
                if outcome is not None:
                    break
            if progress is not None and world.tick % progress_every == 0:
                progress(world.time, limit, wallclock.perf_counter() - start_wall)
    except KeyboardInterrupt as exc:
        outcome = Outcome("interrupted", "interrupted", ctx.tick, ctx.time)
        error = exc
    except BaseException as exc:
        outcome = Outcome(
            "error", f"internal error: {type(exc).__name__}: {exc}", ctx.tick, ctx.time
        )
        error = exc
    finally:
        wall = wallclock.perf_counter() - start_wall
        if outcome is None:  # pragma: no cover - every path sets one
            outcome = Outcome("error", "no outcome", ctx.tick, ctx.time)
        ctx.record("outcome", outcome.status, outcome.reason)
        result = _finish(prepared, recorder, outcome, wall, out, plot)
    if isinstance(error, KeyboardInterrupt):
        raise RunInterrupted(result) from error
    if error is not None:
        raise error
    return result


def _failure_reason(root: py_trees.behaviour.Behaviour) -> str:
    failed = [n for n in root.iterate() if n.status == Status.FAILURE and not n.children]
    if failed:
        node = failed[0]
        why = f": {node.feedback_message}" if node.feedback_message else ""
        return f"`{node.name}` failed{why}"
    return "the scenario's behaviour failed"


def _world_events(ctx: ExecutionContext, events: list[Any]) -> Outcome | None:
    outcome = None
    for event in events:
        ctx.record(event.kind, "-".join(event.actors), event.detail, tuple(event.actors))
        if event.kind == "collision" and outcome is None:
            if not any(ctx.collisions_allowed.get(a, 0) > 0 for a in event.actors):
                outcome = Outcome(
                    "failure", f"collision: {' and '.join(event.actors)}", event.tick, event.time
                )
    return outcome


def _finish(
    prepared: Prepared,
    recorder: Recorder,
    outcome: Outcome,
    wall: float,
    out: str | Path | None,
    plot: bool,
) -> RunResult:
    ctx = prepared.ctx
    metadata = _metadata(prepared, outcome, wall)
    result = RunResult(outcome, recorder.arrays(), list(ctx.records), metadata)
    if out is not None:
        folder = Path(out)
        result.outputs = write(folder, recorder, result.events, metadata)
        if plot:
            from osc2runner.plots import plot_run

            result.outputs.extend(plot_run(result, folder))
    return result


def _metadata(prepared: Prepared, outcome: Outcome, wall: float) -> dict[str, Any]:
    ctx, world = prepared.ctx, prepared.world
    from osc2check.output import tool

    actors = {}
    for name, actor in ctx.actors.items():
        entry: dict[str, Any] = {"type": actor.type.name, "kind": actor.kind}
        if actor.blueprint:
            entry["model"] = actor.blueprint
        if name in world.names:
            spec = world.specs[world.names.index(name)]
            entry["start"] = {
                "s": spec.s,
                "lane": spec.lane,
                "offset": spec.offset,
                "yaw": spec.yaw,
                "speed": spec.speed,
            }
        actors[name] = entry
    return {
        "tool": {"name": "osc2run", "version": tool.version()},
        "versions": versions(),
        "source": prepared.uri,
        "scenario": prepared.scenario.name,
        "seed": ctx.seed,
        "dt_control": world.dt_control,
        "dt_physics": world.dt_physics,
        "steps": world.tick,
        "physics_steps": world.tick * world.substeps,
        "simulated_time": world.time,
        "wall_seconds": wall,
        "real_time_factor": world.time / wall if wall > 0 else None,
        "map": {
            "name": world.road.name,
            "lanes": world.road.lane_count,
            "lane_width": world.road.lane_width,
            "length": world.road.length,
            "scenario_lanes_counted_from": LaneNumbers(world.road).default_side,
            "telemetry_lanes": "1 = rightmost lane in the driving direction",
        },
        "parameter_values": {"source": ctx.values.source, "values": ctx.values.table()},
        "actors": actors,
        "lights": dict(ctx.lights),
        "notes": [*prepared.compiled.notes, *prepared.plan_notes],
        "outcome": {
            "status": outcome.status,
            "reason": outcome.reason,
            "tick": outcome.tick,
            "time": outcome.time,
        },
    }
