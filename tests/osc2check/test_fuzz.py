"""Robustness: damaged and random input never makes ``parse``, ``analyze`` or the CLI raise.

Hypothesis mutates the conformance files (``../shared/conformance/{seed,open,asam-2.1}``,
found beside the repository; left out when absent), the repository's ``examples/`` and the
golden cases: it deletes, duplicates and swaps lines, and deletes, inserts, replaces and swaps
characters, favouring the ones the grammar cares about (brackets, colons, tabs, quotes, ``@``,
``!``, non-ASCII, NUL, ``\\r``). It also feeds random text and random bytes (decoded the way
the CLI decodes a file). Deterministic cases cover the edges: empty and blank files, a 50,000
line file, deep nesting, tabs, line endings, a BOM and invalid UTF-8.

Settings are modest and derandomized, so CI runs the same examples every time.
"""

from __future__ import annotations

import contextlib
import io
import json
import re
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from osc2check import cli, codes, rules
from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.source import decode_source
from osc2check.syntax import parse

REPO = Path(__file__).resolve().parents[2]
CONFORMANCE = REPO.parent / "shared" / "conformance"


def corpus_files() -> list[Path]:
    """The conformance files, the examples, and the golden cases (valid scenarios that reach
    the solver, and one broken file per syntax code)."""
    found = [
        p for sub in ("seed", "open", "asam-2.1") for p in sorted((CONFORMANCE / sub).glob("*.osc"))
    ]
    found += sorted((REPO / "examples").glob("*.osc"))
    return found + sorted((Path(__file__).parent / "cases").rglob("*.osc"))


