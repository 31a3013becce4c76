"""Telemetry: the 1 s jerk filter, the channels, and the files."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from osc2runner.output.telemetry import CHANNELS, Recorder


def _state(accel: float) -> SimpleNamespace:
    return SimpleNamespace(
        x=0.0,
        y=0.0,
        yaw=0.0,
        speed=0.0,
        accel=accel,
        throttle=0.0,
        brake=0.0,
        steer=0.0,
        lane=1,
        friction=1.0,
        road="0",
        lane_id=-2,
        s=12.5,
        t=-5.25,
        articulation=float("nan"),
    )


def test_jerk_is_the_acceleration_change_over_the_last_second():
    rec = Recorder(["a"], dt=0.05)
    accel = [0.0] * 5 + [2.0] * 40  # a 2 m/s² step at tick 5
    for k, a in enumerate(accel):
        rec.record({"a": _state(a)}, k, k * 0.05)
    jerk = rec.arrays()["a"]["jerk"]
    assert jerk[4] == 0.0
    assert jerk[5] == pytest.approx(8.0)  # the first second: the window is the time so far
    assert jerk[20:25] == pytest.approx([2.0] * 5)  # 1 s window: (2 - 0) / 1 s
    assert np.all(jerk[25:] == 0.0)  # the step has left the window


def test_channels_and_missing_lane():
    rec = Recorder(["a"], dt=0.05)
    state = _state(0.0)
    state.lane = None
    rec.record({"a": state}, 0, 0.0)
    arrays = rec.arrays()["a"]
    assert tuple(arrays) == CHANNELS
    assert np.isnan(arrays["lane"][0]) and np.isnan(arrays["lateral_error"][0])
    assert arrays["tick"].dtype == np.int64
    assert (arrays["road"][0], arrays["lane_id"][0], arrays["s"][0]) == ("0", -2, 12.5)
