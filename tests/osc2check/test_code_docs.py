"""Every code has a page with fixed sections; docs/checks.md is generated from them.

Regenerate docs/checks.md with ``OSC2CHECK_UPDATE_DOCS=1 pytest tests/osc2check/test_code_docs.py``
(or ``python -m osc2check.rules docs/checks.md``).
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import pytest

from osc2check import cli, codes, rules
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
            found_by_parser = (
                code.family == "P" and code is not codes.NESTING_TOO_DEEP
            ) or code is codes.NUMBER_OUT_OF_RANGE  # the parser reads numbers' values
            expected = {code.code} if section == "Example" and found_by_parser else set()
            if section == "Example" and f.name != rules.example_files(code)[0].name:
                expected = set()
            assert got == expected, f"{code} {section} {f.name}: {got}"


# Pages whose example the checker does not report yet (remove a code once it does).
PENDING: dict[str, str] = {}
# Options the example and the fix of a page are checked with; the page says so.
OPTIONS: dict[str, tuple[str, ...]] = {"S003": ("--memory-limit", "16")}


def check_example(code, section, tmp_path, monkeypatch, capsys) -> set[tuple[int, str, str]]:
    """Run the page's example through ``osc2check`` (JSON output): (line, code, letter).

    Information findings of other codes (such as L506, an actor the example does not
    place) are incidental to the page and left out; errors and warnings are not.
    """
    own = codes.lookup(str(code))
    files = rules.example_files(code, section)
    tmp_path.mkdir()
    for f in files:
        (tmp_path / f.name).write_bytes(f.data)
    monkeypatch.chdir(tmp_path)
    options = OPTIONS.get(own.code, ())
    status = cli.main([files[0].name, "--isolated", "--output-format", "json", *options])
    out, err = capsys.readouterr()
    assert status in (0, 1), err
    return {
        (f["location"]["start"]["line"], f["code"], f["severity"][0].upper())
        for f in json.loads(out)["findings"]
        if f["location"]["path"] == files[0].name
        and (f["severity"] != "info" or f["code"] == own.code)
    }


@pytest.mark.parametrize(
    "code",
    [
        pytest.param(c, marks=pytest.mark.xfail(reason=PENDING[c.code], strict=True))
        if c.code in PENDING
        else c
        for c in ALL
    ],
    ids=str,
)
def test_checker_reports_exactly_the_marked_findings(code, tmp_path, monkeypatch, capsys):
    example = rules.example_files(code)
    want = {
        (line, c, letter) for name, letter, line, c in markers(example) if name == example[0].name
    }
    assert check_example(code, "Example", tmp_path / "example", monkeypatch, capsys) == want
    assert check_example(code, "Fix", tmp_path / "fix", monkeypatch, capsys) == set()


@pytest.mark.parametrize("code", sorted(OPTIONS), ids=str)
def test_a_page_checked_with_options_says_so(code):
    sections = rules.page_sections(rules.page_text(code))
    said = f"`{' '.join(OPTIONS[code])}`"
    assert said in sections["Example"]
    assert OPTIONS[code][-1] in sections["Fix"]


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
