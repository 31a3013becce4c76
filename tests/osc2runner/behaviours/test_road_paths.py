"""Paths and trajectories through points of the map, and relative ones (ASAM OpenSCENARIO
DSL 2.1 §8.12.2.1 ``create_path_odr_points``, ``create_path_route_points``,
``create_trajectory_*``, ``resolve_relative_path``; §8.8 ``follow_path(relative:)``
with ``relative_path_st``; ``change_position(target_odr:, on_road_network:)``).

The bundled rural road's 300 m left-hand arc (reference line radius 100 m, s 150 to
450 m) gives the closed forms: the right lane's centre runs on the circle of radius
101.75 m about the arc's centre, and a straight line between two points of it cuts
inside that circle by its sagitta.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from osc2check.world.maps import load_map
from osc2runner import run

RURAL = Path(__file__).resolve().parents[3] / "examples" / "maps" / "rural_curves.xodr"
HEADER = f"""\
import osc.standard

scenario s:
    town: map with:
        keep(it.map_file == "{RURAL}")
    car: vehicle
"""
START = """\
        car.assign_position(odr_point: town.create_odr_point("1", "-1", {s}m, 0m)) with:
            speed(50kph, at: start)
"""


def _run(tmp_path, body: str, start: float | None = None):
    """Run ``body`` (the ``do``, or members then a ``do``); with ``start``, ``body`` is the
    action after the car's placement on road 1's right lane at ``start``."""
    if start is not None:
        body = "    do serial:\n" + START.format(s=start) + body
    source = tmp_path / "s.osc"
    source.write_text(HEADER + body)
    result = run(source)
    assert result.outcome.status == "success", result.outcome.reason
    return result


def _arc():
    """Centre and lane radius of the rural road's arc (from its geometry record)."""
    arc = load_map(str(RURAL)).roads["1"].geometries[2]
    assert arc.kind == "arc" and arc.curvature == pytest.approx(0.01)
    cx = arc.x - math.sin(arc.hdg) / arc.curvature
    cy = arc.y + math.cos(arc.hdg) / arc.curvature
    return cx, cy, 1.0 / arc.curvature + 1.75


def _rows(result, action: str) -> slice:
    start = result.event_ticks("start", f"car.{action}")[0]
    end = result.event_ticks("end", f"car.{action}")[0]
    return slice(start + 1, end + 1)  # the first row: before the start's placement


def _follow(tmp_path, start: float, points: str, kph: float = 50.0):
    """The car follows ``create_path_odr_points(points)`` from road 1's right lane at
    ``start``; its telemetry rows while it does, and its distance from the arc's centre."""
    result = _run(
        tmp_path,
        f"""\
        car.follow_path(town.create_path_odr_points({points})) with:
            speed({kph}kph)
""",
        start,
    )
    car = result.telemetry["car"]
    rows = _rows(result, "follow_path")
    cx, cy, _ = _arc()
    return car, rows, np.hypot(car["x"][rows] - cx, car["y"][rows] - cy)


def test_a_path_through_odr_points_on_the_road_network_follows_the_lane(tmp_path):
    car, rows, r = _follow(
        tmp_path,
        170,
        """[town.create_odr_point("1", "-1", 170m, 0m),
            town.create_odr_point("1", "-1", 330m, 0m)], straight_line, true""",
    )
    radius = _arc()[2]
    assert np.abs(r - radius).max() < 0.1  # on the lane's circle, 160 m of arc
    # it ends when the front axle reaches the last point
    assert car["s"][rows][-1] == pytest.approx(330.0 - 1.2 * 100.0 / 101.75, abs=0.6)


def test_off_the_road_network_the_points_are_joined_by_a_straight_line(tmp_path):
    _, _, r = _follow(
        tmp_path,
        160,
        """[town.create_odr_point("1", "-1", 160m, 0m),
            town.create_odr_point("1", "-1", 190m, 0m)], straight_line, false""",
        kph=30.0,
    )
    radius = _arc()[2]
    half = 0.5 * 30.0 * (radius - 1.75) / 100.0 / radius  # half the chord's angle
    # the chord's middle is radius * cos(half) from the centre: the sagitta inside the lane
    assert r.min() == pytest.approx(radius * math.cos(half), abs=0.1)


def test_a_trajectory_through_route_points_is_on_time(tmp_path):
    result = _run(
        tmp_path,
        """\
        car.follow_trajectory(town.create_trajectory_route_points(
            [town.odr_to_route_point("1", "-1", 170m, 0m),
             town.odr_to_route_point("1", "-1", 420m, 0m)],
            [0s, 18s], straight_line, true))
""",
        170,
    )
    car = result.telemetry["car"]
    start = result.event_ticks("start", "car.follow_trajectory")[0]
    at = start + round(9.0 / 0.05)  # halfway in time: halfway along the arc
    assert car["s"][at] == pytest.approx(295.0, abs=0.5)
    assert result.event_ticks("end", "car.follow_trajectory")[0] - start == 360


