"""The catalogue of actors: what each kind, vehicle category and model name is in the world.

One row per entry: its bounding box, wheelbase, mass, top speed and acceleration
limits. The checker places actors with these footprints and checks their speeds
against these limits; the witness records the row and the dimensions it used;
the runner builds its MuJoCo bodies from the same row (``osc2runner.instance``).
A truck checked as a truck is built as a truck.

Rows are found by (in this order) the simulator model name a scenario gives
(``keep(it.model == "vehicle.tesla.model3")``, CARLA's blueprint names), the
vehicle category (``car``, ``bus``, ``truck``, ``trailer``, ``vru_vehicle``,
``other``, the 2.1 list), or the actor kind (``person``, ``animal``,
``stationary_object``). A model name the catalogue does not know falls back to
a category its words suggest (``...hgv`` is a truck), else to the category.

Values are exact (``Fraction``) because the checker reasons over them with
exact arithmetic. Dimensions follow the vehicles' real-world counterparts (the
manufacturers' published length, width, height, wheelbase and kerb mass,
rounded); a scenario's declared ``bounding_box`` overrides the row's box.
Limits: ``max_speed`` is the top speed; ``max_acceleration`` the tractive
limit at low speed on dry asphalt; ``max_deceleration`` full braking on dry
asphalt.

Hitches: a trailer row says where its coupler is (``hitch``, behind the front
of its box; negative on a drawbar ahead of it) and how high (``hitch_height``);
its ``front_overhang`` is the front of its box to its axle (group), so its
``wheelbase`` is the coupler to that axle. Tow vehicles carry a receiver behind
their rear bumper, as :func:`receiver` says by construction (two-wheelers and
trailers tow nothing). Trailers heavier than :data:`UNBRAKED_TRAILER_MASS` have
brakes of their own.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

__all__ = [
    "ACTOR_KINDS",
    "CATEGORIES",
    "CATEGORY_ALIASES",
    "MODELS",
    "NOT_ON_ROADS",
    "UNBRAKED_TRAILER_MASS",
    "WALKING_SPEED",
    "ActorRow",
    "Receiver",
    "category_row",
    "kind_row",
    "model_row",
    "receiver",
    "row_for",
]

KPH = Fraction(5, 18)  # m/s per kph

#: how fast an adult walks at most (m/s); faster is running, which a scenario must mean
#: (the checker's L515; a person's top speed is its row's ``max_speed``)
WALKING_SPEED = Fraction(3)

#: The library actor types the catalogue describes, most specific first.
ACTOR_KINDS = ("vehicle", "person", "animal", "stationary_object")


@dataclass(frozen=True, slots=True)
class ActorRow:
    """One catalogue entry (lengths in m, mass in kg, speeds in m/s, accelerations in m/s²).

    ``body`` names the construction the runner builds: ``car``, ``truck``,
    ``bus``, ``trailer``, ``two_wheeler`` (four-wheeled vehicle bodies with
    these proportions), ``person``, ``animal`` (kinematic walkers) or ``box``
    (a static obstacle).
    """

    key: str  # the model name, vehicle category or actor kind this row is found by
    kind: str  # vehicle | person | animal | stationary_object
    category: str  # the vehicle_category member (the kind for other actors)
    body: str
    length: Fraction
    width: Fraction
    height: Fraction
    mass: Fraction
    max_speed: Fraction
    max_acceleration: Fraction
    max_deceleration: Fraction
    wheelbase: Fraction = Fraction(0)  # 0 for actors without wheels; a trailer's: coupler to axle
    front_overhang: Fraction = Fraction(0)  # front of the box to the front (a trailer's only) axle
    hitch: Fraction = Fraction(0)  # a trailer's coupler behind the front of its box (< 0: ahead)
    hitch_height: Fraction = Fraction(0)  # a trailer's coupler above the ground

    @property
    def is_model(self) -> bool:
        """Whether the row is a named simulator model (not a generic category)."""
        return "." in self.key

    @property
    def is_trailer(self) -> bool:
        """Whether the row is a towed body: no engine, a coupler, one axle (group)."""
        return self.body == "trailer"


@dataclass(frozen=True, slots=True)
class Receiver:
    """A tow vehicle's hitch receiver: its distance behind the front of the vehicle's box
    and its height above the ground (m)."""

    behind_front: Fraction
    height: Fraction


def _f(text: str) -> Fraction:
    return Fraction(text)


def _vehicle(
    key: str,
    category: str,
    body: str,
    size: tuple[str, str, str],
    wheelbase: str,
    overhang: str,
    mass: str,
    top_kph: int,
    accel: str,
    decel: str,
) -> ActorRow:
    length, width, height = (_f(v) for v in size)
    return ActorRow(
        key,
        "vehicle",
        category,
        body,
        length,
        width,
        height,
        _f(mass),
        top_kph * KPH,
        _f(accel),
        _f(decel),
        _f(wheelbase),
        _f(overhang),
    )


def _trailer(
    key: str,
    size: tuple[str, str, str],
    hitch: str,
    axle: str,
    hitch_height: str,
    mass: str,
    top_kph: int,
    category: str = "trailer",
) -> ActorRow:
    """A trailer: its coupler ``hitch`` behind the front of its box (negative on a
    drawbar), its axle (group) ``axle`` behind the front; no engine, braking at 6 m/s²
    when braked."""
    length, width, height = (_f(v) for v in size)
    return ActorRow(
        key,
        "vehicle",
        category,
        "trailer",
        length,
        width,
        height,
        _f(mass),
        top_kph * KPH,
        Fraction(0),
        Fraction(6),
        _f(axle) - _f(hitch),
        _f(axle),
        _f(hitch),
        _f(hitch_height),
    )


#: trailers up to this mass (kg) need no brakes of their own (EU category O1); heavier ones
#: brake with their tow vehicle (O2 to O4)
UNBRAKED_TRAILER_MASS = Fraction(750)

# Generic rows per vehicle category (the 2.1 list of `vehicle_category`, then 2.2's).
_CATEGORY_ROWS = (
    _vehicle("car", "car", "car", ("4.5", "1.8", "1.45"), "2.7", "0.85", "1600", 250, "3", "9"),
    _vehicle("bus", "bus", "bus", ("12", "2.55", "3.2"), "6", "2.7", "13000", 100, "1.5", "6"),
    _vehicle(
        "truck", "truck", "truck", ("12", "2.5", "3.6"), "5.5", "1.5", "12000", 90, "1.6", "6"
    ),
    # a tandem central-axle trailer as trucks tow it, on a 1.5 m drawbar at pintle height
    _trailer("trailer", ("10", "2.5", "3.5"), "-1.5", "5.6", "0.9", "8000", 90),
    _vehicle(
        "vru_vehicle",
        "vru_vehicle",
        "two_wheeler",
        ("1.8", "0.7", "1.7"),
        "1.1",
        "0.35",
        "95",
        45,
        "1.5",
        "3.5",
    ),
    _vehicle("other", "other", "car", ("4.5", "1.8", "1.45"), "2.7", "0.85", "1600", 250, "3", "9"),
    # the categories DSL 2.2 adds (a 2.1 program has no such members)
    _vehicle("van", "van", "car", ("5.3", "2.0", "2.3"), "3.3", "0.9", "2300", 160, "2.5", "8"),
    _vehicle("semi_tractor", "semi_tractor", "truck", ("6.0", "2.5", "3.9"), "3.8", "1.4",
             "8000", 90, "1.8", "6"),
    # a 13.6 m box semi-trailer on its tractor's fifth wheel, 1.2 m up, loaded
    _trailer("semi_trailer", ("13.6", "2.55", "4.0"), "1.6", "10.8", "1.2", "20000", 90,
             "semi_trailer"),
    _vehicle("motorcycle", "motorcycle", "two_wheeler", ("2.1", "0.8", "1.3"), "1.45", "0.35",
             "250", 180, "5", "8"),
    _vehicle("bicycle", "bicycle", "two_wheeler", ("1.75", "0.6", "1.75"), "1.05", "0.3", "90",
             40, "1.5", "3.5"),
    _vehicle("stand_up_scooter", "stand_up_scooter", "two_wheeler", ("1.15", "0.5", "1.2"),
             "0.85", "0.15", "90", 25, "1.5", "3"),
    _vehicle("wheelchair", "wheelchair", "two_wheeler", ("1.1", "0.7", "1.0"), "0.8", "0.15",
             "120", 15, "1", "2.5"),
    _vehicle("work_machine", "work_machine", "truck", ("6.5", "2.5", "3.2"), "3.5", "1.2",
             "12000", 40, "1", "5"),
    _vehicle("tram", "tram", "bus", ("30", "2.65", "3.5"), "20", "5", "40000", 70, "1.3", "2.5"),
    _vehicle("land_vehicle", "land_vehicle", "car", ("4.5", "1.8", "1.45"), "2.7", "0.85",
             "1600", 250, "3", "9"),
)  # fmt: skip

# Simulator model names (CARLA's blueprint library): the real vehicles they depict.
_MODEL_ROWS = (
    # passenger cars and light goods vehicles up to 3.5 t
    _vehicle("vehicle.audi.a2", "car", "car", ("3.83", "1.67", "1.55"), "2.41", "0.7", "1000",
             175, "2.6", "9"),
    _vehicle("vehicle.audi.etron", "car", "car", ("4.9", "1.94", "1.63"), "2.93", "0.9", "2500",
             200, "3.5", "9"),
    _vehicle("vehicle.audi.tt", "car", "car", ("4.18", "1.83", "1.36"), "2.51", "0.85", "1300",
             250, "4", "9.5"),
    _vehicle("vehicle.bmw.grandtourer", "car", "car", ("4.56", "1.8", "1.61"), "2.78", "0.85",
             "1500", 215, "3", "9"),
    _vehicle("vehicle.chevrolet.impala", "car", "car", ("5.11", "1.85", "1.48"), "2.84", "1",
             "1650", 200, "3", "9"),
    _vehicle("vehicle.citroen.c3", "car", "car", ("4", "1.75", "1.47"), "2.54", "0.75", "1100",
             185, "2.6", "9"),
    _vehicle("vehicle.dodge.charger_2020", "car", "car", ("5.04", "1.91", "1.46"), "3.05", "0.95",
             "1800", 250, "4", "9.5"),
    _vehicle("vehicle.ford.mustang", "car", "car", ("4.79", "1.92", "1.38"), "2.72", "0.9",
             "1700", 250, "4.5", "9.5"),
    _vehicle("vehicle.jeep.wrangler_rubicon", "car", "car", ("4.33", "1.88", "1.84"), "2.46",
             "0.8", "2000", 160, "2.8", "8"),
    _vehicle("vehicle.lincoln.mkz_2017", "car", "car", ("4.93", "1.86", "1.48"), "2.85", "0.95",
             "1700", 210, "3", "9"),
    _vehicle("vehicle.lincoln.mkz_2020", "car", "car", ("4.93", "1.86", "1.48"), "2.85", "0.95",
             "1700", 210, "3", "9"),
    _vehicle("vehicle.mercedes.coupe", "car", "car", ("4.7", "1.81", "1.4"), "2.76", "0.85",
             "1600", 250, "3.5", "9.5"),
    _vehicle("vehicle.mercedes.coupe_2020", "car", "car", ("4.84", "1.86", "1.43"), "2.87",
             "0.9", "1700", 250, "3.8", "9.5"),
    _vehicle("vehicle.mini.cooper_s", "car", "car", ("3.88", "1.73", "1.41"), "2.5", "0.7",
             "1250", 235, "3.8", "9.5"),
    _vehicle("vehicle.nissan.micra", "car", "car", ("3.83", "1.67", "1.52"), "2.43", "0.7",
             "1000", 170, "2.5", "9"),
    _vehicle("vehicle.nissan.patrol", "car", "car", ("5.17", "1.99", "1.94"), "3.08", "0.95",
             "2700", 200, "2.8", "8"),
    _vehicle("vehicle.seat.leon", "car", "car", ("4.28", "1.82", "1.46"), "2.64", "0.85", "1300",
             225, "3.2", "9.5"),
    _vehicle("vehicle.tesla.model3", "car", "car", ("4.69", "1.85", "1.44"), "2.88", "0.85",
             "1650", 225, "5", "9.5"),
    _vehicle("vehicle.tesla.cybertruck", "car", "car", ("5.68", "2.2", "1.79"), "3.81", "0.9",
             "3100", 180, "5", "8.5"),
    _vehicle("vehicle.toyota.prius", "car", "car", ("4.54", "1.76", "1.49"), "2.7", "0.9", "1400",
             180, "2.6", "9"),
    _vehicle("vehicle.volkswagen.t2", "car", "car", ("4.51", "1.72", "1.94"), "2.4", "1.05",
             "1400", 110, "1.5", "7"),
    _vehicle("vehicle.mercedes.sprinter", "car", "car", ("5.93", "2.02", "2.7"), "3.66", "1",
             "3000", 160, "2", "7.5"),
    # goods vehicles above 3.5 t and buses
    _vehicle("vehicle.carlamotors.carlacola", "truck", "truck", ("5.21", "2.62", "3.46"), "3.2",
             "1.05", "7500", 100, "1.8", "6.5"),
    _vehicle("vehicle.carlamotors.european_hgv", "truck", "truck", ("12", "2.5", "3.6"), "5.5",
             "1.5", "12000", 90, "1.6", "6"),
    _vehicle("vehicle.carlamotors.firetruck", "truck", "truck", ("8.7", "2.5", "3.3"), "4.6",
             "1.4", "15000", 100, "1.5", "6"),
    _vehicle("vehicle.ford.ambulance", "truck", "truck", ("6.36", "2.4", "2.85"), "3.99", "1",
             "5000", 140, "2", "7"),
    _vehicle("vehicle.mitsubishi.fusorosa", "bus", "bus", ("6.99", "2.01", "2.64"), "3.995",
             "1.1", "5500", 100, "1.8", "6.5"),
    # two-wheelers (mass with rider)
    _vehicle("vehicle.bh.crossbike", "vru_vehicle", "two_wheeler", ("1.72", "0.6", "1.75"),
             "1.07", "0.3", "90", 40, "1.5", "3.5"),
    _vehicle("vehicle.diamondback.century", "vru_vehicle", "two_wheeler", ("1.68", "0.45", "1.75"),
             "1.0", "0.3", "85", 45, "1.5", "3.5"),
    _vehicle("vehicle.gazelle.omafiets", "vru_vehicle", "two_wheeler", ("1.85", "0.65", "1.75"),
             "1.15", "0.32", "95", 30, "1.2", "3"),
    _vehicle("vehicle.harley-davidson.low_rider", "vru_vehicle", "two_wheeler",
             ("2.36", "0.9", "1.3"), "1.6", "0.4", "380", 180, "4", "8"),
    _vehicle("vehicle.kawasaki.ninja", "vru_vehicle", "two_wheeler", ("2.02", "0.75", "1.3"),
             "1.37", "0.35", "260", 250, "6", "9"),
    _vehicle("vehicle.yamaha.yzf", "vru_vehicle", "two_wheeler", ("2.05", "0.72", "1.3"), "1.4",
             "0.35", "270", 250, "6", "9"),
    _vehicle("vehicle.vespa.zx125", "vru_vehicle", "two_wheeler", ("1.86", "0.72", "1.4"), "1.35",
             "0.3", "210", 95, "2.5", "6.5"),
    # trailers a car tows (ball coupling at 0.45 m): a touring caravan (braked) and a light
    # box trailer at the unbraked limit, loaded
    _trailer("trailer.caravan", ("6.5", "2.3", "2.6"), "-1.2", "4", "0.45", "1400", 100),
    _trailer("trailer.box", ("3", "1.6", "1.1"), "-1.3", "1.6", "0.45", "750", 100),
)  # fmt: skip

_KIND_ROWS = (
    ActorRow("person", "person", "person", "person", _f("0.6"), _f("0.6"), _f("1.8"), _f("75"),
             15 * KPH, _f("2"), _f("3")),
    ActorRow("animal", "animal", "animal", "animal", _f("1.5"), _f("0.6"), _f("1.0"), _f("60"),
             40 * KPH, _f("4"), _f("5")),
    ActorRow("stationary_object", "stationary_object", "stationary_object", "box", _f("1"),
             _f("1"), _f("1"), _f("100"), Fraction(0), Fraction(0), Fraction(0)),
)  # fmt: skip

#: 2.2's names for the 2.1 categories (aliases: the same members, the same rows)
CATEGORY_ALIASES = {"heavy_truck": "truck", "micro_mobility_device": "vru_vehicle"}
#: 2.2 categories that are no road vehicle: the world has no body for them
NOT_ON_ROADS = ("train", "watercraft", "aircraft")
CATEGORIES: dict[str, ActorRow] = {row.key: row for row in _CATEGORY_ROWS}
CATEGORIES.update({alias: CATEGORIES[name] for alias, name in CATEGORY_ALIASES.items()})
MODELS: dict[str, ActorRow] = {row.key: row for row in _MODEL_ROWS}
_KINDS: dict[str, ActorRow] = {row.key: row for row in _KIND_ROWS}

# Words in a model name the catalogue does not know, and the category they suggest.
_MODEL_HINTS = (
    ("hgv", "truck"), ("truck", "truck"), ("lorry", "truck"), ("bus", "bus"),
    ("trailer", "trailer"), ("bike", "vru_vehicle"), ("bicycle", "vru_vehicle"),
    ("scooter", "vru_vehicle"), ("motorcycle", "vru_vehicle"),
)  # fmt: skip
_WALKER_PREFIX = "walker."


#: hitch receivers by construction: reach behind the rear bumper and height (m), a ball
#: coupling on cars and a pintle on trucks and buses (ISO 1103, ISO 8755 heights)
_RECEIVERS = {
    "car": (Fraction(1, 10), Fraction(45, 100)),
    "truck": (Fraction(1, 4), Fraction(9, 10)),
    "bus": (Fraction(1, 4), Fraction(9, 10)),
}


def receiver(row: ActorRow, length: Fraction | None = None) -> Receiver | None:
    """The hitch receiver of a vehicle of ``row`` (``length`` when its box is resized), or
    None for what tows nothing (two-wheelers, trailers, persons, objects)."""
    found = _RECEIVERS.get(row.body) if row.kind == "vehicle" else None
    if found is None:
        return None
    reach, height = found
    return Receiver((row.length if length is None else length) + reach, height)


def category_row(category: str) -> ActorRow:
    """The generic row of a vehicle category (``car`` for a name that is not one)."""
    return CATEGORIES.get(category, CATEGORIES["car"])


def kind_row(kind: str) -> ActorRow:
    """The row of a non-vehicle actor kind (``person``, ``animal``, ``stationary_object``)."""
    return _KINDS[kind]


def model_row(model: str) -> ActorRow | None:
    """The row of a simulator model name: a known model, or the category its words
    suggest (``vehicle.acme.big_hgv`` is a truck); None when nothing is known of it."""
    row = MODELS.get(model)
    if row is not None:
        return row
    if model.startswith(_WALKER_PREFIX):
        return _KINDS["person"]
    lowered = model.lower()
    for hint, category in _MODEL_HINTS:
        if hint in lowered:
            return CATEGORIES[category]
    return None


def row_for(kind: str, category: str | None = None, model: str | None = None) -> ActorRow:
    """The row of an actor of ``kind`` (vehicle, person, ...), its category and model name.

    For a vehicle the model wins over the category, and the category over the
    default ``car``; other kinds have one row each.
    """
    if kind != "vehicle":
        return _KINDS.get(kind, _KINDS["stationary_object"])
    if model is not None:
        found = model_row(model)
        if found is not None and found.kind == "vehicle":
            return found
    return category_row(category or "car")
