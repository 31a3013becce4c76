"""The event detector's plain-Python path (few actors) agrees with its numpy path."""

from __future__ import annotations

import numpy as np

from osc2runner.sim.events import EventDetector


def test_small_and_vector_paths_report_the_same_events():
    rng = np.random.default_rng(3)
    names = ["a", "b", "c", "d"]
    half = np.array([[2.25, 0.9], [6.0, 1.25], [2.25, 0.9], [0.5, 0.5]])
    static = np.array([False, False, False, True])
    small = EventDetector(names, half, static)
    vector = EventDetector(names, half, static)
    vector._small = False
    assert small._small
    seen = 0
    for tick in range(400):
        centre = rng.uniform([-5.0, -2.0], [105.0, 12.5], size=(4, 2))
        centre[:3] = centre[3] + rng.normal(0.0, 6.0, size=(3, 2))  # crowd around the box
        yaw = rng.uniform(-0.5, 0.5, size=4)
        # off the road: outside a 100 m x 10.5 m box (the world asks the map instead)
        off = [not (0.0 <= x <= 100.0 and 0.0 <= y <= 10.5) for x, y in centre[:3]]
        a = small.detect(tick, 0.05 * tick, centre, yaw, off)
        b = vector.detect(tick, 0.05 * tick, centre, yaw, off)
        assert a == b
        seen += len(a)
    assert seen > 50
