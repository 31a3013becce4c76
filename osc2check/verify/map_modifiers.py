"""Map elements as solver choices: road, route, lane and junction fields, the map modifiers
over them, and `along`.

A scenario field of type ``road``, ``route`` (``route_element``,
``compound_route``), ``lane`` (``compound_lane``), ``junction`` or ``crossing`` becomes an
integer variable whose values are the map's elements of that kind
(:mod:`osc2check.world.elements`: roads; routes, i.e. a road driven one way;
driving lanes; junctions). The witness shows each by name (``road 3 (against
s)``) and gives the runner its identity.

Each map modifier (ASAM OpenSCENARIO DSL 2.1 §8.12) is a table of the element
combinations that satisfy it on this map, encoded as a disjunction over the
table's rows; a modifier no row satisfies, or modifiers whose rows exclude each
other, make a conflict that names them (L501, C401 machinery):

* ``number_of_lanes(route, num_of_lanes, lane_type, lane_use, directionality)``:
  the route has that many lanes of that type and use in every lane section,
  travelling its way (``uni_direction``) or either way (``bi_direction``; other
  directionalities are not modelled);
* ``routes_are_in_sequence(preceding, succeeding)``: lanes leaving the first route
  enter the second directly (``road:`` is not modelled);
* ``roads_follow_in_junction(junction, in_road, out_road, direction,
  clockwise_count, number_of_roads, in_lane, out_lane, junction_route)``: a way
  through the junction (``resulting_route``, a route over several roads, is not
  modelled);
* ``routes_overlap(route1, route2, overlap_kind)``: routes here are single roads
  driven one way, so every kind but ``other`` means the same route;
* ``routes_are_opposite(route1, route2, containing_road, lateral_overlap)``: the two
  directions of one road (their lanes never overlap: ``never``);
* ``lane_side(lane1, side, lane2, count)`` and ``compound_lane_side``: ``lane1`` is
  ``count`` lanes to ``side`` of ``lane2`` in ``lane2``'s direction of travel
  (``lane_section:`` and ``route:`` are not modelled);
* ``start_lane(lane)``, ``end_lane(lane)``: a lane that begins (ends) where the lanes
  beside it go on.

* ``crossing_connects(crossing, start_lane, end_lane, start_angle)``: a crossing of the
  map (an OpenDRIVE crosswalk, :class:`~osc2check.world.network.Crossing`) that starts
  in ``start_lane``, ends in ``end_lane`` and leaves the start lane at ``start_angle``
  (90° by default; within 1°) (``start_s_coord`` is not modelled).

Whatever is not modelled is recorded in
``problem.skipped`` with its reason, never silently dropped.

``along(route: r)`` ties an actor to a route: in an invocation that begins at time
0 the actor starts on ``r`` (``start_offset:``, when written, from the route's
start); in a later one, ``r`` is reachable ahead of the actor's start.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.verify import ir
from osc2check.verify.element_fields import (
    Element,
    ElementField,
    ElementFields,
    element_kind,
)
from osc2check.verify.problem import ConstraintProblem
from osc2check.verify.road_terms import fraction
from osc2check.verify.terms import InstanceScope, NotEncodable, TermEncoder
from osc2check.world.carriageways import AHEAD_CAP, Carriageway
from osc2check.world.network import LaneRef

if TYPE_CHECKING:
    pass

__all__ = ["ElementValue", "MapFields", "element_value"]


@dataclass(frozen=True, slots=True)
class ElementValue:
    """The element the witness chose for a field: kind plus identity, plain data."""

    kind: str  # road | route | lane | junction | crossing
    road: str = ""
    direction: int = 0
    section: int = 0
    lane: int = 0
    junction: str = ""
    crossing: str = ""  # a crossing's object id (its road is ``road``)

    @property
    def label(self) -> str:
        if self.kind == "junction":
            return f"junction {self.junction}"
        if self.kind == "crossing":
            return f"crossing {self.crossing} (road {self.road})"
        if self.kind == "lane":
            return f"road {self.road} lane {self.lane}"
        text = f"road {self.road}"
        return text + (" (against s)" if self.kind == "route" and self.direction < 0 else "")

    def to_json(self) -> dict[str, object]:
        data: dict[str, object] = {"kind": self.kind, "label": self.label}
        if self.kind == "junction":
            data["junction"] = self.junction
        else:
            data["road"] = self.road
        if self.kind == "route":
            data["direction"] = self.direction
        if self.kind == "lane":
            data.update(section=self.section, lane=self.lane)
        if self.kind == "crossing":
            data["crossing"] = self.crossing
        return data


@dataclass
class _Argument:
    name: str
    element: ElementField | None = None
    term: ir.Term | None = None  # a number or enum value
    word: str | None = None  # an enum member written as a constant
    enum: dict[str, int] = field(default_factory=dict)  # the member values of an enum parameter


@dataclass
class MapFields(ElementFields):
    """The element fields of one scenario on one map, and what constrains them."""

    lw: TermEncoder = field(kw_only=True)

    def __post_init__(self) -> None:
        super().__post_init__()
        self.problem: ConstraintProblem = self.lw.problem
        self.model: Model = self.lw.model

    def field_of(self, node: ast.Node | None, scope: InstanceScope) -> ElementField | None:
        """The element field a modifier argument names, made on first use (None when the
        argument is not a field of an element type)."""
        if not isinstance(node, (ast.NameRef, ast.MemberAccess)):
            return None
        sym = self.model.references.get(
            node.name.name if isinstance(node, ast.NameRef) else node.member
        )
        if sym is None or sym.type is None:
            return None
        kind = element_kind(self.model, sym.type.symbol)
        path = self.lw.path(node, scope)
        if kind is None or path is None:
            return None
        known = self.fields.get(path)
        if known is not None:
            return known
        choices = self.choices(kind)
        labels = tuple((self.label(kind, v), i) for i, v in enumerate(choices))
        var = self.problem.var(path, "int", enum=labels, span=sym.name_span)
        ref = ir.Ref(var)
        self.problem.add(
            ir.Constraint(
                ir.op("and", ir.op(">=", ref, ir.const(0)), ir.op("<", ref, ir.const(len(choices))))
                if choices
                else ir.op("!=", ref, ref),
                sym.name_span or self.problem.span,
                "domain",
                f"a {kind} of map `{self.roads.name}`",
                explanation=f"`{path}` is one of the {len(choices)} {kind}(s) of map "
                f"`{self.roads.name}`",
            )
        )
        found = self.fields[path] = ElementField(path, kind, var)
        return found

    # ---- modifiers

    def modifier(
        self,
        inv: ast.Invocation,
        modifier: Symbol,
        scope: InstanceScope,
        require: Callable[[ir.Term, ast.Invocation], None],
    ) -> None:
        """Constrain the element fields as the map modifier ``inv`` says."""
        name = modifier.name
        handler = _MODIFIERS.get(name)
        if handler is None:
            if name not in ("set_map_file", "set_traffic_lights_control_file"):
                self._skip(inv.span, f"map.{name} is not modelled by the checker")
            return
        given = self._arguments(modifier, scope, inv)
        if given is None:
            return
        rows = handler(self, given, inv)
        if rows is None:
            return
        require(self._table(given, rows), inv)

    def _skip(self, span: Span, why: str) -> None:
        self.problem.skip(span, self.lw.text_of(span), why)

    def _arguments(
        self, modifier: Symbol, scope: InstanceScope, inv: ast.Invocation
    ) -> dict[str, _Argument] | None:
        found: dict[str, _Argument] = {}
        binding = self.model.binding(inv)
        for bound in binding.arguments if binding is not None else ():
            param, node = bound.parameter, bound.value
            if param is None:
                continue
            item = self.field_of(node, scope)
            if item is not None:
                found[param.name] = _Argument(param.name, element=item)
                continue
            enum: dict[str, int] = {}
            if (
                param.type is not None
                and param.type.symbol is not None
                and param.type.kind.name == "ENUM"
            ):
                enum = {m.name: m.value for m in self.model.enum_values(param.type.symbol)}
            member = _enum_word(self.model, node, enum)
            if member is not None:
                found[param.name] = _Argument(param.name, word=member)
                continue
            try:
                term = self.lw.term(node, scope)
                found[param.name] = _Argument(param.name, term=term, enum=enum)
            except NotEncodable as reason:
                self._skip(node.span, f"map.{modifier.name}({param.name}: ...): {reason}")
                return None
        return found

    def _table(self, given: dict[str, _Argument], rows: list[dict[str, object]]) -> ir.Term:
        options: list[ir.Term] = []
        seen: set[tuple[tuple[str, object], ...]] = set()
        for row in rows:
            parts: list[ir.Term] = []
            key: list[tuple[str, object]] = []
            ok = True
            for name, arg in given.items():
                if name not in row:
                    continue
                value = row[name]
                if arg.element is not None:
                    index = self.index_of(arg.element, value)  # type: ignore[arg-type]
                    if index is None:
                        ok = False
                        break
                    parts.append(ir.op("==", ir.Ref(arg.element.var), ir.const(index)))
                    key.append((name, index))
                elif arg.word is not None:
                    if arg.word != value:
                        ok = False
                        break
                elif arg.term is not None:
                    number = arg.enum.get(value, -1) if isinstance(value, str) else value
                    assert isinstance(number, int)
                    if isinstance(arg.term, ir.Const):
                        if arg.term.value != number:
                            ok = False
                            break
                        continue
                    parts.append(ir.op("==", arg.term, ir.const(number)))
                    key.append((name, number))
            if not ok or tuple(key) in seen:
                continue
            seen.add(tuple(key))
            options.append(_all(parts))
        if not options:
            return ir.const(False)
        if any(o == ir.TRUE for o in options):
            return ir.TRUE
        return options[0] if len(options) == 1 else ir.op("or", *options)

    # ---- along

    def tie(
        self,
        road: ir.Var | None,
        s: ir.Var,
        lane: ir.Var,
        target: ElementField,
        at_start: bool,
        start_offset: ir.Term | None,
    ) -> ir.Term:
        """``along(route: target)``: the actor starts on it (``at_start``), else reaches it."""
        if target.kind == "crossing":
            return self._tie_crossing(road, s, target, at_start)
        options: list[ir.Term] = []
        for cw in self.roads.carriageways:
            on_cw = self.roads.on(road, cw)
            if at_start:
                for leg in cw.legs:
                    for value in self._on_leg(target.kind, leg.road, leg.direction):
                        index = self.index_of(target, value)
                        if index is None:
                            continue
                        begin = ir.const(fraction(leg.start))
                        where = (
                            ir.op("==", ir.Ref(s), ir.op("+", begin, start_offset))
                            if start_offset is not None
                            else ir.op(
                                "and",
                                ir.op(">=", ir.Ref(s), ir.const(fraction(leg.start))),
                                ir.op("<=", ir.Ref(s), ir.const(fraction(leg.end))),
                            )
                        )
                        parts = [on_cw, where, ir.op("==", ir.Ref(target.var), ir.const(index))]
                        if isinstance(value, LaneRef):
                            number = ir.const(self.network.osc2_lane_index(value))
                            parts.append(ir.op("==", ir.Ref(lane), number))
                        options.append(_all([p for p in parts if p != ir.TRUE]))
            else:
                indexes = {
                    i
                    for value in self._reachable(cw)
                    if (i := self.index_of(target, value)) is not None
                }
                options.extend(
                    ir.op("and", on_cw, ir.op("==", ir.Ref(target.var), ir.const(i)))
                    if on_cw != ir.TRUE
                    else ir.op("==", ir.Ref(target.var), ir.const(i))
                    for i in sorted(indexes)
                )
        if not options:
            return ir.const(False)
        return options[0] if len(options) == 1 else ir.op("or", *options)

    def _tie_crossing(
        self, road: ir.Var | None, s: ir.Var, target: ElementField, at_start: bool
    ) -> ir.Term:
        """``along(route: c)`` of a crossing: at the start the actor stands where the
        crossing is (its road, ``s`` within half the crossing's width of its middle; the
        actor's lane and lateral place are its own modifiers'); later any crossing."""
        choices = self.choices("crossing")
        if not at_start:
            return ir.TRUE if choices else ir.const(False)
        options: list[ir.Term] = []
        for index, crossing in enumerate(self.network.crossings):
            for cw in self.roads.carriageways:
                for leg in cw.legs:
                    if leg.road != crossing.road:
                        continue
                    middle = leg.carriageway_s(crossing.s)
                    half = 0.5 * crossing.width
                    parts = [
                        self.roads.on(road, cw),
                        ir.op(">=", ir.Ref(s), ir.const(fraction(middle - half))),
                        ir.op("<=", ir.Ref(s), ir.const(fraction(middle + half))),
                        ir.op("==", ir.Ref(target.var), ir.const(index)),
                    ]
                    options.append(_all([p for p in parts if p != ir.TRUE]))
        if not options:
            return ir.const(False)
        return options[0] if len(options) == 1 else ir.op("or", *options)

    def _on_leg(self, kind: str, road: str, direction: int) -> list[Element]:
        if kind in ("road", "route"):
            return [(road, direction)]
        if kind == "lane":
            return [
                ref
                for ref in self.elements.lanes
                if ref.road == road and self.network.lane(ref).direction == direction
            ]
        return []

    def _reachable(self, cw: object) -> list[Element]:
        """Routes and lanes on a carriageway or reachable after its exit."""
        assert isinstance(cw, Carriageway)
        cache: dict[int, list[Element]] = self.network.cache.setdefault(  # type: ignore[assignment]
            "reachable_after", {}
        )
        found = cache.get(cw.index)
        if found is not None:
            return found
        values: list[Element] = []
        for leg in cw.legs:
            values.extend(self._on_leg("lane", leg.road, leg.direction))
            values.append((leg.road, leg.direction))
        last = cw.legs[-1]
        end = self.network.roads[last.road].length if last.direction > 0 else 0.0
        for ref in self._on_leg("lane", last.road, last.direction):
            assert isinstance(ref, LaneRef)
            for span in self.network.reachable(ref, end, AHEAD_CAP):
                values.append(span.lane)
                values.append((span.lane.road, self.network.lane(span.lane).direction))
        found = cache[cw.index] = list(dict.fromkeys(values))
        return found


def _all(parts: list[ir.Term]) -> ir.Term:
    if not parts:
        return ir.TRUE
    return parts[0] if len(parts) == 1 else ir.op("and", *parts)


def _enum_word(model: Model, node: ast.Node, members: dict[str, int]) -> str | None:
    """The enum member a constant argument names (``left``, ``junction_direction!left``; a
    bare name of one of the parameter's ``members``, as library defaults are written)."""
    match node:
        case ast.EnumRef():
            return node.member.text
        case ast.NameRef():
            sym = model.references.get(node.name.name)
            if sym is not None and sym.kind.name == "ENUM_MEMBER":
                return sym.name
            if sym is None and node.name.name.text in members:
                return node.name.name.text
    return None


# ---------------------------------------------------------------- the tables

Rows = list[dict[str, object]]


def _number_of_lanes(m: MapFields, given: dict[str, _Argument], inv: ast.Invocation) -> Rows | None:
    words = {k: given[k].word for k in ("lane_type", "lane_use", "directionality") if k in given}
    for k in ("lane_type", "lane_use", "directionality"):
        if k in given and given[k].word is None:
            m._skip(inv.span, f"map.number_of_lanes({k}: ...) must be a constant to be checked")
            return None
    directionality = words.get("directionality") or "uni_direction"
    if directionality not in ("uni_direction", "bi_direction"):
        m._skip(inv.span, f"map.number_of_lanes(directionality: {directionality}) is not modelled")
        return None
    counts = m.elements.lane_counts(
        m.network,
        words.get("lane_type") or "driving",
        words.get("lane_use") or "normal",
        both_directions=directionality == "bi_direction",
    )
    return [{"route": route, "num_of_lanes": n} for route, n in counts.items()]


def _in_sequence(m: MapFields, given: dict[str, _Argument], inv: ast.Invocation) -> Rows | None:
    if "road" in given:
        m._skip(inv.span, "map.routes_are_in_sequence(road: ...) is not modelled")
    return [{"preceding": a, "succeeding": b} for a, b in sorted(m.elements.sequences(m.network))]


def _follow_in_junction(
    m: MapFields, given: dict[str, _Argument], inv: ast.Invocation
) -> Rows | None:
    if "resulting_route" in given:
        m._skip(
            inv.span,
            "map.roads_follow_in_junction(resulting_route: ...) is not modelled (a route over "
            "several roads); in_road and out_road are",
        )
    return [
        {
            "junction": t.junction,
            "in_road": t.in_road,
            "out_road": t.out_road,
            "direction": t.direction,
            "clockwise_count": t.clockwise_count,
            "number_of_roads": t.number_of_roads,
            "in_lane": t.in_lane,
            "out_lane": t.out_lane,
            "junction_route": t.connecting,
        }
        for t in m.elements.turns
    ]


def _overlap(m: MapFields, given: dict[str, _Argument], inv: ast.Invocation) -> Rows | None:
    kind = given["overlap_kind"].word if "overlap_kind" in given else "any"
    if kind not in ("equal", "start", "end", "inside", "any"):
        m._skip(inv.span, f"map.routes_overlap(overlap_kind: {kind}) is not modelled")
        return None
    return [{"route1": r, "route2": r} for r in m.elements.routes]


def _opposite(m: MapFields, given: dict[str, _Argument], inv: ast.Invocation) -> Rows | None:
    routes = set(m.elements.routes)
    rows: Rows = []
    for road, direction in m.elements.routes:
        if (road, -direction) in routes:
            rows.append(
                {
                    "route1": (road, direction),
                    "route2": (road, -direction),
                    "containing_road": road,
                    "lateral_overlap": "never",
                }
            )
    return rows


def _lane_side(m: MapFields, given: dict[str, _Argument], inv: ast.Invocation) -> Rows | None:
    for unmodelled in ("lane_section", "route"):
        if unmodelled in given:
            m._skip(inv.span, f"map.{inv.name.text}({unmodelled}: ...) is not modelled")
    return [
        {"lane1": a, "side": side, "lane2": b, "count": count}
        for a, side, b, count in sorted(m.elements.lane_sides(m.network))
    ]


def _lane_ends(end: str) -> Callable[[MapFields, dict[str, _Argument], ast.Invocation], Rows]:
    def rows(m: MapFields, given: dict[str, _Argument], inv: ast.Invocation) -> Rows:
        return [{"lane": ref} for ref in sorted(m.elements.lane_ends(m.network, end))]

    return rows


def _crossing(m: MapFields, given: dict[str, _Argument], inv: ast.Invocation) -> Rows | None:
    # a crossing's geometry needs numpy, which a check without one never imports
    from osc2check.world.crossings import ANGLE_TOLERANCE, crossing_angle, crossing_lanes

    if "start_s_coord" in given:
        m._skip(
            inv.span,
            "map.crossing_connects(start_s_coord: ...) is not modelled: the crossing's own "
            "place is taken",
        )
    angle = given.get("start_angle")
    wanted: float | None = None
    if angle is not None:
        if not isinstance(angle.term, ir.Const):
            m._skip(inv.span, "map.crossing_connects(start_angle: ...) must be a constant")
        else:
            wanted = float(angle.term.value)
    rows: Rows = []
    for crossing in m.network.crossings:
        if wanted is not None and abs(crossing_angle(crossing) - wanted) > ANGLE_TOLERANCE:
            continue
        start, end = crossing_lanes(m.network, crossing)
        rows.append({"crossing": crossing.id, "start_lane": start, "end_lane": end})
    return rows


_MODIFIERS: dict[str, Callable[[MapFields, dict[str, _Argument], ast.Invocation], Rows | None]] = {
    "number_of_lanes": _number_of_lanes,
    "routes_are_in_sequence": _in_sequence,
    "roads_follow_in_junction": _follow_in_junction,
    "routes_overlap": _overlap,
    "routes_are_opposite": _opposite,
    "lane_side": _lane_side,
    "compound_lane_side": _lane_side,
    "start_lane": _lane_ends("start"),
    "end_lane": _lane_ends("end"),
    "crossing_connects": _crossing,
}


def element_value(fields: ElementFields, item: ElementField, number: int) -> ElementValue:
    """The element a solver value of ``item``'s variable stands for (the witness's)."""
    choices = fields.choices(item.kind)
    chosen = choices[min(max(number, 0), len(choices) - 1)] if choices else ""
    if item.kind == "route":
        assert isinstance(chosen, tuple)
        return ElementValue("route", road=chosen[0], direction=chosen[1])
    if item.kind == "lane":
        assert isinstance(chosen, LaneRef)
        return ElementValue("lane", chosen.road, section=chosen.section, lane=chosen.lane)
    if item.kind == "junction":
        assert isinstance(chosen, str)
        return ElementValue("junction", junction=chosen)
    if item.kind == "crossing":
        road = next((c.road for c in fields.network.crossings if c.id == chosen), "")
        return ElementValue("crossing", road=road, crossing=str(chosen))
    assert isinstance(chosen, str)
    return ElementValue("road", road=chosen)
