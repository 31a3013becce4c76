"""What a map may cost: the sizes and shapes a road can have, and the samples a map gets.

A map is sampled densely (``layout``): every metre, and closer where the road bends,
so that chords stay within 0.1 mm of the curve. Left alone, a 600-byte file could ask
for anything: an arc of curvature 1e6 (a road coiled 160,000 times a metre), a road
10,000 km long, a lane a thousand kilometres wide, cubic coefficients of 1e300 whose
curve leaves the planet, each sampled to gigabytes of memory or to values that are
not numbers. So each record is held to what a road can be, and the samples of a
whole map to a budget; beyond either the map is refused with a ``MapError`` that
names the file, the element's line and the limit (the checker's L516), and every
other file is still checked.

The limits (far beyond the maps in use: their tightest curve has a radius of 6 m,
their longest road is 1.5 km, their widest road 48 m):

* ``MAX_MAP_BYTES``: 64 MiB of XML; ``MAX_MAP_ELEMENTS``: two million elements.
* ``MAX_ROAD_LENGTH``: a road or a geometry record is at most 100 km long.
* ``MAX_COORDINATE``: every point lies within 100,000 km of the origin (projected
  coordinates of any place on Earth do).
* ``MAX_CURVATURE``: 10 per metre (a radius of 10 cm): no road bends more sharply.
* ``MAX_LATERAL``: a lane border lies at most 500 m beside the reference line.
* ``MAX_ELEVATION``: the road surface lies within 20 km of height zero.
* ``MIN_STEP``: samples are at least 1 cm apart, however sharp the bend.
* ``MAX_SAMPLES``: a million reference-line samples a map (1,000 km of road at one a
  metre), and ``MAX_BORDER_VALUES``, six million lane-border values (samples times
  lane borders: 1,000 km of a five-lane road): the memory a map takes follows its
  real extent, up to these.
* ``MAX_ROAD_AREA``: five square kilometres of road surface a map (its lanes and the
  margin beside them that still gets road coordinates: 200 km of a five-lane road),
  which the runner's grid of the road covers, cell by cell.

With these a map takes at most about a gigabyte and a minute to check and to run
(``bench/bench_limits.py`` prints the worst).
"""

from __future__ import annotations

import math

import numpy as np

from osc2check.world.arrays import FloatArray
from osc2check.world.errors import MapError

__all__ = [
    "MAX_BORDER_VALUES",
    "MAX_COORDINATE",
    "MAX_CURVATURE",
    "MAX_ELEVATION",
    "MAX_LATERAL",
    "MAX_MAP_BYTES",
    "MAX_MAP_ELEMENTS",
    "MAX_ROAD_AREA",
    "MAX_ROAD_LENGTH",
    "MAX_SAMPLES",
    "MIN_STEP",
    "SampleBudget",
    "beyond",
]

MAX_MAP_BYTES = 64 * 1024 * 1024
MAX_MAP_ELEMENTS = 2_000_000
MAX_ROAD_LENGTH = 100_000.0  # m
MAX_COORDINATE = 1e8  # m
MAX_CURVATURE = 10.0  # 1/m
MAX_LATERAL = 500.0  # m
MAX_ELEVATION = 20_000.0  # m
MIN_STEP = 0.01  # m
MAX_SAMPLES = 1_000_000
MAX_BORDER_VALUES = 6_000_000
MAX_ROAD_AREA = 5e6  # m²


class SampleBudget:
    """The samples a map has left; ``take`` raises once they run out."""

    def __init__(self, source: str | None) -> None:
        self.source = source
        self.samples = MAX_SAMPLES
        self.border_values = MAX_BORDER_VALUES
        self.area = MAX_ROAD_AREA

    def take(self, samples: int, rows: int, what: str, line: int | None) -> None:
        """Spend ``samples`` reference-line samples with ``rows`` lane borders each."""
        self.samples -= samples
        self.border_values -= samples * rows
        if self.samples < 0:
            raise MapError(
                f"{what}: the map needs more than {MAX_SAMPLES:,} samples (one a metre, more "
                "on curves): its roads are too long or bend too much to be read",
                self.source,
                line,
            )
        if self.border_values < 0:
            raise MapError(
                f"{what}: the map needs more than {MAX_BORDER_VALUES:,} lane-border values "
                "(samples times lane borders): it has too many lanes over too much road",
                self.source,
                line,
            )

    def take_area(self, area: float, what: str, line: int | None) -> None:
        """Spend ``area`` square metres of road surface."""
        self.area -= area
        if not self.area >= 0:
            raise MapError(
                f"{what}: the map has more than {MAX_ROAD_AREA / 1e6:g} km² of road surface "
                "(its lanes and the margin beside them): it is too large to be read",
                self.source,
                line,
            )


def beyond(values: FloatArray | float, limit: float) -> float | None:
    """The value of ``values`` furthest beyond ``[-limit, limit]`` (or not a number),
    or None when every one is within."""
    array = np.asarray(values, dtype=np.float64)
    if array.size == 0:
        return None
    bad = ~np.isfinite(array) | (np.abs(array) > limit)
    if not bad.any():
        return None
    worst = array[bad]
    finite = worst[np.isfinite(worst)]
    return (
        float(worst[~np.isfinite(worst)][0])
        if finite.size < worst.size
        else float(finite[np.argmax(np.abs(finite))])
    )


def number_text(value: float) -> str:
    """``1e+300``, ``inf`` or ``nan`` as a message shows a value."""
    return "not a number" if math.isnan(value) else f"{value:g}"
