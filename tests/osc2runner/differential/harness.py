"""One generated case through the checker and the runner, and what they must agree on.

* The checker **refuses** a case when it reports an error, or A308 (a form the runner
  does not execute). Then the runner must refuse it before tick 0 with the very same
  findings, and nothing of its own.
* The checker **accepts** it otherwise. Then the runner must run it to an outcome:
  no internal error, no refusal of its own (a ``RunProblem``: a refusal the checker
  never announced), the outcome ``success`` (the generated scenarios are
  satisfiable and physically easy), every argument of every started call read
  (``osc2check.semantics.bindings.ArgumentReads``: a binding nobody read is a silent
  drop), and the tested modifier's effect in the telemetry (:mod:`.properties`).

The analysed library is the process's (``osc2check.semantics.stdlib`` keeps it), so
a case costs its own file's analysis and its run only.
"""

from __future__ import annotations

from dataclasses import dataclass

from osc2check import codes
from osc2check.analysis import Analysis, SourceInput, analyze
from osc2check.diagnostics import Severity
from osc2check.semantics.bindings import ArgumentReads, recording_reads
from osc2runner.errors import ScenarioError
from osc2runner.runner import Checked, check_analysis, execute, prepare_checked
from tests.osc2runner.differential import properties
from tests.osc2runner.differential.cases import Case
from tests.osc2runner.differential.drops import dropped, reading

__all__ = ["Disagreement", "Verdict", "unannounced", "verdict"]

URI = "differential.osc"


class Disagreement(AssertionError):
    """The checker and the runner disagree on a case, or its effect is missing."""


@dataclass(frozen=True)
class Verdict:
    refused: tuple[str, ...]  # the checker's refusing codes ('' when it accepted)
    status: str  # the runner's outcome, or "refused"
    unchecked: str | None = None  # why the property was not read (None: it was)


def refusing(analysis: Analysis) -> list[str]:
    """The checker's findings that stop a run: errors, and A308."""
    return sorted(
        f"{d.code.code}@{d.span.line}:{d.span.column}"
        for d in analysis.diagnostics
        if d.severity is Severity.ERROR or d.code is codes.NOT_EXECUTED
    )


def unannounced(exc: ScenarioError, text: str) -> None:
    """Raise Disagreement when the runner's refusal has messages the checker never gave."""
    if exc.problems:
        raise Disagreement(
            "the runner refused with messages the checker never gave: "
            + "; ".join(str(p) for p in exc.problems)
            + f"\n{text}"
        ) from None


def verdict(case: Case) -> Verdict:
    """Run ``case`` through both tools; raises :class:`Disagreement` (or
    ``PropertyFailed``) when they disagree or the effect is missing."""
    text = case.text()
    with reading() as reads:  # the start placement reads while the checker analyses
        analysis = analyze([SourceInput(URI, text)])
    refused = refusing(analysis)
    try:
        checked = check_analysis(analysis, URI)
    except ScenarioError as exc:
        unannounced(exc, text)
        got = sorted(f"{d.code.code}@{d.span.line}:{d.span.column}" for d in exc.diagnostics)
        if got != refused:
            raise Disagreement(
                f"the runner refused with {got}, the checker {refused}\n{text}"
            ) from None
        return Verdict(tuple(refused), "refused")
    if refused:
        raise Disagreement(f"the checker refused ({refused}) and the runner did not\n{text}")
    return _run(case, checked, text, reads)


def _run(case: Case, checked: Checked, text: str, reads: ArgumentReads) -> Verdict:
    try:
        with recording_reads(reads):
            prepared = prepare_checked(checked)
            result = execute(prepared, duration=case.limit)
    except ScenarioError as exc:
        raise Disagreement(
            "the runner refused a case the checker accepted: "
            + "; ".join(str(p) for p in exc.problems)
            + f"\n{text}"
        ) from None
    except Exception as exc:  # an internal error is what this finds
        raise Disagreement(f"internal error: {type(exc).__name__}: {exc}\n{text}") from exc
    if result.outcome.status != "success":
        raise Disagreement(f"{result.outcome.status}: {result.outcome.reason}\n{text}")
    lost = dropped(checked.analysis, reads)
    if lost:
        raise Disagreement(f"arguments the run never read: {', '.join(lost)}\n{text}")
    observed = properties.Observed(case, result, case.tested_line)
    try:
        unchecked = properties.check(observed)
    except properties.PropertyFailed as exc:
        raise properties.PropertyFailed(f"{exc}\n{text}") from None
    return Verdict((), result.outcome.status, unchecked)
