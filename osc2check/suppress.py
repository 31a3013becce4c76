"""Suppression comments: ``# osc2check: ignore[CODE, slug]`` and friends.

* ``# osc2check: ignore[N101, missing-unit]`` at the end of a line suppresses those
  codes on that line; alone on a line it covers the next line that is not a
  comment. Codes and slugs are accepted, in any case.
* ``# osc2check: ignore`` without codes suppresses every code; so does ``# noqa``.
  ``# noqa: N101, T202`` is accepted as an alias.
* ``# osc2check: file-ignore[N101]`` anywhere in a file suppresses the codes in the
  whole file (without codes: every code).

A finding is matched at its primary span's first line only, never at its
related locations. Lines are the lexer's (``source.LINE_BREAK``), and only
spaces, tabs and form feeds count as blank before a comment, as in the lexer.
A suppression that matches nothing is reported as S001
``unused-suppression``; a code that does not exist as S002
``unknown-suppression-code``. Those two can only be suppressed file-wide.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace

from osc2check import codes
from osc2check.codes import UNKNOWN_SUPPRESSION_CODE, UNUSED_SUPPRESSION, Code
from osc2check.diagnostics import Diagnostic, Fix, Related, TextEdit
from osc2check.source import Span, split_lines

__all__ = ["SuppressedCode", "Suppression", "apply_suppressions", "find_suppressions"]

_OWN_CODES = (UNUSED_SUPPRESSION, UNKNOWN_SUPPRESSION_CODE)
_NAME = r"[A-Za-z][\w-]*"
_DIRECTIVE = re.compile(
    r"osc2check\s*:\s*(?P<kind>file-ignore|ignore)(?:\s*\[(?P<codes>[^\]]*)\]|(?![\w\[-]))",
    re.IGNORECASE,
)
_NOQA = re.compile(
    rf"#\s*noqa(?![\w-])(?:\s*:\s*(?P<codes>{_NAME}(?:[\s,]+{_NAME})*))?",
    re.IGNORECASE,
)
_TOKEN = re.compile(r"[^\s,]+")
_BLANK = " \t\f"  # the lexer's whitespace between tokens


@dataclass(frozen=True, slots=True)
class SuppressedCode:
    """One code named in a suppression comment, as written, and where."""

    name: str
    code: Code | None
    span: Span


@dataclass(frozen=True, slots=True)
class Suppression:
    """One suppression comment.

    ``codes`` empty means every code. ``lines`` are the lines it covers; empty
    for a file-wide suppression.
    """

    span: Span
    kind: str
    codes: tuple[SuppressedCode, ...]
    lines: tuple[int, ...]
    whole_comment: bool = False

    @property
    def file_wide(self) -> bool:
        return self.kind == "file-ignore"

    def matches(self, code: Code) -> list[SuppressedCode] | None:
        """The entries naming ``code`` (``[]`` for an all-codes suppression), or None."""
        if not self.codes:
            return [] if (self.file_wide or code not in _OWN_CODES) else None
        if code in _OWN_CODES and not self.file_wide:
            return None
        found = [c for c in self.codes if c.code == code]
        return found or None

    def covers(self, diagnostic: Diagnostic) -> bool:
        """True when this suppression applies to the diagnostic's primary location."""
        span = diagnostic.span
        if span.uri != self.span.uri:
            return False
        if not self.file_wide and span.line not in self.lines:
            return False
        return self.matches(diagnostic.code) is not None


def _sub_span(comment: Span, offset: int, length: int) -> Span:
    column = comment.column + offset
    start = comment.start + offset
    return Span(
        comment.uri, comment.line, column, comment.line, column + length, start, start + length
    )


def _codes(comment: Span, text: str, group: str | None, base: int) -> tuple[SuppressedCode, ...]:
    if not group:
        return ()
    found = []
    for token in _TOKEN.finditer(group):
        name = token.group()
        span = _sub_span(comment, base + token.start(), len(name))
        found.append(SuppressedCode(name, codes.lookup(name), span))
    return tuple(found)


