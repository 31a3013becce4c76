"""The actors of a scenario instance: which fields are actors, and what each one is in the world.

A scenario field whose type is an actor becomes an :class:`Actor`. Its kind
says how the world represents it:

========================= ============ ==========================================
OSC2 type (or subtype)    kind         in the world
========================= ============ ==========================================
``vehicle``               vehicle      MuJoCo multibody vehicle of its catalogue row
``trailer`` (a row of     trailer      towed body (``sim/trailer.py``): no engine, no
trailer construction)                  driver; it moves when a vehicle tows it
``person``, ``animal``    pedestrian   kinematic walker
``stationary_object``     obstacle     static box
``environment``           environment  weather and road friction (no body)
``map``                   map          selects the road (``map_file``)
anything else             other        no body; invoking an action on it is an error
========================= ============ ==========================================

What a body actor is comes from the witness (``ActorStart.model``: the row of
``osc2check.world.catalogue`` the checker placed it with, and its length and
width), so the body the world builds has the footprint the checker placed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

from osc2check.semantics import types as T
from osc2check.semantics.constants import Value
from osc2check.semantics.members import actor_alias
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.verify.witness import ActorStart, Witness
from osc2check.world.catalogue import MODELS, ActorRow, category_row, kind_row
from osc2runner.instance.bodies import ActorParams, body_params
from osc2runner.instance.values import ScenarioValues, scenario_fields
from osc2runner.sim.vehicle import ObstacleParams

__all__ = ["BODY_KINDS", "Actor", "ActorKind", "actor_kind", "environment_sky", "scenario_actors"]

#: what an actor is in the world (the table of the module docstring)
ActorKind = Literal["vehicle", "trailer", "pedestrian", "obstacle", "environment", "map", "other"]
#: the kinds the world builds a body for
BODY_KINDS: tuple[ActorKind, ...] = ("vehicle", "trailer", "pedestrian", "obstacle")

_KINDS: tuple[tuple[str, ActorKind], ...] = (
    ("vehicle", "vehicle"),
    ("person", "pedestrian"),
    ("animal", "pedestrian"),
    ("stationary_object", "obstacle"),
    ("environment", "environment"),
    ("map", "map"),
)


@dataclass
class Actor:
    """One actor of the scenario instance.

    ``name`` is the field name (also the actor's name in the world and the
    telemetry); ``type`` the OSC2 actor type; ``attributes`` the attributes a
    constraint decides (``model``, ``vehicle_category``, ...), exact; ``row`` the
    catalogue row of a body actor and ``start`` its start in the witness.
    """

    name: str
    symbol: Symbol
    type: Symbol
    kind: ActorKind
    params: ActorParams | None = None
    attributes: dict[str, Value] = field(default_factory=dict)
    row: ActorRow | None = None
    start: ActorStart | None = None
    #: world (x, y, yaw) of a stationary object's ``location`` (instance.locations)
    location: tuple[float, float, float] | None = None

    @property
    def has_body(self) -> bool:
        return self.kind in BODY_KINDS

    @property
    def top_speed(self) -> float:
        """The body's top speed, m/s (its catalogue row's); infinite for a body that does
        not move (an obstacle) and for an actor without a body."""
        p = self.params
        return math.inf if p is None or isinstance(p, ObstacleParams) else p.max_speed

    @property
    def length(self) -> float:
        """The body's length, m (its bounding box's); 0 for an actor without a body."""
        return self.params.length if self.params is not None else 0.0

    @property
    def blueprint(self) -> str | None:
        """The catalogue row the body is built from (a model name, category or kind)."""
        return self.row.key if self.row is not None else None

    def __repr__(self) -> str:
        return f"<actor {self.name}: {self.type.name}>"


def actor_kind(model: Model, type_symbol: Symbol) -> ActorKind:
    """``vehicle``, ``pedestrian``, ``obstacle``, ``environment``, ``map`` or ``other`` (a
    vehicle whose catalogue row is a trailer becomes ``trailer`` once it has its row). Only
    the standard library's types count, as for the checker's placement: a file's own
    ``actor vehicle`` is ``other``, an actor without a body."""
    names = [s.name for s in model.ancestors(type_symbol) if s.library]
    for base, kind in _KINDS:
        if base in names:
            return kind
    return "other"


def _row(start: ActorStart) -> ActorRow:
    if start.model in MODELS:
        return MODELS[start.model]
    if start.kind == "vehicle":
        return category_row(start.category)
    return kind_row(start.kind)


def scenario_actors(
    model: Model, scenario: Symbol, values: ScenarioValues, witness: Witness
) -> list[Actor]:
    """The scenario's actor fields, in declaration order, built as the witness says."""
    actors: list[Actor] = []
    for sym in scenario_fields(model, scenario):
        t = sym.type
        if t is None or t.kind is not T.Kind.COMPOUND or t.symbol is None:
            continue
        if t.symbol.kind is not SymbolKind.ACTOR or actor_alias(model, sym) is not None:
            continue  # an alias names another field's actor: no actor of its own
        kind = actor_kind(model, t.symbol)
        actor = Actor(sym.name, sym, t.symbol, kind, attributes=values.attributes(sym))
        start = witness.actor(sym.name)
        if actor.has_body and start is not None:
            actor.row = _row(start)
            actor.start = start
            actor.params = body_params(actor.row, float(start.length), float(start.width))
            if actor.row.is_trailer:  # a towed body: what its row is decides it, not its type
                actor.kind = "trailer"
        actors.append(actor)
    return actors


#: the environment's members that place the observer of the sky
SITE = ("geodetic_position.latitude", "geodetic_position.longitude")


def environment_sky(
    actors: list[Actor], values: ScenarioValues
) -> tuple[tuple[float, float] | None, float | None]:
    """The world's place and start time (``sim.sky``): ``(latitude, longitude)`` (radians)
    of the first environment actor whose constraints give both, and the ``datetime``
    (Unix seconds) of the first whose constraints give it; None for what none gives."""
    site: tuple[float, float] | None = None
    start: float | None = None
    for actor in actors:
        if actor.kind != "environment":
            continue
        latitude, longitude = (values.constrained_si(f"{actor.name}.{m}") for m in SITE)
        if site is None and latitude is not None and longitude is not None:
            site = (latitude, longitude)
        if start is None:
            start = values.constrained_si(f"{actor.name}.datetime")
    return site, start
