"""``run_campaign``: one logical scenario, many concrete runs, and what they found.

1. The file is checked once here (input errors stop everything: nothing runs),
   the campaign folder made, and the runs planned
   (:mod:`osc2runner.campaign.plan`: ``random`` seeds or ``cover`` bins).
2. With ``resume``, the runs of the folder whose ``record.json`` shows them
   finished are kept and not run again; the folder must hold a campaign of the
   same text of the same file with the same run options (its files are read as
   data, :mod:`~osc2runner.campaign.schema`). Without it, a folder that is not
   empty must hold a campaign of the same scenario (it is written over), unless
   ``force``: a folder of other files is never written into by mistake.
3. An engine runs the rest (:class:`~osc2runner.campaign.pool.LocalPool` or
   :class:`~osc2runner.campaign.ray_engine.RayEngine`); each record is written
   to ``runs/<seed>/record.json`` as it arrives and reported to ``progress``.
4. SIGINT, SIGTERM and SIGHUP stop the campaign: no new run starts, the runs in
   progress end at a tick boundary with their files written (``interrupted``),
   and the outputs are written with what finished; ``resume`` does the rest.
   Only from the main thread: a campaign run from another one installs no
   signal handler.
5. ``campaign.json``, ``runs.csv``, ``junit.xml`` and ``report.html`` are
   written (:mod:`~osc2runner.campaign.outputs`, :mod:`~osc2runner.campaign.report`).
"""

from __future__ import annotations

import hashlib
import logging
import os
import signal
import threading
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, Literal, get_args

from osc2check.config import Config, config_for
from osc2check.inputs import InputError, read_bytes
from osc2runner.campaign.engine import Engine, EngineName
from osc2runner.campaign.outputs import (
    read_campaign,
    read_records,
    replay_command,
    write_campaign,
    write_junit,
    write_record,
    write_runs_csv,
)
from osc2runner.campaign.parameters import parameter_domains, parameter_equations
from osc2runner.campaign.plan import CoverPlan, ItemPlan, plan_cover, plan_random
from osc2runner.campaign.schema import CampaignStatus, FolderError
from osc2runner.campaign.steering import cover_items
from osc2runner.campaign.summary import (
    coverage_table,
    findings,
    kpi_figures,
    summarize,
    worst_runs,
)
from osc2runner.campaign.worker import CampaignSetup, RunRecord, RunTask
from osc2runner.errors import RunProblem, ScenarioError
from osc2runner.execution.signals import SIGNALS, signal_name
from osc2runner.options import RunOptions
from osc2runner.output.files import output_folder
from osc2runner.runner import Checked, check_file

__all__ = [
    "ENGINES",
    "STRATEGIES",
    "CampaignError",
    "CampaignOptions",
    "CampaignResult",
    "run_campaign",
]

log = logging.getLogger(__name__)

ENGINES: tuple[EngineName, ...] = get_args(EngineName)
STRATEGIES = ("random", "cover")
DEFAULT_RUN_TIMEOUT = 600.0  # wall-clock seconds per run


class CampaignError(ValueError):
    """A campaign that cannot start (a bad option, a folder holding another campaign)."""


@dataclass(frozen=True, slots=True)
class CampaignOptions(RunOptions):
    """Everything a campaign is asked to do (the command's options): the options of its
    runs (:class:`~osc2runner.options.RunOptions`, keywords; ``seed`` is the first run's,
    ``plot`` draws every run's plots) and the campaign's own."""

    file: str
    runs: int
    out: str
    jobs: int = 0  # 0: one worker per processor
    engine: EngineName = "local"
    address: str | None = None
    strategy: str = "random"
    run_timeout: float | None = DEFAULT_RUN_TIMEOUT
    resume: bool = False
    export: tuple[str, ...] = ()  # formats written into every run's folder (osc2runner.export)
    force: bool = False  # write into a folder of other files (not a campaign of this scenario)

    def run_options(self) -> dict[str, Any]:
        """What makes two runs of one seed the same run (resume compares these; the
        SUT's step budget is recorded with it but is no part of it)."""
        sut = asdict(self.sut) if self.sut is not None else None
        return {
            "scenario": self.scenario,
            "duration": self.duration,
            "dt_control": self.dt_control,
            "dt_physics": self.dt_physics,
            "sut": {"target": sut["target"], "actor": sut["actor"]} if sut else None,
            "strategy": self.strategy,
            "seed": self.seed,
            **self._language(),
            # vehicles on the kinematic model (a campaign of an older folder has none)
            **({"kinematic": list(self.kinematic)} if self.kinematic else {}),
        }

    def _language(self) -> dict[str, Any]:
        """The OSC2 version and dialect, when the configuration says other than the
        defaults (a campaign of an older folder has neither). Its plug-ins are code, not
        recorded: a resumed campaign loads those its command line and configuration name."""
        if self.config is None:
            return {}
        language = {"osc_version": self.config.osc_version, "dialect": self.config.dialect}
        return {k: v for k, v in language.items() if v != getattr(Config(), k)}

    def language_arguments(self) -> list[str]:
        """The language's command-line options and plug-ins (what a run's replay command
        repeats)."""
        args = [f"--{k.replace('_', '-')}={v}" for k, v in self._language().items()]
        plugins = self.config.plugins if self.config is not None else ()
        return args + [f"--plugin={p}" for p in plugins]


