"""The witness: one concrete instance of a scenario that satisfies every constraint.

Values are exact (SI rationals) and are also shown in a readable unit. The
runner executes exactly this: parameter values and every actor's start lane,
position, heading and speed.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from fractions import Fraction

from osc2check.verify import ir, quick
from osc2check.verify.placement import ActorBody, StartPlacement
from osc2check.world.catalogue import CATEGORIES, ActorRow


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
    s: Fraction  # m, centre along the road
    t: Fraction  # m, lateral offset from the lane centre (left positive)
    x: float
    y: float
    heading: float  # rad
    speed: Fraction  # m/s
    length: Fraction
    width: Fraction
    height: Fraction
    placed: bool  # positioned by the scenario (otherwise chosen freely)

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
    # list members of struct parameters: their items (``ir.ConstraintProblem.lists``)
    lists: dict[str, tuple[ir.ListItem, ...]] = field(default_factory=dict)

    def parameter(self, name: str) -> Value | None:
        return next((p for p in self.parameters if p.name == name), None)

    def actor(self, name: str) -> ActorStart | None:
        return next((a for a in self.actors if a.name == name), None)

    def to_json(self) -> dict[str, object]:
        return {
            "scenario": self.scenario,
            "seed": self.seed,
            "map": self.map,
            "lane_numbering": self.lane_numbering,
            "gap_convention": "bumper to bumper",
            "actors": [a.to_json() for a in self.actors],
            "parameters": [p.to_json() for p in self.parameters],
            "notes": list(self.notes),
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
            lines.append(
                f"  {'actor':<14}{'kind':<20}{'lane':>5}{'s (m)':>10}{'t (m)':>8}"
                f"{'speed (kph)':>13}"
            )
            for a in self.actors:
                kind = a.kind if a.kind == a.category else f"{a.kind}/{a.category}"
                lines.append(
                    f"  {a.name:<14}{kind:<20}{a.lane:>5}"
                    f"{float(a.s):>10.2f}{float(a.t):>8.2f}"
                    f"{float(a.speed * Fraction(18, 5)):>13.2f}"
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
    value = quick.evaluate(term, values)
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
    problem: ir.ConstraintProblem,
    values: dict[str, Fraction | bool],
    active: Iterable[ir.Constraint],
    seed: int | None,
) -> Witness:
    """Assemble the witness of ``problem`` from a solver model's ``values``."""
    mentioned: set[str] = set()
    for c in active:
        if c.kind not in ("domain", "placement"):
            mentioned.update(v.name for v in ir.variables(c.term))
    params = []
    placement: StartPlacement | None = problem.placement
    for name in sorted(problem.variables):
        if "@start." in name:
            continue
        var = problem.variables[name]
        value, text = _display(var, values.get(name, Fraction(0)), problem.strings)
        params.append(Value(name, value, text, name in mentioned))
    actors = []
    notes: list[str] = []
    if placement is not None:
        road = placement.road
        for a in placement.actors.values():
            lane = int(values.get(a.lane.name, Fraction(1)))
            lane = min(max(lane, 1), road.lane_count)
            s = Fraction(values.get(a.s.name, Fraction(0)))
            t = Fraction(values.get(a.t.name, Fraction(0)))
            x, y = road.to_xy(float(s), road.lane_center_t(lane) + float(t))
            row = _row(a.body, values)
            actors.append(
                ActorStart(
                    a.name,
                    a.kind,
                    row.category,
                    row.key,
                    road.to_scenario_lane(lane),
                    s,
                    t,
                    x,
                    y,
                    road.heading,
                    Fraction(values.get(a.speed.name, Fraction(0))),
                    _size(a.body.length, values),
                    _size(a.body.width, values),
                    row.height,
                    a.placed,
                )
            )
            notes.extend(a.body.notes)
        if placement.unknown_map is not None:
            notes.append(f"unknown map `{placement.unknown_map[1]}`: placed on `{road.name}`")
        if placement.unread_map is not None:
            notes.append(
                f"OpenDRIVE maps are not read yet: placed on `{road.name}` instead "
                f"of `{placement.unread_map}`"
            )
        map_name, numbering = road.name, road.numbering
    else:
        map_name, numbering = "", "from_right"
    unused = None
    if placement is not None:
        unused = placement.unread_map or (
            placement.unknown_map[1] if placement.unknown_map is not None else None
        )
    return Witness(
        problem.scenario,
        seed,
        map_name,
        numbering,
        tuple(params),
        tuple(actors),
        tuple(notes),
        unused,
        dict(problem.lists),
    )
