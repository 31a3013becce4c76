"""The ``osc2run`` command: argv -> run -> summary -> exit status.

Exit status: 0 when the scenario ends successfully; 1 when it fails (a failed
phase, the ``fail`` event, a collision, the time limit with bounded phases
still running); 2 for usage errors (one line ``osc2run: error: ...``; a bad
option or ``--out`` is found before the checker runs), input errors (the
checker's error diagnostics or the runner's own problems are printed, and
nothing runs), a run that ended as ``error`` (the physics diverged, or the
system under test failed: it raised, ``SystemExit`` and ``KeyboardInterrupt``
included, or ran past ``--step-timeout``; files written) and internal errors;
128 + the signal's number when SIGINT (130), SIGTERM (143) or SIGHUP (129)
interrupted it, at any point, the system under test's code included (what was
recorded is written first; a second signal ends a system under test that does
not stop).

On a terminal a progress bar shows simulated time and the real-time factor;
otherwise one summary is printed at the end.
"""

from __future__ import annotations

import argparse
import dataclasses
import logging
import os
import sys
import traceback
from collections.abc import Callable, Sequence
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, NoReturn, TextIO, TypeVar

from osc2check.config import (
    ConfigError,
    add_config_arguments,
    add_language_arguments,
    chosen_config,
    config_for,
    with_language_arguments,
)
from osc2runner.errors import ScenarioError
from osc2runner.execution.signals import (
    Caught,
    SignalInterrupt,
    exit_status,
    raising,
    signal_name,
)
from osc2runner.options import (
    DT_CONTROL,
    DT_PHYSICS,
    TIME_LIMIT,
    OptionError,
    RunOptions,
    check_kinematic,
    check_out,
    check_seed,
    check_steps,
    check_time,
)

if TYPE_CHECKING:
    from osc2check.config import Config
    from osc2check.verify.witness import Witness
    from osc2runner.campaign.steering import BinRef
    from osc2runner.errors import RunProblem
    from osc2runner.runner import Checked, Prepared, RunResult
    from osc2runner.sut.loading import SutSpec

__all__ = [
    "EXIT_ERROR",
    "EXIT_FAILURE",
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "UsageError",
    "build_parser",
    "main",
]

EXIT_OK, EXIT_FAILURE, EXIT_ERROR, EXIT_INTERRUPTED = 0, 1, 2, 130


class UsageError(Exception):
    """A bad command line (exit status 2, one line ``osc2run: error: ...``)."""


class _ArgumentParser(argparse.ArgumentParser):
    """argparse that reports a bad command line as one line, ``osc2run: error: ...``."""

    def error(self, message: str) -> NoReturn:
        raise UsageError(message)


def _number(text: str) -> float | str:
    """An option's text as a float, or the text itself when it is not a number (which
    the option's check then refuses as such)."""
    try:
        return float(text)
    except ValueError:
        return text


Checked_ = TypeVar("Checked_")


def _checked(
    text: str | None, parse: Callable[[str], object], check: Callable[[object], Checked_]
) -> Checked_ | None:
    """An option's text parsed and checked; an OptionError quotes the text as given."""
    if text is None:
        return None
    try:
        value: object = parse(text)
    except ValueError:
        value = text
    try:
        return check(value)
    except OptionError as exc:
        raise OptionError(exc.name, text, exc.why) from None


def _version() -> str:
    from osc2check.output import tool

    return tool.version()


