"""What goes wrong before a run starts, reported with its place in the source."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from osc2check.codes import Code, Severity
from osc2check.source import Span
from osc2check.syntax import ast

if TYPE_CHECKING:
    from osc2check.analysis import Analysis
    from osc2check.diagnostics import Diagnostic

__all__ = ["CompileProblem", "RunProblem", "ScenarioError", "problem", "refused_by"]


@dataclass(frozen=True, slots=True)
class RunProblem:
    """One reason a scenario cannot run: a message and, when known, where."""

    message: str
    span: Span | None = None

    def __str__(self) -> str:
        if self.span is None:
            return f"error: {self.message}"
        s = self.span
        return f"{s.uri}:{s.line}:{s.column}: error: {self.message}"


def problem(message: str, node: ast.Node | None = None) -> RunProblem:
    return RunProblem(message, node.span if node is not None else None)


class ScenarioError(Exception):
    """The scenario cannot run (input error, exit status 2); ``problems`` says why.

    ``diagnostics`` holds the checker's error diagnostics when the checker
    rejected the input, ``texts`` the sources to render them with.
    """

    def __init__(
        self,
        problems: Sequence[RunProblem],
        diagnostics: Sequence[Diagnostic] = (),
        texts: dict[str, str] | None = None,
    ) -> None:
        self.problems = list(problems)
        self.diagnostics = list(diagnostics)
        self.texts = dict(texts or {})
        first = self.problems[0] if self.problems else None
        count = len(self.problems) + len(self.diagnostics)
        summary = str(first) if first is not None else f"{count} error(s) in the input"
        super().__init__(summary)


class CompileProblem(Exception):
    """Raised inside the compiler for one problem; collected into a ScenarioError."""

    def __init__(self, message: str, node: ast.Node | None = None) -> None:
        super().__init__(message)
        self.problem = problem(message, node)


def refused_by(
    analysis: Analysis, uri: str, code: Code, span: Span | None = None
) -> ScenarioError | None:
    """The run refused with the checker's own finding of ``code`` in file ``uri`` (at
    ``span`` when given): the same code and message the checker warned with, as an error.
    None when the checker reported none."""
    found = [
        d
        for d in analysis.diagnostics
        if d.code == code and d.span.uri == uri and (span is None or d.span == span)
    ]
    if not found:
        return None
    errors = [replace(d, severity=Severity.ERROR) for d in found]
    return ScenarioError([], diagnostics=errors, texts=analysis.texts)
