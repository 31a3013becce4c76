"""The start state the scenario asks for: which invocations begin at time 0 (``one_of``
members under their choice), their `lane`, `position`, `speed`, `yaw`, `lateral` and
`along` modifiers as constraints on the actors' start variables, and the lane and speed
every phase needs (see ``placement`` for the conventions).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from fractions import Fraction

from osc2check.semantics.bindings import ReadArguments
from osc2check.semantics.members import scenario_do
from osc2check.semantics.phases import (
    Guard,
    TimeZero,
    acting_members,
    enum_word,
    invocations,
    modifier_timing,
    time_zero,
)
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.verify import ir
from osc2check.verify.actor_bodies import ActorPlacer, half_of, plus
from osc2check.verify.lane_steps import LaneSteps, one_of_members
from osc2check.verify.starts import (
    Gap,
    PlacedActor,
    StartPlacement,
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
from osc2check.world.numbering import LANE_REFERENCES, lane_side

_POSITIONING = ("lane", "position")  # the modifiers that place an actor (L506)

#: actions whose actor stands still throughout
_STANDING = ("remain_stationary",)
#: actions that reach a gap to a reference ahead or behind: whether bumper to bumper
_GAP_ACTIONS = {"change_space_gap": True, "change_space_headway": False}


class StartModifiers(ActorPlacer):
    """The invocations that begin at time 0 and their modifiers, as start constraints."""

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
        self._zero_of(time_zero(member.body), invocation_labels(member), scope, found, depth, guard)

    def _zero_of(
        self,
        zero: TimeZero,
        labels: dict[int, ast.Name],
        scope: InstanceScope,
        found: list[tuple[ast.Invocation, InstanceScope]],
        depth: int,
        guard: ir.Term | None,
    ) -> None:
        """``_zero`` of what begins together (``zero``)."""
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
        labels = invocation_labels(member)
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
        if is_first and self.guard is None:
            self.first_action[actor.name] = inv
        if inv.name.text in _GAP_ACTIONS and self.guard is None:
            self._gap_side(actor, inv, placement)
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

    def _gap_side(self, actor: PlacedActor, inv: ast.Invocation, placement: StartPlacement) -> None:
        """``change_space_gap`` (or ``_headway``) ``behind`` or ``ahead`` of a reference
        that begins at time 0: where the scenario leaves the starts open, the actor starts
        on that side, from where driving forward reaches the gap (further back than the
        target behind, within it ahead): tentative."""
        args = self._args(inv)
        side = enum_word(args.get("direction"))
        node = args.get("reference")
        if side not in ("ahead", "behind") or node is None or "target" not in args:
            return
        other = self._reference(node, actor, placement, inv.span)
        target = self._value(args["target"])
        if other is None or target is None:
            return
        gap = ir.op("-", ir.Ref(other.s), ir.Ref(actor.s))
        if side == "ahead":
            gap = ir.op("neg", gap)
        if _GAP_ACTIONS[inv.name.text]:  # bumper to bumper
            gap = ir.op("-", gap, half_of(plus(actor.body.length, other.body.length)))
        reach = ir.op(">=", gap, target) if side == "behind" else in_range(gap, ir.const(0), target)
        self._tentative(
            _with(reach, placement.terms.same(actor.road, other.road)),
            call_span(inv),
            "gap-side",
            f"`{actor.name}` starts {side} `{other.name}`, from where driving forward reaches "
            "the gap",
            f"`{actor.name}` is placed {side} `{other.name}`, from where driving forward "
            f"reaches the gap its `{inv.name.text}` asks",
        )

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
        shared = self.lw.member_decls
        if shared.one_of_invocations is None:
            scenarios = [s.decl for s in self.model.symbols if s.kind is SymbolKind.SCENARIO]
            shared.one_of_invocations = one_of_members(d for d in scenarios if d)
        rules = placement.map.facts.rules
        steps = LaneSteps(self.model, self._value, shared.one_of_invocations, rules != {"LHT"})
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
        """The variable of the lane a later phase's `lane(k)` gives ``actor`` (its start
        lane for one applied at the start; None when there is none)."""

        def lane(item: ast.Invocation) -> ir.Var | None:
            if id(item) in self.applied:
                return actor.lane
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
        half = half_of(plus(actor.body.length, other.body.length))
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


def invocation_labels(member: ast.DoMember) -> dict[int, ast.Name]:
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


def _with(relation: ir.Term, also: ir.Term | None) -> ir.Term:
    return relation if also is None else ir.op("and", relation, also)
