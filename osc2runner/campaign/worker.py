"""One campaign worker: check the file once, then run seed after seed.

A :class:`Worker` is made from a :class:`CampaignSetup` (plain data: the
file's text, the scenario, the run options, the SUT, the campaign folder). It
checks the file once (parse, resolve, verify: :func:`osc2runner.runner.check_file`)
and compiles each run from that analysis (:func:`osc2runner.runner.prepare_checked`)
with the seed's witness, or the witness drawn inside a coverage bin. A run's
files go to ``runs/<seed>/`` exactly as ``osc2run FILE --seed k --out DIR``
writes them; :meth:`Worker.run` returns its :class:`RunRecord` (outcome,
parameters, KPIs, records, coverage hits) whatever happened: a run that cannot
start, or a bug, is recorded as ``error`` with the reason.

The same worker serves the local process pool and Ray: with ``ship_files`` it
writes into a temporary folder and returns the files' bytes in the record, for
a driver that does not share the worker's file system.
"""

from __future__ import annotations

import math
import os
import shutil
import tempfile
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

from osc2check.verify import ir
from osc2check.verify.witness import Witness
from osc2check.world.network import RoadNetwork
from osc2runner.campaign.kpis import run_kpis
from osc2runner.campaign.steering import (
    BinRef,
    SteerableItem,
    cover_items,
    directed_witness,
    scenario_result,
)
from osc2runner.errors import ScenarioError
from osc2runner.execution.outcome import OutcomeStatus
from osc2runner.export import ExportTargets
from osc2runner.options import RunOptions
from osc2runner.output.gaps import subject_actor
from osc2runner.output.telemetry import tick_time
from osc2runner.runner import (
    Checked,
    RunInterrupted,
    RunResult,
    check_file,
    execute,
    prepare_run,
)

__all__ = ["CampaignSetup", "RunRecord", "RunTask", "Worker", "lost_record", "run_folder"]


@dataclass(frozen=True, slots=True)
class CampaignSetup(RunOptions):
    """What every worker of a campaign needs (plain data, sent to other processes): the
    options of its runs (keywords; ``plot``: plots of every run, else of the runs that
    did not pass; each run has its task's seed) and where the file and folder are.

    ``uri`` is the file as named on the command line and ``text`` its content when
    the campaign started (every worker runs that text); ``out`` the campaign folder.
    """

    uri: str
    text: str
    out: str = "."
    ship_files: bool = False
    export: tuple[str, ...] = ()  # formats written into every run's folder (osc2runner.export)


@dataclass(frozen=True, slots=True)
class RunTask:
    """One run to do: its seed, and the coverage bin its witness is drawn in (None: the
    seed's own witness)."""

    seed: int
    bin: BinRef | None = None


@dataclass
class RunRecord:
    """What a campaign keeps of one run (``campaign.json``'s ``runs[]``, one row of
    ``runs.csv``, one testcase of ``junit.xml``)."""

    seed: int
    status: OutcomeStatus
    reason: str
    bin: BinRef | None = None
    time_s: float = 0.0
    tick: int = 0
    parameters: dict[str, dict[str, Any]] = field(default_factory=dict)
    kpis: dict[str, Any] = field(default_factory=dict)
    records: dict[str, Any] = field(default_factory=dict)
    coverage: dict[str, list[int]] = field(default_factory=dict)  # item -> buckets hit
    wall_s: float = 0.0
    folder: str = ""
    files: list[str] = field(default_factory=list)
    error: str | None = None
    shipped: dict[str, bytes] = field(default_factory=dict, repr=False)

    @property
    def passed(self) -> bool:
        return self.status == "success"

    @property
    def finished(self) -> bool:
        """Whether the run went to its end (an interrupted run is done again on resume)."""
        return self.status != "interrupted"

    def to_json(self) -> dict[str, Any]:
        return {
            "seed": self.seed,
            "bin": (
                {"item": self.bin.item, "index": self.bin.index, "label": self.bin.label}
                if self.bin is not None
                else None
            ),
            "outcome": {
                "status": self.status,
                "reason": self.reason,
                "time": self.time_s,
                "tick": self.tick,
            },
            "parameters": self.parameters,
            "kpis": self.kpis,
            "records": self.records,
            "coverage": self.coverage,
            "wall_seconds": self.wall_s,
            "folder": self.folder,
            "files": self.files,
            "error": self.error,
        }


