"""The one-line format: ``path:line:col: CODE message``."""

from __future__ import annotations

from collections.abc import Sequence

from osc2check.diagnostics import Diagnostic


def format_diagnostic(d: Diagnostic) -> str:
    """One finding on one line."""
    return f"{d.span.uri}:{d.span.line}:{d.span.column}: {d.code.code} {d.message}"


def render(diagnostics: Sequence[Diagnostic]) -> str:
    """Every finding, one per line."""
    return "".join(format_diagnostic(d) + "\n" for d in diagnostics)
