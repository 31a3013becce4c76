"""The default human format: a header line, related notes and the source with carets.

```
cut_in.osc:7:40: N101 [error] undefined name `hreo`
  cut_in.osc:4:5: note: did you mean `hero`?
  |
7 |         position(distance: 5m, behind: hreo)
  |                                        ^^^^
```
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from functools import lru_cache

from osc2check.diagnostics import Diagnostic
from osc2check.source import Span


@lru_cache(maxsize=16)
def _lines(text: str) -> tuple[str, ...]:
    """A text's lines, split once however many findings quote it."""
    return tuple(text.splitlines())


def _source_line(text: str, line: int) -> str | None:
    lines = _lines(text)
    return lines[line - 1].rstrip() if 1 <= line <= len(lines) else None


def excerpt(span: Span, text: str) -> list[str]:
    """The span's first line with a gutter, and a caret line under the span."""
    source = _source_line(text, span.line)
    if source is None:
        return []
    start = min(span.column - 1, len(source))
    if span.end_line == span.line:
        width = span.end_column - span.column
    else:
        width = len(source) - start
    pad = "".join("\t" if ch == "\t" else " " for ch in source[:start])
    number = str(span.line)
    gutter = " " * len(number)
    return [
        f"{gutter} |",
        f"{number} | {source}".rstrip(),
        f"{gutter} | {pad}{'^' * max(1, width)}",
    ]


def format_diagnostic(d: Diagnostic, texts_by_uri: Mapping[str, str]) -> str:
    """One finding: header, notes, source excerpt and fix hint, each on its own line."""
    s = d.span
    lines = [f"{s.uri}:{s.line}:{s.column}: {d.code.code} [{d.severity.label}] {d.message}"]
    for r in d.related:
        lines.append(f"  {r.span.uri}:{r.span.line}:{r.span.column}: note: {r.message}")
    text = texts_by_uri.get(s.uri)
    if text is not None:
        lines += excerpt(s, text)
    if d.fix is not None:
        safety = "" if d.fix.safe else " (unsafe)"
        lines.append(f"  = fix{safety}: {d.fix.message}")
    return "\n".join(lines) + "\n"


def render(diagnostics: Sequence[Diagnostic], texts_by_uri: Mapping[str, str]) -> str:
    """Every finding, separated by blank lines."""
    return "\n".join(format_diagnostic(d, texts_by_uri) for d in diagnostics)
