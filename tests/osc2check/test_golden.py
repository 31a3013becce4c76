"""Golden cases: `.osc` files under ``cases/`` run through the real checker.

A case is ``cases/<family>/<CODE>_<slug>.osc``, or a folder ``<CODE>_<slug>/`` of files for
multi-file cases. ``<CODE>_<slug>_ok`` names the near miss: as close to the triggering case
as possible, but reporting nothing of ``CODE``.

Expectations are inline by default, one marker per finding at the end of the line it is
reported on (STYLE.md §7)::

    position(distance: 5m, behind: hreo)    # E: N101 undefined name `hreo`; did you mean `hero`?
    speed(50)                               # E:19: T202

The letter is the severity, the code is required, the message is optional but exact when
given, ``E:19:`` pins the column, and a line without a marker must report nothing. Where a
comment cannot sit (end of file, indentation, encoding, suppression comments that are the
subject, multi-file cases), a pair holds the expectation: ``<case>.expected`` beside the
``.osc`` file or the folder, with the exact ``--output-format concise`` output and the exit
status on the last line (``exit status: 1``). C and L messages quote source lines, comments
included (a known bug), so their cases are pairs for now.

Each case is checked with ``cli.main([case, "--isolated", ...])`` from the case's folder, so
paths read as in the expected output. ``pytest --update-goldens`` rewrites the markers'
messages and the ``.expected`` files from what the checker says now: read the diff before
keeping it.

Goldens record what the checker says today. A wrong or missing finding is a case in
``KNOWN_BUGS`` that expects the right output (strict xfail, left alone by the update); a
wrong message is a strict-xfail test of its own below the goldens. Codes the checker does
not report yet are in ``NOT_IMPLEMENTED``.
"""

from __future__ import annotations

import contextlib
import io
import json
import re
from dataclasses import dataclass
from pathlib import Path

import pytest

from osc2check import cli, codes
from osc2check.source import decode_source

CASES = Path(__file__).resolve().parent / "cases"
CASE_NAME = re.compile(r"^(?P<code>[A-Z]\d{3})_\w+$")
MARKER_START = re.compile(r"#\s*[EWI](?::\d+)?:\s*[A-Z]\d{3}\b")
MARKER = re.compile(
    r"#\s*(?P<letter>[EWI])(?::(?P<column>\d+))?:\s*(?P<code>[A-Z]\d{3})\b[ \t]*(?P<message>.*)$"
)
MARKER_COLUMN = 44  # where an update puts a marker on a line that had none (0-based)
EXIT_LINE = "exit status: {}"

# Codes that the checker does not report yet, with the reason (remove a code once it does).
NOT_IMPLEMENTED: dict[str, str] = {}

# Options a case is checked with (its near miss too), beyond ``--isolated``: a budget
# small enough that a small file hits it.
CASE_OPTIONS: dict[str, tuple[str, ...]] = {
    "S003_scenario_past_memory_budget": ("--memory-limit", "16"),
    "S003_scenario_past_memory_budget_ok": ("--memory-limit", "16"),
}

# Cases that fail today because of a checker bug or a missing check; they must pass once it
# is fixed (strict xfail), and --update-goldens leaves their expectations alone.
KNOWN_BUGS: dict[str, str] = {}


# --- cases --------------------------------------------------------------------------------


@dataclass(frozen=True)
class Case:
    path: Path  # an .osc file or a folder of them

    @property
    def name(self) -> str:
        return self.path.stem if self.path.is_file() else self.path.name

    @property
    def id(self) -> str:
        return self.path.relative_to(CASES).as_posix()

    @property
    def code(self) -> str:
        return CASE_NAME.match(self.name).group("code")

    @property
    def near_miss(self) -> bool:
        return self.name.endswith("_ok")

    @property
    def expected_file(self) -> Path:
        return self.path.with_name(self.name + ".expected")

    @property
    def is_pair(self) -> bool:
        return self.expected_file.exists()

    def files(self) -> dict[str, Path]:
        """The case's files by the path the checker reports (relative to the case's folder)."""
        if self.path.is_file():
            return {self.path.name: self.path}
        return {
            p.relative_to(self.path.parent).as_posix(): p for p in sorted(self.path.rglob("*.osc"))
        }