def build_parser() -> argparse.ArgumentParser:
    p = _ArgumentParser(
        prog="osc2run",
        description="Run an ASAM OpenSCENARIO DSL 2.x scenario in the MuJoCo world.",
        epilog="exit status: 0 success, 1 scenario failed, 2 usage, input or internal error "
        "or diverged physics, 128 + N stopped by signal N (130 SIGINT, 143 SIGTERM, "
        "129 SIGHUP); what was recorded is written first",
    )
    p.add_argument("file", metavar="FILE", nargs="?", help="the .osc file")
    p.add_argument("--scenario", metavar="NAME", help="the scenario to run (when several)")
    p.add_argument(
        "--seed",
        default="0",
        metavar="N",
        help="seed of the run, a non-negative integer (default 0)",
    )
    p.add_argument(
        "--duration",
        metavar="T",
        help=f"time limit in simulated seconds, positive (default {TIME_LIMIT:g})",
    )
    p.add_argument(
        "--out",
        metavar="DIR",
        help="write telemetry.csv, events.csv, run.json here (created when missing; checked "
        "before anything runs)",
    )
    p.add_argument("--plot", action="store_true", help="also write PNG plots (needs --out)")
    p.add_argument(
        "--dt-control",
        default=repr(DT_CONTROL),
        metavar="S",
        help=f"control period: one tree tick (default {DT_CONTROL:g}); a whole multiple of "
        "--dt-physics",
    )
    p.add_argument(
        "--dt-physics",
        default=repr(DT_PHYSICS),
        metavar="S",
        help=f"physics step (default {DT_PHYSICS:g})",
    )
    p.add_argument(
        "--kinematic",
        action="append",
        metavar="NAMES",
        help="move these vehicles by the kinematic model, the lighter one for background "
        "traffic: actor names or shell-style patterns, comma-separated ('npc*', '*'); "
        "the others run on the multibody model (docs/world.md); repeatable",
    )
    p.add_argument(
        "--sut",
        metavar="MODULE:CLASS",
        help="a system under test drives the actor named sut or ego (module:Class, or "
        "path/file.py:Class; default: [tool.osc2run] sut in pyproject.toml)",
    )
    p.add_argument("--sut-actor", metavar="NAME", help="the actor the system under test drives")
    add_language_arguments(p)
    add_config_arguments(p)
    p.add_argument(
        "--step-timeout",
        metavar="S",
        help="wall-clock limit in seconds of each call into the system under test (its "
        "construction, reset and every step; default 60): over it the run ends as error",
    )
    p.add_argument(
        "--bin",
        metavar="ITEM=INDEX",
        help="draw the witness inside bucket INDEX of cover item ITEM (replays a campaign's "
        "directed run)",
    )
    c = p.add_argument_group("campaigns (docs/campaigns.md)")
    c.add_argument("--runs", metavar="N", help="run N concrete tests of the scenario: a campaign")
    c.add_argument(
        "--jobs",
        metavar="J",
        help="workers (default: one per processor; with --engine ray, the number of Ray actors)",
    )
    c.add_argument(
        "--engine",
        choices=("local", "ray"),
        default="local",
        help="local process pool (default) or a Ray cluster",
    )
    c.add_argument(
        "--address",
        metavar="auto|HOST:PORT",
        help="the Ray cluster (default: a local Ray instance)",
    )
    c.add_argument(
        "--strategy",
        choices=("random", "cover"),
        default="random",
        help="random: seeds S..S+N-1; cover: fill the scenario's cover bins",
    )
    c.add_argument(
        "--run-timeout",
        metavar="S",
        help="wall-clock limit of one run in seconds "
        "(default 600): a run over it is recorded as error",
    )
    c.add_argument(
        "--resume",
        metavar="DIR",
        help="finish the campaign in DIR: its finished runs are kept (FILE and options "
        "default to the campaign's, but --sut: give it again, or --trust-folder)",
    )
    c.add_argument(
        "--trust-folder",
        action="store_true",
        help="with --resume: import the system under test the folder's campaign.json names",
    )
    c.add_argument(
        "--force",
        action="store_true",
        help="let --out write into a non-empty folder that holds no campaign of the scenario",
    )
    from osc2runner.export.command import add_export_options

    add_export_options(p)
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar, summary only")
    p.add_argument(
        "--no-cache",
        action="store_true",
        help="neither read nor write the start-up cache (the parser's tables, the analysed "
        "standard library; OSC2_CACHE_DIR says where it is); a campaign's workers follow",
    )
    p.add_argument("--version", action="version", version=f"%(prog)s {_version()}")
    p.add_argument("--debug", action="store_true", help="log details; show tracebacks")
    return p


