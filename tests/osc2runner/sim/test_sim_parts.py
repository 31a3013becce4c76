"""Unit tests of the simulation parts: MJCF generation, actuator layer, controllers."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from osc2runner.sim import versions
from osc2runner.sim.actuators import ActuatorBank
from osc2runner.sim.controllers import (
    LateralPath,
    RateProfile,
    SpeedController,
    _advance_reference,
)
from osc2runner.sim.vehicle import hgv, sedan, vehicle_actuator_xml, vehicle_body_xml
from osc2runner.sim.world import ActorState

# ---------------------------------------------------------------------- vehicle


def _compile_vehicle(params):
    xml = (
        '<mujoco><compiler angle="radian" autolimits="true"/>'
        '<option cone="elliptic" integrator="implicitfast"/><worldbody>'
        '<geom type="plane" size="0 0 1" contype="0" conaffinity="1"/>'
        + vehicle_body_xml("car", params, 0.0, 0.0, 0.3)
        + "</worldbody><actuator>"
        + vehicle_actuator_xml("car", params)
        + "</actuator></mujoco>"
    )
    return mujoco.MjModel.from_xml_string(xml)


@pytest.mark.parametrize("params", [sedan(), hgv()], ids=["sedan", "hgv"])
def test_vehicle_mjcf_masses_and_radian_steer_range(params):
    m = _compile_vehicle(params)
    assert m.nv == 16  # 6 free + 4 suspension + 2 steer + 4 spin
    assert sum(m.body_mass) == pytest.approx(params.mass)
    steer = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, "car_fl_steer")
    # pitfall 1: degrees by default; the range must be the radian value
    assert m.jnt_range[steer] == pytest.approx((-params.max_steer, params.max_steer))


def test_vehicle_tires_override_friction_and_touch_only_the_road():
    m = _compile_vehicle(sedan())
    tire = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "car_rl_tire")
    chassis = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "car_chassis")
    assert m.geom_priority[tire] == 1 and m.geom_condim[tire] == 3
    assert (m.geom_contype[tire], m.geom_conaffinity[tire]) == (1, 0)
    assert (m.geom_contype[chassis], m.geom_conaffinity[chassis]) == (0, 0)
    # only the driven (rear) wheels have motors
    names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_ACTUATOR, i) for i in range(m.nu)]
    assert names == ["car_fl_steer", "car_fr_steer", "car_rl_drive", "car_rr_drive"]


def test_vehicle_params_derived_values():
    p = sedan()
    assert p.wheelbase == pytest.approx(2.7)
    assert sum(p.static_wheel_loads) == pytest.approx(p.mass * 9.81)
    assert sum(p.brake_torque_per_wheel) == pytest.approx(p.max_brake_torque)
    assert p.front_axle_x - p.rear_axle_x == pytest.approx(p.wheelbase)
    assert p.drive_force_available(5.0) == p.max_drive_force
    assert p.drive_force_available(40.0) == pytest.approx(p.max_power / 40.0)
    with pytest.raises(ValueError):
        sedan(drive="4x4")


def test_versions_names_mujoco():
    v = versions()
    assert v["mujoco"] == mujoco.__version__
    assert {"numpy", "python", "platform"} <= set(v)


# ---------------------------------------------------------------------- actuators


def _bank(**changes):
    return ActuatorBank([sedan(**changes)], dt=0.05)


def _update(bank, speed=20.0, mu=1.0, accel=0.0):
    bank.update(np.array([speed]), np.full((1, 4), mu), np.array([accel]), np.array([0.0]))


def test_actuators_rate_limit_pedals_and_steering():
    bank = _bank()
    bank.set_command(0, throttle=0.0, brake=5.0, steer=-3.0)  # clipped to [0,1], [-1,1]
    assert bank.cmd_brake[0] == 1.0 and bank.cmd_steer[0] == -1.0
    _update(bank)
    # Expect: brake 6/s over 50 ms, steer 0.8 rad/s over 50 ms
    assert bank.brake[0] == pytest.approx(0.3)
    assert bank.delta[0] == pytest.approx(-0.04)
    for _ in range(3):
        _update(bank)
    assert bank.brake[0] == pytest.approx(1.0)


def test_actuators_abs_caps_brake_torque_at_the_friction_budget():
    bank = _bank(brake_rate=1e9)
    bank.set_command(0, 0.0, 1.0, 0.0)
    _update(bank, mu=0.4)
    r = sedan().wheel_radius
    loads = np.array(sedan().static_wheel_loads)
    rolling = sedan().rolling_resistance * loads * r
    brake_only = bank.brake_torque[0] - rolling
    assert brake_only == pytest.approx(0.9 * 0.4 * loads * r)
    _update(bank, mu=10.0)  # grip to spare: the brakes' own maximum applies
    assert bank.brake_torque[0] - rolling == pytest.approx(sedan().brake_torque_per_wheel)


def test_actuators_abs_off_locks_at_full_torque():
    bank = _bank(brake_rate=1e9, abs_enabled=False)
    bank.set_command(0, 0.0, 1.0, 0.0)
    _update(bank, mu=0.1)
    rolling = sedan().rolling_resistance * np.array(sedan().static_wheel_loads) * 0.33
    assert bank.brake_torque[0] - rolling == pytest.approx(sedan().brake_torque_per_wheel)


def test_actuators_tcs_caps_drive_torque_and_drives_rear_wheels_only():
    bank = _bank(throttle_rate=1e9)
    bank.set_command(0, 1.0, 0.0, 0.0)
    _update(bank, speed=5.0, mu=1.0)
    torque = bank.drive_torque[0]
    assert torque[0] == torque[1] == 0.0
    assert torque[2] == pytest.approx(5000.0 * 0.33 / 2)
    _update(bank, speed=5.0, mu=0.2)
    rear_load = sedan().static_wheel_loads[2]
    assert bank.drive_torque[0, 2] == pytest.approx(0.9 * 0.2 * rear_load * 0.33)


def test_actuators_load_transfer_moves_load_forward_when_braking():
    bank = _bank()
    loads = bank.estimate_loads(np.array([-8.0]), np.array([0.0]))[0]
    static = np.array(sedan().static_wheel_loads)
    assert loads[0] > static[0] and loads[2] < static[2]
    assert loads.sum() == pytest.approx(static.sum())


def test_actuators_ackermann_steers_the_inner_wheel_more():
    bank = _bank(steer_rate=1e9)
    bank.set_command(0, 0.0, 0.0, 0.5)  # left turn
    _update(bank)
    left, right = bank.steer_angles[0]
    assert left > right > 0.0
    # both wheels point at the same turn centre on the rear axle line
    p = sedan()
    radius = p.wheelbase / math.tan(0.5 * p.max_steer)
    assert math.tan(left) == pytest.approx(p.wheelbase / (radius - p.track / 2))
    assert math.tan(right) == pytest.approx(p.wheelbase / (radius + p.track / 2))


# ---------------------------------------------------------------------- controllers


def test_rate_profile_limits_and_validation():
    assert RateProfile("smooth").limits() == (2.5, 10.0)
    assert RateProfile("constant", peak=1.5).limits() == (1.5, math.inf)
    assert RateProfile("rate_peak", peak=4.0).limits() == (4.0, 10.0)
    assert RateProfile("asap").limits() == (math.inf, math.inf)
    with pytest.raises(ValueError, match="unknown rate profile"):
        RateProfile("gentle")
    with pytest.raises(ValueError, match="needs a peak"):
        RateProfile("rate_peak")


@pytest.mark.parametrize("profile", ["smooth", "constant"])
def test_reference_respects_acceleration_and_jerk_limits(profile):
    a_max, j_max = RateProfile(profile).limits()
    v, a, dt = 22.0, 0.0, 0.05
    accels = []
    for _ in range(400):
        v, a = _advance_reference(v, a, 0.0, a_max, j_max, dt)
        accels.append(a)
        assert v >= 0.0  # never overshoots the target
    assert v == 0.0 and a == 0.0
    accels = np.array(accels)
    assert np.abs(accels).max() <= a_max + 1e-12
    if math.isfinite(j_max):
        # the discrete ramp may land with up to an eighth more than one jerk step
        assert np.abs(np.diff(accels)).max() <= 1.125 * j_max * dt + 1e-9


def test_lateral_path_blends_with_zero_slope_at_both_ends():
    path = LateralPath(1.75, 5.25, 100.0, 140.0)
    assert path.at(90.0) == (1.75, 0.0)
    assert path.at(150.0) == (5.25, 0.0)
    assert path.at(120.0)[0] == pytest.approx(3.5)
    assert path.at(100.001)[1] == pytest.approx(0.0, abs=1e-6)
    assert path.at(120.0)[1] == pytest.approx(30 / 16 * 3.5 / 40)  # quintic peak slope
    sine = LateralPath(0.0, 2.0, 0.0, 10.0, "sinusoidal")
    assert sine.at(5.0) == pytest.approx((1.0, math.pi / 10))


def _state(speed: float, accel: float = 0.0) -> ActorState:
    return ActorState(
        name="ego",
        kind="vehicle",
        tick=0,
        time=0.0,
        x=0.0,
        y=1.75,
        yaw=0.0,
        speed=speed,
        lateral_speed=0.0,
        yaw_rate=0.0,
        accel=accel,
        lane=1,
        s=0.0,
        t=1.75,
        friction=1.0,
        throttle=0.0,
        brake=0.0,
        steer=0.0,
        length=4.5,
        width=1.8,
    )


def test_speed_controller_inverse_model_balances_resistance():
    c = SpeedController(sedan(), 0.05)
    throttle, brake = c.pedals_for(0.0, 20.0)
    assert brake == 0.0
    assert throttle * sedan().drive_force_available(20.0) == pytest.approx(
        sedan().resistance_force(20.0)
    )
    throttle, brake = c.pedals_for(-5.0, 20.0)
    assert throttle == 0.0 and 0.0 < brake < 1.0


def test_speed_controller_holds_a_stopped_car_with_the_brake():
    c = SpeedController(sedan(), 0.05)
    c.set_target(0.0, "smooth")
    assert c.step(_state(0.0)) == (0.0, c.gains.hold_brake)


def test_speed_controller_asap_uses_full_pedal_then_hands_over():
    c = SpeedController(sedan(), 0.05)
    c.set_target(10.0, "asap")
    assert c.step(_state(20.0, -9.0)) == (0.0, 1.0)
    throttle, brake = c.step(_state(10.2, -9.0))  # within the release lead
    assert brake < 1.0
    with pytest.raises(ValueError):
        c.set_target(-1.0)


# ---------------------------------------------------------------------- events


def test_boxes_overlap_uses_orientation():
    from osc2runner.sim.events import boxes_overlap

    car = np.array([2.25, 0.9])
    # side by side 2.0 m apart: clear; rotated 90° the second box reaches across
    assert not boxes_overlap(np.zeros(2), 0.0, car, np.array([0.0, 2.0]), 0.0, car)
    assert boxes_overlap(np.zeros(2), 0.0, car, np.array([0.0, 2.0]), math.pi / 2, car)
    # diagonal gap: the circles overlap, the boxes do not
    assert not boxes_overlap(np.zeros(2), 0.0, car, np.array([4.6, 1.9]), 0.0, car)
    assert boxes_overlap(np.zeros(2), 0.0, car, np.array([4.6, 1.9]), 0.0, car, margin=0.2)


def test_event_detector_reports_each_contact_once_and_ignores_obstacle_pairs():
    from osc2runner.sim.events import EventDetector

    half = np.array([[2.25, 0.9], [0.5, 0.5], [0.5, 0.5]])
    detector = EventDetector(("car", "rock", "stone"), half, np.array([False, True, True]))
    yaw = np.zeros(3)
    apart = np.array([[10.0, 5.0], [20.0, 5.0], [20.5, 5.0]])  # the obstacles overlap each other
    touching = np.array([[17.5, 5.0], [20.0, 5.0], [20.5, 5.0]])
    assert detector.detect(1, 0.05, apart, yaw) == []
    first = detector.detect(2, 0.1, touching, yaw)
    assert [(e.kind, e.actors) for e in first] == [("collision", ("car", "rock"))]
    assert detector.detect(3, 0.15, touching, yaw) == []
    assert detector.collisions == {("car", "rock")}
    assert detector.detect(4, 0.2, apart, yaw) == []
    assert len(detector.detect(5, 0.25, touching, yaw)) == 1
    off = detector.detect(6, 0.3, np.array([[10.0, -1.0], [20.0, 5.0], [20.5, 5.0]]), yaw, [True])
    assert [(e.kind, e.actors) for e in off] == [("off_road", ("car",))]
    assert (
        detector.detect(7, 0.35, np.array([[10.0, -1.0], [20.0, 5.0], [20.5, 5.0]]), yaw, [True])
        == []
    )
