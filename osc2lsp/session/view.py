"""A snapshot seen from a newer version of its text.

While the next analysis runs, the latest snapshot still answers for every
part of the document that did not change since it was made (``TextMap``):
offsets of the current text are turned into the snapshot's to ask the
features, and the spans they answer with are moved back to where that text
is now. A span the edit went through cannot be moved (``moved`` is None):
the current version's analysis has to answer instead.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from osc2lsp.text import LineIndex, TextMap

if TYPE_CHECKING:  # the analysis is imported on first use, not to answer `initialize`
    from osc2check.source import Span
    from osc2lsp.snapshot import Snapshot


def moved(span: Span, key: str, change: TextMap, lines: LineIndex) -> Span | None:
    """``span`` of the old text of file ``key``, moved to the new text (``lines``);
    spans of other files as they are; None where the edit went through it."""
    if span.uri != key:
        return span
    if change.touches(span.start, span.end):
        return None
    start, end = change.to_new(span.start), change.to_new(span.end)
    assert start is not None and end is not None  # both lie outside the changed region
    line, column = lines.position(start)
    end_line, end_column = lines.position(end)
    return replace(
        span,
        line=line + 1,
        column=column + 1,
        end_line=end_line + 1,
        end_column=end_column + 1,
        start=start,
        end=end,
    )


@dataclass(frozen=True)
class View:
    """A snapshot answering for the current text (``lines``); ``change`` relates the
    two texts (None: they are the same)."""

    snap: Snapshot
    change: TextMap | None
    lines: LineIndex

    def span(self, span: Span) -> Span | None:
        if self.change is None:
            return span
        return moved(span, self.snap.key, self.change, self.lines)

    def spans(self, spans: list[Span]) -> list[Span]:
        return [m for s in spans if (m := self.span(s)) is not None]

    def lines_of(self, key: str) -> LineIndex | None:
        return self.lines if key == self.snap.key else self.snap.lines_of(key)
