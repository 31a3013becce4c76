"""Trailers against closed-form physics: a hitched body that follows, loads and brakes.

A car tows a catalogue trailer hitched by a ball joint (``sim/trailer.py``). On a
straight road the articulation settles at 0; on a lane change the trailer's axle
stays within the kinematic off-tracking of the path its hitch draws; braking, an
unbraked trailer adds its mass to what the car's brakes stop, so the deceleration
falls and the stopping distance grows as momentum says; the trailer is covered by
collision and road-departure detection.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from osc2check.world.builtin import builtin_network
from osc2check.world.catalogue import MODELS, receiver
from osc2runner.errors import ScenarioError
from osc2runner.execution.context import RunContext
from osc2runner.execution.loop import TickLoop
from osc2runner.instance.bodies import body_params
from osc2runner.runner import run
from osc2runner.sim import ActorSpec, ObstacleParams, VehicleController, VehicleInput, World, sedan
from osc2runner.sim.trailer import TrailerParams, articulation
from osc2runner.sim.vehicle import GRAVITY

ROAD = builtin_network("default")
LANE_WIDTH = 3.5  # the built-in maps' lanes; lane k's centre is at y = 3.5 (k - 1/2)
CAR = sedan()


def _trailer(model: str) -> TrailerParams:
    row = MODELS[model]
    params = body_params(row, float(row.length), float(row.width))
    assert isinstance(params, TrailerParams)
    return params


CARAVAN = _trailer("trailer.caravan")
BOX = _trailer("trailer.box")


def _towing(
    trailer: TrailerParams, speed: float, lane: int
) -> tuple[World, VehicleController, TickLoop]:
    """A car towing ``trailer`` at ``speed`` in ``lane``, the car's controller holding that
    speed and lane (it knows the load), and the loop that steps them."""
    world = World(
        ROAD,
        [
            ActorSpec("car", CAR, s=80.0, lane=lane, speed=speed),
            ActorSpec("tr", trailer, towed_by="car"),
        ],
    )
    ctrl = VehicleController(CAR, ROAD, world.dt_control)
    ctrl.speed.set_target(speed, "none")
    ctrl.lateral.keep_lane(lane)
    ctrl.speed.towed = trailer
    return world, ctrl, TickLoop.without_scenario(world, {"car": ctrl})


def _hitch_gap(world: World) -> float:
    """Distance between the car's receiver and the trailer's coupler (m), in the plane."""
    car, tr = world.state("car"), world.state("tr")
    rx = car.x + CAR.receiver_x * math.cos(car.yaw)
    ry = car.y + CAR.receiver_x * math.sin(car.yaw)
    p = world.params("tr")
    assert isinstance(p, TrailerParams)
    return math.hypot(
        rx - (tr.x + p.coupler * math.cos(tr.yaw)), ry - (tr.y + p.coupler * math.sin(tr.yaw))
    )


def test_the_catalogue_hitch_geometry_is_the_body_geometry():
    row = MODELS["trailer.caravan"]
    # coupler 1.2 m ahead of the box, axle 4 m behind its front: a 5.2 m trailer wheelbase
    assert CARAVAN.coupler == pytest.approx(float(row.length) / 2 + 1.2)
    assert CARAVAN.wheelbase == pytest.approx(float(row.wheelbase)) == pytest.approx(5.2)
    assert CARAVAN.braked and not BOX.braked  # 1400 kg has brakes, 750 kg none (EU O1)
    assert CARAVAN.nose_load == pytest.approx(0.05 * CARAVAN.mass * GRAVITY)
    car_receiver = receiver(MODELS["vehicle.tesla.model3"])
    assert car_receiver is not None and float(car_receiver.height) == CARAVAN.coupler_height
    assert receiver(MODELS["vehicle.bh.crossbike"]) is None  # a bicycle tows nothing


def test_on_a_straight_road_the_articulation_settles_at_zero():
    world, _, loop = _towing(CARAVAN, 80 / 3.6, lane=2)
    angles = []
    for _ in range(200):  # 10 s
        loop.step()
        angles.append(world.state("tr").articulation)
    car, tr = world.state("car"), world.state("tr")
    assert max(abs(a) for a in angles) < 1e-4  # steady state: straight behind
    assert tr.y == pytest.approx(car.y, abs=1e-4) and tr.speed == pytest.approx(car.speed, abs=1e-3)
    assert car.speed == pytest.approx(80 / 3.6, abs=0.1)  # the load is felt and overcome
    assert _hitch_gap(world) < 0.005  # the ball joint holds


@pytest.mark.parametrize(
    ("trailer", "kph", "seconds"), [(CARAVAN, 50, 4.0), (CARAVAN, 100, 3.0), (BOX, 80, 3.0)]
)
def test_on_a_lane_change_the_trailer_follows_its_hitch_within_the_off_tracking(
    trailer, kph, seconds
):
    """A trailer's axle runs inside the path its hitch draws by at most L²·κ/2 (the
    kinematic off-tracking of a wheelbase L on curvature κ), and ends in the new lane."""
    speed = kph / 3.6
    world, ctrl, loop = _towing(trailer, speed, lane=1)
    hitch, axle = [], []
    for tick in range(round((seconds + 8.0) / world.dt_control) + 40):
        if tick == 40:
            ctrl.lateral.change_lane(world.state("car"), 2, duration=seconds)
        loop.step()
        car, tr = world.state("car"), world.state("tr")
        hitch.append(
            (car.x + CAR.receiver_x * math.cos(car.yaw), car.y + CAR.receiver_x * math.sin(car.yaw))
        )
        axle.append(
            (tr.x + trailer.axle * math.cos(tr.yaw), tr.y + trailer.axle * math.sin(tr.yaw))
        )
    h, a = np.array(hitch), np.array(axle)
    slope = np.gradient(h[:, 1], h[:, 0])
    curvature = np.abs(np.gradient(slope, h[:, 0])) / (1.0 + slope**2) ** 1.5
    bound = trailer.wheelbase**2 * curvature.max() / 2.0
    deviation = np.abs(a[:, 1] - np.interp(a[:, 0], h[:, 0], h[:, 1]))
    assert 0.0 < deviation.max() <= bound + 0.005
    assert a[-1, 1] == pytest.approx(LANE_WIDTH * 1.5, abs=0.005)
    assert abs(world.state("tr").articulation) < 1e-3
    assert _hitch_gap(world) < 0.005


def _stopping(trailer: TrailerParams | None, speed: float = 80 / 3.6) -> tuple[float, float]:
    """Full braking from ``speed``: the distance to standstill and the mean deceleration
    while the speed falls from 80 % to 20 % (the plateau, past the pedal ramp)."""
    specs = [ActorSpec("car", CAR, s=80.0, lane=2, speed=speed)]
    if trailer is not None:
        specs.append(ActorSpec("tr", trailer, towed_by="car"))
    world = World(ROAD, specs)
    x0 = world.state("car").x
    times, speeds = [], []
    while world.state("car").speed > 0.01 and world.time < 10.0:
        world.step_control({"car": VehicleInput(brake=1.0)})
        times.append(world.time)
        speeds.append(world.state("car").speed)
    t, v = np.array(times), np.array(speeds)
    plateau = (v < 0.8 * speed) & (v > 0.2 * speed)
    slope = np.polyfit(t[plateau], v[plateau], 1)[0]
    return world.state("car").x - x0, -slope


def test_braking_distance_grows_with_an_unbraked_trailers_mass_as_momentum_says():
    """The car's brakes (ABS at its tires' friction) are all that stop an unbraked trailer:
    the same force on the mass M + m decelerates it M / (M + m) times as hard, and the
    distance v²/2a grows by (M + m) / M past the pedal ramp."""
    alone, a0 = _stopping(None)
    for mass in (250.0, 500.0, 750.0):
        scale = mass / BOX.mass
        trailer = replace(BOX, mass=mass, inertia=tuple(i * scale for i in BOX.inertia))
        assert not trailer.braked
        distance, a = _stopping(trailer)
        ratio = (CAR.mass + mass) / CAR.mass
        assert a == pytest.approx(a0 / ratio, rel=0.02), mass
        assert distance / alone == pytest.approx(ratio, rel=0.03), mass


def test_a_braked_trailer_brakes_its_own_mass():
    """A braked trailer's wheels brake with the car's pedal, up to its brakes' torque: the
    combination decelerates at (car's force + trailer's force) / (M + m)."""
    _, a0 = _stopping(None)
    distance, a = _stopping(CARAVAN)
    unbraked, a_free = _stopping(replace(CARAVAN, max_brake_torque=0.0))
    trailer_force = min(
        CARAVAN.max_brake_torque / CARAVAN.wheel_radius,
        CARAVAN.abs_margin * 2.0 * CARAVAN.static_wheel_load,  # µ = 1
    )
    expected = (CAR.mass * a0 + trailer_force) / (CAR.mass + CARAVAN.mass)
    assert a == pytest.approx(expected, rel=0.03)
    assert a_free == pytest.approx(a0 * CAR.mass / (CAR.mass + CARAVAN.mass), rel=0.03)
    assert distance < 0.75 * unbraked


def test_the_trailer_is_checked_for_collisions_and_its_tow_vehicle_is_not_one():
    """A box just right of the car's path: the 1.8 m car clears it, the 2.3 m caravan
    behind it hits it. The car and its own trailer never count as a collision."""
    lane = LANE_WIDTH * 1.5
    edge = lane - 0.5 * CAR.width
    box = ObstacleParams(width=1.0)
    world = World(
        ROAD,
        [
            ActorSpec("car", CAR, s=80.0, lane=2, speed=10.0),
            ActorSpec("tr", CARAVAN, towed_by="car"),
            ActorSpec("box", box, x=110.0, y=edge - 0.5 * box.width - 0.1),
        ],
    )
    ctrl = VehicleController(CAR, ROAD, world.dt_control)
    ctrl.speed.set_target(10.0, "none")
    ctrl.lateral.keep_lane(2)
    loop = TickLoop.without_scenario(world, {"car": ctrl})
    for _ in range(80):  # 4 s at 10 m/s: the car passes the box at 110 m, the trailer hits it
        loop.step()
    collisions = [e.actors for e in world.events if e.kind == "collision"]
    assert collisions == [("tr", "box")]


def test_a_trailer_behind_the_start_of_the_road_is_off_the_road():
    world = World(
        ROAD,
        [ActorSpec("car", CAR, s=4.0, lane=1, speed=1.0), ActorSpec("tr", CARAVAN, towed_by="car")],
    )
    world.step_control()
    assert [(e.kind, e.actors) for e in world.events] == [("off_road", ("tr",))]


def test_connect_puts_the_trailer_on_the_hitch_and_disconnect_parks_it():
    world = World(
        ROAD,
        [
            ActorSpec("car", CAR, s=200.0, lane=2, speed=10.0),
            ActorSpec("tr", CARAVAN, s=60.0, lane=1),
        ],
    )
    assert world.articulation("tr") != world.articulation("tr")  # NaN: not hitched
    moved = world.connect("car", "tr")
    assert moved > 100.0  # from where it stood onto the hitch
    assert _hitch_gap(world) < 1e-9 and world.state("tr").speed == pytest.approx(10.0)
    with pytest.raises(ValueError, match="already towed"):
        world.connect("car", "tr")
    world.run(2.0, {"car": VehicleInput(throttle=0.1)})
    assert _hitch_gap(world) < 0.005
    assert world.disconnect("car") == "tr"
    with pytest.raises(ValueError, match="tows no trailer"):
        world.disconnect("car")
    world.run(4.0, {"car": VehicleInput(throttle=0.2)})
    tr = world.state("tr")
    assert abs(tr.speed) < 0.01 and math.isnan(tr.articulation)  # its brakes hold it
    assert world.state("car").x - tr.x > 20.0
    assert not [e for e in world.events if e.kind == "collision"]


def test_a_teleport_reads_the_new_states_of_the_actor_and_its_trailer():
    """RunContext.place: the placed actor's state and its hitched trailer's (the world
    moves it along) are read at once; the other actors' are left as they are."""
    world = World(
        ROAD,
        [
            ActorSpec("car", CAR, s=80.0, lane=2, speed=10.0),
            ActorSpec("tr", CARAVAN, towed_by="car"),
            ActorSpec("other", CAR, s=150.0, lane=1, speed=5.0),
        ],
    )
    ctx = RunContext(ROAD, [])
    ctx.attach(world, {})
    world.run(0.5, {})
    ctx.refresh()
    other = ctx.states["other"]
    ctx.place("car", 120.0, 1.5 * LANE_WIDTH, 0.0, 12.0)
    car, tr = ctx.states["car"], ctx.states["tr"]
    assert (car.x, car.y, car.yaw, car.speed) == pytest.approx((120.0, 1.5 * LANE_WIDTH, 0.0, 12.0))
    assert _hitch_gap(world) < 1e-9
    fresh = world.state("tr")
    assert (tr.x, tr.y, tr.yaw, tr.speed) == (fresh.x, fresh.y, fresh.yaw, fresh.speed)
    assert tr.x < car.x and tr.speed == pytest.approx(12.0)
    assert ctx.states["other"] is other


