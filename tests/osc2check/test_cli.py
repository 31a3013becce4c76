"""The command line: arguments, files, output formats and exit codes.

``osc2check.analysis`` (the lead's module) is replaced by a fake: it reports
N101 for every ``hreo`` and D805 for every ``100.0`` and applies the config's
policy, as the real ``analyze`` does. Swap in the real module once it exists.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import socket
import subprocess
import sys
import threading
import types
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from osc2check import cli, codes, inputs, messages, rules
from osc2check.analysis import AnalysisOptions
from osc2check.diagnostics import Diagnostic
from osc2check.source import Span

CLEAN = "scenario cruise:\n    hero: vehicle\n"
BROKEN = "scenario follow:\n    hero: vehicle\n    do hreo.drive()\n"
DIALECT = "scenario wet:\n    env: environment\n    do env.rain(intensity: 100.0)\n"


@dataclass(frozen=True)
class FakeSource:
    uri: str
    text: str
    problem: str | None = None
    on_disk: bool = False


@dataclass
class FakeAnalysis:
    diagnostics: list[Diagnostic]
    texts: dict[str, str] = field(default_factory=dict)
    verified: dict = field(default_factory=dict)
    unverified: set = field(default_factory=set)


def fake_analyze(sources, options):
    found = []
    for s in sources:
        if s.problem:  # as the real analysis does: P004 at the first replaced character
            column = s.text.find("\ufffd") + 1
            span = Span(s.uri, 1, column, 1, column + 1)
            found.append(messages.invalid_encoding(span, s.problem))
        for line_no, line in enumerate(s.text.splitlines(), start=1):
            for needle, code, message in (
                ("hreo", codes.UNDEFINED_NAME, "undefined name `hreo`"),
                ("100.0", codes.UNITLESS_PHYSICAL_LITERAL, "`100.0` has no unit"),
            ):
                column = line.find(needle) + 1
                if column:
                    span = Span(s.uri, line_no, column, line_no, column + len(needle))
                    found.append(Diagnostic(code, message, span, code.severity))
    return FakeAnalysis(options.policy(found, None), {s.uri: s.text for s in sources})


@pytest.fixture
def analysis(monkeypatch):
    """Install the fake ``osc2check.analysis``; its ``calls`` record each analysis."""
    module = types.ModuleType("osc2check.analysis")
    module.SourceInput = FakeSource
    module.AnalysisOptions = AnalysisOptions
    module.calls = []

    def analyze(sources, options):
        module.calls.append((list(sources), options))
        return fake_analyze(sources, options)

    module.analyze = analyze
    monkeypatch.setitem(sys.modules, "osc2check.analysis", module)
    return module


@pytest.fixture
def project(tmp_path, monkeypatch, analysis):
    """An empty project folder as the working directory (no configuration above it)."""
    monkeypatch.chdir(tmp_path)
    return tmp_path


def write(path: Path, text: str | bytes) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text, encoding="utf-8")
    return path


def run(capsys, *argv: str) -> tuple[int, str, str]:
    status = cli.main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


# --- exit codes and the default format ------------------------------------------


def test_clean_file_exits_0(project, capsys):
    write(project / "a.osc", CLEAN)
    assert run(capsys, "a.osc") == (0, "All checks passed (1 file)\n", "")


def test_files_are_checked_as_saved_and_standard_input_is_not(
    project, capsys, monkeypatch, analysis
):
    """A file's text is the file as saved (a large one's parse may be kept); stdin's not."""
    write(project / "a.osc", CLEAN)
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(CLEAN.encode())))
    assert run(capsys, "a.osc")[0] == 0 and run(capsys, "-")[0] == 0
    (first, _), (second, _) = analysis.calls
    assert [s.on_disk for s in first] == [True] and [s.on_disk for s in second] == [False]


