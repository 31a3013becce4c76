"""The memory budget of one file's check (S003): past it the file has one finding that
names the file, the element being analysed with its line and column, and the budget;
the other files are checked. The budgets here are tiny, so that the tests are cheap."""

from __future__ import annotations

import json
import resource
import subprocess
import sys

import pytest

from osc2check import cli, memory
from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.config import ConfigError, load_config_file
from osc2check.source import point_span
from osc2check.verify import check as verify_check
from osc2check.verify.z3_backend import SolverOutcome

# The solver needs a context for these constraints (propagation does not settle them),
# and 16 MiB leave no room for one (memory.SOLVER_ROOM).
SOLVED = """\
import osc.standard

scenario two_speeds:
    hero: vehicle
    a: speed
    b: speed
    keep(a + b == 30kph)
    keep(a > b)
"""
UNDEFINED = "import osc.standard\n\nscenario typo:\n    x: speed = undefined_speed\n"


def _big(count: int = 6000) -> str:
    """A file of many small declarations: parsing it needs far more than 4 MiB."""
    parts = ["import osc.standard\n"]
    parts += [
        f"struct s{i}:\n    a{i}: int = {i}\n    b{i}: speed = {i}kph\n" for i in range(count)
    ]
    return "\n".join(parts)


def _check(tmp_path, monkeypatch, capsys, files: dict[str, str], *options: str):
    for name, text in files.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    status = cli.main([*files, "--isolated", "--output-format", "json", *options])
    out, err = capsys.readouterr()
    return status, json.loads(out)["findings"], err


def _check_apart(tmp_path, files: dict[str, str], *options: str):
    """As ``_check``, in a process of its own: a process that has run other checks has
    freed memory that a parse could take without growing, so a parse's budget is only
    hit for certain in a fresh one."""
    for name, text in files.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
    command = [sys.executable, "-m", "osc2check.cli", *files, "--isolated"]
    done = subprocess.run(
        [*command, "--output-format", "json", *options],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        check=False,
    )
    return done.returncode, json.loads(done.stdout)["findings"], done.stderr


def test_a_scenario_past_the_budget_is_named_and_the_other_files_are_checked(
    tmp_path, monkeypatch, capsys
):
    files = {"solved.osc": SOLVED, "typo.osc": UNDEFINED}
    status, found, err = _check(tmp_path, monkeypatch, capsys, files, "--memory-limit", "16")
    assert status == 1 and "internal error" not in err
    by_file = {f["location"]["path"]: f for f in found}
    budget = by_file["solved.osc"]
    assert budget["code"] == "S003" and budget["severity"] == "error"
    assert budget["location"]["start"] == {"line": 3, "column": 10}
    assert "solving scenario `two_speeds` at solved.osc:3:10" in budget["message"]
    assert "(16 MiB)" in budget["message"]
    assert by_file["typo.osc"]["code"] == "N101"  # the other file keeps its findings


def test_parsing_past_the_budget_names_the_file_and_the_next_file_is_checked(tmp_path):
    files = {"big.osc": _big(), "typo.osc": UNDEFINED}
    status, found, _ = _check_apart(tmp_path, files, "--memory-limit", "4")
    assert status == 1
    assert [(f["location"]["path"], f["code"]) for f in found] == [
        ("big.osc", "S003"),
        ("typo.osc", "N101"),
    ]
    assert "while parsing the file at big.osc:1:1" in found[0]["message"]


def test_an_import_past_the_budget_is_named_at_the_import(tmp_path):
    files = {"root.osc": 'import "big.osc"\n'}
    (tmp_path / "big.osc").write_text(_big(), encoding="utf-8")
    status, found, _ = _check_apart(tmp_path, files, "--memory-limit", "4")
    assert status == 1 and [f["code"] for f in found] == ["S003"]
    assert found[0]["location"]["start"] == {"line": 1, "column": 1}
    assert "while reading the import of `big.osc` at root.osc:1:1" in found[0]["message"]


def test_the_default_budget_checks_the_same_files_clean(tmp_path, monkeypatch, capsys):
    status, found, _ = _check(tmp_path, monkeypatch, capsys, {"solved.osc": SOLVED})
    assert status == 0 and found == []
    status, found, _ = _check(
        tmp_path, monkeypatch, capsys, {"solved.osc": SOLVED}, "--memory-limit", "0"
    )
    assert status == 0 and found == []


def test_z3_out_of_memory_is_the_budget_at_the_scenario(monkeypatch):
    """z3 answers "out of memory" when an allocation inside it fails under the budget."""
    monkeypatch.setattr(
        verify_check, "check", lambda *a, **k: SolverOutcome("unknown", reason="out of memory")
    )
    found = analyze([SourceInput("solved.osc", SOLVED)]).diagnostics
    assert [(d.code.code, d.span.line, d.span.column) for d in found] == [("S003", 3, 10)]
    assert "while solving scenario `two_speeds`" in found[0].message
    assert "(1 GiB)" in found[0].message  # the default budget, named


def test_the_budget_is_put_back_after_each_file():
    before = resource.getrlimit(resource.RLIMIT_AS)
    analyze([SourceInput("solved.osc", SOLVED)], AnalysisOptions(memory_limit_mib=16))
    assert resource.getrlimit(resource.RLIMIT_AS) == before


