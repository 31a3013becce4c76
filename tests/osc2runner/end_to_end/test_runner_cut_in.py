"""The cut-in scenario through the whole runner: the design paper's file and the example.

One run per file (module fixtures); each test reads it. Figures measured on
telemetry rows, one per control tick (row ``k`` is the state the tree saw at
tick ``k``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from osc2runner import run
from osc2runner.runner import RunResult

ROOT = Path(__file__).resolve().parents[3]
SEED = Path(__file__).resolve().parents[2] / "data" / "seed"  # vendored
KPH = 3.6


def _run(path: Path) -> RunResult:
    return run(path, duration=120.0)


@pytest.fixture(scope="module")
def paper() -> RunResult:
    return _run(SEED / "cut_in_and_stop.osc")


@pytest.fixture(scope="module")
def example() -> RunResult:
    return _run(ROOT / "examples" / "cut_in_and_stop.osc")


def _ahead(result: RunResult, actor: str, reference: str) -> np.ndarray:
    """``actor.position.ahead_of(reference)`` at every tick."""
    a, r = result.telemetry[actor], result.telemetry[reference]
    return (a["x"] - r["x"]) * np.cos(r["yaw"]) + (a["y"] - r["y"]) * np.sin(r["yaw"])


def _record(result: RunResult, kind: str, name: str) -> int:
    ticks = result.event_ticks(kind, name)
    assert ticks, f"no {kind} record of {name}"
    return ticks[0]


def test_paper_cut_in_runs_unchanged_to_success(paper):
    assert paper.outcome.status == "success", paper.outcome.reason
    emitted = [r.name for r in paper.events if r.kind == "emit"]
    assert emitted == ["go_signal", "CRASH_AVOIDED", "OBSTACLE_DETECTED"]
    assert not [r for r in paper.events if r.kind == "collision"]


def test_paper_npc_starts_behind_and_one_lane_right(paper):
    hero, npc = paper.telemetry["hero"], paper.telemetry["npc"]
    # Town06 counts the scenario's lanes from the left: lane 1 is road lane 4
    assert (hero["lane"][0], npc["lane"][0]) == (4.0, 3.0)
    # bodies as the checker placed them: the witness's (and the catalogue's) lengths
    actors = paper.metadata["actors"]
    sizes = {name: a["size"]["length"] for name, a in actors.items() if "size" in a}
    assert (sizes["hero"], sizes["npc"]) == (4.69, 12.0)  # tesla.model3, european_hgv
    bumper_gap = (hero["x"][0] - sizes["hero"] / 2) - (npc["x"][0] + sizes["npc"] / 2)
    assert bumper_gap == pytest.approx(5.0, abs=1e-6)
    assert hero["speed"][0] == npc["speed"][0] == 0.0


def test_hero_holds_35_kph_once_settled(paper):
    hero = paper.telemetry["hero"]
    trigger = _record(paper, "stop", "hero.drive")
    settled = hero["speed"][160:trigger] * KPH  # from 8 s after go to the trigger
    assert settled.size > 200
    assert np.all(np.abs(settled - 35.0) <= 0.3)


def test_fall_trigger_fires_on_the_first_tick_below_the_safety_gap(paper):
    gap = _ahead(paper, "npc", "hero")
    above = np.flatnonzero(gap > 12.0)
    assert above.size, "the npc never got more than 12 m ahead"
    first_below = above[0] + np.flatnonzero(gap[above[0] :] <= 12.0)[0]
    assert _record(paper, "stop", "hero.drive") == first_below
    assert _record(paper, "start", "hero.change_lane") == first_below
    assert gap[first_below] == pytest.approx(12.0, abs=0.25)


def test_rise_trigger_ends_the_npc_overtaking(paper):
    gap = _ahead(paper, "npc", "hero")
    first = int(np.flatnonzero(gap >= 10.0)[0])
    assert _record(paper, "stop", "npc.drive") == first


def test_obstacle_detected_reaches_the_hero_within_one_tick(paper):
    emitted = _record(paper, "emit", "OBSTACLE_DETECTED")
    reaction = _record(paper, "start", "hero.change_speed")
    assert 0 <= reaction - emitted <= 1
    brake = paper.telemetry["hero"]["brake"]
    assert brake[reaction] == 0.0 and brake[reaction + 1] > 0.0  # applied on the next step


def test_hero_lane_change_tracks_its_path(paper):
    start = _record(paper, "start", "hero.change_lane")
    end = _record(paper, "end", "hero.change_lane")
    error = paper.telemetry["hero"]["lateral_error"][start : end + 1]
    assert end - start > 20
    assert np.nanmax(np.abs(error)) < 0.1
    hero = paper.telemetry["hero"]
    assert hero["lane"][end + 10] == 3.0  # one lane right


def test_both_vehicles_stop(paper):
    # the scenario ends on `hero.speed < 0.1kph`; after a hard stop the body rocks
    # back on its suspension a little (signed speed slightly negative)
    hero = paper.telemetry["hero"]["speed"]
    assert hero[-1] < 0.1 / KPH and abs(hero[-1]) < 0.1
    assert np.all(np.abs(paper.telemetry["npc"]["speed"][-10:]) < 0.1)


def test_lights_flash_for_half_a_second(paper):
    lights = [r for r in paper.events if r.kind == "lights"]
    assert [r.detail for r in lights] == ["high_beam", "auto"]
    assert lights[1].tick - lights[0].tick == 10


def test_example_cut_in_runs_to_success(example):
    assert example.outcome.status == "success", example.outcome.reason
    emitted = [r.name for r in example.events if r.kind == "emit"]
    assert emitted == ["go_signal", "crash_avoided", "obstacle_detected"]
    gap = _ahead(example, "npc", "hero")
    trigger = _record(example, "stop", "hero.drive")
    assert gap[trigger] <= 12.0 < gap[trigger - 1]


def test_paper_braking_runs_unchanged_to_success():
    result = _run(SEED / "braking_friction.osc")
    assert result.outcome.status == "success", result.outcome.reason
    emitted = [r.name for r in result.events if r.kind == "emit"]
    assert emitted == [
        "DRY_BRAKE_ASAP_TRIGGERED",
        "DRY_BRAKE_SMOOTH_TRIGGERED",
        "WET_BRAKE_ASAP_TRIGGERED",
    ]
    assert result.telemetry["hero"]["friction"][-1] == pytest.approx(0.4)


def test_runner_md_quotes_these_figures(paper):
    """docs/runner.md's cut-in rows are this run's figures (OSC2_UPDATE_DOCS=1 writes them)."""
    from tests.docs_blocks import ROOT as DOCS_ROOT
    from tests.docs_blocks import check_block

    hero = paper.telemetry["hero"]
    trigger = _record(paper, "stop", "hero.drive")
    settled = hero["speed"][160:trigger] * KPH
    gap = _ahead(paper, "npc", "hero")
    emitted = _record(paper, "emit", "OBSTACLE_DETECTED")
    reaction = _record(paper, "start", "hero.change_speed")
    start = _record(paper, "start", "hero.change_lane")
    end = _record(paper, "end", "hero.change_lane")
    tracking = np.nanmax(np.abs(hero["lateral_error"][start : end + 1]))
    collided = any(r.kind == "collision" for r in paper.events)
    rows = [
        "| scenario | figure | required | measured |",
        "|---|---|---|---|",
        f"| paper's `cut_in_and_stop.osc` | outcome | success, unchanged | "
        f"**{paper.outcome.status}** at {paper.outcome.time:.2f} s, "
        f"{'a collision' if collided else 'no collision'} |",
        f"| | hero speed once settled (8 s after go to the trigger) | 35 ± 0.3 kph | "
        f"**{settled.min():.2f}–{settled.max():.2f} kph** |",
        f"| | `fall(... > safety_gap)` | first tick below 12 m | **tick {trigger}**: "
        f"{gap[trigger - 1]:.2f} m -> {gap[trigger]:.2f} m |",
        f"| | `OBSTACLE_DETECTED` -> hero reaction | within one tick | emitted tick {emitted}, "
        f"`change_speed` starts tick **{reaction}** |",
        f"| | hero lane change tracking ({(end - start) * 0.05:.1f} s) | < 0.1 m | "
        f"**{tracking:.3f} m** |",
    ]
    check_block(DOCS_ROOT / "docs" / "runner.md", "cut-in-figures", "\n".join(rows))
