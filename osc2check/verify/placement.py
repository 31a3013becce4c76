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
  refers to it (``faster_than``, ``slower_than``, ``same_as``), or its first action
  is one a car cannot do from rest (a ``change_lane``: it starts driving).
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
* Open starts read so that the actions can be done (``ir.Constraint.tentative``: each
  reading holds unless it takes part in a conflict, and then gives way): a car changing lanes
  first drives; an actor reaching a gap behind (ahead of) a reference starts further
  back (within it); when nothing acts at time 0 and the scenario first waits a constant
  time, what begins then places the actors too, each keeping its start lane and speed
  while it waits (``_after_waits``).
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

from collections.abc import Iterator, Mapping
from fractions import Fraction

from osc2check.inputs import is_file
from osc2check.semantics import types as T
from osc2check.semantics.constants import NotConstant, Quantity, Value, initial_value
from osc2check.semantics.members import actor_alias, scenario_do
from osc2check.semantics.model import Model
from osc2check.semantics.phases import (
    TimeZero,
    after_waits,
    is_instant,
    leading_parallel,
    modifier_timing,
)
from osc2check.semantics.stdlib import CARLA
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.syntax.walk import walk
from osc2check.verify import ir
from osc2check.verify.actor_bodies import half_of, plus
from osc2check.verify.map_modifiers import MapFields
from osc2check.verify.parameters import Lowerer
from osc2check.verify.problem import ConstraintProblem
from osc2check.verify.propagate import linear
from osc2check.verify.road_terms import RoadTerms, fraction
from osc2check.verify.room import motion_bounds, wait_time
from osc2check.verify.start_modifiers import StartModifiers, invocation_labels
from osc2check.verify.starts import (
    MapChoice,
    StartPlacement,
    largest,
)
from osc2check.verify.terms import (
    InstanceScope,
    call_span,
)
from osc2check.world.catalogue import (
    ACTOR_KINDS,
)
from osc2check.world.errors import MapError, UnknownMapError
from osc2check.world.maps import find_map, map_path, scenario_folder

#: the witness prefers starts in this first share of the road: room to drive ahead
PREFERRED_START_SHARE = Fraction(3, 10)
#: m/s: the least start speed of an actor whose first action needs it driving (30 kph)
DRIVING_START_SPEED = Fraction(25, 3)
#: the actions a vehicle cannot do from rest, nothing else setting its speed: a lane
#: change goes sideways only while the car drives
_DRIVING_FIRST = frozenset({"change_lane"})


def actor_kind(model: Model, sym: Symbol | None) -> str | None:
    """The catalogue kind of an actor type (vehicle, person, animal, stationary_object)."""
    for ancestor in model.ancestors(sym):
        if ancestor.name in ACTOR_KINDS and ancestor.library:
            return ancestor.name
    return None


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


