"""Bad options and a bad ``--out``: one line, exit status 2, before the checker runs."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from osc2runner import run
from osc2runner import runner as runner_module
from osc2runner.cli import main
from osc2runner.options import OptionError

HERE = Path(__file__).parent
ROOT = HERE.parents[1]
EVENTS = HERE / "trees" / "events.osc"


@pytest.fixture
def nothing_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    """Fail the test if the checker or the preparation of a run is reached."""

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("the checker ran although an option was bad")

    monkeypatch.setattr(runner_module, "analyze", refuse)
    monkeypatch.setattr(runner_module, "prepare", refuse)


def _writable(folder: Path) -> bool:
    probe = folder / "probe"
    try:
        probe.write_text("x")
    except OSError:
        return False
    probe.unlink()
    return True


@pytest.fixture
def read_only_folder(tmp_path: Path) -> Iterator[Path]:
    """A folder no file can be created in (permission bits; for root, the immutable flag)."""
    folder = tmp_path / "read-only"
    folder.mkdir()
    folder.chmod(0o555)
    immutable = False
    if _writable(folder) and shutil.which("chattr"):  # root ignores permission bits
        done = subprocess.run(["chattr", "+i", str(folder)], capture_output=True, check=False)
        immutable = done.returncode == 0
    try:
        if _writable(folder):
            pytest.skip("cannot make a read-only folder here (root without chattr +i)")
        yield folder
    finally:
        if immutable:
            subprocess.run(["chattr", "-i", str(folder)], check=False)
        folder.chmod(0o755)


def _one_error_line(err: str) -> str:
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("osc2run: error: "), err
    return lines[0]


@pytest.mark.parametrize(
    ("options", "expected"),
    [
        (["--seed", "-1"], "--seed -1: must be a non-negative integer"),
        (["--seed", "2.5"], "--seed 2.5: must be a non-negative integer"),
        (["--dt-physics", "0"], "--dt-physics 0: must be positive"),
        (["--dt-control", "0"], "--dt-control 0: must be positive"),
        (["--dt-physics", "nan"], "--dt-physics nan: must be a finite number"),
        (["--dt-control", "fast"], "--dt-control fast: must be a number of seconds"),
        (["--dt-physics", "2e-3x"], "--dt-physics 2e-3x: must be a number of seconds"),
        (
            ["--dt-control", "0.033", "--dt-physics", "0.002"],
            "--dt-control 0.033: must be a whole multiple of the physics step 0.002 s",
        ),
        (["--dt-physics", "0.1"], "--dt-control 0.05: must be a whole multiple"),
        (["--dt-physics", "1e-12"], "--dt-physics 1e-12: is too small"),
        (["--duration", "-5"], "--duration -5: must be positive"),
        (["--duration", "inf"], "--duration inf: must be a finite number"),
        (["--duration", "soon"], "--duration soon: must be a number of seconds"),
        (["--plot"], "--plot needs --out DIR"),
        (["--no-such-option"], "unrecognized arguments: --no-such-option"),
    ],
)
def test_bad_options_are_one_line_usage_errors(options, expected, capsys, nothing_runs):
    assert main([str(EVENTS), *options]) == 2
    captured = capsys.readouterr()
    assert expected in _one_error_line(captured.err)
    assert captured.out == ""


def test_out_naming_a_file(tmp_path, capsys, nothing_runs):
    plain = tmp_path / "plain.txt"
    plain.write_text("not a folder")
    assert main([str(EVENTS), "--out", str(plain)]) == 2
    line = _one_error_line(capsys.readouterr().err)
    assert line == f"osc2run: error: --out {plain}: is a file, not a folder"
    assert plain.read_text() == "not a folder"


def test_out_under_a_file(tmp_path, capsys, nothing_runs):
    plain = tmp_path / "plain.txt"
    plain.write_text("x")
    out = plain / "run" / "out"
    assert main([str(EVENTS), "--out", str(out)]) == 2
    line = _one_error_line(capsys.readouterr().err)
    assert line == f"osc2run: error: --out {out}: cannot create the folder: {plain} is not a folder"


def test_out_in_a_read_only_folder(read_only_folder, capsys, nothing_runs):
    assert main([str(EVENTS), "--out", str(read_only_folder)]) == 2
    line = _one_error_line(capsys.readouterr().err)
    assert line.startswith(f"osc2run: error: --out {read_only_folder}: the folder is not writable")
    assert list(read_only_folder.iterdir()) == []


def test_out_to_be_created_in_a_read_only_folder(read_only_folder, capsys, nothing_runs):
    out = read_only_folder / "new"
    assert main([str(EVENTS), "--out", str(out)]) == 2
    line = _one_error_line(capsys.readouterr().err)
    assert f"--out {out}: cannot create the folder: {read_only_folder} is not writable" in line


def test_the_command_line_itself_prints_one_line(tmp_path):
    plain = tmp_path / "plain.txt"
    plain.write_text("x")
    env = dict(
        os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])
    )
    for options in (["--seed", "-1"], ["--out", str(plain)]):
        proc = subprocess.run(
            [sys.executable, "-m", "osc2runner", str(EVENTS), *options],
            capture_output=True,
            text=True,
            env=env,
            cwd=ROOT,
            check=False,
        )
        assert proc.returncode == 2
        assert proc.stdout == ""
        assert "internal error" not in proc.stderr
        _one_error_line(proc.stderr)


def test_a_missing_out_folder_is_created_only_when_the_run_writes(tmp_path, capsys):
    out = tmp_path / "a" / "b"
    assert main([str(EVENTS), "--out", str(out), "--duration", "1", "-q"]) == 1  # timeout
    assert sorted(p.name for p in out.iterdir()) == [
        "coverage.json",
        "events.csv",
        "run.json",
        "telemetry.csv",
    ]


def test_good_steps_are_accepted(capsys):
    assert main([str(EVENTS), "--dt-control", "0.1", "--dt-physics", "0.005", "--duration", "1"])
    assert "simulated 1.00 s in 10 ticks" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"seed": -1}, "seed"),
        ({"seed": 1.0}, "seed"),
        ({"dt_physics": 0.0}, "dt_physics"),
        ({"dt_control": 0.033}, "dt_control"),
        ({"duration": -5.0}, "duration"),
        ({"duration": float("nan")}, "duration"),
    ],
)
def test_the_python_api_checks_options_before_running(kwargs, name, nothing_runs):
    with pytest.raises(OptionError) as caught:
        run(EVENTS, **kwargs)
    assert caught.value.name == name
    assert isinstance(caught.value, ValueError)


def test_the_python_api_checks_out_before_running(tmp_path, nothing_runs):
    plain = tmp_path / "plain.txt"
    plain.write_text("x")
    with pytest.raises(OptionError, match="is a file, not a folder") as caught:
        run(EVENTS, out=plain)
    assert caught.value.name == "out"
    with pytest.raises(OptionError, match="cannot create the folder"):
        run(EVENTS, out=plain / "sub")
