"""The files of a campaign, each written whole or not at all.

In the campaign folder ``DIR``:

* ``runs/<seed>/``: each run's files, as ``osc2run FILE --seed <seed> --out``
  writes them (``telemetry.csv``, ``events.csv``, ``coverage.json``,
  ``run.json``, plots with ``--plot``), plus ``record.json``: what the
  campaign keeps of the run (written when the run's record arrives; ``--resume``
  reads these to skip finished seeds);
* ``campaign.json``: the campaign (source and its SHA-256, options, plan,
  summary, coverage, KPI figures, worst runs) and every run's record with the
  command that replays it; written at the start (``status: running``) and at
  the end (``complete`` or ``interrupted``);
* ``runs.csv``: one row a run: seed, bin, outcome, reason, the parameters that
  vary, the KPIs, the records, wall time, the replay command; a text cell that a
  spreadsheet would read as a formula (it begins with ``=``, ``+``, ``-``, ``@``, a
  tab or a carriage return) begins with a ``'`` (``neutral``);
* ``junit.xml``: one ``testcase`` a run, named by the scenario and the swept
  parameters' values (``my_ccrm[ego_speed=75.8kph,offset=-0.08m]``; with the seed
  when two runs would share a name), the parameters and the seed in
  ``properties``; a ``failure`` for ``failure``/``timeout``, an ``error`` for
  ``error``, ``skipped`` for ``interrupted``, its message the outcome and the KPIs
  — the form CI systems read;
* ``report.html``: :mod:`osc2runner.campaign.report`.

Every JSON file is written with numbers that are not finite as null
(``schema.finite``); ``record.json`` and ``campaign.json`` are read through
:mod:`osc2runner.campaign.schema` (a folder is data: nothing in it is trusted).
"""

from __future__ import annotations

import csv
import io
import json
import logging
import shlex
from collections import Counter
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any
from xml.etree import ElementTree as ET

from osc2check.inputs import InputError, not_regular, probe, read_bytes
from osc2runner.campaign.kpis import KPI_UNITS, kpi_text
from osc2runner.campaign.parameters import compact_text
from osc2runner.campaign.schema import FolderError, campaign_document, finite, record_from_json
from osc2runner.campaign.summary import varying
from osc2runner.campaign.worker import RunRecord
from osc2runner.options import DT_CONTROL, DT_PHYSICS, RunOptions
from osc2runner.output.files import write_atomically

__all__ = [
    "CAMPAIGN_FILE",
    "CAMPAIGN_FORMAT",
    "RECORD_FILE",
    "neutral",
    "read_campaign",
    "replay_command",
    "read_records",
    "write_campaign",
    "write_junit",
    "write_record",
    "write_runs_csv",
]

log = logging.getLogger(__name__)

CAMPAIGN_FILE = "campaign.json"
RECORD_FILE = "record.json"
CAMPAIGN_FORMAT = 1
MAX_RECORD_BYTES = 16 * 1024 * 1024  # far above a record; a file beyond is not one
MAX_CAMPAIGN_BYTES = 256 * 1024 * 1024


def _json(data: Any) -> str:
    return json.dumps(finite(data), indent=2, allow_nan=False, default=str) + "\n"


def write_record(folder: Path, record: RunRecord) -> Path:
    """``runs/<seed>/record.json`` (and the run's files when they were shipped back:
    ``run.json`` last, as a run writes it)."""
    run_dir = folder / record.folder
    run_dir.mkdir(parents=True, exist_ok=True)
    if record.shipped:
        names = sorted(record.shipped, key=lambda n: n == "run.json")
        for name in names:
            write_atomically(run_dir / name, record.shipped[name])
    return write_atomically(run_dir / RECORD_FILE, _json(record.to_json()))


def read_records(folder: Path) -> dict[int, RunRecord]:
    """The records of the runs in ``folder/runs`` that hold one (``schema``), by seed;
    one that is not (unreadable, of another shape, of another seed than its folder's
    name) is left out: the run is done again."""
    found: dict[int, RunRecord] = {}
    runs = folder / "runs"
    if not runs.is_dir():
        return found
    for path in sorted(runs.glob(f"*/{RECORD_FILE}")):
        where = f"{path.parent.name}/{RECORD_FILE}"
        try:
            data = json.loads(read_bytes(path, MAX_RECORD_BYTES))
            record = record_from_json(data, where)
            if str(record.seed) != path.parent.name:
                raise FolderError(f"{where}: the record of seed {record.seed}")
        except (InputError, ValueError) as exc:  # (FolderError, JSONDecodeError)
            log.warning("%s: %s: the run is done again", folder, exc)
            continue
        found[record.seed] = record
    return found


def read_campaign(folder: Path) -> dict[str, Any] | None:
    """What ``campaign.json`` of ``folder`` holds (``schema.campaign_document``), or None
    when there is none; FolderError when it cannot be read or is not a campaign."""
    path = folder / CAMPAIGN_FILE
    try:
        status = probe(path)
    except InputError:
        return None
    try:
        if not_regular(status):
            raise InputError(not_regular(status) or "")
        data = json.loads(read_bytes(path, MAX_CAMPAIGN_BYTES))
    except (InputError, ValueError) as exc:
        raise FolderError(f"{path}: cannot read: {exc}") from None
    return campaign_document(data, str(path))


def write_campaign(folder: Path, document: dict[str, Any]) -> Path:
    return write_atomically(folder / CAMPAIGN_FILE, _json(document))


_FORMULA = ("=", "+", "-", "@", "\t", "\r")


