"""The map's element fields of a scenario: a field of type road, route, lane, junction
or crossing is a variable whose values are the map's elements of that kind
(``map_modifiers`` constrains them; the witness names the chosen ones).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol
from osc2check.verify import ir
from osc2check.verify.road_terms import RoadTerms
from osc2check.world.maps import FoundMap
from osc2check.world.network import LaneRef, RoadNetwork

if TYPE_CHECKING:
    from osc2check.world.elements import MapElements

#: OSC2 type name -> the kind of map element a field of that type is
ELEMENT_KINDS = {
    "junction": "junction",
    "road": "road",
    "lane": "lane",
    "compound_lane": "lane",
    "route": "route",
    "route_element": "route",
    "compound_route": "route",
    "crossing": "crossing",
}

Route = tuple[str, int]
Element = str | Route | LaneRef  # a road or junction id, a route, a lane


def element_kind(model: Model, type_symbol: Symbol | None) -> str | None:
    """The map element kind of a type (its own name first, then its ancestors')."""
    for ancestor in model.ancestors(type_symbol):
        if ancestor.library and ancestor.name in ELEMENT_KINDS:
            return ELEMENT_KINDS[ancestor.name]
    return None


@dataclass(frozen=True, slots=True)
class ElementField:
    """A scenario field whose value is a map element, and its variable."""

    path: str
    kind: str
    var: ir.Var


@dataclass
class ElementFields:
    """The element fields of one scenario on one map: each field's variable, and the
    map's elements of its kind that the variable's values stand for."""

    found: FoundMap  # the map: its network is built when a map modifier first asks
    roads: RoadTerms
    fields: dict[str, ElementField] = field(default_factory=dict)
    along: dict[str, list[ElementField]] = field(default_factory=dict)  # actor -> targets

    def __post_init__(self) -> None:
        self._elements: MapElements | None = None

    @property
    def network(self) -> RoadNetwork:
        return self.found.network

    @property
    def elements(self) -> MapElements:
        """The map's roads, routes, lanes and junctions (made on first use)."""
        if self._elements is None:
            from osc2check.world.elements import map_elements  # routes need numpy

            self._elements = map_elements(self.network)
        return self._elements

    # ---- variables

    def choices(self, kind: str) -> list[Element]:
        e = self.elements
        values: dict[str, Iterable[Element]] = {
            "road": e.roads,
            "route": e.routes,
            "lane": e.lanes,
            "junction": e.junctions,
            "crossing": tuple(c.id for c in self.network.crossings),
        }
        return list(values[kind])

    def label(self, kind: str, value: Element) -> str:
        if kind in ("junction", "crossing"):
            return f"{kind} {value}"
        if kind == "road":
            return f"road {value}"
        if kind == "route":
            assert isinstance(value, tuple)
            return self.elements.route_label(value)
        assert isinstance(value, LaneRef)
        return self.elements.lane_label(value)

    def index_of(self, item: ElementField, value: Element) -> int | None:
        """The index of ``value`` in ``item``'s choices (a route given to a road field is
        its road; None when it has no counterpart)."""
        if item.kind == "road" and isinstance(value, tuple):
            value = value[0]
        elif item.kind == "road" and isinstance(value, LaneRef):
            value = value.road
        choices = self.choices(item.kind)
        try:
            return choices.index(value)
        except ValueError:
            return None
