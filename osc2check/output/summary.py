"""Counting findings: the summary line and the ``--statistics`` table."""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence

from osc2check.codes import Severity
from osc2check.diagnostics import Diagnostic

_NOUNS = {Severity.ERROR: ("error", "errors"), Severity.WARNING: ("warning", "warnings")}


def _count(n: int, singular: str, plural: str) -> str:
    return f"{n} {singular if n == 1 else plural}"


def summary_line(
    diagnostics: Sequence[Diagnostic], files_checked: int, unreadable: int = 0, unverified: int = 0
) -> str:
    """``Found 2 errors, 1 warning in 2 files (3 checked)``, or ``All checks passed (3 files)``.

    With files that could not be read (``unreadable``), or constraints the solver could
    not take (``unverified``, C411, even when that code is not shown), nothing
    "passed": ``No findings in 3 files; 1 file could not be read; 2 constraints not
    verified``.
    """
    checked = _count(files_checked, "file", "files")
    caveats = ""
    if unreadable:
        caveats += f"; {_count(unreadable, 'file', 'files')} could not be read"
    if unverified:
        caveats += f"; {_count(unverified, 'constraint', 'constraints')} not verified"
    if caveats:
        if not diagnostics:
            return f"No findings in {checked}{caveats}"
        return _found(diagnostics, checked) + caveats
    if not diagnostics:
        return f"All checks passed ({checked})"
    return _found(diagnostics, checked)


def _found(diagnostics: Sequence[Diagnostic], checked: str) -> str:
    by_severity = Counter(d.severity for d in diagnostics)
    parts = [
        _count(by_severity[s], *_NOUNS.get(s, (s.label, s.label))) for s in sorted(by_severity)
    ]
    files = _count(len({d.span.uri for d in diagnostics}), "file", "files")
    return f"Found {', '.join(parts)} in {files} ({checked} checked)"


def statistics(diagnostics: Sequence[Diagnostic]) -> str:
    """One line per code: count, code and name, most frequent first."""
    counts = Counter(d.code for d in diagnostics)
    rows = sorted(counts.items(), key=lambda item: (-item[1], item[0].code))
    width = max((len(str(n)) for n in counts.values()), default=1)
    return "".join(f"{n:>{width}}  {code.code}  {code.slug}\n" for code, n in rows)
