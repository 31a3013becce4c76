"""The syntax-first preview: the touched declarations parsed again, the rest of the
last analysis's findings moved to where their text now is."""

from __future__ import annotations

import sys

import pytest

from osc2check.syntax import parse
from osc2check.syntax.incremental import Edit, reparse
from osc2lsp.session.preview import preview
from osc2lsp.text import LineIndex, TextMap
from tests.osc2lsp.lsp_helpers import REPO, snapshot

sys.path.insert(0, str(REPO / "bench"))
from generate import generate  # noqa: E402

TEXT = """import osc.standard

scenario first:
    hero: vehicle
    x: int = 1

# a comment between declarations
scenario second:
    car: vehcle
    y: int = 2

scenario third:
    z: int = 3
"""


def _findings(found) -> list[tuple[str, int, int]]:
    return sorted((d.code.code, d.span.line, d.span.column) for d in found)


def _edit(old: str, new: str) -> Edit:
    change = TextMap(old, new)
    return Edit(change.prefix, change.old_end, change.new_end)


def test_a_new_syntax_error_comes_with_the_other_findings_moved():
    snap = snapshot(TEXT)
    assert _findings(snap.diagnostics) == [("N101", 9, 10)]  # `vehcle`
    new = TEXT.replace("x: int = 1\n", "x: int = (1 +\n\n\n")  # two lines more, a syntax error
    found = preview(snap, LineIndex(new))
    assert found is not None
    assert _findings(found) == _findings(snapshot(new).diagnostics)
    assert ("N101", 11, 10) in _findings(found)  # moved down two lines


def test_a_fixed_syntax_error_goes_and_an_edited_name_waits_for_the_analysis():
    broken = TEXT.replace("z: int = 3", "z: int = (3")
    snap = snapshot(broken)
    assert any(code.startswith("P") for code, *_ in _findings(snap.diagnostics))
    found = preview(snap, LineIndex(TEXT))
    assert found is not None and _findings(found) == [("N101", 9, 10)]
    renamed = TEXT.replace("vehcle", "vehicl")  # still wrong, but the analysis says so
    assert preview(snapshot(TEXT), LineIndex(renamed)) == []


def test_suppressions_and_the_configuration_apply_to_new_syntax_findings():
    snap = snapshot(TEXT)
    unclosed = TEXT.replace("z: int = 3", "z: int = (3")
    codes = sorted({d.code.code for d in snapshot(unclosed).diagnostics if d.code.family == "P"})
    new = unclosed.replace("(3", f"(3  # osc2check: ignore[{', '.join(codes)}]")
    found = preview(snap, LineIndex(new))
    assert found is not None
    assert _findings(found) == _findings(snapshot(new).diagnostics) == [("N101", 9, 10)]


def test_a_triple_quoted_string_makes_the_preview_decline():
    snap = snapshot(TEXT)
    assert preview(snap, LineIndex(TEXT.replace("# a comment", '"""'))) is None


@pytest.mark.parametrize(
    "old, new",
    [
        ("x: int = 1", "x: int = (1"),
        ("x: int = 1", "x: int = 1)"),
        ("    y: int = 2\n", "  y: int = 2\n"),  # inconsistent dedent
        ("scenario third:", "scenario third"),
        ("scenario second:\n", ""),  # two declarations become one
        ("import osc.standard\n", "import osc.standard\n    oops\n"),
    ],
)
def test_the_region_parse_reports_what_a_whole_parse_reports_there(old, new):
    text = TEXT.replace(old, new, 1)
    previous = parse(TEXT, "/tmp/x.osc")
    region = reparse(previous, text, _edit(TEXT, text))
    assert region is not None
    whole = parse(text, "/tmp/x.osc")
    inside = [d for d in whole.diagnostics if region.start <= d.span.start < region.end]
    assert sorted(map(repr, region.diagnostics)) == sorted(map(repr, inside))


def test_a_region_is_a_few_declarations_of_a_large_file():
    text = generate(2000)
    previous = parse(text, "/tmp/x.osc")
    at = text.index("keep(", len(text) // 2)
    new = text[:at] + "keep((" + text[at + 5 :]
    region = reparse(previous, new, _edit(text, new))
    assert region is not None
    assert region.end - region.start < len(text) // 50
    assert [d.code.code for d in region.diagnostics] == [
        d.code.code for d in parse(new, "/tmp/x.osc").diagnostics
    ]