def test_error_exits_1_with_full_output(project, capsys):
    write(project / "a.osc", BROKEN)
    status, out, err = run(capsys, "a.osc")
    assert status == 1
    assert err == ""
    assert out == (
        "a.osc:3:8: N101 [error] undefined name `hreo`\n"
        "  |\n"
        "3 |     do hreo.drive()\n"
        "  |        ^^^^\n"
        "\n"
        "Found 1 error in 1 file (1 file checked)\n"
    )


def test_warning_alone_exits_0_unless_fail_on_warning_or_strict(project, capsys):
    write(project / "w.osc", DIALECT)
    status, out, _ = run(capsys, "w.osc")
    assert status == 0 and "D805 [warning]" in out
    assert run(capsys, "w.osc", "--fail-on", "warning")[0] == 1
    status, out, _ = run(capsys, "w.osc", "--strict")
    assert status == 1 and "D805 [error]" in out


def test_exit_zero_keeps_0_with_errors(project, capsys):
    write(project / "a.osc", BROKEN)
    assert run(capsys, "a.osc", "--exit-zero")[0] == 0


def test_select_and_ignore(project, capsys):
    write(project / "a.osc", BROKEN + "    do env.rain(intensity: 100.0)\n")
    _, out, _ = run(capsys, "a.osc", "--select", "D", "--output-format", "concise")
    assert out.splitlines()[0] == "a.osc:4:28: D805 `100.0` has no unit"
    assert "N101" not in out
    status, out, _ = run(capsys, "a.osc", "--ignore", "undefined-name,D8", "-q")
    assert (status, out) == (0, "")


def test_quiet_leaves_out_the_summary(project, capsys):
    write(project / "a.osc", CLEAN)
    assert run(capsys, "a.osc", "--quiet") == (0, "", "")


def test_statistics(project, capsys):
    write(project / "a.osc", BROKEN)
    write(project / "b.osc", BROKEN)
    status, out, _ = run(capsys, ".", "--statistics")
    assert status == 1
    assert out == "2  N101  undefined-name\nFound 2 errors in 2 files (2 files checked)\n"


# --- output formats through main() -------------------------------------------------


def test_concise_format(project, capsys):
    write(project / "a.osc", BROKEN)
    assert run(capsys, "a.osc", "--output-format", "concise") == (
        1,
        "a.osc:3:8: N101 undefined name `hreo`\nFound 1 error in 1 file (1 file checked)\n",
        "",
    )


def test_github_format(project, capsys):
    write(project / "w.osc", DIALECT)
    assert run(capsys, "w.osc", "--output-format", "github") == (
        0,
        "::warning file=w.osc,line=3,col=28,endLine=3,endColumn=33,title=D805::"
        "`100.0` has no unit\n",
        "",
    )


def test_json_format_is_only_json(project, capsys):
    write(project / "a.osc", BROKEN)
    status, out, _ = run(capsys, "a.osc", "--output-format", "json")
    assert status == 1
    doc = json.loads(out)
    assert [(f["code"], f["location"]["path"]) for f in doc["findings"]] == [("N101", "a.osc")]
    assert doc["findings"][0]["url"] == rules.doc_url(codes.UNDEFINED_NAME)


def test_sarif_format_is_only_sarif(project, capsys):
    write(project / "a.osc", CLEAN)
    status, out, _ = run(capsys, "a.osc", "--output-format", "sarif")
    assert status == 0
    log = json.loads(out)
    assert log["version"] == "2.1.0" and log["runs"][0]["results"] == []


def test_output_format_from_configuration(project, capsys):
    write(project / "osc2check.toml", 'output-format = "concise"\n')
    write(project / "a.osc", BROKEN)
    assert run(capsys, "a.osc")[1].startswith("a.osc:3:8: N101 undefined")


# --- files, folders and standard input ---------------------------------------------