def _parse(argv: list[str]) -> argparse.Namespace:
    """The command line, every option checked (UsageError, OptionError)."""
    args = build_parser().parse_args(argv)
    if args.no_cache:
        from osc2check import cache

        cache.set_enabled(False)  # in the environment too: the workers inherit it
    args.given = {a.split("=", 1)[0] for a in argv if a.startswith("--")}
    args.campaign = args.runs is not None or args.resume is not None
    if args.campaign:
        from osc2runner.campaign.command import campaign_arguments

        campaign_arguments(args)
    elif args.file is None:
        raise UsageError("the following arguments are required: FILE")
    else:
        for name in ("jobs", "address", "run_timeout"):
            if getattr(args, name) is not None:
                raise UsageError(f"--{name.replace('_', '-')} needs --runs N (a campaign)")
        for name in ("trust_folder", "force"):
            if getattr(args, name):
                raise UsageError(f"--{name.replace('_', '-')} needs --runs N (a campaign)")
    if args.plot and not args.out:
        raise UsageError("--plot needs --out DIR")
    args.seed = _checked(args.seed, int, check_seed)
    args.duration = _checked(args.duration, float, lambda v: check_time("duration", v))
    args.run_timeout = _checked(args.run_timeout, float, lambda v: check_time("run_timeout", v))
    args.step_timeout = _checked(args.step_timeout, float, lambda v: check_time("step_timeout", v))
    given = {"dt_control": args.dt_control, "dt_physics": args.dt_physics}
    try:
        args.dt_control, args.dt_physics = check_steps(
            _number(args.dt_control), _number(args.dt_physics)
        )
    except OptionError as exc:
        raise OptionError(exc.name, given[exc.name], exc.why) from None  # the text given
    if args.out is not None:
        args.out = check_out(args.out)  # a bad --out is found before the checker runs
    args.config = _config(args)
    from osc2runner.export.command import export_arguments

    export_arguments(args)
    args.sut_spec = _sut(args)
    args.kinematic = _kinematic(args.kinematic)
    if args.bin is not None:
        from osc2runner.campaign.steering import bin_ref

        try:
            args.bin = bin_ref(args.bin)
        except ValueError as exc:
            raise UsageError(f"--bin {exc}") from None
    args.options = RunOptions(
        scenario=args.scenario,
        seed=args.seed,
        duration=args.duration,
        dt_control=args.dt_control,
        dt_physics=args.dt_physics,
        sut=args.sut_spec,
        config=args.config,
        plot=args.plot,
        kinematic=args.kinematic,
    )  # checked above, each value with the text given
    return args


def _kinematic(given: list[str] | None) -> tuple[str, ...]:
    """``--kinematic`` (given any number of times, each a comma-separated list)."""
    if not given:
        return ()
    items = [item for text in given for item in text.split(",")]
    try:
        return check_kinematic(items)
    except OptionError as exc:
        raise OptionError(exc.name, ",".join(given), exc.why) from None


def _config(args: argparse.Namespace) -> Config | None:
    """The checker's configuration for FILE (``--config FILE``, ``--isolated``, else the
    ``[tool.osc2check]`` above FILE: what ``osc2check`` reads with the same options) with
    ``--osc-version`` and ``--dialect`` on top; None without a FILE or ``--config`` (a
    campaign resumed from its folder reads it there)."""
    try:
        chosen = chosen_config(args)
        if chosen is None and args.file is None:
            return None
        config = with_language_arguments(
            chosen if chosen is not None else config_for(args.file), args
        )
        config.plugin_registry()  # a plug-in that cannot be loaded: said before anything runs
        return config
    except ConfigError as exc:
        raise UsageError(str(exc)) from None


