"""KPIs of a run against closed-form motion (synthetic telemetry)."""

from __future__ import annotations

import numpy as np
import pytest

from osc2runner.campaign.kpis import run_kpis
from osc2runner.output.gaps import subject_actor

DT = 0.05


def channels(x: np.ndarray, y: np.ndarray, speed: np.ndarray, **extra: np.ndarray) -> dict:
    n = len(x)
    accel = np.concatenate([[0.0], np.diff(speed) / DT])
    ch = {
        "tick": np.arange(n),
        "time": np.arange(n) * DT,
        "x": x,
        "y": y,
        "yaw": np.zeros(n),
        "speed": speed,
        "accel": accel,
        "jerk": np.zeros(n),
        "brake": np.zeros(n),
        "lane": np.full(n, 2.0),
    }
    ch.update(extra)
    return ch


def test_ttc_and_gap_of_a_constant_closing_speed() -> None:
    t = np.arange(0, 4.0, DT)
    ego = channels(10.0 * t, np.zeros_like(t), np.full_like(t, 10.0))
    lead = channels(50.0 + 4.0 * t, np.full_like(t, 0.6), np.full_like(t, 4.0))
    k = run_kpis({"ego": ego, "lead": lead}, {"ego": (4.5, 1.8), "lead": (4.5, 1.8)}, [], "ego")
    # gap(t) = 50 - 4.5 - 6 t; closing 6 m/s: TTC = gap / 6, smallest at the last tick
    last = t[-1]
    assert k["min_gap_m"] == pytest.approx(45.5 - 6 * last, abs=1e-3)
    assert k["min_ttc_s"] == pytest.approx((45.5 - 6 * last) / 6.0, abs=1e-3)
    assert k["collision"] is False and k["impact_speed_kph"] is None
    assert k["speed_reduction_kph"] == pytest.approx(36.0)


def test_an_actor_beside_the_path_has_no_ttc() -> None:
    t = np.arange(0, 2.0, DT)
    ego = channels(10.0 * t, np.zeros_like(t), np.full_like(t, 10.0))
    side = channels(30.0 + 0 * t, np.full_like(t, 3.5), np.zeros_like(t))  # next lane
    k = run_kpis({"ego": ego, "side": side}, {"ego": (4.5, 1.8), "side": (4.5, 1.8)}, [], "ego")
    assert k["min_ttc_s"] is None and k["min_gap_m"] is None


def test_impact_speed_time_to_stop_and_lane_departures() -> None:
    n = 100
    t = np.arange(n) * DT
    speed = np.maximum(15.0 - 5.0 * np.maximum(t - 1.0, 0.0), 0.0)  # brakes at 1 s, 5 m/s²
    brake = np.where(t >= 1.0, 1.0, 0.0)
    lane = np.where(t < 2.0, 2.0, np.where(t < 3.0, np.nan, 1.0))
    x = np.cumsum(speed) * DT
    ego = channels(x, np.zeros(n), speed, brake=brake, lane=lane)
    target = channels(np.full(n, 100.0), np.zeros(n), np.zeros(n))
    collisions = [(40, ("ego", "target"))]
    k = run_kpis(
        {"ego": ego, "target": target}, {"ego": (4.5, 1.8), "target": (4.5, 1.8)}, collisions,
        "ego", start_speed=15.0,
    )  # fmt: skip
    v40 = 15.0 - 5.0 * (40 * DT - 1.0)
    assert k["collision"] and k["collision_with"] == "target"
    assert k["collision_time_s"] == pytest.approx(2.0)
    assert k["impact_speed_kph"] == pytest.approx(v40 * 3.6)
    assert k["relative_impact_speed_kph"] == pytest.approx(v40 * 3.6)  # target stands
    assert k["speed_reduction_kph"] == pytest.approx((15.0 - v40) * 3.6)
    assert k["time_to_stop_s"] == pytest.approx(3.0, abs=DT)  # 15 m/s at 5 m/s²
    assert k["max_decel_mps2"] == pytest.approx(5.0, abs=1e-6)
    assert k["lane_departures"] == 2  # into "off the road", then into lane 1


def test_subject_actor() -> None:
    actors = {"hero": {"kind": "vehicle"}, "ego": {"kind": "vehicle"}, "p": {"kind": "pedestrian"}}
    assert subject_actor(actors, None) == "ego"
    assert subject_actor(actors, "hero") == "hero"
    assert subject_actor({"hero": {"kind": "vehicle"}}, None) == "hero"
    assert subject_actor({"p": {"kind": "pedestrian"}}, None) is None


def test_the_braking_plot_and_time_to_stop_agree_on_what_a_stop_is() -> None:
    from osc2runner.output.plots import braking_phases

    n = 120
    t = np.arange(n) * DT
    # brakes at 1 s at 5 m/s², creeps at 0.08 m/s (stopped: below 0.1 m/s) from 4 s, 0 from 5 s
    speed = np.maximum(15.0 - 5.0 * np.maximum(t - 1.0, 0.0), 0.08)
    speed[t >= 5.0] = 0.0
    hard = channels(np.cumsum(speed) * DT, np.zeros(n), speed, brake=np.where(t >= 1.0, 1.0, 0.0))
    stop = run_kpis({"ego": hard}, {}, [], "ego")["time_to_stop_s"]
    ((a, b, ending),) = [(p.start, p.end, p.ending) for p in braking_phases(hard)]
    assert ending == "stop"  # the plot starts a tick before the onset
    assert stop == pytest.approx(3.0) and t[b] - t[a + 1] == pytest.approx(stop)
    # a pedal at 3 % is no brake onset, for either
    light = {**hard, "brake": np.where(t >= 1.0, 0.03, 0.0)}
    assert run_kpis({"ego": light}, {}, [], "ego")["time_to_stop_s"] is None
    assert braking_phases(light) == []


def test_kpi_figures_are_of_the_numeric_kpis_of_finished_runs() -> None:
    from osc2runner.campaign.summary import kpi_figures
    from osc2runner.campaign.worker import RunRecord

    def record(seed: int, status: str, gap: float, collision: bool) -> RunRecord:
        kpis = {"collision": collision, "collision_with": "lead" if collision else None}
        return RunRecord(seed, status, "", kpis={**kpis, "min_gap_m": gap, "lane_departures": 0})

    records = [
        record(0, "success", 2.0, False),
        record(1, "failure", 0.0, True),
        record(2, "success", 4.0, False),
        record(3, "interrupted", 9.0, False),  # not finished: left out
    ]
    figures = kpi_figures(records)
    assert set(figures) == {"min_gap_m", "lane_departures"}  # not the bool, not the actor
    assert figures["min_gap_m"] == {
        "unit": "m", "runs": 3, "min": 0.0, "median": 2.0, "mean": 2.0, "max": 4.0,
    }  # fmt: skip
