"""Silent drops: arguments the checker bound that no stage of a run read.

While a run is recorded (:func:`reading`), the start placement and the runner's
behaviours note each argument they read (``osc2check.semantics.bindings``), and the
runner notes each action whose phase started. :func:`dropped` then lists every
argument *as written* — of each started action, of each modifier in its ``with:``,
its ``duration`` — that nothing read. The list it compares against comes from the
checker's binding table, not from the reads, so a stage that reads nothing cannot
pass: every written argument of a started call must be read.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from osc2check.analysis import Analysis
from osc2check.semantics.bindings import ArgumentReads, recording_reads
from osc2check.syntax import ast
from osc2check.syntax.walk import walk

__all__ = ["checked_arguments", "dropped", "reading"]


@contextmanager
def reading() -> Iterator[ArgumentReads]:
    """Record the reads of the run inside the block."""
    with recording_reads() as reads:
        yield reads


def checked_arguments(
    analysis: Analysis, reads: ArgumentReads
) -> Iterator[tuple[ast.Node, str, str]]:
    """(call, parameter, where) of every argument written for a started action or one of
    its modifiers, in every file of the analysis."""
    for program in analysis.programs.values():
        model = program.model
        for result in program.files.values():
            if result.ast is None:
                continue
            for node in walk(result.ast):
                if not isinstance(node, ast.Invocation) or id(node) not in reads.started:
                    continue
                calls: list[ast.Invocation] = [node]
                calls += [m for m in node.with_members if isinstance(m, ast.Invocation)]
                for call in calls:
                    binding = model.binding(call)
                    if binding is None:
                        continue
                    for bound in binding.written():
                        where = f"{call.span.uri}:{bound.span.line}:{bound.span.column}"
                        yield call, bound.name, f"{where} {call.name.text}({bound.name})"


def dropped(analysis: Analysis, reads: ArgumentReads) -> list[str]:
    """The arguments of started calls that no stage read (see the module docstring)."""
    return sorted(
        where
        for call, name, where in checked_arguments(analysis, reads)
        if not reads.was_read(call, name)
    )