def test_the_innermost_element_is_named_and_z3_errors_count_as_out_of_memory():
    class Z3Exception(Exception):  # z3's error type, by name (z3 is imported lazily)
        pass

    outer = point_span("a.osc", "x\ny\n", 0)
    inner = point_span("a.osc", "x\ny\n", 2)
    with pytest.raises(memory.BudgetExceeded) as caught:
        with memory.analysing(outer, "parsing the file"):
            with memory.analysing(inner, "checking struct `s`"):
                raise Z3Exception(b"out of memory")
    assert caught.value.element == memory.Element(inner, "checking struct `s`")
    with pytest.raises(ValueError), memory.analysing(outer, "parsing the file"):
        raise ValueError("not a memory problem")


def test_the_configuration_sets_the_budget(tmp_path):
    (tmp_path / "osc2check.toml").write_text("memory-limit = 64\n", encoding="utf-8")
    config = load_config_file(tmp_path / "osc2check.toml")
    assert config.analysis_options().memory_limit_mib == 64
    (tmp_path / "osc2check.toml").write_text("memory-limit = 0\n", encoding="utf-8")
    assert load_config_file(tmp_path / "osc2check.toml").analysis_options().memory_limit_mib is None
    (tmp_path / "osc2check.toml").write_text('memory-limit = "1G"\n', encoding="utf-8")
    with pytest.raises(ConfigError, match="memory-limit"):
        load_config_file(tmp_path / "osc2check.toml")


def test_a_bad_memory_limit_option_is_a_usage_error(tmp_path, monkeypatch, capsys):
    (tmp_path / "a.osc").write_text(SOLVED, encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    assert cli.main(["a.osc", "--isolated", "--memory-limit", "1G"]) == 2
    assert "expected a number of MiB" in capsys.readouterr().err


def test_a_declaration_past_the_budget_is_named(monkeypatch):
    from osc2check.semantics.bodies import BodyChecker

    def out_of_memory(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr(BodyChecker, "_structured", out_of_memory)
    text = "import osc.standard\n\nstruct load:\n    mass: mass\n"
    found = analyze([SourceInput("load.osc", text)]).diagnostics
    assert [(d.code.code, d.span.line, d.span.column) for d in found] == [("S003", 3, 8)]
    assert "while checking struct `load` at load.osc:3:8" in found[0].message


def test_a_tighter_limit_the_user_set_is_kept():
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    tight = memory._mapped() + 512 * memory.MIB
    resource.setrlimit(resource.RLIMIT_AS, (tight, hard))
    try:
        with memory.budget(4096):
            assert resource.getrlimit(resource.RLIMIT_AS)[0] == tight
        assert resource.getrlimit(resource.RLIMIT_AS)[0] == tight
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def test_a_map_built_under_a_tight_budget_is_no_internal_error(tmp_path):
    """With no start-up cache, the built-in map is built during the check: numpy, which it
    needs, is loaded before a tight budget (it maps about 120 MiB), not inside it."""
    files = {"solved.osc": SOLVED}
    status, found, err = _check_apart(tmp_path, files, "--memory-limit", "16", "--no-cache")
    assert "internal error" not in err and "Traceback" not in err
    assert status == 1 and [f["code"] for f in found] == ["S003"]
    assert "solving scenario `two_speeds`" in found[0]["message"]


def test_a_library_that_finds_no_room_to_load_is_out_of_memory():
    cause = OSError("libopenblas.so: failed to map segment from shared object")
    error = ImportError("Importing the numpy C-extensions failed.")
    error.__cause__ = cause
    assert memory.is_out_of_memory(error)
    assert not memory.is_out_of_memory(ImportError("No module named 'numpy'"))


def _loaded_after_check(tmp_path, text: str, *options: str) -> tuple[int, str]:
    """Check ``text`` in a new ``osc2check`` process (no stored result); its exit status
    and, from its exit handler, which of z3 and numpy it loaded."""
    path = tmp_path / "case.osc"
    path.write_text(text, encoding="utf-8")
    code = (
        "import atexit, sys\n"
        "atexit.register(lambda: print('loaded', 'z3' in sys.modules, 'numpy' in sys.modules))\n"
        "from osc2check.results import run\n"
        f"sys.argv[1:] = {['--no-cache', *options, str(path)]!r}\n"
        "run()\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert "Traceback" not in proc.stderr
    return proc.returncode, proc.stdout.splitlines()[-1]


DECIDED_BY_PROPAGATION = "import osc.standard\n\nscenario s:\n    x: speed\n    keep(x == 30kph)\n"


def test_a_check_that_needs_no_solver_does_not_load_z3(tmp_path):
    """Under the default budget z3 is loaded when a scenario needs it (a sixth of a small
    file's check), not before; the file it needs it for is checked the same."""
    assert _loaded_after_check(tmp_path, DECIDED_BY_PROPAGATION) == (0, "loaded False False")
    status, loaded = _loaded_after_check(tmp_path, SOLVED)
    assert status == 0 and loaded.startswith("loaded True")  # numpy: without a cache, the map


def test_a_tight_budget_loads_z3_and_numpy_before_it(tmp_path):
    assert _loaded_after_check(tmp_path, DECIDED_BY_PROPAGATION, "--memory-limit", "256") == (
        0,
        "loaded True True",
    )
