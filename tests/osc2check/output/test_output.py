"""Output formats: exact text for a hand-built list of diagnostics."""

from __future__ import annotations

import json

import pytest

from osc2check import codes, rules
from osc2check.codes import Severity
from osc2check.diagnostics import Diagnostic, Fix, Related, TextEdit
from osc2check.inputs import InputProblem
from osc2check.output import render, render_statistics, sarif, tool
from osc2check.output.full import excerpt
from osc2check.output.summary import summary_line
from osc2check.source import Span

A = """\
import osc.standard

scenario follow:
    hero: vehicle
    npc: vehicle
    do npc.drive(duration: 10s) with:
        position(distance: 5m, behind: hreo)
"""
B = """\
scenario wet:
\tenv: environment
\tdo env.rain(intensity: 100.0)
"""
TEXTS = {"a.osc": A, "b.osc": B}


def span(uri: str, line: int, col: int, end_line: int, end_col: int) -> Span:
    return Span(uri, line, col, end_line, end_col)


def diagnostics() -> list[Diagnostic]:
    hreo = span("a.osc", 7, 40, 7, 44)
    return [
        Diagnostic(
            codes.UNDEFINED_NAME,
            "undefined name `hreo`; did you mean `hero`?",
            hreo,
            Severity.ERROR,
            related=(Related(span("a.osc", 4, 5, 4, 9), "`hero` is declared here"),),
            fix=Fix("replace with `hero`", (TextEdit(hreo, "hero"),)),
        ),
        Diagnostic(
            codes.UNITLESS_PHYSICAL_LITERAL,
            "`100.0` has no unit; read as 100 m/s",
            span("b.osc", 3, 25, 3, 30),
            Severity.WARNING,
        ),
        Diagnostic(
            codes.TYPE_MISMATCH,
            "expected `time`, got `bool`",
            span("b.osc", 3, 5, 4, 1),
            Severity.ERROR,
            fix=Fix("use a duration", (), safe=False),
        ),
    ]


FULL = """\
a.osc:7:40: N101 [error] undefined name `hreo`; did you mean `hero`?
  a.osc:4:5: note: `hero` is declared here
  |
7 |         position(distance: 5m, behind: hreo)
  |                                        ^^^^
  = fix: replace with `hero`

b.osc:3:25: D805 [warning] `100.0` has no unit; read as 100 m/s
  |
3 | \tdo env.rain(intensity: 100.0)
  | \t                       ^^^^^

b.osc:3:5: T203 [error] expected `time`, got `bool`
  |
3 | \tdo env.rain(intensity: 100.0)
  | \t   ^^^^^^^^^^^^^^^^^^^^^^^^^^
  = fix (unsafe): use a duration

Found 2 errors, 1 warning in 2 files (3 files checked)
"""

CONCISE = """\
a.osc:7:40: N101 undefined name `hreo`; did you mean `hero`?
b.osc:3:25: D805 `100.0` has no unit; read as 100 m/s
b.osc:3:5: T203 expected `time`, got `bool`
Found 2 errors, 1 warning in 2 files (3 files checked)
"""

GITHUB = """\
::error file=a.osc,line=7,col=40,endLine=7,endColumn=44,title=N101::undefined name `hreo`; did you mean `hero`?
::warning file=b.osc,line=3,col=25,endLine=3,endColumn=30,title=D805::`100.0` has no unit; read as 100 m/s
::error file=b.osc,line=3,col=5,endLine=4,endColumn=1,title=T203::expected `time`, got `bool`
"""  # noqa: E501


def test_full_format_snapshot():
    assert render("full", diagnostics(), TEXTS, files_checked=3) == FULL


def test_full_format_without_findings_says_all_passed():
    assert render("full", [], TEXTS) == "All checks passed (2 files)\n"


def test_full_format_quiet_leaves_out_summary():
    out = render("full", diagnostics()[:1], TEXTS, quiet=True)
    assert out == FULL.split("\n\n")[0] + "\n"
    assert render("full", [], TEXTS, quiet=True) == ""


def test_full_format_without_source_text_prints_no_excerpt():
    out = render("full", diagnostics()[1:2], {}, files_checked=1)
    assert out == (
        "b.osc:3:25: D805 [warning] `100.0` has no unit; read as 100 m/s\n"
        "\n"
        "Found 1 warning in 1 file (1 file checked)\n"
    )


def test_concise_format_snapshot():
    assert render("concise", diagnostics(), TEXTS, files_checked=3) == CONCISE


def test_github_format_snapshot():
    assert render("github", diagnostics(), TEXTS) == GITHUB


def test_github_format_escapes_properties_and_data():
    d = Diagnostic(
        codes.SYNTAX_ERROR, "50% done\nnext", span("dir,x/a:b.osc", 1, 1, 1, 2), Severity.INFO
    )
    assert render("github", [d], {}) == (
        "::notice file=dir%2Cx/a%3Ab.osc,line=1,col=1,endLine=1,endColumn=2,"
        "title=P001::50%25 done%0Anext\n"
    )


