"""``run(path)``: check, instantiate, compile, tick — and write what happened.

The stages, in order (each one package):

1. ``osc2check.analysis.analyze``: error diagnostics stop here
   (:class:`~osc2runner.errors.ScenarioError`, exit status 2);
2. ``instance``: the checker's witness for the seed (parameter values, every
   actor's catalogue row, size and start), the actors and the road;
3. ``compile``: the behaviour tree, against a compile environment;
4. ``execution``: the world built at the witness's starts, then the one tick
   loop — nothing reads the wall clock;
5. ``output``: telemetry, events, metadata (and plots), also when the run fails
   or is interrupted.

Outcomes: ``success`` (the scenario's behaviour succeeded, or only open-ended
actions were still running at the time limit), ``failure`` (a failed phase, the
``fail`` event, a collision no ``avoid_collisions(false)`` allowed),
``timeout`` (the time limit with bounded phases still running),
``interrupted``, ``error`` (a bug: the exception propagates after writing).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import py_trees

from osc2check.analysis import Analysis, SourceInput, analyze
from osc2check.diagnostics import Severity
from osc2check.semantics.phases import time_zero
from osc2check.semantics.symbols import Symbol
from osc2check.source import decode_source
from osc2check.syntax import ast
from osc2runner.compile.environment import CompileEnvironment
from osc2runner.compile.registry import standard_registry
from osc2runner.compile.tree import CompiledScenario, compile_scenario
from osc2runner.errors import RunProblem, ScenarioError
from osc2runner.execution.context import LogRecord, RunContext, fresh_blackboard
from osc2runner.execution.coverage import RunCoverage
from osc2runner.execution.drivers import controllers_for
from osc2runner.execution.initializer import start_specs
from osc2runner.execution.loop import RunOutcome, TickLoop
from osc2runner.instance import ScenarioInstance, instantiate
from osc2runner.instance.roads import LaneNumbers
from osc2runner.output.coverage import write_coverage
from osc2runner.output.telemetry import Recorder, write
from osc2runner.sim import World, versions

__all__ = [
    "Compiled",
    "Prepared",
    "RunInterrupted",
    "RunOutcome",
    "RunResult",
    "compile_file",
    "execute",
    "prepare",
    "run",
]

log = logging.getLogger(__name__)

DEFAULT_TIME_LIMIT = 600.0  # s of simulated time


@dataclass
class RunResult:
    """A finished (or stopped) run.

    ``telemetry[actor][channel]`` is a numpy array over the ticks (channels:
    :data:`osc2runner.output.telemetry.CHANNELS`); ``events`` the event log;
    ``coverage`` every ``cover``/``record`` item with its samples (what
    ``coverage.json`` holds); ``outputs`` the files written.
    """

    outcome: RunOutcome
    telemetry: dict[str, dict[str, np.ndarray]]
    events: list[LogRecord]
    metadata: dict[str, Any]
    outputs: list[Path] = field(default_factory=list)
    coverage: RunCoverage = field(default_factory=RunCoverage)

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
class Compiled:
    """A scenario instantiated and compiled, before its world is built (``compile_file``)."""

    uri: str
    analysis: Analysis
    instance: ScenarioInstance
    env: CompileEnvironment
    compiled: CompiledScenario

    @property
    def scenario(self) -> Symbol:
        return self.instance.scenario

    @property
    def ctx(self) -> RunContext:
        return self.env.run

    @property
    def root(self) -> py_trees.behaviour.Behaviour:
        return self.compiled.root


@dataclass
class Prepared(Compiled):
    """A compiled scenario with its world built at the witness's starts (``prepare``)."""

    world: World | None = None


# ---------------------------------------------------------------------- preparation


def _read(path: str | Path, source: str | None) -> tuple[str, str]:
    uri = str(path)
    if source is not None:
        return uri, source
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise ScenarioError([RunProblem(f"{uri}: cannot read: {exc.strerror or exc}")]) from None
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
        raise ScenarioError([RunProblem(f"{uri}: no scenario `{name}` (scenarios: {known})")])
    if not symbols:
        raise ScenarioError([RunProblem(f"{uri}: declares no scenario to run")])
    if len(symbols) > 1:
        names = ", ".join(s.name for s in symbols)
        raise ScenarioError(
            [RunProblem(f"{uri}: declares several scenarios ({names}); choose one with --scenario")]
        )
    return symbols[0]


def compile_file(
    path: str | Path,
    *,
    scenario: str | None = None,
    seed: int = 0,
    dt_control: float = 0.05,
    source: str | None = None,
) -> Compiled:
    """Check a file, instantiate one of its scenarios and compile it; raises ScenarioError
    for input errors. The blackboard is cleared first: a compiled tree belongs to one run.
    """
    uri, text = _read(path, source)
    analysis = analyze([SourceInput(uri, text)])
    errors = [d for d in analysis.diagnostics if d.severity is Severity.ERROR]
    if errors:
        raise ScenarioError([], diagnostics=errors, texts=analysis.texts)
    sym = _choose_scenario(analysis, uri, scenario)
    instance = instantiate(analysis, uri, sym, seed)
    model = analysis.programs[uri].model
    fresh_blackboard()
    run_ctx = RunContext(instance.road, instance.actors, dt=dt_control, seed=seed)
    env = CompileEnvironment(model, instance.values, standard_registry(), run_ctx)
    compiled = compile_scenario(env, sym, analysis.texts)
    if compiled.problems:
        raise ScenarioError(compiled.problems, texts=analysis.texts)
    return Compiled(uri, analysis, instance, env, compiled)


