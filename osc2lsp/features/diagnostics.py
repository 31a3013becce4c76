"""Diagnostics of a document: exactly what ``osc2check`` reports for it.

The analysis (``osc2check.analysis.analyze``) already applied suppression
comments and the configuration (``select``/``ignore``/``strict`` from
``[tool.osc2check]`` and the client's settings), so this only picks the
document's own findings and names the result for pull requests.
"""

from __future__ import annotations

import hashlib

from osc2check.diagnostics import Diagnostic
from osc2lsp.snapshot import Snapshot


def diagnostics(snapshot: Snapshot) -> list[Diagnostic]:
    """The findings in the snapshot's document, sorted by position."""
    return list(snapshot.diagnostics)


def result_id(snapshot: Snapshot) -> str:
    """A name for a diagnostics result: equal ids mean identical findings."""
    digest = hashlib.sha1()
    for d in snapshot.diagnostics:
        digest.update(
            f"{d.span.start}:{d.span.end}:{d.code.code}:{d.severity}:{d.message}\n".encode()
        )
    return digest.hexdigest()[:16]