def test_json_format_snapshot():
    out = render("json", diagnostics(), TEXTS)
    assert out.endswith("}\n")
    doc = json.loads(out)
    assert doc["version"] == 1
    assert doc["tool"] == {"name": "osc2check", "version": tool.version()}
    assert doc["findings"][0] == {
        "code": "N101",
        "name": "undefined-name",
        "severity": "error",
        "message": "undefined name `hreo`; did you mean `hero`?",
        "location": {
            "path": "a.osc",
            "start": {"line": 7, "column": 40},
            "end": {"line": 7, "column": 44},
        },
        "related": [
            {
                "path": "a.osc",
                "start": {"line": 4, "column": 5},
                "end": {"line": 4, "column": 9},
                "message": "`hero` is declared here",
            }
        ],
        "url": "docs/checks.md#n101-undefined-name",
        "fix": {
            "message": "replace with `hero`",
            "applicability": "safe",
            "edits": [
                {
                    "path": "a.osc",
                    "start": {"line": 7, "column": 40},
                    "end": {"line": 7, "column": 44},
                    "content": "hero",
                }
            ],
        },
    }
    assert [f["code"] for f in doc["findings"]] == ["N101", "D805", "T203"]
    assert doc["findings"][1]["fix"] is None
    assert doc["findings"][1]["related"] == []
    assert doc["findings"][2]["fix"]["applicability"] == "unsafe"


def test_json_format_has_no_summary_and_empty_findings():
    assert json.loads(render("json", [], TEXTS))["findings"] == []


def test_sarif_format_snapshot():
    log = json.loads(render("sarif", diagnostics(), TEXTS))
    assert log["$schema"] == sarif.SCHEMA
    assert log["version"] == "2.1.0"
    (run,) = log["runs"]
    assert run["columnKind"] == "unicodeCodePoints"
    driver = run["tool"]["driver"]
    assert driver["name"] == "osc2check"
    assert driver["version"] == tool.version()
    assert [r["id"] for r in driver["rules"]] == ["D805", "N101", "T203"]
    rule = driver["rules"][1]
    assert rule["name"] == "UndefinedName"
    assert rule["shortDescription"] == {"text": codes.UNDEFINED_NAME.summary}
    assert rule["defaultConfiguration"] == {"level": "error"}
    assert rule["help"]["markdown"] == rules.page_text("N101")
    assert rule["fullDescription"]["text"].startswith("A name that no visible declaration")
    first = run["results"][0]
    assert first == {
        "ruleId": "N101",
        "ruleIndex": 1,
        "level": "error",
        "message": {"text": "undefined name `hreo`; did you mean `hero`?"},
        "locations": [
            {
                "physicalLocation": {
                    "artifactLocation": {"uri": "a.osc"},
                    "region": {"startLine": 7, "startColumn": 40, "endLine": 7, "endColumn": 44},
                }
            }
        ],
        "relatedLocations": [
            {
                "id": 1,
                "message": {"text": "`hero` is declared here"},
                "physicalLocation": {
                    "artifactLocation": {"uri": "a.osc"},
                    "region": {"startLine": 4, "startColumn": 5, "endLine": 4, "endColumn": 9},
                },
            }
        ],
        "partialFingerprints": {"osc2check/v1": sarif.fingerprint(diagnostics()[0])},
    }
    assert [r["level"] for r in run["results"]] == ["error", "warning", "error"]
    assert "relatedLocations" not in run["results"][1]


def test_sarif_fingerprints_are_stable_and_distinct_for_repeats():
    d = diagnostics()[1]
    log = json.loads(render("sarif", [d, d], {}))
    prints = [r["partialFingerprints"]["osc2check/v1"] for r in log["runs"][0]["results"]]
    assert prints[0] == sarif.fingerprint(d) == sarif.fingerprint(d)
    assert prints[0] != prints[1]
    moved = Diagnostic(d.code, d.message, span("b.osc", 9, 1, 9, 2), d.severity)
    assert sarif.fingerprint(moved) == sarif.fingerprint(d)  # line moves keep the alert


def test_sarif_uri_is_percent_encoded():
    d = Diagnostic(codes.SYNTAX_ERROR, "x", span("my dir/a.osc", 1, 1, 1, 2), Severity.ERROR)
    log = json.loads(render("sarif", [d], {}))
    location = log["runs"][0]["results"][0]["locations"][0]["physicalLocation"]
    assert location["artifactLocation"]["uri"] == "my%20dir/a.osc"


PROBLEMS = [
    InputProblem("gone.osc", "cannot read: no such file or directory"),
    InputProblem("d/pipe.osc", "skipped: not a regular file (a named pipe)", Severity.INFO),
]


