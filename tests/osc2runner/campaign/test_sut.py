"""The system-under-test interface: what it sees, what its answers do, what it is told."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from osc2runner import run
from osc2runner.errors import ScenarioError
from osc2runner.sut.loading import SutError, SutSpec, choose_actor, configured_sut

HERE = Path(__file__).parent
SUTS = HERE / "suts.py"
ROOT = HERE.parents[2]
CCRS = ROOT / "examples" / "ncap" / "ccrs.osc"
AEB = ROOT / "examples" / "controllers" / "aeb.py"
ACC = ROOT / "examples" / "controllers" / "acc.py"

FOLLOW = """\
import osc.standard

scenario follow:
    ego: vehicle with:
        keep(it.vehicle_category == car)
    lead: vehicle with:
        keep(it.vehicle_category == car)
    do serial:
        setup: parallel:
            ego.assign_position() with:
                lane(2, at: start)
                speed(20kph, at: start)
            lead.assign_position() with:
                lane(same_as: ego, at: start)
                lateral(distance: 0.5m, at: start)
                position(distance: 30m, ahead_of: ego, at: start)
                speed(10kph, at: start)
        parallel:
            ego.drive(duration: 3s) with:
                speed(20kph)
            lead.drive(duration: 3s) with:
                speed(10kph)
