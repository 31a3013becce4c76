"""``osc2run``: exit statuses, outputs (also on failure and interruption), summaries."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from osc2runner import run
from osc2runner.cli import main
from osc2runner.runner import RunInterrupted

HERE = Path(__file__).parent
ROOT = HERE.parents[1]
EVENTS = HERE / "trees" / "events.osc"

CRASH = """\
import osc.standard

scenario crash:
    a: vehicle
    b: vehicle
    do parallel:
        serial:
            a.assign_position() with:
                lane(1, at: start)
                position(distance: 60m, at: start)
                speed(50kph, at: start)
            a.drive(duration: 10s) with:
                speed(50kph)
        serial:
            b.assign_position() with:
                lane(1, at: start)
                position(distance: 20m, behind: a, at: start)
                speed(50kph, at: start)
            b.drive(duration: 10s) with:
                speed(80kph)
"""

BROKEN = """\
import osc.standard

scenario broken:
    hero: vehicle
    do hero.drvie()
"""


def test_success_exits_0_and_writes_outputs(tmp_path, capsys):
    out = tmp_path / "out"
    assert main([str(EVENTS), "--out", str(out)]) == 0
    summary = capsys.readouterr().out
    assert "success" in summary and "wrote" in summary
    names = sorted(p.name for p in out.iterdir())
    assert names == ["coverage.json", "events.csv", "run.json", "telemetry.csv"]
    meta = json.loads((out / "run.json").read_text())
    assert meta["outcome"]["status"] == "success"
    assert set(meta["versions"]) >= {"mujoco", "numpy", "python", "platform"}
    assert meta["tool"]["name"] == "osc2run" and meta["seed"] == 0
    assert meta["steps"] == 160 and meta["physics_steps"] == 160 * 25
    assert meta["parameter_values"]["source"] == "witness (seed 0)"
    header = (out / "telemetry.csv").read_text().splitlines()[0]
    assert header == (
        "actor,tick,time,x,y,yaw,speed,accel,jerk,throttle,brake,steer,lane,friction,"
        "lateral_error,road,lane_id,s,t,distance,articulation"
    )


@pytest.mark.slow
def test_plots_are_written(tmp_path, capsys):
    out = tmp_path / "out"
    assert main([str(EVENTS), "--out", str(out), "--plot"]) == 0
    pngs = sorted(p.name for p in out.glob("*.png"))
    assert pngs == ["accel_jerk.png", "braking.png", "speed_throttle.png", "world.png"]
    assert (out / "speed_throttle.png").read_bytes()[:4] == b"\x89PNG"


def test_collision_fails_with_1_and_still_writes(tmp_path, capsys):
    source = tmp_path / "crash.osc"
    source.write_text(CRASH)
    out = tmp_path / "out"
    assert main([str(source), "--out", str(out)]) == 1
    assert "collision: a and b" in capsys.readouterr().out
    meta = json.loads((out / "run.json").read_text())
    assert meta["outcome"]["status"] == "failure"
    assert any(e["kind"] == "collision" for e in meta["events"])
    rows = (out / "telemetry.csv").read_text().splitlines()
    assert len(rows) == 1 + 2 * (meta["steps"] + 1)


def test_time_limit_with_bounded_phases_running_fails(capsys):
    assert main([str(EVENTS), "--duration", "1"]) == 1
    assert "timeout" in capsys.readouterr().out


def test_checker_errors_exit_2_in_the_checkers_format(tmp_path, capsys):
    source = tmp_path / "broken.osc"
    source.write_text(BROKEN)
    out = tmp_path / "out"
    assert main([str(source), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "broken.osc:5:13: A301 [error]" in err and "nothing ran" in err
    assert not out.exists()


def test_missing_file_exits_2(capsys):
    assert main(["no/such/file.osc"]) == 2
    assert "no such file" in capsys.readouterr().err


def test_a_bad_run_timeout_is_one_usage_line_that_quotes_it(tmp_path, capsys):
    out = tmp_path / "campaign"
    for text, why in (
        ("abc", "must be a number of seconds"),
        ("-1", "must be positive"),
        ("inf", "must be a finite number of seconds"),
    ):
        assert main([str(EVENTS), "--runs", "2", "--out", str(out), "--run-timeout", text]) == 2
        assert capsys.readouterr().err == f"osc2run: error: --run-timeout {text}: {why}\n"
    assert not out.exists()


def test_interrupted_run_writes_what_it_recorded(tmp_path):
    def interrupt(sim: float, limit: float, wall: float) -> None:
        if sim >= 2.0:
            raise KeyboardInterrupt

    out = tmp_path / "out"
    with pytest.raises(RunInterrupted) as caught:
        run(EVENTS, out=out, progress=interrupt)
    result = caught.value.result
    assert result.outcome.status == "interrupted"
    assert result.telemetry["hero"]["time"][-1] == pytest.approx(2.0)
    meta = json.loads((out / "run.json").read_text())
    assert meta["outcome"]["status"] == "interrupted"
    assert (out / "telemetry.csv").exists()


def test_python_dash_m_runs_the_command(tmp_path):
    env = dict(
        os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])
    )
    proc = subprocess.run(
        [sys.executable, "-m", "osc2runner", str(EVENTS), "--quiet"],
        capture_output=True,
        text=True,
        env=env,
        cwd=ROOT,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("scenario events")
