"""The actors of a scenario instance: which fields are actors, and what each one is in the world.

A scenario field whose type is an actor becomes an :class:`Actor`. Its kind
says how the world represents it:

========================= ============ ==========================================
OSC2 type (or subtype)    kind         in the world
========================= ============ ==========================================
``vehicle``               vehicle      MuJoCo car: sedan, or HGV for trucks/buses
``person``, ``animal``    pedestrian   kinematic capsule
``stationary_object``     obstacle     static box
``environment``           environment  weather and road friction (no body)
``map``                   map          selects the road (``map_file``)
anything else             other        no body; invoking an action on it is an error
========================= ============ ==========================================

The vehicle model comes from the toolkit's ``model`` attribute (CARLA blueprint
names such as ``vehicle.tesla.model3``; see :data:`BLUEPRINTS`), else from
``vehicle_category`` (``truck``, ``bus`` -> HGV; otherwise a sedan).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from osc2check.semantics import types as T
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol
from osc2runner.sim import ObstacleParams, PedestrianParams, VehicleParams, hgv, sedan
from osc2runner.values import ParameterValues, Quantity, scenario_fields, to_runtime

__all__ = ["Actor", "BLUEPRINTS", "actor_kind", "scenario_actors"]

ActorParams = VehicleParams | PedestrianParams | ObstacleParams | None

# Simulator blueprint names (the design paper's CARLA models) -> vehicle parameters.
BLUEPRINTS: dict[str, str] = {
    "vehicle.tesla.model3": "sedan",
    "vehicle.audi.a2": "sedan",
    "vehicle.audi.tt": "sedan",
    "vehicle.bmw.grandtourer": "sedan",
    "vehicle.lincoln.mkz_2017": "sedan",
    "vehicle.lincoln.mkz_2020": "sedan",
    "vehicle.mercedes.coupe": "sedan",
    "vehicle.nissan.micra": "sedan",
    "vehicle.toyota.prius": "sedan",
    "vehicle.carlamotors.european_hgv": "hgv",
    "vehicle.carlamotors.carlacola": "hgv",
    "vehicle.carlamotors.firetruck": "hgv",
    "vehicle.mitsubishi.fusorosa": "hgv",
}
_HEAVY_CATEGORIES = {"truck", "bus"}
_KINDS = (
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
    telemetry); ``type`` the OSC2 actor type; ``attributes`` the constant
    attributes (``model``, ``name``, ``vehicle_category``, ...), exact.
    """

    name: str
    symbol: Symbol
    type: Symbol
    kind: str
    params: ActorParams = None
    attributes: dict[str, object] = field(default_factory=dict)
    blueprint: str | None = None

    @property
    def has_body(self) -> bool:
        return self.kind in ("vehicle", "pedestrian", "obstacle")

    def __repr__(self) -> str:
        return f"<actor {self.name}: {self.type.name}>"


def actor_kind(model: Model, type_symbol: Symbol) -> str:
    """``vehicle``, ``pedestrian``, ``obstacle``, ``environment``, ``map`` or ``other``."""
    names = [s.name for s in model.ancestors(type_symbol)]
    for base, kind in _KINDS:
        if base in names:
            return kind
    return "other"


def _vehicle_params(attributes: dict[str, object]) -> tuple[VehicleParams, str]:
    model = attributes.get("model")
    if isinstance(model, str) and model in BLUEPRINTS:
        kind = BLUEPRINTS[model]
        return (hgv() if kind == "hgv" else sedan()), f"{model} ({kind})"
    category = to_runtime(attributes.get("vehicle_category"))
    if category in _HEAVY_CATEGORIES:
        return hgv(), f"vehicle_category {category} (hgv)"
    if isinstance(model, str):
        heavy = any(word in model.lower() for word in ("truck", "hgv", "bus", "lorry"))
        return (hgv() if heavy else sedan()), f"{model} ({'hgv' if heavy else 'sedan'})"
    return sedan(), "sedan"


def _obstacle_params(attributes: dict[str, object]) -> ObstacleParams:
    return ObstacleParams()


def scenario_actors(model: Model, scenario: Symbol, values: ParameterValues) -> list[Actor]:
    """The scenario's actor fields, in declaration order, with their world parameters."""
    actors: list[Actor] = []
    for sym in scenario_fields(model, scenario):
        t = sym.type
        if t is None or t.kind is not T.Kind.COMPOUND or t.symbol is None:
            continue
        if t.symbol.kind.name != "ACTOR":
            continue
        kind = actor_kind(model, t.symbol)
        attributes: dict[str, object] = {}
        getter = getattr(values, "attributes", None)
        if callable(getter):
            attributes = dict(getter(sym))
        actor = Actor(sym.name, sym, t.symbol, kind, attributes=attributes)
        if kind == "vehicle":
            actor.params, actor.blueprint = _vehicle_params(attributes)
        elif kind == "pedestrian":
            actor.params, actor.blueprint = PedestrianParams(), "pedestrian"
        elif kind == "obstacle":
            actor.params, actor.blueprint = _obstacle_params(attributes), "obstacle"
        actors.append(actor)
    return actors


def quantity(value: object) -> float | None:
    """An exact value as an SI float, or None."""
    if isinstance(value, Quantity):
        return float(value.value)
    return None