def neutral(text: str) -> str:
    """``text`` as a spreadsheet shows it, never runs it: a leading ``'`` before a text
    that begins like a formula (OWASP's advice on CSV injection)."""
    return "'" + text if text.startswith(_FORMULA) else text


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return str(value)  # a number as written is a number (-3.5), not a formula
    if isinstance(value, (list, dict)):
        return neutral(json.dumps(finite(value)))
    return neutral(str(value))


def write_runs_csv(folder: Path, records: Sequence[RunRecord], replay: dict[int, str]) -> Path:
    """``runs.csv``: one row a run (see the module docstring)."""
    params = varying(records)
    record_names = sorted({n for r in records for n in r.records})
    kpi_names = [k for k in KPI_UNITS]
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(
        ["seed", "bin", "outcome", "reason", "time_s"]
        + params
        + ["subject"]
        + kpi_names
        + [f"record:{n}" for n in record_names]
        + ["wall_s", "replay"]
    )
    for r in sorted(records, key=lambda r: r.seed):
        writer.writerow(
            [r.seed, _cell(r.bin.text if r.bin else ""), _cell(r.status), _cell(r.reason)]
            + [_cell(r.time_s)]
            + [_cell(r.parameters.get(p, {}).get("value")) for p in params]
            + [_cell(r.kpis.get("subject"))]
            + [_cell(r.kpis.get(k)) for k in kpi_names]
            + [_cell(r.records.get(n)) for n in record_names]
            + [_cell(r.wall_s), _cell(replay.get(r.seed, ""))]
        )
    return write_atomically(folder / "runs.csv", out.getvalue())


def case_names(
    suite: str, records: Sequence[RunRecord], swept: Sequence[str], units: Mapping[str, str]
) -> dict[int, str]:
    """Each run's testcase name: the scenario and the swept parameters' values
    (``my_ccrm[ego_speed=75.8kph,offset=-0.08m]``); a name two runs share gets the seed."""
    names = {}
    for r in records:
        values = ",".join(
            f"{n}={compact_text(r.parameters[n].get('value'), units.get(n, ''))}"
            for n in swept
            if n in r.parameters
        )
        names[r.seed] = f"{suite}[{values}]" if values else f"{suite} seed {r.seed}"
    counts = Counter(names.values())
    return {s: n if counts[n] == 1 else f"{n} seed {s}" for s, n in names.items()}


def write_junit(
    folder: Path,
    document: Mapping[str, Any],
    records: Sequence[RunRecord],
    replay: dict[int, str],
    wall: float,
) -> Path:
    """``junit.xml``: a testsuite of one testcase a run, named by its swept parameters;
    a failure's message gives the outcome and the KPIs."""
    suite = document["scenario"]
    parameters = document.get("parameters", {})
    units = {n: d.get("unit", "") for n, d in parameters.get("domains", {}).items()}
    names = case_names(suite, records, parameters.get("swept", []), units)
    ordered = sorted(records, key=lambda r: r.seed)
    failures = sum(1 for r in ordered if r.status in ("failure", "timeout"))
    errors = sum(1 for r in ordered if r.status == "error")
    skipped = sum(1 for r in ordered if r.status == "interrupted")
    suites = ET.Element("testsuites", name="osc2run campaign")
    ts = ET.SubElement(
        suites,
        "testsuite",
        name=suite,
        tests=str(len(ordered)),
        failures=str(failures),
        errors=str(errors),
        skipped=str(skipped),
        time=f"{wall:.3f}",
    )
    for r in ordered:
        case = ET.SubElement(
            ts, "testcase", classname=suite, name=names[r.seed], time=f"{r.wall_s:.3f}"
        )
        props = ET.SubElement(case, "properties")
        for name, p in sorted(r.parameters.items()):
            ET.SubElement(props, "property", name=name, value=str(p.get("text", p.get("value"))))
        if r.bin is not None:
            ET.SubElement(props, "property", name="bin", value=r.bin.text)
        ET.SubElement(props, "property", name="seed", value=str(r.seed))
        told = kpi_text(r.kpis)
        message = f"{r.status}: {r.reason}" + (f"; {told}" if told else "")
        detail = f"replay: {replay.get(r.seed, '')}\nfiles: {r.folder}/"
        if r.status in ("failure", "timeout"):
            ET.SubElement(case, "failure", message=message, type=r.status).text = detail
        elif r.status == "error":
            ET.SubElement(case, "error", message=message, type="error").text = detail + (
                f"\n{r.error}" if r.error else ""
            )
        elif r.status == "interrupted":
            ET.SubElement(case, "skipped", message=message)
    ET.indent(suites)
    text = '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(suites, encoding="unicode")
    return write_atomically(folder / "junit.xml", text + "\n")


def replay_command(
    uri: str,
    options: RunOptions,
    *,
    bin_text: str | None,
    language: Sequence[str] = (),
) -> str:
    """The ``osc2run`` command that replays the run of ``options`` alone (byte-identical
    telemetry); ``language``: the OSC2 version, dialect and plug-in options it was run
    with (``options.config`` is not written out)."""
    args = ["osc2run", uri, "--seed", str(options.seed), *language]
    if options.scenario:
        args += ["--scenario", options.scenario]
    if bin_text:
        args += ["--bin", bin_text]
    if options.duration is not None:
        args += ["--duration", f"{options.duration:g}"]
    if options.dt_control != DT_CONTROL:
        args += ["--dt-control", repr(options.dt_control)]
    if options.dt_physics != DT_PHYSICS:
        args += ["--dt-physics", repr(options.dt_physics)]
    if options.kinematic:
        args += ["--kinematic", ",".join(options.kinematic)]
    if options.sut is not None:
        args += ["--sut", options.sut.target]
        if options.sut.actor:
            args += ["--sut-actor", options.sut.actor]
    return shlex.join(args)
