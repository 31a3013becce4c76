"""The versioned JSON format (``"version": 1``): a contract for other tools.

One object, its keys in this order::

    {
      "scenarios": [{"name", "path", "line", "status", "conflicts", "unverified",
                     "witness"?}],
      "version": 1,
      "tool": {"name": "osc2check", "version": "..."},
      "findings": [{"code", "name", "severity", "message", "location", "related",
                    "url", "fix"}],
      "errors": [{"path", "message"}],
      "skipped": [{"path", "message"}]
    }

``scenarios`` come first, so that the witnesses of ``--witness`` (``"witness"``, only
with that option) are read before the findings. ``unverified`` lists the constraints
the solver could not take (``{"path", "line", "column", "text", "reason"}``, C411):
a ``"sat"`` status does not cover them. ``errors`` are the paths that could
not be read (``"cannot read: permission denied"``; the exit status is then 2);
``skipped`` are special files (FIFOs, sockets, devices) left out of a folder walk.
Locations are 1-based. Fields may be added in later versions; consumers ignore fields
they do not know, and do not rely on the order of keys.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any

from osc2check import rules
from osc2check.diagnostics import Diagnostic, Fix
from osc2check.inputs import InputProblem
from osc2check.output import tool
from osc2check.source import Span

FORMAT_VERSION = 1


def location(span: Span) -> dict[str, Any]:
    """``{"path", "start": {"line", "column"}, "end": {...}}``, 1-based."""
    return {
        "path": span.uri,
        "start": {"line": span.line, "column": span.column},
        "end": {"line": span.end_line, "column": span.end_column},
    }


def _fix(fix: Fix | None) -> dict[str, Any] | None:
    if fix is None:
        return None
    return {
        "message": fix.message,
        "applicability": "safe" if fix.safe else "unsafe",
        "edits": [{**location(e.span), "content": e.new_text} for e in fix.edits],
    }


def finding(d: Diagnostic) -> dict[str, Any]:
    """One finding as a JSON-ready dict."""
    return {
        "code": d.code.code,
        "name": d.code.slug,
        "severity": d.severity.label,
        "message": d.message,
        "location": location(d.span),
        "related": [{**location(r.span), "message": r.message} for r in d.related],
        "url": rules.doc_url(d.code),
        "fix": _fix(d.fix),
    }


def render(
    diagnostics: Sequence[Diagnostic],
    scenarios: Sequence[dict[str, object]] = (),
    problems: Sequence[InputProblem] = (),
) -> str:
    """The whole document, indented, with a final newline.

    ``scenarios`` are the verified scenarios (``verify.check.scenario_summary``):
    name, file, status and, when the constraints can hold, the witness. ``problems``
    are the paths not checked: errors and skipped files.
    """
    document = {
        "scenarios": list(scenarios),
        "version": FORMAT_VERSION,
        "tool": {"name": tool.NAME, "version": tool.version()},
        "findings": [finding(d) for d in diagnostics],
        "errors": [{"path": p.path, "message": p.message} for p in problems if p.is_error],
        "skipped": [{"path": p.path, "message": p.message} for p in problems if not p.is_error],
    }
    return json.dumps(document, indent=2, ensure_ascii=False) + "\n"
