"""The formatter: spacing rules, idempotence, tokens and comments kept, refusal."""

from __future__ import annotations

import glob
import sys

import pytest

from osc2check.syntax.lexer import tokenize
from osc2lsp.convert import to_lsp_format_edits
from osc2lsp.features.formatting import (
    FormatOptions,
    format_in_own_style,
    format_text,
    indent_style,
)
from osc2lsp.text import LineIndex
from tests.osc2lsp.lsp_helpers import REPO, seed_path

sys.path.insert(0, str(REPO / "bench"))
from generate import generate  # noqa: E402

CORPUS = sorted(
    glob.glob(str(REPO / "examples" / "*.osc")) + glob.glob(str(REPO / "stdlib" / "*.osc"))
)


@pytest.mark.parametrize(
    "ugly, pretty",
    [
        ("scenario  s :\n  x : int=1+2 # one\n", "scenario s:\n    x: int = 1 + 2  # one\n"),
        (
            "scenario s:\n keep( x>=-3m and y in [ 1m .. 2m ] )\n",
            "scenario s:\n    keep(x >= -3m and y in [1m..2m])\n",
        ),
        (
            "scenario s:\n    do serial:\n          wait @ e\n          hero . drive ( )\n",
            "scenario s:\n    do serial:\n        wait @e\n        hero.drive()\n",
        ),
        ("enum c:[ red,green ]\n", "enum c: [red, green]\n"),
        ("type t is SI (m : 1 , s : - 1)\n", "type t is SI(m: 1, s: -1)\n"),
        (
            "struct p:\n  def f(x:int)->int is expression x*2\n",
            "struct p:\n    def f(x: int) -> int is expression x * 2\n",
        ),
        ("export ns :: * , *\n", "export ns::*, *\n"),
        ("scenario s:\n    x: c = c ! red\n", "scenario s:\n    x: c = c!red\n"),
        ("\n\n\nscenario s:\n\n\n\n\n    x: int\n\n\n", "scenario s:\n\n\n    x: int\n"),
        (
            "scenario s:\n    x: int = a[ 0 ] - (b) * - 2\n",
            "scenario s:\n    x: int = a[0] - (b) * -2\n",
        ),
    ],
)
def test_formatting_rules(ugly, pretty):
    assert format_text(ugly) == pretty


def test_formatting_indents_comments_like_the_next_statement():
    text = "scenario s:\n  # about x\n  x: int\n        # trailing block comment\n  y: int\n"
    assert format_text(text) == (
        "scenario s:\n    # about x\n    x: int\n    # trailing block comment\n    y: int\n"
    )


def test_formatting_moves_continuation_lines_with_their_statement():
    text = "scenario s:\n  x: int = f(1,\n             2)\n"
    assert format_text(text) == "scenario s:\n    x: int = f(1,\n               2)\n"


def test_formatting_with_tabs_and_other_widths():
    text = "scenario s:\n    x: int\n"
    assert format_text(text, FormatOptions(use_tabs=True)) == "scenario s:\n\tx: int\n"
    assert format_text(text, FormatOptions(indent_width=2)) == "scenario s:\n  x: int\n"


def test_formatting_refuses_a_file_with_syntax_errors():
    assert format_text("scenario s:\n    x: int = (1 +\n") is None


@pytest.mark.parametrize("path", CORPUS + [str(seed_path())])
def test_formatting_is_idempotent_and_keeps_tokens_and_comments(path):
    text = open(path, encoding="utf-8", errors="replace").read()
    once = format_text(text)
    assert once is not None
    assert format_text(once) == once
    assert [(t.type, t.value) for t in tokenize(once).tokens if t.type != "NEWLINE"] == [
        (t.type, t.value) for t in tokenize(text).tokens if t.type != "NEWLINE"
    ]
    assert [c.text.rstrip() for c in tokenize(once).comments] == [
        c.text.rstrip() for c in tokenize(text).comments
    ]


def test_formatting_generated_files_is_idempotent():
    text = generate(400)
    once = format_text(text)
    assert once is not None and format_text(once) == once


@pytest.mark.parametrize(
    "text",
    [
        "# a\fb\nscenario s:\n        x: int\n",  # form feed: no line break for LSP
        "# a\x0bb\u2028c\x85d\nscenario s:\r\n        x: int",
        "scenario s:\r        x: int\r  y: int\r",
    ],
)
def test_format_edits_count_lines_as_the_client_does(text):
    lines = LineIndex(text)
    edits = to_lsp_format_edits(text, format_text(text) or "", lines)
    result = text
    for edit in reversed(edits):  # line edits come in order and do not overlap
        start = lines.offset(edit.range.start.line, edit.range.start.character)
        end = lines.offset(edit.range.end.line, edit.range.end.character)
        if edit.range.end.line >= len(lines):
            end = len(text)
        result = result[:start] + edit.new_text + result[end:]
    ours, wanted = LineIndex(result), LineIndex(format_text(text) or "")
    assert len(ours) == len(wanted)  # lines differing only in their line break stay as they are
    assert [ours.line_content(i) for i in range(len(ours))] == [
        wanted.line_content(i) for i in range(len(wanted))
    ]


@pytest.mark.parametrize(
    "text, unit",
    [
        ("scenario s:\n    x: int\n    do serial:\n        wait elapsed(1s)\n", "    "),
        ("scenario s:\n  x: int\n  y: int\n", "  "),
        ("scenario s:\n\tx: int\n\tdo serial:\n\t\twait elapsed(1s)\n", "\t"),
        ("scenario s:\n\tx: int\n\ty: int\n  z: int\n", "\t"),  # most first-level lines
    ],
)
def test_the_indent_unit_is_the_files_own(text, unit):
    style = indent_style(text)
    assert style is not None and style.unit == unit
    assert format_in_own_style(text) == format_text(text, style)


def test_a_file_without_indentation_has_no_indent_style():
    assert indent_style("import osc.standard\nenum c: [a, b]\n") is None
    assert format_in_own_style("enum  c: [a,b]\n") == "enum c: [a, b]\n"


@pytest.mark.parametrize("path", CORPUS)
def test_formatting_in_the_files_own_style(path):
    with open(path, encoding="utf-8", newline="") as f:
        text = f.read()
    expected = format_text(text, indent_style(text) or FormatOptions())
    assert format_in_own_style(text) == expected