def test_folders_are_searched_recursively_honouring_exclude(project, capsys, analysis):
    write(project / "osc2check.toml", 'exclude = ["legacy"]\n')
    write(project / "b" / "z.osc", CLEAN)
    write(project / "b" / "a.osc", CLEAN)
    write(project / "a.osc", CLEAN)
    write(project / "legacy" / "old.osc", BROKEN)
    write(project / ".git" / "x.osc", BROKEN)
    write(project / "build" / "y.osc", BROKEN)
    write(project / "notes.txt", BROKEN)
    assert run(capsys, ".") == (0, "All checks passed (3 files)\n", "")
    ((sources, _),) = analysis.calls
    assert [s.uri for s in sources] == ["a.osc", "b/a.osc", "b/z.osc"]


def test_a_folder_named_explicitly_is_searched_even_if_excluded(project, capsys):
    write(project / "build" / "y.osc", BROKEN)
    assert run(capsys, "build")[0] == 1


def test_force_exclude_applies_to_named_files(project, capsys):
    write(project / "osc2check.toml", 'exclude = ["legacy"]\nforce-exclude = true\n')
    write(project / "legacy" / "old.osc", BROKEN)
    write(project / "a.osc", CLEAN)
    assert run(capsys, "legacy/old.osc", "a.osc") == (0, "All checks passed (1 file)\n", "")


def test_the_same_file_twice_is_checked_once(project, capsys, analysis):
    write(project / "a.osc", CLEAN)
    run(capsys, "a.osc", "./a.osc", ".")
    assert len(analysis.calls[0][0]) == 1


def test_stdin_with_a_file_name(project, capsys, monkeypatch, analysis):
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(BROKEN.encode())))
    status, out, _ = run(
        capsys, "-", "--stdin-filename", "dir/cut_in.osc", "--output-format", "concise"
    )
    assert status == 1
    assert out.startswith("dir/cut_in.osc:3:8: N101")


def test_stdin_without_a_name(project, capsys, monkeypatch):
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(CLEAN.encode())))
    assert run(capsys, "-") == (0, "All checks passed (1 file)\n", "")


def test_invalid_utf8_is_reported_as_p004(project, capsys):
    write(project / "a.osc", b"# Sc\xe9nario\n" + CLEAN.encode())
    status, out, _ = run(capsys, "a.osc", "--output-format", "concise")
    assert status == 1
    assert out.splitlines()[0].startswith("a.osc:1:5: P004 the file is not valid UTF-8")
    assert run(capsys, "a.osc", "--ignore", "P004")[0] == 0


# --- usage, configuration and I/O errors: exit 2 -------------------------------------


def test_missing_path_exits_2_naming_it(project, capsys):
    assert run(capsys, "nope.osc") == (
        2,
        "No findings in 0 files; 1 file could not be read\n",
        "osc2check: error: nope.osc: cannot read: no such file or directory\n",
    )


def test_no_osc_files_exits_2(project, capsys):
    write(project / "notes.txt", CLEAN)
    assert run(capsys, ".") == (2, "", "osc2check: error: no .osc files found in .\n")


# --- paths that cannot be read: reported each, the rest checked, exit 2 ------------------

CANNOT_READ_FIFO = "cannot read: not a regular file (a named pipe)"


@contextlib.contextmanager
def writer_waiting_on(fifo: Path):
    """A thread that opens ``fifo`` for writing and closes it at once.

    A checker that opened the FIFO would get an empty file instead of hanging, and the
    test fails on what it reports; at the end the thread is released if nothing opened
    the FIFO.
    """
    thread = threading.Thread(target=lambda: open(fifo, "wb").close(), daemon=True)
    thread.start()
    try:
        yield
    finally:
        fd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)  # lets a waiting writer go
        thread.join()
        os.close(fd)


def broken_and_good(project: Path) -> None:
    write(project / "good.osc", BROKEN)
    (project / "dangling.osc").symlink_to("gone.osc")
    (project / "loop.osc").symlink_to("loop.osc")


