"""The witness: one concrete instance of a scenario that satisfies every constraint.

Values are exact (SI rationals) and are also shown in a readable unit. The
runner executes exactly this: parameter values, the map, every actor's start
(its lane as the scenario numbers it, its position ``s`` on its carriageway and
its offset ``t``; where that is on the map: road, OpenDRIVE lane, road ``s``, world
pose), heading and speed, the route it takes through the junctions ahead, and
the map element each road, route, lane and junction field stands for.
Constraints the solver could not take (``ConstraintProblem.skipped``, C411) are
listed in ``unverified``: the witness is not claimed to satisfy them.

An actor's route is the roads it drives through from its start: towards the
routes its `along` modifiers name, in order, and at the other forks chosen with
the witness's seed (per actor), so the same seed gives the same routes.
"""

from __future__ import annotations

import zlib
from collections.abc import Iterable
from dataclasses import dataclass, field
from fractions import Fraction
from typing import TYPE_CHECKING

from osc2check.verify import ir, propagate
from osc2check.verify.map_modifiers import ElementValue, element_value
from osc2check.verify.problem import ConstraintProblem
from osc2check.verify.schedule import Schedule, schedule
from osc2check.verify.starts import ActorBody, PlacedActor, StartPlacement
from osc2check.verify.timing import is_timing_variable
from osc2check.world.carriageways import Carriageway, lane_at
from osc2check.world.catalogue import CATEGORIES, ActorRow
from osc2check.world.network import LaneRef, RoadNetwork

if TYPE_CHECKING:
    from osc2check.world.projection import WorldPose

ROUTE_AHEAD = 500.0  # m: how far past its carriageway an actor's route is planned


@dataclass(frozen=True, slots=True)
class Value:
    """A parameter's value: exact SI number (or bool, enum member, string) and its display."""

    name: str
    value: Fraction | bool | str
    text: str  # e.g. "55 kph", "truck", "\"Town06\""
    constrained: bool  # some constraint mentions it (others are free choices)

    def to_json(self) -> dict[str, object]:
        data: dict[str, object] = {
            "name": self.name,
            "text": self.text,
            "constrained": self.constrained,
        }
        if isinstance(self.value, Fraction):
            data["si"] = str(self.value)
            data["si_float"] = float(self.value)
        else:
            data["value"] = self.value
        return data


@dataclass(frozen=True, slots=True)
class ActorStart:
    """One actor at time 0: what it is (catalogue row, category, size) and where it starts.

    The runner builds the actor from ``model`` (the catalogue row's key: a model name,
    a vehicle category or an actor kind) with exactly ``length`` and ``width``.
    """

    name: str
    kind: str
    category: str
    model: str
    lane: int  # as the scenario numbers lanes on this map
    s: Fraction  # m, centre along its carriageway (along the road on a straight map)
    t: Fraction  # m, lateral offset from the lane centre (left positive)
    x: float
    y: float
    heading: float  # rad
    speed: Fraction  # m/s
    length: Fraction
    width: Fraction
    height: Fraction
    placed: bool  # positioned by the scenario (otherwise chosen freely)
    road: str = ""  # the road it starts on
    lane_id: int = 0  # the OpenDRIVE id of its lane
    section: int = 0  # the lane section of that lane
    road_s: float = 0.0  # m, its road coordinate s
    route: tuple[str, ...] = ()  # the roads it drives through, from its start

    @property
    def lane_ref(self) -> LaneRef:
        """Its start lane on the map."""
        return LaneRef(self.road, self.section, self.lane_id)

    def to_json(self) -> dict[str, object]:
        return {
            "name": self.name,
            "kind": self.kind,
            "category": self.category,
            "model": self.model,
            "lane": self.lane,
            "s_m": float(self.s),
            "t_m": float(self.t),
            "x_m": self.x,
            "y_m": self.y,
            "heading_rad": self.heading,
            "speed_mps": float(self.speed),
            "speed_kph": float(self.speed * Fraction(18, 5)),
            "s_exact": str(self.s),
            "speed_exact": str(self.speed),
            "length_m": float(self.length),
            "width_m": float(self.width),
            "height_m": float(self.height),
            "placed_by_scenario": self.placed,
            "road": self.road,
            "lane_id": self.lane_id,
            "section": self.section,
            "road_s_m": self.road_s,
            "route": list(self.route),
        }