@dataclass
class CampaignResult:
    """A campaign that ended: its records (every run of the plan that finished or was
    interrupted), its summary, where its files are, ``complete`` or ``interrupted``
    (with the signal)."""

    records: list[RunRecord]
    summary: dict[str, Any]
    folder: Path
    status: CampaignStatus
    signum: int | None = None
    outputs: list[Path] = field(default_factory=list)
    document: dict[str, Any] = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        return self.status == "complete" and self.summary["failed"] == 0


#: progress("plan", {"total": runs, "done": records kept}) once, then ("record", RunRecord)
Progress = Callable[[Literal["plan", "record"], Any], None]


def _engine(
    options: CampaignOptions, setup: CampaignSetup, jobs: int, clock: Callable[[], float]
) -> Engine:
    if options.engine == "ray":
        from osc2runner.campaign.ray_engine import RayEngine

        return RayEngine(setup, jobs, options.run_timeout, options.address, clock)
    from osc2runner.campaign.pool import LocalPool

    return LocalPool(setup, jobs, options.run_timeout, clock)


def _check(options: CampaignOptions) -> None:
    if options.runs < 1:
        raise CampaignError("--runs must be at least 1")
    if options.engine not in ENGINES:
        raise CampaignError(f"--engine {options.engine}: one of {', '.join(ENGINES)}")
    if options.strategy not in STRATEGIES:
        raise CampaignError(f"--strategy {options.strategy}: one of {', '.join(STRATEGIES)}")
    if options.jobs < 0:
        raise CampaignError("--jobs must be a positive number of workers")


def plan_runs(options: CampaignOptions, checked: Checked) -> CoverPlan:
    """The planned tasks, and every cover item's plan (its bucket labels, for ``random``
    only observed)."""
    items = cover_items(checked, seed=options.seed, dt_control=options.dt_control)
    if options.strategy == "cover":
        if not any(e.steerable for e in items):
            why = "; ".join(f"`{e.item.name}`: {e.reason}" for e in items) or "it has none"
            raise ScenarioError(
                [
                    RunProblem(
                        f"--strategy cover: no cover item of `{checked.scenario.name}` can be "
                        f"steered ({why})",
                        checked.scenario.name_span,
                    )
                ]
            )
        return plan_cover(checked, items, options.seed, options.runs)
    plan = plan_random(options.seed, options.runs)
    plan.items = [
        ItemPlan(e.item.name, not e.reason, e.reason, [b.label for b in e.item.buckets])
        for e in items
    ]
    return plan