def test_broken_and_looping_links_are_reported_and_the_rest_checked(project, capsys):
    broken_and_good(project)
    status, out, err = run(
        capsys, "dangling.osc", "loop.osc", "good.osc", "--output-format", "concise"
    )
    assert status == 2
    assert out == (
        "good.osc:3:8: N101 undefined name `hreo`\n"
        "Found 1 error in 1 file (1 file checked); 2 files could not be read\n"
    )
    assert err == (
        "osc2check: error: dangling.osc: cannot read: broken symbolic link to `gone.osc`\n"
        "osc2check: error: loop.osc: cannot read: symbolic link loop\n"
    )


def test_unreadable_paths_go_into_json_errors(project, capsys):
    broken_and_good(project)
    status, out, err = run(capsys, ".", "--output-format", "json")
    assert status == 2
    doc = json.loads(out)
    assert [f["location"]["path"] for f in doc["findings"]] == ["good.osc"]
    assert doc["errors"] == [
        {"path": "dangling.osc", "message": "cannot read: broken symbolic link to `gone.osc`"},
        {"path": "loop.osc", "message": "cannot read: symbolic link loop"},
    ]
    assert doc["skipped"] == []
    assert err.count("osc2check: error: ") == 2


def test_unreadable_paths_go_into_sarif_invocation(project, capsys):
    broken_and_good(project)
    status, out, _ = run(capsys, "loop.osc", "good.osc", "--output-format", "sarif")
    assert status == 2
    (sarif_run,) = json.loads(out)["runs"]
    assert [r["ruleId"] for r in sarif_run["results"]] == ["N101"]
    (invocation,) = sarif_run["invocations"]
    assert invocation["executionSuccessful"] is False
    assert invocation["toolExecutionNotifications"] == [
        {
            "level": "error",
            "message": {"text": "cannot read: symbolic link loop"},
            "locations": [{"physicalLocation": {"artifactLocation": {"uri": "loop.osc"}}}],
        }
    ]


def test_unreadable_paths_are_github_errors(project, capsys):
    broken_and_good(project)
    status, out, _ = run(capsys, "loop.osc", "good.osc", "--output-format", "github")
    assert status == 2
    assert out.splitlines() == [
        "::error file=loop.osc,title=osc2check::cannot read: symbolic link loop",
        "::error file=good.osc,line=3,col=8,endLine=3,endColumn=12,title=N101::"
        "undefined name `hreo`",
    ]


def test_exit_zero_does_not_hide_a_file_that_cannot_be_read(project, capsys):
    broken_and_good(project)
    assert run(capsys, "loop.osc", "good.osc", "--exit-zero")[0] == 2
    assert run(capsys, "good.osc", "--exit-zero")[0] == 0


def test_fifo_named_is_refused_without_blocking(project, capsys):
    fifo = project / "pipe.osc"
    os.mkfifo(fifo)
    write(project / "a.osc", CLEAN)
    with writer_waiting_on(fifo):
        status, out, err = run(capsys, "pipe.osc", "a.osc")
    assert status == 2
    assert out == "No findings in 1 file; 1 file could not be read\n"
    assert err == f"osc2check: error: pipe.osc: {CANNOT_READ_FIFO}\n"


def test_link_to_a_device_is_refused(project, capsys):
    (project / "zero.osc").symlink_to("/dev/zero")
    status, out, err = run(capsys, "zero.osc", "--output-format", "json")
    assert status == 2
    assert json.loads(out)["errors"] == [
        {"path": "zero.osc", "message": "cannot read: not a regular file (a character device)"}
    ]
    assert "zero.osc: cannot read: not a regular file (a character device)" in err


def test_socket_is_refused(project, capsys):
    sock = socket.socket(socket.AF_UNIX)
    try:
        sock.bind("s.osc")
        status, _, err = run(capsys, "s.osc")
    finally:
        sock.close()
    assert status == 2
    assert err == "osc2check: error: s.osc: cannot read: not a regular file (a socket)\n"


