"""Running the checker's witness: parameter values and start poses from ``osc2check.solve``."""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2runner import run

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def witnessed():
    return run(ROOT / "examples" / "braking_friction.osc", seed=0, duration=20.0)


def test_witness_values_are_used(witnessed):
    values = witnessed.metadata["parameter_values"]
    assert values["source"] == "witness (seed 0)"
    assert values["values"]["test_speed"]["si"] == pytest.approx(80 / 3.6)


def test_witness_start_pose_is_realised(witnessed):
    start = witnessed.metadata["actors"]["hero"]["start"]
    hero = witnessed.telemetry["hero"]
    assert hero["x"][0] == pytest.approx(start["s"])
    assert hero["lane"][0] == 1.0 and hero["speed"][0] == 0.0
