"""Physical inputs checked before a run (friction, rain) and a diverged physics (outcome error)."""

from __future__ import annotations

import csv
import json
import math
from dataclasses import replace
from pathlib import Path

import pytest

from osc2check.world.builtin import builtin_network
from osc2runner import run
from osc2runner import runner as runner_module
from osc2runner.cli import main
from osc2runner.errors import ScenarioError
from osc2runner.sim import ActorSpec, PedestrianInput, PedestrianParams, World, sedan

FRICTION = """\
import osc.standard

scenario s:
    hero: vehicle
    env: environment
    mu: float = 0.5
    do serial:
        hero.assign_position() with:
            lane(1, at: start)
            speed(50kph, at: start)
        env.{action}
        hero.drive(duration: 2s) with:
            speed(60kph)
"""

TWO_CARS = """\
import osc.standard

scenario s:
    hero: vehicle
    npc: vehicle
    do parallel:
        serial:
            hero.assign_position() with:
                lane(1, at: start)
                speed(50kph, at: start)
            hero.drive(duration: 5s) with:
                speed(60kph)
        serial:
            npc.assign_position() with:
                lane(2, at: start)
                speed(50kph, at: start)
            npc.drive(duration: 5s) with:
                speed(60kph)
"""


def _write(tmp_path: Path, text: str) -> Path:
    source = tmp_path / "s.osc"
    source.write_text(text)
    return source


