"""Findings of a new version at once, before its analysis: the syntax-first preview.

A full analysis of a 10,000-line document takes most of a second. While it
runs, the editor gets a preview made in milliseconds from the last analysis
(``Snapshot``) and the new text:

* the segments the edit touched are parsed again
  (``osc2check.syntax.incremental.reparse``) and their syntax findings, after
  the document's suppression comments and configuration, replace the old
  syntax findings of those declarations;
* every other finding of the last analysis is kept, moved to where its text
  is now, unless the edit went through it or it now sits on a line with a
  syntax error (the analysis hides those too).

Findings about names and types of the edited declarations follow with the
analysis, which replaces the preview.
"""

from __future__ import annotations

from dataclasses import replace

from osc2check.codes import UNKNOWN_SUPPRESSION_CODE, UNUSED_SUPPRESSION
from osc2check.diagnostics import Diagnostic, Fix, Related, TextEdit
from osc2check.suppress import apply_suppressions, find_suppressions
from osc2check.syntax.incremental import Edit, Region, reparse
from osc2check.syntax.lexer import Comment
from osc2check.syntax.parser import ParseResult
from osc2lsp.session.view import moved
from osc2lsp.snapshot import Snapshot
from osc2lsp.text import LineIndex, TextMap

_OWN = (UNUSED_SUPPRESSION, UNKNOWN_SUPPRESSION_CODE)
_DIRECTIVES = ("noqa", "osc2check")


def preview(snapshot: Snapshot, lines: LineIndex) -> list[Diagnostic] | None:
    """The findings to show for ``lines.text`` until its analysis is done; None when
    the edit may change how the rest of the file reads (the analysis will tell)."""
    text = lines.text
    change = TextMap(snapshot.text, text)
    if change.unchanged:
        return list(snapshot.diagnostics)
    region = reparse(snapshot.parse, text, Edit(change.prefix, change.old_end, change.new_end))
    if region is None:
        return None
    key = snapshot.key
    replaced = {
        (d.code, d.span.start, d.span.end, d.message)
        for segment in snapshot.parse.segments[region.first : region.after]
        for d in segment.diagnostics
    }
    kept: list[Diagnostic] = []
    for d in snapshot.diagnostics:
        span = d.span
        if span.uri == key and (d.code, span.start, span.end, d.message) in replaced:
            continue  # the region's parse says again what is wrong there
        if span.uri == key and change.touches(span.start, span.end):
            continue
        moved = _moved(d, key, change, lines)
        if moved.span.line not in region.error_lines or moved.code in _OWN:
            kept.append(moved)
    fresh = _as_analysed(list(region.diagnostics), snapshot, region, change, lines)
    return sorted(kept + fresh, key=lambda d: d.sort_key)


def _as_analysed(
    found: list[Diagnostic],
    snapshot: Snapshot,
    region: Region,
    change: TextMap,
    lines: LineIndex,
) -> list[Diagnostic]:
    """``found`` after the document's suppression comments and configuration."""
    key = snapshot.key
    comments = [c for c in region.comments if _directive(c)]
    for c in snapshot.parse.comments:
        if not _directive(c) or region.start <= c.offset < region.old_end:
            continue
        offset = change.to_new(c.offset)
        if offset is not None and not change.touches(c.offset, c.offset + len(c.text)):
            line, column = lines.position(offset)
            comments.append(Comment(offset, line + 1, column + 1, c.text))
    spans = ParseResult(key, lines.text, snapshot.ast, (), tuple(comments)).comment_spans()
    suppressions = find_suppressions(key, spans, lines.text)
    found = [d for d in apply_suppressions(found, suppressions) if d.code not in _OWN]
    policy = getattr(snapshot.config, "policy", None)
    return policy(found, key) if policy is not None else found


def _directive(comment: Comment) -> bool:
    lowered = comment.text.lower()
    return any(word in lowered for word in _DIRECTIVES)


def _moved(d: Diagnostic, key: str, change: TextMap, lines: LineIndex) -> Diagnostic:
    """``d`` with its locations in this document moved to the new text (related notes
    and fixes the edit went through are dropped)."""
    span = moved(d.span, key, change, lines)
    assert span is not None  # the caller dropped the findings the edit went through
    related = tuple(
        Related(m, r.message) for r in d.related if (m := moved(r.span, key, change, lines))
    )
    fix = d.fix
    if fix is not None:
        edits = [(moved(e.span, key, change, lines), e.new_text) for e in fix.edits]
        fix = (
            Fix(fix.message, tuple(TextEdit(s, t) for s, t in edits if s is not None), fix.safe)
            if all(s is not None for s, _ in edits)
            else None
        )
    return replace(d, span=span, related=related, fix=fix)