def test_special_files_in_a_folder_are_skipped_with_a_note(project, capsys):
    write(project / "d" / "a.osc", BROKEN)
    os.mkfifo(project / "d" / "pipe.osc")
    (project / "d" / "zero.osc").symlink_to("/dev/zero")
    with writer_waiting_on(project / "d" / "pipe.osc"):
        status, out, err = run(capsys, "d", "--output-format", "json")
    assert status == 1  # the findings decide: a skipped special file is no error
    doc = json.loads(out)
    assert [f["location"]["path"] for f in doc["findings"]] == ["d/a.osc"]
    assert doc["errors"] == []
    assert doc["skipped"] == [
        {"path": "d/pipe.osc", "message": "skipped: not a regular file (a named pipe)"},
        {"path": "d/zero.osc", "message": "skipped: not a regular file (a character device)"},
    ]
    assert err == (
        "osc2check: note: d/pipe.osc: skipped: not a regular file (a named pipe)\n"
        "osc2check: note: d/zero.osc: skipped: not a regular file (a character device)\n"
    )
    assert run(capsys, "d", "-q")[2] == ""  # --quiet leaves notes out


def test_folder_of_special_files_only_has_no_osc_files(project, capsys):
    os.mkfifo(project / "pipe.osc")
    with writer_waiting_on(project / "pipe.osc"):
        assert run(capsys, ".") == (
            2,
            "",
            "osc2check: error: no .osc files found in . (1 skipped: not regular files)\n",
        )


def test_broken_link_in_a_folder_is_an_error(project, capsys):
    write(project / "d" / "a.osc", CLEAN)
    (project / "d" / "b.osc").symlink_to("nowhere.osc")
    status, out, err = run(capsys, "d")
    assert status == 2
    assert out == "No findings in 1 file; 1 file could not be read\n"
    assert err == "osc2check: error: d/b.osc: cannot read: broken symbolic link to `nowhere.osc`\n"


def test_folder_that_cannot_be_listed_is_an_error(project, capsys, monkeypatch):
    write(project / "d" / "a.osc", CLEAN)
    write(project / "d" / "locked" / "b.osc", BROKEN)
    real_scandir = os.scandir

    def scandir(path="."):
        if Path(path).name == "locked":
            raise PermissionError(13, "Permission denied", os.fspath(path))
        return real_scandir(path)

    monkeypatch.setattr(os, "scandir", scandir)
    status, out, err = run(capsys, "d")
    assert status == 2
    assert out == "No findings in 1 file; 1 file could not be read\n"
    assert err == "osc2check: error: d/locked: cannot read: permission denied\n"


def test_permission_denied_is_reported_and_the_rest_checked(project, capsys):
    secret = write(project / "secret.osc", CLEAN)
    write(project / "a.osc", BROKEN)
    secret.chmod(0)
    if os.access(secret, os.R_OK):
        pytest.skip("running as a user who reads every file (root)")
    status, out, err = run(capsys, "secret.osc", "a.osc", "--output-format", "concise")
    assert status == 2
    assert out.startswith("a.osc:3:8: N101 ")
    assert err == "osc2check: error: secret.osc: cannot read: permission denied\n"


def test_open_refused_is_reported_and_the_rest_checked(project, capsys, monkeypatch):
    """As the test above, for a user (root) whom no permission stops."""
    write(project / "secret.osc", CLEAN)
    write(project / "a.osc", BROKEN)
    real_open = os.open

    def refuse(path, flags, *args, **kwargs):
        if Path(path).name == "secret.osc":
            raise PermissionError(13, "Permission denied", os.fspath(path))
        return real_open(path, flags, *args, **kwargs)

    monkeypatch.setattr(os, "open", refuse)
    status, out, err = run(capsys, "secret.osc", "a.osc", "--output-format", "concise")
    assert status == 2
    assert out.startswith("a.osc:3:8: N101 ")
    assert err == "osc2check: error: secret.osc: cannot read: permission denied\n"


