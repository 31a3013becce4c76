"""Line index, file names and LSP position conversion with non-ASCII text."""

from __future__ import annotations

from lsprotocol import types
from pygls.workspace.position_codec import PositionCodec

from osc2check.source import Span
from osc2lsp.convert import from_lsp_position, to_lsp_position, to_lsp_range
from osc2lsp.text import LineIndex, key_to_uri, uri_to_key

TEXT = "a\r\nb😀c\rd\ne"  # all three line endings, a character outside the BMP


def test_line_index_uses_the_lexers_line_endings():
    lines = LineIndex(TEXT)
    assert len(lines) == 4
    assert [lines.line_content(i) for i in range(4)] == ["a", "b😀c", "d", "e"]
    assert lines.position(TEXT.index("c")) == (1, 2)
    assert lines.offset(1, 2) == TEXT.index("c")


def test_positions_in_utf16_utf8_and_utf32():
    lines = LineIndex(TEXT)
    offset = TEXT.index("c")
    for encoding, character in (("utf-16", 3), ("utf-8", 5), ("utf-32", 2)):
        codec = PositionCodec(encoding)
        position = to_lsp_position(lines, offset, codec)
        assert (position.line, position.character) == (1, character)
        assert from_lsp_position(lines, position, codec) == offset


def test_span_ranges_use_the_spans_file_text():
    lines = LineIndex("x = 1\n# größe 😀 y\n")
    span = Span("f", 2, 11, 2, 12, 0, 0)  # the `y`
    rng = to_lsp_range(span, lines, PositionCodec("utf-16"))
    assert rng.start == types.Position(line=1, character=11)
    assert rng.end == types.Position(line=1, character=12)


def test_uris_and_keys():
    assert uri_to_key("file:///tmp/a%20b.osc") == "/tmp/a b.osc"
    assert key_to_uri("/tmp/a b.osc") == "file:///tmp/a%20b.osc"
    assert uri_to_key("untitled:Untitled-1") == "untitled:Untitled-1"
