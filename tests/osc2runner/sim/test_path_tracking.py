"""Polyline projection: the stretch a follower is on, not whichever part of the path is nearest."""

from __future__ import annotations

import math

import numpy as np
import pytest

from osc2runner.sim.tracking import PathTracker, Polyline
from osc2runner.sim.vehicle import sedan

# out east, up, back west, then south across the first leg at (25, 0)
CROSSING = [(0.0, 0.0), (50.0, 0.0), (50.0, 20.0), (25.0, 20.0), (25.0, -20.0)]


def _brute(path: Polyline, x: float, y: float) -> tuple[float, float, float]:
    """The global nearest point, as the projection used to find it."""
    fresh = Polyline(path.given, path.interpolation)
    fresh._last = None  # no last projection: the whole path is searched
    return fresh.project(x, y)


@pytest.mark.parametrize("interpolation", ["straight_line", "smooth"])
def test_a_follower_keeps_to_its_stretch_where_the_path_crosses_itself(
    interpolation, project=Polyline.project
):
    path = Polyline(CROSSING, interpolation)
    along = np.arange(0.0, path.length, 0.2)
    done = []
    for s in along.tolist():
        x, y, heading = path.at(s)
        # 0.6 m right of the path: on the last leg that is 0.4 m from the first one
        px, py = x + 0.6 * math.sin(heading), y - 0.6 * math.cos(heading)
        got_s, error, _ = project(path, px, py)
        assert got_s == pytest.approx(s, abs=0.35), (s, got_s)
        assert error == pytest.approx(-0.6, abs=0.05) or abs(got_s - s) < 0.35
        done.append(got_s)
    assert all(b >= a - 1e-9 for a, b in zip(done, done[1:], strict=False))
    # the old global search jumps back to the first leg there
    if interpolation == "straight_line":
        assert _brute(path, 24.4, 0.5)[0] < 30.0


def test_a_jump_is_found_over_the_whole_path():
    path = Polyline([(0.0, 0.0), (100.0, 0.0), (100.0, 100.0)], "smooth")
    assert path.project(1.0, 0.5)[0] == pytest.approx(1.0, abs=0.05)
    far = path.project(99.5, 80.0)  # many segments from the last projection
    assert far == _brute(path, 99.5, 80.0)
    x, y, _ = path.at(far[0])
    assert math.hypot(x - 99.5, y - 80.0) == pytest.approx(abs(far[1]))
    assert y == pytest.approx(80.0, abs=0.5)


def test_projections_along_a_path_that_does_not_cross_itself_are_the_global_ones():
    rng = np.random.default_rng(3)
    points = [(float(x), float(10.0 * math.sin(x / 15.0))) for x in np.arange(0.0, 300.0, 12.0)]
    path = Polyline(points, "smooth")
    brute = Polyline(points, "smooth")
    for s in np.arange(0.0, path.length, 0.7).tolist():
        x, y, _ = path.at(s)
        x, y = x + float(rng.normal(0.0, 1.0)), y + float(rng.normal(0.0, 1.0))
        brute._last = None  # a fresh global search each time
        assert path.project(x, y) == brute.project(x, y)


def test_the_tracker_projects_once_per_pose():
    path = Polyline([(0.0, 0.0), (200.0, 0.0)])
    tracker = PathTracker(sedan(), path)
    calls = 0
    nearest = path._nearest

    def counting(*args):
        nonlocal calls
        calls += 1
        return nearest(*args)

    path._nearest = counting
    assert not tracker.done(10.0, 0.3, 0.0)
    tracker.step(10.0, 0.3, 0.0, 5.0)
    assert calls == 1
    assert tracker.s == pytest.approx(10.0 + sedan().front_axle_x)
    tracker.step(10.5, 0.3, 0.0, 5.0)
    assert calls == 2