class PlacementLowerer(StartModifiers):
    """The start placement of one scenario (``lower_placement``)."""

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
        starts = self._start_invocations()
        self._apply_starts(starts, placement, first)
        self._alternatives(placement, first)
        waited = self._after_waits(starts, placement, first)
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
            first_action = self.first_action.get(actor.name)
            if (
                actor.name not in self.moving
                and first_action is not None
                and first_action.name.text in _DRIVING_FIRST
                and not self.moving_when.get(actor.name)
            ):
                self._tentative(
                    ir.op(">=", ir.Ref(actor.speed), ir.const(DRIVING_START_SPEED)),
                    actor.span,
                    "driving",
                    f"`{actor.name}` starts driving, as its first action "
                    f"`{first_action.name.text}` needs",
                    f"`{actor.name}`, whose first action `{first_action.name.text}` needs it "
                    f"to be driving, starts at {float(DRIVING_START_SPEED) * 3.6:g} kph or "
                    "more",
                )
            elif actor.name not in self.moving:
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
        for each in waited:
            index = len(self.problem.constraints)
            self._no_overlap(placement, each)
            self.problem.tentative_from(index, each.note)
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

    def _after_waits(
        self,
        starts: list[tuple[ast.Invocation, InstanceScope]],
        placement: StartPlacement,
        first: set[str],
    ) -> list[_Waited]:
        """When nothing acts at time 0 and the scenario first waits a constant time ``c``
        (``phases.after_waits``): the start modifiers of what begins then hold of each
        actor's state at ``c``. Nothing commands an actor while it waits, so it keeps its
        start lane, offset and speed: it is ``c`` times its start speed further along.
        The same when the scenario's ``do`` begins with a ``parallel`` whose members first
        wait (``_waiting_branches``), each for what begins when its waits end, of actors
        that no time-0 action commands and no earlier member placed: the others are taken
        to keep their start lane and speed too. Each result puts the actors at its ``c``
        while it is entered (``with``)."""
        bodies = self._bodies(self.scenario)
        if self.alternatives or not bodies:
            return []
        acting = [inv for inv, _ in starts if not is_instant(inv)]
        body = bodies[0].body
        if acting:
            branches = _waiting_branches(body)
        else:
            found = after_waits(body)
            branches = [found] if found is not None else []
        placed = self._actors_of(starts, placement, every=False)
        labels = invocation_labels(bodies[0])
        done: list[_Waited] = []
        for waits, zero in branches:
            times = [wait_time(self.model, wait, self._lookup) for wait in waits]
            if zero.alternatives or any(t is None for t in times):
                continue
            delay = sum((t for t in times if t is not None), Fraction(0))
            later: list[tuple[ast.Invocation, InstanceScope]] = []
            self._zero_of(zero, labels, self._root_scope(), later, 0, None)
            if self.alternatives:  # a scenario invoked then starts with a `one_of`
                self.alternatives.clear()
                continue
            names = self._actors_of(later, placement, every=True)
            if names & placed:  # a time-0 action (or an earlier member) says their state
                continue
            placed |= names
            index = len(self.problem.constraints)
            waited = _Waited(self, placement, delay, branch=bool(acting), number=len(done))
            applied = set(self.applied)  # each phase's own limits still hold, firmly
            with waited:
                self._apply_starts(later, placement, first)
            self.applied = applied
            self.scope = self._root_scope()
            self.problem.tentative_from(index, waited.note)
            done.append(waited)
        return done

    def _actors_of(
        self,
        found: list[tuple[ast.Invocation, InstanceScope]],
        placement: StartPlacement,
        every: bool,
    ) -> set[str]:
        """The names of the placed actors of ``found``'s invocations (``every``: also of
        those that take no time)."""
        names = set()
        for inv, scope in found:
            self.scope = scope
            actor = self._actor_at(inv, placement)
            if actor is not None and (every or not is_instant(inv)):
                names.add(actor.name)
        self.scope = self._root_scope()
        return names

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
                    terms.room(actor.road, reach, half_of(actor.body.length)),
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
            source = str(path.resolve()) if path is not None and is_file(path) else None
            return MapChoice(self.default_map if source else fallback.name, fallback, source)
        file = self.maps.get(name, name)  # a name the configuration gives a file
        try:
            found = find_map(file, folder)
        except UnknownMapError as err:
            return MapChoice(fallback.name, fallback, asked=name, span=span, unknown=err.known)
        except MapError as err:
            return MapChoice(fallback.name, fallback, asked=name, span=span, unreadable=err)
        path = map_path(file, folder)
        source = str(path.resolve()) if path is not None and is_file(path) else None
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

    # ---- the invocations that begin at time 0 ------------------------------------------

    # ---- no overlap --------------------------------------------------------------------

    def _no_overlap(self, placement: StartPlacement, waited: _Waited | None = None) -> None:
        """Actors in one lane do not overlap at the start; with ``waited``, nor when the
        scenario's first wait ends, in the same order as at the start, so that at constant
        speeds they never overlap in between."""
        fixed = self._fixed_lanes(placement)
        names = list(placement.actors)
        for i, a_name in enumerate(names):
            for b_name in names[i + 1 :]:
                if a_name in fixed and b_name in fixed and fixed[a_name] != fixed[b_name]:
                    continue  # never in the same lane
                a, b = placement.actors[a_name], placement.actors[b_name]
                need = half_of(plus(a.body.length, b.body.length))
                sa, sb = ir.Ref(a.s), ir.Ref(b.s)
                a_ahead, b_ahead = (
                    ir.op(">=", ir.op("-", sa, sb), need),
                    ir.op(">=", ir.op("-", sb, sa), need),
                )
                if waited is not None:
                    ac, bc = ir.Ref(waited.after[a_name]), ir.Ref(waited.after[b_name])
                    a_ahead = ir.op("and", a_ahead, ir.op(">=", ir.op("-", ac, bc), need))
                    b_ahead = ir.op("and", b_ahead, ir.op(">=", ir.op("-", bc, ac), need))
                apart = placement.terms.apart(a.road, b.road)
                term = ir.op(
                    "or",
                    *((apart,) if apart is not None else ()),
                    ir.op("!=", ir.Ref(a.lane), ir.Ref(b.lane)),
                    a_ahead,
                    b_ahead,
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


class _Waited:
    """Each actor's position when the scenario's first waits end (of one member of its
    ``parallel`` with ``branch``; ``number`` tells the variables of the members after
    the first apart), ``delay`` seconds at its start speed (a variable tied to the
    start's), put in place of its start position while entered."""

    def __init__(
        self,
        lowerer: PlacementLowerer,
        placement: StartPlacement,
        delay: Fraction,
        branch: bool = False,
        number: int = 0,
    ):
        self.actors = list(placement.actors.values())
        self.starts = {actor.name: actor.s for actor in self.actors}
        self.after: dict[str, ir.Var] = {}
        which = "a member of the `parallel` the scenario begins with" if branch else "the scenario"
        self.note = (
            f"the starts after the first wait of {which} ({float(delay):g} s) are placed as "
            "if every actor kept its start lane and speed until then (else the runner "
            "brings them about during the wait)"
        )
        for actor in self.actors:
            after = lowerer.problem.var(
                f"{actor.name}@start.after_wait{number + 1 if number else ''}",
                "real",
                unit="m",
                span=actor.span,
            )
            moved = ir.op("*", ir.const(delay), ir.Ref(actor.speed))
            lowerer._implicit(
                ir.op("==", ir.Ref(after), ir.op("+", ir.Ref(actor.s), moved)),
                actor.span,
                "waiting",
                f"`{actor.name}` keeps its start lane and speed until the first wait of "
                f"{which} ends ({float(delay):g} s)",
            )
            lowerer._implicit(
                lowerer.terms.extent(actor.road, ir.Ref(after), half_of(actor.body.length)),
                actor.span,
                "road-extent",
                f"`{actor.name}` is still on the road when the first wait of {which} ends",
            )
            self.after[actor.name] = after

    def __enter__(self) -> None:
        for actor in self.actors:
            actor.s = self.after[actor.name]

    def __exit__(self, *exc: object) -> None:
        for actor in self.actors:
            actor.s = self.starts[actor.name]


def _waiting_branches(body: ast.Node) -> list[tuple[list[ast.Wait], TimeZero]]:
    """For a body that begins with a ``parallel`` (``phases.leading_parallel``), what each
    member that first waits starts when those waits end (``phases.after_waits`` of that
    member), in source order; none for any other body."""
    parallel = leading_parallel(body)
    if parallel is None:
        return []
    return [f for m in parallel.members if (f := after_waits(m.body)) is not None]


def _unless(guards: list[ir.Term] | None, term: ir.Term) -> ir.Term:
    """``term`` where none of the choices ``guards`` holds (it always does without any)."""
    if not guards:
        return term
    return ir.op("or", *guards, term)


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
