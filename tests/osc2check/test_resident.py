"""The resident checker (``OSC2_RESIDENT=1``): a check handed to it answers as the command
would itself (output, errors, exit status, interrupts), and without a resident process,
or without a folder of the user's own for its socket, the command checks by itself."""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import pytest

from osc2check import resident

pytestmark = pytest.mark.skipif(
    not (hasattr(socket, "send_fds") and hasattr(os, "fork")), reason="no descriptor passing"
)

ROOT = Path(__file__).resolve().parents[2]
COMMAND = "import sys; sys.argv[0] = 'osc2check'; from osc2check.results import run; run()"
GOOD = (ROOT / "examples" / "cut_in_and_stop.osc").read_text()
BAD = """\
import osc.standard

scenario bad:
    car: vehicle
    do car.drive() with:
        speed(fast_speed)
"""


@pytest.fixture
def place(tmp_path: Path) -> dict[str, str]:
    """The command's environment: its own cache and socket folders (short paths: a
    socket's path has at most about 100 characters)."""
    run = Path(f"/tmp/osc2r-{os.getpid()}-{time.monotonic_ns()}")
    run.mkdir(mode=0o700)
    env = {k: v for k, v in os.environ.items() if not k.startswith("OSC2")}
    env.update(
        OSC2_CACHE_DIR=str(tmp_path / "cache"),
        XDG_RUNTIME_DIR=str(run),
        OSC2_RESIDENT_IDLE="120",
    )
    (tmp_path / "good.osc").write_text(GOOD)
    (tmp_path / "bad.osc").write_text(BAD)
    yield env
    resident.stop(str(run / "osc2check"))
    _end_started(run)
    shutil.rmtree(run, ignore_errors=True)  # its files go as the processes leave


def _end_started(run: Path) -> None:
    """End the resident processes started for ``run`` that hold no lock yet (started by
    a command while another one served): they are found by the socket path they were
    given (Linux's /proc; elsewhere they leave when idle)."""
    for cmdline in Path("/proc").glob("[0-9]*/cmdline"):
        try:
            if str(run).encode() in cmdline.read_bytes():
                os.kill(int(cmdline.parent.name), signal.SIGTERM)
        except (OSError, ValueError):
            pass


def _osc2check(
    args: list[str],
    env: dict[str, str],
    cwd: Path,
    *,
    resident_: bool,
    stdin: str = "",
    served: bool | None = True,
) -> tuple[int, str, str]:
    """Exit status, output and errors of the command; ``resident_``: with
    ``OSC2_RESIDENT=1``, and then ``served`` says whether the resident checker must have
    checked (the command imports no analysis of its own) or must not have."""
    environment = dict(env, OSC2_RESIDENT="1") if resident_ else env
    done = subprocess.run(
        [sys.executable, *(["-X", "importtime"] if resident_ else []), "-c", COMMAND, *args],
        env=environment,
        cwd=cwd,
        input=stdin,
        capture_output=True,
        text=True,
        timeout=300,
    )
    errors = done.stderr
    if resident_:
        lines = errors.splitlines(keepends=True)
        imported = [line for line in lines if line.startswith("import time:")]
        analysed = any(line.endswith(" osc2check.analysis\n") for line in imported)
        assert served is None or analysed is not served, args
        errors = "".join(line for line in lines if not line.startswith("import time:"))
    return done.returncode, done.stdout, errors


def _serving(env: dict[str, str], cwd: Path) -> None:
    """Start the resident process and wait until it answers."""
    subprocess.run(
        [sys.executable, "-c", COMMAND, "good.osc"],
        env=dict(env, OSC2_RESIDENT="1"),
        cwd=cwd,
        capture_output=True,
        timeout=300,
    )
    folder = Path(env["XDG_RUNTIME_DIR"]) / "osc2check"
    assert resident.answering(str(folder), wait=240), "the resident checker did not start"


