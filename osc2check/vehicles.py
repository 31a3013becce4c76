"""Default footprints and speed limits of actors, by kind and vehicle category.

The checker places actors with these sizes and the runner builds its vehicles
from the same categories. A scenario may name a vehicle model instead of a
category (the design paper writes CARLA blueprint names such as
``vehicle.carlamotors.european_hgv``); ``category_of_model`` maps those.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

KPH = Fraction(5, 18)


@dataclass(frozen=True, slots=True)
class Footprint:
    category: str
    length: Fraction  # m, along the heading
    width: Fraction  # m
    max_speed: Fraction  # m/s


FOOTPRINTS: dict[str, Footprint] = {
    "car": Footprint("car", Fraction(9, 2), Fraction(9, 5), 250 * KPH),
    "truck": Footprint("truck", Fraction(12), Fraction(5, 2), 90 * KPH),
    "bus": Footprint("bus", Fraction(12), Fraction(5, 2), 100 * KPH),
    "trailer": Footprint("trailer", Fraction(10), Fraction(5, 2), 90 * KPH),
    "vru_vehicle": Footprint("vru_vehicle", Fraction(9, 5), Fraction(7, 10), 45 * KPH),
    "other": Footprint("other", Fraction(9, 2), Fraction(9, 5), 250 * KPH),
    "person": Footprint("person", Fraction(3, 5), Fraction(3, 5), 15 * KPH),
    "animal": Footprint("animal", Fraction(3, 2), Fraction(3, 5), 40 * KPH),
    "stationary_object": Footprint("stationary_object", Fraction(1), Fraction(1), Fraction(0)),
}

_MODEL_HINTS = (
    ("hgv", "truck"),
    ("truck", "truck"),
    ("lorry", "truck"),
    ("bus", "bus"),
    ("bike", "vru_vehicle"),
    ("bicycle", "vru_vehicle"),
    ("scooter", "vru_vehicle"),
)


def category_of_model(model: str) -> str | None:
    """The vehicle category a model name suggests (``...european_hgv`` -> truck)."""
    lowered = model.lower()
    for hint, category in _MODEL_HINTS:
        if hint in lowered:
            return category
    return None


def footprint(kind: str, category: str | None = None) -> Footprint:
    """The footprint of an actor kind (vehicle, person, ...) and vehicle category."""
    if kind == "vehicle":
        return FOOTPRINTS.get(category or "car", FOOTPRINTS["car"])
    return FOOTPRINTS.get(kind, FOOTPRINTS["other"])