def test_a_relative_route_point_path_is_taken_from_the_reference_on_its_road(tmp_path):
    points = """\
    a: route_point with:
        keep(it.s == 10m)
        keep(it.t == 0m)
    b: route_point with:
        keep(it.s == 50m)
        keep(it.t == 3.5m)
    c: route_point with:
        keep(it.s == 120m)
        keep(it.t == 3.5m)
    rp: relative_path_st with:
        keep(it.points == [a, b, c])
        keep(it.interpolation == smooth)
"""
    result = _run(
        tmp_path,
        points
        + "    do serial:\n"
        + START.format(s=150)
        + """\
        car.follow_path(relative: rp, transform: road_relative) with:
            speed(50kph)
""",
    )
    car = result.telemetry["car"]
    rows = _rows(result, "follow_path")
    # from s 150 m, t -1.75 m (the lane's centre): to s 270 m, 3.5 m to the left
    assert car["t"][rows][-1] == pytest.approx(1.75, abs=0.1)
    assert 268.0 < car["s"][rows][-1] < 270.0
    # the same path resolved by the map's method at the same moment
    again = _run(
        tmp_path,
        points
        + "    do serial:\n"
        + START.format(s=150)
        + """\
        car.follow_path(town.resolve_relative_path(rp, car, road_relative)) with:
            speed(50kph)
""",
    )
    assert np.allclose(again.telemetry["car"]["x"], car["x"])


def test_change_position_to_an_odr_point_along_the_road(tmp_path):
    result = _run(
        tmp_path,
        """\
        car.change_position(target_odr: town.create_odr_point("1", "1", 260m, 0m),
            on_road_network: true) with:
            speed(50kph)
""",
        170,
    )
    car = result.telemetry["car"]
    rows = _rows(result, "change_position")
    assert car["t"][rows][-1] == pytest.approx(1.75, abs=0.15)  # the left lane's centre
    assert 257.5 < car["s"][rows][-1] < 260.0


def _straight_centre(length: float = 200.0):
    d = np.linspace(0.0, length, 401)
    return d, d.copy(), np.zeros_like(d), np.zeros_like(d)


def test_a_road_line_offset_changes_as_its_interpolation_says():
    from osc2runner.sim.tracking import RoadLine

    line = RoadLine(_straight_centre(), [0.0, 40.0, 80.0], [0.0, 3.5, 3.5], "straight_line")
    assert line.xy[:, 1][np.searchsorted(line.xy[:, 0], 20.0)] == pytest.approx(1.75)
    diagonal = math.hypot(40.0, 3.5)
    assert list(line.given_s) == pytest.approx([0.0, diagonal, diagonal + 40.0])
    smooth = RoadLine(_straight_centre(), [0.0, 40.0, 80.0], [0.0, 3.5, 3.5], "smooth")
    y = smooth.xy[:, 1]
    assert y.max() > 3.5  # a cubic through the offsets overshoots a little past the middle
    assert np.all(np.abs(np.diff(y)) < 0.1)  # without a corner


def test_a_driven_corner_is_blended_over_the_distance_a_car_turns_in():
    from osc2runner.sim.tracking import CORNER_ACCEL, RoadLine

    line = RoadLine(_straight_centre(), [0.0, 40.0, 80.0], [0.0, 3.5, 3.5], "straight_line")
    v = 50.0 / 3.6
    driven = line.driven([v], least_radius=5.0)
    change = 3.5 / 40.0
    cut = v * v * change * change / (8.0 * CORNER_ACCEL)  # the parabola's cut at the corner
    y = driven.xy[:, 1][np.searchsorted(driven.xy[:, 0], 40.0)]
    assert 3.5 - y == pytest.approx(cut, rel=0.02)


def test_a_relative_odr_trajectory_in_the_lane_frame_keeps_its_lane_and_its_times(tmp_path):
    """§8.8 ``follow_trajectory(relative:, transform: lane_relative)`` with
    ``relative_trajectory_odr``: ``s`` along the reference's lane from where it is, ``t``
    from its lane's centre (docs/runner.md); 120 m in 9 s from s 170 m, on the arc."""
    result = _run(
        tmp_path,
        """\
    a: odr_point with:
        keep(it.road_id == "7")
        keep(it.lane_id == "7")
        keep(it.s == 0m)
        keep(it.t == 0m)
    b: odr_point with:
        keep(it.road_id == "7")
        keep(it.lane_id == "7")
        keep(it.s == 120m)
        keep(it.t == 0m)
    rt: relative_trajectory_odr with:
        keep(it.points == [a, b])
        keep(it.time_stamps == [0s, 9s])
        keep(it.interpolation == straight_line)
    do serial:
"""
        + START.format(s=170)
        + """\
        car.follow_trajectory(relative: rt, reference: car, transform: lane_relative)
""",
    )
    car = result.telemetry["car"]
    rows = _rows(result, "follow_trajectory")
    cx, cy, radius = _arc()
    r = np.hypot(car["x"][rows] - cx, car["y"][rows] - cy)
    assert np.abs(r - radius).max() < 0.1  # the lane's circle: along the lane, not a chord
    start = result.event_ticks("start", "car.follow_trajectory")[0]
    assert car["s"][start + round(4.5 / 0.05)] == pytest.approx(230.0, abs=0.5)
    assert result.event_ticks("end", "car.follow_trajectory")[0] - start == 180
