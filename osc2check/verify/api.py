"""``solve``: the witness of one scenario, for the runner and other tools."""

from __future__ import annotations

from dataclasses import dataclass

from osc2check.diagnostics import Diagnostic
from osc2check.verify.check import verify_program
from osc2check.verify.witness import Witness


@dataclass(frozen=True)
class Unsolvable:
    """Why a scenario has no witness: its conflicts, or an inconclusive solver."""

    scenario: str
    status: str  # "unsat" | "unknown" | "not-found" | "not-checked"
    diagnostics: tuple[Diagnostic, ...]


def solve(analysis, scenario: str | None = None, seed: int = 0,
          uri: str | None = None) -> Witness | Unsolvable:
    """The witness of ``scenario`` (default: the first scenario of the first file).

    ``analysis`` comes from ``osc2check.analyze``; the same seed always gives the
    same witness, different seeds spread over the scenario's feasible space.
    """
    uri = uri or next(iter(analysis.programs), None)
    program = analysis.programs.get(uri) if uri is not None else None
    if program is None:
        return Unsolvable(scenario or "", "not-found", ())
    errors = tuple(d for d in analysis.diagnostics if d.span.uri == uri
                   and d.severity.name == "ERROR")
    if errors and uri not in analysis.verified:
        return Unsolvable(scenario or "", "not-checked", errors)
    result = verify_program(program, seed=seed, scenario=scenario)
    if not result.scenarios:
        return Unsolvable(scenario or "", "not-found", ())
    first = result.scenarios[0]
    if first.witness is not None:
        return first.witness
    own = tuple(d for d in result.diagnostics if d.severity.name == "ERROR")
    return Unsolvable(first.scenario.name, first.outcome.status, own)
