"""Text positions and file names, without the analysis (cheap to import).

Lines end at ``\r\n``, ``\r`` or ``\n``, as in the OSC2 lexer and in LSP: never
at a form feed, ``\x0b``, ``\x1c``-``\x1e``, U+0085, U+2028 or U+2029, where
``str.splitlines()`` would also break (and a client's positions would then land
on the wrong line). Offsets and columns count code points; ``convert.py`` turns
them into the client's units.

``LineIndex.edited`` applies one edit and re-scans only the lines around it, so
that a keystroke in a large document costs little; ``TextMap`` relates offsets
of two versions of a text (an analysis made of an older version is still used
for the parts of the text that did not change).
"""

from __future__ import annotations

import bisect
import re
from pathlib import Path
from urllib.parse import quote, unquote, urlparse

# what a line is, and where two versions of a text differ: one home for the checker and us
from osc2check.source import LINE_BREAK, changed_region

# ---- file names ---------------------------------------------------------------


def uri_to_key(uri: str) -> str:
    """The analysis name of a client URI: a path for ``file:`` URIs, else the URI."""
    if uri.startswith("file:"):
        parsed = urlparse(uri)
        path = unquote(parsed.path)
        if re.match(r"^/[A-Za-z]:", path):  # file:///c:/x on Windows
            path = path[1:]
        return str(Path(path)) if path else uri
    return uri


def key_to_uri(key: str) -> str:
    """The client URI of an analysis name (absolute paths become ``file:`` URIs)."""
    if "://" in key or key.startswith("untitled:"):
        return key
    path = Path(key)
    if path.is_absolute():
        return "file://" + quote(path.as_posix(), safe="/:")
    return key


# ---- lines and offsets --------------------------------------------------------


def _breaks(text: str, low: int, high: int) -> list[int]:
    """Offsets just after each line break inside ``text[low:high]``."""
    return [m.end() for m in LINE_BREAK.finditer(text, low, high)]


class LineIndex:
    """Offsets of line starts; lines end at ``\\r\\n``, ``\\r`` or ``\\n`` as in the lexer."""

    __slots__ = ("text", "starts")

    def __init__(self, text: str, starts: list[int] | None = None):
        self.text = text
        self.starts = starts if starts is not None else [0] + _breaks(text, 0, len(text))

    def edited(self, start: int, end: int, new_text: str) -> LineIndex:
        """The index of this text with ``[start, end)`` replaced by ``new_text``.

        Only the lines from the one before the edit to the first line start after
        it are scanned again (a ``\r`` before the edit and a ``\n`` after it may
        join into one line break); the later line starts move by the change in
        length.
        """
        text = self.text
        start = max(0, min(start, len(text)))
        end = max(start, min(end, len(text)))
        new = text[:start] + new_text + text[end:]
        delta = len(new_text) - (end - start)
        first = max(bisect.bisect_right(self.starts, start) - 2, 0)  # the line before
        low = self.starts[first]
        after = bisect.bisect_right(self.starts, end + 1)  # first start past the edit
        high = self.starts[after] + delta if after < len(self.starts) else len(new)
        starts = self.starts[: first + 1]
        starts += _breaks(new, low, high)
        starts += [s + delta for s in self.starts[after + 1 :]]
        return LineIndex(new, starts)

    def __len__(self) -> int:
        return len(self.starts)

    def line_text(self, line: int) -> str:
        """Line ``line`` (0-based) with its line ending."""
        if line < 0 or line >= len(self.starts):
            return ""
        end = self.starts[line + 1] if line + 1 < len(self.starts) else len(self.text)
        return self.text[self.starts[line] : end]

    def line_content(self, line: int) -> str:
        """Line ``line`` (0-based) without its line ending."""
        return self.line_text(line).rstrip("\r\n")

    def lines(self) -> list[str]:
        return [self.line_text(i) for i in range(len(self.starts))]

    def offset(self, line: int, column: int) -> int:
        """The offset of 0-based (line, column in code points), clamped to the text."""
        if line < 0:
            return 0
        if line >= len(self.starts):
            return len(self.text)
        content = self.line_content(line)
        return self.starts[line] + max(0, min(column, len(content)))

    def position(self, offset: int) -> tuple[int, int]:
        """0-based (line, column in code points) of ``offset``."""
        offset = max(0, min(offset, len(self.text)))
        line = bisect.bisect_right(self.starts, offset) - 1
        return line, offset - self.starts[line]


# ---- two versions of a text -------------------------------------------------


class TextMap:
    """Offsets of an old and a new version of a text, related across one changed region.

    ``old[:prefix] == new[:prefix]`` and the last ``suffix`` characters agree; the
    region between (``old_end``/``new_end`` in each version) is what changed. An
    offset maps when it lies outside that region (at its edges too).
    """

    __slots__ = ("prefix", "old_end", "new_end", "delta")

    def __init__(self, old: str, new: str):
        self.prefix, self.old_end, self.new_end = changed_region(old, new)
        self.delta = len(new) - len(old)

    @property
    def unchanged(self) -> bool:
        return self.prefix == self.old_end == self.new_end

    def to_new(self, offset: int) -> int | None:
        """The offset in the new text of ``offset`` in the old one (None: it changed)."""
        if offset <= self.prefix:
            return offset
        if offset >= self.old_end:
            return offset + self.delta
        return None

    def to_old(self, offset: int) -> int | None:
        """The offset in the old text of ``offset`` in the new one (None: it changed)."""
        if offset <= self.prefix:
            return offset
        if offset >= self.new_end:
            return offset - self.delta
        return None

    def clear_of(self, offset: int) -> bool:
        """Whether ``offset`` of the new text is away from the changed region (not at its
        edges: a name there may have been edited)."""
        return offset < self.prefix or offset > self.new_end

    def touches(self, start: int, end: int) -> bool:
        """Whether the old region ``[start, end]`` meets the changed region (edges included)."""
        return start <= self.old_end and end >= self.prefix
