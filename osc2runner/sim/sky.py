"""The sky: where the sun and the moon are (ASAM OpenSCENARIO DSL 2.1 §8.10, the
``environment`` actor's ``sun`` and ``moon``, and §8.11 ``assign_celestial_position``).

The standard: when the environment's ``geodetic_position`` and ``datetime`` (Unix time
at the scenario's start) are given, sun and moon move by a model; otherwise
``assign_celestial_position`` puts them. Here:

* with both given, a light source's position is computed for the moment
  ``datetime + t`` (``t`` the simulated time) by the low-precision formulas of the
  Astronomical Almanac: the sun within about 0.01 degree, the moon within about 0.3
  degree (its parallax included); geometric positions, without refraction;
* ``assign_celestial_position`` puts a light source at its azimuth and elevation at
  once (**choice**: it stays there, the model no longer moves it; an angle not given
  keeps its value);
* a position nothing gives (no model, no assignment) has no value: reading it is a run
  fault that says so.

Positions are ``celestial_position_2d``: azimuth clockwise from North, elevation above
the horizon, in radians.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from osc2runner.structs import CelestialPosition2d

__all__ = ["LightSource", "Sky", "moon_position", "sun_position"]

#: Julian date of the Unix epoch, and of J2000.0
_JD_UNIX = 2440587.5
_J2000 = 2451545.0


def _days_since_j2000(unix_time: float) -> float:
    return unix_time / 86400.0 + _JD_UNIX - _J2000


def _sun_ecliptic(n: float) -> tuple[float, float, float]:
    """The sun's ecliptic longitude, latitude (0) and the obliquity, degrees, ``n`` days
    after J2000.0."""
    mean_longitude = 280.460 + 0.9856474 * n
    anomaly = math.radians(357.528 + 0.9856003 * n)
    longitude = mean_longitude + 1.915 * math.sin(anomaly) + 0.020 * math.sin(2.0 * anomaly)
    return longitude % 360.0, 0.0, 23.439 - 0.0000004 * n


def _moon_ecliptic(n: float) -> tuple[float, float, float]:
    """The moon's geocentric ecliptic longitude, latitude and horizontal parallax,
    degrees, ``n`` days after J2000.0."""
    t = n / 36525.0

    def s(a: float, b: float) -> float:
        return math.sin(math.radians(a + b * t))

    def c(a: float, b: float) -> float:
        return math.cos(math.radians(a + b * t))

    longitude = (
        218.32
        + 481267.881 * t
        + 6.29 * s(135.0, 477198.87)
        - 1.27 * s(259.3, -413335.36)
        + 0.66 * s(235.7, 890534.22)
        + 0.21 * s(269.9, 954397.74)
        - 0.19 * s(357.5, 35999.05)
        - 0.11 * s(186.5, 966404.03)
    )
    latitude = (
        5.13 * s(93.3, 483202.02)
        + 0.28 * s(228.2, 960400.89)
        - 0.28 * s(318.3, 6003.15)
        - 0.17 * s(217.6, -407332.21)
    )
    parallax = (
        0.9508
        + 0.0518 * c(135.0, 477198.87)
        + 0.0095 * c(259.3, -413335.36)
        + 0.0078 * c(235.7, 890534.22)
        + 0.0028 * c(269.9, 954397.74)
    )
    return longitude % 360.0, latitude, parallax


def _horizontal(
    longitude: float, latitude: float, n: float, site_latitude: float, site_longitude: float
) -> tuple[float, float]:
    """Azimuth (clockwise from North) and elevation, radians, of a body at ecliptic
    ``longitude``/``latitude`` (degrees) seen from the site (radians) ``n`` days after
    J2000.0."""
    obliquity = math.radians(23.439 - 0.0000004 * n)
    lam, beta = math.radians(longitude), math.radians(latitude)
    x = math.cos(beta) * math.cos(lam)
    y = math.cos(obliquity) * math.cos(beta) * math.sin(lam) - math.sin(obliquity) * math.sin(beta)
    z = math.sin(obliquity) * math.cos(beta) * math.sin(lam) + math.cos(obliquity) * math.sin(beta)
    right_ascension = math.atan2(y, x)
    declination = math.asin(max(-1.0, min(1.0, z)))
    sidereal = math.radians((280.46061837 + 360.98564736629 * n) % 360.0)
    hour = sidereal + site_longitude - right_ascension
    phi = site_latitude
    sin_elevation = math.sin(phi) * math.sin(declination) + math.cos(phi) * math.cos(
        declination
    ) * math.cos(hour)
    elevation = math.asin(max(-1.0, min(1.0, sin_elevation)))
    azimuth = math.atan2(
        -math.cos(declination) * math.sin(hour),
        math.sin(declination) * math.cos(phi)
        - math.cos(declination) * math.cos(hour) * math.sin(phi),
    )
    return azimuth % (2.0 * math.pi), elevation


def sun_position(unix_time: float, latitude: float, longitude: float) -> tuple[float, float]:
    """The sun's azimuth and elevation (radians) at ``unix_time`` seen from ``latitude``,
    ``longitude`` (radians, north and east positive)."""
    n = _days_since_j2000(unix_time)
    lam, beta, _ = _sun_ecliptic(n)
    return _horizontal(lam, beta, n, latitude, longitude)


def moon_position(unix_time: float, latitude: float, longitude: float) -> tuple[float, float]:
    """The moon's azimuth and elevation (radians, topocentric: its parallax lowers it)."""
    n = _days_since_j2000(unix_time)
    lam, beta, parallax = _moon_ecliptic(n)
    azimuth, elevation = _horizontal(lam, beta, n, latitude, longitude)
    return azimuth, elevation - math.radians(parallax) * math.cos(elevation)


