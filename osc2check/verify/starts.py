"""Where the start placement puts every actor: the map, each actor's start variables
(lane, ``s``, ``t``, speed, carriageway) and body, the gaps written between them and
the map's element fields; the witness reads it (``placement`` builds it).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import TYPE_CHECKING

from osc2check.source import Span
from osc2check.verify import ir
from osc2check.verify.element_fields import ElementField, ElementFields
from osc2check.verify.road_terms import RoadTerms
from osc2check.world.catalogue import ActorRow
from osc2check.world.errors import MapError
from osc2check.world.maps import FoundMap, MapFacts

if TYPE_CHECKING:
    from osc2check.world.network import RoadNetwork


@dataclass
class ActorBody:
    """What an actor is for placement: its catalogue row and its size and top speed as terms.

    ``row`` is the catalogue row the actor is placed with; when a constraint of the
    scenario mentions a vehicle's category (``keep(it.vehicle_category in [car,
    truck])``, ``keep(it.vehicle_category == truck)``, a conditional inheritance),
    ``row`` is None and the terms depend on the category variable, so the solver
    chooses a category and a footprint that agree, and a conflict that the category
    takes part in names the constraint that chose it (and no other). ``shown`` is the
    row a constraint fixes the category to, for the texts. A declared
    ``bounding_box.length`` or ``.width`` replaces the row's. ``because`` holds the
    constraints that chose a constant row (the keep that names a simulator model),
    which a conflict involving the row's size or speed names too.
    """

    kind: str
    row: ActorRow | None
    length: ir.Term
    width: ir.Term
    max_speed: ir.Term
    category: ir.Var | None = None  # the vehicle_category variable, for vehicles
    because: tuple[ir.Constraint, ...] = ()
    notes: tuple[str, ...] = ()
    shown: ActorRow | None = None

    def widest(self) -> Fraction:
        """The largest width the actor may have (its width when known)."""
        return largest(self.width)

    def size_text(self, term: ir.Term, what: str) -> str:
        """``4.5 m long``, or how the size is decided when it is not a constant."""
        if isinstance(term, ir.Const) and not isinstance(term.value, bool):
            return f"{float(term.value):g} m {what}"
        if isinstance(term, ir.Ref):
            return f"`{term.var.name}` {what}"
        if self.shown is not None:
            size = self.shown.length if what == "long" else self.shown.width
            return f"{what} as its vehicle_category: a {self.shown.category}, {float(size):g} m"
        return f"{what} as its vehicle_category"


def largest(term: ir.Term) -> Fraction:
    """The largest value ``term`` may take: a constant, or the largest of its branches."""
    if isinstance(term, ir.Const) and not isinstance(term.value, bool):
        return term.value
    if isinstance(term, ir.Op) and term.op == "ite":
        return max(largest(term.args[1]), largest(term.args[2]))
    return Fraction(10**6)


@dataclass
class PlacedActor:
    name: str
    kind: str
    body: ActorBody
    span: Span
    lane: ir.Var
    s: ir.Var
    t: ir.Var
    speed: ir.Var
    road: ir.Var | None = None  # its carriageway, on a map with several
    placed: bool = False  # a start `lane` or `position` modifier places it
    acts: bool = False  # the scenario invokes an action of it
    along: list[ElementField] = field(default_factory=list)  # routes `along` names, in order
    heading: ir.Var | None = None  # its start heading from the lane's, given by `yaw` (rad)


@dataclass(frozen=True)
class Gap:
    """A start gap written with `position(..., behind|ahead_of: ...)` (for L511)."""

    follower: str
    leader: str
    gap: ir.Term  # m, bumper to bumper
    speed: ir.Term  # the follower's start speed
    span: Span
    text: str


@dataclass
class MapChoice:
    """The map a scenario is placed on (``name``, ``found``: its facts, its network on
    first use), the name the scenario gives (``asked``) and where (``span``, the
    `map_file` string), and why that one could not be used when it could not (the
    default map is used instead)."""

    name: str
    found: FoundMap
    source: str | None = None  # the file read, for an OpenDRIVE map
    asked: str | None = None
    span: Span | None = None
    unknown: tuple[str, ...] | None = None  # not a map: the known built-in names
    unreadable: MapError | None = None  # a file that cannot be read

    @property
    def facts(self) -> MapFacts:
        return self.found.facts

    @property
    def network(self) -> RoadNetwork:
        """The road network (built here when the facts came from the start-up cache)."""
        return self.found.network


@dataclass
class StartPlacement:
    map: MapChoice
    terms: RoadTerms
    actors: dict[str, PlacedActor] = field(default_factory=dict)
    edges: list[tuple[str, str, Span]] = field(default_factory=list)  # a placed relative to b
    unplaced_references: list[tuple[Span, str, str]] = field(default_factory=list)
    gaps: list[Gap] = field(default_factory=list)
    fields: ElementFields | None = None  # road, route, lane and junction fields
    no_junction: list[Span] = field(default_factory=list)  # CARLA's path_over_junction

    @property
    def network(self) -> RoadNetwork:
        return self.map.network
