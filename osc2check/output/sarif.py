"""SARIF 2.1.0, as GitHub code scanning reads it.

One run; ``rules`` lists the codes that occur, each with its documentation page
as ``help``. Columns are Unicode code points (``columnKind``). Each result has a
``partialFingerprints`` entry: a hash of code, path and message (and, for
identical findings in one file, their ordinal), stable across runs.

The run's one ``invocation`` says whether every path could be read
(``executionSuccessful``) and lists, as ``toolExecutionNotifications``, the paths
that could not (level ``error``) and the special files skipped in a folder walk
(level ``note``).
"""

from __future__ import annotations

import hashlib
import json
from collections import Counter
from collections.abc import Sequence
from typing import Any
from urllib.parse import quote

from osc2check import rules
from osc2check.codes import Code, Severity
from osc2check.diagnostics import Diagnostic
from osc2check.inputs import InputProblem
from osc2check.output import tool
from osc2check.source import Span

SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"
FINGERPRINT_KEY = "osc2check/v1"
_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}


def _uri(path: str) -> str:
    return path if "://" in path else quote(path, safe="/:")


def _location(span: Span) -> dict[str, Any]:
    return {
        "physicalLocation": {
            "artifactLocation": {"uri": _uri(span.uri)},
            "region": {
                "startLine": span.line,
                "startColumn": span.column,
                "endLine": span.end_line,
                "endColumn": span.end_column,
            },
        }
    }


def _rule(code: Code) -> dict[str, Any]:
    sections = rules.page_sections(rules.page_text(code))
    return {
        "id": code.code,
        "name": "".join(part.capitalize() for part in code.slug.split("-")),
        "shortDescription": {"text": code.summary},
        "fullDescription": {"text": sections.get("What it finds", code.summary)},
        "help": {"text": code.summary, "markdown": rules.page_text(code)},
        "defaultConfiguration": {"level": _LEVEL[code.severity]},
        "properties": {"tags": [code.slug, code.family]},
    }


def fingerprint(d: Diagnostic, ordinal: int = 0) -> str:
    """A stable hash of code, path and message (plus the ordinal of a repeat)."""
    key = f"{d.code.code}\0{d.span.uri}\0{d.message}"
    if ordinal:
        key += f"\0{ordinal}"
    return hashlib.sha256(key.encode("utf-8")).hexdigest()[:32]


def _notification(p: InputProblem) -> dict[str, Any]:
    return {
        "level": _LEVEL[p.severity],
        "message": {"text": p.message},
        "locations": [{"physicalLocation": {"artifactLocation": {"uri": _uri(p.path)}}}],
    }


def render(diagnostics: Sequence[Diagnostic], problems: Sequence[InputProblem] = ()) -> str:
    """The SARIF log, indented, with a final newline."""
    used = sorted({d.code for d in diagnostics}, key=lambda c: c.code)
    index = {c: i for i, c in enumerate(used)}
    seen: Counter[tuple[str, str, str]] = Counter()
    results = []
    for d in diagnostics:
        key = (d.code.code, d.span.uri, d.message)
        result: dict[str, Any] = {
            "ruleId": d.code.code,
            "ruleIndex": index[d.code],
            "level": _LEVEL[d.severity],
            "message": {"text": d.message},
            "locations": [_location(d.span)],
        }
        if d.related:
            result["relatedLocations"] = [
                {"id": i, "message": {"text": r.message}, **_location(r.span)}
                for i, r in enumerate(d.related, start=1)
            ]
        result["partialFingerprints"] = {FINGERPRINT_KEY: fingerprint(d, seen[key])}
        seen[key] += 1
        results.append(result)
    log = {
        "$schema": SCHEMA,
        "version": "2.1.0",
        "runs": [
            {
                "tool": {
                    "driver": {
                        "name": tool.NAME,
                        "version": tool.version(),
                        "rules": [_rule(c) for c in used],
                    }
                },
                "invocations": [
                    {
                        "executionSuccessful": not any(p.is_error for p in problems),
                        "toolExecutionNotifications": [_notification(p) for p in problems],
                    }
                ],
                "columnKind": "unicodeCodePoints",
                "results": results,
            }
        ],
    }
    return json.dumps(log, indent=2, ensure_ascii=False) + "\n"
