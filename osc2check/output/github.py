"""GitHub Actions workflow commands: one annotation per finding.

``::error file=PATH,line=L,col=C,endLine=EL,endColumn=EC,title=CODE::message``
(``::warning`` and ``::notice`` for warnings and infos).
"""

from __future__ import annotations

from collections.abc import Sequence

from osc2check.codes import Severity
from osc2check.diagnostics import Diagnostic

_COMMAND = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}


def _escape_data(text: str) -> str:
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def _escape_property(text: str) -> str:
    return _escape_data(text).replace(":", "%3A").replace(",", "%2C")


def format_diagnostic(d: Diagnostic) -> str:
    """One workflow command."""
    s = d.span
    props = {
        "file": s.uri,
        "line": s.line,
        "col": s.column,
        "endLine": s.end_line,
        "endColumn": s.end_column,
        "title": d.code.code,
    }
    joined = ",".join(f"{k}={_escape_property(str(v))}" for k, v in props.items())
    return f"::{_COMMAND[d.severity]} {joined}::{_escape_data(d.message)}"


def render(diagnostics: Sequence[Diagnostic]) -> str:
    """Every finding as a workflow command, one per line."""
    return "".join(format_diagnostic(d) + "\n" for d in diagnostics)
