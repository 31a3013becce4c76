"""The server's copy of a document: LSP line semantics, incremental line index,
offsets between two versions of a text."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lsprotocol import types
from pygls.workspace.position_codec import PositionCodec

from osc2check.source import changed_region, common_prefix, common_suffix
from osc2lsp.convert import from_lsp_position
from osc2lsp.text import LineIndex, TextMap
from tests.osc2lsp.storms import SEPARATORS, final_text, lsp_lines, lsp_position, storms

ALPHABET = st.sampled_from(["a", "é", "😀", " ", "\n", "\r", "\r\n", *SEPARATORS])
TEXTS = st.lists(ALPHABET, max_size=30).map("".join)


def test_lines_end_only_where_lsp_lines_end():
    text = "a\fb\x0bc\x1cd\x1de\x1ef\x85g\u2028h\u2029i\nj"
    lines = LineIndex(text)
    assert len(lines) == 2
    assert lines.line_content(0) == text.split("\n")[0]
    assert lines.position(text.index("j")) == (1, 0)


@given(TEXTS, st.data())
def test_an_edited_index_equals_a_fresh_one(text, data):
    start = data.draw(st.integers(0, len(text)))
    end = data.draw(st.integers(start, len(text)))
    inserted = data.draw(TEXTS)
    edited = LineIndex(text).edited(start, end, inserted)
    fresh = LineIndex(text[:start] + inserted + text[end:])
    assert edited.text == fresh.text
    assert edited.starts == fresh.starts


@given(TEXTS)
def test_line_starts_follow_the_lsp_specification(text):
    assert LineIndex(text).starts == [start for start, _ in lsp_lines(text)]


BASE = "# a\fcomment\u2028with\x85separators\nscenario s:\n    x: int\r\n    y: int\rdo\n"


@pytest.mark.slow
@settings(max_examples=200, deadline=None)
@given(storms(BASE), st.sampled_from(["utf-16", "utf-8", "utf-32"]))
def test_a_storm_of_client_edits_gives_the_clients_text(edits, encoding):
    """What ``did_change`` does with each change: client positions → offsets → edit."""
    codec = PositionCodec(encoding)
    lines = LineIndex(BASE)
    text = BASE
    for edit in edits:
        change = edit.change(text, encoding)
        start = from_lsp_position(lines, types.Position(**change["range"]["start"]), codec)
        end = from_lsp_position(lines, types.Position(**change["range"]["end"]), codec)
        lines = lines.edited(start, end, change["text"])
        text = edit.apply(text)
        assert lines.text == text
    assert lines.text == final_text(BASE, edits)
    assert lines.starts == LineIndex(lines.text).starts


def test_positions_past_the_end_of_a_line_or_the_text_are_clamped():
    lines = LineIndex("ab\ncd")
    codec = PositionCodec("utf-16")
    assert from_lsp_position(lines, types.Position(line=0, character=99), codec) == 2
    assert from_lsp_position(lines, types.Position(line=9, character=0), codec) == 5


@given(TEXTS, TEXTS)
def test_a_text_map_relates_the_unchanged_parts(old, new):
    change = TextMap(old, new)
    assert old[: change.prefix] == new[: change.prefix]
    assert old[change.old_end :] == new[change.new_end :]
    assert change.prefix <= change.old_end and change.prefix <= change.new_end
    # both parts as long as they can be: the suffix may not overlap the prefix
    suffix = len(old) - change.old_end
    assert suffix == len(new) - change.new_end
    shorter = min(len(old), len(new))
    assert change.prefix == shorter or old[change.prefix] != new[change.prefix]
    assert suffix == shorter - change.prefix or old[-suffix - 1] != new[-suffix - 1]
    for offset in range(len(new) + 1):
        back = change.to_old(offset)
        if back is not None and offset < change.prefix:
            assert old[back] == new[offset]
        if back is not None and change.new_end < offset < len(new):
            assert old[back] == new[offset]


def test_common_prefix_and_suffix():
    assert common_prefix("scenario a", "scenario b") == 9
    assert common_suffix("abc xyz", "abd xyz", 7) == 4
    assert common_suffix("aaa", "aaa", 1) == 1
    assert changed_region("abc xyz", "abd xyz") == (2, 3, 3)
    assert changed_region("aaa", "aa") == (2, 3, 2)  # beginning and end never overlap
    assert changed_region("", "new") == (0, 0, 3)
    assert lsp_position("a\r\nb", 3) == {"line": 1, "character": 0}


def test_the_server_starts_without_importing_the_analysis():
    """`initialize` is answered before the checker (lark, z3) is loaded."""
    import os
    import subprocess
    import sys

    from tests.osc2lsp.lsp_helpers import REPO

    path = os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")])
    env = dict(os.environ, PYTHONPATH=path)
    probe = "import sys, osc2lsp.server; print('osc2check.analysis' in sys.modules)"
    found = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, env=env)
    assert found.stdout.strip() == "False", found.stderr
