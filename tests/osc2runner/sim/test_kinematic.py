"""The kinematic model (``sim/kinematic_bank.py``) against the multibody model's acceptance
figures, in a world with other bodies, and chosen per vehicle by a run's ``kinematic``
option (``execution/vehicle_models.py``)."""

from __future__ import annotations

import dataclasses
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from osc2check.world.builtin import builtin_network
from osc2check.world.catalogue import MODELS
from osc2runner.campaign.campaign import CampaignOptions
from osc2runner.campaign.outputs import replay_command
from osc2runner.campaign.schema import campaign_document
from osc2runner.errors import ScenarioError
from osc2runner.execution.loop import TickLoop
from osc2runner.instance.bodies import body_params
from osc2runner.options import OptionError, RunOptions
from osc2runner.runner import prepare, run
from osc2runner.sim import ActorSpec, VehicleController, VehicleInput, World, hgv, sedan
from osc2runner.sim.trailer import TrailerParams
from osc2runner.sut.loading import SutSpec

ROOT = Path(__file__).resolve().parents[3]
CUT_IN = ROOT / "examples" / "cut_in_and_stop.osc"
PASS_THROUGH = f"{ROOT / 'tests' / 'osc2runner' / 'campaign' / 'suts.py'}:PassThrough"
ROAD = builtin_network("default")
G = 9.81
V80 = 80 / 3.6
V35 = 35 / 3.6


def _caravan() -> TrailerParams:
    row = MODELS["trailer.caravan"]
    params = body_params(row, float(row.length), float(row.width))
    assert isinstance(params, TrailerParams)
    return params


def _drive(params, *, kinematic, mu=1.0, v0=V80, target=0.0, profile="asap", seconds=30.0):
    """Speeds and positions of one vehicle in lane 2 driven to ``target``."""
    world = World(ROAD, [ActorSpec("ego", params, s=50.0, lane=2, speed=v0, kinematic=kinematic)])
    world.set_road_friction(mu)
    controller = VehicleController(params, ROAD, world.dt_control)
    controller.lateral.keep_lane(2)
    controller.speed.set_target(target, profile)
    loop = TickLoop.without_scenario(world, {"ego": controller})
    x0 = world.state("ego").x
    rows = []
    for _ in range(round(seconds / world.dt_control)):
        loop.step()
        state = world.state("ego")
        rows.append((state.time, state.x - x0, state.speed, state.accel, state.y))
    return np.array(rows)


# ---------------------------------------------------------------------- the model


@pytest.mark.parametrize(
    ("params", "mu", "profile", "low", "high"),
    [
        # the multibody model's acceptance ranges (docs/world.md, "Measured figures")
        (sedan(), 1.0, "asap", 25.2, 30.5),
        (sedan(), 1.0, "smooth", 98.8 * 0.95, 98.8 * 1.05),
        (sedan(), 0.4, "asap", 62.9 * 0.85, 62.9 * 1.15),
        (hgv(), 1.0, "asap", 30.0, 40.0),
    ],
)
def test_kinematic_stopping_distances_meet_the_multibody_acceptance(params, mu, profile, low, high):
    trace = _drive(params, kinematic=True, mu=mu, profile=profile)
    stopped = np.flatnonzero(trace[:, 2] == 0.0)
    assert len(stopped), "never came to rest"
    distance = trace[stopped[0], 1]
    assert low <= distance <= high
    assert (trace[stopped[0] :, 2] == 0.0).all()  # at rest it stays, never rolls back
    assert abs(trace[-1, 4] - 1.5 * 3.5) < 0.01  # in its lane


def test_kinematic_braking_is_within_three_percent_of_the_multibody_model():
    multibody = _drive(sedan(), kinematic=False, seconds=6.0)
    kinematic = _drive(sedan(), kinematic=True, seconds=6.0)
    assert kinematic[-1, 1] == pytest.approx(multibody[-1, 1], rel=0.03)
    # the deceleration is the friction-limited one (ABS), not more
    assert kinematic[:, 3].min() > -1.0 * G