@pytest.mark.parametrize("argument", ["1e9", "0", "-1", "0.0", "2.5"])
def test_a_constant_friction_out_of_range_is_refused_by_the_checker_at_the_argument(
    tmp_path, capsys, argument
):
    """The checker verifies the range the runner takes (osc2check.world.limits): nothing runs."""
    source = _write(tmp_path, FRICTION.format(action=f"set_road_friction(value: {argument})"))
    out = tmp_path / "out"
    assert main([str(source), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"{source}:11:31: C401 [error]" in err
    assert f"`set_road_friction(value: {argument})`; road friction is in (0, 2]" in err
    assert "nothing ran" in err and not out.exists()


def test_a_friction_parameter_is_checked_where_it_is_passed(tmp_path):
    text = FRICTION.format(action="set_road_friction(mu)").replace("= 0.5", "= 1e9")
    with pytest.raises(ScenarioError) as caught:
        run(_write(tmp_path, text))
    (finding,) = caught.value.diagnostics
    assert finding.code.code == "C401"
    assert (finding.span.line, finding.span.column) == (11, 31)
    assert "`set_road_friction(value: mu)`" in finding.message
    assert "road friction is in (0, 2]" in finding.message
    assert [r.span.line for r in finding.related] == [6, 11]  # the default `mu = 1e9`


def test_the_runner_refuses_constants_that_the_checker_did_not_see(tmp_path, monkeypatch):
    """Its own check at compile time stays: a witness made elsewhere may carry any value.
    With the checker's argument limits left out, the runner refuses the constant at the
    argument, before anything runs."""
    from osc2check.verify import parameters
    from osc2runner.behaviours.environment import friction_problem

    assert friction_problem(1e9) == "road friction must be in (0, 2], got 1e+09"
    assert friction_problem(0.0) == "road friction must be in (0, 2], got 0"
    assert friction_problem(2.0) is None and friction_problem(0.05) is None
    assert friction_problem(float("nan")) is not None
    monkeypatch.setattr(parameters, "ARGUMENT_LIMITS", {})
    for action, column, message in (
        ("set_road_friction(value: 1e9)", 38, "road friction must be in (0, 2], got 1e+09"),
        ("rain(intensity: -5mmph)", 29, "rain intensity must be finite and not negative"),
    ):
        with pytest.raises(ScenarioError) as caught:
            run(_write(tmp_path, FRICTION.format(action=action)))
        assert not caught.value.diagnostics  # the checker found nothing
        (problem,) = caught.value.problems
        assert (problem.span.line, problem.span.column) == (11, column), action
        assert problem.message.startswith(message), problem.message


def test_frictions_in_range_run(tmp_path):
    for value in ("2", "0.05"):
        result = run(_write(tmp_path, FRICTION.format(action=f"set_road_friction({value})")))
        assert result.outcome.status == "success", result.outcome.reason
        assert result.telemetry["hero"]["friction"][-1] == pytest.approx(float(value))


def test_a_friction_known_only_at_run_time_fails_the_phase(tmp_path, capsys):
    source = _write(tmp_path, FRICTION.format(action="set_road_friction(hero.speed / 1mps)"))
    assert main([str(source), "-q"]) == 1
    out = capsys.readouterr().out
    assert "failure" in out
    assert "env.set_road_friction: road friction must be in (0, 2], got 13.88" in out


def test_a_negative_rain_intensity_is_refused_by_the_checker(tmp_path, capsys):
    source = _write(tmp_path, FRICTION.format(action="rain(intensity: -5mmph)"))
    assert main([str(source)]) == 2
    err = capsys.readouterr().err
    assert f"{source}:11:18: C401 [error]" in err
    assert "`rain(intensity: -5mmph)`; a rain intensity is not negative" in err


def _rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as f:
        return list(csv.DictReader(f))


def test_a_diverged_physics_ends_the_run_as_error_and_writes_the_files(
    tmp_path, capsys, monkeypatch
):
    monkeypatch.chdir(tmp_path)  # MuJoCo writes its warning to MUJOCO_LOG.TXT in the cwd
    real_step = World.step_control

    def step_into_nan(self: World, inputs=None):  # the physics blows up at tick 30
        if self.tick == 30:
            self.data.qvel[self.vehicles.vadr[0]] = math.nan
        return real_step(self, inputs)

    monkeypatch.setattr(World, "step_control", step_into_nan)
    out = tmp_path / "out"
    assert main([_write(tmp_path, TWO_CARS).as_posix(), "--out", str(out), "-q"]) == 2
    assert "error at 1.55 s (tick 31): the physics diverged at tick 31" in capsys.readouterr().out
    meta = json.loads((out / "run.json").read_text())
    outcome = meta["outcome"]
    assert outcome["status"] == "error" and outcome["tick"] == 31
    assert "`hero`" in outcome["reason"] and "MuJoCo reset the simulation" in outcome["reason"]
    rows = _rows(out / "telemetry.csv")
    # the telemetry ends with the last physical state, the tick before
    for actor in ("hero", "npc"):
        ticks = [int(r["tick"]) for r in rows if r["actor"] == actor]
        assert ticks == list(range(31))
    assert all(math.isfinite(float(r["speed"])) for r in rows)
    assert meta["events"][-1]["kind"] == "outcome"


def test_a_non_finite_read_out_ends_the_run_as_error(tmp_path, monkeypatch):
    real_step = World.step_control

    def step_to_inf(self: World, inputs=None):  # the read-out of tick 12 is not finite
        events = real_step(self, inputs)
        if self.tick == 12:
            self.vehicles.speed = self.vehicles.speed.copy()
            self.vehicles.speed[1] = math.inf
        return events

    monkeypatch.setattr(World, "step_control", step_to_inf)
    result = run(_write(tmp_path, TWO_CARS))
    assert result.outcome.status == "error"
    assert result.outcome.tick == 12
    assert (
        "`npc`: non-finite state" in result.outcome.reason and "speed inf" in result.outcome.reason
    )
    assert len(result.telemetry["npc"]["tick"]) == 12


def test_the_world_names_a_pedestrian_with_a_non_finite_state():
    world = World(
        builtin_network("default"),
        [
            ActorSpec("car", sedan(), s=40.0, lane=1, speed=10.0),
            ActorSpec("walker", PedestrianParams(), x=120.0, y=-1.0, yaw=math.pi / 2),
        ],
    )
    world.step_control()
    assert world.diverged() is None
    world.set_input("walker", PedestrianInput(speed=math.nan, yaw=0.0))
    world.step_control()
    found = world.diverged()
    assert found is not None and found[0] == "walker" and "speed nan" in found[1]


def test_a_start_that_is_not_finite_is_an_error_before_the_first_tick(tmp_path, monkeypatch):
    real_specs = runner_module.start_specs

    def nan_speed(*args, **kwargs):
        specs, problems = real_specs(*args, **kwargs)
        return [s if s.name != "npc" else replace(s, speed=math.nan) for s in specs], problems

    monkeypatch.setattr(runner_module, "start_specs", nan_speed)
    result = run(_write(tmp_path, TWO_CARS))
    assert result.outcome.status == "error" and result.outcome.tick == 0
    assert (
        "`npc`: non-finite state" in result.outcome.reason and "speed nan" in result.outcome.reason
    )