@dataclass(frozen=True)
class Witness:
    scenario: str
    seed: int | None
    map: str
    lane_numbering: str
    parameters: tuple[Value, ...]
    actors: tuple[ActorStart, ...] = ()
    notes: tuple[str, ...] = field(default_factory=tuple)
    unused_map: str | None = None  # a map the scenario names that placement could not use
    #: constraints left out of the problem (C411): the values need not satisfy them
    unverified: tuple[ir.Skipped, ...] = ()
    # list members of struct parameters: their items (``ConstraintProblem.lists``)
    lists: dict[str, tuple[ir.ListItem, ...]] = field(default_factory=dict)
    map_source: str | None = None  # the OpenDRIVE file of the map (absolute), if it is one
    elements: tuple[tuple[str, ElementValue], ...] = ()  # road/route/lane/junction fields
    #: when each phase must end and each member starts, for the runner's plans
    #: (``verify.schedule``); the values of its durations are this witness's
    schedule: Schedule = field(default_factory=Schedule, compare=False, repr=False)

    def element(self, path: str) -> ElementValue | None:
        return next((v for p, v in self.elements if p == path), None)

    def parameter(self, name: str) -> Value | None:
        return next((p for p in self.parameters if p.name == name), None)

    def actor(self, name: str) -> ActorStart | None:
        return next((a for a in self.actors if a.name == name), None)

    def to_json(self) -> dict[str, object]:
        return {
            "scenario": self.scenario,
            "seed": self.seed,
            "map": self.map,
            "map_source": self.map_source,
            "lane_numbering": self.lane_numbering,
            "gap_convention": "bumper to bumper",
            "actors": [a.to_json() for a in self.actors],
            "parameters": [p.to_json() for p in self.parameters],
            "map_elements": {path: v.to_json() for path, v in self.elements},
            "notes": list(self.notes),
            "unverified": [s.to_json() for s in self.unverified],
            "lists": {
                k: [[kind, str(v) if isinstance(v, Fraction) else v] for kind, v in items]
                for k, items in self.lists.items()
            },
        }

    def table(self) -> str:
        """A readable table of the start state and the constrained parameters."""
        lines = [
            f"witness for scenario `{self.scenario}` (seed {self.seed}, map {self.map}, "
            f"lanes numbered {self.lane_numbering.replace('_', ' ')})"
        ]
        if self.actors:
            on_map = self.map_source is not None  # an OpenDRIVE map: where on it, too
            lines.append(
                f"  {'actor':<14}{'kind':<20}{'lane':>5}{'s (m)':>10}{'t (m)':>8}"
                f"{'speed (kph)':>13}"
                + (f"  {'road':>6}{'lane_id':>8}{'road s':>9}" if on_map else "")
            )
            for a in self.actors:
                kind = a.kind if a.kind == a.category else f"{a.kind}/{a.category}"
                where = f"  {a.road:>6}{a.lane_id:>8}{a.road_s:>9.2f}" if on_map else ""
                lines.append(
                    f"  {a.name:<14}{kind:<20}{a.lane:>5}"
                    f"{float(a.s):>10.2f}{float(a.t):>8.2f}"
                    f"{float(a.speed * Fraction(18, 5)):>13.2f}"
                    + where
                    + ("" if a.placed else "   (not placed by the scenario)")
                )
        shown = [p for p in self.parameters if p.constrained and "@" not in p.name]
        if shown:
            lines.append("  parameters:")
            width = max(len(p.name) for p in shown)
            for p in shown:
                lines.append(f"    {p.name:<{width}}  {p.text}")
        for note in self.notes:
            lines.append(f"  note: {note}")
        for s in self.unverified:
            lines.append(
                f"  not verified (these values need not satisfy it): `{s.text}` at line "
                f"{s.span.line}: {s.reason}"
            )
        return "\n".join(lines)


def _row(body: ActorBody, values: dict[str, Fraction | bool]) -> ActorRow:
    """The catalogue row an actor was placed with (its category's, when that was open)."""
    if body.row is not None:
        return body.row
    value = values.get(body.category.name) if body.category is not None else None
    member = (
        next((n for n, v in body.category.enum if v == value), "car") if body.category else "car"
    )
    return CATEGORIES.get(member, CATEGORIES["car"])


def _size(term: ir.Term, values: dict[str, Fraction | bool]) -> Fraction:
    value = propagate.evaluate(term, values)
    return value if isinstance(value, Fraction) else Fraction(0)


def _display(
    var: ir.Var, value: Fraction | bool, strings: dict[int, str]
) -> tuple[Fraction | bool | str, str]:
    if isinstance(value, bool):
        return value, "true" if value else "false"
    if var.enum:
        name = next((n for n, v in var.enum if v == value), None)
        if name is not None:
            return name, name
    if var.is_string:
        text = strings.get(int(value))
        return (text, f'"{text}"') if text is not None else ("", "any string")
    if var.unit:
        shown = (value - var.unit_offset) / var.unit_factor
        return value, f"{_number(shown)} {var.unit}"
    return value, _number(value)


def _number(value: Fraction) -> str:
    if value.denominator == 1:
        return str(value.numerator)
    return f"{float(value):.6g}"