def test_articulation_is_the_heading_difference_wrapped():
    assert articulation(0.1, -0.1) == pytest.approx(0.2)
    assert articulation(math.pi - 0.1, -math.pi + 0.1) == pytest.approx(-0.2)
    assert articulation(-math.pi, 0.0) == pytest.approx(math.pi)


# ---------------------------------------------------------------------- scenarios

TOWING = """\
import osc.standard

scenario top:
    car: vehicle with:
        keep(it.model == "vehicle.tesla.model3")
    caravan: trailer with:
        keep(it.model == "trailer.caravan")
    do serial:
        car.connect_trailer(trailer: caravan)
        car.drive(duration: 8s) with:
            speed(60kph)
            lane(1, at: start)
            speed(0kph, at: start)
        wait caravan.coupler.is_towed and car.trailer_receiver.is_towing
        car.change_speed(target: 0kph)
        car.disconnect_trailer()
        wait not car.trailer_receiver.is_towing
        car.drive(duration: 3s) with:
            speed(20kph)
"""


def test_a_scenario_tows_a_trailer_from_the_start_and_leaves_it():
    result = run("<towing>.osc", source=TOWING)
    assert result.outcome.status == "success", result.outcome.reason
    car, tr = result.telemetry["car"], result.telemetry["caravan"]
    # hitched from the start: the coupler on the model's own receiver, straight behind
    model3 = MODELS["vehicle.tesla.model3"]
    hitch = receiver(model3)
    assert hitch is not None
    behind = float(hitch.behind_front) - float(model3.length) / 2 + CARAVAN.coupler
    assert car["x"][0] - tr["x"][0] == pytest.approx(behind, abs=1e-6)
    assert car["y"][0] == tr["y"][0]
    changes = [(r.tick, r.detail) for r in result.events if r.kind == "trailer"]
    (connected, at_start), (disconnected, _) = changes
    assert connected == 0 and at_start == "connected (trailer moved 0.00 m)"
    hitched = slice(0, disconnected + 1)
    assert np.all(np.abs(tr["articulation"][hitched]) < 1e-3)
    assert np.all(np.isnan(tr["articulation"][disconnected + 1 :]))
    assert np.all(np.isnan(car["articulation"]))
    # the car pulls its load up to 60 kph within its drive phase
    assert car["speed"][159] * 3.6 == pytest.approx(60.0, abs=0.5)
    # left behind: the trailer stands, the car drives on
    assert abs(tr["speed"][-1]) < 0.01 and car["speed"][-1] * 3.6 == pytest.approx(20.0, abs=1.0)


