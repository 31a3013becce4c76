"""The scenario instance a run executes: the witness's values, the actors, the map.

:func:`instantiate` draws the checker's witness for the seed (``osc2check.solve``,
the only source of values and starts), builds the actors from its catalogue
rows and loads the map it placed them on.
"""

from __future__ import annotations

from dataclasses import dataclass

from osc2check import codes
from osc2check.analysis import Analysis
from osc2check.semantics.symbols import Symbol
from osc2check.verify.api import Unsolvable, solve
from osc2check.verify.witness import Witness
from osc2check.world.errors import MapError, UnknownMapError
from osc2check.world.network import RoadNetwork
from osc2runner.errors import RunProblem, ScenarioError, refused_by
from osc2runner.instance.actors import Actor, scenario_actors
from osc2runner.instance.locations import object_locations
from osc2runner.instance.roads import network_for
from osc2runner.instance.values import ScenarioValues

__all__ = ["CARLA_CONTENT", "ScenarioInstance", "instantiate"]

#: CARLA's content the toolkit has no stand-in for (its maps): the checker warns, and
#: the runner refuses it with the same code and message (CARLA's world poses and
#: trajectory files are A308, osc2check.capabilities)
CARLA_CONTENT = (codes.CARLA_MAP,)


@dataclass
class ScenarioInstance:
    """One concrete instance of a scenario: the witness and what the runner builds from it."""

    scenario: Symbol
    witness: Witness
    values: ScenarioValues
    actors: list[Actor]
    network: RoadNetwork


def instantiate(
    analysis: Analysis, uri: str, scenario: Symbol, seed: int, witness: Witness | None = None
) -> ScenarioInstance:
    """The instance of ``scenario`` for ``seed``; ScenarioError when it has none.

    ``witness`` is the one to run instead of the seed's own (a campaign's witness
    drawn inside a coverage bin); None draws the seed's.
    """
    model = analysis.programs[uri].model
    drawn = witness if witness is not None else solve(analysis, scenario.name, seed, uri)
    if isinstance(drawn, Unsolvable):
        span = scenario.name_span
        if drawn.status == "unsat":
            raise ScenarioError(
                [RunProblem(f"scenario `{scenario.name}` has no solution", span)],
                diagnostics=drawn.diagnostics,
                texts=analysis.texts,
            )
        raise ScenarioError(
            [
                RunProblem(
                    f"the solver could not decide scenario `{scenario.name}` "
                    f"({drawn.status}); nothing to run",
                    span,
                )
            ],
            diagnostics=drawn.diagnostics,
            texts=analysis.texts,
        )
    witness = drawn
    # CARLA's content the toolkit has no stand-in for: refused with the checker's finding
    for code in CARLA_CONTENT:
        refusal = refused_by(analysis, uri, code)
        if refusal is not None:
            raise refusal
    if witness.unused_map is not None:
        raise ScenarioError(
            [
                RunProblem(
                    f"map `{witness.unused_map}` cannot be used by the runner: "
                    + "; ".join(witness.notes),
                    scenario.name_span,
                )
            ]
        )
    values = ScenarioValues(model, scenario, witness)
    actors = scenario_actors(model, scenario, values, witness)
    locations, problems = object_locations(model, scenario, values)
    if problems:
        raise ScenarioError(problems)
    for actor in actors:
        actor.location = locations.get(actor.name)
    try:
        network = network_for(witness)
    except (MapError, UnknownMapError) as exc:
        raise ScenarioError([RunProblem(str(exc), scenario.name_span)]) from None
    return ScenarioInstance(scenario, witness, values, actors, network)