def run_folder(seed: int) -> str:
    """The folder of a run's files, relative to the campaign folder."""
    return f"runs/{seed}"


def lost_record(task: RunTask, why: str, default_reason: str) -> RunRecord:
    """The record of a run whose worker did not answer: ``interrupted`` when the engine
    stopped it for an interrupt (``why`` is ``"interrupted"``), else ``error`` with the
    engine's ``why`` (over the wall-clock limit) or ``default_reason`` (the worker died)."""
    status: OutcomeStatus
    if why == "interrupted":
        status, reason = "interrupted", "the campaign was interrupted"
    else:
        status, reason = "error", why or default_reason
    return RunRecord(task.seed, status, reason, task.bin, folder=run_folder(task.seed))


class Worker:
    """Checks the campaign's file once; runs tasks (see the module docstring).

    ``send`` (a worker process of its own: the local pool's) is how a run's record is
    sent when the run must end the process: a system under test that does not stop
    (``runner.execute``'s ``hard_stop``); the record is sent, then the process ends.

    Raises ScenarioError when the file has input errors (nothing can run).
    """

    def __init__(
        self, setup: CampaignSetup, send: Callable[[RunRecord], None] | None = None
    ) -> None:
        self.setup = setup
        self.send = send
        self.checked: Checked = check_file(
            setup.uri, scenario=setup.scenario, source=setup.text, config=setup.config
        )
        self._items: list[SteerableItem] | None = None

    def items(self) -> list[SteerableItem]:
        """The scenario's cover items and what can steer them (compiled once)."""
        if self._items is None:
            self._items = cover_items(self.checked, dt_control=self.setup.dt_control)
        return self._items

    def witness(self, task: RunTask) -> Witness | None:
        """The witness of a task drawn in a bin (None: the seed's own)."""
        if task.bin is None:
            return None
        return directed_witness(self.checked, self.items(), task.bin, task.seed)

    def run(self, task: RunTask) -> RunRecord:
        """Run one task; its record, whatever happened."""
        setup = self.setup
        started = time.perf_counter()
        rel = run_folder(task.seed)
        temp = tempfile.mkdtemp(prefix="osc2run-") if setup.ship_files else None
        folder = Path(temp) if temp is not None else Path(setup.out) / rel
        record = RunRecord(task.seed, "error", "", task.bin, folder=rel)
        try:
            witness = self.witness(task)
            prepared = prepare_run(self.checked, setup.for_seed(task.seed), witness=witness)
            try:
                result = execute(
                    prepared,
                    out=folder,
                    duration=setup.duration,
                    plot=setup.plot,
                    export=ExportTargets.in_folder(folder, setup.export),
                    hard_stop=self._hard_stop(record, prepared.sut, started),
                )
            except RunInterrupted as exc:
                result = exc.result
            if not setup.plot and result.outcome.status in ("failure", "timeout", "error"):
                _plot_after(result, folder, prepared.world.network)
            describe(record, result, self.checked, prepared.sut)
            for entry in self.items():
                if entry.components:  # cross coverage: the campaign's, from its parts
                    record.coverage[entry.item.name] = entry.hits(record.coverage)
            record.files = sorted(p.name for p in result.outputs)
        except ScenarioError as exc:
            record.reason = _problem_text(exc)
        except Exception as exc:  # a bug in this run: recorded, the campaign goes on
            record.reason = f"internal error: {type(exc).__name__}: {exc}"
            record.error = traceback.format_exc()
        finally:
            record.wall_s = round(time.perf_counter() - started, 3)
            if temp is not None:
                record.shipped = _read_files(Path(temp))
                record.files = sorted(record.shipped)
                shutil.rmtree(temp, ignore_errors=True)
        if record.bin is not None and not record.bin.label:
            record.bin = self._labelled(record.bin)
        return record

    def _hard_stop(
        self, record: RunRecord, sut: dict[str, str] | None, started: float
    ) -> Callable[[RunResult, int], None] | None:
        """What ends this process when its run's system under test does not stop: the
        record of what was written is sent first."""
        send = self.send
        if send is None:
            return None

        def stop(result: RunResult, status: int) -> None:
            describe(record, result, self.checked, sut)
            record.files = sorted(p.name for p in result.outputs)
            record.wall_s = round(time.perf_counter() - started, 3)
            try:
                send(record)
            finally:
                os._exit(status)

        return stop

    def _labelled(self, ref: BinRef) -> BinRef:
        entry = next((e for e in self.items() if e.item.name == ref.item), None)
        if entry is None or not 0 <= ref.index < len(entry.item.buckets):
            return ref
        return BinRef(ref.item, ref.index, entry.item.buckets[ref.index].label)