def _sut(args: argparse.Namespace) -> SutSpec | None:
    """The system under test of the command line or ``[tool.osc2run]``; checked by
    importing it (a usage error when it cannot be used)."""
    from osc2runner.sut.loading import SutError, SutSpec, configured_sut

    spec: SutSpec | None
    try:
        if args.sut is not None:
            spec = SutSpec(args.sut, args.sut_actor).resolved()
        elif args.file is not None and not args.isolated:
            spec, _ = configured_sut(args.file)
            if spec is not None and args.sut_actor is not None:
                spec = SutSpec(spec.target, args.sut_actor)
        else:
            spec = None
        if spec is None and args.sut_actor is not None:
            raise UsageError("--sut-actor needs --sut MODULE:CLASS")
        if spec is None and args.step_timeout is not None:
            raise UsageError("--step-timeout needs --sut MODULE:CLASS")
        if spec is not None and args.step_timeout is not None:
            spec = dataclasses.replace(spec, step_timeout=args.step_timeout)
        if spec is not None:
            spec.load()
    except SutError as exc:
        raise UsageError(f"--sut: {exc}") from None
    return spec


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``) and return the exit status."""
    args_list = list(sys.argv[1:] if argv is None else argv)
    try:
        with raising() as caught:
            return _main(args_list, caught)
    except SignalInterrupt as exc:  # outside the run's loop (the checker, a summary)
        sys.stderr.write(f"osc2run: interrupted by {signal_name(exc.signum)}\n")
        return exit_status(exc.signum)
    except KeyboardInterrupt:
        sys.stderr.write("osc2run: interrupted\n")
        return EXIT_INTERRUPTED


def _main(args_list: list[str], caught: Caught) -> int:
    try:
        args = _parse(args_list)
    except SystemExit as exc:  # --help, --version
        return exc.code if isinstance(exc.code, int) else EXIT_ERROR
    except UsageError as exc:
        sys.stderr.write(f"osc2run: error: {_one_line(str(exc))}\n")
        return EXIT_ERROR
    except OptionError as exc:
        sys.stderr.write(f"osc2run: error: {_one_line(exc.cli)}\n")
        return EXIT_ERROR
    logging.basicConfig(
        level=logging.DEBUG if args.debug else logging.WARNING,
        format="osc2run: %(levelname)s: %(name)s: %(message)s",
        stream=sys.stderr,
    )
    try:
        if args.campaign:
            from osc2runner.campaign.command import run_command

            return run_command(args, sys.stdout, sys.stderr)
        return _run(args, sys.stdout, sys.stderr)
    except BrokenPipeError:  # the reader went away (`osc2run ... | head`): stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return EXIT_FAILURE
    except ScenarioError as exc:
        _print_input_errors(exc, sys.stderr)
        return EXIT_ERROR
    except OptionError as exc:  # --out changed under the run
        sys.stderr.write(f"osc2run: error: {_one_line(exc.cli)}\n")
        return EXIT_ERROR
    except Exception as exc:  # the one guard of this entry point
        if caught.first is not None:  # what the signal cut short failed its own way
            sys.stderr.write(f"osc2run: interrupted by {signal_name(caught.first)}\n")
            return exit_status(caught.first)
        if args.debug:
            traceback.print_exc(file=sys.stderr)
        sys.stderr.write(f"osc2run: internal error: {type(exc).__name__}: {exc}\n")
        if not args.debug:
            sys.stderr.write("osc2run: run with --debug to see the traceback\n")
        return EXIT_ERROR


def _run(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    from osc2runner.runner import RunInterrupted, check_file, execute, prepare_run

    options: RunOptions = args.options
    if not Path(args.file).exists():
        raise ScenarioError([_problem(f"{args.file}: no such file")])
    checked = check_file(args.file, scenario=options.scenario, config=options.config)
    witness = _witness_in_bin(checked, options, args.bin) if args.bin is not None else None
    prepared = prepare_run(checked, options, witness=witness)
    interactive = out.isatty() and not args.quiet
    files = {
        "out": args.out,
        "plot": options.plot,
        "export": args.export_targets,
        "hard_stop": partial(_hard_exit, out),
    }
    try:
        if interactive:
            result = _with_progress(prepared, options, partial(execute, **files))
        else:
            result = execute(prepared, duration=options.duration, **files)
    except RunInterrupted as exc:
        _summary(exc.result, out)
        return exit_status(exc.signum)
    _summary(result, out)
    if (
        result.outcome.status == "error"
    ):  # the physics diverged, the SUT failed (a bug is re-raised)
        return EXIT_ERROR
    return EXIT_OK if result.success else EXIT_FAILURE


def _hard_exit(out: TextIO, result: RunResult, status: int) -> None:
    """End the process now (a system under test that does not stop: its run's files are
    written), with the run's summary."""
    _summary(result, out)
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    os._exit(status)


def _witness_in_bin(checked: Checked, options: RunOptions, where: BinRef) -> Witness:
    """The witness drawn inside the cover bin ``--bin``, as a campaign's directed run's is."""
    from osc2runner.campaign.steering import cover_items, directed_witness

    items = cover_items(checked, dt_control=options.dt_control)
    return directed_witness(checked, items, where, options.seed)


def _with_progress(
    prepared: Prepared, options: RunOptions, execute: Callable[..., RunResult]
) -> RunResult:
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    limit = options.time_limit
    columns = (
        TextColumn("[bold]{task.description}"),
        BarColumn(),
        TextColumn("{task.fields[sim]:>8} / {task.total:g} s simulated"),
        TextColumn("{task.fields[rtf]}"),
        TimeElapsedColumn(),
    )
    with Progress(*columns, transient=True) as progress:
        task = progress.add_task(prepared.scenario.name, total=limit, sim="0.0", rtf="")

        def report(sim: float, total: float, wall: float) -> None:
            rtf = f"{sim / wall:.0f}x real time" if wall > 0 else ""
            progress.update(task, completed=sim, sim=f"{sim:.1f}", rtf=rtf)

        return execute(prepared, duration=options.duration, progress=report)