LATE = """\
import osc.standard

scenario top:
    car: vehicle
    caravan: trailer with:
        keep(it.model == "trailer.caravan")
    do serial:
        parallel:
            car.assign_position() with:
                lane(1, at: start)
                position(distance: 200m, at: start)
                speed(0kph, at: start)
            caravan.assign_position() with:
                lane(2, at: start)
                position(distance: 100m, at: start)
        car.drive(duration: 1s)
        car.connect_trailer(trailer: caravan)
        car.drive(duration: 2s) with:
            speed(20kph)
"""


def test_a_later_connect_puts_the_trailer_on_the_hitch_and_says_how_far_it_moved():
    result = run("<late>.osc", source=LATE)
    assert result.outcome.status == "success", result.outcome.reason
    (change,) = [r for r in result.events if r.kind == "trailer"]
    car, tr = result.telemetry["car"], result.telemetry["caravan"]
    k = change.tick
    assert tr["x"][k - 1] == pytest.approx(100.0) and tr["lane"][k - 1] == 2.0
    assert tr["y"][-1] == pytest.approx(car["y"][-1], abs=1e-3)  # behind the car now
    moved = math.hypot(tr["x"][k + 1] - tr["x"][k - 1], tr["y"][k + 1] - tr["y"][k - 1])
    said = float(change.detail.split("moved ")[1].split(" m")[0])
    assert said == pytest.approx(moved, abs=0.05)