def test_kinematic_speed_hold_and_acceleration_depend_on_friction():
    hold = _drive(sedan(), kinematic=True, v0=V35, target=V35, profile="none", seconds=12.0)
    assert np.abs(hold[-80:, 2] - V35).max() < 0.3 / 3.6
    dry = _drive(sedan(), kinematic=True, v0=0.0, target=V80, seconds=20.0)
    wet = _drive(sedan(), kinematic=True, mu=0.4, v0=0.0, target=V80, seconds=20.0)

    def reached(trace):
        return trace[np.flatnonzero(trace[:, 2] >= 0.99 * V80)[0], 0]

    assert reached(dry) < 0.7 * reached(wet)
    assert dry[:, 3].max() <= 1.0 * G + 1e-9


def test_kinematic_lane_change_tracks_the_path():
    world = World(ROAD, [ActorSpec("ego", sedan(), s=50.0, lane=1, speed=V35, kinematic=True)])
    controller = VehicleController(sedan(), ROAD, world.dt_control)
    controller.lateral.keep_lane(1)
    controller.speed.set_target(V35)
    loop = TickLoop.without_scenario(world, {"ego": controller})
    for _ in range(20):
        loop.step()
    controller.lateral.change_lane(world.state("ego"), 2, duration=4.0)
    during, after = [], []
    for _ in range(180):
        loop.step()
        state = world.state("ego")
        if controller.lateral.done(state):
            after.append(state.y - 1.5 * 3.5)
        else:
            during.append(controller.lateral.error)
    final = world.state("ego")
    assert np.abs(during).max() < 0.1 and np.abs(after).max() < 0.1
    assert final.lane == 2 and abs(final.yaw) < 0.01
    assert abs(final.speed - V35) < 0.3 / 3.6


def test_kinematic_turning_stays_within_the_grip():
    world = World(ROAD, [ActorSpec("ego", sedan(), s=50.0, lane=2, speed=V80, kinematic=True)])
    world.set_road_friction(0.5)
    for _ in range(20):
        world.step_control({"ego": VehicleInput(throttle=0.2, brake=0.0, steer=1.0)})
        state = world.state("ego")
        assert abs(state.speed * state.yaw_rate) <= 0.5 * G + 1e-9
    assert state.yaw > 0.1  # it did turn left


# ---------------------------------------------------------------------- in a world


def _mixed() -> World:
    return World(
        ROAD,
        [
            ActorSpec("body", sedan(), s=50.0, lane=1, speed=10.0),
            ActorSpec("light", sedan(), s=50.0, lane=2, speed=10.0, kinematic=True),
            ActorSpec("truck", hgv(), s=80.0, lane=2, speed=10.0, kinematic=True),
        ],
    )


def test_a_kinematic_vehicle_has_no_body_and_reads_like_any_vehicle():
    world = _mixed()
    plain = World(ROAD, [ActorSpec("body", sedan(), s=50.0, lane=1, speed=10.0)])
    assert world.model.nv == plain.model.nv  # only the multibody vehicle is simulated
    assert [world.model_of(n) for n in world.names] == ["multibody", "kinematic", "kinematic"]
    world.run(2.0, {n: VehicleInput(0.1, 0.0, 0.0) for n in world.names})
    states = {}
    world.read_states(states)
    for name in world.names:
        # field by field, a NaN (a vehicle without a trailer's articulation) as itself:
        # Python 3.13's dataclass equality compares fields with ==, and NaN != NaN
        assert dataclasses.astuple(states[name]) == dataclasses.astuple(world.state(name))
        assert states[name].kind == "vehicle" and states[name].speed > 9.0
    assert world.wheel_speeds("light") == (states["light"].speed,) * 4
    assert sum(world.wheel_loads("light")) == pytest.approx(sedan().mass * G, rel=0.05)
    world.set_wheel_friction("light", 0.3)
    assert world.wheel_friction("light") == (0.3, 0.3, 0.3, 0.3)


def test_kinematic_and_multibody_vehicles_collide_as_boxes():
    world = World(
        ROAD,
        [
            ActorSpec("body", sedan(), s=50.0, lane=2, speed=0.0),
            ActorSpec("light", sedan(), s=30.0, lane=2, speed=15.0, kinematic=True),
        ],
    )
    events = []
    for _ in range(40):
        events += world.step_control({"light": VehicleInput(0.3, 0.0, 0.0)})
    assert ("body", "light") in {tuple(sorted(e.actors)) for e in events if e.kind == "collision"}