def _plot_after(result: RunResult, folder: Path, network: RoadNetwork) -> None:
    """Plots of a run that did not pass (as ``--plot`` draws them: ``world.png`` with the
    map's lanes), and its ``run.json`` again (written last)."""
    from osc2runner.output.plots import plot_run
    from osc2runner.output.telemetry import write_metadata

    plots = plot_run(result, folder, network)
    result.outputs.extend(plots)
    write_metadata(folder, result.metadata, result.events)


def _read_files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


def _problem_text(exc: ScenarioError) -> str:
    parts = [str(p) for p in exc.problems]
    parts += [f"{d.code.code} {d.message}" for d in exc.diagnostics]
    return "; ".join(parts) or "the scenario cannot run"


def describe(
    record: RunRecord, result: RunResult, checked: Checked, sut: dict[str, str] | None
) -> None:
    """Fill ``record`` from a finished run: outcome, parameters, KPIs, records, coverage."""
    o = result.outcome
    meta = result.metadata
    record.status, record.reason, record.tick = o.status, o.reason, o.tick
    record.time_s = tick_time(o.time, meta["dt_control"])
    record.parameters = parameters(meta.get("witness"), checked)
    actors = meta.get("actors", {})
    sizes = {n: (a["size"]["length"], a["size"]["width"]) for n, a in actors.items() if "size" in a}
    subject = subject_actor(actors, sut["actor"] if sut else None)
    start = actors.get(subject, {}).get("start", {}) if subject else {}
    collisions = [(r.tick, r.actors) for r in result.events if r.kind == "collision"]
    record.kpis = {
        "subject": subject,
        **run_kpis(result.telemetry, sizes, collisions, subject, start.get("speed")),
    }
    for item in result.coverage.items:
        if item.kind == "record":
            values = item.values()
            record.records[item.name] = values[-1] if len(values) == 1 else values
        elif item.buckets:
            record.coverage[item.name] = sorted(
                {s.bucket for s in item.samples if s.bucket is not None and not s.ignored}
            )


def parameters(witness: dict[str, Any] | None, checked: Checked) -> dict[str, dict[str, Any]]:
    """The witness's scenario parameters that constraints decide: ``{"text": "50 kph",
    "value": 50.0, "unit": "kph"}`` (value in the unit shown; enums and booleans as
    they are)."""
    if not witness:
        return {}
    variables: dict[str, ir.Var] = scenario_result(checked).problem.variables
    found: dict[str, dict[str, Any]] = {}
    for p in witness.get("parameters", []):
        name = p["name"]
        if not p.get("constrained") or "@" in name:
            continue
        var = variables.get(name)
        entry: dict[str, Any] = {"text": p["text"], "unit": var.unit if var else ""}
        if "si" in p and var is not None and not var.enum and not var.is_string:
            shown = (Fraction(p["si"]) - var.unit_offset) / var.unit_factor
            number = float(shown)
            entry["value"] = int(number) if var.sort == "int" else _round(number)
        else:
            entry["value"] = p.get("value", p["text"])
        found[name] = entry
    return found


def _round(value: float) -> float:
    return float(f"{value:.10g}") if math.isfinite(value) else value


def process_memory() -> int:
    """This process's peak resident memory in bytes (0 where unknown)."""
    try:
        import resource

        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        return int(peak) * (1 if os.uname().sysname == "Darwin" else 1024)
    except (ImportError, OSError):  # pragma: no cover - not POSIX
        return 0