def _covered_lines(comment: Span, lines: Sequence[str] | None) -> tuple[int, ...]:
    """The lines a line suppression covers: its own, or the next non-comment line."""
    if lines is None:
        # Without the text we cannot tell a trailing comment from one on its own line.
        own = (comment.line + 1,)
        return own if comment.column == 1 else (comment.line, comment.line + 1)
    before = lines[comment.line - 1][: comment.column - 1] if comment.line <= len(lines) else ""
    if before.strip(_BLANK):
        return (comment.line,)
    target = comment.line + 1
    while target <= len(lines) and lines[target - 1].lstrip(_BLANK).startswith("#"):
        target += 1
    return (target,)


def _parse(comment: Span, text: str, lines: Sequence[str] | None) -> Suppression | None:
    match = _DIRECTIVE.search(text)
    if match:
        kind = match.group("kind").lower()
        found = _codes(comment, text, match.group("codes"), match.start("codes"))
    else:
        match = _NOQA.search(text)
        if not match:
            return None
        kind = "noqa"
        found = _codes(comment, text, match.group("codes"), match.start("codes"))
    covered = () if kind == "file-ignore" else _covered_lines(comment, lines)
    whole = text[: match.start()].strip("# ") == "" and text[match.end() :].strip() == ""
    return Suppression(comment, kind, found, covered, whole)


def find_suppressions(
    uri: str, comments: Iterable[tuple[Span, str]], text: str | None = None
) -> list[Suppression]:
    """The suppressions among the comments of the file ``uri``.

    ``comments`` are ``(span, text)`` pairs from the lexer, ``text`` starting
    with ``#``. Pass the file's ``text`` so a trailing comment can be told from
    one on its own line; without it a comment after column 1 covers both its
    own line and the next.
    """
    lines = split_lines(text) if text is not None else None
    found = []
    for span, comment in comments:
        if span.uri != uri:
            span = replace(span, uri=uri)
        suppression = _parse(span, comment, lines)
        if suppression is not None:
            found.append(suppression)
    return found


# --- messages (kept here until a shared messages module exists) ---------------


def _unused(s: Suppression, entry: SuppressedCode | None) -> Diagnostic:
    if entry is not None:
        message, span = f"unused suppression of `{entry.name}`", entry.span
    else:
        what = "file-wide suppression" if s.file_wide else "suppression comment"
        message, span = f"unused {what}", s.span
    fix = None
    if s.whole_comment and len(s.codes) <= 1:
        fix = Fix("remove the suppression comment", (TextEdit(s.span, ""),))
    return Diagnostic(UNUSED_SUPPRESSION, message, span, UNUSED_SUPPRESSION.severity, fix=fix)


def _unknown(entry: SuppressedCode) -> Diagnostic:
    close = difflib.get_close_matches(entry.name.upper(), [c.code for c in codes.ALL], n=1)
    close = close or difflib.get_close_matches(entry.name.lower(), [c.slug for c in codes.ALL], n=1)
    related = (Related(entry.span, f"did you mean `{close[0]}`?"),) if close else ()
    code = UNKNOWN_SUPPRESSION_CODE
    message = f"unknown code `{entry.name}` in suppression comment"
    return Diagnostic(code, message, entry.span, code.severity, related=related)


# --- applying -----------------------------------------------------------------


def apply_suppressions(
    diagnostics: Iterable[Diagnostic], suppressions: Sequence[Suppression]
) -> list[Diagnostic]:
    """Drop suppressed diagnostics; add S001 and S002 findings at the comments.

    The result is sorted by ``Diagnostic.sort_key``.
    """
    used: set[tuple[int, int]] = set()  # (suppression index, entry index or -1)
    kept = []
    for d in diagnostics:
        covering = [(i, s) for i, s in enumerate(suppressions) if s.covers(d)]
        for i, s in covering:
            entries = s.matches(d.code) or []
            used.add((i, -1))
            used.update((i, s.codes.index(e)) for e in entries)
        if not covering:
            kept.append(d)

    added = []
    for i, s in enumerate(suppressions):
        if not s.codes:
            if (i, -1) not in used:
                added.append(_unused(s, None))
            continue
        for j, entry in enumerate(s.codes):
            if entry.code is None:
                added.append(_unknown(entry))
            elif (i, j) not in used and not (s.file_wide and entry.code in _OWN_CODES):
                added.append(_unused(s, entry))

    file_wide = [s for s in suppressions if s.file_wide]
    kept += [d for d in added if not any(s.covers(d) for s in file_wide)]
    return sorted(kept, key=lambda d: d.sort_key)
