"""Many generated cases through the checker and the runner at once, lean.

The checker's cost of a case is mostly fixed (the file's analysis), so the cases of a
chunk are analysed as the scenarios ``top0``, ``top1``, ... of one file, and the
runner compiles each accepted one from that analysis (its tree, its actors and their
start placement from the witness: everything before tick 0). A finding is the case's
when it lies in the case's lines. The runner refuses a whole file with a refusing
finding (an error, or A308), and the checker verifies no scenario of a file with an
error, so the cases a batch refuses are set aside and the rest analysed again, until a
batch has none: then all its cases are accepted, and each must compile.

Agreement, per case: refused by the checker ⇒ the runner refuses before tick 0 with
the checker's findings and nothing of its own; accepted ⇒ the runner compiles it with
no refusal of its own (a ``RunProblem``: a message the checker never gave) and no
internal error. Running a case is :func:`.harness.verdict`'s, for a few of them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from osc2check import codes
from osc2check.analysis import SourceInput, analyze
from osc2check.diagnostics import Diagnostic, Severity
from osc2runner.errors import ScenarioError
from osc2runner.runner import check_analysis, compile_checked
from tests.osc2runner.differential.cases import Case
from tests.osc2runner.differential.harness import Disagreement, unannounced

__all__ = ["Outcome", "agree"]

URI = "differential_batch.osc"
HEADER = "import osc.standard\n"


@dataclass
class Outcome:
    """What a chunk's cases came to: the accepted ones (compiled) by index, and the
    refused ones with the checker's refusing codes."""

    accepted: list[int] = field(default_factory=list)
    refused: dict[int, list[str]] = field(default_factory=dict)


def _scenario(case: Case, name: str) -> str:
    """The case's scenario, named ``name``, without the file's import."""
    text = case.text()
    head, _, rest = text.partition("scenario top:")
    assert head.strip() == HEADER.strip(), head
    return f"scenario {name}:{rest}"


def _refusing(d: Diagnostic) -> bool:
    return d.severity is Severity.ERROR or d.code is codes.NOT_EXECUTED


def agree(cases: Sequence[Case]) -> Outcome:
    """Check and compile ``cases`` (see the module docstring); raises Disagreement."""
    outcome = Outcome()
    pending = list(range(len(cases)))
    while pending:
        lines = [HEADER]
        where: list[tuple[int, int, int]] = []  # (first line, last line, case index)
        for i in pending:
            block = _scenario(cases[i], f"top{i}")
            first = sum(part.count("\n") for part in lines) + 1
            lines.append(block)
            where.append((first, first + block.count("\n") - 1, i))
        text = "".join(lines)
        analysis = analyze([SourceInput(URI, text)])
        found: dict[int, list[Diagnostic]] = {i: [] for i in pending}
        for d in analysis.diagnostics:
            if not _refusing(d):
                continue
            owner = next((i for lo, hi, i in where if lo <= d.span.line <= hi), None)
            if owner is None:
                raise Disagreement(f"a finding outside every case: {d}\n{text}")
            found[owner].append(d)
        refused = [i for i in pending if found[i]]
        for i in refused:
            outcome.refused[i] = sorted(d.code.code for d in found[i])
            _runner_refuses(analysis, found[i], cases[i])
        if not refused:
            for i in pending:
                _runner_compiles(analysis, f"top{i}", cases[i])
                outcome.accepted.append(i)
            break
        pending = [i for i in pending if not found[i]]
    return outcome


def _runner_refuses(analysis, findings: list[Diagnostic], case: Case) -> None:  # type: ignore[no-untyped-def]
    """The runner refuses the file before tick 0 with the checker's findings, the
    case's among them, and no message of its own."""
    try:
        check_analysis(analysis, URI)
    except ScenarioError as exc:
        unannounced(exc, case.text())
        got = {(d.code.code, d.span.line, d.span.column, d.message) for d in exc.diagnostics}
        want = {(d.code.code, d.span.line, d.span.column, d.message) for d in findings}
        if not want <= got:
            raise Disagreement(
                f"the runner refused without the checker's {sorted(want - got)}\n{case.text()}"
            ) from None
        return
    raise Disagreement(f"the checker refused and the runner did not\n{case.text()}")


def _runner_compiles(analysis, name: str, case: Case) -> None:  # type: ignore[no-untyped-def]
    """The runner compiles an accepted case up to tick 0, refusing nothing."""
    try:
        compile_checked(check_analysis(analysis, URI, scenario=name))
    except ScenarioError as exc:
        raise Disagreement(
            "the runner refused a case the checker accepted: "
            + "; ".join(str(p) for p in exc.problems)
            + "".join(f"; {d.code.code}: {d.message}" for d in exc.diagnostics)
            + f"\n{case.text()}"
        ) from None
    except Exception as exc:  # an internal error is what this finds
        raise Disagreement(f"internal error: {type(exc).__name__}: {exc}\n{case.text()}") from exc
