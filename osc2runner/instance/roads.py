"""Which road a scenario runs on, and how its lane numbers map to the road's lanes.

The road comes from the ``map_file`` of the scenario's ``map`` actor
(``keep(it.map_file == "Town06")``) or its ``set_map_file`` modifier, else
the built-in ``default`` map. Internally lanes are numbered from the right
(:mod:`osc2check.road`: lane 1 is the rightmost in the driving direction);
a scenario numbers them as its map says (``Road.numbering``): from the right
on the built-in maps, from the left on the CARLA stand-in ``Town06`` (CARLA
numbers lanes outward from the centre line), which is what puts the design
paper's npc "one lane right of the hero" on the road. A ``lane`` modifier's
``from:`` side overrides the map's.
"""

from __future__ import annotations

from dataclasses import dataclass

from osc2check.road import Road, get_map

__all__ = ["LaneNumbers", "road_for"]

DEFAULT_MAP = "default"


def road_for(map_file: str | None) -> Road:
    """The built-in road for a map name (``default`` when None); raises UnknownMapError."""
    return get_map(map_file or DEFAULT_MAP)


@dataclass(frozen=True, slots=True)
class LaneNumbers:
    """Scenario lane numbers <-> road lanes (1 = rightmost) on one road."""

    road: Road

    @property
    def default_side(self) -> str:
        """The side the map counts a scenario's lanes from: ``right`` or ``left``."""
        return "left" if self.road.numbering == "from_left" else "right"

    def to_road(self, number: int, side: str | None = None) -> int:
        """The road lane of scenario lane ``number`` counted from ``side`` (default: the map's)."""
        side = side or self.default_side
        return self.road.lane_count + 1 - number if side == "left" else number

    def to_scenario(self, lane: int, side: str | None = None) -> int:
        """The scenario number of road lane ``lane`` counted from ``side``."""
        side = side or self.default_side
        return self.road.lane_count + 1 - lane if side == "left" else lane

    @staticmethod
    def beside(lane: int, side: str, count: int = 1) -> int:
        """The road lane ``count`` lanes to the ``side`` (left/right) of road lane ``lane``."""
        return lane + count if side == "left" else lane - count
