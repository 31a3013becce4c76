"""Diagnostics: what a pass found, where, and how to fix it.

Passes never format text: they call a function of ``messages`` which returns a
``Diagnostic`` carrying a registered ``Code`` (see ``codes``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from osc2check.codes import Code, Severity
from osc2check.source import Span

__all__ = ["Diagnostic", "Fix", "Related", "Severity", "TextEdit"]


@dataclass(frozen=True, slots=True)
class Related:
    """A second location that explains a diagnostic (first definition, conflicting line)."""

    span: Span
    message: str


@dataclass(frozen=True, slots=True)
class TextEdit:
    """Replace the text of ``span`` with ``new_text``."""

    span: Span
    new_text: str


@dataclass(frozen=True, slots=True)
class Fix:
    """A suggested change; ``safe`` fixes keep the meaning of the scenario."""

    message: str
    edits: tuple[TextEdit, ...]
    safe: bool = True


@dataclass(frozen=True, slots=True)
class Diagnostic:
    code: Code
    message: str
    span: Span
    severity: Severity
    related: tuple[Related, ...] = ()
    fix: Fix | None = None
    data: dict[str, object] = field(default_factory=dict, compare=False, hash=False)

    @property
    def sort_key(self) -> tuple[str, int, int, str, str]:
        return (self.span.uri, self.span.line, self.span.column, self.code.code, self.message)
