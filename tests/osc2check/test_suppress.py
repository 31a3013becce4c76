"""Suppression comments: matching, unused (S001) and unknown (S002) suppressions."""

from __future__ import annotations

from osc2check import codes
from osc2check.diagnostics import Diagnostic, Related
from osc2check.source import Span
from osc2check.suppress import apply_suppressions, find_suppressions
from osc2check.syntax import parse

URI = "s.osc"


def at(line: int, column: int = 9, code: codes.Code = codes.UNDEFINED_NAME, uri=URI):
    return Diagnostic(code, "m", Span(uri, line, column, line, column + 4), code.severity)


def run(text: str, diagnostics: list[Diagnostic]) -> list[tuple[str, int, int, str]]:
    """Suppressions from the real lexer's comments, applied; (code, line, column, message)."""
    comments = parse(text, URI).comment_spans()
    kept = apply_suppressions(diagnostics, find_suppressions(URI, comments, text))
    return [(d.code.code, d.span.line, d.span.column, d.message) for d in kept]


def codes_of(result) -> list[tuple[str, int]]:
    return [(code, line) for code, line, _, _ in result]


SCENARIO = """\
scenario s:
    hero: vehicle
    do serial:
        hreo.drive(){trailing}
        hero.drive()
"""


def test_trailing_code_suppresses_its_line_only():
    text = SCENARIO.format(trailing="  # osc2check: ignore[N101]")
    assert run(text, [at(4), at(5)]) == [("N101", 5, 9, "m")]


def test_slug_case_and_noqa_are_accepted():
    for comment in (
        "# osc2check: ignore[undefined-name]",
        "# OSC2CHECK: IGNORE[n101]",
        "# noqa: N101",
        "# noqa:N101,T202",
        "# why: typo kept on purpose; osc2check: ignore[N101]",
    ):
        text = SCENARIO.format(trailing="  " + comment)
        result = run(text, [at(4)])
        assert [c for c, *_ in result if c != "S001"] == [], comment


def test_bare_ignore_and_bare_noqa_suppress_every_code():
    for comment in ("# osc2check: ignore", "# noqa"):
        text = SCENARIO.format(trailing="  " + comment)
        kept = run(text, [at(4), at(4, 20, codes.MISSING_UNIT)])
        assert kept == [], comment


def test_comment_alone_on_the_line_above_covers_the_next_line():
    text = """\
scenario s:
    do serial:
        # osc2check: ignore[N101]
        # a second comment line in between is skipped
        hreo.drive()
        hreo.drive()
"""
    assert codes_of(run(text, [at(5), at(6)])) == [("N101", 6)]


def test_trailing_comment_does_not_cover_the_next_line():
    text = SCENARIO.format(trailing="  # osc2check: ignore[N101]")
    assert codes_of(run(text, [at(5)])) == [("S001", 4), ("N101", 5)]


def test_unused_suppression_reports_each_unused_code_at_the_code():
    text = SCENARIO.format(trailing="  # osc2check: ignore[N101, T202]")
    result = run(text, [at(4)])
    column = text.splitlines()[3].index("T202") + 1
    assert result == [("S001", 4, column, "unused suppression of `T202`")]


def test_unused_bare_suppression_is_reported_at_the_comment():
    text = SCENARIO.format(trailing="  # osc2check: ignore")
    column = text.splitlines()[3].index("#") + 1
    assert run(text, []) == [("S001", 4, column, "unused suppression comment")]


def test_unused_whole_comment_has_a_fix_that_removes_it():
    text = SCENARIO.format(trailing="  # osc2check: ignore[T202]")
    suppressions = find_suppressions(URI, parse(text, URI).comment_spans(), text)
    (s001,) = apply_suppressions([], suppressions)
    assert s001.fix is not None
    (edit,) = s001.fix.edits
    assert edit.new_text == ""
    assert text[edit.span.start : edit.span.end] == "# osc2check: ignore[T202]"


def test_unknown_code_is_s002_with_a_suggestion_and_no_s001():
    text = SCENARIO.format(trailing="  # osc2check: ignore[undefined-nmae]")
    comments = parse(text, URI).comment_spans()
    kept = apply_suppressions([at(4)], find_suppressions(URI, comments, text))
    assert [(d.code.code, d.span.line) for d in kept] == [("N101", 4), ("S002", 4)]
    s002 = kept[1]
    assert s002.message == "unknown code `undefined-nmae` in suppression comment"
    assert text[s002.span.start : s002.span.end] == "undefined-nmae"
    assert s002.related[0].message == "did you mean `undefined-name`?"


