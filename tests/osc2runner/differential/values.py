"""Argument values for the library's parameters, by type, as hypothesis strategies.

A value is drawn for a parameter from what the library says of it: a physical
quantity in one of its type's units (the magnitude from :data:`MAGNITUDES`, by
physical type, or from :data:`PLAUSIBLE` where a property needs the value in a
range it can observe), an enum member, a boolean, a number, or a range ``[a..b]``
where a scalar is expected. A new physical type without a magnitude is reported by
``test_generator_covers_the_library``, not skipped.

Every strategy is a function of a ``rotation`` (the cell's index): the choice that
hypothesis tries first (the simplest) differs from cell to cell, so that one example
per cell still spreads over the values.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from hypothesis import strategies as st

from tests.osc2runner.differential.library import Parameter, Unit

__all__ = ["MAGNITUDES", "PLAUSIBLE", "Value", "rotated", "value_of"]

#: SI magnitudes by physical type: values are drawn between the two
MAGNITUDES: dict[str, tuple[float, float]] = {
    "speed": (0.0, 15.0),
    "length": (0.0, 30.0),
    "time": (0.5, 3.0),
    "angle": (-0.5, 0.5),
    "acceleration": (-2.0, 2.0),
    "jerk": (1.0, 10.0),
    "temperature": (263.15, 308.15),
    "pressure": (95000.0, 105000.0),
    "angular_rate": (-0.3, 0.3),
    "angular_acceleration": (-0.3, 0.3),
    "mass": (50.0, 2000.0),
    "illuminance": (0.0, 100000.0),
    "luminous_intensity": (0.0, 1000.0),
}

#: Where the telemetry can show a modifier's effect, narrower magnitudes by
#: (callable, parameter) and, where it matters, the actor kind: SI (low, high)
PLAUSIBLE: dict[tuple[str, str] | tuple[str, str, str], tuple[float, float]] = {
    ("speed", "speed"): (4.0, 14.0),
    ("speed", "speed", "person"): (0.5, 2.5),
    ("speed", "speed", "animal"): (0.5, 2.5),
    ("change_speed", "speed"): (-3.0, 3.0),
    ("change_speed", "speed", "person"): (-0.5, 0.5),
    ("change_speed", "speed", "animal"): (-0.5, 0.5),
    ("acceleration", "acceleration"): (-1.5, 1.5),
    ("acceleration", "acceleration", "person"): (-0.5, 0.5),
    ("acceleration", "acceleration", "animal"): (-0.5, 0.5),
    ("lateral", "distance"): (-1.0, 1.0),
    ("position", "distance"): (5.0, 25.0),
    ("position", "time"): (0.5, 2.0),
    ("distance", "distance"): (2.0, 12.0),
    ("yaw", "angle"): (-0.6, 0.6),
    ("orientation", "yaw"): (-0.6, 0.6),
    ("orientation", "pitch"): (-0.2, 0.2),
    ("orientation", "roll"): (-0.2, 0.2),
    ("assign_speed", "speed"): (2.0, 14.0),
    ("assign_speed", "speed", "person"): (0.5, 2.5),
    ("assign_speed", "speed", "animal"): (0.5, 2.5),
    ("change_speed", "target"): (2.0, 14.0),
    ("change_speed", "target", "person"): (0.5, 2.5),
    ("change_speed", "target", "animal"): (0.5, 2.5),
    ("change_speed", "rate_peak"): (1.0, 3.0),
    ("assign_acceleration", "acceleration"): (-1.5, 1.5),
    ("change_acceleration", "target"): (-1.5, 1.5),
    ("follow_lane", "offset"): (-1.0, 1.0),
    ("change_lane", "offset"): (-0.5, 0.5),
    ("follow_lane", "rate_peak"): (0.5, 1.5),
    ("change_lane", "rate_peak"): (1.0, 2.0),
    ("change_space_gap", "target"): (10.0, 30.0),
    ("change_space_headway", "target"): (10.0, 30.0),
    ("change_time_gap", "target"): (1.0, 3.0),
    ("change_time_headway", "target"): (1.0, 3.0),
    ("along", "start_offset"): (0.0, 5.0),
    ("along", "end_offset"): (0.0, 5.0),
    ("along_trajectory", "start_offset"): (0.0, 5.0),
    ("along_trajectory", "end_offset"): (0.0, 5.0),
}

#: whole numbers where the library asks for one (lane counts), by (callable, parameter)
COUNTS: dict[tuple[str, str], tuple[int, int]] = {
    ("lane", "lane"): (1, 3),
    ("change_lane", "lane"): (1, 2),
    ("change_lane", "num_of_lanes"): (1, 2),
}


@dataclass(frozen=True)
class Value:
    """One argument's value: its OSC2 text and what it means (SI number, a (low, high)
    pair for a range, an enum member or a boolean)."""

    text: str
    value: Any
    range: bool = False


def rotated(items: list[Any] | tuple[Any, ...], rotation: int) -> list[Any]:
    """``items`` starting at ``rotation`` (mod their number): hypothesis tries the first."""
    if not items:
        return []
    k = rotation % len(items)
    return [*items[k:], *items[:k]]


def _number(x: float) -> str:
    text = f"{x:.3f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _units(param: Parameter, low: float, high: float) -> list[Unit]:
    """The parameter's units in which the magnitudes read as ordinary numbers."""
    fitting = []
    for unit in param.units:
        factor = float(unit.factor)
        if unit.offset != 0 or factor <= 0:
            continue
        biggest = max(abs(low), abs(high)) / factor
        if 0.1 <= biggest <= 5000 or (biggest == 0 and factor == 1):
            fitting.append(unit)
    return fitting or ([param.si_unit] if param.si_unit else [])


