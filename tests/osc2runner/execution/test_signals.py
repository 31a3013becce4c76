"""SIGINT, SIGTERM and SIGHUP: the loop stops at a tick boundary, the files are whole.

The subprocess tests start a real ``osc2run`` on a long scenario, wait until it
has simulated something (the ``--debug`` log's "simulated 1.0 s" marker, read
from its stderr file) and then send the signal; no test waits a fixed time.
"""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

import pytest

from osc2runner import run
from osc2runner.execution.signals import Interrupts, SignalInterrupt, exit_status, raising
from osc2runner.output import telemetry
from osc2runner.runner import RunInterrupted
from tests.osc2runner.processes import POSIX, ROOT, env, wait_for

HERE = Path(__file__).parent
EVENTS = HERE.parent / "trees" / "events.osc"

LONG = """\
import osc.standard

scenario long_drive:
    hero: vehicle
    npc: vehicle
    do parallel:
        serial:
            hero.assign_position() with:
                lane(1, at: start)
                speed(1kph, at: start)
            hero.drive(duration: 1000s) with:
                speed(1kph)
        serial:
            npc.assign_position() with:
                lane(2, at: start)
                speed(1kph, at: start)
            npc.drive(duration: 1000s) with:
                speed(1kph)
"""

#: started instead of ``python -m osc2runner``: sends itself SIGINT after tick 40, and again
#: while telemetry.csv is being written (the first number formatted), then runs the command
DOUBLE_SIGINT = """\
import os, signal, sys
from osc2runner.cli import main
from osc2runner.execution import loop
from osc2runner.output import telemetry

step = loop.TickLoop.step
def step_then_interrupt(self):
    outcome = step(self)
    if self.world.tick == 40:
        os.kill(os.getpid(), signal.SIGINT)
    return outcome
loop.TickLoop.step = step_then_interrupt

number = telemetry._number
sent = []
def number_and_interrupt(value):
    if not sent:
        sent.append(True)
        os.kill(os.getpid(), signal.SIGINT)
        sys.stderr.write("test: second SIGINT sent while writing telemetry.csv\\n")
    return number(value)
telemetry._number = number_and_interrupt

sys.exit(main(sys.argv[1:]))
"""


def _check_complete(out: Path, signame: str) -> dict[str, Any]:
    """run.json parses and says interrupted by ``signame``; telemetry.csv has every actor's
    row for every tick up to run.json's steps, and nothing more; no temporary files."""
    meta = json.loads((out / "run.json").read_text())
    outcome = meta["outcome"]
    assert outcome["status"] == "interrupted"
    assert outcome["signal"] == signame and signame in outcome["reason"]
    steps = meta["steps"]
    assert steps > 0 and outcome["tick"] == steps
    text = (out / "telemetry.csv").read_text()
    assert text.endswith("\n")
    with (out / "telemetry.csv").open(newline="") as f:
        rows = list(csv.DictReader(f))
    for actor in ("hero", "npc"):
        ticks = [int(r["tick"]) for r in rows if r["actor"] == actor]
        assert ticks == list(range(steps + 1))
    assert len(rows) == 2 * (steps + 1)
    assert all(len(r) == 1 + len(telemetry.CHANNELS) and None not in r.values() for r in rows)
    events = list(csv.DictReader((out / "events.csv").open(newline="")))
    assert events[-1]["kind"] == "outcome" and events[-1]["name"] == "interrupted"
    assert not [p.name for p in out.iterdir() if p.name.endswith(".tmp")]
    return meta


@pytest.mark.slow
@POSIX
@pytest.mark.parametrize("signame", ["SIGTERM", "SIGHUP", "SIGINT"])
def test_a_signal_mid_run_writes_complete_files(tmp_path, signame):
    if not hasattr(signal, signame):
        pytest.skip(f"no {signame} here")
    signum = int(getattr(signal, signame))
    source = tmp_path / "long.osc"
    source.write_text(LONG)
    out = tmp_path / "out"
    err = tmp_path / "stderr.txt"
    command = [sys.executable, "-m", "osc2runner", str(source), "--out", str(out), "--debug"]
    with err.open("w") as stderr:
        proc = subprocess.Popen(
            [*command, "--duration", "1000"],
            stdout=subprocess.PIPE,
            stderr=stderr,
            env=env(),
            cwd=ROOT,
            text=True,
        )
    try:
        wait_for(err, "simulated 1.0 s", proc)
        proc.send_signal(signum)
        stdout, _ = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 128 + signum == exit_status(signum)
    assert "interrupted at" in stdout and f"interrupted by {signame}" in stdout
    meta = _check_complete(out, signame)
    assert meta["simulated_time"] >= 1.0


@pytest.mark.slow
@POSIX
def test_a_second_sigint_while_the_files_are_written_does_not_cut_them(tmp_path):
    source = tmp_path / "long.osc"
    source.write_text(LONG)
    out = tmp_path / "out"
    proc = subprocess.run(
        [sys.executable, "-c", DOUBLE_SIGINT, str(source), "--out", str(out), "-q"],
        capture_output=True,
        text=True,
        env=env(),
        cwd=ROOT,
        timeout=300,
        check=False,
    )
    assert "second SIGINT sent while writing telemetry.csv" in proc.stderr
    assert proc.returncode == 130, proc.stderr
    assert "Traceback" not in proc.stderr
    meta = _check_complete(out, "SIGINT")
    assert meta["steps"] == 40


