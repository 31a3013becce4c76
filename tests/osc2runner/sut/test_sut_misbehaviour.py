"""A system under test cannot lie to CI: whatever its code does, the run ends with an
outcome that says so, its files written, and the command's exit status follows.

It used to: ``sys.exit(0)`` in ``step`` made ``osc2run`` exit 0 with nothing written;
``KeyboardInterrupt`` made the run "interrupted" (and a campaign "complete", its runs
skipped); a failing ``__init__`` or ``reset`` was an internal error; a ``step`` that
slept or looped made ``osc2run`` deaf to SIGINT, SIGTERM and SIGHUP (twice each), with
no limit on its wall-clock time; a signal that cut ``import mujoco`` short was
``internal error: ImportError``.

The subprocess tests wait for the SUT's own marker on stderr ("sut: sleeping") before
they send a signal: no test waits a fixed time.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from osc2runner.campaign import CampaignOptions, run_campaign
from osc2runner.cli import main
from osc2runner.execution.signals import SignalInterrupt
from osc2runner.sut.loading import SutSpec
from tests.osc2runner.processes import POSIX, env, wait_for

HERE = Path(__file__).parent
SUTS = HERE.parent / "campaign" / "suts.py"

EGO = """\
import osc.standard

scenario ego_drive:
    ego: vehicle
    do ego.drive(duration: 20s) with:
        speed(30kph)