def test_json_format_puts_scenarios_first_and_lists_paths_not_checked():
    doc = json.loads(render("json", diagnostics()[:1], TEXTS, problems=PROBLEMS))
    assert list(doc) == ["scenarios", "version", "tool", "findings", "errors", "skipped"]
    assert doc["errors"] == [{"path": "gone.osc", "message": PROBLEMS[0].message}]
    assert doc["skipped"] == [{"path": "d/pipe.osc", "message": PROBLEMS[1].message}]
    assert json.loads(render("json", [], TEXTS))["errors"] == []


def test_sarif_invocation_says_whether_every_path_was_read():
    (run,) = json.loads(render("sarif", [], TEXTS, problems=PROBLEMS))["runs"]
    (invocation,) = run["invocations"]
    assert invocation["executionSuccessful"] is False
    notes = invocation["toolExecutionNotifications"]
    assert [(n["level"], n["message"]["text"]) for n in notes] == [
        ("error", PROBLEMS[0].message),
        ("note", PROBLEMS[1].message),
    ]
    location = notes[1]["locations"][0]["physicalLocation"]["artifactLocation"]
    assert location == {"uri": "d/pipe.osc"}
    (clean,) = json.loads(render("sarif", [], TEXTS, problems=PROBLEMS[1:]))["runs"]
    assert clean["invocations"][0]["executionSuccessful"] is True


def test_github_format_annotates_paths_not_checked_first():
    out = render("github", diagnostics()[1:2], TEXTS, problems=PROBLEMS)
    assert out.splitlines() == [
        "::error file=gone.osc,title=osc2check::cannot read: no such file or directory",
        "::notice file=d/pipe.osc,title=osc2check::skipped: not a regular file (a named pipe)",
        "::warning file=b.osc,line=3,col=25,endLine=3,endColumn=30,title=D805::"
        "`100.0` has no unit; read as 100 m/s",
    ]


def test_human_formats_count_files_that_could_not_be_read():
    assert render("concise", [], TEXTS, files_checked=2, problems=PROBLEMS) == (
        "No findings in 2 files; 1 file could not be read\n"
    )
    assert render("concise", [], TEXTS, files_checked=2, problems=PROBLEMS[1:]) == (
        "All checks passed (2 files)\n"
    )
    assert render("concise", [], TEXTS, quiet=True, problems=PROBLEMS) == ""
    assert render_statistics(diagnostics()[:1], files_checked=1, problems=PROBLEMS) == (
        "1  N101  undefined-name\n"
        "Found 1 error in 1 file (1 file checked); 1 file could not be read\n"
    )


def test_render_rejects_unknown_format():
    with pytest.raises(ValueError, match="xml"):
        render("xml", [], {})


@pytest.mark.parametrize(
    ("severities", "files", "checked", "expected"),
    [
        ([], 0, 1, "All checks passed (1 file)"),
        ([Severity.ERROR], 1, 1, "Found 1 error in 1 file (1 file checked)"),
        (
            [Severity.INFO, Severity.WARNING, Severity.ERROR, Severity.ERROR],
            2,
            5,
            "Found 2 errors, 1 warning, 1 info in 2 files (5 files checked)",
        ),
        ([Severity.WARNING] * 2, 1, 2, "Found 2 warnings in 1 file (2 files checked)"),
    ],
)
def test_summary_line(severities, files, checked, expected):
    ds = [
        Diagnostic(codes.SYNTAX_ERROR, "m", span(f"f{i % max(files, 1)}.osc", 1, 1, 1, 2), s)
        for i, s in enumerate(severities)
    ]
    assert summary_line(ds, checked) == expected


def test_summary_line_with_files_that_could_not_be_read_never_says_passed():
    error = Diagnostic(codes.SYNTAX_ERROR, "m", span("a.osc", 1, 1, 1, 2), Severity.ERROR)
    assert summary_line([], 0, 1) == "No findings in 0 files; 1 file could not be read"
    assert summary_line([], 3, 2) == "No findings in 3 files; 2 files could not be read"
    assert summary_line([error], 3, 1) == (
        "Found 1 error in 1 file (3 files checked); 1 file could not be read"
    )


def test_statistics_counts_per_code_most_frequent_first():
    ds = diagnostics() + [diagnostics()[1]]
    assert render_statistics(ds, files_checked=2) == (
        "2  D805  unitless-physical-literal\n"
        "1  N101  undefined-name\n"
        "1  T203  type-mismatch\n"
        "Found 2 errors, 2 warnings in 2 files (2 files checked)\n"
    )
    assert render_statistics([], files_checked=1, quiet=True) == ""


def test_excerpt_marks_at_least_one_column_at_end_of_line():
    text = "scenario a:\n    x: int\n"
    assert excerpt(span("a.osc", 1, 12, 1, 12), text) == [
        "  |",
        "1 | scenario a:",
        "  |            ^",
    ]
    assert excerpt(span("a.osc", 9, 1, 9, 2), text) == []