CASES = [
    (["good.osc"], ""),
    (["bad.osc"], ""),
    (["good.osc", "bad.osc", "--output-format", "json"], ""),
    (["-", "--stdin-filename", "piped.osc"], BAD),
    (["missing.osc"], ""),
    (["--version"], ""),
    (["good.osc", "--no-cache", "--witness"], ""),
]


def test_a_handed_over_check_answers_as_the_command_does(place, tmp_path):
    _serving(place, tmp_path)
    for args, stdin in CASES:
        here = _osc2check(args, place, tmp_path, resident_=False, stdin=stdin)
        handed = _osc2check(args, place, tmp_path, resident_=True, stdin=stdin)
        assert handed == here, args
    assert _osc2check(["bad.osc"], place, tmp_path, resident_=True)[0] == 1


def test_an_edited_file_is_checked_by_the_resident_process(place, tmp_path):
    _serving(place, tmp_path)
    for n in range(2):  # edited: no stored result answers it
        (tmp_path / "good.osc").write_text(GOOD + f"# edit {n}\n")
        os.utime(tmp_path / "good.osc", (time.time() - 60, time.time() - 60))
        status, out, _ = _osc2check(["good.osc"], place, tmp_path, resident_=True)
        assert status == 0 and "All checks passed" in out


def test_commands_at_once_are_answered_each_as_alone(place, tmp_path):
    _serving(place, tmp_path)
    expected = _osc2check(["bad.osc", "good.osc"], place, tmp_path, resident_=False)
    with ThreadPoolExecutor(8) as pool:
        answers = list(
            pool.map(
                lambda _: _osc2check(["bad.osc", "good.osc"], place, tmp_path, resident_=True),
                range(8),
            )
        )
    assert all(answer == expected for answer in answers)


def test_an_interrupt_of_the_command_ends_the_check(place, tmp_path):
    _serving(place, tmp_path)
    for signum, status in ((signal.SIGINT, 130), (signal.SIGTERM, -signal.SIGTERM)):
        started = _check_large(
            place,
            tmp_path,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            # as from a terminal: a shell's background job (a CI script's) ignores SIGINT
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        )
        started.send_signal(signum)
        out, err = started.communicate(timeout=120)
        assert started.returncode == status, err
        assert out == ""
        assert err == ("osc2check: interrupted\n" if signum == signal.SIGINT else "")


def test_without_a_folder_of_its_own_the_command_checks_by_itself(place, tmp_path):
    shared = Path(place["XDG_RUNTIME_DIR"]) / "osc2check"
    shared.mkdir(mode=0o700)
    shared.chmod(0o777)  # others could put a socket there
    here = _osc2check(["bad.osc"], place, tmp_path, resident_=False)
    assert _osc2check(["bad.osc"], place, tmp_path, resident_=True, served=False) == here
    time.sleep(1.0)
    assert not list(shared.iterdir())  # no resident process was started


