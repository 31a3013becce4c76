"""The lowering of one scenario, its steps in order: the instance tree with its
parameters and constraints (``parameters``), the actors' start placement with the map
modifiers (``placement``), the timing of its behaviour (``timing``), then the fields'
defaults, attached to the variables the steps created.
"""

from __future__ import annotations

from collections.abc import Mapping

from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol
from osc2check.source import Span
from osc2check.verify import timing
from osc2check.verify.parameters import lower_parameters
from osc2check.verify.placement import lower_placement
from osc2check.verify.problem import ConstraintProblem
from osc2check.verify.terms import Declarations, TextOf


def lower_scenario(
    model: Model,
    scenario: Symbol,
    text_of: TextOf,
    default_map: str = "default",
    member_decls: Declarations | None = None,
    maps: Mapping[str, str] | None = None,
    open_categories: bool = False,
) -> ConstraintProblem:
    """The constraint problem of ``scenario`` as a top-level instance, placement included.

    ``member_decls`` (from ``member_declarations(model)``) can be shared by the
    scenarios of one model; ``open_categories``: vehicles whose category nothing
    constrains may be of any category (``placement.PlacementLowerer``).
    """
    span = scenario.name_span or Span("", 1, 1, 1, 1)
    problem = ConstraintProblem(scenario.name, span)
    lowerer = lower_parameters(model, scenario, problem, text_of, member_decls)
    problem.strings = {v: k for k, v in lowerer.strings.items()}
    problem.placement = lower_placement(
        lowerer, scenario, default_map, maps, open_categories=open_categories
    )
    timing.lower_timing(lowerer, scenario)
    if problem.timing is None:  # (the timing's constraints were left out)
        problem.timing = timing.timing_plan(lowerer, scenario)
    lowerer.attach_defaults()
    problem.strings = {v: k for k, v in lowerer.strings.items()}
    return problem