def build_witness(
    problem: ConstraintProblem,
    values: dict[str, Fraction | bool],
    active: Iterable[ir.Constraint],
    seed: int | None,
    rounded: Iterable[str] = (),
) -> Witness:
    """Assemble the witness of ``problem`` from a solver model's ``values``; notes
    go with it (``rounded``: constraints the values hold only up to rounding)."""
    mentioned: set[str] = set()
    for c in active:
        if c.kind not in ("domain", "placement"):
            mentioned.update(v.name for v in ir.variables(c.term))
    params = []
    placement: StartPlacement | None = problem.placement
    for name in sorted(problem.variables):
        if "@start." in name or is_timing_variable(name):
            continue  # the start state is shown as actors; phase times are the runner's
        var = problem.variables[name]
        value, text = _display(var, values.get(name, Fraction(0)), problem.strings)
        params.append(Value(name, value, text, name in mentioned))
    actors = []
    notes: list[str] = [*problem.notes, *rounded]
    elements: list[tuple[str, ElementValue]] = []
    map_name, numbering, source, unused = "", "from_right", None, None
    if placement is not None:
        network = placement.network
        if placement.fields is not None:
            for path, item in sorted(placement.fields.fields.items()):
                number = int(values.get(item.var.name, Fraction(0)))
                elements.append((path, element_value(placement.fields, item, number)))
        for a in placement.actors.values():
            row = _row(a.body, values)
            s = Fraction(values.get(a.s.name, Fraction(0)))
            t = Fraction(values.get(a.t.name, Fraction(0)))
            lane, ref, road_s, pose = _start(placement, a, values, s, t)
            chosen = dict(elements)
            targets = [
                element.road
                for item in a.along
                if (element := chosen.get(item.path)) is not None and element.road
            ]
            route = _route(network, ref, road_s, placement.terms.carriageways, a, s, targets, seed)
            actors.append(
                ActorStart(
                    a.name,
                    a.kind,
                    row.category,
                    row.key,
                    network.scenario_lane(ref),
                    s,
                    t,
                    pose.x,
                    pose.y,
                    pose.yaw + _heading(a, values),
                    Fraction(values.get(a.speed.name, Fraction(0))),
                    _size(a.body.length, values),
                    _size(a.body.width, values),
                    row.height,
                    a.placed,
                    ref.road,
                    ref.lane,
                    ref.section,
                    road_s,
                    route,
                )
            )
            notes.extend(a.body.notes)
        choice = placement.map
        if choice.unknown is not None:
            notes.append(f"unknown map `{choice.asked}`: placed on `{choice.name}`")
            unused = choice.asked
        if choice.unreadable is not None:
            notes.append(
                f"map `{choice.asked}` cannot be read ({choice.unreadable.problem}): placed on "
                f"`{choice.name}`"
            )
            unused = choice.asked
        map_name, numbering, source = choice.name, network.numbering, choice.source
    return Witness(
        problem.scenario,
        seed,
        map_name,
        numbering,
        tuple(params),
        tuple(actors),
        tuple(notes),
        unused,
        tuple(problem.skipped),
        dict(problem.lists),
        source,
        tuple(elements),
        schedule(problem.timing, values),
    )


def _heading(actor: PlacedActor, values: dict[str, Fraction | bool]) -> float:
    """The start heading a ``yaw``/``orientation`` modifier gives, from the lane's (rad)."""
    if actor.heading is None:
        return 0.0
    return float(values.get(actor.heading.name, Fraction(0)))


def _start(
    placement: StartPlacement,
    actor: PlacedActor,
    values: dict[str, Fraction | bool],
    s: Fraction,
    t: Fraction,
) -> tuple[int, LaneRef, float, WorldPose]:
    """Lane number (from the right), lane, road s and world pose of an actor's start."""
    network = placement.network
    cws = placement.terms.carriageways
    index = int(values.get(actor.road.name, Fraction(0))) if actor.road is not None else 0
    cw = cws[min(max(index, 0), len(cws) - 1)]
    at = min(max(float(s), 0.0), cw.length)
    count = max(cw.lane_count(at), 1)
    lane = min(max(int(values.get(actor.lane.name, Fraction(1))), 1), count)
    ref = lane_at(network, cw, at, lane)
    road_s = cw.leg_at(at).road_s(at)
    return lane, ref, road_s, network.lane_to_world(ref, road_s, float(t))


def _route(
    network: RoadNetwork,
    start: LaneRef,
    road_s: float,
    cws: tuple[Carriageway, ...],
    actor: PlacedActor,
    s: Fraction,
    targets: list[str],
    seed: int | None,
) -> tuple[str, ...]:
    """The roads an actor drives through from its start (see the module docstring)."""
    cw = next((c for c in cws if start.road in c.roads), None)
    left = (cw.length - float(s)) if cw is not None else 0.0
    picked = zlib.crc32(f"{seed or 0}/{actor.name}".encode())
    route = network.route(start, seed=picked, max_length=left + ROUTE_AHEAD, towards=targets)
    roads: list[str] = []
    for ref in route.lanes:
        if not roads or roads[-1] != ref.road:
            roads.append(ref.road)
    return tuple(roads)
