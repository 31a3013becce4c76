"""Braking physics through the runner: ``examples/braking_friction.osc`` (sedan from 80 kph).

One run (module fixture) with three stops: dry ``asap``, dry ``smooth``,
friction 0.4 ``asap``. A stop starts at the tick its ``change_speed`` starts
and ends at standstill. Decelerations are the telemetry's 50 ms windows.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from osc2runner import run
from osc2runner.runner import RunResult

ROOT = Path(__file__).resolve().parents[3]
G = 9.81
V80 = 80 / 3.6


# under -n one worker builds the module fixtures for every test here (docs/testing.md)
pytestmark = pytest.mark.xdist_group("osc2runner/end_to_end/test_runner_braking")


@pytest.fixture(scope="module")
def braking() -> RunResult:
    result = run(ROOT / "examples" / "braking_friction.osc", duration=120.0)
    assert result.outcome.status == "success", result.outcome.reason
    return result


def _stops(result: RunResult) -> list[tuple[int, int]]:
    hero = result.telemetry["hero"]
    stops = []
    for onset in result.event_ticks("start", "hero.change_speed"):
        end = onset + int(np.flatnonzero(hero["speed"][onset:] < 0.01)[0])
        stops.append((onset, end))
    assert len(stops) == 3
    return stops


def _distance(result: RunResult, stop: tuple[int, int]) -> float:
    x = result.telemetry["hero"]["x"]
    return float(x[stop[1]] - x[stop[0]])


def test_every_stop_starts_from_80_kph(braking):
    speed = braking.telemetry["hero"]["speed"]
    for onset, _ in _stops(braking):
        assert speed[onset] == pytest.approx(V80, abs=0.3 / 3.6)


def test_dry_asap_stopping_distance(braking):
    dry = _stops(braking)[0]
    assert 25.2 <= _distance(braking, dry) <= 30.5


def test_dry_smooth_plateau_and_distance(braking):
    onset, end = _stops(braking)[1]
    accel = braking.telemetry["hero"]["accel"][onset : end + 1]
    n = len(accel)
    plateau = -accel[n // 4 : 3 * n // 4]
    assert np.all(np.abs(plateau - 2.5) <= 0.15)
    assert _distance(braking, (onset, end)) == pytest.approx(V80**2 / (2 * 2.5), rel=0.05)


def test_wet_asap_peak_deceleration_and_distance(braking):
    onset, end = _stops(braking)[2]
    hero = braking.telemetry["hero"]
    assert hero["friction"][onset] == pytest.approx(0.4)
    peak = -hero["accel"][onset : end + 1].min()
    assert 3.5 <= peak <= 4.3
    assert _distance(braking, (onset, end)) == pytest.approx(V80**2 / (2 * 0.4 * G), rel=0.15)


def test_acceleration_to_80_kph_is_slower_on_the_wet_road(braking):
    hero = braking.telemetry["hero"]
    drives = braking.event_ticks("start", "hero.drive")
    assert len(drives) == 3
    times = []
    for start in (drives[0], drives[2]):  # dry, then friction 0.4
        reached = start + int(np.flatnonzero(hero["speed"][start:] >= 0.99 * V80)[0])
        times.append(hero["time"][reached] - hero["time"][start])
    dry, wet = times
    assert dry < 10.0
    assert wet > 1.5 * dry


def test_filtered_jerk_is_bounded_while_braking_smoothly(braking):
    onset, end = _stops(braking)[1]
    jerk = braking.telemetry["hero"]["jerk"][onset + 20 : end - 20]
    assert np.all(np.abs(jerk) <= 3.0)  # a 1 s average of a 10 m/s³-limited profile


def test_runner_md_quotes_these_figures(braking):
    """docs/runner.md's braking rows are this run's figures (OSC2_UPDATE_DOCS=1 writes them)."""
    from tests.docs_blocks import ROOT as DOCS_ROOT
    from tests.docs_blocks import check_block

    hero = braking.telemetry["hero"]
    (dry, smooth, wet) = _stops(braking)
    peak = -hero["accel"][dry[0] : dry[1] + 1].min()
    accel = -hero["accel"][smooth[0] : smooth[1] + 1]
    plateau = accel[len(accel) // 4 : 3 * len(accel) // 4]
    wet_peak = -hero["accel"][wet[0] : wet[1] + 1].min()
    drives = braking.event_ticks("start", "hero.drive")
    times = [
        hero["time"][s + int(np.flatnonzero(hero["speed"][s:] >= 0.99 * V80)[0])] - hero["time"][s]
        for s in (drives[0], drives[2])
    ]
    rows = [
        "| scenario | figure | required | measured |",
        "|---|---|---|---|",
        f"| `examples/braking_friction.osc` (sedan, 80 kph) | dry `asap` stopping distance | "
        f"25.2–30.5 m | **{_distance(braking, dry):.2f} m** (peak {peak:.2f} m/s²) |",
        f"| | dry `smooth` plateau / distance | 2.5 ± 0.15 m/s² / 98.8 m ± 5% | "
        f"**{plateau.min():.3f}–{plateau.max():.3f}** (mean {plateau.mean():.3f}) / "
        f"**{_distance(braking, smooth):.2f} m** |",
        f"| | µ 0.4 `asap` peak (50 ms) / distance | 3.5–4.3 m/s² / 62.9 m ± 15% | "
        f"**{wet_peak:.2f}** / **{_distance(braking, wet):.2f} m** |",
        f"| | 0 → 99% of 80 kph, µ 1.0 vs 0.4 | visibly slower at 0.4 | "
        f"**{times[0]:.2f} s vs {times[1]:.2f} s** |",
    ]
    check_block(DOCS_ROOT / "docs" / "runner.md", "braking-figures", "\n".join(rows))
