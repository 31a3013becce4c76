"""What each actor of the start placement is, and where it may stand: its body (size,
top speed, category: ``world.catalogue``), its start variables (``starts.PlacedActor``)
and the rules of the road and the catalogue on them (see ``placement`` for the
conventions).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from fractions import Fraction

from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.verify import ir
from osc2check.verify.map_modifiers import MapFields
from osc2check.verify.parameters import Lowerer
from osc2check.verify.problem import ConstraintProblem
from osc2check.verify.road_terms import RoadTerms, between
from osc2check.verify.starts import (
    ActorBody,
    PlacedActor,
)
from osc2check.verify.terms import (
    InstanceScope,
)
from osc2check.world.catalogue import (
    CATEGORIES,
    NOT_ON_ROADS,
    ActorRow,
    kind_row,
    model_row,
)

#: the rule of "a vehicle whose category nothing constrains is a car": a placement that
#: has no solution with it is tried again with those vehicles of any category
UNSAID_CATEGORY = "unsaid-category"


class ActorPlacer:
    """The state of one scenario's start placement, and its actors' bodies and rules."""

    # made by ``PlacementLowerer.lower`` before any actor is placed
    terms: RoadTerms
    fields: MapFields
    constants: dict[str, tuple[Fraction | bool, ir.Constraint]]
    written: set[str]

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
        self.first_action: dict[str, ast.Invocation] = {}  # each actor's first at time 0

    def _root_scope(self) -> InstanceScope:
        return InstanceScope("", self.scenario, "", self.scenario)

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

    def _tentative(self, term: ir.Term, span: Span, rule: str, text: str, note: str) -> None:
        """A start the scenario leaves open, read so that its actions can be done: an
        implicit constraint that gives way when it conflicts (``ir.Constraint``)."""
        index = len(self.problem.constraints)
        self._implicit(term, span, rule, text)
        self.problem.tentative_from(index, note)

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
        half = half_of(body.length)
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
                half_of(body.width),
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


def _is_trailer(model: Model, sym: Symbol | None) -> bool:
    return any(a.name == "trailer" and a.library for a in model.ancestors(sym))


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


def half_of(term: ir.Term) -> ir.Term:
    """Half of ``term`` (a constant when ``term`` is one)."""
    value = _number(term)
    return ir.const(value / 2) if value is not None else ir.op("*", ir.const(Fraction(1, 2)), term)


def plus(a: ir.Term, b: ir.Term) -> ir.Term:
    """``a + b`` (a constant when both are)."""
    x, y = _number(a), _number(b)
    return ir.const(x + y) if x is not None and y is not None else ir.op("+", a, b)