def _summary(result: RunResult, out: TextIO) -> None:
    """The run's summary: outcome, system under test, collisions, what was simulated, the
    events emitted, the files; the wall time and the real-time factor (this machine's)
    on a line of their own."""
    meta = result.metadata
    o = result.outcome
    rtf = meta.get("real_time_factor")
    out.write(
        f"scenario {meta['scenario']} ({meta['source']}): {o.status} at "
        f"{o.time:.2f} s (tick {o.tick}): {o.reason}\n"
    )
    sut = meta.get("sut")
    if sut:
        acts = [e for e in result.events if e.kind == "sut" and e.name == "intervenes"]
        when = f", first at {acts[0].time:.2f} s" if acts else ""
        out.write(
            f"  system under test: {sut['class']} driving {sut['actor']} "
            f"({len(acts)} intervention{'' if len(acts) == 1 else 's'}{when})\n"
        )
    for line in _impacts(result):
        out.write(f"  {line}\n")
    out.write(f"  simulated {meta['simulated_time']:.2f} s in {meta['steps']} ticks\n")
    out.write(
        f"  wall time (this machine): {meta['wall_seconds']:.2f} s"
        + (f", {rtf:.0f}x real time" if rtf else "")
        + "\n"
    )
    emitted = [e for e in result.events if e.kind == "emit"]
    if emitted:
        names = ", ".join(f"{e.name}@{e.time:.2f}s" for e in emitted[:8])
        more = f" (+{len(emitted) - 8} more)" if len(emitted) > 8 else ""
        out.write(f"  events: {names}{more}\n")
    for path in result.outputs:
        out.write(f"  wrote {path}\n")
    out.flush()


def _impacts(result: RunResult) -> list[str]:
    """One line per collision: who, when, each one's speed and the closing speed."""
    import numpy as np

    from osc2runner.campaign.kpis import KPH, closing_speed

    lines = []
    for e in result.events:
        if e.kind != "collision" or len(e.actors) != 2:
            continue
        a, b = (result.telemetry.get(n) for n in e.actors)
        if a is None or b is None:
            continue
        row = min(int(np.searchsorted(a["tick"], e.tick)), len(a["tick"]) - 1)
        speeds = ", ".join(
            f"{n} at {float(ch['speed'][min(row, len(ch['speed']) - 1)]) * KPH:.1f} kph"
            for n, ch in zip(e.actors, (a, b), strict=True)
        )
        closing = closing_speed(a, b, row) * KPH
        lines.append(
            f"collision at {e.time:.2f} s: {speeds}; impact speed (closing, along "
            f"{e.actors[0]}'s heading) {abs(closing):.1f} kph"
        )
    return lines


def _one_line(message: str) -> str:
    return " ".join(message.split())


def _problem(message: str) -> RunProblem:
    from osc2runner.errors import RunProblem

    return RunProblem(message)


def _print_input_errors(exc: ScenarioError, err: TextIO) -> None:
    if exc.diagnostics:
        from osc2check.output import render

        err.write(render("full", exc.diagnostics, exc.texts))
    for problem in exc.problems:
        err.write(f"{problem}\n")
        line = _source_line(problem, exc.texts)
        if line is not None:
            err.write(line)
    if exc.problems:
        n = len(exc.problems)
        err.write(f"osc2run: {n} problem{'s' if n != 1 else ''}; nothing ran\n")
    elif all(d.code.code == "A308" for d in exc.diagnostics):  # capabilities.not_executed
        err.write("osc2run: the checker found forms the runner does not execute; nothing ran\n")
    else:
        err.write("osc2run: the checker found errors; nothing ran\n")
    err.flush()


def _source_line(problem: RunProblem, texts: dict[str, str]) -> str | None:
    span = problem.span
    if span is None or span.uri not in texts:
        return None
    lines = texts[span.uri].splitlines()
    if not 1 <= span.line <= len(lines):
        return None
    text = lines[span.line - 1]
    width = len(str(span.line))
    caret_len = max(1, (span.end_column - span.column) if span.end_line == span.line else 1)
    return (
        f"{' ' * width} |\n{span.line} | {text}\n"
        f"{' ' * width} | {' ' * (span.column - 1)}{'^' * caret_len}\n"
    )


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