@dataclass(frozen=True, slots=True)
class LightSource:
    """``env.sun`` or ``env.moon``: reading ``position`` asks the sky where it is now; a
    position nothing gives raises ``fault(why)`` (a run fault at the reading, by default
    a LookupError)."""

    name: str  # "sun" or "moon"
    sky: Sky
    fault: Callable[[str], Exception] = LookupError

    @property
    def position(self) -> CelestialPosition2d:
        try:
            azimuth, elevation = self.sky.position(self.name)
        except LookupError as exc:
            raise self.fault(str(exc)) from None
        return CelestialPosition2d(azimuth, elevation)

    def __str__(self) -> str:
        return self.name


class Sky:
    """Where the sun and the moon are (see the module docstring), and the world's clock.
    ``site`` is the environment's ``(latitude, longitude)`` when both are given, ``start``
    its ``datetime`` at the scenario's start (Unix seconds), ``dated`` whether a constraint
    gives it; ``clock`` the simulated time since the start."""

    def __init__(
        self,
        site: tuple[float, float] | None = None,
        start: float | None = None,
        clock: Callable[[], float] = lambda: 0.0,
    ) -> None:
        self.site = site
        self.start = 0.0 if start is None else start
        self.dated = start is not None
        self.clock = clock
        self._assigned: dict[str, list[float | None]] = {}

    def now(self) -> float:
        """``env.datetime`` now: the start datetime (0 s, the Unix epoch, when nothing
        gives it) plus the simulated time."""
        return self.start + self.clock()

    def assign(self, name: str, azimuth: float | None, elevation: float | None) -> None:
        """``assign_celestial_position``: put ``name`` there; an angle not given keeps the
        value it has now (none, without a model)."""
        try:
            now: list[float | None] = list(self.position(name))
        except LookupError:
            now = list(self._assigned.get(name, [None, None]))
        if azimuth is not None:
            now[0] = azimuth % (2.0 * math.pi)
        if elevation is not None:
            now[1] = elevation
        self._assigned[name] = now

    def position(self, name: str) -> tuple[float, float]:
        """``(azimuth, elevation)`` of ``name`` now; LookupError when nothing gives it."""
        assigned = self._assigned.get(name)
        if assigned is not None:
            azimuth, elevation = assigned
            if azimuth is None or elevation is None:
                missing = "azimuth" if azimuth is None else "elevation"
                raise LookupError(f"the {name}'s {missing} was never assigned")
            return azimuth, elevation
        if self.site is None or not self.dated:
            raise LookupError(
                f"the {name} has no position: give the environment's geodetic_position and "
                f"datetime, or assign it with assign_celestial_position"
            )
        latitude, longitude = self.site
        model = sun_position if name == "sun" else moon_position
        return model(self.now(), latitude, longitude)