def collect_cases() -> list[Case]:
    found = []
    for path in sorted(CASES.rglob("*")):
        inside = [p for p in path.relative_to(CASES).parents if CASE_NAME.match(p.name)]
        if inside:
            continue  # a file of a folder case
        name = path.stem if path.is_file() else path.name
        if (path.is_dir() or path.suffix == ".osc") and CASE_NAME.match(name):
            found.append(Case(path))
    return found


ALL_CASES = collect_cases()


def case_params(cases: list[Case]) -> list:
    return [
        pytest.param(
            c,
            id=c.id,
            marks=pytest.mark.xfail(strict=True, raises=AssertionError, reason=KNOWN_BUGS[c.id]),
        )
        if c.id in KNOWN_BUGS
        else pytest.param(c, id=c.id)
        for c in cases
    ]


# --- running the checker ------------------------------------------------------------------


def run_cli(case: Case, output_format: str) -> tuple[int, str, str]:
    """(exit status, stdout, stderr) of the CLI on the case, from the case's folder."""
    out, err = io.StringIO(), io.StringIO()
    with (
        contextlib.chdir(case.path.parent),
        contextlib.redirect_stdout(out),
        contextlib.redirect_stderr(err),
    ):
        options = CASE_OPTIONS.get(case.path.stem, ())
        status = cli.main(
            [case.path.name, "--isolated", "--output-format", output_format, *options]
        )
    return status, out.getvalue(), err.getvalue()


@dataclass(frozen=True)
class Finding:
    line: int
    column: int
    letter: str
    code: str
    message: str

    def marker(self, pin: bool) -> str:
        where = f":{self.column}" if pin else ""
        return f"# {self.letter}{where}: {self.code} {self.message}".rstrip()


def findings(case: Case) -> tuple[int, dict[str, list[Finding]], str]:
    """The exit status, the findings by reported path, and stderr."""
    status, out, err = run_cli(case, "json")
    assert status in (0, 1), f"exit status {status}: {err}"
    by_path: dict[str, list[Finding]] = {}
    for f in json.loads(out)["findings"]:
        start = f["location"]["start"]
        by_path.setdefault(f["location"]["path"], []).append(
            Finding(
                start["line"], start["column"], f["severity"][0].upper(), f["code"], f["message"]
            )
        )
    return status, by_path, err


# --- inline markers -----------------------------------------------------------------------


@dataclass(frozen=True)
class Marker:
    letter: str
    column: int | None
    code: str
    message: str | None
    offset: int  # where the marker starts on its line

    def matches(self, f: Finding) -> bool:
        return (
            (self.letter, self.code) == (f.letter, f.code)
            and self.column in (None, f.column)
            and self.message in (None, f.message)
        )

    def __str__(self) -> str:
        where = f":{self.column}" if self.column is not None else ""
        return f"# {self.letter}{where}: {self.code} {self.message or ''}".rstrip()


def read_text(path: Path) -> str:
    return decode_source(path.read_bytes())[0]


def markers_of_line(line: str) -> list[Marker]:
    starts = [m.start() for m in MARKER_START.finditer(line)]
    found = []
    for start, end in zip(starts, [*starts[1:], len(line)], strict=False):
        m = MARKER.match(line[start:end].rstrip())
        found.append(
            Marker(
                m["letter"],
                int(m["column"]) if m["column"] else None,
                m["code"],
                m["message"].strip() or None,
                start,
            )
        )
    return found


def markers(text: str) -> dict[int, list[Marker]]:
    """Line number -> markers on that line."""
    found = {}
    for number, line in enumerate(text.splitlines(), start=1):
        on_line = markers_of_line(line)
        if on_line:
            found[number] = on_line
    return found


def compare_line(expected: list[Marker], actual: list[Finding]) -> list[str]:
    """Problems with one line: markers without a finding and findings without a marker."""
    left = sorted(actual, key=lambda f: (f.column, f.code, f.message))
    problems = []
    for marker in expected:
        match = next((f for f in left if marker.matches(f)), None)
        if match is None:
            problems.append(f"missing:    {marker}")
        else:
            left.remove(match)
    problems += [f"unexpected: {f.marker(pin=True)}" for f in left]
    return problems


def inline_problems(case: Case, by_path: dict[str, list[Finding]]) -> list[str]:
    problems = []
    files = case.files()
    for path in sorted(set(by_path) - set(files)):
        problems += [f"{path}: finding outside the case: {f}" for f in by_path[path]]
    for path, file in files.items():
        expected = markers(read_text(file))
        actual: dict[int, list[Finding]] = {}
        for f in by_path.get(path, []):
            actual.setdefault(f.line, []).append(f)
        for line in sorted(set(expected) | set(actual)):
            problems += [
                f"{path}:{line}: {p}"
                for p in compare_line(expected.get(line, []), actual.get(line, []))
            ]
    return problems


