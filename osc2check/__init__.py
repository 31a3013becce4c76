"""osc2check: the analysis core and static checker for ASAM OpenSCENARIO DSL 2.x.

Public entry points (imported on first use, so that ``import osc2check`` stays cheap):

- ``parse(text, uri) -> ParseResult``: tolerant parsing, never raises;
- ``analyze(sources, options) -> Analysis``: names, types, units, constraints, placement;
- ``solve(analysis, scenario=None, seed=0) -> Witness | Unsolvable``: the concrete instance
  the runner executes.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from osc2check import classcode

classcode.install()  # before the modules that declare dataclasses are imported

if TYPE_CHECKING:  # what __getattr__ gives, as type checkers should see it
    from osc2check.analysis import AnalysisOptions, SourceInput, analyze
    from osc2check.syntax import parse
    from osc2check.verify.api import solve

__all__ = ["AnalysisOptions", "SourceInput", "analyze", "parse", "solve"]


def __getattr__(name: str) -> object:
    if name == "parse":
        from osc2check.syntax import parse

        return parse
    if name in ("analyze", "AnalysisOptions", "SourceInput"):
        from osc2check import analysis

        return getattr(analysis, name)
    if name == "solve":
        from osc2check.verify.api import solve

        return solve
    raise AttributeError(name)