def test_too_large_file_is_refused_unread(project, capsys):
    with open(project / "huge.osc", "wb") as f:
        f.truncate(inputs.MAX_SOURCE_BYTES + 1)  # sparse: no disk space used
    write(project / "a.osc", CLEAN)
    status, out, err = run(capsys, "huge.osc", "a.osc")
    assert status == 2
    assert out == "No findings in 1 file; 1 file could not be read\n"
    assert err == (
        "osc2check: error: huge.osc: cannot read: too large (52,428,801 bytes; "
        "the limit is 50 MiB)\n"
    )


def test_file_that_grows_past_the_limit_while_read_is_refused(tmp_path, monkeypatch):
    small = write(tmp_path / "small.osc", "x")
    big = write(tmp_path / "big.osc", "y" * 100)
    monkeypatch.setattr(inputs, "probe", lambda path: os.stat(small))  # stat before growth
    with pytest.raises(inputs.InputError, match=r"too large \(more than the limit"):
        inputs.read_bytes(big, limit=10)
    assert inputs.read_bytes(big, limit=100) == b"y" * 100


def test_standard_input_is_read_up_to_the_limit(project, capsys, monkeypatch):
    monkeypatch.setattr(inputs, "MAX_SOURCE_BYTES", len(CLEAN))
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(CLEAN.encode())))
    assert run(capsys, "-")[0] == 0
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(CLEAN.encode() + b"#")))
    status, _, err = run(capsys, "-")
    assert status == 2
    assert err == (
        f"osc2check: error: <stdin>: cannot read: too large (more than the limit of "
        f"{len(CLEAN)} bytes)\n"
    )


def test_dump_ast_with_a_path_that_cannot_be_read_exits_2(project, capsys):
    write(project / "a.osc", CLEAN)
    status, out, err = run(capsys, "a.osc", "gone.osc", "--dump-ast")
    assert status == 2
    assert out.startswith("File @1:1\n")
    assert err == "osc2check: error: gone.osc: cannot read: no such file or directory\n"


def test_configuration_file_that_is_a_fifo_is_a_usage_error(project, capsys):
    os.mkfifo(project / "conf.toml")
    write(project / "a.osc", CLEAN)
    with writer_waiting_on(project / "conf.toml"):
        status, out, err = run(capsys, "a.osc", "--config", "conf.toml")
    assert (status, out) == (2, "")
    assert err == "osc2check: error: conf.toml: cannot read: not a regular file (a named pipe)\n"


def test_bad_configuration_exits_2_naming_file_and_key(project, capsys):
    config = write(project / "pyproject.toml", '[tool.osc2check]\nfail-on = "fatal"\n')
    write(project / "a.osc", CLEAN)
    status, out, err = run(capsys, "a.osc")
    assert (status, out) == (2, "")
    assert err.startswith(f"osc2check: error: {config.resolve()}: tool.osc2check.fail-on: ")


def test_explicit_config_file_and_isolated(project, capsys, tmp_path):
    other = write(project / "conf" / "strict.toml", "strict = true\n")
    write(project / "osc2check.toml", 'fail-on = "info"\n')
    write(project / "w.osc", DIALECT)
    assert run(capsys, "w.osc", "--config", str(other))[1].count("D805 [error]") == 1
    assert run(capsys, "w.osc")[0] == 1  # fail-on info from osc2check.toml
    assert run(capsys, "w.osc", "--isolated")[0] == 0
    status, _, err = run(capsys, "w.osc", "--config", "missing.toml")
    assert status == 2 and "missing.toml: cannot read" in err


def test_bad_option_values_exit_2_with_one_line(project, capsys):
    write(project / "a.osc", CLEAN)
    status, _, err = run(capsys, "a.osc", "--select", "X99")
    assert (status, err) == (2, "osc2check: error: --select: unknown code, name or prefix 'X99'\n")
    status, out, err = run(capsys, "a.osc", "--output-format", "xml")
    assert (status, out) == (2, "")
    assert err.startswith("osc2check: error: argument --output-format: invalid choice: 'xml'")
    assert err.count("\n") == 1
    assert run(capsys, "--no-such-option") == (
        2,
        "",
        "osc2check: error: unrecognized arguments: --no-such-option\n",
    )
    assert run(capsys, "a.osc", "--seed") == (
        2,
        "",
        "osc2check: error: argument --seed: expected one argument\n",
    )
    assert run(capsys, "rule", "N101", "N102") == (
        2,
        "",
        "osc2check: error: unrecognized arguments: N102\n",
    )


