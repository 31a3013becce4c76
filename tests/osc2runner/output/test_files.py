"""Output files written whole or not at all (``osc2runner.output.files``), and a run's files."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from osc2runner import run
from osc2runner.output import files
from osc2runner.output.files import FolderError, atomic_open, output_folder, write_atomically

EVENTS = Path(__file__).parents[1] / "trees" / "events.osc"


def _leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.endswith(".tmp"))


def test_write_atomically_writes_text_and_bytes(tmp_path):
    text = tmp_path / "a.json"
    assert write_atomically(text, '{"a": 1}\r\n') == text
    assert text.read_bytes() == b'{"a": 1}\r\n'  # newlines as given
    data = tmp_path / "b.png"
    write_atomically(data, b"\x89PNG\x00")
    assert data.read_bytes() == b"\x89PNG\x00"
    assert _leftovers(tmp_path) == []


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    path = tmp_path / "telemetry.csv"
    path.write_text("old\n")
    with pytest.raises(RuntimeError), atomic_open(path, "w") as f:
        f.write("half of the new")
        assert path.read_text() == "old\n"  # nothing replaced while writing
        raise RuntimeError("disk full")
    assert path.read_text() == "old\n"
    assert _leftovers(tmp_path) == []


def test_an_interrupted_write_of_a_new_file_leaves_no_file(tmp_path):
    path = tmp_path / "run.json"
    with pytest.raises(KeyboardInterrupt), atomic_open(path) as f:
        f.write("{")
        raise KeyboardInterrupt
    assert not path.exists() and _leftovers(tmp_path) == []


def test_the_file_is_synced_before_it_is_renamed(tmp_path, monkeypatch):
    calls: list[str] = []
    real_fsync, real_replace = os.fsync, os.replace
    monkeypatch.setattr(files.os, "fsync", lambda fd: (calls.append("fsync"), real_fsync(fd)))
    monkeypatch.setattr(
        files.os, "replace", lambda a, b: (calls.append("replace"), real_replace(a, b))
    )
    write_atomically(tmp_path / "x.csv", "1\n")
    assert calls[:2] == ["fsync", "replace"]


def test_new_files_get_the_usual_permissions(tmp_path):
    old = os.umask(0o022)
    try:
        path = write_atomically(tmp_path / "x.csv", "1\n")
    finally:
        os.umask(old)
    if os.name == "posix":
        assert path.stat().st_mode & 0o777 == 0o644


def test_atomic_open_only_writes(tmp_path):
    with pytest.raises(ValueError), atomic_open(tmp_path / "x", "a"):  # type: ignore[arg-type]
        pass


def test_output_folder_creates_a_missing_folder_or_only_checks_it(tmp_path):
    deep = tmp_path / "a" / "b"
    assert output_folder(deep, create=False) == deep and not (tmp_path / "a").exists()
    assert output_folder(deep) == deep and deep.is_dir()
    assert output_folder(deep) == deep  # an existing folder
    assert _leftovers(deep) == []


@pytest.mark.parametrize("create", [True, False])
def test_output_folder_refuses_a_file_and_a_path_under_a_file(tmp_path, create):
    plain = tmp_path / "plain.txt"
    plain.write_text("x")
    with pytest.raises(FolderError, match="is a file, not a folder"):
        output_folder(plain, create=create)
    with pytest.raises(FolderError, match=r"cannot create the folder: .*plain.txt is not a folder"):
        output_folder(plain / "sub" / "dir", create=create)


def test_a_run_writes_run_json_last_and_leaves_no_temporary_files(tmp_path, monkeypatch):
    order: list[str] = []
    real_replace = os.replace

    def replace(src, dst):
        order.append(Path(dst).name)
        real_replace(src, dst)

    monkeypatch.setattr(files.os, "replace", replace)
    out = tmp_path / "new" / "out"
    result = run(EVENTS, out=out, plot=True)
    assert order[-1] == "run.json"
    assert set(order) == {p.name for p in result.outputs} == {p.name for p in out.iterdir()}
    assert order[:2] == ["telemetry.csv", "events.csv"]
    assert json.loads((out / "run.json").read_text())["outcome"]["status"] == "success"


def test_an_out_folder_that_became_unusable_during_the_run_is_an_option_error(tmp_path):
    """``--out`` is checked before the run and created when the files are written: a path
    that turned into a file meanwhile is the option's error (one line for the command),
    not an internal error."""
    from osc2runner.options import OptionError
    from osc2runner.runner import execute, prepare

    out = tmp_path / "later" / "out"
    prepared = prepare(EVENTS)

    def block(sim: float, limit: float, wall: float) -> None:
        if not (tmp_path / "later").exists():
            (tmp_path / "later").write_text("a file now\n")

    with pytest.raises(OptionError) as caught:
        execute(prepared, out=out, duration=2.0, progress=block)
    assert caught.value.name == "out"
    assert caught.value.why.startswith("cannot create the folder")