def test_file_ignore_suppresses_everywhere_in_the_file():
    text = "# osc2check: file-ignore[N101, missing-unit]\n" + SCENARIO.format(trailing="")
    kept = run(text, [at(5), at(6), at(6, 3, codes.MISSING_UNIT), at(6, 3, codes.FLOAT_TO_INT)])
    assert codes_of(kept) == [("T204", 6)]


def test_unused_file_ignore_is_reported():
    text = "# osc2check: file-ignore[D805]\n" + SCENARIO.format(trailing="")
    assert codes_of(run(text, [])) == [("S001", 1)]


def test_s001_and_s002_are_not_suppressed_by_line_comments():
    text = SCENARIO.format(trailing="  # osc2check: ignore[T202, S001]  # noqa: S002")
    got = codes_of(run(text, []))
    assert ("S001", 4) in got
    text = SCENARIO.format(trailing="  # osc2check: ignore[C999]  # osc2check: ignore[S002]")
    assert ("S002", 4) in codes_of(run(text, []))


def test_s001_and_s002_are_suppressed_by_file_ignore():
    text = "# osc2check: file-ignore[S001, unknown-suppression-code]\n" + SCENARIO.format(
        trailing="  # osc2check: ignore[T202, C999]"
    )
    assert run(text, []) == []


def test_only_the_primary_location_counts():
    text = SCENARIO.format(trailing="") + "        hero.drive()  # osc2check: ignore[N102]\n"
    d = Diagnostic(
        codes.DUPLICATE_DEFINITION,
        "m",
        Span(URI, 2, 5, 2, 9),
        codes.DUPLICATE_DEFINITION.severity,
        related=(Related(Span(URI, 6, 9, 6, 13), "first"),),
    )
    assert codes_of(run(text, [d])) == [("N102", 2), ("S001", 6)]


def test_a_multi_line_finding_is_matched_at_its_first_line():
    text = SCENARIO.format(trailing="  # osc2check: ignore[N101]")
    d = Diagnostic(codes.UNDEFINED_NAME, "m", Span(URI, 4, 9, 5, 3), codes.Severity.ERROR)
    assert run(text, [d]) == []


def test_suppressions_of_another_file_do_not_apply():
    text = SCENARIO.format(trailing="  # osc2check: ignore[N101]")
    kept = run(text, [at(4, uri="other.osc")])
    assert codes_of(kept) == [("N101", 4), ("S001", 4)]


def test_unclosed_bracket_and_other_comments_are_not_suppressions():
    for comment in (
        "# osc2check: ignore[N101",
        "# osc2check: ignored",
        "# just a note",
        "# noqa-ish",
        "# noqable",
    ):
        text = SCENARIO.format(trailing="  " + comment)
        assert codes_of(run(text, [at(4)])) == [("N101", 4)], comment


def test_without_text_a_comment_in_column_one_covers_the_next_line():
    comment = Span(URI, 3, 1, 3, 26)
    (s,) = find_suppressions(URI, [(comment, "# osc2check: ignore[N101]")])
    assert s.lines == (4,)
    indented = Span(URI, 3, 9, 3, 34)
    (s,) = find_suppressions(URI, [(indented, "# osc2check: ignore[N101]")])
    assert s.lines == (3, 4)


def test_result_is_sorted():
    text = SCENARIO.format(trailing="  # osc2check: ignore[T202]")
    kept = run(text, [at(5), at(2)])
    assert codes_of(kept) == [("N101", 2), ("S001", 4), ("N101", 5)]


def test_lines_are_the_lexers_after_a_form_feed_or_a_line_separator():
    """Only CR LF, LF and CR end a line (as in the lexer and LSP): the form feed, the
    vertical tab and U+2028 in a comment before it do not move a suppression's lines."""
    for separator in ("\f", "\x0b", "\x1c", "\x85", "\u2028", "\u2029"):
        text = (
            "scenario s:\n"
            f"    hero: vehicle  # a{separator}b\n"
            "    do serial:\n"
            "        # osc2check: ignore[N101]\n"
            "        hreo.drive()\n"
        )
        assert run(text, [at(5)]) == [], repr(separator)
        trailing = text.replace("        # osc2check: ignore[N101]\n", "").replace(
            "hreo.drive()", "hreo.drive()  # osc2check: ignore[N101]"
        )
        assert run(trailing, [at(4)]) == [], repr(separator)


def test_a_form_feed_before_a_comment_is_blank_as_in_the_lexer():
    text = SCENARIO.format(trailing="").replace(
        "        hreo.drive()", "\f       # osc2check: ignore[N101]\n        hreo.drive()"
    )
    assert run(text, [at(5)]) == []
