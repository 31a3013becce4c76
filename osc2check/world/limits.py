"""The physical inputs the world takes: one definition for the checker and the runner.

* A road friction coefficient (``environment.set_road_friction(value)``) lies in
  ``FRICTION_RANGE``, (0, 2]: no grip at all, or more than twice a dry road's,
  is outside what the tire model was made for.
* A rain intensity (``environment.rain(intensity)``, a volumetric flux) is finite
  and not negative.

The checker adds each as a constraint on the action's argument (so a constant
outside the range is a conflict at the argument, and a parameter passed there is
chosen inside it); the runner refuses a constant outside it before a run and
fails the phase when a value known only at run time is outside it.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from fractions import Fraction

__all__ = [
    "ARGUMENT_LIMITS",
    "FRICTION_RANGE",
    "ArgumentLimit",
    "friction_problem",
    "mps_to_mmph",
    "rain_problem",
]

#: road friction coefficients the world takes: above the first, at most the second
FRICTION_RANGE = (Fraction(0), Fraction(2))


def mps_to_mmph(value: float) -> float:
    """A volumetric flux in m/s, in the library's `mmph` (the standard's factor, so a
    scenario's `5mmph` reads back as 5)."""
    return value / _mmph_factor()


@functools.cache
def _mmph_factor() -> float:
    from osc2check.semantics.stdlib import standard_library

    unit = standard_library().model.unit("mmph")
    assert unit is not None and unit.factor is not None, "the library declares mmph"
    return float(unit.factor)


@dataclass(frozen=True, slots=True)
class ArgumentLimit:
    """The values an action's argument may take: above ``low`` (or at it, unless
    ``low_open``) and at most ``high`` when given; ``text`` says so."""

    low: Fraction
    low_open: bool
    high: Fraction | None
    text: str


#: (action's qualified name, parameter) -> its limit
ARGUMENT_LIMITS: dict[tuple[str, str], ArgumentLimit] = {
    ("environment.set_road_friction", "value"): ArgumentLimit(
        FRICTION_RANGE[0],
        True,
        FRICTION_RANGE[1],
        f"road friction is in ({FRICTION_RANGE[0]}, {FRICTION_RANGE[1]}]",
    ),
    ("environment.rain", "intensity"): ArgumentLimit(
        Fraction(0), False, None, "a rain intensity is not negative"
    ),
}


def friction_problem(value: object) -> str | None:
    """Why ``value`` is not a road friction coefficient (None when it is one)."""
    low, high = FRICTION_RANGE
    if isinstance(value, (int, float)) and math.isfinite(value) and low < value <= high:
        return None
    return f"road friction must be in ({low}, {high}], got {_number(value)}"


def rain_problem(value: object) -> str | None:
    """Why ``value`` (m/s) is not a rain intensity (None when it is one)."""
    if isinstance(value, (int, float)) and math.isfinite(value) and value >= 0.0:
        return None
    given = f"{mps_to_mmph(value):.6g} mm/h" if isinstance(value, (int, float)) else repr(value)
    return f"rain intensity must be finite and not negative, got {given}"


def _number(value: object) -> str:
    return f"{value:.6g}" if isinstance(value, (int, float)) else repr(value)