CORPUS: list[bytes] = [p.read_bytes() for p in corpus_files()]
WINDOW = 120  # lines kept from a long file, so that one example stays fast to analyze
SPECIAL = list("()[]{}:,.;@!?\"'`#\\-+*/=<>|&~$%^ \t\r\n\x00\x0b\x0c") + [
    "é",
    "ß",
    "→",
    "…",
    "\u00a0",
    "\u200b",
    "\u2028",
    "\ufeff",
    "\ufffd",
    "𝛼",
    "日本",
    "🚗",
    "..",
    "::",
    "->",
    "==",
    "!=",
    "<=",
    "    ",
    "\t\t",
    "\r\n",
    "kph",
    "it",
    "do",
    "with:",
    "serial:",
    "keep(",
    "wait @",
    "emit ",
    "1e",
    "0x",
    "1_000",
    "5m",
    "[1..",
    "]",
]
BAD_BYTES = [
    b"\xff",
    b"\xfe",
    b"\xc3",
    b"\xe2\x82",
    b"\xed\xa0\x80",
    b"\xc0\xaf",
    b"\x80",
    b"\x00",
    b"\xef\xbb\xbf",
    b"\r",
    b"\r\n",
]
SETTINGS = settings(
    max_examples=150,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
# The solver gets a small budget: the fuzz tests look for crashes, not for answers.
OPTIONS = AnalysisOptions(solver_rlimit=300_000, solver_timeout_ms=1000)


# --- strategies -----------------------------------------------------------------------------


def _text(data: bytes) -> str:
    return decode_source(data)[0]


@st.composite
def mutated_text(draw) -> str:
    """A corpus file with a few lines and characters deleted, duplicated, swapped or replaced."""
    lines = _text(draw(st.sampled_from(CORPUS))).splitlines(keepends=True)
    if len(lines) > WINDOW:
        start = draw(st.integers(0, len(lines) - WINDOW))
        lines = lines[start : start + WINDOW]
    for _ in range(draw(st.integers(0, 4))):
        if not lines:
            break
        i, j = (draw(st.integers(0, len(lines) - 1)) for _ in range(2))
        op = draw(st.sampled_from(["delete", "duplicate", "swap", "move"]))
        if op == "delete":
            del lines[i]
        elif op == "duplicate":
            lines.insert(j, lines[i])
        elif op == "swap":
            lines[i], lines[j] = lines[j], lines[i]
        else:
            lines.insert(j, lines.pop(i))
    text = "".join(lines)
    char = st.one_of(st.sampled_from(SPECIAL), st.characters(), st.text(max_size=3))
    for _ in range(draw(st.integers(0, 6))):
        i = draw(st.integers(0, len(text)))
        op = draw(st.sampled_from(["delete", "insert", "replace", "swap"]))
        if op == "delete":
            text = text[:i] + text[i + 1 :]
        elif op == "insert":
            text = text[:i] + draw(char) + text[i:]
        elif op == "replace":
            text = text[:i] + draw(char) + text[i + 1 :]
        elif i + 1 < len(text):
            text = text[:i] + text[i + 1] + text[i] + text[i + 2 :]
    return text


@st.composite
def mutated_bytes(draw) -> bytes:
    """Mutated text, encoded, with stray bytes that are not UTF-8 here and there."""
    data = draw(mutated_text()).encode("utf-8", errors="surrogatepass")
    for _ in range(draw(st.integers(0, 3))):
        i = draw(st.integers(0, len(data)))
        data = data[:i] + draw(st.sampled_from(BAD_BYTES)) + data[i:]
    return data


def _grammar_text() -> st.SearchStrategy[str]:
    """Random text made of OSC2 pieces, so that it gets past the first token now and then."""
    pieces = st.sampled_from(
        SPECIAL
        + [
            "scenario s",
            "actor a",
            "struct r",
            "enum e: [a, b]",
            "hero: vehicle",
            "import osc.standard",
            "hero.drive()",
            "speed(50kph)",
            "lane(1, at: start)",
            "x: int = 3",
            "def f() -> int",
            "is expression",
            "on @e:",
            "one_of:",
            "parallel:",
            "until",
            "elapsed(2s)",
            "\n    ",
        ]
    )
    return st.lists(pieces, max_size=40).map("".join)


ANY_TEXT = st.one_of(mutated_text(), st.text(max_size=400), _grammar_text())
ANY_BYTES = st.one_of(mutated_bytes(), st.binary(max_size=400))


# --- invariants ---------------------------------------------------------------------------


def assert_sane(diagnostics, text: str, uri: str) -> None:
    """Registered codes, and every finding of the file inside the file."""
    # Lines end at \n, \r\n or a lone \r, as in LSP; splitlines() knows a few more breaks.
    lines = max(len(re.split(r"\r\n|\r|\n", text)), len(text.splitlines()) + 1)
    for d in diagnostics:
        assert d.code.code in codes.BY_CODE, d
        if d.span.uri != uri:
            continue
        assert 0 <= d.span.start <= d.span.end <= len(text), d
        assert 1 <= d.span.line <= d.span.end_line <= lines, d


def check_parse(text: str) -> None:
    result = parse(text, "fuzz.osc")
    assert_sane(result.diagnostics, text, "fuzz.osc")


def check_analyze(text: str, problem: str | None = None) -> None:
    uri = "fuzz.osc"
    analysis = analyze([SourceInput(uri=uri, text=text, problem=problem)], OPTIONS)
    assert_sane(analysis.diagnostics, text, uri)


@pytest.fixture(scope="module")
def workdir(tmp_path_factory) -> Path:
    """A folder with the solver budget in ``osc2check.toml``; fuzzed files are written here."""
    folder = tmp_path_factory.mktemp("fuzz")
    (folder / "osc2check.toml").write_text("[solver]\nrlimit = 300000\ntimeout-ms = 1000\n")
    return folder


def run_cli(folder: Path, data: bytes, output_format: str = "concise") -> tuple[int, str, str]:
    path = folder / "fuzz.osc"
    path.write_bytes(data)
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = cli.main(
            [
                str(path),
                "--config",
                str(folder / "osc2check.toml"),
                "--output-format",
                output_format,
            ]
        )
    return status, out.getvalue(), err.getvalue()


def check_cli(folder: Path, data: bytes, output_format: str = "concise") -> None:
    status, out, err = run_cli(folder, data, output_format)
    assert status in (0, 1, 2), status
    assert "Traceback" not in err, err
    assert "internal error" not in err, err  # the CLI's guard caught an exception
    if output_format in ("json", "sarif"):
        json.loads(out)


# --- hypothesis ---------------------------------------------------------------------------


@pytest.mark.slow
@SETTINGS
@given(ANY_TEXT)
def test_parse_never_raises(text: str):
    check_parse(text)


@SETTINGS
@given(ANY_TEXT)
def test_analyze_never_raises(text: str):
    check_analyze(text)


@SETTINGS
@given(ANY_BYTES)
def test_decoded_bytes_never_make_parse_or_analyze_raise(data: bytes):
    text, problem = decode_source(data)
    check_parse(text)
    check_analyze(text, problem)


def _has_page(code: codes.Code) -> bool:
    try:
        rules.page_text(code)
    except FileNotFoundError:
        return False
    return True


# SARIF output reads each reported code's page and fails without it; test_code_docs.py asks
# for every page, and until they all exist SARIF is left out here.
FORMATS = ["concise", "full", "json", "github"]
if all(_has_page(c) for c in codes.ALL):
    FORMATS.append("sarif")


@pytest.mark.slow
@SETTINGS
@given(data=ANY_BYTES, output_format=st.sampled_from(FORMATS))
def test_cli_exits_0_1_or_2_without_traceback(workdir: Path, data: bytes, output_format: str):
    check_cli(workdir, data, output_format)


# --- edge cases ---------------------------------------------------------------------------

HEADER = "import osc.standard\n\nscenario edge:\n    hero: vehicle\n    x: int\n    b: bool\n"
DRIVE = "    do hero.drive(duration: 10s) with:\n        speed(50kph)\n"


def deep_serial(levels: int) -> str:
    lines = ["import osc.standard", "", "scenario deep:", "    hero: vehicle", "    do serial:"]
    lines += ["    " * (level + 2) + "serial:" for level in range(levels)]
    lines.append("    " * (levels + 2) + "hero.drive(duration: 1s)")
    return "\n".join(lines) + "\n"


EDGE_CASES: dict[str, bytes] = {
    "empty": b"",
    "only_whitespace": b"   \n\t\n  \t  \n\n",
    "only_comments": b"# one\n    # two, indented\n\t# three, after a tab\n#",
    "deep_parentheses": (HEADER + "    keep(x == " + "(" * 500 + "1" + ")" * 500 + ")\n").encode(),
    "deep_serial": deep_serial(200).encode(),
    "mixed_tabs_and_spaces": (
        b"import osc.standard\n\nscenario tabs:\n\thero: vehicle\n\tdo serial:\n"
        b"\t    hero.drive(duration: 1s)\n        \thero.drive(duration: 2s)\n"
        b"  \t  hero.drive(duration: 3s)\n"
    ),
    "tabs_aligned_with_spaces": (
        b"import osc.standard\n\nscenario tabs:\n\thero: vehicle\n        npc: vehicle\n"
        b"\tdo serial:\n\t    hero.drive(duration: 1s)\n            npc.drive(duration: 1s)\n"
    ),
    "no_final_newline": (HEADER + DRIVE).rstrip("\n").encode(),
    "crlf": (HEADER + DRIVE).replace("\n", "\r\n").encode(),
    "lone_cr": (HEADER + DRIVE).replace("\n", "\r").encode(),
    "mixed_line_endings": (HEADER + DRIVE).replace("\n", "\r\n", 3).replace("\n", "\r", 2).encode(),
    "bom": b"\xef\xbb\xbf" + (HEADER + DRIVE).encode(),
    "bom_twice": b"\xef\xbb\xbf\xef\xbb\xbf" + (HEADER + DRIVE).encode(),
    "invalid_utf8": (
        b"# Sc\xe9nario\n" + (HEADER + DRIVE).encode() + b'    label: string = "\xff\xfe"\n'
    ),
    "truncated_utf8": (HEADER + DRIVE).encode() + b"# caf\xc3",
    "nul_bytes": (HEADER + DRIVE).encode().replace(b"hero", b"he\x00ro", 1),
    "only_nul": b"\x00" * 64,
    "long_line": (HEADER + "    keep(x == " + " + ".join(["1"] * 200) + ")\n").encode(),
}

# Pathologically deep expressions: analysis reports P005 instead of exhausting the stack.
DEEP_EXPRESSIONS: dict[str, bytes] = {
    "deep_brackets": (HEADER + "    keep(x in " + "[" * 500 + "1..2" + "]" * 500 + ")\n").encode(),
    "deep_list": ("global g: list of int = " + "[" * 500 + "1" + "]" * 500 + "\n").encode(),
    "long_sum": (HEADER + "    keep(x == " + " + ".join(["1"] * 500) + ")\n").encode(),
    "long_and": (HEADER + "    keep(" + " and ".join(["b"] * 500) + ")\n").encode(),
    "deep_not": (HEADER + "    keep(" + "not " * 500 + "b)\n").encode(),
    "deep_minus": (HEADER + "    keep(x == " + "-" * 500 + "1)\n").encode(),
    "long_member_chain": (HEADER + "    keep(hero" + ".speed" * 500 + " > 1kph)\n").encode(),
}
ALL_EDGES = [
    pytest.param(data, id=name) for name, data in {**EDGE_CASES, **DEEP_EXPRESSIONS}.items()
]


@pytest.mark.parametrize("data", ALL_EDGES)
def test_edge_case_parses_analyzes_and_runs(data: bytes, workdir: Path):
    text, problem = decode_source(data)
    check_parse(text)
    check_cli(workdir, data)
    check_analyze(text, problem)


@pytest.mark.parametrize(
    "name",
    [
        "empty",
        "only_whitespace",
        "only_comments",
        "crlf",
        "bom",
        "no_final_newline",
        "deep_serial",
        "deep_parentheses",
        "tabs_aligned_with_spaces",
        "lone_cr",
    ],
)
def test_valid_edge_case_reports_nothing_but_the_unplaced_hero(name: str):
    """Blank files, line endings and a BOM are not findings in themselves."""
    text, problem = decode_source(EDGE_CASES[name])
    assert problem is None
    found = analyze([SourceInput(uri="edge.osc", text=text)], OPTIONS).diagnostics
    assert {d.code.code for d in found} <= {"L506"}, found


def test_invalid_utf8_and_nul_are_reported_as_p004():
    for name in ("invalid_utf8", "truncated_utf8", "nul_bytes", "only_nul"):
        text, problem = decode_source(EDGE_CASES[name])
        assert problem is not None, name
        found = analyze([SourceInput(uri="edge.osc", text=text, problem=problem)], OPTIONS)
        assert "P004" in {d.code.code for d in found.diagnostics}, name


@pytest.mark.slow
def test_a_50000_line_file_parses():
    lines = ["import osc.standard", ""]
    record = 0
    while len(lines) < 50_000:
        lines += [
            f"struct record_{record}:",
            f"    value: int = {record}",
            f'    label: string = "r{record}"',
            "",
        ]
        record += 1
    text = "\n".join(lines[:50_000]) + "\n"
    assert text.count("\n") == 50_000
    result = parse(text, "big.osc")
    assert list(result.diagnostics) == []


def test_corpus_is_found():
    assert CORPUS, "no conformance files and no examples"
    assert any(p.parent.name == "examples" for p in corpus_files())
    assert any(p.parent.name == "placement" for p in corpus_files())


@pytest.mark.parametrize("name", sorted(DEEP_EXPRESSIONS))
def test_too_deep_expression_is_reported_as_p005(name: str):
    text, _ = decode_source(DEEP_EXPRESSIONS[name])
    found = analyze([SourceInput(uri="deep.osc", text=text)], OPTIONS).diagnostics
    assert "P005" in {d.code.code for d in found}, found
