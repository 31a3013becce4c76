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
  ``parallel``. The acting members of a ``one_of`` that begins at time 0 are
  alternatives: an integer variable (``terms.one_of_choice``) says which one the
  run chooses, and each member's start modifiers hold when it is the one chosen
  (``choice == k => ...``), so the solver proves that some member can be placed
  and the witness places the actors for the member the runner then runs.
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
* The road: an actor's footprint (``world.catalogue``) lies within the road's
  length, its lane within the road's lanes and, with a lateral offset, its
  sides within the road's edges; two actors in one lane do not overlap.
* Maps: the map is the scenario's ``map_file`` (``keep(m.map_file == ...)`` or
  ``map.set_map_file(...)``): a built-in name or an OpenDRIVE file relative to
  the scenario file (``osc2check.world.maps``). An actor's lane, ``s`` and ``t``
  are taken on a carriageway (``road_terms``): on a map with several, the
  solver also chooses which (``<actor>@start.road``). Lanes are OSC2's numbers
  on the actor's road and direction; gaps are measured along one carriageway.
  Fields of type road, route, lane and junction, the map modifiers and `along`
  are ``map_modifiers``'.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from fractions import Fraction
from typing import TYPE_CHECKING

from osc2check.semantics import types as T
from osc2check.semantics.bindings import ReadArguments
from osc2check.semantics.constants import NotConstant, Quantity, Value, initial_value
from osc2check.semantics.members import actor_alias, scenario_do
from osc2check.semantics.model import Model
from osc2check.semantics.phases import (
    Guard,
    acting_members,
    enum_word,
    invocations,
    modifier_timing,
    time_zero,
)
from osc2check.semantics.stdlib import CARLA
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.syntax.walk import walk
from osc2check.verify import ir
from osc2check.verify.lane_steps import LaneSteps, one_of_members
from osc2check.verify.map_modifiers import MapFields
from osc2check.verify.parameters import Lowerer
from osc2check.verify.problem import ConstraintProblem
from osc2check.verify.propagate import linear
from osc2check.verify.road_terms import RoadTerms, between, fraction
from osc2check.verify.room import motion_bounds
from osc2check.verify.starts import (
    ActorBody,
    Gap,
    MapChoice,
    PlacedActor,
    StartPlacement,
    largest,
)
from osc2check.verify.terms import (
    MAX_DEPTH,
    InstanceScope,
    NotEncodable,
    call_span,
    coerce,
    in_range,
    join_path,
    one_of_variable,
)
from osc2check.world.catalogue import (
    ACTOR_KINDS,
    CATEGORIES,
    NOT_ON_ROADS,
    ActorRow,
    kind_row,
    model_row,
)
from osc2check.world.errors import MapError, UnknownMapError
from osc2check.world.maps import find_map, map_path, scenario_folder
from osc2check.world.numbering import LANE_REFERENCES, lane_side

if TYPE_CHECKING:
    pass

_POSITIONING = ("lane", "position")  # the modifiers that place an actor (L506)
#: actions whose actor stands still throughout
_STANDING = ("remain_stationary",)
_DEGREE = Fraction(314159265358979, 18000000000000000)  # pi / 180 (a unit factor)
#: the rule of "a vehicle whose category nothing constrains is a car": a placement that
#: has no solution with it is tried again with those vehicles of any category
UNSAID_CATEGORY = "unsaid-category"
#: the witness prefers starts in this first share of the road: room to drive ahead
PREFERRED_START_SHARE = Fraction(3, 10)


def actor_kind(model: Model, sym: Symbol | None) -> str | None:
    """The catalogue kind of an actor type (vehicle, person, animal, stationary_object)."""
    for ancestor in model.ancestors(sym):
        if ancestor.name in ACTOR_KINDS and ancestor.library:
            return ancestor.name
    return None


def _is_trailer(model: Model, sym: Symbol | None) -> bool:
    return any(a.name == "trailer" and a.library for a in model.ancestors(sym))


def _constants(problem: ConstraintProblem) -> dict[str, tuple[Fraction | bool, ir.Constraint]]:
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