def rewrite_markers(file: Path, actual: list[Finding]) -> None:
    """Put one marker per finding on its line, keeping pinned columns and marker positions."""
    data = file.read_bytes()
    text, problem = decode_source(data)
    assert problem is None, f"{file}: not UTF-8; make it a pair (.expected)"
    lines = text.splitlines(keepends=True)
    by_line: dict[int, list[Finding]] = {}
    for f in actual:
        by_line.setdefault(f.line, []).append(f)
    beyond = [f for f in actual if f.line > len(lines)]
    assert not beyond, f"{file}: findings after the last line {beyond}; make it a pair"
    for number, line in enumerate(lines, start=1):
        body = line.rstrip("\r\n")
        ending = line[len(body) :]
        old = markers_of_line(body)
        new = sorted(by_line.get(number, []), key=lambda f: (f.column, f.code, f.message))
        if not old and not new:
            continue
        at = old[0].offset if old else max(len(body.rstrip()) + 2, MARKER_COLUMN)
        body = body[: old[0].offset].rstrip() if old else body.rstrip()
        pinned = {m.code for m in old if m.column is not None}
        if new:
            body = body.ljust(at) + "  ".join(f.marker(f.code in pinned) for f in new)
        lines[number - 1] = body + ending
    file.write_text("".join(lines), encoding="utf-8", newline="")


# --- pairs --------------------------------------------------------------------------------


def pair_output(case: Case) -> tuple[str, str]:
    """The concise output with the exit status on the last line, and stderr."""
    status, out, err = run_cli(case, "concise")
    return out + EXIT_LINE.format(status) + "\n", err


def expected_codes(case: Case) -> set[str]:
    """The codes the case's expectation names."""
    if case.is_pair:
        text = case.expected_file.read_text(encoding="utf-8")
        return set(re.findall(r"^\S+:\d+:\d+: ([A-Z]\d{3}) ", text, re.MULTILINE))
    return {
        m.code for f in case.files().values() for ms in markers(read_text(f)).values() for m in ms
    }


# --- tests --------------------------------------------------------------------------------


@pytest.mark.parametrize("case", case_params(ALL_CASES))
def test_case_reports_exactly_what_it_expects(case: Case, update_goldens: bool):
    update_goldens = update_goldens and case.id not in KNOWN_BUGS
    if case.is_pair:
        got, err = pair_output(case)
        assert "Traceback" not in err and "internal error" not in err, err
        if update_goldens:
            case.expected_file.write_text(got, encoding="utf-8", newline="\n")
        assert got == case.expected_file.read_text(encoding="utf-8")
        return
    status, by_path, err = findings(case)
    assert "Traceback" not in err and "internal error" not in err, err
    everything = [f for fs in by_path.values() for f in fs]
    assert {f.code for f in everything} <= set(codes.BY_CODE), "an unregistered code"
    assert status == (1 if any(f.letter == "E" for f in everything) else 0), err
    if update_goldens:
        for path, file in case.files().items():
            rewrite_markers(file, by_path.get(path, []))
    problems = inline_problems(case, by_path)
    assert not problems, "\n" + "\n".join(problems)


@pytest.mark.parametrize("case", ALL_CASES, ids=lambda c: c.id)
def test_case_name_and_expectation_agree(case: Case):
    """A case triggers its code; its near miss (``_ok``) expects nothing of that code."""
    assert case.code in codes.BY_CODE, f"{case.id}: unknown code {case.code}"
    named = expected_codes(case)
    if case.near_miss:
        assert case.code not in named, f"{case.id}: a near miss must not expect {case.code}"
    else:
        assert case.code in named, f"{case.id}: expects no {case.code}"


def test_every_implemented_code_has_a_case_and_a_near_miss():
    triggered = {c.code for c in ALL_CASES if not c.near_miss and c.id not in KNOWN_BUGS}
    near = {c.code for c in ALL_CASES if c.near_miss}
    implemented = {c.code for c in codes.ALL if c.removed_in is None} - set(NOT_IMPLEMENTED)
    assert sorted(implemented - triggered) == [], "codes without a triggering case"
    assert sorted(implemented - near) == [], "codes without a near miss"
    assert sorted(set(NOT_IMPLEMENTED) & triggered) == [], "remove these from NOT_IMPLEMENTED"
    assert set(NOT_IMPLEMENTED) <= set(codes.BY_CODE)