def test_the_resident_process_leaves_when_idle(place, tmp_path):
    place = dict(place, OSC2_RESIDENT_IDLE="1")
    folder = Path(place["XDG_RUNTIME_DIR"]) / "osc2check"
    # its socket is looked for while the check that starts it runs: on a loaded machine
    # a process idle for a second may have left before a later look
    starting = subprocess.Popen(
        [sys.executable, "-c", COMMAND, "good.osc"],
        env=dict(place, OSC2_RESIDENT="1"),
        cwd=tmp_path,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    deadline = time.monotonic() + 240
    while not list(folder.glob("*.sock")) and time.monotonic() < deadline:
        time.sleep(0.02)
    starting.wait(timeout=300)
    assert time.monotonic() < deadline, "the resident checker did not start"
    deadline = time.monotonic() + 60
    while list(folder.glob("*.sock")) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not list(folder.glob("*.sock"))


def test_another_toolkit_or_module_path_has_another_process(place, monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_RUNTIME_DIR", place["XDG_RUNTIME_DIR"])  # a short path
    first = resident._address(resident._identity())
    monkeypatch.setattr(sys, "path", [*sys.path, str(tmp_path)])
    second = resident._address(resident._identity())
    monkeypatch.setenv("OSC2_NO_CACHE", "1")
    third = resident._address(resident._identity())
    monkeypatch.setenv("OSC2_RESIDENT_IDLE", "5")
    fourth = resident._address(resident._identity())
    assert None not in (first, second, third, fourth)
    assert len({first, second, third, fourth}) == 4
    assert all(a.startswith(place["XDG_RUNTIME_DIR"]) for a in (first, second))


# ---------------------------------------------------------------------- the review's cases

PLUG = """\
import atexit, sys, tempfile, warnings
print("temporary folder:", tempfile.gettempdir())
atexit.register(lambda: sys.stderr.write("plug-in: goodbye\\n"))
"""


def test_a_plug_in_sees_the_command_s_process(place, tmp_path):
    """Its exit handlers run, and it finds the command's temporary folder."""
    _serving(place, tmp_path)
    project = tmp_path / "project"
    project.mkdir()
    (project / "plug.py").write_text(PLUG)
    (project / "osc2check.toml").write_text('plugins = ["plug.py"]\n')
    (project / "good.osc").write_text(GOOD)
    own_temporary = tmp_path / "own-temporary"
    own_temporary.mkdir()
    env = dict(place, TMPDIR=str(own_temporary))
    here = _osc2check(["good.osc"], env, project, resident_=False)
    assert str(own_temporary) in here[1] and "plug-in: goodbye" in here[2]
    assert _osc2check(["good.osc"], env, project, resident_=True) == here


def test_the_warm_up_reads_no_configuration(place, tmp_path):
    """A configuration above the temporary folder names a plug-in: it is never run."""
    shared = tmp_path / "shared"
    (shared / "temporary").mkdir(parents=True)
    marker = tmp_path / "ran"
    (shared / "evil.py").write_text(f"open({str(marker)!r}, 'w').write('ran')\n")
    (shared / "osc2check.toml").write_text(f'plugins = ["{shared / "evil.py"}"]\n')
    env = dict(place, TMPDIR=str(shared / "temporary"))
    _serving(env, tmp_path)
    assert _osc2check(["good.osc"], env, tmp_path, resident_=True)[0] == 0
    assert not marker.exists()


def test_a_closed_stream_is_not_handed_over(place, tmp_path):
    """Nor does it end in an internal error: a closed standard input cannot be read
    (exit 2), a closed output loses the findings but not the exit status."""
    _serving(place, tmp_path)
    for closed, argv, expected in ((0, "-", 2), (1, "bad.osc", 1)):
        for handed in (False, True):
            done = subprocess.run(
                [sys.executable, "-c", COMMAND, argv],
                env=dict(place, OSC2_RESIDENT="1") if handed else place,
                cwd=tmp_path,
                stdout=subprocess.PIPE if closed != 1 else None,
                stderr=subprocess.PIPE,
                text=True,
                preexec_fn=lambda fd=closed: os.close(fd),  # noqa: PLW0108
                timeout=120,
            )
            assert done.returncode == expected, (argv, handed)
            assert "internal error" not in done.stderr and "Traceback" not in done.stderr
            if closed == 0:
                assert "<stdin>: cannot read: standard input is closed" in done.stderr


def test_an_ignored_hangup_is_ignored_by_the_check(place, tmp_path):
    _serving(place, tmp_path)
    started = _check_large(
        place,
        tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        preexec_fn=lambda: signal.signal(signal.SIGHUP, signal.SIG_IGN),
    )
    started.send_signal(signal.SIGHUP)
    out, _ = started.communicate(timeout=300)
    assert started.returncode == 1 and "error" in out  # finished, as without the resident


def test_a_killed_command_ends_its_check(place, tmp_path):
    _serving(place, tmp_path)
    with open(tmp_path / "out.txt", "w") as out:
        started = _check_large(place, tmp_path, stdout=out)
        started.kill()
        started.wait()
    time.sleep(8.0)  # longer than the check would take on a quiet machine
    assert (tmp_path / "out.txt").read_text() == ""


def test_the_lock_keeps_the_resident_process_id(place, tmp_path):
    for _ in range(3):  # commands that come while it warms up
        _osc2check(["good.osc"], place, tmp_path, resident_=True, served=None)
    _serving(place, tmp_path)
    folder = Path(place["XDG_RUNTIME_DIR"]) / "osc2check"
    (lock,) = folder.glob("*.lock")
    pid = int(lock.read_text())
    os.kill(pid, 0)  # the process is there
    bystander = subprocess.Popen(["sleep", "60"])
    try:  # a lock nobody holds, naming a live process: stop must not take its id
        (folder / "left-over.lock").write_text(f"{bystander.pid}\n")
        assert resident.stop(str(folder)) == 1  # the resident process, not the bystander
        time.sleep(1.0)
        assert bystander.poll() is None
    finally:
        bystander.kill()
        bystander.wait()


def test_a_long_socket_path_or_a_bad_idle_time_still_checks(place, tmp_path):
    long_run = Path(place["XDG_RUNTIME_DIR"]) / ("x" * 90)
    long_run.mkdir(mode=0o700)
    env = dict(place, XDG_RUNTIME_DIR=str(long_run))
    here = _osc2check(["bad.osc"], place, tmp_path, resident_=False)
    assert _osc2check(["bad.osc"], env, tmp_path, resident_=True, served=False) == here
    assert not (long_run / "osc2check").exists() or not list((long_run / "osc2check").iterdir())
    for idle in ("0", "-5", "soon"):
        _serving(dict(place, OSC2_RESIDENT_IDLE=idle), tmp_path)  # it serves all the same


def test_process_settings_have_a_process_of_their_own(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_RUNTIME_DIR", str(tmp_path))
    first = resident._identity()
    monkeypatch.setenv("PYTHONWARNINGS", "ignore")
    second = resident._identity()
    mask = os.umask(0o077)
    try:
        third = resident._identity()
    finally:
        os.umask(mask)
    assert first != second != third != first


def _check_large(env: dict[str, str], cwd: Path, **streams: Any) -> subprocess.Popen[str]:
    """Start the check of a 10,000-line file handed to the resident process, and give it
    a second to be under way once the resident process has its child for it (by then the
    command is past its imports: a signal earlier would stop the interpreter starting)."""
    (cwd / "big.osc").write_text(_large())
    servers = _resident_ids(Path(env["XDG_RUNTIME_DIR"]) / "osc2check")
    before = _children(servers)
    started = subprocess.Popen(
        [sys.executable, "-c", COMMAND, "big.osc", "--no-cache"],
        env=dict(env, OSC2_RESIDENT="1"),
        cwd=cwd,
        text=True,
        **streams,
    )
    deadline = time.monotonic() + (120 if Path("/proc/self/stat").is_file() else 0)
    while not (_children(servers) - before) and time.monotonic() < deadline:
        time.sleep(0.02)
    time.sleep(1.0)
    return started


def _resident_ids(folder: Path) -> set[int]:
    """The process ids the resident processes' locks in ``folder`` hold."""
    found = set()
    for lock in folder.glob("*.lock"):
        text = lock.read_text().strip()
        if text.isdigit():
            found.add(int(text))
    return found


def _children(parents: set[int]) -> set[int]:
    """The processes whose parent is one of ``parents`` (from ``/proc``)."""
    found = set()
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except (OSError, IndexError):
            continue
        if int(fields[1]) in parents:
            found.add(int(stat.parent.name))
    return found


def _large() -> str:
    sys.path.insert(0, str(ROOT / "bench"))
    try:
        from generate import generate
    finally:
        sys.path.remove(str(ROOT / "bench"))
    # 20,000 lines: the check must still run a second after it began, when the signal
    # tests send theirs (10,000 lines could be done by then on a fast machine)
    return generate(20000)
