"""The messages of the S codes (suppressions and tooling) built outside
``osc2check.suppress``: a check that ran out of its memory budget."""

from __future__ import annotations

from typing import TYPE_CHECKING

from osc2check import codes
from osc2check.diagnostics import Diagnostic
from osc2check.messages.parts import diagnostic
from osc2check.source import Span

if TYPE_CHECKING:
    from osc2check.memory import Element


def memory_budget(span: Span, element: Element, limit_mib: int | None) -> Diagnostic:
    where = f"{element.span.uri}:{element.span.line}:{element.span.column}"
    return diagnostic(
        codes.MEMORY_BUDGET,
        f"the check of this file needs more memory than its budget ({_mib(limit_mib)}): it "
        f"ran out while {element.what} at {where}, and what follows was not checked; raise "
        "`--memory-limit` (`memory-limit` in the configuration) or split the file",
        span,
    )


def _mib(limit_mib: int | None) -> str:
    if limit_mib is None:
        return "the machine's memory"
    return f"{limit_mib // 1024} GiB" if limit_mib % 1024 == 0 else f"{limit_mib} MiB"