def run_campaign(
    options: CampaignOptions,
    progress: Progress | None = None,
    *,
    clock: Callable[[], float] = time.monotonic,
) -> CampaignResult:
    """Run a campaign (see the module docstring); raises ScenarioError for input errors,
    CampaignError for options or a folder that cannot be used. ``clock`` is the wall clock
    the engine holds each run to ``run_timeout`` with (a test gives one it controls)."""
    _check(options)
    started = time.perf_counter()
    if options.engine == "local":
        from osc2runner.campaign.pool import warm_up

        warm_up()
    started_at = datetime.now(UTC).isoformat(timespec="seconds")
    try:
        data = read_bytes(options.file)  # a regular file of at most the checker's size cap
    except InputError as exc:
        raise ScenarioError([RunProblem(f"{options.file}: cannot read: {exc}")]) from None
    from osc2check.source import decode_source

    text, _ = decode_source(data)
    config = options.config if options.config is not None else config_for(options.file)
    checked = check_file(options.file, scenario=options.scenario, source=text, config=config)
    digest = hashlib.sha256(data).hexdigest()
    folder = output_folder(options.out, create=False)  # made once the runs are planned
    previous: dict[int, RunRecord] = {}
    if options.resume:
        previous = _resumable(folder, options, digest)
    elif not options.force:
        _writable(folder, checked.scenario.name)
    jobs = options.jobs or os.cpu_count() or 1
    setup = CampaignSetup(
        options.file,
        text,
        str(folder),
        ship_files=options.engine == "ray",
        export=options.export,
        **{**options.run_fields(), "config": config},
    )
    engine = _engine(options, setup, min(jobs, options.runs), clock)
    # the workers start while the runs are planned (none when every run finished)
    engine.start(options.runs - sum(r.finished for r in previous.values()))
    try:
        plan = plan_runs(options, checked)
        planned = {t.seed: t for t in plan.tasks}
        kept = {
            s: r
            for s, r in previous.items()
            if s in planned and r.finished and _bin_text(r) == _bin_text(planned[s])
        }
        todo = [t for t in plan.tasks if t.seed not in kept]
        replay = {
            t.seed: replay_command(
                options.file,
                options.for_seed(t.seed),
                bin_text=t.bin.text if t.bin else None,
                language=options.language_arguments(),
            )
            for t in plan.tasks
        }
        document: dict[str, Any] = {
            "format": 1,
            "tool": _tool(),
            "source": options.file,
            "source_sha256": digest,
            "scenario": checked.scenario.name,
            "options": {
                **options.run_options(),
                "sut": asdict(options.sut) if options.sut is not None else None,
                "runs": options.runs,
                "jobs": jobs,
                "engine": options.engine,
                "address": options.address,
                "run_timeout": options.run_timeout,
                "plot": options.plot,
                "export": list(options.export),
            },
            "status": "running",
            "started": started_at,
            "plan": {
                "seeds": [t.seed for t in plan.tasks],
                "directed": [{"seed": t.seed, "bin": t.bin.text} for t in plan.tasks if t.bin],
                "cover": [p.to_json() for p in plan.items],
                "resumed": sorted(kept),
            },
            "parameters": {
                "domains": parameter_domains(checked),
                "equations": parameter_equations(checked),
            },
        }
        folder = output_folder(options.out)
        write_campaign(folder, document)
        records: dict[int, RunRecord] = dict(kept)
        if progress is not None:
            progress("plan", {"total": len(plan.tasks), "done": list(kept.values())})

        spare_core = (os.cpu_count() or 1) > jobs
        preloading: list[threading.Thread] = []

        def on_record(record: RunRecord) -> None:
            # the report's modules are imported on a core no worker needs: one left spare,
            # or the one freed when fewer runs are left than workers
            left = len(todo) - len(records.keys() - kept.keys()) - 1
            if not preloading and (spare_core or left < jobs):
                preloading.append(threading.Thread(target=_preload_report, daemon=True))
                preloading[0].start()
            write_record(folder, record)
            record.shipped = {}
            records[record.seed] = record
            if progress is not None:
                progress("record", record)

        stop_signal: list[int] = []

        def on_signal(signum: int, frame: Any) -> None:
            if not stop_signal:
                stop_signal.append(signum)
                log.info("campaign interrupted by %s: stopping", signal_name(signum))
                engine.stop()

        # signal handlers can only be installed from the main thread (as Interrupts does);
        # a campaign run from another thread is not stopped by signals
        previous_handlers = (
            {s: signal.signal(s, on_signal) for s in SIGNALS}
            if threading.current_thread() is threading.main_thread()
            else {}
        )
        try:
            engine.run(todo, on_record)
        finally:
            for s, handler in previous_handlers.items():
                signal.signal(s, handler if handler is not None else signal.SIG_DFL)
    finally:
        engine.close()
    wall = time.perf_counter() - started
    status: CampaignStatus = "interrupted" if stop_signal else "complete"
    result = finish(folder, document, plan, records, replay, wall, status, engine)
    result.signum = stop_signal[0] if stop_signal else None
    return result


def _preload_report() -> None:
    from osc2runner.campaign.report import preload

    try:
        preload()
    except Exception:  # the report says what is wrong when it is written
        log.debug("the report's modules could not be imported ahead", exc_info=True)


