"""Initial placement: where every actor stands, and how fast it goes, at time 0.

Each actor of the scenario gets a lane, a longitudinal position ``s`` (of its
centre, along the road), a lateral offset ``t`` in its lane and a speed. The
road and the actors' footprints add implicit constraints; the ``at: start``
modifiers of invocations that begin at time 0 add the scenario's own.

Conventions (shown in the witness):

* Lanes: internally lane 1 is the rightmost lane in the driving direction and
  numbers grow to the left. A scenario's ``lane(k)`` counts as the map does
  (``Road.numbering``: from the right on the default roads, from the left on
  the Town06 stand-in, as CARLA does); ``from: left|right`` says explicitly
  which side ``k`` counts from. ``lane(side_of: b, side: left)`` and
  ``left_of: b`` are one lane (or ``lane:`` lanes) to the left of ``b``'s.
* Gaps: ``position(distance: d, behind: b)`` is a bumper-to-bumper gap of
  ``d`` (rear of ``b`` to front of the actor); ``ahead_of`` mirrors it.
  ``position(time: τ, ...)`` is a time headway at the follower's speed: the
  actor's with ``behind``, ``b``'s with ``ahead_of``. Without a reference,
  ``distance`` is the centre's distance from the start of the road.
* Speed: an actor starts at rest unless a ``speed()`` gives its start speed or
  refers to it (``faster_than``, ``slower_than``, ``same_as``).
  ``speed(v, faster_than: b)`` is ``factor * speed(b) + v``,
  ``slower_than`` is ``factor * speed(b) - v``, ``same_as`` is
  ``factor * speed(b)`` (``factor`` defaults to 1).
* Time 0: an invocation begins at time 0 when it is the first member of a
  top-level ``serial`` (after instantaneous members such as
  ``assign_position``, ``rain`` and ``emit``) or any member of a
  ``parallel``; the members of a ``one_of`` are alternatives and none of them
  fixes the start (an actor they place is not reported as unplaced).
* The start state: the modifiers with ``at: start`` of every invocation that
  begins at time 0, and the modifiers without ``at`` (``at: all``, which holds
  at the start too) of each actor's first such invocation, unless the actor
  has an ``at: start`` modifier of the same name. In a later invocation, even
  one that also begins at time 0, a modifier without ``at`` is a target the
  actor reaches during its phase, as runners execute it: ``speed(80kph)``
  after ``assign_position() with: speed(0kph, at: start)`` accelerates, it
  does not contradict the start.
* Every phase: ``lane(k)`` with a number and ``speed(v)`` with a value need a
  lane the road has and a speed the vehicle reaches, whenever they hold.
* The road: an actor's footprint (``vehicles.py``) lies within the road's
  length, its lane within the road's lanes and, with a lateral offset, its
  sides within the road's edges; two actors in one lane do not overlap.
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

INSTANT_ACTIONS = frozenset(
    {  # actions that set a state and take no time
        "assign_position",
        "assign_speed",
        "assign_orientation",
        "assign_acceleration",
        "set_lights",
        "set_road_friction",
        "air",
        "rain",
        "snow",
        "wind",
        "fog",
        "clouds",
        "assign_celestial_position",
        "set_bulb_state",
        "set_state",
        "set_semantic_state",
        "set_group_bulb_state",
        "set_group_state",
        "set_group_semantic_state",
    }
)
_KINDS = ("vehicle", "person", "animal", "stationary_object")
_POSITIONING = ("lane", "position")  # the modifiers that place an actor (L506)


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
    placed: bool = False  # a start `lane` or `position` modifier places it
    acts: bool = False  # the scenario invokes an action of it


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
class Placement:
    road: Road
    actors: dict[str, PlacedActor] = field(default_factory=dict)
    edges: list[tuple[str, str, Span]] = field(default_factory=list)  # a placed relative to b
    unknown_map: tuple[Span, str, tuple[str, ...]] | None = None
    unread_map: str | None = None  # an OpenDRIVE file named by the scenario (not read yet)
    unplaced_references: list[tuple[Span, str, str]] = field(default_factory=list)
    gaps: list[Gap] = field(default_factory=list)


def _kind(model, sym: Symbol | None) -> str | None:
    for ancestor in model.ancestors(sym):
        if ancestor.name in _KINDS and ancestor.library:
            return ancestor.name
    return None


def _constants(problem: ir.Problem) -> dict[str, tuple[Fraction | bool, ir.Constraint]]:
    """The constant that the first hard `==` gives each variable, and that constraint."""
    found: dict[str, tuple[Fraction | bool, ir.Constraint]] = {}
    for c in problem.constraints:
        t = c.term
        if (
            c.strength == "hard"
            and isinstance(t, ir.Op)
            and t.op == "=="
            and isinstance(t.args[0], ir.Ref)
            and isinstance(t.args[1], ir.Const)
        ):
            found.setdefault(t.args[0].var.name, (t.args[1].value, c))
    return found


def _word(node: ast.Node | None) -> str | None:
    """The enum member a modifier argument names (`start`, `at.start`), else None."""
    match node:
        case ast.NameRef():
            return node.name.name.text
        case ast.EnumRef():
            return node.member.text
    return None


class PlacementLowerer:
    def __init__(self, lowerer, scenario: Symbol, default_map: str = "default"):
        self.lw = lowerer
        self.model = lowerer.model
        self.problem: ir.Problem = lowerer.problem
        self.scenario = scenario
        self.default_map = default_map
        self.unknown_map: tuple[Span, str, tuple[str, ...]] | None = None
        self.unread_map: str | None = None
        self.lateral: set[str] = set()  # actors with a lateral offset at the start
        self.moving: set[str] = set()  # actors given a speed at the start
        self.applied: set[int] = set()  # ids of the modifiers applied at the start
        self.alternatives: list[ast.Invocation] = []  # time-0 invocations inside a one_of
        self.explicit: set[tuple[str | None, str]] = set()  # (actor, modifier) with at: start

    def lower(self) -> Placement | None:
        actors = [
            (p, _kind(self.model, p.type.symbol if p.type else None))
            for p in self.model.parameters(self.scenario)
            if p.type is not None and p.type.kind is T.Kind.COMPOUND
        ]
        actors = [(p, k) for p, k in actors if k is not None]
        if not actors:
            return None
        self.constants = _constants(self.problem)
        placement = Placement(self._road())
        placement.unknown_map = self.unknown_map
        placement.unread_map = self.unread_map
        for param, kind in actors:
            placement.actors[param.name] = self._actor(param, kind, placement.road)
        first: set[str] = set()
        starts = self._start_invocations()
        for inv in starts:  # which modifier kinds each actor gets `at: start`
            actor = inv.actor.name.name.text if isinstance(inv.actor, ast.NameRef) else None
            for item in inv.with_members:
                if (
                    isinstance(item, ast.Invocation)
                    and _word(self._args(item).get("at")) == "start"
                ):
                    self.explicit.add((actor, item.name.text))
        for inv in starts:
            self._modifiers(inv, placement, first)
        for inv in self.alternatives:
            actor = (
                placement.actors.get(inv.actor.name.name.text)
                if isinstance(inv.actor, ast.NameRef)
                else None
            )
            if actor is not None and any(
                isinstance(m, ast.Invocation) and m.name.text in _POSITIONING
                for m in inv.with_members
            ):
                actor.placed = True
        self._phase_limits(placement)
        for actor in placement.actors.values():
            if actor.name not in self.lateral:
                self._implicit(
                    ir.op("==", ir.Ref(actor.t), ir.const(0)),
                    actor.span,
                    "lane-centre",
                    f"`{actor.name}` starts on its lane centre (no `lateral(..., at: start)`)",
                )
            if actor.name not in self.moving:
                self._implicit(
                    ir.op("==", ir.Ref(actor.speed), ir.const(0)),
                    actor.span,
                    "at-rest",
                    f"`{actor.name}` starts at rest (no `speed(..., at: start)`)",
                )
            if actor.name in self.lateral or actor.footprint.width > Fraction(
                placement.road.lane_width
            ):
                self._on_road(actor, placement.road)  # else its lane keeps it on the road
        self._no_overlap(placement)
        return placement

    # ---- road and actors -----------------------------------------------------------

    def _road(self) -> Road:
        name = None
        span = None
        for var_name in self.problem.variables:
            if var_name.endswith(".map_file"):
                found = self.constants.get(var_name)
                if found is not None and isinstance(found[0], Fraction):
                    name = self.problem.strings.get(int(found[0]))
                    span = found[1].span  # the constraint that names the map
        if name is None:
            return get_map(self.default_map)
        try:
            return get_map(name)
        except UnknownMapError as err:
            road = get_map(self.default_map)
            if name.lower().endswith(".xodr"):
                self.unread_map = name  # an OpenDRIVE file: not read yet, not an error
            else:
                self.unknown_map = (span or self.problem.span, name, err.known)
            return road

    def _actor(self, param: Symbol, kind: str, road: Road) -> PlacedActor:
        category = None
        value = self.constants.get(f"{param.name}.vehicle_category", (None,))[0]
        if isinstance(value, Fraction):
            var = self.problem.variables[f"{param.name}.vehicle_category"]
            category = next((n for n, v in var.enum if v == value), None)
        if category is None:
            model_name = self.constants.get(f"{param.name}.model", (None,))[0]
            if isinstance(model_name, Fraction):
                category = category_of_model(self.problem.strings.get(int(model_name), ""))
        fp = footprint(kind, category)
        span = param.name_span or self.problem.span
        p = self.problem
        actor = PlacedActor(
            param.name,
            kind,
            fp,
            span,
            p.var(f"{param.name}@start.lane", "int", span=span),
            p.var(f"{param.name}@start.s", "real", unit="m", span=span),
            p.var(f"{param.name}@start.t", "real", unit="m", span=span),
            p.var(
                f"{param.name}@start.speed",
                "real",
                unit="kph",
                unit_factor=Fraction(5, 18),
                span=span,
            ),
        )
        s = ir.Ref(actor.s)
        half = fp.length / 2
        self._lane_range(actor, road)
        self._implicit(
            ir.op(
                "and",
                ir.op(">=", s, ir.const(half)),
                ir.op("<=", s, ir.const(Fraction(road.length) - half)),
            ),
            span,
            "road-extent",
            f"`{param.name}` ({float(fp.length):g} m long) stands on the "
            f"{road.length:g} m road `{road.name}`",
        )
        self._speed_range(actor)
        return actor

    def _on_road(self, actor: PlacedActor, road: Road) -> None:
        """The actor's sides stay on the road (with its lateral offset)."""
        width = Fraction(road.lane_width)
        fp = actor.footprint
        across = ir.op(
            "+",
            ir.op("*", ir.const(width), ir.op("-", ir.Ref(actor.lane), ir.const(Fraction(1, 2)))),
            ir.Ref(actor.t),
        )  # the centre's distance from the right edge
        self._implicit(
            ir.op(
                "and",
                ir.op(">=", across, ir.const(fp.width / 2)),
                ir.op("<=", across, ir.const(width * road.lane_count - fp.width / 2)),
            ),
            actor.span,
            "road-extent",
            f"`{actor.name}` ({float(fp.width):g} m wide) stays on "
            f"the road's {road.lane_count} lanes of {road.lane_width:g} m",
        )

    def _lane_range(self, actor: PlacedActor, road: Road) -> None:
        lane = ir.Ref(actor.lane)
        self._implicit(
            ir.op(
                "and", ir.op(">=", lane, ir.const(1)), ir.op("<=", lane, ir.const(road.lane_count))
            ),
            actor.span,
            "lane-range",
            f"road `{road.name}` has lanes 1 to {road.lane_count}",
        )

    def _speed_range(self, actor: PlacedActor) -> None:
        fp = actor.footprint
        v = ir.Ref(actor.speed)
        top = float(fp.max_speed) * 3.6
        self._implicit(
            ir.op("and", ir.op(">=", v, ir.const(0)), ir.op("<=", v, ir.const(fp.max_speed))),
            actor.span,
            "max-speed",
            f"a {fp.category} goes at most {top:g} kph",
        )

    def _implicit(self, term: ir.Term, span: Span, rule: str, text: str) -> None:
        self.problem.add(
            ir.Constraint(term, span, "placement", text, "hard", rule=rule, explanation=text)
        )

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
            case ast.Composition(op="one_of"):
                # alternatives: none of them is known to run at time 0, so none fixes a
                # start; an actor one of them places counts as placed (no L506)
                for member in body.members:
                    inner: list[ast.Invocation] = []
                    self._collect(member.body, inner)
                    self.alternatives.extend(inner)
                return False
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

    def _modifiers(self, inv: ast.Invocation, placement: Placement, first: set[str]) -> None:
        """Apply the start modifiers of a time-0 invocation: those with `at: start`, and,
        in the actor's first invocation, those without `at` (`at: all` holds at the start
        too) unless a modifier of the same name gives the actor's start explicitly."""
        if not isinstance(inv.actor, ast.NameRef):
            return
        actor = placement.actors.get(inv.actor.name.name.text)
        if actor is None:
            return
        is_first = actor.name not in first
        first.add(actor.name)
        for item in inv.with_members:
            if not isinstance(item, ast.Invocation):
                continue
            args = self._args(item)
            at = _word(args.get("at"))
            if not (
                at == "start"
                or (
                    is_first
                    and at in (None, "all")
                    and (actor.name, item.name.text) not in self.explicit
                )
            ):
                continue
            handler = getattr(self, f"_mod_{item.name.text}", None)
            if handler is not None:
                actor.placed = actor.placed or item.name.text in _POSITIONING
                self.applied.add(id(item))
                handler(actor, args, item, placement)

    def _phase_limits(self, placement: Placement) -> None:
        """A `lane(k)` or `speed(v)` of any phase needs a lane the road has and a speed
        the vehicle reaches, whenever the phase runs."""
        for members in self.lw.member_decls.get(self.scenario, []):
            for member in members:
                if not isinstance(member, ast.DoDirective):
                    continue
                for inv in _invocations(member.member.body):
                    if not isinstance(inv.actor, ast.NameRef):
                        continue
                    actor = placement.actors.get(inv.actor.name.name.text)
                    if actor is None:
                        continue
                    actor.acts = True
                    for item in inv.with_members:
                        if (
                            isinstance(item, ast.Invocation)
                            and id(item) not in self.applied
                            and item.name.text in ("lane", "speed")
                        ):
                            self._phase_limit(actor, item, placement)

    def _phase_limit(self, actor: PlacedActor, item: ast.Invocation, placement: Placement) -> None:
        args = self._args(item)
        name = item.name.text
        if (
            name == "lane"
            and "lane" in args
            and not any(k in args for k in ("same_as", "side_of", "left_of", "right_of"))
        ):
            lane = self.problem.var(f"{actor.name}@{item.span.line}.lane", "int", span=actor.span)
            saved, actor.lane = actor.lane, lane
            try:
                self._lane_range(actor, placement.road)
                self._mod_lane(actor, args, item, placement)
            finally:
                actor.lane = saved
        elif (
            name == "speed"
            and "speed" in args
            and not any(k in args for k in ("faster_than", "slower_than", "same_as"))
        ):
            speed = self.problem.var(
                f"{actor.name}@{item.span.line}.speed",
                "real",
                unit="kph",
                unit_factor=Fraction(5, 18),
                span=actor.span,
            )
            saved, actor.speed = actor.speed, speed
            try:
                self._speed_range(actor)
                self._mod_speed(actor, args, item, placement)
            finally:
                actor.speed = saved

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

    def _reference(
        self, node: ast.Node | None, actor: PlacedActor, placement: Placement, span: Span
    ) -> PlacedActor | None:
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
        from osc2check.verify.lower import call_span

        span = call_span(item)
        self.problem.add(ir.Constraint(term, span, "modifier", self.lw.text_of(span)))

    def _mod_lane(self, actor, args, item, placement) -> None:
        lane = ir.Ref(actor.lane)
        from osc2check.verify.lower import coerce

        count = (
            coerce(actor.lane, self._value(args["lane"]))
            if "lane" in args and not isinstance(args["lane"], ast.RangeLiteral)
            else None
        )
        for key, sign in (("side_of", None), ("left_of", 1), ("right_of", -1)):
            if key not in args:
                continue
            other = self._reference(args[key], actor, placement, item.span)
            if other is None:
                return
            if sign is None:
                sign = 1 if _word(args.get("side")) == "left" else -1
            step = count if count is not None else ir.const(1)
            offset = step if sign > 0 else ir.op("neg", step)
            self._require(ir.op("==", lane, ir.op("+", ir.Ref(other.lane), offset)), item)
            return
        if "same_as" in args:
            other = self._reference(args["same_as"], actor, placement, item.span)
            if other is not None:
                self._require(ir.op("==", lane, ir.Ref(other.lane)), item)
            return
        if "lane" not in args:
            return
        road = placement.road
        numbering = road.numbering
        side = _word(args.get("from"))
        if side in ("left", "right"):
            numbering = f"from_{side}"
        node = args["lane"]
        if isinstance(node, ast.RangeLiteral):
            low, high = self._value(node.low), self._value(node.high)
            if low is None or high is None:
                return
            low, high = (
                _internal_lane(coerce(actor.lane, b), road, numbering) for b in (low, high)
            )
            from osc2check.verify.lower import in_range

            self._require(in_range(lane, low, high), item)
        elif count is not None:
            self._require(ir.op("==", lane, _internal_lane(count, road, numbering)), item)

    def _mod_position(self, actor, args, item, placement) -> None:
        s = ir.Ref(actor.s)
        gap = None
        reference_key = "behind" if "behind" in args else "ahead_of" if "ahead_of" in args else None
        other = (
            self._reference(args.get(reference_key), actor, placement, item.span)
            if reference_key
            else None
        )
        if "distance" in args:
            gap = self._value(args["distance"])
        elif "time" in args and other is not None:
            duration = self._value(args["time"])
            follower = actor if reference_key == "behind" else other
            if duration is not None:
                gap = ir.op("*", duration, ir.Ref(follower.speed))
        if gap is None:
            return
        if other is None:
            self._require(ir.op("==", s, gap), item)
            return
        half = ir.const((actor.footprint.length + other.footprint.length) / 2)
        distance = ir.op("+", half, gap)
        target = (
            ir.op("-", ir.Ref(other.s), distance)
            if reference_key == "behind"
            else ir.op("+", ir.Ref(other.s), distance)
        )
        self._require(ir.op("==", s, target), item)
        follower = actor if reference_key == "behind" else other
        placement.gaps.append(
            Gap(
                follower.name,
                (other if follower is actor else actor).name,
                gap,
                ir.Ref(follower.speed),
                item.span,
                self.lw.text_of(item.span),
            )
        )

    def _mod_speed(self, actor, args, item, placement) -> None:
        self.moving.add(actor.name)
        v = ir.Ref(actor.speed)
        node = args.get("speed")
        for key, sign in (("faster_than", 1), ("slower_than", -1), ("same_as", 0)):
            if key in args:
                other = self._reference(args[key], actor, placement, item.span)
                if other is None:
                    return
                self.moving.add(other.name)  # its speed is what this one's depends on
                delta = self._value(node) if node is not None else ir.const(0)
                if delta is None:
                    return
                base: ir.Term = ir.Ref(other.speed)
                if "factor" in args:
                    factor = self._value(args["factor"])
                    if factor is None:
                        return
                    base = ir.op("*", factor, base)
                target = (
                    base
                    if sign == 0 and node is None
                    else ir.op("+" if sign >= 0 else "-", base, delta)
                )
                self._require(ir.op("==", v, target), item)
                return
        if node is None:
            return
        if isinstance(node, ast.RangeLiteral):
            low, high = self._value(node.low), self._value(node.high)
            if low is not None and high is not None:
                from osc2check.verify.lower import in_range

                self._require(in_range(v, low, high), item)
            return
        value = self._value(node)
        if value is not None:
            self._require(ir.op("==", v, value), item)

    def _mod_lateral(self, actor, args, item, placement) -> None:
        node = args.get("distance")
        value = self._value(node) if node is not None else None
        self.lateral.add(actor.name)
        if value is not None:
            if _word(args.get("side")) == "right" and "side_of" not in args:
                value = ir.op("neg", value)  # an offset to the right of the lane centre
            self._require(ir.op("==", ir.Ref(actor.t), value), item)

    # ---- no overlap --------------------------------------------------------------------

    def _no_overlap(self, placement: Placement) -> None:
        fixed = self._fixed_lanes(placement)
        names = list(placement.actors)
        for i, a_name in enumerate(names):
            for b_name in names[i + 1 :]:
                if a_name in fixed and b_name in fixed and fixed[a_name] != fixed[b_name]:
                    continue  # never in the same lane
                a, b = placement.actors[a_name], placement.actors[b_name]
                need = ir.const((a.footprint.length + b.footprint.length) / 2)
                sa, sb = ir.Ref(a.s), ir.Ref(b.s)
                term = ir.op(
                    "or",
                    ir.op("!=", ir.Ref(a.lane), ir.Ref(b.lane)),
                    ir.op(">=", ir.op("-", sa, sb), need),
                    ir.op(">=", ir.op("-", sb, sa), need),
                )
                self._implicit(
                    term,
                    a.span,
                    "overlap",
                    f"`{a_name}` and `{b_name}` do not overlap at the start",
                )

    def _fixed_lanes(self, placement: Placement) -> dict[str, Fraction]:
        """The start lanes that the lane modifiers fix: `lane(2)`, and `lane(same_as: b)` or
        `lane(side_of: b, ...)` once `b`'s is fixed. Pairs of actors in lanes fixed apart
        need no constraint against overlapping."""
        from osc2check.verify.quick import linear

        owner = {a.lane.name: name for name, a in placement.actors.items()}
        equations = []
        for c in self.problem.constraints:
            t = c.term
            if c.kind == "modifier" and isinstance(t, ir.Op) and t.op == "==":
                names = ir.names(t)
                if names and names <= owner.keys():
                    left, right = linear(t.args[0]), linear(t.args[1])
                    if left is not None and right is not None:
                        form = dict(left[0])
                        for v, k in right[0].items():
                            form[v] = form.get(v, Fraction(0)) - k
                        equations.append(({v: k for v, k in form.items() if k}, left[1] - right[1]))
        known: dict[str, Fraction] = {}
        changed = True
        while changed:
            changed = False
            for form, constant in equations:
                unknown = [v for v in form if v not in known]
                if len(unknown) == 1:
                    v = unknown[0]
                    rest = constant + sum(k * known[u] for u, k in form.items() if u != v)
                    known[v] = -rest / form[v]
                    changed = True
        return {owner[v]: value for v, value in known.items()}


def _invocations(body):
    """The invocations of a `do` tree, in source order."""
    match body:
        case ast.Composition():
            for member in body.members:
                yield from _invocations(member.body)
        case ast.Invocation():
            yield body


def _internal_lane(number: ir.Term, road: Road, numbering: str) -> ir.Term:
    """The internal lane (1 = rightmost) that a scenario's lane ``number`` names."""
    if numbering != "from_left":
        return number
    if isinstance(number, ir.Const):
        return ir.const(road.lane_count + 1 - number.value)
    return ir.op("-", ir.const(road.lane_count + 1), number)


def lower_placement(lowerer, scenario: Symbol, default_map: str = "default") -> Placement | None:
    """Add the placement variables and constraints of ``scenario`` to the lowerer's problem."""
    return PlacementLowerer(lowerer, scenario, default_map).lower()
