"""``osc2run FILE --runs N ...``: the command line of a campaign.

:func:`campaign_arguments` checks the campaign's options (usage errors before
anything runs; with ``--resume DIR`` the file and the options the command line
does not give are those of the campaign in ``DIR``, ``--jobs`` excepted, read
through :mod:`~osc2runner.campaign.schema`). A folder is data, never code: the
system under test its campaign ran is only imported when the command line names
it (``--sut``, compared with the folder's), or with ``--trust-folder``, which says
what it imports;
:func:`run_command` runs it with a progress bar on a terminal (done, failed,
rate, ETA), one line per run otherwise (``-q``: only the summary), prints the
summary and returns the exit status: 0 when every run passed, 1 when one did
not, 2 for usage and input errors, 128 + N when signal N interrupted the
campaign (what finished is written).
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

from osc2runner.options import DT_CONTROL, DT_PHYSICS

if TYPE_CHECKING:
    from osc2runner.campaign.campaign import CampaignOptions, CampaignResult, Progress

__all__ = ["campaign_arguments", "run_command"]


def _usage(message: str) -> Exception:
    from osc2runner.cli import UsageError

    return UsageError(message)


def _count(name: str, text: str | None, default: int) -> int:
    if text is None:
        return default
    try:
        value = int(text)
    except ValueError:
        raise _usage(f"--{name} {text}: must be a positive whole number") from None
    if value < 1:
        raise _usage(f"--{name} {text}: must be a positive whole number")
    return value


def _stored_options(args: argparse.Namespace, stored: dict[str, Any]) -> None:
    """Complete ``args`` with the stored campaign's file and options (``--resume DIR``):
    what the command line does not give is the campaign's own, FILE or not, but the
    system under test (code: see the module docstring)."""
    opts = stored["options"]
    given = args.given
    if args.file is None:
        args.file = stored.get("source")
    args.scenario = args.scenario or opts.get("scenario")
    if args.runs is None:
        args.runs = str(len(stored.get("plan", {}).get("seeds", [])) or 1)
    if "--seed" not in given:
        args.seed = str(opts.get("seed", 0))
    if "--strategy" not in given:
        args.strategy = opts.get("strategy", "random")
    if args.duration is None and opts.get("duration") is not None:
        args.duration = repr(opts["duration"])
    if "--dt-control" not in given:
        args.dt_control = repr(opts.get("dt_control", DT_CONTROL))
    if "--dt-physics" not in given:
        args.dt_physics = repr(opts.get("dt_physics", DT_PHYSICS))
    if "--kinematic" not in given and opts.get("kinematic"):
        args.kinematic = [",".join(opts["kinematic"])]
    sut = opts.get("sut")
    if sut and args.sut is None:
        if not args.trust_folder:
            raise _usage(
                f"--resume {args.resume}: its campaign ran the system under test "
                f"`{sut['target']}`, which would be imported (code); give it again with "
                "--sut, or add --trust-folder to import what the folder names"
            )
        sys.stderr.write(
            f"osc2run: --trust-folder: importing the system under test `{sut['target']}` "
            f"that {Path(args.resume) / 'campaign.json'} names\n"
        )
        args.sut, args.sut_actor = sut["target"], sut.get("actor")
    if sut and args.step_timeout is None and sut.get("step_timeout") is not None:
        args.step_timeout = repr(sut["step_timeout"])
    if "--engine" not in given and opts.get("engine") in ("local", "ray"):
        args.engine = opts["engine"]
    if args.address is None and args.engine == "ray":
        args.address = opts.get("address")
    if args.run_timeout is None and opts.get("run_timeout") is not None:
        args.run_timeout = repr(opts["run_timeout"])
    args.plot = args.plot or bool(opts.get("plot"))
    for name in ("osc_version", "dialect"):  # the language the campaign was checked in
        if getattr(args, name, None) is None and opts.get(name) is not None:
            setattr(args, name, opts[name])
    # plug-ins are code: a resumed campaign loads those of the command line and of the
    # configuration, never what its folder lists (docs/security.md)
    if args.export is None and opts.get("export"):
        args.export = ",".join(opts["export"])


def campaign_arguments(args: argparse.Namespace) -> None:
    """Check and complete the campaign options of the command line (UsageError)."""
    from osc2runner.campaign.outputs import read_campaign
    from osc2runner.campaign.schema import FolderError

    if args.trust_folder and args.resume is None:
        raise _usage("--trust-folder is for --resume DIR")
    if args.resume is not None:
        try:
            found = read_campaign(Path(args.resume))
        except FolderError as exc:
            raise _usage(f"--resume {args.resume}: {exc}") from None
        if found is None:
            raise _usage(f"--resume {args.resume}: no campaign.json there")
        stored = found
        if args.out is not None and Path(args.out).resolve() != Path(args.resume).resolve():
            raise _usage("--resume DIR writes into DIR: leave out --out")
        args.out = args.resume
        _stored_options(args, stored)
    if args.file is None:
        raise _usage("the following arguments are required: FILE (or --resume DIR)")
    if args.out is None:
        raise _usage("--runs needs --out DIR (the campaign's folder) or --resume DIR")
    args.runs = _count("runs", args.runs, 1)
    args.jobs = _count("jobs", args.jobs, 0)
    if args.engine != "ray" and args.address is not None:
        raise _usage("--address needs --engine ray")
    if args.bin is not None:
        raise _usage("--bin is for one run; a campaign chooses bins with --strategy cover")
    # --out (set for every campaign) and --run-timeout are checked by the command line after
    # this, as one run's options are (cli._parse)


def run_command(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    """Run the campaign of the command line; the exit status."""
    from osc2runner.campaign.campaign import (
        DEFAULT_RUN_TIMEOUT,
        CampaignError,
        CampaignOptions,
        run_campaign,
    )
    from osc2runner.campaign.pool import EngineError
    from osc2runner.execution.signals import exit_status

    options = CampaignOptions(
        file=args.file,
        runs=args.runs,
        out=str(args.out),
        jobs=args.jobs,
        engine=args.engine,
        address=args.address,
        strategy=args.strategy,
        run_timeout=args.run_timeout if args.run_timeout is not None else DEFAULT_RUN_TIMEOUT,
        resume=args.resume is not None,
        export=args.export_formats,
        force=args.force,
        **args.options.run_fields(),  # the run's options, as the command line made them
    )
    interactive = out.isatty() and not args.quiet
    try:
        if interactive:
            result = _with_bar(options, run_campaign)
        else:
            result = run_campaign(options, None if args.quiet else _lines(out))
    except (CampaignError, EngineError) as exc:
        err.write(f"osc2run: error: {' '.join(str(exc).split())}\n")
        return 2
    _summary(result, out)
    if result.status == "interrupted":
        return exit_status(result.signum)
    return 0 if result.passed else 1


def _lines(out: TextIO) -> Progress:
    total = [0]
    done = [0]

    def progress(kind: str, payload: Any) -> None:
        if kind == "plan":
            total[0] = payload["total"]
            done[0] = len(payload["done"])
            if done[0]:
                out.write(f"resuming: {done[0]} of {total[0]} runs already finished\n")
            return
        done[0] += 1
        r = payload
        where = f" in {r.bin.text} {r.bin.label}" if r.bin is not None else ""
        out.write(
            f"[{done[0]}/{total[0]}] seed {r.seed}{where}: {r.status}: {r.reason} "
            f"({r.wall_s:.1f} s)\n"
        )
        out.flush()

    return progress


def _with_bar(
    options: CampaignOptions,
    run_campaign: Callable[[CampaignOptions, Progress], CampaignResult],
) -> CampaignResult:
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    columns = (
        TextColumn("[bold]{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("[red]{task.fields[failed]} failed"),
        TextColumn("{task.fields[rate]}"),
        TimeElapsedColumn(),
        TextColumn("ETA"),
        TimeRemainingColumn(),
    )
    with Progress(*columns) as bar:
        task = bar.add_task("campaign", total=None, failed=0, rate="")
        failed = [0]

        def progress(kind: str, payload: Any) -> None:
            if kind == "plan":
                done = payload["done"]
                failed[0] = sum(1 for r in done if not r.passed)
                bar.update(task, total=payload["total"], completed=len(done), failed=failed[0])
                return
            failed[0] += 0 if payload.passed else 1
            bar.advance(task)
            elapsed = bar.tasks[0].elapsed or 0.0
            done = bar.tasks[0].completed
            rate = f"{60.0 * done / elapsed:.0f} runs/min" if elapsed > 0 else ""
            bar.update(task, failed=failed[0], rate=rate)

        return run_campaign(options, progress)


def _summary(result: CampaignResult, out: TextIO) -> None:
    s = result.summary
    doc = result.document
    rate = "–" if s["pass_rate"] is None else f"{100 * s['pass_rate']:.1f} %"
    outcomes = ", ".join(f"{v} {k}" for k, v in s["outcomes"].items()) or "none"
    per_minute = doc.get("runs_per_minute")
    out.write(
        f"campaign {doc['scenario']} ({doc['source']}): {result.status}: {s['finished']} of "
        f"{len(doc['plan']['seeds'])} runs, {s['passed']} passed ({rate}); {outcomes}\n"
    )
    out.write(
        f"  {doc['wall_seconds']:.1f} s wall"
        + (
            f", {per_minute:.1f} runs per minute"
            if per_minute and math.isfinite(per_minute)
            else ""
        )
        + "\n"
    )
    for item in doc.get("coverage", []):
        holes = f"; holes: {', '.join(item['holes'])}" if item["holes"] else ""
        gone = f"; {item['unreachable']} unreachable" if item["unreachable"] else ""
        out.write(
            f"  cover {item['name']}: {item['filled']} of {item['reachable']} buckets filled"
            f"{gone}{holes}\n"
        )
    for line in findings_lines(doc):
        out.write(f"  {line}\n")
    worst = [r for r in result.records if not r.passed and r.finished][:5]
    for r in worst:
        out.write(f"  seed {r.seed}: {r.status}: {r.reason}\n")
    for path in result.outputs:
        out.write(f"  wrote {path}\n")
    out.flush()


def findings_lines(document: dict[str, Any]) -> list[str]:
    """The summary's lines of what the campaign swept (each parameter's spread, a warning
    for one that piles up) and where it failed (the failure boundary)."""
    from osc2runner.campaign.spread import Spread

    parameters = document.get("parameters", {})
    lines = []
    for entry in parameters.get("spread", []):
        spread = Spread(**entry)
        lines.append(f"swept {spread.text()}")
        if spread.warning:
            lines.append(f"warning: {spread.warning}: the runs do not cover what it allows")
    for name, why in parameters.get("derived", {}).items():
        lines.append(f"not swept: {name} {why}")
    found = document.get("failures", {}).get("boundary", {})
    for region in found.get("regions", []):
        lines.append(f"failure boundary: {region['text']}")
    if found.get("why"):
        lines.append(f"failure boundary: none ({found['why']})")
    return lines
