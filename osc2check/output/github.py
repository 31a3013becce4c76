"""GitHub Actions workflow commands: one annotation per finding.

``::error file=PATH,line=L,col=C,endLine=EL,endColumn=EC,title=CODE::message``
(``::warning`` and ``::notice`` for warnings and infos). A path that could not be
read is ``::error file=PATH,title=osc2check::cannot read: why``; a special file
skipped in a folder walk is a ``::notice`` of the same form.
"""

from __future__ import annotations

from collections.abc import Sequence

from osc2check.codes import Severity
from osc2check.diagnostics import Diagnostic
from osc2check.inputs import InputProblem

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


def format_problem(p: InputProblem) -> str:
    """One workflow command for a path that was not checked."""
    props = f"file={_escape_property(p.path)},title={_escape_property('osc2check')}"
    return f"::{_COMMAND[p.severity]} {props}::{_escape_data(p.message)}"


def render(diagnostics: Sequence[Diagnostic], problems: Sequence[InputProblem] = ()) -> str:
    """Every path not checked, then every finding, as workflow commands, one per line."""
    lines = [format_problem(p) for p in problems] + [format_diagnostic(d) for d in diagnostics]
    return "".join(line + "\n" for line in lines)
