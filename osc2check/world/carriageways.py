"""Carriageways: the roads a scenario's actors start on, measured the way a driver sees them.

The checker places actors with a few numbers per actor (a lane number, a
longitudinal position, a lateral offset); on a map those numbers are taken on a
**carriageway**: the driving lanes of one road that travel one way, continued
across road-to-road links where the lanes simply go on (not through junctions).
On each carriageway:

* ``s`` is the distance along the roads' reference lines in the direction of
  travel, from the carriageway's entry (0) to its exit (``length``); for a leg
  driven against its road's ``s`` the road coordinate is ``length - s``;
* lane numbers are OSC2's: the driving lanes travelling that way at ``s``,
  counted from the rightmost (1) as seen in the direction of travel
  (:mod:`.numbering`), so they may change where lane sections change;
* ``ahead`` is how far a vehicle can drive on beyond the exit, through
  junctions and onto other roads (up to :data:`AHEAD_CAP`).

Roads inside junctions (connecting roads) belong to no carriageway: a scenario
starts its actors on the roads between junctions. A built-in straight map has
one carriageway, its road. Gaps between actors (``position(distance: d,
behind: b)``) are taken along one carriageway, so they may span road links but
not junctions.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, cast

from osc2check.world.network import LaneRef, RoadNetwork
from osc2check.world.numbering import driving_lanes_right_to_left
from osc2check.world.topology import Way, end_lanes, linked_ways, travel_ways, way_label

if TYPE_CHECKING:
    from osc2check.world.projection import WorldPose

__all__ = [
    "AHEAD_CAP",
    "Carriageway",
    "LanePiece",
    "Leg",
    "carriageway_of",
    "carriageways",
    "lane_at",
    "start_pose",
]

#: the farthest the room ahead of a carriageway's exit is followed (m)
AHEAD_CAP = 5000.0


@dataclass(frozen=True, slots=True)
class Leg:
    """One road of a carriageway, driven ``direction`` (+1 along its ``s``, -1 against)."""

    road: str
    direction: int
    start: float  # carriageway s where the leg begins
    length: float  # the road's length

    @property
    def end(self) -> float:
        return self.start + self.length

    def road_s(self, s: float) -> float:
        """The road coordinate of carriageway position ``s``."""
        local = min(max(s - self.start, 0.0), self.length)
        return local if self.direction > 0 else self.length - local

    def carriageway_s(self, road_s: float) -> float:
        """The carriageway position of road coordinate ``road_s``."""
        local = road_s if self.direction > 0 else self.length - road_s
        return self.start + local


@dataclass(frozen=True, slots=True)
class LanePiece:
    """A stretch ``[s0, s1]`` of a carriageway with ``count`` driving lanes travelling its
    way, the narrowest of them ``width`` m wide there; ``right`` and ``left`` are how
    much of the road lies beyond them on each side in the direction of travel (the
    narrowest along the stretch: sidewalks, shoulders, the other way's lanes, ...)."""

    s0: float
    s1: float
    count: int
    width: float
    right: float = 0.0
    left: float = 0.0


@dataclass(frozen=True, eq=False)
class Carriageway:
    """Driving lanes of one travel direction over one or more linked roads (see the module)."""

    index: int
    legs: tuple[Leg, ...]
    pieces: tuple[LanePiece, ...]
    length: float
    ahead: float
    exit_junction: str | None

    @property
    def label(self) -> str:
        """``road 3``, or ``road 3 (against s)``; ``roads 1, 2`` over several roads."""
        if len(self.legs) == 1:
            return way_label((self.legs[0].road, self.legs[0].direction))
        return "roads " + ", ".join(leg.road for leg in self.legs)

    @property
    def roads(self) -> tuple[str, ...]:
        return tuple(leg.road for leg in self.legs)

    def leg_at(self, s: float) -> Leg:
        """The leg containing carriageway position ``s`` (the later one at a joint)."""
        for leg in reversed(self.legs):
            if s >= leg.start:
                return leg
        return self.legs[0]

    def lane_count(self, s: float) -> int:
        """Driving lanes travelling this way at ``s`` (0 where there are none)."""
        for piece in self.pieces:
            if piece.s0 <= s <= piece.s1:
                return piece.count
        return 0

    @property
    def most_lanes(self) -> int:
        """The most driving lanes travelling this way anywhere along it."""
        return max((p.count for p in self.pieces), default=0)


def carriageways(network: RoadNetwork) -> tuple[Carriageway, ...]:
    """The carriageways of ``network`` (built on first use, then cached on it)."""
    cached = network.cache.get("carriageways")
    if cached is None:
        cached = network.cache["carriageways"] = _build(network)
    return cast(tuple[Carriageway, ...], cached)


def carriageway_of(network: RoadNetwork, road: str, direction: int) -> tuple[Carriageway, Leg]:
    """The carriageway that drives road ``road`` in ``direction``, and that leg of it.

    Raises:
        KeyError: the road is inside a junction or has no driving lane that way.
    """
    for cw in carriageways(network):
        for leg in cw.legs:
            if leg.road == road and leg.direction == direction:
                return cw, leg
    raise KeyError((road, direction))


def lane_at(network: RoadNetwork, cw: Carriageway, s: float, number: int) -> LaneRef:
    """The driving lane numbered ``number`` from the right at carriageway position ``s``.

    Raises:
        ValueError: no such lane there (the message says how many there are).
    """
    leg = cw.leg_at(s)
    road_s = leg.road_s(s)
    section = network.roads[leg.road].section_at(road_s)
    if leg.direction < 0 and road_s <= section.s0 and section.index > 0:
        # travelling against s, a section's start is where it is left: the earlier
        # section is the one entered there
        section = network.roads[leg.road].sections[section.index - 1]
    lanes = driving_lanes_right_to_left(network, leg.road, section.index, leg.direction)
    if not 1 <= number <= len(lanes):
        raise ValueError(
            f"{cw.label} has {len(lanes)} driving lane(s) at s={s:g}, so there is no lane {number}"
        )
    return lanes[number - 1]


def start_pose(
    network: RoadNetwork, cw: Carriageway, s: float, number: int, offset: float = 0.0
) -> tuple[LaneRef, float, WorldPose]:
    """Where an actor at carriageway position ``s`` in lane ``number`` (from the right),
    ``offset`` m left of the lane centre, stands: its lane, road ``s`` and world pose."""
    ref = lane_at(network, cw, s, number)
    road_s = cw.leg_at(s).road_s(s)
    return ref, road_s, network.lane_to_world(ref, road_s, offset)


# ---------------------------------------------------------------- building


def _build(network: RoadNetwork) -> tuple[Carriageway, ...]:
    legs = [way for way in travel_ways(network) if network.roads[way[0]].junction is None]
    candidates = set(legs)
    nxt: dict[Way, Way] = {}
    for leg in legs:
        after = linked_ways(network, leg, "next")
        if len(after) == 1:
            other = next(iter(after))
            if other in candidates and linked_ways(network, other, "previous") == {leg}:
                nxt[leg] = other
    has_previous = set(nxt.values())
    chains: list[list[Way]] = []
    used: set[Way] = set()
    for first in [leg for leg in legs if leg not in has_previous] + legs:
        if first in used:
            continue
        chain = [first]
        used.add(first)
        while chain[-1] in nxt and nxt[chain[-1]] not in used:
            chain.append(nxt[chain[-1]])
            used.add(chain[-1])
        chains.append(chain)
    return tuple(_carriageway(network, index, chain) for index, chain in enumerate(chains))


def _carriageway(network: RoadNetwork, index: int, chain: list[Way]) -> Carriageway:
    legs: list[Leg] = []
    pieces: list[LanePiece] = []
    start = 0.0
    for road_id, direction in chain:
        road = network.roads[road_id]
        leg = Leg(road_id, direction, start, road.length)
        legs.append(leg)
        sections = road.sections if direction > 0 else tuple(reversed(road.sections))
        for section in sections:
            # narrowest width of each driving lane travelling this way (row p of the
            # borders is lane p's left border, row p + 1 its right border)
            rows = [
                p
                for p, lane in enumerate(section.lanes)
                if lane.drivable and lane.direction == direction
            ]
            borders = section.borders
            widths = [float((borders[p] - borders[p + 1]).min()) for p in rows]
            count, width = len(widths), min(widths, default=0.0)
            above = float((borders[0] - borders[rows[0]]).min()) if rows else 0.0
            below = float((borders[rows[-1] + 1] - borders[-1]).min()) if rows else 0.0
            right, left = (below, above) if direction > 0 else (above, below)
            a, b = sorted((leg.carriageway_s(section.s0), leg.carriageway_s(section.s1)))
            if pieces and pieces[-1].count == count and abs(pieces[-1].s1 - a) < 1e-9:
                last = pieces[-1]
                pieces[-1] = LanePiece(
                    last.s0,
                    b,
                    last.count,
                    min(last.width, width),
                    min(last.right, right),
                    min(last.left, left),
                )
            else:
                pieces.append(LanePiece(a, b, count, width, right, left))
        start += road.length
    last_road, last_direction = chain[-1]
    road = network.roads[last_road]
    link = road.successor if last_direction > 0 else road.predecessor
    junction = link.element_id if link is not None and link.element_type == "junction" else None
    return Carriageway(
        index=index,
        legs=tuple(legs),
        pieces=tuple(p for p in pieces if p.s1 > p.s0),
        length=start,
        ahead=_ahead(network, last_road, last_direction),
        exit_junction=junction,
    )


def _ahead(network: RoadNetwork, road: str, direction: int) -> float:
    """How far the lanes leaving ``road`` driven ``direction`` lead on (capped)."""
    best = 0.0
    end = network.roads[road].length if direction > 0 else 0.0
    for ref in end_lanes(network, road, direction):
        for span in network.reachable(ref, end, AHEAD_CAP):
            best = max(best, span.distance + abs(span.s_to - span.s_from))
    return min(best, AHEAD_CAP)