@pytest.mark.parametrize("seed", ["-1", "1.5", "abc", ""])
def test_seed_that_is_not_a_non_negative_integer_is_a_usage_error(project, capsys, seed):
    write(project / "a.osc", CLEAN)
    assert run(capsys, "a.osc", "--witness", "--seed", seed) == (
        2,
        "",
        f"osc2check: error: argument --seed: expected a non-negative integer, got {seed!r}\n",
    )


def test_seed_zero_and_large_seeds_are_accepted(project, capsys, analysis):
    write(project / "a.osc", CLEAN)
    assert run(capsys, "a.osc", "--witness", "--seed", "0")[0] == 0
    assert run(capsys, "a.osc", "--witness", "--seed=12345678901234567890")[0] == 0
    assert [options.seed for _, options in analysis.calls] == [0, 12345678901234567890]


def test_internal_error_exits_2_without_traceback(project, capsys, analysis):
    write(project / "a.osc", CLEAN)

    def explode(sources, config, **options):
        raise RuntimeError("boom")

    analysis.analyze = explode
    status, out, err = run(capsys, "a.osc")
    assert (status, out) == (2, "")
    assert err.startswith("osc2check: internal error: RuntimeError: boom\n")
    assert "Traceback" not in err
    status, _, err = run(capsys, "a.osc", "--debug")
    assert status == 2 and "Traceback" in err and "RuntimeError: boom" in err


def test_import_of_a_fifo_or_device_is_unresolved_without_blocking(tmp_path, monkeypatch, capsys):
    """The real checker: an imported FIFO or device is never opened."""
    monkeypatch.chdir(tmp_path)
    os.mkfifo(tmp_path / "pipe.osc")
    write(tmp_path / "main.osc", 'import "pipe.osc"\nimport "/dev/zero"\nimport pipe\n')
    with writer_waiting_on(tmp_path / "pipe.osc"):
        status, out, err = run(capsys, "main.osc", "--isolated", "--output-format", "concise")
    assert (status, err) == (1, "")
    assert out.splitlines() == [
        "main.osc:1:8: N105 cannot import `pipe.osc`: `pipe.osc` is not a regular file "
        "(a named pipe)",
        "main.osc:2:8: N105 cannot import `/dev/zero`: `/dev/zero` is not a regular file "
        "(a character device)",
        "main.osc:3:8: N105 cannot import `pipe`: `pipe.osc` is not a regular file (a named pipe)",
        "Found 3 errors in 1 file (1 file checked)",
    ]


# --- witnesses ---------------------------------------------------------------------------

WITNESSED = """\
import osc.standard

scenario cruise:
    hero: vehicle
    limit: speed with:
        keep(limit in [30kph..40kph])
    do hero.drive(duration: 10s) with:
        speed(limit)
"""


def test_witness_comes_first_in_json(tmp_path, monkeypatch, capsys):
    """The real checker: the witness is read before the findings (L506 here)."""
    monkeypatch.chdir(tmp_path)
    write(tmp_path / "w.osc", WITNESSED)
    status, out, _ = run(capsys, "w.osc", "--isolated", "--witness", "--output-format", "json")
    assert status == 0
    doc = json.loads(out)
    assert list(doc) == ["scenarios", "version", "tool", "findings", "errors", "skipped"]
    (scenario,) = doc["scenarios"]
    assert scenario["witness"]["scenario"] == "cruise"
    assert [f["code"] for f in doc["findings"]] == ["L506"]
    assert out.index('"witness"') < out.index('"findings"')


# --- other commands --------------------------------------------------------------------