def test_the_same_inputs_give_the_same_kinematic_states():
    arrays = []
    for _ in range(2):
        world = _mixed()
        for k in range(60):
            world.step_control({"light": VehicleInput(0.3, 0.0, math.sin(k / 10))})
        arrays.append(world.state_array())
    assert np.array_equal(arrays[0], arrays[1])


def test_a_kinematic_vehicle_tows_nothing():
    with pytest.raises(ValueError, match="`car`, which is a kinematic vehicle"):
        World(
            ROAD,
            [
                ActorSpec("car", sedan(), s=50.0, lane=1, kinematic=True),
                ActorSpec("tr", _caravan(), towed_by="car"),
            ],
        )


# ---------------------------------------------------------------------- chosen per run


def test_a_run_states_each_actors_model(tmp_path):
    result = run(CUT_IN, out=tmp_path, kinematic=["npc"])
    assert result.outcome.status == "success"
    actors = json.loads((tmp_path / "run.json").read_text())["actors"]
    assert actors["npc"]["dynamics"] == "kinematic"
    assert actors["hero"]["dynamics"] == "multibody"


@pytest.mark.parametrize(
    ("selected", "sut", "message"),
    [
        (["nobody"], None, "`nobody` is no actor of the scenario"),
        (["x*"], None, "`x*` selects no vehicle that can run on the kinematic model"),
        (["hero"], PASS_THROUGH, "`hero` is driven by the system under test"),
    ],
)
def test_a_selection_the_runner_cannot_take_is_refused_before_the_first_tick(
    selected, sut, message
):
    options = {} if sut is None else {"sut": SutSpec(sut, "hero")}
    with pytest.raises(ScenarioError, match=re.escape(message)):
        run(CUT_IN, kinematic=selected, **options)


def test_every_vehicle_may_be_none():
    source = "import osc.standard\n\nscenario lone:\n    walker: person\n    do wait elapsed(1s)\n"
    prepared = prepare("lone.osc", source=source, kinematic=["*"])
    assert prepared.world.model_of("walker") == "kinematic"  # a pedestrian, as always
    with pytest.raises(ScenarioError, match="`w[*]` selects no vehicle"):
        prepare("lone.osc", source=source, kinematic=["w*"])


def test_a_pattern_leaves_out_the_vehicles_that_cannot_be_kinematic():
    sut = SutSpec(PASS_THROUGH, "hero").resolved()
    prepared = prepare(CUT_IN, kinematic=["*"], sut=sut)
    assert prepared.world.model_of("hero") == "multibody"
    assert prepared.world.model_of("npc") == "kinematic"


def test_a_vehicle_that_may_tow_is_not_kinematic_in_a_scenario_with_a_trailer():
    source = """\
import osc.standard

scenario top:
    car: vehicle with:
        keep(it.model == "vehicle.tesla.model3")
    caravan: trailer with:
        keep(it.model == "trailer.caravan")
    do car.connect_trailer(trailer: caravan)
"""
    with pytest.raises(ScenarioError, match="`car` may tow a trailer of this scenario"):
        prepare("tow.osc", source=source, kinematic=["car"])


def test_the_option_is_checked_replayed_and_kept_by_a_campaign():
    with pytest.raises(OptionError, match="is not an actor name or pattern"):
        RunOptions.checked(kinematic=[""])
    options = RunOptions.checked(kinematic=["npc*", "lead"])
    assert options.kinematic == ("npc*", "lead")
    assert replay_command("f.osc", options, bin_text=None) == (
        "osc2run f.osc --seed 0 --kinematic 'npc*,lead'"
    )
    campaign = CampaignOptions("f.osc", runs=2, out="o", kinematic=("npc*",))
    stored = campaign.run_options()
    assert stored["kinematic"] == ["npc*"]
    document = {
        "format": 1,
        "source": "f.osc",
        "source_sha256": "0" * 64,
        "scenario": "s",
        "status": "complete",
        "options": stored,
    }
    assert campaign_document(document)["options"]["kinematic"] == ["npc*"]
    # a campaign without it stores nothing for it: older folders resume as they were
    assert "kinematic" not in CampaignOptions("f.osc", runs=2, out="o").run_options()
