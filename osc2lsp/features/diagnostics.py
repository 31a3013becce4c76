"""Diagnostics of a document: exactly what ``osc2check`` reports for it.

The analysis (``osc2check.analysis.analyze``) already applied suppression
comments and the configuration (``select``/``ignore``/``strict`` from
``[tool.osc2check]`` and the client's settings), so this only picks the
document's own findings and names a result, so that a client is not sent
the same findings twice (pushed or pulled).
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterable

from osc2check.diagnostics import Diagnostic
from osc2lsp.snapshot import Snapshot


def diagnostics(snapshot: Snapshot) -> list[Diagnostic]:
    """The findings in the snapshot's document, sorted by position."""
    return list(snapshot.diagnostics)


def result_id(found: Snapshot | Iterable[Diagnostic]) -> str:
    """A name for a diagnostics result: equal ids mean identical findings."""
    items = found.diagnostics if isinstance(found, Snapshot) else found
    digest = hashlib.sha1()
    for d in items:
        span = d.span
        related = "|".join(
            f"{r.span.uri}:{r.span.start}:{r.span.end}:{r.message}" for r in d.related
        )
        digest.update(
            f"{span.start}:{span.end}:{span.line}:{span.column}:{d.code.code}:{d.severity}:"
            f"{d.message}:{related}\n".encode()
        )
    return digest.hexdigest()[:16]
