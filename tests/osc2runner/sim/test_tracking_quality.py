"""Tracking quality (issue 20, item 6): lateral error under 0.2 m at up to 50 kph.

The scenes are ``bench/bench_tracking.py``'s (which prints the figures): paths given
by world poses on the built-in road, lane changes, and paths through OpenDRIVE
points along a lane of every bundled and shared map (the shared ones skipped when
``../shared/conformance/opendrive`` is absent), each error measured against the path
the scenario gives, in closed form. A ``straight_line`` path's corner cannot be
driven exactly: the runner drives it on the arc tangent to both lines at
``CORNER_ACCEL`` (radius ``v^2 / a``), which cuts the corner by
``R (1 - cos(theta / 2))``, the closed form the tests compare with.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from osc2runner import run
from osc2runner.sim.tracking import CORNER_ACCEL, Polyline, round_corners

ROOT = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(ROOT / "bench"))
import bench_tracking as bench  # noqa: E402

KINKED = bench.KINKED
#: the scenes held to 0.2 m here (the bench has both interpolations of every road path)
SCENES = [
    scene
    for scene in bench.scenes()
    if "smooth" not in scene.name or scene.name.startswith("path smooth 50")
]


def test_a_rounded_corner_cuts_the_corner_by_the_closed_form():
    theta = math.atan2(7.0, 40.0)
    radius = 30.0
    line = round_corners(np.array(KINKED[:3]), [radius])
    worst = Polyline(KINKED[:3]).distances(line[:, 0], line[:, 1]).max()
    assert worst == pytest.approx(radius * (1.0 - math.cos(theta / 2.0)), rel=1e-3)
    # the arc is tangent to both lines R tan(theta / 2) from the corner
    tangent = radius * math.tan(theta / 2.0)
    assert any(abs(x - (70.0 - tangent)) < 1e-6 and abs(y - 1.75) < 1e-9 for x, y in line)


def test_short_lines_take_at_most_half_of_each_line():
    line = round_corners(np.array([(0.0, 0.0), (4.0, 0.0), (4.0, 4.0)]), [100.0])
    # a quarter circle of radius 2 m: tangent 2 m from the corner on each line
    radii = np.hypot(line[:, 0] - 2.0, line[:, 1] - 2.0)
    inner = line[(line[:, 0] > 2.0 + 1e-9) & (line[:, 1] < 2.0 - 1e-9)]
    assert np.allclose(np.hypot(inner[:, 0] - 2.0, inner[:, 1] - 2.0), 2.0)
    assert radii.min() == pytest.approx(2.0)


@pytest.mark.parametrize("scene", SCENES, ids=lambda s: s.name)
def test_the_lateral_error_stays_under_0_2_m(tmp_path, scene):
    if scene.needs is not None and not scene.needs.exists():
        pytest.skip(f"{scene.needs} is absent")
    source = tmp_path / "s.osc"
    source.write_text(scene.source())
    result = run(source)
    assert result.outcome.status == "success", result.outcome.reason
    error, _ = scene.measure(result)
    assert error < 0.2


@pytest.mark.parametrize("kph", [30.0, 50.0])
def test_a_straight_line_path_cuts_its_corners_no_more_than_the_arc(tmp_path, kph):
    source = tmp_path / "s.osc"
    source.write_text(bench.path_scene(KINKED, "straight_line", kph))
    result = run(source)
    error, _ = bench.path_error(KINKED, "straight_line")(result)
    arc = bench.corner_floor(KINKED, kph, CORNER_ACCEL)
    assert arc == pytest.approx(
        (kph / 3.6) ** 2 / CORNER_ACCEL * (1.0 - math.cos(math.atan2(7.0, 40.0) / 2.0))
    )
    assert error < arc + 0.05  # the arc's cut plus a few cm of tracking