"""


@pytest.fixture
def scenario(tmp_path: Path) -> Path:
    path = tmp_path / "ego.osc"
    path.write_text(EGO, encoding="utf-8")
    return path


def _run_in_process(scenario: Path, sut: str, *more: str) -> tuple[int, str, dict]:
    out = scenario.parent / "out"
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        status = main([str(scenario), "--sut", f"{SUTS}:{sut}", "--out", str(out), "-q", *more])
    outcome = json.loads((out / "run.json").read_text())["outcome"] if out.exists() else {}
    return status, err.getvalue(), outcome


@pytest.mark.parametrize(
    ("sut", "says"),
    [
        ("ExitsZero", "raised SystemExit: 0 in step at tick 0"),
        ("RaisesKeyboardInterrupt", "raised KeyboardInterrupt in step at tick 0"),
        ("RaisesBaseException", "raised OwnBaseException: out of band in step at tick 0"),
        ("FakesASignal", "raised KeyboardInterrupt in step at tick 0"),
        ("FailsInInit", "raised RuntimeError: no licence in its construction"),
        ("FailsInReset", "raised RuntimeError: calibration missing in reset"),
    ],
)
def test_whatever_the_sut_raises_is_a_run_error_naming_it(scenario, sut, says):
    status, err, outcome = _run_in_process(scenario, sut)
    assert status == 2, err
    assert outcome["status"] == "error"
    assert outcome["reason"] == f"the system under test ({sut}) {says}"
    assert "internal error" not in err


def test_a_sut_module_that_exits_on_import_is_a_usage_error(tmp_path, scenario):
    (tmp_path / "leaves.py").write_text("import sys\nsys.exit(0)\n", encoding="utf-8")
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        status = main([str(scenario), "--sut", f"{tmp_path / 'leaves.py'}:Sut"])
    assert status == 2
    assert "cannot import" in err.getvalue() and "SystemExit" in err.getvalue()


@POSIX
@pytest.mark.parametrize("sut", ["SleepsAtTick5", "CatchesTheTimeout"])
def test_a_step_over_its_wall_clock_budget_ends_the_run_as_error(scenario, sut):
    status, err, outcome = _run_in_process(scenario, sut, "--step-timeout", "0.2")
    assert status == 2, err
    assert outcome["status"] == "error"
    assert outcome["reason"].startswith(f"the system under test ({sut}) did not return from step")
    assert outcome["reason"].endswith("within 0.2 s")


def test_step_timeout_is_checked_and_needs_a_sut(scenario, capsys):
    assert main([str(scenario), "--step-timeout", "0"]) == 2
    assert "--step-timeout 0: must be positive" in capsys.readouterr().err
    assert main([str(scenario), "--step-timeout", "1"]) == 2
    assert "--step-timeout needs --sut" in capsys.readouterr().err


def test_a_signal_that_cuts_an_import_short_is_an_interruption(scenario, monkeypatch, capsys):
    """An extension module whose initialisation a signal interrupts fails with its own
    exception (``ImportError: initialization failed`` for ``import mujoco``)."""
    import osc2runner.cli as cli

    def import_cut_short(args, out, err):
        try:
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(60)  # (the signal's exception comes first)
        except SignalInterrupt:
            raise ImportError("initialization failed") from None
        return 0

    monkeypatch.setattr(cli, "_run", import_cut_short)
    assert main([str(scenario)]) == 128 + signal.SIGTERM
    err = capsys.readouterr().err
    assert "interrupted by SIGTERM" in err and "internal error" not in err


# ---- signals reach the SUT's code (a real osc2run) ------------------------------------------


def _start(scenario: Path, sut: str, tmp_path: Path, *more: str) -> tuple[subprocess.Popen, Path]:
    log = tmp_path / "stderr.log"
    command = [sys.executable, "-m", "osc2runner", str(scenario), "--sut", f"{SUTS}:{sut}"]
    command += ["--out", str(tmp_path / "out"), "-q", *more]
    with log.open("wb") as stderr:
        proc = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=stderr, env=env())
    return proc, log


def _written(tmp_path: Path) -> dict:
    """run.json, and telemetry.csv whole: one row per tick recorded."""
    out = tmp_path / "out"
    meta = json.loads((out / "run.json").read_text())
    rows = (out / "telemetry.csv").read_text().splitlines()
    assert len(rows) == 1 + meta["steps"] + 1  # the header, ticks 0 .. steps
    assert not [p for p in out.iterdir() if p.name.endswith(".tmp")]
    return meta


@POSIX
@pytest.mark.parametrize(
    ("sut", "marker", "signame"),
    [("SleepsAtTick5", "sut: sleeping", "SIGTERM"), ("LoopsAtTick5", "sut: looping", "SIGINT")],
)
def test_a_signal_stops_a_run_inside_the_sut(scenario, tmp_path, sut, marker, signame):
    proc, log = _start(scenario, sut, tmp_path)
    wait_for(log, marker, proc)
    proc.send_signal(getattr(signal, signame))
    assert proc.wait(120) == 128 + getattr(signal, signame)
    outcome = _written(tmp_path)["outcome"]
    assert outcome["status"] == "interrupted" and outcome["signal"] == signame
    assert outcome["tick"] == 5


@POSIX
def test_a_second_signal_stops_a_sut_that_swallows_the_first(scenario, tmp_path):
    proc, log = _start(scenario, "SwallowsAtTick5", tmp_path)
    wait_for(log, "sut: swallowing", proc)
    proc.send_signal(signal.SIGTERM)
    wait_for(log, "sut: swallowed SignalInterrupt", proc)
    proc.send_signal(signal.SIGHUP)
    assert proc.wait(120) == 128 + signal.SIGHUP
    outcome = _written(tmp_path)["outcome"]
    assert outcome["status"] == "interrupted" and outcome["signal"] == "SIGHUP"


@POSIX
def test_a_sut_that_swallows_its_timeout_is_stopped_when_it_runs_out_again(scenario, tmp_path):
    proc, log = _start(scenario, "SwallowsAtTick5", tmp_path, "--step-timeout", "0.3")
    assert proc.wait(120) == 2
    assert "swallowed StepTimeout" in log.read_text()
    outcome = _written(tmp_path)["outcome"]
    assert outcome["status"] == "error"
    assert outcome["reason"] == (
        "the system under test (SwallowsAtTick5) in step at tick 5 ran past 0.3 s and did not stop"
    )


# ---- campaigns count such runs as errors ---------------------------------------------------


def test_a_campaign_counts_a_lying_sut_as_errors_never_as_skipped(scenario, tmp_path):
    result = run_campaign(
        CampaignOptions(
            str(scenario),
            runs=2,
            out=str(tmp_path / "campaign"),
            jobs=1,
            sut=SutSpec(f"{SUTS}:RaisesKeyboardInterrupt").resolved(),
        )
    )
    assert [r.status for r in result.records] == ["error", "error"]
    assert result.status == "complete" and result.summary["outcomes"] == {"error": 2}
    doc = json.loads((tmp_path / "campaign" / "campaign.json").read_text())
    assert doc["not_run"] == [] and doc["summary"]["finished"] == 2


# ---- a seeded storm of behaviours ----------------------------------------------------------

#: what each misbehaviour of ``Chaotic`` ends the run with
EXPECTED = {
    "nan": "returned a non-finite command",
    "type": "returned str from step at tick",
    "value_error": "raised ValueError: sensor failure in step",
    "system_exit": "raised SystemExit: 0 in step",
    "keyboard": "raised KeyboardInterrupt in step",
    "base": "raised OwnBaseException: out of band in step",
    "late": "did not return from step",
}


@POSIX
@pytest.mark.parametrize("seed", range(10))
def test_sut_storm_the_first_misbehaviour_ends_the_run_as_error(seed):
    """Each seed draws a SUT that drives well for a while, then misbehaves one way:
    the run ends at that tick as ``error`` saying how, however it misbehaved."""
    from osc2runner import run
    from tests.osc2runner.campaign.suts import Chaotic

    plan = Chaotic.plan(seed)
    tick, kind = next((t, k) for t, k in enumerate(plan) if k not in ("drive", "demand"))
    spec = SutSpec(f"{SUTS}:Chaotic", step_timeout=0.1)
    result = run("ego.osc", source=EGO, seed=seed, sut=spec)
    assert result.outcome.status == "error", result.outcome
    assert result.outcome.tick == tick
    assert EXPECTED[kind] in result.outcome.reason and "(Chaotic)" in result.outcome.reason