class PlacementLowerer:
    def __init__(
        self,
        lowerer: Lowerer,
        scenario: Symbol,
        default_map: str = "default",
        maps: Mapping[str, str] | None = None,
        open_categories: bool = False,
    ):
        self.lw = lowerer
        #: vehicles whose category nothing constrains may be of any category (preferably
        #: cars): the second try when placing them as cars has no solution
        self.open_categories = open_categories
        self.model = lowerer.model
        self.problem: ConstraintProblem = lowerer.problem
        self.scenario = scenario
        self.default_map = default_map
        self.maps = maps or {}  # map names -> files (`[tool.osc2check.maps]`)
        self.lateral: set[str] = set()  # actors with a lateral offset at the start
        self.moving: set[str] = set()  # actors given a speed at the start
        self.applied: set[int] = set()  # ids of the modifiers applied at the start
        #: time-0 invocations inside a ``one_of``, with the choice under which they run
        self.alternatives: list[tuple[ast.Invocation, InstanceScope, ir.Term]] = []
        self.guard: ir.Term | None = None  # the choice the modifiers being applied need
        #: actors given a speed or a lateral offset at the start only under a choice
        self.moving_when: dict[str, list[ir.Term]] = {}
        self.lateral_when: dict[str, list[ir.Term]] = {}
        self.scope = self._root_scope()  # the instance whose members are being placed
        self.explicit: set[tuple[str | None, str]] = set()  # (actor, modifier) with at: start

    def lower(self) -> StartPlacement | None:
        candidates = [
            (p, actor_kind(self.model, p.type.symbol if p.type else None))
            for p in self.model.parameters(self.scenario)
            if p.type is not None
            and p.type.kind is T.Kind.COMPOUND
            and actor_alias(self.model, p) is None  # another name of an actor placed here
        ]
        actors = [(p, k) for p, k in candidates if k is not None]
        self.constants = _constants(self.problem)
        if not actors and not self._map_modifier_members() and self._map_name()[0] is None:
            return None  # nothing to place, and no map to read (lights may stand on one)
        self.written: set[str] = set()  # variables the scenario's own constraints mention
        for c in self.problem.constraints:
            if c.kind not in ("domain", "placement"):
                self.written |= ir.names(c.term)
        choice = self._map()
        self.terms = terms = RoadTerms(choice.facts.carriageways, choice.name)
        placement = StartPlacement(choice, terms)
        self.fields = MapFields(choice.found, terms, lw=self.lw)
        placement.fields = self.fields
        for param, kind in actors:
            placement.actors[param.name] = self._actor(param, kind)
        self._map_modifiers(placement)
        first: set[str] = set()
        self._apply_starts(self._start_invocations(), placement, first)
        self._alternatives(placement, first)
        self._phase_limits(placement)
        for actor in placement.actors.values():
            if actor.name not in self.lateral:
                self._implicit(
                    _unless(
                        self.lateral_when.get(actor.name), ir.op("==", ir.Ref(actor.t), ir.const(0))
                    ),
                    actor.span,
                    "lane-centre",
                    f"`{actor.name}` starts on its lane centre (no `lateral(..., at: start)`)",
                )
            if actor.name not in self.moving:
                self._implicit(
                    _unless(
                        self.moving_when.get(actor.name),
                        ir.op("==", ir.Ref(actor.speed), ir.const(0)),
                    ),
                    actor.span,
                    "at-rest",
                    f"`{actor.name}` starts at rest (no `speed(..., at: start)`)",
                )
            narrowest = min(
                (p.width for cw in terms.carriageways for p in cw.pieces if p.count), default=0.0
            )
            if actor.name in self.lateral or actor.body.widest() > fraction(narrowest):
                self._on_road(actor)  # else its lane keeps it on the road
        self._no_overlap(placement)
        self._room(placement)
        self._preferences(placement)
        return placement

    def _alternatives(self, placement: StartPlacement, first: set[str]) -> None:
        """Apply the start modifiers of the time-0 invocations of ``one_of`` members, each
        under the choice of its member: the modifiers of each member's invocations apply
        as those of the scenario's own time-0 invocations do (``_modifiers``), to the
        actors' state after those."""
        members: dict[ir.Term, list[tuple[ast.Invocation, InstanceScope]]] = {}
        for inv, scope, guard in self.alternatives:
            members.setdefault(guard, []).append((inv, scope))
        moving, lateral = set(self.moving), set(self.lateral)
        for guard, invs in members.items():
            self.guard = guard
            explicit = set(self.explicit)
            self._apply_starts(invs, placement, set(first))
            self.explicit = explicit
            for name in self.moving - moving:
                self.moving_when.setdefault(name, []).append(guard)
            for name in self.lateral - lateral:
                self.lateral_when.setdefault(name, []).append(guard)
            self.moving, self.lateral = set(moving), set(lateral)
        self.guard = None
        self.scope = self._root_scope()

    def _apply_starts(
        self,
        starts: list[tuple[ast.Invocation, InstanceScope]],
        placement: StartPlacement,
        first: set[str],
    ) -> None:
        """Apply the start modifiers of time-0 invocations (``_modifiers``), having noted
        which modifier kinds each actor gets ``at: start``."""
        for inv, scope in starts:
            self.scope = scope
            started = self._actor_at(inv, placement)
            for item in inv.with_members:
                if (
                    isinstance(item, ast.Invocation)
                    and modifier_timing(self._args(item)) == "start"
                ):
                    self.explicit.add((started.name if started else None, item.name.text))
        for inv, scope in starts:
            self.scope = scope
            self._modifiers(inv, placement, first)

    def _choice(self, guard: Guard, scope: InstanceScope) -> ir.Term:
        """The term "the run chooses these members" of the ``one_of`` choices ``guard``."""
        chosen: list[ir.Term] = []
        for comp, index in guard:
            shared = one_of_variable(scope.prefix, comp)
            known = shared.name in self.problem.variables
            var = self.problem.variables.setdefault(shared.name, shared)
            if not known:
                count = len(acting_members(comp))
                self.problem.add(
                    ir.Constraint(
                        in_range(ir.Ref(var), ir.const(0), ir.const(count - 1)),
                        comp.span,
                        "domain",
                        f"one member of the `one_of` (1 to {count}) runs",
                    )
                )
            chosen.append(ir.op("==", ir.Ref(var), ir.const(index)))
        return chosen[0] if len(chosen) == 1 else ir.op("and", *chosen)

    # ---- room to drive, and plausible values -------------------------------------------

    def _room(self, placement: StartPlacement) -> None:
        """Where speeds and durations are constants: road enough ahead of each start."""
        bodies = [member.body for member in self._bodies(self.scenario)]
        motion = motion_bounds(self.model, bodies, self._lookup)
        if motion.duration is None or motion.duration == 0:
            return
        terms = placement.terms
        duration = motion.duration
        for actor in placement.actors.values():
            if actor.kind == "stationary_object" or actor.name in motion.unknown_speed:
                continue
            top = motion.top_speed.get(actor.name, Fraction(0))
            for speed, said in ((ir.const(top), f"{float(top) * 3.6:g} kph"),
                                (ir.Ref(actor.speed), "its start speed")):  # fmt: skip
                reach = ir.op("+", ir.Ref(actor.s), ir.op("*", ir.const(duration), speed))
                self._implicit(
                    terms.room(actor.road, reach, _half(actor.body.length)),
                    actor.span,
                    "road-room",
                    f"`{actor.name}` drives up to {said} for the scenario's "
                    f"{float(duration):g} s and stays on {terms.room_text()}",
                )

    def _lookup(self, sym: Symbol, node: ast.Node) -> Value:
        """A parameter's value where a hard `==` gives it one, or its declared default when
        no hard constraint replaces that (for constant durations and speeds)."""
        found = self.constants.get(sym.name)
        if found is None:
            if any(
                c.strength == "hard" and c.subject is not None and c.subject.name == sym.name
                for c in self.problem.constraints
            ):
                raise NotConstant(f"`{sym.name}` is not a constant", node)
            return initial_value(self.model, sym)
        if isinstance(found[0], bool):
            raise NotConstant(f"`{sym.name}` is not a number", node)
        t = sym.type
        if t is not None and t.kind is T.Kind.PHYSICAL:
            return Quantity(found[0], t.dimension or T.DIMENSIONLESS)
        return found[0]

    def _preferences(self, placement: StartPlacement) -> None:
        """Plausible values where the constraints leave a choice (the witness draws there
        when it can): starts near the road's entry, leaving room to drive; speeds within
        the road's limit and the vehicle's top speed."""
        speed_limit = placement.map.facts.speed_limit
        preferred = self.problem.preferred
        limit = Fraction(speed_limit).limit_denominator(1000) if speed_limit else None
        for actor in placement.actors.values():
            half = largest(actor.body.length) / 2
            room = fraction(placement.terms.longest) - 2 * half
            preferred[actor.s.name] = (half, half + room * PREFERRED_START_SHARE)
            top = largest(actor.body.max_speed)
            plausible = min(top, limit) if limit is not None else top
            for var in self.problem.variables.values():
                if var.unit == "kph" and var.name.startswith(f"{actor.name}@"):
                    preferred[var.name] = (Fraction(0), plausible)
        for var in self.problem.variables.values():
            if var.unit == "kph" and var.name not in preferred and limit is not None:
                preferred[var.name] = (Fraction(0), limit)

    # ---- road and actors -----------------------------------------------------------

    def _map(self) -> MapChoice:
        """The map the scenario names (``map_file`` or ``set_map_file``), read; the default
        map when it names none, or one that cannot be used (the finding says why)."""
        name, span = self._map_name()
        folder = scenario_folder(span.uri if span is not None else self.problem.span.uri)
        try:  # the configured default map (`[tool.osc2check.road] map`), a name or a file
            fallback = find_map(self.default_map, folder)
        except (MapError, UnknownMapError):
            fallback = find_map("default")
        if name is None:
            path = map_path(self.default_map, folder)
            source = str(path.resolve()) if path is not None and path.is_file() else None
            return MapChoice(self.default_map if source else fallback.name, fallback, source)
        file = self.maps.get(name, name)  # a name the configuration gives a file
        try:
            found = find_map(file, folder)
        except UnknownMapError as err:
            return MapChoice(fallback.name, fallback, asked=name, span=span, unknown=err.known)
        except MapError as err:
            return MapChoice(fallback.name, fallback, asked=name, span=span, unreadable=err)
        path = map_path(file, folder)
        source = str(path.resolve()) if path is not None and path.is_file() else None
        return MapChoice(name if source is not None else found.name, found, source, name, span)

    def _map_name(self) -> tuple[str | None, Span | None]:
        """The map name the scenario gives and the span of the string that gives it."""
        for member in self._scenario_members():
            if isinstance(member, ast.Invocation) and member.name.text == "set_map_file":
                for arg in member.arguments:
                    if isinstance(arg, ast.EventArgument):
                        continue
                    literal = self._string_of(arg.value)
                    if literal is not None:
                        return literal.value, literal.span
        for var_name in self.problem.variables:
            if var_name.endswith(".map_file"):
                found = self.constants.get(var_name)
                if found is not None and isinstance(found[0], Fraction):
                    name = self.problem.strings.get(int(found[0]))
                    if name is None:
                        continue
                    within = found[1].span
                    spans = [
                        sp
                        for sp in self.lw.string_spans.get(name, ())
                        if sp.uri == within.uri and within.start <= sp.start <= within.end
                    ]
                    return name, spans[0] if spans else within
        return None, None

    def _string_of(self, node: ast.Node) -> ast.StringLiteral | None:
        """A string literal, or the one a global or field named here has as its default
        (``global my_map: string = "Town04"``)."""
        if isinstance(node, ast.StringLiteral):
            return node
        if isinstance(node, ast.NameRef):
            sym = self.model.reference(node.name.name)
            decl = sym.decl if sym is not None else None
            if isinstance(decl, ast.FieldDecl) and isinstance(decl.default, ast.StringLiteral):
                return decl.default
        return None

    def _scenario_members(self) -> Iterator[ast.Member]:
        for members in self.lw.member_decls.get(self.scenario, []):
            yield from members

    def _map_modifier_members(self) -> list[tuple[ast.Invocation, Symbol]]:
        """The scenario's map modifiers (``m.number_of_lanes(...)``, ...) and their symbols."""
        found = []
        for member in self._scenario_members():
            if not isinstance(member, ast.Invocation):
                continue
            modifier = self.model.references.get(member.name)
            if modifier is None or modifier.kind is not SymbolKind.MODIFIER:
                continue
            if any(a.name == "map" and a.library for a in self.model.ancestors(modifier.actor)):
                found.append((member, modifier))
        for scenario in self._invoked_scenarios():  # CARLA's path conditions hold for the run
            for members in self.lw.member_decls.get(scenario, []):
                for member in members:
                    modifier = (
                        self.model.references.get(member.name)
                        if isinstance(member, ast.Invocation)
                        else None
                    )
                    if modifier is not None and modifier.namespace == CARLA:
                        found.append((member, modifier))  # type: ignore[arg-type]
        return found

    def _invoked_scenarios(self) -> list[Symbol]:
        """The scenarios the scenario invokes, and those they invoke, once each."""
        found: list[Symbol] = []
        stack = [self.scenario]
        while stack:
            do = scenario_do(self.model, self.lw.member_decls, stack.pop())
            for node in walk(do.member) if do is not None else ():
                sym = (
                    self.model.references.get(node.name)
                    if isinstance(node, ast.Invocation)
                    else None
                )
                if sym is not None and sym.kind is SymbolKind.SCENARIO and sym not in found:
                    found.append(sym)
                    stack.append(sym)
        return found

    def _map_modifiers(self, placement: StartPlacement) -> None:
        """Constrain the scenario's element fields as its map modifiers say; CARLA's path
        conditions constrain where its actors start."""
        scope = self._root_scope()
        for member, modifier in self._map_modifier_members():
            if modifier.namespace == CARLA and modifier.name == "path_min_driving_lanes":
                self._min_driving_lanes(member, placement)
                continue
            if modifier.namespace == CARLA and modifier.name == "path_over_junction":
                self._over_junction(member, placement)
                continue
            self.fields.modifier(member, modifier, scope, self._require)

    def _over_junction(self, member: ast.Invocation, placement: StartPlacement) -> None:
        """CARLA's ``path_over_junction``: every vehicle starts before a junction its road
        leads into, ``distance_before`` ahead of it at most (a range: within the range).
        The direction through the junction and the distances in and after it are not
        modelled (recorded as such)."""
        args = self._args(member)
        node = args.get("distance_before")
        if node is None:
            return
        if isinstance(node, ast.RangeLiteral):
            low, high = self._value(node.low), self._value(node.high)
        else:
            low, high = ir.const(0), self._value(node)
        if low is None or high is None:
            return
        for actor in placement.actors.values():
            if actor.kind != "vehicle":
                continue
            term = placement.terms.before_junction(actor.road, ir.Ref(actor.s), low, high)
            if term is None:  # reported where the run starts (an invoker places the actors)
                placement.no_junction.append(call_span(member))
                return
            self._require(term, member)
        for name in ("direction", "distance_in", "distance_after"):
            if name in args:
                self.problem.skip(
                    args[name].span,
                    self.lw.text_of(args[name].span),
                    f"path_over_junction({name}: ...) is not modelled: the route through the "
                    "junction is the seed's",
                )

    def _min_driving_lanes(self, member: ast.Invocation, placement: StartPlacement) -> None:
        """CARLA's ``path_min_driving_lanes(n)``: every vehicle starts where its road has at
        least ``n`` driving lanes in its direction (CARLA chooses its spawn road so)."""
        node = self._args(member).get("min_lanes")
        lanes = self._value(node) if node is not None else None
        if lanes is None:
            return
        for actor in placement.actors.values():
            if actor.kind == "vehicle":
                self._require(placement.terms.wide(actor.road, ir.Ref(actor.s), lanes), member)

    def _body(self, param: Symbol, kind: str) -> ActorBody:
        """The actor's catalogue row and size terms (see ``ActorBody``)."""
        name = param.name
        row: ActorRow | None
        if kind != "vehicle":
            row = kind_row(kind)
            return self._sized(name, ActorBody(kind, row, *self._row_terms(row)))
        category = self.problem.variables.get(f"{name}.vehicle_category")
        because: list[ir.Constraint] = []
        notes: list[str] = []
        row = None
        model = self.constants.get(f"{name}.model")
        if model is not None and isinstance(model[0], Fraction):
            model_name = self.problem.strings.get(int(model[0]), "")
            found = model_row(model_name)
            if found is not None and found.kind == "vehicle":
                row = found
                because.append(model[1])
                if category is not None:
                    self._implicit(
                        ir.op("==", ir.Ref(category), ir.const(_member(category, row.category))),
                        model[1].span,
                        "category",
                        f"`{model_name}` is a {row.category}",
                        because=(model[1],),
                    )
            else:
                notes.append(
                    f"model `{model_name}` of `{name}` is not in the catalogue: its "
                    "vehicle_category decides its size"
                )
        shown = None
        fixed = self.constants.get(f"{name}.vehicle_category")
        if row is None and fixed is not None and category is not None:
            member = next((n for n, v in category.enum if v == fixed[0]), None)
            shown = CATEGORIES.get(member) if member is not None else None
        type_symbol = param.type.symbol if param.type is not None else None
        if row is None and _is_trailer(self.model, type_symbol):
            row = CATEGORIES["trailer"]
        unsaid = row is None and category is not None and not self._mentioned(category)
        if unsaid and not self.open_categories:
            row = CATEGORIES["car"]  # nothing says otherwise: placed, and run, as a car
        if row is not None:
            if category is not None and not because:
                text = (
                    f"`{name}` is a {row.category} (its vehicle_category is not constrained)"
                    if row.category == "car"
                    else f"`{name}` is a {row.category}"
                )
                self._implicit(
                    ir.op("==", ir.Ref(category), ir.const(_member(category, row.category))),
                    param.name_span or self.problem.span,
                    UNSAID_CATEGORY if unsaid else "category",
                    text,
                )
            body = ActorBody(kind, row, *self._row_terms(row), category, tuple(because))
        elif category is not None:  # open: the solver chooses the category and the size
            length = _by_category(category, lambda r: r.length)
            width = _by_category(category, lambda r: r.width)
            top = _by_category(category, lambda r: r.max_speed)
            body = ActorBody(kind, None, length, width, top, category, shown=shown)
            if unsaid:  # the second try (open_categories): any category, a car preferred
                car_value = Fraction(_member(category, "car"))
                self.problem.preferred[category.name] = (car_value, car_value)
            else:
                # without the constraints that mention it, the vehicle would be a car: the
                # solver holds this while it looks for the lines a conflict cannot do without
                self.problem.add(
                    ir.Constraint(
                        ir.op("==", ir.Ref(category), ir.const(_member(category, "car"))),
                        param.name_span or self.problem.span,
                        "placement",
                        f"`{name}` is a car when nothing says otherwise",
                        "hard",
                        category,
                        f"`{name}` is a car when nothing says otherwise",
                        "fallback",
                    )
                )
        else:  # pragma: no cover - every vehicle has the category parameter
            car = CATEGORIES["car"]
            body = ActorBody(kind, car, *self._row_terms(car))
        for member, value in category.enum if category is not None else ():
            if member in NOT_ON_ROADS:  # DSL 2.2's trains, boats and aircraft
                assert category is not None  # as the loop runs
                self._implicit(
                    ir.op("!=", ir.Ref(category), ir.const(value)),
                    param.name_span or self.problem.span,
                    "category",
                    f"`{name}` is no {member}: the world is roads, and its catalogue has "
                    f"no {member}",
                )
        body.notes = tuple(notes)
        return self._sized(name, body)

    @staticmethod
    def _row_terms(row: ActorRow) -> tuple[ir.Term, ir.Term, ir.Term]:
        return ir.const(row.length), ir.const(row.width), ir.const(row.max_speed)

    def _sized(self, name: str, body: ActorBody) -> ActorBody:
        """Declared ``bounding_box`` dimensions replace the row's."""
        for field_name in ("length", "width"):
            var = self.problem.variables.get(f"{name}.bounding_box.{field_name}")
            if var is None or not self._mentioned(var):
                continue
            setattr(body, field_name, ir.Ref(var))
            self._implicit(
                ir.op(">", ir.Ref(var), ir.const(0)),
                var.span or self.problem.span,
                "size",
                f"`{name}`'s bounding box has a positive {field_name}",
            )
        return body

    def _mentioned(self, var: ir.Var) -> bool:
        """Whether a constraint of the scenario (not a domain or placement rule) mentions it."""
        return var.name in self.written

    def _road_var(self, name: str, span: Span) -> ir.Var | None:
        """The variable of an actor's start carriageway (None on a one-carriageway map)."""
        terms = self.terms
        if terms.single:
            return None
        labels = tuple((cw.label, cw.index) for cw in terms.carriageways)
        var = self.problem.var(name, "int", enum=labels, span=span)
        count = len(terms.carriageways)
        text = f"one of the {count} carriageways of map `{terms.name}`"
        self.problem.add(
            ir.Constraint(
                between(ir.Ref(var), 0, count - 1), span, "domain", text, explanation=text
            )
        )
        return var

    def _actor(self, param: Symbol, kind: str) -> PlacedActor:
        body = self._body(param, kind)
        span = param.name_span or self.problem.span
        p = self.problem
        terms = self.terms
        actor = PlacedActor(
            param.name,
            kind,
            body,
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
            self._road_var(f"{param.name}@start.road", span),
        )
        half = _half(body.length)
        self._lane_range(actor)
        self._implicit(
            terms.extent(actor.road, ir.Ref(actor.s), half),
            span,
            "road-extent",
            terms.extent_text(param.name, body.size_text(body.length, "long")),
            because=body.because,
        )
        self._speed_range(actor)
        return actor

    def _on_road(self, actor: PlacedActor) -> None:
        """The actor's sides stay on the road (with its lateral offset): a vehicle's on
        the driving lanes, a person's or an animal's on any lane, sidewalks included."""
        body = actor.body
        terms = self.terms
        walker = actor.kind in ("person", "animal")
        self._implicit(
            terms.across(
                actor.road,
                ir.Ref(actor.lane),
                ir.Ref(actor.t),
                ir.Ref(actor.s),
                _half(body.width),
                walker,
            ),
            actor.span,
            "road-extent",
            terms.across_text(actor.name, body.size_text(body.width, "wide"), walker),
            because=body.because,
        )

    def _lane_range(self, actor: PlacedActor, phase: bool = False) -> None:
        terms = self.terms
        self._implicit(
            terms.lanes(actor.road, ir.Ref(actor.lane), ir.Ref(actor.s), phase),
            actor.span,
            "lane-range",
            terms.lanes_text(phase),
        )

    def _speed_range(self, actor: PlacedActor) -> None:
        body = actor.body
        v = ir.Ref(actor.speed)
        if body.row is not None:
            top = float(body.row.max_speed) * 3.6
            what = body.row.key if body.row.is_model else f"a {body.row.category}"
            text = f"{what} goes at most {top:g} kph"
        else:
            text = f"`{actor.name}` goes at most the top speed of its vehicle_category"
            if body.shown is not None:
                top = float(body.shown.max_speed) * 3.6
                text += f" (a {body.shown.category}: {top:g} kph)"
        self._implicit(
            ir.op("and", ir.op(">=", v, ir.const(0)), ir.op("<=", v, body.max_speed)),
            actor.span,
            "max-speed",
            text,
            because=body.because,
        )

    def _implicit(
        self,
        term: ir.Term,
        span: Span,
        rule: str,
        text: str,
        because: tuple[ir.Constraint, ...] = (),
    ) -> None:
        self.problem.add(
            ir.Constraint(
                term, span, "placement", text, "hard", rule=rule, explanation=text, because=because
            )
        )

    # ---- the invocations that begin at time 0 ------------------------------------------

    def _root_scope(self) -> InstanceScope:
        return InstanceScope("", self.scenario, "", self.scenario)

    def _bodies(self, scenario: Symbol) -> list[ast.DoMember]:
        """The ``do`` the scenario runs (an inherited one too; a later one replaces an
        earlier), as the timing model and the runner take it."""
        do = scenario_do(self.model, self.lw.member_decls, scenario)
        return [] if do is None else [do.member]

    def _start_invocations(self) -> list[tuple[ast.Invocation, InstanceScope]]:
        """The invocations that begin at time 0, each with the instance it belongs to:
        the scenario's own, and those of the scenarios it invokes at time 0."""
        found: list[tuple[ast.Invocation, InstanceScope]] = []
        for member in self._bodies(self.scenario):
            self._zero(member, self._root_scope(), found, 0, None)
        return found

    def _zero(
        self,
        member: ast.DoMember,
        scope: InstanceScope,
        found: list[tuple[ast.Invocation, InstanceScope]],
        depth: int,
        guard: ir.Term | None,
    ) -> None:
        """Collect the time-0 invocations of ``member`` (run under the choice ``guard``,
        when it is inside a ``one_of``): into ``found``, or, inside a ``one_of``, into
        ``alternatives`` with the choice of their member."""
        zero = time_zero(member.body)
        labels = _labels(member)
        options = [(inv, guard) for inv in zero.starts]
        for choices, inv in zero.options:
            chosen = self._choice(choices, scope)
            options.append((inv, chosen if guard is None else ir.op("and", guard, chosen)))
        for inv, when in options:
            inner = self._invoked(inv, scope, labels, depth)
            if inner is not None:
                for body in self._bodies(inner[0]):
                    self._zero(body, inner[1], found, depth + 1, when)
            elif when is None:
                found.append((inv, scope))
            else:
                self.alternatives.append((inv, scope, when))

    def _invoked(
        self,
        inv: ast.Invocation,
        scope: InstanceScope,
        labels: dict[int, ast.Name],
        depth: int,
    ) -> tuple[Symbol, InstanceScope] | None:
        """The scenario an invocation invokes and its instance, or None (an action)."""
        target = self.model.references.get(inv.name)
        if target is None or target.kind is not SymbolKind.SCENARIO or target.library:
            return None
        if depth >= MAX_DEPTH:
            return None
        return self.lw.instance_scope(inv, scope, labels.get(id(inv)))

    def _all_invocations(
        self, member: ast.DoMember, scope: InstanceScope, depth: int = 0
    ) -> Iterator[tuple[ast.Invocation, InstanceScope]]:
        """Every invocation of a `do` tree, into the scenarios it invokes."""
        labels = _labels(member)
        for inv in invocations(member.body):
            inner = self._invoked(inv, scope, labels, depth)
            if inner is None:
                yield inv, scope
            else:
                for body in self._bodies(inner[0]):
                    yield from self._all_invocations(body, inner[1], depth + 1)

    def _actor_at(self, inv: ast.Invocation, placement: StartPlacement) -> PlacedActor | None:
        """The placed actor an invocation is of, in the current instance."""
        if inv.actor is None:
            path = self.scope.actor
        else:
            path = self.lw.path(inv.actor, self.scope)
        return placement.actors.get(path) if path is not None else None

    def _modifiers(self, inv: ast.Invocation, placement: StartPlacement, first: set[str]) -> None:
        """Apply the start modifiers of a time-0 invocation: those with `at: start`, and,
        in the actor's first invocation, those without `at` (`at: all` holds at the start
        too) unless a modifier of the same name gives the actor's start explicitly."""
        actor = self._actor_at(inv, placement)
        if actor is None:
            return
        is_first = actor.name not in first
        first.add(actor.name)
        if inv.name.text == "assign_speed":  # an instant action: its speed is the start speed
            given = self._args(inv, realised=True)
            if "speed" in given:
                self._mod_speed(actor, {"speed": given["speed"]}, inv, placement)
        if inv.name.text in _STANDING:  # it stands: its speed is 0, whatever else says
            self._require(ir.op("==", ir.Ref(actor.speed), ir.const(0)), inv)
        handlers = {
            "lane": self._mod_lane,
            "position": self._mod_position,
            "speed": self._mod_speed,
            "lateral": self._mod_lateral,
            "along": self._mod_along,
            "yaw": self._mod_heading,
            "orientation": self._mod_heading,
        }
        for item in inv.with_members:
            if not isinstance(item, ast.Invocation):
                continue
            args = self._args(item, realised=True)
            if item.name.text == "change_lane":  # a change from the start lane
                self._lane_change(actor, args, item, placement)
            at = modifier_timing(args)
            if not (
                at == "start"
                or (is_first and at == "all" and (actor.name, item.name.text) not in self.explicit)
            ):
                continue
            handler = handlers.get(item.name.text)
            if handler is not None:
                actor.placed = actor.placed or item.name.text in _POSITIONING
                self.applied.add(id(item))
                handler(actor, args, item, placement)

    def _lane_change(
        self,
        actor: PlacedActor,
        args: dict[str, ast.Node],
        item: ast.Invocation,
        placement: StartPlacement,
    ) -> None:
        """``change_lane(n, side)`` in a phase that starts the scenario: the road has a
        lane ``n`` lanes to ``side`` of the start lane (to either side without one, as
        the runner then draws one of those that exist); ``n`` from a range is the
        solver's, which the runner changes by."""
        node = args.get("lane")
        count = self._value(node) if node is not None else ir.const(1)
        if count is None:
            return
        count = coerce(actor.lane, count)
        side = enum_word(args.get("side"))
        beside = []
        for sign, name in ((1, "left"), (-1, "right")):
            if side not in (None, name):
                continue
            step = count if sign > 0 else ir.op("neg", count)
            target = ir.op("+", ir.Ref(actor.lane), step)
            beside.append(placement.terms.lanes(actor.road, target, ir.Ref(actor.s)))
        if beside:
            self._require(beside[0] if len(beside) == 1 else ir.op("or", *beside), item)

    def _phase_limits(self, placement: StartPlacement) -> None:
        """A `lane(k)` or `speed(v)` of any phase needs a lane the road has and a speed
        the vehicle reaches, whenever the phase runs; so does a lane change, from the lane
        the actor is in then (``lane_steps``)."""
        scenarios = [s.decl for s in self.model.symbols if s.kind is SymbolKind.SCENARIO]
        rules = placement.map.facts.rules
        steps = LaneSteps(
            self.model, self._value, one_of_members(d for d in scenarios if d), rules != {"LHT"}
        )
        for member in self._bodies(self.scenario):
            for inv, scope in self._all_invocations(member, self._root_scope()):
                self.scope = scope
                actor = self._actor_at(inv, placement)
                if actor is None:
                    continue
                actor.acts = True
                for item in inv.with_members:
                    if not isinstance(item, ast.Invocation) or id(item) in self.applied:
                        continue
                    if item.name.text in ("lane", "speed"):
                        self._phase_limit(actor, item, placement, inv.name.text in _STANDING)
                    elif item.name.text == "along":
                        self._mod_along(actor, self._args(item), item, placement, at_start=False)
                for change in steps.run(actor.name, actor.lane, inv, self._phase_lane(actor)):
                    lanes = placement.terms.lanes(None, change.lane, ir.Ref(actor.s), phase=True)
                    self._implicit(lanes, change.inv.span, "lane-range", change.text)
        self.scope = self._root_scope()

    def _phase_lane(self, actor: PlacedActor) -> Callable[[ast.Invocation], ir.Var | None]:
        """The variable of the lane a later phase's `lane(k)` gives ``actor`` (None for one
        applied at the start)."""

        def lane(item: ast.Invocation) -> ir.Var | None:
            if id(item) in self.applied:
                return None
            return self.problem.variables.get(self._phase_name(actor, item, "lane"))

        return lane

    def _phase_limit(
        self,
        actor: PlacedActor,
        item: ast.Invocation,
        placement: StartPlacement,
        standing: bool = False,
    ) -> None:
        """The lane or speed a modifier gives in its phase is one the road has and the
        vehicle reaches (``standing``: the phase's action stands, so the speed is 0)."""
        args = self._args(item)
        name = item.name.text
        if name == "lane" and "lane" in args and not any(k in args for k in LANE_REFERENCES):
            lane = self.problem.var(self._phase_name(actor, item, "lane"), "int", span=actor.span)
            saved, actor.lane = actor.lane, lane
            try:
                self._lane_range(actor, phase=True)
                self._mod_lane(actor, args, item, placement, phase=True)
            finally:
                actor.lane = saved
        elif (
            name == "speed"
            and "speed" in args
            and not any(k in args for k in ("faster_than", "slower_than", "same_as"))
        ):
            speed = self.problem.var(
                self._phase_name(actor, item, "speed"),
                "real",
                unit="kph",
                unit_factor=Fraction(5, 18),
                span=actor.span,
            )
            saved, actor.speed = actor.speed, speed
            try:
                self._speed_range(actor)
                self._mod_speed(actor, args, item, placement)
                if standing:
                    self._require(ir.op("==", ir.Ref(speed), ir.const(0)), item)
            finally:
                actor.speed = saved

    def _phase_name(self, actor: PlacedActor, item: ast.Invocation, what: str) -> str:
        """The variable of ``actor``'s lane or speed in the phase of modifier ``item``,
        one for each instance of an invoked scenario."""
        return join_path(self.scope.prefix, f"{actor.name}@{item.span.line}.{what}")

    def _args(self, inv: ast.Invocation, realised: bool = False) -> dict[str, ast.Node]:
        """The arguments given to modifier ``inv``, by parameter (as the checker bound them);
        ``realised``: the start placement realises them, and notes what it reads
        (``bindings.recording_reads``)."""
        binding = self.model.binding(inv)
        given: dict[str, ast.Node] = (
            dict(binding.values(defaults=False)) if binding is not None else {}
        )
        return ReadArguments(inv, given) if realised else given

    def _value(self, node: ast.Node) -> ir.Term | None:
        chosen = self._chosen(node)
        if chosen is not None:
            return chosen
        try:
            return self.lw.term(node, self.scope)
        except NotEncodable as reason:
            self.problem.skip(node.span, self.lw.text_of(node.span), str(reason))
            return None

    def _chosen(self, node: ast.Node | None) -> ir.Term | None:
        """A range given where a scalar is expected: the value chosen from it (the
        argument's own variable, whose value the runner runs with); None otherwise."""
        if not isinstance(node, ast.RangeLiteral):
            return None
        var = self.lw.chosen(node, self.scope)
        return ir.Ref(var) if var is not None else None

    def _reference(
        self, node: ast.Node | None, actor: PlacedActor, placement: StartPlacement, span: Span
    ) -> PlacedActor | None:
        if not isinstance(node, (ast.NameRef, ast.MemberAccess)):
            return None
        path = self.lw.path(node, self.scope)
        other = placement.actors.get(path) if path is not None else None
        if other is None:
            written = node.name.name.text if isinstance(node, ast.NameRef) else str(path)
            placement.unplaced_references.append((node.span, actor.name, written))
            return None
        placement.edges.append((actor.name, other.name, span))
        return other

    def _require(self, term: ir.Term, item: ast.Invocation) -> None:
        span = call_span(item)
        if self.guard is not None:  # a `one_of` member's: it holds when that one runs
            term = ir.op("or", ir.op("not", self.guard), term)
        self.problem.add(ir.Constraint(term, span, "modifier", self.lw.text_of(span)))

    def _mod_lane(
        self,
        actor: PlacedActor,
        args: dict[str, ast.Node],
        item: ast.Invocation,
        placement: StartPlacement,
        phase: bool = False,
    ) -> None:
        lane = ir.Ref(actor.lane)
        terms = placement.terms
        value = (
            self._value(args["lane"])
            if "lane" in args
            and (not isinstance(args["lane"], ast.RangeLiteral) or self._chosen(args["lane"]))
            else None
        )
        count = coerce(actor.lane, value) if value is not None else None
        for key in LANE_REFERENCES:
            if key not in args:
                continue
            other = self._reference(args[key], actor, placement, item.span)
            if other is None:
                return
            sign = lane_side(key, enum_word(args.get("side")))
            step = count if count is not None else ir.const(1)
            target: ir.Term = ir.Ref(other.lane)
            if sign:
                target = ir.op("+", target, step if sign > 0 else ir.op("neg", step))
            relation = ir.op("==", lane, target)
            self._require(_with(relation, terms.same(actor.road, other.road)), item)
            return
        if "lane" not in args:
            return
        from_left = placement.map.facts.numbering == "from_left"
        side = enum_word(args.get("from"))
        if side in ("left", "right"):
            from_left = side == "left"
        node = args["lane"]
        road = None if phase else actor.road
        s = ir.Ref(actor.s)
        if phase and from_left and not terms.single:
            return  # where a later phase is, and so how many lanes it has, is not known here
        # a range whose chosen value is known is that one lane (``count``, below)
        if isinstance(node, ast.RangeLiteral) and self._chosen(node) is None:
            low, high = self._value(node.low), self._value(node.high)
            if low is None or high is None:
                return
            low, high = coerce(actor.lane, low), coerce(actor.lane, high)
            if not from_left:
                self._require(in_range(lane, low, high), item)
            elif terms.single or phase:
                top = ir.const(terms.most_lanes + 1)
                self._require(in_range(lane, ir.op("-", top, low), ir.op("-", top, high)), item)
            else:  # the lane counted from the left depends on how many there are there
                number = self.problem.var(
                    self._phase_name(actor, item, "lane_number"), "int", span=actor.span
                )
                self._require(
                    ir.op(
                        "and",
                        in_range(ir.Ref(number), low, high),
                        terms.numbered(road, lane, s, ir.Ref(number), from_left),
                    ),
                    item,
                )
        elif count is not None:
            self._require(terms.numbered(road, lane, s, count, from_left), item)

    def _mod_position(
        self,
        actor: PlacedActor,
        args: dict[str, ast.Node],
        item: ast.Invocation,
        placement: StartPlacement,
    ) -> None:
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
        half = _half(_plus(actor.body.length, other.body.length))
        distance = ir.op("+", half, gap)
        target = (
            ir.op("-", ir.Ref(other.s), distance)
            if reference_key == "behind"
            else ir.op("+", ir.Ref(other.s), distance)
        )
        self._require(
            _with(ir.op("==", s, target), placement.terms.same(actor.road, other.road)), item
        )
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

    def _mod_speed(
        self,
        actor: PlacedActor,
        args: dict[str, ast.Node],
        item: ast.Invocation,
        placement: StartPlacement,
    ) -> None:
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
        if isinstance(node, ast.RangeLiteral) and self._chosen(node) is None:
            low, high = self._value(node.low), self._value(node.high)
            if low is not None and high is not None:
                self._require(in_range(v, low, high), item)
            return
        value = self._value(node)
        if value is not None:
            self._require(ir.op("==", v, value), item)

    def _mod_heading(
        self,
        actor: PlacedActor,
        args: dict[str, ast.Node],
        item: ast.Invocation,
        placement: StartPlacement,
    ) -> None:
        """``yaw(angle)``, ``orientation(yaw: a)``: the start heading, from the lane's
        (``relative_to_road``, the default; other frames are the capability table's)."""
        node = args.get("angle" if item.name.text == "yaw" else "yaw")
        frame = "measure_by" if item.name.text == "yaw" else "measured_by"
        if node is None or "relative_to" in args:
            return
        if enum_word(args.get(frame)) not in (None, "relative_to_road"):
            return
        value = self._value(node)
        if value is None:
            return
        if actor.heading is None:
            actor.heading = self.problem.var(
                f"{actor.name}@start.heading", "real", unit="rad", span=actor.span
            )
        self._require(ir.op("==", ir.Ref(actor.heading), value), item)

    def _mod_lateral(
        self,
        actor: PlacedActor,
        args: dict[str, ast.Node],
        item: ast.Invocation,
        placement: StartPlacement,
    ) -> None:
        node = args.get("distance")
        value = self._value(node) if node is not None else None
        self.lateral.add(actor.name)
        for key, sign in (("left_of", 1), ("right_of", -1), ("same_as", 0), ("side_of", 0)):
            if key not in args:
                continue
            other = self._reference(args[key], actor, placement, item.span)
            if other is None:
                return
            if key == "side_of":
                sign = -1 if enum_word(args.get("side")) == "right" else 1
            offset = value if value is not None and sign else ir.const(0)
            if sign < 0:
                offset = ir.op("neg", offset)
            relation = placement.terms.beside(
                actor.road,
                ir.Ref(actor.s),
                ir.Ref(actor.lane),
                ir.Ref(actor.t),
                ir.Ref(other.lane),
                ir.Ref(other.t),
                offset,
            )
            self._require(_with(relation, placement.terms.same(actor.road, other.road)), item)
            return
        if value is not None:
            if enum_word(args.get("side")) == "right":
                value = ir.op("neg", value)  # an offset to the right of the lane centre
            self._require(ir.op("==", ir.Ref(actor.t), value), item)

    def _mod_along(
        self,
        actor: PlacedActor,
        args: dict[str, ast.Node],
        item: ast.Invocation,
        placement: StartPlacement,
        at_start: bool = True,
    ) -> None:
        """`along(route: r)`: the actor starts on ``r`` at time 0, else reaches it later."""
        fields = self.fields  # made with the placement
        target = fields.field_of(args.get("route"), self.scope)
        if target is None:
            return  # a world path (``behaviours.paths``): it moves the actor, places nothing
        offset = None
        if at_start and "start_offset" in args:
            offset = self._value(args["start_offset"])
        actor.along.append(target)
        self._require(fields.tie(actor.road, actor.s, actor.lane, target, at_start, offset), item)
        if at_start:
            actor.placed = True

    # ---- no overlap --------------------------------------------------------------------

    def _no_overlap(self, placement: StartPlacement) -> None:
        fixed = self._fixed_lanes(placement)
        names = list(placement.actors)
        for i, a_name in enumerate(names):
            for b_name in names[i + 1 :]:
                if a_name in fixed and b_name in fixed and fixed[a_name] != fixed[b_name]:
                    continue  # never in the same lane
                a, b = placement.actors[a_name], placement.actors[b_name]
                need = _half(_plus(a.body.length, b.body.length))
                sa, sb = ir.Ref(a.s), ir.Ref(b.s)
                apart = placement.terms.apart(a.road, b.road)
                term = ir.op(
                    "or",
                    *((apart,) if apart is not None else ()),
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

    def _fixed_lanes(self, placement: StartPlacement) -> dict[str, Fraction]:
        """The start lanes that the lane modifiers fix: `lane(2)`, and `lane(same_as: b)` or
        `lane(side_of: b, ...)` once `b`'s is fixed. Pairs of actors in lanes fixed apart
        need no constraint against overlapping."""
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


def _labels(member: ast.DoMember) -> dict[int, ast.Name]:
    """The labels of the invocations of a `do` tree (``lbl: hero.cut_in()``), by node id:
    an invoked scenario's instance is named by its label."""
    found: dict[int, ast.Name] = {}
    stack = [member]
    while stack:
        m = stack.pop()
        if m.label is not None and isinstance(m.body, ast.Invocation):
            found[id(m.body)] = m.label
        if isinstance(m.body, ast.Composition):
            stack.extend(m.body.members)
    return found


def _unless(guards: list[ir.Term] | None, term: ir.Term) -> ir.Term:
    """``term`` where none of the choices ``guards`` holds (it always does without any)."""
    if not guards:
        return term
    return ir.op("or", *guards, term)


def _with(relation: ir.Term, also: ir.Term | None) -> ir.Term:
    return relation if also is None else ir.op("and", relation, also)


def lower_placement(
    lowerer: Lowerer,
    scenario: Symbol,
    default_map: str = "default",
    maps: Mapping[str, str] | None = None,
    open_categories: bool = False,
) -> StartPlacement | None:
    """Add the placement variables and constraints of ``scenario`` to the lowerer's problem
    (``open_categories``: see ``PlacementLowerer``)."""
    return PlacementLowerer(lowerer, scenario, default_map, maps, open_categories).lower()


def _member(category: ir.Var, name: str) -> int:
    """The value of enum member ``name`` of the category variable."""
    return next(v for n, v in category.enum if n == name)


def _by_category(category: ir.Var, value_of: Callable[[ActorRow], Fraction]) -> ir.Term:
    """``ite(category == car, value_of(car), ite(...))`` over the category's members."""
    members = [(n, v) for n, v in category.enum if n in CATEGORIES]
    term: ir.Term = ir.const(value_of(CATEGORIES[members[-1][0]]))
    for name, value in reversed(members[:-1]):
        term = ir.op(
            "ite",
            ir.op("==", ir.Ref(category), ir.const(value)),
            ir.const(value_of(CATEGORIES[name])),
            term,
        )
    return term


def _number(term: ir.Term) -> Fraction | None:
    if isinstance(term, ir.Const) and not isinstance(term.value, bool):
        return term.value
    return None


def _half(term: ir.Term) -> ir.Term:
    value = _number(term)
    return ir.const(value / 2) if value is not None else ir.op("*", ir.const(Fraction(1, 2)), term)


def _plus(a: ir.Term, b: ir.Term) -> ir.Term:
    x, y = _number(a), _number(b)
    return ir.const(x + y) if x is not None and y is not None else ir.op("+", a, b)
