"""Initial placement: where every actor stands, and how fast it goes, at time 0.

Each actor of the scenario gets a lane, a longitudinal position ``s`` (of its
centre, along the road), a lateral offset ``t`` in its lane and a speed. The
road and the actors' footprints add implicit constraints; the ``at: start``
modifiers of invocations that begin at time 0 add the scenario's own.

Conventions (shown in the witness): lane 1 is the rightmost lane in the
driving direction; ``position(distance: d, behind: b)`` is a bumper-to-bumper
gap of ``d``; an invocation begins at time 0 when it is the first member of a
top-level ``serial`` (after instantaneous members such as ``assign_position``
and ``emit``) or any member of a ``parallel``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction

from osc2check.road import Road, UnknownMapError, get_map
from osc2check.semantics import types as T
from osc2check.semantics.symbols import Symbol
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.vehicles import Footprint, category_of_model, footprint
from osc2check.verify import ir

INSTANT_ACTIONS = frozenset({"assign_position", "assign_speed", "assign_orientation",
                             "assign_acceleration", "set_lights", "set_road_friction"})
_KINDS = ("vehicle", "person", "animal", "stationary_object")


@dataclass
class PlacedActor:
    name: str
    kind: str
    footprint: Footprint
    span: Span
    lane: ir.Var
    s: ir.Var
    t: ir.Var
    speed: ir.Var
    placed: bool = False  # some `at: start` modifier positions it


@dataclass
class Placement:
    road: Road
    actors: dict[str, PlacedActor] = field(default_factory=dict)
    edges: list[tuple[str, str, Span]] = field(default_factory=list)  # a placed relative to b
    unknown_map: tuple[Span, str, tuple[str, ...]] | None = None
    unplaced_references: list[tuple[Span, str, str]] = field(default_factory=list)


def _kind(model, sym: Symbol | None) -> str | None:
    for ancestor in model.ancestors(sym):
        if ancestor.name in _KINDS and ancestor.library:
            return ancestor.name
    return None


def _constant_of(problem: ir.Problem, var_name: str) -> Fraction | bool | None:
    var = problem.variables.get(var_name)
    if var is None:
        return None
    for c in problem.constraints:
        t = c.term
        if c.strength == "hard" and isinstance(t, ir.Op) and t.op == "==" and \
                isinstance(t.args[0], ir.Ref) and t.args[0].var is var and \
                isinstance(t.args[1], ir.Const):
            return t.args[1].value
    return None


class PlacementLowerer:
    def __init__(self, lowerer, scenario: Symbol, default_map: str = "default"):
        self.lw = lowerer
        self.model = lowerer.model
        self.problem: ir.Problem = lowerer.problem
        self.scenario = scenario
        self.default_map = default_map
        self.unknown_map: tuple[Span, str, tuple[str, ...]] | None = None
        self.lateral: set[str] = set()  # actors with a lateral offset at the start

    def lower(self) -> Placement | None:
        actors = [(p, _kind(self.model, p.type.symbol if p.type else None))
                  for p in self.model.parameters(self.scenario)
                  if p.type is not None and p.type.kind is T.Kind.COMPOUND]
        actors = [(p, k) for p, k in actors if k is not None]
        if not actors:
            return None
        placement = Placement(self._road())
        placement.unknown_map = self.unknown_map
        for param, kind in actors:
            placement.actors[param.name] = self._actor(param, kind, placement.road)
        for inv in self._start_invocations():
            self._modifiers(inv, placement)
        for actor in placement.actors.values():
            if actor.name not in self.lateral:
                self._implicit(ir.op("==", ir.Ref(actor.t), ir.const(0)), actor.span,
                               "lane-centre", f"`{actor.name}` starts on its lane centre "
                               "(no `lateral(..., at: start)`)")
        self._no_overlap(placement)
        return placement

    # ---- road and actors -----------------------------------------------------------

    def _road(self) -> Road:
        name = None
        span = None
        for var_name in self.problem.variables:
            if var_name.endswith(".map_file"):
                value = _constant_of(self.problem, var_name)
                if isinstance(value, Fraction):
                    name = self.problem.strings.get(int(value))
                    span = self.problem.variables[var_name].span
        if name is None:
            return get_map(self.default_map)
        try:
            return get_map(name)
        except UnknownMapError as err:
            road = get_map(self.default_map)
            self.unknown_map = (span or self.problem.span, name, err.known)
            return road

    def _actor(self, param: Symbol, kind: str, road: Road) -> PlacedActor:
        category = None
        value = _constant_of(self.problem, f"{param.name}.vehicle_category")
        if isinstance(value, Fraction):
            var = self.problem.variables[f"{param.name}.vehicle_category"]
            category = next((n for n, v in var.enum if v == value), None)
        if category is None:
            model_name = _constant_of(self.problem, f"{param.name}.model")
            if isinstance(model_name, Fraction):
                category = category_of_model(self.problem.strings.get(int(model_name), ""))
        fp = footprint(kind, category)
        span = param.name_span or self.problem.span
        p = self.problem
        actor = PlacedActor(
            param.name, kind, fp, span,
            p.var(f"{param.name}@start.lane", "int", span=span),
            p.var(f"{param.name}@start.s", "real", unit="m", span=span),
            p.var(f"{param.name}@start.t", "real", unit="m", span=span),
            p.var(f"{param.name}@start.speed", "real", unit="kph",
                  unit_factor=Fraction(5, 18), span=span),
        )
        lane, s, t, v = (ir.Ref(actor.lane), ir.Ref(actor.s), ir.Ref(actor.t),
                         ir.Ref(actor.speed))
        half = fp.length / 2
        self._implicit(ir.op("and", ir.op(">=", lane, ir.const(1)),
                             ir.op("<=", lane, ir.const(road.lane_count))), span, "lane-range",
                       f"road `{road.name}` has lanes 1 to {road.lane_count}")
        self._implicit(ir.op("and", ir.op(">=", s, ir.const(half)),
                             ir.op("<=", s, ir.const(Fraction(road.length) - half))), span,
                       "road-extent",
                       f"`{param.name}` ({fp.length} m long) stands on the {road.length:g} m "
                       f"road `{road.name}`")
        half_lane = Fraction(road.lane_width) / 2 - fp.width / 2
        self._implicit(ir.op("and", ir.op(">=", t, ir.const(-max(half_lane, Fraction(0)))),
                             ir.op("<=", t, ir.const(max(half_lane, Fraction(0))))), span,
                       "road-extent", f"`{param.name}` stays inside its lane")
        top = float(fp.max_speed) * 3.6
        self._implicit(ir.op("and", ir.op(">=", v, ir.const(0)),
                             ir.op("<=", v, ir.const(fp.max_speed))), span, "max-speed",
                       f"a {fp.category} goes at most {top:g} kph")
        return actor

    def _implicit(self, term: ir.Term, span: Span, rule: str, text: str) -> None:
        self.problem.add(ir.Constraint(term, span, "placement", text, "hard", rule=rule,
                                       explanation=text))

    # ---- the invocations that begin at time 0 ------------------------------------------

    def _start_invocations(self) -> list[ast.Invocation]:
        found: list[ast.Invocation] = []
        decls = self.lw.member_decls.get(self.scenario, [])
        for members in decls:
            for member in members:
                if isinstance(member, ast.DoDirective):
                    self._collect(member.member.body, found)
        return found

    def _collect(self, body, found: list) -> bool:
        """Add the time-0 invocations of ``body``; True if ``body`` takes no time."""
        match body:
            case ast.Composition(op="serial"):
                for member in body.members:
                    if not self._collect(member.body, found):
                        return False
                return True
            case ast.Composition():
                instant = True
                for member in body.members:
                    instant = self._collect(member.body, found) and instant
                return instant
            case ast.Invocation():
                found.append(body)
                return body.name.text in INSTANT_ACTIONS
            case ast.Emit() | ast.CallDirective():
                return True
        return False

    def _modifiers(self, inv: ast.Invocation, placement: Placement) -> None:
        if not isinstance(inv.actor, ast.NameRef):
            return
        actor = placement.actors.get(inv.actor.name.name.text)
        if actor is None:
            return
        for item in inv.with_members:
            if not isinstance(item, ast.Invocation):
                continue
            args = self._args(item)
            at = args.get("at")
            if not (isinstance(at, ast.NameRef) and at.name.name.text == "start"):
                continue
            handler = getattr(self, f"_mod_{item.name.text}", None)
            if handler is not None:
                actor.placed = True
                handler(actor, args, item, placement)

    def _args(self, inv: ast.Invocation) -> dict[str, ast.Node]:
        modifier = self.model.references.get(inv.name)
        params = self.model.parameters(modifier) if modifier is not None else []
        bound: dict[str, ast.Node] = {}
        position = 0
        for arg in inv.arguments:
            if isinstance(arg, ast.PositionalArgument) and position < len(params):
                bound[params[position].name] = arg.value
                position += 1
            elif isinstance(arg, ast.NamedArgument):
                bound[arg.name.text] = arg.value
        return bound

    def _scope(self):
        from osc2check.verify.lower import Scope

        return Scope("", self.scenario, "", self.scenario)

    def _value(self, node: ast.Node) -> ir.Term | None:
        from osc2check.verify.lower import NotEncodable

        try:
            return self.lw._term(node, self._scope())
        except NotEncodable as reason:
            self.problem.skipped.append((node.span, str(reason)))
            return None

    def _reference(self, node: ast.Node | None, actor: PlacedActor, placement: Placement,
                   span: Span) -> PlacedActor | None:
        if not isinstance(node, ast.NameRef):
            return None
        name = node.name.name.text
        other = placement.actors.get(name)
        if other is None:
            placement.unplaced_references.append((node.span, actor.name, name))
            return None
        placement.edges.append((actor.name, name, span))
        return other

    def _require(self, term: ir.Term, item: ast.Invocation) -> None:
        self.problem.add(ir.Constraint(term, item.span, "modifier", self.lw.text_of(item.span)))

    def _mod_lane(self, actor, args, item, placement) -> None:
        lane = ir.Ref(actor.lane)
        count = self._value(args["lane"]) if "lane" in args else None
        for key, sign in (("side_of", None), ("left_of", 1), ("right_of", -1)):
            if key not in args:
                continue
            other = self._reference(args[key], actor, placement, item.span)
            if other is None:
                return
            if sign is None:
                side = args.get("side")
                sign = 1 if isinstance(side, ast.NameRef) and \
                    side.name.name.text == "left" else -1
            step = count if count is not None else ir.const(1)
            offset = step if sign > 0 else ir.op("neg", step)
            self._require(ir.op("==", lane, ir.op("+", ir.Ref(other.lane), offset)), item)
            return
        if "same_as" in args:
            other = self._reference(args["same_as"], actor, placement, item.span)
            if other is not None:
                self._require(ir.op("==", lane, ir.Ref(other.lane)), item)
            return
        if "lane" in args and count is not None:
            road = placement.road
            if road.numbering == "from_left":  # scenario numbers count from the left
                count = ir.op("-", ir.const(road.lane_count + 1), count)
            node = args["lane"]
            if isinstance(node, ast.RangeLiteral):
                low, high = (ir.op("-", ir.const(road.lane_count + 1), self._value(b))
                             if road.numbering == "from_left" else self._value(b)
                             for b in (node.low, node.high))
                term = ir.op("or", ir.op("and", ir.op(">=", lane, low), ir.op("<=", lane, high)),
                             ir.op("and", ir.op(">=", lane, high), ir.op("<=", lane, low)))
            else:
                term = ir.op("==", lane, count)
            self._require(term, item)

    def _mod_position(self, actor, args, item, placement) -> None:
        s = ir.Ref(actor.s)
        gap = None
        reference_key = "behind" if "behind" in args else "ahead_of" if "ahead_of" in args \
            else None
        other = self._reference(args.get(reference_key), actor, placement, item.span) \
            if reference_key else None
        if "distance" in args:
            gap = self._value(args["distance"])
        elif "time" in args and other is not None:
            duration = self._value(args["time"])
            if duration is not None:
                gap = ir.op("*", duration, ir.Ref(other.speed))
        if gap is None:
            return
        if other is None:
            self._require(ir.op("==", s, gap), item)
            return
        half = ir.const((actor.footprint.length + other.footprint.length) / 2)
        distance = ir.op("+", half, gap)
        target = ir.op("-", ir.Ref(other.s), distance) if reference_key == "behind" else \
            ir.op("+", ir.Ref(other.s), distance)
        self._require(ir.op("==", s, target), item)

    def _mod_speed(self, actor, args, item, placement) -> None:
        v = ir.Ref(actor.speed)
        node = args.get("speed")
        for key, sign in (("faster_than", 1), ("slower_than", -1), ("same_as", 0)):
            if key in args:
                other = self._reference(args[key], actor, placement, item.span)
                if other is None:
                    return
                delta = self._value(node) if node is not None else ir.const(0)
                if delta is None:
                    return
                base = ir.Ref(other.speed)
                target = base if sign == 0 and node is None else ir.op(
                    "+" if sign >= 0 else "-", base, delta)
                self._require(ir.op("==", v, target), item)
                return
        if node is None:
            return
        if isinstance(node, ast.RangeLiteral):
            self._require(self.lw._in_range(v, node, self._scope()), item)
            return
        value = self._value(node)
        if value is not None:
            self._require(ir.op("==", v, value), item)

    def _mod_lateral(self, actor, args, item, placement) -> None:
        node = args.get("distance")
        value = self._value(node) if node is not None else None
        self.lateral.add(actor.name)
        if value is not None:
            self._require(ir.op("==", ir.Ref(actor.t), value), item)

    # ---- no overlap --------------------------------------------------------------------

    def _no_overlap(self, placement: Placement) -> None:
        fixed = {name: self._fixed_lane(a) for name, a in placement.actors.items()}
        names = list(placement.actors)
        for i, a_name in enumerate(names):
            for b_name in names[i + 1:]:
                if fixed[a_name] is not None and fixed[b_name] is not None and \
                        fixed[a_name] != fixed[b_name]:
                    continue  # never in the same lane
                a, b = placement.actors[a_name], placement.actors[b_name]
                need = ir.const((a.footprint.length + b.footprint.length) / 2)
                sa, sb = ir.Ref(a.s), ir.Ref(b.s)
                term = ir.op("or", ir.op("!=", ir.Ref(a.lane), ir.Ref(b.lane)),
                             ir.op(">=", ir.op("-", sa, sb), need),
                             ir.op(">=", ir.op("-", sb, sa), need))
                self._implicit(term, a.span, "overlap",
                               f"`{a_name}` and `{b_name}` do not overlap at the start")

    def _fixed_lane(self, actor: PlacedActor) -> Fraction | None:
        for c in self.problem.constraints:
            t = c.term
            if c.kind == "modifier" and isinstance(t, ir.Op) and t.op == "==" and \
                    isinstance(t.args[0], ir.Ref) and t.args[0].var is actor.lane and \
                    isinstance(t.args[1], ir.Const):
                return t.args[1].value
        return None


def lower_placement(lowerer, scenario: Symbol, default_map: str = "default") -> Placement | None:
    """Add the placement variables and constraints of ``scenario`` to the lowerer's problem."""
    return PlacementLowerer(lowerer, scenario, default_map).lower()
