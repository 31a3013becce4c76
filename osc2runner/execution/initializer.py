"""The start of a run: every body actor where, and as fast as, the checker's witness says.

The checker placed every actor (``osc2check.verify.placement``) and drew the
witness for the seed: its lane and road, where that is in the world (``x``,
``y``, ``heading``: the pose on the lane's centre moved by its offset ``t``) and
its speed. :func:`start_specs` turns that into the world's
:class:`~osc2runner.sim.ActorSpec` list; the bodies come from the actors'
catalogue rows (``instance.bodies``). Nothing is placed twice.
"""

from __future__ import annotations

from osc2runner.errors import RunProblem
from osc2runner.instance.actors import Actor
from osc2runner.sim import ActorSpec

__all__ = ["start_specs"]


def start_specs(actors: list[Actor]) -> tuple[list[ActorSpec], list[RunProblem]]:
    """The world specs of the body actors, in declaration order, and any that lack a start."""
    specs: list[ActorSpec] = []
    problems: list[RunProblem] = []
    for actor in actors:
        if not actor.has_body:
            continue
        start, params = actor.start, actor.params
        if start is None or params is None:
            problems.append(
                RunProblem(
                    f"the checker's witness has no start for `{actor.name}`",
                    actor.symbol.name_span,
                )
            )
            continue
        if actor.location is not None:
            x, y, yaw = actor.location
            specs.append(ActorSpec(actor.name, params, x=x, y=y, yaw=yaw))
            continue
        specs.append(
            ActorSpec(
                actor.name,
                params,
                s=start.road_s,
                lane=start.lane_ref if start.road else None,
                offset=float(start.t),
                x=start.x,
                y=start.y,
                yaw=start.heading,
                speed=float(start.speed),
            )
        )
    return specs, problems
