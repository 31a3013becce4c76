"""Stored results of whole checks: given again only while nothing the check read changed."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from osc2check import cli, results

ROOT = Path(__file__).resolve().parents[2]
AN_HOUR_AGO = time.time() - 3600

MAIN = """\
import osc.standard
import "lib.osc"

scenario tiny:
    car1: vehicle
    do serial:
        car1.drive() with:
            speed(slow_speed)
"""
LIB = """\
import osc.standard

global slow_speed: speed = 30kph
"""


def _write(path: Path, text: str, *, when: float = AN_HOUR_AGO) -> Path:
    path.write_text(text)
    os.utime(path, (when, when))
    return path


@pytest.fixture
def project(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("OSC2_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("OSC2_NO_CACHE", raising=False)
    folder = tmp_path / "project"
    folder.mkdir()
    _write(folder / "main.osc", MAIN)
    _write(folder / "lib.osc", LIB)
    monkeypatch.chdir(folder)
    return folder


# Each step runs in a process of its own, as the command does: a test worker's process
# holds other tests' modules (some written a moment ago in their folders) and threads,
# which a stored result would rightly depend on.
STEP = """\
import json, sys
from osc2check import cli, results
step, *argv = sys.argv[1:]
if step == "replay":
    print(json.dumps(results._replay(argv)))
    sys.exit(0)
def timed_out(argv):
    results.not_repeatable("the solver stopped: timeout")
    return cli.main(argv)
sys.exit(results._record(argv, timed_out if step == "record-timed-out" else cli.main))
"""


def _step(step: str, argv: list[str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-c", STEP, step, *argv],
        capture_output=True,
        text=True,
        timeout=300,
    )


def _record(argv: list[str], step: str = "record") -> tuple[str, int]:
    """The check of ``argv`` run (and its result stored when it can be): output, status."""
    done = _step(step, argv)
    assert "Traceback" not in done.stderr, done.stderr
    return done.stdout, done.returncode


def _replay(argv: list[str]) -> tuple[str, int] | None:
    """The stored output and status of ``argv`` if they would be given again."""
    done = _step("replay", argv)
    assert done.returncode == 0, done.stderr
    found = json.loads(done.stdout)
    return None if found is None else (found[0], found[1])


def test_a_repeated_check_gives_the_stored_output_and_status(project: Path) -> None:
    output, status = _record(["main.osc"])
    assert "main.osc" in output
    assert _replay(["main.osc"]) == (output, status)
    assert _replay(["main.osc", "--strict"]) is None  # another command line


@pytest.mark.parametrize(
    "change",
    [
        pytest.param(lambda p: _write(p / "main.osc", MAIN + "\n# edited\n"), id="the file"),
        pytest.param(lambda p: _write(p / "lib.osc", LIB.replace("30", "40")), id="an import"),
        pytest.param(
            lambda p: _write(p / "osc2check.toml", 'ignore = ["L506"]\n'), id="a new config"
        ),
        pytest.param(lambda p: os.utime(p / "lib.osc"), id="a touched import"),
    ],
)
def test_a_change_to_what_the_check_read_is_checked_again(project: Path, change: object) -> None:
    _record(["main.osc"])
    assert _replay(["main.osc"]) is not None
    change(project)  # type: ignore[operator]
    assert _replay(["main.osc"]) is None


def test_a_file_added_to_a_checked_folder_is_checked_again(project: Path) -> None:
    os.utime(project, (AN_HOUR_AGO, AN_HOUR_AGO))
    _record(["."])
    assert _replay(["."]) is not None
    _write(project / "other.osc", "import osc.standard\n")
    assert _replay(["."]) is None


def test_an_import_found_later_in_the_search_is_checked_again(project: Path) -> None:
    """``import a.b`` looks beside the file first: a file made there changes the result."""
    library = project / "shared"
    (library / "a").mkdir(parents=True)
    _write(library / "a" / "b.osc", LIB)
    _write(project / "osc2check.toml", f'search-paths = ["{library}"]\n')
    _write(project / "main.osc", MAIN.replace('import "lib.osc"', "import a.b"))
    _record(["main.osc"])
    assert _replay(["main.osc"]) is not None
    (project / "a").mkdir()
    _write(project / "a" / "b.osc", LIB.replace("30", "20"))
    assert _replay(["main.osc"]) is None


def test_a_result_that_depends_on_the_machine_is_not_stored(project: Path) -> None:
    _record(["main.osc"], "record-timed-out")
    assert _replay(["main.osc"]) is None


def test_a_file_edited_during_the_check_is_not_trusted(project: Path) -> None:
    _write(project / "main.osc", MAIN, when=time.time())
    _record(["main.osc"])
    assert _replay(["main.osc"]) is None


@pytest.mark.parametrize(
    "argv",
    [["-"], ["--no-cache", "main.osc"], ["--no-c", "main.osc"], ["rule", "N101"], ["--version"]],
)
def test_some_command_lines_are_never_stored(argv: list[str]) -> None:
    assert not results._storable(argv)


def test_errors_and_notes_on_standard_error_are_not_stored(project: Path) -> None:
    assert _record(["main.osc", "missing.osc"])[1] == cli.EXIT_ERROR
    assert _replay(["main.osc", "missing.osc"]) is None


# --- the command, whole processes ------------------------------------------------------------

PROBE = (
    "import atexit, sys\n"
    "from osc2check.results import run\n"
    "checked = lambda: 'checked\\n' if 'osc2check.analysis' in sys.modules else ''\n"
    "atexit.register(lambda: sys.stderr.write(checked()))\n"
    "sys.argv[0] = 'osc2check'\n"
    "run()\n"
)


def _command(folder: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-c", PROBE, *args],
        cwd=folder,
        env={**os.environ, "OSC2_CACHE_DIR": os.environ["OSC2_CACHE_DIR"]},
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_the_command_answers_a_repeated_check_without_checking(project: Path) -> None:
    first = _command(project, "main.osc", "--output-format", "concise")
    assert "Traceback" not in first.stderr
    assert "checked" in first.stderr
    again = _command(project, "main.osc", "--output-format", "concise")
    assert "checked" not in again.stderr  # the parser was never imported
    assert (again.stdout, again.returncode) == (first.stdout, first.returncode)


def test_a_corrupt_or_concurrent_result_never_changes_the_output(project: Path) -> None:
    args = ("main.osc", "--output-format", "concise")
    first = _command(project, *args)
    entries = list(Path(os.environ["OSC2_CACHE_DIR"]).glob("result-*.bin"))
    assert entries
    for entry in entries:
        entry.write_bytes(b"OSC2CACHE\n" + os.urandom(200))
    damaged = _command(project, *args)
    assert "checked" in damaged.stderr
    with ThreadPoolExecutor(8) as pool:
        runs = list(pool.map(lambda _: _command(project, *args), range(8)))
    for run in [damaged, *runs]:
        assert (run.stdout, run.returncode) == (first.stdout, first.returncode)
        assert "Traceback" not in run.stderr
