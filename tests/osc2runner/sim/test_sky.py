"""The sun and the moon (ASAM OpenSCENARIO DSL 2.1 §8.10: with the environment's
``geodetic_position`` and ``datetime`` they move by a model; §8.11
``assign_celestial_position`` puts one on the sky), checked against closed forms:
the sun at the June solstice culminates ``90 - latitude + obliquity`` high due south,
rises due east at the equator at an equinox, and the moon is full opposite the sun.
"""

from __future__ import annotations

import calendar
import math

import pytest

from osc2runner import run
from osc2runner.sim.sky import Sky, moon_position, sun_position

SOLSTICE = calendar.timegm((2024, 6, 21, 0, 0, 0))  # the solstice was 2024-06-20 20:51 UTC
EQUINOX = calendar.timegm((2024, 3, 20, 0, 0, 0))  # the equinox was 2024-03-20 03:06 UTC
OBLIQUITY = 23.4393  # degrees, J2000.0 (the solstice's declination)


def _over_the_day(start: int, position, latitude: float, longitude: float = 0.0):
    return [
        (start + 60 * k, *position(start + 60 * k, math.radians(latitude), longitude))
        for k in range(1440)
    ]


def test_the_sun_culminates_due_south_at_the_solstice():
    when, azimuth, elevation = max(
        _over_the_day(SOLSTICE, sun_position, 48.0), key=lambda row: row[2]
    )
    assert math.degrees(elevation) == pytest.approx(90.0 - 48.0 + OBLIQUITY, abs=0.03)
    assert math.degrees(azimuth) == pytest.approx(180.0, abs=0.5)
    # on the Greenwich meridian, at 12:02 UTC (the equation of time is -1.8 min)
    assert (when - SOLSTICE) / 3600.0 == pytest.approx(12.03, abs=0.02)


def test_the_sun_rises_due_east_on_the_equator_at_the_equinox():
    rows = _over_the_day(EQUINOX, sun_position, 0.0)
    rising = next(r for a, r in zip(rows, rows[1:], strict=False) if a[2] < 0.0 <= r[2])
    assert math.degrees(rising[1]) == pytest.approx(90.0, abs=0.5)


def test_the_full_moon_stands_opposite_the_sun():
    full = calendar.timegm((2024, 6, 22, 1, 8, 0))  # the full moon of June 2024
    for latitude in (-30.0, 0.0, 48.0):
        sun = sun_position(full, math.radians(latitude), 0.0)
        moon = moon_position(full, math.radians(latitude), 0.0)
        (a1, e1), (a2, e2) = sun, moon
        cos_gap = math.sin(e1) * math.sin(e2) + math.cos(e1) * math.cos(e2) * math.cos(a1 - a2)
        # opposite on the sky: 180 degrees apart, less the moon's latitude (up to 5.3
        # degrees at this full moon) and its parallax (up to 1 degree)
        assert math.degrees(math.acos(cos_gap)) > 180.0 - 6.5


def test_an_assigned_position_stays_and_an_angle_not_given_keeps_its_value():
    sky = Sky((math.radians(48.0), 0.0), float(SOLSTICE), clock=lambda: 43200.0)
    sky.assign("sun", math.radians(120.0), None)
    azimuth, elevation = sky.position("sun")
    assert math.degrees(azimuth) == pytest.approx(120.0)
    assert elevation == pytest.approx(sun_position(SOLSTICE + 43200, math.radians(48.0), 0.0)[1])
    with pytest.raises(LookupError, match="never assigned"):
        empty = Sky()
        empty.assign("moon", None, 0.1)
        empty.position("moon")


SCENARIO = """\
import osc.standard

scenario s:
    env: environment with:
        keep(it.datetime == {datetime}s)
        keep(it.geodetic_position.latitude == 48deg)
        keep(it.geodetic_position.longitude == 0deg)
    car: vehicle
    event go
    record(sun, expression: env.sun.position.elevation, unit: deg, event: go)
    record(moon, expression: env.moon.position.azimuth, unit: deg, event: go)
    record(when, expression: env.datetime, unit: s, event: go)
    do serial:
        car.drive(duration: 2s)
        emit go
        env.assign_celestial_position(light_source: env.sun, azimuth: 120deg, elevation: 30deg)
        car.drive(duration: 5s) with:
            until env.sun.position.elevation < 31deg and env.sun.position.azimuth > 119deg
"""


def _samples(result, name: str) -> list[float]:
    item = next(i for i in result.coverage.items if i.name == name)
    return [s.value for s in item.samples]


def test_the_scenario_reads_the_sun_the_moon_and_the_date(tmp_path):
    noon = SOLSTICE + 12 * 3600
    source = tmp_path / "s.osc"
    source.write_text(SCENARIO.format(datetime=noon))
    result = run(source)
    assert result.outcome.status == "success", result.outcome.reason
    go = result.event_ticks("emit", "go")[0]
    seconds = go * 0.05  # the model's moment: datetime plus the simulated time
    lat = math.radians(48.0)
    assert _samples(result, "sun") == [
        pytest.approx(math.degrees(sun_position(noon + seconds, lat, 0.0)[1]), abs=1e-6)
    ]
    assert _samples(result, "moon") == [
        pytest.approx(math.degrees(moon_position(noon + seconds, lat, 0.0)[0]), abs=1e-6)
    ]
    assert _samples(result, "when") == [pytest.approx(noon + seconds)]  # it runs on
    # the assigned position holds at once: the until ends the drive in its first tick
    assigned = result.event_ticks("end", "env.assign_celestial_position")[0]
    assert result.event_ticks("end", "car.drive")[-1] == assigned


def test_a_sun_nothing_places_is_a_run_fault_at_the_reading(tmp_path):
    source = tmp_path / "s.osc"
    source.write_text(
        "import osc.standard\n\nscenario s:\n    env: environment\n    car: vehicle\n"
        "    do car.drive(duration: 1s) with:\n"
        "        until env.sun.position.elevation > 20deg\n"
    )
    result = run(source)
    assert result.outcome.status == "failure"
    assert result.outcome.reason.startswith(f"{source}:7:15: the sun has no position")
