"""Which map a scenario runs on, and how its lane numbers name the map's lanes.

The map is the witness's: the checker read the scenario's ``map_file`` (a built-in
name, or an OpenDRIVE file relative to the scenario file, whose absolute path the
witness records) and placed every actor on it; the runner loads the same network
(``osc2check.world.maps.load_map``, cached). A scenario numbers the driving lanes
of one direction of travel on the road an actor is on, as its map says
(``RoadNetwork.numbering``): from the right (the standard's default, 1 = the
rightmost lane in the direction of travel), or from the left on the CARLA
stand-in ``Town06`` (CARLA numbers lanes outward from the centre line), which is
what puts the design paper's npc "one lane right of the hero" on the road. A
``lane`` modifier's ``from:`` side overrides the map's.
"""

from __future__ import annotations

from dataclasses import dataclass

from osc2check.verify.witness import Witness
from osc2check.world.builtin import DEFAULT_MAP
from osc2check.world.maps import load_map
from osc2check.world.network import LaneRef, RoadNetwork
from osc2check.world.numbering import driving_lanes_right_to_left
from osc2check.world.topology import neighbour_n

__all__ = ["LaneNumbers", "network_for"]


def network_for(witness: Witness) -> RoadNetwork:
    """The map the witness placed the scenario on (raises MapError, UnknownMapError)."""
    return load_map(witness.map_source or witness.map or DEFAULT_MAP)


@dataclass(frozen=True, slots=True)
class LaneNumbers:
    """Scenario lane numbers <-> the map's lanes, on the road where an actor is."""

    network: RoadNetwork

    @property
    def default_side(self) -> str:
        """The side the map counts a scenario's lanes from: ``right`` or ``left``."""
        return "left" if self.network.numbering == "from_left" else "right"

    def lanes(self, road: str, section: int, direction: int) -> list[LaneRef]:
        """The driving lanes of a section travelling ``direction``, rightmost first."""
        return driving_lanes_right_to_left(self.network, road, section, direction)

    def number(self, ref: LaneRef, side: str | None = None) -> int:
        """The scenario's number of driving lane ``ref`` counted from ``side`` (the map's
        side by default)."""
        side = side or self.default_side
        return self.network.osc2_lane_index(ref, "right" if side == "right" else "left")

    def lane(self, beside: LaneRef, number: int, side: str | None = None) -> LaneRef | None:
        """The lane numbered ``number`` (from ``side``) in the section and direction of
        lane ``beside``, or None when there is none."""
        side = side or self.default_side
        order = self.lanes(beside.road, beside.section, self.network.lane(beside).direction)
        if not 1 <= number <= len(order):
            return None
        return order[number - 1] if side == "right" else order[len(order) - number]

    def count(self, ref: LaneRef) -> int:
        """How many driving lanes travel ``ref``'s way in its section."""
        return len(self.lanes(ref.road, ref.section, self.network.lane(ref).direction))

    def beside(self, ref: LaneRef, side: str, count: int = 1) -> LaneRef | None:
        """The lane ``count`` lanes to the ``side`` (left/right, in ``ref``'s direction of
        travel) of ``ref``, when it is a driving lane travelling the same way; else None."""
        lane = self.network.lane(ref)
        step = lane.direction if side == "left" else -lane.direction
        other = neighbour_n(self.network, ref, step, count)
        if other is None:
            return None
        found = self.network.lane(other)
        return other if found.drivable and found.direction == lane.direction else None
