"""The ``osc2run`` command: argv -> run -> summary -> exit status.

Exit status: 0 when the scenario ends successfully; 1 when it fails (a failed
phase, the ``fail`` event, a collision, the time limit with bounded phases
still running); 2 for input errors (the checker's error diagnostics or the
runner's own problems are printed, and nothing runs) and internal errors;
130 when interrupted (what was recorded is written first).

On a terminal a progress bar shows simulated time and the real-time factor;
otherwise one summary is printed at the end.
"""

from __future__ import annotations

import argparse
import logging
import os
import sys
import traceback
from collections.abc import Sequence
from pathlib import Path
from typing import Any, TextIO

from osc2runner.errors import ScenarioError

__all__ = ["EXIT_ERROR", "EXIT_FAILURE", "EXIT_INTERRUPTED", "EXIT_OK", "build_parser", "main"]

EXIT_OK, EXIT_FAILURE, EXIT_ERROR, EXIT_INTERRUPTED = 0, 1, 2, 130


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="osc2run",
        description="Run an ASAM OpenSCENARIO DSL 2.x scenario in the MuJoCo world.",
        epilog="exit status: 0 success, 1 scenario failed, 2 input or internal error, "
        "130 interrupted",
    )
    p.add_argument("file", metavar="FILE", help="the .osc file")
    p.add_argument("--scenario", metavar="NAME", help="the scenario to run (when several)")
    p.add_argument("--seed", type=int, default=0, metavar="N", help="seed of the run (default 0)")
    p.add_argument(
        "--duration", type=float, metavar="T", help="time limit in simulated seconds (default 600)"
    )
    p.add_argument("--out", metavar="DIR", help="write telemetry.csv, events.csv, run.json here")
    p.add_argument("--plot", action="store_true", help="also write PNG plots (needs --out)")
    p.add_argument(
        "--dt-control",
        type=float,
        default=0.05,
        metavar="S",
        help="control period: one tree tick (default 0.05)",
    )
    p.add_argument(
        "--dt-physics", type=float, default=0.002, metavar="S", help="physics step (default 0.002)"
    )
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar, summary only")
    p.add_argument("--debug", action="store_true", help="log details; show tracebacks")
    return p


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``) and return the exit status."""
    args_list = list(sys.argv[1:] if argv is None else argv)
    try:
        args = build_parser().parse_args(args_list)
    except SystemExit as exc:
        return exc.code if isinstance(exc.code, int) else EXIT_ERROR
    logging.basicConfig(
        level=logging.DEBUG if args.debug else logging.WARNING,
        format="osc2run: %(levelname)s: %(name)s: %(message)s",
        stream=sys.stderr,
    )
    if args.plot and not args.out:
        sys.stderr.write("osc2run: error: --plot needs --out DIR\n")
        return EXIT_ERROR
    try:
        return _run(args, sys.stdout, sys.stderr)
    except BrokenPipeError:  # the reader went away (`osc2run ... | head`): stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return EXIT_FAILURE
    except ScenarioError as exc:
        _print_input_errors(exc, sys.stderr)
        return EXIT_ERROR
    except Exception as exc:  # the one guard of this entry point
        if args.debug:
            traceback.print_exc(file=sys.stderr)
        sys.stderr.write(f"osc2run: internal error: {type(exc).__name__}: {exc}\n")
        if not args.debug:
            sys.stderr.write("osc2run: run with --debug to see the traceback\n")
        return EXIT_ERROR


def _run(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    from osc2runner.runner import RunInterrupted, execute, prepare

    if not Path(args.file).exists():
        raise ScenarioError([_problem(f"{args.file}: no such file")])
    prepared = prepare(
        args.file,
        scenario=args.scenario,
        seed=args.seed,
        dt_control=args.dt_control,
        dt_physics=args.dt_physics,
    )
    interactive = out.isatty() and not args.quiet
    try:
        if interactive:
            result = _with_progress(prepared, args, execute)
        else:
            result = execute(prepared, out=args.out, duration=args.duration, plot=args.plot)
    except RunInterrupted as exc:
        _summary(exc.result, out)
        return EXIT_INTERRUPTED
    _summary(result, out)
    if result.outcome.status == "error":  # pragma: no cover - execute re-raises errors
        return EXIT_ERROR
    return EXIT_OK if result.success else EXIT_FAILURE


def _with_progress(prepared: Any, args: argparse.Namespace, execute: Any) -> Any:
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    limit = args.duration if args.duration is not None else 600.0
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

        return execute(
            prepared, out=args.out, duration=args.duration, plot=args.plot, progress=report
        )


def _summary(result: Any, out: TextIO) -> None:
    meta = result.metadata
    o = result.outcome
    rtf = meta.get("real_time_factor")
    out.write(
        f"scenario {meta['scenario']} ({meta['source']}): {o.status} at "
        f"{o.time:.2f} s (tick {o.tick}): {o.reason}\n"
    )
    out.write(
        f"  simulated {meta['simulated_time']:.2f} s in {meta['steps']} ticks, "
        f"{meta['wall_seconds']:.2f} s wall" + (f", {rtf:.0f}x real time" if rtf else "") + "\n"
    )
    emitted = [e for e in result.events if e.kind == "emit"]
    if emitted:
        names = ", ".join(f"{e.name}@{e.time:.2f}s" for e in emitted[:8])
        more = f" (+{len(emitted) - 8} more)" if len(emitted) > 8 else ""
        out.write(f"  events: {names}{more}\n")
    for path in result.outputs:
        out.write(f"  wrote {path}\n")
    out.flush()


def _problem(message: str) -> Any:
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
    else:
        err.write("osc2run: the checker found errors; nothing ran\n")
    err.flush()


def _source_line(problem: Any, texts: dict[str, str]) -> str | None:
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