# ---------------------------------------------------------------------- in this process


class _Recorder:
    """A signal handler that records what it is called with (and when)."""

    def __init__(self, check: Any = None) -> None:
        self.calls: list[int] = []
        self.check = check

    def __call__(self, signum: int, frame: object) -> None:
        self.calls.append(signum)
        if self.check is not None:
            self.check()


@pytest.fixture
def own_handlers():
    """Recording handlers for SIGINT, SIGTERM (and SIGHUP) during the test, restored after."""
    signums = [int(signal.SIGINT), int(signal.SIGTERM)]
    if hasattr(signal, "SIGHUP"):
        signums.append(int(signal.SIGHUP))
    handlers = {s: _Recorder() for s in signums}
    previous = {s: signal.signal(s, h) for s, h in handlers.items()}
    try:
        yield handlers
    finally:
        for s, h in previous.items():
            signal.signal(s, h)


def test_run_restores_the_handlers_it_found(own_handlers):
    run(EVENTS, duration=1.0)
    for signum, handler in own_handlers.items():
        assert signal.getsignal(signum) is handler


def test_a_signal_stops_the_run_at_the_end_of_the_tick(tmp_path, own_handlers):
    def terminate(sim: float, limit: float, wall: float) -> None:
        if sim >= 2.0:
            os.kill(os.getpid(), signal.SIGTERM)

    out = tmp_path / "out"
    with pytest.raises(RunInterrupted) as caught:
        run(EVENTS, out=out, progress=terminate)
    assert caught.value.signum == signal.SIGTERM
    result = caught.value.result
    assert result.outcome.status == "interrupted" and result.outcome.signal == "SIGTERM"
    assert result.outcome.tick == 40 and result.telemetry["hero"]["tick"][-1] == 40
    assert json.loads((out / "run.json").read_text())["outcome"]["signal"] == "SIGTERM"
    assert own_handlers[int(signal.SIGTERM)].calls == []  # it stopped the run: not passed on
    assert signal.getsignal(signal.SIGTERM) is own_handlers[int(signal.SIGTERM)]


def test_a_signal_while_a_finished_run_writes_is_passed_on_once_the_files_are_whole(
    tmp_path, own_handlers, monkeypatch
):
    out = tmp_path / "out"
    handler = own_handlers[int(signal.SIGINT)]
    handler.check = lambda: handler.calls.append(int((out / "run.json").exists()))
    real_number = telemetry._number
    sent: list[bool] = []

    def number_and_interrupt(value: float) -> str:
        if not sent:
            sent.append(True)
            os.kill(os.getpid(), signal.SIGINT)
        return real_number(value)

    monkeypatch.setattr(telemetry, "_number", number_and_interrupt)
    result = run(EVENTS, out=out)
    assert sent and result.outcome.status == "success"
    assert handler.calls == [int(signal.SIGINT), 1]  # delivered once, after run.json was written
    assert json.loads((out / "run.json").read_text())["outcome"]["status"] == "success"


def test_a_keyboard_interrupt_from_progress_still_stops_the_run(own_handlers):
    def interrupt(sim: float, limit: float, wall: float) -> None:
        raise KeyboardInterrupt

    with pytest.raises(RunInterrupted) as caught:
        run(EVENTS, progress=interrupt)
    assert caught.value.signum is None and caught.value.result.outcome.signal is None
    assert exit_status(caught.value.signum) == 130


def test_a_run_in_another_thread_installs_no_handlers(own_handlers):
    seen: dict[str, Any] = {}

    def work() -> None:
        with Interrupts() as interrupts:
            seen["installed"] = interrupts.installed
        seen["status"] = run(EVENTS, duration=1.0).outcome.status
        seen["handler"] = signal.getsignal(signal.SIGINT)

    thread = threading.Thread(target=work)
    thread.start()
    thread.join()
    assert seen == {
        "installed": False,
        "status": "timeout",
        "handler": own_handlers[int(signal.SIGINT)],
    }


def test_interrupts_note_signals_and_restore_the_handlers(own_handlers):
    """The first signal is noted (the loop stops at the tick's end); a second one before
    the loop stopped raises where the code is."""
    with Interrupts() as interrupts:
        assert interrupts.installed
        os.kill(os.getpid(), signal.SIGTERM)
        assert interrupts.first == signal.SIGTERM
        with pytest.raises(SignalInterrupt) as second:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0)  # let the handler run
        assert second.value.signum == signal.SIGINT
        assert interrupts.received == [signal.SIGTERM, signal.SIGINT]
        assert interrupts.consume() == signal.SIGTERM
    assert own_handlers[int(signal.SIGTERM)].calls == []
    assert own_handlers[int(signal.SIGINT)].calls == []
    assert signal.getsignal(signal.SIGTERM) is own_handlers[int(signal.SIGTERM)]


def test_raising_turns_sigterm_into_an_interrupt(own_handlers):
    with pytest.raises(KeyboardInterrupt) as caught, raising():
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0)  # let the handler run
    assert getattr(caught.value, "signum", None) == signal.SIGTERM
    assert signal.getsignal(signal.SIGTERM) is own_handlers[int(signal.SIGTERM)]