def _scenario(body: str, fields: str = "") -> str:
    return (
        "import osc.standard\n\nscenario top:\n    car: vehicle\n"
        "    box: trailer\n" + fields + "    do serial:\n" + body
    )


def test_what_cannot_tow_or_is_not_towed_fails_the_run_with_its_place():
    bike = _scenario(
        "        car.connect_trailer(trailer: box)\n",
        '    bike: vehicle with:\n        keep(it.model == "vehicle.bh.crossbike")\n',
    ).replace("car.connect", "bike.connect")
    result = run("<bike>.osc", source=bike)
    assert result.outcome.status == "failure"
    assert "`bike` has no hitch receiver" in result.outcome.reason
    assert ":9:9:" in result.outcome.reason  # the invocation's place
    nothing = run("<none>.osc", source=_scenario("        car.disconnect_trailer()\n"))
    assert "`car` tows no trailer" in nothing.outcome.reason
    unset = run(
        "<unset>.osc",
        source=_scenario("        wait box.tow_vehicle == car\n"),
    )
    assert unset.outcome.status == "failure"
    assert "`box.tow_vehicle` has no value: `box` is not towed" in unset.outcome.reason


def test_trailers_the_runner_does_not_build_are_input_errors():
    semi = _scenario(
        "        car.connect_trailer(trailer: box)\n",
    ).replace(
        "    box: trailer\n",
        "    box: trailer with:\n        keep(it.trailer_category == semi_trailer)\n",
    )
    with pytest.raises(ScenarioError, match="builds central-axle trailers only"):
        run("<semi>.osc", source=semi)


def test_a_vehicle_can_tow_when_it_has_a_hitch_receiver():
    assert replace(CAR, hitch_reach=0.9).can_tow
    assert not replace(CAR, hitch_reach=None).can_tow
    world = World(
        ROAD,
        [
            ActorSpec("car", replace(CAR, hitch_reach=0.9), s=80.0, lane=2),
            ActorSpec("van", replace(CAR, hitch_reach=None), s=40.0, lane=2),
        ],
    )
    assert world.can_tow("car") and not world.can_tow("van")
