"""Source text, positions and spans.

Lines and columns are 1-based and count Unicode code points, as the CLI prints
them; ``start``/``end`` are 0-based offsets into the decoded text. The language
server converts to LSP's 0-based UTF-16 positions in one place (``osc2lsp``).

A line ends at ``\r\n``, ``\r`` or ``\n`` (``LINE_BREAK``), in the lexer, in
suppression comments and in the language server alike (LSP's own rule): never at
a form feed, ``\x0b``, ``\x1c``-``\x1e``, U+0085, U+2028 or U+2029, where
``str.splitlines()`` also breaks.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

LINE_BREAK = re.compile(r"\r\n|\r|\n")


def split_lines(text: str) -> list[str]:
    """The lines of ``text`` without their line breaks (a text ending with a line
    break has an empty last line)."""
    return LINE_BREAK.split(text)


@dataclass(frozen=True, slots=True)
class Span:
    """A half-open region of one source file."""

    uri: str
    line: int
    column: int
    end_line: int
    end_column: int
    start: int = 0
    end: int = 0

    def cover(self, other: Span) -> Span:
        """The smallest span of the same file that covers both spans."""
        first = self if (self.line, self.column) <= (other.line, other.column) else other
        ends = (self.end_line, self.end_column) >= (other.end_line, other.end_column)
        last = self if ends else other
        return Span(
            self.uri,
            first.line,
            first.column,
            last.end_line,
            last.end_column,
            min(self.start, other.start),
            max(self.end, other.end),
        )

    def __str__(self) -> str:
        return f"{self.uri}:{self.line}:{self.column}"


def point_span(uri: str, text: str, offset: int) -> Span:
    """A zero-width span at ``offset`` of ``text``."""
    offset = max(0, min(offset, len(text)))
    line = line_of(text, offset)
    column = offset - line_start(text, offset) + 1
    return Span(uri, line, column, line, column, offset, offset)


def line_start(text: str, offset: int) -> int:
    """The offset where the line holding ``offset`` begins (see ``LINE_BREAK``)."""
    newline = text.rfind("\n", 0, offset)
    # a \r after the last \n only: searched for back to the start of the text, a file
    # without one would be read whole for every line
    return max(newline, text.rfind("\r", newline + 1, offset)) + 1


def line_of(text: str, offset: int) -> int:
    """The 1-based line of ``offset`` in ``text`` (see ``LINE_BREAK``)."""
    return (
        text.count("\n", 0, offset)
        + text.count("\r", 0, offset)
        - text.count("\r\n", 0, offset)
        + 1
    )


def strip_comment(line: str) -> str:
    """``line`` without its ``#`` comment (a ``#`` inside a string is kept)."""
    quote = None
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "\"'":
            quote = ch
        elif ch == "#":
            return line[:i]
    return line


def decode_source(data: bytes) -> tuple[str, str | None]:
    """Decode file bytes as UTF-8 (BOM allowed). Returns (text, problem or None).

    Invalid bytes are replaced, never raised on, so a damaged file still parses.
    """
    problem = None
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        text = data.decode("utf-8-sig", errors="replace")
        problem = f"invalid UTF-8 at byte {exc.start}"
    return without_nul(text, problem)


def without_nul(text: str, problem: str | None = None) -> tuple[str, str | None]:
    """``text`` with each NUL character replaced (as an invalid byte is), and the
    problem (P004) that says so, unless ``problem`` already tells of one.

    A NUL is no part of a text file; the checker reads it whether it comes from a
    file's bytes or from an editor's text, so both show the same findings.
    """
    if "\x00" not in text:
        return text, problem
    return text.replace("\x00", "\ufffd"), problem or "NUL byte in source"


def common_prefix(a: str, b: str) -> int:
    """The length of the longest common prefix of ``a`` and ``b``."""
    low, high = 0, min(len(a), len(b))
    while low < high:  # slices compare in C: O(n log n) but fast for any document
        middle = (low + high + 1) // 2
        if a[low:middle] == b[low:middle]:
            low = middle
        else:
            high = middle - 1
    return low


def common_suffix(a: str, b: str, limit: int) -> int:
    """The length (at most ``limit``) of the longest common suffix of ``a`` and ``b``."""
    low, high = 0, min(len(a), len(b), limit)
    while low < high:
        middle = (low + high + 1) // 2
        if a[len(a) - middle : len(a) - low] == b[len(b) - middle : len(b) - low]:
            low = middle
        else:
            high = middle - 1
    return low


def changed_region(old: str, new: str) -> tuple[int, int, int]:
    """Where ``new`` differs from ``old``, as one region: ``(start, old_end, new_end)``,
    ``old[start:old_end]`` having become ``new[start:new_end]`` (their common beginning
    and end, not overlapping, set it apart)."""
    prefix = common_prefix(old, new)
    suffix = common_suffix(old, new, min(len(old), len(new)) - prefix)
    return prefix, len(old) - suffix, len(new) - suffix
