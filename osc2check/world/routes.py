"""Routes through the lane graph, and what lies ahead of a point.

A route starts on a lane and follows successors (:attr:`RoadNetwork.successors`).
Where a lane has one successor there is nothing to decide. At a fork (a
junction, a lane that splits) the next choice is taken from ``choices``: an
index into the successors, or a turn word (``straight``, ``left``, ``right``,
``u-turn``) matched against each successor's turn, i.e. its change of heading
from entry to exit (within 30 degrees: straight; beyond 150: u-turn). When the
choices run out, a fork on the way to the next of ``towards`` (road ids the
route must pass, in order) takes the successor that leads there; otherwise a
seed picks uniformly among the successors (``random.Random``, so the same seed
gives the same route); without a seed the route ends before the fork. A route
also ends at a lane without successors or once it is ``max_length`` long
(loops, such as a roundabout, are allowed).
"""

from __future__ import annotations

import heapq
import math
import random
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from osc2check.world.network import LaneRef, RoadNetwork
from osc2check.world.paths import LanePath, join_paths, lane_path

__all__ = [
    "LaneSpan",
    "Route",
    "Turn",
    "TurnChoice",
    "plan_route",
    "reachable_lanes",
    "turn_along",
    "turn_of",
]

Turn = Literal["straight", "left", "right", "u-turn"]
TurnChoice = Turn | int

_STRAIGHT = math.radians(30.0)
_U_TURN = math.radians(150.0)


@dataclass(frozen=True, eq=False)
class Route:
    """A chain of lanes and its concatenated centre line.

    ``decisions`` lists the turn taken at each fork, in order; ``end`` says why the
    route stops: ``length`` (``max_length`` reached), ``dead_end`` (no successor)
    or ``fork`` (a fork with no choice left and no seed).
    """

    lanes: tuple[LaneRef, ...]
    path: LanePath
    decisions: tuple[Turn, ...]
    end: Literal["length", "dead_end", "fork"]


@dataclass(frozen=True, slots=True)
class LaneSpan:
    """A stretch ``[s_from, s_to]`` of a lane (in road ``s``; ``s_from`` is where traffic
    enters it), reached ``distance`` m after the query point."""

    lane: LaneRef
    s_from: float
    s_to: float
    distance: float


def turn_of(network: RoadNetwork, ref: LaneRef) -> Turn:
    """How a vehicle turns driving lane ``ref`` from entry to exit."""
    return turn_along(lane_path(network, ref))


def turn_along(path: LanePath) -> Turn:
    """How a vehicle turns driving ``path`` from its start to its end."""
    change = float(path.heading[-1] - path.heading[0])
    change = (change + math.pi) % (2.0 * math.pi) - math.pi
    if abs(change) <= _STRAIGHT:
        return "straight"
    if abs(change) >= _U_TURN:
        return "u-turn"
    return "left" if change > 0 else "right"


def plan_route(
    network: RoadNetwork,
    start: LaneRef,
    choices: Sequence[TurnChoice] = (),
    seed: int | None = None,
    max_length: float = 2000.0,
    towards: Sequence[str] = (),
) -> Route:
    """The route from lane ``start`` (see the module docstring for the rules).

    Raises:
        ValueError: a choice names a turn no successor makes, or an index out of range.
    """
    network.lane(start)  # KeyError for a lane that does not exist
    rng = random.Random(seed) if seed is not None else None
    pending = list(choices)
    targets = [road for road in towards if road != start.road]
    lanes = [start]
    decisions: list[Turn] = []
    length = lane_path(network, start).length
    end: Literal["length", "dead_end", "fork"] = "length"
    while length < max_length:
        options = network.successors.get(lanes[-1], ())
        if not options:
            end = "dead_end"
            break
        if len(options) == 1:
            chosen = options[0]
        elif pending:
            chosen = _choose(network, lanes[-1], options, pending.pop(0))
        elif targets and (leading := [r for r in options if _leads_to(network, r, targets[0])]):
            chosen = leading[0] if rng is None else leading[rng.randrange(len(leading))]
        elif rng is not None:
            chosen = options[rng.randrange(len(options))]
        else:
            end = "fork"
            break
        if len(options) > 1:
            decisions.append(turn_of(network, chosen))
        lanes.append(chosen)
        while targets and targets[0] == chosen.road:
            targets.pop(0)
        length += lane_path(network, chosen).length
    path = join_paths([lane_path(network, ref) for ref in lanes])
    return Route(tuple(lanes), path, tuple(decisions), end)


def _leads_to(network: RoadNetwork, ref: LaneRef, road: str, limit: int = 400) -> bool:
    """Whether following successors from lane ``ref`` reaches road ``road``."""
    seen = {ref}
    frontier = deque([ref])
    while frontier and len(seen) < limit:
        current = frontier.popleft()
        if current.road == road:
            return True
        for nxt in network.successors.get(current, ()):
            if nxt not in seen:
                seen.add(nxt)
                frontier.append(nxt)
    return False


def _choose(
    network: RoadNetwork, at: LaneRef, options: tuple[LaneRef, ...], choice: TurnChoice
) -> LaneRef:
    if isinstance(choice, int):
        if not 0 <= choice < len(options):
            raise ValueError(f"choice {choice} after {at}: only {len(options)} successors")
        return options[choice]
    turns = [turn_of(network, ref) for ref in options]
    for ref, turn in zip(options, turns, strict=True):
        if turn == choice:
            return ref
    raise ValueError(f"no `{choice}` after {at}; the successors turn {', '.join(turns)}")


def reachable_lanes(
    network: RoadNetwork, ref: LaneRef, s: float, distance: float
) -> tuple[LaneSpan, ...]:
    """Every lane stretch a vehicle at ``s`` on ``ref`` can reach within ``distance`` m.

    Distances are along lane centre lines; each lane appears once, with the
    shortest way to it. The first span is the rest of ``ref`` itself.
    """
    path = lane_path(network, ref)
    travelled = path.distance_at(s)
    spans: dict[LaneRef, LaneSpan] = {}
    left = path.length - travelled
    spans[ref] = LaneSpan(ref, s, _s_after(network, ref, s, min(distance, left)), 0.0)
    queue: list[tuple[float, LaneRef]] = []
    if left < distance:
        for nxt in network.successors.get(ref, ()):
            heapq.heappush(queue, (left, nxt))
    while queue:
        start, current = heapq.heappop(queue)
        if current in spans:
            continue
        cur_path = lane_path(network, current)
        cur_lane = network.lane(current)
        cur_section = network.section(current)
        entry = cur_section.s0 if cur_lane.direction > 0 else cur_section.s1
        budget = distance - start
        spans[current] = LaneSpan(
            current, entry, _s_after(network, current, entry, min(budget, cur_path.length)), start
        )
        if cur_path.length < budget:
            for nxt in network.successors.get(current, ()):
                if nxt not in spans:
                    heapq.heappush(queue, (start + cur_path.length, nxt))
    return tuple(spans.values())


def _s_after(network: RoadNetwork, ref: LaneRef, s: float, ahead: float) -> float:
    """Road ``s`` reached ``ahead`` m of centre line after ``s`` on lane ``ref``."""
    path = lane_path(network, ref)
    target = path.distance_at(s) + ahead
    return float(np.interp(target, path.distance, path.s))