def prepare(
    path: str | Path,
    *,
    scenario: str | None = None,
    seed: int = 0,
    dt_control: float = 0.05,
    dt_physics: float = 0.002,
    source: str | None = None,
) -> Prepared:
    """Check, instantiate, compile and build the world; raises ScenarioError for input errors."""
    c = compile_file(path, scenario=scenario, seed=seed, dt_control=dt_control, source=source)
    ctx = c.ctx
    specs, problems = start_specs(c.instance.actors, ctx.lanes)
    if problems:
        raise ScenarioError(problems, texts=c.analysis.texts)
    do = next((m for m in _members(c) if isinstance(m, ast.DoDirective)), None)
    if do is not None:  # the witness realised what begins at time 0
        ctx.placed.update(time_zero(do.member.body).starts)
    world = World(ctx.road, specs, dt_control=dt_control, dt_physics=dt_physics)
    ctx.attach(world, controllers_for(world, ctx.road))
    for name, fn in c.env.variable_inits:
        ctx.variables[name] = fn()
    return Prepared(c.uri, c.analysis, c.instance, c.env, c.compiled, world)


def _members(c: Compiled) -> list[ast.Node]:
    """The members of the scenario's declarations, supertypes first (its `do` is the last)."""
    model = c.env.model
    found: list[ast.Node] = []
    for sym in reversed(list(model.ancestors(c.scenario))):
        if isinstance(sym.decl, ast.StructuredDecl):
            found.extend(sym.decl.members)
    return list(reversed(found))


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
    source: str | None = None,
) -> RunResult:
    """Run one scenario of the file at ``path`` (see the module docstring).

    Parameters:
        path: the ``.osc`` file.
        scenario: which scenario (needed when the file declares several).
        seed: seed of the run: picks the checker's witness (parameter values, starts)
            and the random choices left open; recorded.
        out: folder for telemetry, events, metadata (and plots); None writes nothing.
        duration: time limit in simulated seconds (default 600).
        dt_control: control period (tree tick) in seconds.
        dt_physics: physics step in seconds; ``dt_control`` must be a whole multiple.
        plot: also write PNG plots into ``out``.
        progress: called as ``progress(sim_time, limit, wall_seconds)`` every simulated second.
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
    """Tick a prepared scenario to its end and write its files (see :func:`run`)."""
    world = prepared.world
    assert world is not None
    limit = DEFAULT_TIME_LIMIT if duration is None else float(duration)
    ticked = TickLoop(prepared.root, prepared.ctx, world, limit=limit).run(progress)
    result = _finish(prepared, ticked.recorder, ticked.outcome, ticked.wall_seconds, out, plot)
    if isinstance(ticked.error, KeyboardInterrupt):
        raise RunInterrupted(result) from ticked.error
    if ticked.error is not None:
        raise ticked.error
    return result


def _finish(
    prepared: Prepared,
    recorder: Recorder,
    outcome: RunOutcome,
    wall: float,
    out: str | Path | None,
    plot: bool,
) -> RunResult:
    ctx = prepared.ctx
    metadata = _metadata(prepared, outcome, wall)
    coverage = ctx.coverage
    coverage.scenario, coverage.source = prepared.scenario.name, prepared.uri
    result = RunResult(outcome, recorder.arrays(), list(ctx.records), metadata, coverage=coverage)
    if out is not None:
        folder = Path(out)
        result.outputs = write(folder, recorder, result.events, metadata)
        result.outputs.append(write_coverage(folder, coverage))
        if plot:
            from osc2runner.output.plots import plot_run

            result.outputs.extend(plot_run(result, folder))
    return result


def _metadata(prepared: Prepared, outcome: RunOutcome, wall: float) -> dict[str, Any]:
    from osc2check.output import tool

    ctx, world = prepared.ctx, prepared.world
    assert world is not None
    actors = {}
    for name, actor in ctx.actors.items():
        entry: dict[str, Any] = {"type": actor.type.name, "kind": actor.kind}
        if actor.row is not None and actor.params is not None:
            entry["model"] = actor.row.key
            entry["category"] = actor.row.category
            entry["size"] = {
                "length": actor.params.length,
                "width": actor.params.width,
                "height": actor.params.height,
            }
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
        "parameter_values": {
            "source": prepared.instance.values.source,
            "values": prepared.instance.values.table(),
        },
        "witness": prepared.instance.witness.to_json(),
        "actors": actors,
        "lights": dict(ctx.lights),
        "coverage": {
            "file": "coverage.json",
            "items": {
                i.name: {"kind": i.kind, "samples": len(i.samples)} for i in ctx.coverage.items
            },
        },
        "notes": [*prepared.compiled.notes, *prepared.instance.witness.notes],
        "outcome": {
            "status": outcome.status,
            "reason": outcome.reason,
            "tick": outcome.tick,
            "time": outcome.time,
        },
    }