def _quantity(x: float, unit: Unit) -> str:
    return f"{_number(x / float(unit.factor))}{unit.name}"


def magnitude(callable_name: str, param: Parameter, kind: str) -> tuple[float, float] | None:
    return (
        PLAUSIBLE.get((callable_name, param.name, kind))
        or PLAUSIBLE.get((callable_name, param.name))
        or MAGNITUDES.get(param.type_name)
    )


def value_of(
    callable_name: str, param: Parameter, kind: str, rotation: int, ranged: bool
) -> st.SearchStrategy[Value] | None:
    """A strategy for the value of ``param`` of ``callable_name`` for an actor of ``kind``;
    None when the parameter's type is one the generator does not write (a struct, a map
    element, an actor reference: the case builder gives those). ``ranged``: a range
    ``[a..b]`` (where a scalar is expected), else one value."""
    if param.kind == "physical":
        bounds = magnitude(callable_name, param, kind)
        units = _units(param, *bounds) if bounds is not None else []
        if bounds is None or not units:
            return None
        low, high = bounds
        steps = 40
        grid = [low + (high - low) * i / steps for i in range(steps + 1)]
        return _physical(units, grid, rotation, ranged)
    if param.kind == "enum":
        if not param.members:
            return None
        return st.sampled_from([Value(m, m) for m in rotated(list(param.members), rotation)])
    if param.kind == "bool":
        return st.sampled_from(
            [Value("true" if b else "false", b) for b in rotated([True, False], rotation)]
        )
    if param.kind in ("int", "uint"):
        low, high = COUNTS.get((callable_name, param.name), (0 if param.kind == "uint" else -3, 3))
        numbers = list(range(low, high + 1))
        return _whole(numbers, rotation, ranged)
    if param.kind == "float":
        grid = [0.5 + i * 0.25 for i in range(7)]  # 0.5 .. 2.0
        return st.sampled_from([Value(_number(x), x) for x in rotated(grid, rotation)])
    if param.kind == "string":
        return None
    return None


@st.composite
def _physical(
    draw: Any, units: list[Unit], grid: list[float], rotation: int, ranged: bool
) -> Value:
    unit = draw(st.sampled_from(rotated(units, rotation)))
    a = draw(st.sampled_from(rotated(grid, rotation * 7)))
    if ranged:
        b = draw(st.sampled_from([g for g in grid if g > a] or [a]))
        lo, hi = min(a, b), max(a, b)
        text = f"[{_quantity(lo, unit)}..{_quantity(hi, unit)}]"
        return Value(text, (_exact(lo, unit), _exact(hi, unit)), range=True)
    return Value(_quantity(a, unit), _exact(a, unit))


def _exact(x: float, unit: Unit) -> float:
    """The SI value of ``x`` as written in ``unit`` (the text rounds it)."""
    return float(Fraction(_number(x / float(unit.factor))) * unit.factor)


@st.composite
def _whole(draw: Any, numbers: list[int], rotation: int, ranged: bool) -> Value:
    a = draw(st.sampled_from(rotated(numbers, rotation)))
    if ranged:
        b = draw(st.sampled_from([n for n in numbers if n > a] or [a]))
        return Value(f"[{min(a, b)}..{max(a, b)}]", (min(a, b), max(a, b)), range=True)
    return Value(str(a), a)