def _bin_text(run: RunTask | RunRecord) -> str | None:
    return run.bin.text if run.bin is not None else None


def _writable(folder: Path, scenario: str) -> None:
    """A folder a new campaign of ``scenario`` may write into: none yet, an empty one, or
    one holding a campaign of the same scenario (CampaignError otherwise)."""
    try:
        if not folder.is_dir() or not any(folder.iterdir()):
            return
        document = read_campaign(folder)
    except FolderError as exc:
        raise CampaignError(
            f"--out {folder}: not empty, and its campaign.json is not a campaign ({exc}); "
            "choose an empty folder, or add --force to write into it"
        ) from None
    except OSError as exc:
        raise CampaignError(f"--out {folder}: cannot read: {exc.strerror or exc}") from None
    if document is None:
        raise CampaignError(
            f"--out {folder}: the folder is not empty and holds no campaign: its files could "
            "be overwritten; choose an empty folder, or add --force to write into it"
        )
    if document["scenario"] != scenario:
        raise CampaignError(
            f"--out {folder}: it holds a campaign of scenario `{document['scenario']}`, not "
            f"`{scenario}`; choose another folder, or add --force to write into it"
        )


def _resumable(folder: Path, options: CampaignOptions, digest: str) -> dict[int, RunRecord]:
    try:
        document = read_campaign(folder)
    except FolderError as exc:
        raise CampaignError(f"--resume {folder}: {exc}") from None
    if document is None:
        return {}
    if document.get("source_sha256") != digest:
        raise CampaignError(
            f"--resume {folder}: its campaign ran another text of the file "
            f"({document.get('source')}); use a new folder"
        )
    stored = dict(document["options"])
    if stored["sut"] is not None:  # its step budget is no part of the run
        stored["sut"] = {"target": stored["sut"]["target"], "actor": stored["sut"]["actor"]}
    mine = options.run_options()
    changed = [k for k, v in mine.items() if stored.get(k) != v]
    if changed:
        raise CampaignError(
            f"--resume {folder}: its campaign ran with other options ({', '.join(changed)})"
        )
    return read_records(folder)


def _tool() -> dict[str, Any]:
    from osc2check.output import tool
    from osc2runner.sim import versions

    return {"name": "osc2run", "version": tool.version(), "versions": versions()}


def finish(
    folder: Path,
    document: dict[str, Any],
    plan: CoverPlan,
    records: dict[int, RunRecord],
    replay: dict[int, str],
    wall: float,
    status: CampaignStatus,
    engine: Engine,
) -> CampaignResult:
    """Write the campaign's outputs from its records (also after an interrupt)."""
    tasks = plan.tasks
    ordered = [records[t.seed] for t in tasks if t.seed in records]
    summary = summarize(ordered)
    kept = set(document["plan"]["resumed"])
    ran = [r for r in ordered if r.finished and r.seed not in kept]  # by this invocation
    preferred = [p.name for p in plan.items]
    swept, failures = findings(ordered, document.get("parameters", {}), preferred, replay)
    document.update(
        {
            "status": status,
            "finished": datetime.now(UTC).isoformat(timespec="seconds"),
            "wall_seconds": round(wall, 3),
            "runs_per_minute": round(60.0 * len(ran) / wall, 2) if wall > 0 else None,
            "workers": {
                "engine": engine.name,
                "started": getattr(engine, "started_workers", None),
                "retried": getattr(engine, "retried", []),  # runs again: their node died
                "peak_memory_mb": [
                    round(m / 2**20, 1) for m in getattr(engine, "worker_memory", [])
                ],
            },
            "summary": summary,
            "not_run": [t.seed for t in tasks if t.seed not in records],
            "coverage": coverage_table(ordered, plan.items),
            "kpis": kpi_figures(ordered),
            "parameters": swept,
            "failures": failures,
            "worst": [r.seed for r in worst_runs(ordered)],
            "runs": [{**r.to_json(), "replay": replay.get(r.seed, "")} for r in ordered],
        }
    )
    outputs = [
        write_runs_csv(folder, ordered, replay),
        write_junit(folder, document, ordered, replay, wall),
    ]
    from osc2runner.campaign.report import write_report

    outputs.append(write_report(folder, document, ordered))
    outputs.append(write_campaign(folder, document))
    return CampaignResult(ordered, summary, folder, status, None, outputs, document)
