"""``run(path)``: check, instantiate, compile, tick — and write what happened.

The stages, in order (each one package):

1. ``osc2check.analysis.analyze``: error diagnostics stop here
   (:class:`~osc2runner.errors.ScenarioError`, exit status 2);
2. ``instance``: the checker's witness for the seed (parameter values, every
   actor's catalogue row, size and start), the actors and the map;
3. ``compile``: the behaviour tree, against a compile environment;
4. ``execution``: the world built at the witness's starts, then the one tick
   loop — nothing reads the wall clock;
5. ``output``: telemetry, events, metadata (and plots), also when the run fails
   or is interrupted.

Outcomes: ``success`` (the scenario's behaviour succeeded, or only open-ended
actions were still running at the time limit), ``failure`` (a failed phase, the
``fail`` event, a collision no ``avoid_collisions(false)`` allowed),
``timeout`` (the time limit with bounded phases still running),
``interrupted`` (SIGINT, SIGTERM or SIGHUP: the loop stops at the end of the
tick, the files are written, then :class:`RunInterrupted` is raised), ``error``
(the physics diverged: the result is returned; or a bug: the exception
propagates after writing).

The options are checked before anything runs (:mod:`osc2runner.options`:
:class:`~osc2runner.options.OptionError`, a ``ValueError``); every file is written
whole or not at all (:mod:`osc2runner.output.files`), ``run.json`` last.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
import py_trees

from osc2check import codes
from osc2check.analysis import Analysis, SourceInput, analyze
from osc2check.config import Config, ConfigError, config_for
from osc2check.diagnostics import Severity
from osc2check.plugins import PluginError
from osc2check.semantics.roots import RootScenarioError, file_scenarios, root_scenario
from osc2check.semantics.symbols import Symbol
from osc2check.source import decode_source
from osc2check.verify.witness import Witness
from osc2runner.behaviours.towing import hitches_at_start
from osc2runner.behaviours.traffic import run_plans
from osc2runner.compile.environment import CompileEnvironment
from osc2runner.compile.registry import MethodRegistry, standard_registry
from osc2runner.compile.tree import CompiledScenario, compile_scenario
from osc2runner.errors import RunProblem, ScenarioError
from osc2runner.execution.context import LogRecord, RunContext, fresh_blackboard
from osc2runner.execution.coverage import RunCoverage
from osc2runner.execution.drivers import controllers_for, drive_with_sut
from osc2runner.execution.initializer import start_specs
from osc2runner.execution.loop import TickLoop
from osc2runner.execution.outcome import OutcomeStatus, RunOutcome
from osc2runner.execution.signals import Interrupts, exit_status, signal_name
from osc2runner.execution.vehicle_models import kinematic_specs
from osc2runner.export import ExportTargets
from osc2runner.instance import ScenarioInstance, instantiate
from osc2runner.instance.actors import environment_sky
from osc2runner.instance.light_plans import control_plans
from osc2runner.instance.lights import traffic_lights
from osc2runner.instance.roads import LaneNumbers
from osc2runner.options import (
    DT_CONTROL,
    DT_PHYSICS,
    RunOptions,
    check_duration,
    check_out,
)
from osc2runner.output.coverage import write_coverage
from osc2runner.output.lights import light_arrays, write_lights
from osc2runner.output.telemetry import Recorder, tick_time, write_data, write_metadata
from osc2runner.plugin_behaviours import runner_registry
from osc2runner.sim import World, versions
from osc2runner.sim.sky import Sky
from osc2runner.sim.vehicle import VehicleParams
from osc2runner.sut.driver import SutFault, call_sut, sut_info
from osc2runner.sut.loading import SutError, SutSpec, choose_actor

__all__ = [
    "Checked",
    "Compiled",
    "Prepared",
    "RunInterrupted",
    "RunOutcome",
    "RunResult",
    "build_world",
    "check_analysis",
    "check_file",
    "compile_checked",
    "compile_file",
    "execute",
    "prepare",
    "prepare_checked",
    "prepare_run",
    "run",
]

log = logging.getLogger(__name__)


@dataclass
class RunResult:
    """A finished (or stopped) run.

    ``telemetry[actor][channel]`` is a numpy array over the ticks (channels:
    :data:`osc2runner.output.telemetry.CHANNELS`); ``lights[light][column]`` the
    same for traffic lights (:data:`osc2runner.output.lights.LIGHT_COLUMNS`:
    ``semantic`` and ``bulbs`` per tick); ``events`` the event log;
    ``coverage`` every ``cover``/``record`` item with its samples (what
    ``coverage.json`` holds); ``outputs`` the files written.
    """

    outcome: RunOutcome
    telemetry: dict[str, dict[str, np.ndarray]]
    events: list[LogRecord]
    metadata: dict[str, Any]
    outputs: list[Path] = field(default_factory=list)
    coverage: RunCoverage = field(default_factory=RunCoverage)
    lights: dict[str, dict[str, np.ndarray]] = field(default_factory=dict)

    @property
    def success(self) -> bool:
        return self.outcome.ok

    def event_ticks(self, kind: str, name: str) -> list[int]:
        """Ticks of the log records of ``kind`` named ``name``."""
        return [r.tick for r in self.events if r.kind == kind and r.name == name]


class RunInterrupted(KeyboardInterrupt):
    """The run was interrupted (SIGINT, SIGTERM, SIGHUP or a ``KeyboardInterrupt``);
    ``result`` holds what was recorded and written, ``signum`` the signal (None for
    a ``KeyboardInterrupt`` raised by other means)."""

    def __init__(self, result: RunResult, signum: int | None = None) -> None:
        super().__init__(result.outcome.reason)
        self.result = result
        self.signum = signum


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

    world: World
    sut: dict[str, str] | None = None  # the system under test: its class and actor
    sut_fault: str | None = None  # the SUT failed to start (construction, reset): a run error


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
    """The scenario to run: ``--scenario``, else ``top``, else the one no other invokes."""
    program = analysis.programs[uri]
    result = program.files.get(uri)
    scenarios = file_scenarios(program.model, result.ast.declarations if result else ())
    try:
        return root_scenario(program.model, scenarios, name)
    except RootScenarioError as exc:
        choices = f" (choose one with --scenario: {', '.join(exc.choices)})" if exc.choices else ""
        raise ScenarioError([RunProblem(f"{uri}: {exc}{choices}")]) from None


@dataclass
class Checked:
    """A file checked once and its root scenario chosen (:func:`check_file`): what the
    runs of many seeds share (a campaign's worker checks once and compiles per seed)."""

    uri: str
    analysis: Analysis
    scenario: Symbol
    registry: MethodRegistry = field(default_factory=standard_registry)  # with the plug-ins


def check_file(
    path: str | Path,
    *,
    scenario: str | None = None,
    source: str | None = None,
    config: Config | None = None,
) -> Checked:
    """Parse, resolve and verify a file and choose the scenario to run; raises
    ScenarioError for input errors (error diagnostics, no such scenario).

    ``config`` is the checker's configuration (``[tool.osc2check]``: OSC2 version,
    dialect, maps, search paths, module map, the findings' policy); None reads the
    one that applies to ``path``, as ``osc2check`` does.
    """
    uri, text = _read(path, source)
    if config is None:
        config = config_for(path)
    try:
        registry = runner_registry(config.plugin_registry())
    except (ConfigError, PluginError) as exc:
        raise ScenarioError([RunProblem(f"{uri}: {exc}")]) from None
    analysis = analyze([SourceInput(uri, text)], config.analysis_options())
    return check_analysis(analysis, uri, scenario=scenario, registry=registry)


def check_analysis(
    analysis: Analysis,
    uri: str,
    *,
    scenario: str | None = None,
    registry: MethodRegistry | None = None,
) -> Checked:
    """The root scenario of ``uri`` in an analysis the checker made; raises ScenarioError
    for what stops a run: an error, or a form the runner does not execute (A308,
    ``osc2check.capabilities``), refused before tick 0 with the checker's own finding.
    ``registry``: the runner's methods with the plug-ins (the standard ones for None)."""
    refused = [
        d
        for d in analysis.diagnostics
        if d.severity is Severity.ERROR or d.code is codes.NOT_EXECUTED
    ]
    if refused:
        raise ScenarioError([], diagnostics=refused, texts=analysis.texts)
    chosen = _choose_scenario(analysis, uri, scenario)
    return Checked(uri, analysis, chosen, registry if registry is not None else standard_registry())


def compile_checked(
    checked: Checked,
    *,
    seed: int = 0,
    dt_control: float = DT_CONTROL,
    witness: Witness | None = None,
) -> Compiled:
    """Instantiate the checked scenario for ``seed`` (or with ``witness``) and compile it.
    The blackboard is cleared first: a compiled tree belongs to one run."""
    analysis, uri, sym = checked.analysis, checked.uri, checked.scenario
    instance = instantiate(analysis, uri, sym, seed, witness)
    model = analysis.programs[uri].model
    fresh_blackboard()
    run_ctx = RunContext(instance.network, instance.actors, dt=dt_control, seed=seed)
    run_ctx.schedule = instance.witness.schedule
    lights, problems = traffic_lights(model, instance.scenario, instance.values, instance.network)
    plans, plan_notes, plan_problems = control_plans(
        model, instance.scenario, lights, Path(uri).parent
    )
    if problems or plan_problems:
        raise ScenarioError(problems + plan_problems, texts=analysis.texts)
    run_ctx.traffic_lights = {light.name: light for light in lights}
    run_plans(run_ctx, plans)
    site, start = environment_sky(instance.actors, instance.values)
    run_ctx.sky = Sky(site, start, clock=run_ctx.sky.clock)
    env = CompileEnvironment(model, instance.values, checked.registry, run_ctx)
    compiled = compile_scenario(env, sym, analysis.texts)
    if compiled.problems:
        raise ScenarioError(compiled.problems, texts=analysis.texts)
    compiled.notes.extend(plan_notes)
    return Compiled(uri, analysis, instance, env, compiled)


def compile_file(
    path: str | Path,
    *,
    scenario: str | None = None,
    seed: int = 0,
    dt_control: float = DT_CONTROL,
    source: str | None = None,
    config: Config | None = None,
) -> Compiled:
    """Check a file, instantiate one of its scenarios and compile it; raises ScenarioError
    for input errors. The blackboard is cleared first: a compiled tree belongs to one run.
    """
    checked = check_file(path, scenario=scenario, source=source, config=config)
    return compile_checked(checked, seed=seed, dt_control=dt_control)


def build_world(
    c: Compiled,
    *,
    dt_control: float = DT_CONTROL,
    dt_physics: float = DT_PHYSICS,
    sut: SutSpec | None = None,
    kinematic: Sequence[str] = (),
) -> Prepared:
    """The world of a compiled scenario at the witness's starts, its controllers (the
    system under test in its actor's seat when ``sut`` is given) and its variables;
    the vehicles ``kinematic`` selects (names, patterns) on the kinematic model
    (:mod:`osc2runner.execution.vehicle_models`)."""
    ctx = c.ctx
    specs, problems = start_specs(c.instance.actors, hitches_at_start(c.compiled.start_uses))
    if problems:
        raise ScenarioError(problems, texts=c.analysis.texts)
    sut_actor = _sut_actor(c, sut) if sut is not None else None
    specs, wrong = kinematic_specs(specs, kinematic, sut_actor)
    if wrong:
        problems = [RunProblem(f"--kinematic: {why}", c.scenario.name_span) for why in wrong]
        raise ScenarioError(problems, texts=c.analysis.texts)
    world = World(ctx.network, specs, dt_control=dt_control, dt_physics=dt_physics)
    routes = {a.name: a.route for a in c.instance.witness.actors}
    controllers = controllers_for(world, routes, ctx.seed)
    ctx.attach(world, controllers)
    seat: dict[str, str] | None = None
    fault: str | None = None
    if sut is not None and sut_actor is not None:
        params = world.params(sut_actor)
        assert isinstance(params, VehicleParams)
        seat = {"class": sut.target, "actor": sut_actor}
        try:
            instance = sut.make()
            reset = getattr(instance, "reset", None)
            if callable(reset):
                info = sut_info(sut_actor, params, dt_control, ctx.seed, c.scenario.name)
                call_sut(type(instance).__name__, "reset", sut.step_timeout, reset, info)
            drive_with_sut(
                controllers, world, ctx.states, sut_actor, instance, ctx.record, sut.step_timeout
            )
        except SutFault as exc:  # the run ends before its first tick, as an error
            fault = str(exc)
    for name, fn in c.env.variable_inits:
        ctx.variables[name] = fn()
    return Prepared(c.uri, c.analysis, c.instance, c.env, c.compiled, world, seat, fault)


def _sut_actor(c: Compiled, sut: SutSpec) -> str:
    fields = {a.name: a.kind for a in c.instance.actors}
    try:
        return choose_actor(fields, sut.actor)
    except SutError as exc:
        raise ScenarioError(
            [RunProblem(f"--sut: {exc}", c.scenario.name_span)], texts=c.analysis.texts
        ) from None


def prepare_checked(
    checked: Checked,
    *,
    seed: int = 0,
    dt_control: float = DT_CONTROL,
    dt_physics: float = DT_PHYSICS,
    sut: SutSpec | None = None,
    witness: Witness | None = None,
    kinematic: Sequence[str] = (),
) -> Prepared:
    """Compile a checked scenario for ``seed`` and build its world (see :func:`prepare`)."""
    options = RunOptions(
        seed=seed, dt_control=dt_control, dt_physics=dt_physics, sut=sut, kinematic=tuple(kinematic)
    )
    return prepare_run(checked, options, witness=witness)


def prepare_run(
    checked: Checked, options: RunOptions, *, witness: Witness | None = None
) -> Prepared:
    """Compile a checked scenario for ``options.seed`` (or with ``witness``) and build
    its world with the options' steps and system under test."""
    c = compile_checked(checked, seed=options.seed, dt_control=options.dt_control, witness=witness)
    return build_world(
        c,
        dt_control=options.dt_control,
        dt_physics=options.dt_physics,
        sut=options.sut,
        kinematic=options.kinematic,
    )


def prepare(
    path: str | Path,
    *,
    scenario: str | None = None,
    seed: int = 0,
    dt_control: float = DT_CONTROL,
    dt_physics: float = DT_PHYSICS,
    source: str | None = None,
    sut: SutSpec | None = None,
    config: Config | None = None,
    kinematic: Sequence[str] = (),
) -> Prepared:
    """Check, instantiate, compile and build the world; raises ScenarioError for input
    errors. ``kinematic``: the vehicles (names, patterns) on the kinematic model."""
    checked = check_file(path, scenario=scenario, source=source, config=config)
    options = RunOptions(
        seed=seed, dt_control=dt_control, dt_physics=dt_physics, sut=sut, kinematic=tuple(kinematic)
    )
    return prepare_run(checked, options)


# ---------------------------------------------------------------------- running


def run(
    path: str | Path,
    *,
    scenario: str | None = None,
    seed: int = 0,
    out: str | Path | None = None,
    duration: float | None = None,
    dt_control: float = DT_CONTROL,
    dt_physics: float = DT_PHYSICS,
    plot: bool = False,
    progress: Callable[[float, float, float], None] | None = None,
    source: str | None = None,
    sut: SutSpec | str | None = None,
    config: Config | None = None,
    kinematic: Sequence[str] = (),
) -> RunResult:
    """Run one scenario of the file at ``path`` (see the module docstring).

    Parameters:
        path: the ``.osc`` file.
        scenario: which scenario (needed when the file declares several).
        seed: seed of the run, a non-negative integer: picks the checker's witness
            (parameter values, starts) and the random choices left open; recorded.
        out: folder for telemetry, events, metadata (and plots), created when missing;
            None writes nothing.
        duration: time limit in simulated seconds (default 600).
        dt_control: control period (tree tick) in seconds.
        dt_physics: physics step in seconds; ``dt_control`` must be a whole multiple.
        plot: also write PNG plots into ``out``.
        progress: called as ``progress(sim_time, limit, wall_seconds)`` every simulated second.
        source: the file's text, instead of reading ``path``.
        sut: the system under test (:mod:`osc2runner.sut`): a ``SutSpec``, or
            ``"module:Class"`` for the actor named ``sut`` or ``ego``.
        config: the checker's configuration (``osc2check.config.Config``: the OSC2
            version, dialect, maps, search paths, ...); None reads ``[tool.osc2check]``
            from the nearest configuration file above ``path``, as ``osc2check`` does.
        kinematic: the vehicles moved by the kinematic model (names, shell-style patterns:
            :mod:`osc2runner.execution.vehicle_models`); every other vehicle runs on the
            multibody model. ``run.json`` states each actor's (``actors.*.dynamics``).

    The result's outcome is ``error`` (and the files are written) when the physics
    diverged. Called from the main thread, the run installs handlers for SIGINT,
    SIGTERM and SIGHUP while it executes and restores the previous ones after it
    (:mod:`osc2runner.execution.signals`); from another thread it installs none.

    Raises:
        OptionError: a bad option, ``out`` included (a ``ValueError``; nothing ran).
        ScenarioError: the input has errors (nothing ran).
        SutError: the system under test cannot be loaded (a ``ValueError``; nothing ran).
        RunInterrupted: a signal or Ctrl-C; its ``result`` has what was recorded (and written).
    """
    options = RunOptions.checked(
        scenario=scenario,
        seed=seed,
        duration=duration,
        dt_control=dt_control,
        dt_physics=dt_physics,
        config=config,
        plot=plot,
        kinematic=kinematic,
    )
    if out is not None:
        check_out(out)
    spec = SutSpec(sut) if isinstance(sut, str) else sut
    if spec is not None:
        spec = spec.resolved()
        spec.load()
        options = replace(options, sut=spec)
    checked = check_file(path, scenario=options.scenario, source=source, config=options.config)
    prepared = prepare_run(checked, options)
    return execute(
        prepared, out=out, duration=options.duration, plot=options.plot, progress=progress
    )


def execute(
    prepared: Prepared,
    *,
    out: str | Path | None = None,
    duration: float | None = None,
    plot: bool = False,
    progress: Callable[[float, float, float], None] | None = None,
    export: ExportTargets | None = None,
    hard_stop: Callable[[RunResult, int], None] | None = None,
) -> RunResult:
    """Tick a prepared scenario to its end and write its files (see :func:`run`), and
    the exports ``export`` names (:mod:`osc2runner.export`), before ``run.json``.

    Signals are noted from before the first tick until the files are written
    (:class:`~osc2runner.execution.signals.Interrupts`): the first one ends the
    loop at a tick boundary (or where it is, in the system under test's code),
    later ones cannot cut a file short. With ``hard_stop`` (for a command's own
    process), a system under test that does not stop (a second signal, or its budget
    run out twice) is left where it is: the files are written from the signal handler
    and ``hard_stop(result, status)`` is called with the exit status; it must end the
    process (``os._exit``).
    """
    world = prepared.world
    limit = RunOptions(duration=check_duration(duration)).time_limit
    folder = check_out(out) if out is not None else None
    if log.isEnabledFor(logging.DEBUG):
        progress = _logging(progress)
    loop = TickLoop(prepared.root, prepared.ctx, world, limit=limit)

    def stop_now(status: OutcomeStatus, reason: str, signum: int | None) -> None:
        assert hard_stop is not None
        interrupts.consumed = True  # nothing more is taken from here on
        name = signal_name(signum) if signum is not None else None
        ctx = prepared.ctx
        outcome = RunOutcome(status, reason, ctx.tick, ctx.time, signal=name)
        ctx.record("outcome", outcome.status, outcome.reason)
        result = _finish(prepared, loop.recorder, outcome, 0.0, folder, plot, export)
        log.error("%s: the run ended at tick %d, its files written", reason, ctx.tick)
        hard_stop(result, exit_status(signum) if signum is not None else 2)

    with Interrupts(hard_stop=stop_now if hard_stop is not None else None) as interrupts:
        log.debug(
            "ticking scenario %s (signals caught: %s)", prepared.scenario.name, interrupts.installed
        )
        ticked = loop.run(progress, interrupts, fault=prepared.sut_fault)
        interrupts.writing = True
        result = _finish(
            prepared, ticked.recorder, ticked.outcome, ticked.wall_seconds, folder, plot, export
        )
    if ticked.outcome.status == "interrupted":
        raise RunInterrupted(result, ticked.signum) from ticked.error
    if ticked.error is not None:
        raise ticked.error
    return result


def _logging(
    progress: Callable[[float, float, float], None] | None,
) -> Callable[[float, float, float], None]:
    """``progress`` that also logs the simulated time (``--debug``: a marker tests wait for)."""

    def report(sim: float, limit: float, wall: float) -> None:
        log.debug("simulated %.1f s of %g s", sim, limit)
        if progress is not None:
            progress(sim, limit, wall)

    return report


def _finish(
    prepared: Prepared,
    recorder: Recorder,
    outcome: RunOutcome,
    wall: float,
    out: str | Path | None,
    plot: bool,
    export: ExportTargets | None = None,
) -> RunResult:
    """The result, and its files: telemetry and events, the plots, the exports,
    ``run.json`` last (a folder with a ``run.json`` has every file of its run)."""
    ctx = prepared.ctx
    metadata = _metadata(prepared, outcome, wall)
    coverage = ctx.coverage
    coverage.scenario, coverage.source = prepared.scenario.name, prepared.uri
    result = RunResult(outcome, recorder.arrays(), list(ctx.records), metadata, coverage=coverage)
    world = prepared.world
    ticks = recorder.ticks if recorder.names else world.tick + 1
    result.lights = light_arrays(ctx.traffic_lights.values(), ticks, world.dt_control)
    # checked before the run; it may have changed
    folder = check_out(out, create=True) if out is not None else None
    if folder is not None:
        result.outputs = write_data(folder, recorder, result.events)
        if result.lights:
            result.outputs.append(write_lights(folder / "lights.csv", result.lights))
        result.outputs.append(write_coverage(folder, coverage))
        if plot:
            from osc2runner.output.plots import plot_run

            result.outputs.extend(plot_run(result, folder, world.network))
    if export:
        from osc2runner.export import export_run

        result.outputs.extend(export_run(prepared, result, export))
    if folder is not None:
        result.outputs.append(write_metadata(folder, metadata, result.events))
    return result


def _metadata(prepared: Prepared, outcome: RunOutcome, wall: float) -> dict[str, Any]:
    from osc2check.output import tool

    ctx, world = prepared.ctx, prepared.world
    actors = {}
    for name, actor in ctx.actors.items():
        entry: dict[str, Any] = {"type": actor.type.name, "kind": actor.kind}
        if name in world.names:
            entry["dynamics"] = world.model_of(name)
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
            start = actor.start
            entry["start"] = {
                "road": start.road if start is not None else None,
                "lane_id": start.lane_id if start is not None else None,
                "lane": start.lane if start is not None else None,
                "s": spec.s,
                "t": spec.offset,
                "x": spec.x,
                "y": spec.y,
                "yaw": spec.yaw,
                "speed": spec.speed,
                "route": list(start.route) if start is not None else [],
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
        "simulated_time": tick_time(world.time, world.dt_control),
        "wall_seconds": wall,
        "real_time_factor": world.time / wall if wall > 0 else None,
        "map": {
            "name": prepared.instance.witness.map or world.network.name,
            "source": world.network.source,
            "roads": len(world.network.roads),
            "junctions": len(world.network.junctions),
            "scenario_lanes_counted_from": LaneNumbers(world.network).default_side,
            "telemetry_lanes": "lane: 1 = rightmost driving lane in its direction of travel; "
            "lane_id: OpenDRIVE id; s, t: road coordinates on `road`",
        },
        "parameter_values": {
            "source": prepared.instance.values.source,
            "values": prepared.instance.values.table(),
        },
        "witness": prepared.instance.witness.to_json(),
        "actors": actors,
        "lights": dict(ctx.lights),
        "traffic_lights": {
            name: {
                "x": light.x,
                "y": light.y,
                "yaw": light.yaw,
                "group": light.group,
                "placed": light.placed,
            }
            for name, light in ctx.traffic_lights.items()
        },
        "coverage": {
            "file": "coverage.json",
            "items": {
                i.name: {"kind": i.kind, "samples": len(i.samples)} for i in ctx.coverage.items
            },
        },
        "notes": [*prepared.compiled.notes, *prepared.instance.witness.notes],
        **({"sut": prepared.sut} if prepared.sut is not None else {}),
        "outcome": {
            "status": outcome.status,
            "reason": outcome.reason,
            "tick": outcome.tick,
            "time": tick_time(outcome.time, world.dt_control),
            **({"signal": outcome.signal} if outcome.signal is not None else {}),
        },
    }