def test_known_bugs_name_existing_cases():
    assert set(KNOWN_BUGS) <= {c.id for c in ALL_CASES}


def test_markers_are_read_as_written():
    line = "    speed(50)        # E:19: T202 missing unit  # W: D805"
    got = [str(m) for m in markers_of_line(line)]
    assert got == ["# E:19: T202 missing unit", "# W: D805"]
    assert markers("a\n# osc2check: ignore[T202]\n") == {}


# --- known message bugs -------------------------------------------------------------------


def case_named(case_id: str) -> Case:
    (case,) = [c for c in ALL_CASES if c.id == case_id]
    return case


# Goldens record what the checker says today; these tests fail until a message is fixed.


@pytest.mark.parametrize(
    "case_id", ["types/T202_float_field_as_duration.osc", "dialect/D805_unitless_duration.osc"]
)
def test_unit_suggested_for_a_duration_is_a_time_unit(case_id: str):
    case = case_named(case_id)
    _, by_path, _ = findings(case)
    (finding,) = [f for fs in by_path.values() for f in fs if f.code == case.code]
    assert re.search(r"such as `\d+(s|ms|min|h)`", finding.message), finding.message


def test_l507_prints_lengths_as_decimals():
    output, _ = pair_output(case_named("placement/L507_beyond_road_end.osc"))
    assert "L507" in output
    assert not re.search(r"\d+/\d+ m\b", output), output


SYNTAX_ERRORS = [
    "    budget: float = 1..2",
    "    budget: float = 3]",
    "    def time_to_go() -> time is 3s",
]


@pytest.mark.parametrize("line", SYNTAX_ERRORS)
def test_syntax_messages_name_tokens_not_grammar_rules(line: str, tmp_path: Path):
    source = tmp_path / "P001_grammar_rule_names.osc"
    source.write_text(f"import osc.standard\n\nscenario s:\n    hero: vehicle\n{line}\n")
    _, by_path, _ = findings(Case(source))
    messages = [f.message for fs in by_path.values() for f in fs if f.code == "P001"]
    assert messages
    for message in messages:
        rules = re.findall(r"(?<![`\w])[a-z]+_[a-z_]+(?![`\w])", message)
        assert not rules, message


def test_one_mistake_gives_one_finding(tmp_path: Path):
    source = tmp_path / "P001_unclosed_header.osc"
    source.write_text("import osc.standard\n\naction vehicle.slow_down(\n    target: speed\n")
    _, by_path, _ = findings(Case(source))
    assert [f.code for fs in by_path.values() for f in fs] == ["P001"]


# --- the harness itself -------------------------------------------------------------------


def test_update_rewrites_messages_keeps_pins_and_places_new_markers(tmp_path: Path):
    source = tmp_path / "N101_update.osc"
    source.write_bytes(
        b"scenario s:\r\n"
        b"    a: hreo            # E:12: N101 old text\r\n"
        b"    b: int\r\n"
        b"    c: int  # E: T202\r\n"
    )
    rewrite_markers(
        source, [Finding(2, 8, "E", "N101", "new text"), Finding(3, 8, "E", "N102", "twice")]
    )
    lines = source.read_bytes().decode().split("\r\n")
    assert lines[1] == "    a: hreo            # E:8: N101 new text"
    assert lines[2] == "    b: int".ljust(MARKER_COLUMN) + "# E: N102 twice"
    assert lines[3] == "    c: int"
    assert markers(source.read_text()) == {
        2: [Marker("E", 8, "N101", "new text", 23)],
        3: [Marker("E", None, "N102", "twice", MARKER_COLUMN)],
    }


def test_a_line_without_marker_must_report_nothing():
    found = [Finding(3, 5, "E", "N101", "undefined name `x`")]
    assert compare_line([], found) == ["unexpected: # E:5: N101 undefined name `x`"]
    assert compare_line([Marker("W", None, "N101", None, 0)], found) == [
        "missing:    # W: N101",
        "unexpected: # E:5: N101 undefined name `x`",
    ]
    assert compare_line([Marker("E", 5, "N101", "undefined name `x`", 0)], found) == []