"""


def sut(name: str) -> str:
    return f"{SUTS}:{name}"


def test_pass_through_sut_gives_the_run_without_sut(tmp_path: Path) -> None:
    plain = run("follow.osc", source=FOLLOW, out=tmp_path / "plain")
    driven = run("follow.osc", source=FOLLOW, out=tmp_path / "sut", sut=sut("PassThrough"))
    assert (tmp_path / "plain" / "telemetry.csv").read_bytes() == (
        tmp_path / "sut" / "telemetry.csv"
    ).read_bytes()
    assert driven.metadata["sut"]["actor"] == "ego"
    assert "sut" not in plain.metadata


def test_observation_matches_the_states() -> None:
    from osc2runner.runner import execute, prepare
    from osc2runner.sut.driver import SutDriver

    prepared = prepare("follow.osc", source=FOLLOW, sut=SutSpec(sut("PassThrough")).resolved())
    seen = []
    driver = prepared.ctx.controllers["ego"]
    assert isinstance(driver, SutDriver)
    original = driver.sut.step

    def spy(obs):  # type: ignore[no-untyped-def]
        seen.append(obs)
        return original(obs)

    driver.sut.step = spy
    result = execute(prepared)
    assert result.outcome.status == "success"
    obs = seen[0]
    (lead,) = obs.others
    ego_t = result.telemetry["ego"]
    lead_t = result.telemetry["lead"]
    # the first observation is tick 0: the start, read once
    assert obs.tick == 0 and obs.ego.x == pytest.approx(ego_t["x"][0])
    dx = lead_t["x"][0] - ego_t["x"][0]
    dy = lead_t["y"][0] - ego_t["y"][0]
    yaw = ego_t["yaw"][0]
    assert lead.rel_x == pytest.approx(dx * math.cos(yaw) + dy * math.sin(yaw))
    assert lead.rel_y == pytest.approx(-dx * math.sin(yaw) + dy * math.cos(yaw))
    # bumper to bumper: 30 m as placed (4.5 m cars), lead 0.5 m to the left: still in the path
    assert lead.gap == pytest.approx(30.0, abs=0.02)
    assert lead.lateral_gap == pytest.approx(0.5 - 1.8, abs=0.02) and lead.in_path
    # closing at 10 kph: rel_vx = -10/3.6, TTC = gap / closing
    assert lead.rel_vx == pytest.approx(-10 / 3.6, abs=0.02)
    assert lead.time_to_collision == pytest.approx(30.0 / (10 / 3.6), rel=0.01)
    assert obs.intent.speed == pytest.approx(20 / 3.6)
    assert obs.ahead() is lead
    assert len(obs.road.path) == 11 and obs.road.lane == 2


def test_demand_deceleration_is_what_the_car_does() -> None:
    result = run("follow.osc", source=FOLLOW, sut=sut("Decelerate"))
    ego = result.telemetry["ego"]
    # after the pedal ramp (brake rate 6 /s), the inverse model holds -3 m/s²
    moving = (ego["time"] > 0.6) & (ego["speed"] > 1.0)
    assert moving.sum() > 10
    assert np.median(ego["accel"][moving]) == pytest.approx(-3.0, abs=0.3)


def test_sut_that_raises_ends_the_run_as_error(tmp_path: Path) -> None:
    result = run("follow.osc", source=FOLLOW, sut=sut("Raises"), out=tmp_path)
    assert result.outcome.status == "error"
    assert "sensor failure" in result.outcome.reason and "tick 5" in result.outcome.reason
    assert (tmp_path / "run.json").is_file()


def test_aeb_avoids_the_stationary_target_the_plain_driver_hits() -> None:
    plain = run(CCRS, seed=3)
    assert plain.outcome.status == "failure" and "collision" in plain.outcome.reason
    braked = run(CCRS, seed=3, sut=f"{AEB}:Aeb")
    assert braked.outcome.status == "success"
    ego, gvt = braked.telemetry["ego"], braked.telemetry["gvt"]
    gap = gvt["x"][-1] - ego["x"][-1] - 4.5  # both cars 4.5 m long, same heading
    assert 0.0 < gap < 5.0 and ego["speed"][-1] < 0.1


def test_acc_keeps_its_time_gap_behind_a_slower_car() -> None:
    text = FOLLOW.replace("duration: 3s", "duration: 40s")
    result = run("follow.osc", source=text, sut=f"{ACC}:Acc")
    ego, lead = result.telemetry["ego"], result.telemetry["lead"]
    assert result.outcome.status == "success"
    gap = lead["x"][-1] - ego["x"][-1] - 4.5
    v = ego["speed"][-1]
    assert v == pytest.approx(10 / 3.6, abs=0.2)  # follows at the lead's speed
    assert gap == pytest.approx(4.0 + 1.8 * v, abs=1.0)  # standstill + time gap


def test_choose_actor() -> None:
    fields = {"ego": "vehicle", "npc": "vehicle", "ped": "pedestrian"}
    assert choose_actor(fields, None) == "ego"
    assert choose_actor({"sut": "vehicle", **fields}, None) == "sut"
    assert choose_actor(fields, "npc") == "npc"
    with pytest.raises(SutError, match="no actor `x`"):
        choose_actor(fields, "x")
    with pytest.raises(SutError, match="not a vehicle"):
        choose_actor(fields, "ped")
    with pytest.raises(SutError, match="name its field `sut` or `ego`"):
        choose_actor({"hero": "vehicle"}, None)


def test_scenario_without_sut_actor_is_an_input_error() -> None:
    text = re.sub(r"\bego\b", "hero", FOLLOW)
    with pytest.raises(ScenarioError, match="marks no system under test"):
        run("follow.osc", source=text, sut=sut("PassThrough"))


def test_bad_sut_names(tmp_path: Path) -> None:
    with pytest.raises(SutError, match="not `module:Class`"):
        SutSpec("nocolon")
    with pytest.raises(SutError, match="has no class `Nope`"):
        SutSpec(sut("Nope")).load()
    with pytest.raises(SutError, match="cannot import"):
        SutSpec("no_such_module_here:X").load()
    with pytest.raises(SutError, match="no such file"):
        SutSpec(f"{tmp_path}/missing.py:X").load()


def test_pyproject_names_the_sut(tmp_path: Path) -> None:
    (tmp_path / "pyproject.toml").write_text(
        '[tool.osc2run]\nsut = "ctl/aeb.py:Aeb"\nsut-actor = "ego"\n', encoding="utf-8"
    )
    (tmp_path / "scen").mkdir()
    spec, path = configured_sut(tmp_path / "scen" / "a.osc")
    assert path == tmp_path / "pyproject.toml"
    assert spec is not None and spec.actor == "ego"
    assert spec.target == f"{(tmp_path / 'ctl' / 'aeb.py').resolve()}:Aeb"
    (tmp_path / "pyproject.toml").write_text('[tool.osc2run]\nsuts = "x:Y"\n', encoding="utf-8")
    with pytest.raises(SutError, match="no key `suts`"):
        configured_sut(tmp_path / "a.osc")
