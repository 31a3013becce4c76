"""The incremental re-parse: a spliced parse is the whole parse of the new text.

``splice`` re-parses the segments an edit touched and moves the rest; whatever
edits come, the result is compared with ``parse`` of the final text node for
node (types, fields, every span with its offsets), finding for finding, comment
for comment, and the analysis of a spliced parse with the analysis of the text.
Edits are chained (each splice starts from the last splice) as the language
server chains them while the user types.
"""

from __future__ import annotations

import sys
from dataclasses import fields
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.syntax import ParseResult, ast, parse
from osc2check.syntax.incremental import Edit, reparse, splice
from osc2check.syntax.walk import walk

REPO = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(REPO / "bench"))
from generate import generate  # noqa: E402

URI = "/tmp/osc2check-tests/incremental.osc"

BASE = (
    "# a file of several declarations\n"
    "import osc.standard\n"
    "\n"
    "enum colour: [red, green,\n"
    "    blue]\n"
    "struct pose:\n"
    "    x: length = 1m\n"
    "    y: length with:\n"
    "        keep(it > 0m)  # osc2check: ignore[T202]\n"
    "\r\n"
    "actor robot inherits vehicle:\n"
    "    top: speed = 10kph\r"
    "scenario drive_on:\n"
    "    hero: vehicle\n"
    "    gap: length = 5m \\\n"
    "        * 2\n"
    "    do serial:\n"
    "        hero.drive() with:\n"
    "            speed(20kph, at: start)\n"
    "        wait elapsed(2s)\n"
    "global limit: speed = 50kph\n"
)

PIECES = [
    "\n", "\r\n", "\r", " ", "    ", "\t", "\f", "\u2028", "x", "é", ":", "(", ")", "[", "]",
    ",", "#", "\\", '"', "'", "@", "scenario ", "struct t:\n", "    a: int\n", "keep(",
    "hero.", "do serial:\n", "\n        wait elapsed(1s)\n", "import osc.standard\n",
]  # fmt: skip


def nodes(result: ParseResult) -> list[tuple]:
    """Every node of the tree with its type, span and plain fields, in order."""
    found = []
    for node in walk(result.ast):
        plain = tuple(
            (f.name, getattr(node, f.name))
            for f in fields(node)
            if not isinstance(getattr(node, f.name), (ast.Node, tuple))
        )
        found.append((type(node).__name__, plain))
    return found


def same_parse(got: ParseResult, want: ParseResult) -> None:
    assert got.text == want.text
    assert nodes(got) == nodes(want)
    assert got.diagnostics == want.diagnostics
    assert got.comments == want.comments
    assert got.error_lines == want.error_lines
    assert [(s.start, s.line, len(s.declarations)) for s in got.segments] == [
        (s.start, s.line, len(s.declarations)) for s in want.segments
    ]


@st.composite
def edit_chains(draw, base: str, max_edits: int = 8) -> list[tuple[int, int, str]]:
    text, chain = base, []
    for _ in range(draw(st.integers(1, max_edits))):
        start = draw(st.integers(0, len(text)))
        end = draw(st.integers(start, min(len(text), start + 16)))
        inserted = "".join(draw(st.lists(st.sampled_from(PIECES), max_size=3)))
        chain.append((start, end, inserted))
        text = text[:start] + inserted + text[end:]
    return chain


def _edit(old: str, start: int, end: int, inserted: str) -> tuple[str, Edit]:
    new = old[:start] + inserted + old[end:]
    return new, Edit(start, end, start + len(inserted))


@pytest.mark.slow
@settings(max_examples=300, deadline=None)
@given(edit_chains(BASE))
def test_a_chain_of_spliced_parses_is_the_whole_parse_of_each_text(chain):
    text, previous = BASE, parse(BASE, URI)
    for start, end, inserted in chain:
        text, edit = _edit(text, start, end, inserted)
        whole = parse(text, URI)
        spliced = splice(previous, text, edit)
        if spliced is not None:
            same_parse(spliced, whole)
        previous = spliced if spliced is not None else whole


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(edit_chains(BASE, max_edits=4))
def test_the_analysis_of_a_spliced_parse_is_the_analysis_of_the_text(chain):
    options = AnalysisOptions(verify=False)
    text = BASE
    previous = analyze([SourceInput(URI, text)], options).parses[URI]
    for start, end, inserted in chain:
        text, edit = _edit(text, start, end, inserted)
        spliced = splice(previous, text, edit)
        from_splice = analyze([SourceInput(URI, text, parse=spliced)], options)
        assert from_splice.diagnostics == analyze([SourceInput(URI, text)], options).diagnostics
        if spliced is not None:
            assert from_splice.parses[URI] is spliced  # the given parse was used
        previous = from_splice.parses[URI]


@pytest.mark.slow
def test_typing_in_a_large_file_re_parses_one_segment_and_moves_the_rest():
    text = generate(2000)
    previous = parse(text, URI)
    at = text.index("keep(top_", len(text) // 2) + len("keep(top")
    for typed in ("x", "xy", "xyz"):
        new, edit = _edit(text, at, at + len(typed) - 1, typed)
        region = reparse(previous, new, edit)
        assert region is not None and region.after - region.first == 1
        spliced = splice(previous, new, edit)
        assert spliced is not None
        same_parse(spliced, parse(new, URI))
        text, previous = new, spliced
    # a new line, then a new declaration at the end
    at = text.index("\n", at) + 1
    for inserted in ("    keep(top_1 > 0kph)\n", "scenario added:\n    x: int = 1\n"):
        new, edit = _edit(text, at, at, inserted)
        spliced = splice(previous, new, edit)
        assert spliced is not None
        same_parse(spliced, parse(new, URI))
        text, previous = new, spliced


def test_the_unchanged_segments_before_the_edit_are_reused_as_they_are():
    previous = parse(BASE, URI)
    at = BASE.index("wait elapsed")
    new, edit = _edit(BASE, at, at, "x")
    spliced = splice(previous, new, edit)
    assert spliced is not None
    kept = [s for s in previous.segments if s.start < at]
    assert kept and all(a is b for a, b in zip(spliced.segments, kept[:-1], strict=False))


def test_edits_that_reach_past_their_segments_are_declined():
    cases = [
        (BASE, "# a file", '"""a file'),  # a triple-quoted string may run to the end
        (BASE, "import osc.standard\n", "    import osc.standard\n"),  # the outermost level moves
        # the `)` at column 1 closes the bracket the edit opened: it no longer begins a line
        ("global a: int = 1\n)\nglobal b: int = 2\n", "= 1", "= (1"),
        # a backslash continues the line into the next declaration
        ("global a: int = 1\nglobal b: int = 2\n", "= 1", "= 1 \\"),
    ]
    for base, old, new in cases:
        previous = parse(base, URI)
        text = base.replace(old, new, 1)
        start = base.index(old)
        assert splice(previous, text, Edit(start, start + len(old), start + len(new))) is None
        assert previous.segments and parse(text, URI)  # the caller parses the whole text


def test_an_error_in_one_top_level_line_does_not_hide_the_next_lines_error():
    """Each outermost line is parsed alone: one broken declaration's recovery neither
    swallows nor hides the next one (the parser's rule: one error per statement)."""
    found = parse("a # trailing\nb\n", URI)
    assert [(d.span.line, d.message) for d in found.diagnostics] == [
        (1, "unexpected `a`"),
        (2, "unexpected `b`"),
    ]
    found = parse("struct a\nnonsense here\nstruct b\n", URI)
    assert [d.name.name.text for d in found.ast.declarations] == ["a", "b"]
    assert [d.span.line for d in found.diagnostics] == [2]
