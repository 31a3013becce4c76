"""Every code has a page with fixed sections; docs/checks.md is generated from them.

Regenerate docs/checks.md with ``OSC2CHECK_UPDATE_DOCS=1 pytest tests/osc2check/test_code_docs.py``
(or ``python -m osc2check.rules docs/checks.md``).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from osc2check import codes, rules
from osc2check.source import decode_source
from osc2check.syntax import parse

ROOT = Path(__file__).resolve().parents[2]
CHECKS_MD = ROOT / "docs" / "checks.md"
ALL = sorted(codes.ALL, key=lambda c: c.code)
MARKER = re.compile(r"#\s*([EWI])(?::\d+)?:\s*([A-Z]\d{3})\b")


def markers(files: list[rules.ExampleFile]) -> list[tuple[str, str, int, str]]:
    """(file, letter, line, code) for each ``# E: CODE`` marker of the example."""
    found = []
    for f in files:
        for number, line in enumerate(decode_source(f.data)[0].splitlines(), start=1):
            for m in MARKER.finditer(line):
                found.append((f.name, m.group(1), number, m.group(2)))
    return found


@pytest.mark.parametrize("code", ALL, ids=str)
def test_page_has_title_summary_and_every_section_in_order(code):
    text = rules.page_text(code)
    assert text.splitlines()[0] == f"# {code.code} {code.slug}"
    sections = rules.page_sections(text)
    assert list(sections)[:2] == ["title", "summary"]
    assert list(sections)[2:] == list(rules.SECTIONS)
    assert all(sections[name].strip() for name in rules.SECTIONS), code
    assert sections["summary"].rstrip(".").lower() == code.summary.lower()
    assert sections["Since"].startswith(code.since)


@pytest.mark.parametrize("code", ALL, ids=str)
def test_options_section_says_how_to_select_ignore_and_suppress(code):
    options = rules.page_sections(rules.page_text(code))["Options"]
    assert f"--ignore {code.code}" in options
    assert f"file-ignore[{code.code}]" in options
    if code.family == "D":
        assert "--strict" in options
    if code.family != "S":
        assert f"ignore[{code.code}]" in options and f"noqa: {code.code}" in options


@pytest.mark.parametrize("code", ALL, ids=str)
def test_example_marks_its_own_code_and_the_fix_marks_nothing(code):
    example = rules.example_files(code, "Example")
    fix = rules.example_files(code, "Fix")
    assert example and fix
    found = markers(example)
    assert found, f"{code}: the example shows no `# {code.severity.letter}: {code}` marker"
    assert {(letter, c) for _, letter, _, c in found} == {(code.severity.letter, code.code)}
    assert markers(fix) == []
    assert [f.name for f in example] == [f.name for f in fix]


@pytest.mark.parametrize("code", ALL, ids=str)
def test_examples_parse_with_only_their_own_syntax_code(code):
    """The parser exists: an example has no syntax problem but its own; a fix has none."""
    for section in ("Example", "Fix"):
        for f in rules.example_files(code, section):
            text, problem = decode_source(f.data)
            got = {d.code.code for d in parse(text, f.name).diagnostics}
            if problem is not None:
                got.add(codes.INVALID_ENCODING.code)
            expected = {code.code} if section == "Example" and code.family == "P" else set()
            if section == "Example" and f.name != rules.example_files(code)[0].name:
                expected = set()
            assert got == expected, f"{code} {section} {f.name}: {got}"


def test_p004_example_is_not_utf8_and_its_fix_is():
    (example,) = rules.example_files("P004")
    (fix,) = rules.example_files("P004", "Fix")
    assert decode_source(example.data)[1] is not None
    assert decode_source(fix.data)[1] is None


def test_multi_file_example_names_its_files():
    assert [f.name for f in rules.example_files("import-cycle")] == ["main.osc", "lanes.osc"]
    assert [f.name for f in rules.example_files("N101")] == [rules.DEFAULT_EXAMPLE_NAME]


def test_page_lookup_by_slug_and_unknown_code():
    assert rules.page_text("undefined-name") == rules.page_text(codes.UNDEFINED_NAME)
    with pytest.raises(KeyError):
        rules.page_text("X999")


def test_no_page_without_a_code():
    pages = {p.stem for p in (ROOT / "osc2check" / "code_docs").glob("*.md")}
    assert pages == {c.code for c in codes.ALL}


def test_doc_url_points_at_the_heading_anchor_in_checks_md():
    assert rules.doc_url(codes.UNDEFINED_NAME) == "docs/checks.md#n101-undefined-name"
    text = rules.render_checks_md()
    for code in codes.ALL:
        assert f"\n### {code.code} {code.slug}\n" in text
        assert f"(#{rules.anchor(code)})" in text


def test_checks_md_is_up_to_date():
    expected = rules.render_checks_md()
    if os.environ.get("OSC2CHECK_UPDATE_DOCS"):
        CHECKS_MD.write_text(expected, encoding="utf-8", newline="\n")
    assert CHECKS_MD.read_text(encoding="utf-8") == expected, (
        "docs/checks.md is stale: run OSC2CHECK_UPDATE_DOCS=1 pytest "
        "tests/osc2check/test_code_docs.py"
    )