def test_rule_prints_the_page(capsys):
    assert run(capsys, "rule", "N101") == (0, rules.page_text("N101"), "")
    assert run(capsys, "rule", "undefined-name")[1] == rules.page_text("N101")


def test_rule_without_code_lists_all_codes(capsys):
    status, out, _ = run(capsys, "rule")
    assert status == 0
    lines = out.splitlines()
    assert len(lines) == len(codes.ALL)
    assert lines[0].split()[:3] == ["A301", "unknown-action-or-modifier", "error"]


def test_rule_with_unknown_code_exits_2(capsys):
    assert run(capsys, "rule", "X999") == (
        2,
        "",
        "osc2check: error: unknown code 'X999' (osc2check rule lists them)\n",
    )


def test_version_and_help(capsys):
    status, out, _ = run(capsys, "--version")
    assert status == 0 and out.startswith("osc2check ")
    status, out, _ = run(capsys, "--help")
    assert status == 0 and "osc2check rule CODE" in out and "exit status" in out


def test_dump_ast_prints_the_syntax_tree(project, capsys, analysis):
    write(project / "a.osc", CLEAN)
    status, out, _ = run(capsys, "a.osc", "--dump-ast")
    assert status == 0
    assert out.startswith("File @1:1\n  declarations: ScenarioDecl @1:1")
    assert analysis.calls == []


def test_the_cli_imports_neither_pygls_nor_mujoco():
    code = (
        "import sys, osc2check.cli, osc2check.output, osc2check.config, osc2check.suppress;"
        "print(sorted(m for m in ('pygls', 'lsprotocol', 'mujoco', 'z3') if m in sys.modules))"
    )
    root = Path(__file__).resolve().parents[2]
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=root, capture_output=True, text=True, check=True
    )
    assert done.stdout.strip() == "[]"


def test_the_command_exits_with_its_status_its_output_whole_and_its_cache_written(tmp_path):
    """``run`` (the command) skips freeing the process's objects at exit: the status, every
    byte of a long output through a pipe and what the exit handlers store still arrive."""
    root = Path(__file__).resolve().parents[2]
    broken = "\n".join(
        f"scenario s{i}:\n    hero: vehicle\n    do hreo.drive()\n" for i in range(300)
    )
    write(tmp_path / "many.osc", "import osc.standard\n" + broken)
    env = {**os.environ, "OSC2_CACHE_DIR": str(tmp_path / "cache")}
    env.pop("OSC2_NO_CACHE", None)
    command = [sys.executable, "-m", "osc2check.cli", "--output-format", "json", "many.osc"]
    done = subprocess.run(command, cwd=tmp_path, env=env, capture_output=True, timeout=300)
    assert done.returncode == 1, done.stderr
    assert len(json.loads(done.stdout)["findings"]) == 300 and done.stderr == b""
    assert list((tmp_path / "cache").glob("dataclass-code-*.bin"))  # stored at exit
    clean = [*command[:-1], str(root / "examples" / "cut_in_and_stop.osc")]
    done = subprocess.run(clean, cwd=tmp_path, env=env, capture_output=True, timeout=300)
    assert done.returncode == 0 and json.loads(done.stdout)["findings"] == [], done.stderr


def test_an_interrupt_inside_a_foreign_call_is_an_interrupt(monkeypatch, capsys):
    """Ctrl-C while ctypes converts a z3 call's arguments reaches the command as
    ``ctypes.ArgumentError``: it ends the check as an interrupt (130), not an internal
    error."""
    import ctypes

    from osc2check import results

    def interrupted(argv, out):
        raise ctypes.ArgumentError("argument 1: KeyboardInterrupt: ")

    monkeypatch.setattr(cli, "_check_command", interrupted)
    with pytest.raises(KeyboardInterrupt):
        cli.main(["a.osc"])
    assert results.check_interruptible(["--no-cache", "a.osc"]) == 130
    assert capsys.readouterr().err == "osc2check: interrupted\n"
