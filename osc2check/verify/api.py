"""``solve``: the witness of one scenario, for the runner and other tools."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from osc2check.diagnostics import Diagnostic
from osc2check.verify.check import verify_program
from osc2check.verify.witness import Witness

if TYPE_CHECKING:
    from osc2check.analysis import Analysis


@dataclass(frozen=True)
class Unsolvable:
    """Why a scenario has no witness: its conflicts, or an inconclusive solver."""

    scenario: str
    status: str  # "unsat" | "unknown" | "not-found" | "not-checked"
    diagnostics: tuple[Diagnostic, ...]


def solve(
    analysis: Analysis, scenario: str | None = None, seed: int = 0, uri: str | None = None
) -> Witness | Unsolvable:
    """The witness of ``scenario`` (default: the first scenario of the first file).

    ``analysis`` comes from ``osc2check.analyze``; the same seed always gives the
    same witness, different seeds spread over the scenario's feasible space.
    """
    uri = uri or next(iter(analysis.programs), None)
    program = analysis.programs.get(uri) if uri is not None else None
    if uri is None or program is None:
        return Unsolvable(scenario or "", "not-found", ())
    errors = tuple(
        d for d in analysis.diagnostics if d.span.uri == uri and d.severity.name == "ERROR"
    )
    if errors and uri not in analysis.verified:
        return Unsolvable(scenario or "", "not-checked", errors)
    # The analysis verified the file already (unless told not to): draw the witness
    # from its result instead of lowering and solving the scenario again.
    result = analysis.verified.get(uri)
    if result is None or (
        scenario is not None and not any(r.scenario.name == scenario for r in result.scenarios)
    ):
        options = analysis.options
        result = verify_program(
            program,
            seed=None,
            scenario=scenario,
            default_map=options.default_map if options is not None else "default",
            maps=options.maps if options is not None else None,
        )
    chosen = [r for r in result.scenarios if scenario is None or r.scenario.name == scenario]
    if not chosen:
        return Unsolvable(scenario or "", "not-found", ())
    first = chosen[0]
    witness = first.witness_for(seed)
    if witness is not None:
        return witness
    own = tuple(d for d in result.diagnostics if d.severity.name == "ERROR" and d.span.uri == uri)
    return Unsolvable(first.scenario.name, first.outcome.status, own)
