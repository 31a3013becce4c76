"""Acceptance figures: the closed-loop vehicle against closed-form physics.

Sedan from 80 kph (22.22 m/s) on a straight road unless noted. Each
simulation runs once per module (fixtures) and several assertions read it.
Decelerations are measured over 50 ms windows (one control tick), as the
reference recommends: per-physics-step values are contact noise.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from osc2check.world.builtin import builtin_network
from osc2runner.execution.loop import TickLoop
from osc2runner.sim import (
    ActorSpec,
    VehicleController,
    VehicleParams,
    World,
    hgv,
    sedan,
)

ROAD = builtin_network("default")
G = 9.81
V80 = 80 / 3.6
V35 = 35 / 3.6


@dataclass
class Trace:
    """Per-tick samples of one actor after each control step."""

    time: np.ndarray
    x: np.ndarray
    y: np.ndarray
    speed: np.ndarray
    accel: np.ndarray

    @property
    def distance(self) -> float:
        return float(self.x[-1] - self.x[0])


def _drive(
    params: VehicleParams,
    *,
    mu: float,
    v0: float,
    target: float,
    profile: str,
    seconds: float,
    stop_when_stopped: bool = False,
) -> Trace:
    world = World(ROAD, [ActorSpec("ego", params, s=50.0, lane=2, speed=v0)], friction=mu)
    controller = VehicleController(params, ROAD, world.dt_control)
    controller.lateral.keep_lane(2)
    controller.speed.set_target(target, profile)
    loop = TickLoop.without_scenario(world, {"ego": controller})
    rows = []
    first = world.state("ego")
    rows.append((0.0, first.x, first.y, first.speed, 0.0))
    for _ in range(round(seconds / world.dt_control)):
        loop.step()
        s = world.state("ego")
        rows.append((s.time, s.x, s.y, s.speed, s.accel))
        if stop_when_stopped and s.speed < 0.01:
            break
    return Trace(*(np.array(col) for col in zip(*rows, strict=True)))


def _stop(params: VehicleParams, mu: float, profile: str) -> Trace:
    return _drive(
        params, mu=mu, v0=V80, target=0.0, profile=profile, seconds=20.0, stop_when_stopped=True
    )


@pytest.fixture(scope="module")
def dry_asap() -> Trace:
    return _stop(sedan(), 1.0, "asap")


@pytest.fixture(scope="module")
def dry_smooth() -> Trace:
    return _stop(sedan(), 1.0, "smooth")


@pytest.fixture(scope="module")
def wet_asap() -> Trace:
    return _stop(sedan(), 0.4, "asap")


# ---------------------------------------------------------------------- braking


def test_brake_dry_asap_stops_near_mu_g(dry_asap):
    # theory v²/(2µg) = 25.2 m; ABS margin, brake ramp and load transfer add a few metres
    assert dry_asap.speed[-1] < 0.01
    assert 25.2 <= dry_asap.distance <= 30.5
    assert dry_asap.accel.min() > -1.15 * G  # never beyond the friction limit


def test_brake_smooth_plateau_is_comfort_deceleration(dry_smooth):
    n = len(dry_smooth.accel)
    plateau = -dry_smooth.accel[n // 4 : 3 * n // 4]
    assert np.all(np.abs(plateau - 2.5) <= 0.15)
    assert abs(plateau.mean() - 2.5) <= 0.05


def test_brake_smooth_distance_matches_v2_over_2a(dry_smooth):
    theory = V80**2 / (2 * 2.5)  # 98.8 m
    assert dry_smooth.distance == pytest.approx(theory, rel=0.05)


def test_brake_wet_asap_is_friction_limited(wet_asap):
    peak = -wet_asap.accel.min()
    assert 3.5 <= peak <= 4.3
    theory = V80**2 / (2 * 0.4 * G)  # 62.9 m
    assert wet_asap.distance == pytest.approx(theory, rel=0.15)


def test_brake_wet_is_longer_than_dry(dry_asap, wet_asap):
    assert wet_asap.distance > 2.0 * dry_asap.distance


# ---------------------------------------------------------------------- acceleration and hold


@pytest.fixture(scope="module")
def launches() -> dict[float, Trace]:
    return {
        mu: _drive(sedan(), mu=mu, v0=0.0, target=V80, profile="asap", seconds=25.0)
        for mu in (1.0, 0.4)
    }


def _time_to(trace: Trace, speed: float) -> float:
    reached = np.flatnonzero(trace.speed >= speed)
    assert reached.size, "target speed never reached"
    return float(trace.time[reached[0]])


def test_acceleration_is_slower_on_low_friction(launches):
    dry = _time_to(launches[1.0], 0.99 * V80)
    wet = _time_to(launches[0.4], 0.99 * V80)
    assert dry < 10.0
    assert wet > 1.5 * dry
    # traction-limited: mean acceleration below 0.9·µg on the wet road
    assert 0.99 * V80 / wet < 0.9 * 0.4 * G + 0.3


def test_acceleration_reaches_target_without_overshoot(launches):
    for trace in launches.values():
        assert trace.speed.max() <= V80 + 0.3 / 3.6
        assert abs(trace.speed[-1] - V80) < 0.1 / 3.6


@pytest.fixture(scope="module")
def hold35() -> Trace:
    return _drive(sedan(), mu=1.0, v0=0.0, target=V35, profile="smooth", seconds=20.0)


def test_speed_hold_35_kph_within_0_3_kph(hold35):
    kph = hold35.speed * 3.6
    settled = kph[hold35.time >= 8.0]
    assert np.all(np.abs(settled - 35.0) <= 0.3)
    assert kph.max() <= 35.5


# ---------------------------------------------------------------------- lane change


@pytest.fixture(scope="module")
def lane_change():
    world = World(ROAD, [ActorSpec("ego", sedan(), s=50.0, lane=1, speed=V35)])
    controller = VehicleController(sedan(), ROAD, world.dt_control)
    controller.lateral.keep_lane(1)
    controller.speed.set_target(V35)
    loop = TickLoop.without_scenario(world, {"ego": controller})
    for _ in range(round(1.0 / world.dt_control)):
        loop.step()
    controller.lateral.change_lane(world.state("ego"), 2, duration=4.0)
    during, after = [], []
    for _ in range(round(9.0 / world.dt_control)):
        loop.step()
        state = world.state("ego")
        if controller.lateral.done(state):
            after.append(state.y - 1.5 * 3.5)  # lane 2 centre
        else:
            during.append(controller.lateral.error)
    return np.array(during), np.array(after), world.state("ego")


def test_lane_change_tracks_the_path(lane_change):
    during, after, final = lane_change
    assert np.abs(during).max() < 0.1
    assert np.abs(after).max() < 0.1
    assert final.lane == 2 and abs(final.yaw) < 0.01
    assert abs(final.speed - V35) < 0.3 / 3.6


# ---------------------------------------------------------------------- HGV


@pytest.fixture(scope="module")
def hgv_runs() -> dict[str, Trace]:
    return {
        "dry": _stop(hgv(), 1.0, "asap"),
        "wet": _stop(hgv(), 0.4, "asap"),
        "hold": _drive(hgv(), mu=1.0, v0=0.0, target=V80, profile="smooth", seconds=30.0),
    }


def test_hgv_brakes_within_its_brake_force(hgv_runs):
    # 60 kN·m on 0.5 m wheels for 12 t: at most 10 m/s², front/rear split limits it to ~6.6
    dry = hgv_runs["dry"]
    assert 30.0 <= dry.distance <= 45.0
    assert -dry.accel.min() < 0.9 * 1.0 * G
    wet = hgv_runs["wet"]
    assert wet.distance == pytest.approx(V80**2 / (2 * 0.4 * G), rel=0.15)


def test_hgv_holds_speed(hgv_runs):
    hold = hgv_runs["hold"]
    settled = hold.speed[hold.time >= 22.0] * 3.6
    assert np.all(np.abs(settled - 80.0) <= 0.5)


# ---------------------------------------------------------------------- determinism


def _scripted_run() -> tuple[str, bytes]:
    """Three vehicles: a lane change, a friction switch and a truck braking."""
    actors = [
        ActorSpec("ego", sedan(), s=50.0, lane=1, speed=V80),
        ActorSpec("npc", sedan(), s=80.0, lane=2, speed=V35),
        ActorSpec("truck", hgv(), s=120.0, lane=3, speed=V80),
    ]
    world = World(ROAD, actors, friction=0.7)
    controllers = {a.name: VehicleController(a.params, ROAD, world.dt_control) for a in actors}
    for a in actors:
        controllers[a.name].lateral.keep_lane(a.lane)
        controllers[a.name].speed.set_target(a.speed, "smooth")
    loop = TickLoop.without_scenario(world, controllers)
    digest = hashlib.sha256()
    for tick in range(200):
        if tick == 20:
            controllers["npc"].lateral.change_lane(world.state("npc"), 1, duration=3.0)
            controllers["truck"].speed.set_target(0.0, "asap")
        if tick == 100:
            world.set_road_friction(0.4)
        loop.step()
        digest.update(world.state_array().tobytes())
    return digest.hexdigest(), world.state_array().tobytes()


@pytest.mark.slow
def test_two_runs_are_bit_identical():
    first, second = _scripted_run(), _scripted_run()
    assert first[0] == second[0]
    assert first[1] == second[1]


@pytest.mark.slow
def test_a_fresh_process_gives_the_same_run():
    """Same inputs and versions in a new interpreter: the same bits."""
    here = Path(__file__).resolve().parent
    root = here.parents[2]
    code = (
        "import sys; sys.path.insert(0, sys.argv[1]); import test_physics as t; "
        "print(t._scripted_run()[0])"
    )
    path = os.pathsep.join([str(root), os.environ.get("PYTHONPATH", "")])
    env = dict(os.environ, PYTHONPATH=path)
    out = subprocess.run(
        [sys.executable, "-c", code, str(here)],
        capture_output=True,
        text=True,
        check=True,
        env=env,
        cwd=root,
    )
    assert out.stdout.strip() == _scripted_run()[0]
