"""Campaigns on the local pool: outputs, replay, crashes, limits, interrupts, resume."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import threading
from dataclasses import replace
from pathlib import Path
from xml.etree import ElementTree as ET

import pytest

from osc2runner.campaign import CampaignOptions, CampaignResult, run_campaign
from osc2runner.sut.loading import SutSpec

HERE = Path(__file__).parent
ROOT = HERE.parents[2]
SUTS = HERE / "suts.py"
CUT_IN = ROOT / "examples" / "cut_in_and_stop.osc"

SHORT = """\
import osc.standard

scenario short:
    ego: vehicle with:
        keep(it.vehicle_category == car)
    v: speed with:
        keep(it in [10kph..60kph])
    cover(v, unit: kph, range: [0..100], every: 20, event: start)
    record(end_speed, expression: ego.speed, unit: kph)
    do serial:
        ego.assign_position() with:
            lane(2, at: start)
            speed(v, at: start)
        ego.drive(duration: 3s) with:
            speed(v)
"""


def osc2run(*args: str, **kw: object) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run(
        [sys.executable, "-m", "osc2runner", *args],
        capture_output=True, text=True, env=env, cwd=ROOT, timeout=600, **kw,
    )  # fmt: skip


CUT_IN_RUNS = 6  # enough to see the seeds' witnesses differ; the outputs are the same for 40


@pytest.fixture(scope="module")
def cut_in_campaign(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("cut_in") / "campaign"
    done = osc2run(str(CUT_IN), "--runs", str(CUT_IN_RUNS), "--jobs", "2", "--out", str(out))
    assert done.returncode == 0, done.stderr + done.stdout
    n = CUT_IN_RUNS
    assert f"{n} of {n} runs, {n} passed" in done.stdout
    return out


@pytest.mark.slow
@pytest.mark.xdist_group("cut_in_campaign")
def test_a_campaign_writes_the_five_outputs(cut_in_campaign: Path) -> None:
    out = cut_in_campaign
    for name in ("campaign.json", "runs.csv", "junit.xml", "report.html"):
        assert (out / name).is_file(), name
    doc = json.loads((out / "campaign.json").read_text())
    seeds = [r["seed"] for r in doc["runs"]]
    assert sorted(seeds) == list(range(CUT_IN_RUNS))
    assert doc["status"] == "complete" and doc["summary"]["pass_rate"] == 1.0
    for seed in seeds:
        run_dir = out / "runs" / str(seed)
        assert {"telemetry.csv", "events.csv", "coverage.json", "run.json", "record.json"} <= {
            p.name for p in run_dir.iterdir()
        }
    suite = ET.parse(out / "junit.xml").getroot().find("testsuite")
    assert suite is not None and suite.get("tests") == str(CUT_IN_RUNS)
    assert suite.get("failures") == "0" and len(suite.findall("testcase")) == CUT_IN_RUNS
    rows = (out / "runs.csv").read_text().splitlines()
    assert len(rows) == CUT_IN_RUNS + 1 and rows[0].startswith("seed,bin,outcome")
    # every parameter of the cut-in is fixed (`v_hero: speed = 35kph`), and recorded per run
    assert {r["parameters"]["v_hero"]["text"] for r in doc["runs"]} == {"35 kph"}
    # the witnesses differ: the start position is drawn per seed
    positions = {
        json.loads((out / "runs" / str(s) / "run.json").read_text())["actors"]["hero"]["start"]["s"]
        for s in seeds
    }
    assert len(positions) == CUT_IN_RUNS


@pytest.mark.slow
@pytest.mark.xdist_group("cut_in_campaign")
def test_a_campaign_run_replays_alone_byte_identical(cut_in_campaign: Path, tmp_path: Path) -> None:
    doc = json.loads((cut_in_campaign / "campaign.json").read_text())
    for run in (doc["runs"][0], doc["runs"][-1]):  # the first seed and the last
        assert run["replay"] == f"osc2run {CUT_IN} --seed {run['seed']}"
        alone = tmp_path / str(run["seed"])
        done = osc2run(str(CUT_IN), "--seed", str(run["seed"]), "--out", str(alone), "-q")
        assert done.returncode == 0, done.stderr
        for name in ("telemetry.csv", "events.csv"):
            assert (alone / name).read_bytes() == (
                cut_in_campaign / "runs" / str(run["seed"]) / name
            ).read_bytes()


@pytest.mark.slow
@pytest.mark.xdist_group("cut_in_campaign")
def test_report_is_one_self_contained_file(cut_in_campaign: Path) -> None:
    page = (cut_in_campaign / "report.html").read_text()
    assert page.count("data:image/png;base64,") >= 1
    assert "http://" not in page and "https://" not in page and "<script" not in page
    assert 'href="runs/0/run.json"' in page


def _short(tmp_path: Path) -> Path:
    path = tmp_path / "short.osc"
    path.write_text(SHORT, encoding="utf-8")
    return path


class _ClockThatJumps:
    """A campaign's wall clock that stands still until ``trigger`` exists, then reads an
    hour later for good: with one worker, the run in progress at the jump is the only one
    over a limit of 1 s, however loaded the machine is."""

    def __init__(self, trigger: Path) -> None:
        self.trigger = trigger

    def __call__(self) -> float:
        return 3600.0 if self.trigger.exists() else 0.0


@pytest.mark.slow
def test_crash_and_wall_clock_limit_are_errors_and_the_campaign_goes_on(tmp_path: Path) -> None:
    path = _short(tmp_path)
    result = run_campaign(
        CampaignOptions(
            str(path), runs=4, out=str(tmp_path / "c"), jobs=2,
            sut=SutSpec(f"{SUTS}:CrashOnSeed").resolved(),
        )
    )  # fmt: skip
    by_seed = {r.seed: r for r in result.records}
    assert by_seed[2].status == "error" and "died" in by_seed[2].reason
    assert [by_seed[s].status for s in (0, 1, 3)] == ["success"] * 3
    assert result.summary["failed"] == 1 and result.status == "complete"
    suts = Path(shutil.copy(SUTS, tmp_path / "suts.py"))  # its `stuck` lands in tmp_path
    slow = run_campaign(
        CampaignOptions(
            str(path), runs=3, out=str(tmp_path / "d"), jobs=1, run_timeout=1.0,
            sut=SutSpec(f"{suts}:StuckOnSeed").resolved(),
        ),
        clock=_ClockThatJumps(tmp_path / "stuck"),
    )  # fmt: skip
    by_seed = {r.seed: r for r in slow.records}
    assert by_seed[1].status == "error" and "wall-clock limit of 1 s" in by_seed[1].reason
    # the stopped run still wrote its files, ended at a tick boundary, long before its end
    meta = json.loads((tmp_path / "d" / "runs" / "1" / "run.json").read_text())
    assert meta["outcome"]["status"] == "interrupted" and meta["outcome"]["signal"] == "SIGTERM"
    assert 0 < meta["steps"] < 60
    assert by_seed[0].status == by_seed[2].status == "success"


@pytest.mark.slow
def test_plots_of_a_run_that_did_not_pass_are_those_of_plot(tmp_path: Path) -> None:
    """A campaign plots a run that did not pass after it: the same files ``--plot`` writes
    (``world.png`` with the map's lanes)."""
    from osc2runner import run
    from osc2runner.campaign.worker import CampaignSetup, RunTask, Worker

    spec = SutSpec(f"{SUTS}:Raises").resolved()
    alone = run("short.osc", source=SHORT, sut=spec.target, out=tmp_path / "alone", plot=True)
    assert alone.outcome.status == "error"
    worker = Worker(CampaignSetup("short.osc", SHORT, sut=spec, out=str(tmp_path / "c")))
    record = worker.run(RunTask(0))
    assert record.status == "error"
    pngs = sorted(p.name for p in (tmp_path / "alone").glob("*.png"))
    assert "world.png" in pngs and set(pngs) <= set(record.files)
    for name in pngs:
        assert (tmp_path / "alone" / name).read_bytes() == (
            tmp_path / "c" / record.folder / name
        ).read_bytes(), name


def test_the_report_links_every_plot_of_a_run(tmp_path: Path) -> None:
    from osc2runner.campaign.report import _links
    from osc2runner.campaign.worker import RunRecord

    run_dir = tmp_path / "runs" / "3"
    run_dir.mkdir(parents=True)
    wrote = ["braking.png", "world.png", "run.json", "telemetry.csv", "events.csv"]
    for name in [*wrote[:-1], "stray.png"]:
        (run_dir / name).write_bytes(b"")
    record = RunRecord(3, "failure", "collision", folder="runs/3", files=wrote)
    links = _links(record, tmp_path)
    for name in ("braking.png", "world.png", "run.json", "telemetry.csv"):
        assert f'href="runs/3/{name}"' in links, name
    assert "events.csv" not in links  # not there: not linked
    assert "stray" not in links  # there, but the run did not write it


@pytest.mark.slow
def test_records_and_coverage(tmp_path: Path) -> None:
    path = _short(tmp_path)
    result = run_campaign(CampaignOptions(str(path), runs=6, out=str(tmp_path / "c"), jobs=2))
    assert len({r.parameters["v"]["value"] for r in result.records}) > 1  # drawn per seed
    for r in result.records:
        v = r.parameters["v"]["value"]
        assert 10.0 <= v <= 60.0 and r.parameters["v"]["unit"] == "kph"
        assert r.coverage["v"] == [int(v // 20)]
        assert r.records["end_speed"] == pytest.approx(v, abs=0.5)
    (item,) = result.document["coverage"]
    hits = sum(b["hits"] for b in item["buckets"])
    assert hits == 6 and item["buckets"][4]["hits"] == 0  # 80..100 kph: above the range


def test_cover_strategy_fills_every_reachable_bin_and_reports_the_others(tmp_path: Path) -> None:
    path = _short(tmp_path)
    result = run_campaign(
        CampaignOptions(str(path), runs=4, out=str(tmp_path / "c"), jobs=2, strategy="cover")
    )
    (item,) = result.document["coverage"]
    states = [b["state"] for b in item["buckets"]]
    # v in [10..60] kph: [0..20), [20..40), [40..60) reachable, [60..80) only at 60 kph, [80..100]
    assert states[:3] == ["filled"] * 3
    assert states[4] == "unreachable"
    assert item["buckets"][3]["solver"] == "reachable" and states[3] == "filled"


@pytest.mark.slow
def test_directed_run_replays_alone_with_bin(tmp_path: Path) -> None:
    path = _short(tmp_path)
    result = run_campaign(
        CampaignOptions(str(path), runs=4, out=str(tmp_path / "c"), jobs=1, strategy="cover")
    )
    directed = [r for r in result.document["runs"] if r["bin"]]
    assert directed, "v = 60 kph exactly is a bin no seed's witness lands in"
    run = directed[0]
    assert "--bin v=3" in run["replay"]
    alone = tmp_path / "alone"
    done = osc2run(str(path), "--seed", str(run["seed"]), "--bin", "v=3", "--out", str(alone))
    assert done.returncode == 0, done.stderr
    assert (alone / "telemetry.csv").read_bytes() == (
        tmp_path / "c" / "runs" / str(run["seed"]) / "telemetry.csv"
    ).read_bytes()


@pytest.mark.slow
def test_ctrl_c_writes_what_finished_and_resume_does_the_rest(tmp_path: Path) -> None:
    path = _short(tmp_path)
    out = tmp_path / "c"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    args = [sys.executable, "-m", "osc2runner", str(path), "--runs", "8", "--jobs", "2",
            "--out", str(out), "--sut", f"{SUTS}:Slow"]  # fmt: skip
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=env, cwd=ROOT)  # fmt: skip
    assert proc.stdout is not None
    first = proc.stdout.readline()  # the first finished run
    assert first.startswith("[1/8]"), first + (proc.stderr.read() if proc.stderr else "")
    proc.send_signal(signal.SIGINT)
    rest, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    doc = json.loads((out / "campaign.json").read_text())
    assert doc["status"] == "interrupted" and doc["not_run"]
    done_before = {r["seed"] for r in doc["runs"] if r["outcome"]["status"] == "success"}
    assert done_before and len(done_before) < 8
    suite = ET.parse(out / "junit.xml").getroot().find("testsuite")
    assert suite is not None and int(suite.get("tests", 0)) == len(doc["runs"])
    refused = osc2run("--resume", str(out))  # the SUT is code: named again, or trusted
    assert refused.returncode == 2 and "--trust-folder" in refused.stderr
    again = osc2run("--resume", str(out), "--sut", f"{SUTS}:Slow")
    assert again.returncode == 0, again.stderr + again.stdout
    assert f"resuming: {len(done_before)} of 8 runs already finished" in again.stdout
    doc = json.loads((out / "campaign.json").read_text())
    assert doc["status"] == "complete" and len(doc["runs"]) == 8
    assert doc["summary"]["passed"] == 8 and doc["plan"]["resumed"] == sorted(done_before)


@pytest.mark.slow
def test_resume_refuses_another_text(tmp_path: Path) -> None:
    path = _short(tmp_path)
    run_campaign(CampaignOptions(str(path), runs=1, out=str(tmp_path / "c"), jobs=1))
    path.write_text(SHORT.replace("3s", "2s"), encoding="utf-8")
    done = osc2run("--resume", str(tmp_path / "c"))
    assert done.returncode == 2 and "another text of the file" in done.stderr


def test_campaign_usage_errors(tmp_path: Path) -> None:
    path = _short(tmp_path)
    plain = tmp_path / "plain"
    plain.write_text("", encoding="utf-8")
    for args, message in (
        (["--runs", "2", "--out", str(plain)], f"--out {plain}: is a file, not a folder"),
        (["--runs", "3"], "--runs needs --out DIR"),
        (["--runs", "0", "--out", str(tmp_path / "x")], "--runs 0: must be a positive"),
        (["--jobs", "2"], "--jobs needs --runs N"),
        (["--runs", "2", "--out", str(tmp_path / "x"), "--address", "auto"], "needs --engine ray"),
        (["--sut", "nope"], "not `module:Class`"),
    ):
        done = osc2run(str(path), *args)
        assert done.returncode == 2 and message in done.stderr, (args, done.stderr)
        assert done.stderr.count("\n") == 1


GRID = """\
import osc.standard

scenario grid:
    ego: vehicle with:
        keep(it.vehicle_category == car)
    step: uint with:
        keep(it in [1..3])
    v: speed with:
        keep(it == step * 10kph)
    side: int with:
        keep(it in [-1, 1])
    cover(v, unit: kph, range: [5..35], every: 10, event: start)
    cover(side, range: [-1.5..1.5], every: 1, event: start)
    cover(cells, items: [v, side])
    do serial:
        ego.assign_position() with:
            lane(2, at: start)
            speed(v, at: start)
        ego.drive(duration: 1s) with:
            speed(v)
"""


@pytest.mark.slow
def test_cross_coverage_fills_every_combination(tmp_path: Path) -> None:
    path = tmp_path / "grid.osc"
    path.write_text(GRID, encoding="utf-8")
    result = run_campaign(
        CampaignOptions(str(path), runs=6, out=str(tmp_path / "c"), jobs=2, strategy="cover")
    )
    cells = next(i for i in result.document["coverage"] if i["name"] == "cells")
    # 3 speeds x 3 side buckets, of which side 0 is unreachable: 6 reachable cells, 6 runs
    assert cells["reachable"] == 6 and cells["unreachable"] == 3
    assert cells["filled"] == 6 and not cells["holes"]
    labels = [b["label"] for b in cells["buckets"] if b["state"] == "filled"]
    assert "[5..15) × [-1.5..-0.5)" in labels and "[25..35] × [0.5..1.5]" in labels
    combos = {(r.parameters["v"]["value"], r.parameters["side"]["value"]) for r in result.records}
    assert combos == {(v, s) for v in (10.0, 20.0, 30.0) for s in (-1, 1)}


@pytest.mark.slow
def test_resume_with_the_file_keeps_the_campaigns_options(tmp_path: Path) -> None:
    path = _short(tmp_path)
    out = tmp_path / "c"
    first = osc2run(str(path), "--runs", "3", "--seed", "5", "--jobs", "1", "--plot",
                    "--run-timeout", "120", "--out", str(out), "-q")  # fmt: skip
    assert first.returncode == 0, first.stderr + first.stdout
    again = osc2run(str(path), "--resume", str(out))
    assert again.returncode == 0, again.stderr + again.stdout
    assert "resuming: 3 of 3 runs already finished" in again.stdout
    assert "complete: 3 of 3 runs, 3 passed" in again.stdout
    doc = json.loads((out / "campaign.json").read_text())
    assert doc["plan"]["seeds"] == doc["plan"]["resumed"] == [5, 6, 7]
    assert [r["seed"] for r in doc["runs"]] == [5, 6, 7]
    options = doc["options"]
    assert (options["seed"], options["runs"], options["plot"], options["run_timeout"]) == (
        5, 3, True, 120.0,
    )  # fmt: skip
    assert len((out / "runs.csv").read_text().splitlines()) == 4


def test_resuming_a_finished_campaign_starts_no_worker(tmp_path: Path) -> None:
    path = _short(tmp_path)
    options = CampaignOptions(str(path), runs=2, out=str(tmp_path / "c"), jobs=2)
    first = run_campaign(options)
    assert first.status == "complete" and first.document["workers"]["started"] == 2
    again = run_campaign(replace(options, resume=True))
    assert again.status == "complete" and again.document["plan"]["resumed"] == [0, 1]
    assert again.document["workers"]["started"] == 0
    assert again.document["runs_per_minute"] == 0.0  # no run done by this invocation
    assert [r.seed for r in again.records] == [0, 1] and again.summary["passed"] == 2


def test_closing_the_pool_stops_a_worker_still_checking_the_file(tmp_path: Path) -> None:
    from osc2runner.campaign.pool import LocalPool
    from osc2runner.campaign.worker import CampaignSetup

    path = _short(tmp_path)
    pool = LocalPool(CampaignSetup(str(path), SHORT, out=str(tmp_path)), 1, None)
    pool.start(1)  # on a thread of its own
    pool.wait_started()
    (slot,) = pool.slots
    assert not slot.ready
    # the stop waits in the pipe: the worker leaves once ready, not killed (however long
    # checking the file takes on a loaded machine: the wait is a hang guard)
    pool.close(wait=300.0)
    assert slot.process.exitcode == 0


def test_a_campaign_runs_from_another_thread(tmp_path: Path) -> None:
    path = _short(tmp_path)
    found: list[CampaignResult | BaseException] = []

    def run() -> None:
        try:
            found.append(run_campaign(CampaignOptions(str(path), runs=1, out=str(tmp_path / "c"))))
        except BaseException as exc:  # reported below
            found.append(exc)

    thread = threading.Thread(target=run)
    thread.start()
    thread.join(timeout=300)
    (result,) = found
    assert isinstance(result, CampaignResult), repr(result)
    assert result.status == "complete" and result.summary["passed"] == 1


def test_a_lost_run_is_interrupted_or_an_error_in_its_folder() -> None:
    from osc2runner.campaign.steering import BinRef
    from osc2runner.campaign.worker import RunTask, lost_record, run_folder

    task = RunTask(7, BinRef("v", 3, "[60..80)"))
    stopped = lost_record(task, "interrupted", "the worker running it died (signal 9)")
    assert (stopped.status, stopped.reason) == ("interrupted", "the campaign was interrupted")
    assert not stopped.finished and stopped.bin == task.bin and stopped.folder == run_folder(7)
    late = lost_record(task, "over the wall-clock limit of 1 s per run", "died")
    assert (late.status, late.reason) == ("error", "over the wall-clock limit of 1 s per run")
    died = lost_record(task, "", "the worker running it died (signal 9)")
    assert (died.status, died.reason) == ("error", "the worker running it died (signal 9)")
